//! A user's program as a background job: read by the interpreter with its tool table, CAMotics
//! project and subroutine files ([`crate::simulate::canon`]), handed back at once as what a
//! view draws and lists ([`ReadSummary`]: the path, each block's line, kind, tool, feed and
//! nonlinear error, the reports), then — when asked — machined into its stock with each of its
//! tools ([`Finished`]: the height map, which tool last cut each ray, each tool's volume,
//! the crashes of its shanks and holders, rapids and plunges, [`crate::simulate::crash`]).
//! The same pipeline as `interpolab simulate --tools/--project/--machine`.

use glam::DVec3;
use serde_json::{Value, json};
use thiserror::Error;

use super::simulate_run::codec::{counters_of, counters_value, grid_of, grid_value};
use super::{DecodeError, JobError, JobKind, Progress, Reader, f32s_packed, f64s_packed, parse};
use crate::gcode::interp::tools::{TableUnits, ToolError, ToolTable, parse_tool_spec};
use crate::gcode::interp::{Interpreter, NoLibrary, Options, TextLibrary, TextSource};
use crate::geom::Cutter;
use crate::simulate::canon::{
    BlockKind, CanonBuilder, CanonOptions, CanonProgram, KinematicsChoice, MachineSetup, NO_SLOT,
};
use crate::simulate::stock::Grid;
use crate::simulate::{Counters, CrashKind, CrashLog, DexelStock, HeightMap, NO_TOOL, SimError, Simulation};

/// Most points of the path handed back for drawing; a longer program's path is thinned
/// evenly (every block keeps its end).
pub const MAX_PATH_POINTS: usize = 400_000;
/// Most rays of the stock (as the simulation tab's).
pub const MAX_RAYS: usize = 1024 * 1024;
/// Longest side of an automatic grid (rays).
pub const AUTO_GRID_SIDE: f64 = 256.0;
/// Most crash reports handed back to the view (the first ones, in the order the program
/// runs); the counts per kind count them all ([`Finished::crash_counts`]).
pub const MAX_CRASHES_SENT: usize = 1000;
/// Share of the progress bar the reading takes.
const READ_SHARE: f64 = 0.3;

/// A run.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The program's name (for messages).
    pub name: String,
    /// Its text.
    pub text: String,
    /// Subroutine files (name, text): `o<name> call` and `M98 P…` find them by name.
    pub files: Vec<(String, String)>,
    /// A LinuxCNC tool table (`.tbl` text, mm).
    pub tool_table: Option<String>,
    /// A CAMotics project (`.camotics` JSON): its tools and workpiece.
    pub project: Option<String>,
    /// Cutters set by the user (`N:shape:diameter[:corner or angle][,body words]`, as
    /// `--tool`: `flute=`, `shank=r:l`, `holder=r:l`, `nocentre`), over the project's and the
    /// table's: each keeps the table's offsets of its number.
    pub tool_specs: Vec<String>,
    /// The cutter of moves before any tool change and of tools no table has.
    pub default_cutter: Cutter,
    /// The machine's name ([`MachineSetup::NAMES`]); `None`: as the program's comments name
    /// one, else three axes.
    pub machine: Option<String>,
    /// How rotary words are read.
    pub kinematics: KinematicsChoice,
    /// Pitch (mm); `None`: automatic.
    pub pitch_mm: Option<f64>,
    /// The stock block (mm); `None`: the project's workpiece or the automatic one.
    pub stock_mm: Option<[f64; 6]>,
    /// Machine the program (else only read it).
    pub simulate: bool,
}

/// What a view draws and lists of a program read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadSummary {
    /// Lines of the main program.
    pub lines: u32,
    /// The path: tool tip positions (mm, workpiece), x y z per point, in order.
    pub points: Vec<f32>,
    /// For each point, the block whose motion ends the segment to it.
    pub point_block: Vec<u32>,
    /// Per block: its line (in its file), its file (0: the main program), kind (0 rapid,
    /// 1 line, 2 arc, 3 spline), tool slot ([`NO_SLOT`]: none), programmed feed (F as
    /// given: mm/min, 1/min under G93), nonlinear error (mm; NaN: not measured).
    pub block_line: Vec<u32>,
    /// Block files.
    pub block_file: Vec<u16>,
    /// Block kinds.
    pub block_kind: Vec<u8>,
    /// Block tool slots.
    pub block_slot: Vec<u16>,
    /// Block feeds.
    pub block_feed: Vec<f32>,
    /// Block nonlinear errors.
    pub block_error: Vec<f32>,
    /// The tools: number (−1: the default cutter), cutter description, source, feed time
    /// (min), feed blocks.
    pub tools: Vec<ToolRow>,
    /// The interpreter's reports and warnings and the builder's notes: (line, text); line 0
    /// when none applies.
    pub messages: Vec<(u32, String)>,
    /// The machine, when rotary axes go through one.
    pub machine: Option<String>,
    /// The stock block (mm) and where it comes from.
    pub stock_mm: [f64; 6],
    /// Where the stock comes from.
    pub stock_from: String,
    /// The pitch (mm).
    pub pitch_mm: f64,
    /// Moves the simulation will cut.
    pub moves: usize,
    /// Time of the feed blocks at the programmed feed (min).
    pub feed_min: f64,
}

/// One tool of a program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolRow {
    /// T (−1: the default cutter before any tool change).
    pub number: i32,
    /// `Cutter::describe`.
    pub cutter: String,
    /// Where its size comes from.
    pub source: String,
    /// Feed blocks.
    pub feed_blocks: usize,
    /// Time of its feed blocks (min).
    pub feed_min: f64,
    /// Its cutter as the tables give it, as a spec `N:shape:diameter[:corner or angle]` with
    /// the body words the source gives (what the app's tool editor starts from); empty when none names it (the default
    /// cutter, a snub or unknown shape).
    pub spec: String,
    /// The body as the simulation takes it, in words with units (`Cutter::describe_body`:
    /// "(assumed: …)" when no source gave its lengths).
    pub body: String,
    /// The body's lengths as the simulation takes them (mm): flute length, shank radius,
    /// shank length (above the flutes), holder radius, holder length.
    pub body_mm: [f64; 5],
    /// Whether the end cuts at its centre.
    pub centre_cutting: bool,
}

impl ToolRow {
    /// The body lengths of `c` as [`ToolRow::body_mm`] has them (mm).
    #[must_use]
    pub fn body_of(c: &Cutter) -> [f64; 5] {
        [
            c.flute_length_mm,
            c.shank_radius_mm,
            (c.gauge_length_mm - c.flute_length_mm).max(0.0),
            c.holder_radius_mm,
            c.holder_length_mm,
        ]
    }
}

