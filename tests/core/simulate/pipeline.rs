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

mod work {
    use interpolab::geom::Cutter;
    use interpolab::simulate::pipeline::{WorkMeter, machine};
    use interpolab::simulate::{DexelStock, MoveKind, PROJECTED_WORK_ROOM, Program, SimError, SimMove, Simulation};

    /// `n` equal passes of a ball along X through a 20 × 20 mm block, each a little deeper.
    fn passes(n: usize) -> Program {
        let moves = (0..n)
            .map(|k| {
                let z = -0.01 * (k + 1) as f64;
                let y = -8.0 + 16.0 * (k % 8) as f64 / 7.0;
                SimMove {
                    kind: MoveKind::Line { from: glam::DVec3::new(-12.0, y, z), to: glam::DVec3::new(12.0, y, z) },
                    rapid: false,
                    line: k + 1,
                }
            })
            .collect();
        Program { moves, ..Program::default() }
    }

    fn simulation() -> Simulation {
        let stock = DexelStock::block([-10.0, -10.0, -5.0], [10.0, 10.0, 0.0], 0.1).unwrap();
        Simulation::new(stock, &Cutter::ball(2.0).unwrap())
    }

    #[test]
    fn a_run_is_measured_by_its_ray_updates_and_refused_once_its_projection_passes_the_cap() {
        let program = passes(200);
        // The whole run, unmetered: straight moves count one a ray update.
        let mut whole = simulation();
        let Ok(()) = machine(&mut whole, &program.moves, |_| Ok::<(), std::convert::Infallible>(()));
        let c = *whole.counters();
        assert!(c.ray_updates > 100_000 && c.joint_updates == 0, "{c:?}");
        assert_eq!(whole.work_done(), c.ray_updates as f64);
        // A cap the run fits: metered, it ends the same.
        let fits = simulation();
        let meter = WorkMeter::new(&fits, &program.moves).with_cap(whole.work_done());
        let mut sim = fits;
        let mut done = 0;
        machine(&mut sim, &program.moves, |s| {
            done += 1;
            meter.check(s, &program.moves, done)
        })
        .unwrap();
        assert_eq!(sim.counters(), &c);
        // A cap of a fifth of its work: refused once a twentieth of the estimated visits is
        // done (the passes are alike: at move 10 of 200), projecting about the whole.
        let small = simulation();
        let cap = whole.work_done() / 5.0;
        let meter = WorkMeter::new(&small, &program.moves).with_cap(cap);
        let mut sim = small;
        let mut done = 0;
        let err = machine(&mut sim, &program.moves, |s| {
            done += 1;
            meter.check(s, &program.moves, done)
        })
        .unwrap_err();
        let SimError::TooMuchWorkDone { done: at, moves, line, work, projected, max } = err.clone() else {
            panic!("{err}")
        };
        assert_eq!((at, moves, line, max), (10, 200, 10, cap));
        assert!(work < PROJECTED_WORK_ROOM * cap && projected > PROJECTED_WORK_ROOM * cap, "{err}");
        assert!(
            (projected / whole.work_done() - 1.0).abs() < 0.5,
            "projected {projected}, whole {}",
            whole.work_done()
        );
        let text = err.to_string();
        assert!(text.contains("after 10 of 200 moves (line 10)") && text.contains("raise the pitch"), "{text}");
        // A cap under a run's own (what a finishing command's paths and program left) is not
        // called 20 s.
        assert!(text.contains("what the command's earlier work left it") && !text.contains("20 s"), "{text}");
    }

    /// A run its meter stops is run again, once, on the same block at the coarser pitch
    /// `coarser_pitch` gives for the work left: every move machined within what is left;
    /// without a coarser grid, or with none within its coarsest pitch, the meter's refusal.
    #[test]
    fn a_run_its_meter_stops_runs_again_on_a_grid_coarse_enough_for_what_is_left() {
        use interpolab::simulate::pipeline::{CoarserGrid, SampleStep, coarser_pitch, run_metered};
        let program = passes(200);
        let ball = Cutter::ball(2.0).unwrap();
        let stock = || DexelStock::block([-10.0, -10.0, -5.0], [10.0, 10.0, 0.0], 0.1).unwrap();
        let (whole, none) = run_metered(stock(), &ball, SampleStep::Default, &program, f64::INFINITY, None).unwrap();
        assert_eq!(none, None);
        let cap = whole.work_done() / 5.0;
        let grid = CoarserGrid { lo_mm: [-10.0, -10.0, -5.0], hi_mm: [10.0, 10.0, 0.0], max_pitch_mm: 1.0 };
        let (sim, coarsened) = run_metered(stock(), &ball, SampleStep::Default, &program, cap, Some(grid)).unwrap();
        let c = coarsened.unwrap();
        let pitch = sim.stock().grid().pitch_mm;
        assert_eq!(c.asked_pitch_mm, 0.1);
        assert!(c.projected > PROJECTED_WORK_ROOM * cap && c.left < cap && c.left > 0.0, "{c:?}");
        assert_eq!(Some(pitch), coarser_pitch(0.1, c.projected, c.left, 1.0));
        assert!(pitch > 0.1 && pitch < 0.5, "{pitch}");
        assert_eq!(sim.counters().moves, 200);
        assert!(sim.work_done() <= c.left, "{} of {}", sim.work_done(), c.left);
        let (lo, hi) = (sim.stock().grid().x0_mm, sim.stock().z_range_mm());
        assert!((lo - -10.0).abs() <= pitch && hi == (-5.0, 0.0), "{lo} {hi:?}");
        // No coarser grid, or none as fine as needed: the meter's refusal.
        for coarser in [None, Some(CoarserGrid { max_pitch_mm: 0.15, ..grid })] {
            let err = run_metered(stock(), &ball, SampleStep::Default, &program, cap, coarser).unwrap_err();
            assert!(matches!(err, SimError::TooMuchWorkDone { done: 10, .. }), "{err}");
        }
    }
}

