//! The typed project: what a project file means, with every name resolved and every default filled
//! in, and the source span of everything a later stage may need to point at.
//!
//! Lengths are in the project's [`Units`]; densities in g/cm³; angles in degrees. Positions of
//! components, capsules and suspension points are in the *rest frame*: the frame the component
//! meshes are written in, shared by all components.

use std::path::PathBuf;

use miette::SourceSpan;
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};

use crate::geometry::MeshSelector;

pub use super::mesh_frame::{FrameSource, MeshFrame};

/// A value with the span of the source text it came from. Equality ignores the span, so two
/// projects that mean the same thing compare equal however they are laid out.
#[derive(Debug, Clone)]
pub struct Spanned<T> {
    /// The value.
    pub value: T,
    /// Where it was written.
    pub span: SourceSpan,
}

impl<T> Spanned<T> {
    /// Wraps `value` with `span`.
    pub fn new(value: T, span: SourceSpan) -> Self {
        Spanned { value, span }
    }
}

impl<T: PartialEq> PartialEq for Spanned<T> {
    fn eq(&self, other: &Self) -> bool {
        self.value == other.value
    }
}

/// The length unit the project's numbers are written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// Millimetres (the default).
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Metres.
    Metre,
    /// Inches.
    Inch,
}

impl Project {
    /// The name of component `index`, or `""` past the last component.
    pub fn component_name(&self, index: usize) -> &str {
        self.components
            .get(index)
            .map_or("", |component| component.name.value.as_str())
    }
}

impl Units {
    /// The unit for its keyword in the project file (`mm`, `cm`, `m`, `in`).
    pub fn from_keyword(keyword: &str) -> Option<Units> {
        match keyword {
            "mm" => Some(Units::Millimetre),
            "cm" => Some(Units::Centimetre),
            "m" => Some(Units::Metre),
            "in" => Some(Units::Inch),
            _ => None,
        }
    }

    /// The keyword written in the project file.
    pub fn keyword(self) -> &'static str {
        match self {
            Units::Millimetre => "mm",
            Units::Centimetre => "cm",
            Units::Metre => "m",
            Units::Inch => "in",
        }
    }

    /// Length of one unit in millimetres.
    pub fn millimetres(self) -> f64 {
        match self {
            Units::Millimetre => 1.0,
            Units::Centimetre => 10.0,
            Units::Metre => 1000.0,
            Units::Inch => 25.4,
        }
    }

    /// Length of one unit in metres.
    pub fn in_metres(self) -> f64 {
        match self {
            Units::Millimetre => 0.001,
            Units::Centimetre => 0.01,
            Units::Metre => 1.0,
            Units::Inch => 0.0254,
        }
    }

    /// Volume of one cubic unit in cm³ (what a density in g/cm³ multiplies to give grams).
    pub fn cubic_in_cm3(self) -> f64 {
        let centimetres = self.in_metres() * 100.0;
        centimetres * centimetres * centimetres
    }

    /// `millimetres` expressed in this unit (used to convert the built-in defaults).
    pub fn from_millimetres(self, millimetres: f64) -> f64 {
        millimetres * 0.001 / self.in_metres()
    }
}

/// The axis that points up, against gravity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// +X.
    X,
    /// +Y.
    Y,
    /// +Z (the default).
    Z,
}

impl Axis {
    /// The axis for its keyword (`x`, `y`, `z`).
    pub fn from_keyword(keyword: &str) -> Option<Axis> {
        match keyword {
            "x" => Some(Axis::X),
            "y" => Some(Axis::Y),
            "z" => Some(Axis::Z),
            _ => None,
        }
    }

    /// The keyword written in the project file.
    pub fn keyword(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }

    /// The unit vector along the axis.
    pub fn unit_vector(self) -> Vector3<f64> {
        match self {
            Axis::X => Vector3::x(),
            Axis::Y => Vector3::y(),
            Axis::Z => Vector3::z(),
        }
    }
}

