//! The optimizer stage of the pipeline: distance grids and skeletons per component, seeds, the
//! heuristic, the choice of a capsule count, and the chosen design rounded for the solution file.

use std::sync::Arc;
use std::time::Instant;

use super::optimization::{
    candidate_report, conflict_report, repair_warning, seed_report, CapsuleOrigin, Optimization,
    Starts, Timings,
};
use super::workspace::{Reporter, Stage, Workspace};
use crate::balance::PartPrints;
use crate::cancel::Cancel;
use crate::design::Design;
use crate::fabrication::PrintSetup;
use crate::geometry::{DistanceGrid, Skeleton, TriMesh};
use crate::objective::{GridInterior, Parameters};
pub use crate::optimize::length_decimals;
use crate::optimize::{
    backfill, choose, content_hash, default_cell, explain_conflicts, grid_scale, has_room, rank,
    repair_seeds, rescue, run_heuristic, skeleton_seeds, smallest_capsule_radius, Candidate,
    ConflictSpace, GoalRef, GridKey, Method, Origin, Outcome, PrecomputeCache, Problem, Rules,
    SeedRepair, SeedSite, StartCapsule,
};
use crate::spec::model::{Optimize, Project};

/// The optimizer's best design breaks a fabrication rule (a capsule outside its part, too close
/// to the surface, two capsules overlapping), so it is not written.
pub const UNFIT_DESIGN: &str = "ballast::optimize::unfit_design";

/// The error for an optimized design that breaks a fabrication rule, `first` being the first
/// broken: nothing is written, since `check` would refuse the solution file.
pub fn unfit_design(
    settings: &Optimize,
    first: &crate::diagnostic::Problem,
) -> crate::diagnostic::Problem {
    crate::diagnostic::Problem::error(
        UNFIT_DESIGN,
        format!(
            "the best design the optimizer found does not fit the parts, so nothing is written: {}",
            first.message
        ),
    )
    .with_label(settings.span, "this optimization")
    .with_help(
        "list balls small enough for the parts in `ball { diameters ... }`, ask for fewer capsules, or a thinner `wall`",
    )
}

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
    /// Judge the warm start as it is, with no search, when it fits the meshes: watch mode's
    /// first answer to an edit (the design is then [`DesignSource::Earlier`](super::DesignSource)).
    pub judge_warm_start: bool,
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
    /// The written seeds that broke a fabrication rule and what was done to each (indices into
    /// the project's capsules).
    pub repairs: Vec<SeedRepair>,
}

/// Each mesh's distance-grid key: at the project's `grid-cell`, or [`default_cell`] for the
/// smallest capsule radius `min_radius`.
fn grid_keys(settings: &Optimize, meshes: &[TriMesh], min_radius: f64) -> Vec<GridKey> {
    // One key per mesh: making it reads every coordinate.
    meshes
        .iter()
        .map(|mesh| {
            let cell = settings
                .grid_cell
                .unwrap_or_else(|| default_cell(mesh, min_radius));
            GridKey::new(mesh, cell)
        })
        .collect()
}

/// The grids and skeletons of a project's meshes, each at its key, from `cache` or computed into
/// it, each computation told to `reporter` as it starts; stopped by `cancel`.
struct Precompute<'a> {
    project: &'a Project,
    meshes: &'a [TriMesh],
    keys: Vec<GridKey>,
    cache: &'a mut PrecomputeCache,
    cancel: &'a Cancel,
    reporter: Reporter<'a>,
}

impl Precompute<'_> {
    /// Each mesh's distance grid; `None` when cancelled.
    fn grids(&mut self) -> Option<Vec<Arc<DistanceGrid>>> {
        let mut grids = Vec::with_capacity(self.meshes.len());
        for (index, (mesh, &key)) in self.meshes.iter().zip(&self.keys).enumerate() {
            if !self.cache.recall(mesh, key) {
                self.reporter.report(Stage::Grid {
                    component: self.project.component_name(index).to_string(),
                    nodes: DistanceGrid::node_count(mesh, key.cell()),
                });
            }
            grids.push(self.cache.grid(mesh, key, self.cancel)?);
        }
        Some(grids)
    }

    /// Each mesh's skeleton, thinned on its grid; `None` when cancelled.
    fn skeletons(&mut self) -> Option<Vec<Arc<Skeleton>>> {
        let mut skeletons = Vec::with_capacity(self.meshes.len());
        for (index, (mesh, &key)) in self.meshes.iter().zip(&self.keys).enumerate() {
            if !self.cache.holds_skeleton(key) {
                self.reporter.report(Stage::Skeleton {
                    component: self.project.component_name(index).to_string(),
                });
            }
            skeletons.push(self.cache.skeleton(mesh, key, self.cancel)?);
        }
        Some(skeletons)
    }
}

