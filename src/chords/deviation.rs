//! The deviation of a chord: the largest distance from the arc C(s), s ∈ [s0, s1], to the
//! straight segment C(s0)–C(s1).
//!
//! Found by *sampling, then refining*, never by assuming a shape (the arc may be non-convex,
//! have an inflection, bulge past an end of the chord or be a space curve):
//!
//! 1. **Cover.** Sample the arc at `initial_intervals` equal parameter intervals, then split
//!    an interval again while the arc leaves the sub-chord between its ends by more than
//!    `coverage_rel` of the largest distance seen so far (the midpoint's offset from the
//!    sub-chord, i.e. the sub-arc's sagitta), or while the tangent turns by more than
//!    `max_turn_rad` across it. Between samples the arc then stays within a small fraction of
//!    the answer of the sampled polyline, so no bulge of that size is missed.
//! 2. **Refine.** Around every sampled local maximum that could hold the peak, Brent's
//!    parabolic/golden-section search for the largest distance down to [`DeviationOptions::peak_param_rel`] of the
//!    span. The distance is quadratic at a smooth peak, so its value is found to about the
//!    square of that.

use std::convert::Infallible;

use glam::DVec3;

use crate::geom::Curve3;
use crate::numerics::maximise::brent_max;
use crate::numerics::measure::distance_to_segment;
use crate::numerics::tolerance;

/// Settings of [`chord_deviation`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviationOptions {
    /// Equal parameter intervals sampled first (default 8).
    pub initial_intervals: usize,
    /// Split an interval while its sagitta exceeds this fraction of the largest distance
    /// found so far (default 0.05).
    pub coverage_rel: f64,
    /// Split an interval while the tangent turns more than this across it (rad; default
    /// 10° in radians).
    pub max_turn_rad: f64,
    /// Sagittas below this length are not resolved (mm; default
    /// [`tolerance::NEWTON_LENGTH_MM`]). Callers that know their tolerance E pass about
    /// 1e-3·E here to save work on nearly straight arcs.
    pub floor_mm: f64,
    /// Deepest interval splitting (default 24 halvings).
    pub max_depth: u32,
    /// Peak located to this fraction of the span (default [`tolerance::PEAK_PARAM_REL`]).
    pub peak_param_rel: f64,
}

impl Default for DeviationOptions {
    fn default() -> Self {
        Self {
            initial_intervals: 8,
            coverage_rel: 0.05,
            max_turn_rad: 10f64.to_radians(),
            floor_mm: tolerance::NEWTON_LENGTH_MM,
            max_depth: 24,
            peak_param_rel: tolerance::PEAK_PARAM_REL,
        }
    }
}

/// The deviation of one chord.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChordDeviation {
    /// Largest distance from the arc to the chord segment (mm).
    pub max_mm: f64,
    /// Where on the arc it occurs (curve parameter).
    pub at_s: f64,
    /// Curve evaluations spent.
    pub curve_evaluations: u32,
}

#[derive(Clone, Copy)]
struct Sample {
    s: f64,
    p: DVec3,
    t: DVec3,
    g: f64,
}

struct Chord<'c> {
    curve: &'c dyn Curve3,
    a: DVec3,
    b: DVec3,
    evals: u32,
}

impl Chord<'_> {
    fn sample(&mut self, s: f64) -> Sample {
        self.evals += 1;
        let [p, d1, _] = self.curve.derivatives_at(s);
        Sample { s, p, t: d1, g: distance_to_segment(p, self.a, self.b) }
    }

    fn g(&mut self, s: f64) -> f64 {
        self.evals += 1;
        distance_to_segment(self.curve.point_at(s), self.a, self.b)
    }
}

fn turn_angle(a: DVec3, b: DVec3) -> f64 {
    let (la, lb) = (a.length(), b.length());
    if !(la > 0.0 && lb > 0.0) {
        return 0.0;
    }
    a.cross(b).length().atan2(a.dot(b))
}

