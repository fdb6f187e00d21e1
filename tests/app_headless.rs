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
