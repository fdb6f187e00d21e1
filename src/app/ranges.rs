//! The ranges of the app's sliders and number fields, one name each. The widgets read them
//! from here and `tests/app_headless.rs` pushes every slider to both ends of its range from
//! here, so a range changed in one place is tested as it is.

use std::ops::RangeInclusive;

/// Scene: feed F (mm/min, logarithmic).
pub const FEED_MM_PER_MIN: RangeInclusive<f64> = 10.0..=60_000.0;
/// Scene: interpolation period Ts (ms, logarithmic).
pub const PERIOD_MS: RangeInclusive<f64> = 0.1..=50.0;
/// Scene: ball radius R (mm, logarithmic).
pub const BALL_RADIUS_MM: RangeInclusive<f64> = 0.2..=25.0;
/// Scene: allowance C (mm; negative cuts into the surfaces).
pub const ALLOWANCE_MM: RangeInclusive<f64> = -1.0..=3.0;
/// Scene: the tolerances T1, T2 on the surfaces (mm, logarithmic).
pub const SURFACE_TOL_MM: RangeInclusive<f64> = 1e-5..=0.5;
/// Scene: the share b of the tolerance the interpolation may use (dimensionless).
pub const TOL_SHARE: RangeInclusive<f64> = 0.01..=1.0;
/// Scene: lengths typed into number fields (radii, mm), above the surface's own minimum.
pub const LENGTH_MAX_MM: f64 = 1.0e4;
/// Scene: max periods of a run.
pub const MAX_PERIODS: RangeInclusive<usize> = 1..=2_000_000;

/// Crease view: exaggeration of the centres' deviation from the exact crease (×).
pub const CREASE_MAGNIFY: RangeInclusive<f64> = 1.0..=1.0e6;
/// Crease view: playback speed (multiple of the machine's speed).
pub const PLAYBACK_SPEED: RangeInclusive<f64> = 0.05..=200.0;

/// 5-axis tab: the tolerance E (mm, logarithmic).
pub const FIVEAXIS_TOL_MM: RangeInclusive<f64> = 0.0005..=1.0;
/// 5-axis tab: exaggeration of the swept curves' distance from the chords (×).
pub const FIVEAXIS_MAGNIFY: RangeInclusive<f64> = 1.0..=10_000.0;

/// Chords tab: the tolerance d (mm, logarithmic).
pub const CHORDS_TOL_MM: RangeInclusive<f64> = 0.001..=1.0;
/// Chords tab: exaggeration of the chords' error in the geometry plot (×).
pub const CHORDS_MAGNIFY: RangeInclusive<f64> = 1.0..=100_000.0;
/// Chords tab: the curves' typed numbers (mm, mm², degrees), either sign.
pub const CHORDS_NUMBER_ABS_MAX: f64 = 1.0e5;

/// NURBS & G-code tab: the tolerance E of the programs (mm, logarithmic).
pub const NURBS_TOL_MM: RangeInclusive<f64> = 0.001..=0.5;
/// NURBS & G-code tab: the programs' feed (mm/min, logarithmic).
pub const NURBS_FEED_MM_PER_MIN: RangeInclusive<f64> = 60.0..=30_000.0;
/// NURBS & G-code tab: the real-time interpolation's chord-error limit δ (µm, logarithmic).
pub const NURBS_CHORD_TOL_UM: RangeInclusive<f64> = 0.001..=10.0;

pub use super::fillet_panel::{CORNER_RANGE_MM, RADIUS_RANGE_MM, SCALLOP_RANGE_UM, TOLERANCE_RANGE_MM};
pub use super::simulate_panel::PITCH_RANGE_MM;
