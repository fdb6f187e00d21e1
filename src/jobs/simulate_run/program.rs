//! The program of a run, made from its source (a scene's crease written as G-code, its
//! five-axis steps, a G-code text, a finishing program's passes, a benchmark, or moves
//! already made), and the stock block and pitch it is cut on.

use glam::DVec3;

use super::error::SimulateError;
use super::progress::{PROGRAM_SHARE, Reporter};
use super::request::{AUTO_GRID_SIDE, PITCH_RANGE_MM, ProgramSource, Request};
use crate::chords::RootMethod;
use crate::crease::{CreaseCurve, CreaseJob};
use crate::fillet::CcNode;
use crate::fiveaxis::{CreasePath, StepOptions, StepPlanner, ToolAxisRule};
use crate::gcode::interp::Options as ReadOptions;
use crate::gcode::{DesignBuilder, ProgramOptions, ProgrammedPoint, write_program};
use crate::geom::Cutter;
use crate::scene::finish::FinishScene;
use crate::scene::{Scene, build_machine, build_tool_axis};
use crate::simulate::pipeline::{self, ToolPoint};
use crate::simulate::{FinishProgram, MoveKind, Program, SimMove};

/// Periods of the crease run between two looks at the cancel flag.
const PERIODS_PER_CALL: usize = 200;
/// Tolerance (mm) of the crease programs and the step plan written for the simulation (the
/// NURBS tab's and the `steps` command's default).
pub const PROGRAM_TOL_MM: f64 = 0.01;

/// A scene with its crease job.
pub(super) struct CreaseScene {
    /// The scene.
    pub(super) scene: Scene,
    /// Its crease.
    pub(super) job: CreaseJob,
}

/// The stock block and the pitch a program is cut on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockAndPitch {
    /// Stock block `x0, y0, z0, x1, y1, z1` (mm).
    pub stock_mm: [f64; 6],
    /// Pitch (mm).
    pub pitch_mm: f64,
}

/// The scene in JSON `text` with its crease.
pub(super) fn scene_of(text: &str) -> Result<CreaseScene, SimulateError> {
    let scene = Scene::from_json(text).map_err(SimulateError::Scene)?;
    let job = CreaseJob::from_scene(&scene).map_err(SimulateError::Scene)?;
    Ok(CreaseScene { scene, job })
}

/// The scene's crease as a design curve, checking the cancel flag between slices.
fn crease_curve(job: &CreaseJob, rep: &Reporter<'_>) -> Result<CreaseCurve, SimulateError> {
    let mut b = DesignBuilder::new(job).map_err(SimulateError::CreaseStart)?;
    loop {
        rep.cancelled()?;
        if let Some(done) = b.advance(PERIODS_PER_CALL) {
            return done.map_err(SimulateError::CreaseCurve);
        }
    }
}

/// The program of a request's source, in tool-tip moves.
pub(super) fn make_program(req: &Request, rep: &mut Reporter<'_>) -> Result<Program, SimulateError> {
    let (toolpath, point) = match &req.source {
        ProgramSource::Moves(p) => return Ok(p.clone()),
        ProgramSource::Finish { scene, cutter, passes, step_tol_mm } => {
            let fp = finish_program(scene, *cutter, passes, *step_tol_mm)?;
            let mut program = Program::default();
            for k in 0..fp.passes.len() {
                rep.cancelled()?;
                fp.plan_pass(k, &mut program)?;
                rep.at(PROGRAM_SHARE * (k + 1) as f64 / fp.passes.len() as f64);
            }
            return Ok(program);
        }
        ProgramSource::Benchmark { kind, moves } => return Ok(kind.program(*moves)?),
        ProgramSource::Steps { scene } => {
            let CreaseScene { scene, job } = scene_of(scene)?;
            let curve = crease_curve(&job, rep)?;
            let machine = scene.machine.as_ref().map(build_machine).unwrap_or_default();
            let rule = match &scene.tool_axis {
                Some(t) => build_tool_axis(t).map_err(SimulateError::ToolAxis)?,
                None => ToolAxisRule::Bisector,
            };
            let path = CreasePath::new(curve, rule);
            let opts = StepOptions::new(PROGRAM_TOL_MM).with_method(RootMethod::Bisection);
            let mut planner = StepPlanner::new(&machine, &path, &opts).map_err(SimulateError::Steps)?;
            // The planner's own caps bound the nodes; the flag is looked at per node.
            while !planner.is_done() {
                rep.cancelled()?;
                planner.next_node(&machine, &path).map_err(SimulateError::Steps)?;
            }
            let blocks: Vec<_> = planner.nodes().iter().map(|n| n.block).collect();
            return Ok(Program::from_blocks(&machine, &blocks)?);
        }
        ProgramSource::Crease { scene, kind } => {
            let CreaseScene { scene, job } = scene_of(scene)?;
            let curve = crease_curve(&job, rep)?;
            let title = if scene.name.is_empty() { "scene".to_owned() } else { scene.name.clone() };
            let opts = ProgramOptions::default().with_title(&title).with_point(ProgrammedPoint::BallCentre);
            let p = write_program(*kind, &curve, PROGRAM_TOL_MM, &opts)
                .map_err(|source| SimulateError::Write { kind: kind.label(), source })?;
            (p.parsed.toolpath, ToolPoint::BallCentre)
        }
        ProgramSource::Text { name, text } => {
            let dialect = pipeline::guess_dialect(text.as_bytes());
            let parsed = pipeline::read_text(text, dialect, &ReadOptions::default())
                .map_err(|source| SimulateError::Read { name: name.clone(), source })?;
            let point = ToolPoint::of_comments(&parsed.comments);
            (parsed.toolpath, point)
        }
    };
    let chord = pipeline::default_chord_tol_mm;
    // The chord tolerance follows the pitch, which may follow the program's box: chord at
    // the smallest pitch offered first when automatic, then again at the one chosen.
    let pitch0 = req.pitch_mm.unwrap_or(PITCH_RANGE_MM.0);
    let program = pipeline::program_of(&toolpath, point, &req.cutter, chord(pitch0))?;
    if req.pitch_mm.is_none() {
        let pitch = stock_and_pitch(req, &program)?.pitch_mm;
        if (pitch - pitch0).abs() > 0.0 {
            return Ok(pipeline::program_of(&toolpath, point, &req.cutter, chord(pitch))?);
        }
    }
    Ok(program)
}

