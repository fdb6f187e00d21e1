//! A run of the simulation job: its program made, the stock started (or resumed from a kept
//! one), the moves machined with keyframes handed back, and the stock measured.

use std::sync::Mutex;

use super::codec::encode_partial;
use super::error::SimulateError;
use super::output::{Finished, Keyframe, Partial, Prepared};
use super::program::{StockAndPitch, make_program, scene_of, stock_and_pitch};
use super::progress::{PROGRAM_SHARE, RUN_SHARE, Reporter};
use super::request::{DesignSpec, MAX_RAYS, ProgramSource, Request};
use super::session::{Session, SessionKey, SessionStart};
use crate::jobs::Progress;
use crate::scene::finish::FinishScene;
use crate::simulate::pipeline::{self, Measures, SampleStep};
use crate::simulate::{Design, DexelStock, HeightMap, Program, Simulation};

/// Grid rows of the deviation scan between two looks at the cancel flag.
const ROWS_PER_CALL: usize = 4;
/// Most bytes of keyframes (5 bytes a ray: an `f32` height and a machined flag) one run
/// hands back: 6 keyframes of a 512 × 512 grid, or 25 of the automatic 256 × 256. Each
/// is a scan of the stock and 1.75 MB of text at 512 × 512 to write, post and decode;
/// since replays start from a kept stock ([`Session`]) the slider needs fewer of them. (At
/// 40 MiB a 512 × 512 run sent 32 keyframes, 56 MB of text, on a loaded 2-core machine the
/// browser's run took 6.5–8.7 s against 2.0 s natively; 16 MiB: 12.)
pub const KEYFRAME_BYTES: usize = 8 << 20;
/// Most keyframes a request may ask for.
pub const MAX_KEYFRAMES: usize = 256;

/// Moves between keyframes for a run to `target` on `rays` rays asking for at most `wanted`.
#[must_use]
pub fn keyframe_every(target: usize, rays: usize, wanted: usize) -> usize {
    let wanted = wanted.min(MAX_KEYFRAMES);
    if wanted == 0 || target == 0 {
        return 0;
    }
    let by_bytes = (KEYFRAME_BYTES / (5 * rays.max(1))).max(1);
    target.div_ceil(wanted.min(by_bytes)).max(1)
}

fn keyframe(sim: &Simulation) -> Keyframe {
    let map = HeightMap::of(sim.stock());
    Keyframe {
        moves: sim.counters().moves,
        counters: *sim.counters(),
        top_mm: map.top_mm.iter().map(|&z| z as f32).collect(),
        machined: map.machined,
    }
}

/// Runs `req` with `session` holding the kept stocks ([`SimulateRun::run`](super::SimulateRun)
/// uses the process's own; a test gives its own).
///
/// # Errors
/// [`SimulateError`]: a bad program, grid or design, or cancelled.
pub fn run_in_session(
    req: &Request,
    progress: &mut dyn Progress,
    session: &Mutex<Option<Session>>,
) -> Result<Finished, SimulateError> {
    let mut rep = Reporter::new(progress);
    rep.at(0.0);
    let program = make_program(req, &mut rep)?;
    rep.cancelled()?;
    let StockAndPitch { stock_mm, pitch_mm: pitch } = stock_and_pitch(req, &program)?;
    let nx = ((stock_mm[3] - stock_mm[0]) / pitch).ceil();
    let ny = ((stock_mm[4] - stock_mm[1]) / pitch).ceil();
    if !(nx * ny <= MAX_RAYS as f64) {
        return Err(SimulateError::TooManyRays {
            pitch_mm: pitch,
            nx: crate::simulate::ray_count(nx),
            ny: crate::simulate::ray_count(ny),
        });
    }
    let stock =
        DexelStock::block([stock_mm[0], stock_mm[1], stock_mm[2]], [stock_mm[3], stock_mm[4], stock_mm[5]], pitch)?;
    let sample_step =
        req.max_sample_step_mm.map_or(SampleStep::Default, SampleStep::BelowPitch).resolve(pitch, &req.cutter);
    let mut sim = pipeline::start(stock, &req.cutter, sample_step, &program)?;
    let design = match &req.design {
        DesignSpec::None => Design::None,
        DesignSpec::PlaneZ(z) => Design::PlaneZ(*z),
        DesignSpec::Scene(text) => Design::Surfaces(scene_of(text)?.job.surfaces.to_vec()),
        DesignSpec::Finish(text) => {
            let job = FinishScene::from_json(text).and_then(|f| f.job()).map_err(SimulateError::FinishScene)?;
            Design::Surface(job.surface)
        }
    };
    let design_name = design.name();
    let grid = *sim.stock().grid();
    let target = req.target.unwrap_or(usize::MAX).min(program.moves.len());
    let every = keyframe_every(target, grid.len(), req.keyframes);
    let key = SessionKey::of(&program, &stock_mm, pitch, &req.cutter, sample_step);
    let bytes = sim.stock().memory_bytes();
    let SessionStart { generation, kept } =
        session.lock().ok().map_or(SessionStart { generation: 0, kept: None }, |mut s| {
            s.get_or_insert_default().start(key, target, program.moves.len(), bytes)
        });
    if let Some(k) = kept.filter(|_| req.resume) {
        sim = k;
    }
    let resumed_from = sim.counters().moves;
    // The moves went with the request: the page has them, so they do not cross back.
    let sent = if matches!(req.source, ProgramSource::Moves(_)) { Program::default() } else { program.clone() };
    let prepared =
        Prepared { program: sent, stock_mm, pitch_mm: pitch, grid, design_name, target, keyframe_every: every };
    rep.progress.partial(encode_partial(&Partial::Prepared(Box::new(prepared))));
    rep.at(PROGRAM_SHARE);
    let todo = (target - resumed_from).max(1) as f64;
    rep.cancelled()?;
    pipeline::machine(&mut sim, &program.moves[resumed_from..target], |sim| {
        // Moves applied: the kept stock's and this run's, one counter.
        let done = sim.counters().moves;
        if let Ok(mut s) = session.lock()
            && let Some(s) = s.as_mut()
        {
            s.offer(generation, sim);
        }
        if every > 0 && done.is_multiple_of(every) && done < target {
            rep.progress.partial(encode_partial(&Partial::Keyframe(keyframe(sim))));
        }
        rep.at(PROGRAM_SHARE + RUN_SHARE * (done - resumed_from) as f64 / todo);
        rep.cancelled()
    })?;
    let ny = grid.ny.max(1);
    let Measures { map, stats } = pipeline::measure(sim.stock(), &design, ROWS_PER_CALL, |rows_done| {
        rep.at(PROGRAM_SHARE + RUN_SHARE + (1.0 - PROGRAM_SHARE - RUN_SHARE) * rows_done as f64 / ny as f64);
        rep.cancelled()
    })?;
    Ok(Finished { counters: *sim.counters(), resumed_from, map, stats })
}
