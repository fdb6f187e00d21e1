//! The path the machine follows, in joint space: a program's canonical motions (or any
//! design curve) as elements — straight lines, circular/helical arcs, NURBS curves — with
//! G01 corners and other junctions blended by curvature-continuous curves within the
//! contour tolerance, cut into *pieces* whose derivative bounds the feed planner reads.
//!
//! Joints q = (X, Y, Z, A, B, C): mm and radians. The path parameter s is the tool-tip arc
//! length (mm) in X Y Z; on a move of the rotary axes alone it is their angle in degrees (the
//! unit such a move's feed is programmed in).
//!
//! A junction between two feed moves is passed at speed only where the path is smooth
//! enough for the limits: where the tangent turns, it is **blended** (a quintic that
//! matches position, tangent and curvature of both neighbours) or, with exact
//! stop or no tolerance, **stopped at**; where only the curvature jumps it is blended too
//! when jerk is limited (an acceleration jump is an infinite jerk) and passed otherwise.

use glam::DVec3;

use super::{PlanError, Stopped};
use crate::gcode::interp::{Canon, FeedMode, Loc, Pose};
use crate::gcode::path::Plane;
use crate::geom::NurbsCurve;
use crate::numerics::tolerance::NEWTON_STEP_REL;

/// Joint values: X, Y, Z (mm), A, B, C (rad).
pub type Q = [f64; 6];

#[inline]
pub(crate) fn add(a: &Q, b: &Q) -> Q {
    std::array::from_fn(|i| a[i] + b[i])
}
#[inline]
pub(crate) fn sub(a: &Q, b: &Q) -> Q {
    std::array::from_fn(|i| a[i] - b[i])
}
#[inline]
pub(crate) fn scale(a: &Q, k: f64) -> Q {
    std::array::from_fn(|i| a[i] * k)
}
#[inline]
pub(crate) fn axpy(k: f64, x: &Q, y: &Q) -> Q {
    std::array::from_fn(|i| k * x[i] + y[i])
}
#[inline]
pub(crate) fn norm3(a: &Q) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
#[inline]
fn dot3(a: &Q, b: &Q) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// The smaller of a running minimum `acc` (never NaN) and `x`: `acc.min(x)` — a NaN `x` is
/// passed over, a tie keeps `acc` — in one compare-and-select instead of `f64::min`'s NaN
/// handling for both operands. The two differ only in the sign of a zero tie.
#[inline]
pub(crate) fn lower(acc: f64, x: f64) -> f64 {
    if x < acc { x } else { acc }
}
/// The larger of a running maximum `acc` (never NaN) and `x`, as [`lower`].
#[inline]
pub(crate) fn upper(acc: f64, x: f64) -> f64 {
    if x > acc { x } else { acc }
}
#[inline]
fn norm_abc(a: &Q) -> f64 {
    (a[3] * a[3] + a[4] * a[4] + a[5] * a[5]).sqrt()
}

/// Joint values of a canonical pose (degrees → radians).
#[must_use]
pub fn q_of(p: &Pose) -> Q {
    let r = std::f64::consts::PI / 180.0;
    [p.xyz.x, p.xyz.y, p.xyz.z, p.abc.x * r, p.abc.y * r, p.abc.z * r]
}

/// Lengths below this (mm, or degrees on rotary-only moves) are no move at all.
pub const MIN_MOVE: f64 = 1e-9;
/// Turns of the tangent below this (rad) are no corner.
pub const MIN_TURN_RAD: f64 = 1e-9;
/// Corners turning by more than this (rad, 175°) reverse the path: stopped at, not blended.
pub const MAX_BLEND_TURN_RAD: f64 = 175.0 * std::f64::consts::PI / 180.0;
/// An arc whose sweep from its start angle to its end angle is below this (rad) ends where it
/// starts: it is a full turn, not none.
const FULL_TURN_SWEEP_RAD: f64 = 1e-12;
/// Margin (in the cosine) by which a blend's turn must be below 15° to take the two-piece
/// shortcut of [`blend_pieces_of_cos`] (some 4e-9 rad, far above the arc cosine's rounding).
const COS_15_SLACK: f64 = 1e-9;
/// Slack (in 15° steps) of a blend's piece count, so a turn of exactly k·15° formed by
/// rounding does not begin one piece more.
const PIECE_COUNT_SLACK: f64 = 1e-9;
/// A jump of a joint's rate (its unit tangent's component, per mm) across a junction larger
/// than this times (1 + |rate|) is a corner; below it, rounding.
const RATE_JUMP_REL: f64 = 1e-12;
/// A jump of a joint's curvature component across a junction larger than this times
/// (1 + |curvature|) needs a blend when jerk is limited.
const CURVATURE_JUMP_REL: f64 = 1e-9;
/// Turns (rad) at or below this get no first guess of the blend's cut length from the
/// line–line deviation (it divides by the turn's sine): the guess is unbounded.
const BLEND_GUESS_MIN_TURN_RAD: f64 = 1e-6;
/// Most pieces of one curve element (arcs of many turns, long NURBS).
pub const MAX_PIECES_PER_ELEMENT: usize = 4096;
/// Most pieces of a path: a line is one, an arc or curve one per 5° its tangent turns (at least
/// four for an arc), a corner's blend one per 15° and one more. The whole plan stays in memory
/// (its path, phases and per-block times): 140–700 bytes a piece as measured (the most where
/// the path stops at every corner: five to seven phases a piece), so at most about 1 GB.
/// [`build`] counts the pieces as it reads, a blend at the most its corner's turn can give,
/// and refuses at the line that passes this.
pub const MAX_PIECES: usize = 1_500_000;

/// A circular or helical arc (with a radius that may change linearly, as controllers allow
/// within their arc tolerance), with the rotary axes moving linearly; τ ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcShape {
    /// Centre (mm) at the start's normal coordinate.
    pub centre: DVec3,
    /// In-plane unit axes and the plane normal.
    pub e1: DVec3,
    /// Second in-plane axis (e1 turned 90° about `w`).
    pub e2: DVec3,
    /// Plane normal.
    pub w: DVec3,
    /// Start angle (rad, from e1 toward e2).
    pub theta0: f64,
    /// Signed sweep (rad; positive counter-clockwise about w).
    pub sweep: f64,
    /// Radius at the start and its change to the end (mm).
    pub r0: f64,
    /// Radius change over the arc (mm).
    pub dr: f64,
    /// Advance along w (mm).
    pub dn: f64,
    /// Rotary joints at the start and their change (rad).
    pub abc0: [f64; 3],
    /// Change of the rotary joints over the arc (rad).
    pub dabc: [f64; 3],
}

/// The geometry of one element, evaluated in its own parameter τ.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// q = a + (s/len)(b − a); τ is s.
    Line {
        /// Start joints.
        a: Q,
        /// End joints.
        b: Q,
    },
    /// τ ∈ [0, 1] (boxed: the enum stays the size of a line).
    Arc(Box<ArcShape>),
    /// A NURBS curve of the path's list (`curve`), rotary joints fixed; τ is its parameter.
    Nurbs {
        /// Index into [`Path::curves`].
        curve: usize,
        /// Rotary joints (rad).
        abc: [f64; 3],
    },
    /// A quintic Bézier in joint space, τ ∈ [0, 1] (a blend), held in power form:
    /// q(τ) = Σ c_k τ^k, evaluated by Horner's rule.
    Bezier(Box<[Q; 6]>),
}

