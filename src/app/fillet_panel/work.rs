//! The fillet tab's work: a finishing preset with the user's cutter, scallop height,
//! tolerance and strategy, its iso-scallop paths built one path per step by
//! `fillet::IsoScallopSteps` within a time budget per frame, and the comparison table on
//! request: each row (a whole core run, 1–1.5 s natively) a background job
//! (`jobs::fillet_row`, run by `app::jobs`: a thread natively, a Web Worker in the browser),
//! [`TABLE_JOBS_AT_ONCE`] at a time at most (one on a 2-core machine: the page keeps a core),
//! rows filled in as they finish. Dropping the work
//! (the settings changed) drops its jobs, which cancels them.

use web_time::{Duration, Instant};

use crate::app::jobs::{Job as BackgroundJob, Poll};
use crate::fillet::{Edge, FinishJob, IsoScallopSteps, Layout, PartSamples, PathSet, Stats};
use crate::jobs::JobError;
use crate::jobs::fillet_row::{FilletRow, Request as RowRequest};
use crate::scene::finish::{FINISH_PRESETS, FinishScene, StartSpec};

/// Range of the cutter radius R slider (mm).
pub const RADIUS_RANGE_MM: (f64, f64) = (0.5, 25.0);
/// Range of the corner radius r slider (mm); r is also kept ≤ R.
pub const CORNER_RANGE_MM: (f64, f64) = (0.0, 25.0);
/// Range of the scallop height h slider (µm).
pub const SCALLOP_RANGE_UM: (f64, f64) = (1.0, 200.0);
/// Range of the chord tolerance E slider (mm).
pub const TOLERANCE_RANGE_MM: (f64, f64) = (0.0001, 0.1);
/// Most rows of the comparison table computed at once (each in its own thread or Web
/// Worker); fewer on a machine with fewer spare cores (`app::jobs::spare_cores`).
pub const TABLE_JOBS_AT_ONCE: usize = 2;
/// Rows of the comparison table: every strategy with iso-scallop and iso-parametric paths.
pub const TABLE_ROWS: usize = 2 * StrategyChoice::ALL.len();

/// Most points of a start curve picked in the view (a click each).
pub const MAX_PICKS: usize = 16;

/// Where the paths start (the scene's `finish.start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StartChoice {
    /// The scene's default: the edge b = b_min of the chosen direction.
    First,
    /// An edge.
    Edge(Edge),
    /// The curve through the points picked in the view.
    Picked,
}

impl StartChoice {
    /// All, in the order of the menu.
    pub const ALL: [Self; 6] = [
        Self::First,
        Self::Edge(Edge::U0),
        Self::Edge(Edge::U1),
        Self::Edge(Edge::V0),
        Self::Edge(Edge::V1),
        Self::Picked,
    ];

    /// The option value (`set_option("start", …)`).
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::First => "first",
            Self::Edge(e) => e.name(),
            Self::Picked => "picked",
        }
    }

    /// Shown in the UI.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::First => "first edge of the feed direction",
            Self::Edge(Edge::U0) => "edge u = u min (u0)",
            Self::Edge(Edge::U1) => "edge u = u max (u1)",
            Self::Edge(Edge::V0) => "edge v = v min (v0)",
            Self::Edge(Edge::V1) => "edge v = v max (v1)",
            Self::Picked => "picked curve",
        }
    }

    /// From an option value.
    #[must_use]
    pub fn from_key(key: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.key() == key)
    }
}

/// The orientation strategies offered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrategyChoice {
    /// Curvature matched.
    Matched,
    /// Fixed lead 5°.
    Lead5,
    /// Fixed lead 10°.
    Lead10,
    /// Principal-axis method.
    Principal,
    /// A ball end mill of radius R.
    Ball,
}

impl StrategyChoice {
    /// All, in the order of the comparison table.
    pub const ALL: [Self; 5] = [Self::Matched, Self::Lead5, Self::Lead10, Self::Principal, Self::Ball];

    /// The option value (`set_option("strategy", …)`).
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::Matched => "matched",
            Self::Lead5 => "lead5",
            Self::Lead10 => "lead10",
            Self::Principal => "principal",
            Self::Ball => "ball",
        }
    }

    /// Shown in the UI.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Matched => "curvature matched",
            Self::Lead5 => "fixed lead 5°",
            Self::Lead10 => "fixed lead 10°",
            Self::Principal => "principal axis",
            Self::Ball => "ball end mill (r = R)",
        }
    }

    /// From an option value.
    #[must_use]
    pub fn from_key(key: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.key() == key)
    }

    /// The nearest choice for a scene's strategy and lead (degrees).
    fn of_scene(strategy: &str, lead_deg: Option<f64>) -> Self {
        match strategy {
            "principal" => Self::Principal,
            "ball" => Self::Ball,
            "fixed-lead" if lead_deg.unwrap_or(5.0) > 7.5 => Self::Lead10,
            "fixed-lead" => Self::Lead5,
            _ => Self::Matched,
        }
    }
}

