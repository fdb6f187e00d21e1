//! What a job may cost, and its refusal before the work: the pilot's estimate of paths, CC points and check cells, and the check counter.

use glam::{DVec2, DVec3};

use super::{Ctx, FinishSetup, Sample, ToolPath, b_of, iso_curve, make_uv};
use crate::fillet::FinishError;
use crate::fillet::node::CcNode;
use crate::geom::{LocalGeometry, ParametricSurface};
use crate::numerics::limits::CommandShare;

/// What a job's pilot says it will take, and the short paths it built to say so
/// ([`pilot`]).
#[derive(Clone, Debug)]
pub struct Pilot {
    /// Paths the job is estimated to take.
    pub paths: f64,
    /// CC points the job is estimated to take.
    pub cc_points: f64,
    /// Certified check cells the job is estimated to spend.
    pub check_cells: f64,
    /// Check cells a CC point on the pilot, with [`PILOT_CELLS_FACTOR`].
    pub cells_per_point: f64,
    /// The job's paths' length along the surface, estimated: the paths times the pilot's
    /// lines' mean length (mm).
    pub length_mm: f64,
    /// The pilot's runs: short paths of consecutive forward steps built as the job's are
    /// (oriented, checked, chords certified), their lead-ins and lead-outs left out. A
    /// program made of them is the job's program in miniature (a simulation's work per mm).
    pub runs: Vec<ToolPath>,
}

/// The certified check cells the iso-scallop job `setup` would spend, estimated by the
/// pilot its own start runs ([`MAX_CHECK_CELLS`]): for a comparison table, which refuses
/// before any plan when its plans together would pass the budget they share (so the pilot
/// does not refuse the job for its cells here, only for its paths and CC points). 0 when
/// the pilot solved no side step.
///
/// # Errors
/// A bad option or start, no path at the start, or a job whose pilot's paths or CC points
/// pass their caps.
pub fn estimate_check_cells(setup: &FinishSetup) -> Result<f64, FinishError> {
    let ctx = Ctx::start(setup)?;
    let poly = ctx.first_polyline(setup.start)?;
    Ok(ctx.sized_pilot(&poly)?.map_or(0.0, |p| p.check_cells))
}

/// The pilot the iso-scallop job `setup` starts with (as its own start runs it), for an
/// estimate of work that follows the paths (a simulation of their program); `None` when it
/// solved no side step. Costs what the job's refusal before its paths costs: some
/// hundredths of a second on the examples.
///
/// # Errors
/// A bad option or start, no path at the start, or a job refused by its own pilot.
pub fn pilot(setup: &FinishSetup) -> Result<Option<Pilot>, FinishError> {
    let ctx = Ctx::start(setup)?;
    let poly = ctx.first_polyline(setup.start)?;
    ctx.refuse_oversized(&poly)
}

/// Most cells of the certified bottom checks ([`PartSamples::cells_checked`](crate::fillet::PartSamples::cells_checked)) a job may
/// spend on average per CC point, once [`CHECK_COST_SAMPLE`] points are checked. The
/// examples spend 190–1 470 (whole plans, every strategy and layout); a check stops at
/// 40 000 cells, which a surface far larger or more curved than the cutter reaches at every
/// pose tried (a NURBS with one control point at 10⁵ mm: minutes of checks that refuse
/// every point). Stopping there takes a few seconds instead.
pub const MAX_CHECK_CELLS_PER_NODE: u64 = 20_000;

/// CC points checked before [`MAX_CHECK_CELLS_PER_NODE`] applies.
pub const CHECK_COST_SAMPLE: u64 = 8;

/// Most cells of the certified bottom checks a whole job's pilot may estimate (the
/// examples: 0.9–12 million a job, a comparison table of ten plans shares it): some 7 s of
/// checking. The checks themselves stop at [`CHECK_STOP_FACTOR`] times this.
pub const MAX_CHECK_CELLS: u64 = 50_000_000;

/// A job whose pilot's estimate fits its budget of check cells (`max_check_cells`) is
/// stopped only when its checks pass this many times the budget (some 15 s at the default):
/// the room for the pilot's error, so that a job is refused by its pilot, within a second,
/// or built — not refused after most of its work. The pilot on four lines ran 1.0–7.3
/// times too low before [`PILOT_CELLS_FACTOR`] (69 jobs: the unseen family's first twelve,
/// the three examples and three fuzz cases, every strategy), 1.7 at the median; on
/// seven lines, with the factor, the jobs of the examples and three fuzz cases
/// take 0.34–9.3 times its estimate (0.78 at the median).
pub const CHECK_STOP_FACTOR: f64 = 2.0;

