//! The optimizer stage of the pipeline: distance grids and skeletons per component, seeds, the
//! heuristic, the choice of a capsule count, and the chosen design rounded for the solution file.

use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use super::workspace::{Stage, Workspace};
use crate::design::Design;
use crate::fabrication::PrintSetup;
use crate::geometry::PrintVolumes;
use crate::geometry::{DistanceGrid, Skeleton, TriMesh};
use crate::objective::{GridInterior, Parameters};
pub use crate::optimize::length_decimals;
use crate::optimize::{
    capsule_radius, choose, content_hash, default_cell, explain_conflicts, grid_scale, rank,
    run_heuristic, skeleton_seeds, Candidate, Conflict, GoalRef, GridKey, Method, Outcome, Problem,
    Ranking, SeedSite, StartCapsule,
};
use crate::spec::model::{Optimize, Project};

/// How `build` runs the optimizer, beyond what the project file says.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OptimizeOptions {
    /// The local solver.
    pub method: Method,
    /// The capsule count wanted, overriding the project's `optimize capsules=`.
    pub capsules: Option<usize>,
    /// Random starts per capsule count to rank the heuristic's result against (0: none).
    pub exhaustive: usize,
    /// Start from this earlier design instead of the skeleton seeds, when the meshes are the
    /// ones it was made for (watch mode, after an edit that left the geometry alone).
    pub warm_start: Option<WarmStart>,
}

/// An earlier design of the same project and the meshes it was made for.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// The [`content_hash`] of each component's mesh, in component order.
    pub meshes: Vec<u64>,
    /// The capsules and infill.
    pub design: Design,
}

impl WarmStart {
    /// `design`, made for `meshes`.
    pub fn new(meshes: &[TriMesh], design: Design) -> WarmStart {
        WarmStart {
            meshes: meshes.iter().map(content_hash).collect(),
            design,
        }
    }

    /// Whether it was made for exactly these meshes.
    pub fn fits(&self, meshes: &[TriMesh]) -> bool {
        self.meshes.len() == meshes.len()
            && self
                .meshes
                .iter()
                .zip(meshes)
                .all(|(&h, m)| h == content_hash(m))
    }
}

/// What the optimizer did: every capsule count tried and which one was chosen.
#[derive(Debug, Clone, Serialize)]
pub struct Optimization {
    /// The capsule count asked for, if any.
    pub requested: Option<usize>,
    /// Capsules in the chosen design.
    pub chosen: usize,
    /// Whether the chosen design meets every goal.
    pub meets_goals: bool,
    /// The tolerance of the choice, degrees.
    pub tolerance: f64,
    /// Whether the heuristic started from the previous build's design (watch mode) rather than
    /// from the skeleton seeds.
    pub warm_started: bool,
    /// Every capsule count the heuristic tried, most capsules first.
    pub candidates: Vec<CandidateReport>,
    /// Every skeleton segment's midpoint and whether a capsule was seeded there.
    pub seeds: Vec<SeedReport>,
    /// Where the heuristic ranks among random starts, per capsule count (empty unless asked).
    pub exhaustive: Vec<Ranking>,
    /// When the chosen design misses some goal: the goals that cannot be met even alone, and the
    /// pairs that cannot be met together.
    pub conflicts: Vec<ConflictReport>,
    /// Wall-clock seconds per stage. Not deterministic, so never written to a file.
    #[serde(skip)]
    pub timings: Timings,
}

/// Wall-clock seconds of each optimizer stage.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timings {
    /// Distance grids and skeletons.
    pub precompute: f64,
    /// The heuristic, all rounds.
    pub heuristic: f64,
    /// Exhaustive search.
    pub exhaustive: f64,
    /// Explaining conflicts.
    pub conflicts: f64,
}

/// Goals the optimizer cannot meet: one goal that is out of reach even alone, or two that can each
/// be met but not together.
#[derive(Debug, Clone, Serialize)]
pub struct ConflictReport {
    /// The goals, each as `pose name` and index within the pose.
    pub goals: Vec<GoalName>,
    /// How short the best design for just these goals falls, degrees of the smooth objective.
    pub shortfall: f64,
}

/// A goal, named by its pose.
#[derive(Debug, Clone, Serialize)]
pub struct GoalName {
    /// The pose's name.
    pub pose: String,
    /// The goal's index within the pose, from 0.
    pub goal: usize,
    /// The goal's kind: `stand`, `imbalance`, `suspend` or `immerse`.
    pub kind: &'static str,
}

