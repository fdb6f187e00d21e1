//! The simulation tab's work: a background job (`jobs::simulate_run`, run by `app::jobs`: a
//! thread natively, a Web Worker in the browser) writes the program, machines it and
//! measures it, handing back the program, keyframes of the stock on the way and the exact
//! stock and measures at the end. The UI thread only takes what arrived and draws it.
//!
//! Playback: the first run of a program keeps its keyframes (the stock's top heights as
//! `f32` every N moves, at most [`KEYFRAMES`] of them). Moving the slider to move k shows
//! the keyframe at or before k at once, and starts a run of the same moves (sent with the
//! request: no crease, plan or program made again) to k, whose exact stock and measures
//! replace the keyframe when they arrive. Going back to the whole program shows the first
//! run's result again without a run. Why this and not the alternatives: keyframes alone
//! are approximate (the stock between two is unknown, and a keyframe has no deviation) and
//! a worker that keeps its stock between requests would need a second, long-lived kind of
//! worker; a replay costs only the machining to k (tens of ms natively for the examples) and
//! gives the exact state the old slices gave.

use glam::DVec3;
use web_time::{Duration, Instant};

use crate::app::jobs::{Job as BackgroundJob, Poll};
use crate::app::panel::{FILLET_TITLE, FinishHandoff};
use crate::gcode::ProgramKind;
use crate::geom::Cutter;
use crate::jobs::JobError;
use crate::jobs::simulate_run::SimulateRun;
use crate::jobs::simulate_run::output::{Keyframe, Partial};
use crate::jobs::simulate_run::program::ends;
use crate::jobs::simulate_run::request::{self, DesignSpec, ProgramSource, Request};
pub use crate::jobs::simulate_run::request::{AUTO_GRID_SIDE, PITCH_RANGE_MM};
use crate::scene::Scene;
use crate::simulate::bench::BenchKind;
use crate::simulate::{Counters, Grid, HeightMap, InteriorStats, Program, SimStats, interior_stats};

/// How often at most the view's mesh follows the stock while moves are being cut (a new
/// keyframe is a new mesh for the GPU: in a browser drawing on the CPU the dearest frame of
/// a run; the progress bar moves between them, `app::jobs::PROGRESS_POLL`).
const MAP_REFRESH: Duration = Duration::from_millis(1500);
/// Most rays the tab simulates (a 1024 × 1024 grid, 24 MiB); above it the run is refused.
pub const MAX_APP_RAYS: usize = request::MAX_RAYS;
/// Keyframes asked of a program's first run (the slider's instant positions).
pub const KEYFRAMES: usize = 40;
/// Keyframes asked of a replay to one move (the view follows the stock while it runs).
const REPLAY_KEYFRAMES: usize = 8;
/// How long the move slider must rest before a replay to its move starts: dragging it shows
/// keyframes at once and starts one run where the user stops, not one per position passed
/// (each replay in a browser is a new Web Worker).
const REPLAY_SETTLE: Duration = Duration::from_millis(250);

/// Which program is simulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SourceKind {
    /// The scene's crease as a G01 program (ball centre, `gcode::write_program`).
    CreaseG01,
    /// The scene's crease as G02/G03 arcs.
    CreaseArcs,
    /// The scene's crease as one G06.2 NURBS program.
    CreaseNurbs,
    /// The scene's seed-002 five-axis tool steps, joints interpolated linearly.
    Steps,
    /// The last G-code file opened in the app (NURBS & G-code tab) or given as text.
    Loaded,
    /// The finishing program handed over by the fillet tab (seed 001): its five-axis
    /// program through the machine, the fillet cutter, the finish surface as the design.
    Finish,
    /// A benchmark program built in the job from its kind and move count
    /// (`simulate::bench`: the native benchmarks' programs), on their 51.2 mm block.
    Benchmark,
}

impl SourceKind {
    /// All, in menu order.
    pub const ALL: [Self; 7] = [
        Self::CreaseG01,
        Self::CreaseArcs,
        Self::CreaseNurbs,
        Self::Steps,
        Self::Loaded,
        Self::Finish,
        Self::Benchmark,
    ];

