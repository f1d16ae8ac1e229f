//! The solution file: the optimizer's capsules as KDL `capsule` nodes, for a user to commit, diff
//! and verify with `ballast check`.

use std::fmt::Write;

use super::number::number;

/// One capsule to write.
#[derive(Debug, Clone, PartialEq)]
pub struct SolutionCapsule {
    /// The capsule's name.
    pub name: String,
    /// The name of its component.
    pub component: String,
    /// One end of the axis, rest frame.
    pub from: [f64; 3],
    /// The other end.
    pub to: [f64; 3],
    /// Void radius.
    pub radius: f64,
    /// Whether the project pinned it.
    pub pinned: bool,
}

/// A solution file's content.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Comment lines for the top of the file (without the `//`).
    pub header: Vec<String>,
    /// The chosen infill, when the optimizer chose it.
    pub infill: Option<f64>,
    /// The capsules, in order.
    pub capsules: Vec<SolutionCapsule>,
    /// Digits after the decimal point for every length.
    pub decimals: usize,
}

/// The solution as KDL v2 text: the header comments, `infill` when chosen, then one `capsule`
/// node per capsule. The same solution always gives the same text.
pub fn write_solution(solution: &Solution) -> String {
    let mut out = String::new();
    for line in &solution.header {
        let _ = writeln!(out, "// {line}");
    }
    if !solution.header.is_empty() {
        out.push('\n');
    }
    if let Some(infill) = solution.infill {
        let _ = writeln!(out, "infill {}\n", number(infill, 6));
    }
    let d = solution.decimals;
    for (i, capsule) in solution.capsules.iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let pinned = if capsule.pinned { " pinned=#true" } else { "" };
        let _ = writeln!(
            out,
            "capsule {} component={} radius={}{pinned} {{",
            quoted(&capsule.name),
            quoted(&capsule.component),
            number(capsule.radius, d)
        );
        for (node, point) in [("from", capsule.from), ("to", capsule.to)] {
            let _ = writeln!(
                out,
                "    {node} {} {} {}",
                number(point[0], d),
                number(point[1], d),
                number(point[2], d)
            );
        }
        out.push_str("}\n");
    }
    out
}

/// A KDL string literal.
fn quoted(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_trimmed_and_never_negative_zero() {
        assert_eq!(number(1.25, 3), "1.25");
        assert_eq!(number(-0.0001, 3), "0");
        assert_eq!(number(12.0, 3), "12");
        assert_eq!(number(-3.5, 2), "-3.5");
    }

    #[test]
    fn names_are_escaped() {
        assert_eq!(quoted("a \"b\"\\"), "\"a \\\"b\\\"\\\\\"");
    }
}
