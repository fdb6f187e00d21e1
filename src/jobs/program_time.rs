//! A user's program timed on a machine, as a background job: read by the interpreter with its
//! tool table, project and subroutine files (as [`super::user_program`] reads it), its feed
//! planned within the machine's joint limits and contour tolerance ([`crate::plan::time_read`],
//! the pipeline of `interpolab time`), handed back as the cycle time and the planned feed,
//! acceleration and jerk along the path against time, sampled for a plot.

use serde_json::json;
use thiserror::Error;

use super::user_program::{self, UserProgram, UserProgramError};
use super::{DecodeError, JobError, JobKind, Progress, Reader, f32s_packed, parse};
use crate::gcode::interp::tools::TableUnits;
use crate::gcode::interp::{InterpError, Interpreter, Options, TextLibrary, TextSource};
use crate::plan::{Dynamics, PlanError, Stopped, Timing, time_read};

/// Samples of the feed, acceleration and jerk handed back for the plot (evenly in time).
pub const PLOT_SAMPLES: usize = 2000;

/// A run: the program as the tab reads it, and the machine.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The program, its files and tools (its `simulate`, stock and pitch are not used).
    pub program: user_program::Request,
    /// The machine's dynamics and its controller's settings.
    pub machine: Dynamics,
}

/// A program timed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timed {
    /// The machine's name.
    pub machine: String,
    /// Contour tolerance used (mm).
    pub tolerance_mm: f64,
    /// Cycle time (s), dwells included.
    pub total_s: f64,
    /// Time in feed moves (s).
    pub feed_s: f64,
    /// Time in rapids (s).
    pub rapid_s: f64,
    /// Blocks planned.
    pub blocks: usize,
    /// Sample times (s), evenly from 0 to the end, at most [`PLOT_SAMPLES`].
    pub t_s: Vec<f32>,
    /// Planned feed along the path at each sample (mm/min).
    pub feed_mm_min: Vec<f32>,
    /// Acceleration along the path (mm/s²).
    pub acc_mm_s2: Vec<f32>,
    /// Jerk along the path (mm/s³).
    pub jerk_mm_s3: Vec<f32>,
    /// Per block planned, the feed it achieves on average (mm/min): its stretch of the
    /// planned path over its time (dwell left out); NaN for a block of no time.
    pub block_feed_mm_min: Vec<f32>,
    /// Per block planned, its line (in its file).
    pub block_line: Vec<u32>,
    /// Per block planned, its file: 0 the main program, subroutine files numbered as the
    /// interpreter opened them.
    pub block_file: Vec<u16>,
}

/// How far ahead [`feeds_by_block`] looks for a drawn block's line among the planned blocks.
pub const MATCH_AHEAD: usize = 64;

/// The achieved feeds of the planned blocks given to the blocks a view draws (`lines`,
/// `files`: each drawn block's line and file, 0 the main program): the two lists are in
/// program order, but the planner leaves out moves of no length, so each drawn block takes
/// the next planned block of its line and file within [`MATCH_AHEAD`] (a subroutine's
/// blocks as well as the main program's); the others get NaN.
#[must_use]
pub fn feeds_by_block(lines: &[u32], files: &[u16], t: &Timed) -> Vec<f32> {
    let mut j = 0usize;
    lines
        .iter()
        .zip(files)
        .map(|(&line, &file)| {
            let planned = t.block_line.iter().zip(&t.block_file);
            let mut ahead = planned.skip(j).take(MATCH_AHEAD);
            match ahead.position(|(&l, &f)| l == line && f == file) {
                Some(k) => {
                    j += k + 1;
                    t.block_feed_mm_min[j - 1]
                }
                None => f32::NAN,
            }
        })
        .collect()
}

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct ProgramTime;

/// Why a program cannot be timed, in the app's words (the job's output hands it over as a
/// [`JobError`]: [`ProgramTime`]'s output is `Result<_, JobError>`).
#[derive(Clone, Debug, Error)]
pub enum TimeError {
    /// The job was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The program's tools (its table, project or the user's tools) cannot be read.
    #[error(transparent)]
    Tools(UserProgramError),
    /// The interpreter stops on the program (its line and message).
    #[error("{name}: {error}")]
    Program {
        /// The program's name.
        name: String,
        /// Why.
        error: InterpError,
    },
    /// The planner refuses the program on this machine.
    #[error("{name}: {error}")]
    Plan {
        /// The program's name.
        name: String,
        /// Why.
        error: PlanError,
    },
}

