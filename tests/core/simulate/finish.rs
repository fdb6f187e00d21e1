//! The simulation of seed-001 finishing programs: the finish surface as the design (a
//! deviation only over the patch, the closed-form distance there) and the program the
//! fillet paths become (the seed-002 steps of every pass, joints interpolated linearly),
//! against the CL data they come from.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::fillet::{PartSamples, iso_scallop};
use interpolab::geom::{Cutter, Plane, Surface};
use interpolab::scene::finish::FinishScene;
use interpolab::simulate::{
    Design, DexelStock, FinishProgram, HeightMap, MoveKind, SimMove, SimStats, Simulation, over_surface_signed_distance,
};

/// A convex cylinder patch (radius 40 mm, about 7 × 6 mm), fillet R 3, r 1 mm, h 10 µm.
const SMALL_FINISH: &str = r#"{"format":"interpolab-scene/1","name":"small convex cylinder","surfaces":[{"type":"cylinder","origin":[0,0,-40],"axis":[0,1,0],"radius":40,"domain":{"u":[265,275],"v":[0,6]},"normal":"outward"}],
"finish":{"cutter":{"radius":3,"corner_radius":1},"scallop":0.01,"tolerance":0.0005,"direction":"u"}}"#;

#[test]
fn the_finish_surface_gives_a_deviation_only_over_the_patch() {
    // A ball groove along x across a block; the design a plane patch z = 7.5 over
    // x ∈ [2, 8], y ∈ [-20, 20]: rays over it read z − 7.5 exactly, rays beside it none,
    // while the scene-surfaces design (the part bounded by the plane) reads a distance there.
    let c = Cutter::ball(2.0).unwrap();
    let stock = DexelStock::block([0.0, 0.0, 0.0], [10.0, 6.0, 8.0], 0.1).unwrap();
    let mut sim = Simulation::new(stock, &c);
    sim.apply(&SimMove {
        kind: MoveKind::Line { from: DVec3::new(-3.0, 3.0, 7.0), to: DVec3::new(13.0, 3.0, 7.0) },
        line: 0,
        rapid: false,
    });
    let map = HeightMap::of(sim.stock());
    let plane = Surface::Plane(Plane::new(DVec3::new(0.0, 0.0, 7.5), DVec3::Z, DVec3::X, [2.0, 8.0], [-20.0, 20.0]));
    let over = SimStats::of(&map, sim.stock(), &Design::Surface(plane.clone()));
    let part = SimStats::of(&map, sim.stock(), &Design::Surfaces(vec![plane.clone()]));
    let g = map.grid;
    let (mut inside, mut beside) = (0, 0);
    let mut seed = None;
    for k in 0..g.len() {
        let (x, y) = (g.x_mm(k % g.nx), g.y_mm(k / g.nx));
        if !map.machined[k] {
            assert_eq!(over.deviation_mm[k], None);
            continue;
        }
        let p = DVec3::new(x, y, map.top_mm[k]);
        if (2.0..=8.0).contains(&x) {
            let d = over.deviation_mm[k].unwrap();
            assert!((d - (p.z - 7.5)).abs() < 1e-9, "({x}, {y}): {d}");
            assert!((part.deviation_mm[k].unwrap() - d).abs() < 1e-9);
            inside += 1;
        } else {
            assert_eq!(over.deviation_mm[k], None, "({x}, {y}) is beside the patch");
            assert!(part.deviation_mm[k].unwrap() > 0.0, "the part design counts it as outside");
            beside += 1;
        }
        // The function the scan uses, called alone, agrees.
        assert_eq!(over_surface_signed_distance(&plane, p, &mut seed), over.deviation_mm[k]);
    }
    assert!(inside > 500 && beside > 500, "{inside} {beside}");
    // Statistics only over the patch: the groove's floor 0.5 mm under the plane is the worst
    // gouge, its walls above the plane the scallops; nothing from beside the patch.
    let (w, at) = over.worst_gouge.unwrap();
    // The rays nearest the groove's axis lie 0.05 mm off it: the ball's floor is 0.6 µm higher there.
    assert!((w + 0.5 - (2.0 - (4.0f64 - 0.0025).sqrt())).abs() < 1e-9 && (2.0..=8.0).contains(&at.x), "{w} at {at}");
    assert_eq!(over.gouge_rays + over.scallop.count, inside);
    assert_eq!(Design::Surface(plane).name(), "finish surface");
}

