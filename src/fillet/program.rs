//! CL data of one path as a seed-002 design path, so the five-axis machines and the step
//! selection of [`crate::fiveaxis`] turn it into joint values and a program.
//!
//! Between two CC nodes the design is the cutter placed at the CC point interpolated
//! linearly in (u, v) with the orientation (α, ψ) and the feed interpolated linearly too —
//! what the orientation would be if computed there. The path parameter s is the cumulative
//! CC chord length (mm), or a share of the tool tips' chord where the tip moves far more
//! than the contact point ([`TIP_CHORD_SHARE`]).
//!
//! A lead-in or lead-out node ([`CcNode::lead_out`]) is the first or last cutter moved along
//! its feed with the surface's continuation; between it and its CC node tip and axis are
//! interpolated linearly and the CC node's frame stands for the design.
//!
//! The step selection measures a ball at the point `tip + R·axis` with R =
//! [`DesignPath::ball_radius_mm`]; a fillet-end mill is no ball, so this path reports a ball
//! radius 0 (the measured point *is* the tool tip) and as the error of a swept tip p the
//! distance to the design tip at the same fraction of the segment, positive (overcut) when p
//! lies on the part's side of the design tip (`(p − T)·n < 0`). The steps then keep the
//! swept tool tip within E of its design path (the nonlinear error of seed 002, here on the
//! tip of the fillet-end mill).

use std::cell::Cell;

use glam::{DVec2, DVec3};
use thiserror::Error;

use super::FinishError;
use super::contact::{ContactFrame, Pose, place};
use super::node::CcNode;
use super::orient::Strategy;
use super::paths::{FinishSetup, PathSet};
use crate::fiveaxis::{
    CutterLocation, DesignPath, FiveAxisError, Joints, KinematicsError, Machine, StepOptions, StepPlan,
};
use crate::gcode::{Dialect, safe_comment};
use crate::geom::{Cutter, Surface};
use crate::numerics::format::fmt_num;
use crate::numerics::roots::RootMethod;

/// The setup of a finishing job for a program on `machine`: every pose within the machine's
/// rotary travel ([`FinishSetup::reach`]; a point with none is refused, named), so the
/// program's planner meets the travel only between nodes, where [`FinishGcode::plan`] cuts
/// the pass instead of refusing the job.
#[must_use]
pub fn for_machine<'a>(machine: &'a Machine, setup: &FinishSetup<'a>) -> FinishSetup<'a> {
    FinishSetup { reach: Some(machine), ..*setup }
}

/// A chord's length in the design path's parameter s is its CC points' distance, or this
/// share of its tool tips' distance when that is more. Two neighbouring nodes can hold
/// (nearly) the same CC point in different poses (on a folded surface, the gouge checks
/// turning one of them): the tip jumps while s does not move, and the program's steps
/// underflow at the jump. A fuzz patch (the example's control point `[3][1]` moved to
/// y = 360 mm) has a chord of 1.4·10⁻⁷ mm over which the tip moves 2.7 mm; its program was
/// refused after 19 s. Elsewhere the tips move about as far as the CC points, and s is
/// the CC chord length as before.
pub const TIP_CHORD_SHARE: f64 = 0.1;

/// One path's CL data as a design path (module docs).
#[derive(Clone, Debug)]
pub struct FilletDesignPath<'a> {
    surface: &'a Surface,
    cutter: Cutter,
    nodes: &'a [CcNode],
    cum: Vec<f64>,
    /// Designs evaluated between nodes so far (the planner's work, [`PlanBudget`]).
    evaluations: Cell<u64>,
}

impl<'a> FilletDesignPath<'a> {
    /// The design path through `nodes` (at least two) cut by `cutter` on `surface`.
    #[must_use]
    pub fn new(surface: &'a Surface, cutter: Cutter, nodes: &'a [CcNode]) -> Option<Self> {
        if nodes.len() < 2 {
            return None;
        }
        let mut cum = vec![0.0];
        for w in nodes.windows(2) {
            let contact = (w[1].frame.point - w[0].frame.point).length();
            let tip = (w[1].tip - w[0].tip).length();
            let l = cum.last().copied().unwrap_or(0.0) + contact.max(TIP_CHORD_SHARE * tip);
            cum.push(l);
        }
        Some(Self { surface, cutter, nodes, cum, evaluations: Cell::new(0) })
    }

