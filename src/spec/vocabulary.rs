//! The project-file grammar as data: every node, its arguments, its properties and its children.
//!
//! The parser consults this table to reject unknown names (with a "did you mean") and the schema
//! test compares it with `schema/ballast.kdl`, so the documented format and the accepted format
//! cannot drift apart.

/// The type of one argument or property value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueKind {
    /// Any string.
    String,
    /// A string naming a file, relative to the project file.
    Path,
    /// A finite number.
    Number,
    /// A finite number greater than zero.
    Positive,
    /// A finite number greater than or equal to zero.
    NonNegative,
    /// A whole number, zero or more, written without a decimal point (at most `u64::MAX`).
    Count,
    /// `#true` or `#false`.
    Bool,
    /// One of the listed strings.
    Enum(&'static [&'static str]),
}

/// How many positional arguments a node takes and of which kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArgsSpec {
    /// The kind of every argument.
    pub kind: ValueKind,
    /// The fewest arguments accepted.
    pub min: usize,
    /// The most arguments accepted (`usize::MAX` for no limit).
    pub max: usize,
    /// Whether every argument is a length: in the project's units, or in the unit its annotation
    /// names (`(mm)2`).
    pub length: bool,
}

/// One property (`key=value`) of a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PropSpec {
    /// The property's name.
    pub name: &'static str,
    /// The type of its value.
    pub kind: ValueKind,
    /// Whether the node is invalid without it.
    pub required: bool,
    /// Whether the value is a length: in the project's units, or in the unit its annotation names
    /// (`radius=(mm)2`).
    pub length: bool,
}

/// One node of the grammar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeSpec {
    /// The node's name.
    pub name: &'static str,
    /// Its positional arguments.
    pub args: ArgsSpec,
    /// Its properties.
    pub props: &'static [PropSpec],
    /// The nodes allowed in its children block.
    pub children: &'static [NodeSpec],
    /// Whether the node may appear more than once among its siblings.
    pub repeatable: bool,
    /// Whether its parent (or the document) is invalid without it.
    pub required: bool,
}

const fn args(kind: ValueKind, min: usize, max: usize) -> ArgsSpec {
    ArgsSpec {
        kind,
        min,
        max,
        length: false,
    }
}

const fn length_args(kind: ValueKind, min: usize, max: usize) -> ArgsSpec {
    ArgsSpec {
        length: true,
        ..args(kind, min, max)
    }
}

const NO_ARGS: ArgsSpec = args(ValueKind::Number, 0, 0);
const NAME_ARG: ArgsSpec = args(ValueKind::String, 1, 1);
const PATH_ARG: ArgsSpec = args(ValueKind::Path, 1, 1);
/// Three angles in degrees.
const ANGLES: ArgsSpec = args(ValueKind::Number, 3, 3);
/// The three components of a direction, without unit.
const DIRECTION: ArgsSpec = args(ValueKind::Number, 3, 3);
/// The three coordinates of a point or a displacement.
const POINT: ArgsSpec = length_args(ValueKind::Number, 3, 3);

const fn prop(name: &'static str, kind: ValueKind) -> PropSpec {
    PropSpec {
        name,
        kind,
        required: false,
        length: false,
    }
}

const fn length_prop(name: &'static str, kind: ValueKind) -> PropSpec {
    PropSpec {
        length: true,
        ..prop(name, kind)
    }
}

const fn required(prop: PropSpec) -> PropSpec {
    PropSpec {
        required: true,
        ..prop
    }
}

const fn leaf(name: &'static str, args: ArgsSpec, props: &'static [PropSpec]) -> NodeSpec {
    NodeSpec {
        name,
        args,
        props,
        children: &[],
        repeatable: false,
        required: false,
    }
}

const fn repeated(node: NodeSpec) -> NodeSpec {
    NodeSpec {
        repeatable: true,
        ..node
    }
}

const fn mandatory(node: NodeSpec) -> NodeSpec {
    NodeSpec {
        required: true,
        ..node
    }
}

/// Length units a project can be written in.
pub const UNITS: &[&str] = &["mm", "cm", "m", "in"];
/// Axes that can point up.
pub const AXES: &[&str] = &["x", "y", "z"];

/// The mass models a `print` node can name.
pub const MASS_MODELS: &[&str] = &["fdm", "uniform"];

