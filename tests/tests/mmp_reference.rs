//! MMP and FWP-MMP against the exact reference distances (gdist) and
//! against our VTP, on every real and synthetic mesh of the manifest.
//!
//! Pass, per schedule and reference file: at every vertex, within `1e-12 ×`
//! the largest finite reference distance of our VTP (infinite exactly where
//! VTP is), and of the reference (infinite exactly where it is), except at
//! the reference's known defects: the manifest's `oracle_misses` (must be
//! finite) and vertices where VTP itself differs from the reference (the
//! pinch vertex of cow.obj and the dragon's proven oracle errors, checked by
//! `vtp_reference.rs`); there agreeing with VTP is the bar. Such exceptions
//! are allowed only on cow.obj and the dragon, and are counted in the
//! printed line.
//!
//! Run time: the four meshes of 35k-50k vertices are checked from vertex 0
//! by both schedules and from all their sources at once by FWP (the other
//! single-source files are skipped, and say so); the dragon (871k faces,
//! about 38 M windows kept, 4 GB) as stored from vertex 0 by FWP only, the
//! welded dragon the same way but only with `--ignored`. Everything else:
//! every listed source, both schedules.

use std::time::Instant;

use geodesics_mmp::{MmpOptions, Schedule};
use geodesics_tests::{EXACT, reference_mesh};
use geodesics_vtp::VtpOptions;

/// Checks the reference files of manifest key `key`, each with the
/// schedules `plan` gives for its name (none: skipped, and said so).
fn check(key: &str, synthetic: bool, plan: &dyn Fn(&str) -> &'static [Schedule]) {
    let Some(case) = reference_mesh(&format!("mmp_reference {key}"), key, synthetic) else {
        return;
    };
    let mesh = &case.mesh;
    let exceptions_allowed = key.starts_with("cow.obj") || key.starts_with("dragon.ply");
    let mut failures = Vec::new();
    let mut checked = 0;
    for reference_file in &case.files {
        let name = &reference_file.name;
        let schedules = plan(name);
        if schedules.is_empty() {
            eprintln!("mmp_reference {name}: SKIPPED (run time; see the file's doc)");
            continue;
        }
        checked += 1;
        let (sources, max_finite) = (&reference_file.sources, reference_file.max_finite);
        let misses = &reference_file.oracle_misses;
        let reference = reference_file.distances();
        let t = Instant::now();
        let vtp = geodesics_vtp::solve(mesh, sources, &VtpOptions::default())
            .unwrap()
            .0
            .distance;
        let vtp_s = t.elapsed().as_secs_f64();
        let tol = EXACT * max_finite;
        for &schedule in schedules {
            let options = MmpOptions {
                schedule,
                ..MmpOptions::default()
            };
            let (field, stats) = geodesics_mmp::solve(mesh, sources, &options).unwrap();
            let ours = &field.distance;
            assert_eq!(ours.len(), reference.len(), "{name}: vertex count");
            let (mut worst_ref, mut worst_vtp) = (0.0f64, 0.0f64);
            let mut bad = Vec::new();
            let mut special = 0;
            for (i, ((&d, &r), &v)) in ours.iter().zip(&reference).zip(&vtp).enumerate() {
                if d.is_nan() {
                    bad.push(format!("NaN at vertex {i}"));
                    continue;
                }
                // Against our VTP: everywhere.
                if d.is_infinite() || v.is_infinite() {
                    if d.is_infinite() != v.is_infinite() {
                        bad.push(format!("vertex {i}: ours {d}, VTP {v}"));
                    }
                } else {
                    let e = (d - v).abs();
                    worst_vtp = worst_vtp.max(e);
                    if e > tol {
                        bad.push(format!(
                            "vertex {i}: ours {d:.17}, VTP {v:.17}, diff {:.3e}",
                            d - v
                        ));
                    }
                }
                // Against the reference, except its known defects.
                if misses.contains(&i) {
                    if !d.is_finite() {
                        bad.push(format!("oracle miss {i} left infinite"));
                    }
                    continue;
                }
                let agrees = |x: f64| {
                    if x.is_infinite() || r.is_infinite() {
                        x.is_infinite() == r.is_infinite()
                    } else {
                        (x - r).abs() <= tol
                    }
                };
                if agrees(d) {
                    if d.is_finite() {
                        worst_ref = worst_ref.max((d - r).abs());
                    }
                } else if !agrees(v) {
                    special += 1;
                } else {
                    bad.push(format!(
                        "vertex {i}: ours {d:.17}, reference {r:.17}, diff {:.3e}",
                        d - r
                    ));
                }
            }
            if special > 0 && !exceptions_allowed {
                bad.push(format!(
                    "{special} vertices where VTP and the reference disagree on a mesh without known oracle defects"
                ));
            }
            eprintln!(
                "mmp_reference {name} {schedule:?}: max |err| / max: reference {:.2e}, VTP {:.2e}; {} failures, {special} at oracle defects (VTP's value holds); solve {:.3}s (VTP {vtp_s:.3}s), {} propagations, {} windows kept, {:.1} MB windows",
                worst_ref / max_finite,
                worst_vtp / max_finite,
                bad.len(),
                stats.total_seconds,
                stats.window_propagations,
                stats.peak_live_windows,
                stats.peak_window_bytes as f64 / 1e6,
            );
            if !bad.is_empty() {
                bad.truncate(10);
                failures.push(format!("{name} {schedule:?}: {}", bad.join("; ")));
            }
        }
    }
    assert!(checked > 0, "{key}: no file checked");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

const BOTH: &[Schedule] = &[Schedule::PriorityQueue, Schedule::Fwp];
const FWP: &[Schedule] = &[Schedule::Fwp];

fn all(_: &str) -> &'static [Schedule] {
    BOTH
}

