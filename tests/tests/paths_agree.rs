//! VTP's paths (traced from per-vertex provenance) and MMP's (backtraced
//! from its kept windows) are the same paths: same length, and the same
//! points one by one, on procedural and real meshes.

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_shapes::{bumpy_sphere, jittered_flat_grid, jittered_icosphere};
use geodesics_tests::data_dir;
use geodesics_window::{Source, SurfacePoint};

fn compare(name: &str, mesh: &Mesh, sources: &[Source], stride: usize) {
    let (field, _, prov) =
        geodesics_vtp::solve_with_provenance(mesh, sources, &Default::default()).unwrap();
    let mmp = geodesics_mmp::run(mesh, sources, &Default::default()).unwrap();
    let scale = mesh.bbox_diagonal();
    let (mut compared, mut worst) = (0, 0.0f64);
    for target in (0..mesh.input_vertex_count() as u32).step_by(stride) {
        if !field.distance[target as usize].is_finite() {
            continue;
        }
        let a = geodesics_vtp::trace_path(mesh, sources, &prov, &field, target).unwrap();
        let b = mmp.path_to_vertex(target).unwrap();
        assert!(
            (a.length - b.length).abs() <= 1e-12 * scale,
            "{name} target {target}: lengths {} and {}",
            a.length,
            b.length
        );
        // Ties between equally short paths may be broken differently; only
        // compare point by point when the two took the same route.
        let same_kinds = a.points.len() == b.points.len()
            && a.points.iter().zip(&b.points).all(|(p, q)| {
                std::mem::discriminant(p) == std::mem::discriminant(q)
                    && match (p, q) {
                        (SurfacePoint::Vertex(u), SurfacePoint::Vertex(v)) => u == v,
                        _ => true,
                    }
            });
        if !same_kinds {
            eprintln!("VTP {:?}\nMMP {:?}", a.points, b.points);
        }
        assert!(
            same_kinds,
            "{name} target {target}: VTP's path has {} points, MMP's {}",
            a.points.len(),
            b.points.len()
        );
        for (p, q) in a.polyline.iter().zip(&b.polyline) {
            worst = worst.max(p.distance(*q));
        }
        compared += 1;
    }
    eprintln!(
        "{name}: {compared} paths, worst point distance / scale {:.2e}",
        worst / scale
    );
    assert!(worst <= 1e-8 * scale, "{name}: points differ by {worst:e}");
}

#[test]
fn procedural_meshes() {
    let build = |s| Mesh::build(s, &BuildOptions::default()).unwrap();
    compare(
        "jittered grid",
        &build(jittered_flat_grid(20, 20, 1.0, 0.2, 3)),
        &[Source::Vertex(0)],
        1,
    );
    compare(
        "jittered icosphere",
        &build(jittered_icosphere(3, 1.0, 0.1, 4)),
        &[Source::Vertex(5)],
        1,
    );
    compare(
        "bumpy sphere",
        &build(bumpy_sphere(3, 1.0, 40, 0.2, 7)),
        &[Source::Vertex(0), Source::Vertex(300)],
        1,
    );
}

#[test]
fn real_meshes() {
    let Some(dir) = data_dir("paths_agree on real meshes") else {
        return;
    };
    for (file, stride) in [("hand.off", 1), ("fertility.off", 7), ("camelhead.off", 37)] {
        let soup = geodesics_io::read_mesh(&dir.join(file)).unwrap();
        let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap();
        compare(file, &mesh, &[Source::Vertex(0)], stride);
    }
}
