//! The app (feature `app`): state, widgets and views over the core. Thin by design: every
//! number it shows comes from the core; this layer keeps state, lays out widgets and feeds
//! the renderer.
//!
//! Data flow, slider to frame: a control edits the *draft* scene → the draft is validated
//! (core) → if valid it becomes the scene and the `compute::Computation` restarts → each
//! frame the computation advances within a time budget → views read its periods (rows,
//! measured errors, estimates, exact crease points) → the 3D view uploads what changed to the
//! GPU and the plots draw.

pub mod ablate;
pub mod budget;
mod chords_panel;
mod compute;
mod crease_panel;
mod fillet_panel;
mod fiveaxis_panel;
pub mod fonts;
pub mod jobs;
mod nurbs_panel;
mod overlay;
pub mod panel;
mod papers;
mod platform;
pub mod ranges;
mod scene_controls;
mod simulate_panel;
mod userprog_panel;
mod widgets;

#[cfg(not(target_arch = "wasm32"))]
pub mod native;
#[cfg(target_arch = "wasm32")]
pub mod web;

use eframe::egui;
use web_time::{Duration, Instant};

use crate::crease::{InterpOptions, Method, StopReason};
use crate::scene::{PRESETS, Scene};
use compute::Computation;
use panel::{Panel, PanelContext};
use platform::{FileKind, Incoming, Platform};
use scene_controls::{Asked, SceneEditor, preset_of, preset_title};

/// Storage key of the last scene (browser local storage / native app data).
const STORAGE_SCENE: &str = "interpolab.scene";

/// Severity of a message in the banner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Level {
    Info,
    Error,
}

/// The banner under the top bar.
#[derive(Clone, Debug)]
struct Notice {
    level: Level,
    text: String,
    shown: Instant,
}

/// Playback of the cutter along the computed path.
#[derive(Clone, Copy, Debug)]
pub struct Playback {
    /// Whether time runs.
    pub playing: bool,
    /// Position as a (fractional) period index.
    pub k: f64,
    /// Multiple of real time (1 = the machine's speed).
    pub speed: f64,
}

impl Default for Playback {
    fn default() -> Self {
        Self { playing: false, k: 0.0, speed: 1.0 }
    }
}

