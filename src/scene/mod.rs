//! Scenes: the `interpolab-scene/1` JSON format (see `docs/scene-format.md`).
//!
//! A [`Scene`] holds the file's values in the file's units (mm, mm/min, ms, degrees) and is
//! what the app edits and saves. [`Scene::from_json`] parses and validates, naming the key
//! path of every problem and what to change; [`Scene::to_json`] writes it back (parse ∘ write
//! is the identity); [`crate::crease::CreaseJob::from_scene`] converts it to internal units
//! (radians, unit frames, NURBS in homogeneous form).

mod build;
mod dupkeys;
pub mod finish;
mod finish_spec;
mod job;
pub mod link;
mod parse;
pub mod presets;
mod write;

use thiserror::Error;

pub use build::{build_machine, build_surface, build_tool_axis, machine_spec, params_from_file};
pub use presets::{PRESETS, Preset};
pub use write::machine_value;

/// The format tag this version reads and writes.
pub const FORMAT: &str = "interpolab-scene/1";

/// Default of `path.max_steps` when the key is absent.
pub const DEFAULT_MAX_STEPS: u64 = 200_000;

/// Most characters of a file name's stem made from a scene's name ([`file_stem`]).
pub const MAX_FILE_STEM_CHARS: usize = 100;

/// The stem of a file name for a scene's downloads (`torus-ring-through-a-tilted-plate`):
/// the name's ASCII letters and digits in lower case, every run of anything else one `-`,
/// none at either end, at most [`MAX_FILE_STEM_CHARS`] characters; `None` when nothing is
/// left. So a name can give a file no path, no extension and no character a file system or
/// a browser treats specially. Looks at no more of the name than it needs.
#[must_use]
pub fn file_stem(name: &str) -> Option<String> {
    let mut stem = String::new();
    let mut gap = false;
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            if gap && !stem.is_empty() {
                if stem.len() + 1 >= MAX_FILE_STEM_CHARS {
                    break;
                }
                stem.push('-');
            }
            gap = false;
            stem.push(c.to_ascii_lowercase());
            if stem.len() == MAX_FILE_STEM_CHARS {
                break;
            }
        } else {
            gap = true;
        }
    }
    (!stem.is_empty()).then_some(stem)
}

/// A problem in a scene: where (`path`, e.g. `surfaces[1].radius`), what, and how to fix it.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("{path}: {problem}; {fix}")]
pub struct SceneError {
    /// Key path in the JSON document (`surfaces[0].domain.u`), or `(file)` for syntax errors.
    pub path: String,
    /// What is wrong, in the user's terms.
    pub problem: String,
    /// What to change.
    pub fix: String,
}

impl SceneError {
    pub(crate) fn new(path: impl Into<String>, problem: impl Into<String>, fix: impl Into<String>) -> Self {
        Self { path: path.into(), problem: tidy_numbers(&problem.into()), fix: fix.into() }
    }
}

/// Longest decimal a message shows as written; longer ones (Rust prints 1e300 with all its
/// 301 digits) are rewritten in exponent form.
const MAX_DECIMAL_CHARS: usize = 24;

/// Rewrites every decimal number longer than [`MAX_DECIMAL_CHARS`] in `text` as the shortest
/// exponent form of the same double (`1e300`, `-2.5e-200`), so a message never shows a
/// runaway number.
fn tidy_numbers(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let start = i;
        let mut j = i;
        if b[j] == b'-' && j + 1 < b.len() && b[j + 1].is_ascii_digit() {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_digit() && (start == 0 || !b[start - 1].is_ascii_alphanumeric()) {
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                j += 1;
            }
            let token = &text[start..j];
            match token.trim_end_matches('.').parse::<f64>() {
                Ok(x) if token.len() > MAX_DECIMAL_CHARS => out.push_str(&format!("{x:e}")),
                _ => out.push_str(token),
            }
            i = j;
        } else {
            let ch = text[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Which side of a closed analytic surface the cutter is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    /// Normal points away from the axis or centre (cutter outside).
    Outward,
    /// Normal points toward the axis or centre (cutter inside).
    Inward,
}

impl Orientation {
    /// The JSON spelling.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Outward => "outward",
            Self::Inward => "inward",
        }
    }
    /// +1 or −1.
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::Outward => 1.0,
            Self::Inward => -1.0,
        }
    }
}

