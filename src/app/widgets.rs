//! Widgets and colours several panels share: the surfaces' colours, a collapsing section, a
//! logarithmic tolerance slider, the red frame around a message, and the widget rectangles
//! a panel publishes in the status element. One copy each, so every tab looks and answers
//! the same way.

use std::ops::RangeInclusive;

use eframe::egui;

/// Display colours of the scene's surfaces S1 and S2 (controls, 3D views, legends, plots).
pub const SURFACE_COLORS: [egui::Color32; 2] =
    [egui::Color32::from_rgb(105, 155, 230), egui::Color32::from_rgb(236, 160, 72)];

/// Colour of text telling a problem (a failed run, a value over its tolerance).
pub const PROBLEM_TEXT: egui::Color32 = egui::Color32::from_rgb(255, 120, 110);

/// A section of the side panel with a strong title, open at first if `open`.
pub fn section(ui: &mut egui::Ui, title: &str, open: bool, add: impl FnOnce(&mut egui::Ui)) {
    egui::CollapsingHeader::new(egui::RichText::new(title).strong()).default_open(open).show(ui, add);
}

/// A message in a dark red frame (white text), e.g. an input that was not applied.
pub fn error_frame(ui: &mut egui::Ui, add: impl FnOnce(&mut egui::Ui)) {
    egui::Frame::new().fill(egui::Color32::from_rgb(80, 24, 24)).inner_margin(6.0).corner_radius(4.0).show(ui, add);
}

/// [`error_frame`] holding one line of text.
pub fn error_text(ui: &mut egui::Ui, text: impl Into<String>) {
    error_frame(ui, |ui| {
        ui.colored_label(egui::Color32::WHITE, text.into());
    });
}

/// A logarithmic tolerance slider in mm (`label`, four decimals) over `range`: a finite
/// value the user sets is clamped into the range and written to `tol_mm`. Returns the
/// slider's response (its rectangle is published by the panels).
pub fn tolerance_slider(
    ui: &mut egui::Ui,
    tol_mm: &mut f64,
    range: RangeInclusive<f64>,
    label: &str,
) -> egui::Response {
    let mut tol = *tol_mm;
    let r = ui.add(
        egui::Slider::new(&mut tol, range.clone())
            .logarithmic(true)
            .text(label)
            .suffix(" mm")
            .custom_formatter(|v, _| format!("{v:.4}"))
            .clamping(egui::SliderClamping::Always),
    );
    if r.changed() && tol.is_finite() {
        *tol_mm = tol.clamp(*range.start(), *range.end());
    }
    r
}

/// Clamps a tolerance given by name (automation, `set_option`) into a slider's range, or says
/// why it is not a tolerance.
pub fn tolerance_option(key: &str, value: &str, range: &RangeInclusive<f64>) -> Result<f64, String> {
    let t = value.parse::<f64>().map_err(|_| format!("{key}: \"{value}\" is not a number"))?;
    if !(t > 0.0 && t.is_finite()) {
        return Err(format!("{key}: {t} is not a positive length"));
    }
    Ok(t.clamp(*range.start(), *range.end()))
}

/// Widget rectangles as `{name: [x, y, w, h]}` (points) for the status element.
pub fn rects_json(rects: &[(&'static str, egui::Rect)]) -> serde_json::Value {
    rects.iter().map(|(k, r)| ((*k).to_owned(), serde_json::json!([r.min.x, r.min.y, r.width(), r.height()]))).collect()
}

/// Text in the top-right corner of a view: what it shows or why it cannot (in
/// [`PROBLEM_TEXT`] when `ok` is false).
pub fn view_status(painter: &egui::Painter, rect: egui::Rect, ok: bool, text: String, font: egui::FontId) {
    painter.text(
        egui::pos2(rect.right() - 10.0, rect.top() + 10.0),
        egui::Align2::RIGHT_TOP,
        text,
        font,
        if ok { egui::Color32::from_gray(212) } else { PROBLEM_TEXT },
    );
}

/// One line of a view's legend: a colour swatch and its text at `(x, *y)`; moves `y` down.
pub fn legend_entry(painter: &egui::Painter, x: f32, y: &mut f32, color: egui::Color32, text: String) {
    let font = egui::FontId::proportional(13.0);
    painter.rect_filled(egui::Rect::from_min_size(egui::pos2(x, *y + 3.0), egui::vec2(12.0, 10.0)), 2.0, color);
    painter.text(egui::pos2(x + 18.0, *y), egui::Align2::LEFT_TOP, text, font, egui::Color32::from_gray(225));
    *y += 18.0;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tolerance_by_name_is_clamped_into_the_slider_or_refused() {
        let range = 0.001..=1.0;
        assert_eq!(tolerance_option("tol_mm", "0.05", &range), Ok(0.05));
        assert_eq!(tolerance_option("tol_mm", "5", &range), Ok(1.0));
        assert_eq!(tolerance_option("tol_mm", "1e-9", &range), Ok(0.001));
        for bad in ["0", "-1", "NaN", "inf"] {
            let e = tolerance_option("tol_mm", bad, &range).expect_err(bad);
            assert!(e.contains("positive length"), "{bad}: {e}");
        }
        assert!(tolerance_option("tol_mm", "abc", &range).is_err_and(|e| e.contains("not a number")));
    }
}