/// The user's choices (mm, µm where named).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Index into `FINISH_PRESETS`.
    pub preset: usize,
    /// Cutter radius R (mm).
    pub radius_mm: f64,
    /// Corner radius r (mm).
    pub corner_mm: f64,
    /// Scallop height h (µm).
    pub scallop_um: f64,
    /// Chord tolerance E (mm).
    pub tol_mm: f64,
    /// Orientation.
    pub strategy: StrategyChoice,
    /// Where the paths start.
    pub start: StartChoice,
    /// The picked start curve's points, surface parameters in file units (degrees for
    /// angles); the first `n_picks` are used.
    pub picks: [[f64; 2]; MAX_PICKS],
    /// How many points are picked.
    pub n_picks: usize,
}

impl Settings {
    /// A preset's own values (the first preset when the index is out of range or the
    /// preset does not parse, which the tests exclude).
    #[must_use]
    pub fn of_preset(preset: usize) -> Self {
        let preset = preset.min(FINISH_PRESETS.len().saturating_sub(1));
        match FINISH_PRESETS.get(preset).and_then(|p| FinishScene::from_json(p.json).ok()) {
            Some(s) => Self {
                preset,
                radius_mm: s.finish.cutter.radius,
                corner_mm: s.finish.cutter.corner_radius,
                scallop_um: s.finish.scallop * 1e3,
                tol_mm: s.finish.tolerance,
                strategy: StrategyChoice::of_scene(&s.finish.strategy, s.finish.lead),
                start: match &s.finish.start {
                    Some(StartSpec::Boundary(name)) => {
                        Edge::from_name(name).map_or(StartChoice::First, StartChoice::Edge)
                    }
                    _ => StartChoice::First,
                },
                picks: [[0.0; 2]; MAX_PICKS],
                n_picks: 0,
            },
            None => Self {
                preset,
                radius_mm: 5.0,
                corner_mm: 1.0,
                scallop_um: 10.0,
                tol_mm: 0.01,
                strategy: StrategyChoice::Matched,
                start: StartChoice::First,
                picks: [[0.0; 2]; MAX_PICKS],
                n_picks: 0,
            },
        }
    }

    /// The preset's scene with these settings written into it (what the command line would
    /// read from an edited file).
    ///
    /// # Errors
    /// The preset's name for an unknown index, or the scene's own message for a value it
    /// refuses (e.g. a shank narrower than the cutter).
    pub fn scene(&self) -> Result<FinishScene, String> {
        let p = FINISH_PRESETS.get(self.preset).ok_or_else(|| format!("no finishing preset {}", self.preset))?;
        let mut s = FinishScene::from_json(p.json).map_err(|e| e.to_string())?;
        s.finish.cutter.radius = self.radius_mm;
        s.finish.cutter.corner_radius = self.corner_mm;
        s.finish.scallop = self.scallop_um * crate::numerics::units::MM_PER_UM;
        s.finish.tolerance = self.tol_mm;
        let (name, lead) = match self.strategy {
            StrategyChoice::Matched => ("matched", None),
            StrategyChoice::Lead5 => ("fixed-lead", Some(5.0)),
            StrategyChoice::Lead10 => ("fixed-lead", Some(10.0)),
            StrategyChoice::Principal => ("principal", None),
            StrategyChoice::Ball => ("ball", None),
        };
        name.clone_into(&mut s.finish.strategy);
        s.finish.lead = lead;
        s.finish.start = match self.start {
            StartChoice::First => None,
            StartChoice::Edge(e) => Some(StartSpec::Boundary(e.name().to_owned())),
            StartChoice::Picked => Some(StartSpec::Curve(self.picked().to_vec())),
        };
        Ok(s)
    }

    /// The picked points (file units).
    #[must_use]
    pub fn picked(&self) -> &[[f64; 2]] {
        &self.picks[..self.n_picks.min(MAX_PICKS)]
    }

    /// Adds a picked point (file units); false when [`MAX_PICKS`] are picked already.
    pub fn pick(&mut self, uv_file: [f64; 2]) -> bool {
        if self.n_picks >= MAX_PICKS {
            return false;
        }
        self.picks[self.n_picks] = uv_file;
        self.n_picks += 1;
        true
    }

