//! Canned cycles — G73, G74, G81–G89 with G98/G99, L repeats, G90/G91 and the three planes —
//! expanded into the moves LinuxCNC 2.9 makes for them.
//!
//! The rules are LinuxCNC's (`src/emc/rs274ngc/interp_cycles.cc`, `convert_cycle`,
//! `convert_cycle_xy/_yz/_zx` and the per-cycle functions; the G-code manual's sections
//! "G80-G89 Canned Cycles", "Preliminary and In-Between Motion", "Sticky Words", "Repeat
//! Cycle", "G98, G99"), checked move for move against its standalone interpreter `rs274`
//! (see the tests). In the plane's own axes — (a, b) in the plane and n along its normal:
//! (X, Y | Z) for G17, (Z, X | Y) for G18, (Y, Z | X) for G19 ([`Plane::axes`]):
//!
//! - **Levels.** R is the retract level and the n word (Z in G17) the bottom. The *initial
//!   level* is n of the position where a series of contiguous cycle blocks began
//!   ([`CycleState::initial_level`]); G98 retracts to it ("old Z") when it is above R,
//!   otherwise — and always with G99 — to R. R below the bottom is refused.
//! - **Distance mode.** In G90 a, b, R and the bottom are absolute. In G91 a and b are
//!   increments applied at every repeat (from the current position), R is an increment from the
//!   *initial level* and the bottom an increment from R.
//! - **Preliminary motion.** When the initial level is below R, n rapids up to R first (once).
//!   Each repeat then rapids in the plane to (a, b) — at the current level on the first repeat
//!   when that is above R, else at the clear level — and down to R if it is not there yet.
//! - **Sticky words.** R, the bottom, Q (G73/G83) and I J K (G87) carry over while the *same*
//!   cycle continues; a new cycle code needs them again. P is kept by every cycle and read by
//!   G74/G84 without any check (LinuxCNC's `cycle_p`, zero at first); L is never sticky.
//!
//! The moves are in the **program frame** (before G92/G5x offsets and XY rotation) in **mm**;
//! the executor maps them to the machine frame. Internally every length is computed in
//! program units (`CycleInput::unit_mm`), in LinuxCNC's order of operations, so that a peck
//! count or a retract level decided by a tie comes out as it does in `rs274`.
//!
//! Where this departs from LinuxCNC (each refused with a message, where LinuxCNC runs):
//! L beyond [`MAX_CYCLE_REPEATS`], pecks beyond [`MAX_CYCLE_PECKS`], a block expanding to
//! more than [`MAX_CYCLE_MOVES`] moves, a negative dwell P, and polar words (`@`, `^`)
//! outside G17 (LinuxCNC's G18/G19 cycles ignore them). Every refusal comes before any move,
//! where LinuxCNC may already have made the preliminary moves. G74/G84 in G18 and G19 are
//! *reproduced* with LinuxCNC's exchanged axes (its `convert_cycle_g74_g84` passes the
//! coordinates in the wrong order for those planes) and flagged with
//! [`CycleNote::TappingAxesExchanged`] so the executor can warn once.

use glam::DVec3;
use thiserror::Error;

use super::INTEGER_SLACK;
use super::state::MM_PER_INCH;
use crate::gcode::path::Plane;
pub use crate::numerics::limits::{MAX_CYCLE_MOVES, MAX_CYCLE_PECKS, MAX_CYCLE_REPEATS};

#[cfg(test)]
mod tests;

/// LinuxCNC 2.9's back-off before each G73 peck and above the last depth after a G83
/// retract: 0.010 inch (`G83_RAPID_DELTA`), also used as 0.254 mm in metric programs.
pub const PECK_CLEARANCE_INCH: f64 = 0.010;

/// A G number within this of a whole number of tenths is that cycle's code (`81.0000001`
/// is G81).
const G_NUMBER_SLACK: f64 = 1e-6;

/// A program unit within this (mm per unit) of 25.4 is the inch.
const UNIT_MATCH_SLACK: f64 = 1e-12;

/// The canned cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CycleKind {
    /// Drilling with chip breaking: pecks of Q, backing off 0.010 in between.
    G73,
    /// Left-hand tapping (spindle counter-clockwise), dwell P, feed out.
    G74,
    /// Drilling: feed to the bottom, rapid out.
    G81,
    /// Drilling with a dwell P at the bottom.
    G82,
    /// Peck drilling: pecks of Q, rapid out to R after each.
    G83,
    /// Right-hand tapping (spindle clockwise), dwell P, feed out.
    G84,
    /// Boring, feed out.
    G85,
    /// Boring, dwell P, spindle stop, rapid out.
    G86,
    /// Back boring with an oriented spindle: I J offsets, K the top of the counterbore.
    G87,
    /// Boring, dwell P, spindle stop, program stop for a manual retract.
    G88,
    /// Boring, dwell P, feed out.
    G89,
}

