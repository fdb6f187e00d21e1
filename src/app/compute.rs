//! Incremental computation of the crease path within a per-frame time budget, so sliders
//! stay live and long paths show progress instead of freezing the page.

use glam::DVec3;
use web_time::{Duration, Instant};

use crate::crease::{
    CreaseError, CreaseJob, Diagnostics, EndNotReached, InterpOptions, Interpolator, Row, Step, StopReason,
    crease_deviation, diagnose,
};
use crate::scene::{Scene, SceneError};

/// Periods stepped between two clock readings.
const BATCH: usize = 512;

/// Everything the views show about one period.
#[derive(Clone, Copy, Debug)]
pub struct Period {
    /// The interpolator's row.
    pub row: Row,
    /// Measured errors and the paper's estimates.
    pub diag: Option<Diagnostics>,
    /// Nearest point of the exact crease (mm), if Newton converged there.
    pub exact: Option<DVec3>,
}

/// A path being computed.
pub struct Computation {
    /// The job of the current scene (`None` if the scene failed to build).
    pub job: Option<CreaseJob>,
    interp: Option<Interpolator>,
    /// Periods computed so far, row 0 first.
    pub periods: Vec<Period>,
    /// How the run ended (`None` while it runs).
    pub outcome: Option<Result<StopReason, CreaseError>>,
    /// Seconds spent in the interpolator's steps only.
    pub step_seconds: f64,
    /// Seconds spent measuring errors (foot points, exact crease).
    pub measure_seconds: f64,
    /// Bumped on every restart; views compare it to know when to rebuild.
    pub generation: u64,
    /// When this run started (wall clock, for "computed in …").
    started: Instant,
    /// Wall time from start to finish (s).
    pub wall_seconds: f64,
    /// Running maxima over the periods so far (kept as they arrive: O(1) per frame).
    worst_e: [f64; 2],
    worst_b16: [Option<f64>; 2],
    /// Path length so far (mm).
    pub length_mm: f64,
}

impl Default for Computation {
    fn default() -> Self {
        Self {
            job: None,
            interp: None,
            periods: Vec::new(),
            outcome: None,
            step_seconds: 0.0,
            measure_seconds: 0.0,
            generation: 0,
            started: Instant::now(),
            wall_seconds: 0.0,
            worst_e: [0.0; 2],
            worst_b16: [Some(0.0); 2],
            length_mm: 0.0,
        }
    }
}

impl Computation {
    /// Starts over for a scene. A scene error is returned (and nothing computed); a crease
    /// that cannot be started ends the run at once with its error in `outcome`.
    pub fn restart(&mut self, scene: &Scene, opts: InterpOptions) -> Result<(), SceneError> {
        self.generation += 1;
        self.periods.clear();
        self.outcome = None;
        self.interp = None;
        self.step_seconds = 0.0;
        self.measure_seconds = 0.0;
        self.wall_seconds = 0.0;
        self.worst_e = [0.0; 2];
        self.worst_b16 = [Some(0.0); 2];
        self.length_mm = 0.0;
        self.started = Instant::now();
        let job = match CreaseJob::from_scene(scene) {
            Ok(j) => j,
            Err(e) => {
                self.job = None;
                return Err(e);
            }
        };
        let t0 = Instant::now();
        match Interpolator::new(job.clone(), opts) {
            Ok(it) => {
                self.step_seconds += t0.elapsed().as_secs_f64();
                let row = it.first_row();
                self.push(&job, row);
                self.interp = Some(it);
            }
            Err(e) => self.outcome = Some(Err(e)),
        }
        self.job = Some(job);
        Ok(())
    }

    fn push(&mut self, job: &CreaseJob, row: Row) {
        let t = Instant::now();
        self.push_untimed(job, row);
        self.measure_seconds += t.elapsed().as_secs_f64();
    }

    fn push_untimed(&mut self, job: &CreaseJob, row: Row) {
        let diag = diagnose(job, &row);
        let exact = crease_deviation(job, row.p, row.uv).map(|(_, cp)| cp.p);
        if let Some(d) = &diag {
            for i in 0..2 {
                self.worst_e[i] = self.worst_e[i].max(d.measured[i].abs());
                self.worst_b16[i] = match (self.worst_b16[i], d.est16[i]) {
                    (Some(x), Some(y)) => Some(x.max(y)),
                    _ => None,
                };
            }
        }
        if let Some(last) = self.periods.last() {
            self.length_mm += (row.p - last.row.p).length();
        }
        self.periods.push(Period { row, diag, exact });
    }

    /// Unit sense of travel at the start of the present run.
    #[must_use]
    pub fn start_sense(&self) -> Option<DVec3> {
        self.interp.as_ref().map(Interpolator::start_sense)
    }

    /// Once the run stopped short of `path.end`: the note saying what to change.
    #[must_use]
    pub fn end_not_reached(&self) -> Option<EndNotReached> {
        self.interp.as_ref()?.end_not_reached()
    }

    /// Whether the run is still going.
    #[must_use]
    pub fn running(&self) -> bool {
        self.outcome.is_none() && self.interp.is_some()
    }

    /// Advances for at most `budget` of wall time. Returns true if periods were added.
    pub fn advance(&mut self, budget: Duration) -> bool {
        let Some(job) = self.job.clone() else {
            return false;
        };
        let before = self.periods.len();
        let t_end = Instant::now() + budget;
        'outer: while self.outcome.is_none() {
            let Some(it) = self.interp.as_mut() else {
                break;
            };
            // Step a batch, then measure it: the timings stay separate. Batches are long
            // enough (~0.3 ms) for browsers' coarse timers (0.1 ms) to average out.
            let t = Instant::now();
            let mut batch = Vec::with_capacity(BATCH);
            for _ in 0..BATCH {
                match it.step() {
                    Ok(Step::Row(r)) => batch.push(r),
                    Ok(Step::Stopped(reason)) => {
                        self.outcome = Some(Ok(reason));
                        break;
                    }
                    Err(e) => {
                        self.outcome = Some(Err(e));
                        break;
                    }
                }
            }
            self.step_seconds += t.elapsed().as_secs_f64();
            let t = Instant::now();
            for r in batch {
                self.push_untimed(&job, r);
            }
            self.measure_seconds += t.elapsed().as_secs_f64();
            if Instant::now() >= t_end {
                break 'outer;
            }
        }
        if self.outcome.is_some() && self.wall_seconds == 0.0 {
            self.wall_seconds = self.started.elapsed().as_secs_f64();
        }
        self.periods.len() > before
    }

    /// Mean interpolator time per period (µs), once there are periods.
    #[must_use]
    pub fn us_per_period(&self) -> Option<f64> {
        let n = self.periods.len().saturating_sub(1);
        (n > 0).then(|| self.step_seconds * 1e6 / n as f64)
    }

    /// Worst |e_i| over the path (mm) and worst bound (16) (`None` where it does not apply).
    #[must_use]
    pub fn worst(&self) -> ([f64; 2], [Option<f64>; 2]) {
        (self.worst_e, self.worst_b16)
    }
}
