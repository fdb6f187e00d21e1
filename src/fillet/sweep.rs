//! The cutter as a machine sweeps it between two CL rows — tip and axis interpolated
//! linearly, as a controller reads the rows — measured against the design surface: how deep
//! the surface reaches into the swept cutter between the rows (the gouge between poses), and
//! the material left between two neighbouring paths actually built (the cusp, against the
//! side step's prediction). `docs/fillet.md`, "Between the poses" and "The measured cusp".
//!
//! The cutter is its solid below the flute length: the corner ball of radius r swept over the
//! disc of radius R0 = R − r at height r above the tip, and up the flutes. A point's signed
//! depth in it is r minus its distance to that core.

use glam::{DVec2, DVec3};

use super::node::CcNode;
use crate::geom::{Cutter, ParametricSurface, Surface};

/// Signed depth (mm) of `p` inside the cutter at (`tip`, unit `axis`): positive inside,
/// minus the distance to the solid outside.
#[must_use]
pub fn depth_in_cutter(cutter: &Cutter, tip: DVec3, axis: DVec3, p: DVec3) -> f64 {
    let (r, r0) = (cutter.corner_radius_mm, cutter.torus_radius_mm());
    let w = p - tip;
    let z = w.dot(axis);
    let rho = (w - z * axis).length();
    let dz = if z < r {
        r - z
    } else if z > cutter.flute_length_mm {
        z - cutter.flute_length_mm
    } else {
        0.0
    };
    let dr = (rho - r0).max(0.0);
    // Millimetre lengths: no overflow for `hypot` to guard against, and this runs in the
    // innermost loop of the cusp measurement.
    r - (dz * dz + dr * dr).sqrt()
}

/// The swept pose at `t` ∈ [0, 1] between rows `a` and `b`: tip and axis interpolated
/// linearly (the axis renormalised), as the controller moves them.
#[must_use]
pub fn pose_between(a: &CcNode, b: &CcNode, t: f64) -> (DVec3, DVec3) {
    (a.tip.lerp(b.tip, t), a.axis.lerp(b.axis, t).try_normalize().unwrap_or(a.axis))
}

/// Golden-section rounds on a chord's parameter: the bracket shrinks to 0.618²⁴ ≈ 1e-5 of
/// the chord (a 1 mm chord: 10 nm, where the distance changes by far less than 1 nm).
const GOLDEN_ROUNDS: usize = 24;

/// Smallest distance (mm; negative: deepest inside) from `p` to the cutter swept along the
/// chord `a` → `b`: golden section on the chord's parameter (the distance from a point to a
/// convex body moved along a line is convex in the motion; the axis turns a fraction of a
/// degree over a chord), and the chord's ends.
#[must_use]
pub fn distance_to_chord(cutter: &Cutter, a: &CcNode, b: &CcNode, p: DVec3) -> f64 {
    let d = |t: f64| {
        let (tip, axis) = pose_between(a, b, t);
        -depth_in_cutter(cutter, tip, axis, p)
    };
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let (mut x1, mut x2) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
    let (mut f1, mut f2) = (d(x1), d(x2));
    for _ in 0..GOLDEN_ROUNDS {
        if f1 < f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - phi * (hi - lo);
            f1 = d(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + phi * (hi - lo);
            f2 = d(x2);
        }
    }
    f1.min(f2).min(d(0.0)).min(d(1.0))
}

/// Chords each side of a row that [`left_by_path`] sweeps: the cutter's lowest point at a
/// cross offset trails or leads its contact by a few tenths of a millimetre, rows lie up to
/// the max step apart.
pub const CHORDS_AROUND: usize = 3;

/// The material left at `p` (mm; negative: `p` inside the swept cutter) by a path's cutter
/// swept over the rows within [`CHORDS_AROUND`] of row `j` (lead-outs included: the
/// cutter travels them): the two chords either side of the row nearest `p`.
#[must_use]
pub fn left_by_path(cutter: &Cutter, nodes: &[CcNode], j: usize, p: DVec3) -> f64 {
    if nodes.len() < 2 {
        return nodes.first().map_or(f64::INFINITY, |n| -depth_in_cutter(cutter, n.tip, n.axis, p));
    }
    let first = j.saturating_sub(CHORDS_AROUND);
    let last = (j + CHORDS_AROUND + 1).min(nodes.len() - 1);
    // The row nearest `p` among them, then the two chords on either side of it: the swept
    // distance dips below the rows' only between neighbours of the nearest.
    let mut best = (f64::INFINITY, first);
    for (k, n) in nodes.iter().enumerate().take(last + 1).skip(first) {
        let d = -depth_in_cutter(cutter, n.tip, n.axis, p);
        if d < best.0 {
            best = (d, k);
        }
    }
    let k = best.1;
    let mut out = best.0;
    if k > 0 {
        out = out.min(distance_to_chord(cutter, &nodes[k - 1], &nodes[k], p));
    }
    if k + 1 < nodes.len() {
        out = out.min(distance_to_chord(cutter, &nodes[k], &nodes[k + 1], p));
    }
    out
}

