//! Every algorithm of the facade from vertex 0 on `bunny.off` (Tables 1
//! and 3 of Qin et al. 2016): one entry per algorithm, so criterion's
//! report compares them measured in the same run. `cargo xtask tables`
//! prints the same comparison with propagations and peak memory.

use criterion::{Criterion, criterion_group, criterion_main};
use geodesics::{Algorithm, Source};

fn algorithms(c: &mut Criterion) {
    let Some(dir) = geodesics_tests::data_dir("algorithm benchmark") else {
        return;
    };
    // Renumbered for locality, as the CLI loads it.
    let mesh = geodesics_tests::load_mesh(&dir.join("bunny.off"), false);
    let mut group = c.benchmark_group("algorithms on bunny.off");
    group.sample_size(10);
    for &name in Algorithm::NAMES {
        let algorithm: Algorithm = name.parse().expect("listed names parse");
        group.bench_function(name, |b| {
            b.iter(|| geodesics::compute(&mesh, &[Source::Vertex(0)], &algorithm).expect("solves"))
        });
    }
    group.finish();
}

criterion_group!(benches, algorithms);
criterion_main!(benches);
