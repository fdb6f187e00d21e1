//! `finish`: seed 001's five-axis finishing of one surface with a fillet-end mill — the CL
//! data (CSV or JSON), the comparison table (`--table`) and a five-axis G-code program
//! through a seed-002 machine (`--gcode`).
//!
//! Exit status: 0 success; 1 some CC points were refused (counted on standard error, a line
//! per reason; the JSON names each; the other points are still written); 2 bad input (one
//! line naming the problem and what to change).

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use serde_json::{Value, json};

use super::{Fatal, OutFormat};

use interpolab::fillet::paths::share_after_paths;
use interpolab::fillet::program::{FinishGcode, FinishProgramError, MAX_PLAN_DESIGNS, for_machine};
use interpolab::fillet::{
    FinishError, FinishJob, FinishSetup, PartSamples, PathSet, PathStart, Strategy, compare, iso_parametric,
    iso_scallop,
};
use interpolab::fiveaxis::FiveAxisError;
use interpolab::numerics::limits::CommandShare;
use interpolab::report::{fmt_fixed, fmt_num, one_line};
use interpolab::scene::finish::FinishScene;

/// Orientation strategies by their command-line names.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum StrategyArg {
    /// Curvature matching (widest strip without local gouging).
    Matched,
    /// Fixed lead angle (--lead, default 5°).
    FixedLead,
    /// The principal-axis method.
    Principal,
    /// A ball end mill of the same radius.
    Ball,
}

/// Path layouts by their command-line names.
#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum LayoutArg {
    /// Iso-scallop paths.
    IsoScallop,
    /// Iso-parametric paths at the same worst scallop.
    IsoParametric,
}

/// `interpolab finish`.
#[derive(Args)]
pub(crate) struct FinishArgs {
    /// Finishing scene file (interpolab-scene/1 JSON with a `finish` key).
    scene: PathBuf,
    /// Output format of the CL data.
    #[arg(long, value_enum, default_value = "csv")]
    format: OutFormat,
    /// Write the CL data (or the table) to this file instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Orientation strategy (default: the scene's `finish.strategy`).
    #[arg(long, value_enum)]
    strategy: Option<StrategyArg>,
    /// Lead angle for --strategy fixed-lead (degrees).
    #[arg(value_parser = super::finite, long, default_value_t = 5.0)]
    lead: f64,
    /// Path layout.
    #[arg(long, value_enum, default_value = "iso-scallop")]
    layout: LayoutArg,
    /// Print the comparison table (matched / fixed lead 5°, 10° / principal axis / ball;
    /// iso-scallop / iso-parametric) instead of the CL data.
    #[arg(long)]
    table: bool,
    /// Also write a five-axis G-code program (G01 with the machine's joints, steps by the
    /// 5-axis step selection within the scene's tolerance) to this file.
    #[arg(long)]
    gcode: Option<PathBuf>,
    /// Tolerance E of the G-code steps (mm): the swept tool tip stays within E of its design
    /// path between blocks.
    #[arg(value_parser = super::finite, long, default_value_t = 0.01)]
    gcode_tolerance: f64,
}

/// A count of work units as the table's warning prints it: 3 significant digits, exponent
/// form.
fn fmt_units(n: u64) -> String {
    format!("{:.2e}", n as f64)
}

pub(super) fn load(path: &Path) -> Result<FinishJob, Fatal> {
    let text = super::read_capped(path, interpolab::numerics::limits::MAX_SCENE_BYTES, "scene")
        .map_err(|e| Fatal(format!("cannot read scene file {}: {e}", path.display())))?;
    let scene = FinishScene::from_json(&text).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    scene.job().map_err(|e| Fatal(format!("{}: {e}", path.display())))
}

fn sink(out: Option<&Path>) -> Result<Box<dyn Write>, Fatal> {
    Ok(match out {
        Some(p) => Box::new(BufWriter::new(
            fs::File::create(p).map_err(|e| Fatal(format!("cannot create {}: {e}", p.display())))?,
        )),
        None => Box::new(BufWriter::new(io::stdout().lock())),
    })
}

