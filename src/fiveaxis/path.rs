//! Design paths: what the step selection walks along. A path gives, at each parameter s, a
//! *cutter location* (ball centre, tool axis, tool tip) and measures the signed error of a
//! ball placed anywhere near it.
//!
//! Two kinds:
//! - [`CreasePath`]: the crease of a scene (seed 000) — the ball touches two surfaces; its
//!   centre runs on the crease curve, parametrised by chord length (mm);
//! - [`ProfilePath`]: a planar profile extruded along Z (a blade section, the circle of the
//!   paper's Example 1) — the ball touches one surface, the extrusion of the profile.
//!
//! **Signed error** of a ball with centre p on surface i, in the core's sign convention
//! ([`crate::numerics::sign`]), which is seed 002's rule (overcut +), so δ, δt and δn are the
//! paper's own:
//! `e_i = R' − d_i(p)`, with `d_i` the signed distance from p to S_i, positive on the cutter
//! side, and R' = R + C. `e_i > 0`: the ball cuts into S_i by e_i (gouge, overcut);
//! `e_i < 0`: it leaves |e_i| of stock (undercut). At a cutter location of the path, e_i = 0.

use glam::{DVec2, DVec3};

use super::FiveAxisError;
use super::toolaxis::{AxisFrame, ToolAxisRule};
use crate::crease::CreaseCurve;
use crate::geom::{Curve3, ProjectOptions, project_point};
use crate::numerics::sign;

/// The cutter at one parameter of a design path (workpiece coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutterLocation {
    /// Path parameter (mm of chord length for crease paths; the profile's own parameter for
    /// profile paths).
    pub s: f64,
    /// Ball centre (mm).
    pub centre: DVec3,
    /// Unit tool axis, tip → spindle.
    pub axis: DVec3,
    /// Tool tip, `centre − R·axis` (mm): the programmed point.
    pub tip: DVec3,
    /// Unit contact normals (the second equals the first on one-surface paths).
    pub normals: [DVec3; 2],
    /// Unit direction of travel.
    pub travel: DVec3,
    /// Foot-point guesses for [`DesignPath::surface_errors`] (surface parameters, or the
    /// profile parameter in `x`).
    pub hints: [DVec2; 2],
}

/// A path the five-axis step selection can walk (module docs).
pub trait DesignPath {
    /// Parameter range `(start, end)`.
    fn range(&self) -> (f64, f64);
    /// Ball radius R (mm).
    fn ball_radius_mm(&self) -> f64;
    /// R' = R + allowance: the centre's offset from the surfaces (mm).
    fn effective_radius_mm(&self) -> f64;
    /// 1 or 2.
    fn surface_count(&self) -> usize;
    /// The cutter location at s.
    ///
    /// # Errors
    /// When the location cannot be computed (no crease point, undefined tool axis).
    fn location_at(&self, s: f64) -> Result<CutterLocation, FiveAxisError>;
    /// Signed errors `e_i = R' − d_i(p)` (gouge +) of a ball centred at `p`, a point of the
    /// segment from `a` to `b` at fraction `tau` (for the foot-point guesses). Entries past
    /// [`Self::surface_count`] are `None`.
    fn surface_errors(&self, p: DVec3, a: &CutterLocation, b: &CutterLocation, tau: f64) -> [Option<f64>; 2];
    /// The first trial step of seed 002 at s, `√(8ρE)` as a parameter step, if defined.
    fn first_step(&self, s: f64, tol_mm: f64) -> Option<f64>;
}

/// Interpolates foot-point guesses; a jump (a periodic parameter wrapping) takes the nearer
/// end instead.
fn mix_hint(a: DVec2, b: DVec2, tau: f64) -> DVec2 {
    if (b - a).length() > 1.0 { if tau < 0.5 { a } else { b } } else { a.lerp(b, tau) }
}

/// The crease of a scene as a design path.
#[derive(Clone, Debug)]
pub struct CreasePath {
    curve: CreaseCurve,
    rule: ToolAxisRule,
}

