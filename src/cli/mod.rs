//! The native command line. Every subcommand drives the core; nothing here computes
//! geometry itself.
//!
//! Exit status: 0 success; 1 `check` found an error above the tolerance; 2 a bad scene,
//! an unreadable file, or a crease that cannot be started or continued (one line on
//! standard error naming the problem, where, and what to change; rows computed before are
//! still written).
//!
//! One file per area: [`crease`] (`run`, `check`), [`gcode`] (`gcode`, `replay`, `compare`,
//! `nurbs`), [`userprog`] (`canon`, and `replay` and `simulate` of a user's program),
//! [`fiveaxis`] (`steps`, `example1`, `table1`, `chords`), [`finish`], [`simulate`], [`time`];
//! [`program`] reads program files for them, [`dynamics`] a machine's dynamics (`--machine`),
//! [`plain_run`] reads a plain `run` without clap.

mod crease;
mod dynamics;
mod finish;
mod fiveaxis;
mod gcode;
mod plain_run;
mod program;
mod simulate;
mod time;
mod userprog;

use std::ffi::OsString;
use std::io::{self, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

#[derive(Parser)]
#[command(
    name = "interpolab",
    version,
    about = "CNC tool-path interpolation lab: tool paths by the papers' methods, G-code written and read, cutting simulation, machining time",
    long_about = "CNC tool-path interpolation lab: tool paths by the papers' methods (crease interpolation; fillet-end finishing; five-axis tool steps; equal-error chords; NURBS fitting and G-code; docs/papers.md cites each paper), G-code programs written and read, cutting simulation on a dexel stock, and the time a program takes on a machine.\n\nWithout a subcommand (and built with the `app` feature) it opens the app in a window."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum OutFormat {
    Csv,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum MethodArg {
    /// The crease paper's track–correct–re-solve step (no iteration).
    Seed000,
    /// Newton projection onto the exact crease (precise mode).
    Exact,
}

#[derive(Subcommand)]
enum Command {
    /// Interpolate the crease of a scene: one row per period (k, t_ms, x, y, z, u1, v1, u2, v2).
    Run {
        /// Scene file (interpolab-scene/1 JSON).
        scene: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value = "csv")]
        format: OutFormat,
        /// Write to this file instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Add measured errors e1, e2 and the paper's estimates (11), (12), (16) as columns (mm).
        #[arg(long)]
        errors: bool,
        /// Stepper.
        #[arg(long, value_enum, default_value = "seed000")]
        method: MethodArg,
        /// Full turns of a closed crease before stopping.
        #[arg(long, default_value_t = 1)]
        turns: u32,
    },
    /// Validate a scene, run it and print a summary (length, periods, curvatures, errors).
    Check {
        /// Scene file.
        scene: PathBuf,
    },
    /// Write a G01, G02/G03 or G06.2 program for a scene's crease within a tolerance.
    Gcode(gcode::GcodeArgs),
    /// Read a G-code program; with --scene, report its deviation from the design crease.
    Replay(Box<gcode::ReplayArgs>),
    /// Read a G-code program as the controller reads it (RS274/NGC, LinuxCNC, FANUC macros) and print its canonical calls, one a line, in machine mm.
    Canon(userprog::CanonArgs),
    /// Compare the G01, G02/G03 and G06.2 programs at a tolerance (blocks, bytes, deviation, smoothness).
    Compare(gcode::CompareArgs),
    /// Real-time interpolation of the fitted G06.2 curve: one CSV row per period.
    Nurbs(gcode::NurbsArgs),
    /// Five-axis tool steps (Ji, Zhou, An & Zhang 2010): nodes with joint values so every segment's |δt + δn| = E.
    Steps(fiveaxis::StepsArgs),
    /// Example 1 of the 5-axis steps paper: the gouge of one block, then the steps the method inserts.
    Example1(fiveaxis::Example1Args),
    /// Table 1 of the 5-axis steps paper: iterations and time per step-selection method at 0.1, 0.01, 0.001 mm.
    Table1(fiveaxis::Table1Args),
    /// Equal-error chords of a planar curve or a scene's crease; --table compares spacings.
    Chords(fiveaxis::ChordsArgs),
    /// Five-axis finishing of one surface with a fillet-end mill: CL data, --table, --gcode.
    Finish(finish::FinishArgs),
    /// Cutting simulation: machine a G-code program into a dexel stock; height map (CSV), PNG, statistics (JSON).
    Simulate(Box<simulate::SimulateArgs>),
    /// The time a program takes on a machine: feed planned within its limits, corners blended, look-ahead; per block and, with --periods, per period.
    Time(time::TimeArgs),
}