/// What an element is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElemKind {
    /// A rapid traverse (G0).
    Rapid,
    /// A programmed feed move (G1, G2/G3, a spline).
    Feed,
    /// A blend the planner put between two feed moves.
    Blend,
}

/// One element of the path.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Geometry.
    pub shape: Shape,
    /// Kind.
    pub kind: ElemKind,
    /// Parameter range used (lines: [0, len]).
    pub tau: (f64, f64),
    /// Length (mm; degrees on rotary-only moves).
    pub len: f64,
    /// Path position of the start (mm).
    pub s0: f64,
    /// Programmed speed cap (mm/s; ∞ for rapids).
    pub feed: f64,
    /// Index of the block (canonical motion) it belongs to; a blend belongs to the block
    /// it leaves.
    pub block: usize,
    /// The path stops (v = 0) at the end of this element.
    pub stop_after: bool,
}

/// One planned block: a canonical motion of the program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// Source line (1-based, in `file`).
    pub line: u32,
    /// Source file: 0 the main program, subroutine files numbered as the interpreter opened
    /// them ([`crate::gcode::interp::Loc::file`]).
    pub file: u16,
    /// Rapid or feed.
    pub rapid: bool,
    /// Programmed length (mm; degrees on rotary-only moves).
    pub len: f64,
    /// Where the block begins on the planned path (mm): its first element's start, or the
    /// middle of the blend it is entered through.
    pub s_start: f64,
    /// Seconds of dwell after it (G4).
    pub dwell_after_s: f64,
}

/// A piece: a sub-interval of one element over which the planner holds bounds constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Element index.
    pub elem: u32,
    /// Parameter range within the element.
    pub tau: (f64, f64),
    /// Path position of the start (mm).
    pub s0: f64,
    /// Length (mm).
    pub h: f64,
}

/// Bounds of the path derivatives over a piece, per joint: q' = dq/ds in [lo1, hi1],
/// q'' in [lo2, hi2], |q'''| ≤ m3.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Bounds {
    /// Lower bound of q'.
    pub lo1: Q,
    /// Upper bound of q'.
    pub hi1: Q,
    /// Lower bound of q''.
    pub lo2: Q,
    /// Upper bound of q''.
    pub hi2: Q,
    /// Bound of |q'''|.
    pub m3: Q,
}

/// A path ready for planning.
#[derive(Clone, Debug, Default)]
pub struct Path {
    /// Elements in order.
    pub elems: Vec<Element>,
    /// Pieces in order (each element's pieces contiguous).
    pub pieces: Vec<Piece>,
    /// The NURBS curves of the spline elements ([`Shape::Nurbs`]'s `curve` indexes it).
    pub curves: Vec<NurbsCurve>,
    /// The pieces counted as the program was read, each blend at the most its corner's turn
    /// gives (≥ `pieces.len()`; equal on a path of lines whose corners are all blended and
    /// turn by other than whole 15° steps); the count [`MAX_PIECES`] holds.
    pub pieces_bound: usize,
    /// The program's blocks.
    pub blocks: Vec<Block>,
    /// Total length (mm).
    pub length: f64,
    /// Dwell time (s) in the program.
    pub dwell_s: f64,
    /// Tool changes and program stops (stops of the path, no time added).
    pub stops: usize,
    /// Largest blend deviation from the programmed path measured when blending (mm).
    pub max_blend_dev: f64,
    /// Corners blended.
    pub blends: usize,
    /// The programmed end (joints): the last motion's end.
    pub end: Q,
    /// Junctions stopped at (corners without a blend, mode changes).
    pub corner_stops: usize,
}

/// How junctions are treated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JunctionRules {
    /// Contour tolerance P (mm); 0 stops at every corner.
    pub tol_mm: f64,
    /// Stop at every corner (G61).
    pub exact_stop: bool,
    /// Jerk is limited: curvature jumps must be blended or stopped at.
    pub jerk_limited: bool,
}

impl Shape {
    /// q, dq/dτ, d²q/dτ² at τ.
    #[must_use]
    pub fn eval(&self, curves: &[NurbsCurve], t: f64) -> [Q; 3] {
        match self {
            Self::Line { a, b } => {
                // τ is not s here: callers of lines use `Element::at`.
                let d = sub(b, a);
                [axpy(t, &d, a), d, [0.0; 6]]
            }
            Self::Arc(c) => {
                let th = c.theta0 + c.sweep * t;
                let (sn, cs) = th.sin_cos();
                let r = c.r0 + c.dr * t;
                let radial = c.e1 * cs + c.e2 * sn;
                let tang = c.e2 * cs - c.e1 * sn;
                let p = c.centre + radial * r + c.w * (c.dn * t);
                let d1 = radial * c.dr + tang * (r * c.sweep) + c.w * c.dn;
                let d2 = tang * (2.0 * c.dr * c.sweep) - radial * (r * c.sweep * c.sweep);
                [
                    [p.x, p.y, p.z, c.abc0[0] + c.dabc[0] * t, c.abc0[1] + c.dabc[1] * t, c.abc0[2] + c.dabc[2] * t],
                    [d1.x, d1.y, d1.z, c.dabc[0], c.dabc[1], c.dabc[2]],
                    [d2.x, d2.y, d2.z, 0.0, 0.0, 0.0],
                ]
            }
            Self::Nurbs { curve, abc } => {
                let [p, d1, d2] = curves.get(*curve).map_or([DVec3::ZERO; 3], |c| c.derivatives_at(t));
                [
                    [p.x, p.y, p.z, abc[0], abc[1], abc[2]],
                    [d1.x, d1.y, d1.z, 0.0, 0.0, 0.0],
                    [d2.x, d2.y, d2.z, 0.0, 0.0, 0.0],
                ]
            }
            Self::Bezier(c) => power5(c, t),
        }
    }
}

/// The power-form coefficients of a quintic Bézier from its control points.
fn power_of(b: &[Q; 6]) -> [Q; 6] {
    std::array::from_fn(|k| {
        std::array::from_fn(|i| {
            let p = |j: usize| b[j][i];
            match k {
                0 => p(0),
                1 => 5.0 * (p(1) - p(0)),
                2 => 10.0 * (p(2) - 2.0 * p(1) + p(0)),
                3 => 10.0 * (p(3) - 3.0 * p(2) + 3.0 * p(1) - p(0)),
                4 => 5.0 * (p(4) - 4.0 * p(3) + 6.0 * p(2) - 4.0 * p(1) + p(0)),
                _ => p(5) - 5.0 * p(4) + 10.0 * p(3) - 10.0 * p(2) + 5.0 * p(1) - p(0),
            }
        })
    })
}

/// q, q_τ, q_ττ of a quintic in power form (Horner).
#[inline]
fn power5(c: &[Q; 6], t: f64) -> [Q; 3] {
    let mut p = [0.0; 6];
    let mut d1 = [0.0; 6];
    let mut d2 = [0.0; 6];
    for i in 0..6 {
        p[i] = ((((c[5][i] * t + c[4][i]) * t + c[3][i]) * t + c[2][i]) * t + c[1][i]) * t + c[0][i];
        d1[i] = (((5.0 * c[5][i] * t + 4.0 * c[4][i]) * t + 3.0 * c[3][i]) * t + 2.0 * c[2][i]) * t + c[1][i];
        d2[i] = ((20.0 * c[5][i] * t + 12.0 * c[4][i]) * t + 6.0 * c[3][i]) * t + 2.0 * c[2][i];
    }
    [p, d1, d2]
}

