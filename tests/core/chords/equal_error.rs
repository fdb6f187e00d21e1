//! `equal_error_chords` on curves with closed forms (circle, helix, the crease of a floor and
//! a round wall), on curves with inflections and narrow bulges checked by dense re-sampling,
//! and on bad input.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::assert_near;
use interpolab::chords::{
    ChordError, ChordOptions, DeviationOptions, RootMethod, chord_deviation, distance_to_segment, equal_error_chords,
    equal_error_chords_with,
};
use interpolab::crease::{CreaseCurve, InterpOptions, run_to_end};
use interpolab::geom::Curve3;

/// A helix of radius `r` and rise `pitch_per_rad` per radian, parametrised by `k` units of s
/// per radian over `[0, k·turn_rad]`. `pitch_per_rad = 0` is a circle in z = 0.
struct Helix {
    r: f64,
    pitch_per_rad: f64,
    k: f64,
    turn_rad: f64,
}

impl Curve3 for Helix {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let s = s.clamp(0.0, self.k * self.turn_rad);
        let (t, w) = (s / self.k, 1.0 / self.k);
        let (sn, cs) = t.sin_cos();
        [
            DVec3::new(self.r * cs, self.r * sn, self.pitch_per_rad * t),
            DVec3::new(-self.r * sn, self.r * cs, self.pitch_per_rad) * w,
            DVec3::new(-self.r * cs, -self.r * sn, 0.0) * (w * w),
        ]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, self.k * self.turn_rad)
    }
}

/// A planar graph y = f(x) in z = 0, parametrised by x, with f given with two derivatives.
struct Graph<F: Fn(f64) -> [f64; 3]> {
    f: F,
    x: [f64; 2],
}

impl<F: Fn(f64) -> [f64; 3]> Curve3 for Graph<F> {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let x = s.clamp(self.x[0], self.x[1]);
        let [y, dy, ddy] = (self.f)(x);
        [DVec3::new(x, y, 0.0), DVec3::new(1.0, dy, 0.0), DVec3::new(0.0, ddy, 0.0)]
    }
    fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[1])
    }
}

/// Largest distance from the arc to the chord by brute force: `n` equal parameter samples.
fn dense_deviation(curve: &dyn Curve3, s0: f64, s1: f64, n: usize) -> f64 {
    let (a, b) = (curve.point_at(s0), curve.point_at(s1));
    (0..=n).map(|i| distance_to_segment(curve.point_at(s0 + (s1 - s0) * i as f64 / n as f64), a, b)).fold(0.0, f64::max)
}

/// Every chord within d by dense re-sampling, every chord but the last at least 0.9·d.
fn assert_equal_error(curve: &dyn Curve3, nodes: &[f64], d: f64) {
    assert!(nodes.len() >= 2);
    assert_eq!(nodes[0], curve.range().0);
    assert_eq!(nodes[nodes.len() - 1], curve.range().1);
    for (i, w) in nodes.windows(2).enumerate() {
        assert!(w[1] > w[0], "nodes must increase: {w:?}");
        let dev = dense_deviation(curve, w[0], w[1], 4000);
        assert!(dev <= d * (1.0 + 1e-9), "chord {i} deviates {dev} > {d}");
        if i + 2 < nodes.len() {
            assert!(dev >= 0.9 * d, "chord {i} deviates only {dev} < 0.9·{d}: nodes denser than needed");
        }
    }
}

/// Closed form for an arc of radius ρ and angle Θ: each chord spans θ = 2·acos(1 − d/ρ),
/// so ⌈Θ/θ⌉ chords.
fn circle_chord_count(rho: f64, arc_rad: f64, d: f64) -> usize {
    let theta = 2.0 * (1.0 - d / rho).acos();
    (arc_rad / theta).ceil() as usize
}

#[test]
fn circle_chords_span_the_closed_form_angle() {
    let (rho, d): (f64, f64) = (20.0, 0.01);
    let theta = 2.0 * (1.0 - d / rho).acos();
    // Non-unit speed: 3 units of s per radian.
    let arc = Helix { r: rho, pitch_per_rad: 0.0, k: 3.0, turn_rad: 2.0 };
    let nodes = equal_error_chords(&arc, d).unwrap();
    assert_eq!(nodes.len(), circle_chord_count(rho, 2.0, d) + 1);
    for w in nodes.windows(2).take(nodes.len() - 2) {
        // Window [d − 1e-6, d] → angle within ~5e-5 relative.
        assert_near!((w[1] - w[0]) / 3.0, theta, 1e-4 * theta);
    }
    assert_equal_error(&arc, &nodes, d);
}

#[test]
fn helix_chords_have_the_circle_sagitta_whatever_the_pitch() {
    // The chord of a helix over angle θ misses the arc's midpoint by r(1 − cos θ/2) (same z,
    // radial offset), exactly as for the circle of the same radius.
    let (r, d): (f64, f64) = (15.0, 0.005);
    let helix = Helix { r, pitch_per_rad: 4.0, k: 1.0, turn_rad: 9.0 };
    let nodes = equal_error_chords(&helix, d).unwrap();
    assert_eq!(nodes.len(), circle_chord_count(r, 9.0, d) + 1);
    let theta = 2.0 * (1.0 - d / r).acos();
    assert_near!(nodes[1] - nodes[0], theta, 1e-4 * theta);
    assert_equal_error(&helix, &nodes, d);
}

