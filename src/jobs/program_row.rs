//! One row of the NURBS & G-code comparison as a background job: the design path (a scene's
//! crease or seed 004's parabola), one program kind written, read back and measured by
//! [`compare_row`], and, when a machine is given, the program read back timed on it
//! ([`cycle_time`], what `interpolab compare --machine` prints). Writing a program takes
//! 0.1–6 s in a browser, far more than a frame.
//!
//! The request carries the scene as its JSON text (the worker rebuilds the crease from it;
//! the caller checks beforehand that the text gives the same job), the output the program's
//! text and numbers: the reader's view of the program is parsed again from the text on the
//! receiving side, which is what [`crate::gcode::write_program`] did with the same text.

use glam::DVec3;
use serde_json::{Value, json};
use thiserror::Error;

use super::{DecodeError, JobError, JobKind, Progress, Reader, nums, parse, vec3};
use crate::crease::CreaseJob;
use crate::gcode::compare::Junctions;
use crate::gcode::path::Toolpath;
use crate::gcode::{
    CompareOptions, CompareRow, DesignError, Deviation, Dialect, Program, ProgramError, ProgramKind, ProgramOptions,
    ProgrammedPoint, compare_row, crease_design, parse_program_in,
};
use crate::geom::{Curve3, NurbsCurve};
use crate::nurbs_path::{FitError, Parabola};
use crate::plan::{Dynamics, PlanError, canon_of_toolpath, time_program};
use crate::report::fmt_fixed;
use crate::scene::{Scene, SceneError};

/// A program's time on a machine: its feed planned within the machine's joint limits and
/// contour tolerance ([`time_program`] on [`canon_of_toolpath`] of the program as read back).
#[derive(Clone, Debug, PartialEq)]
pub struct CycleTime {
    /// The machine's name.
    pub machine: String,
    /// Planned cycle time (s): every move, rapids and dwells included.
    pub total_s: f64,
    /// Time in feed moves (s), dwells left out.
    pub feed_s: f64,
    /// Length of the feed moves along the planned path (mm), blends included.
    pub cut_mm: f64,
}

impl CycleTime {
    /// The headers of [`Self::cells`], as `interpolab compare --machine` prints them.
    pub const HEADS: [&'static str; 3] = ["time s", "feed time s", "mean feed mm/min"];

    /// The cycle time (s) and the feed moves' time (s) to 0.1 ms, the mean feed (mm/min) to
    /// 0.1 (empty when there is none): the cells of `interpolab compare --machine`'s table and
    /// of the app's copied table.
    #[must_use]
    pub fn cells(&self) -> [String; 3] {
        [
            fmt_fixed(self.total_s, 4),
            fmt_fixed(self.feed_s, 4),
            self.mean_feed_mm_min().map_or(String::new(), |f| fmt_fixed(f, 1)),
        ]
    }

    /// Mean feed over the cut (mm/min): the feed moves' length over their time; `None` when
    /// the program spends no time in feed moves.
    #[must_use]
    pub fn mean_feed_mm_min(&self) -> Option<f64> {
        (self.feed_s > 0.0).then(|| 60.0 * self.cut_mm / self.feed_s)
    }
}

/// The time of a program (a toolpath as any dialect's reader gives it) on a machine: what
/// `interpolab compare --machine M` prints per row and the comparison job hands back.
///
/// # Errors
/// The planner's: a bad machine, a feed move without a feed, a program beyond its caps.
pub fn cycle_time(toolpath: &Toolpath, machine: &Dynamics) -> Result<CycleTime, PlanError> {
    let t = time_program(canon_of_toolpath(toolpath), machine)?;
    let (feed_s, _) = t.feed_rapid_s();
    let cut_mm: f64 = t.path.blocks.iter().filter(|b| !b.rapid).map(|b| b.len).sum();
    Ok(CycleTime { machine: machine.name.clone(), total_s: t.total_s(), feed_s, cut_mm })
}

/// Why one program of the comparison cannot be made, in the app's words (the job's output
/// hands it over as a [`JobError`]: [`ProgramRow`]'s output is `Result<_, JobError>`).
#[derive(Clone, Debug, Error)]
pub enum RowError {
    /// The job was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The scene of the design path cannot be read or run.
    #[error("the scene: {0}")]
    Scene(SceneError),
    /// The scene's crease gives no design path.
    #[error("The scene's crease gives no design path: {0}. Change the scene, or use the parabola profile.")]
    NoDesign(DesignError),
    /// The program cannot be written ([`describe_program_error`]).
    #[error("{}", describe_program_error(.source, *.kind))]
    Program {
        /// The program's kind.
        kind: ProgramKind,
        /// Why.
        source: ProgramError,
    },
}

impl From<RowError> for JobError {
    fn from(e: RowError) -> Self {
        match e {
            RowError::Cancelled => Self::Cancelled,
            e => Self::failed(e),
        }
    }
}

/// A row of the comparison with its time on the machine of the request.
#[derive(Clone, Debug)]
pub struct TimedRow {
    /// The program written, read back and measured.
    pub row: CompareRow,
    /// Its time on the machine (`None`: no machine asked for; an error: why it could not be
    /// planned, in the app's words).
    pub time: Option<Result<CycleTime, String>>,
}

/// Writes, measures and (with a machine) times one program: the job's work, callable on any
/// thread.
///
/// # Errors
/// The program cannot be written ([`RowError::Program`]). A planning error is not one: it is
/// the row's `time`.
pub fn timed_row(
    kind: ProgramKind,
    design: &dyn Curve3,
    tol_mm: f64,
    options: &CompareOptions,
    machine: Option<&Dynamics>,
) -> Result<TimedRow, RowError> {
    let row = compare_row(kind, design, tol_mm, options).map_err(|source| RowError::Program { kind, source })?;
    let time = machine.map(|m| {
        cycle_time(&row.program.parsed.toolpath, m)
            .map_err(|e| format!("The {} program cannot be timed on {}: {e}", kind.label(), m.name))
    });
    Ok(TimedRow { row, time })
}

/// Where the design path comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignSpec {
    /// Seed 004's profile ([`Parabola::paper_like`]).
    Parabola,
    /// The crease of the scene in this JSON text (`interpolab-scene/1`).
    Scene(String),
}

