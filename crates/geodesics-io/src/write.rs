//! Writers of per-vertex scalar fields: text, CSV, NPY, colored binary PLY.
//! Every writer writes a temporary file next to the output and renames it
//! into place, and refuses to write over any of the inputs.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use geodesics_mesh::IndexedTriangles;

use crate::IoError;
use crate::error::display_name;

/// Output formats of [`write_field`], chosen by the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FieldFormat {
    /// `.txt`: one value per line, shortest round-trip decimal, `inf` for
    /// unreachable vertices.
    Text,
    /// `.csv`: a `vertex,distance` header, then `index,value` rows.
    Csv,
    /// `.npy`: NumPy format 1.0, little-endian `f8`, shape `(n,)`.
    Npy,
    /// `.ply`: binary little-endian PLY of the mesh with per-vertex
    /// `double distance` and `uchar red green blue` (a perceptual ramp over
    /// the finite values; unreachable vertices gray).
    Ply,
}

impl FieldFormat {
    /// The format for an output path, from its extension (case-insensitive).
    ///
    /// ```
    /// use geodesics_io::FieldFormat;
    /// assert_eq!(FieldFormat::from_path("d.NPY".as_ref()), Some(FieldFormat::Npy));
    /// assert_eq!(FieldFormat::from_path("d.json".as_ref()), None);
    /// ```
    pub fn from_path(path: &Path) -> Option<FieldFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "txt" => FieldFormat::Text,
            "csv" => FieldFormat::Csv,
            "npy" => FieldFormat::Npy,
            "ply" => FieldFormat::Ply,
            _ => return None,
        })
    }
}

/// Writes one value per vertex (`f64::INFINITY` = unreachable) to `path`, in
/// the [`FieldFormat`] its extension names.
///
/// `mesh` is required for `.ply` output; when given, `values` must have one
/// entry per mesh vertex. The file is written to a temporary file in the
/// same directory and renamed into place, so readers never see a partial
/// file. Refused, with nothing written, when `path` is the same file as any
/// of `protected_inputs` (compared after resolving symbolic links, and by
/// file identity on Unix).
///
/// ```
/// # let dir = std::env::temp_dir().join(format!("geodesics-io-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// let out = dir.join("distance.txt");
/// geodesics_io::write_field(&out, &[0.0, 1.5, f64::INFINITY], None, &[])?;
/// assert_eq!(std::fs::read_to_string(&out).unwrap(), "0\n1.5\ninf\n");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), geodesics_io::IoError>(())
/// ```
pub fn write_field(
    path: &Path,
    values: &[f64],
    mesh: Option<&IndexedTriangles>,
    protected_inputs: &[&Path],
) -> Result<(), IoError> {
    let file = display_name(path);
    let format = FieldFormat::from_path(path)
        .ok_or_else(|| IoError::UnknownFieldFormat { file: file.clone() })?;
    if let Some(m) = mesh
        && m.positions.len() != values.len()
    {
        return Err(IoError::LengthMismatch {
            file,
            values: values.len(),
            vertices: m.positions.len(),
        });
    }
    if format == FieldFormat::Ply && mesh.is_none() {
        return Err(IoError::MeshRequired { file });
    }
    if would_overwrite(path, protected_inputs) {
        return Err(IoError::WouldOverwriteInput { file });
    }
    let io_err = |source| IoError::Io {
        file: file.clone(),
        source,
    };
    atomic_write(path, |w| match (format, mesh) {
        (FieldFormat::Text, _) => write_text(w, values),
        (FieldFormat::Csv, _) => write_csv(w, values),
        (FieldFormat::Npy, _) => write_npy(w, values),
        (FieldFormat::Ply, Some(mesh)) => write_ply(w, values, mesh),
        (FieldFormat::Ply, None) => Err(io::Error::other("mesh required")),
    })
    .map_err(io_err)
}

