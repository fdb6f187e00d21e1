//! The comparison tables (seed 004: blocks, bytes, worst deviation, junction smoothness of
//! the G01, G02/G03 and G06.2 programs, and their time and mean feed on the chosen machine;
//! feed fluctuation of each real-time update) and the G-code view of the selected program
//! with line numbers.

use eframe::egui;

use super::um;
use super::view::{ARCS_COLOR, CURVE_COLOR, LINES_COLOR, fluct_t, turbo};
use super::work::{Wanted, Work};
use crate::gcode::ProgramKind;
use crate::report::fmt_fixed;

const STALE: egui::Color32 = egui::Color32::from_gray(110);
const BAD: egui::Color32 = egui::Color32::from_rgb(255, 120, 110);

/// Colour of a program kind in the view and the table.
pub(super) fn kind_color(kind: ProgramKind) -> egui::Color32 {
    match kind {
        ProgramKind::Lines => LINES_COLOR,
        ProgramKind::Arcs => ARCS_COLOR,
        ProgramKind::Nurbs => CURVE_COLOR,
    }
}

/// `x` with `digits` significant digits, trailing zeros kept and no decimals past the units
/// (e.g. 9.980, 14.01, 1486); "—" for a value that is not finite.
#[must_use]
pub(super) fn significant(x: f64, digits: i32) -> String {
    if !x.is_finite() {
        return "—".to_owned();
    }
    let a = x.abs();
    let decimals = if a > 0.0 { (digits - 1 - a.log10().floor() as i32).clamp(0, 9) as usize } else { 0 };
    format!("{x:.decimals$}")
}

