//! The feed plan: the tool's speed along the path, s(t), within every joint's velocity,
//! acceleration and jerk limits, the programmed feed, and the look-ahead window.
//!
//! **Jerk-free settings** (no axis limits jerk): time-optimal path parameterisation by
//! reachability on the pieces (the method of TOPP-RA, Pham & Pham, IEEE T-RO 34(3), 2018).
//! In x = ṡ² and u = s̈ a joint's acceleration is q'(s)·u + q''(s)·x; over a piece the
//! planner holds u constant (x linear in s) and asks, for every joint,
//! max over the piece of |q'·u + q''·x| ≤ a_max with q', q'' replaced by their bounds on the
//! piece ([`super::path::Bounds`]) — linear in (u, x), so holding at both ends of the piece
//! it holds all along. A backward pass finds the largest x from which the rest can still
//! be done (ending at rest), a forward pass takes the largest u that stays within it. The
//! joint velocities bound x by v_max²/q'², the feed by F².
//!
//! **Jerk-limited settings**: each piece gets a tangential acceleration A and jerk J and a
//! speed cap V such that any motion with ṡ ≤ V, |s̈| ≤ A, |s⃛| ≤ J on it keeps every joint
//! within its limits: with q̇ = q'ṡ, q̈ = q''ṡ² + q's̈, q⃛ = q'''ṡ³ + 3q''ṡs̈ + q's⃛, a curved
//! piece gives half of each joint's acceleration to the tangent (A = ½a/|q'|) and half to
//! the normal (V² ≤ ½a/|q''|), half its jerk to the tangent (J = ½j/|q'|), a quarter to
//! q'''V³ and a quarter to 3q''VA; a straight piece gives all to the tangent. An
//! acceleration-limited plan over these (the passes above with constant A) gives the speed
//! levels; its *knots* — where its acceleration is zero: plateaus, peaks, troughs, stops —
//! become the ends of S-curve segments ([`super::scurve`]) with the least A and J of the
//! pieces they span, their speeds lowered by passes until every segment's ramps fit. An
//! S-curve that starts where the acceleration-limited plan starts a rise, and accelerates
//! at most as hard, stays below it, so below every cap (docs/feed-planning.md).
//!
//! **Look-ahead window** of N blocks: within block b the speed must also allow a stop at the
//! end of block b + N − 1 (a controller that sees N blocks must be able to stop where its
//! buffer ends), computed by a backward pass per block (O(N) pieces each).

use std::borrow::Cow;

use super::machine::JointLimits;
use super::path::{Bounds, MIN_MOVE, Path, Piece, Shape, lower, piece_bounds, upper};
use super::scurve::{self, Phase};
use crate::numerics::tolerance::ROUNDING_REL;

/// Relative slack of the comparisons that decide whether a piece's speed can rise to a peak
/// and fall again within it (lengths against the piece's length, peak against end speeds):
/// absorbs the rounding of quantities formed differently.
const PEAK_SLACK_REL: f64 = 1e-12;
/// Floor added to the speed term of a trend's tolerance, so two zero speeds compare flat.
const TREND_FLOOR: f64 = 1e-12;

/// A phase of the plan placed in time and along the path.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimedPhase {
    /// Start time (s).
    pub t0: f64,
    /// Path position at the start (mm).
    pub s0: f64,
    /// Speed at the start (mm/s).
    pub v0: f64,
    /// The phase (duration, starting acceleration, jerk).
    pub phase: Phase,
}

impl TimedPhase {
    /// s, ṡ, s̈ at time `t` within the phase (clamped to it).
    #[must_use]
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let dt = (t - self.t0).clamp(0.0, self.phase.dur);
        let Phase { a0, j, .. } = self.phase;
        (
            self.s0 + self.v0 * dt + 0.5 * a0 * dt * dt + j * dt * dt * dt / 6.0,
            self.v0 + a0 * dt + 0.5 * j * dt * dt,
            a0 + j * dt,
        )
    }
}

/// Options of the planner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeedOptions {
    /// Joint limits.
    pub limits: JointLimits,
    /// Look-ahead window (blocks); `None` the whole program.
    pub window: Option<usize>,
    /// Share of a curved piece's acceleration and jerk given to the tangent (0.5).
    pub tangent_share: f64,
}

