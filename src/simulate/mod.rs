//! Cutting simulation on a dexel (extended Z-buffer) stock: any program the product writes
//! or reads is machined into a block, and the result is measured (height map, deviation
//! from a design surface, scallops, gouges, removed volume).
//!
//! Glossary:
//! - *ray*: a vertical line of the stock's grid, at the centre of a square cell;
//! - *pitch*: the spacing of the rays in x and y (mm), the simulation's resolution;
//! - *material interval*: a span (lo, hi) of z along a ray that holds material; a ray holds
//!   a sorted list of disjoint ones, so undercuts and side cuts of a tilted tool are kept;
//! - *dexel*: a ray with its material intervals (a "depth pixel"); the stock is a grid of
//!   them ([`stock::DexelStock`]);
//! - *swept envelope*: the solid a cutter sweeps along one move; removing it from the stock
//!   is, ray by ray, a 1-D interval subtraction of the span the ray crosses it in
//!   ([`sweep`]).
//!
//! Only Z rays (not tri-dexel): every program of the product machines from above (3-axis,
//! and 5-axis with the tool axis in the upper half-space), and the quantities measured —
//! height map, scallops, gouges against a surface seen from above — are read along Z. The
//! price is that a wall steeper than the pitch allows is resolved only to one pitch in x, y
//! (see docs/simulation.md for the error budget).
//!
//! Modules: [`stock`] (rays, interval subtraction), [`sweep`] (cutter and envelope against
//! a ray), [`program`] (moves from G-code and 5-axis plans), [`measure`] (maps and
//! statistics, CSV and PNG output), [`interior`] (a finishing program's interior band and
//! its scallop statistics), [`finish`] (seed 001's finishing programs), [`pipeline`] (make the
//! program, then simulate it: the steps the command line and the app's job share), [`bench`](mod@bench) (the
//! benchmark programs). Layout and error bounds: `docs/simulation.md`.

pub mod bench;
pub mod canon;
pub mod crash;
pub mod finish;
pub mod interior;
pub mod measure;
pub mod pipeline;
pub mod program;
pub mod stock;
pub mod sweep;

use glam::DVec3;
use thiserror::Error;

pub use crash::{Crash, CrashKind, CrashLog, TOUCH_MM};
pub use finish::{FinishProgram, stock_box_mm};
pub use interior::{INTERIOR_END_MM, INTERIOR_SIDE_MM, InteriorStats, interior_mask, interior_stats};
pub use measure::{
    Design, DeviationScan, FootSeed, HeightMap, SimStats, heights_csv, over_surface_signed_distance,
    part_signed_distance, png_rgb,
};
pub use program::{MoveKind, Program, SimMove};
pub use stock::{DexelStock, Grid, Interval};
pub use sweep::{BallSegment, LineSweep, ToolShape, line_span, tilted_span};

use crate::geom::{Cutter, CutterKind};

/// A cell count this close below a whole number (relative) is that whole number: a stock
/// 10 mm wide at pitch 0.1 has 100 rays, not 101, whatever the rounding of 10/0.1.
pub const GRID_ROUND_REL: f64 = 1e-9;

/// Accuracy (mm) of the iterative ray solves (fillet corner against a ray, fillet on a
/// sloped 3-axis move): far below any pitch.
pub const ROOT_TOL_MM: f64 = 1e-7;

/// Iteration cap of those solves (golden sections shrink a bracket 0.618× per step).
pub const MAX_SOLVE_ITERATIONS: usize = 100;

/// Horizontal motion (mm) below which a 3-axis move is a plunge; vertical motion below
/// which it is horizontal.
pub const SAME_POINT_MM: f64 = 1e-12;

/// |sin| below which a tool axis counts as horizontal (for the slab of a cylinder) or as
/// vertical (for its radial quadratic).
pub const AXIS_FLAT_SIN: f64 = 1e-12;

/// Material (mm of ray length, summed over a move's rays) below which a move is said to
/// remove nothing: the rounding of two envelopes that touch (a rapid retracting from the
/// end of a cut re-cuts that end's surface to within ~1e-15 mm).
pub const CUT_NOISE_MM: f64 = 1e-6;

/// Most tool positions one 5-axis move is sampled at (and most swept segments + 1).
pub const MAX_SAMPLES_PER_MOVE: usize = 10_000;

/// Default error bound of a ball end mill's swept 5-axis segments, as a fraction of the
/// pitch (Hausdorff distance between the segments' envelope and the interpolated motion's).
pub const SWEEP_TOL_PER_PITCH: f64 = 0.5;

/// Poses a 5-axis move is pre-sampled at to plan its samples or segments.
const PRE_SAMPLES: usize = 32;

/// Most ray visits (rays inside the boxes of all moves and samples) a run may need; a
/// program estimated above it is refused before it starts (about a minute of work).
pub const MAX_RAY_VISITS: f64 = 4e9;

/// What a ray update of a 5-axis move costs in ray updates of straight 3-axis moves:
/// measured 0.11–0.19 µs for a fillet end mill's poses (the corner solved by Newton's steps)
/// and 0.06–0.10 µs for the ball's swept segments, against 0.03 µs (the finishing examples'
/// programs at pitch 0.5 and 1 mm with each strategy, on the 2-core development machine).
pub const JOINT_UPDATE_COST: f64 = 6.0;

/// What a ray the shank and holder checks of a 5-axis move visit costs in ray updates of
/// straight moves ([`Counters::crash_visits`]): measured 0.043–0.050 µs against 0.03 µs (the
/// concave mould's programs, whose holder passes over the stock's walls: 16–81 million
/// such visits, more than the cutter's own updates).
pub const CRASH_VISIT_COST: f64 = 1.5;

/// Most work a run does ([`Simulation::work_done`], in straight-move ray updates): about
/// 20 s at the measured costs (100 million updates of 5-axis moves, or 600 million of
/// straight ones). A run is refused ([`pipeline::WorkMeter`]) as soon as what it has done,
/// scaled by the moves still to come, reads [`PROJECTED_WORK_ROOM`] times it, and stopped
/// when what it has done does.
pub const MAX_WORK: f64 = 6.25e8;

