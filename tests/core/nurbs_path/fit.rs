//! NURBS fitting (seed 004): interpolation through points, approximation to a tolerance,
//! checked against closed forms (circle, parabola) by distance computations written here,
//! independently of the library's own measuring code.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::geom::{Curve3, NurbsCurve};
use interpolab::nurbs_path::{
    ApproxOptions, EndCondition, FitError, InterpolateOptions, KnotRule, Parabola, Parametrization, approximate_curve,
    approximate_points, interpolate, parameters,
};

/// A circle of radius r in the plane z = h, centred on the z axis, over [a0, a1] rad.
struct Arc {
    r: f64,
    h: f64,
    a0: f64,
    a1: f64,
}

impl Curve3 for Arc {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let t = s.clamp(self.a0, self.a1);
        let (sn, cs) = t.sin_cos();
        [
            DVec3::new(self.r * cs, self.r * sn, self.h),
            DVec3::new(-self.r * sn, self.r * cs, 0.0),
            DVec3::new(-self.r * cs, -self.r * sn, 0.0),
        ]
    }
    fn range(&self) -> (f64, f64) {
        (self.a0, self.a1)
    }
}

/// Exact distance from (X, Y, Z) to the parabola y = a·x² in z = 0: the foot x solves
/// 2a²x³ + (1 − 2aY)x − X = 0, found by bisection on a bracket around every sign change.
fn parabola_distance(a: f64, x0: f64, x1: f64, p: DVec3) -> f64 {
    let f = |x: f64| 2.0 * a * a * x * x * x + (1.0 - 2.0 * a * p.y) * x - p.x;
    let dist = |x: f64| ((x - p.x).powi(2) + (a * x * x - p.y).powi(2) + p.z * p.z).sqrt();
    let mut best = dist(x0).min(dist(x1));
    let n = 4000;
    for i in 0..n {
        let (mut lo, mut hi) = (x0 + (x1 - x0) * i as f64 / n as f64, x0 + (x1 - x0) * (i + 1) as f64 / n as f64);
        if f(lo) * f(hi) > 0.0 {
            continue;
        }
        for _ in 0..80 {
            let m = 0.5 * (lo + hi);
            if f(lo) * f(m) <= 0.0 {
                hi = m;
            } else {
                lo = m;
            }
        }
        best = best.min(dist(0.5 * (lo + hi)));
    }
    best
}

fn sample(c: &NurbsCurve, n: usize) -> Vec<DVec3> {
    let (a, b) = c.range();
    (0..=n).map(|i| c.point_at(a + (b - a) * i as f64 / n as f64)).collect()
}

fn helix_points(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.37 + 0.05 * (i as f64 * 1.7).sin();
            DVec3::new(20.0 * t.cos(), 15.0 * t.sin(), 2.0 * t)
        })
        .collect()
}

#[test]
fn interpolation_passes_through_every_point() {
    let pts = helix_points(23);
    for degree in 1..=5 {
        for par in [Parametrization::Uniform, Parametrization::ChordLength, Parametrization::Centripetal] {
            for end in [
                EndCondition::Free,
                EndCondition::EstimatedTangents,
                EndCondition::Tangents { start: DVec3::X, end: DVec3::new(1.0, 1.0, 0.0) },
            ] {
                if degree == 1 && end != EndCondition::Free {
                    continue;
                }
                let o = InterpolateOptions::default().with_degree(degree).with_parametrization(par).with_end(end);
                let c = interpolate(&pts, &o).unwrap_or_else(|e| panic!("degree {degree} {par:?} {end:?}: {e}"));
                let u = parameters(&pts, par).expect("parameters");
                for (k, q) in pts.iter().enumerate() {
                    let d = (c.point_at(u[k]) - *q).length();
                    assert!(d < 1e-9, "degree {degree} {par:?} {end:?}: point {k} missed by {d:e} mm");
                }
            }
        }
    }
}

