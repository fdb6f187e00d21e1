//! Where on the parameter plane the surface bends how much: the bound K of its second
//! derivative that the certified bottom check ([`super::gouge`]) needs on each cell it
//! looks at, taken from the part's sample grid near the cell rather than from the whole
//! surface.
//!
//! The bottom check halves cells of the parameter plane, starting from a
//! [`FIRST_CELLS`] × [`FIRST_CELLS`] grid, one side at a time: a cell halved `a` times
//! across u and `b` times across v is one of `FIRST_CELLS·2^a` × `FIRST_CELLS·2^b` equal
//! rectangles. For every such pair of levels up to [`MAX_LEVEL`] the map holds, for each
//! rectangle, the largest second-derivative measure found at the grid points within one
//! grid spacing of it, times the allowance; a finer cell takes the value of the rectangle of
//! [`MAX_LEVEL`] that holds it. On a surface that bends hard in one place (a control point
//! pulled far out) the cells elsewhere are bounded by what the surface does there, not by
//! the worst place, and the check needs far fewer of them.

/// Cells of the bottom check's first grid along each parameter.
pub const FIRST_CELLS: usize = 4;

/// The finest level of halvings the map keeps per parameter (4·2⁵ = 128 rectangles a side,
/// finer than the part's default 200-point grid spacing would need to be kept apart).
pub const MAX_LEVEL: usize = 5;

/// The largest second derivative of the surface near each rectangle of the bottom check's
/// subdivision (module docs), mm per internal parameter unit².
#[derive(Clone, Debug)]
pub struct SecondBound {
    /// Levels kept per parameter (≤ [`MAX_LEVEL`]; fewer for a coarse grid).
    levels: usize,
    /// `values[a * (levels + 1) + b]`: the rectangles of level (a, b), row-major over u then
    /// v (`FIRST_CELLS·2^a` × `FIRST_CELLS·2^b`).
    values: Vec<Vec<f64>>,
    /// The largest value anywhere: the bound of the whole surface.
    global: f64,
}

impl SecondBound {
    /// Builds the map from an `n × n` grid of samples over the domain (row `i` at `i·n`,
    /// uniform in u along the rows' index and in v within a row), each already scaled by the
    /// allowance.
    #[must_use]
    pub fn from_grid(samples: &[f64], n: usize) -> Self {
        let global = samples.iter().copied().fold(0.0, f64::max);
        if n < 2 || samples.len() != n * n {
            return Self { levels: 0, values: vec![vec![global; FIRST_CELLS * FIRST_CELLS]], global };
        }
        // Enough levels that the finest rectangles are about one grid spacing across.
        let spacing_cells = n - 1;
        let mut levels = 0;
        while levels < MAX_LEVEL && FIRST_CELLS << levels < spacing_cells {
            levels += 1;
        }
        let side = |level: usize| FIRST_CELLS << level;
        // The finest level directly: the grid points within one spacing of each rectangle
        // (the rectangle [i/m, (i+1)/m] of the unit interval holds grid indices from
        // floor(i·(n−1)/m) to ceil((i+1)·(n−1)/m); one more each way).
        let fine = side(levels);
        let span = |i: usize| {
            let lo = (i * spacing_cells / fine).saturating_sub(1);
            let hi = ((i + 1) * spacing_cells).div_ceil(fine) + 1;
            (lo, hi.min(n - 1))
        };
        let mut finest = vec![0.0f64; fine * fine];
        for i in 0..fine {
            let (i0, i1) = span(i);
            for j in 0..fine {
                let (j0, j1) = span(j);
                let mut m = 0.0f64;
                for gi in i0..=i1 {
                    for &s in &samples[gi * n + j0..=gi * n + j1] {
                        m = m.max(s);
                    }
                }
                finest[i * fine + j] = m;
            }
        }
        // Coarser levels: a rectangle's near points are its two halves' near points.
        let count = levels + 1;
        let mut values = vec![Vec::new(); count * count];
        values[levels * count + levels] = finest;
        for a in (0..=levels).rev() {
            for b in (0..=levels).rev() {
                if a == levels && b == levels {
                    continue;
                }
                let (su, sv) = (side(a), side(b));
                let mut v = vec![0.0f64; su * sv];
                if b < levels {
                    // From (a, b + 1): halves across v.
                    let child = &values[a * count + b + 1];
                    let csv = side(b + 1);
                    for i in 0..su {
                        for j in 0..sv {
                            v[i * sv + j] = child[i * csv + 2 * j].max(child[i * csv + 2 * j + 1]);
                        }
                    }
                } else {
                    // From (a + 1, b): halves across u.
                    let child = &values[(a + 1) * count + b];
                    for i in 0..su {
                        for j in 0..sv {
                            v[i * sv + j] = child[2 * i * sv + j].max(child[(2 * i + 1) * sv + j]);
                        }
                    }
                }
                values[a * count + b] = v;
            }
        }
        Self { levels, values, global }
    }

