//! Seed 001's finishing programs as the simulation runs them: the CL paths of
//! [`crate::fillet`] (a fillet-end mill, or a ball, on one machined surface) turned into the
//! five-axis program `interpolab finish --gcode` writes — per pass, the seed-002 step
//! selection on the scene's machine ([`crate::fillet::program::plan_path_pieces`]), and between
//! its blocks the joints interpolated linearly ([`MoveKind::Joints`]), so the simulated cut
//! is what the machine sweeps, nonlinear error included.
//!
//! Why joint moves and not the tool tip and axis of each CL node: a tip-and-axis move would
//! simulate the design (the CL data), not the program a machine runs; between two blocks the
//! machine's linear joint motion leaves that design by up to the step tolerance, and that
//! is part of what a simulation should show. The joint moves need no new move kind.
//!
//! Only the passes are simulated: the written program starts each pass with a G00 from the
//! end of the last, straight through the part (its header says to check the clearance), so
//! those linking moves are left out here.
//!
//! The design the result is measured against is the finish surface itself
//! ([`Design::Surface`]); the default stock is the part's box ([`FinishProgram::stock_mm`]).

use glam::{DVec2, DVec3};

use super::interior::{INTERIOR_END_MM, INTERIOR_SIDE_MM, interior_mask};
use super::stock::Grid;
use super::{Design, MAX_WORK, MoveKind, PROJECTED_WORK_ROOM, Program, SimError, SimMove, Simulation};
use crate::fillet::paths::Pilot;
use crate::fillet::program::{MAX_PLAN_DESIGNS, PlanBudget, design_length_mm, plan_path_pieces_within};
use crate::fillet::{CcNode, FinishJob, PathSet, Strategy, ToolPath};
use crate::fiveaxis::Machine;
use crate::geom::{Cutter, ParametricSurface, Surface};

/// Share of the scallop height h the cusps between sampled poses may take
/// ([`FinishProgram::pose_step_mm`]).
pub const POSE_CUSP_SHARE: f64 = 0.25;
/// Smallest pose step (mm) [`FinishProgram::pose_step_mm`] gives (bounds the work for small
/// corners and flat end mills).
pub const MIN_POSE_STEP_MM: f64 = 0.02;

/// The work a finishing program's 5-axis moves do ([`Simulation::work_done`]) per ray their
/// boxes visit ([`Simulation::estimate_move_visits`]) where the cutter is sampled pose by
/// pose (flat and fillet end mills): 3.85–5.03 on the three examples' programs (matched and
/// fixed-lead orientation) at pitch 0.5 and 1 mm, 7.2–8.3 on the concave mould's, whose
/// holder checks visit more rays than the cutter updates. The least, so that
/// [`WorkProjection`] errs low rather than refuse a program that fits.
pub const WORK_PER_VISIT: f64 = 3.8;

/// [`WORK_PER_VISIT`] for the ball's closed-form swept segments: 2.15–3.04 on the examples'
/// programs at pitch 0.5 and 1 mm (18.6–20.9 on the concave mould's, its holder checks).
pub const WORK_PER_SEGMENT_VISIT: f64 = 2.1;

/// The work per estimated ray visit [`WorkProjection`] counts on `sim`: [`WORK_PER_VISIT`],
/// or [`WORK_PER_SEGMENT_VISIT`] where `sim` sweeps the ball's segments.
#[must_use]
pub fn work_per_visit(sim: &Simulation) -> f64 {
    if sim.sweep_tol_mm().is_some() { WORK_PER_SEGMENT_VISIT } else { WORK_PER_VISIT }
}

/// How far over a run's stop ([`PROJECTED_WORK_ROOM`] × [`MAX_WORK`]) a finishing program's
/// projected work may read before it is refused ([`WorkProjection`]): the room for the
/// projection's error, so that a program that fits is run and, if the projection was low,
/// the run's own meter still stops it.
pub const PROJECTION_ROOM: f64 = 1.5;

/// Samples per parameter direction of the part's box ([`FinishProgram::part_box`]).
pub const PART_BOX_SAMPLES: usize = 33;