    /// Key for `set_option` and the status.
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::CreaseG01 => "crease-g01",
            Self::CreaseArcs => "crease-arcs",
            Self::CreaseNurbs => "crease-nurbs",
            Self::Steps => "steps",
            Self::Loaded => "loaded",
            Self::Finish => "finish",
            Self::Benchmark => "benchmark",
        }
    }

    /// Menu label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::CreaseG01 => "Scene crease, G01 program",
            Self::CreaseArcs => "Scene crease, G02/G03 program",
            Self::CreaseNurbs => "Scene crease, G06.2 program",
            Self::Steps => "Scene 5-axis tool steps",
            Self::Loaded => "Loaded G-code file",
            Self::Finish => "Fillet tab's finishing program",
            Self::Benchmark => "Benchmark raster (ball R 3 on a 51.2 mm block)",
        }
    }

    /// Whether the program is made from the scene's crease.
    #[must_use]
    pub fn needs_crease(self) -> bool {
        !matches!(self, Self::Loaded | Self::Finish | Self::Benchmark)
    }

    fn program_kind(self) -> Option<ProgramKind> {
        match self {
            Self::CreaseG01 => Some(ProgramKind::Lines),
            Self::CreaseArcs => Some(ProgramKind::Arcs),
            Self::CreaseNurbs => Some(ProgramKind::Nurbs),
            _ => None,
        }
    }
}

/// The cutter chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CutterChoice {
    /// The scene's ball (its tool radius).
    SceneBall,
    /// A ball end mill of radius R (mm).
    Ball(f64),
    /// A flat end mill of radius R (mm).
    Flat(f64),
    /// A fillet end mill of radius R and corner r (mm).
    Fillet(f64, f64),
}

impl CutterChoice {
    /// The core cutter, or why not.
    ///
    /// # Errors
    /// The core's message for bad radii.
    pub fn cutter(self, scene: &Scene) -> Result<Cutter, String> {
        let c = match self {
            Self::SceneBall => Cutter::ball(scene.tool.radius),
            Self::Ball(r) => Cutter::ball(r),
            Self::Flat(r) => Cutter::flat(r),
            Self::Fillet(r, c) => Cutter::fillet(r, c),
        };
        c.map_err(|e| format!("cutter: {e}"))
    }
}

/// The design the result is compared with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DesignChoice {
    /// The scene's two surfaces for the scene's programs, none for a loaded file.
    Auto,
    /// No design: heights only.
    None,
    /// The scene's two surfaces.
    Scene,
    /// The plane z = value (mm), material below.
    PlaneZ(f64),
}

/// Everything a run depends on (a change restarts it).
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs {
    /// Program source.
    pub source: SourceKind,
    /// Cutter.
    pub cutter: CutterChoice,
    /// Pitch (mm); `None`: automatic (grid ≤ 256 rays a side).
    pub pitch_mm: Option<f64>,
    /// Stock block `x0, y0, z0, x1, y1, z1` (mm); `None`: the program's box plus margin.
    pub stock_mm: Option<[f64; 6]>,
    /// Margin (mm) around the program's box of an automatic stock.
    pub margin_mm: f64,
    /// Design.
    pub design: DesignChoice,
    /// The scene's generation (crease restarts) and the loaded program's.
    pub scene_generation: u64,
    /// Generation of the loaded program.
    pub loaded_generation: u64,
    /// Generation of the finishing program handed over (bumped on every hand-over).
    pub finish_generation: u64,
    /// The benchmark program (source `benchmark`): its kind and moves.
    pub bench: (BenchKind, usize),
}

/// The program a run machines, with what to draw of it.
#[derive(Debug)]
pub struct Prepared {
    /// Moves.
    pub program: Program,
    /// Cutter.
    pub cutter: Cutter,
    /// Tool tip at the end of each move (mm), and at the start of the first.
    pub tips: Vec<DVec3>,
    /// Whether the design is a plane or surfaces.
    pub design_name: &'static str,
    /// Stock block used (mm).
    pub stock_mm: [f64; 6],
    /// Pitch used (mm).
    pub pitch_mm: f64,
    /// The stock's grid.
    pub grid: Grid,
}

