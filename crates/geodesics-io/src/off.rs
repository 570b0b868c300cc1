//! OFF reader: `OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`... headers, counts on
//! the keyword line or the next, `#` comments anywhere, CRLF, polygons
//! fan-triangulated, per-vertex and per-face extras (colors, normals) ignored.

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::error::{ParseError, show};
use crate::text::{Lines, parse_count, parse_f64, parse_i64, tokens};

/// Whether `token` is an OFF header keyword: optional prefix letters, then `OFF`.
pub(crate) fn is_keyword(token: &[u8]) -> bool {
    token
        .strip_suffix(b"OFF")
        .is_some_and(|prefix| prefix.iter().all(|b| b"CNSTn4".contains(b)))
}

pub(crate) fn parse(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    let mut lines = Lines::new(data);
    let Some((first_line, first)) = lines.next_content(true) else {
        return Err(ParseError::whole(
            "no OFF header (the file has only comments or blank lines)",
        ));
    };

    // Header: keyword, then "V F [E]" on the same line or the next.
    let mut toks = tokens(first).peekable();
    let mut count_line = first_line;
    let mut counts: Vec<&[u8]> = Vec::with_capacity(3);
    match toks.peek() {
        Some(kw) if is_keyword(kw) => {
            if kw.contains(&b'4') || kw.contains(&b'n') {
                return Err(ParseError::line(
                    first_line,
                    format!(
                        "{} describes points of dimension other than 3, which is not supported",
                        show(kw)
                    ),
                ));
            }
            toks.next();
            counts.extend(toks);
            if counts
                .first()
                .is_some_and(|t| t.eq_ignore_ascii_case(b"BINARY"))
            {
                return Err(ParseError::line(
                    first_line,
                    "binary OFF is not supported (only ascii OFF)",
                ));
            }
            if counts.is_empty() {
                match lines.next_content(true) {
                    Some((n, line)) => {
                        count_line = n;
                        counts.extend(tokens(line));
                    }
                    None => {
                        return Err(ParseError::line(
                            first_line + 1,
                            "file ends before the vertex and face counts",
                        ));
                    }
                }
            }
        }
        Some(t) if parse_i64(t).is_some() => counts.extend(toks),
        Some(t) => {
            return Err(ParseError::line(
                first_line,
                format!("expected an OFF header keyword, found {}", show(t)),
            ));
        }
        None => return Err(ParseError::line(first_line, "expected an OFF header")),
    }
    if counts.len() < 2 {
        return Err(ParseError::line(
            count_line,
            format!(
                "expected vertex and face counts, found {} number(s)",
                counts.len()
            ),
        ));
    }
    let n_vertices = parse_count(counts[0]).ok_or_else(|| {
        ParseError::line(
            count_line,
            format!("invalid vertex count {}", show(counts[0])),
        )
    })?;
    let n_faces = parse_count(counts[1]).ok_or_else(|| {
        ParseError::line(
            count_line,
            format!("invalid face count {}", show(counts[1])),
        )
    })?;
    if n_vertices > u32::MAX as usize {
        return Err(ParseError::line(
            count_line,
            format!("{n_vertices} vertices is more than 32-bit indices can address"),
        ));
    }

    // Capacity capped by what the remaining bytes can hold ("0 0 0\n", "3 0 1 2\n").
    let remaining = data.len().saturating_sub(lines.offset());
    let mut positions = Vec::with_capacity(n_vertices.min(remaining / 6));
    for i in 0..n_vertices {
        let Some((n, line)) = lines.next_content(true) else {
            return Err(ParseError::line(
                lines.line_number() + 1,
                format!("file ends after {i} of {n_vertices} vertices (truncated?)"),
            ));
        };
        let mut xyz = [0.0; 3];
        let mut found = 0;
        for token in tokens(line).take(3) {
            xyz[found] = parse_f64(token).ok_or_else(|| {
                ParseError::line(n, format!("vertex {i}: invalid coordinate {}", show(token)))
            })?;
            found += 1;
        }
        if found < 3 {
            return Err(ParseError::line(
                n,
                format!("vertex {i}: expected 3 coordinates, found {found}"),
            ));
        }
        positions.push(DVec3::from_array(xyz));
    }

    let remaining = data.len().saturating_sub(lines.offset());
    let mut triangles = Vec::with_capacity(n_faces.min(remaining / 8));
    for f in 0..n_faces {
        let Some((n, line)) = lines.next_content(true) else {
            return Err(ParseError::line(
                lines.line_number() + 1,
                format!("file ends after {f} of {n_faces} faces (truncated?)"),
            ));
        };
        let mut toks = tokens(line);
        let first = toks.next().unwrap_or_default();
        let corners = parse_count(first).ok_or_else(|| {
            ParseError::line(n, format!("face {f}: invalid vertex count {}", show(first)))
        })?;
        if corners < 3 {
            return Err(ParseError::line(
                n,
                format!("face {f} has {corners} vertices (at least 3 needed)"),
            ));
        }
        let (mut v0, mut prev) = (0u32, 0u32);
        let mut found = 0;
        for token in toks.take(corners) {
            let index = parse_i64(token)
                .filter(|&k| k >= 0 && (k as u64) < n_vertices as u64)
                .ok_or_else(|| {
                    ParseError::line(
                        n,
                        format!(
                            "face {f} refers to vertex {}, but the file has {n_vertices} vertices",
                            String::from_utf8_lossy(token)
                        ),
                    )
                })? as u32;
            match found {
                0 => v0 = index,
                1 => {}
                _ => triangles.push([v0, prev, index]),
            }
            prev = index;
            found += 1;
        }
        if found < corners {
            return Err(ParseError::line(
                n,
                format!("face {f}: expected {corners} vertex indices, found {found}"),
            ));
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

    fn ok(s: &str) -> IndexedTriangles {
        parse(s.as_bytes()).unwrap()
    }

    fn err(s: &str) -> String {
        match parse(s.as_bytes()).unwrap_err() {
            ParseError::At(loc, m) => format!("{loc}: {m}"),
            ParseError::Whole(m) => m,
        }
    }

    const QUAD: &str = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";

    #[test]
    fn plain_quad_is_fan_triangulated() {
        let m = ok(QUAD);
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn header_variants() {
        let expected = ok(QUAD);
        for s in [
            "OFF 4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
            "OFF\r\n4 1 0\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n",
            "# leading comment\n\nOFF # keyword\n# counts next\n4 1\n\n0 0 0 # v0\n1 0 0\n# mid\n1 1 0\n0 1 0\n4 0 1 2 3 255 0 0\n",
            "COFF\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 1 2 3 4\n1 1 0 0 0 0 0\n0 1 0 0 0 0 0\n4 0 1 2 3\n",
            "NOFF\n4 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3 0.5 0.5 0.5 1\n",
            "4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
            "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3",
        ] {
            assert_eq!(ok(s), expected, "{s:?}");
        }
    }

    #[test]
    fn unreferenced_vertices_are_kept() {
        let m = ok("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n9 9 9\n3 0 1 2\n");
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.positions[3], DVec3::splat(9.0));
    }

    #[test]
    fn defects_name_the_line() {
        assert_eq!(
            err("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
            "line 4: vertex 1: expected 3 coordinates, found 2"
        );
        assert_eq!(
            err("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
            "line 6: face 0 refers to vertex 7, but the file has 3 vertices"
        );
        assert_eq!(
            err("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "line 7: file ends after 1 of 2 faces (truncated?)"
        );
        assert_eq!(
            err("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"),
            "line 6: face 0: expected 4 vertex indices, found 3"
        );
        assert_eq!(
            err("OFF\n3 1 0\n0 x 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "line 3: vertex 0: invalid coordinate \"x\""
        );
        assert!(err("OFF\n3\n").contains("expected vertex and face counts"));
        assert!(err("OFF BINARY\n").contains("binary OFF"));
        assert!(err("4OFF\n1 0 0\n0 0 0 0\n").contains("dimension"));
        assert!(err("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n").contains("at least 3"));
        assert!(err("# only a comment\n").contains("no OFF header"));
    }

    #[test]
    fn huge_counts_do_not_allocate() {
        assert!(err("OFF\n4000000000 4000000000 0\n0 0 0\n").contains("file ends after 1"));
        assert!(err("OFF\n99999999999 1 0\n").contains("32-bit"));
    }

    #[test]
    fn nan_parses_and_is_left_to_the_mesh_builder() {
        let m = ok("OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
        assert!(m.positions[0].x.is_nan());
    }
}
