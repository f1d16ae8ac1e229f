//! A lexical pass that runs before the KDL parser and keeps it within a bounded stack.
//!
//! The `kdl` crate's parser recurses once per nesting level of children blocks, per token of a
//! block comment, per slashdash in a chain (`/- /- /- node`) and per stray `}` it recovers from, so
//! a small hostile file could overflow the stack. This pass finds deep nesting, long slashdash
//! chains and unmatched `}` itself, and blanks out the bodies of block comments (which mean nothing
//! to a project). It knows just enough of KDL to tell strings and comments apart from structure.

use miette::SourceSpan;

/// Children blocks nested deeper than this are refused; the grammar needs three levels.
pub const MAX_NESTING: usize = 32;
/// Slashdashes in a row longer than this are refused.
pub const MAX_SLASHDASH_CHAIN: usize = 8;

/// Why the text was refused before parsing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// A `{` opening a block deeper than [`MAX_NESTING`].
    TooDeep(SourceSpan),
    /// A `/-` continuing a chain longer than [`MAX_SLASHDASH_CHAIN`].
    LongSlashdashChain(SourceSpan),
    /// A `}` that closes no block.
    UnmatchedClose(SourceSpan),
}

/// Checks `source` and returns the text to give the parser: the same text, byte for byte, except
/// that the bodies of block comments are replaced by spaces (newlines kept), so every offset the
/// parser reports still points into `source`.
pub fn prepare(source: &str) -> Result<String, Refusal> {
    let mut bytes = source.as_bytes().to_vec();
    let mut depth = 0usize;
    let mut chain = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1).copied()) {
            (b'"', _) => {
                i = skip_string(&bytes, i);
                chain = 0;
            }
            (b'#', _) => {
                i = skip_raw_string(&bytes, i);
                chain = 0;
            }
            (b'/', Some(b'/')) => {
                i = skip_line(&bytes, i);
            }
            (b'/', Some(b'*')) => {
                i = blank_block_comment(&mut bytes, i);
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
                if !byte.is_ascii_whitespace() && byte != b'\\' {
                    chain = 0;
                }
                i += 1;
            }
        }
    }
    // Spaces were written only over whole characters (comment bodies lie between ASCII
    // delimiters), so the text is still UTF-8 and the lossy conversion never replaces anything.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The index after a quoted string starting at `start` (single- or multi-line, with escapes).
fn skip_string(bytes: &[u8], start: usize) -> usize {
    let multiline = bytes[start..].starts_with(b"\"\"\"");
    let mut i = start + if multiline { 3 } else { 1 };
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' if !multiline => return i + 1,
            b'"' if bytes[i..].starts_with(b"\"\"\"") => return i + 3,
            _ => i += 1,
        }
    }
    bytes.len()
}

/// The index after a raw string (`#"..."#`, `##"""..."""##`) starting at `start`, or after the
/// `#` when it starts a keyword such as `#true`.
fn skip_raw_string(bytes: &[u8], start: usize) -> usize {
    let hashes = bytes[start..].iter().take_while(|&&b| b == b'#').count();
    let open = start + hashes;
    if bytes.get(open) != Some(&b'"') {
        return open;
    }
    let quotes = if bytes[open..].starts_with(b"\"\"\"") {
        3
    } else {
        1
    };
    let mut i = open + quotes;
    while i < bytes.len() {
        let closes = bytes[i..].starts_with(&b"\"\"\""[..quotes])
            && bytes[i + quotes..]
                .iter()
                .take_while(|&&b| b == b'#')
                .count()
                >= hashes;
        if closes {
            return i + quotes + hashes;
        }
        i += 1;
    }
    bytes.len()
}

/// The index of the newline ending the line comment at `start` (or the end of the text).
fn skip_line(bytes: &[u8], start: usize) -> usize {
    bytes[start..]
        .iter()
        .position(|&b| b == b'\n' || b == b'\r')
        .map_or(bytes.len(), |offset| start + offset)
}

/// Blanks the body of the (possibly nested) block comment opening at `start` and returns the
/// index after its closing `*/`. An unclosed comment is blanked to the end of the text, where the
/// parser reports it.
fn blank_block_comment(bytes: &mut [u8], start: usize) -> usize {
    let mut level = 0usize;
    let mut i = start;
    while i < bytes.len() {
        if bytes[i..].starts_with(b"/*") {
            level += 1;
            i += 2;
        } else if bytes[i..].starts_with(b"*/") {
            level -= 1;
            i += 2;
            if level == 0 {
                // Keep the outermost delimiters; blank everything between them.
                blank(&mut bytes[start + 2..i - 2]);
                return i;
            }
        } else {
            i += 1;
        }
    }
    blank(&mut bytes[start + 2..]);
    bytes.len()
}

/// Replaces every byte but line breaks with a space.
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
        let text = "a \"{{{\" #\"}}\"# 1 { b /-c; d }\n// }\n";
        assert_eq!(prepare(text).unwrap(), text);
    }

    #[test]
    fn blanks_comment_bodies_in_place() {
        let text = "a /* x /* é */ } */ 1";
        let prepared = prepare(text).unwrap();
        assert_eq!(prepared.len(), text.len());
        let body = text.len() - "a /**/ 1".len();
        assert_eq!(prepared, format!("a /*{}*/ 1", " ".repeat(body)));
    }

    #[test]
    fn refuses_deep_nesting_at_the_first_brace_too_many() {
        let text = "a{".repeat(MAX_NESTING + 1);
        let offset = 2 * MAX_NESTING + 1;
        assert_eq!(prepare(&text), Err(Refusal::TooDeep((offset, 1).into())));
    }

    #[test]
    fn refuses_stray_close_and_long_chains() {
        assert_eq!(
            prepare("a {}\n}"),
            Err(Refusal::UnmatchedClose((5, 1).into()))
        );
        let chain = "/- ".repeat(MAX_SLASHDASH_CHAIN + 1) + "a";
        assert!(matches!(
            prepare(&chain),
            Err(Refusal::LongSlashdashChain(_))
        ));
        assert!(prepare(&"a /-1 ".repeat(100)).is_ok());
    }

    #[test]
    fn raw_strings_need_their_hashes() {
        let text = "a ##\"x\"# }\"## { }";
        assert_eq!(prepare(text).unwrap(), text);
    }
}
