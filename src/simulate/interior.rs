//! The **interior band** of a finishing program: the rays between its first and last pass,
//! away from the passes' ends, where the scallop between two neighbouring passes is the
//! paths' own (their h) and not where the cutter leaves the part. Over the whole machined
//! patch the largest "scallop" sits at its edges (the bicubic patch's 551 µm against h = 40
//! µm), which reads as a failure; over the interior band it is the number the paths were
//! built for (docs/simulation.md, "Finishing programs … against their scallop height").
//!
//! The band, seen from above (x, y), from the passes' contact points in travel order:
//! - its outline is the first pass, the line through the passes' far ends, the last pass
//!   backwards and the line through their near ends (each pass's ends put in the first
//!   pass's direction, so zig-zag passes give the same outline);
//! - a ray is inside when it lies within that outline (even-odd rule), at least
//!   [`INTERIOR_SIDE_MM`] from the first and the last pass and at least [`INTERIOR_END_MM`]
//!   from the lines through the passes' ends.
//!
//! Work: one scanline crossing per outline edge and grid row, and for the distance margins
//! each segment's neighbourhood of rays (its box widened by the margin) — proportional to
//! the outline's length and the grid's rows, never to rays × edges.

use glam::{DVec2, DVec3};

use super::measure::{SimStats, Summary};
use super::stock::Grid;

/// Distance (mm) the interior band keeps from the lines through the passes' ends (where the
/// cutter enters and leaves the part).
pub const INTERIOR_END_MM: f64 = 1.0;
/// Distance (mm) the interior band keeps from the first and the last pass (beyond them only
/// one pass cuts).
pub const INTERIOR_SIDE_MM: f64 = 0.5;

/// The scallop statistics over the interior band.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InteriorStats {
    /// Rays of the band with a deviation (machined, over the design).
    pub rays: usize,
    /// The positive deviations (stock left) of those rays.
    pub scallop: Summary,
    /// Their most negative deviation (mm), if any ray of the band gouges.
    pub worst_gouge_mm: Option<f64>,
}

/// Which rays of `grid` lie in the interior band of `passes` (each pass's contact points in
/// travel order, mm; passes of fewer than two points are left out), row-major as the grid's
/// rays. All false for fewer than two passes.
#[must_use]
pub fn interior_mask(grid: &Grid, passes: &[Vec<DVec3>], end_mm: f64, side_mm: f64) -> Vec<bool> {
    let mut mask = vec![false; grid.len()];
    let paths: Vec<Vec<DVec2>> = passes
        .iter()
        .filter(|p| p.len() >= 2 && p.iter().all(|q| q.is_finite()))
        .map(|p| p.iter().map(|q| q.truncate()).collect())
        .collect();
    if paths.len() < 2 || grid.is_empty() {
        return mask;
    }
    // Each pass's ends in the first pass's direction.
    let mut oriented: Vec<Vec<DVec2>> = Vec::with_capacity(paths.len());
    for p in paths {
        let flip = oriented.last().is_some_and(|prev: &Vec<DVec2>| {
            let (a, b) = (prev[0], prev[prev.len() - 1]);
            let (c, d) = (p[0], p[p.len() - 1]);
            c.distance(a) + d.distance(b) > c.distance(b) + d.distance(a)
        });
        oriented.push(if flip { p.into_iter().rev().collect() } else { p });
    }
    let n = oriented.len();
    let starts: Vec<DVec2> = oriented.iter().map(|p| p[0]).collect();
    let ends: Vec<DVec2> = oriented.iter().map(|p| p[p.len() - 1]).collect();
    // The outline: first pass, far ends, last pass backwards, near ends back to the start.
    let mut outline: Vec<DVec2> = oriented[0].clone();
    outline.extend(&ends[1..n - 1]);
    outline.extend(oriented[n - 1].iter().rev());
    outline.extend(starts[1..n - 1].iter().rev());
    // Inside the outline, row by row (even-odd crossings at the rays' y).
    let mut xs = Vec::new();
    for j in 0..grid.ny {
        let y = grid.y_mm(j);
        xs.clear();
        for (k, a) in outline.iter().enumerate() {
            let b = outline[(k + 1) % outline.len()];
            if (a.y <= y) != (b.y <= y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            if let Some((i0, i1)) = grid.columns(pair[0], pair[1]) {
                mask[j * grid.nx + i0..=j * grid.nx + i1].fill(true);
            }
        }
    }
    // Margins: clear the rays near the first and last pass and the lines through the ends.
    for (line, margin) in [(&oriented[0], side_mm), (&oriented[n - 1], side_mm), (&starts, end_mm), (&ends, end_mm)] {
        clear_near(grid, line, margin, &mut mask);
    }
    mask
}

/// Clears the rays of `mask` within `margin_mm` of the polyline `line`.
fn clear_near(grid: &Grid, line: &[DVec2], margin_mm: f64, mask: &mut [bool]) {
    if !(margin_mm > 0.0) {
        return;
    }
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (lo, hi) = (a.min(b) - margin_mm, a.max(b) + margin_mm);
        let (Some((i0, i1)), Some((j0, j1))) = (grid.columns(lo.x, hi.x), grid.rows(lo.y, hi.y)) else { continue };
        for j in j0..=j1 {
            for i in i0..=i1 {
                let k = j * grid.nx + i;
                if mask[k] && distance_to_segment(DVec2::new(grid.x_mm(i), grid.y_mm(j)), a, b) < margin_mm {
                    mask[k] = false;
                }
            }
        }
    }
}