/// The programs table. `wanted` is `None` while the inputs are not ready (all stale).
pub fn programs_table(ui: &mut egui::Ui, work: &Work, wanted: Option<&Wanted>) {
    let feed = wanted.map_or(0.0, |w| w.program.feed_mm_per_min);
    let lines_blocks = work.row(0).map(|r| r.path_blocks);
    let machine = wanted.and_then(|w| w.machine.as_ref()).map(|m| m.name.as_str());
    let time_head = machine.map(|m| format!("time on {m}"));
    let time_tip = machine.map(|m| {
        format!(
            "Cycle time (s) of the program on the machine {m}: its feed planned within the machine's axis limits \
             (velocity, acceleration, jerk) and contour tolerance, rapids included — `interpolab compare --machine {m}`. \
             Hover a time for the feed moves' share."
        )
    });
    let columns = if machine.is_some() { 10 } else { 8 };
    egui::Grid::new("nurbs-compare").num_columns(columns).striped(true).spacing([10.0, 3.0]).show(ui, |ui| {
        for (h, tip) in [
            ("program", "Program kind"),
            ("path blocks", "Blocks describing the cut: G01/G02/G03 moves; for G06.2 the control-point blocks plus the closing knot blocks"),
            ("vs G01", "Path blocks relative to the G01 program"),
            ("bytes", "Size of the whole program text"),
            ("max deviation", "Worst two-sided distance between the program (after rounding, read back from its text) and the design path"),
            ("junctions", "Junctions between consecutive cutting moves"),
            ("max turn", "Largest tangent turn at a junction: the velocity jumps by 2F·sin(θ/2) there"),
            ("velocity jump", "At the feed F: 2F·sin(θ/2) (mm/min)"),
        ] {
            ui.label(egui::RichText::new(h).strong()).on_hover_text(tip);
        }
        if let (Some(h), Some(tip)) = (&time_head, &time_tip) {
            ui.label(egui::RichText::new(h).strong()).on_hover_text(tip);
            ui.label(egui::RichText::new("mean feed").strong()).on_hover_text(
                "Length of the feed moves over their planned time (mm/min): below F where the machine slows \
                 down — at corners, in tight curvature, to start and stop",
            );
        }
        ui.end_row();
        for (i, kind) in ProgramKind::ALL.into_iter().enumerate() {
            let fresh = wanted.is_some_and(|w| work.row_fresh(i, w));
            let color = if fresh { ui.visuals().text_color() } else { STALE };
            let dialect = wanted.map_or_else(Default::default, |w| w.program.dialect);
            ui.label(egui::RichText::new(dialect.kind_label(kind)).color(kind_color(kind)).strong())
                .on_hover_text(format!("{} program", dialect.label()));
            match &work.rows[i].value {
                None => {
                    ui.label(egui::RichText::new("computing…").color(STALE).italics());
                    ui.end_row();
                    continue;
                }
                Some(Err(e)) => {
                    // The reason is said under the table (it is long).
                    ui.label(egui::RichText::new("not written").color(if fresh { BAD } else { STALE }))
                        .on_hover_text(e);
                    ui.end_row();
                    continue;
                }
                Some(Ok(timed)) => {
                    let r = &timed.row;
                    let t = |s: String| egui::RichText::new(s).color(color);
                    ui.label(t(r.path_blocks.to_string()));
                    let vs = match lines_blocks {
                        Some(l) if l > 0 => format!("{:+.0} %", 100.0 * (r.path_blocks as f64 - l as f64) / l as f64),
                        _ => "—".to_owned(),
                    };
                    ui.label(t(vs));
                    ui.label(t(r.bytes.to_string()));
                    ui.label(t(um(r.deviation_mm)));
                    ui.label(t(r.junctions.count.to_string()));
                    ui.label(t(format!("{}°", fmt_fixed(r.junctions.max_turn_deg, 3))));
                    ui.label(t(format!("{} mm/min", fmt_fixed(r.junctions.velocity_jump(feed), 1))));
                    if machine.is_some() {
                        match &timed.time {
                            Some(Ok(c)) => {
                                ui.label(t(format!("{} s", significant(c.total_s, 4)))).on_hover_text(format!(
                                    "{} s in feed moves, {} s in rapids, on {}",
                                    significant(c.feed_s, 4),
                                    significant(c.total_s - c.feed_s, 4),
                                    c.machine
                                ));
                                ui.label(t(c
                                    .mean_feed_mm_min()
                                    .map_or_else(|| "—".to_owned(), |f| format!("{} mm/min", significant(f, 4)))));
                            }
                            Some(Err(e)) => {
                                ui.label(egui::RichText::new("not timed").color(if fresh { BAD } else { STALE }))
                                    .on_hover_text(e);
                            }
                            None => {
                                ui.label(egui::RichText::new("—").color(STALE));
                            }
                        }
                    }
                }
            }
            ui.end_row();
        }
    });
    // Why programs were not written, each reason once.
    let mut reasons: Vec<(Vec<&str>, &str)> = Vec::new();
    for (i, kind) in ProgramKind::ALL.into_iter().enumerate() {
        let why = match &work.rows[i].value {
            Some(Err(e)) => Some(e),
            Some(Ok(t)) => t.time.as_ref().and_then(|c| c.as_ref().err()),
            None => None,
        };
        if let Some(e) = why {
            match reasons.iter_mut().find(|(_, r)| *r == e.as_str()) {
                Some((kinds, _)) => kinds.push(kind.label()),
                None => reasons.push((vec![kind.label()], e.as_str())),
            }
        }
    }
    for (kinds, e) in reasons {
        ui.label(egui::RichText::new(format!("{}: {e}", kinds.join(", "))).color(BAD));
    }
}

