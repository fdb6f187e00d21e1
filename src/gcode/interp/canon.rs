//! Canonical motions: what a program does once every word, mode and offset has been applied —
//! the one stream the interpreter emits and everything downstream reads (replay, deviation,
//! the simulation, the app's views, the feed planner).
//!
//! The idea is LinuxCNC's *canonical machining functions* (`STRAIGHT_TRAVERSE`,
//! `STRAIGHT_FEED`, `ARC_FEED`, `NURBS_FEED`, `DWELL`, `CHANGE_TOOL`, …), with two
//! differences a viewer wants:
//!
//! - **Positions are final.** LinuxCNC passes program coordinates and lets its canonical layer
//!   add the offsets; here every position is already in the **machine frame**, in **mm**:
//!   `machine = rotate_z(program + G92/G52 offset, XY rotation) + G54…G59.3 offset`, and inch
//!   programs are scaled by 25.4. The point is the **controlled point** — the tool tip as
//!   programmed. The tool length offset in force (G43/G43.1/G43.2) is *not* added to it; it is
//!   a separate [`Canon::ToolLengthOffset`] so that a simulation can put the real tool where
//!   the controller would (`spindle nose = tip + offset`).
//! - **Every motion knows its source line** ([`Loc`]), so a report, a gouge or a crash can
//!   name the line a user wrote.
//!
//! Rotary axes A, B, C are carried in every motion in **degrees**, as programmed (LinuxCNC
//! and FANUC both program rotary axes in degrees); they are not scaled by G20. Arc and
//! spline motions move the rotary axes linearly from start to end, as LinuxCNC does.
//!
//! A motion's start is the end of the motion before it; the first motion starts at the
//! machine origin (all six axes zero), as LinuxCNC's `rs274` and a simulator without a
//! machine position assume.

use glam::DVec3;

use crate::gcode::path::Plane;
use crate::geom::NurbsCurve;

/// Where something comes from: a line of the main program or of a subroutine file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Loc {
    /// Which file: 0 is the main program; subroutine files are numbered in the order they
    /// were first opened.
    pub file: u16,
    /// 1-based line in that file (comments and blank lines counted).
    pub line: u32,
}

impl Loc {
    /// A line of the main program.
    #[must_use]
    pub fn main(line: u32) -> Self {
        Self { file: 0, line }
    }
}

/// A position of the six axes: X, Y, Z in mm (machine frame) and A, B, C in degrees.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// X, Y, Z of the controlled point (mm, machine frame).
    pub xyz: DVec3,
    /// A, B, C rotary axes (degrees).
    pub abc: DVec3,
}

impl Pose {
    /// A pose with the rotary axes at zero.
    #[must_use]
    pub fn at(xyz: DVec3) -> Self {
        Self { xyz, abc: DVec3::ZERO }
    }
}

/// How the feed of a motion is given (RS274/NGC group 5: G93, G94, G95).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FeedMode {
    /// G94: `rate` is mm/min along the path (or degrees/min for a rotary-only move).
    #[default]
    PerMinute,
    /// G93 inverse time: the move takes `1 / rate` minutes; `rate` is 1/min.
    InverseTime,
    /// G95: `rate` is mm per spindle revolution.
    PerRevolution,
}

/// The feed of a cutting motion.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Feed {
    /// How `rate` is meant.
    pub mode: FeedMode,
    /// The programmed F in the mode's unit: mm/min (G94), 1/min (G93), mm/rev (G95); inch
    /// programs are converted to mm. Zero when the program gave none (LinuxCNC moves at
    /// F0 too: such a move is reported).
    pub rate: f64,
    /// Spindle speed in force (rev/min; 0 when stopped), for G95 feeds.
    pub spindle_rpm: f64,
}

/// Why a canonical motion was made, when it was not programmed as such: a canned cycle's
/// moves, a cutter-compensation corner, a reference return.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Origin {
    /// Programmed as this motion (G0, G1, G2, G3, a spline).
    #[default]
    Programmed,
    /// One of the moves of a canned cycle (G73, G81–G89).
    Cycle,
    /// Added by cutter radius compensation (a corner arc or an entry/exit move).
    Compensation,
    /// A G28/G30 return through its intermediate point.
    Reference,
    /// A probing move (G38.x), taken to its programmed end.
    Probe,
}

