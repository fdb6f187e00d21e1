//! The NURBS panel's computations, run one step per frame so the page never freezes: the
//! design path, then the G01, G02/G03 and G06.2 programs (one per frame, each written and
//! checked by the core), then the real-time interpolation of the G06.2 curve, then the
//! deviation of a loaded program. Every step is keyed by exactly what it depends on, so a
//! change of the update order reruns only the real-time step, a tolerance change the
//! programs and what follows, and a new scene everything. Results stay on screen (marked
//! stale) until their replacement is ready. No egui here: the steps are plain core calls.
//!
//! The three programs are background jobs (`app::jobs`, kind `jobs::program_row`), started
//! together and polled each frame: natively on threads, in the browser in Web Workers; each
//! also times its program on the chosen machine. Only the crease periods and the real-time
//! periods run here, a few thousand per frame.

use std::rc::Rc;

use glam::DVec3;
use web_time::{Duration, Instant};

use crate::app::jobs::{Job, Poll};
use crate::crease::{CreaseCurve, CreaseJob};
use crate::gcode::{
    CompareOptions, CompareRow, Comparison, DesignBuilder, DesignError, Deviation, DeviationOptions, Dialect,
    ExtraColumns, ParsedProgram, ProgramKind, ProgramOptions, ProgrammedPoint, deviation,
};
use crate::geom::Curve3;
use crate::jobs::JobError;
use crate::jobs::program_row::{CycleTime, DesignSpec, ProgramRow, Request, TimedRow, timed_row};
use crate::numerics::measure::{ArcLengthTable, Translated};
use crate::nurbs_path::{FeedStats, Parabola, RealtimeRun, RealtimeStepper, Update};
use crate::plan::Dynamics;
use crate::scene::Scene;

/// Finest spacing (mm) of the samples of a design curve drawn in the view.
const MIN_SAMPLE_SPACING_MM: f64 = 1e-3;

/// Periods of the crease or of a real-time run per step: a few ms natively, ~10 ms in a
/// browser, so a 10⁵-period path (a slow feed) is spread over frames.
const PERIODS_PER_STEP: usize = 4000;

/// Quiet time after the last change of an input before the work starts (a slider being
/// dragged does not start a computation per frame).
pub const DEBOUNCE: Duration = Duration::from_millis(250);

/// Where the design path comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The current scene's ball-centre crease (`gcode::crease_design`).
    Crease,
    /// Seed 004's parabola-like profile (`Parabola::paper_like`).
    Parabola,
}

/// Which point of the ball the programs carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Point {
    /// Ball centre.
    Centre,
    /// Ball tip (centre − R·ẑ).
    Tip,
}

/// The design curve: the crease or the profile.
#[derive(Clone, Debug)]
pub enum DesignCurve {
    /// A scene's crease.
    Crease(Box<CreaseCurve>),
    /// The comparison profile.
    Parabola(Parabola),
}

impl Curve3 for DesignCurve {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        match self {
            Self::Crease(c) => c.derivatives_at(s),
            Self::Parabola(p) => p.derivatives_at(s),
        }
    }
    fn range(&self) -> (f64, f64) {
        match self {
            Self::Crease(c) => c.range(),
            Self::Parabola(p) => p.range(),
        }
    }
}

/// A design path with what the programs take from its source.
#[derive(Debug)]
pub struct Design {
    /// The ball-centre curve.
    pub curve: DesignCurve,
    /// Title written into the programs (as the command line does).
    pub title: String,
    /// Length (mm).
    pub length_mm: f64,
}

impl Design {
    /// Ball-centre points every ~`spacing_mm` (and at least 64), for drawing and framing.
    #[must_use]
    pub fn samples(&self, spacing_mm: f64) -> Vec<DVec3> {
        let (a, b) = self.curve.range();
        let n = ((self.length_mm / spacing_mm.max(MIN_SAMPLE_SPACING_MM)).ceil() as usize).clamp(64, 20_000);
        (0..=n).map(|i| self.curve.point_at(a + (b - a) * i as f64 / n as f64)).collect()
    }
}

/// What the design is made from.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignInput {
    /// The crease of this job (its scene's name as the title).
    Crease(Box<CreaseJob>, String),
    /// The profile.
    Parabola,
}

/// Every input of the programs besides the design.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramInput {
    /// Tolerance E (mm).
    pub tol_mm: f64,
    /// Resolution (mm).
    pub resolution_mm: f64,
    /// Programmed point.
    pub point: ProgrammedPoint,
    /// Feed F (mm/min).
    pub feed_mm_per_min: f64,
    /// G06.2 degree.
    pub degree: usize,
    /// Controller dialect of the programs.
    pub dialect: Dialect,
}

