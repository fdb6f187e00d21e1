//! The dexel stock: a grid of vertical rays, each a sorted list of disjoint material
//! intervals, and the exact 1-D subtraction that removes a span of a ray.
//!
//! # Layout
//!
//! Most rays of a machined block hold one interval (the material below the cut surface),
//! so each ray stores one interval inline (`Ray`: two f64 and a tag, 24 bytes). Only a
//! ray split into several intervals (an undercut, a side cut of a tilted tool) moves its
//! list into a spill slot (`Vec<Interval>`) of the stock; when it shrinks back to one
//! interval or none the slot is freed for reuse. A 1024 × 1024 block of single-interval
//! rays takes 24 MiB.

use super::SimError;

/// Largest number of rays a stock may have (2048 × 2048): about 100 MB of single-interval
/// rays. A finer grid is refused before it is allocated.
pub const MAX_RAYS: usize = 1 << 22;

/// A material interval along a ray: the material occupies `lo_mm < z < hi_mm` (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Bottom of the material (mm).
    pub lo_mm: f64,
    /// Top of the material (mm).
    pub hi_mm: f64,
}

/// Tag of a ray whose material is all gone.
const EMPTY: u32 = u32::MAX;
/// Tag of a ray with exactly one (inline) interval.
const INLINE: u32 = 0;

/// One ray's storage: the inline interval, or a tag pointing into the spill slots.
#[derive(Clone, Copy, Debug)]
struct Ray {
    iv: Interval,
    /// [`INLINE`], [`EMPTY`], or 1 + the index of the spill slot holding the list.
    tag: u32,
}

/// The grid of rays: ray (i, j) runs along +Z through (x0 + (i + ½)·pitch, y0 + (j + ½)·pitch),
/// the centre of its square cell. Row-major: index = j·nx + i.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Lower x of the grid (mm).
    pub x0_mm: f64,
    /// Lower y of the grid (mm).
    pub y0_mm: f64,
    /// Spacing of the rays in x and y (mm).
    pub pitch_mm: f64,
    /// Rays along x.
    pub nx: usize,
    /// Rays along y.
    pub ny: usize,
}

impl Grid {
    /// x of ray column i (mm).
    #[must_use]
    pub fn x_mm(&self, i: usize) -> f64 {
        self.x0_mm + (i as f64 + 0.5) * self.pitch_mm
    }

    /// y of ray row j (mm).
    #[must_use]
    pub fn y_mm(&self, j: usize) -> f64 {
        self.y0_mm + (j as f64 + 0.5) * self.pitch_mm
    }

    /// Number of rays.
    #[must_use]
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the grid has no ray (never true for a built stock).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The inclusive range of columns whose rays lie in [xa, xb] (mm), `None` when none does.
    #[must_use]
    pub fn columns(&self, xa_mm: f64, xb_mm: f64) -> Option<(usize, usize)> {
        index_range(self.x0_mm, self.pitch_mm, self.nx, xa_mm, xb_mm)
    }

    /// The inclusive range of rows whose rays lie in [ya, yb] (mm), `None` when none does.
    #[must_use]
    pub fn rows(&self, ya_mm: f64, yb_mm: f64) -> Option<(usize, usize)> {
        index_range(self.y0_mm, self.pitch_mm, self.ny, ya_mm, yb_mm)
    }
}

fn index_range(origin: f64, pitch: f64, n: usize, a: f64, b: f64) -> Option<(usize, usize)> {
    if !(a <= b) || n == 0 {
        return None;
    }
    // Ray k sits at origin + (k + ½)·pitch.
    let lo = ((a - origin) / pitch - 0.5).ceil().max(0.0);
    let hi = ((b - origin) / pitch - 0.5).floor().min(n as f64 - 1.0);
    if !(lo <= hi) {
        return None;
    }
    // Both are whole numbers within [0, n − 1] here.
    Some((lo as usize, hi as usize))
}

/// The stock: a block of material sampled by the rays of a [`Grid`].
#[derive(Clone, Debug)]
pub struct DexelStock {
    grid: Grid,
    z0_mm: f64,
    z1_mm: f64,
    rays: Vec<Ray>,
    spills: Vec<Vec<Interval>>,
    free_spills: Vec<u32>,
}

