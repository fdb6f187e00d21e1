//! Gouge and interference checks of a placed cutter against the part, and the adjustment of
//! the orientation until they pass.
//!
//! - **Local, bottom and rear**: points of the cutter's lower surface (flat bottom and
//!   corner, 36 meridians × 8 heights) are projected onto the surface; one more than the
//!   tolerance below it is a gouge, unless its foot is on an edge of the domain and the point
//!   lies beyond that edge (over no material). Points that lie higher above the
//!   tangent plane than the part can rise within that distance (½·k⁺·d², k⁺ the part's
//!   largest concave normal curvature, sampled once) cannot be below it and are skipped; on
//!   a part convex everywhere (k⁺ ≤ 0) the cutter, a convex solid resting on the tangent
//!   plane, cannot gouge, and this check costs nothing.
//! - **Global**: the part's sample points (a grid) against the cutter's solid of revolution
//!   around the axis: a point at height z above the tip and distance ρ from the axis
//!   collides when ρ < (the solid's radius at z) − tolerance — with the flutes (a gouge), the
//!   shank or the holder (an interference).
//!
//! Where a check fails the inclination is raised in steps of 0.25° (to the strategy's largest),
//! then the azimuth turned by ±10°, ±20°, ±30°; the first pose that passes is kept and the
//! change reported. When none passes the point is refused with the reason.

use glam::{DVec2, DVec3};

use super::contact::{ContactFrame, Pose, gouge_margin, place};
use super::orient::OrientOptions;
use crate::geom::{Cutter, LocalGeometry, ParametricSurface, ProjectOptions, Surface, project_point};

/// Which part of the cutter met the part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClashPart {
    /// The bottom or corner (a local or rear gouge).
    Bottom,
    /// The flank of the flutes (a gouge).
    Flank,
    /// The shank (an interference).
    Shank,
    /// The holder (an interference).
    Holder,
}

impl ClashPart {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Bottom => "bottom",
            Self::Flank => "flank",
            Self::Shank => "shank",
            Self::Holder => "holder",
        }
    }
}

/// A failed check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clash {
    /// Where on the cutter.
    pub part: ClashPart,
    /// How far the part reaches into the cutter (mm).
    pub depth_mm: f64,
    /// The part's point (mm).
    pub at: DVec3,
}

/// The part sampled once for all checks.
#[derive(Clone, Debug)]
pub struct PartSamples {
    /// Grid points of the surface (mm).
    pub points: Vec<DVec3>,
    /// The largest concave normal curvature k⁺ found on the grid (1/mm; ≤ 0 when convex
    /// everywhere).
    pub k_concave_max: f64,
}

impl PartSamples {
    /// An n × n grid over the domain (n clamped to [4, 200]).
    #[must_use]
    pub fn new(surface: &Surface, n: usize) -> Self {
        let n = n.clamp(4, 200);
        let dom = surface.domain();
        let mut points = Vec::with_capacity(n * n);
        let mut kmax = f64::NEG_INFINITY;
        for i in 0..n {
            for j in 0..n {
                let uv = DVec2::new(
                    dom.u.min + dom.u.width() * i as f64 / (n - 1) as f64,
                    dom.v.min + dom.v.width() * j as f64 / (n - 1) as f64,
                );
                let d = surface.derivatives_at(uv);
                points.push(d.point);
                if let Some(g) = LocalGeometry::try_new(d) {
                    kmax = kmax.max(g.principal_curvatures().0);
                }
            }
        }
        Self { points, k_concave_max: kmax }
    }
}

/// Share of the gouge tolerance allowed at the sample points by [`adjust`].
const SAMPLE_SHARE: f64 = 0.5;

/// Meridians and heights of the lower-surface sample of the bottom check.
const MERIDIANS: usize = 36;

/// The cutter's lower-surface sample points (mm): the flat bottom at radii 0, R0/2, R0 and
/// the corner at 5°, 10°, 20°, 35°, 55°, 90° from the bottom, on 36 meridians.
fn lower_points(cutter: &Cutter, tip: DVec3, axis: DVec3) -> Vec<DVec3> {
    let e1 = crate::geom::any_perpendicular(axis);
    let e2 = axis.cross(e1);
    let (r, r0) = (cutter.corner_radius_mm, cutter.torus_radius_mm());
    let mut pts = vec![tip];
    for k in 0..MERIDIANS {
        let phi = std::f64::consts::TAU * k as f64 / MERIDIANS as f64;
        let e = phi.cos() * e1 + phi.sin() * e2;
        for rho in [0.5 * r0, r0] {
            if rho > 0.0 {
                pts.push(tip + rho * e);
            }
        }
        for deg in [5.0f64, 10.0, 20.0, 35.0, 55.0, 90.0] {
            let b = deg.to_radians();
            pts.push(tip + (r0 + r * b.sin()) * e + r * (1.0 - b.cos()) * axis);
        }
    }
    pts
}

