//! Cutter radius compensation (G41/G42, G41.1/G42.1, G40) as LinuxCNC 2.9's interpreter
//! does it.
//!
//! The programmed path is the part's outline; with compensation on, the controlled point
//! (the cutter's centre, or a lathe tool's nose centre) runs one tool radius to the left
//! (G41) or right (G42) of it, as seen from the positive end of the plane's normal axis
//! looking at the plane, facing the direction of travel. Only the XY (G17) and XZ (G18)
//! planes have it; in XZ the in-plane axes are taken in the order (Z, X), as for G18 arcs.
//!
//! # How the path is built (the rules of LinuxCNC's `rs274ngc` interpreter)
//!
//! The rules and numbers below are those of LinuxCNC's `interp_convert.cc`
//! (`convert_cutter_compensation_on/off`, `convert_straight_comp1/comp2`,
//! `convert_arc_comp1/comp2`), `interp_arc.cc` (`arc_data_comp_ijk/r`) and `interp_queue.cc`
//! (the queue of delayed moves, `move_endpoint_and_flush`), at the version Debian 12 ships
//! (2.9.0~pre1, git f1270d6ed7; the same in substance on LinuxCNC's master of 2026); they
//! are restated here in our own terms.
//!
//! - **Delay.** The end of a compensated move depends on the move after it (an outside
//!   corner ends on the offset line, an inside corner stops short), so each compensated move
//!   is *held* until the next move with motion in the plane decides its end. Moves with no
//!   motion in the plane (a Z plunge in G17) are held behind it and share its end.
//!   Non-motion calls given to [`CutterComp::pass`] while moves are held (a dwell, a spindle
//!   change) are held too, so their order among the motions is kept.
//! - **Entry move** (the first move after G41/G42): a straight move from the current
//!   position P₀ to the programmed end P ends at P + r·n, n the unit normal of P₀→P on the
//!   compensation side; it must be longer than the radius. An arc may be the entry move: it
//!   ends at its programmed end moved one radius along the arc's radius (toward the centre
//!   when the tool is inside the arc), and its centre is moved along the same line so that
//!   the new arc still starts at P₀.
//! - **Following moves.** At the corner between the held move and the new one, the angle
//!   β between them decides (0.05 rad tolerance):
//!   - **convex** (the tool outside the corner, β > 0.05): the tool goes around the
//!     programmed corner point on an added arc of the tool radius (for a G0, a straight
//!     traverse to the arc's end instead);
//!   - **straight on** (|β| ≤ 0.05): no corner move;
//!   - **concave** (the tool inside the corner): the held move is shortened (or lengthened)
//!     to where it meets the new move's offset path — the intersection of two offset lines,
//!     of an offset line and an offset circle, or of two offset circles. A held straight move
//!     that would have to run backwards to get there, or a held arc that would have to turn
//!     further than it was programmed (by more than 0.0254 rad in a G21 program, 0.001 rad
//!     in G20), is a gouge and an error naming the line of the new move; so is an offset
//!     line or circle that the other offset path does not reach. A reversal after an arc
//!     with the tool outside it (the "h" and "m" shapes) is treated as concave. (A held
//!     *entry* move is checked against its offset normal, not its direction: LinuxCNC
//!     records it so.)
//! - **Arcs** with the tool inside need a radius larger than the tool's.
//! - **G40** ends the held moves where they are (no corner with the next move) and turns
//!   compensation off; the next move is an ordinary move from there to its programmed end,
//!   and must be straight.
//! - **Program stops** (M0, M1, M60, M2, M30) also end the held moves where they are. At
//!   the next concave corner LinuxCNC has nothing held, yet reads the corner's first move
//!   from its emptied queue's memory (the first move released last); that is kept, as it
//!   decides whether the corner is refused.
//! - A negative radius (a negative tool table diameter, `G41.1 D-…`) swaps the side.
//! - Motion along the plane's normal happens on the programmed move, none on an added
//!   corner move; the rotary axes, as in LinuxCNC, reach their end values on the corner
//!   move already.
//!
//! Everything here is in **mm in the program frame** (the interpreter's coordinates before
//! work offsets and rotation); the interpreter maps the output to the machine.
//!
//! # Use
//!
//! ```
//! use glam::DVec3;
//! use interpolab::gcode::interp::comp::{CutterComp, Emit, MoveKind, ProgMove, Side};
//! use interpolab::gcode::interp::Loc;
//! use interpolab::gcode::path::Plane;
//!
//! let mut comp: CutterComp<(), ()> = CutterComp::new(Plane::Xy);
//! let mut out = Vec::new();
//! comp.start(Side::Left, 5.0, DVec3::new(-20.0, -20.0, 0.0), Loc::main(1)).unwrap();
//! let feed = |x: f64, y: f64, line| ProgMove {
//!     kind: MoveKind::Feed, end: DVec3::new(x, y, 0.0), abc: DVec3::ZERO, loc: Loc::main(line), tag: (),
//! };
//! comp.push(feed(0.0, 0.0, 2), &mut out).unwrap(); // entry
//! comp.push(feed(50.0, 0.0, 3), &mut out).unwrap();
//! comp.stop(Loc::main(4), &mut out).unwrap(); // G40
//! // The entry, a corner arc around (0, 0), the line along Y = 5 (left of +X).
//! assert_eq!(out.len(), 3);
//! let Emit::Move { mv, .. } = &out[2] else { panic!() };
//! assert!((mv.end - DVec3::new(50.0, 5.0, 0.0)).length() < 1e-12);
//! ```

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::fmt;

use glam::{DVec2, DVec3};

use super::canon::{Loc, Origin};
use crate::gcode::path::Plane;

/// β within this many radians of a straight continuation (or of a reversal) counts as one:
/// LinuxCNC's `TOLERANCE_CONCAVE_CORNER`.
pub const CORNER_TOLERANCE_RAD: f64 = 0.05;

