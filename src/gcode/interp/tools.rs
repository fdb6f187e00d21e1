//! Tool tables: the tools a program's `T`, `M6`, `G43` and `G41`/`G42` words refer to — their
//! length offsets, diameters and shapes — read from a LinuxCNC `.tbl` file, a CAMotics
//! project (`.camotics`) or a command-line spec `N:shape:diameter[:corner]`.
//!
//! Everything is stored in **mm** and **degrees**; a `.tbl` is in the machine's units, which
//! the file does not say, so the reader takes them as an argument ([`TableUnits`]).
//!
//! **LinuxCNC `.tbl`** (LinuxCNC manual, "Tool Table Format"; `tooldata_read_entry`): one
//! tool a line, words `T` (tool number), `P` (pocket), `X Y Z A B C U V W` (offsets), `D`
//! (diameter), `I J` (lathe front and back angles), `Q` (lathe orientation), in any order,
//! then an optional `;` and a remark; a line starting with `;` is a comment. Differences,
//! all on input LinuxCNC would misread or skip: words may be separated by tabs as well as
//! spaces (LinuxCNC 2.9 splits at spaces only), a line LinuxCNC skips as "unrecognized"
//! (an unknown letter, a word without a number) is refused with its line, as is a tool
//! number given twice (LinuxCNC keeps both and finds the first) and a line without `T`. A
//! negative `D` is taken as its absolute value, as the manual says.
//!
//! **The shape from the remark** — our convention, since a `.tbl` has no shape column: the
//! remark's first word, in any case, names it, and the rest of the remark is free text:
//!
//! | remark starts with | shape |
//! |---|---|
//! | `flat`, `endmill` | flat end mill of diameter D |
//! | `ball`, `ballnose` | ball end mill of diameter D |
//! | `bull r=1`, `bull 1`, `fillet r1`, `torus r=1` | bull nose (fillet) mill, corner radius 1 in the table's units |
//! | `v90`, `v 90`, `v=90`, `vbit 60` | V cutter with a 90° included tip angle |
//! | `drill`, `drill 135` | drill with a 118° (or the given) point angle |
//!
//! Without one of these words the tool is taken as a **flat end mill of diameter D** and
//! [`ToolEntry::shape_assumed`] says so, for a viewer to mention.
//!
//! **The body from the remark**, also our convention: words anywhere in it, in the table's
//! units — `flute=20` (flute length), `shank=3:30` (radius:length above the flutes),
//! `holder=10:40` (radius:length above the shank), `nocentre` (the end does not cut at its
//! centre) — fill [`ToolEntry::body`] ([`BodySpec::word`]); what is not given keeps the
//! defaults of [`Cutter::fillet`].
//!
//! **CAMotics** (`src/gcode/Tool.cpp`, `ToolTable.cpp`, `src/camotics/project/Project.cpp`,
//! `Workpiece.cpp` of CAMotics): a JSON project whose `tools` object maps tool numbers to
//! `{units: "metric"|"imperial", shape: "cylindrical"|"ballnose"|"conical"|"snubnose"|
//! "spheroid", length, diameter, snub_diameter, description}` (a tool without `units` is
//! metric; without `length`/`diameter` it is 10 mm long and 2 mm across, CAMotics' defaults);
//! `units` of the project, `workpiece {automatic, margin, bounds {min, max}}` (bounds in mm),
//! `files`. A conical tool's included angle is 2·atan(R / length), as CAMotics computes it.
//!
//! **Command line** `N:shape:diameter[:corner]`, diameter in mm: `1:ball:6`, `2:bull:10:1`
//! (corner radius 1 mm), `3:v:6:90` (90° tip), `4:flat:3`, `5:drill:8[:118]`, each with
//! optional body words after commas, in mm: `1:ball:6,flute=20,shank=3:30,holder=10:40`.

use std::collections::BTreeMap;

use glam::DVec3;
use thiserror::Error;

use crate::geom::{BodySpec, Cutter, CutterError};
pub use crate::numerics::limits::{MAX_TOOL_TABLE_BYTES, MAX_TOOLS};

#[cfg(test)]
mod tests;

/// Millimetres per inch.
const MM_PER_INCH: f64 = 25.4;

/// A drill's point angle when the remark gives none (degrees): the common twist drill.
pub const DEFAULT_DRILL_POINT_DEG: f64 = 118.0;

/// The units a `.tbl` file is written in (the machine's units: LinuxCNC's
/// `[TRAJ]LINEAR_UNITS`; LinuxCNC's standalone `rs274` takes inches).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TableUnits {
    /// Millimetres.
    #[default]
    Mm,
    /// Inches.
    Inch,
}

