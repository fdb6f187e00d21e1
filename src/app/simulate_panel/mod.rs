//! The "Cutting simulation" view: a program of the product (the scene's crease as G01,
//! G02/G03 or G06.2, the seed-002 five-axis steps of the scene, or the last G-code file
//! opened in the app) machined into a dexel stock by `simulate::Simulation` in a background
//! job (`work.rs`: a thread natively, a Web Worker in the browser; keyframes of the stock
//! while it runs and for the move slider); the machined stock drawn as a height field coloured by
//! its deviation from the design, with the scallop and gouge statistics and the removed
//! volume. Format and error bounds of the core: docs/simulation.md.
//!
//! Loaded files: the NURBS & G-code tab owns `.nc` files (opening, dropping, the reader's
//! messages by line); the app keeps the last one opened and hands it to this view as the
//! source "Loaded G-code file", so a file is opened once and seen in both tabs.

mod compare;
mod view;
pub mod work;

use std::rc::Rc;

use eframe::egui;

use super::panel::{FinishHandoff, Panel, PanelContext, Payload, SIMULATION_TITLE};
use crate::simulate::bench::{self, BenchKind};
use compare::{MapImage, MapTextures, draw_maps};
use view::SimView;
pub use work::PITCH_RANGE_MM;
use work::{AUTO_GRID_SIDE, CutterChoice, DesignChoice, Inputs, Job, MAX_APP_RAYS, SourceKind};

/// Moves of the benchmark program chosen from the menu (the 10 000-move program).
const BENCH_DEFAULT_MOVES: usize = 10_000;

/// The user's choices.
#[derive(Clone, Debug, PartialEq)]
struct Settings {
    source: SourceKind,
    cutter: CutterChoice,
    pitch_mm: Option<f64>,
    stock_mm: Option<[f64; 6]>,
    margin_mm: f64,
    design: DesignChoice,
    band_um: f64,
    /// The benchmark program (source `benchmark`).
    bench: (BenchKind, usize),
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            source: SourceKind::CreaseG01,
            cutter: CutterChoice::SceneBall,
            pitch_mm: None,
            stock_mm: None,
            margin_mm: 2.0,
            design: DesignChoice::Auto,
            band_um: 50.0,
            bench: (BenchKind::FiveAxis, BENCH_DEFAULT_MOVES),
        }
    }
}

/// The panel.
#[derive(Default)]
pub struct SimulatePanel {
    settings: Settings,
    job: Option<Job>,
    view: SimView,
    /// A program given as text (`set_option("program_text", …)`), replacing the app's
    /// loaded file.
    own_program: Option<(String, String)>,
    own_generation: u64,
    /// Move the slider asks for (`None`: the whole program).
    target: Option<usize>,
    /// Restart requested by the user.
    restart: bool,
    /// The inputs refused by the stock or grid checks, with the message (not retried until
    /// they change).
    rects: Vec<(&'static str, egui::Rect)>,
    /// Program A of the side-by-side comparison: the numbers and map of a run pinned by
    /// the user, shown next to the current run's (B).
    pinned: Option<Numbers>,
    /// Bumped on every pin (the key of A's map texture).
    pin_serial: u64,
    /// The finishing program handed over by the fillet tab (source `finish`).
    finish: Option<Rc<FinishHandoff>>,
    finish_generation: u64,
    /// Bumped for every new job (with its map generation, the key of B's map).
    job_serial: u64,
    /// The current run's map for the comparison, with the key (job, map generation) it was
    /// built for.
    current_map: Option<((u64, u64), Rc<MapImage>)>,
    map_textures: MapTextures,
}

/// The numbers of a finished run, for the A/B comparison of two programs of the same part.
#[derive(Clone, Debug, PartialEq)]
struct Numbers {
    program: String,
    moves: usize,
    removed_mm3: f64,
    design: &'static str,
    /// max, mean, p95 (µm) and rays.
    scallop_um: Option<([f64; 3], usize)>,
    /// Worst gouge (µm) and gouge rays.
    gouge_um: Option<(f64, usize)>,
    /// Where the worst gouge is: (x, y) (mm).
    gouge_at_mm: Option<[f64; 2]>,
    /// Simulation time (ms) of the moves.
    sim_ms: f64,
    /// Total run time (ms): program, simulation and measure.
    total_ms: f64,
    /// The deviation map (kept when pinned).
    map: Option<Rc<MapImage>>,
}

impl Numbers {
    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "program": self.program,
            "moves": self.moves,
            "removed_volume_mm3": (self.removed_mm3 * 1e6).round() / 1e6,
            "design": self.design,
            "scallop_um": self.scallop_um.map(|(v, n)| serde_json::json!({"max": v[0], "mean": v[1], "p95": v[2], "rays": n})),
            "gouge": self.gouge_um.map(|(w, n)| serde_json::json!({
                "worst_um": w, "rays": n,
                "x_mm": self.gouge_at_mm.map(|p| nm(p[0])), "y_mm": self.gouge_at_mm.map(|p| nm(p[1])),
            })),
            "sim_ms": self.sim_ms,
            "total_ms": self.total_ms,
            "map": self.map.as_ref().map(|m| serde_json::json!({"nx": m.nx, "ny": m.ny, "measured_rays": m.measured_rays()})),
        })
    }
}