/// One capsule count the heuristic tried.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateReport {
    /// Number of capsules.
    pub capsules: usize,
    /// The smooth objective `f` reached, degrees (at most 0 when every goal is met; lower is
    /// better).
    pub objective: f64,
    /// The smallest tilt margin over every `stand` goal, degrees, when there are stand goals.
    pub worst_tilt_margin: Option<f64>,
    /// Whether every goal is met and every capsule can be printed.
    pub meets_goals: bool,
    /// Whether every capsule can be printed where it is: the fabrication checks pass, every
    /// ball insertable at a pause in its component's print orientation.
    pub printable: bool,
    /// Wall-clock seconds. Not deterministic, so never written to a file.
    #[serde(skip)]
    pub seconds: f64,
}

/// One skeleton segment's midpoint.
#[derive(Debug, Clone, Serialize)]
pub struct SeedReport {
    /// The component whose skeleton it is on.
    pub component: String,
    /// The midpoint, rest frame of the component.
    pub midpoint: [f64; 3],
    /// Distance to the component's surface, project units (positive inside).
    pub depth: f64,
    /// Whether a capsule was seeded there.
    pub seeded: bool,
}

/// What the heuristic starts from: the interior distance of every component and the start
/// capsules.
pub struct Preparation {
    /// One distance grid per component, in component order.
    pub interior: Arc<GridInterior>,
    /// The written capsules (pinned or not), then, unless some written capsule is unpinned, one
    /// seed per skeleton segment deep enough inside its component. From a warm start: the pinned
    /// written capsules, then the earlier design's other capsules.
    pub seeds: Vec<StartCapsule>,
    /// Every skeleton segment's midpoint and whether it was seeded (empty when the written
    /// capsules or a warm start are the seeds).
    pub sites: Vec<SeedSite>,
}

/// The precomputation of the optimizer: distance grids (from the workspace's cache when it holds
/// them, at the project's `grid-cell` or [`default_cell`]), then the seeds: from `warm` when
/// given, else from skeletons thinned on the grids. `None` when the workspace was cancelled.
pub fn prepare(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    workspace: &mut Workspace,
    warm: Option<&Design>,
) -> Option<Preparation> {
    let parameters = Parameters::for_project(project);
    // One key per mesh: making it reads every coordinate.
    let keys: Vec<GridKey> = meshes
        .iter()
        .map(|mesh| {
            let cell = settings
                .grid_cell
                .unwrap_or_else(|| default_cell(mesh, parameters.min_radius));
            GridKey::new(mesh, cell)
        })
        .collect();
    let mut grids = Vec::with_capacity(meshes.len());
    for (index, (mesh, &key)) in meshes.iter().zip(&keys).enumerate() {
        if !workspace.cache.recall(mesh, key) {
            workspace.report(Stage::Grid {
                component: project.component_name(index).to_string(),
                nodes: DistanceGrid::node_count(mesh, key.cell()),
            });
        }
        grids.push(workspace.cache.grid(mesh, key, &workspace.cancel)?);
    }
    let interior = Arc::new(GridInterior { grids });
    let mut seeds = written_capsules(project);
    if let Some(design) = warm {
        seeds.retain(|c| c.pinned);
        seeds.extend(warm_capsules(design, &seeds));
    }
    if warm.is_some() || seeds.iter().any(|c| !c.pinned) {
        return Some(Preparation {
            interior,
            seeds,
            sites: Vec::new(),
        });
    }
    let mut skeletons: Vec<Arc<Skeleton>> = Vec::with_capacity(meshes.len());
    for (index, (mesh, &key)) in meshes.iter().zip(&keys).enumerate() {
        if !workspace.cache.holds_skeleton(key) {
            workspace.report(Stage::Skeleton {
                component: project.component_name(index).to_string(),
            });
        }
        skeletons.push(workspace.cache.skeleton(mesh, key, &workspace.cancel)?);
    }
    let (starts, sites) = skeleton_seeds(
        &skeletons,
        interior.as_ref(),
        parameters.min_radius,
        project.wall,
    );
    seeds.extend(starts);
    Some(Preparation {
        interior,
        seeds,
        sites,
    })
}

/// Runs the optimizer on `project` (which has an `optimize` node) and returns the chosen design,
/// rounded, with what the optimizer did; `None` when the workspace was cancelled.
///
/// With a warm start that fits the meshes, the heuristic starts from that design; when what it
/// reaches misses a goal, the full search from the skeleton seeds runs too and the better choice
/// is kept.
pub fn optimize_design(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    prints: &[PrintVolumes],
    print: &PrintSetup,
    options: &OptimizeOptions,
    workspace: &mut Workspace,
) -> Option<(Design, Optimization)> {
    let warm = options
        .warm_start
        .as_ref()
        .filter(|warm| warm.fits(meshes))
        .map(|warm| &warm.design);
    if let Some(design) = warm {
        let optimized = optimize_from(
            project,
            settings,
            meshes,
            prints,
            print,
            options,
            workspace,
            Some(design),
        )?;
        if optimized.1.meets_goals {
            return Some(optimized);
        }
    }
    optimize_from(
        project, settings, meshes, prints, print, options, workspace, None,
    )
}

