//! `steps`, `example1`, `table1`, `chords`: seed 002's five-axis tool steps and seed 003's
//! equal-error chords. Wall times are measured here (never in the core, which stays free
//! of clocks so it runs unchanged in the browser).
//!
//! Exit status: 0 success; 2 bad input or a path that cannot be planned (one line on
//! standard error naming the problem and what to change).

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, ValueEnum};
use serde_json::{Value, json};

use super::{Fatal, OutFormat};

use interpolab::chords::planar::{Spacing, seed003_ellipse, seed003_hyperbola, seed003_parabola, spacing_nodes};
use interpolab::chords::{ChordOptions, RootMethod, equal_error_chords_with};
use interpolab::crease::CreaseCurve;
use interpolab::fiveaxis::{
    CreasePath, DesignPath, Machine, MachineKind, NacaProfile, StepNode, StepOptions, StepPlan, ToolAxisRule,
    blade_case, evaluate_nodes, example1, plan_steps, swept_samples,
};
use interpolab::gcode::crease_design;
use interpolab::geom::Curve3;
use interpolab::plan::steps::{DEFAULT_FEED_MM_PER_MIN, dynamics_of, steps_canon};
use interpolab::plan::{Dynamics, StepsFeed, StepsTime, time_steps};
use interpolab::report::{csv_comment_text, fmt_num, one_line};
use interpolab::scene::{build_machine, build_tool_axis, machine_spec, machine_value};

/// Root methods by their command-line names.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum RootArg {
    /// Halve the bracket.
    Bisection,
    /// Golden-section cut of the bracket.
    Golden,
    /// The 5-axis steps paper's modified secant (regula falsi), eq. (4).
    Secant,
    /// Regula falsi with the Illinois modification.
    Illinois,
    /// Regula falsi with the Anderson–Björck modification.
    AndersonBjorck,
}

impl RootArg {
    fn method(self) -> RootMethod {
        match self {
            Self::Bisection => RootMethod::Bisection,
            Self::Golden => RootMethod::Golden,
            Self::Secant => RootMethod::Secant,
            Self::Illinois => RootMethod::Illinois,
            Self::AndersonBjorck => RootMethod::AndersonBjorck,
        }
    }
}

/// Planar test curves of the chords article (and the blade section).
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum CurveArg {
    /// y = 0.025·x², 0 ≤ x ≤ 60 mm.
    Parabola,
    /// x·y = 400 mm², 5 ≤ x ≤ 80 mm.
    Hyperbola,
    /// Quarter ellipse, semi-axes 60 and 30 mm.
    Ellipse,
    /// NACA 2412 section, 100 mm chord.
    Naca2412,
}

/// `interpolab steps`.
#[derive(Args)]
pub(crate) struct StepsArgs {
    /// Scene file: its crease, `machine` and `tool_axis` (defaults when absent).
    scene: Option<PathBuf>,
    /// The 5-axis steps paper's Example 1 instead of a scene.
    #[arg(long, conflicts_with = "scene")]
    example1: bool,
    /// A blade section instead of a scene: NACA four digits, e.g. 2412 (100 mm chord).
    #[arg(long, conflicts_with_all = ["scene", "example1"])]
    blade: Option<String>,
    /// Tolerance E on every segment's total error |δt + δn| (mm).
    #[arg(value_parser = super::finite, long)]
    tolerance: f64,
    /// Root finder inside the bracket.
    #[arg(long, value_enum, default_value = "secant")]
    method: RootArg,
    /// Also hold the swept tool tip within E of the design tip path (as a post-processor
    /// checking the programmed point would); adds the column tip_design_mm.
    #[arg(long)]
    bound_tip: bool,
    /// Feed F (mm/min) of the tool tip relative to the workpiece, for the plan's time on the
    /// machine's dynamics preset. Default: the scene's `motion.feed`, else 1000.
    #[arg(long, value_parser = super::finite)]
    feed: Option<f64>,
    /// The machine's dynamics for the time: a preset or a machine file (as `interpolab time
    /// --machine`). Default: the preset named as the machine's structure (table-ac, …).
    #[arg(long)]
    machine: Option<String>,
    /// Drop the jerk limits of those dynamics (acceleration may jump).
    #[arg(long)]
    no_jerk: bool,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: OutFormat,
}

/// `interpolab example1`.
#[derive(Args)]
pub(crate) struct Example1Args {
    /// Tolerance E (mm); the paper's chord error is 0.01.
    #[arg(value_parser = super::finite, long, default_value_t = 0.01)]
    tolerance: f64,
    /// Root finder inside the bracket.
    #[arg(long, value_enum, default_value = "secant")]
    method: RootArg,
    /// Points of the swept tool printed for the single block before steps are inserted.
    #[arg(long, default_value_t = 10)]
    samples: usize,
    /// The machine's structure instead of the paper's table-ac (the same pivots through the
    /// origin and travel; a head gets a 150 mm tool length, as in the 5-axis tab).
    #[arg(long)]
    structure: Option<String>,
    /// Feed F (mm/min) of the tool tip relative to the workpiece, for the time of the plans
    /// before and after on the machine's dynamics preset (table-ac).
    #[arg(long, value_parser = super::finite, default_value_t = DEFAULT_FEED_MM_PER_MIN)]
    feed: f64,
    /// The machine's dynamics for the time: a preset or a machine file (as `interpolab time
    /// --machine`). Default: the preset named as the machine's structure (table-ac, …).
    #[arg(long)]
    machine: Option<String>,
    /// Drop the jerk limits of those dynamics (acceleration may jump).
    #[arg(long)]
    no_jerk: bool,
}

