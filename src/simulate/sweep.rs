//! Where a cutter, or the envelope it sweeps along a move, crosses one vertical ray.
//!
//! The simulated tool is the cutter's solid of revolution up to its *body top* H, the gauge
//! length: the bottom (flat, corner torus) and the flank of radius R continued up to H. The
//! shank is taken as part of that cylinder (a shank narrower than R lies inside it; a wider
//! one is not modelled) and the holder is not subtracted — a holder touching the stock is a
//! collision, not a cut. Tilted tool (tip T, unit axis a), in the tool frame of
//! [`crate::geom::cutter`]:
//!
//! - ball: the sphere of radius R centred at T + R·a, and the cylinder of radius R from
//!   that centre up to T + H·a;
//! - flat: the cylinder of radius R from T to T + H·a;
//! - fillet: the points within r of the disk of radius R0 = R − r centred at T + r·a
//!   (that is the flat bottom and the corner torus, and a little above it inside the
//!   flank), and the cylinder of radius R from T + r·a to T + H·a. Exact when H ≥ 2r.
//!
//! Each body is convex, so a ray crosses it in one interval, found in closed form (sphere,
//! cylinder: a quadratic) or, for the fillet's corner, by minimising the convex distance
//! along the ray to the centre disk and bisecting for its two roots to
//! [`ROOT_TOL_MM`](super::ROOT_TOL_MM).

use glam::DVec3;

use super::{MAX_SOLVE_ITERATIONS, ROOT_TOL_MM};
use crate::geom::{Cutter, CutterKind};

/// The simulated shape of a cutter (mm): what [`Cutter`] says, reduced to what cuts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolShape {
    /// Ball, fillet or flat.
    pub kind: CutterKind,
    /// Cutter radius R (mm).
    pub radius_mm: f64,
    /// Corner radius r (mm).
    pub corner_mm: f64,
    /// Body top H above the tip (mm): the gauge length, at least 2r.
    pub top_mm: f64,
}

impl ToolShape {
    /// The simulated shape of a cutter.
    #[must_use]
    pub fn of(cutter: &Cutter) -> Self {
        let kind = cutter.kind();
        let corner_mm = match kind {
            CutterKind::Ball => cutter.radius_mm,
            CutterKind::Flat => 0.0,
            CutterKind::Fillet => cutter.corner_radius_mm,
        };
        Self {
            kind,
            radius_mm: cutter.radius_mm,
            corner_mm,
            top_mm: cutter.gauge_length_mm.max(2.0 * corner_mm).max(cutter.flute_length_mm),
        }
    }

    /// R0 = R − r (mm).
    #[must_use]
    pub fn torus_mm(&self) -> f64 {
        (self.radius_mm - self.corner_mm).max(0.0)
    }

    /// Height of the bottom above the tip at radial distance ρ ≤ R (mm).
    #[must_use]
    pub fn bottom_mm(&self, rho_mm: f64) -> f64 {
        let d = rho_mm - self.torus_mm();
        if d <= 0.0 {
            return 0.0;
        }
        let r = self.corner_mm;
        r - (r * r - d * d).max(0.0).sqrt()
    }
}

/// The envelope a 3-axis cutter (axis +Z) sweeps moving its tip straight from `a` to `b`,
/// crossed by the ray at (x, y): `Some((lo, hi))` (mm), `None` when the ray misses it.
/// One-off form of [`LineSweep::span`].
#[must_use]
pub fn line_span(tool: &ToolShape, a: DVec3, b: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    LineSweep::new(tool, a, b).span(x, y)
}

