//! Tool-step selection (seed 002): every chosen segment re-checked by dense re-sampling of
//! the swept tool, computed here from the printed joints with closed-form distances; the
//! order of the methods' iteration counts; bad input.
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::chords::RootMethod;
use interpolab::crease::{CreaseCurve, InterpOptions, run_to_end};
use interpolab::fiveaxis::{
    CreasePath, FiveAxisError, KinematicsError, Machine, NacaProfile, StepOptions, StepPlan, ToolAxisRule, blade_case,
    example1, plan_steps,
};

/// The torus ring through a tilted plate: torus R0 = 40, r0 = 15 about Z (outward), plane
/// through (0, 0, 4) with normal (0, −sin 12°, cos 12°), ball R = 4.
fn torus_plane_path(rule: ToolAxisRule) -> CreasePath {
    let job = support::job(include_str!("../../../examples/torus-plane.json"));
    let rows = run_to_end(job.clone(), InterpOptions::default()).rows;
    CreasePath::new(CreaseCurve::from_rows(&job, &rows).unwrap(), rule)
}

/// Signed errors (gouge +) of a ball of radius 4 centred at c in the torus-plane corner,
/// from closed-form distances.
fn torus_plane_errors(c: DVec3) -> [f64; 2] {
    let rho = c.truncate().length();
    let d_torus = DVec3::new(rho - 40.0, c.z, 0.0).length() - 15.0;
    let n = DVec3::new(0.0, -0.20791169081775934, 0.9781476007338057);
    let d_plane = (c - DVec3::new(0.0, 0.0, 4.0)).dot(n);
    [4.0 - d_torus, 4.0 - d_plane]
}

/// Re-samples every segment of `plan` from its joints (`n` points) and checks
/// max |e| ≤ E and, except for the last segment and rotary-limited ones, ≥ 0.9·E.
fn assert_every_segment_within(
    plan: &StepPlan,
    machine: &Machine,
    ball_mm: f64,
    n: usize,
    errors: impl Fn(DVec3) -> Vec<f64>,
) {
    let tol = plan.tol_mm;
    let count = plan.nodes.len();
    for (k, w) in plan.nodes.windows(2).enumerate() {
        let (ja, jb) = (w[0].block.joints, w[1].block.joints);
        let mut worst = 0.0f64;
        for i in 0..=n {
            let pose = machine.pose_from_joints(&ja.lerp(&jb, i as f64 / n as f64));
            let centre = pose.tip_in_workpiece + ball_mm * pose.axis_in_workpiece;
            for e in errors(centre) {
                worst = worst.max(e.abs());
            }
        }
        assert!(worst <= tol * (1.0 + 1e-6) + 2e-9, "segment {k}: |δ| = {worst} > E = {tol}");
        if k + 2 < count && !w[1].rotary_limited {
            assert!(worst >= 0.9 * tol, "segment {k}: |δ| = {worst} < 0.9·E: nodes denser than needed");
        }
        // The reported δ agrees with the re-computation.
        let reported = w[1].total_mm.unwrap().abs();
        assert!((reported - worst).abs() <= 1e-3 * tol + 1e-9, "segment {k}: reported {reported}, re-computed {worst}");
    }
}

#[test]
fn crease_segments_are_within_tolerance_by_dense_resampling() {
    let path = torus_plane_path(ToolAxisRule::Bisector);
    // A machine whose axes do not pass through the torus axis, so δn is not trivial.
    let machine =
        Machine { pivots_mm: [DVec3::new(0.0, 0.0, -60.0), DVec3::new(12.0, -7.0, 0.0)], ..Machine::default() };
    for (tol, method) in [(0.05, RootMethod::Secant), (0.01, RootMethod::AndersonBjorck)] {
        let plan = plan_steps(&machine, &path, &StepOptions::new(tol).with_method(method)).unwrap();
        assert!(plan.nodes.len() > 10);
        assert_every_segment_within(&plan, &machine, 4.0, 300, |c| torus_plane_errors(c).to_vec());
    }
}

#[test]
fn crease_segments_with_lead_and_tilt_on_a_head_machine_are_within_tolerance() {
    let path = torus_plane_path(ToolAxisRule::Normal1 { lead_rad: 10f64.to_radians(), tilt_rad: 25f64.to_radians() });
    let machine = Machine {
        kind: interpolab::fiveaxis::MachineKind::HeadBC,
        pivots_mm: [DVec3::new(0.0, 0.0, 40.0), DVec3::ZERO],
        tool_length_mm: 160.0,
        limits_rad: [Some([-100f64.to_radians(), 100f64.to_radians()]), None],
    };
    let plan = plan_steps(&machine, &path, &StepOptions::new(0.01)).unwrap();
    assert_every_segment_within(&plan, &machine, 4.0, 300, |c| torus_plane_errors(c).to_vec());
}

