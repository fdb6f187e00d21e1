//! The iso-scallop paths, one after the other across the surface, each corrected from the cusp measured to the path before it.

use glam::{DVec2, DVec3};

use super::budget::{EXTRAPOLATION_ROOM, PROJECT_CELLS_UNTIL, check_stop};
use super::build::Reaches;
use super::side_step::{SCALLOP_FLOOR_REL, Step};
use super::{
    CELLS_ESTIMATE_AFTER, CELLS_ESTIMATE_AFTER_SHARE, Ctx, ESTIMATE_AFTER_SHARE, FinishOptions, FinishSetup, Layout,
    PathSet, PathStart, Pilot, Refusal, ScallopFlag, ToolPath, b_of,
};
use crate::fillet::FinishError;
use crate::fillet::gouge::PartSamples;
use crate::fillet::node::CcNode;
use crate::fillet::orient::Strategy;
use crate::geom::{LocalGeometry, ParametricSurface, Surface};
use crate::numerics::tolerance::DOMAIN_SLACK;

/// The measured cusp's band (× h) outside which the corrector builds a path again, the
/// cusp it aims at (× h), the most it scales a side step by in one round, and its rounds.
pub(super) const CUSP_BAND: (f64, f64) = (0.0, 1.04);

pub(super) const CUSP_TARGET: f64 = 0.995;

pub(super) const CUSP_SCALE: (f64, f64) = (0.6, 1.0);

pub(super) const CUSP_CORRECTIONS: usize = 4;

/// The share of the checks' budget (`FinishOptions::max_check_cells`) the corrector's
/// rebuilds may spend over a whole job, by default (`FinishOptions::corrector_share`); past
/// it the paths are built once each, their cusps still measured and named
/// ([`PathSet::scallop_flags`], [`PathSet::corrector_stopped_at`]).
///
/// Where a fold defeats it, the corrector rebuilds nearly every path four times and the
/// cusps stay at 40–640·h all the same: on fuzz blades and patches with a control point
/// moved 360 mm its rebuilds cost 2.4–4.3 times the paths' first builds (3–7·10⁷ cells,
/// measured by a probe), which the pilot (first builds and side steps, times
/// [`PILOT_CELLS_FACTOR`](super::PILOT_CELLS_FACTOR)) does not see, and such jobs ran to the
/// checks' stop after 20–24 s of CPU. The examples' correctors spend at most 6·10⁴ cells.
pub const CORRECTOR_CELLS_SHARE: f64 = 0.5;

/// A measured cusp above this many h after the corrector is named in
/// [`PathSet::scallop_flags`].
pub const FLAG_ABOVE: f64 = 1.10;

/// Half the span (mm along the path) over which [`smooth_factors`] takes the smallest
/// factor, and the most the factor changes per mm of path.
pub(super) const FACTOR_SPAN_MM: f64 = 3.0;

pub(super) const FACTOR_SLOPE: f64 = 0.02;

/// Most change of the side step along a path (mm per mm of path): the offset curve turns by
/// at most about this many radians from the path it offsets ([`limit_step_slope`]).
pub(super) const SIDE_STEP_SLOPE: f64 = 0.5;

/// The side steps lowered until they change along the path by at most [`SIDE_STEP_SLOPE`]
/// mm per mm between neighbouring nodes (the lower Lipschitz envelope, one pass each way):
/// a step far above its neighbours' (a side-step solution that jumped, a cusp correction at
/// one node) would bend the offset curve into a kink that the next path's feed, and with it
/// its side steps, turns with; lowering never widens a scallop.
pub(super) fn limit_step_slope(nodes: &[CcNode], steps: &mut [Step]) {
    let gap = |i: usize, j: usize| match (nodes.get(i), nodes.get(j)) {
        (Some(a), Some(b)) => (b.frame.point - a.frame.point).length(),
        _ => 0.0,
    };
    for k in 1..steps.len() {
        let cap = steps[k - 1].width_mm + SIDE_STEP_SLOPE * gap(steps[k - 1].node, steps[k].node);
        steps[k].width_mm = steps[k].width_mm.min(cap);
    }
    for k in (0..steps.len().saturating_sub(1)).rev() {
        let cap = steps[k + 1].width_mm + SIDE_STEP_SLOPE * gap(steps[k].node, steps[k + 1].node);
        steps[k].width_mm = steps[k].width_mm.min(cap);
    }
}

