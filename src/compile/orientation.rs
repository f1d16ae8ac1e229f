//! Each component's print orientation, once the meshes are loaded (the front end knows no
//! meshes): its `print` block's, or the one ballast chooses; and the [`PrintPlan`] of a design.

use nalgebra::{Point3, Rotation3, Vector3};

use crate::balance::up_to_print;
use crate::design::{Design, PlacedCapsule};
use crate::diagnostic::Problem;
use crate::fabrication::{
    choose, declared_down, declared_rotation, height, lay_out, plan_insertions, Bed, ComponentPlan,
    InsertionHook, InsertionRank, LayerGrid, Orientation, OrientationChoice, PrintFrame, PrintPlan,
    PrintSetup,
};
use crate::geometry::{mass_properties, ConvexHull, TriMesh};
use crate::spec::model::{PrintOrientation, Project};

/// The problem code of a `print { down }` on a component whose mesh has no volume.
pub const NO_HULL: &str = "ballast::component::no_hull";

/// The bed the layout is centred on, millimetres: the middle of a Prusa MK3's 250 × 210 mm bed.
pub const BED_CENTRE_MM: [f64; 2] = [125.0, 105.0];
/// The space between neighbouring components on the bed, millimetres.
pub const BED_GAP_MM: f64 = 10.0;

/// Every component's print orientation, in project order: declared by its `print` block, or
/// chosen ([`choose`]) from its convex hull with its centroid (the whole solid's, uniform), the
/// facets first ranked by how many of `known`'s capsules in the component can take their ball at
/// a pause, then by the fewest pauses ([`insertion_rank`]). `known` holds the capsules fixed
/// before any optimizing: the written ones without `optimize`, the pinned ones with it; a
/// component with none of them is ranked by its facets alone. An error at `down` when the mesh
/// has no hull; a component without a hull and without a declaration is printed with the
/// project's `up` axis up.
pub fn print_orientations(
    project: &Project,
    meshes: &[TriMesh],
    hulls: &[Option<ConvexHull>],
    known: &Design,
) -> (Vec<Orientation>, Vec<Problem>) {
    let grid = layer_grid(project);
    let mut problems = Vec::new();
    let orientations = project
        .components
        .iter()
        .zip(meshes.iter().zip(hulls))
        .enumerate()
        .map(|(index, (component, (mesh, hull)))| {
            let points = &mesh.positions;
            let centre = mass_properties(mesh).centroid;
            let Some(hull) = hull else {
                if let Some(PrintOrientation::Down(down)) = &component.print {
                    problems.push(
                        Problem::error(
                            NO_HULL,
                            format!(
                                "component `{}` has no volume, so `down` names no facet",
                                component.name.value
                            ),
                        )
                        .with_label(down.span, "this direction")
                        .with_help("write the print orientation as `rotate`, or fix the mesh"),
                    );
                }
                return flat(project, points, component.print.as_ref());
            };
            match &component.print {
                Some(PrintOrientation::Down(down)) => {
                    declared_down(hull, points, &centre, &down.value)
                        .unwrap_or_else(|| flat(project, points, None))
                }
                Some(PrintOrientation::Rotate(rotation)) => {
                    declared_rotation(hull, points, rotation.value.to_rotation_matrix())
                }
                None => {
                    let capsules = known.capsules_of(index);
                    let rank = |r: &Rotation3<f64>| insertion_rank(&capsules, mesh, r, &grid);
                    let rank: Option<InsertionHook> = (!capsules.is_empty()).then_some(&rank);
                    choose(hull, points, &centre, &-project.up.unit_vector(), rank)
                }
            }
        })
        .collect();
    (orientations, problems)
}

/// How well printing the component of mesh `mesh` turned by `to_print` lets its `capsules`
/// (indices into their design, as [`Design::capsules_of`] gives them) take their balls: how many
/// have a pause, and how many pauses they need.
pub fn insertion_rank(
    capsules: &[(usize, &PlacedCapsule)],
    mesh: &TriMesh,
    to_print: &Rotation3<f64>,
    grid: &LayerGrid,
) -> InsertionRank {
    let frame = PrintFrame::new(mesh, to_print.inverse() * Vector3::z());
    let (insertions, pauses) = plan_insertions(capsules, &frame, grid, &|_| String::new());
    InsertionRank {
        insertable: insertions.iter().filter(|i| i.pause.is_some()).count(),
        pauses: pauses.len(),
    }
}

/// The layer grid of `project`'s print settings.
pub fn layer_grid(project: &Project) -> LayerGrid {
    LayerGrid {
        first_layer_height: project.print.first_layer_height,
        layer_height: project.print.layer_height,
        pause_clearance: project.ball.pause_clearance,
    }
}

/// How `orientations` print `project`'s components: each one's print direction and the layer
/// grid (what [`PrintSetup::from_plan`] gives for the plan of these orientations).
pub fn print_setup(project: &Project, orientations: &[Orientation]) -> PrintSetup {
    let rotations: Vec<Rotation3<f64>> = orientations.iter().map(|o| o.to_print).collect();
    PrintSetup::from_rotations(&rotations, layer_grid(project))
}

/// The orientation of a part without a hull: the declared rotation, else the project's `up`
/// axis up.
fn flat(
    project: &Project,
    points: &[Point3<f64>],
    declared: Option<&PrintOrientation>,
) -> Orientation {
    let (to_print, choice) = match declared {
        Some(PrintOrientation::Rotate(rotation)) => (
            rotation.value.to_rotation_matrix(),
            OrientationChoice::Declared,
        ),
        _ => (
            up_to_print(project.up),
            OrientationChoice::Chosen {
                area: 0.0,
                reason: "the part has no volume: printed with the project's up axis up".to_string(),
            },
        ),
    };
    Orientation {
        to_print,
        down: to_print.inverse() * -Vector3::z(),
        choice,
        facet_area: None,
        height: height(points, &to_print),
    }
}

/// The print plan of `project`'s components in `orientations`, laid out on the bed
/// ([`BED_CENTRE_MM`], [`BED_GAP_MM`], in project units). Capsule insertions and pauses are left
/// empty.
pub fn print_plan(
    project: &Project,
    meshes: &[TriMesh],
    orientations: &[Orientation],
) -> PrintPlan {
    let mm = |value: f64| project.units.from_millimetres(value);
    let bed = Bed {
        centre: BED_CENTRE_MM.map(mm),
        gap: mm(BED_GAP_MM),
    };
    let points: Vec<&[Point3<f64>]> = meshes
        .iter()
        .map(|mesh| mesh.positions.as_slice())
        .collect();
    let rotations: Vec<_> = orientations.iter().map(|o| o.to_print).collect();
    let placed = lay_out(&bed, &points, &rotations);
    PrintPlan {
        first_layer_height: project.print.first_layer_height,
        layer_height: project.print.layer_height,
        pause_clearance: project.ball.pause_clearance,
        components: orientations
            .iter()
            .zip(placed)
            .enumerate()
            .map(|(component, (orientation, to_bed))| ComponentPlan {
                component,
                to_bed,
                down: orientation.down,
                up: orientation.to_print.inverse() * Vector3::z(),
                orientation: orientation.choice.clone(),
                capsules: Vec::new(),
                pauses: Vec::new(),
            })
            .collect(),
    }
}