/// The real-time table: one row per update of the G06.2 curve.
pub fn realtime_table(ui: &mut egui::Ui, work: &Work, wanted: Option<&Wanted>) {
    let fresh = wanted.is_some_and(|w| work.realtime_fresh(w));
    if wanted.is_some_and(|w| work.row_fresh(2, w)) && work.row(2).is_none() {
        ui.label(
            egui::RichText::new("No real-time interpolation: there is no G06.2 program at these settings.")
                .color(STALE),
        );
        return;
    }
    let Some(rt) = work.realtime.ok() else {
        let text = match &work.realtime.value {
            Some(Err(e)) => e.clone(),
            _ => "real-time interpolation: computing…".to_owned(),
        };
        ui.label(egui::RichText::new(text).color(STALE).italics());
        return;
    };
    let chosen = rt.run.stats.update;
    egui::Grid::new("nurbs-realtime").num_columns(6).striped(true).spacing([10.0, 3.0]).show(ui, |ui| {
        for (h, tip) in [
            ("G06.2 update", "How the curve parameter advances each period (first / second order Taylor, or second order corrected by a Newton step on the chord length)"),
            ("periods", "Interpolation periods to run the curve"),
            ("max |Δf/f|", "Largest relative feed fluctuation of a period (the last, shortened period left out)"),
            ("RMS |Δf/f|", "RMS relative feed fluctuation"),
            ("max chord error", "Largest distance between the curve and the straight step of a period"),
            ("feed-limited", "Periods whose feed the chord tolerance lowered"),
        ] {
            ui.label(egui::RichText::new(h).strong()).on_hover_text(tip);
        }
        ui.end_row();
        for s in &rt.stats {
            let color = if fresh { ui.visuals().text_color() } else { STALE };
            let t = |s: String| egui::RichText::new(s).color(color);
            let name = if s.update == chosen { format!("{} (plotted)", s.update.as_str()) } else { s.update.as_str().to_owned() };
            ui.label(t(name).strong());
            ui.label(t(s.periods.to_string()));
            ui.horizontal(|ui| {
                let (rect, _) = ui.allocate_exact_size(egui::vec2(9.0, 9.0), egui::Sense::hover());
                ui.painter().circle_filled(rect.center(), 4.0, turbo(fluct_t(s.max_fluctuation)));
                ui.label(t(format!("{:.2e}", s.max_fluctuation)));
            });
            ui.label(t(format!("{:.2e}", s.rms_fluctuation)));
            ui.label(t(um(s.max_chord_error_mm)));
            ui.label(t(s.limited_periods.to_string()));
            ui.end_row();
        }
    });
}

/// Which program the G-code view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shown {
    /// A written program.
    Kind(ProgramKind),
    /// The loaded file.
    Loaded,
}

/// The text with line numbers, one row per line (only visible rows are laid out), the
/// line `mark` highlighted; scrolls to `scroll_to` when given.
pub fn code_view(ui: &mut egui::Ui, text: &str, mark: Option<usize>, scroll_to: Option<usize>) {
    let lines: Vec<&str> = text.lines().collect();
    let font = egui::TextStyle::Monospace.resolve(ui.style());
    let row_h = ui.fonts_mut(|f| f.row_height(&font));
    let digits = lines.len().max(1).to_string().len();
    let mut area = egui::ScrollArea::both().id_salt("nurbs-gcode").auto_shrink([false, false]);
    if let Some(l) = scroll_to {
        let y = (row_h + ui.spacing().item_spacing.y) * (l.saturating_sub(6)) as f32;
        area = area.vertical_scroll_offset(y);
    }
    egui::Frame::new().fill(egui::Color32::from_rgb(16, 18, 22)).inner_margin(4.0).corner_radius(3.0).show(ui, |ui| {
        area.show_rows(ui, row_h, lines.len(), |ui, range| {
            for i in range {
                let n = i + 1;
                let marked = mark == Some(n);
                let row = egui::RichText::new(format!("{n:>digits$}  "))
                    .font(font.clone())
                    .color(egui::Color32::from_gray(95));
                let body = egui::RichText::new(lines[i]).font(font.clone()).color(if lines[i].starts_with('(') {
                    egui::Color32::from_gray(135)
                } else if marked {
                    egui::Color32::WHITE
                } else {
                    egui::Color32::from_gray(215)
                });
                // The highlight goes under the text: reserve its shape first.
                let under = ui.painter().add(egui::Shape::Noop);
                let r = ui.horizontal(|ui| {
                    ui.spacing_mut().item_spacing.x = 0.0;
                    ui.label(row);
                    ui.add(egui::Label::new(body).extend());
                });
                if marked {
                    ui.painter().set(
                        under,
                        egui::Shape::rect_filled(
                            r.response.rect.expand2(egui::vec2(2.0, 0.0)),
                            2.0,
                            egui::Color32::from_rgb(110, 30, 28),
                        ),
                    );
                }
            }
        });
    });
}

#[cfg(test)]
mod tests {
    #[test]
    fn significant_digits_keep_their_zeros() {
        use super::significant;
        assert_eq!(significant(9.980_487, 4), "9.980");
        assert_eq!(significant(14.008_67, 4), "14.01");
        assert_eq!(significant(1486.37, 4), "1486");
        assert_eq!(significant(0.012_345, 4), "0.01235");
        assert_eq!(significant(f64::NAN, 4), "—");
    }
}
