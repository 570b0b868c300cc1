//! ICH and FWP-CH against the exact reference distances (gdist / MMP) and
//! against our VTP, on every real and synthetic mesh of the manifest.
//!
//! Pass, for both schedules, from every listed source and from all of them
//! at once (to keep the run time moderate: on the larger meshes from vertex
//! 0 and from all sources; on the dragon from one source per variant and
//! up to a distance limit, the full dragon being `#[ignore]`d tests; what
//! is not checked is named in the output):
//!
//! - against our VTP: within `1e-12 ×` the largest finite reference
//!   distance at every vertex, infinite exactly where VTP is;
//! - against the reference: the same bar, infinite exactly where it is,
//!   with the special cases of `vtp_reference.rs`: the manifest's
//!   `oracle_misses` must be finite; on a mesh with a pinch vertex (cow.obj)
//!   ours may be shorter where a second solve from the pinch vertex shows
//!   the path goes through it; on the dragon, where gdist is proven wrong
//!   at a few vertices (`vtp_reference.rs` walks our VTP's paths there),
//!   ours may differ from gdist only where it agrees with our VTP.

use std::time::Instant;

use geodesics_ich::{IchOptions, Schedule};
use geodesics_mesh::Mesh;
use geodesics_tests::{EXACT, data_dir, load_mesh, reference_mesh};
use geodesics_vtp::VtpOptions;
use geodesics_window::Source;

const SCHEDULES: [(Schedule, &str); 2] =
    [(Schedule::PriorityQueue, "ich"), (Schedule::Fwp, "fwp-ch")];

fn vtp(mesh: &Mesh, sources: &[Source], limit: Option<f64>) -> (Vec<f64>, u64) {
    let options = VtpOptions {
        max_distance: limit,
        ..VtpOptions::default()
    };
    let (field, stats) = geodesics_vtp::solve(mesh, sources, &options).unwrap();
    (field.distance, stats.window_propagations)
}

fn ich(
    mesh: &Mesh,
    sources: &[Source],
    schedule: Schedule,
    limit: Option<f64>,
) -> (Vec<f64>, geodesics_window::Stats) {
    let options = IchOptions {
        schedule,
        max_distance: limit,
        ..IchOptions::default()
    };
    let (field, stats) = geodesics_ich::solve(mesh, sources, &options).unwrap();
    (field.distance, stats)
}

