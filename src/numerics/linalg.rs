//! Small dense linear solves (2×2, 3×3, 4×4) without allocation.
//!
//! Every solver returns `None` when the system is singular to working precision instead of
//! producing infinities; callers turn that into an error that names the geometric cause.

use glam::{DVec2, DVec3};

/// Solves `[a b; c d] x = r` by Cramer's rule. `None` when the determinant is negligible
/// relative to the matrix entries.
#[must_use]
pub fn solve2(a: f64, b: f64, c: f64, d: f64, r: DVec2) -> Option<DVec2> {
    let det = a * d - b * c;
    let scale = (a.abs() + b.abs()) * (c.abs() + d.abs());
    if !(det.abs() > crate::numerics::tolerance::SINGULAR_DET_REL * scale) || !det.is_finite() {
        return None;
    }
    Some(DVec2::new((r.x * d - b * r.y) / det, (a * r.y - c * r.x) / det))
}

/// Solves the 3×3 system whose *rows* are `r0, r1, r2`: `r_i · x = b_i`.
/// Uses the explicit inverse through cross products (columns `r1×r2, r2×r0, r0×r1` over the
/// determinant), which is exact for the small, well-scaled systems of the interpolator.
#[must_use]
pub fn solve3_rows(r0: DVec3, r1: DVec3, r2: DVec3, b: DVec3) -> Option<DVec3> {
    let c0 = r1.cross(r2);
    let c1 = r2.cross(r0);
    let c2 = r0.cross(r1);
    let det = r0.dot(c0);
    let scale = r0.length() * r1.length() * r2.length();
    if !(det.abs() > crate::numerics::tolerance::SINGULAR_DET_REL * scale) || !det.is_finite() {
        return None;
    }
    Some((c0 * b.x + c1 * b.y + c2 * b.z) / det)
}

/// Solves a 4×4 system `m x = b` (row-major `m`) by Gaussian elimination with partial
/// pivoting. `None` when a pivot vanishes relative to the largest entry.
#[must_use]
pub fn solve4(mut m: [[f64; 4]; 4], mut b: [f64; 4]) -> Option<[f64; 4]> {
    let scale = m.iter().flatten().fold(0.0_f64, |s, v| s.max(v.abs()));
    if !(scale > 0.0) || !scale.is_finite() {
        return None;
    }
    for col in 0..4 {
        let mut piv = col;
        for row in col + 1..4 {
            if m[row][col].abs() > m[piv][col].abs() {
                piv = row;
            }
        }
        if m[piv][col].abs() <= crate::numerics::tolerance::DENSE_PIVOT_REL * scale {
            return None;
        }
        m.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..4 {
            let factor = m[row][col] / m[col][col];
            for k in col..4 {
                m[row][k] -= factor * m[col][k];
            }
            b[row] -= factor * b[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..4).rev() {
        let mut s = b[row];
        for k in row + 1..4 {
            s -= m[row][k] * x[k];
        }
        x[row] = s / m[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}
