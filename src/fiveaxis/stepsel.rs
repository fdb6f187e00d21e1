//! Tool-step selection (seed 002, §3): nodes along a design path such that every segment's
//! total error |δ| = |δt + δn| equals the tolerance E (the last at most E).
//!
//! From the current node s_a, δ(s) is the error of the segment from s_a to a candidate node
//! s, with the candidate's joints from inverse kinematics nearest the farthest candidate
//! already found within E ([`super::swept::block_at`]) and δ measured on the swept tool
//! ([`super::swept::segment_total`]). The next node solves |δ(s)| = E by
//! [`crate::numerics::roots::next_node`]: bracketing from the first step √(8ρE) (later the previous
//! step), doubling, then the chosen [`RootMethod`]. Each δ counts as one iteration.
//!
//! Everything here is a pure function of its inputs (no clocks, no globals): an app can call
//! [`plan_steps`] every frame while a tolerance slider moves.

use super::FiveAxisError;
use super::machine::Machine;
use super::path::DesignPath;
use super::swept::{Block, SegmentReport, block_at, segment_report, segment_total, tip_design_deviation};
use crate::numerics::maximise::MaxOptions;
use crate::numerics::roots::{RootMethod, SearchFailure, SearchOptions, next_node};
use crate::numerics::tolerance;

/// Settings of [`plan_steps`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOptions {
    /// The tolerance E (mm).
    pub tol_mm: f64,
    /// Bracketing and root search (default [`SearchOptions::default`]: the paper's modified
    /// secant, doubling, ε = 1e-6 mm).
    pub search: SearchOptions,
    /// How a segment's worst error is located; `floor` is replaced by 1e-3·E (default
    /// [`MaxOptions::default`]).
    pub swept: MaxOptions,
    /// Most nodes before giving up (default 200 000).
    pub max_nodes: usize,
    /// Compute the full [`SegmentReport`] of every chosen segment (default true; an app
    /// dragging a slider may turn it off and keep only δ).
    pub reports: bool,
    /// Largest move of either rotary axis in one segment (rad; default 90°). A move near
    /// 180° makes the block ambiguous (the machine may turn either way), and on a machine
    /// whose rotary motion alone follows the path exactly (a round pocket centred on the C
    /// axis) nothing else would end a segment. Enforced continuously: the search sees
    /// `max(|δ|, E·|Δθ|/θ_max)`, so a segment ends where either reaches E.
    pub max_rotary_step_rad: f64,
    /// Also hold the swept tool tip within E of the design tip path (default false). The
    /// search then sees `max(|δ|, tip distance, rotary term)`: segments are shorter where
    /// the tip leaves its design path further than the ball leaves the surfaces (up to
    /// 2.9× on shallow crease corners, docs/fiveaxis.md), and such segments have |δ| < E.
    pub bound_tip: bool,
}

impl StepOptions {
    /// Default settings for tolerance `tol_mm`.
    #[must_use]
    pub fn new(tol_mm: f64) -> Self {
        Self {
            tol_mm,
            search: SearchOptions::default(),
            swept: MaxOptions::default(),
            max_nodes: 200_000,
            reports: true,
            max_rotary_step_rad: std::f64::consts::FRAC_PI_2,
            bound_tip: false,
        }
    }

    /// Also bounding the tip's distance from the design tip path ([`Self::bound_tip`]).
    #[must_use]
    pub fn with_tip_bound(mut self, bound_tip: bool) -> Self {
        self.bound_tip = bound_tip;
        self
    }

    /// With another root method.
    #[must_use]
    pub fn with_method(mut self, method: RootMethod) -> Self {
        self.search.method = method;
        self
    }

    fn swept_for_tol(&self) -> MaxOptions {
        MaxOptions { floor: crate::numerics::tolerance::SWEPT_FLOOR_REL_TOL * self.tol_mm, ..self.swept }
    }
}

/// One chosen node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepNode {
    /// The block (cutter location and joints).
    pub block: Block,
    /// δ of the segment ending at this node (mm; `None` for the first node).
    pub total_mm: Option<f64>,
    /// The full report of that segment (when [`StepOptions::reports`]).
    pub report: Option<SegmentReport>,
    /// δ evaluations spent finding this node (bracketing included).
    pub evaluations: u32,
    /// Of those, spent bracketing.
    pub bracket_evaluations: u32,
    /// The segment was ended by [`StepOptions::max_rotary_step_rad`], not by the error.
    pub rotary_limited: bool,
    /// With [`StepOptions::bound_tip`]: the swept tip's largest distance from the design tip
    /// path over the segment ending here (mm).
    pub tip_design_mm: Option<f64>,
    /// The segment was ended by that tip distance, not by |δ| or the rotary step.
    pub tip_limited: bool,
}

/// The larger rotary move between two blocks (rad).
#[must_use]
pub fn rotary_step_rad(a: &Block, b: &Block) -> f64 {
    let (ja, jb) = (a.joints.rotary_rad, b.joints.rotary_rad);
    (jb[0] - ja[0]).abs().max((jb[1] - ja[1]).abs())
}

