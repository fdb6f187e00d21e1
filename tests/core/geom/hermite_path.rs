//! The Hermite design path: it passes through its points with their tangents, and the
//! segment lookup agrees with a plain search for evenly and very unevenly spaced points.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::DVec3;
use interpolab::geom::{Curve3, HermitePath};

fn helix(n: usize, uneven: bool) -> HermitePath {
    let mut t = 0.0;
    let mut points = Vec::new();
    let mut tangents = Vec::new();
    for i in 0..n {
        let (s, c) = f64::sin_cos(t);
        points.push(DVec3::new(30.0 * c, 30.0 * s, 4.0 * t));
        tangents.push(DVec3::new(-30.0 * s, 30.0 * c, 4.0).normalize());
        // Uneven: steps alternate between 0.001 and 0.05 rad, with a burst of tiny ones.
        t += if uneven { if i % 7 == 0 || (200..260).contains(&i) { 0.001 } else { 0.05 } } else { 0.01 };
    }
    HermitePath::new(points, tangents).expect("valid")
}

#[test]
fn segment_lookup_matches_a_linear_scan() {
    let mut rng = Rng::new(21);
    for uneven in [false, true] {
        let path = helix(800, uneven);
        let params = path.params();
        for _ in 0..3000 {
            let s = rng.range(-1.0, path.length() + 1.0);
            let expect = if s <= params[0] {
                0
            } else if s >= path.length() {
                params.len() - 2
            } else {
                params.windows(2).position(|w| w[0] <= s && s < w[1]).expect("inside")
            };
            assert_eq!(path.segment(s), expect, "s = {s}, uneven = {uneven}");
        }
    }
}

#[test]
fn path_passes_through_its_points_with_their_tangents() {
    let path = helix(300, true);
    for (i, (&s, p)) in path.params().iter().zip(path.points()).enumerate() {
        let [c, d, _] = path.derivatives_at(s);
        assert!((c - *p).length() < 1e-9, "point {i}");
        assert!((d.length() - 1.0).abs() < 1e-9, "unit speed at the points (chord-length parameter)");
    }
    // Between points it stays on the helix far below a micrometre (h = 0.5 mm, ρ ≈ 30 mm).
    let even = helix(300, false);
    for k in 0..1000 {
        let s = even.length() * k as f64 / 1000.0;
        let p = even.point_at(s);
        let r = (p.x * p.x + p.y * p.y).sqrt();
        assert!((r - 30.0).abs() < 1e-6, "radius {r} at s = {s}");
    }
}