/// The steps of a rigid transform, in a pose or in a pose's component block.
const TRANSFORM_STEPS: [NodeSpec; 3] = [
    repeated(leaf("rotate", ANGLES, &[])),
    repeated(leaf("translate", POINT, &[])),
    repeated(leaf("pivot", POINT, &[])),
];

const CONTACT: PropSpec = length_prop("contact-tolerance", ValueKind::Positive);
const TOLERANCE: PropSpec = prop("tolerance", ValueKind::NonNegative);
const UNIQUE: PropSpec = prop("unique", ValueKind::Bool);

/// The `capsule` node, in a project file and in a solution file.
const CAPSULE: NodeSpec = NodeSpec {
    name: "capsule",
    args: NAME_ARG,
    props: &[
        required(prop("component", ValueKind::String)),
        required(length_prop("radius", ValueKind::Positive)),
        prop("pinned", ValueKind::Bool),
    ],
    children: &[
        mandatory(leaf("from", POINT, &[])),
        mandatory(leaf("to", POINT, &[])),
    ],
    repeatable: true,
    required: false,
};

const POSE_CHILDREN: &[NodeSpec] = &[
    TRANSFORM_STEPS[0],
    TRANSFORM_STEPS[1],
    TRANSFORM_STEPS[2],
    leaf("down", DIRECTION, &[]),
    NodeSpec {
        name: "component",
        args: NAME_ARG,
        props: &[],
        children: &TRANSFORM_STEPS,
        repeatable: true,
        required: false,
    },
    repeated(leaf(
        "stand",
        NO_ARGS,
        &[prop("margin", ValueKind::NonNegative), CONTACT],
    )),
    repeated(leaf(
        "imbalance",
        NO_ARGS,
        &[prop("margin", ValueKind::NonNegative), CONTACT],
    )),
    repeated(leaf(
        "suspend",
        POINT,
        &[prop("component", ValueKind::String), TOLERANCE, UNIQUE],
    )),
    repeated(leaf(
        "immerse",
        NO_ARGS,
        &[
            required(prop("fluid-density", ValueKind::Positive)),
            length_prop("min-distance", ValueKind::NonNegative),
            TOLERANCE,
            prop("mass-tolerance", ValueKind::NonNegative),
            UNIQUE,
        ],
    )),
];

/// A component's (or rig part's) `print` block: how it lies on the print bed.
const PRINT_ORIENTATION: NodeSpec = NodeSpec {
    name: "print",
    args: NO_ARGS,
    props: &[],
    children: &[leaf("down", DIRECTION, &[]), leaf("rotate", ANGLES, &[])],
    repeatable: false,
    required: false,
};

