//! Replaying a program against the design path: how far the cutting moves stray from the
//! design curve and how far the design curve is from the cutting moves.
//!
//! The deviation is two-sided (Hausdorff-style), so a program that leaves the path and one
//! that stops short or skips a part are both caught:
//!
//! - program → design: every cutting move is sampled (per line, per arc, per NURBS knot
//!   span), the distance of each sample to the design curve found by a coarse nearest sample
//!   and Newton's foot point, and the worst sample of every piece refined by golden section;
//! - design → program: the design curve is sampled densely, each sample's distance to the
//!   program found the same way on the moves next to the nearest program sample, and every
//!   local maximum refined by golden section.
//!
//! Rapid moves (G00) are positioning, not part of the cut, and are left out.

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec3;
use thiserror::Error;

use super::path::{Motion, PathBlock, Segment, Toolpath, push_sample_params, sample_params, segment_length};
use crate::geom::Curve3;
use crate::numerics::maximise::max_on_interval;
use crate::numerics::measure::{ArcLengthTable, nearest_on_curve};

/// Options of [`deviation`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviationOptions {
    /// Samples per program piece (line, arc, NURBS knot span) before refinement (default 16).
    pub samples_per_piece: usize,
    /// Golden-section refinements of each worst sample (default 16: the peak to 1e-3 of the
    /// sample spacing, its value far below the output resolution).
    pub refine: usize,
    /// Spacing of the design-curve samples (mm, default 0.2).
    pub design_spacing_mm: f64,
}

impl Default for DeviationOptions {
    fn default() -> Self {
        Self { samples_per_piece: 16, refine: 16, design_spacing_mm: 0.2 }
    }
}

/// Why a program could not be compared.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ReplayError {
    /// No cutting moves.
    #[error("the program has no cutting moves (G01, G02, G03 or G06.2) to compare with the design path")]
    NoCuts,
    /// Empty design curve.
    #[error("the design curve has no length")]
    EmptyDesign,
}

/// The two-sided deviation of a program from a design curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    /// Largest distance from a point of the cutting moves to the design curve (mm).
    pub program_to_design_mm: f64,
    /// Where it occurs on the program (mm).
    pub program_point: DVec3,
    /// The program line of that move.
    pub program_line: usize,
    /// Largest distance from a point of the design curve to the cutting moves (mm).
    pub design_to_program_mm: f64,
    /// Where it occurs on the design curve (mm).
    pub design_point: DVec3,
    /// Arc length along the design curve of that point (mm).
    pub design_s_mm: f64,
    /// Distance between the first cutting point and the design start (mm).
    pub start_gap_mm: f64,
    /// Distance between the last cutting point and the design end (mm).
    pub end_gap_mm: f64,
    /// Length of the design curve (mm).
    pub design_length_mm: f64,
    /// Spacing of the samples actually taken (mm): the requested one, or coarser when the
    /// program and design are too long for [`crate::numerics::limits::MAX_REPLAY_SAMPLES`]; a peak
    /// between samples is then missed by at most half of it before refinement.
    pub sample_spacing_mm: f64,
}

impl Deviation {
    /// The larger of the two directions (mm).
    #[must_use]
    pub fn max_mm(&self) -> f64 {
        self.program_to_design_mm.max(self.design_to_program_mm)
    }
}

/// Samples of a curve with their parameters, for nearest-sample searches.
struct Cloud {
    pts: Vec<DVec3>,
    /// (owner block, parameter, window low, window high): the window spans the neighbouring
    /// samples of the same owner, where the foot point of a near point must lie.
    at: Vec<(usize, f64, f64, f64)>,
    /// Largest distance between consecutive samples (mm).
    spacing: f64,
    grid: Grid,
    /// The nearest sample of the last whole-cloud search: the next one (a query near the
    /// last) starts from it, so the blocks farther than it are skipped at once.
    hint: std::cell::Cell<usize>,
}

