//! STL reader, ascii and binary. STL stores three corners per triangle; they
//! are welded by exactly equal coordinates (`-0.0 == 0.0`) and numbered in
//! order of first appearance.

use std::collections::HashMap;

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::error::{ParseError, show};
use crate::text::{Lines, parse_f64, tokens};

/// Whether `data` (the whole file) is binary STL: exactly `84 + 50 n` bytes
/// for the triangle count `n` in bytes 80..84. Binary files may start with
/// `solid` too, so the size decides.
pub(crate) fn is_binary(data: &[u8]) -> bool {
    match data.get(80..84) {
        Some(b) => {
            let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64;
            data.len() as u64 == 84 + 50 * n
        }
        None => false,
    }
}

/// Whether the data starts like ascii STL.
pub(crate) fn looks_ascii(head: &[u8]) -> bool {
    let t = head.trim_ascii_start();
    t.starts_with(b"solid") && t.get(5).is_none_or(|b| b.is_ascii_whitespace())
}

pub(crate) fn parse(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    if is_binary(data) || !looks_ascii(data) {
        parse_binary(data)
    } else {
        parse_ascii(data)
    }
}

/// Welds corners by exact position.
struct Welder {
    map: HashMap<[u64; 3], u32>,
    positions: Vec<DVec3>,
}

impl Welder {
    fn with_capacity(corners: usize) -> Self {
        // Closed meshes have about half as many vertices as triangles.
        let n = corners / 6;
        Welder {
            map: HashMap::with_capacity(n),
            positions: Vec::with_capacity(n),
        }
    }

    #[inline]
    fn index(&mut self, p: [f64; 3]) -> Result<u32, ()> {
        // +0.0 turns -0.0 into +0.0; NaNs keep their bits (and are refused later).
        let key = p.map(|c| (c + 0.0).to_bits());
        let next = self.positions.len();
        match self.map.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => Ok(*e.get()),
            std::collections::hash_map::Entry::Vacant(e) => {
                let i = u32::try_from(next).map_err(|_| ())?;
                e.insert(i);
                self.positions.push(DVec3::from_array(p));
                Ok(i)
            }
        }
    }
}

fn parse_binary(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    let Some(count) = data.get(80..84) else {
        return Err(ParseError::byte(
            data.len(),
            format!(
                "file ends inside the 84-byte binary STL header ({} bytes; not ascii STL either: it does not start with 'solid')",
                data.len()
            ),
        ));
    };
    let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    let body = &data[84..];
    let available = body.len() / 50;
    if available < n {
        return Err(ParseError::byte(
            84 + available * 50,
            format!("file ends inside triangle {available} of {n} (truncated?)"),
        ));
    }
    let mut welder = Welder::with_capacity(3 * n);
    let mut triangles = Vec::with_capacity(n);
    for (t, rec) in body.chunks_exact(50).take(n).enumerate() {
        let mut tri = [0u32; 3];
        for (k, slot) in tri.iter_mut().enumerate() {
            let mut p = [0.0f64; 3];
            for (c, out) in p.iter_mut().enumerate() {
                let o = 12 + 12 * k + 4 * c;
                let b = [rec[o], rec[o + 1], rec[o + 2], rec[o + 3]];
                *out = f64::from(f32::from_le_bytes(b));
            }
            *slot = welder.index(p).map_err(|_| {
                ParseError::byte(84 + 50 * t, "more vertices than 32-bit indices can address")
            })?;
        }
        triangles.push(tri);
    }
    Ok(IndexedTriangles {
        positions: welder.positions,
        triangles,
    })
}

