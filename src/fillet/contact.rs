//! The cutter at one contact point: the local frame, the orientation (inclination and
//! azimuth, or lead and tilt), where the tool tip goes, the cutter's curvature in every
//! direction of the tangent plane (its *effective cutting curvature*), and the height of the
//! swept cutter above the surface across the feed (the profile that leaves the scallop).
//!
//! # Frame and orientation
//!
//! At the CC point q with unit normal n (toward the cutter) and unit feed direction f in the
//! tangent plane, c = n × f points across the feed (to the left of the travel seen from the
//! spindle). Directions of the tangent plane are `t(θ) = cos θ·f + sin θ·c`.
//!
//! The tool axis is `a = cos α·n + sin α·d` with the *inclination* α (angle from the normal)
//! and the *meridian direction* `d = t(ψ)`, ψ the *azimuth*. In lead/tilt terms
//! `a = cos ω·(cos λ·n + sin λ·f) + sin ω·c`: `sin ω = sin α·sin ψ`, `tan λ = tan α·cos ψ`.
//!
//! # Where the cutter touches
//!
//! The cutter's lower surface is the torus swept by the corner circle (radius r, centre on
//! the circle of radius R0 = R − r at height r above the tip). At the contact its outward
//! normal is −n, so the contact lies on the corner's meridian in the plane of a and n, on the
//! side of d: with `e = −sin α·n + cos α·d` (the unit radial direction of the contact, ⊥ a)
//! the tip is `T = q + r·n − R0·e − r·a`.
//!
//! # Effective cutting curvature (closed form)
//!
//! The torus' principal directions at the contact are the meridian (in the plane of a and n,
//! tangent direction d) and the parallel (d⊥ = n × d). Along the meridian the curvature is
//! that of the corner circle, `k_mer = 1/r`. The parallel is a circle of radius
//! `ρ = R0 + r·sin α` in a plane ⊥ a; its principal normal makes the angle 90° − α with −n,
//! so by Meusnier `k_par = sin α / (R0 + r·sin α)`: the effective cutting radius
//! `R0/sin α + r` of the literature, here exact. By Euler, in the direction t(θ)
//! `κ(θ) = k_mer·cos²(θ − ψ) + k_par·sin²(θ − ψ)` — the curvature of the normal section
//! of the cutter's envelope (the torus is the envelope of the rotating cutting edge). Signs
//! as the surface's ([`crate::geom::LocalGeometry`]): positive when the section bends toward
//! n. A ball (R0 = 0) gives 1/R in every direction; a flat end mill (r = 0) gives
//! `sin α / R` across its meridian and a sharp edge (∞) elsewhere.
//!
//! # Local gouging and the strip
//!
//! With Q_c and Q_s the second fundamental forms of cutter and surface in the basis (f, c),
//! the cutter clears the surface near q to second order iff `D = Q_c − Q_s` is positive
//! definite; we ask `λ_min(D) ≥ m` (a margin m, 1/mm), i.e. `κ(θ) ≥ k_s(θ) + m` for every θ.
//! Moving along the path, the cutter at distance x behind the cross plane stands at height
//! `½·D(x, y)` above the surface at the cross offset y; the envelope is the minimum over x:
//! `½·Δκ·y²` with `Δκ = D_cc − D_fc²/D_ff`. Between two passes w apart the scallop is then
//! `h = Δκ·w²/8`, so `w = √(8h/Δκ)`.

use glam::{DVec2, DVec3};

use crate::geom::{Cutter, LocalGeometry, ParametricSurface, Surface, first_form_if_regular};
use crate::numerics::tolerance;

/// A symmetric 2×2 form in the basis (f, c) of the tangent plane (1/mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Form2 {
    /// Value on (f, f).
    pub ff: f64,
    /// Value on (f, c).
    pub fc: f64,
    /// Value on (c, c).
    pub cc: f64,
}