/// The results of a finished (or partial) run.
#[derive(Debug)]
pub struct Results {
    /// Height map at the last measure.
    pub map: HeightMap,
    /// Statistics at the last measure.
    pub stats: SimStats,
    /// Moves applied when measured.
    pub moves: usize,
    /// The run's counts.
    pub counters: Counters,
    /// The move of the kept stock the run started from (0: the block; see
    /// `jobs::simulate_run::session::Session`).
    pub resumed_from: usize,
    /// A finishing program's scallops over its interior band (`simulate::interior`), when
    /// measured against its finish surface.
    pub interior: Option<InteriorStats>,
}

/// The stock shown while a run goes on: a keyframe (its heights, no deviation).
#[derive(Debug)]
struct Shown {
    moves: usize,
    counters: Counters,
    map: HeightMap,
}

/// A program's simulation: its runs, what arrived from them, and the move shown.
pub struct Job {
    /// Its inputs.
    pub inputs: Inputs,
    /// The first run's request (the replays change its source, target and keyframes).
    request: Option<Request>,
    run: Option<BackgroundJob<SimulateRun>>,
    /// Target move of the run under way (`None`: all).
    run_target: Option<usize>,
    /// The program, once made.
    pub prepared: Option<Prepared>,
    /// Keyframes of the first whole run, in move order.
    keyframes: Vec<Keyframe>,
    /// The whole program's results (kept for going back to the end).
    full: Option<std::rc::Rc<Results>>,
    shown: Option<Shown>,
    /// Move to simulate up to (`None`: all).
    pub target: Option<usize>,
    /// Results of the last measure.
    pub results: Option<std::rc::Rc<Results>>,
    /// Why the run stopped, if it failed.
    pub error: Option<String>,
    /// Wall time of the last run (ms), from its start to its output.
    pub sim_ms: f64,
    /// Wall time of all runs of this program (ms).
    pub total_ms: f64,
    /// Longest time one frame spent on the job (ms): taking and decoding what arrived.
    pub slowest_call_ms: f64,
    /// Bumped when the height map shown changes (the view re-uploads).
    pub map_generation: u64,
    /// Whether the user cancelled.
    pub cancelled: bool,
    /// Fraction done of the run under way.
    fraction: f64,
    /// When the shown map last changed while cutting.
    shown_at: Option<Instant>,
    /// Whether every run finished off the UI thread.
    pub in_background: bool,
    /// The finishing program (source `finish`), planned in the run.
    finish: Option<std::rc::Rc<FinishHandoff>>,
    /// A replay to start once the move slider has rested ([`REPLAY_SETTLE`]).
    pending_replay: Option<(Request, Instant)>,
}

impl Job {
    /// A run of `inputs` on `scene` (`loaded`: the loaded program's name and text; `finish`:
    /// the finishing program handed over), started at once — a finishing program's steps are
    /// planned in the run, off the page.
    #[must_use]
    pub fn new(
        inputs: Inputs,
        scene: &Scene,
        loaded: Option<&(String, String)>,
        target: Option<usize>,
        finish: Option<std::rc::Rc<FinishHandoff>>,
    ) -> Self {
        let mut job = Self {
            inputs,
            request: None,
            run: None,
            run_target: None,
            prepared: None,
            keyframes: Vec::new(),
            full: None,
            shown: None,
            target,
            results: None,
            error: None,
            sim_ms: 0.0,
            total_ms: 0.0,
            slowest_call_ms: 0.0,
            map_generation: 0,
            cancelled: false,
            fraction: 0.0,
            shown_at: None,
            in_background: true,
            finish,
            pending_replay: None,
        };
        let request = if job.inputs.source == SourceKind::Finish {
            job.finish_request(scene)
        } else {
            job.request_of(scene, loaded)
        };
        match request {
            Ok(r) => {
                job.run = Some(BackgroundJob::start(Request { target, ..r.clone() }));
                job.run_target = target;
                job.request = Some(r);
            }
            Err(e) => job.error = Some(e),
        }
        job
    }