#[test]
fn end_tangents_are_the_given_directions() {
    let pts = helix_points(9);
    let (t0, t1) = (DVec3::new(0.0, 1.0, 0.2), DVec3::new(-1.0, 0.3, 0.0));
    let c = interpolate(&pts, &InterpolateOptions::default().with_end(EndCondition::Tangents { start: t0, end: t1 }))
        .expect("fit");
    let (a, b) = c.range();
    let d0 = c.derivatives_at(a)[1];
    let d1 = c.derivatives_at(b)[1];
    assert!(d0.normalize().cross(t0.normalize()).length() < 1e-12 && d0.dot(t0) > 0.0, "start tangent {d0}");
    assert!(d1.normalize().cross(t1.normalize()).length() < 1e-12 && d1.dot(t1) > 0.0, "end tangent {d1}");
    // Chord-length parameters: the given tangent gets unit parametric speed at the ends.
    interpolab::assert_near!(d0.length(), 1.0, 1e-12);
    interpolab::assert_near!(d1.length(), 1.0, 1e-12);
}

#[test]
fn papers_cubic_with_knots_at_the_chord_length_parameters() {
    // Seed 004: cubic, cumulative chord length, knots at the parameters, end tangents.
    let pts: Vec<DVec3> = (0..=8)
        .map(|i| {
            let x = -40.0 + 10.0 * i as f64;
            DVec3::new(x, x * x / 40.0, 0.0)
        })
        .collect();
    let o = InterpolateOptions::default()
        .with_knots(KnotRule::AtParameters)
        .with_end(EndCondition::Tangents { start: DVec3::new(1.0, -2.0, 0.0), end: DVec3::new(1.0, 2.0, 0.0) });
    let c = interpolate(&pts, &o).expect("cubic spline");
    let u = parameters(&pts, Parametrization::ChordLength).expect("parameters");
    assert_eq!(c.len(), pts.len() + 2, "n + 3 control points");
    assert_eq!(&c.knots()[4..c.knots().len() - 4], &u[1..u.len() - 1], "interior knots are the parameters");
    for (k, q) in pts.iter().enumerate() {
        assert!((c.point_at(u[k]) - *q).length() < 1e-9);
    }
    // Between the points the cubic stays close to the parabola (tangents are exact).
    let worst = sample(&c, 2000).iter().map(|p| parabola_distance(1.0 / 40.0, -40.0, 40.0, *p)).fold(0.0, f64::max);
    assert!(worst < 0.05, "interpolant strays {worst} mm from the parabola");
}

#[test]
fn knots_at_parameters_are_refused_where_they_do_not_fit() {
    let pts = helix_points(10);
    let e = interpolate(&pts, &InterpolateOptions::default().with_degree(4).with_knots(KnotRule::AtParameters))
        .unwrap_err();
    assert!(matches!(e, FitError::KnotRule { degree: 4, tangents: true }), "{e}");
    assert!(e.to_string().contains("averaging"), "{e}");
}

#[test]
fn circle_fit_stays_within_tolerance() {
    for (tol, r) in [(0.01, 25.0), (0.001, 25.0), (0.01, 3.0)] {
        let arc = Arc { r, h: 7.0, a0: 0.3, a1: 0.3 + 1.9 * std::f64::consts::PI };
        let fit = approximate_curve(&arc, tol, &ApproxOptions::default()).expect("fit");
        // Independent check: distance to the full circle is sqrt((ρ − r)² + (z − h)²); the
        // fit's angles must cover the arc without leaving it.
        let mut last_angle = 0.3;
        for p in sample(&fit.curve, 20_000) {
            let rho = p.x.hypot(p.y);
            let d = ((rho - r).powi(2) + (p.z - 7.0).powi(2)).sqrt();
            assert!(d <= tol, "r {r} tol {tol}: point {p} is {d} mm from the circle");
            let mut ang = p.y.atan2(p.x);
            while ang < last_angle - 0.5 {
                ang += std::f64::consts::TAU;
            }
            assert!(ang >= last_angle - 1e-9, "the fit turns back at {p}");
            last_angle = ang;
        }
        interpolab::assert_near!(last_angle, arc.a1, 1e-12);
        assert!(fit.curve.len() < 40, "r {r} tol {tol}: {} control points", fit.curve.len());
    }
}

