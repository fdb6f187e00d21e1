//! The app run headless (no window, no GPU): every preset computes the same path as the
//! core, and every slider pushed to either end of its range gives a clear message or a
//! valid result — never a panic or a NaN on screen. Native only; needs the `app` feature.
#![cfg(all(feature = "app", not(target_arch = "wasm32")))]

use eframe::egui;
use std::ops::RangeInclusive;

use interpolab::app::{InterpolabApp, ranges};
use interpolab::crease::{CreaseJob, InterpOptions, run_to_end};
use interpolab::scene::{PRESETS, Scene};

/// How long a test waits for the app to reach a state before it calls the app stuck: a hang
/// guard only, generous for a loaded 2-core machine. The work the app cuts into slices has a
/// wall-time budget per frame and background jobs run on threads, so how many frames a
/// computation takes depends on the machine's load: the tests wait for states, never for a
/// number of frames.
const HANG_GUARD: std::time::Duration = std::time::Duration::from_secs(600);

struct Harness {
    ctx: egui::Context,
    app: InterpolabApp,
    frame: eframe::Frame,
}

impl Harness {
    fn new() -> Self {
        let ctx = egui::Context::default();
        let cc = eframe::CreationContext::_new_kittest(ctx.clone());
        let app = InterpolabApp::new(&cc);
        Self { ctx, app, frame: eframe::Frame::_new_kittest() }
    }

    fn frame(&mut self) {
        self.frame_events(Vec::new());
    }

    fn frame_events(&mut self, events: Vec<egui::Event>) {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1400.0, 900.0))),
            events,
            ..Default::default()
        };
        let (app, frame) = (&mut self.app, &mut self.frame);
        let out = self.ctx.run_ui(input, |ui| eframe::App::ui(app, ui, frame));
        out.drop_without_applying_deltas();
    }

    /// Clicks the middle of the widget the status publishes under `name`.
    fn click(&mut self, name: &str) {
        let s: serde_json::Value = serde_json::from_str(&self.app.status()).expect("status is JSON");
        let r = s["ui"][name].as_array().unwrap_or_else(|| panic!("{name} is not on screen: {}", s["ui"]));
        let at = egui::pos2(
            (r[0].as_f64().expect("x") + r[2].as_f64().expect("w") / 2.0) as f32,
            (r[1].as_f64().expect("y") + r[3].as_f64().expect("h") / 2.0) as f32,
        );
        let press = |pressed| egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        self.frame_events(vec![egui::Event::PointerMoved(at), press(true)]);
        self.frame_events(vec![press(false)]);
        self.frame_events(vec![egui::Event::PointerGone]);
    }

    /// Runs frames until the computation settles; returns the status.
    fn settle(&mut self) -> serde_json::Value {
        let t0 = std::time::Instant::now();
        while t0.elapsed() < HANG_GUARD {
            self.frame();
            let s: serde_json::Value = serde_json::from_str(&self.app.status()).expect("status is JSON");
            if s["running"] == false && s["frames"].as_u64().unwrap_or(0) >= 2 {
                return s;
            }
        }
        panic!("computation did not settle");
    }
}

#[test]
fn every_preset_computes_the_same_path_as_the_core() {
    let mut h = Harness::new();
    for p in PRESETS {
        h.app.open_text(&format!("{}.json", p.id), p.json);
        let s = h.settle();
        let scene = Scene::from_json(p.json).expect("preset");
        let job = CreaseJob::from_scene(&scene).expect("builds");
        let core = run_to_end(job, InterpOptions::default());
        assert_eq!(s["scene"], scene.name);
        assert_eq!(s["periods"].as_u64(), Some(core.rows.len() as u64 - 1), "{}", p.id);
        assert_eq!(s["stop"], core.outcome.as_ref().map_or("error", |r| r.tag()), "{}", p.id);
        assert_eq!(s["error"], "", "{}: {}", p.id, s["error"]);
    }
}

#[test]
fn a_bad_file_is_reported_and_the_scene_kept() {
    let mut h = Harness::new();
    h.app.open_text("a.json", PRESETS[1].json);
    let before = h.settle();
    h.app.open_text("broken.json", "{ \"format\": \"interpolab-scene/1\", \"surfaces\": 3 }");
    let after = h.settle();
    assert_eq!(after["scene"], before["scene"]);
    assert_eq!(after["periods"], before["periods"]);
    let err = after["error"].as_str().expect("text");
    assert!(err.contains("broken.json") && err.contains("kept"), "{err}");
}

#[test]
fn a_run_that_misses_path_end_tells_which_direction_to_set() {
    // A straight V-groove along x from x = −40 toward x = +40; the sense of n1 × n2 is −x.
    let json = include_str!("data/groove-end-behind-start.json");
    let mut h = Harness::new();
    h.app.open_text("groove.json", json);
    let s = h.settle();
    let job = CreaseJob::from_scene(&Scene::from_json(json).expect("valid")).expect("builds");
    let core = run_to_end(job, InterpOptions::default());
    let expected = core.end_not_reached.expect("the core misses the end").to_string();
    assert!(expected.contains("path.direction to [1.000, 0.000, 0.000]"), "{expected}");
    assert_eq!(s["end_note"].as_str(), Some(expected.as_str()), "{}", s["end_note"]);
    assert_eq!(s["error"], "", "a note, not an error: {}", s["error"]);
    // The note's button sets the advised direction: the end is reached and the note goes.
    h.click("run_toward_end");
    let s = h.settle();
    assert_eq!(s["stop"], "reached_end", "{s}");
    assert!(s["end_note"].is_null(), "{}", s["end_note"]);
    assert_eq!(h.app.scene().path.direction, Some([1.0, 0.0, 0.0]));
    assert!(s["ui"].get("run_toward_end").is_none(), "the button goes with the note");
}

/// One end of a slider's range.
fn end(range: &RangeInclusive<f64>, hi: bool) -> f64 {
    if hi { *range.end() } else { *range.start() }
}

/// Pushes each slider to both ends of its range (`interpolab::app::ranges`).
#[test]
fn sliders_at_their_extremes_never_panic_or_show_nan() {
    type Edit = fn(&mut Scene, bool);
    let edits: [(&str, Edit); 8] = [
        ("feed", |s, hi| s.motion.feed = end(&ranges::FEED_MM_PER_MIN, hi)),
        ("period", |s, hi| s.motion.period = end(&ranges::PERIOD_MS, hi)),
        ("radius", |s, hi| s.tool.radius = end(&ranges::BALL_RADIUS_MM, hi)),
        ("allowance", |s, hi| s.tool.allowance = end(&ranges::ALLOWANCE_MM, hi)),
        ("t1", |s, hi| s.tolerance.t1 = end(&ranges::SURFACE_TOL_MM, hi)),
        ("t2", |s, hi| s.tolerance.t2 = end(&ranges::SURFACE_TOL_MM, hi)),
        ("share", |s, hi| s.tolerance.share = end(&ranges::TOL_SHARE, hi)),
        ("feed and period", |s, hi| {
            s.motion.feed = end(&ranges::FEED_MM_PER_MIN, hi);
            s.motion.period = end(&ranges::PERIOD_MS, hi);
            s.path.max_steps = 20_000;
        }),
    ];
    let mut h = Harness::new();
    for p in PRESETS.iter().take(4) {
        for (name, edit) in edits {
            for hi in [false, true] {
                h.app.open_text("preset.json", p.json);
                h.settle();
                h.app.edit_draft(|s| edit(s, hi));
                let s = h.settle();
                let text = s.to_string();
                assert!(!text.contains("NaN") && !text.contains("inf"), "{} {name} {hi}: {text}", p.id);
                let err = s["error"].as_str().expect("text");
                if !err.is_empty() {
                    // A failure must say what to change.
                    assert!(
                        ["lower", "use ", "give", "move", "change", "end the path", "turn"]
                            .iter()
                            .any(|w| err.contains(w)),
                        "{} {name} {hi}: unhelpful message: {err}",
                        p.id
                    );
                }
                for w in s["worst_error_mm"].as_array().expect("array") {
                    assert!(w.as_f64().is_some_and(f64::is_finite), "{} {name}: {w}", p.id);
                }
            }
        }
    }
}

/// Whether the side panel shows the scene's controls this frame (the feed slider and the
/// share button publish their rectangles only when drawn).
fn scene_controls_shown(h: &mut Harness) -> bool {
    h.frame();
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    let feed = s["ui"].get("feed_slider").is_some();
    assert_eq!(feed, s["ui"].get("share_button").is_some(), "the scene's controls come as one: {}", s["ui"]);
    feed
}

#[test]
fn each_tab_shows_the_scene_controls_only_where_it_uses_the_scene() {
    let mut h = Harness::new();
    h.settle();
    // The crease tab is a tab like the others: shown by its title, named in the status.
    set(&mut h, "Crease interpolation", "", "");
    assert!(scene_controls_shown(&mut h));
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("JSON");
    assert_eq!(s["panel"]["title"], "Crease interpolation");
    for title in ["Crease interpolation", FIVE_AXIS, CHORDS, "NURBS & G-code", SIMULATION, FILLET] {
        assert!(s["ui"].get(title).is_some(), "tab {title} not on screen: {}", s["ui"]);
    }
    // Tabs on their own curves or parts: no scene controls; on the scene's crease: shown.
    for (title, key, own, scene) in [
        (FIVE_AXIS, "source", "example1", "scene"),
        (CHORDS, "curve", "parabola", "crease"),
        ("NURBS & G-code", "source", "parabola", "crease"),
    ] {
        set(&mut h, title, key, own);
        assert!(!scene_controls_shown(&mut h), "{title} on {own}");
        set(&mut h, title, key, scene);
        assert!(scene_controls_shown(&mut h), "{title} on {scene}");
    }
    set(&mut h, FILLET, "", "");
    assert!(!scene_controls_shown(&mut h), "the fillet tab has its own parts");
}