impl CreasePath {
    /// A crease path with this tool-axis rule.
    #[must_use]
    pub fn new(curve: CreaseCurve, rule: ToolAxisRule) -> Self {
        Self { curve, rule }
    }

    /// The crease curve.
    #[must_use]
    pub fn curve(&self) -> &CreaseCurve {
        &self.curve
    }

    /// The tool-axis rule.
    #[must_use]
    pub fn rule(&self) -> ToolAxisRule {
        self.rule
    }
}

impl DesignPath for CreasePath {
    fn range(&self) -> (f64, f64) {
        self.curve.range()
    }
    fn ball_radius_mm(&self) -> f64 {
        self.curve.job().ball_radius_mm
    }
    fn effective_radius_mm(&self) -> f64 {
        self.curve.job().r_eff_mm
    }
    fn surface_count(&self) -> usize {
        2
    }
    fn location_at(&self, s: f64) -> Result<CutterLocation, FiveAxisError> {
        let frame = self.curve.exact_at(s).ok_or(FiveAxisError::Crease { s })?;
        let (a, b) = self.range();
        let fraction = if b > a { (s - a) / (b - a) } else { 0.0 };
        let axis = self
            .rule
            .axis(&AxisFrame { n1: frame.normal[0], n2: Some(frame.normal[1]), travel: frame.tangent, fraction })
            .ok_or(FiveAxisError::ToolAxis { s, rule: self.rule.name() })?;
        Ok(CutterLocation {
            s,
            centre: frame.center,
            axis,
            tip: frame.center - self.ball_radius_mm() * axis,
            normals: frame.normal,
            travel: frame.tangent,
            hints: frame.uv,
        })
    }
    fn surface_errors(&self, p: DVec3, a: &CutterLocation, b: &CutterLocation, tau: f64) -> [Option<f64>; 2] {
        let r_eff = self.effective_radius_mm();
        let job = self.curve.job();
        // The signed distance is stationary in the foot point, so a foot to 1e-9 mm gives it
        // to far below that; one Newton iteration fewer than the default 1e-11 mm.
        let opts =
            ProjectOptions { step_tol_mm: crate::numerics::tolerance::NEWTON_LENGTH_MM, ..ProjectOptions::default() };
        let e = |i: usize| {
            let foot = project_point(&job.surfaces[i], p, mix_hint(a.hints[i], b.hints[i], tau), opts);
            sign::overcut_mm(foot.signed_distance, r_eff)
        };
        [Some(e(0)), Some(e(1))]
    }
    fn first_step(&self, s: f64, tol_mm: f64) -> Option<f64> {
        crate::chords::first_step_estimate(&self.curve, s, tol_mm)
    }
}

/// Which side of a planar profile the tool is on, looking along the travel from above (+Z).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolSide {
    /// The tool is on the left of the direction of travel.
    Left,
    /// The tool is on the right.
    Right,
}

/// The ball that follows a profile: its side, radius R and allowance C (R' = R + C).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileBall {
    /// Side of the profile the tool is on.
    pub side: ToolSide,
    /// Ball radius R (mm).
    pub ball_radius_mm: f64,
    /// Stock C left on the profile (mm).
    pub allowance_mm: f64,
}

/// A planar profile (a curve in a plane z = const) extruded along Z, cut by a ball on one
/// side: the contact point runs along the profile, the centre along its offset by R'.
pub struct ProfilePath {
    curve: Box<dyn Curve3>,
    range: (f64, f64),
    ball: ProfileBall,
    rule: ToolAxisRule,
}

impl std::fmt::Debug for ProfilePath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProfilePath")
            .field("range", &self.range)
            .field("ball", &self.ball)
            .field("rule", &self.rule)
            .finish_non_exhaustive()
    }
}

