//! `schema/ballast.kdl` against the parser: the schema must describe exactly the grammar in
//! `spec::vocabulary`, and an independent validator built from the schema alone must accept every
//! example and valid test project (which the parser must accept too).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use ballast::spec::parse_project;
use ballast::spec::vocabulary::{self, NodeSpec, ValueKind};
use kdl::{KdlDocument, KdlEntry, KdlNode, KdlValue};

const SCHEMA: &str = "schema/ballast.kdl";

/// A `node` of the schema.
#[derive(Debug)]
struct SchemaNode {
    name: String,
    description: Option<String>,
    min: usize,
    max: Option<usize>,
    value: Option<ValueRule>,
    props: Vec<PropRule>,
    children: Vec<SchemaNode>,
}

/// A `value` of the schema: how many arguments, and what each must be.
#[derive(Debug)]
struct ValueRule {
    min: usize,
    max: Option<usize>,
    rule: Rule,
}

/// A `prop` of the schema.
#[derive(Debug)]
struct PropRule {
    name: String,
    description: Option<String>,
    required: bool,
    rule: Rule,
}

/// The validations of one value.
#[derive(Debug, Default)]
struct Rule {
    ty: String,
    keywords: Vec<String>,
    format: Option<String>,
    greater_than: Option<f64>,
    at_least: Option<f64>,
    tags: Vec<String>,
}

fn read_schema() -> Vec<SchemaNode> {
    let text = std::fs::read_to_string(SCHEMA).unwrap();
    let document = KdlDocument::parse_v2(&text).expect("the schema is valid KDL v2");
    let root = document.get("document").expect("a `document` node");
    let mut nodes = Vec::new();
    for child in children(root) {
        match child.name().value() {
            "info" => {}
            "node" => nodes.push(read_node(child)),
            other => panic!("unexpected `{other}` in the schema's document"),
        }
    }
    nodes
}

fn children(node: &KdlNode) -> &[KdlNode] {
    node.children().map_or(&[], |block| block.nodes())
}

fn first_string(node: &KdlNode) -> String {
    node.get(0)
        .and_then(KdlValue::as_string)
        .unwrap_or_else(|| panic!("`{}` needs a string argument", node.name().value()))
        .to_owned()
}

fn count(node: &KdlNode) -> usize {
    let count = node.get(0).and_then(KdlValue::as_integer);
    let count = count.unwrap_or_else(|| panic!("`{}` needs a count", node.name().value()));
    usize::try_from(count).unwrap()
}

fn description(node: &KdlNode) -> Option<String> {
    node.get("description")
        .and_then(KdlValue::as_string)
        .map(str::to_owned)
}

fn read_node(node: &KdlNode) -> SchemaNode {
    let mut read = SchemaNode {
        name: first_string(node),
        description: description(node),
        min: 0,
        max: None,
        value: None,
        props: Vec::new(),
        children: Vec::new(),
    };
    for child in children(node) {
        match child.name().value() {
            "min" => read.min = count(child),
            "max" => read.max = Some(count(child)),
            "value" => {
                let mut value = ValueRule {
                    min: 0,
                    max: None,
                    rule: Rule::default(),
                };
                for item in children(child) {
                    match item.name().value() {
                        "min" => value.min = count(item),
                        "max" => value.max = Some(count(item)),
                        _ => read_validation(item, &mut value.rule, &read.name),
                    }
                }
                read.value = Some(value);
            }
            "prop" => {
                let mut prop = PropRule {
                    name: first_string(child),
                    description: description(child),
                    required: false,
                    rule: Rule::default(),
                };
                for item in children(child) {
                    match item.name().value() {
                        "required" => prop.required = item.get(0) == Some(&KdlValue::Bool(true)),
                        _ => read_validation(item, &mut prop.rule, &prop.name),
                    }
                }
                read.props.push(prop);
            }
            "children" => read.children = children(child).iter().map(read_node).collect(),
            other => panic!("unexpected `{other}` in schema node `{}`", read.name),
        }
    }
    read
}

fn read_validation(item: &KdlNode, rule: &mut Rule, owner: &str) {
    let number = |item: &KdlNode| match item.get(0) {
        Some(KdlValue::Integer(n)) => *n as f64,
        Some(KdlValue::Float(f)) => *f,
        _ => panic!("`{}` of `{owner}` needs a number", item.name().value()),
    };
    let strings = |item: &KdlNode| -> Vec<String> {
        item.entries()
            .iter()
            .filter_map(|entry| entry.value().as_string().map(str::to_owned))
            .collect()
    };
    match item.name().value() {
        "type" => rule.ty = first_string(item),
        "enum" => rule.keywords = strings(item),
        "format" => rule.format = Some(first_string(item)),
        ">" => rule.greater_than = Some(number(item)),
        ">=" => rule.at_least = Some(number(item)),
        "tag" => {
            let tag_enum = children(item).iter().find(|n| n.name().value() == "enum");
            rule.tags = strings(tag_enum.expect("`tag` holds an `enum`"));
        }
        other => panic!("unexpected validation `{other}` on `{owner}`"),
    }
}