impl TableUnits {
    /// Millimetres per unit.
    #[must_use]
    pub fn mm(self) -> f64 {
        match self {
            Self::Mm => 1.0,
            Self::Inch => MM_PER_INCH,
        }
    }
}

/// The cutting shape of a tool.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ToolShape {
    /// Flat end mill (CAMotics `cylindrical`).
    #[default]
    Flat,
    /// Ball end mill (CAMotics `ballnose`).
    Ball,
    /// Bull-nose (fillet, toroidal) end mill.
    Bull {
        /// Corner radius (mm), 0 < r < D/2.
        corner_radius_mm: f64,
    },
    /// V cutter, engraver or chamfer mill (CAMotics `conical`).
    V {
        /// Included tip angle (degrees).
        tip_angle_deg: f64,
    },
    /// Twist drill.
    Drill {
        /// Included point angle (degrees).
        point_angle_deg: f64,
    },
    /// A cone cut off by a flat tip (CAMotics `snubnose`).
    Snub {
        /// Diameter of the flat tip (mm).
        tip_diameter_mm: f64,
    },
    /// A shape the source names that is not modelled (CAMotics `spheroid`).
    Unknown,
}

impl ToolShape {
    /// Its name, as in a remark or a spec (`flat`, `ball`, `bull`, `v`, `drill`, `snub`, `unknown`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Flat => "flat",
            Self::Ball => "ball",
            Self::Bull { .. } => "bull",
            Self::V { .. } => "v",
            Self::Drill { .. } => "drill",
            Self::Snub { .. } => "snub",
            Self::Unknown => "unknown",
        }
    }
}

/// One tool.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolEntry {
    /// The tool number (T), ≥ 0.
    pub number: i32,
    /// The pocket (P), when given.
    pub pocket: Option<i32>,
    /// X, Y, Z length offsets (mm): what G43 adds (Z along the spindle; X on a lathe).
    pub offset_mm: DVec3,
    /// A, B, C offsets (degrees).
    pub rotary_offset_deg: DVec3,
    /// U, V, W offsets (mm).
    pub uvw_offset_mm: DVec3,
    /// Cutting diameter (mm), ≥ 0 (zero: not given).
    pub diameter_mm: f64,
    /// Length of the cutting part along the axis (mm), when the source gives it (CAMotics
    /// `length`).
    pub length_mm: Option<f64>,
    /// The shape.
    pub shape: ToolShape,
    /// The shape was not given and is assumed flat.
    pub shape_assumed: bool,
    /// The body lengths the source gives (flutes, shank, holder, centre cutting): a `.tbl`
    /// remark's words, a CAMotics tool's `length` as its flutes, a spec's words.
    pub body: BodySpec,
    /// Lathe front angle I (degrees), back angle J (degrees) and orientation Q, when given.
    pub lathe: Option<LatheTool>,
    /// The remark (`.tbl`), description (CAMotics) or spec, trimmed.
    pub comment: String,
}

/// A lathe tool's angles and orientation (LinuxCNC `I`, `J`, `Q`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LatheTool {
    /// Front angle (degrees).
    pub front_angle_deg: f64,
    /// Back angle (degrees).
    pub back_angle_deg: f64,
    /// Orientation 0–9.
    pub orientation: i32,
}

impl ToolEntry {
    /// A tool with its number, shape and diameter (mm), everything else zero.
    #[must_use]
    pub fn new(number: i32, shape: ToolShape, diameter_mm: f64) -> Self {
        Self { number, shape, diameter_mm, ..Self::default() }
    }

    /// The tool as a spec `N:shape:diameter[:corner or angle]` ([`parse_tool_spec`] reads it
    /// back to the same shape and diameter); `None` for a shape a spec cannot name (snub,
    /// unknown) or no diameter.
    #[must_use]
    pub fn spec(&self) -> Option<String> {
        let (n, d) = (self.number, self.diameter_mm);
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        let mut spec = match self.shape {
            ToolShape::Flat | ToolShape::Ball => format!("{n}:{}:{d}", self.shape.name()),
            ToolShape::Bull { corner_radius_mm } => format!("{n}:bull:{d}:{corner_radius_mm}"),
            ToolShape::V { tip_angle_deg } => format!("{n}:v:{d}:{tip_angle_deg}"),
            ToolShape::Drill { point_angle_deg } => format!("{n}:drill:{d}:{point_angle_deg}"),
            ToolShape::Snub { .. } | ToolShape::Unknown => return None,
        };
        if !self.body.is_empty() {
            spec.push(',');
            spec.push_str(&self.body.words(","));
        }
        Some(spec)
    }

