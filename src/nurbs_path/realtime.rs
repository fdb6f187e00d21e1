//! Real-time NURBS interpolation (seed 004, §3): every interpolation period Ts the CNC
//! advances the curve parameter from u_k to u_{k+1} so that the tool moves one feed step
//! f = F·Ts along the curve, and sends C(u_{k+1}) to the drives.
//!
//! With the parametric speed v = |C'(u)| and arc length s, du/ds = 1/v and
//! d²u/ds² = −(C'·C'')/v⁴, so Taylor's expansion of u(s) gives the updates
//!
//! - first order: `Δu = f / v`;
//! - second order: `Δu = f / v − f²·(C'·C'') / (2 v⁴)`;
//! - corrected (ours): the second-order value refined by Newton steps on the chord condition
//!   `g(u) = |C(u) − C(u_k)| − f = 0`, `g'(u) = (C(u) − C(u_k))·C'(u) / |C(u) − C(u_k)|`.
//!   One step makes the step length exact to about the square of the second-order error.
//!
//! Their quality is the **feed fluctuation** `(|C(u_{k+1}) − C(u_k)| − f_k) / f_k`, reported
//! as its largest magnitude and RMS over all periods but the last (which ends the curve and
//! is shorter on purpose). The **chord error** of a period is the largest distance from the
//! curve between u_k and u_{k+1} to the straight step the drives make; for a circle of radius
//! ρ it is `ρ − √(ρ² − f²/4) ≈ f²/(8ρ)`. With a chord tolerance δ the feed step is limited to
//! the chord of the osculating circle whose sagitta is δ: `f_k = min(F·Ts, 2√(2ρδ − δ²))`,
//! ρ = 1/κ taken as the larger curvature at u_k and half a step ahead (the curvature-based
//! feed limit; with δ ≥ ρ the step is at most 2ρ).

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use glam::DVec3;
use thiserror::Error;

use crate::geom::Curve3;
use crate::numerics::measure::distance_to_segment;
use crate::numerics::units;

/// The parameter update of each period.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Update {
    /// `Δu = f / |C'|`.
    FirstOrder,
    /// `Δu = f/|C'| − f²(C'·C'')/(2|C'|⁴)`.
    SecondOrder,
    /// Second order, then Newton on the chord length.
    Corrected,
}

impl Update {
    /// All three, in order.
    pub const ALL: [Self; 3] = [Self::FirstOrder, Self::SecondOrder, Self::Corrected];

    /// Name used on the command line and in tables.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::FirstOrder => "first",
            Self::SecondOrder => "second",
            Self::Corrected => "corrected",
        }
    }
}

/// Options of [`interpolate_realtime`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealtimeOptions {
    /// Feed per period f = F·Ts (mm; default 0.1, F = 1500 mm/min as in seed 000's example
    /// and Ts = 4 ms). Set from the file's units by [`Self::with_feed`].
    pub feed_per_period_mm: f64,
    /// Interpolation period Ts (s, default 0.004).
    pub period_s: f64,
    /// Parameter update (default corrected).
    pub update: Update,
    /// Chord tolerance δ of the curvature-based feed limit (mm); `None` (default) runs at F.
    pub chord_tol_mm: Option<f64>,
    /// Newton steps of the corrected update (default 1).
    pub corrector_steps: usize,
    /// Keep every period's sample (default true); otherwise only the statistics.
    pub keep_samples: bool,
    /// Most periods (default 10 million) before giving up.
    pub max_periods: u64,
}

impl Default for RealtimeOptions {
    fn default() -> Self {
        Self {
            feed_per_period_mm: units::mm_per_period(1500.0, 4.0),
            period_s: units::s_from_ms(4.0),
            update: Update::Corrected,
            chord_tol_mm: None,
            corrector_steps: 1,
            keep_samples: true,
            max_periods: 10_000_000,
        }
    }
}

