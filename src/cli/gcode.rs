//! `gcode`, `replay`, `compare`, `nurbs`: seed 004's programs and real-time NURBS
//! interpolation on the design path of a scene (its ball-centre crease) or on the
//! parabola-like comparison profile.
//!
//! Exit status: 0 success; 1 `replay` found a deviation above `--tolerance` or words it
//! does not model; 2 bad input (one line on standard error naming the problem and the fix).

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, ValueEnum};

use super::Fatal;

use interpolab::gcode::{
    CompareOptions, DeviationOptions, Dialect, ExtraColumns, ProgramKind, ProgramOptions, ProgrammedPoint, Segment,
    Summarizer, TableStyle, compare, crease_design, deviation, format_comparisons_with, summarize, write_program,
};
use interpolab::geom::Curve3;
use interpolab::jobs::program_row::{CycleTime, cycle_time};
use interpolab::nurbs_path::measure::Translated;
use interpolab::nurbs_path::{Parabola, RealtimeOptions, Update, interpolate_realtime};
use interpolab::report::{fmt_fixed, fmt_num};

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum KindArg {
    /// G01 lines by equal-error chords.
    G01,
    /// G02/G03 arcs (G17/G18/G19, helical where valid) and G01 lines.
    Arcs,
    /// FANUC-style G06.2 NURBS.
    Nurbs,
}

/// `--dialect`: one dialect, or (for `compare`) `all`.
#[derive(Clone, Debug)]
pub(crate) struct DialectsArg(Vec<Dialect>);

fn parse_dialects(s: &str) -> Result<DialectsArg, String> {
    if s.trim().eq_ignore_ascii_case("all") {
        return Ok(DialectsArg(Dialect::ALL.to_vec()));
    }
    s.parse::<Dialect>().map(|d| DialectsArg(vec![d])).map_err(|e| format!("{e} (or all, for compare)"))
}

