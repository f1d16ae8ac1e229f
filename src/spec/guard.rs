//! A lexical pass that runs before the KDL parser and keeps it within a bounded stack and time.
//!
//! The `kdl` crate's parser recurses once per nesting level of children blocks, per token of a
//! block comment, per slashdash in a chain (`/- /- /- node`) and per stray `}` it recovers from,
//! and long slashdash chains take it time that grows much faster than their length, so a small
//! hostile file could overflow the stack or hang. This pass finds deep nesting, long slashdash
//! chains and unmatched `}` itself, and blanks out the bodies of comments (which mean nothing to a
//! project). It knows KDL v2's lexical rules (every line end and space it allows, strings and
//! their escapes) well enough to tell strings and comments apart from structure exactly as the
//! parser does; a string whose end the two could disagree on (unclosed, broken by a line end, with
//! a bad escape, a forbidden code point, or glued to a word) is refused here, with its own
//! diagnostic, before the parser sees it.

use miette::SourceSpan;

/// Children blocks nested deeper than this are refused; the grammar needs three levels.
pub const MAX_NESTING: usize = 32;
/// Slashdashes in a row longer than this are refused: the parser takes time quadratic in the
/// length of the file, with a large factor, from two slashdashes in a row before a bad value on.
pub const MAX_SLASHDASH_CHAIN: usize = 1;

/// Why the text was refused before parsing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// A `{` opening a block deeper than [`MAX_NESTING`].
    TooDeep(SourceSpan),
    /// A `/-` continuing a chain longer than [`MAX_SLASHDASH_CHAIN`].
    LongSlashdashChain(SourceSpan),
    /// A `}` that closes no block.
    UnmatchedClose(SourceSpan),
    /// A `/*` comment that is never closed (the span is its `/*`).
    UnclosedComment(SourceSpan),
    /// A string that is not valid KDL, at the span of the fault.
    BadString(SourceSpan, StringFault),
}

/// What is wrong with a string the guard refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StringFault {
    /// The text ends before the string is closed.
    Unclosed,
    /// A line ends inside a single-line string.
    LineEnd,
    /// A code point KDL forbids in text (a control character, a direction mark, a BOM).
    Forbidden(char),
    /// A `\` not followed by one of KDL's escapes.
    BadEscape,
    /// `"""` (or `#"""`) not followed by a line end.
    MultiLineOpening,
    /// A line of a multi-line string that does not start with the closing line's indentation,
    /// or a closing line with more than spaces before its `"""`.
    Indentation,
    /// A quote right after a word, with no space between (`a"b"`).
    Glued,
}

/// Checks `source` and returns the text to give the parser: the same text, byte for byte, except
/// that the bodies of comments are replaced by spaces (line ends kept), so every offset the
/// parser reports still points into `source`.
pub fn prepare(source: &str) -> Result<String, Refusal> {
    let text = source.as_bytes();
    let mut bytes = text.to_vec();
    let mut depth = 0usize;
    let mut chain = 0usize;
    // Where the last block comment ended: a string may follow one directly.
    let mut comment_end = usize::MAX;
    let mut i = 0;
    while i < text.len() {
        if let Some(length) = newline_len(text, i).or_else(|| space_len(text, i)) {
            i += length;
            continue;
        }
        match (text[i], text.get(i + 1).copied()) {
            (b'"', _) => {
                if glued(source, i, comment_end) {
                    return Err(Refusal::BadString((i, 1).into(), StringFault::Glued));
                }
                i = skip_string(source, i)?;
                chain = 0;
            }
            (b'#', _) => {
                let hashes = text[i..].iter().take_while(|&&b| b == b'#').count();
                if text.get(i + hashes) == Some(&b'"') {
                    if glued(source, i, comment_end) {
                        return Err(Refusal::BadString((i, 1).into(), StringFault::Glued));
                    }
                    i = skip_raw_string(source, i, hashes)?;
                } else {
                    i += hashes;
                }
                chain = 0;
            }
            (b'/', Some(b'/')) => {
                i = blank_line_comment(text, &mut bytes, i);
            }
            (b'/', Some(b'*')) => {
                i = blank_block_comment(text, &mut bytes, i)?;
                comment_end = i;
            }
            (b'/', Some(b'-')) => {
                chain += 1;
                if chain > MAX_SLASHDASH_CHAIN {
                    return Err(Refusal::LongSlashdashChain((i, 2).into()));
                }
                i += 2;
            }
            (b'{', _) => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(Refusal::TooDeep((i, 1).into()));
                }
                chain = 0;
                i += 1;
            }
            (b'}', _) => {
                if depth == 0 {
                    return Err(Refusal::UnmatchedClose((i, 1).into()));
                }
                depth -= 1;
                chain = 0;
                i += 1;
            }
            (byte, _) => {
                // A `\` continues the line (an escline), which a slashdash may span.
                if byte != b'\\' {
                    chain = 0;
                }
                i += 1;
            }
        }
    }
    // Spaces were written only over whole characters (comment bodies lie between ASCII
    // delimiters and line ends), so the text is still UTF-8 and nothing is replaced.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The byte length of the KDL line end at `i` (CRLF, CR, LF, NEL, VT, FF, LS, PS), if any.