/// Halvings of the compass search's step, from 0.25 mm to 0.25 mm / 2⁶ ≈ 4 µm: there the
/// depth, quadratic about its peak with a curvature of at most 1/r ≤ 10 /mm (r ≥ 0.1 mm),
/// is within 10 × (4 µm)²/2 = 0.08 nm of it.
const COMPASS_HALVINGS: usize = 6;
/// The compass search's first step on the surface (mm).
const COMPASS_FIRST_MM: f64 = 0.25;
/// Most moves of the compass search (each tries four neighbours).
const COMPASS_MOVES: usize = 200;

/// How deep (mm; negative: how far clear) the design surface reaches into the cutter at
/// (`tip`, `axis`) near the surface point of `uv`: a compass search over (u, v) from `uv`
/// for the surface point deepest in the cutter (steps from 0.25 mm on the surface, halved
/// to 4 µm), the parameters clamped to the surface's domain.
#[must_use]
pub fn surface_depth_near(cutter: &Cutter, surface: &Surface, tip: DVec3, axis: DVec3, uv: DVec2) -> f64 {
    let domain = surface.domain();
    // The point and first derivatives only (`tangents_at`: the same bits as
    // `derivatives_at`'s).
    let (point, du, dv) = surface.tangents_at(uv);
    let (lu, lv) = (du.length(), dv.length());
    if !(lu > 0.0 && lv > 0.0 && lu.is_finite() && lv.is_finite()) {
        return depth_in_cutter(cutter, tip, axis, point);
    }
    let depth = |uv: DVec2| depth_in_cutter(cutter, tip, axis, surface.point_at(uv));
    let bits = |uv: DVec2| [uv.x.to_bits(), uv.y.to_bits()];
    let mut at = domain.clamp(uv);
    let mut best = depth(at);
    // The point the last move left (bits): its depth is below `best`, so a trial landing on
    // it again would not be taken and is not evaluated again.
    let mut left: Option<[u64; 2]> = None;
    let mut step = COMPASS_FIRST_MM;
    let mut halvings = 0;
    let mut moves = 0;
    while halvings <= COMPASS_HALVINGS && moves < COMPASS_MOVES {
        let (su, sv) = (step / lu, step / lv);
        let mut moved = false;
        for delta in [DVec2::new(su, 0.0), DVec2::new(-su, 0.0), DVec2::new(0.0, sv), DVec2::new(0.0, -sv)] {
            let trial = domain.clamp(at + delta);
            if left == Some(bits(trial)) {
                continue;
            }
            let v = depth(trial);
            if v > best {
                left = Some(bits(at));
                best = v;
                at = trial;
                moved = true;
                break;
            }
        }
        moves += 1;
        if !moved {
            step *= 0.5;
            halvings += 1;
        }
    }
    best
}

/// Rounds of the cusp's root search (regula falsi, Illinois): the cusp's place to well
/// under a micrometre across a millimetre-wide strip.
const CUSP_ROUNDS: usize = 30;

/// The cusp's root search stops when its bracket spans less than this in (u, v) (parameter
/// units) or the two paths leave heights differing by less than this (mm): far below any
/// scallop worth measuring.
const CUSP_DONE: f64 = 1e-9;

/// A path's CC polyline prepared for nearest-point queries ([`cusp_between`]): its segments
/// (those between two CC points; lead-in and lead-out left out) in runs of about √n, each
/// run bounded by a sphere, so a query tests the spheres and then the segments of the runs
/// that can hold a nearer point — about √n tests a query instead of n, the answer the same
/// as a scan of every segment (ties to the lower segment index, as the scan's).
#[derive(Clone, Debug)]
pub struct NearPath<'a> {
    nodes: &'a [CcNode],
    /// Per run: the first and one past the last segment index, the centre and radius (mm).
    runs: Vec<(usize, usize, DVec3, f64)>,
    /// The uv of the path's first and last CC points.
    ends: Option<(DVec2, DVec2)>,
}

/// Fewest segments in a [`NearPath`] run.
const MIN_RUN: usize = 16;

/// A run's bounding sphere is widened by this fraction of its radius …
const RUN_WIDEN_REL: f64 = 1e-9;
/// … and this length (mm), so rounding never drops a run holding a point at exactly the
/// best distance found.
const RUN_WIDEN_MM: f64 = 1e-12;

impl<'a> NearPath<'a> {
    /// Prepares `nodes` (work and memory linear in their count).
    #[must_use]
    pub fn new(nodes: &'a [CcNode]) -> Self {
        let segments = nodes.len().saturating_sub(1);
        let run = MIN_RUN.max((segments as f64).sqrt().ceil() as usize);
        let mut runs = Vec::with_capacity(segments / run + 1);
        let mut k0 = 0;
        while k0 < segments {
            let k1 = (k0 + run).min(segments);
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for k in k0..k1 {
                let (a, b) = (&nodes[k], &nodes[k + 1]);
                if a.lead_out || b.lead_out {
                    continue;
                }
                lo = lo.min(a.frame.point).min(b.frame.point);
                hi = hi.max(a.frame.point).max(b.frame.point);
            }
            if lo.x <= hi.x {
                let centre = 0.5 * (lo + hi);
                // Widened by a part in 10⁹ so that rounding never drops a run holding a
                // point at exactly the best distance found (the scan's tie rule needs it).
                let radius = 0.5 * (hi - lo).length() * (1.0 + RUN_WIDEN_REL) + RUN_WIDEN_MM;
                runs.push((k0, k1, centre, radius));
            }
            k0 = k1;
        }
        let mut cc = nodes.iter().filter(|n| !n.lead_out);
        let ends = cc.next().map(|f| (f.frame.uv, cc.next_back().map_or(f.frame.uv, |l| l.frame.uv)));
        Self { nodes, runs, ends }
    }