/// The interpolab app.
pub struct InterpolabApp {
    scene: Scene,
    /// The scene as the shared controls edit it, the method, and the frame's requests.
    editor: SceneEditor,
    compute: Computation,
    playback: Playback,
    notice: Option<Notice>,
    platform: Platform,
    render_state: Option<eframe::egui_wgpu::RenderState>,
    /// Help's line on what draws the frames ([`graphics_line`]; the adapter never changes).
    graphics: Option<String>,
    /// The tab shown: an index into `panels`.
    tab: usize,
    /// The tabs (crease, 5-axis, chords, NURBS & G-code, simulation, fillet, the user's
    /// program), in order.
    panels: Vec<Box<dyn Panel>>,
    frames: u64,
    first_frame_ms: Option<f64>,
    last_status: String,
    last_fragment: String,
    show_help: bool,
    /// Rectangles of key widgets this frame (points), published in the status element.
    widget_rects: Vec<(&'static str, egui::Rect)>,
    /// The last G-code file opened (name, text): the NURBS tab reads it, the simulation
    /// tab machines it.
    program: Option<(String, String)>,
    program_generation: u64,
}

fn default_scene() -> Scene {
    PRESETS.first().and_then(|p| Scene::from_json(p.json).ok()).unwrap_or_else(|| {
        // The presets are checked by the tests; this cannot happen in a released build.
        unreachable_scene()
    })
}

#[cold]
fn unreachable_scene() -> Scene {
    log::error!("built-in presets failed to parse");
    Scene::from_json(PRESETS[0].json).unwrap_or_else(|e| panic!("preset: {e}"))
}

impl InterpolabApp {
    /// Creates the app: scene from the link, else the last session's, else the first preset.
    #[must_use]
    pub fn new(cc: &eframe::CreationContext<'_>) -> Self {
        let ctx = &cc.egui_ctx;
        style(ctx);
        let platform = Platform::new(ctx);
        let render_state = cc.wgpu_render_state.clone();
        if let Some(rs) = &render_state {
            crate::render::Renderer3d::install(rs);
            crate::render::flat_fill::FlatFills::install(rs);
            crate::render::egui_pass::EguiPass::install(rs);
        }
        let mut notice = None;
        let fragment = platform.fragment();
        let from_link = match Scene::from_link_fragment(&fragment) {
            Ok(s) => s,
            Err(e) => {
                notice = Some(Notice {
                    level: Level::Error,
                    text: format!("The link's scene was not opened — {e}"),
                    shown: Instant::now(),
                });
                None
            }
        };
        let stored = cc.storage.and_then(|s| s.get_string(STORAGE_SCENE)).and_then(|text| Scene::from_json(&text).ok());
        let scene = from_link.clone().or(stored).unwrap_or_else(default_scene);
        let mut app = Self {
            editor: SceneEditor::new(&scene),
            scene,
            compute: Computation::default(),
            playback: Playback::default(),
            notice,
            platform,
            graphics: graphics_line(render_state.as_ref()),
            render_state,
            tab: 0,
            panels: panels(),
            frames: 0,
            first_frame_ms: None,
            last_status: String::new(),
            last_fragment: fragment,
            show_help: false,
            widget_rects: Vec::new(),
            program: None,
            program_generation: 0,
        };
        if from_link.is_some() {
            app.info("Opened the scene from the link.");
        }
        app.restart();
        let query = app.platform.query();
        app.apply_query(&query);
        app
    }

    /// Applies the automation options of a page address's query (`?view=TITLE&set=KEY:VALUE…`,
    /// see [`query_options`]): shows the view and sets its options in order; a refused one
    /// is shown in the banner and the rest are skipped.
    pub fn apply_query(&mut self, query: &str) {
        let Some((title, options)) = query_options(query) else { return };
        if let Err(e) = self.set_panel_option(&title, "", "") {
            self.error(format!("The address's view was not shown — {e}"));
            return;
        }
        for (key, value) in options {
            if let Err(e) = self.set_panel_option(&title, &key, &value) {
                self.error(format!("The address's option {key} was not set — {e}"));
                return;
            }
        }
    }

    fn info(&mut self, text: impl Into<String>) {
        self.notice = Some(Notice { level: Level::Info, text: text.into(), shown: Instant::now() });
    }

    fn error(&mut self, text: impl Into<String>) {
        self.notice = Some(Notice { level: Level::Error, text: text.into(), shown: Instant::now() });
    }

    /// Recomputes the current scene from the start.
    fn restart(&mut self) {
        if let Err(e) = self.compute.restart(&self.scene, self.editor.opts) {
            // The scene was validated before it became current; report rather than panic.
            self.error(format!("The scene cannot be computed — {e}"));
        }
        self.playback.k = 0.0;
    }

    /// Makes `scene` current (a loaded file, a link, a preset) and frames it.
    fn load_scene(&mut self, scene: Scene, source: &str) {
        self.editor.preset = preset_of(&scene);
        self.scene = scene.clone();
        self.editor.draft = scene;
        self.editor.error = None;
        self.restart();
        for p in &mut self.panels {
            p.scene_opened();
        }
        self.playback = Playback::default();
        self.info(format!("Opened {source}."));
    }

    fn handle_files(&mut self, files: Vec<Incoming>) {
        for f in files.into_iter().filter(|f| f.kind == FileKind::Scene) {
            match f.text {
                Err(e) => self.error(format!("{}: {e} — the current scene is kept.", f.name)),
                Ok(text) => match Scene::from_json(&text) {
                    Ok(scene) => self.load_scene(scene, &f.name),
                    Err(e) => self.error(format!("{} is not a usable scene — {e}. The current scene is kept.", f.name)),
                },
            }
        }
    }

