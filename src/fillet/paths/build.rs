//! One path along a uv polyline: the forward steps, the orientation and gouge checks of its nodes, its chords certified between the poses, its lead-in and lead-out.

use glam::{DVec2, DVec3};

use super::{Ctx, Refusal, Sample, ToolPath, a_of};
use crate::fillet::FinishError;
use crate::fillet::contact::{ContactFrame, CrossProfile, Pose, place};
use crate::fillet::gouge::{Adjustment, REACH_MARGIN_RAD, adjust, check};
use crate::fillet::node::CcNode;
use crate::fillet::orient::{pose_at, smooth_inclinations};
use crate::fillet::program::design_between;
use crate::fillet::sweep::{pose_between, surface_depth_near};
use crate::geom::{Cutter, ParametricSurface};
use crate::numerics::tolerance::ROUNDING_REL;

/// How far (mm) a path's last cutter must travel on past the far end along its feed so that
/// every point of the far edge within `reach_mm` of the CC curve across is cut as low as the
/// moving cutter cuts elsewhere; `slant` is the tangent of the edge's angle from the cross
/// direction c (0 when the edge runs square to the feed). At most the cutter's diameter 2·R.
///
/// Two parts. (1) The cutter's lowest point at cross offset y trails the contact: with the
/// meridian along the feed (azimuth 0, the contact at the front of the corner torus) it lies
/// on the corner ball whose centre sits on the centre circle (radius R0 = R − r, in the
/// plane ⟂ a) at a lateral offset y_c between 0 and y, and that centre trails the contact's
/// centre by R0·(1 − cos φ)·cos α ≤ R0 − √(R0² − y²) along the feed (sin φ = y_c/R0). A
/// moving cutter cuts the point (x, y) when it stands that far ahead of x; stopped at the
/// end it leaves the static cutter's section there (measured: up to 2.4·h on the blade).
/// With a tilt (azimuth ≠ 0) the centre circle's diameter 2·R0 bounds this lag; a ball
/// (R0 = 0) has its lowest point beside the contact: 0. (2) A slanted edge's points at cross
/// offset y lie up to y·slant further ahead (on the blade's far edge the end nodes of
/// neighbouring paths are 0.32 mm apart along the feed for a 2.15 mm side step).
#[must_use]
pub fn lead_out_mm(cutter: &Cutter, pose: &Pose, reach_mm: f64, slant: f64) -> f64 {
    let r0 = cutter.torus_radius_mm();
    let y = reach_mm.max(0.0);
    let lag = if r0 <= 0.0 {
        0.0
    } else if pose.azimuth_rad != 0.0 {
        2.0 * r0
    } else {
        let yc = y.min(r0);
        r0 - (r0 * r0 - yc * yc).sqrt()
    };
    let ahead = if slant.is_finite() { y * slant.abs() } else { f64::INFINITY };
    (lag + ahead).min(2.0 * cutter.radius_mm)
}

/// The contact frame a lead-out of `d_mm` (mm) past `end` stands on: the surface continued
/// past the path's end to second order. The point moves along the feed's normal section
/// (d·f + ½·k_ff·d²·n), and the frame turns as the surface's normal turns along the feed,
/// dn/ds = −(k_ff·f + k_fc·c), df/ds = k_ff·n: the rotation by d·(k_fc·f − k_ff·c). The
/// cutter placed there with the last pose keeps its pose to the surface's continuation: its
/// lean across the feed follows the twist k_fc, its lean along it k_ff. Moved straight with
/// the axis held, on the mould (k_fc up to 0.005 /mm at a 2.4 mm side step, the bowl rising
/// ahead) the cusps of the last 0.4 mm before the far end rose to 1.19·h, 1.112·h inside the
/// edge lines; turned, ≤ 1.04·h (docs/fillet.md, "The mould's ends").
#[must_use]
pub fn lead_out_frame(end: &ContactFrame, d_mm: f64) -> ContactFrame {
    let (f, c, n) = (end.feed, end.cross, end.normal);
    let (ff, fc) = (end.surface_form.ff, end.surface_form.fc);
    // The point on the normal section's osculating circle (to second order: ½·ff·d² along n).
    let point = end.point + d_mm * f + 0.5 * ff * d_mm * d_mm * n;
    // The frame turned as the surface's normal turns along the feed: dn/ds = −(ff·f + fc·c),
    // df/ds = ff·n, i.e. the rotation vector (fc·f − ff·c) per mm.
    let rot = glam::DQuat::from_scaled_axis(d_mm * (fc * f - ff * c));
    ContactFrame { point, feed: rot * f, cross: rot * c, normal: rot * n, ..*end }
}