    /// The point of the CC polyline nearest to `q` within `reach_mm`: its distance (mm), the
    /// index of the segment's first row and its uv.
    #[must_use]
    pub fn nearest(&self, q: DVec3, reach_mm: f64) -> Option<(f64, usize, DVec2)> {
        let mut best: Option<(f64, usize, DVec2)> = None;
        // The run whose sphere comes nearest first, so the bound prunes the rest.
        let lower = |r: &(usize, usize, DVec3, f64)| (r.2 - q).length() - r.3;
        let first = self.runs.iter().enumerate().min_by(|x, y| lower(x.1).total_cmp(&lower(y.1))).map(|(i, _)| i)?;
        let order = std::iter::once(first).chain((0..self.runs.len()).filter(|&i| i != first));
        for i in order {
            let run = &self.runs[i];
            let bound = lower(run);
            if bound > reach_mm || best.is_some_and(|b| bound > b.0) {
                continue;
            }
            for k in run.0..run.1 {
                let (a, b) = (&self.nodes[k], &self.nodes[k + 1]);
                if a.lead_out || b.lead_out {
                    continue;
                }
                let (p0, p1) = (a.frame.point, b.frame.point);
                let d = p1 - p0;
                let len2 = d.length_squared();
                let t = if len2 > 0.0 { ((q - p0).dot(d) / len2).clamp(0.0, 1.0) } else { 0.0 };
                let dist = (p0 + t * d - q).length();
                // Lengths are never −0 or NaN here (a NaN fails `dist <= reach_mm`), so the
                // total order is the usual one, ties to the lower index.
                let better = best.is_none_or(|b| dist.total_cmp(&b.0).then(k.cmp(&b.1)).is_lt());
                if dist <= reach_mm && better {
                    best = Some((dist, k, a.frame.uv.lerp(b.frame.uv, t)));
                }
            }
        }
        best
    }
}

/// The cusp between path `a`'s row `j` and path `b`: on the surface curve from `a`'s CC
/// point straight (in u, v) to the point of `b`'s CC polyline nearest to it, the point where the material left by the two swept cutters is equal —
/// the top of the ridge between them. Returns its height (mm) and the index of `b`'s row
/// before that point; `None` when `b` does not come within `reach_mm`, or the
/// ridge is not between the two (the paths overlap there).
#[must_use]
pub fn cusp_between(
    cutter: &Cutter,
    surface: &Surface,
    a: &[CcNode],
    j: usize,
    b: &NearPath<'_>,
    reach_mm: f64,
) -> Option<(f64, usize)> {
    let node = a.get(j)?;
    // The point of b's CC polyline nearest to the node (robust where a path turns: the plane
    // normal to a turned feed would meet b far off).
    let (_, k, uv_b) = b.nearest(node.frame.point, reach_mm)?;
    // Nearest at b's first or last CC point: b does not pass beside this node (it ends
    // before it, at an edge of the domain); there is no cusp between the two to measure.
    if b.ends.is_some_and(|(first, last)| uv_b == first || uv_b == last) {
        return None;
    }
    let b = b.nodes;
    let uv_a = node.frame.uv;
    let gap = |s: f64| -> (f64, f64) {
        let p = surface.point_at(uv_a.lerp(uv_b, s));
        (left_by_path(cutter, a, j, p), left_by_path(cutter, b, k, p))
    };
    let (la0, lb0) = gap(0.0);
    let (la1, lb1) = gap(1.0);
    let (mut s0, mut g0, mut s1, mut g1) = (0.0, la0 - lb0, 1.0, la1 - lb1);
    if !(g0 < 0.0 && g1 > 0.0) {
        return None;
    }
    let mut side = 0i8;
    let mut height = 0.0;
    for _ in 0..CUSP_ROUNDS {
        let s = (s0 * g1 - s1 * g0) / (g1 - g0);
        let (la, lb) = gap(s);
        height = la.max(lb);
        let g = la - lb;
        if g < 0.0 {
            s0 = s;
            g0 = g;
            if side == -1 {
                g1 *= 0.5;
            }
            side = -1;
        } else {
            s1 = s;
            g1 = g;
            if side == 1 {
                g0 *= 0.5;
            }
            side = 1;
        }
        if (s1 - s0) * (uv_b - uv_a).length() < CUSP_DONE || g.abs() < CUSP_DONE {
            break;
        }
    }
    Some((height, k))
}