#[test]
fn parabola_fit_stays_within_tolerance() {
    let para = Parabola::paper_like();
    for tol in [0.01, 0.002] {
        let fit = approximate_curve(&para, tol, &ApproxOptions::default()).expect("fit");
        let worst = sample(&fit.curve, 3000)
            .iter()
            .map(|p| parabola_distance(para.a, para.x0, para.x1, *p))
            .fold(0.0, f64::max);
        assert!(worst <= tol, "tol {tol}: worst {worst}");
        assert!(
            fit.max_deviation_mm <= tol && fit.max_deviation_mm > 0.3 * worst,
            "reported {} vs independent {worst}",
            fit.max_deviation_mm
        );
        let start = fit.curve.point_at(fit.curve.range().0);
        let end = fit.curve.point_at(fit.curve.range().1);
        assert!(
            (start - para.point_at(para.x0)).length() < 1e-12 && (end - para.point_at(para.x1)).length() < 1e-12,
            "ends are interpolated"
        );
    }
}

/// Controllers that imply uniform knots (Sinumerik one PL, LinuxCNC G5.2) get a fit with
/// equal spans (a quantum does not apply), still within the tolerance.
#[test]
fn uniform_fit_has_equal_spans_and_stays_within_tolerance() {
    let para = Parabola::paper_like();
    let opts = ApproxOptions::default().with_uniform_knots(true).with_knot_quantum(Some(0.001));
    for tol in [0.01, 0.002] {
        let fit = approximate_curve(&para, tol, &opts).expect("fit");
        let c = &fit.curve;
        let k = c.knots();
        let p = c.degree();
        let spans: Vec<f64> = k[p..k.len() - p].windows(2).map(|w| w[1] - w[0]).collect();
        assert_eq!(spans.len(), c.len() - p, "no repeated interior knots");
        assert!(spans.iter().all(|h| (h - spans[0]).abs() < 1e-9 * spans[0].max(1.0)), "{spans:?}");
        let worst = sample(c, 3000).iter().map(|q| parabola_distance(para.a, para.x0, para.x1, *q)).fold(0.0, f64::max);
        assert!(worst <= tol, "tol {tol}: worst {worst}");
        // Equal spans cannot follow the parabola's curvature: more control points than the
        // refined and equidistributed fit.
        let free = approximate_curve(&para, tol, &ApproxOptions::default()).expect("fit");
        assert!(c.len() > free.curve.len(), "{} vs {}", c.len(), free.curve.len());
    }
}

#[test]
fn tighter_tolerance_needs_more_control_points() {
    let para = Parabola::paper_like();
    let counts: Vec<usize> = [0.1, 0.01, 0.001, 0.0001]
        .iter()
        .map(|&t| approximate_curve(&para, t, &ApproxOptions::default()).expect("fit").curve.len())
        .collect();
    assert!(counts.windows(2).all(|w| w[0] <= w[1]) && counts[0] < counts[3], "{counts:?}");
}

#[test]
fn knots_are_multiples_of_the_quantum() {
    let arc = Arc { r: 12.0, h: 0.0, a0: 0.0, a1: 3.0 };
    let fit = approximate_curve(&arc, 0.005, &ApproxOptions::default().with_knot_quantum(Some(0.001))).expect("fit");
    for k in fit.curve.knots() {
        let q = k / 0.001;
        assert!((q - q.round()).abs() < 1e-6, "knot {k} is not a multiple of 0.001");
    }
    assert!(fit.max_deviation_mm <= 0.005);
}

