//! A rough wall-clock look at the planner's speed on the benchmark program (ignored: speed is
//! measured by `cargo bench --bench plan`, never asserted). Run with
//! `cargo test --release --no-default-features --test plan_speed -- --ignored --nocapture`.

use glam::DVec3;
use interpolab::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use interpolab::plan::{Dynamics, time_program};

fn wavy_spiral(n: usize) -> Vec<Canon> {
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

#[test]
#[ignore = "a timing look, not a check"]
fn time_the_planner_on_100k_blocks() {
    let program = wavy_spiral(100_000);
    let only = std::env::var("PLAN_SPEED_MODE").unwrap_or_default();
    for (name, m) in
        [("jerk", Dynamics::preset("vmc").expect("p")), ("free", Dynamics::preset("vmc").expect("p").without_jerk())]
    {
        if !only.is_empty() && only != name {
            continue;
        }
        let reps: usize = std::env::var("PLAN_SPEED_REPS").ok().and_then(|r| r.parse().ok()).unwrap_or(3);
        for _ in 0..reps {
            let t0 = std::time::Instant::now();
            let path = interpolab::plan::path::build(
                program.iter().cloned(),
                &interpolab::plan::JunctionRules {
                    tol_mm: m.tolerance_mm,
                    exact_stop: false,
                    jerk_limited: name == "jerk",
                },
            )
            .expect("path");
            let t1 = t0.elapsed();
            let t = time_program(program.iter().cloned(), &m).expect("plans");
            eprintln!(
                "{name}: path {:.1} ms, whole {:.1} ms; {} pieces, {} phases, {:.3} s",
                t1.as_secs_f64() * 1e3,
                (t0.elapsed() - t1).as_secs_f64() * 1e3,
                path.pieces.len(),
                t.plan.phases.len(),
                t.total_s()
            );
        }
    }
}
