//! Exact crease points by Newton's method on the four contact parameters (u1, v1, u2, v2).
//!
//! The crease condition `P1 = P2` with `P_i = r_i + R'·n_i` (3 equations) is completed by
//! one scalar condition that picks the point:
//! - [`Constraint::NearestTo`] `s`: `(P − s)·t = 0` with `t = n1 × n2 / |n1 × n2|`, i.e. the
//!   crease point whose normal plane contains `s` — the nearest crease point to a nearby `s`
//!   (used for `path.start`, `path.end` and to measure the interpolator);
//! - [`Constraint::AtDistance`] `(c, f)`: `|P − c| = f` — the crease point one feed per
//!   period from the previous one (the precise mode).
//!
//! The Jacobian uses the offset surfaces' tangents `∂P_i/∂u = r_u + R'·n_u`, with `n_u` from
//! the Weingarten equations, so no finite differences are involved. For `NearestTo` the
//! variation of t is neglected in the Jacobian (a quasi-Newton step; the residual still
//! converges to zero because the condition itself is evaluated exactly).

use glam::{DVec2, DVec3};

use super::{CreaseError, CreaseJob, Location};
use crate::geom::{LocalGeometry, ParametricSurface, project_point_global};
use crate::numerics::linalg;
use crate::numerics::tolerance;

/// Settings of the crease Newton solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Iterations before giving up (default 60).
    pub max_iterations: usize,
    /// Converged when the residual is below this (mm; default [`tolerance::NEWTON_LENGTH_MM`]).
    pub tol_mm: f64,
    /// Largest move of the centre in one iteration (mm; default 5). Keeps a far start from
    /// jumping to an unrelated branch.
    pub max_step_mm: f64,
    /// Clamp non-periodic parameters to the domains (default true). The precise stepper
    /// turns it off so a crease point just past a domain edge is found and then reported as
    /// a domain stop rather than as a convergence failure.
    pub stay_in_domain: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self { max_iterations: 60, tol_mm: tolerance::NEWTON_LENGTH_MM, max_step_mm: 5.0, stay_in_domain: true }
    }
}

/// The extra condition picking one point of the crease.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constraint {
    /// The crease point whose normal plane holds this point (mm).
    NearestTo(DVec3),
    /// The crease point at distance `dist` (mm) from `from`, near the initial guess.
    AtDistance {
        /// Centre of the sphere (mm).
        from: DVec3,
        /// Its radius (mm).
        dist: f64,
    },
    /// The crease point where one contact parameter takes a given value (internal units):
    /// where the crease meets a domain edge.
    Param {
        /// 0 for S1, 1 for S2.
        surface: usize,
        /// 0 for u, 1 for v.
        axis: usize,
        /// The parameter's value there (internal units).
        value: f64,
    },
}

/// An exact point of the crease with its contact data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CreasePoint {
    /// Cutter centre on the crease (mm), the mean of P1 and P2.
    pub p: DVec3,
    /// Contact parameters (internal units).
    pub uv: [DVec2; 2],
    /// Unit normals at the contact points.
    pub n: [DVec3; 2],
    /// Unit crease tangent `n1 × n2 / |n1 × n2|` (not yet oriented along the travel).
    pub tangent: DVec3,
    /// Newton iterations used.
    pub iterations: usize,
}

/// Why Newton failed, before it is given a location.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum NewtonFail {
    /// No convergence; the last residual (mm).
    NoConvergence(f64),
    /// Normals (anti)parallel at the iterate: angle (deg) and the gap |P1 − P2| (mm)
    /// between the offset points there.
    Tangential(f64, f64),
    /// Singular parametrisation on a surface.
    Singular(usize),
}