#[test]
fn a_finishing_program_is_the_seed_002_steps_of_every_pass() {
    let job = FinishScene::from_json(SMALL_FINISH).unwrap().job().unwrap();
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let set = iso_scallop(&job.setup(&part)).unwrap();
    let tol = 0.001;
    let fp = FinishProgram::new(&job, &set, tol).unwrap();
    assert_eq!(fp.passes.len(), set.paths.iter().filter(|p| p.nodes.len() >= 2).count());
    assert!(fp.passes.len() >= 3);
    assert_eq!(fp.cutter, job.cutter, "the matched strategy machines with the scene's cutter");
    let program = fp.program().unwrap();
    // Pass by pass: the moves join the blocks of each pass, and each pass starts at its first
    // CL node (tip and axis) and ends at its last.
    let mut k = 0;
    for (pi, nodes) in fp.passes.iter().enumerate() {
        let mut one = interpolab::simulate::Program::default();
        fp.plan_pass(pi, &mut one).unwrap();
        assert!(!one.moves.is_empty());
        assert_eq!(&program.moves[k..k + one.moves.len()], &one.moves[..]);
        let pose = |m: &SimMove, end: bool| match m.kind {
            MoveKind::Joints { machine, from, to } => machine.pose_from_joints(if end { &to } else { &from }),
            MoveKind::Line { .. } => panic!("a finishing program is five-axis"),
        };
        let (first, last) = (pose(&one.moves[0], false), pose(&one.moves[one.moves.len() - 1], true));
        let (a, b) = (nodes[0], nodes[nodes.len() - 1]);
        assert!((first.tip_in_workpiece - a.tip).length() < 1e-6, "pass {pi}: {} vs {}", first.tip_in_workpiece, a.tip);
        assert!((last.tip_in_workpiece - b.tip).length() < 1e-6, "pass {pi}");
        assert!((first.axis_in_workpiece.normalize() - a.axis).length() < 1e-9, "pass {pi}");
        // Consecutive moves share their joints (no gap inside a pass).
        for w in one.moves.windows(2) {
            let (MoveKind::Joints { to, .. }, MoveKind::Joints { from, .. }) = (w[0].kind, w[1].kind) else {
                panic!("five-axis moves")
            };
            assert_eq!(to, from);
        }
        k += one.moves.len();
    }
    assert_eq!(k, program.moves.len());
    // The default stock holds the part's box, widened by R + margin in x and y.
    let (lo, hi) = fp.part_box().unwrap();
    let s = fp.stock_mm(2.0).unwrap();
    let half = 40.0 * 5f64.to_radians().sin();
    assert!((lo.x + half).abs() < 1e-9 && (hi.x - half).abs() < 1e-9 && lo.y.abs() < 1e-9 && (hi.y - 6.0).abs() < 1e-9);
    assert!((s[0] - (lo.x - 5.0)).abs() < 1e-12 && (s[4] - (hi.y + 5.0)).abs() < 1e-12);
    assert!((s[2] - (lo.z - 2.0)).abs() < 1e-12 && (s[5] - (hi.z + 2.0)).abs() < 1e-12);
    assert!(matches!(fp.design(), Design::Surface(_)));
    // A step tolerance that is not a positive length is refused with a message.
    let e = FinishProgram::new(&job, &set, 0.0).unwrap_err().to_string();
    assert!(e.contains("positive length"), "{e}");
    let e = FinishProgram::new(&job, &set, f64::NAN).unwrap_err().to_string();
    assert!(e.contains("positive length"), "{e}");
}

