//! What a machined stock shows: its height map, its signed deviation from a design surface,
//! the scallop map and statistics, the worst gouge, and the files a script reads (CSV) or a
//! person looks at (PNG).
//!
//! Signs: the deviation is positive where material is left above the design (stock left,
//! scallops) and negative where the cutter went below it (a gouge). A ray counts as
//! *machined* when its material differs from the original block's.

use glam::{DVec2, DVec3};

use super::stock::{DexelStock, Grid};
use crate::geom::{ProjectOptions, Surface, project_point, project_point_global};
use crate::numerics::format::fmt_fixed;

/// The surface the machining is compared with.
#[derive(Clone, Debug, Default)]
pub enum Design {
    /// None: no deviation, no scallop map.
    #[default]
    None,
    /// The horizontal plane z = value (mm), material below it.
    PlaneZ(f64),
    /// Parametric surfaces with normals toward the cutter (a scene's two surfaces): the
    /// deviation of a point is its signed distance from the part, the union of the
    /// surfaces' material sides ([`part_signed_distance`]).
    Surfaces(Vec<Surface>),
    /// One machined surface with its material side (normal toward the cutter): a seed-001
    /// finishing part. The deviation of a ray is its signed distance from the surface where
    /// its nearest point lies inside the patch; a ray beside the patch (its nearest point on
    /// the patch's edge, off the normal) has none — it is not over the design, so it counts
    /// in neither the scallops nor the gouges ([`over_surface_signed_distance`]).
    Surface(Surface),
}

impl Design {
    /// A short name for reports: `none`, `plane`, `scene surfaces` or `finish surface`.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::None => "none",
            Self::PlaneZ(_) => "plane",
            Self::Surfaces(_) => "scene surfaces",
            Self::Surface(_) => "finish surface",
        }
    }
}

/// The top of each ray and whether it was machined.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// The grid.
    pub grid: Grid,
    /// Top of the highest material interval per ray (mm), row-major; the stock's bottom z0
    /// for a ray cut through.
    pub top_mm: Vec<f64>,
    /// Whether each ray's material differs from the original block.
    pub machined: Vec<bool>,
    /// Rays cut through (no material left).
    pub through: usize,
}

impl HeightMap {
    /// The height map of a stock.
    #[must_use]
    pub fn of(stock: &DexelStock) -> Self {
        let grid = *stock.grid();
        let (z0, z1) = stock.z_range_mm();
        let mut top_mm = Vec::with_capacity(grid.len());
        let mut machined = Vec::with_capacity(grid.len());
        let mut through = 0;
        for k in 0..grid.len() {
            let iv = stock.intervals(k);
            match iv {
                // Exact: an untouched ray keeps the block's own end values bit for bit.
                [only] => machined.push(only.lo_mm.to_bits() != z0.to_bits() || only.hi_mm.to_bits() != z1.to_bits()),
                _ => machined.push(true),
            }
            match iv.last() {
                Some(t) => top_mm.push(t.hi_mm),
                None => {
                    through += 1;
                    top_mm.push(z0);
                }
            }
        }
        Self { grid, top_mm, machined, through }
    }
}

/// max, mean and 95th percentile of a set of values (mm), and how many there were.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// Number of values.
    pub count: usize,
    /// Largest (mm).
    pub max_mm: f64,
    /// Mean (mm).
    pub mean_mm: f64,
    /// 95th percentile (mm): the value at rank ⌈0.95·n⌉ of the sorted values.
    pub p95_mm: f64,
}

impl Summary {
    /// Of a set of finite values; all zero for none.
    #[must_use]
    pub fn of(mut v: Vec<f64>) -> Self {
        if v.is_empty() {
            return Self::default();
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n);
        Self { count: n, max_mm: v[n - 1], mean_mm: v.iter().sum::<f64>() / n as f64, p95_mm: v[rank - 1] }
    }
}

/// The measures of a machined stock against a design.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimStats {
    /// Rays machined.
    pub machined_rays: usize,
    /// Rays cut through.
    pub through_rays: usize,
    /// Rays holding more than one material interval.
    pub split_rays: usize,
    /// Signed deviation per ray (mm), row-major; `None` where the ray is not machined or
    /// there is no design.
    pub deviation_mm: Vec<Option<f64>>,
    /// Scallops: the positive deviations of machined rays (stock left).
    pub scallop: Summary,
    /// Most negative deviation (mm) and the (x, y) (mm) of its ray, if any ray gouges.
    pub worst_gouge: Option<(f64, DVec2)>,
    /// Machined rays below the design.
    pub gouge_rays: usize,
}