impl Form2 {
    /// The form on the unit direction t(θ) (θ rad from f toward c).
    #[must_use]
    pub fn at(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        self.ff * c * c + 2.0 * self.fc * s * c + self.cc * s * s
    }

    /// `self − other`.
    #[must_use]
    pub fn minus(&self, other: &Self) -> Self {
        Self { ff: self.ff - other.ff, fc: self.fc - other.fc, cc: self.cc - other.cc }
    }

    /// Smallest eigenvalue: the minimum of [`Self::at`] over θ.
    #[must_use]
    pub fn min_eigen(&self) -> f64 {
        let half = 0.5 * (self.ff - self.cc);
        0.5 * (self.ff + self.cc) - half.hypot(self.fc)
    }

    /// Curvature of the form's silhouette seen along f: `cc − fc²/ff` (∞ when ff ≤ 0).
    #[must_use]
    pub fn silhouette(&self) -> f64 {
        if self.ff > 0.0 { self.cc - self.fc * self.fc / self.ff } else { f64::INFINITY }
    }
}

/// The unit feed f (the tangential part of `feed_hint`) and cross direction c = n × f at a
/// point of unit normal `n`; `None` when the hint is (almost) normal to the surface.
fn feed_and_cross(n: DVec3, feed_hint: DVec3) -> Option<(DVec3, DVec3)> {
    let f = (feed_hint - feed_hint.dot(n) * n).try_normalize()?;
    Some((f, n.cross(f)))
}

/// The local frame at a CC point (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFrame {
    /// Surface parameters (internal units).
    pub uv: DVec2,
    /// The CC point q (mm).
    pub point: DVec3,
    /// Unit normal n, toward the cutter.
    pub normal: DVec3,
    /// Unit feed direction f (tangent).
    pub feed: DVec3,
    /// Unit cross direction c = n × f.
    pub cross: DVec3,
    /// The surface's second fundamental form in (f, c) (1/mm; positive = concave toward n).
    pub surface_form: Form2,
}

impl ContactFrame {
    /// The frame at `uv` with the feed along the tangential part of `feed_hint`; `None` at a
    /// singular point or when the hint is (almost) normal to the surface.
    #[must_use]
    pub fn new(surface: &Surface, uv: DVec2, feed_hint: DVec3) -> Option<Self> {
        Self::with_cross_uv(surface, uv, feed_hint).map(|(frame, _)| frame)
    }

    /// [`Self::new`] with the parameter direction of c (per mm) it found on the way: what
    /// [`CrossProfile::new`] would evaluate the surface's derivatives at `uv` again for
    /// ([`CrossProfile::with_cross_uv`]).
    #[must_use]
    pub fn with_cross_uv(surface: &Surface, uv: DVec2, feed_hint: DVec3) -> Option<(Self, DVec2)> {
        let d = surface.derivatives_at(uv);
        let geo = LocalGeometry::try_new(d)?;
        let n = d.normal;
        let (f, c) = feed_and_cross(n, feed_hint)?;
        let (cf, cc) = (geo.tangent_coords(f), geo.tangent_coords(c));
        let surface_form =
            Form2 { ff: geo.second_form(cf, cf), fc: geo.second_form(cf, cc), cc: geo.second_form(cc, cc) };
        Some((Self { uv, point: d.point, normal: n, feed: f, cross: c, surface_form }, cc))
    }

    /// [`Self::new`] without the surface's second form (`surface_form` zero): the same
    /// point, normal, feed and cross directions to the last bit, `None` at the same places,
    /// for half the evaluation on a NURBS surface (no second derivatives). For placing a
    /// cutter ([`place`]), which needs no curvature; never for a curvature or a gouge margin.
    #[must_use]
    pub fn first_order(surface: &Surface, uv: DVec2, feed_hint: DVec3) -> Option<Self> {
        let d = surface.first_order_at(uv);
        first_form_if_regular(d.du, d.dv, d.normal)?;
        let (feed, cross) = feed_and_cross(d.normal, feed_hint)?;
        let surface_form = Form2 { ff: 0.0, fc: 0.0, cc: 0.0 };
        Some(Self { uv, point: d.point, normal: d.normal, feed, cross, surface_form })
    }

