//! The simulation job's progress: the overall fraction done, reported when it moved enough,
//! and the cancel flag.

use super::error::SimulateError;
use crate::jobs::Progress;

/// Smallest change of the fraction done worth a progress report.
const PROGRESS_STEP: f64 = 0.005;
/// Shares of the fraction done: the program is made in the first, the moves cut in the
/// second, the deviation measured in the rest.
pub(super) const PROGRAM_SHARE: f64 = 0.1;
pub(super) const RUN_SHARE: f64 = 0.8;

/// Reports the overall fraction done when it moved enough.
pub(super) struct Reporter<'a> {
    /// Where the reports go.
    pub(super) progress: &'a mut dyn Progress,
    /// The fraction last reported.
    last: f64,
}

impl<'a> Reporter<'a> {
    /// A reporter to `progress` that has reported nothing yet.
    pub(super) fn new(progress: &'a mut dyn Progress) -> Self {
        Self { progress, last: -1.0 }
    }

    /// Reports `fraction` done if it moved by [`PROGRESS_STEP`] or reached 1.
    pub(super) fn at(&mut self, fraction: f64) {
        if fraction - self.last >= PROGRESS_STEP || fraction >= 1.0 {
            self.last = fraction;
            self.progress.progress(fraction.min(1.0));
        }
    }
    /// [`SimulateError::Cancelled`] once the job was cancelled.
    pub(super) fn cancelled(&self) -> Result<(), SimulateError> {
        if self.progress.cancelled() { Err(SimulateError::Cancelled) } else { Ok(()) }
    }
}