    /// Opens a scene pasted into the address bar of an open page.
    fn handle_fragment(&mut self) {
        let fragment = self.platform.fragment();
        if fragment == self.last_fragment {
            return;
        }
        self.last_fragment = fragment.clone();
        match Scene::from_link_fragment(&fragment) {
            Ok(Some(scene)) if scene != self.scene => self.load_scene(scene, "the scene from the link"),
            Ok(_) => {}
            Err(e) => self.error(format!("The link's scene was not opened — {e}. The current scene is kept.")),
        }
    }

    /// Applies the draft if it is valid; otherwise keeps computing the last valid scene.
    fn apply_draft(&mut self) {
        match self.editor.draft.validate() {
            Ok(()) => {
                self.editor.error = None;
                if self.editor.draft != self.scene {
                    self.scene = self.editor.draft.clone();
                    self.editor.preset = None;
                    self.restart();
                }
            }
            Err(e) => self.editor.error = Some(e),
        }
    }

    /// Opens a scene given as text, as if a file of that name had been chosen (an invalid
    /// scene is reported and the current one kept).
    pub fn open_text(&mut self, name: &str, text: &str) {
        self.handle_files(vec![Incoming { name: name.to_owned(), text: Ok(text.to_owned()), kind: FileKind::Scene }]);
    }

    /// Edits the draft scene as the controls do, then applies it if valid.
    pub fn edit_draft(&mut self, edit: impl FnOnce(&mut Scene)) {
        edit(&mut self.editor.draft);
        self.apply_draft();
    }

    /// Shows the tab titled `title` and sets one of its options as its widgets would, e.g.
    /// `("5-axis steps", "source", "scene")`; with an empty `key` only shows it. For
    /// headless tests and automation.
    ///
    /// # Errors
    /// No view with that title, or the view's own message for an unknown option or value.
    pub fn set_panel_option(&mut self, title: &str, key: &str, value: &str) -> Result<(), String> {
        let i = self.panels.iter().position(|p| p.title() == title).ok_or_else(|| format!("no view titled {title}"))?;
        self.tab = i;
        if key.is_empty() { Ok(()) } else { self.panels[i].set_option(key, value) }
    }

    /// Shows the view a [`panel::Handoff`] names and sets its options; a refused option is
    /// shown in the banner.
    fn route_handoff(&mut self, h: panel::Handoff) {
        let Some(i) = self.panels.iter().position(|p| p.title() == h.to) else {
            self.error(format!("No view titled {} to hand the program to.", h.to));
            return;
        };
        self.tab = i;
        if let Some(p) = &h.payload
            && let Err(e) = self.panels[i].receive(p)
        {
            self.error(format!("{}: {e}", h.to));
            return;
        }
        for (key, value) in &h.options {
            if let Err(e) = self.panels[i].set_option(key, value) {
                self.error(format!("{}: {e}", h.to));
                return;
            }
        }
    }

    /// The current (valid) scene.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The state published for tests and assistive tools, as JSON text.
    #[must_use]
    pub fn status(&self) -> String {
        self.status_json()
    }

    fn share_link(&mut self, ctx: &egui::Context) {
        let fragment = self.scene.to_link_fragment();
        let url = self.platform.share_url(&fragment);
        self.platform.set_fragment(&fragment);
        self.last_fragment = format!("#{fragment}");
        ctx.copy_text(url.clone());
        self.info(format!("Link copied to the clipboard ({} characters). It opens this exact scene.", url.len()));
    }

    fn file_name(&self) -> String {
        format!("{}.json", crate::scene::file_stem(&self.scene.name).unwrap_or_else(|| "scene".to_owned()))
    }

