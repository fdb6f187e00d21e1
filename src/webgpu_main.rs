//! The `interpolab-webgpu` binary: the browser page built with WebGPU alone (feature
//! `webgpu`), which `web/index.html` loads when the browser offers a WebGPU adapter. It is the
//! same app as `interpolab` on wasm32 (`app::web::start`), without WebGL2. Natively there is
//! nothing to run: the command line and the window are `interpolab`.

#![forbid(unsafe_code)]

#[cfg(target_arch = "wasm32")]
fn main() {
    interpolab::app::web::start();
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    eprintln!("interpolab-webgpu is the browser page's WebGPU build; natively, run `interpolab`");
    std::process::ExitCode::from(2)
}
