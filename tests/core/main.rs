//! The core's tests, one module per area of `src/` (natively with `--no-default-features`,
//! and the same sources compiled to wasm32 under Node). Each file swaps `#[test]` for
//! `wasm_bindgen_test` on wasm32; the few that need files or processes are
//! `#[cfg(not(target_arch = "wasm32"))]`. Where a new test goes: tests/README.md.
//!
//! Run one area: `cargo test --no-default-features --test core fiveaxis::`.

#[path = "../support/mod.rs"]
mod support;

/// `src/chords/`: equal-error chords (seed 003) and typed curves.
mod chords {
    mod equal_error;
    mod expr;
    mod planar;
}

/// `src/crease/`: the seed-000 interpolator, its failures, path ends and the b·T warning.
mod crease {
    mod failures;
    mod interpolation;
    mod path_ends;
    mod warning_screen;
}

// `src/fillet/`: seed 001's fillet-end finishing.
mod fillet;
// Seed 001 on random surfaces, cutters and heights it has never seen, judged by an independent
// swept-cutter height map (natively: its jobs take seconds each in a debug build).
#[cfg(not(target_arch = "wasm32"))]
mod fillet_unseen;

/// `src/fiveaxis/`: machines, the swept tool, step selection (seed 002).
mod fiveaxis {
    mod kinematics;
    mod planner;
    mod steps;
    mod swept;
    mod tip_design;
}

/// `src/gcode/`: programs out and in, the three dialects.
mod gcode {
    // Cutter radius compensation (`gcode::interp::comp`), with rs274 natively.
    mod comp;
    mod dialects;
    // User text in written programs: every writer, hostile names (proptest, native).
    #[cfg(not(target_arch = "wasm32"))]
    mod hostile;
    // The interpreter's short way for plain motion lines equals the general one.
    mod interp_plain;
    mod parse;
    mod roundtrip;
    // A program summarised move by move equals its held summary (what `replay` streams).
    mod summary;
}

/// `src/geom/`: differential geometry, derivatives, the Hermite path, NURBS evaluation.
mod geom {
    mod curvature;
    mod derivatives;
    mod hermite_path;
    mod nurbs;
}

// `src/jobs/`: a comparison row's time on a machine (the NURBS tab's and `compare --machine`'s).
mod jobs;

/// `src/nurbs_path/`: NURBS fitting and real-time NURBS interpolation (seed 004).
mod nurbs_path {
    mod fit;
    mod realtime;
}

// `src/report.rs`: the CSV/JSON number format.
mod report;

/// `src/scene/`: the scene format and its machine keys.
mod scene {
    mod format;
    mod machine;
}

/// `src/simulate/`: the dexel cutting simulation, and finishing programs through it.
mod simulate {
    // The whole tool: crashes of the shank, holder, rapids and plunges; flutes to their length.
    mod crash;
    mod dexel;
    mod finish;
    // The pipeline the command line and the app's job share: dialect, reading, point, sampling.
    mod pipeline;
    // A user's program: joint and TCP programs through the machines, nonlinear error per block.
    mod rotary;
    // A user's program: its tools, tool lengths, times and volumes.
    mod tools;
}

// `src/plan/`: feed planning — every period within the limits and the tolerance.
mod plan;
// `src/plan/steps.rs`: seed 002's step plans timed on their machine.
mod plan_steps;
