//! The optional `machine` and `tool_axis` keys of a scene: absent keys change nothing,
//! every kind round-trips, every bad value is refused with its key path and a fix, and the
//! conversion to internal units.
#![allow(clippy::unwrap_used, clippy::float_cmp, reason = "tests: an error should fail the test; defaults are exact")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::assert_near;
use interpolab::fiveaxis::{MachineKind, ToolAxisRule};
use interpolab::scene::{MachineSpec, Scene, SceneError, ToolAxisSpec, build_machine, build_tool_axis};
use serde_json::Value;

const BASE: &str = include_str!("../../../examples/torus-plane.json");

/// The base scene with `extra` (a JSON object's members) added at the top level.
fn with(extra: &str) -> String {
    let mut v: Value = serde_json::from_str(BASE).unwrap();
    let add: Value = serde_json::from_str(&format!("{{{extra}}}")).unwrap();
    for (k, x) in add.as_object().unwrap() {
        v.as_object_mut().unwrap().insert(k.clone(), x.clone());
    }
    v.to_string()
}

fn refused(json: &str) -> SceneError {
    match Scene::from_json(json) {
        Err(e) => e,
        Ok(_) => panic!("should be refused: {json}"),
    }
}

#[test]
fn a_scene_without_the_new_keys_parses_and_writes_as_before() {
    let s = support::scene(BASE);
    assert_eq!(s.machine, None);
    assert_eq!(s.tool_axis, None);
    let out = s.to_json();
    assert!(!out.contains("machine") && !out.contains("tool_axis"), "{out}");
    assert_eq!(support::scene(&out), s);
    let null_keys = with(r#""machine": null, "tool_axis": null"#);
    assert_eq!(support::scene(&null_keys), s);
}

#[test]
fn every_machine_kind_and_rule_round_trips() {
    let machines = [
        r#""machine": {"kind": "table-ac", "pivots": {"a": [0, 0, -80], "c": [10, 5, 0]}, "limits": {"a": [-30, 110], "c": null}}"#,
        r#""machine": {"kind": "table-bc", "pivots": {"b": [0, 0, -60]}, "limits": {"b": [-90, 90], "c": [-360, 360]}}"#,
        r#""machine": {"kind": "head-bc", "pivots": {"b": [0, 20, 0]}, "tool_length": 150}"#,
        r#""machine": {"kind": "head-a-table-c", "pivots": {"a": [0, 0, 30], "c": [5, 5, 0]}, "tool_length": 120.5}"#,
    ];
    let rules = [
        r#""tool_axis": {"rule": "bisector"}"#,
        r#""tool_axis": {"rule": "normal1", "lead": 5, "tilt": -12.5}"#,
        r#""tool_axis": {"rule": "fixed", "vector": [0, 1, 1]}"#,
    ];
    for m in machines {
        for r in rules {
            let s = support::scene(&with(&format!("{m}, {r}")));
            assert!(s.machine.is_some() && s.tool_axis.is_some());
            assert_eq!(support::scene(&s.to_json()), s, "pretty round trip of {m}, {r}");
            assert_eq!(support::scene(&s.to_json_compact()), s, "compact round trip of {m}, {r}");
        }
    }
}

#[test]
fn absent_machine_keys_take_the_documented_defaults() {
    let s = support::scene(&with(r#""machine": {"kind": "table-bc"}"#));
    let m = s.machine.unwrap();
    assert_eq!(m.kind, MachineKind::TableBC);
    assert_eq!(m.pivots, [[0.0; 3]; 2]);
    assert_eq!(m.tool_length, 0.0);
    assert_eq!(m.limits, [Some([-120.0, 120.0]), None]);
    let s = support::scene(&with(r#""tool_axis": {"rule": "normal1"}"#));
    assert_eq!(s.tool_axis, Some(ToolAxisSpec::Normal1 { lead: 0.0, tilt: 0.0 }));
}

#[test]
fn machine_and_rule_convert_to_radians_and_unit_vectors() {
    let spec = MachineSpec {
        kind: MachineKind::HeadATableC,
        pivots: [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]],
        tool_length: 99.0,
        limits: [Some([-45.0, 90.0]), None],
    };
    let m = build_machine(&spec);
    assert_eq!(m.pivots_mm, [DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)]);
    assert_near!(m.limits_rad[0].unwrap()[0], -std::f64::consts::FRAC_PI_4, 1e-15);
    assert_near!(m.limits_rad[0].unwrap()[1], std::f64::consts::FRAC_PI_2, 1e-15);
    assert_eq!(m.limits_rad[1], None);
    match build_tool_axis(&ToolAxisSpec::Normal1 { lead: 30.0, tilt: -60.0 }).unwrap() {
        ToolAxisRule::Normal1 { lead_rad, tilt_rad } => {
            assert_near!(lead_rad, std::f64::consts::FRAC_PI_6, 1e-15);
            assert_near!(tilt_rad, -std::f64::consts::FRAC_PI_3, 1e-15);
        }
        other => panic!("{other:?}"),
    }
    match build_tool_axis(&ToolAxisSpec::Fixed { vector: [0.0, 3.0, 4.0] }).unwrap() {
        ToolAxisRule::Fixed { axis } => {
            assert!((axis - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-15)
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_machine_values_name_their_key() {
    let cases = [
        (r#""machine": {"kind": "table-xy"}"#, "machine.kind", "table-ac"),
        (r#""machine": {"pivots": {}}"#, "machine.kind", "add \"kind\""),
        (r#""machine": {"kind": "table-ac", "pivot": {}}"#, "machine.pivot", "did you mean \"pivots\""),
        (r#""machine": {"kind": "table-bc", "pivots": {"a": [0, 0, 0]}}"#, "machine.pivots.a", "allowed here: b, c"),
        (
            r#""machine": {"kind": "head-bc", "pivots": {"c": [0, 0, 0]}, "tool_length": 100}"#,
            "machine.pivots.c",
            "allowed here: b",
        ),
        (r#""machine": {"kind": "head-bc"}"#, "machine.tool_length", "tool length"),
        (r#""machine": {"kind": "table-ac", "tool_length": -1}"#, "machine.tool_length", "≥ 0"),
        (r#""machine": {"kind": "table-ac", "limits": {"a": [30, -30]}}"#, "machine.limits.a", "min < max"),
        (r#""machine": {"kind": "table-ac", "limits": {"a": [30]}}"#, "machine.limits.a", "[min, max]"),
        (r#""machine": {"kind": "table-ac", "pivots": {"c": [0, "x", 0]}}"#, "machine.pivots.c[1]", "without quotes"),
        (r#""machine": "table-ac""#, "machine", "expected an object"),
    ];
    for (extra, path, hint) in cases {
        let e = refused(&with(extra));
        assert_eq!(e.path, path, "{extra}: {e}");
        assert!(e.to_string().contains(hint), "{extra}: `{e}` should mention `{hint}`");
    }
}

#[test]
fn bad_tool_axis_values_name_their_key() {
    let cases = [
        (r#""tool_axis": {"rule": "normal2"}"#, "tool_axis.rule", "bisector"),
        (r#""tool_axis": {"lead": 3}"#, "tool_axis.rule", "add \"rule\""),
        (r#""tool_axis": {"rule": "bisector", "lead": 3}"#, "tool_axis.lead", "allowed here: rule"),
        (r#""tool_axis": {"rule": "normal1", "lead": 95}"#, "tool_axis.lead", "between -90 and 90"),
        (r#""tool_axis": {"rule": "normal1", "tilt": -90}"#, "tool_axis.tilt", "between -90 and 90"),
        (r#""tool_axis": {"rule": "fixed"}"#, "tool_axis.vector", "add \"vector\""),
        (r#""tool_axis": {"rule": "fixed", "vector": [0, 0, 0]}"#, "tool_axis.vector", "non-zero"),
        (r#""tool_axis": {"rule": "normal1", "tilt": 10, "tilts": 3}"#, "tool_axis.tilts", "did you mean \"tilt\""),
    ];
    for (extra, path, hint) in cases {
        let e = refused(&with(extra));
        assert_eq!(e.path, path, "{extra}: {e}");
        assert!(e.to_string().contains(hint), "{extra}: `{e}` should mention `{hint}`");
    }
}

#[test]
fn the_five_axis_example_reads_writes_and_builds() {
    let text = include_str!("../../../examples/torus-plate-head-bc.json");
    let s = support::scene(text);
    assert_eq!(s.to_json(), text, "the example file is in the writer's own layout");
    let m = build_machine(&s.machine.unwrap());
    assert_eq!(m.kind, MachineKind::HeadBC);
    assert_near!(m.tool_length_mm, 160.0, 0.0);
    assert!(matches!(build_tool_axis(&s.tool_axis.unwrap()).unwrap(), ToolAxisRule::Normal1 { .. }));
}