impl RealtimeOptions {
    /// Sets feed and period from the file's (and G-code's) units: F in mm/min, Ts in ms —
    /// an edge conversion ([`units`]): f = F·Ts/60 000 is formed once from these numbers.
    #[must_use]
    pub fn with_feed(mut self, feed_mm_per_min: f64, period_ms: f64) -> Self {
        self.feed_per_period_mm = units::mm_per_period(feed_mm_per_min, period_ms);
        self.period_s = units::s_from_ms(period_ms);
        self
    }
    /// Sets the update.
    #[must_use]
    pub fn with_update(mut self, update: Update) -> Self {
        self.update = update;
        self
    }
    /// Sets the chord tolerance of the feed limit (mm).
    #[must_use]
    pub fn with_chord_tol(mut self, tol_mm: Option<f64>) -> Self {
        self.chord_tol_mm = tol_mm;
        self
    }
    /// Sets whether samples are kept.
    #[must_use]
    pub fn with_samples(mut self, keep: bool) -> Self {
        self.keep_samples = keep;
        self
    }
    /// The feed per period f = F·Ts (mm).
    #[must_use]
    pub fn feed_per_period_mm(&self) -> f64 {
        self.feed_per_period_mm
    }
}

/// Samples of the curve whose polyline bounds its length from below, to refuse a run
/// needing more than `max_periods` before it starts.
const LENGTH_SAMPLES: usize = 64;

/// Why a real-time run could not be made.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum RealtimeError {
    /// Feed or period not a positive finite number.
    #[error(
        "the feed per period ({feed_per_period_mm} mm) and the period ({} ms) must be positive; give e.g. F = 1500 mm/min and Ts = 4 ms",
        units::ms_from_s(*period_s)
    )]
    BadMotion {
        /// f = F·Ts (mm).
        feed_per_period_mm: f64,
        /// Ts (s).
        period_s: f64,
    },
    /// The chord tolerance is not a positive length.
    #[error("the chord tolerance of the feed limit must be a positive length, got {0} mm")]
    BadChordTol(f64),
    /// The curve stands still (C' = 0) at a parameter.
    #[error(
        "the curve's parametric speed |C'| vanishes at u = {u}; the parameter cannot be advanced there — refit the curve without a cusp"
    )]
    Stalled {
        /// Where.
        u: f64,
    },
    /// Too many periods.
    #[error("more than {max} periods would be needed; raise the feed or the period, or shorten the curve")]
    TooManyPeriods {
        /// The limit.
        max: u64,
    },
}

/// One period of a real-time run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodSample {
    /// Period index (1 for the first step).
    pub k: u64,
    /// Curve parameter reached.
    pub u: f64,
    /// C(u) (mm).
    pub point: DVec3,
    /// The step this period aimed at, f_k (mm).
    pub target_mm: f64,
    /// The step made, |C(u_k) − C(u_{k−1})| (mm).
    pub step_mm: f64,
    /// (step − target)/target; 0 for the last period.
    pub fluctuation: f64,
    /// Chord error of the period (mm).
    pub chord_error_mm: f64,
    /// Whether the curvature limit lowered the feed this period.
    pub limited: bool,
    /// Whether this is the last (shortened) period.
    pub last: bool,
}

/// Summary of a real-time run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedStats {
    /// The update used.
    pub update: Update,
    /// Periods run.
    pub periods: u64,
    /// Largest |fluctuation| over all periods but the last.
    pub max_fluctuation: f64,
    /// RMS fluctuation over all periods but the last.
    pub rms_fluctuation: f64,
    /// Largest chord error (mm).
    pub max_chord_error_mm: f64,
    /// Periods whose feed the curvature limit lowered.
    pub limited_periods: u64,
    /// Time to run the curve, periods × Ts (s).
    pub time_s: f64,
    /// Sum of the steps (mm).
    pub length_mm: f64,
}

/// A real-time run: every period's sample (if kept) and the statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct RealtimeRun {
    /// Per-period samples (empty unless [`RealtimeOptions::keep_samples`]).
    pub samples: Vec<PeriodSample>,
    /// Statistics.
    pub stats: FeedStats,
}

/// Largest step along a circle of radius 1/κ whose chord error (sagitta) is `tol`.
#[must_use]
pub fn chord_limited_step(kappa: f64, tol_mm: f64) -> f64 {
    if !(kappa > 0.0) {
        return f64::INFINITY;
    }
    let rho = 1.0 / kappa;
    if tol_mm >= rho { 2.0 * rho } else { 2.0 * (tol_mm * (2.0 * rho - tol_mm)).sqrt() }
}