    /// The first run's request: the source, cutter and design resolved against the scene.
    fn request_of(&self, scene: &Scene, loaded: Option<&(String, String)>) -> Result<Request, String> {
        let i = &self.inputs;
        let cutter = match (i.source, i.cutter) {
            (SourceKind::Benchmark, CutterChoice::SceneBall) => {
                Cutter::ball(crate::simulate::bench::BALL_MM).map_err(|e| format!("cutter: {e}"))?
            }
            (_, c) => c.cutter(scene)?,
        };
        let source = match i.source.program_kind() {
            Some(kind) => ProgramSource::Crease { scene: scene.to_json(), kind },
            None if i.source == SourceKind::Steps => ProgramSource::Steps { scene: scene.to_json() },
            None if i.source == SourceKind::Benchmark => ProgramSource::Benchmark { kind: i.bench.0, moves: i.bench.1 },
            None => {
                let (name, text) = loaded.ok_or(
                    "no G-code file loaded: open one in the \"NURBS & G-code\" tab (Open program… or drop a file), then come back",
                )?;
                ProgramSource::Text { name: name.clone(), text: text.clone() }
            }
        };
        let design = match (i.design, i.source) {
            (DesignChoice::None, _) | (DesignChoice::Auto, SourceKind::Loaded | SourceKind::Benchmark) => {
                DesignSpec::None
            }
            (DesignChoice::PlaneZ(z), _) => DesignSpec::PlaneZ(z),
            (DesignChoice::Scene | DesignChoice::Auto, _) => DesignSpec::Scene(scene.to_json()),
        };
        Ok(Request {
            source,
            cutter,
            pitch_mm: i.pitch_mm,
            stock_mm: i.stock_mm.or((i.source == SourceKind::Benchmark).then(BenchKind::stock_mm)),
            margin_mm: i.margin_mm,
            max_sample_step_mm: None,
            design,
            target: None,
            keyframes: KEYFRAMES,
            resume: false,
        })
    }

    /// The request of a finishing program: its passes, planned into seed-002 steps in the
    /// run (off the page), the program's own cutter (unless another is chosen), the part's
    /// box as the stock (unless one is given) and the finish surface as the design.
    fn finish_request(&self, scene: &Scene) -> Result<Request, String> {
        let i = &self.inputs;
        let f = self.finish.as_ref().ok_or_else(|| {
            format!("no finishing program yet: build paths in the \"{FILLET_TITLE}\" tab and press Simulate this program → there")
        })?;
        let cutter = match i.cutter {
            CutterChoice::SceneBall => f.program.cutter,
            c => c.cutter(scene)?,
        };
        let design = match i.design {
            DesignChoice::None => DesignSpec::None,
            DesignChoice::PlaneZ(z) => DesignSpec::PlaneZ(z),
            DesignChoice::Scene | DesignChoice::Auto => DesignSpec::Finish(f.scene_json.clone()),
        };
        let p = &f.program;
        Ok(Request {
            source: ProgramSource::Finish {
                scene: f.scene_json.clone(),
                cutter: p.cutter,
                passes: p.passes.clone(),
                step_tol_mm: p.step_tol_mm,
            },
            cutter,
            pitch_mm: i.pitch_mm,
            stock_mm: i.stock_mm.or_else(|| f.program.stock_mm(i.margin_mm)),
            margin_mm: i.margin_mm,
            max_sample_step_mm: crate::simulate::FinishProgram::pose_step_mm(&cutter, f.scallop_mm),
            design,
            target: None,
            keyframes: KEYFRAMES,
            resume: false,
        })
    }

    /// The largest step between sampled poses asked of the run (mm), if one was.
    #[must_use]
    pub fn pose_step_mm(&self) -> Option<f64> {
        self.request.as_ref().and_then(|r| r.max_sample_step_mm)
    }

    /// Whether work remains.
    #[must_use]
    pub fn computing(&self) -> bool {
        self.error.is_none() && !self.cancelled && (self.run.is_some() || self.pending_replay.is_some())
    }

