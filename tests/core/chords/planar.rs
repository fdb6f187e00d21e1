//! Seed 003 on planar curves: the general equal-error search against the paper's own
//! construction on the parabola, closed-form radii of the test curves, and the comparison
//! with equal-interval and equal-step nodes.
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use interpolab::assert_near;
use interpolab::chords::planar::{
    FnCurve, Sizing, Spacing, min_radius, parabola_paper_nodes, seed003_ellipse, seed003_hyperbola, seed003_parabola,
    spacing_nodes,
};
use interpolab::chords::{
    ChordOptions, DeviationOptions, SearchOptions, chord_deviation, distance_to_segment, equal_error_chords, next_node,
};
use interpolab::geom::Curve3;

/// Largest distance from the parabola y = a·x² over [x0, x1] to its chord, by brute force.
fn parabola_chord_deviation(a: f64, x0: f64, x1: f64) -> f64 {
    let p = |x: f64| glam::DVec3::new(x, a * x * x, 0.0);
    (0..=20_000)
        .map(|i| distance_to_segment(p(x0 + (x1 - x0) * f64::from(i) / 20_000.0), p(x0), p(x1)))
        .fold(0.0, f64::max)
}

#[test]
fn the_papers_construction_gives_chords_of_exactly_d() {
    let par = seed003_parabola();
    for d in [0.05, 0.01] {
        let nodes = parabola_paper_nodes(par.a, par.x0, par.x1, d).unwrap();
        for (i, w) in nodes.windows(2).enumerate() {
            let dev = parabola_chord_deviation(par.a, w[0], w[1]);
            if i + 2 < nodes.len() {
                assert_near!(dev, d, 1e-7, "chord {i} at d = {d}");
            } else {
                assert!(dev <= d + 1e-9);
            }
        }
    }
}

#[test]
fn the_general_search_reproduces_the_papers_parabola_nodes() {
    let par = seed003_parabola();
    let opts = SearchOptions::default();
    for d in [0.05, 0.01] {
        let paper = parabola_paper_nodes(par.a, par.x0, par.x1, d).unwrap();
        let general = equal_error_chords(&par, d).unwrap();
        assert_eq!(general.len(), paper.len(), "node count at d = {d}");
        // Step by step from the paper's own nodes, the search lands on the paper's next
        // node to within what its acceptance window [d − ε, d] allows: δL ≈ L·ε/(2d).
        let eps = opts.window_for(d);
        for w in paper.windows(2).take(paper.len() - 2) {
            let err =
                |x: f64| -> Result<f64, ()> { Ok(chord_deviation(&par, w[0], x, &DeviationOptions::default()).max_mm) };
            let node = next_node(err, w[0], par.x1, 0.5 * (w[1] - w[0]), d, &opts).unwrap();
            let len = w[1] - w[0];
            assert!((node.s - w[1]).abs() <= len * eps / d, "from x = {}: {} vs the paper's {}", w[0], node.s, w[1]);
        }
    }
}

#[test]
fn test_curves_have_their_closed_form_smallest_radius() {
    let (s, rho) = min_radius(&seed003_parabola());
    assert_near!(s, 0.0, 1e-9);
    assert_near!(rho, 1.0 / (2.0 * 0.025), 1e-9);
    let (s, rho) = min_radius(&seed003_hyperbola());
    assert_near!(s, 20.0, 1e-4);
    assert_near!(rho, 800f64.sqrt(), 1e-7);
    let (_, rho) = min_radius(&seed003_ellipse());
    assert_near!(rho, 30.0 * 30.0 / 60.0, 1e-9);
}

#[test]
fn equal_error_needs_the_fewest_nodes_of_every_spacing_within_d() {
    for d in [0.05, 0.01] {
        let curves: [&dyn Curve3; 3] = [&seed003_parabola(), &seed003_hyperbola(), &seed003_ellipse()];
        for c in curves {
            let rows: Vec<_> =
                Spacing::ALL.iter().map(|&sp| spacing_nodes(c, d, sp, &ChordOptions::default()).unwrap()).collect();
            let ee = &rows[0];
            assert!(ee.worst_mm() <= d);
            for r in &rows[1..] {
                if r.worst_mm() <= d {
                    assert!(
                        ee.params.len() <= r.params.len(),
                        "{}: {} < {} equal-error nodes",
                        r.spacing.label(),
                        r.params.len(),
                        ee.params.len()
                    );
                }
            }
            // The widest uniform spacings are within d by construction and one part more
            // would not be.
            for r in rows.iter().filter(|r| {
                matches!(r.spacing, Spacing::EqualInterval(Sizing::Widest) | Spacing::EqualStep(Sizing::Widest))
            }) {
                assert!(r.worst_mm() <= d, "{}: {}", r.spacing.label(), r.worst_mm());
            }
        }
    }
}

#[test]
fn sizing_by_the_smallest_radius_fails_on_a_steep_hyperbola() {
    // Equal Δx sized at the vertex: at x = 5 the slope is −16, so the same Δx gives a chord
    // 16 times longer on a curve only ~30 times flatter — it deviates by more than d there.
    let row =
        spacing_nodes(&seed003_hyperbola(), 0.05, Spacing::EqualInterval(Sizing::MinRadius), &ChordOptions::default())
            .unwrap();
    assert!(row.worst_mm() > 0.05, "{}", row.worst_mm());
}

#[test]
fn a_curve_given_as_a_function_matches_its_analytic_twin() {
    let e = seed003_ellipse();
    let f = FnCurve::new(|t: f64| glam::DVec2::new(60.0 * t.cos(), 30.0 * t.sin()), (e.t0, e.t1));
    let a = equal_error_chords(&e, 0.01).unwrap();
    let b = equal_error_chords(&f, 0.01).unwrap();
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_near!(*x, *y, 1e-4);
    }
}