/// Every tab is named by its subject, never by the project's internal "seed" numbers, and
/// names the paper it follows in its status and help; each paper's English title is the one
/// docs/papers.md cites. The user's own program follows none.
#[test]
fn each_tab_names_its_subject_and_its_paper() {
    let mut h = Harness::new();
    h.settle();
    let papers =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/papers.md")).expect("docs/papers.md");
    for title in ["Crease interpolation", FIVE_AXIS, CHORDS, "NURBS & G-code", SIMULATION, FILLET, "Your program"] {
        set(&mut h, title, "", "");
        h.frame();
        let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("JSON");
        assert_eq!(s["panel"]["title"], title);
        assert!(!title.to_lowercase().contains("seed"), "{title}");
        let paper = &s["panel"]["paper"];
        if title == "Your program" {
            assert!(paper.is_null(), "{title}: {paper}");
            continue;
        }
        let paper = paper.as_str().unwrap_or_else(|| panic!("{title} names no paper: {s}"));
        // The quoted English title, or the authors where our copy prints no title.
        let cited = paper
            .split('“')
            .nth(1)
            .and_then(|t| t.split('”').next())
            .unwrap_or_else(|| paper.split(" (").next().expect("authors"));
        assert!(papers.contains(cited), "{title}: \"{cited}\" is not in docs/papers.md");
    }
}

/// Shows a view and sets an option as its widgets would.
fn set(h: &mut Harness, title: &str, key: &str, value: &str) {
    if let Err(e) = h.app.set_panel_option(title, key, value) {
        panic!("{title} {key}={value}: {e}");
    }
}

/// Runs frames until the shown view's status says it is done; returns that status.
fn settle_panel(h: &mut Harness, what: &str) -> serde_json::Value {
    let t0 = std::time::Instant::now();
    while t0.elapsed() < HANG_GUARD {
        h.frame();
        let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        let p = &s["panel"]["status"];
        if s["running"] == false && p.is_object() && p["computing"] == false {
            let text = s.to_string();
            assert!(!text.contains("NaN") && !text.contains("inf"), "{what}: {text}");
            return p.clone();
        }
        // A background job needs time, not frames.
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("{what}: the view did not finish");
}

const FIVE_AXIS: &str = "5-axis steps";

#[test]
fn the_five_axis_view_reproduces_example1_before_and_after() {
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FIVE_AXIS, "source", "example1");
    set(&mut h, FIVE_AXIS, "before", "true");
    let before = settle_panel(&mut h, "example 1 before");
    assert_eq!(before["blocks"], 2, "{before}");
    let gouge = before["worst_delta_mm"].as_f64().expect("δ");
    assert!((gouge - 8.79).abs() < 0.01, "the single block gouges by 8.79 mm: {gouge}");
    set(&mut h, FIVE_AXIS, "before", "false");
    let after = settle_panel(&mut h, "example 1 after");
    // docs/fiveaxis.md: 30 blocks inserted (32 in all), every segment within E = 0.01 mm,
    // 166 iterations with the modified secant, 41 with Anderson–Björck.
    assert_eq!(after["blocks"], 32, "{after}");
    let worst = after["worst_delta_mm"].as_f64().expect("δ");
    assert!(worst <= 0.01 && worst > 0.0099, "{worst}");
    assert_eq!(after["compare"]["secant"], 166, "{after}");
    assert_eq!(after["compare"]["anderson-bjorck"], 41, "{after}");
    assert_eq!(after["error"], "");
}

#[test]
fn the_five_axis_view_plans_every_preset_and_reports_bad_input() {
    let mut h = Harness::new();
    for p in PRESETS {
        h.app.open_text(&format!("{}.json", p.id), p.json);
        h.settle();
        set(&mut h, FIVE_AXIS, "source", "scene");
        set(&mut h, FIVE_AXIS, "tol_mm", "0.05");
        let s = settle_panel(&mut h, p.id);
        assert_eq!(s["error"], "", "{}: {s}", p.id);
        assert!(s["blocks"].as_u64().is_some_and(|n| n >= 2), "{}: {s}", p.id);
        let worst = s["worst_delta_mm"].as_f64().expect("δ");
        assert!(worst.abs() <= 0.05 * (1.0 + 1e-6), "{}: {worst}", p.id);
        assert!(s["compare"].as_object().is_some_and(|c| c.values().all(serde_json::Value::is_u64)), "{}: {s}", p.id);
    }
    // The blade, at the extremes of the tolerance slider.
    set(&mut h, FIVE_AXIS, "source", "naca2412");
    for tol in [ranges::FIVEAXIS_TOL_MM.end(), ranges::FIVEAXIS_TOL_MM.start()] {
        let tol = &tol.to_string();
        set(&mut h, FIVE_AXIS, "tol_mm", tol);
        let s = settle_panel(&mut h, "blade");
        assert_eq!(s["error"], "", "{tol}: {s}");
    }
    // A tilting axis with too little travel for the torus crease: the plan stops where the
    // bisector leaves it, says which axis and what to change, and keeps the blocks before.
    h.app.open_text("torus-plane.json", include_str!("../examples/torus-plane.json"));
    h.settle();
    set(&mut h, FIVE_AXIS, "source", "scene");
    set(&mut h, FIVE_AXIS, "tol_mm", "0.01");
    // A frame first: choosing a path resets the machine to the path's own, as in the app.
    settle_panel(&mut h, "torus-plane");
    set(&mut h, FIVE_AXIS, "tilt_travel_deg", "40");
    let s = settle_panel(&mut h, "torus-plane, A within ±40°");
    let err = s["error"].as_str().expect("text");
    assert!(
        err.contains("A = ") && err.contains("outside its travel") && err.contains("widen machine.limits"),
        "{err}"
    );
    assert!(s["blocks"].as_u64().is_some_and(|n| n >= 2), "the blocks before the stop are kept: {s}");
    // A machine whose head cannot reach the blade's tool axes: a clear message, no panic.
    set(&mut h, FIVE_AXIS, "source", "naca2412");
    set(&mut h, FIVE_AXIS, "tol_mm", "0.05");
    set(&mut h, FIVE_AXIS, "machine", "head-a-table-c");
    let s = settle_panel(&mut h, "blade on head-a-table-c");
    let err = s["error"].as_str().expect("text");
    if !err.is_empty() {
        assert!(err.contains("change") || err.contains("widen") || err.contains("raise"), "{err}");
    }
}

#[test]
fn the_five_axis_tip_bound_gives_the_cores_plan() {
    let mut h = Harness::new();
    h.app.open_text("torus-plane.json", include_str!("../examples/torus-plane.json"));
    h.settle();
    set(&mut h, FIVE_AXIS, "source", "scene");
    set(&mut h, FIVE_AXIS, "tol_mm", "0.01");
    let plain = settle_panel(&mut h, "torus-plane");
    set(&mut h, FIVE_AXIS, "bound_tip", "true");
    let bound = settle_panel(&mut h, "torus-plane, tip bound");
    assert_eq!(bound["bound_tip"], true);
    // The core's plans for the same crease, machine and axis rule (as `steps` makes them).
    let scene = Scene::from_json(include_str!("../examples/torus-plane.json")).expect("example");
    let job = CreaseJob::from_scene(&scene).expect("builds");
    let rows = run_to_end(job.clone(), InterpOptions::default()).rows;
    let path = interpolab::fiveaxis::CreasePath::new(
        interpolab::crease::CreaseCurve::from_rows(&job, &rows).expect("curve"),
        interpolab::fiveaxis::ToolAxisRule::Bisector,
    );
    let machine = interpolab::fiveaxis::Machine::default();
    let opts = interpolab::fiveaxis::StepOptions::new(0.01);
    let core_plain = interpolab::fiveaxis::plan_steps(&machine, &path, &opts).expect("plan");
    let core_bound = interpolab::fiveaxis::plan_steps(&machine, &path, &opts.with_tip_bound(true)).expect("plan");
    assert_eq!(plain["blocks"].as_u64(), Some(core_plain.nodes.len() as u64), "{plain}");
    assert_eq!(bound["blocks"].as_u64(), Some(core_bound.nodes.len() as u64), "{bound}");
    assert!(core_bound.nodes.len() > core_plain.nodes.len());
}

const CHORDS: &str = "Chords";

fn row<'a>(s: &'a serde_json::Value, label: &str) -> &'a serde_json::Value {
    &s["rows"][label]
}