/// `interpolab table1`.
#[derive(Args)]
pub(crate) struct Table1Args {
    /// Scene files to add to the comparison (their crease, machine and tool axis).
    scenes: Vec<PathBuf>,
    /// Leave out the NACA 2412 blade section.
    #[arg(long)]
    no_blade: bool,
    /// Tolerances (mm).
    #[arg(long, value_delimiter = ',', default_values_t = [0.1, 0.01, 0.001])]
    tolerances: Vec<f64>,
    /// Runs per method and tolerance; the median time is printed.
    #[arg(long, default_value_t = 5)]
    repeat: usize,
}

/// `interpolab chords`.
#[derive(Args)]
pub(crate) struct ChordsArgs {
    /// Scene files: their ball-centre crease is the curve (one without --table).
    scenes: Vec<PathBuf>,
    /// A built-in planar curve instead of a scene.
    #[arg(long, value_enum)]
    curve: Option<CurveArg>,
    /// Chord tolerance d (mm); repeat or separate by commas with --table.
    #[arg(long, value_delimiter = ',')]
    tolerance: Vec<f64>,
    /// Compare equal-error, equal-interval and equal-step nodes (node counts and worst
    /// errors) on the parabola, hyperbola and ellipse and on the scenes given.
    #[arg(long)]
    table: bool,
    /// Root finder inside the bracket.
    #[arg(long, value_enum, default_value = "anderson-bjorck")]
    method: RootArg,
    /// Output format of the node list.
    #[arg(long, value_enum, default_value = "csv")]
    format: OutFormat,
}

/// A design path with its machine and a description for the output.
struct Case {
    title: String,
    path: Box<dyn DesignPath>,
    machine: Machine,
    machine_note: &'static str,
    rule: String,
    /// Unit of the path parameter s.
    s_unit: &'static str,
    /// The scene's feed (mm/min); `None` for the built-in paths.
    feed: Option<f64>,
}

/// A scene and its crease as a design curve (the same run the G-code commands use).
fn load_crease(path: &Path) -> Result<(CreaseCurve, interpolab::scene::Scene), Fatal> {
    let (scene, job) = super::crease::load(path)?;
    let curve = crease_design(&job).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    Ok((curve, scene))
}

fn scene_case(path: &Path) -> Result<Case, Fatal> {
    let (curve, scene) = load_crease(path)?;
    let (machine, machine_note) = match &scene.machine {
        Some(m) => (build_machine(m), ""),
        None => (Machine::default(), " (the scene has no \"machine\": the default)"),
    };
    let rule = match &scene.tool_axis {
        Some(t) => build_tool_axis(t).map_err(|e| Fatal(format!("{}: {e}", path.display())))?,
        None => ToolAxisRule::Bisector,
    };
    Ok(Case {
        title: if scene.name.is_empty() {
            path.display().to_string()
        } else {
            format!("{} ({})", scene.name, path.display())
        },
        path: Box::new(CreasePath::new(curve, rule)),
        machine,
        machine_note,
        rule: describe_rule(&rule),
        s_unit: "mm",
        feed: Some(scene.motion.feed),
    })
}

fn example1_case() -> Case {
    let ex = example1();
    Case {
        title:
            "Example 1 of the 5-axis steps paper: circle r = 25 mm at z = 50, P1 (0, 25, 50) → P2 (1.744, 24.939, 50)"
                .into(),
        rule: "turning from T1 (0, 1, 0) to T2 (0.997, -0.070, 0) along the great circle".into(),
        path: Box::new(ex.path),
        machine: ex.machine,
        machine_note: "",
        s_unit: "rad",
        feed: None,
    }
}

fn blade_case_for(digits: &str) -> Result<Case, Fatal> {
    let naca = NacaProfile::from_digits(digits, 100.0).ok_or_else(|| {
        Fatal(format!(
            "--blade {digits}: not a NACA four-digit section; give four digits with a non-zero thickness, e.g. 2412"
        ))
    })?;
    let (path, machine) =
        blade_case(naca).ok_or_else(|| Fatal(format!("--blade {digits}: the section could not be sampled")))?;
    Ok(Case {
        title: format!("NACA {digits} blade section, 100 mm chord, cut all round from outside"),
        rule: "normal1, lead 0°, tilt −30° (the outward normal tipped 30° up)".into(),
        path: Box::new(path),
        machine,
        machine_note: "",
        s_unit: "mm",
        feed: None,
    })
}