    fn segment(&self, s: f64) -> (usize, f64) {
        let k = self.cum.partition_point(|&c| c <= s).clamp(1, self.cum.len() - 1);
        let (c0, c1) = (self.cum[k - 1], self.cum[k]);
        (k, if c1 > c0 { ((s - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.0 })
    }

    fn design_at(&self, s: f64) -> Option<(ContactFrame, DVec3, DVec3)> {
        let (k, t) = self.segment(s);
        let (a, b) = (&self.nodes[k - 1], &self.nodes[k]);
        if t <= 0.0 {
            return Some((a.frame, a.tip, a.axis));
        }
        if t >= 1.0 {
            return Some((b.frame, b.tip, b.axis));
        }
        self.evaluations.set(self.evaluations.get() + 1);
        design_between(self.surface, &self.cutter, a, b, t)
    }
}

/// The design between CC nodes `a` and `b` at the fraction `t` in (0, 1) (module docs): the
/// frame, the tool tip (mm) and the unit axis the program's planner follows there; `None`
/// where the surface has no frame. The frame is [`ContactFrame::first_order`]'s (no
/// second form): the planner evaluates it at every sample of every trial step.
#[must_use]
pub fn design_between(
    surface: &Surface,
    cutter: &Cutter,
    a: &CcNode,
    b: &CcNode,
    t: f64,
) -> Option<(ContactFrame, DVec3, DVec3)> {
    if a.lead_out || b.lead_out {
        // A lead-in or lead-out: the first or last cutter moved along its feed with the
        // surface's continuation (the axis turned with it), tip and axis linearly as the
        // machine moves between CL rows.
        let cc = if a.lead_out { b } else { a };
        return Some((cc.frame, a.tip.lerp(b.tip, t), a.axis.lerp(b.axis, t).normalize()));
    }
    let uv: DVec2 = a.frame.uv.lerp(b.frame.uv, t);
    let feed = a.frame.feed.lerp(b.frame.feed, t);
    let frame = ContactFrame::first_order(surface, uv, feed)?;
    let pose = Pose {
        inclination_rad: a.pose.inclination_rad + t * (b.pose.inclination_rad - a.pose.inclination_rad),
        azimuth_rad: a.pose.azimuth_rad + t * (b.pose.azimuth_rad - a.pose.azimuth_rad),
    };
    let (tip, axis) = place(cutter, &frame, &pose);
    Some((frame, tip, axis))
}

impl DesignPath for FilletDesignPath<'_> {
    fn range(&self) -> (f64, f64) {
        (0.0, self.cum.last().copied().unwrap_or(0.0))
    }
    fn ball_radius_mm(&self) -> f64 {
        0.0
    }
    fn effective_radius_mm(&self) -> f64 {
        0.0
    }
    fn surface_count(&self) -> usize {
        1
    }
    fn location_at(&self, s: f64) -> Result<CutterLocation, FiveAxisError> {
        let (frame, tip, axis) = self.design_at(s).ok_or(FiveAxisError::Crease { s })?;
        Ok(CutterLocation {
            s,
            centre: tip,
            axis,
            tip,
            normals: [frame.normal, frame.normal],
            travel: frame.feed,
            hints: [frame.uv, frame.uv],
        })
    }
    fn surface_errors(&self, p: DVec3, a: &CutterLocation, b: &CutterLocation, tau: f64) -> [Option<f64>; 2] {
        let s = a.s + tau * (b.s - a.s);
        let e = self.design_at(s).map_or(f64::NAN, |(frame, tip, _)| {
            let d = p - tip;
            if d.dot(frame.normal) < 0.0 { d.length() } else { -d.length() }
        });
        [Some(e), None]
    }
    fn first_step(&self, s: f64, _tol_mm: f64) -> Option<f64> {
        let (k, _) = self.segment(s);
        Some(self.cum[k] - self.cum[k - 1]).filter(|l| *l > 0.0)
    }
}

/// Most blocks a finishing program may have over all its paths.
pub const MAX_PROGRAM_BLOCKS: usize = 400_000;

/// Most designs between CC nodes ([`design_between`]: a surface frame, the tool placed on
/// it) a finishing program's planning may evaluate, over all its paths: its work, for
/// each block's trial steps and their sampled errors evaluate the design some 120–270
/// times (the examples' programs 118–272 times a block, two fuzz cases' 130–175; 209–471
/// with the paper's modified secant, before [`FINISH_STEP_METHOD`]). About 0.28 µs each
/// natively (fuzz-case programs of 5–44 million evaluations), so some 28 s: about what the
/// paths' checks may spend ([`super::paths::check_stop`]). A command that builds the paths
/// first plans within the share of its work they left
/// ([`crate::numerics::limits::CommandShare`]).
pub const MAX_PLAN_DESIGNS: f64 = 1e8;

/// How a finishing program's planning solves each step's δ(s) = E (within the paper's
/// window): Anderson–Björck's regula falsi. The paper's modified secant (plain regula falsi,
/// the 5-axis tab's default, which shows the paper's iteration counts) keeps one end of its
/// bracket for many steps where δ is convex in the step, as it is on these paths: it took
/// 8.3–10.2 errors a block on the examples' programs and 13.8–14.9 on two folded fuzz jobs,
/// where Anderson–Björck takes 4.8–6.8 and 5.2–5.9, for the same window and as many blocks
/// (±0.03 %). Each error evaluates the design some 25–42 times: the examples' `finish
/// --gcode` takes 0.40–0.86 s of CPU instead of 0.42–0.94, the folded patch's 15.8 s instead
/// of 29.4 (docs/fillet.md, "Command line").
pub const FINISH_STEP_METHOD: RootMethod = RootMethod::AndersonBjorck;

/// Blocks planned before the program's size and work are estimated from them.
const ESTIMATE_AFTER_BLOCKS: usize = 2_000;

/// What a finishing program's planning may spend and has spent: its blocks (at most
/// [`MAX_PROGRAM_BLOCKS`]) and its design evaluations (at most the budget's own cap), both
/// projected over the whole design length from the part planned once
/// 2 000 blocks are, so that a program on course to pass either is refused then.
#[derive(Clone, Debug)]
pub struct PlanBudget {
    total_mm: f64,
    done_mm: f64,
    blocks: usize,
    designs: u64,
    max_designs: f64,
}

impl PlanBudget {
    /// The budget of a program whose paths' design length is `total_mm` (mm; 0 when not
    /// known: nothing is then projected, only what is spent is judged), which may evaluate
    /// `max_designs` designs.
    #[must_use]
    pub fn new(total_mm: f64, max_designs: f64) -> Self {
        Self { total_mm, done_mm: 0.0, blocks: 0, designs: 0, max_designs }
    }

