//! One step of an equal-error node search: from the current node s_a, find the next node s
//! whose segment error δ(s) equals the tolerance E.
//!
//! This is seed 002's procedure (Ji, Zhou, An & Zhang 2010, §3), written once for every
//! error function of the crate — the chord deviation of a curve ([`crate::chords::chord_deviation`])
//! and the five-axis total error δ = δt + δn (`crate::fiveaxis`):
//!
//! 1. **Bracket** (§3.1): `u_low = s_a`; trial `u_high = u_low + Δs`; while δ(u_high) < E,
//!    `u_low = u_high` and `Δs ← α·Δs` (α ≥ 1, default 2). The first Δs is the caller's
//!    estimate (seed 002: `Δl = √(8ρE)`, `Δs = Δl/|p'(s_a)|`; later the previous step).
//! 2. **Solve** `f(s) = δ(s) − E = 0` inside `(u_low, u_high)` with one of the
//!    [`RootMethod`]s; the root stays bracketed throughout.
//!
//! Acceptance: a node is taken when `E − ε ≤ δ ≤ E` (ε = [`SearchOptions::window_mm`], the
//! paper's 1e-6 termination), i.e. every returned segment is within the tolerance. The last
//! node is the end of the range, with δ ≤ E. Every call of δ counts as one *evaluation*
//! (the paper's "iterations").

use crate::numerics::tolerance;

/// How the root of δ(s) = E is found once it is bracketed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RootMethod {
    /// Halve the bracket (seed 002's reference \[12\]).
    Bisection,
    /// Cut the bracket at the golden ratio, the shorter part next to the end whose error is
    /// closer to E (seed 002's reference \[14\]).
    Golden,
    /// Seed 002's modified secant, eq. (4): `s = s_high − f_high (s_high − s_low)/(f_high − f_low)`,
    /// replacing the end of the same sign (classical regula falsi).
    #[default]
    Secant,
    /// Regula falsi with the Illinois modification: when the same end is replaced twice in
    /// a row, the error kept at the other end is halved in the interpolation formula.
    Illinois,
    /// Regula falsi with the Anderson–Björck modification: the kept end's error is scaled
    /// by `m = 1 − f_new/f_replaced` (0.5 if m ≤ 0) when the same end is replaced twice in
    /// a row. Superlinear on convex error functions, where plain regula falsi is linear.
    AndersonBjorck,
}

impl RootMethod {
    /// Every method, in the order the comparison tables print them.
    pub const ALL: [Self; 5] = [Self::Bisection, Self::Golden, Self::Secant, Self::Illinois, Self::AndersonBjorck];

    /// Short name as used on the command line (`bisection`, `golden`, `secant`, `illinois`,
    /// `anderson-bjorck`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Bisection => "bisection",
            Self::Golden => "golden",
            Self::Secant => "secant",
            Self::Illinois => "illinois",
            Self::AndersonBjorck => "anderson-bjorck",
        }
    }

    /// The method with this short name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.as_str() == name)
    }
}

/// Settings of a node search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchOptions {
    /// Root finder inside the bracket (default [`RootMethod::Secant`], the paper's).
    pub method: RootMethod,
    /// α, growth of the trial step while bracketing; seed 002 asks α ≥ 1 (default 2,
    /// doubling).
    pub growth: f64,
    /// ε, width of the acceptance window `[E − ε, E]` in mm (default
    /// [`tolerance::STEP_WINDOW_MM`], the paper's 1e-6).
    pub window_mm: f64,
    /// Cap of ε relative to E (default [`tolerance::STEP_WINDOW_REL`]): ε = min(window_mm,
    /// window_rel·E).
    pub window_rel: f64,
    /// Most error evaluations for one node before giving up (default 2000: plain regula
    /// falsi may crawl for hundreds of steps from a bracket whose far end errs by orders of
    /// magnitude more than E).
    pub max_evaluations: u32,
}

impl Default for SearchOptions {
    fn default() -> Self {
        Self {
            method: RootMethod::default(),
            growth: 2.0,
            window_mm: tolerance::STEP_WINDOW_MM,
            window_rel: tolerance::STEP_WINDOW_REL,
            max_evaluations: 2000,
        }
    }
}

impl SearchOptions {
    /// These options with another root method.
    #[must_use]
    pub fn with_method(mut self, method: RootMethod) -> Self {
        self.method = method;
        self
    }

    /// The acceptance window ε (mm) for the tolerance E.
    #[must_use]
    pub fn window_for(&self, tol_mm: f64) -> f64 {
        self.window_mm.min(self.window_rel * tol_mm)
    }
}

/// The node one search found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoundNode {
    /// Its parameter.
    pub s: f64,
    /// δ of the segment from the previous node to it (mm); in `[E − ε, E]` unless `is_end`.
    pub error_mm: f64,
    /// Error evaluations spent on this node, bracketing included.
    pub evaluations: u32,
    /// Of those, the evaluations spent bracketing.
    pub bracket_evaluations: u32,
    /// The node is the end of the range (its segment's error may be below E − ε).
    pub is_end: bool,
    /// The error jumped across E inside a bracket at rounding width, so the node was taken
    /// just before the jump (its error is below E − ε although it is not the end).
    pub jumped: bool,
}