/// Radians as degrees, rounded to 1e-9° so that a limit typed as 120 prints as 120.
fn fmt_deg(rad: f64) -> String {
    fmt_num((rad.to_degrees() * 1e9).round() / 1e9)
}

fn describe_rule(r: &ToolAxisRule) -> String {
    match *r {
        ToolAxisRule::Bisector => "bisector of n1 and n2".into(),
        ToolAxisRule::Normal1 { lead_rad, tilt_rad } => {
            format!("normal1, lead {}°, tilt {}°", fmt_deg(lead_rad), fmt_deg(tilt_rad))
        }
        ToolAxisRule::Fixed { axis } => {
            format!("fixed ({}, {}, {})", fmt_num(axis.x), fmt_num(axis.y), fmt_num(axis.z))
        }
        ToolAxisRule::Interpolated { .. } => "interpolated".into(),
    }
}

fn describe_machine(m: &Machine) -> String {
    let names = m.axis_names();
    let v = |p: glam::DVec3| format!("[{}, {}, {}]", fmt_num(p.x), fmt_num(p.y), fmt_num(p.z));
    let mut parts = vec![m.kind.as_str().to_owned()];
    for (i, has) in m.kind.has_pivot().into_iter().enumerate() {
        if has {
            parts.push(format!("pivot {} {} mm", names[i].to_lowercase(), v(m.pivots_mm[i])));
        }
    }
    if m.kind.uses_tool_length() {
        parts.push(format!("tool length {} mm", fmt_num(m.tool_length_mm)));
    }
    for (name, lim) in names.iter().zip(m.limits_rad) {
        parts.push(match lim {
            Some([lo, hi]) => format!("{name} [{}, {}]°", fmt_deg(lo), fmt_deg(hi)),
            None => format!("{name} unlimited"),
        });
    }
    parts.join(", ")
}

fn fatal_io(e: &io::Error) -> Fatal {
    if e.kind() == io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    Fatal(format!("cannot write the output: {e}"))
}

/// Column names of the node table; the rotary columns named as the machine names them
/// (`tip_design_mm` last, with `--bound-tip`).
fn step_columns(kind: MachineKind, bound_tip: bool) -> Vec<String> {
    let [t, c] = kind.axis_names();
    [
        "node",
        "s",
        "X",
        "Y",
        "Z",
        t,
        c,
        "tip_x",
        "tip_y",
        "tip_z",
        "axis_i",
        "axis_j",
        "axis_k",
        "delta_mm",
        "delta_t_mm",
        "delta_n_mm",
        "tip_dev_mm",
        "gouge_mm",
        "stock_mm",
        "iterations",
        "limited_by",
        "tip_design_mm",
    ]
    .iter()
    .filter(|c| bound_tip || **c != "tip_design_mm")
    .map(|s| (*s).to_owned())
    .collect()
}

fn step_values(i: usize, n: &StepNode) -> (Vec<f64>, &'static str) {
    let b = &n.block;
    let j = &b.joints;
    let mut v = vec![
        i as f64,
        b.location.s,
        j.xyz_mm.x,
        j.xyz_mm.y,
        j.xyz_mm.z,
        j.rotary_rad[0].to_degrees(),
        j.rotary_rad[1].to_degrees(),
        b.location.tip.x,
        b.location.tip.y,
        b.location.tip.z,
        b.location.axis.x,
        b.location.axis.y,
        b.location.axis.z,
    ];
    match n.report {
        Some(r) => v.extend([r.total_mm, r.chord_mm, r.nonlinear_mm, r.tip_deviation_mm, r.gouge_mm, r.stock_mm]),
        None => v.extend([f64::NAN; 6]),
    }
    v.push(f64::from(n.evaluations));
    let limited = if i == 0 {
        ""
    } else if n.rotary_limited {
        "rotary_step"
    } else if n.tip_limited {
        "tip"
    } else {
        "error"
    };
    (v, limited)
}

/// The largest tip distance from the design tip path and the segments it ended (with
/// `--bound-tip`; `None` otherwise).
fn tip_summary(plan: &StepPlan) -> Option<(f64, usize)> {
    let worst = plan.nodes.iter().filter_map(|n| n.tip_design_mm).reduce(f64::max)?;
    Some((worst, plan.nodes.iter().filter(|n| n.tip_limited).count()))
}

fn summary(plan: &StepPlan) -> String {
    let limited = plan.nodes.iter().filter(|n| n.rotary_limited).count();
    let tip = tip_summary(plan).map_or(String::new(), |(worst, n)| {
        format!("; tip from the design tip path at most {} mm, {n} segment(s) ended by it", fmt_num(worst))
    });
    format!(
        "{} nodes, {} segments, worst |δ| {} mm (E = {} mm), {} iterations (δ evaluations, method {}), {} segment(s) ended by the 90° rotary step{tip}",
        plan.nodes.len(),
        plan.segments(),
        fmt_num(plan.worst_mm()),
        fmt_num(plan.tol_mm),
        plan.total_evaluations(),
        plan.method.as_str(),
        limited
    )
}