    /// The unit tangent t(θ) = cos θ·f + sin θ·c.
    #[must_use]
    pub fn direction(&self, theta: f64) -> DVec3 {
        let (s, c) = theta.sin_cos();
        c * self.feed + s * self.cross
    }
}

/// The cutter's orientation at a contact point (module docs), radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Inclination α of the axis from the surface normal (rad, ≥ 0).
    pub inclination_rad: f64,
    /// Azimuth ψ of the meridian direction d from the feed toward c (rad).
    pub azimuth_rad: f64,
}

impl Pose {
    /// The pose whose axis is `axis` (unit) at `frame`: α = angle(axis, n), ψ from the feed
    /// toward c of the axis' part in the tangent plane (0 when the axis is the normal).
    #[must_use]
    pub fn from_axis(frame: &ContactFrame, axis: DVec3) -> Self {
        let inclination_rad = axis.dot(frame.normal).clamp(-1.0, 1.0).acos();
        let (f, c) = (axis.dot(frame.feed), axis.dot(frame.cross));
        let azimuth_rad = if f == 0.0 && c == 0.0 { 0.0 } else { c.atan2(f) };
        Self { inclination_rad, azimuth_rad }
    }

    /// The pose of lead λ (toward the feed) and tilt ω (toward c), radians.
    #[must_use]
    pub fn from_lead_tilt(lead_rad: f64, tilt_rad: f64) -> Self {
        let a = DVec3::new(tilt_rad.cos() * lead_rad.sin(), tilt_rad.sin(), tilt_rad.cos() * lead_rad.cos());
        let incl = a.z.clamp(-1.0, 1.0).acos();
        let azim = if a.x.hypot(a.y) > 0.0 { a.y.atan2(a.x) } else { 0.0 };
        Self { inclination_rad: incl, azimuth_rad: azim }
    }

    /// Lead angle λ (rad): the axis' turn toward the feed.
    #[must_use]
    pub fn lead_rad(&self) -> f64 {
        (self.inclination_rad.sin() * self.azimuth_rad.cos()).atan2(self.inclination_rad.cos())
    }

    /// Tilt angle ω (rad): the axis' turn toward c, sideways.
    #[must_use]
    pub fn tilt_rad(&self) -> f64 {
        (self.inclination_rad.sin() * self.azimuth_rad.sin()).clamp(-1.0, 1.0).asin()
    }

    /// The unit tool axis at `frame`.
    #[must_use]
    pub fn axis(&self, frame: &ContactFrame) -> DVec3 {
        let (s, c) = self.inclination_rad.sin_cos();
        c * frame.normal + s * frame.direction(self.azimuth_rad)
    }
}

/// Principal curvatures `(k_mer, k_par)` of the cutter's lower surface at the contact for
/// inclination α (1/mm; module docs).
#[must_use]
pub fn cutter_principal(cutter: &Cutter, inclination_rad: f64) -> (f64, f64) {
    let r = cutter.corner_radius_mm;
    let r0 = cutter.torus_radius_mm();
    let k_mer = 1.0 / r.max(tolerance::FILLET_SHARP_EDGE_MM);
    if r0 <= 0.0 {
        return (k_mer, k_mer);
    }
    let s = inclination_rad.sin().max(0.0);
    (k_mer, s / (r0 + r * s))
}