#[test]
fn the_chords_view_gives_the_node_counts_of_docs_chords_md() {
    let mut h = Harness::new();
    h.settle();
    // docs/chords.md, d = 0.05 mm: parabola 18 / 23 / 41, hyperbola 21 / 33 / 39, ellipse
    // 17 / 21 / 31 (equal-error / equal-interval / equal-step, both sized by ρ_min).
    for (curve, counts) in [("parabola", [18, 23, 41]), ("hyperbola", [21, 33, 39]), ("ellipse", [17, 21, 31])] {
        set(&mut h, CHORDS, "curve", curve);
        set(&mut h, CHORDS, "tol_mm", "0.05");
        let s = settle_panel(&mut h, curve);
        assert_eq!(s["error"], "", "{curve}: {s}");
        for (label, n) in
            ["equal-error", "equal-interval, sized by ρ_min", "equal-step, sized by ρ_min"].iter().zip(counts)
        {
            assert_eq!(row(&s, label)["nodes"], n, "{curve} {label}: {s}");
        }
        let worst = row(&s, "equal-error")["worst_mm"].as_f64().expect("worst");
        assert!(worst <= 0.05 && worst > 0.0499, "{curve}: {worst}");
    }
}

#[test]
fn the_chords_view_takes_typed_curves_and_says_what_is_wrong_with_bad_ones() {
    let mut h = Harness::new();
    h.settle();
    set(&mut h, CHORDS, "curve", "typed");
    set(&mut h, CHORDS, "x", "60*cos(t)");
    set(&mut h, CHORDS, "y", "30*sin(t)");
    set(&mut h, CHORDS, "t0", "0");
    set(&mut h, CHORDS, "t1", "pi/2");
    set(&mut h, CHORDS, "tol_mm", "0.01");
    let s = settle_panel(&mut h, "typed ellipse");
    assert_eq!(row(&s, "equal-error")["nodes"], 37, "the quarter ellipse at 0.01 mm: {s}");
    for (key, value, expect) in [
        ("y", "30 sin(t)", "y(t), column 4"),
        ("x", "sqrt(t - 1)", "not defined at t ="),
        ("t1", "0", "t0 < t1"),
        ("t1", "2*", "t1, column 3"),
    ] {
        set(&mut h, CHORDS, key, value);
        let s = settle_panel(&mut h, value);
        let err = s["error"].as_str().expect("text");
        assert!(err.contains(expect), "{key} = {value}: {err}");
        // The last valid curve stays computed.
        assert_eq!(row(&s, "equal-error")["nodes"], 37, "{s}");
        // Undo for the next case.
        set(&mut h, CHORDS, "x", "60*cos(t)");
        set(&mut h, CHORDS, "y", "30*sin(t)");
        set(&mut h, CHORDS, "t1", "pi/2");
    }
    // The ends of the tolerance slider.
    for tol in [ranges::CHORDS_TOL_MM.end(), ranges::CHORDS_TOL_MM.start()] {
        let tol = &tol.to_string();
        set(&mut h, CHORDS, "tol_mm", tol);
        let s = settle_panel(&mut h, tol);
        assert_eq!(s["error"], "", "{tol}: {s}");
        assert!(row(&s, "equal-error")["nodes"].as_u64().is_some_and(|n| n >= 2), "{s}");
    }
}

#[test]
fn the_chords_view_cuts_the_crease_of_every_preset() {
    let mut h = Harness::new();
    for p in PRESETS {
        h.app.open_text(&format!("{}.json", p.id), p.json);
        h.settle();
        set(&mut h, CHORDS, "curve", "crease");
        set(&mut h, CHORDS, "tol_mm", "0.05");
        let s = settle_panel(&mut h, p.id);
        assert_eq!(s["error"], "", "{}: {s}", p.id);
        for label in ["equal-error", "equal-interval, sized by ρ_min", "equal-step, sized by ρ_min"] {
            assert!(row(&s, label)["nodes"].as_u64().is_some_and(|n| n >= 2), "{} {label}: {s}", p.id);
        }
        // The crease is drawn in its best-fit plane: for the two creases that lie in a plane,
        // that plane (the floor z = 0 of the round pocket; the tilted plate of the torus).
        let n: Vec<f64> =
            s["plot_plane_normal"].as_array().expect("normal").iter().filter_map(|x| x.as_f64()).collect();
        let plane = match p.id {
            "floor-round-wall" => Some([0.0, 0.0, 1.0]),
            "torus-plane" => Some([0.0, -0.20791169081775934, 0.9781476007338057]),
            _ => None,
        };
        if let Some(m) = plane {
            let dot: f64 = n.iter().zip(m).map(|(a, b)| a * b).sum();
            assert!(dot.abs() > 1.0 - 1e-9, "{}: drawn in the plane with normal {n:?}, expected {m:?}", p.id);
        }
    }
}

// ---- NURBS & G-code panel ----

mod nurbs_panel {
    use std::path::{Path, PathBuf};
    use std::sync::Arc;

    use eframe::egui;
    use interpolab::crease::CreaseJob;
    use interpolab::gcode::{CompareOptions, ProgramOptions, compare, crease_design};
    use interpolab::scene::{PRESETS, Scene};

    use super::Harness;

    const TAB: &str = "NURBS & G-code";

    /// A file dropped on the window (what a browser or the desktop gives the app).
    #[derive(Debug)]
    struct Dropped(PathBuf, Vec<u8>);

    impl egui::DroppedFile for Dropped {
        fn path(&self) -> &Path {
            &self.0
        }
        fn bytes(&self) -> Result<Vec<u8>, String> {
            Ok(self.1.clone())
        }
    }

