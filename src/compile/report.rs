//! The JSON report: the project's settings, its components and capsules, and what the design does
//! in every pose. `schema/report.schema.json` describes it; `docs/report.md` explains each field.

use std::path::{Component as PathPart, Path};

use serde::Serialize;

use super::{Compilation, DesignSource, GoalName, Optimization};
use crate::balance::{capsule_shell, PoseEvaluation};
use crate::design::Design;
use crate::fabrication::{ComponentPlan, Orientation, OrientationChoice};
use crate::spec::model::{MassModel, MeshFrame, Print, Project, Units};

/// Version of the report's layout; raised when a field changes meaning or disappears.
pub const REPORT_FORMAT: u32 = 1;

/// Everything `ballast check --json` prints and `ballast build` writes.
#[derive(Debug, Clone, Serialize)]
pub struct Report<'a> {
    /// [`REPORT_FORMAT`].
    pub format: u32,
    /// The ballast version that wrote it.
    pub ballast: &'static str,
    /// The project file's name.
    pub project: String,
    /// The length unit of every length in the report.
    pub units: &'static str,
    /// The up axis.
    pub up: [f64; 3],
    /// The print material.
    pub material: MaterialReport<'a>,
    /// The balls.
    pub ball: BallReport<'a>,
    /// Infill fraction evaluated.
    pub infill: f64,
    /// The mass model and the slicer settings it assumes.
    pub print: PrintReport,
    /// Minimum wall around capsules, project units.
    pub wall: f64,
    /// The components, in project order.
    pub components: Vec<ComponentReport>,
    /// The capsules, in design order.
    pub capsules: Vec<CapsuleReport>,
    /// Mass of every ball together, grams.
    pub ball_mass: f64,
    /// One per pose, in project order.
    pub poses: Vec<PoseReport<'a>>,
    /// Per component, in project order: when the balls go in.
    pub insertion: Vec<InsertionReport>,
    /// How many goals there are, and how many are met.
    pub goals: GoalCount,
    /// Whether every goal of every pose is met (the exit status is 0 exactly then).
    pub all_goals_met: bool,
    /// Where the capsules came from: `written` in the project file, the `solution` file, or
    /// `optimized` by this build.
    pub design: &'static str,
    /// What the optimizer did, when this build ran it; `null` otherwise.
    pub optimization: Option<&'a Optimization>,
    /// The goals the model without capsules meets and this design does not.
    pub solid_goals_lost: &'a [GoalName],
}

/// The print material.
#[derive(Debug, Clone, Serialize)]
pub struct MaterialReport<'a> {
    /// Its label.
    pub name: &'a str,
    /// g/cm³.
    pub density: f64,
}

/// The mass model and the print settings it assumed, lengths in project units.
#[derive(Debug, Clone, Serialize)]
pub struct PrintReport {
    /// `fdm` or `uniform`.
    pub model: MassModel,
    /// Perimeter loops.
    pub perimeters: u64,
    /// Extrusion width.
    pub extrusion_width: f64,
    /// Layer height.
    pub layer_height: f64,
    /// First layer height.
    pub first_layer_height: f64,
    /// Solid layers under top surfaces.
    pub top_solid_layers: u64,
    /// Solid layers over bottom surfaces.
    pub bottom_solid_layers: u64,
    /// Regions smaller than this are filled solid, square project units.
    pub solid_infill_below_area: f64,
    /// How far top and bottom solid layers reach into the sparse infill.
    pub surface_margin: f64,
    /// Horizontal thickness of the perimeters.
    pub perimeter_thickness: f64,
    /// Thickness of the solid shell modelled around every capsule (0 under `uniform`).
    pub capsule_shell: f64,
}

impl PrintReport {
    /// The report of `print`.
    pub fn new(print: &Print) -> PrintReport {
        PrintReport {
            model: print.model,
            perimeters: print.perimeters,
            extrusion_width: print.extrusion_width,
            layer_height: print.layer_height,
            first_layer_height: print.first_layer_height,
            top_solid_layers: print.top_solid_layers,
            bottom_solid_layers: print.bottom_solid_layers,
            solid_infill_below_area: print.solid_infill_below_area,
            surface_margin: print.surface_margin,
            perimeter_thickness: print.perimeter_thickness(),
            capsule_shell: capsule_shell(print),
        }
    }
}

