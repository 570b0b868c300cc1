//! PLY reader: `ascii`, `binary_little_endian`, `binary_big_endian`; every
//! scalar type name; extra vertex properties; list properties of any count
//! and item types; faces from a list named `vertex_indices` or
//! `vertex_index`; other elements skipped; polygons fan-triangulated.

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::error::{ParseError, show};
use crate::text::{Lines, parse_count, parse_f64, parse_i64, tokens};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Scalar> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// Reads a value as f64 from `b`, which holds exactly `self.size()` bytes
    /// (any shorter slice reads as 0; callers check bounds first).
    #[inline]
    fn read_f64(self, b: &[u8], big: bool) -> f64 {
        match self {
            Scalar::F32 => f64::from(f32::from_bits(read_u32(b, big))),
            Scalar::F64 => f64::from_bits(read_u64(b, big)),
            _ => self.read_i64(b, big) as f64,
        }
    }

    /// Reads an integer value (floats are truncated; callers only call this
    /// on integer types).
    #[inline]
    fn read_i64(self, b: &[u8], big: bool) -> i64 {
        match self {
            Scalar::I8 => i64::from(b.first().copied().unwrap_or(0) as i8),
            Scalar::U8 => i64::from(b.first().copied().unwrap_or(0)),
            Scalar::I16 => i64::from(read_u16(b, big) as i16),
            Scalar::U16 => i64::from(read_u16(b, big)),
            Scalar::I32 => i64::from(read_u32(b, big) as i32),
            Scalar::U32 => i64::from(read_u32(b, big)),
            Scalar::F32 => f32::from_bits(read_u32(b, big)) as i64,
            Scalar::F64 => f64::from_bits(read_u64(b, big)) as i64,
        }
    }
}

#[inline]
fn read_u16(b: &[u8], big: bool) -> u16 {
    let a: [u8; 2] = b.get(..2).and_then(|s| s.try_into().ok()).unwrap_or([0; 2]);
    if big {
        u16::from_be_bytes(a)
    } else {
        u16::from_le_bytes(a)
    }
}

#[inline]
fn read_u32(b: &[u8], big: bool) -> u32 {
    let a: [u8; 4] = b.get(..4).and_then(|s| s.try_into().ok()).unwrap_or([0; 4]);
    if big {
        u32::from_be_bytes(a)
    } else {
        u32::from_le_bytes(a)
    }
}

#[inline]
fn read_u64(b: &[u8], big: bool) -> u64 {
    let a: [u8; 8] = b.get(..8).and_then(|s| s.try_into().ok()).unwrap_or([0; 8]);
    if big {
        u64::from_be_bytes(a)
    } else {
        u64::from_le_bytes(a)
    }
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Property {
    name: Vec<u8>,
    kind: Kind,
}

#[derive(Debug)]
struct Element {
    name: Vec<u8>,
    count: usize,
    properties: Vec<Property>,
    /// Header line of the `element` statement (for messages).
    line: usize,
}

impl Element {
    fn property(&self, name: &[u8]) -> Option<usize> {
        self.properties.iter().position(|p| p.name == name)
    }

    /// Size of one record if every property is a scalar.
    fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .try_fold(0usize, |acc, p| match p.kind {
                Kind::Scalar(t) => Some(acc + t.size()),
                Kind::List { .. } => None,
            })
    }

    /// Smallest possible size of one record in the binary encoding.
    fn min_size(&self) -> usize {
        self.properties
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(t) => t.size(),
                Kind::List { count, .. } => count.size(),
            })
            .sum::<usize>()
            .max(1)
    }

    fn singular(&self) -> String {
        String::from_utf8_lossy(&self.name).into_owned()
    }
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
    /// Number of header lines (the body's first line is `lines + 1`).
    lines: usize,
}

/// Whether the data starts like a PLY file.
pub(crate) fn has_magic(head: &[u8]) -> bool {
    head.starts_with(b"ply\n") || head.starts_with(b"ply\r\n") || head == b"ply"
}

