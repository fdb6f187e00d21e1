//! Unit conversions, written once. The scene file and the command line speak mm/min and ms
//! (the papers' and the controllers' units); these functions are the one place that turns
//! them into a distance per period.

/// Milliseconds in a minute: a feed in mm/min times a period in ms, divided by this, is mm.
pub const MS_PER_MIN: f64 = 60_000.0;

/// Distance travelled in one interpolation period (mm) at feed `feed_mm_per_min` (mm/min)
/// and period `period_ms` (ms): f = F·Ts / 60 000.
#[must_use]
pub fn mm_per_period(feed_mm_per_min: f64, period_ms: f64) -> f64 {
    feed_mm_per_min * period_ms / MS_PER_MIN
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
}
