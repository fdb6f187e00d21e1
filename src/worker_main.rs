//! The `interpolab-worker` binary: the core compiled to wasm for the browser's Web Worker
//! (built by Trunk from `web/index.html` with `--no-default-features --features worker`:
//! no egui, no wgpu). It answers the app's background jobs (`interpolab::jobs`).

#![forbid(unsafe_code)]

#[cfg(all(target_arch = "wasm32", feature = "worker"))]
fn main() {
    worker::start();
}

/// The Web Worker's side: installs a message handler on the worker's global scope, then says
/// `ready`. The worker's script (`web/jobs-worker.js`) keeps the messages that arrive before
/// this handler is installed and hands them to it afterwards, so the page posts a job without
/// waiting for `ready`. Each message is a string `kind '\n' request`; the answer is `ok '\n' output` or
/// `err '\n' message` (a request the worker cannot decode). Progress is posted as
/// `progress '\n' fraction`, a partial output as `partial '\n' text`. The page runs one job at a time on a worker, terminates it to
/// cancel (so a job here never needs to look at `Progress::cancelled`) and may send a worker
/// that answered its next job. (Browser glue lives in this
/// binary, not in the core: `tests/core_boundary.rs`.)
#[cfg(all(target_arch = "wasm32", feature = "worker"))]
mod worker {
    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::{Closure, JsValue};

    use interpolab::jobs::{Progress, run_encoded};

    struct Post(web_sys::DedicatedWorkerGlobalScope);

    impl Progress for Post {
        fn progress(&mut self, fraction: f64) {
            let _ = self.0.post_message(&JsValue::from_str(&format!("progress\n{fraction}")));
        }
        fn cancelled(&self) -> bool {
            false
        }
        fn partial(&mut self, encoded: String) {
            let _ = self.0.post_message(&JsValue::from_str(&format!("partial\n{encoded}")));
        }
    }

    /// Installs the handler (the worker binary's `main`).
    pub fn start() {
        let scope: web_sys::DedicatedWorkerGlobalScope = js_sys::global().unchecked_into();
        let reply_to = scope.clone();
        let handler = Closure::<dyn FnMut(web_sys::MessageEvent)>::new(move |e: web_sys::MessageEvent| {
            let text = e.data().as_string().unwrap_or_default();
            let (name, request) = text.split_once('\n').unwrap_or((text.as_str(), ""));
            let mut post = Post(reply_to.clone());
            let answer = match run_encoded(name, request, &mut post) {
                Ok(out) => format!("ok\n{out}"),
                Err(e) => format!("err\n{e}"),
            };
            let _ = reply_to.post_message(&JsValue::from_str(&answer));
        });
        scope.set_onmessage(Some(handler.as_ref().unchecked_ref()));
        handler.forget();
        let _ = scope.post_message(&JsValue::from_str("ready\n"));
    }
}

#[cfg(not(all(target_arch = "wasm32", feature = "worker")))]
fn main() {
    eprintln!("interpolab-worker runs only in a browser's Web Worker (wasm32, feature worker)");
}