/// Largest distance from the curve between `u0` and `u1` to the chord `[a, b]`: Newton on
/// `g(t) = r⊥·C'`, r⊥ the part of `C(t) − a` across the chord (its stationary point), from the
/// middle, `g' = |C'⊥|² + r⊥·C''`; kept inside the step and checked against the middle.
#[must_use]
pub fn chord_error(curve: &dyn Curve3, u0: f64, u1: f64, a: DVec3, b: DVec3) -> f64 {
    let e = (b - a).normalize_or_zero();
    let across = |v: DVec3| v - v.dot(e) * e;
    let mid = 0.5 * (u0 + u1);
    let mut t = mid;
    for _ in 0..6 {
        let [c, d1, d2] = curve.derivatives_at(t);
        let r = across(c - a);
        let g = r.dot(d1);
        let gp = across(d1).length_squared() + r.dot(d2);
        if !(gp < 0.0) {
            // Not at a maximum's basin: keep the middle.
            break;
        }
        let tn = (t - g / gp).clamp(u0, u1);
        let done =
            (tn - t).abs() <= crate::numerics::tolerance::PARAM_NEWTON_REL * (u1 - u0).abs().max(f64::MIN_POSITIVE);
        t = tn;
        if done {
            break;
        }
    }
    distance_to_segment(curve.point_at(t), a, b).max(distance_to_segment(curve.point_at(mid), a, b))
}

/// The parameter step of one period from `u` for a step length `f`.
fn advance(curve: &dyn Curve3, u: f64, f: f64, update: Update, steps: usize) -> Option<f64> {
    let [c0, d1, d2] = curve.derivatives_at(u);
    let v = d1.length();
    if !(v > 0.0) {
        return None;
    }
    let first = f / v;
    if update == Update::FirstOrder {
        return Some(first);
    }
    let second = first - f * f * d1.dot(d2) / (2.0 * v.powi(4));
    let second = if second > 0.0 { second } else { first };
    if update == Update::SecondOrder {
        return Some(second);
    }
    let mut du = second;
    for _ in 0..steps {
        let [c, d, _] = curve.derivatives_at(u + du);
        let w = c - c0;
        let len = w.length();
        let gp = if len > 0.0 { w.dot(d) / len } else { 0.0 };
        if !(gp > 0.0) {
            break;
        }
        let next = du - (len - f) / gp;
        if !(next > 0.0 && next.is_finite()) {
            break;
        }
        du = next;
    }
    Some(du)
}

/// Runs real-time interpolation over the whole curve.
///
/// # Errors
/// [`RealtimeError`] for bad options, a stalled curve or too many periods.
pub fn interpolate_realtime(curve: &dyn Curve3, opts: &RealtimeOptions) -> Result<RealtimeRun, RealtimeError> {
    let mut run = RealtimeStepper::new(curve, opts)?;
    while !run.advance(curve, u64::MAX)? {}
    Ok(run.finish())
}

/// [`interpolate_realtime`] a number of periods at a time, for callers that must not block
/// (the app runs a few thousand periods per frame): the same periods, samples and
/// statistics as the one call, however the run is split.
#[derive(Clone, Debug)]
pub struct RealtimeStepper {
    opts: RealtimeOptions,
    f: f64,
    u: f64,
    p: DVec3,
    k: u64,
    max_f: f64,
    sum2: f64,
    n_f: u64,
    max_chord: f64,
    limited_n: u64,
    length: f64,
    samples: Vec<PeriodSample>,
}

