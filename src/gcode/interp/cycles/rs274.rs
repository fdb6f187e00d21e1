//! Test support shared by the cycle, spline and tool-table tests: runs LinuxCNC's standalone
//! interpreter `rs274` on a program and reads the canonical calls it prints
//! (`   12 N..... STRAIGHT_FEED(4.0000, 5.0000, -3.0000, …)`).
//!
//! `rs274` prints program coordinates in program units with four decimals. When it is not
//! installed (`scripts/setup.sh test` installs Debian's `linuxcnc-uspace`), [`run`] says so
//! on stderr once per test and returns `None`, and the test returns without checking.

use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One canonical call: its name and its arguments as printed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Call {
    /// `STRAIGHT_FEED`, `DWELL`, …
    pub name: String,
    /// The text between the parentheses, split at commas and trimmed.
    pub args: Vec<String>,
}

impl Call {
    /// The arguments as numbers (`None` for one that is not).
    pub fn numbers(&self) -> Vec<Option<f64>> {
        self.args.iter().map(|a| a.parse::<f64>().ok()).collect()
    }
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

fn temp_path(ext: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("interpolab-rs274-{}-{n}.{ext}", std::process::id()))
}

/// Runs `rs274 -g` on `program` (with `-t` and the tool table's text when given). `None`
/// when `rs274` is not installed; `Some(Err(stderr))` when it refuses the program.
pub(crate) fn run(program: &str, tool_table: Option<&str>) -> Option<Result<Vec<Call>, String>> {
    let ngc = temp_path("ngc");
    std::fs::write(&ngc, program).ok()?;
    let tbl = tool_table.map(|t| {
        let p = temp_path("tbl");
        let _ = std::fs::write(&p, t);
        p
    });
    // rs274 keeps its tool table in `$HOME/.tool.mmap`, truncated by every run: give each
    // run a home of its own so that tests running side by side do not share it.
    let home = temp_path("home");
    let _ = std::fs::create_dir_all(&home);
    let mut cmd = Command::new("rs274");
    cmd.env("HOME", &home);
    if let Some(t) = &tbl {
        cmd.arg("-t").arg(t);
    }
    cmd.arg("-g").arg(&ngc);
    let output = cmd.output();
    let _ = std::fs::remove_file(&ngc);
    let _ = std::fs::remove_dir_all(&home);
    if let Some(t) = &tbl {
        let _ = std::fs::remove_file(t);
    }
    let output = match output {
        Ok(o) => o,
        Err(e) => {
            eprintln!("skipped: LinuxCNC's rs274 could not be run ({e}); `scripts/setup.sh test` installs it");
            return None;
        }
    };
    let stdout = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        return Some(Err(String::from_utf8_lossy(&output.stderr).into_owned()));
    }
    Some(Ok(stdout.lines().filter_map(parse_line).collect()))
}

/// `   12 N..... NAME(a, b)` → the call.
fn parse_line(line: &str) -> Option<Call> {
    let rest = line.trim_start();
    let rest = rest.split_once(' ')?.1.trim_start();
    let rest = rest.strip_prefix('N')?.trim_start_matches(|c: char| c == '.' || c.is_ascii_digit()).trim_start();
    let open = rest.find('(')?;
    let close = rest.rfind(')')?;
    let name = rest[..open].to_owned();
    let inner = &rest[open + 1..close];
    let args =
        if inner.trim().is_empty() { Vec::new() } else { inner.split(',').map(|s| s.trim().to_owned()).collect() };
    Some(Call { name, args })
}

/// The calls strictly between the `DWELL` printed for `G4 P<start>` and the one for
/// `G4 P<end>` (markers a test puts around the part it checks).
pub(crate) fn between(calls: &[Call], start: f64, end: f64) -> Vec<Call> {
    let is = |c: &Call, v: f64| c.name == "DWELL" && c.numbers().first().copied().flatten() == Some(v);
    let from = calls.iter().position(|c| is(c, start)).map_or(calls.len(), |i| i + 1);
    let to = calls[from..].iter().position(|c| is(c, end)).map_or(calls.len(), |i| from + i);
    calls[from..to].to_vec()
}

#[test]
fn printed_calls_are_parsed() {
    let c = parse_line("   17 N..... STRAIGHT_FEED(4.0000, 5.0000, -3.0000, 0.0000, 0.0000, 0.0000)");
    assert_eq!(
        c.map(|c| (c.name.clone(), c.numbers())),
        Some(("STRAIGHT_FEED".to_owned(), vec![Some(4.0), Some(5.0), Some(-3.0), Some(0.0), Some(0.0), Some(0.0)]))
    );
    assert_eq!(parse_line("   20 N..... PROGRAM_STOP()").map(|c| c.args.len()), Some(0));
    assert_eq!(parse_line("executing"), None);
}
