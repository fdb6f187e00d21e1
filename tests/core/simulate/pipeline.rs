//! The one simulation pipeline the command line and the app's job share
//! (`simulate::pipeline`): the dialect judged on a program's head only, each dialect read to
//! the same path as its own reader gives, the programmed point from the header, and the two
//! sampling rules.
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use interpolab::gcode::interp::Options;
use interpolab::gcode::{Dialect, read_program};
use interpolab::geom::Cutter;
use interpolab::simulate::pipeline::{
    DIALECT_GUESS_BYTES, SampleStep, ToolPoint, guess_dialect, program_of, read_text,
};

#[test]
fn the_dialect_is_guessed_from_the_head_alone() {
    // A FANUC-looking head, then a Sinumerik word: guessed FANUC past the head (as a file the
    // command line does not read whole to guess), Sinumerik within it.
    let filler = "G01 X1 Y1\n".repeat(DIALECT_GUESS_BYTES / 10 + 1);
    let late = format!("G21 G90\n{filler}BSPLINE SD=3\n");
    assert_eq!(guess_dialect(late.as_bytes()), Dialect::Fanuc);
    let early = "G21 G90\nBSPLINE SD=3\nG01 X1 Y1\n";
    assert_eq!(guess_dialect(early.as_bytes()), Dialect::Sinumerik);
    assert_eq!(guess_dialect(early.as_bytes()), Dialect::guess(early));
}

#[test]
fn every_dialect_is_read_as_its_reader_reads_it() {
    let programs = [
        (Dialect::Fanuc, "G21 G90 G17\nG00 X0 Y0 Z5\nG01 Z0 F300\nG02 X10 Y0 I5 J0\nG01 X20\nM30\n"),
        (Dialect::LinuxCnc, "G21 G90 G17\nG00 X0 Y0 Z5\nG01 Z0 F300\nG03 X10 Y0 I5 J0\nG01 X20\nM2\n"),
        (Dialect::Sinumerik, "G71 G90 G17\nG0 X0 Y0 Z5\nG1 Z0 F300\nG2 X10 Y0 I5 J0\nG1 X20\nM30\n"),
    ];
    let ball = Cutter::ball(2.0).unwrap();
    for (d, text) in programs {
        let ours = read_text(text, d, &Options::default()).unwrap();
        let theirs = read_program(text, d, &Options::default()).unwrap();
        assert_eq!(ours.toolpath, theirs.toolpath, "{d:?}");
        assert!(!ours.toolpath.blocks.is_empty(), "{d:?}");
        // No header: the points are tool tips, and the program's moves start at them.
        let point = ToolPoint::of_comments(&ours.comments);
        assert_eq!(point, ToolPoint::Tip, "{d:?}");
        let p = program_of(&ours.toolpath, point, &ball, 0.01).unwrap();
        let centre = program_of(&ours.toolpath, ToolPoint::BallCentre, &ball, 0.01).unwrap();
        assert_eq!(p.moves.len(), centre.moves.len(), "{d:?}");
    }
}

#[test]
fn a_header_naming_the_ball_centre_moves_the_points_down_by_the_radius() {
    let text = "(PROGRAMMED POINT: BALL CENTRE)\nG21 G90\nG01 X0 Y0 Z3 F100\nG01 X5\n";
    let parsed = read_text(text, guess_dialect(text.as_bytes()), &Options::default()).unwrap();
    assert_eq!(ToolPoint::of_comments(&parsed.comments), ToolPoint::BallCentre);
    assert_eq!(ToolPoint::BallCentre.tip_offset(&Cutter::ball(2.5).unwrap()).z, -2.5);
    assert_eq!(ToolPoint::BallCentre.label(), "ball centre");
    assert_eq!(ToolPoint::Tip.label(), "tool tip");
}

#[test]
fn a_given_sample_step_holds_for_every_cutter_and_the_slider_s_only_below_the_pitch() {
    let (ball, flat) = (Cutter::ball(3.0).unwrap(), Cutter::flat(3.0).unwrap());
    assert_eq!(SampleStep::Default.resolve(0.1, &flat), None);
    assert_eq!(SampleStep::Given(0.05).resolve(0.1, &ball), Some(0.05));
    assert_eq!(SampleStep::Given(0.5).resolve(0.1, &flat), Some(0.5));
    assert_eq!(SampleStep::BelowPitch(0.05).resolve(0.1, &flat), Some(0.05));
    assert_eq!(SampleStep::BelowPitch(0.05).resolve(0.1, &ball), None, "a ball is swept in closed form");
    assert_eq!(SampleStep::BelowPitch(0.1).resolve(0.1, &flat), None, "not finer than the pitch");
}
