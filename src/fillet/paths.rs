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
//!   both cutters ([`super::contact::CrossProfile`], [`super::contact::scallop_between`]),
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

use glam::{DVec2, DVec3};

use super::FinishError;
use super::contact::{ContactFrame, CrossProfile, Pose, place, scallop_between};
use super::gouge::{Adjustment, PartSamples, adjust, check};
use super::node::CcNode;
use super::orient::{OrientOptions, Strategy, pose_at, smooth_inclinations};
use super::sweep::{NearPath, cusp_between, pose_between, surface_depth_near};
use crate::geom::{Cutter, LocalGeometry, ParametricSurface, Surface};
use crate::numerics::limits::MAX_START_CURVE_POINTS;
use crate::numerics::tolerance::DOMAIN_SLACK;

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

impl PathStart {
    /// The parameter the paths run along (0 = u, 1 = v): the edge's, the curve's
    /// ([`curve_along`]), or for the first boundary [`choose_along`].
    #[must_use]
    pub fn along(&self, surface: &Surface, cutter: &Cutter, strategy: &Strategy, opts: &FinishOptions) -> usize {
        match self {
            Self::FirstBoundary => choose_along(surface, cutter, strategy, opts),
            Self::Boundary(e) => e.along(),
            Self::Curve(pts) => curve_along(surface, pts, opts.direction),
        }
    }
}

/// The parameter a start curve's paths run along: the one `direction` names, or for
/// [`FeedDirection::Auto`] the one in which the points span the larger share of the domain
/// (u on a tie).
#[must_use]
pub fn curve_along(surface: &Surface, pts: &[DVec2], direction: FeedDirection) -> usize {
    match direction {
        FeedDirection::U => 0,
        FeedDirection::V => 1,
        FeedDirection::Auto => {
            let d = surface.domain();
            let share = |get: fn(DVec2) -> f64, width: f64| {
                let (lo, hi) = pts
                    .iter()
                    .map(|&p| get(p))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
                if hi > lo && width > 0.0 { (hi - lo) / width } else { 0.0 }
            };
            usize::from(share(|p| p.y, d.v.width()) > share(|p| p.x, d.u.width()))
        }
    }
}

/// The start curve as the first path's uv polyline for paths along `along`: checked (at
/// least 2 points, finite, inside the domain, at most [`MAX_START_CURVE_POINTS`]), sorted
/// by the along parameter a (points no further along than the previous one dropped),
/// each segment divided into pieces of at most 1/64 of the a-range, and extended at
/// constant b to both a-boundaries.
///
/// # Errors
/// [`FinishError::BadStart`] naming the problem.
pub fn start_polyline(surface: &Surface, pts: &[DVec2], along: usize) -> Result<Vec<DVec2>, FinishError> {
    let bad = |reason: String| Err(FinishError::BadStart { reason });
    if pts.len() < 2 {
        return bad(format!("the start curve needs at least 2 points, got {}", pts.len()));
    }
    if pts.len() > MAX_START_CURVE_POINTS {
        return bad(format!("the start curve has {} points, more than {MAX_START_CURVE_POINTS}", pts.len()));
    }
    let dom = surface.domain();
    for (i, p) in pts.iter().enumerate() {
        if !(p.is_finite() && dom.contains(*p)) {
            let f = dom.to_file(*p);
            return bad(format!("point {i} of the start curve, ({}, {}), is outside the surface's domain", f.x, f.y));
        }
    }
    let ra = if along == 0 { dom.u } else { dom.v };
    let (a0, a1) = (ra.min, ra.max);
    let mut sorted: Vec<DVec2> = pts.iter().map(|&p| dom.clamp(p)).collect();
    sorted.sort_by(|p, q| a_of(*p, along).total_cmp(&a_of(*q, along)));
    let slack = DOMAIN_SLACK * (a1 - a0).max(1.0);
    let mut kept: Vec<DVec2> = Vec::with_capacity(sorted.len());
    for p in sorted {
        if kept.last().is_none_or(|q| a_of(p, along) > a_of(*q, along) + slack) {
            kept.push(p);
        }
    }
    let name = if along == 0 { 'u' } else { 'v' };
    let (Some(&first), Some(&last)) = (kept.first(), kept.last()) else {
        return bad("the start curve has no points".to_owned());
    };
    if kept.len() < 2 {
        return bad(format!("the start curve's points all have the same {name}; the paths run along {name}"));
    }
    let mut poly = Vec::with_capacity(kept.len() * 4 + 2);
    if a_of(first, along) > a0 + slack {
        poly.push(make_uv(a0, b_of(first, along), along));
    }
    poly.push(first);
    for w in kept.windows(2) {
        let share = (a_of(w[1], along) - a_of(w[0], along)) / (a1 - a0);
        let pieces = (share * START_CURVE_PIECES).ceil().clamp(1.0, START_CURVE_PIECES) as usize;
        for k in 1..=pieces {
            poly.push(w[0].lerp(w[1], k as f64 / pieces as f64));
        }
    }
    if a_of(last, along) < a1 - slack {
        poly.push(make_uv(a1, b_of(last, along), along));
    }
    Ok(poly)
}

/// Pieces of a start curve's segment spanning the whole a-range (as [`iso_curve`]'s 64).
const START_CURVE_PIECES: f64 = 64.0;

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
    /// Most cells the job's certified bottom checks may spend (default [`MAX_CHECK_CELLS`];
    /// a comparison table shares it among its plans).
    pub max_check_cells: u64,
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
        }
    }
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

/// A forward-step sample: uv, the polyline's direction there (mm), the azimuth window.
type Sample = (DVec2, DVec3, Option<(f64, f64)>);

/// What a pilot says a job will take: paths, CC points, certified check cells (and the
/// cells a point it measured).
#[derive(Clone, Copy, Debug)]
struct Estimate {
    paths: f64,
    nodes: f64,
    cells: f64,
    cells_per_node: f64,
}

/// The certified check cells an iso-scallop job from `start` would spend, estimated by the
/// pilot its own start runs ([`MAX_CHECK_CELLS`]): for a comparison table, which refuses
/// before any plan when its plans together would pass the budget they share. 0 when the
/// pilot solved no side step.
///
/// # Errors
/// A bad option or start, no path at the start, or a job refused by its own pilot.
pub fn estimate_check_cells(
    surface: &Surface,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
    part: &PartSamples,
    start: &PathStart,
) -> Result<f64, FinishError> {
    let ctx = Ctx::start(surface, cutter, strategy, opts, part, start)?;
    let poly = ctx.first_polyline(start)?;
    Ok(ctx.refuse_oversized(&poly)?.map_or(0.0, |e| e.cells))
}

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
    /// `part.cells_checked()` when the job started, and the CC points checked since.
    cells_at_start: u64,
    nodes_checked: std::cell::Cell<u64>,
}

/// Most cells of the certified bottom checks ([`PartSamples::cells_checked`]) a job may
/// spend on average per CC point, once [`CHECK_COST_SAMPLE`] points are checked. The
/// examples spend 190–1 470 (whole plans, every strategy and layout); a check stops at
/// 40 000 cells, which a surface far larger or more curved than the cutter reaches at every
/// pose tried (a NURBS with one control point at 10⁵ mm: minutes of checks that refuse
/// every point). Stopping there takes a few seconds instead.
pub const MAX_CHECK_CELLS_PER_NODE: u64 = 20_000;
/// CC points checked before [`MAX_CHECK_CELLS_PER_NODE`] applies.
pub const CHECK_COST_SAMPLE: u64 = 8;
/// Most cells of the certified bottom checks a whole job may spend (the examples: 0.9–12
/// million a job, a comparison table of ten plans shares it), some 15 s of checking.
pub const MAX_CHECK_CELLS: u64 = 100_000_000;

/// A job whose paths or CC points, estimated before they are built
/// (`Ctx::refuse_oversized`), exceed their caps by this factor is refused at once; below
/// it the caps themselves stop the work as it goes.
pub const ESTIMATE_MARGIN: f64 = 1.25;

/// Share of the surface covered after which the iso-scallop paths' CC points are estimated
/// from the share, and the job refused when the estimate passes the cap.
pub const ESTIMATE_AFTER_SHARE: f64 = 0.05;

/// Share of the surface, and cells checked, after which the checks' total cost is
/// estimated from the share (refused above twice [`MAX_CHECK_CELLS`] below
/// [`ESTIMATE_AFTER_SHARE`], above it from there).
pub const CELLS_ESTIMATE_AFTER_SHARE: f64 = 0.01;
/// See [`CELLS_ESTIMATE_AFTER_SHARE`].
pub const CELLS_ESTIMATE_AFTER: f64 = 1e6;

/// Points of each pilot line whose side steps the estimate solves.
const PILOT_POINTS: usize = 16;

/// Lines of the pilot: the first path's and iso-curves spread across the surface.
const PILOT_LINES: usize = 4;