/// Per-piece limits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PieceLimits {
    /// Speed cap squared (mm²/s²).
    pub x_cap: f64,
    /// Tangential acceleration (mm/s²).
    pub a: f64,
    /// Tangential jerk (mm/s³; ∞ when not limited).
    pub j: f64,
    /// A straight piece: q' constant, q'' = 0 (the tangential model is exact on it).
    pub line: bool,
}

/// The planned motion.
#[derive(Clone, Debug, Default)]
pub struct FeedPlan {
    /// Phases in time order; dwells are phases at rest.
    pub phases: Vec<TimedPhase>,
    /// Total time (s), dwells included.
    pub duration: f64,
    /// True when planned with jerk limits (S-curves).
    pub jerk_limited: bool,
    /// The acceleration-limited plan as (s, ṡ) points (the S-curves' guide in jerk mode).
    pub guide: Vec<(f64, f64)>,
}

fn cap_of(b: &Bounds, feed: f64, lim: &JointLimits, share: f64, curved: bool) -> PieceLimits {
    let mut v = feed;
    let mut a = f64::INFINITY;
    let mut j = f64::INFINITY;
    let (ta, tj) = if curved { (share, share) } else { (1.0, 1.0) };
    for i in 0..6 {
        let q1 = b.lo1[i].abs().max(b.hi1[i].abs());
        let q2 = b.lo2[i].abs().max(b.hi2[i].abs());
        if q1 > 0.0 {
            v = lower(v, lim.v[i] / q1);
            a = lower(a, ta * lim.a[i] / q1);
            j = lower(j, tj * lim.j[i] / q1);
        }
        if q2 > 0.0 {
            v = lower(v, ((1.0 - ta) * lim.a[i] / q2).sqrt());
        }
    }
    if curved && !j.is_infinite() {
        // A quarter of each joint's jerk for the q''' v^3 term, a quarter for 3 q'' v a:
        // the speed takes the first, the tangential acceleration gives way for the second
        // (corners are short; their speed matters more than how fast it changes there).
        let mut cube = f64::INFINITY;
        for i in 0..6 {
            if b.m3[i] > 0.0 {
                cube = lower(cube, 0.5 * (1.0 - tj) * lim.j[i] / b.m3[i]);
            }
        }
        // The cube root only where it can bind: at or above v³ (with a margin for the
        // rounding of v³ and of the root) it is at least v.
        if cube.is_finite() && !(cube >= v * v * v * (1.0 + 16.0 * f64::EPSILON)) {
            v = lower(v, scurve::cbrt(cube));
        }
        for i in 0..6 {
            let q2 = b.lo2[i].abs().max(b.hi2[i].abs());
            let rest = 0.5 * (1.0 - tj) * lim.j[i];
            if q2 > 0.0 && v > 0.0 {
                a = lower(a, rest / (3.0 * q2 * v));
            }
        }
    }
    PieceLimits { x_cap: v * v, a, j, line: !curved }
}

/// Plans the feed over a path.
#[must_use]
pub fn plan(path: &Path, opts: &FeedOptions) -> FeedPlan {
    let jerk = !opts.limits.jerk_free();
    let (pieces, bounds, lims) = work_pieces(path, opts, jerk);
    let n = pieces.len();
    // Stops: piece boundaries where v = 0.
    let mut stop = vec![false; n + 1];
    stop[0] = true;
    stop[n] = true;
    for k in 0..n {
        let e = &path.elems[pieces[k].elem as usize];
        let last_of_elem = k + 1 == n || pieces[k + 1].elem != pieces[k].elem;
        if last_of_elem && e.stop_after {
            stop[k + 1] = true;
        }
    }
    let pieces = &pieces[..];
    let model = if jerk {
        Model::Tangential(&lims)
    } else {
        Model::Coupled { bounds: &bounds, lims: &lims, a: &opts.limits.a }
    };
    let hs: Vec<f64> = pieces.iter().map(|p| p.h).collect();
    let mut env = backward(&model, &hs, &stop, 0, n);
    if let Some(w) = opts.window {
        window_limit(path, pieces, &model, &hs, &stop, w, &mut env);
    }
    let x = forward(&model, &hs, &env);
    let guide = guide(path, pieces, &lims, &hs, &x, jerk);
    let mut out = FeedPlan { jerk_limited: jerk, ..FeedPlan::default() };
    if jerk {
        scurves(path, pieces, &lims, &guide, &stop, &mut out);
    } else {
        trapezoids(path, &guide, &mut out);
    }
    out.guide = guide.iter().map(|g| (g.s, g.x.sqrt())).collect();
    out
}