impl ProfilePath {
    /// A profile path over `range` of `curve` (which must lie in a plane z = const and be
    /// regular there), followed by `ball` with the tool axis by `rule`.
    #[must_use]
    pub fn new(curve: Box<dyn Curve3>, range: (f64, f64), ball: ProfileBall, rule: ToolAxisRule) -> Self {
        Self { curve, range, ball, rule }
    }

    /// The profile curve.
    #[must_use]
    pub fn curve(&self) -> &dyn Curve3 {
        self.curve.as_ref()
    }

    /// Unit in-plane normal toward the tool and unit tangent at s.
    fn frame(&self, s: f64) -> Option<(DVec3, DVec3)> {
        let d1 = self.curve.derivatives_at(s)[1];
        let t = DVec3::new(d1.x, d1.y, 0.0).try_normalize()?;
        let left = DVec3::Z.cross(t);
        Some((if self.ball.side == ToolSide::Left { left } else { -left }, t))
    }

    /// Foot point of p's projection on the profile (in the plane), by Newton from `guess`:
    /// returns the signed distance, positive on the tool side.
    fn signed_distance(&self, p: DVec3, guess: f64) -> f64 {
        let (lo, hi) = self.curve.range();
        let mut t = guess.clamp(lo, hi);
        let flat = |v: DVec3| DVec3::new(v.x, v.y, 0.0);
        let p = flat(p);
        for _ in 0..30 {
            let [c, d1, d2] = self.curve.derivatives_at(t);
            let (c, d1, d2) = (flat(c), flat(d1), flat(d2));
            let w = c - p;
            let g = w.dot(d1);
            let mut h = d1.dot(d1) + w.dot(d2);
            if h <= 0.0 {
                h = d1.dot(d1);
            }
            if h.is_nan() || h <= 0.0 {
                break;
            }
            let next = (t - g / h).clamp(lo, hi);
            let moved = ((next - t) * d1.length()).abs();
            t = next;
            if moved < crate::numerics::tolerance::NEWTON_LENGTH_FLOOR_MM {
                break;
            }
        }
        let c = flat(self.curve.point_at(t));
        match self.frame(t) {
            Some((n, _)) => (p - c).dot(n),
            None => (p - c).length(),
        }
    }
}

impl DesignPath for ProfilePath {
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn ball_radius_mm(&self) -> f64 {
        self.ball.ball_radius_mm
    }
    fn effective_radius_mm(&self) -> f64 {
        self.ball.ball_radius_mm + self.ball.allowance_mm
    }
    fn surface_count(&self) -> usize {
        1
    }
    fn location_at(&self, s: f64) -> Result<CutterLocation, FiveAxisError> {
        let (n, t) = self.frame(s).ok_or(FiveAxisError::ToolAxis { s, rule: "profile normal" })?;
        let q = self.curve.point_at(s);
        let centre = q + self.effective_radius_mm() * n;
        let (a, b) = self.range;
        let fraction = if b > a { (s - a) / (b - a) } else { 0.0 };
        let axis = self
            .rule
            .axis(&AxisFrame { n1: n, n2: None, travel: t, fraction })
            .ok_or(FiveAxisError::ToolAxis { s, rule: self.rule.name() })?;
        Ok(CutterLocation {
            s,
            centre,
            axis,
            tip: centre - self.ball.ball_radius_mm * axis,
            normals: [n, n],
            travel: t,
            hints: [DVec2::new(s, 0.0), DVec2::new(s, 0.0)],
        })
    }
    fn surface_errors(&self, p: DVec3, a: &CutterLocation, b: &CutterLocation, tau: f64) -> [Option<f64>; 2] {
        let guess = a.hints[0].x + tau * (b.hints[0].x - a.hints[0].x);
        [Some(sign::overcut_mm(self.signed_distance(p, guess), self.effective_radius_mm())), None]
    }
    fn first_step(&self, s: f64, tol_mm: f64) -> Option<f64> {
        crate::chords::first_step_estimate(self.curve.as_ref(), s, tol_mm)
    }
}
