//! The per-period crease interpolator of seed 000 and the precise (Newton) stepper.
//!
//! One period of [`Method::Seed000`], from the centre p and contact parameters (u_i, v_i):
//!
//! 1. **Track** (eq. 3): `t = ±n1 × n2 / |n1 × n2|` (sense kept from the previous period),
//!    `p* = p + f·t`.
//! 2. **Correct** (eq. 4): with `k_i` the normal curvature of S_i along t, replace S_i by its
//!    osculating sphere (centre `o_i = q_i + n_i/k_i`); the ball is tangent to it when
//!    `|p_e − o_i| = D_i = (1 − R'k_i)/|k_i|`. Linearised at p*,
//!    `ŵ_i·δp = D_i − |p* − o_i|` with `ŵ_i = (p* − o_i)/|p* − o_i|`, and δp stays in the
//!    plane of o1, o2, p*: `(ŵ1 × ŵ2)·δp = 0`. One 3×3 solve.
//!    Written with `d_i = p* − q_i`, `h_i = d_i·n_i`, `s_i = √(1 − 2k_i h_i + k_i²|d_i|²)`:
//!    `ŵ_i ∝ w_i = (k_i d_i − n_i)/s_i` and
//!    `D_i − |p* − o_i| = sgn(k_i)·[2(h_i − R') + k_i(R'² − |d_i|²)] / [(1 − R'k_i) + s_i]`,
//!    so the signs cancel and `w_i·δp = [2(h_i − R') + k_i(R'² − |d_i|²)] / [(1 − R'k_i) + s_i]`
//!    holds for every k_i including the flat limit k_i = 0, where it reads
//!    `(p_e − q_i)·n_i = R'` (the tangent plane) — no division by k_i anywhere.
//! 3. **Re-solve the contacts** (eq. 5): `δr_i = (p_e − p_i)/(1 − k_i R')` with
//!    `p_i = q_i + R'n_i`, and `(δu_i, δv_i)` from
//!    `(r_u δu + r_v δv)·(n_i × δr_i) = 0`, `(r_u δu + r_v δv)·δr_i = |δr_i|²`.
//!
//! One 3×3 and two 2×2 linear solves; no iteration. The only addition to the paper is
//! optional and on by default ([`InterpOptions::exact_feed`]): the step p → p_e is rescaled to
//! length exactly f, so eq. (2) `|p_{K+1} − p_K| = f` holds to rounding rather than to
//! O(f²k²) (the correction δp is not perpendicular to the chord). The rescale moves p_e along
//! the chord by about f³k²/8, which changes its distance to either surface by far less than
//! a nanometre.
//!
//! [`Method::Exact`] instead puts every centre on the exact crease at distance f from the
//! previous one by Newton's method ([`super::newton`]); it is the reference the paper's
//! method is measured against and a "precise mode" in the app.

use glam::{DVec2, DVec3};

use super::newton::{self, Constraint, CreasePoint, NewtonOptions, locate_crease_point};
use super::{CreaseError, CreaseJob, EndNotReached, Location, Row, StopReason};
use crate::geom::{Domain, LocalGeometry, ParametricSurface};
use crate::tolerance;

/// Which stepper runs each period.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// Seed 000's track–correct–re-solve step (no iteration).
    #[default]
    Seed000,
    /// Newton projection onto the exact crease at distance f (the reference).
    Exact,
}

/// Settings of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpOptions {
    /// Stepper (default [`Method::Seed000`]).
    pub method: Method,
    /// Rescale each step to length exactly f (eq. 2). Default true.
    pub exact_feed: bool,
    /// Full turns of a closed crease before stopping (default 1).
    pub turns: u32,
    /// Largest correction |δp| accepted, as a fraction of f (default 0.5). Beyond it the
    /// feed per period is too long for the crease's curvature.
    pub max_correction_ratio: f64,
}

impl Default for InterpOptions {
    fn default() -> Self {
        Self { method: Method::Seed000, exact_feed: true, turns: 1, max_correction_ratio: 0.5 }
    }
}