/// Every input of the real-time runs besides the G06.2 curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealtimeInput {
    /// The update whose samples are kept (plotted and drawn).
    pub update: Update,
    /// Period Ts (ms).
    pub period_ms: f64,
    /// Chord tolerance of the feed limit (mm).
    pub chord_tol_mm: Option<f64>,
}

/// All the inputs of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Wanted {
    /// The design.
    pub design: DesignInput,
    /// The programs.
    pub program: ProgramInput,
    /// The real-time runs.
    pub realtime: RealtimeInput,
    /// The machine the programs are timed on (`None`: not timed).
    pub machine: Option<Dynamics>,
}

/// A result with the key it was computed for and a generation number that changes whenever
/// the value is replaced (so views rebuild only what changed).
#[derive(Debug)]
pub struct Slot<K, T> {
    key: Option<K>,
    /// The value (an error is a message in the user's terms).
    pub value: Option<Result<T, String>>,
    /// Bumped on every replacement.
    pub generation: u64,
}

impl<K: PartialEq, T> Default for Slot<K, T> {
    fn default() -> Self {
        Self { key: None, value: None, generation: 0 }
    }
}

impl<K: PartialEq, T> Slot<K, T> {
    fn is_for(&self, key: &K) -> bool {
        self.key.as_ref() == Some(key)
    }
    fn clear(&mut self) {
        self.key = None;
        self.value = None;
        self.generation += 1;
    }
    fn set(&mut self, key: K, value: Result<T, String>) {
        self.key = Some(key);
        self.value = Some(value);
        self.generation += 1;
    }
    /// Replaces the value by one that differs only in what nothing drawn depends on (a row's
    /// time on another machine): the generation stays, so nothing is rebuilt or rerun.
    fn set_same(&mut self, key: K, value: Result<T, String>) {
        self.key = Some(key);
        self.value = Some(value);
    }
    /// The value if it was computed without error.
    #[must_use]
    pub fn ok(&self) -> Option<&T> {
        self.value.as_ref().and_then(|v| v.as_ref().ok())
    }
}

/// The real-time runs of the G06.2 curve.
#[derive(Debug)]
pub struct Realtime {
    /// Statistics of every update (the comparison's second table).
    pub stats: Vec<FeedStats>,
    /// The chosen update's run with every period's sample.
    pub run: RealtimeRun,
    /// The feed per period f = F·Ts of the run (mm).
    pub feed_per_period_mm: f64,
    /// The period (ms).
    pub period_ms: f64,
}

/// A G-code file the user loaded.
#[derive(Debug)]
pub struct Loaded {
    /// File name.
    pub name: String,
    /// Its text.
    pub text: String,
    /// The parsed program, or the reader's error (with its line).
    pub parsed: Result<ParsedProgram, String>,
    /// The line the reader's error is about.
    pub error_line: Option<usize>,
    /// Programmed point named by the program's header, if it has one of ours.
    pub point: Option<ProgrammedPoint>,
    /// Bumped for every file loaded.
    pub generation: u64,
    /// The interpreter while it reads the file, a slice a step ([`READ_CALLS_PER_STEP`]): the
    /// path drawn grows as it reads; `parsed` is final once this is `None`.
    pub reader: Option<crate::gcode::ProgramReader>,
}

/// Canonical calls read in one step of loading a program: a few milliseconds of the frame
/// budget in the browser, so a 180 000-line program opens over a few dozen frames.
const READ_CALLS_PER_STEP: usize = 4000;

type DesignSlot = Slot<DesignInput, Rc<Design>>;
type RowKey = (u64, ProgramInput, Option<Dynamics>);
type RealtimeKey = (u64, u64, ProgramInput, RealtimeInput);
type LoadedKey = (u64, u64, ProgramInput);

