//! Real-time NURBS interpolation (seed 004): the three parameter updates, their feed
//! fluctuation, the chord error per period and the curvature-based feed limit.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::geom::NurbsCurve;
use interpolab::nurbs_path::realtime::chord_limited_step;
use interpolab::nurbs_path::{Parabola, RealtimeError, RealtimeOptions, RealtimeStepper, Update, interpolate_realtime};

/// A cubic Bézier whose parametric speed varies about 30-fold (3|P1 − P0| at the start,
/// 3|P3 − P2| at the end): control points crowded at the start.
fn uneven_cubic() -> NurbsCurve {
    let pts =
        [DVec3::new(0.0, 0.0, 0.0), DVec3::new(2.0, 0.4, 0.0), DVec3::new(5.0, 3.0, 1.0), DVec3::new(60.0, 20.0, 4.0)];
    NurbsCurve::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &pts, None).expect("valid cubic")
}

/// The exact rational quadratic quarter circle of radius r (weights 1, √2/2, 1).
fn quarter_circle(r: f64) -> NurbsCurve {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    NurbsCurve::try_new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        &[DVec3::new(r, 0.0, 0.0), DVec3::new(r, r, 0.0), DVec3::new(0.0, r, 0.0)],
        Some(&[1.0, w, 1.0]),
    )
    .expect("valid circle")
}

fn speed_ratio(c: &NurbsCurve) -> f64 {
    let (a, b) = c.range();
    let v: Vec<f64> = (0..=1000).map(|i| c.derivatives_at(a + (b - a) * i as f64 / 1000.0)[1].length()).collect();
    v.iter().copied().fold(0.0, f64::max) / v.iter().copied().fold(f64::INFINITY, f64::min)
}

#[test]
fn corrected_update_fluctuates_far_less_than_first_order() {
    let c = uneven_cubic();
    assert!(speed_ratio(&c) > 10.0, "the test curve must vary its parametric speed strongly");
    let stats: Vec<_> = Update::ALL
        .iter()
        .map(|&u| {
            interpolate_realtime(&c, &RealtimeOptions::default().with_feed(1500.0, 4.0).with_update(u))
                .expect("run")
                .stats
        })
        .collect();
    let (first, second, corrected) = (stats[0], stats[1], stats[2]);
    // Measured here: first ≈ 3e-2, second ≈ 2e-3, corrected ≈ 8e-8.
    assert!(first.max_fluctuation > 1e-2, "first order should visibly fluctuate: {first:?}");
    assert!(second.max_fluctuation < 0.2 * first.max_fluctuation, "second {second:?} vs first {first:?}");
    assert!(
        corrected.max_fluctuation < 1e-4 * first.max_fluctuation && corrected.max_fluctuation < 1e-6,
        "corrected {corrected:?}"
    );
    assert!(corrected.rms_fluctuation < 1e-4 * first.rms_fluctuation, "corrected {corrected:?} vs first {first:?}");
    assert!(corrected.rms_fluctuation <= corrected.max_fluctuation && first.rms_fluctuation <= first.max_fluctuation);
}

#[test]
fn first_order_steps_fall_short_where_the_curve_bends() {
    // Taylor's first-order step is along the tangent; the chord of an arc is shorter than
    // the arc, and the chord is what is measured: on a circle with uniform speed the
    // fluctuation is the chord/arc ratio minus one, ≈ −f²/(24ρ²).
    let c = quarter_circle(10.0);
    let run = interpolate_realtime(&c, &RealtimeOptions::default().with_update(Update::Corrected)).expect("run");
    let f = RealtimeOptions::default().feed_per_period_mm();
    for s in run.samples.iter().filter(|s| !s.last) {
        assert!((s.step_mm - f).abs() < 1e-10 * f, "corrected step {} vs f {f}", s.step_mm);
    }
}

#[test]
fn chord_error_matches_the_circle_formula() {
    let rho = 10.0;
    let c = quarter_circle(rho);
    let o = RealtimeOptions::default().with_feed(30_000.0, 4.0).with_update(Update::Corrected);
    let f = o.feed_per_period_mm();
    let run = interpolate_realtime(&c, &o).expect("run");
    // The sagitta of the chord actually made.
    let sagitta = |c: f64| rho - (rho * rho - c * c / 4.0).sqrt();
    for s in run.samples.iter() {
        assert!(
            (s.chord_error_mm - sagitta(s.step_mm)).abs() < 1e-9,
            "period {}: {} vs {}",
            s.k,
            s.chord_error_mm,
            sagitta(s.step_mm)
        );
    }
    let longest = run.samples.iter().map(|s| s.step_mm).fold(0.0, f64::max);
    interpolab::assert_near!(longest, f, 1e-5 * f);
    interpolab::assert_near!(run.stats.max_chord_error_mm, sagitta(longest), 1e-9);
}