/// How far over [`MAX_WORK`] a run may go, as done or as projected, before it is refused:
/// the projection weighs the moves still to come by their estimated ray visits, which follow
/// the work only roughly.
pub const PROJECTED_WORK_ROOM: f64 = 1.25;

/// A count of rays as a message prints it: whole below a billion, else to three digits
/// with an exponent (a mistyped pitch gives 10²² rays, not 23 digits).
pub(crate) fn ray_count(rays: f64) -> String {
    if rays < 1e9 { format!("{rays:.0}") } else { format!("{rays:.2e}") }
}

/// Why a simulation could not be set up or run. Messages name the problem and the fix.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SimError {
    /// The stock block or pitch is unusable.
    #[error("{0}")]
    Stock(String),
    /// The grid would have too many rays.
    #[error(
        "a pitch of {pitch_mm} mm gives {} rays, more than the {max} allowed; raise the pitch or shrink the stock",
        ray_count(*rays)
    )]
    TooManyRays {
        /// Rays the grid would have.
        rays: f64,
        /// The cap.
        max: usize,
        /// The pitch asked for (mm).
        pitch_mm: f64,
    },
    /// The program cannot be turned into moves.
    #[error("{0}")]
    Program(String),
    /// The program would take too long on this grid.
    #[error(
        "the program would visit about {visits:.2e} rays on this grid, more than {max:.0e}; raise the pitch, shrink the stock or split the program"
    )]
    TooMuchWork {
        /// Estimated ray visits.
        visits: f64,
        /// The cap.
        max: f64,
    },
    /// A run's work passes [`MAX_WORK`], as done or as projected from the moves done.
    #[error(
        "the simulation would take too long on this grid: after {done} of {moves} moves{} it has done {} and projects {} for the whole program, more than the {} it may do ({}); raise the pitch, shrink the stock or split the program",
        if *line > 0 { format!(" (line {line})") } else { String::new() },
        work_units(*work), work_units(*projected), work_units(*max),
        if *max < MAX_WORK { "what the command's earlier work left it" } else { "about 20 s" }
    )]
    TooMuchWorkDone {
        /// Moves machined.
        done: usize,
        /// Moves in the program.
        moves: usize,
        /// Source line of the last move machined.
        line: usize,
        /// Work done ([`Simulation::work_done`]).
        work: f64,
        /// Work projected for the whole program.
        projected: f64,
        /// The cap ([`MAX_WORK`]).
        max: f64,
    },
    /// A finishing program's planning would pass the design evaluations it may spend
    /// ([`crate::fiveaxis::FiveAxisError::TooMuchWork`]).
    #[error("pass {pass}: {source}")]
    PlanWork {
        /// The pass being planned.
        pass: usize,
        /// The planner's refusal.
        source: crate::fiveaxis::FiveAxisError,
    },
    /// A finishing program's simulation, estimated before its paths are built
    /// ([`finish::WorkProjection`]), passes [`MAX_WORK`] by more than the estimate's room.
    #[error(
        "the simulation would take too long on this grid: estimated before the paths are built (from the finishing job's pilot), its program would take about {}, more than the {} a run may do (about 20 s); raise the pitch, shrink the stock, or raise the scallop height",
        work_units(*projected), work_units(*max)
    )]
    TooMuchFinishWork {
        /// Work projected for the whole program (straight-move ray updates).
        projected: f64,
        /// The cap ([`MAX_WORK`]).
        max: f64,
    },
}

/// Work as a message prints it: millions of straight-move ray updates.
fn work_units(w: f64) -> String {
    let m = w / 1e6;
    if m < 1e4 { format!("{m:.0} million ray updates") } else { format!("{m:.2e} million ray updates") }
}

/// Counts of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counters {
    /// Moves applied.
    pub moves: usize,
    /// Tool positions of 5-axis moves applied.
    pub samples: u64,
    /// Rays inside the moves' boxes.
    pub rays_visited: u64,
    /// Ray-interval updates: spans subtracted from a ray.
    pub ray_updates: u64,
    /// The part of `ray_updates` made by 5-axis moves.
    pub joint_updates: u64,
    /// Rays the shank and holder checks of 5-axis moves visited (inside a part's box at a
    /// checked pose, above the stock's lowest point there).
    pub crash_visits: u64,
    /// Material removed (mm³).
    pub removed_mm3: f64,
    /// Rapid moves (G00) that removed material.
    pub rapid_cuts: usize,
    /// Line of the first of them (0 for in-memory programs).
    pub first_rapid_cut_line: Option<usize>,
    /// Largest measured distance (mm) between the true pose at the middle of a swept
    /// ball-end segment of a 5-axis move and the straight interpolation the segment uses
    /// (its centre, and the top of its body): the sagitta part of the sweep error.
    pub sweep_sagitta_mm: f64,
}

/// A stock being machined by one cutter.
#[derive(Clone, Debug)]
pub struct Simulation {
    stock: DexelStock,
    tool: ToolShape,
    /// Largest displacement (mm) of any point of the cutter's body between two samples of a
    /// 5-axis move (default: the pitch), where 5-axis moves are sampled pose by pose.
    sample_step_mm: f64,
    /// Error bound (mm, Hausdorff) of the closed-form swept segments a ball end mill's 5-axis
    /// moves are cut in; `None` samples them pose by pose as the other cutters.
    sweep_tol_mm: Option<f64>,
    /// Tip and axis (mm, unit) where the last swept segment ended: a segment starting there
    /// skips the pose it shares with it.
    last_pose: Option<(DVec3, DVec3)>,
    counters: Counters,
    /// The sweep tolerance asked for by [`Self::with_sweep_tol`] (kept for later ball end
    /// mills after a tool change); `None`: the default.
    sweep_tol_asked: Option<f64>,
    /// Whether 5-axis moves are sampled pose by pose for every cutter
    /// ([`Self::with_sample_step`]).
    sampled: bool,
    /// Which tool slot cuts now ([`Self::set_tool`]), and, when asked for
    /// ([`Self::with_tool_map`]), the slot that last removed material from each ray
    /// ([`NO_TOOL`] where none did).
    slot: u16,
    tool_map: Option<Vec<u16>>,
    /// The crashes so far ([`crash`]).
    crashes: CrashLog,
    /// Whether moves are checked for crashes (default; off only to measure what the checks
    /// cost, [`Self::without_crash_checks`]).
    crash_checks: bool,
    /// The move being applied: its line, whether it is a rapid, its index in the run.
    now: MoveNow,
}