// ---------------------------------------------------------------------------------------------
// Drift: the schema and the vocabulary, reduced to the same facts and compared both ways.

/// One fact per node ("count"), per node's arguments ("args") and per property, keyed by path.
type Facts = BTreeMap<String, String>;

fn upper(max: Option<usize>) -> String {
    max.map_or_else(|| "many".to_owned(), |max| max.to_string())
}

fn rule_kind(rule: &Rule) -> String {
    let base = match (rule.ty.as_str(), rule.format.as_deref()) {
        ("string", Some("path")) => "path".to_owned(),
        ("string", None) if !rule.keywords.is_empty() => {
            format!("keyword({})", rule.keywords.join("|"))
        }
        ("string", None) => "string".to_owned(),
        ("number", Some("u64")) if rule.greater_than.is_none() && rule.at_least.is_none() => {
            "count".to_owned()
        }
        ("boolean", None) => "boolean".to_owned(),
        ("number", None) => match (rule.greater_than, rule.at_least) {
            (Some(0.0), None) => "positive".to_owned(),
            (None, Some(0.0)) => "non-negative".to_owned(),
            (None, None) => "number".to_owned(),
            other => format!("number with bounds {other:?}"),
        },
        (ty, format) => format!("{ty} (format {format:?})"),
    };
    match rule.tags.as_slice() {
        [] => base,
        tags if tags == vocabulary::UNITS => format!("{base} length"),
        tags => format!("{base} tags({})", tags.join("|")),
    }
}

fn schema_facts(nodes: &[SchemaNode], path: &str, facts: &mut Facts) {
    for node in nodes {
        let here = format!("{path}/{}", node.name);
        facts.insert(
            format!("{here} count"),
            format!("{}..{}", node.min, upper(node.max)),
        );
        let args = match &node.value {
            None => "none".to_owned(),
            Some(value) => format!(
                "{}..{} {}",
                value.min,
                upper(value.max),
                rule_kind(&value.rule)
            ),
        };
        facts.insert(format!("{here} args"), args);
        for prop in &node.props {
            let required = if prop.required {
                "required"
            } else {
                "optional"
            };
            facts.insert(
                format!("{here} {}=", prop.name),
                format!("{required} {}", rule_kind(&prop.rule)),
            );
        }
        schema_facts(&node.children, &here, facts);
    }
}

fn kind(kind: ValueKind, length: bool) -> String {
    let base = match kind {
        ValueKind::String => "string".to_owned(),
        ValueKind::Path => "path".to_owned(),
        ValueKind::Number => "number".to_owned(),
        ValueKind::Positive => "positive".to_owned(),
        ValueKind::NonNegative => "non-negative".to_owned(),
        ValueKind::Count => "count".to_owned(),
        ValueKind::Bool => "boolean".to_owned(),
        ValueKind::Enum(keywords) => format!("keyword({})", keywords.join("|")),
    };
    if length {
        format!("{base} length")
    } else {
        base
    }
}

fn vocabulary_facts(nodes: &[NodeSpec], path: &str, facts: &mut Facts) {
    for node in nodes {
        let here = format!("{path}/{}", node.name);
        let max = (!node.repeatable).then_some(1);
        facts.insert(
            format!("{here} count"),
            format!("{}..{}", usize::from(node.required), upper(max)),
        );
        let args = &node.args;
        let value = if args.max == 0 {
            "none".to_owned()
        } else {
            let max = (args.max != usize::MAX).then_some(args.max);
            format!(
                "{}..{} {}",
                args.min,
                upper(max),
                kind(args.kind, args.length)
            )
        };
        facts.insert(format!("{here} args"), value);
        for prop in node.props {
            let required = if prop.required {
                "required"
            } else {
                "optional"
            };
            facts.insert(
                format!("{here} {}=", prop.name),
                format!("{required} {}", kind(prop.kind, prop.length)),
            );
        }
        vocabulary_facts(node.children, &here, facts);
    }
}

