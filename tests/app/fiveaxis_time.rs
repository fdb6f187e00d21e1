//! The 5-axis tab's time of the before/after plans, run headless: the tab's seconds are the
//! core's (`plan::time_steps` on the same blocks, machine preset and feed), on Example 1's
//! machine and after a change of structure. Native only; needs the `app` feature.
#![allow(clippy::unwrap_used, clippy::expect_used, reason = "tests: a failure should fail the test")]

use interpolab::fiveaxis::{
    Block, DesignPath, Machine, MachineKind, StepOptions, evaluate_nodes, example1, plan_steps,
};
use interpolab::plan::steps::{DEFAULT_FEED_MM_PER_MIN, dynamics_of};
use interpolab::plan::{StepsFeed, time_steps};

use super::{FIVE_AXIS, Harness, set, settle_panel};

/// The core's before and after times of Example 1 on `machine` (E 0.01 mm, the secant).
fn core_times(machine: &Machine) -> (f64, f64) {
    let ex = example1();
    let (a, b) = ex.path.range();
    let before: Vec<Block> = evaluate_nodes(machine, &ex.path, &[a, b], &Default::default())
        .expect("before")
        .iter()
        .map(|n| n.block)
        .collect();
    let after: Vec<Block> =
        plan_steps(machine, &ex.path, &StepOptions::new(0.01)).expect("after").nodes.iter().map(|n| n.block).collect();
    let dynamics = dynamics_of(machine.kind);
    let time = |blocks: &[Block]| {
        time_steps(machine.kind, blocks, DEFAULT_FEED_MM_PER_MIN, StepsFeed::Tip, &dynamics).expect("timed").cycle_s
    };
    (time(&before), time(&after))
}

fn seconds(status: &serde_json::Value, key: &str) -> f64 {
    status["time"][key].as_f64().unwrap_or_else(|| panic!("time.{key}: {status}"))
}

#[test]
fn the_five_axis_tab_times_example1_before_and_after_as_the_core_does() {
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FIVE_AXIS, "source", "example1");
    set(&mut h, FIVE_AXIS, "tol_mm", "0.01");
    let machine = example1().machine;
    let (before, after) = core_times(&machine);
    for shown in ["true", "false"] {
        set(&mut h, FIVE_AXIS, "before", shown);
        let s = settle_panel(&mut h, "example 1");
        assert_eq!(s["time"]["machine"], "table-ac", "{s}");
        assert_eq!(s["time"]["feed_mm_per_min"], DEFAULT_FEED_MM_PER_MIN, "{s}");
        assert_eq!(s["time"]["feed_default"], true, "{s}");
        assert_eq!(s["time"]["error"], "", "{s}");
        // The same blocks, machine and feed: the same seconds, to the last bit.
        assert_eq!(seconds(&s, "before_s"), before, "before shown {shown}: {s}");
        assert_eq!(seconds(&s, "after_s"), after, "before shown {shown}: {s}");
    }
    // Other structures: the tab's machine (its pivots; a head gets a 150 mm tool length) on
    // that structure's preset. docs/feed-planning.md: head-bc's slower C head.
    for (kind, tool_length_mm) in [(MachineKind::TableBC, 0.0), (MachineKind::HeadBC, 150.0)] {
        set(&mut h, FIVE_AXIS, "machine", kind.as_str());
        let s = settle_panel(&mut h, kind.as_str());
        assert_eq!(s["error"], "", "{s}");
        let (before, after) = core_times(&Machine { kind, tool_length_mm, ..machine });
        assert_eq!(s["time"]["machine"], kind.as_str(), "{s}");
        assert_eq!((seconds(&s, "before_s"), seconds(&s, "after_s")), (before, after), "{s}");
    }
}