impl CycleKind {
    /// All cycles, in G-code order.
    pub const ALL: [Self; 11] = [
        Self::G73,
        Self::G74,
        Self::G81,
        Self::G82,
        Self::G83,
        Self::G84,
        Self::G85,
        Self::G86,
        Self::G87,
        Self::G88,
        Self::G89,
    ];

    /// The cycle of a G number (`81.0` → G81); `None` for other codes.
    #[must_use]
    pub fn from_g(number: f64) -> Option<Self> {
        let tenths = (number * 10.0).round();
        if (number * 10.0 - tenths).abs() > G_NUMBER_SLACK {
            return None;
        }
        Some(match tenths as i64 {
            730 => Self::G73,
            740 => Self::G74,
            810 => Self::G81,
            820 => Self::G82,
            830 => Self::G83,
            840 => Self::G84,
            850 => Self::G85,
            860 => Self::G86,
            870 => Self::G87,
            880 => Self::G88,
            890 => Self::G89,
            _ => return None,
        })
    }

    /// The G code as written: `G81`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::G73 => "G73",
            Self::G74 => "G74",
            Self::G81 => "G81",
            Self::G82 => "G82",
            Self::G83 => "G83",
            Self::G84 => "G84",
            Self::G85 => "G85",
            Self::G86 => "G86",
            Self::G87 => "G87",
            Self::G88 => "G88",
            Self::G89 => "G89",
        }
    }

    /// Whether the cycle dwells P seconds and needs P on its first block (G82, G86, G88,
    /// G89). G74/G84 also dwell P but take the last P of any cycle when it is missing.
    fn needs_p(self) -> bool {
        matches!(self, Self::G82 | Self::G86 | Self::G88 | Self::G89)
    }
}

/// The retract mode (group 10).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Retract {
    /// G98: back to the initial level when it is above R.
    OldZ,
    /// G99: back to R (LinuxCNC's default).
    #[default]
    RPlane,
}

/// Which way the spindle turns when the cycle starts (M3, M4, M5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SpindleDir {
    /// M5 (or never started).
    #[default]
    Stopped,
    /// M3.
    Clockwise,
    /// M4.
    CounterClockwise,
}

/// The words of one cycle block that the cycle reads, as written (absolute or incremental per
/// the distance mode), lengths already converted to **mm** (X, Y, Z, R, Q, I, J, K and the
/// polar radius `@`), P in seconds, L a count, the polar angle `^` in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CycleWords {
    /// X (mm).
    pub x: Option<f64>,
    /// Y (mm).
    pub y: Option<f64>,
    /// Z (mm).
    pub z: Option<f64>,
    /// R, the retract level (mm).
    pub r: Option<f64>,
    /// Q, the peck depth of G73/G83 (mm).
    pub q: Option<f64>,
    /// P, the dwell (s).
    pub p: Option<f64>,
    /// I, the G87 offset along X (mm).
    pub i: Option<f64>,
    /// J, the G87 offset along Y (mm).
    pub j: Option<f64>,
    /// K, the G87 offset along Z (mm).
    pub k: Option<f64>,
    /// L, the number of repeats (as written; it must be a positive integer).
    pub l: Option<f64>,
    /// `@`, the polar radius (mm), G17 only.
    pub polar_radius: Option<f64>,
    /// `^`, the polar angle (degrees), G17 only.
    pub polar_angle_deg: Option<f64>,
    /// The first rotary-axis letter on the block (`A`, `B`, `C`), which a cycle refuses.
    pub rotary: Option<char>,
}

/// One canned-cycle block: the cycle, the modes it runs in and its words.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleInput {
    /// The cycle (the motion mode of the block).
    pub kind: CycleKind,
    /// The selected plane.
    pub plane: Plane,
    /// The current position in the program frame (mm).
    pub position: DVec3,
    /// G91 (true) or G90.
    pub incremental: bool,
    /// G98 or G99.
    pub retract: Retract,
    /// Spindle direction in force (G74/G84/G86/G87/G88 check it and restore it).
    pub spindle: SpindleDir,
    /// The F in force, in any unit; zero when none was programmed (refused, as LinuxCNC does).
    pub feed_rate: f64,
    /// G93 inverse-time feed is in force (refused).
    pub inverse_time: bool,
    /// Cutter radius compensation (G41/G42/G41.1/G42.1) is on (refused).
    pub cutter_comp: bool,
    /// The length of one program unit (mm): 1 under G21, 25.4 under G20. Lengths are
    /// computed in program units in LinuxCNC's order and converted back.
    pub unit_mm: f64,
    /// The block's words.
    pub words: CycleWords,
}

