//! `interpolab simulate`: machine a G-code program into a dexel stock and write its height
//! map (CSV), a PNG, and the statistics (JSON on standard output). Format: docs/simulation.md.

use std::convert::Infallible;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use glam::DVec3;
use interpolab::crease::CreaseJob;
use interpolab::fillet::paths::share_after_paths;
use interpolab::fillet::program::{MAX_PLAN_DESIGNS, for_machine};
use interpolab::fillet::{
    Built, FinishError, FinishJob, FinishSetup, PartSamples, PathSet, Strategy, iso_scallop_checked,
};
use interpolab::geom::Cutter;
use interpolab::numerics::format::fmt_num;
use interpolab::numerics::limits::CommandShare;
use interpolab::scene::Scene;
use interpolab::simulate::bench::BenchKind;
use interpolab::simulate::finish::WorkProjection;
use interpolab::simulate::pipeline::{self, CoarserGrid, Measures, SampleStep, ToolPoint};
use interpolab::simulate::{Design, DexelStock, FinishProgram, MAX_WORK, Program, SimError, Simulation, stock_box_mm};
use interpolab::simulate::{INTERIOR_END_MM, INTERIOR_SIDE_MM, InteriorStats, interior_mask, interior_stats};
use serde_json::json;

use super::Fatal;

/// Which point of the tool the program's coordinates give.
#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum PointArg {
    /// The header comment of a program written by `interpolab gcode` decides; else the tip.
    Auto,
    /// The tool tip (bottom centre of the cutter).
    Tip,
    /// The ball centre: the tip is R below it.
    Centre,
}

#[derive(Args)]
pub(crate) struct SimulateArgs {
    /// G-code program (G00/G01/G02/G03 in G17/G18/G19, helical, G06.2 NURBS); with
    /// --project it may be left out (the project's files are read).
    #[arg(required_unless_present_any = ["benchmark", "project"])]
    program: Option<PathBuf>,
    #[command(flatten)]
    read: super::program::ReadArgs,
    /// Instead of PROGRAM: the benchmark program `five-axis:N` or `three-axis:N` (N moves of
    /// the ball raster on the 51.2 mm block, docs/simulation.md), built in memory; give
    /// --cutter and --stock as for a program (the benchmarks: ball:3, 0,0,0,51.2,51.2,20).
    #[arg(long, conflicts_with_all = ["program", "steps", "finish", "scene"])]
    benchmark: Option<String>,
    /// Cutter: `ball:R`, `flat:R`, `fillet:R,r`, `v:R,angle` or `drill:R[,angle]` (mm,
    /// degrees), e.g. `ball:5` (with --finish: default the scene's cutter as its strategy
    /// machines; with tools: the cutter before the first tool change and of tools the table
    /// lacks).
    #[arg(long)]
    cutter: Option<String>,
    /// Stock block `x0,y0,z0,x1,y1,z1` (mm) (with --finish: default the part's box widened
    /// by R + --margin in x and y, --margin below and above it).
    #[arg(long, allow_hyphen_values = true)]
    stock: Option<String>,
    /// Ray spacing in x and y (mm).
    #[arg(value_parser = super::finite, long, default_value_t = 0.1)]
    pitch: f64,
    /// Which tool point the program gives.
    #[arg(long, value_enum, default_value = "auto")]
    point: PointArg,
    /// Chord tolerance for arcs and NURBS (mm); default a tenth of the pitch.
    #[arg(value_parser = super::finite, long)]
    chord_tol: Option<f64>,
    /// Design: the horizontal plane z = this (mm), material below.
    #[arg(value_parser = super::finite, long, allow_hyphen_values = true, conflicts_with = "scene")]
    design_z: Option<f64>,
    /// Design: the two surfaces of this scene (interpolab-scene/1), normals toward the cutter.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Write the height map as CSV to this file.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write a PNG of the result (deviation colours with a design, heights without).
    #[arg(long)]
    png: Option<PathBuf>,
    /// PROGRAM is a scene: simulate its five-axis tool steps at this tolerance (mm),
    /// joints interpolated linearly on the scene's machine; the design is its two surfaces.
    #[arg(value_parser = super::finite, long, conflicts_with_all = ["design_z", "scene"])]
    steps: Option<f64>,
    /// PROGRAM is a finishing scene (a `finish` key): simulate the five-axis
    /// program `interpolab finish --gcode` writes for it, steps within this tolerance (mm),
    /// joints interpolated linearly on the scene's machine; the design is the finish surface.
    /// A run too fine for the work the paths left is run on a coarser grid (said on stderr).
    #[arg(value_parser = super::finite, long, conflicts_with_all = ["design_z", "scene", "steps"])]
    finish: Option<f64>,
    /// With --finish: the orientation strategy (default: the scene's `finish.strategy`).
    #[arg(long, value_enum, requires = "finish")]
    strategy: Option<super::finish::StrategyArg>,
    /// With --finish and --strategy fixed-lead: the lead angle (degrees).
    #[arg(value_parser = super::finite, long, default_value_t = 5.0, requires = "finish")]
    lead: f64,
    /// With --finish: the path layout.
    #[arg(long, value_enum, default_value = "iso-scallop", requires = "finish")]
    layout: super::finish::LayoutArg,
    /// With --finish and no --stock: margin (mm) of the automatic stock around the part.
    #[arg(value_parser = super::finite, long, default_value_t = 2.0, requires = "finish")]
    margin: f64,
    /// Sample 5-axis moves pose by pose (every cutter, the ball included) so no point of the
    /// cutter moves more than this (mm) between two poses; default one pitch for flat and
    /// fillet end mills, closed-form swept segments for the ball.
    #[arg(value_parser = super::finite, long)]
    sample_step: Option<f64>,
    /// Deviation shown at full colour in the PNG (µm).
    #[arg(value_parser = super::finite, long, default_value_t = 50.0)]
    band_um: f64,
    #[command(flatten)]
    tools: super::userprog::ToolArgs,
    /// With tools or a machine: write which tool last cut each ray (`.csv`: i,j,x_mm,y_mm,tool;
    /// `.png`: a colour per tool, grey where none cut).
    #[arg(long)]
    tool_map: Option<PathBuf>,
    /// Write the crashes (shank, holder, rapid through stock, plunge of a tool that does not
    /// cut at its centre), one a block, as CSV to this file (docs/simulation.md, "Crashes").
    #[arg(long)]
    crashes: Option<PathBuf>,
    /// With a machine: count the blocks whose nonlinear error exceeds this (mm), in the JSON.
    #[arg(value_parser = super::finite, long)]
    tolerance: Option<f64>,
}

