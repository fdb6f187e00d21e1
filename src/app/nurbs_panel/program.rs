//! The NURBS & G-code tab's program column: the comparison table, the program text with
//! copy, download and go-to-line, and the G-code file loaded.

use eframe::egui;

use super::table::{self, Shown};
use super::work::Source;
use super::{NurbsPanel, um};
use crate::app::panel::PanelContext;
use crate::app::platform::FileKind;
use crate::gcode::{Dialect, ProgramKind, TableStyle, format_comparison, format_comparisons_with};
use crate::plan::PRESETS;

impl NurbsPanel {
    pub(super) fn side(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let w = self.wanted.clone();
        // Why nothing below is current: the crease still computing, or no design path.
        let problem = match (&self.waiting, &self.work.design.value) {
            (Some(why), _) => Some(why.clone()),
            (None, Some(Err(e))) if w.as_ref().is_some_and(|w| self.work.design_fresh(w)) => Some((false, e.clone())),
            _ => None,
        };
        if let Some((progress, text)) = problem {
            let color = if progress { egui::Color32::from_gray(200) } else { egui::Color32::from_rgb(255, 120, 110) };
            ui.label(egui::RichText::new(text).color(color));
            ui.add_space(4.0);
        }
        ui.horizontal(|ui| {
            let (tol, feed) =
                w.as_ref().map_or((self.settings.tol_mm, 0.0), |w| (w.program.tol_mm, w.program.feed_mm_per_min));
            ui.label(egui::RichText::new(format!("Programs within E = {} at F = {feed:.0} mm/min", um(tol))).strong());
            if let Some(c) = w.as_ref().and_then(|w| self.work.comparison(w))
                && ui
                    .small_button("copy table")
                    .on_hover_text("Both tables as Markdown, as `interpolab compare [--machine M]` prints them")
                    .clicked()
            {
                let text = match self.work.time_columns() {
                    Some(extra) => format_comparisons_with(&[c], &extra, TableStyle::Markdown),
                    None => format_comparison(&c, TableStyle::Markdown),
                };
                ui.ctx().copy_text(text);
                cx.info("Comparison tables copied to the clipboard (Markdown).");
            }
        });
        self.machine_picker(ui);
        table::programs_table(ui, &self.work, w.as_ref());
        ui.add_space(4.0);
        table::realtime_table(ui, &self.work, w.as_ref());
        ui.separator();
        self.gcode(ui, cx);
    }

    /// The machine the programs are timed on (a preset), or none to hide the time columns.
    fn machine_picker(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.horizontal(|ui| {
            ui.label("time on machine:");
            let r = egui::ComboBox::from_id_salt("nurbs-machine")
                .selected_text(s.machine.unwrap_or("none"))
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut s.machine, None, "none").on_hover_text("Hide the time columns");
                    for p in PRESETS {
                        ui.selectable_value(&mut s.machine, Some(p), p);
                    }
                })
                .response
                .on_hover_text(
                    "Each program's feed planned on this machine's dynamics (`interpolab compare --machine`): \
                     hobby-router a GRBL-class router, vmc a vertical machining centre; the five-axis presets have \
                     the VMC's linear axes, so the same times for these three-axis programs",
                );
            self.rects.push(("machine", r.rect));
        });
    }

    pub(super) fn file_stem(&self, cx: &PanelContext<'_>) -> String {
        let name = match self.settings.source {
            Source::Parabola => "parabola",
            Source::Crease => cx.scene.name.as_str(),
        };
        crate::scene::file_stem(name).unwrap_or_else(|| "program".to_owned())
    }

    pub(super) fn gcode(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("G-code:").strong());
            for kind in ProgramKind::ALL {
                let r = ui.selectable_label(self.shown == Shown::Kind(kind), self.settings.dialect.kind_label(kind));
                self.rects.push((kind.label(), r.rect));
                if r.clicked() {
                    self.shown = Shown::Kind(kind);
                    self.scroll_to = Some(1);
                }
            }
            if let Some(l) = &self.work.loaded {
                let chars: Vec<char> = l.name.chars().collect();
                let name = if chars.len() > 28 {
                    format!("…{}", chars[chars.len() - 26..].iter().collect::<String>())
                } else {
                    l.name.clone()
                };
                if ui.selectable_label(self.shown == Shown::Loaded, name).on_hover_text(&l.name).clicked() {
                    self.shown = Shown::Loaded;
                    self.scroll_to = Some(1);
                }
            }
            ui.separator();
            let r = ui.button("Open a G-code file…").on_hover_text(
                "Read a program (.nc, .ngc, .gcode, .tap, .txt) and draw it over the design; or drop it on the page",
            );
            self.rects.push(("open_gcode", r.rect));
            if r.clicked() {
                cx.pick_file(FileKind::GCode);
            }
        });
        // The text shown and what to say about it.
        let (text, name, mark): (Option<&str>, String, Option<usize>) = match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                match self.work.row(i) {
                    Some(r) => (
                        Some(r.program.text.as_str()),
                        match self.settings.dialect {
                            Dialect::Fanuc => format!("{}-{}.nc", self.file_stem(cx), kind.as_str()),
                            d => format!("{}-{d}-{}.nc", self.file_stem(cx), kind.as_str()),
                        },
                        Some(r.program.deviation.program_line),
                    ),
                    None => (None, String::new(), None),
                }
            }
            Shown::Loaded => match &self.work.loaded {
                Some(l) => (
                    Some(l.text.as_str()),
                    l.name.clone(),
                    l.error_line.or_else(|| self.work.loaded_deviation.ok().map(|d| d.program_line)),
                ),
                None => (None, String::new(), None),
            },
        };
        let mut go_to = None;
        let mut close = false;
        let mut saved = None;
        ui.horizontal_wrapped(|ui| {
            let enabled = text.is_some();
            if ui
                .add_enabled(enabled, egui::Button::new("Copy"))
                .on_hover_text("Copy the program text to the clipboard")
                .clicked()
                && let Some(t) = text
            {
                ui.ctx().copy_text(t.to_owned());
                cx.info(format!("{name} copied to the clipboard ({} bytes).", t.len()));
            }
            let r = ui.add_enabled(enabled, egui::Button::new("Download")).on_hover_text(format!("Save as {name}"));
            self.rects.push(("download", r.rect));
            if r.clicked()
                && let Some(t) = text
            {
                cx.save_text(&name, t);
                saved = Some(name.clone());
            }
            if let Some(m) = mark
                && ui
                    .small_button(format!("go to line {m}"))
                    .on_hover_text("The line of the largest deviation, or of the reader's error")
                    .clicked()
            {
                go_to = Some(m);
            }
            close = self.shown == Shown::Loaded && ui.small_button("close file").clicked();
        });
        self.about_shown(ui);
        let scroll_to = go_to.or(self.scroll_to);
        match text {
            Some(t) => table::code_view(ui, t, mark, scroll_to),
            None => {
                let msg = match self.shown {
                    Shown::Loaded => "No file loaded.".to_owned(),
                    Shown::Kind(kind) => {
                        let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                        match &self.work.rows[i].value {
                            Some(Err(e)) => e.clone(),
                            _ => "computing…".to_owned(),
                        }
                    }
                };
                ui.label(egui::RichText::new(msg).weak().italics());
            }
        }
        self.scroll_to = None;
        if saved.is_some() {
            self.downloaded = saved;
        }
        if close {
            self.work.unload();
            self.shown = Shown::Kind(ProgramKind::Nurbs);
        }
    }
}
