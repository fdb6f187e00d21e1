//! What every 3D view shares: the mouse and touch camera controls, the message without a
//! GPU, the overlays drawn over the image (axis triad, scale bar in mm), and the decimation
//! every long plotted series goes through.

use eframe::egui;
use glam::{Mat4, Vec3};

use crate::render::gpu::paint_callback;
use crate::render::{OrbitCamera, ViewCallback, ViewId};

/// Says in the view's rectangle that there is no GPU device to draw with.
pub fn no_gpu(painter: &egui::Painter, rect: egui::Rect) {
    painter.text(
        rect.center(),
        egui::Align2::CENTER_CENTER,
        "3D view unavailable: no GPU device (wgpu)",
        egui::FontId::proportional(16.0),
        egui::Color32::LIGHT_RED,
    );
}

/// Orbits with the primary button, pans with the secondary or middle button (or shift and
/// the primary) — the drags every 3D view answers the same way.
pub fn orbit_and_pan(camera: &mut OrbitCamera, ui: &egui::Ui, response: &egui::Response, rect: egui::Rect) {
    let shift = ui.input(|i| i.modifiers.shift);
    let delta = response.drag_delta();
    if response.dragged_by(egui::PointerButton::Primary) && !shift {
        camera.orbit(delta.x, delta.y);
    } else if response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && shift)
    {
        camera.pan(delta.x, delta.y, rect.height());
    }
}

/// The whole camera control of a view that zooms about its centre: drags
/// ([`orbit_and_pan`]), the wheel and pinching ([`zoom_factor`]), and a double click that
/// fits a sphere of `radius` (view units) about the origin.
pub fn camera_controls(
    camera: &mut OrbitCamera,
    ui: &egui::Ui,
    response: &egui::Response,
    rect: egui::Rect,
    radius: f32,
) {
    orbit_and_pan(camera, ui, response, rect);
    let factor = zoom_factor(ui, response);
    if (factor - 1.0).abs() > f32::EPSILON {
        camera.zoom(factor);
    }
    if response.double_clicked() {
        camera.fit(Vec3::ZERO, radius);
    }
}

/// The zoom asked for this frame by the wheel and by pinching, as a factor for
/// [`OrbitCamera::zoom`] (1 when the pointer is not over the view).
#[must_use]
pub fn zoom_factor(ui: &egui::Ui, response: &egui::Response) -> f32 {
    if !response.hovered() {
        return 1.0;
    }
    let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
    (scroll * 0.0025).exp() * zoom
}

/// Queues the GPU drawing of `view` into `rect` as `camera` sees it (`hide_back_faces`: hide
/// the material side of surfaces); returns the clip-from-world matrix it used.
pub fn paint_view(
    ui: &egui::Ui,
    rect: egui::Rect,
    camera: &OrbitCamera,
    view: ViewId,
    background: [f32; 4],
    hide_back_faces: bool,
) -> Mat4 {
    let ppp = ui.ctx().pixels_per_point();
    let size_px = [(rect.width() * ppp).round().max(1.0) as u32, (rect.height() * ppp).round().max(1.0) as u32];
    let clip = camera.clip_from_world(rect.width() / rect.height().max(1.0));
    ui.painter().add(paint_callback(
        rect,
        ViewCallback {
            view,
            clip_from_local: clip.to_cols_array_2d(),
            eye: camera.eye().to_array(),
            size_px,
            background,
            hide_back_faces,
        },
    ));
    clip
}

/// A button of [`view_buttons`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewButton {
    /// Default view angles, fitted.
    Reset,
    /// Frame the content.
    Fit,
}

/// The "reset" and "fit" buttons of a view, right-aligned in `at`; `fit_hint` says what
/// "fit" frames. Returns the one clicked.
pub fn view_buttons(ui: &mut egui::Ui, at: egui::Rect, fit_hint: &str) -> Option<ViewButton> {
    let mut child =
        ui.new_child(egui::UiBuilder::new().max_rect(at).layout(egui::Layout::right_to_left(egui::Align::Center)));
    let reset = child.small_button("reset").on_hover_text("Default view angles, fitted").clicked();
    let fit = child.small_button("fit").on_hover_text(fit_hint).clicked();
    if reset { Some(ViewButton::Reset) } else { fit.then_some(ViewButton::Fit) }
}