/// The panel's results and the steps that fill them.
#[derive(Debug, Default)]
pub struct Work {
    /// The design path.
    pub design: DesignSlot,
    /// One row per program kind, in [`ProgramKind::ALL`] order, with its time on the machine.
    pub rows: [Slot<RowKey, TimedRow>; 3],
    /// The real-time runs of the G06.2 program.
    pub realtime: Slot<RealtimeKey, Realtime>,
    /// A loaded program.
    pub loaded: Option<Loaded>,
    /// Its deviation from the design.
    pub loaded_deviation: Slot<LoadedKey, Deviation>,
    last_wanted: Option<Wanted>,
    changed_at: Option<Instant>,
    loaded_generation: u64,
    /// The crease being run for the design path.
    design_task: Option<(DesignInput, DesignBuilder)>,
    /// The real-time runs under way.
    realtime_task: Option<RealtimeTask>,
    /// The programs being written in the background, one per kind, with the key they are for.
    row_jobs: [Option<(RowKey, Job<ProgramRow>)>; 3],
    /// The scene's JSON text for a crease job, when it gives that job back exactly (what a
    /// worker is sent to rebuild the design); `None` inside: compute on this thread.
    scene_text: Option<(Box<CreaseJob>, Option<String>)>,
}

/// The real-time runs of one G06.2 curve under way.
#[derive(Debug)]
struct RealtimeTask {
    key: RealtimeKey,
    /// Index in [`Update::ALL`] of the run under way.
    next: usize,
    stepper: Option<RealtimeStepper>,
    stats: Vec<FeedStats>,
    /// The chosen update's run, with samples.
    run: Option<RealtimeRun>,
}

/// What the panel still has to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pending {
    /// Everything is up to date.
    Nothing,
    /// Inputs changed less than [`DEBOUNCE`] ago.
    Waiting(Duration),
    /// A step is due.
    Working,
}

impl Work {
    /// The compare options the programs were (or will be) written with.
    #[must_use]
    pub fn compare_options(title: &str, p: &ProgramInput, r: &RealtimeInput) -> CompareOptions {
        CompareOptions {
            program: ProgramOptions::default()
                .with_resolution(p.resolution_mm)
                .with_feed(p.feed_mm_per_min)
                .with_point(p.point)
                .with_title(title)
                .with_degree(p.degree)
                .with_dialect(p.dialect),
            period_ms: r.period_ms,
            chord_tol_mm: r.chord_tol_mm,
        }
    }

    /// Loads a program's text (parsed at once: reading is fast).
    pub fn load(&mut self, name: &str, text: String) {
        // The dialect as the program says (our header) or its words show.
        let dialect = Dialect::guess(&text);
        let reader = crate::gcode::ProgramReader::new(
            std::sync::Arc::from(text.as_str()),
            dialect,
            &crate::gcode::interp::Options::default(),
        );
        self.loaded_generation += 1;
        self.loaded_deviation.clear();
        self.loaded = Some(Loaded {
            name: name.to_owned(),
            text,
            parsed: Ok(ParsedProgram::default()),
            error_line: None,
            point: None,
            generation: self.loaded_generation,
            reader: Some(reader),
        });
    }

    /// Reads the next slice of the loaded program; `true` when a slice was read.
    fn read_step(&mut self) -> bool {
        let Some(l) = self.loaded.as_mut() else {
            return false;
        };
        let Some(reader) = l.reader.as_mut() else {
            return false;
        };
        if !reader.step(READ_CALLS_PER_STEP) {
            return true;
        }
        if let Some(reader) = l.reader.take() {
            let parsed = reader.into_result();
            l.error_line = parsed.as_ref().err().map(crate::gcode::ParseError::line);
            l.point = parsed.as_ref().ok().and_then(|p| ProgrammedPoint::from_comments(&p.comments));
            l.parsed = parsed.map_err(|e| e.to_string());
        }
        true
    }

    /// Forgets the loaded program.
    pub fn unload(&mut self) {
        self.loaded = None;
        self.loaded_deviation.clear();
    }

    /// Whether the design slot holds the design for `w`.
    #[must_use]
    pub fn design_fresh(&self, w: &Wanted) -> bool {
        self.design.is_for(&w.design)
    }

    fn row_key(&self, w: &Wanted) -> RowKey {
        (self.design.generation, w.program.clone(), w.machine.clone())
    }

    /// Row `i`'s program and numbers, if it was written.
    #[must_use]
    pub fn row(&self, i: usize) -> Option<&CompareRow> {
        self.rows[i].ok().map(|t| &t.row)
    }

    /// Row `i`'s time on the machine: `None` while not written or not timed.
    #[must_use]
    pub fn row_time(&self, i: usize) -> Option<&Result<CycleTime, String>> {
        self.rows[i].ok().and_then(|t| t.time.as_ref())
    }

