//! glTF 2.0 reader (`.gltf` JSON and `.glb` binary).
//!
//! The `gltf` crate parses and validates the JSON document; the GLB container
//! and all buffer/accessor reads are done here with checked bounds, because
//! the crate's own GLB header parsing and accessor iterators can panic on
//! malformed input (length underflow, slicing past a buffer's end).
//!
//! Every triangle primitive (`TRIANGLES`, and `TRIANGLE_STRIP` /
//! `TRIANGLE_FAN` converted per the glTF spec, dropping the degenerate
//! triangles strips use as restarts) of every mesh instance is appended:
//! positions in accessor order, transformed by the node's world matrix.
//! Instances come from the nodes of the default scene; if there is none, of
//! every scene; if there are no scenes, of every root node; if there are no
//! nodes, every mesh once, untransformed.

use std::borrow::Cow;
use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::buffer::Source;
use ::gltf::mesh::{Mode, Semantic};
use ::gltf::scene::Transform;
use ::gltf::{Accessor, Document, Node};
use geodesics_mesh::IndexedTriangles;
use glam::{DMat4, DQuat, DVec3};

use crate::error::{ParseError, one_line, show};

/// Accessors without a buffer view are all zeros (plus sparse values); a
/// count above this from a tiny file would be a memory bomb.
const MAX_VIEWLESS_COUNT: usize = 1 << 24;