    /// Forgets the picked points.
    pub fn clear_picks(&mut self) {
        self.picks = [[0.0; 2]; MAX_PICKS];
        self.n_picks = 0;
    }

    /// Whether the paths wait for more picked points (start from a picked curve with fewer
    /// than 2).
    #[must_use]
    pub fn waiting_for_picks(&self) -> bool {
        self.start == StartChoice::Picked && self.n_picks < 2
    }
}

/// One row of the comparison table.
#[derive(Clone, Debug)]
pub struct Row {
    /// Strategy.
    pub strategy: StrategyChoice,
    /// Layout.
    pub layout: Layout,
    /// Numbers or the core's message.
    pub stats: Result<Stats, JobError>,
    /// Wall time of this row (ms): from its job's start to its output (in a browser the
    /// worker's start included), or the main paths' core time for the row they are.
    pub ms: f64,
}

/// The strategy and layout of table row `k` (strategies in [`StrategyChoice::ALL`] order,
/// iso-scallop before iso-parametric).
#[must_use]
pub fn table_row(k: usize) -> (StrategyChoice, Layout) {
    let strategy = StrategyChoice::ALL[(k / 2).min(StrategyChoice::ALL.len() - 1)];
    (strategy, if k.is_multiple_of(2) { Layout::IsoScallop } else { Layout::IsoParametric })
}

/// A job for one set of settings.
pub struct Job {
    /// The settings it was made for.
    pub settings: Settings,
    /// The scene's finishing job (surface, cutter, strategy, options, machine, start; the
    /// machine the default table A/C when the preset has none: what the simulation's
    /// five-axis program runs on).
    pub finish: FinishJob,
    part: PartSamples,
    steps: Option<IsoScallopSteps>,
    /// The finished paths.
    pub result: Option<PathSet>,
    /// The core's message when it failed.
    pub error: Option<String>,
    /// Core time spent on the paths so far (ms).
    pub core_ms: f64,
    /// Longest single step (ms).
    pub longest_step_ms: f64,
    /// The comparison rows by index ([`table_row`]), each once it has arrived.
    pub table: Vec<Option<Row>>,
    /// Whether the table was requested.
    pub table_requested: bool,
    /// The rows' jobs under way (row index, job).
    table_jobs: Vec<(usize, BackgroundJob<FilletRow>)>,
    /// Next row to start.
    next_row: usize,
    /// Whether every row's job so far ran off the UI thread.
    rows_background: bool,
}

impl Job {
    /// Builds the job's inputs (no paths yet).
    ///
    /// # Errors
    /// The scene's message for a refused value.
    pub fn new(settings: Settings) -> Result<Self, String> {
        // Waiting for picks, the surface is shown (to pick on) and no paths are built.
        let waiting = settings.waiting_for_picks();
        let scene =
            if waiting { Settings { start: StartChoice::First, ..settings }.scene()? } else { settings.scene()? };
        let job = scene.job().map_err(|e| e.to_string())?;
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        let error = waiting.then(|| {
            format!(
                "Start from a picked curve: click 2 or more points on the surface (click mode \"add a start-curve point\"); {} so far",
                settings.n_picks
            )
        });
        Ok(Self {
            settings,
            finish: job,
            part,
            steps: None,
            result: None,
            error,
            core_ms: 0.0,
            longest_step_ms: 0.0,
            table: vec![None; TABLE_ROWS],
            table_requested: false,
            table_jobs: Vec::new(),
            next_row: 0,
            rows_background: true,
        })
    }

    /// Whether the main paths are still being built.
    #[must_use]
    pub fn computing_paths(&self) -> bool {
        self.result.is_none() && self.error.is_none()
    }

    /// Whether the table is being built.
    #[must_use]
    pub fn computing_table(&self) -> bool {
        self.table_requested && self.error.is_none() && self.rows_done() < TABLE_ROWS
    }

    /// Rows of the table arrived so far.
    #[must_use]
    pub fn rows_done(&self) -> usize {
        self.table.iter().filter(|r| r.is_some()).count()
    }

    /// Rows whose job runs off the UI thread (false: in a browser without a worker).
    #[must_use]
    pub fn rows_in_background(&self) -> bool {
        self.rows_background && self.table_jobs.iter().all(|(_, j)| j.ran_in_background())
    }

    /// Progress of the main paths, 0 … 1.
    #[must_use]
    pub fn progress(&self) -> f64 {
        if self.result.is_some() || self.error.is_some() {
            1.0
        } else {
            self.steps.as_ref().map_or(0.0, |s| s.progress(&self.finish.surface))
        }
    }

