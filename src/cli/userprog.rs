//! A user's program with its tools and machine: `simulate PROGRAM --tools FILE | --project
//! FILE.camotics | --tool N:shape:D [--machine KIND]` and `replay PROGRAM --machine KIND
//! --tolerance E` (the per-block nonlinear error of a rotary program). The program is read by
//! the interpreter into canonical motions and turned into the simulation's moves by
//! [`interpolab::simulate::canon`]; everything here parses options and prints.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, ValueEnum};
use glam::DVec3;
use interpolab::gcode::interp::tools::{CamoticsProject, TableUnits, ToolTable, parse_tool_spec};
use std::io::{self, Write as _};

use interpolab::gcode::interp::{Canon, FeedMode, Interpreter, Loc, Options};
use interpolab::geom::Cutter;
use interpolab::numerics::format::{fmt_fixed, fmt_num, push_num};
use interpolab::numerics::limits::MAX_TOOL_TABLE_BYTES;
use interpolab::simulate::canon::{
    BlockKind, CanonBuilder, CanonOptions, CanonProgram, KinematicsChoice, MachineSetup, RotaryMode,
};
use interpolab::simulate::{Design, DexelStock, HeightMap, NO_TOOL, SimStats, Simulation};
use serde_json::json;

use super::Fatal;
use super::program::ReadArgs;

/// Units of a LinuxCNC tool table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum TableUnitsArg {
    /// Millimetres (a machine set up in mm).
    Mm,
    /// Inches.
    Inch,
}

/// How the rotary words are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum KinematicsArg {
    /// Tool-centre-point control between M428/G43.4 and M429/G49, joints elsewhere.
    Auto,
    /// The words are the machine's joints.
    Joints,
    /// Tool-centre-point control: X Y Z are the tip in the workpiece (G43.4, TRAORI).
    Tcp,
}

/// The tools and machine of a user's program.
#[derive(Args, Debug, Clone)]
pub(crate) struct ToolArgs {
    /// LinuxCNC tool table (`.tbl`): T, Z (the tool's length), D; the shape from the
    /// remark's first word (flat, ball, bull r=1, v90, drill), else flat.
    #[arg(long)]
    pub tools: Option<PathBuf>,
    /// Units of --tools.
    #[arg(long, value_enum, default_value = "mm")]
    pub tool_units: TableUnitsArg,
    /// CAMotics project (`.camotics`): its tools, its workpiece as the stock, and its
    /// program files when PROGRAM is not given.
    #[arg(long)]
    pub project: Option<PathBuf>,
    /// A tool `N:shape:diameter[:corner|angle]` (mm, degrees), e.g. 1:ball:6, 2:bull:10:1,
    /// 3:v:6:90, 4:drill:8, then optional body words `,flute=L,shank=R:L,holder=R:L,nocentre`
    /// (mm); repeat for more; gives a table's tool of that number this cutter, keeping its
    /// length offset.
    #[arg(long = "tool")]
    pub tool_specs: Vec<String>,
    /// Machine of the rotary axes: table-ac, table-bc, head-bc, head-a-table-c, or wrap-a (a
    /// 4-axis rotary table about X); default: as the program's comments name it (LinuxCNC's
    /// `;TCP:xyzac`), else three axes (rotary words left out).
    #[arg(long)]
    pub machine: Option<String>,
    /// How the rotary words are read.
    #[arg(long, value_enum, default_value = "auto")]
    pub kinematics: KinematicsArg,
    /// Head machines: tool length from the last head axis to the tip (mm).
    #[arg(value_parser = super::finite, long, default_value_t = 0.0)]
    pub head_length: f64,
    /// Pivot of the tilting axis (A or B) `x,y,z` (mm): table machines, a point on the axis
    /// in the workpiece at zero angles; head machines, the offset from the control point.
    #[arg(long, allow_hyphen_values = true)]
    pub pivot_tilt: Option<String>,
    /// Pivot of the C axis `x,y,z` (mm), as --pivot-tilt.
    #[arg(long, allow_hyphen_values = true)]
    pub pivot_c: Option<String>,
}