impl RealtimeStepper {
    /// Starts a run of `curve` at the start of its range.
    ///
    /// # Errors
    /// [`RealtimeError`] for bad options.
    pub fn new(curve: &dyn Curve3, opts: &RealtimeOptions) -> Result<Self, RealtimeError> {
        let f = opts.feed_per_period_mm();
        if !(f.is_finite() && f > 0.0 && opts.period_s > 0.0) {
            return Err(RealtimeError::BadMotion { feed_per_period_mm: f, period_s: opts.period_s });
        }
        if let Some(t) = opts.chord_tol_mm
            && !(t.is_finite() && t > 0.0)
        {
            return Err(RealtimeError::BadChordTol(t));
        }
        let (u0, u1) = curve.range();
        // Refuse before the work: a polyline through samples of the curve is no longer than
        // the curve, so this many periods at least would be needed.
        let mut lower_mm = 0.0;
        let mut prev = curve.point_at(u0);
        for i in 1..=LENGTH_SAMPLES {
            let p = curve.point_at(u0 + (u1 - u0) * i as f64 / LENGTH_SAMPLES as f64);
            lower_mm += (p - prev).length();
            prev = p;
        }
        if lower_mm / f > opts.max_periods as f64 {
            return Err(RealtimeError::TooManyPeriods { max: opts.max_periods });
        }
        Ok(Self {
            opts: *opts,
            f,
            u: u0,
            p: curve.point_at(u0),
            k: 0,
            max_f: 0.0,
            sum2: 0.0,
            n_f: 0,
            max_chord: 0.0,
            limited_n: 0,
            length: 0.0,
            samples: Vec::new(),
        })
    }

    /// Periods run so far.
    #[must_use]
    pub fn periods(&self) -> u64 {
        self.k
    }

    /// Runs at most `periods` more periods of `curve` (the curve given to [`Self::new`]).
    /// Returns whether the end of the curve has been reached.
    ///
    /// # Errors
    /// [`RealtimeError`] for a stalled curve or too many periods.
    pub fn advance(&mut self, curve: &dyn Curve3, periods: u64) -> Result<bool, RealtimeError> {
        let opts = &self.opts;
        let f = self.f;
        let (_, u1) = curve.range();
        let stop = self.k.saturating_add(periods);
        while self.u < u1 {
            if self.k >= stop {
                return Ok(false);
            }
            let (u, p) = (self.u, self.p);
            if self.k >= opts.max_periods {
                return Err(RealtimeError::TooManyPeriods { max: opts.max_periods });
            }
            self.k += 1;
            let mut target = f;
            let mut limited = false;
            if let Some(tol) = opts.chord_tol_mm {
                let v = curve.derivatives_at(u)[1].length();
                let ahead = if v > 0.0 { (u + 0.5 * f / v).min(u1) } else { u };
                let kappa = curve.curvature_at(u).max(curve.curvature_at(ahead));
                let lim = chord_limited_step(kappa, tol);
                if lim < target {
                    target = lim;
                    limited = true;
                    self.limited_n += 1;
                }
            }
            let du =
                advance(curve, u, target, opts.update, opts.corrector_steps).ok_or(RealtimeError::Stalled { u })?;
            let (un, last) = if u + du >= u1 { (u1, true) } else { (u + du, false) };
            let pn = curve.point_at(un);
            let step = (pn - p).length();
            let fluct = if last { 0.0 } else { (step - target) / target };
            if !last {
                self.max_f = self.max_f.max(fluct.abs());
                self.sum2 += fluct * fluct;
                self.n_f += 1;
            }
            let chord = chord_error(curve, u, un, p, pn);
            self.max_chord = self.max_chord.max(chord);
            self.length += step;
            if opts.keep_samples {
                self.samples.push(PeriodSample {
                    k: self.k,
                    u: un,
                    point: pn,
                    target_mm: target,
                    step_mm: step,
                    fluctuation: fluct,
                    chord_error_mm: chord,
                    limited,
                    last,
                });
            }
            if !(un > u) {
                return Err(RealtimeError::Stalled { u });
            }
            self.u = un;
            self.p = pn;
        }
        Ok(true)
    }

    /// The run so far: its samples and statistics (of the whole curve once
    /// [`Self::advance`] has returned `true`).
    #[must_use]
    pub fn finish(self) -> RealtimeRun {
        let rms = if self.n_f > 0 { (self.sum2 / self.n_f as f64).sqrt() } else { 0.0 };
        RealtimeRun {
            samples: self.samples,
            stats: FeedStats {
                update: self.opts.update,
                periods: self.k,
                max_fluctuation: self.max_f,
                rms_fluctuation: rms,
                max_chord_error_mm: self.max_chord,
                limited_periods: self.limited_n,
                time_s: self.k as f64 * self.opts.period_s,
                length_mm: self.length,
            },
        }
    }
}