/// [`optimize_design`] from the seeds [`prepare`] gives for `warm`.
#[allow(clippy::too_many_arguments)]
fn optimize_from(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    prints: &[PrintVolumes],
    print: &PrintSetup,
    options: &OptimizeOptions,
    workspace: &mut Workspace,
    warm: Option<&Design>,
) -> Option<(Design, Optimization)> {
    let clock = Instant::now();
    let Preparation {
        interior,
        seeds,
        sites,
    } = prepare(project, settings, meshes, workspace, warm)?;
    let precompute = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let problem = Problem::new(
        project,
        meshes,
        prints,
        print.clone(),
        interior.clone(),
        options.method,
    )
    .with_cancel(workspace.cancel.clone());
    let requested = options.capsules.or(settings.capsules);
    let mut candidates = run_heuristic(&problem, &seeds, requested, &|capsules| {
        workspace.report(Stage::Round { capsules })
    });
    if problem.is_cancelled() || candidates.is_empty() {
        return None;
    }
    // Every candidate is judged as the solution file would hold it, so the table, the choice
    // and `check` agree even for a design on the edge of a goal.
    for candidate in &mut candidates {
        candidate.outcome = rounded(&problem, &candidate.outcome, meshes);
    }
    let heuristic = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let exhaustive = if options.exhaustive > 0 {
        workspace.report(Stage::Exhaustive {
            starts: options.exhaustive,
        });
        rank(
            &problem,
            interior.as_ref(),
            &seeds,
            &candidates,
            options.exhaustive,
            settings.seed,
        )
    } else {
        Vec::new()
    };
    let exhaustive_seconds = clock.elapsed().as_secs_f64();

    let chosen = choose(&candidates, requested, settings.tolerance_degrees);
    let outcome = candidates[chosen].outcome.clone();
    let design = named(project, outcome.design.clone());

    let clock = Instant::now();
    let conflicts = if outcome.meets_goals {
        Vec::new()
    } else {
        workspace.report(Stage::Conflicts);
        let unmet: Vec<GoalRef> = outcome
            .poses
            .iter()
            .enumerate()
            .flat_map(|(pose, p)| {
                p.goals
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| !g.met)
                    .map(move |(goal, _)| GoalRef { pose, goal })
            })
            .collect();
        let starts = [seeds_for(&seeds, &candidates[chosen]), seeds.clone()];
        explain_conflicts(
            project,
            meshes,
            prints,
            print,
            &interior,
            &starts,
            &unmet,
            &workspace.cancel,
        )
        .iter()
        .map(|c| conflict_report(project, c))
        .collect()
    };
    if problem.is_cancelled() {
        return None;
    }
    let conflicts_seconds = clock.elapsed().as_secs_f64();
    let optimization = Optimization {
        requested,
        chosen: design.capsules.len(),
        meets_goals: outcome.meets_goals,
        tolerance: settings.tolerance_degrees,
        warm_started: warm.is_some(),
        candidates: candidates.iter().map(candidate_report).collect(),
        seeds: sites
            .iter()
            .map(|site| seed_report(project, site))
            .collect(),
        exhaustive,
        conflicts,
        timings: Timings {
            precompute,
            heuristic,
            exhaustive: exhaustive_seconds,
            conflicts: conflicts_seconds,
        },
    };
    Some((design, optimization))
}

/// The capsules of the project file as start capsules, named and pinned as written.
fn written_capsules(project: &Project) -> Vec<StartCapsule> {
    project
        .capsules
        .iter()
        .map(|c| StartCapsule {
            component: c.component.value,
            from: c.from,
            to: c.to,
            radius: c.radius,
            pinned: c.pinned,
            name: Some(c.name.value.clone()),
        })
        .collect()
}

/// The capsules of an earlier design to start from, leaving out those named like a pinned
/// written capsule (`pinned`: the written one is used as written).
fn warm_capsules(design: &Design, pinned: &[StartCapsule]) -> Vec<StartCapsule> {
    design
        .capsules
        .iter()
        .filter(|c| {
            !pinned
                .iter()
                .any(|p| p.name.as_deref() == Some(c.name.as_str()))
        })
        .map(|c| StartCapsule {
            component: c.component,
            from: c.from,
            to: c.to,
            radius: c.radius,
            pinned: false,
            name: Some(c.name.clone()),
        })
        .collect()
}

