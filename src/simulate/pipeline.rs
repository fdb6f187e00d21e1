//! Make the program, then simulate it: the one pipeline of the command line's
//! `interpolab simulate` and the app's simulation job (`jobs::simulate_run`). A G-code text
//! is read in its dialect ([`guess_dialect`] from its head unless given, [`read_options`],
//! [`read_text`] or [`read_interpreted`] at most [`MAX_MOVES`] moves), its points moved to
//! the tool tip ([`ToolPoint`]) and cut into chords ([`program_of`], by default at
//! [`default_chord_tol_mm`]); a simulation is started on a stock with the cutter and its
//! sampling ([`SampleStep`], [`start`]: refused above [`MAX_RAY_VISITS`]), machines the
//! moves ([`machine`]) and its stock is measured against a design ([`measure`]).
//!
//! Each caller keeps only what is its own: the command line streams a file with the files
//! beside it as subroutines and prints JSON; the job reads the text it was handed, reports
//! progress, looks at its cancel flag, keeps stocks and sends keyframes.

use std::hint::black_box;

use glam::DVec3;

use super::program::MAX_MOVES;
use super::{
    Design, DeviationScan, DexelStock, HeightMap, MAX_RAY_VISITS, MAX_WORK, PROJECTED_WORK_ROOM, Program, SimError,
    SimMove, SimStats, Simulation,
};
use crate::gcode::interp::{Interpreter, Options};
use crate::gcode::{Dialect, ParseError, ParsedProgram, ProgrammedPoint, Toolpath, parse_program_in, read_from_capped};
use crate::geom::{Cutter, CutterKind};

/// Bytes of a program's head its dialect is guessed from (a file is not read whole for it).
pub const DIALECT_GUESS_BYTES: usize = 64 << 10;

/// Comments a program is read with (its header among them: the programmed point).
pub const KEPT_COMMENTS: usize = 64;

/// The dialect of a program, guessed from its first [`DIALECT_GUESS_BYTES`] bytes (read as
/// UTF-8, a malformed sequence replaced).
#[must_use]
pub fn guess_dialect(text: &[u8]) -> Dialect {
    let head = &text[..text.len().min(DIALECT_GUESS_BYTES)];
    Dialect::guess(&String::from_utf8_lossy(head))
}

/// The interpreter's options to read a program of `dialect` with: `base` (units, strictness,
/// block delete, tools) with [`KEPT_COMMENTS`] comments kept and FANUC's meanings for a
/// FANUC program.
#[must_use]
pub fn read_options(dialect: Dialect, base: &Options) -> Options {
    Options { keep_comments: KEPT_COMMENTS, fanuc: dialect == Dialect::Fanuc, ..base.clone() }
}

/// Reads the moves of a FANUC or LinuxCNC program from an interpreter over it (opened with
/// [`read_options`]), refusing past [`MAX_MOVES`] moves.
///
/// # Errors
/// The line that cannot be read, or [`ParseError::TooManyMoves`].
pub fn read_interpreted(it: Interpreter<'_>, dialect: Dialect) -> Result<ParsedProgram, ParseError> {
    read_from_capped(it, dialect, MAX_MOVES)
}

/// Reads a whole program text in `dialect`: Sinumerik by its own reader, FANUC and LinuxCNC
/// through the interpreter ([`read_options`] of `base`, no subroutine files,
/// [`read_interpreted`]).
///
/// # Errors
/// The line that cannot be read, or [`ParseError::TooManyMoves`].
pub fn read_text(text: &str, dialect: Dialect, base: &Options) -> Result<ParsedProgram, ParseError> {
    if dialect == Dialect::Sinumerik {
        return parse_program_in(text, dialect);
    }
    read_interpreted(Interpreter::from_text(text, read_options(dialect, base)), dialect)
}

/// The point of the tool a program's coordinates give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolPoint {
    /// The tool tip (bottom centre of the cutter).
    Tip,
    /// The ball centre: the tip is one cutter radius below it.
    BallCentre,
}

impl ToolPoint {
    /// What a program's header comments say (`PROGRAMMED POINT: BALL CENTRE`, as
    /// `interpolab gcode` writes it); the tip otherwise.
    #[must_use]
    pub fn of_comments(comments: &[(usize, String)]) -> Self {
        match ProgrammedPoint::from_comments(comments) {
            Some(ProgrammedPoint::BallCentre) => Self::BallCentre,
            _ => Self::Tip,
        }
    }

