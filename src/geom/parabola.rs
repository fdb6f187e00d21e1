//! Test and comparison profiles with exact derivatives.
//!
//! Seed 004 fits a planar parabola-like profile (its table 2, lost in the scanned text)
//! and compares G01, line-and-arc and G06.2 programs for it at 0.01 mm. [`Parabola`] is our
//! stand-in: y = a·x² in the plane z = const, parametrised by x.

use glam::DVec3;

use crate::geom::Curve3;

/// The parabola C(x) = (x, a·x², z) for x in `[x0, x1]` (mm); its curvature
/// κ = 2|a| / (1 + 4a²x²)^{3/2} is largest, 2|a|, at the vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parabola {
    /// Coefficient a (1/mm).
    pub a: f64,
    /// First x (mm).
    pub x0: f64,
    /// Last x (mm).
    pub x1: f64,
    /// Height of the plane (mm).
    pub z: f64,
}

impl Parabola {
    /// The profile `interpolab compare --profile parabola` uses: y = x²/40 (a = 0.025 /mm,
    /// vertex radius 20 mm) for x from −60 to 60 mm, a 90 mm deep, 120 mm wide part of the size
    /// and shape of seed 004's profile.
    #[must_use]
    pub fn paper_like() -> Self {
        Self { a: 0.025, x0: -60.0, x1: 60.0, z: 0.0 }
    }
}

impl Curve3 for Parabola {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let x = s.clamp(self.x0, self.x1);
        [
            DVec3::new(x, self.a * x * x, self.z),
            DVec3::new(1.0, 2.0 * self.a * x, 0.0),
            DVec3::new(0.0, 2.0 * self.a, 0.0),
        ]
    }
    fn range(&self) -> (f64, f64) {
        (self.x0, self.x1)
    }
}