/// What a cycle does, in order. Positions are in the program frame (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CycleMove {
    /// `STRAIGHT_TRAVERSE` to a point. Zero-length traverses are kept, as `rs274` prints them.
    Rapid(DVec3),
    /// `STRAIGHT_FEED` to a point, at the feed in force.
    Feed(DVec3),
    /// `DWELL`.
    Dwell {
        /// Seconds.
        seconds: f64,
    },
    /// `STOP_SPINDLE_TURNING`.
    SpindleStop,
    /// `START_SPINDLE_CLOCKWISE` (true) or `_COUNTERCLOCKWISE` (false), at the speed in force.
    SpindleStart {
        /// M3 (true) or M4 (false).
        clockwise: bool,
    },
    /// `ORIENT_SPINDLE` (G87) to an angle.
    SpindleOrient {
        /// Degrees (LinuxCNC's G87 always orients to 0).
        angle_deg: f64,
    },
    /// `PROGRAM_STOP` (G88): the operator retracts the spindle by hand.
    ProgramStop,
    /// Not a canonical call: where LinuxCNC assumes the operator has taken the tool during
    /// the G88 stop (the clear level above the hole). `rs274` prints nothing for it; a
    /// viewer draws it as a rapid so the next move does not start from the hole's bottom.
    OperatorRetract(DVec3),
}

/// Something about a cycle the executor should report (once).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CycleNote {
    /// G74/G84 in G18 or G19: LinuxCNC 2.9 feeds to a point whose coordinates are exchanged
    /// (its tapping cycle passes them in the XY order for every plane); the moves are shown
    /// as LinuxCNC makes them.
    TappingAxesExchanged,
}

impl std::fmt::Display for CycleNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::TappingAxesExchanged => f.write_str(
                "LinuxCNC 2.9 taps (G74/G84) in the G18 and G19 planes along exchanged axes; the moves are shown as LinuxCNC makes them — tap in G17 instead",
            ),
        }
    }
}

/// The result of one cycle block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleOutcome {
    /// The position the interpreter holds after the block (program frame, mm): the last hole's
    /// (a, b) at the clear level — also after G88, whose tool the operator took out by hand.
    pub end: DVec3,
    /// A note to report, if any.
    pub note: Option<CycleNote>,
}

/// The sticky values LinuxCNC keeps between cycle blocks (`cycle_r`, `cycle_cc`, `cycle_p`,
/// `cycle_q`, `cycle_i/j/k`, `cycle_il`), in **program units** as written, as LinuxCNC keeps
/// them, and the cycle mode in force.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CycleState {
    /// The cycle of the last cycle block, while the motion mode is still that cycle.
    mode: Option<CycleKind>,
    /// The initial level (program units), set by the first block of a series of cycles.
    initial_level: Option<f64>,
    r: f64,
    depth: f64,
    p: f64,
    q: f64,
    ijk: [f64; 3],
}

impl CycleState {
    /// No cycle yet: every sticky value zero, as LinuxCNC starts.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Leaves cycle mode: call it whenever a block executes a motion that is not a canned
    /// cycle (G0, G1, G2, G3, G5.x, G33, G38.x, G76, G80 — LinuxCNC's `convert_motion`). The
    /// next cycle block then needs its R and bottom again and takes a new initial level; P and
    /// Q keep their values, as in LinuxCNC.
    pub fn leave(&mut self) {
        self.mode = None;
        self.initial_level = None;
    }

    /// The cycle in force, if the motion mode is a cycle.
    #[must_use]
    pub fn mode(&self) -> Option<CycleKind> {
        self.mode
    }

    /// The initial (G98) level of the series of cycles in progress, in program units.
    #[must_use]
    pub fn initial_level(&self) -> Option<f64> {
        self.initial_level
    }
}

