//! Byte-level helpers shared by the text readers (OBJ, OFF, ASCII PLY): lines with their
//! numbers, whitespace-separated tokens, numbers parsed without allocating.

/// Iterates over `(1-based line number, line without its end-of-line bytes)`. Lines end at
/// LF, CR LF or a lone CR (classic Mac OS writers), and a leading UTF-8 byte-order mark is
/// skipped (Windows writers put one before the first record).
pub struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Lines {
            rest: bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes),
            number: 0,
        }
    }

    /// The bytes not yet returned.
    pub fn rest(&self) -> &'a [u8] {
        self.rest
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        self.number += 1;
        let (line, rest) = match memchr::memchr2(b'\n', b'\r', self.rest) {
            Some(i) if self.rest[i] == b'\r' && self.rest.get(i + 1) == Some(&b'\n') => {
                (&self.rest[..i], &self.rest[i + 2..])
            }
            Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        Some((self.number, line))
    }
}

/// Whitespace-separated tokens of a line.
pub fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
}

/// `line` up to (not including) a `#` comment.
pub fn strip_comment(line: &[u8]) -> &[u8] {
    match memchr::memchr(b'#', line) {
        Some(i) => &line[..i],
        None => line,
    }
}

/// `line` up to (not including) a `#` that begins a word — at the start of the line or
/// after white space — the comment of OBJ's records (`v 1 2 3 # corner`, `f 1 2 3 # lid`).
/// A `#` inside a word (`g part#2`, `usemtl steel#4`) is part of the name, not a comment.
pub fn strip_word_comment(line: &[u8]) -> &[u8] {
    memchr::memchr_iter(b'#', line)
        .find(|&i| i == 0 || line[i - 1].is_ascii_whitespace())
        .map_or(line, |i| &line[..i])
}

/// A token shown in an error message (lossy for non-UTF-8 bytes, shortened when long).
pub fn show(token: &[u8]) -> String {
    let s = String::from_utf8_lossy(token);
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

/// Parses a decimal floating-point token; `None` when it is not one.
pub fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a (possibly signed) decimal integer token; `None` when it is not one.
pub fn parse_i64(token: &[u8]) -> Option<i64> {
    let (neg, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        b'+' => (false, &token[1..]),
        _ => (false, token),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i64::from(d - b'0');
    }
    Some(if neg { -v } else { v })
}

/// Writes an f64 in the shortest form that reads back to the same bits.
pub fn write_f64(out: &mut dyn std::io::Write, x: f64) -> std::io::Result<()> {
    let mut buf = ryu::Buffer::new();
    out.write_all(buf.format_finite(x).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_number_and_strip_cr() {
        let v: Vec<_> = Lines::new(b"a\r\nb\n\nc").collect();
        let bom_and_cr: Vec<_> = Lines::new(b"\xEF\xBB\xBFv 1\rv 2\r\rf").collect();
        assert_eq!(
            bom_and_cr,
            vec![
                (1, &b"v 1"[..]),
                (2, &b"v 2"[..]),
                (3, &b""[..]),
                (4, &b"f"[..])
            ]
        );
        assert_eq!(v, vec![(1, &b"a"[..]), (2, b"b"), (3, b""), (4, b"c")]);
    }

    #[test]
    fn a_comment_starts_at_a_word_not_inside_one() {
        assert_eq!(strip_word_comment(b"v 1 2 3 # corner"), b"v 1 2 3 ");
        assert_eq!(strip_word_comment(b"f 1 2 3\t#lid"), b"f 1 2 3\t");
        assert_eq!(strip_word_comment(b"# all comment"), b"");
        assert_eq!(strip_word_comment(b"g part#2 # left"), b"g part#2 ");
        assert_eq!(strip_word_comment(b"g part#2"), b"g part#2");
    }

    #[test]
    fn integers() {
        assert_eq!(parse_i64(b"-12"), Some(-12));
        assert_eq!(parse_i64(b"7"), Some(7));
        assert_eq!(parse_i64(b"7a"), None);
        assert_eq!(parse_i64(b"-"), None);
        assert_eq!(parse_i64(b"99999999999999999999"), None);
    }

    #[test]
    fn shortest_float_round_trips() {
        for x in [0.1, 1.0 / 3.0, -2.5e-300, 6.02e23, 0.0] {
            let mut out = Vec::new();
            write_f64(&mut out, x).unwrap();
            assert_eq!(parse_f64(&out).unwrap().to_bits(), x.to_bits());
        }
    }
}
