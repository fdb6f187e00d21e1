//! Checks a plan from its periods alone, independently of the planner: joint velocity,
//! acceleration and jerk by first, second and third differences of the positions, and the
//! end. Why differences need no allowance for the limits themselves: the n-th difference
//! Δⁿp_k equals Tsⁿ times a weighted average of p⁽ⁿ⁾ over [t_k, t_{k+n}] (a B-spline kernel
//! of degree n − 1, non-negative, integral one), so a motion within a limit gives
//! differences within it. What needs an allowance is the positions' own error ε: up to
//! 2ⁿε/Tsⁿ in the n-th difference.

use super::machine::JointLimits;
use super::path::Q;

/// Largest values seen, per joint: velocity, acceleration, jerk (mm/s… or rad/s…).
#[derive(Clone, Debug, PartialEq)]
pub struct LimitReport {
    /// Periods checked.
    pub periods: u64,
    /// Largest |Δp|/Ts, |Δ²p|/Ts², |Δ³p|/Ts³ per joint.
    pub max: [[f64; 3]; 6],
    /// The period (index of the first position of the difference) of each maximum.
    pub at: [[u64; 3]; 6],
    /// Largest of measured/limit over joints and orders, the allowance subtracted first.
    pub worst_ratio: f64,
    /// The allowances used per order (mm/s, mm/s², mm/s³ for an error of `eps_mm`).
    pub allowance: [f64; 3],
    /// The last position and the two differences at the end (velocity and acceleration of
    /// the last three periods).
    pub last: Q,
    /// |Δp|/Ts and |Δ²p|/Ts² at the end (largest joint).
    pub end_rates: [f64; 2],
}

impl LimitReport {
    /// True when no joint's velocity, acceleration or jerk exceeds its limit beyond the
    /// allowance.
    #[must_use]
    pub fn within(&self) -> bool {
        self.worst_ratio <= 1.0
    }
}

/// A streaming checker: feed positions in order.
#[derive(Clone, Debug)]
pub struct LimitChecker {
    lim: JointLimits,
    ts: f64,
    eps: f64,
    hist: [Q; 4],
    n: u64,
    rep: LimitReport,
}

impl LimitChecker {
    /// A checker at period `ts` (s) for positions known to `eps_mm` (mm, or rad on the
    /// rotary joints).
    #[must_use]
    pub fn new(lim: JointLimits, ts: f64, eps_mm: f64) -> Self {
        let allowance = [2.0 * eps_mm / ts, 4.0 * eps_mm / (ts * ts), 8.0 * eps_mm / (ts * ts * ts)];
        Self {
            lim,
            ts,
            eps: eps_mm,
            hist: [[0.0; 6]; 4],
            n: 0,
            rep: LimitReport {
                periods: 0,
                max: [[0.0; 3]; 6],
                at: [[0; 3]; 6],
                worst_ratio: 0.0,
                allowance,
                last: [0.0; 6],
                end_rates: [0.0; 2],
            },
        }
    }

    /// The positions' error bound used.
    #[must_use]
    pub fn eps(&self) -> f64 {
        self.eps
    }

    /// Adds the next period's position.
    pub fn push(&mut self, q: &Q) {
        self.hist.rotate_left(1);
        self.hist[3] = *q;
        self.n += 1;
        let h = &self.hist;
        let ts = self.ts;
        for i in 0..6 {
            let lims = [self.lim.v[i], self.lim.a[i], self.lim.j[i]];
            let d1 = h[3][i] - h[2][i];
            let d2 = h[3][i] - 2.0 * h[2][i] + h[1][i];
            let d3 = h[3][i] - 3.0 * h[2][i] + 3.0 * h[1][i] - h[0][i];
            let vals = [d1.abs() / ts, d2.abs() / (ts * ts), d3.abs() / (ts * ts * ts)];
            for o in 0..3 {
                if self.n < (o as u64) + 2 {
                    continue;
                }
                if vals[o] > self.rep.max[i][o] {
                    self.rep.max[i][o] = vals[o];
                    self.rep.at[i][o] = self.n - 2 - o as u64;
                }
                if lims[o].is_finite() {
                    let r = (vals[o] - self.rep.allowance[o]).max(0.0) / lims[o];
                    self.rep.worst_ratio = self.rep.worst_ratio.max(r);
                }
            }
        }
    }

    /// The report.
    #[must_use]
    pub fn finish(mut self) -> LimitReport {
        self.rep.periods = self.n;
        let h = &self.hist;
        self.rep.last = h[3];
        let mut v: f64 = 0.0;
        let mut a: f64 = 0.0;
        for i in 0..6 {
            v = v.max((h[3][i] - h[2][i]).abs() / self.ts);
            a = a.max((h[3][i] - 2.0 * h[2][i] + h[1][i]).abs() / (self.ts * self.ts));
        }
        self.rep.end_rates = [v, a];
        self.rep
    }
}