/// A held arc whose end moves at a concave corner may turn further than programmed by this
/// much (radians) in a millimetre program: LinuxCNC compares the two sweep angles with a
/// slack of 0.0254 in G21 and 0.001 in G20 (a length in program units, used as an angle).
const ARC_OVERTURN_SLACK_MM_PROGRAM: f64 = 0.0254;
/// The same in an inch program (radians).
const ARC_OVERTURN_SLACK_INCH_PROGRAM: f64 = 0.001;

/// `|cos A|` below this in the entry-arc construction means the tool cannot make the arc:
/// LinuxCNC's `TOLERANCE_EQUAL`.
const ENTRY_ARC_COS_MIN: f64 = 1e-4;

/// LinuxCNC's default start/end radius tolerance of centre-format arcs (`2·0.01·√2` mm,
/// `2·0.001·√2` inch), used here to check the entry arc's construction.
const ARC_RADIUS_TOL_MM: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2;
const ARC_RADIUS_TOL_INCH: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2;

/// Largest number of calls held at once (moves with no motion in the plane and passed
/// calls pile up behind a held move): past it the program is refused.
pub const MAX_HELD: usize = 100_000;

/// The side of the programmed path the tool runs on, facing the direction of travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// G41 / G41.1.
    Left,
    /// G42 / G42.1.
    Right,
}

impl Side {
    fn swapped(self) -> Self {
        match self {
            Self::Left => Self::Right,
            Self::Right => Self::Left,
        }
    }

    /// +1 left, −1 right: the sense of the quarter turn from the direction of travel to the
    /// side the tool is on.
    fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }

    /// Whether an arc turning `turns` (positive counter-clockwise) has the tool on its
    /// concave side: left of a counter-clockwise arc or right of a clockwise one.
    fn inside(self, turns: i32) -> bool {
        match self {
            Self::Left => turns > 0,
            Self::Right => turns < 0,
        }
    }
}

/// What a move is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// G0.
    Traverse,
    /// G1.
    Feed,
    /// G2/G3 in the compensation plane.
    Arc {
        /// The centre (mm, program frame); only its in-plane coordinates are read. On
        /// output, its coordinate along the plane's normal is the arc's start's.
        center: DVec3,
        /// LinuxCNC's turn count: positive counter-clockwise (G3), negative clockwise
        /// (G2), |turns| = 1 for less than a full turn, each further unit a full turn more
        /// (the P word); never 0.
        turns: i32,
    },
}

/// One move in the program frame, in and out of compensation.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgMove<T> {
    /// Straight or arc.
    pub kind: MoveKind,
    /// End point X, Y, Z (mm, program frame).
    pub end: DVec3,
    /// End of the rotary axes A, B, C (degrees).
    pub abc: DVec3,
    /// The line the move comes from; errors name it, and moves added at a corner carry the
    /// line of the move after the corner.
    pub loc: Loc,
    /// The caller's data (feed, index, …), carried to the output unchanged; an added corner
    /// move carries a clone of the following move's.
    pub tag: T,
}

/// What comes out, in order.
#[derive(Clone, Debug, PartialEq)]
pub enum Emit<T, P> {
    /// A motion: a pushed move with its end (and an arc's centre) moved to the compensated
    /// path, or a move compensation added (a corner arc or traverse; `origin` says which).
    Move {
        /// The move.
        mv: ProgMove<T>,
        /// [`Origin::Programmed`] or [`Origin::Compensation`].
        origin: Origin,
    },
    /// A call given to [`CutterComp::pass`], in its place among the motions.
    Pass(P),
}

/// What may not be done while compensation is on (LinuxCNC refuses each); see
/// [`CutterComp::refuse_if_on`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Refusal {
    /// A G53 move (refused only when the radius is not zero).
    MachineCoordinates,
    /// G28 / G30.
    ReferenceReturn,
    /// G28.1 / G30.1.
    SetReference,
    /// G73, G76, G81–G89.
    CannedCycle,
    /// M6 (tool change).
    ToolChange,
    /// G43, G43.1, G43.2, G49.
    ToolLengthOffset,
    /// G52, G92, G92.1, G92.2, G92.3.
    AxisOffsets,
    /// G54–G59.3, or G10 L2/L20 on the active system.
    CoordinateSystem,
    /// G38.x.
    Probe,
    /// G5, G5.1, G5.2.
    Spline,
    /// G61, G61.1, G64.
    PathControlMode,
    /// G98, G99.
    RetractMode,
}

impl Refusal {
    fn what(self) -> &'static str {
        match self {
            Self::MachineCoordinates => "a G53 move",
            Self::ReferenceReturn => "G28/G30",
            Self::SetReference => "G28.1/G30.1",
            Self::CannedCycle => "a canned cycle",
            Self::ToolChange => "a tool change",
            Self::ToolLengthOffset => "a tool length offset change (G43/G49)",
            Self::AxisOffsets => "G52/G92 axis offsets",
            Self::CoordinateSystem => "a change of the active coordinate system",
            Self::Probe => "probing",
            Self::Spline => "a spline",
            Self::PathControlMode => "a path control mode change (G61/G64)",
            Self::RetractMode => "a retract mode change (G98/G99)",
        }
    }
}

/// The place of an error, as the message prints it.
struct At(Loc);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.file == 0 {
            write!(f, "line {}", self.0.line)
        } else {
            write!(f, "line {} of subroutine file {}", self.0.line, self.0.file)
        }
    }
}