    fn top_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.heading("interpolab");
            ui.label(egui::RichText::new("CNC tool-path interpolation lab").weak());
            ui.separator();
            let r = ui.selectable_label(self.show_help, "Help");
            if r.clicked() {
                self.show_help = !self.show_help;
            }
            self.widget_rects.push(("help", r.rect));
        });
    }

    /// Acts on what the scene's controls asked this frame: a preset, a file, saving, a share
    /// link, an edited draft, a changed method.
    fn act_on(&mut self, asked: Asked, ctx: &egui::Context) {
        if let Some(i) = asked.preset {
            match Scene::from_json(PRESETS[i].json) {
                Ok(s) => self.load_scene(s, &format!("the preset \"{}\"", preset_title(i))),
                Err(e) => self.error(format!("preset {}: {e}", PRESETS[i].id)),
            }
        }
        if asked.open {
            self.platform.pick_file(FileKind::Scene);
        }
        if asked.save {
            let name = self.file_name();
            match self.platform.save_text(&name, &self.scene.to_json()) {
                Ok(msg) => self.info(msg),
                Err(e) => self.error(format!("Saving failed: {e}")),
            }
        }
        if asked.share {
            self.share_link(ctx);
        }
        if asked.scene_changed {
            self.apply_draft();
        }
        if asked.options_changed {
            self.restart();
        }
    }

    fn banner(&mut self, ui: &mut egui::Ui) {
        let Some(n) = &self.notice else { return };
        if n.level == Level::Info && n.shown.elapsed() > Duration::from_secs(6) {
            self.notice = None;
            return;
        }
        let (fill, stroke) = match n.level {
            Level::Info => (egui::Color32::from_rgb(28, 60, 44), egui::Color32::from_rgb(90, 190, 120)),
            Level::Error => (egui::Color32::from_rgb(80, 24, 24), egui::Color32::from_rgb(235, 90, 80)),
        };
        let mut close = false;
        egui::Frame::new().fill(fill).stroke(egui::Stroke::new(1.0, stroke)).inner_margin(6.0).corner_radius(4.0).show(
            ui,
            |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.label(egui::RichText::new(if n.level == Level::Error { "⚠" } else { "ℹ" }).color(stroke));
                    ui.label(egui::RichText::new(&n.text).color(egui::Color32::WHITE));
                    if ui.small_button("✕").on_hover_text("Dismiss").clicked() {
                        close = true;
                    }
                });
            },
        );
        if close {
            self.notice = None;
        }
    }

    /// The tab shown and the context it draws from (disjoint borrows of the app's fields).
    fn context(&mut self, incoming: Vec<Incoming>) -> (&mut dyn Panel, PanelContext<'_>) {
        let tab = self.tab.min(self.panels.len().saturating_sub(1));
        let cx = PanelContext {
            scene: &self.scene,
            compute: &self.compute,
            render_state: self.render_state.as_ref(),
            playback: &mut self.playback,
            editor: &mut self.editor,
            rects: &mut self.widget_rects,
            platform: &mut self.platform,
            incoming,
            program: &self.program,
            program_generation: self.program_generation,
            messages: Vec::new(),
            handoff: None,
        };
        (self.panels[tab].as_mut(), cx)
    }

    fn status_json(&self) -> String {
        let stop = match &self.compute.outcome {
            None => serde_json::Value::Null,
            Some(Ok(r)) => r.tag().into(),
            Some(Err(_)) => "error".into(),
        };
        let error = match (&self.compute.outcome, &self.editor.error, &self.notice) {
            (Some(Err(e)), _, _) => e.to_string(),
            (_, Some(e), _) => e.to_string(),
            (_, _, Some(n)) if n.level == Level::Error => n.text.clone(),
            _ => String::new(),
        };
        let (worst, _) = self.compute.worst();
        let ui: serde_json::Map<String, serde_json::Value> = self
            .widget_rects
            .iter()
            .map(|(k, r)| ((*k).to_owned(), serde_json::json!([r.min.x, r.min.y, r.width(), r.height()])))
            .collect();
        serde_json::json!({
            "scene": self.scene.name,
            "periods": self.compute.periods.len().saturating_sub(1),
            "running": self.compute.running(),
            "stop": stop,
            "end_note": self.compute.end_not_reached().map(|n| n.to_string()),
            "error": error,
            "feed_mm_per_min": self.scene.motion.feed,
            "period_ms": self.scene.motion.period,
            "worst_error_mm": [worst[0], worst[1]],
            "frames": self.frames,
            "first_frame_ms": self.first_frame_ms,
            "gpu_backend": self.render_state.as_ref().map(|rs| format!("{:?}", rs.adapter.get_info().backend)),
            "jobs": {
                "background": jobs::finished_counts().0,
                "on_page": jobs::finished_counts().1,
            },
            "graphics": self.graphics,
            "gpu_adapter": self.render_state.as_ref().map(|rs| {
                let i = rs.adapter.get_info();
                format!("{} ({:?}{})", i.name, i.device_type, if crate::render::gpu::is_software(&i) { ", software: no MSAA" } else { "" })
            }),
            "playback_k": self.playback.k.floor(),
            "ui": ui,
            "panel": self.panels.get(self.tab).map_or(serde_json::Value::Null, |p| {
                serde_json::json!({ "title": p.title(), "paper": p.paper(), "status": p.status() })
            }),
        })
        .to_string()
    }
}