#[test]
fn schema_and_vocabulary_describe_the_same_grammar() {
    let mut schema = Facts::new();
    schema_facts(&read_schema(), "", &mut schema);
    let mut grammar = Facts::new();
    vocabulary_facts(vocabulary::DOCUMENT, "", &mut grammar);
    let mut differences = Vec::new();
    for (key, documented) in &schema {
        match grammar.get(key) {
            None => differences.push(format!(
                "{key}: in the schema ({documented}), not in the vocabulary"
            )),
            Some(accepted) if accepted != documented => differences.push(format!(
                "{key}: the schema says {documented}, the vocabulary {accepted}"
            )),
            Some(_) => {}
        }
    }
    for (key, accepted) in &grammar {
        if !schema.contains_key(key) {
            differences.push(format!(
                "{key}: in the vocabulary ({accepted}), not in the schema"
            ));
        }
    }
    assert!(
        differences.is_empty(),
        "{SCHEMA} and spec::vocabulary differ:\n{}",
        differences.join("\n")
    );
}

#[test]
fn every_schema_node_and_property_is_described() {
    fn visit(nodes: &[SchemaNode], path: &str, missing: &mut Vec<String>) {
        for node in nodes {
            let here = format!("{path}/{}", node.name);
            if node.description.is_none() {
                missing.push(here.clone());
            }
            for prop in node.props.iter().filter(|prop| prop.description.is_none()) {
                missing.push(format!("{here} {}=", prop.name));
            }
            visit(&node.children, &here, missing);
        }
    }
    let mut missing = Vec::new();
    visit(&read_schema(), "", &mut missing);
    assert!(missing.is_empty(), "no description: {missing:?}");
}

// ---------------------------------------------------------------------------------------------
// An independent validator: checks a document against the schema alone.

fn validate(document: &KdlDocument, schema: &[SchemaNode]) -> Vec<String> {
    let mut errors = Vec::new();
    validate_block(document.nodes(), schema, "", &mut errors);
    errors
}

fn validate_block(nodes: &[KdlNode], schema: &[SchemaNode], path: &str, errors: &mut Vec<String>) {
    for rule in schema {
        // A top-level `rig`'s parts are components, as the schema's `component` says.
        let stands_in = |name: &str| path.is_empty() && rule.name == "component" && name == "rig";
        let count = nodes
            .iter()
            .filter(|n| n.name().value() == rule.name || stands_in(n.name().value()))
            .count();
        if count < rule.min || rule.max.is_some_and(|max| count > max) {
            errors.push(format!(
                "{path}/{}: {count} found, {}..{} allowed",
                rule.name,
                rule.min,
                upper(rule.max)
            ));
        }
    }
    for node in nodes {
        let name = node.name().value();
        let here = format!("{path}/{name}");
        let Some(rule) = schema.iter().find(|rule| rule.name == name) else {
            errors.push(format!("{here}: unknown node"));
            continue;
        };
        if node.ty().is_some() {
            errors.push(format!("{here}: a node takes no tag"));
        }
        validate_entries(node, rule, &here, errors);
        match node.children() {
            Some(_) if rule.children.is_empty() => {
                errors.push(format!("{here}: takes no children"))
            }
            block => validate_block(
                block.map_or(&[], |b| b.nodes()),
                &rule.children,
                &here,
                errors,
            ),
        }
    }
}

fn validate_entries(node: &KdlNode, rule: &SchemaNode, here: &str, errors: &mut Vec<String>) {
    let args: Vec<&KdlEntry> = node
        .entries()
        .iter()
        .filter(|e| e.name().is_none())
        .collect();
    let (min, max) = rule
        .value
        .as_ref()
        .map_or((0, Some(0)), |value| (value.min, value.max));
    if args.len() < min || max.is_some_and(|max| args.len() > max) {
        errors.push(format!(
            "{here}: {} arguments, {min}..{} allowed",
            args.len(),
            upper(max)
        ));
    }
    if let Some(value) = &rule.value {
        for arg in &args {
            validate_value(arg, &value.rule, here, errors);
        }
    }
    let mut seen = Vec::new();
    for entry in node.entries() {
        let Some(key) = entry.name() else { continue };
        let key = key.value();
        if seen.contains(&key) {
            errors.push(format!("{here}: {key}= written twice"));
        }
        seen.push(key);
        match rule.props.iter().find(|prop| prop.name == key) {
            Some(prop) => validate_value(entry, &prop.rule, &format!("{here} {key}="), errors),
            None => errors.push(format!("{here}: unknown property {key}=")),
        }
    }
    for prop in rule.props.iter().filter(|prop| prop.required) {
        if !seen.contains(&prop.name.as_str()) {
            errors.push(format!("{here}: needs {}=", prop.name));
        }
    }
}