/// A quintic Bézier and its first two derivatives (de Casteljau on the hodographs).
fn bezier5(b: &[Q; 6], t: f64) -> [Q; 3] {
    let u = 1.0 - t;
    // Bernstein basis of degree 5, 4, 3.
    let b5 = [
        u.powi(5),
        5.0 * t * u.powi(4),
        10.0 * t * t * u.powi(3),
        10.0 * t.powi(3) * u * u,
        5.0 * t.powi(4) * u,
        t.powi(5),
    ];
    let b4 = [u.powi(4), 4.0 * t * u.powi(3), 6.0 * t * t * u * u, 4.0 * t.powi(3) * u, t.powi(4)];
    let b3 = [u.powi(3), 3.0 * t * u * u, 3.0 * t * t * u, t.powi(3)];
    let mut p = [0.0; 6];
    let mut d1 = [0.0; 6];
    let mut d2 = [0.0; 6];
    for i in 0..6 {
        for k in 0..6 {
            p[i] += b5[k] * b[k][i];
        }
        for k in 0..5 {
            d1[i] += 5.0 * b4[k] * (b[k + 1][i] - b[k][i]);
        }
        for k in 0..4 {
            d2[i] += 20.0 * b3[k] * (b[k + 2][i] - 2.0 * b[k + 1][i] + b[k][i]);
        }
    }
    [p, d1, d2]
}

/// Derivatives with respect to the path parameter s from those in τ: q' = q_τ/σ,
/// q'' = (q_ττ σ − q_τ σ_τ)/σ³ with σ = ds/dτ (the X Y Z speed, or the rotary speed in
/// degrees on a rotary-only element).
fn in_s(d: &[Q; 3], deg: bool) -> (Q, Q, f64) {
    let (sigma, dsigma) = if deg {
        let k = 180.0 / std::f64::consts::PI;
        let s = norm_abc(&d[1]) * k;
        let ds = if s > 0.0 { (d[1][3] * d[2][3] + d[1][4] * d[2][4] + d[1][5] * d[2][5]) * k * k / s } else { 0.0 };
        (s, ds)
    } else {
        let s = norm3(&d[1]);
        (s, if s > 0.0 { dot3(&d[1], &d[2]) / s } else { 0.0 })
    };
    if sigma <= 0.0 {
        return ([0.0; 6], [0.0; 6], 0.0);
    }
    let q1 = scale(&d[1], 1.0 / sigma);
    let q2: Q = std::array::from_fn(|i| (d[2][i] * sigma - d[1][i] * dsigma) / (sigma * sigma * sigma));
    (q1, q2, sigma)
}

/// Five-point Gauss–Legendre nodes and weights on [−1, 1].
const GL5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

impl Element {
    fn is_deg(&self) -> bool {
        match &self.shape {
            Shape::Line { a, b } => norm3(&sub(b, a)) < MIN_MOVE,
            _ => false,
        }
    }

    /// Speed ds/dτ at τ.
    fn sigma(&self, curves: &[NurbsCurve], t: f64) -> f64 {
        if let Shape::Bezier(c) = &self.shape {
            // Only the first derivative's X Y Z (Horner).
            let mut d = [0.0; 3];
            for i in 0..3 {
                d[i] = (((5.0 * c[5][i] * t + 4.0 * c[4][i]) * t + 3.0 * c[3][i]) * t + 2.0 * c[2][i]) * t + c[1][i];
            }
            return (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        }
        if let Shape::Arc(c) = &self.shape {
            // dq/dτ's X Y Z is radial·dr + tangent·(r·sweep) + w·dn over orthonormal axes,
            // so its length needs no sine or cosine (they were most of an arc's table).
            let r = c.r0 + c.dr * t;
            let v = r * c.sweep;
            return (c.dr * c.dr + v * v + c.dn * c.dn).sqrt();
        }
        let d = self.shape.eval(curves, t);
        if self.is_deg() { norm_abc(&d[1]) * 180.0 / std::f64::consts::PI } else { norm3(&d[1]) }
    }

    /// Arc length from τa to τb (Gauss–Legendre, 5 points; `n` equal sub-intervals).
    #[must_use]
    pub fn length_between(&self, curves: &[NurbsCurve], ta: f64, tb: f64, n: usize) -> f64 {
        if let Shape::Line { .. } = self.shape {
            return tb - ta;
        }
        let n = n.max(1);
        let h = (tb - ta) / n as f64;
        let mut sum = 0.0;
        for k in 0..n {
            let m = ta + h * (k as f64 + 0.5);
            for (x, w) in GL5 {
                sum += w * self.sigma(curves, m + 0.5 * h * x);
            }
        }
        sum * 0.5 * h
    }

    /// q, q', q'' at parameter τ (derivatives in s).
    #[must_use]
    pub fn at_tau(&self, curves: &[NurbsCurve], t: f64) -> (Q, Q, Q) {
        match &self.shape {
            Shape::Line { a, b } => {
                let d = scale(&sub(b, a), 1.0 / self.len);
                let p = if t >= self.len { *b } else { axpy(t, &d, a) };
                (p, d, [0.0; 6])
            }
            s => {
                let d = s.eval(curves, t);
                let (q1, q2, _) = in_s(&d, false);
                (d[0], q1, q2)
            }
        }
    }

    /// τ at element-local arc length `s` from a known point (τ_ref, s_ref): Newton on
    /// the Gauss–Legendre length.
    #[must_use]
    pub fn tau_at(&self, curves: &[NurbsCurve], s: f64, t_ref: f64, s_ref: f64) -> f64 {
        if let Shape::Line { .. } = self.shape {
            return s;
        }
        let (lo, hi) = (self.tau.0.min(self.tau.1), self.tau.0.max(self.tau.1));
        let mut t = t_ref;
        let sig = self.sigma(curves, t);
        if sig > 0.0 {
            t = (t + (s - s_ref) / sig).clamp(lo, hi);
        }
        for _ in 0..8 {
            let err = s_ref + self.length_between(curves, t_ref, t, 1) - s;
            let sig = self.sigma(curves, t);
            if sig <= 0.0 {
                break;
            }
            let step = err / sig;
            t = (t - step).clamp(lo, hi);
            if step.abs() <= NEWTON_STEP_REL * (1.0 + t.abs()) {
                break;
            }
        }
        t
    }
}

/// The programmed geometry of one canonical motion.
struct Raw {
    shape: Shape,
    rapid: bool,
    len: f64,
    feed: f64,
    block: usize,
    /// The path stops after it (a dwell, tool change, program stop, or the next motion is
    /// of the other kind).
    stop_after: bool,
    /// Parameter range.
    tau: (f64, f64),
    /// Arc-length table at piece boundaries: (τ, s) from start to end.
    table: Vec<(f64, f64)>,
    trim_start: f64,
    trim_end: f64,
}

impl Raw {
    fn elem(&self) -> Element {
        Element {
            shape: self.shape.clone(),
            kind: if self.rapid { ElemKind::Rapid } else { ElemKind::Feed },
            tau: self.tau,
            len: self.len,
            s0: 0.0,
            feed: self.feed,
            block: self.block,
            stop_after: self.stop_after,
        }
    }

    /// τ at element-local arc length s, from the table.
    fn tau_at(&self, curves: &[NurbsCurve], s: f64) -> f64 {
        if let Shape::Line { .. } = self.shape {
            return s.clamp(0.0, self.len);
        }
        let k =
            self.table.partition_point(|&(_, ss)| ss <= s).saturating_sub(1).min(self.table.len().saturating_sub(2));
        let (ta, sa) = self.table[k];
        self.elem().tau_at(curves, s, ta, sa)
    }