/// A whole project file, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Project {
    /// The unit of every length in the file.
    pub units: Units,
    /// The up axis; gravity points the other way.
    pub up: Axis,
    /// The printed material.
    pub material: Material,
    /// The steel balls.
    pub ball: Ball,
    /// How full the printed interior is.
    pub infill: Infill,
    /// Minimum material left between a capsule and the surface, and between two capsules.
    pub wall: f64,
    /// How the parts are printed, and so where the material is.
    pub print: Print,
    /// The printed parts, in file order.
    pub components: Vec<Component>,
    /// The named states of the model, in file order.
    pub poses: Vec<Pose>,
    /// The capsules written in the project file, in file order: the design itself without
    /// [`Project::optimize`], the optimizer's pinned capsules and seeds with it.
    pub capsules: Vec<Capsule>,
    /// How the optimizer places capsules, when the project asks for it (`optimize`).
    pub optimize: Option<Optimize>,
    /// Where the build writes.
    pub output: Output,
}

/// The most capsules the optimizer is asked to place (`optimize capsules=`, `--capsules`, or
/// the capsules written in a project that optimizes).
pub const MAX_OPTIMIZED_CAPSULES: usize = 8;
/// The most poses × capsules the optimizer is asked to weigh: its work in each step grows with
/// both.
pub const MAX_POSE_CAPSULES: usize = 32;

/// The `optimize` node: the project asks the optimizer to place its capsules. Equality ignores
/// the spans.
#[derive(Debug, Clone)]
pub struct Optimize {
    /// How many capsules the design should have; `None` lets the optimizer choose by
    /// [`Optimize::tolerance_degrees`].
    pub capsules: Option<usize>,
    /// Cell size of the signed distance grid that keeps capsules inside their component, project
    /// units; `None` derives it from the capsule sizes.
    pub grid_cell: Option<f64>,
    /// Where `grid-cell=` was written, when it was.
    pub grid_cell_span: Option<SourceSpan>,
    /// When the optimizer chooses the capsule count, what each capsule costs, degrees of
    /// objective: the design meeting every goal with the lowest objective plus this much per
    /// capsule is taken.
    pub tolerance_degrees: f64,
    /// Seed of the random starts of exhaustive search.
    pub seed: u64,
    /// The whole `optimize` node.
    pub span: SourceSpan,
}

/// The printed material.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// A label for reports (e.g. `"PLA"`).
    pub name: String,
    /// Density in g/cm³.
    pub density: f64,
}

/// The balls that roll inside capsules.
#[derive(Debug, Clone, PartialEq)]
pub struct Ball {
    /// Density in g/cm³ (steel by default).
    pub density: f64,
    /// Gap between a ball and its capsule's wall, project units: a ball's radius is at most the
    /// capsule radius minus this.
    pub clearance: f64,
    /// Least gap between the top of a ball resting in its void and the top of the layer the
    /// print pauses after for it, project units (`docs/fabrication.md`, "The window").
    pub pause_clearance: f64,
    /// A capsule whose axis is within this many degrees of horizontal cannot be trusted to send its
    /// ball to either end.
    pub min_angle: f64,
    /// Ball diameters that can be bought, project units: the stock sizes
    /// ([`stock_diameters_mm`](super::stock::stock_diameters_mm)) unless the project lists its
    /// own. Empty means any size (`any-size=#true`).
    pub diameters: Vec<f64>,
}

impl Ball {
    /// Radius of the ball that goes in a capsule of `capsule_radius`: the largest available ball
    /// that leaves the clearance, or `None` when no ball fits.
    pub fn radius_for(&self, capsule_radius: f64) -> Option<f64> {
        let largest = capsule_radius - self.clearance;
        if largest <= 0.0 {
            return None;
        }
        if self.diameters.is_empty() {
            return Some(largest);
        }
        self.diameters
            .iter()
            .map(|diameter| diameter / 2.0)
            .filter(|radius| *radius <= largest * (1.0 + 1e-9))
            .max_by(f64::total_cmp)
    }

    /// Whether balls come from a list of diameters rather than in any size.
    pub fn is_listed(&self) -> bool {
        !self.diameters.is_empty()
    }

