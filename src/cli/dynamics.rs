//! The machine's dynamics from the command line: `--machine PRESET|FILE` and the overrides
//! of `interpolab time` (shared by `time`, `compare --machine`, `steps` and `example1`).

use std::path::Path;

use interpolab::plan::{Dynamics, PRESETS};

use super::Fatal;

/// A machine from `--machine` (a preset or a file).
pub(crate) fn machine_of(arg: &str) -> Result<Dynamics, Fatal> {
    if let Some(d) = Dynamics::preset(arg) {
        return Ok(d);
    }
    let p = Path::new(arg);
    if !p.exists() {
        return Err(Fatal(format!(
            "--machine: '{arg}' is neither a preset nor a file; give one of {} or a machine file (JSON)",
            PRESETS.join(", ")
        )));
    }
    let text = super::read_capped(p, interpolab::numerics::limits::MAX_SCENE_BYTES, "machine file")
        .map_err(|e| Fatal(format!("cannot read machine file {arg}: {e}")))?;
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| Fatal(format!("{arg}: not JSON: {e}; give a machine object")))?;
    let obj = v.get("dynamics").unwrap_or(&v);
    Dynamics::from_value(obj).map_err(|e| Fatal(format!("{arg}: {e}")))
}

/// The machine with the command line's overrides, checked before any work; a bad value
/// names its option.
pub(crate) fn machine_with(
    base: Dynamics,
    tolerance: Option<f64>,
    exact_stop: bool,
    window: Option<usize>,
    period: Option<f64>,
    no_jerk: bool,
) -> Result<Dynamics, Fatal> {
    let mut d = base;
    if let Some(t) = tolerance {
        d.tolerance_mm = t;
    }
    d.exact_stop |= exact_stop;
    if let Some(w) = window {
        d.window_blocks = Some(w);
    }
    if let Some(p) = period {
        d.period_ms = p;
    }
    if no_jerk {
        d = d.without_jerk();
    }
    d.validate().map_err(|e| {
        let opt = match e.path.as_str() {
            "tolerance" => "--tolerance".to_owned(),
            "lookahead" => "--window".to_owned(),
            "period" => "--period".to_owned(),
            p => format!("--machine {}: {p}", d.name),
        };
        Fatal(format!("{opt}: {}; {}", e.problem, e.fix))
    })?;
    Ok(d)
}