    /// Design evaluations spent so far.
    #[must_use]
    pub fn designs(&self) -> u64 {
        self.designs
    }

    /// Blocks planned so far.
    #[must_use]
    pub fn blocks(&self) -> usize {
        self.blocks
    }

    /// The error that stops the program when, `blocks` more and `designs` more evaluations
    /// on `done_mm` more of the design (the path being planned, up to `s`), it is on course
    /// to pass [`MAX_PROGRAM_BLOCKS`] or its design evaluations.
    fn over(&self, blocks: usize, done_mm: f64, designs: u64, tol_mm: f64, s: f64) -> Option<FiveAxisError> {
        let (b, d, e) = (self.blocks + blocks, self.done_mm + done_mm, self.designs + designs);
        let share = (b >= ESTIMATE_AFTER_BLOCKS && d > 0.0 && self.total_mm > d).then(|| self.total_mm / d);
        if b >= MAX_PROGRAM_BLOCKS || share.is_some_and(|k| b as f64 * k > MAX_PROGRAM_BLOCKS as f64) {
            return Some(FiveAxisError::TooManyNodes { tol_mm, max_nodes: MAX_PROGRAM_BLOCKS, s });
        }
        let projected = e as f64 * share.unwrap_or(1.0);
        (!(projected <= self.max_designs)).then_some(FiveAxisError::TooMuchWork {
            s,
            evaluations: e,
            projected,
            max: self.max_designs,
        })
    }
}

/// The seed-002 steps of one design path within the program's block budget: refused as soon as the blocks planned
/// so far, in proportion to the design length they cover, say the whole program would need
/// more than [`MAX_PROGRAM_BLOCKS`].
///
/// Each step is found as seed 002 finds it — its error δ brought into the paper's window
/// `[E − ε, E]` — by Anderson–Björck's regula falsi rather than the paper's plain one
/// ([`FINISH_STEP_METHOD`]).
fn plan_path_within(
    machine: &Machine,
    path: &FilletDesignPath<'_>,
    tol_mm: f64,
    budget: &mut PlanBudget,
) -> Result<StepPlan, FiveAxisError> {
    let mut opts = StepOptions::new(tol_mm).with_method(FINISH_STEP_METHOD);
    opts.reports = false;
    let (start, end) = path.range();
    let run = |opts: &StepOptions| -> Result<StepPlan, FiveAxisError> {
        let mut planner = crate::fiveaxis::StepPlanner::new(machine, path, opts)?;
        while !planner.is_done() {
            let node = planner.next_node(machine, path)?;
            let s = node.block.location.s;
            if planner.nodes().len() % 256 == 0
                && let Some(e) = budget.over(planner.nodes().len(), s - start, path.evaluations.get(), tol_mm, s)
            {
                return Err(e);
            }
        }
        Ok(planner.into_plan())
    };
    let plan = match run(&opts) {
        // The design is only piecewise smooth (linear between CC nodes): where the regula
        // falsi stalls at a kink, bisection still brackets the step.
        Err(FiveAxisError::NoConvergence { .. }) => run(&opts.with_method(RootMethod::Bisection)),
        other => other,
    };
    // Spent whether or not the path was planned (a run cut out of travel is planned again
    // in parts).
    budget.designs += path.evaluations.get();
    let plan = plan?;
    budget.blocks += plan.nodes.len();
    budget.done_mm += end - start;
    // Judged once more at the path's end: a path of fewer than 256 blocks is not judged
    // inside its loop.
    if let Some(e) = budget.over(0, 0.0, 0, tol_mm, end) {
        return Err(e);
    }
    Ok(plan)
}

/// The design length (s, mm: [`FilletDesignPath`]'s parameter) of paths of `nodes`, cut by
/// `tool` (the one that machines), for a [`PlanBudget`].
#[must_use]
pub fn design_length_mm<'a>(surface: &Surface, tool: &Cutter, paths: impl Iterator<Item = &'a [CcNode]>) -> f64 {
    paths.filter_map(|nodes| FilletDesignPath::new(surface, *tool, nodes)).map(|p| p.range().1).sum()
}

