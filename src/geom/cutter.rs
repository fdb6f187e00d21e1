//! The milling cutter: a fillet-end (toroidal, "bull-nose") mill and its two limits, the
//! ball end mill (r = R) and the flat end mill (r = 0), with the shank and holder above it.
//!
//! Tool frame (all lengths mm): the *tool tip* T (the centre of the cutter's bottom face,
//! the point a CL file programs) at the origin, the unit *tool axis* a pointing from the tip
//! up into the spindle. In it the cutter is the solid of revolution whose half-profile, at
//! height z above the tip and radial distance ρ from the axis, is
//!
//! | part | profile |
//! |---|---|
//! | flat bottom | z = 0 for ρ ≤ R0, with R0 = R − r (the torus' centre-circle radius) |
//! | corner (torus) | (ρ − R0)² + (z − r)² = r², for R0 ≤ ρ ≤ R and z ≤ r |
//! | flank | ρ = R for r ≤ z ≤ flute length |
//! | shank | ρ = shank radius, from the flute length up to the holder |
//! | holder | ρ = holder radius, from the gauge length up by the holder length |
//!
//! A ball end mill has R0 = 0 (no flat bottom), a flat end mill r = 0 (no corner). The
//! *cutting edge* is the bottom, corner and flank (height ≤ flute length); the shank and
//! holder must never touch the part (the global interference check).
//!
//! A *tapered* cutter (V cutter, engraver, chamfer mill, drill point, CAMotics' snub-nose
//! tool) has a cone instead of the corner: a flat of radius r_t at the tip (0 for a sharp
//! point), then the cone of half angle α (half the included tip angle) up to the radius R,
//! reached at the cone height h_c = (R − r_t)·cot α, then the flank:
//!
//! | part | profile |
//! |---|---|
//! | flat tip | z = 0 for ρ ≤ r_t |
//! | cone | z = (ρ − r_t)·cot α, for r_t ≤ ρ ≤ R |
//! | flank | ρ = R for h_c ≤ z ≤ flute length |

use thiserror::Error;

/// Default flute length per unit of the cutter radius R (a cutter built without lengths).
pub const DEFAULT_FLUTE_PER_R: f64 = 3.0;
/// Default shank length above the flutes per unit of R (its radius: R).
pub const DEFAULT_SHANK_PER_R: f64 = 3.0;
/// Default holder radius per unit of R.
pub const DEFAULT_HOLDER_RADIUS_PER_R: f64 = 2.5;
/// Default holder length per unit of R.
pub const DEFAULT_HOLDER_LENGTH_PER_R: f64 = 6.0;

/// A length (mm) rounded to the micrometre for a message.
fn round_um(mm: f64) -> f64 {
    (mm * 1e3).round() / 1e3
}

/// The three shapes the cutter can take, by its corner radius.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutterKind {
    /// r = R: a ball end mill.
    Ball,
    /// 0 < r < R: a fillet-end (toroidal) mill.
    Fillet,
    /// r = 0: a flat end mill.
    Flat,
    /// A conical tip ([`Taper`]): V cutter, engraver, drill.
    Tapered,
}

impl CutterKind {
    /// Lower-case name, as in files and on the command line (`ball`, `fillet`, `flat`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ball => "ball",
            Self::Fillet => "fillet",
            Self::Flat => "flat",
            Self::Tapered => "tapered",
        }
    }
}

/// Why a cutter's dimensions were refused. Each message names the dimension and what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CutterError {
    /// A dimension that must be a positive finite length is not.
    #[error("cutter {name} must be a positive length in mm, got {value}; give a value above 0")]
    NotPositive {
        /// Which dimension.
        name: &'static str,
        /// What was given (mm).
        value: f64,
    },
    /// The corner radius is negative or larger than the cutter radius.
    #[error(
        "cutter corner radius r = {corner_mm} mm must lie in [0, R] with R = {radius_mm} mm (r = R is a ball end mill, r = 0 a flat end mill)"
    )]
    Corner {
        /// r (mm).
        corner_mm: f64,
        /// R (mm).
        radius_mm: f64,
    },
    /// The flutes are shorter than the corner: the cutting edge would not reach the flank.
    #[error(
        "cutter flute length {flute_mm} mm is shorter than the corner radius r = {corner_mm} mm; give a flute length of at least r"
    )]
    ShortFlute {
        /// Flute length (mm).
        flute_mm: f64,
        /// r (mm).
        corner_mm: f64,
    },
    /// A tapered cutter's tip angle is outside (0°, 180°).
    #[error(
        "cutter tip angle {angle_deg}° must lie between 0° and 180° (the included angle, e.g. 90 for a V cutter, 118 for a drill)"
    )]
    TipAngle {
        /// The included angle given (degrees).
        angle_deg: f64,
    },
    /// A tapered cutter's flat tip is negative or not smaller than R.
    #[error("cutter flat tip radius {tip_mm} mm must lie in [0, R) with R = {radius_mm} mm (0 is a sharp point)")]
    TipFlat {
        /// r_t (mm).
        tip_mm: f64,
        /// R (mm).
        radius_mm: f64,
    },
}