fn plan_case(case: &Case, tol: f64, method: RootMethod, bound_tip: bool) -> Result<StepPlan, Fatal> {
    plan_steps(&case.machine, case.path.as_ref(), &StepOptions::new(tol).with_method(method).with_tip_bound(bound_tip))
        .map_err(|e| Fatal(format!("{}: {e}", case.title)))
}

/// The feed of `--feed`, checked before any work.
fn checked_feed(feed: f64) -> Result<f64, Fatal> {
    if feed > 0.0 && feed <= interpolab::numerics::limits::MAX_FEED_MM_PER_MIN {
        Ok(feed)
    } else {
        Err(Fatal(format!("--feed: {}", interpolab::plan::StepsTimeError::BadFeed { feed_mm_per_min: feed })))
    }
}

/// The dynamics of `--machine` (default: the preset named as the structure), without jerk
/// limits with `--no-jerk`; checked before any work.
fn dynamics_for(kind: MachineKind, machine: Option<&str>, no_jerk: bool) -> Result<Dynamics, Fatal> {
    let base = match machine {
        Some(m) => super::dynamics::machine_of(m)?,
        None => dynamics_of(kind),
    };
    super::dynamics::machine_with(base, None, false, None, None, no_jerk)
}

/// A plan's time on `dynamics` at feed F (mm/min) of the tool tip relative to the workpiece
/// (inverse time per block, docs/feed-planning.md).
fn plan_time(kind: MachineKind, nodes: &[StepNode], feed: f64, dynamics: &Dynamics) -> Result<StepsTime, Fatal> {
    let blocks: Vec<_> = nodes.iter().map(|n| n.block).collect();
    time_steps(kind, &blocks, feed, StepsFeed::Tip, dynamics)
        .map_err(|e| Fatal(format!("the plan's time on {}: {e}", dynamics.name)))
}

/// One line: the cycle time and its two lower bounds.
fn time_text(t: &StepsTime) -> String {
    format!(
        "{:.4} s on {} at F {} mm/min of the tool tip (G93, one inverse time per block); the feed alone {:.4} s, the rotary axes at least {:.4} s",
        t.cycle_s,
        t.machine,
        fmt_num(t.feed_mm_per_min),
        t.feed_s,
        t.rotary_bound_s
    )
}

/// The `time` object of `--format json` (units in the keys).
fn time_json(t: &StepsTime) -> Value {
    json!({
        "machine": t.machine,
        "feed_mm_per_min": t.feed_mm_per_min,
        "feed_along": "tip",
        "cycle_s": t.cycle_s,
        "feed_s": t.feed_s,
        "rotary_bound_s": t.rotary_bound_s,
        "tip_path_mm": t.tip_path_mm,
        "joint_path_mm": t.joint_path_mm,
        "segment_s": t.segment_s,
    })
}