/// Parses `ball:R`, `flat:R`, `fillet:R,r`, `v:R,angle`, `drill:R[,angle]`, each followed
/// by optional body words (`,flute=25,shank=3:40,holder=16:60,nocentre`, mm).
pub(crate) fn parse_cutter(text: &str) -> Result<Cutter, Fatal> {
    let bad = || {
        Fatal(format!(
            "--cutter `{text}`: give ball:R, flat:R or fillet:R,r in mm, or a tapered v:R,angle or drill:R[,angle] (included angle in degrees), e.g. ball:5, fillet:5,1, v:3,90, then optional ,flute=L ,shank=radius:length ,holder=radius:length ,nocentre (mm)"
        ))
    };
    let (kind, rest) = text.split_once(':').ok_or_else(bad)?;
    let mut body = interpolab::geom::BodySpec::default();
    let mut numbers = Vec::new();
    for piece in rest.split(',') {
        if !body.word(piece, 1.0).map_err(|e| Fatal(format!("--cutter: {e}")))? {
            numbers.push(piece);
        }
    }
    let dims = numbers.join(",");
    let dims = dims.as_str();
    let c = match kind.trim() {
        "ball" => Cutter::ball(super::numbers(dims, "cutter", 1)?[0]),
        "flat" => Cutter::flat(super::numbers(dims, "cutter", 1)?[0]),
        "fillet" => {
            let v = super::numbers(dims, "cutter", 2)?;
            Cutter::fillet(v[0], v[1])
        }
        "v" => {
            let v = super::numbers(dims, "cutter", 2)?;
            Cutter::tapered(v[0], v[1], 0.0)
        }
        "drill" => {
            let v: Vec<f64> = if dims.contains(',') {
                super::numbers(dims, "cutter", 2)?
            } else {
                super::numbers(dims, "cutter", 1)?
            };
            Cutter::tapered(v[0], v.get(1).copied().unwrap_or(118.0), 0.0)
        }
        _ => return Err(bad()),
    };
    c.and_then(|c| c.with_body(&body)).map_err(|e| Fatal(format!("--cutter `{text}`: {e}")))
}