/// A finishing program of seed 001, ready to plan and simulate (plain data: the surface,
/// the cutter that machines, the machine and the CC nodes of every pass).
#[derive(Clone, Debug, PartialEq)]
pub struct FinishProgram {
    /// The machined surface, normal toward the cutter (the design).
    pub surface: Surface,
    /// The cutter that machines (the strategy's: a ball of the same R for `ball`).
    pub cutter: Cutter,
    /// The machine whose joints are interpolated.
    pub machine: Machine,
    /// The passes' CC nodes, first to last (passes of fewer than two nodes are skipped).
    pub passes: Vec<Vec<CcNode>>,
    /// Tolerance E (mm) of the seed-002 steps between blocks.
    pub step_tol_mm: f64,
    /// A short description (strategy, layout), for reports and the A/B comparison.
    pub label: String,
}

impl FinishProgram {
    /// The program of a finishing job's paths `set`, with steps within `step_tol_mm`.
    ///
    /// # Errors
    /// [`SimError::Program`] for a step tolerance that is not a positive length.
    pub fn new(job: &FinishJob, set: &PathSet, step_tol_mm: f64) -> Result<Self, SimError> {
        Self::of_paths(&job.surface, &job.cutter, &job.machine, set, step_tol_mm)
    }

    /// As [`FinishProgram::new`] from the job's parts (`cutter` as the scene gives it; the
    /// set's strategy decides the cutter that machines).
    ///
    /// # Errors
    /// [`SimError::Program`] for a step tolerance that is not a positive length.
    pub fn of_paths(
        surface: &Surface,
        cutter: &Cutter,
        machine: &Machine,
        set: &PathSet,
        step_tol_mm: f64,
    ) -> Result<Self, SimError> {
        if !(step_tol_mm > 0.0 && step_tol_mm.is_finite()) {
            return Err(SimError::Program(format!(
                "the step tolerance must be a positive length in mm, got {step_tol_mm}; give e.g. 0.01"
            )));
        }
        Ok(Self {
            surface: surface.clone(),
            cutter: set.strategy.cutter_for(cutter),
            machine: *machine,
            passes: set.paths.iter().filter(|p| p.nodes.len() >= 2).map(|p| p.nodes.clone()).collect(),
            step_tol_mm,
            label: format!("{}, {}", set.strategy.name(), set.layout.name()),
        })
    }

    /// Appends the moves of pass `k` (its seed-002 steps, joints interpolated linearly) to
    /// `program`; nothing for a pass that does not exist.
    ///
    /// # Errors
    /// [`SimError::Program`] when the steps cannot be planned (the planner's message) or
    /// the program grows beyond [`super::program::MAX_MOVES`].
    pub fn plan_pass(&self, k: usize, program: &mut Program) -> Result<(), SimError> {
        let Some(nodes) = self.passes.get(k) else { return Ok(()) };
        let mut budget = PlanBudget::new(0.0, MAX_PLAN_DESIGNS);
        push_pass(&self.machine, &self.surface, &self.cutter, (k, nodes), self.step_tol_mm, program, &mut budget)
    }

    /// The whole program (every pass planned; see [`FinishProgram::plan_pass`]).
    ///
    /// # Errors
    /// As [`FinishProgram::plan_pass`].
    pub fn program(&self) -> Result<Program, SimError> {
        self.program_within(MAX_PLAN_DESIGNS).map(|(program, _)| program)
    }

    /// The whole program, its planning evaluating at most `max_designs` designs (what a
    /// command's paths left of its work: [`crate::numerics::limits::CommandShare`]), and the
    /// designs it evaluated.
    ///
    /// # Errors
    /// As [`FinishProgram::plan_pass`]; [`SimError::PlanWork`] naming the pass being planned
    /// when the program is on course to pass `max_designs`.
    pub fn program_within(&self, max_designs: f64) -> Result<(Program, u64), SimError> {
        let total_mm = design_length_mm(&self.surface, &self.cutter, self.passes.iter().map(Vec::as_slice));
        let mut budget = PlanBudget::new(total_mm, max_designs);
        let mut out = Program::default();
        for (k, nodes) in self.passes.iter().enumerate() {
            push_pass(&self.machine, &self.surface, &self.cutter, (k, nodes), self.step_tol_mm, &mut out, &mut budget)?;
        }
        Ok((out, budget.designs()))
    }

    /// The contact points of every pass (mm), in travel order (lead-in and lead-out rows,
    /// which are not contact points, left out).
    #[must_use]
    pub fn cc_points(&self) -> Vec<Vec<DVec3>> {
        self.passes.iter().map(|p| p.iter().filter(|n| !n.lead_out).map(|n| n.frame.point).collect()).collect()
    }

