//! How a component's mesh file coordinates become rest-frame coordinates: the mesh's unit and up
//! axis (written, the glTF specification's, 3MF's, or the project's) and a scale factor.

use nalgebra::Rotation3;

use super::model::{Axis, Units};

/// How a component's mesh coordinates become rest-frame coordinates: a quarter turn that takes
/// the mesh's up axis onto the project's, then a scale from the mesh's unit into the project's,
/// times `scale`.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshFrame {
    /// The unit of the mesh file's coordinates.
    pub units: Units,
    /// Where [`MeshFrame::units`] came from.
    pub units_from: FrameSource,
    /// The axis that points up in the mesh file.
    pub up: Axis,
    /// Where [`MeshFrame::up`] came from.
    pub up_from: FrameSource,
    /// The factor written as `scale=` (1 without it), applied on top of the unit conversion.
    pub scale: f64,
}

/// Where a component's mesh unit or mesh up axis came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameSource {
    /// Written on the component (`mesh-units=`, `mesh-up=`).
    Written,
    /// The glTF specification: metres, +Y up (the default for `.gltf` and `.glb` files).
    Gltf,
    /// A 3MF file: +Z up, and millimetres once read (its own `unit` is applied as it is
    /// read; the default for `.3mf` files).
    ThreeMf,
    /// The project's own `units` and `up` (the default for OBJ files).
    Project,
}

impl FrameSource {
    /// The word the report uses: `written`, `gltf` or `project`.
    pub fn keyword(self) -> &'static str {
        match self {
            FrameSource::Written => "written",
            FrameSource::Gltf => "gltf",
            FrameSource::ThreeMf => "3mf",
            FrameSource::Project => "project",
        }
    }
}

impl MeshFrame {
    /// The frame of a mesh in the project's own units and up axis, unscaled: the identity.
    pub fn project(units: Units, up: Axis) -> MeshFrame {
        MeshFrame {
            units,
            units_from: FrameSource::Project,
            up,
            up_from: FrameSource::Project,
            scale: 1.0,
        }
    }

    /// The frame the glTF specification gives its files: metres, +Y up, unscaled.
    pub fn gltf() -> MeshFrame {
        MeshFrame {
            units: Units::Metre,
            units_from: FrameSource::Gltf,
            up: Axis::Y,
            up_from: FrameSource::Gltf,
            scale: 1.0,
        }
    }

    /// The frame of a 3MF file once read: millimetres (the loader applies the file's `unit`),
    /// +Z up (the build platform's normal), unscaled.
    pub fn three_mf() -> MeshFrame {
        MeshFrame {
            units: Units::Millimetre,
            units_from: FrameSource::ThreeMf,
            up: Axis::Z,
            up_from: FrameSource::ThreeMf,
            scale: 1.0,
        }
    }

    /// Project units per mesh unit: the unit conversion into `project` units times `scale`.
    pub fn factor(&self, project: Units) -> f64 {
        // Millimetres per unit are exact in binary for every unit but the inch's 25.4, so
        // metres into millimetres is exactly 1000 and a unit into itself exactly 1.
        self.scale * self.units.millimetres() / project.millimetres()
    }

    /// The quarter turn that takes the mesh's up axis onto `project_up` (about their cross
    /// product), or the identity when they are the same axis; its matrix holds only 0 and ±1.
    pub fn rotation(&self, project_up: Axis) -> Rotation3<f64> {
        let (a, b) = (self.up.unit_vector(), project_up.unit_vector());
        if a == b {
            return Rotation3::identity();
        }
        let n = a.cross(&b);
        Rotation3::from_matrix_unchecked(b * a.transpose() - a * b.transpose() + n * n.transpose())
    }

    /// Whether the mesh is used exactly as its file gives it (no turn, factor 1).
    pub fn is_identity(&self, project: Units, project_up: Axis) -> bool {
        self.factor(project) == 1.0 && self.up == project_up
    }
}