/// Why a cycle block was refused. Each message names the word and what to write.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CycleError {
    /// F is zero.
    #[error(
        "{kind} feeds at F0; program a feed rate F before or on the cycle block (LinuxCNC: cannot feed with zero feed rate)"
    )]
    ZeroFeed {
        /// The cycle.
        kind: &'static str,
    },
    /// G93 in force.
    #[error("{kind} cannot run in inverse-time feed (G93); select G94 before the cycle")]
    InverseTime {
        /// The cycle.
        kind: &'static str,
    },
    /// Cutter compensation on.
    #[error("{kind} cannot run with cutter radius compensation on; cancel it with G40 before the cycle")]
    CutterComp {
        /// The cycle.
        kind: &'static str,
    },
    /// A rotary-axis word in the block.
    #[error("an {letter} word cannot be in a canned cycle block ({kind}); move the rotary axis on a block of its own")]
    RotaryWord {
        /// The cycle.
        kind: &'static str,
        /// The letter.
        letter: char,
    },
    /// No R on the first block of a cycle.
    #[error(
        "{kind} needs R, the retract level; give R on this block (R carries over only while the same cycle continues)"
    )]
    MissingR {
        /// The cycle.
        kind: &'static str,
    },
    /// No bottom on the first block of a cycle.
    #[error(
        "{kind} needs {letter}, the bottom of the hole, on its first block ({plane}: the cycle drills along {letter})"
    )]
    MissingDepth {
        /// The cycle.
        kind: &'static str,
        /// The letter along the plane's normal.
        letter: char,
        /// The plane code.
        plane: &'static str,
    },
    /// R below the bottom.
    #[error(
        "{kind}: R {r_mm} mm is below the bottom {letter} {bottom_mm} mm (LinuxCNC: R less than {letter} in cycle); the cycle feeds from R down to {letter}, so R must be at or above it"
    )]
    RBelowBottom {
        /// The cycle.
        kind: &'static str,
        /// The normal-axis letter.
        letter: char,
        /// R as an absolute level (mm).
        r_mm: f64,
        /// The bottom as an absolute level (mm).
        bottom_mm: f64,
    },
    /// L is not a positive integer.
    #[error(
        "L{value} is not a number of repeats; write a positive whole number, e.g. L1 (LinuxCNC refuses L0 and negative L)"
    )]
    BadRepeat {
        /// As written.
        value: f64,
    },
    /// L above the cap.
    #[error(
        "L{value} repeats are more than the {cap} a cycle block may ask for here; split the holes over several blocks"
    )]
    TooManyRepeats {
        /// As written.
        value: f64,
        /// The cap.
        cap: u32,
    },
    /// L on G74, which LinuxCNC 2.9 refuses.
    #[error("G74 takes no L in LinuxCNC 2.9 (\"L word with no … canned cycle\"); repeat the G74 block instead")]
    RepeatOnG74,
    /// Q missing on the first G73/G83 block.
    #[error("{kind} needs Q, the peck depth (mm), on its first block")]
    MissingQ {
        /// The cycle.
        kind: &'static str,
    },
    /// Q not positive.
    #[error("{kind}: peck depth Q{q_mm} mm must be positive")]
    BadQ {
        /// The cycle.
        kind: &'static str,
        /// Q (mm).
        q_mm: f64,
    },
    /// Too many pecks.
    #[error(
        "{kind}: a peck depth of Q{q_mm} mm over {depth_mm} mm makes about {pecks} pecks, more than the {cap} a hole may have here; give a larger Q"
    )]
    TooManyPecks {
        /// The cycle.
        kind: &'static str,
        /// Q (mm).
        q_mm: f64,
        /// From R to the bottom (mm).
        depth_mm: f64,
        /// Estimated pecks.
        pecks: f64,
        /// The cap.
        cap: usize,
    },
    /// The block would expand to too many moves.
    #[error(
        "{kind} with L{repeats} expands to about {moves} moves, more than the {cap} one block may make; use fewer repeats or a larger Q"
    )]
    TooManyMoves {
        /// The cycle.
        kind: &'static str,
        /// L.
        repeats: u32,
        /// Estimated moves.
        moves: f64,
        /// The cap.
        cap: usize,
    },
    /// P missing on the first block of a dwelling cycle.
    #[error("{kind} needs P, the dwell at the bottom (seconds), on its first block; write P0 for none")]
    MissingP {
        /// The cycle.
        kind: &'static str,
    },
    /// P negative.
    #[error("{kind}: dwell P{p} must be zero or more seconds")]
    NegativeP {
        /// The cycle.
        kind: &'static str,
        /// P.
        p: f64,
    },
    /// G87 without I, J or K on its first block.
    #[error(
        "G87 needs {letter} on its first block: I and J offset the tool to slip through the hole, K is the top of the counterbore"
    )]
    MissingG87Word {
        /// The missing letter.
        letter: char,
    },
    /// Spindle not turning where it must.
    #[error("{kind} needs the spindle turning; start it with M3 (or M4) before the cycle")]
    SpindleStopped {
        /// The cycle.
        kind: &'static str,
    },
    /// Spindle turning the wrong way for tapping.
    #[error("{kind} taps with the spindle turning {want}; it turns the other way — program {code} before the cycle")]
    SpindleWrongWay {
        /// The cycle.
        kind: &'static str,
        /// "clockwise" or "counter-clockwise".
        want: &'static str,
        /// "M3" or "M4".
        code: &'static str,
    },
    /// Polar words outside G17.
    #[error(
        "{kind}: polar words (@, ^) in a canned cycle work in the G17 plane only; give {a}{b} coordinates in {plane}"
    )]
    PolarOutsideXy {
        /// The cycle.
        kind: &'static str,
        /// First in-plane letter.
        a: char,
        /// Second in-plane letter.
        b: char,
        /// The plane code.
        plane: &'static str,
    },
    /// Polar and X/Y together.
    #[error("{kind}: a polar word (@, ^) and {letter} in one block; give the position one way")]
    PolarWithAxis {
        /// The cycle.
        kind: &'static str,
        /// X or Y.
        letter: char,
    },
    /// Incremental polar motion at the origin.
    #[error("{kind}: incremental polar motion (G91 with @ or ^) is undefined at the origin; move off X0 Y0 first")]
    PolarAtOrigin {
        /// The cycle.
        kind: &'static str,
    },
    /// A length or count is not finite.
    #[error("{kind}: {letter}{value} is not a finite number")]
    NotFinite {
        /// The cycle.
        kind: &'static str,
        /// The word's letter.
        letter: char,
        /// What was given.
        value: f64,
    },
}