    /// The rays of `grid` in the program's interior band ([`super::interior`]: between the
    /// first and last pass, [`INTERIOR_SIDE_MM`] from them and [`INTERIOR_END_MM`] from the
    /// passes' ends).
    #[must_use]
    pub fn interior_mask(&self, grid: &Grid) -> Vec<bool> {
        interior_mask(grid, &self.cc_points(), INTERIOR_END_MM, INTERIOR_SIDE_MM)
    }

    /// The design: the finish surface ([`Design::Surface`]).
    #[must_use]
    pub fn design(&self) -> Design {
        Design::Surface(self.surface.clone())
    }

    /// The box (mm) of the surface's points on a [`PART_BOX_SAMPLES`]² grid of its domain;
    /// `None` when no point is finite.
    #[must_use]
    pub fn part_box(&self) -> Option<(DVec3, DVec3)> {
        part_box(&self.surface)
    }

    /// The largest step (mm) between the sampled poses of a flat or fillet `cutter` for a
    /// program judged on scallop `scallop_mm`: between two poses the corner (radius r) leaves
    /// a cusp of about s²/(8r), kept to [`POSE_CUSP_SHARE`] of h, so the simulated scallop
    /// measures the paths, not the sampling; at least [`MIN_POSE_STEP_MM`]. `None` for a ball
    /// (its moves are swept in closed form).
    #[must_use]
    pub fn pose_step_mm(cutter: &Cutter, scallop_mm: f64) -> Option<f64> {
        (cutter.kind() != crate::geom::CutterKind::Ball && scallop_mm > 0.0 && scallop_mm.is_finite())
            .then(|| (8.0 * cutter.corner_radius_mm * POSE_CUSP_SHARE * scallop_mm).sqrt().max(MIN_POSE_STEP_MM))
    }

    /// The default stock `x0, y0, z0, x1, y1, z1` (mm): the part's box widened by the
    /// cutter radius and `margin_mm` in x and y (the cutter overhangs the edge paths), from
    /// `margin_mm` below its lowest point to `margin_mm` above its highest (the finishing
    /// allowance). `None` when the box is not finite.
    #[must_use]
    pub fn stock_mm(&self, margin_mm: f64) -> Option<[f64; 6]> {
        stock_box_mm(&self.surface, &self.cutter, margin_mm)
    }
}

/// [`FinishProgram::stock_mm`] before any path is planned: it depends only on the surface,
/// the cutter the program machines with (`Strategy::cutter_for`) and the margin (mm), so a
/// caller can size (and refuse) the stock before the planning's work.
#[must_use]
pub fn stock_box_mm(surface: &Surface, cutter: &Cutter, margin_mm: f64) -> Option<[f64; 6]> {
    let (lo, hi) = part_box(surface)?;
    let m = margin_mm.max(0.0);
    let w = cutter.radius_mm + m;
    Some([lo.x - w, lo.y - w, lo.z - m, hi.x + w, hi.y + w, hi.z + m])
}

