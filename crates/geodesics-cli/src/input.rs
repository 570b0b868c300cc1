//! Loading the mesh a command works on: a file, or the built-in demo shape.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};

/// The built-in mesh used when no file is given.
pub const DEMO_SHAPE: &str = "bumpy:4";

/// Where the mesh comes from, shared by every subcommand.
#[derive(Args, Debug, Clone)]
pub struct MeshArgs {
    /// Mesh file (OBJ, PLY, OFF, STL, glTF/GLB). Without it, a built-in
    /// procedural mesh is used.
    pub mesh: Option<PathBuf>,
    /// Use a procedural mesh instead of a file, e.g. `icosphere:4`,
    /// `torus:120x40`, `grid:100x100`, `bumpy:5`.
    #[arg(long, value_name = "SPEC", num_args = 0..=1, conflicts_with = "mesh")]
    pub demo: Option<Option<String>>,
    /// Merge vertices with exactly equal positions before building topology.
    #[arg(long)]
    pub weld: bool,
    /// Keep the file's vertex and face order in memory. By default the mesh
    /// is renumbered internally so that neighbours sit close in memory
    /// (faster on files whose order is scattered); every number the commands
    /// read or print is the file's either way.
    #[arg(long)]
    pub keep_order: bool,
}

/// A loaded mesh with what it took to get it.
pub struct LoadedMesh {
    /// What the user asked for (file path or demo spec).
    pub name: String,
    /// The validated mesh.
    pub mesh: Mesh,
    /// Seconds spent reading the file (or generating the shape).
    pub load_seconds: f64,
    /// Seconds spent building topology.
    pub build_seconds: f64,
}

impl MeshArgs {
    /// Reads (or generates) and builds the mesh.
    pub fn load(&self) -> Result<LoadedMesh> {
        let start = Instant::now();
        let (name, soup) = match (&self.mesh, &self.demo) {
            (Some(path), _) => (path.display().to_string(), read(path)?),
            (None, spec) => {
                let spec = spec
                    .clone()
                    .flatten()
                    .unwrap_or_else(|| DEMO_SHAPE.to_string());
                let soup = geodesics_shapes::from_spec(&spec)
                    .with_context(|| format!("demo shape `{spec}`"))?;
                (format!("demo:{spec}"), soup)
            }
        };
        let load_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let options = BuildOptions {
            weld: self.weld,
            reorder: !self.keep_order,
        };
        let mesh = Mesh::build(soup, &options).with_context(|| name.clone())?;
        let build_seconds = start.elapsed().as_secs_f64();
        Ok(LoadedMesh {
            name,
            mesh,
            load_seconds,
            build_seconds,
        })
    }
}

fn read(path: &Path) -> Result<IndexedTriangles> {
    Ok(geodesics_io::read_mesh(path)?)
}
