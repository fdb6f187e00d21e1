//! `interpolab time PROGRAM|SCENE --machine PRESET|FILE`: the time a program takes on a
//! machine — feed planned within the joints' velocity, acceleration and jerk limits, corners
//! blended within the contour tolerance, look-ahead — with per-block times and, with
//! `--periods`, every interpolation period as CSV (checked against the limits from the
//! positions alone before the command ends).

use std::fmt::Write as _;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use interpolab::gcode::interp::Canon;
use interpolab::gcode::read::MAX_PATH_MOVES;
use interpolab::gcode::{Dialect, ProgramKind, ProgramOptions, crease_design, write_program};
use interpolab::numerics::format::push_num;
use interpolab::plan::{Dynamics, LimitChecker, Period, Stopped, Timing, canon_of_toolpath, time_program, time_read};
use interpolab::report::fmt_num;

use super::Fatal;
use super::dynamics::{machine_of, machine_with};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum SceneKind {
    /// G01 lines.
    G01,
    /// G02/G03 arcs.
    Arcs,
    /// G06.2 NURBS.
    Nurbs,
}

/// `interpolab time`.
#[derive(Args, Debug)]
pub(crate) struct TimeArgs {
    /// A G-code program, or a scene (`.json`: its crease, written as the program `--kind`).
    pub input: PathBuf,
    /// The machine: a preset (hobby-router, vmc, table-ac, table-bc, head-bc,
    /// head-a-table-c) or a machine file (JSON: `{"preset": …, "axes": {…}, …}`, or a scene
    /// with a `dynamics` key). Default: the scene's `dynamics`, else vmc.
    #[arg(long)]
    pub machine: Option<String>,
    /// Contour tolerance P (mm) for corner blending, instead of the machine's; 0 stops at
    /// every corner.
    #[arg(long, value_parser = super::finite)]
    pub tolerance: Option<f64>,
    /// Exact stop at every corner (G61).
    #[arg(long)]
    pub exact_stop: bool,
    /// Look-ahead window in blocks, instead of the machine's (default the whole program).
    #[arg(long)]
    pub window: Option<usize>,
    /// Interpolation period Ts (ms), instead of the machine's.
    #[arg(long, value_parser = super::finite)]
    pub period: Option<f64>,
    /// Drop the jerk limits (acceleration may jump): the setting of the time-optimal bound.
    #[arg(long)]
    pub no_jerk: bool,
    /// Write every period as CSV: k, t_s, x, y, z (mm), a, b, c (deg), feed (mm/min),
    /// acceleration (mm/s²), jerk (mm/s³) along the path, and the block's line.
    #[arg(long)]
    pub periods: Option<PathBuf>,
    /// Write the time of every block as CSV.
    #[arg(long)]
    pub blocks: Option<PathBuf>,
    /// Write the planned path's geometry as CSV: s (mm), q, q' and q'' of the six joints
    /// (mm, rad), the feed cap (mm/s), every `--geometry-step` mm and at every piece's ends
    /// (what scripts/plan-anchors.py hands to TOPP-RA).
    #[arg(long)]
    pub geometry: Option<PathBuf>,
    /// Spacing of the `--geometry` samples (mm).
    #[arg(long, value_parser = super::finite, default_value_t = 0.25)]
    pub geometry_step: f64,
    /// For a scene: the program written from its crease.
    #[arg(long, value_enum, default_value = "nurbs")]
    pub kind: SceneKind,
    /// For a scene: the program's tolerance (mm).
    #[arg(long, value_parser = super::finite, default_value_t = 0.01)]
    pub program_tolerance: f64,
    /// For a scene: instead of a 3-axis program, the five-axis tool steps at this
    /// tolerance (mm) through the scene's machine, as the joint moves the machine makes.
    #[arg(long, value_parser = super::finite)]
    pub steps: Option<f64>,
    #[command(flatten)]
    pub read: super::program::ReadArgs,
}

