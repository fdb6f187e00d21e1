//! A/B side by side: the deviation maps of two runs of the same part (program A pinned, B
//! the current run), one pixel per ray with +y up, drawn with the same colour scale as the
//! 3D view (blue gouge ≤ −band, green 0, red stock left ≥ +band; grey by height where a
//! machined ray has no deviation, light grey where not machined) and one legend in µm, the
//! worst gouge of each marked by a ring.

use eframe::egui;

use super::view::deviation_color;
use super::work::Results;

/// Height (points) of the two maps at most.
const MAP_HEIGHT: f32 = 220.0;
/// Colour of unmachined rays (as the 3D view's).
const UNCUT: egui::Color32 = egui::Color32::from_rgb(158, 158, 153);

/// One ray of a map.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pixel {
    /// Not machined.
    Uncut,
    /// Machined, no deviation (no design there): grey by height, 0 (bottom) … 255 (top).
    Grey(u8),
    /// Signed deviation (mm).
    Deviation(f32),
}

/// A run's map, kept when the run is pinned as A (so A's picture survives the next run).
#[derive(Clone, Debug, PartialEq)]
pub struct MapImage {
    /// Rays along x.
    pub nx: usize,
    /// Rays along y.
    pub ny: usize,
    /// Stock rectangle `x0, y0, x1, y1` (mm) covered by the grid.
    pub extent_mm: [f64; 4],
    /// Worst gouge's (x, y) (mm), if any.
    pub gouge_mm: Option<[f64; 2]>,
    pixels: Vec<Pixel>,
}

impl MapImage {
    /// The map of a measured run on a stock spanning `z_range` (mm) in height.
    #[must_use]
    pub fn of(r: &Results, z_range: (f64, f64)) -> Self {
        let g = r.map.grid;
        let span = (z_range.1 - z_range.0).max(f64::MIN_POSITIVE);
        let pixels = (0..g.len())
            .map(|k| match (r.stats.deviation_mm.get(k).copied().flatten(), r.map.machined[k]) {
                (Some(d), _) => Pixel::Deviation(d as f32),
                (None, false) => Pixel::Uncut,
                (None, true) => Pixel::Grey(((r.map.top_mm[k] - z_range.0) / span * 255.0).clamp(0.0, 255.0) as u8),
            })
            .collect();
        Self {
            nx: g.nx,
            ny: g.ny,
            extent_mm: [g.x0_mm, g.y0_mm, g.x0_mm + g.nx as f64 * g.pitch_mm, g.y0_mm + g.ny as f64 * g.pitch_mm],
            gouge_mm: r.stats.worst_gouge.map(|(_, p)| [p.x, p.y]),
            pixels,
        }
    }

    /// Rays with a deviation.
    #[must_use]
    pub fn measured_rays(&self) -> usize {
        self.pixels.iter().filter(|p| matches!(p, Pixel::Deviation(_))).count()
    }

    /// The image at a band of `band_mm` (full colour), row 0 at the top (largest y).
    fn colours(&self, band_mm: f64) -> egui::ColorImage {
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        let mut px = Vec::with_capacity(self.nx * self.ny);
        for row in 0..self.ny {
            let j = self.ny - 1 - row;
            for i in 0..self.nx {
                px.push(match self.pixels[j * self.nx + i] {
                    Pixel::Uncut => UNCUT,
                    Pixel::Grey(v) => egui::Color32::from_gray(v),
                    Pixel::Deviation(d) => {
                        let c = deviation_color(f64::from(d), band_mm);
                        egui::Color32::from_rgb(byte(c[0]), byte(c[1]), byte(c[2]))
                    }
                });
            }
        }
        egui::ColorImage::new([self.nx, self.ny], px)
    }
}

/// The two maps' textures, rebuilt only when their map or the band changes.
#[derive(Default)]
pub struct MapTextures {
    slots: [Option<((u64, u64), egui::TextureHandle)>; 2],
}

impl MapTextures {
    fn texture(
        &mut self,
        ui: &egui::Ui,
        slot: usize,
        key: (u64, u64),
        map: &MapImage,
        band_mm: f64,
    ) -> egui::TextureId {
        let stale = self.slots[slot].as_ref().is_none_or(|(k, _)| *k != key);
        if stale {
            let name = if slot == 0 { "sim_map_a" } else { "sim_map_b" };
            let t = ui.ctx().load_texture(name, map.colours(band_mm), egui::TextureOptions::NEAREST);
            self.slots[slot] = Some((key, t));
        }
        self.slots[slot].as_ref().map_or(egui::TextureId::default(), |(_, t)| t.id())
    }
}