/// Iso-curves across (at the start, the middle and the end of the along parameter) whose
/// length gives the width the paths must cover, and the points each is measured at.
const WIDTH_CURVES: usize = 3;
const WIDTH_POINTS: usize = 64;

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
    fn start(
        surface: &'a Surface,
        cutter: &Cutter,
        strategy: Strategy,
        opts: &'a FinishOptions,
        part: &'a PartSamples,
        start: &PathStart,
    ) -> Result<Self, FinishError> {
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
            nodes_checked: std::cell::Cell::new(0),
        })
    }

    /// Counts a checked CC point and stops the job once its checks cost far more than any
    /// usable part's ([`MAX_CHECK_CELLS_PER_NODE`], [`MAX_CHECK_CELLS`]).
    fn count_check(&self) -> Result<(), FinishError> {
        let nodes = self.nodes_checked.get() + 1;
        self.nodes_checked.set(nodes);
        let cells = self.part.cells_checked().saturating_sub(self.cells_at_start);
        let max = self.opts.max_check_cells;
        if cells > max {
            return Err(FinishError::TooMuchChecking { detail: format!("passed {max} cells after {nodes} CC points") });
        }
        // After CHECK_COST_SAMPLE points, or sooner once the cells spent would already put
        // that many points over the average (a first point costing a million cells).
        if (nodes >= CHECK_COST_SAMPLE || cells > CHECK_COST_SAMPLE * MAX_CHECK_CELLS_PER_NODE)
            && cells / nodes > MAX_CHECK_CELLS_PER_NODE
        {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "cost {} cells a CC point over the first {nodes} (more than {MAX_CHECK_CELLS_PER_NODE})",
                    cells / nodes
                ),
            });
        }
        Ok(())
    }

    /// Refuses a job whose paths would pass their caps by more than [`ESTIMATE_MARGIN`], or
    /// whose checks would pass [`MAX_CHECK_CELLS`], before they are built. A pilot on the
    /// first path's polyline and on [`PILOT_LINES`] − 1 iso-curves across the surface: each
    /// line's forward steps counted (no orientation or check), [`PILOT_POINTS`] of them
    /// oriented and checked and their side steps solved. The paths across are the surface's
    /// width across times the mean of 1/side step, each with the lines' mean CC points, each
    /// point checked at the pilot's mean cost.
    fn refuse_oversized(&self, poly: &[DVec2]) -> Result<Option<Estimate>, FinishError> {
        let Some(est) = self.pilot(poly)? else { return Ok(None) };
        let (paths, nodes) = (est.paths, est.nodes);
        if paths > ESTIMATE_MARGIN * self.opts.max_paths as f64 || nodes > ESTIMATE_MARGIN * self.opts.max_nodes as f64
        {
            return Err(FinishError::Oversized {
                paths,
                nodes,
                max_paths: self.opts.max_paths,
                max_nodes: self.opts.max_nodes,
            });
        }
        let (cells, cells_per_node) = (est.cells, est.cells_per_node);
        let max = self.opts.max_check_cells;
        if cells > max as f64 {
            return Err(FinishError::TooMuchChecking {
                detail: format!(
                    "would pass {max} cells: about {cells:.2e} over about {nodes:.0} CC points (estimated before the paths are built, {cells_per_node:.0} cells a point on a pilot)"
                ),
            });
        }
        Ok(Some(est))
    }

    /// The pilot of [`Self::refuse_oversized`]: the job's paths, CC points and check cells
    /// estimated from it; `None` when no side step could be solved on it.
    fn pilot(&self, poly: &[DVec2]) -> Result<Option<Estimate>, FinishError> {
        let ((a0, a1), (b0, b1)) = self.ranges();
        let mut lines = vec![poly.to_vec()];
        for k in 1..PILOT_LINES {
            lines.push(iso_curve((a0, a1), b0 + (b1 - b0) * k as f64 / (PILOT_LINES - 1) as f64, self.along));
        }
        let mut side = None;
        let (mut inverse, mut samples_sum, mut pilot_nodes) = (Vec::new(), 0usize, 0usize);
        let cells_before = self.part.cells_checked();
        for line in &lines {
            let mut budget = self.opts.max_nodes;
            let samples = self.forward_samples(line, None, &mut budget)?;
            samples_sum += samples.len();
            let every = (samples.len() / PILOT_POINTS).max(1);
            let pilot_samples: Vec<Sample> = samples
                .iter()
                .enumerate()
                .filter(|(k, _)| k % every == 0 || *k + 1 == samples.len())
                .map(|(_, s)| *s)
                .collect();
            let mut scratch = Vec::new();
            let pilot = self.path_from_samples(pilot_samples, &mut scratch, &mut budget)?;
            pilot_nodes += pilot.nodes.len();
            // Not one of PILOT_POINTS points spread along the first path can be cut: the job
            // stops here, as it would after trying every point of that path.
            if side.is_none() && samples.len() > PILOT_POINTS && pilot.nodes.iter().all(|n| n.lead_out) {
                return Err(FinishError::NoPath { reason: scratch.first().map_or("no CC point", |r| r.reason) });
            }
            // The side toward the far edge, from the first line's first node (as the job's).
            if side.is_none()
                && let Some(n0) = pilot.nodes.iter().find(|n| !n.lead_out)
            {
                let g = LocalGeometry::try_new(self.surface.derivatives_at(n0.frame.uv));
                let tc = g.map_or(DVec2::ZERO, |g| g.tangent_coords(n0.frame.cross));
                side = Some(if b_of(tc, self.along) >= 0.0 { 1.0 } else { -1.0 } * self.toward);
            }
            let Some(side) = side else { continue };
            let ctx = Ctx { side, nodes_checked: std::cell::Cell::new(self.nodes_checked.get()), ..*self };
            inverse.extend(
                pilot
                    .nodes
                    .iter()
                    .filter(|n| !n.lead_out)
                    .map(|n| ctx.side_step(n).2)
                    .filter(|w| *w > 0.0 && w.is_finite())
                    .map(|w| 1.0 / w),
            );
            self.nodes_checked.set(ctx.nodes_checked.get());
        }
        // The checks' cost per CC point on the pilot (its paths and side steps, as a job's).
        let cells_per_node = self.part.cells_checked().saturating_sub(cells_before) as f64 / pilot_nodes.max(1) as f64;
        let samples_per_path = samples_sum as f64 / lines.len() as f64;
        if inverse.is_empty() {
            return Ok(None);
        }
        let per_mm = inverse.iter().sum::<f64>() / inverse.len() as f64;
        let mut width = 0.0;
        for i in 0..WIDTH_CURVES {
            let a = a0 + (a1 - a0) * i as f64 / (WIDTH_CURVES - 1) as f64;
            let mut prev: Option<DVec3> = None;
            for j in 0..=WIDTH_POINTS {
                let p = self.surface.point_at(make_uv(a, b0 + (b1 - b0) * j as f64 / WIDTH_POINTS as f64, self.along));
                if let Some(q) = prev {
                    width += (p - q).length() / WIDTH_CURVES as f64;
                }
                prev = Some(p);
            }
        }
        let paths = (width * per_mm).max(1.0);
        let nodes = paths * samples_per_path;
        Ok(Some(Estimate { paths, nodes, cells: nodes * cells_per_node, cells_per_node }))
    }

    /// The first path's uv polyline for `start`: an edge's iso-curve or the start curve.
    fn first_polyline(&self, start: &PathStart) -> Result<Vec<DVec2>, FinishError> {
        let ((a0, a1), (b0, b1)) = self.ranges();
        Ok(match start {
            PathStart::FirstBoundary => iso_curve((a0, a1), b0, self.along),
            PathStart::Boundary(e) => iso_curve((a0, a1), if e.at_max() { b1 } else { b0 }, self.along),
            PathStart::Curve(pts) => start_polyline(self.surface, pts, self.along)?,
        })
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let d = self.surface.domain();
        let (ra, rb) = if self.along == 0 { (d.u, d.v) } else { (d.v, d.u) };
        ((ra.min, ra.max), (rb.min, rb.max))
    }

    /// Nodes along a uv polyline by the forward step, oriented, smoothed, checked.
    /// `psi_ref`: per polyline vertex, the azimuth window (centre, half width, rad) the
    /// side step assumed for it (offset paths); without it each node's window is centred on
    /// the previous node's azimuth.
    fn build_path(
        &self,
        poly: &[DVec2],
        psi_ref: Option<&[(f64, f64)]>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<ToolPath, FinishError> {
        let samples = self.forward_samples(poly, psi_ref, budget)?;
        self.path_from_samples(samples, refused, budget)
    }

    /// The points of a path along a uv polyline by the forward step (each counted against
    /// `budget`): the cheap part of [`Self::build_path`], before any orientation or check.
    fn forward_samples(
        &self,
        poly: &[DVec2],
        psi_ref: Option<&[(f64, f64)]>,
        budget: &mut usize,
    ) -> Result<Vec<Sample>, FinishError> {
        let pts: Vec<DVec3> = poly.iter().map(|&uv| self.surface.point_at(uv)).collect();
        let mut cum = vec![0.0];
        for w in pts.windows(2) {
            let l = cum.last().copied().unwrap_or(0.0) + (w[1] - w[0]).length();
            cum.push(l);
        }
        let total = cum.last().copied().unwrap_or(0.0);
        let segment = |s: f64| -> (usize, f64) {
            let k = cum.partition_point(|&c| c <= s).clamp(1, cum.len().max(2) - 1);
            let (c0, c1) = (cum[k - 1], cum[k]);
            (k, if c1 > c0 { ((s - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 0.0 })
        };
        let point = |s: f64| -> DVec3 {
            let (k, t) = segment(s);
            pts[k - 1].lerp(pts[k], t)
        };
        // The feed of an offset path: the chord over ±half the longest step (FEED_CHORD), so
        // that a short jog of the offset curve (a trimmed swallowtail's corner, a cusp's
        // remnant) does not turn a node's feed, and with it the next side step, sideways.
        let half = if psi_ref.is_some() { FEED_CHORD * self.opts.max_step_mm } else { 0.0 };
        let at = |s: f64| -> (DVec2, DVec3, Option<(f64, f64)>) {
            let (k, t) = segment(s);
            let psi = psi_ref.and_then(|r| {
                let (a, b) = (r.get(k - 1)?, r.get(k)?);
                Some((a.0 + t * (b.0 - a.0), a.1.max(b.1)))
            });
            let chord = point((s + half).min(total)) - point((s - half).max(0.0));
            let dir = if half > 0.0 && chord.length_squared() > 0.0 { chord } else { pts[k] - pts[k - 1] };
            (poly[k - 1].lerp(poly[k], t), dir, psi)
        };
        // Forward steps.
        let mut samples: Vec<Sample> = Vec::new();
        let mut s = 0.0;
        loop {
            if *budget == 0 {
                return Err(FinishError::TooManyNodes { max_nodes: self.opts.max_nodes });
            }
            *budget -= 1;
            let (uv, dir, psi) = at(s);
            samples.push((uv, dir, psi));
            if s >= total {
                break;
            }
            // Normal curvature along the feed, positive where the surface bends toward the
            // cutter (concave): there the chord sag only raises the cutter, E alone bounds it.
            let ff = ContactFrame::new(self.surface, uv, dir).map_or(0.0, |f| f.surface_form.ff);
            let k = ff.abs();
            let sag = if ff < 0.0 {
                self.opts.chord_tol_mm.min(SAG_SHARE_OF_H * self.opts.scallop_mm)
            } else {
                self.opts.chord_tol_mm
            };
            let step = if k > 0.0 { (8.0 * sag / k).sqrt() } else { f64::INFINITY };
            let step = step.min(self.opts.max_step_mm).max(1e-3 * self.opts.max_step_mm);
            s = if s + step >= total - 1e-9 * total.max(1.0) { total } else { s + step };
        }
        Ok(samples)
    }

    /// The path of [`Self::forward_samples`]'s points: oriented, smoothed, checked.
    fn path_from_samples(
        &self,
        samples: Vec<Sample>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<ToolPath, FinishError> {
        // Frames and poses, ψ warm-started from the previous node.
        let mut frames = Vec::with_capacity(samples.len());
        let mut poses: Vec<Pose> = Vec::with_capacity(samples.len());
        let mut prev: Option<(DVec3, Pose)> = None;
        let oo = &self.opts.orient;
        for (uv, dir, psi_win) in samples {
            let Some(frame) = ContactFrame::new(self.surface, uv, dir) else {
                refused.push(Refusal {
                    uv,
                    point: self.surface.point_at(uv),
                    reason: "singular point of the surface (no normal)",
                    depth_mm: 0.0,
                });
                continue;
            };
            let window = match (psi_win, prev) {
                (Some((c, d)), _) => ((c - d).max(-oo.max_azimuth_rad), (c + d).min(oo.max_azimuth_rad)),
                (None, Some((p, pose))) => {
                    let d = oo.max_turn_rad_per_mm * (frame.point - p).length();
                    ((pose.azimuth_rad - d).max(-oo.max_azimuth_rad), (pose.azimuth_rad + d).min(oo.max_azimuth_rad))
                }
                (None, None) => (-oo.max_azimuth_rad, oo.max_azimuth_rad),
            };
            let found = pose_at(&self.strategy, &self.cutter, &frame, oo, window).or_else(|| {
                pose_at(&self.strategy, &self.cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))
            });
            let Some((pose, _)) = found else {
                refused.push(Refusal {
                    uv,
                    point: frame.point,
                    reason: "the surface is more concave than the cutter's largest effective curvature",
                    depth_mm: 0.0,
                });
                continue;
            };
            prev = Some((frame.point, pose));
            frames.push(frame);
            poses.push(pose);
        }
        let ds: Vec<f64> = frames.windows(2).map(|w| (w[1].point - w[0].point).length()).collect();
        smooth_inclinations(&mut poses, &ds, oo.max_turn_rad_per_mm);
        let tool = self.strategy.cutter_for(&self.cutter);
        // Gouge checks and adjustment, then the inclinations smoothed again (raising only).
        let mut checked: Vec<(ContactFrame, Pose, Option<Adjustment>)> = Vec::with_capacity(frames.len());
        for (frame, pose) in frames.into_iter().zip(poses) {
            let verdict = adjust(&tool, self.surface, self.part, &frame, pose, oo, self.opts.gouge_tol_mm);
            self.count_check()?;
            match verdict {
                Ok((pose, adjusted)) => checked.push((frame, pose, adjusted)),
                Err(clash) => refused.push(Refusal {
                    uv: frame.uv,
                    point: frame.point,
                    reason: match clash.part {
                        super::gouge::ClashPart::Bottom => {
                            "the cutter's bottom gouges the surface at every inclination tried"
                        }
                        super::gouge::ClashPart::Flank => {
                            "the cutter's flank gouges the part at every inclination tried"
                        }
                        super::gouge::ClashPart::Shank => "the shank collides with the part at every inclination tried",
                        super::gouge::ClashPart::Holder => {
                            "the holder collides with the part at every inclination tried"
                        }
                    },
                    depth_mm: clash.depth_mm,
                }),
            }
        }
        let mut poses: Vec<Pose> = checked.iter().map(|c| c.1).collect();
        let ds: Vec<f64> = checked.windows(2).map(|w| (w[1].0.point - w[0].0.point).length()).collect();
        smooth_inclinations(&mut poses, &ds, oo.max_turn_rad_per_mm);
        let nodes: Vec<CcNode> = checked
            .into_iter()
            .zip(poses)
            .map(|((frame, _, adjusted), pose)| self.node(&tool, frame, pose, adjusted))
            .collect();
        let mut nodes = self.certify_chords(&tool, nodes, refused, budget)?;
        if let Some(lead) = nodes.last().and_then(|last| self.lead_out(&tool, last, true)) {
            nodes.push(lead);
        }
        if let Some(lead) = nodes.first().and_then(|first| self.lead_out(&tool, first, false)) {
            nodes.insert(0, lead);
        }
        Ok(ToolPath { nodes })
    }

    /// The CC node of `frame` with the cutter at `pose`: placed, with its strip width.
    fn node(&self, tool: &Cutter, frame: ContactFrame, pose: Pose, adjusted: Option<Adjustment>) -> CcNode {
        let (tip, axis) = place(tool, &frame, &pose);
        let prof = CrossProfile::new(tool, self.surface, frame, &pose);
        let h = self.opts.scallop_mm;
        CcNode {
            frame,
            pose,
            tip,
            axis,
            strip_mm: prof.reach(h, 1.0) + prof.reach(h, -1.0),
            side_step_mm: None,
            scallop_mm: None,
            adjusted,
            lead_out: false,
        }
    }

    /// The path's chords certified between their poses: where the design surface reaches
    /// deeper than [`BETWEEN_CHECK_SHARE`] × the gouge tolerance into the cutter swept to the
    /// middle of a chord (tip and axis interpolated, as the controller moves them), or the
    /// swept cutter stands clear of it there by more than the chord tolerance E and
    /// [`LIFT_SHARE_OF_H`]·h (material left on the path itself, which the scallop between
    /// the paths stands on), a CC
    /// node is put at the middle of the chord's CC points (its pose the mean of the two,
    /// gouge-checked as every pose), and each half checked again, at most [`CHORD_SPLITS`]
    /// times. A chord whose middle node cannot be placed clear is left and its middle
    /// refused (named, with its depth). Each node put in is counted against `budget` (the
    /// job's CC points, as the forward steps count theirs).
    fn certify_chords(
        &self,
        tool: &Cutter,
        nodes: Vec<CcNode>,
        refused: &mut Vec<Refusal>,
        budget: &mut usize,
    ) -> Result<Vec<CcNode>, FinishError> {
        let tol = BETWEEN_CHECK_SHARE * self.opts.gouge_tol_mm;
        let mut out: Vec<CcNode> = Vec::with_capacity(nodes.len());
        for target in nodes {
            // Each chord to check with its halvings so far and the lift of the chord it halves.
            let mut pending = vec![(target, 0usize, f64::INFINITY)];
            while let Some((b, depth, parent_lift)) = pending.pop() {
                let Some(a) = out.last().copied() else {
                    out.push(b);
                    continue;
                };
                let (tip, axis) = pose_between(&a, &b, 0.5);
                let uv = a.frame.uv.lerp(b.frame.uv, 0.5);
                let deep = surface_depth_near(tool, self.surface, tip, axis, uv);
                // A lift is halved only while halving helps (a chord's sag falls fourfold with
                // its length; a lift that does not fall to half its parent's is the strategy's
                // own stand-off, which more nodes would not lower, only check).
                let lifted = -deep > self.opts.chord_tol_mm.max(LIFT_SHARE_OF_H * self.opts.scallop_mm)
                    && -deep < LIFT_HALVING_GAIN * parent_lift;
                if (deep > tol || lifted) && !a.lead_out && !b.lead_out {
                    let placed = if depth < CHORD_SPLITS { self.node_between(tool, &a, &b)? } else { None };
                    if let Some(mid) = placed {
                        if *budget == 0 {
                            return Err(FinishError::TooManyNodes { max_nodes: self.opts.max_nodes });
                        }
                        *budget -= 1;
                        pending.push((b, depth + 1, -deep));
                        pending.push((mid, depth + 1, -deep));
                        continue;
                    }
                }
                if deep > tol && !a.lead_out && !b.lead_out {
                    refused.push(Refusal {
                        uv,
                        point: self.surface.point_at(uv),
                        reason: "the cutter swept between two poses reaches below the surface and no pose between them clears it",
                        depth_mm: deep,
                    });
                }
                out.push(b);
            }
        }
        Ok(out)
    }

    /// A CC node at the middle of the CC points of `a` and `b` (in u, v), its feed along the
    /// chord, its pose the mean of theirs after the gouge checks; `None` where the surface
    /// has no frame there or the checks find no clear pose.
    fn node_between(&self, tool: &Cutter, a: &CcNode, b: &CcNode) -> Result<Option<CcNode>, FinishError> {
        let uv = a.frame.uv.lerp(b.frame.uv, 0.5);
        let Some(frame) = ContactFrame::new(self.surface, uv, b.frame.point - a.frame.point) else {
            return Ok(None);
        };
        // The strategy's pose within the two azimuths (its own rules, such as the matched
        // cutter's cross-curvature floor, hold there too), else the mean of the two.
        let (p0, p1) = (a.pose.azimuth_rad.min(b.pose.azimuth_rad), a.pose.azimuth_rad.max(b.pose.azimuth_rad));
        let pose = pose_at(&self.strategy, &self.cutter, &frame, &self.opts.orient, (p0, p1)).map_or(
            Pose {
                inclination_rad: 0.5 * (a.pose.inclination_rad + b.pose.inclination_rad),
                azimuth_rad: 0.5 * (a.pose.azimuth_rad + b.pose.azimuth_rad),
            },
            |p| p.0,
        );
        let verdict = adjust(tool, self.surface, self.part, &frame, pose, &self.opts.orient, self.opts.gouge_tol_mm);
        self.count_check()?;
        Ok(verdict.ok().map(|(pose, adjusted)| self.node(tool, frame, pose, adjusted)))
    }

    /// The lead-out after `last` when it lies on the along parameter's far end (`far`), or
    /// the lead-in before the first node `last` when it lies on the near end (`!far`): its
    /// cutter moved [`lead_out_mm`] on (back) along the feed with the surface's continuation,
    /// for the strip's reach at h on either side. The lowest point of the cutter at a cross
    /// offset lies behind the contact on one side and, where the surface is twisted, ahead of
    /// it on the other: both ends need the poses past them (the mould's start edge line
    /// measured 2.10·h without a lead-in, 1.035·h with one).
    fn lead_out(&self, tool: &Cutter, last: &CcNode, far: bool) -> Option<CcNode> {
        let ((a0, a1), _) = self.ranges();
        let a = a_of(last.frame.uv, self.along);
        let slack = LEAD_OUT_EDGE_REL * (a1 - a0);
        if (far && a < a1 - slack) || (!far && a > a0 + slack) {
            return None;
        }
        let sense = if far { 1.0 } else { -1.0 };
        let h = self.opts.scallop_mm;
        let prof = CrossProfile::new(tool, self.surface, last.frame, &last.pose);
        let reach = prof.reach(h, 1.0).max(prof.reach(h, -1.0));
        // The far edge's slant against the cross direction: tan of its angle from c.
        let der = self.surface.derivatives_at(last.frame.uv);
        let edge = if self.along == 0 { der.dv } else { der.du };
        let (along_f, along_c) = (edge.dot(last.frame.feed).abs(), edge.dot(last.frame.cross).abs());
        let slant = if along_c > 0.0 { along_f / along_c } else { f64::INFINITY };
        // Where the far edge is slanted part of the cutter is still over the surface past the
        // end node: the lead-out is checked like every pose and halved until it clears (none
        // after LEAD_OUT_HALVINGS).
        let mut d = lead_out_mm(tool, &last.pose, reach, slant);
        let tol = LEAD_OUT_CHECK_SHARE * self.opts.gouge_tol_mm;
        for _ in 0..=LEAD_OUT_HALVINGS {
            if d <= 0.0 {
                return None;
            }
            // The cutter continued with the surface past the end (its twist and its curvature
            // along the feed), not moved straight: see `lead_out_frame`.
            let frame = lead_out_frame(&last.frame, sense * d);
            if check(tool, self.surface, self.part, &frame, &last.pose, tol).is_none() {
                let (tip, axis) = place(tool, &frame, &last.pose);
                return Some(CcNode {
                    frame,
                    tip,
                    axis,
                    side_step_mm: None,
                    scallop_mm: None,
                    adjusted: None,
                    lead_out: true,
                    ..*last
                });
            }
            d *= 0.5;
        }
        None
    }

    /// The next path's uv polyline from the side steps `steps` of `nodes` (node index, step
    /// mm, reached the far edge, scallop solved): each node walked its step across, the curve
    /// cut at its self-intersections (swallowtails) and at the a-edges, what is left of a cusp
    /// (a vertex or two back along a without a crossing: where the offset's radius is just
    /// that of the stretch it offsets) dropped, so that no node's feed, and with it the next
    /// side step's direction, turns back; the ends extended to the a-boundaries along its end
    /// segments (a step along b = const would kink the path there, and the kink would grow
    /// path by path through the end nodes' cross directions), b kept inside its range. With
    /// each vertex its azimuth window. `None` when nothing is left.
    fn offset_curve(&self, nodes: &[CcNode], steps: &[(usize, f64, bool, f64)]) -> Option<OffsetCurve> {
        let along = self.along;
        let ((a0, a1), (b0, b1)) = self.ranges();
        let rate = self.opts.orient.max_turn_rad_per_mm;
        let mut offset: Vec<Vertex> = Vec::with_capacity(steps.len());
        for &(i, w, _, _) in steps {
            let node = nodes.get(i)?;
            let (uv, _) = self.walk(&node.frame, w);
            // The vertex with a as walked (the walk's own uv is clamped to the domain).
            let vertex =
                if a_of(uv, along) > a0 && a_of(uv, along) < a1 { uv } else { self.offset_vertex(&node.frame, w) };
            offset.push((vertex, (node.pose.azimuth_rad, rate * w)));
        }
        let mut offset = clip_along(&trim_swallowtails(&offset), (a0, a1), along);
        let mut a_last = f64::NEG_INFINITY;
        offset.retain(|v| {
            let keep = a_of(v.0, along) > a_last;
            if keep {
                a_last = a_of(v.0, along);
            }
            keep
        });
        let mut poly: Vec<DVec2> = offset.iter().map(|v| v.0).collect();
        let mut refs: Vec<(f64, f64)> = offset.iter().map(|v| v.1).collect();
        let (&f, &l) = (poly.first()?, poly.last()?);
        if a_of(f, along) > a0 {
            let b = extend_b(poly.get(1).copied(), f, a0, along).clamp(b0, b1);
            poly.insert(0, make_uv(a0, b, along));
            refs.insert(0, refs[0]);
        }
        if a_of(l, along) < a1 {
            let b = extend_b(poly.len().checked_sub(2).and_then(|i| poly.get(i)).copied(), l, a1, along).clamp(b0, b1);
            poly.push(make_uv(a1, b, along));
            refs.push(refs[refs.len() - 1]);
        }
        (poly.len() >= 2).then_some((poly, refs))
    }

    /// The cusp measured between each node of `steps` (on `nodes`) and the path `next`
    /// built from them ([`cusp_between`]), `None` where it reached the far edge or `next`
    /// does not pass beside it.
    fn measure_cusps(
        &self,
        tool: &Cutter,
        nodes: &[CcNode],
        next: &[CcNode],
        steps: &[(usize, f64, bool, f64)],
    ) -> Vec<Option<f64>> {
        let next = NearPath::new(next);
        steps
            .iter()
            .map(|&(i, w, beyond, _)| {
                if beyond {
                    return None;
                }
                cusp_between(tool, self.surface, nodes, i, &next, 2.0 * w + tool.radius_mm).map(|c| c.0)
            })
            .collect()
    }

    /// Walks `w_mm` across the surface from `frame` along ±c; returns the uv (clamped to the
    /// domain) and whether it reached or passed b's far end.
    fn walk(&self, frame: &ContactFrame, w_mm: f64) -> (DVec2, bool) {
        let (uv, beyond) = self.walk_unclamped(frame, w_mm);
        (self.surface.domain().clamp(uv), beyond)
    }

    /// The next path's vertex from `node` at side step `w_mm`: b clamped to the domain (a
    /// point beyond the far edge is put on it), a as walked — possibly outside the a-range,
    /// where [`clip_along`] cuts the offset curve at the edge instead of running it along.
    fn offset_vertex(&self, frame: &ContactFrame, w_mm: f64) -> DVec2 {
        let (raw, _) = self.walk_unclamped(frame, w_mm);
        let ((_, _), (b0, b1)) = self.ranges();
        make_uv(a_of(raw, self.along), b_of(raw, self.along).clamp(b0, b1), self.along)
    }

    /// [`Ctx::walk`] without the clamp.
    fn walk_unclamped(&self, frame: &ContactFrame, w_mm: f64) -> (DVec2, bool) {
        let mut uv = frame.uv;
        let mut t = self.side * frame.cross;
        let sub = 4;
        for _ in 0..sub {
            let d = self.surface.derivatives_at(uv);
            let Some(g) = LocalGeometry::try_new(d) else { break };
            t = (t - t.dot(d.normal) * d.normal).normalize_or_zero();
            uv += g.tangent_coords(t) * (w_mm / sub as f64);
        }
        let ((_, _), (b0, b1)) = self.ranges();
        let b = b_of(uv, self.along);
        let beyond = if self.toward > 0.0 { b >= b1 } else { b <= b0 };
        (uv, beyond)
    }

    /// The pose the next path's node at `frame_b`, `w_mm` across from `node`, will get: the
    /// strategy's within the azimuth window around the node's, α held within the turn rate
    /// of the node's, and (when `checked`) after the gouge checks; with whether the checks
    /// changed it.
    fn next_pose(&self, node: &CcNode, frame_b: &ContactFrame, w_mm: f64, checked: bool) -> (Pose, bool) {
        let oo = &self.opts.orient;
        let psi = node.pose.azimuth_rad;
        let d = oo.max_turn_rad_per_mm * w_mm;
        let window = ((psi - d).max(-oo.max_azimuth_rad), (psi + d).min(oo.max_azimuth_rad));
        let pose_b = pose_at(&self.strategy, &self.cutter, frame_b, oo, window).map_or(node.pose, |p| p.0);
        let pose_b = Pose { inclination_rad: pose_b.inclination_rad.max(node.pose.inclination_rad - d), ..pose_b };
        if !checked {
            return (pose_b, false);
        }
        let tool = self.strategy.cutter_for(&self.cutter);
        match adjust(&tool, self.surface, self.part, frame_b, pose_b, oo, self.opts.gouge_tol_mm) {
            Ok((p, adj)) => (p, adj.is_some()),
            Err(_) => (pose_b, false),
        }
    }

    /// Side step from `node` solved so the scallop is h; the uv of the next path's point,
    /// whether it lies on (or beyond) the far boundary, the step and the scallop. Solved
    /// first with the next poses unchecked (the gouge checks are the costly part); when the
    /// checks changed this node's pose and change the next one's at the solution, solved
    /// again with every trial pose checked.
    fn side_step(&self, node: &CcNode) -> (DVec2, bool, f64, f64) {
        let first = self.solve_side_step(node, false);
        let (uv, beyond, w, _) = first;
        if beyond {
            return first;
        }
        // The prediction matters only where the checks act: where they left this node as it
        // was, the next one is taken unchecked too (its own checks run when its path is built,
        // so this affects the scallop's accuracy, never the gouge-freedom).
        if node.adjusted.is_none() {
            return first;
        }
        match ContactFrame::new(self.surface, uv, node.frame.feed) {
            Some(frame_b) if self.next_pose(node, &frame_b, w, true).1 => self.solve_side_step(node, true),
            _ => first,
        }
    }

    fn solve_side_step(&self, node: &CcNode, checked: bool) -> (DVec2, bool, f64, f64) {
        let h = self.opts.scallop_mm;
        let tool = self.strategy.cutter_for(&self.cutter);
        let a = CrossProfile::new(&tool, self.surface, node.frame, &node.pose);
        // No strip is wider than the cutter: the side step stays within (0, 2R].
        let w_max = 2.0 * tool.radius_mm;
        let mut w = (a.reach(h, self.side) * 2.0).min(w_max);
        // Bracket of w: scallop below h at `lo`, above at `hi`.
        let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
        let mut result = (node.frame.uv, true, w, 0.0);
        for _ in 0..SIDE_STEP_ROUNDS {
            let (uv, beyond) = self.walk(&node.frame, w);
            if beyond {
                return (uv, true, w, 0.0);
            }
            let Some(frame_b) = ContactFrame::new(self.surface, uv, node.frame.feed) else {
                return (uv, beyond, w, 0.0);
            };
            let (pose_b, _) = self.next_pose(node, &frame_b, w, checked);
            let b = CrossProfile::new(&tool, self.surface, frame_b, &pose_b);
            let s = scallop_between(&a, &b, self.side * w);
            result = (uv, beyond, w, s);
            if (s - h).abs() < SIDE_STEP_REL * h {
                break;
            }
            if s < h {
                lo = lo.max(w);
            } else {
                hi = hi.min(w);
            }
            // h ∝ w² near the solution; the step is kept inside the bracket and within a
            // factor 2.
            let mut next = w * (h / s.max(1e-3 * h)).sqrt().clamp(0.5, 2.0);
            if next <= lo || next >= hi {
                next = if hi.is_finite() { 0.5 * (lo + hi) } else { 2.0 * lo.max(w) };
            }
            if next > w_max {
                next = w_max;
                if lo >= w_max {
                    break;
                }
            }
            w = next;
        }
        result
    }
}

/// How far (mm) a path's last cutter must travel on past the far end along its feed so that
/// every point of the far edge within `reach_mm` of the CC curve across is cut as low as the
/// moving cutter cuts elsewhere; `slant` is the tangent of the edge's angle from the cross
/// direction c (0 when the edge runs square to the feed). At most the cutter's diameter 2·R.
///
/// Two parts. (1) The cutter's lowest point at cross offset y trails the contact: with the
/// meridian along the feed (azimuth 0, the contact at the front of the corner torus) it lies
/// on the corner ball whose centre sits on the centre circle (radius R0 = R − r, in the
/// plane ⟂ a) at a lateral offset y_c between 0 and y, and that centre trails the contact's
/// centre by R0·(1 − cos φ)·cos α ≤ R0 − √(R0² − y²) along the feed (sin φ = y_c/R0). A
/// moving cutter cuts the point (x, y) when it stands that far ahead of x; stopped at the
/// end it leaves the static cutter's section there (measured: up to 2.4·h on the blade).
/// With a tilt (azimuth ≠ 0) the centre circle's diameter 2·R0 bounds this lag; a ball
/// (R0 = 0) has its lowest point beside the contact: 0. (2) A slanted edge's points at cross
/// offset y lie up to y·slant further ahead (on the blade's far edge the end nodes of
/// neighbouring paths are 0.32 mm apart along the feed for a 2.15 mm side step).
#[must_use]
pub fn lead_out_mm(cutter: &Cutter, pose: &Pose, reach_mm: f64, slant: f64) -> f64 {
    let r0 = cutter.torus_radius_mm();
    let y = reach_mm.max(0.0);
    let lag = if r0 <= 0.0 {
        0.0
    } else if pose.azimuth_rad != 0.0 {
        2.0 * r0
    } else {
        let yc = y.min(r0);
        r0 - (r0 * r0 - yc * yc).sqrt()
    };
    let ahead = if slant.is_finite() { y * slant.abs() } else { f64::INFINITY };
    (lag + ahead).min(2.0 * cutter.radius_mm)
}

/// The contact frame a lead-out of `d_mm` (mm) past `end` stands on: the surface continued
/// past the path's end to second order. The point moves along the feed's normal section
/// (d·f + ½·k_ff·d²·n), and the frame turns as the surface's normal turns along the feed,
/// dn/ds = −(k_ff·f + k_fc·c), df/ds = k_ff·n: the rotation by d·(k_fc·f − k_ff·c). The
/// cutter placed there with the last pose keeps its pose to the surface's continuation: its
/// lean across the feed follows the twist k_fc, its lean along it k_ff. Moved straight with
/// the axis held, on the mould (k_fc up to 0.005 /mm at a 2.4 mm side step, the bowl rising
/// ahead) the cusps of the last 0.4 mm before the far end rose to 1.19·h, 1.112·h inside the
/// edge lines; turned, ≤ 1.04·h (docs/fillet.md, "The mould's ends").
#[must_use]
pub fn lead_out_frame(end: &ContactFrame, d_mm: f64) -> ContactFrame {
    let (f, c, n) = (end.feed, end.cross, end.normal);
    let (ff, fc) = (end.surface_form.ff, end.surface_form.fc);
    // The point on the normal section's osculating circle (to second order: ½·ff·d² along n).
    let point = end.point + d_mm * f + 0.5 * ff * d_mm * d_mm * n;
    // The frame turned as the surface's normal turns along the feed: dn/ds = −(ff·f + fc·c),
    // df/ds = ff·n, i.e. the rotation vector (fc·f − ff·c) per mm.
    let rot = glam::DQuat::from_scaled_axis(d_mm * (fc * f - ff * c));
    ContactFrame { point, feed: rot * f, cross: rot * c, normal: rot * n, ..*end }
}

/// The forward step keeps the chord's sag within this share of h as well as within E: the
/// cutter between two CL rows moves on the chord, raised (concave along the feed) or lowered
/// (convex) by up to the sag, and the cusp with it. Measured from the CL data with E = h/20
/// (the examples): cusps of 0.947·h between the rows on the convex blade; with h/40 the band
/// keeps ±5 % with room for the side step's own ±0.5 % and the model's error. Applied only
/// where the surface is convex along the feed (the chord below it, the cusp lowered): on the
/// concave mould h/40 everywhere took the brute-force sections to 0.941–0.983·h (E alone:
/// 0.978–1.008·h), measured after merging the lead-outs with the mould's floor and trims.
const SAG_SHARE_OF_H: f64 = 1.0 / 40.0;

/// Halvings of a lead-out that the gouge checks find too long before it is left out.
const LEAD_OUT_HALVINGS: usize = 6;

/// Share of the gouge tolerance a lead-out's check allows (as `gouge::adjust` does: the
/// check measures the part's depth inside the cutter, a re-computation the cutter's below
/// the part; the two agree to first order).
const LEAD_OUT_CHECK_SHARE: f64 = 0.9;

/// A path's last node counts as on the along parameter's far end within this fraction of
/// the along range.
const LEAD_OUT_EDGE_REL: f64 = 1e-9;

/// An offset curve ready to be built: its uv polyline and, per vertex, the azimuth window
/// (centre, half width; rad) the side step assumed there.
type OffsetCurve = (Vec<DVec2>, Vec<(f64, f64)>);

/// A vertex of an offset curve: uv and the azimuth window (centre, half width; rad) the
/// side step assumed there.
type Vertex = (DVec2, (f64, f64));

/// Most segments after a segment of an offset curve that [`trim_swallowtails`] tests it
/// against: bounds its work by this × the vertices (a swallowtail spans a few nodes).
const SWALLOWTAIL_SEGMENTS: usize = 256;

/// Where segments p0p1 and q0q1 cross: the parameters (t, s) ∈ [0, 1)² along each, `None`
/// when they do not cross or are parallel.
fn crossing(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Option<(f64, f64)> {
    let (r, d, w) = (p1 - p0, q1 - q0, q0 - p0);
    let den = r.perp_dot(d);
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let t = w.perp_dot(d) / den;
    let s = w.perp_dot(r) / den;
    ((0.0..1.0).contains(&t) && (0.0..1.0).contains(&s)).then_some((t, s))
}

/// A vertex between `a` and `b` at `t`: uv and azimuth interpolated, the wider window.
fn vertex_between(a: &Vertex, b: &Vertex, t: f64) -> Vertex {
    (a.0.lerp(b.0, t), (a.1.0 + t * (b.1.0 - a.1.0), a.1.1.max(b.1.1)))
}

/// The offset curve with its swallowtails cut out: where segment i crosses a later segment
/// j (the farthest such j within [`SWALLOWTAIL_SEGMENTS`]), the loop between them is
/// replaced by the crossing point. Where the curve offsets a concave stretch of the last
/// path by more than its radius, it runs back over itself; the part of the loop beyond the
/// crossing lies inside the strip already cut. (Keeping only the vertices whose a increases,
/// as before, joined the loop's far branch to the near one across the crossing and left a
/// gap: the mould's 3.7·h, docs/fillet.md.)
fn trim_swallowtails(pts: &[Vertex]) -> Vec<Vertex> {
    let n = pts.len();
    let Some(first) = pts.first() else { return Vec::new() };
    let mut work = pts.to_vec();
    let mut out = vec![*first];
    let mut i = 0;
    while i + 1 < n {
        let last = (i + SWALLOWTAIL_SEGMENTS).min(n - 2);
        let cut = (i + 2..=last)
            .rev()
            .find_map(|j| crossing(work[i].0, work[i + 1].0, work[j].0, work[j + 1].0).map(|(t, s)| (j, t, s)));
        if let Some((j, t, s)) = cut {
            let x = vertex_between(&work[i], &work[i + 1], t);
            let x = (x.0, vertex_between(&work[j], &work[j + 1], s).1);
            out.push(x);
            work[j] = x;
            i = j;
        } else {
            out.push(work[i + 1]);
            i += 1;
        }
    }
    out
}

/// The polyline cut to the along range [a0, a1]: vertices outside are left out, and where a
/// segment crosses an edge the crossing is put in (so a stretch that leaves and re-enters
/// becomes a straight piece between the two crossings).
fn clip_along(pts: &[Vertex], (a0, a1): (f64, f64), along: usize) -> Vec<Vertex> {
    let inside = |v: &Vertex| (a0..=a1).contains(&a_of(v.0, along));
    let mut out = Vec::with_capacity(pts.len());
    for (k, v) in pts.iter().enumerate() {
        if k > 0 {
            let p = &pts[k - 1];
            let (ap, av) = (a_of(p.0, along), a_of(v.0, along));
            let mut cuts: Vec<f64> =
                [a0, a1].iter().filter(|&&e| (ap - e) * (av - e) < 0.0).map(|&e| (e - ap) / (av - ap)).collect();
            cuts.sort_by(f64::total_cmp);
            for t in cuts {
                let mut x = vertex_between(p, v, t);
                x.0 = make_uv((a_of(x.0, along)).clamp(a0, a1), b_of(x.0, along), along);
                out.push(x);
            }
        }
        if inside(v) {
            out.push(*v);
        }
    }
    out
}

/// Half the chord that gives an offset path's feed at a node, relative to the longest
/// forward step.
const FEED_CHORD: f64 = 0.5;

/// Share of the gouge tolerance the surface may reach into the cutter swept to a chord's
/// middle before the chord certification (`docs/fillet.md`, "Between the poses") puts a node there (the poses are checked to
/// `gouge::CHECK_SHARE` = 0.9 of it too).
pub const BETWEEN_CHECK_SHARE: f64 = 0.9;

/// Share of h the cutter swept to a chord's middle may stand clear of the surface (when
/// above the chord tolerance) before the chord certification (`docs/fillet.md`, "Between the poses") puts a node there.
pub const LIFT_SHARE_OF_H: f64 = 0.1;

/// The share of its parent's lift a halved chord's lift must fall below for the chord
/// certification to halve it again.
pub const LIFT_HALVING_GAIN: f64 = 0.5;

/// Most halvings of one chord by the chord certification (`docs/fillet.md`, "Between the poses") (up to 2⁴ − 1 nodes put into it).
pub const CHORD_SPLITS: usize = 4;

/// The measured cusp's band (× h) outside which the corrector builds a path again, the
/// cusp it aims at (× h), the most it scales a side step by in one round, and its rounds.
const CUSP_BAND: (f64, f64) = (0.0, 1.04);
const CUSP_TARGET: f64 = 0.995;
const CUSP_SCALE: (f64, f64) = (0.6, 1.0);
const CUSP_CORRECTIONS: usize = 4;

/// A measured cusp above this many h after the corrector is named in
/// [`PathSet::scallop_flags`].
pub const FLAG_ABOVE: f64 = 1.10;

/// Half the span (mm along the path) over which [`smooth_factors`] takes the smallest
/// factor, and the most the factor changes per mm of path.
const FACTOR_SPAN_MM: f64 = 3.0;
const FACTOR_SLOPE: f64 = 0.02;

/// Most change of the side step along a path (mm per mm of path): the offset curve turns by
/// at most about this many radians from the path it offsets ([`limit_step_slope`]).
const SIDE_STEP_SLOPE: f64 = 0.5;

/// Most rounds of the side-step correction, and its acceptance (relative to h).
const SIDE_STEP_ROUNDS: usize = 12;
const SIDE_STEP_REL: f64 = 0.005;

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

/// The side steps lowered until they change along the path by at most [`SIDE_STEP_SLOPE`]
/// mm per mm between neighbouring nodes (the lower Lipschitz envelope, one pass each way):
/// a step far above its neighbours' (a side-step solution that jumped, a cusp correction at
/// one node) would bend the offset curve into a kink that the next path's feed, and with it
/// its side steps, turns with; lowering never widens a scallop.
fn limit_step_slope(nodes: &[CcNode], steps: &mut [(usize, f64, bool, f64)]) {
    let gap = |i: usize, j: usize| match (nodes.get(i), nodes.get(j)) {
        (Some(a), Some(b)) => (b.frame.point - a.frame.point).length(),
        _ => 0.0,
    };
    for k in 1..steps.len() {
        let cap = steps[k - 1].1 + SIDE_STEP_SLOPE * gap(steps[k - 1].0, steps[k].0);
        steps[k].1 = steps[k].1.min(cap);
    }
    for k in (0..steps.len().saturating_sub(1)).rev() {
        let cap = steps[k + 1].1 + SIDE_STEP_SLOPE * gap(steps[k].0, steps[k + 1].0);
        steps[k].1 = steps[k].1.min(cap);
    }
}

/// The corrector's factors made smooth along the path: each the smallest within
/// [`FACTOR_SPAN_MM`] of its node, then lowered until it changes by at most
/// [`FACTOR_SLOPE`] per mm (a step scaled at one node and not at the next would put a kink
/// into the offset curve, which the paths after it inherit).
fn smooth_factors(nodes: &[CcNode], steps: &[(usize, f64, bool, f64)], factors: &[f64]) -> Vec<f64> {
    let at: Vec<f64> = {
        let mut s = 0.0;
        let mut prev: Option<DVec3> = None;
        steps
            .iter()
            .map(|st| {
                let p = nodes.get(st.0).map_or(DVec3::ZERO, |n| n.frame.point);
                if let Some(q) = prev {
                    s += (p - q).length();
                }
                prev = Some(p);
                s
            })
            .collect()
    };
    let mut out: Vec<f64> = (0..factors.len())
        .map(|k| {
            let lo = at.partition_point(|&x| x < at[k] - FACTOR_SPAN_MM);
            let hi = at.partition_point(|&x| x <= at[k] + FACTOR_SPAN_MM);
            factors[lo..hi.max(lo + 1).min(factors.len())].iter().copied().fold(factors[k], f64::min)
        })
        .collect();
    for k in 1..out.len() {
        out[k] = out[k].min(out[k - 1] + FACTOR_SLOPE * (at[k] - at[k - 1]));
    }
    for k in (0..out.len().saturating_sub(1)).rev() {
        out[k] = out[k].min(out[k + 1] + FACTOR_SLOPE * (at[k + 1] - at[k]));
    }
    out
}

/// The b at which the line from `other` through the end point `end` (uv) reaches the along
/// parameter `a`; `end`'s b when there is no other point or the line runs along b.
fn extend_b(other: Option<DVec2>, end: DVec2, a: f64, along: usize) -> f64 {
    let Some(o) = other else { return b_of(end, along) };
    let da = a_of(end, along) - a_of(o, along);
    if da == 0.0 {
        return b_of(end, along);
    }
    b_of(end, along) + (a - a_of(end, along)) / da * (b_of(end, along) - b_of(o, along))
}

/// A dense polyline of the iso-curve b = const (64 segments).
fn iso_curve(a_range: (f64, f64), b: f64, along: usize) -> Vec<DVec2> {
    (0..=64).map(|i| make_uv(a_range.0 + (a_range.1 - a_range.0) * f64::from(i) / 64.0, b, along)).collect()
}

/// Mean strip width (mm) over a 3 × 3 grid with paths along parameter `along`.
fn mean_strip(surface: &Surface, cutter: &Cutter, strategy: &Strategy, opts: &FinishOptions, along: usize) -> f64 {
    let d = surface.domain();
    let tool = strategy.cutter_for(cutter);
    let oo = &opts.orient;
    let mut sum = 0.0;
    let mut count = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let uv = DVec2::new(
                d.u.min + d.u.width() * (0.2 + 0.3 * f64::from(i)),
                d.v.min + d.v.width() * (0.2 + 0.3 * f64::from(j)),
            );
            let der = surface.derivatives_at(uv);
            let dir = if along == 0 { der.du } else { der.dv };
            let Some(frame) = ContactFrame::new(surface, uv, dir) else { continue };
            let Some((pose, _)) = pose_at(strategy, cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))
            else {
                continue;
            };
            let prof = CrossProfile::new(&tool, surface, frame, &pose);
            sum += prof.reach(opts.scallop_mm, 1.0) + prof.reach(opts.scallop_mm, -1.0);
            count += 1.0;
        }
    }
    if count > 0.0 { sum / count } else { 0.0 }
}