fn um(mm: f64) -> f64 {
    (mm * 1e6).round() / 1e3
}

/// A length rounded to 1e-6 mm, as `interpolab simulate` prints lengths.
fn nm(mm: f64) -> f64 {
    (mm * 1e6).round() / 1e6
}

impl SimulatePanel {
    fn inputs(&self, cx: &PanelContext<'_>) -> Inputs {
        let s = &self.settings;
        let loaded_generation = if self.own_program.is_some() { self.own_generation } else { cx.program_generation };
        Inputs {
            source: s.source,
            cutter: s.cutter,
            pitch_mm: s.pitch_mm,
            stock_mm: s.stock_mm,
            margin_mm: s.margin_mm,
            design: s.design,
            scene_generation: cx.compute.generation,
            loaded_generation,
            finish_generation: self.finish_generation,
            bench: s.bench,
        }
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &PanelContext<'_>) {
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label("Program:");
            let mut bench_item = None;
            let r = egui::ComboBox::from_id_salt("sim_source").selected_text(s.source.label()).show_ui(ui, |ui| {
                for k in SourceKind::ALL {
                    let item = ui.selectable_value(&mut s.source, k, k.label());
                    if k == SourceKind::Benchmark {
                        bench_item = Some(item.rect);
                    }
                }
            });
            self.rects.push(("sim_source", r.response.rect));
            // The benchmark's item while the menu is open (automation: e2e/sim-bench.mjs --press).
            if let Some(item) = bench_item {
                self.rects.push(("sim_source_benchmark", item));
            }
            if s.source == SourceKind::Finish {
                ui.label(
                    self.finish
                        .as_ref()
                        .map_or("(none: press Simulate this program → in the Fillet end mill tab)".to_owned(), |f| {
                            format!("{} ({} passes)", f.program.label, f.program.passes.len())
                        }),
                );
            }
            if s.source == SourceKind::Loaded {
                let name = self.own_program.as_ref().or(cx.program.as_ref()).map(|(n, _)| n.as_str());
                ui.label(name.map_or("(none: open one in the NURBS & G-code tab)".to_owned(), |n| n.to_owned()));
            }
            ui.separator();
            ui.label("Cutter:");
            let kind = match s.cutter {
                CutterChoice::SceneBall => 0,
                CutterChoice::Ball(_) => 1,
                CutterChoice::Flat(_) => 2,
                CutterChoice::Fillet(..) => 3,
            };
            let own = if s.source == SourceKind::Finish { "program's cutter" } else { "scene's ball" };
            let names = [own, "ball", "flat", "fillet"];
            let mut chosen = kind;
            egui::ComboBox::from_id_salt("sim_cutter").selected_text(names[kind]).show_ui(ui, |ui| {
                for (i, n) in names.iter().enumerate() {
                    ui.selectable_value(&mut chosen, i, *n);
                }
            });
            let own_r = match (&self.finish, s.source) {
                (Some(fp), SourceKind::Finish) => fp.program.cutter.radius_mm,
                _ => cx.scene.tool.radius,
            };
            let r0 = match s.cutter {
                CutterChoice::SceneBall => own_r,
                CutterChoice::Ball(r) | CutterChoice::Flat(r) | CutterChoice::Fillet(r, _) => r,
            };
            if chosen != kind {
                s.cutter = match chosen {
                    1 => CutterChoice::Ball(r0),
                    2 => CutterChoice::Flat(r0),
                    3 => CutterChoice::Fillet(r0, r0 * 0.2),
                    _ => CutterChoice::SceneBall,
                };
            }
            match &mut s.cutter {
                CutterChoice::SceneBall => match (&self.finish, s.source) {
                    (Some(fp), SourceKind::Finish) => {
                        ui.label(fp.program.cutter.describe());
                    }
                    _ => {
                        ui.label(format!("R = {} mm", cx.scene.tool.radius));
                    }
                },
                CutterChoice::Ball(r) | CutterChoice::Flat(r) => {
                    ui.add(egui::DragValue::new(r).range(0.05..=50.0).speed(0.05).prefix("R ").suffix(" mm"));
                }
                CutterChoice::Fillet(r, c) => {
                    ui.add(egui::DragValue::new(r).range(0.05..=50.0).speed(0.05).prefix("R ").suffix(" mm"));
                    ui.add(egui::DragValue::new(c).range(0.01..=50.0).speed(0.02).prefix("r ").suffix(" mm"));
                }
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("Pitch:");
            let mut auto = s.pitch_mm.is_none();
            if ui
                .checkbox(&mut auto, "auto")
                .on_hover_text(format!("Grid of at most {AUTO_GRID_SIDE} rays a side"))
                .changed()
            {
                s.pitch_mm = if auto {
                    None
                } else {
                    self.job.as_ref().and_then(|j| j.prepared.as_ref()).map(|p| p.pitch_mm).or(Some(0.1))
                };
            }
            if let Some(p) = &mut s.pitch_mm {
                ui.add(egui::DragValue::new(p).range(PITCH_RANGE_MM.0..=PITCH_RANGE_MM.1).speed(0.002).suffix(" mm"));
            }
            ui.separator();
            ui.label("Stock (mm):");
            let mut auto = s.stock_mm.is_none();
            if ui
                .checkbox(&mut auto, "auto")
                .on_hover_text("The program's cutting moves' box plus the cutter radius and the margin")
                .changed()
            {
                s.stock_mm =
                    if auto { None } else { self.job.as_ref().and_then(|j| j.prepared.as_ref()).map(|p| p.stock_mm) };
            }
            match &mut s.stock_mm {
                None => {
                    ui.add(
                        egui::DragValue::new(&mut s.margin_mm)
                            .range(0.0..=100.0)
                            .speed(0.1)
                            .prefix("margin ")
                            .suffix(" mm"),
                    );
                }
                Some(b) => {
                    for (v, n) in b.iter_mut().zip(["x0 ", "y0 ", "z0 ", "x1 ", "y1 ", "z1 "]) {
                        ui.add(egui::DragValue::new(v).speed(0.1).prefix(n).max_decimals(3));
                    }
                }
            }
            ui.separator();
            ui.label("Design:");
            let label = match s.design {
                DesignChoice::Auto => "auto".to_owned(),
                DesignChoice::None => "none".to_owned(),
                DesignChoice::Scene => "scene surfaces".to_owned(),
                DesignChoice::PlaneZ(z) => format!("plane z = {z} mm"),
            };
            egui::ComboBox::from_id_salt("sim_design").selected_text(label).show_ui(ui, |ui| {
                ui.selectable_value(&mut s.design, DesignChoice::Auto, "auto (scene surfaces; none for a file)");
                ui.selectable_value(&mut s.design, DesignChoice::None, "none");
                ui.selectable_value(&mut s.design, DesignChoice::Scene, "scene surfaces");
                if ui.selectable_label(matches!(s.design, DesignChoice::PlaneZ(_)), "plane z = …").clicked() {
                    s.design = DesignChoice::PlaneZ(0.0);
                }
            });
            if let DesignChoice::PlaneZ(z) = &mut s.design {
                ui.add(egui::DragValue::new(z).speed(0.01).prefix("z ").suffix(" mm"));
            }
            ui.add(egui::DragValue::new(&mut s.band_um).range(1.0..=1000.0).speed(0.5).prefix("band ± ").suffix(" µm"))
                .on_hover_text("Deviation shown at full colour");
        });
    }

    fn playback(&mut self, ui: &mut egui::Ui) {
        let Some(job) = &mut self.job else { return };
        let total = job.total_moves();
        ui.horizontal_wrapped(|ui| {
            if total > 0 {
                let mut k = self.target.unwrap_or(total).min(total);
                let r = ui.add(egui::Slider::new(&mut k, 0..=total).text(format!("of {total} moves")));
                self.rects.push(("sim_move_slider", r.rect));
                if r.changed() {
                    self.target = (k < total).then_some(k);
                }
            }
            if job.computing() {
                let (f, text) = job.progress();
                ui.add(egui::ProgressBar::new(f).desired_width(220.0).text(text));
                let r = ui.button("Cancel");
                self.rects.push(("sim_cancel", r.rect));
                if r.clicked() {
                    job.cancel();
                }
            }
            let r = ui.button("Restart").on_hover_text("Simulate again from the block");
            self.rects.push(("sim_restart", r.rect));
            if r.clicked() {
                self.restart = true;
            }
        });
    }

    /// The current run's numbers once it is measured to its last move.
    fn current_numbers(&self) -> Option<Numbers> {
        let job = self.job.as_ref()?;
        let p = job.prepared.as_ref()?;
        let counters = job.counters()?;
        let r = job.measured()?;
        let has_design = p.design_name != "none";
        let sc = &r.stats.scallop;
        let program = match (&self.own_program, &self.finish, self.settings.source) {
            (Some((name, _)), _, SourceKind::Loaded) => format!("{} ({name})", SourceKind::Loaded.label()),
            (_, Some(fp), SourceKind::Finish) => format!("finishing program: {}", fp.program.label),
            (_, _, k) => k.label().to_owned(),
        };
        let map = self
            .current_map
            .as_ref()
            .filter(|(k, _)| *k == (self.job_serial, job.map_generation))
            .map(|(_, m)| Rc::clone(m));
        Some(Numbers {
            program,
            moves: job.applied(),
            removed_mm3: counters.removed_mm3,
            design: p.design_name,
            scallop_um: has_design.then(|| ([um(sc.max_mm), um(sc.mean_mm), um(sc.p95_mm)], sc.count)),
            gouge_um: r.stats.worst_gouge.filter(|_| has_design).map(|(d, _)| (um(d), r.stats.gouge_rays)),
            gouge_at_mm: r.stats.worst_gouge.filter(|_| has_design).map(|(_, p)| [p.x, p.y]),
            sim_ms: job.sim_ms,
            total_ms: job.total_ms,
            map,
        })
    }

    /// Pin as A / clear A, and the two runs' numbers side by side.
    fn comparison(&mut self, ui: &mut egui::Ui) {
        let current = self.current_numbers();
        ui.horizontal(|ui| {
            let r = ui.add_enabled(current.is_some(), egui::Button::new("Pin as A")).on_hover_text(
                "Keep this run's numbers as program A, to compare with the next program (B) side by side",
            );
            self.rects.push(("sim_pin_a", r.rect));
            if r.clicked() {
                self.pinned.clone_from(&current);
                self.pin_serial += 1;
            }
            if self.pinned.is_some() && ui.button("Clear A").clicked() {
                self.pinned = None;
            }
        });
        let Some(a) = &self.pinned else { return };
        let fmt_sc = |n: Option<&Numbers>| {
            n.map_or("—".to_owned(), |n| {
                n.scallop_um
                    .map_or("no design".to_owned(), |(v, c)| format!("{} / {} / {} ({c} rays)", v[0], v[1], v[2]))
            })
        };
        let fmt_g = |n: Option<&Numbers>| {
            n.map_or("—".to_owned(), |n| match (n.design, n.gouge_um) {
                ("none", _) => "no design".to_owned(),
                (_, Some((w, c))) => format!("{w} ({c} rays)"),
                (_, None) => "none".to_owned(),
            })
        };
        let b = current.as_ref();
        egui::Grid::new("sim_ab").striped(true).show(ui, |ui| {
            ui.label("");
            ui.strong("A (pinned)");
            ui.strong("B (current)");
            ui.end_row();
            ui.label("program");
            ui.label(&a.program);
            ui.label(b.map_or("computing…", |n| n.program.as_str()));
            ui.end_row();
            ui.label("moves");
            ui.label(a.moves.to_string());
            ui.label(b.map_or("—".to_owned(), |n| n.moves.to_string()));
            ui.end_row();
            ui.label("removed volume (mm³)");
            ui.label(format!("{:.3}", a.removed_mm3));
            ui.label(b.map_or("—".to_owned(), |n| format!("{:.3}", n.removed_mm3)));
            ui.end_row();
            ui.label("scallop max / mean / p95 (µm)");
            ui.label(fmt_sc(Some(a)));
            ui.label(fmt_sc(b));
            ui.end_row();
            ui.label("worst gouge (µm)");
            ui.label(fmt_g(Some(a)));
            ui.label(fmt_g(b));
            ui.end_row();
            let at = |n: Option<&Numbers>| {
                n.and_then(|n| n.gouge_at_mm).map_or("—".to_owned(), |p| format!("({:.3}, {:.3})", p[0], p[1]))
            };
            ui.label("worst gouge at x, y (mm)");
            ui.label(at(Some(a)));
            ui.label(at(b));
            ui.end_row();
            let time = |n: Option<&Numbers>| {
                n.map_or("—".to_owned(), |n| format!("{:.0} (all steps {:.0})", n.sim_ms, n.total_ms))
            };
            ui.label("simulation time (ms)");
            ui.label(time(Some(a)));
            ui.label(time(b));
            ui.end_row();
        });
        // The two maps side by side, same colour scale and legend.
        if let Some(map_a) = a.map.clone() {
            let b_map = b.and_then(|n| n.map.clone());
            let key_b =
                self.job_serial.wrapping_mul(1 << 32).wrapping_add(self.job.as_ref().map_or(0, |j| j.map_generation));
            let drawn = draw_maps(
                ui,
                &mut self.map_textures,
                (&map_a, self.pin_serial),
                b_map.as_deref().map(|m| (m, key_b)),
                self.settings.band_um,
            );
            self.rects.extend(drawn);
        }
    }

    /// Builds the current run's map for the comparison once it is measured (kept until the
    /// run's map changes).
    fn refresh_map(&mut self) {
        let Some(job) = &self.job else { return };
        let key = (self.job_serial, job.map_generation);
        if self.current_map.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        let (Some(r), Some(p)) = (job.measured(), &job.prepared) else {
            return;
        };
        // The stock block's bottom and top (mm), as the stock itself gives them.
        self.current_map = Some((key, Rc::new(MapImage::of(r, (p.stock_mm[2], p.stock_mm[5])))));
    }

    fn numbers(&mut self, ui: &mut egui::Ui) {
        let Some(job) = &self.job else { return };
        if let Some(e) = &job.error {
            ui.colored_label(egui::Color32::LIGHT_RED, format!("⚠ {e}"));
            return;
        }
        let Some(p) = &job.prepared else { return };
        let mut go = None;
        ui.horizontal_wrapped(|ui| {
            if let (Some(g), Some(c)) = (job.grid(), job.counters()) {
                ui.label(format!(
                    "grid {} × {} at {} mm · moves {} / {} · removed {:.3} mm³ · last run {:.0} ms in the {} (all runs {:.0} ms; longest frame on it {:.1} ms)",
                    g.nx,
                    g.ny,
                    g.pitch_mm,
                    job.applied(),
                    job.total_moves(),
                    c.removed_mm3,
                    job.sim_ms,
                    if job.in_background { "background" } else { "page" },
                    job.total_ms,
                    job.slowest_call_ms
                ));
                if let Some(step) = job.pose_step_mm().filter(|s| *s < g.pitch_mm) {
                    ui.label(format!("· 5-axis poses every {step:.3} mm (cusps between them ≤ h/4)"))
                        .on_hover_text("A flat or fillet cutter's 5-axis moves are sampled pose by pose; between two poses its corner leaves a cusp of about s²/(8r)");
                }
            }
            if let Some(r) = job.measured() {
                if p.design_name != "none" {
                    let s = &r.stats.scallop;
                    if let Some(b) = &r.interior {
                        let r = ui.label(format!(
                            "· scallop, interior: max {} / mean {} / p95 {} µm ({} rays)",
                            um(b.scallop.max_mm),
                            um(b.scallop.mean_mm),
                            um(b.scallop.p95_mm),
                            b.scallop.count
                        )).on_hover_text(format!(
                            "Between the first and last pass, {} mm from them, and {} mm from the passes' ends: the scallop the paths leave between neighbouring passes",
                            crate::simulate::INTERIOR_SIDE_MM,
                            crate::simulate::INTERIOR_END_MM
                        ));
                        self.rects.push(("sim_interior", r.rect));
                    }
                    let whole = if r.interior.is_some() { "· whole patch, edges included (where the cutter leaves the part):" } else { "· scallop" };
                    ui.label(format!(
                        "{whole} max {} / mean {} / p95 {} µm ({} rays)",
                        um(s.max_mm),
                        um(s.mean_mm),
                        um(s.p95_mm),
                        s.count
                    ));
                    match r.stats.worst_gouge {
                        Some((d, at)) => {
                            ui.label(format!("· worst gouge {} µm at ({:.3}, {:.3}) mm", um(d), at.x, at.y));
                            let b = ui.button("go there").on_hover_text("Centre the view on the worst gouge");
                            if b.clicked() {
                                let z = r.map.top_mm[index_of(&r.map.grid, at.x, at.y)];
                                go = Some(glam::DVec3::new(at.x, at.y, z));
                            }
                        }
                        None => {
                            ui.label("· no gouge");
                        }
                    }
                } else {
                    ui.label("· no design: heights only");
                }
            }
        });
        if let Some(pt) = go {
            self.view.go_to(pt);
        }
    }
}