/// The G73/G83 back-off in program units: 0.010 in an inch program, 0.010 · 25.4 in a
/// metric one — the same products LinuxCNC forms.
fn peck_clearance(unit: f64) -> f64 {
    if (unit - MM_PER_INCH).abs() < UNIT_MATCH_SLACK { PECK_CLEARANCE_INCH } else { PECK_CLEARANCE_INCH * 25.4 / unit }
}

/// The letter of axis index 0, 1, 2.
fn axis_letter(i: usize) -> char {
    ['X', 'Y', 'Z'][i]
}

/// The point LinuxCNC's G74/G84 feeds to in each plane: its `convert_cycle_g74_g84` calls
/// the plane's feed function with (a, b, bottom) for G17 but with (bottom, a, b) for G19
/// and (b, bottom, a) for G18, which the feed function then maps as it maps (a, b, n).
fn tapping_point(plane: Plane, a: f64, b: f64, n: f64) -> DVec3 {
    match plane {
        Plane::Xy => DVec3::new(a, b, n),
        // (end1, end2, end3) = (bottom, a, b) → X = end3, Y = end1, Z = end2.
        Plane::Yz => DVec3::new(b, n, a),
        // (end1, end2, end3) = (b, bottom, a) → X = end2, Y = end3, Z = end1.
        Plane::Zx => DVec3::new(n, a, b),
    }
}

/// L as a count: LinuxCNC rounds a value within 1e-4 of an integer and refuses others, zero
/// and negatives.
fn repeats(kind: CycleKind, l: Option<f64>) -> Result<u32, CycleError> {
    let Some(value) = l else {
        return Ok(1);
    };
    if kind == CycleKind::G74 {
        return Err(CycleError::RepeatOnG74);
    }
    if !value.is_finite() {
        return Err(CycleError::BadRepeat { value });
    }
    let floor = value.floor();
    let n = if value - floor > 1.0 - INTEGER_SLACK {
        floor + 1.0
    } else if value - floor > INTEGER_SLACK {
        return Err(CycleError::BadRepeat { value });
    } else {
        floor
    };
    if n < 1.0 {
        return Err(CycleError::BadRepeat { value });
    }
    if n > f64::from(MAX_CYCLE_REPEATS) {
        return Err(CycleError::TooManyRepeats { value, cap: MAX_CYCLE_REPEATS });
    }
    Ok(n as u32)
}

/// The values one block runs with, in program units, resolved from its words and the
/// sticky state, before any move.
struct Plan {
    /// Retract level R (absolute).
    r: f64,
    /// Bottom (absolute).
    bottom: f64,
    /// First hole position before the first increment (a, b).
    a: f64,
    b: f64,
    /// Per-repeat increments (a, b) in G91.
    inc_a: f64,
    inc_b: f64,
    /// Per-repeat polar increments in G91 (radius, angle in radians).
    inc_radius: f64,
    inc_theta: f64,
    repeats: u32,
    /// Dwell (s).
    p: f64,
    /// Peck depth.
    q: f64,
    /// G87: offsets (a, b) and the counterbore top (absolute).
    offset_a: f64,
    offset_b: f64,
    middle: f64,
    /// The raw sticky values to keep.
    r_word: f64,
    depth_word: f64,
    ijk: [f64; 3],
}

