//! One written value checked against what the vocabulary expects: its type, finiteness, range,
//! keyword and unit annotation. Lengths come out in the project's units.

use kdl::{KdlEntry, KdlIdentifier, KdlValue};
use miette::SourceSpan;

use super::codes;
use super::model::Units;
use super::tree::{Scalar, Value};
use super::vocabulary::{self, ValueKind};
use crate::diagnostic::Problem;

/// What a value must be, and how messages name its owner.
#[derive(Debug, Clone, Copy)]
pub struct Slot<'a> {
    /// The property or node the value belongs to, as messages name it (`margin`, `rotate`).
    pub owner: &'a str,
    /// The expected kind.
    pub kind: ValueKind,
    /// Whether the value is a length (and so may carry a unit annotation).
    pub length: bool,
}

/// Checks the value of `entry`, written at `span`, against `slot`. Returns the value in project
/// units, or `None` after reporting every problem found with it.
pub fn check_value(
    entry: &KdlEntry,
    span: SourceSpan,
    slot: Slot<'_>,
    units: Units,
    problems: &mut Vec<Problem>,
) -> Option<Value> {
    let factor = match entry.ty() {
        None => Some(1.0),
        Some(annotation) => unit_factor(annotation, span, slot, units, problems),
    };
    let scalar = match slot.kind {
        ValueKind::String | ValueKind::Enum(_) => text(entry, span, slot),
        ValueKind::Path => text(entry, span, slot).and_then(|path| non_empty(path, span, slot)),
        ValueKind::Number | ValueKind::Positive | ValueKind::NonNegative => {
            number(entry, span, slot, factor.unwrap_or(1.0), units)
        }
        ValueKind::Count => count(entry, span, slot),
        ValueKind::Bool => flag(entry, span, slot),
    };
    match scalar {
        Ok(scalar) => factor.map(|_| Value { scalar, span }),
        Err(problem) => {
            problems.push(*problem);
            None
        }
    }
}

/// The factor from the annotated unit to the project's, or `None` after reporting a bad
/// annotation.
fn unit_factor(
    annotation: &KdlIdentifier,
    value_span: SourceSpan,
    slot: Slot<'_>,
    units: Units,
    problems: &mut Vec<Problem>,
) -> Option<f64> {
    let written = annotation.value();
    let annotation_span = annotation_span(value_span, annotation);
    if !slot.length {
        problems.push(
            Problem::error(
                codes::UNIT,
                format!("`{}` is not a length, so it takes no unit", slot.owner),
            )
            .with_label(annotation_span, "means nothing here")
            .with_help("remove the annotation"),
        );
        return None;
    }
    match Units::from_keyword(written) {
        Some(unit) => Some(unit.in_metres() / units.in_metres()),
        None => {
            let help = match vocabulary::suggest(written, vocabulary::UNITS.iter().copied()) {
                Some(unit) => format!("did you mean `({unit})`?"),
                None => format!(
                    "a length may be written in {}",
                    listing(vocabulary::UNITS, |unit| format!("`({unit})`"), "or")
                ),
            };
            problems.push(
                Problem::error(codes::UNIT, format!("unknown unit `{written}`"))
                    .with_label(annotation_span, "not a unit of length")
                    .with_help(help),
            );
            None
        }
    }
}

/// The span of a type annotation with its parentheses, in an entry or node starting at `whole`.
pub fn annotation_span(whole: SourceSpan, annotation: &KdlIdentifier) -> SourceSpan {
    let end = annotation.span().offset() + annotation.span().len() + 1;
    (whole.offset(), end.saturating_sub(whole.offset())).into()
}

/// A string value, checked against a keyword list when there is one.
fn text(entry: &KdlEntry, span: SourceSpan, slot: Slot<'_>) -> Result<Scalar, Box<Problem>> {
    let KdlValue::String(text) = entry.value() else {
        return Err(wrong_type(entry.value(), span, slot));
    };
    if let ValueKind::Enum(keywords) = slot.kind {
        if !keywords.contains(&text.as_str()) {
            let mut problem = Problem::error(
                codes::UNKNOWN_KEYWORD,
                format!("`{}` does not accept `{text}`", slot.owner),
            )
            .with_label(span, format!("expected {}", expected(slot.kind)));
            if let Some(keyword) = vocabulary::suggest(text, keywords.iter().copied()) {
                problem = problem.with_help(format!("did you mean `{keyword}`?"));
            }
            return Err(Box::new(problem));
        }
    }
    Ok(Scalar::Text(text.clone()))
}

