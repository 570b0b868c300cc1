//! Mesh readers (OBJ, PLY, OFF, STL, glTF/GLB) and writers of per-vertex
//! scalar fields (text, CSV, NPY, colored PLY) for `geodesics`.
//!
//! Readers return [`IndexedTriangles`] exactly as the file numbers its
//! vertices, so that per-vertex results line up with the input file:
//!
//! - **OBJ**: in order of the `v` lines, all vertices kept (unreferenced
//!   too), several objects/groups merged into one vertex array, negative
//!   indices relative to the vertices defined so far, texture/normal indices
//!   ignored.
//! - **OFF**, **PLY**: in file order, unreferenced vertices kept.
//! - **STL**: corners welded by exactly equal coordinates (`-0.0 == 0.0`),
//!   numbered in order of first appearance.
//! - **glTF/GLB**: in order of each primitive's position accessor, primitives
//!   and mesh instances (nodes of the default scene, or of every scene if
//!   there is no default) appended, positions transformed to world space.
//!
//! Polygons are fan-triangulated from their first corner. Readers never
//! panic; every defect is an [`IoError`] whose one-line message names the
//! file and the line (text formats) or byte offset (binary formats).
//! Geometric and topological defects (NaN coordinates, non-manifold edges,
//! faces repeating a vertex) are left to [`geodesics_mesh::Mesh::build`].
//!
//! # Example
//!
//! ```
//! use geodesics_io::{MeshFormat, read_mesh_bytes};
//!
//! let off = b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
//! let soup = read_mesh_bytes(off, MeshFormat::Off)?;
//! assert_eq!(soup.positions.len(), 4);
//! assert_eq!(soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
//!
//! // Defects name the place.
//! let err = read_mesh_bytes(b"OFF\n3 1 0\n0 0 0\n1 0\n", MeshFormat::Off).unwrap_err();
//! assert_eq!(err.to_string(), "<memory>: line 4: vertex 1: expected 3 coordinates, found 2");
//! # Ok::<(), geodesics_io::IoError>(())
//! ```
//!
//! Fields are written atomically (temporary file, then rename) by
//! [`write_field`], which refuses to overwrite any of the inputs.

mod error;
mod gltf;
mod obj;
mod off;
mod ply;
mod stl;
mod text;
mod write;

use std::path::Path;

pub use error::{IoError, Location};
pub use geodesics_mesh::IndexedTriangles;
pub use write::{FieldFormat, would_overwrite, write_bytes_atomic, write_field};

use error::display_name;

/// The mesh file formats [`read_mesh`] understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Stanford PLY, ascii or binary (`.ply`).
    Ply,
    /// Object File Format, ascii (`.off`).
    Off,
    /// Stereolithography, ascii or binary (`.stl`).
    Stl,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
}

impl MeshFormat {
    /// The format named by a file extension (case-insensitive, without the
    /// dot), if any.
    pub fn from_extension(ext: &str) -> Option<MeshFormat> {
        Some(match ext.to_ascii_lowercase().as_str() {
            "obj" => MeshFormat::Obj,
            "ply" => MeshFormat::Ply,
            "off" => MeshFormat::Off,
            "stl" => MeshFormat::Stl,
            "gltf" | "glb" => MeshFormat::Gltf,
            _ => return None,
        })
    }
}

/// Tells the format of a mesh file: by its extension if it has a known one,
/// otherwise by the first bytes `head` of its content (`ply` magic, `glTF`
/// magic or a JSON object, an OFF keyword, `solid`, OBJ statements; binary
/// STL only when `head` is the whole file, by its size `84 + 50 n`). `None`
/// if neither tells.
///
/// ```
/// use geodesics_io::{MeshFormat, detect_format};
/// use std::path::Path;
///
/// assert_eq!(detect_format(Path::new("a.GLB"), b""), Some(MeshFormat::Gltf));
/// assert_eq!(detect_format(Path::new("mesh.dat"), b"ply\nformat ascii 1.0\n"), Some(MeshFormat::Ply));
/// assert_eq!(detect_format(Path::new("mesh"), b"\x00\x01"), None);
/// ```
pub fn detect_format(path: &Path, head: &[u8]) -> Option<MeshFormat> {
    if let Some(f) = path
        .extension()
        .and_then(|e| e.to_str())
        .and_then(MeshFormat::from_extension)
    {
        return Some(f);
    }
    sniff(head)
}

