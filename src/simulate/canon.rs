//! A user's program as the simulation runs it: the canonical motions of the interpreter
//! ([`crate::gcode::interp::Canon`]) turned into moves, each tool change switching the cutter,
//! tool length offsets as programmed and the rotary axes through a machine — with what a
//! report or a viewer needs of every block: its line, its tool, its feed and time at the
//! programmed feed, and, for a block that turns the rotary axes, seed 002's nonlinear error.
//!
//! # Tools
//!
//! The tool in the spindle is the one of the last `M6`/`M61` ([`Canon::ToolChange`]); its
//! shape and size come from the tool table ([`CanonOptions::tools`], [`cutter_of`]). Before
//! the first tool change the spindle holds [`CanonOptions::default_cutter`] if given, else
//! the table's only tool, else its lowest-numbered one (a note says which). A tool number the
//! table lacks is cut with the default cutter, or refused with the line that asks for it.
//!
//! # Tool length
//!
//! The interpreter's positions are the *programmed* tip; the controller puts the spindle nose
//! at `programmed tip + offset in force` ([`Canon::ToolLengthOffset`]). The real tool is as
//! long as its table entry's Z offset `L` (LinuxCNC's convention: the table's Z is the tool's
//! length from the gauge line), so its tip is `Δ = L − offset` *beyond* the programmed point,
//! along the tool axis: zero when the program applies the tool's own offset (`G43 H` of the
//! tool in the spindle), a gouge when it forgets it. Each new Δ ≠ 0 is noted with its line.
//!
//! # Rotary axes
//!
//! Without a machine the rotary words are left out (and noted). With one
//! ([`MachineSetup`]: the four machines of [`crate::fiveaxis`], or `wrap-a`, a rotary table
//! about X — `table-ac` with C held at 0), A/B/C are read in one of two ways ([`RotaryMode`]):
//!
//! - **joints** (trivial kinematics, the default): X, Y, Z and the two rotary words are the
//!   machine's joints; the machine moves them linearly between blocks, and the tool tip and
//!   axis in the workpiece come from forward kinematics
//!   ([`crate::fiveaxis::Machine::pose_from_joints`]). Between two blocks that turn a rotary
//!   axis the tip leaves the straight line between the blocks' tips: seed 002's nonlinear
//!   error, measured per block ([`RotaryBlock::nonlinear_mm`]).
//! - **TCP** (tool-centre-point control: LinuxCNC's `M428`-style kinematics switch, `G43.4`):
//!   X, Y, Z are the tip in the workpiece and the rotary words set the tool axis; the
//!   controller moves the tip straight while the rotary axes move linearly. The simulation
//!   follows that motion with joint moves placed so that their tip stays within the chord
//!   tolerance of the straight line. The nonlinear error reported for such a block is the one
//!   the same two poses would have on a machine *without* TCP (the joints interpolated
//!   linearly, as seed 002 assumes: a post-processor's view); under TCP it is zero.
//!
//! `Auto` ([`KinematicsChoice`]) reads a program as TCP from a line with `M428` or `G43.4`
//! (the interpreter reports both as not modelled, see [`TcpWatch`]) up to `M429` or, for
//! `G43.4`, the next tool length offset call (`G43`, `G49`). Sinumerik `TRAORI` reaches this
//! layer only as a skipped line: give [`KinematicsChoice::Tcp`].
//!
//! Arcs and splines are cut into chords in X, Y, Z (the chord tolerance), the rotary axes
//! moving linearly along them; their nonlinear error is not measured (a note counts them).
//!
//! # Time
//!
//! Each feed block's time at its programmed feed: `G94` length / F (length along X, Y, Z, or
//! the rotary travel in degrees for a rotary-only move, as LinuxCNC reads F), `G93` 1 / F
//! (inverse time), `G95` length / (F · spindle speed). A block with F0 (or G95 with the
//! spindle stopped) is counted as untimed; rapids are not timed (the machine's rapid rate
//! is not in the program) — their length is.

use glam::DVec3;

use super::program::{MoveKind, Program, SimMove};
use super::{SimError, Simulation};
use crate::fiveaxis::{Joints, Machine, MachineKind};
use crate::gcode::interp::tools::{ToolEntry, ToolShape as TableShape, ToolTable};
use crate::gcode::interp::{Canon, Feed, FeedMode, Interpreter, Loc, Pose, Report};
use crate::gcode::parse::ParsedProgram;
use crate::gcode::path::Segment;
use crate::geom::Cutter;
use crate::numerics::maximise::{MaxOptions, sampled_max};
use crate::numerics::measure::distance_to_segment;

/// Rotary motion (degrees) below which a block does not turn an axis.
pub const ROTARY_STILL_DEG: f64 = 1e-9;

/// A tool length difference (mm) below which the tool is as long as the offset in force.
pub const LENGTH_MATCH_MM: f64 = 1e-9;

/// |z| of the tool axis above which it counts as vertical (a table machine at zero tilt):
/// such moves are cut as 3-axis moves.
const VERTICAL_AXIS_Z: f64 = 1.0 - 1e-12;

/// Most notes kept; later ones are counted in [`CanonProgram::notes_dropped`].
pub const MAX_NOTES: usize = 200;

/// Most sub-moves one TCP move is cut into.
pub const MAX_TCP_PIECES: usize = 4096;

/// Blocks a program may have (each is about 200 bytes).
pub const MAX_BLOCKS: usize = 2_000_000;

/// A tool slot that holds no tool (moves are not cut).
pub const NO_SLOT: u16 = u16::MAX;

/// How the rotary words of a program are read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RotaryMode {
    /// The words are the machine's joints (trivial kinematics).
    #[default]
    Joints,
    /// Tool-centre-point control: X, Y, Z are the tip in the workpiece.
    Tcp,
}

