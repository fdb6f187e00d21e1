//! The iso-parametric paths at the same worst scallop, for comparison.

use super::{Ctx, FinishSetup, Layout, PathSet, a_of, iso_curve, make_uv};
use crate::fillet::FinishError;
use crate::fillet::contact::{ContactFrame, CrossProfile, scallop_between};
use crate::fillet::orient::pose_at;
use crate::geom::ParametricSurface;

/// Iso-parametric paths b = const at the same worst scallop h (module docs), along the
/// parameter the iso-scallop paths from `setup.start` run along ([`PathStart::along`](super::PathStart::along)), so
/// the two layouts compare on the same feed direction; they are the same b = const family
/// for every start. The spacing starts from the narrowest strip over a trial set of 9
/// iso-curves and is narrowed until the scallop solved at every node to the next path is at
/// most h (at most 8 rounds).
///
/// # Errors
/// As [`iso_scallop`](super::iso_scallop).
pub fn iso_parametric(setup: &FinishSetup) -> Result<PathSet, FinishError> {
    let FinishSetup { surface, cutter, strategy, options: opts, .. } = *setup;
    let ctx = Ctx::start(setup)?;
    let along = ctx.along;
    let ((a0, a1), (b0, b1)) = ctx.ranges();
    let tool = strategy.cutter_for(cutter);
    let h = opts.scallop_mm;
    ctx.refuse_oversized(&iso_curve((a0, a1), b0, along))?;
    let mut refused = Vec::new();
    let mut budget = opts.max_nodes;
    // The first guess of the spacing: the narrowest strip over 9 trial curves, in b.
    let mut db = f64::INFINITY;
    for k in 0..9 {
        let b = b0 + (b1 - b0) * f64::from(k) / 8.0;
        let mut scratch = Vec::new();
        let p = ctx.build_path(&iso_curve((a0, a1), b, along), None, &mut scratch, &mut budget)?;
        for n in &p.nodes {
            let d = surface.derivatives_at(n.frame.uv);
            let sb = if along == 0 { d.dv } else { d.du };
            let across = sb.dot(n.frame.cross).abs();
            if across > 0.0 {
                db = db.min(n.strip_mm / across);
            }
        }
    }
    if !db.is_finite() || db <= 0.0 {
        return Err(FinishError::NoPath { reason: "no strip width could be computed on the trial paths" });
    }
    let mut budget = opts.max_nodes;
    for _round in 0..8 {
        let count = (((b1 - b0) / db).ceil() as usize + 1).max(2);
        if count > opts.max_paths {
            return Err(FinishError::TooManyPaths { max_paths: opts.max_paths });
        }
        budget = opts.max_nodes;
        refused.clear();
        let mut paths = Vec::with_capacity(count);
        for k in 0..count {
            let b = b0 + (b1 - b0) * k as f64 / (count - 1) as f64;
            paths.push(ctx.build_path(&iso_curve((a0, a1), b, along), None, &mut refused, &mut budget)?);
        }
        let spacing = (b1 - b0) / (count - 1) as f64;
        let mut worst = 0.0f64;
        for k in 0..count - 1 {
            let b_next = b0 + (b1 - b0) * (k + 1) as f64 / (count - 1) as f64;
            for node in paths[k].nodes.iter_mut().filter(|n| !n.lead_out) {
                let uv_b = make_uv(a_of(node.frame.uv, along), b_next, along);
                let Some(fb) = ContactFrame::new(surface, uv_b, node.frame.feed) else { continue };
                let oo = &opts.orient;
                let psi = node.pose.azimuth_rad;
                let pose_b = pose_at(
                    &strategy,
                    cutter,
                    &fb,
                    oo,
                    ((psi - 0.5).max(-oo.max_azimuth_rad), (psi + 0.5).min(oo.max_azimuth_rad)),
                )
                .map_or(node.pose, |p| p.0);
                let w = (fb.point - node.frame.point).dot(node.frame.cross);
                let pa = CrossProfile::new(&tool, surface, node.frame, &node.pose);
                let pb = CrossProfile::new(&tool, surface, fb, &pose_b);
                let s = scallop_between(&pa, &pb, w);
                node.side_step_mm = Some(w.abs());
                node.scallop_mm = Some(s);
                worst = worst.max(s);
            }
        }
        if worst <= h * 1.0001 {
            return Ok(PathSet {
                paths,
                layout: Layout::IsoParametric,
                strategy,
                along,
                refused,
                second_side: None,
                scallop_flags: Vec::new(),
                corrector_stopped_at: None,
            });
        }
        db = spacing * (h / worst).sqrt() * 0.999;
    }
    let _ = budget;
    Err(FinishError::NoPath { reason: "the iso-parametric spacing did not settle in 8 rounds" })
}
