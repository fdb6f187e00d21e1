//! Background jobs: work that takes longer than a frame, described so it can run anywhere —
//! on a native thread, or in the browser in a Web Worker running this core compiled to wasm
//! (a second wasm module without egui or wgpu: the `interpolab-worker` binary, feature
//! `worker`).
//!
//! A job kind ([`JobKind`]) is a plain function from a request to an output, plus a text
//! encoding of both, so a request can cross into a worker and its output come back through
//! `postMessage`. Floating-point numbers are encoded by their bits ([`f64::to_bits`]), so an
//! output decoded on the other side is the one computed, bit for bit. The app's runner
//! (`app::jobs`) starts, polls and cancels jobs; this module only defines them and, for the
//! worker, answers a request by its kind's name ([`run_encoded`]).
//!
//! Every kind's output is `Result<_, JobError>`: [`JobError`] tells a cancellation from a
//! failure, whose message is the kind's own typed error as the user reads it.
//!
//! A job may also hand back *partial* outputs while it runs ([`Progress::partial`], e.g. the
//! stock's heights every so many moves of a cutting simulation), in the same text encoding.
//!
//! Kinds: [`program_row::ProgramRow`] (one program of the NURBS & G-code comparison),
//! [`fillet_row::FilletRow`] (one row of the fillet tab's comparison table),
//! [`simulate_run::SimulateRun`] (a cutting simulation: the program written, machined and
//! measured, with keyframes of the stock on the way), [`user_program::UserProgram`] (a user's
//! program with its tools and machine: read, drawn, machined), [`program_time::ProgramTime`]
//! (that program's feed planned and timed on a machine's dynamics).

pub mod fillet_row;
pub mod program_row;
pub mod program_time;
pub mod simulate_run;
pub mod user_program;

use glam::DVec3;
use serde_json::Value;
use thiserror::Error;

/// Why an encoded request, output or partial output cannot be read: a message naming the
/// malformed field (e.g. `program-row request.point: "x" is neither centre nor tip`). Only a
/// page and a worker of different builds, or a bug, give one; a job's own failure is its
/// output's error instead, in the user's terms.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("{0}")]
pub struct DecodeError(String);

impl From<String> for DecodeError {
    fn from(message: String) -> Self {
        Self(message)
    }
}

impl From<&str> for DecodeError {
    fn from(message: &str) -> Self {
        Self(message.to_owned())
    }
}

/// Why the worker cannot answer a message ([`run_encoded`]).
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum WorkerError {
    /// No job kind has that name.
    #[error("the worker knows no job \"{0}\"")]
    UnknownJob(String),
    /// The request does not decode.
    #[error(transparent)]
    Request(#[from] DecodeError),
}

/// Why a job gives no result: the one error every kind's output carries
/// (`Result<_, JobError>`). Each kind has its own typed error inside, in the user's terms
/// ([`program_row::RowError`], [`simulate_run::error::SimulateError`], …); at the job's
/// edge it is either a cancellation or a failure with that error's message, because the
/// output crosses into and out of a Web Worker as text ([`JobError::encode`],
/// [`JobError::decode`]).
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum JobError {
    /// The job was cancelled before it finished ([`Progress::cancelled`]).
    #[error("cancelled")]
    Cancelled,
    /// The job failed: the message shown to the user, as the kind's own error words it.
    #[error("{0}")]
    Failed(String),
}

impl JobError {
    /// A failure with `error`'s message.
    pub fn failed(error: impl std::fmt::Display) -> Self {
        Self::Failed(error.to_string())
    }

    /// The error as an encoded output: `{"error":"message"}` for a failure,
    /// `{"cancelled":true}` for a cancellation.
    #[must_use]
    pub fn encode(&self) -> String {
        match self {
            Self::Cancelled => serde_json::json!({ "cancelled": true }),
            Self::Failed(message) => serde_json::json!({ "error": message }),
        }
        .to_string()
    }

    /// The error an encoded output `v` of `what` (e.g. `"program-row output"`) carries, if it
    /// is one ([`JobError::encode`]); `None` for an output that is not an error.
    ///
    /// # Errors
    /// An error field that is not text, or a cancellation that is not `true`.
    pub fn decode(v: &Value, what: &str) -> Result<Option<Self>, DecodeError> {
        if let Some(c) = v.get("cancelled") {
            return match c {
                Value::Bool(true) => Ok(Some(Self::Cancelled)),
                _ => Err(format!("{what}.cancelled: not true").into()),
            };
        }
        match v.get("error") {
            None => Ok(None),
            Some(e) => e
                .as_str()
                .map(|m| Some(Self::Failed(m.to_owned())))
                .ok_or_else(|| format!("{what}.error: not text").into()),
        }
    }
}

/// What a running job reports besides its output.
pub trait Progress {
    /// Fraction done, 0 to 1 (for a progress bar).
    fn progress(&mut self, fraction: f64);
    /// Whether the job was cancelled (a job may stop early and return anything).
    fn cancelled(&self) -> bool;
    /// A partial output as text, to be read by its kind's [`JobKind::decode_partial`] (default: dropped).
    fn partial(&mut self, _encoded: String) {}
}

/// A kind of background job.
pub trait JobKind: 'static {
    /// Its name in messages to the worker (unique among kinds).
    const NAME: &'static str;
    /// What the job is given.
    type Request: Send + 'static;
    /// What it gives back (every kind: `Result<_, JobError>`).
    type Output: Send + 'static;
    /// What it may hand back while it runs (`()` for kinds that hand back nothing early).
    type Partial: Send + 'static;
    /// Does the work.
    fn run(request: &Self::Request, progress: &mut dyn Progress) -> Self::Output;
    /// The request as text.
    fn encode_request(request: &Self::Request) -> String;
    /// The request from its text.
    ///
    /// # Errors
    /// A message naming what is malformed.
    fn decode_request(text: &str) -> Result<Self::Request, DecodeError>;
    /// The output as text.
    fn encode_output(output: &Self::Output) -> String;
    /// The output from its text.
    ///
    /// # Errors
    /// A message naming what is malformed.
    fn decode_output(text: &str) -> Result<Self::Output, DecodeError>;
    /// A partial output from its text ([`Progress::partial`]).
    ///
    /// # Errors
    /// A message naming what is malformed.
    fn decode_partial(text: &str) -> Result<Self::Partial, DecodeError>;
}