/// Which [`RotaryMode`] a program is read in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum KinematicsChoice {
    /// TCP between `M428`/`G43.4` and their cancels ([`TcpWatch`]), joints elsewhere.
    #[default]
    Auto,
    /// Joints throughout.
    Joints,
    /// TCP throughout.
    Tcp,
}

/// A machine for the rotary axes: one of [`crate::fiveaxis`]'s four, or a rotary table
/// about X alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineSetup {
    /// The kinematics (pivots, tool length of head machines).
    pub machine: Machine,
    /// A 4-axis rotary table about X (`wrap-a`): the `table-ac` kinematics with C held at 0.
    pub four_axis: bool,
}

impl MachineSetup {
    /// The names [`Self::from_name`] knows.
    pub const NAMES: [&'static str; 5] = ["table-ac", "table-bc", "head-bc", "head-a-table-c", "wrap-a"];

    /// A machine by name with its pivots at the workpiece origin, no travel limits (a
    /// program's own angles are what moves the machine) and, for head machines, a tool
    /// length (pivot to tip) of `head_length_mm`.
    #[must_use]
    pub fn from_name(name: &str, head_length_mm: f64) -> Option<Self> {
        let (kind, four_axis) = match name {
            "wrap-a" => (MachineKind::TableAC, true),
            other => (MachineKind::from_name(other)?, false),
        };
        let machine =
            Machine { kind, pivots_mm: [DVec3::ZERO; 2], tool_length_mm: head_length_mm, limits_rad: [None; 2] };
        Some(Self { machine, four_axis })
    }

    /// Its name (`table-ac`, …, `wrap-a`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        if self.four_axis { "wrap-a" } else { self.machine.kind.as_str() }
    }

    /// The machine a program's comments name, if one does: LinuxCNC's `xyzac`/`xyzbc`
    /// (e.g. `M428 ;TCP:xyzac`) or one of [`Self::NAMES`], the first found.
    #[must_use]
    pub fn from_comments(comments: &[(Loc, String)], head_length_mm: f64) -> Option<(Self, Loc)> {
        for (loc, text) in comments {
            let t = text.to_ascii_lowercase();
            for (word, name) in [
                ("head-a-table-c", "head-a-table-c"),
                ("table-ac", "table-ac"),
                ("table-bc", "table-bc"),
                ("head-bc", "head-bc"),
                ("wrap-a", "wrap-a"),
                ("xyzac", "table-ac"),
                ("xyzbc", "table-bc"),
            ] {
                if t.contains(word) {
                    return Self::from_name(name, head_length_mm).map(|m| (m, *loc));
                }
            }
        }
        None
    }

    /// Indices into (A, B, C) of the machine's two rotary words `[tilt, C]`.
    #[must_use]
    pub fn words(&self) -> [usize; 2] {
        match self.machine.kind {
            MachineKind::TableAC | MachineKind::HeadATableC => [0, 2],
            MachineKind::TableBC | MachineKind::HeadBC => [1, 2],
        }
    }

    /// The joints' rotary values (rad) for programmed A, B, C (degrees).
    #[must_use]
    pub fn rotary_rad(&self, abc_deg: DVec3) -> [f64; 2] {
        let [t, c] = self.words();
        let c = if self.four_axis { 0.0 } else { abc_deg[c].to_radians() };
        [abc_deg[t].to_radians(), c]
    }

    /// The rotary words this machine does not have (letters), for a note when they move.
    fn unused(&self) -> Vec<usize> {
        let used = self.words();
        (0..3).filter(|i| !used.contains(i) || (self.four_axis && *i == 2)).collect()
    }
}

/// How a program is read into moves.
#[derive(Clone, Debug)]
pub struct CanonOptions {
    /// The machine of the rotary axes; `None`: three axes, rotary words left out.
    pub machine: Option<MachineSetup>,
    /// How the rotary words are read.
    pub kinematics: KinematicsChoice,
    /// Chord tolerance of arcs, splines and TCP moves (mm).
    pub chord_tol_mm: f64,
    /// The tools by number.
    pub tools: ToolTable,
    /// The cutter before the first tool change and of tool numbers the table lacks.
    pub default_cutter: Option<Cutter>,
}

/// A tool the program uses, with its totals.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramTool {
    /// Its number (T); −1 for the default cutter before any tool change.
    pub number: i32,
    /// Its shape and size.
    pub cutter: Cutter,
    /// Its length (mm): the table's Z offset (0 when not given).
    pub length_mm: f64,
    /// Where its size comes from (`tool table`, `the default cutter (tool 3 is not in the
    /// table)`, …).
    pub source: String,
    /// Where it first cuts.
    pub first: Loc,
    /// Feed blocks (G1, G2, G3, splines) with this tool.
    pub feed_blocks: usize,
    /// Rapid blocks (G0) with this tool.
    pub rapid_blocks: usize,
    /// Length of its feed blocks (mm, along X, Y, Z).
    pub feed_mm: f64,
    /// Length of its rapid blocks (mm).
    pub rapid_mm: f64,
    /// Time of its feed blocks at the programmed feed (min).
    pub feed_min: f64,
    /// Feed blocks without a time (F0, or G95 with the spindle stopped).
    pub untimed_blocks: usize,
    /// Material it removed (mm³), after [`CanonProgram::run`].
    pub removed_mm3: f64,
}

/// What a block does, for colours and counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockKind {
    /// G0.
    Rapid,
    /// G1 (and the feed moves of canned cycles).
    Line,
    /// G2/G3.
    Arc,
    /// A spline (G5, G5.1, G5.2, G6.2).
    Spline,
}