/// Reads a file the command line was given, at most `cap` bytes of it
/// ([`interpolab::numerics::limits`]): a wrong path (`/dev/zero`) is refused, not read forever.
pub(crate) fn read_capped(path: &std::path::Path, cap: u64, what: &'static str) -> Result<String, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    interpolab::numerics::limits::read_text(file, cap, what)
}

/// The parser of every numeric option: a decimal number that is finite. `nan`, `inf` and
/// `1e999` are refused while the arguments are read, with the option's name and the text
/// given (clap adds them), before any work and before a message could print a non-number.
pub(crate) fn finite(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        // The text is not repeated: it is a non-number, which no message of ours prints.
        Ok(_) => {
            Err("needs a finite number, and the value given is not one; give a decimal number such as 0.5".to_owned())
        }
        Err(_) => Err(format!("needs a number, got '{}'; give a decimal number such as 0.5", text.trim())),
    }
}

/// Pretty-prints a JSON document (two-space indent, keys in insertion order) with every
/// number as the shortest decimal that reads back to the same double
/// ([`interpolab::numerics::format::push_num`], as every other command prints numbers:
/// `4`, not `4.0`); a non-finite number prints as null.
pub(crate) fn pretty_json(v: &serde_json::Value, depth: usize, out: &mut String) {
    use serde_json::Value;
    let pad = |out: &mut String, d: usize| out.extend(std::iter::repeat_n("  ", d));
    match v {
        Value::Number(n) => match (n.as_i64(), n.as_u64(), n.as_f64()) {
            (Some(i), _, _) => out.push_str(&i.to_string()),
            (_, Some(u), _) => out.push_str(&u.to_string()),
            (_, _, Some(x)) if x.is_finite() => interpolab::numerics::format::push_num(out, x),
            _ => out.push_str("null"),
        },
        Value::Array(items) if !items.is_empty() => {
            out.push('[');
            for (k, item) in items.iter().enumerate() {
                out.push_str(if k == 0 { "\n" } else { ",\n" });
                pad(out, depth + 1);
                pretty_json(item, depth + 1, out);
            }
            out.push('\n');
            pad(out, depth);
            out.push(']');
        }
        Value::Object(map) if !map.is_empty() => {
            out.push('{');
            for (k, (key, item)) in map.iter().enumerate() {
                out.push_str(if k == 0 { "\n" } else { ",\n" });
                pad(out, depth + 1);
                out.push_str(&serde_json::to_string(key).unwrap_or_default());
                out.push_str(": ");
                pretty_json(item, depth + 1, out);
            }
            out.push('\n');
            pad(out, depth);
            out.push('}');
        }
        other => out.push_str(&serde_json::to_string(other).unwrap_or_default()),
    }
}

pub(crate) fn numbers(text: &str, what: &str, n: usize) -> Result<Vec<f64>, Fatal> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| Fatal(format!("--{what} `{text}`: expected {n} comma-separated numbers in mm")))?;
    if v.len() != n || v.iter().any(|x| !x.is_finite()) {
        return Err(Fatal(format!("--{what} `{text}`: expected {n} comma-separated finite numbers in mm")));
    }
    Ok(v)
}

