//! Where the paths start and which way they run: the along parameter (the widest-strip rule), an edge or a curve as the first path, iso-curves.

use glam::DVec2;

use super::{Ctx, FeedDirection, FinishOptions, PathStart, a_of, b_of, make_uv};
use crate::fillet::FinishError;
use crate::fillet::contact::{ContactFrame, CrossProfile};
use crate::fillet::orient::{Strategy, pose_at};
use crate::geom::{Cutter, ParametricSurface, Surface};
use crate::numerics::limits::MAX_START_CURVE_POINTS;
use crate::numerics::tolerance::DOMAIN_SLACK;

impl PathStart {
    /// The parameter the paths run along (0 = u, 1 = v): the edge's, the curve's
    /// ([`curve_along`]), or for the first boundary [`choose_along`].
    #[must_use]
    pub fn along(&self, surface: &Surface, cutter: &Cutter, strategy: &Strategy, opts: &FinishOptions) -> usize {
        match self {
            Self::FirstBoundary => choose_along(surface, cutter, strategy, opts),
            Self::Boundary(e) => e.along(),
            Self::Curve(pts) => curve_along(surface, pts, opts.direction),
        }
    }
}

/// The parameter a start curve's paths run along: the one `direction` names, or for
/// [`FeedDirection::Auto`] the one in which the points span the larger share of the domain
/// (u on a tie).
#[must_use]
pub fn curve_along(surface: &Surface, pts: &[DVec2], direction: FeedDirection) -> usize {
    match direction {
        FeedDirection::U => 0,
        FeedDirection::V => 1,
        FeedDirection::Auto => {
            let d = surface.domain();
            let share = |get: fn(DVec2) -> f64, width: f64| {
                let (lo, hi) = pts
                    .iter()
                    .map(|&p| get(p))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
                if hi > lo && width > 0.0 { (hi - lo) / width } else { 0.0 }
            };
            usize::from(share(|p| p.y, d.v.width()) > share(|p| p.x, d.u.width()))
        }
    }
}

/// The start curve as the first path's uv polyline for paths along `along`: checked (at
/// least 2 points, finite, inside the domain, at most [`MAX_START_CURVE_POINTS`]), sorted
/// by the along parameter a (points no further along than the previous one dropped),
/// each segment divided into pieces of at most 1/64 of the a-range, and extended at
/// constant b to both a-boundaries.
///
/// # Errors
/// [`FinishError::BadStart`] naming the problem.
pub fn start_polyline(surface: &Surface, pts: &[DVec2], along: usize) -> Result<Vec<DVec2>, FinishError> {
    let bad = |reason: String| Err(FinishError::BadStart { reason });
    if pts.len() < 2 {
        return bad(format!("the start curve needs at least 2 points, got {}", pts.len()));
    }
    if pts.len() > MAX_START_CURVE_POINTS {
        return bad(format!("the start curve has {} points, more than {MAX_START_CURVE_POINTS}", pts.len()));
    }
    let dom = surface.domain();
    for (i, p) in pts.iter().enumerate() {
        if !(p.is_finite() && dom.contains(*p)) {
            let f = dom.to_file(*p);
            return bad(format!("point {i} of the start curve, ({}, {}), is outside the surface's domain", f.x, f.y));
        }
    }
    let ra = if along == 0 { dom.u } else { dom.v };
    let (a0, a1) = (ra.min, ra.max);
    let mut sorted: Vec<DVec2> = pts.iter().map(|&p| dom.clamp(p)).collect();
    sorted.sort_by(|p, q| a_of(*p, along).total_cmp(&a_of(*q, along)));
    let slack = DOMAIN_SLACK * (a1 - a0).max(1.0);
    let mut kept: Vec<DVec2> = Vec::with_capacity(sorted.len());
    for p in sorted {
        if kept.last().is_none_or(|q| a_of(p, along) > a_of(*q, along) + slack) {
            kept.push(p);
        }
    }
    let name = if along == 0 { 'u' } else { 'v' };
    let (Some(&first), Some(&last)) = (kept.first(), kept.last()) else {
        return bad("the start curve has no points".to_owned());
    };
    if kept.len() < 2 {
        return bad(format!("the start curve's points all have the same {name}; the paths run along {name}"));
    }
    let mut poly = Vec::with_capacity(kept.len() * 4 + 2);
    if a_of(first, along) > a0 + slack {
        poly.push(make_uv(a0, b_of(first, along), along));
    }
    poly.push(first);
    for w in kept.windows(2) {
        let share = (a_of(w[1], along) - a_of(w[0], along)) / (a1 - a0);
        let pieces = (share * START_CURVE_PIECES).ceil().clamp(1.0, START_CURVE_PIECES) as usize;
        for k in 1..=pieces {
            poly.push(w[0].lerp(w[1], k as f64 / pieces as f64));
        }
    }
    if a_of(last, along) < a1 - slack {
        poly.push(make_uv(a1, b_of(last, along), along));
    }
    Ok(poly)
}