pub(crate) fn parse(data: &[u8], base: Option<&Path>) -> Result<IndexedTriangles, ParseError> {
    let (json, blob) = if data.starts_with(b"glTF") {
        split_glb(data)?
    } else {
        let text = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
        if !text.trim_ascii_start().starts_with(b"{") {
            return Err(ParseError::byte(
                0,
                format!(
                    "not glTF: starts with {} instead of the 'glTF' magic or a JSON object",
                    show(&data[..data.len().min(4)])
                ),
            ));
        }
        (text, None)
    };
    let doc = &document(json)?;

    let instances = instances(doc)?;
    let buffers = load_buffers(doc, &instances, blob, base)?;

    let mut positions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (mesh_index, world) in instances {
        let Some(mesh) = doc.meshes().nth(mesh_index) else {
            continue;
        };
        for prim in mesh.primitives() {
            let mode = prim.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                continue;
            }
            let what = format!("mesh {mesh_index} primitive {}", prim.index());
            let Some(pos) = prim.get(&Semantic::Positions) else {
                return Err(ParseError::whole(format!(
                    "{what} has no POSITION attribute"
                )));
            };
            if pos.dimensions() != Dimensions::Vec3 {
                return Err(ParseError::whole(format!(
                    "{what}: POSITION accessor {} is {:?}, not VEC3",
                    pos.index(),
                    pos.dimensions()
                )));
            }
            let coords = read_accessor(&pos, &buffers, true)
                .map_err(|m| ParseError::whole(format!("{what}: {m}")))?;
            let n = coords.len() / 3;
            let base_index = positions.len();
            if base_index + n > u32::MAX as usize {
                return Err(ParseError::whole(
                    "more vertices than 32-bit indices can address",
                ));
            }
            let identity = world == DMat4::IDENTITY;
            positions.extend(coords.chunks_exact(3).map(|c| {
                let p = DVec3::new(c[0], c[1], c[2]);
                if identity {
                    p
                } else {
                    world.transform_point3(p)
                }
            }));

            let indices: Vec<u32> = match prim.indices() {
                Some(acc) => {
                    if acc.dimensions() != Dimensions::Scalar
                        || !matches!(
                            acc.data_type(),
                            DataType::U8 | DataType::U16 | DataType::U32
                        )
                    {
                        return Err(ParseError::whole(format!(
                            "{what}: index accessor {} is not an unsigned integer scalar",
                            acc.index()
                        )));
                    }
                    let values = read_accessor(&acc, &buffers, false)
                        .map_err(|m| ParseError::whole(format!("{what}: {m}")))?;
                    let mut out = Vec::with_capacity(values.len());
                    for v in values {
                        if !(v >= 0.0 && v < n as f64) {
                            return Err(ParseError::whole(format!(
                                "{what}: index {v} is beyond its {n} vertices"
                            )));
                        }
                        out.push(v as u32);
                    }
                    out
                }
                None => (0..n as u32).collect(),
            };
            let b = base_index as u32;
            let shift = |t: [u32; 3]| t.map(|i| i + b);
            match mode {
                Mode::Triangles => {
                    if !indices.len().is_multiple_of(3) {
                        return Err(ParseError::whole(format!(
                            "{what}: {} indices is not a multiple of 3",
                            indices.len()
                        )));
                    }
                    triangles.extend(indices.chunks_exact(3).map(|t| shift([t[0], t[1], t[2]])));
                }
                Mode::TriangleStrip => {
                    for (i, w) in indices.windows(3).enumerate() {
                        // p_i = (v_i, v_{i+1+i%2}, v_{i+2-i%2})
                        let t = if i % 2 == 0 {
                            [w[0], w[1], w[2]]
                        } else {
                            [w[0], w[2], w[1]]
                        };
                        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                            triangles.push(shift(t));
                        }
                    }
                }
                _ => {
                    // Fan: p_i = (v_{i+1}, v_{i+2}, v_0)
                    if let Some((&v0, rest)) = indices.split_first() {
                        for w in rest.windows(2) {
                            let t = [w[0], w[1], v0];
                            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                                triangles.push(shift(t));
                            }
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

/// Parses and validates the JSON document. Missing `min`/`max` of accessors
/// (required for POSITION by the spec, often left out by exporters, never
/// used here) is tolerated; every other validation error is refused, since
/// the `gltf` crate's accessors rely on validated indices.
fn document(json: &[u8]) -> Result<Document, ParseError> {
    use ::gltf::json::validation::{Error, Validate};
    let root: ::gltf::json::Root = ::gltf::json::deserialize::from_slice(json)
        .map_err(|e| ParseError::whole(format!("invalid glTF JSON: {e}")))?;
    // gltf-json 1.4.1's primitive validation indexes `accessors` with the
    // POSITION index unchecked (a panic on an out-of-range index): check first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    return Err(ParseError::whole(format!(
                        "invalid glTF: meshes[{m}].primitives[{p}].attributes[{:?}] refers to \
                         accessor {} but there are {}",
                        semantic.to_string(),
                        index.value(),
                        root.accessors.len()
                    )));
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(&root, ::gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let tolerated = matches!(error, Error::Missing)
            && (path.0.ends_with(".min") || path.0.ends_with(".max"));
        if !tolerated && errors.len() < 5 {
            errors.push(format!("{path}: {error}"));
        }
    });
    if !errors.is_empty() {
        return Err(ParseError::whole(format!(
            "invalid glTF: {}",
            errors.join("; ")
        )));
    }
    Ok(Document::from_json_without_validation(root))
}

