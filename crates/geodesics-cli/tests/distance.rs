//! `geodesics distance` end to end: the demo, a real mesh against the
//! reference, output formats, sources of every kind, and refusals.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use geodesics_tests::{data_dir, max_finite, parse_distances, read_distances, reference_dir};
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

/// Runs the CLI expecting a clean refusal: exit 1, one line on stderr.
fn refuse(args: &[&str]) -> String {
    let out = geodesics(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{args:?}: stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    stderr
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("geodesics-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn demo_runs_without_arguments() {
    let stdout = ok(&geodesics(&["distance"]));
    assert!(stdout.contains("demo:bumpy:4"), "{stdout}");
    assert!(stdout.contains("reached 2562 of 2562 vertices"), "{stdout}");
    let filtered = regex_free_mask(&stdout);
    insta::assert_snapshot!(filtered);
}

/// Masks timings (they vary) but keeps every count.
fn regex_free_mask(text: &str) -> String {
    text.lines()
        .map(|l| {
            if let Some(rest) = l.strip_prefix("solve ") {
                let after = rest.split_once(" s: ").map_or(rest, |(_, a)| a);
                let (props, tail) = after.split_once(" (").unwrap_or((after, ""));
                let tail = tail.split_once(" ns each), ").map_or(tail, |(_, t)| t);
                format!("solve [t] s: {props} ([t] ns each), {tail}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn flat_grid_from_a_face_point_is_euclidean() {
    let dir = scratch("grid");
    let out = dir.join("d.txt");
    // Face 0 of grid:10x10 is [0, 1, 12] at (0,0), (1,0), (1,1).
    ok(&geodesics(&[
        "distance",
        "--demo",
        "grid:10x10",
        "--source-point",
        "0:0.5,0.25,0.25",
        "--output",
        s(&out),
    ]));
    let d = read_distances(&out);
    let (sx, sy) = (0.5, 0.25); // 0.5*(0,0) + 0.25*(1,0) + 0.25*(1,1)
    for (v, &got) in d.iter().enumerate() {
        let (x, y) = ((v % 11) as f64, (v / 11) as f64);
        let want = ((x - sx).powi(2) + (y - sy).powi(2)).sqrt();
        assert!((got - want).abs() < 1e-12, "vertex {v}: {got} vs {want}");
    }
    // A point on the boundary edge 0-1, given from vertex 1: (0.25, 0).
    ok(&geodesics(&[
        "distance",
        "--demo",
        "grid:10x10",
        "--source-edge",
        "1,0:0.75",
        "--output",
        s(&out),
    ]));
    let d = read_distances(&out);
    for (v, &got) in d.iter().enumerate() {
        let (x, y) = ((v % 11) as f64, (v / 11) as f64);
        let want = ((x - 0.25).powi(2) + y.powi(2)).sqrt();
        assert!((got - want).abs() < 1e-12, "vertex {v}: {got} vs {want}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn stats_say_which_parameters_ran() {
    // A stats file is read long after the run: it names λ, λ_g, the
    // threads and the distance limit that produced its numbers.
    let dir = scratch("params");
    let stats = dir.join("stats.json");
    let run = |extra: &[&str]| -> (String, Value) {
        let mut args = vec!["distance", "--demo", "bumpy:3", "--stats", s(&stats)];
        args.extend_from_slice(extra);
        let stdout = ok(&geodesics(&args));
        let json = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
        (stdout, json)
    };
    let (stdout, json) = run(&["--algorithm", "avtp", "--lambda", "4"]);
    assert_eq!(json["lambda"], 4.0);
    assert_eq!(json["lambda_g"], 8.0);
    assert_eq!(json["threads"], 1);
    let resets = json["window_resets"].as_u64().unwrap();
    assert!(resets > 0, "{json}");
    assert!(
        stdout.contains(&format!(
            "λ = 4, λ_g = 8 (mean edge lengths), {resets} window resets"
        )),
        "{stdout}"
    );
    assert_eq!(json["light_apices"], false);
    let (stdout, json) = run(&["--algorithm", "pavtp", "--lambda", "4", "--light-apices"]);
    assert_eq!(json["light_apices"], true);
    assert!(stdout.contains("apices lit before each"), "{stdout}");
    let refused = refuse(&["distance", "--demo", "bumpy:3", "--light-apices"]);
    assert!(refused.contains("it is exact"), "{refused}");
    let (stdout, json) = run(&[
        "--algorithm",
        "pvtp",
        "--threads",
        "2",
        "--max-distance",
        "1",
    ]);
    assert_eq!(json["threads"], 2);
    assert_eq!(json["distance_limit"], 1.0);
    assert!(
        json["lambda"].is_null() && json["lambda_g"].is_null() && json["light_apices"].is_null(),
        "{json}"
    );
    assert_eq!(json["window_resets"], 0);
    assert!(stdout.contains("ran on 2 threads"), "{stdout}");
    let (stdout, json) = run(&[]);
    assert_eq!(json["threads"], 1);
    assert!(json["distance_limit"].is_null(), "{json}");
    assert!(
        !stdout.contains("approximate") && !stdout.contains("threads"),
        "{stdout}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn hand_matches_the_reference_and_writes_every_format() {
    let Some(data) = data_dir("distance CLI on hand.off") else {
        return;
    };
    let mesh = data.join("hand.off");
    let dir = scratch("hand");
    let txt = dir.join("d.txt");
    let stats = dir.join("stats.json");
    ok(&geodesics(&[
        "distance",
        s(&mesh),
        "--source",
        "0",
        "--output",
        s(&txt),
        "--stats",
        s(&stats),
    ]));
    let ours = read_distances(&txt);
    let reference = read_distances(&reference_dir(&data).join("hand.off.src0.txt"));
    let max = reference.iter().copied().fold(0.0, f64::max);
    for (v, (a, b)) in ours.iter().zip(&reference).enumerate() {
        assert!((a - b).abs() <= 1e-12 * max, "vertex {v}: {a} vs {b}");
    }
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    for key in [
        "time_seconds",
        "window_propagations",
        "windows_created",
        "peak_windows",
        "peak_window_bytes",
    ] {
        assert!(json[key].is_number(), "stats lacks {key}: {json}");
    }
    assert!(json["window_propagations"].as_u64().unwrap() > 0);
    // The process's peak memory: at least the mesh it read, far below a
    // gigabyte for a 2,390-face hand.
    if cfg!(target_os = "linux") {
        let rss = json["peak_rss_bytes"]
            .as_u64()
            .expect("Linux reports VmHWM");
        let file = std::fs::metadata(&mesh).unwrap().len();
        assert!(file < rss && rss < 1 << 30, "peak_rss_bytes {rss}");
    } else {
        assert!(json["peak_rss_bytes"].is_null() || json["peak_rss_bytes"].is_u64());
    }

    // Several sources: the field is the minimum.
    ok(&geodesics(&[
        "distance",
        s(&mesh),
        "--source",
        "0",
        "--source",
        "148",
        "--source",
        "942",
        "--output",
        s(&txt),
    ]));
    let multi = read_distances(&txt);
    let reference = read_distances(&reference_dir(&data).join("hand.off.multi.txt"));
    for (v, (a, b)) in multi.iter().zip(&reference).enumerate() {
        assert!((a - b).abs() <= 1e-12 * max, "multi vertex {v}: {a} vs {b}");
    }

    for ext in ["csv", "npy", "ply"] {
        let out = dir.join(format!("d.{ext}"));
        ok(&geodesics(&["distance", s(&mesh), "--output", s(&out)]));
        let bytes = std::fs::read(&out).unwrap();
        match ext {
            "csv" => {
                let text = String::from_utf8(bytes).unwrap();
                assert!(text.starts_with("vertex,distance\n"));
                assert_eq!(text.lines().count(), 1 + ours.len());
            }
            "npy" => {
                assert!(bytes.starts_with(b"\x93NUMPY"));
                assert_eq!(bytes.len() % 8, 0);
            }
            _ => {
                let back = geodesics_io::read_mesh(&out).unwrap();
                assert_eq!(back.positions.len(), ours.len());
            }
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn max_distance_leaves_far_vertices_unreachable() {
    let dir = scratch("max");
    let out = dir.join("d.txt");
    ok(&geodesics(&[
        "distance",
        "--demo",
        "grid:10x10",
        "--max-distance",
        "3.5",
        "--output",
        s(&out),
    ]));
    let d = parse_distances(&std::fs::read_to_string(&out).unwrap()).unwrap();
    for (v, &got) in d.iter().enumerate() {
        let (x, y) = ((v % 11) as f64, (v / 11) as f64);
        let want = (x * x + y * y).sqrt();
        if want <= 3.5 {
            assert!((got - want).abs() < 1e-12, "vertex {v}");
        } else {
            assert!(
                got.is_infinite() || (got - want).abs() < 1e-12,
                "vertex {v}: {got}"
            );
        }
    }
    assert!(d.iter().any(|x| x.is_infinite()));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn refusals_are_one_line_and_leave_the_input_untouched() {
    let dir = scratch("refuse");
    let mesh = dir.join("m.off");
    let text = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    std::fs::write(&mesh, text).unwrap();
    let e = refuse(&["distance", s(&mesh), "--output", s(&mesh)]);
    assert!(e.contains("overwrite"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--stats", s(&mesh)]);
    assert!(e.contains("overwrite"), "{e}");
    assert_eq!(std::fs::read_to_string(&mesh).unwrap(), text);
    let e = refuse(&["distance", s(&mesh), "--source", "17"]);
    assert!(e.contains("17"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--algorithm", "nope"]);
    assert!(e.contains("unknown algorithm `nope`"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--source-point", "5:1,0,0"]);
    assert!(e.contains("face 5"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--source-point", "0:0.5,0.5"]);
    assert!(e.contains("FACE:B0,B1,B2"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--source-edge", "0,2:1.5"]);
    assert!(e.contains("1.5"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--source-edge", "0,9:0.5"]);
    assert!(e.contains("out of range"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--source-edge", "1,3:0.5"]);
    assert!(e.contains("share no edge"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--max-distance=-1"]);
    assert!(e.contains("max-distance"), "{e}");
    let e = refuse(&["distance", s(&mesh), "--output", s(&dir.join("d.xyz"))]);
    assert!(e.contains("d.xyz"), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// The CLI renumbers meshes in memory; `--keep-order` does not. Every
/// number read or written is the file's either way: the same distances
/// (within the exactness bar) from a vertex, a face point and an edge
/// point, and the same mesh written back to PLY.
#[test]
fn keep_order_changes_nothing_the_user_sees() {
    let Some(data) = data_dir("distance CLI --keep-order on cow.obj") else {
        return;
    };
    let mesh = data.join("cow.obj");
    let soup = geodesics_io::read_mesh(&mesh).unwrap();
    let [a, b, _] = soup.triangles[100];
    let edge = format!("{a},{b}:0.3");
    let dir = scratch("keep-order");
    let run = |keep: bool, ext: &str| {
        let out = dir.join(format!("d{keep}.{ext}"));
        let mut args = vec![
            "distance",
            s(&mesh),
            "--source",
            "7",
            "--source-point",
            "100:0.2,0.3,0.5",
            "--source-edge",
            &edge,
            "--output",
            s(&out),
        ];
        if keep {
            args.push("--keep-order");
        }
        ok(&geodesics(&args));
        out
    };
    let kept = read_distances(&run(true, "txt"));
    let renumbered = read_distances(&run(false, "txt"));
    assert_eq!(kept.len(), soup.positions.len());
    let max = max_finite(&kept);
    for (v, (x, y)) in kept.iter().zip(&renumbered).enumerate() {
        assert!((x - y).abs() <= 1e-12 * max, "vertex {v}: {x} vs {y}");
    }
    let kept_ply = geodesics_io::read_mesh(&run(true, "ply")).unwrap();
    let renumbered_ply = geodesics_io::read_mesh(&run(false, "ply")).unwrap();
    assert_eq!(kept_ply, renumbered_ply);
    assert_eq!(kept_ply.positions, soup.positions);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_solve_without_propagations_prints_no_time_per_propagation() {
    // Two triangles sharing the edge 0–1, source 0: the distances come
    // along the edges and no window is propagated.
    let dir = scratch("no-propagation");
    let mesh = dir.join("two.off");
    std::fs::write(
        &mesh,
        "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 -1 0\n3 0 1 2\n3 1 0 3\n",
    )
    .unwrap();
    let out = dir.join("d.txt");
    let stdout = ok(&geodesics(&["distance", s(&mesh), "-o", s(&out)]));
    assert!(stdout.contains(" 0 window propagations, "), "{stdout}");
    assert!(!stdout.contains("ns each"), "{stdout}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// A bipyramid over a square, apex 1e12 above it: a needle.
fn write_needle(path: &Path) {
    let text = "OFF\n6 8 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n0 0 1e12\n0 0 -1\n\
                3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n3 1 0 5\n3 2 1 5\n3 3 2 5\n3 0 3 5\n";
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_needle_is_refused_by_name_solved_by_mmp_and_flagged_by_info() {
    let dir = scratch("needle");
    let mesh = dir.join("needle.off");
    write_needle(&mesh);
    let out = dir.join("d.txt");
    for algorithm in ["vtp", "pvtp", "avtp", "ich"] {
        let stderr = refuse(&[
            "distance",
            s(&mesh),
            "--algorithm",
            algorithm,
            "--output",
            s(&out),
        ]);
        assert!(
            stderr.contains("vertex 4 is a spike"),
            "{algorithm}: {stderr}"
        );
        assert!(!out.exists(), "{algorithm}: nothing written");
    }
    ok(&geodesics(&[
        "distance",
        s(&mesh),
        "--algorithm",
        "mmp",
        "--output",
        s(&out),
    ]));
    let d = read_distances(&out);
    // From vertex 0 straight up the face to the tip.
    assert!((d[4] - (1e24f64 + 1.0).sqrt()).abs() <= 1e-12 * d[4]);
    let info: Value = serde_json::from_str(&ok(&geodesics(&["info", s(&mesh), "--json"]))).unwrap();
    assert_eq!(info["sharpest_vertex"], 4);
    assert!(info["sharpest_angle"].as_f64().unwrap() < 1e-11);
    // `path` refuses it the same way, naming the file too, and MMP traces it.
    let stderr = refuse(&["path", s(&mesh), "--target", "4"]);
    assert!(
        stderr.contains("needle.off: vertex 4 is a spike"),
        "{stderr}"
    );
    ok(&geodesics(&[
        "path",
        s(&mesh),
        "--target",
        "4",
        "--algorithm",
        "mmp",
    ]));
    let table = ok(&geodesics(&["info", s(&mesh)]));
    assert!(
        table.contains("a needle, only mmp solves this mesh"),
        "{table}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
