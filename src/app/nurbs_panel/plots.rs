//! Plots of the real-time run over time (ms): the feed (mm/min) or its relative fluctuation
//! per period, and the chord error per period (µm, log) against the tolerance.

use crate::app::overlay::decimate;
use eframe::egui;
use egui_plot::{Corner, HLine, Legend, Line, Plot, PlotPoints, uniform_grid_spacer};

use super::view::{LOADED_COLOR, turbo};
use super::work::Realtime;

/// The feed plot shows at least this fraction of F around F (±1 ppm), so rounding noise is
/// not blown up.
const FEED_PLOT_MIN_REL: f64 = 1e-6;

/// What the first plot shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedPlot {
    /// Feed per period as a speed, F·(1 + Δf/f) (mm/min).
    Feed,
    /// |Δf/f| per period, log.
    Fluctuation,
}

/// Floor of the log plots: |Δf/f| and chord errors below it are drawn at it.
const LOG_FLOOR: f64 = 1e-16;

/// Grid steps for a linear axis: labelled lines at a 1-2-5 step giving about 5 labels, thin
/// lines at a fifth of it.
fn nice_grid(input: egui_plot::GridInput) -> [f64; 3] {
    let span = (input.bounds.1 - input.bounds.0).abs().max(f64::MIN_POSITIVE);
    let raw = span / 5.0;
    let pow = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * pow).find(|s| *s >= raw).unwrap_or(10.0 * pow);
    [step / 5.0, step, step * 10.0]
}

fn log_axis(mark: egui_plot::GridMark) -> String {
    format!("1e{:.0}", mark.value)
}

/// The plotted series of one run, reduced to their envelopes (built once per run and mode,
/// not every frame: a slow feed gives 10⁵ periods).
#[derive(Default)]
pub struct Series {
    key: Option<(u64, FeedPlot)>,
    feed: Vec<[f64; 2]>,
    chord: Vec<[f64; 2]>,
}

impl Series {
    fn update(&mut self, generation: u64, mode: FeedPlot, rt: &Realtime) {
        if self.key == Some((generation, mode)) {
            return;
        }
        let ts = rt.period_ms;
        let samples = rt.run.samples.iter().filter(|s| !s.last);
        let feed: Vec<[f64; 2]> = match mode {
            FeedPlot::Feed => samples.clone().map(|s| [s.k as f64 * ts, s.step_mm / ts * 60_000.0]).collect(),
            FeedPlot::Fluctuation => {
                samples.clone().map(|s| [s.k as f64 * ts, s.fluctuation.abs().max(LOG_FLOOR).log10()]).collect()
            }
        };
        let chord: Vec<[f64; 2]> =
            samples.map(|s| [s.k as f64 * ts, (s.chord_error_mm * 1000.0).max(LOG_FLOOR).log10()]).collect();
        self.feed = decimate(&feed, 1200);
        self.chord = decimate(&chord, 1200);
        self.key = Some((generation, mode));
    }
}