/// Points bucketed in cubic cells: the point indices sorted by cell, and a map from a cell to
/// its run in that list. Lookups only (never iterated), so results do not depend on the
/// map's order.
struct Grid {
    cell: f64,
    order: Vec<usize>,
    /// Cell key (the three cell indices mixed into one word; two cells sharing a key only
    /// merge their candidates, which are then measured anyway) → run in `order`.
    runs: HashMap<u64, (usize, usize), BuildHasherDefault<CellHasher>>,
    /// Every run of `order` (one cell, in key order) with the box of its points, grouped in
    /// blocks of [`BOX_GROUP`] runs with the box of the block: a scan of the whole cloud
    /// skips the blocks and cells whose box is farther than the best point found.
    boxes: Vec<(usize, usize, DVec3, DVec3)>,
    groups: Vec<(usize, usize, DVec3, DVec3)>,
    /// The groups, grouped again the same way.
    tops: Vec<(usize, usize, DVec3, DVec3)>,
}

/// Program samples past which coincident ones are merged ([`deviation`]).
const DEDUPE_AFTER: usize = 65_536;

/// Past [`DEDUPE_AFTER`] samples, samples in the same cell of this fraction of the sample
/// spacing are one position …
const DEDUPE_CELL_REL: f64 = 1e-3;
/// … the cell at least this wide (mm).
const DEDUPE_CELL_MIN_MM: f64 = 1e-9;

/// Cells per block of the whole-cloud scan ([`Grid::within`]).
const BOX_GROUP: usize = 32;

/// A small multiplicative hasher for cell keys (deterministic, no random seed).
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_i64(&mut self, i: i64) {
        self.write_u64(i as u64);
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
}

impl Grid {
    fn key(&self, p: DVec3) -> [i64; 3] {
        let c = (p / self.cell).floor();
        [c.x as i64, c.y as i64, c.z as i64]
    }

    fn word(k: [i64; 3]) -> u64 {
        (k[0] as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (k[1] as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            ^ (k[2] as u64).wrapping_mul(0x1656_67B1_9E37_79F9)
    }

    fn new(pts: &[DVec3], cell: f64) -> Self {
        let mut g = Self {
            cell,
            order: Vec::with_capacity(pts.len()),
            runs: HashMap::default(),
            boxes: Vec::new(),
            groups: Vec::new(),
            tops: Vec::new(),
        };
        let mut keyed: Vec<(u64, usize)> = pts.iter().enumerate().map(|(i, p)| (Self::word(g.key(*p)), i)).collect();
        keyed.sort_unstable();
        let mut start = 0;
        for (n, (k, i)) in keyed.iter().enumerate() {
            g.order.push(*i);
            if n + 1 == keyed.len() || keyed[n + 1].0 != *k {
                g.runs.insert(*k, (start, n + 1));
                let (lo, hi) = g.order[start..=n]
                    .iter()
                    .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| (lo.min(pts[i]), hi.max(pts[i])));
                g.boxes.push((start, n + 1, lo, hi));
                start = n + 1;
            }
        }
        g.groups = Self::group(&g.boxes);
        g.tops = Self::group(&g.groups);
        g
    }

    /// Calls `f` for every point of the cells whose box lies within `reach()` of `x` (asked
    /// again before each block and cell: it may shrink as `f` finds nearer points). Boxes
    /// strictly farther are skipped, so a search for the nearest point finds the one a scan
    /// of every point would.
    fn within(&self, x: DVec3, reach: &dyn Fn() -> f64, f: &mut dyn FnMut(usize)) {
        let gap = |lo: DVec3, hi: DVec3| (lo - x).max(x - hi).max(DVec3::ZERO).length();
        for &(ta, tb, tlo, thi) in &self.tops {
            if gap(tlo, thi) > reach() {
                continue;
            }
            for &(ga, gb, glo, ghi) in &self.groups[ta..tb] {
                if gap(glo, ghi) > reach() {
                    continue;
                }
                for &(a, b, lo, hi) in &self.boxes[ga..gb] {
                    if gap(lo, hi) > reach() {
                        continue;
                    }
                    for &i in &self.order[a..b] {
                        f(i);
                    }
                }
            }
        }
    }

    /// Runs of [`BOX_GROUP`] boxes with the box around each run.
    fn group(boxes: &[(usize, usize, DVec3, DVec3)]) -> Vec<(usize, usize, DVec3, DVec3)> {
        boxes
            .chunks(BOX_GROUP)
            .enumerate()
            .map(|(k, chunk)| {
                let (lo, hi) =
                    chunk.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), b| (lo.min(b.2), hi.max(b.3)));
                (k * BOX_GROUP, k * BOX_GROUP + chunk.len(), lo, hi)
            })
            .collect()
    }

    /// Indices of the points in one cell.
    fn cell_items(&self, k: [i64; 3]) -> &[usize] {
        match self.runs.get(&Self::word(k)) {
            Some(&(a, b)) => &self.order[a..b],
            None => &[],
        }
    }

    /// Calls `f` for every point in the cells at Chebyshev ring distance `r` from `c`.
    fn ring(&self, c: [i64; 3], r: i64, f: &mut dyn FnMut(usize)) {
        for dx in -r..=r {
            for dy in -r..=r {
                let edge = dx.abs() == r || dy.abs() == r;
                let step = if edge || r == 0 { 1 } else { 2 * r };
                let mut dz = -r;
                while dz <= r {
                    for &i in self.cell_items([c[0] + dx, c[1] + dy, c[2] + dz]) {
                        f(i);
                    }
                    dz += step.max(1);
                }
            }
        }
    }
}

