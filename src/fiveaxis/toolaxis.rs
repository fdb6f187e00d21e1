//! Tool-axis rules: how the tool axis is chosen along a path from the local geometry.
//!
//! At a cutter location the path knows the unit normal n1 of surface 1 at its contact
//! point, the normal n2 of surface 2 (crease paths), and the unit direction of travel t.
//!
//! | rule | tool axis T (tip → spindle) |
//! |---|---|
//! | `bisector` | (n1 + n2)/\|n1 + n2\| (n1 alone on a one-surface path) |
//! | `normal1` (lead λ, tilt β) | cos β·(cos λ·n1 + sin λ·t) + sin β·(t × n1), with t made ⊥ n1 |
//! | `fixed` | the given vector, normalised |
//! | interpolated (presets only) | great-circle interpolation from T_start to T_end by the fraction of the path's parameter range |
//!
//! Positive lead tips the spindle end forward, toward the direction of travel; positive
//! tilt tips it toward t × n1 (to the left of the travel seen from the spindle).

use glam::DVec3;

use crate::numerics::tolerance;

/// A tool-axis rule (internal units: radians, unit vectors).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ToolAxisRule {
    /// Bisector of the two contact normals (the default).
    #[default]
    Bisector,
    /// Surface-1 normal turned by lead and tilt angles.
    Normal1 {
        /// Lead λ (rad).
        lead_rad: f64,
        /// Tilt β (rad).
        tilt_rad: f64,
    },
    /// A constant direction (unit).
    Fixed {
        /// The axis.
        axis: DVec3,
    },
    /// Great-circle interpolation between two unit axes by the fraction of the path range.
    Interpolated {
        /// Axis at the start of the path.
        from: DVec3,
        /// Axis at the end of the path.
        to: DVec3,
    },
}

/// The local geometry a rule reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisFrame {
    /// Unit normal of surface 1 at its contact point (toward the cutter).
    pub n1: DVec3,
    /// Unit normal of surface 2, if the path has one.
    pub n2: Option<DVec3>,
    /// Unit direction of travel.
    pub travel: DVec3,
    /// Fraction of the path's parameter range, 0 at the start and 1 at the end.
    pub fraction: f64,
}

/// Spherical linear interpolation between unit vectors (the shorter great circle).
#[must_use]
pub fn slerp(a: DVec3, b: DVec3, x: f64) -> DVec3 {
    let c = a.dot(b).clamp(-1.0, 1.0);
    let theta = c.acos();
    let s = theta.sin();
    if s < crate::numerics::tolerance::PARALLEL_SIN {
        return a.lerp(b, x).normalize_or_zero();
    }
    (a * ((1.0 - x) * theta).sin() + b * (x * theta).sin()) / s
}

impl ToolAxisRule {
    /// The unit tool axis for this local geometry, or `None` when the rule is undefined there
    /// (opposite normals for the bisector; a zero fixed vector).
    #[must_use]
    pub fn axis(&self, f: &AxisFrame) -> Option<DVec3> {
        let v = match *self {
            Self::Bisector => f.n1 + f.n2.unwrap_or(f.n1),
            Self::Normal1 { lead_rad, tilt_rad } => {
                let n = f.n1;
                let t = (f.travel - n * f.travel.dot(n)).try_normalize()?;
                let (sl, cl) = lead_rad.sin_cos();
                let (sb, cb) = tilt_rad.sin_cos();
                cb * (cl * n + sl * t) + sb * t.cross(n)
            }
            Self::Fixed { axis } => axis,
            Self::Interpolated { from, to } => {
                slerp(from.try_normalize()?, to.try_normalize()?, f.fraction.clamp(0.0, 1.0))
            }
        };
        if v.length() > tolerance::MIN_DIRECTION_LENGTH { v.try_normalize() } else { None }
    }

    /// Short name (`bisector`, `normal1`, `fixed`, `interpolated`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Bisector => "bisector",
            Self::Normal1 { .. } => "normal1",
            Self::Fixed { .. } => "fixed",
            Self::Interpolated { .. } => "interpolated",
        }
    }
}