/// Expands one canned-cycle block into `out` (appended) and updates the sticky state.
///
/// # Errors
/// A [`CycleError`] naming the missing or wrong word; nothing is appended and the state is
/// unchanged then.
pub fn expand(
    input: &CycleInput,
    sticky: &mut CycleState,
    out: &mut Vec<CycleMove>,
) -> Result<CycleOutcome, CycleError> {
    let kind = input.kind;
    let name = kind.name();
    let unit = if input.unit_mm > 0.0 && input.unit_mm.is_finite() { input.unit_mm } else { 1.0 };
    let w = &input.words;
    for (letter, v) in [
        ('X', w.x),
        ('Y', w.y),
        ('Z', w.z),
        ('R', w.r),
        ('Q', w.q),
        ('P', w.p),
        ('I', w.i),
        ('J', w.j),
        ('K', w.k),
        ('@', w.polar_radius),
        ('^', w.polar_angle_deg),
    ] {
        if let Some(value) = v
            && !value.is_finite()
        {
            return Err(CycleError::NotFinite { kind: name, letter, value });
        }
    }
    if input.feed_rate == 0.0 {
        return Err(CycleError::ZeroFeed { kind: name });
    }
    if input.inverse_time {
        return Err(CycleError::InverseTime { kind: name });
    }
    if input.cutter_comp {
        return Err(CycleError::CutterComp { kind: name });
    }
    if let Some(letter) = w.rotary {
        return Err(CycleError::RotaryWord { kind: name, letter });
    }
    let same = sticky.mode == Some(kind);
    let plan = plan(input, sticky, unit, same)?;
    spindle_check(kind, input.spindle)?;
    let per_hole = moves_per_hole(kind, &plan, unit)?;
    let moves = per_hole * f64::from(plan.repeats) + 1.0;
    if moves > MAX_CYCLE_MOVES as f64 {
        return Err(CycleError::TooManyMoves {
            kind: name,
            repeats: plan.repeats,
            moves: moves.round(),
            cap: MAX_CYCLE_MOVES,
        });
    }

    // Everything is checked: make the moves (program units until `emit`).
    let inn = input.plane.axes().2;
    let pos = input.position / unit;
    let mut current_cc = pos[inn];
    let mut old_cc = sticky.initial_level.unwrap_or(current_cc);
    let initial_level = old_cc;
    let r = plan.r;
    let start = out.len();
    let to_mm = |a: f64, b: f64, n: f64| input.plane.join(a, b, n) * unit;
    if old_cc < r {
        let mut p = pos;
        p[inn] = r;
        out.push(CycleMove::Rapid(p * unit));
        old_cc = r;
        current_cc = r;
    }
    let clear = if input.retract == Retract::RPlane { r } else { old_cc };
    let (mut a, mut b) = (plan.a, plan.b);
    let mut note = None;
    for rep in 0..plan.repeats {
        a += plan.inc_a;
        b += plan.inc_b;
        if plan.inc_radius != 0.0 {
            if a == 0.0 && b == 0.0 {
                out.truncate(start);
                return Err(CycleError::PolarAtOrigin { kind: name });
            }
            let theta = b.atan2(a);
            let radius = b.hypot(a) + plan.inc_radius;
            (a, b) = (radius * theta.cos(), radius * theta.sin());
        }
        if plan.inc_theta != 0.0 {
            if a == 0.0 && b == 0.0 {
                out.truncate(start);
                return Err(CycleError::PolarAtOrigin { kind: name });
            }
            let theta = b.atan2(a) + plan.inc_theta;
            let radius = b.hypot(a);
            (a, b) = (radius * theta.cos(), radius * theta.sin());
        }
        if rep == 0 && current_cc > r {
            out.push(CycleMove::Rapid(to_mm(a, b, current_cc)));
            out.push(CycleMove::Rapid(to_mm(a, b, r)));
        } else {
            out.push(CycleMove::Rapid(to_mm(a, b, clear)));
            if clear > r {
                out.push(CycleMove::Rapid(to_mm(a, b, r)));
            }
        }
        let feed = |n: f64| CycleMove::Feed(to_mm(a, b, n));
        let rapid = |n: f64| CycleMove::Rapid(to_mm(a, b, n));
        let bottom = plan.bottom;
        match kind {
            CycleKind::G81 => {
                out.push(feed(bottom));
                out.push(rapid(clear));
            }
            CycleKind::G82 => {
                out.push(feed(bottom));
                out.push(CycleMove::Dwell { seconds: plan.p });
                out.push(rapid(clear));
            }
            CycleKind::G73 | CycleKind::G83 => {
                let back_off = peck_clearance(unit);
                let mut depth = r - plan.q;
                while depth > bottom {
                    out.push(feed(depth));
                    if kind == CycleKind::G83 {
                        out.push(rapid(r));
                    }
                    out.push(rapid(depth + back_off));
                    depth -= plan.q;
                }
                out.push(feed(bottom));
                out.push(rapid(clear));
            }
            CycleKind::G74 | CycleKind::G84 => {
                let right = kind == CycleKind::G84;
                let tap = |n: f64| CycleMove::Feed(tapping_point(input.plane, a, b, n) * unit);
                out.push(tap(bottom));
                out.push(CycleMove::SpindleStop);
                out.push(CycleMove::SpindleStart { clockwise: !right });
                out.push(CycleMove::Dwell { seconds: plan.p });
                out.push(tap(clear));
                out.push(CycleMove::SpindleStop);
                out.push(CycleMove::SpindleStart { clockwise: right });
                if input.plane != Plane::Xy {
                    note = Some(CycleNote::TappingAxesExchanged);
                }
            }
            CycleKind::G85 => {
                out.push(feed(bottom));
                out.push(feed(r));
                out.push(rapid(clear));
            }
            CycleKind::G86 => {
                out.push(feed(bottom));
                out.push(CycleMove::Dwell { seconds: plan.p });
                out.push(CycleMove::SpindleStop);
                out.push(rapid(clear));
                out.push(CycleMove::SpindleStart { clockwise: input.spindle == SpindleDir::Clockwise });
            }
            CycleKind::G87 => {
                let (oa, ob) = (a + plan.offset_a, b + plan.offset_b);
                let cw = input.spindle == SpindleDir::Clockwise;
                out.push(CycleMove::Rapid(to_mm(oa, ob, r)));
                out.push(CycleMove::SpindleStop);
                out.push(CycleMove::SpindleOrient { angle_deg: 0.0 });
                out.push(CycleMove::Rapid(to_mm(oa, ob, bottom)));
                out.push(rapid(bottom));
                out.push(CycleMove::SpindleStart { clockwise: cw });
                out.push(feed(plan.middle));
                out.push(feed(bottom));
                out.push(CycleMove::SpindleStop);
                out.push(CycleMove::SpindleOrient { angle_deg: 0.0 });
                out.push(CycleMove::Rapid(to_mm(oa, ob, bottom)));
                out.push(CycleMove::Rapid(to_mm(oa, ob, clear)));
                out.push(rapid(clear));
                out.push(CycleMove::SpindleStart { clockwise: cw });
            }
            CycleKind::G88 => {
                out.push(feed(bottom));
                out.push(CycleMove::Dwell { seconds: plan.p });
                out.push(CycleMove::SpindleStop);
                out.push(CycleMove::ProgramStop);
                out.push(CycleMove::OperatorRetract(to_mm(a, b, clear)));
                out.push(CycleMove::SpindleStart { clockwise: input.spindle == SpindleDir::Clockwise });
            }
            CycleKind::G89 => {
                out.push(feed(bottom));
                out.push(CycleMove::Dwell { seconds: plan.p });
                out.push(feed(clear));
            }
        }
    }

    sticky.mode = Some(kind);
    sticky.initial_level = Some(initial_level);
    sticky.r = plan.r_word;
    sticky.depth = plan.depth_word;
    match kind {
        CycleKind::G73 | CycleKind::G83 => sticky.q = plan.q,
        CycleKind::G81 | CycleKind::G85 => {}
        CycleKind::G87 => sticky.ijk = plan.ijk,
        _ => sticky.p = plan.p,
    }
    Ok(CycleOutcome { end: to_mm(a, b, clear), note })
}