    /// The corner radius (mm): D/2 for a ball, r for a bull nose, 0 for a flat end mill;
    /// `None` for the other shapes.
    #[must_use]
    pub fn corner_radius_mm(&self) -> Option<f64> {
        match self.shape {
            ToolShape::Flat => Some(0.0),
            ToolShape::Ball => Some(0.5 * self.diameter_mm),
            ToolShape::Bull { corner_radius_mm } => Some(corner_radius_mm),
            _ => None,
        }
    }

    /// The tool as the simulation's [`Cutter`] (its body from [`Self::body`], defaults for
    /// what that leaves out), for the shapes it models: flat, ball and bull nose. `None` for
    /// the others.
    ///
    /// # Errors
    /// When the diameter is zero or the corner does not fit.
    pub fn cutter(&self) -> Option<Result<Cutter, CutterError>> {
        let r = 0.5 * self.diameter_mm;
        let c = match self.shape {
            ToolShape::Flat => Cutter::flat(r),
            ToolShape::Ball => Cutter::ball(r),
            ToolShape::Bull { corner_radius_mm } => Cutter::fillet(r, corner_radius_mm),
            _ => return None,
        };
        Some(c.and_then(|c| c.with_body(&self.body)))
    }
}

/// Tools by number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolTable {
    tools: BTreeMap<i32, ToolEntry>,
}

/// A CAMotics workpiece (its `workpiece` object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CamoticsWorkpiece {
    /// CAMotics sizes the stock from the program's cuts itself.
    pub automatic: bool,
    /// The margin added around automatic bounds (percent of their size).
    pub margin_percent: f64,
    /// The stock box (mm), when given: min and max corners.
    pub bounds_mm: Option<(DVec3, DVec3)>,
}

/// What a CAMotics project holds for a viewer.
#[derive(Clone, Debug, PartialEq)]
pub struct CamoticsProject {
    /// The project's display units.
    pub units: TableUnits,
    /// The tools.
    pub tools: ToolTable,
    /// The workpiece, when the project has one.
    pub workpiece: Option<CamoticsWorkpiece>,
    /// The program files, as written (relative to the project).
    pub files: Vec<String>,
}

/// Why a tool table or spec was refused. Each message names the place and what to write.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ToolError {
    /// The file is larger than the cap.
    #[error("the tool table is larger than {cap_mib} MiB; check the path (a tool table is far smaller)")]
    TooLarge {
        /// The cap (MiB).
        cap_mib: u64,
    },
    /// More tools than the cap.
    #[error("{place}: more than {cap} tools; a table holds at most {cap}")]
    TooMany {
        /// Where.
        place: String,
        /// The cap.
        cap: usize,
    },
    /// A `.tbl` word that is not one.
    #[error(
        "line {line}: '{word}' is not a tool-table word; write letter and number, e.g. T1 P1 Z25.4 D6, with T P X Y Z A B C U V W D I J Q"
    )]
    BadWord {
        /// Line.
        line: usize,
        /// The word.
        word: String,
    },
    /// A `.tbl` letter twice.
    #[error("line {line}: {letter} appears twice; keep one")]
    Repeated {
        /// Line.
        line: usize,
        /// The letter.
        letter: char,
    },
    /// A `.tbl` line without T.
    #[error("line {line}: no tool number; start the line with T and the number, e.g. T3 P3 Z30 D6")]
    NoNumber {
        /// Line.
        line: usize,
    },
    /// A tool number defined twice.
    #[error("{place}: tool {number} is already defined ({first}); tool numbers must be unique")]
    Duplicate {
        /// Where the second is.
        place: String,
        /// The number.
        number: i32,
        /// Where the first is.
        first: String,
    },
    /// A tool number out of range.
    #[error("{place}: tool number {number} must be a whole number from 0 to 2147483647")]
    BadNumber {
        /// Where.
        place: String,
        /// As written.
        number: String,
    },
    /// A shape word with a missing or bad parameter.
    #[error("{place}: {what}")]
    Shape {
        /// Where.
        place: String,
        /// What is wrong and what to write.
        what: String,
    },
    /// A CAMotics project that is not what CAMotics writes.
    #[error("{path}: {what}")]
    Camotics {
        /// The key path (`tools.3.shape`).
        path: String,
        /// What is wrong and what to write.
        what: String,
    },
    /// A command-line spec that is not `N:shape:diameter[:corner]`.
    #[error("tool spec '{spec}': {what}")]
    Spec {
        /// As given.
        spec: String,
        /// What is wrong and what to write.
        what: String,
    },
}

impl ToolTable {
    /// An empty table.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The tool of a number.
    #[must_use]
    pub fn get(&self, number: i32) -> Option<&ToolEntry> {
        self.tools.get(&number)
    }

    /// The tools in ascending number.
    pub fn iter(&self) -> impl Iterator<Item = &ToolEntry> {
        self.tools.values()
    }

