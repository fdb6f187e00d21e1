//! The app run headless (no window, no GPU): every preset computes the same path as the
//! core, and every slider pushed to either end of its range gives a clear message or a
//! valid result — never a panic or a NaN on screen. Native only; needs the `app` feature.
#![cfg(all(feature = "app", not(target_arch = "wasm32")))]

use eframe::egui;
use interpolab::app::InterpolabApp;
use interpolab::crease::{CreaseJob, InterpOptions, run_to_end};
use interpolab::scene::{PRESETS, Scene};

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
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1400.0, 900.0))),
            ..Default::default()
        };
        let (app, frame) = (&mut self.app, &mut self.frame);
        let out = self.ctx.run_ui(input, |ui| eframe::App::ui(app, ui, frame));
        out.drop_without_applying_deltas();
    }

    /// Runs frames until the computation settles; returns the status.
    fn settle(&mut self) -> serde_json::Value {
        for _ in 0..5000 {
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

/// Pushes each slider to both ends of its range (the ranges of `controls.rs`).
#[test]
fn sliders_at_their_extremes_never_panic_or_show_nan() {
    type Edit = fn(&mut Scene, bool);
    let edits: [(&str, Edit); 7] = [
        ("feed", |s, hi| s.motion.feed = if hi { 60_000.0 } else { 10.0 }),
        ("period", |s, hi| s.motion.period = if hi { 50.0 } else { 0.1 }),
        ("radius", |s, hi| s.tool.radius = if hi { 25.0 } else { 0.2 }),
        ("allowance", |s, hi| s.tool.allowance = if hi { 3.0 } else { -1.0 }),
        ("t1", |s, hi| s.tolerance.t1 = if hi { 0.5 } else { 1e-5 }),
        ("share", |s, hi| s.tolerance.share = if hi { 1.0 } else { 0.01 }),
        ("feed and period", |s, hi| {
            s.motion.feed = if hi { 60_000.0 } else { 10.0 };
            s.motion.period = if hi { 50.0 } else { 0.1 };
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

/// Shows a view and sets an option as its widgets would.
fn set(h: &mut Harness, title: &str, key: &str, value: &str) {
    if let Err(e) = h.app.set_panel_option(title, key, value) {
        panic!("{title} {key}={value}: {e}");
    }
}

/// Runs frames until the shown view's status says it is done; returns that status.
fn settle_panel(h: &mut Harness, what: &str) -> serde_json::Value {
    for _ in 0..20_000 {
        h.frame();
        let s: serde_json::Value = serde_json::from_str(&h.app.status()).expect("status is JSON");
        let p = &s["panel"]["status"];
        if s["running"] == false && p.is_object() && p["computing"] == false {
            let text = s.to_string();
            assert!(!text.contains("NaN") && !text.contains("inf"), "{what}: {text}");
            return p.clone();
        }
    }
    panic!("{what}: the view did not finish");
}

const FIVE_AXIS: &str = "5-axis (seed 002)";

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
    for tol in ["1.0", "0.0005"] {
        set(&mut h, FIVE_AXIS, "tol_mm", tol);
        let s = settle_panel(&mut h, "blade");
        assert_eq!(s["error"], "", "{tol}: {s}");
    }
    // A machine whose head cannot reach the blade's tool axes: a clear message, no panic.
    set(&mut h, FIVE_AXIS, "tol_mm", "0.05");
    set(&mut h, FIVE_AXIS, "machine", "head-a-table-c");
    let s = settle_panel(&mut h, "blade on head-a-table-c");
    let err = s["error"].as_str().expect("text");
    if !err.is_empty() {
        assert!(err.contains("change") || err.contains("widen") || err.contains("raise"), "{err}");
    }
}

const CHORDS: &str = "Chords (seed 003)";

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
    for tol in ["1.0", "0.001"] {
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
