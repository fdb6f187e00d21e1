//! The `interpolab-worker` binary: the core compiled to wasm for the browser's Web Worker
//! (built by Trunk from `web/index.html` with `--no-default-features --features worker`:
//! no egui, no wgpu). It answers the app's background jobs (`interpolab::jobs`).

#![forbid(unsafe_code)]

#[cfg(all(target_arch = "wasm32", feature = "worker"))]
fn main() {
    interpolab::jobs::worker::start();
}

#[cfg(not(all(target_arch = "wasm32", feature = "worker")))]
fn main() {
    eprintln!("interpolab-worker runs only in a browser's Web Worker (wasm32, feature worker)");
}