/// The `--stock` box `x0,y0,z0,x1,y1,z1` (mm) as a dexel stock of rays `pitch` mm apart.
pub(crate) fn stock_block(text: &str, pitch: f64) -> Result<interpolab::simulate::DexelStock, Fatal> {
    let s = numbers(text, "stock", 6)?;
    interpolab::simulate::DexelStock::block([s[0], s[1], s[2]], [s[3], s[4], s[5]], pitch)
        .map_err(|e| Fatal(e.to_string()))
}

/// A failure that ends the program with status 2 and one line on stderr.
pub(crate) struct Fatal(pub(crate) String);

/// Parses the arguments and runs the subcommand.
pub fn main() -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    // A plain `run` skips building clap's command tree (`plain_run`); the values are the ones
    // clap would give, and anything else is clap's to parse, with its messages.
    let command = match plain_run::parse(&args) {
        Some(plain_run::RunArgs { scene, format, out, errors, method, turns }) => {
            Some(Command::Run { scene, format, out, errors, method, turns })
        }
        None => match Cli::try_parse_from(args) {
            Ok(cli) => cli.command,
            Err(e) => return usage_error(&e),
        },
    };
    let result = match command {
        None => open_app(),
        Some(Command::Run { scene, format, out, errors, method, turns }) => {
            crease::run(&scene, format, out.as_deref(), errors, method, turns)
        }
        Some(Command::Check { scene }) => crease::check(&scene),
        Some(Command::Gcode(a)) => gcode::gcode(&a),
        Some(Command::Replay(a)) => gcode::replay(&a),
        Some(Command::Canon(a)) => userprog::canon(&a),
        Some(Command::Compare(a)) => gcode::compare_cmd(&a),
        Some(Command::Nurbs(a)) => gcode::nurbs(&a),
        Some(Command::Steps(a)) => fiveaxis::steps(&a),
        Some(Command::Example1(a)) => fiveaxis::example1_cmd(&a),
        Some(Command::Table1(a)) => fiveaxis::table1(&a),
        Some(Command::Chords(a)) => fiveaxis::chords(&a),
        Some(Command::Finish(a)) => finish::finish(&a),
        Some(Command::Simulate(a)) => simulate::simulate(&a),
        Some(Command::Time(a)) => time::time(&a),
    };
    match result {
        Ok(code) => code,
        Err(Fatal(msg)) => {
            // One line, whatever user text the message quotes.
            let _ = writeln!(io::stderr(), "interpolab: {}", interpolab::report::message_line(&msg));
            ExitCode::from(2)
        }
    }
}

/// clap's help and version go out as clap prints them; a usage error (an unknown option, a
/// value that does not parse) becomes one line like every other refusal: clap's message and
/// its tip, if any, status 2.
fn usage_error(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    // A value our parser refused: the option and our reason (clap's own text would repeat a
    // `nan` or `inf` the user typed).
    if e.kind() == ErrorKind::ValueValidation {
        use std::error::Error as _;
        if let (Some(clap::error::ContextValue::String(arg)), Some(why)) =
            (e.get(clap::error::ContextKind::InvalidArg), e.source())
        {
            let _ = writeln!(io::stderr(), "interpolab: {arg} {why} (see --help)");
            return ExitCode::from(2);
        }
    }
    let text = e.render().to_string();
    // clap's message is its lines before `Usage:` (a list of missing arguments follows the
    // first line), then perhaps a `tip:`.
    let mut message = String::new();
    let mut tip = None;
    for l in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if l.starts_with("Usage:") || l.starts_with("For more information") {
            break;
        }
        if let Some(t) = l.strip_prefix("tip: ") {
            tip = Some(t.to_owned());
            continue;
        }
        if !message.is_empty() {
            message.push(' ');
        }
        message.push_str(l.strip_prefix("error: ").unwrap_or(l));
    }
    if message.is_empty() {
        message.push_str("the arguments could not be read");
    }
    let line = match tip {
        Some(tip) => format!("interpolab: {message}; {tip} (see --help)"),
        None => format!("interpolab: {message} (see --help)"),
    };
    let _ = writeln!(io::stderr(), "{}", interpolab::report::message_line(&line));
    ExitCode::from(2)
}