    /// q, q', q'' at element-local arc length s.
    fn at_s(&self, curves: &[NurbsCurve], s: f64) -> (Q, Q, Q) {
        if let Shape::Line { a, b } = &self.shape {
            let d = scale(&sub(b, a), 1.0 / self.len);
            let p = if s >= self.len { *b } else { axpy(s, &d, a) };
            return (p, d, [0.0; 6]);
        }
        let e = self.elem();
        e.at_tau(curves, self.tau_at(curves, s))
    }
}

/// Feed cap (mm/s) of a feed motion of length `len`.
fn feed_cap(feed: &crate::gcode::interp::Feed, len: f64, line: u32) -> Result<f64, PlanError> {
    let v = match feed.mode {
        FeedMode::PerMinute => feed.rate / 60.0,
        FeedMode::InverseTime => len * feed.rate / 60.0,
        FeedMode::PerRevolution => feed.rate * feed.spindle_rpm.abs() / 60.0,
    };
    if v.is_finite() && v > 0.0 { Ok(v) } else { Err(PlanError::NoFeed { line }) }
}

/// Builds the arc and its table.
fn arc_shape(start: &Q, end: &Q, centre: DVec3, plane: Plane, turns: i32) -> ArcShape {
    let (ia, ib, inn) = plane.axes();
    let mut e1 = DVec3::ZERO;
    let mut e2 = DVec3::ZERO;
    let mut w = DVec3::ZERO;
    e1[ia] = 1.0;
    e2[ib] = 1.0;
    w[inn] = 1.0;
    let rs = [start[ia] - centre[ia], start[ib] - centre[ib]];
    let re = [end[ia] - centre[ia], end[ib] - centre[ib]];
    let th0 = rs[1].atan2(rs[0]);
    let th1 = re[1].atan2(re[0]);
    let tau = std::f64::consts::TAU;
    let ccw = turns > 0;
    let mut sweep = if ccw { (th1 - th0).rem_euclid(tau) } else { -(th0 - th1).rem_euclid(tau) };
    if sweep.abs() < FULL_TURN_SWEEP_RAD {
        sweep = if ccw { tau } else { -tau };
    }
    let extra = f64::from(turns.unsigned_abs().saturating_sub(1));
    sweep += if ccw { tau * extra } else { -tau * extra };
    let r0 = (rs[0] * rs[0] + rs[1] * rs[1]).sqrt();
    let r1 = (re[0] * re[0] + re[1] * re[1]).sqrt();
    let mut c = centre;
    c[inn] = start[inn];
    ArcShape {
        centre: c,
        e1,
        e2,
        w,
        theta0: th0,
        sweep,
        r0,
        dr: r1 - r0,
        dn: end[inn] - start[inn],
        abc0: [start[3], start[4], start[5]],
        dabc: [end[3] - start[3], end[4] - start[4], end[5] - start[5]],
    }
}

/// Pieces of a curve: breakpoints in τ so that the tangent turns by at most `max_turn` per
/// piece (sampled), at least `min` pieces, NURBS knots always breakpoints.
fn curve_breaks(shape: &Shape, curves: &[NurbsCurve], tau: (f64, f64), min: usize, max_turn: f64) -> Vec<f64> {
    let mut knots: Vec<f64> = vec![tau.0, tau.1];
    if let Shape::Nurbs { curve, .. } = shape
        && let Some(c) = curves.get(*curve)
    {
        {
            knots = c.knots().iter().copied().filter(|k| *k >= tau.0 && *k <= tau.1).collect();
            knots.dedup();
            if knots.first() != Some(&tau.0) {
                knots.insert(0, tau.0);
            }
            if knots.last() != Some(&tau.1) {
                knots.push(tau.1);
            }
        }
    }
    let mut out = vec![tau.0];
    let per_span_min = min.div_ceil(knots.len().saturating_sub(1).max(1)).max(1);
    for w in knots.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        // Turn over the span from 8 samples.
        let mut turn = 0.0;
        let mut prev: Option<DVec3> = None;
        for i in 0..=8 {
            let d = shape.eval(curves, a + (b - a) * f64::from(i) / 8.0);
            let t = DVec3::new(d[1][0], d[1][1], d[1][2]).normalize_or_zero();
            if let Some(p) = prev {
                turn += p.dot(t).clamp(-1.0, 1.0).acos();
            }
            prev = Some(t);
        }
        let n = ((turn / max_turn).ceil() as usize).max(per_span_min).min(MAX_PIECES_PER_ELEMENT);
        for i in 1..=n {
            out.push(if i == n { b } else { a + (b - a) * i as f64 / n as f64 });
        }
    }
    out
}

fn table_of(e: &Element, curves: &[NurbsCurve], breaks: &[f64]) -> Vec<(f64, f64)> {
    let mut s = 0.0;
    let mut out = Vec::with_capacity(breaks.len());
    out.push((breaks[0], 0.0));
    for w in breaks.windows(2) {
        s += e.length_between(curves, w[0], w[1], 2);
        out.push((w[1], s));
    }
    out
}

/// cos 15° (rounded to nearest): the first step of a blend's piece count.
const COS_15_DEG: f64 = 0.965_925_826_289_068_3;

/// A blend's pieces from the cosine of its end tangents' turn: one, and one per 15° of the
/// turn begun — `1 + ⌈acos(cos)/15°⌉`, with the arc cosine only where the count is not plain:
/// below 15° by a clear margin (1e-9 in the cosine, some 4e-9 rad, far above acos' rounding)
/// the turn takes one step, and none at all when the tangents agree.
fn blend_pieces_of_cos(cos: f64) -> usize {
    if cos >= 1.0 {
        1
    } else if cos > COS_15_DEG + COS_15_SLACK {
        2
    } else {
        1 + (cos.acos() / (15f64).to_radians()).ceil() as usize
    }
}

/// Deviation of a line–line blend from its legs per unit cut length m and sin φ.
pub const LINE_BLEND_DEV: f64 = 0.234_375;

/// Largest turn of an arc's or NURBS' tangent per piece (rad, 5°).
const PIECE_TURN_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Reads canonical motions into a path: elements, blends, pieces, blocks.
///
/// # Errors
/// [`PlanError`] for a feed move without a feed, or a path beyond the caps.
pub fn build<I>(canon: I, rules: &JunctionRules) -> Result<Path, PlanError>
where
    I: IntoIterator<Item = Canon>,
{
    build_read(canon.into_iter().map(Ok::<Canon, std::convert::Infallible>), rules).map_err(|e| match e {
        Stopped::Plan(e) => e,
        Stopped::Read(never) => match never {},
    })
}

