//! A cutting simulation as a background job: the program written (the scene's crease as
//! G01, G02/G03 or G06.2, the scene's seed-002 tool steps) or read (a G-code text) or given
//! (moves made by an earlier run), machined into a dexel stock up to a target move by
//! [`Simulation`], and measured against the design ([`DeviationScan`](crate::simulate::DeviationScan)). A long program takes
//! seconds in a browser; in a Web Worker the page stays responsive.
//!
//! While it runs the job hands back, as partial outputs ([`Partial`]): the program once it
//! is made ([`Prepared`]: the moves, the stock and the grid), then **keyframes** of the
//! stock — its top heights as `f32` and which rays are machined — every `N` moves, `N` chosen
//! so a run sends at most [`Request::keyframes`] of them and at most
//! [`KEYFRAME_BYTES`] in all. The page shows the latest keyframe while the run goes on,
//! and, when the user scrubs the move slider back, the keyframe at or before the move at
//! once; the exact stock at that move comes from a new run of this job to that move with the
//! moves of the first ([`ProgramSource::Moves`]: no crease, plan or program written again).
//! The output is the stock's exact height map and its measures at the target move.
//!
//! Everything crosses as text: numbers by their bits, large arrays packed as base64url of
//! their little-endian bytes (a 256 × 256 keyframe is 437 KB of text, the final map with its
//! deviations 1.4 MB; a run without a design sends no deviations: 0.8 MB).

use glam::{DVec2, DVec3};
use serde_json::{Value, json};

use super::{JobKind, Progress, Reader, bits_packed, f32s_packed, f64s_packed, parse};
use crate::chords::RootMethod;
use crate::crease::CreaseJob;
use crate::fillet::CcNode;
use crate::fillet::contact::{ContactFrame, Form2, Pose};
use crate::fiveaxis::{CreasePath, Joints, Machine, MachineKind, StepOptions, StepPlanner, ToolAxisRule};
use crate::gcode::interp::Options as ReadOptions;
use crate::gcode::{DesignBuilder, ProgramKind, ProgramOptions, ProgrammedPoint, write_program};
use crate::geom::Cutter;
use crate::scene::finish::FinishScene;
use crate::scene::{Scene, build_machine, build_tool_axis};
use crate::simulate::FinishProgram;
use crate::simulate::bench::BenchKind;
use crate::simulate::measure::Summary;
use crate::simulate::pipeline::{self, Measures, SampleStep, ToolPoint};
use crate::simulate::stock::Grid;
use crate::simulate::{Counters, Design, DexelStock, HeightMap, MoveKind, Program, SimMove, SimStats, Simulation};

/// Periods of the crease run between two looks at the cancel flag.
const PERIODS_PER_CALL: usize = 200;
/// Grid rows of the deviation scan between two looks at the cancel flag.
const ROWS_PER_CALL: usize = 4;
/// Most rays a run simulates (a 1024 × 1024 grid, 24 MiB of stock); above it the run is
/// refused before it starts.
pub const MAX_RAYS: usize = 1024 * 1024;
/// Longest side (rays) of the grid an automatic pitch aims at.
pub const AUTO_GRID_SIDE: f64 = 256.0;
/// Pitch range offered (mm).
pub const PITCH_RANGE_MM: (f64, f64) = (0.02, 0.5);
/// Tolerance (mm) of the crease programs and the step plan written for the simulation (the
/// NURBS tab's and the `steps` command's default).
pub const PROGRAM_TOL_MM: f64 = 0.01;
/// Most bytes of keyframes (5 bytes a ray: an `f32` height and a machined flag) one run
/// hands back: 6 keyframes of a 512 × 512 grid, or 25 of the automatic 256 × 256. Each
/// is a scan of the stock and 1.75 MB of text at 512 × 512 to write, post and decode;
/// since replays start from a kept stock ([`Session`]) the slider needs fewer of them. (At
/// 40 MiB a 512 × 512 run sent 32 keyframes, 56 MB of text, on a loaded 2-core machine the
/// browser's run took 6.5–8.7 s against 2.0 s natively; 16 MiB: 12.)
pub const KEYFRAME_BYTES: usize = 8 << 20;
/// Most keyframes a request may ask for.
pub const MAX_KEYFRAMES: usize = 256;
/// Most bytes of stocks a [`Session`] keeps for replays (the stocks themselves, as
/// [`DexelStock::memory_bytes`] counts them): 8 of a 512 × 512 grid (6 MiB each), 2 of a
/// 1024 × 1024 one.
pub const KEPT_STOCK_BYTES: usize = 64 << 20;
/// Most stocks a [`Session`] keeps (evenly spaced over the program).
pub const MAX_KEPT_STOCKS: usize = 8;
/// Smallest change of the fraction done worth a progress report.
const PROGRESS_STEP: f64 = 0.005;
/// Shares of the fraction done: the program is made in the first, the moves cut in the
/// second, the deviation measured in the rest.
const PROGRAM_SHARE: f64 = 0.1;
const RUN_SHARE: f64 = 0.8;

/// Where the program comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgramSource {
    /// The crease of the scene in this JSON text as a program of this kind (ball centres,
    /// written by [`write_program`] within [`PROGRAM_TOL_MM`], moved down by the cutter
    /// radius to the tool tip).
    Crease {
        /// `interpolab-scene/1` text.
        scene: String,
        /// G01, G02/G03 or G06.2.
        kind: ProgramKind,
    },
    /// The scene's seed-002 five-axis tool steps within [`PROGRAM_TOL_MM`], joints
    /// interpolated linearly.
    Steps {
        /// `interpolab-scene/1` text.
        scene: String,
    },
    /// A G-code program's text (a file the user opened); a program of ball centres (its
    /// header says so) is moved down by the cutter radius.
    Text {
        /// Its name, for messages.
        name: String,
        /// The program.
        text: String,
    },
    /// Moves already made (an earlier run's [`Prepared::program`]).
    Moves(Program),
    /// A seed-001 finishing program: its passes' CC nodes, planned in the job pass by pass
    /// into seed-002 steps ([`FinishProgram::plan_pass`]) on the machine and surface of the
    /// finishing scene, joints interpolated linearly — off the page's thread.
    Finish {
        /// The finishing scene (`FinishScene::to_json`): its surface and machine.
        scene: String,
        /// The cutter that machines the passes (the strategy's).
        cutter: Cutter,
        /// The CC nodes of every pass, in travel order.
        passes: Vec<Vec<CcNode>>,
        /// Tolerance E (mm) of the steps.
        step_tol_mm: f64,
    },
    /// A benchmark program built in the job from its kind and move count
    /// ([`crate::simulate::bench`]): the browser's measurement of the native benchmark,
    /// without the program's text handed to the worker.
    Benchmark {
        /// Which program.
        kind: BenchKind,
        /// Its moves (at most [`crate::simulate::bench::MAX_BENCH_MOVES`]).
        moves: usize,
    },
}