/// One program of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The design path.
    pub design: DesignSpec,
    /// The program kind.
    pub kind: ProgramKind,
    /// Tolerance E (mm).
    pub tol_mm: f64,
    /// Options of the programs, as [`compare_row`] takes them.
    pub options: CompareOptions,
    /// The machine to time the program on (`None`: not timed).
    pub machine: Option<Dynamics>,
}

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct ProgramRow;

/// The design curve of a request.
enum Design {
    Parabola(Parabola),
    Crease(Box<crate::crease::CreaseCurve>),
}

impl Design {
    fn curve(&self) -> &dyn Curve3 {
        match self {
            Self::Parabola(p) => p,
            Self::Crease(c) => c.as_ref(),
        }
    }
}

fn build_design(spec: &DesignSpec) -> Result<Design, RowError> {
    match spec {
        DesignSpec::Parabola => Ok(Design::Parabola(Parabola::paper_like())),
        DesignSpec::Scene(text) => {
            let scene = Scene::from_json(text).map_err(RowError::Scene)?;
            let job = CreaseJob::from_scene(&scene).map_err(RowError::Scene)?;
            crease_design(&job).map(|c| Design::Crease(Box::new(c))).map_err(RowError::NoDesign)
        }
    }
}

/// The job's work on a request.
fn run_row(request: &Request, progress: &mut dyn Progress) -> Result<TimedRow, RowError> {
    let design = build_design(&request.design)?;
    if progress.cancelled() {
        return Err(RowError::Cancelled);
    }
    progress.progress(0.5);
    timed_row(request.kind, design.curve(), request.tol_mm, &request.options, request.machine.as_ref())
}

impl JobKind for ProgramRow {
    const NAME: &'static str = "program-row";
    type Request = Request;
    type Output = Result<TimedRow, JobError>;
    type Partial = ();

    fn run(request: &Request, progress: &mut dyn Progress) -> Self::Output {
        run_row(request, progress).map_err(JobError::from)
    }