/// Most planning pieces one path piece is cut into.
const MAX_SUBPIECES: usize = 64;
/// Most planning pieces of a jerk-free plan after cutting (about 0.5 kB each: bounds, limits,
/// the envelope and the phases). On a path that would pass it the later pieces get fewer
/// cuts, each keeping at least one: the bounds then hold over longer pieces, so the feed is
/// lower there and still within the limits.
const MAX_WORK_PIECES: usize = super::path::MAX_PIECES;

/// How many planning pieces a curved path piece needs without jerk limits (1 for a line, or
/// with jerk limits).
fn cuts(p: &Piece, b: &Bounds, l: &PieceLimits, curved: bool, jerk: bool) -> usize {
    if jerk || !curved || !(l.a > 0.0) || !l.x_cap.is_finite() {
        return 1;
    }
    let ramp = l.x_cap / (2.0 * l.a);
    let by_ramp = if ramp > 0.0 { (4.0 * p.h / ramp).ceil() as usize } else { 1 };
    // The bounds hold over the whole piece: where q'' changes much along it (a blend's
    // curvature rises from zero to its peak), cut it so each part's range is at most 20 % of
    // the largest |q''|.
    let top = (0..6).fold(0.0f64, |m, i| m.max(b.lo2[i].abs()).max(b.hi2[i].abs()));
    let spread = (0..6).fold(0.0f64, |m, i| m.max(b.hi2[i] - b.lo2[i]));
    let by_curv = if top > 0.0 { (spread / (0.2 * top)).ceil() as usize } else { 1 };
    by_ramp.max(by_curv).clamp(1, MAX_SUBPIECES)
}

/// The pieces the planner works on, their bounds (jerk-free settings) and limits. Without
/// jerk limits the speed is constant-acceleration per curved piece, so a curved piece longer
/// than a quarter of the distance it needs to reach its cap from rest is cut into as many
/// pieces as that takes (at most [`MAX_SUBPIECES`], and [`MAX_WORK_PIECES`] in all); straight
/// pieces may rise and fall inside themselves and are kept whole.
fn work_pieces<'a>(
    path: &'a Path,
    opts: &FeedOptions,
    jerk: bool,
) -> (Cow<'a, [Piece]>, Vec<Bounds>, Vec<PieceLimits>) {
    let curved_at = |p: &Piece| !matches!(path.elems[p.elem as usize].shape, Shape::Line { .. });
    let limits_of = |p: &Piece, b: &Bounds| {
        let e = &path.elems[p.elem as usize];
        cap_of(b, e.feed, &opts.limits, opts.tangent_share, curved_at(p))
    };
    // The path's own pieces until one is cut (never with jerk limits): no copy.
    let mut cut: Option<Vec<Piece>> = None;
    let mut bounds: Vec<Bounds> = Vec::with_capacity(if jerk { 0 } else { path.pieces.len() });
    let mut lims: Vec<PieceLimits> = Vec::with_capacity(path.pieces.len());
    // Each piece keeps at least one planning piece; cuts beyond it are granted while the
    // pieces after it can still keep theirs within MAX_WORK_PIECES, so a path whose cuts fit
    // is cut exactly as without the cap.
    let mut total = 0usize;
    for (idx, p) in path.pieces.iter().enumerate() {
        let e = &path.elems[p.elem as usize];
        let curved = curved_at(p);
        let b = piece_bounds(path, p);
        let l = limits_of(p, &b);
        let room = MAX_WORK_PIECES.saturating_sub(total + (path.pieces.len() - idx - 1)).max(1);
        let n = cuts(p, &b, &l, curved, jerk).min(room);
        total += n;
        if n == 1 {
            if let Some(c) = &mut cut {
                c.push(*p);
            }
            lims.push(l);
            if !jerk {
                bounds.push(b);
            }
            continue;
        }
        let pieces = cut.get_or_insert_with(|| {
            let mut c = Vec::with_capacity(2 * path.pieces.len());
            c.extend_from_slice(&path.pieces[..idx]);
            c
        });
        let mut s0 = p.s0;
        let dt = (p.tau.1 - p.tau.0) / n as f64;
        for i in 0..n {
            let ta = p.tau.0 + dt * i as f64;
            let tb = if i + 1 == n { p.tau.1 } else { ta + dt };
            let h = if i + 1 == n { p.s0 + p.h - s0 } else { e.length_between(&path.curves, ta, tb, 1) };
            let q = Piece { elem: p.elem, tau: (ta, tb), s0, h };
            let b = piece_bounds(path, &q);
            lims.push(cap_of(&b, e.feed, &opts.limits, opts.tangent_share, curved));
            bounds.push(b);
            pieces.push(q);
            s0 += h;
        }
    }
    let pieces = cut.map_or(Cow::Borrowed(&path.pieces[..]), Cow::Owned);
    (pieces, bounds, lims)
}

