//! The side step from a node to the next path, solved so the scallop between the two cutters is h, and the cusp measured once the next path is built.

use glam::DVec2;

use super::Ctx;
use crate::fillet::FinishError;
use crate::fillet::contact::{ContactFrame, CrossProfile, Pose, scallop_between};
use crate::fillet::gouge::adjust;
use crate::fillet::node::CcNode;
use crate::fillet::orient::pose_at;
use crate::fillet::sweep::{NearPath, cusp_between};
use crate::geom::Cutter;

/// Most rounds of the side-step correction, and its acceptance (relative to h).
pub(super) const SIDE_STEP_ROUNDS: usize = 12;

pub(super) const SIDE_STEP_REL: f64 = 0.005;

/// A measured scallop is floored at this fraction of the target height h before a side step
/// is scaled by √(h / scallop): a scallop of (almost) zero then widens the step by the
/// clamp's factor, not by infinity.
pub(super) const SCALLOP_FLOOR_REL: f64 = 1e-3;

/// A side step solved at a node.
#[derive(Clone, Copy, Debug)]
pub(super) struct Solved {
    /// The next path's point (clamped to the domain).
    pub(super) uv: DVec2,
    /// Whether the walk reached or passed the far edge.
    pub(super) beyond: bool,
    /// The side step (mm).
    pub(super) width_mm: f64,
    /// The scallop the cross profiles give at that step (mm; 0 where none was computed).
    pub(super) scallop_mm: f64,
}

/// A node's step to the next path, as the next path is built from it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Step {
    /// The node's index in its path.
    pub(super) node: usize,
    /// The side step (mm), as predicted, then as limited and corrected.
    pub(super) width_mm: f64,
    /// Whether it reached the far edge (no cusp to measure there).
    pub(super) beyond: bool,
    /// The scallop the prediction gave (mm).
    pub(super) predicted_mm: f64,
}

impl Ctx<'_> {
    /// The cusp measured between each node of `steps` (on `nodes`) and the path `next`
    /// built from them ([`cusp_between`]), `None` where it reached the far edge or `next`
    /// does not pass beside it.
    pub(super) fn measure_cusps(
        &self,
        tool: &Cutter,
        nodes: &[CcNode],
        next: &[CcNode],
        steps: &[Step],
    ) -> Vec<Option<f64>> {
        let next = NearPath::new(next);
        steps
            .iter()
            .map(|st| {
                if st.beyond {
                    return None;
                }
                self.part.cusps.add(1);
                cusp_between(tool, self.surface, nodes, st.node, &next, 2.0 * st.width_mm + tool.radius_mm).map(|c| c.0)
            })
            .collect()
    }

    /// The pose the next path's node at `frame_b`, `w_mm` across from `node`, will get: the
    /// strategy's within the azimuth window around the node's, α held within the turn rate
    /// of the node's, and (when `checked`) after the gouge checks; with whether the checks
    /// changed it.
    ///
    /// # Errors
    /// The job's checks over their limits ([`Self::check_meter`]).
    pub(super) fn next_pose(
        &self,
        node: &CcNode,
        frame_b: &ContactFrame,
        w_mm: f64,
        checked: bool,
    ) -> Result<(Pose, bool), FinishError> {
        let oo = &self.opts.orient;
        let psi = node.pose.azimuth_rad;
        let d = oo.max_turn_rad_per_mm * w_mm;
        let window = ((psi - d).max(-oo.max_azimuth_rad), (psi + d).min(oo.max_azimuth_rad));
        let pose_b = pose_at(&self.strategy, &self.cutter, frame_b, oo, window).map_or(node.pose, |p| p.0);
        let pose_b = Pose { inclination_rad: pose_b.inclination_rad.max(node.pose.inclination_rad - d), ..pose_b };
        if !checked {
            return Ok((pose_b, false));
        }
        let tool = self.strategy.cutter_for(&self.cutter);
        let verdict = adjust(&tool, self.surface, self.part, frame_b, pose_b, oo, self.opts.gouge_tol_mm, self.reach);
        self.check_meter()?;
        Ok(match verdict {
            Ok((p, adj)) => (p, adj.is_some()),
            Err(_) => (pose_b, false),
        })
    }

    /// Side step from `node` solved so the scallop is h; the uv of the next path's point,
    /// whether it lies on (or beyond) the far boundary, the step and the scallop. Solved
    /// first with the next poses unchecked (the gouge checks are the costly part); when the
    /// checks changed this node's pose and change the next one's at the solution, solved
    /// again with every trial pose checked.
    ///
    /// # Errors
    /// The job's checks over their limits ([`Self::check_meter`]).
    pub(super) fn side_step(&self, node: &CcNode) -> Result<Solved, FinishError> {
        let first = self.solve_side_step(node, false)?;
        let Solved { uv, beyond, width_mm: w, .. } = first;
        if beyond {
            return Ok(first);
        }
        // The prediction matters only where the checks act: where they left this node as it
        // was, the next one is taken unchecked too (its own checks run when its path is built,
        // so this affects the scallop's accuracy, never the gouge-freedom).
        if node.adjusted.is_none() {
            return Ok(first);
        }
        match ContactFrame::new(self.surface, uv, node.frame.feed) {
            Some(frame_b) if self.next_pose(node, &frame_b, w, true)?.1 => self.solve_side_step(node, true),
            _ => Ok(first),
        }
    }

    pub(super) fn solve_side_step(&self, node: &CcNode, checked: bool) -> Result<Solved, FinishError> {
        let h = self.opts.scallop_mm;
        let tool = self.strategy.cutter_for(&self.cutter);
        let a = CrossProfile::new(&tool, self.surface, node.frame, &node.pose);
        // No strip is wider than the cutter: the side step stays within (0, 2R].
        let w_max = 2.0 * tool.radius_mm;
        let mut w = (self.reach(&tool, node, self.side) * 2.0).min(w_max);
        // Bracket of w: scallop below h at `lo`, above at `hi`.
        let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
        let mut result = Solved { uv: node.frame.uv, beyond: true, width_mm: w, scallop_mm: 0.0 };
        for _ in 0..SIDE_STEP_ROUNDS {
            self.part.side_trials.add(1);
            let (uv, beyond) = self.walk(&node.frame, w);
            if beyond {
                return Ok(Solved { uv, beyond: true, width_mm: w, scallop_mm: 0.0 });
            }
            let Some((frame_b, cross_uv)) = ContactFrame::with_cross_uv(self.surface, uv, node.frame.feed) else {
                return Ok(Solved { uv, beyond, width_mm: w, scallop_mm: 0.0 });
            };
            let (pose_b, _) = self.next_pose(node, &frame_b, w, checked)?;
            let b = CrossProfile::with_cross_uv(&tool, self.surface, frame_b, &pose_b, Some(cross_uv));
            let s = scallop_between(&a, &b, self.side * w);
            result = Solved { uv, beyond, width_mm: w, scallop_mm: s };
            if (s - h).abs() < SIDE_STEP_REL * h {
                break;
            }
            if s < h {
                lo = lo.max(w);
            } else {
                hi = hi.min(w);
            }
            // h ∝ w² near the solution; the step is kept inside the bracket and within a
            // factor 2.
            let mut next = w * (h / s.max(SCALLOP_FLOOR_REL * h)).sqrt().clamp(0.5, 2.0);
            if next <= lo || next >= hi {
                next = if hi.is_finite() { 0.5 * (lo + hi) } else { 2.0 * lo.max(w) };
            }
            if next > w_max {
                next = w_max;
                if lo >= w_max {
                    break;
                }
            }
            w = next;
        }
        Ok(result)
    }
}
