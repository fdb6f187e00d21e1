//! The swept tool between two blocks and its errors (seed 002, §1–2).
//!
//! Between two blocks the machine moves every joint linearly: `J(τ) = J_a + τ(J_b − J_a)`,
//! τ ∈ [0, 1]. Forward kinematics turns J(τ) into the *swept* tool tip and axis in workpiece
//! coordinates; the ball centre follows as `tip + R·axis`. The programmed motion is the
//! straight *chord* between the two programmed points.
//!
//! Errors, all signed with seed 002's rule (overcut +, undercut −; see [`super::path`]):
//! - total error δ(τ) = e_i of the swept ball on surface i;
//! - chord error δt(τ) = e_i of a ball whose centre runs on the centre chord at the same τ
//!   (the arc–chord error of the programmed path);
//! - nonlinear error δn(τ) = δ(τ) − δt(τ), the part due to the rotary axes.
//!
//! So δ = δt + δn holds pointwise (seed 002, eq. 1). On a convex surface the chord cuts in
//! (δt > 0); on a concave one it leaves stock (δt < 0), and a nonlinear error of the
//! opposite sign cancels part of it. A segment's error is the δ of largest magnitude over τ
//! and the surfaces.
//!
//! The *tip deviation* — the largest distance from the swept tool tip to the programmed tip
//! chord — is the purely geometric nonlinear error of the programmed point, reported for
//! comparison with post-processor checks.

use glam::DVec3;

use super::FiveAxisError;
use super::machine::{Joints, Machine};
use super::path::{CutterLocation, DesignPath};
use crate::numerics::maximise::{MaxOptions, brent_max, sampled_max};
use crate::numerics::measure::distance_to_segment;

/// One NC block: a cutter location and the machine's joint values for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    /// The cutter location (workpiece coordinates).
    pub location: CutterLocation,
    /// Joint values (inverse kinematics).
    pub joints: Joints,
}

/// The block at path parameter s, with the inverse-kinematics branch nearest `previous`.
///
/// # Errors
/// When the location cannot be computed or no joint solution is within travel.
pub fn block_at(
    machine: &Machine,
    path: &dyn DesignPath,
    s: f64,
    previous: Option<&Joints>,
) -> Result<Block, FiveAxisError> {
    let location = path.location_at(s)?;
    let joints = machine
        .joints_from_pose(location.tip, location.axis, previous)
        .map_err(|source| FiveAxisError::Kinematics { s, source })?;
    Ok(Block { location, joints })
}

/// The swept tool at one τ of a segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptPoint {
    /// Fraction of the segment, 0 at block a, 1 at block b.
    pub tau: f64,
    /// Interpolated joints.
    pub joints: Joints,
    /// Swept tool tip (workpiece, mm).
    pub tip: DVec3,
    /// Swept tool axis (unit).
    pub axis: DVec3,
    /// Swept ball centre, `tip + R·axis` (mm).
    pub centre: DVec3,
    /// The programmed tip chord at τ (mm).
    pub tip_on_chord: DVec3,
    /// The centre chord at τ (mm).
    pub centre_on_chord: DVec3,
    /// δ: signed error of the swept ball on each surface (mm; gouge +).
    pub errors_mm: [Option<f64>; 2],
    /// δt: signed error of the ball on the centre chord (mm).
    pub chord_errors_mm: [Option<f64>; 2],
}

impl SweptPoint {
    /// δn = δ − δt on surface i (mm).
    #[must_use]
    pub fn nonlinear_mm(&self, i: usize) -> Option<f64> {
        Some(self.errors_mm[i]? - self.chord_errors_mm[i]?)
    }
}

fn swept_pose(
    machine: &Machine,
    path: &dyn DesignPath,
    a: &Block,
    b: &Block,
    tau: f64,
) -> (Joints, DVec3, DVec3, DVec3) {
    let j = a.joints.lerp(&b.joints, tau);
    let pose = machine.pose_from_joints(&j);
    let centre = pose.tip_in_workpiece + path.ball_radius_mm() * pose.axis_in_workpiece;
    (j, pose.tip_in_workpiece, pose.axis_in_workpiece, centre)
}

/// The swept tool at τ with all its errors.
#[must_use]
pub fn swept_point(machine: &Machine, path: &dyn DesignPath, a: &Block, b: &Block, tau: f64) -> SweptPoint {
    let (joints, tip, axis, centre) = swept_pose(machine, path, a, b, tau);
    let (la, lb) = (&a.location, &b.location);
    let centre_on_chord = la.centre.lerp(lb.centre, tau);
    SweptPoint {
        tau,
        joints,
        tip,
        axis,
        centre,
        tip_on_chord: la.tip.lerp(lb.tip, tau),
        centre_on_chord,
        errors_mm: path.surface_errors(centre, la, lb, tau),
        chord_errors_mm: path.surface_errors(centre_on_chord, la, lb, tau),
    }
}