/// What the machined stock is compared with.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignSpec {
    /// Nothing: heights only.
    None,
    /// The plane z = value (mm), material below.
    PlaneZ(f64),
    /// The surfaces of the scene in this JSON text.
    Scene(String),
    /// The machined surface of the seed-001 finishing scene in this JSON text
    /// (`FinishScene::to_json`), material on the side away from the cutter.
    Finish(String),
}

/// A run.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The program.
    pub source: ProgramSource,
    /// The cutter.
    pub cutter: Cutter,
    /// Pitch (mm); `None`: automatic (at most [`AUTO_GRID_SIDE`] rays a side).
    pub pitch_mm: Option<f64>,
    /// Stock block `x0, y0, z0, x1, y1, z1` (mm); `None`: the program's box plus margin.
    pub stock_mm: Option<[f64; 6]>,
    /// Margin (mm) around the program's box of an automatic stock.
    pub margin_mm: f64,
    /// Largest step (mm) between the sampled poses of a flat or fillet cutter's 5-axis move;
    /// `None`: one pitch. Between two poses the cutter leaves a cusp of about s²/(8r), so a
    /// program judged on a scallop h needs s well under √(8·r·h) (a ball's moves are swept
    /// in closed form and ignore it).
    pub max_sample_step_mm: Option<f64>,
    /// The design.
    pub design: DesignSpec,
    /// Move to machine up to (`None`: all).
    pub target: Option<usize>,
    /// Most keyframes to hand back (0: none).
    pub keyframes: usize,
    /// Whether the run may start from a stock an earlier run of the same program kept
    /// ([`Session`]; a replay of the move slider) instead of the block. Every run keeps
    /// stocks for later ones; a program's first run starts from the block so it sends all
    /// its keyframes.
    pub resume: bool,
}

impl Request {
    /// The benchmark program `kind` of `moves` moves as the benchmarks machine it (the CLI's
    /// `simulate --benchmark`, `benches/native_and_wasm/simulate.rs`): a ball of
    /// [`crate::simulate::bench::BALL_MM`] on the benchmark block at `pitch_mm` (mm), no
    /// design, no keyframes, from the block.
    ///
    /// # Errors
    /// None for the benchmark's ball (the cutter's constructor is fallible in general).
    pub fn benchmark(kind: BenchKind, moves: usize, pitch_mm: f64) -> Result<Self, crate::geom::CutterError> {
        Ok(Self {
            source: ProgramSource::Benchmark { kind, moves },
            cutter: Cutter::ball(crate::simulate::bench::BALL_MM)?,
            pitch_mm: Some(pitch_mm),
            stock_mm: Some(BenchKind::stock_mm()),
            margin_mm: 0.0,
            max_sample_step_mm: None,
            design: DesignSpec::None,
            target: None,
            keyframes: 0,
            resume: false,
        })
    }
}

/// The program made, with the stock it is cut into (the first partial output).
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    /// The moves.
    pub program: Program,
    /// Stock block used (mm).
    pub stock_mm: [f64; 6],
    /// Pitch used (mm).
    pub pitch_mm: f64,
    /// The stock's grid.
    pub grid: Grid,
    /// The design: `"none"`, `"plane"`, `"scene surfaces"` or `"finish surface"`.
    pub design_name: &'static str,
    /// Moves the run goes to.
    pub target: usize,
    /// Moves between keyframes (0: no keyframes).
    pub keyframe_every: usize,
}

/// The stock after some moves, for the view (heights in `f32`, enough for drawing).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    /// Moves applied.
    pub moves: usize,
    /// The run's counts then.
    pub counters: Counters,
    /// Top of each ray (mm, row-major as [`HeightMap::top_mm`]).
    pub top_mm: Vec<f32>,
    /// Whether each ray was machined.
    pub machined: Vec<bool>,
}

impl Keyframe {
    /// The keyframe as a height map of `grid` (heights widened to `f64`).
    #[must_use]
    pub fn map(&self, grid: Grid) -> HeightMap {
        HeightMap {
            grid,
            top_mm: self.top_mm.iter().map(|&z| f64::from(z)).collect(),
            machined: self.machined.clone(),
            through: 0,
        }
    }
}

/// A partial output.
#[derive(Clone, Debug, PartialEq)]
pub enum Partial {
    /// The program is made.
    Prepared(Box<Prepared>),
    /// The stock after some moves.
    Keyframe(Keyframe),
}

/// The run's result at its target move.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// Counts of the run (from move 0, also when it started from a kept stock).
    pub counters: Counters,
    /// The move of the kept stock the run started from ([`Session`]; 0: the whole block).
    pub resumed_from: usize,
    /// The stock's height map.
    pub map: HeightMap,
    /// Its measures against the design.
    pub stats: SimStats,
}

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct SimulateRun;

/// Reports the overall fraction done when it moved enough.
struct Reporter<'a> {
    progress: &'a mut dyn Progress,
    last: f64,
}

impl Reporter<'_> {
    fn at(&mut self, fraction: f64) {
        if fraction - self.last >= PROGRESS_STEP || fraction >= 1.0 {
            self.last = fraction;
            self.progress.progress(fraction.min(1.0));
        }
    }
    fn cancelled(&self) -> Result<(), String> {
        if self.progress.cancelled() { Err("cancelled".to_owned()) } else { Ok(()) }
    }
}

