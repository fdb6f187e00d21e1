//! The native window: the same app on the desktop, `cargo run` without arguments.

use super::InterpolabApp;

/// Opens the app in a window and returns when it closes.
///
/// # Errors
/// When no window or GPU device can be created.
pub fn run() -> Result<(), eframe::Error> {
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: eframe::egui::ViewportBuilder::default().with_inner_size([1400.0, 900.0]).with_title("interpolab"),
        ..Default::default()
    };
    eframe::run_native("interpolab", options, Box::new(|cc| Ok(Box::new(InterpolabApp::new(cc)))))
}