/// The world axes X (red), Y (green), Z (blue) as seen by `camera`, `length` points long,
/// from `origin` (usually near the view's bottom-left corner).
pub fn axis_triad(painter: &egui::Painter, origin: egui::Pos2, length: f32, camera: &OrbitCamera, font: &egui::FontId) {
    let eye = camera.eye();
    let forward = (camera.target - eye).normalize();
    let right = forward.cross(Vec3::Z).normalize_or_zero();
    let up = right.cross(forward);
    for (axis, name, color) in [
        (Vec3::X, "X", egui::Color32::from_rgb(235, 90, 80)),
        (Vec3::Y, "Y", egui::Color32::from_rgb(110, 210, 110)),
        (Vec3::Z, "Z", egui::Color32::from_rgb(100, 150, 255)),
    ] {
        let tip = origin + egui::vec2(axis.dot(right), -axis.dot(up)) * length;
        painter.line_segment([origin, tip], egui::Stroke::new(2.0, color));
        painter.text(tip + (tip - origin).normalized() * 8.0, egui::Align2::CENTER_CENTER, name, font.clone(), color);
    }
}

/// The length of the scale bar: the round value (1, 2 or 5 × 10ⁿ mm) that spans at least 60
/// points at `mm_per_point`.
#[must_use]
pub fn scale_bar_length_mm(mm_per_point: f64) -> f64 {
    let pow = 10f64.powf((100.0 * mm_per_point).log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * pow).find(|l| *l / mm_per_point >= 60.0).unwrap_or(10.0 * pow)
}

/// A scale bar ending at `end` (its right end), labelled in mm or µm.
pub fn scale_bar(painter: &egui::Painter, end: egui::Pos2, mm_per_point: f64, font: &egui::FontId) {
    let nice = scale_bar_length_mm(mm_per_point);
    let len_pt = (nice / mm_per_point) as f32;
    let start = end - egui::vec2(len_pt, 0.0);
    let white = egui::Color32::from_gray(220);
    painter.line_segment([start, end], egui::Stroke::new(2.0, white));
    for x in [start, end] {
        painter.line_segment([x - egui::vec2(0.0, 5.0), x + egui::vec2(0.0, 5.0)], egui::Stroke::new(2.0, white));
    }
    let label = if nice >= 1.0 { format!("{nice} mm") } else { format!("{} µm", nice * 1000.0) };
    painter.text(start + egui::vec2(len_pt / 2.0, -12.0), egui::Align2::CENTER_CENTER, label, font.clone(), white);
}