fn is_scene(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

pub(super) fn time(a: &TimeArgs) -> Result<ExitCode, Fatal> {
    // Everything the user gave is checked before the program is read.
    let (canon, title, scene_machine) = if is_scene(&a.input) {
        if !(a.program_tolerance > 0.0) {
            return Err(Fatal("--program-tolerance must be a positive length in mm; give e.g. 0.01".to_owned()));
        }
        let base = match &a.machine {
            Some(m) => machine_of(m)?,
            None => match scene_dynamics(&a.input)? {
                Some(d) => d,
                None => default_machine()?,
            },
        };
        let machine = machine_with(base, a.tolerance, a.exact_stop, a.window, a.period, a.no_jerk)?;
        if let Some(tol) = a.steps {
            if !(tol > 0.0) {
                return Err(Fatal("--steps must be a positive tolerance in mm; give e.g. 0.01".to_owned()));
            }
            let (canon, title) = super::fiveaxis::scene_steps_program(&a.input, tol)?;
            return finish(a, canon, &title, &machine);
        }
        let (scene, job) = super::crease::load(&a.input)?;
        let design = crease_design(&job).map_err(|e| Fatal(format!("{}: {e}", a.input.display())))?;
        let kind = match a.kind {
            SceneKind::G01 => ProgramKind::Lines,
            SceneKind::Arcs => ProgramKind::Arcs,
            SceneKind::Nurbs => ProgramKind::Nurbs,
        };
        let opts = ProgramOptions::default().with_feed(scene.motion.feed).with_title(&scene.name);
        let p = write_program(kind, &design, a.program_tolerance, &opts).map_err(|e| Fatal(e.to_string()))?;
        let title = format!(
            "{} as {} at {} mm",
            a.input.display(),
            Dialect::Fanuc.kind_label(kind),
            fmt_num(a.program_tolerance)
        );
        (canon_of_toolpath(&p.parsed.toolpath), title, machine)
    } else {
        let base = match &a.machine {
            Some(m) => machine_of(m)?,
            None => default_machine()?,
        };
        let machine = machine_with(base, a.tolerance, a.exact_stop, a.window, a.period, a.no_jerk)?;
        let (timing, notes) = time_file(&a.input, &a.read, &machine)?;
        let code = report_timing(a, &timing, &a.input.display().to_string())?;
        for line in notes {
            eprintln!("{line}");
        }
        return Ok(code);
    };
    finish(a, canon, &title, &scene_machine)
}

fn finish(a: &TimeArgs, canon: Vec<Canon>, title: &str, machine: &Dynamics) -> Result<ExitCode, Fatal> {
    let timing = time_program(canon, machine).map_err(|e| Fatal(format!("{}: {e}", a.input.display())))?;
    report_timing(a, &timing, title)
}

/// The summary on standard output and the files the options ask for.
fn report_timing(a: &TimeArgs, timing: &Timing, title: &str) -> Result<ExitCode, Fatal> {
    if a.periods.is_some() {
        let periods = (timing.total_s() / timing.machine.period_s()).ceil();
        if !(periods <= MAX_PERIODS) {
            return Err(Fatal(format!(
                "--periods: the program takes {} s, {} periods of {} ms, more than {MAX_PERIODS} (about {} GB of CSV); time a part of it, or give a longer --period",
                if timing.total_s() < 1e7 {
                    format!("{:.1}", timing.total_s())
                } else {
                    format!("{:.3e}", timing.total_s())
                },
                fmt_num(periods),
                fmt_num(timing.machine.period_ms),
                fmt_num(MAX_PERIODS * 75.0 / 1e9),
            )));
        }
    }
    let mut out = summary(title, timing);
    if let Some(p) = &a.blocks {
        write_blocks(p, timing)?;
    }
    if let Some(p) = &a.geometry {
        write_geometry(p, timing, a.geometry_step)?;
    }
    if let Some(p) = &a.periods {
        let rep = write_periods(p, timing)?;
        let _ = writeln!(
            out,
            "periods      {} written to {}; checked from the positions: largest joint velocity/acceleration/jerk at {:.4} of its limit{}",
            rep.periods,
            p.display(),
            rep.worst_ratio,
            if rep.within() { "" } else { " — OVER A LIMIT" }
        );
    }
    let mut o = io::stdout().lock();
    let _ = o.write_all(out.as_bytes());
    Ok(ExitCode::SUCCESS)
}

fn default_machine() -> Result<Dynamics, Fatal> {
    Dynamics::preset("vmc").ok_or_else(|| Fatal("the vmc preset is missing (a bug; please report it)".to_owned()))
}

fn scene_dynamics(p: &Path) -> Result<Option<Dynamics>, Fatal> {
    let text = super::read_capped(p, interpolab::numerics::limits::MAX_SCENE_BYTES, "scene")
        .map_err(|e| Fatal(format!("cannot read scene file {}: {e}", p.display())))?;
    let scene = interpolab::scene::Scene::from_json(&text).map_err(|e| Fatal(format!("{}: {e}", p.display())))?;
    Ok(scene.dynamics)
}

/// A program file timed on `machine`: FANUC and LinuxCNC programs streamed from the
/// interpreter into the planner (the canonical motions are never held as a list; the planner
/// refuses at the line where its path passes its cap), Sinumerik through its reader; with the
/// interpreter's report lines, printed once nothing more can be refused.
fn time_file(path: &Path, read: &super::program::ReadArgs, machine: &Dynamics) -> Result<(Timing, Vec<String>), Fatal> {
    use std::io::Read as _;
    let mut head = Vec::new();
    fs::File::open(path)
        .and_then(|f| f.take(64 << 10).read_to_end(&mut head))
        .map_err(|e| Fatal(format!("cannot read program {}: {e}", path.display())))?;
    let plan_err = |e: interpolab::plan::PlanError| Fatal(format!("{}: {e}", path.display()));
    if Dialect::guess(&String::from_utf8_lossy(&head)) == Dialect::Sinumerik {
        let (parsed, _, _) = super::program::read_path(path, Some(Dialect::Sinumerik), read, MAX_PATH_MOVES)?;
        return Ok((time_program(canon_of_toolpath(&parsed.toolpath), machine).map_err(plan_err)?, Vec::new()));
    }
    let mut it = super::program::open(path, read.options())?;
    let timing = time_read(it.by_ref(), machine).map_err(|e| match e {
        Stopped::Read(e) => Fatal(format!("{}: {e}", path.display())),
        Stopped::Plan(e) => plan_err(e),
    })?;
    Ok((timing, super::program::report_lines_of(&it, path)))
}

/// One line naming a machine and its controller settings.
pub(crate) fn machine_note(m: &Dynamics) -> String {
    let ax = |i: usize| {
        let a = &m.axes[i];
        format!(
            "{} {} mm/min {} mm/s² {}",
            ["X", "Y", "Z"][i],
            fmt_num(a.velocity),
            fmt_num(a.acceleration),
            a.jerk.map_or("no jerk limit".to_owned(), |j| format!("{} mm/s³", fmt_num(j)))
        )
    };
    format!(
        "Times on the machine {} ({}, {}, {}; {}, look-ahead {}, Ts {} ms): the feed planned within these limits (interpolab time).",
        m.name,
        ax(0),
        ax(1),
        ax(2),
        if m.exact_stop || m.tolerance_mm <= 0.0 {
            "exact stop at corners".to_owned()
        } else {
            format!("corners blended within {} mm", fmt_num(m.tolerance_mm))
        },
        m.window_blocks.map_or("the whole program".to_owned(), |w| format!("{w} blocks")),
        fmt_num(m.period_ms)
    )
}

/// Four decimals, or four significant ones in exponent form from a billion on (a mistyped
/// coordinate of 40 digits does not print 40 digits).
fn four(x: f64) -> String {
    if x.abs() < 1e9 { format!("{x:.4}") } else { format!("{x:.4e}") }
}

fn summary(title: &str, t: &Timing) -> String {
    let m = &t.machine;
    let mut s = String::new();
    let (feed, rapid) = t.feed_rapid_s();
    let _ = writeln!(s, "program      {title}");
    let mut lim = String::new();
    for (i, ax) in m.axes.iter().enumerate().take(3) {
        let _ = write!(
            lim,
            "{}{} {} mm/min {} mm/s² {}",
            if i > 0 { ", " } else { "" },
            ["X", "Y", "Z"][i],
            fmt_num(ax.velocity),
            fmt_num(ax.acceleration),
            ax.jerk.map_or("no jerk limit".to_owned(), |j| format!("{} mm/s³", fmt_num(j)))
        );
    }
    let _ = writeln!(s, "machine      {}: {lim}", m.name);
    let _ = writeln!(
        s,
        "controller   {}, look-ahead {}, Ts {} ms",
        if m.exact_stop || m.tolerance_mm <= 0.0 {
            "exact stop at corners (G61)".to_owned()
        } else {
            format!("corners blended within P = {} mm (G64 P)", fmt_num(m.tolerance_mm))
        },
        m.window_blocks.map_or("the whole program".to_owned(), |w| format!("{w} blocks")),
        fmt_num(m.period_ms)
    );
    let _ = writeln!(
        s,
        "time         {} s (feed moves {} s, rapids {} s, dwell {} s)",
        four(t.total_s()),
        four(feed),
        four(rapid),
        four(t.path.dwell_s)
    );
    let _ = writeln!(
        s,
        "path         {} mm in {} blocks; {} corners blended (largest deviation {:.6} mm), {} stops at corners",
        four(t.path.length),
        t.path.blocks.len(),
        t.path.blends,
        t.path.max_blend_dev,
        t.path.corner_stops
    );
    let f_len: f64 = t.path.blocks.iter().filter(|b| !b.rapid).map(|b| b.len).sum();
    if feed > 0.0 {
        let _ = writeln!(s, "feed         mean {:.1} mm/min over the feed moves", 60.0 * f_len / feed);
    }
    s
}

/// Most samples `--geometry` writes.
const MAX_GEOMETRY_SAMPLES: usize = 2_000_000;
/// Most rows `--periods` writes (about 75 bytes each).
const MAX_PERIODS: f64 = 20_000_000.0;

fn write_geometry(p: &Path, t: &Timing, step: f64) -> Result<(), Fatal> {
    if !(step > 0.0) {
        return Err(Fatal("--geometry-step must be a positive length in mm; give e.g. 0.25".to_owned()));
    }
    let f = fs::File::create(p).map_err(|e| Fatal(format!("cannot create {}: {e}", p.display())))?;
    let mut w = BufWriter::with_capacity(1 << 16, f);
    let mut line = String::from("s,x,y,z,a,b,c,dx,dy,dz,da,db,dc,ddx,ddy,ddz,dda,ddb,ddc,feed_mm_per_s\n");
    let mut count = 0usize;
    for (k, piece) in t.path.pieces.iter().enumerate() {
        let n = ((piece.h / step).ceil() as usize).max(1);
        // A stop (v = 0) at the piece's start: the path's start, or after an element the
        // path stops at; its row carries feed 0.
        let stop = k == 0
            || (t.path.pieces[k - 1].elem != piece.elem && t.path.elems[t.path.pieces[k - 1].elem as usize].stop_after);
        let end_stop = t.path.pieces.get(k + 1).is_none_or(|q| q.elem != piece.elem)
            && t.path.elems[piece.elem as usize].stop_after;
        // Uniform samples, and near a stop samples closing in geometrically (step/2, /4, …
        // down to 2^-24 of the step): a grid's first interval from rest costs it
        // √(2h/a) where the motion needs less, so the bound comes closer from above.
        let mut at: Vec<f64> = (0..n).map(|i| piece.h * (i as f64 / n as f64)).collect();
        let first = piece.h / n as f64;
        for e in 1..=24 {
            let d = first * 0.5f64.powi(e);
            if stop {
                at.push(d);
            }
            if end_stop {
                at.push(piece.h - d);
            }
        }
        at.sort_by(f64::total_cmp);
        at.dedup();
        for (i, off) in at.iter().enumerate() {
            count += 1;
            if count > MAX_GEOMETRY_SAMPLES {
                return Err(Fatal(format!(
                    "--geometry: more than {MAX_GEOMETRY_SAMPLES} samples; give a larger --geometry-step"
                )));
            }
            geometry_row(&mut line, t, piece.s0 + off, stop && i == 0);
        }
        w.write_all(line.as_bytes()).map_err(|e| Fatal(format!("cannot write {}: {e}", p.display())))?;
        line.clear();
    }
    geometry_row(&mut line, t, t.path.length, true);
    w.write_all(line.as_bytes())
        .and_then(|()| w.flush())
        .map_err(|e| Fatal(format!("cannot write {}: {e}", p.display())))
}

fn geometry_row(line: &mut String, t: &Timing, s: f64, stop: bool) {
    let (q, q1, q2, feed) = t.path.derivatives_at(s);
    push_num(line, s);
    for v in q.iter().chain(&q1).chain(&q2) {
        line.push(',');
        push_num(line, *v);
    }
    line.push(',');
    push_num(
        line,
        if stop {
            0.0
        } else if feed.is_finite() {
            feed
        } else {
            1e9
        },
    );
    line.push('\n');
}

fn write_blocks(p: &Path, t: &Timing) -> Result<(), Fatal> {
    let mut out = String::from("block,line,kind,length_mm,time_s\n");
    for (i, (b, tt)) in t.path.blocks.iter().zip(&t.block_time_s).enumerate() {
        let _ = writeln!(
            out,
            "{i},{},{},{},{}",
            b.line,
            if b.rapid { "rapid" } else { "feed" },
            fmt_num(b.len),
            fmt_num(*tt)
        );
    }
    fs::write(p, out).map_err(|e| Fatal(format!("cannot write {}: {e}", p.display())))
}

fn write_periods(p: &Path, t: &Timing) -> Result<interpolab::plan::LimitReport, Fatal> {
    let f = fs::File::create(p).map_err(|e| Fatal(format!("cannot create {}: {e}", p.display())))?;
    let mut w = BufWriter::with_capacity(1 << 16, f);
    let ts = t.machine.period_s();
    let scale = t.path.length;
    let mut checker = LimitChecker::new(t.machine.joint_limits(), ts, 4.0 * f64::EPSILON * scale.max(1.0) * 1e3);
    let mut line = String::with_capacity(256);
    let _ = w.write_all(b"k,t_s,x,y,z,a,b,c,feed_mm_per_min,accel_mm_per_s2,jerk_mm_per_s3,line\n");
    let mut sm = t.sampler();
    let mut per = Period::default();
    let deg = 180.0 / std::f64::consts::PI;
    while sm.next_period(&mut per) {
        checker.push(&per.q);
        line.clear();
        let _ = write!(line, "{},", per.k);
        push_num(&mut line, per.t);
        for (i, q) in per.q.iter().enumerate() {
            line.push(',');
            push_num(&mut line, if i < 3 { *q } else { *q * deg });
        }
        line.push(',');
        push_num(&mut line, per.v * 60.0);
        line.push(',');
        push_num(&mut line, per.a);
        line.push(',');
        push_num(&mut line, per.j);
        let _ = writeln!(line, ",{}", t.path.blocks.get(per.block).map_or(0, |b| b.line));
        w.write_all(line.as_bytes()).map_err(|e| Fatal(format!("cannot write {}: {e}", p.display())))?;
    }
    w.flush().map_err(|e| Fatal(format!("cannot write {}: {e}", p.display())))?;
    Ok(checker.finish())
}