/// The app's look: the dark theme, its fonts, and panels without a background of their own —
/// the frame is cleared to their colour instead ([`PANEL_FILL`], `clear_color`), which looks
/// the same. On a CPU rasteriser (SwiftShader) every pixel egui's shader fills costs time, and
/// the panels' fills covered the whole window once more per frame.
fn style(ctx: &egui::Context) {
    ctx.set_theme(egui::Theme::Dark);
    ctx.style_mut_of(egui::Theme::Dark, |s| s.visuals.panel_fill = egui::Color32::TRANSPARENT);
    fonts::install(ctx);
    ablate::restyle(ctx);
}

/// The tabs, in order.
fn panels() -> Vec<Box<dyn Panel>> {
    vec![
        Box::new(crease_panel::CreasePanel::default()),
        Box::new(fiveaxis_panel::FiveAxisPanel::default()),
        Box::new(chords_panel::ChordsPanel::default()),
        Box::new(nurbs_panel::NurbsPanel::default()),
        Box::new(simulate_panel::SimulatePanel::default()),
        Box::new(fillet_panel::FilletPanel::default()),
        Box::new(userprog_panel::UserProgramPanel::default()),
    ]
}

/// The colour behind every panel: egui's dark panel fill, drawn as the frame's clear colour
/// (the panels themselves are transparent, see [`style`]).
const PANEL_FILL: egui::Color32 = egui::Color32::from_gray(27);

/// The side panel's widest size (points). Without a cap an egui side panel lays its
/// contents out in the whole window's width, so the tabs' wrapped rows of controls never
/// wrap and the panel grows over the view; capped, they wrap. The user can drag it narrower.
const SIDE_PANEL_MAX_WIDTH: f32 = 420.0;

