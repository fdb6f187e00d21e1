//! A machine's dynamics: per-axis velocity, acceleration and jerk limits of X Y Z (mm) and
//! A B C (degrees), the contour tolerance for corner blending (LinuxCNC's `G64 P`), exact stop
//! (`G61`), the look-ahead window and the interpolation period — with presets and the JSON
//! form the scene file (`dynamics`) and `interpolab time --machine FILE` read.
//!
//! Units: in the file and in [`AxisLimits`] velocities are mm/min (deg/min for A, B, C),
//! accelerations mm/s² (deg/s²), jerks mm/s³ (deg/s³), the tolerance mm and the period ms.
//! [`Dynamics::joint_limits`] converts them once into the planner's units: mm/s, mm/s²,
//! mm/s³ and rad/s, rad/s², rad/s³.

use serde_json::Value;
use thiserror::Error;

use crate::numerics::units;

/// Names of the six axes, in joint order.
pub const AXIS_NAMES: [&str; 6] = ["x", "y", "z", "a", "b", "c"];

/// Largest velocity limit accepted (mm/min or deg/min): a million, as the feed cap.
pub const MAX_VELOCITY: f64 = 1e6;
/// Largest acceleration limit accepted (mm/s² or deg/s²): 1e7, a thousand g.
pub const MAX_ACCELERATION: f64 = 1e7;
/// Largest jerk limit accepted (mm/s³ or deg/s³).
pub const MAX_JERK: f64 = 1e10;
/// Largest contour tolerance (mm): a blend may cut a corner by at most this.
pub const MAX_TOLERANCE_MM: f64 = 10.0;
/// Period range (ms).
pub const PERIOD_RANGE_MS: [f64; 2] = [0.01, 100.0];
/// Largest look-ahead window (blocks); larger windows are the whole program.
pub const MAX_WINDOW: usize = 1_000_000;

/// The limits of one axis, in file units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisLimits {
    /// Largest velocity (mm/min; deg/min for rotary axes).
    pub velocity: f64,
    /// Largest acceleration (mm/s²; deg/s²).
    pub acceleration: f64,
    /// Largest jerk (mm/s³; deg/s³); `None`: not limited (acceleration may jump).
    pub jerk: Option<f64>,
}

impl AxisLimits {
    const fn new(velocity: f64, acceleration: f64, jerk: f64) -> Self {
        Self { velocity, acceleration, jerk: Some(jerk) }
    }
}

/// A machine's dynamics and its controller's path settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    /// Name (a preset's, or the file's `name`).
    pub name: String,
    /// Limits of X, Y, Z, A, B, C.
    pub axes: [AxisLimits; 6],
    /// Contour tolerance P (mm): corners are blended so that the path stays within P of the
    /// programmed path (LinuxCNC `G64 P`); 0 stops at every corner.
    pub tolerance_mm: f64,
    /// Exact stop at every corner (`G61`), whatever the tolerance.
    pub exact_stop: bool,
    /// Look-ahead: how many blocks the controller sees ahead of the one it runs; `None`: the
    /// whole program.
    pub window_blocks: Option<usize>,
    /// Interpolation period Ts (ms).
    pub period_ms: f64,
}

/// The limits of the six joints in the planner's units: mm/s, mm/s², mm/s³ for X Y Z and
/// rad/s, rad/s², rad/s³ for A B C; an unlimited jerk is `f64::INFINITY`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointLimits {
    /// Velocity limits.
    pub v: [f64; 6],
    /// Acceleration limits.
    pub a: [f64; 6],
    /// Jerk limits (∞ when not limited).
    pub j: [f64; 6],
}

impl JointLimits {
    /// True when no axis limits jerk (an acceleration-limited, "jerk-free" setting).
    #[must_use]
    pub fn jerk_free(&self) -> bool {
        self.j.iter().all(|j| j.is_infinite())
    }
}

/// The presets, by name.
pub const PRESETS: [&str; 6] = ["hobby-router", "vmc", "table-ac", "table-bc", "head-bc", "head-a-table-c"];