/// Where the design comes from.
struct SimulateDesign<'a> {
    design_z: Option<f64>,
    scene: Option<&'a Path>,
}

fn load_design(a: &SimulateDesign<'_>) -> Result<Design, Fatal> {
    if let Some(z) = a.design_z {
        if !z.is_finite() {
            return Err(Fatal(format!("--design-z {z}: give a finite height in mm")));
        }
        return Ok(Design::PlaneZ(z));
    }
    let Some(path) = a.scene else {
        return Ok(Design::None);
    };
    let text = fs::read_to_string(path).map_err(|e| Fatal(format!("cannot read scene {}: {e}", path.display())))?;
    let scene = Scene::from_json(&text).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    let job = CreaseJob::from_scene(&scene).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    Ok(Design::Surfaces(job.surfaces.to_vec()))
}

pub(super) fn simulate(a: &SimulateArgs) -> Result<ExitCode, Fatal> {
    if !(a.band_um > 0.0 && a.band_um.is_finite()) {
        return Err(Fatal(format!("--band-um {}: give a positive deviation in µm", a.band_um)));
    }
    if let Some(step) = a.sample_step
        && !(step > 0.0 && step.is_finite())
    {
        return Err(Fatal(format!("--sample-step {step}: give a positive length in mm, e.g. 0.025")));
    }
    if let Some(tol) = a.finish {
        if !(a.margin >= 0.0 && a.margin.is_finite()) {
            return Err(Fatal(format!("--margin {}: give a margin of 0 mm or more", a.margin)));
        }
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(Fatal(format!(
                "--finish {tol}: the step tolerance must be a positive length in mm; give e.g. 0.01"
            )));
        }
        return simulate_finish(a, tol);
    }
    if a.tools.any() {
        return simulate_user(a);
    }
    if a.tool_map.is_some() {
        return Err(Fatal("--tool-map needs the program's tools: give --tools, --project or --tool".to_owned()));
    }
    let cutter = parse_cutter(a.cutter.as_deref().ok_or_else(|| {
        Fatal("--cutter is required: give ball:R, flat:R or fillet:R,r in mm (e.g. ball:5)".to_owned())
    })?)?;
    let stock = super::stock_block(
        a.stock.as_deref().ok_or_else(|| {
            Fatal("--stock is required: give the block as x0,y0,z0,x1,y1,z1 in mm (e.g. -10,-10,-5,10,10,0)".to_owned())
        })?,
        a.pitch,
    )?;
    if let Some(b) = &a.benchmark {
        let (kind, n) = BenchKind::parse(b).map_err(|e| Fatal(format!("--{e}")))?;
        let program = kind.program(n).map_err(|e| Fatal(format!("--benchmark {b}: {e}")))?;
        let design = load_design(&SimulateDesign { design_z: a.design_z, scene: None })?;
        return finish(a, &cutter, stock, &program, &design, RunHow::given(a));
    }
    let path = program_path(a)?;
    if let Some(tol) = a.steps {
        let (machine, blocks, _) = super::fiveaxis::scene_blocks(path, tol)?;
        let program = Program::from_blocks(&machine, &blocks).map_err(|e| Fatal(e.to_string()))?;
        let design = load_design(&SimulateDesign { design_z: None, scene: Some(path) })?;
        return finish(a, &cutter, stock, &program, &design, RunHow::given(a));
    }
    let design = load_design(&SimulateDesign { design_z: a.design_z, scene: a.scene.as_deref() })?;
    let (parsed, _, _) = super::program::read_path(path, None, &a.read, interpolab::simulate::program::MAX_MOVES)?;
    for l in super::program::report_lines(&parsed) {
        eprintln!("interpolab: {l}");
    }
    let point = match a.point {
        PointArg::Tip => ToolPoint::Tip,
        PointArg::Centre => ToolPoint::BallCentre,
        PointArg::Auto => ToolPoint::of_comments(&parsed.comments),
    };
    let program = pipeline::program_of(&parsed.toolpath, point, &cutter, chord_tol_mm(a))
        .map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    finish(a, &cutter, stock, &program, &design, RunHow { point, ..RunHow::given(a) })
}