impl ToolArgs {
    /// Whether any option asks for the user-program path.
    pub(crate) fn any(&self) -> bool {
        self.tools.is_some() || self.project.is_some() || !self.tool_specs.is_empty() || self.machine.is_some()
    }
}

fn vec3(text: &str, what: &str) -> Result<DVec3, Fatal> {
    let v: Vec<f64> = text.split(',').filter_map(|s| s.trim().parse::<f64>().ok()).collect();
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(Fatal(format!("--{what} `{text}`: give three comma-separated numbers x,y,z in mm")));
    }
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// The tools, machine and project a program is read with.
pub(crate) struct Setup {
    pub table: ToolTable,
    pub project: Option<(PathBuf, CamoticsProject)>,
    pub machine: Option<MachineSetup>,
    pub kinematics: KinematicsChoice,
}

pub(crate) fn setup(a: &ToolArgs) -> Result<Setup, Fatal> {
    let mut table = ToolTable::new();
    let mut project = None;
    if let Some(p) = &a.project {
        let text = super::read_capped(p, MAX_TOOL_TABLE_BYTES, "CAMotics project")
            .map_err(|e| Fatal(format!("cannot read project {}: {e}", p.display())))?;
        let proj = ToolTable::from_camotics(&text).map_err(|e| Fatal(format!("{}: {e}", p.display())))?;
        table = proj.tools.clone();
        project = Some((p.clone(), proj));
    }
    if let Some(p) = &a.tools {
        let text = super::read_capped(p, MAX_TOOL_TABLE_BYTES, "tool table")
            .map_err(|e| Fatal(format!("cannot read tool table {}: {e}", p.display())))?;
        let units = if a.tool_units == TableUnitsArg::Inch { TableUnits::Inch } else { TableUnits::Mm };
        let t = ToolTable::from_linuxcnc(&text, units).map_err(|e| Fatal(format!("{}: {e}", p.display())))?;
        for e in t.iter() {
            table.set(e.clone()).map_err(|e| Fatal(format!("{}: {e}", p.display())))?;
        }
    }
    for s in &a.tool_specs {
        let e = parse_tool_spec(s).map_err(|e| Fatal(format!("--tool {e}")))?;
        table.set_cutter(e).map_err(|e| Fatal(format!("--tool {s}: {e}")))?;
    }
    let machine = match &a.machine {
        None => None,
        Some(name) => {
            let mut m = MachineSetup::from_name(name, a.head_length).ok_or_else(|| {
                Fatal(format!("--machine {name}: not a machine; give one of {}", MachineSetup::NAMES.join(", ")))
            })?;
            if let Some(p) = &a.pivot_tilt {
                m.machine.pivots_mm[0] = vec3(p, "pivot-tilt")?;
            }
            if let Some(p) = &a.pivot_c {
                m.machine.pivots_mm[1] = vec3(p, "pivot-c")?;
            }
            Some(m)
        }
    };
    let kinematics = match a.kinematics {
        KinematicsArg::Auto => KinematicsChoice::Auto,
        KinematicsArg::Joints => KinematicsChoice::Joints,
        KinematicsArg::Tcp => KinematicsChoice::Tcp,
    };
    Ok(Setup { table, project, machine, kinematics })
}

/// The program files: PROGRAM, or the project's files beside the project.
pub(crate) fn program_files(program: Option<&Path>, s: &Setup) -> Result<Vec<PathBuf>, Fatal> {
    if let Some(p) = program {
        return Ok(vec![p.to_path_buf()]);
    }
    let Some((path, proj)) = &s.project else {
        return Err(Fatal("give a PROGRAM file (or --project with its files)".to_owned()));
    };
    if proj.files.is_empty() {
        return Err(Fatal(format!("{}: the project lists no program files; give PROGRAM", path.display())));
    }
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok(proj.files.iter().map(|f| dir.join(f)).collect())
}