#[test]
fn the_work_of_five_axis_moves_is_weighed_by_their_measured_cost() {
    use glam::DVec3;
    use interpolab::fiveaxis::Joints;
    use interpolab::simulate::canon::MachineSetup;
    use interpolab::simulate::{CRASH_VISIT_COST, DexelStock, JOINT_UPDATE_COST, MoveKind, SimMove, Simulation};
    let m = MachineSetup::from_name("head-bc", 0.0).unwrap().machine;
    let joints = |x: f64| Joints { xyz_mm: DVec3::new(x, 0.0, -0.5), rotary_rad: [0.2, 0.0] };
    let stock = DexelStock::block([-10.0, -10.0, -5.0], [10.0, 10.0, 0.0], 0.1).unwrap();
    let mut sim = Simulation::new(stock, &Cutter::flat(2.0).unwrap());
    let line = SimMove {
        kind: MoveKind::Line { from: DVec3::new(-8.0, 5.0, -0.5), to: DVec3::new(8.0, 5.0, -0.5) },
        line: 1,
        rapid: false,
    };
    sim.apply(&line);
    let straight = sim.counters().ray_updates;
    sim.apply(&SimMove {
        kind: MoveKind::Joints { machine: m, from: joints(-8.0), to: joints(8.0) },
        line: 2,
        rapid: false,
    });
    let c = *sim.counters();
    let joint = c.ray_updates - straight;
    assert!(straight > 1000 && joint > 1000, "{c:?}");
    assert_eq!(c.joint_updates, joint);
    assert_eq!(sim.work_done(), straight as f64 + JOINT_UPDATE_COST * joint as f64);

    // A cutter whose shank starts 1 mm above the tip, run 4 mm deep: its 5-axis move's part
    // checks visit rays of stock above the shank's lowest point, and they count too.
    let short = Cutter::try_new(2.0, 0.0, 1.0, 2.0, 6.0, 5.0, 10.0).unwrap();
    let stock = DexelStock::block([-10.0, -10.0, -5.0], [10.0, 10.0, 0.0], 0.1).unwrap();
    let mut deep = Simulation::new(stock, &short);
    let low = |x: f64| Joints { xyz_mm: DVec3::new(x, 0.0, -4.0), rotary_rad: [0.2, 0.0] };
    deep.apply(&SimMove {
        kind: MoveKind::Joints { machine: m, from: low(-8.0), to: low(8.0) },
        line: 1,
        rapid: false,
    });
    let c = *deep.counters();
    assert!(c.crash_visits > 1000 && c.crash_visits <= c.rays_visited, "{c:?}");
    assert_eq!(
        deep.work_done(),
        (c.ray_updates - c.joint_updates) as f64
            + JOINT_UPDATE_COST * c.joint_updates as f64
            + CRASH_VISIT_COST * c.crash_visits as f64
    );
}

/// The coarser grid a run its meter stopped is run on again: the work, scaled as 1/pitch²,
/// fits the share of what is left, the pitch is at most a tenth above the exact one and has
/// two significant digits, and none is offered when nothing is left, when the run fits, or
/// past the largest pitch asked.
#[test]
fn a_coarser_pitch_fits_the_work_left_in_two_digits() {
    use interpolab::simulate::pipeline::{COARSER_RUN_SHARE, coarser_pitch};
    for &pitch in &[0.05, 0.1, 0.25, 0.5, 0.7, 1.0, 2.0, 3.3] {
        for &ratio in &[0.7, 1.0, 1.3, 2.0, 3.3, 10.0, 97.0, 1e4] {
            let left = 3.7e8;
            let projected = ratio * left;
            let exact = pitch * (projected / (COARSER_RUN_SHARE * left)).sqrt();
            let got = coarser_pitch(pitch, projected, left, f64::INFINITY);
            if exact <= pitch {
                assert_eq!(got, None, "a run that fits gets no coarser grid ({pitch}, {ratio})");
                continue;
            }
            let p = got.unwrap();
            assert!(p >= exact && p <= 1.1 * exact, "{p} for an exact {exact}");
            assert!(projected * (pitch / p).powi(2) <= COARSER_RUN_SHARE * left * (1.0 + 1e-12));
            let text = p.to_string();
            let digits = text.trim_start_matches(['0', '.']).replace('.', "");
            assert!(digits.trim_end_matches('0').len() <= 2, "{text}");
            assert_eq!(coarser_pitch(pitch, projected, left, 0.999 * p), None);
        }
    }
    assert_eq!(coarser_pitch(0.5, 1e9, 0.0, 10.0), None);
    assert_eq!(coarser_pitch(0.5, f64::NAN, 1e8, 10.0), None);
    assert_eq!(coarser_pitch(0.5, 1e9, -1.0, 10.0), None);
    assert_eq!(coarser_pitch(0.0, 1e9, 1e8, 10.0), None);
}