/// The nodes chosen along a path.
#[derive(Clone, Debug, PartialEq)]
pub struct StepPlan {
    /// Nodes, the first at the start of the path and the last at its end.
    pub nodes: Vec<StepNode>,
    /// The tolerance E (mm).
    pub tol_mm: f64,
    /// The root method used.
    pub method: RootMethod,
}

impl StepPlan {
    /// All δ evaluations (the paper's iteration count).
    #[must_use]
    pub fn total_evaluations(&self) -> u64 {
        self.nodes.iter().map(|n| u64::from(n.evaluations)).sum()
    }

    /// Number of segments (nodes − 1).
    #[must_use]
    pub fn segments(&self) -> usize {
        self.nodes.len().saturating_sub(1)
    }

    /// The largest |δ| of any segment (mm).
    #[must_use]
    pub fn worst_mm(&self) -> f64 {
        self.nodes.iter().filter_map(|n| n.total_mm).map(f64::abs).fold(0.0, f64::max)
    }
}

/// Chooses nodes along `path` so every segment's |δ| is E (module docs).
///
/// # Errors
/// A tolerance that is not positive; a location, tool axis or joint solution that cannot be
/// computed (out of travel: the message names the axis and angle); steps that underflow or
/// too many nodes.
pub fn plan_steps(machine: &Machine, path: &dyn DesignPath, opts: &StepOptions) -> Result<StepPlan, FiveAxisError> {
    let mut planner = StepPlanner::new(machine, path, opts)?;
    while !planner.is_done() {
        planner.next_node(machine, path)?;
    }
    Ok(planner.into_plan())
}

/// [`plan_steps`] one node at a time, for callers that must not block for a whole plan (an
/// app spreading the work over frames within a time budget). The planner keeps only its own
/// state: every call takes the same `machine` and `path` it was created with. Its nodes are
/// exactly those of [`plan_steps`].
#[derive(Clone, Debug)]
pub struct StepPlanner {
    opts: StepOptions,
    swept: MaxOptions,
    rotary_scale: f64,
    start: f64,
    end: f64,
    step: Option<f64>,
    nodes: Vec<StepNode>,
}

