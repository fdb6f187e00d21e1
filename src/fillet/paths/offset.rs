//! The next path's curve: each node walked its side step across the surface, the curve cut at its swallowtails and at the along edges, its ends extended to them.

use glam::DVec2;

use super::side_step::Step;
use super::{Ctx, a_of, b_of, make_uv};
use crate::fillet::contact::ContactFrame;
use crate::fillet::node::CcNode;
use crate::geom::{LocalGeometry, ParametricSurface};

/// An offset curve ready to be built: its uv polyline and, per vertex, the azimuth window
/// (centre, half width; rad) the side step assumed there.
pub(super) type OffsetCurve = (Vec<DVec2>, Vec<(f64, f64)>);

/// A vertex of an offset curve: uv and the azimuth window (centre, half width; rad) the
/// side step assumed there.
pub(super) type Vertex = (DVec2, (f64, f64));

/// Most segments after a segment of an offset curve that [`trim_swallowtails`] tests it
/// against: bounds its work by this × the vertices (a swallowtail spans a few nodes).
pub(super) const SWALLOWTAIL_SEGMENTS: usize = 256;

/// Where segments p0p1 and q0q1 cross: the parameters (t, s) ∈ [0, 1)² along each, `None`
/// when they do not cross or are parallel.
pub(super) fn crossing(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Option<(f64, f64)> {
    let (r, d, w) = (p1 - p0, q1 - q0, q0 - p0);
    let den = r.perp_dot(d);
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let t = w.perp_dot(d) / den;
    let s = w.perp_dot(r) / den;
    ((0.0..1.0).contains(&t) && (0.0..1.0).contains(&s)).then_some((t, s))
}

/// A vertex between `a` and `b` at `t`: uv and azimuth interpolated, the wider window.
pub(super) fn vertex_between(a: &Vertex, b: &Vertex, t: f64) -> Vertex {
    (a.0.lerp(b.0, t), (a.1.0 + t * (b.1.0 - a.1.0), a.1.1.max(b.1.1)))
}

/// The offset curve with its swallowtails cut out: where segment i crosses a later segment
/// j (the farthest such j within [`SWALLOWTAIL_SEGMENTS`]), the loop between them is
/// replaced by the crossing point. Where the curve offsets a concave stretch of the last
/// path by more than its radius, it runs back over itself; the part of the loop beyond the
/// crossing lies inside the strip already cut. (Keeping only the vertices whose a increases,
/// as before, joined the loop's far branch to the near one across the crossing and left a
/// gap: the mould's 3.7·h, docs/fillet.md.)
pub(super) fn trim_swallowtails(pts: &[Vertex]) -> Vec<Vertex> {
    let n = pts.len();
    let Some(first) = pts.first() else { return Vec::new() };
    let mut work = pts.to_vec();
    let mut out = vec![*first];
    let mut i = 0;
    while i + 1 < n {
        let last = (i + SWALLOWTAIL_SEGMENTS).min(n - 2);
        let cut = (i + 2..=last)
            .rev()
            .find_map(|j| crossing(work[i].0, work[i + 1].0, work[j].0, work[j + 1].0).map(|(t, s)| (j, t, s)));
        if let Some((j, t, s)) = cut {
            let x = vertex_between(&work[i], &work[i + 1], t);
            let x = (x.0, vertex_between(&work[j], &work[j + 1], s).1);
            out.push(x);
            work[j] = x;
            i = j;
        } else {
            out.push(work[i + 1]);
            i += 1;
        }
    }
    out
}

/// The polyline cut to the along range [a0, a1]: vertices outside are left out, and where a
/// segment crosses an edge the crossing is put in (so a stretch that leaves and re-enters
/// becomes a straight piece between the two crossings).
pub(super) fn clip_along(pts: &[Vertex], (a0, a1): (f64, f64), along: usize) -> Vec<Vertex> {
    let inside = |v: &Vertex| (a0..=a1).contains(&a_of(v.0, along));
    let mut out = Vec::with_capacity(pts.len());
    for (k, v) in pts.iter().enumerate() {
        if k > 0 {
            let p = &pts[k - 1];
            let (ap, av) = (a_of(p.0, along), a_of(v.0, along));
            let mut cuts: Vec<f64> =
                [a0, a1].iter().filter(|&&e| (ap - e) * (av - e) < 0.0).map(|&e| (e - ap) / (av - ap)).collect();
            cuts.sort_by(f64::total_cmp);
            for t in cuts {
                let mut x = vertex_between(p, v, t);
                x.0 = make_uv((a_of(x.0, along)).clamp(a0, a1), b_of(x.0, along), along);
                out.push(x);
            }
        }
        if inside(v) {
            out.push(*v);
        }
    }
    out
}

/// The b at which the line from `other` through the end point `end` (uv) reaches the along
/// parameter `a`; `end`'s b when there is no other point or the line runs along b.
pub(super) fn extend_b(other: Option<DVec2>, end: DVec2, a: f64, along: usize) -> f64 {
    let Some(o) = other else { return b_of(end, along) };
    let da = a_of(end, along) - a_of(o, along);
    if da == 0.0 {
        return b_of(end, along);
    }
    b_of(end, along) + (a - a_of(end, along)) / da * (b_of(end, along) - b_of(o, along))
}

impl Ctx<'_> {
    /// The next path's uv polyline from the side steps `steps` of `nodes` (node index, step
    /// mm, reached the far edge, scallop solved): each node walked its step across, the curve
    /// cut at its self-intersections (swallowtails) and at the a-edges, what is left of a cusp
    /// (a vertex or two back along a without a crossing: where the offset's radius is just
    /// that of the stretch it offsets) dropped, so that no node's feed, and with it the next
    /// side step's direction, turns back; the ends extended to the a-boundaries along its end
    /// segments (a step along b = const would kink the path there, and the kink would grow
    /// path by path through the end nodes' cross directions), b kept inside its range. With
    /// each vertex its azimuth window. `None` when nothing is left.
    pub(super) fn offset_curve(&self, nodes: &[CcNode], steps: &[Step]) -> Option<OffsetCurve> {
        let along = self.along;
        let ((a0, a1), (b0, b1)) = self.ranges();
        let rate = self.opts.orient.max_turn_rad_per_mm;
        let mut offset: Vec<Vertex> = Vec::with_capacity(steps.len());
        for &Step { node: i, width_mm: w, .. } in steps {
            let node = nodes.get(i)?;
            let (uv, _) = self.walk(&node.frame, w);
            // The vertex with a as walked (the walk's own uv is clamped to the domain).
            let vertex =
                if a_of(uv, along) > a0 && a_of(uv, along) < a1 { uv } else { self.offset_vertex(&node.frame, w) };
            offset.push((vertex, (node.pose.azimuth_rad, rate * w)));
        }
        let mut offset = clip_along(&trim_swallowtails(&offset), (a0, a1), along);
        let mut a_last = f64::NEG_INFINITY;
        offset.retain(|v| {
            let keep = a_of(v.0, along) > a_last;
            if keep {
                a_last = a_of(v.0, along);
            }
            keep
        });
        let mut poly: Vec<DVec2> = offset.iter().map(|v| v.0).collect();
        let mut refs: Vec<(f64, f64)> = offset.iter().map(|v| v.1).collect();
        let (&f, &l) = (poly.first()?, poly.last()?);
        if a_of(f, along) > a0 {
            let b = extend_b(poly.get(1).copied(), f, a0, along).clamp(b0, b1);
            poly.insert(0, make_uv(a0, b, along));
            refs.insert(0, refs[0]);
        }
        if a_of(l, along) < a1 {
            let b = extend_b(poly.len().checked_sub(2).and_then(|i| poly.get(i)).copied(), l, a1, along).clamp(b0, b1);
            poly.push(make_uv(a1, b, along));
            refs.push(refs[refs.len() - 1]);
        }
        (poly.len() >= 2).then_some((poly, refs))
    }

    /// Walks `w_mm` across the surface from `frame` along ±c; returns the uv (clamped to the
    /// domain) and whether it reached or passed b's far end.
    pub(super) fn walk(&self, frame: &ContactFrame, w_mm: f64) -> (DVec2, bool) {
        let (uv, beyond) = self.walk_unclamped(frame, w_mm);
        (self.surface.domain().clamp(uv), beyond)
    }

    /// The next path's vertex from `node` at side step `w_mm`: b clamped to the domain (a
    /// point beyond the far edge is put on it), a as walked — possibly outside the a-range,
    /// where [`clip_along`] cuts the offset curve at the edge instead of running it along.
    pub(super) fn offset_vertex(&self, frame: &ContactFrame, w_mm: f64) -> DVec2 {
        let (raw, _) = self.walk_unclamped(frame, w_mm);
        let ((_, _), (b0, b1)) = self.ranges();
        make_uv(a_of(raw, self.along), b_of(raw, self.along).clamp(b0, b1), self.along)
    }

    /// [`Ctx::walk`] without the clamp.
    pub(super) fn walk_unclamped(&self, frame: &ContactFrame, w_mm: f64) -> (DVec2, bool) {
        let mut uv = frame.uv;
        let mut t = self.side * frame.cross;
        let sub = 4;
        for _ in 0..sub {
            let d = self.surface.derivatives_at(uv);
            let Some(g) = LocalGeometry::try_new(d) else { break };
            t = (t - t.dot(d.normal) * d.normal).normalize_or_zero();
            uv += g.tangent_coords(t) * (w_mm / sub as f64);
        }
        let ((_, _), (b0, b1)) = self.ranges();
        let b = b_of(uv, self.along);
        let beyond = if self.toward > 0.0 { b >= b1 } else { b <= b0 };
        (uv, beyond)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertices(pts: &[(f64, f64)]) -> Vec<Vertex> {
        pts.iter().enumerate().map(|(k, &(u, v))| (DVec2::new(u, v), (k as f64, 0.1))).collect()
    }

    /// Does any segment of the polyline cross a non-adjacent one? (brute force over all pairs)
    fn self_crossing(p: &[Vertex]) -> bool {
        (0..p.len().saturating_sub(1)).any(|i| {
            (i + 2..p.len().saturating_sub(1)).any(|j| crossing(p[i].0, p[i + 1].0, p[j].0, p[j + 1].0).is_some())
        })
    }

    #[test]
    fn a_swallowtail_is_cut_at_its_crossing() {
        // Along u, then a loop back over itself (the offset of a tight concave stretch), then
        // along again: segments 1-2 and 4-5 cross at (0.5, 0.1).
        let p = vertices(&[(0.0, 0.0), (0.4, 0.0), (0.7, 0.2), (0.6, 0.3), (0.3, 0.2), (0.7, 0.1), (1.0, 0.1)]);
        assert!(self_crossing(&p));
        let t = trim_swallowtails(&p);
        assert!(!self_crossing(&t), "{t:?}");
        // The loop's vertices are gone, the crossing replaces them, the ends are kept.
        let uv: Vec<DVec2> = t.iter().map(|v| v.0).collect();
        assert_eq!(uv.len(), 5, "{uv:?}");
        assert_eq!(uv[0], DVec2::new(0.0, 0.0));
        assert_eq!(uv[1], DVec2::new(0.4, 0.0));
        // Segment (0.4, 0) → (0.7, 0.2) meets (0.3, 0.2) → (0.7, 0.1) where both lines agree.
        let x = uv[2];
        let on_first = (x - DVec2::new(0.4, 0.0)).perp_dot(DVec2::new(0.3, 0.2));
        let on_second = (x - DVec2::new(0.3, 0.2)).perp_dot(DVec2::new(0.4, -0.1));
        assert!(on_first.abs() < 1e-12 && on_second.abs() < 1e-12, "{x}");
        assert_eq!(uv[3], DVec2::new(0.7, 0.1));
        assert_eq!(uv[4], DVec2::new(1.0, 0.1));
        // The crossing's azimuth window comes from the far branch (segment 4-5): between 4 and 5.
        assert!(t[2].1.0 > 4.0 && t[2].1.0 < 5.0, "{:?}", t[2]);
    }

    #[test]
    fn a_curve_without_crossings_is_left_as_it_is() {
        let p: Vec<Vertex> = (0..200)
            .map(|k| {
                let u = f64::from(k) / 199.0;
                (DVec2::new(u, 0.3 + 0.05 * (9.0 * u).sin()), (0.0, 0.1))
            })
            .collect();
        assert_eq!(trim_swallowtails(&p), p);
    }

    #[test]
    fn the_offset_is_cut_at_the_along_edges() {
        // Leaves through a = 0 on the left (as the mould's corner offsets do), runs inside,
        // leaves and re-enters through a = 1.
        let p = vertices(&[(-0.2, 0.1), (0.2, 0.3), (0.8, 0.3), (1.2, 0.5), (0.9, 0.7)]);
        for along in [0, 1] {
            let q: Vec<Vertex> =
                p.iter().map(|v| (if along == 0 { v.0 } else { DVec2::new(v.0.y, v.0.x) }, v.1)).collect();
            let c = clip_along(&q, (0.0, 1.0), along);
            let a: Vec<f64> = c.iter().map(|v| a_of(v.0, along)).collect();
            let b: Vec<f64> = c.iter().map(|v| b_of(v.0, along)).collect();
            assert_eq!(c.len(), 6, "{c:?}");
            // The entry through a = 0 at b = 0.2, the exit and re-entry through a = 1 at
            // b = 0.4 and b = 0.5 + 0.2·⅔ (linear along the segments).
            let want = [(0.0, 0.2), (0.2, 0.3), (0.8, 0.3), (1.0, 0.4), (1.0, 0.5 + 0.2 * 2.0 / 3.0), (0.9, 0.7)];
            for (k, &(wa, wb)) in want.iter().enumerate() {
                assert!((a[k] - wa).abs() < 1e-12 && (b[k] - wb).abs() < 1e-12, "{k}: {} {}", a[k], b[k]);
            }
        }
    }
}
