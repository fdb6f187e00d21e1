//! Where a ray meets a surface: what a click in a 3D view picks (the fillet tab's start
//! curve). The surface is cut into an n × n grid of parameter cells, two triangles each; the
//! nearest triangle the ray crosses gives a first (u, v, t), which Newton's method on
//! S(u, v) = o + t·d refines to the surface itself (at most [`RAY_NEWTON_STEPS`] steps,
//! staying inside the domain). Bounded: n is clamped to [`RAY_GRID_MAX`].

use glam::{DVec2, DVec3};

use super::{ParametricSurface, Surface};
use crate::numerics::linalg::solve3_rows;
use crate::numerics::tolerance::{NEWTON_LENGTH_MM, RAY_TRIANGLE_SLACK};

/// Most cells of the grid a side.
pub const RAY_GRID_MAX: usize = 512;
/// Most Newton steps of the refinement.
pub const RAY_NEWTON_STEPS: usize = 12;

/// A ray's first hit on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Surface parameters (internal units).
    pub uv: DVec2,
    /// Distance along the ray from its start (mm, the ray's direction unit).
    pub t_mm: f64,
    /// The surface point S(uv) (mm).
    pub point: DVec3,
}

/// Parameter t of the ray `o + t·d` through the triangle (a, b, c) and the barycentric
/// weights of b and c, if it crosses it ahead of o (Möller–Trumbore).
fn triangle(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if !(det.abs() > f64::EPSILON * e1.length() * e2.length()) {
        return None;
    }
    let s = o - a;
    let w1 = s.dot(p) / det;
    let q = s.cross(e1);
    let w2 = d.dot(q) / det;
    let slack = RAY_TRIANGLE_SLACK;
    if w1 < -slack || w2 < -slack || w1 + w2 > 1.0 + slack {
        return None;
    }
    let t = e2.dot(q) / det;
    (t > 0.0).then_some((t, w1, w2))
}