/// The move [`Simulation::apply`] is applying.
#[derive(Clone, Copy, Debug, Default)]
struct MoveNow {
    line: usize,
    rapid: bool,
    index: usize,
    /// The move's geometry: its end tip is computed only for a crash report.
    kind: Option<MoveKind>,
    /// Whether a move was applied before (the first one starts a block).
    started: bool,
}

/// A ray of the tool map no tool cut.
pub const NO_TOOL: u16 = u16::MAX;

impl Simulation {
    /// A simulation of `cutter` on `stock`; 5-axis moves are sampled so no point of the
    /// cutter moves more than one pitch between samples.
    #[must_use]
    pub fn new(stock: DexelStock, cutter: &Cutter) -> Self {
        let pitch = stock.grid().pitch_mm;
        let tool = ToolShape::of(cutter);
        let sweep_tol_mm = (tool.kind == CutterKind::Ball).then_some(pitch * SWEEP_TOL_PER_PITCH);
        Self {
            stock,
            tool,
            sample_step_mm: pitch,
            sweep_tol_mm,
            last_pose: None,
            counters: Counters::default(),
            sweep_tol_asked: None,
            sampled: false,
            slot: 0,
            tool_map: None,
            crashes: CrashLog::default(),
            crash_checks: true,
            now: MoveNow::default(),
        }
    }

    /// The same simulation without crash checks: the flutes cut as with them, no crash is
    /// looked for (the benchmarks measure what the checks cost with it).
    #[must_use]
    pub fn without_crash_checks(mut self) -> Self {
        self.crash_checks = false;
        self
    }

    /// The crashes found so far ([`crash`]).
    #[must_use]
    pub fn crashes(&self) -> &CrashLog {
        &self.crashes
    }

    /// Changes the cutter from the next move on (a program's tool change): `slot` numbers
    /// it in the tool map ([`Self::with_tool_map`]). The sampling and sweep settings asked
    /// for stay: a ball end mill cuts 5-axis moves in swept segments unless
    /// [`Self::with_sample_step`] was called.
    pub fn set_tool(&mut self, cutter: &Cutter, slot: u16) {
        self.tool = ToolShape::of(cutter);
        self.slot = slot;
        self.last_pose = None;
        let pitch = self.stock.grid().pitch_mm;
        self.sweep_tol_mm = (self.tool.kind == CutterKind::Ball && !self.sampled)
            .then(|| self.sweep_tol_asked.unwrap_or(pitch * SWEEP_TOL_PER_PITCH));
    }

    /// The same simulation recording, for every ray, the tool slot ([`Self::set_tool`]; 0 at
    /// the start) that last removed material from it.
    #[must_use]
    pub fn with_tool_map(mut self) -> Self {
        self.tool_map = Some(vec![NO_TOOL; self.stock.grid().len()]);
        self
    }

    /// The tool slot that last removed material from each ray (row-major, as the grid),
    /// [`NO_TOOL`] where none did; `None` unless [`Self::with_tool_map`] was called.
    #[must_use]
    pub fn tool_map(&self) -> Option<&[u16]> {
        self.tool_map.as_deref()
    }

    /// The same simulation sampling 5-axis moves pose by pose (every cutter, the ball end
    /// mill included) so no point of the cutter's body moves more than `step_mm` between two
    /// tool positions (a non-positive or non-finite step keeps the pitch): the dense
    /// reference the swept segments are measured against.
    #[must_use]
    pub fn with_sample_step(mut self, step_mm: f64) -> Self {
        if step_mm > 0.0 && step_mm.is_finite() {
            self.sample_step_mm = step_mm;
        }
        self.sweep_tol_mm = None;
        self.sampled = true;
        self
    }

    /// The same simulation cutting a ball end mill's 5-axis moves in closed-form swept
    /// segments within `tol_mm` (Hausdorff) of the interpolated motion (a non-positive or
    /// non-finite value keeps the default, [`SWEEP_TOL_PER_PITCH`] × pitch). No effect on
    /// other cutters.
    #[must_use]
    pub fn with_sweep_tol(mut self, tol_mm: f64) -> Self {
        if tol_mm > 0.0 && tol_mm.is_finite() {
            self.sweep_tol_asked = Some(tol_mm);
        }
        if self.tool.kind == CutterKind::Ball {
            let pitch = self.stock.grid().pitch_mm;
            self.sweep_tol_mm =
                Some(if tol_mm > 0.0 && tol_mm.is_finite() { tol_mm } else { pitch * SWEEP_TOL_PER_PITCH });
        }
        self
    }

    /// The sweep tolerance (mm) of a ball end mill's 5-axis segments, `None` when 5-axis
    /// moves are sampled pose by pose.
    #[must_use]
    pub fn sweep_tol_mm(&self) -> Option<f64> {
        self.sweep_tol_mm
    }

    /// The stock as machined so far.
    #[must_use]
    pub fn stock(&self) -> &DexelStock {
        &self.stock
    }

    /// The stock as machined so far, the simulation given up (one that only estimated a
    /// program's work hands its stock, untouched, to the run).
    #[must_use]
    pub fn into_stock(self) -> DexelStock {
        self.stock
    }

    /// The simulated cutter shape.
    #[must_use]
    pub fn tool(&self) -> &ToolShape {
        &self.tool
    }