impl NewtonFail {
    pub(crate) fn into_error(self, at: Location, job: &CreaseJob) -> CreaseError {
        let _ = job;
        match self {
            Self::NoConvergence(res) => match at {
                Location::Start | Location::End => CreaseError::NoCrease {
                    at,
                    detail: if res.is_finite() {
                        format!("the offset surfaces stay {res:.3} mm apart there after Newton's iterations")
                    } else {
                        "Newton's iterations ran off the surfaces".to_owned()
                    },
                },
                Location::Period { .. } => CreaseError::NewtonFailed { at, detail: format!("residual {res:.3e} mm") },
            },
            // The normals are not parallel, but the Newton system is singular (its tangent
            // rows dependent): say so, rather than call non-parallel normals parallel.
            Self::Tangential(angle_deg, gap) if angle_deg >= tolerance::MIN_CREASE_ANGLE_RAD.to_degrees() => match at {
                Location::Start | Location::End => CreaseError::NoCrease {
                    at,
                    detail: if gap.is_finite() {
                        format!("Newton's linear system is singular there, with the offset surfaces {gap:.3} mm apart")
                    } else {
                        "Newton's linear system is singular there".to_owned()
                    },
                },
                Location::Period { .. } => {
                    CreaseError::NewtonFailed { at, detail: "Newton's linear system is singular there".to_owned() }
                }
            },
            // Parallel normals where the offset surfaces actually meet: tangential contact.
            Self::Tangential(angle_deg, gap) if gap <= TOUCHING_GAP_MM => {
                CreaseError::Tangential { at, angle_deg, min_deg: tolerance::MIN_CREASE_ANGLE_RAD.to_degrees() }
            }
            // Parallel normals with the offsets apart: Newton was drawn to where the surfaces
            // face each other, which means they do not meet here at all.
            Self::Tangential(angle_deg, gap) if !gap.is_finite() => match at {
                Location::Start | Location::End => CreaseError::NoCrease {
                    at,
                    detail: format!(
                        "the offset surfaces face each other (normals {angle_deg:.3}° from parallel) instead of crossing"
                    ),
                },
                Location::Period { .. } => {
                    CreaseError::NewtonFailed { at, detail: "normals parallel with the offsets apart".to_owned() }
                }
            },
            Self::Tangential(angle_deg, gap) => match at {
                Location::Start | Location::End => CreaseError::NoCrease {
                    at,
                    detail: format!(
                        "the offset surfaces face each other {gap:.3} mm apart (normals {angle_deg:.3}° from parallel) instead of crossing"
                    ),
                },
                Location::Period { .. } => CreaseError::NewtonFailed {
                    at,
                    detail: format!("normals parallel with the offsets {gap:.3e} mm apart"),
                },
            },
            Self::Singular(surface) => CreaseError::Singular { at, surface },
        }
    }
}

/// Below this gap (mm) between the two offset points, parallel normals mean the surfaces
/// touch tangentially; above it, that they do not meet.
const TOUCHING_GAP_MM: f64 = 1e-3;

/// Local data of one surface at its contact parameters.
pub(crate) struct Contact {
    pub geo: LocalGeometry,
    /// Offset point P = r + R'·n.
    pub offset: DVec3,
    /// ∂P/∂u, ∂P/∂v.
    pub dp: [DVec3; 2],
}

pub(crate) fn contact(job: &CreaseJob, i: usize, uv: DVec2) -> Result<Contact, NewtonFail> {
    let d = job.surfaces[i].derivatives_at(uv);
    let geo = LocalGeometry::try_new(d).ok_or(NewtonFail::Singular(i))?;
    let (nu, nv) = geo.normal_derivatives();
    let r = job.r_eff_mm;
    Ok(Contact { offset: d.point + r * d.normal, dp: [d.du + r * nu, d.dv + r * nv], geo })
}

/// Solves for the crease point satisfying `constraint`, starting from contact parameters
/// `uv0`.
pub(crate) fn solve(
    job: &CreaseJob,
    uv0: [DVec2; 2],
    constraint: Constraint,
    opts: NewtonOptions,
) -> Result<CreasePoint, NewtonFail> {
    solve_with_geometry(job, uv0, constraint, opts).map(|(cp, _)| cp)
}

