//! The checked tree: the project file's nodes after every name, count, type, range and unit has
//! been checked against the vocabulary. Values that failed a check are absent (their problem is
//! already reported), so the resolver reads only good values and never reports a mistake twice.

use miette::SourceSpan;
use nalgebra::{Point3, Vector3};

use super::model::Spanned;

/// A value that passed its checks; lengths are already in the project's units.
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar {
    /// A finite number.
    Number(f64),
    /// A string (a name, a path or a keyword).
    Text(String),
    /// A whole number, zero or more.
    Count(u64),
    /// `#true` or `#false`.
    Flag(bool),
}

/// A checked value and where it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    /// The value.
    pub scalar: Scalar,
    /// The value as written, with its annotation (without the `key=` of a property).
    pub span: SourceSpan,
}

/// A node the vocabulary knows, with its checked arguments, properties and children.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// The node's name, as in the vocabulary.
    pub name: &'static str,
    /// The whole node, children included.
    pub span: SourceSpan,
    /// The node's name as written.
    pub name_span: SourceSpan,
    /// One entry per argument written, `None` where the argument failed a check.
    pub args: Vec<Option<Value>>,
    /// The properties written (each once), in file order, with `None` where the value failed a
    /// check.
    pub props: Vec<(&'static str, Option<Value>)>,
    /// The known child nodes, in file order.
    pub children: Vec<Node>,
}

impl Node {
    /// The first argument when it is a good string (a name or a path).
    pub fn text_arg(&self) -> Option<Spanned<String>> {
        match self.args.first()? {
            Some(Value {
                scalar: Scalar::Text(text),
                span,
            }) => Some(Spanned::new(text.clone(), *span)),
            _ => None,
        }
    }

    /// All arguments as numbers, when every one passed its checks.
    pub fn numbers(&self) -> Option<Vec<f64>> {
        self.args
            .iter()
            .map(|arg| match arg {
                Some(Value {
                    scalar: Scalar::Number(number),
                    ..
                }) => Some(*number),
                _ => None,
            })
            .collect()
    }

    /// The first argument when it is a good number.
    pub fn number_arg(&self) -> Option<f64> {
        self.numbers()?.first().copied()
    }

    /// The three arguments of a vector node.
    pub fn vector(&self) -> Option<Vector3<f64>> {
        match self.numbers()?.as_slice() {
            [x, y, z] => Some(Vector3::new(*x, *y, *z)),
            _ => None,
        }
    }

    /// The three arguments of a point node.
    pub fn point(&self) -> Option<Point3<f64>> {
        self.vector().map(Point3::from)
    }

    /// Whether the property `name` was written, good or not.
    pub fn has(&self, name: &str) -> bool {
        self.props.iter().any(|(key, _)| *key == name)
    }

    /// The property `name`, when it was written and passed its checks.
    pub fn prop(&self, name: &str) -> Option<&Value> {
        self.props
            .iter()
            .find(|(key, _)| *key == name)
            .and_then(|(_, value)| value.as_ref())
    }

    /// The number property `name`.
    pub fn number(&self, name: &str) -> Option<f64> {
        match self.prop(name)?.scalar {
            Scalar::Number(number) => Some(number),
            _ => None,
        }
    }

    /// The whole-number property `name`.
    pub fn count(&self, name: &str) -> Option<u64> {
        match self.prop(name)?.scalar {
            Scalar::Count(count) => Some(count),
            _ => None,
        }
    }

    /// The boolean property `name`.
    pub fn flag(&self, name: &str) -> Option<bool> {
        match self.prop(name)?.scalar {
            Scalar::Flag(flag) => Some(flag),
            _ => None,
        }
    }

    /// The string property `name`, with the span of its value.
    pub fn text(&self, name: &str) -> Option<Spanned<String>> {
        let value = self.prop(name)?;
        match &value.scalar {
            Scalar::Text(text) => Some(Spanned::new(text.clone(), value.span)),
            _ => None,
        }
    }

    /// The children called `name`, in file order.
    pub fn children_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Node> {
        self.children.iter().filter(move |child| child.name == name)
    }

    /// The first child called `name`.
    pub fn child(&self, name: &str) -> Option<&Node> {
        self.children.iter().find(|child| child.name == name)
    }
}
