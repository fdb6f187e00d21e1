//! Tool paths over a whole surface: iso-scallop paths and, for comparison, iso-parametric
//! paths at the same worst scallop.
//!
//! Paths run along one parameter (the *along* parameter a, u or v) and follow each other
//! across the other (b). Along a path the CC points are spaced by the **forward step** from
//! the chord error E and the normal curvature k_f of the path: `ℓ = √(8E'/|k_f|)` with
//! E' = min(E, h/40) where the surface is convex along the feed, else E (the chord's sag
//! below a convex surface lowers the cusp; `SAG_SHARE_OF_H`), at most
//! [`FinishOptions::max_step_mm`]. The nodes of a path are oriented by the strategy and
//! smoothed ([`super::orient`]), checked for gouges ([`super::gouge`]), and then:
//!
//! - **iso-scallop**: the first path is where [`PathStart`] says: by default the boundary
//!   b = b_min, or another edge of the domain, or a curve through given parameters (extended
//!   to the a-boundaries). From every node of a path the
//!   **side step** w to the next path is solved so the scallop between the two cutters is h:
//!   the second-order guess `w = 2·√(2h/Δκ)` is corrected with the exact cross profiles of
//!   both cutters ([`crate::fillet::contact::CrossProfile`], [`crate::fillet::contact::scallop_between`]),
//!   `w ← w·√(h/scallop)`, until within 0.5 % of h (at most 12 rounds). The next path goes
//!   through the points w away across the surface (a walk along c in 4 sub-steps), cut at
//!   its self-intersections (swallowtails, `trim_swallowtails`) and at the a-boundaries
//!   (`clip_along`), with what is left of cusps dropped (a increasing); points beyond the far
//!   edge are put on it, its ends are extended to the a-boundaries along its end segments,
//!   and it is resampled by the forward step, each node's feed the chord over ±½ max step.
//!   Paths follow until one lies on the far edge entirely. From a curve inside the domain
//!   they go to both sides: first toward increasing b until b_max, then again from the curve
//!   toward decreasing b until b_min.
//! - **iso-parametric**: paths b = const, equally spaced, as many as needed so that at every
//!   node the scallop to the next path is at most h.
//!
//! Every path that ends on the along parameter's far end gets a **lead-out**: one more CL
//! node, the last cutter moved [`lead_out_mm`] on along its feed with the surface's
//! continuation ([`lead_out_frame`], [`CcNode::lead_out`]); every path that starts on the near
//! end likewise a **lead-in** before its first node, the first cutter moved back.
//!
//! All loops are capped ([`FinishOptions::max_paths`], [`FinishOptions::max_nodes`]).
//!
//! The files: `start` (where the paths start, which way they run), `build` (one path: forward
//! steps, orientation, gouge checks, chords certified between the poses, lead-in and
//! lead-out), `side_step` (the side step solved at a node, the cusp measured to the next
//! path), `offset` (the next path's curve), `iso_scallop` and `iso_parametric` (the layouts),
//! `budget` (what a job may cost: the pilot's estimate, the check counter).

use glam::{DVec2, DVec3};

use super::FinishError;
use super::contact::ContactFrame;
use super::gouge::PartSamples;
use super::node::CcNode;
use super::orient::{OrientOptions, Strategy};
use crate::fiveaxis::Machine;
use crate::geom::{Cutter, ParametricSurface, Surface};

mod budget;
mod build;
mod iso_parametric;
mod iso_scallop;
mod offset;
mod side_step;
mod start;

pub use budget::{
    CELLS_ESTIMATE_AFTER, CELLS_ESTIMATE_AFTER_SHARE, CHECK_COST_SAMPLE, CHECK_STOP_FACTOR, ESTIMATE_AFTER_SHARE,
    ESTIMATE_MARGIN, MAX_CHECK_CELLS, MAX_CHECK_CELLS_PER_NODE, PILOT_CELLS_FACTOR, PILOT_LOW_BY, Pilot, check_stop,
    estimate_check_cells, pilot, share_after_paths,
};
pub use build::{BETWEEN_CHECK_SHARE, CHORD_SPLITS, LIFT_HALVING_GAIN, LIFT_SHARE_OF_H, lead_out_frame, lead_out_mm};
pub use iso_parametric::iso_parametric;
pub use iso_scallop::{Built, CORRECTOR_CELLS_SHARE, FLAG_ABOVE, IsoScallopSteps, iso_scallop, iso_scallop_checked};
use start::iso_curve;
pub use start::{choose_along, curve_along, start_polyline, strip_by_direction};

/// Which parameter the paths run along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedDirection {
    /// Along u (paths v = const for iso-parametric).
    U,
    /// Along v.
    V,
    /// The one of the two with the wider mean strip (the widest-strip rule).
    Auto,
}