fn linear(v: f64, a: f64, j: f64, vz: f64, az: f64, jz: f64) -> [AxisLimits; 3] {
    [AxisLimits::new(v, a, j), AxisLimits::new(v, a, j), AxisLimits::new(vz, az, jz)]
}

impl Dynamics {
    /// A preset by name ([`PRESETS`]).
    ///
    /// - `hobby-router`: a belt or screw-driven router of the GRBL class: X/Y 5000 mm/min,
    ///   300 mm/s², 3000 mm/s³; Z 2000 mm/min, 150 mm/s², 1500 mm/s³; P = 0.05 mm, Ts = 1 ms.
    /// - `vmc`: a vertical machining centre: X/Y/Z 30 m/min (Z 24), 3000 mm/s² (0.3 g),
    ///   50 000 mm/s³; P = 0.01 mm, Ts = 1 ms.
    /// - the four five-axis structures of the 5-axis tab ([`crate::fiveaxis::MachineKind`]):
    ///   the VMC's linear axes and rotary axes as such machines have them — a trunnion tilt
    ///   5400 deg/min (15 rpm), 600 deg/s², 6000 deg/s³; a rotary table 7200 deg/min (20 rpm),
    ///   900 deg/s², 9000 deg/s³; a spindle head's axes 3600 deg/min, 400 deg/s², 4000 deg/s³.
    ///
    /// The axes a structure lacks get the values of its other rotary axes (they do not move).
    #[must_use]
    pub fn preset(name: &str) -> Option<Self> {
        let vmc = linear(30_000.0, 3000.0, 50_000.0, 24_000.0, 3000.0, 50_000.0);
        let tilt = AxisLimits::new(5400.0, 600.0, 6000.0);
        let table = AxisLimits::new(7200.0, 900.0, 9000.0);
        let head = AxisLimits::new(3600.0, 400.0, 4000.0);
        let (lin, rot, tol) = match name {
            "hobby-router" => (
                linear(5000.0, 300.0, 3000.0, 2000.0, 150.0, 1500.0),
                [AxisLimits::new(3600.0, 300.0, 3000.0); 3],
                0.05,
            ),
            "vmc" => (vmc, [table; 3], 0.01),
            "table-ac" => (vmc, [tilt, table, table], 0.01),
            "table-bc" => (vmc, [tilt, tilt, table], 0.01),
            "head-bc" => (vmc, [head, head, head], 0.01),
            "head-a-table-c" => (vmc, [head, head, table], 0.01),
            _ => return None,
        };
        Some(Self {
            name: name.to_owned(),
            axes: [lin[0], lin[1], lin[2], rot[0], rot[1], rot[2]],
            tolerance_mm: tol,
            exact_stop: false,
            window_blocks: None,
            period_ms: 1.0,
        })
    }

    /// The same machine without jerk limits (acceleration may jump): the setting on which
    /// the time-optimal bound (TOPP) is compared.
    #[must_use]
    pub fn without_jerk(mut self) -> Self {
        for a in &mut self.axes {
            a.jerk = None;
        }
        self
    }

    /// The joint limits in the planner's units.
    #[must_use]
    pub fn joint_limits(&self) -> JointLimits {
        let mut l = JointLimits { v: [0.0; 6], a: [0.0; 6], j: [f64::INFINITY; 6] };
        for (i, ax) in self.axes.iter().enumerate() {
            let k = if i < 3 { 1.0 } else { std::f64::consts::PI / 180.0 };
            l.v[i] = units::mm_per_s_from_mm_per_min(ax.velocity) * k;
            l.a[i] = ax.acceleration * k;
            l.j[i] = ax.jerk.map_or(f64::INFINITY, |j| j * k);
        }
        l
    }

    /// The period in seconds.
    #[must_use]
    pub fn period_s(&self) -> f64 {
        units::s_from_ms(self.period_ms)
    }