/// A parameter rectangle in file units: `u: [a, b]`, `v: [a, b]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomainSpec {
    /// Range of u (degrees for angles, mm for lengths).
    pub u: [f64; 2],
    /// Range of v (degrees for angles, mm for lengths).
    pub v: [f64; 2],
}

/// One surface as written in a scene file (file units).
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceSpec {
    /// `r = o + u·e1 + v·e2`, `e1 = u_axis`, `e2 = normal × e1`.
    Plane {
        /// A point of the plane (mm).
        origin: [f64; 3],
        /// Normal, the cutter's side (any length > 0).
        normal: [f64; 3],
        /// Direction of u, in the plane.
        u_axis: [f64; 3],
        /// u, v ranges (mm).
        domain: DomainSpec,
    },
    /// A circular cylinder.
    Cylinder {
        /// A point on the axis, v = 0 (mm).
        origin: [f64; 3],
        /// Axis direction.
        axis: [f64; 3],
        /// Radius (mm).
        radius: f64,
        /// Direction of u = 0, ⊥ axis.
        ref_dir: Option<[f64; 3]>,
        /// u range (degrees), v range (mm along the axis).
        domain: DomainSpec,
        /// Cutter side.
        normal: Orientation,
    },
    /// A sphere.
    Sphere {
        /// Centre (mm).
        center: [f64; 3],
        /// Radius (mm).
        radius: f64,
        /// Polar axis (default +z).
        axis: Option<[f64; 3]>,
        /// Direction of u = 0, ⊥ axis.
        ref_dir: Option<[f64; 3]>,
        /// u (longitude), v (latitude) ranges in degrees; default the whole sphere.
        domain: Option<DomainSpec>,
        /// Cutter side.
        normal: Orientation,
    },
    /// A ring torus.
    Torus {
        /// Centre (mm).
        center: [f64; 3],
        /// Axis.
        axis: [f64; 3],
        /// Axis to tube centre (mm).
        major_radius: f64,
        /// Tube radius (mm).
        minor_radius: f64,
        /// Direction of u = 0, ⊥ axis.
        ref_dir: Option<[f64; 3]>,
        /// u, v ranges in degrees; default the whole torus.
        domain: Option<DomainSpec>,
        /// Cutter side.
        normal: Orientation,
    },
    /// A tensor-product NURBS.
    Nurbs {
        /// Degrees `[p, q]` in u and v.
        degree: [usize; 2],
        /// Clamped knot vector in u.
        knots_u: Vec<f64>,
        /// Clamped knot vector in v.
        knots_v: Vec<f64>,
        /// Control net, `points[i][j]`, i along u (mm).
        points: Vec<Vec<[f64; 3]>>,
        /// Weights, same shape, > 0 (all 1 when absent).
        weights: Option<Vec<Vec<f64>>>,
        /// Reverse the normal r_u × r_v.
        flip_normal: bool,
    },
}

impl SurfaceSpec {
    /// The JSON `type`.
    #[must_use]
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Plane { .. } => "plane",
            Self::Cylinder { .. } => "cylinder",
            Self::Sphere { .. } => "sphere",
            Self::Torus { .. } => "torus",
            Self::Nurbs { .. } => "nurbs",
        }
    }
}

/// `tool`: the ball-end cutter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolSpec {
    /// Ball radius R (mm).
    pub radius: f64,
    /// Stock C left on both surfaces (mm); the centre runs at R' = R + C. May be negative
    /// (undersize) as long as R' > 0.
    pub allowance: f64,
}

/// `motion`: feed and interpolation period.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionSpec {
    /// Programmed feed F (mm/min).
    pub feed: f64,
    /// Interpolation period Ts (ms).
    pub period: f64,
}

/// `tolerance`: allowed machining errors and the interpolation's share of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToleranceSpec {
    /// T1, allowed error on surface 1 (mm).
    pub t1: f64,
    /// T2, allowed error on surface 2 (mm).
    pub t2: f64,
    /// b, share of the tolerance given to interpolation, 0 < b ≤ 1.
    pub share: f64,
}

/// `path`: where the cut starts and ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathSpec {
    /// Approximate cutter-centre start point (mm).
    pub start: [f64; 3],
    /// Approximate end point (mm), or `None` (JSON `null`).
    pub end: Option<[f64; 3]>,
    /// Most periods to run (default [`DEFAULT_MAX_STEPS`]).
    pub max_steps: u64,
    /// Sense of travel at the start (default: the sense of n1 × n2).
    pub direction: Option<[f64; 3]>,
}