    fn encode_request(r: &Request) -> String {
        let p = &r.options.program;
        let (point, radius) = match p.point {
            ProgrammedPoint::BallCentre => ("centre", 0.0),
            ProgrammedPoint::BallTip { radius_mm } => ("tip", radius_mm),
        };
        json!({
            "scene": match &r.design { DesignSpec::Parabola => Value::Null, DesignSpec::Scene(t) => Value::from(t.as_str()) },
            "kind": kind_index(r.kind),
            "tol_mm": super::num(r.tol_mm),
            "resolution_mm": super::num(p.resolution_mm),
            "feed_mm_per_min": super::num(p.feed_mm_per_min),
            "point": point,
            "radius_mm": super::num(radius),
            "title": p.title,
            "degree": p.degree,
            "dialect": Dialect::ALL.iter().position(|d| *d == p.dialect).unwrap_or(0),
            "period_ms": super::num(r.options.period_ms),
            "chord_tol_mm": r.options.chord_tol_mm.map_or(Value::Null, super::num),
            "machine": r.machine.as_ref().map_or(Value::Null, Dynamics::to_value),
        })
        .to_string()
    }

    fn decode_request(text: &str) -> Result<Request, DecodeError> {
        let v = parse(text, "program-row request")?;
        let r = Reader::new(&v, "program-row request")?;
        let design = match r.value("scene")? {
            Value::Null => DesignSpec::Parabola,
            s => DesignSpec::Scene(s.as_str().ok_or("program-row request.scene: not text")?.to_owned()),
        };
        let point = match r.str("point")? {
            "centre" => ProgrammedPoint::BallCentre,
            "tip" => ProgrammedPoint::BallTip { radius_mm: r.f64("radius_mm")? },
            other => return Err(format!("program-row request.point: \"{other}\" is neither centre nor tip").into()),
        };
        let dialect = *Dialect::ALL.get(r.usize("dialect")?).ok_or("program-row request.dialect: out of range")?;
        // A request of an older page has no machine: not timed.
        let machine = match v.get("machine") {
            None | Some(Value::Null) => None,
            Some(m) => Some(Dynamics::from_value(m).map_err(|e| format!("program-row request.machine: {e}"))?),
        };
        let program = ProgramOptions::default()
            .with_resolution(r.f64("resolution_mm")?)
            .with_feed(r.f64("feed_mm_per_min")?)
            .with_point(point)
            .with_title(r.str("title")?)
            .with_degree(r.usize("degree")?)
            .with_dialect(dialect);
        Ok(Request {
            design,
            kind: *ProgramKind::ALL.get(r.usize("kind")?).ok_or("program-row request.kind: out of range")?,
            tol_mm: r.f64("tol_mm")?,
            options: CompareOptions {
                program,
                period_ms: r.f64("period_ms")?,
                chord_tol_mm: r.opt_f64("chord_tol_mm")?,
            },
            machine,
        })
    }

    fn encode_output(out: &Self::Output) -> String {
        let (row, time) = match out {
            Err(e) => return e.encode(),
            Ok(t) => (&t.row, &t.time),
        };
        let time = match time {
            None => Value::Null,
            Some(Err(e)) => json!({ "error": e }),
            Some(Ok(t)) => json!({
                "machine": t.machine,
                "total_s": super::num(t.total_s),
                "feed_s": super::num(t.feed_s),
                "cut_mm": super::num(t.cut_mm),
            }),
        };
        let p = &row.program;
        let d = &p.deviation;
        let nurbs = p.nurbs.as_ref().map_or(Value::Null, |c| {
            json!({
                "degree": c.degree(),
                "knots": nums(c.knots().iter().copied()),
                "points": Value::from((0..c.len()).map(|i| vec3(c.control_point(i))).collect::<Vec<_>>()),
                "weights": nums((0..c.len()).map(|i| c.weight(i))),
            })
        });
        json!({
            "kind": kind_index(row.kind),
            "path_blocks": row.path_blocks,
            "total_blocks": row.total_blocks,
            "bytes": row.bytes,
            "deviation_mm": super::num(row.deviation_mm),
            "junctions": {
                "count": row.junctions.count,
                "max_turn_deg": super::num(row.junctions.max_turn_deg),
                "max_curvature_jump": super::num(row.junctions.max_curvature_jump),
            },
            "time": time,
            "program": {
                "kind": kind_index(p.kind),
                "dialect": Dialect::ALL.iter().position(|x| *x == p.dialect).unwrap_or(0),
                "text": p.text,
                "tol_mm": super::num(p.tol_mm),
                "fit_tol_mm": super::num(p.fit_tol_mm),
                "path_blocks": p.path_blocks,
                "blend_mm": p.blend_mm.map_or(Value::Null, super::num),
                "attempts": p.attempts,
                "nurbs": nurbs,
                "deviation": {
                    "program_to_design_mm": super::num(d.program_to_design_mm),
                    "program_point": vec3(d.program_point),
                    "program_line": d.program_line,
                    "design_to_program_mm": super::num(d.design_to_program_mm),
                    "design_point": vec3(d.design_point),
                    "design_s_mm": super::num(d.design_s_mm),
                    "start_gap_mm": super::num(d.start_gap_mm),
                    "end_gap_mm": super::num(d.end_gap_mm),
                    "design_length_mm": super::num(d.design_length_mm),
                    "sample_spacing_mm": super::num(d.sample_spacing_mm),
                },
            },
        })
        .to_string()
    }