    /// The listed ball radii smaller than `ball_radius`, largest first.
    pub fn smaller(&self, ball_radius: f64) -> impl Iterator<Item = f64> + '_ {
        let mut radii: Vec<f64> = self
            .diameters
            .iter()
            .map(|diameter| diameter / 2.0)
            .filter(|radius| *radius < ball_radius * (1.0 - 1e-9))
            .collect();
        radii.sort_by(|a, b| b.total_cmp(a));
        radii.into_iter()
    }

    /// The smallest listed ball radius larger than `ball_radius`, if any.
    pub fn next_larger(&self, ball_radius: f64) -> Option<f64> {
        self.diameters
            .iter()
            .map(|diameter| diameter / 2.0)
            .filter(|radius| *radius > ball_radius * (1.0 + 1e-9))
            .min_by(f64::total_cmp)
    }
}

/// How the material of a printed part is laid out (the `print` node).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MassModel {
    /// As an FDM slicer deposits it: solid shells (perimeters, top and bottom layers, the walls of
    /// every capsule, narrow regions) around sparse infill.
    Fdm,
    /// Material at the infill fraction everywhere: for materials that are not printed in layers.
    Uniform,
}

impl MassModel {
    /// The model a `print model=` keyword names.
    pub fn from_keyword(keyword: &str) -> Option<MassModel> {
        match keyword {
            "fdm" => Some(MassModel::Fdm),
            "uniform" => Some(MassModel::Uniform),
            _ => None,
        }
    }
}

/// The slicer settings the mass model assumes (the `print` node). Lengths in project units; the
/// defaults are PrusaSlicer 2.5's for a 0.4 mm nozzle (`prusa-slicer --help-fff`). Each component
/// is built along its own print orientation (its `print` block, or the facet ballast chooses).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Print {
    /// Where the material is.
    pub model: MassModel,
    /// Perimeter loops around every outline, the outside and every hole (PrusaSlicer: 3).
    pub perimeters: u64,
    /// Extrusion width (PrusaSlicer: 1.125 × the 0.4 mm nozzle, 0.45 mm).
    pub extrusion_width: f64,
    /// Layer height (PrusaSlicer: 0.3 mm).
    pub layer_height: f64,
    /// Height of the first layer (PrusaSlicer: 0.35 mm).
    pub first_layer_height: f64,
    /// Solid layers under every top surface (PrusaSlicer: 3).
    pub top_solid_layers: u64,
    /// Solid layers over every bottom surface (PrusaSlicer: 3).
    pub bottom_solid_layers: u64,
    /// Interior regions of a layer smaller than this area, square project units, are filled
    /// solid (PrusaSlicer: 70 mm²).
    pub solid_infill_below_area: f64,
    /// How far the solid layers of a top or bottom surface reach past it into the sparse infill
    /// (PrusaSlicer 2.5: a fixed 3 mm, `EXTERNAL_INFILL_MARGIN`; not a setting of the slicer, so
    /// not of the project file either).
    pub surface_margin: f64,
}

impl Print {
    /// PrusaSlicer's defaults, in `units`.
    pub fn defaults(units: Units) -> Print {
        let mm = |value: f64| units.from_millimetres(value);
        Print {
            model: MassModel::Fdm,
            perimeters: 3,
            extrusion_width: mm(0.45),
            layer_height: mm(0.3),
            first_layer_height: mm(0.35),
            top_solid_layers: 3,
            bottom_solid_layers: 3,
            solid_infill_below_area: mm(mm(70.0)),
            surface_margin: mm(3.0),
        }
    }

    /// The spacing of neighbouring extrusions: the width less the rounding of an extrusion's
    /// sides, `w − h(1 − π/4)` (PrusaSlicer's `Flow::spacing`).
    pub fn spacing(&self) -> f64 {
        self.extrusion_width - self.layer_height * (1.0 - std::f64::consts::FRAC_PI_4)
    }

    /// Thickness of the perimeters, measured horizontally: `perimeters × spacing`.
    pub fn perimeter_thickness(&self) -> f64 {
        self.perimeters as f64 * self.spacing()
    }
}