/// The parameter (0 = u, 1 = v) the paths run along: as asked, or for
/// [`FeedDirection::Auto`] the one with the wider mean strip (the widest-strip rule applied
/// to the two families of iso-curves).
#[must_use]
pub fn choose_along(surface: &Surface, cutter: &Cutter, strategy: &Strategy, opts: &FinishOptions) -> usize {
    match opts.direction {
        FeedDirection::U => 0,
        FeedDirection::V => 1,
        FeedDirection::Auto => {
            let wu = mean_strip(surface, cutter, strategy, opts, 0);
            let wv = mean_strip(surface, cutter, strategy, opts, 1);
            usize::from(wv > wu)
        }
    }
}

/// The strip width (mm) at `uv` for every feed direction θ (rad, from r_u toward n × r_u) in
/// `steps` equal steps over [0°, 180°), with the strategy's orientation: the thesis' rule
/// picks the widest.
#[must_use]
pub fn strip_by_direction(
    surface: &Surface,
    cutter: &Cutter,
    strategy: &Strategy,
    opts: &FinishOptions,
    uv: DVec2,
    steps: usize,
) -> Vec<(f64, f64)> {
    let der = surface.derivatives_at(uv);
    let Some(base) = ContactFrame::new(surface, uv, der.du) else { return Vec::new() };
    let tool = strategy.cutter_for(cutter);
    let oo = &opts.orient;
    let steps = steps.clamp(2, 720);
    (0..steps)
        .filter_map(|i| {
            let theta = std::f64::consts::PI * i as f64 / steps as f64;
            let frame = ContactFrame::new(surface, uv, base.direction(theta))?;
            let (pose, _) = pose_at(strategy, cutter, &frame, oo, (-oo.max_azimuth_rad, oo.max_azimuth_rad))?;
            let prof = CrossProfile::new(&tool, surface, frame, &pose);
            Some((theta, prof.reach(opts.scallop_mm, 1.0) + prof.reach(opts.scallop_mm, -1.0)))
        })
        .collect()
}