    /// The bound on the rectangle `index` of level `level` (halvings across u and v): its
    /// own value at or above [`MAX_LEVEL`]'s resolution, else that of the rectangle holding it.
    #[must_use]
    pub fn at(&self, level: (u32, u32), index: (u64, u64)) -> f64 {
        let count = self.levels + 1;
        let (a, b) = (level.0 as usize, level.1 as usize);
        let (ka, kb) = (a.min(self.levels), b.min(self.levels));
        let (i, j) = ((index.0 as usize) >> (a - ka), (index.1 as usize) >> (b - kb));
        let sv = FIRST_CELLS << kb;
        self.values.get(ka * count + kb).and_then(|v| v.get(i * sv + j)).copied().unwrap_or(self.global)
    }

    /// The largest value on the whole surface.
    #[must_use]
    pub fn global(&self) -> f64 {
        self.global
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map against a brute-force maximum over the grid points near each rectangle, at
    /// every level, for a grid with one tall peak.
    #[test]
    fn each_rectangle_holds_the_largest_value_near_it_and_no_less() {
        let n = 37;
        let samples: Vec<f64> = (0..n * n)
            .map(|k| {
                let (i, j) = ((k / n) as f64, (k % n) as f64);
                1.0 + (i * 0.37 + j * 0.11).sin().abs() + if k == 20 * n + 9 { 500.0 } else { 0.0 }
            })
            .collect();
        let map = SecondBound::from_grid(&samples, n);
        assert_eq!(map.global(), samples.iter().copied().fold(0.0, f64::max));
        for a in 0..=MAX_LEVEL + 1 {
            for b in 0..=MAX_LEVEL + 1 {
                let (su, sv) = (FIRST_CELLS << a, FIRST_CELLS << b);
                for i in 0..su {
                    for j in 0..sv {
                        // Grid points whose parameter lies within one spacing of the rectangle.
                        let h = 1.0 / (n - 1) as f64;
                        let (u0, u1) = (i as f64 / su as f64 - h, (i + 1) as f64 / su as f64 + h);
                        let (v0, v1) = (j as f64 / sv as f64 - h, (j + 1) as f64 / sv as f64 + h);
                        let near = (0..n * n)
                            .filter(|k| {
                                let (u, v) = ((k / n) as f64 * h, (k % n) as f64 * h);
                                u >= u0 - 1e-12 && u <= u1 + 1e-12 && v >= v0 - 1e-12 && v <= v1 + 1e-12
                            })
                            .map(|k| samples[k])
                            .fold(0.0, f64::max);
                        let got = map.at((a as u32, b as u32), (i as u64, j as u64));
                        assert!(got >= near, "level ({a}, {b}) cell ({i}, {j}): {got} < {near}");
                        assert!(got <= map.global());
                    }
                }
            }
        }
        // Far from the peak the bound is the surface's own, not the peak's.
        assert!(map.at((3, 3), (0, 0)) < 3.0);
        assert!(map.at((0, 0), (2, 0)) > 500.0);
    }
}
