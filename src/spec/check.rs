//! The parsed KDL document checked against the vocabulary, node by node: names, annotations,
//! argument counts, properties, values, children blocks, repeated and missing nodes. Every rule
//! comes from [`vocabulary::DOCUMENT`]; nothing here knows what a particular node means.

use kdl::{KdlDocument, KdlEntry, KdlIdentifier, KdlNode};
use miette::SourceSpan;

use super::codes;
use super::model::Units;
use super::tree::Node;
use super::value::{annotation_span, check_value, listing, Slot};
use super::vocabulary::{self, ArgsSpec, NodeSpec, PropSpec, ValueKind};
use crate::diagnostic::Problem;

/// Checks `document` (parsed from `source`) against the top-level nodes `root` (a project file's
/// [`vocabulary::DOCUMENT`] or a solution file's [`vocabulary::SOLUTION`]) and returns its known
/// nodes, with every value that passed its checks converted to `units`. Problems are appended to
/// `problems`.
pub fn check_document(
    document: &KdlDocument,
    source: &str,
    root: &'static [NodeSpec],
    units: Units,
    problems: &mut Vec<Problem>,
) -> Vec<Node> {
    let mut checker = Checker {
        source,
        root,
        units,
        path: Vec::new(),
        problems,
    };
    checker.siblings(document.nodes(), root, None)
}

struct Checker<'a> {
    source: &'a str,
    /// The top-level nodes of the kind of file being checked.
    root: &'static [NodeSpec],
    units: Units,
    /// The names of the nodes whose children block is being checked, outermost first.
    path: Vec<&'static str>,
    problems: &'a mut Vec<Problem>,
}