    /// Number of tools.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tools.len()
    }

    /// Whether the table is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tools.is_empty()
    }

    /// Adds a tool (from a spec, say).
    ///
    /// # Errors
    /// A number already in the table, or more than [`MAX_TOOLS`] tools.
    pub fn insert(&mut self, tool: ToolEntry, place: &str) -> Result<(), ToolError> {
        if self.tools.contains_key(&tool.number) {
            return Err(ToolError::Duplicate {
                place: place.to_owned(),
                number: tool.number,
                first: "earlier".to_owned(),
            });
        }
        if self.tools.len() >= MAX_TOOLS {
            return Err(ToolError::TooMany { place: place.to_owned(), cap: MAX_TOOLS });
        }
        self.tools.insert(tool.number, tool);
        Ok(())
    }

    /// Sets a tool, replacing the entry of its number (`G10 L1`, `L10`, `L11`).
    ///
    /// # Errors
    /// [`ToolError::TooMany`] when a new number would pass [`MAX_TOOLS`].
    pub fn set(&mut self, tool: ToolEntry) -> Result<(), ToolError> {
        if !self.tools.contains_key(&tool.number) && self.tools.len() >= MAX_TOOLS {
            return Err(ToolError::TooMany { place: "G10".to_owned(), cap: MAX_TOOLS });
        }
        self.tools.insert(tool.number, tool);
        Ok(())
    }

    /// Gives a tool the shape and diameter of `spec` (a [`parse_tool_spec`] entry), keeping
    /// what the table already says of that number besides (its length and other offsets,
    /// pocket, cutting length): `--tool` and the app's tool editor change the cutter, not where
    /// `G43` puts it. A number the table lacks is added.
    ///
    /// # Errors
    /// [`ToolError::TooMany`] when a new number would pass [`MAX_TOOLS`].
    pub fn set_cutter(&mut self, spec: ToolEntry) -> Result<(), ToolError> {
        let tool = match self.tools.get(&spec.number) {
            Some(old) => ToolEntry {
                shape: spec.shape,
                diameter_mm: spec.diameter_mm,
                shape_assumed: false,
                comment: spec.comment,
                ..old.clone()
            },
            None => spec,
        };
        self.set(tool)
    }

    /// Reads a LinuxCNC `.tbl` written in `units`.
    ///
    /// # Errors
    /// The first line that is not a tool line (see the module docs), or a file beyond
    /// [`MAX_TOOL_TABLE_BYTES`] or [`MAX_TOOLS`].
    pub fn from_linuxcnc(text: &str, units: TableUnits) -> Result<Self, ToolError> {
        if text.len() as u64 > MAX_TOOL_TABLE_BYTES {
            return Err(ToolError::TooLarge { cap_mib: MAX_TOOL_TABLE_BYTES >> 20 });
        }
        let mut table = Self::new();
        let mut lines_of: BTreeMap<i32, usize> = BTreeMap::new();
        for (idx, raw) in text.lines().enumerate() {
            let line = idx + 1;
            let (data, remark) = match raw.split_once(';') {
                Some((d, r)) => (d, Some(r.trim())),
                None => (raw, None),
            };
            if data.trim().is_empty() {
                continue;
            }
            let tool = tbl_line(line, data, remark.unwrap_or(""), units)?;
            if let Some(first) = lines_of.get(&tool.number) {
                return Err(ToolError::Duplicate {
                    place: format!("line {line}"),
                    number: tool.number,
                    first: format!("line {first}"),
                });
            }
            if table.len() >= MAX_TOOLS {
                return Err(ToolError::TooMany { place: format!("line {line}"), cap: MAX_TOOLS });
            }
            lines_of.insert(tool.number, line);
            table.tools.insert(tool.number, tool);
        }
        Ok(table)
    }

    /// Writes the table as a LinuxCNC `.tbl` in `units`: every word LinuxCNC reads, numbers
    /// in their shortest exact form, the shape as the first word of the remark when the
    /// remark does not start with it (an assumed shape is not written).
    #[must_use]
    pub fn to_linuxcnc(&self, units: TableUnits) -> String {
        let s = units.mm();
        let mut out = String::new();
        for t in self.iter() {
            out.push_str(&format!("T{}", t.number));
            if let Some(p) = t.pocket {
                out.push_str(&format!(" P{p}"));
            }
            for (l, v) in ['X', 'Y', 'Z'].into_iter().zip(t.offset_mm.to_array()) {
                out.push_str(&format!(" {l}{}", v / s));
            }
            for (l, v) in ['A', 'B', 'C'].into_iter().zip(t.rotary_offset_deg.to_array()) {
                out.push_str(&format!(" {l}{v}"));
            }
            for (l, v) in ['U', 'V', 'W'].into_iter().zip(t.uvw_offset_mm.to_array()) {
                out.push_str(&format!(" {l}{}", v / s));
            }
            out.push_str(&format!(" D{}", t.diameter_mm / s));
            if let Some(l) = t.lathe {
                out.push_str(&format!(" I{} J{} Q{}", l.front_angle_deg, l.back_angle_deg, l.orientation));
            }
            let keyword = match t.shape {
                _ if t.shape_assumed => String::new(),
                ToolShape::Bull { corner_radius_mm } => format!("bull r={}", corner_radius_mm / s),
                ToolShape::V { tip_angle_deg } => format!("v{tip_angle_deg}"),
                ToolShape::Drill { point_angle_deg } => format!("drill {point_angle_deg}"),
                ToolShape::Flat | ToolShape::Ball => t.shape.name().to_owned(),
                // No remark word for these: written as free text, read back as flat.
                ToolShape::Snub { .. } | ToolShape::Unknown => String::new(),
            };
            let starts = remark_shape(&t.comment, s).ok().flatten().is_some_and(|sh| sh == t.shape);
            let remark = if keyword.is_empty() || starts {
                t.comment.clone()
            } else {
                format!("{keyword} {}", t.comment).trim().to_owned()
            };
            if !remark.is_empty() {
                out.push_str(&format!(" ;{remark}"));
            }
            out.push('\n');
        }
        out
    }

    /// Reads the tools (and workpiece and files) of a CAMotics project.
    ///
    /// # Errors
    /// Text that is not JSON, or a key whose value CAMotics would not write, named by its
    /// path.
    pub fn from_camotics(text: &str) -> Result<CamoticsProject, ToolError> {
        if text.len() as u64 > MAX_TOOL_TABLE_BYTES {
            return Err(ToolError::TooLarge { cap_mib: MAX_TOOL_TABLE_BYTES >> 20 });
        }
        let bad = |path: &str, what: String| ToolError::Camotics { path: path.to_owned(), what };
        let root: serde_json::Value = serde_json::from_str(text).map_err(|e| {
            bad(
                "project",
                format!("not JSON ({e}); a CAMotics project is the JSON file CAMotics saves (the older XML projects are not read)"),
            )
        })?;
        let Some(obj) = root.as_object() else {
            return Err(bad("project", "must be a JSON object with \"tools\", \"workpiece\" and \"files\"".to_owned()));
        };
        let units = match obj.get("units") {
            None => TableUnits::Mm,
            Some(v) => {
                camotics_units(v).ok_or_else(|| bad("units", "must be \"metric\" or \"imperial\"".to_owned()))?
            }
        };
        let mut tools = ToolTable::new();
        if let Some(t) = obj.get("tools") {
            let Some(map) = t.as_object() else {
                return Err(bad(
                    "tools",
                    "must be an object keyed by tool number, e.g. {\"1\": {\"shape\": \"ballnose\", …}}".to_owned(),
                ));
            };
            if map.len() > MAX_TOOLS {
                return Err(ToolError::TooMany { place: "tools".to_owned(), cap: MAX_TOOLS });
            }
            for (key, value) in map {
                let path = format!("tools.{key}");
                let tool = camotics_tool(&path, key, value)?;
                if let Some(first) = tools.get(tool.number) {
                    return Err(ToolError::Duplicate {
                        place: path,
                        number: tool.number,
                        first: format!("tools.{}", first.number),
                    });
                }
                tools.tools.insert(tool.number, tool);
            }
        }
        let workpiece = match obj.get("workpiece") {
            None => None,
            Some(w) => Some(camotics_workpiece(w)?),
        };
        let files = match obj.get("files") {
            None => Vec::new(),
            Some(serde_json::Value::Array(a)) => a
                .iter()
                .enumerate()
                .map(|(i, f)| {
                    f.as_str()
                        .map(str::to_owned)
                        .ok_or_else(|| bad(&format!("files[{i}]"), "must be a file name (a string)".to_owned()))
                })
                .collect::<Result<_, _>>()?,
            Some(_) => return Err(bad("files", "must be a list of file names".to_owned())),
        };
        Ok(CamoticsProject { units, tools, workpiece, files })
    }
}