/// The inclination α (rad) whose parallel curvature `k_par` equals `kappa` (1/mm): the
/// inverse of `sin α/(R0 + r sin α)`; `None` when no α ≤ 90° reaches it (κ ≥ 1/R).
#[must_use]
pub fn inclination_for(cutter: &Cutter, kappa: f64) -> Option<f64> {
    let r = cutter.corner_radius_mm;
    let r0 = cutter.torus_radius_mm();
    if kappa <= 0.0 {
        return Some(0.0);
    }
    if r0 <= 0.0 {
        return (kappa * r <= 1.0).then_some(0.0);
    }
    let den = 1.0 - kappa * r;
    if den <= 0.0 {
        return None;
    }
    let s = kappa * r0 / den;
    (s <= 1.0).then(|| s.asin())
}

/// The cutter's second fundamental form Q_c in (f, c) for this pose (1/mm).
#[must_use]
pub fn cutter_form(cutter: &Cutter, pose: &Pose) -> Form2 {
    cutter_form_of(cutter_principal(cutter, pose.inclination_rad), pose.azimuth_rad.sin_cos())
}

/// [`cutter_form`] from the principal curvatures `(k_mer, k_par)` ([`cutter_principal`],
/// 1/mm) and `(sin ψ, cos ψ)`, for searches that reuse them across a grid (the same
/// arithmetic, so the same bits).
#[must_use]
pub fn cutter_form_of((k_mer, k_par): (f64, f64), (s, c): (f64, f64)) -> Form2 {
    Form2 { ff: k_mer * c * c + k_par * s * s, fc: (k_mer - k_par) * s * c, cc: k_mer * s * s + k_par * c * c }
}

/// The effective cutting curvature κ(θ) (1/mm) of the cutter in the direction t(θ) of the
/// tangent plane (θ rad from the feed toward c): Euler's formula on the torus' principal
/// curvatures (module docs).
#[must_use]
pub fn effective_curvature(cutter: &Cutter, pose: &Pose, theta_rad: f64) -> f64 {
    let (k_mer, k_par) = cutter_principal(cutter, pose.inclination_rad);
    let (s, c) = (theta_rad - pose.azimuth_rad).sin_cos();
    k_mer * c * c + k_par * s * s
}

/// Tool tip and unit axis for the cutter touching at `frame` with `pose` (mm; module docs).
#[must_use]
pub fn place(cutter: &Cutter, frame: &ContactFrame, pose: &Pose) -> (DVec3, DVec3) {
    let a = pose.axis(frame);
    let (s, c) = pose.inclination_rad.sin_cos();
    let e = -s * frame.normal + c * frame.direction(pose.azimuth_rad);
    let r = cutter.corner_radius_mm;
    let tip = frame.point + r * frame.normal - cutter.torus_radius_mm() * e - r * a;
    (tip, a)
}

/// Δκ = silhouette of D = Q_c − Q_s along the feed (1/mm): the curvature of the swept
/// cutter's envelope above the surface across the feed, to second order (module docs).
#[must_use]
pub fn cross_curvature(cutter: &Cutter, frame: &ContactFrame, pose: &Pose) -> f64 {
    cutter_form(cutter, pose).minus(&frame.surface_form).silhouette()
}

/// The local no-gouge margin `min_θ (κ(θ) − k_s(θ))` = λ_min(Q_c − Q_s) (1/mm).
#[must_use]
pub fn gouge_margin(cutter: &Cutter, frame: &ContactFrame, pose: &Pose) -> f64 {
    cutter_form(cutter, pose).minus(&frame.surface_form).min_eigen()
}

/// Most safeguarded Newton steps of [`projected_height`] (a step that would leave the
/// bracket halves it instead, so 64 reach the bits of f64).
const SLOPE_ITERATIONS: usize = 64;
/// The bracket of slopes s of [`projected_height`] (|s| ≤ 4: the section's tangent up to
/// 76° from the tangent plane).
const SLOPE_BRACKET: f64 = 4.0;

