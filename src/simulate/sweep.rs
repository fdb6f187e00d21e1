//! Where a cutter, or the envelope it sweeps along a move, crosses one vertical ray.
//!
//! The cutting tool is the cutter's solid of revolution up to its *flute top* H, the flute
//! length (at least 2r and the cone height): the bottom (flat, corner torus) and the flank of
//! radius R up to H. The shank and the holder above never cut: they are checked against the
//! stock for crashes ([`super::crash`]). Tilted tool (tip T, unit axis a), in the tool frame
//! of [`crate::geom::cutter`]:
//!
//! - ball: the sphere of radius R centred at T + R·a, and the cylinder of radius R from
//!   that centre up to T + H·a;
//! - flat: the cylinder of radius R from T to T + H·a;
//! - fillet: the points within r of the disk of radius R0 = R − r centred at T + r·a
//!   (that is the flat bottom and the corner torus, and a little above it inside the
//!   flank), and the cylinder of radius R from T + r·a to T + H·a. Exact when H ≥ 2r;
//! - tapered (V cutter, drill): the cone frustum from the flat tip of radius r_t at T to the
//!   radius R at T + h_c·a (the points whose distance from the axis is at most
//!   r_t + h·tan α at height h), and the cylinder of radius R from T + h_c·a to T + H·a.
//!
//! Each body is convex, so a ray crosses it in one interval, found in closed form (sphere,
//! cylinder, cone: a quadratic) or, for the fillet's corner, by Newton's steps on the convex
//! distance along the ray to the centre disk, from both ends, to [`super::ROOT_TOL_MM`].

use glam::DVec3;

use super::crash::Part;
use super::{MAX_SOLVE_ITERATIONS, ROOT_TOL_MM};
use crate::geom::{Cutter, CutterKind};
use crate::numerics::maximise::golden_bracket;

/// The simulated shape of a cutter (mm): what [`Cutter`] says, reduced to what cuts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolShape {
    /// Ball, fillet or flat.
    pub kind: CutterKind,
    /// Cutter radius R (mm).
    pub radius_mm: f64,
    /// Corner radius r (mm).
    pub corner_mm: f64,
    /// Flute top H above the tip (mm): the flute length, at least 2r and the cone height.
    pub top_mm: f64,
    /// The shank above the flutes, `None` when it has no length.
    pub shank: Option<Part>,
    /// The holder above the shank.
    pub holder: Option<Part>,
    /// Whether the end cuts at its centre.
    pub centre_cutting: bool,
    /// Tapered cutters: the radius of the flat at the tip, r_t (mm); 0 for the others.
    pub tip_flat_mm: f64,
    /// Tapered cutters: cot α, the cone's rise per mm of radius; 0 for the others.
    pub cot: f64,
    /// Tapered cutters: the cone height h_c = (R − r_t)·cot α (mm); 0 for the others.
    pub cone_mm: f64,
}

impl ToolShape {
    /// The simulated shape of a cutter.
    #[must_use]
    pub fn of(cutter: &Cutter) -> Self {
        let kind = cutter.kind();
        let corner_mm = match kind {
            CutterKind::Ball => cutter.radius_mm,
            CutterKind::Flat | CutterKind::Tapered => 0.0,
            CutterKind::Fillet => cutter.corner_radius_mm,
        };
        let (tip_flat_mm, cot) = cutter.taper.map_or((0.0, 0.0), |t| (t.tip_radius_mm, 1.0 / t.half_angle_rad.tan()));
        let cone_mm = cutter.cone_height_mm();
        let top_mm = cutter.flute_length_mm.max(2.0 * corner_mm).max(cone_mm);
        let gauge = cutter.gauge_length_mm.max(top_mm);
        let part = |radius_mm: f64, from_mm: f64, to_mm: f64| {
            (to_mm > from_mm && radius_mm > 0.0).then_some(Part { radius_mm, from_mm, to_mm })
        };
        Self {
            kind,
            radius_mm: cutter.radius_mm,
            corner_mm,
            top_mm,
            shank: part(cutter.shank_radius_mm, top_mm, gauge),
            holder: part(cutter.holder_radius_mm, gauge, gauge + cutter.holder_length_mm),
            centre_cutting: cutter.centre_cutting,
            tip_flat_mm,
            cot,
            cone_mm,
        }
    }

