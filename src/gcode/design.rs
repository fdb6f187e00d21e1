//! The design path of a scene: the cutter-centre crease, interpolated once with the default
//! options and held as a [`CreaseCurve`] (a C¹ Hermite path through the periods' centres
//! with the exact crease tangents, parametrised by chord length in mm).

use thiserror::Error;

use crate::crease::{CreaseCurve, CreaseError, CreaseJob, InterpOptions, Interpolator, Row, Step};

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
    let mut builder = DesignBuilder::new(job)?;
    loop {
        if let Some(design) = builder.advance(usize::MAX) {
            return design;
        }
    }
}

/// [`crease_design`] a number of periods at a time, for callers that must not block (the
/// app runs a few thousand periods per frame): the rows of `run_to_end` with the default
/// options, so the same curve however the run is split.
#[derive(Clone, Debug)]
pub struct DesignBuilder {
    job: CreaseJob,
    interp: Interpolator,
    rows: Vec<Row>,
}

impl DesignBuilder {
    /// Starts the crease of `job`.
    ///
    /// # Errors
    /// [`DesignError::Crease`] when the crease cannot be started.
    pub fn new(job: &CreaseJob) -> Result<Self, DesignError> {
        let interp = Interpolator::new(job.clone(), InterpOptions::default()).map_err(DesignError::Crease)?;
        let rows = vec![interp.first_row()];
        Ok(Self { job: job.clone(), interp, rows })
    }

    /// Periods run so far.
    #[must_use]
    pub fn periods(&self) -> usize {
        self.rows.len() - 1
    }

    /// Runs at most `periods` more periods; once the crease has ended, the design curve (or
    /// why there is none).
    pub fn advance(&mut self, periods: usize) -> Option<Result<CreaseCurve, DesignError>> {
        for _ in 0..periods {
            match self.interp.step() {
                Ok(Step::Row(r)) => self.rows.push(r),
                Ok(Step::Stopped(_)) => {
                    return Some(
                        CreaseCurve::from_rows(&self.job, &self.rows).ok_or(DesignError::TooShort(self.rows.len())),
                    );
                }
                Err(e) => return Some(Err(DesignError::Crease(e))),
            }
        }
        None
    }
}