impl eframe::App for InterpolabApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.frames += 1;
        self.widget_rects.clear();
        if self.frames == 2 && self.first_frame_ms.is_none() {
            // The first frame has been presented by the time the second one starts.
            self.first_frame_ms = Some(Platform::now_ms());
            // A worker for the first job, now that the page is up (none if a job has one).
            jobs::start_spare_worker();
        }

        self.platform.accept_dropped(&ctx);
        let files = self.platform.take_incoming();
        let (scene_files, mut other_files): (Vec<_>, Vec<_>) =
            files.into_iter().partition(|f| f.kind == FileKind::Scene);
        if !scene_files.is_empty() {
            self.handle_files(scene_files);
        }
        // The last program opened is kept for the simulation tab.
        if let Some(f) = other_files.iter().rev().find(|f| f.kind == FileKind::GCode)
            && let Ok(text) = &f.text
        {
            self.program = Some((f.name.clone(), text.clone()));
            self.program_generation += 1;
        }
        // Files for a panel switch to it; with no panel for them, say so.
        // The tab shown keeps a file it takes (a G-code file opened in the user-program tab
        // stays there); otherwise the first tab that takes it is shown.
        if let Some(f) = other_files.first() {
            let takes = |p: &dyn Panel| p.accepts() == Some(f.kind) || p.accepts_also().contains(&f.kind);
            if !self.panels.get(self.tab).is_some_and(|p| takes(p.as_ref())) {
                match self.panels.iter().position(|p| takes(p.as_ref())) {
                    Some(i) => self.tab = i,
                    None => {
                        self.error(format!("{}: this app version has no view for this kind of file.", f.name));
                        other_files.clear();
                    }
                }
            }
        }
        self.handle_fragment();
        self.platform.ui(&ctx);

        if self.compute.running() {
            self.compute.advance(budget::FRAME_BUDGET);
            ctx.request_repaint();
        }
        let n_periods = self.compute.periods.len();
        if self.playback.playing && n_periods > 1 {
            let dt = f64::from(ctx.input(|i| i.stable_dt)).min(0.1);
            self.playback.k += dt * self.playback.speed * 1000.0 / self.scene.motion.period;
            let last = (n_periods - 1) as f64;
            if self.playback.k >= last {
                self.playback.k = last;
                if !self.compute.running() {
                    self.playback.playing = false;
                }
            }
            ctx.request_repaint();
        }
        self.playback.k = self.playback.k.clamp(0.0, n_periods.saturating_sub(1) as f64);

        if !ablate::hidden(ablate::Part::Top) {
            egui::Panel::top("top_bar").show(ui, |ui| {
                ui.add_space(2.0);
                self.top_bar(ui);
                ui.add_space(2.0);
            });
        }

        // The tab's controls in the side panel, then its view in the central area; both see
        // the same context, and the scene's edits are applied after each.
        let kind = self.panels.get(self.tab).and_then(|p| p.accepts());
        let also = self.panels.get(self.tab).map_or(&[][..], |p| p.accepts_also());
        let mut incoming: Vec<Incoming> =
            other_files.drain(..).filter(|f| Some(f.kind) == kind || also.contains(&f.kind)).collect();
        let mut messages = Vec::new();
        let mut handoff = None;
        if !ablate::hidden(ablate::Part::Side) {
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(320.0)
                .min_size(240.0)
                .max_size(SIDE_PANEL_MAX_WIDTH)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        let (panel, mut cx) = self.context(Vec::new());
                        panel.controls(ui, &mut cx);
                        messages.append(&mut cx.messages);
                        handoff = handoff.take().or(cx.handoff);
                    });
                });
        }
        let asked = std::mem::take(&mut self.editor.asked);
        self.act_on(asked, &ctx);

        egui::CentralPanel::default().show(ui, |ui| {
            self.banner(ui);
            if self.show_help {
                let shown = self.panels.get(self.tab).map(|p| (p.title(), p.paper()));
                help(ui, shown, self.graphics.as_deref());
            }
            if !ablate::hidden(ablate::Part::Tabs) {
                ui.horizontal(|ui| {
                    for (i, p) in self.panels.iter().enumerate() {
                        let r = ui.selectable_value(&mut self.tab, i, p.title());
                        self.widget_rects.push((p.title(), r.rect));
                    }
                });
                ui.separator();
            }
            let (panel, mut cx) = self.context(std::mem::take(&mut incoming));
            panel.ui(ui, &mut cx);
            messages.append(&mut cx.messages);
            handoff = handoff.take().or(cx.handoff);
        });
        let asked = std::mem::take(&mut self.editor.asked);
        self.act_on(asked, &ctx);
        for m in messages {
            match m {
                Ok(t) => self.info(t),
                Err(t) => self.error(t),
            }
        }
        if let Some(h) = handoff {
            self.route_handoff(h);
        }

        let status = self.status_json();
        if status != self.last_status {
            self.platform.set_status(&status);
            self.last_status = status;
        }
        if self.notice.as_ref().is_some_and(|n| n.level == Level::Info) {
            ctx.request_repaint_after(Duration::from_millis(500));
        }
        ablate::strip_shapes(&ctx);
        ablate::log_area(&ctx, self.frames);
        crate::render::flat_fill::flatten(&ctx);
        crate::render::egui_pass::replace_frame(&ctx, self.render_state.as_ref());
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        storage.set_string(STORAGE_SCENE, self.scene.to_json_compact());
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        PANEL_FILL.to_normalized_gamma_f32()
    }

    fn auto_save_interval(&self) -> std::time::Duration {
        std::time::Duration::from_secs(5)
    }
}