/// Runs an encoded request of the kind named `name` and returns its encoded output: what a
/// worker does with a message.
///
/// # Errors
/// An unknown kind or a malformed request.
pub fn run_encoded(name: &str, request: &str, progress: &mut dyn Progress) -> Result<String, WorkerError> {
    fn go<K: JobKind>(request: &str, progress: &mut dyn Progress) -> Result<String, WorkerError> {
        let req = K::decode_request(request)?;
        Ok(K::encode_output(&K::run(&req, progress)))
    }
    match name {
        program_row::ProgramRow::NAME => go::<program_row::ProgramRow>(request, progress),
        fillet_row::FilletRow::NAME => go::<fillet_row::FilletRow>(request, progress),
        simulate_run::SimulateRun::NAME => go::<simulate_run::SimulateRun>(request, progress),
        user_program::UserProgram::NAME => go::<user_program::UserProgram>(request, progress),
        program_time::ProgramTime::NAME => go::<program_time::ProgramTime>(request, progress),
        _ => Err(WorkerError::UnknownJob(name.to_owned())),
    }
}

/// A [`Progress`] that ignores reports and is never cancelled.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn progress(&mut self, _fraction: f64) {}
    fn cancelled(&self) -> bool {
        false
    }
}

// ---- encoding helpers: f64 by bits, so values cross unchanged ----

pub(crate) fn num(x: f64) -> Value {
    Value::from(x.to_bits())
}

pub(crate) fn vec3(v: DVec3) -> Value {
    Value::from(vec![num(v.x), num(v.y), num(v.z)])
}

pub(crate) fn nums(xs: impl IntoIterator<Item = f64>) -> Value {
    Value::from(xs.into_iter().map(num).collect::<Vec<_>>())
}

/// Reading an encoded object field by field, with the field's name in every error.
pub(crate) struct Reader<'a> {
    obj: &'a serde_json::Map<String, Value>,
    what: &'static str,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(v: &'a Value, what: &'static str) -> Result<Self, DecodeError> {
        v.as_object().map(|obj| Self { obj, what }).ok_or_else(|| DecodeError::from(format!("{what}: not an object")))
    }
    pub(crate) fn value(&self, key: &str) -> Result<&'a Value, DecodeError> {
        self.obj.get(key).ok_or_else(|| DecodeError::from(format!("{}: no field \"{key}\"", self.what)))
    }
    pub(crate) fn f64(&self, key: &str) -> Result<f64, DecodeError> {
        as_f64(self.value(key)?).ok_or_else(|| DecodeError::from(format!("{}.{key}: not an encoded number", self.what)))
    }
    pub(crate) fn opt_f64(&self, key: &str) -> Result<Option<f64>, DecodeError> {
        match self.value(key)? {
            Value::Null => Ok(None),
            v => as_f64(v)
                .map(Some)
                .ok_or_else(|| DecodeError::from(format!("{}.{key}: not an encoded number", self.what))),
        }
    }
    pub(crate) fn usize(&self, key: &str) -> Result<usize, DecodeError> {
        self.value(key)?
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| DecodeError::from(format!("{}.{key}: not a count", self.what)))
    }
    pub(crate) fn str(&self, key: &str) -> Result<&'a str, DecodeError> {
        self.value(key)?.as_str().ok_or_else(|| DecodeError::from(format!("{}.{key}: not text", self.what)))
    }
    pub(crate) fn vec3(&self, key: &str) -> Result<DVec3, DecodeError> {
        let xs = self.f64s(key)?;
        match xs[..] {
            [x, y, z] => Ok(DVec3::new(x, y, z)),
            _ => Err(format!("{}.{key}: not three numbers", self.what).into()),
        }
    }
    pub(crate) fn f64s(&self, key: &str) -> Result<Vec<f64>, DecodeError> {
        self.value(key)?
            .as_array()
            .and_then(|a| a.iter().map(as_f64).collect::<Option<Vec<_>>>())
            .ok_or_else(|| DecodeError::from(format!("{}.{key}: not a list of encoded numbers", self.what)))
    }
}