    /// The time columns of `interpolab compare --machine` (time s, feed time s, mean feed
    /// mm/min, as it formats them), when every row was timed.
    #[must_use]
    pub fn time_columns(&self) -> Option<ExtraColumns> {
        let cells =
            (0..3).map(|i| self.row_time(i)?.as_ref().ok().map(|t| t.cells().to_vec())).collect::<Option<Vec<_>>>()?;
        let name = self.row_time(0)?.as_ref().ok()?.machine.clone();
        Some(ExtraColumns {
            heads: CycleTime::HEADS.map(str::to_owned).to_vec(),
            cells: vec![cells],
            notes: vec![format!(
                "Times on the machine {name}: the feed planned within its limits (interpolab compare --machine {name})."
            )],
        })
    }

    /// Whether row `i` is for the current inputs.
    #[must_use]
    pub fn row_fresh(&self, i: usize, w: &Wanted) -> bool {
        self.design_fresh(w) && self.rows[i].is_for(&self.row_key(w))
    }

    fn realtime_key(&self, w: &Wanted) -> RealtimeKey {
        (self.design.generation, self.rows[2].generation, w.program.clone(), w.realtime)
    }

    /// Whether the real-time runs are for the current inputs.
    #[must_use]
    pub fn realtime_fresh(&self, w: &Wanted) -> bool {
        self.row_fresh(2, w) && self.realtime.is_for(&self.realtime_key(w))
    }

    fn loaded_key(&self, w: &Wanted) -> Option<LoadedKey> {
        self.loaded.as_ref().map(|l| (self.design.generation, l.generation, w.program.clone()))
    }

    /// Whether the loaded program's deviation is for the current inputs and file.
    #[must_use]
    pub fn loaded_fresh(&self, w: &Wanted) -> bool {
        self.design_fresh(w) && self.loaded_key(w).is_some_and(|k| self.loaded_deviation.is_for(&k))
    }

    /// What is left to do for `w`.
    #[must_use]
    pub fn pending(&self, w: &Wanted) -> Pending {
        let loaded_due =
            self.loaded.as_ref().is_some_and(|l| l.reader.is_some() || l.parsed.is_ok()) && !self.loaded_fresh(w);
        let design_ok = self.design_fresh(w) && self.design.ok().is_some();
        let done = self.design_fresh(w)
            && (!design_ok || ((0..3).all(|i| self.row_fresh(i, w)) && self.realtime_done(w) && !loaded_due));
        if done {
            return Pending::Nothing;
        }
        match self.changed_at {
            Some(t) if t.elapsed() < DEBOUNCE => Pending::Waiting(DEBOUNCE - t.elapsed()),
            _ => Pending::Working,
        }
    }

    /// The real-time step is done, or cannot run (no G06.2 program).
    fn realtime_done(&self, w: &Wanted) -> bool {
        self.realtime_fresh(w) || (self.row_fresh(2, w) && self.row(2).is_none())
    }

    /// Notes the inputs of this frame (restarting the quiet time when they changed).
    pub fn want(&mut self, w: &Wanted) {
        if self.last_wanted.as_ref() != Some(w) {
            // The first inputs start at once; later changes wait for the quiet time.
            if self.last_wanted.is_some() {
                self.changed_at = Some(Instant::now());
            }
            self.last_wanted = Some(w.clone());
        }
    }

    /// Notes the scene the crease job comes from (its JSON goes to the program jobs). Checked
    /// once per job: the text must give the same job back, or the programs are written here.
    pub fn note_scene(&mut self, job: &CreaseJob, scene: &Scene) {
        if self.scene_text.as_ref().is_some_and(|(j, _)| **j == *job) {
            return;
        }
        let text = scene.to_json();
        let same = Scene::from_json(&text).ok().and_then(|s| CreaseJob::from_scene(&s).ok()).is_some_and(|j| j == *job);
        self.scene_text = Some((Box::new(job.clone()), same.then_some(text)));
    }

    /// What a program job is sent to rebuild the design, if it can be.
    fn design_spec(&self, input: &DesignInput) -> Option<DesignSpec> {
        match input {
            DesignInput::Parabola => Some(DesignSpec::Parabola),
            DesignInput::Crease(job, _) => match &self.scene_text {
                Some((j, Some(text))) if **j == **job => Some(DesignSpec::Scene(text.clone())),
                _ => None,
            },
        }
    }

    /// Whether programs are being written in the background (the panel only needs to look
    /// again now and then).
    #[must_use]
    pub fn waiting_on_jobs(&self) -> bool {
        self.row_jobs.iter().any(|j| j.as_ref().is_some_and(|(_, job)| job.in_background()))
    }