    fn decode_output(text: &str) -> Result<Self::Output, DecodeError> {
        let v = parse(text, "program-row output")?;
        if let Some(e) = JobError::decode(&v, "program-row output")? {
            return Ok(Err(e));
        }
        let r = Reader::new(&v, "program-row output")?;
        let j = Reader::new(r.value("junctions")?, "program-row output.junctions")?;
        let pv = Reader::new(r.value("program")?, "program-row output.program")?;
        let dv = Reader::new(pv.value("deviation")?, "program-row output.program.deviation")?;
        let kind = *ProgramKind::ALL.get(pv.usize("kind")?).ok_or("program-row output.program.kind: out of range")?;
        let dialect =
            *Dialect::ALL.get(pv.usize("dialect")?).ok_or("program-row output.program.dialect: out of range")?;
        let text = pv.str("text")?.to_owned();
        let parsed = parse_program_in(&text, dialect).map_err(|e| format!("the program does not read back: {e}"))?;
        let nurbs = match pv.value("nurbs")? {
            Value::Null => None,
            n => {
                let n = Reader::new(n, "program-row output.program.nurbs")?;
                let points = n
                    .value("points")?
                    .as_array()
                    .ok_or("program-row output.program.nurbs.points: not a list")?
                    .iter()
                    .map(|p| p.as_array().and_then(|a| a.iter().map(|x| x.as_u64().map(f64::from_bits)).collect()))
                    .map(|xs: Option<Vec<f64>>| match xs.as_deref() {
                        Some([x, y, z]) => Ok(DVec3::new(*x, *y, *z)),
                        _ => Err(DecodeError::from("program-row output.program.nurbs.points: not points")),
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                let weights = n.f64s("weights")?;
                let curve = NurbsCurve::try_new(n.usize("degree")?, n.f64s("knots")?, &points, Some(&weights))
                    .map_err(|e| format!("program-row output.program.nurbs: {e}"))?;
                Some(curve)
            }
        };
        let program = Program {
            kind,
            dialect,
            blend_mm: pv.opt_f64("blend_mm")?,
            parsed,
            text,
            deviation: Deviation {
                program_to_design_mm: dv.f64("program_to_design_mm")?,
                program_point: dv.vec3("program_point")?,
                program_line: dv.usize("program_line")?,
                design_to_program_mm: dv.f64("design_to_program_mm")?,
                design_point: dv.vec3("design_point")?,
                design_s_mm: dv.f64("design_s_mm")?,
                start_gap_mm: dv.f64("start_gap_mm")?,
                end_gap_mm: dv.f64("end_gap_mm")?,
                design_length_mm: dv.f64("design_length_mm")?,
                sample_spacing_mm: dv.f64("sample_spacing_mm")?,
            },
            tol_mm: pv.f64("tol_mm")?,
            fit_tol_mm: pv.f64("fit_tol_mm")?,
            path_blocks: pv.usize("path_blocks")?,
            nurbs,
            attempts: pv.usize("attempts")?,
        };
        // An output of an older worker has no time: not timed.
        let time = match v.get("time") {
            None | Some(Value::Null) => None,
            Some(t) => {
                let t = Reader::new(t, "program-row output.time")?;
                Some(match t.value("error") {
                    Ok(e) => Err(e.as_str().ok_or("program-row output.time.error: not text")?.to_owned()),
                    Err(_) => Ok(CycleTime {
                        machine: t.str("machine")?.to_owned(),
                        total_s: t.f64("total_s")?,
                        feed_s: t.f64("feed_s")?,
                        cut_mm: t.f64("cut_mm")?,
                    }),
                })
            }
        };
        let row = CompareRow {
            kind: *ProgramKind::ALL.get(r.usize("kind")?).ok_or("program-row output.kind: out of range")?,
            path_blocks: r.usize("path_blocks")?,
            total_blocks: r.usize("total_blocks")?,
            bytes: r.usize("bytes")?,
            deviation_mm: r.f64("deviation_mm")?,
            junctions: Junctions {
                count: j.usize("count")?,
                max_turn_deg: j.f64("max_turn_deg")?,
                max_curvature_jump: j.f64("max_curvature_jump")?,
            },
            program,
        };
        Ok(Ok(TimedRow { row, time }))
    }

    fn decode_partial(_text: &str) -> Result<(), DecodeError> {
        Ok(())
    }
}

fn kind_index(kind: ProgramKind) -> usize {
    ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0)
}

/// A program error in the app's terms (the core's messages name the command line's flags).
#[must_use]
pub fn describe_program_error(e: &ProgramError, kind: ProgramKind) -> String {
    let um = |mm: f64| format!("{} µm", crate::report::fmt_fixed(mm * 1000.0, 3));
    match e {
        ProgramError::BelowResolution { tol_mm, resolution_mm } => format!(
            "The tolerance {} is below twice the resolution {}: rounding alone moves points by up to {}. \
             Raise the tolerance to at least {} or pick a finer resolution.",
            um(*tol_mm),
            um(*resolution_mm),
            um(resolution_mm * 3f64.sqrt() / 2.0),
            um(2.0 * resolution_mm)
        ),
        ProgramError::NotMet { achieved_mm, tol_mm, .. } => format!(
            "The {} program deviates {} after rounding, more than the tolerance {}. Raise the tolerance or pick a finer resolution.",
            kind.label(),
            um(*achieved_mm),
            um(*tol_mm)
        ),
        ProgramError::Fit(FitError::NotConverged { tol_mm, achieved_mm, control_points }) => format!(
            "The G06.2 fit could not get within {} (best {} with {control_points} control points). Raise the tolerance.",
            um(*tol_mm),
            um(*achieved_mm)
        ),
        other => format!("{}: {other}", kind.label()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::NoProgress;

    fn request(design: DesignSpec, kind: ProgramKind, dialect: Dialect, tol_mm: f64) -> Request {
        Request {
            machine: Dynamics::preset("hobby-router"),
            design,
            kind,
            tol_mm,
            options: CompareOptions {
                program: ProgramOptions::default()
                    .with_feed(1234.5)
                    .with_point(ProgrammedPoint::BallTip { radius_mm: 2.5 })
                    .with_title("a \"quoted\" title")
                    .with_dialect(dialect),
                period_ms: 4.0,
                chord_tol_mm: Some(0.001),
            },
        }
    }

    /// A request read back is the request; an output read back is the output, field for
    /// field and bit for bit (what crosses into the worker and back changes nothing).
    #[test]
    fn request_and_output_cross_unchanged() {
        let scene = crate::scene::PRESETS[0].json.to_owned();
        for (design, kind, dialect) in [
            (DesignSpec::Parabola, ProgramKind::Lines, Dialect::Fanuc),
            (DesignSpec::Parabola, ProgramKind::Arcs, Dialect::LinuxCnc),
            (DesignSpec::Parabola, ProgramKind::Nurbs, Dialect::Fanuc),
            (DesignSpec::Parabola, ProgramKind::Nurbs, Dialect::Sinumerik),
            (DesignSpec::Scene(scene.clone()), ProgramKind::Nurbs, Dialect::Fanuc),
        ] {
            let req = request(design, kind, dialect, 0.01);
            let back = ProgramRow::decode_request(&ProgramRow::encode_request(&req)).unwrap();
            assert_eq!(back, req);
            let out = ProgramRow::run(&back, &mut NoProgress);
            let timed = out.as_ref().unwrap();
            let row = &timed.row;
            let got = ProgramRow::decode_output(&ProgramRow::encode_output(&out)).unwrap().unwrap();
            let time = timed.time.as_ref().unwrap().as_ref().unwrap();
            assert_eq!(got.time.as_ref().unwrap().as_ref().unwrap(), time, "the time crosses bit for bit");
            assert!(time.total_s > 0.0 && time.feed_s > 0.0 && time.feed_s <= time.total_s, "{time:?}");
            let got = got.row;
            assert_eq!(got.kind, row.kind);
            assert_eq!((got.path_blocks, got.total_blocks, got.bytes), (row.path_blocks, row.total_blocks, row.bytes));
            assert_eq!(got.deviation_mm.to_bits(), row.deviation_mm.to_bits());
            assert_eq!(got.junctions, row.junctions);
            let (a, b) = (&got.program, &row.program);
            assert_eq!((a.kind, a.dialect, &a.text), (b.kind, b.dialect, &b.text));
            assert_eq!(a.parsed, b.parsed, "the text parses to what the writer read back");
            assert_eq!(a.deviation, b.deviation);
            assert_eq!((a.tol_mm, a.fit_tol_mm, a.blend_mm), (b.tol_mm, b.fit_tol_mm, b.blend_mm));
            assert_eq!((a.path_blocks, a.attempts), (b.path_blocks, b.attempts));
            assert_eq!(a.nurbs, b.nurbs);
            assert_eq!(kind == ProgramKind::Nurbs, a.nurbs.is_some());
        }
    }

    /// The job gives what the comparison computes directly, and errors in the app's words.
    #[test]
    fn the_job_is_compare_row_and_errors_are_described() {
        let req = request(DesignSpec::Parabola, ProgramKind::Arcs, Dialect::Fanuc, 0.01);
        let direct = compare_row(ProgramKind::Arcs, &Parabola::paper_like(), 0.01, &req.options).unwrap();
        let job = ProgramRow::run(&req, &mut NoProgress).unwrap();
        assert_eq!(job.row.program.text, direct.program.text);
        let bad = request(DesignSpec::Parabola, ProgramKind::Lines, Dialect::Fanuc, 0.0015);
        let err = ProgramRow::run(&bad, &mut NoProgress).unwrap_err();
        assert!(matches!(&err, JobError::Failed(m) if m.contains("below twice the resolution")), "{err}");
        let out = ProgramRow::decode_output(&ProgramRow::encode_output(&Err(err.clone()))).unwrap();
        assert_eq!(out.unwrap_err(), err);
        let broken = ProgramRow::decode_request("{\"scene\": null}").unwrap_err().to_string();
        assert!(broken.contains("no field"), "{broken}");
        // A request and an output of an older page or worker (no machine, no time) still read:
        // not timed.
        let mut untimed = req.clone();
        untimed.machine = None;
        let text = ProgramRow::encode_request(&untimed).replace(",\"machine\":null", "");
        assert!(!text.contains("machine"), "{text}");
        assert_eq!(ProgramRow::decode_request(&text).unwrap(), untimed);
        let out = ProgramRow::run(&untimed, &mut NoProgress);
        assert!(out.as_ref().unwrap().time.is_none());
        let text = ProgramRow::encode_output(&out).replace("\"time\":null,", "");
        assert!(!text.contains("\"time\""), "{text}");
        assert!(ProgramRow::decode_output(&text).unwrap().unwrap().time.is_none());
        // A machine the planner refuses: the program is written, its time says why not.
        let mut bad_machine = req.clone();
        if let Some(m) = bad_machine.machine.as_mut() {
            m.axes[0].acceleration = 0.0;
        }
        let out = ProgramRow::run(&bad_machine, &mut NoProgress).unwrap();
        let e = out.time.unwrap().unwrap_err();
        assert!(e.contains("cannot be timed on hobby-router") && e.contains("acceleration"), "{e}");
        let scene = request(DesignSpec::Scene("{}".into()), ProgramKind::Lines, Dialect::Fanuc, 0.01);
        let err = ProgramRow::run(&scene, &mut NoProgress).unwrap_err();
        assert!(matches!(&err, JobError::Failed(m) if m.starts_with("the scene")), "{err}");
    }
}
