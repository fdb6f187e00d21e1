use glam::{DVec2, DVec3};
use serde_json::Value;

use super::output::{Finished, Keyframe, Partial, Prepared};
use super::request::{DesignSpec, ProgramSource, Request};
use super::run::{KEYFRAME_BYTES, keyframe_every, run_in_session};
use super::session::{KEPT_STOCK_BYTES, MAX_KEPT_STOCKS, Session};
use super::*;
use crate::fillet::CcNode;
use crate::gcode::ProgramKind;
use crate::geom::Cutter;
use crate::jobs::{JobKind, NoProgress, Progress};
use crate::simulate::{Design, DexelStock, HeightMap, MoveKind, Program, SimMove, SimStats, Simulation};

/// Collects what a job hands back, and cancels after a number of cancel checks when asked.
#[derive(Default)]
struct Collect {
    partials: Vec<String>,
    fractions: Vec<f64>,
    checks: std::cell::Cell<usize>,
    cancel_after: Option<usize>,
}

impl Progress for Collect {
    fn progress(&mut self, fraction: f64) {
        self.fractions.push(fraction);
    }
    fn cancelled(&self) -> bool {
        self.checks.set(self.checks.get() + 1);
        self.cancel_after.is_some_and(|n| self.checks.get() > n)
    }
    fn partial(&mut self, encoded: String) {
        self.partials.push(encoded);
    }
}

/// Three parallel ball passes and a plunge through a block (a program of tool tips).
const GROOVES: &str = "%\nG21 G90\nG00 X-2 Y0 Z5\nG01 Z-1 F500\nG01 X12\nG00 Z5\nG00 X-2 Y1.5\nG01 Z-1\nG01 X12\nG00 Z5\nG00 X-2 Y3\nG01 Z-1\nG01 X12\nG00 Z5\nG00 X5 Y6\nG01 Z-2\nG00 Z5\nM30\n%\n";

fn grooves(target: Option<usize>, keyframes: usize) -> Request {
    Request {
        source: ProgramSource::Text { name: "grooves.nc".into(), text: GROOVES.into() },
        cutter: Cutter::ball(1.0).unwrap(),
        pitch_mm: Some(0.1),
        stock_mm: Some([-1.0, -2.0, -4.0, 11.0, 8.0, 0.0]),
        margin_mm: 2.0,
        max_sample_step_mm: None,
        design: DesignSpec::PlaneZ(-1.0),
        target,
        keyframes,
        resume: false,
    }
}

fn decode_all(c: &Collect) -> (Prepared, Vec<Keyframe>) {
    let mut prepared = None;
    let mut keys = Vec::new();
    for t in &c.partials {
        match SimulateRun::decode_partial(t).unwrap() {
            Partial::Prepared(p) => {
                assert!(prepared.is_none(), "one Prepared per run");
                assert!(keys.is_empty(), "the program comes before its keyframes");
                prepared = Some(*p);
            }
            Partial::Keyframe(k) => keys.push(k),
        }
    }
    (prepared.unwrap(), keys)
}

/// The stock machined directly by the core to move `k`.
fn direct(p: &Prepared, cutter: &Cutter, k: usize) -> Simulation {
    let s = p.stock_mm;
    let stock = DexelStock::block([s[0], s[1], s[2]], [s[3], s[4], s[5]], p.pitch_mm).unwrap();
    let mut sim = Simulation::new(stock, cutter);
    for m in &p.program.moves[..k] {
        sim.apply(m);
    }
    sim
}