fn newline_len(text: &[u8], i: usize) -> Option<usize> {
    match text[i..] {
        [b'\r', b'\n', ..] => Some(2),
        [b'\r' | b'\n' | 0x0B | 0x0C, ..] => Some(1),
        [0xC2, 0x85, ..] => Some(2),
        [0xE2, 0x80, 0xA8 | 0xA9, ..] => Some(3),
        _ => None,
    }
}

/// The byte length of the KDL space at `i` (tab, space and the Unicode spaces), if any.
fn space_len(text: &[u8], i: usize) -> Option<usize> {
    match text[i..] {
        [b'\t' | b' ', ..] => Some(1),
        [0xC2, 0xA0, ..] => Some(2),
        [0xE1, 0x9A, 0x80, ..] => Some(3),
        [0xE2, 0x80, 0x80..=0x8A | 0xAF, ..] => Some(3),
        [0xE2, 0x81, 0x9F, ..] => Some(3),
        [0xE3, 0x80, 0x80, ..] => Some(3),
        _ => None,
    }
}

/// Whether KDL forbids `c` in text.
fn forbidden(c: char) -> bool {
    matches!(c,
        '\u{0000}'..='\u{0008}'
        | '\u{000E}'..='\u{001F}'
        | '\u{007F}'
        | '\u{200E}'..='\u{200F}'
        | '\u{202A}'..='\u{202E}'
        | '\u{2066}'..='\u{2069}'
        | '\u{FEFF}'
    )
}

/// Whether the quote or raw string opening at `i` directly follows a word (no space, line end,
/// `=`, parenthesis, brace, `;` or comment between them).
fn glued(source: &str, i: usize, comment_end: usize) -> bool {
    if i == comment_end {
        return false;
    }
    match source[..i].chars().next_back() {
        None | Some('=' | '(' | ')' | '{' | '}' | ';' | '\u{FEFF}') => false,
        Some(c) => {
            let mut buffer = [0u8; 4];
            let bytes = c.encode_utf8(&mut buffer).as_bytes();
            newline_len(bytes, 0)
                .or_else(|| space_len(bytes, 0))
                .is_none()
        }
    }
}

/// The index after the quoted string (single- or multi-line, with escapes) opening at `start`.
fn skip_string(source: &str, start: usize) -> Result<usize, Refusal> {
    let text = source.as_bytes();
    if text[start..].starts_with(b"\"\"\"") {
        let body = start + 3;
        let Some(line_end) = newline_len(text, body) else {
            return Err(fault(start, 3, StringFault::MultiLineOpening));
        };
        let mut i = body + line_end;
        while i < text.len() {
            if text[i..].starts_with(b"\"\"\"") {
                check_indentation(source, body + line_end, i, start)?;
                return Ok(i + 3);
            }
            i = string_char(source, i, true)?;
        }
        return Err(fault(start, 3, StringFault::Unclosed));
    }
    let mut i = start + 1;
    while i < text.len() {
        if text[i] == b'"' {
            return Ok(i + 1);
        }
        i = string_char(source, i, false)?;
    }
    Err(fault(start, 1, StringFault::Unclosed))
}

/// The index after the character (or escape) at `i` of a quoted string's body.
fn string_char(source: &str, i: usize, multiline: bool) -> Result<usize, Refusal> {
    let text = source.as_bytes();
    if text[i] == b'\\' {
        return escape(source, i);
    }
    if let Some(length) = newline_len(text, i) {
        return if multiline {
            Ok(i + length)
        } else {
            Err(fault(i, length, StringFault::LineEnd))
        };
    }
    let c = char_at(source, i);
    if forbidden(c) {
        return Err(fault(i, c.len_utf8(), StringFault::Forbidden(c)));
    }
    Ok(i + c.len_utf8())
}