/// Most cuts the planner's errors make in one run of a path where the axis between its
/// nodes leaves the machine's travel ([`plan_path_pieces`]); past it the path is refused with the
/// planner's error.
pub const MAX_PLANNER_CUTS: usize = 64;

/// Fractions of a chord at which [`plan_path_pieces_within`] looks for the design between two nodes
/// leaving the machine's travel before the planner runs.
const TRAVEL_SAMPLES_PER_CHORD: u32 = 16;

/// The blocks' joints of one path's program, in pieces: where the design between two nodes
/// needs a rotary angle outside the machine's travel — across a gap of refused points the
/// interpolated frame can swing the axis far from both ends — the pass ends at the node
/// before and the next piece starts at the node after (each piece starts with a rapid
/// move, as every pass does); a node itself out of travel is an error. It finds
/// such places first where `TRAVEL_SAMPLES_PER_CHORD` (16) samples of a chord show them, then
/// where the planner stops (its error's s), at most [`MAX_PLANNER_CUTS`] times in a run.
///
/// It spends the program's `budget` (`tool`: the cutter that machines).
///
/// # Errors
/// The planner's error; [`FiveAxisError::Kinematics`] out of travel past the cuts' cap;
/// [`FiveAxisError::TooManyNodes`] or [`FiveAxisError::TooMuchWork`] when the budget is
/// passed.
pub fn plan_path_pieces_within(
    machine: &Machine,
    surface: &Surface,
    tool: &Cutter,
    nodes: &[CcNode],
    tol_mm: f64,
    budget: &mut PlanBudget,
) -> Result<Vec<Vec<Joints>>, FiveAxisError> {
    // A node out of travel is the paths' fault (built for no machine, or another), not the
    // design's between them: the planner's error, as it would stop there.
    let mut s = 0.0;
    for (k, n) in nodes.iter().enumerate() {
        if k > 0 {
            s += (n.frame.point - nodes[k - 1].frame.point).length();
        }
        if let Err(source @ KinematicsError::OutOfTravel { .. }) = machine.joints_from_pose(n.tip, n.axis, None) {
            return Err(FiveAxisError::Kinematics { s, source });
        }
    }
    // The runs between chords whose design leaves the travel at one of its samples (most
    // such places, found without planning); the planner finds the rest.
    budget.designs += u64::from(TRAVEL_SAMPLES_PER_CHORD - 1) * nodes.len().saturating_sub(1) as u64;
    let chord_out = |a: &CcNode, b: &CcNode| {
        (1..TRAVEL_SAMPLES_PER_CHORD).any(|i| {
            let t = f64::from(i) / f64::from(TRAVEL_SAMPLES_PER_CHORD);
            design_between(surface, tool, a, b, t).is_some_and(|d| !machine.reaches_axis(d.2, 0.0))
        })
    };
    let mut pieces = Vec::new();
    let mut first = 0;
    for k in 1..=nodes.len() {
        if k < nodes.len() && !chord_out(&nodes[k - 1], &nodes[k]) {
            continue;
        }
        // One run, cut where the planner stops out of travel: the part before the chord
        // holding its s is planned next, then the part after (its nodes are within travel:
        // checked above).
        let mut pending = vec![&nodes[first..k]];
        first = k;
        let mut cuts = 0;
        while let Some(run) = pending.pop() {
            let Some(path) = FilletDesignPath::new(surface, *tool, run) else { continue };
            match plan_path_within(machine, &path, tol_mm, budget) {
                Ok(plan) => pieces.push(plan.nodes.iter().map(|n| n.block.joints).collect()),
                Err(FiveAxisError::Kinematics { s, source: KinematicsError::OutOfTravel { .. } })
                    if cuts < MAX_PLANNER_CUTS =>
                {
                    cuts += 1;
                    let c = path.cum.partition_point(|&c| c <= s).clamp(1, run.len() - 1);
                    pending.push(&run[c..]);
                    pending.push(&run[..c]);
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok(pieces)
}

/// One path's program in pieces as [`FinishGcode::plan`] writes it ([`plan_path_pieces_within`]: cut
/// where the axis between two nodes would leave the machine's travel), on its own: no
/// budget but the blocks' cap, [`MAX_PROGRAM_BLOCKS`], and [`MAX_PLAN_DESIGNS`].
/// `cutter`: the one that machines.
///
/// # Errors
/// The planner's error; [`FiveAxisError::Kinematics`] out of travel past
/// [`MAX_PLANNER_CUTS`] cuts in a run.
pub fn plan_path_pieces(
    machine: &Machine,
    surface: &Surface,
    cutter: &Cutter,
    nodes: &[CcNode],
    tol_mm: f64,
) -> Result<Vec<Vec<Joints>>, FiveAxisError> {
    plan_path_pieces_within(machine, surface, cutter, nodes, tol_mm, &mut PlanBudget::new(0.0, MAX_PLAN_DESIGNS))
}

/// Why a finishing program could not be planned.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FinishProgramError {
    /// The seed-002 steps of one path failed.
    #[error("path {path}: {source}")]
    Plan {
        /// Index of the path in its set.
        path: usize,
        /// The planner's error.
        source: FiveAxisError,
    },
    /// The paths themselves could not be made.
    #[error(transparent)]
    Paths(#[from] FinishError),
}

/// The five-axis program of a finishing job, planned (what `interpolab finish --gcode`
/// writes): per path of two or more nodes, the joints of its seed-002 steps on the machine.
/// [`FinishGcode::text`] writes it for any name: the name enters the program only through
/// [`crate::gcode::comment::safe_comment`], so the blocks do not depend on it.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishGcode {
    /// The machine whose joints the blocks carry.
    pub machine: Machine,
    /// The cutter that machines (the strategy's).
    pub tool: Cutter,
    /// The orientation strategy.
    pub strategy: Strategy,
    /// Paths in the set (including any too short to write).
    pub paths: usize,
    /// Tolerance E of the steps (mm).
    pub tol_mm: f64,
    /// Programmed feed (mm/min).
    pub feed_mm_per_min: f64,
    /// Per written pass: the index of its path in the set and its blocks' joints, first to
    /// last. A path whose axis would leave the machine's travel between two nodes is written
    /// as several passes of the same index ([`plan_path_pieces_within`]).
    pub passes: Vec<(usize, Vec<Joints>)>,
    /// Designs its planning evaluated ([`MAX_PLAN_DESIGNS`]).
    pub designs: u64,
}

impl FinishGcode {
    /// Plans the steps of every path of `set` (cut by the strategy's cutter from `cutter`)
    /// on `machine` within `tol_mm`, evaluating at most [`MAX_PLAN_DESIGNS`] designs.
    ///
    /// # Errors
    /// [`FinishProgramError::Plan`] naming the path whose steps failed.
    pub fn plan(
        machine: &Machine,
        surface: &Surface,
        cutter: &Cutter,
        set: &PathSet,
        feed_mm_per_min: f64,
        tol_mm: f64,
    ) -> Result<Self, FinishProgramError> {
        Self::plan_within(machine, surface, cutter, set, feed_mm_per_min, tol_mm, MAX_PLAN_DESIGNS)
    }

    /// [`FinishGcode::plan`] evaluating at most `max_designs` designs (what a command's
    /// paths left of its work: [`crate::numerics::limits::CommandShare`]).
    ///
    /// # Errors
    /// As [`FinishGcode::plan`]; the path being planned when the program is on course to
    /// pass `max_designs` ([`FiveAxisError::TooMuchWork`]).
    pub fn plan_within(
        machine: &Machine,
        surface: &Surface,
        cutter: &Cutter,
        set: &PathSet,
        feed_mm_per_min: f64,
        tol_mm: f64,
        max_designs: f64,
    ) -> Result<Self, FinishProgramError> {
        let tool = set.strategy.cutter_for(cutter);
        let total_mm = design_length_mm(surface, &tool, set.paths.iter().map(|p| p.nodes.as_slice()));
        let mut budget = PlanBudget::new(total_mm, max_designs);
        let mut passes = Vec::new();
        for (pi, p) in set.paths.iter().enumerate().filter(|(_, p)| p.nodes.len() >= 2) {
            for joints in plan_path_pieces_within(machine, surface, &tool, &p.nodes, tol_mm, &mut budget)
                .map_err(|source| FinishProgramError::Plan { path: pi, source })?
            {
                passes.push((pi, joints));
            }
        }
        Ok(Self {
            machine: *machine,
            tool,
            strategy: set.strategy,
            paths: set.paths.len(),
            tol_mm,
            feed_mm_per_min,
            passes,
            designs: budget.designs(),
        })
    }

    /// The program's text, named `name` in its first comment: a header of comments, `G90
    /// G21 G94`, per pass a comment, a `G00` to its first block and `G01` through the rest
    /// (X Y Z in mm to 4 decimals, the rotary axes in degrees; F on the first `G01`), `M30`
    /// and a comment counting the blocks. Every comment by
    /// [`crate::gcode::comment::safe_comment`] (FANUC's `( … )`).
    #[must_use]
    pub fn text(&self, name: &str) -> String {
        let m = &self.machine;
        let [ta, ca] = m.axis_names();
        let comment = |text: &str| safe_comment(Dialect::Fanuc, text) + "\n";
        let mut text = comment(&format!("interpolab finish: {name}"));
        text.push_str(&comment(&format!(
            "cutter {}, strategy {}, {} paths, steps within {} mm by seed-002 step selection, machine {}",
            self.tool.describe(),
            self.strategy.name().replace('°', " deg"),
            self.paths,
            self.tol_mm,
            m.kind.as_str()
        )));
        text.push_str(&comment(&format!(
            "X Y Z in mm, {ta} {ca} in degrees, each pass starts with a rapid move: check the clearance"
        )));
        text.push_str("G90 G21 G94\n");
        let mut blocks = 0usize;
        let mut last_path = None;
        for (pi, joints) in &self.passes {
            if last_path == Some(*pi) {
                text.push_str(&comment(&format!(
                    "pass {pi} goes on past a stretch where the tool axis would leave the machine's travel"
                )));
            } else {
                text.push_str(&comment(&format!("pass {pi}")));
            }
            last_path = Some(*pi);
            for (k, j) in joints.iter().enumerate() {
                let word = if k == 0 { "G00" } else { "G01" };
                text.push_str(&format!(
                    "{word} X{:.4} Y{:.4} Z{:.4} {ta}{:.4} {ca}{:.4}",
                    j.xyz_mm.x,
                    j.xyz_mm.y,
                    j.xyz_mm.z,
                    j.rotary_rad[0].to_degrees(),
                    j.rotary_rad[1].to_degrees()
                ));
                if k == 1 {
                    text.push_str(&format!(" F{}", fmt_num(self.feed_mm_per_min)));
                }
                text.push('\n');
                blocks += 1;
            }
        }
        text.push_str("M30\n");
        text.push_str(&comment(&format!("{blocks} blocks")));
        text
    }
}
