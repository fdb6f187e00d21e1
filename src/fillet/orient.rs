//! Tool orientation strategies at a CC point, and smooth orientation along a path.
//!
//! | strategy | lead/tilt |
//! |---|---|
//! | `matched` | the (α, ψ) with the smallest cross curvature Δκ (widest strip) subject to `κ(θ) ≥ k_s(θ) + m` for every θ |
//! | `fixed-lead` | lead λ given, tilt 0 (the common CAM default, "Sturz") |
//! | `principal` | meridian along the principal direction nearest the feed, α from the curvature across it: `k_par(α) = k_s(d⊥) + m` (Rao, Ismail & Bedi 1997) |
//! | `ball` | a ball end mill of the same R along the normal |
//!
//! Every strategy's result is then held to the local no-gouge condition: where it fails the
//! inclination is raised (which only adds curvature to the cutter, module `contact`) until
//! it passes, and the raise is reported.
//!
//! **Smoothness along a path** (no flips): `matched` searches ψ only within a window of
//! ±[`OrientOptions::max_turn_rad_per_mm`]·(step) around the previous node's azimuth
//! (warm start), and α is then limited to change by at most that rate per mm between
//! neighbours by a forward pass (`α_j ≥ α_{j−1} − rate·ds`) and a backward pass
//! (`α_j ≥ α_{j+1} − rate·ds`). Both passes only *raise* α at fixed ψ, which keeps every
//! node gouge-free.

use super::contact::{ContactFrame, Pose, cutter_form_of, cutter_principal, gouge_margin, inclination_for};
use crate::geom::{Cutter, CutterKind};
use crate::numerics::tolerance;

/// How the tool is oriented at each CC point (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Strategy {
    /// Curvature matching: the widest strip without local gouging.
    Matched,
    /// A fixed lead angle λ (rad), no tilt.
    FixedLead {
        /// λ (rad).
        lead_rad: f64,
    },
    /// The principal-axis method.
    PrincipalAxis,
    /// A ball end mill of the same radius R, along the normal.
    Ball,
}

impl Strategy {
    /// Name as in files and on the command line.
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Matched => "matched".into(),
            Self::FixedLead { lead_rad } => format!("fixed-lead {:.1}°", lead_rad.to_degrees()),
            Self::PrincipalAxis => "principal".into(),
            Self::Ball => "ball".into(),
        }
    }

    /// The cutter this strategy machines with: a ball of the same R (and shank/holder) for
    /// [`Strategy::Ball`], otherwise `cutter` itself.
    #[must_use]
    pub fn cutter_for(&self, cutter: &Cutter) -> Cutter {
        match self {
            Self::Ball => Cutter { corner_radius_mm: cutter.radius_mm, ..*cutter },
            _ => *cutter,
        }
    }
}

/// Settings of the orientation (radians, 1/mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientOptions {
    /// The margin m of `κ(θ) ≥ k_s(θ) + m` (1/mm; default 0.002, i.e. the cutter's
    /// effective radius at least 1/(k_s + m)).
    pub margin_per_mm: f64,
    /// Largest inclination α (rad; default 45°).
    pub max_inclination_rad: f64,
    /// Largest |ψ| for `matched` (rad; default 0: lead only; scenes: `finish.max_tilt` in
    /// degrees). Turning the meridian off the feed (tilt) brings the corner's meridian
    /// curvature 1/r into the cross profile; that curvature holds only over the arc r·α
    /// between the contact and the flat bottom, so the second-order model overstates the
    /// strip (scallops up to 2·h at tilts of 5°–20° before the cusp was measured). The
    /// iso-scallop paths measure the cusp each path leaves and correct the side steps from
    /// it, which holds the scallop with tilt too (docs/fillet.md, "Tilt").
    pub max_azimuth_rad: f64,
    /// Largest change of α and ψ per mm of path (rad/mm; default 3°/mm).
    pub max_turn_rad_per_mm: f64,
    /// Smallest cross curvature Δκ (1/mm) `matched` leaves across the feed (default
    /// [`tolerance::FILLET_MIN_CROSS_CURVATURE_PER_MM`], 0.0125 /mm): where the cutter could
    /// match a concave surface closer, α is raised until Δκ reaches it, so that small errors
    /// of the next path's pose or direction cost only a few per cent of the scallop
    /// (docs/fillet.md, "The mould's scallop"). 0 turns it off.
    pub min_cross_curvature_per_mm: f64,
}

impl Default for OrientOptions {
    fn default() -> Self {
        Self {
            margin_per_mm: 0.002,
            max_inclination_rad: 45f64.to_radians(),
            max_azimuth_rad: 0.0,
            max_turn_rad_per_mm: 3f64.to_radians(),
            min_cross_curvature_per_mm: tolerance::FILLET_MIN_CROSS_CURVATURE_PER_MM,
        }
    }
}

