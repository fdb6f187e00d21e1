//! G-code out (G01 chords, G02/G03 arcs, FANUC-style G06.2 NURBS) and in (parsing and
//! replaying programs against the design path) — seed 004's comparison of line, line-and-arc
//! and NURBS programs.
//!
//! Glossary:
//! - *design path*: the curve the program must follow, by default the crease's ball-centre
//!   path ([`design::crease_design`]);
//! - *programmed point*: the point of the tool the coordinates carry (ball centre, or the
//!   ball tip of a 3-axis ball end mill);
//! - *resolution*: the machine's least input increment; every written number is rounded to
//!   it, and programs are checked after that rounding;
//! - *path blocks*: the blocks describing the cut (G01/G02/G03 moves; for G06.2 one block per
//!   control point plus `order` closing knot blocks);
//! - *deviation*: the two-sided distance between a program's cutting moves and the design
//!   path ([`replay::deviation`]).
//!
//! Modules: [`path`] the geometry of moves; [`kind`] the three program kinds; [`dialect`] the
//! controllers' words; [`comment`] the one way text enters a program (every comment any
//! writer writes, user text made safe); [`arcs`] tolerance-driven arc fitting;
//! [`mod@write`] the three program writers with the rounding check; [`parse`] the reader;
//! [`replay`] deviation and summary; [`mod@compare`] the comparison table; [`design`] the design
//! path of a scene. All are pure functions of (curve, tolerance, options), for the command
//! line and the app alike.

pub mod arcs;
pub mod comment;
pub mod compare;
pub mod design;
pub mod dialect;
pub mod interp;
pub mod kind;
pub mod parse;
pub mod path;
pub mod read;
pub mod replay;
pub mod write;

pub use comment::safe_comment;
pub use compare::{
    CompareOptions, CompareRow, Comparison, ExtraColumns, TableStyle, compare, compare_row, format_comparison,
    format_comparisons, format_comparisons_with, realtime_stats,
};
pub use design::{DesignBuilder, DesignError, crease_design};
pub use dialect::{Dialect, HeaderKey, UnknownDialect};
pub use kind::ProgramKind;
pub use parse::{ParseError, ParsedProgram, Unsupported};
pub use path::{ArcMove, LineMove, Motion, PathBlock, Plane, Segment, Toolpath};
pub use read::{
    ProgramReader, parse_program, parse_program_in, read_from, read_from_capped, read_from_weighted, read_program,
    read_streamed,
};
pub use replay::{Deviation, DeviationOptions, ProgramSummary, ReplayError, Summarizer, deviation, summarize};
pub use write::{Program, ProgramError, ProgramOptions, ProgrammedPoint, write_program};