/// Parses a command-line tool spec `N:shape:diameter[:corner]` (mm, degrees).
///
/// # Errors
/// A spec that is not of that form, with what to write.
pub fn parse_tool_spec(spec: &str) -> Result<ToolEntry, ToolError> {
    let fail = |what: String| ToolError::Spec { spec: spec.to_owned(), what };
    let mut pieces = spec.split(',');
    let head = pieces.next().unwrap_or_default();
    let mut body = BodySpec::default();
    for w in pieces {
        if !body.word(w, 1.0).map_err(fail)? {
            return Err(fail(format!(
                "'{}' is not a body word; write flute=25, shank=3:40 (radius:length), holder=16:60 or nocentre, e.g. 1:ball:6,flute=20",
                w.chars().take(40).collect::<String>()
            )));
        }
    }
    let parts: Vec<&str> = head.split(':').map(str::trim).collect();
    if parts.len() < 3 || parts.len() > 4 {
        return Err(fail("write N:shape:diameter[:corner], e.g. 1:ball:6, 2:bull:10:1, 3:v:6:90, 4:flat:3".to_owned()));
    }
    let number = parse_number(parts[0])
        .ok_or_else(|| fail(format!("'{}' is not a tool number; write a whole number, e.g. 1:ball:6", parts[0])))?;
    let diameter: f64 =
        parts[2].parse().ok().filter(|d: &f64| *d > 0.0 && d.is_finite()).ok_or_else(|| {
            fail(format!("'{}' is not a diameter; give the cutting diameter in mm, above 0", parts[2]))
        })?;
    let extra = match parts.get(3) {
        None => None,
        Some(t) => Some(
            t.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| fail(format!("'{t}' is not a number")))?,
        ),
    };
    let shape = match parts[1].to_ascii_lowercase().as_str() {
        "flat" | "endmill" => ToolShape::Flat,
        "ball" | "ballnose" => ToolShape::Ball,
        "bull" | "fillet" | "torus" => {
            let r = extra.ok_or_else(|| {
                fail(format!("a bull nose needs its corner radius: write {number}:bull:{}:1", parts[2]))
            })?;
            bull(r, diameter).map_err(fail)?
        }
        "v" | "vbit" => {
            let a = extra
                .ok_or_else(|| fail(format!("a V cutter needs its tip angle: write {number}:v:{}:90", parts[2])))?;
            ToolShape::V { tip_angle_deg: angle(a).map_err(fail)? }
        }
        "drill" => ToolShape::Drill { point_angle_deg: angle(extra.unwrap_or(DEFAULT_DRILL_POINT_DEG)).map_err(fail)? },
        other => return Err(fail(format!("'{other}' is not a shape; use flat, ball, bull, v or drill"))),
    };
    if extra.is_some() && matches!(shape, ToolShape::Flat | ToolShape::Ball) {
        return Err(fail(format!(
            "a {} end mill takes no fourth field; write {number}:{}:{}",
            shape.name(),
            shape.name(),
            parts[2]
        )));
    }
    Ok(ToolEntry { number, shape, diameter_mm: diameter, body, comment: spec.to_owned(), ..ToolEntry::default() })
}

