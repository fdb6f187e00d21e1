//! CL data of one path as a seed-002 design path, so the five-axis machines and the step
//! selection of [`crate::fiveaxis`] turn it into joint values and a program.
//!
//! Between two CC nodes the design is the cutter placed at the CC point interpolated
//! linearly in (u, v) with the orientation (α, ψ) and the feed interpolated linearly too —
//! what the orientation would be if computed there. The path parameter s is the cumulative
//! CC chord length (mm).
//!
//! A lead-in or lead-out node ([`CcNode::lead_out`]) is the first or last cutter moved along
//! its feed with the surface's continuation; between it and its CC node tip and axis are
//! interpolated linearly and the CC node's frame stands for the design.
//!
//! The step selection measures a ball at the point `tip + R·axis` with R =
//! [`DesignPath::ball_radius_mm`]; a fillet-end mill is no ball, so this path reports a ball
//! radius 0 (the measured point *is* the tool tip) and as the error of a swept tip p the
//! distance to the design tip at the same fraction of the segment, positive (overcut) when p
//! lies on the part's side of the design tip (`(p − T)·n < 0`). The steps then keep the
//! swept tool tip within E of its design path (the nonlinear error of seed 002, here on the
//! tip of the fillet-end mill).

use glam::{DVec2, DVec3};

use super::contact::{ContactFrame, Pose, place};
use super::paths::CcNode;
use crate::fiveaxis::{CutterLocation, DesignPath, FiveAxisError, Machine, StepOptions, StepPlan, plan_steps};
use crate::geom::{Cutter, Surface};

/// One path's CL data as a design path (module docs).
#[derive(Clone, Debug)]
pub struct FilletDesignPath<'a> {
    surface: &'a Surface,
    cutter: Cutter,
    nodes: &'a [CcNode],
    cum: Vec<f64>,
}

impl<'a> FilletDesignPath<'a> {
    /// The design path through `nodes` (at least two) cut by `cutter` on `surface`.
    #[must_use]
    pub fn new(surface: &'a Surface, cutter: Cutter, nodes: &'a [CcNode]) -> Option<Self> {
        if nodes.len() < 2 {
            return None;
        }
        let mut cum = vec![0.0];
        for w in nodes.windows(2) {
            let l = cum.last().copied().unwrap_or(0.0) + (w[1].frame.point - w[0].frame.point).length();
            cum.push(l);
        }
        Some(Self { surface, cutter, nodes, cum })
    }

    fn segment(&self, s: f64) -> (usize, f64) {
        let k = self.cum.partition_point(|&c| c <= s).clamp(1, self.cum.len() - 1);
        let (c0, c1) = (self.cum[k - 1], self.cum[k]);
        (k, if c1 > c0 { ((s - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.0 })
    }

    fn design_at(&self, s: f64) -> Option<(ContactFrame, DVec3, DVec3)> {
        let (k, t) = self.segment(s);
        let (a, b) = (&self.nodes[k - 1], &self.nodes[k]);
        if t <= 0.0 {
            return Some((a.frame, a.tip, a.axis));
        }
        if t >= 1.0 {
            return Some((b.frame, b.tip, b.axis));
        }
        if a.lead_out || b.lead_out {
            // A lead-in or lead-out: the first or last cutter moved along its feed with the
            // surface's continuation (the axis turned with it), tip and axis linearly as the
            // machine moves between CL rows.
            let cc = if a.lead_out { b } else { a };
            return Some((cc.frame, a.tip.lerp(b.tip, t), a.axis.lerp(b.axis, t).normalize()));
        }
        let uv: DVec2 = a.frame.uv.lerp(b.frame.uv, t);
        let feed = a.frame.feed.lerp(b.frame.feed, t);
        let frame = ContactFrame::new(self.surface, uv, feed)?;
        let pose = Pose {
            inclination_rad: a.pose.inclination_rad + t * (b.pose.inclination_rad - a.pose.inclination_rad),
            azimuth_rad: a.pose.azimuth_rad + t * (b.pose.azimuth_rad - a.pose.azimuth_rad),
        };
        let (tip, axis) = place(&self.cutter, &frame, &pose);
        Some((frame, tip, axis))
    }
}

impl DesignPath for FilletDesignPath<'_> {
    fn range(&self) -> (f64, f64) {
        (0.0, self.cum.last().copied().unwrap_or(0.0))
    }
    fn ball_radius_mm(&self) -> f64 {
        0.0
    }
    fn effective_radius_mm(&self) -> f64 {
        0.0
    }
    fn surface_count(&self) -> usize {
        1
    }
    fn location_at(&self, s: f64) -> Result<CutterLocation, FiveAxisError> {
        let (frame, tip, axis) = self.design_at(s).ok_or(FiveAxisError::Crease { s })?;
        Ok(CutterLocation {
            s,
            centre: tip,
            axis,
            tip,
            normals: [frame.normal, frame.normal],
            travel: frame.feed,
            hints: [frame.uv, frame.uv],
        })
    }
    fn surface_errors(&self, p: DVec3, a: &CutterLocation, b: &CutterLocation, tau: f64) -> [Option<f64>; 2] {
        let s = a.s + tau * (b.s - a.s);
        let e = self.design_at(s).map_or(f64::NAN, |(frame, tip, _)| {
            let d = p - tip;
            if d.dot(frame.normal) < 0.0 { d.length() } else { -d.length() }
        });
        [Some(e), None]
    }
    fn first_step(&self, s: f64, _tol_mm: f64) -> Option<f64> {
        let (k, _) = self.segment(s);
        Some(self.cum[k] - self.cum[k - 1]).filter(|l| *l > 0.0)
    }
}

/// The seed-002 step plan of one path on `machine` within `tol_mm` (the paper's modified
/// secant; bisection where it stalls).
///
/// # Errors
/// As [`plan_steps`]; a path of fewer than two nodes is an empty path.
pub fn plan_path(
    machine: &Machine,
    surface: &Surface,
    cutter: &Cutter,
    nodes: &[CcNode],
    tol_mm: f64,
) -> Result<StepPlan, FiveAxisError> {
    let path =
        FilletDesignPath::new(surface, *cutter, nodes).ok_or(FiveAxisError::EmptyPath { start: 0.0, end: 0.0 })?;
    let mut opts = StepOptions::new(tol_mm);
    opts.reports = false;
    match plan_steps(machine, &path, &opts) {
        // The design is only piecewise smooth (linear between CC nodes): where the secant
        // stalls at a kink, bisection still brackets the step.
        Err(FiveAxisError::NoConvergence { .. }) => {
            plan_steps(machine, &path, &opts.with_method(crate::numerics::roots::RootMethod::Bisection))
        }
        other => other,
    }
}