/// Iso-scallop paths (module docs). The same as running [`IsoScallopSteps`] to its end.
///
/// # Errors
/// A bad option, no path at the first boundary, or too many paths or nodes.
pub fn iso_scallop(
    surface: &Surface,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
    part: &PartSamples,
) -> Result<PathSet, FinishError> {
    iso_scallop_from(surface, cutter, strategy, opts, part, &PathStart::FirstBoundary)
}

/// Iso-scallop paths from the first path `start` says (module docs). The same as running
/// [`IsoScallopSteps::start_from`] to its end.
///
/// # Errors
/// A bad option or start curve, no path at the start, or too many paths or nodes.
pub fn iso_scallop_from(
    surface: &Surface,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
    part: &PartSamples,
    start: &PathStart,
) -> Result<PathSet, FinishError> {
    let mut steps = IsoScallopSteps::start_from(surface, cutter, strategy, opts, part, start)?;
    while !steps.step(surface, cutter, opts, part)? {}
    Ok(steps.finish())
}

/// Iso-scallop paths built one path per call, for callers that spread the work over time
/// (the app's tab). [`IsoScallopSteps::start`] builds the first path; every
/// [`IsoScallopSteps::step`] builds the next one from the side steps of the last; the
/// result is exactly [`iso_scallop`]'s. Every call must get the same surface, cutter,
/// options and part samples as `start`.
///
/// From a start curve the paths go to both sides, in this order (the order of machining):
/// the curve, the paths toward increasing b outward to b_max, then — after a linking move —
/// the paths toward decreasing b outward from the curve to b_min. Each path's side steps
/// and scallops are to the next path of its own side (the curve's: to the first path toward
/// increasing b); the last path of each side has none.
#[derive(Clone, Debug)]
pub struct IsoScallopSteps {
    strategy: Strategy,
    along: usize,
    /// +1 when c points toward increasing b (at the first path's first node).
    c_sign: f64,
    /// +1 while the paths advance toward increasing b, −1 toward decreasing b.
    toward: f64,
    /// The path the next step offsets from.
    frontier: usize,
    /// Whether the side toward decreasing b is still to be done from the start curve.
    second_side: bool,
    /// Whether that side is being done.
    in_second_side: bool,
    /// Where the covered band began (b, internal units): the edge or the curve's lowest b.
    start_b: f64,
    /// The index of the second side's first path, once built.
    second_side_at: Option<usize>,
    refused: Vec<Refusal>,
    flags: Vec<ScallopFlag>,
    budget: usize,
    /// The checking work so far (see [`Ctx::count_check`]): the part's cell count when the
    /// job started and the CC points checked.
    cells_at_start: u64,
    nodes_checked: u64,
    paths: Vec<ToolPath>,
    done: bool,
}

