//! The interface every tab implements, the crease view included (one struct per tab, as
//! egui's demo apps do): a title, the controls it shows in the app's side panel, and a `ui`
//! that draws the central area, both from a shared context. Tabs own their state and their
//! GPU view id; they read the scene and its computed crease and change the scene only
//! through the shared scene controls ([`PanelContext::scene_controls`]).

use std::rc::Rc;

use eframe::egui;
use eframe::egui_wgpu::RenderState;

use super::Playback;
use super::compute::Computation;
use super::platform::{FileKind, Incoming, Platform};
use super::scene_controls::{SceneEditor, scene_controls};
use crate::crease::CreaseCurve;
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
    /// The crease's playback position (the app advances it every frame).
    pub playback: &'a mut Playback,
    /// The scene as the shared controls edit it (draft, method, requests to the app).
    pub editor: &'a mut SceneEditor,
    /// Rectangles of widgets published at the top level of the status element's `ui`.
    pub rects: &'a mut Vec<(&'static str, egui::Rect)>,
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

/// Title of the fillet end mill view, where a finishing program for the simulation is made.
pub const FILLET_TITLE: &str = "Fillet end mill";

/// A request from one view to another, routed by the app after the frame: show the view
/// titled `to` and set its options in order, as [`Panel::set_option`] would — e.g. the 5-axis
/// tab's "Simulate this program" is `("Cutting simulation", [("source", "steps")])`. A view
/// hands over what it shows without knowing the other view's type.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Handoff {
    /// Title of the receiving view.
    pub to: &'static str,
    /// Options to set on it, in order (key, value).
    pub options: Vec<(&'static str, String)>,
    /// Data too large for an option, given to [`Panel::receive`] before the options.
    pub payload: Option<Payload>,
}

/// Data one view hands another (plain data, shared, never edited by the receiver).
#[derive(Clone, Debug, PartialEq)]
pub enum Payload {
    /// A seed-001 finishing program (the fillet tab's paths, cutter, machine and surface).
    Finish(Rc<FinishHandoff>),
}

/// A seed-001 finishing program handed to the simulation, with the finishing scene it was
/// made from as text (what a background job rebuilds the design surface from).
#[derive(Clone, Debug, PartialEq)]
pub struct FinishHandoff {
    /// The passes, cutter, machine and surface.
    pub program: crate::simulate::FinishProgram,
    /// The finishing scene (`FinishScene::to_json`).
    pub scene_json: String,
    /// The scallop height h (mm) the paths were built for (the simulation samples finely
    /// enough to measure it).
    pub scallop_mm: f64,
}

impl PanelContext<'_> {
    /// Draws the scene's controls (picker, every input, the method) for a tab that shows the
    /// scene or its crease; the app applies the edits after the frame's panels.
    pub fn scene_controls(&mut self, ui: &mut egui::Ui) {
        let sense = self.compute.start_sense().map(|d| [d.x, d.y, d.z]);
        scene_controls(ui, self.editor, sense, self.rects);
    }
    /// Publishes a widget's rectangle under `name` at the top level of the status's `ui`.
    pub fn publish(&mut self, name: &'static str, rect: egui::Rect) {
        self.rects.push((name, rect));
    }
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

/// A tab: its controls in the side panel and its view in the central area.
pub trait Panel {
    /// Tab title (also the key of its tab button in the status element, and what the
    /// end-to-end test clicks).
    fn title(&self) -> &'static str;
    /// The paper the view is built from, as one line for its help (authors, English title,
    /// venue, year: `app::papers`); `None` for a view of the user's own work.
    fn paper(&self) -> Option<&'static str> {
        None
    }
    /// The kind of files this view accepts (routed to it when opened or dropped).
    fn accepts(&self) -> Option<FileKind> {
        None
    }
    /// Other kinds of files this view takes: routed to it when it is shown, or when no view
    /// [`Panel::accepts`] them first.
    fn accepts_also(&self) -> &'static [FileKind] {
        &[]
    }
    /// Draws the controls that act on what this tab shows into the app's side panel; a tab
    /// that shows the scene or its crease adds the shared [`PanelContext::scene_controls`].
    /// Called every frame before [`Panel::ui`].
    fn controls(&mut self, _ui: &mut egui::Ui, _cx: &mut PanelContext<'_>) {}
    /// Draws the view into the whole central area (its own plots, tables and prose included).
    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>);
    /// A new scene was opened (a file, a preset, a link): e.g. frame it again.
    fn scene_opened(&mut self) {}
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
    /// Takes data another view handed over ([`Handoff::payload`]); an error when the view
    /// takes none of that kind.
    fn receive(&mut self, payload: &Payload) -> Result<(), String> {
        let kind = match payload {
            Payload::Finish(_) => "a finishing program",
        };
        Err(format!("this view cannot take {kind}"))
    }
}

/// Why the scene's crease is not (yet) a design curve.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CreaseProblem {
    /// Its computation is still running (the text says how far it is).
    Waiting(String),
    /// It failed or is too short (the text says why).
    Failed(String),
}

/// The scene's computed crease as a design curve (`CreaseCurve::from_rows`), built once per
/// computation: what the tabs that cut, step or fit along the crease start from.
#[derive(Default)]
pub struct SceneCrease {
    built: Option<(u64, Result<Rc<CreaseCurve>, String>)>,
}

impl SceneCrease {
    /// The crease of the finished computation `c`, or why there is none yet.
    pub fn get(&mut self, c: &Computation) -> Result<Rc<CreaseCurve>, CreaseProblem> {
        if c.running() {
            return Err(CreaseProblem::Waiting(format!(
                "waiting for the crease of the scene: {} periods so far…",
                c.periods.len()
            )));
        }
        if self.built.as_ref().is_none_or(|(g, _)| *g != c.generation) {
            let built = match (&c.job, &c.outcome) {
                (_, Some(Err(e))) => Err(format!("the crease of this scene could not be computed — {e}")),
                (Some(job), _) => {
                    let rows: Vec<_> = c.periods.iter().map(|p| p.row).collect();
                    CreaseCurve::from_rows(job, &rows)
                        .map(Rc::new)
                        .ok_or_else(|| "the crease of this scene has fewer than two points".to_owned())
                }
                (None, _) => Err("the scene has no valid crease".to_owned()),
            };
            self.built = Some((c.generation, built));
        }
        match &self.built {
            Some((_, r)) => r.clone().map_err(CreaseProblem::Failed),
            None => Err(CreaseProblem::Failed("the scene has no valid crease".to_owned())),
        }
    }
}