/// Splits a GLB container into its JSON chunk and optional BIN chunk.
fn split_glb(data: &[u8]) -> Result<(&[u8], Option<&[u8]>), ParseError> {
    let u32_at = |o: usize| {
        data.get(o..o + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let (Some(version), Some(length)) = (u32_at(4), u32_at(8)) else {
        return Err(ParseError::byte(
            data.len(),
            "file ends inside the 12-byte GLB header (truncated?)",
        ));
    };
    if version != 2 {
        return Err(ParseError::byte(
            4,
            format!("GLB version {version} is not supported (only 2)"),
        ));
    }
    if length > data.len() {
        return Err(ParseError::byte(
            8,
            format!(
                "the GLB header says {length} bytes but the file has {} (truncated?)",
                data.len()
            ),
        ));
    }
    let data = &data[..length.max(12)];
    let mut pos = 12;
    let mut json = None;
    let mut bin = None;
    while pos < data.len() {
        let (Some(len), Some(kind)) = (u32_at(pos), data.get(pos + 4..pos + 8)) else {
            return Err(ParseError::byte(
                pos,
                "file ends inside a GLB chunk header (truncated?)",
            ));
        };
        let start = pos + 8;
        let Some(chunk) = start.checked_add(len).and_then(|end| data.get(start..end)) else {
            return Err(ParseError::byte(
                pos,
                format!(
                    "GLB chunk {} of {len} bytes runs past the end of the data (truncated?)",
                    show(kind)
                ),
            ));
        };
        match kind {
            b"JSON" if json.is_none() => json = Some(chunk),
            b"BIN\0" if bin.is_none() => bin = Some(chunk),
            _ => {}
        }
        pos = start + len.next_multiple_of(4);
    }
    match json {
        Some(j) => Ok((j, bin)),
        None => Err(ParseError::byte(12, "GLB has no JSON chunk")),
    }
}

/// Meshes to emit, with their world matrices.
fn instances(doc: &Document) -> Result<Vec<(usize, DMat4)>, ParseError> {
    let roots: Vec<Vec<Node>> = if let Some(scene) = doc.default_scene() {
        vec![scene.nodes().collect()]
    } else if doc.scenes().len() > 0 {
        doc.scenes().map(|s| s.nodes().collect()).collect()
    } else if doc.nodes().len() > 0 {
        let mut is_child = vec![false; doc.nodes().len()];
        for n in doc.nodes() {
            for c in n.children() {
                if let Some(slot) = is_child.get_mut(c.index()) {
                    *slot = true;
                }
            }
        }
        vec![
            doc.nodes()
                .filter(|n| !is_child.get(n.index()).copied().unwrap_or(true))
                .collect(),
        ]
    } else {
        return Ok(doc.meshes().map(|m| (m.index(), DMat4::IDENTITY)).collect());
    };
    let mut out = Vec::new();
    for scene_roots in roots {
        // glTF node hierarchies are strict trees; refusing a second visit
        // within one scene rules out cycles and exponential sharing.
        let mut visited = vec![false; doc.nodes().len()];
        // Depth-first in document order: push in reverse, pop from the end.
        let mut stack: Vec<(Node, DMat4)> = scene_roots
            .into_iter()
            .rev()
            .map(|n| (n, DMat4::IDENTITY))
            .collect();
        while let Some((node, parent)) = stack.pop() {
            match visited.get_mut(node.index()) {
                Some(seen) if !*seen => *seen = true,
                _ => {
                    return Err(ParseError::whole(format!(
                        "node {} is reached twice in one scene (the node hierarchy must be a tree)",
                        node.index()
                    )));
                }
            }
            let world = parent * local_matrix(&node);
            if let Some(mesh) = node.mesh() {
                out.push((mesh.index(), world));
            }
            let children: Vec<Node> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| (c, world)));
        }
    }
    Ok(out)
}

fn local_matrix(node: &Node) -> DMat4 {
    let w = |a: [f32; 3]| DVec3::from_array(a.map(f64::from));
    match node.transform() {
        Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let [x, y, z, q] = rotation.map(f64::from);
            DMat4::from_scale_rotation_translation(
                w(scale),
                DQuat::from_xyzw(x, y, z, q),
                w(translation),
            )
        }
    }
}