/// With tools or a machine: the program read through the interpreter into the moves of its
/// own tools and rotary axes (`userprog`).
fn simulate_user(a: &SimulateArgs) -> Result<ExitCode, Fatal> {
    if a.benchmark.is_some() || a.steps.is_some() || a.finish.is_some() {
        return Err(Fatal(
            "--tools, --project, --tool and --machine read a G-code PROGRAM; leave out --benchmark, --steps and --finish"
                .to_owned(),
        ));
    }
    if let Some(t) = a.tolerance
        && !(t > 0.0)
    {
        return Err(Fatal(format!("--tolerance {t}: give a positive length in mm, e.g. 0.01")));
    }
    let cutter = a.cutter.as_deref().map(parse_cutter).transpose()?;
    let design = load_design(&SimulateDesign { design_z: a.design_z, scene: a.scene.as_deref() })?;
    let chord_tol = chord_tol_mm(a);
    if !(chord_tol > 0.0) {
        return Err(Fatal(format!("--chord-tol {chord_tol}: give a positive length in mm")));
    }
    super::userprog::simulate(&super::userprog::SimulateRequest {
        program: a.program.as_deref(),
        read: &a.read,
        tools: &a.tools,
        cutter,
        stock: super::userprog::StockChoice { given: a.stock.as_deref(), pitch: a.pitch },
        chord_tol,
        sample_step: a.sample_step,
        design,
        out: a.out.as_deref(),
        png: a.png.as_deref(),
        tool_map: a.tool_map.as_deref(),
        crashes: a.crashes.as_deref(),
        band_um: a.band_um,
        tolerance: a.tolerance,
    })
}

/// `--finish TOL`: PROGRAM is a finishing scene; its paths (the strategy and layout asked
/// for) become the five-axis program `interpolab finish --gcode` writes, simulated against
/// the finish surface.
fn simulate_finish(a: &SimulateArgs, tol: f64) -> Result<ExitCode, Fatal> {
    let path = program_path(a)?;
    let name = path.display().to_string();
    let job = super::finish::load(path)?;
    let strategy = super::finish::strategy_arg(a.strategy, a.lead, &job)?;
    // The cutter and the stock first: a stock refused (too many rays, an empty box) is
    // refused before the paths are planned.
    let cutter = match &a.cutter {
        Some(c) => parse_cutter(c)?,
        None => strategy.cutter_for(&job.cutter),
    };
    let block = match &a.stock {
        Some(s) => super::numbers(s, "stock", 6)?,
        None => stock_box_mm(&job.surface, &strategy.cutter_for(&job.cutter), a.margin)
            .ok_or_else(|| {
                Fatal(format!("{name}: the surface has no finite points to size the stock from; give --stock"))
            })?
            .to_vec(),
    };
    let block = ([block[0], block[1], block[2]], [block[3], block[4], block[5]]);
    let stock = DexelStock::block(block.0, block.1, a.pitch).map_err(|e| Fatal(e.to_string()))?;
    // Poses close enough that the sampling's cusps stay under a quarter of h (the app's
    // hand-over does the same), unless --sample-step says otherwise.
    let pose_step =
        a.sample_step.or_else(|| FinishProgram::pose_step_mm(&cutter, job.options.scallop_mm).filter(|s| *s < a.pitch));
    let how = RunHow {
        sample_step: pose_step.map_or(SampleStep::Default, SampleStep::Given),
        point: ToolPoint::Tip,
        finish_info: None,
        interior_passes: None,
        work_share: CommandShare::whole(),
        coarser: Some(block),
    };
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    let (set, stock) = finish_paths_metered(a, &job, strategy, &part, stock, &cutter, &how, tol, &name)?;
    let fp = FinishProgram::new(&job, &set, tol).map_err(|e| Fatal(format!("--finish {tol}: {e}")))?;
    // One command's work: the program is planned within what the paths left, and the run
    // within what both left.
    let mut share = share_after_paths(part.cells_checked(), job.options.max_check_cells);
    let (program, designs) = fp.program_within(share.cap(MAX_PLAN_DESIGNS)).map_err(|e| {
        let over = matches!(e, SimError::PlanWork { .. });
        Fatal(format!(
            "{name}: {e}{}",
            if over { super::finish::spent_note(share, "the paths' checks") } else { String::new() }
        ))
    })?;
    share.spend(designs as f64, MAX_PLAN_DESIGNS);
    let extra = json!({
        "label": fp.label,
        "pose_step_mm": pose_step,
        "passes": fp.passes.len(),
        "cc_points": fp.passes.iter().map(Vec::len).sum::<usize>(),
        "scallop_mm": job.options.scallop_mm,
        "chord_tol_mm": job.options.chord_tol_mm,
        "step_tol_mm": tol,
        "refused": set.refused.len(),
    });
    let how = RunHow { finish_info: Some(extra), interior_passes: Some(fp.cc_points()), work_share: share, ..how };
    let status = finish(a, &cutter, stock, &program, &fp.design(), how)?;
    // Named once the run is done, so that a refusal of the command (the run's meter) stays
    // its only line.
    for line in super::finish::refused_lines(&name, &set.refused, "the simulated program leaves them out") {
        eprintln!("{line}");
    }
    Ok(status)
}

