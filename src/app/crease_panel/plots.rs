//! Numbers and plots under the 3D view: playback controls, the summary, measured errors
//! e1, e2 per period against ±b·T and the paper's bound (16), and step length against f.
//! The plots' cursor follows the playback position.

use crate::app::ablate;
use eframe::egui;
use egui_plot::{Corner, HLine, Legend, Line, LineStyle, Plot, PlotPoints, VLine};

use crate::app::compute::Computation;
use crate::app::overlay::decimate;
use crate::app::ranges;
use crate::app::widgets::{PROBLEM_TEXT, SURFACE_COLORS};
use crate::app::{Playback, describe_outcome, fmt_len};
use crate::scene::Scene;

/// Which plot is shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PlotTab {
    /// e1, e2 per period.
    #[default]
    Errors,
    /// Step length − f per period.
    Steps,
}

/// Plot options and the decimated series, rebuilt only when the path changed.
#[derive(Clone, Debug)]
pub struct PlotState {
    /// Which plot.
    pub tab: PlotTab,
    /// |e| on a log scale (else signed, linear).
    pub log: bool,
    cache: Series,
}

impl Default for PlotState {
    fn default() -> Self {
        Self { tab: PlotTab::Errors, log: true, cache: Series::default() }
    }
}

/// Decimated plot series of one computation.
#[derive(Clone, Debug, Default)]
struct Series {
    /// (generation, periods, log scale) they were built from.
    key: Option<(u64, usize, bool)>,
    built: Option<web_time::Instant>,
    e: [Vec<[f64; 2]>; 2],
    b16: [Vec<[f64; 2]>; 2],
    steps: Vec<[f64; 2]>,
}

/// Points kept per series (about two per bucket of the plot's width).
const PLOT_BUCKETS: usize = 1500;

impl Series {
    /// Rebuilds when the path changed — while a long path is still growing, at most four
    /// times a second, so each frame stays O(1) in the path's length.
    fn update(&mut self, compute: &Computation, scene: &Scene, log: bool) {
        let key = (compute.generation, compute.periods.len(), log);
        if self.key == Some(key) {
            return;
        }
        let same_run = self.key.is_some_and(|k| k.0 == key.0 && k.2 == key.2);
        if same_run && compute.running() && self.built.is_some_and(|t| t.elapsed().as_millis() < 250) {
            return;
        }
        let period = scene.motion.period;
        let f = scene.feed_per_period_mm();
        let y = |mm: f64| if log { (mm.abs().max(LOG_FLOOR_MM) * 1e3).log10() } else { mm * 1e3 };
        let mut e = [Vec::new(), Vec::new()];
        let mut b16 = [Vec::new(), Vec::new()];
        for p in &compute.periods {
            let t = p.row.k as f64 * period;
            if let Some(d) = &p.diag {
                for i in 0..2 {
                    e[i].push([t, y(crate::numerics::sign::stock_positive(d.measured[i]))]);
                    if let Some(b) = d.est16[i] {
                        b16[i].push([t, y(b)]);
                    }
                }
            }
        }
        let steps: Vec<[f64; 2]> = compute
            .periods
            .windows(2)
            .map(|w| [w[1].row.k as f64 * period, ((w[1].row.p - w[0].row.p).length() - f) * 1e6])
            .collect();
        self.e = e.map(|v| decimate(&v, PLOT_BUCKETS));
        self.b16 = b16.map(|v| decimate(&v, PLOT_BUCKETS));
        self.steps = decimate(&steps, PLOT_BUCKETS);
        self.key = Some(key);
        self.built = Some(web_time::Instant::now());
    }
}