/// Pieces of a start curve's segment spanning the whole a-range (as [`iso_curve`]'s 64).
pub(super) const START_CURVE_PIECES: f64 = 64.0;

/// A dense polyline of the iso-curve b = const (64 segments).
pub(super) fn iso_curve(a_range: (f64, f64), b: f64, along: usize) -> Vec<DVec2> {
    (0..=64).map(|i| make_uv(a_range.0 + (a_range.1 - a_range.0) * f64::from(i) / 64.0, b, along)).collect()
}

/// Mean strip width (mm) over a 3 × 3 grid with paths along parameter `along`.
pub(super) fn mean_strip(
    surface: &Surface,
    cutter: &Cutter,
    strategy: &Strategy,
    opts: &FinishOptions,
    along: usize,
) -> f64 {
    let d = surface.domain();
    let tool = strategy.cutter_for(cutter);
    let oo = &opts.orient;
    let mut sum = 0.0;
    let mut count = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let uv = DVec2::new(
                d.u.min + d.u.width() * (0.2 + 0.3 * f64::from(i)),
                d.v.min + d.v.width() * (0.2 + 0.3 * f64::from(j)),
            );
            let der = surface.derivatives_at(uv);
            let dir = if along == 0 { der.du } else { der.dv };
            let Some(frame) = ContactFrame::new(surface, uv, dir) else { continue };
            let Some((pose, _)) = pose_at(strategy, cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))
            else {
                continue;
            };
            let prof = CrossProfile::new(&tool, surface, frame, &pose);
            sum += prof.reach(opts.scallop_mm, 1.0) + prof.reach(opts.scallop_mm, -1.0);
            count += 1.0;
        }
    }
    if count > 0.0 { sum / count } else { 0.0 }
}

/// The parameter (0 = u, 1 = v) the paths run along: as asked, or for
/// [`FeedDirection::Auto`] the one with the wider mean strip (the widest-strip rule applied
/// to the two families of iso-curves).
#[must_use]
pub fn choose_along(surface: &Surface, cutter: &Cutter, strategy: &Strategy, opts: &FinishOptions) -> usize {
    match opts.direction {
        FeedDirection::U => 0,
        FeedDirection::V => 1,
        FeedDirection::Auto => {
            let wu = mean_strip(surface, cutter, strategy, opts, 0);
            let wv = mean_strip(surface, cutter, strategy, opts, 1);
            usize::from(wv > wu)
        }
    }
}

/// The strip width (mm) at `uv` for every feed direction θ (rad, from r_u toward n × r_u) in
/// `steps` equal steps over [0°, 180°), with the strategy's orientation: the thesis' rule
/// picks the widest.
#[must_use]
pub fn strip_by_direction(
    surface: &Surface,
    cutter: &Cutter,
    strategy: &Strategy,
    opts: &FinishOptions,
    uv: DVec2,
    steps: usize,
) -> Vec<(f64, f64)> {
    let der = surface.derivatives_at(uv);
    let Some(base) = ContactFrame::new(surface, uv, der.du) else { return Vec::new() };
    let tool = strategy.cutter_for(cutter);
    let oo = &opts.orient;
    let steps = steps.clamp(2, 720);
    (0..steps)
        .filter_map(|i| {
            let theta = std::f64::consts::PI * i as f64 / steps as f64;
            let frame = ContactFrame::new(surface, uv, base.direction(theta))?;
            let (pose, _) = pose_at(strategy, cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))?;
            let prof = CrossProfile::new(&tool, surface, frame, &pose);
            Some((theta, prof.reach(opts.scallop_mm, 1.0) + prof.reach(opts.scallop_mm, -1.0)))
        })
        .collect()
}

impl Ctx<'_> {
    /// The first path's uv polyline for `start`: an edge's iso-curve or the start curve.
    pub(super) fn first_polyline(&self, start: &PathStart) -> Result<Vec<DVec2>, FinishError> {
        let ((a0, a1), (b0, b1)) = self.ranges();
        Ok(match start {
            PathStart::FirstBoundary => iso_curve((a0, a1), b0, self.along),
            PathStart::Boundary(e) => iso_curve((a0, a1), if e.at_max() { b1 } else { b0 }, self.along),
            PathStart::Curve(pts) => start_polyline(self.surface, pts, self.along)?,
        })
    }
}