/// One crash as the view lists it ([`crate::simulate::Crash`] with its block and tool).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrashRow {
    /// What met the stock.
    pub kind: CrashKind,
    /// Line of the block (in its file, from 1).
    pub line: u32,
    /// The block (index in [`ReadSummary::block_line`]) whose move met the stock; `None`
    /// when it cannot be told.
    pub block: Option<u32>,
    /// The tool's number (T; −1: the default cutter); `None` when unknown.
    pub tool: Option<i32>,
    /// The most stock along one vertical ray inside the offending part (mm).
    pub depth_mm: f64,
    /// That ray at the top of that stock (mm, workpiece).
    pub at_mm: DVec3,
}

/// The machined stock.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// The run's counts.
    pub counters: Counters,
    /// The height map.
    pub map: HeightMap,
    /// Per ray the tool slot that last removed material ([`NO_TOOL`]: none).
    pub tool_map: Vec<u16>,
    /// Volume each tool removed (mm³), by slot.
    pub removed_mm3: Vec<f64>,
    /// Blocks with a crash of each kind, in [`CrashKind::ALL`]'s order (shank, holder,
    /// rapid, plunge), every one counted.
    pub crash_counts: [usize; 4],
    /// The first [`MAX_CRASHES_SENT`] crash reports, in the order the program ran; the
    /// counts minus these are the ones left out ([`Finished::crashes_left_out`]).
    pub crashes: Vec<CrashRow>,
}

impl Finished {
    /// All crash reports (blocks with a crash of some kind).
    #[must_use]
    pub fn crash_total(&self) -> usize {
        self.crash_counts.iter().sum()
    }

    /// Crash reports counted but not listed (past [`MAX_CRASHES_SENT`] or the core's cap).
    #[must_use]
    pub fn crashes_left_out(&self) -> usize {
        self.crash_total().saturating_sub(self.crashes.len())
    }
}

/// A partial output: a piece of the program read ([`encode_pieces`]).
pub type Partial = Box<SummaryPiece>;

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct UserProgram;

/// Why a user's program cannot be read or machined, in the app's words (the job's output hands
/// it over as a [`JobError`]: [`UserProgram`]'s output is `Result<_, JobError>`).
#[derive(Clone, Debug, Error)]
pub enum UserProgramError {
    /// The job was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The CAMotics project's tools cannot be read.
    #[error("the CAMotics project: {0}")]
    Project(ToolError),
    /// The tool table cannot be read, or one of its tools set.
    #[error("the tool table: {0}")]
    ToolTable(ToolError),
    /// A tool the user set cannot be read (the message starts with the tool).
    #[error("tool {0}")]
    ToolSpec(ToolError),
    /// A tool the user set cannot be used.
    #[error("tool {spec}: {error}")]
    Tool {
        /// The tool as the user wrote it.
        spec: String,
        /// Why.
        error: ToolError,
    },
    /// The machine named is not one the app has.
    #[error("\"{0}\" is not a machine; choose one of {names}", names = MachineSetup::NAMES.join(", "))]
    UnknownMachine(String),
    /// The program cannot be read into moves (the interpreter's or the builder's error).
    #[error("{name}: {error}")]
    Program {
        /// The program's name.
        name: String,
        /// Why.
        error: SimError,
    },
    /// No stock was given and the program has no feed move to size one from.
    #[error("the program has no feed move to size the stock from; give the stock")]
    NoFeedMove,
    /// The grid has more than [`MAX_RAYS`] rays.
    #[error(
        "a pitch of {pitch_mm} mm on this stock gives {nx} × {ny} rays, more than the {MAX_RAYS} this view simulates; raise the pitch"
    )]
    TooManyRays {
        /// The pitch (mm).
        pitch_mm: f64,
        /// Rays in x, as counted for the message.
        nx: String,
        /// Rays in y, as counted for the message.
        ny: String,
    },
    /// The simulation's own refusal: the stock, the program or the work bound.
    #[error(transparent)]
    Sim(SimError),
}

impl From<UserProgramError> for JobError {
    fn from(e: UserProgramError) -> Self {
        match e {
            UserProgramError::Cancelled => Self::Cancelled,
            e => Self::failed(e),
        }
    }
}

/// The tools of a request: the project's, then the table's (a number in both: the table's),
/// then the cutters set by the user.
pub(crate) fn tools_of(
    req: &Request,
) -> Result<(ToolTable, Option<crate::gcode::interp::tools::CamoticsProject>), UserProgramError> {
    let mut table = ToolTable::new();
    let mut project = None;
    if let Some(p) = &req.project {
        let proj = ToolTable::from_camotics(p).map_err(UserProgramError::Project)?;
        table = proj.tools.clone();
        project = Some(proj);
    }
    if let Some(t) = &req.tool_table {
        let t = ToolTable::from_linuxcnc(t, TableUnits::Mm).map_err(UserProgramError::ToolTable)?;
        for e in t.iter() {
            table.set(e.clone()).map_err(UserProgramError::ToolTable)?;
        }
    }
    for s in &req.tool_specs {
        let e = parse_tool_spec(s).map_err(UserProgramError::ToolSpec)?;
        table.set_cutter(e).map_err(|error| UserProgramError::Tool { spec: s.clone(), error })?;
    }
    Ok((table, project))
}

