//! Unit conversions, written once.
//!
//! Inside the core, lengths are mm, times seconds, speeds mm/s and angles radians. The scene
//! file, the command line and the app speak mm/min and ms (the papers' and the controllers'
//! units) and degrees; these functions are the one place that turns the one into the other,
//! and they are called only at those edges (`scene`, `cli`, `app`, `report`).
//!
//! A number printed in a file unit is computed from the file's own numbers, not converted
//! back from the core's: a round trip through f64 is not the identity (of the periods
//! 0.001, 0.002, …, 100 ms, 1 463 come back from `s_from_ms` then `ms_from_s` one ulp off,
//! and a time k·Ts does so for about one k in eight), and the output is a byte contract.
//! So the edge keeps the file's feed and period for what it prints, and the feed per period
//! f = F·Ts/60 000 is formed once from the file's numbers ([`mm_per_period`]).

/// Milliseconds in a minute: a feed in mm/min times a period in ms, divided by this, is mm.
pub const MS_PER_MIN: f64 = 60_000.0;

/// Milliseconds in a second.
pub const MS_PER_S: f64 = 1000.0;

/// Seconds in a minute.
pub const S_PER_MIN: f64 = 60.0;

/// Millimetres in a micrometre: a deviation band given in µm (command line, UI) times this is
/// mm.
pub const MM_PER_UM: f64 = 1e-3;

/// Distance travelled in one interpolation period (mm) at feed `feed_mm_per_min` (mm/min)
/// and period `period_ms` (ms): f = F·Ts / 60 000.
#[must_use]
pub fn mm_per_period(feed_mm_per_min: f64, period_ms: f64) -> f64 {
    feed_mm_per_min * period_ms / MS_PER_MIN
}

/// A time in ms (file, command line, UI) as seconds (core).
#[must_use]
pub fn s_from_ms(ms: f64) -> f64 {
    ms / MS_PER_S
}

/// A time in seconds (core) as ms (file, command line, UI).
#[must_use]
pub fn ms_from_s(s: f64) -> f64 {
    s * MS_PER_S
}

/// A feed in mm/min (file, G-code F word) as mm/s (core).
#[must_use]
pub fn mm_per_s_from_mm_per_min(mm_per_min: f64) -> f64 {
    mm_per_min / S_PER_MIN
}

/// A feed in mm/s (core) as mm/min (file, G-code F word).
#[must_use]
pub fn mm_per_min_from_mm_per_s(mm_per_s: f64) -> f64 {
    mm_per_s * S_PER_MIN
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feed_per_period_matches_hand_conversion() {
        // 6000 mm/min is 100 mm/s; in 1 ms that is 0.1 mm, in 4 ms 0.4 mm.
        assert!((mm_per_period(6000.0, 1.0) - 0.1).abs() < 1e-15);
        assert!((mm_per_period(6000.0, 4.0) - 0.4).abs() < 1e-15);
        // A minute-long period covers exactly the feed.
        assert!((mm_per_period(250.0, MS_PER_MIN) - 250.0).abs() < 1e-12);
    }

    #[test]
    fn core_units_agree_with_the_file_units() {
        // 1500 mm/min is 25 mm/s; 4 ms is 0.004 s; f = 25 mm/s · 0.004 s = 0.1 mm either way.
        assert_eq!(mm_per_s_from_mm_per_min(1500.0), 25.0);
        assert_eq!(mm_per_min_from_mm_per_s(25.0), 1500.0);
        assert!((s_from_ms(4.0) - 0.004).abs() < 1e-18);
        assert_eq!(ms_from_s(2.5), 2500.0);
        let f_core = mm_per_s_from_mm_per_min(1500.0) * s_from_ms(4.0);
        assert!((f_core - mm_per_period(1500.0, 4.0)).abs() < 1e-16);
    }

    #[test]
    fn a_round_trip_can_move_the_last_bit() {
        // Why the edge prints from the file's numbers: 0.123 ms through seconds and back is
        // not 0.123 in f64 (the module documentation's count).
        let back = ms_from_s(s_from_ms(0.123));
        assert!(back != 0.123 && (back - 0.123).abs() < 1e-16);
    }
}