/// Playback controls: play/pause, step, scrub, speed.
pub fn playback_bar(ui: &mut egui::Ui, pb: &mut Playback, compute: &Computation, period_ms: f64) {
    let n = compute.periods.len();
    let last = n.saturating_sub(1) as f64;
    ui.horizontal(|ui| {
        if ui.button(if pb.playing { "Pause" } else { "Play" }).clicked() {
            if !pb.playing && pb.k >= last {
                pb.k = 0.0;
            }
            pb.playing = !pb.playing;
        }
        if ui.button("Start").on_hover_text("back to the start").clicked() {
            pb.k = 0.0;
        }
        if ui.button("−1").on_hover_text("one period back").clicked() {
            pb.playing = false;
            pb.k = (pb.k.floor() - 1.0).max(0.0);
        }
        if ui.button("+1").on_hover_text("one period forward").clicked() {
            pb.playing = false;
            pb.k = (pb.k.floor() + 1.0).min(last);
        }
        let mut k = pb.k.floor();
        ui.spacing_mut().slider_width = (ui.available_width() - 520.0).clamp(120.0, 900.0);
        if ui.add(egui::Slider::new(&mut k, 0.0..=last.max(1.0)).step_by(1.0).text("period")).changed() {
            pb.k = k;
            pb.playing = false;
        }
        ui.spacing_mut().slider_width = 90.0;
        ui.add(egui::Slider::new(&mut pb.speed, ranges::PLAYBACK_SPEED).logarithmic(true).suffix("×").text("speed"));
        ui.label(format!("t = {:.3} s of {:.3} s", pb.k.floor() * period_ms / 1000.0, last * period_ms / 1000.0));
    });
}

/// Floor of the log plot (mm): 0.1 pm, below the rounding of a foot-point projection.
const LOG_FLOOR_MM: f64 = 1e-10;

/// What the user asked for in the plots panel.
#[derive(Default)]
pub struct PlotsOutput {
    /// A `path.direction` to set (the "run toward path.end" button).
    pub direction: Option<[f64; 3]>,
    /// Where that button is (for the status element).
    pub toward_end_rect: Option<egui::Rect>,
}

fn summary(ui: &mut egui::Ui, compute: &Computation, scene: &Scene, out: &mut PlotsOutput) {
    let n = compute.periods.len().saturating_sub(1);
    let f = scene.feed_per_period_mm();
    let (worst, bound) = compute.worst();
    egui::Grid::new("summary").num_columns(2).striped(true).spacing([12.0, 3.0]).show(ui, |ui| {
        let (ok, text) = describe_outcome(compute);
        ui.label("run");
        ui.vertical(|ui| {
            // Long messages (a domain exit, an error) wrap instead of widening the table.
            ui.set_max_width(300.0);
            let color = if ok { ui.visuals().text_color() } else { PROBLEM_TEXT };
            ui.add(egui::Label::new(egui::RichText::new(text).color(color)).wrap());
        });
        ui.end_row();
        if let Some(note) = compute.end_not_reached() {
            ui.label("path.end");
            ui.vertical(|ui| {
                ui.set_max_width(300.0);
                let text = egui::RichText::new(note.to_string()).color(egui::Color32::from_rgb(240, 190, 90));
                ui.add(egui::Label::new(text).wrap());
                if let Some(sense) = note.away_from_end {
                    let b = ui
                        .button("run toward path.end")
                        .on_hover_text("Sets path.direction against the present sense of travel and runs again");
                    out.toward_end_rect = Some(b.rect);
                    if b.clicked() {
                        out.direction = Some(crate::crease::reversed_direction(sense));
                    }
                }
            });
            ui.end_row();
        }
        ui.label("periods");
        ui.label(format!("{n}"));
        ui.end_row();
        ui.label("path length");
        ui.label(format!("{:.3} mm  (f = {f:.4} mm)", compute.length_mm));
        ui.end_row();
        ui.label("machining time");
        ui.label(format!("{:.3} s", n as f64 * scene.motion.period / 1000.0));
        ui.end_row();
        for i in 0..2 {
            let allowed = scene.tolerance.share * if i == 0 { scene.tolerance.t1 } else { scene.tolerance.t2 };
            ui.label(format!("worst |e{}|", i + 1));
            let within = worst[i] <= allowed;
            ui.label(
                egui::RichText::new(format!("{}  (b·T{} = {})", fmt_len(worst[i]), i + 1, fmt_len(allowed)))
                    .color(if within { ui.visuals().text_color() } else { PROBLEM_TEXT }),
            );
            ui.end_row();
            ui.label(format!("bound (16) on S{}", i + 1));
            ui.label(bound[i].map_or_else(|| "not applicable".to_owned(), fmt_len));
            ui.end_row();
        }
        ui.label("compute, this device");
        match compute.us_per_period() {
            Some(us) => ui.label(format!(
                "{us:.2} µs per period; error measurement {:.2} µs",
                compute.measure_seconds * 1e6 / compute.periods.len().max(1) as f64
            )),
            None => ui.label("—"),
        };
        ui.end_row();
    });
}