/// The data of every buffer the instances' primitives read (others `None`).
fn load_buffers<'a>(
    doc: &Document,
    instances: &[(usize, DMat4)],
    blob: Option<&'a [u8]>,
    base: Option<&Path>,
) -> Result<Vec<Option<Cow<'a, [u8]>>>, ParseError> {
    let mut needed = vec![false; doc.buffers().len()];
    let mut need = |acc: &Accessor| {
        let mut views = Vec::with_capacity(3);
        views.extend(acc.view());
        if let Some(s) = acc.sparse() {
            views.push(s.indices().view());
            views.push(s.values().view());
        }
        for v in views {
            if let Some(slot) = needed.get_mut(v.buffer().index()) {
                *slot = true;
            }
        }
    };
    for &(m, _) in instances {
        for prim in doc.meshes().nth(m).into_iter().flat_map(|m| m.primitives()) {
            prim.get(&Semantic::Positions).iter().for_each(&mut need);
            prim.indices().iter().for_each(&mut need);
        }
    }
    let mut out = Vec::with_capacity(needed.len());
    for (buffer, needed) in doc.buffers().zip(needed) {
        if !needed {
            out.push(None);
            continue;
        }
        let i = buffer.index();
        let data: Cow<'a, [u8]> = match buffer.source() {
            Source::Bin => Cow::Borrowed(blob.ok_or_else(|| {
                ParseError::whole(format!(
                    "buffer {i} refers to the GLB BIN chunk, which is missing"
                ))
            })?),
            Source::Uri(uri) => Cow::Owned(
                load_uri(uri, base).map_err(|m| ParseError::whole(format!("buffer {i}: {m}")))?,
            ),
        };
        if data.len() < buffer.length() {
            return Err(ParseError::whole(format!(
                "buffer {i} has {} bytes but declares {} (truncated?)",
                data.len(),
                buffer.length()
            )));
        }
        out.push(Some(data));
    }
    Ok(out)
}

fn load_uri(uri: &str, base: Option<&Path>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((_, payload)) = rest.split_once(";base64,") else {
            return Err("only base64 data URIs are supported".into());
        };
        return decode_base64(payload.as_bytes()).ok_or_else(|| "invalid base64 data URI".into());
    }
    if uri.contains("://") {
        return Err(format!("unsupported URI {}", show(uri.as_bytes())));
    }
    let Some(base) = base else {
        return Err(format!(
            "external buffer {} can only be loaded when reading from a file",
            show(uri.as_bytes())
        ));
    };
    let path = base.join(percent_decode(uri));
    std::fs::read(&path).map_err(|e| one_line(&format!("{}: {e}", path.display())))
}

fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%'
            && let (Some(h), Some(l)) = (
                b.get(i + 1).copied().and_then(hex),
                b.get(i + 2).copied().and_then(hex),
            )
        {
            out.push((h * 16 + l) as u8);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn decode_base64(s: &[u8]) -> Option<Vec<u8>> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        } as u32)
    };
    let s: &[u8] = {
        let mut end = s.len();
        while end > 0 && s[end - 1] == b'=' {
            end -= 1;
        }
        &s[..end]
    };
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    for chunk in s.chunks(4) {
        let mut acc = 0u32;
        for &c in chunk {
            acc = (acc << 6) | val(c)?;
        }
        match chunk.len() {
            4 => out.extend_from_slice(&acc.to_be_bytes()[1..]),
            3 => out.extend_from_slice(&(acc << 6).to_be_bytes()[1..3]),
            2 => out.push((acc >> 4) as u8),
            _ => return None,
        }
    }
    Some(out)
}