/// Index of the ray nearest (x, y) (mm).
fn index_of(g: &crate::simulate::Grid, x: f64, y: f64) -> usize {
    let i = (((x - g.x0_mm) / g.pitch_mm - 0.5).round().max(0.0) as usize).min(g.nx.saturating_sub(1));
    let j = (((y - g.y0_mm) / g.pitch_mm - 0.5).round().max(0.0) as usize).min(g.ny.saturating_sub(1));
    j * g.nx + i
}

fn parse_f64(key: &str, value: &str, what: &str) -> Result<f64, String> {
    value
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{key}: \"{value}\" is not {what}"))
}

impl Panel for SimulatePanel {
    fn title(&self) -> &'static str {
        SIMULATION_TITLE
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::FIVE_AXIS_FINISHING)
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.rects.clear();
        self.controls(ui, cx);
        let s = &self.settings;
        // The scene's controls where the scene is used: its programs, its ball, its surfaces.
        let own_cutter = s.source == SourceKind::Finish && s.cutter == CutterChoice::SceneBall;
        let scene_design = s.design == DesignChoice::Scene && s.source != SourceKind::Finish;
        if s.source.needs_crease() || (s.cutter == CutterChoice::SceneBall && !own_cutter) || scene_design {
            ui.separator();
            cx.scene_controls(ui);
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let inputs = self.inputs(cx);
        if self.restart || self.job.as_ref().is_none_or(|j| j.inputs != inputs) {
            if self
                .job
                .as_ref()
                .is_none_or(|j| j.inputs.stock_mm != inputs.stock_mm || j.inputs.source != inputs.source)
            {
                self.view.refit = true;
            }
            let loaded = self.own_program.as_ref().or(cx.program.as_ref());
            self.job = Some(Job::new(inputs, cx.scene, loaded, self.target, self.finish.clone()));
            self.job_serial += 1;
            self.restart = false;
        }
        if let Some(job) = &mut self.job {
            job.set_target(self.target);
            if job.computing() {
                // The run is elsewhere: take what arrived, and look again for the progress
                // bar a few times a second (what the run hands back wakes the page at once).
                super::jobs::set_waker(ui.ctx());
                job.advance();
                ui.ctx().request_repaint_after(job.next_look());
            }
        }
        self.playback(ui);
        self.numbers(ui);
        self.refresh_map();
        self.comparison(ui);
        let rect = ui.available_rect_before_wrap();
        let legend = self.job.as_ref().and_then(|j| j.prepared.as_ref()).is_some_and(|p| p.design_name != "none");
        self.view.ui(ui, rect, cx.render_state, self.job.as_ref(), self.settings.band_um, legend);
    }

    fn status(&self) -> serde_json::Value {
        let s = &self.settings;
        let Some(job) = &self.job else {
            return serde_json::json!({ "computing": false, "source": s.source.key(), "stage": "waiting" });
        };
        let prepared = job.prepared.as_ref();
        let results = job.measured();
        let has_design = prepared.is_some_and(|p| p.design_name != "none");
        let t = self.view.camera.target;
        let camera = [t.x, t.y, t.z];
        serde_json::json!({
            "ui": super::widgets::rects_json(&self.rects),
            "computing": job.computing(),
            "stage": job.stage_name(),
            "source": s.source.key(),
            "benchmark": (s.source == SourceKind::Benchmark).then(|| format!("{}:{}", s.bench.0.key(), s.bench.1)),
            "error": job.error,
            "cutter": prepared.map(|p| p.cutter.describe()),
            "grid": job.grid().map(|g| serde_json::json!({ "nx": g.nx, "ny": g.ny, "pitch_mm": g.pitch_mm })),
            "stock_mm": prepared.map(|p| p.stock_mm),
            "moves_total": job.total_moves(),
            "moves_simulated": job.applied(),
            "target_move": job.target_moves(),
            "removed_volume_mm3": job.counters().map(|c| (c.removed_mm3 * 1e6).round() / 1e6),
            "ray_updates": job.counters().map(|c| c.ray_updates),
            "in_background": job.in_background,
            "progress": job.progress().0,
            "chord_error_mm": prepared.map(|p| p.program.chord_error_mm),
            "design": prepared.map(|p| p.design_name),
            "measured": results.is_some(),
            "scallop_um": results.filter(|_| has_design).map(|r| serde_json::json!({
                "rays": r.stats.scallop.count,
                "max": um(r.stats.scallop.max_mm),
                "mean": um(r.stats.scallop.mean_mm),
                "p95": um(r.stats.scallop.p95_mm),
            })),
            "scallop_interior_um": results.and_then(|r| r.interior.as_ref()).map(|b| serde_json::json!({
                "rays": b.scallop.count,
                "max": um(b.scallop.max_mm),
                "mean": um(b.scallop.mean_mm),
                "p95": um(b.scallop.p95_mm),
                "band_rays": b.rays,
                "worst_gouge_um": b.worst_gouge_mm.map(um),
            })),
            "gouge": results.and_then(|r| r.stats.worst_gouge.map(|(d, p)| serde_json::json!({
                "worst_um": um(d), "x_mm": nm(p.x), "y_mm": nm(p.y), "rays": r.stats.gouge_rays
            }))),
            "sim_ms": job.sim_ms,
            "resumed_from_move": results.map(|r| r.resumed_from),
            "total_ms": job.total_ms,
            "slowest_frame_ms": job.slowest_call_ms,
            "pose_step_mm": job.pose_step_mm(),
            "camera_target_local_mm": camera,
            "finish": self.finish.as_ref().map(|f| serde_json::json!({
                "label": f.program.label, "passes": f.program.passes.len(), "cutter": f.program.cutter.describe(), "step_tol_mm": f.program.step_tol_mm,
            })),
            "comparison": self.pinned.as_ref().map(|a| serde_json::json!({
                "a": a.json(),
                "b": self.current_numbers().map(|b| b.json()),
            })),
        })
    }

    fn receive(&mut self, payload: &Payload) -> Result<(), String> {
        match payload {
            Payload::Finish(fp) => {
                self.finish = Some(Rc::clone(fp));
                self.finish_generation += 1;
                // The program's own cutter, a stock sized to its part, its surface as the design.
                let s = &mut self.settings;
                s.source = SourceKind::Finish;
                s.cutter = CutterChoice::SceneBall;
                s.stock_mm = None;
                s.design = DesignChoice::Auto;
                self.target = None;
                Ok(())
            }
        }
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        let s = &mut self.settings;
        match key {
            "source" => {
                s.source = SourceKind::ALL.into_iter().find(|k| k.key() == value).ok_or_else(|| {
                    format!(
                        "source: \"{value}\" is not one of crease-g01, crease-arcs, crease-nurbs, steps, loaded, finish, benchmark"
                    )
                })?;
            }
            // The native benchmark's program, built in the worker from its kind and moves, on
            // its block, grid (pitch 0.1 mm: 512 × 512 rays) and ball; `pitch` and `stock`
            // set after it change those.
            "benchmark" => {
                s.bench = BenchKind::parse(value)?;
                s.source = SourceKind::Benchmark;
                s.cutter = CutterChoice::Ball(bench::BALL_MM);
                s.stock_mm = Some(BenchKind::stock_mm());
                s.pitch_mm = Some(bench::PITCH_MM);
                s.design = DesignChoice::None;
                self.target = None;
            }
            "program_text" => {
                self.own_generation += 1;
                self.own_program = Some(("program".to_owned(), value.to_owned()));
                s.source = SourceKind::Loaded;
            }
            // The name a program given as text is shown under (after `program_text`).
            "program_name" => match &mut self.own_program {
                Some((name, _)) => value.clone_into(name),
                None => return Err("program_name: give program_text first".to_owned()),
            },
            "cutter" => {
                let bad = || format!("cutter: \"{value}\" — give scene, ball:R, flat:R or fillet:R,r in mm");
                s.cutter = if value == "scene" {
                    CutterChoice::SceneBall
                } else {
                    let (kind, dims) = value.split_once(':').ok_or_else(bad)?;
                    let v: Vec<f64> = dims
                        .split(',')
                        .map(|d| d.trim().parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|_| bad())?;
                    match (kind, v.as_slice()) {
                        ("ball", [r]) => CutterChoice::Ball(*r),
                        ("flat", [r]) => CutterChoice::Flat(*r),
                        ("fillet", [r, c]) => CutterChoice::Fillet(*r, *c),
                        _ => return Err(bad()),
                    }
                };
            }
            "pitch" => {
                if value == "auto" {
                    s.pitch_mm = None;
                } else {
                    let p = parse_f64(key, value, "a pitch in mm")?;
                    if !(PITCH_RANGE_MM.0..=PITCH_RANGE_MM.1).contains(&p) {
                        return Err(format!("pitch: {p} mm is outside {} … {} mm", PITCH_RANGE_MM.0, PITCH_RANGE_MM.1));
                    }
                    s.pitch_mm = Some(p);
                }
            }
            "stock" => {
                if value == "auto" {
                    s.stock_mm = None;
                } else {
                    let v: Vec<f64> = value
                        .split(',')
                        .map(|d| d.trim().parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|_| format!("stock: \"{value}\" — give auto or x0,y0,z0,x1,y1,z1 in mm"))?;
                    let b: [f64; 6] = v.try_into().map_err(|_| {
                        format!("stock: \"{value}\" — give auto or six numbers x0,y0,z0,x1,y1,z1 in mm")
                    })?;
                    s.stock_mm = Some(b);
                }
            }
            "margin" => s.margin_mm = parse_f64(key, value, "a margin in mm")?.max(0.0),
            "design" => {
                s.design = match value {
                    "auto" => DesignChoice::Auto,
                    "none" => DesignChoice::None,
                    "scene" => DesignChoice::Scene,
                    _ => match value.strip_prefix("plane:") {
                        Some(z) => DesignChoice::PlaneZ(parse_f64(key, z, "a height in mm")?),
                        None => return Err(format!("design: \"{value}\" — give auto, none, scene or plane:Z (mm)")),
                    },
                };
            }
            "band_um" => s.band_um = parse_f64(key, value, "a deviation in µm")?.clamp(1.0, 1000.0),
            "move" => {
                self.target = if value == "all" {
                    None
                } else {
                    Some(
                        value
                            .trim()
                            .parse::<usize>()
                            .map_err(|_| format!("move: \"{value}\" — give all or a move number"))?,
                    )
                };
            }
            "cancel" => {
                if let Some(j) = &mut self.job {
                    j.cancel();
                }
            }
            "restart" => self.restart = true,
            "pin_a" => {
                self.pinned = Some(self.current_numbers().ok_or("pin_a: the run is not finished and measured yet")?);
                self.pin_serial += 1;
            }
            "clear_a" => self.pinned = None,
            "go_to_gouge" => {
                let at = self.job.as_ref().and_then(|j| j.results.as_ref()).and_then(|r| {
                    r.stats
                        .worst_gouge
                        .map(|(_, at)| glam::DVec3::new(at.x, at.y, r.map.top_mm[index_of(&r.map.grid, at.x, at.y)]))
                });
                match at {
                    Some(p) => self.view.go_to(p),
                    None => return Err("go_to_gouge: no gouge measured".to_owned()),
                }
            }
            _ => {
                return Err(format!(
                    "this view has no option \"{key}\"; it has source, benchmark, program_text, cutter, pitch, stock, margin, design, band_um, move, cancel, restart, go_to_gouge, pin_a, clear_a, program_name (max {MAX_APP_RAYS} rays)"
                ));
            }
        }
        Ok(())
    }
}
