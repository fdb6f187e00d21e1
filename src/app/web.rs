//! The browser entry point: starts the app on the page's canvas, removes the loading text,
//! and shows a visible message if the app fails to start or panics later.

use eframe::wasm_bindgen::JsCast;

use super::InterpolabApp;

/// Id of the canvas in `web/index.html`.
pub const CANVAS_ID: &str = "interpolab_canvas";
/// Id of the loading / error text in `web/index.html`.
pub const LOADING_ID: &str = "loading_text";

fn show_failure(message: &str) {
    let Some(doc) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    if let Some(el) = doc.get_element_by_id(LOADING_ID) {
        // Fixed markup; the message (which may quote a scene's name) only as text.
        el.set_inner_html("<p><b>interpolab stopped.</b></p>");
        for text in [message, "Reload the page to start again; your last scene is kept."] {
            if let Ok(p) = doc.create_element("p") {
                p.set_text_content(Some(text));
                let _ = el.append_child(&p);
            }
        }
        if let Ok(html) = el.dyn_into::<web_sys::HtmlElement>() {
            let _ = html.style().set_property("display", "block");
        }
        let _ = doc.document_element().map(|e| e.class_list().add_1("failed"));
    }
}

/// The WebGPU-only build could not start: asks the page's loader (`web/index.html`,
/// `interpolabLoadWebGlPage`) to load the build with WebGL2 on a fresh canvas. False when the
/// page has no such loader.
fn hand_over_to_webgl_page(message: &str) -> bool {
    let Some(window) = web_sys::window() else {
        return false;
    };
    let Ok(f) = js_sys::Reflect::get(&window, &"interpolabLoadWebGlPage".into()) else {
        return false;
    };
    let Ok(f) = f.dyn_into::<js_sys::Function>() else {
        return false;
    };
    f.call1(&window, &message.into()).is_ok()
}

/// Starts the app (called from `main` on wasm32).
pub fn start() {
    eframe::WebLogger::init(log::LevelFilter::Info).ok();
    // No dithering: egui's UI is flat colours, where it changes nothing visible, and on a CPU
    // rasteriser (SwiftShader) it is a sizeable part of every pixel's shading.
    let web_options = eframe::WebOptions { dithering: false, ..eframe::WebOptions::default() };
    let query = web_sys::window().and_then(|w| w.location().search().ok()).unwrap_or_default();
    // Measuring only (`e2e/frame-profile.mjs`): parts of the frame left out, see `app::ablate`.
    super::ablate::set(super::ablate::parse(&query));
    wasm_bindgen_futures::spawn_local(async move {
        let Some(doc) = web_sys::window().and_then(|w| w.document()) else {
            return;
        };
        let Some(canvas) =
            doc.get_element_by_id(CANVAS_ID).and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        else {
            show_failure(&format!("the page has no <canvas id=\"{CANVAS_ID}\">"));
            return;
        };
        let runner = eframe::WebRunner::new();
        let started = if query.contains(FLOOR_QUERY) {
            let extra = FloorExtra::from_query(&query);
            runner
                .start(canvas, web_options, Box::new(move |cc| Ok(Box::new(FloorProbe::new(&cc.egui_ctx, extra)))))
                .await
        } else {
            runner.start(canvas, web_options, Box::new(|cc| Ok(Box::new(InterpolabApp::new(cc))))).await
        };
        match started {
            Ok(()) => {
                if let Some(el) = doc.get_element_by_id(LOADING_ID) {
                    el.remove();
                }
                // Watch for a later panic: eframe stops the app; tell the user instead of
                // leaving a frozen canvas.
                watch_for_panic(runner);
            }
            Err(e) => {
                let message = format!("It could not start: {e:?}. A browser with WebGPU or WebGL2 is needed.");
                // The WebGPU-only page hands over to the page with WebGL2 (web/index.html).
                if cfg!(feature = "webgl") || !hand_over_to_webgl_page(&message) {
                    show_failure(&message);
                }
            }
        }
    });
}

/// The query that starts [`FloorProbe`] instead of the app (`e2e/frame-profile.mjs`).
const FLOOR_QUERY: &str = "probe=floor";

/// Most extra shapes [`FloorExtra`] draws.
const FLOOR_EXTRA_MAX: usize = 10_000;