pub(super) fn steps(a: &StepsArgs) -> Result<ExitCode, Fatal> {
    let case = match (&a.scene, a.example1, &a.blade) {
        (Some(p), _, _) => scene_case(p)?,
        (None, true, _) => example1_case(),
        (None, false, Some(d)) => blade_case_for(d)?,
        (None, false, None) => {
            return Err(Fatal("steps: give a scene file, --example1 or --blade 2412".into()));
        }
    };
    let feed = checked_feed(a.feed.or(case.feed).unwrap_or(DEFAULT_FEED_MM_PER_MIN))?;
    let dynamics = dynamics_for(case.machine.kind, a.machine.as_deref(), a.no_jerk)?;
    let plan = plan_case(&case, a.tolerance, a.method.method(), a.bound_tip)?;
    let time = plan_time(case.machine.kind, &plan.nodes, feed, &dynamics)?;
    let cols = step_columns(case.machine.kind, a.bound_tip);
    let mut o = BufWriter::new(io::stdout().lock());
    let r = (|| -> io::Result<()> {
        match a.format {
            OutFormat::Csv => {
                writeln!(o, "# interpolab steps: {}", csv_comment_text(&case.title))?;
                writeln!(o, "# machine: {}{}", describe_machine(&case.machine), case.machine_note)?;
                writeln!(
                    o,
                    "# tool axis: {}; ball R = {} mm, R' = {} mm; programmed point: tool tip = ball centre - R*axis; s in {}",
                    case.rule,
                    fmt_num(case.path.ball_radius_mm()),
                    fmt_num(case.path.effective_radius_mm()),
                    case.s_unit
                )?;
                writeln!(
                    o,
                    "# X, Y, Z in mm and {}, {} in degrees; between rows every joint moves linearly (docs/fiveaxis.md); delta = delta_t + delta_n, overcut +",
                    case.machine.axis_names()[0],
                    case.machine.axis_names()[1]
                )?;
                writeln!(
                    o,
                    "# delta_*, gouge, stock: the ball's signed errors on the surfaces (R' minus distance; what a ball end mill cuts); tip_dev_mm: the tool tip's distance from its programmed chord, for reference"
                )?;
                if a.bound_tip {
                    writeln!(
                        o,
                        "# --bound-tip: tip_design_mm, the swept tool tip's largest distance from the design tip path, is also held within E (limited_by = tip where it ended the segment)"
                    )?;
                }
                writeln!(o, "{}", cols.join(","))?;
                for (i, n) in plan.nodes.iter().enumerate() {
                    let (v, lim) = step_values(i, n);
                    let mut cells: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
                    cells.push(lim.to_owned());
                    if a.bound_tip {
                        cells.push(n.tip_design_mm.map_or(String::new(), fmt_num));
                    }
                    writeln!(o, "{}", cells.join(","))?;
                }
                writeln!(o, "# summary: {}", summary(&plan))?;
                writeln!(o, "# time: {}", time_text(&time))?;
            }
            OutFormat::Json => {
                let rows: Vec<Value> = plan
                    .nodes
                    .iter()
                    .enumerate()
                    .map(|(i, n)| {
                        let (v, lim) = step_values(i, n);
                        let mut row: Vec<Value> =
                            v.iter().map(|x| if x.is_finite() { json!(x) } else { Value::Null }).collect();
                        row.push(if lim.is_empty() { Value::Null } else { json!(lim) });
                        if a.bound_tip {
                            row.push(n.tip_design_mm.map_or(Value::Null, |t| json!(t)));
                        }
                        Value::Array(row)
                    })
                    .collect();
                let tip = tip_summary(&plan);
                let doc = json!({
                    "format": "interpolab-steps/1",
                    "design": case.title,
                    "machine": machine_value(&machine_spec(&case.machine)),
                    "tool_axis": case.rule,
                    "ball_radius_mm": case.path.ball_radius_mm(),
                    "effective_radius_mm": case.path.effective_radius_mm(),
                    "programmed_point": "tool tip = ball centre - R*axis",
                    "s_unit": case.s_unit,
                    "tolerance_mm": plan.tol_mm,
                    "method": plan.method.as_str(),
                    "columns": cols,
                    "rows": rows,
                    "summary": {
                        "nodes": plan.nodes.len(),
                        "segments": plan.segments(),
                        "worst_mm": plan.worst_mm(),
                        "iterations": plan.total_evaluations(),
                        "rotary_limited": plan.nodes.iter().filter(|n| n.rotary_limited).count(),
                        "bound_tip": a.bound_tip,
                        "worst_tip_design_mm": tip.map(|t| t.0),
                        "tip_limited": tip.map(|t| t.1),
                    },
                    "time": time_json(&time),
                });
                writeln!(o, "{}", serde_json::to_string_pretty(&doc).unwrap_or_default())?;
            }
        }
        o.flush()
    })();
    r.map_err(|e| fatal_io(&e))?;
    Ok(ExitCode::SUCCESS)
}

fn signed(x: f64) -> String {
    let tag = if x > 0.0 {
        "overcut"
    } else if x < 0.0 {
        "undercut"
    } else {
        "exact"
    };
    format!("{:+.6} mm ({tag})", x)
}