/// A finishing program's simulation work as `simulate --finish` estimates it to refuse a
/// run before its paths: on the small patch every path's estimate is its pass's moves'
/// visits times `work_per_visit` (the poses' `WORK_PER_VISIT`), and the run does at least
/// that work (the constant is the least the examples' runs measured); the program planned
/// within its share of the command's work (`program_within`) is the same program, or
/// refused naming its pass when the share is too small; the mould's pilot lets the
/// example's grid (1 mm) through and refuses one of 0.1 mm (its run would do some 25 times
/// the 1 mm run's 4.2·10⁷ units of work).
#[test]
fn a_finishing_programs_work_is_projected_from_its_pilot_and_its_paths() {
    use interpolab::fillet::paths::pilot;
    use interpolab::simulate::SimError;
    use interpolab::simulate::finish::{WORK_PER_VISIT, WorkProjection, work_per_visit};
    let job = FinishScene::from_json(SMALL_FINISH).unwrap().job().unwrap();
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let setup = job.setup(&part);
    let set = iso_scallop(&setup).unwrap();
    let tol = 0.005;
    let fp = FinishProgram::new(&job, &set, tol).unwrap();
    let s = fp.stock_mm(2.0).unwrap();
    let stock = DexelStock::block([s[0], s[1], s[2]], [s[3], s[4], s[5]], 0.25).unwrap();
    let step = FinishProgram::pose_step_mm(&fp.cutter, job.options.scallop_mm).unwrap();
    let mut sim = Simulation::new(stock, &fp.cutter).with_sample_step(step);
    let projection = WorkProjection::new(&job.surface, &job.cutter, &job.machine, job.strategy, tol);
    let every: f64 = set.paths.iter().map(|p| projection.work_of(&sim, std::slice::from_ref(p))).sum();
    let program = fp.program().unwrap();
    let visits: f64 = program.moves.iter().map(|m| sim.estimate_move_visits(m)).sum();
    assert_eq!(work_per_visit(&sim), WORK_PER_VISIT);
    assert!((every - WORK_PER_VISIT * visits).abs() <= 1e-9 * every, "{every} vs {}", WORK_PER_VISIT * visits);
    let (within, designs) = fp.program_within(interpolab::fillet::program::MAX_PLAN_DESIGNS).unwrap();
    assert_eq!(within, program);
    assert!(designs > 0);
    match fp.program_within(designs as f64 / 3.0) {
        Err(SimError::PlanWork { pass, .. }) => assert!(pass < fp.passes.len()),
        other => panic!("expected the planning refused, got {:?}", other.map(|p| p.1)),
    }
    sim.run(&program).unwrap();
    assert!(sim.work_done() >= every, "the run did {} against the estimate {every}", sim.work_done());

    let text = interpolab::scene::finish::FINISH_PRESETS.iter().find(|p| p.id == "finish-concave-mould").unwrap().json;
    let job = FinishScene::from_json(text).unwrap().job().unwrap();
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let plan = pilot(&job.setup(&part)).unwrap().unwrap();
    let cutter = job.strategy.cutter_for(&job.cutter);
    let s = interpolab::simulate::stock_box_mm(&job.surface, &cutter, 2.0).unwrap();
    let projection = WorkProjection::new(&job.surface, &job.cutter, &job.machine, job.strategy, tol);
    let step = FinishProgram::pose_step_mm(&cutter, job.options.scallop_mm).unwrap();
    for (pitch, fits) in [(1.0, true), (0.1, false)] {
        let stock = DexelStock::block([s[0], s[1], s[2]], [s[3], s[4], s[5]], pitch).unwrap();
        let sim = Simulation::new(stock, &cutter).with_sample_step(step);
        match projection.check_pilot(&sim, &plan) {
            Ok(()) => assert!(fits, "pitch {pitch} mm: not refused"),
            Err(SimError::TooMuchFinishWork { projected, max }) => {
                assert!(!fits && projected > max, "pitch {pitch} mm: {projected} of {max}");
            }
            Err(e) => panic!("pitch {pitch} mm: {e}"),
        }
    }
}
