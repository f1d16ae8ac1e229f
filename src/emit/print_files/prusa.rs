//! The PrusaSlicer project 3MF (the 2.x layout of PrusaSlicer's `Format/3mf.cpp`).
//!
//! Every part is one object, placed by its build item at its place on the bed. The object's
//! first volume is the part's solid (outer surface plus reversed capsule shells, as in the STL);
//! each capsule adds a support blocker volume (its capsule grown by
//! [`BLOCKER_MARGIN`](super::BLOCKER_MARGIN)), so that
//! support, if the user turns it on, never fills a void. The bed's pauses go in
//! `Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml`, keyed by the top of the first layer
//! printed after the pause; the print settings of the mass model in `Metadata/Slic3r_PE.config`.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::xml::{escape, mesh_elements, xy_centre};
use super::zip::{ArchiveTooLarge, ZipWriter};
use super::{blocker_mesh, number, solid_mesh, BedPart, BedPlatePause, PrintSettings, PAUSE_GCODE};

/// The generator the model names. PrusaSlicer reads volume types (negative volumes, support
/// blockers) only from files whose `Application` is PrusaSlicer 2.x (PrusaSlicer #15694).
const APPLICATION: &str = "PrusaSlicer-2.5.0";

/// The PrusaSlicer 3MF project of `parts`, pausing at `pauses` (the whole bed's, lowest first),
/// printed with `settings`.
pub fn write_prusa_3mf(
    parts: &[BedPart],
    pauses: &[BedPlatePause],
    settings: &PrintSettings,
) -> Result<Vec<u8>, ArchiveTooLarge> {
    let mut zip = ZipWriter::default();
    zip.add("[Content_Types].xml", CONTENT_TYPES.as_bytes())?;
    zip.add("_rels/.rels", RELS.as_bytes())?;
    zip.add("3D/3dmodel.model", model(parts).as_bytes())?;
    zip.add("Metadata/Slic3r_PE.config", config(settings).as_bytes())?;
    zip.add(
        "Metadata/Slic3r_PE_model.config",
        model_config(parts).as_bytes(),
    )?;
    zip.add(
        "Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml",
        custom_gcodes(pauses).as_bytes(),
    )?;
    zip.finish()
}

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
 <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
 <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>
"#;

const RELS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
 <Relationship Target="/3D/3dmodel.model" Id="rel-1" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"#;

/// `3D/3dmodel.model`: one object per part, its volumes' triangles concatenated, and a build
/// item translating it to its place on the bed.
fn model(parts: &[BedPart]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" \
         xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\" \
         xmlns:slic3rpe=\"http://schemas.slic3r.org/3mf/2017/06\">\n \
         <metadata name=\"slic3rpe:Version3mf\">1</metadata>\n",
    );
    let _ = writeln!(
        out,
        " <metadata name=\"Application\">{APPLICATION}</metadata>"
    );
    let _ = writeln!(out, " <metadata name=\"Designer\">ballast</metadata>");
    out.push_str(" <resources>\n");
    for (i, part) in parts.iter().enumerate() {
        let solid = solid_mesh(part);
        let blockers: Vec<_> = part.voids.iter().map(blocker_mesh).collect();
        let mut meshes = vec![&solid];
        meshes.extend(blockers.iter());
        let _ = writeln!(out, "  <object id=\"{}\" type=\"model\">", i + 1);
        out.push_str("   <mesh>\n");
        out.push_str(&mesh_elements(&meshes, xy_centre(&part.surface), "    "));
        out.push_str("   </mesh>\n  </object>\n");
    }
    out.push_str(" </resources>\n <build>\n");
    for (i, part) in parts.iter().enumerate() {
        let [x, y] = xy_centre(&part.surface);
        let _ = writeln!(
            out,
            "  <item objectid=\"{}\" transform=\"1 0 0 0 1 0 0 0 1 {} {} 0\" printable=\"1\"/>",
            i + 1,
            number(x, 5),
            number(y, 5)
        );
    }
    out.push_str(" </build>\n</model>\n");
    out
}

