//! Allocation-free helpers for the text formats: lines with numbers,
//! whitespace tokens, number parsing.

/// Lines of a byte buffer with their 1-based numbers; `\r\n` and `\n` both
/// end a line, the `\r` is dropped.
pub(crate) struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Lines {
            data,
            pos: 0,
            line: 0,
        }
    }

    /// Number of the line returned last (0 before the first).
    pub(crate) fn line_number(&self) -> usize {
        self.line
    }

    /// Byte offset where the next line starts.
    pub(crate) fn offset(&self) -> usize {
        self.pos
    }

    /// The next line that has content once a `#` comment (if `comments`) and
    /// surrounding whitespace are removed.
    pub(crate) fn next_content(&mut self, comments: bool) -> Option<(usize, &'a [u8])> {
        loop {
            let (n, line) = self.next()?;
            let line = if comments { strip_comment(line) } else { line };
            let line = line.trim_ascii();
            if !line.is_empty() {
                return Some((n, line));
            }
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        let rest = self.data.get(self.pos..)?;
        if rest.is_empty() {
            return None;
        }
        let (line, advance) = match rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&rest[..i], i + 1),
            None => (rest, rest.len()),
        };
        self.pos += advance;
        self.line += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((self.line, line))
    }
}

/// The part of a line before a `#`.
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Whitespace-separated tokens of a line.
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
}

/// Parses a decimal floating-point number (also `nan`, `inf`).
pub(crate) fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a decimal integer with optional sign, without overflow.
pub(crate) fn parse_i64(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.split_first()? {
        (b'-', rest) => (true, rest),
        (b'+', rest) => (false, rest),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_sub(i64::from(d))?;
    }
    if negative {
        Some(value)
    } else {
        value.checked_neg()
    }
}

/// Parses a non-negative count.
pub(crate) fn parse_count(token: &[u8]) -> Option<usize> {
    usize::try_from(parse_i64(token)?).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_cr_and_count() {
        let mut l = Lines::new(b"a\r\n\r\n  # c\nb c # d\nlast");
        assert_eq!(l.next_content(true), Some((1, &b"a"[..])));
        assert_eq!(l.next_content(true), Some((4, &b"b c"[..])));
        assert_eq!(l.next_content(true), Some((5, &b"last"[..])));
        assert_eq!(l.next_content(true), None);
    }

    #[test]
    fn integers() {
        assert_eq!(parse_i64(b"-12"), Some(-12));
        assert_eq!(parse_i64(b"+7"), Some(7));
        assert_eq!(parse_i64(b"-9223372036854775808"), Some(i64::MIN));
        assert_eq!(parse_i64(b"9223372036854775808"), None);
        assert_eq!(parse_i64(b"1.0"), None);
        assert_eq!(parse_i64(b"-"), None);
        assert_eq!(parse_count(b"-1"), None);
    }
}