enum Model<'a> {
    Tangential(&'a [PieceLimits]),
    Coupled { bounds: &'a [Bounds], lims: &'a [PieceLimits], a: &'a [f64; 6] },
}

impl Model<'_> {
    fn lim(&self, k: usize) -> &PieceLimits {
        match self {
            Self::Tangential(l) | Self::Coupled { lims: l, .. } => &l[k],
        }
    }

    /// Largest x at the start of piece k from which x1 at its end is reachable.
    fn back(&self, k: usize, h: f64, x1: f64) -> f64 {
        let l = self.lim(k);
        let cap = l.x_cap;
        // `cap` is never NaN (a square of a minimum started at the feed), so `lower` is `min`.
        let x1 = lower(cap, x1);
        match self {
            Self::Coupled { bounds, a, .. } if !l.line => {
                let b = &bounds[k];
                let mut u_min = f64::NEG_INFINITY;
                let mut lower = |c: f64, r: f64| {
                    // c·u ≤ r with u ≤ 0: a lower bound when c < 0.
                    if c < 0.0 {
                        // u_min starts at -∞ and never takes a NaN: `upper` is `max`.
                        u_min = upper(u_min, r / c);
                    }
                };
                for i in 0..6 {
                    if a[i].is_infinite() {
                        continue;
                    }
                    let (l1, h1, l2, h2) = (b.lo1[i], b.hi1[i], b.lo2[i], b.hi2[i]);
                    lower(l1, a[i] - h2 * x1);
                    lower(-h1, a[i] + l2 * x1);
                    lower(l1 - 2.0 * h * h2, a[i] - h2 * x1);
                    lower(-h1 + 2.0 * h * l2, a[i] + l2 * x1);
                }
                let u = u_min.min(0.0);
                if u.is_finite() { (x1 - 2.0 * h * u).min(cap) } else { cap }
            }
            _ => lower(cap, x1 + 2.0 * h * l.a),
        }
    }

    /// x at the end of piece k from x0 at its start: as high as the piece allows, at most
    /// `x1_max`.
    fn fwd(&self, k: usize, h: f64, x0: f64, x1_max: f64) -> f64 {
        let l = self.lim(k);
        let cap = lower(l.x_cap, x1_max);
        match self {
            Self::Coupled { bounds, a, .. } if !l.line => {
                let b = &bounds[k];
                let mut u_hi: f64 = (cap - x0) / (2.0 * h);
                if u_hi > 0.0 {
                    let mut upper = |c: f64, r: f64| {
                        if c > 0.0 {
                            // u_hi > 0 here, never NaN: `lower` is `min`.
                            u_hi = lower(u_hi, r / c);
                        }
                    };
                    for i in 0..6 {
                        if a[i].is_infinite() {
                            continue;
                        }
                        let (l1, h1, l2, h2) = (b.lo1[i], b.hi1[i], b.lo2[i], b.hi2[i]);
                        upper(h1, a[i] - h2 * x0);
                        upper(-l1, a[i] + l2 * x0);
                        upper(h1 + 2.0 * h * h2, a[i] - h2 * x0);
                        upper(-l1 - 2.0 * h * l2, a[i] + l2 * x0);
                    }
                    u_hi = u_hi.max(0.0);
                }
                x0 + 2.0 * h * u_hi
            }
            _ => lower(cap, x0 + 2.0 * h * l.a),
        }
    }
}