/// The conical tip of a tapered cutter (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Taper {
    /// Half the included tip angle, α (rad), 0 < α < π/2: a 90° V cutter has π/4, a 118°
    /// drill 59°.
    pub half_angle_rad: f64,
    /// Radius of the flat at the tip, r_t (mm), 0 ≤ r_t < R: 0 for a sharp point.
    pub tip_radius_mm: f64,
}

/// A fillet-end mill with its shank and holder. All lengths mm; see the module docs for the
/// tool frame. Build it with [`Cutter::try_new`] (or [`Cutter::ball`], [`Cutter::flat`],
/// [`Cutter::fillet`] with default shank and holder) so its dimensions are consistent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    /// Cutter radius R (mm): half the cutting diameter.
    pub radius_mm: f64,
    /// Corner radius r (mm), 0 ≤ r ≤ R.
    pub corner_radius_mm: f64,
    /// Length of the cutting edge along the axis, from the tip (mm).
    pub flute_length_mm: f64,
    /// Radius of the shank above the flutes (mm); usually R or a little less.
    pub shank_radius_mm: f64,
    /// Gauge length: from the tip to the holder's face (mm), ≥ the flute length.
    pub gauge_length_mm: f64,
    /// Radius of the tool holder (mm).
    pub holder_radius_mm: f64,
    /// Length of the tool holder along the axis (mm).
    pub holder_length_mm: f64,
    /// A conical tip instead of the corner (then `corner_radius_mm` is 0); `None` for the
    /// ball, fillet and flat end mills.
    pub taper: Option<Taper>,
    /// Whether the end cuts at its centre (it can plunge); an end mill whose teeth stop short
    /// of the axis cannot, and a plunge with it is a crash of the simulation.
    pub centre_cutting: bool,
    /// Whether the body's lengths (flutes, shank, holder) were given by the user's source;
    /// false: they are the defaults of [`Cutter::fillet`], and a report says so.
    pub body_given: bool,
}

/// The body lengths a tool's source gives (mm), each optional: the flute length, the
/// shank's radius and length, the holder's radius and length, and whether the end cuts at
/// its centre. Written as words `flute=25`, `shank=3:40` (radius:length), `holder=16:60`,
/// `nocentre` (or `centre=no`) — on the command line after a cutter or tool spec, in a
/// LinuxCNC table's remark — see [`BodySpec::word`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodySpec {
    /// Flute (cutting) length from the tip (mm).
    pub flute_mm: Option<f64>,
    /// Shank radius and length above the flutes (mm).
    pub shank_mm: Option<(f64, f64)>,
    /// Holder radius and length above the shank (mm).
    pub holder_mm: Option<(f64, f64)>,
    /// Whether the end cuts at its centre.
    pub centre_cutting: Option<bool>,
}

/// Most characters of a body word echoed in a message.
const ECHO_CHARS: usize = 40;