    fn frame_with(
        h: &mut Harness,
        events: Vec<egui::Event>,
        dropped: Vec<egui::DroppedFileHandle>,
    ) -> serde_json::Value {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1400.0, 900.0))),
            events,
            dropped_files: dropped,
            ..Default::default()
        };
        let (app, frame) = (&mut h.app, &mut h.frame);
        let out = h.ctx.run_ui(input, |ui| eframe::App::ui(app, ui, frame));
        out.drop_without_applying_deltas();
        serde_json::from_str(&h.app.status()).expect("status is JSON")
    }

    /// Clicks the panel's tab (its rectangle is in the status).
    fn open_tab(h: &mut Harness) {
        frame_with(h, Vec::new(), Vec::new());
        h.click(TAB);
        let s = frame_with(h, Vec::new(), Vec::new());
        assert_eq!(s["panel"]["title"], TAB, "the tab opens");
    }

    /// Frames until the panel has nothing left to do (the work waits a quiet time first).
    fn until_done(h: &mut Harness) -> serde_json::Value {
        let t0 = std::time::Instant::now();
        while t0.elapsed() < super::HANG_GUARD {
            let s = frame_with(h, Vec::new(), Vec::new());
            if s["panel"]["status"]["done"] == true {
                return s["panel"]["status"].clone();
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        panic!("the NURBS panel did not finish");
    }

    #[test]
    fn nurbs_panel_gives_the_core_comparison_on_every_preset() {
        let mut h = Harness::new();
        h.app.open_text("first.json", PRESETS[0].json);
        h.settle();
        open_tab(&mut h);
        for p in PRESETS {
            h.app.open_text(&format!("{}.json", p.id), p.json);
            h.settle();
            let s = until_done(&mut h);
            let text = s.to_string();
            assert!(!text.contains("NaN") && !text.contains("inf"), "{}: {text}", p.id);
            assert_eq!(s["status_ok"], true, "{}: {text}", p.id);
            // The same comparison as `interpolab compare SCENE --tolerance 0.01`.
            let scene = Scene::from_json(p.json).expect("preset");
            let job = CreaseJob::from_scene(&scene).expect("builds");
            let design = crease_design(&job).expect("design");
            let opts = CompareOptions {
                program: ProgramOptions::default().with_feed(scene.motion.feed).with_title(&scene.name),
                period_ms: scene.motion.period,
                chord_tol_mm: None,
            };
            let core = compare(&design, 0.01, &opts).expect("comparison");
            let rows = s["rows"].as_array().expect("rows");
            assert_eq!(rows.len(), 3);
            for (row, c) in rows.iter().zip(&core.rows) {
                assert_eq!(row["kind"], c.kind.label(), "{}", p.id);
                assert_eq!(row["fresh"], true, "{}", p.id);
                assert_eq!(row["path_blocks"].as_u64(), Some(c.path_blocks as u64), "{} {}", p.id, c.kind.label());
                assert_eq!(row["bytes"].as_u64(), Some(c.bytes as u64), "{} {}", p.id, c.kind.label());
                // JSON text round trip: equal to the last bits serde_json's reader keeps.
                let d = row["deviation_mm"].as_f64().expect("deviation");
                assert!((d - c.deviation_mm).abs() <= 1e-12 * c.deviation_mm, "{} {}: {d}", p.id, c.kind.label());
            }
            let rt = s["realtime"].as_array().expect("realtime");
            assert_eq!(rt.len(), core.realtime.len(), "{}", p.id);
            for (r, c) in rt.iter().zip(&core.realtime) {
                assert_eq!(r["periods"].as_u64(), Some(c.periods), "{}", p.id);
                let m = r["max_fluctuation"].as_f64().expect("fluctuation");
                assert!((m - c.max_fluctuation).abs() <= 1e-12 * c.max_fluctuation, "{}: {m}", p.id);
            }
        }
    }

    #[test]
    fn a_dropped_program_is_measured_and_a_malformed_one_named_by_its_line() {
        let mut h = Harness::new();
        h.app.open_text("dome.json", PRESETS[1].json);
        h.settle();
        // Our own G06.2 program for this scene, dropped on the window: it opens the panel and
        // is measured against the design (within the tolerance it was written for).
        let scene = Scene::from_json(PRESETS[1].json).expect("preset");
        let job = CreaseJob::from_scene(&scene).expect("builds");
        let design = crease_design(&job).expect("design");
        let opts = ProgramOptions::default().with_feed(scene.motion.feed);
        let program = interpolab::gcode::write_program(interpolab::gcode::ProgramKind::Nurbs, &design, 0.02, &opts)
            .expect("program");
        let file: egui::DroppedFileHandle =
            Arc::new(Dropped(PathBuf::from("dome.nc"), program.text.clone().into_bytes()));
        let s = frame_with(&mut h, Vec::new(), vec![file]);
        assert_eq!(s["panel"]["title"], TAB, "a dropped .nc file opens the panel");
        let s = until_done(&mut h);
        let loaded = &s["loaded"];
        assert_eq!(loaded["name"], "dome.nc");
        assert!(loaded["error"].is_null(), "{loaded}");
        let d = loaded["deviation_mm"].as_f64().expect("a deviation");
        assert!((d - program.deviation.max_mm()).abs() < 1e-9, "{d} vs {}", program.deviation.max_mm());
        // A malformed program (an arc with neither centre nor radius; parameters such as `#1`
        // are read now): the error names its line and what to change, nothing panics.
        let bad = "%\nG21 G90\nG00 X0 Y0 Z5\nG02 X10 Y0 F500\nM30\n%\n";
        let file: egui::DroppedFileHandle = Arc::new(Dropped(PathBuf::from("bad.ngc"), bad.as_bytes().to_vec()));
        frame_with(&mut h, Vec::new(), vec![file]);
        let s = frame_with(&mut h, Vec::new(), Vec::new());
        let loaded = &s["panel"]["status"]["loaded"];
        assert_eq!(loaded["name"], "bad.ngc");
        let err = loaded["error"].as_str().expect("an error");
        assert!(err.contains("line 4") && err.contains("radius R"), "{err}");
        let banner = s["error"].as_str().expect("text");
        assert!(banner.contains("bad.ngc") && banner.contains("line 4"), "{banner}");
    }

    /// Seed 004's profile through the view's options: the numbers of `docs/nurbs-gcode.md`
    /// (`interpolab compare --profile parabola --tolerance 0.01`), and each update and the
    /// chord-error feed limit reach the real-time run.
    #[test]
    fn the_parabola_profile_gives_the_documented_table() {
        let mut h = Harness::new();
        h.settle();
        super::set(&mut h, TAB, "source", "parabola");
        super::set(&mut h, TAB, "tol_mm", "0.01");
        let s = until_done(&mut h);
        let blocks: Vec<u64> =
            s["rows"].as_array().expect("rows").iter().filter_map(|r| r["path_blocks"].as_u64()).collect();
        let bytes: Vec<u64> = s["rows"].as_array().expect("rows").iter().filter_map(|r| r["bytes"].as_u64()).collect();
        assert_eq!(blocks, [77, 15, 18], "{s}");
        assert_eq!(bytes, [1834, 886, 859], "{s}");
        assert_eq!(s["design_mm"].as_f64().map(|l| (l * 10.0).round() / 10.0), Some(226.1));
        let rt = s["realtime"].as_array().expect("realtime");
        let periods: Vec<u64> = rt.iter().filter_map(|r| r["periods"].as_u64()).collect();
        assert_eq!(periods, [2262, 2262, 2262]);
        let fl: Vec<f64> = rt.iter().filter_map(|r| r["max_fluctuation"].as_f64()).collect();
        assert!(fl[0] > 1e-5 && fl[1] < 1e-5 && fl[2] < 1e-12, "{fl:?}");
        // A chord tolerance under the vertex's chord error (6.2e-5 mm) lowers the feed there.
        super::set(&mut h, TAB, "chord_tol_mm", "0.00002");
        let s = until_done(&mut h);
        assert!(s["realtime"].as_array().expect("realtime").iter().all(|r| r["periods"].as_u64() > Some(2262)), "{s}");
        assert!(h.app.set_panel_option(TAB, "update", "fourth").is_err_and(|e| e.contains("corrected")));
    }

    /// The time column: each row's time on the machine is the core's (`cycle_time` of the
    /// program `compare_row` writes, what `interpolab compare --profile parabola --tolerance
    /// 0.01 --machine M` prints), the machine picker changes it, and "none" hides it.
    #[test]
    fn the_time_column_is_the_cores_and_follows_the_machine() {
        use interpolab::gcode::{ProgramKind, compare_row};
        use interpolab::jobs::program_row::cycle_time;
        use interpolab::plan::Dynamics;
        let para = interpolab::nurbs_path::Parabola::paper_like();
        let opts = CompareOptions {
            program: ProgramOptions::default().with_feed(1500.0).with_title("parabola y = x^2/40, x from -60 to 60 mm"),
            period_ms: 4.0,
            chord_tol_mm: None,
        };
        let core = |machine: &str| -> Vec<f64> {
            let m = Dynamics::preset(machine).expect("preset");
            ProgramKind::ALL
                .into_iter()
                .map(|k| {
                    let row = compare_row(k, &para, 0.01, &opts).expect("written");
                    cycle_time(&row.program.parsed.toolpath, &m).expect("timed").total_s
                })
                .collect()
        };
        let times = |s: &serde_json::Value, machine: &str| -> Vec<f64> {
            let rows = s["rows"].as_array().expect("rows");
            rows.iter()
                .map(|r| {
                    assert_eq!(r["time_machine"], machine, "{r}");
                    let mean = r["mean_feed_mm_min"].as_f64().expect("a mean feed");
                    assert!(mean > 0.0 && mean <= 1500.0 * (1.0 + 1e-9), "{r}");
                    r["time_s"].as_f64().expect("a time")
                })
                .collect()
        };
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs());
        let mut h = Harness::new();
        h.settle();
        super::set(&mut h, TAB, "source", "parabola");
        super::set(&mut h, TAB, "tol_mm", "0.01");
        let s = until_done(&mut h);
        assert_eq!(s["machine"], "vmc", "the machining centre by default");
        let (vmc, vmc_core) = (times(&s, "vmc"), core("vmc"));
        assert!(close(&vmc, &vmc_core), "tab {vmc:?}, core {vmc_core:?}");
        super::set(&mut h, TAB, "machine", "hobby-router");
        let s = until_done(&mut h);
        let (hobby, hobby_core) = (times(&s, "hobby-router"), core("hobby-router"));
        assert!(close(&hobby, &hobby_core), "tab {hobby:?}, core {hobby_core:?}");
        // The router's lower limits take longer on every program.
        assert!(hobby.iter().zip(&vmc).all(|(r, v)| r > v), "router {hobby:?}, vmc {vmc:?}");
        assert!(!s.to_string().contains("NaN"));
        super::set(&mut h, TAB, "machine", "none");
        let s = until_done(&mut h);
        assert!(s["machine"].is_null(), "{s}");
        assert!(s["rows"].as_array().expect("rows").iter().all(|r| r["time_s"].is_null() && r["path_blocks"].is_u64()));
        let e = h.app.set_panel_option(TAB, "machine", "okuma").expect_err("not a preset");
        assert!(e.contains("none") && e.contains("vmc") && e.contains("hobby-router"), "{e}");
    }

    /// The dialect choice writes the programs in Sinumerik's and LinuxCNC's words, with the
    /// command line's numbers (`interpolab compare --profile parabola --tolerance 0.01
    /// --dialect all`, docs/gcode-dialects.md).
    #[test]
    fn the_dialect_choice_gives_the_command_lines_programs() {
        let mut h = Harness::new();
        h.settle();
        super::set(&mut h, TAB, "source", "parabola");
        super::set(&mut h, TAB, "tol_mm", "0.01");
        for (dialect, blocks, bytes) in
            [("sinumerik", [77, 15, 26], [1774, 887, 1350]), ("linuxcnc", [77, 15, 27], [1775, 972, 1007])]
        {
            super::set(&mut h, TAB, "dialect", dialect);
            let s = until_done(&mut h);
            let rows = s["rows"].as_array().expect("rows");
            let got_blocks: Vec<u64> = rows.iter().filter_map(|r| r["path_blocks"].as_u64()).collect();
            let got_bytes: Vec<u64> = rows.iter().filter_map(|r| r["bytes"].as_u64()).collect();
            assert_eq!(got_blocks, blocks, "{dialect}: {s}");
            assert_eq!(got_bytes, bytes, "{dialect}: {s}");
        }
        assert!(
            h.app.set_panel_option(TAB, "dialect", "okuma").is_err_and(|e| e.contains("fanuc, sinumerik, linuxcnc"))
        );
    }

    /// At the slowest feed the real-time runs have 10⁵ periods in all: they are spread over
    /// frames and still give the core's numbers.
    #[test]
    fn a_slow_feed_is_run_over_many_frames_with_the_cores_numbers() {
        let mut h = Harness::new();
        h.settle();
        super::set(&mut h, TAB, "source", "parabola");
        until_done(&mut h);
        super::set(&mut h, TAB, "feed_mm_per_min", "60");
        let mut frames = 0;
        let t0 = std::time::Instant::now();
        let s = loop {
            let s = frame_with(&mut h, Vec::new(), Vec::new());
            frames += 1;
            if s["panel"]["status"]["done"] == true {
                break s["panel"]["status"].clone();
            }
            assert!(t0.elapsed() < super::HANG_GUARD, "did not finish");
        };
        let para = interpolab::nurbs_path::Parabola::paper_like();
        let opts = ProgramOptions::default().with_feed(60.0).with_title("parabola y = x^2/40, x from -60 to 60 mm");
        let program = interpolab::gcode::write_program(interpolab::gcode::ProgramKind::Nurbs, &para, 0.01, &opts)
            .expect("program");
        let curve = program.read_back_curves().next().expect("curve");
        let core = interpolab::nurbs_path::interpolate_realtime(
            curve,
            &interpolab::nurbs_path::RealtimeOptions::default().with_feed(60.0, 4.0),
        )
        .expect("runs");
        let rt = s["realtime"].as_array().expect("realtime");
        assert!(rt.iter().all(|r| r["periods"].as_u64() == Some(core.stats.periods)), "{s}");
        assert!(core.stats.periods > 50_000);
        assert!(frames > 5, "{frames} frames");
    }

    #[test]
    fn a_tolerance_below_the_resolution_says_what_to_change() {
        let mut h = Harness::new();
        h.app.open_text("dome.json", PRESETS[1].json);
        h.settle();
        open_tab(&mut h);
        let s = until_done(&mut h);
        // Drag the tolerance slider to its left end: 1 µm, below twice the 1 µm resolution.
        let r = s["ui"]["tolerance_slider"].as_array().expect("the slider's rectangle");
        let f = |i: usize| r[i].as_f64().expect("number") as f32;
        let (y, x0) = (f(1) + f(3) / 2.0, f(0) + 20.0);
        let button = |pos, pressed| egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        };
        frame_with(
            &mut h,
            vec![egui::Event::PointerMoved(egui::pos2(x0, y)), button(egui::pos2(x0, y), true)],
            Vec::new(),
        );
        frame_with(&mut h, vec![egui::Event::PointerMoved(egui::pos2(f(0) - 200.0, y))], Vec::new());
        frame_with(&mut h, vec![button(egui::pos2(f(0) - 200.0, y), false), egui::Event::PointerGone], Vec::new());
        let s = until_done(&mut h);
        let left_end = *interpolab::app::ranges::NURBS_TOL_MM.start();
        assert!((s["tol_mm"].as_f64().expect("tolerance") - left_end).abs() < 1e-12, "{}", s["tol_mm"]);
        assert_eq!(s["status_ok"], false, "{s}");
        for row in s["rows"].as_array().expect("rows") {
            let e = row["error"].as_str().expect("every program is refused");
            assert!(e.contains("below twice the resolution") && e.contains("Raise the tolerance"), "{e}");
        }
        assert!(!s.to_string().contains("NaN"));
    }
}