/// A block that turns a rotary axis on a machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotaryBlock {
    /// How its words were read.
    pub mode: RotaryMode,
    /// The machine's joints at its start and end (TCP: those the controller commands).
    pub from: Joints,
    /// End joints.
    pub to: Joints,
    /// The tool tip at its start and end in the workpiece (mm): the programmed chord.
    pub tip_from: DVec3,
    /// End tip (mm).
    pub tip_to: DVec3,
    /// Seed 002's nonlinear error: the largest distance (mm) from the tip swept with the
    /// joints moving linearly to the chord; for a TCP block what it would be without TCP.
    /// Measured for feed lines (G1); `None` for rapids, arcs and splines.
    pub nonlinear_mm: Option<f64>,
    /// Where along the block (0 to 1) the largest deviation is.
    pub at_tau: f64,
    /// The swept tip there (mm, workpiece).
    pub worst_tip: DVec3,
}

/// One programmed motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProgramBlock {
    /// Its line.
    pub loc: Loc,
    /// Rapid, line, arc or spline.
    pub kind: BlockKind,
    /// Its tool's slot in [`CanonProgram::tools`] ([`NO_SLOT`]: no tool in the spindle).
    pub slot: u16,
    /// The feed in force (a rapid's is the last programmed feed, unused).
    pub feed: Feed,
    /// Length along X, Y, Z (mm): the chords of arcs and splines.
    pub length_mm: f64,
    /// Rotary travel (degrees, the largest of A, B, C).
    pub rotary_deg: f64,
    /// Time at the programmed feed (min); `None` for rapids and untimed blocks.
    pub time_min: Option<f64>,
    /// Its moves: `program.moves[first..end]`.
    pub moves: (u32, u32),
    /// The tool tip at its end (mm, workpiece): for drawing the path.
    pub end_tip: DVec3,
    /// The rotary part, when it turns a rotary axis on a machine.
    pub rotary: Option<RotaryBlock>,
    /// Material it removed (mm³), after [`CanonProgram::run`].
    pub removed_mm3: f64,
}

/// A note on how the program was read: an assumption or something left out, with its line.
#[derive(Clone, Debug, PartialEq)]
pub struct Note {
    /// Where it first applies.
    pub loc: Loc,
    /// What, and what to do about it.
    pub text: String,
}

/// A program ready to simulate, with its tools, blocks and notes.
#[derive(Clone, Debug, Default)]
pub struct CanonProgram {
    /// The moves.
    pub program: Program,
    /// The tools used, by slot.
    pub tools: Vec<ProgramTool>,
    /// The programmed motions in order.
    pub blocks: Vec<ProgramBlock>,
    /// Notes, first [`MAX_NOTES`].
    pub notes: Vec<Note>,
    /// Notes left out past [`MAX_NOTES`].
    pub notes_dropped: usize,
    /// The machine, when rotary axes are read through one.
    pub machine: Option<MachineSetup>,
    /// The box (mm) CAMotics would make an automatic workpiece from: the feed moves' tips
    /// widened by their tool's radius in x and y; `None` without feed moves.
    pub cut_box: Option<(DVec3, DVec3)>,
    /// Arcs and splines that turn a rotary axis (their nonlinear error is not measured).
    pub rotary_curves: usize,
}

/// Follows the interpreter's reports of the codes that switch tool-centre-point control:
/// `M428` (LinuxCNC's sample 5-axis configurations remap it to their TCP kinematics) and
/// `G43.4`/`G43.5` turn it on; `M429` (identity kinematics) and, after `G43.4`, the next
/// tool length offset call turn it off. The interpreter reports each unmodelled code once
/// with a count that grows each time the code is executed; a count that grew since the last
/// look means the code ran on a line before the motion at hand.
#[derive(Clone, Debug, Default)]
pub struct TcpWatch {
    counts: [u64; 3],
    on: bool,
    by_g43_4: bool,
}

impl TcpWatch {
    /// Updates the state from the reports after a call; returns whether TCP is on.
    pub fn update(&mut self, reports: &[Report]) -> bool {
        let count = |code: &str| reports.iter().find(|r| r.code == code).map_or(0, |r| r.count);
        let now = [count("M428"), count("M429"), count("G43.4") + count("G43.5")];
        let grew = |i: usize| now[i] > self.counts[i];
        if grew(0) || grew(2) {
            self.on = true;
            self.by_g43_4 = grew(2);
        }
        if grew(1) && !(grew(0) || grew(2)) {
            self.on = false;
        }
        self.counts = now;
        self.on
    }

    /// A tool length offset call (`G43`, `G49`) was made: it cancels `G43.4`.
    pub fn tool_offset(&mut self) {
        if self.by_g43_4 {
            self.on = false;
            self.by_g43_4 = false;
        }
    }

    /// Whether TCP is on.
    #[must_use]
    pub fn on(&self) -> bool {
        self.on
    }
}