fn backward(model: &Model<'_>, hs: &[f64], stop: &[bool], from: usize, to: usize) -> Vec<f64> {
    let mut k = Vec::new();
    backward_into(model, hs, stop, from, to, &mut k);
    k
}

/// [`backward`] into `k` (its old contents dropped, its allocation kept).
fn backward_into(model: &Model<'_>, hs: &[f64], stop: &[bool], from: usize, to: usize, k: &mut Vec<f64>) {
    k.clear();
    k.resize(to - from + 1, f64::INFINITY);
    k[to - from] = 0.0;
    for p in (from..to).rev() {
        let x1 = if stop[p + 1] { 0.0 } else { k[p + 1 - from] };
        k[p + 1 - from] = x1;
        k[p - from] = if stop[p] { 0.0 } else { model.back(p, hs[p], x1) };
    }
}

fn window_limit(
    path: &Path,
    pieces: &[Piece],
    model: &Model<'_>,
    hs: &[f64],
    stop: &[bool],
    w: usize,
    env: &mut [f64],
) {
    let n = hs.len();
    let block_of = |k: usize| path.elems[pieces[k].elem as usize].block;
    // First piece of every block.
    let mut starts: Vec<usize> = Vec::new();
    for k in 0..n {
        if k == 0 || block_of(k) != block_of(k - 1) {
            starts.push(k);
        }
    }
    starts.push(n);
    let mut k = Vec::new();
    for bi in 0..starts.len() - 1 {
        let from = starts[bi];
        let to = starts[(bi + w).min(starts.len() - 1)];
        let this_end = starts[bi + 1];
        backward_into(model, hs, stop, from, to, &mut k);
        // Within block bi (its pieces' starts and its end) the speed must allow the stop.
        for p in from..=this_end {
            env[p] = lower(env[p], k[p - from]);
        }
    }
}

fn forward(model: &Model<'_>, hs: &[f64], env: &[f64]) -> Vec<f64> {
    let n = hs.len();
    let mut x: Vec<f64> = vec![0.0; n + 1];
    for k in 0..n {
        let x0 = lower(env[k], x[k]);
        x[k] = x0;
        x[k + 1] = model.fwd(k, hs[k], x0, env[k + 1]).clamp(0.0, env[k + 1]);
    }
    x
}

/// A point of the acceleration-limited plan: path position, ṡ², the piece it lies in.
#[derive(Clone, Copy, Debug)]
struct Pt {
    s: f64,
    x: f64,
    piece: usize,
}

/// The acceleration-limited plan as points joined by straight lines in (s, x = ṡ²) — a
/// constant acceleration between neighbours. On a straight piece (and every piece of the
/// tangential model) the speed may rise and fall inside it: peak
/// x_p = min(cap, (x₀ + x₁)/2 + A·h), reached after (x_p − x₀)/(2A).
fn guide(path: &Path, pieces: &[Piece], lims: &[PieceLimits], hs: &[f64], x: &[f64], jerk: bool) -> Vec<Pt> {
    let n = hs.len();
    // At most three points a piece (its start, the end of a rise, the start of a fall) and
    // the end: reserved once, never grown and copied.
    let mut out = Vec::with_capacity(3 * n + 1);
    for k in 0..n {
        let s0 = pieces[k].s0;
        let h = hs[k];
        let (x0, x1) = (x[k], x[k + 1]);
        out.push(Pt { s: s0, x: x0, piece: k });
        let l = &lims[k];
        let coupled_curve = !jerk && !l.line;
        if h > 0.0 && !coupled_curve && l.a.is_finite() && l.a > 0.0 {
            let xp = lower(l.x_cap, 0.5 * (x0 + x1) + l.a * h);
            let d1 = upper(0.0, (xp - x0) / (2.0 * l.a));
            let d2 = upper(0.0, (xp - x1) / (2.0 * l.a));
            // A rise to the peak that ends inside the piece, and a fall from it that starts
            // inside; the plateau between them is the straight stretch at x_p.
            if d1 + d2 <= h * (1.0 + PEAK_SLACK_REL) {
                let rise = xp > x0 * (1.0 + PEAK_SLACK_REL) && d1 < h;
                let fall = xp > x1 * (1.0 + PEAK_SLACK_REL) && d2 < h;
                if rise && d1 > 0.0 {
                    out.push(Pt { s: s0 + d1, x: xp, piece: k });
                }
                if fall && h - d2 > if rise { d1 } else { 0.0 } {
                    out.push(Pt { s: s0 + h - d2, x: xp, piece: k });
                }
            }
        }
    }
    out.push(Pt { s: path.length, x: x[n], piece: n.saturating_sub(1) });
    out
}