impl Cloud {
    fn from_samples(samples: Vec<(usize, f64, DVec3)>) -> Self {
        let n = samples.len();
        let mut pts = Vec::with_capacity(n);
        let mut at = Vec::with_capacity(n);
        let mut spacing = 0.0_f64;
        for i in 0..n {
            let (b, t, p) = samples[i];
            let lo = if i > 0 && samples[i - 1].0 == b { samples[i - 1].1 } else { t };
            let hi = if i + 1 < n && samples[i + 1].0 == b { samples[i + 1].1 } else { t };
            if i > 0 {
                spacing = spacing.max((p - samples[i - 1].2).length());
            }
            pts.push(p);
            at.push((b, t, lo, hi));
        }
        let cell = (2.0 * spacing).max(crate::numerics::tolerance::REPLAY_MIN_SPACING_MM);
        let grid = Grid::new(&pts, cell);
        Self { pts, at, spacing, grid, hint: std::cell::Cell::new(0) }
    }

    /// The nearest sample, and the nearest one more than `sep` samples away from it (another
    /// branch of the curve, e.g. the other end of a closed loop) if it is within one sample
    /// spacing of the nearest distance. Ties go to the lower index.
    fn nearest_two(&self, x: DVec3, sep: usize) -> (usize, Option<usize>) {
        const MAX_RINGS: i64 = 6;
        let c = self.grid.key(x);
        let better = |d: f64, i: usize, best: (f64, usize)| match d.total_cmp(&best.0) {
            std::cmp::Ordering::Less => true,
            std::cmp::Ordering::Equal => i < best.1,
            std::cmp::Ordering::Greater => false,
        };
        let mut best = (f64::INFINITY, usize::MAX);
        let mut rings = 0i64;
        // Far from the last search's nearest sample, the rings (hundreds of cells) are
        // likely empty: the whole-cloud search below, pruned by its boxes, is exact and
        // cheaper. Near it, the rings as usual.
        let far =
            self.pts.get(self.hint.get()).is_some_and(|p| (*p - x).length() > (MAX_RINGS as f64) * self.grid.cell);
        if far {
            rings = MAX_RINGS + 1;
        } else {
            loop {
                self.grid.ring(c, rings, &mut |i| {
                    let d = (self.pts[i] - x).length();
                    if better(d, i, best) {
                        best = (d, i);
                    }
                });
                // Unscanned cells are at least rings·cell away.
                if best.1 != usize::MAX && (rings as f64) * self.grid.cell > best.0 + self.spacing {
                    break;
                }
                rings += 1;
                if rings > MAX_RINGS {
                    break;
                }
            }
        }
        let scan_all = far
            || best.1 == usize::MAX
            || (rings > MAX_RINGS && (MAX_RINGS as f64) * self.grid.cell <= best.0 + self.spacing);
        let limit;
        let mut second = (f64::INFINITY, usize::MAX);
        if scan_all {
            // Far from the cloud: the cells whose box can hold a sample no farther than the
            // best so far (starting from the last search's nearest) — the samples a scan of
            // every one would pick.
            let h = self.hint.get().min(self.pts.len().saturating_sub(1));
            let found =
                std::cell::Cell::new(self.pts.get(h).map_or((f64::INFINITY, usize::MAX), |p| ((*p - x).length(), h)));
            self.grid.within(x, &|| found.get().0, &mut |i| {
                let d = (self.pts[i] - x).length();
                if better(d, i, found.get()) {
                    found.set((d, i));
                }
            });
            best = found.get();
            self.hint.set(best.1);
            limit = best.0 + self.spacing;
            let near = std::cell::Cell::new(second);
            self.grid.within(x, &|| limit, &mut |i| {
                let d = (self.pts[i] - x).length();
                if i.abs_diff(best.1) > sep && d <= limit && better(d, i, near.get()) {
                    near.set((d, i));
                }
            });
            second = near.get();
        } else {
            limit = best.0 + self.spacing;
            for r in 0..=rings.min(MAX_RINGS) {
                self.grid.ring(c, r, &mut |i| {
                    let d = (self.pts[i] - x).length();
                    if i.abs_diff(best.1) > sep && d <= limit && better(d, i, second) {
                        second = (d, i);
                    }
                });
            }
        }
        if best.1 != usize::MAX {
            self.hint.set(best.1);
        }
        (best.1, (second.1 != usize::MAX).then_some(second.1))
    }
}

