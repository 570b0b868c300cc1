//! Fuzz target: the Ply reader, then the mesh builder on whatever it accepts.
#![no_main]

use geodesics_io::{MeshFormat, read_mesh_bytes};
use geodesics_mesh::{BuildOptions, Mesh};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(soup) = read_mesh_bytes(data, MeshFormat::Ply) {
        let _ = Mesh::build(soup.clone(), &BuildOptions::default());
        let weld = BuildOptions {
            weld: true,
            ..BuildOptions::default()
        };
        let _ = Mesh::build(soup, &weld);
    }
});
