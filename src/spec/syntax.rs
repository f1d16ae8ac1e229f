//! Project text to a KDL v2 document, or the syntax errors that stop the front end.

use kdl::KdlDocument;

use super::codes::SYNTAX;
use miette::SourceSpan;

use super::guard::{self, Refusal, StringFault};
use crate::diagnostic::Problem;

/// Longest project file accepted, in bytes. Project files are written by hand; this bounds the
/// time (a few seconds for a file of this size that is all syntax errors) and the stack a hostile
/// file can cost.
pub const MAX_SOURCE_BYTES: usize = 512 << 10;

/// How to live with [`MAX_SOURCE_BYTES`].
pub const TOO_LARGE_HELP: &str =
    "a project or solution file is written by hand and needs a few kilobytes; \
     the limit is fixed (docs/limits.md, \"Project and solution files\")";

/// The parser's stack: a fixed part, a part per byte of text and a larger part per byte that can
/// make the parser recurse. Even after [`guard::prepare`], the `kdl` parser's error recovery
/// recurses about once per malformed token, at up to about 650 bytes of stack per byte of text;
/// a level of children blocks costs it about 8 KB, a slashdash about 4.5 KB. The guard keeps
/// those within its limits; the budget per `{` and `/` still covers the parser seeing structure
/// wherever such a byte is written, so no text can overflow the stack. It is reserved address
/// space, used only as far as the parser goes.
const BASE_STACK_BYTES: usize = 8 << 20;
const STACK_BYTES_PER_SOURCE_BYTE: usize = 2 << 10;
const STACK_BYTES_PER_BRACE: usize = 32 << 10;
const STACK_BYTES_PER_SLASH: usize = 8 << 10;
/// The most stack the parser is given; a text that would need more is refused.
const MAX_STACK_BYTES: usize = 1536 << 20;

/// Parses `source` as KDL v2, or returns every syntax error found.
pub fn read(source: &str) -> Result<KdlDocument, Vec<Problem>> {
    if source.len() > MAX_SOURCE_BYTES {
        return Err(vec![Problem::error(
            SYNTAX,
            format!(
                "the file is {} bytes long; the most ballast reads is {MAX_SOURCE_BYTES}",
                source.len()
            ),
        )
        .with_help(TOO_LARGE_HELP)]);
    }
    let prepared = guard::prepare(source).map_err(|refusal| vec![refused(refusal)])?;
    let braces = prepared.bytes().filter(|&b| b == b'{').count();
    let slashes = prepared.bytes().filter(|&b| b == b'/').count();
    let stack = BASE_STACK_BYTES
        + STACK_BYTES_PER_SOURCE_BYTE * prepared.len()
        + STACK_BYTES_PER_BRACE * braces
        + STACK_BYTES_PER_SLASH * slashes;
    if stack > MAX_STACK_BYTES {
        return Err(vec![Problem::error(
            SYNTAX,
            format!(
                "the file holds {braces} `{{` and {slashes} `/`, too many to parse safely in \
                 {} MB of stack",
                MAX_STACK_BYTES >> 20
            ),
        )
        .with_help(
            "a project file needs a few hundred at most; see docs/limits.md, \"Project and solution files\"",
        )]);
    }
    let parsed = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("kdl-parse".into())
            .stack_size(stack)
            .spawn_scoped(scope, || KdlDocument::parse_v2(&prepared))
            .map(|handle| handle.join())
    });
    match parsed {
        Ok(Ok(Ok(document))) => Ok(document),
        Ok(Ok(Err(error))) => Err(syntax_problems(source, error)),
        Ok(Err(_)) => Err(vec![Problem::error(
            SYNTAX,
            "the KDL parser failed on this file",
        )]),
        Err(error) => Err(vec![Problem::error(
            SYNTAX,
            format!("cannot start the KDL parser: {error}"),
        )]),
    }
}

/// One problem per diagnostic the `kdl` crate reported, in source order, without repeats.
fn syntax_problems(source: &str, error: kdl::KdlError) -> Vec<Problem> {
    let mut problems: Vec<Problem> = error
        .diagnostics
        .into_iter()
        .map(|diagnostic| {
            let message = diagnostic
                .message
                .unwrap_or_else(|| "invalid KDL".to_owned());
            let label = diagnostic.label.unwrap_or_default();
            let span = last_line(source, diagnostic.span);
            let help = keyword_help(source, span).or(diagnostic.help);
            let problem = Problem::error(SYNTAX, message).with_label(span, label);
            match help {
                Some(help) => problem.with_help(help),
                None => problem,
            }
        })
        .collect();
    // Sorting by label (span first), then by text, puts repeats side by side.
    problems
        .sort_by(|a, b| (&a.labels, &a.message, &a.help).cmp(&(&b.labels, &b.message, &b.help)));
    problems.dedup();
    if problems.is_empty() {
        problems.push(Problem::error(SYNTAX, "invalid KDL"));
    }
    problems
}