/// As [`build`], over motions read as the path is built (an interpreter streaming a file):
/// the first read error stops it, and is returned, before any more work.
///
/// # Errors
/// [`Stopped::Read`] with the reader's error, or [`Stopped::Plan`] as [`build`].
pub fn build_read<I, E>(canon: I, rules: &JunctionRules) -> Result<Path, Stopped<E>>
where
    I: IntoIterator<Item = Result<Canon, E>>,
{
    let mut path = Path::default();
    let canon = canon.into_iter();
    let mut raws: Vec<Raw> = Vec::with_capacity(canon.size_hint().0.min(MAX_PIECES));
    path.blocks.reserve(raws.capacity());
    let mut pos: Q = [0.0; 6];
    let mut pieces = 0usize;
    for c in canon {
        let c = c.map_err(Stopped::Read)?;
        let loc = c.loc();
        let line = loc.line;
        match c {
            Canon::Traverse { end, .. } | Canon::Line { end, .. } => {
                let q = q_of(&end);
                let d = sub(&q, &pos);
                let lxyz = norm3(&d);
                let len = if lxyz >= MIN_MOVE { lxyz } else { norm_abc(&d) * 180.0 / std::f64::consts::PI };
                if len >= MIN_MOVE {
                    let rapid = matches!(c, Canon::Traverse { .. });
                    let feed = match &c {
                        Canon::Line { feed, .. } => feed_cap(feed, len, line)?,
                        _ => f64::INFINITY,
                    };
                    push_raw(
                        &mut raws,
                        &mut path,
                        Shape::Line { a: pos, b: q },
                        rapid,
                        len,
                        feed,
                        loc,
                        (0.0, len),
                        None,
                        (&mut pieces, rules),
                    )?;
                }
                pos = q;
            }
            Canon::Arc { end, center, plane, turns, feed, .. } => {
                let q = q_of(&end);
                let arc = arc_shape(&pos, &q, center, plane, turns);
                let shape = Shape::Arc(Box::new(arc));
                let probe = Element {
                    shape: shape.clone(),
                    kind: ElemKind::Feed,
                    tau: (0.0, 1.0),
                    len: 0.0,
                    s0: 0.0,
                    feed: 0.0,
                    block: 0,
                    stop_after: false,
                };
                let len = probe.length_between(&path.curves, 0.0, 1.0, 16);
                if len >= MIN_MOVE {
                    let f = feed_cap(&feed, len, line)?;
                    push_raw(
                        &mut raws,
                        &mut path,
                        shape,
                        false,
                        len,
                        f,
                        loc,
                        (0.0, 1.0),
                        Some(4),
                        (&mut pieces, rules),
                    )?;
                }
                pos = q;
            }
            Canon::Spline { curve, end, feed, .. } => {
                let q = q_of(&end);
                let (u0, u1) = curve.range();
                path.curves.push(*curve);
                let idx = path.curves.len() - 1;
                let shape = Shape::Nurbs { curve: idx, abc: [pos[3], pos[4], pos[5]] };
                let probe = Element {
                    shape: shape.clone(),
                    kind: ElemKind::Feed,
                    tau: (u0, u1),
                    len: 0.0,
                    s0: 0.0,
                    feed: 0.0,
                    block: 0,
                    stop_after: false,
                };
                let breaks = curve_breaks(&shape, &path.curves, (u0, u1), 1, PIECE_TURN_RAD);
                let len = table_of(&probe, &path.curves, &breaks).last().map_or(0.0, |t| t.1);
                if len >= MIN_MOVE {
                    let f = feed_cap(&feed, len, line)?;
                    push_raw(&mut raws, &mut path, shape, false, len, f, loc, (u0, u1), Some(1), (&mut pieces, rules))?;
                }
                pos = q;
            }
            Canon::Dwell { seconds, .. } => {
                if let Some(r) = raws.last_mut() {
                    r.stop_after = true;
                }
                if let Some(b) = path.blocks.last_mut() {
                    b.dwell_after_s += seconds.max(0.0);
                }
                path.dwell_s += seconds.max(0.0);
            }
            Canon::ToolChange { .. } | Canon::Stop { .. } => {
                if let Some(r) = raws.last_mut() {
                    r.stop_after = true;
                }
                path.stops += 1;
            }
            Canon::Spindle { .. } | Canon::ToolLengthOffset { .. } => {}
        }
    }
    if let Some(r) = raws.last_mut() {
        r.stop_after = true;
    }
    path.end = pos;
    path.pieces_bound = pieces;
    junctions(&mut raws, &mut path, rules);
    Ok(path)
}

#[allow(clippy::too_many_arguments)]
fn push_raw(
    raws: &mut Vec<Raw>,
    path: &mut Path,
    shape: Shape,
    rapid: bool,
    len: f64,
    feed: f64,
    loc: Loc,
    tau: (f64, f64),
    min_pieces: Option<usize>,
    count: (&mut usize, &JunctionRules),
) -> Result<(), PlanError> {
    let (pieces, rules) = count;
    let block = path.blocks.len();
    path.blocks.push(Block { line: loc.line, file: loc.file, rapid, len, s_start: 0.0, dwell_after_s: 0.0 });
    let mut raw = Raw {
        shape,
        rapid,
        len,
        feed,
        block,
        stop_after: false,
        tau,
        table: Vec::new(),
        trim_start: 0.0,
        trim_end: 0.0,
    };
    if let Some(min) = min_pieces {
        let breaks = curve_breaks(&raw.shape, &path.curves, tau, min, PIECE_TURN_RAD);
        let e = raw.elem();
        raw.table = table_of(&e, &path.curves, &breaks);
        if let Some(last) = raw.table.last() {
            raw.len = last.1;
        }
    }
    if let Some(prev) = raws.last_mut()
        && prev.rapid != rapid
    {
        prev.stop_after = true;
    }
    let own = raw.table.len().saturating_sub(1).max(1);
    let blend = raws.last().map_or(0, |prev| blend_pieces_at_most(prev, &raw, &path.curves, rules));
    *pieces = pieces.saturating_add(own + blend);
    if *pieces > MAX_PIECES {
        return Err(PlanError::TooLarge { line: loc.line, max: MAX_PIECES });
    }
    raws.push(raw);
    Ok(())
}

/// The most pieces a blend between `a` and `b` can take: none where the path stops (a rapid,
/// exact stop, a reversal) or goes straight on, else one and one per 15° its end tangents
/// turn (what [`junctions`] gives a blend). Between two lines those are the lines'
/// directions; a curved neighbour is trimmed by at most half its length, over which its
/// tangent turns by at most half its pieces' 5° each, added to the corner's turn. A hair
/// (1e-9 of a 15° step) above keeps the count an upper bound at turns of whole 15° steps.
fn blend_pieces_at_most(a: &Raw, b: &Raw, curves: &[NurbsCurve], rules: &JunctionRules) -> usize {
    if a.stop_after || a.rapid || b.rapid || rules.exact_stop || rules.tol_mm <= 0.0 {
        return 0;
    }
    let (_, ta, _) = a.at_s(curves, a.len);
    let (_, tb, _) = b.at_s(curves, 0.0);
    if norm3(&ta) < 0.5 || norm3(&tb) < 0.5 {
        return 0;
    }
    let turn = (dot3(&ta, &tb) / (norm3(&ta) * norm3(&tb))).clamp(-1.0, 1.0).acos();
    let both_lines = matches!(a.shape, Shape::Line { .. }) && matches!(b.shape, Shape::Line { .. });
    if (both_lines && turn <= MIN_TURN_RAD) || turn > MAX_BLEND_TURN_RAD {
        return 0;
    }
    let half_turn = |r: &Raw| 0.5 * PIECE_TURN_RAD * r.table.len().saturating_sub(1) as f64;
    let ends = (turn + half_turn(a) + half_turn(b)).min(std::f64::consts::PI);
    1 + (ends / (15f64).to_radians() + PIECE_COUNT_SLACK).ceil() as usize
}