/// Reduces a long series to at most ~2·`buckets` points keeping each bucket's lowest and
/// highest value (in x order), so a plot keeps its envelope at any length.
#[must_use]
pub fn decimate(points: &[[f64; 2]], buckets: usize) -> Vec<[f64; 2]> {
    if points.len() <= 2 * buckets {
        return points.to_vec();
    }
    let per = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for chunk in points.chunks(per) {
        let (mut lo, mut hi) = (chunk[0], chunk[0]);
        for p in chunk {
            if p[1] < lo[1] {
                lo = *p;
            }
            if p[1] > hi[1] {
                hi = *p;
            }
        }
        if lo[0] <= hi[0] {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
    out
}

/// A colour-bar legend over a 3D view, its right edge `right_bottom.x`, its bottom
/// `right_bottom.y`: `title` above a bar of `width` points whose colour at a fraction t in
/// [0, 1] is `colour(t)` (RGB(A) in 0…1), and `labels` under it at their fractions. The dark
/// background grows to the title, so no text is clipped.
pub fn colour_bar(
    painter: &egui::Painter,
    right_bottom: egui::Pos2,
    width: f32,
    title: &str,
    labels: &[(f32, String)],
    colour: impl Fn(f64) -> [f32; 4],
    font: &egui::FontId,
) {
    let text = egui::Color32::from_gray(225);
    let galley = painter.layout_no_wrap(title.to_owned(), font.clone(), text);
    let full = width.max(galley.size().x);
    let left = right_bottom.x - 8.0 - full;
    let top = right_bottom.y - 30.0;
    let bg = egui::Rect::from_min_max(
        egui::pos2(left - 8.0, top - 22.0),
        egui::pos2(left + full + 8.0, right_bottom.y + 4.0),
    );
    painter.rect_filled(bg, 3.0, egui::Color32::from_black_alpha(170));
    let n = 48;
    for k in 0..n {
        let c = colour((f64::from(k) + 0.5) / f64::from(n));
        let r = egui::Rect::from_min_size(
            egui::pos2(left + k as f32 / n as f32 * width, top),
            egui::vec2(width / n as f32 + 0.5, 12.0),
        );
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0) as u8;
        painter.rect_filled(r, 0.0, egui::Color32::from_rgb(byte(c[0]), byte(c[1]), byte(c[2])));
    }
    for (at, s) in labels {
        let align = if *at <= 0.0 {
            egui::Align2::LEFT_TOP
        } else if *at >= 1.0 {
            egui::Align2::RIGHT_TOP
        } else {
            egui::Align2::CENTER_TOP
        };
        painter.text(egui::pos2(left + at * width, top + 14.0), align, s, font.clone(), text);
    }
    painter.galley(egui::pos2(left, top - 4.0 - galley.size().y), galley, text);
}

/// What every 3D view draws over its image and answers below it: the axis triad, the scale
/// bar in mm, and the fit / reset buttons (`fit_hint` on hover), which frame a sphere of
/// `radius` (view units) about the origin.
pub fn view_frame(ui: &mut egui::Ui, rect: egui::Rect, camera: &mut OrbitCamera, radius: f32, fit_hint: &str) {
    let painter = ui.painter_at(rect);
    let font = egui::FontId::proportional(13.0);
    axis_triad(&painter, rect.left_bottom() + egui::vec2(40.0, -40.0), 26.0, camera, &font);
    scale_bar(
        &painter,
        rect.right_bottom() + egui::vec2(-20.0, -22.0),
        f64::from(camera.mm_per_point(rect.height())),
        &font,
    );
    let buttons = egui::Rect::from_min_size(rect.right_top() + egui::vec2(-120.0, 6.0), egui::vec2(112.0, 20.0));
    fit_buttons(ui, buttons, camera, radius, fit_hint);
}

/// The [`view_buttons`] in `at` acting on `camera`: "reset" turns it back to its default
/// direction, and both frame a sphere of `radius` (view units) about the origin.
pub fn fit_buttons(ui: &mut egui::Ui, at: egui::Rect, camera: &mut OrbitCamera, radius: f32, fit_hint: &str) {
    if let Some(b) = view_buttons(ui, at, fit_hint) {
        if b == ViewButton::Reset {
            *camera = OrbitCamera::default();
        }
        camera.fit(Vec3::ZERO, radius);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bar_is_a_round_length_of_at_least_60_points() {
        for mm_per_point in [1e-4, 3.7e-3, 0.01, 0.05, 0.2, 1.0, 7.5, 40.0] {
            let len = scale_bar_length_mm(mm_per_point);
            let points = len / mm_per_point;
            assert!(points >= 60.0 - 1e-9, "{mm_per_point} mm/pt: bar {len} mm is {points} pt");
            // The next smaller round value would be under 60 points (the bar is the shortest).
            assert!(points < 60.0 * 2.5 + 1e-9, "{mm_per_point} mm/pt: bar {len} mm is {points} pt");
            let mantissa = len / 10f64.powf(len.log10().floor());
            assert!([1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9), "{len} mm is not 1, 2 or 5 × 10ⁿ");
        }
    }

    #[test]
    fn decimation_keeps_the_envelope_and_the_order() {
        let n = 10_000;
        let points: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let x = i as f64;
                [x, (x * 0.37).sin() + if i == 4321 { 5.0 } else { 0.0 } - if i == 777 { 3.0 } else { 0.0 }]
            })
            .collect();
        let out = decimate(&points, 100);
        assert!(out.len() <= 202, "{} points", out.len());
        assert!(out.windows(2).all(|w| w[0][0] <= w[1][0]), "x order lost");
        let max = out.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        let min = out.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        assert!(out.contains(&points[4321]) && (max - points[4321][1]).abs() < 1e-12, "spike lost");
        assert!(out.contains(&points[777]) && (min - points[777][1]).abs() < 1e-12, "dip lost");
        // Every output point is an input point.
        assert!(out.iter().all(|p| points[p[0] as usize] == *p));
        // Short series pass unchanged.
        assert_eq!(decimate(&points[..150], 100), points[..150].to_vec());
    }
}