impl Checker<'_> {
    /// Checks the nodes of one children block (or the document) against the nodes `allowed` there;
    /// `parent` is where the name of the block's node is written.
    fn siblings(
        &mut self,
        nodes: &[KdlNode],
        allowed: &'static [NodeSpec],
        parent: Option<SourceSpan>,
    ) -> Vec<Node> {
        let mut checked: Vec<Node> = Vec::new();
        for node in nodes {
            self.node_annotation(node);
            let Some(spec) = vocabulary::find(allowed, node.name().value()) else {
                self.unknown_node(node.name(), allowed);
                continue;
            };
            if !spec.repeatable {
                if let Some(first) = checked.iter().find(|other| other.name == spec.name) {
                    self.problems.push(
                        Problem::error(
                            codes::DUPLICATE_NODE,
                            format!("`{}` is written more than once", spec.name),
                        )
                        .with_label(node.name().span(), "written again here")
                        .with_label(first.name_span, "first written here")
                        .with_help("keep only one"),
                    );
                }
            }
            checked.push(self.node(node, spec));
        }
        for spec in allowed.iter().filter(|spec| spec.required) {
            // A rig's parts are components too.
            let stands_in = |node: &Node| spec.name == "component" && node.name == "rig";
            if !checked
                .iter()
                .any(|node| node.name == spec.name || stands_in(node))
            {
                self.missing_node(spec, parent);
            }
        }
        checked
    }

    /// Checks one known node: its entries and its children block.
    fn node(&mut self, node: &KdlNode, spec: &'static NodeSpec) -> Node {
        let mut args = Vec::new();
        let mut extra_args: Vec<SourceSpan> = Vec::new();
        let mut props = Vec::new();
        let mut written_props: Vec<&KdlIdentifier> = Vec::new();
        for entry in node.entries() {
            let Some(key) = entry.name() else {
                if args.len() < spec.args.max {
                    let slot = Slot {
                        owner: spec.name,
                        kind: spec.args.kind,
                        length: spec.args.length,
                    };
                    args.push(check_value(
                        entry,
                        entry.span(),
                        slot,
                        self.units,
                        self.problems,
                    ));
                } else {
                    extra_args.push(entry.span());
                }
                continue;
            };
            let Some(prop) = spec.props.iter().find(|prop| prop.name == key.value()) else {
                self.unknown_property(key, spec);
                continue;
            };
            if let Some(first) = written_props.iter().find(|k| k.value() == key.value()) {
                self.problems.push(
                    Problem::error(
                        codes::DUPLICATE_PROPERTY,
                        format!("`{}` is written twice on `{}`", prop.name, spec.name),
                    )
                    .with_label(key.span(), "written again here")
                    .with_label(first.span(), "first written here"),
                );
                continue;
            }
            written_props.push(key);
            let slot = Slot {
                owner: prop.name,
                kind: prop.kind,
                length: prop.length,
            };
            let span = self.prop_value_span(entry, key);
            let value = check_value(entry, span, slot, self.units, self.problems);
            props.push((prop.name, value));
        }
        self.argument_count(node, spec, args.len() + extra_args.len(), &extra_args);
        for prop in spec.props.iter().filter(|prop| prop.required) {
            if !written_props.iter().any(|key| key.value() == prop.name) {
                self.missing_property(node, spec, prop);
            }
        }
        let children = match node.children() {
            Some(_) if spec.children.is_empty() => {
                self.unexpected_children(node, spec);
                Vec::new()
            }
            block => {
                self.path.push(spec.name);
                let children = self.siblings(
                    block.map_or(&[], |block| block.nodes()),
                    spec.children,
                    Some(node.name().span()),
                );
                self.path.pop();
                children
            }
        };
        Node {
            name: spec.name,
            span: self.trim_end(node.span()),
            name_span: node.name().span(),
            args,
            props,
            children,
        }
    }

    /// Reports a type annotation on a node.
    fn node_annotation(&mut self, node: &KdlNode) {
        if let Some(annotation) = node.ty() {
            let written = annotation.value();
            self.problems.push(
                Problem::error(
                    codes::ANNOTATION,
                    format!(
                        "the annotation `({written})` on `{}` means nothing",
                        node.name().value()
                    ),
                )
                .with_label(annotation_span(node.span(), annotation), "not used")
                .with_help(format!("remove `({written})`")),
            );
        }
    }

    fn unknown_node(&mut self, name: &KdlIdentifier, allowed: &[NodeSpec]) {
        let written = name.value();
        let here = place(&self.path);
        let places = vocabulary::places_in(self.root, written);
        let (message, help) = if places.is_empty() {
            let help = match vocabulary::suggest(written, allowed.iter().map(|spec| spec.name)) {
                Some(known) => format!("did you mean `{known}`?"),
                None => format!(
                    "allowed {here}: {}",
                    listing(&names(allowed), |name| format!("`{name}`"), "and")
                ),
            };
            (format!("unknown node `{written}`"), help)
        } else {
            let homes: Vec<String> = places.iter().map(|path| place(path)).collect();
            let homes: Vec<&str> = homes.iter().map(String::as_str).collect();
            (
                format!("`{written}` does not belong {here}"),
                format!(
                    "`{written}` belongs {}",
                    listing(&homes, str::to_owned, "or")
                ),
            )
        };
        self.problems.push(
            Problem::error(codes::UNKNOWN_NODE, message)
                .with_label(name.span(), format!("not known {here}"))
                .with_help(help),
        );
    }

    fn unknown_property(&mut self, key: &KdlIdentifier, spec: &NodeSpec) {
        let written = key.value();
        let known: Vec<&str> = spec.props.iter().map(|prop| prop.name).collect();
        let help = match vocabulary::suggest(written, known.iter().copied()) {
            Some(prop) => format!("did you mean `{prop}`?"),
            None if known.is_empty() => format!("`{}` takes no properties", spec.name),
            None => format!(
                "`{}` takes {}",
                spec.name,
                listing(&known, |prop| format!("`{prop}=`"), "and")
            ),
        };
        self.problems.push(
            Problem::error(
                codes::UNKNOWN_PROPERTY,
                format!("unknown property `{written}` on `{}`", spec.name),
            )
            .with_label(key.span(), format!("not a property of `{}`", spec.name))
            .with_help(help),
        );
    }

    fn argument_count(
        &mut self,
        node: &KdlNode,
        spec: &NodeSpec,
        written: usize,
        extra: &[SourceSpan],
    ) {
        let ArgsSpec { min, max, .. } = spec.args;
        if (min..=max).contains(&written) {
            return;
        }
        let message = format!(
            "`{}` takes {}, found {written}",
            spec.name,
            count(spec.args)
        );
        let problem = match (extra.first(), extra.last()) {
            (Some(first), Some(last)) => Problem::error(codes::ARGUMENT_COUNT, message)
                .with_label(join(*first, *last), "unexpected"),
            _ => Problem::error(codes::ARGUMENT_COUNT, message)
                .with_label(node.name().span(), format!("needs {}", count(spec.args))),
        };
        self.problems.push(problem);
    }

    fn missing_property(&mut self, node: &KdlNode, spec: &NodeSpec, prop: &PropSpec) {
        self.problems.push(
            Problem::error(
                codes::MISSING_PROPERTY,
                format!("`{}` needs `{}=`", spec.name, prop.name),
            )
            .with_label(node.name().span(), format!("no `{}=` here", prop.name))
            .with_help(format!(
                "add `{}=` with {}",
                prop.name,
                kind_words(prop.kind)
            )),
        );
    }

    fn missing_node(&mut self, spec: &NodeSpec, parent: Option<SourceSpan>) {
        let example = example(spec);
        let problem = match self.path.last().zip(parent) {
            None => Problem::error(
                codes::MISSING_NODE,
                format!("the project has no `{}`", spec.name),
            )
            .with_help(format!("add `{example}`")),
            Some((parent, name_span)) => Problem::error(
                codes::MISSING_NODE,
                format!("`{parent}` has no `{}`", spec.name),
            )
            .with_label(name_span, format!("needs `{}`", spec.name))
            .with_help(format!("add `{example}` in its children block")),
        };
        self.problems.push(problem);
    }

    fn unexpected_children(&mut self, node: &KdlNode, spec: &NodeSpec) {
        self.problems.push(
            Problem::error(
                codes::UNEXPECTED_CHILDREN,
                format!("`{}` takes no children block", spec.name),
            )
            .with_label(self.children_span(node), "not expected")
            .with_help(if spec.props.is_empty() {
                "remove the block".to_owned()
            } else {
                format!(
                    "options are properties: `{} {}=...`",
                    spec.name, spec.props[0].name
                )
            }),
        );
    }

    /// The span of a property's value: from the first character after `=` to the entry's end.
    fn prop_value_span(&self, entry: &KdlEntry, key: &KdlIdentifier) -> SourceSpan {
        let entry_end = entry.span().offset() + entry.span().len();
        let after_key = key.span().offset() + key.span().len();
        let start = self
            .source
            .get(after_key..entry_end)
            .and_then(|between| {
                let equals = between.find('=')?;
                let value = between[equals + 1..].trim_start();
                Some(entry_end - value.len())
            })
            .unwrap_or(entry.span().offset());
        (start, entry_end - start).into()
    }

    /// `span` without the whitespace the parser counts as the end of a node.
    fn trim_end(&self, span: SourceSpan) -> SourceSpan {
        let end = span.offset() + span.len();
        match self.source.get(span.offset()..end) {
            Some(text) => (span.offset(), text.trim_end().len()).into(),
            None => span,
        }
    }

    /// The span of a node's children block, from its `{` to the node's end.
    fn children_span(&self, node: &KdlNode) -> SourceSpan {
        let node_span = self.trim_end(node.span());
        let node_end = node_span.offset() + node_span.len();
        let before_block = node
            .entries()
            .last()
            .map(KdlEntry::span)
            .unwrap_or(node.name().span());
        let from = before_block.offset() + before_block.len();
        match self
            .source
            .get(from..node_end)
            .and_then(|rest| rest.find('{'))
        {
            Some(brace) => (from + brace, node_end - from - brace).into(),
            None => node.name().span(),
        }
    }
}