/// How many times low a job's pilot may read and its job still be built: a job is refused
/// by its pilot when this many times its estimate passes the checks' stop ([`check_stop`];
/// at the defaults an estimate over 3.3·10⁷ cells, a third of the stop), within a second,
/// rather than stopped after most of its work. The pilot's runs do not see the side-step
/// corrector's paths built again, and on a strongly folded surface the job checks 2–3 times
/// the cells a CC point its pilot measured: the bicubic patch with one control point raised
/// 360 mm (fuzz cases; `[2][0]`, `[0][2]`, `[1][2]`, `[2][3]`, `[3][2]`) reads 3.5–4.3·10⁷ cells and
/// takes 8.2·10⁷ to over 10⁸ (more than 1.1·10⁸ where it reaches the stop). The examples'
/// jobs read 0.9–12·10⁶.
pub const PILOT_LOW_BY: f64 = 3.0;

/// The pilot's cells, measured on its runs, are multiplied by this: the job builds paths
/// the pilot does not (the side-step corrector builds a path again where the measured cusp
/// leaves its band, and its narrower steps make more paths), measured 1.7 times the
/// pilot's at the median ([`CHECK_STOP_FACTOR`]'s jobs).
pub const PILOT_CELLS_FACTOR: f64 = 1.7;

/// An iso-scallop job without a pilot (none of its pilot's side steps could be solved) is
/// refused when its cells extrapolated from the share of the surface it has covered read
/// this many times its stop: the extrapolation's own error (the mould's fixed-lead plan
/// reads 1.45–2.1 times its final cost at 6–9 % of its surface, the unseen surfaces up to
/// 3.9 times early on). A job with a pilot does not read it: it projects its cost per CC
/// point over the pilot's CC points (`IsoScallopSteps::refuse_costly_checks`), and past
/// [`PROJECT_CELLS_UNTIL`] of the stop only the stop stops it. Read there, the share refused
/// fuzz jobs after 2–5 s that complete in 8–20 s: their checks' cost is not spread evenly
/// over the surface (the patch with a corner moved onto another reads 10–13 times its
/// final cells at 1–5 % of its surface, the blade with `[2][0]` moved to x = 3, 7–16 times).
pub(super) const EXTRAPOLATION_ROOM: f64 = 2.0;

/// Share of the checks' stop up to which an iso-scallop job's cost per CC point is
/// projected over its pilot's CC points (`IsoScallopSteps::refuse_costly_checks`): the
/// projection is there to spare the work, and is read while it can (a tenth of the stop is
/// about 1.5 s of checks). Later it has little left to spare, and it reads high on a job
/// that covers less of the surface than its pilot: a fuzz patch with an edge control point
/// pulled 360 mm out, folded, whose far part is refused point by point, completes with
/// 4.0·10⁷ cells over 5 700 CC points where its pilot counted 19 600, and its projection
/// passes the stop from 1.2·10⁷ cells on. Past it only the stop itself stops the job.
pub(super) const PROJECT_CELLS_UNTIL: f64 = 0.1;

/// Where a job's checks stop: [`CHECK_STOP_FACTOR`] × its budget.
#[must_use]
pub fn check_stop(max_check_cells: u64) -> u64 {
    (CHECK_STOP_FACTOR * max_check_cells as f64) as u64
}

/// The share of a command's work a finishing job's paths leave to what follows them (its
/// program's planning, a simulation of it): the command's whole less the `cells_checked`
/// as a share of the checks' stop ([`check_stop`] of `max_check_cells`), the cap the paths
/// alone may reach.
#[must_use]
pub fn share_after_paths(cells_checked: u64, max_check_cells: u64) -> CommandShare {
    let mut share = CommandShare::whole();
    share.spend(cells_checked as f64, check_stop(max_check_cells) as f64);
    share
}

/// A job whose paths or CC points, estimated before they are built
/// (`Ctx::refuse_oversized`), exceed their caps by this factor is refused at once; below
/// it the caps themselves stop the work as it goes.
pub const ESTIMATE_MARGIN: f64 = 1.25;

/// Share of the surface covered after which the iso-scallop paths' CC points are estimated
/// from the share, and the job refused when the estimate passes the cap.
pub const ESTIMATE_AFTER_SHARE: f64 = 0.05;

/// Cells checked after which an iso-scallop job's checks' total cost is projected: from
/// the cost per CC point over its pilot's CC points (refused above the checks' stop), and,
/// for a job without a pilot, from the share of the surface covered, from this share on
/// (refused at twice the stop).
pub const CELLS_ESTIMATE_AFTER_SHARE: f64 = 0.01;