/// The box (mm) of a surface's points on a [`PART_BOX_SAMPLES`]² grid of its domain.
#[must_use]
pub fn part_box(surface: &Surface) -> Option<(DVec3, DVec3)> {
    let d = surface.domain();
    let n = PART_BOX_SAMPLES;
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..n {
        for j in 0..n {
            let s = DVec2::new(i as f64, j as f64) / (n - 1) as f64;
            let p = surface.point_at(DVec2::new(d.u.min + s.x * d.u.width(), d.v.min + s.y * d.v.width()));
            if p.is_finite() {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
    }
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// One pass's seed-002 steps on `machine` (`cutter` the one that machines, steps within
/// `step_tol_mm`, spending `budget`) pushed onto `program` as joint moves:
/// [`FinishProgram::plan_pass`]'s body, which [`WorkProjection`] runs on the pilot's runs.
/// `pass`: the pass's index (for the message) and its nodes.
fn push_pass(
    machine: &Machine,
    surface: &Surface,
    cutter: &Cutter,
    pass: (usize, &[CcNode]),
    step_tol_mm: f64,
    program: &mut Program,
    budget: &mut PlanBudget,
) -> Result<(), SimError> {
    let (k, nodes) = pass;
    let pieces =
        plan_path_pieces_within(machine, surface, cutter, nodes, step_tol_mm, budget).map_err(|e| match e {
            e @ crate::fiveaxis::FiveAxisError::TooMuchWork { .. } => SimError::PlanWork { pass: k, source: e },
            e => SimError::Program(format!("pass {k}: the 5-axis steps cannot be planned — {e}")),
        })?;
    // A pass cut where the axis would leave the travel goes on after a rapid move, which
    // is left out as the linking moves are.
    for joints in &pieces {
        for w in joints.windows(2) {
            program.push(SimMove {
                kind: MoveKind::Joints { machine: *machine, from: w[0], to: w[1] },
                line: 0,
                rapid: false,
            })?;
        }
    }
    Ok(())
}

/// A finishing program's simulation work ([`Simulation::work_done`], straight-move ray
/// updates), estimated before its paths are built from the job's pilot: so that a
/// simulation that would pass [`MAX_WORK`] by far is refused in the first second of the
/// job, not after its paths (seconds). The pilot's runs are planned as the program's
/// passes will be; their moves' estimated ray visits ([`Simulation::estimate_move_visits`])
/// times [`work_per_visit`] are their work. (The work was also projected from the share of
/// the surface the paths had covered as they were built: on fuzz jobs whose cost is not
/// spread evenly over the surface that read up to ten times the run's work and refused,
/// after 3–8 s, runs that complete in 11–24 s. What the pilot misses, the run's own meter
/// stops, within what the paths and the program left of the command's work.)
#[derive(Clone, Debug)]
pub struct WorkProjection<'a> {
    surface: &'a Surface,
    cutter: &'a Cutter,
    machine: &'a Machine,
    strategy: Strategy,
    step_tol_mm: f64,
}

impl<'a> WorkProjection<'a> {
    /// The projection of a job on `surface` with `cutter` (the scene's) and `strategy`, its
    /// program on `machine` with steps within `step_tol_mm`.
    #[must_use]
    pub fn new(
        surface: &'a Surface,
        cutter: &'a Cutter,
        machine: &'a Machine,
        strategy: Strategy,
        step_tol_mm: f64,
    ) -> Self {
        Self { surface, cutter, machine, strategy, step_tol_mm }
    }

    /// The estimated work of `paths`' passes on `sim` (0 for a path too short to be a pass,
    /// or whose steps cannot be planned: the program itself will say why).
    #[must_use]
    pub fn work_of(&self, sim: &Simulation, paths: &[ToolPath]) -> f64 {
        if !(self.step_tol_mm > 0.0 && self.step_tol_mm.is_finite()) {
            return 0.0;
        }
        let tool = self.strategy.cutter_for(self.cutter);
        let mut visits = 0.0;
        let mut budget = PlanBudget::new(0.0, MAX_PLAN_DESIGNS);
        for (k, path) in paths.iter().filter(|p| p.nodes.len() >= 2).enumerate() {
            let mut pass = Program::default();
            if push_pass(self.machine, self.surface, &tool, (k, &path.nodes), self.step_tol_mm, &mut pass, &mut budget)
                .is_ok()
            {
                visits += pass.moves.iter().map(|m| sim.estimate_move_visits(m)).sum::<f64>();
            }
        }
        work_per_visit(sim) * visits
    }

    /// Refuses the program when the job's `pilot` says its simulation on `sim` would pass
    /// [`PROJECTION_ROOM`] × [`PROJECTED_WORK_ROOM`] × [`MAX_WORK`]: the pilot's runs' work
    /// per mm of run, times the job's estimated length.
    ///
    /// # Errors
    /// [`SimError::TooMuchFinishWork`].
    pub fn check_pilot(&self, sim: &Simulation, pilot: &Pilot) -> Result<(), SimError> {
        let runs_mm: f64 = pilot.runs.iter().map(ToolPath::length_mm).sum();
        if !(runs_mm > 0.0 && pilot.length_mm.is_finite()) {
            return Ok(());
        }
        let projected = self.work_of(sim, &pilot.runs) / runs_mm * pilot.length_mm;
        if projected > PROJECTION_ROOM * PROJECTED_WORK_ROOM * MAX_WORK {
            return Err(SimError::TooMuchFinishWork { projected, max: MAX_WORK });
        }
        Ok(())
    }
}