fn fatal_io(e: &io::Error) -> Fatal {
    if e.kind() == io::ErrorKind::BrokenPipe {
        std::process::exit(0);
    }
    Fatal(format!("cannot write the output: {e}"))
}

/// Columns of the CL data (units in `docs/fillet.md`).
const COLUMNS: [&str; 20] = [
    "path",
    "node",
    "x",
    "y",
    "z",
    "i",
    "j",
    "k",
    "cc_x",
    "cc_y",
    "cc_z",
    "u",
    "v",
    "lead_deg",
    "tilt_deg",
    "strip_mm",
    "side_step_mm",
    "scallop_mm",
    "adjusted",
    "lead_out",
];

fn rows(job: &FinishJob, set: &PathSet) -> Vec<Vec<Value>> {
    let dom = interpolab::geom::ParametricSurface::domain(&job.surface);
    let mut out = Vec::new();
    for (pi, p) in set.paths.iter().enumerate() {
        for (ni, n) in p.nodes.iter().enumerate() {
            let uv = dom.to_file(n.frame.uv);
            let num = |x: f64| json!(x);
            out.push(vec![
                json!(pi),
                json!(ni),
                num(n.tip.x),
                num(n.tip.y),
                num(n.tip.z),
                num(n.axis.x),
                num(n.axis.y),
                num(n.axis.z),
                num(n.frame.point.x),
                num(n.frame.point.y),
                num(n.frame.point.z),
                num(uv.x),
                num(uv.y),
                num(n.pose.lead_rad().to_degrees()),
                num(n.pose.tilt_rad().to_degrees()),
                num(n.strip_mm),
                n.side_step_mm.map_or(Value::Null, num),
                n.scallop_mm.map_or(Value::Null, num),
                json!(n.adjusted.is_some()),
                json!(n.lead_out),
            ]);
        }
    }
    out
}

fn csv_cell(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::Bool(b) => if *b { "1" } else { "0" }.to_owned(),
        Value::Number(n) => {
            n.as_f64().map_or_else(String::new, |x| if n.is_u64() { n.to_string() } else { fmt_num(x) })
        }
        other => other.to_string(),
    }
}

fn strategy_of(a: &FinishArgs, job: &FinishJob) -> Result<Strategy, Fatal> {
    strategy_arg(a.strategy, a.lead, job)
}

/// The strategy of `--strategy` (with `--lead` in degrees for fixed-lead), else the scene's.
pub(super) fn strategy_arg(strategy: Option<StrategyArg>, lead_deg: f64, job: &FinishJob) -> Result<Strategy, Fatal> {
    Ok(match strategy {
        None => job.strategy,
        Some(StrategyArg::Matched) => Strategy::Matched,
        Some(StrategyArg::Principal) => Strategy::PrincipalAxis,
        Some(StrategyArg::Ball) => Strategy::Ball,
        Some(StrategyArg::FixedLead) => {
            if !(lead_deg.abs() < 80.0) {
                return Err(Fatal(format!(
                    "--lead {lead_deg} is not a usable lead angle; give one between -80 and 80 degrees"
                )));
            }
            Strategy::FixedLead { lead_rad: lead_deg.to_radians() }
        }
    })
}

/// The JSON's `start`: the edge's name, or the curve (file units) with the index of the first
/// path of its second side (`null` when that side has no paths); `None` for the default start.
fn start_json(job: &FinishJob, set: &PathSet) -> Option<Value> {
    use interpolab::geom::ParametricSurface;
    match &job.start {
        PathStart::FirstBoundary => None,
        PathStart::Boundary(e) => Some(json!(e.name())),
        PathStart::Curve(pts) => {
            let dom = job.surface.domain();
            let file: Vec<[f64; 2]> = pts.iter().map(|&p| dom.to_file(p).to_array()).collect();
            Some(json!({ "curve": file, "second_side_first_path": set.second_side }))
        }
    }
}

