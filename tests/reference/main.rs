//! Against outside references run beside the product: LinuxCNC's own interpreter `rs274`
//! (`scripts/setup.sh test` installs Debian's `linuxcnc-uspace`), native only. Its runner and
//! the reader of its canonical calls are `tests/support/rs274.rs`.
//!
//! Run one: `cargo test --no-default-features --test reference interp::`.
#![cfg(not(target_arch = "wasm32"))]

#[path = "../support/mod.rs"]
mod support;

// The reference itself: rs274's output read and normalised, checked against positions
// computed from the programs' own numbers.
mod rs274;
// The interpreter against rs274: LinuxCNC's samples and our feature programs, call for call.
mod interp;
// Canned cycles, splines and tool tables against rs274.
mod cycles;
// The feed planner's single moves against Ruckig's S-curves (the `ruckig` crate).
mod plan_ruckig;
// The feed planner against TOPP-RA's time-optimal bound (tests/data/plan/topp_bounds.csv).
mod plan_topp;
