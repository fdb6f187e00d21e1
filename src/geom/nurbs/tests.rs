//! The surface's evaluations against one another: the tangents of the standard algorithm
//! bit for bit with its second-derivative evaluation, the power form to rounding.

use glam::{DVec2, DVec3};

use super::{MAX_POWER_COEFFICIENTS, NurbsSurface};
use crate::geom::ParametricSurface;

/// How far the power form's point and first derivatives may differ from the standard
/// algorithm's, relative to the largest of their lengths (or 1 mm).
const POWER_FORM_REL_TOL: f64 = 1e-12;

/// `tangents_at` gives exactly (every bit) the point and first derivatives of
/// `derivatives_at`, for rational surfaces of the specialised and the general degrees.
#[test]
fn tangents_are_the_first_derivatives_bit_for_bit() {
    for degree in [[3, 3], [2, 2], [2, 1], [1, 2], [3, 2], [4, 1]] {
        let (n_u, n_v) = (degree[0] + 3, degree[1] + 2);
        let clamped = |p: usize, n: usize| {
            let mut k = vec![0.0; p + 1];
            for i in 1..n - p {
                k.push(i as f64 / (n - p) as f64 + 0.01 * (i * i) as f64);
            }
            let last = k.last().copied().unwrap_or(0.0) + 0.5;
            k.extend(std::iter::repeat_n(last, p + 1));
            k
        };
        let (points, weights) = wavy_net(n_u, n_v);
        let s = NurbsSurface::try_new(
            degree,
            clamped(degree[0], n_u),
            clamped(degree[1], n_v),
            &points,
            Some(&weights),
            false,
        )
        .unwrap_or_else(|e| panic!("{degree:?}: {e}"));
        let dom = s.domain();
        let mut compared = 0;
        for i in 0..=20 {
            for j in 0..=20 {
                let uv = DVec2::new(
                    dom.u.min + dom.u.width() * f64::from(i) / 20.0,
                    dom.v.min + dom.v.width() * f64::from(j) / 20.0,
                );
                let d = s.derivatives_at(uv);
                let (p, du, dv) = s.tangents_at(uv);
                assert!(p == d.point && du == d.du && dv == d.dv, "{degree:?} at {uv}");
                assert!(d.du.length() > 0.0 && d.dv.length() > 0.0, "{degree:?} at {uv}: degenerate");
                compared += 1;
            }
        }
        assert_eq!(compared, 441);
    }
}

/// An n_u × n_v net of a wavy sheet and uneven weights (1 … 1.9), for the tests below.
fn wavy_net(n_u: usize, n_v: usize) -> (Vec<Vec<DVec3>>, Vec<Vec<f64>>) {
    let points = (0..n_u)
        .map(|i| {
            (0..n_v)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    DVec3::new(10.0 * x, 7.0 * y + x, (0.7 * x + 1.3 * y).sin() * 3.0)
                })
                .collect()
        })
        .collect();
    let weights = (0..n_u).map(|i| (0..n_v).map(|j| 1.0 + 0.3 * ((i * 3 + j) % 4) as f64).collect()).collect();
    (points, weights)
}

/// A clamped knot vector for n points of degree p with uneven interior spacing, one
/// interior knot doubled when `doubled` (and p ≥ 2).
fn uneven_knots(p: usize, n: usize, doubled: bool) -> Vec<f64> {
    let mut k = vec![0.0; p + 1];
    let mut i = 1;
    while k.len() < n {
        let x = i as f64 / (n - p) as f64 + 0.01 * (i * i) as f64;
        k.push(x);
        if doubled && p >= 2 && i == 1 && k.len() < n {
            k.push(x);
        }
        i += 1;
    }
    let last = k.last().copied().unwrap_or(0.0) + 0.5;
    k.extend(std::iter::repeat_n(last, p + 1));
    k
}

/// The power form gives the point and first derivatives of the standard algorithm to
/// rounding ([`POWER_FORM_REL_TOL`] relative to the net's size), on every span (a doubled knot included),
/// at the ends and outside the domain (both extrapolate the end spans' polynomials),
/// for rational nets of the specialised and general degrees.
#[test]
fn power_form_tangents_agree_with_the_standard_algorithm() {
    let cases = [([3, 3], true), ([2, 2], false), ([2, 1], true), ([1, 2], false), ([3, 2], true), ([5, 4], true)];
    for ((degree, doubled), rational) in cases.into_iter().flat_map(|c| [(c, true), (c, false)]) {
        let (n_u, n_v) = (degree[0] + 5, degree[1] + 4);
        let (points, weights) = wavy_net(n_u, n_v);
        let s = NurbsSurface::try_new(
            degree,
            uneven_knots(degree[0], n_u, doubled),
            uneven_knots(degree[1], n_v, doubled),
            &points,
            rational.then_some(weights.as_slice()),
            false,
        )
        .unwrap_or_else(|e| panic!("{degree:?}: {e}"));
        let power = s.power_form().unwrap_or_else(|| panic!("{degree:?}: no power form"));
        // Unit weights take the polynomial path.
        assert_eq!(power.is_polynomial(), !rational, "{degree:?}");
        let dom = s.domain();
        let mut worst = 0.0f64;
        for i in -2..=62 {
            for j in -2..=62 {
                let uv = DVec2::new(
                    dom.u.min + dom.u.width() * f64::from(i) / 60.0,
                    dom.v.min + dom.v.width() * f64::from(j) / 60.0,
                );
                let (p, du, dv) = s.tangents_at(uv);
                let (fp, fdu, fdv) = s.tangents_fast_at(uv);
                let scale = p.length().max(du.length()).max(dv.length()).max(1.0);
                let err = (fp - p).length().max((fdu - du).length()).max((fdv - dv).length()) / scale;
                worst = worst.max(err);
            }
        }
        assert!(worst < POWER_FORM_REL_TOL, "{degree:?} (rational {rational}): relative difference {worst:e}");
    }
}

/// A net whose power form would exceed [`MAX_POWER_COEFFICIENTS`] keeps none and
/// evaluates by the standard algorithm (the same bits).
#[test]
fn a_net_too_large_for_the_power_form_falls_back() {
    let (p, n) = (9, 40);
    let points: Vec<Vec<DVec3>> =
        (0..n).map(|i| (0..n).map(|j| DVec3::new(i as f64, j as f64, ((i * j) % 7) as f64)).collect()).collect();
    let s = NurbsSurface::try_new([p, p], uneven_knots(p, n, false), uneven_knots(p, n, false), &points, None, false)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!((n - p) * (n - p) * (p + 1) * (p + 1) > MAX_POWER_COEFFICIENTS);
    assert!(s.power_form().is_none());
    let uv = DVec2::new(0.37, 0.61);
    assert_eq!(s.tangents_fast_at(uv), s.tangents_at(uv));
}