/// A `span` from the top of the file over several lines, cut to the last word of its last line:
/// the `kdl` crate starts some spans at the top of the file (a bad number such as `2.`, an
/// unclosed `/*`), which would point at the wrong place and draw the whole file.
fn last_line(source: &str, span: SourceSpan) -> SourceSpan {
    let start = span.offset().min(source.len());
    let end = (span.offset() + span.len()).min(source.len());
    let (Some(covered), true) = (source.get(start..end), source.is_char_boundary(end)) else {
        return span;
    };
    if start != 0 || !covered.trim_end().contains(is_line_end) {
        return span;
    }
    let text = covered.trim_end();
    let word = text.rfind(|c: char| c.is_whitespace()).map_or(0, |at| {
        at + text[at..].chars().next().map_or(1, char::len_utf8)
    });
    (start + word, text.len() - word).into()
}

/// Whether `c` ends a line in KDL.
fn is_line_end(c: char) -> bool {
    matches!(
        c,
        '\n' | '\r' | '\u{85}' | '\u{0B}' | '\u{0C}' | '\u{2028}' | '\u{2029}'
    )
}

/// The hint for a KDL v1 keyword (`true`, `null`, `inf`) written where KDL v2 wants `#true`.
fn keyword_help(source: &str, span: SourceSpan) -> Option<String> {
    let start = span.offset();
    let word = source
        .get(start..)?
        .split(|c: char| c.is_whitespace() || matches!(c, ';' | '{' | '}' | ')' | '='))
        .next()?;
    let word = word.rsplit('=').next()?;
    matches!(word, "true" | "false" | "null" | "inf" | "-inf" | "nan")
        .then(|| format!("KDL v2 writes keywords with a `#`: write `#{word}`"))
}

/// The problem for text the guard refused.
fn refused(refusal: Refusal) -> Problem {
    match refusal {
        Refusal::TooDeep(span) => Problem::error(
            SYNTAX,
            format!("blocks are nested more than {} deep", guard::MAX_NESTING),
        )
        .with_label(span, "this block is too deep")
        .with_help("a project file needs at most three levels: pose, component, step"),
        Refusal::LongSlashdashChain(span) => Problem::error(
            SYNTAX,
            format!(
                "more than {} slashdashes (`/-`) in a row",
                guard::MAX_SLASHDASH_CHAIN
            ),
        )
        .with_label(span, "one too many")
        .with_help("one `/-` comments out the whole node after it"),
        Refusal::UnmatchedClose(span) => Problem::error(SYNTAX, "unmatched `}`")
            .with_label(span, "this closes no block")
            .with_help("remove it, or add the `{` it should close"),
        Refusal::UnclosedComment(span) => Problem::error(SYNTAX, "unclosed `/*` comment")
            .with_label(span, "this comment is never closed")
            .with_help("close it with `*/`"),
        Refusal::BadString(span, fault) => bad_string(span, fault),
    }
}

/// The problem for a string the guard refused.
fn bad_string(span: SourceSpan, fault: StringFault) -> Problem {
    let (message, label, help) = match fault {
        StringFault::Unclosed => (
            "unclosed string".to_owned(),
            "this string is never closed",
            "close it with the same quote (and hashes) it opens with",
        ),
        StringFault::LineEnd => (
            "a line ends inside a string".to_owned(),
            "line end",
            "close the string on its line, or write a multi-line string between `\"\"\"` lines",
        ),
        StringFault::Forbidden(c) => (
            format!("U+{:04X} is not allowed in KDL text", u32::from(c)),
            "forbidden character",
            "remove it, or write it as an escape such as `\\u{200e}`",
        ),
        StringFault::BadEscape => (
            "unknown escape in a string".to_owned(),
            "not an escape",
            "the escapes are `\\\\`, `\\\"`, `\\n`, `\\r`, `\\t`, `\\b`, `\\f`, `\\s` and `\\u{...}`",
        ),
        StringFault::MultiLineOpening => (
            "a multi-line string's opening quotes must end their line".to_owned(),
            "text after `\"\"\"`",
            "start the text on the next line, or use a single `\"`",
        ),
        StringFault::Indentation => (
            "a multi-line string's lines must start with its closing line's indentation".to_owned(),
            "indented differently",
            "indent every line at least as far as the closing `\"\"\"`",
        ),
        StringFault::Glued => (
            "a quote right after a word".to_owned(),
            "no space before this quote",
            "put a space before the string",
        ),
    };
    Problem::error(SYNTAX, message)
        .with_label(span, label)
        .with_help(help)
}