impl SimStats {
    /// Compares a height map with a design.
    #[must_use]
    pub fn of(map: &HeightMap, stock: &DexelStock, design: &Design) -> Self {
        let mut scan = DeviationScan::new(map, design);
        scan.rows(map, design, map.grid.ny);
        scan.finish(map, stock)
    }
}

/// [`SimStats::of`] a number of grid rows at a time, for callers that must not block (the
/// app measures a few rows per frame): the same projections in the same order (each
/// surface's foot point seeds the next ray's), so the same numbers however it is split.
#[derive(Clone, Debug)]
pub struct DeviationScan {
    dev: Vec<Option<f64>>,
    guesses: Vec<Option<FootSeed>>,
    next_row: usize,
}

impl DeviationScan {
    /// Starts the scan of `map` against `design`.
    #[must_use]
    pub fn new(map: &HeightMap, design: &Design) -> Self {
        let guesses = match design {
            Design::Surfaces(s) => vec![None; s.len()],
            Design::Surface(_) => vec![None],
            _ => Vec::new(),
        };
        Self { dev: vec![None; map.grid.len()], guesses, next_row: 0 }
    }

    /// Rows scanned so far (of `map.grid.ny`).
    #[must_use]
    pub fn rows_done(&self) -> usize {
        self.next_row
    }

    /// Scans at most `rows` more rows of `map` (the map and design [`Self::new`] was given).
    pub fn rows(&mut self, map: &HeightMap, design: &Design, rows: usize) {
        let g = map.grid;
        let end = self.next_row.saturating_add(rows).min(g.ny);
        for j in self.next_row..end {
            for i in 0..g.nx {
                let k = j * g.nx + i;
                if !map.machined[k] {
                    continue;
                }
                let p = DVec3::new(g.x_mm(i), g.y_mm(j), map.top_mm[k]);
                self.dev[k] = match design {
                    Design::None => None,
                    Design::PlaneZ(z) => Some(p.z - z),
                    Design::Surfaces(surfaces) => part_signed_distance(surfaces, p, &mut self.guesses),
                    Design::Surface(s) => {
                        self.guesses.first_mut().and_then(|seed| over_surface_signed_distance(s, p, seed))
                    }
                };
            }
        }
        self.next_row = end;
    }

    /// The statistics once every row is scanned (rows not scanned count as unmachined).
    #[must_use]
    pub fn finish(self, map: &HeightMap, stock: &DexelStock) -> SimStats {
        let g = map.grid;
        let dev = self.dev;
        let mut scallops = Vec::new();
        let mut worst: Option<(f64, DVec2)> = None;
        let mut gouge_rays = 0;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let Some(d) = dev[j * g.nx + i] else { continue };
                if d >= 0.0 {
                    scallops.push(d);
                } else {
                    gouge_rays += 1;
                    if worst.is_none_or(|(w, _)| d < w) {
                        worst = Some((d, DVec2::new(g.x_mm(i), g.y_mm(j))));
                    }
                }
            }
        }
        SimStats {
            machined_rays: map.machined.iter().filter(|&&m| m).count(),
            through_rays: map.through,
            split_rays: stock.split_rays(),
            deviation_mm: dev,
            scallop: Summary::of(scallops),
            worst_gouge: worst,
            gouge_rays,
        }
    }
}

/// A foot whose offset p − r leaves the normal by more than this (cosine) lies on the edge
/// of its patch with p beside it, not above or below: the surface says nothing of the side
/// p is on.
pub const FOOT_ALONG_NORMAL_COS: f64 = 0.999;

/// Slack (mm) of the Lipschitz check of [`part_signed_distance`]: Newton's own accuracy.
pub const FOOT_SLACK_MM: f64 = 1e-6;

/// Where the last projection onto a surface landed: its parameters, the point projected
/// and its distance (mm), the seed and the yardstick of the next projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootSeed {
    /// Parameters of the foot (the surface's internal units).
    pub uv: DVec2,
    /// The point that was projected (mm).
    pub point: DVec3,
    /// Its distance from the foot (mm).
    pub distance_mm: f64,
}

