//! Anchors of the feed planner against an outside reference: Ruckig (Berscheid & Kröger,
//! "Jerk-limited Real-time Trajectory Generation with Arbitrary Target States", RSS 2021;
//! the `ruckig` crate builds its C++ library) computes the time-optimal jerk-limited
//! profile of one axis from rest to rest. A single straight move from rest to rest is that
//! problem along the line, with the line's limits (the least over the joints of the joint's
//! limit over its share of the direction): our duration must equal Ruckig's to 1e-9 s.

use interpolab::gcode::interp::Interpreter;
use interpolab::plan::scurve::rest_to_rest_time;
use interpolab::plan::{AxisLimits, Dynamics, time_program};

fn ruckig_time(d: f64, v: f64, a: f64, j: f64) -> f64 {
    let mut input = ruckig::InputParameter::new(1);
    input.current_position = vec![0.0];
    input.current_velocity = vec![0.0];
    input.current_acceleration = vec![0.0];
    input.target_position = vec![d];
    input.target_velocity = vec![0.0];
    input.target_acceleration = vec![0.0];
    input.max_velocity = vec![v];
    input.max_acceleration = vec![a];
    input.max_jerk = vec![j];
    let mut r = ruckig::Ruckig::new_direct_and_offline(1);
    let mut traj = ruckig::Trajectory::new_direct(1);
    let res = r.calculate(&mut input, &mut traj);
    assert!(matches!(res, ruckig::Result::Working | ruckig::Result::Finished), "ruckig: {res:?}");
    traj.get_duration()
}

/// A small deterministic generator (no dependency): xorshift64*.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Log-uniform in [lo, hi].
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.next()).exp()
    }
}

#[test]
fn rest_to_rest_durations_equal_ruckigs() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut worst: f64 = 0.0;
    for _ in 0..500 {
        // Lengths from a micrometre to a metre, limits over the range of real machines: every
        // case of the profile (cruise or not, acceleration reached or not).
        let d = rng.log(1e-3, 1000.0);
        let v = rng.log(1.0, 1000.0);
        let a = rng.log(10.0, 20_000.0);
        let j = rng.log(100.0, 1e6);
        let ours = rest_to_rest_time(d, v, a, j);
        let theirs = ruckig_time(d, v, a, j);
        worst = worst.max((ours - theirs).abs());
        assert!((ours - theirs).abs() <= 1e-9, "d {d} v {v} a {a} j {j}: ours {ours} s, Ruckig {theirs} s");
    }
    eprintln!("largest difference from Ruckig over 500 moves: {worst:e} s");
}

fn machine(v: [f64; 3], a: [f64; 3], j: [f64; 3]) -> Dynamics {
    let mut m = Dynamics::preset("vmc").expect("preset");
    for i in 0..3 {
        m.axes[i] = AxisLimits { velocity: v[i], acceleration: a[i], jerk: Some(j[i]) };
    }
    m
}

#[test]
fn a_single_straight_move_takes_ruckigs_time_along_the_line() {
    let mut rng = Rng(42);
    for _ in 0..100 {
        let v = [rng.log(1000.0, 40_000.0), rng.log(1000.0, 40_000.0), rng.log(1000.0, 40_000.0)];
        let a = [rng.log(100.0, 5000.0), rng.log(100.0, 5000.0), rng.log(100.0, 5000.0)];
        let j = [rng.log(1000.0, 1e5), rng.log(1000.0, 1e5), rng.log(1000.0, 1e5)];
        let end = [200.0 * (rng.next() - 0.5), 200.0 * (rng.next() - 0.5), 50.0 * (rng.next() - 0.5)];
        let feed = rng.log(100.0, 60_000.0);
        let text = format!("G1 X{} Y{} Z{} F{}\n", end[0], end[1], end[2], feed);
        let canon: Vec<_> = Interpreter::from_text(&text, Default::default()).map(|c| c.expect("reads")).collect();
        let m = machine(v, a, j);
        let t = time_program(canon, &m).expect("plans");
        // The line's limits: for each joint its limit over |direction component|.
        let len = (end[0] * end[0] + end[1] * end[1] + end[2] * end[2]).sqrt();
        let (mut vl, mut al, mut jl) = (feed / 60.0, f64::INFINITY, f64::INFINITY);
        for i in 0..3 {
            let u = (end[i] / len).abs();
            if u > 0.0 {
                vl = vl.min(v[i] / 60.0 / u);
                al = al.min(a[i] / u);
                jl = jl.min(j[i] / u);
            }
        }
        let theirs = ruckig_time(len, vl, al, jl);
        assert!(
            (t.total_s() - theirs).abs() <= 1e-9,
            "{text}: planned {} s, Ruckig {theirs} s (limits v {vl} a {al} j {jl})",
            t.total_s()
        );
    }
}