fn parse_number(s: &str) -> Option<i32> {
    s.parse::<i32>().ok().filter(|n| *n >= 0)
}

fn angle(a: f64) -> Result<f64, String> {
    if a > 0.0 && a < 180.0 {
        Ok(a)
    } else {
        Err(format!("angle {a}° must lie between 0 and 180 degrees (the included angle)"))
    }
}

fn bull(r_mm: f64, diameter_mm: f64) -> Result<ToolShape, String> {
    if r_mm > 0.0 && r_mm < 0.5 * diameter_mm {
        Ok(ToolShape::Bull { corner_radius_mm: r_mm })
    } else {
        Err(format!(
            "corner radius {r_mm} mm must lie between 0 and half the diameter ({} mm); 0 is a flat end mill, D/2 a ball",
            0.5 * diameter_mm
        ))
    }
}

/// One `.tbl` line's words.
fn tbl_line(line: usize, data: &str, remark: &str, units: TableUnits) -> Result<ToolEntry, ToolError> {
    let s = units.mm();
    let mut seen = [false; 26];
    let mut t = ToolEntry { comment: remark.to_owned(), ..ToolEntry::default() };
    let mut number = None;
    let mut lathe = LatheTool::default();
    let mut has_lathe = false;
    for word in data.split_whitespace() {
        let mut chars = word.chars();
        let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
        let text = chars.as_str();
        let bad = || ToolError::BadWord { line, word: word.to_owned() };
        if !letter.is_ascii_uppercase() {
            return Err(bad());
        }
        let li = (letter as u8 - b'A') as usize;
        if seen[li] {
            return Err(ToolError::Repeated { line, letter });
        }
        seen[li] = true;
        let real = || text.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(bad);
        let int = || text.parse::<i32>().map_err(|_| bad());
        match letter {
            'T' => {
                number =
                    Some(parse_number(text).ok_or_else(|| ToolError::BadNumber {
                        place: format!("line {line}"),
                        number: text.to_owned(),
                    })?)
            }
            'P' => t.pocket = Some(int()?),
            'X' => t.offset_mm.x = real()? * s,
            'Y' => t.offset_mm.y = real()? * s,
            'Z' => t.offset_mm.z = real()? * s,
            'A' => t.rotary_offset_deg.x = real()?,
            'B' => t.rotary_offset_deg.y = real()?,
            'C' => t.rotary_offset_deg.z = real()?,
            'U' => t.uvw_offset_mm.x = real()? * s,
            'V' => t.uvw_offset_mm.y = real()? * s,
            'W' => t.uvw_offset_mm.z = real()? * s,
            'D' => t.diameter_mm = real()?.abs() * s,
            'I' => (lathe.front_angle_deg, has_lathe) = (real()?, true),
            'J' => (lathe.back_angle_deg, has_lathe) = (real()?, true),
            'Q' => (lathe.orientation, has_lathe) = (int()?, true),
            _ => return Err(bad()),
        }
    }
    t.number = number.ok_or(ToolError::NoNumber { line })?;
    t.lathe = has_lathe.then_some(lathe);
    let place = format!("line {line}");
    for w in remark.split_whitespace() {
        t.body.word(w, s).map_err(|what| ToolError::Shape { place: place.clone(), what })?;
    }
    match remark_shape(remark, s).map_err(|what| ToolError::Shape { place: place.clone(), what })? {
        Some(shape) => {
            if let ToolShape::Bull { corner_radius_mm } = shape {
                bull(corner_radius_mm, t.diameter_mm).map_err(|what| ToolError::Shape { place, what })?;
            }
            t.shape = shape;
        }
        None => {
            t.shape = ToolShape::Flat;
            t.shape_assumed = true;
        }
    }
    Ok(t)
}