/// The first point where the ray `origin + t·dir` (t > 0) meets `surface`, from a grid of
/// `grid` × `grid` cells (clamped to 2 … [`RAY_GRID_MAX`]); `None` when it misses (or `dir`
/// is zero). The hit lies on the surface to Newton's tolerance where the refinement
/// converges inside the domain, else on the triangle (within the grid's chord error).
#[must_use]
pub fn ray_hit(surface: &Surface, origin: DVec3, dir: DVec3, grid: usize) -> Option<RayHit> {
    let d = dir.try_normalize()?;
    let n = grid.clamp(2, RAY_GRID_MAX);
    let dom = surface.domain();
    let uv_at = |i: usize, j: usize| {
        DVec2::new(dom.u.min + dom.u.width() * i as f64 / n as f64, dom.v.min + dom.v.width() * j as f64 / n as f64)
    };
    // One row of points at a time: two rows in memory.
    let row = |j: usize| (0..=n).map(|i| surface.point_at(uv_at(i, j))).collect::<Vec<_>>();
    let mut below = row(0);
    let mut best: Option<(f64, DVec2)> = None;
    for j in 0..n {
        let above = row(j + 1);
        for i in 0..n {
            let (p00, p10, p01, p11) = (below[i], below[i + 1], above[i], above[i + 1]);
            let (q00, q10, q01, q11) = (uv_at(i, j), uv_at(i + 1, j), uv_at(i, j + 1), uv_at(i + 1, j + 1));
            for (a, b, c, ua, ub, uc) in [(p00, p10, p11, q00, q10, q11), (p00, p11, p01, q00, q11, q01)] {
                if let Some((t, w1, w2)) = triangle(origin, d, a, b, c)
                    && best.is_none_or(|(bt, _)| t < bt)
                {
                    best = Some((t, ua + (ub - ua) * w1 + (uc - ua) * w2));
                }
            }
        }
        below = above;
    }
    let (t0, uv0) = best?;
    // Newton on F(u, v, t) = S(u, v) − o − t·d: rows of J are the x, y, z components of
    // [S_u, S_v, −d].
    let (mut uv, mut t) = (dom.clamp(uv0), t0);
    for _ in 0..RAY_NEWTON_STEPS {
        let s = surface.derivatives_at(uv);
        let f = s.point - origin - t * d;
        if f.length() < NEWTON_LENGTH_MM {
            return Some(RayHit { uv, t_mm: t, point: s.point });
        }
        let rows =
            [DVec3::new(s.du.x, s.dv.x, -d.x), DVec3::new(s.du.y, s.dv.y, -d.y), DVec3::new(s.du.z, s.dv.z, -d.z)];
        let Some(step) = solve3_rows(rows[0], rows[1], rows[2], -f) else { break };
        let next = uv + DVec2::new(step.x, step.y);
        if !dom.contains(next) {
            break;
        }
        uv = dom.clamp(next);
        t += step.z;
    }
    Some(RayHit { uv: dom.clamp(uv0), t_mm: t0, point: origin + t0 * d })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Cylinder, Frame, Plane};
    use crate::geom::{Domain, ParamRange, ParamUnit};

    /// On a plane the hit is the closed-form intersection; on a cylinder the root of the
    /// quadratic, the nearer of two; a ray past the surface misses.
    #[test]
    fn rays_hit_a_plane_and_a_cylinder_where_the_closed_forms_say() {
        let plane =
            Surface::Plane(Plane::new(DVec3::new(0.0, 0.0, 2.0), DVec3::Z, DVec3::X, [-10.0, 30.0], [0.0, 20.0]));
        for (o, d) in [
            (DVec3::new(3.0, 4.0, 50.0), DVec3::new(0.1, 0.2, -1.0)),
            (DVec3::new(-5.0, 19.0, -7.0), DVec3::new(0.3, -0.5, 1.0)),
        ] {
            let hit = ray_hit(&plane, o, d, 16).expect("hit");
            let dn = d.normalize();
            let t = (2.0 - o.z) / dn.z;
            let p = o + t * dn;
            assert!((hit.t_mm - t).abs() < 1e-9 && (hit.point - p).length() < 1e-9, "{hit:?} against {p}");
            assert!((hit.uv - DVec2::new(p.x, p.y)).length() < 1e-9);
        }
        assert!(ray_hit(&plane, DVec3::new(100.0, 4.0, 50.0), -DVec3::Z, 16).is_none(), "outside the domain");
        assert!(ray_hit(&plane, DVec3::new(3.0, 4.0, 50.0), DVec3::Z, 16).is_none(), "pointing away");
        let rho = 30.0;
        let cyl = Surface::Cylinder(Cylinder {
            origin: DVec3::ZERO,
            frame: Frame::from_axis(DVec3::Z, Some(DVec3::X)),
            radius: rho,
            sign: 1.0,
            domain: Domain {
                u: ParamRange::new(0.0, std::f64::consts::TAU, ParamUnit::Angle),
                v: ParamRange::new(0.0, 40.0, ParamUnit::Length),
            },
        });
        for (o, d) in [
            (DVec3::new(100.0, 7.0, 12.0), DVec3::new(-1.0, 0.05, 0.1)),
            (DVec3::new(-20.0, 80.0, 30.0), DVec3::new(0.2, -1.0, -0.3)),
        ] {
            let hit = ray_hit(&cyl, o, d, 32).expect("hit");
            let dn = d.normalize();
            // |(o + t d)_xy| = ρ: the smaller root.
            let (a, b, c) = (
                dn.truncate().length_squared(),
                2.0 * o.truncate().dot(dn.truncate()),
                o.truncate().length_squared() - rho * rho,
            );
            let t = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
            let p = o + t * dn;
            assert!((hit.point - p).length() < 1e-8 && (hit.t_mm - t).abs() < 1e-8, "{hit:?} against {p}");
            assert!((cyl.point_at(hit.uv) - p).length() < 1e-8);
        }
    }
}