/// A quintic Bézier from `pa` to `pb` matching the tangents (dq/ds) `ta`, `tb` and second
/// derivatives `ka`, `kb` there: control points P₀, P₀ + λT₀/5, P₀ + μT₀ + λ²K₀/20 and
/// mirrored. B'(0) = λT₀ and B''(0) = 20(μ − 2λ/5)T₀ + λ²K₀, so d²q/ds² at the end is K₀
/// whatever μ (a tangential second derivative only changes the speed of the parameter): the
/// blend is curvature-continuous with both neighbours for every λ, μ > 0.
#[expect(clippy::too_many_arguments, reason = "two end states and the two shape parameters, read together")]
fn hermite(pa: &Q, ta: &Q, ka: &Q, pb: &Q, tb: &Q, kb: &Q, lambda: f64, mu: f64) -> [Q; 6] {
    let l2 = lambda * lambda;
    [
        *pa,
        axpy(lambda / 5.0, ta, pa),
        add(&axpy(mu, ta, pa), &scale(ka, l2 / 20.0)),
        add(&axpy(-mu, tb, pb), &scale(kb, l2 / 20.0)),
        axpy(-lambda / 5.0, tb, pb),
        *pb,
    ]
}

fn dist_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).length()
}

fn v3(q: &Q) -> DVec3 {
    DVec3::new(q[0], q[1], q[2])
}

/// Samples of the programmed geometry a blend replaces: polylines of the end of `a` and the
/// start of `b` (lines exactly; curves by 16 chords, their sagitta added as a margin).
fn replaced(a: &Raw, b: &Raw, m: f64, curves: &[NurbsCurve]) -> (Vec<DVec3>, f64) {
    let mut pts = Vec::with_capacity(34);
    let mut margin: f64 = 0.0;
    for (r, from, to) in [(a, a.len - m, a.len), (b, 0.0, m)] {
        let n = if let Shape::Line { .. } = r.shape { 1 } else { 16 };
        let start = pts.len();
        for i in 0..=n {
            let s = from + (to - from) * i as f64 / n as f64;
            let (p, _, k) = r.at_s(curves, s);
            pts.push(v3(&p));
            let h = (to - from) / n as f64;
            margin = margin.max(norm3(&k) * h * h / 8.0);
        }
        if start > 0 {
            // Keep the two polylines apart: a NaN marks the break.
            pts.insert(start, DVec3::NAN);
        }
    }
    (pts, margin)
}

/// Largest distance from the blend to the polylines (mm), over 33 samples.
fn deviation(bez: &[Q; 6], poly: &[DVec3], margin: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..=32 {
        let p = v3(&bezier5(bez, f64::from(i) / 32.0)[0]);
        let mut best = f64::INFINITY;
        for w in poly.windows(2) {
            if w[0].is_nan() || w[1].is_nan() {
                continue;
            }
            best = best.min(dist_to_segment(p, w[0], w[1]));
        }
        worst = worst.max(best);
    }
    worst + margin
}

/// Decides and builds every junction's blend, then lays out elements, pieces and blocks.
fn junctions(raws: &mut [Raw], path: &mut Path, rules: &JunctionRules) {
    let n = raws.len();
    let mut blends: Vec<Blend> = vec![None; n];
    for i in 0..n.saturating_sub(1) {
        if raws[i].stop_after || raws[i].rapid || raws[i + 1].rapid {
            if !raws[i].stop_after {
                raws[i].stop_after = true;
            }
            continue;
        }
        let (a, b) = (&raws[i], &raws[i + 1]);
        let (_, ta, ka) = a.at_s(&path.curves, a.len);
        let (_, tb, kb) = b.at_s(&path.curves, 0.0);
        let rot_only = norm3(&ta) < 0.5 || norm3(&tb) < 0.5;
        let cos = (dot3(&ta, &tb) / (norm3(&ta) * norm3(&tb))).clamp(-1.0, 1.0);
        let turn = if rot_only { 0.0 } else { cos.acos() };
        let rate_jump = (3..6).any(|k| (ta[k] - tb[k]).abs() > RATE_JUMP_REL * (1.0 + ta[k].abs()));
        let curv_jump =
            (0..6).any(|k| (ka[k] - kb[k]).abs() > CURVATURE_JUMP_REL * (1.0 + ka[k].abs().max(kb[k].abs())));
        let corner =
            turn > MIN_TURN_RAD || rate_jump || (rot_only && sub(&ta, &tb).iter().any(|x| x.abs() > RATE_JUMP_REL));
        let needs = corner || (rules.jerk_limited && curv_jump);
        if !needs {
            continue;
        }
        if rot_only || rules.exact_stop || rules.tol_mm <= 0.0 || turn > MAX_BLEND_TURN_RAD {
            raws[i].stop_after = true;
            path.corner_stops += 1;
            continue;
        }
        let both_lines = matches!(a.shape, Shape::Line { .. }) && matches!(b.shape, Shape::Line { .. });
        let room_a = 0.5 * a.len;
        let room_b = 0.5 * b.len;
        let tol = rules.tol_mm;
        let guess = if turn > BLEND_GUESS_MIN_TURN_RAD { tol / (0.234 * turn.sin().max(0.05)) } else { f64::INFINITY };
        let mut m = guess.min(room_a).min(room_b);
        let mut done = None;
        if both_lines && turn <= std::f64::consts::FRAC_PI_2 {
            // Closed form: the blend is symmetric, and its deviation from the two legs is
            // largest at its middle, B(½) = C + (u₂ − u₁)·m·(1 + 5·0.7 + 10·0.3)/32, which
            // lies |B(½) − C|·cos(φ/2) = 0.234375·m·sin φ from each leg (checked against a
            // dense scan in the tests).
            m = m.min(0.999 * tol / (LINE_BLEND_DEV * turn.sin()));
            let (pa, ta, ka) = a.at_s(&path.curves, a.len - m);
            let (pb, tb, kb) = b.at_s(&path.curves, m);
            let bez = hermite(&pa, &ta, &ka, &pb, &tb, &kb, 1.5 * m, 0.7 * m);
            done = Some((bez, m, LINE_BLEND_DEV * m * turn.sin()));
        }
        for _ in 0..if done.is_some() { 0 } else { 12 } {
            if m < MIN_MOVE {
                break;
            }
            let (pa, ta, ka) = a.at_s(&path.curves, a.len - m);
            let (pb, tb, kb) = b.at_s(&path.curves, m);
            // Between two lines: control points at 0.3 m and 0.7 m from the corner on each
            // leg (λ = 1.5 m, μ = 0.7 m), the least peak curvature for the deviation among
            // the shapes tried (docs/feed-planning.md: 1.14 times a tangent arc's at a 3°
            // turn, deviation 0.234·m·sin φ). Where a neighbour is curved, λ = the chord and
            // μ = 2λ/5 make the blend follow it (near arc-length speed at both ends).
            let (lambda, mu) = if both_lines {
                (1.5 * m, 0.7 * m)
            } else {
                let c = norm3(&sub(&pb, &pa));
                (c, 0.4 * c)
            };
            let bez = hermite(&pa, &ta, &ka, &pb, &tb, &kb, lambda, mu);
            let (poly, margin) = replaced(a, b, m, &path.curves);
            let dev = deviation(&bez, &poly, margin);
            if dev <= 0.95 * tol {
                done = Some((bez, m, dev));
                break;
            }
            m *= (0.9 * tol / dev).min(0.9);
        }
        match done {
            Some((bez, m, dev)) => {
                raws[i].trim_end = m;
                raws[i + 1].trim_start = m;
                path.max_blend_dev = path.max_blend_dev.max(dev);
                path.blends += 1;
                // The blend's pieces: one per 15° its tangent turns, and one more.
                let cos = {
                    let t0 = v3(&bez[1]) - v3(&bez[0]);
                    let t1 = v3(&bez[5]) - v3(&bez[4]);
                    t0.normalize_or_zero().dot(t1.normalize_or_zero()).clamp(-1.0, 1.0)
                };
                // Below 15° by a clear margin (1e-9 in the cosine, some 4e-9 rad, far above
                // acos' rounding) one step; no turn, none; else from the angle.
                let pieces = blend_pieces_of_cos(cos);
                blends[i] = Some((Box::new(power_of(&bez)), pieces));
            }
            None => {
                raws[i].stop_after = true;
                path.corner_stops += 1;
            }
        }
    }
    layout(raws, blends, path);
}