/// `Metadata/Slic3r_PE_model.config`: each object's name and its volumes by triangle range.
fn model_config(parts: &[BedPart]) -> String {
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<config>\n");
    for (i, part) in parts.iter().enumerate() {
        let _ = writeln!(out, " <object id=\"{}\" instances_count=\"1\">", i + 1);
        let _ = writeln!(
            out,
            "  <metadata type=\"object\" key=\"name\" value=\"{}\"/>",
            escape(&part.name)
        );
        let mut first = 0;
        let mut volume = |out: &mut String, name: &str, kind: &str, triangles: usize| {
            let _ = writeln!(
                out,
                "  <volume firstid=\"{first}\" lastid=\"{}\">",
                first + triangles - 1
            );
            let _ = writeln!(
                out,
                "   <metadata type=\"volume\" key=\"name\" value=\"{}\"/>",
                escape(name)
            );
            let _ = writeln!(
                out,
                "   <metadata type=\"volume\" key=\"volume_type\" value=\"{kind}\"/>"
            );
            out.push_str(
                "   <metadata type=\"volume\" key=\"matrix\" value=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\"/>\n",
            );
            out.push_str("  </volume>\n");
            first += triangles;
        };
        volume(
            &mut out,
            &part.name,
            "ModelPart",
            solid_mesh(part).triangles.len(),
        );
        for void in &part.voids {
            volume(
                &mut out,
                &format!("capsule {} (support blocker)", void.name),
                "SupportBlocker",
                blocker_mesh(void).triangles.len(),
            );
        }
        out.push_str(" </object>\n");
    }
    out.push_str("</config>\n");
    out
}

/// `Metadata/Slic3r_PE.config`: the settings the mass model assumes, support off, and the
/// pause G-code. Keys are PrusaSlicer's, one `; key = value` line each, in key order.
fn config(settings: &PrintSettings) -> String {
    let mut keys = BTreeMap::new();
    let [x, y] = settings.bed.map(|v| number(v, 3));
    keys.insert("bed_shape", format!("0x0,{x}x0,{x}x{y},0x{y}"));
    keys.insert(
        "bottom_solid_layers",
        settings.bottom_solid_layers.to_string(),
    );
    keys.insert("extrusion_width", number(settings.extrusion_width, 4));
    // PrusaSlicer's default pattern (stars) refuses 100%; rectilinear prints it solid.
    if settings.infill >= 1.0 {
        keys.insert("fill_pattern", "rectilinear".to_string());
    }
    keys.insert(
        "fill_density",
        format!("{}%", number(100.0 * settings.infill, 2)),
    );
    keys.insert("first_layer_height", number(settings.first_layer_height, 4));
    // `; printing object NAME` labels, so a sliced program maps back to its parts.
    keys.insert("gcode_label_objects", "1".to_string());
    keys.insert("layer_height", number(settings.layer_height, 4));
    keys.insert("pause_print_gcode", PAUSE_GCODE.to_string());
    keys.insert("perimeters", settings.perimeters.to_string());
    keys.insert(
        "solid_infill_below_area",
        number(settings.solid_infill_below_area, 3),
    );
    keys.insert("support_material", "0".to_string());
    keys.insert("top_solid_layers", settings.top_solid_layers.to_string());
    let mut out = String::from("; generated by ballast\n\n");
    for (key, value) in keys {
        let _ = writeln!(out, "; {key} = {value}");
    }
    out
}

/// `Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml`: one pause print (type 1) per pause,
/// keyed by its resume height.
fn custom_gcodes(pauses: &[BedPlatePause]) -> String {
    let mut out =
        String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<custom_gcodes_per_print_z>\n");
    for pause in pauses {
        let _ = writeln!(
            out,
            "<code print_z=\"{}\" type=\"1\" extruder=\"1\" color=\"\" extra=\"{}\" gcode=\"{PAUSE_GCODE}\"/>",
            number(pause.resume_height, 5),
            escape(&pause.message)
        );
    }
    out.push_str("<mode value=\"SingleExtruder\"/>\n</custom_gcodes_per_print_z>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::super::test_parts::settings;
    use super::*;

    #[test]
    fn the_config_holds_the_mass_models_settings_in_key_order() {
        let text = config(&settings());
        let keys: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("; "))
            .filter_map(|l| l.split_once(" = ").map(|(key, _)| key))
            .collect();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        assert_eq!(keys, sorted);
        assert!(text.contains("; fill_density = 15%\n"));
        assert!(text.contains("; first_layer_height = 0.35\n"));
        assert!(text.contains("; gcode_label_objects = 1\n"));
        assert!(!text.contains("fill_pattern"));
        let solid = PrintSettings {
            infill: 1.0,
            ..settings()
        };
        assert!(config(&solid).contains("; fill_density = 100%\n; fill_pattern = rectilinear\n"));
    }
}
