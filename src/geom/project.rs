//! Foot-point projection: the point of a surface nearest to a given point.
//!
//! Newton's method on the stationarity conditions `(r − p)·r_u = 0`, `(r − p)·r_v = 0` with
//! the full Hessian `[r_u·r_u + (r−p)·r_uu, …]`, falling back to the first fundamental form
//! (Gauss–Newton) where the Hessian is not positive definite, and halving steps that do not
//! bring the surface closer. Periodic parameters wrap; others are clamped to the domain.

use glam::{DVec2, DVec3};

use super::parametric::{ParametricSurface, SurfaceDerivs};
use super::surface::Surface;
use crate::numerics::linalg;

/// Settings of [`project_point`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectOptions {
    /// Newton iterations before giving up (default 40).
    pub max_iterations: usize,
    /// Converged when a Newton step moves the foot point less than this (mm; default 1e-11).
    pub step_tol_mm: f64,
}

impl Default for ProjectOptions {
    fn default() -> Self {
        Self { max_iterations: 40, step_tol_mm: crate::numerics::tolerance::FOOT_STEP_MM }
    }
}

/// Result of a projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Foot {
    /// Parameters of the foot point (internal units).
    pub uv: DVec2,
    /// The foot point r(uv) (mm).
    pub point: DVec3,
    /// Oriented unit normal at the foot point.
    pub normal: DVec3,
    /// `(p − r)·n`: positive on the normal (cutter) side (mm).
    pub signed_distance: f64,
    /// `|p − r|` (mm).
    pub distance: f64,
    /// Whether Newton converged (an unconverged foot is still the best point found).
    pub converged: bool,
}

/// Projects `p` onto `surface` starting from the parameters `guess`.
#[must_use]
pub fn project_point(surface: &Surface, p: DVec3, guess: DVec2, opts: ProjectOptions) -> Foot {
    let uv = surface.domain().clamp(guess);
    project_point_from(surface, p, uv, surface.derivatives_at(uv), opts)
}

/// [`project_point`] from parameters `uv` inside the domain whose derivatives `d` the caller
/// already has (`d` must be `surface.derivatives_at(uv)`; the result is then the same, bit
/// for bit, as `project_point(surface, p, uv, opts)`).
#[must_use]
pub fn project_point_from(surface: &Surface, p: DVec3, uv: DVec2, d: SurfaceDerivs, opts: ProjectOptions) -> Foot {
    let domain = surface.domain();
    let mut uv = uv;
    let mut d = d;
    let mut dist2 = (d.point - p).length_squared();
    let mut converged = false;
    for _ in 0..opts.max_iterations {
        let w = d.point - p;
        let grad = DVec2::new(w.dot(d.du), w.dot(d.dv));
        let (e, f, g) = (d.du.dot(d.du), d.du.dot(d.dv), d.dv.dot(d.dv));
        let (huu, huv, hvv) = (e + w.dot(d.duu), f + w.dot(d.duv), g + w.dot(d.dvv));
        let newton =
            if huu > 0.0 && huu * hvv - huv * huv > 0.0 { linalg::solve2(huu, huv, huv, hvv, -grad) } else { None };
        let Some(mut step) = newton.or_else(|| linalg::solve2(e, f, f, g, -grad)) else {
            break;
        };
        // Halve until the distance does not grow (it always can: the step is a descent
        // direction of the squared distance).
        let mut accepted = false;
        for _ in 0..30 {
            let cand = domain.clamp(uv + step);
            let dc = surface.derivatives_at(cand);
            let dist2c = (dc.point - p).length_squared();
            if dist2c
                <= dist2 * (1.0 + crate::numerics::tolerance::DESCENT_SLACK_REL)
                    + crate::numerics::tolerance::DESCENT_SLACK_MM2
            {
                let moved = (dc.point - d.point).length();
                uv = cand;
                d = dc;
                dist2 = dist2c;
                accepted = true;
                if moved < opts.step_tol_mm {
                    converged = true;
                }
                break;
            }
            step *= 0.5;
        }
        if !accepted {
            // No decrease possible at working precision: we are at the minimum.
            converged = true;
        }
        if converged {
            break;
        }
    }
    let w = p - d.point;
    Foot { uv, point: d.point, normal: d.normal, signed_distance: w.dot(d.normal), distance: w.length(), converged }
}

/// How many of the nearest grid samples [`project_point_global`] refines.
const REFINED: usize = 4;

/// Projects `p` onto `surface` without a starting guess: samples the domain on a grid,
/// refines the nearest few samples by [`project_point`] and keeps the nearest foot.
#[must_use]
pub fn project_point_global(surface: &Surface, p: DVec3, samples: usize) -> Foot {
    let domain = surface.domain();
    let n = samples.max(2);
    // The `REFINED` nearest samples, nearest first, ties in sampling order (what a stable
    // sort of all n² samples would put first, without sorting them).
    let mut best: [(f64, DVec2); REFINED] = [(f64::INFINITY, DVec2::ZERO); REFINED];
    let mut kept = 0;
    for i in 0..n {
        for j in 0..n {
            let su = if domain.u.periodic { i as f64 / n as f64 } else { i as f64 / (n - 1) as f64 };
            let sv = if domain.v.periodic { j as f64 / n as f64 } else { j as f64 / (n - 1) as f64 };
            let uv = DVec2::new(domain.u.min + su * domain.u.width(), domain.v.min + sv * domain.v.width());
            let d2 = (surface.point_at(uv) - p).length_squared();
            // After the samples that are not greater (total order, as `f64::total_cmp`).
            let at = best[..kept].iter().position(|b| d2.total_cmp(&b.0).is_lt()).unwrap_or(kept);
            if at < REFINED {
                best.copy_within(at..REFINED - 1, at + 1);
                best[at] = (d2, uv);
                kept = (kept + 1).min(REFINED);
            }
        }
    }
    let mut result: Option<Foot> = None;
    for &(_, uv) in &best[..kept] {
        let foot = project_point(surface, p, uv, ProjectOptions::default());
        if result.is_none_or(|r| foot.distance < r.distance) {
            result = Some(foot);
        }
    }
    // n² ≥ 4 samples were seen, so `best` is full and the loop ran.
    result.unwrap_or_else(|| project_point(surface, p, domain.clamp(DVec2::ZERO), ProjectOptions::default()))
}