/// Why compensation refused a program (each is an error in LinuxCNC too, at the same line).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompError {
    /// G41/G42 in the YZ plane (or G19 while on).
    #[error("{}: cutter radius compensation works in the XY (G17) and XZ (G18) planes only; select one before G41/G42", At(*at))]
    PlaneNotSupported {
        /// Where.
        at: Loc,
    },
    /// G41/G42 while already on.
    #[error("{}: cutter radius compensation is already on; give G40 before turning it on again", At(*at))]
    AlreadyOn {
        /// Where.
        at: Loc,
    },
    /// G17/G18/G19 changing the plane while on.
    #[error("{}: the plane cannot change while cutter radius compensation is on; give G40 first", At(*at))]
    PlaneChange {
        /// Where.
        at: Loc,
    },
    /// A radius that is not a number.
    #[error("{}: the cutter compensation radius {radius_mm} is not a finite length in mm", At(*at))]
    BadRadius {
        /// Where.
        at: Loc,
        /// The radius given (mm).
        radius_mm: f64,
    },
    /// A lathe tool orientation out of 0–9, or a lathe tool (orientation 1–8) outside G18.
    #[error("{}: lathe tool orientation {orientation} {}", At(*at), if *orientation > 9 { "is not in 0–9" } else { "needs the XZ plane (G18) for cutter compensation" })]
    BadOrientation {
        /// Where.
        at: Loc,
        /// The orientation given.
        orientation: u8,
    },
    /// A move with a coordinate that is not a number, or an arc with no turn.
    #[error("{}: {what}", At(*at))]
    BadMove {
        /// Where.
        at: Loc,
        /// What is wrong.
        what: &'static str,
    },
    /// The straight entry move is not longer than the tool radius.
    #[error("{}: the cutter compensation entry move ({length_mm:.4} mm in the plane) is not longer than the tool radius {radius_mm:.4} mm; start farther from the path", At(*at))]
    EntryTooShort {
        /// Where.
        at: Loc,
        /// In-plane length of the entry move (mm).
        length_mm: f64,
        /// Tool radius (mm).
        radius_mm: f64,
    },
    /// The entry arc's chord is not longer than the tool radius.
    #[error("{}: the cutter compensation entry arc ({length_mm:.4} mm start to end) is not longer than the tool radius {radius_mm:.4} mm; start farther from the path", At(*at))]
    EntryArcTooShort {
        /// Where.
        at: Loc,
        /// Distance from the arc's start to its end in the plane (mm).
        length_mm: f64,
        /// Tool radius (mm).
        radius_mm: f64,
    },
    /// An arc with the tool inside it whose radius is not larger than the tool's (LinuxCNC:
    /// "Tool radius not less than arc radius with comp").
    #[error("{}: the tool radius {radius_mm:.4} mm is not less than the arc's radius {arc_radius_mm:.4} mm with the tool inside the arc; use a smaller tool or a larger arc", At(*at))]
    ToolTooBigForArc {
        /// Where.
        at: Loc,
        /// Arc radius (mm).
        arc_radius_mm: f64,
        /// Tool radius (mm).
        radius_mm: f64,
    },
    /// The move after G40 is an arc.
    #[error("{}: the move after turning cutter compensation off (G40) must be straight, not an arc", At(*at))]
    ArcAfterExit {
        /// Where.
        at: Loc,
    },
    /// At a concave corner the held straight move would have to run backwards: the move
    /// before the corner is shorter than the tool needs (LinuxCNC: "Straight feed/traverse
    /// in concave corner cannot be reached by the tool without gouging").
    #[error("{}: concave corner: the {} before it is too short for the tool — it cannot be reached without gouging", At(*at), if *traverse { "straight traverse" } else { "straight feed" })]
    ConcaveLineGouge {
        /// Where (the move after the corner).
        at: Loc,
        /// The held move is a traverse.
        traverse: bool,
    },
    /// At a concave corner an arc would have to turn further than programmed, or the
    /// offset line does not reach the arc's offset circle (LinuxCNC: "Arc move in concave
    /// corner cannot be reached by the tool without gouging").
    #[error("{}: concave corner: the arc cannot be reached by the tool without gouging", At(*at))]
    ConcaveArcGouge {
        /// Where (the move that makes the corner).
        at: Loc,
    },
    /// Arc then straight: the offset line misses the arc's offset circle.
    #[error("{}: concave corner: the arc before this straight move leaves no room for the tool without gouging", At(*at))]
    ArcToLineGouge {
        /// Where.
        at: Loc,
    },
    /// Arc then arc: the two offset circles do not meet.
    #[error("{}: concave corner: the two arcs leave no room for the tool without gouging", At(*at))]
    ArcToArcGouge {
        /// Where.
        at: Loc,
    },
    /// Arc then arc with the same centre at a concave corner.
    #[error("{}: concave corner between two arcs with the same centre; the tool path is undefined", At(*at))]
    ArcToArcSameCenter {
        /// Where.
        at: Loc,
    },
    /// A straight move reversing exactly onto the previous one at a concave corner.
    #[error("{}: a zero-degree inside corner (the path turns straight back) cannot be compensated", At(*at))]
    ZeroDegreeCorner {
        /// Where.
        at: Loc,
    },
    /// A consistency check of the construction failed (LinuxCNC reports these as bugs).
    #[error("{}: cutter compensation could not build this move ({what})", At(*at))]
    Construction {
        /// Where.
        at: Loc,
        /// Which check.
        what: &'static str,
    },
    /// More than [`MAX_HELD`] calls waiting behind one compensated move.
    #[error("{}: more than {cap} moves without motion in the compensation plane while compensation is on; move in the plane or give G40", At(*at))]
    TooManyHeld {
        /// Where.
        at: Loc,
        /// The cap.
        cap: usize,
    },
    /// Something LinuxCNC refuses while compensation is on.
    #[error("{}: {} is not allowed while cutter radius compensation is on; give G40 first", At(*at), what.what())]
    Refused {
        /// Where.
        at: Loc,
        /// What was asked.
        what: Refusal,
    },
}

/// Compensation in force.
#[derive(Clone, Copy, Debug)]
struct Active {
    side: Side,
    /// mm, ≥ 0.
    radius: f64,
}

/// A held call. Positions are in plane coordinates (a, b) with n along the normal.
#[derive(Clone, Debug)]
enum Held<T, P> {
    Line {
        traverse: bool,
        /// The direction the move was meant to go in the plane (not normalised; zero for a
        /// move with no in-plane motion): a shortened move must not reverse it.
        dir: DVec2,
        end: DVec2,
        n: f64,
        abc: DVec3,
        loc: Loc,
        tag: T,
        origin: Origin,
    },
    Arc {
        /// The angle the arc was meant to turn (radians, signed; 0: never checked).
        sweep: f64,
        end: DVec2,
        center: DVec2,
        turns: i32,
        start_n: f64,
        n: f64,
        abc: DVec3,
        loc: Loc,
        tag: T,
        origin: Origin,
    },
    Pass(P),
}