/// The top-level nodes of a project file.
pub const DOCUMENT: &[NodeSpec] = &[
    leaf("units", args(ValueKind::Enum(UNITS), 1, 1), &[]),
    leaf("up", args(ValueKind::Enum(AXES), 1, 1), &[]),
    leaf(
        "material",
        args(ValueKind::String, 0, 1),
        &[required(prop("density", ValueKind::Positive))],
    ),
    NodeSpec {
        name: "ball",
        args: NO_ARGS,
        props: &[
            prop("density", ValueKind::Positive),
            length_prop("clearance", ValueKind::NonNegative),
            length_prop("pause-clearance", ValueKind::NonNegative),
            prop("min-angle", ValueKind::NonNegative),
            prop("any-size", ValueKind::Bool),
        ],
        children: &[leaf(
            "diameters",
            length_args(ValueKind::Positive, 1, usize::MAX),
            &[],
        )],
        repeatable: false,
        required: false,
    },
    leaf(
        "infill",
        args(ValueKind::Positive, 0, 1),
        &[
            prop("min", ValueKind::Positive),
            prop("max", ValueKind::Positive),
        ],
    ),
    leaf("wall", length_args(ValueKind::NonNegative, 1, 1), &[]),
    leaf(
        "print",
        NO_ARGS,
        &[
            prop("model", ValueKind::Enum(MASS_MODELS)),
            prop("perimeters", ValueKind::Count),
            length_prop("extrusion-width", ValueKind::Positive),
            length_prop("layer-height", ValueKind::Positive),
            length_prop("first-layer-height", ValueKind::Positive),
            prop("top-solid-layers", ValueKind::Count),
            prop("bottom-solid-layers", ValueKind::Count),
            prop("solid-infill-below-area", ValueKind::NonNegative),
        ],
    ),
    NodeSpec {
        name: "component",
        args: NAME_ARG,
        props: &[
            required(prop("mesh", ValueKind::Path)),
            prop("object", ValueKind::String),
            prop("node", ValueKind::String),
            prop("mesh-units", ValueKind::Enum(UNITS)),
            prop("mesh-up", ValueKind::Enum(AXES)),
            prop("scale", ValueKind::Positive),
        ],
        children: &[PRINT_ORIENTATION],
        repeatable: true,
        required: true,
    },
    NodeSpec {
        name: "rig",
        args: PATH_ARG,
        props: &[
            prop("mesh-units", ValueKind::Enum(UNITS)),
            prop("mesh-up", ValueKind::Enum(AXES)),
            prop("scale", ValueKind::Positive),
        ],
        children: &[
            leaf("nodes", args(ValueKind::String, 1, usize::MAX), &[]),
            NodeSpec {
                name: "part",
                args: NAME_ARG,
                props: &[],
                children: &[PRINT_ORIENTATION],
                repeatable: true,
                required: false,
            },
        ],
        repeatable: false,
        required: false,
    },
    NodeSpec {
        name: "pose",
        args: NAME_ARG,
        props: &[
            prop("animation", ValueKind::String),
            prop("time", ValueKind::NonNegative),
            prop("scene", ValueKind::String),
        ],
        children: POSE_CHILDREN,
        repeatable: true,
        required: true,
    },
    CAPSULE,
    leaf(
        "optimize",
        NO_ARGS,
        &[
            prop("capsules", ValueKind::Count),
            length_prop("grid-cell", ValueKind::Positive),
            prop("tolerance", ValueKind::NonNegative),
            prop("seed", ValueKind::Count),
        ],
    ),
    NodeSpec {
        name: "output",
        args: NO_ARGS,
        props: &[],
        children: &[
            leaf("gltf", PATH_ARG, &[]),
            leaf("report", PATH_ARG, &[]),
            leaf("solution", PATH_ARG, &[]),
            leaf("stl", PATH_ARG, &[]),
            leaf("prusa", PATH_ARG, &[]),
            leaf("sheet", PATH_ARG, &[]),
        ],
        repeatable: false,
        required: false,
    },
];

/// The top-level nodes of a solution file: the optimizer's capsules, and the infill it chose when
/// the project gives a range.
pub const SOLUTION: &[NodeSpec] = &[
    CAPSULE,
    leaf("infill", args(ValueKind::Positive, 1, 1), &[]),
];

/// Looks a node up among `siblings` by name.
pub fn find<'a>(siblings: &'a [NodeSpec], name: &str) -> Option<&'a NodeSpec> {
    siblings.iter().find(|spec| spec.name == name)
}

/// The closest known name to `unknown`, if one is close enough to be a likely typo.
pub fn suggest<'a>(unknown: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    // Jaro-Winkler finds typos in long names; an edit distance catches short ones ("amr" for
    // "arm"), where Jaro-Winkler's matching window is too small to see a transposition.
    // Below three letters every name is one edit away, so edits say nothing there.
    let length = unknown.chars().count();
    let allowed_edits = if length >= 3 { 1.max(length / 4) } else { 0 };
    known
        .into_iter()
        .filter_map(|name| {
            let edits = strsim::damerau_levenshtein(unknown, name);
            let similarity = strsim::jaro_winkler(unknown, name);
            (similarity > 0.8 || edits <= allowed_edits).then_some((edits, similarity, name))
        })
        .min_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)))
        .map(|(_, _, name)| name)
}

/// Where a node called `name` may be written in a project file: for each place, the names of the
/// nodes from the top level down to the one whose children block accepts it (empty for the top
/// level itself).
pub fn places(name: &str) -> Vec<Vec<&'static str>> {
    places_in(DOCUMENT, name)
}

/// Where a node called `name` may be written in a document whose top-level nodes are `root`, as
/// for [`places`].
pub fn places_in(root: &'static [NodeSpec], name: &str) -> Vec<Vec<&'static str>> {
    fn visit(
        siblings: &'static [NodeSpec],
        path: &mut Vec<&'static str>,
        name: &str,
        found: &mut Vec<Vec<&'static str>>,
    ) {
        if find(siblings, name).is_some() {
            found.push(path.clone());
        }
        for spec in siblings {
            path.push(spec.name);
            visit(spec.children, path, name, found);
            path.pop();
        }
    }
    let mut found = Vec::new();
    visit(root, &mut Vec::new(), name, &mut found);
    found
}