#[cfg(feature = "app")]
fn open_app() -> Result<ExitCode, Fatal> {
    interpolab::app::native::run().map_err(|e| Fatal(format!("cannot open the app window: {e}")))?;
    Ok(ExitCode::SUCCESS)
}

#[cfg(not(feature = "app"))]
fn open_app() -> Result<ExitCode, Fatal> {
    use clap::CommandFactory;
    let _ = Cli::command().print_help();
    Ok(ExitCode::SUCCESS)
}

/// Writes `bytes` to `path`, or the error naming the file.
pub(crate) fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<(), Fatal> {
    std::fs::write(path, bytes).map_err(|e| Fatal(format!("cannot write {}: {e}", path.display())))
}

/// The height map's files a `simulate` run was asked for: the CSV to `out`, the PNG (its
/// deviation band ±`band_um` µm) to `png`; `stats` when the run has a design.
pub(crate) fn write_height_files(
    out: Option<&std::path::Path>,
    png: Option<&std::path::Path>,
    band_um: f64,
    map: &interpolab::simulate::HeightMap,
    stats: Option<&interpolab::simulate::SimStats>,
    z_range_mm: (f64, f64),
) -> Result<(), Fatal> {
    if let Some(out) = out {
        write_file(out, interpolab::simulate::heights_csv(map, stats).as_bytes())?;
    }
    if let Some(png) = png {
        let band_mm = band_um * interpolab::numerics::units::MM_PER_UM;
        write_file(png, &interpolab::simulate::png_rgb(map, stats, z_range_mm, band_mm))?;
    }
    Ok(())
}

/// The crashes of a `simulate` run: one line on standard error (counts per kind and the
/// first), the CSV list written to `path` when given, and the JSON `crashes` object.
/// `tool_number` names a tool slot's tool (`None`: the one cutter of a plain run).
/// `assumed`: a tool's lengths are the defaults (the line says how to give them).
pub(crate) fn crash_report(
    log: &interpolab::simulate::CrashLog,
    path: Option<&std::path::Path>,
    assumed: bool,
    tool_number: impl Fn(u16) -> Option<i32>,
) -> Result<serde_json::Value, Fatal> {
    use interpolab::simulate::CrashKind;
    if let Some(line) = log.summary() {
        let more = if path.is_some() { "" } else { "; --crashes FILE lists them" };
        let lengths = if assumed && (log.count(CrashKind::Shank) > 0 || log.count(CrashKind::Holder) > 0) {
            " (the tool's flute, shank and holder lengths are assumed: give them, e.g. --cutter ball:3,flute=25,shank=3:40,holder=16:60)"
        } else {
            ""
        };
        eprintln!("interpolab: {line}{lengths}{more}");
    }
    if let Some(path) = path {
        write_file(path, log.csv(&tool_number).as_bytes())?;
    }
    let nm = |mm: f64| (mm * 1e6).round() / 1e6 + 0.0;
    let mut counts = serde_json::Map::new();
    for k in CrashKind::ALL {
        counts.insert(k.name().to_owned(), log.count(k).into());
    }
    let first = log.list().first().map(|c| {
        serde_json::json!({
            "line": c.line, "kind": c.kind.name(), "tool": tool_number(c.slot),
            "depth_mm": nm(c.depth_mm), "x_mm": nm(c.at_mm.x), "y_mm": nm(c.at_mm.y), "z_mm": nm(c.at_mm.z),
        })
    });
    let deepest = log.list().iter().map(|c| c.depth_mm).fold(0.0_f64, f64::max);
    Ok(serde_json::json!({
        "total": log.total(),
        "by_kind": counts,
        "deepest_mm": nm(deepest),
        "first": first,
        "touch_mm": interpolab::simulate::TOUCH_MM,
    }))
}
