//! `geodesics info` end to end: real meshes against the README's table, the
//! broken-input corpus, usage errors, and the printed table.

use std::path::Path;
use std::process::{Command, Output};

use geodesics_tests::{REAL_MESHES, data_dir};
use serde_json::Value;

fn geodesics(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geodesics"))
        .args(args)
        .output()
        .expect("the geodesics binary runs")
}

fn assert_clean_failure(out: &Output, code: i32, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(code), "{what}: stderr {stderr}");
    assert!(!stderr.contains("panicked"), "{what} panicked: {stderr}");
    stderr
}

#[test]
fn info_json_reproduces_the_readme_table_on_every_real_mesh() {
    let Some(dir) = data_dir("info on real meshes") else {
        return;
    };
    for e in REAL_MESHES {
        let path = dir.join(e.file);
        let path = path.to_str().expect("utf-8 path");
        let mut args = vec!["info", path, "--json"];
        if e.weld {
            args.push("--weld");
        }
        let out = geodesics(&args);
        assert!(
            out.status.success(),
            "{}: {}",
            e.file,
            String::from_utf8_lossy(&out.stderr)
        );
        let v: Value = serde_json::from_slice(&out.stdout).expect("info --json prints JSON");
        let what = format!("{} (weld {})", e.file, e.weld);
        let num = |k: &str| {
            v[k].as_i64()
                .unwrap_or_else(|| panic!("{what}: key {k}: {v}"))
        };
        assert_eq!(num("vertices"), e.vertices as i64, "{what} vertices");
        assert_eq!(num("faces"), e.faces as i64, "{what} faces");
        assert_eq!(num("components"), e.components as i64, "{what} components");
        assert_eq!(
            num("boundary_loops"),
            e.boundary_loops as i64,
            "{what} loops"
        );
        assert_eq!(num("euler_characteristic"), e.euler, "{what} χ");
        assert_eq!(v["genus"].as_i64(), e.genus, "{what} genus");
        assert_eq!(
            num("nonmanifold_vertices"),
            e.nonmanifold_vertices as i64,
            "{what} pinch"
        );
        assert_eq!(
            num("zero_area_faces"),
            e.zero_area_faces as i64,
            "{what} zero-area"
        );
        assert_eq!(
            num("duplicate_positions"),
            e.duplicate_positions as i64,
            "{what} duplicates"
        );
        assert_eq!(
            num("unreferenced_vertices"),
            e.unreferenced_vertices as i64,
            "{what} unreferenced"
        );
        for key in [
            "saddle_vertices",
            "boundary_vertices",
            "anisotropy_mean",
            "bbox_diagonal",
            "length_scale",
            "sharpest_angle",
        ] {
            assert!(v[key].is_number(), "{what}: {key} missing");
        }
    }
}

#[test]
fn info_matches_the_readme_anisotropy_and_diagonal() {
    let Some(dir) = data_dir("anisotropy on real meshes") else {
        return;
    };
    // (file, g(M) mean, bbox diagonal) from the README table and details.
    for (file, mean, diagonal) in [
        ("armadillo.obj", 1.359, 1.512),
        ("blade.off", 10.516, 129.6),
        ("bunny.off", 1.635, 0.2502),
        ("fandisk.obj", 1.352, 7.616),
    ] {
        let out = geodesics(&["info", dir.join(file).to_str().unwrap(), "--json"]);
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        let got_mean = v["anisotropy_mean"].as_f64().unwrap();
        let got_diag = v["bbox_diagonal"].as_f64().unwrap();
        assert!(
            (got_mean - mean).abs() < 1e-3,
            "{file}: g(M) {got_mean} vs {mean}"
        );
        assert!(
            (got_diag - diagonal).abs() < 1e-3 * diagonal,
            "{file}: diagonal {got_diag} vs {diagonal}"
        );
    }
}

#[test]
fn broken_inputs_fail_with_one_line_and_exit_1() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fixtures/broken");
    let mut seen = 0;
    for entry in std::fs::read_dir(&corpus).expect("the broken corpus is committed") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            continue;
        }
        seen += 1;
        let out = geodesics(&["info", path.to_str().unwrap()]);
        let what = path.display().to_string();
        let stderr = assert_clean_failure(&out, 1, &what);
        assert_eq!(stderr.trim_end().lines().count(), 1, "{what}: {stderr}");
        assert!(stderr.starts_with("error: "), "{what}: {stderr}");
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(
            stderr.contains(name),
            "{what}: message must name the file: {stderr}"
        );
    }
    assert!(
        seen >= 8,
        "the corpus holds at least 8 broken files, found {seen}"
    );
}

#[test]
fn missing_file_and_usage_errors() {
    let out = geodesics(&["info", "/nonexistent/mesh.off"]);
    let stderr = assert_clean_failure(&out, 1, "missing file");
    assert!(stderr.contains("/nonexistent/mesh.off"), "{stderr}");
    // The system's reason once, not repeated by the chain of causes.
    let reason = stderr
        .rsplit(": ")
        .next()
        .expect("the message has a reason")
        .trim();
    assert_eq!(stderr.matches(reason).count(), 1, "{stderr}");
    let out = geodesics(&["info", "--no-such-flag"]);
    assert_clean_failure(&out, 2, "unknown flag");
    let out = geodesics(&["no-such-command"]);
    assert_clean_failure(&out, 2, "unknown subcommand");
}

#[test]
fn info_table_on_the_demo_mesh() {
    let out = geodesics(&["info", "--demo", "icosphere:2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8(out.stdout).unwrap();
    insta::with_settings!({filters => vec![(r"load \d+\.\d+ s, build \d+\.\d+ s", "load [t] s, build [t] s")]}, {
        insta::assert_snapshot!(table);
    });
}
