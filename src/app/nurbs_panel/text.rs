//! The NURBS & G-code tab's prose: the state of its work in one line, and what the shown
//! program is (its size and deviation, or the reader's complaints).

use eframe::egui;

use super::table::Shown;
use super::work::Pending;
use super::{NurbsPanel, um, view};
use crate::gcode::{ProgramKind, ProgrammedPoint};

impl NurbsPanel {
    /// One line about the work's state for the view's corner.
    pub(super) fn status_line(&self) -> (bool, String) {
        if let Some(w) = &self.waiting {
            return w.clone();
        }
        let Some(w) = &self.wanted else { return (true, String::new()) };
        if let Some(Err(e)) = &self.work.design.value {
            return (false, e.clone());
        }
        match self.work.pending(w) {
            Pending::Nothing => {
                let errs = self.work.rows.iter().filter(|r| matches!(r.value, Some(Err(_)))).count();
                if errs > 0 {
                    (false, format!("{errs} program(s) could not be written — see the table"))
                } else {
                    (true, "up to date".to_owned())
                }
            }
            Pending::Waiting(_) | Pending::Working => {
                let what = if !self.work.design_fresh(w) {
                    match self.work.design_progress() {
                        Some(n) => return (true, format!("computing… design path ({n} periods of the crease)")),
                        None => "design path",
                    }
                } else if let jobs @ [_, ..] = &self.work.jobs_running()[..] {
                    // The programs are written in the background, side by side.
                    let list: Vec<String> =
                        jobs.iter().map(|(k, t)| format!("{} ({t:.1} s)", w.program.dialect.kind_label(*k))).collect();
                    return (true, format!("computing in the background… {}", list.join(", ")));
                } else if !self.work.row_fresh(0, w) {
                    "G01 program"
                } else if !self.work.row_fresh(1, w) {
                    "G02/G03 program"
                } else if !self.work.row_fresh(2, w) {
                    "G06.2 program"
                } else if !self.work.realtime_fresh(w) {
                    match self.work.realtime_progress() {
                        Some((u, k)) => {
                            return (
                                true,
                                format!("computing… real-time interpolation, {} update ({k} periods)", u.as_str()),
                            );
                        }
                        None => "real-time interpolation",
                    }
                } else {
                    "deviation of the loaded program"
                };
                (true, format!("computing… {what}"))
            }
        }
    }

    /// A line about the shown program: its size and deviation, or the reader's complaints.
    pub(super) fn about_shown(&self, ui: &mut egui::Ui) {
        let red = egui::Color32::from_rgb(255, 120, 110);
        let yellow = egui::Color32::from_rgb(240, 200, 90);
        match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                if let Some(r) = self.work.row(i) {
                    ui.label(format!(
                        "{}: {} path blocks, {} lines, {} bytes; deviation after rounding {} (program → design largest at line {}).",
                        kind.label(),
                        r.path_blocks,
                        r.program.parsed.lines,
                        r.bytes,
                        um(r.deviation_mm),
                        r.program.deviation.program_line
                    ));
                }
            }
            Shown::Loaded => {
                let Some(l) = &self.work.loaded else { return };
                if let Some(r) = &l.reader {
                    ui.label(format!(
                        "{}: reading — {:.0} % of the file, {} moves so far …",
                        l.name,
                        100.0 * r.progress(),
                        r.program().toolpath.blocks.len()
                    ));
                    return;
                }
                match &l.parsed {
                    Err(e) => {
                        ui.label(egui::RichText::new(format!("{}: {e}", l.name)).color(red));
                    }
                    Ok(p) => {
                        let s = crate::gcode::summarize(&p.toolpath);
                        ui.label(format!(
                            "{}: {} lines, {} path blocks (G01 {}, G02 {}, G03 {}, G06.2 curves {}), cutting length {:.3} mm.",
                            l.name,
                            p.lines,
                            p.path_blocks(),
                            s.moves[1],
                            s.moves[2],
                            s.moves[3],
                            s.moves[4],
                            s.cut_length_mm
                        ));
                        match &self.work.loaded_deviation.value {
                            Some(Ok(d)) => {
                                let point = l.point.map_or("the panel's programmed point", |p| match p {
                                    ProgrammedPoint::BallCentre => "ball centre (from its header)",
                                    ProgrammedPoint::BallTip { .. } => "ball tip (from its header)",
                                });
                                ui.label(
                                    egui::RichText::new(format!(
                                        "Deviation from the design path: {} — program → design {} (line {}), design → program {}; gaps at the ends {} / {}. Point: {point}.",
                                        um(d.max_mm()),
                                        um(d.program_to_design_mm),
                                        d.program_line,
                                        um(d.design_to_program_mm),
                                        um(d.start_gap_mm),
                                        um(d.end_gap_mm)
                                    ))
                                    .color(view::LOADED_COLOR),
                                );
                            }
                            Some(Err(e)) => {
                                ui.label(egui::RichText::new(e).color(red));
                            }
                            None => {
                                ui.label(egui::RichText::new("measuring the deviation…").weak().italics());
                            }
                        }
                        if !p.unsupported.is_empty() {
                            let list: Vec<String> = p
                                .unsupported
                                .iter()
                                .take(6)
                                .map(|u| {
                                    let times =
                                        if u.count > 1 { format!(", {} times", u.count) } else { String::new() };
                                    format!("line {}: {} ({}{times})", u.line, u.word, u.reason)
                                })
                                .collect();
                            let more = if p.unsupported.len() > 6 {
                                format!(" and {} more", p.unsupported.len() - 6)
                            } else {
                                String::new()
                            };
                            ui.label(
                                egui::RichText::new(format!(
                                    "Not modelled, effect left out: {}{more}",
                                    list.join("; ")
                                ))
                                .color(yellow),
                            );
                        }
                    }
                }
            }
        }
    }
}