impl IsoScallopSteps {
    /// Checks the options and builds the first path (on the boundary b = b0).
    ///
    /// # Errors
    /// A bad option or no path at the first boundary.
    pub fn start(
        surface: &Surface,
        cutter: &Cutter,
        strategy: Strategy,
        opts: &FinishOptions,
        part: &PartSamples,
    ) -> Result<Self, FinishError> {
        Self::start_from(surface, cutter, strategy, opts, part, &PathStart::FirstBoundary)
    }

    /// Checks the options and the start, and builds the first path where `start` says.
    ///
    /// # Errors
    /// A bad option or start curve, or no path at the start.
    pub fn start_from(
        surface: &Surface,
        cutter: &Cutter,
        strategy: Strategy,
        opts: &FinishOptions,
        part: &PartSamples,
        start: &PathStart,
    ) -> Result<Self, FinishError> {
        let ctx = Ctx::start(surface, cutter, strategy, opts, part, start)?;
        let along = ctx.along;
        let (_, (b0, b1)) = ctx.ranges();
        let poly = ctx.first_polyline(start)?;
        let (toward, second_side) = match start {
            PathStart::Boundary(e) if e.at_max() => (-1.0, false),
            PathStart::FirstBoundary | PathStart::Boundary(_) => (1.0, false),
            PathStart::Curve(_) => (1.0, true),
        };
        let start_b = match start {
            PathStart::Curve(_) => poly.iter().map(|&p| b_of(p, along)).fold(b1, f64::min),
            _ => b0,
        };
        ctx.refuse_oversized(&poly)?;
        let mut refused = Vec::new();
        let mut budget = opts.max_nodes;
        let first = ctx.build_path(&poly, None, &mut refused, &mut budget)?;
        let Some(n0) = first.nodes.iter().find(|n| !n.lead_out) else {
            return Err(FinishError::NoPath { reason: refused.first().map_or("no CC point", |r| r.reason) });
        };
        // c toward increasing b?
        let g = LocalGeometry::try_new(surface.derivatives_at(n0.frame.uv));
        let tc = g.map_or(DVec2::ZERO, |g| g.tangent_coords(n0.frame.cross));
        let c_sign = if b_of(tc, along) >= 0.0 { 1.0 } else { -1.0 };
        Ok(Self {
            strategy,
            along,
            c_sign,
            toward,
            frontier: 0,
            second_side,
            in_second_side: false,
            start_b,
            second_side_at: None,
            refused,
            flags: Vec::new(),
            budget,
            cells_at_start: ctx.cells_at_start,
            nodes_checked: ctx.nodes_checked.get(),
            paths: vec![first],
            done: false,
        })
    }