impl DexelStock {
    /// A block from (x0, y0, z0) to (x1, y1, z1) (mm) sampled at `pitch_mm`. The grid has
    /// ⌈(x1 − x0)/pitch⌉ × ⌈(y1 − y0)/pitch⌉ rays at the cell centres (the last cell may
    /// overhang the block by less than one pitch).
    ///
    /// # Errors
    /// [`SimError::Stock`] for a non-finite or empty block or a pitch that is not a positive
    /// length, [`SimError::TooManyRays`] above [`MAX_RAYS`].
    pub fn block(lo_mm: [f64; 3], hi_mm: [f64; 3], pitch_mm: f64) -> Result<Self, SimError> {
        if !(pitch_mm > 0.0 && pitch_mm.is_finite()) {
            return Err(SimError::Stock(format!("the pitch must be a positive length in mm, got {pitch_mm}")));
        }
        for k in 0..3 {
            if !(lo_mm[k].is_finite() && hi_mm[k].is_finite() && hi_mm[k] > lo_mm[k]) {
                let axis = ["x", "y", "z"][k];
                return Err(SimError::Stock(format!(
                    "the stock's {axis} range [{}, {}] mm is empty or not finite; give {axis}0 < {axis}1",
                    lo_mm[k], hi_mm[k]
                )));
            }
        }
        let cells = |w: f64| (w / pitch_mm - super::GRID_ROUND_REL).ceil().max(1.0);
        let (fx, fy) = (cells(hi_mm[0] - lo_mm[0]), cells(hi_mm[1] - lo_mm[1]));
        if fx * fy > MAX_RAYS as f64 {
            return Err(SimError::TooManyRays { rays: fx * fy, max: MAX_RAYS, pitch_mm });
        }
        let grid = Grid { x0_mm: lo_mm[0], y0_mm: lo_mm[1], pitch_mm, nx: fx as usize, ny: fy as usize };
        let ray = Ray { iv: Interval { lo_mm: lo_mm[2], hi_mm: hi_mm[2] }, tag: INLINE };
        Ok(Self {
            grid,
            z0_mm: lo_mm[2],
            z1_mm: hi_mm[2],
            rays: vec![ray; grid.len()],
            spills: Vec::new(),
            free_spills: Vec::new(),
        })
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Bottom and top of the original block (mm).
    #[must_use]
    pub fn z_range_mm(&self) -> (f64, f64) {
        (self.z0_mm, self.z1_mm)
    }

    /// The material intervals of ray `index` (row-major), bottom to top.
    #[must_use]
    pub fn intervals(&self, index: usize) -> &[Interval] {
        let Some(r) = self.rays.get(index) else {
            return &[];
        };
        match r.tag {
            EMPTY => &[],
            INLINE => std::slice::from_ref(&r.iv),
            k => self.spills.get(k as usize - 1).map_or(&[], Vec::as_slice),
        }
    }

    /// Top of the highest material interval of ray `index` (mm); `None` when the ray is
    /// cut through.
    #[must_use]
    pub fn top_mm(&self, index: usize) -> Option<f64> {
        self.intervals(index).last().map(|iv| iv.hi_mm)
    }

    /// Total material length along ray `index` (mm).
    #[must_use]
    pub fn material_mm(&self, index: usize) -> f64 {
        self.intervals(index).iter().map(|iv| iv.hi_mm - iv.lo_mm).sum()
    }

    /// The material of ray `index` inside `lo_mm < z < hi_mm`: its length (mm) and the top of
    /// the highest piece of it (mm); `None` when there is none.
    #[must_use]
    pub fn material_in(&self, index: usize, lo_mm: f64, hi_mm: f64) -> Option<(f64, f64)> {
        let mut length = 0.0;
        let mut top = f64::NEG_INFINITY;
        for iv in self.intervals(index) {
            let (a, b) = (iv.lo_mm.max(lo_mm), iv.hi_mm.min(hi_mm));
            if b > a {
                length += b - a;
                top = b;
            }
        }
        (length > 0.0).then_some((length, top))
    }

    /// Rays holding more than one interval.
    #[must_use]
    pub fn split_rays(&self) -> usize {
        self.rays.iter().filter(|r| r.tag != EMPTY && r.tag != INLINE).count()
    }

    /// Bytes held by the stock: the ray array plus the spill lists (their capacity).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        self.rays.capacity() * std::mem::size_of::<Ray>()
            + self.spills.capacity() * std::mem::size_of::<Vec<Interval>>()
            + self.spills.iter().map(|s| s.capacity() * std::mem::size_of::<Interval>()).sum::<usize>()
            + self.free_spills.capacity() * std::mem::size_of::<u32>()
    }

