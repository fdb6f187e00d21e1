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
        el.set_inner_html(&format!(
            "<p><b>interpolab stopped.</b></p><p>{}</p><p>Reload the page to start again; your last scene is kept.</p>",
            message.replace('&', "&amp;").replace('<', "&lt;")
        ));
        if let Ok(html) = el.dyn_into::<web_sys::HtmlElement>() {
            let _ = html.style().set_property("display", "block");
        }
        let _ = doc.document_element().map(|e| e.class_list().add_1("failed"));
    }
}

/// Starts the app (called from `main` on wasm32).
pub fn start() {
    eframe::WebLogger::init(log::LevelFilter::Info).ok();
    let web_options = eframe::WebOptions::default();
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
        let started = runner.start(canvas, web_options, Box::new(|cc| Ok(Box::new(InterpolabApp::new(cc))))).await;
        match started {
            Ok(()) => {
                if let Some(el) = doc.get_element_by_id(LOADING_ID) {
                    el.remove();
                }
                // Watch for a later panic: eframe stops the app; tell the user instead of
                // leaving a frozen canvas.
                watch_for_panic(runner);
            }
            Err(e) => show_failure(&format!("It could not start: {e:?}. A browser with WebGPU or WebGL2 is needed.")),
        }
    });
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