/// Distance (mm) from p to the segment ab.
#[must_use]
pub fn distance_to_segment(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + t * ab)
}

/// The statistics of `stats`' deviations over the rays `mask` marks (as [`SimStats`]'
/// scallop: the positive deviations, and the worst negative one).
#[must_use]
pub fn interior_stats(stats: &SimStats, mask: &[bool]) -> InteriorStats {
    let mut scallops = Vec::new();
    let mut worst: Option<f64> = None;
    let mut rays = 0;
    for (d, _) in stats.deviation_mm.iter().zip(mask).filter(|(_, m)| **m) {
        let Some(d) = *d else { continue };
        rays += 1;
        if d >= 0.0 {
            scallops.push(d);
        } else if worst.is_none_or(|w| d < w) {
            worst = Some(d);
        }
    }
    InteriorStats { rays, scallop: Summary::of(scallops), worst_gouge_mm: worst }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize, pitch: f64) -> Grid {
        Grid { x0_mm: -1.0, y0_mm: -1.0, pitch_mm: pitch, nx, ny }
    }

    /// The definition applied ray by ray: inside the outline by a ray cast, then the four
    /// distances to every segment.
    fn brute(g: &Grid, passes: &[Vec<DVec3>], end: f64, side: f64) -> Vec<bool> {
        let mut p: Vec<Vec<DVec2>> = passes.iter().map(|p| p.iter().map(|q| q.truncate()).collect()).collect();
        for k in 1..p.len() {
            let (a, b) = (p[k - 1][0], *p[k - 1].last().unwrap());
            let (c, d) = (p[k][0], *p[k].last().unwrap());
            if c.distance(a) + d.distance(b) > c.distance(b) + d.distance(a) {
                p[k].reverse();
            }
        }
        let n = p.len();
        let starts: Vec<DVec2> = p.iter().map(|q| q[0]).collect();
        let ends: Vec<DVec2> = p.iter().map(|q| *q.last().unwrap()).collect();
        let mut outline = p[0].clone();
        outline.extend(&ends[1..n - 1]);
        outline.extend(p[n - 1].iter().rev());
        outline.extend(starts[1..n - 1].iter().rev());
        let dist = |q: DVec2, l: &[DVec2]| {
            l.windows(2).map(|w| distance_to_segment(q, w[0], w[1])).fold(f64::INFINITY, f64::min)
        };
        let mut out = vec![false; g.len()];
        for j in 0..g.ny {
            for i in 0..g.nx {
                let q = DVec2::new(g.x_mm(i), g.y_mm(j));
                let mut inside = false;
                for k in 0..outline.len() {
                    let (a, b) = (outline[k], outline[(k + 1) % outline.len()]);
                    if (a.y <= q.y) != (b.y <= q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                        inside = !inside;
                    }
                }
                out[j * g.nx + i] = inside
                    && dist(q, &p[0]) >= side
                    && dist(q, &p[n - 1]) >= side
                    && dist(q, &starts) >= end
                    && dist(q, &ends) >= end;
            }
        }
        out
    }

    #[test]
    fn straight_passes_give_the_closed_form_rectangle() {
        // Six passes along x from 0 to 7 mm, 1.2 mm apart, zig-zag.
        let passes: Vec<Vec<DVec3>> = (0..6)
            .map(|k| {
                let y = 1.2 * f64::from(k);
                let mut p: Vec<DVec3> = (0..=14).map(|i| DVec3::new(0.5 * f64::from(i), y, 3.0)).collect();
                if k % 2 == 1 {
                    p.reverse();
                }
                p
            })
            .collect();
        let g = grid(100, 90, 0.1);
        let mask = interior_mask(&g, &passes, INTERIOR_END_MM, INTERIOR_SIDE_MM);
        for j in 0..g.ny {
            for i in 0..g.nx {
                let (x, y) = (g.x_mm(i), g.y_mm(j));
                let want = (1.0..=6.0).contains(&x) && (0.5..=5.5).contains(&y);
                assert_eq!(mask[j * g.nx + i], want, "ray at ({x}, {y})");
            }
        }
    }

    #[test]
    fn wavy_passes_agree_with_the_definition_ray_by_ray() {
        // Passes of different lengths along a wave, their ends on slanted lines.
        let passes: Vec<Vec<DVec3>> = (0..7)
            .map(|k| {
                let k = f64::from(k);
                let (x0, x1) = (0.3 * k, 8.0 - 0.2 * k);
                let mut p: Vec<DVec3> = (0..=30)
                    .map(|i| {
                        let x = x0 + (x1 - x0) * f64::from(i) / 30.0;
                        DVec3::new(x, 0.9 * k + 0.3 * (x * 0.8 + k).sin(), 0.0)
                    })
                    .collect();
                if k as usize % 2 == 1 {
                    p.reverse();
                }
                p
            })
            .collect();
        let g = grid(110, 90, 0.1);
        let mask = interior_mask(&g, &passes, INTERIOR_END_MM, INTERIOR_SIDE_MM);
        let want = brute(&g, &passes, INTERIOR_END_MM, INTERIOR_SIDE_MM);
        let inside = want.iter().filter(|&&m| m).count();
        assert!(inside > 1000, "the band is not empty: {inside} rays");
        let differ: Vec<usize> = (0..g.len()).filter(|&k| mask[k] != want[k]).collect();
        assert!(differ.is_empty(), "{} rays differ, e.g. {:?}", differ.len(), &differ[..differ.len().min(5)]);
    }

    #[test]
    fn statistics_over_the_band_only() {
        let stats = SimStats {
            deviation_mm: vec![Some(0.5), Some(0.01), None, Some(-0.002), Some(0.02), Some(-0.3)],
            ..SimStats::default()
        };
        let mask = [false, true, true, true, true, false];
        let s = interior_stats(&stats, &mask);
        assert_eq!(s.rays, 3);
        assert_eq!(s.scallop.count, 2);
        assert_eq!(s.scallop.max_mm, 0.02);
        assert_eq!(s.worst_gouge_mm, Some(-0.002));
        assert_eq!(interior_mask(&grid(4, 4, 1.0), &[vec![DVec3::ZERO, DVec3::X]], 1.0, 0.5), vec![false; 16]);
    }
}
