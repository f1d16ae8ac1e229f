//! The little XML the 3MF writers need: escaped attribute values and mesh elements.

use std::fmt::Write;

use super::{number, BedMesh};

/// `text` escaped for an XML attribute value in double quotes.
pub(super) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' => out.push_str("&#10;"),
            c if c.is_control() => {}
            c => out.push(c),
        }
    }
    out
}

/// The core 3MF `<vertices>` and `<triangles>` of `meshes` concatenated, each vertex moved by
/// `-origin` (the object's origin on the bed), one indentation level below `<mesh>`.
pub(super) fn mesh_elements(meshes: &[&BedMesh], origin: [f64; 2], indent: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{indent}<vertices>");
    for mesh in meshes {
        for p in &mesh.positions {
            let _ = writeln!(
                out,
                "{indent} <vertex x=\"{}\" y=\"{}\" z=\"{}\"/>",
                number(p.x - origin[0], 5),
                number(p.y - origin[1], 5),
                number(p.z, 5)
            );
        }
    }
    let _ = writeln!(out, "{indent}</vertices>");
    let _ = writeln!(out, "{indent}<triangles>");
    let mut base = 0usize;
    for mesh in meshes {
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| base + i as usize);
            let _ = writeln!(out, "{indent} <triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>");
        }
        base += mesh.positions.len();
    }
    let _ = writeln!(out, "{indent}</triangles>");
    out
}

/// The centre of `mesh`'s bounding box in x and y: the origin of its slicer object.
pub(super) fn xy_centre(mesh: &BedMesh) -> [f64; 2] {
    let mut low = [f64::INFINITY; 2];
    let mut high = [f64::NEG_INFINITY; 2];
    for p in &mesh.positions {
        for k in 0..2 {
            low[k] = low[k].min(p[k]);
            high[k] = high[k].max(p[k]);
        }
    }
    if mesh.positions.is_empty() {
        return [0.0, 0.0];
    }
    [0, 1].map(|k| (low[k] + high[k]) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_quotes() {
        assert_eq!(
            escape("Insert `a` & <b> \"c\" 'd'"),
            "Insert `a` &amp; &lt;b&gt; &quot;c&quot; &apos;d&apos;"
        );
    }
}