    /// Paths built so far.
    #[must_use]
    pub fn paths_so_far(&self) -> &[crate::fillet::ToolPath] {
        match (&self.result, &self.steps) {
            (Some(r), _) => &r.paths,
            (None, Some(s)) => s.paths(),
            _ => &[],
        }
    }

    /// Builds paths (one per step) until the budget is spent, then looks after the table's
    /// jobs (starts rows, takes the finished ones).
    pub fn advance(&mut self, budget: Duration) {
        let start = Instant::now();
        while self.computing_paths() && start.elapsed() < budget {
            let t = Instant::now();
            let setup = self.finish.setup(&self.part);
            let r = match self.steps.as_mut() {
                None => IsoScallopSteps::start(&setup).map(|s| {
                    self.steps = Some(s);
                    false
                }),
                Some(s) => s.step(&setup),
            };
            let ms = t.elapsed().as_secs_f64() * 1e3;
            self.core_ms += ms;
            self.longest_step_ms = self.longest_step_ms.max(ms);
            match r {
                Err(e) => self.error = Some(e.to_string()),
                Ok(true) => self.result = self.steps.take().map(IsoScallopSteps::finish),
                Ok(false) => {}
            }
        }
        if self.computing_table() {
            self.advance_table();
        }
    }

    /// Takes the rows that finished and starts the next ones, [`TABLE_JOBS_AT_ONCE`] at a
    /// time. The main paths' own row (iso-scallop with the chosen strategy) is their result,
    /// taken when they are done.
    fn advance_table(&mut self) {
        let feed = self.finish.options.feed_mm_per_min;
        let mut k = 0;
        while k < self.table_jobs.len() {
            let (row, job) = &mut self.table_jobs[k];
            if let Poll::Done(stats) = job.poll() {
                self.rows_background &= job.ran_in_background();
                let (strategy, layout) = table_row(*row);
                let ms = job.elapsed().as_secs_f64() * 1e3;
                self.table[*row] = Some(Row { strategy, layout, stats, ms });
                self.table_jobs.swap_remove(k);
            } else {
                k += 1;
            }
        }
        let own = (0..TABLE_ROWS).find(|&k| {
            let (s, l) = table_row(k);
            l == Layout::IsoScallop && s == self.settings.strategy
        });
        if let (Some(k), Some(r)) = (own, &self.result)
            && self.table[k].is_none()
        {
            let (strategy, layout) = table_row(k);
            self.table[k] = Some(Row { strategy, layout, stats: Ok(r.stats(feed)), ms: self.core_ms });
        }
        let at_once = TABLE_JOBS_AT_ONCE.min(crate::app::jobs::spare_cores());
        while self.table_jobs.len() < at_once && self.next_row < TABLE_ROWS {
            let k = self.next_row;
            self.next_row += 1;
            if Some(k) == own || self.table[k].is_some() {
                continue;
            }
            let (strategy, layout) = table_row(k);
            let settings = Settings { strategy, ..self.settings };
            match settings.scene() {
                Ok(scene) => self.table_jobs.push((k, BackgroundJob::start(RowRequest { scene, layout }))),
                Err(e) => self.table[k] = Some(Row { strategy, layout, stats: Err(JobError::Failed(e)), ms: 0.0 }),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slider clamps what it shows: a preset value outside its range would be changed
    /// silently the first time the slider is drawn (the presets' E = 0.0005 mm became 0.001
    /// mm with a range starting at 0.001), and the tab would no longer compute the preset.
    #[test]
    fn every_presets_values_lie_in_their_sliders_ranges() {
        let inside = |v: f64, (lo, hi): (f64, f64)| lo <= v && v <= hi;
        for k in 0..FINISH_PRESETS.len() {
            let s = Settings::of_preset(k);
            let id = FINISH_PRESETS[k].id;
            assert!(inside(s.radius_mm, RADIUS_RANGE_MM), "{id}: R {} outside {RADIUS_RANGE_MM:?}", s.radius_mm);
            assert!(inside(s.corner_mm, CORNER_RANGE_MM), "{id}: r {} outside {CORNER_RANGE_MM:?}", s.corner_mm);
            assert!(inside(s.scallop_um, SCALLOP_RANGE_UM), "{id}: h {} µm outside {SCALLOP_RANGE_UM:?}", s.scallop_um);
            assert!(inside(s.tol_mm, TOLERANCE_RANGE_MM), "{id}: E {} outside {TOLERANCE_RANGE_MM:?}", s.tol_mm);
        }
    }
}