/// The largest length accepted anywhere, in millimetres (1 km): far beyond any printed object,
/// and small enough that volumes and moments stay finite.
pub const MAX_LENGTH_MM: f64 = 1e6;
/// The largest magnitude of any other number (densities, angles, counts of degrees).
pub const MAX_NUMBER: f64 = 1e9;

/// A path that is not empty.
fn non_empty(path: Scalar, span: SourceSpan, slot: Slot<'_>) -> Result<Scalar, Box<Problem>> {
    match &path {
        Scalar::Text(text) if text.trim().is_empty() => Err(Box::new(
            Problem::error(
                codes::OUT_OF_RANGE,
                format!("`{}` is an empty path", slot.owner),
            )
            .with_label(span, "names no file")
            .with_help("write the file's path, relative to the project's folder"),
        )),
        _ => Ok(path),
    }
}

/// A finite number in range, multiplied by `factor` (the unit conversion).
fn number(
    entry: &KdlEntry,
    span: SourceSpan,
    slot: Slot<'_>,
    factor: f64,
    units: Units,
) -> Result<Scalar, Box<Problem>> {
    let written = match entry.value() {
        // Every i128 converts to a finite f64 (rounded to the nearest representable value).
        KdlValue::Integer(integer) => *integer as f64,
        KdlValue::Float(float) => *float,
        KdlValue::String(text) => {
            let mut problem = *wrong_type(entry.value(), span, slot);
            if let Some(help) = string_number_help(text, slot.length, units) {
                problem = problem.with_help(help);
            }
            return Err(Box::new(problem));
        }
        other => return Err(wrong_type(other, span, slot)),
    };
    let number = written * factor;
    if !number.is_finite() {
        return Err(Box::new(
            Problem::error(
                codes::NOT_FINITE,
                format!("`{}` must be a finite number", slot.owner),
            )
            .with_label(span, "not a finite number"),
        ));
    }
    let (largest, what) = if slot.length {
        (MAX_LENGTH_MM / (units.in_metres() * 1000.0), "a length")
    } else {
        (MAX_NUMBER, "a number")
    };
    if number.abs() > largest {
        return Err(Box::new(
            Problem::error(
                codes::OUT_OF_RANGE,
                format!(
                    "`{}` is {written:e}, more than ballast accepts as {what} (at most {largest:e}{})",
                    slot.owner,
                    if slot.length {
                        format!(" {}, 1 km", units.keyword())
                    } else {
                        String::new()
                    }
                ),
            )
            .with_label(span, "far too large")
            .with_help("a printed object is at most a few metres across; the limit is fixed (docs/limits.md)"),
        ));
    }
    let (in_range, bound) = match slot.kind {
        ValueKind::Positive => (number > 0.0, "greater than zero"),
        ValueKind::NonNegative => (number >= 0.0, "zero or more"),
        _ => (true, ""),
    };
    if !in_range {
        return Err(Box::new(
            Problem::error(
                codes::OUT_OF_RANGE,
                format!("`{}` must be {bound}, found {written}", slot.owner),
            )
            .with_label(span, "out of range"),
        ));
    }
    Ok(Scalar::Number(number))
}

/// A whole number, zero or more, written without a decimal point.
fn count(entry: &KdlEntry, span: SourceSpan, slot: Slot<'_>) -> Result<Scalar, Box<Problem>> {
    match entry.value() {
        KdlValue::Integer(integer) => match u64::try_from(*integer) {
            Ok(count) => Ok(Scalar::Count(count)),
            Err(_) => {
                let bound = if *integer < 0 {
                    "zero or more".to_owned()
                } else {
                    format!("at most {}", u64::MAX)
                };
                Err(Box::new(
                    Problem::error(
                        codes::OUT_OF_RANGE,
                        format!("`{}` must be {bound}, found {integer}", slot.owner),
                    )
                    .with_label(span, "out of range"),
                ))
            }
        },
        KdlValue::Float(float) if !float.is_finite() => Err(Box::new(
            Problem::error(
                codes::NOT_FINITE,
                format!("`{}` must be a whole number", slot.owner),
            )
            .with_label(span, "not a finite number"),
        )),
        KdlValue::Float(float) => {
            let help = if *float < 0.0 {
                "write a whole number, zero or more".to_owned()
            } else if float.fract() == 0.0 {
                // `abs` turns `-0.0` into `0`.
                format!("write it without a decimal point: `{:.0}`", float.abs())
            } else {
                format!(
                    "write a whole number, such as `{:.0}` or `{:.0}`",
                    float.floor(),
                    float.ceil()
                )
            };
            Err(Box::new(
                Problem::error(
                    codes::WRONG_TYPE,
                    format!("expected a whole number, found {float:?}"),
                )
                .with_label(span, format!("`{}` takes a whole number", slot.owner))
                .with_help(help),
            ))
        }
        KdlValue::String(text) => {
            let problem = *wrong_type(entry.value(), span, slot);
            Err(Box::new(match text.trim().parse::<u64>() {
                Ok(count) => problem.with_help(format!("remove the quotes: `{count}`")),
                Err(_) => problem,
            }))
        }
        other => Err(wrong_type(other, span, slot)),
    }
}

