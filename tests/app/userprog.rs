//! The "Your program" tab run headless (no window, no GPU): a two-tool program with its tool
//! table and a subroutine file is read and drawn, its reports listed by line, a message picks
//! its line, and Simulate machines the same stock as the core's job for the same request.
//! Native only; needs the `app` feature.
#![allow(clippy::unwrap_used, clippy::expect_used, reason = "tests: a failure should fail the test")]

use interpolab::geom::Cutter;
use interpolab::jobs::NoProgress;
use interpolab::jobs::user_program::{Request, run};
use interpolab::simulate::canon::KinematicsChoice;

use super::Harness;

const TAB: &str = "Your program";

/// The tab's status on `app_headless`'s harness.
impl Harness {
    fn panel(&self) -> serde_json::Value {
        let s: serde_json::Value = serde_json::from_str(&self.app.status()).expect("status is JSON");
        s["panel"]["status"].clone()
    }

    /// Frames until the tab's job is done and `ready` holds.
    fn until(&mut self, what: &str, ready: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
        let t0 = std::time::Instant::now();
        while t0.elapsed() < super::HANG_GUARD {
            self.frame();
            let p = self.panel();
            if p["computing"] == false && ready(&p) {
                return p;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        panic!("{what}: never ready; last {}", self.panel());
    }
}

const PROGRAM: &str = "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F200\nG1 X20\nG0 Z5\nT2 M6\no<groove> call\nM123\nM30\n";
const SUB: &str = "o<groove> sub\nG0 X0 Y8\nG1 Z-2 F100\nG1 X20\nG0 Z5\no<groove> endsub\n";
const TABLE: &str = "T1 P1 D6 ;flat\nT2 P2 D4 ;v90\n";

/// The core's request for what the tests open in the tab (the tab's default cutter, its
/// automatic stock and pitch; read only).
fn request() -> Request {
    Request {
        name: "two.ngc".to_owned(),
        text: PROGRAM.to_owned(),
        files: vec![("groove.ngc".to_owned(), SUB.to_owned())],
        tool_table: Some(TABLE.to_owned()),
        project: None,
        tool_specs: Vec::new(),
        default_cutter: Cutter::flat(1.5).unwrap(),
        machine: None,
        kinematics: KinematicsChoice::Auto,
        pitch_mm: None,
        stock_mm: None,
        simulate: false,
    }
}

#[test]
fn a_two_tool_program_is_read_listed_and_machined_as_the_core_does() {
    let mut h = Harness::new();
    h.app.set_panel_option(TAB, "file:tools.tbl", TABLE).unwrap();
    h.app.set_panel_option(TAB, "file:groove.ngc", SUB).unwrap();
    h.app.set_panel_option(TAB, "file:two.ngc", PROGRAM).unwrap();
    let p = h.until("the program read", |p| p["blocks"].is_number());
    assert_eq!(p["program"], "two.ngc");
    assert_eq!(p["subroutines"][0], "groove.ngc", "{p}");
    assert_eq!(p["blocks"], 8, "{p}");
    assert_eq!(p["tools"][1]["cutter"], "V R 2 mm, 90°", "{p}");
    assert!(p["drawn_segments"].as_u64().unwrap() >= 5, "{p}");
    // The unknown M code is reported with its line; picking it selects the next motion's line.
    let msgs: Vec<String> = p["messages"].as_array().unwrap().iter().map(|m| m.as_str().unwrap().to_owned()).collect();
    assert!(msgs.iter().any(|m| m.starts_with("9: M123")), "{msgs:?}");
    h.app.set_panel_option(TAB, "line", "4").unwrap();
    h.frame();
    assert_eq!(h.panel()["selected_line"], 4);
    h.app.set_panel_option(TAB, "colour", "tool").unwrap();
    h.app.set_panel_option(TAB, "pitch", "0.25").unwrap();
    // The pitch changed the inputs: wait for the new reading before simulating.
    h.until("the program read again", |p| p["blocks"] == 8);
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("the stock machined", |p| p["removed_mm3"].is_array());
    let removed: Vec<f64> = p["removed_mm3"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    // The core's job for the same request (its automatic stock and the pitch).
    let req = Request { pitch_mm: Some(0.25), simulate: true, ..request() };
    let f = run(&req, &mut NoProgress).unwrap().unwrap();
    assert_eq!(removed, f.removed_mm3);
    assert!(removed[0] > 100.0 && removed[1] > 20.0, "{removed:?}");
    assert_eq!(p["stock_rays"].as_u64().unwrap() as usize, f.map.grid.len());

    // A stock set in the tab: a bad block is refused with what to change and nothing lost;
    // a good one is what Simulate machines (the core's job with that stock), without reading
    // the program again.
    let err = h.app.set_panel_option(TAB, "stock", "-5,-5,-5,25,15").unwrap_err();
    assert!(err.contains("six lengths in mm"), "{err}");
    let err = h.app.set_panel_option(TAB, "stock", "-5,-5,0,25,15,-5").unwrap_err();
    assert!(err.contains("z from 0 mm is not below z to -5 mm"), "{err}");
    assert_eq!(h.panel()["stock_from"], p["stock_from"], "a refused stock changes nothing");
    h.app.set_panel_option(TAB, "stock", "-2,-3,-1.5,22,12,0").unwrap();
    h.frame();
    let q = h.panel();
    assert_eq!(q["stock_mm"], serde_json::json!([-2.0, -3.0, -1.5, 22.0, 12.0, 0.0]), "{q}");
    assert_eq!(q["stock_from"], "set here");
    assert_eq!(q["computing"], false, "setting the stock does not read again");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    // (Simulate drops the last result at once: the next one is the set stock's.)
    let p = h.until("the set stock machined", |p| p["removed_mm3"].is_array());
    let f = run(&Request { stock_mm: Some([-2.0, -3.0, -1.5, 22.0, 12.0, 0.0]), ..req.clone() }, &mut NoProgress)
        .unwrap()
        .unwrap();
    let got: Vec<f64> = p["removed_mm3"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(got, f.removed_mm3);
    assert_eq!(p["stock_rays"].as_u64().unwrap() as usize, f.map.grid.len());
    // Back to the automatic stock: read again, the reading's own block.
    h.app.set_panel_option(TAB, "stock", "auto").unwrap();
    let p =
        h.until("the automatic stock back", |p| p["stock_from"].as_str().is_some_and(|s| s.starts_with("automatic")));
    assert_eq!(p["blocks"], 8);
    // The tool editor: each tool starts as its table gives it; a cutter set there (the
    // option is the editor's Apply) reads the program again with it, and Simulate machines
    // what the core's job does with the same spec. A bad spec is refused, nothing changed.
    assert_eq!(p["tools"][0]["spec"], "1:flat:6", "{p}");
    assert_eq!(p["tools"][1]["spec"], "2:v:4:90", "{p}");
    let err = h.app.set_panel_option(TAB, "tool", "2:ball:-4").unwrap_err();
    assert!(err.contains("diameter"), "{err}");
    assert_eq!(h.panel()["tool_specs"], serde_json::json!([]));
    h.app.set_panel_option(TAB, "tool", "2:ball:4").unwrap();
    let p = h.until("read with the ball", |p| p["tools"][1]["spec"] == "2:ball:4");
    assert!(p["tools"][1]["cutter"].as_str().unwrap().starts_with("ball"), "{p}");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("machined with the ball", |p| p["removed_mm3"].is_array());
    let f = run(&Request { tool_specs: vec!["2:ball:4".to_owned()], ..req }, &mut NoProgress).unwrap().unwrap();
    let got: Vec<f64> = p["removed_mm3"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(got, f.removed_mm3);
    // A 4 mm ball 2 mm deep cuts a half disc (2π mm²) along the groove where the 90° V cut
    // a triangle (4 mm²): the groove tool's volume grows.
    assert!(got[1] > removed[1] * 1.2, "{got:?} vs {removed:?}");
    h.app.set_panel_option(TAB, "tool", "reset").unwrap();
    let p = h.until("the tables' tools back", |p| p["tools"][1]["spec"] == "2:v:4:90");
    assert_eq!(p["tool_specs"], serde_json::json!([]));
    // An edit stays with a new program, and goes with a new tool table (it decides again).
    h.app.set_panel_option(TAB, "tool", "2:ball:4").unwrap();
    h.app.set_panel_option(TAB, "file:two.ngc", PROGRAM).unwrap();
    let p = h.until("the program again, edited", |p| p["tools"][1]["spec"] == "2:ball:4");
    assert_eq!(p["tool_specs"], serde_json::json!(["2:ball:4"]));
    h.app.set_panel_option(TAB, "file:tools.tbl", TABLE).unwrap();
    let p = h.until("the new table's tools", |p| p["tools"][1]["spec"] == "2:v:4:90");
    assert_eq!(p["tool_specs"], serde_json::json!([]));
}

/// The program timed on a machine in the tab: the cycle time is the planner's on the same
/// request, a tolerance of 0 (stop at every corner) takes at least as long, a change of
/// setting plans again by itself, and a bad tolerance is refused with what to give.
#[test]
fn the_program_is_timed_on_a_machine_as_the_planner_times_it() {
    use interpolab::jobs::JobKind;
    use interpolab::jobs::program_time::{ProgramTime, Request as TimeRequest};
    use interpolab::plan::Dynamics;
    let mut h = Harness::new();
    h.app.set_panel_option(TAB, "file:tools.tbl", TABLE).unwrap();
    h.app.set_panel_option(TAB, "file:groove.ngc", SUB).unwrap();
    h.app.set_panel_option(TAB, "file:two.ngc", PROGRAM).unwrap();
    h.until("the program read", |p| p["blocks"] == 8);
    h.app.set_panel_option(TAB, "time_machine", "hobby-router").unwrap();
    h.app.set_panel_option(TAB, "time", "").unwrap();
    let p = h.until("the program timed", |p| p["time"]["total_s"].is_number() && p["time"]["running"] == false);
    let program = request();
    let router = Dynamics::preset("hobby-router").unwrap();
    let core =
        ProgramTime::run(&TimeRequest { program: program.clone(), machine: router.clone() }, &mut NoProgress).unwrap();
    let total = p["time"]["total_s"].as_f64().unwrap();
    assert_eq!(total, core.total_s);
    assert_eq!(p["time"]["machine"], "hobby-router");
    assert_eq!(p["time"]["samples"], core.t_s.len());
    // The feed never passes F200 in this program's feed moves, nor the router's rapid speed.
    assert!(p["time"]["max_feed_mm_min"].as_f64().unwrap() <= router.axes[0].velocity * 1.000_001, "{p}");
    // The path coloured by the feed achieved: every feed block's average at most its
    // programmed feed, and the blocks that start from rest below it. (The main program's
    // two feed blocks and the subroutine file's two, matched by line and file.)
    h.app.set_panel_option(TAB, "colour", "achieved").unwrap();
    h.frame();
    let a = h.panel()["achieved"].clone();
    assert_eq!(a["blocks"], 4, "{a}");
    assert!(a["max_ratio"].as_f64().unwrap() <= 1.0 + 1e-5, "{a}");
    assert!(a["min_ratio"].as_f64().unwrap() < 0.999, "{a}");
    // Stopping at every corner: planned again by itself, never faster.
    let err = h.app.set_panel_option(TAB, "time_tolerance", "-1").unwrap_err();
    assert!(err.contains("from 0 to"), "{err}");
    h.app.set_panel_option(TAB, "time_tolerance", "0").unwrap();
    let p = h.until("timed again", |p| p["time"]["for_tolerance_mm"] == 0.0 && p["time"]["running"] == false);
    let stopped = p["time"]["total_s"].as_f64().unwrap();
    assert!(stopped >= total * (1.0 - 1e-12), "{stopped} s stopping at corners, {total} s blended");
    let mut m = router;
    m.tolerance_mm = 0.0;
    assert_eq!(
        stopped,
        ProgramTime::run(&TimeRequest { program: program.clone(), machine: m.clone() }, &mut NoProgress)
            .unwrap()
            .total_s
    );
    // The limits scaled (every axis: velocity × 0.25, acceleration × 0.5): planned again by
    // itself, the core's time on the scaled machine, and slower.
    let err = h.app.set_panel_option(TAB, "time_limits", "1,1").unwrap_err();
    assert!(err.contains("three factors"), "{err}");
    assert!(h.app.set_panel_option(TAB, "time_limits", "0,1,1").is_err());
    h.app.set_panel_option(TAB, "time_limits", "0.25,0.5,1").unwrap();
    let p = h.until("timed on the slower machine", |p| {
        p["time"]["for_x_velocity_mm_min"] == m.axes[0].velocity * 0.25 && p["time"]["running"] == false
    });
    assert_eq!(p["time"]["x_limits"]["acceleration_mm_s2"], m.axes[0].acceleration * 0.5);
    let slow = p["time"]["total_s"].as_f64().unwrap();
    for a in &mut m.axes {
        a.velocity *= 0.25;
        a.acceleration *= 0.5;
    }
    m.name = "hobby-router (limits × 0.25, 0.5, 1)".to_owned();
    assert_eq!(slow, ProgramTime::run(&TimeRequest { program, machine: m }, &mut NoProgress).unwrap().total_s);
    assert!(slow > stopped, "{slow} s on the slower machine, {stopped} s before");
}

/// A flat 6 mm end mill with 10 mm flutes fed at Z−15 across a 30 mm deep block (line 5):
/// its shank meets the 5 mm of stock above the flutes there, and the G0 out of the slot
/// (line 6) goes through the stock the shank left.
const DEEP: &str = "G21 G90\nT1 M6\nG0 X-10 Y10 Z5\nG0 Z-15\nG1 X30 F300\nG0 Z5\nM30\n";
/// The same tool plunged 8 mm (line 4) and fed across: within its flutes.
const SHALLOW: &str = "G21 G90\nT1 M6\nG0 X10 Y10 Z5\nG1 Z-8 F300\nG1 X30\nG0 Z5\nM30\n";
const BLOCK: &str = "0,0,-30,40,20,0";

/// The crashes of a simulation in the tab: the core's, listed by line with the part, tool
/// and depth (mm), counted per kind in the status, marked in the view, and a row's click
/// shows its line; longer flutes set in the tool editor (its body words) clear them; a tool
/// that does not cut at its centre is reported where it plunges; a clean program has none.
#[test]
fn crashes_are_listed_by_line_and_depth_and_a_longer_tool_clears_them() {
    let mut h = Harness::new();
    h.app.set_panel_option(TAB, "tool", "1:flat:6,flute=10").unwrap();
    h.app.set_panel_option(TAB, "file:deep.ngc", DEEP).unwrap();
    h.app.set_panel_option(TAB, "stock", BLOCK).unwrap();
    h.app.set_panel_option(TAB, "pitch", "0.5").unwrap();
    let p = h.until("the deep program read", |p| p["blocks"].is_number() && p["tools"][0]["spec"].is_string());
    assert_eq!(p["crashes"], serde_json::Value::Null, "no crash before a simulation: {p}");
    let t = &p["tools"][0];
    assert_eq!(t["spec"], "1:flat:6,flute=10", "{p}");
    assert_eq!(t["body_mm"], serde_json::json!([10.0, 3.0, 9.0, 7.5, 18.0]), "{p}");
    let body = t["body"].as_str().unwrap();
    assert!(body.starts_with("flutes 10 mm, shank R 3 × 9 mm") && !body.contains("assumed"), "{body}");
    let err = h.app.set_panel_option(TAB, "crash", "0").unwrap_err();
    assert!(err.contains("Simulate first"), "{err}");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("the deep program machined", |p| p["crashes"].is_object());
    let c = &p["crashes"];
    assert_eq!(c["by_kind"], serde_json::json!({"shank": 2, "holder": 0, "rapid": 1, "plunge": 0}), "{c}");
    assert_eq!((c["total"].as_u64(), c["listed"].as_u64(), c["left_out"].as_u64()), (Some(3), Some(3), Some(0)));
    assert_eq!(p["first_crash_line"], 5, "{p}");
    let first = &c["first"];
    assert_eq!(
        (first["line"].as_u64(), first["kind"].as_str(), first["tool"].as_i64()),
        (Some(5), Some("shank"), Some(1))
    );
    let depth = first["depth_mm"].as_f64().unwrap();
    assert!((depth - 5.0).abs() < 0.05, "5 mm of stock above the 10 mm flutes at Z-15: {depth} mm");
    // Where the shank first entered the block: its top face, at the slot's start.
    assert!(first["z_mm"].as_f64().unwrap().abs() < 1e-9 && first["x_mm"].as_f64().unwrap() < 3.5, "{first}");
    assert!(c["summary"].as_str().unwrap().starts_with("3 crashes (2 shank, 1 rapid), the deepest 5.0"), "{c}");
    // As the core's job for the same request.
    let req = Request {
        name: "deep.ngc".to_owned(),
        text: DEEP.to_owned(),
        files: Vec::new(),
        tool_table: None,
        tool_specs: vec!["1:flat:6,flute=10".to_owned()],
        pitch_mm: Some(0.5),
        stock_mm: Some([0.0, 0.0, -30.0, 40.0, 20.0, 0.0]),
        simulate: true,
        ..request()
    };
    let f = run(&req, &mut NoProgress).unwrap().unwrap();
    assert_eq!(f.crashes.len(), 3);
    assert_eq!(first["depth_mm"].as_f64(), Some(f.crashes[0].depth_mm));
    // Each crash marked in the 3D view.
    h.frame();
    assert_eq!(h.panel()["drawn_crash_marks"], 3, "{}", h.panel());
    // A click on the first row shows its line and circles its mark.
    assert_ne!(h.panel()["selected_line"], 5);
    super::click_panel_widget(&mut h, "first_crash");
    let p = h.panel();
    assert_eq!(p["selected_line"], 5, "{p}");
    assert_eq!(p["crashes"]["picked"]["line"], 5, "{p}");
    // Another row by the option; a row past the list is refused with the list's length.
    h.app.set_panel_option(TAB, "crash", "2").unwrap();
    h.frame();
    let p = h.panel();
    assert_eq!((p["selected_line"].as_u64(), p["crashes"]["picked"]["kind"].as_str()), (Some(6), Some("rapid")));
    let err = h.app.set_panel_option(TAB, "crash", "3").unwrap_err();
    assert!(err.contains("3 row(s)"), "{err}");

    // Flutes longer than the cut is deep: the tool's body in its spec (the editor's Apply),
    // read again and machined without a crash.
    h.app.set_panel_option(TAB, "tool", "1:flat:6,flute=20").unwrap();
    let p = h.until("read with 20 mm flutes", |p| p["tools"][0]["spec"] == "1:flat:6,flute=20");
    assert!(p["tools"][0]["body"].as_str().unwrap().starts_with("flutes 20 mm"), "{p}");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("machined with 20 mm flutes", |p| p["crashes"].is_object());
    assert_eq!(p["crashes"]["total"], 0, "{p}");
    assert_eq!(p["first_crash_line"], serde_json::Value::Null);
    assert!(p["crashes"]["summary"].as_str().unwrap().starts_with("no crash"), "{p}");
    assert_eq!(p["drawn_crash_marks"], 0);

    // A shallow program with a tool that cannot plunge: the plunge at line 4 is its crash;
    // with a centre-cutting tool the same program is clean.
    h.app.set_panel_option(TAB, "tool", "1:flat:6,flute=20,nocentre").unwrap();
    h.app.set_panel_option(TAB, "file:shallow.ngc", SHALLOW).unwrap();
    let p = h.until("the shallow program read", |p| {
        p["program"] == "shallow.ngc" && p["tools"][0]["spec"] == "1:flat:6,flute=20,nocentre"
    });
    assert_eq!(p["tools"][0]["centre_cutting"], false, "{p}");
    assert!(p["tools"][0]["body"].as_str().unwrap().contains("no centre cutting"), "{p}");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("the plunge machined", |p| p["crashes"].is_object());
    assert_eq!(p["crashes"]["by_kind"]["plunge"], 1, "{p}");
    assert_eq!(p["crashes"]["total"], 1, "{p}");
    assert_eq!(p["first_crash_line"], 4, "{p}");
    h.app.set_panel_option(TAB, "tool", "1:flat:6,flute=20").unwrap();
    h.until("read with a centre-cutting tool", |p| p["tools"][0]["spec"] == "1:flat:6,flute=20");
    h.app.set_panel_option(TAB, "simulate", "").unwrap();
    let p = h.until("the clean program machined", |p| p["crashes"].is_object());
    assert_eq!(p["crashes"]["total"], 0, "{p}");
    assert_eq!(p["crashes"]["by_kind"], serde_json::json!({"shank": 0, "holder": 0, "rapid": 0, "plunge": 0}));
}
