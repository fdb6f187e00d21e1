//! Measured interpolation errors and the paper's error estimates, per period.
//!
//! *Measured* (the truth): the signed distance from the centre to S_i by foot-point
//! projection, against R'. The core states it overcut positive ([`crate::numerics::sign`]):
//! `R' − dist(p, S_i)`, positive where the ball cuts into S_i. Seed 000 writes
//! `e_i = dist(p, S_i) − R'` (negative: a gouge), and so do the `e1`, `e2` columns printed;
//! requirement (1) of seed 000, `|e_i| ≤ b·T_i`, holds in either sign.
//!
//! *Estimated* (seed 000, §3–4), with k_i the normal curvature along the crease tangent t,
//! k_max, k_min the principal curvatures, Δk = k_max − k_min, τ_i the geodesic torsion along
//! t, R the cutter radius (we use R'), f the feed per period, ε_i = (q_i + R'n_i) − p the
//! initial error vector and |mp| the radius of the circle where the two tangency spheres
//! meet:
//!
//! - (11), one step without initial error:
//!   `Δ ≈ τ²Rf² / (2(1+|k|R)²) + |τ|f³ / (2(1+|k|R)²·|mp|)`
//! - (12), one step with initial error:
//!   `Δ < (|Δk| + Δk²R + τ²R) / (2(1+|k|R)²) · (f + |ε|)²`
//! - (16), steady state:
//!   `Δ_ω < (|Δk| + Δk²R + τ²R)·f² / (2(1+|k|R)(1 + R|k| − R√(Δk² + τ²)))`,
//!   meaningful only while the last factor is positive (else `None`: no steady state is
//!   guaranteed).
//!
//! `|mp| = D1·D2·√(1 − (n1·n2)²)/|o1o2|` with `D_i = (1 − R'k_i)/|k_i|` the distance from
//! the centre to the osculating sphere's centre; multiplied through by |k1 k2| it becomes
//! `(1 − R'k1)(1 − R'k2)√(1 − (n1·n2)²) / |k1k2(q1 − q2) + k2 n1 − k1 n2|`, which is finite
//! for flat surfaces (|mp| = ∞ when both are flat: the f³ term vanishes).

use glam::DVec3;

use super::{CreaseJob, Row};
use crate::geom::{LocalGeometry, ParametricSurface, ProjectOptions, SurfaceDerivs, project_point, project_point_from};
use crate::numerics::sign;
use crate::numerics::tolerance;

/// Errors and estimates at one row. Lengths in mm, curvatures in 1/mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diagnostics {
    /// Measured signed error R' − dist(p, S_i) (mm; overcut positive, the core's sign — seed
    /// 000's e_i is its negative, see [`measured_errors`]).
    pub measured: [f64; 2],
    /// Estimate (11) per surface (mm).
    pub est11: [f64; 2],
    /// Bound (12) per surface (mm).
    pub est12: [f64; 2],
    /// Steady-state bound (16) per surface (mm); `None` outside its validity.
    pub est16: [Option<f64>; 2],
    /// Normal curvature along the crease tangent, k_i (1/mm).
    pub k_t: [f64; 2],
    /// Principal curvatures (k_max, k_min) per surface (1/mm).
    pub principal: [(f64, f64); 2],
    /// Geodesic torsion along the crease tangent, τ_i (1/mm).
    pub tau: [f64; 2],
    /// |ε_i|, the initial error of the row (mm).
    pub eps: [f64; 2],
    /// |mp| (mm; infinite when both surfaces are flat along t).
    pub mp: f64,
    /// Angle between the two normals (deg).
    pub crease_angle_deg: f64,
}

/// The measured errors at a row (mm, the core's sign: overcut positive, see
/// [`crate::numerics::sign`]): R' minus the signed distance from the centre to each surface
/// by foot-point projection (from the row's contact parameters).
///
/// Seed 000 writes the error the other way, e_i = dist(p, S_i) − R' (negative: the ball cuts
/// into S_i); its e_i is `sign::stock_positive` of this, which is what `interpolab run
/// --errors` prints. Requirement (1), |e_i| ≤ b·T_i, does not see the sign.
#[must_use]
pub fn measured_errors(job: &CreaseJob, row: &Row) -> [f64; 2] {
    std::array::from_fn(|i| {
        sign::overcut_mm(
            project_point(&job.surfaces[i], row.p, row.uv[i], ProjectOptions::default()).signed_distance,
            job.r_eff_mm,
        )
    })
}

