//! # interpolab
//!
//! A CNC tool-path interpolation lab. The **core** (everything except `app` and `render`)
//! is plain Rust on `f64` with no GUI dependency; it builds for `wasm32-unknown-unknown` and
//! natively with `--no-default-features`. The **app** (feature `app`, on by default) draws
//! the core's results with egui/eframe and wgpu.
//!
//! Layers, bottom up:
//! - [`numerics::linalg`], [`numerics::tolerance`]: small solves and named tolerances;
//! - [`geom`]: surfaces, NURBS, differential geometry, projection;
//! - [`scene`]: the `interpolab-scene/1` JSON format (parse, validate, write);
//! - [`crease`]: seed 000 — interpolation along the crease of two surfaces, the exact
//!   Newton crease, measured errors and the paper's estimates;
//! - [`fiveaxis`]: seed 002 — 5-axis machines, nonlinear error, tool-step selection;
//! - [`chords`]: seed 003 — equal-error chords;
//! - [`nurbs_path`]: seed 004 — NURBS fitting and real-time NURBS interpolation;
//! - [`gcode`]: G01/G02/G03/G06.2 programs out and in;
//! - [`simulate`]: cutting simulation on a dexel stock (any program, maps and statistics);
//! - [`report`]: CSV/JSON output of runs (what the command line prints).
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