/// The paths of `simulate --finish`, as `finish --gcode` builds them (every pose within the
/// machine's travel, [`interpolab::fillet::program::for_machine`]), refused before any path
/// when the job's pilot says the simulation of their program would pass the work a run may
/// do by far ([`interpolab::simulate::finish::WorkProjection`]); what it misses, the run's
/// meter stops, within what the paths and the program left of the command's work. The
/// stock comes back untouched, for the run.
#[allow(clippy::too_many_arguments)]
fn finish_paths_metered(
    a: &SimulateArgs,
    job: &FinishJob,
    strategy: Strategy,
    part: &PartSamples,
    stock: DexelStock,
    cutter: &Cutter,
    how: &RunHow,
    tol: f64,
    name: &str,
) -> Result<(PathSet, DexelStock), Fatal> {
    let fail = |e: &dyn std::fmt::Display| Fatal(format!("{name}: {e}"));
    let setup = FinishSetup { strategy, ..job.setup(part) };
    let setup = for_machine(&job.machine, &setup);
    let pitch = stock.grid().pitch_mm;
    let mut sim = Simulation::new(stock, cutter);
    if let Some(step) = how.sample_step.resolve(pitch, cutter) {
        sim = sim.with_sample_step(step);
    }
    let projection = WorkProjection::new(&job.surface, &job.cutter, &job.machine, strategy, tol);
    if !matches!(a.layout, super::finish::LayoutArg::IsoScallop) {
        if let Some(pilot) = interpolab::fillet::paths::pilot(&setup).map_err(|e| fail(&e))? {
            projection.check_pilot(&sim, &pilot).map_err(|e| fail(&e))?;
        }
        return Ok((super::finish::paths_for(job, strategy, a.layout, part, true, name)?, sim.into_stock()));
    }
    let set = iso_scallop_checked(&setup, |built| {
        if let Built::Pilot(pilot) = built {
            projection.check_pilot(&sim, pilot)?;
        }
        Ok::<(), Stop>(())
    })
    .map_err(|e| fail(&e))?;
    Ok((set, sim.into_stock()))
}