    /// Counts so far.
    #[must_use]
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// Height above the tip (mm) up to which the body of a tool at this pose can reach below
    /// the stock's top: a body point at height h along the axis a lies at least
    /// h·a_z − R·√(1 − a_z²) above the tip, so above the stock beyond this. Negative when the
    /// whole tool is above the stock; H for an axis pointing sideways or down.
    #[must_use]
    pub fn reach_mm(&self, tip: DVec3, axis: DVec3) -> f64 {
        let (_, z1) = self.stock.z_range_mm();
        let t = &self.tool;
        let sin = (1.0 - axis.z * axis.z).max(0.0).sqrt();
        if axis.z > AXIS_FLAT_SIN { ((z1 - tip.z + t.radius_mm * sin) / axis.z).min(t.top_mm) } else { t.top_mm }
    }

    /// Tool positions a 5-axis move is sampled at (2 to [`MAX_SAMPLES_PER_MOVE`]): enough
    /// that no point of the body that can reach below the stock's top ([`Self::reach_mm`])
    /// moves more than the sample step between two of them — the tip's travel plus the axis'
    /// turn times that reach — judged on a 32-chord estimate of the move raised by a quarter.
    #[must_use]
    pub fn samples_of(
        &self,
        machine: &crate::fiveaxis::Machine,
        from: &crate::fiveaxis::Joints,
        to: &crate::fiveaxis::Joints,
    ) -> usize {
        self.samples_with_step(machine, from, to, self.sample_step_mm)
    }

    /// [`Self::samples_of`] for another step (mm).
    fn samples_with_step(
        &self,
        machine: &crate::fiveaxis::Machine,
        from: &crate::fiveaxis::Joints,
        to: &crate::fiveaxis::Joints,
        step_mm: f64,
    ) -> usize {
        const PRE: usize = PRE_SAMPLES;
        let pose = |k: usize| machine.pose_from_joints(&from.lerp(to, k as f64 / PRE as f64));
        let reach = |p: &crate::fiveaxis::ToolPose| self.reach_mm(p.tip_in_workpiece, p.axis_in_workpiece).max(0.0);
        let mut prev = pose(0);
        let mut travel = 0.0;
        for k in 1..=PRE {
            let p = pose(k);
            let turn = prev.axis_in_workpiece.angle_between(p.axis_in_workpiece);
            let arm = reach(&prev).max(reach(&p));
            travel += (p.tip_in_workpiece - prev.tip_in_workpiece).length() + turn * arm;
            prev = p;
        }
        let n = (1.25 * travel / step_mm).ceil();
        if n.is_finite() { (n as usize).clamp(1, MAX_SAMPLES_PER_MOVE - 1) + 1 } else { MAX_SAMPLES_PER_MOVE }
    }

    /// Body length above the ball centre (mm) a swept segment between two poses needs: up
    /// to where the body of both poses is above the stock's top ([`Self::reach_mm`]) plus
    /// `tol_mm`, at most H − R; 0 when only the ball can reach the stock.
    fn segment_body_mm(&self, p0: &crate::fiveaxis::ToolPose, p1: &crate::fiveaxis::ToolPose, tol_mm: f64) -> f64 {
        let r = self.tool.radius_mm;
        let reach = |p: &crate::fiveaxis::ToolPose| self.reach_mm(p.tip_in_workpiece, p.axis_in_workpiece);
        (reach(p0).max(reach(p1)) + tol_mm - r).clamp(0.0, (self.tool.top_mm - r).max(0.0))
    }

    /// Swept segments a ball end mill's 5-axis move is cut in (1 to
    /// [`MAX_SAMPLES_PER_MOVE`] − 1) so that the envelope is within `tol_mm` of the
    /// interpolated motion's: half of it for the twist of the ruled surface the axis sweeps
    /// (L·|Δa|/4 per segment, from the axis' chordal turn on a 32-chord estimate raised by a
    /// quarter), 3/8 for the sagitta of the centre's and the body top's paths against their
    /// chords (max|c''|/(8n²), max|c''| from second differences of the same 33 poses raised
    /// by a half), and the last 1/8 ([`sweep::NOTCH_SHARE`]) for the notch along a segment's
    /// diagonal when its cylinder is left out.
    #[must_use]
    pub fn segments_of(
        &self,
        machine: &crate::fiveaxis::Machine,
        from: &crate::fiveaxis::Joints,
        to: &crate::fiveaxis::Joints,
        tol_mm: f64,
    ) -> usize {
        let r = self.tool.radius_mm;
        let poses: [crate::fiveaxis::ToolPose; PRE_SAMPLES + 1] =
            std::array::from_fn(|k| machine.pose_from_joints(&from.lerp(to, k as f64 / PRE_SAMPLES as f64)));
        let body = poses.iter().fold(0.0_f64, |b, p| b.max(self.segment_body_mm(p, p, tol_mm)));
        let centre = |p: &crate::fiveaxis::ToolPose| p.tip_in_workpiece + r * p.axis_in_workpiece;
        let mut turn = 0.0;
        let mut bend: f64 = 0.0;
        for k in 1..=PRE_SAMPLES {
            turn += (poses[k].axis_in_workpiece - poses[k - 1].axis_in_workpiece).length();
            if k < PRE_SAMPLES {
                let (a, b, c) = (&poses[k - 1], &poses[k], &poses[k + 1]);
                let dc = centre(c) - 2.0 * centre(b) + centre(a);
                let da = c.axis_in_workpiece - 2.0 * b.axis_in_workpiece + a.axis_in_workpiece;
                bend = bend.max(dc.length() + body * da.length());
            }
        }
        let bend = bend * (PRE_SAMPLES * PRE_SAMPLES) as f64;
        let n_twist = 1.25 * body * turn / (2.0 * tol_mm);
        let n_sagitta = (1.5 * bend / (3.0 * tol_mm)).sqrt();
        let n = n_twist.max(n_sagitta).ceil();
        if n.is_finite() { (n as usize).clamp(1, MAX_SAMPLES_PER_MOVE - 1) } else { MAX_SAMPLES_PER_MOVE - 1 }
    }