/// Height (mm, along n) above the tangent plane at q of the lower boundary of the cutter
/// solid projected along the feed f onto the cross plane, at the cross offset y (mm): the
/// section of the cutter swept along a straight line. Exact for the solid
/// `disc(R0) ⊕ ball(r)` by the support function: the lower boundary is
/// `z(y) = max_s [s·y − h(s)]` with `h(s) = H(s·c − n)`, `H(U) = U·C0 + R0·|U − (U·a)a| + r·|U|`,
/// C0 the corner circle's centre relative to q. h is convex (a support function along a
/// line), so the maximiser solves `h'(s) = y`, h' increasing: safeguarded Newton on
/// s ∈ [−4, 4] (an end of the bracket when h' − y keeps its sign there), with
///
/// `h'(s) = C0·c + R0·q'/(2√q) + r·s/√(s²+1)`, `q(s) = s² + 1 − (s·a_c − a_n)²`,
/// `h''(s) = R0·(q''/2 − (q'/(2√q))²)/√q + r/(s²+1)^{3/2}`, `q' = 2s − 2(s·a_c − a_n)·a_c`,
/// `q'' = 2 − 2a_c²`.
#[must_use]
pub fn projected_height(cutter: &Cutter, frame: &ContactFrame, tip: DVec3, axis: DVec3, y: f64) -> f64 {
    let r = cutter.corner_radius_mm;
    let r0 = cutter.torus_radius_mm();
    let c0 = tip + r * axis - frame.point;
    let (c0c, c0n) = (c0.dot(frame.cross), c0.dot(frame.normal));
    let (ac, an) = (axis.dot(frame.cross), axis.dot(frame.normal));
    // G(s) = s·y − h(s) (to be maximised), G' = y − h', G'' = −h''.
    let value = |s: f64| {
        // U = s·c − n; |U − (U·a)a|² = |U|² − (U·a)².
        let ua = s * ac - an;
        let uu = s * s + 1.0;
        s * y - (s * c0c - c0n + r0 * (uu - ua * ua).max(0.0).sqrt() + r * uu.sqrt())
    };
    let slope = |s: f64| {
        let ua = s * ac - an;
        let uu = s * s + 1.0;
        let q = (uu - ua * ua).max(0.0);
        let dq = 2.0 * s - 2.0 * ua * ac;
        let (mut d1, mut d2) = (c0c + r * s / uu.sqrt(), r / (uu * uu.sqrt()));
        if q > 0.0 {
            let sq = q.sqrt();
            let f1 = 0.5 * dq / sq;
            d1 += r0 * f1;
            d2 += r0 * ((1.0 - ac * ac) - f1 * f1) / sq;
        } else if r0 > 0.0 {
            // U along the axis: h has a kink here; bisection takes over.
            d2 = f64::INFINITY;
        }
        (y - d1, d2)
    };
    let (mut lo, mut hi) = (-SLOPE_BRACKET, SLOPE_BRACKET);
    if slope(lo).0 <= 0.0 {
        return value(lo);
    }
    if slope(hi).0 >= 0.0 {
        return value(hi);
    }
    let mut s = 0.0f64;
    for _ in 0..SLOPE_ITERATIONS {
        let (g1, h2) = slope(s);
        if g1 > 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        // Newton on G' = 0: s + G'/h'' (h'' > 0); bisection when it leaves the bracket.
        let newton = s + g1 / h2;
        let next = if newton > lo && newton < hi && h2.is_finite() { newton } else { 0.5 * (lo + hi) };
        let done = (next - s).abs() <= f64::EPSILON * (1.0 + s.abs()) || hi - lo <= f64::EPSILON * (1.0 + s.abs());
        s = next;
        if done {
            break;
        }
    }
    value(s)
}

/// Height (mm, along n) of the surface's section by the cross plane (through q, ⊥ f) at the
/// cross offset y, by Newton from the tangent-plane guess; `None` when it leaves the domain
/// or does not converge in 12 steps.
#[must_use]
pub fn section_height(surface: &Surface, frame: &ContactFrame, y: f64) -> Option<f64> {
    let geo = LocalGeometry::try_new(surface.derivatives_at(frame.uv))?;
    section_height_from(surface, frame, geo.tangent_coords(frame.cross), y)
}