    /// Checks every value; the first bad one as an error naming its key and what to give.
    ///
    /// # Errors
    /// [`MachineError`] with the key path (`axes.x.acceleration`).
    pub fn validate(&self) -> Result<(), MachineError> {
        for (i, ax) in self.axes.iter().enumerate() {
            let n = AXIS_NAMES[i];
            let (lu, au, ju) = if i < 3 { ("mm/min", "mm/s²", "mm/s³") } else { ("deg/min", "deg/s²", "deg/s³") };
            positive(&format!("axes.{n}.velocity"), ax.velocity, MAX_VELOCITY, &format!("the velocity limit in {lu}"))?;
            positive(
                &format!("axes.{n}.acceleration"),
                ax.acceleration,
                MAX_ACCELERATION,
                &format!("the acceleration limit in {au}"),
            )?;
            if let Some(j) = ax.jerk {
                positive(&format!("axes.{n}.jerk"), j, MAX_JERK, &format!("the jerk limit in {ju}, or null for none"))?;
            }
        }
        if !(self.tolerance_mm >= 0.0 && self.tolerance_mm <= MAX_TOLERANCE_MM) {
            return Err(MachineError::new(
                "tolerance",
                format!("must be from 0 to {MAX_TOLERANCE_MM} mm, got {}", self.tolerance_mm),
                "give the contour tolerance (G64 P) in mm, e.g. 0.01, or 0 to stop at every corner",
            ));
        }
        if !(self.period_ms >= PERIOD_RANGE_MS[0] && self.period_ms <= PERIOD_RANGE_MS[1]) {
            return Err(MachineError::new(
                "period",
                format!("must be from {} to {} ms, got {}", PERIOD_RANGE_MS[0], PERIOD_RANGE_MS[1], self.period_ms),
                "give the interpolation period in ms, e.g. 1",
            ));
        }
        if let Some(w) = self.window_blocks
            && (w == 0 || w > MAX_WINDOW)
        {
            return Err(MachineError::new(
                "lookahead",
                format!("must be from 1 to {MAX_WINDOW} blocks, got {w}"),
                "give the number of blocks the controller looks ahead, or null for the whole program",
            ));
        }
        Ok(())
    }

