//! `geodesics path` end to end: the demo, every output format, VTP and MMP
//! agreeing, and refusals.

use std::process::{Command, Output};

use serde_json::Value;

fn geodesics(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geodesics"))
        .args(args)
        .output()
        .expect("the geodesics binary runs")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

fn refuse(args: &[&str]) -> String {
    let out = geodesics(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{args:?}: stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    stderr
}

#[test]
fn demo_path_summary() {
    let stdout = ok(&geodesics(&["path", "--target", "2000"]));
    insta::assert_snapshot!(stdout);
}

#[test]
fn formats_and_algorithms() {
    let dir = std::env::temp_dir().join(format!("geodesics-cli-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("p.json");
    let obj = dir.join("p.obj");
    let csv = dir.join("p.csv");
    let base = ["path", "--target", "1234", "--source", "7"];
    ok(&geodesics(
        &[&base[..], &["--output", json.to_str().unwrap()]].concat(),
    ));
    ok(&geodesics(
        &[
            &base[..],
            &["--algorithm", "mmp", "--output", obj.to_str().unwrap()],
        ]
        .concat(),
    ));
    ok(&geodesics(
        &[&base[..], &["--output", csv.to_str().unwrap()]].concat(),
    ));
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let points = doc["points"].as_array().unwrap();
    assert_eq!(points[0]["kind"], "vertex");
    assert_eq!(points[0]["vertices"][0], 7);
    assert_eq!(points.last().unwrap()["vertices"][0], 1234);
    let length = doc["length"].as_f64().unwrap();
    // The OBJ polyline (from MMP) has the same length as VTP's JSON path.
    let obj_text = std::fs::read_to_string(&obj).unwrap();
    let verts: Vec<[f64; 3]> = obj_text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let obj_length: f64 = verts
        .windows(2)
        .map(|w| {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .sum();
    assert!(
        (obj_length - length).abs() < 1e-12,
        "{obj_length} vs {length}"
    );
    assert!(obj_text.lines().any(|l| l.starts_with("l 1 2")));
    let csv_text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv_text.lines().count(), points.len() + 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn refusals() {
    assert!(refuse(&["path", "--target", "99999"]).contains("out of range"));
    assert!(refuse(&["path", "--target", "5", "--algorithm", "avtp"]).contains("traces no paths"));
    assert!(
        refuse(&["path", "--target", "5", "--output", "p.xyz"]).contains("unknown path format")
    );
}