fn parse_header(data: &[u8]) -> Result<Header, ParseError> {
    let mut lines = Lines::new(data);
    match lines.next() {
        Some((_, l)) if l.trim_ascii_end() == b"ply" => {}
        _ => {
            return Err(ParseError::line(
                1,
                "not a PLY file (first line is not 'ply')",
            ));
        }
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some((n, line)) = lines.next() else {
            return Err(ParseError::line(
                lines.line_number() + 1,
                "file ends inside the header (no 'end_header' line)",
            ));
        };
        let mut toks = tokens(line);
        let Some(keyword) = toks.next() else { continue };
        match keyword {
            b"end_header" => break,
            b"comment" | b"obj_info" => {}
            b"format" => {
                let kind = toks.next().unwrap_or_default();
                encoding = Some(match kind {
                    b"ascii" => Encoding::Ascii,
                    b"binary_little_endian" => Encoding::Little,
                    b"binary_big_endian" => Encoding::Big,
                    other => {
                        return Err(ParseError::line(
                            n,
                            format!("unknown PLY format {}", show(other)),
                        ));
                    }
                });
            }
            b"element" => {
                let (Some(name), Some(count)) = (toks.next(), toks.next()) else {
                    return Err(ParseError::line(n, "expected 'element <name> <count>'"));
                };
                let count = parse_count(count).ok_or_else(|| {
                    ParseError::line(n, format!("invalid element count {}", show(count)))
                })?;
                elements.push(Element {
                    name: name.to_vec(),
                    count,
                    properties: Vec::new(),
                    line: n,
                });
            }
            b"property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(ParseError::line(n, "property before any element"));
                };
                let toks: Vec<&[u8]> = toks.collect();
                let scalar = |t: &[u8]| {
                    Scalar::from_name(t).ok_or_else(|| {
                        ParseError::line(n, format!("unknown property type {}", show(t)))
                    })
                };
                let property = match toks.as_slice() {
                    [b"list", count, item, name] => {
                        let count = scalar(count)?;
                        if !count.is_integer() {
                            return Err(ParseError::line(
                                n,
                                "list count type must be an integer type",
                            ));
                        }
                        Property {
                            name: name.to_vec(),
                            kind: Kind::List {
                                count,
                                item: scalar(item)?,
                            },
                        }
                    }
                    [ty, name] => Property {
                        name: name.to_vec(),
                        kind: Kind::Scalar(scalar(ty)?),
                    },
                    _ => {
                        return Err(ParseError::line(
                            n,
                            "expected 'property <type> <name>' or 'property list <count type> <item type> <name>'",
                        ));
                    }
                };
                element.properties.push(property);
            }
            other => {
                return Err(ParseError::line(
                    n,
                    format!("unknown header keyword {}", show(other)),
                ));
            }
        }
    }
    let Some(encoding) = encoding else {
        return Err(ParseError::line(1, "the header has no 'format' line"));
    };
    Ok(Header {
        encoding,
        elements,
        body: lines.offset(),
        lines: lines.line_number(),
    })
}

/// Where the parts we need are.
struct Layout {
    vertex: usize,
    xyz: [usize; 3],
    n_vertices: usize,
    /// Face element and its index-list property.
    face: Option<(usize, usize)>,
}

