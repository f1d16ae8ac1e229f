//! The materials the glTF writer paints with: colours, translucency, emission.

use gltf::json;
use json::validation::Checked;

/// The materials the writer uses, each created on first use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Paint {
    Component,
    Capsule,
    Steel,
    CentreOfMass,
    SupportPolygon,
    Gravity,
    String,
    Buoyancy,
}

impl Paint {
    pub(super) const ALL: [Paint; 8] = [
        Paint::Component,
        Paint::Capsule,
        Paint::Steel,
        Paint::CentreOfMass,
        Paint::SupportPolygon,
        Paint::Gravity,
        Paint::String,
        Paint::Buoyancy,
    ];

    pub(super) fn material(self) -> json::Material {
        // (name, base colour, metallic, roughness, emissive, blend)
        let (name, colour, metallic, roughness, emissive, blend) = match self {
            Paint::Component => ("component", [0.8, 0.8, 0.8, 0.3], 0.0, 0.7, false, true),
            Paint::Capsule => ("capsule", [0.2, 0.6, 1.0, 0.35], 0.0, 0.3, false, true),
            Paint::Steel => ("steel", [0.56, 0.57, 0.58, 1.0], 1.0, 0.25, false, false),
            Paint::CentreOfMass => (
                "centre of mass",
                [1.0, 0.0, 0.0, 1.0],
                0.0,
                0.5,
                true,
                false,
            ),
            Paint::SupportPolygon => (
                "support polygon",
                [0.0, 0.8, 0.2, 1.0],
                0.0,
                1.0,
                true,
                false,
            ),
            Paint::Gravity => ("gravity", [1.0, 0.85, 0.0, 1.0], 0.0, 1.0, true, false),
            Paint::String => ("string", [0.9, 0.9, 0.85, 1.0], 0.0, 1.0, true, false),
            Paint::Buoyancy => (
                "buoyancy centre",
                [0.0, 0.3, 1.0, 1.0],
                0.0,
                0.5,
                true,
                false,
            ),
        };
        let emissive_factor = if emissive {
            [colour[0], colour[1], colour[2]]
        } else {
            [0.0; 3]
        };
        json::Material {
            alpha_mode: Checked::Valid(if blend {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: false,
            name: Some(name.to_owned()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(colour),
                metallic_factor: json::material::StrengthFactor(metallic),
                roughness_factor: json::material::StrengthFactor(roughness),
                ..Default::default()
            },
            emissive_factor: json::material::EmissiveFactor(emissive_factor),
            ..Default::default()
        }
    }
}
