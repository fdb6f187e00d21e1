//! # interpolab
//!
//! A CNC tool-path interpolation lab. The **core** (everything except `app` and `render`)
//! is plain Rust on `f64` with no GUI dependency; it builds for `wasm32-unknown-unknown` and
//! natively with `--no-default-features`. The **app** (feature `app`, on by default) draws
//! the core's results with egui/eframe and wgpu.
//!
//! Layers, bottom up; a module imports only modules of its own layer or below
//! (`python3 scripts/modgraph.py` checks it: its `LAYERS` are these floors):
//! - [`numerics::tolerance`], [`numerics::limits`], [`numerics::linalg`]: named tolerances,
//!   caps on input sizes and loops, small solves;
//! - [`geom`]: surfaces, NURBS, cutters, differential geometry, projection;
//! - [`numerics`] (its other files): number text, distances and arc lengths, maximisers, root
//!   finders, knots, plane fits, units, the sign of machining error;
//! - the papers, side by side (one imports another only where its method builds on that
//!   paper's, and never in a cycle):
//!   - [`crease`]: seed 000 — interpolation along the crease of two surfaces, the exact
//!     Newton crease, measured errors and the paper's estimates;
//!   - [`chords`]: seed 003 — equal-error chords;
//!   - [`nurbs_path`]: seed 004 — NURBS fitting and real-time NURBS interpolation;
//!   - [`fiveaxis`]: seed 002 — 5-axis machines, nonlinear error, tool-step selection;
//!   - [`gcode`]: G01/G02/G03/G06.2 programs out and in;
//!   - [`fillet`]: seed 001 — five-axis finishing with a fillet-end mill (iso-scallop paths);
//!   - [`plan`]: feed planning — joint limits, blended corners, jerk-limited feed, times;
//!   - [`simulate`]: cutting simulation on a dexel stock (any program, maps and statistics);
//! - [`scene`]: the `interpolab-scene/1` JSON format (parse, validate, write) and the jobs
//!   it describes; [`report`]: CSV/JSON output of runs (what the command line prints);
//! - [`jobs`]: background job kinds (a request, an output, an exact text encoding of both),
//!   run on a native thread or in the browser's Web Worker;
//! - `render` and `app` (feature `app`): GPU drawing of the 3D views, and the GUI;
//! - on top, this crate root and the binaries (`main.rs` with the command line `cli`, and
//!   `worker_main.rs`).
//!
//! Units: mm, seconds and radians inside; mm/min, ms and degrees only in files and UI.

#![forbid(unsafe_code)]

pub mod chords;
pub mod crease;
pub mod fillet;
pub mod fiveaxis;
pub mod gcode;
pub mod geom;
pub mod jobs;
pub mod numerics;
pub mod nurbs_path;
pub mod plan;
pub mod report;
pub mod scene;
pub mod simulate;

#[cfg(feature = "app")]
pub mod app;
#[cfg(feature = "app")]
pub mod render;