    /// A flat end mill of the part's radius and length, to sweep the part as a cutter whose
    /// tip is the part's bottom.
    #[must_use]
    pub fn of_part(part: &Part) -> Self {
        Self {
            kind: CutterKind::Flat,
            radius_mm: part.radius_mm,
            corner_mm: 0.0,
            top_mm: part.to_mm - part.from_mm,
            shank: None,
            holder: None,
            centre_cutting: true,
            tip_flat_mm: 0.0,
            cot: 0.0,
            cone_mm: 0.0,
        }
    }

    /// The flutes shrunk by `d_mm` in radius (and corner) and top, to be placed `d_mm` higher:
    /// a solid at least about `d_mm` inside the flutes, for a touch tolerance.
    #[must_use]
    pub fn shrunk(&self, d_mm: f64) -> Self {
        let radius_mm = (self.radius_mm - d_mm).max(d_mm);
        let corner_mm = if self.kind == CutterKind::Ball { radius_mm } else { (self.corner_mm - d_mm).max(0.0) };
        let tip_flat_mm = (self.tip_flat_mm - d_mm).max(0.0);
        let cone_mm =
            if self.kind == CutterKind::Tapered { (radius_mm - tip_flat_mm).max(0.0) * self.cot } else { 0.0 };
        Self {
            radius_mm,
            corner_mm,
            tip_flat_mm,
            cone_mm,
            top_mm: (self.top_mm - 2.0 * d_mm).max(2.0 * corner_mm).max(cone_mm),
            shank: None,
            holder: None,
            ..*self
        }
    }

    /// The widest radius of the flutes, the shank and the holder (mm).
    #[must_use]
    pub fn widest_mm(&self) -> f64 {
        let p = |p: Option<Part>| p.map_or(0.0, |p| p.radius_mm);
        self.radius_mm.max(p(self.shank)).max(p(self.holder))
    }

    /// R0 = R − r (mm).
    #[must_use]
    pub fn torus_mm(&self) -> f64 {
        (self.radius_mm - self.corner_mm).max(0.0)
    }