/// The move a corner is computed with: a held straight move or a held arc (compensated).
#[derive(Clone, Copy, Debug)]
enum Front {
    Line,
    Arc { center: DVec2, end: DVec2, turns: i32 },
}

/// Cutter radius compensation between the block executor (programmed moves in) and the
/// canonical motions (compensated moves out).
///
/// Push every G0/G1/G2/G3 move through [`push`](Self::push), on or off (when off it only
/// passes them on, and checks the rule that an arc may not follow G40). `T` is the caller's
/// per-move data, `P` its non-motion calls (see [`pass`](Self::pass)).
///
/// While compensation is on, the position the executor uses for incremental words and for
/// axes a block leaves out is the **programmed** position (the last pushed end), as in
/// LinuxCNC; after G40 it is that same position.
///
/// After an error the program stops (as LinuxCNC's does): the state is not meant to be used
/// further.
#[derive(Clone, Debug)]
pub struct CutterComp<T, P> {
    plane: Plane,
    active: Option<Active>,
    /// Lathe tool orientation (0 and 9: the controlled point is the nose centre).
    orientation: u8,
    /// The radius the held moves were made with (kept after G40 for the lathe shift).
    radius: f64,
    first_move: bool,
    arc_not_allowed: bool,
    /// Programmed position (program frame, mm).
    program: DVec3,
    /// Compensated position of the last held move's end (program frame, mm, before the
    /// lathe shift).
    current: DVec3,
    held: Vec<Held<T, P>>,
    /// The first of the moves released last (see [`front`](Self::front)).
    last_front: Front,
    /// Start (in the plane) of the last move held, while it is known; LinuxCNC's
    /// `endpoint`.
    endpoint: Option<DVec2>,
    inch: bool,
}

impl<T: Clone, P> CutterComp<T, P> {
    /// Compensation off, in `plane` (the interpreter's G17/G18/G19 at the start).
    #[must_use]
    pub fn new(plane: Plane) -> Self {
        Self {
            plane,
            active: None,
            orientation: 0,
            radius: 0.0,
            first_move: true,
            arc_not_allowed: false,
            program: DVec3::ZERO,
            current: DVec3::ZERO,
            held: Vec::new(),
            last_front: Front::Line,
            endpoint: None,
            inch: false,
        }
    }

    /// Whether G41/G42 is in force (also with a zero radius).
    #[must_use]
    pub fn is_on(&self) -> bool {
        self.active.is_some()
    }

    /// The side and radius (mm) in force, after a negative radius swapped the side.
    #[must_use]
    pub fn side_and_radius(&self) -> Option<(Side, f64)> {
        self.active.map(|a| (a.side, a.radius))
    }

    /// Calls held, waiting for a later move.
    #[must_use]
    pub fn held(&self) -> usize {
        self.held.len()
    }

    /// The plane in force.
    #[must_use]
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// Whether the program is in inches (G20) now: three of LinuxCNC's tolerances are in
    /// program units (the slack of a shortened arc's sweep, and two consistency checks).
    /// Positions stay in mm.
    pub fn set_inch(&mut self, inch: bool) {
        self.inch = inch;
    }

    /// G17/G18/G19. Refused when it changes the plane while compensation is on.
    pub fn set_plane(&mut self, plane: Plane, at: Loc) -> Result<(), CompError> {
        if self.active.is_some() && plane != self.plane {
            return Err(CompError::PlaneChange { at });
        }
        self.plane = plane;
        Ok(())
    }

    /// Refuses `what` while compensation is on, as LinuxCNC does (a G53 move only when the
    /// radius is not zero).
    pub fn refuse_if_on(&self, what: Refusal, at: Loc) -> Result<(), CompError> {
        match self.active {
            Some(a) if what != Refusal::MachineCoordinates || a.radius > 0.0 => Err(CompError::Refused { at, what }),
            _ => Ok(()),
        }
    }

    /// G41/G42 (`radius_mm` from the tool table's diameter / 2) or G41.1/G42.1 (`D` / 2), a
    /// milling cutter; `position` is the programmed position now (mm, program frame). A
    /// negative radius swaps the side; zero turns compensation on with no offset.
    pub fn start(&mut self, side: Side, radius_mm: f64, position: DVec3, at: Loc) -> Result<(), CompError> {
        self.start_with_orientation(side, radius_mm, 0, position, at)
    }

    /// [`start`](Self::start) with a lathe tool's orientation (1–8: the tool table's `Q`, or
    /// G41.1/G42.1's `L`; 0 and 9 mean the controlled point is the nose centre). With
    /// orientation 1–8 the output is the tool's reference point, one radius from the nose
    /// centre along X and Z, as LinuxCNC places it; that needs the XZ plane.
    pub fn start_with_orientation(
        &mut self,
        side: Side,
        radius_mm: f64,
        orientation: u8,
        position: DVec3,
        at: Loc,
    ) -> Result<(), CompError> {
        if self.plane == Plane::Yz {
            return Err(CompError::PlaneNotSupported { at });
        }
        if self.active.is_some() {
            return Err(CompError::AlreadyOn { at });
        }
        if !radius_mm.is_finite() {
            return Err(CompError::BadRadius { at, radius_mm });
        }
        if orientation > 9 || (self.plane != Plane::Zx && orientation != 0 && orientation != 9) {
            return Err(CompError::BadOrientation { at, orientation });
        }
        if !position.is_finite() {
            return Err(CompError::BadMove { at, what: "the position at G41/G42 is not finite" });
        }
        let (side, radius) = if radius_mm < 0.0 { (side.swapped(), -radius_mm) } else { (side, radius_mm) };
        self.active = Some(Active { side, radius });
        self.radius = radius;
        self.orientation = orientation;
        self.program = position;
        self.current = position;
        Ok(())
    }

    /// G40. Ends the held moves where they are and turns compensation off; the next move
    /// is not compensated and must be straight (when a compensated move was made).
    pub fn stop(&mut self, at: Loc, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        if self.active.is_some_and(|a| a.radius > 0.0) && !self.first_move {
            let (c, _) = self.split(self.current);
            self.move_end_and_flush(c, at, out)?;
            self.current = self.program;
            self.arc_not_allowed = true;
        }
        self.active = None;
        self.first_move = true;
        Ok(())
    }