/// The two plots side by side in `ui`; `rt` with its generation.
pub fn plots(
    ui: &mut egui::Ui,
    series: &mut Series,
    mode: FeedPlot,
    rt: Option<(u64, &Realtime)>,
    feed_mm_per_min: f64,
    tol_mm: f64,
    chord_tol_mm: Option<f64>,
) {
    let Some((generation, rt)) = rt else {
        ui.centered_and_justified(|ui| {
            ui.label(
                egui::RichText::new("The real-time interpolation plots appear once the G06.2 program is written.")
                    .weak(),
            );
        });
        return;
    };
    series.update(generation, mode, rt);
    let update = rt.run.stats.update.as_str();
    let link = egui::Id::unique("nurbs-time-axis");
    let width = (ui.available_width() - 12.0) / 2.0;
    let height = ui.available_height();
    ui.horizontal_top(|ui| {
        ui.allocate_ui(egui::vec2(width, height), |ui| {
            ui.vertical(|ui| {
                let title = match mode {
                    FeedPlot::Feed => format!("feed per period, {update} update (mm/min)"),
                    FeedPlot::Fluctuation => format!("feed fluctuation |Δf/f| per period, {update} update (log)"),
                };
                ui.label(egui::RichText::new(title).strong());
                let label = match mode {
                    FeedPlot::Feed => "feed (mm/min)",
                    FeedPlot::Fluctuation => "|Δf/f| (log)",
                };
                let mut plot = Plot::new("nurbs-feed")
                    .legend(Legend::default().position(Corner::RightBottom).background_alpha(0.6))
                    .x_axis_label("t (ms)")
                    .x_grid_spacer(uniform_grid_spacer(nice_grid))
                    .y_axis_label(label)
                    .allow_scroll(false)
                    .link_axis(link, [true, false]);
                match mode {
                    FeedPlot::Feed => {
                        // At least ±1 ppm of F around F, so rounding noise is not blown up.
                        plot = plot
                            .include_y(feed_mm_per_min * (1.0 - FEED_PLOT_MIN_REL))
                            .include_y(feed_mm_per_min * (1.0 + FEED_PLOT_MIN_REL));
                    }
                    FeedPlot::Fluctuation => {
                        plot = plot
                            .y_axis_formatter(|m, _| log_axis(m))
                            .y_grid_spacer(uniform_grid_spacer(|_| [1.0, 2.0, 4.0]))
                            .include_y(-15.0)
                            .include_y(-3.0);
                    }
                }
                plot.show(ui, |p| {
                    let name = match mode {
                        FeedPlot::Feed => format!("feed, {update} update"),
                        FeedPlot::Fluctuation => format!("|Δf/f|, {update} update"),
                    };
                    p.line(Line::new(name, PlotPoints::from(series.feed.clone())).color(turbo(0.75)).width(1.5));
                    if mode == FeedPlot::Feed {
                        p.hline(
                            HLine::new(format!("programmed F = {feed_mm_per_min:.0} mm/min"), feed_mm_per_min)
                                .color(egui::Color32::from_gray(170)),
                        );
                    }
                });
            });
        });
        ui.separator();
        ui.allocate_ui(egui::vec2(width, height), |ui| {
            ui.vertical(|ui| {
                ui.label(
                    egui::RichText::new(format!(
                        "chord error per period (µm, log): max {} µm",
                        crate::report::fmt_fixed(rt.run.stats.max_chord_error_mm * 1000.0, 6)
                    ))
                    .strong(),
                );
                Plot::new("nurbs-chord")
                    .legend(Legend::default().position(Corner::RightBottom).background_alpha(0.6))
                    .x_axis_label("t (ms)")
                    .x_grid_spacer(uniform_grid_spacer(nice_grid))
                    .y_axis_label("chord error (µm, log)")
                    .allow_scroll(false)
                    .link_axis(link, [true, false])
                    .y_axis_formatter(|m, _| log_axis(m))
                    .y_grid_spacer(uniform_grid_spacer(|_| [1.0, 2.0, 4.0]))
                    .include_y((tol_mm * 1000.0).log10() + 0.3)
                    .show(ui, |p| {
                        p.line(
                            Line::new("chord error", PlotPoints::from(series.chord.clone()))
                                .color(egui::Color32::from_rgb(120, 200, 255))
                                .width(1.5),
                        );
                        p.hline(
                            HLine::new(format!("tolerance E = {}", super::um(tol_mm)), (tol_mm * 1000.0).log10())
                                .color(egui::Color32::from_rgb(235, 90, 80)),
                        );
                        if let Some(d) = chord_tol_mm {
                            p.hline(
                                HLine::new(format!("chord tolerance δ = {}", super::um(d)), (d * 1000.0).log10())
                                    .color(LOADED_COLOR),
                            );
                        }
                    });
            });
        });
    });
}