/// The job gives what the core computes directly: the map and measures at the target, the
/// program it cut, and keyframes equal to the stock at their moves (heights rounded to f32),
/// as often as asked and never more.
#[test]
fn the_run_is_the_core_simulation_with_keyframes_of_the_stock() {
    let req = grooves(None, 4);
    let mut c = Collect::default();
    let out = SimulateRun::run(&req, &mut c).unwrap();
    let (p, keys) = decode_all(&c);
    let moves = p.program.moves.len();
    // Fourteen moves: the first rapid, from an unknown position, is only where the tool starts.
    assert_eq!(moves, 14, "{:?}", p.program.moves);
    assert_eq!(p.target, moves);
    assert_eq!(p.keyframe_every, moves.div_ceil(4));
    assert_eq!(keys.len(), (moves - 1) / p.keyframe_every);
    let sim = direct(&p, &req.cutter, moves);
    assert_eq!(out.counters, *sim.counters());
    assert_eq!(out.map, HeightMap::of(sim.stock()));
    assert_eq!(out.stats, SimStats::of(&out.map, sim.stock(), &Design::PlaneZ(-1.0)));
    assert!(out.counters.removed_mm3 > 1.0);
    // Passes 1.5 mm apart at the plane leave the textbook scallop h = R − √(R² − w²/4)
    // midway, on the rays at y = 0.75 and 2.25 mm (row j has y = −2 + (j + ½)·0.1).
    let h = 1.0 - (1.0f64 - 0.75 * 0.75).sqrt();
    let g = out.map.grid;
    for j in [27, 42] {
        for i in [30, 59, 90] {
            let d = out.stats.deviation_mm[j * g.nx + i].unwrap();
            assert!((d - h).abs() < 1e-9, "ray ({i}, {j}): {d} vs {h}");
        }
    }
    for k in &keys {
        assert_eq!(k.moves % p.keyframe_every, 0);
        let at = direct(&p, &req.cutter, k.moves);
        let map = HeightMap::of(at.stock());
        assert_eq!(k.counters, *at.counters());
        assert_eq!(k.machined, map.machined);
        assert!(k.top_mm.iter().zip(&map.top_mm).all(|(a, b)| *a == *b as f32));
        assert_eq!(k.map(p.grid).machined, map.machined);
    }
    // Progress rises to 1 and never falls.
    assert!(c.fractions.windows(2).all(|w| w[1] >= w[0]) && c.fractions.last() == Some(&1.0));
    // The output crosses unchanged, bit for bit.
    let text = SimulateRun::encode_output(&Ok(out.clone()));
    let back = SimulateRun::decode_output(&text).unwrap().unwrap();
    assert_eq!(back, out);
    assert!(back.map.top_mm.iter().zip(&out.map.top_mm).all(|(a, b)| a.to_bits() == b.to_bits()));
}

/// A run without a design sends no deviation arrays (`null`), and its output still decodes
/// to the run's exact map and measures: every ray without a deviation. With a design, the
/// arrays are there.
#[test]
fn a_run_without_a_design_sends_no_deviations_and_decodes_to_the_same_output() {
    let req = Request { design: DesignSpec::None, ..grooves(None, 0) };
    let out = SimulateRun::run(&req, &mut NoProgress).unwrap();
    assert!(out.counters.removed_mm3 > 1.0);
    assert!(out.stats.deviation_mm.iter().all(Option::is_none));
    let text = SimulateRun::encode_output(&Ok(out.clone()));
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["stats"]["deviation_mm"], Value::Null);
    assert_eq!(v["stats"]["has_deviation"], Value::Null);
    let back = SimulateRun::decode_output(&text).unwrap().unwrap();
    assert_eq!(back, out);
    assert!(back.map.top_mm.iter().zip(&out.map.top_mm).all(|(a, b)| a.to_bits() == b.to_bits()));
    // The same run against a plane: the arrays are sent, and the text is longer by them.
    let with = SimulateRun::run(&grooves(None, 0), &mut NoProgress).unwrap();
    let with_text = SimulateRun::encode_output(&Ok(with.clone()));
    let w: Value = serde_json::from_str(&with_text).unwrap();
    assert!(w["stats"]["deviation_mm"].is_string(), "{}", w["stats"]["deviation_mm"]);
    assert!(with_text.len() > text.len() + 8 * out.map.grid.len());
    assert_eq!(SimulateRun::decode_output(&with_text).unwrap().unwrap(), with);
}

/// A replay of the first run's moves to move k (no program written again) gives the stock
/// a run of the text to move k gives, which is the core's stock after k moves.
#[test]
fn a_replay_of_the_moves_to_move_k_is_the_stock_at_k() {
    let mut c = Collect::default();
    SimulateRun::run(&grooves(None, 0), &mut c).unwrap();
    let (p, keys) = decode_all(&c);
    assert!(keys.is_empty(), "no keyframes asked for");
    for k in [0, 1, 5, 9, 14] {
        let from_text = SimulateRun::run(&grooves(Some(k), 0), &mut NoProgress).unwrap();
        let mut replay = grooves(Some(k), 0);
        replay.source = ProgramSource::Moves(p.program.clone());
        let replay = SimulateRun::decode_request(&SimulateRun::encode_request(&replay)).unwrap();
        let again = SimulateRun::run(&replay, &mut NoProgress).unwrap();
        assert_eq!(again, from_text, "move {k}");
        assert_eq!(again.counters.moves, k);
        assert_eq!(again.map, HeightMap::of(direct(&p, &replay.cutter, k).stock()));
    }
}