/// A program read into moves, with the lines to print about it.
pub(crate) struct Read {
    pub program: CanonProgram,
    pub messages: Vec<String>,
    pub name: String,
    pub main_lines: u32,
}

fn loc_text(files: &[String], loc: Loc) -> String {
    match files.get(usize::from(loc.file)) {
        Some(f) if loc.file != 0 => format!("{f}:{}", loc.line),
        _ => loc.line.to_string(),
    }
}

/// Reads the program files through the interpreter (with the tool table) into a
/// [`CanonProgram`].
pub(crate) fn read(
    files: &[PathBuf],
    read: &ReadArgs,
    s: &Setup,
    default_cutter: Option<Cutter>,
    chord_tol_mm: f64,
) -> Result<Read, Fatal> {
    let mut opts = read.options();
    opts.tools = s.table.clone();
    opts.keep_comments = 64;
    if let Some((_, p)) = &s.project
        && p.units == TableUnits::Inch
    {
        opts.inch = true;
    }
    let name = files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" + ");
    let mut messages = Vec::new();
    let mut machine = s.machine;
    // The machine from the header when none is given: read the first file's comments.
    if machine.is_none()
        && let Some(first) = files.first()
    {
        let mut head = super::program::open(first, opts.clone())?;
        let mut n = 0;
        while n < 200 {
            match head.next() {
                Some(Ok(_)) => n += 1,
                _ => break,
            }
        }
        if let Some((m, loc)) = MachineSetup::from_comments(head.comments(), 0.0) {
            messages.push(format!(
                "machine      {} (named by the comment on line {}; --machine to choose another)",
                m.name(),
                loc.line
            ));
            machine = Some(m);
        }
    }
    let copts =
        CanonOptions { machine, kinematics: s.kinematics, chord_tol_mm, tools: s.table.clone(), default_cutter };
    let mut b = CanonBuilder::new(copts);
    let mut main_lines = 0;
    for path in files {
        let mut it: Interpreter<'static> = super::program::open(path, opts.clone())?;
        let mut sub_files = vec![String::new()];
        b.read(&mut it, |_| true).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
        for k in 1..64u16 {
            let n = it.file_name(k);
            if n.is_empty() {
                break;
            }
            sub_files.push(n.to_owned());
        }
        for w in it.warnings() {
            messages.push(format!("WARNING      {}: line {}: {}", path.display(), loc_text(&sub_files, w.loc), w.text));
        }
        for r in it.reports() {
            let times = if r.count == 1 { "once".to_owned() } else { format!("{} times", r.count) };
            messages.push(format!(
                "UNSUPPORTED  {}: line {}: {} ({times}): {}",
                path.display(),
                loc_text(&sub_files, r.first),
                r.code,
                r.what
            ));
        }
        main_lines += it.main_lines();
    }
    let program = b.finish();
    for n in &program.notes {
        messages.push(format!("NOTE         line {}: {}", n.loc.line, n.text));
    }
    if program.notes_dropped > 0 {
        messages.push(format!("NOTE         {} more notes left out", program.notes_dropped));
    }
    Ok(Read { program, messages, name, main_lines })
}

/// The per-tool totals as JSON.
fn tools_json(p: &CanonProgram) -> serde_json::Value {
    let r6 = |x: f64| (x * 1e6).round() / 1e6;
    json!(
        p.tools
            .iter()
            .map(|t| json!({
                "tool": t.number,
                "cutter": t.cutter.describe(),
                "body": t.cutter.describe_body(),
                "length_mm": r6(t.length_mm),
                "source": t.source,
                "first_line": t.first.line,
                "feed_blocks": t.feed_blocks,
                "rapid_blocks": t.rapid_blocks,
                "feed_mm": r6(t.feed_mm),
                "rapid_mm": r6(t.rapid_mm),
                "feed_time_min": r6(t.feed_min),
                "untimed_blocks": t.untimed_blocks,
                "removed_volume_mm3": r6(t.removed_mm3),
            }))
            .collect::<Vec<_>>()
    )
}