/// What one call of [`Interpolator::step`] produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// A new period's row.
    Row(Row),
    /// The run is over (the stop is final: further calls return it again).
    Stopped(StopReason),
}

/// Centre, contact parameters, travel direction and the local geometry at the new contacts.
type ExactStep = (DVec3, [DVec2; 2], DVec3, Option<[LocalGeometry; 2]>);

/// Passing a target point: detects the period nearest to it.
#[derive(Clone, Copy, Debug)]
struct Target {
    point: DVec3,
    /// Set once the path has been farther than `2·capture` from the point.
    left: bool,
}

/// A crease interpolation in progress. Owns its job; drive it with [`Self::step`] (one
/// period per call) or [`Self::run`].
#[derive(Clone, Debug)]
pub struct Interpolator {
    job: CreaseJob,
    opts: InterpOptions,
    domains: [Domain; 2],
    start: CreasePoint,
    end: Option<Target>,
    home: Target,
    turns: u32,
    /// Last emitted row.
    row: Row,
    /// Unit travel direction of the last period.
    prev_t: DVec3,
    /// Unit sense of travel at the start (n1 × n2, or its reverse chosen by `path.direction`).
    start_sense: DVec3,
    stopped: Option<StopReason>,
    capture: f64,
    /// Local geometry at the current row's contacts when the last step already computed it
    /// (the precise stepper's final Newton evaluation).
    cached: Option<[LocalGeometry; 2]>,
    /// Geometry of the step being taken, moved to `cached` when the step is committed.
    pending: Option<[LocalGeometry; 2]>,
}

impl Interpolator {
    /// Brings `path.start` (and `path.end`) onto the crease and prepares the first period.
    ///
    /// # Errors
    /// When the start or end cannot be put on the crease (no crease near, tangential
    /// contact, a fold, a singular point) or `path.direction` is ambiguous.
    pub fn new(job: CreaseJob, opts: InterpOptions) -> Result<Self, CreaseError> {
        let start = locate_crease_point(&job, job.start, Location::Start)?;
        let end = match job.end {
            Some(e) => Some(locate_crease_point(&job, e, Location::End)?),
            None => None,
        };
        let sense = match job.direction {
            Some(d) => {
                let c = d.normalize().dot(start.tangent);
                if c.abs() < 1e-6 {
                    return Err(CreaseError::DirectionAmbiguous);
                }
                c.signum()
            }
            None => 1.0,
        };
        let capture = 2.0 * job.feed_per_period_mm + 1e-6;
        let domains = [job.surfaces[0].domain(), job.surfaces[1].domain()];
        let row = Row { k: 0, t_ms: 0.0, p: start.p, uv: start.uv };
        Ok(Self {
            opts,
            domains,
            end: end.map(|e| Target { point: e.p, left: false }),
            home: Target { point: start.p, left: false },
            turns: 0,
            row,
            prev_t: sense * start.tangent,
            start_sense: sense * start.tangent,
            stopped: None,
            capture,
            cached: None,
            pending: None,
            start,
            job,
        })
    }

    /// The job being run.
    #[must_use]
    pub fn job(&self) -> &CreaseJob {
        &self.job
    }

    /// The options in use.
    #[must_use]
    pub fn options(&self) -> &InterpOptions {
        &self.opts
    }

    /// Row 0: the start point brought onto the crease.
    #[must_use]
    pub fn first_row(&self) -> Row {
        Row { k: 0, t_ms: 0.0, p: self.start.p, uv: self.start.uv }
    }

    /// The exact crease point of `path.start`.
    #[must_use]
    pub fn start_point(&self) -> &CreasePoint {
        &self.start
    }

    /// The last row produced (row 0 before the first step).
    #[must_use]
    pub fn current(&self) -> Row {
        self.row
    }

    /// Unit direction of travel at the current row.
    #[must_use]
    pub fn direction(&self) -> DVec3 {
        self.prev_t
    }

    /// Unit sense of travel at the start: n1 × n2, or its reverse when `path.direction` asks.
    #[must_use]
    pub fn start_sense(&self) -> DVec3 {
        self.start_sense
    }