    /// A program stop (M0, M1, M60): ends the held moves where they are; compensation stays
    /// on.
    pub fn flush(&mut self, at: Loc, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        let (c, _) = self.split(self.current);
        self.move_end_and_flush(c, at, out)
    }

    /// Program end (M2, M30): [`flush`](Self::flush), then compensation off (no G40 rules
    /// for the next move).
    ///
    /// A program that ends at `%` or at the end of its file gives no call here in LinuxCNC:
    /// its last compensated move is never output (and a file with neither `%` nor M2 is an
    /// error there).
    pub fn end_program(&mut self, at: Loc, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        self.flush(at, out)?;
        self.active = None;
        self.first_move = true;
        Ok(())
    }

    /// A non-motion call (a dwell, a spindle or coolant change, a comment): output now when
    /// nothing is held, else held behind the held moves so that the order is kept.
    ///
    /// Refused when more than [`MAX_HELD`] calls would wait (`at` names the line).
    pub fn pass(&mut self, call: P, at: Loc, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        if self.held.is_empty() {
            out.push(Emit::Pass(call));
        } else if self.held.len() >= MAX_HELD {
            return Err(CompError::TooManyHeld { at, cap: MAX_HELD });
        } else {
            self.held.push(Held::Pass(call));
        }
        Ok(())
    }

    /// One programmed move (from the last programmed end to `mv.end`). Its compensated
    /// form, with a corner move before it, comes out once a later move (or
    /// [`stop`](Self::stop), [`flush`](Self::flush)) decides where it ends.
    pub fn push(&mut self, mv: ProgMove<T>, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        let at = mv.loc;
        if !mv.end.is_finite() || !mv.abc.is_finite() {
            return Err(CompError::BadMove { at, what: "a move's end is not finite" });
        }
        let arc = match mv.kind {
            MoveKind::Arc { center, turns } => {
                if self.arc_not_allowed {
                    return Err(CompError::ArcAfterExit { at });
                }
                if turns == 0 || !center.is_finite() {
                    return Err(CompError::BadMove {
                        at,
                        what: "an arc needs a finite centre and a nonzero turn count",
                    });
                }
                Some((center, turns))
            }
            MoveKind::Traverse | MoveKind::Feed => {
                self.arc_not_allowed = false;
                None
            }
        };
        let active = match self.active {
            Some(a) if a.radius > 0.0 => a,
            _ => {
                // Off, or on with no offset: the move as programmed.
                self.program = mv.end;
                self.current = mv.end;
                out.push(Emit::Move { mv, origin: Origin::Programmed });
                return Ok(());
            }
        };
        match (arc, self.first_move) {
            (None, true) => self.line_entry(active, mv),
            (None, false) => self.line_next(active, mv, out),
            (Some((center, turns)), true) => self.arc_entry(active, mv, center, turns),
            (Some((center, turns)), false) => self.arc_next(active, mv, center, turns, out),
        }
    }

    fn split(&self, p: DVec3) -> (DVec2, f64) {
        let (a, b, n) = self.plane.split(p);
        (DVec2::new(a, b), n)
    }

    fn join(&self, p: DVec2, n: f64) -> DVec3 {
        self.plane.join(p.x, p.y, n)
    }

    /// Sets the programmed and compensated positions after a move.
    fn moved(&mut self, programmed: DVec3, tool: DVec2, n: f64) {
        self.program = programmed;
        self.current = self.join(tool, n);
    }

    /// The first straight move after G41/G42: ends one radius off its programmed end,
    /// square to the move.
    fn line_entry(&mut self, comp: Active, mv: ProgMove<T>) -> Result<(), CompError> {
        let (c, _) = self.split(self.current);
        let (p, pn) = self.split(mv.end);
        let d = p - c;
        let length = d.x.hypot(d.y);
        if length <= comp.radius {
            return Err(CompError::EntryTooShort { at: mv.loc, length_mm: length, radius_mm: comp.radius });
        }
        let normal_angle = d.y.atan2(d.x) + comp.side.sign() * FRAC_PI_2;
        let normal = unit(normal_angle);
        let end = p + comp.radius * normal;
        self.endpoint = Some(c);
        // LinuxCNC records the normal, not the direction of travel, as the direction a
        // shortened entry move must keep.
        self.held.push(Held::Line {
            traverse: mv.kind == MoveKind::Traverse,
            dir: normal,
            end,
            n: pn,
            abc: mv.abc,
            loc: mv.loc,
            tag: mv.tag,
            origin: Origin::Programmed,
        });
        self.first_move = false;
        self.moved(mv.end, end, pn);
        Ok(())
    }