/// How full the printed interior is: 1.0 is solid.
#[derive(Debug, Clone, PartialEq)]
pub struct Infill {
    /// The fraction used when the design is evaluated.
    pub value: f64,
    /// The range the optimizer may choose from, when the project gives one.
    pub range: Option<(f64, f64)>,
}

/// A printed part. Equality ignores the spans.
#[derive(Debug, Clone)]
pub struct Component {
    /// Unique among components.
    pub name: Spanned<String>,
    /// The mesh file, resolved against the project file's folder; the span is the `mesh=` value.
    pub mesh: Spanned<PathBuf>,
    /// Which part of the mesh file.
    pub selector: MeshSelector,
    /// How the mesh file's coordinates become rest-frame coordinates: its unit, its up axis and a
    /// scale factor.
    pub frame: MeshFrame,
    /// How the component lies on the print bed, when its `print` block says; `None`: ballast
    /// chooses.
    pub print: Option<PrintOrientation>,
    /// The whole `component` node.
    pub span: SourceSpan,
}

/// A component's declared print orientation (its `print` block). The print frame has +z up,
/// away from the bed, whatever the project's `up` axis.
#[derive(Debug, Clone, PartialEq)]
pub enum PrintOrientation {
    /// `down x y z`: the rest-frame direction that points to the bed; the hull facet the ray from
    /// the component's centroid along it meets goes on the bed. Never zero.
    Down(Spanned<Vector3<f64>>),
    /// `rotate rx ry rz`: rest frame to print frame, extrinsic X, Y, Z Euler angles in degrees
    /// (as a pose's `rotate`).
    Rotate(Spanned<UnitQuaternion<f64>>),
}

/// A named state of the model: where each component is, and what must happen. Equality ignores
/// the spans.
#[derive(Debug, Clone)]
pub struct Pose {
    /// Unique among poses.
    pub name: Spanned<String>,
    /// Rest frame to world, applied after each component's own transform. For a pose with
    /// [`down`](Pose::down), the identity until the driver, once the meshes are loaded, sets it
    /// to the rotation that puts the chosen facet on the ground.
    pub transform: Isometry3<f64>,
    /// The `down x y z` direction, model frame (components placed by the pose), when the pose
    /// names its resting facet instead of writing a rotation: the facet of the hull that the ray
    /// from the solid model's centre of mass along it meets goes on the ground. Never zero.
    pub down: Option<Spanned<Vector3<f64>>>,
    /// Per component (same order as [`Project::components`]): component rest frame to model
    /// frame; the identity unless the pose moves that component. A component's world transform
    /// is `transform * component_transforms[i]`.
    pub component_transforms: Vec<Isometry3<f64>>,
    /// What must happen in this pose.
    pub goals: Vec<Spanned<Goal>>,
    /// The whole `pose` node.
    pub span: SourceSpan,
}

impl Pose {
    /// Rest frame to world for `component` in this pose: `transform * component_transforms[i]`,
    /// with the identity standing in for a missing component transform.
    pub fn component_frame(&self, component: usize) -> Isometry3<f64> {
        match self.component_transforms.get(component) {
            Some(own) => self.transform * own,
            None => self.transform,
        }
    }
}

/// What must happen in a pose.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// Rest on the ground and survive a tilt of at least `margin` degrees in every direction.
    Stand {
        /// Degrees of tilt the pose must survive.
        margin: f64,
        /// Vertices within this height of the lowest one touch the ground once the pose rests on
        /// its hull (project units); `None`: the hull's coplanarity tolerance.
        contact_tolerance: Option<f64>,
    },
    /// Fall over when put down: the centre of mass is at least `margin` degrees outside the support.
    Imbalance {
        /// Degrees by which the centre of mass must lie outside the support polygon.
        margin: f64,
        /// As for [`Goal::Stand`].
        contact_tolerance: Option<f64>,
    },
    /// Hang from a string tied at `point` with the centre of mass straight below it.
    Suspend {
        /// The attachment point, rest frame of `component`.
        point: Point3<f64>,
        /// Index into [`Project::components`] of the component the point is attached to.
        component: usize,
        /// Allowed angle between the string and gravity, degrees.
        tolerance: f64,
        /// Met only when hanging as wanted is the model's only stable state (`unique=#true`).
        unique: bool,
    },
    /// Float upright in a fluid: the centre of buoyancy straight above the centre of mass.
    Immerse {
        /// Density of the fluid, g/cm³.
        fluid_density: f64,
        /// Minimum distance between the centres of buoyancy and mass, project units.
        min_distance: f64,
        /// Allowed angle between the centre-to-centre direction and up, degrees.
        tolerance: f64,
        /// When given, |mass − fluid density × volume| must be at most this many grams.
        mass_tolerance: Option<f64>,
        /// Met only when floating as wanted is the model's only stable state: it rights itself
        /// from any orientation (`unique=#true`).
        unique: bool,
    },
}