fn layout(h: &Header) -> Result<Layout, ParseError> {
    let mut vertex = None;
    let mut face = None;
    for (i, e) in h.elements.iter().enumerate() {
        let slot = match e.name.as_slice() {
            b"vertex" => &mut vertex,
            b"face" => &mut face,
            _ => continue,
        };
        if slot.is_some() {
            return Err(ParseError::line(
                e.line,
                format!("second '{}' element", e.singular()),
            ));
        }
        *slot = Some(i);
    }
    let Some(vertex) = vertex else {
        return Err(ParseError::whole("the header declares no 'vertex' element"));
    };
    let ve = &h.elements[vertex];
    let mut xyz = [0; 3];
    for (slot, name) in xyz.iter_mut().zip([&b"x"[..], b"y", b"z"]) {
        *slot = match ve.property(name) {
            Some(p) if matches!(ve.properties[p].kind, Kind::Scalar(_)) => p,
            Some(_) => {
                return Err(ParseError::line(
                    ve.line,
                    format!("vertex property '{}' is a list", name[0] as char),
                ));
            }
            None => {
                return Err(ParseError::line(
                    ve.line,
                    format!("the vertex element has no '{}' property", name[0] as char),
                ));
            }
        };
    }
    if ve.count > u32::MAX as usize {
        return Err(ParseError::line(
            ve.line,
            format!(
                "{} vertices is more than 32-bit indices can address",
                ve.count
            ),
        ));
    }
    let face = match face {
        None => None,
        Some(f) => {
            let fe = &h.elements[f];
            let p = fe
                .property(b"vertex_indices")
                .or_else(|| fe.property(b"vertex_index"))
                .ok_or_else(|| {
                    ParseError::line(
                        fe.line,
                        "the face element has no 'vertex_indices' (or 'vertex_index') list",
                    )
                })?;
            match fe.properties[p].kind {
                Kind::List { item, .. } if item.is_integer() => {}
                Kind::List { .. } => {
                    return Err(ParseError::line(
                        fe.line,
                        "face vertex indices must have an integer type",
                    ));
                }
                Kind::Scalar(_) => {
                    return Err(ParseError::line(
                        fe.line,
                        "face vertex indices must be a list property",
                    ));
                }
            }
            Some((f, p))
        }
    };
    Ok(Layout {
        vertex,
        xyz,
        n_vertices: ve.count,
        face,
    })
}

/// Adds the fan triangulation of one polygon, given its corners one by one.
struct Fan {
    v0: u32,
    prev: u32,
    corners: usize,
}

impl Fan {
    fn new() -> Self {
        Fan {
            v0: 0,
            prev: 0,
            corners: 0,
        }
    }

    #[inline]
    fn push(&mut self, v: u32, triangles: &mut Vec<[u32; 3]>) {
        match self.corners {
            0 => self.v0 = v,
            1 => {}
            _ => triangles.push([self.v0, self.prev, v]),
        }
        self.prev = v;
        self.corners += 1;
    }
}

fn index_error(face: usize, index: i64, n_vertices: usize) -> String {
    format!("face {face} refers to vertex {index}, but the file has {n_vertices} vertices")
}

pub(crate) fn parse(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    let header = parse_header(data)?;
    let layout = layout(&header)?;
    match header.encoding {
        Encoding::Ascii => parse_ascii(data, &header, &layout),
        Encoding::Little => parse_binary(data, &header, &layout, false),
        Encoding::Big => parse_binary(data, &header, &layout, true),
    }
}