    /// The current side is covered: on to the other side of the start curve, or done.
    /// Returns whether all is done.
    fn end_side(&mut self) -> bool {
        if self.second_side {
            self.second_side = false;
            self.in_second_side = true;
            self.toward = -1.0;
            self.frontier = 0;
            false
        } else {
            self.done = true;
            true
        }
    }

    /// Builds the next path; `Ok(true)` when the surface is covered (then further calls do
    /// nothing).
    ///
    /// # Errors
    /// Too many paths or nodes.
    pub fn step(
        &mut self,
        surface: &Surface,
        cutter: &Cutter,
        opts: &FinishOptions,
        part: &PartSamples,
    ) -> Result<bool, FinishError> {
        if self.done {
            return Ok(true);
        }
        let along = self.along;
        let (side, toward) = (self.c_sign * self.toward, self.toward);
        let ctx = Ctx {
            surface,
            cutter: *cutter,
            strategy: self.strategy,
            opts,
            part,
            along,
            side,
            toward,
            cells_at_start: self.cells_at_start,
            nodes_checked: std::cell::Cell::new(self.nodes_checked),
        };
        let (_, (b0, b1)) = ctx.ranges();
        if self.paths.len() >= opts.max_paths {
            return Err(FinishError::TooManyPaths { max_paths: opts.max_paths });
        }
        // The side steps from the start curve toward decreasing b are not stored on it: it
        // keeps those to the next path in the order of machining.
        let keep = !(self.in_second_side && self.frontier == 0);
        let Some(last) = self.paths.get_mut(self.frontier) else {
            self.done = true;
            return Ok(true);
        };
        let slack = 1e-12 * (b1 - b0);
        let on_far_edge = |uv: DVec2| {
            let b = b_of(uv, along);
            if toward > 0.0 { b >= b1 - slack } else { b <= b0 + slack }
        };
        if last.nodes.iter().all(|n| on_far_edge(n.frame.uv)) {
            return Ok(self.end_side());
        }
        // The side steps predicted from each node's cross profile (one per node, with whether
        // it reached the far edge).
        let mut steps: Vec<(usize, f64, bool, f64)> = Vec::with_capacity(last.nodes.len());
        for (i, node) in last.nodes.iter().enumerate().filter(|(_, n)| !n.lead_out) {
            let (_, beyond, w, s) = ctx.side_step(node);
            steps.push((i, w, beyond, s));
        }
        limit_step_slope(&last.nodes, &mut steps);
        let Some((poly, refs)) = ctx.offset_curve(&last.nodes, &steps) else {
            return Ok(self.end_side());
        };
        let (refused_before, budget_before) = (self.refused.len(), self.budget);
        let mut next = ctx.build_path(&poly, Some(&refs), &mut self.refused, &mut self.budget)?;
        // The corrector: the cusp measured between the path just built and this one, from
        // their swept cutters; where it leaves the band, the side steps there are scaled by
        // √(h / cusp) (the cusp grows with the square of the step) and the path built again.
        let tool = self.strategy.cutter_for(cutter);
        let h = opts.scallop_mm;
        let mut measured = ctx.measure_cusps(&tool, &last.nodes, &next.nodes, &steps);
        let off = |m: &Option<f64>| m.is_some_and(|c| c > CUSP_BAND.1 * h || c < CUSP_BAND.0 * h);
        // The rounds go on from the last trial (a round that made the cusp worse can still
        // lead to a better one); the one kept leaves the least cusp over the band, summed
        // over the nodes.
        let excess = |ms: &[Option<f64>]| ms.iter().flatten().map(|c| (c - CUSP_BAND.1 * h).max(0.0)).sum::<f64>();
        let mut best_excess = excess(&measured);
        let mut current = (steps.clone(), measured.clone());
        // Corrected only for the strategies whose paths are meant to leave h (matched, ball);
        // the fixed-lead and principal-axis cutters cannot match a concave surface's
        // curvature by their definition, and correcting them only spends checks (on the
        // mould, past the job's budget): their cusps are measured and named.
        let rounds = if matches!(self.strategy, Strategy::Matched | Strategy::Ball) { CUSP_CORRECTIONS } else { 0 };
        for _ in 0..rounds {
            if !current.1.iter().any(off) {
                break;
            }
            let factors: Vec<f64> = current
                .1
                .iter()
                .map(|m| match *m {
                    Some(c) if off(m) => (CUSP_TARGET * h / c.max(1e-3 * h)).sqrt().clamp(CUSP_SCALE.0, CUSP_SCALE.1),
                    _ => 1.0,
                })
                .collect();
            let factors = smooth_factors(&last.nodes, &current.0, &factors);
            let mut trial = current.0.clone();
            for (st, f) in trial.iter_mut().zip(&factors) {
                st.1 *= f;
            }
            limit_step_slope(&last.nodes, &mut trial);
            let Some((poly, refs)) = ctx.offset_curve(&last.nodes, &trial) else { break };
            let mut refused = self.refused[..refused_before].to_vec();
            let mut budget = budget_before;
            let again = ctx.build_path(&poly, Some(&refs), &mut refused, &mut budget)?;
            let again_measured = ctx.measure_cusps(&tool, &last.nodes, &again.nodes, &trial);
            let e = excess(&again_measured);
            if e < best_excess {
                best_excess = e;
                (steps, next, measured) = (trial.clone(), again, again_measured.clone());
                self.refused = refused;
                self.budget = budget;
            }
            current = (trial, again_measured);
        }
        // Where no round brought the cusp within FLAG_ABOVE·h, the place is named.
        for (&(i, ..), m) in steps.iter().zip(&measured) {
            if let (Some(c), Some(node)) = (*m, last.nodes.get(i))
                && c > FLAG_ABOVE * h
            {
                self.flags.push(ScallopFlag {
                    uv: node.frame.uv,
                    point: node.frame.point,
                    path: self.frontier,
                    scallop_mm: c,
                });
            }
        }
        if keep {
            for ((i, w, _, predicted), m) in steps.iter().zip(&measured) {
                if let Some(node) = last.nodes.get_mut(*i) {
                    node.side_step_mm = Some(*w);
                    node.scallop_mm = Some(m.unwrap_or(*predicted));
                }
            }
        }
        self.nodes_checked = ctx.nodes_checked.get();
        if next.nodes.is_empty() {
            return Ok(self.end_side());
        }
        self.paths.push(next);
        self.frontier = self.paths.len() - 1;
        // Refused as soon as the share covered says the whole would pass the cap (one side
        // from an edge; a start curve's two sides are left to the cap itself).
        if !self.second_side && !self.in_second_side {
            let share = self.progress(surface);
            let used = (opts.max_nodes - self.budget) as f64;
            if share >= ESTIMATE_AFTER_SHARE && used / share > opts.max_nodes as f64 {
                return Err(FinishError::Oversized {
                    paths: self.paths.len() as f64 / share,
                    nodes: used / share,
                    max_paths: opts.max_paths,
                    max_nodes: opts.max_nodes,
                });
            }
            // The checks' cost from an earlier share (they are what takes the time), with
            // room for a costly start below 5 %.
            let cells = part.cells_checked().saturating_sub(self.cells_at_start) as f64;
            let room = if share < ESTIMATE_AFTER_SHARE { 2.0 } else { 1.0 };
            if share >= CELLS_ESTIMATE_AFTER_SHARE
                && cells >= CELLS_ESTIMATE_AFTER
                && cells / share > room * opts.max_check_cells as f64
            {
                return Err(FinishError::TooMuchChecking {
                    detail: format!(
                        "would pass {} cells: about {:.2e} (estimated from the {:.0} % of the surface covered)",
                        opts.max_check_cells,
                        cells / share,
                        share * 100.0
                    ),
                });
            }
        }
        if self.in_second_side && self.second_side_at.is_none() {
            self.second_side_at = Some(self.frontier);
        }
        Ok(false)
    }

