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
use crate::geom::{Domain, LocalGeometry, ParametricSurface, SurfaceDerivs};
use crate::numerics::tolerance;

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

/// A crease interpolation in progress. Owns its job; drive it with [`Self::step`] (one
/// period per call) or [`Self::run`].
#[derive(Clone, Debug)]
pub struct Interpolator {
    job: CreaseJob,
    opts: InterpOptions,
    domains: [Domain; 2],
    start: CreasePoint,
    /// The exact crease point of `path.end` (none when the scene has none, or when it is the
    /// start itself: then the run goes round the closed crease).
    end: Option<CreasePoint>,
    turns: u32,
    /// Duration of the last row's period (s) once the run ended on an exact end point.
    final_period_s: Option<f64>,
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
                if c.abs() < tolerance::PERPENDICULAR_COS {
                    return Err(CreaseError::DirectionAmbiguous);
                }
                c.signum()
            }
            None => 1.0,
        };
        let end = end.filter(|e| (e.p - start.p).length() > tolerance::END_AT_START_MM);
        // The crease passes within this distance of a target it crosses (the sagitta of a
        // period plus the interpolation error are far below f while the correction is
        // bounded by half of f).
        let capture = job.feed_per_period_mm + tolerance::END_AT_START_MM;
        let domains = [job.surfaces[0].domain(), job.surfaces[1].domain()];
        let row = Row { k: 0, t_s: 0.0, p: start.p, uv: start.uv };
        Ok(Self {
            opts,
            domains,
            end,
            turns: 0,
            final_period_s: None,
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

    /// Both surfaces' derivatives at the current row's contact parameters, for a caller that
    /// measures the row (the b·T warning): the next period starts from this very evaluation
    /// (it is kept), so the row costs no extra evaluation. `None` once stopped, when the last
    /// step already brought the geometry (the precise stepper), or at a singular point (the
    /// next step reports it).
    pub fn row_derivatives(&mut self) -> Option<[SurfaceDerivs; 2]> {
        if self.stopped.is_some() || self.cached.is_some() {
            return None;
        }
        let geo = [
            LocalGeometry::try_new(self.job.surfaces[0].derivatives_at(self.row.uv[0]))?,
            LocalGeometry::try_new(self.job.surfaces[1].derivatives_at(self.row.uv[1]))?,
        ];
        self.cached = Some(geo);
        Some([geo[0].d, geo[1].d])
    }

    /// Row 0: the start point brought onto the crease.
    #[must_use]
    pub fn first_row(&self) -> Row {
        Row { k: 0, t_s: 0.0, p: self.start.p, uv: self.start.uv }
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

    /// Once the run has stopped on an exact end point (`path.end`, the start of a closed
    /// crease, or a domain edge): the duration of the last row's period (s), at most Ts
    /// when the last period is the shorter final one (see docs/scene-format.md).
    #[must_use]
    pub fn final_period_s(&self) -> Option<f64> {
        self.final_period_s
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
        let at = Location::Period { k, t_s: k as f64 * self.job.period_s };
        let (p_next, uv_next, t, geo_next) = match self.opts.method {
            Method::Seed000 => {
                let (p, uv, t) = self.seed000_step(at)?;
                (p, uv, t, None)
            }
            Method::Exact => self.exact_step(at)?,
        };
        let prev = self.row;
        // Passing path.end or, on a closed crease, the start again: the target's foot on the
        // chord lies in (prev, next] and near it — a test no long step can jump over.
        // Checked before the domain, since an end inside the domain comes before the edge.
        if let Some(end) = self.end
            && passes(end.p, prev.p, p_next, self.capture)
        {
            return Ok(self.finish_at(end.p, end.uv, StopReason::ReachedEnd));
        }
        if passes(self.start.p, prev.p, p_next, self.capture) && (p_next - prev.p).dot(self.start_sense) > 0.0 {
            self.turns += 1;
            if self.turns >= self.opts.turns {
                let (p, uv) = (self.start.p, self.start.uv);
                return Ok(self.finish_at(p, uv, StopReason::Closed { turns: self.turns }));
            }
        }
        // Domain check before anything is committed: the first parameter (along the step)
        // to cross its range ends the path on the exact crease point at that edge.
        let mut exit: Option<(f64, usize, usize, f64, StopReason)> = None;
        for i in 0..2 {
            let d = self.domains[i];
            for (axis, param, range) in [(0, 'u', d.u), (1, 'v', d.v)] {
                let value = uv_next[i][axis];
                if !range.contains(value) {
                    let bound = if value > range.max { range.max } else { range.min };
                    let from = prev.uv[i][axis];
                    let lambda = ((bound - from) / (value - from)).clamp(0.0, 1.0);
                    let lambda = if lambda.is_finite() { lambda } else { 0.0 };
                    if exit.is_none_or(|e| lambda < e.0) {
                        let reason = StopReason::LeftDomain {
                            surface: i,
                            param,
                            value: range.unit.to_file(value),
                            range: [range.unit.to_file(range.min), range.unit.to_file(range.max)],
                        };
                        exit = Some((lambda, i, axis, bound, reason));
                    }
                }
            }
        }
        if let Some((lambda, surface, axis, bound, reason)) = exit {
            return Ok(match self.domain_edge(p_next, uv_next, lambda, surface, axis, bound) {
                Some((p, uv)) => self.finish_at(p, uv, reason),
                None => self.stop(reason),
            });
        }
        let uv_next = [self.domains[0].wrap(uv_next[0]), self.domains[1].wrap(uv_next[1])];
        // Wrapping a periodic parameter does not change the point, so the geometry holds.
        self.pending = geo_next;
        let next = Row { k, t_s: at_time(at), p: p_next, uv: uv_next };
        self.commit(next, t);
        Ok(Step::Row(next))
    }

    /// Ends the run on the exact point `p` (contacts `uv`) with a final period shorter than
    /// (or, by rounding, equal to) a whole one: its time is the previous row's plus the
    /// time to cover the chord at the programmed feed. No row when the previous one already
    /// lies on it ([`tolerance::END_MERGE_MM`]).
    fn finish_at(&mut self, p: DVec3, uv: [DVec2; 2], reason: StopReason) -> Step {
        let prev = self.row;
        let chord = p - prev.p;
        let len = chord.length();
        if !(len > tolerance::END_MERGE_MM) {
            return self.stop(reason);
        }
        let dt_s = self.job.period_s * len / self.job.feed_per_period_mm;
        let row = Row {
            k: prev.k + 1,
            t_s: prev.t_s + dt_s,
            p,
            uv: [self.domains[0].wrap(uv[0]), self.domains[1].wrap(uv[1])],
        };
        self.final_period_s = Some(dt_s);
        self.pending = None;
        self.commit(row, chord / len);
        self.stop_with_row(reason)
    }

    /// The exact crease point where parameter `axis` of surface `surface` reaches `bound`,
    /// between the current row and the step's `p_next` (contacts `uv_next`, unwrapped),
    /// `lambda` the linear estimate of where along the step. A bounded Newton solve (at
    /// most [`NewtonOptions::max_iterations`] iterations, no larger moves than f) from the
    /// interpolated contacts; `None` when it does not converge or lands outside the step
    /// or outside the other parameters' ranges (the run then stops at the last row, as
    /// before).
    fn domain_edge(
        &self,
        p_next: DVec3,
        uv_next: [DVec2; 2],
        lambda: f64,
        surface: usize,
        axis: usize,
        bound: f64,
    ) -> Option<(DVec3, [DVec2; 2])> {
        let prev = self.row;
        let guess = [prev.uv[0].lerp(uv_next[0], lambda), prev.uv[1].lerp(uv_next[1], lambda)];
        let f = self.job.feed_per_period_mm;
        let cp = newton::solve(
            &self.job,
            guess,
            Constraint::Param { surface, axis, value: bound },
            NewtonOptions { max_step_mm: f, ..NewtonOptions::default() },
        )
        .ok()?;
        let inside = self.domains[0].contains(cp.uv[0]) && self.domains[1].contains(cp.uv[1]);
        let dir = p_next - prev.p;
        let len2 = dir.length_squared();
        let along = (cp.p - prev.p).dot(dir) / len2;
        let foot = prev.p + along * dir;
        let on_step =
            (0.0..=1.0 + tolerance::END_AT_START_MM / f).contains(&along) && (cp.p - foot).length() <= self.capture;
        (inside && on_step).then_some((cp.p, cp.uv))
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
        if !(det > tolerance::CORRECTION_SINGULAR_SIN2) {
            return Err(CreaseError::Tangential {
                at,
                angle_deg: det.sqrt().min(1.0).asin().to_degrees(),
                min_deg: tolerance::MIN_CREASE_ANGLE_RAD.to_degrees(),
            });
        }
        let dp = (c[0] * w[1].cross(m) + c[1] * m.cross(w[0])) / det;
        let max_dp = self.opts.max_correction_ratio * f + tolerance::CORRECTION_SLACK_MM;
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
        Location::Period { t_s, .. } => t_s,
        _ => 0.0,
    }
}

/// Whether the step `a → b` passes `target`: the target's foot on the chord's line lies
/// after `a` and not after `b`, within `capture` of the chord. A sign change of the
/// along-chord offset, so however long the step, a target it passes is not missed; the
/// first step of a run (from the start itself, offset exactly 0) does not pass the start.
/// Cheap when far: two dot products.
fn passes(target: DVec3, a: DVec3, b: DVec3, capture: f64) -> bool {
    let dir = b - a;
    let ga = (a - target).dot(dir);
    let gb = (b - target).dot(dir);
    if !(ga < 0.0 && gb >= 0.0) {
        return false;
    }
    let foot = a - dir * (ga / dir.length_squared());
    (foot - target).length_squared() <= capture * capture
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
