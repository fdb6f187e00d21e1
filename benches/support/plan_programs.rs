//! The feed planner's benchmark program, shared by `benches/plan.rs` (criterion, native) and
//! `benches/native_and_wasm/plan.rs` (the same source natively and as wasm32 under Node), so
//! both plan the same blocks.
#![allow(dead_code)]

use glam::DVec3;
use interpolab::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use interpolab::plan::Dynamics;

/// `n` G01 blocks of about 0.5 mm along r = 40 + 5 sin(7θ) in XY, z rising 0.02 mm a turn.
#[must_use]
pub fn wavy_spiral(n: usize) -> Vec<Canon> {
    let feed = Feed { mode: FeedMode::PerMinute, rate: 3000.0, spindle_rpm: 10_000.0 };
    let mut out = Vec::with_capacity(n + 1);
    out.push(Canon::Traverse {
        loc: Loc::main(1),
        end: Pose::at(DVec3::new(40.0, 0.0, 0.0)),
        origin: Origin::Programmed,
    });
    let mut th: f64 = 0.0;
    for k in 0..n {
        th += 0.5 / 40.0;
        let r = 40.0 + 5.0 * (7.0 * th).sin();
        let p = DVec3::new(r * th.cos(), r * th.sin(), 0.02 * th / std::f64::consts::TAU);
        out.push(Canon::Line { loc: Loc::main(k as u32 + 2), end: Pose::at(p), feed, origin: Origin::Programmed });
    }
    out
}

/// The machines the program is planned on: the VMC with and without its jerk limits, and the
/// hobby router with a look-ahead window of 50 blocks.
#[must_use]
pub fn machines() -> Vec<(&'static str, Dynamics)> {
    let mut out = Vec::new();
    for (name, m) in [
        ("vmc_jerk_limited", Dynamics::preset("vmc")),
        ("vmc_jerk_free", Dynamics::preset("vmc").map(Dynamics::without_jerk)),
        (
            "hobby_router_window_50",
            Dynamics::preset("hobby-router").map(|mut d| {
                d.window_blocks = Some(50);
                d
            }),
        ),
    ] {
        if let Some(m) = m {
            out.push((name, m));
        }
    }
    out
}