    /// Once stopped short of `path.end`: how far it was left and what to change (see
    /// [`EndNotReached`]).
    #[must_use]
    pub fn end_not_reached(&self) -> Option<EndNotReached> {
        EndNotReached::check(&self.job, &self.stopped?, self.start.p, self.start_sense, self.row.p)
    }

    /// Full turns of a closed crease completed so far.
    #[must_use]
    pub fn turns_completed(&self) -> u32 {
        self.turns
    }

    /// Why the run stopped, once it has.
    #[must_use]
    pub fn stopped(&self) -> Option<StopReason> {
        self.stopped
    }

    /// Runs one period.
    ///
    /// # Errors
    /// When the crease cannot be continued (tangential contact, fold, singular point,
    /// feed too long for the curvature); the rows produced before remain valid.
    pub fn step(&mut self) -> Result<Step, CreaseError> {
        if let Some(reason) = self.stopped {
            return Ok(Step::Stopped(reason));
        }
        if self.row.k >= self.job.max_steps {
            return Ok(self.stop(StopReason::MaxSteps));
        }
        let k = self.row.k + 1;
        let at = Location::Period { k, t_ms: k as f64 * self.job.period_ms };
        let (p_next, uv_next, t, geo_next) = match self.opts.method {
            Method::Seed000 => {
                let (p, uv, t) = self.seed000_step(at)?;
                (p, uv, t, None)
            }
            Method::Exact => self.exact_step(at)?,
        };
        // Domain check before anything is committed.
        for i in 0..2 {
            let d = self.domains[i];
            for (param, range, value) in [('u', d.u, uv_next[i].x), ('v', d.v, uv_next[i].y)] {
                if !range.contains(value) {
                    return Ok(self.stop(StopReason::LeftDomain {
                        surface: i,
                        param,
                        value: range.unit.to_file(value),
                        range: [range.unit.to_file(range.min), range.unit.to_file(range.max)],
                    }));
                }
            }
        }
        let uv_next = [self.domains[0].wrap(uv_next[0]), self.domains[1].wrap(uv_next[1])];
        // Wrapping a periodic parameter does not change the point, so the geometry holds.
        self.pending = geo_next;
        let next = Row { k, t_ms: at_time(at), p: p_next, uv: uv_next };
        let prev = self.row;

        // Passing path.end or, on a closed crease, the start again.
        if let Some(take_next) = self.end.as_mut().and_then(|end| passes(end, prev.p, next.p, self.capture)) {
            if take_next {
                self.commit(next, t);
                return Ok(self.stop_with_row(StopReason::ReachedEnd));
            }
            return Ok(self.stop(StopReason::ReachedEnd));
        }
        if let Some(take_next) = passes(&mut self.home, prev.p, next.p, self.capture) {
            self.turns += 1;
            self.home.left = false;
            if self.turns >= self.opts.turns {
                if take_next {
                    self.commit(next, t);
                    return Ok(self.stop_with_row(StopReason::Closed { turns: self.turns }));
                }
                return Ok(self.stop(StopReason::Closed { turns: self.turns }));
            }
        }
        self.commit(next, t);
        Ok(Step::Row(next))
    }

    fn commit(&mut self, row: Row, t: DVec3) {
        self.row = row;
        self.prev_t = t;
        self.cached = self.pending.take();
    }

    fn stop(&mut self, reason: StopReason) -> Step {
        self.stopped = Some(reason);
        Step::Stopped(reason)
    }

    /// Stops after emitting the row just committed: the caller gets the row now and the
    /// stop on the next call.
    fn stop_with_row(&mut self, reason: StopReason) -> Step {
        self.stopped = Some(reason);
        Step::Row(self.row)
    }

    /// Runs to the end, handing every row (row 0 first) to `sink`.
    ///
    /// # Errors
    /// As [`Self::step`]; rows before the error have been handed out.
    pub fn run(&mut self, mut sink: impl FnMut(&Row)) -> Result<StopReason, CreaseError> {
        if self.row.k == 0 && self.stopped.is_none() {
            sink(&self.row);
        }
        loop {
            match self.step()? {
                Step::Row(r) => sink(&r),
                Step::Stopped(reason) => return Ok(reason),
            }
        }
    }

