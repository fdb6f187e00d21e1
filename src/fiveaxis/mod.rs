//! Seed 002 (Ji, Zhou, An & Zhang, 2010): five-axis machines, the nonlinear error of linear
//! joint interpolation, and tool-step selection along a path.
//!
//! Glossary:
//! - *block*: one programmed position of the machine — a cutter location and its joint
//!   values (X, Y, Z and two rotary angles);
//! - *tool tip*: the bottom of the ball, `centre − R·T`, the programmed point;
//! - *tool axis* T: unit vector from the tip toward the spindle;
//! - *swept curve*: the path the tool tip (or the ball centre) takes in workpiece
//!   coordinates while the joints move linearly between two blocks;
//! - *chord error* δt: the error of the straight programmed motion (arc–chord);
//! - *nonlinear error* δn: what the rotary axes add, δ − δt;
//! - *total error* δ = δt + δn, signed: overcut (gouge) +, undercut (stock) −.
//!
//! Modules: [`machine`] (kinematics of four structures), [`toolaxis`] (tool-axis rules),
//! [`path`] (design paths: the crease of a scene, a planar profile), [`swept`] (the swept
//! tool and its errors), [`stepsel`] (step selection so every segment's |δ| = E),
//! [`blade`] (NACA section), [`presets`] (the paper's Example 1, the Table-1 blade case).
//! Conventions: `docs/fiveaxis.md`.

pub mod blade;
pub mod machine;
pub mod path;
pub mod presets;
pub mod stepsel;
pub mod swept;
pub mod toolaxis;

use thiserror::Error;

use crate::numerics::format::fmt_num;

pub use blade::NacaProfile;
pub use machine::{Joints, KinematicsError, Machine, MachineKind, ToolPose};
pub use path::{CreasePath, CutterLocation, DesignPath, ProfileBall, ProfilePath, ToolSide};
pub use presets::{CircleArc, Example1, blade_case, example1};
pub use stepsel::{StepNode, StepOptions, StepPlan, StepPlanner, evaluate_nodes, plan_steps, rotary_step_rad};
pub use swept::{
    Block, Followed, SegmentReport, SegmentTotal, SweptPoint, block_at, design_deviation, segment_report,
    segment_total, swept_point, swept_samples, tip_design_deviation,
};
pub use toolaxis::{AxisFrame, ToolAxisRule};

/// Why a five-axis computation failed. Every message says where (path parameter s) and
/// what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FiveAxisError {
    /// The tolerance is not a positive length.
    #[error("the tolerance must be a positive length in mm, got {}; give e.g. 0.01", fmt_num(*tol_mm))]
    BadTolerance {
        /// The value given.
        tol_mm: f64,
    },
    /// The path's parameter range is empty.
    #[error("the path's parameter range [{start}, {end}] is empty; the crease run produced too few points")]
    EmptyPath {
        /// Start.
        start: f64,
        /// End.
        end: f64,
    },
    /// No joint values for a cutter location.
    #[error("at s = {s:.4} along the path: {source}")]
    Kinematics {
        /// Path parameter.
        s: f64,
        /// The kinematic problem.
        source: KinematicsError,
    },
    /// The tool-axis rule is undefined at a location.
    #[error(
        "at s = {s:.4} along the path the tool-axis rule `{rule}` is undefined (opposite normals, a zero vector or a singular point); choose another tool_axis rule"
    )]
    ToolAxis {
        /// Path parameter.
        s: f64,
        /// The rule's name.
        rule: &'static str,
    },
    /// The exact crease point could not be found.
    #[error(
        "at s = {s:.4} mm along the crease the exact crease point could not be found; shorten the path (path.end) or check the surfaces there"
    )]
    Crease {
        /// Path parameter.
        s: f64,
    },
    /// An error value was NaN or infinite.
    #[error("the swept error is not finite near s = {s:.4}; check the machine's pivots and the tool-axis rule")]
    NotFinite {
        /// Path parameter.
        s: f64,
    },
    /// Even the shortest step exceeds the tolerance.
    #[error(
        "at s = {s:.6} even the shortest segment has an error of {error_mm:.3e} mm, more than the tolerance {} mm: the steps underflow; raise the tolerance, or change the tool-axis rule if a rotary axis flips there",
        fmt_num(*tol_mm)
    )]
    Underflow {
        /// Path parameter of the current node.
        s: f64,
        /// Error of the shortest segment tried (mm).
        error_mm: f64,
        /// The tolerance (mm).
        tol_mm: f64,
    },
    /// The root search did not converge.
    #[error("the step search after s = {s:.6} did not converge in {evaluations} evaluations; raise the tolerance")]
    NoConvergence {
        /// Path parameter.
        s: f64,
        /// Evaluations spent.
        evaluations: u32,
    },
    /// Too many nodes.
    #[error(
        "a tolerance of {} mm needs more than {max_nodes} nodes (stopped at s = {s:.4}); raise the tolerance",
        fmt_num(*tol_mm)
    )]
    TooManyNodes {
        /// The tolerance (mm).
        tol_mm: f64,
        /// The limit.
        max_nodes: usize,
        /// How far the nodes got.
        s: f64,
    },
    /// Planning a program's steps would pass the design evaluations it may spend (a
    /// finishing program: [`crate::fillet::program::MAX_PLAN_DESIGNS`], less what the
    /// command's paths spent).
    #[error(
        "planning the steps would pass the {max:.2e} design evaluations left for it: {evaluations} by s = {s:.4}, on course for about {projected:.2e} over the whole program; raise the tolerance, or the scallop height for fewer paths"
    )]
    TooMuchWork {
        /// Path parameter where the planning stopped.
        s: f64,
        /// Design evaluations spent so far.
        evaluations: u64,
        /// The whole program's, projected from those (at least the evaluations spent).
        projected: f64,
        /// What the planning may spend.
        max: f64,
    },
}