/// Samples of one curve (owner 0) at `n + 1` parameters equally spaced in arc length.
fn design_cloud(design: &dyn Curve3, table: &ArcLengthTable, n: usize) -> Cloud {
    let (ta, tb) = design.range();
    let length = table.length();
    let samples = (0..=n)
        .map(|i| {
            let t = if i == 0 {
                ta
            } else if i == n {
                tb
            } else {
                table.t_at(design, length * i as f64 / n as f64)
            };
            (0, t, design.point_at(t))
        })
        .collect();
    Cloud::from_samples(samples)
}

/// Distance from x to a curve sampled by `cloud`: foot points by Newton inside the windows
/// of the nearest sample and its two neighbours (which may belong to the next or previous
/// move, so junctions are covered), and of the nearest sample of another branch; the
/// smallest counts.
fn distance_via<'c>(cloud: &Cloud, curve_of: &dyn Fn(usize) -> &'c dyn Curve3, x: DVec3) -> f64 {
    let (i, j) = cloud.nearest_two(x, 20);
    let mut best = f64::INFINITY;
    for k in std::iter::once(i).chain(j) {
        // The sample's own window spans both neighbours of the same move; a neighbour of
        // another move (across a junction) brings that move's window.
        for m in k.saturating_sub(1)..=(k + 1).min(cloud.at.len() - 1) {
            if m != k && cloud.at[m].0 == cloud.at[k].0 {
                continue;
            }
            let (b, t, lo, hi) = cloud.at[m];
            best = best.min(nearest_on_curve(curve_of(b), x, t, lo, hi).dist);
        }
    }
    best
}