    /// The programs being written in the background: kind, seconds so far.
    #[must_use]
    pub fn jobs_running(&self) -> Vec<(ProgramKind, f64)> {
        ProgramKind::ALL
            .into_iter()
            .zip(&self.row_jobs)
            .filter_map(|(k, j)| j.as_ref().map(|(_, job)| (k, job.elapsed().as_secs_f64())))
            .collect()
    }

    /// Runs the next due step for `w`, if the quiet time is over. Returns whether a step ran.
    pub fn step(&mut self, w: &Wanted) -> bool {
        if self.pending(w) != Pending::Working {
            return false;
        }
        self.step_now(w)
    }

    /// Runs the next due step for `w` regardless of the quiet time (tests, first frame).
    pub fn step_now(&mut self, w: &Wanted) -> bool {
        if !self.design_fresh(w) {
            if let Some(value) = self.design_step(&w.design) {
                self.design.set(w.design.clone(), value.map(Rc::new));
            }
            return true;
        }
        let Some(design) = self.design.ok().cloned() else {
            return false;
        };
        let opts = Self::compare_options(&design.title, &w.program, &w.realtime);
        let spec = self.design_spec(&w.design);
        let mut rows_due = false;
        for (i, kind) in ProgramKind::ALL.into_iter().enumerate() {
            if self.row_fresh(i, w) {
                continue;
            }
            rows_due = true;
            let key = self.row_key(w);
            let value = if let Some(spec) = &spec {
                // In the background: start the job for these inputs (replacing, and so
                // cancelling, one for older inputs), then see whether it is done.
                if self.row_jobs[i].as_ref().is_none_or(|(k, _)| *k != key) {
                    let request = Request {
                        design: spec.clone(),
                        kind,
                        tol_mm: w.program.tol_mm,
                        options: opts.clone(),
                        machine: w.machine.clone(),
                    };
                    self.row_jobs[i] = Some((key.clone(), Job::start(request)));
                }
                match self.row_jobs[i].as_mut().map(|(_, job)| job.poll()) {
                    Some(Poll::Done(value)) => {
                        self.row_jobs[i] = None;
                        value
                    }
                    _ => continue,
                }
            } else {
                timed_row(kind, &design.curve, w.program.tol_mm, &opts, w.machine.as_ref()).map_err(JobError::from)
            }
            .map_err(|e| e.to_string());
            if kind == ProgramKind::Nurbs && value.is_err() {
                // Nothing to run: drop the last curve's run rather than show it as current.
                self.realtime.clear();
            }
            // Only the machine changed (the same program text): what is drawn and run from
            // the program stays.
            let same_program = matches!((&self.rows[i].value, &value),
                (Some(Ok(a)), Ok(b)) if a.row.program.text == b.row.program.text && self.rows[i].key.as_ref().is_some_and(|k| k.0 == key.0 && k.1 == key.1));
            if same_program {
                self.rows[i].set_same(key, value);
            } else {
                self.rows[i].set(key, value);
            }
            return true;
        }
        if rows_due {
            // Waiting for the background: nothing ran here.
            return false;
        }
        if !self.realtime_done(w) {
            let key = self.realtime_key(w);
            if let Some(value) = self.realtime_step(&key, &opts, w.realtime.update) {
                self.realtime.set(key, value);
            }
            return true;
        }
        if self.read_step() {
            return true;
        }
        if let (Some(key), Some(loaded)) = (self.loaded_key(w), &self.loaded)
            && !self.loaded_deviation.is_for(&key)
        {
            let value = match &loaded.parsed {
                Ok(p) => {
                    // The program's own header decides the point; otherwise the panel's.
                    let point = loaded.point.unwrap_or(w.program.point);
                    let moved = Translated { inner: &design.curve, offset: point.offset() };
                    deviation(&p.toolpath, &moved, &DeviationOptions::default()).map_err(|e| e.to_string())
                }
                Err(e) => Err(e.clone()),
            };
            self.loaded_deviation.set(key, value);
            return true;
        }
        false
    }

