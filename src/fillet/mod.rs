//! Seed 001: five-axis finishing of a free-form surface with a fillet-end (toroidal,
//! "bull-nose") mill — effective cutting curvature, curvature-matched tool orientation,
//! iso-scallop paths, gouge and interference checks. Conventions and derivations:
//! `docs/fillet.md`.
//!
//! Glossary:
//! - *CC point* (cutter contact) q: where the cutter touches the design surface; n the
//!   surface's unit normal there, toward the cutter;
//! - *CL point* (cutter location): what a program positions — here the *tool tip* T (centre
//!   of the cutter's bottom face) and the unit *tool axis* a (tip → spindle), workpiece
//!   coordinates;
//! - *feed direction* f: the unit tangent of the path at q; c = n × f across it;
//! - *lead angle* λ: the axis turned from n toward f; *tilt angle* ω: turned sideways toward
//!   c (`a = cos ω (cos λ n + sin λ f) + sin ω c`); equivalently the *inclination* α from n
//!   and the *azimuth* ψ of the turn in the tangent plane;
//! - *effective cutting curvature* κ(θ): the curvature, at q, of the cutter's envelope
//!   (the torus of its rotating edge) cut by the normal plane of the tangent direction θ;
//!   the cutter clears the surface locally when κ(θ) ≥ the surface's normal curvature k_s(θ)
//!   in every direction (signs: positive when bending toward n);
//! - *machining strip*: the band along a path where the swept cutter stays within the
//!   scallop height h of the surface; its width is the side step it allows;
//! - *scallop*: the ridge of material left between two neighbouring paths, h its height
//!   above the design surface.
//!
//! Modules: [`contact`] (frame, pose, placement, curvatures, cross profile), [`orient`]
//! (strategies, smoothing), [`gouge`] (checks and adjustment), [`paths`] (forward and side
//! steps, iso-scallop and iso-parametric paths, comparison numbers), [`program`] (CL data as
//! a seed-002 design path for the machines and step selection).

pub mod contact;
pub mod gouge;
pub mod node;
pub mod orient;
pub mod paths;
pub mod program;
pub mod second_bound;
pub mod sweep;

use thiserror::Error;

use crate::fiveaxis::Machine;
use crate::geom::{Cutter, Surface};

pub use contact::{ContactFrame, CrossProfile, Form2, Pose, effective_curvature, place, scallop_between};
pub use gouge::{Adjustment, Clash, ClashPart, PartSamples};
pub use node::CcNode;
pub use orient::{OrientOptions, Strategy};
pub use paths::{
    Built, Edge, FeedDirection, FinishOptions, FinishSetup, IsoScallopSteps, Layout, PathSet, PathStart, Refusal,
    ScallopFlag, Stats, ToolPath, iso_parametric, iso_scallop, iso_scallop_checked,
};

/// A finishing scene in core units, ready to compute (what `scene::finish` builds from a
/// finishing scene; here, below `scene`, so that `simulate` can take one without importing
/// `scene`).
#[derive(Clone, Debug)]
pub struct FinishJob {
    /// Display name.
    pub name: String,
    /// The surface.
    pub surface: Surface,
    /// The cutter.
    pub cutter: Cutter,
    /// The strategy.
    pub strategy: Strategy,
    /// Path options.
    pub options: FinishOptions,
    /// The machine (the default table A/C when the scene has none).
    pub machine: Machine,
    /// Where the iso-scallop paths start (`finish.start`; parameters in internal units).
    pub start: PathStart,
}

impl FinishJob {
    /// The job's inputs borrowed for the path layouts, with `part` its part sampled once
    /// (`PartSamples::new(&job.surface, job.options.part_grid)`).
    #[must_use]
    pub fn setup<'a>(&'a self, part: &'a PartSamples) -> FinishSetup<'a> {
        FinishSetup {
            surface: &self.surface,
            cutter: &self.cutter,
            strategy: self.strategy,
            options: &self.options,
            part,
            start: &self.start,
            reach: None,
        }
    }
}