#[test]
fn chords_through_inflections_stay_within_tolerance() {
    // y = 5 sin(x/4) on [0, 60]: several inflections, curvature radius down to 3.2 mm.
    let curve = Graph {
        f: |x: f64| [5.0 * (x / 4.0).sin(), 1.25 * (x / 4.0).cos(), -0.3125 * (x / 4.0).sin()],
        x: [0.0, 60.0],
    };
    for d in [0.1, 0.01, 0.001] {
        let nodes = equal_error_chords(&curve, d).unwrap();
        assert_equal_error(&curve, &nodes, d);
    }
}

#[test]
fn a_narrow_bump_is_not_missed() {
    // A straight line with a Gaussian bump 0.2 mm high and 0.5 mm wide at x = 37.3: any
    // chord spanning the bump deviates by about 0.2 mm, so with d = 0.05 nodes must crowd
    // around it and no chord may jump over it.
    let (h, w, x0) = (0.2, 0.5, 37.3);
    let f = move |x: f64| {
        let u = (x - x0) / w;
        let e = (-u * u).exp();
        [h * e, -2.0 * u / w * h * e, (4.0 * u * u - 2.0) / (w * w) * h * e]
    };
    let curve = Graph { f, x: [0.0, 100.0] };
    let d = 0.05;
    let nodes = equal_error_chords(&curve, d).unwrap();
    assert!(nodes.iter().any(|&x| (x - x0).abs() < 2.0 * w), "no node near the bump: {nodes:?}");
    assert_equal_error(&curve, &nodes, d);
}

#[test]
fn deviation_of_a_circle_chord_is_the_sagitta() {
    let arc = Helix { r: 7.0, pitch_per_rad: 0.0, k: 1.0, turn_rad: 3.0 };
    for theta in [0.01, 0.3, 1.0, 2.5] {
        let dev = chord_deviation(&arc, 0.2, 0.2 + theta, &DeviationOptions::default());
        assert_near!(dev.max_mm, 7.0 * (1.0 - (theta / 2.0).cos()), 1e-9 * 7.0, "θ = {theta}");
        assert_near!(dev.at_s, 0.2 + theta / 2.0, 1e-4 * theta);
    }
}

#[test]
fn deviation_counts_a_bulge_past_the_chord_end() {
    // Over more than half a turn the arc bulges beyond the chord's ends: the deviation is
    // then the distance to the segment (the diameter's end points), not to its line.
    let arc = Helix { r: 10.0, pitch_per_rad: 0.0, k: 1.0, turn_rad: 6.0 };
    let theta = 5.0; // > π
    let dev = chord_deviation(&arc, 0.0, theta, &DeviationOptions::default());
    let dense = dense_deviation(&arc, 0.0, theta, 200_000);
    assert_near!(dev.max_mm, dense, 1e-6);
    assert!(dev.max_mm > 10.0);
}

#[test]
fn crease_of_floor_and_round_wall_is_a_circle_of_radius_45() {
    // Ball R = 5 in a floor/cylinder (radius 50, inward) corner: the centre runs on a circle
    // of radius 45 at z = 5; the crease curve is parametrised by chord length.
    let job = support::job(include_str!("../../../examples/floor-round-wall.json"));
    let rows = run_to_end(job.clone(), InterpOptions::default()).rows;
    let curve = CreaseCurve::from_rows(&job, &rows).unwrap();
    let (s0, s1) = curve.range();
    let arc_rad = (s1 - s0) / 45.0; // chord length ≈ arc length (f = 0.1 mm, error ~1e-7)
    let d = 0.01;
    let nodes = equal_error_chords(&curve, d).unwrap();
    let expected = circle_chord_count(45.0, arc_rad, d) + 1;
    assert!((nodes.len() as i64 - expected as i64).abs() <= 1, "{} nodes, closed form {expected}", nodes.len());
    assert_equal_error(&curve, &nodes, d);
}

#[test]
fn straight_curve_needs_one_chord() {
    let line = Graph { f: |x: f64| [0.5 * x + 1.0, 0.5, 0.0], x: [-3.0, 40.0] };
    assert_eq!(equal_error_chords(&line, 1e-3).unwrap(), vec![-3.0, 40.0]);
}

#[test]
fn every_root_method_gives_equal_error_chords() {
    let curve = Graph { f: |x: f64| [0.05 * x * x, 0.1 * x, 0.1], x: [0.0, 40.0] };
    let d = 0.01;
    let mut counts = Vec::new();
    for m in RootMethod::ALL {
        let opts = ChordOptions { search: ChordOptions::default().search.with_method(m), ..ChordOptions::default() };
        let nodes = equal_error_chords_with(&curve, d, &opts).unwrap();
        assert_equal_error(&curve, &nodes.params, d);
        counts.push(nodes.len());
    }
    // Same tolerance, same node count (they differ only inside the 1e-6 mm window).
    assert!(counts.iter().all(|&c| c == counts[0]), "{counts:?}");
}

#[test]
fn bad_tolerance_is_reported() {
    let arc = Helix { r: 5.0, pitch_per_rad: 0.0, k: 1.0, turn_rad: 1.0 };
    for tol in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        match equal_error_chords(&arc, tol) {
            Err(ChordError::BadTolerance { .. }) => {}
            other => panic!("tolerance {tol}: expected BadTolerance, got {other:?}"),
        }
    }
}

#[test]
fn tolerance_below_rounding_is_an_error_not_a_hang() {
    let arc = Helix { r: 50.0, pitch_per_rad: 0.0, k: 1.0, turn_rad: 6.0 };
    let opts = ChordOptions { max_nodes: 10_000, ..ChordOptions::default() };
    match equal_error_chords_with(&arc, 1e-13, &opts) {
        Err(ChordError::TooManyNodes { .. } | ChordError::Underflow { .. }) => {}
        other => panic!("expected an error, got {:?}", other.map(|n| n.len())),
    }
}