/// Checks the cutter placed at `frame` with `pose` (module docs); the deepest clash, or
/// `None` when it is clear to `tol_mm`.
#[must_use]
pub fn check(
    cutter: &Cutter,
    surface: &Surface,
    part: &PartSamples,
    frame: &ContactFrame,
    pose: &Pose,
    tol_mm: f64,
) -> Option<Clash> {
    let (tip, axis) = place(cutter, frame, pose);
    let mut worst: Option<Clash> = None;
    let mut note = |c: Clash| {
        if worst.is_none_or(|w| c.depth_mm > w.depth_mm) {
            worst = Some(c);
        }
    };
    // Local and rear: the lower surface against the surface.
    if part.k_concave_max > 0.0 {
        let geo = LocalGeometry::try_new(surface.derivatives_at(frame.uv));
        let dom = surface.domain();
        let opts = ProjectOptions { max_iterations: 8, ..ProjectOptions::default() };
        for p in lower_points(cutter, tip, axis) {
            let w = p - frame.point;
            let d2 = w.length_squared();
            if w.dot(frame.normal) > 0.5 * part.k_concave_max * d2 + tol_mm {
                continue;
            }
            let guess = geo.map_or(frame.uv, |g| frame.uv + g.tangent_coords(w));
            let foot = project_point(surface, p, guess, opts);
            // A foot on an edge of the domain: the point is over the part only when it does
            // not lie beyond that edge (outward along the parameter's tangent).
            let fd = surface.derivatives_at(foot.uv);
            let w = p - foot.point;
            let beyond = (foot.uv.x <= dom.u.min && !dom.u.periodic && w.dot(fd.du) < 0.0)
                || (foot.uv.x >= dom.u.max && !dom.u.periodic && w.dot(fd.du) > 0.0)
                || (foot.uv.y <= dom.v.min && !dom.v.periodic && w.dot(fd.dv) < 0.0)
                || (foot.uv.y >= dom.v.max && !dom.v.periodic && w.dot(fd.dv) > 0.0);
            if !beyond && foot.signed_distance < -tol_mm {
                note(Clash { part: ClashPart::Bottom, depth_mm: -foot.signed_distance, at: foot.point });
            }
        }
    }
    // Global: the part's points against the solid of revolution.
    for &p in &part.points {
        let w = p - tip;
        let z = w.dot(axis);
        if z <= cutter.corner_radius_mm {
            continue;
        }
        let Some(rad) = cutter.radius_at_height_mm(z) else { continue };
        let rho = (w - z * axis).length();
        if rho < rad - tol_mm {
            let part = if z <= cutter.flute_length_mm {
                ClashPart::Flank
            } else if z <= cutter.gauge_length_mm {
                ClashPart::Shank
            } else {
                ClashPart::Holder
            };
            note(Clash { part, depth_mm: rad - rho, at: p });
        }
    }
    worst
}

/// What [`adjust`] changed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adjustment {
    /// The clash that was found first.
    pub clash: Clash,
    /// Inclination added (rad).
    pub raised_rad: f64,
    /// Azimuth turned (rad).
    pub turned_rad: f64,
}

/// Checks and, where needed, adjusts the pose (module docs). `Ok((pose, None))`: clear as
/// given; `Ok((pose, Some(adj)))`: clear after the adjustment; `Err(clash)`: refused.
///
/// # Errors
/// The first clash when no adjusted pose passes.
pub fn adjust(
    cutter: &Cutter,
    surface: &Surface,
    part: &PartSamples,
    frame: &ContactFrame,
    pose: Pose,
    opts: &OrientOptions,
    tol_mm: f64,
) -> Result<(Pose, Option<Adjustment>), Clash> {
    // The sample is finite: half the tolerance at the samples keeps the cutter within the
    // tolerance between them (tested against a dense brute force).
    let tol = SAMPLE_SHARE * tol_mm;
    let Some(first) = check(cutter, surface, part, frame, &pose, tol) else {
        return Ok((pose, None));
    };
    let ok = |p: &Pose| {
        gouge_margin(cutter, frame, p) >= opts.margin_per_mm && check(cutter, surface, part, frame, p, tol).is_none()
    };
    let deg = 0.25f64.to_radians();
    let top = opts.max_inclination_rad.max(pose.inclination_rad);
    for turn in [0.0, 10.0, -10.0, 20.0, -20.0, 30.0, -30.0] {
        let mut p = Pose { azimuth_rad: pose.azimuth_rad + f64::to_radians(turn), ..pose };
        for _ in 0..=360 {
            if ok(&p) {
                return Ok((
                    p,
                    Some(Adjustment {
                        clash: first,
                        raised_rad: p.inclination_rad - pose.inclination_rad,
                        turned_rad: p.azimuth_rad - pose.azimuth_rad,
                    }),
                ));
            }
            if p.inclination_rad >= top {
                break;
            }
            p.inclination_rad = (p.inclination_rad + deg).min(top);
        }
    }
    Err(first)
}