/// A straight 3-axis move with what every ray needs precomputed.
///
/// For the ray at (x, y), lo is the minimum over the move of the tip height plus the bottom
/// profile at the ray's distance from the axis: exact in closed form for a horizontal move
/// (the nearest point of the projected segment), for a plunge, for a flat end mill (an end
/// of the range of the move where the ray is under the cutter) and for a ball end mill (the
/// lowest point of the capsule of the ball centre's segment); for a fillet-end mill on a
/// sloped move the function is convex in the move's parameter and is minimised by golden
/// sections to [`ROOT_TOL_MM`] of the move's length. hi is the highest tip height over the
/// range of the move where the ray is under the cutter, plus H.
#[derive(Clone, Copy, Debug)]
pub struct LineSweep {
    tool: ToolShape,
    a: DVec3,
    d: DVec3,
    /// |d_xy|² and |d|² (mm²).
    a2: f64,
    len2: f64,
    kind: LineKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LineKind {
    Plunge,
    Horizontal,
    Sloped,
}

impl LineSweep {
    /// The move of the tip from `a` to `b` (mm).
    #[must_use]
    pub fn new(tool: &ToolShape, a: DVec3, b: DVec3) -> Self {
        let d = b - a;
        let a2 = d.x * d.x + d.y * d.y;
        let kind = if a2 <= super::SAME_POINT_MM * super::SAME_POINT_MM {
            LineKind::Plunge
        } else if d.z.abs() <= super::SAME_POINT_MM {
            LineKind::Horizontal
        } else {
            LineKind::Sloped
        };
        Self { tool: *tool, a, d, a2, len2: a2 + d.z * d.z, kind }
    }

    /// Height of the bottom above the tip at squared radial distance `rho2` ≤ R² (mm).
    #[inline]
    fn bottom_sq(&self, rho2: f64) -> f64 {
        match self.tool.kind {
            CutterKind::Flat => 0.0,
            CutterKind::Ball => {
                let r = self.tool.radius_mm;
                r - (r * r - rho2).max(0.0).sqrt()
            }
            CutterKind::Fillet => self.tool.bottom_mm(rho2.sqrt()),
        }
    }

    /// The span of the ray at (x, y) inside the envelope (mm), `None` when it misses.
    #[inline]
    #[must_use]
    pub fn span(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let tool = &self.tool;
        let big_r = tool.radius_mm;
        let (a, d) = (self.a, self.d);
        let (qx, qy) = (x - a.x, y - a.y);
        let q2 = qx * qx + qy * qy;
        match self.kind {
            LineKind::Plunge => {
                // No horizontal motion: the ray keeps its distance from the axis.
                if q2 > big_r * big_r {
                    return None;
                }
                let lo = a.z.min(a.z + d.z) + self.bottom_sq(q2);
                Some((lo, a.z.max(a.z + d.z) + tool.top_mm))
            }
            LineKind::Horizontal => {
                // The nearest point of the projected segment.
                let t = ((qx * d.x + qy * d.y) / self.a2).clamp(0.0, 1.0);
                let (ex, ey) = (qx - t * d.x, qy - t * d.y);
                let rho2 = ex * ex + ey * ey;
                if rho2 > big_r * big_r {
                    return None;
                }
                Some((a.z + self.bottom_sq(rho2), a.z + tool.top_mm))
            }
            LineKind::Sloped => self.sloped(qx, qy, q2),
        }
    }