fn scene_of(text: &str) -> Result<(Scene, CreaseJob), String> {
    let scene = Scene::from_json(text).map_err(|e| format!("the scene: {e}"))?;
    let job = CreaseJob::from_scene(&scene).map_err(|e| format!("the scene: {e}"))?;
    Ok((scene, job))
}

/// The scene's crease as a design curve, checking the cancel flag between slices.
fn crease_curve(job: &CreaseJob, rep: &Reporter<'_>) -> Result<crate::crease::CreaseCurve, String> {
    let mut b = DesignBuilder::new(job).map_err(|e| format!("the scene's crease cannot be run — {e}"))?;
    loop {
        rep.cancelled()?;
        if let Some(done) = b.advance(PERIODS_PER_CALL) {
            return done.map_err(|e| format!("the scene's crease gives no design curve — {e}"));
        }
    }
}

/// The program of a request's source, in tool-tip moves.
fn make_program(req: &Request, rep: &mut Reporter<'_>) -> Result<Program, String> {
    let (toolpath, point) = match &req.source {
        ProgramSource::Moves(p) => return Ok(p.clone()),
        ProgramSource::Finish { scene, cutter, passes, step_tol_mm } => {
            let fp = finish_program(scene, *cutter, passes, *step_tol_mm)?;
            let mut program = Program::default();
            for k in 0..fp.passes.len() {
                rep.cancelled()?;
                fp.plan_pass(k, &mut program).map_err(|e| e.to_string())?;
                rep.at(PROGRAM_SHARE * (k + 1) as f64 / fp.passes.len() as f64);
            }
            return Ok(program);
        }
        ProgramSource::Benchmark { kind, moves } => return kind.program(*moves).map_err(|e| e.to_string()),
        ProgramSource::Steps { scene } => {
            let (scene, job) = scene_of(scene)?;
            let curve = crease_curve(&job, rep)?;
            let machine = scene.machine.as_ref().map(build_machine).unwrap_or_default();
            let rule = match &scene.tool_axis {
                Some(t) => build_tool_axis(t).map_err(|e| e.to_string())?,
                None => ToolAxisRule::Bisector,
            };
            let path = CreasePath::new(curve, rule);
            let opts = StepOptions::new(PROGRAM_TOL_MM).with_method(RootMethod::Bisection);
            let mut planner = StepPlanner::new(&machine, &path, &opts)
                .map_err(|e| format!("the 5-axis steps cannot be planned — {e}"))?;
            // The planner's own caps bound the nodes; the flag is looked at per node.
            while !planner.is_done() {
                rep.cancelled()?;
                planner.next_node(&machine, &path).map_err(|e| format!("the 5-axis steps cannot be planned — {e}"))?;
            }
            let blocks: Vec<_> = planner.nodes().iter().map(|n| n.block).collect();
            return Program::from_blocks(&machine, &blocks).map_err(|e| e.to_string());
        }
        ProgramSource::Crease { scene, kind } => {
            let (scene, job) = scene_of(scene)?;
            let curve = crease_curve(&job, rep)?;
            let title = if scene.name.is_empty() { "scene".to_owned() } else { scene.name.clone() };
            let opts = ProgramOptions::default().with_title(&title).with_point(ProgrammedPoint::BallCentre);
            let p = write_program(*kind, &curve, PROGRAM_TOL_MM, &opts)
                .map_err(|e| format!("the {} program cannot be written — {e}", kind.label()))?;
            (p.parsed.toolpath, ToolPoint::BallCentre)
        }
        ProgramSource::Text { name, text } => {
            let dialect = pipeline::guess_dialect(text.as_bytes());
            let parsed = pipeline::read_text(text, dialect, &ReadOptions::default())
                .map_err(|e| format!("{name} is not a program this reader can follow — {e}"))?;
            let point = ToolPoint::of_comments(&parsed.comments);
            (parsed.toolpath, point)
        }
    };
    let chord = pipeline::default_chord_tol_mm;
    // The chord tolerance follows the pitch, which may follow the program's box: chord at
    // the smallest pitch offered first when automatic, then again at the one chosen.
    let pitch0 = req.pitch_mm.unwrap_or(PITCH_RANGE_MM.0);
    let program = pipeline::program_of(&toolpath, point, &req.cutter, chord(pitch0)).map_err(|e| e.to_string())?;
    if req.pitch_mm.is_none() {
        let (_, pitch) = stock_and_pitch(req, &program)?;
        if (pitch - pitch0).abs() > 0.0 {
            return pipeline::program_of(&toolpath, point, &req.cutter, chord(pitch)).map_err(|e| e.to_string());
        }
    }
    Ok(program)
}