    /// Height of the bottom above the tip at radial distance ρ ≤ R (mm).
    #[must_use]
    pub fn bottom_mm(&self, rho_mm: f64) -> f64 {
        if self.kind == CutterKind::Tapered {
            return (rho_mm - self.tip_flat_mm).max(0.0) * self.cot;
        }
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
/// sloped move (and a tapered cutter's) the function is convex in the move's parameter and
/// is minimised by golden sections to [`ROOT_TOL_MM`] of the move's length. hi is the highest tip height over the
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
            CutterKind::Fillet | CutterKind::Tapered => self.tool.bottom_mm(rho2.sqrt()),
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
            CutterKind::Fillet | CutterKind::Tapered => {
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

/// The minimum of a convex f on [a, b]: golden sections ([`golden_bracket`] on −f) down to
/// a bracket of width `tol` (at most [`MAX_SOLVE_ITERATIONS`] steps), then the bracket's
/// ends too (the minimum of a monotone f sits there): `(argmin, min)`.
fn golden_min(f: impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    let g = golden_bracket(&mut |t| -f(t), a, b, tol, MAX_SOLVE_ITERATIONS);
    let (x, v) = g.best_inner();
    let mut best = (x, -v);
    for t in [g.lo, g.hi] {
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
    // The flank starts above the corner (r) or the cone (h_c); one of them is 0.
    let r = tool.corner_mm + tool.cone_mm;
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
        CutterKind::Tapered => cone_span(tool, tip, axis, x, y),
    };
    match (body, corner) {
        (Some(p), Some(q)) => Some((p.0.min(q.0), p.1.max(q.1))),
        (p, q) => p.or(q),
    }
}

/// The ray against a tapered cutter's cone frustum: the part of the infinite cone with apex
/// A = T − r_t·cot α·a, half angle α, between the heights h₀ = r_t·cot α and h₀ + h_c above
/// A. A point p = A + w lies in the cone when cos²α·|w|² − (w·a)² ≤ 0 and w·a ≥ 0; along the
/// ray that is a quadratic in z, and the slab bounds z linearly. The frustum is convex, so
/// the ray meets it in one interval.
fn cone_span(tool: &ToolShape, tip: DVec3, axis: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    let h0 = tool.tip_flat_mm * tool.cot;
    let apex = tip - h0 * axis;
    let w0 = DVec3::new(x - apex.x, y - apex.y, -apex.z);
    let wa = w0.dot(axis);
    let az = axis.z;
    // Slab h₀ ≤ w·a ≤ h₀ + h_c, with w·a = wa + z·a_z.
    let (lo, hi) = if az.abs() > super::AXIS_FLAT_SIN {
        let za = (h0 - wa) / az;
        let zb = (h0 + tool.cone_mm - wa) / az;
        (za.min(zb), za.max(zb))
    } else if (h0..=h0 + tool.cone_mm).contains(&wa) {
        (f64::NEG_INFINITY, f64::INFINITY)
    } else {
        return None;
    };
    // cos²α = cot²α / (1 + cot²α).
    let c2 = tool.cot * tool.cot / (1.0 + tool.cot * tool.cot);
    let qa = c2 - az * az;
    let qb = 2.0 * (c2 * w0.z - wa * az);
    let qc = c2 * w0.length_squared() - wa * wa;
    quadratic_le_zero(qa, qb, qc, lo, hi)
}

/// The interval of z in [lo, hi] where qa·z² + qb·z + qc ≤ 0, for a quadratic known to be
/// ≤ 0 on at most one interval there (a convex body's section); `None` when empty. Where the
/// quadratic opens downward its two outer pieces are cut to [lo, hi] and the longer kept
/// (the other is empty unless the ray only touches the body).
fn quadratic_le_zero(qa: f64, qb: f64, qc: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    let keep = |a: f64, b: f64| (a <= b && a.is_finite() && b.is_finite()).then_some((a, b));
    let scale = qa.abs().max(qb.abs()).max(qc.abs()).max(f64::MIN_POSITIVE);
    if qa.abs() <= super::AXIS_FLAT_SIN * scale {
        // Linear: qb·z + qc ≤ 0.
        if qb.abs() <= f64::MIN_POSITIVE {
            return if qc <= 0.0 { keep(lo, hi) } else { None };
        }
        let z = -qc / qb;
        return if qb > 0.0 { keep(lo, hi.min(z)) } else { keep(lo.max(z), hi) };
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if qa > 0.0 {
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        let (r1, r2) = ((-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa));
        return keep(lo.max(r1.min(r2)), hi.min(r1.max(r2)));
    }
    if disc <= 0.0 {
        return keep(lo, hi);
    }
    let s = disc.sqrt();
    let (r1, r2) = ((-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa));
    let (r1, r2) = (r1.min(r2), r1.max(r2));
    match (keep(lo, hi.min(r1)), keep(lo.max(r2), hi)) {
        (Some(a), Some(b)) => Some(if a.1 - a.0 >= b.1 - b.0 { a } else { b }),
        (a, b) => a.or(b),
    }
}

/// The ray against the points within r of the centre disk (radius R0 at T + r·a, normal a).
///
/// The excess e(z) = (distance from the ray's point to the disk) − r is convex along the ray
/// (the distance to a convex set is), so Newton's steps from either end of the bracket (the
/// cylinder of radius R around the corner) move monotonically toward the root on that side,
/// each landing short of it (a convex function lies above its tangents), and a slope that
/// turns before the excess reaches 0 shows the ray misses: 2.0–3.7 evaluations a root on the
/// examples' programs, where golden sections for the minimum and two bisections took some
/// ninety.
fn fillet_corner(tool: &ToolShape, tip: DVec3, axis: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    let r = tool.corner_mm;
    let r0 = tool.torus_mm();
    // The corner body lies inside the cylinder of radius R from T to T + 2r·a.
    let (zl, zh) = ray_cylinder(tip, axis, 2.0 * r, tool.radius_mm, x, y)?;
    let centre = tip + r * axis;
    // The excess and its derivative in z. With v the point from the centre, h = v·a its
    // height over the disk's plane and u = v − h·a its radial part (ρ = |u|): h' = a_z and
    // ρ' = u_z / ρ.
    let excess = |z: f64| {
        let v = DVec3::new(x, y, z) - centre;
        let h = v.dot(axis);
        let u = v - h * axis;
        let rho = u.length();
        if rho <= r0 {
            (h.abs() - r, if h >= 0.0 { axis.z } else { -axis.z })
        } else {
            let e = rho - r0;
            // sqrt rather than hypot: IEEE-exact, so the rays are bit-identical across platforms.
            let d = (h * h + e * e).sqrt();
            (d - r, (h * axis.z + e * u.z / rho) / d)
        }
    };
    let lo = newton_root(&excess, zl, zh)?;
    // The ray enters the body, so it leaves it: from the top, the same steps downward.
    let hi = newton_root(&excess, zh, lo).unwrap_or(lo);
    Some((lo, hi))
}

/// The root of a convex `excess` (value, derivative) met first walking from `from` toward
/// `toward` (either direction), by Newton's steps, which for a convex function never pass
/// it: `from` itself when the excess is ≤ 0 there, `None` when the excess turns upward (or
/// the walk passes `toward`) before it reaches 0. Stops once a step is under
/// [`ROOT_TOL_MM`] (the root is then nearer than that: the steps shrink at least as fast as
/// the distance left), or after [`MAX_SOLVE_ITERATIONS`] steps.
fn newton_root(excess: &impl Fn(f64) -> (f64, f64), from: f64, toward: f64) -> Option<f64> {
    let dir = if toward >= from { 1.0 } else { -1.0 };
    let mut z = from;
    for _ in 0..MAX_SOLVE_ITERATIONS {
        let (e, de) = excess(z);
        if e <= 0.0 {
            return Some(z);
        }
        // The slope toward `toward`: the excess must fall that way for a root to lie ahead.
        let fall = -de * dir;
        if !(fall > 0.0) {
            return None;
        }
        let step = e / fall;
        z += dir * step;
        if (z - toward) * dir > 0.0 {
            return None;
        }
        if step <= ROOT_TOL_MM {
            return Some(z);
        }
    }
    Some(z)
}

/// The ray at (x, y) against a part of a tilted tool (tip, unit axis): the interval of z
/// inside it (mm), `None` when it misses.
#[must_use]
pub fn part_span(part: &Part, tip: DVec3, axis: DVec3, x: f64, y: f64) -> Option<(f64, f64)> {
    ray_cylinder(tip + part.from_mm * axis, axis, part.to_mm - part.from_mm, part.radius_mm, x, y)
}

/// The box (mm) around a part of a tilted tool.
#[must_use]
pub fn part_box(part: &Part, tip: DVec3, axis: DVec3) -> (DVec3, DVec3) {
    let r = part.radius_mm;
    let ext = DVec3::new(
        r * (1.0 - axis.x * axis.x).max(0.0).sqrt(),
        r * (1.0 - axis.y * axis.y).max(0.0).sqrt(),
        r * (1.0 - axis.z * axis.z).max(0.0).sqrt(),
    );
    let (a, b) = (tip + part.from_mm * axis, tip + part.to_mm * axis);
    (a.min(b) - ext, a.max(b) + ext)
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

/// The smaller of two numbers that are not NaN: a plain comparison (one select in wasm32,
/// where `f64::min` must also handle NaN and costs several instructions).
#[inline]
fn lesser(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// The larger of two numbers that are not NaN (see [`lesser`]).
#[inline]
fn greater(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// A solid cylinder without end caps, set up for vertical rays: radius R around the segment
/// from `p0` along the unit `axis` for `len` mm (the region between the two end planes
/// perpendicular to the axis). Everything that does not depend on the ray is precomputed, so
/// a ray costs a few multiplications and, when it hits, one square root.
#[derive(Clone, Copy, Debug)]
struct RayCyl {
    p0: DVec3,
    axis: DVec3,
    len: f64,
    r2: f64,
    /// 1 / a_z, or 0 when the axis is horizontal (the slab does not bound z).
    inv_az: f64,
    /// 1 − a_z², and 1 / (2(1 − a_z²)) or 0 when the axis is vertical.
    qa: f64,
    inv_2qa: f64,
    /// The x range (mm) of the cylinder's box: rays outside miss it.
    x_range: (f64, f64),
}

impl RayCyl {
    fn new(p0: DVec3, axis: DVec3, len: f64, radius: f64) -> Self {
        let p1 = p0 + len * axis;
        let x_range = (p0.x.min(p1.x) - radius, p0.x.max(p1.x) + radius);
        let az = axis.z;
        let inv_az = if az.abs() > super::AXIS_FLAT_SIN { 1.0 / az } else { 0.0 };
        let qa = 1.0 - az * az;
        let inv_2qa = if qa > super::AXIS_FLAT_SIN * super::AXIS_FLAT_SIN { 0.5 / qa } else { 0.0 };
        Self { p0, axis, len, r2: radius * radius, inv_az, qa, inv_2qa, x_range }
    }

    /// The span of z of the ray at (x, y) inside the cylinder (the same solid as
    /// `ray_cylinder`).
    #[inline]
    fn span(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        if x < self.x_range.0 || x > self.x_range.1 {
            return None;
        }
        let (dx, dy, pz) = (x - self.p0.x, y - self.p0.y, self.p0.z);
        let a = self.axis;
        // w(z) = (dx, dy, z − pz); w·a = wa + z·a_z.
        let wa = dx * a.x + dy * a.y - pz * a.z;
        let (mut lo, mut hi) = if self.inv_az != 0.0 {
            let za = -wa * self.inv_az;
            let zb = (self.len - wa) * self.inv_az;
            (lesser(za, zb), greater(za, zb))
        } else if (0.0..=self.len).contains(&wa) {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            return None;
        };
        let qc = dx * dx + dy * dy + pz * pz - wa * wa - self.r2;
        if self.inv_2qa == 0.0 {
            if qc > 0.0 {
                return None;
            }
        } else {
            let qb = 2.0 * (-pz - wa * a.z);
            let disc = qb * qb - 4.0 * self.qa * qc;
            if disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            lo = greater(lo, (-qb - s) * self.inv_2qa);
            hi = lesser(hi, (-qb + s) * self.inv_2qa);
        }
        (lo <= hi && lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    }
}

/// One linear constraint m·p + k ≥ 0 on the points p of a ray, as a bound on z.
#[derive(Clone, Copy, Debug)]
struct HalfSpace {
    mx: f64,
    my: f64,
    k: f64,
    /// 1 / m_z, or 0 when m is horizontal.
    inv_mz: f64,
}

impl HalfSpace {
    /// The half-space of p with m·(p − v) ≥ 0.
    fn new(m: DVec3, v: DVec3) -> Self {
        let inv_mz = if m.z.abs() > super::AXIS_FLAT_SIN { 1.0 / m.z } else { 0.0 };
        Self { mx: m.x, my: m.y, k: -m.dot(v), inv_mz }
    }

    /// Narrows [lo, hi] to the ray's part inside; false when nothing is left.
    #[inline]
    fn clip(&self, x: f64, y: f64, lo: &mut f64, hi: &mut f64) -> bool {
        let f0 = self.mx * x + self.my * y + self.k;
        if self.inv_mz == 0.0 {
            return f0 >= 0.0;
        }
        let z = -f0 * self.inv_mz;
        if self.inv_mz > 0.0 {
            *lo = greater(*lo, z);
        } else {
            *hi = lesser(*hi, z);
        }
        *lo <= *hi
    }
}

/// The points within R of a triangle's plane, over the triangle: the slab of thickness 2R
/// around its plane cut by the three planes through its edges perpendicular to it.
#[derive(Clone, Copy, Debug)]
struct ThickTriangle {
    faces: [HalfSpace; 5],
    /// The x range (mm) of the triangle's box widened by R: rays outside miss it.
    x_range: (f64, f64),
}

impl ThickTriangle {
    /// `None` for a triangle with no area (its edges' capsules cover it).
    fn new(v: [DVec3; 3], radius: f64) -> Option<Self> {
        let n = (v[1] - v[0]).cross(v[2] - v[0]);
        let area2 = n.length();
        if !(area2 > super::SAME_POINT_MM * super::SAME_POINT_MM) {
            return None;
        }
        let n = n / area2;
        let edge = |i: usize| {
            let (a, b, c) = (v[i], v[(i + 1) % 3], v[(i + 2) % 3]);
            let m = n.cross(b - a);
            HalfSpace::new(if m.dot(c - a) >= 0.0 { m } else { -m }, a)
        };
        Some(Self {
            faces: [
                HalfSpace::new(n, v[0] - radius * n),
                HalfSpace::new(-n, v[0] + radius * n),
                edge(0),
                edge(1),
                edge(2),
            ],
            x_range: (v[0].x.min(v[1].x).min(v[2].x) - radius, v[0].x.max(v[1].x).max(v[2].x) + radius),
        })
    }

    #[inline]
    fn span(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        if x < self.x_range.0 || x > self.x_range.1 {
            return None;
        }
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for f in &self.faces {
            if !f.clip(x, y, &mut lo, &mut hi) {
                return None;
            }
        }
        (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
    }
}

/// The envelope a ball-end cutter sweeps between two poses, in closed form.
///
/// The simulated ball-end tool is the set of points within R of its axis segment from the
/// ball centre c up to the body length L above it (the ball, and the flank cylinder; its top
/// is flat, see below). Moving from pose (c₀, a₀) to (c₁, a₁) with the centre and the axis
/// interpolated linearly, the axis segment sweeps the ruled quadrilateral c₀, c₁, c₁ + L·a₁,
/// c₀ + L·a₀, so the envelope is the set of points within R of it. That quadrilateral is
/// taken as its two triangles (c₀, c₁, c₁ + L·a₁) and (c₀, c₁ + L·a₁, c₀ + L·a₀): within
/// |L·(a₁ − a₀)|/4 of the ruled surface (its twist), exact when the axis does not turn. The
/// points within R of the triangles are the pieces this sweep tests a ray against: the
/// capsule of the centres' chord (two spheres and a cylinder — the ball's sweep, exact for a
/// straight centre path), the flank cylinders of the two poses, the cylinder around the
/// diagonal (it fills the notch where the two triangles fold) and the two triangles
/// thickened by R. The rounding along the top edge is left out: L is chosen where the body
/// is above the stock, so it removes nothing; otherwise the top stays flat as in
/// [`tilted_span`].
#[derive(Clone, Copy, Debug)]
pub struct BallSegment {
    /// Ball centres tested (the start pose's is left out when the previous segment ended at
    /// the same pose and has cut it already).
    centres: [DVec3; 2],
    n_centres: usize,
    r2: f64,
    /// The chord's cylinder, the flanks, the diagonal's cylinder (those that exist).
    cyls: [Option<RayCyl>; 4],
    tri: [Option<ThickTriangle>; 2],
}

/// Part of the sweep tolerance the notch along the diagonal may take before its cylinder is
/// tested (the rest goes to the twist and the sagitta, see `Simulation::segments_of`).
pub const NOTCH_SHARE: f64 = 0.125;

impl BallSegment {
    /// The sweep of a ball of radius `radius_mm` whose centre moves from `c0` to `c1` while
    /// its unit axis turns from `a0` to `a1`, with `body_mm` (L) of flank above the centre.
    /// The diagonal's cylinder is left out when the notch it fills, R(1 − cos δ/2) for the
    /// fold δ between the two triangles, is at most [`NOTCH_SHARE`] × `tol_mm`.
    #[must_use]
    pub fn new(radius_mm: f64, c0: DVec3, a0: DVec3, c1: DVec3, a1: DVec3, body_mm: f64, tol_mm: f64) -> Self {
        let d = c1 - c0;
        let len = d.length();
        let chord = (len > super::SAME_POINT_MM).then(|| RayCyl::new(c0, d / len, len, radius_mm));
        let flank = |c: DVec3, a: DVec3| (body_mm > 0.0).then(|| RayCyl::new(c, a, body_mm, radius_mm));
        let (t0, t1) = (c0 + body_mm * a0, c1 + body_mm * a1);
        let tri = if body_mm > 0.0 {
            [ThickTriangle::new([c0, c1, t1], radius_mm), ThickTriangle::new([c0, t1, t0], radius_mm)]
        } else {
            [None, None]
        };
        // cos δ between the triangles' normals (1 when either is degenerate: no fold).
        let n1 = (c1 - c0).cross(t1 - c0).normalize_or_zero();
        let n2 = (t1 - c0).cross(t0 - c0).normalize_or_zero();
        let cos_fold = if n1 == DVec3::ZERO || n2 == DVec3::ZERO { 1.0 } else { n1.dot(n2).clamp(-1.0, 1.0) };
        let notch = radius_mm * (1.0 - (0.5 * (1.0 + cos_fold)).sqrt());
        let diag = t1 - c0;
        let diag_len = diag.length();
        let diagonal = (body_mm > 0.0 && diag_len > super::SAME_POINT_MM && notch > NOTCH_SHARE * tol_mm)
            .then(|| RayCyl::new(c0, diag / diag_len, diag_len, radius_mm));
        Self {
            centres: [c1, c0],
            n_centres: 2,
            r2: radius_mm * radius_mm,
            cyls: [chord, flank(c1, a1), diagonal, flank(c0, a0)],
            tri,
        }
    }

    /// The same sweep without the start pose's ball and flank: for a segment that begins
    /// where the previous one, already subtracted, ended (the union of the two subtractions
    /// is unchanged).
    #[must_use]
    pub fn continuing(mut self) -> Self {
        self.n_centres = 1;
        self.cyls[3] = None;
        self
    }

    /// The span of z of the ray at (x, y) inside the sweep (mm), `None` when it misses.
    #[inline]
    #[must_use]
    pub fn span(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in &self.centres[..self.n_centres] {
            let (ex, ey) = (x - c.x, y - c.y);
            let s2 = self.r2 - ex * ex - ey * ey;
            if s2 >= 0.0 {
                let s = s2.sqrt();
                lo = lesser(lo, c.z - s);
                hi = greater(hi, c.z + s);
            }
        }
        for cyl in self.cyls.iter().flatten() {
            if let Some((l, h)) = cyl.span(x, y) {
                lo = lesser(lo, l);
                hi = greater(hi, h);
            }
        }
        for t in self.tri.iter().flatten() {
            if let Some((l, h)) = t.span(x, y) {
                lo = lesser(lo, l);
                hi = greater(hi, h);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}