/// One canonical call.
#[derive(Clone, Debug, PartialEq)]
pub enum Canon {
    /// Straight move at the machine's rapid rate (G0).
    Traverse {
        /// Source.
        loc: Loc,
        /// End pose.
        end: Pose,
        /// Why.
        origin: Origin,
    },
    /// Straight move at feed (G1, and the feed moves of cycles).
    Line {
        /// Source.
        loc: Loc,
        /// End pose.
        end: Pose,
        /// Feed in force.
        feed: Feed,
        /// Why.
        origin: Origin,
    },
    /// Circular or helical move at feed (G2/G3).
    Arc {
        /// Source.
        loc: Loc,
        /// End pose.
        end: Pose,
        /// Centre (mm, machine frame); its coordinate along the plane's normal is the start's.
        center: DVec3,
        /// The plane (G17/G18/G19); XY-rotation never tilts it.
        plane: Plane,
        /// LinuxCNC's rotation count: positive counter-clockwise (G3), negative clockwise
        /// (G2), seen from the plane normal's positive side; |turns| = 1 turns less than a
        /// full circle (or exactly one when the end equals the start in the plane), each
        /// further unit one more full turn (the `P` word).
        turns: i32,
        /// Feed in force.
        feed: Feed,
        /// Why.
        origin: Origin,
    },
    /// A NURBS or polynomial spline at feed (G5, G5.1, G5.2/G5.3, G6.2), as one NURBS curve
    /// in the machine frame (mm); the rotary axes stay where they are.
    Spline {
        /// Source (the line of the G-word that started the curve).
        loc: Loc,
        /// The curve; it starts at the current position.
        curve: Box<NurbsCurve>,
        /// End pose (the curve's end).
        end: Pose,
        /// Feed in force.
        feed: Feed,
    },
    /// G4: wait.
    Dwell {
        /// Source.
        loc: Loc,
        /// Seconds.
        seconds: f64,
    },
    /// M6 (or M61: no motion, the table's tool declared in the spindle).
    ToolChange {
        /// Source.
        loc: Loc,
        /// The tool number now in the spindle (0: none).
        tool: i32,
    },
    /// G43/G43.1/G43.2/G49: the tool length offset in force from here on (mm; `Z` along the
    /// spindle, X for lathes; zero when cancelled).
    ToolLengthOffset {
        /// Source.
        loc: Loc,
        /// Offset (mm).
        offset: DVec3,
    },
    /// Spindle speed or direction changed (S, M3, M4, M5).
    Spindle {
        /// Source.
        loc: Loc,
        /// Speed (rev/min), signed: positive M3, negative M4, zero stopped.
        rpm: f64,
    },
    /// Program stop (M0, M1) or end (M2, M30, `%` at the end).
    Stop {
        /// Source.
        loc: Loc,
        /// True at the program's end.
        end: bool,
    },
}

impl Canon {
    /// Where the call comes from.
    #[must_use]
    pub fn loc(&self) -> Loc {
        match self {
            Self::Traverse { loc, .. }
            | Self::Line { loc, .. }
            | Self::Arc { loc, .. }
            | Self::Spline { loc, .. }
            | Self::Dwell { loc, .. }
            | Self::ToolChange { loc, .. }
            | Self::ToolLengthOffset { loc, .. }
            | Self::Spindle { loc, .. }
            | Self::Stop { loc, .. } => *loc,
        }
    }

    /// The end pose of a motion; `None` for calls that do not move.
    #[must_use]
    pub fn end(&self) -> Option<Pose> {
        match self {
            Self::Traverse { end, .. } | Self::Line { end, .. } | Self::Arc { end, .. } | Self::Spline { end, .. } => {
                Some(*end)
            }
            _ => None,
        }
    }
}
