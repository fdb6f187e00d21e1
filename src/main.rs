//! The `interpolab` binary.
//!
//! - Natively: the command line (`interpolab run SCENE`, `interpolab check SCENE`, …); with no
//!   subcommand and the `app` feature it opens the app in a window.
//! - On wasm32 (built by Trunk): starts the browser app on the page's canvas.

#![forbid(unsafe_code)]

#[cfg(not(target_arch = "wasm32"))]
mod cli;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(all(target_arch = "wasm32", feature = "app"))]
fn main() {
    interpolab::app::web::start();
}

#[cfg(all(target_arch = "wasm32", not(feature = "app")))]
fn main() {}