/// Resolves the block's words and the sticky values into the levels and positions the
/// cycle runs with (LinuxCNC's `convert_cycle` and `convert_cycle_xy` up to `CYCLE_MACRO`).
fn plan(input: &CycleInput, sticky: &CycleState, unit: f64, same: bool) -> Result<Plan, CycleError> {
    let kind = input.kind;
    let name = kind.name();
    let w = &input.words;
    let (ia, ib, inn) = input.plane.axes();
    let axis = [w.x, w.y, w.z].map(|v| v.map(|v| v / unit));
    let pos = input.position / unit;

    let r_word = match w.r {
        Some(r) => r / unit,
        None if same => sticky.r,
        None => return Err(CycleError::MissingR { kind: name }),
    };
    let repeats = repeats(kind, w.l)?;
    let depth_word = match axis[inn] {
        Some(d) => d,
        None if same => sticky.depth,
        None => {
            return Err(CycleError::MissingDepth { kind: name, letter: axis_letter(inn), plane: input.plane.gcode() });
        }
    };
    let old_cc = sticky.initial_level.unwrap_or(pos[inn]);

    let polar = w.polar_radius.is_some() || w.polar_angle_deg.is_some();
    if polar {
        if input.plane != Plane::Xy {
            return Err(CycleError::PolarOutsideXy {
                kind: name,
                a: axis_letter(ia),
                b: axis_letter(ib),
                plane: input.plane.gcode(),
            });
        }
        if w.x.is_some() {
            return Err(CycleError::PolarWithAxis { kind: name, letter: 'X' });
        }
        if w.y.is_some() {
            return Err(CycleError::PolarWithAxis { kind: name, letter: 'Y' });
        }
    }
    let (mut a, mut b) = (pos[ia], pos[ib]);
    let (mut inc_a, mut inc_b, mut inc_radius, mut inc_theta) = (0.0, 0.0, 0.0, 0.0);
    let (r, bottom) = if input.incremental {
        inc_a = axis[ia].unwrap_or(0.0);
        inc_b = axis[ib].unwrap_or(0.0);
        inc_radius = w.polar_radius.map_or(0.0, |v| v / unit);
        inc_theta = w.polar_angle_deg.map_or(0.0, f64::to_radians);
        let r = r_word + old_cc;
        (r, r + depth_word)
    } else {
        if polar {
            let radius = w.polar_radius.map_or_else(|| pos.y.hypot(pos.x), |v| v / unit);
            let theta = w.polar_angle_deg.map_or_else(|| pos.y.atan2(pos.x), f64::to_radians);
            (a, b) = (radius * theta.cos(), radius * theta.sin());
        } else {
            a = axis[ia].unwrap_or(a);
            b = axis[ib].unwrap_or(b);
        }
        (r_word, depth_word)
    };
    if r < bottom {
        return Err(CycleError::RBelowBottom {
            kind: name,
            letter: axis_letter(inn),
            r_mm: r * unit,
            bottom_mm: bottom * unit,
        });
    }

    let mut p = sticky.p;
    if kind.needs_p() || matches!(kind, CycleKind::G74 | CycleKind::G84) {
        match w.p {
            Some(v) if v < 0.0 => return Err(CycleError::NegativeP { kind: name, p: v }),
            Some(v) => p = v,
            None if kind.needs_p() && !same => return Err(CycleError::MissingP { kind: name }),
            None => {}
        }
    }
    let mut q = sticky.q;
    if matches!(kind, CycleKind::G73 | CycleKind::G83) {
        match w.q {
            Some(v) => q = v / unit,
            None if !same => return Err(CycleError::MissingQ { kind: name }),
            None => {}
        }
        if !(q > 0.0) {
            return Err(CycleError::BadQ { kind: name, q_mm: q * unit });
        }
    }
    let mut ijk = sticky.ijk;
    let (mut offset_a, mut offset_b, mut middle) = (0.0, 0.0, 0.0);
    if kind == CycleKind::G87 {
        for (slot, (letter, v)) in ijk.iter_mut().zip([('I', w.i), ('J', w.j), ('K', w.k)]) {
            match v {
                Some(v) => *slot = v / unit,
                None if !same => return Err(CycleError::MissingG87Word { letter }),
                None => {}
            }
        }
        offset_a = ijk[ia];
        offset_b = ijk[ib];
        middle = if input.incremental { bottom + ijk[inn] } else { ijk[inn] };
    }
    Ok(Plan {
        r,
        bottom,
        a,
        b,
        inc_a,
        inc_b,
        inc_radius,
        inc_theta,
        repeats,
        p,
        q,
        offset_a,
        offset_b,
        middle,
        r_word,
        depth_word,
        ijk,
    })
}