fn parse_binary(
    data: &[u8],
    header: &Header,
    layout: &Layout,
    big: bool,
) -> Result<IndexedTriangles, ParseError> {
    let mut pos = header.body;
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let truncated = |at: usize, what: &str, i: usize| {
        ParseError::byte(at, format!("file ends inside {what} {i} (truncated?)"))
    };
    for (ei, e) in header.elements.iter().enumerate() {
        let remaining = data.len().saturating_sub(pos);
        let what = e.singular();
        if ei == layout.vertex {
            positions.reserve_exact(e.count.min(remaining / e.min_size()));
            if let Some(size) = e.fixed_size() {
                // Fast path: fixed-size records.
                let offsets = layout.xyz.map(|p| {
                    e.properties[..p]
                        .iter()
                        .map(|q| match q.kind {
                            Kind::Scalar(t) => t.size(),
                            Kind::List { .. } => 0,
                        })
                        .sum::<usize>()
                });
                let types = layout.xyz.map(|p| match e.properties[p].kind {
                    Kind::Scalar(t) => t,
                    Kind::List { .. } => Scalar::F64,
                });
                let total = size.checked_mul(e.count);
                let body = total
                    .and_then(|t| data.get(pos..pos.checked_add(t)?))
                    .ok_or_else(|| {
                        let i = remaining / size.max(1);
                        truncated(pos + i * size, &what, i)
                    })?;
                if size > 0 {
                    positions.extend(body.chunks_exact(size).map(|r| {
                        DVec3::new(
                            types[0].read_f64(r.get(offsets[0]..).unwrap_or(&[]), big),
                            types[1].read_f64(r.get(offsets[1]..).unwrap_or(&[]), big),
                            types[2].read_f64(r.get(offsets[2]..).unwrap_or(&[]), big),
                        )
                    }));
                }
                pos += body.len();
            } else {
                for i in 0..e.count {
                    let mut xyz = [0.0; 3];
                    for (pi, p) in e.properties.iter().enumerate() {
                        let start = pos;
                        match p.kind {
                            Kind::Scalar(t) => {
                                let b = data
                                    .get(pos..pos + t.size())
                                    .ok_or_else(|| truncated(start, &what, i))?;
                                if let Some(k) = layout.xyz.iter().position(|&x| x == pi) {
                                    xyz[k] = t.read_f64(b, big);
                                }
                                pos += t.size();
                            }
                            Kind::List { count, item } => {
                                pos = skip_list(data, pos, count, item, big)
                                    .ok_or_else(|| truncated(start, &what, i))?;
                            }
                        }
                    }
                    positions.push(DVec3::from_array(xyz));
                }
            }
        } else if Some(ei) == layout.face.map(|f| f.0) {
            let list = layout.face.map_or(0, |f| f.1);
            triangles.reserve_exact(e.count.min(remaining / e.min_size()));
            let n_vertices = layout.n_vertices;
            for f in 0..e.count {
                let record = pos;
                for (pi, p) in e.properties.iter().enumerate() {
                    match p.kind {
                        Kind::Scalar(t) => {
                            if pos + t.size() > data.len() {
                                return Err(truncated(record, &what, f));
                            }
                            pos += t.size();
                        }
                        Kind::List { count, item } if pi == list => {
                            let n = data
                                .get(pos..pos + count.size())
                                .map(|b| count.read_i64(b, big))
                                .ok_or_else(|| truncated(record, &what, f))?;
                            let n = usize::try_from(n).map_err(|_| {
                                ParseError::byte(
                                    pos,
                                    format!("{what} {f}: negative list length {n}"),
                                )
                            })?;
                            if n < 3 {
                                return Err(ParseError::byte(
                                    pos,
                                    format!("{what} {f} has {n} vertices (at least 3 needed)"),
                                ));
                            }
                            pos += count.size();
                            let size = item.size();
                            let items = data
                                .get(pos..pos.saturating_add(n.saturating_mul(size)))
                                .ok_or_else(|| truncated(record, &what, f))?;
                            let mut fan = Fan::new();
                            for b in items.chunks_exact(size) {
                                let k = item.read_i64(b, big);
                                if k < 0 || k as u64 >= n_vertices as u64 {
                                    return Err(ParseError::byte(
                                        pos,
                                        index_error(f, k, n_vertices),
                                    ));
                                }
                                fan.push(k as u32, &mut triangles);
                                pos += size;
                            }
                        }
                        Kind::List { count, item } => {
                            pos = skip_list(data, pos, count, item, big)
                                .ok_or_else(|| truncated(record, &what, f))?;
                        }
                    }
                }
            }
        } else if let Some(size) = e.fixed_size() {
            let end = size
                .checked_mul(e.count)
                .and_then(|t| pos.checked_add(t))
                .filter(|&end| end <= data.len())
                .ok_or_else(|| {
                    let i = remaining / size.max(1);
                    truncated(pos + i * size, &what, i)
                })?;
            pos = end;
        } else {
            for i in 0..e.count {
                let record = pos;
                for p in &e.properties {
                    match p.kind {
                        Kind::Scalar(t) => {
                            if pos + t.size() > data.len() {
                                return Err(truncated(record, &what, i));
                            }
                            pos += t.size();
                        }
                        Kind::List { count, item } => {
                            pos = skip_list(data, pos, count, item, big)
                                .ok_or_else(|| truncated(record, &what, i))?;
                        }
                    }
                }
            }
        }
    }
    Ok(IndexedTriangles {
        positions,
        triangles,
    })
}

/// Skips one binary list property starting at `pos`; `None` if the data ends
/// first or the length is negative.
fn skip_list(data: &[u8], pos: usize, count: Scalar, item: Scalar, big: bool) -> Option<usize> {
    let n = count.read_i64(data.get(pos..pos + count.size())?, big);
    let n = usize::try_from(n).ok()?;
    let end = (pos + count.size()).checked_add(n.checked_mul(item.size())?)?;
    (end <= data.len()).then_some(end)
}

