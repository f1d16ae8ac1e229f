//! The code of every problem the front end reports. Codes are stable: tools and tests match on
//! them, so a code is never reused for a different mistake.

/// The text is not valid KDL v2 (or is too large or too deeply nested to read).
pub const SYNTAX: &str = "ballast::syntax";
/// A project file that cannot be read (or is not UTF-8 text).
pub const FILE_UNREADABLE: &str = "ballast::file::unreadable";
/// A solution file that cannot be read (or is not UTF-8 text); scripts matched this code before
/// the project file had one, so it stays distinct.
pub const SOLUTION_UNREADABLE: &str = "ballast::solution::unreadable";
/// A project or solution file that is a folder, a device, a pipe or a socket.
pub const FILE_NOT_REGULAR: &str = "ballast::file::not_a_file";
/// A project or solution file larger than the most ballast reads.
pub const FILE_TOO_LARGE: &str = "ballast::file::too_large";
/// More problems than are kept: the rest were left out.
pub const TOO_MANY_PROBLEMS: &str = "ballast::too_many_problems";
/// A node the grammar does not have, or has only elsewhere.
pub const UNKNOWN_NODE: &str = "ballast::unknown_node";
/// A property the node does not take.
pub const UNKNOWN_PROPERTY: &str = "ballast::unknown_property";
/// Too few or too many arguments.
pub const ARGUMENT_COUNT: &str = "ballast::argument_count";
/// A value of the wrong type: a string where a number belongs, and so on.
pub const WRONG_TYPE: &str = "ballast::wrong_type";
/// A number that is not finite (`#inf`, `#nan`, or too large).
pub const NOT_FINITE: &str = "ballast::not_finite";
/// A number outside its allowed range.
pub const OUT_OF_RANGE: &str = "ballast::out_of_range";
/// A keyword the value does not accept (`units "feet"`).
pub const UNKNOWN_KEYWORD: &str = "ballast::unknown_keyword";
/// A required property is missing (or only one bound of a range is given).
pub const MISSING_PROPERTY: &str = "ballast::missing_property";
/// A required node is missing.
pub const MISSING_NODE: &str = "ballast::missing_node";
/// A node that may appear once appears again.
pub const DUPLICATE_NODE: &str = "ballast::duplicate_node";
/// A property written twice on one node.
pub const DUPLICATE_PROPERTY: &str = "ballast::duplicate_property";
/// A children block on a node that takes none.
pub const UNEXPECTED_CHILDREN: &str = "ballast::unexpected_children";
/// A type annotation on a node, which means nothing in a project file.
pub const ANNOTATION: &str = "ballast::annotation";
/// A unit annotation that is unknown or on a value that is not a length.
pub const UNIT: &str = "ballast::unit";
/// Two components, poses or capsules with one name, or one component moved twice in a pose.
pub const DUPLICATE_NAME: &str = "ballast::duplicate_name";
/// A reference to a component that does not exist.
pub const UNKNOWN_COMPONENT: &str = "ballast::unknown_component";
/// Two properties that exclude each other (`object=` and `node=`).
pub const CONFLICTING_PROPERTIES: &str = "ballast::conflicting_properties";
/// `mesh-units=` on a component whose mesh file states its own unit (3MF).
pub const MESH_UNITS_STATED: &str = "ballast::mesh_units_stated";
/// `down 0 0 0` in a pose: a direction of length zero.
pub const ZERO_DOWN: &str = "ballast::pose::zero_down";
/// `down` beside `rotate`, `translate` or `pivot` in one pose.
pub const DOWN_WITH_STEPS: &str = "ballast::pose::down_with_steps";
/// `down 0 0 0` in a component's `print` block.
pub const ZERO_PRINT_DOWN: &str = "ballast::component::zero_down";
/// `down` and `rotate` in one component's `print` block.
pub const PRINT_DOWN_WITH_ROTATE: &str = "ballast::component::down_with_rotate";
/// `optimize capsules=N` asks for fewer capsules than the project pins.
pub const TOO_FEW_CAPSULES: &str = "ballast::optimize::too_few_capsules";
/// `optimize` asks for more capsules, or more poses × capsules, than the optimizer takes.
pub const TOO_MANY_CAPSULES: &str = "ballast::optimize::too_many_capsules";
/// `optimize grid-cell=` gives a distance grid of more nodes than the optimizer takes.
pub const GRID_TOO_FINE: &str = "ballast::optimize::grid_too_fine";
/// A solution file's `infill` that the project does not leave open: outside the project's
/// `min`..`max`, or different from its fixed infill.
pub const SOLUTION_INFILL: &str = "ballast::solution::infill";
/// A G-code file given to `verify --gcode` has a move word whose value is not a number.
pub const GCODE_NUMBER: &str = "ballast::gcode::not_a_number";
/// A G-code move gives one axis twice (`E1e3` is `E1` then `e3`: G-code has no exponents).
pub const GCODE_REPEATED: &str = "ballast::gcode::repeated_word";
/// A G-code coordinate or filament length past what ballast reads (`docs/limits.md`).
pub const GCODE_RANGE: &str = "ballast::gcode::out_of_range";
/// A G-code `G2`/`G3` that is no arc ballast reads (no centre, another plane, full turns).
pub const GCODE_ARC: &str = "ballast::gcode::not_an_arc";
/// A G-code file with more pauses than ballast reads.
pub const GCODE_PAUSES: &str = "ballast::gcode::too_many_pauses";
/// A G-code object label or `M117` message longer than ballast reads.
pub const GCODE_TEXT: &str = "ballast::gcode::too_long";
/// `pauses`: a planned pause's resume height is no layer of the G-code file (its layers are
/// not the plan's), or the file extrudes nothing.
pub const PAUSES_NO_LAYER: &str = "ballast::pauses::no_layer";
/// `pauses`: the G-code file prints layers at a planned resume height more than once (objects
/// printed one at a time).
pub const PAUSES_REPEATED_HEIGHT: &str = "ballast::pauses::repeated_height";
/// A `rig` file that cannot be read as glTF.
pub const RIG_UNREADABLE: &str = "ballast::rig::unreadable";
/// A `rig`'s `nodes` list names a node the file does not have.
pub const RIG_UNKNOWN_NODE: &str = "ballast::rig::unknown_node";
/// A rig part that is not one node: a name several nodes share.
pub const RIG_AMBIGUOUS_NODE: &str = "ballast::rig::ambiguous_node";
/// A rig part without a mesh of its own, or a rig scene without mesh nodes.
pub const RIG_NO_MESH: &str = "ballast::rig::no_mesh";
/// A mesh node of a rig's scene without a name, which a component needs.
pub const RIG_UNNAMED_NODE: &str = "ballast::rig::unnamed_node";
/// A rig part that is a skinned mesh (out of scope: parts are rigid).
pub const RIG_SKINNED: &str = "ballast::rig::skinned";
/// A pose's `animation=` that the rig does not have.
pub const RIG_UNKNOWN_ANIMATION: &str = "ballast::rig::unknown_animation";
/// A pose's `scene=` that the rig does not have (or that several of its scenes share).
pub const RIG_UNKNOWN_SCENE: &str = "ballast::rig::unknown_scene";
/// A rig part that a pose's `scene=` does not hold.
pub const RIG_NOT_IN_SCENE: &str = "ballast::rig::not_in_scene";
/// A pose with both `animation=` and `scene=`.
pub const RIG_TWO_SOURCES: &str = "ballast::rig::two_sources";
/// A pose's `animation=` or `scene=` in a project without a `rig`.
pub const RIG_MISSING: &str = "ballast::rig::missing";
/// A pose's `time=` outside its animation's keys.
pub const RIG_TIME_OUTSIDE: &str = "ballast::rig::time_outside";
/// A pose from an animation with several keys and no `time=`.
pub const RIG_TIME_NEEDED: &str = "ballast::rig::time_needed";
/// An animation or scene that moves a rig part other than rigidly (scale, shear, mirror, morph
/// weights).
pub const RIG_NOT_RIGID: &str = "ballast::rig::not_rigid";
/// A rig's `part` block names no part of the rig.
pub const RIG_UNKNOWN_PART: &str = "ballast::rig::unknown_part";