/// Default travel of the tilting axis (A or B) when `machine.limits` does not give one
/// (degrees).
pub const DEFAULT_TILT_LIMITS_DEG: [f64; 2] = [-120.0, 120.0];

/// `machine` (optional): the five-axis machine the tool-step selection plans for, in file
/// units (mm, degrees). See `docs/scene-format.md` and `docs/fiveaxis.md`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineSpec {
    /// Structure (`table-ac`, `table-bc`, `head-bc`, `head-a-table-c`).
    pub kind: crate::fiveaxis::MachineKind,
    /// Pivots of the tilting axis and of C (mm; `[0, 0, 0]` when absent). `head-bc` has no C
    /// pivot.
    pub pivots: [[f64; 3]; 2],
    /// Distance from the last head axis to the tool tip (mm); head machines need it > 0.
    pub tool_length: f64,
    /// Travel of the tilting axis and of C (degrees), `None` for unlimited. Absent keys
    /// default to [`DEFAULT_TILT_LIMITS_DEG`] and unlimited C.
    pub limits: [Option<[f64; 2]>; 2],
}

/// `tool_axis` (optional): how the tool axis is chosen along the crease.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToolAxisSpec {
    /// `{ "rule": "bisector" }`: the bisector of the two contact normals.
    Bisector,
    /// `{ "rule": "normal1", "lead": deg, "tilt": deg }`: the normal of surface 1 turned by
    /// lead (toward the travel) and tilt (sideways), both default 0.
    Normal1 {
        /// Lead angle (degrees).
        lead: f64,
        /// Tilt angle (degrees).
        tilt: f64,
    },
    /// `{ "rule": "fixed", "vector": [i, j, k] }`: a constant direction.
    Fixed {
        /// The direction (any length > 0).
        vector: [f64; 3],
    },
}

/// A whole scene in file units.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Display name.
    pub name: String,
    /// S1 and S2.
    pub surfaces: [SurfaceSpec; 2],
    /// The cutter.
    pub tool: ToolSpec,
    /// Feed and period.
    pub motion: MotionSpec,
    /// Tolerances.
    pub tolerance: ToleranceSpec,
    /// Start and end.
    pub path: PathSpec,
    /// The five-axis machine (`None`: the key is absent).
    pub machine: Option<MachineSpec>,
    /// The tool-axis rule (`None`: the key is absent).
    pub tool_axis: Option<ToolAxisSpec>,
    /// The machine's dynamics for feed planning (`None`: the key is absent).
    pub dynamics: Option<crate::plan::Dynamics>,
}

impl Scene {
    /// Parses and validates a scene document.
    ///
    /// # Errors
    /// The first problem found, with its key path and a fix.
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        let scene = parse::parse(text)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Writes the scene as pretty-printed JSON (keys in the format's order).
    #[must_use]
    pub fn to_json(&self) -> String {
        write::to_json(self)
    }

    /// Writes the scene as one-line JSON (for share links).
    #[must_use]
    pub fn to_json_compact(&self) -> String {
        write::to_json_compact(self)
    }

    /// Checks every value's range (radii > 0, tolerances > 0, knot vectors, …).
    ///
    /// # Errors
    /// The first problem found, with its key path and a fix.
    pub fn validate(&self) -> Result<(), SceneError> {
        build::validate(self)
    }

    /// Feed per period f = F·Ts/60000 (mm).
    #[must_use]
    pub fn feed_per_period_mm(&self) -> f64 {
        crate::numerics::units::mm_per_period(self.motion.feed, self.motion.period)
    }

    /// Effective cutter radius R' = R + C (mm).
    #[must_use]
    pub fn effective_radius_mm(&self) -> f64 {
        self.tool.radius + self.tool.allowance
    }
}

#[cfg(test)]
mod tidy_tests {
    #[test]
    fn runaway_decimals_are_written_in_exponent_form() {
        let long = format!("got {}, range [-80, {}]", 1e300, -1e-200);
        assert_eq!(super::tidy_numbers(&long), "got 1e300, range [-80, -1e-200]");
        assert_eq!(super::tidy_numbers("u = 0.5 mm, knot 6 (0.25), 1.5°"), "u = 0.5 mm, knot 6 (0.25), 1.5°");
    }
}