/// The largest measured |e_i| of a run and the period where it occurred, kept for the b·T
/// warning of `interpolab run` at a fraction of the cost of [`measured_errors`] on every
/// row: each row is first *screened* from one evaluation at the row's own contact
/// parameters (already within a few micrometres of the foot point): the squared distance's
/// second-order model there gives the foot point's distance without evaluating the surface
/// again (`model_distance`) when the model's Newton step is shorter than
/// [`tolerance::SCREEN_MODEL_STEP_MM`]; a longer step is taken once (if it descends and
/// stays in the domain) and the model applied again there, one evaluation; otherwise a
/// projection of at most three Newton steps from those parameters, that stops once a step
/// moves less than [`tolerance::SCREEN_STEP_MM`]. Only a screened
/// |e_i| of at least [`tolerance::SCREEN_FRACTION`]·b·T_i, or a screen that has not
/// settled, is measured again by the full projection. Every row whose error exceeds b·T is
/// therefore measured exactly as [`measured_errors`] measures it, and the warning (surface,
/// size, period) is the same; below half of b·T the recorded worst is the screened value,
/// equal to the full one to far below [`tolerance::MEASUREMENT_FLOOR_MM`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorstError {
    /// Per surface: the largest |e_i| seen (mm) and its period.
    pub worst: [(f64, u64); 2],
}

impl WorstError {
    /// Screens (and when needed measures) the row's errors.
    pub fn observe(&mut self, job: &CreaseJob, row: &Row) {
        self.observe_with(job, row, None);
    }

    /// [`Self::observe`] given both surfaces' derivatives at the row's contact parameters
    /// (e.g. [`super::Interpolator::row_derivatives`]), which the screen then does not
    /// evaluate again. The result is the same, bit for bit.
    pub fn observe_with(&mut self, job: &CreaseJob, row: &Row, derivs: Option<[SurfaceDerivs; 2]>) {
        let screen = ProjectOptions { max_iterations: 3, step_tol_mm: tolerance::SCREEN_STEP_MM };
        for i in 0..2 {
            let s = &job.surfaces[i];
            let uv = s.domain().clamp(row.uv[i]);
            // The screen starts from the clamped parameters: the given evaluation serves only
            // where clamping left them as they were.
            let d = match derivs {
                Some(d) if uv == row.uv[i] => d[i],
                _ => s.derivatives_at(uv),
            };
            let screened = match model_distance(row.p, &d) {
                Ok(dist) => Some(dist),
                // One Newton step of the model (it was long), then the model again there: the
                // step converges quadratically, so one evaluation usually settles it.
                Err(Some(step)) if domain_keeps(s, uv + step) => {
                    let next = s.derivatives_at(uv + step);
                    // Taken only if it does not move away (the projection's descent rule).
                    let descends = (next.point - row.p).length_squared()
                        <= (d.point - row.p).length_squared() * (1.0 + tolerance::DESCENT_SLACK_REL)
                            + tolerance::DESCENT_SLACK_MM2;
                    match model_distance(row.p, &next) {
                        Ok(dist) if descends => Some(dist),
                        _ => {
                            let foot = project_point_from(s, row.p, uv, d, screen);
                            foot.converged.then_some(foot.signed_distance)
                        }
                    }
                }
                Err(_) => {
                    let foot = project_point_from(s, row.p, uv, d, screen);
                    foot.converged.then_some(foot.signed_distance)
                }
            };
            let mut e = screened.map_or(f64::INFINITY, |dist| (dist - job.r_eff_mm).abs());
            if !(e < tolerance::SCREEN_FRACTION * job.allowed_error_mm(i)) {
                e = (project_point(&job.surfaces[i], row.p, row.uv[i], ProjectOptions::default()).signed_distance
                    - job.r_eff_mm)
                    .abs();
            }
            self.note(i, e, row.k);
        }
    }

