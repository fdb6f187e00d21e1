//! The interpolator on the planned feed: joint positions every period Ts, with the path
//! speed, acceleration and jerk of that instant. No allocation per period: the caller's
//! [`Period`] is filled in place.

use super::feed::FeedPlan;
use super::path::{Path, Q, Shape};

/// One interpolation period.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Period {
    /// Period number (0 at the start).
    pub k: u64,
    /// Time (s).
    pub t: f64,
    /// Joint positions: X Y Z (mm), A B C (rad).
    pub q: Q,
    /// Path position (mm).
    pub s: f64,
    /// Path speed (mm/s).
    pub v: f64,
    /// Path acceleration (mm/s²).
    pub a: f64,
    /// Path jerk (mm/s³).
    pub j: f64,
    /// Index of the block (canonical motion) the tool is in.
    pub block: usize,
}

/// Periods at rest printed after the end, so that the last positions show zero velocity
/// and acceleration by differences.
pub const REST_PERIODS: u64 = 3;

/// Walks the plan period by period.
#[derive(Clone, Debug)]
pub struct Sampler<'a> {
    path: &'a Path,
    plan: &'a FeedPlan,
    ts: f64,
    k: u64,
    last: u64,
    phase: usize,
    piece: usize,
    /// (piece, τ, s) of the last curve evaluation, to start Newton from.
    cache: (usize, f64, f64),
}

impl<'a> Sampler<'a> {
    /// A sampler at period `ts` (s).
    #[must_use]
    pub fn new(path: &'a Path, plan: &'a FeedPlan, ts: f64) -> Self {
        let last = (plan.duration / ts).ceil() as u64 + REST_PERIODS;
        Self { path, plan, ts, k: 0, last, phase: 0, piece: 0, cache: (usize::MAX, 0.0, 0.0) }
    }

    /// Number of periods the sampler gives (the first at t = 0 included).
    #[must_use]
    pub fn periods(&self) -> u64 {
        self.last + 1
    }

    /// Fills `out` with the next period; false when done.
    pub fn next_period(&mut self, out: &mut Period) -> bool {
        if self.k > self.last {
            return false;
        }
        let t = self.k as f64 * self.ts;
        out.k = self.k;
        out.t = t;
        self.k += 1;
        let phases = &self.plan.phases;
        while self.phase + 1 < phases.len() && t >= phases[self.phase + 1].t0 {
            self.phase += 1;
        }
        let (s, v, a, j) = match phases.get(self.phase) {
            Some(p) if t < p.t0 + p.phase.dur => {
                let (s, v, a) = p.at(t);
                (s, v, a, p.phase.j)
            }
            Some(p) if self.phase + 1 < phases.len() => {
                let (s, v, a) = p.at(t);
                (s, v, a, 0.0)
            }
            _ => (self.path.length, 0.0, 0.0, 0.0),
        };
        let s = s.clamp(0.0, self.path.length);
        out.s = s;
        out.v = v;
        out.a = a;
        out.j = j;
        self.position(s, out);
        true
    }

    fn position(&mut self, s: f64, out: &mut Period) {
        let path = self.path;
        if s >= path.length || path.pieces.is_empty() {
            out.q = path.end;
            out.block = path.blocks.len().saturating_sub(1);
            return;
        }
        while self.piece + 1 < path.pieces.len() && s >= path.pieces[self.piece + 1].s0 {
            self.piece += 1;
        }
        let p = &path.pieces[self.piece];
        let e = &path.elems[p.elem as usize];
        out.block = e.block;
        match &e.shape {
            Shape::Line { .. } => {
                out.q = e.at_tau(&path.curves, (s - e.s0).clamp(0.0, e.len)).0;
            }
            _ => {
                let (t_ref, s_ref) = if self.cache.0 == self.piece && self.cache.2 <= s {
                    (self.cache.1, self.cache.2)
                } else {
                    (p.tau.0, p.s0)
                };
                let t = e.tau_at(&path.curves, s, t_ref, s_ref);
                self.cache = (self.piece, t, s);
                out.q = e.at_tau(&path.curves, t).0;
            }
        }
    }
}