    /// Translation (mm) from the programmed point to the tip of `cutter`.
    #[must_use]
    pub fn tip_offset(self, cutter: &Cutter) -> DVec3 {
        match self {
            Self::Tip => DVec3::ZERO,
            Self::BallCentre => DVec3::new(0.0, 0.0, -cutter.radius_mm),
        }
    }

    /// Its name in reports: `tool tip` or `ball centre`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Tip => "tool tip",
            Self::BallCentre => "ball centre",
        }
    }
}

/// The chord tolerance (mm) arcs and NURBS are cut at when none is given: a tenth of the
/// pitch `pitch_mm` (mm).
#[must_use]
pub fn default_chord_tol_mm(pitch_mm: f64) -> f64 {
    pitch_mm / 10.0
}

/// A program read into a path as tool-tip moves of `cutter`: its points given as `point`,
/// arcs and NURBS cut into chords within `chord_tol_mm` (mm).
///
/// # Errors
/// [`SimError::Program`] (a chord tolerance that is not a positive length, too many chords
/// or moves).
pub fn program_of(
    toolpath: &Toolpath,
    point: ToolPoint,
    cutter: &Cutter,
    chord_tol_mm: f64,
) -> Result<Program, SimError> {
    Program::from_toolpath(toolpath, point.tip_offset(cutter), chord_tol_mm)
}

/// How 5-axis moves are sampled between poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleStep {
    /// The simulation's own choice: closed-form swept segments for a ball, poses one pitch
    /// apart for flat and fillet end mills.
    Default,
    /// Pose by pose at most this far apart (mm), every cutter, the ball included (the
    /// command line's `--sample-step`).
    Given(f64),
    /// At most this far apart (mm) where that is finer than the default: below the pitch,
    /// for a cutter that is not a ball (the app's slider); else [`SampleStep::Default`].
    BelowPitch(f64),
}

impl SampleStep {
    /// The step (mm) the simulation samples at on a grid of pitch `pitch_mm` (mm) with
    /// `cutter` (`None`: the default).
    #[must_use]
    pub fn resolve(self, pitch_mm: f64, cutter: &Cutter) -> Option<f64> {
        match self {
            Self::Default => None,
            Self::Given(step) => Some(step),
            Self::BelowPitch(step) => (step < pitch_mm && cutter.kind() != CutterKind::Ball).then_some(step),
        }
    }
}

/// A simulation of `cutter` on `stock`, 5-axis moves sampled every `sample_step_mm` (mm;
/// `None`: the default, [`SampleStep::resolve`]), ready to machine `program`.
///
/// # Errors
/// [`SimError::TooMuchWork`] when the program would visit more than [`MAX_RAY_VISITS`] rays.
pub fn start(
    stock: DexelStock,
    cutter: &Cutter,
    sample_step_mm: Option<f64>,
    program: &Program,
) -> Result<Simulation, SimError> {
    start_metered(stock, cutter, sample_step_mm, program).map(|(sim, _)| sim)
}

/// [`start`], with the [`WorkMeter`] of the program made from the same estimates (each
/// move's visits are estimated once).
///
/// # Errors
/// As [`start`].
pub fn start_metered(
    stock: DexelStock,
    cutter: &Cutter,
    sample_step_mm: Option<f64>,
    program: &Program,
) -> Result<(Simulation, WorkMeter), SimError> {
    let mut sim = Simulation::new(stock, cutter);
    if let Some(step) = sample_step_mm {
        sim = sim.with_sample_step(step);
    }
    let meter = WorkMeter::new(&sim, &program.moves);
    let visits = meter.estimated_visits();
    if !(visits <= MAX_RAY_VISITS) {
        return Err(SimError::TooMuchWork { visits, max: MAX_RAY_VISITS });
    }
    Ok((sim, meter))
}

/// Share of the work left that a run on a coarser grid ([`coarser_pitch`]) is sized to
/// project: the room for the meter's projection, which reads the rest of the program by its
/// estimated ray visits, and for the work not scaling exactly as 1/pitch² (the rays a cutter
/// covers grow by its rim as well as its area).
pub const COARSER_RUN_SHARE: f64 = 0.6;