/// The balls.
#[derive(Debug, Clone, Serialize)]
pub struct BallReport<'a> {
    /// g/cm³.
    pub density: f64,
    /// Gap between ball and capsule, project units.
    pub clearance: f64,
    /// Degrees from horizontal below which a ball's end is undetermined.
    pub min_angle: f64,
    /// Available ball diameters, project units; empty means any.
    pub diameters: &'a [f64],
}

/// One component.
#[derive(Debug, Clone, Serialize)]
pub struct ComponentReport {
    /// Its name.
    pub name: String,
    /// The mesh file, relative to the project file's folder when inside it.
    pub mesh: String,
    /// The object or node selected in the mesh file, if any.
    pub part: Option<String>,
    /// How the mesh file's coordinates were read into the rest frame.
    pub mesh_frame: MeshFrameReport,
    /// Vertex count after welding.
    pub vertices: usize,
    /// Triangle count.
    pub triangles: usize,
    /// Enclosed volume, cubic project units.
    pub volume: f64,
    /// Centroid of the enclosed volume, rest frame.
    pub centroid: [f64; 3],
    /// Volume printed solid before capsules are cut, cubic project units (0 under `uniform`).
    pub solid_volume: f64,
    /// Volume printed at the infill fraction before capsules are cut, cubic project units.
    pub sparse_volume: f64,
    /// How it is printed.
    pub print: ComponentPrintReport,
}

/// How a component's mesh coordinates became rest-frame coordinates.
#[derive(Debug, Clone, Serialize)]
pub struct MeshFrameReport {
    /// The unit of the mesh file's coordinates (`mm`, `cm`, `m`, `in`).
    pub units: &'static str,
    /// Where the unit came from: `written` (`mesh-units=`), `gltf` (the glTF specification's
    /// metres) or `project` (the project's `units`).
    pub units_from: &'static str,
    /// The mesh file's up axis (`x`, `y`, `z`).
    pub up: &'static str,
    /// Where the up axis came from, as for `units_from`.
    pub up_from: &'static str,
    /// The written `scale=` factor, 1 without it.
    pub scale: f64,
    /// Project units per mesh unit: the unit conversion times `scale`.
    pub factor: f64,
}

impl MeshFrameReport {
    /// The report of `frame` in a project in `units`.
    pub fn new(frame: &MeshFrame, units: Units) -> MeshFrameReport {
        MeshFrameReport {
            units: frame.units.keyword(),
            units_from: frame.units_from.keyword(),
            up: frame.up.keyword(),
            up_from: frame.up_from.keyword(),
            scale: frame.scale,
            factor: frame.factor(units),
        }
    }
}

/// How one component is printed: its orientation and its place on the bed.
#[derive(Debug, Clone, Serialize)]
pub struct ComponentPrintReport {
    /// `declared` (the component's `print` block) or `chosen` by ballast.
    pub choice: &'static str,
    /// The rest-frame unit direction that points to the bed.
    pub down: [f64; 3],
    /// Rest frame to print frame as a `print { rotate }` would write it: extrinsic X, Y, Z Euler
    /// angles, degrees.
    pub rotate: [f64; 3],
    /// Area of the hull facet on the bed, square project units; `None` when the part stands on
    /// an edge or a corner.
    pub facet_area: Option<f64>,
    /// Why ballast chose it; `None` when declared.
    pub reason: Option<String>,
    /// Height of the part on the bed, project units.
    pub height: f64,
    /// Where the rest frame's origin lands on the bed (the translation of the rest frame to bed
    /// frame transform), project units.
    pub bed_offset: [f64; 3],
}

impl ComponentPrintReport {
    /// The report of a component printed in `orientation`, placed on the bed by `plan`.
    pub fn new(orientation: &Orientation, plan: &ComponentPlan) -> ComponentPrintReport {
        let (x, y, z) = orientation.to_print.euler_angles();
        let tidy = |value: f64| value + 0.0;
        ComponentPrintReport {
            choice: match orientation.choice {
                OrientationChoice::Declared => "declared",
                OrientationChoice::Chosen { .. } => "chosen",
            },
            down: orientation.down.map(tidy).into(),
            rotate: [x, y, z].map(|a| tidy(a.to_degrees())),
            facet_area: orientation.facet_area,
            reason: match &orientation.choice {
                OrientationChoice::Declared => None,
                OrientationChoice::Chosen { reason, .. } => Some(reason.clone()),
            },
            height: orientation.height,
            bed_offset: plan.to_bed.translation.vector.map(tidy).into(),
        }
    }
}