pub(super) fn finish(a: &FinishArgs) -> Result<ExitCode, Fatal> {
    // Options first: a refusal comes before any path is computed or any output written.
    if a.gcode.is_some() && !(a.gcode_tolerance > 0.0 && a.gcode_tolerance.is_finite()) {
        return Err(Fatal(format!(
            "--gcode-tolerance {} is not a positive length; give it in mm, e.g. 0.01",
            a.gcode_tolerance
        )));
    }
    let job = load(&a.scene)?;
    let name = a.scene.display().to_string();
    let part = PartSamples::new(&job.surface, job.options.part_grid);
    if a.table {
        let rows = compare(&job.setup(&part)).map_err(|e| Fatal(format!("{name}: {e}")))?;
        let mut w = sink(a.out.as_deref())?;
        let h = job.options.scallop_mm;
        let mut text = format!(
            "{}: {}, scallop h {h} mm, chord tolerance {} mm, feed {} mm/min\n",
            one_line(if job.name.is_empty() { &name } else { &job.name }),
            job.cutter.describe(),
            job.options.chord_tol_mm,
            job.options.feed_mm_per_min
        );
        text.push_str("| strategy | layout | passes | CC points | length mm | strip min mm | strip mean mm | strip max mm | time min | adjusted |\n|---|---|---|---|---|---|---|---|---|---|\n");
        let mut left_out = Vec::new();
        for r in &rows {
            let Ok(s) = &r.plan else {
                left_out.push(r);
                text.push_str(&format!(
                    "| {} | {} | — | — | — | — | — | — | — | left out |\n",
                    r.strategy.name(),
                    r.layout.name()
                ));
                continue;
            };
            text.push_str(&format!(
                "| {} | {} | {} | {} | {:.1} | {:.3} | {:.3} | {:.3} | {:.2} | {} |\n",
                r.strategy.name(),
                r.layout.name(),
                s.passes,
                s.nodes,
                s.length_mm,
                s.strip_mm[0],
                s.strip_mm[1],
                s.strip_mm[2],
                s.time_min,
                s.adjusted
            ));
        }
        w.write_all(text.as_bytes()).map_err(|e| fatal_io(&e))?;
        w.flush().map_err(|e| fatal_io(&e))?;
        if left_out.is_empty() {
            return Ok(ExitCode::SUCCESS);
        }
        // The rows built are written; the ones left out are named on one line, as a warning.
        let names: Vec<String> = left_out
            .iter()
            .map(|r| {
                let Err(l) = r.plan else { return String::new() };
                if l.work == 0 {
                    format!("{} {} (no budget left)", r.strategy.name(), r.layout.name())
                } else {
                    format!(
                        "{} {} ({}, after {} units of work)",
                        r.strategy.name(),
                        r.layout.name(),
                        l.cause.describe(),
                        fmt_units(l.work)
                    )
                }
            })
            .collect();
        eprintln!(
            "interpolab: {name}: the table left out {} of its 10 plans: {}; raise the scallop height or use a larger cutter to see them",
            left_out.len(),
            names.join(", ")
        );
        return Ok(ExitCode::from(1));
    }
    let strategy = strategy_of(a, &job)?;
    let set = paths_for(&job, strategy, a.layout, &part, a.gcode.is_some(), &name)?;
    // The 5-axis program is planned before the CL data is written: a tolerance it cannot
    // meet within its bounds is refused with nothing written.
    let gcode = match &a.gcode {
        Some(g) => Some((g, plan_gcode(&job, &set, &name, a.gcode_tolerance, part.cells_checked())?)),
        None => None,
    };
    let data = rows(&job, &set);
    let mut w = sink(a.out.as_deref())?;
    match a.format {
        OutFormat::Csv => {
            let mut text = COLUMNS.join(",");
            text.push('\n');
            for r in &data {
                text.push_str(&r.iter().map(csv_cell).collect::<Vec<_>>().join(","));
                text.push('\n');
            }
            w.write_all(text.as_bytes()).map_err(|e| fatal_io(&e))?;
        }
        OutFormat::Json => {
            let s = set.stats(job.options.feed_mm_per_min);
            let c = &job.cutter;
            let mut doc = json!({
                "format": "interpolab-finish/1",
                "scene": job.name,
                "cutter": {
                    "radius_mm": c.radius_mm, "corner_radius_mm": c.corner_radius_mm,
                    "flute_length_mm": c.flute_length_mm, "shank_radius_mm": c.shank_radius_mm,
                    "gauge_length_mm": c.gauge_length_mm, "holder_radius_mm": c.holder_radius_mm,
                    "holder_length_mm": c.holder_length_mm,
                    "machined_with": set.strategy.cutter_for(c).describe(),
                },
                "strategy": set.strategy.name(),
                "layout": set.layout.name(),
                "along": if set.along == 0 { "u" } else { "v" },
                "scallop_mm": job.options.scallop_mm,
                "chord_tol_mm": job.options.chord_tol_mm,
                "columns": COLUMNS,
                "rows": data,
                "stats": {
                    "passes": s.passes, "nodes": s.nodes, "length_mm": s.length_mm,
                    "strip_min_mm": s.strip_mm[0], "strip_mean_mm": s.strip_mm[1], "strip_max_mm": s.strip_mm[2],
                    "time_min": s.time_min, "adjusted": s.adjusted,
                },
                "refused": set.refused.iter().map(|r| json!({
                    "u": r.uv.x, "v": r.uv.y, "x": r.point.x, "y": r.point.y, "z": r.point.z,
                    "reason": r.reason, "depth_mm": r.depth_mm,
                })).collect::<Vec<_>>(),
            });
            // Only where the corrector left a cusp above FLAG_ABOVE·h, so other output is as before.
            if !set.scallop_flags.is_empty() {
                doc["scallop_flags"] = set
                    .scallop_flags
                    .iter()
                    .map(|f| {
                        json!({
                            "u": f.uv.x, "v": f.uv.y, "x": f.point.x, "y": f.point.y, "z": f.point.z,
                            "path": f.path, "scallop_mm": f.scallop_mm,
                        })
                    })
                    .collect::<Vec<_>>()
                    .into();
            }
            // Only when the corrector stopped, so other output is as before.
            if let Some(k) = set.corrector_stopped_at {
                doc["corrector_stopped_at_path"] = k.into();
            }
            // Only when the scene has `finish.start`, so the output of other scenes is as before.
            if let Some(start) = start_json(&job, &set) {
                doc["start"] = start;
            }
            let text = serde_json::to_string_pretty(&doc).map_err(|e| Fatal(format!("cannot write JSON: {e}")))?;
            w.write_all(text.as_bytes()).map_err(|e| fatal_io(&e))?;
            w.write_all(b"\n").map_err(|e| fatal_io(&e))?;
        }
    }
    w.flush().map_err(|e| fatal_io(&e))?;
    if let Some((path, program)) = gcode {
        let text = program.text(if job.name.is_empty() { &name } else { &job.name });
        fs::write(path, text).map_err(|e| Fatal(format!("cannot write {}: {e}", path.display())))?;
    }
    let mut err = io::stderr().lock();
    for line in refused_lines(
        &name,
        &set.refused,
        "use a smaller cutter, a larger finish.max_inclination or a shorter gauge length (the JSON lists every one)",
    ) {
        let _ = writeln!(err, "{line}");
    }
    if let Some(worst) = set.scallop_flags.iter().max_by(|a, b| a.scallop_mm.total_cmp(&b.scallop_mm)) {
        let h = job.options.scallop_mm;
        let _ = writeln!(
            err,
            "interpolab: {name}: the scallop stays above {:.2}·h at {} place(s) (measured between neighbouring paths after the side steps' correction{}; the worst {:.2}·h at ({:.3}, {:.3}, {:.3}) mm, after path {}); use a smaller max step or scallop height, or a cutter with a larger corner radius",
            interpolab::fillet::paths::FLAG_ABOVE,
            set.scallop_flags.len(),
            corrector_note(set.corrector_stopped_at, job.options.corrector_share),
            worst.scallop_mm / h,
            worst.point.x,
            worst.point.y,
            worst.point.z,
            worst.path
        );
    }
    Ok(if set.refused.is_empty() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// The program of `set`, planned within the share of the command's work its paths left
/// (their `cells_checked`: [`share_after_paths`]).
fn plan_gcode(
    job: &FinishJob,
    set: &PathSet,
    name: &str,
    tol_mm: f64,
    cells_checked: u64,
) -> Result<FinishGcode, Fatal> {
    let share = share_after_paths(cells_checked, job.options.max_check_cells);
    let max_designs = share.cap(MAX_PLAN_DESIGNS);
    FinishGcode::plan_within(
        &job.machine,
        &job.surface,
        &job.cutter,
        set,
        job.options.feed_mm_per_min,
        tol_mm,
        max_designs,
    )
    .map_err(|e| {
        let over = matches!(e, FinishProgramError::Plan { source: FiveAxisError::TooMuchWork { .. }, .. });
        Fatal(format!("{name}: {e}{}", if over { spent_note(share, "the paths' checks") } else { String::new() }))
    })
}

/// What a refusal for a part's share adds when the command's earlier parts (`what`) spent
/// some of its work: how much.
pub(super) fn spent_note(share: CommandShare, what: &str) -> String {
    if share.left() < 1.0 {
        format!(" ({what} spent {:.0} % of the command's work)", 100.0 * (1.0 - share.left()))
    } else {
        String::new()
    }
}

/// The refused CC points of a job on standard error's terms: one line per reason with how many,
/// the first and the last (mm), and `advice` — not a line per point (a job can refuse
/// thousands).
pub(super) fn refused_lines(name: &str, refused: &[interpolab::fillet::Refusal], advice: &str) -> Vec<String> {
    let at = |p: glam::DVec3| format!("({}, {}, {}) mm", fmt_fixed(p.x, 3), fmt_fixed(p.y, 3), fmt_fixed(p.z, 3));
    let mut reasons: Vec<&str> = Vec::new();
    for r in refused {
        if !reasons.contains(&r.reason) {
            reasons.push(r.reason);
        }
    }
    reasons
        .iter()
        .map(|&reason| {
            let these: Vec<_> = refused.iter().filter(|r| r.reason == reason).collect();
            let (first, last) = (these[0], these[these.len() - 1]);
            let place = if these.len() == 1 {
                format!("at {}", at(first.point))
            } else {
                format!("the first at {}, the last at {}", at(first.point), at(last.point))
            };
            format!("interpolab: {name}: {} CC point(s) refused ({reason}), {place}; {advice}", these.len())
        })
        .collect()
}

/// The job's paths in `layout`; for a program on the scene's machine (`for_program`), every
/// pose within its rotary travel ([`for_machine`]).
pub(super) fn paths_for(
    job: &FinishJob,
    strategy: Strategy,
    layout: LayoutArg,
    part: &PartSamples,
    for_program: bool,
    name: &str,
) -> Result<PathSet, Fatal> {
    let fail = |e: FinishError| Fatal(format!("{name}: {e}"));
    let setup = FinishSetup { strategy, ..job.setup(part) };
    let setup = if for_program { for_machine(&job.machine, &setup) } else { setup };
    match layout {
        LayoutArg::IsoParametric => iso_parametric(&setup).map_err(fail),
        LayoutArg::IsoScallop => iso_scallop(&setup).map_err(fail),
    }
}

/// The scallop warning's note when the corrector stopped correcting (empty otherwise):
/// `share`, the job's `FinishOptions::corrector_share`.
fn corrector_note(stopped_at: Option<usize>, share: f64) -> String {
    stopped_at.map_or_else(String::new, |k| {
        format!(
            ", which stopped from path {k} on: its rebuilds had checked {:.0} % of the checks' budget, where the surface folds or turns tighter than the cutter",
            share * 100.0
        )
    })
}
