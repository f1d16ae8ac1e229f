//! What one process keeps from build to build, and how it steers the build in flight: the
//! precompute and print caches, the cancel flag, and where progress goes.

use std::sync::{Mutex, PoisonError};

use super::mesh_cache::MeshCache;
use super::outputs::PrintFileCache;
use super::print_cache::PrintCache;
use super::DesignSource;
use crate::cancel::Cancel;
use crate::diagnostic::Problem;
use crate::optimize::{PrecomputeCache, Round, MAX_EXPLANATION_SOLVES, RESCUE_ROUNDS};

/// The state builds share in one process. `build` and `check` use a fresh one; watch mode keeps
/// one for the whole session, so an unchanged mesh is never parsed, checked or sampled twice.
#[derive(Default)]
pub struct Workspace {
    /// Meshes already loaded and checked.
    pub meshes: MeshCache,
    /// Distance grids and skeletons already built.
    pub cache: PrecomputeCache,
    /// Print volumes already computed.
    pub prints: PrintCache,
    /// The print files last written, for [`write_outputs_with`](super::write_outputs_with).
    pub print_files: PrintFileCache,
    /// Set from another thread to stop the build in flight (watch mode: a newer save).
    pub cancel: Cancel,
    /// Told as each long stage starts; silent when `None`.
    pub progress: Option<Box<dyn Fn(Stage) + Send + Sync>>,
    /// The long stage the build in flight started last, told or not (read it with
    /// [`stage`](Self::stage)).
    pub last_stage: Mutex<Option<Stage>>,
}

impl Workspace {
    /// An empty cache, a flag nobody sets, no progress.
    pub fn new() -> Workspace {
        Workspace::default()
    }

    /// Marks the start of a build for every cache (see [`prune`](Self::prune)).
    pub fn start_build(&mut self) {
        *self
            .last_stage
            .lock()
            .unwrap_or_else(PoisonError::into_inner) = None;
        self.meshes.start_build();
        self.cache.start_build();
        self.prints.start_build();
    }

    /// Drops from every cache what the build since [`start_build`](Self::start_build) did not
    /// use: call it after a good build, so a long session holds one version of each mesh. A
    /// build whose design was judged without a search ([`DesignSource::Earlier`]) asks for no
    /// grid or skeleton, so those are kept for the search that follows it.
    pub fn prune(&mut self, source: &DesignSource) {
        self.meshes.prune();
        if *source != DesignSource::Earlier {
            self.cache.prune();
        }
        self.prints.prune();
    }

    /// Tells the progress sink that `stage` starts.
    pub(crate) fn report(&self, stage: Stage) {
        self.reporter().report(stage);
    }

    /// Where this workspace's stages are told.
    fn reporter(&self) -> Reporter<'_> {
        Reporter {
            progress: &self.progress,
            last_stage: &self.last_stage,
        }
    }

    /// The print-volume and precompute caches apart, with the cancel flag and where stages are
    /// told: what it takes to fill both caches at once.
    pub(crate) fn split(
        &mut self,
    ) -> (&mut PrintCache, &mut PrecomputeCache, &Cancel, Reporter<'_>) {
        let reporter = Reporter {
            progress: &self.progress,
            last_stage: &self.last_stage,
        };
        (&mut self.prints, &mut self.cache, &self.cancel, reporter)
    }

    /// The long stage the build in flight (or the last one) started last, if any: where a
    /// build that was stopped stood.
    pub fn stage(&self) -> Option<Stage> {
        self.last_stage
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }
}

/// Where a workspace's stages are told: its progress sink, and the last stage it was told
/// ([`Workspace::stage`]). Shared by the threads of one build.
#[derive(Clone, Copy)]
pub(crate) struct Reporter<'a> {
    progress: &'a Option<Box<dyn Fn(Stage) + Send + Sync>>,
    last_stage: &'a Mutex<Option<Stage>>,
}

impl Reporter<'_> {
    /// Tells the progress sink that `stage` starts.
    pub(crate) fn report(&self, stage: Stage) {
        *self
            .last_stage
            .lock()
            .unwrap_or_else(PoisonError::into_inner) = Some(stage.clone());
        if let Some(progress) = self.progress {
            progress(stage);
        }
    }
}

/// A stage of a build that can take long, as it starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stage {
    /// Sampling the distance grid of a component: its name and node count.
    Grid {
        /// The component.
        component: String,
        /// Nodes to sample.
        nodes: usize,
    },
    /// Thinning a component's grid to its skeleton.
    Skeleton {
        /// The component.
        component: String,
    },
    /// A local solve of a round of the capsule-count heuristic.
    Round(Round),
    /// A round of random starts after no capsule count met every goal.
    Rescue {
        /// The round, from 1.
        round: usize,
        /// Random starts in the round.
        starts: usize,
    },
    /// Capsule counts that missed a goal, solved again from a smaller count's design that meets
    /// every goal.
    Backfill {
        /// Counts solved again.
        solves: usize,
    },
    /// Random starts to rank the heuristic's result (`--exhaustive`).
    Exhaustive {
        /// Random starts per capsule count.
        starts: usize,
    },
    /// A solve of the explanation of the goals the chosen design misses.
    Conflicts {
        /// The solve, from 1.
        solve: usize,
    },
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stage::Grid { component, nodes } => {
                write!(
                    f,
                    "sampling the distance grid of `{component}` ({nodes} nodes)"
                )
            }
            Stage::Skeleton { component } => write!(f, "thinning the skeleton of `{component}`"),
            Stage::Round(at) => write!(
                f,
                "round {} of at most {}: {} capsule{}, solve {}/{}",
                at.round,
                at.most_rounds,
                at.capsules,
                if at.capsules == 1 { "" } else { "s" },
                at.solve,
                at.solves
            ),
            Stage::Rescue { round, starts } => write!(
                f,
                "no capsule count met every goal: round {round} of at most {RESCUE_ROUNDS} of random starts ({starts} starts)"
            ),
            Stage::Backfill { solves } => write!(
                f,
                "solving {solves} capsule count{} again from fewer capsules that meet every goal",
                if *solves == 1 { "" } else { "s" }
            ),
            Stage::Exhaustive { starts } => {
                write!(
                    f,
                    "ranking against {starts} random starts per capsule count"
                )
            }
            Stage::Conflicts { solve } => write!(
                f,
                "explaining the goals not met: solve {solve} of at most {MAX_EXPLANATION_SOLVES}"
            ),
        }
    }
}

/// Why a build produced nothing.
#[derive(Debug)]
pub enum Failure {
    /// The project is invalid: every problem found, warnings included.
    Invalid(Vec<Problem>),
    /// The workspace's cancel flag was set before the build finished.
    Cancelled,
}