/// The nonlinear error summary: measured blocks, the largest and its line, those over `tol`.
fn nonlinear_json(p: &CanonProgram, tol: Option<f64>) -> serde_json::Value {
    let measured: Vec<_> =
        p.blocks.iter().filter_map(|b| b.rotary.and_then(|r| r.nonlinear_mm).map(|e| (b, e))).collect();
    let worst = measured.iter().copied().fold(None::<(&interpolab::simulate::canon::ProgramBlock, f64)>, |acc, x| {
        if acc.is_none_or(|a| x.1 > a.1) { Some(x) } else { acc }
    });
    let r6 = |x: f64| (x * 1e6).round() / 1e6;
    json!({
        "rotary_blocks": p.blocks.iter().filter(|b| b.rotary.is_some()).count(),
        "measured_blocks": measured.len(),
        "tcp_blocks": p.blocks.iter().filter(|b| b.rotary.is_some_and(|r| r.mode == RotaryMode::Tcp)).count(),
        "max_mm": worst.map(|w| r6(w.1)),
        "max_line": worst.map(|w| w.0.loc.line),
        "tolerance_mm": tol,
        "over_tolerance": tol.map(|t| p.over_tolerance(t).count()),
        "over_lines": tol.map(|t| p.over_tolerance(t).take(50).map(|b| b.loc.line).collect::<Vec<_>>()),
    })
}

/// Where the stock comes from.
pub(crate) struct StockChoice<'a> {
    pub given: Option<&'a str>,
    pub pitch: f64,
}

fn stock_of(c: &StockChoice<'_>, s: &Setup, p: &CanonProgram) -> Result<(DexelStock, String), Fatal> {
    if let Some(text) = c.given {
        return Ok((super::stock_block(text, c.pitch)?, "--stock".to_owned()));
    }
    let from_project = s.project.as_ref().and_then(|(_, proj)| proj.workpiece);
    let (b, how) = match from_project {
        Some(w) if !w.automatic && w.bounds_mm.is_some() => {
            let (lo, hi) = w.bounds_mm.unwrap_or_default();
            ([lo.x, lo.y, lo.z, hi.x, hi.y, hi.z], "the project's workpiece".to_owned())
        }
        other => {
            let margin = other.map_or(5.0, |w| w.margin_percent);
            let b = p.automatic_stock(margin).ok_or_else(|| {
                Fatal("the program has no feed moves to size the stock from; give --stock x0,y0,z0,x1,y1,z1".to_owned())
            })?;
            (b, format!("automatic (the cuts' box, top at z = 0, margin {margin} %, as CAMotics)"))
        }
    };
    let stock = DexelStock::block([b[0], b[1], b[2]], [b[3], b[4], b[5]], c.pitch).map_err(|e| Fatal(e.to_string()))?;
    Ok((stock, how))
}

/// Colours of the tool map: one per slot, cycling.
const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

fn tool_map_bytes(path: &Path, map: &HeightMap, slots: &[u16], p: &CanonProgram) -> Vec<u8> {
    let g = map.grid;
    let number = |s: u16| p.tools.get(usize::from(s)).map(|t| t.number);
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        let mut rgb = Vec::with_capacity(g.len() * 3);
        for row in 0..g.ny {
            let j = g.ny - 1 - row;
            for i in 0..g.nx {
                let s = slots.get(j * g.nx + i).copied().unwrap_or(NO_TOOL);
                rgb.extend_from_slice(&if s == NO_TOOL {
                    [220, 220, 220]
                } else {
                    PALETTE[usize::from(s) % PALETTE.len()]
                });
            }
        }
        return interpolab::simulate::measure::png_from_rgb(g.nx, g.ny, &rgb);
    }
    let mut out = String::with_capacity(g.len() * 32 + 32);
    out.push_str("i,j,x_mm,y_mm,tool\n");
    for j in 0..g.ny {
        for i in 0..g.nx {
            let s = slots.get(j * g.nx + i).copied().unwrap_or(NO_TOOL);
            let t = if s == NO_TOOL { String::new() } else { number(s).map_or(String::new(), |n| n.to_string()) };
            let _ = writeln!(out, "{i},{j},{},{},{t}", fmt_fixed(g.x_mm(i), 6), fmt_fixed(g.y_mm(j), 6));
        }
    }
    out.into_bytes()
}

