//! NURBS evaluation: exact conics from rational quadratics, derivatives against finite
//! differences, the B-spline basis' partition of unity, and knot-vector validation.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::{DVec2, DVec3};
use interpolab::geom::nurbs::{NurbsError, basis_derivatives, basis_functions, find_span, validate_knots};
use interpolab::geom::{NurbsCurve, NurbsSurface, ParametricSurface};

/// The full circle of radius `r` in the xy-plane as a 9-point rational quadratic.
fn circle(r: f64) -> NurbsCurve {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let pts: Vec<DVec3> =
        [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.), (1., 0.)]
            .iter()
            .map(|&(x, y)| DVec3::new(x * r, y * r, 0.0))
            .collect();
    let weights = [1.0, w, 1.0, w, 1.0, w, 1.0, w, 1.0];
    let knots = vec![0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0];
    NurbsCurve::try_new(2, knots, &pts, Some(&weights)).expect("valid circle")
}

#[test]
fn rational_quadratic_circle_lies_on_its_circle_to_1e_12() {
    let r = 37.5;
    let c = circle(r);
    for i in 0..=4000 {
        let u = i as f64 / 4000.0;
        let [p, d1, d2] = c.derivatives_at(u);
        assert!((p.length() - r).abs() < 1e-12 * r, "|p| = {} at u = {u}", p.length());
        // Tangent ⊥ radius; curvature of a circle is 1/r.
        assert!(p.dot(d1).abs() < 1e-9 * r * d1.length(), "p·p' = {} at u = {u}", p.dot(d1));
        let kappa = d1.cross(d2).length() / d1.length().powi(3);
        assert!((kappa - 1.0 / r).abs() < 1e-9 / r, "curvature {kappa} at u = {u}");
    }
}

#[test]
fn nurbs_cylinder_patch_lies_on_the_cylinder() {
    // Quarter cylinder, radius 12, axis z, height 30: rational quadratic × linear.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = [(12.0, 0.0, 1.0), (12.0, 12.0, w), (0.0, 12.0, 1.0)];
    let points: Vec<Vec<DVec3>> =
        arc.iter().map(|&(x, y, _)| vec![DVec3::new(x, y, 0.0), DVec3::new(x, y, 30.0)]).collect();
    let weights: Vec<Vec<f64>> = arc.iter().map(|&(_, _, w)| vec![w, w]).collect();
    let s = NurbsSurface::try_new(
        [2, 1],
        vec![0., 0., 0., 1., 1., 1.],
        vec![0., 0., 1., 1.],
        &points,
        Some(&weights),
        false,
    )
    .expect("valid");
    let mut rng = Rng::new(5);
    for _ in 0..500 {
        let uv = DVec2::new(rng.next_f64(), rng.next_f64());
        let d = s.derivatives_at(uv);
        let radial = DVec3::new(d.point.x, d.point.y, 0.0);
        assert!((radial.length() - 12.0).abs() < 1e-12 * 12.0);
        assert!((d.point.z - 30.0 * uv.y).abs() < 1e-12);
        // r_u × r_v: the arc runs counter-clockwise and v up, so the normal points outward.
        assert!((d.normal - radial / 12.0).length() < 1e-12);
    }
}

#[test]
fn curve_derivatives_match_central_differences() {
    let pts: Vec<DVec3> =
        (0..8).map(|i| DVec3::new(i as f64 * 5.0, (i as f64 * 0.9).sin() * 7.0, (i * i) as f64 * 0.3)).collect();
    let weights = [1.0, 0.5, 2.0, 1.0, 0.7, 1.3, 1.0, 0.9];
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.4, 0.45, 0.8, 1.0, 1.0, 1.0, 1.0];
    let c = NurbsCurve::try_new(3, knots, &pts, Some(&weights)).expect("valid");
    let h = 1e-6;
    for i in 1..200 {
        let u = i as f64 / 200.0;
        let [_, d1, d2] = c.derivatives_at(u);
        let fd1 = (c.point_at(u + h) - c.point_at(u - h)) / (2.0 * h);
        let fd2 = (c.derivatives_at(u + h)[1] - c.derivatives_at(u - h)[1]) / (2.0 * h);
        assert!((fd1 - d1).length() < 1e-5 * (1.0 + d1.length()), "C' at {u}: {d1:?} vs {fd1:?}");
        assert!((fd2 - d2).length() < 1e-4 * (1.0 + d2.length()), "C'' at {u}: {d2:?} vs {fd2:?}");
    }
}

#[test]
fn basis_functions_sum_to_one_and_their_derivatives_to_zero() {
    let knots = [0.0, 0.0, 0.0, 0.0, 0.2, 0.2, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0];
    let n_points = knots.len() - 4;
    let mut rng = Rng::new(9);
    for _ in 0..300 {
        let u = rng.next_f64();
        let span = find_span(&knots, n_points, 3, u);
        assert!(knots[span] <= u && u < knots[span + 1]);
        let d = basis_derivatives(&knots, span, 3, u);
        let s0: f64 = d[0][..4].iter().sum();
        let s1: f64 = d[1][..4].iter().sum();
        let s2: f64 = d[2][..4].iter().sum();
        assert!((s0 - 1.0).abs() < 1e-14 && s1.abs() < 1e-11 && s2.abs() < 1e-9, "sums {s0} {s1} {s2}");
        assert!(d[0][..4].iter().all(|&n| n >= -1e-15), "basis functions are non-negative");
    }
}