/// Which layout of paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Iso-scallop paths.
    IsoScallop,
    /// Iso-parametric paths at the same worst scallop.
    IsoParametric,
}

impl Layout {
    /// Name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::IsoScallop => "iso-scallop",
            Self::IsoParametric => "iso-parametric",
        }
    }
}

/// One edge of the parameter domain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// u = u_min (paths along v).
    U0,
    /// u = u_max (paths along v).
    U1,
    /// v = v_min (paths along u).
    V0,
    /// v = v_max (paths along u).
    V1,
}

impl Edge {
    /// Every edge, in the order of their names.
    pub const ALL: [Self; 4] = [Self::U0, Self::U1, Self::V0, Self::V1];

    /// The scene's name: `u0`, `u1`, `v0`, `v1`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::U0 => "u0",
            Self::U1 => "u1",
            Self::V0 => "v0",
            Self::V1 => "v1",
        }
    }

    /// The edge of a scene name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }

    /// The parameter the paths run along when they start on this edge (0 = u, 1 = v): an
    /// edge u = const is an iso-curve along v.
    #[must_use]
    pub fn along(self) -> usize {
        match self {
            Self::U0 | Self::U1 => 1,
            Self::V0 | Self::V1 => 0,
        }
    }

    /// Whether the edge is at the upper end of its parameter (the paths then advance toward
    /// decreasing b).
    #[must_use]
    pub fn at_max(self) -> bool {
        matches!(self, Self::U1 | Self::V1)
    }
}

/// Where the iso-scallop paths start (`finish.start` in a scene).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum PathStart {
    /// The boundary b = b_min of the parameter [`FinishOptions::direction`] chooses (the
    /// behaviour before `finish.start` existed).
    #[default]
    FirstBoundary,
    /// This edge; the paths run along it and advance toward the opposite edge.
    Boundary(Edge),
    /// A curve through these surface parameters (internal units: radians for angles), at
    /// least 2, inside the domain. The paths run along the parameter in which the curve
    /// spans more of the domain (or the one [`FinishOptions::direction`] names); the points
    /// are joined in the order of that parameter and the curve is extended at constant b to
    /// the a-boundaries. The paths then go to both sides (module docs).
    Curve(Vec<DVec2>),
}

/// Settings of a finishing job (mm, rad, mm/min).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinishOptions {
    /// Scallop height h (mm).
    pub scallop_mm: f64,
    /// Chord error E of the forward step (mm).
    pub chord_tol_mm: f64,
    /// Longest forward step (mm).
    pub max_step_mm: f64,
    /// Along which parameter.
    pub direction: FeedDirection,
    /// Orientation settings.
    pub orient: OrientOptions,
    /// Feed for the machining time (mm/min).
    pub feed_mm_per_min: f64,
    /// Tolerance of the gouge checks (mm).
    pub gouge_tol_mm: f64,
    /// Grid size of the part samples of the global check (n × n).
    pub part_grid: usize,
    /// Most paths.
    pub max_paths: usize,
    /// Most CC points over all paths.
    pub max_nodes: usize,
    /// Most cells the job's certified bottom checks may be estimated to spend before the
    /// work (default [`MAX_CHECK_CELLS`]; a comparison table shares it among its plans); the
    /// checks stop at [`check_stop`] of it.
    pub max_check_cells: u64,
    /// Most work ([`PartSamples::work_done`](crate::fillet::PartSamples::work_done), in
    /// bottom-check cells and their equivalents): past it a job stops with
    /// [`FinishError::OverShare`] (how a comparison table gives each plan its share), and a
    /// comparison table shares it among its plans. `None` (the default): a job has no cap of its own (its pilot and its
    /// checks' caps bound it), a table has [`TABLE_WORK_FACTOR`](crate::fillet::TABLE_WORK_FACTOR)
    /// times `max_check_cells`.
    pub max_work: Option<u64>,
    /// The share of `max_check_cells` the side steps' corrector may spend rebuilding paths
    /// over the whole job (default [`CORRECTOR_CELLS_SHARE`]); past it each path is built
    /// once and its cusps measured and named ([`PathSet::corrector_stopped_at`]).
    pub corrector_share: f64,
}