/// The index after the escape starting with the `\` at `i`.
fn escape(source: &str, i: usize) -> Result<usize, Refusal> {
    let text = source.as_bytes();
    let bad = |length: usize| fault(i, length, StringFault::BadEscape);
    match text.get(i + 1) {
        Some(b'\\' | b'"' | b'b' | b'f' | b'n' | b'r' | b't' | b's') => Ok(i + 2),
        Some(b'u') => {
            if text.get(i + 2) != Some(&b'{') {
                return Err(bad(2));
            }
            let digits = text[i + 3..]
                .iter()
                .take_while(|b| b.is_ascii_hexdigit())
                .count();
            let close = i + 3 + digits;
            let value = std::str::from_utf8(&text[i + 3..close])
                .ok()
                .and_then(|hex| u32::from_str_radix(hex, 16).ok())
                .and_then(char::from_u32);
            match (digits, text.get(close), value) {
                (1..=6, Some(b'}'), Some(_)) => Ok(close + 1),
                _ => Err(bad(close - i)),
            }
        }
        _ => {
            // A whitespace escape: the `\` and every space and line end after it.
            let mut j = i + 1;
            while j < text.len() {
                match newline_len(text, j).or_else(|| space_len(text, j)) {
                    Some(length) => j += length,
                    None => break,
                }
            }
            if j == i + 1 {
                Err(bad(1))
            } else {
                Ok(j)
            }
        }
    }
}

/// The index after the raw string (`#"..."#`, `##"""..."""##`) whose `hashes` hashes start at
/// `start`.
fn skip_raw_string(source: &str, start: usize, hashes: usize) -> Result<usize, Refusal> {
    let text = source.as_bytes();
    let open = start + hashes;
    let multiline = text[open..].starts_with(b"\"\"\"");
    let quotes = if multiline { 3 } else { 1 };
    let body = open + quotes;
    let mut i = body;
    if multiline {
        match newline_len(text, body) {
            Some(length) => i += length,
            None => return Err(fault(start, hashes + 3, StringFault::MultiLineOpening)),
        }
    }
    let first_line = i;
    while i < text.len() {
        let closes = text[i..].starts_with(&b"\"\"\""[..quotes])
            && text[i + quotes..]
                .iter()
                .take_while(|&&b| b == b'#')
                .count()
                >= hashes;
        if closes {
            if multiline {
                check_indentation(source, first_line, i, start)?;
            }
            return Ok(i + quotes + hashes);
        }
        if let Some(length) = newline_len(text, i) {
            if !multiline {
                return Err(fault(i, length, StringFault::LineEnd));
            }
            i += length;
            continue;
        }
        let c = char_at(source, i);
        if forbidden(c) {
            return Err(fault(i, c.len_utf8(), StringFault::Forbidden(c)));
        }
        i += c.len_utf8();
    }
    Err(fault(start, hashes + quotes, StringFault::Unclosed))
}

/// Checks a multi-line string's indentation: the closing `"""` at `close` has only spaces before
/// it on its line, and every line from `first` on starts with those spaces or holds only spaces.
fn check_indentation(
    source: &str,
    first: usize,
    close: usize,
    start: usize,
) -> Result<(), Refusal> {
    let text = source.as_bytes();
    // Line ends never start inside a multi-byte character, so stepping by bytes finds them all.
    let mut lines = Vec::new();
    let (mut j, mut line) = (first, first);
    while j < close {
        match newline_len(text, j) {
            Some(length) => {
                lines.push(line..j);
                j += length;
                line = j;
            }
            None => j += 1,
        }
    }
    let prefix = &source[line..close];
    let spaces_only = |part: &str| {
        let bytes = part.as_bytes();
        let mut k = 0;
        while k < bytes.len() {
            match space_len(bytes, k) {
                Some(length) => k += length,
                None => return false,
            }
        }
        true
    };
    if !spaces_only(prefix) {
        return Err(fault(start, close + 3 - start, StringFault::Indentation));
    }
    match lines.into_iter().find(|body| {
        !source[body.clone()].starts_with(prefix) && !spaces_only(&source[body.clone()])
    }) {
        Some(body) => Err(fault(body.start, body.len(), StringFault::Indentation)),
        None => Ok(()),
    }
}

/// The character starting at byte `i`.
fn char_at(source: &str, i: usize) -> char {
    source[i..].chars().next().unwrap_or('\u{FFFD}')
}

/// The refusal of a string at `offset`, `length` bytes long.
fn fault(offset: usize, length: usize, fault: StringFault) -> Refusal {
    Refusal::BadString((offset, length).into(), fault)
}

/// Blanks the body of the line comment at `start` and returns the index of the line end ending it
/// (or the end of the text).
fn blank_line_comment(text: &[u8], bytes: &mut [u8], start: usize) -> usize {
    let end = (start + 2..text.len())
        .find(|&i| newline_len(text, i).is_some())
        .unwrap_or(text.len());
    bytes[start + 2..end].fill(b' ');
    end
}