/// The pitch (mm) of a grid on which a run its meter stopped at `pitch_mm`, projecting
/// `projected` units of work, would fit in the `left` units it has left: the work scales as
/// the rays under the cutter, 1/pitch², so `pitch_mm · √(projected / (COARSER_RUN_SHARE ·
/// left))`, rounded up to two significant digits. `None` when nothing is left, the inputs
/// are not finite and positive, or the pitch would pass `max_pitch_mm` (a grid that coarse
/// shows little of the cut: the caller refuses as before).
#[must_use]
pub fn coarser_pitch(pitch_mm: f64, projected: f64, left: f64, max_pitch_mm: f64) -> Option<f64> {
    if !(pitch_mm > 0.0 && pitch_mm.is_finite() && projected.is_finite() && left > 0.0 && left.is_finite()) {
        return None;
    }
    let exact = pitch_mm * (projected / (COARSER_RUN_SHARE * left)).sqrt();
    if !(exact > pitch_mm) {
        return None;
    }
    // Two significant digits, rounded up (0.9713 → 0.98, 1.234 → 1.3), and the nearest
    // double to that decimal, so it prints as it reads.
    let magnitude = exact.log10().floor() as i32;
    let unit = 10f64.powi(magnitude - 1);
    let decimals = usize::try_from(1 - magnitude).unwrap_or(0);
    let pitch = (exact / unit).ceil() * unit;
    let pitch = format!("{pitch:.decimals$}").parse().unwrap_or(pitch);
    (pitch <= max_pitch_mm).then_some(pitch)
}

/// The bound on a run's work ([`MAX_WORK`]): refuses it once the work done, scaled by the
/// estimated ray visits of the moves still to come, reads [`PROJECTED_WORK_ROOM`] times the
/// cap (judged once a twentieth of the estimated visits is done), and stops it when the work
/// done does. Deterministic: counts of ray updates, never a clock.
#[derive(Clone, Debug)]
pub struct WorkMeter {
    /// Estimated ray visits of the moves before each move (`moves.len() + 1` entries).
    before: Vec<f64>,
    /// The cap (straight-move ray updates): [`MAX_WORK`].
    max: f64,
}

impl WorkMeter {
    /// The meter of `moves` machined by `sim` from its start.
    #[must_use]
    pub fn new(sim: &Simulation, moves: &[SimMove]) -> Self {
        let mut before = Vec::with_capacity(moves.len() + 1);
        let mut sum = 0.0;
        before.push(0.0);
        for m in moves {
            sum += sim.estimate_move_visits(m);
            before.push(sum);
        }
        Self { before, max: MAX_WORK }
    }

    /// The program's estimated ray visits ([`Simulation::estimate_visits`]).
    #[must_use]
    pub fn estimated_visits(&self) -> f64 {
        self.before.last().copied().unwrap_or(0.0)
    }

    /// The same meter with another cap (straight-move ray updates; tests use small ones).
    #[must_use]
    pub fn with_cap(mut self, max: f64) -> Self {
        self.max = max;
        self
    }

    /// After the first `done` moves of the meter's program.
    ///
    /// # Errors
    /// [`SimError::TooMuchWorkDone`] when the work done, or projected, passes the room.
    pub fn check(&self, sim: &Simulation, moves: &[SimMove], done: usize) -> Result<(), SimError> {
        let total = self.estimated_visits();
        let so_far = self.before.get(done).copied().unwrap_or(total);
        let work = sim.work_done();
        let projected = if so_far >= 0.05 * total && so_far > 0.0 { work * total / so_far } else { work };
        let stop = PROJECTED_WORK_ROOM * self.max;
        if work > stop || projected > stop {
            return Err(SimError::TooMuchWorkDone {
                done,
                moves: moves.len(),
                line: done.checked_sub(1).and_then(|k| moves.get(k)).map_or(0, |m| m.line),
                work,
                projected: projected.max(work),
                max: self.max,
            });
        }
        Ok(())
    }
}