impl StepPlanner {
    /// Starts a plan: checks the tolerance and the range and computes the first block.
    ///
    /// # Errors
    /// As [`plan_steps`] for the tolerance, the range and the first block.
    pub fn new(machine: &Machine, path: &dyn DesignPath, opts: &StepOptions) -> Result<Self, FiveAxisError> {
        let tol = opts.tol_mm;
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(FiveAxisError::BadTolerance { tol_mm: tol });
        }
        let (start, end) = path.range();
        if !(start.is_finite() && end.is_finite() && end > start) {
            return Err(FiveAxisError::EmptyPath { start, end });
        }
        let rotary_scale = if opts.max_rotary_step_rad > 0.0 { tol / opts.max_rotary_step_rad } else { 0.0 };
        let first = block_at(machine, path, start, None)?;
        Ok(Self {
            opts: *opts,
            swept: opts.swept_for_tol(),
            rotary_scale,
            start,
            end,
            step: path.first_step(start, tol),
            nodes: vec![StepNode {
                block: first,
                total_mm: None,
                report: None,
                evaluations: 0,
                bracket_evaluations: 0,
                rotary_limited: false,
                tip_design_mm: None,
                tip_limited: false,
            }],
        })
    }

    /// Whether the last node is the end of the path.
    #[must_use]
    pub fn is_done(&self) -> bool {
        self.nodes.last().is_none_or(|n| n.block.location.s >= self.end)
    }

    /// The nodes chosen so far (the first is the start of the path).
    #[must_use]
    pub fn nodes(&self) -> &[StepNode] {
        &self.nodes
    }

    /// The settings.
    #[must_use]
    pub fn options(&self) -> &StepOptions {
        &self.opts
    }

    /// Finds the next node and returns it (the last one again once [`Self::is_done`]).
    ///
    /// # Errors
    /// As [`plan_steps`]; the nodes found before stay available.
    pub fn next_node(&mut self, machine: &Machine, path: &dyn DesignPath) -> Result<StepNode, FiveAxisError> {
        let tol = self.opts.tol_mm;
        let (swept, rotary_scale, end) = (self.swept, self.rotary_scale, self.end);
        let Some(&last) = self.nodes.last() else {
            return Err(FiveAxisError::EmptyPath { start: end, end });
        };
        let current = last.block;
        if current.location.s >= end {
            return Ok(last);
        }
        if self.nodes.len() >= self.opts.max_nodes {
            return Err(FiveAxisError::TooManyNodes {
                tol_mm: tol,
                max_nodes: self.opts.max_nodes,
                s: current.location.s,
            });
        }
        let from = current.location.s;
        let bound_tip = self.opts.bound_tip;
        // The tip's distance from the design tip path, when it is bounded too.
        let tip_of = |b: &Block| -> Result<Option<f64>, FiveAxisError> {
            bound_tip.then(|| tip_design_deviation(machine, path, &current, b, &swept)).transpose()
        };
        // Every candidate block with its δ and tip distance, so the accepted one is not
        // recomputed.
        let mut tried: Vec<(f64, Block, f64, Option<f64>)> = Vec::new();
        // Joints of the farthest candidate found within the tolerance: the inverse
        // kinematics of the next candidate continues from there, so the joints follow the
        // path through the evaluated points instead of jumping to another branch when a
        // trial step is long (a doubling can reach rotary moves past 90°).
        let mut anchor = (from, current.joints);
        let error = |s: f64| -> Result<f64, FiveAxisError> {
            let prev = if anchor.0 < s { anchor.1 } else { current.joints };
            let b = block_at(machine, path, s, Some(&prev))?;
            let t = segment_total(machine, path, &current, &b, &swept)?;
            let tip = tip_of(&b)?;
            tried.push((s, b, t.total_mm, tip));
            let v = t.total_mm.abs().max(rotary_scale * rotary_step_rad(&current, &b)).max(tip.unwrap_or(0.0));
            if v < tol && s > anchor.0 {
                anchor = (s, b.joints);
            }
            Ok(v)
        };
        let first_step = self.step.unwrap_or((end - from) / 16.0);
        let found = next_node(error, from, end, first_step, tol, &self.opts.search).map_err(|e| match e {
            SearchFailure::Eval(e) => e,
            SearchFailure::NotFinite { s } => FiveAxisError::NotFinite { s },
            SearchFailure::Underflow { s_from, error_mm } => {
                FiveAxisError::Underflow { s: s_from, error_mm, tol_mm: tol }
            }
            SearchFailure::NoConvergence { s_from, evaluations } => {
                FiveAxisError::NoConvergence { s: s_from, evaluations }
            }
        })?;
        // A node placed where δ jumps across E (the search's bracket shrank to rounding)
        // with next to no progress means the error is discontinuous right ahead: each further
        // node would stop at the same jump a rounding step later, for hundreds of thousands
        // of nodes. Refuse at once, with the error just past the jump.
        if found.jumped && found.s - from <= tolerance::STEP_STALL_REL * (end - self.start).abs() {
            let past = tried.iter().filter(|t| t.0 > found.s).min_by(|a, b| a.0.total_cmp(&b.0)).map_or(tol, |t| t.2);
            return Err(FiveAxisError::Underflow { s: from, error_mm: past, tol_mm: tol });
        }
        let (block, total, tip) = match tried.iter().rev().find(|t| t.0.to_bits() == found.s.to_bits()) {
            Some(&(_, b, e, tip)) => (b, e, tip),
            None => {
                let b = block_at(machine, path, found.s, Some(&current.joints))?;
                let e = segment_total(machine, path, &current, &b, &swept)?.total_mm;
                let tip = tip_of(&b)?;
                (b, e, tip)
            }
        };
        let report =
            if self.opts.reports { Some(segment_report(machine, path, &current, &block, &swept)?) } else { None };
        let rotary = rotary_scale * rotary_step_rad(&current, &block);
        // Ended by the tip: it is the largest term and reached the tolerance (the last
        // segment, cut short by the end of the path, is ended by nothing).
        let tip_limited = tip.is_some_and(|t| t > total.abs() && t > rotary && t >= 0.99 * tol);
        let rotary_limited = !tip_limited && rotary > total.abs();
        let node = StepNode {
            block,
            total_mm: Some(total),
            report,
            evaluations: found.evaluations,
            bracket_evaluations: found.bracket_evaluations,
            rotary_limited,
            tip_design_mm: tip,
            tip_limited,
        };
        self.nodes.push(node);
        self.step = Some(found.s - from);
        Ok(node)
    }

    /// The plan (complete once [`Self::is_done`]; otherwise the nodes so far).
    #[must_use]
    pub fn into_plan(self) -> StepPlan {
        StepPlan { nodes: self.nodes, tol_mm: self.opts.tol_mm, method: self.opts.search.method }
    }
}

/// Blocks and segment reports for given node parameters (no search): to check a program —
/// e.g. the paper's Example 1 before steps are inserted, or chord nodes chosen without the
/// nonlinear error.
///
/// # Errors
/// As [`plan_steps`] for locations and joints.
pub fn evaluate_nodes(
    machine: &Machine,
    path: &dyn DesignPath,
    params: &[f64],
    swept: &MaxOptions,
) -> Result<Vec<StepNode>, FiveAxisError> {
    let mut out: Vec<StepNode> = Vec::with_capacity(params.len());
    for &s in params {
        let prev = out.last().map(|n| n.block);
        let block = block_at(machine, path, s, prev.as_ref().map(|b| &b.joints))?;
        let report = match prev {
            Some(a) => Some(segment_report(machine, path, &a, &block, swept)?),
            None => None,
        };
        out.push(StepNode {
            block,
            total_mm: report.map(|r| r.total_mm),
            report,
            evaluations: 0,
            bracket_evaluations: 0,
            rotary_limited: false,
            tip_design_mm: None,
            tip_limited: false,
        });
    }
    Ok(out)
}