    /// One swept segment of a ball end mill between two poses (`mid` is the true pose
    /// halfway, measured against the segment's interpolation); the material removed (mm³).
    fn cut_segment(
        &mut self,
        p0: &crate::fiveaxis::ToolPose,
        p1: &crate::fiveaxis::ToolPose,
        mid: &crate::fiveaxis::ToolPose,
        tol_mm: f64,
    ) -> f64 {
        let r = self.tool.radius_mm;
        let body = self.segment_body_mm(p0, p1, tol_mm);
        let (a0, a1) = (p0.axis_in_workpiece.normalize_or_zero(), p1.axis_in_workpiece.normalize_or_zero());
        let (c0, c1) = (p0.tip_in_workpiece + r * a0, p1.tip_in_workpiece + r * a1);
        let am = mid.axis_in_workpiece.normalize_or_zero();
        let cm = mid.tip_in_workpiece + r * am;
        let sagitta =
            (cm - 0.5 * (c0 + c1)).length().max((cm + body * am - 0.5 * (c0 + body * a0 + c1 + body * a1)).length());
        self.counters.sweep_sagitta_mm = self.counters.sweep_sagitta_mm.max(sagitta);
        let (_, z1) = self.stock.z_range_mm();
        let (t0, t1) = (c0 + body * a0, c1 + body * a1);
        let lo = c0.min(c1).min(t0).min(t1) - DVec3::splat(r);
        let hi = c0.max(c1).max(t0).max(t1) + DVec3::splat(r);
        if lo.z >= z1 {
            return 0.0;
        }
        let g = *self.stock.grid();
        let (Some((i0, i1)), Some((j0, j1))) = (g.columns(lo.x, hi.x), g.rows(lo.y, hi.y)) else {
            return 0.0;
        };
        let mut seg = BallSegment::new(r, c0, a0, c1, a1, body, tol_mm);
        if self.last_pose == Some((p0.tip_in_workpiece, a0)) {
            seg = seg.continuing();
        }
        self.last_pose = Some((p1.tip_in_workpiece, a1));
        self.subtract_spans((i0, i1), (j0, j1), |x, y| seg.span(x, y))
    }

    /// Estimated rays visited by a program (the sum of its moves' and samples' boxes), to
    /// refuse a run before it starts.
    #[must_use]
    pub fn estimate_visits(&self, program: &Program) -> f64 {
        program.moves.iter().map(|m| self.estimate_move_visits(m)).sum()
    }

    /// Estimated rays one move visits with the current cutter ([`Self::estimate_visits`]).
    #[must_use]
    pub fn estimate_move_visits(&self, m: &SimMove) -> f64 {
        let g = self.stock.grid();
        let area = |lo: DVec3, hi: DVec3| {
            let w = ((hi.x - lo.x) / g.pitch_mm + 1.0).min(g.nx as f64);
            let h = ((hi.y - lo.y) / g.pitch_mm + 1.0).min(g.ny as f64);
            w.max(0.0) * h.max(0.0)
        };
        let r = DVec3::new(self.tool.radius_mm, self.tool.radius_mm, 0.0);
        match m.kind {
            MoveKind::Line { from, to } => area(from.min(to) - r, from.max(to) + r),
            MoveKind::Joints { machine, from, to } if self.sweep_tol_mm.is_some() => {
                let n = self.segments_of(&machine, &from, &to, self.sweep_tol_mm.unwrap_or(0.0));
                let (p, q) = (machine.pose_from_joints(&from), machine.pose_from_joints(&to));
                let step = DVec3::splat((q.tip_in_workpiece - p.tip_in_workpiece).length() / n as f64);
                let (lo, hi) =
                    sweep::tilted_box(&self.tool, p.tip_in_workpiece, p.axis_in_workpiece, self.tool.radius_mm * 2.0);
                n as f64 * area(lo - step, hi + step)
            }
            MoveKind::Joints { machine, from, to } => {
                let n = self.samples_of(&machine, &from, &to);
                let p = machine.pose_from_joints(&from);
                let (lo, hi) =
                    sweep::tilted_box(&self.tool, p.tip_in_workpiece, p.axis_in_workpiece, self.tool.radius_mm * 2.0);
                n as f64 * area(lo, hi)
            }
        }
    }

    /// Runs a whole program.
    ///
    /// # Errors
    /// [`SimError::TooMuchWork`] when [`Simulation::estimate_visits`] exceeds
    /// [`MAX_RAY_VISITS`], before any move is applied.
    pub fn run(&mut self, program: &Program) -> Result<(), SimError> {
        let visits = self.estimate_visits(program);
        if !(visits <= MAX_RAY_VISITS) {
            return Err(SimError::TooMuchWork { visits, max: MAX_RAY_VISITS });
        }
        for m in &program.moves {
            self.apply(m);
        }
        Ok(())
    }

    /// Applies one move; returns the material it removed (mm³).
    ///
    /// Never inlined, on purpose: a browser's WebAssembly engine (V8) first runs a function
    /// from quickly compiled baseline code and swaps in optimised code only for the calls
    /// that start after it became hot — it cannot replace a call already running. Inlined
    /// into the caller's loop over a program's moves, the whole program ran in the one
    /// baseline-compiled call; as its own function the optimised code takes over after the
    /// first moves (docs/simulation.md, "In the browser"). The arithmetic is the same
    /// either way (no reordering of floating-point operations), so are the rays. (`wasm-opt
    /// -O3` does not know this attribute and inlines a function called from one place: the
    /// worker's loop, `jobs::simulate_run`, calls it through an opaque pointer.)
    #[inline(never)]
    pub fn apply(&mut self, m: &SimMove) -> f64 {
        let updates_before = self.counters.ray_updates;
        let removed = self.apply_move(m);
        if matches!(m.kind, MoveKind::Joints { .. }) {
            self.counters.joint_updates += self.counters.ray_updates - updates_before;
        }
        removed
    }