/// What `simulate` passes on.
pub(crate) struct SimulateRequest<'a> {
    pub program: Option<&'a Path>,
    pub read: &'a ReadArgs,
    pub tools: &'a ToolArgs,
    pub cutter: Option<Cutter>,
    pub stock: StockChoice<'a>,
    pub chord_tol: f64,
    pub sample_step: Option<f64>,
    pub design: Design,
    pub out: Option<&'a Path>,
    pub png: Option<&'a Path>,
    pub tool_map: Option<&'a Path>,
    pub crashes: Option<&'a Path>,
    pub band_um: f64,
    pub tolerance: Option<f64>,
}

/// `simulate` with tools and a machine.
pub(crate) fn simulate(r: &SimulateRequest<'_>) -> Result<ExitCode, Fatal> {
    let s = setup(r.tools)?;
    let files = program_files(r.program, &s)?;
    let rd = read(&files, r.read, &s, r.cutter, r.chord_tol)?;
    for m in &rd.messages {
        eprintln!("interpolab: {m}");
    }
    let mut p = rd.program;
    let (stock, stock_how) = stock_of(&r.stock, &s, &p)?;
    let first = p
        .tools
        .first()
        .map(|t| t.cutter)
        .or(r.cutter)
        .ok_or_else(|| Fatal(format!("{}: the program makes no move with a tool; nothing to simulate", rd.name)))?;
    let mut sim = Simulation::new(stock, &first);
    if let Some(step) = r.sample_step {
        sim = sim.with_sample_step(step);
    }
    if r.tool_map.is_some() {
        sim = sim.with_tool_map();
    }
    let t0 = Instant::now();
    p.run(&mut sim, |_| true).map_err(|e| Fatal(format!("{}: {e}", rd.name)))?;
    let run_ms = t0.elapsed().as_secs_f64() * 1e3;
    let map = HeightMap::of(sim.stock());
    let stats = SimStats::of(&map, sim.stock(), &r.design);
    let has_design = !matches!(r.design, Design::None);
    super::write_height_files(r.out, r.png, r.band_um, &map, has_design.then_some(&stats), sim.stock().z_range_mm())?;
    if let (Some(path), Some(slots)) = (r.tool_map, sim.tool_map()) {
        super::write_file(path, &tool_map_bytes(path, &map, slots, &p))?;
    }
    let c = sim.counters();
    let assumed = p.tools.iter().any(|t| !t.cutter.body_given);
    let crashes = super::crash_report(sim.crashes(), r.crashes, assumed, |slot| {
        p.tools.get(usize::from(slot)).map(|t| t.number)
    })?;
    let g = map.grid;
    let um = |mm: f64| (mm * 1e6).round() / 1e3;
    let nm = |mm: f64| (mm * 1e6).round() / 1e6;
    let (z0, z1) = sim.stock().z_range_mm();
    let time: f64 = p.tools.iter().map(|t| t.feed_min).sum();
    let summary = json!({
        "format": "interpolab-simulate/1",
        "program": rd.name,
        "cutter": p.tools.first().map(|t| t.cutter.describe()),
        "programmed_point": "tool tip",
        "grid": { "nx": g.nx, "ny": g.ny, "pitch_mm": nm(g.pitch_mm), "x0_mm": nm(g.x0_mm), "y0_mm": nm(g.y0_mm) },
        "stock": { "z0_mm": nm(z0), "z1_mm": nm(z1), "from": stock_how },
        "machine": p.machine.map(|m| m.name()),
        "blocks": p.blocks.len(),
        "moves": c.moves,
        "chord_tol_mm": r.chord_tol,
        "chord_error_mm": nm(p.program.chord_error_mm),
        "sweep_sagitta_mm": nm(c.sweep_sagitta_mm),
        "ray_updates": c.ray_updates,
        "run_ms": (run_ms * 1e3).round() / 1e3,
        "removed_volume_mm3": nm(c.removed_mm3),
        "feed_time_min": nm(time),
        "tools": tools_json(&p),
        "nonlinear": p.machine.map(|_| nonlinear_json(&p, r.tolerance)),
        "machined_rays": stats.machined_rays,
        "through_rays": stats.through_rays,
        "split_rays": stats.split_rays,
        "rapid_cuts": c.rapid_cuts,
        "crashes": crashes,
        "memory_bytes": sim.stock().memory_bytes(),
        "design": r.design.name(),
        "scallop_um": has_design.then(|| json!({
            "rays": stats.scallop.count,
            "max": um(stats.scallop.max_mm),
            "mean": um(stats.scallop.mean_mm),
            "p95": um(stats.scallop.p95_mm),
        })),
        "gouge": stats.worst_gouge.map(|(d, p)| json!({ "worst_um": um(d), "x_mm": nm(p.x), "y_mm": nm(p.y), "rays": stats.gouge_rays })),
        "notes": p.notes.iter().map(|n| format!("line {}: {}", n.loc.line, n.text)).collect::<Vec<_>>(),
    });
    let mut text = String::new();
    super::pretty_json(&summary, 0, &mut text);
    println!("{text}");
    Ok(ExitCode::SUCCESS)
}