/// Draws A and B (B may be missing while it computes) side by side at the same scale in
/// mm, with one legend; returns the rectangles drawn (`sim_map_a`, `sim_map_b`). `keys`
/// identify each map's content (a new key rebuilds its texture).
pub fn draw_maps(
    ui: &mut egui::Ui,
    textures: &mut MapTextures,
    a: (&MapImage, u64),
    b: Option<(&MapImage, u64)>,
    band_um: f64,
) -> Vec<(&'static str, egui::Rect)> {
    let band_mm = band_um * crate::numerics::units::MM_PER_UM;
    let band_key = band_um.to_bits();
    let mut out = Vec::new();
    // One scale (points per mm) for both, so the same part looks the same size.
    let width_mm = |m: &MapImage| (m.extent_mm[2] - m.extent_mm[0]).max(f64::MIN_POSITIVE);
    let height_mm = |m: &MapImage| (m.extent_mm[3] - m.extent_mm[1]).max(f64::MIN_POSITIVE);
    let maps: Vec<&MapImage> = std::iter::once(a.0).chain(b.map(|b| b.0)).collect();
    let w_max = maps.iter().map(|m| width_mm(m)).fold(0.0, f64::max);
    let h_max = maps.iter().map(|m| height_mm(m)).fold(0.0, f64::max);
    let each = f64::from(((ui.available_width() - 24.0) / 2.0).max(60.0));
    let scale = (each / w_max).min(f64::from(MAP_HEIGHT) / h_max);
    ui.horizontal_top(|ui| {
        for (slot, (name, entry)) in [("sim_map_a", Some(a)), ("sim_map_b", b)].into_iter().enumerate() {
            ui.vertical(|ui| {
                ui.strong(if slot == 0 { "A (pinned)" } else { "B (current)" });
                let Some((map, key)) = entry else {
                    ui.label("computing…");
                    return;
                };
                let size = egui::vec2((width_mm(map) * scale) as f32, (height_mm(map) * scale) as f32);
                let id = textures.texture(ui, slot, (key, band_key), map, band_mm);
                let r = ui.add(egui::Image::new(egui::load::SizedTexture::new(id, size)));
                if let Some([x, y]) = map.gouge_mm {
                    let e = map.extent_mm;
                    let at = egui::pos2(
                        r.rect.left() + ((x - e[0]) * scale) as f32,
                        r.rect.bottom() - ((y - e[1]) * scale) as f32,
                    );
                    ui.painter_at(r.rect).circle_stroke(at, 6.0, egui::Stroke::new(2.0, egui::Color32::WHITE));
                }
                out.push((name, r.rect));
            });
        }
    });
    // The legend both maps share.
    let (rect, _) = ui.allocate_exact_size(egui::vec2(300.0, 34.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let n = 48;
    let bar = egui::Rect::from_min_size(rect.min, egui::vec2(rect.width(), 12.0));
    for k in 0..n {
        let t = (f64::from(k) + 0.5) / f64::from(n);
        let c = deviation_color(2.0 * t - 1.0, 1.0);
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0) as u8;
        let x0 = bar.left() + k as f32 / n as f32 * bar.width();
        painter.rect_filled(
            egui::Rect::from_min_size(egui::pos2(x0, bar.top()), egui::vec2(bar.width() / n as f32 + 0.5, 12.0)),
            0.0,
            egui::Color32::from_rgb(byte(c[0]), byte(c[1]), byte(c[2])),
        );
    }
    let font = egui::FontId::proportional(12.0);
    let text = ui.visuals().text_color();
    for (at, s, align) in [
        (0.0, format!("−{band_um} µm gouge"), egui::Align2::LEFT_TOP),
        (0.5, "0".to_owned(), egui::Align2::CENTER_TOP),
        (1.0, format!("+{band_um} µm left"), egui::Align2::RIGHT_TOP),
    ] {
        painter.text(egui::pos2(bar.left() + at * bar.width(), bar.bottom() + 2.0), align, s, font.clone(), text);
    }
    out.push(("sim_maps_legend", rect));
    out
}