/// The forward step keeps the chord's sag within this share of h as well as within E: the
/// cutter between two CL rows moves on the chord, raised (concave along the feed) or lowered
/// (convex) by up to the sag, and the cusp with it. Measured from the CL data with E = h/20
/// (the examples): cusps of 0.947·h between the rows on the convex blade; with h/40 the band
/// keeps ±5 % with room for the side step's own ±0.5 % and the model's error. Applied only
/// where the surface is convex along the feed (the chord below it, the cusp lowered): on the
/// concave mould h/40 everywhere took the brute-force sections to 0.941–0.983·h (E alone:
/// 0.978–1.008·h), measured after merging the lead-outs with the mould's floor and trims.
pub(super) const SAG_SHARE_OF_H: f64 = 1.0 / 40.0;

/// Halvings of a lead-out that the gouge checks find too long before it is left out.
pub(super) const LEAD_OUT_HALVINGS: usize = 6;

/// Share of the gouge tolerance a lead-out's check allows (as `gouge::adjust` does: the
/// check measures the part's depth inside the cutter, a re-computation the cutter's below
/// the part; the two agree to first order).
pub(super) const LEAD_OUT_CHECK_SHARE: f64 = 0.9;

/// A path's last node counts as on the along parameter's far end within this fraction of
/// the along range.
pub(super) const LEAD_OUT_EDGE_REL: f64 = 1e-9;

/// Shortest step along a path, as a fraction of the longest (`max_step_mm`): where the
/// curvature would ask for less, the path is sampled at this.
const MIN_STEP_REL: f64 = 1e-3;

/// Half the chord that gives an offset path's feed at a node, relative to the longest
/// forward step.
pub(super) const FEED_CHORD: f64 = 0.5;

/// Share of the gouge tolerance the surface may reach into the cutter swept to a chord's
/// middle before the chord certification (`docs/fillet.md`, "Between the poses") puts a node there (the poses are checked to
/// `gouge::CHECK_SHARE` = 0.9 of it too).
pub const BETWEEN_CHECK_SHARE: f64 = 0.9;

/// Share of h the cutter swept to a chord's middle may stand clear of the surface (when
/// above the chord tolerance) before the chord certification (`docs/fillet.md`, "Between the poses") puts a node there.
pub const LIFT_SHARE_OF_H: f64 = 0.1;

/// The share of its parent's lift a halved chord's lift must fall below for the chord
/// certification to halve it again.
pub const LIFT_HALVING_GAIN: f64 = 0.5;

/// Most halvings of one chord by the chord certification (`docs/fillet.md`, "Between the poses") (up to 2⁴ − 1 nodes put into it).
pub const CHORD_SPLITS: usize = 4;

/// The strip's reaches at h (mm; toward −c and +c, `CrossProfile::reach`) of the CC nodes
/// [`Ctx::node`] built, by the bits of their frame and pose: the side steps from a node (its
/// reach toward the next path is the side step's first guess) and its lead-out (the larger
/// reach) need the same two numbers its strip width was made of, the same computation on
/// the same inputs. Kept for the path being built (`current`) and the one before it
/// (`previous`, the one the side steps start from); [`Reaches::next_path`] drops the rest.
/// A node not found is computed again, to the same bits.
#[derive(Clone, Debug, Default)]
pub(super) struct Reaches {
    current: std::collections::HashMap<[u64; 13], [f64; 2]>,
    previous: std::collections::HashMap<[u64; 13], [f64; 2]>,
}

