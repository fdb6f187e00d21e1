//! A blade section: the NACA four-digit aerofoil as a closed planar curve, the test curve of
//! the Table-1 comparison (seed 002, Example 2, used "a blade section curve").
//!
//! NACA `MPTT` with chord c: maximum camber m = M/100 at p = P/10 of the chord, thickness
//! t = TT/100. With x ∈ [0, 1] along the chord,
//!
//! - half-thickness `y_t = 5t(0.2969√x − 0.1260x − 0.3516x² + 0.2843x³ − 0.1036x⁴)` (the
//!   closed-trailing-edge coefficient −0.1036 instead of −0.1015);
//! - camber line `y_c = m/p²·(2px − x²)` for x < p, `m/(1−p)²·((1 − 2p) + 2px − x²)` after;
//! - surface point `(x − y_t sin θ_c, y_c + y_t cos θ_c)` (upper) and with −y_t (lower),
//!   θ_c = atan(dy_c/dx).
//!
//! Parametrised by θ ∈ [0, 2π] with `x = (1 + cos θ)/2`: θ = 0 is the trailing edge, θ
//! runs over the upper surface to the leading edge at θ = π and back along the lower
//! surface — counter-clockwise seen from +Z. Since `√x = |cos(θ/2)|`, the signed
//! half-thickness is `5t(0.2969 cos(θ/2) ± (…))`, smooth through the leading edge. The curve
//! lies in the plane z = `z_mm`. Derivatives are central differences of the exact point.

use glam::DVec3;

/// How far (θ, rad) the blade's path starts after and ends before the trailing edge, where
/// the θ-parametrisation has speed 0 (x = 1 − 2.5e-7 of the chord there). A geometric
/// choice of this section's model, not a numerical tolerance.
const TRAILING_EDGE_GAP_RAD: f64 = 1e-3;

/// Step (θ, rad) of the central differences of the section's second derivative: the
/// section is a closed form of degree ≤ 4 in cos θ, whose third derivative is O(1), so the
/// truncation error (h²) and the rounding (ε/h²·|p| ~ 1e-8 mm for a 100 mm chord) balance
/// near here.
const FD_STEP_RAD: f64 = 1e-4;

use crate::geom::{Curve3, HermitePath};

/// A NACA four-digit section (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NacaProfile {
    /// Maximum camber, fraction of the chord (NACA 2412: 0.02).
    pub camber: f64,
    /// Position of maximum camber, fraction of the chord (NACA 2412: 0.4).
    pub camber_pos: f64,
    /// Thickness, fraction of the chord (NACA 2412: 0.12).
    pub thickness: f64,
    /// Chord length (mm).
    pub chord_mm: f64,
    /// Height of the section plane (mm).
    pub z_mm: f64,
}

impl NacaProfile {
    /// The section named by four digits (`"2412"`), chord `chord_mm`, in the plane z = 0.
    #[must_use]
    pub fn from_digits(digits: &str, chord_mm: f64) -> Option<Self> {
        let d: Vec<u32> = digits.chars().map(|c| c.to_digit(10)).collect::<Option<_>>()?;
        if d.len() != 4 || d[2] * 10 + d[3] == 0 {
            return None;
        }
        Some(Self {
            camber: f64::from(d[0]) / 100.0,
            camber_pos: f64::from(d[1]) / 10.0,
            thickness: f64::from(d[2] * 10 + d[3]) / 100.0,
            chord_mm,
            z_mm: 0.0,
        })
    }

    /// NACA 2412 with a 100 mm chord.
    #[must_use]
    pub fn naca2412() -> Self {
        Self { camber: 0.02, camber_pos: 0.4, thickness: 0.12, chord_mm: 100.0, z_mm: 0.0 }
    }

    /// The section as a C¹ path through `n` points (equal steps of θ, so denser at the
    /// leading and trailing edges) with the exact unit tangents, parametrised by chord length
    /// in mm, from just past the trailing edge (θ = 1e-3, x = 1 − 2.5e-7) around to it again.
    /// The θ-parametrisation has speed 0 at the trailing edge, which would defeat seed 002's
    /// step estimate Δs = Δl/|p'|; by chord length |p'| = 1. With n = 4000 the path departs
    /// from the exact section by well under 1e-6 mm.
    #[must_use]
    pub fn to_path(&self, n: usize) -> Option<HermitePath> {
        let n = n.max(2);
        let (a, b) = (TRAILING_EDGE_GAP_RAD, std::f64::consts::TAU - TRAILING_EDGE_GAP_RAD);
        let thetas = (0..n).map(|i| a + (b - a) * i as f64 / (n - 1) as f64);
        let (points, tangents) = thetas.map(|t| (self.point(t), self.derivatives_at(t)[1])).unzip();
        HermitePath::new(points, tangents)
    }

    /// The point at θ (clamped to [0, 2π]).
    #[must_use]
    pub fn point(&self, theta: f64) -> DVec3 {
        let th = theta.clamp(0.0, std::f64::consts::TAU);
        let x = 0.5 * (1.0 + th.cos());
        let sigma = (0.5 * th).cos(); // ±√x: + on the upper surface
        let poly = x * (-0.1260 + x * (-0.3516 + x * (0.2843 - 0.1036 * x)));
        let yt = 5.0 * self.thickness * (0.2969 * sigma + sigma.signum() * poly);
        let (m, p) = (self.camber, self.camber_pos);
        let (yc, slope) = if m == 0.0 || p <= 0.0 {
            (0.0, 0.0)
        } else if x < p {
            (m / (p * p) * (2.0 * p * x - x * x), 2.0 * m / (p * p) * (p - x))
        } else {
            (
                m / ((1.0 - p) * (1.0 - p)) * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x),
                2.0 * m / ((1.0 - p) * (1.0 - p)) * (p - x),
            )
        };
        let tc = slope.atan();
        let c = self.chord_mm;
        DVec3::new(c * (x - yt * tc.sin()), c * (yc + yt * tc.cos()), self.z_mm)
    }
}

impl Curve3 for NacaProfile {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let (lo, hi) = (0.0, std::f64::consts::TAU);
        let s = s.clamp(lo, hi);
        let h = FD_STEP_RAD;
        // Keep the stencil inside the range (one-sided at the ends).
        let m = s.clamp(lo + h, hi - h);
        let (a, b, c) = (self.point(m - h), self.point(m), self.point(m + h));
        let d1c = (c - a) / (2.0 * h);
        let d2 = (a - 2.0 * b + c) / (h * h);
        let d1 = d1c + d2 * (s - m);
        [self.point(s), d1, d2]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, std::f64::consts::TAU)
    }
}