/// Reads an accessor into a flat `Vec<f64>` (`count × components`), with
/// every offset bounds-checked. `normalize`: apply the normalized-integer
/// mapping when the accessor says so.
fn read_accessor(
    acc: &Accessor,
    buffers: &[Option<Cow<[u8]>>],
    normalize: bool,
) -> Result<Vec<f64>, String> {
    let ty = acc.data_type();
    let comps = acc.dimensions().multiplicity();
    let csize = ty.size();
    let elem = csize * comps;
    let count = acc.count();
    let norm = normalize && acc.normalized();
    let name = format!("accessor {}", acc.index());

    let view_bytes = |view: &::gltf::buffer::View| -> Result<&[u8], String> {
        let data = buffers
            .get(view.buffer().index())
            .and_then(|b| b.as_deref())
            .ok_or_else(|| format!("buffer {} is not loaded", view.buffer().index()))?;
        view.offset()
            .checked_add(view.length())
            .and_then(|end| data.get(view.offset()..end))
            .ok_or_else(|| {
                format!(
                    "buffer view {} (bytes {}..+{}) runs past the end of buffer {} ({} bytes)",
                    view.index(),
                    view.offset(),
                    view.length(),
                    view.buffer().index(),
                    data.len()
                )
            })
    };

    let mut out: Vec<f64>;
    match acc.view() {
        Some(view) => {
            let bytes = view_bytes(&view)?;
            let stride = view.stride().unwrap_or(elem).max(1);
            let start = acc.offset();
            // Bytes from the accessor's start to the end of its last element.
            let span = match count.checked_sub(1) {
                None => Some(0),
                Some(last) => last.checked_mul(stride).and_then(|x| x.checked_add(elem)),
            };
            let Some(slice) = span.and_then(|span| bytes.get(start..start.checked_add(span)?))
            else {
                return Err(format!(
                    "{name} ({count} elements of {elem} bytes, stride {stride}, offset {start}) \
                     runs past the end of buffer view {} ({} bytes)",
                    view.index(),
                    bytes.len()
                ));
            };
            out = Vec::with_capacity(count * comps);
            for i in 0..count {
                let e = slice.get(i * stride..i * stride + elem).unwrap_or_default();
                for c in 0..comps {
                    out.push(component(ty, e.get(c * csize..).unwrap_or_default(), norm));
                }
            }
        }
        None => {
            if count > MAX_VIEWLESS_COUNT {
                return Err(format!(
                    "{name} has no buffer view and {count} elements (at most {MAX_VIEWLESS_COUNT} supported)"
                ));
            }
            out = vec![0.0; count * comps];
        }
    }

    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        let iv = sparse.indices();
        let vv = sparse.values();
        let isize = match iv.index_type() {
            ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let ib = view_bytes(&iv.view())?;
        let vb = view_bytes(&vv.view())?;
        let ib = n
            .checked_mul(isize.size())
            .and_then(|len| ib.get(iv.offset()..iv.offset().checked_add(len)?));
        let vb = n
            .checked_mul(elem)
            .and_then(|len| vb.get(vv.offset()..vv.offset().checked_add(len)?));
        let (Some(ib), Some(vb)) = (ib, vb) else {
            return Err(format!(
                "{name}: sparse data runs past the end of its buffer view"
            ));
        };
        for (k, (ie, ve)) in ib
            .chunks_exact(isize.size())
            .zip(vb.chunks_exact(elem))
            .enumerate()
        {
            let target = component(isize, ie, false);
            if !(target >= 0.0 && target < count as f64) {
                return Err(format!(
                    "{name}: sparse index {k} is {target}, beyond its {count} elements"
                ));
            }
            let t = target as usize;
            for c in 0..comps {
                if let Some(slot) = out.get_mut(t * comps + c) {
                    *slot = component(ty, ve.get(c * csize..).unwrap_or_default(), norm);
                }
            }
        }
    }
    Ok(out)
}

