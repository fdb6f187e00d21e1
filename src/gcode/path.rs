//! The geometry of a G-code program: straight moves, circular and helical arcs in the three
//! principal planes, and NURBS curves — what the writer emits and the reader rebuilds.
//!
//! Arc conventions (ISO 6983 / RS274): the plane is chosen by G17 (XY), G18 (ZX) or G19
//! (YZ); with the plane's in-plane axes (a, b) and normal axis n taken as (X, Y, Z),
//! (Z, X, Y) and (Y, Z, X) — each a right-handed triple — G03 turns counter-clockwise,
//! i.e. positively about +n (from +a toward +b), and G02 clockwise, as seen looking from the
//! positive n axis toward the origin. The centre is given by I, J, K: offsets from the start
//! point along X, Y, Z (only the two in-plane ones matter). Motion along n during an arc is
//! proportional to the angle turned: a helix.

use glam::DVec3;

use crate::geom::{Curve3, NurbsCurve};

/// Arc plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    /// G17: XY, normal +Z.
    Xy,
    /// G18: ZX, normal +Y.
    Zx,
    /// G19: YZ, normal +X.
    Yz,
}

impl Plane {
    /// All three, in G-code order.
    pub const ALL: [Self; 3] = [Self::Xy, Self::Zx, Self::Yz];

    /// Indices (a, b, n) into (x, y, z) of the in-plane axes and the normal.
    #[must_use]
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Self::Xy => (0, 1, 2),
            Self::Zx => (2, 0, 1),
            Self::Yz => (1, 2, 0),
        }
    }

    /// The G code selecting the plane.
    #[must_use]
    pub fn gcode(self) -> &'static str {
        match self {
            Self::Xy => "G17",
            Self::Zx => "G18",
            Self::Yz => "G19",
        }
    }

    /// In-plane coordinates (a, b) and normal coordinate n of a point.
    #[must_use]
    pub fn split(self, p: DVec3) -> (f64, f64, f64) {
        let (a, b, n) = self.axes();
        (p[a], p[b], p[n])
    }

    /// The point with in-plane coordinates (a, b) and normal coordinate n.
    #[must_use]
    pub fn join(self, a: f64, b: f64, n: f64) -> DVec3 {
        let (ia, ib, inn) = self.axes();
        let mut v = DVec3::ZERO;
        v[ia] = a;
        v[ib] = b;
        v[inn] = n;
        v
    }
}

/// A circular or helical arc (G02/G03).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcMove {
    /// Start point (mm).
    pub start: DVec3,
    /// End point (mm).
    pub end: DVec3,
    /// Centre (mm); only its in-plane coordinates matter.
    pub center: DVec3,
    /// Plane.
    pub plane: Plane,
    /// G03 (counter-clockwise) when true, G02 when false.
    pub ccw: bool,
}

impl ArcMove {
    fn polar(&self, p: DVec3) -> (f64, f64) {
        let (ca, cb, _) = self.plane.split(self.center);
        let (a, b, _) = self.plane.split(p);
        ((b - cb).atan2(a - ca), (a - ca).hypot(b - cb))
    }

    /// Radius at the start (mm).
    #[must_use]
    pub fn radius_start(&self) -> f64 {
        self.polar(self.start).1
    }

    /// Radius at the end (mm).
    #[must_use]
    pub fn radius_end(&self) -> f64 {
        self.polar(self.end).1
    }

    /// Signed angle turned (rad): positive for G03, negative for G02, of magnitude in
    /// (0, 2π]; an arc ending where it starts is a full turn.
    #[must_use]
    pub fn sweep(&self) -> f64 {
        let (ts, _) = self.polar(self.start);
        let (te, _) = self.polar(self.end);
        let tau = std::f64::consts::TAU;
        let mut d = if self.ccw { (te - ts).rem_euclid(tau) } else { (ts - te).rem_euclid(tau) };
        if d == 0.0 {
            d = tau;
        }
        if self.ccw { d } else { -d }
    }

    /// Approximate length (mm): that of a helix with the mean radius.
    #[must_use]
    pub fn length(&self) -> f64 {
        let r = 0.5 * (self.radius_start() + self.radius_end());
        let dn = self.plane.split(self.end).2 - self.plane.split(self.start).2;
        (r * self.sweep()).hypot(dn)
    }
}

/// Arcs are parametrised by the fraction τ ∈ [0, 1] of the angle turned; the radius changes
/// linearly from the start radius to the end radius (as controllers do when the two differ by
/// rounding) and the normal coordinate linearly with τ.
impl Curve3 for ArcMove {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let tau = s.clamp(0.0, 1.0);
        let (ts, rs) = self.polar(self.start);
        let re = self.radius_end();
        let d = self.sweep();
        let (ca, cb, _) = self.plane.split(self.center);
        let ns = self.plane.split(self.start).2;
        let dn = self.plane.split(self.end).2 - ns;
        let dr = re - rs;
        let th = ts + tau * d;
        let r = rs + tau * dr;
        let (sn, cs) = th.sin_cos();
        let p = self.plane.join(ca + r * cs, cb + r * sn, ns + tau * dn);
        let d1 = self.plane.join(dr * cs - r * d * sn, dr * sn + r * d * cs, dn);
        let d2 = self.plane.join(-2.0 * dr * d * sn - r * d * d * cs, 2.0 * dr * d * cs - r * d * d * sn, 0.0);
        [p, d1, d2]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
}