/// The stock block and pitch for `program`: the request's, else automatic.
///
/// # Errors
/// A program without a cutting move and no stock given.
pub fn stock_and_pitch(req: &Request, program: &Program) -> Result<([f64; 6], f64), String> {
    let stock = match req.stock_mm {
        Some(s) => s,
        None => auto_stock(program, &req.cutter, req.margin_mm)
            .ok_or("the program has no cutting move to size the stock from; give the stock block")?,
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
    Ok((stock, pitch))
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

/// Moves between keyframes for a run to `target` on `rays` rays asking for at most `wanted`.
#[must_use]
pub fn keyframe_every(target: usize, rays: usize, wanted: usize) -> usize {
    let wanted = wanted.min(MAX_KEYFRAMES);
    if wanted == 0 || target == 0 {
        return 0;
    }
    let by_bytes = (KEYFRAME_BYTES / (5 * rays.max(1))).max(1);
    target.div_ceil(wanted.min(by_bytes)).max(1)
}

fn keyframe(sim: &Simulation) -> Keyframe {
    let map = HeightMap::of(sim.stock());
    Keyframe {
        moves: sim.counters().moves,
        counters: *sim.counters(),
        top_mm: map.top_mm.iter().map(|&z| z as f32).collect(),
        machined: map.machined,
    }
}

/// What makes two runs machine the same stock: the program's moves (their kinds, rapid
/// flags and every number by its bits), the stock block, the pitch, the cutter and the
/// sampling step asked for. Two runs with equal keys leave bit-identical stocks after every
/// move, so one may start from the other's kept stock.
#[derive(Clone, Debug, PartialEq, Eq)]
struct SessionKey(Vec<u64>);

impl SessionKey {
    fn of(program: &Program, stock_mm: &[f64; 6], pitch_mm: f64, cutter: &Cutter, sample_step: Option<f64>) -> Self {
        let mut key = Vec::with_capacity(program.moves.len() * 26 + 16);
        for m in &program.moves {
            key.push(u64::from(matches!(m.kind, MoveKind::Joints { .. })) | (u64::from(m.rapid) << 1));
            key.extend(move_numbers(m).into_iter().map(f64::to_bits));
        }
        key.push(program.moves.len() as u64);
        key.extend(stock_mm.iter().map(|x| x.to_bits()));
        key.push(pitch_mm.to_bits());
        key.extend(cutter.numbers().map(f64::to_bits));
        key.push(sample_step.map_or(u64::MAX, f64::to_bits));
        Self(key)
    }
}

/// Stocks of one program kept between runs, so a replay to move k (the move slider) starts
/// from the nearest kept stock at or before k instead of the block: the simulation state
/// ([`Simulation`]: stock, counters, last pose) after every `every` moves, cloned as a run
/// passes them, at most [`MAX_KEPT_STOCKS`] and [`KEPT_STOCK_BYTES`] in all. A run of
/// another program (another key) replaces the session. In a browser the session lives in the
/// Web Worker, which the page keeps between jobs (`app::jobs`); natively in the process.
#[derive(Debug, Default)]
pub struct Session {
    key: Option<SessionKey>,
    /// Bumped with every new key: a run offers its stocks only to the session it started
    /// (another program's run may have replaced it meanwhile, natively on another thread).
    generation: u64,
    every: usize,
    /// Kept states, in move order.
    kept: Vec<Simulation>,
    bytes: usize,
}

/// The process's (the worker's) session.
static SESSION: std::sync::Mutex<Option<Session>> = std::sync::Mutex::new(None);

impl Session {
    /// Moves between kept stocks for a program of `moves` moves on a stock of `bytes` bytes:
    /// as many stocks as the budget holds, at most [`MAX_KEPT_STOCKS`], spread evenly
    /// (0: none fit).
    #[must_use]
    pub fn spacing(moves: usize, bytes: usize) -> usize {
        let slots = (KEPT_STOCK_BYTES / bytes.max(1)).min(MAX_KEPT_STOCKS);
        if slots == 0 || moves < 2 { 0 } else { moves.div_ceil(slots + 1).max(1) }
    }

    /// Moves of the stocks kept, in order.
    #[must_use]
    pub fn kept_moves(&self) -> Vec<usize> {
        self.kept.iter().map(|s| s.counters().moves).collect()
    }

    /// Bytes of the stocks kept.
    #[must_use]
    pub fn kept_bytes(&self) -> usize {
        self.bytes
    }

    /// The session's generation and the state to start a run of `key` to move `target`
    /// from: a copy of the kept state nearest at or before `target`, if any. A different key
    /// starts a new session for it (`moves` moves, `bytes` bytes a stock).
    fn start(&mut self, key: SessionKey, target: usize, moves: usize, bytes: usize) -> (u64, Option<Simulation>) {
        if self.key.as_ref() != Some(&key) {
            let generation = self.generation.wrapping_add(1);
            *self = Self { key: Some(key), generation, every: Self::spacing(moves, bytes), kept: Vec::new(), bytes: 0 };
            return (generation, None);
        }
        (self.generation, self.kept.iter().rev().find(|s| s.counters().moves <= target).cloned())
    }

    /// Keeps a copy of `sim` (a state of the run that started generation `generation`) if
    /// its move is on the spacing, not kept yet and within budget.
    fn offer(&mut self, generation: u64, sim: &Simulation) {
        let k = sim.counters().moves;
        if generation != self.generation || self.every == 0 || k == 0 || !k.is_multiple_of(self.every) {
            return;
        }
        let bytes = sim.stock().memory_bytes();
        let at = self.kept.partition_point(|s| s.counters().moves < k);
        if self.kept.get(at).is_some_and(|s| s.counters().moves == k)
            || self.kept.len() >= MAX_KEPT_STOCKS
            || self.bytes + bytes > KEPT_STOCK_BYTES
        {
            return;
        }
        self.kept.insert(at, sim.clone());
        self.bytes += bytes;
    }
}

/// Runs `req` with `session` holding the kept stocks ([`SimulateRun::run`] uses the
/// process's own; a test gives its own).
///
/// # Errors
/// The run's message (a bad program, grid or design, or cancelled).
pub fn run_in_session(
    req: &Request,
    progress: &mut dyn Progress,
    session: &std::sync::Mutex<Option<Session>>,
) -> Result<Finished, String> {
    let mut rep = Reporter { progress, last: -1.0 };
    rep.at(0.0);
    let program = make_program(req, &mut rep)?;
    rep.cancelled()?;
    let (stock_mm, pitch) = stock_and_pitch(req, &program)?;
    let nx = ((stock_mm[3] - stock_mm[0]) / pitch).ceil();
    let ny = ((stock_mm[4] - stock_mm[1]) / pitch).ceil();
    if !(nx * ny <= MAX_RAYS as f64) {
        return Err(format!(
            "a pitch of {pitch} mm on this stock gives {} × {} rays, more than the {MAX_RAYS} this view simulates; raise the pitch or shrink the stock",
            crate::simulate::ray_count(nx),
            crate::simulate::ray_count(ny)
        ));
    }
    let stock =
        DexelStock::block([stock_mm[0], stock_mm[1], stock_mm[2]], [stock_mm[3], stock_mm[4], stock_mm[5]], pitch)
            .map_err(|e| e.to_string())?;
    let sample_step =
        req.max_sample_step_mm.map_or(SampleStep::Default, SampleStep::BelowPitch).resolve(pitch, &req.cutter);
    let mut sim = pipeline::start(stock, &req.cutter, sample_step, &program).map_err(|e| e.to_string())?;
    let design = match &req.design {
        DesignSpec::None => Design::None,
        DesignSpec::PlaneZ(z) => Design::PlaneZ(*z),
        DesignSpec::Scene(text) => Design::Surfaces(scene_of(text)?.1.surfaces.to_vec()),
        DesignSpec::Finish(text) => {
            let job =
                FinishScene::from_json(text).and_then(|f| f.job()).map_err(|e| format!("the finishing scene: {e}"))?;
            Design::Surface(job.surface)
        }
    };
    let design_name = design.name();
    let grid = *sim.stock().grid();
    let target = req.target.unwrap_or(usize::MAX).min(program.moves.len());
    let every = keyframe_every(target, grid.len(), req.keyframes);
    let key = SessionKey::of(&program, &stock_mm, pitch, &req.cutter, sample_step);
    let bytes = sim.stock().memory_bytes();
    let (generation, kept) = session
        .lock()
        .ok()
        .map_or((0, None), |mut s| s.get_or_insert_default().start(key, target, program.moves.len(), bytes));
    if let Some(k) = kept.filter(|_| req.resume) {
        sim = k;
    }
    let resumed_from = sim.counters().moves;
    // The moves went with the request: the page has them, so they do not cross back.
    let sent = if matches!(req.source, ProgramSource::Moves(_)) { Program::default() } else { program.clone() };
    let prepared =
        Prepared { program: sent, stock_mm, pitch_mm: pitch, grid, design_name, target, keyframe_every: every };
    rep.progress.partial(encode_partial(&Partial::Prepared(Box::new(prepared))));
    rep.at(PROGRAM_SHARE);
    let todo = (target - resumed_from).max(1) as f64;
    rep.cancelled()?;
    pipeline::machine(&mut sim, &program.moves[resumed_from..target], |sim| {
        // Moves applied: the kept stock's and this run's, one counter.
        let done = sim.counters().moves;
        if let Ok(mut s) = session.lock()
            && let Some(s) = s.as_mut()
        {
            s.offer(generation, sim);
        }
        if every > 0 && done.is_multiple_of(every) && done < target {
            rep.progress.partial(encode_partial(&Partial::Keyframe(keyframe(sim))));
        }
        rep.at(PROGRAM_SHARE + RUN_SHARE * (done - resumed_from) as f64 / todo);
        rep.cancelled()
    })?;
    let ny = grid.ny.max(1);
    let Measures { map, stats } = pipeline::measure(sim.stock(), &design, ROWS_PER_CALL, |rows_done| {
        rep.at(PROGRAM_SHARE + RUN_SHARE + (1.0 - PROGRAM_SHARE - RUN_SHARE) * rows_done as f64 / ny as f64);
        rep.cancelled()
    })?;
    Ok(Finished { counters: *sim.counters(), resumed_from, map, stats })
}

impl JobKind for SimulateRun {
    const NAME: &'static str = "simulate-run";
    type Request = Request;
    type Output = Result<Finished, String>;
    type Partial = Partial;

    fn run(req: &Request, progress: &mut dyn Progress) -> Self::Output {
        run_in_session(req, progress, &SESSION)
    }

    fn encode_request(r: &Request) -> String {
        let source = match &r.source {
            ProgramSource::Crease { scene, kind } => {
                json!({ "crease": scene, "kind": ProgramKind::ALL.iter().position(|k| k == kind).unwrap_or(0) })
            }
            ProgramSource::Steps { scene } => json!({ "steps": scene }),
            ProgramSource::Text { name, text } => json!({ "name": name, "text": text }),
            ProgramSource::Moves(p) => json!({ "moves": program_value(p) }),
            ProgramSource::Benchmark { kind, moves } => json!({ "benchmark": kind.key(), "count": moves }),
            ProgramSource::Finish { scene, cutter, passes, step_tol_mm } => json!({
                "finish": scene,
                "cutter": cutter_value(cutter),
                "passes": passes.iter().map(|p| nodes_value(p)).collect::<Vec<_>>(),
                "step_tol_mm": super::num(*step_tol_mm),
            }),
        };
        json!({
            "source": source,
            "cutter": cutter_value(&r.cutter),
            "pitch_mm": r.pitch_mm.map_or(Value::Null, super::num),
            "stock_mm": r.stock_mm.map_or(Value::Null, super::nums),
            "margin_mm": super::num(r.margin_mm),
            "max_sample_step_mm": r.max_sample_step_mm.map_or(Value::Null, super::num),
            "design": match &r.design {
                DesignSpec::None => Value::Null,
                DesignSpec::PlaneZ(z) => json!({ "plane_z_mm": super::num(*z) }),
                DesignSpec::Scene(s) => json!({ "scene": s }),
                DesignSpec::Finish(s) => json!({ "finish": s }),
            },
            "target": r.target,
            "keyframes": r.keyframes,
            "resume": r.resume,
        })
        .to_string()
    }

    fn decode_request(text: &str) -> Result<Request, String> {
        const W: &str = "simulate-run request";
        let v = parse(text, W)?;
        let r = Reader::new(&v, W)?;
        let s = Reader::new(r.value("source")?, "simulate-run request.source")?;
        let source = if let Ok(scene) = s.str("crease") {
            let kind =
                *ProgramKind::ALL.get(s.usize("kind")?).ok_or("simulate-run request.source.kind: out of range")?;
            ProgramSource::Crease { scene: scene.to_owned(), kind }
        } else if let Ok(scene) = s.str("steps") {
            ProgramSource::Steps { scene: scene.to_owned() }
        } else if let Ok(text) = s.str("text") {
            ProgramSource::Text { name: s.str("name")?.to_owned(), text: text.to_owned() }
        } else if let Ok(scene) = s.str("finish") {
            let passes = s
                .value("passes")?
                .as_array()
                .ok_or("simulate-run request.source.passes: not a list")?
                .iter()
                .map(nodes_of)
                .collect::<Result<Vec<_>, _>>()?;
            ProgramSource::Finish {
                scene: scene.to_owned(),
                cutter: cutter_of(&s.f64s("cutter")?).map_err(|e| format!("{W}.source.cutter: {e}"))?,
                passes,
                step_tol_mm: s.f64("step_tol_mm")?,
            }
        } else if let Ok(kind) = s.str("benchmark") {
            let (kind, moves) = BenchKind::parse(&format!("{kind}:{}", s.usize("count")?))
                .map_err(|e| format!("simulate-run request.source: {e}"))?;
            ProgramSource::Benchmark { kind, moves }
        } else {
            ProgramSource::Moves(program_of(s.value("moves")?)?)
        };
        let cutter = cutter_of(&r.f64s("cutter")?).map_err(|e| format!("{W}.cutter: {e}"))?;
        let stock_mm = match r.value("stock_mm")? {
            Value::Null => None,
            _ => Some(r.f64s("stock_mm")?.try_into().map_err(|_| format!("{W}.stock_mm: not six numbers"))?),
        };
        let design = match r.value("design")? {
            Value::Null => DesignSpec::None,
            d => {
                let d = Reader::new(d, "simulate-run request.design")?;
                if let Ok(s) = d.str("scene") {
                    DesignSpec::Scene(s.to_owned())
                } else if let Ok(s) = d.str("finish") {
                    DesignSpec::Finish(s.to_owned())
                } else {
                    DesignSpec::PlaneZ(d.f64("plane_z_mm")?)
                }
            }
        };
        let target = match r.value("target")? {
            Value::Null => None,
            _ => Some(r.usize("target")?),
        };
        Ok(Request {
            source,
            cutter,
            pitch_mm: r.opt_f64("pitch_mm")?,
            stock_mm,
            margin_mm: r.f64("margin_mm")?,
            max_sample_step_mm: match r.value("max_sample_step_mm")? {
                Value::Null => None,
                _ => Some(r.f64("max_sample_step_mm")?),
            },
            design,
            target,
            keyframes: r.usize("keyframes")?,
            resume: r.value("resume")?.as_bool().ok_or(format!("{W}.resume: not true or false"))?,
        })
    }

    fn encode_output(out: &Self::Output) -> String {
        let f = match out {
            Err(e) => return json!({ "error": e }).to_string(),
            Ok(f) => f,
        };
        let s = &f.stats;
        // A run without a design (or whose design is over no ray) has no deviation on any
        // ray: the two arrays (2.4 MB of text at 512 × 512) are left out, `null` instead.
        let (dev, has) = if s.deviation_mm.iter().any(Option::is_some) {
            let dev: Vec<f64> = s.deviation_mm.iter().map(|d| d.unwrap_or(0.0)).collect();
            let has: Vec<bool> = s.deviation_mm.iter().map(Option::is_some).collect();
            (f64s_packed(&dev), bits_packed(&has))
        } else {
            (Value::Null, Value::Null)
        };
        json!({
            "counters": counters_value(&f.counters),
            "resumed_from": f.resumed_from,
            "map": {
                "grid": grid_value(&f.map.grid),
                "top_mm": f64s_packed(&f.map.top_mm),
                "machined": bits_packed(&f.map.machined),
                "through": f.map.through,
            },
            "stats": {
                "machined_rays": s.machined_rays,
                "through_rays": s.through_rays,
                "split_rays": s.split_rays,
                "deviation_mm": dev,
                "has_deviation": has,
                "scallop": {
                    "count": s.scallop.count,
                    "max_mm": super::num(s.scallop.max_mm),
                    "mean_mm": super::num(s.scallop.mean_mm),
                    "p95_mm": super::num(s.scallop.p95_mm),
                },
                "worst_gouge": s.worst_gouge.map_or(Value::Null, |(d, at)| super::nums([d, at.x, at.y])),
                "gouge_rays": s.gouge_rays,
            },
        })
        .to_string()
    }

    fn decode_output(text: &str) -> Result<Self::Output, String> {
        const W: &str = "simulate-run output";
        let v = parse(text, W)?;
        if let Some(e) = v.get("error") {
            return Ok(Err(e.as_str().unwrap_or("the simulation failed").to_owned()));
        }
        let r = Reader::new(&v, W)?;
        let m = Reader::new(r.value("map")?, "simulate-run output.map")?;
        let grid = grid_of(m.value("grid")?)?;
        let n = grid.len();
        let map = HeightMap {
            grid,
            top_mm: m.f64s_packed("top_mm", n)?,
            machined: m.bits_packed("machined", n)?,
            through: m.usize("through")?,
        };
        let s = Reader::new(r.value("stats")?, "simulate-run output.stats")?;
        // `null`: no ray has a deviation (a run without a design).
        let (dev, has) = match s.value("deviation_mm")? {
            Value::Null => (vec![0.0; n], vec![false; n]),
            _ => (s.f64s_packed("deviation_mm", n)?, s.bits_packed("has_deviation", n)?),
        };
        let sc = Reader::new(s.value("scallop")?, "simulate-run output.stats.scallop")?;
        let worst_gouge = match s.value("worst_gouge")? {
            Value::Null => None,
            _ => match s.f64s("worst_gouge")?[..] {
                [d, x, y] => Some((d, DVec2::new(x, y))),
                _ => return Err(format!("{W}.stats.worst_gouge: not three numbers")),
            },
        };
        let stats = SimStats {
            machined_rays: s.usize("machined_rays")?,
            through_rays: s.usize("through_rays")?,
            split_rays: s.usize("split_rays")?,
            deviation_mm: dev.into_iter().zip(has).map(|(d, h)| h.then_some(d)).collect(),
            scallop: Summary {
                count: sc.usize("count")?,
                max_mm: sc.f64("max_mm")?,
                mean_mm: sc.f64("mean_mm")?,
                p95_mm: sc.f64("p95_mm")?,
            },
            worst_gouge,
            gouge_rays: s.usize("gouge_rays")?,
        };
        Ok(Ok(Finished {
            counters: counters_of(r.value("counters")?)?,
            resumed_from: r.usize("resumed_from")?,
            map,
            stats,
        }))
    }

    fn decode_partial(text: &str) -> Result<Partial, String> {
        const W: &str = "simulate-run partial";
        let v = parse(text, W)?;
        let r = Reader::new(&v, W)?;
        if let Ok(p) = r.value("prepared") {
            let p = Reader::new(p, "simulate-run partial.prepared")?;
            let design_name = match p.str("design")? {
                "none" => "none",
                "plane" => "plane",
                "scene surfaces" => "scene surfaces",
                "finish surface" => "finish surface",
                other => return Err(format!("{W}.prepared.design: \"{other}\" is not a design")),
            };
            return Ok(Partial::Prepared(Box::new(Prepared {
                program: program_of(p.value("program")?)?,
                stock_mm: p
                    .f64s("stock_mm")?
                    .try_into()
                    .map_err(|_| format!("{W}.prepared.stock_mm: not six numbers"))?,
                pitch_mm: p.f64("pitch_mm")?,
                grid: grid_of(p.value("grid")?)?,
                design_name,
                target: p.usize("target")?,
                keyframe_every: p.usize("keyframe_every")?,
            })));
        }
        let k = Reader::new(r.value("keyframe")?, "simulate-run partial.keyframe")?;
        let n = k.usize("rays")?;
        if n > MAX_RAYS {
            return Err(format!("{W}.keyframe.rays: {n} is more than {MAX_RAYS}"));
        }
        Ok(Partial::Keyframe(Keyframe {
            moves: k.usize("moves")?,
            counters: counters_of(k.value("counters")?)?,
            top_mm: k.f32s_packed("top_mm", n)?,
            machined: k.bits_packed("machined", n)?,
        }))
    }
}

/// A partial output as text ([`JobKind::decode_partial`] reads it).
#[must_use]
pub fn encode_partial(p: &Partial) -> String {
    match p {
        Partial::Prepared(p) => json!({ "prepared": {
            "program": program_value(&p.program),
            "stock_mm": super::nums(p.stock_mm),
            "pitch_mm": super::num(p.pitch_mm),
            "grid": grid_value(&p.grid),
            "design": p.design_name,
            "target": p.target,
            "keyframe_every": p.keyframe_every,
        }}),
        Partial::Keyframe(k) => json!({ "keyframe": {
            "moves": k.moves,
            "counters": counters_value(&k.counters),
            "rays": k.top_mm.len(),
            "top_mm": f32s_packed(&k.top_mm),
            "machined": bits_packed(&k.machined),
        }}),
    }
    .to_string()
}

fn cutter_value(c: &Cutter) -> Value {
    super::nums(c.numbers())
}

fn cutter_of(c: &[f64]) -> Result<Cutter, String> {
    Cutter::from_numbers(c)
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
) -> Result<FinishProgram, String> {
    let job = FinishScene::from_json(scene).and_then(|f| f.job()).map_err(|e| format!("the finishing scene: {e}"))?;
    if !(step_tol_mm > 0.0 && step_tol_mm.is_finite()) {
        return Err(format!("the step tolerance must be a positive length in mm, got {step_tol_mm}; give e.g. 0.01"));
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

/// Numbers of a CC node: uv, point, normal, feed, cross, the surface's form (3), pose (2),
/// tip, axis, strip, side step and scallop (NaN: none), lead-out (1) or CC point (0).
const NODE_NUMBERS: usize = 2 + 3 * 4 + 3 + 2 + 3 + 3 + 3 + 1;

/// A pass's CC nodes, packed (what planning needs of them; the gouge checks' record of an
/// adjustment stays on the page).
fn nodes_value(nodes: &[CcNode]) -> Value {
    let mut d = Vec::with_capacity(nodes.len() * NODE_NUMBERS);
    for n in nodes {
        let f = &n.frame;
        d.extend([f.uv.x, f.uv.y]);
        for v in [f.point, f.normal, f.feed, f.cross] {
            d.extend([v.x, v.y, v.z]);
        }
        d.extend([f.surface_form.ff, f.surface_form.fc, f.surface_form.cc]);
        d.extend([n.pose.inclination_rad, n.pose.azimuth_rad]);
        d.extend([n.tip.x, n.tip.y, n.tip.z, n.axis.x, n.axis.y, n.axis.z]);
        d.extend([n.strip_mm, n.side_step_mm.unwrap_or(f64::NAN), n.scallop_mm.unwrap_or(f64::NAN)]);
        d.push(if n.lead_out { 1.0 } else { 0.0 });
    }
    json!({ "count": nodes.len(), "data": f64s_packed(&d) })
}

fn nodes_of(v: &Value) -> Result<Vec<CcNode>, String> {
    let r = Reader::new(v, "simulate-run request.source.passes[]")?;
    let n = r.usize("count")?;
    let d = r.f64s_packed("data", n.checked_mul(NODE_NUMBERS).ok_or("simulate-run request: too many CC nodes")?)?;
    let v3 = |s: &[f64]| DVec3::new(s[0], s[1], s[2]);
    let opt = |x: f64| (!x.is_nan()).then_some(x);
    Ok(d.chunks_exact(NODE_NUMBERS)
        .map(|c| CcNode {
            frame: ContactFrame {
                uv: DVec2::new(c[0], c[1]),
                point: v3(&c[2..5]),
                normal: v3(&c[5..8]),
                feed: v3(&c[8..11]),
                cross: v3(&c[11..14]),
                surface_form: Form2 { ff: c[14], fc: c[15], cc: c[16] },
            },
            pose: Pose { inclination_rad: c[17], azimuth_rad: c[18] },
            tip: v3(&c[19..22]),
            axis: v3(&c[22..25]),
            strip_mm: c[25],
            side_step_mm: opt(c[26]),
            scallop_mm: opt(c[27]),
            adjusted: None,
            lead_out: c[28] != 0.0,
        })
        .collect())
}

pub(crate) fn grid_value(g: &Grid) -> Value {
    json!({ "x0_mm": super::num(g.x0_mm), "y0_mm": super::num(g.y0_mm), "pitch_mm": super::num(g.pitch_mm), "nx": g.nx, "ny": g.ny })
}

pub(crate) fn grid_of(v: &Value) -> Result<Grid, String> {
    let g = Reader::new(v, "simulate-run grid")?;
    let grid = Grid {
        x0_mm: g.f64("x0_mm")?,
        y0_mm: g.f64("y0_mm")?,
        pitch_mm: g.f64("pitch_mm")?,
        nx: g.usize("nx")?,
        ny: g.usize("ny")?,
    };
    if grid.nx.checked_mul(grid.ny).is_none_or(|n| n > MAX_RAYS) {
        return Err(format!("simulate-run grid: {} × {} rays is more than {MAX_RAYS}", grid.nx, grid.ny));
    }
    Ok(grid)
}

pub(crate) fn counters_value(c: &Counters) -> Value {
    json!({
        "moves": c.moves,
        "samples": c.samples,
        "rays_visited": c.rays_visited,
        "ray_updates": c.ray_updates,
        "removed_mm3": super::num(c.removed_mm3),
        "rapid_cuts": c.rapid_cuts,
        "first_rapid_cut_line": c.first_rapid_cut_line,
        "sweep_sagitta_mm": super::num(c.sweep_sagitta_mm),
    })
}

pub(crate) fn counters_of(v: &Value) -> Result<Counters, String> {
    let c = Reader::new(v, "simulate-run counters")?;
    let u64_of = |k: &str| c.value(k)?.as_u64().ok_or_else(|| format!("simulate-run counters.{k}: not a count"));
    Ok(Counters {
        moves: c.usize("moves")?,
        samples: u64_of("samples")?,
        rays_visited: u64_of("rays_visited")?,
        ray_updates: u64_of("ray_updates")?,
        removed_mm3: c.f64("removed_mm3")?,
        rapid_cuts: c.usize("rapid_cuts")?,
        first_rapid_cut_line: match c.value("first_rapid_cut_line")? {
            Value::Null => None,
            _ => Some(c.usize("first_rapid_cut_line")?),
        },
        sweep_sagitta_mm: c.f64("sweep_sagitta_mm")?,
    })
}

/// Numbers of a line move: from, to.
const LINE_NUMBERS: usize = 6;
/// Numbers of a joints move: the machine (kind, two pivots, tool length, two limits as
/// flag, low, high) and the two joint sets (xyz, two rotary).
const JOINTS_NUMBERS: usize = 14 + 10;

/// Every number of a move, in the order [`program_of`] reads them: a line's two tips (6),
/// a 5-axis move's machine (kind, pivots, tool length, limits: 14) and its two joint sets
/// (10).
fn move_numbers(m: &SimMove) -> Vec<f64> {
    match m.kind {
        MoveKind::Line { from, to } => vec![from.x, from.y, from.z, to.x, to.y, to.z],
        MoveKind::Joints { machine, from, to } => {
            let mut data = Vec::with_capacity(24);
            let kind = MachineKind::ALL.iter().position(|k| *k == machine.kind).unwrap_or(0);
            data.push(kind as f64);
            for v in machine.pivots_mm {
                data.extend([v.x, v.y, v.z]);
            }
            data.push(machine.tool_length_mm);
            for l in machine.limits_rad {
                match l {
                    Some([lo, hi]) => data.extend([1.0, lo, hi]),
                    None => data.extend([0.0, 0.0, 0.0]),
                }
            }
            for j in [from, to] {
                data.extend([j.xyz_mm.x, j.xyz_mm.y, j.xyz_mm.z, j.rotary_rad[0], j.rotary_rad[1]]);
            }
            data
        }
    }
}

fn program_value(p: &Program) -> Value {
    let data: Vec<f64> = p.moves.iter().flat_map(move_numbers).collect();
    json!({
        "count": p.moves.len(),
        "joints": bits_packed(&p.moves.iter().map(|m| matches!(m.kind, MoveKind::Joints { .. })).collect::<Vec<_>>()),
        "rapid": bits_packed(&p.moves.iter().map(|m| m.rapid).collect::<Vec<_>>()),
        "lines": p.moves.iter().map(|m| m.line).collect::<Vec<_>>(),
        "data": f64s_packed(&data),
        "numbers": data.len(),
        "chord_error_mm": super::num(p.chord_error_mm),
    })
}

fn program_of(v: &Value) -> Result<Program, String> {
    const W: &str = "simulate-run program";
    let r = Reader::new(v, W)?;
    // The count is bounded by the text: every move has its flags, line and numbers in it.
    let n = r.usize("count")?;
    let joints = r.bits_packed("joints", n)?;
    let rapid = r.bits_packed("rapid", n)?;
    let lines: Vec<usize> = r
        .value("lines")?
        .as_array()
        .and_then(|a| a.iter().map(|x| x.as_u64().and_then(|x| usize::try_from(x).ok())).collect())
        .ok_or_else(|| format!("{W}.lines: not a list of line numbers"))?;
    let numbers = r.usize("numbers")?;
    let expected: usize = joints.iter().map(|j| if *j { JOINTS_NUMBERS } else { LINE_NUMBERS }).sum();
    if lines.len() != n || numbers != expected {
        return Err(format!("{W}: {} lines and {numbers} numbers for {n} moves", lines.len()));
    }
    let data = r.f64s_packed("data", numbers)?;
    let mut at = 0;
    let mut take = |k: usize| {
        let s = &data[at..at + k];
        at += k;
        s
    };
    let v3 = |s: &[f64]| DVec3::new(s[0], s[1], s[2]);
    let mut moves = Vec::with_capacity(n);
    for i in 0..n {
        let kind = if joints[i] {
            let d = take(JOINTS_NUMBERS);
            let kind = *MachineKind::ALL.get(d[0] as usize).ok_or_else(|| format!("{W}: move {i}: no machine kind"))?;
            let limit = |s: &[f64]| (s[0] != 0.0).then_some([s[1], s[2]]);
            let machine = Machine {
                kind,
                pivots_mm: [v3(&d[1..4]), v3(&d[4..7])],
                tool_length_mm: d[7],
                limits_rad: [limit(&d[8..11]), limit(&d[11..14])],
            };
            let j = |s: &[f64]| Joints { xyz_mm: v3(s), rotary_rad: [s[3], s[4]] };
            MoveKind::Joints { machine, from: j(&d[14..19]), to: j(&d[19..24]) }
        } else {
            let d = take(LINE_NUMBERS);
            MoveKind::Line { from: v3(&d[0..3]), to: v3(&d[3..6]) }
        };
        moves.push(SimMove { kind, line: lines[i], rapid: rapid[i] });
    }
    Ok(Program { moves, chord_error_mm: r.f64("chord_error_mm")? })
}

#[cfg(test)]
mod tests;
