//! Times two steps of Loop and of midpoint subdivision on a large mesh
//! (default: an icosphere of subdivision 6, 81,920 faces).
//!
//! ```text
//! cargo run --release -p geodesics-shapes --example subdivide_timing [SPEC] [STEPS]
//! ```

use std::time::Instant;

use geodesics_shapes::{IndexedTriangles, Shape, ShapeError, loop_subdivide, midpoint_subdivide};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let spec = args.next().unwrap_or_else(|| "icosphere:6".to_owned());
    let steps: u32 = args.next().map_or(Ok(2), |s| s.parse())?;
    let mesh = Shape::from_spec(&spec)?.build()?;
    println!(
        "{spec}: {} vertices, {} faces; {steps} steps",
        mesh.positions.len(),
        mesh.triangles.len()
    );
    type Subdivide = fn(&IndexedTriangles, u32) -> Result<IndexedTriangles, ShapeError>;
    let schemes: [(&str, Subdivide); 2] =
        [("loop", loop_subdivide), ("midpoint", midpoint_subdivide)];
    for (name, f) in schemes {
        let mut best = f64::INFINITY;
        let mut faces = 0;
        for _ in 0..5 {
            let start = Instant::now();
            let out = f(&mesh, steps)?;
            best = best.min(start.elapsed().as_secs_f64());
            faces = out.triangles.len();
        }
        println!(
            "{name:>8}: {faces} faces in {:.1} ms (best of 5)",
            best * 1e3
        );
    }
    Ok(())
}