/// See [`CELLS_ESTIMATE_AFTER_SHARE`].
pub const CELLS_ESTIMATE_AFTER: f64 = 1e6;

/// Runs of consecutive forward steps the pilot builds on each of its lines, and the steps
/// of a run: their CC points' side steps and checks are what the estimate measures.
pub(super) const PILOT_RUNS: usize = 6;

/// See [`PILOT_RUNS`].
pub(super) const PILOT_RUN: usize = 4;

/// Lines of the pilot: the first path's and iso-curves spread across the surface. Seven,
/// so that a band of costly checks narrower than a third of the surface is not missed
/// between them: on a fuzz case's blade with one control point raised 360 mm, 80 % of the
/// job's cells fall on 8 % of its area (a band 0.2 wide across, 20 000–54 000 cells a
/// point against some 1 000 elsewhere). Four lines passed either side of it and estimated
/// 2.3·10⁷ cells, under the budget, for a job of 8.9·10⁸ cells (131 s) that its checks'
/// extrapolation then refused after 4 s; seven estimate 1.26·10⁸ and refuse it (the whole
/// `finish` command: 0.15–0.22 s of CPU).
/// On the 30 jobs of the examples and three fuzz cases (every strategy) seven lines
/// estimate 0.81–2.3 times what four did (1.15 at the median), at twice the pilot's cost
/// (at most 0.06 s).
pub(super) const PILOT_LINES: usize = 7;

/// Iso-curves across, spread evenly over the along parameter, whose greatest length is the
/// width the paths must cover (the paths run the whole length, so the widest place sets
/// their count), and the points each is measured at. A fuzz blade with one control point
/// raised 360 mm is 80 mm across at both ends and the middle but 254 mm a quarter of the way
/// along: three curves (the start, the middle and the end, averaged) put its job at 54 paths
/// and 2.2e7 cells, under the budget, and its checks' extrapolation refused it after 5 s of
/// CPU; the widest of seventeen puts it at 169 paths and 6.9e7 cells, and the pilot refuses
/// it (the whole `simulate --finish` command: 0.03 s). On the examples the two agree within
/// 1 %.
pub(super) const WIDTH_CURVES: usize = 17;

pub(super) const WIDTH_POINTS: usize = 64;

/// One pilot line's measures ([`Ctx::pilot`]).
#[derive(Clone, Copy, Debug, Default)]
struct LineTally {
    /// Its forward steps.
    samples: f64,
    /// Its runs' forward steps, and the CC points they ended with (their certified chords'
    /// inserted points included, lead-outs not).
    run_samples: f64,
    run_nodes: f64,
    /// Cells its runs and their points' side steps checked.
    cells: f64,
    /// The sum and count of 1 / side step (1/mm) over its points whose side step was solved.
    inverse_sum: f64,
    inverse_count: usize,
}

impl LineTally {
    /// Paths a mm across where the line lies: its own points' mean, or `overall` (every
    /// line's) when none of its side steps was solved.
    fn per_mm(&self, overall: f64) -> f64 {
        if self.inverse_count > 0 { self.inverse_sum / self.inverse_count as f64 } else { overall }
    }
}

