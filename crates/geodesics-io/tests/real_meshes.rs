//! Reads every mesh of the shared data folder and checks the vertex and face
//! counts against the folder's README table.
//!
//! The folder is `$GEODESICS_DATA`, by default `/work/shared/data/meshes`
//! (`../shared/data/meshes` from the workspace root). If it is absent the
//! test prints `SKIPPED` to stderr and passes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use geodesics_io::read_mesh;
use geodesics_mesh::{BuildOptions, Mesh};

fn data_dir() -> PathBuf {
    match std::env::var_os("GEODESICS_DATA") {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes"),
    }
}

/// Rows `| `name` | format | V | F | ...` of the README summary table.
fn readme_counts(readme: &str) -> Vec<(String, usize, usize)> {
    readme
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            // ["", "`name`", format, V, F, ...]
            let name = cells.get(1)?.strip_prefix('`')?.strip_suffix('`')?;
            let number = |s: &str| s.replace(',', "").parse::<usize>().ok();
            Some((
                name.to_owned(),
                number(cells.get(3)?)?,
                number(cells.get(4)?)?,
            ))
        })
        .collect()
}

#[test]
fn every_shared_mesh_matches_the_readme() {
    let dir = data_dir();
    if !dir.is_dir() {
        eprintln!(
            "SKIPPED: mesh folder {} not found (set GEODESICS_DATA)",
            dir.display()
        );
        return;
    }
    let readme =
        std::fs::read_to_string(dir.join("README.md")).expect("README.md next to the meshes");
    let table = readme_counts(&readme);
    assert!(
        table.len() >= 14,
        "README table has only {} rows",
        table.len()
    );

    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            geodesics_io::MeshFormat::from_extension(
                p.extension().and_then(|e| e.to_str()).unwrap_or(""),
            )
            .is_some()
        })
        .collect();
    files.sort();
    for (name, _, _) in &table {
        assert!(
            files
                .iter()
                .any(|f| f.file_name().unwrap() == name.as_str()),
            "{name} listed but missing"
        );
    }

    for path in &files {
        let name = path.file_name().unwrap().to_str().unwrap();
        let start = Instant::now();
        let soup = read_mesh(path).unwrap_or_else(|e| panic!("{e}"));
        let elapsed = start.elapsed();
        let (v, f) = (soup.positions.len(), soup.triangles.len());
        eprintln!(
            "{name}: V {v}, F {f}, read in {:.1} ms",
            elapsed.as_secs_f64() * 1e3
        );
        let (_, ev, ef) = table
            .iter()
            .find(|(n, _, _)| n == name)
            .unwrap_or_else(|| panic!("{name} has no row in the README table"));
        assert_eq!((v, f), (*ev, *ef), "{name}: V, F");
        Mesh::build(soup, &BuildOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    }

    // The synthetic meshes have no table row: they must read and build.
    let synthetic = dir.join("synthetic");
    if let Ok(entries) = std::fs::read_dir(&synthetic) {
        for path in entries.map(|e| e.unwrap().path()) {
            if path.extension().is_some_and(|e| e == "md") {
                continue;
            }
            let soup = read_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
            eprintln!(
                "synthetic/{}: V {}, F {}",
                path.file_name().unwrap().to_string_lossy(),
                soup.positions.len(),
                soup.triangles.len()
            );
            Mesh::build(soup, &BuildOptions::default())
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
    }
}

/// dragon.ply (binary PLY, 871k faces) must read fast; the time is printed,
/// not asserted (`cargo test --release -p geodesics-io -- --nocapture dragon`).
#[test]
fn dragon_read_time() {
    let path = data_dir().join("dragon.ply");
    if !path.is_file() {
        eprintln!("SKIPPED: {} not found (set GEODESICS_DATA)", path.display());
        return;
    }
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let start = Instant::now();
        let soup = read_mesh(&path).unwrap();
        best = best.min(start.elapsed().as_secs_f64());
        assert_eq!(
            (soup.positions.len(), soup.triangles.len()),
            (437_645, 871_414)
        );
    }
    let start = Instant::now();
    let bytes = std::fs::read(&path).unwrap();
    let io = start.elapsed().as_secs_f64();
    let start = Instant::now();
    geodesics_io::read_mesh_bytes(&bytes, geodesics_io::MeshFormat::Ply).unwrap();
    let parse = start.elapsed().as_secs_f64();
    eprintln!(
        "dragon.ply: best of 3 reads {:.1} ms (last: file read {:.1} ms, parse {:.1} ms)",
        best * 1e3,
        io * 1e3,
        parse * 1e3
    );
}