/// One little-endian component; missing bytes read as zero.
fn component(ty: DataType, b: &[u8], normalized: bool) -> f64 {
    let mut a = [0u8; 4];
    for (d, s) in a.iter_mut().zip(b) {
        *d = *s;
    }
    let (v, max) = match ty {
        DataType::I8 => (f64::from(a[0] as i8), 127.0),
        DataType::U8 => (f64::from(a[0]), 255.0),
        DataType::I16 => (f64::from(i16::from_le_bytes([a[0], a[1]])), 32767.0),
        DataType::U16 => (f64::from(u16::from_le_bytes([a[0], a[1]])), 65535.0),
        DataType::U32 => (f64::from(u32::from_le_bytes(a)), 4294967295.0),
        DataType::F32 => return f64::from(f32::from_le_bytes(a)),
    };
    if normalized { (v / max).max(-1.0) } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(data: &[u8]) -> String {
        match parse(data, None).unwrap_err() {
            ParseError::At(loc, m) => format!("{loc}: {m}"),
            ParseError::Whole(m) => m,
        }
    }

    fn b64(bytes: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for c in bytes.chunks(3) {
            let n = (u32::from(c[0]) << 16)
                | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
                | u32::from(*c.get(2).unwrap_or(&0));
            for k in 0..=c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            }
        }
        while !s.len().is_multiple_of(4) {
            s.push('=');
        }
        s
    }

    /// A unit quad (4 positions) plus the given index bytes in one buffer.
    fn quad_buffer(indices: &[u16]) -> Vec<u8> {
        let mut buf = Vec::new();
        for p in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]] {
            for c in p {
                buf.extend(c.to_le_bytes());
            }
        }
        for i in indices {
            buf.extend(i.to_le_bytes());
        }
        while buf.len() % 4 != 0 {
            buf.push(0);
        }
        buf
    }

    /// JSON with one mesh of one primitive, given mode and node/scene parts.
    fn json(
        buffer_uri: Option<&str>,
        buf_len: usize,
        n_idx: usize,
        mode: u32,
        rest: &str,
    ) -> String {
        let uri = buffer_uri
            .map(|u| format!(",\"uri\":\"{u}\""))
            .unwrap_or_default();
        format!(
            r#"{{"asset":{{"version":"2.0"}},
            "buffers":[{{"byteLength":{buf_len}{uri}}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},
                           {{"buffer":0,"byteOffset":48,"byteLength":{}}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"type":"VEC3","count":4}},
                         {{"bufferView":1,"componentType":5123,"type":"SCALAR","count":{n_idx}}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":{mode}}}]}}]
            {rest}}}"#,
            n_idx * 2
        )
    }

    fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
        let mut j = json.as_bytes().to_vec();
        while !j.len().is_multiple_of(4) {
            j.push(b' ');
        }
        let total = 12 + 8 + j.len() + 8 + bin.len();
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((j.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(j);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }

    #[test]
    fn glb_two_nodes_share_a_mesh_with_transforms() {
        let buf = quad_buffer(&[0, 1, 2, 0, 2, 3]);
        let j = json(
            None,
            buf.len(),
            6,
            4,
            r#","nodes":[{"mesh":0},{"children":[2],"translation":[10,0,0]},
                        {"mesh":0,"scale":[2,2,2]}],
               "scenes":[{"nodes":[0,1]}],"scene":0"#,
        );
        let m = parse(&glb(&j, &buf), None).unwrap();
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.positions[2], DVec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.positions[6], DVec3::new(12.0, 2.0, 0.0));
        assert_eq!(
            m.triangles,
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]
        );
    }

    #[test]
    fn gltf_json_with_data_uri_strip_and_fan() {
        let buf = quad_buffer(&[0, 1, 3, 2]);
        let uri = format!("data:application/octet-stream;base64,{}", b64(&buf));
        let strip = json(Some(&uri), buf.len(), 4, 5, "");
        let m = parse(strip.as_bytes(), None).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 3], [1, 2, 3]]);
        let buf = quad_buffer(&[0, 1, 2, 3]);
        let uri = format!("data:application/gltf-buffer;base64,{}", b64(&buf));
        let fan = json(Some(&uri), buf.len(), 4, 6, "");
        let m = parse(fan.as_bytes(), None).unwrap();
        assert_eq!(m.triangles, vec![[1, 2, 0], [2, 3, 0]]);
    }

    #[test]
    fn external_buffer_next_to_the_file() {
        let dir = std::env::temp_dir().join(format!("geodesics-io-gltf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let buf = quad_buffer(&[0, 1, 2, 0, 2, 3]);
        std::fs::write(dir.join("my mesh.bin"), &buf).unwrap();
        let j = json(Some("my%20mesh.bin"), buf.len(), 6, 4, "");
        std::fs::write(dir.join("quad.gltf"), j).unwrap();
        let m = crate::read_mesh(&dir.join("quad.gltf")).unwrap();
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        std::fs::remove_file(dir.join("my mesh.bin")).unwrap();
        let e = crate::read_mesh(&dir.join("quad.gltf"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("buffer 0:") && e.contains("my mesh.bin"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn empty_accessor_with_offset_past_the_view_is_refused_not_a_panic() {
        let buf = quad_buffer(&[0, 1, 2]);
        let uri = format!("data:;base64,{}", b64(&buf));
        let j = json(Some(&uri), buf.len(), 3, 4, "")
            .replace(r#""count":4}"#, r#""count":0,"byteOffset":4000}"#);
        assert!(err(j.as_bytes()).contains("runs past the end"));
    }

    #[test]
    fn no_default_scene_walks_every_scene_and_ignores_points() {
        let buf = quad_buffer(&[0, 1, 2, 0, 2, 3]);
        let j = json(
            None,
            buf.len(),
            6,
            4,
            r#","nodes":[{"mesh":0}],"scenes":[{"nodes":[0]},{"nodes":[0]}]"#,
        );
        let m = parse(&glb(&j, &buf), None).unwrap();
        assert_eq!(m.triangles.len(), 4);
        let points = json(None, buf.len(), 6, 0, "");
        let m = parse(&glb(&points, &buf), None).unwrap();
        assert!(m.triangles.is_empty());
    }

    #[test]
    fn defects() {
        let buf = quad_buffer(&[0, 1, 2, 0, 2, 3]);
        let good = glb(&json(None, buf.len(), 6, 4, ""), &buf);
        assert!(parse(&good, None).is_ok());
        let mut bad = good.clone();
        bad[0] = b'x';
        assert!(err(&bad).contains("not glTF"));
        assert!(err(&good[..good.len() - 10]).contains("truncated?"));
        assert!(err(&good[..7]).contains("GLB header"));
        let bad_index = glb(
            &json(None, buf.len(), 6, 4, ""),
            &quad_buffer(&[0, 1, 2, 0, 2, 9]),
        );
        assert!(err(&bad_index).contains("index 9 is beyond its 4 vertices"));
        let external = json(Some("mesh.bin"), buf.len(), 6, 4, "");
        assert!(err(external.as_bytes()).contains("only be loaded when reading from a file"));
        assert!(err(b"{\"asset\":").contains("invalid glTF JSON"));
        let cyclic = json(
            Some(&format!("data:;base64,{}", b64(&buf))),
            buf.len(),
            6,
            4,
            r#","nodes":[{"mesh":0,"children":[1]},{"children":[0]}],"scenes":[{"nodes":[0]}]"#,
        );
        assert!(err(cyclic.as_bytes()).contains("tree"));
        let mut short_header = good.clone();
        short_header[8..12].copy_from_slice(&3u32.to_le_bytes());
        assert!(parse(&short_header, None).is_err());
    }

    #[test]
    fn position_index_out_of_range_is_an_error_not_a_panic() {
        // Found by fuzzing: gltf-json's validation indexes this unchecked.
        let buf = quad_buffer(&[0, 1, 2, 0, 2, 3]);
        let j = json(None, buf.len(), 6, 4, "").replace(r#""POSITION":0"#, r#""POSITION":5"#);
        assert!(err(&glb(&j, &buf)).contains("refers to accessor 5 but there are 2"));
    }

    #[test]
    fn base64_round_trip() {
        for n in 0..10 {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 37 + 5) as u8).collect();
            assert_eq!(decode_base64(b64(&bytes).as_bytes()).unwrap(), bytes);
        }
    }
}