    /// Evaluates both surfaces at the current contacts: local geometry, the oriented unit
    /// crease tangent and the normal curvatures along it.
    fn local(&self, at: Location) -> Result<([LocalGeometry; 2], DVec3), CreaseError> {
        let [g1, g2] = match self.cached {
            Some(geo) => geo,
            None => {
                let mut geo = [None, None];
                for i in 0..2 {
                    let d = self.job.surfaces[i].derivatives_at(self.row.uv[i]);
                    geo[i] = Some(LocalGeometry::try_new(d).ok_or(CreaseError::Singular { at, surface: i })?);
                }
                let [Some(g1), Some(g2)] = geo else {
                    return Err(CreaseError::Singular { at, surface: 0 });
                };
                [g1, g2]
            }
        };
        let cross = g1.d.normal.cross(g2.d.normal);
        let sin = cross.length();
        if sin < tolerance::MIN_CREASE_ANGLE_RAD.sin() || !sin.is_finite() {
            return Err(CreaseError::Tangential {
                at,
                angle_deg: sin.min(1.0).asin().to_degrees(),
                min_deg: tolerance::MIN_CREASE_ANGLE_RAD.to_degrees(),
            });
        }
        let mut t = cross / sin;
        if t.dot(self.prev_t) < 0.0 {
            t = -t;
        }
        Ok(([g1, g2], t))
    }

    fn fold_check(&self, geo: &[LocalGeometry; 2], at: Location) -> Result<(), CreaseError> {
        let r = self.job.r_eff_mm;
        for (i, g) in geo.iter().enumerate() {
            if !g.offset_is_regular(r) {
                let (k_max, _) = g.principal_curvatures();
                return Err(CreaseError::Fold { at, surface: i, radius_mm: 1.0 / k_max, r_eff_mm: r });
            }
        }
        Ok(())
    }

    /// Seed 000, eqs. (3)–(5).
    fn seed000_step(&self, at: Location) -> Result<(DVec3, [DVec2; 2], DVec3), CreaseError> {
        let (geo, t) = self.local(at)?;
        self.fold_check(&geo, at)?;
        let r = self.job.r_eff_mm;
        let f = self.job.feed_per_period_mm;
        let p = self.row.p;
        // 1. Track (3).
        let p_star = p + f * t;
        // 2. Correct (4), in the k-regular form of the module docs.
        let mut k = [0.0; 2];
        let mut w = [DVec3::ZERO; 2];
        let mut c = [0.0; 2];
        for i in 0..2 {
            let (q, n) = (geo[i].d.point, geo[i].d.normal);
            let ki = geo[i].normal_curvature(t);
            let d = p_star - q;
            let h = d.dot(n);
            let dd = d.length_squared();
            let s = (1.0 - 2.0 * ki * h + ki * ki * dd).max(0.0).sqrt();
            k[i] = ki;
            w[i] = (ki * d - n) / s;
            c[i] = (2.0 * (h - r) + ki * (r * r - dd)) / ((1.0 - r * ki) + s);
        }
        // The rows w1, w2 are unit vectors (|k d − n| = s by the definition of s), so with
        // m = w1 × w2 the system's inverse has columns w2 × m, m × w1, m over det = |m|².
        let m = w[0].cross(w[1]);
        let det = m.length_squared();
        if !(det > 1e-18) {
            return Err(CreaseError::Tangential {
                at,
                angle_deg: det.sqrt().min(1.0).asin().to_degrees(),
                min_deg: tolerance::MIN_CREASE_ANGLE_RAD.to_degrees(),
            });
        }
        let dp = (c[0] * w[1].cross(m) + c[1] * m.cross(w[0])) / det;
        let max_dp = self.opts.max_correction_ratio * f + 1e-9;
        if !(dp.length_squared() <= max_dp * max_dp) {
            return Err(CreaseError::StepTooLong { at, feed_mm: f, correction_mm: dp.length() });
        }
        let mut p_e = p_star + dp;
        if self.opts.exact_feed {
            p_e = p + f * (p_e - p).normalize();
        }
        // 3. Re-solve the contact parameters (5).
        let mut uv = self.row.uv;
        for i in 0..2 {
            let (q, n) = (geo[i].d.point, geo[i].d.normal);
            let p_i = q + r * n;
            let dr = (p_e - p_i) / (1.0 - k[i] * r);
            let len = dr.length();
            if len > 0.0 {
                let e = dr / len;
                let Some(duv) = crate::geom::solve_tangent(&geo[i].d, n.cross(e), 0.0, e, len) else {
                    return Err(CreaseError::Singular { at, surface: i });
                };
                uv[i] += duv;
            }
        }
        if !(p_e.is_finite() && uv[0].is_finite() && uv[1].is_finite()) {
            return Err(CreaseError::StepTooLong { at, feed_mm: f, correction_mm: f64::INFINITY });
        }
        Ok((p_e, uv, t))
    }

