//! Right-handed orthonormal frames for the analytic surfaces.

use glam::DVec3;

/// A right-handed orthonormal frame `(e1, e2, a)` with `e2 = a × e1`.
///
/// For cylinders, spheres and tori `a` is the axis and `e1` the reference direction from
/// which the angular parameter u is measured, turning from `e1` toward `e2` (counter-clockwise
/// seen from the tip of `a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Reference direction (u = 0), unit.
    pub e1: DVec3,
    /// `a × e1` (u = 90°), unit.
    pub e2: DVec3,
    /// Axis, unit.
    pub a: DVec3,
}

impl Frame {
    /// Builds the frame from a unit axis and an optional reference direction. The reference
    /// is made exactly perpendicular by removing its axial part; without one,
    /// [`any_perpendicular`] picks it.
    #[must_use]
    pub fn from_axis(axis: DVec3, reference: Option<DVec3>) -> Self {
        let a = axis.normalize();
        let e1 = match reference {
            Some(r) => (r - a * r.dot(a)).normalize(),
            None => any_perpendicular(a),
        };
        Self { e1, e2: a.cross(e1), a }
    }
}

/// The deterministic unit vector perpendicular to the unit vector `a` used when a scene
/// gives no `ref_dir`: the world axis (x, then y, then z on ties) least aligned with `a`,
/// with its component along `a` removed. For `a = +z` this is `+x` (and `e2 = +y`).
#[must_use]
pub fn any_perpendicular(a: DVec3) -> DVec3 {
    let abs = a.abs();
    let w = if abs.x <= abs.y && abs.x <= abs.z {
        DVec3::X
    } else if abs.y <= abs.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (w - a * w.dot(a)).normalize()
}