/// The smallest inclination this cutter may use (rad): 0 for a ball, else
/// [`tolerance::FILLET_MIN_INCLINATION_RAD`].
#[must_use]
pub fn min_inclination(cutter: &Cutter) -> f64 {
    if cutter.kind() == CutterKind::Ball { 0.0 } else { tolerance::FILLET_MIN_INCLINATION_RAD }
}

/// Grid cells of the matched search in α and ψ, then of each of its two refinements.
const GRID_ALPHA: usize = 40;
const GRID_PSI: usize = 24;
const REFINE: usize = 8;
// The matched search's column table holds GRID_PSI + 1 azimuths, enough for the refinement's.
const _: () = assert!(REFINE <= GRID_PSI);
/// Relative weight per radian of the azimuth's distance from the window's centre in the
/// matched objective: a pose 10° further off must be 1.7 % narrower-scalloped to be chosen.
const AZIMUTH_PREFERENCE: f64 = 0.1;

/// The matched pose at `frame` with ψ within `[psi_lo, psi_hi]` (rad): grid search and two
/// local refinements of Δκ over the feasible set — gouge-free with the margin and Δκ at least
/// [`OrientOptions::min_cross_curvature_per_mm`]; where no pose reaches that floor, the
/// widest strip without it. `None` when no pose is gouge-free.
#[must_use]
pub fn matched_pose(
    cutter: &Cutter,
    frame: &ContactFrame,
    opts: &OrientOptions,
    psi_range: (f64, f64),
) -> Option<Pose> {
    let floor = opts.min_cross_curvature_per_mm;
    if floor > 0.0
        && let Some(p) = matched_pose_above(cutter, frame, opts, psi_range, floor)
    {
        return Some(p);
    }
    matched_pose_above(cutter, frame, opts, psi_range, f64::NEG_INFINITY)
}

/// [`matched_pose`] with the cross curvature held at or above `floor` (1/mm).
fn matched_pose_above(
    cutter: &Cutter,
    frame: &ContactFrame,
    opts: &OrientOptions,
    psi_range: (f64, f64),
    floor: f64,
) -> Option<Pose> {
    let a_lo = min_inclination(cutter);
    let a_hi = opts.max_inclination_rad.max(a_lo);
    let m = opts.margin_per_mm;
    // Near-ties in Δκ between azimuths are common (the optimum is flat in ψ); a small
    // preference for the window's centre (the previous node's ψ) keeps the choice from
    // jumping between them.
    let psi_ref = 0.5 * (psi_range.0 + psi_range.1);
    // The cutter's principal curvatures at α and (sin ψ, cos ψ), each computed once per grid
    // row or column (`cutter_form_of`: the same bits as `cutter_form`).
    let eval = |k: (f64, f64), psi: f64, psi_sc: (f64, f64)| -> Option<f64> {
        // D = Q_c − Q_s once for both: the margin (`gouge_margin`) is its smallest
        // eigenvalue, Δκ (`cross_curvature`) its silhouette, held at or above the floor.
        let d = cutter_form_of(k, psi_sc).minus(&frame.surface_form);
        if d.min_eigen() < m {
            return None;
        }
        let dk = d.silhouette();
        (dk >= floor).then(|| dk * (1.0 + AZIMUTH_PREFERENCE * (psi - psi_ref).abs()))
    };
    if cutter.kind() == CutterKind::Ball {
        let p = Pose { inclination_rad: 0.0, azimuth_rad: 0.0 };
        return eval(cutter_principal(cutter, 0.0), 0.0, 0.0f64.sin_cos()).map(|_| p);
    }
    let mut best: Option<(f64, f64, f64)> = None;
    let search = |a0: f64, a1: f64, p0: f64, p1: f64, na: usize, np: usize, best: &mut Option<(f64, f64, f64)>| {
        // The columns' ψ with their sines and cosines (np ≤ GRID_PSI).
        let mut cols = [(0.0, (0.0, 0.0)); GRID_PSI + 1];
        for (j, col) in cols.iter_mut().enumerate().take(np + 1) {
            let psi = if np == 0 { 0.5 * (p0 + p1) } else { p0 + (p1 - p0) * j as f64 / np as f64 };
            *col = (psi, psi.sin_cos());
        }
        for i in 0..=na {
            let alpha = a0 + (a1 - a0) * i as f64 / na as f64;
            let k = cutter_principal(cutter, alpha);
            for &(psi, psi_sc) in &cols[..=np] {
                if let Some(v) = eval(k, psi, psi_sc)
                    && best.is_none_or(|b| v < b.0)
                {
                    *best = Some((v, alpha, psi));
                }
            }
        }
    };
    let np = if psi_range.1 > psi_range.0 { GRID_PSI } else { 0 };
    search(a_lo, a_hi, psi_range.0, psi_range.1, GRID_ALPHA, np, &mut best);
    let (mut da, mut dp) = ((a_hi - a_lo) / GRID_ALPHA as f64, (psi_range.1 - psi_range.0) / GRID_PSI as f64);
    for _ in 0..2 {
        let (_, a, p) = best?;
        let (a0, a1) = ((a - da).max(a_lo), (a + da).min(a_hi));
        let (p0, p1) = ((p - dp).max(psi_range.0), (p + dp).min(psi_range.1));
        search(a0, a1, p0, p1, REFINE, if np == 0 { 0 } else { REFINE }, &mut best);
        da *= 2.0 / REFINE as f64;
        dp *= 2.0 / REFINE as f64;
    }
    best.map(|(_, a, p)| Pose { inclination_rad: a, azimuth_rad: p })
}