/// Help's line on the graphics: the API the app draws with, and whether a software
/// rasteriser draws it (a browser without a usable GPU), which makes every frame slower.
fn graphics_line(rs: Option<&eframe::egui_wgpu::RenderState>) -> Option<String> {
    use eframe::wgpu::Backend;
    let info = rs?.adapter.get_info();
    let api = match info.backend {
        Backend::BrowserWebGpu => "WebGPU",
        Backend::Gl if cfg!(target_arch = "wasm32") => "WebGL2",
        Backend::Gl => "OpenGL",
        Backend::Vulkan => "Vulkan",
        Backend::Metal => "Metal",
        Backend::Dx12 => "Direct3D 12",
        Backend::Noop => return None,
    };
    let by = if crate::render::gpu::is_software(&info) {
        "by a software rasteriser on the CPU (no GPU in use here), so frames are slower than on a GPU"
    } else {
        "on the GPU"
    };
    let name = if info.name.is_empty() { String::new() } else { format!(" ({})", info.name) };
    Some(format!("• Drawn with {api} {by}{name}."))
}

/// The help box: how to use the app, what draws its frames (`graphics`, from
/// [`graphics_line`]), then the shown tab's paper (`shown`: its title and [`Panel::paper`]).
fn help(ui: &mut egui::Ui, shown: Option<(&str, Option<&str>)>, graphics: Option<&str>) {
    egui::Frame::group(ui.style()).show(ui, |ui| {
        ui.label(egui::RichText::new("How to use interpolab").strong());
        ui.label("• Pick an example at the top, or open / drop a scene file. Every change recomputes the path at once.");
        ui.label("• 3D view: drag to turn, right-drag or shift-drag to pan, wheel or pinch to zoom, double-click to fit.");
        ui.label("• The ball cutter (R) touches both surfaces; its centre runs on the crease of the two offset surfaces (translucent).");
        ui.label("• Each period the centre advances by f = F·Ts. The plots show the measured errors e1, e2 against the allowed ±b·T and the paper's steady-state bound (16).");
        ui.label("• Playback moves the cutter at the machine's speed (× the speed factor); the plots' cursor follows it.");
        ui.label("• 🔗 Share link copies a URL that opens this exact scene; the last scene is kept across reloads.");
        if let Some(g) = graphics {
            ui.label(egui::RichText::new(g).weak());
        }
        match shown {
            Some((title, Some(paper))) => {
                ui.separator();
                ui.label(egui::RichText::new(format!("The {title} tab follows")).strong());
                ui.label(paper);
                ui.label(egui::RichText::new("docs/papers.md cites each paper in full and says where the lab departs from it.").weak());
            }
            Some((title, None)) => {
                ui.separator();
                ui.label(format!("The {title} tab follows no paper: it reads, times and simulates your own program."));
            }
            None => {}
        }
    });
}