/// [`section_height`] with the parameter direction of c at q (`cross_uv`, per mm) given.
fn section_height_from(surface: &Surface, frame: &ContactFrame, cross_uv: DVec2, y: f64) -> Option<f64> {
    let domain = surface.domain();
    let mut uv = frame.uv + cross_uv * y;
    for _ in 0..12 {
        if !domain.contains(uv) {
            return None;
        }
        // Only r, r_u and r_v enter (the same bits as `derivatives_at`'s).
        let (point, du, dv) = surface.tangents_fast_at(uv);
        let w = point - frame.point;
        let (r1, r2) = (w.dot(frame.feed), w.dot(frame.cross) - y);
        if r1.abs().max(r2.abs()) < tolerance::FILLET_HEIGHT_MM {
            return Some(w.dot(frame.normal));
        }
        let step = crate::numerics::linalg::solve2(
            du.dot(frame.feed),
            dv.dot(frame.feed),
            du.dot(frame.cross),
            dv.dot(frame.cross),
            DVec2::new(-r1, -r2),
        )?;
        uv += step;
    }
    None
}

/// Most steps of [`increasing_root`].
const ROOT_ITERATIONS: usize = 100;

/// A bracket `(lo, hi)` narrower than `tol` around a sign change of `f` on [lo, hi]
/// (`f(lo) < 0 ≤ f(hi)` given as `f_lo`, `f_hi`; f continuous): the Illinois variant of
/// regula falsi, which keeps the bracket of bisection (every step lands inside it) and
/// converges superlinearly where f is smooth; a step that would land within tol/4 of an
/// end is moved to tol/4 from it, so the bracket closes from both sides. At most 100 steps.
fn increasing_root(
    mut f: impl FnMut(f64) -> f64,
    (mut lo, mut hi): (f64, f64),
    (mut f_lo, mut f_hi): (f64, f64),
    tol: f64,
) -> (f64, f64) {
    // Which end was kept in the last step (−1 lo, +1 hi, 0 none): kept twice, its value is
    // halved (Illinois).
    let mut kept = 0i8;
    for _ in 0..ROOT_ITERATIONS {
        if hi - lo < tol {
            break;
        }
        let secant = if f_hi > f_lo { lo - f_lo * (hi - lo) / (f_hi - f_lo) } else { 0.5 * (lo + hi) };
        let guard = 0.25 * tol;
        let x = if secant.is_finite() { secant.clamp(lo + guard, hi - guard) } else { 0.5 * (lo + hi) };
        let fx = f(x);
        if fx < 0.0 {
            lo = x;
            f_lo = fx;
            if kept == 1 {
                f_hi *= 0.5;
            }
            kept = 1;
        } else {
            hi = x;
            f_hi = fx;
            if kept == -1 {
                f_lo *= 0.5;
            }
            kept = -1;
        }
    }
    (lo, hi)
}

/// The swept cutter's height above the design surface at the cross offset y (mm): the
/// exact straight-line projection of the cutter ([`projected_height`]) with its
/// second-order term replaced by the moving cutter's (`½·Δκ·y²`, module docs), minus the
/// surface section's departure from its own second-order term. Exact to second order for
/// any path and exact for a straight path on a plane.
#[derive(Clone, Copy, Debug)]
pub struct CrossProfile<'a> {
    cutter: &'a Cutter,
    surface: &'a Surface,
    frame: ContactFrame,
    tip: DVec3,
    axis: DVec3,
    /// Second-order coefficient of the straight projection (1/mm).
    k_proj: f64,
    /// Δκ of the moving cutter (1/mm).
    k_move: f64,
    /// The parameter direction of c at q (per mm): the start of the surface section.
    cross_uv: Option<DVec2>,
}