/// `#true` or `#false`.
fn flag(entry: &KdlEntry, span: SourceSpan, slot: Slot<'_>) -> Result<Scalar, Box<Problem>> {
    match entry.value() {
        KdlValue::Bool(flag) => Ok(Scalar::Flag(*flag)),
        other => {
            let meant = match other {
                KdlValue::String(text) => match text.trim().to_ascii_lowercase().as_str() {
                    "true" | "yes" | "on" | "1" => Some(true),
                    "false" | "no" | "off" | "0" => Some(false),
                    _ => None,
                },
                KdlValue::Integer(1) => Some(true),
                KdlValue::Integer(0) => Some(false),
                _ => None,
            };
            let help = match meant {
                Some(flag) => format!("write `#{flag}`"),
                None => "write `#true` or `#false`".to_owned(),
            };
            Err(Box::new((*wrong_type(other, span, slot)).with_help(help)))
        }
    }
}

/// The problem for a value of the wrong type.
fn wrong_type(found: &KdlValue, span: SourceSpan, slot: Slot<'_>) -> Box<Problem> {
    let found = match found {
        KdlValue::String(_) => "a string",
        KdlValue::Integer(_) | KdlValue::Float(_) => "a number",
        KdlValue::Bool(true) => "`#true`",
        KdlValue::Bool(false) => "`#false`",
        KdlValue::Null => "`#null`",
    };
    let expected = expected(slot.kind);
    Box::new(
        Problem::error(
            codes::WRONG_TYPE,
            format!("expected {expected}, found {found}"),
        )
        .with_label(span, format!("`{}` takes {expected}", slot.owner)),
    )
}

/// How to write `text` (a string where a number belongs) as a number, when it looks like one.
fn string_number_help(text: &str, length: bool, units: Units) -> Option<String> {
    let text = text.trim();
    if let Ok(number) = text.parse::<f64>() {
        return Some(format!("remove the quotes: `{number}`"));
    }
    let split = text
        .find(|c: char| c.is_alphabetic())
        .filter(|&at| at > 0)?;
    let number = text[..split].trim().parse::<f64>().ok()?;
    let unit = text[split..].trim();
    let project = units.keyword();
    Some(match (length, Units::from_keyword(unit)) {
        (true, Some(_)) => {
            format!("write `({unit}){number}` or a plain number in the project's units ({project})")
        }
        (true, None) => format!("write a plain number in the project's units ({project})"),
        (false, _) => format!("write a plain number: `{number}`"),
    })
}

/// What a kind of value is, in words.
fn expected(kind: ValueKind) -> String {
    match kind {
        ValueKind::String => "a string".to_owned(),
        ValueKind::Path => "a file path (a string)".to_owned(),
        ValueKind::Number | ValueKind::Positive | ValueKind::NonNegative => "a number".to_owned(),
        ValueKind::Count => "a whole number".to_owned(),
        ValueKind::Bool => "`#true` or `#false`".to_owned(),
        ValueKind::Enum(keywords) => {
            format!("one of {}", listing(keywords, |k| format!("`{k}`"), "or"))
        }
    }
}

/// `a, b or c`.
pub fn listing(items: &[&str], show: impl Fn(&str) -> String, last: &str) -> String {
    let shown: Vec<String> = items.iter().map(|item| show(item)).collect();
    match shown.split_last() {
        None => String::new(),
        Some((only, [])) => only.clone(),
        Some((tail, head)) => format!("{} {last} {tail}", head.join(", ")),
    }
}