impl FinishOptions {
    /// Defaults for scallop h and chord error E (mm): max step 2 mm, feed 1000 mm/min, gouge
    /// tolerance E, a 48 × 48 part grid, at most 2000 paths and 400 000 nodes.
    #[must_use]
    pub fn new(scallop_mm: f64, chord_tol_mm: f64) -> Self {
        Self {
            scallop_mm,
            chord_tol_mm,
            max_step_mm: 2.0,
            direction: FeedDirection::Auto,
            orient: OrientOptions::default(),
            feed_mm_per_min: 1000.0,
            gouge_tol_mm: chord_tol_mm,
            part_grid: 48,
            max_paths: 2000,
            max_nodes: 400_000,
            max_check_cells: MAX_CHECK_CELLS,
            max_work: None,
            corrector_share: CORRECTOR_CELLS_SHARE,
        }
    }
}

/// One finishing job's inputs, borrowed: what [`iso_scallop`], [`iso_parametric`],
/// [`estimate_check_cells`] and [`IsoScallopSteps`] take instead of the same six arguments
/// each. [`crate::fillet::FinishJob::setup`] makes one from a scene's job; a table or a test
/// that varies one input writes `FinishSetup { strategy, ..setup }`.
#[derive(Clone, Copy, Debug)]
pub struct FinishSetup<'a> {
    /// The surface to finish.
    pub surface: &'a Surface,
    /// The cutter (mm).
    pub cutter: &'a Cutter,
    /// How the tool is oriented at each CC point.
    pub strategy: Strategy,
    /// Path options (tolerances in mm, caps).
    pub options: &'a FinishOptions,
    /// The part sampled once for the gouge checks (its counter of checked cells is shared
    /// by every job given it).
    pub part: &'a PartSamples,
    /// Where the iso-scallop paths start; the iso-parametric paths run along the same
    /// parameter ([`PathStart::along`]).
    pub start: &'a PathStart,
    /// The machine the paths are for, whose rotary travel every pose must lie within (the
    /// gouge checks' search keeps the axis there, [`crate::fillet::gouge::adjust`]; a point
    /// with no such pose is refused), or `None`: the CL data alone, for no machine.
    pub reach: Option<&'a Machine>,
}

/// One path: its nodes in the order of travel.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolPath {
    /// The CC nodes.
    pub nodes: Vec<CcNode>,
}

impl ToolPath {
    /// Length of the CC polyline (mm).
    #[must_use]
    pub fn length_mm(&self) -> f64 {
        self.nodes.windows(2).map(|w| (w[1].frame.point - w[0].frame.point).length()).sum()
    }
}

/// A point that could not be machined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refusal {
    /// Surface parameters (internal units).
    pub uv: DVec2,
    /// The CC point (mm).
    pub point: DVec3,
    /// Why.
    pub reason: &'static str,
    /// Depth of the clash (mm), if one.
    pub depth_mm: f64,
}

/// The paths of one strategy and layout, with their statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct PathSet {
    /// The paths, first to last.
    pub paths: Vec<ToolPath>,
    /// The layout.
    pub layout: Layout,
    /// The strategy.
    pub strategy: Strategy,
    /// 0: paths along u, 1: along v.
    pub along: usize,
    /// Points refused (left out of their path).
    pub refused: Vec<Refusal>,
    /// From a start curve: the index of the first path of its second side (toward
    /// decreasing b; the paths before it are the curve and its first side), if that side
    /// has paths. The path before it is not its neighbour: a linking move comes between.
    pub second_side: Option<usize>,
    /// Places where the cusp measured between two neighbouring paths stayed above
    /// [`FLAG_ABOVE`]·h after the side steps' correction (iso-scallop paths only).
    pub scallop_flags: Vec<ScallopFlag>,
    /// The first path the corrector left as first built, its rebuilds having spent their
    /// share of the checks' budget ([`CORRECTOR_CELLS_SHARE`]); that path's cusps and every
    /// later path's are measured and flagged, not corrected. `None` when it corrected every
    /// path that needed it.
    pub corrector_stopped_at: Option<usize>,
}

/// A place where the scallop could not be held at h: the cusp measured between a path's node
/// and the next path, from their swept cutters, after the corrector's rounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScallopFlag {
    /// The node's surface parameters (internal units).
    pub uv: DVec2,
    /// The node's CC point (mm).
    pub point: DVec3,
    /// The node's path; the cusp lies between it and the next path of its side.
    pub path: usize,
    /// The cusp measured there (mm).
    pub scallop_mm: f64,
}

/// Numbers comparing path sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Passes.
    pub passes: usize,
    /// CC points (lead-outs not counted).
    pub nodes: usize,
    /// Total path length (mm), lead-outs included (the cutter travels them).
    pub length_mm: f64,
    /// Strip width min, mean, max (mm).
    pub strip_mm: [f64; 3],
    /// Solved scallop min and max over the nodes with a next path (mm).
    pub scallop_mm: [f64; 2],
    /// Machining time at the feed (min), cutting moves only.
    pub time_min: f64,
    /// Nodes whose orientation the gouge checks changed.
    pub adjusted: usize,
}