    /// A straight move after the first.
    fn line_next(&mut self, comp: Active, mv: ProgMove<T>, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        let at = mv.loc;
        let traverse = mv.kind == MoveKind::Traverse;
        let (c, cn) = self.split(self.current);
        let (o, _) = self.split(self.program);
        let (p, pn) = self.split(mv.end);
        if p == o {
            // No motion in the plane: held behind the last move, ending where it ends.
            if self.held.len() >= MAX_HELD {
                return Err(CompError::TooManyHeld { at, cap: MAX_HELD });
            }
            self.held.push(Held::Line {
                traverse,
                dir: DVec2::ZERO,
                end: c,
                n: pn,
                abc: mv.abc,
                loc: at,
                tag: mv.tag,
                origin: Origin::Programmed,
            });
            self.moved(mv.end, c, pn);
            return Ok(());
        }
        let r = comp.radius;
        // theta: from the programmed corner to the tool (the held move's offset normal);
        // alpha: the new move's direction. beta is the turn from the new direction to the
        // old one seen from the tool's side, in [-π/2, 3π/2): 0 straight on, positive convex.
        let mut theta = angle(c - o);
        let mut alpha = angle(p - o);
        let (beta, quarter) = match comp.side {
            Side::Left => {
                if theta < alpha {
                    theta += TAU;
                }
                (theta - alpha - FRAC_PI_2, FRAC_PI_2)
            }
            Side::Right => {
                if alpha < theta {
                    alpha += TAU;
                }
                (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
            }
        };
        let offset = r * unit(alpha + quarter);
        let end = p + offset;
        let corner_end = o + offset;
        let small = CORNER_TOLERANCE_RAD;
        let front_arc_turns = match self.held.first() {
            Some(Held::Arc { turns, .. }) => Some(*turns),
            _ => None,
        };
        // A near reversal after an arc with the tool outside it (the "h" shape): the tool
        // stays on the near side, a concave corner.
        let reversal_after_arc = beta > PI - small && front_arc_turns.is_some_and(|t| !comp.side.inside(t));
        let concave = beta < -small || beta > PI + small || reversal_after_arc;
        if !concave && beta > small {
            // Convex: around the programmed corner on the tool radius.
            self.move_end_and_flush(c, at, out)?;
            let kind = if traverse {
                MoveKind::Traverse
            } else {
                MoveKind::Arc { center: self.join(o, cn), turns: -comp.side.sign() as i32 }
            };
            let corner = ProgMove { kind, end: self.join(corner_end, cn), abc: mv.abc, loc: at, tag: mv.tag.clone() };
            out.push(Emit::Move { mv: self.lathe_shift(corner), origin: Origin::Compensation });
            self.last_front = if traverse {
                Front::Line
            } else {
                Front::Arc { center: o, end: corner_end, turns: -comp.side.sign() as i32 }
            };
            self.endpoint = Some(corner_end);
        } else if concave {
            match self.front() {
                Front::Arc { center: k, end: e, turns } => {
                    let meet = arc_line_corner(comp, k, e, turns, o, p, at)?;
                    self.move_end_and_flush(meet, at, out)?;
                }
                Front::Line => {
                    // Two offset lines meet `retreat` back along the held move.
                    let half_corner = (beta + PI) / 2.0;
                    if half_corner == 0.0 {
                        return Err(CompError::ZeroDegreeCorner { at });
                    }
                    let retreat = r / half_corner.tan();
                    let meet = c + retreat * unit(theta + quarter);
                    self.move_end_and_flush(meet, at, out)?;
                }
            }
        } else {
            // Straight on (or a tangent arc before): no corner.
            self.release(out);
            self.endpoint = Some(c);
        }
        self.held.push(Held::Line {
            traverse,
            dir: p - o,
            end,
            n: pn,
            abc: mv.abc,
            loc: at,
            tag: mv.tag,
            origin: Origin::Programmed,
        });
        self.moved(mv.end, end, pn);
        Ok(())
    }

    /// The first move after G41/G42 is an arc.
    fn arc_entry(&mut self, comp: Active, mv: ProgMove<T>, center: DVec3, turns: i32) -> Result<(), CompError> {
        let at = mv.loc;
        let r = comp.radius;
        let (c, cn) = self.split(self.current);
        let (p, pn) = self.split(mv.end);
        let (k, _) = self.split(center);
        let chord = (p - c).x.hypot((p - c).y);
        if chord <= r {
            return Err(CompError::EntryArcTooShort { at, length_mm: chord, radius_mm: r });
        }
        let inside = comp.side.inside(turns);
        let arc_radius = (k - c).x.hypot((k - c).y);
        if inside && arc_radius <= r {
            return Err(CompError::ToolTooBigForArc { at, arc_radius_mm: arc_radius, radius_mm: r });
        }
        // The end moves one radius along the arc's radius, toward the centre when inside.
        let away = if inside { k - p } else { p - k };
        let end = p + r * unit(angle(away));
        // The new centre lies on the line from the new end through the old centre, as far
        // from the start as from the new end: the triangle (end, centre, chord midpoint)
        // has its right angle at the midpoint.
        let half_chord = (c - end).x.hypot((c - end).y) / 2.0;
        let to_center = angle(k - end);
        let a = angle(c - end) - to_center;
        if a.cos().abs() < ENTRY_ARC_COS_MIN {
            return Err(CompError::ToolTooBigForArc { at, arc_radius_mm: arc_radius, radius_mm: r });
        }
        let new_center = end + (half_chord / a.cos()) * unit(to_center);
        let r_end = (new_center - end).x.hypot((new_center - end).y);
        let r_start = (new_center - c).x.hypot((new_center - c).y);
        let tol = if self.inch { ARC_RADIUS_TOL_INCH * 25.4 } else { ARC_RADIUS_TOL_MM };
        if (r_end - r_start).abs() > tol {
            return Err(CompError::Construction { at, what: "the entry arc's radii differ" });
        }
        if self.orientation != 0 && self.orientation != 9 {
            // A lathe tool first moves its reference point to where the arc starts.
            self.held.push(Held::Line {
                traverse: false,
                dir: DVec2::ZERO,
                end: c,
                n: cn,
                abc: mv.abc,
                loc: at,
                tag: mv.tag.clone(),
                origin: Origin::Compensation,
            });
            self.endpoint = Some(c);
        }
        self.held.push(Held::Arc {
            sweep: sweep(c, new_center, turns, end),
            end,
            center: new_center,
            turns,
            start_n: cn,
            n: pn,
            abc: mv.abc,
            loc: at,
            tag: mv.tag,
            origin: Origin::Programmed,
        });
        self.first_move = false;
        self.moved(mv.end, end, pn);
        Ok(())
    }

    /// An arc after the first move.
    fn arc_next(
        &mut self,
        comp: Active,
        mv: ProgMove<T>,
        center: DVec3,
        turns: i32,
        out: &mut Vec<Emit<T, P>>,
    ) -> Result<(), CompError> {
        let at = mv.loc;
        let r = comp.radius;
        let (o, _) = self.split(self.program);
        let (c, cn) = self.split(self.current);
        let (p, pn) = self.split(mv.end);
        let (k, _) = self.split(center);
        let arc_radius = (k - p).x.hypot((k - p).y);
        let side = comp.side.sign();
        // theta: direction of travel at the end of the held move; alpha: the arc's at its
        // start; beta as for lines (0 tangent, positive convex), put in [-π/2, 3π/2] once.
        let theta = angle(c - o) - side * FRAC_PI_2;
        let mut delta = angle(k - o);
        let alpha = if turns > 0 { delta - FRAC_PI_2 } else { delta + FRAC_PI_2 };
        let mut beta = side * (theta - alpha);
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        let inside = comp.side.inside(turns);
        let gamma = if inside {
            if arc_radius <= r {
                return Err(CompError::ToolTooBigForArc { at, arc_radius_mm: arc_radius, radius_mm: r });
            }
            angle(k - p)
        } else {
            delta += PI;
            angle(p - k)
        };
        let end = p + r * unit(gamma);
        let small = CORNER_TOLERANCE_RAD;
        let abc = mv.abc;
        let main = |tag: T| Held::Arc {
            sweep: sweep(o, k, turns, p),
            end,
            center: k,
            turns,
            start_n: cn,
            n: pn,
            abc,
            loc: at,
            tag,
            origin: Origin::Programmed,
        };
        // Concave, or a reversal onto an arc with the tool outside it (the "m" and "h"
        // shapes, taken as concave).
        let concave = beta < -small || beta > PI + small || ((beta - PI).abs() < small && !inside);
        if concave {
            let meet = match self.front() {
                Front::Arc { center: k0, end: e0, turns: t0 } => {
                    arc_arc_corner(comp, k0, e0, t0, k, arc_radius, turns, at)?
                }
                Front::Line => line_arc_corner(comp, k, arc_radius, turns, theta, beta, at)?,
            };
            self.move_end_and_flush(meet, at, out)?;
            self.held.push(main(mv.tag));
        } else if beta > small {
            // Convex: a corner arc around the programmed corner to where the offset arc
            // starts, then the arc.
            let corner_end = o + r * unit(delta);
            self.release(out);
            let corner = ProgMove {
                kind: MoveKind::Arc { center: self.join(o, cn), turns: -side as i32 },
                end: self.join(corner_end, cn),
                abc: mv.abc,
                loc: at,
                tag: mv.tag.clone(),
            };
            out.push(Emit::Move { mv: self.lathe_shift(corner), origin: Origin::Compensation });
            self.last_front = Front::Arc { center: o, end: corner_end, turns: -side as i32 };
            self.endpoint = Some(corner_end);
            self.held.push(main(mv.tag));
        } else {
            self.release(out);
            self.endpoint = Some(c);
            self.held.push(main(mv.tag));
        }
        self.moved(mv.end, end, pn);
        Ok(())
    }

    /// The first held move, whose corner with the next move is computed; when nothing is
    /// held (after a program stop), the first of the last moves released — what LinuxCNC's
    /// emptied queue still holds in memory and reads there.
    fn front(&self) -> Front {
        match self.held.first() {
            Some(Held::Arc { center, end, turns, .. }) => Front::Arc { center: *center, end: *end, turns: *turns },
            Some(Held::Line { .. } | Held::Pass(_)) => Front::Line,
            None => self.last_front,
        }
    }

    /// Moves the end of every held move to `to` (in the plane), checking that none has to
    /// run backwards or turn further than programmed, then outputs them all.
    fn move_end_and_flush(&mut self, to: DVec2, at: Loc, out: &mut Vec<Emit<T, P>>) -> Result<(), CompError> {
        if self.held.is_empty() {
            return Ok(());
        }
        let start = self.endpoint;
        // LinuxCNC's 0.01 program units between a held arc's old and new radius.
        let mismatch = if self.inch { 0.01 * 25.4 } else { 0.01 };
        let slack = if self.inch { ARC_OVERTURN_SLACK_INCH_PROGRAM } else { ARC_OVERTURN_SLACK_MM_PROGRAM };
        for h in &mut self.held {
            match h {
                Held::Line { traverse, dir, end, .. } => {
                    if start.is_some_and(|s| dir.dot(to - s) < 0.0) {
                        return Err(CompError::ConcaveLineGouge { at, traverse: *traverse });
                    }
                    *end = to;
                }
                Held::Arc { sweep: planned, end, center, turns, .. } => {
                    let r1 = (*end - *center).x.hypot((*end - *center).y);
                    let r2 = (to - *center).x.hypot((to - *center).y);
                    if (r1 - r2).abs() > mismatch {
                        return Err(CompError::Construction { at, what: "a shortened arc's radii differ" });
                    }
                    if let Some(s) = start {
                        let now = sweep(s, *center, *turns, to);
                        if *planned != 0.0 && now.abs() > planned.abs() + slack {
                            return Err(CompError::ConcaveArcGouge { at });
                        }
                    }
                    *end = to;
                }
                Held::Pass(_) => {}
            }
        }
        self.release(out);
        self.endpoint = Some(to);
        Ok(())
    }

    /// Outputs every held call as it is.
    fn release(&mut self, out: &mut Vec<Emit<T, P>>) {
        self.endpoint = None;
        match self.held.first() {
            Some(Held::Arc { center, end, turns, .. }) => {
                self.last_front = Front::Arc { center: *center, end: *end, turns: *turns };
            }
            Some(Held::Line { .. }) => self.last_front = Front::Line,
            Some(Held::Pass(_)) | None => {}
        }
        // The buffer is put back afterwards, so holding and releasing does not allocate.
        let mut held = std::mem::take(&mut self.held);
        out.reserve(held.len());
        for h in held.drain(..) {
            let e = match h {
                Held::Line { traverse, end, n, abc, loc, tag, origin, .. } => {
                    let kind = if traverse { MoveKind::Traverse } else { MoveKind::Feed };
                    let mv = ProgMove { kind, end: self.join(end, n), abc, loc, tag };
                    Emit::Move { mv: self.lathe_shift(mv), origin }
                }
                Held::Arc { end, center, turns, start_n, n, abc, loc, tag, origin, .. } => {
                    let kind = MoveKind::Arc { center: self.join(center, start_n), turns };
                    let mv = ProgMove { kind, end: self.join(end, n), abc, loc, tag };
                    Emit::Move { mv: self.lathe_shift(mv), origin }
                }
                Held::Pass(p) => Emit::Pass(p),
            };
            out.push(e);
        }
        self.held = held;
    }

    /// A lathe tool's reference point from its nose centre (XZ plane, orientations 1–8):
    /// LinuxCNC's `latheorigin_x/z`.
    fn lathe_shift(&self, mut mv: ProgMove<T>) -> ProgMove<T> {
        if self.plane != Plane::Zx {
            return mv;
        }
        let r = self.radius;
        let dx = match self.orientation {
            1 | 2 | 6 => -r,
            3 | 4 | 8 => r,
            _ => 0.0,
        };
        let dz = match self.orientation {
            2 | 3 | 7 => -r,
            1 | 4 | 5 => r,
            _ => 0.0,
        };
        let shift = DVec3::new(dx, 0.0, dz);
        mv.end += shift;
        if let MoveKind::Arc { center, .. } = &mut mv.kind {
            *center += shift;
        }
        mv
    }
}

/// The unit vector at `angle` radians from the first in-plane axis.
fn unit(angle: f64) -> DVec2 {
    DVec2::new(angle.cos(), angle.sin())
}

/// The direction of `v` (radians, (−π, π]).
fn angle(v: DVec2) -> f64 {
    v.y.atan2(v.x)
}

/// The signed angle an arc around `center` turns from `start` to `end` with LinuxCNC's turn
/// count (positive counter-clockwise; an end on the start is a full turn).
fn sweep(start: DVec2, center: DVec2, turns: i32, end: DVec2) -> f64 {
    if turns == 0 {
        return 0.0;
    }
    let mut a0 = angle(start - center);
    let mut a1 = angle(end - center);
    if turns > 0 {
        if a1 <= a0 {
            a1 += TAU;
        }
        (a1 - a0) + f64::from(turns - 1) * TAU
    } else {
        if a0 <= a1 {
            a0 += TAU;
        }
        (a1 - a0) + f64::from(turns + 1) * TAU
    }
}

/// Concave corner from a held (compensated) arc to a straight move from `o` toward `p`:
/// where the arc's offset circle meets the line's offset line.
fn arc_line_corner(
    comp: Active,
    k: DVec2,
    e: DVec2,
    turns: i32,
    o: DVec2,
    p: DVec2,
    at: Loc,
) -> Result<DVec2, CompError> {
    let r = comp.radius;
    let r_comp = (k - e).x.hypot((k - e).y);
    let inside = comp.side.inside(turns);
    // The programmed arc's radius, from the compensated one.
    let r_prog = if inside { r_comp + r } else { r_comp - r };
    // A normal of the line, on the side the arc turns toward.
    let nrm_angle = angle(p - o) + if turns > 0 { FRAC_PI_2 } else { -FRAC_PI_2 };
    // Distance of the centre from the programmed line along that normal, then from the
    // offset line; its ratio to the offset circle's radius places the meeting point.
    let d = r_prog * (nrm_angle - angle(k - o)).cos();
    let (l, s) = if inside { ((d - r) / r_comp, -1.0) } else { ((d + r) / r_comp, 1.0) };
    if !(-1.0..=1.0).contains(&l) {
        return Err(CompError::ArcToLineGouge { at });
    }
    let sense = if turns > 0 { s } else { -s };
    let from_center = nrm_angle + PI + sense * l.acos();
    Ok(k + r_comp * unit(from_center))
}

/// Concave corner from a held straight move to an arc around `k`: where the line's offset
/// line (through the tool's position, direction `theta`) meets the arc's offset circle.
fn line_arc_corner(
    comp: Active,
    k: DVec2,
    arc_radius: f64,
    turns: i32,
    theta: f64,
    beta: f64,
    at: Loc,
) -> Result<DVec2, CompError> {
    let r = comp.radius;
    // Signed distance of the programmed corner's tangent line from the centre, in units
    // of the arc radius times the sine of the corner.
    let h = arc_radius * (beta - FRAC_PI_2).sin();
    let (dist, from_center) = if comp.side.inside(turns) {
        let dist = arc_radius - r;
        let l = (h + r) / dist;
        if !(-1.0..=1.0).contains(&l) {
            return Err(CompError::ConcaveArcGouge { at });
        }
        (dist, if turns > 0 { theta + l.asin() } else { theta - l.asin() })
    } else {
        let dist = arc_radius + r;
        let l = (h - r) / dist;
        if !(-1.0..=1.0).contains(&l) {
            return Err(CompError::ConcaveArcGouge { at });
        }
        (dist, if turns > 0 { theta + PI - l.asin() } else { theta + PI + l.asin() })
    };
    Ok(k + dist * unit(from_center))
}

/// Concave corner from a held (compensated) arc around `k0` to an arc around `k`: where
/// the two offset circles meet.
#[allow(clippy::too_many_arguments, reason = "the corner is defined by both arcs and the tool")]
fn arc_arc_corner(
    comp: Active,
    k0: DVec2,
    e0: DVec2,
    t0: i32,
    k: DVec2,
    arc_radius: f64,
    turns: i32,
    at: Loc,
) -> Result<DVec2, CompError> {
    let r = comp.radius;
    let old_r = (k0 - e0).x.hypot((k0 - e0).y);
    let new_r = if comp.side.inside(turns) { arc_radius - r } else { arc_radius + r };
    let between = (k0 - k).x.hypot((k0 - k).y);
    if old_r == 0.0 || between == 0.0 {
        return Err(CompError::ArcToArcSameCenter { at });
    }
    // Law of cosines in the triangle (old centre, new centre, meeting point).
    let cos_a = (old_r * old_r + between * between - new_r * new_r) / (2.0 * old_r * between);
    if !(-1.0..=1.0).contains(&cos_a) {
        return Err(CompError::ArcToArcGouge { at });
    }
    let pullback = cos_a.acos();
    let towards = angle(k - k0);
    let plus = comp.side.inside(t0) == (turns > 0);
    let dir = if plus { towards + pullback } else { towards - pullback };
    Ok(k0 + old_r * unit(dir))
}