/// The simulation's cutter for a tool table entry: flat, ball and bull-nose end mills, V
/// cutters and drills (sharp cones), CAMotics' snub-nose tools (a cone with a flat tip; its
/// angle from the tool's length, 2·atan((R − r_t)/length)). The entry's length, when given
/// (CAMotics), is the flute length.
///
/// # Errors
/// A tool with no diameter, or a shape that is not modelled (CAMotics' spheroid), with what
/// to give instead.
pub fn cutter_of(t: &ToolEntry) -> Result<Cutter, String> {
    let n = t.number;
    let r = 0.5 * t.diameter_mm;
    if !(r > 0.0 && r.is_finite()) {
        return Err(format!(
            "tool {n} has no diameter in the table; give its D (LinuxCNC) or diameter (CAMotics), or --tool {n}:flat:6"
        ));
    }
    let bad = |e: crate::geom::CutterError| format!("tool {n}: {e}");
    let mut c = match t.shape {
        TableShape::Flat => Cutter::flat(r).map_err(bad)?,
        TableShape::Ball => Cutter::ball(r).map_err(bad)?,
        TableShape::Bull { corner_radius_mm } => Cutter::fillet(r, corner_radius_mm).map_err(bad)?,
        TableShape::V { tip_angle_deg } => Cutter::tapered(r, tip_angle_deg, 0.0).map_err(bad)?,
        TableShape::Drill { point_angle_deg } => Cutter::tapered(r, point_angle_deg, 0.0).map_err(bad)?,
        TableShape::Snub { tip_diameter_mm } => {
            let tip = 0.5 * tip_diameter_mm;
            let len = t.length_mm.filter(|l| *l > 0.0).unwrap_or(10.0);
            if tip >= r {
                Cutter::flat(r).map_err(bad)?
            } else {
                Cutter::tapered(r, 2.0 * ((r - tip) / len).atan().to_degrees(), tip).map_err(bad)?
            }
        }
        TableShape::Unknown => {
            return Err(format!(
                "tool {n}: its shape is not modelled (a CAMotics spheroid); give it as --tool {n}:ball:{}",
                t.diameter_mm
            ));
        }
    };
    let mut body = t.body;
    if body.flute_mm.is_none() {
        body.flute_mm = t.length_mm.filter(|l| *l > 0.0 && l.is_finite());
    }
    c = c.with_body(&body).map_err(bad)?;
    Ok(c)
}

/// The largest distance (mm) from the tool tip the machine sweeps between two joint sets
/// (joints interpolated linearly) to the straight chord between the two end tips, and where:
/// `(distance, τ, swept tip)`. Seed 002's nonlinear error of one block.
#[must_use]
pub fn nonlinear_error(machine: &Machine, from: &Joints, to: &Joints) -> (f64, f64, DVec3) {
    let a = machine.pose_from_joints(from).tip_in_workpiece;
    let b = machine.pose_from_joints(to).tip_in_workpiece;
    let tip = |tau: f64| machine.pose_from_joints(&from.lerp(to, tau)).tip_in_workpiece;
    let opts = MaxOptions::default();
    let peak = sampled_max(|tau| Ok::<f64, ()>(distance_to_segment(tip(tau), a, b)), 0.0, 1.0, &opts);
    match peak {
        Ok(p) if p.value.is_finite() => (p.value.max(0.0), p.x, tip(p.x)),
        _ => (f64::NAN, 0.0, a),
    }
}

/// The tool tip at the start and end of a move (mm, workpiece).
#[must_use]
pub fn move_ends(m: &SimMove) -> [DVec3; 2] {
    match m.kind {
        MoveKind::Line { from, to } => [from, to],
        MoveKind::Joints { machine, from, to } => {
            [machine.pose_from_joints(&from).tip_in_workpiece, machine.pose_from_joints(&to).tip_in_workpiece]
        }
    }
}

/// Reads canonical calls into a [`CanonProgram`], one at a time.
pub struct CanonBuilder {
    opts: CanonOptions,
    out: CanonProgram,
    /// Where the controlled point is (the last motion's end).
    pos: Pose,
    /// Tool length offset in force (mm).
    offset: DVec3,
    /// Slot of the tool in the spindle (`None`: before the first tool change).
    slot: Option<u16>,
    /// A motion was seen (the first, a rapid from an unknown place, is not cut).
    moved: bool,
    /// Δ last noted (mm) per slot, so each new tool-length mismatch is noted once.
    noted_delta: Vec<f64>,
    scratch: ParsedProgram,
    unused_rotary_noted: bool,
    rotary_without_machine: u64,
    first_rotary_without_machine: Loc,
}

impl CanonBuilder {
    /// A builder with these options.
    #[must_use]
    pub fn new(opts: CanonOptions) -> Self {
        let machine = opts.machine;
        Self {
            opts,
            out: CanonProgram { machine, ..CanonProgram::default() },
            pos: Pose::default(),
            offset: DVec3::ZERO,
            slot: None,
            moved: false,
            noted_delta: Vec::new(),
            scratch: ParsedProgram::default(),
            unused_rotary_noted: false,
            rotary_without_machine: 0,
            first_rotary_without_machine: Loc::default(),
        }
    }

    /// The program so far.
    #[must_use]
    pub fn program(&self) -> &CanonProgram {
        &self.out
    }

    fn note(&mut self, loc: Loc, text: String) {
        if self.out.notes.len() < MAX_NOTES {
            self.out.notes.push(Note { loc, text });
        } else {
            self.out.notes_dropped += 1;
        }
    }

    /// The slot of a tool number (adding the tool on first use).
    fn slot_of(&mut self, number: i32, loc: Loc) -> Result<u16, SimError> {
        if let Some(i) = self.out.tools.iter().position(|t| t.number == number) {
            return Ok(u16::try_from(i).unwrap_or(NO_SLOT));
        }
        let (cutter, length, source) = match self.opts.tools.get(number) {
            Some(entry) => {
                let c = cutter_of(entry).map_err(|e| SimError::Program(format!("line {}: {e}", loc.line)))?;
                let shape = if entry.shape_assumed {
                    " (no shape in its remark: taken as a flat end mill)".to_owned()
                } else {
                    String::new()
                };
                (c, entry.offset_mm.z, format!("tool table{shape}"))
            }
            None if number < 0 => match self.opts.default_cutter {
                Some(c) => (c, 0.0, "the default cutter (--cutter)".to_owned()),
                None => {
                    return Err(SimError::Program(
                        "the program cuts before any tool change and no cutter is given; give --cutter or a tool table"
                            .to_owned(),
                    ));
                }
            },
            None => match self.opts.default_cutter {
                Some(c) => (c, 0.0, format!("the default cutter (tool {number} is not in the tool table)")),
                None => {
                    return Err(SimError::Program(format!(
                        "line {}: tool {number} is not in the tool table; add it, or give --tool {number}:flat:6 (N:shape:diameter) or --cutter",
                        loc.line
                    )));
                }
            },
        };
        if self.out.tools.len() >= usize::from(NO_SLOT) {
            return Err(SimError::Program(format!("line {}: more than {} tools used", loc.line, NO_SLOT)));
        }
        self.out.tools.push(ProgramTool {
            number,
            cutter,
            length_mm: length,
            source,
            first: loc,
            feed_blocks: 0,
            rapid_blocks: 0,
            feed_mm: 0.0,
            rapid_mm: 0.0,
            feed_min: 0.0,
            untimed_blocks: 0,
            removed_mm3: 0.0,
        });
        self.noted_delta.push(0.0);
        Ok(u16::try_from(self.out.tools.len() - 1).unwrap_or(NO_SLOT))
    }