/// Whether the seeds come from the skeletons: without a warm start, when every one of the
/// project's written capsules (`written`) is pinned.
fn seeds_from_skeletons(written: &[StartCapsule], warm: bool) -> bool {
    !warm && written.iter().all(|c| c.pinned)
}

/// Samples into `cache` the grids, and the skeletons when the seeds come from them, that
/// [`prepare`] reads for `project` (with no skeleton when `warm`, a warm start given): so that they can
/// be computed beside another stage of the build (the print volumes), on another thread.
/// Stops early when `cancel` is set; [`prepare`] then finds what is missing.
pub(super) fn precompute_ahead(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    warm: bool,
    cache: &mut PrecomputeCache,
    cancel: &Cancel,
    reporter: Reporter,
) {
    let mut precompute = Precompute {
        project,
        meshes,
        keys: grid_keys(
            settings,
            meshes,
            Parameters::for_project(project).min_radius,
        ),
        cache,
        cancel,
        reporter,
    };
    if precompute.grids().is_some() && seeds_from_skeletons(&written_capsules(project), warm) {
        // A cancelled thinning leaves nothing for `prepare` to find: it thins again.
        let _ = precompute.skeletons();
    }
}

/// The precomputation of the optimizer: distance grids (from the workspace's cache when it holds
/// them, at the project's `grid-cell` or [`default_cell`]), then the seeds: from `warm` when
/// given, else from skeletons thinned on the grids. `None` when the workspace was cancelled.
pub fn prepare(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    print: &PrintSetup,
    workspace: &mut Workspace,
    warm: Option<&Design>,
) -> Option<Preparation> {
    let parameters = Parameters::for_project(project);
    let (_, cache, cancel, reporter) = workspace.split();
    let mut precompute = Precompute {
        project,
        meshes,
        keys: grid_keys(settings, meshes, parameters.min_radius),
        cache,
        cancel,
        reporter,
    };
    let grids = precompute.grids()?;
    let interior = Arc::new(GridInterior { grids });
    let mut seeds = written_capsules(project);
    if let Some(design) = warm {
        seeds.retain(|c| c.pinned);
        seeds.extend(warm_capsules(design, &seeds));
    }
    // With a warm start the pinned written capsules are among the seeds, whatever it says.
    if !seeds_from_skeletons(&seeds, warm.is_some()) {
        let repairs = if warm.is_some() {
            Vec::new()
        } else {
            let rules = Rules {
                meshes,
                interior: interior.as_ref(),
                ball: &project.ball,
                min_radius: parameters.min_radius,
                wall: project.wall,
                scale: grid_scale(length_decimals(meshes)),
                print,
            };
            repair_seeds(&mut seeds, &rules)
        };
        return Some(Preparation {
            interior,
            seeds,
            sites: Vec::new(),
            repairs,
        });
    }
    let skeletons = precompute.skeletons()?;
    let ball = &project.ball;
    let scale = grid_scale(length_decimals(meshes));
    let smallest = smallest_capsule_radius(ball, parameters.min_radius, scale);
    let room: Vec<bool> = meshes
        .iter()
        .zip(&print.up)
        .map(|(mesh, up)| {
            has_room(
                &mesh.positions,
                up,
                smallest,
                project.wall,
                ball.clearance,
                print.grid.layer_height,
            )
        })
        .collect();
    let (starts, sites) = skeleton_seeds(
        &skeletons,
        interior.as_ref(),
        &room,
        parameters.min_radius,
        project.wall,
    );
    seeds.extend(starts);
    Some(Preparation {
        interior,
        seeds,
        sites,
        repairs: Vec::new(),
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
    prints: &PartPrints,
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
        if optimized.1.meets_goals || optimized.1.interrupted.is_some() {
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
    prints: &PartPrints,
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
        repairs,
    } = prepare(project, settings, meshes, print, workspace, warm)?;
    let precompute = clock.elapsed().as_secs_f64();
    let warnings = repairs
        .iter()
        .map(|repair| repair_warning(project, repair))
        .collect();

    // Poses without goals are only shown: they take no part in the search (not even with their
    // ball-elevation constraint), so adding one leaves the design as it was.
    let steering = with_goal_poses_only(project);
    let project = &steering;
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
    let candidates = run_heuristic(&problem, &seeds, requested, &|round| {
        workspace.report(Stage::Round(round))
    });
    // Interrupted (not cancelled), the rounds finished so far still hold designs worth keeping.
    let interrupted = || workspace.cancel.interruption();
    if candidates.is_empty() || (problem.is_cancelled() && interrupted().is_none()) {
        return None;
    }
    // No count meeting every goal, random starts get a few rounds (not from a warm start: the
    // full search follows it when it misses).
    let mut candidates = candidates;
    let rescue_starts = if warm.is_none() && !problem.is_cancelled() {
        rescue(
            &problem,
            interior.as_ref(),
            &seeds,
            &mut candidates,
            requested,
            settings.seed,
            &|round, starts| workspace.report(Stage::Rescue { round, starts }),
        )
    } else {
        0
    };
    // A count that misses a goal where the next fewer capsules meet every goal starts again from
    // their design (not from a warm start, as the rescue; not when one count is asked for).
    if requested.is_none() && warm.is_none() && !problem.is_cancelled() {
        backfill(&problem, &mut candidates, &|solves| {
            workspace.report(Stage::Backfill { solves })
        });
    }
    let chosen = choose(&candidates, requested, settings.tolerance_degrees);
    // The chosen design with a smaller stock ball tried when it has one movable capsule (one
    // more judged design), unless the search was interrupted.
    if !problem.is_cancelled() {
        let candidate = &mut candidates[chosen];
        candidate.outcome = problem.with_other_balls(&candidate.starts, candidate.outcome.clone());
    }
    let heuristic = clock.elapsed().as_secs_f64();

    let clock = Instant::now();
    let mut exhaustive = if options.exhaustive > 0 && !problem.is_cancelled() {
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
    // A ranking cut short compares with starts that were never solved: it means nothing.
    if problem.is_cancelled() {
        exhaustive.clear();
    }
    let exhaustive_seconds = clock.elapsed().as_secs_f64();

    let outcome = candidates[chosen].outcome.clone();
    let (design, origins) = named(project, outcome.design.clone(), &candidates[chosen].starts);

    let clock = Instant::now();
    let explanation = if outcome.meets_goals || problem.is_cancelled() {
        None
    } else {
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
        let starts = conflict_starts(&seeds, &candidates, chosen, requested);
        let space = ConflictSpace { starts: &starts };
        let achieved: Vec<Vec<GoalRef>> = candidates
            .iter()
            .enumerate()
            .filter(|(i, c)| {
                (requested.is_none() || *i == chosen) && c.outcome.fabrication.is_empty()
            })
            .map(|(_, c)| goals_met(&c.outcome))
            .collect();
        Some(explain_conflicts(
            project,
            meshes,
            prints,
            print,
            &interior,
            &space,
            &unmet,
            &achieved,
            &workspace.cancel,
            &|solve| workspace.report(Stage::Conflicts { solve }),
        ))
    };
    let interrupted = interrupted();
    // Cancelled, nothing is kept; interrupted, the conflicts shown before are kept.
    if problem.is_cancelled() {
        interrupted?;
    }
    let conflicts_cut_short = explanation.as_ref().is_some_and(|e| e.cut_short);
    let conflicts = explanation
        .map(|e| e.conflicts)
        .unwrap_or_default()
        .iter()
        .map(|c| conflict_report(project, c))
        .collect();
    let conflicts_seconds = clock.elapsed().as_secs_f64();
    let optimization = Optimization {
        requested,
        chosen: design.capsules.len(),
        meets_goals: outcome.meets_goals,
        tolerance: settings.tolerance_degrees,
        warm_started: warm.is_some(),
        interrupted,
        candidates: candidates.iter().map(candidate_report).collect(),
        seeds: sites
            .iter()
            .map(|site| seed_report(project, site))
            .collect(),
        starts: Starts::of(&seeds),
        origins,
        rescue_starts,
        exhaustive,
        conflicts,
        conflicts_cut_short,
        timings: Timings {
            precompute,
            heuristic,
            exhaustive: exhaustive_seconds,
            conflicts: conflicts_seconds,
        },
        warnings,
    };
    Some((design, optimization))
}

/// `project` without the poses that have no goals: what the optimizer steers by. The pose indices
/// of its results (conflicts) are indices into this project's poses.
fn with_goal_poses_only(project: &Project) -> Project {
    let mut steering = project.clone();
    steering.poses.retain(|pose| !pose.goals.is_empty());
    steering
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
            origin: Origin::Written,
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
            origin: Origin::Earlier,
        })
        .collect()
}

/// `design` with every capsule named after where it is, unless pinned (a pinned capsule keeps the
/// name it is written with): its component and a counter, `"<component> 1"`, `"<component> 2"`, …
/// per component in design order, skipping the names of pinned capsules. Also where each capsule
/// came from, from `starts` (one per capsule, in design order).
fn named(
    project: &Project,
    mut design: Design,
    starts: &[StartCapsule],
) -> (Design, Vec<CapsuleOrigin>) {
    let pinned: Vec<&str> = project
        .capsules
        .iter()
        .filter(|c| c.pinned)
        .map(|c| c.name.value.as_str())
        .collect();
    let mut counters = vec![0usize; project.components.len()];
    let mut origins = Vec::with_capacity(design.capsules.len());
    for (capsule, start) in design.capsules.iter_mut().zip(starts) {
        if !start.pinned {
            let component = project.component_name(capsule.component);
            let mut k = counters.get(capsule.component).copied().unwrap_or(0);
            capsule.name = loop {
                k += 1;
                let name = format!("{component} {k}");
                if !pinned.contains(&name.as_str()) {
                    break name;
                }
            };
            if let Some(counter) = counters.get_mut(capsule.component) {
                *counter = k;
            }
        }
        let (seed, site) = match start.origin {
            _ if start.pinned => ("pinned", None),
            Origin::Written => ("written", None),
            Origin::Skeleton(site) => ("skeleton", Some(site)),
            Origin::Earlier => ("earlier", None),
            Origin::Random => ("random", None),
        };
        origins.push(CapsuleOrigin {
            capsule: capsule.name.clone(),
            seed,
            seed_name: start.name.clone().filter(|_| site.is_none()),
            site,
        });
    }
    (design, origins)
}

/// The goals `outcome` meets, pose by pose.
fn goals_met(outcome: &Outcome) -> Vec<GoalRef> {
    outcome
        .poses
        .iter()
        .enumerate()
        .flat_map(|(pose, p)| {
            p.goals
                .iter()
                .enumerate()
                .filter(|(_, g)| g.met)
                .map(move |(goal, _)| GoalRef { pose, goal })
        })
        .collect()
}

/// The starts for explaining conflicts, all in the design space the build searched: with a
/// capsule count asked for, the chosen candidate (that count) where the heuristic left it and as
/// its round started, and with one movable capsule, each seed alone beside the pinned ones;
/// otherwise every candidate of at most the chosen count, where the heuristic left it and as its
/// round started. Fewest capsules first.
fn conflict_starts(
    seeds: &[StartCapsule],
    candidates: &[Candidate],
    chosen: usize,
    requested: Option<usize>,
) -> Vec<Vec<StartCapsule>> {
    let mut starts: Vec<Vec<StartCapsule>> = Vec::new();
    let mut add = |start: Vec<StartCapsule>| {
        if !starts.contains(&start) {
            starts.push(start);
        }
    };
    for (i, candidate) in candidates.iter().enumerate() {
        if requested.is_some() && i != chosen {
            continue;
        }
        if candidate.capsules > candidates[chosen].capsules {
            continue;
        }
        add(seeds_for(seeds, candidate));
        add(candidate.starts.clone());
    }
    let movable = candidates[chosen]
        .starts
        .iter()
        .filter(|c| !c.pinned)
        .count();
    if requested.is_some() && movable == 1 {
        let pinned: Vec<StartCapsule> = seeds.iter().filter(|s| s.pinned).cloned().collect();
        for alone in seeds.iter().filter(|s| !s.pinned) {
            let mut start = pinned.clone();
            start.push(alone.clone());
            add(start);
        }
    }
    // Fewest capsules first: the cheapest solves, and a set of goals stops at the first batch
    // that meets it. Whether a set is met, and the shortfall of one that is not (the best over
    // every start), do not depend on the order.
    starts.sort_by_key(Vec::len);
    starts
}

/// The start for explaining conflicts: the chosen candidate's capsules where the heuristic left
/// them (none when it has none).
fn seeds_for(seeds: &[StartCapsule], candidate: &Candidate) -> Vec<StartCapsule> {
    candidate
        .outcome
        .design
        .capsules
        .iter()
        .zip(&candidate.starts)
        .map(|(c, start)| StartCapsule {
            component: c.component,
            from: c.from,
            to: c.to,
            radius: c.radius,
            pinned: seeds
                .iter()
                .any(|s| s.pinned && s.name.as_deref() == Some(c.name.as_str())),
            name: Some(c.name.clone()),
            origin: start.origin,
        })
        .collect()
}