impl DialectsArg {
    /// The one dialect of `gcode` and `nurbs`.
    fn one(&self) -> Result<Dialect, Fatal> {
        match self.0.as_slice() {
            [d] => Ok(*d),
            _ => Err(Fatal("--dialect all is for compare; give one of fanuc, sinumerik, linuxcnc".to_owned())),
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum ProfileArg {
    /// y = x²/40 for x from −60 to 60 mm (z = 0): a parabola-like profile like the NURBS paper's.
    Parabola,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum PointArg {
    /// The ball centre (the x, y, z of `interpolab run`).
    Centre,
    /// The ball tip of a 3-axis ball end mill: centre − R·ẑ.
    Tip,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum UpdateArg {
    /// First-order Taylor update.
    First,
    /// Second-order Taylor update.
    Second,
    /// Second order corrected by a Newton step on the chord length.
    Corrected,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum TableArg {
    /// Markdown tables.
    Markdown,
    /// CSV.
    Csv,
}

/// The design path: a scene's crease or a built-in profile.
#[derive(Args)]
pub(crate) struct DesignArgs {
    /// Scene file (interpolab-scene/1 JSON); its ball-centre crease is the design path.
    scene: Option<PathBuf>,
    /// A built-in profile instead of a scene.
    #[arg(long, value_enum, conflicts_with = "scene")]
    profile: Option<ProfileArg>,
}

/// Options shared by the program writers.
#[derive(Args)]
pub(crate) struct ProgramArgs {
    /// Tolerance E (mm): every program stays within E of the design path after rounding.
    #[arg(value_parser = super::finite, long)]
    tolerance: f64,
    /// Machine resolution (mm), a power of ten; numbers are rounded to it.
    #[arg(value_parser = super::finite, long, default_value_t = 0.001)]
    resolution: f64,
    /// Programmed point.
    #[arg(long, value_enum, default_value = "centre")]
    point: PointArg,
    /// Feed F (mm/min); default the scene's motion.feed (1500 for a profile).
    #[arg(value_parser = super::finite, long)]
    feed: Option<f64>,
    /// Ball radius R for `--point tip` with a profile (mm); a scene gives its tool.radius.
    #[arg(value_parser = super::finite, long)]
    tool_radius: Option<f64>,
    /// Absolute safe height (mm); default 5 mm above the highest point of the path.
    #[arg(value_parser = super::finite, long)]
    safe_z: Option<f64>,
    /// Degree of G06.2 curves (1 to 3; BSPLINE and G5.2: 2 or 3).
    #[arg(long, default_value_t = 3)]
    degree: usize,
    /// Controller dialect: fanuc (G06.2), sinumerik (BSPLINE), linuxcnc (G5.2, XY only);
    /// `compare` also takes all.
    #[arg(long, default_value = "fanuc", value_parser = parse_dialects)]
    dialect: DialectsArg,
}

#[derive(Args)]
pub(crate) struct GcodeArgs {
    #[command(flatten)]
    design: DesignArgs,
    /// Program kind.
    #[arg(long, value_enum)]
    kind: KindArg,
    #[command(flatten)]
    program: ProgramArgs,
    /// Number the blocks N10, N20, …
    #[arg(long)]
    line_numbers: bool,
    /// Write to this file instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Args)]
pub(crate) struct CompareArgs {
    #[command(flatten)]
    design: DesignArgs,
    #[command(flatten)]
    program: ProgramArgs,
    /// Table format.
    #[arg(long, value_enum, default_value = "markdown")]
    format: TableArg,
    /// Add the time each program takes on this machine (a preset or a machine file; see
    /// `interpolab time`): feed planned within its limits, corners blended within its
    /// contour tolerance.
    #[arg(long)]
    machine: Option<String>,
    /// With --machine: its contour tolerance P (mm) instead of the machine's.
    #[arg(long, value_parser = super::finite)]
    blend_tolerance: Option<f64>,
    /// With --machine: without jerk limits.
    #[arg(long)]
    no_jerk: bool,
}

#[derive(Args)]
pub(crate) struct ReplayArgs {
    /// The program to read.
    program: PathBuf,
    /// Compare with this scene's ball-centre crease.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Compare with a built-in profile.
    #[arg(long, value_enum, conflicts_with = "scene")]
    profile: Option<ProfileArg>,
    /// Programmed point of the program; default: as its header says (ours), else the centre.
    #[arg(long, value_enum)]
    point: Option<PointArg>,
    /// Ball radius for `--point tip` with a profile (mm).
    #[arg(value_parser = super::finite, long)]
    tool_radius: Option<f64>,
    /// Report whether the deviation is within this tolerance (mm); exit 1 if not.
    #[arg(value_parser = super::finite, long)]
    tolerance: Option<f64>,
    /// Dialect of the program: fanuc, sinumerik or linuxcnc; default guessed from the text
    /// (our header's DIALECT comment, else BSPLINE/SD=/PL=/PW=/G710 → sinumerik,
    /// G5.2/G5.3 → linuxcnc, else fanuc).
    #[arg(long, value_parser = parse_dialect)]
    dialect: Option<Dialect>,
    #[command(flatten)]
    read: super::program::ReadArgs,
    #[command(flatten)]
    tools: super::userprog::ToolArgs,
    /// With --machine and --tolerance: list every block that turns a rotary axis, not only
    /// those over the tolerance.
    #[arg(long)]
    all: bool,
}

fn parse_dialect(s: &str) -> Result<Dialect, String> {
    s.parse::<Dialect>().map_err(|e| e.to_string())
}

#[derive(Args)]
pub(crate) struct NurbsArgs {
    #[command(flatten)]
    design: DesignArgs,
    #[command(flatten)]
    program: ProgramArgs,
    /// Parameter update of each period.
    #[arg(long, value_enum, default_value = "corrected")]
    update: UpdateArg,
    /// Interpolation period Ts (ms); default the scene's motion.period (4 for a profile).
    #[arg(value_parser = super::finite, long)]
    period: Option<f64>,
    /// Chord tolerance of the curvature-based feed limit (mm); default none.
    #[arg(value_parser = super::finite, long)]
    chord_tol: Option<f64>,
    /// Write the per-period CSV to this file instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// A loaded design path with the scene's motion and tool.
struct Design {
    curve: Box<dyn Curve3>,
    title: String,
    feed: f64,
    period_ms: f64,
    ball_radius: Option<f64>,
}

fn load_design(scene: Option<&Path>, profile: Option<ProfileArg>) -> Result<Design, Fatal> {
    match (scene, profile) {
        (Some(path), _) => {
            let (scene, job) = super::crease::load(path)?;
            let curve = crease_design(&job).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
            let title = if scene.name.is_empty() { path.display().to_string() } else { scene.name.clone() };
            Ok(Design {
                curve: Box::new(curve),
                title,
                feed: scene.motion.feed,
                period_ms: scene.motion.period,
                ball_radius: Some(job.ball_radius_mm),
            })
        }
        (None, Some(ProfileArg::Parabola)) => Ok(Design {
            curve: Box::new(Parabola::paper_like()),
            title: "parabola y = x^2/40, x from -60 to 60 mm".to_owned(),
            feed: 1500.0,
            period_ms: 4.0,
            ball_radius: None,
        }),
        (None, None) => Err(Fatal("give a scene file, or --profile parabola".to_owned())),
    }
}

fn point_of(arg: PointArg, tool_radius: Option<f64>, design: &Design) -> Result<ProgrammedPoint, Fatal> {
    match arg {
        PointArg::Centre => Ok(ProgrammedPoint::BallCentre),
        PointArg::Tip => {
            let r = tool_radius
                .or(design.ball_radius)
                .ok_or_else(|| Fatal("--point tip needs the ball radius: give --tool-radius (mm)".to_owned()))?;
            if !(r.is_finite() && r > 0.0) {
                return Err(Fatal(format!("--tool-radius must be a positive length in mm, got {r}")));
            }
            Ok(ProgrammedPoint::BallTip { radius_mm: r })
        }
    }
}

fn program_options(a: &ProgramArgs, design: &Design) -> Result<ProgramOptions, Fatal> {
    let feed = a.feed.unwrap_or(design.feed);
    let dialect = a.dialect.0.first().copied().unwrap_or_default();
    Ok(ProgramOptions::default()
        .with_dialect(dialect)
        .with_resolution(a.resolution)
        .with_feed(feed)
        .with_point(point_of(a.point, a.tool_radius, design)?)
        .with_title(&design.title)
        .with_degree(a.degree)
        .with_safe_z(a.safe_z))
}

fn kind_of(k: KindArg) -> ProgramKind {
    match k {
        KindArg::G01 => ProgramKind::Lines,
        KindArg::Arcs => ProgramKind::Arcs,
        KindArg::Nurbs => ProgramKind::Nurbs,
    }
}

fn write_out(out: Option<&Path>, text: &str) -> Result<(), Fatal> {
    match out {
        Some(p) => fs::write(p, text).map_err(|e| Fatal(format!("cannot write {}: {e}", p.display()))),
        None => {
            let mut o = io::stdout().lock();
            match o.write_all(text.as_bytes()).and_then(|()| o.flush()) {
                Ok(()) => Ok(()),
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(Fatal(format!("cannot write the output: {e}"))),
            }
        }
    }
}

pub(super) fn gcode(a: &GcodeArgs) -> Result<ExitCode, Fatal> {
    let design = load_design(a.design.scene.as_deref(), a.design.profile)?;
    let opts =
        program_options(&a.program, &design)?.with_line_numbers(a.line_numbers).with_dialect(a.program.dialect.one()?);
    let kind = kind_of(a.kind);
    let p = write_program(kind, design.curve.as_ref(), a.program.tolerance, &opts).map_err(|e| Fatal(e.to_string()))?;
    write_out(a.out.as_deref(), &p.text)?;
    let _ = writeln!(
        io::stderr(),
        "interpolab: {} program: {} path blocks, {} bytes, max deviation {} mm after rounding to {} mm (tolerance {} mm){}",
        opts.dialect.kind_label(kind),
        p.path_blocks,
        p.bytes(),
        fmt_fixed(p.deviation.max_mm(), 6),
        fmt_num(a.program.resolution),
        fmt_num(a.program.tolerance),
        p.blend_mm.map_or(String::new(), |b| format!(", G64 P{} blending", fmt_num(b)))
    );
    Ok(ExitCode::SUCCESS)
}

pub(super) fn compare_cmd(a: &CompareArgs) -> Result<ExitCode, Fatal> {
    // The machine is checked before any program is written.
    let machine = match &a.machine {
        Some(m) => Some(super::dynamics::machine_with(
            super::dynamics::machine_of(m)?,
            a.blend_tolerance,
            false,
            None,
            None,
            a.no_jerk,
        )?),
        None if a.blend_tolerance.is_some() || a.no_jerk => {
            return Err(Fatal("--blend-tolerance and --no-jerk need --machine; give --machine vmc".to_owned()));
        }
        None => None,
    };
    let design = load_design(a.design.scene.as_deref(), a.design.profile)?;
    let mut cs = Vec::new();
    for &dialect in &a.program.dialect.0 {
        let opts = CompareOptions {
            program: program_options(&a.program, &design)?.with_dialect(dialect),
            period_ms: design.period_ms,
            chord_tol_mm: None,
        };
        let c = compare(design.curve.as_ref(), a.program.tolerance, &opts)
            .map_err(|e| Fatal(format!("{}: {e}", dialect.label())))?;
        cs.push(c);
    }
    let style = match a.format {
        TableArg::Markdown => TableStyle::Markdown,
        TableArg::Csv => TableStyle::Csv,
    };
    let mut extra = ExtraColumns::default();
    if let Some(m) = &machine {
        extra.heads = CycleTime::HEADS.map(str::to_owned).to_vec();
        for c in &cs {
            let mut rows = Vec::new();
            for r in &c.rows {
                // The time the app's comparison job gives its row (one function for both).
                let t = cycle_time(&r.program.parsed.toolpath, m).map_err(|e| Fatal(e.to_string()))?;
                rows.push(t.cells().to_vec());
            }
            extra.cells.push(rows);
        }
        extra.notes.push(super::time::machine_note(m));
    }
    write_out(None, &format_comparisons_with(&cs, &extra, style))?;
    Ok(ExitCode::SUCCESS)
}

fn v3(p: glam::DVec3) -> String {
    format!("({}, {}, {})", fmt_fixed(p.x, 4), fmt_fixed(p.y, 4), fmt_fixed(p.z, 4))
}

pub(super) fn replay(a: &ReplayArgs) -> Result<ExitCode, Fatal> {
    if a.tools.machine.is_some() {
        if a.scene.is_some() || a.profile.is_some() {
            return Err(Fatal(
                "--machine reports the program's own nonlinear error; leave out --scene and --profile".to_owned(),
            ));
        }
        return super::userprog::replay(&a.program, &a.read, &a.tools, a.tolerance, a.all);
    }
    // Measured against a design, a program is held to less work (each move is searched, a
    // curve costing more than a line), refused as it is read.
    use interpolab::gcode::Motion;
    use interpolab::numerics::limits::{DEVIATION_CURVE_WEIGHT, MAX_DEVIATION_MOVES};
    let measured = a.scene.is_some() || a.profile.is_some();
    let deviation_work =
        |m: &Motion| if matches!(m, Motion::Rapid | Motion::Linear) { 1 } else { DEVIATION_CURVE_WEIGHT };
    let over = |line: usize| {
        format!(
            "line {line}: measuring the moves so far against a design is more than {MAX_DEVIATION_MOVES} line-equivalents of work (an arc or curve counts {DEVIATION_CURVE_WEIGHT}); split the program or replay it without --scene"
        )
    };
    // Without a design only the summary is asked for: the moves stream through it and none
    // is held (the reader still refuses past its cap of moves, where it would when holding).
    let (parsed, dialect, how, s, path_blocks) = if measured {
        let weighing =
            super::program::Weighing { max_work: MAX_DEVIATION_MOVES, weight: &deviation_work, over: Some(&over) };
        let (parsed, dialect, how) = super::program::read_path_weighed(&a.program, a.dialect, &a.read, &weighing)?;
        let s = summarize(&parsed.toolpath);
        let path_blocks = parsed.path_blocks();
        (parsed, dialect, how, s, path_blocks)
    } else {
        // The path blocks a program's curves take depend on its dialect, known once it is
        // read (it may be guessed): counted in each.
        const DIALECTS: [Dialect; 3] = [Dialect::Fanuc, Dialect::Sinumerik, Dialect::LinuxCnc];
        let mut sum = Summarizer::default();
        let mut path_blocks = [0usize; 3];
        let (parsed, dialect, how) = super::program::read_path_streamed(&a.program, a.dialect, &a.read, &mut |b| {
            sum.add(b);
            if b.motion != Motion::Rapid {
                for (n, d) in path_blocks.iter_mut().zip(DIALECTS) {
                    *n += if let Segment::Nurbs(c) = &b.segment { d.nurbs_blocks(c) } else { 1 };
                }
            }
        })?;
        let path_blocks = DIALECTS.iter().zip(path_blocks).find(|(d, _)| **d == dialect).map_or(0, |(_, n)| n);
        (parsed, dialect, how, sum.finish(), path_blocks)
    };
    let mut lines = vec![
        format!("program      {} ({} lines, {} blocks)", a.program.display(), parsed.lines, parsed.blocks),
        format!("dialect      {dialect} ({}), {how}", dialect.label()),
        format!(
            "moves        G00 {}, G01 {}, G02 {}, G03 {}, {} curves {} ({} control points); path blocks {}",
            s.moves[0],
            s.moves[1],
            s.moves[2],
            s.moves[3],
            dialect.kind_label(ProgramKind::Nurbs),
            s.moves[4],
            s.nurbs_control_points,
            path_blocks
        ),
        format!("length       cutting {:.4} mm, rapid {:.4} mm", s.cut_length_mm + 0.0, s.rapid_length_mm + 0.0),
    ];
    if let Some((lo, hi)) = s.bounds {
        lines.push(format!("bounds       {} to {} mm", v3(lo), v3(hi)));
    }
    if let Some((lo, hi)) = s.feed_range {
        lines.push(format!("feed         {} to {} mm/min", fmt_num(lo), fmt_num(hi)));
    }
    let blend = parsed.blend_mm.unwrap_or(0.0);
    if let Some(b) = parsed.blend_mm {
        lines.push(format!(
            "blending     G64 P{} mm: the control may leave the programmed path by up to that much more",
            fmt_num(b)
        ));
    }
    lines.extend(super::program::report_lines(&parsed));
    let mut failed = !parsed.unsupported.is_empty();
    if a.scene.is_some() || a.profile.is_some() {
        // The measuring's work before it starts: a line counts one, a curve more (a
        // Sinumerik program, read whole by its own reader, is weighed here).
        let work: usize = parsed.toolpath.blocks.iter().map(|b| deviation_work(&b.motion)).sum();
        if work > MAX_DEVIATION_MOVES {
            return Err(Fatal(format!(
                "{}: measuring {} moves against a design is {work} line-equivalents of work (an arc or curve counts {DEVIATION_CURVE_WEIGHT}), more than {MAX_DEVIATION_MOVES}; split the program or replay it without --scene",
                a.program.display(),
                parsed.toolpath.blocks.len()
            )));
        }
        let design = load_design(a.scene.as_deref(), a.profile)?;
        let point = match a.point {
            Some(p) => point_of(p, a.tool_radius, &design)?,
            None => ProgrammedPoint::from_comments(&parsed.comments).unwrap_or(ProgrammedPoint::BallCentre),
        };
        let moved = Translated { inner: design.curve.as_ref(), offset: point.offset() };
        let d = deviation(&parsed.toolpath, &moved, &DeviationOptions::default())
            .map_err(|e| Fatal(format!("{}: {e}", a.program.display())))?;
        lines.push(format!(
            "design       {} ({:.4} mm), programmed point: {}",
            design.title,
            d.design_length_mm,
            point.value().to_lowercase()
        ));
        if d.sample_spacing_mm > DeviationOptions::default().design_spacing_mm {
            lines.push(format!(
                "note         the program is too long to sample every 0.2 mm: samples {} mm apart (peaks between them found to within half of that, then refined)",
                fmt_fixed(d.sample_spacing_mm, 3)
            ));
        }
        lines.push(format!(
            "program → design  max {} mm at {} (line {})",
            fmt_fixed(d.program_to_design_mm, 6),
            v3(d.program_point),
            d.program_line
        ));
        lines.push(format!(
            "design → program  max {} mm at {} (s = {:.3} mm along the design)",
            fmt_fixed(d.design_to_program_mm, 6),
            v3(d.design_point),
            d.design_s_mm
        ));
        lines.push(format!(
            "gaps         start {} mm, end {} mm",
            fmt_fixed(d.start_gap_mm, 6),
            fmt_fixed(d.end_gap_mm, 6)
        ));
        match a.tolerance {
            Some(t) => {
                // With blending, the worst case is the deviation plus the blending tolerance.
                let ok = d.max_mm() + blend <= t;
                failed |= !ok;
                let plus = if blend > 0.0 {
                    format!(" + G64 P{} = {} mm", fmt_num(blend), fmt_fixed(d.max_mm() + blend, 6))
                } else {
                    String::new()
                };
                lines.push(format!(
                    "deviation    {} mm{plus}: {} the tolerance {} mm",
                    fmt_fixed(d.max_mm(), 6),
                    if ok { "within" } else { "EXCEEDS" },
                    fmt_num(t)
                ));
            }
            None => lines.push(format!("deviation    {} mm", fmt_fixed(d.max_mm(), 6))),
        }
    } else if a.tolerance.is_some() {
        return Err(Fatal(
            "--tolerance needs a design path to compare with: give --scene SCENE or --profile parabola".to_owned(),
        ));
    }
    write_out(None, &(lines.join("\n") + "\n"))?;
    Ok(if failed { ExitCode::from(1) } else { ExitCode::SUCCESS })
}

pub(super) fn nurbs(a: &NurbsArgs) -> Result<ExitCode, Fatal> {
    let design = load_design(a.design.scene.as_deref(), a.design.profile)?;
    let opts = program_options(&a.program, &design)?.with_dialect(a.program.dialect.one()?);
    let p = write_program(ProgramKind::Nurbs, design.curve.as_ref(), a.program.tolerance, &opts)
        .map_err(|e| Fatal(e.to_string()))?;
    let curve = p
        .parsed
        .toolpath
        .cuts()
        .find_map(|b| if let Segment::Nurbs(c) = &b.segment { Some(c.clone()) } else { None })
        .ok_or_else(|| Fatal("the NURBS program holds no curve (a bug; please report it)".to_owned()))?;
    let update = match a.update {
        UpdateArg::First => Update::FirstOrder,
        UpdateArg::Second => Update::SecondOrder,
        UpdateArg::Corrected => Update::Corrected,
    };
    let period = a.period.unwrap_or(design.period_ms);
    let ro = RealtimeOptions::default()
        .with_feed(opts.feed_mm_per_min, period)
        .with_update(update)
        .with_chord_tol(a.chord_tol);
    let run = interpolate_realtime(&curve, &ro).map_err(|e| Fatal(e.to_string()))?;
    let mut csv = String::from("k,t_ms,u,x,y,z,target_mm,step_mm,fluctuation,chord_error_mm,limited\n");
    for s in &run.samples {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            s.k,
            fmt_num(s.k as f64 * period),
            fmt_num(s.u),
            fmt_num(s.point.x),
            fmt_num(s.point.y),
            fmt_num(s.point.z),
            fmt_num(s.target_mm),
            fmt_num(s.step_mm),
            fmt_num(s.fluctuation),
            fmt_num(s.chord_error_mm),
            u8::from(s.limited)
        ));
    }
    write_out(a.out.as_deref(), &csv)?;
    let st = run.stats;
    let _ = writeln!(
        io::stderr(),
        "interpolab: {} curve of {} control points, {} update: {} periods, feed fluctuation max {:.3e} RMS {:.3e}, max chord error {:.3e} mm, {} feed-limited periods",
        opts.dialect.kind_label(ProgramKind::Nurbs),
        curve.len(),
        update.as_str(),
        st.periods,
        st.max_fluctuation,
        st.rms_fluctuation,
        st.max_chord_error_mm,
        st.limited_periods
    );
    Ok(ExitCode::SUCCESS)
}