    /// Reads a machine from its JSON object (the scene's `dynamics`, or a machine file
    /// `{"format": "interpolab-machine/1", …}`). Keys: `preset` (a base to start from,
    /// default `vmc`), `name`, `axes` (`x` … `c`, each with `velocity`, `acceleration`,
    /// `jerk`; any subset, any axis), `tolerance`, `exact_stop`, `lookahead`, `period`.
    ///
    /// # Errors
    /// [`MachineError`] naming the key and what to give.
    pub fn from_value(v: &Value) -> Result<Self, MachineError> {
        let Some(o) = v.as_object() else {
            return Err(MachineError::new("", "must be an object", "give { \"preset\": \"vmc\", … }"));
        };
        const KEYS: [&str; 8] = ["format", "name", "preset", "axes", "tolerance", "exact_stop", "lookahead", "period"];
        for k in o.keys() {
            if !KEYS.contains(&k.as_str()) {
                return Err(MachineError::new(k, "is not a machine key", format!("use one of {}", KEYS.join(", "))));
            }
        }
        if let Some(f) = o.get("format")
            && f.as_str() != Some("interpolab-machine/1")
        {
            return Err(MachineError::new("format", "must be \"interpolab-machine/1\"", "give that exact text"));
        }
        let base = match o.get("preset") {
            None | Some(Value::Null) => "vmc",
            Some(Value::String(s)) => s.as_str(),
            Some(_) => {
                return Err(MachineError::new("preset", "must be a text", format!("one of {}", PRESETS.join(", "))));
            }
        };
        let mut d = Self::preset(base).ok_or_else(|| {
            MachineError::new(
                "preset",
                format!("\"{base}\" is not a preset"),
                format!("use one of {}", PRESETS.join(", ")),
            )
        })?;
        match o.get("name") {
            None | Some(Value::Null) => {}
            Some(Value::String(s)) => d.name.clone_from(s),
            Some(_) => return Err(MachineError::new("name", "must be a text", "give the machine's name")),
        }
        if let Some(axes) = o.get("axes") {
            let Some(axes) = axes.as_object() else {
                return Err(MachineError::new("axes", "must be an object", "give { \"x\": { \"velocity\": … }, … }"));
            };
            for (k, av) in axes {
                let Some(i) = AXIS_NAMES.iter().position(|n| n == k) else {
                    return Err(MachineError::new(format!("axes.{k}"), "is not an axis", "use x, y, z, a, b or c"));
                };
                let Some(ao) = av.as_object() else {
                    return Err(MachineError::new(
                        format!("axes.{k}"),
                        "must be an object",
                        "give { \"velocity\": …, \"acceleration\": …, \"jerk\": … }",
                    ));
                };
                for (key, x) in ao {
                    let path = format!("axes.{k}.{key}");
                    match key.as_str() {
                        "velocity" => d.axes[i].velocity = number(&path, x)?,
                        "acceleration" => d.axes[i].acceleration = number(&path, x)?,
                        "jerk" => d.axes[i].jerk = if x.is_null() { None } else { Some(number(&path, x)?) },
                        _ => {
                            return Err(MachineError::new(
                                path,
                                "is not an axis limit",
                                "use velocity, acceleration or jerk",
                            ));
                        }
                    }
                }
            }
        }
        if let Some(x) = o.get("tolerance") {
            d.tolerance_mm = number("tolerance", x)?;
        }
        if let Some(x) = o.get("exact_stop") {
            d.exact_stop = x
                .as_bool()
                .ok_or_else(|| MachineError::new("exact_stop", "must be true or false", "give true for G61"))?;
        }
        match o.get("lookahead") {
            None | Some(Value::Null) => {}
            Some(x) => {
                let n = x.as_u64().ok_or_else(|| {
                    MachineError::new(
                        "lookahead",
                        "must be a whole number of blocks",
                        "give e.g. 100, or null for the whole program",
                    )
                })?;
                d.window_blocks = Some(usize::try_from(n).unwrap_or(usize::MAX));
            }
        }
        if let Some(x) = o.get("period") {
            d.period_ms = number("period", x)?;
        }
        d.validate()?;
        Ok(d)
    }

    /// The JSON object of this machine (every key; [`Self::from_value`] reads it back to
    /// the same machine).
    #[must_use]
    pub fn to_value(&self) -> Value {
        let mut axes = serde_json::Map::new();
        for (i, a) in self.axes.iter().enumerate() {
            axes.insert(
                AXIS_NAMES[i].to_owned(),
                serde_json::json!({ "velocity": a.velocity, "acceleration": a.acceleration, "jerk": a.jerk }),
            );
        }
        serde_json::json!({
            "name": self.name,
            "axes": axes,
            "tolerance": self.tolerance_mm,
            "exact_stop": self.exact_stop,
            "lookahead": self.window_blocks,
            "period": self.period_ms,
        })
    }
}

fn number(path: &str, v: &Value) -> Result<f64, MachineError> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| MachineError::new(path, "must be a number", "give a decimal number"))
}

fn positive(path: &str, x: f64, max: f64, what: &str) -> Result<(), MachineError> {
    if x > 0.0 && x <= max {
        Ok(())
    } else {
        Err(MachineError::new(path, format!("must be > 0 and at most {max:e}, got {x}"), format!("give {what}")))
    }
}

/// A bad machine value: the key path, what is wrong and what to give.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("{path}: {problem}; {fix}")]
pub struct MachineError {
    /// Key path (`axes.x.jerk`).
    pub path: String,
    /// What is wrong.
    pub problem: String,
    /// What to give instead.
    pub fix: String,
}

impl MachineError {
    pub(crate) fn new(path: impl Into<String>, problem: impl Into<String>, fix: impl Into<String>) -> Self {
        Self { path: path.into(), problem: problem.into(), fix: fix.into() }
    }
}
