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
    Edge, FeedDirection, FinishOptions, FinishSetup, IsoScallopSteps, Layout, PathSet, PathStart, Refusal, ScallopFlag,
    Stats, ToolPath, iso_parametric, iso_scallop, iso_scallop_checked,
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
    /// Its numbers.
    pub stats: Stats,
}

/// The comparison table of a job: matched, fixed lead 5° and 10°, principal axis and ball
/// (each in place of `job.strategy`), each with iso-scallop paths from `job.start` and
/// iso-parametric paths along the same parameter.
///
/// # Errors
/// The first job that fails.
pub fn compare(job: &FinishSetup) -> Result<Vec<Comparison>, FinishError> {
    let strategies = [
        Strategy::Matched,
        Strategy::FixedLead { lead_rad: 5f64.to_radians() },
        Strategy::FixedLead { lead_rad: 10f64.to_radians() },
        Strategy::PrincipalAxis,
        Strategy::Ball,
    ];
    // The table's ten plans share one budget of check cells. Refused before any is built
    // when the plans together would pass it: each strategy's pilot (as its own job's start
    // runs it) estimates its iso-scallop plan; its iso-parametric plan, at the same worst
    // scallop, takes at least as many paths, so twice that is the least the pair costs.
    let (opts, part) = (job.options, job.part);
    let setup = |strategy| FinishSetup { strategy, ..*job };
    let mut each = Vec::with_capacity(strategies.len());
    for s in strategies {
        each.push(2.0 * paths::estimate_check_cells(&setup(s))?);
    }
    let estimated: f64 = each.iter().sum();
    if estimated > opts.max_check_cells as f64 {
        return Err(FinishError::TooMuchChecking {
            detail: format!(
                "of the table's ten plans would pass {} cells: about {estimated:.2e} (estimated before any is built, from each strategy's pilot)",
                opts.max_check_cells
            ),
        });
    }
    let mut rows = Vec::new();
    // Then each plan may spend its share of what the ones before left: SHARE_ROOM times its
    // estimate's part of the estimates still to come (at most all that is left). A plan
    // past that has outrun its estimate so far that the projection below would refuse the
    // table after it on the same ratio; its own checks stop it as soon as the part of the
    // surface it has covered says so (a few per cent) instead of after it is built. The room
    // covers that early extrapolation's error (the mould's fixed-lead plan read 2.1 times
    // its final cost at 6 % of its surface).
    const SHARE_ROOM: f64 = 3.0;
    let start_cells = part.cells_checked();
    let estimate_of = |plan: usize| 0.5 * each[plan / 2];
    let budget_for = |part: &PartSamples, plan: usize| -> FinishOptions {
        let spent = part.cells_checked().saturating_sub(start_cells);
        let this = estimate_of(plan);
        let rest: f64 = (plan..2 * each.len()).map(estimate_of).sum();
        let left = paths::check_stop(opts.max_check_cells).saturating_sub(spent) as f64;
        // A plan its pilot could not estimate (no side step solved there: 0) has no share
        // to keep to: it may spend what is left, as before the shares.
        let share = if this > 0.0 && rest > 0.0 { (SHARE_ROOM * left * this / rest).min(left) } else { left };
        // The plan's checks stop at its share (its budget times the stop factor).
        FinishOptions { max_check_cells: (share / paths::CHECK_STOP_FACTOR) as u64, ..*opts }
    };
    // A plan's own refusal names its share of the table's budget.
    let in_table = |s: Strategy, layout: Layout, e: FinishError| match e {
        FinishError::TooMuchChecking { detail } => FinishError::TooMuchChecking {
            detail: format!(
                "of the table's ten plans would pass {} cells: its {} {} plan {detail} (its share: 3 times its estimate's part of what the plans before it left)",
                paths::check_stop(opts.max_check_cells),
                s.name(),
                layout.name()
            ),
        },
        other => other,
    };
    // The pilots' estimates of the plans still to come (each pair: half its estimate a plan),
    // scaled by how far the plans built so far outran theirs: refused as soon as the whole
    // table would pass the budget, after every plan.
    let project = |part: &PartSamples, plans: usize| -> Result<(), FinishError> {
        let spent = part.cells_checked().saturating_sub(start_cells) as f64;
        let total: f64 = each.iter().sum();
        let done: f64 = (0..plans).map(estimate_of).sum();
        let projected = spent + (total - done) * if done > 0.0 { (spent / done).max(1.0) } else { 1.0 };
        let stop = paths::check_stop(opts.max_check_cells);
        if projected > stop as f64 {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "of the table's ten plans would pass {stop} cells: about {projected:.2e} (projected after {plans} of them, which spent {spent:.2e})"
                ),
            });
        }
        Ok(())
    };
    for (k, s) in strategies.into_iter().enumerate() {
        let iso = iso_scallop(&FinishSetup { options: &budget_for(part, 2 * k), ..setup(s) })
            .map_err(|e| in_table(s, Layout::IsoScallop, e))?;
        rows.push(Comparison { strategy: s, layout: Layout::IsoScallop, stats: iso.stats(opts.feed_mm_per_min) });
        project(part, 2 * k + 1)?;
        let par = iso_parametric(&FinishSetup { options: &budget_for(part, 2 * k + 1), ..setup(s) })
            .map_err(|e| in_table(s, Layout::IsoParametric, e))?;
        rows.push(Comparison { strategy: s, layout: Layout::IsoParametric, stats: par.stats(opts.feed_mm_per_min) });
        project(part, 2 * k + 2)?;
    }
    Ok(rows)
}