    /// The paths built so far (the last one's side steps and scallops are filled by the
    /// next `step`).
    #[must_use]
    pub fn paths(&self) -> &[ToolPath] {
        &self.paths
    }

    /// How far the paths have come across the surface, 0 … 1: the share of the surface's b
    /// range between where the paths began and the nearest node of the last path (1 when
    /// done). Advancing toward decreasing b (from the upper edge, or the start curve's
    /// second side), the share between the last path's farthest-back node and b_max.
    #[must_use]
    pub fn progress(&self, surface: &Surface) -> f64 {
        if self.done {
            return 1.0;
        }
        let d = surface.domain();
        let rb = if self.along == 0 { d.v } else { d.u };
        let span = rb.max - rb.min;
        let bs = || {
            self.paths.get(self.frontier).into_iter().flat_map(|p| p.nodes.iter()).map(|n| b_of(n.frame.uv, self.along))
        };
        let covered = if self.toward > 0.0 {
            bs().min_by(f64::total_cmp).map(|b| b - self.start_b)
        } else {
            bs().max_by(f64::total_cmp).map(|b| rb.max - b)
        };
        match covered {
            Some(c) if span > 0.0 => (c / span).clamp(0.0, 1.0),
            _ => 0.0,
        }
    }

    /// Whether the surface is covered.
    #[must_use]
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// The CC points refused so far.
    #[must_use]
    pub fn refused(&self) -> &[Refusal] {
        &self.refused
    }