/// Reads the request's program into moves; `progress` gets the fraction of the text read.
///
/// # Errors
/// A bad table or project, an unknown machine, the interpreter's error with its line, the
/// builder's (a tool no table gives), or cancelled.
pub fn read(req: &Request, progress: &mut dyn Progress) -> Result<(CanonProgram, ReadSummary), UserProgramError> {
    let (table, project) = tools_of(req)?;
    let mut opts = Options { tools: table.clone(), keep_comments: 64, ..Options::default() };
    if project.as_ref().is_some_and(|p| p.units == TableUnits::Inch) {
        opts.inch = true;
    }
    let mut machine = match &req.machine {
        None => None,
        Some(name) => {
            Some(MachineSetup::from_name(name, 0.0).ok_or_else(|| UserProgramError::UnknownMachine(name.clone()))?)
        }
    };
    let mut messages = Vec::new();
    if machine.is_none() {
        // The machine the first comments name (LinuxCNC's `M428 ;TCP:xyzac`).
        let mut head = Interpreter::new(Box::new(TextSource::new(&req.text)), Box::new(NoLibrary), opts.clone());
        for _ in 0..200 {
            if !matches!(head.next(), Some(Ok(_))) {
                break;
            }
        }
        if let Some((m, loc)) = MachineSetup::from_comments(head.comments(), 0.0) {
            messages.push((loc.line, format!("machine {} named by this comment", m.name())));
            machine = Some(m);
        }
    }
    let mut lib = TextLibrary::new();
    for (name, text) in &req.files {
        lib.add(name, text);
    }
    let mut it = Interpreter::new(Box::new(TextSource::new(&req.text)), Box::new(lib), opts);
    let specs: std::collections::BTreeMap<i32, String> =
        table.iter().filter_map(|e| Some((e.number, e.spec()?))).collect();
    let mut b = CanonBuilder::new(CanonOptions {
        machine,
        kinematics: req.kinematics,
        chord_tol_mm: req.pitch_mm.unwrap_or(0.2) / 10.0,
        tools: table,
        default_cutter: Some(req.default_cutter),
    });
    let size = req.text.len().max(1) as f64;
    let mut calls = 0u64;
    let done = b
        .read(&mut it, |it| {
            calls += 1;
            if calls.is_multiple_of(512) {
                progress.progress(READ_SHARE * it.main_offset() as f64 / size);
                return !progress.cancelled();
            }
            true
        })
        .map_err(|error| UserProgramError::Program { name: req.name.clone(), error })?;
    if !done {
        return Err(UserProgramError::Cancelled);
    }
    for w in it.warnings() {
        messages.push((w.loc.line, format!("warning: {}", w.text)));
    }
    for r in it.reports() {
        let times = if r.count == 1 { "once".to_owned() } else { format!("{} times", r.count) };
        messages.push((r.first.line, format!("{} ({times}): {}", r.code, r.what)));
    }
    let main_lines = it.main_lines();
    let p = b.finish();
    for n in &p.notes {
        messages.push((n.loc.line, n.text.clone()));
    }
    messages.sort_by_key(|m| m.0);
    let (stock_mm, stock_from) = match (req.stock_mm, project.as_ref().and_then(|p| p.workpiece)) {
        (Some(s), _) => (s, "given".to_owned()),
        (None, Some(w)) if !w.automatic && w.bounds_mm.is_some() => {
            let (lo, hi) = w.bounds_mm.unwrap_or_default();
            ([lo.x, lo.y, lo.z, hi.x, hi.y, hi.z], "the project's workpiece".to_owned())
        }
        (None, w) => {
            let margin = w.map_or(5.0, |w| w.margin_percent);
            let s = p.automatic_stock(margin).ok_or(UserProgramError::NoFeedMove)?;
            (s, format!("automatic (the cuts' box, margin {margin} %)"))
        }
    };
    let pitch_mm = match req.pitch_mm {
        Some(p) => p,
        None => {
            let side = (stock_mm[3] - stock_mm[0]).max(stock_mm[4] - stock_mm[1]);
            let p = side / AUTO_GRID_SIDE;
            let scale = 10f64.powf(p.log10().floor() - 1.0);
            ((p / scale).ceil() * scale).clamp(0.02, 2.0)
        }
    };
    let mut summary = summarize(&p, main_lines, messages, stock_mm, stock_from, pitch_mm);
    for t in &mut summary.tools {
        t.spec = specs.get(&t.number).cloned().unwrap_or_default();
    }
    Ok((p, summary))
}

fn summarize(
    p: &CanonProgram,
    lines: u32,
    messages: Vec<(u32, String)>,
    stock_mm: [f64; 6],
    stock_from: String,
    pitch_mm: f64,
) -> ReadSummary {
    let n = p.blocks.len();
    let mut s = ReadSummary {
        lines,
        messages,
        machine: p.machine.map(|m| m.name().to_owned()),
        stock_mm,
        stock_from,
        pitch_mm,
        moves: p.program.moves.len(),
        feed_min: p.tools.iter().map(|t| t.feed_min).sum(),
        ..ReadSummary::default()
    };
    // Every move's end, thinned evenly past the cap (each block keeps its end).
    let total: usize = p.blocks.iter().map(|b| (b.moves.1 - b.moves.0).max(1) as usize).sum();
    let keep_every = total.div_ceil(MAX_PATH_POINTS).max(1);
    let mut k = 0usize;
    for (i, b) in p.blocks.iter().enumerate() {
        s.block_line.push(b.loc.line);
        s.block_file.push(b.loc.file);
        s.block_kind.push(match b.kind {
            BlockKind::Rapid => 0,
            BlockKind::Line => 1,
            BlockKind::Arc => 2,
            BlockKind::Spline => 3,
        });
        s.block_slot.push(b.slot);
        s.block_feed.push(b.feed.rate as f32);
        s.block_error.push(b.rotary.and_then(|r| r.nonlinear_mm).map_or(f32::NAN, |e| e as f32));
        let block = u32::try_from(i).unwrap_or(u32::MAX);
        let moves = p.program.moves.get(b.moves.0 as usize..b.moves.1 as usize).unwrap_or(&[]);
        let mut push = |q: DVec3| {
            s.points.extend([q.x as f32, q.y as f32, q.z as f32]);
            s.point_block.push(block);
        };
        let last = moves.len().saturating_sub(1);
        for (j, m) in moves.iter().enumerate() {
            k += 1;
            if j == last || k.is_multiple_of(keep_every) {
                push(crate::simulate::canon::move_ends(m)[1]);
            }
        }
        if moves.is_empty() {
            push(b.end_tip);
        }
    }
    debug_assert_eq!(s.block_line.len(), n);
    s.tools = p
        .tools
        .iter()
        .map(|t| ToolRow {
            number: t.number,
            cutter: t.cutter.describe(),
            source: t.source.clone(),
            feed_blocks: t.feed_blocks,
            feed_min: t.feed_min,
            spec: String::new(),
            body: t.cutter.describe_body(),
            body_mm: ToolRow::body_of(&t.cutter),
            centre_cutting: t.cutter.centre_cutting,
        })
        .collect();
    s
}

/// The crashes of a run as the view lists them: the first [`MAX_CRASHES_SENT`], each with
/// its block (the simulation counts the moves it applies; blocks without a tool are not
/// applied) and its tool's number.
fn crash_rows(p: &CanonProgram, log: &CrashLog) -> Vec<CrashRow> {
    // (first applied move, block) of each block the run applies, in order.
    let mut starts = Vec::with_capacity(p.blocks.len());
    let mut applied = 0usize;
    for (k, b) in p.blocks.iter().enumerate() {
        if b.slot == NO_SLOT {
            continue;
        }
        let n = (b.moves.1.saturating_sub(b.moves.0)) as usize;
        if n > 0 {
            starts.push((applied, k));
        }
        applied += n;
    }
    log.list()
        .iter()
        .take(MAX_CRASHES_SENT)
        .map(|c| {
            let at = starts.partition_point(|s| s.0 <= c.move_index);
            let block = at.checked_sub(1).and_then(|i| starts.get(i)).map(|s| s.1);
            CrashRow {
                kind: c.kind,
                line: u32::try_from(c.line).unwrap_or(u32::MAX),
                block: block.and_then(|b| u32::try_from(b).ok()),
                tool: p.tools.get(usize::from(c.slot)).map(|t| t.number),
                depth_mm: c.depth_mm,
                at_mm: c.at_mm,
            }
        })
        .collect()
}