/// A junction's blend: its power form and the number of pieces it is cut into.
type Blend = Option<(Box<[Q; 6]>, usize)>;

fn layout(raws: &[Raw], mut blends: Vec<Blend>, path: &mut Path) {
    let mut s = 0.0;
    let n_blends = blends.iter().filter(|b| b.is_some()).count();
    path.elems.reserve(raws.len() + n_blends);
    path.pieces.reserve(raws.len() + 2 * n_blends);
    let mut blended_into = false;
    for (i, r) in raws.iter().enumerate() {
        let keep = r.len - r.trim_start - r.trim_end;
        // The block starts where its trimmed move starts, or in the middle of the blend
        // entering it.
        if !blended_into {
            path.blocks[r.block].s_start = s;
        }
        if keep > MIN_MOVE {
            let mut e = r.elem();
            e.s0 = s;
            e.len = keep;
            e.stop_after = r.stop_after && blends[i].is_none();
            let idx = path.elems.len() as u32;
            match &r.shape {
                Shape::Line { a, b } => {
                    let d = scale(&sub(b, a), 1.0 / r.len);
                    let pa = if r.trim_start > 0.0 { axpy(r.trim_start, &d, a) } else { *a };
                    let pb = if r.trim_end > 0.0 { axpy(r.len - r.trim_end, &d, a) } else { *b };
                    e.shape = Shape::Line { a: pa, b: pb };
                    e.tau = (0.0, keep);
                    path.pieces.push(Piece { elem: idx, tau: (0.0, keep), s0: s, h: keep });
                }
                _ => {
                    let t0 = if r.trim_start > 0.0 { r.tau_at(&path.curves, r.trim_start) } else { r.tau.0 };
                    let t1 = if r.trim_end > 0.0 { r.tau_at(&path.curves, r.len - r.trim_end) } else { r.tau.1 };
                    e.tau = (t0, t1);
                    // Pieces: the table's intervals inside [t0, t1].
                    let mut prev_t = t0;
                    let mut prev_s = r.trim_start;
                    for &(tk, sk) in &r.table {
                        if tk <= t0 {
                            continue;
                        }
                        let (tk, sk) = if tk >= t1 { (t1, r.len - r.trim_end) } else { (tk, sk) };
                        if sk - prev_s > 0.0 {
                            path.pieces.push(Piece {
                                elem: idx,
                                tau: (prev_t, tk),
                                s0: s + prev_s - r.trim_start,
                                h: sk - prev_s,
                            });
                        }
                        prev_t = tk;
                        prev_s = sk;
                        if tk >= t1 {
                            break;
                        }
                    }
                }
            }
            path.elems.push(e);
            s += keep;
        }
        blended_into = blends[i].is_some();
        if let Some((power, n)) = blends[i].take() {
            let e0 = Element {
                shape: Shape::Bezier(power),
                kind: ElemKind::Blend,
                tau: (0.0, 1.0),
                len: 0.0,
                s0: s,
                feed: r.feed.min(raws[i + 1].feed),
                block: r.block,
                stop_after: false,
            };
            let idx = path.elems.len() as u32;
            let mut len = 0.0;
            for k in 0..n {
                let (ta, tb) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
                let h = e0.length_between(&path.curves, ta, tb, 1);
                path.pieces.push(Piece { elem: idx, tau: (ta, tb), s0: s + len, h });
                len += h;
            }
            let mut e = e0;
            e.len = len;
            path.elems.push(e);
            path.blocks[raws[i + 1].block].s_start = s + 0.5 * len;
            s += len;
        }
    }
    path.length = s;
}

/// Bounds of q', q'', q''' over a piece, from 5 samples with a margin of half the largest
/// change between neighbouring samples.
#[must_use]
pub fn piece_bounds(path: &Path, p: &Piece) -> Bounds {
    let Some(e) = path.elems.get(p.elem as usize) else {
        return Bounds::default();
    };
    let mut q1 = [[0.0; 6]; SAMPLES];
    let mut q2 = [[0.0; 6]; SAMPLES];
    let mut sig = [0.0; SAMPLES];
    let dt = (p.tau.1 - p.tau.0) / (SAMPLES - 1) as f64;
    let active = match &e.shape {
        Shape::Line { a, b } => {
            let d = scale(&sub(b, a), 1.0 / e.len);
            return Bounds { lo1: d, hi1: d, ..Bounds::default() };
        }
        Shape::Bezier(c) => {
            // A blend: straight from its power form, and only the joints it moves (a joint
            // whose coefficients past the constant are zero has q' = q'' = 0 exactly, so
            // bounds of zero, which is what evaluating it would give).
            let active: [bool; 6] = std::array::from_fn(|i| (1..6).any(|k| c[k][i] != 0.0));
            if active == [true, true, true, false, false, false] {
                return blend_bounds_xyz(c, p.tau.0, dt);
            }
            for k in 0..SAMPLES {
                let t = p.tau.0 + dt * k as f64;
                let mut d1 = [0.0; 6];
                let mut d2 = [0.0; 6];
                for i in 0..6 {
                    if i < 3 || active[i] {
                        d1[i] = (((5.0 * c[5][i] * t + 4.0 * c[4][i]) * t + 3.0 * c[3][i]) * t + 2.0 * c[2][i]) * t
                            + c[1][i];
                        d2[i] = ((20.0 * c[5][i] * t + 12.0 * c[4][i]) * t + 6.0 * c[3][i]) * t + 2.0 * c[2][i];
                    }
                }
                // As `in_s` does (not in degrees: a blend always moves the tool tip).
                let sigma = norm3(&d1);
                if sigma > 0.0 {
                    let dsigma = dot3(&d1, &d2) / sigma;
                    let inv = 1.0 / sigma;
                    let cube = sigma * sigma * sigma;
                    for i in 0..6 {
                        if active[i] {
                            q1[k][i] = d1[i] * inv;
                            q2[k][i] = (d2[i] * sigma - d1[i] * dsigma) / cube;
                        }
                    }
                    sig[k] = sigma;
                }
            }
            active
        }
        _ => {
            for k in 0..SAMPLES {
                let t = p.tau.0 + dt * k as f64;
                let d = e.shape.eval(&path.curves, t);
                (q1[k], q2[k], sig[k]) = in_s(&d, false);
            }
            [true; 6]
        }
    };
    let mut sv = [0.0; SAMPLES];
    for k in 1..SAMPLES {
        sv[k] = sv[k - 1] + 0.5 * (sig[k] + sig[k - 1]) * dt;
    }
    let mut out = Bounds::default();
    for i in (0..6).filter(|&i| active[i]) {
        joint_bounds(&mut out, i, &std::array::from_fn(|k| q1[k][i]), &std::array::from_fn(|k| q2[k][i]), &sv);
    }
    out
}