    /// Records errors already measured (e.g. by [`diagnose`]).
    pub fn observe_measured(&mut self, measured: [f64; 2], k: u64) {
        for i in 0..2 {
            self.note(i, measured[i].abs(), k);
        }
    }

    fn note(&mut self, i: usize, e: f64, k: u64) {
        if e > self.worst[i].0 {
            self.worst[i] = (e, k);
        }
    }
}

/// The signed distance (mm, positive on the normal's side) from `p` to the surface near
/// `d`'s point, from one evaluation: the squared distance φ(s) = ½|r(uv + s) − p|² is
/// replaced by its second-order model at uv (gradient Jᵀw, Hessian JᵀJ + w·r″, w = r − p),
/// whose minimum ½|w|² + ½g·s* at the Newton step s* is the foot point's. `None` where the
/// model does not settle it: a Hessian that is not positive definite, a step that moves the
/// point [`tolerance::SCREEN_MODEL_STEP_MM`] or more (the model neglects φ's third-order
/// term, which grows with the cube of the step; then `Err(Some(step))`, the model's Newton
/// step in parameters), or a singular point (no normal).
fn model_distance(p: DVec3, d: &SurfaceDerivs) -> Result<f64, Option<glam::DVec2>> {
    if d.normal == DVec3::ZERO {
        return Err(None);
    }
    let w = d.point - p;
    let grad = glam::DVec2::new(w.dot(d.du), w.dot(d.dv));
    let (e, f, g) = (d.du.dot(d.du), d.du.dot(d.dv), d.dv.dot(d.dv));
    let (huu, huv, hvv) = (e + w.dot(d.duu), f + w.dot(d.duv), g + w.dot(d.dvv));
    if !(huu > 0.0 && huu * hvv - huv * huv > 0.0) {
        return Err(None);
    }
    let step = crate::numerics::linalg::solve2(huu, huv, huv, hvv, -grad).ok_or(None)?;
    let moved = (d.du * step.x + d.dv * step.y).length();
    if !(moved < tolerance::SCREEN_MODEL_STEP_MM) {
        return Err(moved.is_finite().then_some(step));
    }
    // ½|w|² + ½ g·s* is the model's minimum of φ; the distance is √(2φ).
    let dist2 = w.length_squared() + grad.dot(step);
    if !(dist2 >= 0.0) {
        return Err(None);
    }
    let sign = if (-w).dot(d.normal) < 0.0 { -1.0 } else { 1.0 };
    Ok(sign * dist2.sqrt())
}

/// Whether `uv` lies in the surface's domain as it is (clamping would move it).
fn domain_keeps(s: &crate::geom::Surface, uv: glam::DVec2) -> bool {
    s.domain().clamp(uv) == uv
}

