//! The fillet tab's work: a finishing preset with the user's cutter, scallop height,
//! tolerance and strategy, its iso-scallop paths built one path per step by
//! `fillet::IsoScallopSteps` within a time budget per frame, and the comparison table built
//! one row per frame on request.

use web_time::{Duration, Instant};

use crate::fillet::{
    FinishOptions, IsoScallopSteps, Layout, PartSamples, PathSet, Stats, Strategy, iso_parametric, iso_scallop,
};
use crate::geom::{Cutter, Surface};
use crate::scene::finish::{FINISH_PRESETS, FinishScene};

/// Range of the cutter radius R slider (mm).
pub const RADIUS_RANGE_MM: (f64, f64) = (0.5, 25.0);
/// Range of the corner radius r slider (mm); r is also kept ≤ R.
pub const CORNER_RANGE_MM: (f64, f64) = (0.0, 25.0);
/// Range of the scallop height h slider (µm).
pub const SCALLOP_RANGE_UM: (f64, f64) = (1.0, 200.0);
/// Range of the chord tolerance E slider (mm).
pub const TOLERANCE_RANGE_MM: (f64, f64) = (0.001, 0.1);

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

    /// The core's strategy.
    #[must_use]
    pub fn strategy(self) -> Strategy {
        match self {
            Self::Matched => Strategy::Matched,
            Self::Lead5 => Strategy::FixedLead { lead_rad: 5f64.to_radians() },
            Self::Lead10 => Strategy::FixedLead { lead_rad: 10f64.to_radians() },
            Self::Principal => Strategy::PrincipalAxis,
            Self::Ball => Strategy::Ball,
        }
    }

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
            },
            None => Self {
                preset,
                radius_mm: 5.0,
                corner_mm: 1.0,
                scallop_um: 10.0,
                tol_mm: 0.01,
                strategy: StrategyChoice::Matched,
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
        s.finish.scallop = self.scallop_um * 1e-3;
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
        Ok(s)
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
    pub stats: Result<Stats, String>,
    /// Wall time of the core for this row (ms).
    pub ms: f64,
}

/// A job for one set of settings.
pub struct Job {
    /// The settings it was made for.
    pub settings: Settings,
    /// The surface.
    pub surface: Surface,
    /// The cutter.
    pub cutter: Cutter,
    /// The core's strategy.
    pub strategy: Strategy,
    /// The core's options.
    pub options: FinishOptions,
    /// The scene's machine (the default table A/C when the preset has none): what the
    /// simulation's five-axis program runs on.
    pub machine: crate::fiveaxis::Machine,
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
    /// The comparison rows computed so far (when requested).
    pub table: Vec<Row>,
    /// Whether the table was requested.
    pub table_requested: bool,
}

impl Job {
    /// Builds the job's inputs (no paths yet).
    ///
    /// # Errors
    /// The scene's message for a refused value.
    pub fn new(settings: Settings) -> Result<Self, String> {
        let scene = settings.scene()?;
        let job = scene.job().map_err(|e| e.to_string())?;
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        Ok(Self {
            settings,
            surface: job.surface,
            cutter: job.cutter,
            strategy: job.strategy,
            options: job.options,
            machine: job.machine,
            part,
            steps: None,
            result: None,
            error: None,
            core_ms: 0.0,
            longest_step_ms: 0.0,
            table: Vec::new(),
            table_requested: false,
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
        self.table_requested && self.error.is_none() && self.table.len() < 2 * StrategyChoice::ALL.len()
    }

    /// Progress of the main paths, 0 … 1.
    #[must_use]
    pub fn progress(&self) -> f64 {
        if self.result.is_some() || self.error.is_some() {
            1.0
        } else {
            self.steps.as_ref().map_or(0.0, |s| s.progress(&self.surface))
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

    /// Builds paths (one per step) until the budget is spent; then, if requested, one
    /// comparison row (a whole core run, which may take longer than the budget).
    pub fn advance(&mut self, budget: Duration) {
        let start = Instant::now();
        while self.computing_paths() && start.elapsed() < budget {
            let t = Instant::now();
            let r = match self.steps.as_mut() {
                None => IsoScallopSteps::start(&self.surface, &self.cutter, self.strategy, &self.options, &self.part)
                    .map(|s| {
                        self.steps = Some(s);
                        false
                    }),
                Some(s) => s.step(&self.surface, &self.cutter, &self.options, &self.part),
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
        if self.computing_paths() || !self.computing_table() || start.elapsed() >= budget {
            return;
        }
        let k = self.table.len();
        let strategy = StrategyChoice::ALL[k / 2];
        let layout = if k.is_multiple_of(2) { Layout::IsoScallop } else { Layout::IsoParametric };
        let feed = self.options.feed_mm_per_min;
        // The main result is the iso-scallop row of its own strategy.
        if layout == Layout::IsoScallop
            && strategy.strategy() == self.strategy
            && let Some(r) = &self.result
        {
            self.table.push(Row { strategy, layout, stats: Ok(r.stats(feed)), ms: self.core_ms });
            return;
        }
        let t = Instant::now();
        let (s, c, o, p) = (&self.surface, &self.cutter, &self.options, &self.part);
        let res = match layout {
            Layout::IsoScallop => iso_scallop(s, c, strategy.strategy(), o, p),
            Layout::IsoParametric => iso_parametric(s, c, strategy.strategy(), o, p),
        };
        let ms = t.elapsed().as_secs_f64() * 1e3;
        self.table.push(Row { strategy, layout, stats: res.map(|r| r.stats(feed)).map_err(|e| e.to_string()), ms });
    }
}
