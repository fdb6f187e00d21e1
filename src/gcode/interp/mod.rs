//! The RS274/NGC interpreter: program text → [canonical motions](canon).
//!
//! It reads programs as LinuxCNC's interpreter does (RS274/NGC with LinuxCNC's parameters,
//! expressions and O-words) and the FANUC family's additions (`M98`/`M99` subprograms, Macro B
//! `IF`/`GOTO`/`WHILE`, `G65`, `G68` rotation, `G6.2` NURBS), applies every mode, offset and
//! unit, and emits one stream of [`canon::Canon`] calls in machine millimetres.

pub mod canon;
pub mod comp;

pub use canon::{Canon, Feed, FeedMode, Loc, Origin, Pose};