/// What the floor probe draws besides its line of text, to price SwiftShader's costs
/// (`?probe=floor&draws=N&shapes=N&fills=N`, each at most [`FLOOR_EXTRA_MAX`]).
#[derive(Clone, Copy, Debug, Default)]
struct FloorExtra {
    /// Small rectangles (8×8 points), each in a clip rectangle of its own: as many extra
    /// draw calls in egui's render pass.
    draws: usize,
    /// The same rectangles, all in the panel's clip rectangle: as many shapes, one draw.
    shapes: usize,
    /// Translucent rectangles covering the whole window: as many coverings of every pixel.
    fills: usize,
}

impl FloorExtra {
    fn from_query(query: &str) -> Self {
        let q = query.strip_prefix('?').unwrap_or(query);
        let get = |key: &str| {
            q.split('&')
                .find_map(|kv| kv.strip_prefix(key).and_then(|v| v.strip_prefix('=')))
                .and_then(|v| v.parse::<usize>().ok())
                .map_or(0, |n| n.min(FLOOR_EXTRA_MAX))
        };
        Self { draws: get("draws"), shapes: get("shapes"), fills: get("fills") }
    }
}

/// The frame-time floor of this browser: an egui frame at the page's size with one line of
/// text and nothing to compute, redrawn continuously. `e2e/frame-profile.mjs` compares every
/// tab's frames with it. It publishes `{"probe":"floor","frames":n}` in the status element.
struct FloorProbe {
    frames: u64,
    extra: FloorExtra,
}

impl FloorProbe {
    /// With the app's fonts and look (transparent panels over the cleared frame).
    fn new(ctx: &eframe::egui::Context, extra: FloorExtra) -> Self {
        super::style(ctx);
        Self { frames: 0, extra }
    }
}

impl eframe::App for FloorProbe {
    fn clear_color(&self, _visuals: &eframe::egui::Visuals) -> [f32; 4] {
        super::PANEL_FILL.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut eframe::egui::Ui, _frame: &mut eframe::Frame) {
        self.frames += 1;
        let extra = self.extra;
        eframe::egui::CentralPanel::default().show(ui, |ui| {
            use eframe::egui::{Color32, Rect, pos2, vec2};
            ui.label(format!("interpolab frame-time floor: an empty frame, drawn {} times", self.frames));
            let area = ui.max_rect();
            let cols = ((area.width() / 10.0).max(1.0)) as usize;
            let cell = |i: usize| {
                Rect::from_min_size(
                    area.min + vec2((i % cols) as f32 * 10.0, 30.0 + (i / cols) as f32 * 10.0),
                    vec2(8.0, 8.0),
                )
            };
            for i in 0..extra.draws {
                let r = cell(i);
                ui.painter().with_clip_rect(r.expand(1.0)).rect_filled(r, 0.0, Color32::from_rgb(90, 140, 200));
            }
            for i in 0..extra.shapes {
                ui.painter().rect_filled(cell(i), 0.0, Color32::from_rgb(200, 140, 90));
            }
            let all = ui.ctx().content_rect();
            for _ in 0..extra.fills {
                ui.painter().with_clip_rect(all).rect_filled(
                    Rect::from_min_max(pos2(all.min.x, all.min.y), all.max),
                    0.0,
                    Color32::from_white_alpha(4),
                );
            }
        });
        if let Some(el) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.get_element_by_id("app-status")) {
            el.set_text_content(Some(&format!("{{\"probe\":\"floor\",\"frames\":{}}}", self.frames)));
        }
        ui.ctx().request_repaint();
    }
}

fn watch_for_panic(runner: eframe::WebRunner) {
    use eframe::wasm_bindgen::prelude::Closure;
    let Some(window) = web_sys::window() else {
        return;
    };
    let handle = std::rc::Rc::new(std::cell::Cell::new(0));
    let handle2 = handle.clone();
    let check = Closure::<dyn FnMut()>::new(move || {
        if runner.has_panicked() {
            let summary = runner.panic_summary().map_or_else(|| "unknown error".to_owned(), |s| s.message());
            // Recreate the message element (it was removed after the start).
            if let Some(doc) = web_sys::window().and_then(|w| w.document())
                && doc.get_element_by_id(LOADING_ID).is_none()
                && let (Ok(div), Some(body)) = (doc.create_element("div"), doc.body())
            {
                div.set_id(LOADING_ID);
                let _ = body.append_child(&div);
            }
            show_failure(&format!("It hit an internal error: {summary}"));
            if let Some(w) = web_sys::window() {
                w.clear_interval_with_handle(handle2.get());
            }
        }
    });
    if let Ok(id) = window.set_interval_with_callback_and_timeout_and_arguments_0(check.as_ref().unchecked_ref(), 1000)
    {
        handle.set(id);
    }
    check.forget();
}