/// One capsule.
#[derive(Debug, Clone, Serialize)]
pub struct CapsuleReport {
    /// Its name.
    pub name: String,
    /// The name of its component.
    pub component: String,
    /// One end of the axis, rest frame.
    pub from: [f64; 3],
    /// The other end, rest frame.
    pub to: [f64; 3],
    /// Radius of the void.
    pub radius: f64,
    /// Radius of its ball.
    pub ball_radius: f64,
    /// Diameter of its ball, project units.
    pub ball_diameter: f64,
    /// Diameter of its ball, millimetres (how balls are sold).
    pub ball_diameter_mm: f64,
    /// Mass of its ball, grams.
    pub ball_mass: f64,
    /// Gap between the ball and the capsule's wall, `radius − ball_radius`, project units.
    pub gap: f64,
    /// Volume of the void, cubic project units.
    pub volume: f64,
}

/// One pose: the physics evaluation plus a summary flag.
#[derive(Debug, Clone, Serialize)]
pub struct PoseReport<'a> {
    /// What the design does in the pose.
    #[serde(flatten)]
    pub evaluation: &'a PoseEvaluation,
    /// Whether every goal of this pose is met.
    pub all_goals_met: bool,
}

impl<'a> PoseReport<'a> {
    /// The report entry of `evaluation`.
    pub fn new(evaluation: &'a PoseEvaluation) -> PoseReport<'a> {
        PoseReport {
            evaluation,
            all_goals_met: evaluation.goals.iter().all(|goal| goal.met),
        }
    }
}

/// How the balls of one component go in.
#[derive(Debug, Clone, Serialize)]
pub struct InsertionReport {
    /// The component's name.
    pub component: String,
    /// The rest-frame direction it is printed along.
    pub up: [f64; 3],
    /// The pauses, lowest first.
    pub pauses: Vec<PauseReport>,
    /// Its capsules, in design order.
    pub capsules: Vec<CapsuleInsertionReport>,
}

/// One pause of the print.
#[derive(Debug, Clone, Serialize)]
pub struct PauseReport {
    /// Layers printed before it.
    pub layers_done: usize,
    /// Top of the last layer printed, above the bed.
    pub height: f64,
    /// Top of the first layer printed after it (where slicers key a pause).
    pub resume_height: f64,
    /// Names of the capsules whose balls go in, in design order.
    pub capsules: Vec<String>,
    /// What the printer shows.
    pub message: String,
}

/// When one capsule's ball can go in.
#[derive(Debug, Clone, Serialize)]
pub struct CapsuleInsertionReport {
    /// The capsule's name.
    pub capsule: String,
    /// Heights above the bed at which the print may pause for it, `[low, high]`, or `null`.
    pub window: Option<[f64; 2]>,
    /// Index into the component's `pauses`, or `null` when no layer boundary is in the window.
    pub pause: Option<usize>,
    /// Widest span of the void's ceiling a slicer bridges (overhang past 45°).
    pub ceiling_bridge: f64,
}

impl InsertionReport {
    /// The report entry of `plan`, names taken from `project` and `design`.
    fn new(plan: &ComponentPlan, project: &Project, design: &Design) -> InsertionReport {
        let name = |index: usize| {
            design
                .capsules
                .get(index)
                .map(|c| c.name.clone())
                .unwrap_or_default()
        };
        InsertionReport {
            component: project.component_name(plan.component).to_string(),
            up: (-plan.down).into(),
            pauses: plan
                .pauses
                .iter()
                .map(|pause| PauseReport {
                    layers_done: pause.layers_done,
                    height: pause.height,
                    resume_height: pause.resume_height,
                    capsules: pause.capsules.iter().map(|&c| name(c)).collect(),
                    message: pause.message.clone(),
                })
                .collect(),
            capsules: plan
                .capsules
                .iter()
                .map(|capsule| CapsuleInsertionReport {
                    capsule: name(capsule.capsule),
                    window: capsule.window.map(|(low, high)| [low, high]),
                    pause: capsule.pause,
                    ceiling_bridge: capsule.ceiling_bridge,
                })
                .collect(),
        }
    }
}

/// How many goals are met.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct GoalCount {
    /// Goals over all poses.
    pub total: usize,
    /// Of which met.
    pub met: usize,
}