    /// The slot cutting now: the tool in the spindle, or the initial one.
    fn current_slot(&mut self, loc: Loc) -> Result<u16, SimError> {
        if let Some(s) = self.slot {
            return Ok(s);
        }
        let s = if self.opts.default_cutter.is_some() {
            self.slot_of(-1, loc)?
        } else {
            let first = self.opts.tools.iter().next().map(|t| t.number);
            let Some(n) = first else {
                return self.slot_of(-1, loc);
            };
            let s = self.slot_of(n, loc)?;
            let how =
                if self.opts.tools.len() == 1 { "the table's only tool" } else { "the table's lowest-numbered tool" };
            self.note(
                loc,
                format!("the program moves before any tool change (M6): it is cut with tool {n}, {how}; give --cutter to choose"),
            );
            s
        };
        self.slot = Some(s);
        Ok(s)
    }

    /// Adds one canonical call; `tcp` says whether tool-centre-point control is on for it
    /// (as [`TcpWatch`] follows it; ignored unless the kinematics choice is `Auto`).
    ///
    /// # Errors
    /// A tool the table cannot give, too many moves or blocks, a curve needing too many
    /// chords.
    pub fn push(&mut self, c: &Canon, tcp: bool) -> Result<(), SimError> {
        match c {
            Canon::ToolChange { tool, loc } => {
                self.slot = Some(if *tool <= 0 { NO_SLOT } else { self.slot_of(*tool, *loc)? });
                Ok(())
            }
            Canon::ToolLengthOffset { offset, .. } => {
                // The spindle stays where it is: the programmed point now reads old − new
                // further along the axis.
                self.pos.xyz += self.offset - *offset;
                self.offset = *offset;
                Ok(())
            }
            Canon::Traverse { loc, end, .. } => self.motion(*loc, BlockKind::Rapid, *end, None, c, tcp),
            Canon::Line { loc, end, feed, .. } => self.motion(*loc, BlockKind::Line, *end, Some(*feed), c, tcp),
            Canon::Arc { loc, end, feed, .. } => self.motion(*loc, BlockKind::Arc, *end, Some(*feed), c, tcp),
            Canon::Spline { loc, end, feed, .. } => self.motion(*loc, BlockKind::Spline, *end, Some(*feed), c, tcp),
            Canon::Dwell { .. } | Canon::Spindle { .. } | Canon::Stop { .. } => Ok(()),
        }
    }

    /// The points (controlled point, mm) of a motion's chords and each one's fraction of
    /// the motion (for the rotary axes).
    fn chord_points(&mut self, c: &Canon, loc: Loc) -> Result<Vec<(DVec3, f64)>, SimError> {
        let start = self.pos.xyz;
        let Some(end) = c.end() else {
            return Ok(Vec::new());
        };
        if matches!(c, Canon::Traverse { .. } | Canon::Line { .. }) {
            return Ok(vec![(start, 0.0), (end.xyz, 1.0)]);
        }
        self.scratch.toolpath.blocks.clear();
        let (mut p, mut tlo) = (start, DVec3::ZERO);
        crate::gcode::read::push(&mut self.scratch, &mut p, &mut tlo, c.clone());
        let line = loc.line as usize;
        let segments: Vec<Segment> = self.scratch.toolpath.blocks.drain(..).map(|b| b.segment).collect();
        let mut pts: Vec<DVec3> = vec![start];
        for s in &segments {
            let more = self.out.program.segment_points(s, line, self.opts.chord_tol_mm)?;
            pts.extend(more.into_iter().skip(1));
        }
        // Fractions by chord length (the rotary axes move linearly along the path).
        let total: f64 = pts.windows(2).map(|w| (w[1] - w[0]).length()).sum();
        let mut acc = 0.0;
        let mut out = Vec::with_capacity(pts.len());
        for (i, p) in pts.iter().enumerate() {
            if i > 0 {
                acc += (*p - pts[i - 1]).length();
            }
            let f = if total > 0.0 { acc / total } else { i as f64 / (pts.len() - 1).max(1) as f64 };
            out.push((*p, f));
        }
        Ok(out)
    }

