//! Banded linear systems of curve fitting: Gaussian elimination with partial pivoting on
//! rows stored as short dense windows.
//!
//! The collocation matrix of B-spline interpolation and the normal matrix of B-spline least
//! squares have at most p + 1 non-zeros per row around the diagonal, so a system of n
//! unknowns costs O(n·p²) instead of O(n³) and O(n·p) memory instead of O(n²). Row swaps of
//! partial pivoting can widen a row to the right by the lower bandwidth; each row keeps its
//! own window `[start, start + len)`, so this is handled without a fixed band layout.

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use glam::DVec3;

use crate::numerics::tolerance;

/// One matrix row: the entries of columns `start .. start + vals.len()`; all others are zero.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct BandRow {
    pub start: usize,
    pub vals: Vec<f64>,
}

impl BandRow {
    pub fn new(start: usize, vals: Vec<f64>) -> Self {
        Self { start, vals }
    }

    fn get(&self, col: usize) -> f64 {
        if col < self.start {
            return 0.0;
        }
        self.vals.get(col - self.start).copied().unwrap_or(0.0)
    }

    fn end(&self) -> usize {
        self.start + self.vals.len()
    }

    /// `self -= f · other`, on columns ≥ `from` (entries left of `from` are dropped: they are
    /// eliminated).
    fn sub_scaled(&mut self, other: &Self, f: f64, from: usize) {
        let start = from.max(self.start.min(other.start));
        let end = self.end().max(other.end());
        let vals: Vec<f64> = (start..end).map(|c| self.get(c) - f * other.get(c)).collect();
        self.start = start;
        self.vals = vals;
    }
}

/// Solves `A x = b` for a square banded `A` given by rows, with three right-hand sides at once
/// (x, y, z of control points). The lower bandwidth (how far left of the diagonal a row
/// starts) is read from the rows. `None` when a pivot is negligible (singular system).
pub(crate) fn solve(mut rows: Vec<BandRow>, mut rhs: Vec<DVec3>) -> Option<Vec<DVec3>> {
    let n = rows.len();
    if rhs.len() != n || n == 0 {
        return None;
    }
    let lower = rows.iter().enumerate().map(|(i, r)| i.saturating_sub(r.start)).max().unwrap_or(0);
    let scale = rows.iter().flat_map(|r| r.vals.iter()).fold(0.0_f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    for k in 0..n {
        let last = (k + lower).min(n - 1);
        let mut piv = k;
        for r in k + 1..=last {
            if rows[r].get(k).abs() > rows[piv].get(k).abs() {
                piv = r;
            }
        }
        let pv = rows[piv].get(k);
        if !(pv.abs() > tolerance::FIT_PIVOT_REL * scale) {
            return None;
        }
        rows.swap(k, piv);
        rhs.swap(k, piv);
        let (head, tail) = rows.split_at_mut(k + 1);
        let pivot_row = &head[k];
        let pivot_rhs = rhs[k];
        for (off, row) in tail.iter_mut().take(last - k).enumerate() {
            let f = row.get(k) / pv;
            if f != 0.0 {
                row.sub_scaled(pivot_row, f, k + 1);
                let r = k + 1 + off;
                rhs[r] -= f * pivot_rhs;
            }
        }
    }
    let mut x = vec![DVec3::ZERO; n];
    for k in (0..n).rev() {
        let row = &rows[k];
        let mut s = rhs[k];
        for (c, xc) in x.iter().enumerate().take(row.end().min(n)).skip(k + 1) {
            s -= row.get(c) * *xc;
        }
        x[k] = s / row.get(k);
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_tridiagonal_needing_a_swap() {
        // [0 1 0; 1 0 1; 0 1 1] x = b has a zero first pivot.
        let rows = vec![
            BandRow::new(0, vec![0.0, 1.0]),
            BandRow::new(0, vec![1.0, 0.0, 1.0]),
            BandRow::new(1, vec![1.0, 1.0]),
        ];
        let xs = [DVec3::new(1.0, 2.0, 3.0), DVec3::new(-1.0, 0.5, 4.0), DVec3::new(2.0, 2.0, -2.0)];
        let b = vec![xs[1], xs[0] + xs[2], xs[1] + xs[2]];
        let Some(x) = solve(rows, b) else { panic!("the system is regular") };
        for (a, e) in x.iter().zip(xs.iter()) {
            assert!((*a - *e).length() < 1e-12, "{a} vs {e}");
        }
    }

    #[test]
    fn reports_a_singular_system() {
        let rows = vec![BandRow::new(0, vec![1.0, 1.0]), BandRow::new(0, vec![2.0, 2.0])];
        assert!(solve(rows, vec![DVec3::ONE, DVec3::ONE]).is_none());
    }
}