/// As [`solve`], also returning the local geometry of both surfaces at the solution (the
/// last evaluation Newton made), so a stepper need not evaluate there again.
pub(crate) fn solve_with_geometry(
    job: &CreaseJob,
    uv0: [DVec2; 2],
    constraint: Constraint,
    opts: NewtonOptions,
) -> Result<(CreasePoint, [LocalGeometry; 2]), NewtonFail> {
    let domains = [job.surfaces[0].domain(), job.surfaces[1].domain()];
    let keep = |i: usize, x: DVec2| {
        if opts.stay_in_domain { domains[i].clamp(x) } else { domains[i].wrap(x) }
    };
    let mut uv = [keep(0, uv0[0]), keep(1, uv0[1])];
    let min_sin = tolerance::MIN_CREASE_ANGLE_RAD.sin();
    let mut last_res = f64::INFINITY;
    for it in 0..=opts.max_iterations {
        let c = [contact(job, 0, uv[0])?, contact(job, 1, uv[1])?];
        let (n1, n2) = (c[0].geo.d.normal, c[1].geo.d.normal);
        let cross = n1.cross(n2);
        let sin = cross.length();
        let t = cross / sin;
        let g = c[0].offset - c[1].offset;
        let mid = 0.5 * (c[0].offset + c[1].offset);
        // The constraint is evaluated at the midpoint of P1 and P2; `dir` is the direction
        // whose component of that midpoint it fixes. A parameter constraint is measured in
        // mm (the parameter's offset times the speed |∂P/∂u| there), so one tolerance serves.
        let (h, dir) = match constraint {
            Constraint::NearestTo(s) => ((mid - s).dot(t), t),
            Constraint::AtDistance { from, dist } => {
                let w = mid - from;
                (w.length() - dist, w.normalize_or_zero())
            }
            Constraint::Param { surface, axis, value } => {
                let speed = c[surface.min(1)].dp[axis.min(1)].length();
                ((uv[surface.min(1)][axis.min(1)] - value) * speed, DVec3::ZERO)
            }
        };
        let res = g.length().max(h.abs());
        if res <= opts.tol_mm && (res <= tolerance::NEWTON_LENGTH_FLOOR_MM || res >= 0.25 * last_res) {
            // Converged, and either at the floor or no longer improving quickly.
            if sin < min_sin {
                return Err(NewtonFail::Tangential(sin.min(1.0).asin().to_degrees(), g.length()));
            }
            let [c0, c1] = c;
            return Ok((CreasePoint { p: mid, uv, n: [n1, n2], tangent: t, iterations: it }, [c0.geo, c1.geo]));
        }
        if it == opts.max_iterations {
            break;
        }
        if !(sin >= tolerance::TANGENTIAL_GIVE_UP_REL * min_sin) {
            return Err(NewtonFail::Tangential(sin.min(1.0).asin().to_degrees(), g.length()));
        }
        last_res = res;
        // Rows: P1 − P2 = 0 (3) and the constraint. Unknowns: Δu1, Δv1, Δu2, Δv2.
        let (a, b) = (c[0].dp, c[1].dp);
        // ∂h/∂(u1, v1, u2, v2) = dir·½(P1_u, P1_v, P2_u, P2_v) (t held fixed for NearestTo).
        let last_row = match constraint {
            Constraint::Param { surface, axis, .. } => {
                let mut row = [0.0; 4];
                row[2 * surface.min(1) + axis.min(1)] = c[surface.min(1)].dp[axis.min(1)].length();
                row
            }
            _ => [0.5 * dir.dot(a[0]), 0.5 * dir.dot(a[1]), 0.5 * dir.dot(b[0]), 0.5 * dir.dot(b[1])],
        };
        let m = [
            [a[0].x, a[1].x, -b[0].x, -b[1].x],
            [a[0].y, a[1].y, -b[0].y, -b[1].y],
            [a[0].z, a[1].z, -b[0].z, -b[1].z],
            last_row,
        ];
        let Some(delta) = linalg::solve4(m, [-g.x, -g.y, -g.z, -h]) else {
            return Err(NewtonFail::Tangential(sin.min(1.0).asin().to_degrees(), g.length()));
        };
        let mut d1 = DVec2::new(delta[0], delta[1]);
        let mut d2 = DVec2::new(delta[2], delta[3]);
        let moved = (a[0] * d1.x + a[1] * d1.y).length().max((b[0] * d2.x + b[1] * d2.y).length());
        if moved > opts.max_step_mm {
            let s = opts.max_step_mm / moved;
            d1 *= s;
            d2 *= s;
        }
        uv = [keep(0, uv[0] + d1), keep(1, uv[1] + d2)];
    }
    Err(NewtonFail::NoConvergence(last_res))
}

/// Brings an approximate cutter-centre position onto the crease: contact guesses by
/// foot-point projection of `near` onto both surfaces, then Newton with
/// [`Constraint::NearestTo`]. Checks the result for tangential contact and for a concave
/// radius smaller than R'.
///
/// # Errors
/// [`CreaseError::NoCrease`], [`CreaseError::Tangential`], [`CreaseError::Fold`] or
/// [`CreaseError::Singular`] at `at`.
pub fn locate_crease_point(job: &CreaseJob, near: DVec3, at: Location) -> Result<CreasePoint, CreaseError> {
    let guess =
        [project_point_global(&job.surfaces[0], near, 24).uv, project_point_global(&job.surfaces[1], near, 24).uv];
    let cp =
        solve(job, guess, Constraint::NearestTo(near), NewtonOptions::default()).map_err(|e| e.into_error(at, job))?;
    check_fold(job, &cp.uv, at)?;
    Ok(cp)
}

/// Errors with [`CreaseError::Fold`] if a principal curvature at a contact point is concave
/// with radius ≤ R' (1 − k_max·R' ≤ 0).
pub(crate) fn check_fold(job: &CreaseJob, uv: &[DVec2; 2], at: Location) -> Result<(), CreaseError> {
    for (i, s) in job.surfaces.iter().enumerate() {
        let geo = LocalGeometry::try_new(s.derivatives_at(uv[i])).ok_or(CreaseError::Singular { at, surface: i })?;
        let (k_max, _) = geo.principal_curvatures();
        if 1.0 - k_max * job.r_eff_mm <= 0.0 {
            return Err(CreaseError::Fold { at, surface: i, radius_mm: 1.0 / k_max, r_eff_mm: job.r_eff_mm });
        }
    }
    Ok(())
}

/// Distance (mm) from a cutter centre `p` to the exact crease, by Newton from the contact
/// parameters `uv` (typically the interpolator's own). `None` if Newton fails there.
#[must_use]
pub fn crease_deviation(job: &CreaseJob, p: DVec3, uv: [DVec2; 2]) -> Option<(f64, CreasePoint)> {
    let cp = solve(job, uv, Constraint::NearestTo(p), NewtonOptions::default()).ok()?;
    Some(((cp.p - p).length(), cp))
}