const SIMULATION: &str = "Cutting simulation";

/// A small program of tool tips (no header): a plunge, two lines (one 0.1 mm below the
/// design plane z = 0.5), a clockwise arc, a rising line and a retract.
const SIM_PROGRAM: &str = "G21 G90 G17
G00 X2 Y3 Z5
G01 Z0.5 F600
G01 X18 Y3 Z0.4
G01 X18 Y7
G02 X10 Y7 I-4 J0
G01 X2 Y7 Z0.6
G00 Z5
";

/// Two JSON values with the same numbers: `interpolab simulate` prints -100 for -100.0 (the
/// shortest form), which serde_json reads as an integer.
fn num_eq(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| num_eq(v, w)))
        }
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(v, w)| num_eq(v, w)),
        _ => a == b,
    }
}

/// The core's own numbers for the same inputs, as `interpolab simulate` prints them.
fn simulate_cli(program: &str, extra: &[&str]) -> serde_json::Value {
    let dir = std::env::temp_dir().join(format!("interpolab-simview-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("prog.nc");
    std::fs::write(&path, program).expect("write program");
    let mut args = vec!["simulate", path.to_str().expect("utf-8 path")];
    args.extend_from_slice(extra);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_interpolab")).args(&args).output().expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON")
}

#[test]
fn the_simulation_view_gives_the_command_lines_numbers_and_plays_back_move_by_move() {
    let mut h = Harness::new();
    set(&mut h, SIMULATION, "program_text", SIM_PROGRAM);
    set(&mut h, SIMULATION, "cutter", "ball:1.5");
    set(&mut h, SIMULATION, "stock", "0,0,0,20,10,2");
    set(&mut h, SIMULATION, "pitch", "0.1");
    set(&mut h, SIMULATION, "design", "plane:0.5");
    let s = settle_panel(&mut h, "simulation");
    assert_eq!(s["error"], serde_json::Value::Null, "{s}");
    assert_eq!(s["stage"], "done", "{s}");
    let cli = simulate_cli(
        SIM_PROGRAM,
        &["--cutter", "ball:1.5", "--stock", "0,0,0,20,10,2", "--pitch", "0.1", "--design-z", "0.5"],
    );
    assert_eq!(s["grid"]["nx"], cli["grid"]["nx"]);
    assert_eq!(s["grid"]["ny"], cli["grid"]["ny"]);
    assert_eq!(s["moves_total"], cli["moves"], "{s}\n{cli}");
    assert_eq!(s["moves_simulated"], cli["moves"]);
    assert!(num_eq(&s["removed_volume_mm3"], &cli["removed_volume_mm3"]), "{s}\n{cli}");
    assert_eq!(s["ray_updates"], cli["ray_updates"]);
    assert!(num_eq(&s["scallop_um"], &cli["scallop_um"]), "{s}\n{cli}");
    assert!(num_eq(&s["gouge"], &cli["gouge"]), "{s}\n{cli}");
    // The moves at tip z = 0.4 cut 0.1 mm below the plane: the worst gouge is −100 µm.
    let worst = s["gouge"]["worst_um"].as_f64().expect("a gouge");
    assert!((worst + 100.0).abs() < 1e-6, "{s}");
    let total = s["removed_volume_mm3"].as_f64().expect("volume");
    assert!(total > 0.0);

    // "go there" moves the camera's target to the gouge (local coordinates: relative to
    // the stock's centre (10, 5, 1)).
    set(&mut h, SIMULATION, "go_to_gouge", "");
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("JSON");
    let t = &s["panel"]["status"]["camera_target_local_mm"];
    let gx = cli["gouge"]["x_mm"].as_f64().expect("x");
    assert!((t[0].as_f64().expect("x") - (gx - 10.0)).abs() < 1e-3, "{t}");
    let gy = cli["gouge"]["y_mm"].as_f64().expect("y");
    assert!((t[1].as_f64().expect("y") - (gy - 5.0)).abs() < 1e-3, "{t}");
    assert!((t[2].as_f64().expect("z") - (0.5 - 0.1 - 1.0)).abs() < 0.05, "{t}");

    // The slider: back to move 2 restarts from the block and gives the core's first two
    // moves; forward to the end again gives the whole run.
    let first_two = {
        use interpolab::geom::Cutter;
        use interpolab::simulate::{DexelStock, Program, Simulation};
        let parsed = interpolab::gcode::parse_program(SIM_PROGRAM).expect("parses");
        let program = Program::from_toolpath(&parsed.toolpath, glam::DVec3::ZERO, 0.01).expect("moves");
        let stock = DexelStock::block([0.0, 0.0, 0.0], [20.0, 10.0, 2.0], 0.1).expect("stock");
        let mut sim = Simulation::new(stock, &Cutter::ball(1.5).expect("cutter"));
        for m in &program.moves[..2] {
            sim.apply(m);
        }
        (sim.counters().removed_mm3 * 1e6).round() / 1e6
    };
    set(&mut h, SIMULATION, "move", "2");
    let s = settle_panel(&mut h, "simulation to move 2");
    assert_eq!(s["moves_simulated"], 2, "{s}");
    assert_eq!(s["removed_volume_mm3"].as_f64(), Some(first_two), "{s}");
    assert!(first_two < total);
    set(&mut h, SIMULATION, "move", "all");
    let s = settle_panel(&mut h, "simulation to the end");
    assert!(num_eq(&s["removed_volume_mm3"], &cli["removed_volume_mm3"]), "{s}");
    assert!(num_eq(&s["gouge"], &cli["gouge"]), "{s}");

    // Bad options say what they accept; a grid over the cap is refused with a message.
    let (finest, _) = ranges::PITCH_RANGE_MM;
    let below = (finest / 20.0).to_string();
    assert!(h.app.set_panel_option(SIMULATION, "pitch", &below).is_err_and(|e| e.contains(&finest.to_string())));
    assert!(h.app.set_panel_option(SIMULATION, "cutter", "drill:3").is_err_and(|e| e.contains("ball:R")));
    set(&mut h, SIMULATION, "stock", "0,0,0,300,300,2");
    set(&mut h, SIMULATION, "pitch", &finest.to_string());
    let s = settle_panel(&mut h, "simulation over the cap");
    let e = s["error"].as_str().expect("refused");
    assert!(e.contains("raise the pitch") && e.contains("rays"), "{e}");
}

#[test]
fn the_simulation_view_machines_the_scenes_crease_program_against_its_surfaces() {
    let mut h = Harness::new();
    h.settle();
    set(&mut h, SIMULATION, "source", "crease-g01");
    let s = settle_panel(&mut h, "crease G01 simulation");
    assert_eq!(s["error"], serde_json::Value::Null, "{s}");
    assert_eq!(s["design"], "scene surfaces");
    assert!(s["grid"]["nx"].as_u64().expect("nx") <= 256 && s["grid"]["ny"].as_u64().expect("ny") <= 256, "{s}");
    assert!(s["removed_volume_mm3"].as_f64().expect("volume") > 0.0, "{s}");
    assert!(s["scallop_um"]["rays"].as_u64().expect("rays") > 0, "{s}");
}

#[test]
fn the_simulation_view_gives_the_command_lines_numbers_for_the_scenes_programs() {
    // The default scene (floor-round-wall) as a G06.2 program and as seed-002 steps: the
    // view's automatic stock and pitch given to `interpolab simulate` give the same numbers.
    let mut h = Harness::new();
    h.settle();
    assert_eq!(h.app.scene().name, Scene::from_json(PRESETS[0].json).expect("preset").name);
    let radius = h.app.scene().tool.radius.to_string();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/floor-round-wall.json");
    for source in ["crease-nurbs", "steps"] {
        set(&mut h, SIMULATION, "source", source);
        set(&mut h, SIMULATION, "stock", "auto");
        set(&mut h, SIMULATION, "pitch", "auto");
        let s = settle_panel(&mut h, source);
        assert_eq!(s["error"], serde_json::Value::Null, "{source}: {s}");
        let b: Vec<String> = s["stock_mm"].as_array().expect("stock").iter().map(ToString::to_string).collect();
        let stock = b.join(",");
        let pitch = s["grid"]["pitch_mm"].to_string();
        let cutter = format!("ball:{radius}");
        let cli = if source == "steps" {
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_interpolab"))
                .args(["simulate", scene, "--steps", "0.01", "--cutter", &cutter, "--stock", &stock, "--pitch", &pitch])
                .output()
                .expect("runs");
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            serde_json::from_slice(&out.stdout).expect("JSON")
        } else {
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_interpolab"))
                .args(["gcode", scene, "--kind", "nurbs", "--tolerance", "0.01"])
                .output()
                .expect("runs");
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            let program = String::from_utf8(out.stdout).expect("utf-8");
            simulate_cli(&program, &["--cutter", &cutter, "--stock", &stock, "--pitch", &pitch, "--scene", scene])
        };
        assert_eq!(s["moves_total"], cli["moves"], "{source}: {s}\n{cli}");
        assert!(num_eq(&s["removed_volume_mm3"], &cli["removed_volume_mm3"]), "{source}: {s}\n{cli}");
        assert!(num_eq(&s["gouge"], &cli["gouge"]), "{source}: {s}\n{cli}");
        assert!(num_eq(&s["scallop_um"], &cli["scallop_um"]), "{source}: {s}\n{cli}");
    }
}

const FILLET: &str = "Fillet end mill";

#[test]
fn the_fillet_view_builds_the_cores_iso_scallop_paths_over_frames_and_restarts_on_a_change() {
    use interpolab::fillet::{PartSamples, iso_scallop};
    use interpolab::scene::finish::{FINISH_PRESETS, FinishScene};
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FILLET, "preset", "finish-bicubic-patch");
    set(&mut h, FILLET, "strategy", "matched");
    set(&mut h, FILLET, "h", "0.02");
    // A few frames into the job, then a change: the old job is dropped.
    h.frame();
    h.frame();
    set(&mut h, FILLET, "h", "0.04");
    set(&mut h, FILLET, "R", "6");
    set(&mut h, FILLET, "r", "1.5");
    let mut seen = std::collections::BTreeSet::new();
    let t0 = std::time::Instant::now();
    let s = loop {
        assert!(t0.elapsed() < HANG_GUARD, "the fillet paths did not finish");
        h.frame();
        let all: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        let p = all["panel"]["status"].clone();
        if p["computing_paths"] == true {
            seen.insert(p["paths_so_far"].as_u64().expect("paths so far"));
        }
        if p["computing"] == false {
            break p;
        }
    };
    assert_eq!(s["error"], serde_json::Value::Null, "{s}");
    // The core's own result on the same inputs.
    let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).expect("preset");
    scene.finish.scallop = 0.04;
    scene.finish.cutter.radius = 6.0;
    scene.finish.cutter.corner_radius = 1.5;
    "matched".clone_into(&mut scene.finish.strategy);
    scene.finish.lead = None;
    let job = scene.job().expect("job");
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let core = iso_scallop(&job.setup(&part)).expect("core");
    let st = core.stats(job.options.feed_mm_per_min);
    assert!(st.passes > 2, "a case with several passes: {}", st.passes);
    assert_eq!(s["passes"], st.passes, "{s}");
    assert_eq!(s["nodes"], st.nodes, "{s}");
    // Equal to the last bit but for serde_json's float parsing (within 1 ulp).
    let same = |key: &serde_json::Value, want: f64| {
        let got = key.as_f64().expect("number");
        assert!((got - want).abs() <= 1e-14 * want.abs().max(1.0), "{got} against the core's {want}: {s}");
    };
    same(&s["length_mm"], st.length_mm);
    same(&s["strip_mm"]["min"], st.strip_mm[0]);
    same(&s["strip_mm"]["mean"], st.strip_mm[1]);
    same(&s["strip_mm"]["max"], st.strip_mm[2]);
    assert_eq!(s["adjusted"], st.adjusted, "{s}");
    assert_eq!(s["refused"], core.refused.len(), "{s}");
    assert_eq!(s["scallop_flags"], core.scallop_flags.len(), "{s}");
    assert!((s["h_mm"].as_f64().expect("h") - 0.04).abs() < 1e-12, "{s}");
    // The paths were built over several frames, not in one.
    assert!(seen.len() >= 2, "path counts seen while computing: {seen:?} of {}", st.passes);
    // The inset's numbers at the selected CC point: the matched cutter clears the surface.
    let sel = &s["selected"];
    assert!(sel["k_cutter_per_mm"].as_f64().expect("κ") >= sel["k_surface_per_mm"].as_f64().expect("k") - 1e-9, "{s}");
}