fn parse_ascii(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    let mut welder = Welder::with_capacity(data.len() / 40);
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(data.len() / 250);
    let lines = Lines::new(data);
    // Corners of the current facet (polygons are fan-triangulated).
    let mut v0 = 0u32;
    let mut prev = 0u32;
    let mut corners = 0usize;
    let mut in_facet = false;
    let mut facet_line = 0;
    let mut facets = 0usize;
    for (n, line) in lines {
        let mut toks = tokens(line);
        let Some(keyword) = toks.next() else { continue };
        match keyword {
            b"solid" | b"endsolid" | b"outer" | b"endloop" => {}
            b"facet" => {
                if in_facet {
                    return Err(ParseError::line(
                        n,
                        "'facet' inside a facet (missing 'endfacet')",
                    ));
                }
                in_facet = true;
                facet_line = n;
                corners = 0;
            }
            b"endfacet" => {
                if !in_facet {
                    return Err(ParseError::line(n, "'endfacet' without 'facet'"));
                }
                if corners < 3 {
                    return Err(ParseError::line(
                        n,
                        format!("facet {facets} has {corners} vertices (at least 3 needed)"),
                    ));
                }
                in_facet = false;
                facets += 1;
            }
            b"vertex" => {
                if !in_facet {
                    return Err(ParseError::line(n, "'vertex' outside a facet"));
                }
                let mut p = [0.0; 3];
                let mut found = 0;
                for token in toks.take(3) {
                    p[found] = parse_f64(token).ok_or_else(|| {
                        ParseError::line(n, format!("invalid coordinate {}", show(token)))
                    })?;
                    found += 1;
                }
                if found < 3 {
                    return Err(ParseError::line(
                        n,
                        format!("expected 3 coordinates, found {found}"),
                    ));
                }
                let v = welder.index(p).map_err(|_| {
                    ParseError::line(n, "more vertices than 32-bit indices can address")
                })?;
                match corners {
                    0 => v0 = v,
                    1 => {}
                    _ => triangles.push([v0, prev, v]),
                }
                prev = v;
                corners += 1;
            }
            other => {
                return Err(ParseError::line(
                    n,
                    format!("unexpected {} in ascii STL", show(other)),
                ));
            }
        }
    }
    if in_facet {
        return Err(ParseError::line(
            facet_line,
            format!("file ends inside facet {facets} (truncated?)"),
        ));
    }
    Ok(IndexedTriangles {
        positions: welder.positions,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(data: &[u8]) -> String {
        match parse(data).unwrap_err() {
            ParseError::At(loc, m) => format!("{loc}: {m}"),
            ParseError::Whole(m) => m,
        }
    }

    /// Two triangles sharing an edge; the shared corners use -0.0 once.
    fn binary(header: &[u8; 80]) -> Vec<u8> {
        let tris: [[[f32; 3]; 3]; 2] = [
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            [[-0.0, 0.0, 0.0], [1.0, 1.0, -0.0], [0.0, 1.0, 0.0]],
        ];
        let mut out = header.to_vec();
        out.extend(2u32.to_le_bytes());
        for t in tris {
            out.extend([0u8; 12]);
            for p in t {
                for c in p {
                    out.extend(c.to_le_bytes());
                }
            }
            out.extend([0u8; 2]);
        }
        out
    }

    fn expected() -> IndexedTriangles {
        IndexedTriangles {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    #[test]
    fn binary_welds_in_order_of_first_appearance() {
        assert_eq!(parse(&binary(&[0; 80])).unwrap(), expected());
    }

    #[test]
    fn binary_starting_with_solid_is_recognised_by_size() {
        let mut header = [b' '; 80];
        header[..11].copy_from_slice(b"solid thing");
        let data = binary(&header);
        assert!(is_binary(&data));
        assert_eq!(parse(&data).unwrap(), expected());
    }

    #[test]
    fn ascii_with_several_solids_and_crlf() {
        let s = "solid a\r\n facet normal 0 0 1\r\n  outer loop\r\n   vertex 0 0 0\r\n   vertex 1 0 0\r\n\
                 vertex 1 1 0\r\n  endloop\r\n endfacet\r\nendsolid a\r\n\
                 solid b\r\nfacet normal 0 0 1\r\nouter loop\r\nvertex -0 0 0\r\nvertex 1 1 -0\r\n\
                 vertex 0 1 0\r\nendloop\r\nendfacet\r\nendsolid\r\n";
        assert_eq!(parse(s.as_bytes()).unwrap(), expected());
    }

    #[test]
    fn ascii_polygon_facet_is_fan_triangulated() {
        let s = "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n\
                 vertex 0 1 0\nendloop\nendfacet\nendsolid\n";
        assert_eq!(parse(s.as_bytes()).unwrap(), expected());
    }

    #[test]
    fn defects() {
        let data = binary(&[0; 80]);
        assert_eq!(
            err(&data[..84 + 70]),
            "byte 134: file ends inside triangle 1 of 2 (truncated?)"
        );
        assert!(err(b"\x01\x02").contains("84-byte binary STL header"));
        assert_eq!(
            err(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n"),
            "line 4: expected 3 coordinates, found 2"
        );
        assert_eq!(
            err(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
            "line 2: file ends inside facet 0 (truncated?)"
        );
        assert!(err(b"solid x\nhello\n").contains("unexpected \"hello\""));
    }
}