fn validate_value(entry: &KdlEntry, rule: &Rule, here: &str, errors: &mut Vec<String>) {
    if let Some(tag) = entry.ty() {
        if !rule.tags.iter().any(|allowed| allowed == tag.value()) {
            errors.push(format!("{here}: tag ({}) not allowed", tag.value()));
        }
    }
    let number = match entry.value() {
        KdlValue::Integer(integer) => Some(*integer as f64),
        KdlValue::Float(float) => Some(*float),
        _ => None,
    };
    match (rule.ty.as_str(), entry.value(), number) {
        ("string", KdlValue::String(text), _) => {
            if !rule.keywords.is_empty() && !rule.keywords.contains(text) {
                errors.push(format!(
                    "{here}: `{text}` is not one of {:?}",
                    rule.keywords
                ));
            }
        }
        ("boolean", KdlValue::Bool(_), _) => {}
        ("number", value, _) if rule.format.as_deref() == Some("u64") => {
            let whole = matches!(value, KdlValue::Integer(n) if u64::try_from(*n).is_ok());
            if !whole {
                errors.push(format!(
                    "{here}: {value:?} is not a whole number, zero or more"
                ));
            }
        }
        ("number", _, Some(number)) => {
            let too_small = rule.greater_than.is_some_and(|bound| number <= bound)
                || rule.at_least.is_some_and(|bound| number < bound);
            if !number.is_finite() || too_small {
                errors.push(format!("{here}: {number} out of range"));
            }
        }
        (ty, value, _) => errors.push(format!("{here}: expected a {ty}, found {value:?}")),
    }
}

/// Every `.kdl` file under `folder`, at any depth; none when the folder does not exist.
fn kdl_files(folder: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return Vec::new();
    };
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(kdl_files(&path));
        } else if path.extension().is_some_and(|ext| ext == "kdl") {
            files.push(path);
        }
    }
    files.sort();
    files
}

#[test]
fn examples_and_valid_projects_satisfy_the_schema_and_the_parser() {
    let schema = read_schema();
    let mut files = kdl_files(Path::new("examples"));
    files.extend(kdl_files(Path::new("tests/data/spec/ok")));
    // Solution files hold capsules only, not a project; the next test checks them.
    files.retain(|file| !is_solution(file));
    assert!(!files.is_empty(), "no project file to check");
    let mut failures = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        match KdlDocument::parse_v2(&text) {
            Ok(document) => {
                for error in validate(&document, &schema) {
                    failures.push(format!("{}: schema: {error}", file.display()));
                }
            }
            Err(error) => failures.push(format!("{}: not KDL v2: {error:?}", file.display())),
        }
        for problem in parse_project(&text, file).problems {
            failures.push(format!(
                "{}: parser: {}: {}",
                file.display(),
                problem.code,
                problem.message
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Whether `file` is a solution file (`<project>.solution.kdl`) rather than a project.
fn is_solution(file: &Path) -> bool {
    file.to_string_lossy().ends_with(".solution.kdl")
}

#[test]
fn example_solution_files_parse_against_their_projects() {
    let solutions: Vec<PathBuf> = kdl_files(Path::new("examples"))
        .into_iter()
        .filter(|file| is_solution(file))
        .collect();
    assert!(!solutions.is_empty(), "no solution file to check");
    let mut failures = Vec::new();
    for solution in &solutions {
        let name = solution.file_name().unwrap().to_string_lossy();
        let project_path = solution.with_file_name(name.replace(".solution.kdl", ".kdl"));
        let project_text = std::fs::read_to_string(&project_path).unwrap();
        let project = parse_project(&project_text, &project_path)
            .project
            .expect("the example project is valid");
        let text = std::fs::read_to_string(solution).unwrap();
        let parsed = ballast::spec::parse_solution(&text, solution, &project);
        for problem in &parsed.problems {
            failures.push(format!(
                "{}: {}: {}",
                solution.display(),
                problem.code,
                problem.message
            ));
        }
        if parsed.capsules.is_none_or(|c| c.is_empty()) {
            failures.push(format!("{}: no capsules", solution.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The validator is no rubber stamp: it rejects the broken projects whose mistakes the schema
/// can express.
#[test]
fn the_validator_rejects_what_the_schema_forbids() {
    let schema = read_schema();
    for case in [
        "annotation",
        "argument_count",
        "duplicate_node",
        "duplicate_property",
        "empty",
        "missing_node",
        "missing_property",
        "not_finite",
        "out_of_range",
        "unexpected_children",
        "unit",
        "unknown_keyword",
        "unknown_node",
        "unknown_property",
        "wrong_type",
    ] {
        let path = format!("tests/data/spec/err/{case}.kdl");
        let document = KdlDocument::parse_v2(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert!(
            !validate(&document, &schema).is_empty(),
            "{path} passed the schema"
        );
    }
}