/// Splits `[x0, x1]` while it may hide part of the arc (module docs, step 1), appending the
/// new samples (and `x1`) to `out` in order.
fn cover(
    chord: &mut Chord<'_>,
    x0: Sample,
    x1: Sample,
    depth: u32,
    best: &mut f64,
    opts: &DeviationOptions,
    out: &mut Vec<Sample>,
) {
    let m = chord.sample(0.5 * (x0.s + x1.s));
    *best = best.max(m.g);
    let sagitta = distance_to_segment(m.p, x0.p, x1.p);
    let limit = (opts.coverage_rel * *best).max(opts.floor_mm);
    let split = depth < opts.max_depth && (sagitta > limit || turn_angle(x0.t, x1.t) > opts.max_turn_rad);
    if split {
        cover(chord, x0, m, depth + 1, best, opts, out);
        cover(chord, m, x1, depth + 1, best, opts, out);
    } else {
        out.push(m);
        out.push(x1);
    }
}

/// The largest distance from the arc `C(s)`, `s ∈ [s0, s1]`, to the segment `C(s0)–C(s1)`
/// (module docs). `s0 > s1` is allowed (the same chord).
///
/// ```
/// # use interpolab::chords::{chord_deviation, DeviationOptions};
/// # use interpolab::geom::{Curve3, HermitePath};
/// # use glam::DVec3;
/// // A straight path has no deviation.
/// let line = HermitePath::new(vec![DVec3::ZERO, DVec3::X * 10.0], vec![DVec3::X, DVec3::X]).unwrap();
/// let d = chord_deviation(&line, 0.0, 10.0, &DeviationOptions::default());
/// assert!(d.max_mm < 1e-12);
/// ```
#[must_use]
pub fn chord_deviation(curve: &dyn Curve3, s0: f64, s1: f64, opts: &DeviationOptions) -> ChordDeviation {
    let (s0, s1) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
    let mut chord = Chord { curve, a: curve.point_at(s0), b: curve.point_at(s1), evals: 2 };
    if s1.partial_cmp(&s0) != Some(std::cmp::Ordering::Greater) {
        return ChordDeviation { max_mm: 0.0, at_s: s0, curve_evaluations: chord.evals };
    }
    let n = opts.initial_intervals.max(2);
    let h = (s1 - s0) / n as f64;
    let coarse: Vec<Sample> = (0..=n).map(|i| chord.sample(if i == n { s1 } else { s0 + h * i as f64 })).collect();
    let mut best = coarse.iter().map(|x| x.g).fold(0.0, f64::max);
    let mut samples = Vec::with_capacity(4 * n + 1);
    samples.push(coarse[0]);
    for w in coarse.windows(2) {
        cover(&mut chord, w[0], w[1], 0, &mut best, opts, &mut samples);
    }

    // Refine every local maximum of the samples that could hold the peak: one whose value
    // is within the coverage margin of the best sample.
    let mut top = samples.iter().fold((s0, 0.0), |acc, x| if x.g > acc.1 { (x.s, x.g) } else { acc });
    let margin = (3.0 * opts.coverage_rel * top.1).max(opts.floor_mm);
    let width = opts.peak_param_rel * (s1 - s0);
    let last = samples.len() - 1;
    let candidates: Vec<usize> = (1..last)
        .filter(|&i| {
            samples[i].g >= samples[i - 1].g && samples[i].g >= samples[i + 1].g && samples[i].g + margin >= top.1
        })
        .collect();
    for i in candidates {
        let g = |s: f64| -> Result<f64, Infallible> { Ok(chord.g(s)) };
        let seed = (samples[i].s, samples[i].g);
        let Ok((s, v, _)) = brent_max(g, samples[i - 1].s, samples[i + 1].s, width, seed);
        if v > top.1 {
            top = (s, v);
        }
    }
    ChordDeviation { max_mm: top.1, at_s: top.0, curve_evaluations: chord.evals }
}
