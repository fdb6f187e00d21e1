//! The simulation tab's work, split into steps the panel runs within a time budget per
//! frame: the scene's crease (for the programs written from it), the seed-002 step plan,
//! the program's moves, the stock, the moves applied one by one up to the slider's move,
//! and the deviation scan row by row. Every number comes from the core
//! (`gcode::write_program`, `fiveaxis::StepPlanner`, `simulate::Simulation`,
//! `simulate::DeviationScan`).

use std::rc::Rc;

use glam::DVec3;
use web_time::{Duration, Instant};

use crate::chords::RootMethod;
use crate::crease::{CreaseCurve, CreaseJob};
use crate::fiveaxis::{CreasePath, Machine, StepOptions, StepPlanner, ToolAxisRule};
use crate::gcode::{
    DesignBuilder, ProgramKind, ProgramOptions, ProgrammedPoint, Toolpath, parse_program_in, write_program,
};
use crate::geom::Cutter;
use crate::scene::{Scene, build_machine, build_tool_axis};
use crate::simulate::{
    Design, DeviationScan, DexelStock, FinishProgram, HeightMap, MoveKind, Program, SimStats, Simulation,
};

/// Periods of the crease run per call while building the design curve.
const PERIODS_PER_CALL: usize = 200;
/// How often the view's mesh follows the stock while moves are being cut.
const MAP_REFRESH: Duration = Duration::from_millis(200);
/// Grid rows of the deviation scan per call.
const ROWS_PER_CALL: usize = 4;
/// Most rays the tab simulates (a 1024 × 1024 grid, 24 MiB); above it the run is refused.
pub const MAX_APP_RAYS: usize = 1024 * 1024;
/// Longest side (rays) of the grid an automatic pitch aims at, so the view stays responsive
/// in a software rasteriser.
pub const AUTO_GRID_SIDE: f64 = 256.0;
/// Pitch range offered (mm).
pub const PITCH_RANGE_MM: (f64, f64) = (0.02, 0.5);
/// Tolerance (mm) of the crease programs and the step plan written for the simulation (the
/// NURBS tab's and the `steps` command's default).
pub const PROGRAM_TOL_MM: f64 = 0.01;

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
}

impl SourceKind {
    /// All, in menu order.
    pub const ALL: [Self; 6] =
        [Self::CreaseG01, Self::CreaseArcs, Self::CreaseNurbs, Self::Steps, Self::Loaded, Self::Finish];

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
        }
    }

    /// Menu label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::CreaseG01 => "Scene crease, G01 program",
            Self::CreaseArcs => "Scene crease, G02/G03 program",
            Self::CreaseNurbs => "Scene crease, G06.2 program",
            Self::Steps => "Scene 5-axis tool steps (seed 002)",
            Self::Loaded => "Loaded G-code file",
            Self::Finish => "Fillet tab's finishing program (seed 001)",
        }
    }

    fn program_kind(self) -> Option<ProgramKind> {
        match self {
            Self::CreaseG01 => Some(ProgramKind::Lines),
            Self::CreaseArcs => Some(ProgramKind::Arcs),
            Self::CreaseNurbs => Some(ProgramKind::Nurbs),
            _ => None,
        }
    }

    /// Whether the program is made from the scene's crease.
    #[must_use]
    pub fn needs_crease(self) -> bool {
        !matches!(self, Self::Loaded | Self::Finish)
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
    /// Design.
    pub design: Design,
    /// Whether the design is a plane or surfaces.
    pub design_name: &'static str,
    /// Stock block used (mm).
    pub stock_mm: [f64; 6],
    /// Pitch used (mm).
    pub pitch_mm: f64,
}

/// Where the run is.
enum Stage {
    /// Running the scene's crease for the design curve.
    Crease(Box<DesignBuilder>),
    /// Planning the seed-002 steps node by node.
    Plan(Box<(StepPlanner, CreasePath, Machine)>),
    /// Planning a finishing program's steps pass by pass: the next pass, the moves so far.
    FinishPlan(usize, Box<Program>),
    /// Writing the program and building the stock (one call).
    Program(Option<Box<CreaseCurve>>),
    /// Applying moves up to the target.
    Run,
    /// Scanning the deviation.
    Measure(Box<(HeightMap, DeviationScan)>),
    /// Finished (up to the target move).
    Done,
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
}