/// `n + 1` equally spaced swept points of a segment (for drawing).
#[must_use]
pub fn swept_samples(machine: &Machine, path: &dyn DesignPath, a: &Block, b: &Block, n: usize) -> Vec<SweptPoint> {
    let n = n.max(1);
    (0..=n).map(|i| swept_point(machine, path, a, b, i as f64 / n as f64)).collect()
}

fn largest(e: [Option<f64>; 2]) -> (f64, usize) {
    let mut best = (0.0f64, 0usize);
    for (i, v) in e.iter().enumerate() {
        if let Some(v) = v
            && (v.abs() > best.0.abs() || i == 0)
        {
            best = (*v, i);
        }
    }
    best
}

fn not_finite(s: f64) -> FiveAxisError {
    FiveAxisError::NotFinite { s }
}

/// δ of a segment: the signed total error of largest magnitude over τ and the surfaces, and
/// where. This is what the step search evaluates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentTotal {
    /// δ (mm; gouge +).
    pub total_mm: f64,
    /// τ of the worst point.
    pub at_tau: f64,
    /// Surface index (0 or 1) of the worst point.
    pub surface: usize,
    /// Swept-ball evaluations spent.
    pub evaluations: u32,
}

/// The largest |δ| of the segment from `a` to `b`, located by sampling and refinement.
///
/// # Errors
/// [`FiveAxisError::NotFinite`] when the surface errors are not finite.
pub fn segment_total(
    machine: &Machine,
    path: &dyn DesignPath,
    a: &Block,
    b: &Block,
    opts: &MaxOptions,
) -> Result<SegmentTotal, FiveAxisError> {
    let (la, lb) = (&a.location, &b.location);
    let g = |tau: f64| -> Result<f64, FiveAxisError> {
        let (_, _, _, centre) = swept_pose(machine, path, a, b, tau);
        let v = largest(path.surface_errors(centre, la, lb, tau)).0.abs();
        if v.is_finite() { Ok(v) } else { Err(not_finite(la.s + tau * (lb.s - la.s))) }
    };
    let peak = sampled_max(g, 0.0, 1.0, opts)?;
    let (_, _, _, centre) = swept_pose(machine, path, a, b, peak.x);
    let (total, surface) = largest(path.surface_errors(centre, la, lb, peak.x));
    Ok(SegmentTotal { total_mm: total, at_tau: peak.x, surface, evaluations: peak.evaluations + 1 })
}

/// Everything about one segment's errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentReport {
    /// δ: the signed total error of largest magnitude (mm; gouge +).
    pub total_mm: f64,
    /// τ where it occurs.
    pub at_tau: f64,
    /// Surface index where it occurs.
    pub surface: usize,
    /// δt there: the chord's share (mm).
    pub chord_mm: f64,
    /// δn there: the rotary axes' share, δ − δt (mm).
    pub nonlinear_mm: f64,
    /// The chord's own worst error over the segment (signed, mm): seed 002's arc–chord
    /// error of the programmed motion.
    pub worst_chord_mm: f64,
    /// Deepest gouge over the segment and both surfaces (mm, ≥ 0).
    pub gouge_mm: f64,
    /// Most stock left (mm, ≥ 0).
    pub stock_mm: f64,
    /// Largest distance from the swept tool tip to the programmed tip chord (mm).
    pub tip_deviation_mm: f64,
}

/// The full error report of the segment from `a` to `b`.
///
/// # Errors
/// [`FiveAxisError::NotFinite`] when the surface errors are not finite.
pub fn segment_report(
    machine: &Machine,
    path: &dyn DesignPath,
    a: &Block,
    b: &Block,
    opts: &MaxOptions,
) -> Result<SegmentReport, FiveAxisError> {
    let (la, lb) = (&a.location, &b.location);
    let s_at = |tau: f64| la.s + tau * (lb.s - la.s);
    let total = segment_total(machine, path, a, b, opts)?;
    let at = swept_point(machine, path, a, b, total.at_tau);
    let chord_mm = at.chord_errors_mm[total.surface].unwrap_or(0.0);

    let chord_peak = sampled_max(
        |tau| {
            let c = la.centre.lerp(lb.centre, tau);
            let v = largest(path.surface_errors(c, la, lb, tau)).0.abs();
            if v.is_finite() { Ok(v) } else { Err(not_finite(s_at(tau))) }
        },
        0.0,
        1.0,
        opts,
    )?;
    let worst_chord_mm = largest(path.surface_errors(la.centre.lerp(lb.centre, chord_peak.x), la, lb, chord_peak.x)).0;

    let signed_peak = |sign: f64| {
        sampled_max(
            |tau| {
                let (_, _, _, c) = swept_pose(machine, path, a, b, tau);
                let e = path.surface_errors(c, la, lb, tau);
                let v = e.iter().flatten().map(|x| sign * x).fold(f64::NEG_INFINITY, f64::max);
                if v.is_finite() { Ok(v) } else { Err(not_finite(s_at(tau))) }
            },
            0.0,
            1.0,
            opts,
        )
    };
    let gouge_mm = signed_peak(1.0)?.value.max(0.0);
    let stock_mm = signed_peak(-1.0)?.value.max(0.0);

    let tip_peak = sampled_max(
        |tau| -> Result<f64, FiveAxisError> {
            let (_, tip, _, _) = swept_pose(machine, path, a, b, tau);
            Ok(distance_to_segment(tip, la.tip, lb.tip))
        },
        0.0,
        1.0,
        opts,
    )?;
    Ok(SegmentReport {
        total_mm: total.total_mm,
        at_tau: total.at_tau,
        surface: total.surface,
        chord_mm,
        nonlinear_mm: total.total_mm - chord_mm,
        worst_chord_mm,
        gouge_mm,
        stock_mm,
        tip_deviation_mm: tip_peak.value,
    })
}

