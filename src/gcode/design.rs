//! The design path of a scene: the cutter-centre crease, interpolated once with the default
//! options and held as a [`CreaseCurve`] (a C¹ Hermite path through the periods' centres
//! with the exact crease tangents, parametrised by chord length in mm).

use thiserror::Error;

use crate::crease::{CreaseCurve, CreaseError, CreaseJob, InterpOptions, run_to_end};

/// Why a scene gives no design path.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum DesignError {
    /// The crease run failed.
    #[error("the crease cannot be interpolated: {0}")]
    Crease(CreaseError),
    /// Fewer than two points.
    #[error(
        "the crease run produced {0} point(s); a path needs at least two — check path.start, path.end and path.max_steps"
    )]
    TooShort(usize),
}

/// Runs the crease of `job` to its end and returns it as a design curve.
///
/// # Errors
/// [`DesignError`] when the crease cannot be run or is too short.
pub fn crease_design(job: &CreaseJob) -> Result<CreaseCurve, DesignError> {
    let run = run_to_end(job.clone(), InterpOptions::default());
    if let Err(e) = run.outcome {
        return Err(DesignError::Crease(e));
    }
    CreaseCurve::from_rows(job, &run.rows).ok_or(DesignError::TooShort(run.rows.len()))
}