impl<'a> CrossProfile<'a> {
    /// The profile of the cutter at `frame` with `pose`.
    #[must_use]
    pub fn new(cutter: &'a Cutter, surface: &'a Surface, frame: ContactFrame, pose: &Pose) -> Self {
        let cross_uv = LocalGeometry::try_new(surface.derivatives_at(frame.uv)).map(|g| g.tangent_coords(frame.cross));
        Self::with_cross_uv(cutter, surface, frame, pose, cross_uv)
    }

    /// [`Self::new`] with the parameter direction of c at the frame's point given (per mm;
    /// `None` at a singular point): from [`ContactFrame::with_cross_uv`], the same bits.
    #[must_use]
    pub fn with_cross_uv(
        cutter: &'a Cutter,
        surface: &'a Surface,
        frame: ContactFrame,
        pose: &Pose,
        cross_uv: Option<DVec2>,
    ) -> Self {
        let (tip, axis) = place(cutter, &frame, pose);
        let qc = cutter_form(cutter, pose);
        Self {
            cutter,
            surface,
            frame,
            tip,
            axis,
            k_proj: qc.silhouette(),
            k_move: qc.minus(&frame.surface_form).silhouette(),
            cross_uv,
        }
    }

    /// Height (mm) above the design surface at the cross offset y (mm, toward c).
    #[must_use]
    pub fn height(&self, y: f64) -> f64 {
        let z = projected_height(self.cutter, &self.frame, self.tip, self.axis, y);
        let ks = self.frame.surface_form.cc;
        let zs = self
            .cross_uv
            .and_then(|c| section_height_from(self.surface, &self.frame, c, y))
            .unwrap_or(0.5 * ks * y * y);
        let y2 = 0.5 * y * y;
        (z - self.k_proj * y2) + self.k_move * y2 - (zs - ks * y2)
    }

    /// Offset y > 0 (sign +1) or y < 0 (sign −1) where the height reaches `h_mm`, by
    /// bracketed regula falsi (`increasing_root`) to [`tolerance::FILLET_HEIGHT_MM`];
    /// capped at the cutter radius R.
    #[must_use]
    pub fn reach(&self, h_mm: f64, sign: f64) -> f64 {
        let big_r = self.cutter.radius_mm;
        let f_hi = self.height(sign * big_r) - h_mm;
        if f_hi < 0.0 {
            return big_r;
        }
        let f_lo = self.height(0.0) - h_mm;
        if f_lo >= 0.0 {
            return 0.0;
        }
        let (lo, hi) =
            increasing_root(|y| self.height(sign * y) - h_mm, (0.0, big_r), (f_lo, f_hi), tolerance::FILLET_HEIGHT_MM);
        0.5 * (lo + hi)
    }

    /// The frame.
    #[must_use]
    pub fn frame(&self) -> &ContactFrame {
        &self.frame
    }

    /// Tool tip and axis.
    #[must_use]
    pub fn tool(&self) -> (DVec3, DVec3) {
        (self.tip, self.axis)
    }
}