#[test]
fn example1_after_inserting_steps_every_segment_is_within_tolerance() {
    let ex = example1();
    let plan = plan_steps(&ex.machine, &ex.path, &StepOptions::new(ex.tol_mm)).unwrap();
    // On the cylinder of radius 25 (tool outside): e = R' − (|(x, y)| − 25) = 30 − |(x, y)|.
    assert_every_segment_within(&plan, &ex.machine, 5.0, 2000, |c| vec![30.0 - c.truncate().length()]);
    // The turn of C (94°) is now spread over the inserted blocks.
    assert!(plan.nodes.len() > 10, "{} nodes", plan.nodes.len());
    let c: Vec<f64> = plan.nodes.iter().map(|n| n.block.joints.rotary_rad[1].to_degrees()).collect();
    assert!(c.windows(2).all(|w| w[1] > w[0] && w[1] - w[0] < 10.0), "{c:?}");
}

/// Distance from p (in z = 0) to the exact NACA 2412 section: nearest of a dense polyline,
/// then refined by golden-section search on the exact point function.
fn naca_distance(naca: &NacaProfile, dense: &[(f64, DVec3)], p: DVec3) -> f64 {
    let p = DVec3::new(p.x, p.y, 0.0);
    let (mut i, mut best) = (0, f64::INFINITY);
    for (k, (_, q)) in dense.iter().enumerate() {
        let d = (*q - p).length_squared();
        if d < best {
            best = d;
            i = k;
        }
    }
    let (mut lo, mut hi) = (dense[i.saturating_sub(1)].0, dense[(i + 1).min(dense.len() - 1)].0);
    let f = |t: f64| (naca.point(t) - p).length();
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if f(x1) < f(x2) { hi = x2 } else { lo = x1 }
    }
    f(0.5 * (lo + hi))
}

#[test]
fn blade_segments_are_within_tolerance_against_the_exact_section() {
    let naca = NacaProfile::naca2412();
    let (path, machine) = blade_case(naca).unwrap();
    let dense: Vec<(f64, DVec3)> = (0..=20_000)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 20_000.0;
            (t, naca.point(t))
        })
        .collect();
    let plan = plan_steps(&machine, &path, &StepOptions::new(0.01)).unwrap();
    // The ball (R = 5) runs outside the section: e = 5 − distance.
    assert_every_segment_within(&plan, &machine, 5.0, 60, |c| vec![5.0 - naca_distance(&naca, &dense, c)]);
}

#[test]
fn modified_secant_needs_fewer_iterations_than_bisection_at_one_micron() {
    // Seed 002's Table 1: at 0.001 mm bisection > golden section > modified secant. And the
    // Anderson–Björck correction beats the paper's plain regula falsi.
    let (blade, machine) = blade_case(NacaProfile::naca2412()).unwrap();
    let crease = torus_plane_path(ToolAxisRule::Bisector);
    let default = Machine::default();
    let cases: [(&dyn interpolab::fiveaxis::DesignPath, &Machine); 2] = [(&blade, &machine), (&crease, &default)];
    for (path, m) in cases {
        let evals = |method: RootMethod| {
            let opts = StepOptions { reports: false, ..StepOptions::new(0.001).with_method(method) };
            plan_steps(m, path, &opts).unwrap().total_evaluations()
        };
        let [bisection, golden, secant, _, ab] = RootMethod::ALL.map(evals);
        assert!(secant < golden && golden < bisection, "bisection {bisection}, golden {golden}, secant {secant}");
        assert!(ab < secant, "anderson-bjorck {ab}, secant {secant}");
    }
}

#[test]
fn bad_tolerance_is_an_error() {
    let ex = example1();
    for tol in [0.0, -0.01, f64::NAN] {
        assert!(matches!(
            plan_steps(&ex.machine, &ex.path, &StepOptions::new(tol)),
            Err(FiveAxisError::BadTolerance { .. })
        ));
    }
}

#[test]
fn a_tool_axis_outside_travel_names_the_axis_and_where() {
    let path = torus_plane_path(ToolAxisRule::Bisector);
    let machine = Machine { limits_rad: [Some([-10f64.to_radians(), 10f64.to_radians()]), None], ..Machine::default() };
    let err = plan_steps(&machine, &path, &StepOptions::new(0.01)).unwrap_err();
    match &err {
        FiveAxisError::Kinematics { source: KinematicsError::OutOfTravel { axis_name, .. }, .. } => {
            assert_eq!(*axis_name, "A")
        }
        other => panic!("expected an out-of-travel error, got {other:?}"),
    }
    assert!(err.to_string().contains("outside its travel"), "{err}");
}

#[test]
fn a_zero_fixed_axis_is_an_error() {
    let path = torus_plane_path(ToolAxisRule::Fixed { axis: DVec3::ZERO });
    let err = plan_steps(&Machine::default(), &path, &StepOptions::new(0.01)).unwrap_err();
    assert!(matches!(err, FiveAxisError::ToolAxis { .. }), "{err:?}");
}

#[test]
fn a_tolerance_below_rounding_ends_with_an_error_not_a_hang() {
    let ex = example1();
    let opts = StepOptions { max_nodes: 2000, reports: false, ..StepOptions::new(1e-13) };
    match plan_steps(&ex.machine, &ex.path, &opts) {
        Err(
            FiveAxisError::TooManyNodes { .. } | FiveAxisError::Underflow { .. } | FiveAxisError::NoConvergence { .. },
        ) => {}
        other => panic!("expected an error, got {:?}", other.map(|p| p.nodes.len())),
    }
}