    /// The precise stepper: predictor along the tangent, Newton onto the exact crease at
    /// distance f.
    fn exact_step(&self, at: Location) -> Result<ExactStep, CreaseError> {
        let (geo, t) = self.local(at)?;
        self.fold_check(&geo, at)?;
        let r = self.job.r_eff_mm;
        let f = self.job.feed_per_period_mm;
        let mut guess = self.row.uv;
        for i in 0..2 {
            let ki = geo[i].normal_curvature(t);
            guess[i] += geo[i].tangent_coords(f * t) / (1.0 - ki * r);
        }
        let (cp, geo_next) = newton::solve_with_geometry(
            &self.job,
            guess,
            Constraint::AtDistance { from: self.row.p, dist: f },
            NewtonOptions { max_step_mm: f, stay_in_domain: false, ..NewtonOptions::default() },
        )
        .map_err(|e| e.into_error(at, &self.job))?;
        if (cp.p - self.row.p).dot(t) <= 0.0 {
            return Err(CreaseError::NewtonFailed { at, detail: "the step turned back along the crease".into() });
        }
        Ok((cp.p, cp.uv, t, Some(geo_next)))
    }
}

fn at_time(at: Location) -> f64 {
    match at {
        Location::Period { t_ms, .. } => t_ms,
        _ => 0.0,
    }
}

/// Whether the step `a → b` passes the target (crosses its normal plane while within the
/// capture distance, after having been away). `Some(true)` if `b` is the nearer of the two.
fn passes(target: &mut Target, a: DVec3, b: DVec3, capture: f64) -> Option<bool> {
    // Squared distances: this runs every period.
    let db = (b - target.point).length_squared();
    if !target.left {
        if db > 4.0 * capture * capture {
            target.left = true;
        }
        return None;
    }
    let da = (a - target.point).length_squared();
    if da.min(db) > capture * capture {
        return None;
    }
    let dir = b - a;
    let ga = (a - target.point).dot(dir);
    let gb = (b - target.point).dot(dir);
    (ga <= 0.0 && gb > 0.0).then_some(db < da)
}

/// Rows and outcome of a whole run.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// All rows produced, row 0 first (empty if the start failed).
    pub rows: Vec<Row>,
    /// Why it stopped, or the error that stopped it.
    pub outcome: Result<StopReason, CreaseError>,
    /// Set when the run stopped short of `path.end` ([`Interpolator::end_not_reached`]).
    pub end_not_reached: Option<EndNotReached>,
}

/// Runs a job from start to stop, collecting every row.
#[must_use]
pub fn run_to_end(job: CreaseJob, opts: InterpOptions) -> RunResult {
    let mut rows = Vec::new();
    let mut end_not_reached = None;
    let outcome = Interpolator::new(job, opts).and_then(|mut it| {
        let reason = it.run(|r| rows.push(*r))?;
        end_not_reached = it.end_not_reached();
        Ok(reason)
    });
    RunResult { rows, outcome, end_not_reached }
}