/// The principal-axis pose (module docs), before the no-gouge raise.
#[must_use]
pub fn principal_pose(cutter: &Cutter, frame: &ContactFrame, opts: &OrientOptions) -> Option<Pose> {
    let q = frame.surface_form;
    // Principal directions in (f, c): tan 2φ = 2 fc / (ff − cc).
    let phi = 0.5 * (2.0 * q.fc).atan2(q.ff - q.cc);
    let half = std::f64::consts::FRAC_PI_2;
    // The principal direction nearest the feed: φ or φ ± 90°, brought into (−45°, 45°].
    let mut psi = phi;
    while psi > 0.5 * half {
        psi -= half;
    }
    while psi <= -0.5 * half {
        psi += half;
    }
    let across = q.at(psi + half);
    let alpha = inclination_for(cutter, across + opts.margin_per_mm)?.max(min_inclination(cutter));
    Some(Pose { inclination_rad: alpha, azimuth_rad: psi })
}

/// Raises α at fixed ψ (steps of 0.25°) until the local no-gouge condition holds; returns
/// the pose and how much α was raised (rad), or `None` when even the largest inclination
/// gouges.
#[must_use]
pub fn raise_until_clear(
    cutter: &Cutter,
    frame: &ContactFrame,
    opts: &OrientOptions,
    pose: Pose,
) -> Option<(Pose, f64)> {
    let step = 0.25f64.to_radians();
    let m = opts.margin_per_mm;
    let mut p = pose;
    let limit = opts.max_inclination_rad.max(pose.inclination_rad);
    loop {
        if gouge_margin(cutter, frame, &p) >= m {
            return Some((p, p.inclination_rad - pose.inclination_rad));
        }
        if p.inclination_rad >= limit {
            return None;
        }
        p.inclination_rad = (p.inclination_rad + step).min(limit);
    }
}

/// The pose a strategy gives at one CC point (before smoothing), with the α raised by the
/// local check (rad). `psi_range` only applies to `matched`. `None`: no pose is locally
/// gouge-free.
#[must_use]
pub fn pose_at(
    strategy: &Strategy,
    cutter: &Cutter,
    frame: &ContactFrame,
    opts: &OrientOptions,
    psi_range: (f64, f64),
) -> Option<(Pose, f64)> {
    let tool = strategy.cutter_for(cutter);
    let first = match strategy {
        Strategy::Matched => matched_pose(&tool, frame, opts, psi_range)?,
        Strategy::FixedLead { lead_rad } => Pose {
            inclination_rad: lead_rad.abs().max(min_inclination(&tool)),
            azimuth_rad: if *lead_rad < 0.0 { std::f64::consts::PI } else { 0.0 },
        },
        Strategy::PrincipalAxis => principal_pose(&tool, frame, opts)
            .unwrap_or(Pose { inclination_rad: opts.max_inclination_rad, azimuth_rad: 0.0 }),
        Strategy::Ball => Pose { inclination_rad: 0.0, azimuth_rad: 0.0 },
    };
    raise_until_clear(&tool, frame, opts, first)
}

/// The cutter's smallest curvature at inclination α (1/mm): its effective cutting
/// curvature across the meridian.
#[must_use]
pub fn across_curvature(cutter: &Cutter, inclination_rad: f64) -> f64 {
    cutter_principal(cutter, inclination_rad).1
}

/// Limits the change of α between neighbouring nodes (spaced `ds_mm[j]` = distance from
/// node j to j+1) to `rate`·ds by raising α (module docs).
pub fn smooth_inclinations(poses: &mut [Pose], ds_mm: &[f64], rate_rad_per_mm: f64) {
    let n = poses.len();
    for j in 1..n {
        let lim = poses[j - 1].inclination_rad - rate_rad_per_mm * ds_mm[j - 1];
        if poses[j].inclination_rad < lim {
            poses[j].inclination_rad = lim;
        }
    }
    for j in (0..n.saturating_sub(1)).rev() {
        let lim = poses[j + 1].inclination_rad - rate_rad_per_mm * ds_mm[j];
        if poses[j].inclination_rad < lim {
            poses[j].inclination_rad = lim;
        }
    }
}