/// Checks every reference file of `key` (a manifest key such as
/// `bunny.off` or `dragon.ply.welded`) whose name passes `filter`, with
/// the given schedules. With a `limit`, every solver stops at that
/// distance: vertices whose reference distance is below it are checked as
/// usual, those beyond must be unreached, and those within `1e-9 ×` of it
/// either way.
fn check(
    key: &str,
    synthetic: bool,
    filter: &dyn Fn(&str) -> bool,
    schedules: &[(Schedule, &str)],
    limit: Option<f64>,
) {
    let Some(case) = reference_mesh(&format!("ich_reference {key}"), key, synthetic) else {
        return;
    };
    let gdist_known_wrong = case.file.starts_with("dragon");
    let mesh = &case.mesh;
    let pinch: Vec<u32> = (0..mesh.input_vertex_count() as u32)
        .filter(|&v| mesh.is_pinch(mesh.mesh_vertex(v)))
        .collect();
    let pinch_fields: Vec<Vec<f64>> = pinch
        .iter()
        .map(|&v| vtp(mesh, &[Source::Vertex(v)], None).0)
        .collect();
    let mut failures = Vec::new();
    let mut skipped = Vec::new();
    for reference_file in &case.files {
        let name = &reference_file.name;
        if !filter(name) {
            skipped.push(name.as_str());
            continue;
        }
        let (sources, max_finite) = (&reference_file.sources, reference_file.max_finite);
        let misses = &reference_file.oracle_misses;
        let reference = reference_file.distances();
        let tol = EXACT * max_finite;
        let t = Instant::now();
        let (ours_vtp, vtp_props) = vtp(mesh, sources, limit);
        let vtp_s = t.elapsed().as_secs_f64();
        let near_limit = |x: f64| limit.is_some_and(|m| (x - m).abs() <= 1e-9 * m);
        let (mut beyond_limit, mut at_limit) = (0, 0);
        for &(schedule, label) in schedules {
            let t = Instant::now();
            let (ours, stats) = ich(mesh, sources, schedule, limit);
            let solve_s = t.elapsed().as_secs_f64();
            assert_eq!(ours.len(), reference.len(), "{name}: vertex count");
            let mut bad = Vec::new();
            let (mut worst_ref, mut worst_vtp) = (0.0f64, 0.0f64);
            let (mut via_pinch, mut as_vtp) = (0, 0);
            for (i, ((&d, &r), &v)) in ours.iter().zip(&reference).zip(&ours_vtp).enumerate() {
                assert!(!d.is_nan(), "{label} {name}: NaN at vertex {i}");
                if near_limit(r) || near_limit(d) || near_limit(v) {
                    at_limit += 1;
                    continue;
                }
                if limit.is_some_and(|m| r > m) && !misses.contains(&i) {
                    beyond_limit += 1;
                    if d.is_finite() {
                        bad.push(format!("vertex {i}: {label} {d} beyond the limit"));
                    }
                    continue;
                }
                // Against our VTP, everywhere.
                if d.is_infinite() || v.is_infinite() {
                    if d.is_infinite() != v.is_infinite() {
                        bad.push(format!("vertex {i}: {label} {d}, vtp {v}"));
                    }
                } else {
                    worst_vtp = worst_vtp.max((d - v).abs());
                    if (d - v).abs() > tol {
                        bad.push(format!(
                            "vertex {i}: {label} {d:.17}, vtp {v:.17}, diff {:.3e}",
                            d - v
                        ));
                    }
                }
                // Against the reference.
                if misses.contains(&i) {
                    if !d.is_finite() && limit.is_none() {
                        bad.push(format!("oracle miss {i} left infinite"));
                    }
                    continue;
                }
                if r.is_infinite() || d.is_infinite() {
                    if r.is_infinite() != d.is_infinite() {
                        bad.push(format!("vertex {i}: {label} {d}, reference {r}"));
                    }
                    continue;
                }
                let err = d - r;
                if err.abs() <= tol {
                    worst_ref = worst_ref.max(err.abs());
                    continue;
                }
                if err < 0.0
                    && pinch
                        .iter()
                        .zip(&pinch_fields)
                        .any(|(&p, pf)| (ours[p as usize] + pf[i] - d).abs() <= tol)
                {
                    via_pinch += 1;
                    continue;
                }
                if gdist_known_wrong && (d - v).abs() <= tol {
                    as_vtp += 1;
                    continue;
                }
                worst_ref = worst_ref.max(err.abs());
                bad.push(format!(
                    "vertex {i}: {label} {d:.17}, reference {r:.17}, diff {err:.3e}"
                ));
            }
            eprintln!(
                "ich_reference {label} {name}: max |err|/max vs reference {:.2e}, vs vtp {:.2e}, {} failures, {via_pinch} shorter via pinch, {as_vtp} off gdist as our vtp, solve {solve_s:.3}s (vtp {vtp_s:.3}s), {} propagations ({:.2}x vtp's {vtp_props}), peak {} windows ({} bytes)",
                worst_ref / max_finite,
                worst_vtp / max_finite,
                bad.len(),
                stats.window_propagations,
                stats.window_propagations as f64 / vtp_props as f64,
                stats.peak_live_windows,
                stats.peak_window_bytes,
            );
            if !bad.is_empty() {
                bad.truncate(10);
                failures.push(format!("{label} {name}: {}", bad.join("; ")));
            }
        }
        if let Some(m) = limit {
            eprintln!(
                "ich_reference {name}: LIMITED to distance {m} (of {max_finite}): {beyond_limit} vertex checks beyond it (unreached), {at_limit} within 1e-9 of it (not compared)"
            );
        }
    }
    if !skipped.is_empty() {
        eprintln!(
            "ich_reference {key}: NOT CHECKED here (run time): {}",
            skipped.join(", ")
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn all(_: &str) -> bool {
    true
}

/// On the larger meshes, to keep the run time moderate: the vertex-0 file
/// and the all-sources file (the others are named as not checked).
fn src0_and_multi(f: &str) -> bool {
    f.ends_with(".src0.txt") || f.ends_with(".multi.txt")
}

macro_rules! mesh_tests {
    ($($name:ident => $key:expr, $synthetic:expr, $filter:expr),* $(,)?) => {$(
        #[test]
        fn $name() {
            check($key, $synthetic, &$filter, &SCHEDULES, None);
        }
    )*};
}

mesh_tests! {
    armadillo => "armadillo.obj", false, src0_and_multi,
    blade => "blade.off", false, all,
    bunny => "bunny.off", false, src0_and_multi,
    bunny_zipper => "bunny_zipper.ply", false, src0_and_multi,
    camelhead => "camelhead.off", false, all,
    cow => "cow.obj", false, all,
    fandisk => "fandisk.obj", false, all,
    fertility => "fertility.off", false, all,
    hand => "hand.off", false, all,
    knot => "knot.stl", false, all,
    rockerarm => "rockerarm.off", false, all,
    screw => "screw_m3x10.stl", false, all,
    skull => "skull.glb", false, src0_and_multi,
    synthetic_grid => "grid101.off", true, src0_and_multi,
    synthetic_icosphere => "icosphere4.off", true, all,
    synthetic_torus => "torus120x40.off", true, all,
}

/// The dragon (871k faces; a full ICH solve takes minutes): one source
/// per variant, every solver stopped at distance 0.04 (about a seventh of
/// the largest distance). The full solves are the ignored tests below.
const DRAGON_LIMIT: f64 = 0.04;

fn dragon_stored(f: &str) -> bool {
    f == "dragon.ply.src12061.txt"
}

fn dragon_welded(f: &str) -> bool {
    f == "dragon.ply.welded.src0.txt"
}

#[test]
fn dragon_src12061_limited() {
    check(
        "dragon.ply",
        false,
        &dragon_stored,
        &SCHEDULES,
        Some(DRAGON_LIMIT),
    );
}

#[test]
fn dragon_welded_src0_limited() {
    check(
        "dragon.ply.welded",
        false,
        &dragon_welded,
        &SCHEDULES,
        Some(DRAGON_LIMIT),
    );
}

/// The whole dragon as stored from vertex 12061 (where gdist is proven too
/// short at one vertex, see `vtp_reference.rs`): about 20 minutes per
/// schedule on a loaded 2-core machine. `cargo test -p geodesics-tests
/// --test ich_reference -- --ignored`.
#[test]
#[ignore = "minutes: the full dragon"]
fn dragon_src12061_full() {
    check("dragon.ply", false, &dragon_stored, &SCHEDULES, None);
}

/// The whole welded dragon from vertex 0.
#[test]
#[ignore = "minutes: the full dragon"]
fn dragon_welded_src0_full() {
    check("dragon.ply.welded", false, &dragon_welded, &SCHEDULES, None);
}

/// cow.obj has a pinch vertex, where Xin's ICH aborts: from the pinch
/// vertex itself and from a neighbour of it, ours reaches every vertex and
/// agrees with our VTP everywhere (gdist does not pass through pinch
/// vertices, so VTP, checked against gdist elsewhere, is the bar here).
#[test]
fn cow_pinch_vertex() {
    let Some(data) = data_dir("ich_reference cow pinch vertex") else {
        return;
    };
    let mesh = load_mesh(&data.join("cow.obj"), false);
    let pinch: Vec<u32> = (0..mesh.input_vertex_count() as u32)
        .filter(|&v| mesh.is_pinch(mesh.mesh_vertex(v)))
        .collect();
    assert_eq!(pinch.len(), 1, "cow.obj has one pinch vertex");
    let p = pinch[0];
    // A neighbour of the pinch vertex, in one of its fans.
    let h = mesh
        .vertex_half_edge(p)
        .expect("the pinch vertex has faces");
    let q = mesh.pinch_origin(mesh.head(h));
    for src in [p, q] {
        let sources = [Source::Vertex(src)];
        let (v, _) = vtp(&mesh, &sources, None);
        let max = v
            .iter()
            .cloned()
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        for (schedule, label) in SCHEDULES {
            let (d, stats) = ich(&mesh, &sources, schedule, None);
            assert!(d.iter().all(|x| x.is_finite()), "{label}: unreached vertex");
            let worst = d
                .iter()
                .zip(&v)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            eprintln!(
                "ich_reference cow.obj {label} from vertex {src} (pinch {p}): max |err|/max vs vtp {:.2e}, {} propagations",
                worst / max,
                stats.window_propagations
            );
            assert!(worst <= EXACT * max, "{label} from {src}: {worst:e}");
        }
    }
}