impl From<TimeError> for JobError {
    fn from(e: TimeError) -> Self {
        match e {
            TimeError::Cancelled => Self::Cancelled,
            TimeError::Tools(e) => e.into(),
            e => Self::failed(e),
        }
    }
}

/// Reads the program into canonical motions and plans it on the machine.
///
/// # Errors
/// A bad table or project, the interpreter's error with its line, the planner's (a feed move
/// without a feed, a bad machine, a program beyond its caps), or cancelled.
pub fn time(req: &Request, progress: &mut dyn Progress) -> Result<Timing, TimeError> {
    let p = &req.program;
    let (table, project) = user_program::tools_of(p).map_err(TimeError::Tools)?;
    let inch = project.as_ref().is_some_and(|p| p.units == TableUnits::Inch);
    let opts = Options { tools: table, inch, ..Options::default() };
    let mut lib = TextLibrary::new();
    for (name, text) in &p.files {
        lib.add(name, text);
    }
    let mut it = Interpreter::new(Box::new(TextSource::new(&p.text)), Box::new(lib), opts);
    let size = p.text.len().max(1) as f64;
    // The motions go to the planner as they are read (never held as a list); progress is
    // half the text read, and a cancel stops the reading.
    let mut read = 0usize;
    let stream = std::iter::from_fn(|| {
        let c = it.next()?;
        read += 1;
        if read.is_multiple_of(4096) {
            progress.progress(0.5 * it.main_offset() as f64 / size);
            if progress.cancelled() {
                return Some(Err(TimeError::Cancelled));
            }
        }
        Some(c.map_err(|error| TimeError::Program { name: p.name.clone(), error }))
    });
    let t = time_read(stream, &req.machine).map_err(|e| match e {
        Stopped::Read(e) => e,
        Stopped::Plan(error) => TimeError::Plan { name: p.name.clone(), error },
    })?;
    progress.progress(1.0);
    Ok(t)
}

/// The cycle time and the plot's samples of a timing.
#[must_use]
pub fn timed(t: &Timing) -> Timed {
    let (feed_s, rapid_s) = t.feed_rapid_s();
    let mut out = Timed {
        machine: t.machine.name.clone(),
        tolerance_mm: t.machine.tolerance_mm,
        total_s: t.total_s(),
        feed_s,
        rapid_s,
        blocks: t.path.blocks.len(),
        ..Timed::default()
    };
    let blocks = &t.path.blocks;
    let end_s = t.plan.phases.last().map_or(0.0, |p| p.at(p.t0 + p.phase.dur).0);
    out.block_feed_mm_min = blocks
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let next = blocks.get(i + 1).map_or(end_s, |n| n.s_start);
            let dt = t.block_time_s.get(i).copied().unwrap_or(0.0) - b.dwell_after_s;
            if dt > 0.0 { (60.0 * (next - b.s_start).max(0.0) / dt) as f32 } else { f32::NAN }
        })
        .collect();
    out.block_line = blocks.iter().map(|b| b.line).collect();
    out.block_file = blocks.iter().map(|b| b.file).collect();
    let phases = &t.plan.phases;
    let n = if out.total_s > 0.0 && !phases.is_empty() { PLOT_SAMPLES } else { 0 };
    let mut k = 0usize;
    for i in 0..n {
        let time = out.total_s * i as f64 / (n - 1) as f64;
        // Phases are in time order: walk forward to the one holding `time`.
        while k + 1 < phases.len() && phases[k + 1].t0 <= time {
            k += 1;
        }
        let p = &phases[k];
        let (_, v, a) = p.at(time);
        out.t_s.push(time as f32);
        out.feed_mm_min.push((60.0 * v) as f32);
        out.acc_mm_s2.push(a as f32);
        out.jerk_mm_s3.push(p.phase.j as f32);
    }
    out
}

impl JobKind for ProgramTime {
    const NAME: &'static str = "program-time";
    type Request = Request;
    type Output = Result<Timed, JobError>;
    type Partial = ();

    fn run(req: &Request, progress: &mut dyn Progress) -> Self::Output {
        time(req, progress).map(|t| timed(&t)).map_err(JobError::from)
    }

    /// The machine as one line of JSON, then the program's request as the user-program job
    /// writes it.
    fn encode_request(r: &Request) -> String {
        format!("{}\n{}", r.machine.to_value(), UserProgram::encode_request(&r.program))
    }