    #[allow(clippy::too_many_lines, reason = "one motion's geometry, time and rotary report in order")]
    fn motion(
        &mut self,
        loc: Loc,
        kind: BlockKind,
        end: Pose,
        feed: Option<Feed>,
        c: &Canon,
        tcp_now: bool,
    ) -> Result<(), SimError> {
        if self.out.blocks.len() >= MAX_BLOCKS {
            return Err(SimError::Program(format!(
                "line {}: more than {MAX_BLOCKS} motions; split the program",
                loc.line
            )));
        }
        let start = self.pos;
        let first_move = !self.moved;
        self.moved = true;
        // A leading rapid before any tool change is not cut and needs no tool.
        let slot = if first_move && kind == BlockKind::Rapid && self.slot.is_none() {
            NO_SLOT
        } else {
            self.current_slot(loc)?
        };
        let mode = match self.opts.kinematics {
            KinematicsChoice::Joints => RotaryMode::Joints,
            KinematicsChoice::Tcp => RotaryMode::Tcp,
            KinematicsChoice::Auto => {
                if tcp_now {
                    RotaryMode::Tcp
                } else {
                    RotaryMode::Joints
                }
            }
        };
        let d_abc = end.abc - start.abc;
        let rotary_deg = d_abc.abs().max_element();
        let pts = self.chord_points(c, loc)?;
        let length_mm: f64 = pts.windows(2).map(|w| (w[1].0 - w[0].0).length()).sum();
        let first_index = self.out.program.moves.len();
        let tool = self.out.tools.get(usize::from(slot)).map(|t| (t.number, t.length_mm, t.cutter.radius_mm));
        let delta = tool.map_or(0.0, |(_, len, _)| len - self.offset.z);
        if let Some((number, len, _)) = tool
            && (delta - self.noted_delta[usize::from(slot)]).abs() > LENGTH_MATCH_MM
        {
            self.noted_delta[usize::from(slot)] = delta;
            let text = if delta.abs() <= LENGTH_MATCH_MM {
                format!("tool {number} now has its own length offset ({len} mm)")
            } else {
                format!(
                    "tool {number} is {len} mm long but the length offset in force is {} mm: its tip runs {} mm {} the programmed point (G43 H{number} missing?)",
                    self.offset.z,
                    delta.abs(),
                    if delta > 0.0 { "beyond" } else { "short of" },
                )
            };
            self.note(loc, text);
        }
        let rapid = kind == BlockKind::Rapid;
        let line = loc.line as usize;
        let mut rotary = None;
        let mut end_tip = end.xyz - delta * DVec3::Z;
        // The first motion comes from an unknown place (a leading rapid is not cut).
        let cut = slot != NO_SLOT && !(first_move && rapid);
        match self.opts.machine {
            None => {
                if rotary_deg > ROTARY_STILL_DEG {
                    if self.rotary_without_machine == 0 {
                        self.first_rotary_without_machine = loc;
                    }
                    self.rotary_without_machine += 1;
                }
                if cut {
                    for w in pts.windows(2) {
                        let (a, b) = (w[0].0 - delta * DVec3::Z, w[1].0 - delta * DVec3::Z);
                        self.out.program.push(SimMove { kind: MoveKind::Line { from: a, to: b }, line, rapid })?;
                    }
                }
            }
            Some(setup) => {
                if !self.unused_rotary_noted {
                    let moved: Vec<char> = setup
                        .unused()
                        .into_iter()
                        .filter(|&i| d_abc[i].abs() > ROTARY_STILL_DEG || end.abc[i].abs() > ROTARY_STILL_DEG)
                        .map(|i| ['A', 'B', 'C'][i])
                        .collect();
                    if !moved.is_empty() {
                        self.unused_rotary_noted = true;
                        let list: String = moved.iter().collect();
                        self.note(
                            loc,
                            format!(
                                "the {} machine has no {list} axis: {list} words are left out (choose another --machine)",
                                setup.name()
                            ),
                        );
                    }
                }
                let mut machine = setup.machine;
                let a0 = setup.rotary_rad(start.abc);
                let a1 = setup.rotary_rad(end.abc);
                let ang = |f: f64| [a0[0] + f * (a1[0] - a0[0]), a0[1] + f * (a1[1] - a0[1])];
                let axis_at = |m: &Machine, a: [f64; 2]| {
                    m.pose_from_joints(&Joints { xyz_mm: DVec3::ZERO, rotary_rad: a }).axis_in_workpiece
                };
                let turns = (a1[0] - a0[0]).abs().max((a1[1] - a0[1]).abs()) > ROTARY_STILL_DEG.to_radians();
                // Joints of a controlled point at given angles, the tool Δ longer.
                let joints_of = |m: &Machine, p: DVec3, a: [f64; 2]| -> Joints {
                    match mode {
                        RotaryMode::Tcp => m.joints_at_angles(p - delta * axis_at(m, a), a),
                        RotaryMode::Joints => Joints { xyz_mm: p, rotary_rad: a },
                    }
                };
                // Head machines: the tool reaches Δ further from the head axis; table
                // machines: Δ lower along machine Z (the shift below).
                if mode == RotaryMode::Joints && machine.kind.uses_tool_length() {
                    machine.tool_length_mm += delta;
                }
                let shift = if mode == RotaryMode::Joints && !machine.kind.uses_tool_length() {
                    delta * DVec3::Z
                } else {
                    DVec3::ZERO
                };
                let m = machine;
                let j_end = {
                    let mut j = joints_of(&m, end.xyz, a1);
                    j.xyz_mm -= shift;
                    j
                };
                end_tip = m.pose_from_joints(&j_end).tip_in_workpiece;
                if turns {
                    let mut j0 = joints_of(&m, start.xyz, a0);
                    j0.xyz_mm -= shift;
                    let tip_from = m.pose_from_joints(&j0).tip_in_workpiece;
                    // Feed lines only: a rapid's path does not shape the part (and the first
                    // motion comes from an unknown place); arcs and splines are not measured.
                    let measured = kind == BlockKind::Line && !first_move;
                    let (nl, tau, worst) =
                        if measured { nonlinear_error(&m, &j0, &j_end) } else { (f64::NAN, 0.0, tip_from) };
                    if matches!(kind, BlockKind::Arc | BlockKind::Spline) {
                        self.out.rotary_curves += 1;
                    }
                    rotary = Some(RotaryBlock {
                        mode,
                        from: j0,
                        to: j_end,
                        tip_from,
                        tip_to: end_tip,
                        nonlinear_mm: measured.then_some(nl),
                        at_tau: tau,
                        worst_tip: worst,
                    });
                }
                if cut {
                    for w in pts.windows(2) {
                        let (p0, f0) = w[0];
                        let (p1, f1) = w[1];
                        let (b0, b1) = (ang(f0), ang(f1));
                        let mut j0 = joints_of(&m, p0, b0);
                        let mut j1 = joints_of(&m, p1, b1);
                        j0.xyz_mm -= shift;
                        j1.xyz_mm -= shift;
                        let piece_turns =
                            (b1[0] - b0[0]).abs().max((b1[1] - b0[1]).abs()) > ROTARY_STILL_DEG.to_radians();
                        let axis = axis_at(&m, b0);
                        if !piece_turns && axis.z >= VERTICAL_AXIS_Z {
                            let (a, b) =
                                (m.pose_from_joints(&j0).tip_in_workpiece, m.pose_from_joints(&j1).tip_in_workpiece);
                            self.out.program.push(SimMove { kind: MoveKind::Line { from: a, to: b }, line, rapid })?;
                        } else if mode == RotaryMode::Tcp && piece_turns {
                            self.tcp_pieces(&m, (p0, b0), (p1, b1), delta, line, rapid)?;
                        } else {
                            self.out.program.push(SimMove {
                                kind: MoveKind::Joints { machine: m, from: j0, to: j1 },
                                line,
                                rapid,
                            })?;
                        }
                    }
                }
            }
        }
        // Time and totals.
        let time_min = match feed {
            None => None,
            Some(f) => {
                let travel = if length_mm > 0.0 { length_mm } else { rotary_deg };
                let t = match f.mode {
                    FeedMode::PerMinute => travel / f.rate,
                    FeedMode::InverseTime => 1.0 / f.rate,
                    FeedMode::PerRevolution => travel / (f.rate * f.spindle_rpm.abs()),
                };
                (t.is_finite() && t >= 0.0).then_some(t)
            }
        };
        if slot != NO_SLOT
            && let Some(t) = self.out.tools.get_mut(usize::from(slot))
        {
            if rapid {
                t.rapid_blocks += 1;
                t.rapid_mm += length_mm;
            } else {
                t.feed_blocks += 1;
                t.feed_mm += length_mm;
                match time_min {
                    Some(m) => t.feed_min += m,
                    None => t.untimed_blocks += 1,
                }
            }
        }
        if !rapid && cut {
            let r = tool.map_or(0.0, |(_, _, r)| r);
            let moves = &self.out.program.moves[first_index..];
            let ends: Vec<DVec3> = moves.iter().flat_map(move_ends).collect();
            for p in ends {
                let lo = p - DVec3::new(r, r, 0.0);
                let hi = p + DVec3::new(r, r, 0.0);
                self.out.cut_box = Some(match self.out.cut_box {
                    None => (lo, hi),
                    Some((a, b)) => (a.min(lo), b.max(hi)),
                });
            }
        }
        let feed = feed.unwrap_or_default();
        self.out.blocks.push(ProgramBlock {
            loc,
            kind,
            slot,
            feed,
            length_mm,
            rotary_deg,
            time_min,
            moves: (
                u32::try_from(first_index).unwrap_or(u32::MAX),
                u32::try_from(self.out.program.moves.len()).unwrap_or(u32::MAX),
            ),
            end_tip,
            rotary,
            removed_mm3: 0.0,
        });
        self.pos = end;
        Ok(())
    }