/// `replay PROGRAM --machine KIND [--tolerance E]`: the per-block nonlinear error table.
pub(crate) fn replay(
    program: &Path,
    read_args: &ReadArgs,
    tools: &ToolArgs,
    tolerance: Option<f64>,
    all: bool,
) -> Result<ExitCode, Fatal> {
    if let Some(t) = tolerance
        && !(t > 0.0)
    {
        return Err(Fatal(format!("--tolerance {t}: give a positive length in mm, e.g. 0.01")));
    }
    let s = setup(tools)?;
    // No cutter is needed to read the motions: the default is a placeholder for tools the
    // table lacks (lengths zero).
    let placeholder = Cutter::flat(1.0).ok();
    let rd = read(&[program.to_path_buf()], read_args, &s, placeholder, 0.01)?;
    let p = &rd.program;
    let mut out = String::new();
    let _ = writeln!(out, "program      {} ({} lines, {} motions)", rd.name, rd.main_lines, p.blocks.len());
    let Some(m) = p.machine else {
        return Err(Fatal(format!(
            "{}: no machine: give --machine (table-ac, table-bc, head-bc, head-a-table-c, wrap-a)",
            rd.name
        )));
    };
    let [tilt, c] = m.words().map(|i| ['A', 'B', 'C'][i]);
    let piv = m.machine.pivots_mm;
    let _ = writeln!(
        out,
        "machine      {} (axes {tilt}{}; pivots {tilt} ({}, {}, {}), C ({}, {}, {}) mm{})",
        m.name(),
        if m.four_axis { String::new() } else { format!(", {c}") },
        fmt_num(piv[0].x),
        fmt_num(piv[0].y),
        fmt_num(piv[0].z),
        fmt_num(piv[1].x),
        fmt_num(piv[1].y),
        fmt_num(piv[1].z),
        if m.machine.kind.uses_tool_length() {
            format!("; tool length {} mm", fmt_num(m.machine.tool_length_mm))
        } else {
            String::new()
        }
    );
    for msg in &rd.messages {
        let _ = writeln!(out, "{msg}");
    }
    let feed_time: f64 = p.tools.iter().map(|t| t.feed_min).sum();
    let untimed: usize = p.tools.iter().map(|t| t.untimed_blocks).sum();
    let _ = writeln!(
        out,
        "time         {} min at the programmed feed ({} feed blocks{})",
        fmt_fixed(feed_time, 4),
        p.blocks.iter().filter(|b| b.kind != BlockKind::Rapid).count(),
        if untimed > 0 { format!(", {untimed} without a time") } else { String::new() }
    );
    let rotary: Vec<_> = p.blocks.iter().filter(|b| b.rotary.is_some()).collect();
    let measured: Vec<_> =
        rotary.iter().filter_map(|b| b.rotary.and_then(|r| r.nonlinear_mm).map(|e| (*b, e))).collect();
    let tcp = rotary.iter().filter(|b| b.rotary.is_some_and(|r| r.mode == RotaryMode::Tcp)).count();
    let _ = writeln!(
        out,
        "rotary       {} blocks turn a rotary axis ({} read as TCP, {} as joints); {} measured",
        rotary.len(),
        tcp,
        rotary.len() - tcp,
        measured.len()
    );
    if tcp > 0 {
        let _ = writeln!(
            out,
            "note         TCP blocks: the controller keeps the tip on the chord; their error is what the same poses give with the joints interpolated linearly (a machine without TCP)"
        );
    }
    let worst = measured.iter().copied().fold(None::<(&interpolab::simulate::canon::ProgramBlock, f64)>, |acc, x| {
        if acc.is_none_or(|a| x.1 > a.1) { Some(x) } else { acc }
    });
    if let Some((b, e)) = worst {
        let _ = writeln!(out, "nonlinear    max {} mm at line {}", fmt_fixed(e, 6), b.loc.line);
    }
    let over = tolerance.map(|t| measured.iter().filter(|(_, e)| *e > t).count());
    if let (Some(t), Some(n)) = (tolerance, over) {
        let _ = writeln!(out, "tolerance    {} mm: {n} of {} blocks over", fmt_num(t), measured.len());
    }
    let _ = writeln!(
        out,
        "\n{:>8} {:>5} {:>10} {:>10} {:>10} {:>12} {:>5}  worst tip (x, y, z) mm",
        "line",
        "mode",
        format!("d{tilt}_deg"),
        format!("d{c}_deg"),
        "chord_mm",
        "nonlinear_mm",
        "over"
    );
    for (b, e) in &measured {
        let is_over = tolerance.is_some_and(|t| *e > t);
        if !(all || tolerance.is_none() || is_over) {
            continue;
        }
        let Some(r) = b.rotary else { continue };
        let d = [
            (r.to.rotary_rad[0] - r.from.rotary_rad[0]).to_degrees(),
            (r.to.rotary_rad[1] - r.from.rotary_rad[1]).to_degrees(),
        ];
        let _ = writeln!(
            out,
            "{:>8} {:>5} {:>10} {:>10} {:>10} {:>12} {:>5}  ({}, {}, {})",
            b.loc.line,
            if r.mode == RotaryMode::Tcp { "tcp" } else { "joint" },
            fmt_fixed(d[0], 4),
            fmt_fixed(d[1], 4),
            fmt_fixed((r.tip_to - r.tip_from).length(), 4),
            fmt_fixed(*e, 6),
            if is_over { "*" } else { "" },
            fmt_fixed(r.worst_tip.x, 4),
            fmt_fixed(r.worst_tip.y, 4),
            fmt_fixed(r.worst_tip.z, 4),
        );
    }
    print!("{out}");
    Ok(if over.is_some_and(|n| n > 0) { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

/// `interpolab canon PROGRAM`.
#[derive(Args, Debug)]
pub(crate) struct CanonArgs {
    /// The G-code program (RS274/NGC, LinuxCNC or FANUC); subroutine files are looked for
    /// beside it (`o<name> call` → `name.ngc`, `M98 P1234` → `O1234.nc`).
    pub program: PathBuf,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Tools (`--tools`, `--project`, `--tool`): G43 takes their lengths, G41/G42 their radii.
    #[command(flatten)]
    pub tools: ToolArgs,
}

/// Prints the program's canonical calls.
pub(crate) fn canon(a: &CanonArgs) -> Result<ExitCode, Fatal> {
    let table = setup(&a.tools)?.table;
    let mut it = super::program::open(&a.program, Options { tools: table, ..a.read.options() })?;
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    let mut line = String::new();
    let nums = |s: &mut String, v: &[f64]| {
        for x in v {
            s.push(' ');
            push_num(s, *x);
        }
    };
    while let Some(c) = it.next() {
        let c = c.map_err(|e| Fatal(format!("{}: {e}", a.program.display())))?;
        line.clear();
        let at = super::program::canon_loc(&it, c.loc());
        match &c {
            Canon::Traverse { end, .. } => {
                let _ = write!(line, "TRAVERSE {at}");
                nums(&mut line, &[end.xyz.x, end.xyz.y, end.xyz.z, end.abc.x, end.abc.y, end.abc.z]);
            }
            Canon::Line { end, feed, .. } => {
                let _ = write!(line, "LINE {at}");
                nums(&mut line, &[end.xyz.x, end.xyz.y, end.xyz.z, end.abc.x, end.abc.y, end.abc.z]);
                let _ = write!(line, " F{}", feed_text(feed.mode));
                nums(&mut line, &[feed.rate]);
            }
            Canon::Arc { end, center, plane, turns, feed, .. } => {
                let _ = write!(line, "ARC {at}");
                nums(&mut line, &[end.xyz.x, end.xyz.y, end.xyz.z, end.abc.x, end.abc.y, end.abc.z]);
                let _ = write!(line, " C");
                nums(&mut line, &[center.x, center.y, center.z]);
                let _ = write!(line, " {} {turns} F{}", plane.gcode(), feed_text(feed.mode));
                nums(&mut line, &[feed.rate]);
            }
            Canon::Spline { curve, end, feed, .. } => {
                let _ = write!(line, "SPLINE {at} degree {} points {}", curve.degree(), curve.len());
                nums(&mut line, &[end.xyz.x, end.xyz.y, end.xyz.z]);
                let _ = write!(line, " F{}", feed_text(feed.mode));
                nums(&mut line, &[feed.rate]);
            }
            Canon::Dwell { seconds, .. } => {
                let _ = write!(line, "DWELL {at}");
                nums(&mut line, &[*seconds]);
            }
            Canon::ToolChange { tool, .. } => {
                let _ = write!(line, "TOOL {at} {tool}");
            }
            Canon::ToolLengthOffset { offset, .. } => {
                let _ = write!(line, "TOOL_OFFSET {at}");
                nums(&mut line, &[offset.x, offset.y, offset.z]);
            }
            Canon::Spindle { rpm, .. } => {
                let _ = write!(line, "SPINDLE {at}");
                nums(&mut line, &[*rpm]);
            }
            Canon::Stop { end, .. } => {
                let _ = write!(line, "{} {at}", if *end { "END" } else { "STOP" });
            }
        }
        line.push('\n');
        out.write_all(line.as_bytes()).map_err(|e| Fatal(e.to_string()))?;
    }
    out.flush().map_err(|e| Fatal(e.to_string()))?;
    super::program::report(&it, &a.program);
    Ok(ExitCode::SUCCESS)
}

fn feed_text(m: FeedMode) -> &'static str {
    match m {
        FeedMode::PerMinute => "",
        FeedMode::InverseTime => "inverse",
        FeedMode::PerRevolution => "rev",
    }
}