/// Why a search failed.
#[derive(Clone, Debug, PartialEq)]
pub enum SearchFailure<E> {
    /// The error function itself failed.
    Eval(E),
    /// The error function returned NaN or ±∞ at `s`.
    NotFinite {
        /// Where.
        s: f64,
    },
    /// Already the smallest representable step past `s_from` exceeds the tolerance.
    Underflow {
        /// The current node.
        s_from: f64,
        /// The error of the shortest segment tried (mm).
        error_mm: f64,
    },
    /// `max_evaluations` were spent without meeting the window.
    NoConvergence {
        /// The current node.
        s_from: f64,
        /// Evaluations spent.
        evaluations: u32,
    },
}

/// Finds the next node after `s_from` (see the module docs).
///
/// `error(s)` is δ of the segment `[s_from, s]` in mm (δ(s_from) = 0 is assumed, not
/// evaluated). `first_step` is the first trial Δs (replaced by the whole remaining range when
/// not positive and finite). `tol_mm` must be positive.
///
/// # Errors
/// [`SearchFailure`]: the error function failed or was not finite, the step underflowed, or
/// the evaluation budget ran out.
pub fn next_node<E>(
    mut error: impl FnMut(f64) -> Result<f64, E>,
    s_from: f64,
    s_end: f64,
    first_step: f64,
    tol_mm: f64,
    opts: &SearchOptions,
) -> Result<FoundNode, SearchFailure<E>> {
    let window = opts.window_for(tol_mm);
    // f(s) = δ(s) − target, accepted when |f| ≤ half: δ ∈ [E − ε, E].
    let half = 0.5 * window;
    let target = tol_mm - half;
    let remaining = s_end - s_from;
    let mut step = if first_step > 0.0 && first_step.is_finite() { first_step.min(remaining) } else { remaining };
    let growth = if opts.growth >= 1.0 { opts.growth } else { 1.0 };
    let scale = s_from.abs().max(s_end.abs()).max(remaining.abs());
    let min_width = tolerance::STEP_PARAM_REL * scale;

    let mut evals = 0u32;
    let mut eval = |s: f64, evals: &mut u32| -> Result<f64, SearchFailure<E>> {
        *evals += 1;
        let d = error(s).map_err(SearchFailure::Eval)?;
        if d.is_finite() { Ok(d) } else { Err(SearchFailure::NotFinite { s }) }
    };
    let found = |s: f64, d: f64, evals: u32, bracket: u32, is_end: bool, jumped: bool| FoundNode {
        s,
        error_mm: d,
        evaluations: evals,
        bracket_evaluations: bracket,
        is_end,
        jumped,
    };

    // 1. Bracket.
    let mut lo = s_from;
    let mut f_lo = -target;
    let mut d_lo = 0.0;
    let (mut hi, mut f_hi) = loop {
        let hi = if s_end - lo <= step { s_end } else { lo + step };
        let d = eval(hi, &mut evals)?;
        let is_end = hi >= s_end;
        if is_end && d <= tol_mm {
            return Ok(found(s_end, d, evals, evals, true, false));
        }
        let f = d - target;
        if f.abs() <= half {
            return Ok(found(hi, d, evals, evals, false, false));
        }
        if f > 0.0 {
            break (hi, f);
        }
        lo = hi;
        f_lo = f;
        d_lo = d;
        step *= growth;
        if evals >= opts.max_evaluations {
            return Err(SearchFailure::NoConvergence { s_from, evaluations: evals });
        }
    };
    let bracket_evals = evals;

    // 2. Solve inside (lo, hi), f_lo < 0 < f_hi.
    // Scaled copies of the end errors for the Illinois / Anderson–Björck formulas.
    let (mut g_lo, mut g_hi) = (f_lo, f_hi);
    // Which end the previous iterate replaced: -1 low, +1 high, 0 none yet.
    let mut last_side = 0i8;
    let w_golden = 1.0 - 1.0 / ((1.0 + 5f64.sqrt()) / 2.0);
    loop {
        if hi - lo <= min_width {
            // δ jumps across E within rounding: take the last point below E.
            if lo > s_from {
                return Ok(found(lo, d_lo, evals, bracket_evals, false, true));
            }
            return Err(SearchFailure::Underflow { s_from, error_mm: f_hi + target });
        }
        if evals >= opts.max_evaluations {
            return Err(SearchFailure::NoConvergence { s_from, evaluations: evals });
        }
        let mut x = match opts.method {
            RootMethod::Bisection => 0.5 * (lo + hi),
            RootMethod::Golden => {
                if f_lo.abs() < f_hi.abs() {
                    lo + w_golden * (hi - lo)
                } else {
                    hi - w_golden * (hi - lo)
                }
            }
            RootMethod::Secant => hi - f_hi * (hi - lo) / (f_hi - f_lo),
            RootMethod::Illinois | RootMethod::AndersonBjorck => hi - g_hi * (hi - lo) / (g_hi - g_lo),
        };
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let d = eval(x, &mut evals)?;
        let f = d - target;
        if f.abs() <= half {
            return Ok(found(x, d, evals, bracket_evals, false, false));
        }
        let side: i8 = if f < 0.0 { -1 } else { 1 };
        if side == last_side {
            // The other end was kept twice in a row: damp its error.
            let replaced = if side < 0 { f_lo } else { f_hi };
            let m = match opts.method {
                RootMethod::Illinois => 0.5,
                RootMethod::AndersonBjorck => {
                    let m = 1.0 - f / replaced;
                    if m > 0.0 { m } else { 0.5 }
                }
                _ => 1.0,
            };
            if side < 0 {
                g_hi *= m;
            } else {
                g_lo *= m;
            }
        }
        if side < 0 {
            lo = x;
            f_lo = f;
            g_lo = f;
            d_lo = d;
        } else {
            hi = x;
            f_hi = f;
            g_hi = f;
        }
        last_side = side;
    }
}