/// Machines `moves` one after the other, calling `after` with the simulation after each
/// (a job's progress, cancel flag, kept stocks and keyframes); stops at its first error.
///
/// # Errors
/// The first error of `after`.
pub fn machine<E>(
    sim: &mut Simulation,
    moves: &[SimMove],
    mut after: impl FnMut(&Simulation) -> Result<(), E>,
) -> Result<(), E> {
    // Each move is a call V8 can run in optimised code (`Simulation::apply`): through a
    // pointer no optimiser sees through, since `wasm-opt -O3` inlines a function called from
    // one place whatever Rust asked (with it the worker's job was back to 2.4–2.9 s).
    let apply: fn(&mut Simulation, &SimMove) -> f64 = black_box(Simulation::apply);
    for m in moves {
        apply(sim, m);
        after(sim)?;
    }
    Ok(())
}

/// The same stock block on a coarser grid, for a run its meter stops ([`run_metered`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoarserGrid {
    /// The block's lower corner (mm).
    pub lo_mm: [f64; 3],
    /// Its upper corner (mm).
    pub hi_mm: [f64; 3],
    /// The coarsest pitch offered (mm); coarser, the run is refused as before.
    pub max_pitch_mm: f64,
}

/// A run [`run_metered`] gave up for a coarser grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coarsened {
    /// The pitch asked for (mm).
    pub asked_pitch_mm: f64,
    /// The work its meter projected ([`Simulation::work_done`] units).
    pub projected: f64,
    /// The work left after it, which the coarser run was sized for.
    pub left: f64,
}

/// Machines `program` on `stock` within `cap` units of work ([`WorkMeter`], refused as it
/// says); when its meter stops it and `coarser` is given, once more on the block's grid at
/// [`coarser_pitch`] within what is left (`None` there: the meter's refusal). Returns the
/// simulation and, when it ran again, what it gave up.
///
/// # Errors
/// [`start_metered`]'s, and the meter's [`SimError::TooMuchWorkDone`].
pub fn run_metered(
    stock: DexelStock,
    cutter: &Cutter,
    sample_step: SampleStep,
    program: &Program,
    cap: f64,
    coarser: Option<CoarserGrid>,
) -> Result<(Simulation, Option<Coarsened>), SimError> {
    let run = |stock: DexelStock, cap: f64| -> Result<Simulation, SimError> {
        let step = sample_step.resolve(stock.grid().pitch_mm, cutter);
        let (mut sim, meter) = start_metered(stock, cutter, step, program)?;
        let meter = meter.with_cap(cap);
        let mut done = 0;
        machine(&mut sim, &program.moves, |sim| {
            done += 1;
            meter.check(sim, &program.moves, done)
        })?;
        Ok(sim)
    };
    let asked_pitch_mm = stock.grid().pitch_mm;
    let e = match run(stock, cap) {
        Ok(sim) => return Ok((sim, None)),
        Err(e) => e,
    };
    let SimError::TooMuchWorkDone { work, projected, .. } = e else { return Err(e) };
    let left = cap - work;
    let Some((g, pitch)) =
        coarser.and_then(|g| Some((g, coarser_pitch(asked_pitch_mm, projected, left, g.max_pitch_mm)?)))
    else {
        return Err(e);
    };
    let Ok(stock) = DexelStock::block(g.lo_mm, g.hi_mm, pitch) else { return Err(e) };
    let sim = run(stock, left)?;
    Ok((sim, Some(Coarsened { asked_pitch_mm, projected, left })))
}

/// A machined stock's height map and its measures against a design.
#[derive(Clone, Debug, PartialEq)]
pub struct Measures {
    /// The height map.
    pub map: HeightMap,
    /// Its measures.
    pub stats: SimStats,
}

/// Measures `stock` against `design`, `rows_per_call` grid rows at a time, calling `after`
/// with the rows done after each call (a job's progress and cancel flag; [`SimStats::of`]
/// in one call when `rows_per_call` is at least the grid's rows).
///
/// # Errors
/// The first error of `after`.
pub fn measure<E>(
    stock: &DexelStock,
    design: &Design,
    rows_per_call: usize,
    mut after: impl FnMut(usize) -> Result<(), E>,
) -> Result<Measures, E> {
    let map = HeightMap::of(stock);
    let mut scan = DeviationScan::new(&map, design);
    while scan.rows_done() < map.grid.ny {
        scan.rows(&map, design, rows_per_call.max(1));
        after(scan.rows_done())?;
    }
    let stats = scan.finish(&map, stock);
    Ok(Measures { map, stats })
}
