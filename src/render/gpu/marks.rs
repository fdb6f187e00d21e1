//! Measuring aids of the 3D views (`app::ablate`, web `?hide=`): layers or whole scene passes
//! left out, performance marks of passes and uploads, and the one log line of a missing
//! resource. Process-wide switches, off in normal use.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use super::Layer;

/// Measuring only (`app::ablate`, web `?hide=`): the layers left out of every scene pass, one
/// bit per [`Layer`] in declaration order, and bit 31 to skip the scene pass altogether (the
/// view then shows the image it holds). Zero in normal use.
pub(super) static SKIPPED: AtomicU32 = AtomicU32::new(0);

/// The bit of `SKIPPED` that skips the whole scene pass.
pub const SKIP_SCENE_PASS: u32 = 1 << 31;

/// Sets the layers (bit `1 << layer as u32`) left out of every scene pass, for measuring.
pub fn set_skipped_layers(bits: u32) {
    SKIPPED.store(bits, Ordering::Relaxed);
}

/// Measuring only (`app::ablate`, web `?hide=marks`): whether the renderer leaves a
/// `performance.mark` in the page for each scene pass and each layer upload, so a Chromium
/// trace (`e2e/frame-profile.mjs --trace`) tells what a long frame held. Off in normal use.
static MARKS: AtomicBool = AtomicBool::new(false);

/// Turns the performance marks of scene passes and uploads on or off, for measuring.
pub fn set_marks(on: bool) {
    MARKS.store(on, Ordering::Relaxed);
}

/// Leaves `text()` as a performance mark in the page when marks are on (web only).
pub(super) fn mark(text: impl FnOnce() -> String) {
    if !MARKS.load(Ordering::Relaxed) {
        return;
    }
    let text = text();
    #[cfg(target_arch = "wasm32")]
    if let Some(p) = web_sys::window().and_then(|w| w.performance()) {
        // A failed mark only loses a measuring aid.
        let _ = p.mark(&text);
    }
    #[cfg(not(target_arch = "wasm32"))]
    log::debug!("{text}");
}

/// Whether `layer` is left out of every scene pass.
pub(super) fn skipped(layer: Layer) -> bool {
    SKIPPED.load(Ordering::Relaxed) & (1 << layer as u32) != 0
}

/// Whether a missing resource was logged already.
static MISSING_LOGGED: AtomicBool = AtomicBool::new(false);

/// Logs the first missing resource (`what`); later ones are skipped silently.
pub(super) fn log_missing_once(what: &str) {
    if !MISSING_LOGGED.swap(true, Ordering::Relaxed) {
        log::error!("3D view skipped: {what}");
    }
}