/// Writes `bytes` to `path` atomically (temporary file beside it, then
/// rename), refusing when `path` is one of `protected_inputs`: for reports
/// and other small outputs that should never be half-written.
///
/// ```
/// # let dir = std::env::temp_dir().join(format!("geodesics-io-bytes-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// let out = dir.join("stats.json");
/// geodesics_io::write_bytes_atomic(&out, b"{}\n", &[])?;
/// assert!(geodesics_io::write_bytes_atomic(&out, b"{}\n", &[&out]).is_err());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), geodesics_io::IoError>(())
/// ```
pub fn write_bytes_atomic(
    path: &Path,
    bytes: &[u8],
    protected_inputs: &[&Path],
) -> Result<(), IoError> {
    let file = display_name(path);
    if would_overwrite(path, protected_inputs) {
        return Err(IoError::WouldOverwriteInput { file });
    }
    atomic_write(path, |w| w.write_all(bytes)).map_err(|source| IoError::Io { file, source })
}

/// Canonical form of a path that may not exist yet (its directory must).
fn resolve(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = fs::canonicalize(path) {
        return Some(p);
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    Some(fs::canonicalize(parent).ok()?.join(name))
}

/// Whether writing `out` would replace one of `inputs` (same path after
/// resolving `.`, `..` and symlinks, or the same file through a hard link):
/// lets a caller refuse before long work, as the writers do themselves.
pub fn would_overwrite(out: &Path, inputs: &[&Path]) -> bool {
    inputs.iter().any(|input| same_file(out, input))
}

/// Whether writing `out` would replace the file `input`.
fn same_file(out: &Path, input: &Path) -> bool {
    match (resolve(out), resolve(input)) {
        (Some(a), Some(b)) if a == b => return true,
        // Unresolvable (e.g. missing directory): compare as spelled.
        (None, _) | (_, None)
            if std::path::absolute(out).ok() == std::path::absolute(input).ok() =>
        {
            return true;
        }
        _ => {}
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (fs::metadata(out), fs::metadata(input)) {
            return a.dev() == b.dev() && a.ino() == b.ino();
        }
    }
    false
}

/// Writes through `body` into a temporary file next to `path`, then renames
/// it over `path`. On failure the temporary file is removed.
fn atomic_write(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> io::Result<()> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))?;
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(
        ".{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let tmp = dir.join(tmp_name);
    let file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
    let result = (|| {
        let mut w = BufWriter::with_capacity(1 << 16, file);
        body(&mut w)?;
        let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

fn write_text(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    for v in values {
        writeln!(w, "{v}")?;
    }
    Ok(())
}

fn write_csv(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    writeln!(w, "vertex,distance")?;
    for (i, v) in values.iter().enumerate() {
        writeln!(w, "{i},{v}")?;
    }
    Ok(())
}

/// The NPY 1.0 header for `n` little-endian f64, padded so that the data
/// starts at a multiple of 64 bytes.
fn npy_header(n: usize) -> Vec<u8> {
    let dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({n},), }}");
    let unpadded = 10 + dict.len() + 1;
    let total = unpadded.next_multiple_of(64);
    let header_len = total - 10;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header_len as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out.resize(total - 1, b' ');
    out.push(b'\n');
    out
}

fn write_npy(w: &mut impl Write, values: &[f64]) -> io::Result<()> {
    w.write_all(&npy_header(values.len()))?;
    for v in values {
        w.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// Unreachable (and NaN) vertices.
const GRAY: [u8; 3] = [128, 128, 128];

/// Viridis, sampled at 9 evenly spaced points (perceptually uniform, readable
/// in gray scale and by color-blind viewers).
const VIRIDIS: [[f64; 3]; 9] = [
    [68.0, 1.0, 84.0],
    [71.0, 44.0, 122.0],
    [59.0, 82.0, 139.0],
    [44.0, 113.0, 142.0],
    [33.0, 145.0, 140.0],
    [39.0, 173.0, 129.0],
    [92.0, 200.0, 99.0],
    [170.0, 220.0, 50.0],
    [253.0, 231.0, 37.0],
];

/// Color of `t` in `[0, 1]` on the ramp.
fn ramp(t: f64) -> [u8; 3] {
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|c| (a[c] + (b[c] - a[c]) * f).round() as u8)
}

/// Colors for `values`, the ramp spanning their finite range.
fn colors(values: &[f64]) -> impl Iterator<Item = [u8; 3]> + '_ {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let span = hi - lo;
    values.iter().map(move |&v| {
        if !v.is_finite() {
            GRAY
        } else if span > 0.0 {
            ramp((v - lo) / span)
        } else {
            ramp(0.0)
        }
    })
}

fn write_ply(w: &mut impl Write, values: &[f64], mesh: &IndexedTriangles) -> io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\n\
         comment per-vertex geodesic distance (inf = unreachable, shown gray)\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         property double distance\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.triangles.len()
    )?;
    let mut record = [0u8; 35];
    for ((p, v), rgb) in mesh.positions.iter().zip(values).zip(colors(values)) {
        for (k, x) in [p.x, p.y, p.z, *v].iter().enumerate() {
            record[8 * k..8 * k + 8].copy_from_slice(&x.to_le_bytes());
        }
        record[32..].copy_from_slice(&rgb);
        w.write_all(&record)?;
    }
    let mut face = [3u8; 13];
    for t in &mesh.triangles {
        for (k, i) in t.iter().enumerate() {
            face[1 + 4 * k..5 + 4 * k].copy_from_slice(&i.to_le_bytes());
        }
        w.write_all(&face)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A fresh empty directory for one test.
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("geodesics-io-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    fn tricky() -> Vec<f64> {
        vec![
            0.0,
            -0.0,
            0.1 + 0.2,
            1.0 / 3.0,
            f64::MIN_POSITIVE,
            5e-324,
            1e-300,
            1.7976931348623157e308,
            123_456_789.123_456_79,
            f64::INFINITY,
            2.0f64.sqrt(),
        ]
    }

    #[test]
    fn text_round_trips_bit_exactly() {
        let dir = scratch("txt");
        let out = dir.join("d.txt");
        let values = tricky();
        write_field(&out, &values, None, &[]).unwrap();
        let text = fs::read_to_string(&out).unwrap();
        let back: Vec<f64> = text.lines().map(|l| l.parse().unwrap()).collect();
        assert_eq!(back.len(), values.len());
        for (a, b) in values.iter().zip(&back) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
        }
        assert!(text.contains("\ninf\n"));
        assert_eq!(entries(&dir), vec!["d.txt"]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn csv_has_header_and_rows() {
        let dir = scratch("csv");
        let out = dir.join("d.CSV");
        write_field(&out, &[0.5, f64::INFINITY], None, &[]).unwrap();
        assert_eq!(
            fs::read_to_string(&out).unwrap(),
            "vertex,distance\n0,0.5\n1,inf\n"
        );
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn npy_header_is_valid() {
        for n in [0usize, 1, 7, 1000, 123_456_789] {
            let h = npy_header(n);
            assert_eq!(h.len() % 64, 0);
            assert_eq!(&h[..8], b"\x93NUMPY\x01\x00");
            assert_eq!(u16::from_le_bytes([h[8], h[9]]) as usize, h.len() - 10);
            assert_eq!(*h.last().unwrap(), b'\n');
            let dict = std::str::from_utf8(&h[10..]).unwrap().trim_end();
            assert_eq!(
                dict,
                format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({n},), }}")
            );
        }
        let dir = scratch("npy");
        let out = dir.join("d.npy");
        let values = tricky();
        write_field(&out, &values, None, &[]).unwrap();
        let bytes = fs::read(&out).unwrap();
        let start = npy_header(values.len()).len();
        assert_eq!(&bytes[..start], npy_header(values.len()).as_slice());
        assert_eq!(bytes.len(), start + 8 * values.len());
        for (i, v) in values.iter().enumerate() {
            let b: [u8; 8] = bytes[start + 8 * i..start + 8 * i + 8].try_into().unwrap();
            assert_eq!(f64::from_le_bytes(b).to_bits(), v.to_bits());
        }
        fs::remove_dir_all(dir).unwrap();
    }

    fn tetra() -> IndexedTriangles {
        IndexedTriangles {
            positions: vec![
                DVec3::new(1.0, 1.0, 1.0),
                DVec3::new(1.0, -1.0, -1.0),
                DVec3::new(-1.0, 1.0, -1.0),
                DVec3::new(-1.0, -1.0, 0.1),
            ],
            triangles: vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
        }
    }

    #[test]
    fn ply_reads_back_with_colors() {
        let dir = scratch("ply");
        let out = dir.join("d.ply");
        let mesh = tetra();
        let values = [0.0, 1.0, 2.0, f64::INFINITY];
        write_field(&out, &values, Some(&mesh), &[]).unwrap();
        assert_eq!(crate::read_mesh(&out).unwrap(), mesh);
        let bytes = fs::read(&out).unwrap();
        let body = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        assert_eq!(bytes.len(), body + 35 * 4 + 13 * 4);
        let rec = |i: usize| &bytes[body + 35 * i..body + 35 * (i + 1)];
        assert_eq!(f64::from_le_bytes(rec(2)[24..32].try_into().unwrap()), 2.0);
        assert_eq!(&rec(0)[32..], &[68, 1, 84]);
        assert_eq!(&rec(2)[32..], &[253, 231, 37]);
        assert_eq!(&rec(3)[32..], &GRAY);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn ramp_is_monotone_in_lightness() {
        let lum = |c: [u8; 3]| {
            0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])
        };
        let mut last = -1.0;
        for k in 0..=100 {
            let l = lum(ramp(f64::from(k) / 100.0));
            assert!(l > last, "{k}");
            last = l;
        }
        assert_eq!(colors(&[3.0, 3.0]).collect::<Vec<_>>(), vec![ramp(0.0); 2]);
    }

    #[test]
    fn refuses_to_overwrite_an_input() {
        let dir = scratch("protect");
        let input = dir.join("in.txt");
        fs::write(&input, "original").unwrap();
        let check = |out: &Path| {
            let e = write_field(
                out,
                &[1.0],
                None,
                &[Path::new("/nonexistent/x.off"), &input],
            )
            .unwrap_err();
            assert!(matches!(e, IoError::WouldOverwriteInput { .. }), "{e}");
            assert!(!e.to_string().contains('\n'));
            assert_eq!(fs::read_to_string(&input).unwrap(), "original");
        };
        check(&input);
        check(&dir.join(".").join("in.txt"));
        fs::create_dir(dir.join("sub")).unwrap();
        check(&dir.join("sub/../in.txt"));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&input, dir.join("link.txt")).unwrap();
            check(&dir.join("link.txt"));
            fs::hard_link(&input, dir.join("hard.txt")).unwrap();
            check(&dir.join("hard.txt"));
        }
        // A different file is fine.
        write_field(&dir.join("out.txt"), &[1.0], None, &[&input]).unwrap();
        assert_eq!(fs::read_to_string(&input).unwrap(), "original");
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn atomic_replace_and_no_leftovers() {
        let dir = scratch("atomic");
        let out = dir.join("d.txt");
        fs::write(&out, "old contents that are longer\n").unwrap();
        write_field(&out, &[2.5], None, &[]).unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "2.5\n");
        assert_eq!(entries(&dir), vec!["d.txt"]);
        // A missing directory: error naming the file, nothing created.
        let e = write_field(&dir.join("missing/d.txt"), &[1.0], None, &[]).unwrap_err();
        assert!(
            e.to_string()
                .starts_with(&format!("{}", dir.join("missing/d.txt").display()))
        );
        assert_eq!(entries(&dir), vec!["d.txt"]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn argument_errors_write_nothing() {
        let dir = scratch("args");
        let mesh = tetra();
        let e = write_field(&dir.join("d.ply"), &[1.0; 4], None, &[]).unwrap_err();
        assert!(matches!(e, IoError::MeshRequired { .. }), "{e}");
        let e = write_field(&dir.join("d.txt"), &[1.0; 3], Some(&mesh), &[]).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: 3 values given for a mesh of 4 vertices",
                dir.join("d.txt").display()
            )
        );
        let e = write_field(&dir.join("d.json"), &[1.0], None, &[]).unwrap_err();
        assert!(matches!(e, IoError::UnknownFieldFormat { .. }), "{e}");
        assert!(entries(&dir).is_empty());
        fs::remove_dir_all(dir).unwrap();
    }
}