    /// The work done so far, in ray updates of straight moves: those of 3-axis moves, those
    /// of 5-axis moves weighed by [`JOINT_UPDATE_COST`] and the rays their shank and holder
    /// checks visited, by [`CRASH_VISIT_COST`].
    #[must_use]
    pub fn work_done(&self) -> f64 {
        let c = &self.counters;
        (c.ray_updates - c.joint_updates) as f64
            + JOINT_UPDATE_COST * c.joint_updates as f64
            + CRASH_VISIT_COST * c.crash_visits as f64
    }

    fn apply_move(&mut self, m: &SimMove) -> f64 {
        // A block: consecutive moves of one line (every move of an in-memory program).
        if !self.now.started || m.line == 0 || m.line != self.now.line {
            self.crashes.begin_block();
        }
        self.now =
            MoveNow { line: m.line, rapid: m.rapid, index: self.counters.moves, kind: Some(m.kind), started: true };
        if let MoveKind::Joints { machine, from, to } = m.kind
            && m.rapid
            && self.crash_checks
        {
            self.check_joint_poses(&machine, &from, &to, true);
        }
        let removed = match m.kind {
            MoveKind::Line { from, to } => self.cut_line(from, to),
            MoveKind::Joints { machine, from, to } if self.sweep_tol_mm.is_some() => {
                let tol = self.sweep_tol_mm.unwrap_or(0.0);
                let n = self.segments_of(&machine, &from, &to, tol);
                let pose = |tau: f64| machine.pose_from_joints(&from.lerp(&to, tau));
                let mut prev = pose(0.0);
                let mut removed = 0.0;
                for k in 1..=n {
                    let next = pose(k as f64 / n as f64);
                    let mid = pose((k as f64 - 0.5) / n as f64);
                    removed += self.cut_segment(&prev, &next, &mid, tol);
                    prev = next;
                }
                self.counters.samples += n as u64 + 1;
                removed
            }
            MoveKind::Joints { machine, from, to } => {
                let n = self.samples_of(&machine, &from, &to);
                let mut removed = 0.0;
                for k in 0..n {
                    let tau = k as f64 / (n - 1).max(1) as f64;
                    let pose = machine.pose_from_joints(&from.lerp(&to, tau));
                    removed += self.cut_pose(pose.tip_in_workpiece, pose.axis_in_workpiece.normalize_or_zero());
                }
                self.counters.samples += n as u64;
                removed
            }
        };
        if let MoveKind::Joints { machine, from, to } = m.kind
            && self.crash_checks
        {
            self.check_joint_poses(&machine, &from, &to, false);
        }
        self.counters.moves += 1;
        self.counters.removed_mm3 += removed;
        let pitch = self.stock.grid().pitch_mm;
        if m.rapid && removed > CUT_NOISE_MM * pitch * pitch {
            self.counters.rapid_cuts += 1;
            if self.counters.first_rapid_cut_line.is_none() {
                self.counters.first_rapid_cut_line = Some(m.line);
            }
        }
        removed
    }

    /// A straight 3-axis move of the tip from `a` to `b`; the material removed (mm³).
    fn cut_line(&mut self, a: DVec3, b: DVec3) -> f64 {
        let (_, z1) = self.stock.z_range_mm();
        let low = a.z.min(b.z);
        if low >= z1 {
            return 0.0;
        }
        let tool = self.tool;
        let checks = self.crash_checks;
        if checks && !tool.centre_cutting && !self.now.rapid {
            self.check_plunge(a, b);
        }
        // The parts that can reach below the stock's top on this move.
        let reaches =
            |p: Option<crash::Part>| p.filter(|p| checks && p.checked().is_some_and(|t| low + t.from_mm < z1));
        let (shank, holder) = (reaches(tool.shank), reaches(tool.holder));
        if shank.is_some() || holder.is_some() || (checks && self.now.rapid) {
            return self.cut_line_checked(a, b, [shank, holder]);
        }
        let g = *self.stock.grid();
        let r = self.tool.radius_mm;
        let (Some((i0, i1)), Some((j0, j1))) =
            (g.columns(a.x.min(b.x) - r, a.x.max(b.x) + r), g.rows(a.y.min(b.y) - r, a.y.max(b.y) + r))
        else {
            return 0.0;
        };
        let sweep = LineSweep::new(&self.tool, a, b);
        self.subtract_spans((i0, i1), (j0, j1), |x, y| sweep.span(x, y))
    }