/// N_{i,p}(u) by the Cox–de Boor recursion (0/0 = 0), independent of the library's tables.
fn cox_de_boor(knots: &[f64], i: usize, p: usize, u: f64) -> f64 {
    if p == 0 {
        return if knots[i] <= u && u < knots[i + 1] { 1.0 } else { 0.0 };
    }
    let a = knots[i + p] - knots[i];
    let b = knots[i + p + 1] - knots[i + 1];
    let left = if a > 0.0 { (u - knots[i]) / a * cox_de_boor(knots, i, p - 1, u) } else { 0.0 };
    let right = if b > 0.0 { (knots[i + p + 1] - u) / b * cox_de_boor(knots, i + 1, p - 1, u) } else { 0.0 };
    left + right
}

/// The point-only paths (unrolled for degrees 1 to 3, generic above) give exactly the bits of
/// the full evaluation, and the basis functions agree with Cox–de Boor.
#[test]
fn point_only_evaluation_is_the_full_evaluation_bit_for_bit() {
    let mut rng = Rng::new(17);
    for p in 1..=5usize {
        for q in 1..=4usize {
            let (n_u, n_v) = (p + 3, q + 2);
            let clamped = |n: usize, d: usize, rng: &mut Rng| -> Vec<f64> {
                let mut inner: Vec<f64> = (0..n - d - 1).map(|_| rng.range(0.05, 0.95)).collect();
                inner.sort_by(f64::total_cmp);
                let mut k = vec![0.0; d + 1];
                k.extend(inner);
                k.extend(vec![1.0; d + 1]);
                k
            };
            let (ku, kv) = (clamped(n_u, p, &mut rng), clamped(n_v, q, &mut rng));
            let points: Vec<Vec<DVec3>> = (0..n_u)
                .map(|i| (0..n_v).map(|j| DVec3::new(i as f64 * 10.0, j as f64 * 10.0, rng.range(-5.0, 5.0))).collect())
                .collect();
            let weights: Vec<Vec<f64>> = (0..n_u).map(|_| (0..n_v).map(|_| rng.range(0.5, 2.0)).collect()).collect();
            let s = NurbsSurface::try_new([p, q], ku.clone(), kv, &points, Some(&weights), false).expect("valid");
            for _ in 0..200 {
                let uv = DVec2::new(rng.next_f64(), rng.next_f64());
                let full = s.derivatives_at(uv).point;
                let point = s.point_at(uv);
                assert_eq!(
                    point.to_array().map(f64::to_bits),
                    full.to_array().map(f64::to_bits),
                    "p {p} q {q} at {uv}"
                );
                let span = find_span(&ku, n_u, p, uv.x);
                let n = basis_functions(&ku, span, p, uv.x);
                let d = basis_derivatives(&ku, span, p, uv.x);
                for j in 0..=p {
                    assert_eq!(n[j].to_bits(), d[0][j].to_bits(), "p {p}: N_{j}");
                    let reference = cox_de_boor(&ku, span - p + j, p, uv.x);
                    assert!((n[j] - reference).abs() < 1e-14, "p {p}: N_{j} {} vs {reference}", n[j]);
                }
            }
        }
    }
}

#[test]
fn bad_knot_vectors_are_named() {
    assert_eq!(validate_knots(&[0., 0., 1., 1.], 2, 1), Ok(()));
    assert!(matches!(validate_knots(&[0., 0., 1.], 2, 1), Err(NurbsError::KnotCount { expected: 4, .. })));
    assert!(matches!(validate_knots(&[0., 0., 0.5, 0.2, 1., 1.], 4, 1), Err(NurbsError::Decreasing { index: 3, .. })));
    assert!(matches!(
        validate_knots(&[0., 0.1, 0.5, 1., 1., 1.], 3, 2),
        Err(NurbsError::NotClamped { end: "start", .. })
    ));
    assert!(matches!(
        validate_knots(&[0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1.], 6, 2),
        Err(NurbsError::Multiplicity { multiplicity: 3, .. })
    ));
    assert!(matches!(validate_knots(&[1., 1., 1., 1.], 2, 1), Err(NurbsError::EmptyRange)));
    assert!(matches!(validate_knots(&[0., 0., 0.], 2, 0), Err(NurbsError::Degree(0))));
    assert!(matches!(validate_knots(&[0., 0., 1., 1.], 1, 1), Err(NurbsError::TooFewPoints { .. })));
    let w = [1.0, -1.0];
    let pts = [DVec3::ZERO, DVec3::X];
    assert!(matches!(
        NurbsCurve::try_new(1, vec![0., 0., 1., 1.], &pts, Some(&w)),
        Err(NurbsError::Weight { index: 1, .. })
    ));
}