/// Measures the two-sided deviation of the cutting moves of `path` from `design`.
///
/// # Errors
/// [`ReplayError`] if the program has no cutting moves or the design curve no length.
pub fn deviation(path: &Toolpath, design: &dyn Curve3, opts: &DeviationOptions) -> Result<Deviation, ReplayError> {
    let cuts: Vec<&PathBlock> = path.cuts().collect();
    if cuts.is_empty() {
        return Err(ReplayError::NoCuts);
    }
    let (ta, tb) = design.range();
    let table = ArcLengthTable::new(design, 64);
    let length = table.length();
    if !(length > 0.0) {
        return Err(ReplayError::EmptyDesign);
    }
    // Sample spacing: the requested one, coarsened when the program and the design together
    // would need more than the sample budget (a move of ten kilometres, a corrupt control
    // point). The distance to a curve changes by at most the distance moved, so a sample
    // spacing h misses no peak by more than h/2 before the peaks are refined; `Deviation`
    // reports the spacing used.
    let piece_len = |c: &dyn Curve3, a: f64, b: f64| {
        (c.point_at(b) - c.point_at(a)).length() + (c.point_at(0.5 * (a + b)) - c.point_at(a)).length()
    };
    let mut program_len = 0.0;
    let mut pieces = 0usize;
    for blk in &cuts {
        let c = blk.segment.curve();
        for w in sample_params(&blk.segment, 1).windows(2) {
            program_len += piece_len(c, w[0], w[1]);
            pieces += 1;
        }
    }
    // A program of very many short pieces (a million G01 lines) gets fewer samples per
    // piece: as many as its length needs at the spacing, at least its two ends, and no
    // golden-section refinement inside a piece shorter than the spacing (the distance along
    // it then differs from its sampled maximum by at most a quarter of the spacing).
    let dense = pieces.saturating_mul(opts.samples_per_piece + 1) <= crate::numerics::limits::MAX_REPLAY_SAMPLES / 2;
    let per_piece = if dense { opts.samples_per_piece } else { 1 };
    let budget = crate::numerics::limits::MAX_REPLAY_SAMPLES.saturating_sub(pieces * (per_piece + 1)).max(1 << 16);
    let spacing = opts
        .design_spacing_mm
        .max(crate::numerics::tolerance::REPLAY_MIN_SPACING_MM)
        .max((program_len + length) / budget as f64);
    if !spacing.is_finite() {
        return Err(ReplayError::EmptyDesign);
    }
    // Design samples, equally spaced in arc length.
    let n_d = ((length / spacing).ceil() as usize).max(8);
    let dcloud = design_cloud(design, &table, n_d);
    // Program samples, at most `spacing` apart.
    let mut samples = Vec::new();
    for (b, blk) in cuts.iter().enumerate() {
        let c = blk.segment.curve();
        let params = sample_params(&blk.segment, 1);
        samples.push((b, params[0], c.point_at(params[0])));
        for w in params.windows(2) {
            let len = piece_len(c, w[0], w[1]);
            let n = per_piece.max((len / spacing).ceil() as usize).max(1);
            for k in 1..=n {
                let t = w[0] + (w[1] - w[0]) * k as f64 / n as f64;
                samples.push((b, t, c.point_at(t)));
            }
        }
    }
    // A program that retraces itself (a back-and-forth of a million moves) puts its samples
    // on the same points, which every search near them would scan: past DEDUPE_AFTER samples
    // one is kept per position (to a thousandth of the spacing). Smaller clouds stay whole.
    if samples.len() > DEDUPE_AFTER {
        let q = (spacing * DEDUPE_CELL_REL).max(DEDUPE_CELL_MIN_MM);
        let mut seen = std::collections::HashSet::with_capacity(samples.len());
        samples.retain(|(_, _, p)| {
            let k = (*p / q).round();
            seen.insert([k.x as i64, k.y as i64, k.z as i64])
        });
    }
    let pcloud = Cloud::from_samples(samples);
    let design_of = |_: usize| -> &dyn Curve3 { design };
    let cut_of = |b: usize| -> &dyn Curve3 { cuts[b].segment.curve() };
    // Program → design, per piece.
    let mut p2d = (0.0_f64, DVec3::ZERO, cuts[0].line);
    for blk in &cuts {
        let c = blk.segment.curve();
        let params = sample_params(&blk.segment, 1);
        for w in params.windows(2) {
            let mut f = |t: f64| distance_via(&dcloud, &design_of, c.point_at(t));
            let (n, refine) = if dense {
                (opts.samples_per_piece, opts.refine)
            } else {
                let len = piece_len(c, w[0], w[1]);
                let n = ((len / spacing).ceil() as usize).clamp(2, opts.samples_per_piece.max(2));
                (n, if len > spacing { opts.refine } else { 0 })
            };
            let (d, t) = max_on_interval(&mut f, w[0], w[1], n, refine);
            if d > p2d.0 {
                p2d = (d, c.point_at(t), blk.line);
            }
        }
    }
    // Design → program, samples then local maxima refined.
    let dists: Vec<f64> = dcloud.pts.iter().map(|&x| distance_via(&pcloud, &cut_of, x)).collect();
    let coarse_max = dists.iter().copied().fold(0.0_f64, f64::max);
    let mut d2p = (0.0_f64, dcloud.pts[0], 0.0_f64);
    for i in 0..dists.len() {
        let left = if i > 0 { dists[i - 1] } else { f64::NEG_INFINITY };
        let right = if i + 1 < dists.len() { dists[i + 1] } else { f64::NEG_INFINITY };
        if dists[i] > d2p.0 {
            d2p = (dists[i], dcloud.pts[i], length * i as f64 / n_d as f64);
        }
        if dists[i] >= left && dists[i] >= right && dists[i] >= 0.5 * coarse_max {
            let (_, _, lo, hi) = dcloud.at[i];
            let mut f = |t: f64| distance_via(&pcloud, &cut_of, design.point_at(t));
            let (d, t) = max_on_interval(&mut f, lo, hi, 2, opts.refine);
            if d > d2p.0 {
                d2p = (d, design.point_at(t), table.s_at(design, t));
            }
        }
    }
    let first = cuts[0].segment.start();
    let last = cuts[cuts.len() - 1].segment.end();
    Ok(Deviation {
        program_to_design_mm: p2d.0,
        program_point: p2d.1,
        program_line: p2d.2,
        design_to_program_mm: d2p.0,
        design_point: d2p.1,
        design_s_mm: d2p.2,
        start_gap_mm: (first - design.point_at(ta)).length(),
        end_gap_mm: (last - design.point_at(tb)).length(),
        design_length_mm: length,
        sample_spacing_mm: spacing,
    })
}

