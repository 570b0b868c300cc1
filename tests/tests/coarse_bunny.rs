//! The coarse bunny the benchmarks subdivide to compare with Du et al.'s
//! 235K- and 940K-face meshes (`cargo xtask bench|avtp|pvtp`):
//! `bunny.off` simplified to the 3,674 faces of their low-resolution
//! Stanford bunny is a closed genus-0 surface with their 1,839 vertices,
//! and exact VTP agrees with MMP on it and on its Loop subdivision.

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_tests::{EXACT, data_dir, max_finite};
use geodesics_window::Source;

/// Du et al.'s coarse bunny: 1,839 vertices, 3,674 faces.
const FACES: usize = 3_674;

#[test]
fn bunny_simplified_to_the_authors_face_count() {
    let Some(dir) = data_dir("coarse bunny") else {
        return;
    };
    let bunny = geodesics_io::read_mesh(&dir.join("bunny.off")).unwrap();
    let coarse = geodesics_shapes::simplify(&bunny, FACES).unwrap();
    assert_eq!(coarse.triangles.len(), FACES);
    // Same input, same mesh (the benchmarks rebuild it every run).
    assert_eq!(geodesics_shapes::simplify(&bunny, FACES).unwrap(), coarse);
    let fine = geodesics_shapes::loop_subdivide(&coarse, 1).unwrap();
    let mesh = Mesh::build(coarse, &BuildOptions::default()).unwrap();
    let s = mesh.summary();
    assert_eq!(
        (s.vertices, s.components, s.boundary_loops, s.genus),
        (1_839, 1, 0, Some(0))
    );
    assert_eq!(s.zero_area_faces, 0);
    for mesh in [mesh, Mesh::build(fine, &BuildOptions::default()).unwrap()] {
        let sources = [Source::Vertex(0)];
        let vtp = geodesics_vtp::solve(&mesh, &sources, &Default::default())
            .unwrap()
            .0
            .distance;
        let mmp = geodesics_mmp::solve(&mesh, &sources, &Default::default())
            .unwrap()
            .0
            .distance;
        let tol = EXACT * max_finite(&mmp);
        for (v, (a, b)) in vtp.iter().zip(&mmp).enumerate() {
            assert!((a - b).abs() <= tol, "vertex {v}: VTP {a}, MMP {b}");
        }
    }
}