/// Signed distance (mm) of `p` from the part bounded by `surfaces` (normals toward the
/// cutter, material on the other side): the part is the union of the surfaces' material
/// sides, so its signed distance is the smallest of theirs — exact outside the part (the
/// distance to a union is the smallest distance to its members), and inside it −(the largest
/// depth below one surface), the depth below the part's boundary wherever the nearest
/// boundary point lies on one surface outside the other's material. Per surface the foot is
/// found by Newton from `seeds` (the previous ray's feet; a global search when there is
/// none, and `seeds` is updated), and checked by a global search when it claims p inside that
/// surface's material or lies farther than the seed's distance plus the step (a local
/// projection may converge to a far foot — the far side of a torus' tube, say — which would
/// read as a deep gouge or hide one). A foot on its patch's edge with p beside it
/// ([`FOOT_ALONG_NORMAL_COS`]) counts as outside that material, at its distance. `None` when
/// no surface gives a finite distance.
pub fn part_signed_distance(surfaces: &[Surface], p: DVec3, seeds: &mut [Option<FootSeed>]) -> Option<f64> {
    let mut best: Option<f64> = None;
    for (s, seed) in surfaces.iter().zip(seeds.iter_mut()) {
        let Some((sd, _)) = checked_foot(s, p, seed) else { continue };
        if best.is_none_or(|b: f64| sd < b) {
            best = Some(sd);
        }
    }
    best
}

/// Signed distance (mm) of `p` from one machined surface (normal toward the cutter,
/// material on the other side) where `p` lies over or under the patch: its nearest point is
/// inside the patch, or on its edge with `p` along the normal there
/// ([`FOOT_ALONG_NORMAL_COS`]). `None` beside the patch (the nearest point on the edge, `p`
/// off its normal) or without a finite distance. The foot is found and checked as in
/// [`part_signed_distance`] (Newton from `seed`, a global search when it is suspect).
pub fn over_surface_signed_distance(surface: &Surface, p: DVec3, seed: &mut Option<FootSeed>) -> Option<f64> {
    checked_foot(surface, p, seed).and_then(|(sd, along_normal)| along_normal.then_some(sd))
}

/// The signed distance of `p` from one surface's material side and whether `p` lies along
/// the normal of its foot (else the foot is on the patch's edge with `p` beside it and the
/// distance counts as outside); see [`part_signed_distance`].
fn checked_foot(s: &Surface, p: DVec3, seed: &mut Option<FootSeed>) -> Option<(f64, bool)> {
    const GLOBAL_SAMPLES: usize = 16;
    let mut foot = match seed {
        Some(f) => project_point(s, p, f.uv, ProjectOptions::default()),
        None => project_point_global(s, p, GLOBAL_SAMPLES),
    };
    // The distance to a surface is 1-Lipschitz: farther than the seed's distance plus the
    // step means Newton settled on a foot that is not the nearest.
    let suspect = seed.is_some_and(|f| {
        foot.signed_distance < 0.0 || foot.distance > f.distance_mm + (p - f.point).length() + FOOT_SLACK_MM
    });
    if suspect {
        let global = project_point_global(s, p, GLOBAL_SAMPLES);
        if global.distance < foot.distance {
            foot = global;
        }
    }
    *seed = Some(FootSeed { uv: foot.uv, point: p, distance_mm: foot.distance });
    if !foot.signed_distance.is_finite() {
        return None;
    }
    let along = foot.signed_distance.abs() >= FOOT_ALONG_NORMAL_COS * foot.distance;
    Some((if along { foot.signed_distance } else { foot.distance }, along))
}

/// The height map as CSV: a header line `i,j,x_mm,y_mm,top_mm,machined,deviation_mm`, then
/// one row per ray, row-major (i along x fastest). `deviation_mm` is empty where there is
/// none; `machined` is 0 or 1. Lengths with 6 decimals (nm).
#[must_use]
pub fn heights_csv(map: &HeightMap, stats: Option<&SimStats>) -> String {
    let g = map.grid;
    let mut out = String::with_capacity(g.len() * 48 + 64);
    out.push_str("i,j,x_mm,y_mm,top_mm,machined,deviation_mm\n");
    for j in 0..g.ny {
        for i in 0..g.nx {
            let k = j * g.nx + i;
            let d = stats.and_then(|s| s.deviation_mm[k]).map_or(String::new(), |d| fmt_fixed(d, 6));
            out.push_str(&format!(
                "{i},{j},{},{},{},{},{d}\n",
                fmt_fixed(g.x_mm(i), 6),
                fmt_fixed(g.y_mm(j), 6),
                fmt_fixed(map.top_mm[k], 6),
                u8::from(map.machined[k])
            ));
        }
    }
    out
}