/// The summary and the selected plot, side by side.
pub fn plots(
    ui: &mut egui::Ui,
    state: &mut PlotState,
    compute: &Computation,
    scene: &Scene,
    cursor_k: f64,
) -> PlotsOutput {
    let mut out = PlotsOutput::default();
    ui.horizontal_top(|ui| {
        ui.vertical(|ui| {
            ui.set_width(330.0);
            ui.set_max_width(330.0);
            summary(ui, compute, scene, &mut out);
        });
        ui.separator();
        ui.vertical(|ui| {
            ui.horizontal(|ui| {
                ui.selectable_value(&mut state.tab, PlotTab::Errors, "errors e1, e2");
                ui.selectable_value(&mut state.tab, PlotTab::Steps, "step length − f");
                if state.tab == PlotTab::Errors {
                    ui.separator();
                    ui.checkbox(&mut state.log, "log scale |e|");
                }
            });
            let period = scene.motion.period;
            let cursor_t = cursor_k.floor() * period;
            state.cache.update(compute, scene, state.log);
            match state.tab {
                _ if ablate::hidden(ablate::Part::Plot) => {}
                PlotTab::Errors => errors_plot(ui, state.log, &state.cache, scene, cursor_t),
                PlotTab::Steps => steps_plot(ui, &state.cache, scene, cursor_t),
            }
        });
    });
    out
}

fn errors_plot(ui: &mut egui::Ui, log: bool, series: &Series, scene: &Scene, cursor_t: f64) {
    let allowed = [scene.tolerance.share * scene.tolerance.t1, scene.tolerance.share * scene.tolerance.t2];
    let plot = Plot::new("errors")
        .legend(Legend::default().position(Corner::LeftTop).background_alpha(0.6))
        .x_axis_label("t (ms)")
        .y_axis_label(if log { "|e| (µm, log)" } else { "e (µm)" })
        .allow_scroll(false)
        .show_grid(!ablate::hidden(ablate::Part::Grid))
        .y_axis_formatter(
            move |mark, _| {
                if log { format!("1e{:.0}", mark.value) } else { format!("{:.3}", mark.value) }
            },
        );
    plot.show(ui, |p| {
        for i in 0..2 {
            if ablate::hidden(ablate::Part::PlotData) {
                break;
            }
            let color = SURFACE_COLORS[i];
            p.line(
                Line::new(format!("e{} measured", i + 1), PlotPoints::from(series.e[i].clone()))
                    .color(color)
                    .width(1.5),
            );
            p.line(
                Line::new(format!("bound (16) S{}", i + 1), PlotPoints::from(series.b16[i].clone()))
                    .color(color.gamma_multiply(0.7))
                    .style(LineStyle::dashed_loose()),
            );
            let tol = if log { (allowed[i] * 1e3).log10() } else { allowed[i] * 1e3 };
            p.hline(
                HLine::new(format!("b·T{} = {}", i + 1, fmt_len(allowed[i])), tol)
                    .color(egui::Color32::from_rgb(235, 90, 80))
                    .width(1.0),
            );
            if !log {
                p.hline(
                    HLine::new(format!("−b·T{}", i + 1), -tol).color(egui::Color32::from_rgb(235, 90, 80)).width(1.0),
                );
            }
        }
        p.vline(VLine::new("playback", cursor_t).color(egui::Color32::from_gray(200)).width(1.0));
    });
}

fn steps_plot(ui: &mut egui::Ui, series: &Series, scene: &Scene, cursor_t: f64) {
    let f = scene.feed_per_period_mm();
    Plot::new("steps")
        .legend(Legend::default().position(Corner::LeftTop).background_alpha(0.6))
        .x_axis_label("t (ms)")
        .y_axis_label("|Δp| − f (nm)")
        .allow_scroll(false)
        .show(ui, |p| {
            p.line(
                Line::new("step length − f", PlotPoints::from(series.steps.clone()))
                    .color(egui::Color32::from_rgb(120, 230, 120)),
            );
            p.hline(HLine::new(format!("f = {f:.4} mm"), 0.0).color(egui::Color32::from_gray(160)));
            p.vline(VLine::new("playback", cursor_t).color(egui::Color32::from_gray(200)).width(1.0));
        });
}
