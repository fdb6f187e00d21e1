//! The command line `interpolab`, run as a user or a script would (a process per case: native
//! only). One module per command family, as in `src/cli/`. Where a new test goes:
//! tests/README.md.
//!
//! Run one family: `cargo test --no-default-features --test cli simulate::`.
#![cfg(not(target_arch = "wasm32"))]

// Issue 11's cases: bounded memory and one-line refusals.
mod bounded;
// `interpolab finish` (seed 001).
mod fillet;
// `interpolab steps`, `example1`, `table1`, `chords` (seeds 002, 003).
mod fiveaxis;
// `interpolab gcode`, `replay`, `compare`, `nurbs` (seed 004).
mod gcode;
// User text through every writer of the command line.
mod hostile;
// A user's program with its tools and machine: simulate, replay, canon.
mod userprog;
// `interpolab run` and `check` (seed 000).
mod run;
// `interpolab simulate`.
mod simulate;