    fn sloped(&self, qx: f64, qy: f64, q2: f64) -> Option<(f64, f64)> {
        let tool = &self.tool;
        let big_r = tool.radius_mm;
        let (a, d, a2) = (self.a, self.d, self.a2);
        let qd = qx * d.x + qy * d.y;
        // The move's parameters t ∈ [0, 1] where the ray is within R of the axis.
        let disc = qd * qd - a2 * (q2 - big_r * big_r);
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let t1 = ((qd - s) / a2).max(0.0);
        let t2 = ((qd + s) / a2).min(1.0);
        if t1 > t2 {
            return None;
        }
        let z = |t: f64| a.z + t * d.z;
        let hi = z(t1).max(z(t2)) + tool.top_mm;
        let lo = match tool.kind {
            CutterKind::Flat => z(t1).min(z(t2)),
            CutterKind::Ball => capsule_low(big_r, qx, qy, d.x, d.y, d.z, qd, q2, a2, self.len2, a.z + big_r),
            CutterKind::Fillet => {
                let f = |t: f64| {
                    let (ex, ey) = (qx - t * d.x, qy - t * d.y);
                    z(t) + tool.bottom_mm((ex * ex + ey * ey).sqrt())
                };
                golden_min(f, t1, t2, ROOT_TOL_MM / self.len2.sqrt()).1
            }
        };
        Some((lo, hi))
    }
}

/// Lowest point on the ray of the capsule of radius R around the segment from the ball
/// centre c_a = (a.x, a.y, cz) to c_a + (dx, dy, dz); the ray is known to meet it.
#[allow(clippy::too_many_arguments)]
fn capsule_low(
    big_r: f64,
    qx: f64,
    qy: f64,
    dx: f64,
    dy: f64,
    dz: f64,
    qd: f64,
    q2: f64,
    a2: f64,
    len2: f64,
    cz: f64,
) -> f64 {
    let r2 = big_r * big_r;
    let mut low = f64::INFINITY;
    // The two end spheres.
    if q2 <= r2 {
        low = low.min(cz - (r2 - q2).sqrt());
    }
    let (ex, ey) = (qx - dx, qy - dy);
    let e2 = ex * ex + ey * ey;
    if e2 <= r2 {
        low = low.min(cz + dz - (r2 - e2).sqrt());
    }
    // The cylinder: with u = z − cz, the squared distance to the centre line is
    // q2 + u² − (qd + u·dz)²/len2 ≤ R²; its lower root counts where its foot lies on the segment.
    let qa = a2 / len2;
    let qb = -2.0 * qd * dz / len2;
    let qc = q2 - qd * qd / len2 - r2;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc >= 0.0 {
        let u = (-qb - disc.sqrt()) / (2.0 * qa);
        let t = (qd + u * dz) / len2;
        if (0.0..=1.0).contains(&t) {
            low = low.min(cz + u);
        }
    }
    low
}

/// Golden-section search for the minimum of a convex f on [a, b] down to a bracket of
/// width `tol` (at most [`MAX_SOLVE_ITERATIONS`] steps): `(argmin, min)`.
fn golden_min(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let (mut a, mut b) = (a, b);
    let mut c = b - INV_PHI * (b - a);
    let mut d = a + INV_PHI * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..MAX_SOLVE_ITERATIONS {
        if b - a <= tol {
            break;
        }
        if fc <= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - INV_PHI * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INV_PHI * (b - a);
            fd = f(d);
        }
    }
    // The ends too: the minimum of a monotone f sits there.
    let mut best = if fc <= fd { (c, fc) } else { (d, fd) };
    for t in [a, b] {
        let v = f(t);
        if v < best.1 {
            best = (t, v);
        }
    }
    best
}