    /// A straight 3-axis move whose shank or holder can reach the stock, or a rapid: the cut
    /// with the crash checks of [`crash`], ray by ray; the material removed (mm³).
    fn cut_line_checked(&mut self, a: DVec3, b: DVec3, parts: [Option<crash::Part>; 2]) -> f64 {
        let g = *self.stock.grid();
        let tool = self.tool;
        let w = parts.iter().flatten().fold(tool.radius_mm, |w, p| w.max(p.radius_mm));
        let (Some((i0, i1)), Some((j0, j1))) =
            (g.columns(a.x.min(b.x) - w, a.x.max(b.x) + w), g.rows(a.y.min(b.y) - w, a.y.max(b.y) + w))
        else {
            return 0.0;
        };
        let sweep = LineSweep::new(&tool, a, b);
        // Each check: the solid shrunk by the touch (does it meet stock?) and the whole one
        // (how deep?).
        let swept = |p: &crash::Part| {
            let lift = DVec3::Z * p.from_mm;
            LineSweep::new(&ToolShape::of_part(p), a + lift, b + lift)
        };
        let part_sweeps = parts.map(|p| p.and_then(|whole| Some((swept(&whole.checked()?), swept(&whole)))));
        let rapid = self.now.rapid.then(|| {
            let lift = DVec3::Z * TOUCH_MM;
            (LineSweep::new(&tool.shrunk(TOUCH_MM), a + lift, b + lift), sweep)
        });
        // The parts meet the stock after the flutes' cut unless the move climbs (crash docs).
        let climbing = b.z > a.z;
        // Below these heights (the checked solids' lowest points on the move) a ray's stock
        // cannot meet them: shank, holder, the flutes of a rapid.
        let low = a.z.min(b.z);
        let floor = parts.map(|p| p.and_then(|p| p.checked()).map_or(f64::INFINITY, |t| low + t.from_mm));
        let rapid_floor = low + TOUCH_MM;
        // Deepest (depth, place) per kind: shank, holder, rapid.
        let mut worst: [Option<(f64, DVec3)>; 3] = [None; 3];
        let check = |stock: &DexelStock,
                     slot: &mut Option<(f64, DVec3)>,
                     (touch, whole): &(LineSweep, LineSweep),
                     floor: f64,
                     k: usize,
                     x: f64,
                     y: f64| {
            if stock.top_mm(k).is_none_or(|t| t <= floor) {
                return;
            }
            let Some((touched, _)) = touch.span(x, y).and_then(|(lo, hi)| stock.material_in(k, lo, hi)) else {
                return;
            };
            // The whole part holds at most 2 µm more of a ray the shrunk one meets.
            if slot.is_some_and(|(d, _)| touched + 2.0 * TOUCH_MM <= d) {
                return;
            }
            if let Some((depth, top)) = whole.span(x, y).and_then(|(lo, hi)| stock.material_in(k, lo, hi))
                && slot.is_none_or(|(d, _)| depth > d)
            {
                *slot = Some((depth, DVec3::new(x, y, top)));
            }
        };
        let mut removed = 0.0;
        for j in j0..=j1 {
            let y = g.y_mm(j);
            for i in i0..=i1 {
                let x = g.x_mm(i);
                let k = j * g.nx + i;
                self.counters.rays_visited += 1;
                if let Some(r) = &rapid {
                    check(&self.stock, &mut worst[2], r, rapid_floor, k, x, y);
                }
                if climbing {
                    for ((slot, s), f) in worst.iter_mut().zip(&part_sweeps).zip(floor) {
                        if let Some(s) = s {
                            check(&self.stock, slot, s, f, k, x, y);
                        }
                    }
                }
                if let Some((lo, hi)) = sweep.span(x, y) {
                    self.counters.ray_updates += 1;
                    removed += self.take(k, lo, hi);
                }
                if !climbing {
                    for ((slot, s), f) in worst.iter_mut().zip(&part_sweeps).zip(floor) {
                        if let Some(s) = s {
                            check(&self.stock, slot, s, f, k, x, y);
                        }
                    }
                }
            }
        }
        for (kind, w) in [CrashKind::Shank, CrashKind::Holder, CrashKind::Rapid].into_iter().zip(worst) {
            if let Some((depth, at)) = w {
                self.record_crash(kind, depth, at);
            }
        }
        removed * g.pitch_mm * g.pitch_mm
    }

    /// A feed move of a tool that does not cut at its centre: a plunge ([`crash`]) when it
    /// descends more steeply than [`crash::PLUNGE_MIN_DEG`] into stock.
    fn check_plunge(&mut self, a: DVec3, b: DVec3) {
        let d = b - a;
        let drop = -d.z;
        let run = d.x.hypot(d.y);
        if !(drop > TOUCH_MM && drop > run * crash::PLUNGE_MIN_DEG.to_radians().tan()) {
            return;
        }
        let g = *self.stock.grid();
        let half = 0.5 * g.pitch_mm;
        let (Some((i, _)), Some((j, _))) = (g.columns(b.x - half, b.x + half), g.rows(b.y - half, b.y + half)) else {
            return;
        };
        let k = j * g.nx + i;
        if self.stock.material_in(k, b.z + TOUCH_MM, a.z).is_some()
            && let Some((depth, top)) = self.stock.material_in(k, b.z, a.z)
        {
            self.record_crash(CrashKind::Plunge, depth, DVec3::new(g.x_mm(i), g.y_mm(j), top));
        }
    }

