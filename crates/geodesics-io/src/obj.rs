//! Wavefront OBJ reader (geometry only).
//!
//! Hand-written rather than `tobj`: tobj (4.0, `single_index = false`)
//! re-numbers the vertices of each model in order of first reference inside
//! that model's faces (`export_faces` keeps a per-model `index_map`), so it
//! drops unreferenced vertices, restarts numbering per object/group, and
//! reports errors without line numbers. Our results are per vertex in the
//! numbering of the file's `v` lines, so we need exactly that numbering.
//!
//! Supported: `v x y z [w] [r g b]`, `f`/`fo` with corners `i`, `i/t`,
//! `i//n`, `i/t/n` (texture and normal indices ignored), negative indices
//! (relative to the vertices defined so far), polygons fan-triangulated from
//! their first corner, `#` comments, `\` line continuation, CRLF. All other
//! statements (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, ...)
//! are ignored, so several objects and groups share one vertex array.

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::error::{ParseError, show};
use crate::text::{Lines, parse_f64, parse_i64, strip_comment, tokens};

pub(crate) fn parse(data: &[u8]) -> Result<IndexedTriangles, ParseError> {
    let mut positions: Vec<DVec3> = Vec::with_capacity((data.len() / 64).min(1 << 20));
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity((data.len() / 64).min(1 << 21));
    // Largest positive (forward-referencing) index and its line, checked at the end.
    let mut forward: Option<(usize, i64)> = None;
    let mut lines = Lines::new(data);
    // Buffer for joining `\`-continued lines (reused, only used when needed).
    let mut joined: Vec<u8> = Vec::new();

    while let Some((line_no, raw)) = lines.next() {
        let mut line = raw;
        if raw.trim_ascii_end().ends_with(b"\\") {
            joined.clear();
            let mut part = raw;
            loop {
                let trimmed = part.trim_ascii_end();
                match trimmed.strip_suffix(b"\\") {
                    Some(head) => {
                        joined.extend_from_slice(head);
                        joined.push(b' ');
                        match lines.next() {
                            Some((_, next)) => part = next,
                            None => break,
                        }
                    }
                    None => {
                        joined.extend_from_slice(part);
                        break;
                    }
                }
            }
            line = &joined;
        }
        let line = strip_comment(line);
        let mut toks = tokens(line);
        let Some(keyword) = toks.next() else { continue };
        match keyword {
            b"v" => {
                let mut xyz = [0.0; 3];
                let mut found = 0;
                for token in toks.take(3) {
                    xyz[found] = parse_f64(token).ok_or_else(|| {
                        ParseError::line(line_no, format!("invalid coordinate {}", show(token)))
                    })?;
                    found += 1;
                }
                if found < 3 {
                    return Err(ParseError::line(
                        line_no,
                        format!("expected 3 coordinates, found {found}"),
                    ));
                }
                if positions.len() >= u32::MAX as usize {
                    return Err(ParseError::line(
                        line_no,
                        "more vertices than 32-bit indices can address",
                    ));
                }
                positions.push(DVec3::from_array(xyz));
            }
            b"f" | b"fo" => {
                let defined = positions.len() as i64;
                let (mut v0, mut prev) = (0u32, 0u32);
                let mut corners = 0usize;
                for token in toks {
                    let first = match token.iter().position(|&b| b == b'/') {
                        Some(i) => &token[..i],
                        None => token,
                    };
                    let index = parse_i64(first).ok_or_else(|| {
                        ParseError::line(line_no, format!("invalid face index {}", show(token)))
                    })?;
                    let resolved = if index < 0 {
                        let r = defined + index;
                        if r < 0 {
                            return Err(ParseError::line(
                                line_no,
                                format!(
                                    "face index {index} is beyond the {defined} vertices defined so far"
                                ),
                            ));
                        }
                        r
                    } else if index == 0 {
                        return Err(ParseError::line(
                            line_no,
                            "face index 0 is invalid (OBJ indices start at 1)",
                        ));
                    } else {
                        if index > defined && forward.is_none_or(|(_, k)| index > k) {
                            forward = Some((line_no, index));
                        }
                        index - 1
                    };
                    let resolved = u32::try_from(resolved).map_err(|_| {
                        ParseError::line(line_no, format!("face index {index} is too large"))
                    })?;
                    match corners {
                        0 => v0 = resolved,
                        1 => {}
                        _ => triangles.push([v0, prev, resolved]),
                    }
                    prev = resolved;
                    corners += 1;
                }
                if corners < 3 {
                    return Err(ParseError::line(
                        line_no,
                        format!("face has {corners} vertices (at least 3 needed)"),
                    ));
                }
            }
            _ => {}
        }
    }
    if let Some((line_no, index)) = forward
        && index > positions.len() as i64
    {
        return Err(ParseError::line(
            line_no,
            format!(
                "face index {index} is beyond the {} vertices in the file",
                positions.len()
            ),
        ));
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

    #[test]
    fn corner_syntaxes_and_negative_indices() {
        let m = ok("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2//1 -2/1 4\n");
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn objects_share_file_numbering_and_unreferenced_are_kept() {
        let s = "# two objects\no a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 7 7 7\ng left\nf 1 2 3\n\
                 o b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nusemtl red\ns off\nf -3 -2 -1\nf 5 6 7\n";
        let m = ok(s);
        assert_eq!(m.positions.len(), 7);
        assert_eq!(m.positions[3], DVec3::splat(7.0));
        assert_eq!(m.triangles, vec![[0, 1, 2], [4, 5, 6], [4, 5, 6]]);
    }

    #[test]
    fn continuation_crlf_comments_and_extras() {
        let s = "v 0 0 0 1 0.5 0.5 0.5\r\nv 1 \\\r\n 0 0\r\nv 0 1 0 # comment\r\nf 1 2 \\\n3\r\n";
        let m = ok(s);
        assert_eq!(m.positions[1], DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn forward_references_within_the_file_are_allowed() {
        let m = ok("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn defects_name_the_line() {
        let v8 = "v 0 0 0\n".repeat(8);
        assert_eq!(
            err(&format!("{v8}f 1 2 -12\n")),
            "line 9: face index -12 is beyond the 8 vertices defined so far"
        );
        assert_eq!(
            err("v 0 0 0\nv 1 0\n"),
            "line 2: expected 3 coordinates, found 2"
        );
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n\n"),
            "line 4: face index 9 is beyond the 3 vertices in the file"
        );
        assert!(err("v 0 0 0\nf 0 1 1\n").contains("index 0"));
        assert!(err("v 0 0 0\nf 1 1\n").contains("at least 3"));
        assert!(err("v 0 0 0\nf a b c\n").contains("invalid face index"));
        assert!(err("v 0 0 z\n").contains("invalid coordinate \"z\""));
    }

    #[test]
    fn empty_and_comment_only_files_give_no_triangles() {
        assert_eq!(ok("# nothing\n"), IndexedTriangles::default());
        assert_eq!(ok("\\"), IndexedTriangles::default());
    }
}