/// What a program holds, without a design path.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramSummary {
    /// Blocks per motion: G00, G01, G02, G03, G06.2 curves.
    pub moves: [usize; 5],
    /// Control points of all G06.2 curves.
    pub nurbs_control_points: usize,
    /// Length of the cutting moves (mm).
    pub cut_length_mm: f64,
    /// Length of the rapid moves (mm).
    pub rapid_length_mm: f64,
    /// Bounding box of the cutting moves (mm).
    pub bounds: Option<(DVec3, DVec3)>,
    /// Lowest and highest feed of the cutting moves (mm/min).
    pub feed_range: Option<(f64, f64)>,
}

/// Summarises a toolpath.
#[must_use]
pub fn summarize(path: &Toolpath) -> ProgramSummary {
    let mut s = Summarizer::default();
    for b in &path.blocks {
        s.add(b);
    }
    s.finish()
}

/// Sample steps of a move for the bounds ([`Toolpath::cut_bounds`]; per knot span of a curve).
const SAMPLE_STEPS: usize = 16;

/// Folds one coordinate of a line's bounds samples (`a (1 − t) + b t` at t = i / 16, as
/// glam's lerp) into `lo` and `hi` as glam's `min` and `max` do (`if lo < v { lo } else
/// { v }`), sample after sample, bit for bit.
///
/// When `a` and `b` are *coarse* — their last five significand bits zero, far from overflow
/// and underflow: whole millimetres, halves, quarters … — every product `a (1 − t)`, `b t`
/// is exact (t has at most five significant bits), so each sample is the exact value
/// rounded, and rounding keeps order: the samples run monotonically from `a` (t = 0: a·1 +
/// b·0) to `b` (t = 1). Folding a sample no lower than one folded before changes nothing, so
/// when none of them is a zero (whose two signs compare equal) folding the 17 samples is
/// folding the lower end into `lo` and the upper into `hi`. That holds when `a` equals `b`
/// (every sample is `a`, the exact a (1 − t) + a t) or when they have the same sign (all
/// samples lie between them, away from zero), and for a zero the line keeps.
fn fold_line_samples(lo: &mut f64, hi: &mut f64, a: f64, b: f64) {
    let coarse = |v: f64| v.to_bits() & 0x1f == 0 && (1e-280..1e280).contains(&v.abs());
    // A zero the line keeps: every sample is that zero, sign and all (±0·u ± 0·t).
    let same_zero = a == 0.0 && a.to_bits() == b.to_bits();
    if same_zero || (coarse(a) && coarse(b) && (a > 0.0) == (b > 0.0)) {
        let (l, h) = if a < b { (a, b) } else { (b, a) };
        *lo = if *lo < l { *lo } else { l };
        *hi = if *hi > h { *hi } else { h };
        return;
    }
    for (&t, &u) in LINE_T.iter().zip(&LINE_ONE_MINUS_T) {
        let v = a * u + b * t;
        *lo = if *lo < v { *lo } else { v };
        *hi = if *hi > v { *hi } else { v };
    }
}