fn parse_ascii(
    data: &[u8],
    header: &Header,
    layout: &Layout,
) -> Result<IndexedTriangles, ParseError> {
    let body = data.get(header.body..).unwrap_or_default();
    let mut lines = Lines::new(body);
    let line_of = |n: usize| n + header.lines;
    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (ei, e) in header.elements.iter().enumerate() {
        let what = e.singular();
        let remaining = body.len().saturating_sub(lines.offset());
        let is_vertex = ei == layout.vertex;
        let face_list = layout.face.filter(|f| f.0 == ei).map(|f| f.1);
        if is_vertex {
            positions.reserve_exact(e.count.min(remaining / 6));
        }
        if face_list.is_some() {
            triangles.reserve_exact(e.count.min(remaining / 8));
        }
        if e.properties.is_empty() {
            // Records without properties occupy no text.
            continue;
        }
        for i in 0..e.count {
            let (n, line) = {
                lines.next_content(false).ok_or_else(|| {
                    ParseError::line(
                        line_of(lines.line_number() + 1),
                        format!(
                            "file ends after {i} of {} {what} records (truncated?)",
                            e.count
                        ),
                    )
                })?
            };
            let line_no = line_of(n);
            let mut toks = tokens(line);
            let mut xyz = [0.0; 3];
            let mut fan = Fan::new();
            let mut found = 0usize;
            let mut needed = 0usize;
            let short = |found: usize, needed: usize| {
                ParseError::line(
                    line_no,
                    format!("{what} {i}: expected {needed} values, found {found}"),
                )
            };
            for (pi, p) in e.properties.iter().enumerate() {
                match p.kind {
                    Kind::Scalar(scalar) => {
                        needed += 1;
                        let t = toks.next().ok_or_else(|| short(found, needed))?;
                        found += 1;
                        if is_vertex && let Some(k) = layout.xyz.iter().position(|&x| x == pi) {
                            let value = parse_f64(t).ok_or_else(|| {
                                ParseError::line(
                                    line_no,
                                    format!("{what} {i}: invalid number {}", show(t)),
                                )
                            })?;
                            // The header's type is the value's precision: a
                            // `float` written as text is the nearest f32, as
                            // every other reader (and the binary path) sees it.
                            xyz[k] = if scalar == Scalar::F32 {
                                f64::from(value as f32)
                            } else {
                                value
                            };
                        }
                    }
                    Kind::List { .. } => {
                        needed += 1;
                        let t = toks.next().ok_or_else(|| short(found, needed))?;
                        found += 1;
                        let len = parse_count(t).ok_or_else(|| {
                            ParseError::line(
                                line_no,
                                format!("{what} {i}: invalid list length {}", show(t)),
                            )
                        })?;
                        let is_faces = face_list == Some(pi);
                        if is_faces && len < 3 {
                            return Err(ParseError::line(
                                line_no,
                                format!("{what} {i} has {len} vertices (at least 3 needed)"),
                            ));
                        }
                        needed = needed.saturating_add(len);
                        for _ in 0..len {
                            let t = toks.next().ok_or_else(|| short(found, needed))?;
                            found += 1;
                            if is_faces {
                                let k = parse_i64(t).ok_or_else(|| {
                                    ParseError::line(
                                        line_no,
                                        format!("{what} {i}: invalid vertex index {}", show(t)),
                                    )
                                })?;
                                if k < 0 || k as u64 >= layout.n_vertices as u64 {
                                    return Err(ParseError::line(
                                        line_no,
                                        index_error(i, k, layout.n_vertices),
                                    ));
                                }
                                fan.push(k as u32, &mut triangles);
                            }
                        }
                    }
                }
            }
            if is_vertex {
                positions.push(DVec3::from_array(xyz));
            }
        }
    }
    Ok(IndexedTriangles {
        positions,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(s: &[u8]) -> IndexedTriangles {
        parse(s).unwrap()
    }

    fn err(s: &[u8]) -> String {
        match parse(s).unwrap_err() {
            ParseError::At(loc, m) => format!("{loc}: {m}"),
            ParseError::Whole(m) => m,
        }
    }

    fn quad() -> IndexedTriangles {
        IndexedTriangles {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.5),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment hi\nobj_info x\n\
        element camera 1\nproperty float f\nproperty list uchar float k\n\
        element vertex 4\nproperty float32 x\nproperty float32 y\nproperty float32 z\n\
        property float confidence\nproperty list uint8 float32 extra\n\
        element face 1\nproperty uchar flags\nproperty list uint8 int32 vertex_indices\n\
        element edge 2\nproperty int vertex1\nproperty int vertex2\n\
        end_header\n\
        1.5 2 9 9\n\
        0 0 0 0.5 0\n1 0 0 0.5 1 7\n1 1 0 0.5 2 7 7\n0 1 0.5 0.5 0\n\
        3 4 0 1 2 3\n\
        0 1\n1 2\n";

    #[test]
    fn ascii_with_extras_and_other_elements() {
        assert_eq!(ok(ASCII.as_bytes()), quad());
        let crlf = ASCII.replace('\n', "\r\n");
        assert_eq!(ok(crlf.as_bytes()), quad());
    }

    /// Encodes `quad()` in binary with every feature: camera before,
    /// extra vertex properties and lists, face flags, `vertex_index`, edge after.
    fn binary(big: bool, types: [&str; 4]) -> Vec<u8> {
        let [coord, count, index, extra] = types;
        let fmt = if big {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut out = format!(
            "ply\r\nformat {fmt} 1.0\r\ncomment c\r\n\
             element camera 1\r\nproperty double f\r\nproperty list ushort {extra} k\r\n\
             element vertex 4\r\nproperty {extra} confidence\r\nproperty {coord} x\r\n\
             property {coord} y\r\nproperty {coord} z\r\n\
             element face 1\r\nproperty list {count} {index} vertex_index\r\nproperty char flags\r\n\
             element edge 1\r\nproperty list int uint e\r\n\
             end_header\r\n"
        )
        .into_bytes();
        let num = |out: &mut Vec<u8>, ty: &str, v: f64| {
            macro_rules! put {
                ($t:ty) => {{
                    let x = v as $t;
                    out.extend(if big {
                        x.to_be_bytes().to_vec()
                    } else {
                        x.to_le_bytes().to_vec()
                    });
                }};
            }
            match ty {
                "char" | "int8" => put!(i8),
                "uchar" | "uint8" => put!(u8),
                "short" | "int16" => put!(i16),
                "ushort" | "uint16" => put!(u16),
                "int" | "int32" => put!(i32),
                "uint" | "uint32" => put!(u32),
                "float" | "float32" => put!(f32),
                "double" | "float64" => put!(f64),
                _ => panic!("{ty}"),
            }
        };
        num(&mut out, "double", 1.0);
        num(&mut out, "ushort", 2.0);
        num(&mut out, extra, 3.0);
        num(&mut out, extra, 4.0);
        for p in quad().positions {
            num(&mut out, extra, 7.0);
            for c in p.to_array() {
                num(&mut out, coord, c);
            }
        }
        num(&mut out, count, 4.0);
        for k in 0..4 {
            num(&mut out, index, f64::from(k));
        }
        num(&mut out, "char", -1.0);
        num(&mut out, "int", 2.0);
        num(&mut out, "uint", 0.0);
        num(&mut out, "uint", 1.0);
        out
    }

    #[test]
    fn binary_both_endians_all_types() {
        let names = [
            "char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
            "int16", "uint16", "int32", "uint32", "float32", "float64",
        ];
        for big in [false, true] {
            for (k, extra) in names.iter().enumerate() {
                let coord = if k % 2 == 0 { "float" } else { "double" };
                let count = ["uchar", "ushort", "uint", "int8", "int16", "int32"][k % 6];
                let index = ["int", "uint", "ushort", "uchar", "int32", "uint16"][k % 6];
                let bytes = binary(big, [coord, count, index, extra]);
                assert_eq!(
                    ok(&bytes),
                    quad(),
                    "big={big} {coord} {count} {index} {extra}"
                );
            }
        }
    }

    #[test]
    fn integer_coordinates() {
        let mut q = quad();
        q.positions[3].z = 0.0;
        let bytes = binary(false, ["short", "uchar", "int", "float"]);
        assert_eq!(ok(&bytes), q);
    }

    #[test]
    fn truncation_is_reported_with_offset_and_record() {
        let bytes = binary(false, ["float", "uchar", "int", "float"]);
        let body = bytes
            .windows(12)
            .position(|w| w == b"end_header\r\n")
            .unwrap()
            + 12;
        // camera: 8 + 2 + 2*4 = 18 bytes; vertices 4 * 16 = 64; face 1 + 16 + 1.
        let cut = &bytes[..body + 18 + 64 + 5];
        assert_eq!(
            err(cut),
            format!("byte {}: file ends inside face 0 (truncated?)", body + 82)
        );
        let cut = &bytes[..body + 18 + 40];
        assert_eq!(
            err(cut),
            format!(
                "byte {}: file ends inside vertex 2 (truncated?)",
                body + 18 + 32
            )
        );
        let cut = &bytes[..body + 5];
        assert!(err(cut).contains("inside camera 0"));
        let cut = &bytes[..bytes.len() - 1];
        assert!(err(cut).contains("inside edge 0"));
    }

    #[test]
    fn ascii_float_is_read_at_float_precision() {
        // 0.1 is not an f32: a `float` property gives the nearest f32, a
        // `double` property the nearest f64.
        let text = |ty: &str| {
            format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty {ty} x\nproperty {ty} y\n\
                 property {ty} z\nelement face 1\nproperty list uchar int vertex_indices\n\
                 end_header\n0.1 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
            )
        };
        let read = |ty: &str| crate::read_mesh_bytes(text(ty).as_bytes(), crate::MeshFormat::Ply);
        assert_eq!(read("float").unwrap().positions[0].x, f64::from(0.1f32));
        assert_eq!(read("float32").unwrap().positions[0].x, f64::from(0.1f32));
        assert_eq!(read("double").unwrap().positions[0].x, 0.1);
    }

    #[test]
    fn ascii_defects_name_the_line() {
        let s = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n";
        assert_eq!(
            err(s.as_bytes()),
            "line 11: vertex 1: expected 3 values, found 2"
        );
        let s = s.replace("1 0\n", "1 0 0\n").replace("3 0 1 2", "3 0 1 3");
        assert_eq!(
            err(s.as_bytes()),
            "line 13: face 0 refers to vertex 3, but the file has 3 vertices"
        );
        let s = s.replace("3 0 1 3\n", "");
        assert!(err(s.as_bytes()).contains("file ends after 0 of 1 face records"));
    }

    #[test]
    fn header_defects() {
        assert!(err(b"plx\n").contains("not a PLY file"));
        assert!(err(b"ply\nformat ascii 1.0\nelement vertex 1\n").contains("no 'end_header'"));
        assert!(err(b"ply\nformat foo 1.0\nend_header\n").contains("unknown PLY format"));
        assert!(err(b"ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n").contains("no 'format'"));
        assert!(err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n").contains("no 'z'"));
        assert!(
            err(b"ply\nformat ascii 1.0\nproperty float x\nend_header\n")
                .contains("before any element")
        );
        assert!(
            err(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n")
                .contains("unknown property type")
        );
        assert!(err(b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty int a\nend_header\n").contains("no 'vertex_indices'"));
    }

    #[test]
    fn huge_counts_do_not_allocate() {
        let s =
            b"ply\nformat binary_little_endian 1.0\nelement vertex 400000000\nproperty float x\n\
                  property float y\nproperty float z\nelement face 9223372036854775807\n\
                  property list uint uint vertex_indices\nend_header\n\0\0\0\0";
        assert!(err(s).contains("file ends inside vertex 0"));
        let s = b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n\
                  property float y\nproperty float z\nelement face 1\n\
                  property list uint uint vertex_indices\nend_header\n\xff\xff\xff\xff\0\0\0\0";
        assert!(err(s).contains("file ends inside face 0"));
    }
}