fn as_f64(v: &Value) -> Option<f64> {
    v.as_u64().map(f64::from_bits)
}

/// Floats as the base64url text of their little-endian bytes: a large array crosses as a
/// compact string, each value bit for bit.
pub(crate) fn f64s_packed(xs: &[f64]) -> Value {
    let bytes: Vec<u8> = xs.iter().flat_map(|x| x.to_le_bytes()).collect();
    Value::from(crate::scene::link::base64url_encode(&bytes))
}

/// Single-precision floats packed as [`f64s_packed`] does.
pub(crate) fn f32s_packed(xs: &[f32]) -> Value {
    let bytes: Vec<u8> = xs.iter().flat_map(|x| x.to_le_bytes()).collect();
    Value::from(crate::scene::link::base64url_encode(&bytes))
}

/// Flags packed eight to a byte (bit i of byte i / 8 is flag i), as base64url text.
pub(crate) fn bits_packed(flags: &[bool]) -> Value {
    let mut bytes = vec![0u8; flags.len().div_ceil(8)];
    for (i, _) in flags.iter().enumerate().filter(|(_, f)| **f) {
        bytes[i / 8] |= 1 << (i % 8);
    }
    Value::from(crate::scene::link::base64url_encode(&bytes))
}

impl Reader<'_> {
    fn packed(&self, key: &str) -> Result<Vec<u8>, DecodeError> {
        self.str(key)
            .ok()
            .and_then(crate::scene::link::base64url_decode)
            .ok_or_else(|| DecodeError::from(format!("{}.{key}: not packed data", self.what)))
    }
    /// `n` floats packed by [`f64s_packed`].
    pub(crate) fn f64s_packed(&self, key: &str, n: usize) -> Result<Vec<f64>, DecodeError> {
        let b = self.packed(key)?;
        if b.len() != 8 * n {
            return Err(format!("{}.{key}: {} bytes for {n} numbers", self.what, b.len()).into());
        }
        Ok(b.chunks_exact(8).map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])).collect())
    }
    /// `n` floats packed by [`f32s_packed`].
    pub(crate) fn f32s_packed(&self, key: &str, n: usize) -> Result<Vec<f32>, DecodeError> {
        let b = self.packed(key)?;
        if b.len() != 4 * n {
            return Err(format!("{}.{key}: {} bytes for {n} numbers", self.what, b.len()).into());
        }
        Ok(b.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
    }
    /// `n` flags packed by [`bits_packed`].
    pub(crate) fn bits_packed(&self, key: &str, n: usize) -> Result<Vec<bool>, DecodeError> {
        let b = self.packed(key)?;
        if b.len() != n.div_ceil(8) {
            return Err(format!("{}.{key}: {} bytes for {n} flags", self.what, b.len()).into());
        }
        Ok((0..n).map(|i| b[i / 8] & (1 << (i % 8)) != 0).collect())
    }
}

pub(crate) fn parse(text: &str, what: &'static str) -> Result<Value, DecodeError> {
    serde_json::from_str(text).map_err(|e| format!("{what}: not JSON ({e})").into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(e: &JobError) -> Option<JobError> {
        let text = e.encode();
        JobError::decode(&parse(&text, "test output").unwrap(), "test output").unwrap()
    }

    /// A cancellation crosses as a cancellation, never as a failure whose text says so.
    #[test]
    fn a_cancellation_round_trips() {
        assert_eq!(round_trip(&JobError::Cancelled), Some(JobError::Cancelled));
        assert_eq!(JobError::Cancelled.to_string(), "cancelled");
    }

    /// A failure crosses with its message byte for byte, even one that reads "cancelled".
    #[test]
    fn a_failure_round_trips_with_its_message() {
        for m in ["the scene: no field \"path\"", "cancelled", "", "tool 3: µ \u{1f}\n"] {
            let e = JobError::Failed(m.to_owned());
            assert_eq!(round_trip(&e), Some(e.clone()));
            assert_eq!(e.to_string(), m);
        }
    }

    /// An output that is not an error is none; a malformed error names its field.
    #[test]
    fn an_output_without_an_error_is_none_and_a_bad_one_is_refused() {
        let ok = parse(r#"{"passes": 3}"#, "t").unwrap();
        assert_eq!(JobError::decode(&ok, "t"), Ok(None));
        let bad = parse(r#"{"error": 3}"#, "t").unwrap();
        assert_eq!(JobError::decode(&bad, "t").unwrap_err().to_string(), "t.error: not text");
        let bad = parse(r#"{"cancelled": false}"#, "t").unwrap();
        assert_eq!(JobError::decode(&bad, "t").unwrap_err().to_string(), "t.cancelled: not true");
    }
}