/// `outcome`'s design with every length rounded to [`length_decimals`], judged again. Ends move
/// to the nearest step. With any ball size, each unpinned radius shrinks by at least one step, so
/// rounding cannot bring a capsule closer to the surface or to another capsule than it was; with
/// stock balls the optimizer's radius, a ball plus the clearance, is already on the grid and is
/// kept.
fn rounded(problem: &Problem, outcome: &Outcome, meshes: &[TriMesh]) -> Outcome {
    // k / 10^d, both exact, is the double the solution file's decimal `k·10^-d` reads back as;
    // k · 10^-d is not always (−1503 · 0.01 = −15.030000000000001).
    let scale = grid_scale(length_decimals(meshes));
    let round = |v: f64| (v * scale).round() / scale;
    let ball = &problem.project().ball;
    let written = &problem.project().capsules;
    let mut design = outcome.design.clone();
    for capsule in &mut design.capsules {
        let pinned = written
            .iter()
            .any(|w| w.pinned && w.name.value == capsule.name);
        if pinned {
            continue;
        }
        capsule.from = capsule.from.map(round);
        capsule.to = capsule.to.map(round);
        let stock = ball
            .radius_for(capsule.radius)
            .filter(|_| ball.is_listed())
            .map(|b| (capsule_radius(ball, b, scale), b));
        match stock {
            Some((radius, b)) => {
                capsule.radius = radius;
                capsule.ball_radius = b;
            }
            None => {
                capsule.radius = ((capsule.radius * scale).floor() - 1.0) / scale;
                if let Some(b) = ball.radius_for(capsule.radius) {
                    capsule.ball_radius = b;
                }
            }
        }
    }
    if problem.project().infill.range.is_some() {
        design.infill = (design.infill * 1e6).round() / 1e6;
    }
    let mut judged = problem.judge(design);
    judged.value = outcome.value;
    judged
}

/// Names the capsules the optimizer seeded (`"<component> 1"`, `"<component> 2"`, … in design
/// order), skipping names already taken.
fn named(project: &Project, mut design: Design) -> Design {
    let written: Vec<&str> = project
        .capsules
        .iter()
        .map(|c| c.name.value.as_str())
        .collect();
    let mut taken: Vec<String> = design
        .capsules
        .iter()
        .filter(|c| written.contains(&c.name.as_str()))
        .map(|c| c.name.clone())
        .collect();
    for capsule in &mut design.capsules {
        if written.contains(&capsule.name.as_str()) {
            continue;
        }
        let component = project.component_name(capsule.component);
        let name = (1..)
            .map(|k| format!("{component} {k}"))
            .find(|name| !taken.contains(name))
            .unwrap_or_default();
        taken.push(name.clone());
        capsule.name = name;
    }
    design
}

/// The start for explaining conflicts: the chosen candidate's capsules where the heuristic left
/// them, or the seeds when it has none.
fn seeds_for(seeds: &[StartCapsule], candidate: &Candidate) -> Vec<StartCapsule> {
    if candidate.outcome.design.capsules.is_empty() {
        return seeds.to_vec();
    }
    candidate
        .outcome
        .design
        .capsules
        .iter()
        .map(|c| StartCapsule {
            component: c.component,
            from: c.from,
            to: c.to,
            radius: c.radius,
            pinned: seeds
                .iter()
                .any(|s| s.pinned && s.name.as_deref() == Some(c.name.as_str())),
            name: Some(c.name.clone()),
        })
        .collect()
}

fn conflict_report(project: &Project, conflict: &Conflict) -> ConflictReport {
    ConflictReport {
        goals: conflict
            .goals
            .iter()
            .map(|g| {
                let pose = &project.poses[g.pose];
                GoalName {
                    pose: pose.name.value.clone(),
                    goal: g.goal,
                    kind: pose.goals[g.goal].value.keyword(),
                }
            })
            .collect(),
        shortfall: conflict.shortfall,
    }
}

fn candidate_report(candidate: &Candidate) -> CandidateReport {
    CandidateReport {
        capsules: candidate.capsules,
        objective: candidate.outcome.value.to_degrees(),
        worst_tilt_margin: candidate.outcome.worst_tilt_margin,
        meets_goals: candidate.outcome.meets_goals,
        printable: candidate.outcome.fabrication.is_empty(),
        seconds: candidate.seconds,
    }
}

fn seed_report(project: &Project, site: &SeedSite) -> SeedReport {
    SeedReport {
        component: project.component_name(site.component).to_string(),
        midpoint: site.midpoint.coords.into(),
        depth: site.depth,
        seeded: site.seeded,
    }
}