    /// A TCP move from (p0, angles b0) to (p1, b1): the tip straight, the angles linear, cut
    /// as joint moves whose tip stays within the chord tolerance of the straight line.
    fn tcp_pieces(
        &mut self,
        m: &Machine,
        (p0, b0): (DVec3, [f64; 2]),
        (p1, b1): (DVec3, [f64; 2]),
        delta: f64,
        line: usize,
        rapid: bool,
    ) -> Result<(), SimError> {
        let at = |f: f64| -> (DVec3, Joints) {
            let a = [b0[0] + f * (b1[0] - b0[0]), b0[1] + f * (b1[1] - b0[1])];
            let axis = m.pose_from_joints(&Joints { xyz_mm: DVec3::ZERO, rotary_rad: a }).axis_in_workpiece;
            let tip = p0.lerp(p1, f) - delta * axis;
            (tip, m.joints_at_angles(tip, a))
        };
        // The middle deviation of n equal pieces: the sagitta shrinks as 1/n².
        let deviation = |n: usize| -> f64 {
            (0..n)
                .map(|k| {
                    let (f0, f1) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
                    let (_, j0) = at(f0);
                    let (_, j1) = at(f1);
                    let (tip, _) = at(0.5 * (f0 + f1));
                    (m.pose_from_joints(&j0.lerp(&j1, 0.5)).tip_in_workpiece - tip).length()
                })
                .fold(0.0, f64::max)
        };
        let tol = self.opts.chord_tol_mm;
        let d1 = deviation(1);
        let mut n = if d1 > tol { ((d1 / tol).sqrt().ceil() as usize).clamp(1, MAX_TCP_PIECES) } else { 1 };
        let mut d = if n == 1 { d1 } else { deviation(n) };
        while d > tol && n < MAX_TCP_PIECES {
            n = (2 * n).min(MAX_TCP_PIECES);
            d = deviation(n);
        }
        self.out.program.note_chord_error(d);
        let mut prev = at(0.0).1;
        for k in 1..=n {
            let next = at(k as f64 / n as f64).1;
            self.out.program.push(SimMove {
                kind: MoveKind::Joints { machine: *m, from: prev, to: next },
                line,
                rapid,
            })?;
            prev = next;
        }
        Ok(())
    }

