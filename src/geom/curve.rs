//! Parametric space curves: the trait every curve of the core implements (NURBS curves,
//! the crease path, planar test curves), and a C¹ piecewise-cubic Hermite path through
//! points with known unit tangents.

use glam::DVec3;

use super::nurbs::NurbsCurve;

/// A parametric curve C(s) in mm over a closed parameter range.
pub trait Curve3 {
    /// `[C, C', C'']` at s (mm, mm per unit s, mm per unit s²). Values of s outside the range
    /// are clamped to it.
    fn derivatives_at(&self, s: f64) -> [DVec3; 3];
    /// The parameter range `(start, end)`.
    fn range(&self) -> (f64, f64);
    /// C(s) (mm).
    fn point_at(&self, s: f64) -> DVec3 {
        self.derivatives_at(s)[0]
    }
    /// Curvature κ = |C' × C''| / |C'|³ (1/mm).
    fn curvature_at(&self, s: f64) -> f64 {
        let [_, d1, d2] = self.derivatives_at(s);
        let l = d1.length();
        if l > 0.0 { d1.cross(d2).length() / (l * l * l) } else { 0.0 }
    }
}

impl Curve3 for NurbsCurve {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let (a, b) = self.range();
        NurbsCurve::derivatives_at(self, s.clamp(a, b))
    }
    fn range(&self) -> (f64, f64) {
        NurbsCurve::range(self)
    }
}

/// A C¹ path through points `p_i` with unit tangents `t_i`, parametrised by cumulative
/// chord length (mm): on `[s_i, s_{i+1}]`, with `h = s_{i+1} − s_i` and `τ = (s − s_i)/h`,
/// `C = h00(τ)p_i + h10(τ)h·t_i + h01(τ)p_{i+1} + h11(τ)h·t_{i+1}` (cubic Hermite basis).
///
/// Through points 0.1 mm apart on a curve of radius ρ its deviation from the true curve is of
/// order h⁴/ρ³, far below a nanometre — so a crease sampled once per period is a faithful
/// design curve for chords, fitting and G-code.
#[derive(Clone, Debug, PartialEq)]
pub struct HermitePath {
    s: Vec<f64>,
    p: Vec<DVec3>,
    t: Vec<DVec3>,
}

impl HermitePath {
    /// A path through `points` with unit `tangents` (same length, at least 2; consecutive
    /// points distinct). Returns `None` otherwise.
    #[must_use]
    pub fn new(points: Vec<DVec3>, tangents: Vec<DVec3>) -> Option<Self> {
        if points.len() < 2 || points.len() != tangents.len() {
            return None;
        }
        let mut s = Vec::with_capacity(points.len());
        s.push(0.0);
        for w in points.windows(2) {
            let h = (w[1] - w[0]).length();
            if !(h > 0.0) {
                return None;
            }
            s.push(s[s.len() - 1] + h);
        }
        let t = tangents.into_iter().map(|t| t.normalize_or_zero()).collect();
        Some(Self { s, p: points, t })
    }

    /// The points the path passes through.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.p
    }

    /// Chord-length parameter of each point (mm).
    #[must_use]
    pub fn params(&self) -> &[f64] {
        &self.s
    }

    /// Total chord length (mm).
    #[must_use]
    pub fn length(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// Index i of the segment `[s_i, s_{i+1}]` holding s (clamped). Points one feed per
    /// period apart are nearly evenly spaced, so the proportional guess `s/L·(n−1)` is at most
    /// a step or two off: a short walk from it, with a binary search as the fallback for
    /// unevenly spaced points, keeps every evaluation O(1) on a crease.
    #[must_use]
    pub fn segment(&self, s: f64) -> usize {
        let n = self.s.len();
        let last = n - 2;
        let len = self.length();
        if !(s > self.s[0]) {
            return 0;
        }
        if s >= len {
            return last;
        }
        let mut i = ((s / len) * (n - 1) as f64) as usize;
        i = i.min(last);
        for _ in 0..8 {
            if s < self.s[i] {
                i -= 1;
            } else if s >= self.s[i + 1] {
                i += 1;
            } else {
                return i;
            }
        }
        match self.s.binary_search_by(|x| x.total_cmp(&s)) {
            Ok(i) => i.min(last),
            Err(i) => i.saturating_sub(1).min(last),
        }
    }
}

impl Curve3 for HermitePath {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let s = s.clamp(self.s[0], self.length());
        let i = self.segment(s);
        let h = self.s[i + 1] - self.s[i];
        let x = (s - self.s[i]) / h;
        let (p0, p1) = (self.p[i], self.p[i + 1]);
        let (m0, m1) = (self.t[i] * h, self.t[i + 1] * h);
        let x2 = x * x;
        let x3 = x2 * x;
        let c =
            (2.0 * x3 - 3.0 * x2 + 1.0) * p0 + (x3 - 2.0 * x2 + x) * m0 + (-2.0 * x3 + 3.0 * x2) * p1 + (x3 - x2) * m1;
        let d = (6.0 * x2 - 6.0 * x) * p0
            + (3.0 * x2 - 4.0 * x + 1.0) * m0
            + (-6.0 * x2 + 6.0 * x) * p1
            + (3.0 * x2 - 2.0 * x) * m1;
        let dd = (12.0 * x - 6.0) * p0 + (6.0 * x - 4.0) * m0 + (-12.0 * x + 6.0) * p1 + (6.0 * x - 2.0) * m1;
        [c, d / h, dd / (h * h)]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, self.length())
    }
}