/// The shape a remark names by our convention (module docs), `None` when its first word is
/// not a shape word; lengths in the table's units times `s`.
fn remark_shape(remark: &str, s: f64) -> Result<Option<ToolShape>, String> {
    let mut words = remark.split_whitespace();
    let Some(first) = words.next() else {
        return Ok(None);
    };
    let first = first.to_ascii_lowercase();
    let split = first.find(|c: char| !c.is_ascii_alphabetic()).unwrap_or(first.len());
    let (name, rest) = first.split_at(split);
    let rest = rest.trim_start_matches('=');
    // The parameter: the rest of the first word, or the next word (`r=1`, `a=90`, `1`).
    let param = |key: char| -> Option<String> {
        if !rest.is_empty() {
            return Some(rest.to_owned());
        }
        let next = words.clone().next()?.to_ascii_lowercase();
        let v = next.strip_prefix(key).map_or(next.as_str(), |v| v.trim_start_matches('=')).to_owned();
        v.parse::<f64>().is_ok().then_some(v)
    };
    let number = |v: Option<String>| v.and_then(|v| v.parse::<f64>().ok()).filter(|v| v.is_finite());
    Ok(Some(match name {
        "flat" | "endmill" => ToolShape::Flat,
        "ball" | "ballnose" => ToolShape::Ball,
        "bull" | "bullnose" | "fillet" | "torus" => {
            let r = number(param('r')).ok_or_else(|| {
                format!("'{first}' needs the corner radius; write e.g. ;{name} r=1 (in the table's units)")
            })?;
            ToolShape::Bull { corner_radius_mm: r * s }
        }
        "v" | "vbit" => {
            let a = number(param('a'))
                .ok_or_else(|| format!("'{first}' needs the tip angle; write e.g. ;v90 (degrees)"))?;
            ToolShape::V { tip_angle_deg: angle(a)? }
        }
        "drill" => ToolShape::Drill { point_angle_deg: angle(number(param('a')).unwrap_or(DEFAULT_DRILL_POINT_DEG))? },
        _ => return Ok(None),
    }))
}

fn camotics_units(v: &serde_json::Value) -> Option<TableUnits> {
    match v.as_str()?.to_ascii_lowercase().as_str() {
        "metric" | "mm" => Some(TableUnits::Mm),
        "imperial" | "inch" => Some(TableUnits::Inch),
        _ => None,
    }
}