/// The comparison table's rows are background jobs: they arrive while the view keeps
/// drawing, each is the core's own run on the same inputs, and none ran on the UI thread.
#[test]
fn the_fillet_table_rows_are_background_jobs_giving_the_cores_numbers() {
    use interpolab::fillet::{Layout, PartSamples, iso_parametric, iso_scallop};
    use interpolab::scene::finish::{FINISH_PRESETS, FinishScene};
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FILLET, "preset", "finish-bicubic-patch");
    set(&mut h, FILLET, "h", "0.05");
    set(&mut h, FILLET, "R", "6");
    set(&mut h, FILLET, "r", "1.5");
    set(&mut h, FILLET, "table", "true");
    let before = interpolab::app::jobs::finished_counts();
    // Rows done, read in every frame drawn while the table computed. How many distinct
    // counts a frame sees depends on the machine's load (rows finish on other threads), so
    // what is asserted is the order, not the number of readings.
    let mut partial_tables = Vec::new();
    let t0 = std::time::Instant::now();
    let s = loop {
        assert!(t0.elapsed() < HANG_GUARD, "the fillet table did not finish: {partial_tables:?}");
        h.frame();
        let all: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        let p = all["panel"]["status"].clone();
        if p["computing_table"] == true {
            partial_tables.push(p["table_rows_done"].as_u64().expect("rows done"));
        }
        if p["computing"] == false {
            break p;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    };
    let rows = s["table"].as_array().expect("rows");
    assert_eq!(rows.len(), 10, "{s}");
    // Rows arrived while frames were drawn: frames ran while the table computed, the rows
    // done never went back, and no frame drawn while it computed showed all ten.
    assert!(!partial_tables.is_empty(), "no frame was drawn while the table computed");
    assert!(
        partial_tables.windows(2).all(|w| w[0] <= w[1]) && partial_tables.iter().all(|&n| n < 10),
        "rows arrived one by one while frames were drawn: {partial_tables:?}"
    );
    assert_eq!(s["table_in_background"], true, "{s}");
    let after = interpolab::app::jobs::finished_counts();
    assert!(after.0 >= before.0 + 9 && after.1 == before.1, "{before:?} → {after:?}");
    // Two rows against the core's own runs.
    for (strategy, lead, layout, k) in
        [("ball", None, Layout::IsoParametric, 9), ("fixed-lead", Some(10.0), Layout::IsoScallop, 4)]
    {
        let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).expect("preset");
        scene.finish.scallop = 0.05;
        scene.finish.cutter.radius = 6.0;
        scene.finish.cutter.corner_radius = 1.5;
        strategy.clone_into(&mut scene.finish.strategy);
        scene.finish.lead = lead;
        let job = scene.job().expect("job");
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        let core = match layout {
            Layout::IsoScallop => iso_scallop(&job.setup(&part)),
            Layout::IsoParametric => iso_parametric(&job.setup(&part)),
        }
        .expect("core")
        .stats(job.options.feed_mm_per_min);
        let row = &rows[k];
        assert_eq!(row["layout"], layout.name(), "{row}");
        assert_eq!(row["passes"], core.passes, "{row}");
        assert_eq!(row["length_mm"].as_f64(), Some(core.length_mm), "{row}");
        assert_eq!(row["strip_mm"][0].as_f64(), Some(core.strip_mm[0]), "{row}");
    }
}

#[test]
fn the_fillet_view_refuses_bad_options_with_a_message() {
    let mut h = Harness::new();
    h.settle();
    for (k, v, want) in [
        ("h", "0", "outside"),
        ("R", "nan", "outside"),
        ("r", "abc", "number"),
        ("strategy", "sideways", "not one of"),
        ("preset", "teapot", "not one of"),
        ("speed", "1", "no option"),
    ] {
        let e = h.app.set_panel_option(FILLET, k, v).expect_err("refused");
        assert!(e.contains(want), "{k}={v}: {e}");
    }
    set(&mut h, FILLET, "R", "2");
    let e = h.app.set_panel_option(FILLET, "r", "3").expect_err("r above R");
    assert!(e.contains("r ≤ R"), "{e}");
}