/// The meshes of 35k-50k vertices: vertex 0 by both schedules, all
/// sources at once by FWP, the other single sources skipped.
fn big(name: &str) -> &'static [Schedule] {
    if name.ends_with(".src0.txt") {
        BOTH
    } else if name.ends_with(".multi.txt") {
        FWP
    } else {
        &[]
    }
}

macro_rules! mesh_tests {
    ($($name:ident => $key:expr, $plan:expr);* $(;)?) => {$(
        #[test]
        fn $name() {
            check($key, false, &$plan);
        }
    )*};
}

mesh_tests! {
    armadillo => "armadillo.obj", big;
    blade => "blade.off", all;
    bunny => "bunny.off", big;
    bunny_zipper => "bunny_zipper.ply", big;
    camelhead => "camelhead.off", all;
    cow => "cow.obj", all;
    fandisk => "fandisk.obj", all;
    fertility => "fertility.off", all;
    hand => "hand.off", all;
    knot => "knot.stl", all;
    rockerarm => "rockerarm.off", all;
    screw => "screw_m3x10.stl", all;
    skull => "skull.glb", big;
}

#[test]
fn synthetic_grid() {
    check("grid101.off", true, &all);
}

#[test]
fn synthetic_icosphere() {
    check("icosphere4.off", true, &all);
}

#[test]
fn synthetic_torus() {
    check("torus120x40.off", true, &all);
}

/// The dragon as stored (871k faces, 151 components, zero-area faces,
/// gdist's misses), from vertex 0 by FWP only: MMP keeps every window
/// (about 38 M here, 4 GB), and a solve takes one to three minutes on two
/// busy cores. The other sources and the priority queue are skipped.
#[test]
fn dragon_src0_fwp() {
    check("dragon.ply", false, &|f: &str| {
        if f == "dragon.ply.src0.txt" { FWP } else { &[] }
    });
}

/// The welded dragon, the same way: 4 GB more and another minute or two,
/// so not in the default run (`cargo test -p geodesics-tests --test
/// mmp_reference -- --ignored`). Passed when written: max |err| / max
/// 2.0e-14 against gdist and VTP (the same at VTP), 124 vertices at
/// gdist's known defects, where VTP's value holds.
#[test]
#[ignore = "4 GB and minutes: run with --ignored"]
fn dragon_welded_src0_fwp() {
    check("dragon.ply.welded", false, &|f: &str| {
        if f == "dragon.ply.welded.src0.txt" {
            FWP
        } else {
            &[]
        }
    });
}