    /// Removes the span `lo_mm < z < hi_mm` from ray `index`: intervals inside it are
    /// removed, intervals crossing one end are trimmed, an interval containing it is split in
    /// two. Exact (no tolerance): only end points of the span and of the intervals appear in
    /// the result, and no interval of zero length is kept. Returns the material length
    /// removed (mm). An empty or reversed span, or an index outside the grid, removes nothing.
    pub fn subtract(&mut self, index: usize, lo_mm: f64, hi_mm: f64) -> f64 {
        let (c, d) = (lo_mm, hi_mm);
        if !(c < d) {
            return 0.0;
        }
        let Some(r) = self.rays.get_mut(index) else {
            return 0.0;
        };
        match r.tag {
            EMPTY => 0.0,
            INLINE => {
                let (a, b) = (r.iv.lo_mm, r.iv.hi_mm);
                if d <= a || c >= b {
                    return 0.0;
                }
                let removed = d.min(b) - c.max(a);
                match (c > a, d < b) {
                    (false, false) => r.tag = EMPTY,
                    (false, true) => r.iv.lo_mm = d,
                    (true, false) => r.iv.hi_mm = c,
                    (true, true) => {
                        let list = vec![Interval { lo_mm: a, hi_mm: c }, Interval { lo_mm: d, hi_mm: b }];
                        let tag = spill(&mut self.spills, &mut self.free_spills, list);
                        if let Some(r) = self.rays.get_mut(index) {
                            r.tag = tag;
                        }
                    }
                }
                removed
            }
            k => {
                let slot = k as usize - 1;
                let Some(list) = self.spills.get_mut(slot) else {
                    return 0.0;
                };
                let removed = subtract_list(list, c, d);
                match list.len() {
                    0 => {
                        r.tag = EMPTY;
                        self.free_spills.push(k);
                    }
                    1 => {
                        *r = Ray { iv: list[0], tag: INLINE };
                        list.clear();
                        list.shrink_to(0);
                        self.free_spills.push(k);
                    }
                    _ => {}
                }
                removed
            }
        }
    }
}

/// Puts a list into a free (or new) spill slot and returns the ray's tag for it.
fn spill(spills: &mut Vec<Vec<Interval>>, free: &mut Vec<u32>, list: Vec<Interval>) -> u32 {
    if let Some(k) = free.pop()
        && let Some(s) = spills.get_mut(k as usize - 1)
    {
        *s = list;
        return k;
    }
    spills.push(list);
    // MAX_RAYS < u32::MAX − 1, and there is at most one slot per ray.
    u32::try_from(spills.len()).unwrap_or(EMPTY - 1)
}

/// Subtracts the span (c, d), c < d, from a sorted list of disjoint intervals in place;
/// returns the length removed (mm).
pub(crate) fn subtract_list(list: &mut Vec<Interval>, c: f64, d: f64) -> f64 {
    // Intervals [first, last) overlap (c, d) with positive length.
    let first = list.partition_point(|iv| iv.hi_mm <= c);
    let last = list.partition_point(|iv| iv.lo_mm < d);
    if first >= last {
        return 0.0;
    }
    let removed: f64 = list[first..last].iter().map(|iv| iv.hi_mm.min(d) - iv.lo_mm.max(c)).sum();
    let (head, tail) = (list[first], list[last - 1]);
    let left = (head.lo_mm < c).then_some(Interval { lo_mm: head.lo_mm, hi_mm: c });
    let right = (tail.hi_mm > d).then_some(Interval { lo_mm: d, hi_mm: tail.hi_mm });
    list.splice(first..last, left.into_iter().chain(right));
    removed
}