impl BodySpec {
    /// Whether nothing is given.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Reads one word (`flute=25`, `shank=3:40`, `holder=16:60`, `nocentre`, `centre=no|yes`;
    /// keys in any case, lengths times `scale` to mm). `Ok(false)`: not a body word (the
    /// caller decides); `Err`: a body word with a bad value, what to write instead.
    ///
    /// # Errors
    /// A key this reader knows with a value that is not a positive length (or pair of them).
    pub fn word(&mut self, word: &str, scale: f64) -> Result<bool, String> {
        let lower = word.trim().to_ascii_lowercase();
        let echo: String = word.chars().take(ECHO_CHARS).collect();
        if matches!(lower.as_str(), "nocentre" | "nocenter" | "centre=no" | "center=no") {
            self.centre_cutting = Some(false);
            return Ok(true);
        }
        if matches!(lower.as_str(), "centre" | "center" | "centre=yes" | "center=yes") {
            self.centre_cutting = Some(true);
            return Ok(true);
        }
        let Some((key, value)) = lower.split_once('=') else {
            return Ok(false);
        };
        let length = |t: &str| t.trim().parse::<f64>().ok().filter(|v| *v > 0.0 && v.is_finite()).map(|v| v * scale);
        let pair = |t: &str| {
            let (a, b) = t.split_once(':')?;
            Some((length(a)?, length(b)?))
        };
        match key.trim() {
            "flute" | "flutes" => {
                self.flute_mm = Some(
                    length(value).ok_or_else(|| format!("'{echo}': give the flute length above 0, e.g. flute=25"))?,
                );
            }
            "shank" => {
                self.shank_mm =
                    Some(pair(value).ok_or_else(|| {
                        format!("'{echo}': give the shank as radius:length above 0, e.g. shank=3:40")
                    })?);
            }
            "holder" => {
                self.holder_mm =
                    Some(pair(value).ok_or_else(|| {
                        format!("'{echo}': give the holder as radius:length above 0, e.g. holder=16:60")
                    })?);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// The words [`Self::word`] reads back to this spec (lengths in mm), joined by `sep`;
    /// empty when nothing is given.
    #[must_use]
    pub fn words(&self, sep: &str) -> String {
        let mut w = Vec::new();
        if let Some(f) = self.flute_mm {
            w.push(format!("flute={f}"));
        }
        if let Some((r, l)) = self.shank_mm {
            w.push(format!("shank={r}:{l}"));
        }
        if let Some((r, l)) = self.holder_mm {
            w.push(format!("holder={r}:{l}"));
        }
        if self.centre_cutting == Some(false) {
            w.push("nocentre".to_owned());
        }
        w.join(sep)
    }
}

impl Cutter {
    /// A cutter of radius R and corner radius r with default proportions: flutes 3·R long,
    /// shank radius R, gauge length 6·R, holder radius 2.5·R and length 6·R
    /// ([`DEFAULT_FLUTE_PER_R`] and the others); its [`Cutter::body_given`] is false.
    ///
    /// # Errors
    /// When R is not a positive length or r lies outside [0, R].
    pub fn fillet(radius_mm: f64, corner_radius_mm: f64) -> Result<Self, CutterError> {
        let r = radius_mm;
        let mut c = Self::try_new(
            radius_mm,
            corner_radius_mm,
            DEFAULT_FLUTE_PER_R * r,
            r,
            (DEFAULT_FLUTE_PER_R + DEFAULT_SHANK_PER_R) * r,
            DEFAULT_HOLDER_RADIUS_PER_R * r,
            DEFAULT_HOLDER_LENGTH_PER_R * r,
        )?;
        c.body_given = false;
        Ok(c)
    }

    /// The same cutter with the body lengths `body` gives (the others kept): the flutes
    /// raised to at least the corner radius and the cone, a shank not given keeps its radius
    /// and is [`DEFAULT_SHANK_PER_R`]·R long above the flutes, a holder not given keeps its
    /// size. [`Cutter::body_given`] is set when `body` gives any length.
    ///
    /// # Errors
    /// A length that is not positive (the spec's reader refuses those first).
    pub fn with_body(&self, body: &BodySpec) -> Result<Self, CutterError> {
        let flute = body.flute_mm.unwrap_or(self.flute_length_mm).max(self.corner_radius_mm).max(self.cone_height_mm());
        let (shank_r, shank_l) = body.shank_mm.unwrap_or((
            self.shank_radius_mm,
            if body.flute_mm.is_some() {
                DEFAULT_SHANK_PER_R * self.radius_mm
            } else {
                (self.gauge_length_mm - self.flute_length_mm).max(0.0)
            },
        ));
        let (holder_r, holder_l) = body.holder_mm.unwrap_or((self.holder_radius_mm, self.holder_length_mm));
        let mut c =
            Self::try_new(self.radius_mm, self.corner_radius_mm, flute, shank_r, flute + shank_l, holder_r, holder_l)?;
        c.taper = self.taper;
        c.centre_cutting = body.centre_cutting.unwrap_or(self.centre_cutting);
        c.body_given =
            self.body_given || body.flute_mm.is_some() || body.shank_mm.is_some() || body.holder_mm.is_some();
        Ok(c)
    }

    /// The body as a line with units, e.g. `flutes 25 mm, shank R 3 × 15 mm, holder R 16 ×
    /// 60 mm`, with `(assumed: …)` when the source gave no lengths and `, no centre cutting`.
    #[must_use]
    pub fn describe_body(&self) -> String {
        let shank = (self.gauge_length_mm - self.flute_length_mm).max(0.0);
        let mut s = format!(
            "flutes {} mm, shank R {} × {} mm, holder R {} × {} mm",
            round_um(self.flute_length_mm),
            round_um(self.shank_radius_mm),
            round_um(shank),
            round_um(self.holder_radius_mm),
            round_um(self.holder_length_mm)
        );
        if !self.centre_cutting {
            s.push_str(", no centre cutting");
        }
        if !self.body_given {
            s.push_str(" (assumed: flutes 3·R, shank R × 3·R, holder 2.5·R × 6·R; give flute=, shank=, holder=)");
        }
        s
    }

    /// The cutter as numbers for a message between threads: R, r, flute length, shank
    /// radius, gauge length, holder radius, holder length, taper half angle (rad, 0 for
    /// none), tip flat, centre cutting (1/0), body given (1/0). [`Cutter::from_numbers`]
    /// reads them back.
    #[must_use]
    pub fn numbers(&self) -> [f64; 11] {
        let taper = self.taper.map_or([0.0, 0.0], |t| [t.half_angle_rad, t.tip_radius_mm]);
        [
            self.radius_mm,
            self.corner_radius_mm,
            self.flute_length_mm,
            self.shank_radius_mm,
            self.gauge_length_mm,
            self.holder_radius_mm,
            self.holder_length_mm,
            taper[0],
            taper[1],
            f64::from(u8::from(self.centre_cutting)),
            f64::from(u8::from(self.body_given)),
        ]
    }

    /// A cutter from [`Cutter::numbers`] (seven numbers: no taper, centre cutting, body
    /// given; nine: with the taper).
    ///
    /// # Errors
    /// Another count of numbers, or dimensions [`Cutter::try_new`] refuses.
    pub fn from_numbers(v: &[f64]) -> Result<Self, String> {
        if !matches!(v.len(), 7 | 9 | 11) {
            return Err(format!("the cutter: {} numbers, expected 7, 9 or 11", v.len()));
        }
        let mut c = Self::try_new(v[0], v[1], v[2], v[3], v[4], v[5], v[6]).map_err(|e| e.to_string())?;
        if let (Some(&half), Some(&tip)) = (v.get(7), v.get(8))
            && half > 0.0
        {
            c.taper = Some(Taper { half_angle_rad: half, tip_radius_mm: tip });
        }
        if let (Some(&centre), Some(&given)) = (v.get(9), v.get(10)) {
            c.centre_cutting = centre != 0.0;
            c.body_given = given != 0.0;
        }
        Ok(c)
    }

    /// A ball end mill of radius R (r = R), default proportions as [`Cutter::fillet`].
    ///
    /// # Errors
    /// When R is not a positive length.
    pub fn ball(radius_mm: f64) -> Result<Self, CutterError> {
        Self::fillet(radius_mm, radius_mm)
    }

    /// A flat end mill of radius R (r = 0), default proportions as [`Cutter::fillet`].
    ///
    /// # Errors
    /// When R is not a positive length.
    pub fn flat(radius_mm: f64) -> Result<Self, CutterError> {
        Self::fillet(radius_mm, 0.0)
    }

    /// A cutter with every dimension given (mm).
    ///
    /// # Errors
    /// The first dimension that is not a positive length, a corner radius outside [0, R],
    /// or flutes shorter than the corner. A gauge length shorter than the flutes is raised
    /// to the flute length (the holder starts where the flutes end).
    pub fn try_new(
        radius_mm: f64,
        corner_radius_mm: f64,
        flute_length_mm: f64,
        shank_radius_mm: f64,
        gauge_length_mm: f64,
        holder_radius_mm: f64,
        holder_length_mm: f64,
    ) -> Result<Self, CutterError> {
        for (name, value) in [
            ("radius R", radius_mm),
            ("flute length", flute_length_mm),
            ("shank radius", shank_radius_mm),
            ("gauge length", gauge_length_mm),
            ("holder radius", holder_radius_mm),
            ("holder length", holder_length_mm),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(CutterError::NotPositive { name, value });
            }
        }
        if !(corner_radius_mm >= 0.0 && corner_radius_mm <= radius_mm) {
            return Err(CutterError::Corner { corner_mm: corner_radius_mm, radius_mm });
        }
        if flute_length_mm < corner_radius_mm {
            return Err(CutterError::ShortFlute { flute_mm: flute_length_mm, corner_mm: corner_radius_mm });
        }
        Ok(Self {
            radius_mm,
            corner_radius_mm,
            flute_length_mm,
            shank_radius_mm,
            gauge_length_mm: gauge_length_mm.max(flute_length_mm),
            holder_radius_mm,
            holder_length_mm,
            taper: None,
            centre_cutting: true,
            body_given: true,
        })
    }

    /// A tapered cutter (V cutter, drill, snub nose) of radius R with an included tip angle
    /// (degrees, in (0, 180)) and a flat of radius `tip_radius_mm` at the tip (0: a sharp
    /// point), default proportions as [`Cutter::fillet`] with the flutes and the gauge length
    /// raised to at least the cone height h_c = (R − r_t)·cot α.
    ///
    /// # Errors
    /// When R is not a positive length, the angle lies outside (0°, 180°) or the flat is
    /// negative or not smaller than R.
    pub fn tapered(radius_mm: f64, tip_angle_deg: f64, tip_radius_mm: f64) -> Result<Self, CutterError> {
        let r = radius_mm;
        let base = Self::flat(r)?;
        if !(tip_angle_deg > 0.0 && tip_angle_deg < 180.0) {
            return Err(CutterError::TipAngle { angle_deg: tip_angle_deg });
        }
        if !(tip_radius_mm >= 0.0 && tip_radius_mm < r) {
            return Err(CutterError::TipFlat { tip_mm: tip_radius_mm, radius_mm: r });
        }
        let taper = Taper { half_angle_rad: 0.5 * tip_angle_deg.to_radians(), tip_radius_mm };
        let h = (r - tip_radius_mm) / taper.half_angle_rad.tan();
        Ok(Self {
            flute_length_mm: base.flute_length_mm.max(h),
            gauge_length_mm: base.gauge_length_mm.max(h),
            taper: Some(taper),
            ..base
        })
    }

    /// The height of the cone of a tapered cutter above the tip (mm): (R − r_t)·cot α; 0 for
    /// the others.
    #[must_use]
    pub fn cone_height_mm(&self) -> f64 {
        self.taper.map_or(0.0, |t| (self.radius_mm - t.tip_radius_mm).max(0.0) / t.half_angle_rad.tan())
    }

    /// Ball, fillet or flat, by the corner radius. A corner radius within 1e-12 relative of
    /// R counts as a ball.
    #[must_use]
    pub fn kind(&self) -> CutterKind {
        if self.taper.is_some() {
            CutterKind::Tapered
        } else if self.corner_radius_mm <= 0.0 {
            CutterKind::Flat
        } else if self.corner_radius_mm >= self.radius_mm * (1.0 - crate::numerics::tolerance::CORNER_IS_RADIUS_REL) {
            CutterKind::Ball
        } else {
            CutterKind::Fillet
        }
    }

    /// R0 = R − r: radius of the circle the corner's centres lie on (mm); the flat bottom's
    /// radius. 0 for a ball end mill.
    #[must_use]
    pub fn torus_radius_mm(&self) -> f64 {
        (self.radius_mm - self.corner_radius_mm).max(0.0)
    }

    /// Height above the tip (mm) of the cutter's lower surface at radial distance `rho_mm`
    /// from the axis: 0 on the flat bottom, on the corner's torus below, `None` outside the
    /// cutter (ρ > R). This is the profile a 3-axis cutter presses into a height map.
    #[must_use]
    pub fn bottom_height_mm(&self, rho_mm: f64) -> Option<f64> {
        let rho = rho_mm.abs();
        if rho > self.radius_mm {
            return None;
        }
        if let Some(t) = self.taper {
            return Some((rho - t.tip_radius_mm).max(0.0) / t.half_angle_rad.tan());
        }
        let r0 = self.torus_radius_mm();
        if rho <= r0 {
            return Some(0.0);
        }
        let r = self.corner_radius_mm;
        let d = rho - r0;
        Some(r - (r * r - d * d).max(0.0).sqrt())
    }

    /// Radius of the cutter's solid (mm) at height `z_mm` above the tip: the corner's
    /// radius below r, R up to the flute length, the shank up to the gauge length, the
    /// holder above it; `None` below the tip or above the holder.
    #[must_use]
    pub fn radius_at_height_mm(&self, z_mm: f64) -> Option<f64> {
        let r = self.corner_radius_mm;
        if z_mm < 0.0 {
            return None;
        }
        if let Some(t) = self.taper
            && z_mm < self.cone_height_mm()
        {
            return Some(t.tip_radius_mm + z_mm * t.half_angle_rad.tan());
        }
        if z_mm < r {
            let dz = r - z_mm;
            return Some(self.torus_radius_mm() + (r * r - dz * dz).max(0.0).sqrt());
        }
        if z_mm <= self.flute_length_mm {
            return Some(self.radius_mm);
        }
        if z_mm <= self.gauge_length_mm {
            return Some(self.shank_radius_mm);
        }
        if z_mm <= self.gauge_length_mm + self.holder_length_mm {
            return Some(self.holder_radius_mm);
        }
        None
    }

    /// A one-line description with units, e.g. `fillet R 5 mm, r 1 mm`.
    #[must_use]
    pub fn describe(&self) -> String {
        match self.kind() {
            CutterKind::Ball => format!("ball R {} mm", self.radius_mm),
            CutterKind::Flat => format!("flat R {} mm", self.radius_mm),
            CutterKind::Fillet => format!("fillet R {} mm, r {} mm", self.radius_mm, self.corner_radius_mm),
            CutterKind::Tapered => {
                let t = self.taper.unwrap_or(Taper { half_angle_rad: 0.0, tip_radius_mm: 0.0 });
                // Rust prints an f64 as its shortest round-trip decimal (90 for 90.0).
                let angle = (2e6 * t.half_angle_rad.to_degrees()).round() / 1e6;
                if t.tip_radius_mm > 0.0 {
                    format!("tapered R {} mm, {angle}°, flat tip r {} mm", self.radius_mm, t.tip_radius_mm)
                } else {
                    format!("V R {} mm, {angle}°", self.radius_mm)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_is_continuous_and_meets_the_flank() {
        for (big_r, r) in [(5.0, 5.0), (5.0, 1.0), (5.0, 0.0), (3.0, 2.999)] {
            let c = Cutter::fillet(big_r, r).unwrap();
            // At ρ = R the bottom reaches height r, where the flank begins.
            let top = c.bottom_height_mm(big_r).unwrap();
            assert!((top - r).abs() < 1e-12, "{big_r} {r}: {top}");
            // The two profile functions are inverses on the corner.
            for i in 1..50 {
                let z = r * f64::from(i) / 50.0;
                let rho = c.radius_at_height_mm(z).unwrap();
                let back = c.bottom_height_mm(rho).unwrap();
                assert!((back - z).abs() < 1e-9, "{big_r} {r}: z {z} → ρ {rho} → {back}");
            }
            assert_eq!(c.bottom_height_mm(big_r + 1e-9), None);
        }
    }

    #[test]
    fn kinds_and_refusals() {
        assert_eq!(Cutter::ball(5.0).unwrap().kind(), CutterKind::Ball);
        assert_eq!(Cutter::flat(5.0).unwrap().kind(), CutterKind::Flat);
        assert_eq!(Cutter::fillet(5.0, 1.0).unwrap().kind(), CutterKind::Fillet);
        assert!(matches!(Cutter::fillet(5.0, 6.0), Err(CutterError::Corner { .. })));
        assert!(matches!(Cutter::fillet(f64::NAN, 1.0), Err(CutterError::NotPositive { .. })));
        assert!(matches!(Cutter::fillet(5.0, -1.0), Err(CutterError::Corner { .. })));
        let e = Cutter::try_new(5.0, 2.0, 1.0, 5.0, 30.0, 12.0, 30.0).unwrap_err();
        assert!(e.to_string().contains("flute length"), "{e}");
    }
}