/// [`piece_bounds`] of a blend piece that moves X, Y and Z and no rotary joint (most of
/// them): the same operations in the same order, so the same bits, on three joints without
/// the per-joint tests (straight-line code the compiler unrolls).
fn blend_bounds_xyz(c: &[Q; 6], tau0: f64, dt: f64) -> Bounds {
    // Joint-major: q1[i][k] is joint i's q' at sample k.
    let mut q1 = [[0.0; SAMPLES]; 3];
    let mut q2 = [[0.0; SAMPLES]; 3];
    let mut sig = [0.0; SAMPLES];
    for k in 0..SAMPLES {
        let t = tau0 + dt * k as f64;
        let d1: [f64; 3] = std::array::from_fn(|i| {
            (((5.0 * c[5][i] * t + 4.0 * c[4][i]) * t + 3.0 * c[3][i]) * t + 2.0 * c[2][i]) * t + c[1][i]
        });
        let d2: [f64; 3] =
            std::array::from_fn(|i| ((20.0 * c[5][i] * t + 12.0 * c[4][i]) * t + 6.0 * c[3][i]) * t + 2.0 * c[2][i]);
        let sigma = (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]).sqrt();
        if sigma > 0.0 {
            let dsigma = (d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2]) / sigma;
            let inv = 1.0 / sigma;
            let cube = sigma * sigma * sigma;
            for i in 0..3 {
                q1[i][k] = d1[i] * inv;
                q2[i][k] = (d2[i] * sigma - d1[i] * dsigma) / cube;
            }
            sig[k] = sigma;
        }
    }
    let mut sv = [0.0; SAMPLES];
    for k in 1..SAMPLES {
        sv[k] = sv[k - 1] + 0.5 * (sig[k] + sig[k - 1]) * dt;
    }
    let mut out = Bounds::default();
    for i in 0..3 {
        joint_bounds(&mut out, i, &q1[i], &q2[i], &sv);
    }
    out
}

/// Joint `i`'s bounds in `out` from its q′ (`a`) and q″ (`b`) at a piece's samples, `sv`
/// the arc length at each: the samples' extremes widened by half the largest step between
/// two samples, and the largest rate of q″ per mm by half again. Shared by
/// [`piece_bounds`] and its three-joint blend form, so both give the same bits.
#[inline]
fn joint_bounds(out: &mut Bounds, i: usize, a: &[f64; SAMPLES], b: &[f64; SAMPLES], sv: &[f64; SAMPLES]) {
    let (mut lo1, mut hi1) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut lo2, mut hi2) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut d1, mut d2, mut m3) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..SAMPLES {
        lo1 = lower(lo1, a[k]);
        hi1 = upper(hi1, a[k]);
        lo2 = lower(lo2, b[k]);
        hi2 = upper(hi2, b[k]);
        if k > 0 {
            d1 = upper(d1, (a[k] - a[k - 1]).abs());
            let dd = (b[k] - b[k - 1]).abs();
            d2 = upper(d2, dd);
            let ds = sv[k] - sv[k - 1];
            if ds > 0.0 {
                m3 = upper(m3, dd / ds);
            }
        }
    }
    out.lo1[i] = lo1 - 0.5 * d1;
    out.hi1[i] = hi1 + 0.5 * d1;
    out.lo2[i] = lo2 - 0.5 * d2;
    out.hi2[i] = hi2 + 0.5 * d2;
    out.m3[i] = m3 * 1.5;
}

/// Samples a piece's bounds are taken from (a blend's half, an arc's or NURBS' 5°).
const SAMPLES: usize = 5;

impl Path {
    /// q, q', q'' (derivatives in s) and the programmed feed cap (mm/s) at path position s:
    /// for exporting the geometry (the time-optimal anchor reads it), not per period.
    #[must_use]
    pub fn derivatives_at(&self, s: f64) -> (Q, Q, Q, f64) {
        if self.pieces.is_empty() {
            return (self.end, [0.0; 6], [0.0; 6], 0.0);
        }
        let k = self.pieces.partition_point(|p| p.s0 <= s).saturating_sub(1);
        let p = &self.pieces[k];
        let e = &self.elems[p.elem as usize];
        let (q, q1, q2) = match &e.shape {
            Shape::Line { .. } => e.at_tau(&self.curves, (s - e.s0).clamp(0.0, e.len)),
            _ => e.at_tau(&self.curves, e.tau_at(&self.curves, s.min(p.s0 + p.h), p.tau.0, p.s0)),
        };
        (q, q1, q2, e.feed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The piece count's shortcut below 15° gives what the arc cosine gives, on both sides
    /// of the step and near no turn.
    #[test]
    fn blend_piece_shortcut_is_the_arc_cosine() {
        let full = |c: f64| 1 + (c.acos() / (15f64).to_radians()).ceil() as usize;
        let mut cs = vec![1.0, 1.0 - f64::EPSILON, 0.999, 0.98, COS_15_DEG, 0.5, -1.0];
        for k in 0..20_000 {
            let d = f64::from(k) * 1e-13;
            cs.extend([COS_15_DEG + 1e-9 + d, COS_15_DEG + 1e-9 - d, COS_15_DEG + d, 1.0 - d, 1.0 - 1e-4 * d * 1e9]);
        }
        for c in cs.into_iter().filter(|c| (-1.0..=1.0).contains(c)) {
            assert_eq!(blend_pieces_of_cos(c), full(c), "cos {c}");
        }
    }

    /// The closed form of a line–line blend's deviation equals a dense scan of its distance to
    /// the two legs, and its ends match the legs' position, direction and zero curvature.
    #[test]
    fn line_blend_deviation_is_its_closed_form() {
        for deg in [0.5f64, 3.0, 17.0, 30.0, 60.0, 90.0] {
            let phi = deg.to_radians();
            let m = 2.0;
            let u1: Q = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0];
            let u2: Q = [phi.cos(), phi.sin(), 0.0, 0.0, 0.0, 0.0];
            let c: Q = [10.0, -3.0, 4.0, 0.0, 0.0, 0.0];
            let pa = axpy(-m, &u1, &c);
            let pb = axpy(m, &u2, &c);
            let z = [0.0; 6];
            let bez = hermite(&pa, &u1, &z, &pb, &u2, &z, 1.5 * m, 0.7 * m);
            let (a0, b0, a1) = (v3(&pa), v3(&c), v3(&pb));
            let mut worst: f64 = 0.0;
            for i in 0..=4000 {
                let p = v3(&bezier5(&bez, f64::from(i) / 4000.0)[0]);
                worst = worst.max(dist_to_segment(p, a0, b0).min(dist_to_segment(p, b0, a1)));
            }
            let closed = LINE_BLEND_DEV * m * phi.sin();
            assert!((worst - closed).abs() <= 1e-9 * (1.0 + closed), "{deg}°: scan {worst}, closed form {closed}");
            // Ends: on the legs, along them, curvature zero (power form as the planner holds it).
            let pw = power_of(&bez);
            for (t, p, u) in [(0.0, pa, u1), (1.0, pb, u2)] {
                let [q, d1, d2] = power5(&pw, t);
                let (q1, q2, _) = in_s(&[q, d1, d2], false);
                for i in 0..3 {
                    assert!((q[i] - p[i]).abs() < 1e-12);
                    assert!((q1[i] - u[i]).abs() < 1e-12);
                    assert!(q2[i].abs() < 1e-9, "{deg}°: q'' {q2:?} at τ = {t}");
                }
            }
        }
    }
}
