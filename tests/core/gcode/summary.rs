//! A program summarised one move at a time (`Summarizer`, `read_streamed`: what `replay`
//! without a design does, holding no move) equals the summary of the held path, bit for bit.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::gcode::{
    ArcMove, Dialect, LineMove, Motion, PathBlock, Plane, Segment, Toolpath, read_from, read_streamed, summarize,
};
use interpolab::geom::NurbsCurve;

use crate::support::Rng;

fn bits(v: DVec3) -> [u64; 3] {
    v.to_array().map(f64::to_bits)
}

/// A coordinate of every kind the line fast path of the summary tells apart: whole and half
/// millimetres (exact multiples), decimals, both zeros, tiny and huge values.
fn coordinate(rng: &mut Rng) -> f64 {
    let k = (rng.next_f64() * 9.0) as u32;
    match k {
        0 => (rng.range(-20.0, 20.0)).round(),
        1 => (rng.range(-20.0, 20.0) * 2.0).round() / 2.0,
        2 => (rng.range(-50.0, 50.0) * 1000.0).round() / 1000.0,
        3 => 0.0,
        4 => -0.0,
        5 => rng.range(-1e-9, 1e-9),
        6 => rng.range(-1e6, 1e6),
        7 => 0.1 * (rng.range(0.0, 30.0)).round(),
        _ => rng.range(-10.0, 10.0) * 25.4,
    }
}

fn point(rng: &mut Rng, from: DVec3) -> DVec3 {
    // Often only one or two axes move, as in most programs.
    let mut p = from;
    for k in 0..3 {
        if rng.next_f64() < 0.5 {
            p[k] = coordinate(rng);
        }
    }
    p
}

fn random_path(seed: u64) -> Toolpath {
    let mut rng = Rng::new(seed);
    let mut blocks = Vec::new();
    let mut at = DVec3::new(coordinate(&mut rng), coordinate(&mut rng), coordinate(&mut rng));
    for line in 1..400 {
        let roll = rng.next_f64();
        let (motion, segment) = if roll < 0.85 {
            let end = point(&mut rng, at);
            let motion = if rng.next_f64() < 0.2 { Motion::Rapid } else { Motion::Linear };
            (motion, Segment::Line(LineMove { start: at, end }))
        } else if roll < 0.97 {
            let r = rng.range(0.5, 20.0);
            let a = rng.range(0.0, std::f64::consts::TAU);
            let center = at - DVec3::new(r * a.cos(), r * a.sin(), 0.0);
            let b = a + rng.range(-3.0, 3.0);
            let end = center + DVec3::new(r * b.cos(), r * b.sin(), rng.range(-1.0, 1.0));
            let ccw = rng.next_f64() < 0.5;
            let motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
            (motion, Segment::Arc(ArcMove { start: at, end, center, plane: Plane::Xy, ccw }))
        } else {
            let pts = [at, point(&mut rng, at), point(&mut rng, at), point(&mut rng, at)];
            let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
            let curve = NurbsCurve::try_new(3, knots, &pts, None).expect("a cubic Bézier");
            (Motion::Nurbs, Segment::Nurbs(curve))
        };
        let end = segment.end();
        let feed = (motion != Motion::Rapid).then(|| rng.range(10.0, 5000.0).round());
        blocks.push(PathBlock { line, motion, segment, feed_mm_per_min: feed });
        at = end;
    }
    Toolpath { blocks }
}

#[test]
fn the_summary_built_move_by_move_equals_the_held_paths_lengths_and_bounds_bit_for_bit() {
    for seed in 1..40 {
        let path = random_path(seed);
        let s = summarize(&path);
        assert_eq!(s.cut_length_mm.to_bits(), path.cut_length().to_bits(), "seed {seed}");
        assert_eq!(s.rapid_length_mm.to_bits(), path.rapid_length().to_bits(), "seed {seed}");
        let (lo, hi) = s.bounds.expect("cuts");
        let (want_lo, want_hi) = path.cut_bounds().expect("cuts");
        assert_eq!((bits(lo), bits(hi)), (bits(want_lo), bits(want_hi)), "seed {seed}");
        let cuts = path.blocks.iter().filter(|b| b.motion != Motion::Rapid).count();
        assert_eq!(s.moves.iter().sum::<usize>() - s.moves[0], cuts);
    }
    // Lines alone, along one axis, through both zeros: the bounds' signs of zero too.
    for (a, b) in [(0.0, -0.0), (-0.0, 0.0), (-0.0, -0.0), (1.0, 2.0), (0.1, 0.1), (-3.5, -3.5), (1e-300, 1e-300)] {
        let line = |start: DVec3, end: DVec3| PathBlock {
            line: 1,
            motion: Motion::Linear,
            segment: Segment::Line(LineMove { start, end }),
            feed_mm_per_min: Some(100.0),
        };
        let path = Toolpath {
            blocks: vec![
                line(DVec3::new(a, b, 0.3), DVec3::new(b, b, 0.3)),
                line(DVec3::new(b, b, 0.3), DVec3::new(a, -0.0, 0.7)),
            ],
        };
        let (lo, hi) = summarize(&path).bounds.expect("cuts");
        let (want_lo, want_hi) = path.cut_bounds().expect("cuts");
        assert_eq!((bits(lo), bits(hi)), (bits(want_lo), bits(want_hi)), "{a} {b}");
    }
}

#[test]
fn a_program_streamed_hands_over_the_moves_a_held_read_keeps() {
    let text = "G21 G90 (start)\nG0 X0 Y0 Z5\nG1 Z-1 F300\nX10\nG2 X20 Y0 I5 J0 P2\nG3 X10 Y0 R5\n\
                G1 G91 X-1 Y1\nG90 G0 Z5\nM5 M30\n";
    let opts = Options::default();
    let held = read_from(Interpreter::from_text(text, opts.clone()), Dialect::LinuxCnc).expect("reads");
    let mut moves = Vec::new();
    let streamed = read_streamed(Interpreter::from_text(text, opts), Dialect::LinuxCnc, &mut |b| moves.push(b.clone()))
        .expect("reads");
    assert!(held.toolpath.blocks.len() >= 8, "{:?}", held.toolpath.blocks.len());
    assert_eq!(moves, held.toolpath.blocks);
    assert!(streamed.toolpath.blocks.is_empty());
    assert_eq!((streamed.lines, streamed.blocks), (held.lines, held.blocks));
    assert_eq!(streamed.comments, held.comments);
    assert_eq!(streamed.warnings, held.warnings);
    assert_eq!(streamed.unsupported.len(), held.unsupported.len());
}

/// The bytes a held move costs, as docs/bounded-work.md gives them (64-bit targets): a path
/// block of `replay --scene` and `simulate`'s reading, and a move of the simulation.
#[cfg(target_pointer_width = "64")]
#[test]
fn the_held_records_are_the_documented_size() {
    assert_eq!(std::mem::size_of::<PathBlock>(), 112);
    assert_eq!(std::mem::size_of::<interpolab::simulate::program::SimMove>(), 208);
}