impl<'a> Report<'a> {
    /// The report of `compilation`, whose project file is `project_path`.
    pub fn new(compilation: &'a Compilation, project_path: &Path) -> Report<'a> {
        let project = &compilation.project;
        let folder = project_path.parent().unwrap_or(Path::new(""));
        let components = project
            .components
            .iter()
            .zip(&compilation.meshes)
            .zip(&compilation.mass)
            .zip(&compilation.prints)
            .zip(
                compilation
                    .orientations
                    .iter()
                    .zip(&compilation.print_plan.components),
            )
            .map(
                |((((component, mesh), mass), print), (orientation, plan))| ComponentReport {
                    name: component.name.value.clone(),
                    mesh: relative_path(&component.mesh.value, folder),
                    part: component.selector.part_name().map(str::to_owned),
                    mesh_frame: MeshFrameReport::new(&component.frame, project.units),
                    vertices: mesh.positions.len(),
                    triangles: mesh.triangles.len(),
                    volume: mass.volume,
                    centroid: mass.centroid.coords.into(),
                    solid_volume: print.solid.volume,
                    sparse_volume: print.sparse.volume,
                    print: ComponentPrintReport::new(orientation, plan),
                },
            )
            .collect();
        let capsules = compilation
            .design
            .capsules
            .iter()
            .map(|capsule| CapsuleReport {
                name: capsule.name.clone(),
                component: project.component_name(capsule.component).to_string(),
                from: capsule.from.coords.into(),
                to: capsule.to.coords.into(),
                radius: capsule.radius,
                ball_radius: capsule.ball_radius,
                ball_diameter: 2.0 * capsule.ball_radius,
                ball_diameter_mm: 2.0 * capsule.ball_radius * project.units.in_metres() * 1e3,
                ball_mass: project.ball.density
                    * capsule.ball_volume()
                    * project.units.cubic_in_cm3(),
                gap: capsule.radius - capsule.ball_radius,
                volume: capsule.volume(),
            })
            .collect::<Vec<CapsuleReport>>();
        let ball_mass = capsules.iter().map(|c| c.ball_mass).sum();
        let poses = compilation.poses.iter().map(PoseReport::new).collect();
        let all_goals: Vec<bool> = compilation
            .poses
            .iter()
            .flat_map(|pose| pose.goals.iter().map(|goal| goal.met))
            .collect();
        Report {
            format: REPORT_FORMAT,
            ballast: env!("CARGO_PKG_VERSION"),
            project: project_path
                .file_name()
                .map(|name| name.to_string_lossy().into_owned())
                .unwrap_or_default(),
            units: project.units.keyword(),
            up: project.up.unit_vector().into(),
            material: MaterialReport {
                name: &project.material.name,
                density: project.material.density,
            },
            ball: BallReport {
                density: project.ball.density,
                clearance: project.ball.clearance,
                min_angle: project.ball.min_angle,
                diameters: &project.ball.diameters,
            },
            infill: compilation.design.infill,
            print: PrintReport::new(&project.print),
            wall: project.wall,
            components,
            capsules,
            ball_mass,
            poses,
            insertion: compilation
                .print_plan
                .components
                .iter()
                .map(|plan| InsertionReport::new(plan, project, &compilation.design))
                .collect(),
            goals: GoalCount {
                total: all_goals.len(),
                met: all_goals.iter().filter(|met| **met).count(),
            },
            all_goals_met: all_goals.iter().all(|met| *met),
            design: match compilation.source {
                DesignSource::Written => "written",
                DesignSource::SolutionFile(_) => "solution",
                DesignSource::Optimized => "optimized",
                DesignSource::Earlier => "earlier",
            },
            optimization: compilation.optimization.as_ref(),
            solid_goals_lost: &compilation.solid_goals_lost,
        }
    }

    /// The report as pretty-printed JSON with a final newline; the same bytes for the same input.
    pub fn to_json(&self) -> String {
        let mut text =
            serde_json::to_string_pretty(self).expect("a report holds only plain, finite data");
        text.push('\n');
        text
    }
}

/// `path` relative to `folder` with `/` separators when it lies inside it, else as given. Keeps
/// machine-specific absolute paths out of the report.
fn relative_path(path: &Path, folder: &Path) -> String {
    let shown = path.strip_prefix(folder).unwrap_or(path);
    shown
        .components()
        .filter(|part| !matches!(part, PathPart::CurDir))
        .map(|part| part.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}