/// Reads and, when asked, machines the program.
///
/// # Errors
/// As [`read`]; a grid over [`MAX_RAYS`], too much work, or cancelled.
pub fn run(req: &Request, progress: &mut dyn Progress) -> Result<Option<Finished>, UserProgramError> {
    let (mut p, summary) = read(req, progress)?;
    let (stock_mm, pitch) = (summary.stock_mm, summary.pitch_mm);
    for piece in encode_pieces(&summary) {
        progress.partial(piece);
    }
    if !req.simulate {
        progress.progress(1.0);
        return Ok(None);
    }
    let nx = ((stock_mm[3] - stock_mm[0]) / pitch).ceil();
    let ny = ((stock_mm[4] - stock_mm[1]) / pitch).ceil();
    if !(nx * ny <= MAX_RAYS as f64) {
        return Err(UserProgramError::TooManyRays {
            pitch_mm: pitch,
            nx: crate::simulate::ray_count(nx),
            ny: crate::simulate::ray_count(ny),
        });
    }
    let stock =
        DexelStock::block([stock_mm[0], stock_mm[1], stock_mm[2]], [stock_mm[3], stock_mm[4], stock_mm[5]], pitch)
            .map_err(UserProgramError::Sim)?;
    let first = p.tools.first().map_or(req.default_cutter, |t| t.cutter);
    let mut sim = Simulation::new(stock, &first).with_tool_map();
    let total = p.program.moves.len().max(1) as f64;
    let done = p
        .run(&mut sim, |moves| {
            progress.progress(READ_SHARE + (1.0 - READ_SHARE) * moves as f64 / total);
            !progress.cancelled()
        })
        .map_err(UserProgramError::Sim)?;
    if !done {
        return Err(UserProgramError::Cancelled);
    }
    let map = HeightMap::of(sim.stock());
    let tool_map = sim.tool_map().map_or_else(|| vec![NO_TOOL; map.grid.len()], <[u16]>::to_vec);
    Ok(Some(Finished {
        counters: *sim.counters(),
        map,
        tool_map,
        removed_mm3: p.tools.iter().map(|t| t.removed_mm3).collect(),
        crash_counts: sim.crashes().counts(),
        crashes: crash_rows(&p, sim.crashes()),
    }))
}

fn f32s_of(xs: impl IntoIterator<Item = f32>) -> Value {
    f32s_packed(&xs.into_iter().collect::<Vec<_>>())
}

/// Blocks per partial output. A program's summary crosses to the page in pieces of this many
/// blocks (with their points), so the page decodes a piece at a time within its frame budget
/// and the path grows while it arrives: a 180 000-line raster crossed as one 9.6 MB text
/// whose decoding alone was one frame of half a second in the browser.
pub const PIECE_BLOCKS: usize = 4096;

/// A partial output: a piece of the program read. Its `summary` holds the blocks from
/// `first_block` on and their points; the first piece (`first_block` 0) also carries the
/// rest of the summary (lines, tools, messages, machine, stock, pitch, moves, time), the
/// others leave those empty.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SummaryPiece {
    /// Index of the piece's first block in the whole program.
    pub first_block: usize,
    /// Blocks of the whole program.
    pub total_blocks: usize,
    /// The whole path's box (mm, workpiece): min x, y, z, max x, y, z; in the first piece
    /// (the view frames the whole path from its first piece on).
    pub bounds_mm: [f32; 6],
    /// The piece.
    pub summary: ReadSummary,
}

impl SummaryPiece {
    /// Whether this is the program's last piece.
    #[must_use]
    pub fn is_last(&self) -> bool {
        self.first_block + self.summary.block_line.len() >= self.total_blocks
    }
}

impl ReadSummary {
    /// Takes the next piece: the first replaces the summary, each later one appends its
    /// blocks and points. Returns false (and changes nothing) for a piece that does not
    /// follow on from the blocks held.
    pub fn take_piece(&mut self, piece: SummaryPiece) -> bool {
        if piece.first_block == 0 {
            *self = piece.summary;
            return true;
        }
        if piece.first_block != self.block_line.len() {
            return false;
        }
        let p = piece.summary;
        self.points.extend_from_slice(&p.points);
        self.point_block.extend_from_slice(&p.point_block);
        self.block_line.extend_from_slice(&p.block_line);
        self.block_file.extend_from_slice(&p.block_file);
        self.block_kind.extend_from_slice(&p.block_kind);
        self.block_slot.extend_from_slice(&p.block_slot);
        self.block_feed.extend_from_slice(&p.block_feed);
        self.block_error.extend_from_slice(&p.block_error);
        true
    }
}

/// The path's box (mm): min x, y, z, max x, y, z over its finite points (zeros for none).
fn bounds_of(points: &[f32]) -> [f32; 6] {
    let mut b = [f32::INFINITY, f32::INFINITY, f32::INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY];
    for p in points.chunks_exact(3).filter(|p| p.iter().all(|c| c.is_finite())) {
        for i in 0..3 {
            b[i] = b[i].min(p[i]);
            b[i + 3] = b[i + 3].max(p[i]);
        }
    }
    if b[0] > b[3] { [0.0; 6] } else { b }
}

/// The summary as partial outputs: pieces of [`PIECE_BLOCKS`] blocks ([`SummaryPiece`]), in
/// order; at least one (a program without blocks is one empty piece).
#[must_use]
pub fn encode_pieces(s: &ReadSummary) -> Vec<String> {
    let nb = s.block_line.len();
    let bounds = bounds_of(&s.points);
    let mut out = Vec::with_capacity(nb.div_ceil(PIECE_BLOCKS).max(1));
    let (mut b0, mut p0) = (0, 0);
    loop {
        let b1 = (b0 + PIECE_BLOCKS).min(nb);
        // Points are in block order: this piece's are those of blocks below b1 (the last
        // piece takes any left).
        let p1 = if b1 == nb {
            s.point_block.len()
        } else {
            p0 + s.point_block[p0..].partition_point(|&b| (b as usize) < b1)
        };
        out.push(encode_piece(s, b0..b1, p0..p1, bounds));
        if b1 == nb {
            return out;
        }
        (b0, p0) = (b1, p1);
    }
}

