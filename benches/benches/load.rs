//! Loading real meshes and building their topology (issue: dragon.ply, 871K
//! faces, goal ≤ 0.5 s for read + build).

use criterion::{Criterion, criterion_group, criterion_main};
use geodesics_mesh::{BuildOptions, Mesh};

fn load(c: &mut Criterion) {
    let Some(dir) = geodesics_tests::data_dir("load benchmark") else {
        return;
    };
    let mut group = c.benchmark_group("load");
    group.sample_size(10);
    for file in ["bunny.off", "armadillo.obj", "skull.glb", "dragon.ply"] {
        let path = dir.join(file);
        group.bench_function(format!("read/{file}"), |b| {
            b.iter(|| geodesics_io::read_mesh(&path).expect("real mesh reads"))
        });
        let soup = geodesics_io::read_mesh(&path).expect("real mesh reads");
        // `Mesh::build`'s default (file order), and renumbered for locality
        // as the CLI builds it.
        let renumbered = BuildOptions {
            reorder: true,
            ..BuildOptions::default()
        };
        group.bench_function(format!("build/{file}"), |b| {
            b.iter(|| Mesh::build(soup.clone(), &BuildOptions::default()).expect("builds"))
        });
        group.bench_function(format!("build, renumbered/{file}"), |b| {
            b.iter(|| Mesh::build(soup.clone(), &renumbered).expect("builds"))
        });
        group.bench_function(format!("read+build/{file}"), |b| {
            b.iter(|| {
                let soup = geodesics_io::read_mesh(&path).expect("real mesh reads");
                Mesh::build(soup, &BuildOptions::default()).expect("builds")
            })
        });
        group.bench_function(format!("read+build, renumbered/{file}"), |b| {
            b.iter(|| {
                let soup = geodesics_io::read_mesh(&path).expect("real mesh reads");
                Mesh::build(soup, &renumbered).expect("builds")
            })
        });
    }
    let path = dir.join("dragon.ply");
    group.bench_function("read+build/dragon.ply --weld", |b| {
        b.iter(|| {
            let soup = geodesics_io::read_mesh(&path).expect("real mesh reads");
            Mesh::build(
                soup,
                &BuildOptions {
                    weld: true,
                    ..BuildOptions::default()
                },
            )
            .expect("builds")
        })
    });
    group.finish();
}

criterion_group!(benches, load);
criterion_main!(benches);