/// Every source crosses into the worker unchanged: a scene's crease program and steps, a
/// text, and moves with 5-axis joints (the scene's steps, made by the job itself).
#[test]
fn requests_cross_unchanged() {
    let scene = crate::scene::PRESETS[0].json.to_owned();
    let mut reqs = vec![
        grooves(Some(3), 8),
        Request {
            source: ProgramSource::Crease { scene: scene.clone(), kind: ProgramKind::Nurbs },
            cutter: Cutter::fillet(3.0, 0.5).unwrap(),
            pitch_mm: None,
            stock_mm: None,
            margin_mm: 1.5,
            max_sample_step_mm: Some(0.03125),
            design: DesignSpec::Scene(scene.clone()),
            target: None,
            keyframes: 40,
            resume: false,
        },
        Request { source: ProgramSource::Steps { scene: scene.clone() }, ..grooves(None, 1) },
        Request {
            design: DesignSpec::Finish(crate::scene::finish::FINISH_PRESETS[0].json.to_owned()),
            ..grooves(None, 2)
        },
    ];
    // The steps program has joints moves: made by the job, then sent back as moves.
    let mut c = Collect::default();
    let steps = Request { target: Some(0), ..reqs[2].clone() };
    let ran = SimulateRun::run(&Request { stock_mm: None, pitch_mm: None, ..steps }, &mut c);
    assert!(ran.is_ok(), "{ran:?}");
    let (p, _) = decode_all(&c);
    assert!(p.program.moves.iter().all(|m| matches!(m.kind, MoveKind::Joints { .. })) && p.program.moves.len() > 2);
    reqs.push(Request { source: ProgramSource::Moves(p.program), ..grooves(Some(2), 0) });
    reqs.push(Request {
        source: ProgramSource::Benchmark { kind: crate::simulate::bench::BenchKind::FiveAxis, moves: 10_000 },
        ..grooves(None, 0)
    });
    for r in reqs {
        assert_eq!(SimulateRun::decode_request(&SimulateRun::encode_request(&r)).unwrap(), r);
    }
    let e =
        SimulateRun::decode_request(r#"{"source": {"benchmark": "five-axis", "count": 0}}"#).unwrap_err().to_string();
    assert!(e.contains("five-axis:N"), "{e}");
}

/// A benchmark source runs the core's benchmark program: the same moves, the same stock.
#[test]
fn a_benchmark_run_machines_the_core_benchmark_program() {
    use crate::simulate::bench::{self, BenchKind};
    let req = Request::benchmark(BenchKind::FiveAxis, 120, 0.8).unwrap();
    let mut c = Collect::default();
    let out = SimulateRun::run(&req, &mut c).unwrap();
    let (p, _) = decode_all(&c);
    let program = bench::five_axis(120).unwrap();
    assert_eq!(p.program, program);
    let s = BenchKind::stock_mm();
    let stock = DexelStock::block([s[0], s[1], s[2]], [s[3], s[4], s[5]], 0.8).unwrap();
    let mut sim = Simulation::new(stock, &Cutter::ball(bench::BALL_MM).unwrap());
    sim.run(&program).unwrap();
    assert_eq!(out.counters, *sim.counters());
    assert_eq!(out.map, HeightMap::of(sim.stock()));
}

/// A cancelled run stops; bad input gets a message, not a panic.
#[test]
fn cancelled_and_bad_runs_say_so() {
    let mut c = Collect { cancel_after: Some(5), ..Collect::default() };
    assert_eq!(SimulateRun::run(&grooves(None, 0), &mut c).unwrap_err(), JobError::Cancelled);
    assert!(c.checks.get() == 6, "stopped at the first look after the flag: {}", c.checks.get());
    let bad =
        Request { source: ProgramSource::Text { name: "bad.nc".into(), text: "G01 X#1\n".into() }, ..grooves(None, 0) };
    let e = SimulateRun::run(&bad, &mut NoProgress).unwrap_err();
    assert!(matches!(&e, JobError::Failed(m) if m.starts_with("bad.nc is not a program")), "{e}");
    let fine = Request { pitch_mm: Some(0.001), ..grooves(None, 0) };
    let e = SimulateRun::run(&fine, &mut NoProgress).unwrap_err();
    assert!(matches!(&e, JobError::Failed(m) if m.contains("raise the pitch")), "{e}");
    let e = SimulateRun::decode_request("{\"source\": {}}").unwrap_err().to_string();
    assert!(e.contains("simulate-run request"), "{e}");
    let e = SimulateRun::decode_partial("{\"keyframe\": {\"moves\": 1}}").unwrap_err().to_string();
    assert!(e.contains("keyframe"), "{e}");
}

/// Keyframes: as many as asked when small, fewer when their bytes would pass the cap.
#[test]
fn keyframes_are_bounded_by_count_and_bytes() {
    assert_eq!(keyframe_every(100, 256 * 256, 10), 10);
    assert_eq!(keyframe_every(100, 256 * 256, 0), 0);
    assert_eq!(keyframe_every(0, 256 * 256, 10), 0);
    assert_eq!(keyframe_every(7, 100, 40), 1);
    let every = keyframe_every(10_000, 1024 * 1024, 200);
    let count = 10_000 / every;
    let most = KEYFRAME_BYTES / (5 * 1024 * 1024);
    assert!(count <= most && count + 1 >= most, "{every} → {count} keyframes of at most {most}");
}

/// A finishing scene's design reaches the worker as its text and is measured as the core
/// measures its machined surface: the same deviation on every ray as `Design::Surface` of
/// the scene's own job, rays off the patch without one.
#[test]
fn a_finishing_scene_is_measured_against_its_machined_surface() {
    let text = crate::scene::finish::FINISH_PRESETS[0].json;
    let job = crate::scene::finish::FinishScene::from_json(text).unwrap().job().unwrap();
    let design = Design::Surface(job.surface.clone());
    // Two ball passes across the patch's middle, 0.2 mm into it, on a small block around them.
    let dom = crate::geom::ParametricSurface::domain(&job.surface);
    let mid = crate::geom::ParametricSurface::point_at(&job.surface, DVec2::new(dom.u.mid(), dom.v.mid()));
    let tip = |dx: f64, dy: f64| mid + DVec3::new(dx, dy, -0.2);
    let moves = vec![
        SimMove { kind: MoveKind::Line { from: tip(-6.0, 0.0), to: tip(6.0, 0.0) }, line: 1, rapid: false },
        SimMove { kind: MoveKind::Line { from: tip(6.0, 1.5), to: tip(-6.0, 1.5) }, line: 2, rapid: false },
    ];
    let req = Request {
        source: ProgramSource::Moves(Program { moves, chord_error_mm: 0.0 }),
        cutter: Cutter::ball(2.0).unwrap(),
        pitch_mm: Some(0.25),
        stock_mm: Some([mid.x - 10.0, mid.y - 8.0, mid.z - 6.0, mid.x + 10.0, mid.y + 8.0, mid.z + 4.0]),
        margin_mm: 0.0,
        max_sample_step_mm: None,
        design: DesignSpec::Finish(text.to_owned()),
        target: None,
        keyframes: 0,
        resume: false,
    };
    let req = SimulateRun::decode_request(&SimulateRun::encode_request(&req)).unwrap();
    let mut c = Collect::default();
    let out = SimulateRun::run(&req, &mut c).unwrap();
    let (p, _) = decode_all(&c);
    assert_eq!(p.design_name, "finish surface");
    let sim = direct(&p, &req.cutter, p.program.moves.len());
    assert_eq!(out.stats, SimStats::of(&out.map, sim.stock(), &design));
    let measured = out.stats.deviation_mm.iter().filter(|d| d.is_some()).count();
    assert!(measured > 100, "{measured} rays measured");
}

/// The largest pose step reaches the simulation: a fillet cutter's 5-axis moves are sampled
/// finer when asked (more samples, and the cusps between poses, ≈ s²/(8r), shallower), a
/// step above the pitch changes nothing, and a ball's moves keep their closed-form sweeps.
#[test]
fn the_largest_pose_step_reaches_the_simulation() {
    let scene = crate::scene::PRESETS[0].json.to_owned();
    let steps = |cutter: Cutter, step: Option<f64>| Request {
        source: ProgramSource::Steps { scene: scene.clone() },
        cutter,
        pitch_mm: Some(0.5),
        stock_mm: None,
        margin_mm: 2.0,
        max_sample_step_mm: step,
        design: DesignSpec::None,
        target: None,
        keyframes: 0,
        resume: false,
    };
    let fillet = Cutter::fillet(3.0, 0.5).unwrap();
    let samples = |r: &Request| SimulateRun::run(r, &mut NoProgress).unwrap().counters.samples;
    let (coarse, fine) = (samples(&steps(fillet, None)), samples(&steps(fillet, Some(0.125))));
    assert!(coarse > 10 && fine >= 3 * coarse, "pitch 0.5: {coarse} samples; step 0.125: {fine}");
    assert_eq!(samples(&steps(fillet, Some(2.0))), coarse, "a step above the pitch keeps the pitch");
    let ball = Cutter::ball(3.0).unwrap();
    assert_eq!(samples(&steps(ball, Some(0.125))), samples(&steps(ball, None)), "a ball keeps its swept segments");
}

/// A finishing program's steps are planned in the job (off the page): the request carries
/// the finishing scene, the cutter and the CC nodes; the moves the job plans are those of
/// `FinishProgram::plan_pass` run here, pass by pass, bit for bit, and a run of them
/// measures against the finish surface.
#[test]
fn a_finishing_program_is_planned_in_the_job_as_on_the_page() {
    use crate::fillet::{PartSamples, iso_scallop};
    use crate::scene::finish::{FINISH_PRESETS, FinishScene};
    use crate::simulate::FinishProgram;
    let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).unwrap();
    // A coarse scallop and tolerance: few passes and steps, a short test.
    scene.finish.scallop = 0.1;
    scene.finish.tolerance = 0.005;
    let job = scene.job().unwrap();
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let set = iso_scallop(&job.setup(&part)).unwrap();
    let fp = FinishProgram::new(&job, &set, 0.005).unwrap();
    assert!(fp.passes.len() >= 3, "{} passes", fp.passes.len());
    let mut here = Program::default();
    for k in 0..fp.passes.len() {
        fp.plan_pass(k, &mut here).unwrap();
    }
    let text = scene.to_json();
    let req = Request {
        source: ProgramSource::Finish {
            scene: text.clone(),
            cutter: fp.cutter,
            passes: fp.passes.clone(),
            step_tol_mm: fp.step_tol_mm,
        },
        cutter: fp.cutter,
        pitch_mm: Some(0.5),
        stock_mm: fp.stock_mm(2.0),
        margin_mm: 2.0,
        max_sample_step_mm: None,
        design: DesignSpec::Finish(text),
        target: Some(3),
        keyframes: 0,
        resume: false,
    };
    let crossed = SimulateRun::decode_request(&SimulateRun::encode_request(&req)).unwrap();
    // The nodes cross without the gouge checks' record (planning does not read it).
    let ProgramSource::Finish { passes, .. } = &crossed.source else { panic!("not a finishing source") };
    for (a, b) in passes.iter().flatten().zip(fp.passes.iter().flatten()) {
        assert_eq!(CcNode { adjusted: b.adjusted, ..*a }, *b);
    }
    let mut c = Collect::default();
    let out = SimulateRun::run(&crossed, &mut c).unwrap();
    let (p, _) = decode_all(&c);
    assert_eq!(p.program, here, "the job's plan is the page's");
    assert_eq!(p.design_name, "finish surface");
    assert_eq!(out.counters.moves, 3);
    assert!(c.fractions.windows(2).all(|w| w[0] <= w[1]), "progress rises: {:?}", c.fractions);
    assert!(c.fractions.iter().any(|f| *f > 0.0 && *f <= 0.1), "planning reports progress: {:?}", c.fractions);
    // A bad step tolerance is a message.
    let bad = Request {
        source: ProgramSource::Finish {
            scene: FINISH_PRESETS[0].json.to_owned(),
            cutter: fp.cutter,
            passes: Vec::new(),
            step_tol_mm: 0.0,
        },
        ..req
    };
    let e = SimulateRun::run(&bad, &mut NoProgress).unwrap_err();
    assert!(matches!(&e, JobError::Failed(m) if m.contains("step tolerance")), "{e}");
}