/// LinuxCNC's spindle checks: tapping needs the matching direction, G86–G88 a turning spindle.
fn spindle_check(kind: CycleKind, spindle: SpindleDir) -> Result<(), CycleError> {
    let name = kind.name();
    match (kind, spindle) {
        (CycleKind::G74 | CycleKind::G84 | CycleKind::G86 | CycleKind::G87 | CycleKind::G88, SpindleDir::Stopped) => {
            Err(CycleError::SpindleStopped { kind: name })
        }
        (CycleKind::G84, SpindleDir::CounterClockwise) => {
            Err(CycleError::SpindleWrongWay { kind: name, want: "clockwise", code: "M3" })
        }
        (CycleKind::G74, SpindleDir::Clockwise) => {
            Err(CycleError::SpindleWrongWay { kind: name, want: "counter-clockwise", code: "M4" })
        }
        _ => Ok(()),
    }
}

/// Moves one repeat makes at most (for the work cap), refusing too many pecks first.
fn moves_per_hole(kind: CycleKind, plan: &Plan, unit: f64) -> Result<f64, CycleError> {
    let body = match kind {
        CycleKind::G73 | CycleKind::G83 => {
            let pecks = ((plan.r - plan.bottom) / plan.q).ceil();
            if !(pecks <= MAX_CYCLE_PECKS as f64) {
                return Err(CycleError::TooManyPecks {
                    kind: kind.name(),
                    q_mm: plan.q * unit,
                    depth_mm: (plan.r - plan.bottom) * unit,
                    pecks,
                    cap: MAX_CYCLE_PECKS,
                });
            }
            pecks * if kind == CycleKind::G83 { 3.0 } else { 2.0 } + 2.0
        }
        CycleKind::G87 => 14.0,
        _ => 7.0,
    };
    Ok(body + 2.0)
}