/// Why [`finish_paths_metered`] stopped its paths.
#[derive(Debug, thiserror::Error)]
enum Stop {
    #[error(transparent)]
    Finish(#[from] FinishError),
    #[error(transparent)]
    Work(#[from] SimError),
}

/// The interior band's statistics as the JSON's `interior` (µm to 1e-3).
fn interior_json(s: &InteriorStats) -> serde_json::Value {
    let um = |mm: f64| (mm * 1e6).round() / 1e3;
    json!({
        "end_mm": INTERIOR_END_MM,
        "side_mm": INTERIOR_SIDE_MM,
        "rays": s.rays,
        "scallop_um": { "rays": s.scallop.count, "max": um(s.scallop.max_mm), "mean": um(s.scallop.mean_mm), "p95": um(s.scallop.p95_mm) },
        "worst_gouge_um": s.worst_gouge_mm.map(um),
    })
}

/// PROGRAM (clap requires it unless `--benchmark` is given).
fn program_path(a: &SimulateArgs) -> Result<&Path, Fatal> {
    a.program.as_deref().ok_or_else(|| Fatal("give a PROGRAM file (or --benchmark five-axis:N)".to_owned()))
}

/// The program's name in messages and the JSON: its path, or `benchmark five-axis:N`.
fn program_name(a: &SimulateArgs) -> String {
    match (&a.program, &a.benchmark) {
        (Some(p), _) => p.display().to_string(),
        (None, Some(b)) => format!("benchmark {b}"),
        (None, None) => String::new(),
    }
}

/// The chord tolerance (mm): `--chord-tol`, else the pipeline's default for the pitch.
fn chord_tol_mm(a: &SimulateArgs) -> f64 {
    a.chord_tol.unwrap_or_else(|| pipeline::default_chord_tol_mm(a.pitch))
}

/// The coarsest grid a finishing program's run stopped by its meter is run again on, in
/// cutter radii: half a radius, so the cutter still spans four rays. Coarser, the command is
/// refused as before.
const COARSEST_PITCH_RADII: f64 = 0.5;

/// How a program is run and reported besides its arguments.
struct RunHow {
    /// How 5-axis moves are sampled.
    sample_step: SampleStep,
    /// The point of the tool the program's coordinates give.
    point: ToolPoint,
    /// The finishing program's facts for the JSON output.
    finish_info: Option<serde_json::Value>,
    /// The finishing program's contact points per pass: its interior band's statistics
    /// are added to the JSON (`interior`).
    interior_passes: Option<Vec<Vec<DVec3>>>,
    /// The share of the command's work left for the run (a finishing program's paths and
    /// planning spent the rest).
    work_share: CommandShare,
    /// The stock block's corners (mm) when a run its meter stops may be run again on a
    /// coarser grid of the same block ([`pipeline::coarser_pitch`]): a finishing program,
    /// whose paths and planning came first. `None`: the meter's refusal ends the command.
    coarser: Option<([f64; 3], [f64; 3])>,
}

impl RunHow {
    /// A program of tool tips, sampled as `--sample-step` says, with nothing to add to the
    /// JSON.
    fn given(a: &SimulateArgs) -> Self {
        Self {
            sample_step: a.sample_step.map_or(SampleStep::Default, SampleStep::Given),
            point: ToolPoint::Tip,
            finish_info: None,
            interior_passes: None,
            work_share: CommandShare::whole(),
            coarser: None,
        }
    }
}

fn finish(
    a: &SimulateArgs,
    cutter: &Cutter,
    stock: DexelStock,
    program: &Program,
    design: &Design,
    how: RunHow,
) -> Result<ExitCode, Fatal> {
    let RunHow { sample_step, point, finish_info, interior_passes, work_share, coarser } = how;
    let chord_tol = chord_tol_mm(a);
    let t0 = Instant::now();
    // After a finishing job's paths and program, the run has what they left; stopped by its
    // meter, it runs again on a grid coarse enough for what is left then, if there is one.
    let coarser = coarser.map(|(lo_mm, hi_mm)| CoarserGrid {
        lo_mm,
        hi_mm,
        max_pitch_mm: COARSEST_PITCH_RADII * cutter.radius_mm,
    });
    let spent = || super::finish::spent_note(work_share, "the finishing job's paths and program");
    let (sim, coarsened) =
        pipeline::run_metered(stock, cutter, sample_step, program, work_share.cap(MAX_WORK), coarser).map_err(|e| {
            let note = if matches!(e, SimError::TooMuchWorkDone { .. }) { spent() } else { String::new() };
            Fatal(format!("{}: {e}{note}", program_name(a)))
        })?;
    if let Some(c) = coarsened {
        let pitch = sim.stock().grid().pitch_mm;
        eprintln!(
            "interpolab: {}: at pitch {} mm the run would take about {} million ray updates, more than the {} million the command had left{}; simulated at pitch {} mm instead (a --pitch of {} or more runs at once)",
            program_name(a),
            fmt_num(c.asked_pitch_mm),
            (c.projected / 1e6).round(),
            (c.left / 1e6).round().max(0.0),
            spent(),
            fmt_num(pitch),
            fmt_num(pitch),
        );
    }
    let run_ms = t0.elapsed().as_secs_f64() * 1e3;
    let Ok(Measures { map, stats }) = pipeline::measure(sim.stock(), design, usize::MAX, |_| Ok::<(), Infallible>(()));
    let has_design = !matches!(design, Design::None);
    super::write_height_files(
        a.out.as_deref(),
        a.png.as_deref(),
        a.band_um,
        &map,
        has_design.then_some(&stats),
        sim.stock().z_range_mm(),
    )?;
    let c = sim.counters();
    let crashes = super::crash_report(sim.crashes(), a.crashes.as_deref(), !cutter.body_given, |_| None)?;
    let g = map.grid;
    let um = |mm: f64| (mm * 1e6).round() / 1e3;
    // Lengths to the CSV's resolution (1e-6 mm), so a ray's x0 + (i + ½)·p prints as 45.75.
    let nm = |mm: f64| (mm * 1e6).round() / 1e6;
    let summary = json!({
        "format": "interpolab-simulate/1",
        "program": program_name(a),
        "cutter": cutter.describe(),
        "tool_body": cutter.describe_body(),
        "programmed_point": point.label(),
        "grid": { "nx": g.nx, "ny": g.ny, "pitch_mm": nm(g.pitch_mm), "x0_mm": nm(g.x0_mm), "y0_mm": nm(g.y0_mm) },
        "moves": c.moves,
        "chord_tol_mm": chord_tol,
        "chord_error_mm": nm(program.chord_error_mm),
        "sweep_tol_mm": sim.sweep_tol_mm().map(nm),
        "sweep_sagitta_mm": nm(c.sweep_sagitta_mm),
        "ray_updates": c.ray_updates,
        "run_ms": (run_ms * 1e3).round() / 1e3,
        "removed_volume_mm3": (c.removed_mm3 * 1e6).round() / 1e6,
        "machined_rays": stats.machined_rays,
        "through_rays": stats.through_rays,
        "split_rays": stats.split_rays,
        "rapid_cuts": c.rapid_cuts,
        "crashes": crashes,
        "memory_bytes": sim.stock().memory_bytes(),
        "design": design.name(),
        "scallop_um": has_design.then(|| json!({
            "rays": stats.scallop.count,
            "max": um(stats.scallop.max_mm),
            "mean": um(stats.scallop.mean_mm),
            "p95": um(stats.scallop.p95_mm),
        })),
        "gouge": stats.worst_gouge.map(|(d, p)| json!({ "worst_um": um(d), "x_mm": nm(p.x), "y_mm": nm(p.y), "rays": stats.gouge_rays })),
    });
    let mut summary = summary;
    if let (Some(c), Some(obj)) = (coarsened, summary.as_object_mut()) {
        obj.insert("pitch_asked_mm".to_owned(), json!(nm(c.asked_pitch_mm)));
    }
    if let (Some(info), Some(obj)) = (finish_info, summary.as_object_mut()) {
        obj.insert("finish".to_owned(), info);
    }
    if let (Some(passes), Some(obj)) = (interior_passes, summary.as_object_mut()) {
        let mask = interior_mask(&map.grid, &passes, INTERIOR_END_MM, INTERIOR_SIDE_MM);
        obj.insert("interior".to_owned(), interior_json(&interior_stats(&stats, &mask)));
    }
    let mut text = String::new();
    super::pretty_json(&summary, 0, &mut text);
    println!("{text}");
    Ok(ExitCode::SUCCESS)
}