/// The corrector's factors made smooth along the path: each the smallest within
/// [`FACTOR_SPAN_MM`] of its node, then lowered until it changes by at most
/// [`FACTOR_SLOPE`] per mm (a step scaled at one node and not at the next would put a kink
/// into the offset curve, which the paths after it inherit).
pub(super) fn smooth_factors(nodes: &[CcNode], steps: &[Step], factors: &[f64]) -> Vec<f64> {
    let at: Vec<f64> = {
        let mut s = 0.0;
        let mut prev: Option<DVec3> = None;
        steps
            .iter()
            .map(|st| {
                let p = nodes.get(st.node).map_or(DVec3::ZERO, |n| n.frame.point);
                if let Some(q) = prev {
                    s += (p - q).length();
                }
                prev = Some(p);
                s
            })
            .collect()
    };
    let mut out: Vec<f64> = (0..factors.len())
        .map(|k| {
            let lo = at.partition_point(|&x| x < at[k] - FACTOR_SPAN_MM);
            let hi = at.partition_point(|&x| x <= at[k] + FACTOR_SPAN_MM);
            factors[lo..hi.max(lo + 1).min(factors.len())].iter().copied().fold(factors[k], f64::min)
        })
        .collect();
    for k in 1..out.len() {
        out[k] = out[k].min(out[k - 1] + FACTOR_SLOPE * (at[k] - at[k - 1]));
    }
    for k in (0..out.len().saturating_sub(1)).rev() {
        out[k] = out[k].min(out[k + 1] + FACTOR_SLOPE * (at[k + 1] - at[k]));
    }
    out
}

/// Iso-scallop paths from the first path `setup.start` says (module docs). The same as
/// running [`IsoScallopSteps::start`] to its end.
///
/// # Errors
/// A bad option or start curve, no path at the start, or too many paths or nodes.
pub fn iso_scallop(setup: &FinishSetup) -> Result<PathSet, FinishError> {
    iso_scallop_checked(setup, |_| Ok(()))
}

/// What [`iso_scallop_checked`] shows its caller as the job goes, in the order of the work.
#[derive(Clone, Copy, Debug)]
pub enum Built<'a> {
    /// The job's pilot, before any path is built (when it solved a side step): its estimate
    /// of the job and its short runs built as the job's paths are.
    Pilot(&'a Pilot),
    /// A path just built.
    Path {
        /// Its index in the set, in the order of machining.
        index: usize,
        /// The path.
        path: &'a ToolPath,
        /// The share of the surface covered so far, 0–1 ([`IsoScallopSteps::progress`]).
        covered: f64,
    },
}