fn camotics_tool(path: &str, key: &str, value: &serde_json::Value) -> Result<ToolEntry, ToolError> {
    let bad = |p: &str, what: String| ToolError::Camotics { path: p.to_owned(), what };
    let Some(obj) = value.as_object() else {
        return Err(bad(path, "must be an object with shape, diameter, length, units".to_owned()));
    };
    let mut number = key.parse::<u32>().ok().and_then(|n| i32::try_from(n).ok());
    if let Some(n) = obj.get("number") {
        number = n.as_u64().and_then(|n| i32::try_from(n).ok());
        if number.is_none() {
            return Err(ToolError::BadNumber { place: format!("{path}.number"), number: n.to_string() });
        }
    }
    let number = number.ok_or_else(|| ToolError::BadNumber { place: path.to_owned(), number: key.to_owned() })?;
    let units = match obj.get("units") {
        None => TableUnits::Mm,
        Some(u) => camotics_units(u)
            .ok_or_else(|| bad(&format!("{path}.units"), "must be \"metric\" or \"imperial\"".to_owned()))?,
    };
    let s = units.mm();
    let num = |k: &str, default_mm: f64| -> Result<f64, ToolError> {
        match obj.get(k) {
            None => Ok(default_mm),
            Some(v) => v.as_f64().filter(|v| v.is_finite() && *v >= 0.0).map(|v| v * s).ok_or_else(|| {
                bad(
                    &format!("{path}.{k}"),
                    format!(
                        "must be a length of zero or more ({})",
                        if units == TableUnits::Mm { "mm" } else { "inches" }
                    ),
                )
            }),
        }
    };
    // CAMotics' defaults (a metric tool 10 mm long, radius 1 mm), kept in mm whatever the
    // tool's units, as CAMotics sets them before reading.
    let length = num("length", 10.0)?;
    let diameter = num("diameter", 2.0)?;
    let snub = num("snub_diameter", 0.0)?;
    let shape_name = match obj.get("shape") {
        None => "cylindrical".to_owned(),
        Some(v) => v
            .as_str()
            .map(str::to_ascii_lowercase)
            .ok_or_else(|| bad(&format!("{path}.shape"), "must be a shape name".to_owned()))?,
    };
    let shape = match shape_name.trim_start_matches("ts_") {
        "cylindrical" | "cylinder" => ToolShape::Flat,
        "ballnose" => ToolShape::Ball,
        "conical" | "cone" => {
            if !(length > 0.0 && diameter > 0.0) {
                return Err(bad(
                    path,
                    "a conical tool needs a length and a diameter above 0 (its angle is 2·atan(R / length))".to_owned(),
                ));
            }
            ToolShape::V { tip_angle_deg: 2.0 * (0.5 * diameter / length).atan().to_degrees() }
        }
        "snubnose" => ToolShape::Snub { tip_diameter_mm: snub },
        "spheroid" | "sphere" => ToolShape::Unknown,
        other => {
            return Err(bad(
                &format!("{path}.shape"),
                format!("'{other}' is not a CAMotics shape; use cylindrical, ballnose, conical, snubnose or spheroid"),
            ));
        }
    };
    let comment = match obj.get("description") {
        None => String::new(),
        Some(v) => v
            .as_str()
            .map(|s| s.trim().to_owned())
            .ok_or_else(|| bad(&format!("{path}.description"), "must be text".to_owned()))?,
    };
    let body = BodySpec { flute_mm: (length > 0.0).then_some(length), ..BodySpec::default() };
    Ok(ToolEntry {
        number,
        diameter_mm: diameter,
        length_mm: Some(length),
        shape,
        body,
        comment,
        ..ToolEntry::default()
    })
}

fn camotics_workpiece(w: &serde_json::Value) -> Result<CamoticsWorkpiece, ToolError> {
    let bad = |p: &str, what: &str| ToolError::Camotics { path: p.to_owned(), what: what.to_owned() };
    let Some(obj) = w.as_object() else {
        return Err(bad("workpiece", "must be an object with automatic, margin and bounds"));
    };
    let automatic = match obj.get("automatic") {
        None => true,
        Some(v) => v.as_bool().ok_or_else(|| bad("workpiece.automatic", "must be true or false"))?,
    };
    let margin_percent = match obj.get("margin") {
        None => 5.0,
        Some(v) => {
            v.as_f64().filter(|v| v.is_finite()).ok_or_else(|| bad("workpiece.margin", "must be a number (percent)"))?
        }
    };
    let bounds_mm = match obj.get("bounds") {
        None => None,
        Some(b) => {
            let corner = |k: &str| -> Result<DVec3, ToolError> {
                let p = format!("workpiece.bounds.{k}");
                let a = b
                    .get(k)
                    .and_then(|v| v.as_array())
                    .filter(|a| a.len() == 3)
                    .ok_or_else(|| bad(&p, "must be [x, y, z] in mm"))?;
                let v: Vec<f64> = a.iter().filter_map(serde_json::Value::as_f64).filter(|v| v.is_finite()).collect();
                if v.len() == 3 { Ok(DVec3::new(v[0], v[1], v[2])) } else { Err(bad(&p, "must be [x, y, z] in mm")) }
            };
            Some((corner("min")?, corner("max")?))
        }
    };
    Ok(CamoticsWorkpiece { automatic, margin_percent, bounds_mm })
}