impl Reaches {
    /// The key of a node: every number its cross profile is made of (the frame's point,
    /// normal, feed and parameters, which determine the rest of it, and the pose).
    fn key(frame: &ContactFrame, pose: &Pose) -> [u64; 13] {
        let (p, n, f) = (frame.point, frame.normal, frame.feed);
        [p.x, p.y, p.z, n.x, n.y, n.z, f.x, f.y, f.z, frame.uv.x, frame.uv.y, pose.inclination_rad, pose.azimuth_rad]
            .map(f64::to_bits)
    }

    /// The next path is about to be built: the current one's reaches become the previous
    /// ones, older ones are dropped.
    pub(super) fn next_path(&mut self) {
        self.previous = std::mem::take(&mut self.current);
    }

    fn get(&self, frame: &ContactFrame, pose: &Pose) -> Option<[f64; 2]> {
        let key = Self::key(frame, pose);
        self.current.get(&key).or_else(|| self.previous.get(&key)).copied()
    }
}

impl Ctx<'_> {
    /// The strip's reach at h from `node` toward `sign`·c (`sign` ±1), as its cross profile
    /// gives it: from [`Reaches`] when the node's reaches are there (the same bits).
    pub(super) fn reach(&self, tool: &Cutter, node: &CcNode, sign: f64) -> f64 {
        #[expect(clippy::float_cmp, reason = "only the exact signs the memo holds")]
        let index = if sign == 1.0 {
            Some(1)
        } else if sign == -1.0 {
            Some(0)
        } else {
            None
        };
        if let (Some(i), Some(memo)) = (index, self.reaches)
            && let Some(reach) = memo.borrow().get(&node.frame, &node.pose)
        {
            return reach[i];
        }
        CrossProfile::new(tool, self.surface, node.frame, &node.pose).reach(self.opts.scallop_mm, sign)
    }

    /// Nodes along a uv polyline by the forward step, oriented, smoothed, checked.
    /// `psi_ref`: per polyline vertex, the azimuth window (centre, half width, rad) the
    /// side step assumed for it (offset paths); without it each node's window is centred on
    /// the previous node's azimuth.
    pub(super) fn build_path(
        &self,
        poly: &[DVec2],
        psi_ref: Option<&[(f64, f64)]>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<ToolPath, FinishError> {
        let samples = self.forward_samples(poly, psi_ref, budget)?;
        self.path_from_samples(samples, refused, budget)
    }

    /// The points of a path along a uv polyline by the forward step (each counted against
    /// `budget`): the cheap part of [`Self::build_path`], before any orientation or check.
    pub(super) fn forward_samples(
        &self,
        poly: &[DVec2],
        psi_ref: Option<&[(f64, f64)]>,
        budget: &mut usize,
    ) -> Result<Vec<Sample>, FinishError> {
        let pts: Vec<DVec3> = poly.iter().map(|&uv| self.surface.point_at(uv)).collect();
        let mut cum = vec![0.0];
        for w in pts.windows(2) {
            let l = cum.last().copied().unwrap_or(0.0) + (w[1] - w[0]).length();
            cum.push(l);
        }
        let total = cum.last().copied().unwrap_or(0.0);
        let segment = |s: f64| -> (usize, f64) {
            let k = cum.partition_point(|&c| c <= s).clamp(1, cum.len().max(2) - 1);
            let (c0, c1) = (cum[k - 1], cum[k]);
            (k, if c1 > c0 { ((s - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.0 })
        };
        let point = |s: f64| -> DVec3 {
            let (k, t) = segment(s);
            pts[k - 1].lerp(pts[k], t)
        };
        // The feed of an offset path: the chord over ±half the longest step (FEED_CHORD), so
        // that a short jog of the offset curve (a trimmed swallowtail's corner, a cusp's
        // remnant) does not turn a node's feed, and with it the next side step, sideways.
        let half = if psi_ref.is_some() { FEED_CHORD * self.opts.max_step_mm } else { 0.0 };
        let at = |s: f64| -> (DVec2, DVec3, Option<(f64, f64)>) {
            let (k, t) = segment(s);
            let psi = psi_ref.and_then(|r| {
                let (a, b) = (r.get(k - 1)?, r.get(k)?);
                Some((a.0 + t * (b.0 - a.0), a.1.max(b.1)))
            });
            let chord = point((s + half).min(total)) - point((s - half).max(0.0));
            let dir = if half > 0.0 && chord.length_squared() > 0.0 { chord } else { pts[k] - pts[k - 1] };
            (poly[k - 1].lerp(poly[k], t), dir, psi)
        };
        // Forward steps.
        let mut samples: Vec<Sample> = Vec::new();
        let mut s = 0.0;
        loop {
            if *budget == 0 {
                return Err(FinishError::TooManyNodes { max_nodes: self.opts.max_nodes });
            }
            *budget -= 1;
            let (uv, dir, psi) = at(s);
            if s >= total {
                samples.push((uv, dir, psi, None));
                break;
            }
            // Normal curvature along the feed, positive where the surface bends toward the
            // cutter (concave): there the chord sag only raises the cutter, E alone bounds it.
            let frame = ContactFrame::with_cross_uv(self.surface, uv, dir);
            samples.push((uv, dir, psi, frame));
            let ff = frame.map_or(0.0, |f| f.0.surface_form.ff);
            let k = ff.abs();
            let sag = if ff < 0.0 {
                self.opts.chord_tol_mm.min(SAG_SHARE_OF_H * self.opts.scallop_mm)
            } else {
                self.opts.chord_tol_mm
            };
            let step = if k > 0.0 { (8.0 * sag / k).sqrt() } else { f64::INFINITY };
            let step = step.min(self.opts.max_step_mm).max(MIN_STEP_REL * self.opts.max_step_mm);
            s = if s + step >= total - ROUNDING_REL * total.max(1.0) { total } else { s + step };
        }
        Ok(samples)
    }

    /// The path of [`Self::forward_samples`]'s points: oriented, smoothed, checked.
    pub(super) fn path_from_samples(
        &self,
        samples: Vec<Sample>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<ToolPath, FinishError> {
        // Frames and poses, ψ warm-started from the previous node.
        let mut frames = Vec::with_capacity(samples.len());
        let mut poses: Vec<Pose> = Vec::with_capacity(samples.len());
        let mut prev: Option<(DVec3, Pose)> = None;
        let oo = &self.opts.orient;
        for (uv, dir, psi_win, found) in samples {
            let Some((frame, cross_uv)) = found.or_else(|| ContactFrame::with_cross_uv(self.surface, uv, dir)) else {
                refused.push(Refusal {
                    uv,
                    point: self.surface.point_at(uv),
                    reason: "singular point of the surface (no normal)",
                    depth_mm: 0.0,
                });
                continue;
            };
            let window = match (psi_win, prev) {
                (Some((c, d)), _) => ((c - d).max(-oo.max_azimuth_rad), (c + d).min(oo.max_azimuth_rad)),
                (None, Some((p, pose))) => {
                    let d = oo.max_turn_rad_per_mm * (frame.point - p).length();
                    ((pose.azimuth_rad - d).max(-oo.max_azimuth_rad), (pose.azimuth_rad + d).min(oo.max_azimuth_rad))
                }
                (None, None) => (-oo.max_azimuth_rad, oo.max_azimuth_rad),
            };
            let found = pose_at(&self.strategy, &self.cutter, &frame, oo, window).or_else(|| {
                pose_at(&self.strategy, &self.cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))
            });
            let Some((pose, _)) = found else {
                refused.push(Refusal {
                    uv,
                    point: frame.point,
                    reason: "the surface is more concave than the cutter's largest effective curvature",
                    depth_mm: 0.0,
                });
                continue;
            };
            prev = Some((frame.point, pose));
            frames.push((frame, cross_uv));
            poses.push(pose);
        }
        let ds: Vec<f64> = frames.windows(2).map(|w| (w[1].0.point - w[0].0.point).length()).collect();
        smooth_inclinations(&mut poses, &ds, oo.max_turn_rad_per_mm);
        let tool = self.strategy.cutter_for(&self.cutter);
        // Gouge checks and adjustment, then the inclinations smoothed again (raising only).
        let mut checked: Vec<((ContactFrame, DVec2), Pose, Option<Adjustment>)> = Vec::with_capacity(frames.len());
        for ((frame, cross_uv), pose) in frames.into_iter().zip(poses) {
            let verdict = adjust(&tool, self.surface, self.part, &frame, pose, oo, self.opts.gouge_tol_mm, self.reach);
            self.count_check()?;
            match verdict {
                Ok((pose, adjusted)) => checked.push(((frame, cross_uv), pose, adjusted)),
                Err(clash) => refused.push(Refusal {
                    uv: frame.uv,
                    point: frame.point,
                    reason: match clash.part {
                        crate::fillet::gouge::ClashPart::Bottom => {
                            "the cutter's bottom gouges the surface at every inclination tried"
                        }
                        crate::fillet::gouge::ClashPart::Flank => {
                            "the cutter's flank gouges the part at every inclination tried"
                        }
                        crate::fillet::gouge::ClashPart::Shank => {
                            "the shank collides with the part at every inclination tried"
                        }
                        crate::fillet::gouge::ClashPart::Holder => {
                            "the holder collides with the part at every inclination tried"
                        }
                        crate::fillet::gouge::ClashPart::Travel => {
                            "the machine cannot tilt the tool axis to any clear inclination tried (its rotary travel)"
                        }
                    },
                    depth_mm: clash.depth_mm,
                }),
            }
        }
        let mut poses: Vec<Pose> = checked.iter().map(|c| c.1).collect();
        let ds: Vec<f64> = checked.windows(2).map(|w| (w[1].0.0.point - w[0].0.0.point).length()).collect();
        smooth_inclinations(&mut poses, &ds, oo.max_turn_rad_per_mm);
        if let Some(machine) = self.reach {
            // A raise that tilts the axis out of the machine's travel is taken back: the
            // checked pose was within it (the turn rate is then over its limit there, which
            // only the smoothness asks for; travel the machine must have).
            for (pose, c) in poses.iter_mut().zip(&checked) {
                if !machine.reaches_axis(pose.axis(&c.0.0), REACH_MARGIN_RAD) {
                    *pose = c.1;
                }
            }
        }
        let nodes: Vec<CcNode> = checked
            .into_iter()
            .zip(poses)
            .map(|(((frame, cross_uv), _, adjusted), pose)| self.node(&tool, frame, Some(cross_uv), pose, adjusted))
            .collect();
        let mut nodes = self.certify_chords(&tool, nodes, refused, budget)?;
        if let Some(lead) = nodes.last().and_then(|last| self.lead_out(&tool, last, true)) {
            nodes.push(lead);
        }
        if let Some(lead) = nodes.first().and_then(|first| self.lead_out(&tool, first, false)) {
            nodes.insert(0, lead);
        }
        Ok(ToolPath { nodes })
    }

    /// The CC node of `frame` with the cutter at `pose`: placed, with its strip width.
    /// `cross_uv`: the frame's cross direction in (u, v) when [`ContactFrame::with_cross_uv`]
    /// gave it (else evaluated here, the same bits).
    pub(super) fn node(
        &self,
        tool: &Cutter,
        frame: ContactFrame,
        cross_uv: Option<DVec2>,
        pose: Pose,
        adjusted: Option<Adjustment>,
    ) -> CcNode {
        let (tip, axis) = place(tool, &frame, &pose);
        let prof = match cross_uv {
            Some(c) => CrossProfile::with_cross_uv(tool, self.surface, frame, &pose, Some(c)),
            None => CrossProfile::new(tool, self.surface, frame, &pose),
        };
        let h = self.opts.scallop_mm;
        let reach = [prof.reach(h, -1.0), prof.reach(h, 1.0)];
        if let Some(memo) = self.reaches {
            memo.borrow_mut().current.insert(Reaches::key(&frame, &pose), reach);
        }
        CcNode {
            frame,
            pose,
            tip,
            axis,
            strip_mm: reach[1] + reach[0],
            side_step_mm: None,
            scallop_mm: None,
            adjusted,
            lead_out: false,
        }
    }

    /// The path's chords certified between their poses: where the design surface reaches
    /// deeper than [`BETWEEN_CHECK_SHARE`] × the gouge tolerance into the cutter swept to the
    /// middle of a chord (tip and axis interpolated, as the controller moves them), or the
    /// swept cutter stands clear of it there by more than the chord tolerance E and
    /// [`LIFT_SHARE_OF_H`]·h (material left on the path itself, which the scallop between
    /// the paths stands on), a CC
    /// node is put at the middle of the chord's CC points (its pose the mean of the two,
    /// gouge-checked as every pose), and each half checked again, at most [`CHORD_SPLITS`]
    /// times. A chord whose middle node cannot be placed clear is left and its middle
    /// refused (named, with its depth). Each node put in is counted against `budget` (the
    /// job's CC points, as the forward steps count theirs).
    pub(super) fn certify_chords(
        &self,
        tool: &Cutter,
        nodes: Vec<CcNode>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<Vec<CcNode>, FinishError> {
        let tol = BETWEEN_CHECK_SHARE * self.opts.gouge_tol_mm;
        let mut out: Vec<CcNode> = Vec::with_capacity(nodes.len());
        for target in nodes {
            // Each chord to check with its halvings so far and the lift of the chord it halves.
            let mut pending = vec![(target, 0usize, f64::INFINITY)];
            while let Some((b, depth, parent_lift)) = pending.pop() {
                let Some(a) = out.last().copied() else {
                    out.push(b);
                    continue;
                };
                let (tip, axis) = pose_between(&a, &b, 0.5);
                let uv = a.frame.uv.lerp(b.frame.uv, 0.5);
                let deep = surface_depth_near(tool, self.surface, tip, axis, uv);
                // Lead-ins and lead-outs are neither split nor refused.
                let interior = !a.lead_out && !b.lead_out;
                // For a machine: the axis the program's planner follows at the chord's
                // quarters within its travel, with half the nodes' room (the axis swings past
                // its samples by ≪ that between them). Sampled only where it decides: a chord
                // too deep is split or refused for that.
                let swung = interior
                    && !(deep > tol)
                    && self.reach.is_some_and(|m| {
                        [0.25, 0.5, 0.75].iter().any(|&t| {
                            design_between(self.surface, tool, &a, &b, t)
                                .is_some_and(|d| !m.reaches_axis(d.2, 0.5 * REACH_MARGIN_RAD))
                        })
                    });
                // A lift is halved only while halving helps (a chord's sag falls fourfold with
                // its length; a lift that does not fall to half its parent's is the strategy's
                // own stand-off, which more nodes would not lower, only check).
                let lifted = -deep > self.opts.chord_tol_mm.max(LIFT_SHARE_OF_H * self.opts.scallop_mm)
                    && -deep < LIFT_HALVING_GAIN * parent_lift;
                if (deep > tol || lifted || swung) && interior {
                    let placed = if depth < CHORD_SPLITS { self.node_between(tool, &a, &b)? } else { None };
                    if let Some(mid) = placed {
                        if *budget == 0 {
                            return Err(FinishError::TooManyNodes { max_nodes: self.opts.max_nodes });
                        }
                        *budget -= 1;
                        pending.push((b, depth + 1, -deep));
                        pending.push((mid, depth + 1, -deep));
                        continue;
                    }
                }
                if deep > tol && interior {
                    refused.push(Refusal {
                        uv,
                        point: self.surface.point_at(uv),
                        reason: "the cutter swept between two poses reaches below the surface and no pose between them clears it",
                        depth_mm: deep,
                    });
                } else if swung {
                    refused.push(Refusal {
                        uv,
                        point: self.surface.point_at(uv),
                        reason: "the tool axis between two poses leaves the machine's rotary travel and no pose between them is within it",
                        depth_mm: 0.0,
                    });
                }
                out.push(b);
            }
        }
        Ok(out)
    }

    /// A CC node at the middle of the CC points of `a` and `b` (in u, v), its feed along the
    /// chord, its pose the mean of theirs after the gouge checks; `None` where the surface
    /// has no frame there or the checks find no clear pose.
    pub(super) fn node_between(&self, tool: &Cutter, a: &CcNode, b: &CcNode) -> Result<Option<CcNode>, FinishError> {
        let uv = a.frame.uv.lerp(b.frame.uv, 0.5);
        let Some((frame, cross_uv)) = ContactFrame::with_cross_uv(self.surface, uv, b.frame.point - a.frame.point)
        else {
            return Ok(None);
        };
        // The strategy's pose within the two azimuths (its own rules, such as the matched
        // cutter's cross-curvature floor, hold there too), else the mean of the two.
        let (p0, p1) = (a.pose.azimuth_rad.min(b.pose.azimuth_rad), a.pose.azimuth_rad.max(b.pose.azimuth_rad));
        let pose = pose_at(&self.strategy, &self.cutter, &frame, &self.opts.orient, (p0, p1)).map_or(
            Pose {
                inclination_rad: 0.5 * (a.pose.inclination_rad + b.pose.inclination_rad),
                azimuth_rad: 0.5 * (a.pose.azimuth_rad + b.pose.azimuth_rad),
            },
            |p| p.0,
        );
        let verdict =
            adjust(tool, self.surface, self.part, &frame, pose, &self.opts.orient, self.opts.gouge_tol_mm, self.reach);
        self.count_check()?;
        Ok(verdict.ok().map(|(pose, adjusted)| self.node(tool, frame, Some(cross_uv), pose, adjusted)))
    }

    /// The lead-out after `last` when it lies on the along parameter's far end (`far`), or
    /// the lead-in before the first node `last` when it lies on the near end (`!far`): its
    /// cutter moved [`lead_out_mm`] on (back) along the feed with the surface's continuation,
    /// for the strip's reach at h on either side. The lowest point of the cutter at a cross
    /// offset lies behind the contact on one side and, where the surface is twisted, ahead of
    /// it on the other: both ends need the poses past them (the mould's start edge line
    /// measured 2.10·h without a lead-in, 1.035·h with one).
    pub(super) fn lead_out(&self, tool: &Cutter, last: &CcNode, far: bool) -> Option<CcNode> {
        let ((a0, a1), _) = self.ranges();
        let a = a_of(last.frame.uv, self.along);
        let slack = LEAD_OUT_EDGE_REL * (a1 - a0);
        if (far && a < a1 - slack) || (!far && a > a0 + slack) {
            return None;
        }
        let sense = if far { 1.0 } else { -1.0 };
        let reach = self.reach(tool, last, 1.0).max(self.reach(tool, last, -1.0));
        // The far edge's slant against the cross direction: tan of its angle from c.
        let der = self.surface.derivatives_at(last.frame.uv);
        let edge = if self.along == 0 { der.dv } else { der.du };
        let (along_f, along_c) = (edge.dot(last.frame.feed).abs(), edge.dot(last.frame.cross).abs());
        let slant = if along_c > 0.0 { along_f / along_c } else { f64::INFINITY };
        // Where the far edge is slanted part of the cutter is still over the surface past the
        // end node: the lead-out is checked like every pose and halved until it clears (none
        // after LEAD_OUT_HALVINGS).
        let mut d = lead_out_mm(tool, &last.pose, reach, slant);
        let tol = LEAD_OUT_CHECK_SHARE * self.opts.gouge_tol_mm;
        for _ in 0..=LEAD_OUT_HALVINGS {
            if d <= 0.0 {
                return None;
            }
            // The cutter continued with the surface past the end (its twist and its curvature
            // along the feed), not moved straight: see `lead_out_frame`.
            let frame = lead_out_frame(&last.frame, sense * d);
            let (tip, axis) = place(tool, &frame, &last.pose);
            // The continued frame turns the axis with it: for a machine, within its travel.
            if self.reach.is_none_or(|m| m.reaches_axis(axis, REACH_MARGIN_RAD))
                && check(tool, self.surface, self.part, &frame, &last.pose, tol).is_none()
            {
                return Some(CcNode {
                    frame,
                    tip,
                    axis,
                    side_step_mm: None,
                    scallop_mm: None,
                    adjusted: None,
                    lead_out: true,
                    ..*last
                });
            }
            d *= 0.5;
        }
        None
    }
}