/// The point of the tool whose swept path [`design_deviation`] compares with its design path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Followed {
    /// The tool tip: design tip path `tip(s) = centre(s) − R·axis(s)`.
    Tip,
    /// The ball centre: design centre path (for a crease, the exact crease).
    Centre,
}

/// The largest distance (mm) from the swept tool tip of the segment from `a` to `b` to the
/// *design tip path* of `path` ([`design_deviation`] with [`Followed::Tip`]).
///
/// # Errors
/// As [`design_deviation`].
pub fn tip_design_deviation(
    machine: &Machine,
    path: &dyn DesignPath,
    a: &Block,
    b: &Block,
    opts: &MaxOptions,
) -> Result<f64, FiveAxisError> {
    design_deviation(machine, path, a, b, opts, Followed::Tip)
}

/// The largest distance (mm) from the swept tool tip (or ball centre, `followed`) of the
/// segment from `a` to `b` to its design path of `path` (the exact design curve, the same
/// tool-axis rule): for the tip, what a checker that compares the tip the machine sweeps with
/// the tip the design asks for would measure. It is not what step selection bounds (that is
/// the ball's signed surface error δ) and it is not bounded by E: see `docs/fiveaxis.md`.
///
/// For each τ the nearest point of the design path is searched over the segment's
/// parameter interval widened by its own length on both sides (clamped to the path): the
/// path is sampled there, then the squared distance is minimised by Brent's method around the
/// nearest sample. The largest distance over τ is located like δ ([`sampled_max`]).
///
/// # Errors
/// When a design location cannot be computed or a distance is not finite.
pub fn design_deviation(
    machine: &Machine,
    path: &dyn DesignPath,
    a: &Block,
    b: &Block,
    opts: &MaxOptions,
    followed: Followed,
) -> Result<f64, FiveAxisError> {
    let design_point = |l: &CutterLocation| match followed {
        Followed::Tip => l.tip,
        Followed::Centre => l.centre,
    };
    const SAMPLES: usize = 24;
    let (sa, sb) = (a.location.s, b.location.s);
    let (lo_path, hi_path) = path.range();
    let width = (sb - sa).abs();
    let (lo, hi) = ((sa.min(sb) - width).max(lo_path), (sa.max(sb) + width).min(hi_path));
    let design_at = |s: f64| path.location_at(s).map(|l| design_point(&l));
    let mut samples = Vec::with_capacity(SAMPLES + 1);
    for i in 0..=SAMPLES {
        let s = if i == SAMPLES { hi } else { lo + (hi - lo) * i as f64 / SAMPLES as f64 };
        samples.push((s, design_at(s)?));
    }
    let tol_s = crate::numerics::tolerance::PARAM_SEARCH_REL * (hi - lo).max(f64::MIN_POSITIVE);
    let distance = |p: DVec3| -> Result<f64, FiveAxisError> {
        let (i, _) = samples
            .iter()
            .enumerate()
            .map(|(i, (_, q))| (i, (*q - p).length_squared()))
            .fold((0, f64::INFINITY), |best, x| if x.1 < best.1 { x } else { best });
        let (l, r) = (samples[i.saturating_sub(1)].0, samples[(i + 1).min(SAMPLES)].0);
        let seed = (samples[i].0, -(samples[i].1 - p).length_squared());
        let (_, neg_d2, _) = brent_max(|s| design_at(s).map(|q| -(q - p).length_squared()), l, r, tol_s, seed)?;
        let d = (-neg_d2).max(0.0).sqrt();
        if d.is_finite() { Ok(d) } else { Err(not_finite(sa)) }
    };
    let peak = sampled_max(
        |tau| {
            let (_, tip, _, centre) = swept_pose(machine, path, a, b, tau);
            distance(match followed {
                Followed::Tip => tip,
                Followed::Centre => centre,
            })
        },
        0.0,
        1.0,
        opts,
    )?;
    Ok(peak.value)
}
