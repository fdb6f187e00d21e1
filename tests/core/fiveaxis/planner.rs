//! The resumable step planner (`StepPlanner`, one node per call, for an app that spreads a
//! plan over frames) gives exactly the nodes of `plan_steps`, and keeps the nodes found
//! before a failure.
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use interpolab::chords::RootMethod;
use interpolab::crease::{CreaseCurve, InterpOptions, run_to_end};
use interpolab::fiveaxis::{
    CreasePath, FiveAxisError, Machine, StepOptions, StepPlanner, ToolAxisRule, example1, plan_steps,
};

#[test]
fn the_planner_node_by_node_gives_the_nodes_of_plan_steps() {
    let ex = example1();
    for method in [RootMethod::Secant, RootMethod::AndersonBjorck] {
        let opts = StepOptions::new(0.01).with_method(method);
        let whole = plan_steps(&ex.machine, &ex.path, &opts).unwrap();
        let mut planner = StepPlanner::new(&ex.machine, &ex.path, &opts).unwrap();
        assert_eq!(planner.nodes().len(), 1);
        let mut calls = 0;
        while !planner.is_done() {
            let node = planner.next_node(&ex.machine, &ex.path).unwrap();
            calls += 1;
            assert_eq!(Some(&node), planner.nodes().last());
        }
        assert_eq!(calls, whole.segments());
        // Past the end it returns the last node again and adds nothing.
        let last = planner.next_node(&ex.machine, &ex.path).unwrap();
        assert_eq!(Some(&last), whole.nodes.last());
        assert_eq!(planner.into_plan(), whole);
    }
}

#[test]
fn the_planner_keeps_the_nodes_found_before_a_tool_axis_leaves_travel() {
    let job = support::job(include_str!("../../../examples/torus-plane.json"));
    let rows = run_to_end(job.clone(), InterpOptions::default()).rows;
    let path = CreasePath::new(CreaseCurve::from_rows(&job, &rows).unwrap(), ToolAxisRule::Bisector);
    // The bisector tilts past 40° part-way along this crease: a travel of ±40° is left there.
    let machine = Machine { limits_rad: [Some([-40f64.to_radians(), 40f64.to_radians()]), None], ..Machine::default() };
    let opts = StepOptions::new(0.01);
    let whole = plan_steps(&machine, &path, &opts);
    let mut planner = StepPlanner::new(&machine, &path, &opts).unwrap();
    let err = loop {
        match planner.next_node(&machine, &path) {
            Ok(_) if planner.is_done() => panic!("expected the A axis to leave its travel"),
            Ok(_) => {}
            Err(e) => break e,
        }
    };
    assert!(matches!(err, FiveAxisError::Kinematics { .. }), "{err:?}");
    assert_eq!(whole.unwrap_err(), err);
    assert!(planner.nodes().len() > 1, "nodes before the failure are kept");
    let (start, end) = interpolab::fiveaxis::DesignPath::range(&path);
    let reached = planner.nodes().last().unwrap().block.location.s;
    assert!(reached > start && reached < end);
}