    /// The shank and holder (and, for a rapid, the flutes) of a 5-axis move at the poses it
    /// is sampled at: `before` the move's cut for the flutes of a rapid, after it for the
    /// parts ([`crash`]). Nothing more is done when, on a 32-chord estimate of the move, no
    /// part comes within a chord's travel of the stock's top.
    fn check_joint_poses(
        &mut self,
        machine: &crate::fiveaxis::Machine,
        from: &crate::fiveaxis::Joints,
        to: &crate::fiveaxis::Joints,
        before: bool,
    ) {
        let tool = self.tool;
        let touch = tool.shrunk(TOUCH_MM);
        // The solids checked: the flutes shrunk by the touch (their box as a part), or the parts.
        // Each solid whole (its box, how deep) and shrunk by the touch (does it meet stock?).
        let flutes = crash::Part { radius_mm: tool.radius_mm, from_mm: 0.0, to_mm: tool.top_mm };
        let parts: Vec<(CrashKind, crash::Part, crash::Part)> = if before {
            let shrunk = crash::Part { radius_mm: touch.radius_mm, from_mm: TOUCH_MM, to_mm: TOUCH_MM + touch.top_mm };
            vec![(CrashKind::Rapid, flutes, shrunk)]
        } else {
            [(CrashKind::Shank, tool.shank), (CrashKind::Holder, tool.holder)]
                .into_iter()
                .filter_map(|(k, p)| Some((k, p?, p?.checked()?)))
                .collect()
        };
        let (_, z1) = self.stock.z_range_mm();
        let pose = |tau: f64| {
            let p = machine.pose_from_joints(&from.lerp(to, tau));
            (p.tip_in_workpiece, p.axis_in_workpiece.normalize_or_zero())
        };
        let pre: [(DVec3, DVec3); PRE_SAMPLES + 1] = std::array::from_fn(|k| pose(k as f64 / PRE_SAMPLES as f64));
        let near = |part: &crash::Part| {
            let mut low = f64::INFINITY;
            let mut chord: f64 = 0.0;
            for (k, (tip, axis)) in pre.iter().enumerate() {
                low = low.min(sweep::part_box(part, *tip, *axis).0.z);
                if k > 0 {
                    let (t0, a0) = pre[k - 1];
                    chord = chord.max((*tip - t0).length() + (*axis - a0).length() * part.to_mm);
                }
            }
            low - 1.25 * chord < z1
        };
        let parts: Vec<_> = parts.into_iter().filter(|(_, _, t)| near(t)).collect();
        if parts.is_empty() {
            return;
        }
        let n = self.samples_with_step(machine, from, to, crash::POSE_STEP_PITCHES * self.stock.grid().pitch_mm);
        let g = *self.stock.grid();
        let mut worst: Vec<Option<(f64, DVec3)>> = vec![None; parts.len()];
        for s in 0..n {
            let (tip, axis) = pose(s as f64 / (n - 1).max(1) as f64);
            for ((kind, whole, part), slot) in parts.iter().zip(worst.iter_mut()) {
                let (lo, hi) = sweep::part_box(part, tip, axis);
                if lo.z >= z1 {
                    continue;
                }
                let (Some((i0, i1)), Some((j0, j1))) = (g.columns(lo.x, hi.x), g.rows(lo.y, hi.y)) else {
                    continue;
                };
                for j in j0..=j1 {
                    let y = g.y_mm(j);
                    for i in i0..=i1 {
                        let x = g.x_mm(i);
                        self.counters.rays_visited += 1;
                        let k = j * g.nx + i;
                        // A ray whose stock is all below the part's lowest point cannot meet it.
                        if self.stock.top_mm(k).is_none_or(|t| t <= lo.z) {
                            continue;
                        }
                        self.counters.crash_visits += 1;
                        let (touched, whole) = if *kind == CrashKind::Rapid {
                            (
                                tilted_span(&touch, tip + TOUCH_MM * axis, axis, x, y),
                                tilted_span(&tool, tip, axis, x, y),
                            )
                        } else {
                            (sweep::part_span(part, tip, axis, x, y), sweep::part_span(whole, tip, axis, x, y))
                        };
                        if touched.and_then(|(lo, hi)| self.stock.material_in(k, lo, hi)).is_none() {
                            continue;
                        }
                        let found = whole.and_then(|(lo, hi)| self.stock.material_in(k, lo, hi));
                        if let Some((depth, top)) = found
                            && slot.is_none_or(|(d, _)| depth > d)
                        {
                            *slot = Some((depth, DVec3::new(x, y, top)));
                        }
                    }
                }
            }
        }
        for ((kind, _, _), w) in parts.iter().zip(worst) {
            if let Some((depth, at)) = w {
                self.record_crash(*kind, depth, at);
            }
        }
    }

    /// Records a crash of the move being applied; in a rapid, the shank or holder meeting
    /// stock is a rapid crash too (any part of the tool entering stock in a G0).
    fn record_crash(&mut self, kind: CrashKind, depth_mm: f64, at_mm: DVec3) {
        let c = Crash {
            kind,
            line: self.now.line,
            move_index: self.now.index,
            slot: self.slot,
            depth_mm,
            at_mm,
            tip_mm: match self.now.kind {
                Some(MoveKind::Line { to, .. }) => to,
                Some(MoveKind::Joints { machine, to, .. }) => machine.pose_from_joints(&to).tip_in_workpiece,
                None => DVec3::ZERO,
            },
        };
        self.crashes.record(c);
        if self.now.rapid && matches!(kind, CrashKind::Shank | CrashKind::Holder) {
            self.crashes.record(Crash { kind: CrashKind::Rapid, ..c });
        }
    }

    /// Subtracts `lo < z < hi` from ray `k`, marking the tool map; the length removed (mm).
    #[inline]
    fn take(&mut self, k: usize, lo: f64, hi: f64) -> f64 {
        let cut = self.stock.subtract(k, lo, hi);
        if cut > 0.0
            && let Some(map) = self.tool_map.as_mut()
            && let Some(t) = map.get_mut(k)
        {
            *t = self.slot;
        }
        cut
    }

    /// Subtracts from every ray of columns i0..=i1 and rows j0..=j1 the span `span(x, y)`
    /// gives it (none: the ray is missed), counting visits and updates; the material
    /// removed (mm³).
    fn subtract_spans(
        &mut self,
        (i0, i1): (usize, usize),
        (j0, j1): (usize, usize),
        span: impl Fn(f64, f64) -> Option<(f64, f64)>,
    ) -> f64 {
        let g = *self.stock.grid();
        let mut removed = 0.0;
        for j in j0..=j1 {
            let y = g.y_mm(j);
            for i in i0..=i1 {
                self.counters.rays_visited += 1;
                if let Some((lo, hi)) = span(g.x_mm(i), y) {
                    self.counters.ray_updates += 1;
                    removed += self.take(j * g.nx + i, lo, hi);
                }
            }
        }
        removed * g.pitch_mm * g.pitch_mm
    }

    /// One position of a tilted cutter; the material removed (mm³).
    fn cut_pose(&mut self, tip: DVec3, axis: DVec3) -> f64 {
        let (_, z1) = self.stock.z_range_mm();
        let t = &self.tool;
        // Only the part of the body that can reach below the stock's top matters.
        let sin = (1.0 - axis.z * axis.z).max(0.0).sqrt();
        let h =
            if axis.z > AXIS_FLAT_SIN { ((z1 - tip.z + t.radius_mm * sin) / axis.z).min(t.top_mm) } else { t.top_mm };
        if h < 0.0 {
            return 0.0;
        }
        let (lo, hi) = sweep::tilted_box(t, tip, axis, h);
        if lo.z >= z1 {
            return 0.0;
        }
        let g = *self.stock.grid();
        let (Some((i0, i1)), Some((j0, j1))) = (g.columns(lo.x, hi.x), g.rows(lo.y, hi.y)) else {
            return 0.0;
        };
        let tool = self.tool;
        self.subtract_spans((i0, i1), (j0, j1), |x, y| tilted_span(&tool, tip, axis, x, y))
    }
}