/// Evaluates measured errors and estimates at a row. `None` at a singular point.
#[must_use]
pub fn diagnose(job: &CreaseJob, row: &Row) -> Option<Diagnostics> {
    let r = job.r_eff_mm;
    let f = job.feed_per_period_mm;
    let geo: [_; 2] = std::array::from_fn(|i| LocalGeometry::try_new(job.surfaces[i].derivatives_at(row.uv[i])));
    let [Some(g1), Some(g2)] = geo else {
        return None;
    };
    let measured = measured_errors(job, row);
    let (n1, n2) = (g1.d.normal, g2.d.normal);
    let cross = n1.cross(n2);
    let sin = cross.length();
    let t = if sin > 0.0 { cross / sin } else { DVec3::ZERO };
    let k_t = [g1.normal_curvature(t), g2.normal_curvature(t)];
    let principal = [g1.principal_curvatures(), g2.principal_curvatures()];
    let tau = [g1.geodesic_torsion(t), g2.geodesic_torsion(t)];
    let eps = [(g1.d.point + r * n1 - row.p).length(), (g2.d.point + r * n2 - row.p).length()];
    let denom = (k_t[0] * k_t[1] * (g1.d.point - g2.d.point) + k_t[1] * n1 - k_t[0] * n2).length();
    let numer = (1.0 - r * k_t[0]) * (1.0 - r * k_t[1]) * sin;
    let mp = if denom > 0.0 { numer / denom } else { f64::INFINITY };

    let mut est11 = [0.0; 2];
    let mut est12 = [0.0; 2];
    let mut est16 = [None; 2];
    for i in 0..2 {
        let k = k_t[i].abs();
        let dk = (principal[i].0 - principal[i].1).abs();
        let tau2 = tau[i] * tau[i];
        let a = 1.0 + k * r;
        let third = if mp.is_finite() { tau[i].abs() * f.powi(3) / (2.0 * a * a * mp) } else { 0.0 };
        est11[i] = tau2 * r * f * f / (2.0 * a * a) + third;
        let coeff = dk + dk * dk * r + tau2 * r;
        est12[i] = coeff / (2.0 * a * a) * (f + eps[i]).powi(2);
        let stab = 1.0 + r * k - r * (dk * dk + tau2).sqrt();
        est16[i] = (stab > 0.0).then(|| coeff * f * f / (2.0 * a * stab));
    }
    Some(Diagnostics {
        measured,
        est11,
        est12,
        est16,
        k_t,
        principal,
        tau,
        eps,
        mp,
        crease_angle_deg: sin.min(1.0).asin().to_degrees(),
    })
}

#[cfg(test)]
mod tests {
    use super::model_distance;
    use crate::geom::{Domain, Frame, ParamRange, ParamUnit, ParametricSurface, Sphere, Surface};
    use crate::numerics::tolerance;
    use glam::{DVec2, DVec3};

    /// On a sphere the distance from p is |p − c| − ρ in closed form: the model's distance,
    /// from the derivatives at parameters a little off the foot point, equals it to 1e-12 mm
    /// while the model's step is short, and the model declines once the step reaches
    /// `SCREEN_MODEL_STEP_MM` (the screen then projects).
    #[test]
    fn the_model_distance_is_the_closed_form_one_near_the_foot_point_and_declines_far_from_it() {
        for (radius, sign) in [(40.0, 1.0), (12.0, -1.0)] {
            let center = DVec3::new(3.0, -2.0, 5.0);
            let sphere = Surface::Sphere(Sphere {
                center,
                frame: Frame::from_axis(DVec3::Z, Some(DVec3::X)),
                radius,
                sign,
                domain: Domain {
                    u: ParamRange::new(-std::f64::consts::PI, std::f64::consts::PI, ParamUnit::Angle),
                    v: ParamRange::new(-1.5, 1.5, ParamUnit::Angle),
                },
            });
            let foot_uv = DVec2::new(0.7, 0.4);
            let foot = sphere.derivatives_at(foot_uv);
            // A ball centre R' = 5 mm off the surface on the normal's side.
            let p = foot.point + 5.0 * foot.normal;
            let exact = sign * ((p - center).length() - radius);
            assert!((exact - 5.0).abs() < 1e-12, "{exact}");
            let mut settled = 0;
            let mut declined = 0;
            for &off_mm in &[0.0, 1e-6, 1e-5, 1e-4, 1e-3, 0.01, 0.1] {
                for dir in [DVec2::X, DVec2::Y, DVec2::new(0.6, -0.8)] {
                    // Parameters whose point lies about `off_mm` from the foot point.
                    let uv = foot_uv + dir * off_mm / radius;
                    let d = sphere.derivatives_at(uv);
                    match model_distance(p, &d) {
                        Ok(dist) => {
                            settled += 1;
                            assert!(
                                (dist - exact).abs() <= 1e-12,
                                "ρ {radius} sign {sign}: {off_mm} mm off: {dist} vs {exact}"
                            );
                        }
                        Err(_) => {
                            declined += 1;
                            // Declined only where the step is not short.
                            assert!(off_mm >= tolerance::SCREEN_MODEL_STEP_MM * 0.5, "declined {off_mm} mm off");
                        }
                    }
                }
            }
            assert_eq!(declined, 6, "the two far offsets decline in every direction");
            assert_eq!(settled, 15);
        }
    }
}
