//! The B-spline basis functions on one knot span and their first and second derivatives
//! (the triangular table of the standard algorithm), with the common degrees specialised.

use super::MAX_ORDER;

/// Basis functions `N_{span−p+j, p}` and their first and second derivatives at `u`:
/// `ders[k][j]` is the k-th derivative, `j = 0..=p`. Derivatives above the degree are zero.
#[must_use]
pub fn basis_derivatives(knots: &[f64], span: usize, p: usize, u: f64) -> [[f64; MAX_ORDER]; 3] {
    // The common degrees with p a constant, so the loops unroll and the unused parts of the
    // tables vanish; the arithmetic (and so every bit of the result) is the same.
    match p {
        1 => basis_derivatives_of(knots, span, 1, u),
        2 => basis_derivatives_of(knots, span, 2, u),
        3 => basis_derivatives_of(knots, span, 3, u),
        _ => basis_derivatives_of(knots, span, p, u),
    }
}

/// The basis functions `N_{span−p+j, p}(u)`, `j = 0..=p`: the first row of
/// [`basis_derivatives`], by the same arithmetic (the same bits) without the derivatives.
#[must_use]
pub fn basis_functions(knots: &[f64], span: usize, p: usize, u: f64) -> [f64; MAX_ORDER] {
    match p {
        1 => basis_functions_of(knots, span, 1, u),
        2 => basis_functions_of(knots, span, 2, u),
        3 => basis_functions_of(knots, span, 3, u),
        _ => basis_functions_of(knots, span, p, u),
    }
}

#[inline(always)]
pub(super) fn basis_functions_of(knots: &[f64], span: usize, p: usize, u: f64) -> [f64; MAX_ORDER] {
    let mut n = [0.0; MAX_ORDER];
    let mut left = [0.0; MAX_ORDER];
    let mut right = [0.0; MAX_ORDER];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // As in `basis_derivatives_of`: n[r] holds ndu[r][j − 1], the divisor ndu[j][r].
            let temp = n[r] / (right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

#[inline(always)]
fn basis_derivatives_of(knots: &[f64], span: usize, p: usize, u: f64) -> [[f64; MAX_ORDER]; 3] {
    basis_derivatives_sized::<MAX_ORDER, 2>(knots, span, p, u)
}

/// [`basis_derivatives_of`] in tables of order `O` (> p; the exact p + 1 for the common
/// degrees, so no unused table is cleared) up to the derivative order `D` (≤ 2; the rows
/// above it stay zero), by the same arithmetic: the values it computes have the same bits.
#[inline(always)]
pub(super) fn basis_derivatives_sized<const O: usize, const D: usize>(
    knots: &[f64],
    span: usize,
    p: usize,
    u: f64,
) -> [[f64; O]; 3] {
    let mut ndu = [[0.0; O]; O];
    let mut left = [0.0; O];
    let mut right = [0.0; O];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences; upper: basis functions.
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0; O]; 3];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let nd = p.min(D);
    let mut a = [[0.0; 3]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let pk = p - k;
            // rk = r − k may be negative; keep it signed.
            let rk = r as isize - k as isize;
            if rk >= 0 {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize { k - 1 } else { p - r };
            let mut j = j1;
            while j <= j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
                j += 1;
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
        for v in row.iter_mut().take(p + 1) {
            *v *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}
