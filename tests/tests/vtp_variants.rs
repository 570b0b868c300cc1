//! The paper's VTP variants (FTP, OPVTP, OPFTP, VTP-MMP, VTP-CH,
//! VTP-Exhaustive, VTP-Trimming and the Fig 12 ablations) on every
//! reference mesh: each agrees with plain VTP (itself checked against the
//! independent reference in `vtp_reference.rs`) within 1e-12 of the largest
//! distance at every vertex, and with the reference directly where the
//! reference is trustworthy (no pinch vertex, not the dragon).
//!
//! One source per mesh (the `src0` file); on the dragon only the variants
//! that change the schedule or the merge run, from one source, as stored
//! and welded (the others cost minutes there).

use geodesics_tests::{EXACT, reference_mesh};
use geodesics_vtp::{Source, VARIANTS, VtpOptions, solve};

fn check_mesh(key: &str, synthetic: bool) {
    check_mesh_with(key, synthetic, false);
}

/// `every_variant_on_the_dragon`: also the variants skipped there by
/// default (minutes each).
fn check_mesh_with(key: &str, synthetic: bool, all_variants: bool) {
    let Some(case) = reference_mesh(&format!("vtp_variants {key}"), key, synthetic) else {
        return;
    };
    let mesh = &case.mesh;
    let name = format!("{key}.src0.txt");
    let file = case
        .files
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("{name} not in the manifest"));
    let (sources, max_finite) = (&file.sources, file.max_finite);
    let reference = file.distances();
    let trusted =
        !key.starts_with("dragon") && !(0..mesh.vertex_count() as u32).any(|v| mesh.is_pinch(v));
    let vtp = solve(mesh, sources, &VtpOptions::default())
        .unwrap()
        .0
        .distance;
    let tol = EXACT * max_finite;
    for &(variant, ..) in VARIANTS {
        if key.starts_with("dragon") && !all_variants && !matches!(variant, "ftp" | "opvtp") {
            continue;
        }
        let options = VtpOptions::variant(variant).unwrap();
        let (field, stats) = solve(mesh, sources, &options).unwrap();
        let mut worst_vtp = 0.0f64;
        let mut worst_ref = 0.0f64;
        for (v, &d) in field.distance.iter().enumerate() {
            let e = vtp[v];
            assert_eq!(
                d.is_finite(),
                e.is_finite(),
                "{key} {variant}: vertex {v} is {d}, VTP says {e}"
            );
            if d.is_finite() {
                worst_vtp = worst_vtp.max((d - e).abs());
                if trusted {
                    worst_ref = worst_ref.max((d - reference[v]).abs());
                }
            }
        }
        eprintln!(
            "{key} {variant}: max |d - vtp| / max {:.2e}, max |d - reference| / max {:.2e}, {} propagations",
            worst_vtp / max_finite,
            worst_ref / max_finite,
            stats.window_propagations
        );
        assert!(
            worst_vtp <= tol,
            "{key} {variant}: off VTP by {worst_vtp:e}"
        );
        assert!(
            worst_ref <= tol,
            "{key} {variant}: off the reference by {worst_ref:e}"
        );
    }
}

macro_rules! mesh_tests {
    ($($test:ident: $key:expr, $synthetic:expr;)*) => {
        $(
            #[test]
            fn $test() {
                check_mesh($key, $synthetic);
            }
        )*
    };
}

mesh_tests! {
    armadillo: "armadillo.obj", false;
    blade: "blade.off", false;
    bunny: "bunny.off", false;
    bunny_zipper: "bunny_zipper.ply", false;
    camelhead: "camelhead.off", false;
    cow: "cow.obj", false;
    dragon: "dragon.ply", false;
    dragon_welded: "dragon.ply.welded", false;
    fandisk: "fandisk.obj", false;
    fertility: "fertility.off", false;
    hand: "hand.off", false;
    knot: "knot.stl", false;
    rockerarm: "rockerarm.off", false;
    screw: "screw_m3x10.stl", false;
    skull: "skull.glb", false;
    grid: "grid101.off", true;
    icosphere: "icosphere4.off", true;
    torus: "torus120x40.off", true;
}

/// Every variant on the dragon, as stored and welded (run with
/// `-- --ignored`; about ten minutes).
#[test]
#[ignore]
fn every_variant_on_the_dragon() {
    check_mesh_with("dragon.ply", false, true);
    check_mesh_with("dragon.ply.welded", false, true);
}

/// Every variant with a distance limit returns the unlimited field within
/// it and ∞ beyond (on `bunny.off`, from sources and limits where the
/// face-sorted schedule once stopped at the first face whose apex lay
/// beyond the limit, although windows crossing that face still reached
/// nearer vertices past its other edges: 5e-5 of the largest distance off,
/// and vertices left unreached).
#[test]
fn every_variant_keeps_the_field_within_a_distance_limit() {
    let Some(dir) = geodesics_tests::data_dir("vtp_variants limits") else {
        return;
    };
    let mesh = geodesics_tests::load_mesh(&dir.join("bunny.off"), false);
    let h = mesh.average_edge_length();
    for source in [21531, 0, 17000] {
        let sources = [Source::Vertex(source)];
        let full = solve(&mesh, &sources, &VtpOptions::default())
            .unwrap()
            .0
            .distance;
        let tol = EXACT * geodesics_tests::max_finite(&full);
        for limit in [10.0 * h, 40.0 * h] {
            for &(variant, ..) in VARIANTS {
                let options = VtpOptions {
                    max_distance: Some(limit),
                    ..VtpOptions::variant(variant).unwrap()
                };
                let limited = solve(&mesh, &sources, &options).unwrap().0.distance;
                let mut worst = 0.0f64;
                for (v, (&d, &e)) in limited.iter().zip(&full).enumerate() {
                    if (e - limit).abs() <= tol {
                        continue; // on the limit: either answer is right
                    }
                    if e < limit {
                        assert!(
                            d.is_finite(),
                            "{variant} from {source} within {limit}: vertex {v} at {e} left unreached"
                        );
                        worst = worst.max((d - e).abs());
                    } else {
                        assert!(
                            d.is_infinite(),
                            "{variant} from {source} within {limit}: vertex {v} at {e} reported as {d}"
                        );
                    }
                }
                assert!(
                    worst <= tol,
                    "{variant} from {source} within {limit}: off the unlimited field by {worst:e}"
                );
            }
        }
    }
}