    /// One step of the design path: a parabola at once, a crease [`PERIODS_PER_STEP`] periods
    /// at a time. `Some` when done.
    fn design_step(&mut self, input: &DesignInput) -> Option<Result<Design, String>> {
        let DesignInput::Crease(job, name) = input else {
            return Some(make_parabola());
        };
        let fresh = self.design_task.as_ref().is_some_and(|(i, _)| i == input);
        if !fresh {
            match DesignBuilder::new(job) {
                Ok(b) => self.design_task = Some((input.clone(), b)),
                Err(e) => return Some(Err(crease_failed(&e))),
            }
        }
        let (_, builder) = self.design_task.as_mut()?;
        let done = builder.advance(PERIODS_PER_STEP)?;
        self.design_task = None;
        Some(done.map_err(|e| crease_failed(&e)).map(|c| Design {
            length_mm: c.path().length(),
            curve: DesignCurve::Crease(Box::new(c)),
            title: if name.is_empty() { "scene".to_owned() } else { name.clone() },
        }))
    }

    /// Periods of the design path run so far, while it is being built.
    #[must_use]
    pub fn design_progress(&self) -> Option<usize> {
        self.design_task.as_ref().map(|(_, b)| b.periods())
    }

    /// The update being run and its periods so far, while the real-time runs are under way.
    #[must_use]
    pub fn realtime_progress(&self) -> Option<(Update, u64)> {
        let t = self.realtime_task.as_ref()?;
        Some((*Update::ALL.get(t.next)?, t.stepper.as_ref().map_or(0, RealtimeStepper::periods)))
    }

    /// One step of the real-time runs of the G06.2 curve: [`PERIODS_PER_STEP`] periods of
    /// one update's run; the updates in [`Update::ALL`] order, each run once, the chosen one
    /// keeping its samples. `Some` when all are done.
    fn realtime_step(
        &mut self,
        key: &RealtimeKey,
        opts: &CompareOptions,
        chosen: Update,
    ) -> Option<Result<Realtime, String>> {
        let Some(curve) = self.rows[2].ok().and_then(|r| r.row.program.read_back_curves().next()) else {
            return Some(Err("the G06.2 program holds no curve".to_owned()));
        };
        if self.realtime_task.as_ref().is_none_or(|t| t.key != *key) {
            self.realtime_task =
                Some(RealtimeTask { key: key.clone(), next: 0, stepper: None, stats: Vec::new(), run: None });
        }
        let task = self.realtime_task.as_mut()?;
        let Some(&update) = Update::ALL.get(task.next) else {
            let t = self.realtime_task.take()?;
            let ro = opts.realtime(chosen);
            return Some(match t.run {
                Some(run) => Ok(Realtime {
                    stats: t.stats,
                    run,
                    feed_per_period_mm: ro.feed_per_period_mm(),
                    period_ms: opts.period_ms,
                }),
                None => Err(format!("the {} update could not run this curve", chosen.as_str())),
            });
        };
        let ro = opts.realtime(update).with_samples(update == chosen);
        let stepper = match task.stepper.take() {
            Some(s) => Ok(s),
            None => RealtimeStepper::new(curve, &ro),
        };
        // As `realtime_stats`: an update that cannot run the curve is left out of the table.
        match stepper.and_then(|mut s| s.advance(curve, PERIODS_PER_STEP as u64).map(|done| (done, s))) {
            Ok((false, s)) => task.stepper = Some(s),
            Ok((true, s)) => {
                let run = s.finish();
                task.stats.push(run.stats);
                if update == chosen {
                    task.run = Some(run);
                }
                task.next += 1;
            }
            Err(e) => {
                if update == chosen {
                    self.realtime_task = None;
                    return Some(Err(e.to_string()));
                }
                task.next += 1;
            }
        }
        None
    }

    /// The comparison, when every row is fresh and written.
    #[must_use]
    pub fn comparison(&self, w: &Wanted) -> Option<Comparison> {
        if !(0..3).all(|i| self.row_fresh(i, w)) {
            return None;
        }
        let rows: Vec<CompareRow> = self.rows.iter().map(|r| r.ok().map(|t| t.row.clone())).collect::<Option<_>>()?;
        let realtime = if self.realtime_fresh(w) { self.realtime.ok()?.stats.clone() } else { Vec::new() };
        Some(Comparison {
            tol_mm: w.program.tol_mm,
            feed_mm_per_min: w.program.feed_mm_per_min,
            rows,
            realtime,
            notes: Vec::new(),
        })
    }
}

fn make_parabola() -> Result<Design, String> {
    let p = Parabola::paper_like();
    Ok(Design {
        length_mm: ArcLengthTable::new(&p, 256).length(),
        curve: DesignCurve::Parabola(p),
        title: "parabola y = x^2/40, x from -60 to 60 mm".to_owned(),
    })
}

fn crease_failed(e: &DesignError) -> String {
    format!("The scene's crease gives no design path: {e}. Change the scene, or use the parabola profile.")
}
