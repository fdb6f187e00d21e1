//! The interface every central view besides the crease view implements (one struct per
//! view, as egui's demo apps do): a title for its tab and a `ui` that draws it from a shared
//! context. Views own their state and their GPU view id; they read the scene and the
//! computed crease, never change them.

use eframe::egui;
use eframe::egui_wgpu::RenderState;

use super::Playback;
use super::compute::Computation;
use super::platform::{FileKind, Incoming, Platform};
use crate::scene::Scene;

/// What a view may read and do this frame.
pub struct PanelContext<'a> {
    /// The current (valid) scene.
    pub scene: &'a Scene,
    /// The crease computed for it: `compute.job`, `compute.periods` (rows with measured
    /// errors), `compute.running()`, `compute.generation` (bumped on every restart).
    pub compute: &'a Computation,
    /// The GPU, when the app runs with wgpu (for 3D views: `crate::render`).
    pub render_state: Option<&'a RenderState>,
    /// The crease view's playback position.
    pub playback: &'a Playback,
    /// File picker / download.
    pub platform: &'a mut Platform,
    /// Files of this view's kind given to the app this frame (e.g. a dropped `.nc`).
    pub incoming: Vec<Incoming>,
    /// The last G-code file opened in the app (name, text), whichever view read it.
    pub program: &'a Option<(String, String)>,
    /// Bumped for every G-code file opened.
    pub program_generation: u64,
    /// Messages for the banner: `Err` for problems, `Ok` for information.
    pub messages: Vec<Result<String, String>>,
    /// A request to hand something to another view (set by the view, routed by the app
    /// after the frame).
    pub handoff: Option<Handoff>,
}

/// Title of the cutting simulation view, the target of the "Simulate this program" buttons.
pub const SIMULATION_TITLE: &str = "Cutting simulation";

/// A request from one view to another, routed by the app after the frame: show the view
/// titled `to` and set its options in order, as [`Panel::set_option`] would — e.g. the 5-axis
/// tab's "Simulate this program" is `("Cutting simulation", [("source", "steps")])`. A view
/// hands over what it shows without knowing the other view's type.
#[derive(Clone, Debug, PartialEq)]
pub struct Handoff {
    /// Title of the receiving view.
    pub to: &'static str,
    /// Options to set on it, in order (key, value).
    pub options: Vec<(&'static str, String)>,
}

impl PanelContext<'_> {
    /// Shows an error in the app's banner.
    pub fn error(&mut self, text: impl Into<String>) {
        self.messages.push(Err(text.into()));
    }
    /// Shows a short information in the app's banner.
    pub fn info(&mut self, text: impl Into<String>) {
        self.messages.push(Ok(text.into()));
    }
    /// Opens the file picker for a kind of file (the result arrives in `incoming`).
    pub fn pick_file(&mut self, kind: FileKind) {
        self.platform.pick_file(kind);
    }
    /// Downloads (web) or saves (native) a text file; reports the outcome in the banner.
    pub fn save_text(&mut self, name: &str, text: &str) {
        match self.platform.save_text(name, text) {
            Ok(m) => self.info(m),
            Err(e) => self.error(format!("Saving {name} failed: {e}")),
        }
    }
}

/// A central view with its own tab.
pub trait Panel {
    /// Tab title.
    fn title(&self) -> &'static str;
    /// The kind of files this view accepts (routed to it when opened or dropped).
    fn accepts(&self) -> Option<FileKind> {
        None
    }
    /// Draws the view into the whole central area.
    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>);
    /// What the view shows, for the app's status element (end-to-end and headless tests):
    /// e.g. whether it is computing, its main numbers, its error. `Null` by default.
    fn status(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
    /// Sets one of the view's options by name, as its widgets would (for headless tests and
    /// automation), e.g. `("source", "scene")`. An unknown key or a bad value is an error
    /// saying what the view accepts.
    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        Err(format!("this view has no option \"{key}\" (value \"{value}\")"))
    }
}