/// Blanks the body of the (possibly nested) block comment opening at `start` and returns the
/// index after its closing `*/`, or refuses an unclosed one.
fn blank_block_comment(text: &[u8], bytes: &mut [u8], start: usize) -> Result<usize, Refusal> {
    let mut level = 0usize;
    let mut i = start;
    while i < text.len() {
        if text[i..].starts_with(b"/*") {
            level += 1;
            i += 2;
        } else if text[i..].starts_with(b"*/") {
            level -= 1;
            i += 2;
            if level == 0 {
                // Keep the outermost delimiters; blank everything between them.
                blank(&mut bytes[start + 2..i - 2]);
                return Ok(i);
            }
        } else {
            i += 1;
        }
    }
    Err(Refusal::UnclosedComment((start, 2).into()))
}

/// Replaces every byte but `\n` and `\r` with a space.
fn blank(bytes: &mut [u8]) {
    for byte in bytes {
        if *byte != b'\n' && *byte != b'\r' {
            *byte = b' ';
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_ordinary_text_unchanged() {
        let text = "a \"{{{\" #\"}}\"# 1 { b /-c; d }\n";
        assert_eq!(prepare(text).unwrap(), text);
        let multiline = "a \"\"\"\n  x {\n\n  \"\"\" #\"\"\"\n y\n \"\"\"#\n";
        assert_eq!(prepare(multiline).unwrap(), multiline);
    }

    #[test]
    fn blanks_comment_bodies_in_place() {
        let text = "a /* x /* é */ } */ 1";
        let prepared = prepare(text).unwrap();
        assert_eq!(prepared.len(), text.len());
        let body = text.len() - "a /**/ 1".len();
        assert_eq!(prepared, format!("a /*{}*/ 1", " ".repeat(body)));
        assert_eq!(prepare("a // {{ é\nb").unwrap(), "a //      \nb");
    }

    #[test]
    fn refuses_deep_nesting_at_the_first_brace_too_many() {
        let text = "a{".repeat(MAX_NESTING + 1);
        let offset = 2 * MAX_NESTING + 1;
        assert_eq!(prepare(&text), Err(Refusal::TooDeep((offset, 1).into())));
    }

    #[test]
    fn every_kdl_line_end_ends_a_line_comment() {
        for end in [
            "\n", "\r", "\u{85}", "\u{0B}", "\u{0C}", "\u{2028}", "\u{2029}",
        ] {
            let text = format!("//{end}{}", "a{".repeat(MAX_NESTING + 1));
            assert!(
                matches!(prepare(&text), Err(Refusal::TooDeep(_))),
                "{end:?}"
            );
        }
    }

    #[test]
    fn refuses_stray_close_and_long_chains() {
        assert_eq!(
            prepare("a {}\n}"),
            Err(Refusal::UnmatchedClose((5, 1).into()))
        );
        for space in [" ", "\u{A0}", "\u{3000}", "\n", "\u{2028}", " \\\n "] {
            let chain = format!("/-{space}").repeat(MAX_SLASHDASH_CHAIN + 1) + "a";
            assert!(
                matches!(prepare(&chain), Err(Refusal::LongSlashdashChain(_))),
                "{space:?}"
            );
        }
        assert!(prepare(&"a /-1 ".repeat(100)).is_ok());
    }

    #[test]
    fn raw_strings_need_their_hashes() {
        let text = "a ##\"x\"# }\"## { }";
        assert_eq!(prepare(text).unwrap(), text);
    }

    #[test]
    fn refuses_strings_whose_end_is_unclear() {
        let cases = [
            ("a \"x", StringFault::Unclosed, 2),
            ("a \"x\n{", StringFault::LineEnd, 4),
            ("a \"x\u{2028}{", StringFault::LineEnd, 4),
            ("a #\"x\n\"#", StringFault::LineEnd, 5),
            ("a \"\\q\"", StringFault::BadEscape, 3),
            ("a \"\\u{110000}\"", StringFault::BadEscape, 3),
            ("a \"\u{200E}\"", StringFault::Forbidden('\u{200E}'), 3),
            ("a\"x\"", StringFault::Glued, 1),
            ("a \"\"\"x\"\"\"", StringFault::MultiLineOpening, 2),
            ("a \"\"\"\n  x\n y\n  \"\"\"", StringFault::Indentation, 10),
        ];
        for (text, expected, offset) in cases {
            match prepare(text) {
                Err(Refusal::BadString(span, fault)) => {
                    assert_eq!((fault, span.offset()), (expected, offset), "{text:?}")
                }
                other => panic!("{text:?}: {other:?}"),
            }
        }
        assert!(prepare("a \"x\\\n   y\" /**/\"z\" b=\"w\" (t)\"v\"").is_ok());
    }

    #[test]
    fn refuses_an_unclosed_comment_at_its_opening() {
        assert_eq!(
            prepare("a\n/* b /* */"),
            Err(Refusal::UnclosedComment((2, 2).into()))
        );
    }
}