/// A straight move parametrised by τ ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineMove {
    /// Start (mm).
    pub start: DVec3,
    /// End (mm).
    pub end: DVec3,
}

impl Curve3 for LineMove {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let t = s.clamp(0.0, 1.0);
        [self.start.lerp(self.end, t), self.end - self.start, DVec3::ZERO]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
}

/// One piece of geometry of a program.
#[derive(Clone, Debug, PartialEq)]
pub enum Segment {
    /// G00 or G01.
    Line(LineMove),
    /// G02 or G03.
    Arc(ArcMove),
    /// G06.2.
    Nurbs(NurbsCurve),
}

impl Segment {
    /// The segment as a curve.
    #[must_use]
    pub fn curve(&self) -> &dyn Curve3 {
        match self {
            Self::Line(l) => l,
            Self::Arc(a) => a,
            Self::Nurbs(n) => n,
        }
    }

    /// Start point (mm).
    #[must_use]
    pub fn start(&self) -> DVec3 {
        let c = self.curve();
        c.point_at(c.range().0)
    }

    /// End point (mm).
    #[must_use]
    pub fn end(&self) -> DVec3 {
        let c = self.curve();
        c.point_at(c.range().1)
    }
}

/// The kind of motion of a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// G00 positioning (not part of the cut).
    Rapid,
    /// G01.
    Linear,
    /// G02.
    ArcCw,
    /// G03.
    ArcCcw,
    /// G06.2.
    Nurbs,
}

impl Motion {
    /// The G code.
    #[must_use]
    pub fn gcode(self) -> &'static str {
        match self {
            Self::Rapid => "G00",
            Self::Linear => "G01",
            Self::ArcCw => "G02",
            Self::ArcCcw => "G03",
            Self::Nurbs => "G06.2",
        }
    }
}

/// One move of a program, with the line it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct PathBlock {
    /// 1-based line of the program where the move is programmed (for G06.2 the line of the
    /// `G06.2` word).
    pub line: usize,
    /// Motion kind.
    pub motion: Motion,
    /// Geometry.
    pub segment: Segment,
    /// Feed in force (mm/min); `None` for rapids.
    pub feed_mm_per_min: Option<f64>,
}

/// The moves of a program in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Toolpath {
    /// All moves, rapids included.
    pub blocks: Vec<PathBlock>,
}

impl Toolpath {
    /// The cutting moves (everything but G00).
    pub fn cuts(&self) -> impl Iterator<Item = &PathBlock> {
        self.blocks.iter().filter(|b| b.motion != Motion::Rapid)
    }

    /// Length of the cutting moves (mm); NURBS by 64 chords per knot span.
    #[must_use]
    pub fn cut_length(&self) -> f64 {
        self.cuts().map(|b| segment_length(&b.segment)).sum()
    }

    /// Length of the rapid moves (mm).
    #[must_use]
    pub fn rapid_length(&self) -> f64 {
        self.blocks.iter().filter(|b| b.motion == Motion::Rapid).map(|b| segment_length(&b.segment)).sum()
    }

    /// Bounding box (min, max) of the cutting moves, from their end points and samples.
    #[must_use]
    pub fn cut_bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut bb: Option<(DVec3, DVec3)> = None;
        // The points of `sample_segment`, from one buffer of parameters for every move.
        let mut params = Vec::new();
        for b in self.cuts() {
            params.clear();
            push_sample_params(&b.segment, 16, &mut params);
            let curve = b.segment.curve();
            for &t in &params {
                let p = curve.point_at(t);
                bb = Some(match bb {
                    None => (p, p),
                    Some((lo, hi)) => (lo.min(p), hi.max(p)),
                });
            }
        }
        bb
    }
}

/// Points of a segment: its ends and `per_piece` equal parameter steps per piece (per knot
/// span for a NURBS, the whole segment for lines and arcs).
#[must_use]
pub fn sample_segment(seg: &Segment, per_piece: usize) -> Vec<DVec3> {
    sample_params(seg, per_piece).into_iter().map(|t| seg.curve().point_at(t)).collect()
}

/// Parameters of [`sample_segment`].
#[must_use]
pub fn sample_params(seg: &Segment, per_piece: usize) -> Vec<f64> {
    let mut out = Vec::new();
    push_sample_params(seg, per_piece, &mut out);
    out
}

/// [`sample_params`] appended to `out`.
pub(super) fn push_sample_params(seg: &Segment, per_piece: usize, out: &mut Vec<f64>) {
    let n = per_piece.max(1);
    let nurbs_breaks;
    let breaks: &[f64] = match seg {
        Segment::Nurbs(c) => {
            nurbs_breaks = crate::numerics::knots::span_breaks(c.knots(), c.degree());
            &nurbs_breaks
        }
        _ => &[0.0, 1.0],
    };
    out.reserve(1 + breaks.len().saturating_sub(1) * n);
    out.push(breaks[0]);
    for w in breaks.windows(2) {
        for i in 1..=n {
            out.push(w[0] + (w[1] - w[0]) * i as f64 / n as f64);
        }
    }
}

pub(super) fn segment_length(seg: &Segment) -> f64 {
    match seg {
        Segment::Line(l) => (l.end - l.start).length(),
        Segment::Arc(a) => a.length(),
        Segment::Nurbs(_) => sample_segment(seg, 64).windows(2).map(|w| (w[1] - w[0]).length()).sum(),
    }
}