/// The stock intervals of two simulations, every ray, by their bits.
fn same_stock(a: &Simulation, b: &Simulation) -> bool {
    let bits = |s: &Simulation, i: usize| -> Vec<(u64, u64)> {
        s.stock().intervals(i).iter().map(|v| (v.lo_mm.to_bits(), v.hi_mm.to_bits())).collect()
    };
    a.stock().grid() == b.stock().grid()
        && a.counters() == b.counters()
        && (0..a.stock().grid().len()).all(|i| bits(a, i) == bits(b, i))
}

/// A worker keeps the stock for replays: the first run of the 5-axis benchmark program keeps
/// full stocks at evenly spaced moves (each bit for bit the core's stock at its move); a
/// replay to move k starts from the nearest kept at or before k and gives, bit for bit, what
/// a fresh run to k gives; a run that may not resume, or of another program, starts from
/// the block (and another program replaces the kept stocks).
#[test]
fn a_replay_starts_from_the_nearest_kept_stock_and_equals_a_fresh_run() {
    use crate::simulate::bench::BenchKind;
    let first = Request {
        design: DesignSpec::PlaneZ(15.0),
        keyframes: 5,
        ..Request::benchmark(BenchKind::FiveAxis, 300, 0.4).unwrap()
    };
    let session = std::sync::Mutex::new(None);
    let mut c = Collect::default();
    let whole = run_in_session(&first, &mut c, &session).unwrap();
    let (p, keys) = decode_all(&c);
    assert_eq!((whole.resumed_from, keys.len()), (0, 4), "a first run starts from the block, sends its keyframes");
    let block_bytes = direct(&p, &first.cutter, 0).stock().memory_bytes();
    let every = Session::spacing(300, block_bytes);
    assert_eq!(every, 300usize.div_ceil(MAX_KEPT_STOCKS + 1), "128 × 128 rays: 8 stocks fit the budget");
    {
        let s = session.lock().unwrap();
        let s = s.as_ref().unwrap();
        let want: Vec<usize> = (1..=MAX_KEPT_STOCKS).map(|i| i * every).filter(|&k| k <= 300).collect();
        assert_eq!(s.kept_moves(), want);
        assert!(s.kept_bytes() <= KEPT_STOCK_BYTES);
        for kept in &s.kept {
            let fresh = direct(&p, &first.cutter, kept.counters().moves);
            assert!(same_stock(kept, &fresh), "kept stock at move {}", kept.counters().moves);
        }
    }
    let replay_to = |k: usize, resume: bool| Request {
        source: ProgramSource::Moves(p.program.clone()),
        target: Some(k),
        keyframes: 2,
        resume,
        ..first.clone()
    };
    for k in [0, every - 1, every, every + 7, 5 * every + 1, 299, 300] {
        let req = SimulateRun::decode_request(&SimulateRun::encode_request(&replay_to(k, true))).unwrap();
        let mut c = Collect::default();
        let fast = run_in_session(&req, &mut c, &session).unwrap();
        assert_eq!(fast.resumed_from, k / every * every, "move {k}");
        let fresh = run_in_session(&replay_to(k, false), &mut NoProgress, &std::sync::Mutex::new(None)).unwrap();
        assert_eq!(fresh.resumed_from, 0);
        assert_eq!(Finished { resumed_from: 0, ..fast.clone() }, fresh, "move {k}");
        assert!(fast.map.top_mm.iter().zip(&fresh.map.top_mm).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(fast.counters.removed_mm3.to_bits(), fresh.counters.removed_mm3.to_bits());
        assert_eq!(fast.map, HeightMap::of(direct(&p, &first.cutter, k).stock()));
        // Progress still rises to 1; the moves the page has do not cross back.
        assert_eq!(c.fractions.last(), Some(&1.0));
        let (prepared, _) = decode_all(&c);
        assert!(prepared.program.moves.is_empty() && prepared.target == k);
    }
    // Not allowed to resume: from the block, same stock.
    let slow = run_in_session(&replay_to(250, false), &mut NoProgress, &session).unwrap();
    assert_eq!(slow.resumed_from, 0);
    // Another program (another pitch) replaces the kept stocks, and its own first replay
    // starts from the block.
    let other = Request { pitch_mm: Some(0.8), ..replay_to(250, true) };
    assert_eq!(run_in_session(&other, &mut NoProgress, &session).unwrap().resumed_from, 0);
    assert!(session.lock().unwrap().as_ref().unwrap().kept_moves().iter().all(|&k| k <= 250));
    assert_eq!(run_in_session(&replay_to(250, true), &mut NoProgress, &session).unwrap().resumed_from, 0);
}

/// The kept stocks stay within their budget: none of a grid too large for it, fewer when a
/// stock is large.
#[test]
fn kept_stocks_are_bounded_by_count_and_bytes() {
    assert_eq!(Session::spacing(10_000, 24 * 512 * 512), 10_000usize.div_ceil(MAX_KEPT_STOCKS + 1));
    assert_eq!(Session::spacing(10_000, 24 * 1024 * 1024), 10_000usize.div_ceil(3));
    assert_eq!(Session::spacing(10_000, KEPT_STOCK_BYTES + 1), 0);
    assert_eq!(Session::spacing(1, 100), 0);
    assert_eq!(Session::spacing(0, 100), 0);
}