/// The ray at (x, y) against the solid cylinder of radius `radius` around the axis from
/// `p0` along unit `axis` for `len` mm: the interval of z inside it.
fn ray_cylinder(p0: DVec3, axis: DVec3, len: f64, radius: f64, x: f64, y: f64) -> Option<(f64, f64)> {
    // w(z) = (x, y, z) − p0 = w0 + z·ẑ
    let w0 = DVec3::new(x - p0.x, y - p0.y, -p0.z);
    let wa = w0.dot(axis);
    let az = axis.z;
    // Slab 0 ≤ w·a ≤ len, with w·a = wa + z·az.
    let (mut lo, mut hi) = if az.abs() > super::AXIS_FLAT_SIN {
        let za = -wa / az;
        let zb = (len - wa) / az;
        (za.min(zb), za.max(zb))
    } else if (0.0..=len).contains(&wa) {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        return None;
    };
    // Radial: |w|² − (w·a)² ≤ radius², a quadratic in z.
    let qa = 1.0 - az * az;
    let qb = 2.0 * (w0.z - wa * az);
    let qc = w0.length_squared() - wa * wa - radius * radius;
    if qa <= super::AXIS_FLAT_SIN * super::AXIS_FLAT_SIN {
        if qc > 0.0 {
            return None;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        lo = lo.max((-qb - s) / (2.0 * qa));
        hi = hi.min((-qb + s) / (2.0 * qa));
    }
    (lo <= hi && lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// The ray at (x, y) against a tilted cutter with tip `tip` and unit axis `axis`: the
/// interval of z inside the simulated tool (see the module docs), `None` when it misses.
#[must_use]
pub fn tilted_span(tool: &ToolShape, tip: DVec3, axis: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    let big_r = tool.radius_mm;
    let r = tool.corner_mm;
    let body = ray_cylinder(tip + r * axis, axis, tool.top_mm - r, big_r, x, y);
    let corner = match tool.kind {
        CutterKind::Flat => None,
        CutterKind::Ball => {
            let c = tip + big_r * axis;
            let (ex, ey) = (x - c.x, y - c.y);
            let s2 = big_r * big_r - ex * ex - ey * ey;
            (s2 >= 0.0).then(|| (c.z - s2.sqrt(), c.z + s2.sqrt()))
        }
        CutterKind::Fillet => fillet_corner(tool, tip, axis, x, y),
    };
    match (body, corner) {
        (Some(p), Some(q)) => Some((p.0.min(q.0), p.1.max(q.1))),
        (p, q) => p.or(q),
    }
}

/// The ray against the points within r of the centre disk (radius R0 at T + r·a, normal a).
fn fillet_corner(tool: &ToolShape, tip: DVec3, axis: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    let r = tool.corner_mm;
    let r0 = tool.torus_mm();
    // The corner body lies inside the cylinder of radius R from T to T + 2r·a.
    let (zl, zh) = ray_cylinder(tip, axis, 2.0 * r, tool.radius_mm, x, y)?;
    let centre = tip + r * axis;
    let excess = |z: f64| {
        let v = DVec3::new(x, y, z) - centre;
        let h = v.dot(axis);
        let rho = (v - h * axis).length();
        // sqrt rather than hypot: IEEE-exact, so the rays are bit-identical across platforms.
        let d = if rho <= r0 { h.abs() } else { (h * h + (rho - r0) * (rho - r0)).sqrt() };
        d - r
    };
    let (zm, m) = golden_min(excess, zl, zh, ROOT_TOL_MM);
    if m > 0.0 {
        return None;
    }
    Some((bisect_root(&excess, zl, zm), bisect_root(&excess, zh, zm)))
}

/// The point between `outside` (excess > 0, or the bracket's end) and `inside` (excess ≤ 0)
/// where the excess crosses zero, to [`ROOT_TOL_MM`]; returns the inside end of the bracket.
fn bisect_root(excess: &impl Fn(f64) -> f64, outside: f64, inside: f64) -> f64 {
    if excess(outside) <= 0.0 {
        return outside;
    }
    let (mut o, mut i) = (outside, inside);
    for _ in 0..MAX_SOLVE_ITERATIONS {
        if (o - i).abs() <= ROOT_TOL_MM {
            break;
        }
        let m = 0.5 * (o + i);
        if excess(m) <= 0.0 {
            i = m;
        } else {
            o = m;
        }
    }
    i
}

/// The axis-aligned box (min, max) (mm) of a tilted cutter's body up to `h_mm` above the
/// tip: the hull of the two end disks of the cylinder of radius R.
#[must_use]
pub fn tilted_box(tool: &ToolShape, tip: DVec3, axis: DVec3, h_mm: f64) -> (DVec3, DVec3) {
    let r = tool.radius_mm;
    let ext = DVec3::new(
        r * (1.0 - axis.x * axis.x).max(0.0).sqrt(),
        r * (1.0 - axis.y * axis.y).max(0.0).sqrt(),
        r * (1.0 - axis.z * axis.z).max(0.0).sqrt(),
    );
    let top = tip + h_mm * axis;
    (tip.min(top) - ext, tip.max(top) + ext)
}