/// Scallop (mm) left between the cutter of profile `a` and the cutter of profile `b` whose
/// CC point lies `w_mm` across a (toward a's c when positive, the other way when negative):
/// the height where the two profiles cross, `a.height(y) = b.height(y − w)`, found on y
/// between 0 and w (bracketed regula falsi, `increasing_root`, to
/// [`tolerance::FILLET_HEIGHT_MM`]).
#[must_use]
pub fn scallop_between(a: &CrossProfile<'_>, b: &CrossProfile<'_>, w_mm: f64) -> f64 {
    let sign = if w_mm < 0.0 { -1.0 } else { 1.0 };
    let diff = |t: f64| a.height(sign * t) - b.height(sign * t - w_mm);
    let (f_lo, f_hi) = (diff(0.0), diff(w_mm.abs()));
    let (lo, hi) = if f_lo >= 0.0 {
        (0.0, 0.0)
    } else if f_hi < 0.0 {
        (w_mm.abs(), w_mm.abs())
    } else {
        increasing_root(diff, (0.0, w_mm.abs()), (f_lo, f_hi), tolerance::FILLET_HEIGHT_MM)
    };
    let y = sign * 0.5 * (lo + hi);
    a.height(y).min(b.height(y - w_mm))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lowest point, at cross offset y, of the cutter solid `disc(R0) ⊕ ball(r)`
    /// projected along f, by brute force: the rim circle of the corner centres sampled in
    /// 20 000 steps (the lowest point of the projected disc at any cross offset lies on its
    /// rim's projection), each carrying the corner ball's lowest point above y.
    fn brute_height(cutter: &Cutter, frame: &ContactFrame, tip: DVec3, axis: DVec3, y: f64) -> f64 {
        let r = cutter.corner_radius_mm;
        let r0 = cutter.torus_radius_mm();
        let centre = tip + r * axis;
        let e1 = axis.any_orthonormal_vector();
        let e2 = axis.cross(e1);
        let mut best = f64::INFINITY;
        for k in 0..20_000 {
            let phi = std::f64::consts::TAU * f64::from(k) / 20_000.0;
            for frac in [0.0, 1.0] {
                let p = centre + frac * r0 * (phi.cos() * e1 + phi.sin() * e2) - frame.point;
                let dy = y - p.dot(frame.cross);
                if dy.abs() <= r {
                    best = best.min(p.dot(frame.normal) - (r * r - dy * dy).sqrt());
                }
            }
        }
        best
    }

    #[test]
    fn the_projected_height_is_the_lowest_point_of_the_projected_solid() {
        let frame = ContactFrame {
            uv: DVec2::ZERO,
            point: DVec3::ZERO,
            normal: DVec3::Z,
            feed: DVec3::X,
            cross: DVec3::Y,
            surface_form: Form2 { ff: 0.0, fc: 0.0, cc: 0.0 },
        };
        let (mut worst, mut compared) = (0.0f64, 0usize);
        for (big_r, r) in [(5.0, 1.0), (4.0, 2.5), (5.0, 5.0), (6.0, 0.5)] {
            let Ok(cutter) = Cutter::fillet(big_r, r) else { panic!("cutter {big_r} {r}") };
            for (lead_deg, tilt_deg) in [(3.0, 0.0), (12.0, 0.0), (30.0, 5.0), (8.0, -15.0), (45.0, 20.0)] {
                let pose = Pose::from_lead_tilt(f64::to_radians(lead_deg), f64::to_radians(tilt_deg));
                let (tip, axis) = place(&cutter, &frame, &pose);
                // Inside the projected solid, where the section's slope (by a difference
                // of the brute force) stays within the bracket of the search (|s| ≤ 4).
                for k in -12..=12 {
                    let y = 0.08 * big_r * f64::from(k);
                    let want = brute_height(&cutter, &frame, tip, axis, y);
                    let (up, down) = (
                        brute_height(&cutter, &frame, tip, axis, y + 0.01),
                        brute_height(&cutter, &frame, tip, axis, y - 0.01),
                    );
                    if !(want.is_finite() && up.is_finite() && down.is_finite() && (up - down).abs() < 2.0 * 0.01 * 3.5)
                    {
                        continue;
                    }
                    let got = projected_height(&cutter, &frame, tip, axis, y);
                    compared += 1;
                    worst = worst.max((got - want).abs());
                    assert!(
                        (got - want).abs() < 1e-6,
                        "R {big_r} r {r} lead {lead_deg} tilt {tilt_deg} y {y}: {got} against {want}"
                    );
                }
            }
        }
        assert!(compared >= 200, "only {compared} offsets compared");
        assert!(worst > 0.0, "the comparison compared nothing");
    }
}