/// A place in the grammar, in words: "at the top level", "inside `component` within `pose`".
fn place(path: &[&str]) -> String {
    match path.split_last() {
        None => "at the top level".to_owned(),
        Some((parent, ancestors)) => {
            let mut words = format!("inside `{parent}`");
            for ancestor in ancestors.iter().rev() {
                words.push_str(&format!(" within `{ancestor}`"));
            }
            words
        }
    }
}

/// The names of `specs`.
fn names(specs: &[NodeSpec]) -> Vec<&'static str> {
    specs.iter().map(|spec| spec.name).collect()
}

/// The smallest span covering `first` and `last`.
fn join(first: SourceSpan, last: SourceSpan) -> SourceSpan {
    let end = last.offset() + last.len();
    (first.offset(), end.saturating_sub(first.offset())).into()
}

/// "3 arguments", "no arguments", "at most 1 argument", ...
fn count(args: ArgsSpec) -> String {
    let plural = |n: usize| if n == 1 { "argument" } else { "arguments" };
    match (args.min, args.max) {
        (0, 0) => "no arguments".to_owned(),
        (min, max) if min == max => format!("{min} {}", plural(min)),
        (0, max) => format!("at most {max} {}", plural(max)),
        (min, usize::MAX) => format!("at least {min} {}", plural(min)),
        (min, max) => format!("{min} to {max} arguments"),
    }
}

/// What a property of `kind` is given, for help texts.
fn kind_words(kind: ValueKind) -> &'static str {
    match kind {
        ValueKind::String | ValueKind::Enum(_) => "a string",
        ValueKind::Path => "a file path",
        ValueKind::Number | ValueKind::Positive | ValueKind::NonNegative => "a number",
        ValueKind::Count => "a whole number",
        ValueKind::Bool => "`#true` or `#false`",
    }
}

/// A line a user can add to supply a missing node.
fn example(spec: &NodeSpec) -> String {
    match (spec.name, spec.args.max) {
        ("pose", _) => r#"pose "rest" { stand }"#.to_owned(),
        ("component", _) => r#"component "body" mesh="body.obj"` or `rig "figure.glb""#.to_owned(),
        (name, 3) => format!("{name} x y z"),
        (name, _) => name.to_owned(),
    }
}