/// Why a finishing job failed. Each message says what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FinishError {
    /// An option that must be a positive length is not.
    #[error("the {name} must be a positive length in mm, got {value}; give a value above 0")]
    BadOption {
        /// Which option.
        name: &'static str,
        /// The value.
        value: f64,
    },
    /// Not even the first path could be built.
    #[error(
        "no path could be started on the first boundary or curve: {reason}; use a smaller cutter or a larger max_inclination"
    )]
    NoPath {
        /// Why.
        reason: &'static str,
    },
    /// The start curve cannot be used.
    #[error("{reason}; give the start curve as 2 or more [u, v] points inside the surface's domain")]
    BadStart {
        /// What is wrong with it.
        reason: String,
    },
    /// The paths would exceed their cap.
    #[error(
        "the surface needs more than {max_paths} paths at this scallop height; raise the scallop height or use a larger cutter"
    )]
    TooManyPaths {
        /// The cap.
        max_paths: usize,
    },
    /// The CC points would exceed their cap.
    #[error(
        "the paths need more than {max_nodes} CC points; raise the chord tolerance, the max step or the scallop height"
    )]
    TooManyNodes {
        /// The cap.
        max_nodes: usize,
    },
    /// The paths or their CC points would pass their caps: estimated before they are built
    /// (by more than `paths::ESTIMATE_MARGIN`), or from the share of the surface covered.
    #[error(
        "the paths would number about {paths:.0} with about {nodes:.2e} CC points (estimated before the paths are built, or from the share of the surface they covered), more than the {max_paths} paths or {max_nodes} CC points allowed; raise the scallop height, the chord tolerance or the max step, use a larger cutter, or check the surface (a mistyped control point?)"
    )]
    Oversized {
        /// Estimated paths.
        paths: f64,
        /// Estimated CC points.
        nodes: f64,
        /// The cap on paths.
        max_paths: usize,
        /// The cap on CC points.
        max_nodes: usize,
    },
    /// A comparison table's plan did more work than its share of the table's budget
    /// (`FinishOptions::max_work`); the table leaves the plan out and goes on.
    #[error(
        "the plan stopped after {work} units of work, more than its share of the comparison table's budget ({max_work}); raise the scallop height or use a larger cutter"
    )]
    OverShare {
        /// Work done (bottom-check cells and their equivalents).
        work: u64,
        /// The share.
        max_work: u64,
    },
    /// The certified gouge checks cost far more than on any usable part
    /// (`paths::MAX_CHECK_CELLS_PER_NODE`, `paths::MAX_CHECK_CELLS`).
    #[error(
        "the gouge checks {detail}: the surface is far larger or more curved than this cutter can be checked against; check the surface (a mistyped control point?), or use a larger cutter or scallop height"
    )]
    TooMuchChecking {
        /// What was measured against which cap.
        detail: String,
    },
}

/// One row of the comparison table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// The strategy.
    pub strategy: Strategy,
    /// The layout.
    pub layout: Layout,
    /// Its numbers, or why the table left the plan out.
    pub plan: Result<Stats, LeftOut>,
}

/// A plan the comparison table left out, and the work it did first (in bottom-check cells
/// and their equivalents, [`PartSamples::work_done`]; 0 when nothing of the budget was left
/// for it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LeftOut {
    /// Work the plan did before it stopped.
    pub work: u64,
    /// Its share of the table's budget.
    pub share: u64,
    /// Why it stopped.
    pub cause: LeftOutCause,
}

/// Why the comparison table left a plan out. Each is a refusal when the plan is a job of its
/// own; in a table, one plan's size says nothing about the others', so the table goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeftOutCause {
    /// Its work passed its share ([`FinishError::OverShare`]), or no budget was left.
    Share,
    /// Its gouge checks would pass their stop ([`FinishError::TooMuchChecking`]).
    Checks,
    /// It needs more paths or CC points than allowed ([`FinishError::Oversized`],
    /// [`FinishError::TooManyPaths`], [`FinishError::TooManyNodes`]).
    Size,
    /// Its first path could not be started, or its iso-parametric spacing did not settle
    /// ([`FinishError::NoPath`]): a strategy's cutter or a layout the surface does not suit.
    NoStart,
}

impl LeftOutCause {
    /// The cause as the table's warning names it.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Self::Share => "past its share of the budget",
            Self::Checks => "its gouge checks would pass their stop",
            Self::Size => "more paths or CC points than allowed",
            Self::NoStart => "no path could be started, or its spacing did not settle",
        }
    }

    /// The cause for which a table leaves out a plan that failed with `e`; `None` for an
    /// error that is not the plan's own (a bad option, a bad start curve), which ends the
    /// table.
    #[must_use]
    pub fn of(e: &FinishError) -> Option<Self> {
        match e {
            FinishError::OverShare { .. } => Some(Self::Share),
            FinishError::TooMuchChecking { .. } => Some(Self::Checks),
            FinishError::Oversized { .. } | FinishError::TooManyPaths { .. } | FinishError::TooManyNodes { .. } => {
                Some(Self::Size)
            }
            FinishError::NoPath { .. } => Some(Self::NoStart),
            _ => None,
        }
    }
}

/// The comparison table's budget of work ([`PartSamples::work_done`]) as a multiple of its
/// jobs' budget of check cells (`FinishOptions::max_check_cells`): 80 million at the
/// default, some 15 s of CPU. The example tables do 23–58 million.
pub const TABLE_WORK_FACTOR: f64 = 1.6;