    /// Reads an interpreter's calls to its end (or an error), following tool-centre-point
    /// control through its reports ([`TcpWatch`]). `keep_going` is asked after each call
    /// (for progress and cancelling): false stops the reading. Returns whether it reached
    /// the end.
    ///
    /// # Errors
    /// The interpreter's error (its line and message), or the builder's ([`Self::push`]).
    pub fn read(
        &mut self,
        it: &mut Interpreter<'_>,
        mut keep_going: impl FnMut(&Interpreter<'_>) -> bool,
    ) -> Result<bool, SimError> {
        let mut watch = TcpWatch::default();
        while let Some(c) = it.next() {
            let c = c.map_err(|e| SimError::Program(e.to_string()))?;
            let tcp = watch.update(it.reports());
            if matches!(c, Canon::ToolLengthOffset { .. }) {
                watch.tool_offset();
            }
            self.push(&c, tcp)?;
            if !keep_going(it) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The program, with the notes of what was counted along the way.
    #[must_use]
    pub fn finish(mut self) -> CanonProgram {
        if self.rotary_without_machine > 0 {
            let n = self.rotary_without_machine;
            let loc = self.first_rotary_without_machine;
            self.note(
                loc,
                format!(
                    "{n} motion(s) turn a rotary axis (A, B or C) but no machine is given: the rotary motion is left out; give --machine (table-ac, table-bc, head-bc, head-a-table-c, wrap-a)"
                ),
            );
        }
        if self.out.rotary_curves > 0 {
            let n = self.out.rotary_curves;
            let loc = self
                .out
                .blocks
                .iter()
                .find(|b| b.rotary.is_some_and(|r| r.nonlinear_mm.is_none()))
                .map_or_else(Loc::default, |b| b.loc);
            self.note(
                loc,
                format!(
                    "{n} arc(s) or spline(s) turn a rotary axis: they are cut, their nonlinear error is not measured"
                ),
            );
        }
        self.out
    }
}

impl CanonProgram {
    /// The blocks that turn a rotary axis and whose nonlinear error exceeds `tol_mm`.
    pub fn over_tolerance(&self, tol_mm: f64) -> impl Iterator<Item = &ProgramBlock> {
        self.blocks.iter().filter(move |b| b.rotary.and_then(|r| r.nonlinear_mm).is_some_and(|e| e > tol_mm))
    }

    /// Rays the run would visit (each tool's moves against its own radius), for a refusal
    /// before it starts.
    fn estimate_visits(&self, sim: &mut Simulation) -> f64 {
        let mut total = 0.0;
        let mut current = NO_SLOT;
        for b in &self.blocks {
            if b.slot == NO_SLOT {
                continue;
            }
            if b.slot != current {
                current = b.slot;
                if let Some(t) = self.tools.get(usize::from(current)) {
                    sim.set_tool(&t.cutter, current);
                }
            }
            let (i, j) = (b.moves.0 as usize, b.moves.1 as usize);
            total +=
                self.program.moves.get(i..j).map_or(0.0, |ms| ms.iter().map(|m| sim.estimate_move_visits(m)).sum());
        }
        total
    }

    /// Runs the program on `sim`, switching the cutter at each tool change, and adds each
    /// block's and each tool's removed volume. `keep_going` is called after each block with
    /// the moves done; returning false stops the run (cancelled). Returns whether it ran to
    /// the end.
    ///
    /// # Errors
    /// [`SimError::TooMuchWork`] when the program would visit more than
    /// [`super::MAX_RAY_VISITS`] rays, before any move is cut.
    pub fn run(&mut self, sim: &mut Simulation, mut keep_going: impl FnMut(usize) -> bool) -> Result<bool, SimError> {
        let visits = self.estimate_visits(sim);
        if !(visits <= super::MAX_RAY_VISITS) {
            return Err(SimError::TooMuchWork { visits, max: super::MAX_RAY_VISITS });
        }
        let mut current = NO_SLOT;
        for k in 0..self.blocks.len() {
            let b = self.blocks[k];
            if b.slot == NO_SLOT {
                continue;
            }
            if b.slot != current {
                current = b.slot;
                if let Some(t) = self.tools.get(usize::from(current)) {
                    sim.set_tool(&t.cutter, current);
                }
            }
            let mut removed = 0.0;
            for i in b.moves.0..b.moves.1 {
                if let Some(m) = self.program.moves.get(i as usize) {
                    removed += sim.apply(m);
                }
            }
            self.blocks[k].removed_mm3 = removed;
            if let Some(t) = self.tools.get_mut(usize::from(b.slot)) {
                t.removed_mm3 += removed;
            }
            if !keep_going(b.moves.1 as usize) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The workpiece CAMotics makes automatically for this program: the box of the feed
    /// moves' tool sweeps ([`Self::cut_box`]) with its top at z = 0, at least 2 mm thick,
    /// widened by `margin_percent` of its size in x and y on both sides and below (CAMotics'
    /// `Workpiece::update`). A program that cuts only above z = 0 (a part whose zero is not
    /// its top, a rotary job) gets its top at the highest feed tip instead. `None` without
    /// feed moves or when the box is empty.
    #[must_use]
    pub fn automatic_stock(&self, margin_percent: f64) -> Option<[f64; 6]> {
        let (lo, hi) = self.cut_box?;
        let mut lo = lo;
        let top = if lo.z < 0.0 { 0.0 } else { hi.z };
        let hi = DVec3::new(hi.x, hi.y, top);
        if hi.z - lo.z < 2.0 {
            lo.z -= 2.0;
        }
        let size = hi - lo;
        if !(size.x > 0.0 && size.y > 0.0 && size.z > 0.0) {
            return None;
        }
        let m = size * (margin_percent.max(0.0) / 100.0);
        Some([lo.x - m.x, lo.y - m.y, lo.z - m.z, hi.x + m.x, hi.y + m.y, hi.z])
    }
}