    /// The path set built so far (all of it once `step` returned `Ok(true)`).
    #[must_use]
    pub fn finish(self) -> PathSet {
        PathSet {
            paths: self.paths,
            layout: Layout::IsoScallop,
            strategy: self.strategy,
            along: self.along,
            refused: self.refused,
            second_side: self.second_side_at,
            scallop_flags: self.flags,
        }
    }
}

/// Iso-parametric paths b = const at the same worst scallop h (module docs): the spacing
/// starts from the narrowest strip over a trial set of 9 iso-curves and is narrowed until
/// the scallop solved at every node to the next path is at most h (at most 8 rounds).
///
/// # Errors
/// As [`iso_scallop`].
pub fn iso_parametric(
    surface: &Surface,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
    part: &PartSamples,
) -> Result<PathSet, FinishError> {
    iso_parametric_from(surface, cutter, strategy, opts, part, &PathStart::FirstBoundary)
}

/// Iso-parametric paths along the parameter the iso-scallop paths from `start` run along
/// ([`PathStart::along`]), so the two layouts compare on the same feed direction; they are
/// the same b = const family for every start.
///
/// # Errors
/// As [`iso_scallop`].
pub fn iso_parametric_from(
    surface: &Surface,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
    part: &PartSamples,
    start: &PathStart,
) -> Result<PathSet, FinishError> {
    let ctx = Ctx::start(surface, cutter, strategy, opts, part, start)?;
    let along = ctx.along;
    let ((a0, a1), (b0, b1)) = ctx.ranges();
    let tool = strategy.cutter_for(cutter);
    let h = opts.scallop_mm;
    ctx.refuse_oversized(&iso_curve((a0, a1), b0, along))?;
    let mut refused = Vec::new();
    let mut budget = opts.max_nodes;
    // The first guess of the spacing: the narrowest strip over 9 trial curves, in b.
    let mut db = f64::INFINITY;
    for k in 0..9 {
        let b = b0 + (b1 - b0) * f64::from(k) / 8.0;
        let mut scratch = Vec::new();
        let p = ctx.build_path(&iso_curve((a0, a1), b, along), None, &mut scratch, &mut budget)?;
        for n in &p.nodes {
            let d = surface.derivatives_at(n.frame.uv);
            let sb = if along == 0 { d.dv } else { d.du };
            let across = sb.dot(n.frame.cross).abs();
            if across > 0.0 {
                db = db.min(n.strip_mm / across);
            }
        }
    }
    if !db.is_finite() || db <= 0.0 {
        return Err(FinishError::NoPath { reason: "no strip width could be computed on the trial paths" });
    }
    let mut budget = opts.max_nodes;
    for _round in 0..8 {
        let count = (((b1 - b0) / db).ceil() as usize + 1).max(2);
        if count > opts.max_paths {
            return Err(FinishError::TooManyPaths { max_paths: opts.max_paths });
        }
        budget = opts.max_nodes;
        refused.clear();
        let mut paths = Vec::with_capacity(count);
        for k in 0..count {
            let b = b0 + (b1 - b0) * k as f64 / (count - 1) as f64;
            paths.push(ctx.build_path(&iso_curve((a0, a1), b, along), None, &mut refused, &mut budget)?);
        }
        let spacing = (b1 - b0) / (count - 1) as f64;
        let mut worst = 0.0f64;
        for k in 0..count - 1 {
            let b_next = b0 + (b1 - b0) * (k + 1) as f64 / (count - 1) as f64;
            for node in paths[k].nodes.iter_mut().filter(|n| !n.lead_out) {
                let uv_b = make_uv(a_of(node.frame.uv, along), b_next, along);
                let Some(fb) = ContactFrame::new(surface, uv_b, node.frame.feed) else { continue };
                let oo = &opts.orient;
                let psi = node.pose.azimuth_rad;
                let pose_b = pose_at(
                    &strategy,
                    cutter,
                    &fb,
                    oo,
                    ((psi - 0.5).max(-oo.max_azimuth_rad), (psi + 0.5).min(oo.max_azimuth_rad)),
                )
                .map_or(node.pose, |p| p.0);
                let w = (fb.point - node.frame.point).dot(node.frame.cross);
                let pa = CrossProfile::new(&tool, surface, node.frame, &node.pose);
                let pb = CrossProfile::new(&tool, surface, fb, &pose_b);
                let s = scallop_between(&pa, &pb, w);
                node.side_step_mm = Some(w.abs());
                node.scallop_mm = Some(s);
                worst = worst.max(s);
            }
        }
        if worst <= h * 1.0001 {
            return Ok(PathSet {
                paths,
                layout: Layout::IsoParametric,
                strategy,
                along,
                refused,
                second_side: None,
                scallop_flags: Vec::new(),
            });
        }
        db = spacing * (h / worst).sqrt() * 0.999;
    }
    let _ = budget;
    Err(FinishError::NoPath { reason: "the iso-parametric spacing did not settle in 8 rounds" })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertices(pts: &[(f64, f64)]) -> Vec<Vertex> {
        pts.iter().enumerate().map(|(k, &(u, v))| (DVec2::new(u, v), (k as f64, 0.1))).collect()
    }

    /// Does any segment of the polyline cross a non-adjacent one? (brute force over all pairs)
    fn self_crossing(p: &[Vertex]) -> bool {
        (0..p.len().saturating_sub(1)).any(|i| {
            (i + 2..p.len().saturating_sub(1)).any(|j| crossing(p[i].0, p[i + 1].0, p[j].0, p[j + 1].0).is_some())
        })
    }

    #[test]
    fn a_swallowtail_is_cut_at_its_crossing() {
        // Along u, then a loop back over itself (the offset of a tight concave stretch), then
        // along again: segments 1-2 and 4-5 cross at (0.5, 0.1).
        let p = vertices(&[(0.0, 0.0), (0.4, 0.0), (0.7, 0.2), (0.6, 0.3), (0.3, 0.2), (0.7, 0.1), (1.0, 0.1)]);
        assert!(self_crossing(&p));
        let t = trim_swallowtails(&p);
        assert!(!self_crossing(&t), "{t:?}");
        // The loop's vertices are gone, the crossing replaces them, the ends are kept.
        let uv: Vec<DVec2> = t.iter().map(|v| v.0).collect();
        assert_eq!(uv.len(), 5, "{uv:?}");
        assert_eq!(uv[0], DVec2::new(0.0, 0.0));
        assert_eq!(uv[1], DVec2::new(0.4, 0.0));
        // Segment (0.4, 0) → (0.7, 0.2) meets (0.3, 0.2) → (0.7, 0.1) where both lines agree.
        let x = uv[2];
        let on_first = (x - DVec2::new(0.4, 0.0)).perp_dot(DVec2::new(0.3, 0.2));
        let on_second = (x - DVec2::new(0.3, 0.2)).perp_dot(DVec2::new(0.4, -0.1));
        assert!(on_first.abs() < 1e-12 && on_second.abs() < 1e-12, "{x}");
        assert_eq!(uv[3], DVec2::new(0.7, 0.1));
        assert_eq!(uv[4], DVec2::new(1.0, 0.1));
        // The crossing's azimuth window comes from the far branch (segment 4-5): between 4 and 5.
        assert!(t[2].1.0 > 4.0 && t[2].1.0 < 5.0, "{:?}", t[2]);
    }

    #[test]
    fn a_curve_without_crossings_is_left_as_it_is() {
        let p: Vec<Vertex> = (0..200)
            .map(|k| {
                let u = f64::from(k) / 199.0;
                (DVec2::new(u, 0.3 + 0.05 * (9.0 * u).sin()), (0.0, 0.1))
            })
            .collect();
        assert_eq!(trim_swallowtails(&p), p);
    }

    #[test]
    fn the_offset_is_cut_at_the_along_edges() {
        // Leaves through a = 0 on the left (as the mould's corner offsets do), runs inside,
        // leaves and re-enters through a = 1.
        let p = vertices(&[(-0.2, 0.1), (0.2, 0.3), (0.8, 0.3), (1.2, 0.5), (0.9, 0.7)]);
        for along in [0, 1] {
            let q: Vec<Vertex> =
                p.iter().map(|v| (if along == 0 { v.0 } else { DVec2::new(v.0.y, v.0.x) }, v.1)).collect();
            let c = clip_along(&q, (0.0, 1.0), along);
            let a: Vec<f64> = c.iter().map(|v| a_of(v.0, along)).collect();
            let b: Vec<f64> = c.iter().map(|v| b_of(v.0, along)).collect();
            assert_eq!(c.len(), 6, "{c:?}");
            // The entry through a = 0 at b = 0.2, the exit and re-entry through a = 1 at
            // b = 0.4 and b = 0.5 + 0.2·⅔ (linear along the segments).
            let want = [(0.0, 0.2), (0.2, 0.3), (0.8, 0.3), (1.0, 0.4), (1.0, 0.5 + 0.2 * 2.0 / 3.0), (0.9, 0.7)];
            for (k, &(wa, wb)) in want.iter().enumerate() {
                assert!((a[k] - wa).abs() < 1e-12 && (b[k] - wb).abs() < 1e-12, "{k}: {} {}", a[k], b[k]);
            }
        }
    }
}