#[test]
fn feed_limit_keeps_the_chord_error_within_tolerance() {
    let c = quarter_circle(2.0);
    let tol = 1e-4;
    let free = interpolate_realtime(&c, &RealtimeOptions::default().with_feed(30_000.0, 4.0)).expect("run");
    assert!(free.stats.max_chord_error_mm > tol, "without the limit the chord error exceeds tol: {:?}", free.stats);
    let limited =
        interpolate_realtime(&c, &RealtimeOptions::default().with_feed(30_000.0, 4.0).with_chord_tol(Some(tol)))
            .expect("run");
    assert!(limited.stats.max_chord_error_mm <= tol * (1.0 + 1e-9), "{:?}", limited.stats);
    assert!(limited.stats.limited_periods + 1 >= limited.stats.periods, "every period of a tight circle is limited");
    assert!(limited.stats.periods > free.stats.periods);
    // The limited step is the chord with sagitta tol: 2·sqrt(tol·(2ρ − tol)).
    interpolab::assert_near!(chord_limited_step(0.5, tol), 2.0 * (tol * (4.0 - tol)).sqrt(), 1e-15);
}

#[test]
fn steps_add_up_to_the_curve_length() {
    let c = quarter_circle(10.0);
    let run = interpolate_realtime(&c, &RealtimeOptions::default()).expect("run");
    let (rho, arc) = (10.0, 10.0 * std::f64::consts::FRAC_PI_2);
    let f = RealtimeOptions::default().feed_per_period_mm();
    // N − 1 full chords of length f (each spanning the arc 2ρ·asin(f/2ρ)), then the chord of
    // the remaining arc.
    let n = run.stats.periods as f64;
    let last_arc = arc - (n - 1.0) * 2.0 * rho * (f / (2.0 * rho)).asin();
    let expected = (n - 1.0) * f + 2.0 * rho * (last_arc / (2.0 * rho)).sin();
    assert!(last_arc > 0.0 && last_arc <= 2.0 * rho * (f / (2.0 * rho)).asin() + 1e-12);
    interpolab::assert_near!(run.stats.length_mm, expected, 1e-9);
    let last = run.samples.last().expect("samples");
    assert!(last.last && (last.point - DVec3::new(0.0, 10.0, 0.0)).length() < 1e-12);
    assert_eq!(run.stats.periods as usize, run.samples.len());
}

#[test]
fn bad_motion_is_refused() {
    let c = quarter_circle(10.0);
    let e = interpolate_realtime(&c, &RealtimeOptions::default().with_feed(0.0, 4.0)).unwrap_err();
    assert!(matches!(e, RealtimeError::BadMotion { .. }) && e.to_string().contains("positive"), "{e}");
    let e = interpolate_realtime(&c, &RealtimeOptions::default().with_chord_tol(Some(-1.0))).unwrap_err();
    assert!(matches!(e, RealtimeError::BadChordTol(_)), "{e}");
    // A curve that stands still: all control points equal.
    let p = DVec3::new(1.0, 2.0, 3.0);
    let still = NurbsCurve::try_new(1, vec![0.0, 0.0, 1.0, 1.0], &[p, p], None).expect("valid");
    let e = interpolate_realtime(&still, &RealtimeOptions::default()).unwrap_err();
    assert!(matches!(e, RealtimeError::Stalled { .. }) && e.to_string().contains("vanishes"), "{e}");
    let _ = still.point_at(0.5);
}

/// The app runs the interpolation a few thousand periods per frame: any split gives the
/// periods, samples and statistics of the one call.
#[test]
fn a_run_split_into_steps_equals_the_one_call() {
    let para = Parabola::paper_like();
    for (update, chord_tol) in [(Update::FirstOrder, None), (Update::Corrected, Some(2e-5))] {
        let opts = RealtimeOptions::default().with_update(update).with_chord_tol(chord_tol);
        let whole = interpolate_realtime(&para, &opts).expect("runs");
        for chunk in [1u64, 7, 1000] {
            let mut run = RealtimeStepper::new(&para, &opts).expect("starts");
            let mut calls = 0;
            while !run.advance(&para, chunk).expect("runs") {
                calls += 1;
                assert_eq!(run.periods(), calls * chunk, "a call runs exactly its periods");
            }
            let split = run.finish();
            assert_eq!(split, whole, "{} in chunks of {chunk}", update.as_str());
        }
    }
    assert!(RealtimeStepper::new(&para, &RealtimeOptions::default().with_feed(0.0, 4.0)).is_err());
}
