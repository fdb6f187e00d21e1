//! Why a run of the simulation job stops: one variant a cause, each message the text the page
//! shows (the job hands it over as a [`JobError`]: [`super::SimulateRun`]'s output is
//! `Result<_, JobError>`).

use thiserror::Error;

use super::request::MAX_RAYS;
use crate::fiveaxis::FiveAxisError;
use crate::gcode::{DesignError, ParseError, ProgramError};
use crate::jobs::JobError;
use crate::scene::SceneError;
use crate::simulate::SimError;

/// Why a run of the simulation job stops.
#[derive(Clone, Debug, Error)]
pub enum SimulateError {
    /// The job was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The scene of the program or the design cannot be read.
    #[error("the scene: {0}")]
    Scene(SceneError),
    /// The finishing scene cannot be read.
    #[error("the finishing scene: {0}")]
    FinishScene(SceneError),
    /// The scene's tool-axis rule cannot be built.
    #[error(transparent)]
    ToolAxis(SceneError),
    /// The scene's crease cannot be started.
    #[error("the scene's crease cannot be run — {0}")]
    CreaseStart(DesignError),
    /// The scene's crease gives no design curve.
    #[error("the scene's crease gives no design curve — {0}")]
    CreaseCurve(DesignError),
    /// The seed-002 steps cannot be planned.
    #[error("the 5-axis steps cannot be planned — {0}")]
    Steps(FiveAxisError),
    /// The crease's program cannot be written.
    #[error("the {kind} program cannot be written — {source}")]
    Write {
        /// The program's kind (`ProgramKind::label`).
        kind: &'static str,
        /// Why.
        source: ProgramError,
    },
    /// A G-code text that the reader cannot follow.
    #[error("{name} is not a program this reader can follow — {source}")]
    Read {
        /// The program's name.
        name: String,
        /// Why.
        source: ParseError,
    },
    /// A finishing program's step tolerance (mm) that is not a positive length.
    #[error("the step tolerance must be a positive length in mm, got {0}; give e.g. 0.01")]
    StepTolerance(f64),
    /// No stock block was given and the program has no cutting move to size one from.
    #[error("the program has no cutting move to size the stock from; give the stock block")]
    NoCuttingMove,
    /// The grid has more than [`MAX_RAYS`] rays.
    #[error(
        "a pitch of {pitch_mm} mm on this stock gives {nx} × {ny} rays, more than the {MAX_RAYS} this view simulates; raise the pitch or shrink the stock"
    )]
    TooManyRays {
        /// The pitch (mm).
        pitch_mm: f64,
        /// Rays in x, as counted for the message.
        nx: String,
        /// Rays in y, as counted for the message.
        ny: String,
    },
    /// The simulation's own refusal: the program, the stock or the work bound.
    #[error(transparent)]
    Sim(#[from] SimError),
}

impl From<SimulateError> for JobError {
    fn from(e: SimulateError) -> Self {
        match e {
            SimulateError::Cancelled => Self::Cancelled,
            e => Self::failed(e),
        }
    }
}