/// A run.
pub struct Job {
    /// Its inputs.
    pub inputs: Inputs,
    stage: Stage,
    /// The program, once written.
    pub prepared: Option<Prepared>,
    /// The simulation.
    pub sim: Option<Simulation>,
    /// Move to simulate up to (`None`: all).
    pub target: Option<usize>,
    /// Results of the last measure.
    pub results: Option<Results>,
    /// Why the run stopped, if it failed.
    pub error: Option<String>,
    /// Compute time spent in the simulation proper (moves applied, ms).
    pub sim_ms: f64,
    /// Compute time of the whole run, program and measure included (ms).
    pub total_ms: f64,
    /// Longest single call of [`Job::advance`] (ms): what one frame cost at most.
    pub slowest_call_ms: f64,
    /// Bumped when the height map changes (the view re-uploads).
    pub map_generation: u64,
    /// Whether the user cancelled.
    pub cancelled: bool,
    /// When the height map was last handed to the view while cutting.
    shown_at: Option<Instant>,
    /// The finishing program (source `finish`).
    finish: Option<Rc<FinishProgram>>,
}

impl Job {
    /// A run of `inputs`, waiting for its first step.
    #[must_use]
    pub fn new(inputs: Inputs, crease: Option<&CreaseJob>, finish: Option<Rc<FinishProgram>>) -> Self {
        let mut job = Self {
            inputs,
            stage: Stage::Done,
            prepared: None,
            sim: None,
            target: None,
            results: None,
            error: None,
            sim_ms: 0.0,
            total_ms: 0.0,
            slowest_call_ms: 0.0,
            map_generation: 0,
            cancelled: false,
            shown_at: None,
            finish,
        };
        if job.inputs.source == SourceKind::Finish {
            if job.finish.is_some() {
                job.stage = Stage::FinishPlan(0, Box::default());
            } else {
                job.error = Some(
                    "no finishing program yet: build paths in the \"Fillet end mill (seed 001)\" tab and press ▶ Simulate this program there"
                        .to_owned(),
                );
            }
        } else if job.inputs.source.needs_crease() {
            match crease.map(DesignBuilder::new) {
                Some(Ok(b)) => job.stage = Stage::Crease(Box::new(b)),
                Some(Err(e)) => job.error = Some(format!("the scene's crease cannot be run — {e}")),
                None => job.error = Some("the scene has no crease (it failed to build); fix the scene".to_owned()),
            }
        } else {
            job.stage = Stage::Program(None);
        }
        job
    }

    /// Whether work remains.
    #[must_use]
    pub fn computing(&self) -> bool {
        self.error.is_none() && !self.cancelled && !matches!(self.stage, Stage::Done)
    }