/// The comparison table of a job: matched, fixed lead 5° and 10°, principal axis and ball
/// (each in place of `job.strategy`), each with iso-scallop paths from `job.start` and
/// iso-parametric paths along the same parameter.
///
/// The table is refused before any plan is built when its plans' pilots say they would
/// pass the budget of check cells. Past that it is built to a budget of work
/// (`FinishOptions::max_work`, by default [`TABLE_WORK_FACTOR`] times the cells' budget):
/// each plan may do its share of what the plans before it left, and one that passes its
/// share is left out ([`LeftOut`]) while the table goes on, as is one whose own caps stop
/// it (paths, CC points, checks). A pilot can be far out on a
/// tightly curved surface (ten times, on a blade with a control point moved onto its nose),
/// so a table that only refused would be refused after most of its work; this one keeps
/// the rows it built, and its time is bounded by the budget.
///
/// # Errors
/// The table's pilots, a plan that fails for another reason than its size (a bad option,
/// no path at the start), or no plan built.
pub fn compare(job: &FinishSetup) -> Result<Vec<Comparison>, FinishError> {
    let strategies = [
        Strategy::Matched,
        Strategy::FixedLead { lead_rad: 5f64.to_radians() },
        Strategy::FixedLead { lead_rad: 10f64.to_radians() },
        Strategy::PrincipalAxis,
        Strategy::Ball,
    ];
    // Refused before any plan is built when the plans together would pass the budget of
    // check cells: each strategy's pilot (as its own job's start runs it) estimates its
    // iso-scallop plan; its iso-parametric plan, at the same worst scallop, takes at least
    // as many paths, so twice that is the least the pair costs.
    let (opts, part) = (job.options, job.part);
    let setup = |strategy| FinishSetup { strategy, ..*job };
    // The sum is read after each pilot: it only grows, so the table is refused as soon as
    // one pilot puts it over, not after all five (a fuzz patch's first pilot read 100 times
    // the budget, and the five took 1.4 s).
    let mut each = Vec::with_capacity(strategies.len());
    let mut estimated = 0.0;
    for s in strategies {
        each.push(2.0 * paths::estimate_check_cells(&setup(s))?);
        estimated += each[each.len() - 1];
        if estimated > opts.max_check_cells as f64 {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "of the table's ten plans would pass {} cells: about {estimated:.2e} or more (estimated before any is built, from {} of the five strategies' pilots)",
                    opts.max_check_cells,
                    each.len()
                ),
            });
        }
    }
    // Then each plan may do SHARE_ROOM times its estimate's part of the work the plans before
    // it left of the budget (at most all of it). The room is for the estimates' error: a
    // plan that keeps to its estimate is never stopped.
    const SHARE_ROOM: f64 = 3.0;
    let budget = opts.max_work.unwrap_or((TABLE_WORK_FACTOR * opts.max_check_cells as f64) as u64);
    let start_work = part.work_done();
    let estimate_of = |plan: usize| 0.5 * each[plan / 2];
    let share_for = |part: &PartSamples, plan: usize| -> u64 {
        let left = budget.saturating_sub(part.work_done().saturating_sub(start_work));
        let this = estimate_of(plan);
        let rest: f64 = (plan..2 * each.len()).map(estimate_of).sum();
        // A plan its pilot could not estimate (no side step solved there: 0) has no share
        // to keep to: it may do what is left.
        if this > 0.0 && rest > 0.0 { ((SHARE_ROOM * left as f64 * this / rest) as u64).min(left) } else { left }
    };
    let mut rows = Vec::new();
    for (k, s) in strategies.into_iter().enumerate() {
        for (j, layout) in [Layout::IsoScallop, Layout::IsoParametric].into_iter().enumerate() {
            let share = share_for(part, 2 * k + j);
            let plan = if share == 0 {
                Err(LeftOut { work: 0, share, cause: LeftOutCause::Share })
            } else {
                let options = FinishOptions { max_work: Some(share), ..*opts };
                let job = FinishSetup { options: &options, ..setup(s) };
                let before = part.work_done();
                let built = if layout == Layout::IsoScallop { iso_scallop(&job) } else { iso_parametric(&job) };
                let left_out = |cause| Err(LeftOut { work: part.work_done().saturating_sub(before), share, cause });
                match built {
                    Ok(set) => Ok(set.stats(opts.feed_mm_per_min)),
                    Err(FinishError::OverShare { work, max_work }) => {
                        Err(LeftOut { work, share: max_work, cause: LeftOutCause::Share })
                    }
                    Err(e) => match LeftOutCause::of(&e) {
                        Some(cause) => left_out(cause),
                        None => return Err(e),
                    },
                }
            };
            rows.push(Comparison { strategy: s, layout, plan });
        }
    }
    if rows.iter().all(|r| r.plan.is_err()) {
        return Err(FinishError::TooMuchChecking {
            detail: format!(
                "of the table's ten plans each passed its share of the table's budget of {:.2e} units of work or its own caps, or could not be started (estimated before any was built at {estimated:.2e} cells)",
                budget as f64
            ),
        });
    }
    Ok(rows)
}
