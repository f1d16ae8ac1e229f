//! The user documentation keeps up with the code: every node, property and diagnostic code the
//! program knows is documented in docs/format.md.

use std::path::Path;

use ballast::spec::vocabulary::{NodeSpec, DOCUMENT};

fn read(relative: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)).unwrap()
}

fn collect_names(nodes: &[NodeSpec], names: &mut Vec<&'static str>) {
    for node in nodes {
        names.push(node.name);
        names.extend(node.props.iter().map(|prop| prop.name));
        collect_names(node.children, names);
    }
}

#[test]
fn every_node_and_property_is_documented() {
    let format = read("docs/format.md");
    let mut names = Vec::new();
    collect_names(DOCUMENT, &mut names);
    let missing: Vec<_> = names
        .iter()
        .filter(|name| !format.contains(&format!("`{name}")))
        .collect();
    assert!(missing.is_empty(), "not in docs/format.md: {missing:?}");
}

/// Every `"ballast::..."` string literal in the Rust sources under `folder`.
fn codes_in(folder: &Path, codes: &mut Vec<String>) {
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            codes_in(&path, codes);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            for piece in text.split("\"ballast::").skip(1) {
                let code: String = piece
                    .chars()
                    .take_while(|c| c.is_ascii_lowercase() || *c == '_' || *c == ':')
                    .collect();
                codes.push(format!("ballast::{code}"));
            }
        }
    }
}

#[test]
fn every_diagnostic_code_is_documented() {
    let format = read("docs/format.md");
    let mut codes = Vec::new();
    codes_in(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut codes,
    );
    codes.sort();
    codes.dedup();
    assert!(codes.len() > 20, "found only {codes:?}");
    let missing: Vec<_> = codes
        .iter()
        .filter(|code| !format.contains(&format!("`{code}`")))
        .collect();
    assert!(missing.is_empty(), "not in docs/format.md: {missing:?}");
}
