//! A cutting simulation as a background job: the program written (the scene's crease as G01,
//! G02/G03 or G06.2, the scene's seed-002 tool steps) or read (a G-code text) or given (moves
//! made by an earlier run), machined into a dexel stock up to a target move by
//! [`Simulation`](crate::simulate::Simulation), and measured against the design
//! ([`DeviationScan`](crate::simulate::DeviationScan)), by the steps the command line shares
//! ([`crate::simulate::pipeline`]). A long program takes seconds in a browser; in a Web Worker
//! the page stays responsive.
//!
//! While it runs the job hands back, as partial outputs ([`Partial`]): the program once it is
//! made ([`Prepared`](output::Prepared): the moves, the stock and the grid), then **keyframes**
//! of the stock — its top heights as `f32` and which rays are machined — every `N` moves, `N`
//! chosen so a run sends at most [`Request::keyframes`] of them and at most
//! [`run::KEYFRAME_BYTES`] in all. The page shows the latest keyframe while the run goes on,
//! and, when the user scrubs the move slider back, the keyframe at or before the move at once;
//! the exact stock at that move comes from a new run of this job to that move with the moves of
//! the first ([`ProgramSource::Moves`](request::ProgramSource::Moves): no crease, plan or
//! program written again). The output is the stock's exact height map and its measures at the
//! target move.
//!
//! Everything crosses as text: numbers by their bits, large arrays packed as base64url of
//! their little-endian bytes (a 256 × 256 keyframe is 437 KB of text, the final map with its
//! deviations 1.4 MB; a run without a design sends no deviations: 0.8 MB).
//!
//! Files, one concern each: [`request`] (what a run is asked: the program's source, the
//! stock, the design), [`program`] (the program made from its source, the stock and pitch
//! chosen for it), [`run`] (the run: machining, keyframes, measures), [`session`] (the
//! stocks kept between runs of one program), [`output`] (what a run hands back), [`codec`]
//! (all of it as text), [`error`] (why a run stops), and the job's progress reports
//! (`progress.rs`).

use super::{DecodeError, JobError, JobKind, Progress};
use output::{Finished, Partial};
use request::Request;

pub mod codec;
pub mod error;
pub mod output;
pub mod program;
mod progress;
pub mod request;
pub mod run;
pub mod session;

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct SimulateRun;

impl JobKind for SimulateRun {
    const NAME: &'static str = "simulate-run";
    type Request = Request;
    type Output = Result<Finished, JobError>;
    type Partial = Partial;

    fn run(req: &Request, progress: &mut dyn Progress) -> Self::Output {
        run::run_in_session(req, progress, &session::SESSION).map_err(JobError::from)
    }

    fn encode_request(r: &Request) -> String {
        codec::encode_request(r)
    }

    fn decode_request(text: &str) -> Result<Request, DecodeError> {
        codec::decode_request(text)
    }

    fn encode_output(out: &Self::Output) -> String {
        codec::encode_output(out)
    }

    fn decode_output(text: &str) -> Result<Self::Output, DecodeError> {
        codec::decode_output(text)
    }

    fn decode_partial(text: &str) -> Result<Partial, DecodeError> {
        codec::decode_partial(text)
    }
}

#[cfg(test)]
mod tests;