    fn decode_request(text: &str) -> Result<Request, DecodeError> {
        let (machine, program) = text.split_once('\n').ok_or("program-time request: no program after the machine")?;
        let machine =
            Dynamics::from_value(&parse(machine, "program-time request.machine")?).map_err(|e| e.to_string())?;
        Ok(Request { program: UserProgram::decode_request(program)?, machine })
    }

    fn encode_output(out: &Self::Output) -> String {
        match out {
            Err(e) => e.encode(),
            Ok(t) => json!({
                "machine": t.machine,
                "tolerance_mm": super::num(t.tolerance_mm),
                "total_s": super::num(t.total_s),
                "feed_s": super::num(t.feed_s),
                "rapid_s": super::num(t.rapid_s),
                "blocks": t.blocks,
                "samples": t.t_s.len(),
                "t_s": f32s_packed(&t.t_s),
                "feed_mm_min": f32s_packed(&t.feed_mm_min),
                "acc_mm_s2": f32s_packed(&t.acc_mm_s2),
                "jerk_mm_s3": f32s_packed(&t.jerk_mm_s3),
                "block_feed_mm_min": f32s_packed(&t.block_feed_mm_min),
                // Lines as f32: exact below 2^24.
                "block_line": f32s_packed(&t.block_line.iter().map(|&l| l as f32).collect::<Vec<_>>()),
                "block_file": f32s_packed(&t.block_file.iter().map(|&f| f32::from(f)).collect::<Vec<_>>()),
            })
            .to_string(),
        }
    }

    fn decode_output(text: &str) -> Result<Self::Output, DecodeError> {
        const W: &str = "program-time output";
        let v = parse(text, W)?;
        if let Some(e) = JobError::decode(&v, W)? {
            return Ok(Err(e));
        }
        let r = Reader::new(&v, W)?;
        let n = r.usize("samples")?;
        if n > PLOT_SAMPLES || r.usize("blocks")? > crate::simulate::canon::MAX_BLOCKS {
            return Err(format!("{W}: more than {PLOT_SAMPLES} samples or too many blocks").into());
        }
        Ok(Ok(Timed {
            machine: r.str("machine")?.to_owned(),
            tolerance_mm: r.f64("tolerance_mm")?,
            total_s: r.f64("total_s")?,
            feed_s: r.f64("feed_s")?,
            rapid_s: r.f64("rapid_s")?,
            blocks: r.usize("blocks")?,
            t_s: r.f32s_packed("t_s", n)?,
            feed_mm_min: r.f32s_packed("feed_mm_min", n)?,
            acc_mm_s2: r.f32s_packed("acc_mm_s2", n)?,
            jerk_mm_s3: r.f32s_packed("jerk_mm_s3", n)?,
            block_feed_mm_min: r.f32s_packed("block_feed_mm_min", r.usize("blocks")?)?,
            block_line: r.f32s_packed("block_line", r.usize("blocks")?)?.into_iter().map(|l| l as u32).collect(),
            block_file: r.f32s_packed("block_file", r.usize("blocks")?)?.into_iter().map(|f| f as u16).collect(),
        }))
    }

    fn decode_partial(_text: &str) -> Result<(), DecodeError> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Cutter;
    use crate::jobs::NoProgress;
    use crate::simulate::canon::KinematicsChoice;

    fn request(machine: &str) -> Request {
        Request {
            program: user_program::Request {
                name: "corner.ngc".to_owned(),
                text: "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X40 F3000\nG1 Y30\nG2 X10 Y30 R15\nG0 Z5\nM30\n"
                    .to_owned(),
                files: Vec::new(),
                tool_table: Some("T1 P1 Z40 D6 ;flat\n".to_owned()),
                project: None,
                tool_specs: Vec::new(),
                default_cutter: Cutter::flat(1.5).unwrap_or_else(|_| unreachable!()),
                machine: None,
                kinematics: KinematicsChoice::Auto,
                pitch_mm: None,
                stock_mm: None,
                simulate: false,
            },
            machine: Dynamics::preset(machine).unwrap_or_else(|| panic!("{machine}")),
        }
    }

