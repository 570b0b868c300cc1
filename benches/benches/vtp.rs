//! Exact VTP from vertex 0 on the meshes of the VTP issue's speed table.
//! `cargo xtask bench` prints the same measurements as a table with window
//! counts and gdist measured in the same run.

use criterion::{Criterion, criterion_group, criterion_main};
use geodesics::{Algorithm, Source};

fn vtp(c: &mut Criterion) {
    let Some(dir) = geodesics_tests::data_dir("vtp benchmark") else {
        return;
    };
    let mut group = c.benchmark_group("vtp");
    group.sample_size(10);
    for file in ["bunny.off", "armadillo.obj"] {
        // Renumbered for locality, as the CLI loads it.
        let mesh = geodesics_tests::load_mesh(&dir.join(file), false);
        group.bench_function(file, |b| {
            b.iter(|| {
                geodesics::compute(&mesh, &[Source::Vertex(0)], &Algorithm::default())
                    .expect("solves")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, vtp);
criterion_main!(benches);