/// One piece: blocks `blocks` and points `points` of `s`, its header when it is the first.
fn encode_piece(
    s: &ReadSummary,
    blocks: std::ops::Range<usize>,
    points: std::ops::Range<usize>,
    bounds: [f32; 6],
) -> String {
    let (b, p) = (blocks.clone(), points.clone());
    let mut v = json!({
        "first_block": blocks.start,
        "total_blocks": s.block_line.len(),
        "points": p.len(),
        "xyz": f32s_packed(&s.points[3 * p.start..3 * p.end]),
        "point_block": f32s_of(s.point_block[p].iter().map(|&b| b as f32)),
        "blocks": b.len(),
        // Lines and files as f32: exact below 2^24 (the interpreter's files and a program's
        // lines stay far below it).
        "block_line": f32s_of(s.block_line[b.clone()].iter().map(|&l| l as f32)),
        "block_file": f32s_of(s.block_file[b.clone()].iter().map(|&f| f32::from(f))),
        "block_kind": f32s_of(s.block_kind[b.clone()].iter().map(|&k| f32::from(k))),
        "block_slot": f32s_of(s.block_slot[b.clone()].iter().map(|&k| f32::from(k))),
        "block_feed": f32s_packed(&s.block_feed[b.clone()]),
        "block_error": f32s_packed(&s.block_error[b]),
    });
    if blocks.start == 0 {
        v["bounds_mm"] = f32s_packed(&bounds);
        v["header"] = json!({
            "lines": s.lines,
            "tools": s.tools.iter().map(|t| json!({
                "number": t.number, "cutter": t.cutter, "source": t.source,
                "feed_blocks": t.feed_blocks, "feed_min": super::num(t.feed_min), "spec": t.spec,
                "body": t.body, "body_mm": super::nums(t.body_mm), "centre_cutting": t.centre_cutting,
            })).collect::<Vec<_>>(),
            "messages": s.messages.iter().map(|(l, t)| json!([l, t])).collect::<Vec<_>>(),
            "machine": s.machine,
            "stock_mm": super::nums(s.stock_mm),
            "stock_from": s.stock_from,
            "pitch_mm": super::num(s.pitch_mm),
            "moves": s.moves,
            "feed_min": super::num(s.feed_min),
        });
    }
    v.to_string()
}

fn decode_piece(text: &str) -> Result<SummaryPiece, DecodeError> {
    const W: &str = "user-program partial";
    let v = parse(text, W)?;
    let r = Reader::new(&v, W)?;
    let n = r.usize("points")?;
    let nb = r.usize("blocks")?;
    let first_block = r.usize("first_block")?;
    let total_blocks = r.usize("total_blocks")?;
    let max_blocks = crate::simulate::canon::MAX_BLOCKS;
    if n > MAX_PATH_POINTS + max_blocks || total_blocks > max_blocks || first_block + nb > total_blocks {
        return Err(format!("{W}: too many points or blocks, or a piece past the program's end").into());
    }
    let as_u = |xs: Vec<f32>| -> Vec<u32> { xs.into_iter().map(|x| x as u32).collect() };
    let mut s = ReadSummary {
        points: r.f32s_packed("xyz", 3 * n)?,
        point_block: as_u(r.f32s_packed("point_block", n)?),
        block_line: as_u(r.f32s_packed("block_line", nb)?),
        block_file: r.f32s_packed("block_file", nb)?.into_iter().map(|x| x as u16).collect(),
        block_kind: r.f32s_packed("block_kind", nb)?.into_iter().map(|x| x as u8).collect(),
        block_slot: r.f32s_packed("block_slot", nb)?.into_iter().map(|x| x as u16).collect(),
        block_feed: r.f32s_packed("block_feed", nb)?,
        block_error: r.f32s_packed("block_error", nb)?,
        ..ReadSummary::default()
    };
    let mut bounds_mm = [0.0; 6];
    if first_block == 0 {
        bounds_mm = r.f32s_packed("bounds_mm", 6)?.try_into().map_err(|_| format!("{W}.bounds_mm: not six numbers"))?;
        let h = Reader::new(r.value("header")?, "user-program partial.header")?;
        decode_header(&h, &mut s)?;
    }
    Ok(SummaryPiece { first_block, total_blocks, bounds_mm, summary: s })
}

/// The first piece's header into `s`.
fn decode_header(h: &Reader<'_>, s: &mut ReadSummary) -> Result<(), DecodeError> {
    const W: &str = "user-program partial.header";
    s.tools = h
        .value("tools")?
        .as_array()
        .ok_or(format!("{W}.tools: not a list"))?
        .iter()
        .map(|t| {
            let t = Reader::new(t, "user-program partial.header.tools[]")?;
            Ok(ToolRow {
                number: i32::try_from(t.value("number")?.as_i64().ok_or("a tool number")?)
                    .map_err(|e| e.to_string())?,
                cutter: t.str("cutter")?.to_owned(),
                source: t.str("source")?.to_owned(),
                feed_blocks: t.usize("feed_blocks")?,
                feed_min: t.f64("feed_min")?,
                spec: t.str("spec")?.to_owned(),
                body: t.str("body")?.to_owned(),
                body_mm: t
                    .f64s("body_mm")?
                    .try_into()
                    .map_err(|_| "user-program partial.header.tools[].body_mm: not five numbers".to_owned())?,
                centre_cutting: t
                    .value("centre_cutting")?
                    .as_bool()
                    .ok_or("user-program partial.header.tools[].centre_cutting: not true or false")?,
            })
        })
        .collect::<Result<Vec<_>, DecodeError>>()?;
    s.messages = h
        .value("messages")?
        .as_array()
        .ok_or(format!("{W}.messages: not a list"))?
        .iter()
        .map(|m| {
            let line = m.get(0).and_then(Value::as_u64).and_then(|l| u32::try_from(l).ok());
            let text = m.get(1).and_then(Value::as_str);
            line.zip(text)
                .map(|(l, t)| (l, t.to_owned()))
                .ok_or_else(|| format!("{W}.messages: not [line, text]").into())
        })
        .collect::<Result<Vec<_>, DecodeError>>()?;
    s.lines = u32::try_from(h.usize("lines")?).unwrap_or(u32::MAX);
    s.machine = match h.value("machine")? {
        Value::Null => None,
        v => Some(v.as_str().ok_or(format!("{W}.machine: not text"))?.to_owned()),
    };
    s.stock_mm = h.f64s("stock_mm")?.try_into().map_err(|_| format!("{W}.stock_mm: not six numbers"))?;
    s.stock_from = h.str("stock_from")?.to_owned();
    s.pitch_mm = h.f64("pitch_mm")?;
    s.moves = h.usize("moves")?;
    s.feed_min = h.f64("feed_min")?;
    Ok(())
}

fn kinematics_index(k: KinematicsChoice) -> u64 {
    match k {
        KinematicsChoice::Auto => 0,
        KinematicsChoice::Joints => 1,
        KinematicsChoice::Tcp => 2,
    }
}

impl JobKind for UserProgram {
    const NAME: &'static str = "user-program";
    type Request = Request;
    type Output = Result<Option<Finished>, JobError>;
    type Partial = Partial;