impl Ctx<'_> {
    /// Counts a checked CC point and stops the job once its checks cost far more than any
    /// usable part's ([`MAX_CHECK_CELLS_PER_NODE`], [`MAX_CHECK_CELLS`]), or its work passes
    /// the share a comparison table gave it (`FinishOptions::max_work`).
    pub(super) fn count_check(&self) -> Result<(), FinishError> {
        self.nodes_checked.set(self.nodes_checked.get() + 1);
        self.check_meter()
    }

    /// [`Self::count_check`]'s limits without a CC point counted: for the checks a CC point
    /// runs besides its own, the trial poses of its side step to the next path (up to
    /// [`SIDE_STEP_ROUNDS`](super::side_step::SIDE_STEP_ROUNDS) + 1 of them, each up to
    /// [`MAX_ADJUST_CELLS`](crate::fillet::gouge::MAX_ADJUST_CELLS)), so that one point's
    /// side step cannot spend millions of cells before the point's average is read. A fuzz
    /// case's mould with one control point raised 360 mm spent 14 million cells in the
    /// pilot's side steps between two points and was refused after 1.6 s of CPU.
    pub(super) fn check_meter(&self) -> Result<(), FinishError> {
        let nodes = self.nodes_checked.get();
        if let Some(max_work) = self.opts.max_work {
            let work = self.part.work_done().saturating_sub(self.work_at_start);
            if work > max_work {
                return Err(FinishError::OverShare { work, max_work });
            }
        }
        let cells = self.part.cells_checked().saturating_sub(self.cells_at_start);
        let stop = check_stop(self.opts.max_check_cells);
        if cells > stop {
            return Err(FinishError::TooMuchChecking {
                detail: format!("passed {stop} cells after {nodes} CC points"),
            });
        }
        // After CHECK_COST_SAMPLE points, or sooner once the cells spent would already put
        // that many points over the average (a first point costing a million cells).
        if (nodes >= CHECK_COST_SAMPLE || cells > CHECK_COST_SAMPLE * MAX_CHECK_CELLS_PER_NODE)
            && cells / nodes.max(1) > MAX_CHECK_CELLS_PER_NODE
        {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "cost {} cells a CC point over the first {} (more than {MAX_CHECK_CELLS_PER_NODE})",
                    cells / nodes.max(1),
                    nodes.max(1)
                ),
            });
        }
        Ok(())
    }

    /// Refuses a job whose paths would pass their caps by more than [`ESTIMATE_MARGIN`], or
    /// whose checks could pass their stop ([`PILOT_LOW_BY`] times the estimate over
    /// [`check_stop`]), before they are built. A pilot on the
    /// first path's polyline and on [`PILOT_LINES`] − 1 iso-curves across the surface: each
    /// line's forward steps counted (no orientation or check), [`PILOT_RUNS`] runs of
    /// [`PILOT_RUN`] of them built as paths (oriented, checked, chords certified) and their
    /// side steps solved. The paths across are the surface's width across times the mean of
    /// 1/side step; the CC points and cells are the width times the mean over the lines of
    /// the line's forward steps × its 1/side step × its runs' CC points (or cells) per step:
    /// each line stands for the paths where it lies. Taken as the product of the lines'
    /// means instead, two fuzz jobs whose paths crowd and lengthen toward a wall read
    /// 4.0·10⁷ and 4.6·10⁷ cells, under the budget, and ran 14–19 s to the checks' stop;
    /// this reads 6.1·10⁷ and 5.4·10⁷ and refuses them.
    pub(super) fn refuse_oversized(&self, poly: &[DVec2]) -> Result<Option<Pilot>, FinishError> {
        let Some(est) = self.sized_pilot(poly)? else { return Ok(None) };
        let (cells, cells_per_node, nodes) = (est.check_cells, est.cells_per_point, est.cc_points);
        let stop = check_stop(self.opts.max_check_cells);
        if PILOT_LOW_BY * cells > stop as f64 {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "could pass their stop of {stop} cells: about {cells:.2e} over about {nodes:.0} CC points (estimated before the paths are built, {cells_per_node:.0} cells a point on a pilot, with the paths it does not build), and a job can take {PILOT_LOW_BY} times its estimate"
                ),
            });
        }
        Ok(Some(est))
    }

    /// The pilot of [`Self::refuse_oversized`], refused only for its paths or CC points (a
    /// comparison table weighs its plans' cells together).
    fn sized_pilot(&self, poly: &[DVec2]) -> Result<Option<Pilot>, FinishError> {
        let Some(est) = self.pilot(poly)? else { return Ok(None) };
        let (paths, nodes) = (est.paths, est.cc_points);
        if paths > ESTIMATE_MARGIN * self.opts.max_paths as f64 || nodes > ESTIMATE_MARGIN * self.opts.max_nodes as f64
        {
            return Err(FinishError::Oversized {
                paths,
                nodes,
                max_paths: self.opts.max_paths,
                max_nodes: self.opts.max_nodes,
            });
        }
        Ok(Some(est))
    }

    /// The pilot of [`Self::refuse_oversized`]: the job's paths, CC points and check cells
    /// estimated from it; `None` when no side step could be solved on it.
    pub(super) fn pilot(&self, poly: &[DVec2]) -> Result<Option<Pilot>, FinishError> {
        let ((a0, a1), (b0, b1)) = self.ranges();
        let mut lines = vec![poly.to_vec()];
        for k in 1..PILOT_LINES {
            lines.push(iso_curve((a0, a1), b0 + (b1 - b0) * k as f64 / (PILOT_LINES - 1) as f64, self.along));
        }
        let mut side = None;
        let mut tallies: Vec<LineTally> = Vec::with_capacity(lines.len());
        let (mut run_paths, mut lines_mm) = (Vec::new(), 0.0);
        for line in &lines {
            let cells_before = self.part.cells_checked();
            let mut tally = LineTally::default();
            let mut budget = self.opts.max_nodes;
            let samples = self.forward_samples(line, None, &mut budget)?;
            tally.samples = samples.len() as f64;
            let points: Vec<DVec3> = samples.iter().map(|s| self.surface.point_at(s.0)).collect();
            lines_mm += points.windows(2).map(|w| (w[1] - w[0]).length()).sum::<f64>();
            // PILOT_RUNS runs of PILOT_RUN consecutive forward steps spread along the line,
            // each built as a path of its own: its chords are the job's chords, so their
            // certification inserts the points the job's would, and each check starts from
            // its neighbour's as in the job.
            let mut nodes: Vec<CcNode> = Vec::new();
            let mut scratch = Vec::new();
            let runs = PILOT_RUNS.min(samples.len().div_ceil(PILOT_RUN)).max(1);
            for r in 0..runs {
                let first = if runs == 1 { 0 } else { (samples.len() - PILOT_RUN.min(samples.len())) * r / (runs - 1) };
                let run: Vec<Sample> = samples.iter().skip(first).take(PILOT_RUN).copied().collect();
                tally.run_samples += run.len() as f64;
                let path = self.path_from_samples(run, &mut scratch, &mut budget)?;
                let cut: Vec<CcNode> = path.nodes.into_iter().filter(|n| !n.lead_out).collect();
                tally.run_nodes += cut.len() as f64;
                nodes.extend_from_slice(&cut);
                run_paths.push(ToolPath { nodes: cut });
            }
            // Not one of the points tried along the first path can be cut: the job stops
            // here, as it would after trying every point of that path.
            if side.is_none() && samples.len() > PILOT_RUNS * PILOT_RUN && nodes.is_empty() {
                return Err(FinishError::NoPath { reason: scratch.first().map_or("no CC point", |r| r.reason) });
            }
            // The side toward the far edge, from the first line's first node (as the job's).
            if side.is_none()
                && let Some(n0) = nodes.first()
            {
                let g = LocalGeometry::try_new(self.surface.derivatives_at(n0.frame.uv));
                let tc = g.map_or(DVec2::ZERO, |g| g.tangent_coords(n0.frame.cross));
                side = Some(if b_of(tc, self.along) >= 0.0 { 1.0 } else { -1.0 } * self.toward);
            }
            if let Some(side) = side {
                let ctx = Ctx { side, nodes_checked: std::cell::Cell::new(self.nodes_checked.get()), ..*self };
                for n in &nodes {
                    let inverse = 1.0 / ctx.side_step(n)?.width_mm;
                    if inverse > 0.0 && inverse.is_finite() {
                        tally.inverse_sum += inverse;
                        tally.inverse_count += 1;
                    }
                }
                self.nodes_checked.set(ctx.nodes_checked.get());
            }
            tally.cells = self.part.cells_checked().saturating_sub(cells_before) as f64;
            tallies.push(tally);
        }
        let count: usize = tallies.iter().map(|t| t.inverse_count).sum();
        if count == 0 {
            return Ok(None);
        }
        // Paths a mm across, from every side step solved.
        let per_mm = tallies.iter().map(|t| t.inverse_sum).sum::<f64>() / count as f64;
        let mut width = 0.0;
        for i in 0..WIDTH_CURVES {
            let a = a0 + (a1 - a0) * i as f64 / (WIDTH_CURVES - 1) as f64;
            let (mut prev, mut across): (Option<DVec3>, f64) = (None, 0.0);
            for j in 0..=WIDTH_POINTS {
                let p = self.surface.point_at(make_uv(a, b0 + (b1 - b0) * j as f64 / WIDTH_POINTS as f64, self.along));
                if let Some(q) = prev {
                    across += (p - q).length();
                }
                prev = Some(p);
            }
            width = f64::max(width, across);
        }
        // At least one path's width.
        let across = (width * per_mm).max(1.0) / per_mm;
        // Each line stands for the paths where it lies: its forward steps times its paths a
        // mm across, times its runs' CC points and cells per forward step, so that paths
        // that are longer, denser and costlier in the same place (toward a wall) are counted
        // as such, not as the product of the lines' means.
        let n = tallies.len() as f64;
        let nodes = across
            * tallies.iter().map(|t| t.per_mm(per_mm) * t.samples * t.run_nodes / t.run_samples.max(1.0)).sum::<f64>()
            / n;
        let cells = across
            * tallies.iter().map(|t| t.per_mm(per_mm) * t.samples * t.cells / t.run_samples.max(1.0)).sum::<f64>()
            / n
            * PILOT_CELLS_FACTOR;
        let paths = across * per_mm;
        Ok(Some(Pilot {
            paths,
            cc_points: nodes,
            check_cells: cells,
            cells_per_point: cells / nodes.max(1.0),
            length_mm: paths * lines_mm / lines.len() as f64,
            runs: run_paths,
        }))
    }
}