#[test]
fn point_approximation_holds_every_point_with_few_control_points() {
    let pts: Vec<DVec3> = (0..400)
        .map(|i| {
            let x = i as f64 * 0.25;
            DVec3::new(x, 8.0 * (x / 9.0).sin(), 0.5 * (x / 15.0).cos())
        })
        .collect();
    for tol in [0.01, 0.001] {
        let fit = approximate_points(&pts, tol, Parametrization::ChordLength, &ApproxOptions::default()).expect("fit");
        assert!(
            !fit.interpolates && fit.curve.len() < pts.len() / 5,
            "tol {tol}: {} control points for {} points",
            fit.curve.len(),
            pts.len()
        );
        // Independent check against a dense polyline of the fit (its own sag is far below tol).
        let poly = sample(&fit.curve, 40_000);
        for (k, q) in pts.iter().enumerate() {
            let d = poly.windows(2).map(|w| seg_dist(*q, w[0], w[1])).fold(f64::INFINITY, f64::min);
            assert!(d <= tol * 1.0001, "tol {tol}: point {k} is {d} mm away");
        }
    }
}

fn seg_dist(x: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (a + t * ab - x).length()
}

#[test]
fn point_approximation_of_few_points_falls_back_to_interpolation() {
    let pts = helix_points(6);
    let fit = approximate_points(&pts, 1e-9, Parametrization::Centripetal, &ApproxOptions::default()).expect("fit");
    assert!(fit.interpolates);
    let u = parameters(&pts, Parametrization::Centripetal).expect("parameters");
    for (k, q) in pts.iter().enumerate() {
        assert!((fit.curve.point_at(u[k]) - *q).length() < 1e-9);
    }
}

#[test]
fn bad_fitting_input_is_refused_with_the_reason() {
    let pts = helix_points(8);
    let e = interpolate(&pts[..3], &InterpolateOptions::default().with_end(EndCondition::Free)).unwrap_err();
    assert!(
        matches!(e, FitError::TooFewPoints { got: 3, need: 4, degree: 3 }) && e.to_string().contains("need at least 4"),
        "{e}"
    );
    let mut dup = pts.clone();
    dup[4] = dup[3];
    let e = interpolate(&dup, &InterpolateOptions::default()).unwrap_err();
    assert!(matches!(e, FitError::DuplicatePoint { index: 4 }) && e.to_string().contains("point 4"), "{e}");
    let e = interpolate(
        &pts,
        &InterpolateOptions::default().with_end(EndCondition::Tangents { start: DVec3::ZERO, end: DVec3::X }),
    )
    .unwrap_err();
    assert!(matches!(e, FitError::ZeroTangent { end: "start" }), "{e}");
    let mut nan = pts.clone();
    nan[2].y = f64::NAN;
    assert!(matches!(interpolate(&nan, &InterpolateOptions::default()).unwrap_err(), FitError::NotFinite { index: 2 }));
    assert!(matches!(
        interpolate(&pts, &InterpolateOptions::default().with_degree(0)).unwrap_err(),
        FitError::Degree(0)
    ));
    for tol in [0.0, -1.0, f64::NAN] {
        let e = approximate_curve(&Parabola::paper_like(), tol, &ApproxOptions::default()).unwrap_err();
        assert!(matches!(e, FitError::BadTolerance { .. }) && e.to_string().contains("positive"), "{e}");
    }
    let flat = Parabola { a: 0.1, x0: 1.0, x1: 1.0, z: 0.0 };
    assert!(matches!(approximate_curve(&flat, 0.01, &ApproxOptions::default()).unwrap_err(), FitError::EmptyCurve));
}

#[test]
fn approximation_of_the_crease_is_within_tolerance() {
    let job = support::job(include_str!("../../../examples/rational-nurbs-vault.json"));
    let design = interpolab::gcode::crease_design(&job).expect("crease");
    let fit = approximate_curve(&design, 0.005, &ApproxOptions::default()).expect("fit");
    assert!(fit.max_deviation_mm <= 0.005);
    // Independent of the fit's own check: every crease row lies within tolerance of a dense
    // polyline of the fit.
    let poly = sample(&fit.curve, 20_000);
    for p in design.path().points().iter().step_by(7) {
        let d = poly.windows(2).map(|w| seg_dist(*p, w[0], w[1])).fold(f64::INFINITY, f64::min);
        assert!(d <= 0.005 * 1.0001, "row {p} is {d} mm from the fit");
    }
}