pub(super) fn example1_cmd(a: &Example1Args) -> Result<ExitCode, Fatal> {
    let feed = checked_feed(a.feed)?;
    let mut ex = example1();
    if let Some(k) = &a.structure {
        ex.machine.kind = MachineKind::from_name(k).ok_or_else(|| {
            Fatal(format!(
                "--structure: '{k}' is not a machine structure; give table-ac, table-bc, head-bc or head-a-table-c"
            ))
        })?;
        if ex.machine.kind.uses_tool_length() {
            ex.machine.tool_length_mm = 150.0;
        }
    }
    let dynamics = dynamics_for(ex.machine.kind, a.machine.as_deref(), a.no_jerk)?;
    let names = ex.machine.axis_names();
    let (s0, s1) = ex.path.range();
    let mut out = String::new();
    let mut line = |s: String| {
        out.push_str(&s);
        out.push('\n');
    };
    line("Example 1 of the 5-axis steps paper (Ji, Zhou, An & Zhang 2010)".into());
    line("  circle r = 25 mm about the Z axis at z = 50 (a convex boss, tool outside), ball R = 5 mm".into());
    line(format!("  machine: {}; tolerance E = {} mm", describe_machine(&ex.machine), fmt_num(a.tolerance)));
    let before = evaluate_nodes(&ex.machine, &ex.path, &[s0, s1], &Default::default())
        .map_err(|e| Fatal(format!("example 1: {e}")))?;
    for (k, n) in before.iter().enumerate() {
        let j = &n.block.joints;
        line(format!(
            "  P{} = ({}, {}, {}), T{} = ({}, {}, {}): X {:.4} Y {:.4} Z {:.4} {} {:.4}° {} {:.4}°",
            k + 1,
            fmt_num(ex.contacts[k].x),
            fmt_num(ex.contacts[k].y),
            fmt_num(ex.contacts[k].z),
            k + 1,
            fmt_num(ex.axes[k].x),
            fmt_num(ex.axes[k].y),
            fmt_num(ex.axes[k].z),
            j.xyz_mm.x,
            j.xyz_mm.y,
            j.xyz_mm.z,
            names[0],
            j.rotary_rad[0].to_degrees(),
            names[1],
            j.rotary_rad[1].to_degrees()
        ));
    }
    let rep = before[1].report.ok_or_else(|| Fatal("example 1: no segment report".into()))?;
    line(String::new());
    line("Before: one block P1 -> P2, every joint moved linearly".into());
    line(format!("  chord error δt of the straight programmed motion   {}", signed(rep.worst_chord_mm)));
    line(format!("  total error δ = δt + δn at its worst (τ = {:.3})   {}", rep.at_tau, signed(rep.total_mm)));
    line(format!("    of which δt {} and δn {}", signed(rep.chord_mm), signed(rep.nonlinear_mm)));
    line(format!("  tool tip's largest distance from its chord        {:.6} mm", rep.tip_deviation_mm));
    line(format!("  time: {}", time_text(&plan_time(ex.machine.kind, &before, feed, &dynamics)?)));
    line("  the swept tool (τ: tool tip x y z; ball centre x y z; δ on the cylinder):".into());
    for p in swept_samples(&ex.machine, &ex.path, &before[0].block, &before[1].block, a.samples.max(1)) {
        line(format!(
            "    τ {:.3}: tip {:9.4} {:9.4} {:9.4}  centre {:9.4} {:9.4} {:9.4}  δ {:+.6}",
            p.tau,
            p.tip.x,
            p.tip.y,
            p.tip.z,
            p.centre.x,
            p.centre.y,
            p.centre.z,
            p.errors_mm[0].unwrap_or(f64::NAN)
        ));
    }
    let plan = plan_steps(&ex.machine, &ex.path, &StepOptions::new(a.tolerance).with_method(a.method.method()))
        .map_err(|e| Fatal(format!("example 1: {e}")))?;
    line(String::new());
    line(format!(
        "After: the method inserts {} blocks between P1 and P2 ({} segments, {} iterations with {})",
        plan.nodes.len().saturating_sub(2),
        plan.segments(),
        plan.total_evaluations(),
        plan.method.as_str()
    ));
    line(format!(
        "  node  s (rad)     contact angle   X          Y          Z          {}         {}          δ (mm)      δt (mm)     δn (mm)",
        names[0], names[1]
    ));
    for (i, n) in plan.nodes.iter().enumerate() {
        let j = &n.block.joints;
        let ang = 90.0 - n.block.location.s.to_degrees();
        let (d, dt, dn) = n.report.map_or((String::new(), String::new(), String::new()), |r| {
            (format!("{:+.7}", r.total_mm), format!("{:+.7}", r.chord_mm), format!("{:+.7}", r.nonlinear_mm))
        });
        line(format!(
            "  {i:4}  {:.7}  {:8.4}°     {:9.4}  {:9.4}  {:9.4}  {:8.4}°  {:9.4}°  {d:>11} {dt:>11} {dn:>11}",
            n.block.location.s,
            ang,
            j.xyz_mm.x,
            j.xyz_mm.y,
            j.xyz_mm.z,
            j.rotary_rad[0].to_degrees(),
            j.rotary_rad[1].to_degrees()
        ));
    }
    line(format!("  worst |δ| after: {} mm (E = {} mm)", fmt_num(plan.worst_mm()), fmt_num(plan.tol_mm)));
    line(format!("  time: {}", time_text(&plan_time(ex.machine.kind, &plan.nodes, feed, &dynamics)?)));
    let mut o = io::stdout().lock();
    o.write_all(out.as_bytes()).map_err(|e| fatal_io(&e))?;
    Ok(ExitCode::SUCCESS)
}