/// Clicks the middle of a widget the shown view publishes in its status (`panel.status.ui`).
fn click_panel_widget(h: &mut Harness, name: &str) {
    let s = panel_status(h);
    let r = s["ui"][name].as_array().unwrap_or_else(|| panic!("{name} is not on screen: {}", s["ui"])).clone();
    let at = egui::pos2(
        (r[0].as_f64().expect("x") + r[2].as_f64().expect("w") / 2.0) as f32,
        (r[1].as_f64().expect("y") + r[3].as_f64().expect("h") / 2.0) as f32,
    );
    click_at(h, at);
}

#[test]
fn simulate_this_program_hands_the_five_axis_and_nurbs_programs_over_and_compares_them() {
    let mut h = Harness::new();
    h.settle();
    // The 5-axis tab on the scene's crease at the simulation's tolerance (0.01 mm): its
    // button hands its steps to the Cutting simulation, which machines every block-to-block
    // move of that plan.
    set(&mut h, FIVE_AXIS, "source", "scene");
    set(&mut h, FIVE_AXIS, "tol_mm", "0.01");
    let plan = settle_panel(&mut h, "5-axis scene steps");
    let blocks = plan["blocks"].as_u64().expect("blocks");
    assert!(blocks >= 3, "{plan}");
    click_panel_widget(&mut h, "fa_simulate");
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    assert_eq!(s["panel"]["title"], SIMULATION, "the button shows the simulation tab");
    assert_eq!(s["panel"]["status"]["source"], "steps");
    let a = settle_panel(&mut h, "simulation of the handed-over steps");
    assert_eq!(a["stage"], "done", "{a}");
    assert_eq!(a["moves_total"].as_u64(), Some(blocks - 1), "one move per pair of blocks: {a}");
    assert_eq!(a["design"], "scene surfaces");
    // Pin it as A.
    click_panel_widget(&mut h, "sim_pin_a");
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    let cmp = &s["panel"]["status"]["comparison"];
    assert_eq!(cmp["a"]["removed_volume_mm3"], a["removed_volume_mm3"], "{cmp}");
    assert_eq!(cmp["a"]["gouge"]["worst_um"], a["gouge"]["worst_um"], "{cmp}");
    assert_eq!(cmp["a"]["scallop_um"]["p95"], a["scallop_um"]["p95"], "{cmp}");
    assert!(cmp["a"]["program"].as_str().expect("program").contains("5-axis tool steps"), "{cmp}");

    // The NURBS & G-code tab's shown program (the scene's crease as G06.2): its text goes to
    // the simulation as program B, measured against the scene's surfaces with its ball.
    set(&mut h, "NURBS & G-code", "", "");
    let t0 = std::time::Instant::now();
    loop {
        h.frame();
        let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        if s["panel"]["status"]["ui"]["nurbs_simulate"].is_array() && s["panel"]["status"]["computing"] == false {
            break;
        }
        assert!(t0.elapsed() < HANG_GUARD, "the NURBS tab did not finish: {}", s["panel"]);
        // Its programs are written by background jobs: they need time, not frames.
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    set(&mut h, "NURBS & G-code", "simulate", "");
    h.frame();
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    assert_eq!(s["panel"]["title"], SIMULATION, "handed over: {}", s["panel"]);
    assert_eq!(s["panel"]["status"]["source"], "loaded");
    let b = settle_panel(&mut h, "simulation of the NURBS tab's program");
    assert_eq!(b["stage"], "done", "{b}");
    assert_eq!(b["design"], "scene surfaces");
    let cmp = &b["comparison"];
    assert!(cmp["b"]["program"].as_str().expect("program B").contains("NURBS & G-code tab"), "{cmp}");
    assert_eq!(cmp["b"]["removed_volume_mm3"], b["removed_volume_mm3"]);
    assert_eq!(cmp["a"]["removed_volume_mm3"], a["removed_volume_mm3"], "A stays pinned");
    assert_ne!(cmp["a"]["moves"], cmp["b"]["moves"], "two different programs of the part: {cmp}");
    // Both programs follow the same crease within their tolerance: neither gouges the part
    // by more than a few tolerances.
    for side in ["a", "b"] {
        let w = cmp[side]["gouge"]["worst_um"].as_f64().unwrap_or(0.0);
        assert!(w > -50.0, "{side}: {cmp}");
    }
}

/// Runs frames until the fillet tab's paths are done; returns its status.
fn settle_fillet(h: &mut Harness) -> serde_json::Value {
    let t0 = std::time::Instant::now();
    while t0.elapsed() < HANG_GUARD {
        h.frame();
        let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        let p = &s["panel"]["status"];
        if p["computing"] == false && p["passes"].is_u64() {
            return p.clone();
        }
    }
    panic!("the fillet tab did not finish its paths");
}

#[test]
fn the_fillet_tab_hands_its_program_to_the_simulation_and_two_maps_are_compared() {
    use interpolab::fillet::{PartSamples, iso_scallop};
    use interpolab::scene::finish::{FINISH_PRESETS, FinishScene};
    use interpolab::simulate::FinishProgram;
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FILLET, "preset", "finish-bicubic-patch");
    set(&mut h, FILLET, "strategy", "matched");
    set(&mut h, FILLET, "h", "0.04");
    set(&mut h, FILLET, "R", "6");
    set(&mut h, FILLET, "r", "1.5");
    // E coarser than the preset's 0.0005 mm: fewer steps, so the headless run stays short.
    set(&mut h, FILLET, "E", "0.002");
    let f = settle_fillet(&mut h);
    assert_eq!(f["error"], serde_json::Value::Null, "{f}");
    // The button, clicked: the simulation tab shows the fillet tab's program.
    click_panel_widget(&mut h, "fillet_simulate");
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    assert_eq!(s["panel"]["title"], SIMULATION, "the button shows the simulation tab: {}", s["panel"]);
    let p = &s["panel"]["status"];
    assert_eq!(p["source"], "finish", "{p}");
    assert_eq!(p["finish"]["passes"], f["passes"], "every pass handed over: {p}");
    assert!(p["finish"]["label"].as_str().expect("label").contains("matched, iso-scallop"), "{p}");
    assert_eq!(p["finish"]["cutter"], "fillet R 6 mm, r 1.5 mm", "{p}");
    assert_eq!(p["finish"]["step_tol_mm"], 0.002, "the tab's E: {p}");
    set(&mut h, SIMULATION, "pitch", "0.5");
    let a = settle_panel(&mut h, "simulation of the fillet tab's program");
    assert_eq!(a["stage"], "done", "{a}");
    assert_eq!(a["design"], "finish surface", "{a}");
    assert_eq!(a["cutter"], "fillet R 6 mm, r 1.5 mm", "{a}");
    // The core's own program on the same inputs: the same moves, on a stock sized to the part.
    let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).expect("preset");
    scene.finish.scallop = 0.04;
    scene.finish.cutter.radius = 6.0;
    scene.finish.cutter.corner_radius = 1.5;
    scene.finish.tolerance = 0.002;
    "matched".clone_into(&mut scene.finish.strategy);
    scene.finish.lead = None;
    let job = scene.job().expect("job");
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let set_core = iso_scallop(&job.setup(&part)).expect("core");
    let fp = FinishProgram::new(&job, &set_core, job.options.chord_tol_mm).expect("program");
    let program = fp.program().expect("planned");
    assert_eq!(a["moves_total"].as_u64(), Some(program.moves.len() as u64), "{a}");
    let stock = fp.stock_mm(2.0).expect("stock");
    let got: Vec<f64> = a["stock_mm"].as_array().expect("stock").iter().map(|v| v.as_f64().expect("mm")).collect();
    assert_eq!(got, stock.to_vec(), "the automatic stock is the part's box: {a}");
    // The command line on the same finishing scene gives the same numbers, the interior
    // band's scallops included (the tab shows both: interior and whole patch).
    let dir = std::env::temp_dir().join(format!("interpolab-interior-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let scene_path = dir.join("finish.json");
    std::fs::write(&scene_path, scene.to_json()).expect("scene written");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_interpolab"))
        .args(["simulate", scene_path.to_str().expect("path"), "--finish", "0.002", "--pitch", "0.5"])
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let cli: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(cli["moves"], a["moves_total"], "{cli}");
    assert_eq!(cli["scallop_um"], a["scallop_um"], "whole patch: {cli}");
    let (ci, ai) = (&cli["interior"]["scallop_um"], &a["scallop_interior_um"]);
    for k in ["rays", "max", "mean", "p95"] {
        assert_eq!(ci[k], ai[k], "interior {k}: command line {ci}, app {ai}");
    }
    assert_eq!(cli["interior"]["rays"], ai["band_rays"], "{cli}");
    assert!(ai["rays"].as_u64().expect("rays") > 100, "the band holds scallops: {ai}");
    // The band is a subset of the measured rays (since the paths end with lead-outs the
    // patch's edges no longer hold the largest scallop, so the two maxima may be equal).
    assert!(
        ai["rays"].as_u64().expect("rays") < a["scallop_um"]["rays"].as_u64().expect("rays")
            && ai["max"].as_f64().expect("max") <= a["scallop_um"]["max"].as_f64().expect("max"),
        "the interior is a part of the patch: {ai} vs {}",
        a["scallop_um"]
    );
    let _ = std::fs::remove_dir_all(&dir);
    // Scallops were measured over the patch; the matched paths leave about h between them.
    let sc = &a["scallop_um"];
    assert!(sc["rays"].as_u64().expect("rays") > 1000, "{a}");
    assert!(sc["p95"].as_f64().expect("p95") < 3.0 * 40.0, "{a}");
    // Pin A: its numbers and its map stay.
    click_panel_widget(&mut h, "sim_pin_a");
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    let cmp = s["panel"]["status"]["comparison"].clone();
    assert!(cmp["a"]["map"]["measured_rays"].as_u64().expect("A's map") > 1000, "{cmp}");
    assert_eq!(cmp["a"]["removed_volume_mm3"], a["removed_volume_mm3"], "{cmp}");
    assert!(s["panel"]["status"]["ui"]["sim_map_a"].is_array(), "A's map drawn: {}", s["panel"]["status"]["ui"]);

    // Program B: the same part with a ball end mill of the same R, from the same button.
    set(&mut h, FILLET, "strategy", "ball");
    let fb = settle_fillet(&mut h);
    assert!(fb["passes"].as_u64() > f["passes"].as_u64(), "the ball needs more passes: {fb}");
    set(&mut h, FILLET, "simulate", "");
    h.frame();
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    assert_eq!(s["panel"]["title"], SIMULATION);
    assert_eq!(s["panel"]["status"]["finish"]["cutter"], "ball R 6 mm", "{}", s["panel"]["status"]);
    let b = settle_panel(&mut h, "simulation of the ball program");
    assert_eq!(b["stage"], "done", "{b}");
    let cmp = &b["comparison"];
    assert_eq!(cmp["a"], s["panel"]["status"]["comparison"]["a"], "A stays pinned, map included");
    assert!(cmp["a"]["program"].as_str().expect("A").contains("matched"), "{cmp}");
    assert!(cmp["b"]["program"].as_str().expect("B").contains("ball"), "{cmp}");
    assert_eq!(cmp["b"]["removed_volume_mm3"], b["removed_volume_mm3"], "{cmp}");
    assert_eq!(cmp["b"]["map"]["nx"], b["grid"]["nx"], "{cmp}");
    assert!(cmp["b"]["moves"].as_u64() > cmp["a"]["moves"].as_u64(), "{cmp}");
    // Both maps drawn side by side, with one legend.
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    let ui = &s["panel"]["status"]["ui"];
    for k in ["sim_map_a", "sim_map_b", "sim_maps_legend"] {
        assert!(ui[k].is_array(), "{k} not drawn: {ui}");
    }
    let (ra, rb) = (&ui["sim_map_a"], &ui["sim_map_b"]);
    assert!(rb[0].as_f64() > ra[0].as_f64(), "B beside A: {ui}");
    // The same part at the same scale: the same size on screen.
    assert_eq!(ra[2], rb[2], "{ui}");
}

/// The fillet tab's panel status after one frame.
/// The shown view's status (`panel.status`) after one more frame.
fn panel_status(h: &mut Harness) -> serde_json::Value {
    h.frame();
    let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
    s["panel"]["status"].clone()
}

/// A primary click (press, release) at `at` (points).
fn click_at(h: &mut Harness, at: egui::Pos2) {
    let press = |pressed| egui::Event::PointerButton {
        pos: at,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    h.frame_events(vec![egui::Event::PointerMoved(at), press(true)]);
    h.frame_events(vec![press(false)]);
    h.frame_events(vec![egui::Event::PointerGone]);
}

/// Clicks on the surface in the fillet view pick the start curve: each picked point is the
/// surface point the camera shows under the click (re-projected within half a point), the
/// tab's paths are the core's from the scene the command line would read with that curve as
/// `finish.start`, and a click in "select" mode selects the CC node nearest on screen.
#[test]
fn a_curve_picked_in_the_fillet_view_is_the_cores_start_and_a_click_selects_a_cc_point() {
    use interpolab::fillet::{PartSamples, PathStart, iso_scallop};
    use interpolab::geom::ParametricSurface;
    use interpolab::render::OrbitCamera;
    use interpolab::scene::finish::{FINISH_PRESETS, FinishScene, StartSpec};
    let mut h = Harness::new();
    h.settle();
    set(&mut h, FILLET, "preset", "finish-bicubic-patch");
    set(&mut h, FILLET, "h", "0.04");
    set(&mut h, FILLET, "start", "picked");
    let s = panel_status(&mut h);
    assert_eq!(s["click_mode"], "pick", "{s}");
    assert!(s["error"].as_str().is_some_and(|e| e.contains("click 2 or more points")), "{s}");
    let r: Vec<f32> =
        s["ui"]["fillet_view"].as_array().expect("view rect").iter().map(|x| x.as_f64().unwrap() as f32).collect();
    let rect = egui::Rect::from_min_size(egui::pos2(r[0], r[1]), egui::vec2(r[2], r[3]));
    let clicks = [
        rect.center() + egui::vec2(-110.0, 15.0),
        rect.center() + egui::vec2(0.0, -10.0),
        rect.center() + egui::vec2(120.0, 5.0),
    ];
    for at in clicks {
        click_at(&mut h, at);
        let s = panel_status(&mut h);
        assert!(s["last_click"].as_str().is_some_and(|c| c.starts_with("picked")), "{s}");
    }
    let s = panel_status(&mut h);
    let picked: Vec<[f64; 2]> = s["picked"]
        .as_array()
        .expect("picked")
        .iter()
        .map(|p| [p[0].as_f64().expect("u"), p[1].as_f64().expect("v")])
        .collect();
    assert_eq!(picked.len(), 3, "{s}");
    // Each picked point, seen through the tab's camera, lies under its click.
    let cam = &s["camera"];
    let f = |v: &serde_json::Value| v.as_f64().expect("number") as f32;
    let camera = OrbitCamera {
        target: glam::Vec3::new(f(&cam["target"][0]), f(&cam["target"][1]), f(&cam["target"][2])),
        yaw: f(&cam["yaw"]),
        pitch: f(&cam["pitch"]),
        distance: f(&cam["distance"]),
        fov_y: f(&cam["fov_y"]),
    };
    let origin = glam::DVec3::new(
        cam["origin_mm"][0].as_f64().unwrap(),
        cam["origin_mm"][1].as_f64().unwrap(),
        cam["origin_mm"][2].as_f64().unwrap(),
    );
    let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).expect("preset");
    scene.finish.scallop = 0.04;
    scene.finish.start = Some(StartSpec::Curve(picked.clone()));
    let job = scene.job().expect("the picked curve is a valid start");
    assert!(matches!(job.start, PathStart::Curve(_)));
    let screen = |p: glam::DVec3| {
        let ndc = camera.project(rect.width() / rect.height(), (p - origin).as_vec3())?;
        Some(egui::pos2(
            rect.left() + (ndc.x + 1.0) * 0.5 * rect.width(),
            rect.top() + (1.0 - ndc.y) * 0.5 * rect.height(),
        ))
    };
    for (uv, at) in picked.iter().zip(clicks) {
        let p = job.surface.point_at(interpolab::scene::params_from_file(&job.surface, glam::DVec2::from(*uv)));
        let seen = screen(p).expect("in front of the camera");
        assert!(seen.distance(at) < 0.5, "picked {uv:?} appears at {seen:?}, clicked at {at:?}");
    }
    // The paths: the core's from the same scene.
    let s = settle_panel(&mut h, "fillet paths from a picked curve");
    assert_eq!(s["error"], serde_json::Value::Null, "{s}");
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let core = iso_scallop(&job.setup(&part)).expect("core");
    let st = core.stats(job.options.feed_mm_per_min);
    assert!(core.second_side.is_some(), "an interior curve: paths on both sides");
    assert_eq!(s["passes"], st.passes, "{s}");
    assert_eq!(s["nodes"], st.nodes, "{s}");
    assert_eq!(s["second_side"], core.second_side.expect("second side"), "{s}");
    let got = s["length_mm"].as_f64().expect("length");
    assert!((got - st.length_mm).abs() <= 1e-14 * st.length_mm, "{got} against {}", st.length_mm);
    // A click in "select" mode selects the CC node nearest to it on screen.
    set(&mut h, FILLET, "click_mode", "select");
    let at = rect.center() + egui::vec2(40.0, 60.0);
    click_at(&mut h, at);
    let s = panel_status(&mut h);
    let mut best = (f32::INFINITY, 0, 0);
    for (p, path) in core.paths.iter().enumerate() {
        for (k, n) in path.nodes.iter().enumerate().filter(|(_, n)| !n.lead_out) {
            if let Some(q) = screen(n.frame.point)
                && q.distance(at) < best.0
            {
                best = (q.distance(at), p, k);
            }
        }
    }
    assert!(best.0 < 14.0, "a CC node near the click: {best:?}");
    assert_eq!(
        (s["selected"]["path"].as_u64(), s["selected"]["node"].as_u64()),
        (Some(best.1 as u64), Some(best.2 as u64)),
        "{s}"
    );
}

// The Your program tab.
#[path = "app/userprog.rs"]
mod userprog;

// The 5-axis tab's time of its plans.
#[path = "app/fiveaxis_time.rs"]
mod fiveaxis_time;
