//! Every file of `tests/fixtures/broken/` must be refused, by the reader or
//! by `Mesh::build`, with a one-line message, never a panic; reader-level
//! defects must be reader errors naming the place.

use std::path::{Path, PathBuf};

use geodesics_io::{IoError, MeshFormat, read_mesh, read_mesh_bytes};
use geodesics_mesh::{Mesh, MeshError};

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/broken")
}

enum Refusal {
    Reader(IoError),
    Build(MeshError),
}

fn load(path: &Path) -> Result<Mesh, Refusal> {
    let soup = read_mesh(path).map_err(Refusal::Reader)?;
    Mesh::build(soup, &Default::default()).map_err(Refusal::Build)
}

/// (file, refused by the reader?, expected piece of the message)
const EXPECTED: &[(&str, bool, &str)] = &[
    (
        "truncated_binary.ply",
        true,
        "file ends inside face 1 (truncated?)",
    ),
    ("nan_coordinate.off", false, "non-finite"),
    (
        "index_out_of_range.off",
        true,
        "line 8: face 1 refers to vertex 4, but the file has 4 vertices",
    ),
    ("empty.obj", true, "empty.obj: the file is empty"),
    ("random_bytes.ply", true, "line 1: not a PLY file"),
    ("random_bytes.stl", true, "(truncated?)"),
    ("nonmanifold_edge.off", false, "non-manifold edge"),
    ("repeated_vertex.off", false, "repeats a vertex"),
    (
        "negative_index.obj",
        true,
        "negative_index.obj: line 9: face index -12 is beyond the 8 vertices defined so far",
    ),
    (
        "truncated_binary.stl",
        true,
        "byte 334: file ends inside triangle 5 of 12 (truncated?)",
    ),
    ("bad_magic.glb", true, "byte 0: not glTF"),
    ("truncated.glb", true, "(truncated?)"),
];

#[test]
fn every_broken_file_is_refused_on_one_line() {
    let dir = corpus_dir();
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap() != "README.md")
        .collect();
    files.sort();
    assert!(files.len() >= EXPECTED.len());
    for path in &files {
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(
            readme.contains(&format!("`{name}`")),
            "{name} is not described in README.md"
        );
        let outcome = std::panic::catch_unwind(|| load(path))
            .unwrap_or_else(|_| panic!("{name}: reading or building panicked"));
        let (by_reader, message) = match outcome {
            Ok(_) => panic!("{name}: was accepted"),
            Err(Refusal::Reader(e)) => (true, e.to_string()),
            Err(Refusal::Build(e)) => (false, e.to_string()),
        };
        eprintln!("{name}: {message}");
        assert!(
            !message.contains('\n'),
            "{name}: message has a line break: {message:?}"
        );
        if let Some(&(_, reader, piece)) = EXPECTED.iter().find(|(n, _, _)| *n == name) {
            assert_eq!(
                by_reader, reader,
                "{name}: refused by the wrong stage: {message}"
            );
            assert!(
                message.contains(piece),
                "{name}: {message:?} lacks {piece:?}"
            );
            if by_reader {
                assert!(
                    message.contains(name),
                    "{name}: message does not name the file: {message}"
                );
            }
        }
    }
    for (name, _, _) in EXPECTED {
        assert!(
            files.iter().any(|f| f.file_name().unwrap() == *name),
            "{name} missing"
        );
    }
}

/// Cheap deterministic stand-in for fuzzing (which needs nightly): mutate
/// valid and broken inputs byte by byte, truncate them at every length, and
/// feed them to every reader. Nothing may panic.
#[test]
fn mutated_inputs_never_panic() {
    let mut seeds: Vec<Vec<u8>> = std::fs::read_dir(corpus_dir())
        .unwrap()
        .map(|e| std::fs::read(e.unwrap().path()).unwrap())
        .collect();
    seeds.push(b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 2 3 1\n".to_vec());
    seeds.push(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 -1/1\nf -3 -2 -1\n".to_vec());
    seeds.push(
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
          property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
          0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            .to_vec(),
    );
    seeds.push(
        b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
          endloop\nendfacet\nendsolid s\n"
            .to_vec(),
    );
    let formats = [
        MeshFormat::Obj,
        MeshFormat::Ply,
        MeshFormat::Off,
        MeshFormat::Stl,
        MeshFormat::Gltf,
    ];
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let interesting = [
        0u8, 0xff, b'\n', b' ', b'-', b'9', b'/', b'#', b'\\', 0x80, b'e', b'.',
    ];
    let mut runs = 0;
    for seed in &seeds {
        for len in 0..=seed.len().min(600) {
            for f in formats {
                let _ = read_mesh_bytes(&seed[..len], f);
            }
            runs += 1;
        }
        for _ in 0..400 {
            let mut m = seed.clone();
            if m.is_empty() {
                m.push(0);
            }
            for _ in 0..1 + next() % 4 {
                let i = (next() % m.len() as u64) as usize;
                m[i] = if next() % 2 == 0 {
                    interesting[(next() % interesting.len() as u64) as usize]
                } else {
                    next() as u8
                };
            }
            for f in formats {
                if let Ok(soup) = read_mesh_bytes(&m, f) {
                    let _ = Mesh::build(soup, &Default::default());
                }
            }
            runs += 1;
        }
    }
    eprintln!(
        "{runs} mutated/truncated inputs x {} formats, no panic",
        formats.len()
    );
}
