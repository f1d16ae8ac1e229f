//! Edits a designer makes to a project's files, as the watch tests and the watch benchmark make
//! them.
#![allow(dead_code)]

/// The OBJ text `text` with every vertex moved by `dx` along x: the same shape, new content.
pub fn shifted_obj(text: &str, dx: f64) -> String {
    let moved: Vec<String> = text
        .lines()
        .map(|line| match line.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest
                    .split_whitespace()
                    .map(|v| v.parse().expect("a vertex coordinate"))
                    .collect();
                format!("v {} {} {}", c[0] + dx, c[1], c[2])
            }
            None => line.to_string(),
        })
        .collect();
    moved.join("\n") + "\n"
}