/// The sample parameters of a line, `push_sample_params`'s `0 + (1 − 0)·i / 16` (all within
/// 0…1, so `point_at`'s clamp keeps them).
const LINE_T: [f64; SAMPLE_STEPS + 1] = {
    let mut t = [0.0; SAMPLE_STEPS + 1];
    let mut i = 1;
    while i <= SAMPLE_STEPS {
        t[i] = 0.0 + (1.0 - 0.0) * i as f64 / SAMPLE_STEPS as f64;
        i += 1;
    }
    t
};

/// `1 − t` of [`LINE_T`], as glam's lerp computes it.
const LINE_ONE_MINUS_T: [f64; SAMPLE_STEPS + 1] = {
    let mut u = [0.0; SAMPLE_STEPS + 1];
    let mut i = 0;
    while i <= SAMPLE_STEPS {
        u[i] = 1.0 - LINE_T[i];
        i += 1;
    }
    u
};

/// A [`ProgramSummary`] built one block at a time, so a command that only summarises a
/// program never holds its moves ([`crate::gcode::read_streamed`]). Blocks added in the
/// path's order give the summary [`summarize`] gives, bit for bit: the lengths are summed in
/// the same order and the bounds come from the same sample points.
#[derive(Clone, Debug)]
pub struct Summarizer {
    moves: [usize; 5],
    ncp: usize,
    feed: Option<(f64, f64)>,
    cut: f64,
    rapid: f64,
    bounds: Option<(DVec3, DVec3)>,
    /// The sample parameters of one block (a buffer kept between blocks).
    params: Vec<f64>,
}

impl Default for Summarizer {
    fn default() -> Self {
        // A sum of lengths starts at -0.0, as `Iterator::sum` of f64 does.
        Self { moves: [0; 5], ncp: 0, feed: None, cut: -0.0, rapid: -0.0, bounds: None, params: Vec::new() }
    }
}

impl Summarizer {
    /// Adds the next block of the path.
    pub fn add(&mut self, b: &PathBlock) {
        let i = match b.motion {
            Motion::Rapid => 0,
            Motion::Linear => 1,
            Motion::ArcCw => 2,
            Motion::ArcCcw => 3,
            Motion::Nurbs => 4,
        };
        self.moves[i] += 1;
        if let Segment::Nurbs(c) = &b.segment {
            self.ncp += c.len();
        }
        if let Some(f) = b.feed_mm_per_min {
            self.feed = Some(match self.feed {
                None => (f, f),
                Some((lo, hi)) => (lo.min(f), hi.max(f)),
            });
        }
        if b.motion == Motion::Rapid {
            self.rapid += segment_length(&b.segment);
            return;
        }
        self.cut += segment_length(&b.segment);
        if let Segment::Line(l) = &b.segment {
            // A line's samples are those `push_sample_params` and `LineMove::point_at` make,
            // folded into the bounds axis by axis in the same order with the same operations
            // (glam's lerp, min and max), without the buffer and the dynamic call: most moves
            // are lines.
            let (mut lo, mut hi) = self.bounds.unwrap_or_else(|| {
                let p = l.start.lerp(l.end, 0.0);
                (p, p)
            });
            for k in 0..3 {
                fold_line_samples(&mut lo[k], &mut hi[k], l.start[k], l.end[k]);
            }
            self.bounds = Some((lo, hi));
            return;
        }
        self.params.clear();
        push_sample_params(&b.segment, SAMPLE_STEPS, &mut self.params);
        let curve = b.segment.curve();
        for &t in &self.params {
            let p = curve.point_at(t);
            self.bounds = Some(match self.bounds {
                None => (p, p),
                Some((lo, hi)) => (lo.min(p), hi.max(p)),
            });
        }
    }

    /// The summary of the blocks added.
    #[must_use]
    pub fn finish(self) -> ProgramSummary {
        ProgramSummary {
            moves: self.moves,
            nurbs_control_points: self.ncp,
            cut_length_mm: self.cut,
            rapid_length_mm: self.rapid,
            bounds: self.bounds,
            feed_range: self.feed,
        }
    }
}