/// Formats a length in mm with three significant digits in a unit suited to its size
/// (mm, µm, nm, pm), e.g. `5.00 µm`, `0.206 pm`.
pub(crate) fn fmt_len(mm: f64) -> String {
    let a = mm.abs();
    if !mm.is_finite() {
        return "—".to_owned();
    }
    if a == 0.0 {
        return "0 µm".to_owned();
    }
    if a < 1e-12 {
        return format!("{mm:.1e} mm");
    }
    let (scale, unit) = if a >= 1.0 {
        (1.0, "mm")
    } else if a >= 1e-3 {
        (1e3, "µm")
    } else if a >= 1e-6 {
        (1e6, "nm")
    } else {
        (1e9, "pm")
    };
    let v = mm * scale;
    let digits = if v.abs() >= 100.0 {
        1
    } else if v.abs() >= 10.0 {
        2
    } else {
        3
    };
    format!("{v:.digits$} {unit}")
}

/// One-line description of how a run ended.
pub(crate) fn describe_outcome(c: &Computation) -> (bool, String) {
    match &c.outcome {
        None if c.running() => (true, format!("computing… {} periods", c.periods.len().saturating_sub(1))),
        None => (false, "not started".to_owned()),
        Some(Ok(StopReason::Closed { .. })) => (true, "closed crease: one full turn".to_owned()),
        Some(Ok(r)) => (true, format!("stopped: {r}")),
        Some(Err(e)) => (false, e.to_string()),
    }
}

/// Whether the method in use is the seed-000 stepper.
pub(crate) fn is_seed000(o: &InterpOptions) -> bool {
    o.method == Method::Seed000
}

/// The automation options of a page address's query: `view=TITLE` names the view to show,
/// each `set=KEY:VALUE` one of its options (`Panel::set_option`), in order; values are
/// percent-encoded (`+` is a space). E.g. `?view=Cutting+simulation&set=benchmark:five-axis:10000`
/// makes the simulation tab build and run the native benchmark's 5-axis program in its
/// worker (e2e/sim-bench.mjs). `None` without a `view`.
#[must_use]
pub fn query_options(query: &str) -> Option<(String, Vec<(String, String)>)> {
    let q = query.strip_prefix('?').unwrap_or(query);
    let mut view = None;
    let mut options = Vec::new();
    for part in q.split('&') {
        let (k, v) = part.split_once('=').unwrap_or((part, ""));
        let v = percent_decode(v);
        match k {
            "view" => view = Some(v),
            "set" => {
                let (key, value) = v.split_once(':').unwrap_or((v.as_str(), ""));
                options.push((key.to_owned(), value.to_owned()));
            }
            _ => {}
        }
    }
    view.map(|v| (v, options))
}

/// `%XX` escapes and `+` (space) of a query value; a malformed escape is kept as written.
fn percent_decode(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| char::from(c).to_digit(16);
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len() => match (hex(b[i + 1]), hex(b[i + 2])) {
                (Some(h), Some(l)) => {
                    out.push(u8::try_from(h * 16 + l).unwrap_or(b'?'));
                    i += 3;
                    continue;
                }
                _ => out.push(b'%'),
            },
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod query_tests {
    use super::query_options;

    #[test]
    fn a_query_names_a_view_and_its_options_in_order() {
        let (view, opts) = query_options("?view=Cutting+simulation&set=benchmark:five-axis:10000&set=pitch%3A0.4&x=1")
            .expect("a view");
        assert_eq!(view, "Cutting simulation");
        assert_eq!(
            opts,
            [("benchmark".to_owned(), "five-axis:10000".to_owned()), ("pitch".to_owned(), "0.4".to_owned())]
        );
        assert_eq!(query_options("?set=pitch:0.4"), None, "no view, nothing to do");
        assert_eq!(query_options(""), None);
        let (_, opts) = query_options("view=A&set=k:100%&set=k:%zz%4").expect("a view");
        assert_eq!(opts[0].1, "100%", "a malformed escape is kept");
        assert_eq!(opts[1].1, "%zz%4");
    }
}