    /// A short name of the stage, for the status and the progress text.
    #[must_use]
    pub fn stage_name(&self) -> &'static str {
        if self.error.is_some() {
            return "error";
        }
        if self.cancelled {
            return "cancelled";
        }
        match self.stage {
            Stage::Crease(_) => "crease",
            Stage::Plan(_) | Stage::FinishPlan(..) => "plan",
            Stage::Program(_) => "program",
            Stage::Run => "simulate",
            Stage::Measure(_) => "measure",
            Stage::Done => "done",
        }
    }

    /// Moves in the program (0 before it is written).
    #[must_use]
    pub fn total_moves(&self) -> usize {
        self.prepared.as_ref().map_or(0, |p| p.program.moves.len())
    }

    /// Moves applied so far.
    #[must_use]
    pub fn applied(&self) -> usize {
        self.sim.as_ref().map_or(0, |s| s.counters().moves)
    }

    /// The move the run goes to.
    #[must_use]
    pub fn target_moves(&self) -> usize {
        self.target.unwrap_or(usize::MAX).min(self.total_moves())
    }

    /// Progress of the current stage in [0, 1] and a text for it.
    #[must_use]
    pub fn progress(&self) -> (f32, String) {
        match &self.stage {
            Stage::Crease(b) => (0.0, format!("Running the scene's crease: {} periods…", b.periods())),
            Stage::Plan(p) => (0.0, format!("Planning the 5-axis tool steps: {} blocks…", p.0.nodes().len())),
            Stage::FinishPlan(k, _) => {
                let n = self.finish.as_ref().map_or(0, |f| f.passes.len()).max(1);
                (*k as f32 / n as f32, format!("Planning the 5-axis steps of pass {k} of {n}…"))
            }
            Stage::Program(_) => (0.0, "Writing the program…".to_owned()),
            Stage::Run => {
                let (a, t) = (self.applied(), self.target_moves().max(1));
                (a as f32 / t as f32, format!("Simulating move {a} of {t}…"))
            }
            Stage::Measure(m) => {
                let ny = m.0.grid.ny.max(1);
                (
                    m.1.rows_done() as f32 / ny as f32,
                    format!("Measuring the deviation: row {} of {ny}…", m.1.rows_done()),
                )
            }
            Stage::Done => (1.0, String::new()),
        }
    }

    /// Sets the move to simulate up to (`None`: all): continues from here when it lies
    /// ahead, restarts the stock from the block when it lies behind.
    pub fn set_target(&mut self, target: Option<usize>) {
        if self.target == target {
            return;
        }
        self.target = target;
        if self.prepared.is_none() || self.error.is_some() {
            return;
        }
        let want = self.target_moves();
        if want < self.applied()
            && let (Some(p), Some(sim)) = (&self.prepared, &self.sim)
        {
            // Back in the program: start again from the block.
            if let Ok(stock) = DexelStock::block(
                [p.stock_mm[0], p.stock_mm[1], p.stock_mm[2]],
                [p.stock_mm[3], p.stock_mm[4], p.stock_mm[5]],
                sim.stock().grid().pitch_mm,
            ) {
                self.sim = Some(Simulation::new(stock, &p.cutter));
                self.sim_ms = 0.0;
            }
        }
        self.cancelled = false;
        self.stage = Stage::Run;
    }

    /// Stops the run where it is (the map shows what was simulated).
    pub fn cancel(&mut self) {
        if self.computing() {
            self.cancelled = true;
        }
    }

    /// Works for about `budget`; `scene` is the current scene and `loaded` the loaded
    /// program's (name, text).
    pub fn advance(&mut self, budget: Duration, scene: &Scene, loaded: Option<&(String, String)>) {
        let t0 = Instant::now();
        while self.computing() && t0.elapsed() < budget {
            if let Err(e) = self.step(scene, loaded, t0, budget) {
                self.error = Some(e);
            }
        }
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        self.total_ms += ms;
        self.slowest_call_ms = self.slowest_call_ms.max(ms);
    }

    fn step(
        &mut self,
        scene: &Scene,
        loaded: Option<&(String, String)>,
        t0: Instant,
        budget: Duration,
    ) -> Result<(), String> {
        match &mut self.stage {
            Stage::Crease(b) => {
                if let Some(done) = b.advance(PERIODS_PER_CALL) {
                    let curve = done.map_err(|e| format!("the scene's crease gives no design curve — {e}"))?;
                    if self.inputs.source == SourceKind::Steps {
                        let machine = scene.machine.as_ref().map(build_machine).unwrap_or_default();
                        let rule = match &scene.tool_axis {
                            Some(t) => build_tool_axis(t).map_err(|e| e.to_string())?,
                            None => ToolAxisRule::Bisector,
                        };
                        let path = CreasePath::new(curve, rule);
                        let opts = StepOptions::new(PROGRAM_TOL_MM).with_method(RootMethod::Bisection);
                        let planner = StepPlanner::new(&machine, &path, &opts)
                            .map_err(|e| format!("the 5-axis steps cannot be planned — {e}"))?;
                        self.stage = Stage::Plan(Box::new((planner, path, machine)));
                    } else {
                        self.stage = Stage::Program(Some(Box::new(curve)));
                    }
                }
            }
            Stage::Plan(p) => {
                let (planner, path, machine) = &mut **p;
                while !planner.is_done() && t0.elapsed() < budget {
                    planner
                        .next_node(machine, path)
                        .map_err(|e| format!("the 5-axis steps cannot be planned — {e}"))?;
                }
                if planner.is_done() {
                    let blocks: Vec<_> = planner.nodes().iter().map(|n| n.block).collect();
                    let program = Program::from_blocks(machine, &blocks).map_err(|e| e.to_string())?;
                    self.prepare(scene, program)?;
                }
            }
            Stage::FinishPlan(k, program) => {
                let fp = self.finish.clone().ok_or("internal: no finishing program")?;
                // One pass per call at least: a pass is the smallest step of the planner.
                while *k < fp.passes.len() {
                    fp.plan_pass(*k, program).map_err(|e| e.to_string())?;
                    *k += 1;
                    if t0.elapsed() >= budget {
                        break;
                    }
                }
                if *k >= fp.passes.len() {
                    let program = std::mem::take(&mut **program);
                    self.prepare(scene, program)?;
                }
            }
            Stage::Program(curve) => {
                let curve = curve.take();
                let program = self.write(scene, curve.as_deref(), loaded)?;
                self.prepare(scene, program)?;
            }
            Stage::Run => {
                let target = self.target_moves();
                let (Some(p), Some(sim)) = (&self.prepared, &mut self.sim) else {
                    return Err("internal: no program to simulate".to_owned());
                };
                let t = Instant::now();
                while sim.counters().moves < target && t0.elapsed() < budget {
                    sim.apply(&p.program.moves[sim.counters().moves]);
                }
                self.sim_ms += t.elapsed().as_secs_f64() * 1e3;
                // The view rebuilds its mesh (one vertex per ray) when this changes: a few
                // times a second while cutting, not every frame.
                if self.shown_at.is_none_or(|at| at.elapsed() >= MAP_REFRESH) || sim.counters().moves >= target {
                    self.map_generation += 1;
                    self.shown_at = Some(Instant::now());
                }
                if sim.counters().moves >= target {
                    let map = HeightMap::of(sim.stock());
                    let scan = DeviationScan::new(&map, &p.design);
                    self.stage = Stage::Measure(Box::new((map, scan)));
                }
            }
            Stage::Measure(m) => {
                let (Some(p), Some(sim)) = (&self.prepared, &self.sim) else {
                    return Err("internal: no program to measure".to_owned());
                };
                let (map, scan) = &mut **m;
                scan.rows(map, &p.design, ROWS_PER_CALL);
                if scan.rows_done() >= map.grid.ny {
                    let Stage::Measure(m) = std::mem::replace(&mut self.stage, Stage::Done) else {
                        return Ok(());
                    };
                    let (map, scan) = *m;
                    let stats = scan.finish(&map, sim.stock());
                    self.results = Some(Results { map, stats, moves: sim.counters().moves });
                    self.map_generation += 1;
                }
            }
            Stage::Done => {}
        }
        Ok(())
    }

    /// The program text's moves: a crease program written by the core, or the loaded file.
    /// A program of ball centres (ours, or a file whose header says so) is moved down by
    /// the cutter radius to tool tips, as `interpolab simulate --point auto` does.
    fn write(
        &self,
        scene: &Scene,
        curve: Option<&CreaseCurve>,
        loaded: Option<&(String, String)>,
    ) -> Result<Program, String> {
        let cutter = self.inputs.cutter.cutter(scene)?;
        let chord = |pitch: f64| pitch / 10.0;
        let (toolpath, centre): (Toolpath, bool) = if let Some(kind) = self.inputs.source.program_kind() {
            let curve = curve.ok_or("internal: no crease curve")?;
            let title = if scene.name.is_empty() { "scene".to_owned() } else { scene.name.clone() };
            let opts = ProgramOptions::default().with_title(&title).with_point(ProgrammedPoint::BallCentre);
            let p = write_program(kind, curve, PROGRAM_TOL_MM, &opts)
                .map_err(|e| format!("the {} program cannot be written — {e}", kind.label()))?;
            (p.parsed.toolpath, true)
        } else {
            let (name, text) = loaded.ok_or(
                "no G-code file loaded: open one in the \"NURBS & G-code\" tab (Open program… or drop a file), then come back",
            )?;
            let parsed = parse_program_in(text, crate::gcode::Dialect::guess(text))
                .map_err(|e| format!("{name} is not a program this reader can follow — {e}"))?;
            let centre = matches!(ProgrammedPoint::from_comments(&parsed.comments), Some(ProgrammedPoint::BallCentre));
            (parsed.toolpath, centre)
        };
        let offset = if centre { DVec3::new(0.0, 0.0, -cutter.radius_mm) } else { DVec3::ZERO };
        // The chord tolerance follows the pitch, which may follow the program's box: chord
        // at the smallest pitch offered first when automatic, then again at the one chosen.
        let pitch0 = self.inputs.pitch_mm.unwrap_or(PITCH_RANGE_MM.0);
        let program = Program::from_toolpath(&toolpath, offset, chord(pitch0)).map_err(|e| e.to_string())?;
        if self.inputs.pitch_mm.is_none() {
            let (_, pitch) = self.stock_and_pitch(&program, &cutter)?;
            if (pitch - pitch0).abs() > 0.0 {
                let program = Program::from_toolpath(&toolpath, offset, chord(pitch)).map_err(|e| e.to_string())?;
                return Ok(program);
            }
        }
        Ok(program)
    }

    /// The cutter: the finishing program's own for `finish` when the choice is the
    /// program's (`CutterChoice::SceneBall`), else the choice.
    fn cutter(&self, scene: &Scene) -> Result<Cutter, String> {
        match (&self.finish, self.inputs.source, self.inputs.cutter) {
            (Some(fp), SourceKind::Finish, CutterChoice::SceneBall) => Ok(fp.cutter),
            (_, _, c) => c.cutter(scene),
        }
    }

    /// The stock block and pitch for `program`: the user's, else automatic (a finishing
    /// program's: the part's box, [`FinishProgram::stock_mm`]).
    fn stock_and_pitch(&self, program: &Program, cutter: &Cutter) -> Result<([f64; 6], f64), String> {
        let part = match (&self.finish, self.inputs.source) {
            (Some(fp), SourceKind::Finish) => fp.stock_mm(self.inputs.margin_mm),
            _ => None,
        };
        let stock = match (self.inputs.stock_mm, part) {
            (Some(s), _) | (None, Some(s)) => s,
            (None, None) => auto_stock(program, cutter, self.inputs.margin_mm)
                .ok_or("the program has no cutting move to size the stock from; give the stock block")?,
        };
        let pitch = match self.inputs.pitch_mm {
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

    /// Builds the stock and the simulation for `program`.
    fn prepare(&mut self, scene: &Scene, program: Program) -> Result<(), String> {
        let cutter = self.cutter(scene)?;
        let (stock_mm, pitch) = self.stock_and_pitch(&program, &cutter)?;
        let nx = ((stock_mm[3] - stock_mm[0]) / pitch).ceil();
        let ny = ((stock_mm[4] - stock_mm[1]) / pitch).ceil();
        if nx * ny > MAX_APP_RAYS as f64 {
            return Err(format!(
                "a pitch of {pitch} mm on this stock gives {nx:.0} × {ny:.0} rays, more than the {MAX_APP_RAYS} this view simulates; raise the pitch or shrink the stock"
            ));
        }
        let stock =
            DexelStock::block([stock_mm[0], stock_mm[1], stock_mm[2]], [stock_mm[3], stock_mm[4], stock_mm[5]], pitch)
                .map_err(|e| e.to_string())?;
        let sim = Simulation::new(stock, &cutter);
        let visits = sim.estimate_visits(&program);
        if !(visits <= crate::simulate::MAX_RAY_VISITS) {
            return Err(
                crate::simulate::SimError::TooMuchWork { visits, max: crate::simulate::MAX_RAY_VISITS }.to_string()
            );
        }
        let with_scene = || {
            CreaseJob::from_scene(scene)
                .map(|j| Design::Surfaces(j.surfaces.to_vec()))
                .map_err(|e| format!("the scene's surfaces: {e}"))
        };
        let (design, design_name) = match (self.inputs.design, self.inputs.source) {
            (DesignChoice::None, _) | (DesignChoice::Auto, SourceKind::Loaded) => (Design::None, "none"),
            (DesignChoice::PlaneZ(z), _) => (Design::PlaneZ(z), "plane"),
            (DesignChoice::Scene | DesignChoice::Auto, SourceKind::Finish) => {
                let fp = self.finish.as_ref().ok_or("internal: no finishing program")?;
                (fp.design(), "finish surface")
            }
            (DesignChoice::Scene | DesignChoice::Auto, _) => (with_scene()?, "scene surfaces"),
        };
        let tips = tips_of(&program);
        self.prepared = Some(Prepared { program, cutter, tips, design, design_name, stock_mm, pitch_mm: pitch });
        self.sim = Some(sim);
        self.stage = Stage::Run;
        Ok(())
    }
}

/// The tool tip at the start of the first move and the end of every move (mm).
fn tips_of(program: &Program) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(program.moves.len() + 1);
    for (k, m) in program.moves.iter().enumerate() {
        let (a, b) = match m.kind {
            MoveKind::Line { from, to } => (from, to),
            MoveKind::Joints { machine, from, to } => {
                (machine.pose_from_joints(&from).tip_in_workpiece, machine.pose_from_joints(&to).tip_in_workpiece)
            }
        };
        if k == 0 {
            out.push(a);
        }
        out.push(b);
    }
    out
}

/// The box of the program's cutting moves (rapids left out) widened by the cutter radius
/// and `margin_mm` in x and y; z from `margin_mm` below the lowest tip to one radius above
/// the highest cutting tip. `None` without a cutting move.
#[must_use]
pub fn auto_stock(program: &Program, cutter: &Cutter, margin_mm: f64) -> Option<[f64; 6]> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for m in program.moves.iter().filter(|m| !m.rapid) {
        let pts = match m.kind {
            MoveKind::Line { from, to } => [from, to],
            MoveKind::Joints { machine, from, to } => {
                [machine.pose_from_joints(&from).tip_in_workpiece, machine.pose_from_joints(&to).tip_in_workpiece]
            }
        };
        for p in pts {
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