fn trapezoids(path: &Path, guide: &[Pt], out: &mut FeedPlan) {
    let mut t = 0.0;
    out.phases.reserve(guide.len());
    for w in guide.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = b.s - a.s;
        if d > 0.0 {
            let (v0, v1) = (a.x.sqrt(), b.x.sqrt());
            let dur = if v0 + v1 > 0.0 { 2.0 * d / (v0 + v1) } else { 0.0 };
            let u = if dur > 0.0 { (v1 - v0) / dur } else { 0.0 };
            out.phases.push(TimedPhase { t0: t, s0: a.s, v0, phase: Phase { dur, a0: u, j: 0.0 } });
            t += dur;
        }
    }
    out.duration = t;
    insert_dwells(path, out);
}

/// Dwells (G4) as phases at rest where their block stops, later phases shifted.
fn insert_dwells(path: &Path, out: &mut FeedPlan) {
    if path.dwell_s <= 0.0 {
        // No G4 with a time: nothing to insert (and no need to read every element).
        return;
    }
    let mut dwells: Vec<(f64, f64)> = Vec::new();
    for e in &path.elems {
        let d = path.blocks.get(e.block).map_or(0.0, |b| b.dwell_after_s);
        if e.stop_after && d > 0.0 && dwells.last().is_none_or(|l| l.0 < e.s0 + e.len) {
            dwells.push((e.s0 + e.len, d));
        }
    }
    if dwells.is_empty() {
        return;
    }
    let mut phases = Vec::with_capacity(out.phases.len() + dwells.len());
    let mut shift = 0.0;
    let mut next = 0;
    for p in out.phases.drain(..) {
        while next < dwells.len() && p.s0 >= dwells[next].0 - MIN_MOVE && p.v0 == 0.0 {
            let (s, d) = dwells[next];
            phases.push(TimedPhase {
                t0: p.t0 + shift,
                s0: s.min(p.s0),
                v0: 0.0,
                phase: Phase { dur: d, a0: 0.0, j: 0.0 },
            });
            shift += d;
            next += 1;
        }
        phases.push(TimedPhase { t0: p.t0 + shift, ..p });
    }
    while next < dwells.len() {
        let (s, d) = dwells[next];
        phases.push(TimedPhase { t0: out.duration + shift, s0: s, v0: 0.0, phase: Phase { dur: d, a0: 0.0, j: 0.0 } });
        shift += d;
        next += 1;
    }
    out.phases = phases;
    out.duration += shift;
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Trend {
    Up,
    Flat,
    Down,
}

fn scurves(path: &Path, pieces: &[Piece], lims: &[PieceLimits], g: &[Pt], stop: &[bool], out: &mut FeedPlan) {
    let m = g.len();
    if m < 2 {
        return;
    }
    let trend = |i: usize| {
        let d = g[i + 1].x - g[i].x;
        let tol = ROUNDING_REL * (g[i + 1].x.max(g[i].x) + TREND_FLOOR);
        if g[i + 1].s <= g[i].s {
            None
        } else if d > tol {
            Some(Trend::Up)
        } else if d < -tol {
            Some(Trend::Down)
        } else {
            Some(Trend::Flat)
        }
    };
    let is_stop = |i: usize| {
        let p = &g[i];
        p.x <= 0.0 && (i == 0 || i + 1 == m || (p.piece < stop.len() && (stop[p.piece] || stop[p.piece + 1])))
    };
    // Runs of one trend along the plan, then the knots: every trough (a fall turning into a
    // rise), both ends of every plateau that is not a peak (a shoulder, or a trough held
    // for a while: a cap the S-curves must not cross), and the stops; a peak — a rise
    // turning into a fall, with or without a plateau between — is not a knot: one S-curve
    // segment runs from trough to trough through it, its peak at most the plan's.
    // Each run as its trend and the guide point it ends at.
    let mut runs: Vec<(Trend, usize)> = Vec::with_capacity(m - 1);
    for i in 0..m - 1 {
        let Some(tr) = trend(i) else { continue };
        match runs.last_mut() {
            Some(r) if r.0 == tr => r.1 = i + 1,
            _ => runs.push((tr, i + 1)),
        }
    }
    let peak_flat = |r: usize| {
        runs[r].0 == Trend::Flat
            && r > 0
            && r + 1 < runs.len()
            && runs[r - 1].0 == Trend::Up
            && runs[r + 1].0 == Trend::Down
    };
    let mut knots: Vec<usize> = Vec::with_capacity(runs.len() + 2);
    knots.push(0);
    for r in 0..runs.len().saturating_sub(1) {
        let (a, b) = (runs[r].0, runs[r + 1].0);
        let at = runs[r].1;
        let knot = (a == Trend::Down && b == Trend::Up)
            || (a == Trend::Flat && !peak_flat(r))
            || (b == Trend::Flat && !peak_flat(r + 1))
            || is_stop(at);
        if knot && *knots.last().unwrap_or(&0) != at {
            knots.push(at);
        }
    }
    if *knots.last().unwrap_or(&0) != m - 1 {
        knots.push(m - 1);
    }
    let mut v: Vec<f64> = knots.iter().map(|&i| g[i].x.max(0.0).sqrt()).collect();
    struct Seg {
        d: f64,
        a: f64,
        j: f64,
        cap: f64,
    }
    let mut segs: Vec<Seg> = Vec::with_capacity(knots.len());
    for w in knots.windows(2) {
        let (i0, i1) = (w[0], w[1]);
        let (pa, pb) = (g[i0].piece, g[i1].piece);
        let mut a = f64::INFINITY;
        let mut j = f64::INFINITY;
        // The pieces the segment touches: from the one holding its start to the one holding
        // its end (a knot on a boundary belongs to the later piece, which the segment does
        // not enter when it ends there).
        let last = if g[i1].s <= pieces.get(pb).map_or(f64::INFINITY, |p| p.s0) && pb > pa { pb - 1 } else { pb };
        for l in &lims[pa..=last.min(lims.len() - 1)] {
            a = lower(a, l.a);
            j = lower(j, l.j);
        }
        let top = g[i0..=i1].iter().fold(0.0f64, |t, p| upper(t, p.x));
        segs.push(Seg { d: g[i1].s - g[i0].s, a, j, cap: top.max(0.0).sqrt() });
    }
    // `reach` capped at the knot's own speed is min(that speed, the uncapped reach) — the
    // speed when a ramp to it fits, which it checks first — without solving for the
    // reach on most segments (falls, and rises that fit).
    for i in 0..segs.len() {
        let s = &segs[i];
        v[i + 1] = scurve::reach(v[i], s.d, s.a, s.j, v[i + 1]);
    }
    for i in (0..segs.len()).rev() {
        let s = &segs[i];
        v[i] = scurve::reach(v[i + 1], s.d, s.a, s.j, v[i]);
    }
    let mut t = 0.0;
    // At most 7 phases a segment (two ramps of 3, a cruise): never grown and copied; the
    // pages beyond the phases written are not touched.
    out.phases.reserve(7 * segs.len());
    let mut ph: Vec<Phase> = Vec::with_capacity(8);
    for (i, s) in segs.iter().enumerate() {
        let (v0, v1) = (v[i], v[i + 1]);
        let cap = s.cap.max(v0).max(v1);
        ph.clear();
        scurve::push_segment(v0, v1, s.d, cap, s.a, s.j, &mut ph);
        let (mut ss, mut vv) = (g[knots[i]].s, v0);
        for p in &ph {
            out.phases.push(TimedPhase { t0: t, s0: ss, v0: vv, phase: *p });
            let d = p.dur;
            ss += vv * d + 0.5 * p.a0 * d * d + p.j * d * d * d / 6.0;
            vv += p.a0 * d + 0.5 * p.j * d * d;
            t += d;
        }
    }
    out.duration = t;
    insert_dwells(path, out);
}