/// [`iso_scallop`] with `check` shown the job's pilot before any path, then every path as
/// soon as it is built ([`Built`]): the first `Err` stops the job there, before the paths
/// after it are built. A caller that refuses a job for what one path does (a tool axis its
/// machine cannot reach, say) refuses it at that path, not after all of them; one that can
/// judge from the pilot refuses it before the paths.
///
/// # Errors
/// What [`iso_scallop`] refuses, or the first error of `check`.
pub fn iso_scallop_checked<E: From<FinishError>>(
    setup: &FinishSetup,
    mut check: impl FnMut(Built<'_>) -> Result<(), E>,
) -> Result<PathSet, E> {
    let mut steps = IsoScallopSteps::start_checked(setup, |p| check(Built::Pilot(p)))?;
    let mut checked = 0;
    loop {
        let covered = steps.progress(setup.surface);
        // Every path the last call added.
        for (index, path) in steps.paths().iter().enumerate().skip(checked) {
            check(Built::Path { index, path, covered })?;
        }
        checked = steps.paths().len();
        if steps.is_done() {
            return Ok(steps.finish());
        }
        steps.step(setup)?;
    }
}

/// Iso-scallop paths built one path per call, for callers that spread the work over time
/// (the app's tab). [`IsoScallopSteps::start`] builds the first path; every
/// [`IsoScallopSteps::step`] builds the next one from the side steps of the last; the
/// result is exactly [`iso_scallop`]'s. Every call must get the same [`FinishSetup`] as
/// `start` (`step` keeps the strategy and the start `start` was given).
///
/// From a start curve the paths go to both sides, in this order (the order of machining):
/// the curve, the paths toward increasing b outward to b_max, then — after a linking move —
/// the paths toward decreasing b outward from the curve to b_min. Each path's side steps
/// and scallops are to the next path of its own side (the curve's: to the first path toward
/// increasing b); the last path of each side has none.
#[derive(Clone, Debug)]
pub struct IsoScallopSteps {
    strategy: Strategy,
    along: usize,
    /// +1 when c points toward increasing b (at the first path's first node).
    c_sign: f64,
    /// +1 while the paths advance toward increasing b, −1 toward decreasing b.
    toward: f64,
    /// The path the next step offsets from.
    frontier: usize,
    /// Whether the side toward decreasing b is still to be done from the start curve.
    second_side: bool,
    /// Whether that side is being done.
    in_second_side: bool,
    /// Where the covered band began (b, internal units): the edge or the curve's lowest b.
    start_b: f64,
    /// The index of the second side's first path, once built.
    second_side_at: Option<usize>,
    refused: Vec<Refusal>,
    flags: Vec<ScallopFlag>,
    budget: usize,
    /// The checking work so far (see [`Ctx::count_check`]): the part's cell count when the
    /// job started and the CC points checked.
    cells_at_start: u64,
    work_at_start: u64,
    nodes_checked: u64,
    paths: Vec<ToolPath>,
    done: bool,
    /// The strip's reaches of the last path's nodes, for the next step's side steps.
    reaches: Reaches,
    /// The CC points the job's pilot estimated (0 without a pilot): what the checks' cost
    /// per point so far is projected over.
    pilot_nodes: f64,
    /// Cells the corrector's rebuilds have checked so far, and the first path it left
    /// uncorrected for [`CORRECTOR_CELLS_SHARE`].
    corrector_cells: u64,
    corrector_stopped_at: Option<usize>,
}

impl IsoScallopSteps {
    /// Checks the options and the start, and builds the first path where `setup.start`
    /// says.
    ///
    /// # Errors
    /// A bad option or start curve, or no path at the start.
    pub fn start(setup: &FinishSetup) -> Result<Self, FinishError> {
        Self::start_checked(setup, |_| Ok(()))
    }

    /// [`Self::start`] with `check_pilot` shown the job's pilot (when it solved a side step)
    /// before the first path is built: its first `Err` stops the job there.
    ///
    /// # Errors
    /// What [`Self::start`] refuses, or the error of `check_pilot`.
    pub fn start_checked<E: From<FinishError>>(
        setup: &FinishSetup,
        check_pilot: impl FnOnce(&Pilot) -> Result<(), E>,
    ) -> Result<Self, E> {
        let FinishSetup { surface, strategy, options: opts, start, .. } = *setup;
        let reaches = std::cell::RefCell::new(Reaches::default());
        let mut ctx = Ctx::start(setup)?;
        ctx.reaches = Some(&reaches);
        let along = ctx.along;
        let (_, (b0, b1)) = ctx.ranges();
        let poly = ctx.first_polyline(start)?;
        let (toward, second_side) = match start {
            PathStart::Boundary(e) if e.at_max() => (-1.0, false),
            PathStart::FirstBoundary | PathStart::Boundary(_) => (1.0, false),
            PathStart::Curve(_) => (1.0, true),
        };
        let start_b = match start {
            PathStart::Curve(_) => poly.iter().map(|&p| b_of(p, along)).fold(b1, f64::min),
            _ => b0,
        };
        let pilot = ctx.refuse_oversized(&poly)?;
        if let Some(pilot) = &pilot {
            check_pilot(pilot)?;
        }
        let mut refused = Vec::new();
        let mut budget = opts.max_nodes;
        let first = ctx.build_path(&poly, None, &mut refused, &mut budget)?;
        let Some(n0) = first.nodes.iter().find(|n| !n.lead_out) else {
            return Err(FinishError::NoPath { reason: refused.first().map_or("no CC point", |r| r.reason) }.into());
        };
        // c toward increasing b?
        let g = LocalGeometry::try_new(surface.derivatives_at(n0.frame.uv));
        let tc = g.map_or(DVec2::ZERO, |g| g.tangent_coords(n0.frame.cross));
        let c_sign = if b_of(tc, along) >= 0.0 { 1.0 } else { -1.0 };
        Ok(Self {
            strategy,
            along,
            c_sign,
            toward,
            frontier: 0,
            second_side,
            in_second_side: false,
            start_b,
            second_side_at: None,
            refused,
            flags: Vec::new(),
            budget,
            cells_at_start: ctx.cells_at_start,
            work_at_start: ctx.work_at_start,
            nodes_checked: ctx.nodes_checked.get(),
            paths: vec![first],
            done: false,
            reaches: reaches.into_inner(),
            pilot_nodes: pilot.map_or(0.0, |p| p.cc_points),
            corrector_cells: 0,
            corrector_stopped_at: None,
        })
    }

    /// The current side is covered: on to the other side of the start curve, or done.
    /// Returns whether all is done.
    fn end_side(&mut self) -> bool {
        if self.second_side {
            self.second_side = false;
            self.in_second_side = true;
            self.toward = -1.0;
            self.frontier = 0;
            false
        } else {
            self.done = true;
            true
        }
    }

    /// Builds the next path; `Ok(true)` when the surface is covered (then further calls do
    /// nothing).
    ///
    /// # Errors
    /// Too many paths or nodes.
    pub fn step(&mut self, setup: &FinishSetup) -> Result<bool, FinishError> {
        let FinishSetup { surface, cutter, options: opts, part, reach, .. } = *setup;
        if self.done {
            return Ok(true);
        }
        let along = self.along;
        let (side, toward) = (self.c_sign * self.toward, self.toward);
        // Taken for this step and put back at its end (a step that ends the side early
        // leaves it empty: the next one computes the reaches again).
        let reaches = std::cell::RefCell::new(std::mem::take(&mut self.reaches));
        reaches.borrow_mut().next_path();
        let ctx = Ctx {
            surface,
            cutter: *cutter,
            strategy: self.strategy,
            opts,
            part,
            along,
            side,
            toward,
            cells_at_start: self.cells_at_start,
            work_at_start: self.work_at_start,
            nodes_checked: std::cell::Cell::new(self.nodes_checked),
            reaches: Some(&reaches),
            reach,
        };
        let (_, (b0, b1)) = ctx.ranges();
        if self.paths.len() >= opts.max_paths {
            return Err(FinishError::TooManyPaths { max_paths: opts.max_paths });
        }
        // The side steps from the start curve toward decreasing b are not stored on it: it
        // keeps those to the next path in the order of machining.
        let keep = !(self.in_second_side && self.frontier == 0);
        // The index the path built here will have.
        let next_index = self.paths.len();
        let Some(last) = self.paths.get_mut(self.frontier) else {
            self.done = true;
            return Ok(true);
        };
        let slack = DOMAIN_SLACK * (b1 - b0);
        let on_far_edge = |uv: DVec2| {
            let b = b_of(uv, along);
            if toward > 0.0 { b >= b1 - slack } else { b <= b0 + slack }
        };
        if last.nodes.iter().all(|n| on_far_edge(n.frame.uv)) {
            return Ok(self.end_side());
        }
        // The side steps predicted from each node's cross profile (one per node, with whether
        // it reached the far edge).
        let mut steps: Vec<Step> = Vec::with_capacity(last.nodes.len());
        for (i, node) in last.nodes.iter().enumerate().filter(|(_, n)| !n.lead_out) {
            let solved = ctx.side_step(node)?;
            steps.push(Step {
                node: i,
                width_mm: solved.width_mm,
                beyond: solved.beyond,
                predicted_mm: solved.scallop_mm,
            });
        }
        limit_step_slope(&last.nodes, &mut steps);
        let Some((poly, refs)) = ctx.offset_curve(&last.nodes, &steps) else {
            return Ok(self.end_side());
        };
        let (refused_before, budget_before) = (self.refused.len(), self.budget);
        let mut next = ctx.build_path(&poly, Some(&refs), &mut self.refused, &mut self.budget)?;
        // The corrector: the cusp measured between the path just built and this one, from
        // their swept cutters; where it leaves the band, the side steps there are scaled by
        // √(h / cusp) (the cusp grows with the square of the step) and the path built again.
        let tool = self.strategy.cutter_for(cutter);
        let h = opts.scallop_mm;
        let mut measured = ctx.measure_cusps(&tool, &last.nodes, &next.nodes, &steps);
        let off = |m: &Option<f64>| m.is_some_and(|c| c > CUSP_BAND.1 * h || c < CUSP_BAND.0 * h);
        // The rounds go on from the last trial (a round that made the cusp worse can still
        // lead to a better one); the one kept leaves the least cusp over the band, summed
        // over the nodes.
        let excess = |ms: &[Option<f64>]| ms.iter().flatten().map(|c| (c - CUSP_BAND.1 * h).max(0.0)).sum::<f64>();
        let mut best_excess = excess(&measured);
        let mut current = (steps.clone(), measured.clone());
        // Corrected only for the strategies whose paths are meant to leave h (matched, ball);
        // the fixed-lead and principal-axis cutters cannot match a concave surface's
        // curvature by their definition, and correcting them only spends checks (on the
        // mould, past the job's budget): their cusps are measured and named.
        let rounds = if matches!(self.strategy, Strategy::Matched | Strategy::Ball) { CUSP_CORRECTIONS } else { 0 };
        // The rebuilds' cells over the job, against their share of the checks' budget.
        let corrector_cap = (opts.corrector_share * opts.max_check_cells as f64) as u64;
        let cells_before_rounds = part.cells_checked();
        for _ in 0..rounds {
            if !current.1.iter().any(off) {
                break;
            }
            if self.corrector_cells + part.cells_checked().saturating_sub(cells_before_rounds) >= corrector_cap {
                self.corrector_stopped_at.get_or_insert(next_index);
                break;
            }
            let factors: Vec<f64> = current
                .1
                .iter()
                .map(|m| match *m {
                    Some(c) if off(m) => {
                        (CUSP_TARGET * h / c.max(SCALLOP_FLOOR_REL * h)).sqrt().clamp(CUSP_SCALE.0, CUSP_SCALE.1)
                    }
                    _ => 1.0,
                })
                .collect();
            let factors = smooth_factors(&last.nodes, &current.0, &factors);
            let mut trial = current.0.clone();
            for (st, f) in trial.iter_mut().zip(&factors) {
                st.width_mm *= f;
            }
            limit_step_slope(&last.nodes, &mut trial);
            let Some((poly, refs)) = ctx.offset_curve(&last.nodes, &trial) else { break };
            let mut refused = self.refused[..refused_before].to_vec();
            let mut budget = budget_before;
            let again = ctx.build_path(&poly, Some(&refs), &mut refused, &mut budget)?;
            let again_measured = ctx.measure_cusps(&tool, &last.nodes, &again.nodes, &trial);
            let e = excess(&again_measured);
            if e < best_excess {
                best_excess = e;
                (steps, next, measured) = (trial.clone(), again, again_measured.clone());
                self.refused = refused;
                self.budget = budget;
            }
            current = (trial, again_measured);
        }
        self.corrector_cells += part.cells_checked().saturating_sub(cells_before_rounds);
        // Where no round brought the cusp within FLAG_ABOVE·h, the place is named.
        for (st, m) in steps.iter().zip(&measured) {
            if let (Some(c), Some(node)) = (*m, last.nodes.get(st.node))
                && c > FLAG_ABOVE * h
            {
                self.flags.push(ScallopFlag {
                    uv: node.frame.uv,
                    point: node.frame.point,
                    path: self.frontier,
                    scallop_mm: c,
                });
            }
        }
        if keep {
            for (st, m) in steps.iter().zip(&measured) {
                if let Some(node) = last.nodes.get_mut(st.node) {
                    node.side_step_mm = Some(st.width_mm);
                    node.scallop_mm = Some(m.unwrap_or(st.predicted_mm));
                }
            }
        }
        self.nodes_checked = ctx.nodes_checked.get();
        self.reaches = reaches.into_inner();
        if next.nodes.is_empty() {
            return Ok(self.end_side());
        }
        self.paths.push(next);
        self.frontier = self.paths.len() - 1;
        // Refused as soon as the share covered says the whole would pass the cap (one side
        // from an edge; a start curve's two sides are left to the cap itself).
        if !self.second_side && !self.in_second_side {
            let share = self.progress(surface);
            let used = (opts.max_nodes - self.budget) as f64;
            if share >= ESTIMATE_AFTER_SHARE && used / share > opts.max_nodes as f64 {
                return Err(FinishError::Oversized {
                    paths: self.paths.len() as f64 / share,
                    nodes: used / share,
                    max_paths: opts.max_paths,
                    max_nodes: opts.max_nodes,
                });
            }
            // The checks' cost from the share covered, refused when it reads twice the stop,
            // for a job without a pilot only. With one, the cost per CC point is projected
            // over the pilot's points early on (`refuse_costly_checks`), and later the stop
            // itself stops the job: the share read early is far out where the checks' cost
            // is not spread evenly over the surface (fuzz jobs that complete in 8–20 s read
            // 7–16 times their final cells early on, and were refused by it after 2–5 s).
            let cells = part.cells_checked().saturating_sub(self.cells_at_start) as f64;
            let stop = check_stop(opts.max_check_cells) as f64;
            if self.pilot_nodes == 0.0
                && share >= CELLS_ESTIMATE_AFTER_SHARE
                && cells >= CELLS_ESTIMATE_AFTER
                && cells / share > EXTRAPOLATION_ROOM * stop
            {
                return Err(FinishError::TooMuchChecking {
                    detail: format!(
                        "would pass {stop} cells: about {:.2e} (estimated from the {:.0} % of the surface covered)",
                        cells / share,
                        share * 100.0
                    ),
                });
            }
        }
        self.refuse_costly_checks(part, opts)?;
        if self.in_second_side && self.second_side_at.is_none() {
            self.second_side_at = Some(self.frontier);
        }
        Ok(false)
    }

    /// Refuses the job once its checks' cost per CC point so far, times the CC points its
    /// pilot estimated (or those built, when more), passes the checks' stop
    /// ([`check_stop`]): the pilot's cost per point was far out, and the stop itself would
    /// come after most of the work. Read from [`CELLS_ESTIMATE_AFTER`] cells (a few paths)
    /// to [`PROJECT_CELLS_UNTIL`] of the stop.
    ///
    /// Projected this way the checks' cost read at most 1.02 times the job's final cost, at
    /// any path, on the 94 jobs measured (the three examples' tables, and the unseen surfaces
    /// of `tests/core/fillet_unseen.rs`, seeds 24 and 25, 40 jobs each), where extrapolated
    /// from the share of the surface covered it read up to 3.9 times. That extrapolation
    /// refused jobs that complete in 4 s under the budget (fuzz cases with a corner of the
    /// patch pulled onto another, whose first paths' far end hardly moves), and let one whose
    /// pilot was low (the patch with its middle raised 360 mm) run to the stop, 18 s (that
    /// job's pilot now refuses it, [`PILOT_LOW_BY`](super::PILOT_LOW_BY)). It reads
    /// high where the job covers less of the surface than its pilot (a fold whose far part
    /// is refused point by point): hence the window. Past it only the stop stops the job.
    fn refuse_costly_checks(&self, part: &PartSamples, opts: &FinishOptions) -> Result<(), FinishError> {
        let cells = part.cells_checked().saturating_sub(self.cells_at_start) as f64;
        let used = (opts.max_nodes - self.budget) as f64;
        let stop = check_stop(opts.max_check_cells);
        if self.pilot_nodes == 0.0
            || cells < CELLS_ESTIMATE_AFTER
            || cells > PROJECT_CELLS_UNTIL * stop as f64
            || used < 1.0
        {
            return Ok(());
        }
        let nodes = self.pilot_nodes.max(used);
        let projected = cells / used * nodes;
        if projected > stop as f64 {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "would pass {stop} cells: about {projected:.3e} ({:.0} cells a CC point on the {used:.0} built, over the {nodes:.0} the job is estimated to take)",
                    cells / used
                ),
            });
        }
        Ok(())
    }

    /// The paths built so far (the last one's side steps and scallops are filled by the
    /// next `step`).
    #[must_use]
    pub fn paths(&self) -> &[ToolPath] {
        &self.paths
    }

    /// How far the paths have come across the surface, 0 … 1: the share of the surface's b
    /// range between where the paths began and the nearest node of the last path (1 when
    /// done). Advancing toward decreasing b (from the upper edge, or the start curve's
    /// second side), the share between the last path's farthest-back node and b_max.
    #[must_use]
    pub fn progress(&self, surface: &Surface) -> f64 {
        if self.done {
            return 1.0;
        }
        let d = surface.domain();
        let rb = if self.along == 0 { d.v } else { d.u };
        let span = rb.max - rb.min;
        let bs = || {
            self.paths.get(self.frontier).into_iter().flat_map(|p| p.nodes.iter()).map(|n| b_of(n.frame.uv, self.along))
        };
        let covered = if self.toward > 0.0 {
            bs().min_by(f64::total_cmp).map(|b| b - self.start_b)
        } else {
            bs().max_by(f64::total_cmp).map(|b| rb.max - b)
        };
        match covered {
            Some(c) if span > 0.0 => (c / span).clamp(0.0, 1.0),
            _ => 0.0,
        }
    }

    /// Whether the surface is covered.
    #[must_use]
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The CC points refused so far.
    #[must_use]
    pub fn refused(&self) -> &[Refusal] {
        &self.refused
    }

    /// The path set built so far (all of it once `step` returned `Ok(true)`).
    #[must_use]
    pub fn finish(self) -> PathSet {
        PathSet {
            paths: self.paths,
            layout: Layout::IsoScallop,
            strategy: self.strategy,
            along: self.along,
            refused: self.refused,
            second_side: self.second_side_at,
            scallop_flags: self.flags,
            corrector_stopped_at: self.corrector_stopped_at,
        }
    }
}
