//! Project text to a KDL v2 document, or the syntax errors that stop the front end.

use kdl::KdlDocument;

use super::codes::SYNTAX;
use super::guard::{self, Refusal};
use crate::diagnostic::Problem;

/// Longest project file accepted, in bytes. Project files are written by hand; this bounds the
/// time (a few seconds for a file of this size that is all syntax errors) and the stack a hostile
/// file can cost.
pub const MAX_SOURCE_BYTES: usize = 512 << 10;

/// The parser's stack: a fixed part plus a part per byte of text. Even after [`guard::prepare`],
/// the `kdl` parser's error recovery recurses about once per malformed token, at up to about
/// 512 bytes of stack per byte of text; the budget leaves a fourfold margin. It is reserved
/// address space, used only as far as the parser goes.
const BASE_STACK_BYTES: usize = 8 << 20;
const STACK_BYTES_PER_SOURCE_BYTE: usize = 2 << 10;

/// Parses `source` as KDL v2, or returns every syntax error found.
pub fn read(source: &str) -> Result<KdlDocument, Vec<Problem>> {
    if source.len() > MAX_SOURCE_BYTES {
        return Err(vec![Problem::error(
            SYNTAX,
            format!(
                "the file is {} bytes long; the most ballast reads is {MAX_SOURCE_BYTES}",
                source.len()
            ),
        )]);
    }
    let prepared = guard::prepare(source).map_err(|refusal| vec![refused(refusal)])?;
    let stack = BASE_STACK_BYTES + STACK_BYTES_PER_SOURCE_BYTE * prepared.len();
    let parsed = std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("kdl-parse".into())
            .stack_size(stack)
            .spawn_scoped(scope, || KdlDocument::parse_v2(&prepared))
            .map(|handle| handle.join())
    });
    match parsed {
        Ok(Ok(Ok(document))) => Ok(document),
        Ok(Ok(Err(error))) => Err(syntax_problems(error)),
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
fn syntax_problems(error: kdl::KdlError) -> Vec<Problem> {
    let mut problems: Vec<Problem> = error
        .diagnostics
        .into_iter()
        .map(|diagnostic| {
            let message = diagnostic
                .message
                .unwrap_or_else(|| "invalid KDL".to_owned());
            let label = diagnostic.label.unwrap_or_default();
            let problem = Problem::error(SYNTAX, message).with_label(diagnostic.span, label);
            match diagnostic.help {
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
    }
}