    fn run(req: &Request, progress: &mut dyn Progress) -> Self::Output {
        run(req, progress).map_err(JobError::from)
    }

    /// The request's fields as one line of JSON, then the program's text as it is: a big
    /// program crosses without JSON's escaping, once (the page's thread writes it while a
    /// frame waits).
    fn encode_request(r: &Request) -> String {
        let head = json!({
            "name": r.name,
            "files": r.files.iter().map(|(n, t)| json!([n, t])).collect::<Vec<_>>(),
            "tool_table": r.tool_table,
            "project": r.project,
            "tool_specs": r.tool_specs,
            "default_cutter": super::nums(r.default_cutter.numbers()),
            "machine": r.machine,
            "kinematics": kinematics_index(r.kinematics),
            "pitch_mm": r.pitch_mm.map_or(Value::Null, super::num),
            "stock_mm": r.stock_mm.map_or(Value::Null, super::nums),
            "simulate": r.simulate,
        })
        .to_string();
        let mut out = String::with_capacity(head.len() + 1 + r.text.len());
        out.push_str(&head);
        out.push('\n');
        out.push_str(&r.text);
        out
    }

    fn decode_request(text: &str) -> Result<Request, DecodeError> {
        const W: &str = "user-program request";
        // JSON text holds no raw line break: the first one ends the fields.
        let (head, program) = text.split_once('\n').ok_or(format!("{W}: no program text after the fields"))?;
        let v = parse(head, W)?;
        let r = Reader::new(&v, W)?;
        let opt_text = |k: &str| -> Result<Option<String>, DecodeError> {
            match r.value(k)? {
                Value::Null => Ok(None),
                v => v.as_str().map(|s| Some(s.to_owned())).ok_or_else(|| format!("{W}.{k}: not text").into()),
            }
        };
        let files = r
            .value("files")?
            .as_array()
            .ok_or(format!("{W}.files: not a list"))?
            .iter()
            .map(|f| {
                let n = f.get(0).and_then(Value::as_str);
                let t = f.get(1).and_then(Value::as_str);
                n.zip(t)
                    .map(|(n, t)| (n.to_owned(), t.to_owned()))
                    .ok_or_else(|| format!("{W}.files: not [name, text]").into())
            })
            .collect::<Result<Vec<_>, DecodeError>>()?;
        Ok(Request {
            name: r.str("name")?.to_owned(),
            text: program.to_owned(),
            files,
            tool_table: opt_text("tool_table")?,
            project: opt_text("project")?,
            tool_specs: r
                .value("tool_specs")?
                .as_array()
                .ok_or(format!("{W}.tool_specs: not a list"))?
                .iter()
                .map(|v| v.as_str().map(str::to_owned).ok_or(format!("{W}.tool_specs: not text")))
                .collect::<Result<_, _>>()?,
            default_cutter: Cutter::from_numbers(&r.f64s("default_cutter")?)?,
            machine: opt_text("machine")?,
            kinematics: match r.usize("kinematics")? {
                0 => KinematicsChoice::Auto,
                1 => KinematicsChoice::Joints,
                2 => KinematicsChoice::Tcp,
                k => return Err(format!("{W}.kinematics: {k} is not 0, 1 or 2").into()),
            },
            pitch_mm: r.opt_f64("pitch_mm")?,
            stock_mm: match r.value("stock_mm")? {
                Value::Null => None,
                _ => Some(r.f64s("stock_mm")?.try_into().map_err(|_| format!("{W}.stock_mm: not six numbers"))?),
            },
            simulate: r.value("simulate")?.as_bool().ok_or(format!("{W}.simulate: not true or false"))?,
        })
    }

    fn encode_output(out: &Self::Output) -> String {
        match out {
            Err(e) => return e.encode(),
            Ok(None) => json!({ "read": true }),
            Ok(Some(f)) => json!({
                "counters": counters_value(&f.counters),
                "grid": grid_value(&f.map.grid),
                "top_mm": f64s_packed(&f.map.top_mm),
                "machined": super::bits_packed(&f.map.machined),
                "through": f.map.through,
                "tool_map": f32s_of(f.tool_map.iter().map(|&t| f32::from(t))),
                "removed_mm3": super::nums(f.removed_mm3.iter().copied()),
                "crash_counts": f.crash_counts,
                "crashes": f.crashes.len(),
                "crash_list": f64s_packed(&crash_numbers(&f.crashes)),
            }),
        }
        .to_string()
    }

    fn decode_output(text: &str) -> Result<Self::Output, DecodeError> {
        const W: &str = "user-program output";
        let v = parse(text, W)?;
        if let Some(e) = JobError::decode(&v, W)? {
            return Ok(Err(e));
        }
        if v.get("read").is_some() {
            return Ok(Ok(None));
        }
        let r = Reader::new(&v, W)?;
        let grid: Grid = grid_of(r.value("grid")?)?;
        let n = grid.len();
        Ok(Ok(Some(Finished {
            counters: counters_of(r.value("counters")?)?,
            map: HeightMap {
                grid,
                top_mm: r.f64s_packed("top_mm", n)?,
                machined: r.bits_packed("machined", n)?,
                through: r.usize("through")?,
            },
            tool_map: r.f32s_packed("tool_map", n)?.into_iter().map(|t| t as u16).collect(),
            removed_mm3: r.f64s("removed_mm3")?,
            crash_counts: {
                let c = r.value("crash_counts")?.as_array().filter(|c| c.len() == 4);
                let c = c.ok_or(format!("{W}.crash_counts: not four counts"))?;
                let mut counts = [0usize; 4];
                for (n, v) in counts.iter_mut().zip(c) {
                    *n = v
                        .as_u64()
                        .and_then(|v| usize::try_from(v).ok())
                        .ok_or(format!("{W}.crash_counts: not a count"))?;
                }
                counts
            },
            crashes: {
                let n = r.usize("crashes")?;
                if n > MAX_CRASHES_SENT {
                    return Err(format!("{W}.crashes: {n} reports, more than the {MAX_CRASHES_SENT} sent").into());
                }
                crashes_of(&r.f64s_packed("crash_list", CRASH_NUMBERS * n)?)?
            },
        })))
    }

    fn decode_partial(text: &str) -> Result<Partial, DecodeError> {
        decode_piece(text).map(Box::new)
    }
}

/// Numbers per crash report crossing to the page: kind, line, block (−1: none), tool (NaN:
/// none), depth, x, y, z.
const CRASH_NUMBERS: usize = 8;

fn crash_numbers(rows: &[CrashRow]) -> Vec<f64> {
    rows.iter()
        .flat_map(|c| {
            [
                c.kind.index() as f64,
                f64::from(c.line),
                c.block.map_or(-1.0, f64::from),
                c.tool.map_or(f64::NAN, f64::from),
                c.depth_mm,
                c.at_mm.x,
                c.at_mm.y,
                c.at_mm.z,
            ]
        })
        .collect()
}