impl PathSet {
    /// The statistics at feed `feed_mm_per_min`.
    #[must_use]
    pub fn stats(&self, feed_mm_per_min: f64) -> Stats {
        let nodes: Vec<&CcNode> = self.paths.iter().flat_map(|p| p.nodes.iter()).filter(|n| !n.lead_out).collect();
        let length_mm: f64 = self.paths.iter().map(ToolPath::length_mm).sum();
        let (mut lo, mut hi, mut sum) = (f64::INFINITY, 0.0f64, 0.0);
        for n in &nodes {
            lo = lo.min(n.strip_mm);
            hi = hi.max(n.strip_mm);
            sum += n.strip_mm;
        }
        let (mut slo, mut shi) = (f64::INFINITY, 0.0f64);
        for s in nodes.iter().filter_map(|n| n.scallop_mm) {
            slo = slo.min(s);
            shi = shi.max(s);
        }
        let count = nodes.len().max(1) as f64;
        Stats {
            passes: self.paths.len(),
            nodes: nodes.len(),
            length_mm,
            strip_mm: [if lo.is_finite() { lo } else { 0.0 }, sum / count, hi],
            scallop_mm: [if slo.is_finite() { slo } else { 0.0 }, shi],
            time_min: if feed_mm_per_min > 0.0 { length_mm / feed_mm_per_min } else { 0.0 },
            adjusted: nodes.iter().filter(|n| n.adjusted.is_some()).count(),
        }
    }
}

/// A forward-step sample: uv, the polyline's direction there (mm), the azimuth window, and
/// the contact frame there with its cross direction in (u, v) when the forward step found
/// one (`ContactFrame::with_cross_uv` of the same uv and direction: the node's frame).
type Sample = (DVec2, DVec3, Option<(f64, f64)>, Option<(ContactFrame, DVec2)>);

/// Everything a job needs, borrowed.
struct Ctx<'a> {
    surface: &'a Surface,
    cutter: Cutter,
    strategy: Strategy,
    opts: &'a FinishOptions,
    part: &'a PartSamples,
    along: usize,
    /// The sign that turns c toward the far edge: +1 when c points toward increasing b and
    /// the paths advance that way, else −1 (decided on the first path).
    side: f64,
    /// +1 while the paths advance toward increasing b, −1 toward decreasing b.
    toward: f64,
    /// `part.cells_checked()` and `part.work_done()` when the job started, and the CC points
    /// checked since.
    cells_at_start: u64,
    work_at_start: u64,
    nodes_checked: std::cell::Cell<u64>,
    /// The strip's reaches of the nodes built lately ([`build::Reaches`]), where the job
    /// keeps them between its steps.
    reaches: Option<&'a std::cell::RefCell<build::Reaches>>,
    /// [`FinishSetup::reach`].
    reach: Option<&'a Machine>,
}

fn a_of(uv: DVec2, along: usize) -> f64 {
    if along == 0 { uv.x } else { uv.y }
}
fn b_of(uv: DVec2, along: usize) -> f64 {
    if along == 0 { uv.y } else { uv.x }
}
fn make_uv(a: f64, b: f64, along: usize) -> DVec2 {
    if along == 0 { DVec2::new(a, b) } else { DVec2::new(b, a) }
}

impl<'a> Ctx<'a> {
    /// A job's context after checking its options: the along parameter chosen by the start
    /// ([`PathStart::along`]), c taken toward increasing b until the first path says
    /// otherwise.
    fn start(setup: &FinishSetup<'a>) -> Result<Self, FinishError> {
        let FinishSetup { surface, cutter, strategy, options: opts, part, start, reach } = *setup;
        check_options(opts)?;
        let along = start.along(surface, cutter, &strategy, opts);
        Ok(Self {
            surface,
            cutter: *cutter,
            strategy,
            opts,
            part,
            along,
            side: 1.0,
            toward: 1.0,
            cells_at_start: part.cells_checked(),
            work_at_start: part.work_done(),
            nodes_checked: std::cell::Cell::new(0),
            reaches: None,
            reach,
        })
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let d = self.surface.domain();
        let (ra, rb) = if self.along == 0 { (d.u, d.v) } else { (d.v, d.u) };
        ((ra.min, ra.max), (rb.min, rb.max))
    }
}

fn check_options(opts: &FinishOptions) -> Result<(), FinishError> {
    for (name, v) in [
        ("scallop height", opts.scallop_mm),
        ("chord tolerance", opts.chord_tol_mm),
        ("max step", opts.max_step_mm),
        ("gouge tolerance", opts.gouge_tol_mm),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(FinishError::BadOption { name, value: v });
        }
    }
    Ok(())
}