/// The stock block and pitch for `program`: the request's, else automatic.
///
/// # Errors
/// A program without a cutting move and no stock given.
pub fn stock_and_pitch(req: &Request, program: &Program) -> Result<StockAndPitch, SimulateError> {
    let stock = match req.stock_mm {
        Some(s) => s,
        None => auto_stock(program, &req.cutter, req.margin_mm).ok_or(SimulateError::NoCuttingMove)?,
    };
    let pitch = match req.pitch_mm {
        Some(p) => p,
        None => {
            let side = (stock[3] - stock[0]).max(stock[4] - stock[1]);
            let p = side / AUTO_GRID_SIDE;
            // Round up to 2 significant digits, within the range offered.
            let scale = 10f64.powf(p.log10().floor() - 1.0);
            ((p / scale).ceil() * scale).clamp(PITCH_RANGE_MM.0, PITCH_RANGE_MM.1)
        }
    };
    Ok(StockAndPitch { stock_mm: stock, pitch_mm: pitch })
}

/// The box of the program's cutting moves (rapids left out) widened by the cutter radius
/// and `margin_mm` in x and y; z from `margin_mm` below the lowest tip to one radius above
/// the highest cutting tip. `None` without a cutting move.
#[must_use]
pub fn auto_stock(program: &Program, cutter: &Cutter, margin_mm: f64) -> Option<[f64; 6]> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for m in program.moves.iter().filter(|m| !m.rapid) {
        for p in ends(m) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let r = cutter.radius_mm;
    let m = margin_mm.max(0.0);
    Some([lo.x - r - m, lo.y - r - m, lo.z - m, hi.x + r + m, hi.y + r + m, hi.z + r])
}

/// The tool tip at the start and end of a move (mm).
#[must_use]
pub fn ends(m: &SimMove) -> [DVec3; 2] {
    match m.kind {
        MoveKind::Line { from, to } => [from, to],
        MoveKind::Joints { machine, from, to } => {
            [machine.pose_from_joints(&from).tip_in_workpiece, machine.pose_from_joints(&to).tip_in_workpiece]
        }
    }
}

/// The finishing program of a [`ProgramSource::Finish`]: the scene's surface and machine,
/// the passes and cutter given.
///
/// # Errors
/// The scene's message, or the step tolerance's.
pub fn finish_program(
    scene: &str,
    cutter: Cutter,
    passes: &[Vec<CcNode>],
    step_tol_mm: f64,
) -> Result<FinishProgram, SimulateError> {
    let job = FinishScene::from_json(scene).and_then(|f| f.job()).map_err(SimulateError::FinishScene)?;
    if !(step_tol_mm > 0.0 && step_tol_mm.is_finite()) {
        return Err(SimulateError::StepTolerance(step_tol_mm));
    }
    Ok(FinishProgram {
        surface: job.surface,
        cutter,
        machine: job.machine,
        passes: passes.iter().filter(|p| p.len() >= 2).cloned().collect(),
        step_tol_mm,
        label: String::new(),
    })
}
