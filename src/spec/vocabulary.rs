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
}

const NO_ARGS: ArgsSpec = ArgsSpec {
    kind: ValueKind::Number,
    min: 0,
    max: 0,
};
const NAME_ARG: ArgsSpec = ArgsSpec {
    kind: ValueKind::String,
    min: 1,
    max: 1,
};
const VEC3_ARGS: ArgsSpec = ArgsSpec {
    kind: ValueKind::Number,
    min: 3,
    max: 3,
};

const fn prop(name: &'static str, kind: ValueKind) -> PropSpec {
    PropSpec {
        name,
        kind,
        required: false,
    }
}

const fn required(name: &'static str, kind: ValueKind) -> PropSpec {
    PropSpec {
        name,
        kind,
        required: true,
    }
}

const fn leaf(name: &'static str, args: ArgsSpec, props: &'static [PropSpec]) -> NodeSpec {
    NodeSpec {
        name,
        args,
        props,
        children: &[],
        repeatable: false,
    }
}

const fn repeated(node: NodeSpec) -> NodeSpec {
    NodeSpec {
        repeatable: true,
        ..node
    }
}

/// Length units a project can be written in.
pub const UNITS: &[&str] = &["mm", "cm", "m", "in"];
/// Axes that can point up.
pub const AXES: &[&str] = &["x", "y", "z"];

/// The steps of a rigid transform, in a pose or in a pose's component block.
const TRANSFORM_STEPS: [NodeSpec; 3] = [
    repeated(leaf("rotate", VEC3_ARGS, &[])),
    repeated(leaf("translate", VEC3_ARGS, &[])),
    repeated(leaf("pivot", VEC3_ARGS, &[])),
];

const CONTACT: PropSpec = prop("contact-tolerance", ValueKind::Positive);
const TOLERANCE: PropSpec = prop("tolerance", ValueKind::NonNegative);

const POSE_CHILDREN: &[NodeSpec] = &[
    TRANSFORM_STEPS[0],
    TRANSFORM_STEPS[1],
    TRANSFORM_STEPS[2],
    NodeSpec {
        name: "component",
        args: NAME_ARG,
        props: &[],
        children: &TRANSFORM_STEPS,
        repeatable: true,
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
        VEC3_ARGS,
        &[prop("component", ValueKind::String), TOLERANCE],
    )),
    repeated(leaf(
        "immerse",
        NO_ARGS,
        &[
            required("fluid-density", ValueKind::Positive),
            prop("min-distance", ValueKind::NonNegative),
            TOLERANCE,
            prop("mass-tolerance", ValueKind::NonNegative),
        ],
    )),
];

/// The top-level nodes of a project file.
pub const DOCUMENT: &[NodeSpec] = &[
    leaf(
        "units",
        ArgsSpec {
            kind: ValueKind::Enum(UNITS),
            min: 1,
            max: 1,
        },
        &[],
    ),
    leaf(
        "up",
        ArgsSpec {
            kind: ValueKind::Enum(AXES),
            min: 1,
            max: 1,
        },
        &[],
    ),
    leaf(
        "material",
        ArgsSpec {
            kind: ValueKind::String,
            min: 0,
            max: 1,
        },
        &[required("density", ValueKind::Positive)],
    ),
    NodeSpec {
        name: "ball",
        args: NO_ARGS,
        props: &[
            prop("density", ValueKind::Positive),
            prop("clearance", ValueKind::NonNegative),
            prop("min-angle", ValueKind::NonNegative),
        ],
        children: &[leaf(
            "diameters",
            ArgsSpec {
                kind: ValueKind::Positive,
                min: 1,
                max: usize::MAX,
            },
            &[],
        )],
        repeatable: false,
    },
    leaf(
        "infill",
        ArgsSpec {
            kind: ValueKind::Positive,
            min: 0,
            max: 1,
        },
        &[
            prop("min", ValueKind::Positive),
            prop("max", ValueKind::Positive),
        ],
    ),
    leaf(
        "wall",
        ArgsSpec {
            kind: ValueKind::NonNegative,
            min: 1,
            max: 1,
        },
        &[],
    ),
    repeated(leaf(
        "component",
        NAME_ARG,
        &[
            required("mesh", ValueKind::Path),
            prop("object", ValueKind::String),
            prop("node", ValueKind::String),
        ],
    )),
    NodeSpec {
        name: "pose",
        args: NAME_ARG,
        props: &[],
        children: POSE_CHILDREN,
        repeatable: true,
    },
    NodeSpec {
        name: "capsule",
        args: NAME_ARG,
        props: &[
            required("component", ValueKind::String),
            required("radius", ValueKind::Positive),
        ],
        children: &[leaf("from", VEC3_ARGS, &[]), leaf("to", VEC3_ARGS, &[])],
        repeatable: true,
    },
    NodeSpec {
        name: "output",
        args: NO_ARGS,
        props: &[],
        children: &[
            leaf(
                "gltf",
                ArgsSpec {
                    kind: ValueKind::Path,
                    min: 1,
                    max: 1,
                },
                &[],
            ),
            leaf(
                "report",
                ArgsSpec {
                    kind: ValueKind::Path,
                    min: 1,
                    max: 1,
                },
                &[],
            ),
        ],
        repeatable: false,
    },
];

/// Looks a node up among `siblings` by name.
pub fn find<'a>(siblings: &'a [NodeSpec], name: &str) -> Option<&'a NodeSpec> {
    siblings.iter().find(|spec| spec.name == name)
}

/// The closest known name to `unknown`, if one is close enough to be a likely typo.
pub fn suggest<'a>(unknown: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    known
        .into_iter()
        .map(|name| (strsim::jaro_winkler(unknown, name), name))
        .filter(|(score, _)| *score > 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, name)| name)
}