/// Colour of one ray in the PNG: with a deviation, blue (gouge, −band and below) through
/// green (within ±band/10) to red (stock left, +band and above); without, grey by height
/// from the stock's bottom (black) to its top (white); unmachined rays light grey.
fn colour(top: f64, dev: Option<f64>, machined: bool, z: (f64, f64), band_mm: f64) -> [u8; 3] {
    let to_u8 = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    match dev {
        Some(d) => {
            let s = (d / band_mm).clamp(-1.0, 1.0);
            if s < 0.0 { [0, to_u8(1.0 + s), to_u8(-s)] } else { [to_u8(s), to_u8(1.0 - s), 0] }
        }
        None if !machined => [220, 220, 220],
        None => {
            let v = to_u8((top - z.0) / (z.1 - z.0));
            [v, v, v]
        }
    }
}

/// The height map (or the deviation, when `stats` carries one) as an RGB PNG, one pixel per
/// ray, +y up. `band_mm` is the deviation shown at full colour (see the colour rule of
/// docs/simulation.md). Written with stored (uncompressed) deflate blocks: no dependency.
#[must_use]
pub fn png_rgb(map: &HeightMap, stats: Option<&SimStats>, z_range: (f64, f64), band_mm: f64) -> Vec<u8> {
    let g = map.grid;
    let mut raw = Vec::with_capacity(g.ny * (1 + 3 * g.nx));
    for row in 0..g.ny {
        let j = g.ny - 1 - row;
        raw.push(0u8); // filter: none
        for i in 0..g.nx {
            let k = j * g.nx + i;
            let dev = stats.and_then(|s| s.deviation_mm[k]);
            raw.extend_from_slice(&colour(map.top_mm[k], dev, map.machined[k], z_range, band_mm));
        }
    }
    encode_png(u32::try_from(g.nx).unwrap_or(u32::MAX), u32::try_from(g.ny).unwrap_or(u32::MAX), &raw)
}

/// A PNG of `width` × `height` 8-bit RGB pixels given row by row from the top (3 bytes a
/// pixel); missing pixels are black.
#[must_use]
pub fn png_from_rgb(width: usize, height: usize, rgb: &[u8]) -> Vec<u8> {
    let mut raw = Vec::with_capacity(height * (1 + 3 * width));
    for row in 0..height {
        raw.push(0u8);
        for k in 0..3 * width {
            raw.push(rgb.get(row * 3 * width + k).copied().unwrap_or(0));
        }
    }
    encode_png(u32::try_from(width).unwrap_or(u32::MAX), u32::try_from(height).unwrap_or(u32::MAX), &raw)
}

/// A PNG of 8-bit RGB pixels from filtered scanlines `raw` (each row: a filter byte 0 and
/// 3·width bytes).
fn encode_png(width: u32, height: u32, raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]); // depth 8, RGB, deflate, no filter method, no interlace
    chunk(&mut out, *b"IHDR", &ihdr);
    // zlib stream: header, stored blocks of at most 65 535 bytes, Adler-32.
    let mut z = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = if raw.is_empty() { vec![&[][..]] } else { raw.chunks(65_535).collect() };
    for (n, b) in blocks.iter().enumerate() {
        z.push(u8::from(n + 1 == blocks.len()));
        let len = u16::try_from(b.len()).unwrap_or(u16::MAX);
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&(!len).to_le_bytes());
        z.extend_from_slice(b);
    }
    let (mut a, mut s) = (1u32, 0u32);
    for &byte in raw {
        a = (a + u32::from(byte)) % 65_521;
        s = (s + a) % 65_521;
    }
    z.extend_from_slice(&((s << 16) | a).to_be_bytes());
    chunk(&mut out, *b"IDAT", &z);
    chunk(&mut out, *b"IEND", &[]);
    out
}

fn chunk(out: &mut Vec<u8>, kind: [u8; 4], data: &[u8]) {
    out.extend_from_slice(&u32::try_from(data.len()).unwrap_or(u32::MAX).to_be_bytes());
    out.extend_from_slice(&kind);
    out.extend_from_slice(data);
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in kind.iter().chain(data) {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    out.extend_from_slice(&(!crc).to_be_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_crc_matches_the_standard_check_value() {
        // CRC-32 of "IEND" with no data is the well-known AE 42 60 82.
        let mut out = Vec::new();
        chunk(&mut out, *b"IEND", &[]);
        assert_eq!(&out[8..12], &[0xAE, 0x42, 0x60, 0x82]);
    }

    #[test]
    fn summary_percentile() {
        let s = Summary::of((1..=100).map(f64::from).collect());
        assert_eq!(s.count, 100);
        assert!(
            (s.max_mm - 100.0).abs() < 1e-12 && (s.p95_mm - 95.0).abs() < 1e-12 && (s.mean_mm - 50.5).abs() < 1e-12
        );
    }
}