/// Guesses the format from the content alone.
fn sniff(head: &[u8]) -> Option<MeshFormat> {
    if ply::has_magic(head) {
        return Some(MeshFormat::Ply);
    }
    if head.starts_with(b"glTF") {
        return Some(MeshFormat::Gltf);
    }
    if stl::is_binary(head) {
        // Only when `head` is the whole file: its size is 84 + 50 n.
        return Some(MeshFormat::Stl);
    }
    let text = head.trim_ascii_start();
    if text.starts_with(b"{") {
        return Some(MeshFormat::Gltf);
    }
    if stl::looks_ascii(head) {
        return Some(MeshFormat::Stl);
    }
    // First statement that is not a comment.
    let mut lines = text::Lines::new(head);
    let (_, first) = lines.next_content(true)?;
    let keyword = text::tokens(first).next()?;
    if off::is_keyword(keyword) {
        return Some(MeshFormat::Off);
    }
    const OBJ: [&[u8]; 12] = [
        b"v", b"vt", b"vn", b"vp", b"f", b"o", b"g", b"s", b"usemtl", b"mtllib", b"l", b"p",
    ];
    if OBJ.contains(&keyword) {
        return Some(MeshFormat::Obj);
    }
    None
}

/// Reads a mesh file; the format comes from the extension, or from the
/// content when the extension is missing or unknown (see [`detect_format`]).
/// glTF files may refer to external buffers next to them.
///
/// ```no_run
/// let soup = geodesics_io::read_mesh("bunny.off".as_ref())?;
/// println!("{} vertices, {} triangles", soup.positions.len(), soup.triangles.len());
/// # Ok::<(), geodesics_io::IoError>(())
/// ```
pub fn read_mesh(path: &Path) -> Result<IndexedTriangles, IoError> {
    let file = display_name(path);
    let bytes = std::fs::read(path).map_err(|source| IoError::Io {
        file: file.clone(),
        source,
    })?;
    if bytes.is_empty() {
        return Err(IoError::Empty { file });
    }
    let format =
        detect_format(path, &bytes).ok_or_else(|| IoError::UnknownFormat { file: file.clone() })?;
    let base = path.parent();
    parse(&bytes, format, Some(base.unwrap_or(Path::new(""))), file)
}

/// Reads a mesh from bytes in the given format; messages name the file
/// `<memory>`. glTF external buffers (other than `data:` URIs) need
/// [`read_mesh`].
pub fn read_mesh_bytes(bytes: &[u8], format: MeshFormat) -> Result<IndexedTriangles, IoError> {
    let file = "<memory>".to_owned();
    if bytes.is_empty() {
        return Err(IoError::Empty { file });
    }
    parse(bytes, format, None, file)
}

fn parse(
    bytes: &[u8],
    format: MeshFormat,
    base: Option<&Path>,
    file: String,
) -> Result<IndexedTriangles, IoError> {
    let result = match format {
        MeshFormat::Obj => obj::parse(bytes),
        MeshFormat::Ply => ply::parse(bytes),
        MeshFormat::Off => off::parse(bytes),
        MeshFormat::Stl => stl::parse(bytes),
        MeshFormat::Gltf => gltf::parse(bytes, base),
    };
    result.map_err(|e| e.with_file(file))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detect_by_extension_then_content() {
        let p = Path::new;
        assert_eq!(detect_format(p("x.OBJ"), b""), Some(MeshFormat::Obj));
        assert_eq!(detect_format(p("x.off"), b"ply\n"), Some(MeshFormat::Off));
        assert_eq!(detect_format(p("x.gltf"), b""), Some(MeshFormat::Gltf));
        assert_eq!(
            detect_format(p("x"), b"ply\r\nformat"),
            Some(MeshFormat::Ply)
        );
        assert_eq!(
            detect_format(p("x"), b"glTF\x02\0\0\0"),
            Some(MeshFormat::Gltf)
        );
        assert_eq!(
            detect_format(p("x.json"), b" {\"asset\":{}}"),
            Some(MeshFormat::Gltf)
        );
        assert_eq!(
            detect_format(p("x"), b"solid cube\n"),
            Some(MeshFormat::Stl)
        );
        assert_eq!(detect_format(p("x"), b"# c\nCOFF\n"), Some(MeshFormat::Off));
        assert_eq!(
            detect_format(p("x.txt"), b"# c\n\nv 1 2 3\n"),
            Some(MeshFormat::Obj)
        );
        assert_eq!(detect_format(p("x"), b"\0\0\0"), None);
        let mut stl = vec![0u8; 84 + 50];
        stl[80] = 1;
        assert_eq!(detect_format(p("x"), &stl), Some(MeshFormat::Stl));
        assert_eq!(detect_format(p("x"), b""), None);
    }

    #[test]
    fn empty_input_is_an_error() {
        let e = read_mesh_bytes(b"", MeshFormat::Ply).unwrap_err();
        assert_eq!(e.to_string(), "<memory>: the file is empty");
    }
}