fn median_ms(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

pub(super) fn table1(a: &Table1Args) -> Result<ExitCode, Fatal> {
    if let Some(t) = a.tolerances.iter().find(|t| !(**t > 0.0 && t.is_finite())) {
        return Err(Fatal(format!("--tolerances: {t} is not a positive length in mm; give e.g. 0.1,0.01,0.001")));
    }
    let mut cases = Vec::new();
    if !a.no_blade {
        cases.push(blade_case_for("2412")?);
    }
    for p in &a.scenes {
        cases.push(scene_case(p)?);
    }
    let repeat = a.repeat.max(1);
    let mut o = BufWriter::new(io::stdout().lock());
    let mut w = |s: String| writeln!(o, "{s}").map_err(|e| fatal_io(&e));
    w(format!(
        "Iterations (δ evaluations, bracketing included) / wall time (median of {repeat} runs, ms) / nodes, per method and tolerance. Native build; times vary with the machine."
    ))?;
    for case in &cases {
        w(String::new())?;
        w(format!("### {}", one_line(&case.title)))?;
        w(format!("machine: {}{}; tool axis: {}", describe_machine(&case.machine), case.machine_note, case.rule))?;
        w(String::new())?;
        let mut header = "| method |".to_owned();
        let mut rule = "|---|".to_owned();
        for t in &a.tolerances {
            header.push_str(&format!(" {} mm: iterations | time (ms) | nodes |", fmt_num(*t)));
            rule.push_str("---:|---:|---:|");
        }
        w(header)?;
        w(rule)?;
        for m in RootMethod::ALL {
            let mut row = format!(
                "| {} |",
                if m == RootMethod::Secant { "secant (paper)".to_owned() } else { m.as_str().to_owned() }
            );
            for &t in &a.tolerances {
                let opts = StepOptions { reports: false, ..StepOptions::new(t).with_method(m) };
                let mut times = Vec::with_capacity(repeat);
                let mut last = None;
                for _ in 0..repeat {
                    let start = Instant::now();
                    let plan = plan_steps(&case.machine, case.path.as_ref(), &opts)
                        .map_err(|e| Fatal(format!("{}: {e}", case.title)))?;
                    times.push(start.elapsed().as_secs_f64() * 1e3);
                    last = Some(plan);
                }
                let plan = last.ok_or_else(|| Fatal("no run".into()))?;
                row.push_str(&format!(
                    " {} | {:.2} | {} |",
                    plan.total_evaluations(),
                    median_ms(times),
                    plan.nodes.len()
                ));
            }
            w(row)?;
        }
    }
    o.flush().map_err(|e| fatal_io(&e))?;
    Ok(ExitCode::SUCCESS)
}

fn planar_curve(c: CurveArg) -> (String, Box<dyn Curve3>) {
    match c {
        CurveArg::Parabola => ("parabola y = 0.025·x², 0 ≤ x ≤ 60 mm (param x)".into(), Box::new(seed003_parabola())),
        CurveArg::Hyperbola => {
            ("hyperbola x·y = 400 mm², 5 ≤ x ≤ 80 mm (param x)".into(), Box::new(seed003_hyperbola()))
        }
        CurveArg::Ellipse => {
            ("quarter ellipse 60 × 30 mm, from (60, 0) to (0, 30) (param t, rad)".into(), Box::new(seed003_ellipse()))
        }
        CurveArg::Naca2412 => {
            ("NACA 2412 section, 100 mm chord (param θ, rad)".into(), Box::new(NacaProfile::naca2412()))
        }
    }
}

fn chord_opts(method: RootArg) -> ChordOptions {
    ChordOptions { search: ChordOptions::default().search.with_method(method.method()), ..ChordOptions::default() }
}

pub(super) fn chords(a: &ChordsArgs) -> Result<ExitCode, Fatal> {
    if let Some(t) = a.tolerance.iter().find(|t| !(**t > 0.0 && t.is_finite())) {
        return Err(Fatal(format!("--tolerance: {t} is not a positive length in mm; give e.g. 0.01")));
    }
    let opts = chord_opts(a.method);
    if a.table {
        return chords_table(a, &opts);
    }
    let (title, curve): (String, Box<dyn Curve3>) = match (a.scenes.as_slice(), a.curve) {
        ([p], None) => {
            let (c, scene) = load_crease(p)?;
            (
                format!(
                    "ball-centre crease of {} (param: chord length, mm)",
                    if scene.name.is_empty() { p.display().to_string() } else { scene.name }
                ),
                Box::new(c),
            )
        }
        ([], Some(c)) => planar_curve(c),
        _ => {
            return Err(Fatal("chords: give one scene file or --curve (or --table for the comparison)".into()));
        }
    };
    let [tol] = a.tolerance[..] else {
        return Err(Fatal("chords: give one --tolerance in mm, e.g. --tolerance 0.01".into()));
    };
    let nodes = equal_error_chords_with(curve.as_ref(), tol, &opts).map_err(|e| Fatal(format!("chords: {e}")))?;
    let mut o = BufWriter::new(io::stdout().lock());
    let r = (|| -> io::Result<()> {
        match a.format {
            OutFormat::Csv => {
                writeln!(
                    o,
                    "# interpolab chords: {}; every chord deviates by d = {} mm, the last by at most d",
                    csv_comment_text(&title),
                    fmt_num(tol)
                )?;
                writeln!(o, "node,param,x,y,z,chord_error_mm,iterations")?;
                for (i, &s) in nodes.params.iter().enumerate() {
                    let p = curve.point_at(s);
                    let (e, it) = if i == 0 {
                        (String::new(), String::new())
                    } else {
                        (fmt_num(nodes.errors_mm[i - 1]), nodes.evaluations[i - 1].to_string())
                    };
                    writeln!(o, "{i},{},{},{},{},{e},{it}", fmt_num(s), fmt_num(p.x), fmt_num(p.y), fmt_num(p.z))?;
                }
                writeln!(
                    o,
                    "# summary: {} nodes, {} chords, worst {} mm, {} iterations (chord-deviation evaluations)",
                    nodes.len(),
                    nodes.len() - 1,
                    fmt_num(nodes.worst_error_mm()),
                    nodes.total_evaluations()
                )?;
            }
            OutFormat::Json => {
                let pts: Vec<[f64; 3]> = nodes.params.iter().map(|&s| curve.point_at(s).to_array()).collect();
                let doc = json!({
                    "format": "interpolab-chords/1",
                    "curve": title,
                    "tolerance_mm": tol,
                    "params": nodes.params,
                    "points": pts,
                    "chord_errors_mm": nodes.errors_mm,
                    "iterations": nodes.evaluations,
                });
                writeln!(o, "{}", serde_json::to_string_pretty(&doc).unwrap_or_default())?;
            }
        }
        o.flush()
    })();
    r.map_err(|e| fatal_io(&e))?;
    Ok(ExitCode::SUCCESS)
}

fn chords_table(a: &ChordsArgs, opts: &ChordOptions) -> Result<ExitCode, Fatal> {
    let tols = if a.tolerance.is_empty() { vec![0.05, 0.01] } else { a.tolerance.clone() };
    let mut curves: Vec<(String, Box<dyn Curve3>)> = match a.curve {
        Some(c) => vec![planar_curve(c)],
        None => [CurveArg::Parabola, CurveArg::Hyperbola, CurveArg::Ellipse].into_iter().map(planar_curve).collect(),
    };
    for p in &a.scenes {
        let (c, scene) = load_crease(p)?;
        let name =
            if scene.name.is_empty() { p.display().to_string() } else { format!("{} ({})", scene.name, p.display()) };
        curves.push((format!("ball-centre crease of {name} (param: chord length, mm)"), Box::new(c)));
    }
    let mut o = BufWriter::new(io::stdout().lock());
    let mut w = |s: String| writeln!(o, "{s}").map_err(|e| fatal_io(&e));
    w("Nodes and worst chord error per spacing. Equal-interval: constant parameter step; equal-step: constant chord length.".into())?;
    for (title, curve) in &curves {
        w(String::new())?;
        w(format!("### {}", one_line(title)))?;
        w(String::new())?;
        w("| d (mm) | spacing | nodes | worst error (mm) | step |".into())?;
        w("|---:|---|---:|---:|---:|".into())?;
        for &d in &tols {
            for sp in Spacing::ALL {
                let row = spacing_nodes(curve.as_ref(), d, sp, opts).map_err(|e| Fatal(format!("{title}: {e}")))?;
                let step = if sp == Spacing::EqualError { "—".to_owned() } else { format!("{:.5}", row.step) };
                let flag = if row.worst_mm() > d * (1.0 + interpolab::numerics::tolerance::ROUNDING_REL) {
                    " (exceeds d)"
                } else {
                    ""
                };
                w(format!(
                    "| {} | {} | {} | {:.6}{flag} | {step} |",
                    fmt_num(d),
                    sp.label(),
                    row.params.len(),
                    row.worst_mm()
                ))?;
            }
        }
    }
    o.flush().map_err(|e| fatal_io(&e))?;
    Ok(ExitCode::SUCCESS)
}

/// The seed-002 tool steps of a scene's crease at tolerance `tol_mm` (Bisection root
/// search), for the cutting simulation: the machine, the blocks, and the scene's ball
/// radius (mm).
pub(super) fn scene_blocks(
    path: &Path,
    tol_mm: f64,
) -> Result<(Machine, Vec<interpolab::fiveaxis::Block>, f64), Fatal> {
    let case = scene_case(path)?;
    let plan = plan_case(&case, tol_mm, RootMethod::Bisection, false)?;
    Ok((case.machine, plan.nodes.iter().map(|n| n.block).collect(), case.path.ball_radius_mm()))
}

/// A scene's seed-002 tool steps at tolerance `tol` as the joint program a five-axis machine
/// runs (for `interpolab time --steps`): a traverse to the first node, then one straight
/// joint move per segment at the scene's feed, its rotary joints named by the machine (A or
/// B, and C). Without tool-centre-point control the feed applies to the X Y Z joints' path.
pub(super) fn scene_steps_program(
    path: &Path,
    tol: f64,
) -> Result<(Vec<interpolab::gcode::interp::Canon>, String), Fatal> {
    let case = scene_case(path)?;
    let (scene, _) = super::crease::load(path)?;
    let plan = plan_case(&case, tol, RootMethod::default(), false)?;
    let blocks: Vec<_> = plan.nodes.iter().map(|n| n.block).collect();
    let out = steps_canon(case.machine.kind, &blocks, scene.motion.feed, StepsFeed::Joints)
        .map_err(|e| Fatal(format!("{}: {e}", case.title)))?;
    let title = format!(
        "{}: {} five-axis tool steps at {} mm on {} {}",
        case.title,
        plan.segments(),
        fmt_num(tol),
        case.machine.kind.as_str(),
        case.machine_note
    );
    Ok((out, title))
}
