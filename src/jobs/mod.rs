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
//! Kinds: [`program_row::ProgramRow`] (one program of the NURBS & G-code comparison).

pub mod program_row;

use glam::DVec3;
use serde_json::Value;

/// What a running job reports besides its output.
pub trait Progress {
    /// Fraction done, 0 to 1 (for a progress bar).
    fn progress(&mut self, fraction: f64);
    /// Whether the job was cancelled (a job may stop early and return anything).
    fn cancelled(&self) -> bool;
}

/// A kind of background job.
pub trait JobKind: 'static {
    /// Its name in messages to the worker (unique among kinds).
    const NAME: &'static str;
    /// What the job is given.
    type Request: Send + 'static;
    /// What it gives back.
    type Output: Send + 'static;
    /// Does the work.
    fn run(request: &Self::Request, progress: &mut dyn Progress) -> Self::Output;
    /// The request as text.
    fn encode_request(request: &Self::Request) -> String;
    /// The request from its text.
    ///
    /// # Errors
    /// A message naming what is malformed.
    fn decode_request(text: &str) -> Result<Self::Request, String>;
    /// The output as text.
    fn encode_output(output: &Self::Output) -> String;
    /// The output from its text.
    ///
    /// # Errors
    /// A message naming what is malformed.
    fn decode_output(text: &str) -> Result<Self::Output, String>;
}

/// Runs an encoded request of the kind named `name` and returns its encoded output: what a
/// worker does with a message.
///
/// # Errors
/// An unknown kind or a malformed request.
pub fn run_encoded(name: &str, request: &str, progress: &mut dyn Progress) -> Result<String, String> {
    fn go<K: JobKind>(request: &str, progress: &mut dyn Progress) -> Result<String, String> {
        let req = K::decode_request(request)?;
        Ok(K::encode_output(&K::run(&req, progress)))
    }
    match name {
        program_row::ProgramRow::NAME => go::<program_row::ProgramRow>(request, progress),
        _ => Err(format!("the worker knows no job \"{name}\"")),
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
    pub(crate) fn new(v: &'a Value, what: &'static str) -> Result<Self, String> {
        v.as_object().map(|obj| Self { obj, what }).ok_or_else(|| format!("{what}: not an object"))
    }
    pub(crate) fn value(&self, key: &str) -> Result<&'a Value, String> {
        self.obj.get(key).ok_or_else(|| format!("{}: no field \"{key}\"", self.what))
    }
    pub(crate) fn f64(&self, key: &str) -> Result<f64, String> {
        as_f64(self.value(key)?).ok_or_else(|| format!("{}.{key}: not an encoded number", self.what))
    }
    pub(crate) fn opt_f64(&self, key: &str) -> Result<Option<f64>, String> {
        match self.value(key)? {
            Value::Null => Ok(None),
            v => as_f64(v).map(Some).ok_or_else(|| format!("{}.{key}: not an encoded number", self.what)),
        }
    }
    pub(crate) fn usize(&self, key: &str) -> Result<usize, String> {
        self.value(key)?
            .as_u64()
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| format!("{}.{key}: not a count", self.what))
    }
    pub(crate) fn str(&self, key: &str) -> Result<&'a str, String> {
        self.value(key)?.as_str().ok_or_else(|| format!("{}.{key}: not text", self.what))
    }
    pub(crate) fn vec3(&self, key: &str) -> Result<DVec3, String> {
        let xs = self.f64s(key)?;
        match xs[..] {
            [x, y, z] => Ok(DVec3::new(x, y, z)),
            _ => Err(format!("{}.{key}: not three numbers", self.what)),
        }
    }
    pub(crate) fn f64s(&self, key: &str) -> Result<Vec<f64>, String> {
        self.value(key)?
            .as_array()
            .and_then(|a| a.iter().map(as_f64).collect::<Option<Vec<_>>>())
            .ok_or_else(|| format!("{}.{key}: not a list of encoded numbers", self.what))
    }
}

fn as_f64(v: &Value) -> Option<f64> {
    v.as_u64().map(f64::from_bits)
}

pub(crate) fn parse(text: &str, what: &'static str) -> Result<Value, String> {
    serde_json::from_str(text).map_err(|e| format!("{what}: not JSON ({e})"))
}