impl Goal {
    /// The goal's node name in the project file.
    pub fn keyword(&self) -> &'static str {
        match self {
            Goal::Stand { .. } => "stand",
            Goal::Imbalance { .. } => "imbalance",
            Goal::Suspend { .. } => "suspend",
            Goal::Immerse { .. } => "immerse",
        }
    }
}

/// A capsule-shaped void holding one ball, written in a project or solution file. Equality ignores
/// the spans.
#[derive(Debug, Clone)]
pub struct Capsule {
    /// Unique among capsules.
    pub name: Spanned<String>,
    /// Index into [`Project::components`]; the span is the `component=` value.
    pub component: Spanned<usize>,
    /// One end of the axis, rest frame.
    pub from: Point3<f64>,
    /// The other end of the axis, rest frame.
    pub to: Point3<f64>,
    /// Radius of the void, project units.
    pub radius: f64,
    /// With [`Project::optimize`], whether the optimizer must keep the capsule exactly as written
    /// (`pinned=#true`) rather than move, resize or remove it. No effect without `optimize`.
    pub pinned: bool,
    /// The whole `capsule` node.
    pub span: SourceSpan,
}

// Exhaustive destructuring: a new field must be added to these comparisons to compile.
impl PartialEq for Component {
    fn eq(&self, other: &Self) -> bool {
        let Component {
            name,
            mesh,
            selector,
            frame,
            print,
            span: _,
        } = self;
        (name, mesh, selector, frame, print)
            == (
                &other.name,
                &other.mesh,
                &other.selector,
                &other.frame,
                &other.print,
            )
    }
}

impl PartialEq for Pose {
    fn eq(&self, other: &Self) -> bool {
        let Pose {
            name,
            transform,
            down,
            component_transforms,
            goals,
            span: _,
        } = self;
        (name, transform, down, component_transforms, goals)
            == (
                &other.name,
                &other.transform,
                &other.down,
                &other.component_transforms,
                &other.goals,
            )
    }
}

impl PartialEq for Capsule {
    fn eq(&self, other: &Self) -> bool {
        let Capsule {
            name,
            component,
            from,
            to,
            radius,
            pinned,
            span: _,
        } = self;
        (name, component, from, to, radius, pinned)
            == (
                &other.name,
                &other.component,
                &other.from,
                &other.to,
                &other.radius,
                &other.pinned,
            )
    }
}

impl PartialEq for Optimize {
    fn eq(&self, other: &Self) -> bool {
        let Optimize {
            capsules,
            grid_cell,
            grid_cell_span: _,
            tolerance_degrees,
            seed,
            span: _,
        } = self;
        (capsules, grid_cell, tolerance_degrees, seed)
            == (
                &other.capsules,
                &other.grid_cell,
                &other.tolerance_degrees,
                &other.seed,
            )
    }
}

/// Where the build writes, resolved against the project file's folder.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// The binary glTF file.
    pub gltf: PathBuf,
    /// The JSON report.
    pub report: PathBuf,
    /// The optimizer's capsules as KDL `capsule` nodes, to commit, diff and check.
    pub solution: PathBuf,
    /// The folder of the binary STL files, one `<component>.stl` per component in its print
    /// orientation.
    pub stl: PathBuf,
    /// The PrusaSlicer project (3MF): every component on the bed, the pauses, the settings.
    pub prusa: PathBuf,
    /// The insertion sheet (markdown), its side-view pictures beside it.
    pub sheet: PathBuf,
}