fn crashes_of(xs: &[f64]) -> Result<Vec<CrashRow>, DecodeError> {
    const W: &str = "user-program output.crash_list";
    xs.chunks_exact(CRASH_NUMBERS)
        .map(|c| {
            let whole = |x: f64| (x >= 0.0 && x <= f64::from(u32::MAX) && x.fract() == 0.0).then_some(x as u32);
            let kind = whole(c[0])
                .and_then(|k| CrashKind::ALL.get(k as usize).copied())
                .ok_or(format!("{W}: {} is not a kind of crash", c[0]))?;
            Ok(CrashRow {
                kind,
                line: whole(c[1]).ok_or(format!("{W}: {} is not a line", c[1]))?,
                block: if c[2] < 0.0 {
                    None
                } else {
                    Some(whole(c[2]).ok_or(format!("{W}: {} is not a block", c[2]))?)
                },
                tool: if c[3].is_nan() { None } else { Some(c[3] as i32) },
                depth_mm: c[4],
                at_mm: DVec3::new(c[5], c[6], c[7]),
            })
        })
        .collect()
}

/// Whether a slot is a tool ([`NO_SLOT`] is none).
#[must_use]
pub fn is_tool(slot: u16) -> bool {
    slot != NO_SLOT
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::NoProgress;

    /// Collects partial outputs.
    struct Keep(Vec<String>);
    impl Progress for Keep {
        fn progress(&mut self, _f: f64) {}
        fn cancelled(&self) -> bool {
            false
        }
        fn partial(&mut self, e: String) {
            self.0.push(e);
        }
    }

    fn request(simulate: bool) -> Request {
        Request {
            name: "two.ngc".to_owned(),
            text: "G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F200\nG1 X20\nG0 Z5\nT2 M6\no<groove> call\nM30\n".to_owned(),
            files: vec![(
                "groove.ngc".to_owned(),
                "o<groove> sub\nG0 X0 Y8\nG1 Z-2 F100\nG1 X20\nG0 Z5\no<groove> endsub\n".to_owned(),
            )],
            tool_table: Some("T1 P1 D6 ;flat\nT2 P2 D4 ;v90\n".to_owned()),
            project: None,
            tool_specs: Vec::new(),
            default_cutter: Cutter::ball(1.0).unwrap_or_else(|_| unreachable!()),
            machine: None,
            kinematics: KinematicsChoice::Auto,
            pitch_mm: Some(0.25),
            stock_mm: Some([-5.0, -5.0, -5.0, 25.0, 15.0, 0.0]),
            simulate,
        }
    }

    #[test]
    fn a_request_crosses_as_text_and_runs_the_same_on_both_sides() {
        let req = request(true);
        let back = UserProgram::decode_request(&UserProgram::encode_request(&req)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(back, req);
        let mut keep = Keep(Vec::new());
        let out = UserProgram::run(&req, &mut keep);
        let f = out.clone().unwrap_or_else(|e| panic!("{e}")).unwrap_or_else(|| panic!("no stock"));
        // The subroutine's groove is tool 2's (a V: 2 mm deep is 4 mm wide), the first tool 1's.
        let g = f.map.grid;
        let at = |x: f64, y: f64| {
            let i = ((x - g.x0_mm) / g.pitch_mm) as usize;
            let j = ((y - g.y0_mm) / g.pitch_mm) as usize;
            (j * g.nx + i, g.y_mm(j))
        };
        assert_eq!(f.tool_map[at(10.0, 0.1).0], 0);
        let (k, y) = at(10.0, 8.1);
        assert_eq!(f.tool_map[k], 1);
        assert!((f.map.top_mm[k] - (-2.0 + (y - 8.0).abs())).abs() < 1e-9, "{}", f.map.top_mm[k]);
        let again = UserProgram::decode_output(&UserProgram::encode_output(&out)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again, out);
        assert_eq!(keep.0.len(), 1, "a small program crosses in one piece");
        let piece = UserProgram::decode_partial(&keep.0[0]).unwrap_or_else(|e| panic!("{e}"));
        assert!(piece.is_last());
        let s = piece.summary;
        assert_eq!(s.block_line.len(), 8);
        assert_eq!(s.tools.iter().map(|t| t.number).collect::<Vec<_>>(), [1, 2]);
        // Blocks of the subroutine carry their file's lines.
        assert_eq!((s.block_file[4], s.block_line[4]), (1, 2));
        let read_only = UserProgram::run(&request(false), &mut NoProgress);
        assert_eq!(read_only, Ok(None));
    }

    /// A flat 6 mm end mill with 10 mm flutes fed across a 30 mm deep block at Z−15: its
    /// shank (radius 3 mm, from 10 mm above the tip) rubs the 5 mm of stock above the flutes
    /// on that line; the G0 up out of the slot is a rapid through the stock the shank left.
    /// The crashes cross with their lines, blocks, tools and depths; the tool rows with their
    /// body.
    #[test]
    fn a_shank_crash_crosses_with_its_line_block_and_depth() {
        let req = Request {
            name: "deep.ngc".to_owned(),
            text: "G21 G90\nT1 M6\nG0 X-10 Y10 Z5\nG0 Z-15\nG1 X30 F300\nG0 Z5\nM30\n".to_owned(),
            files: Vec::new(),
            tool_table: None,
            project: None,
            tool_specs: vec!["1:flat:6,flute=10".to_owned()],
            default_cutter: Cutter::flat(1.5).unwrap_or_else(|_| unreachable!()),
            machine: None,
            kinematics: KinematicsChoice::Auto,
            pitch_mm: Some(0.5),
            stock_mm: Some([0.0, 0.0, -30.0, 40.0, 20.0, 0.0]),
            simulate: true,
        };
        let (_, summary) = read(&req, &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        let t = &summary.tools[0];
        assert_eq!(t.spec, "1:flat:6,flute=10");
        // Flutes given; the shank 3·R above them, the holder assumed (2.5·R × 6·R).
        let body: Vec<String> = t.body_mm.iter().map(|v| format!("{v}")).collect();
        assert_eq!(body, ["10", "3", "9", "7.5", "18"]);
        assert!(t.body.starts_with("flutes 10 mm, shank R 3 × 9 mm") && !t.body.contains("assumed"), "{}", t.body);
        assert!(t.centre_cutting);
        let out = UserProgram::run(&req, &mut NoProgress);
        let f = out.clone().unwrap_or_else(|e| panic!("{e}")).unwrap_or_else(|| panic!("no stock"));
        let first = f.crashes.first().unwrap_or_else(|| panic!("no crash: {f:?}"));
        assert_eq!((first.kind, first.line, first.tool), (CrashKind::Shank, 5, Some(1)));
        assert!((first.depth_mm - 5.0).abs() < 0.01, "{first:?}");
        assert!(first.at_mm.x > 0.0 && first.at_mm.x < 33.0 && (first.at_mm.z - 0.0).abs() < 1e-9, "{first:?}");
        let b = first.block.unwrap_or_else(|| panic!("no block")) as usize;
        assert_eq!((summary.block_line[b], summary.block_kind[b]), (5, 1), "the G1 of line 5");
        // Climbing out, the shank and the flutes (in a G0) meet the stock the shank left.
        let kinds: Vec<(CrashKind, u32)> = f.crashes.iter().map(|c| (c.kind, c.line)).collect();
        assert_eq!(kinds, [(CrashKind::Shank, 5), (CrashKind::Shank, 6), (CrashKind::Rapid, 6)]);
        assert_eq!(f.crash_counts, [2, 0, 1, 0]);
        assert_eq!(f.crash_total(), f.crashes.len());
        assert_eq!(f.crashes_left_out(), 0);
        let again = UserProgram::decode_output(&UserProgram::encode_output(&out)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again, out);
        // The tool rows cross with their body.
        let texts = encode_pieces(&summary);
        let piece = UserProgram::decode_partial(&texts[0]).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(piece.summary.tools, summary.tools);
        // A clean program: no crash at all.
        let clean =
            Request { text: "G21 G90\nT1 M6\nG0 X-10 Y10 Z5\nG1 Z-8 F300\nG1 X30\nG0 Z5\nM30\n".to_owned(), ..req };
        let f = UserProgram::run(&clean, &mut NoProgress)
            .unwrap_or_else(|e| panic!("{e}"))
            .unwrap_or_else(|| panic!("no stock"));
        assert_eq!((f.crash_counts, f.crashes.len()), ([0; 4], 0), "{:?}", f.crashes);
    }

    /// Past [`MAX_CRASHES_SENT`] reports only the first cross, the counts keep them all, and
    /// a list longer than the cap is refused when read.
    #[test]
    fn crash_reports_past_the_cap_are_counted_not_sent() {
        let mut text = String::from("G21 G90\nT1 M6\nG0 X0 Y0 Z5\nG0 Z-1\n");
        // A raster in rapids at Z−1: each block meets fresh stock.
        for y in 0..30 {
            for x in 0..40 {
                let x = if y % 2 == 0 { x } else { 39 - x };
                text.push_str(&format!("G0 X{x} Y{y}\n"));
            }
        }
        let req = Request {
            name: "rapids.ngc".to_owned(),
            text,
            files: Vec::new(),
            tool_table: None,
            project: None,
            tool_specs: vec!["1:flat:1".to_owned()],
            default_cutter: Cutter::flat(1.5).unwrap_or_else(|_| unreachable!()),
            machine: None,
            kinematics: KinematicsChoice::Auto,
            pitch_mm: Some(0.25),
            stock_mm: Some([-1.0, -1.0, -2.0, 41.0, 31.0, 0.0]),
            simulate: true,
        };
        let out = UserProgram::run(&req, &mut NoProgress);
        let f = out.clone().unwrap_or_else(|e| panic!("{e}")).unwrap_or_else(|| panic!("no stock"));
        assert!(f.crash_counts[CrashKind::Rapid.index()] > 1100, "{:?}", f.crash_counts);
        assert_eq!(f.crashes.len(), MAX_CRASHES_SENT);
        assert_eq!(f.crashes_left_out(), f.crash_total() - MAX_CRASHES_SENT);
        // In the order the program ran: lines rise.
        assert!(f.crashes.windows(2).all(|w| w[0].line < w[1].line));
        let text = UserProgram::encode_output(&out);
        assert_eq!(UserProgram::decode_output(&text), Ok(out));
        let too_many = text.replacen(&format!("\"crashes\":{MAX_CRASHES_SENT}"), "\"crashes\":1001", 1);
        assert_ne!(too_many, text);
        assert!(UserProgram::decode_output(&too_many).is_err_and(|e| e.to_string().contains("more than")));
    }

    /// A program of several pieces crosses whole: the pieces taken in order give the summary
    /// read (bit for bit, NaN errors included); one out of order is refused and changes
    /// nothing.
    #[test]
    fn a_long_program_crosses_in_pieces_that_add_up_to_its_summary() {
        let mut text = String::from("G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F300\n");
        let n = 2 * PIECE_BLOCKS + 123;
        for k in 0..n {
            // Arcs among the lines: blocks of several points.
            if k % 7 == 0 {
                let (x, y) = (k % 40, (k / 40) % 30);
                text.push_str(&format!("G1 X{x} Y{y}\nG2 X{} Y{y} R1.5\n", x + 2));
            } else {
                text.push_str(&format!("G1 X{} Y{}\n", k % 40, (k / 40) % 30));
            }
        }
        let mut req = request(false);
        req.text = text;
        req.files.clear();
        req.tool_table = None;
        let (_, whole) = read(&req, &mut NoProgress).unwrap_or_else(|e| panic!("{e}"));
        assert!(whole.block_line.len() > 2 * PIECE_BLOCKS && whole.points.len() / 3 > whole.block_line.len());
        let texts = encode_pieces(&whole);
        assert_eq!(texts.len(), whole.block_line.len().div_ceil(PIECE_BLOCKS));
        let pieces: Vec<SummaryPiece> =
            texts.iter().map(|t| *UserProgram::decode_partial(t).unwrap_or_else(|e| panic!("{e}"))).collect();
        let mut got = ReadSummary::default();
        assert!(!got.take_piece(pieces[1].clone()), "the second piece cannot come first");
        assert_eq!(got, ReadSummary::default());
        for (i, p) in pieces.iter().enumerate() {
            assert_eq!(p.is_last(), i + 1 == pieces.len());
            assert!(got.take_piece(p.clone()));
        }
        let bits = |xs: &[f32]| xs.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&got.points), bits(&whole.points));
        assert_eq!(bits(&got.block_error), bits(&whole.block_error));
        assert_eq!(bits(&got.block_feed), bits(&whole.block_feed));
        let strip = |s: &ReadSummary| ReadSummary {
            points: Vec::new(),
            block_error: Vec::new(),
            block_feed: Vec::new(),
            ..s.clone()
        };
        assert_eq!(strip(&got), strip(&whole));
        // The first piece's box holds every point of the path.
        let b = pieces[0].bounds_mm;
        assert!(whole.points.chunks_exact(3).all(|p| (0..3).all(|i| b[i] <= p[i] && p[i] <= b[i + 3])));
        assert!((0..3).all(|i| whole.points.chunks_exact(3).any(|p| p[i] == b[i])
            && whole.points.chunks_exact(3).any(|p| p[i] == b[i + 3])));
    }
}