    /// A short name of the stage, for the status and the progress text.
    #[must_use]
    pub fn stage_name(&self) -> &'static str {
        if self.error.is_some() {
            "error"
        } else if self.cancelled {
            "cancelled"
        } else if self.run.is_none() && self.pending_replay.is_none() {
            "done"
        } else if self.prepared.is_none() {
            "program"
        } else if self.fraction < 0.9 {
            "simulate"
        } else {
            "measure"
        }
    }

    /// Moves in the program (0 before it is made).
    #[must_use]
    pub fn total_moves(&self) -> usize {
        self.prepared.as_ref().map_or(0, |p| p.program.moves.len())
    }

    /// Moves applied in the stock shown.
    #[must_use]
    pub fn applied(&self) -> usize {
        match (&self.shown, &self.results) {
            (Some(s), _) => s.moves,
            (None, Some(r)) => r.moves,
            (None, None) => 0,
        }
    }

    /// The run's counts for the stock shown.
    #[must_use]
    pub fn counters(&self) -> Option<Counters> {
        match (&self.shown, &self.results) {
            (Some(s), _) => Some(s.counters),
            (None, Some(r)) => Some(r.counters),
            (None, None) => None,
        }
    }

    /// The stock's grid, once the program is made.
    #[must_use]
    pub fn grid(&self) -> Option<Grid> {
        self.prepared.as_ref().map(|p| p.grid)
    }

    /// The height map shown and, when it is a measured one, the deviation of each ray.
    #[must_use]
    pub fn current_map(&self) -> Option<(&HeightMap, Option<&[Option<f64>]>)> {
        match (&self.shown, &self.results) {
            (Some(s), _) => Some((&s.map, None)),
            (None, Some(r)) => Some((&r.map, Some(r.stats.deviation_mm.as_slice()))),
            (None, None) => None,
        }
    }

    /// The measured results of the stock shown (none while a run goes on).
    #[must_use]
    pub fn measured(&self) -> Option<&Results> {
        self.results.as_deref().filter(|_| self.run.is_none() && self.shown.is_none())
    }

    /// The move the run goes to.
    #[must_use]
    pub fn target_moves(&self) -> usize {
        self.target.unwrap_or(usize::MAX).min(self.total_moves())
    }

    /// Progress of the run in [0, 1] and a text for it.
    #[must_use]
    pub fn progress(&self) -> (f32, String) {
        let f = self.fraction as f32;
        match self.stage_name() {
            "program" if self.inputs.source == SourceKind::Finish => {
                (f, "Planning the passes' 5-axis steps (in the background)…".to_owned())
            }
            "program" => (f, "Writing the program…".to_owned()),
            "simulate" => {
                let t = self.target_moves();
                let k = ((self.fraction - 0.1) / 0.8 * t as f64).clamp(0.0, t as f64) as usize;
                (f, format!("Simulating move {k} of {t} (in the background)…"))
            }
            "measure" => (f, "Measuring the deviation…".to_owned()),
            _ => (1.0, String::new()),
        }
    }

    /// Sets the move to simulate up to (`None`: all): shows the keyframe at or before it at
    /// once and starts a run to it (the whole program's result is kept and shown again
    /// without one).
    pub fn set_target(&mut self, target: Option<usize>) {
        if self.target == target {
            return;
        }
        self.target = target;
        self.cancelled = false;
        self.pending_replay = None;
        let Some(req) = &self.request else { return };
        if self.error.is_some() {
            return;
        }
        let Some(p) = &self.prepared else {
            // Still making the program: start again with the new target.
            self.run = Some(BackgroundJob::start(Request { target, ..req.clone() }));
            self.run_target = target;
            return;
        };
        let k = self.target_moves();
        if k >= p.program.moves.len()
            && let Some(full) = &self.full
        {
            self.run = None;
            self.shown = None;
            self.results = Some(full.clone());
            self.map_generation += 1;
            return;
        }
        if let Some(key) = self.keyframes.iter().rev().find(|f| f.moves <= k) {
            self.shown = Some(Shown { moves: key.moves, counters: key.counters, map: key.map(p.grid) });
        } else {
            self.shown = Some(Shown { moves: 0, counters: Counters::default(), map: block_map(p) });
        }
        self.map_generation += 1;
        let replay = Request {
            source: ProgramSource::Moves(p.program.clone()),
            pitch_mm: Some(p.pitch_mm),
            stock_mm: Some(p.stock_mm),
            target: Some(k),
            keyframes: REPLAY_KEYFRAMES,
            resume: true,
            ..req.clone()
        };
        self.fraction = 0.0;
        // The run under way is of no use now; the replay starts when the slider rests.
        self.run = None;
        self.pending_replay = Some((replay, Instant::now()));
        self.run_target = Some(k);
    }

    /// When the panel should look at the run again if nothing else repaints: when a resting
    /// slider's replay is due, else a few times a second for the progress bar (what the run
    /// hands back wakes the page itself: `app::jobs::set_waker`).
    #[must_use]
    pub fn next_look(&self) -> Duration {
        match &self.pending_replay {
            Some((_, at)) => REPLAY_SETTLE.saturating_sub(at.elapsed()).max(crate::app::jobs::POLL),
            None => crate::app::jobs::PROGRESS_POLL,
        }
    }

    /// Stops the run where it is (the view keeps the stock shown).
    pub fn cancel(&mut self) {
        if self.computing() {
            self.run = None;
            self.pending_replay = None;
            self.cancelled = true;
        }
    }

    /// Starts a replay whose slider rested and takes what the run handed back since the
    /// last frame.
    pub fn advance(&mut self) {
        if self.pending_replay.as_ref().is_some_and(|(_, at)| at.elapsed() >= REPLAY_SETTLE)
            && let Some((replay, _)) = self.pending_replay.take()
        {
            self.run = Some(BackgroundJob::start_keeping_worker(replay));
        }
        let t0 = Instant::now();
        let Some(run) = &mut self.run else { return };
        let polled = run.poll();
        self.in_background &= run.ran_in_background();
        let elapsed_ms = run.elapsed().as_secs_f64() * 1e3;
        let whole = self.run_target.is_none_or(|k| self.prepared.as_ref().is_some_and(|p| k >= p.program.moves.len()));
        let mut newest = None;
        for part in run.take_partials() {
            match part {
                Partial::Prepared(p) => {
                    if self.prepared.is_none()
                        && let Some(req) = &self.request
                    {
                        let tips = tips_of(&p.program);
                        self.prepared = Some(Prepared {
                            tips,
                            program: p.program,
                            cutter: req.cutter,
                            design_name: p.design_name,
                            stock_mm: p.stock_mm,
                            pitch_mm: p.pitch_mm,
                            grid: p.grid,
                        });
                    }
                }
                Partial::Keyframe(k) => {
                    if self.run_target.is_none() && self.keyframes.last().is_none_or(|l| l.moves < k.moves) {
                        self.keyframes.push(k.clone());
                    }
                    newest = Some(k);
                }
            }
        }
        if let (Some(k), Some(p)) = (newest, &self.prepared)
            && self.shown_at.is_none_or(|at| at.elapsed() >= MAP_REFRESH)
        {
            self.shown = Some(Shown { moves: k.moves, counters: k.counters, map: k.map(p.grid) });
            self.shown_at = Some(Instant::now());
            self.map_generation += 1;
        }
        match polled {
            Poll::Running(f) => self.fraction = f.unwrap_or(self.fraction),
            Poll::Done(Err(JobError::Cancelled)) => {
                self.cancelled = true;
                self.run = None;
            }
            Poll::Done(Err(JobError::Failed(message))) => {
                self.error = Some(message);
                self.run = None;
            }
            Poll::Done(Ok(f)) => {
                let interior = match (&self.finish, self.request.as_ref().map(|r| &r.design)) {
                    (Some(h), Some(DesignSpec::Finish(_))) => {
                        Some(interior_stats(&f.stats, &h.program.interior_mask(&f.map.grid)))
                    }
                    _ => None,
                };
                let r = std::rc::Rc::new(Results {
                    interior,
                    moves: f.counters.moves,
                    counters: f.counters,
                    resumed_from: f.resumed_from,
                    map: f.map,
                    stats: f.stats,
                });
                if whole {
                    self.full = Some(r.clone());
                }
                self.results = Some(r);
                self.shown = None;
                self.run = None;
                self.fraction = 1.0;
                self.sim_ms = elapsed_ms;
                self.total_ms += elapsed_ms;
                self.map_generation += 1;
            }
        }
        self.slowest_call_ms = self.slowest_call_ms.max(t0.elapsed().as_secs_f64() * 1e3);
    }
}

/// The untouched block as a height map (before the first keyframe).
fn block_map(p: &Prepared) -> HeightMap {
    let n = p.grid.len();
    HeightMap { grid: p.grid, top_mm: vec![p.stock_mm[5]; n], machined: vec![false; n], through: 0 }
}

/// The tool tip at the start of the first move and the end of every move (mm).
fn tips_of(program: &Program) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(program.moves.len() + 1);
    for (k, m) in program.moves.iter().enumerate() {
        let [a, b] = ends(m);
        if k == 0 {
            out.push(a);
        }
        out.push(b);
    }
    out
}
