//! The finishing scene as read from the file (seed 001), in file units (mm, degrees, mm/min,
//! 1/mm): what `parse.rs` produces and `finish.rs` turns into a job. A file of its own so the
//! two do not import each other (re-exported from [`super::finish`]).

use super::{MachineSpec, SurfaceSpec};

/// `finish.cutter` (mm). Absent dimensions take [`crate::geom::Cutter::fillet`]'s proportions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutterSpec {
    /// Cutter radius R (mm).
    pub radius: f64,
    /// Corner radius r (mm), 0 ≤ r ≤ R.
    pub corner_radius: f64,
    /// Flute length (mm; default 3R).
    pub flute_length: Option<f64>,
    /// Shank radius (mm; default R).
    pub shank_radius: Option<f64>,
    /// Gauge length, tip to holder (mm; default 6R).
    pub gauge_length: Option<f64>,
    /// Holder radius (mm; default 2.5R).
    pub holder_radius: Option<f64>,
    /// Holder length (mm; default 6R).
    pub holder_length: Option<f64>,
}

/// `finish.start`: where the iso-scallop paths start (file units).
#[derive(Clone, Debug, PartialEq)]
pub enum StartSpec {
    /// An edge of the domain by name: `u0`, `u1`, `v0` or `v1` (checked by the job).
    Boundary(String),
    /// `{"curve": [[u, v], …]}`: points in the surface's parameters, file units (degrees for
    /// angles, mm for lengths).
    Curve(Vec<[f64; 2]>),
}

/// `finish`: the cutter and the path parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishSpec {
    /// The cutter.
    pub cutter: CutterSpec,
    /// `matched` (default), `fixed-lead`, `principal` or `ball`.
    pub strategy: String,
    /// Lead angle for `fixed-lead` (degrees; default 5).
    pub lead: Option<f64>,
    /// Scallop height h (mm).
    pub scallop: f64,
    /// Chord tolerance E (mm): forward step, gouge tolerance and G-code steps.
    pub tolerance: f64,
    /// Longest forward step (mm; default 2).
    pub max_step: Option<f64>,
    /// `u`, `v` or `auto` (default).
    pub direction: String,
    /// Curvature margin m (1/mm; default 0.002).
    pub margin: Option<f64>,
    /// Smallest cross curvature Δκ `matched` leaves across the feed (1/mm; default 0.0125,
    /// 0 turns the floor off).
    pub min_cross_curvature: Option<f64>,
    /// Largest inclination of the axis from the normal (degrees; default 45).
    pub max_inclination: Option<f64>,
    /// Largest tilt |ψ| of the `matched` cutter's meridian off the feed (degrees; default 0:
    /// lead only).
    pub max_tilt: Option<f64>,
    /// Feed for the machining time and the G-code (mm/min; default 1000).
    pub feed: Option<f64>,
    /// Where the iso-scallop paths start (`None`: the first boundary of the direction).
    pub start: Option<StartSpec>,
}

/// A whole finishing scene in file units.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishScene {
    /// Display name.
    pub name: String,
    /// The surface to finish.
    pub surface: SurfaceSpec,
    /// Cutter and path parameters.
    pub finish: FinishSpec,
    /// The five-axis machine for G-code (`None`: the key is absent).
    pub machine: Option<MachineSpec>,
}