    /// The request and the output cross as text unchanged; the time is the planner's on the
    /// same motions, the samples start and end at rest and never pass the programmed feed.
    #[test]
    fn a_program_is_timed_as_the_planner_times_it_and_crosses_unchanged() {
        let req = request("hobby-router");
        let back = ProgramTime::decode_request(&ProgramTime::encode_request(&req)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, req);
        let out = ProgramTime::run(&req, &mut NoProgress);
        let again = ProgramTime::decode_output(&ProgramTime::encode_output(&out)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again, out);
        let t = out.unwrap_or_else(|e| panic!("{e}"));
        let direct = time(&req, &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.total_s.to_bits(), direct.plan.duration.to_bits());
        assert!((t.feed_s + t.rapid_s - t.total_s).abs() <= 1e-9 * t.total_s, "{t:?}");
        assert_eq!(t.t_s.len(), PLOT_SAMPLES);
        assert!(t.feed_mm_min[0].abs() < 1e-3 && t.feed_mm_min[PLOT_SAMPLES - 1].abs() < 1e-3);
        // Feed moves at most F3000; rapids at the machine's rapid speed: none above the
        // fastest axis's velocity.
        let vmax = req.machine.axes.iter().map(|a| a.velocity).fold(0.0, f64::max);
        assert!(t.feed_mm_min.iter().all(|&f| f >= -1e-3 && f64::from(f) <= vmax * (1.0 + 1e-6)));
        // Every block's average achieved feed is at most its programmed one (F600, F3000)
        // or the rapid speed, and the first cut starts from rest: below its feed.
        assert_eq!(t.block_feed_mm_min.len(), t.blocks);
        let fed: Vec<(f32, bool)> =
            t.block_feed_mm_min.iter().zip(&direct.path.blocks).map(|(f, b)| (*f, b.rapid)).collect();
        assert!(fed.iter().all(|(f, rapid)| f.is_nan() || *rapid || *f <= 3000.0 * (1.0 + 1e-5)), "{fed:?}");
        assert!(fed.iter().any(|(f, rapid)| !rapid && *f < 0.999 * 600.0), "{fed:?}");
        // Given to drawn blocks by line: a drawn block the planner left out (no length) and
        // one of a subroutine file get none, the rest their planned block's feed.
        let mut lines: Vec<u32> = t.block_line.clone();
        lines.insert(2, t.block_line[1]);
        let mut files = vec![0u16; lines.len()];
        files.push(1);
        lines.push(3);
        let by = feeds_by_block(&lines, &files, &t);
        assert_eq!(by.len(), lines.len());
        assert_eq!(by[0].to_bits(), t.block_feed_mm_min[0].to_bits());
        assert_eq!(by[1].to_bits(), t.block_feed_mm_min[1].to_bits());
        assert!(by[2].is_nan() && by[by.len() - 1].is_nan());
        assert_eq!(by[3].to_bits(), t.block_feed_mm_min[2].to_bits());
        // A lighter machine takes longer on the same program.
        let vmc = ProgramTime::run(&request("vmc"), &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        assert!(vmc.total_s < t.total_s, "vmc {} s, hobby router {} s", vmc.total_s, t.total_s);
        // A program without a feed on a feed move is refused naming its line.
        let mut bad = request("vmc");
        bad.program.text = "G21 G90\nG1 X10\n".to_owned();
        let e = ProgramTime::run(&bad, &mut NoProgress).unwrap_err();
        assert!(matches!(&e, JobError::Failed(m) if m.contains("line 2")), "{e}");
    }

    /// A subroutine file's blocks are matched to their planned blocks by line and file, as
    /// the main program's are: every feed move the view draws, in either file, gets an
    /// achieved feed, and the subroutine's lines (which repeat the main program's line
    /// numbers) are not taken for the main program's.
    #[test]
    fn a_subroutine_file_s_blocks_get_their_achieved_feed() {
        let mut req = request("vmc");
        req.program.text = "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F600\no<square> call\nG1 X-20 F900\nG0 Z5\nM30\n".to_owned();
        req.program.files = vec![(
            "square.ngc".to_owned(),
            "o<square> sub\nG1 X20 F1200\nG1 Y20\nG1 X0\nG1 Y0\no<square> endsub\n".to_owned(),
        )];
        let (_, drawn) = user_program::read(&req.program, &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        let t = ProgramTime::run(&req, &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        assert!(t.block_file.contains(&1), "no planned block from the subroutine file: {:?}", t.block_file);
        let by = feeds_by_block(&drawn.block_line, &drawn.block_file, &t);
        let mut sub_feeds = 0;
        for ((&line, &file), f) in drawn.block_line.iter().zip(&drawn.block_file).zip(&by) {
            // Every drawn block has a planned one here (no move of zero length).
            assert!(f.is_finite(), "file {file} line {line}: no achieved feed");
            if file == 1 {
                sub_feeds += 1;
                assert!(*f <= 1200.0 * (1.0 + 1e-5), "file 1 line {line}: {f} mm/min over F1200");
            }
        }
        assert_eq!(sub_feeds, 4, "{:?}", drawn.block_file);
    }
}
