//! Gouge and interference checks of a placed cutter against the part, and the adjustment of
//! the orientation until they pass.
//!
//! - **Local, bottom and rear**: how deep the part reaches into the cutter's convex solid
//!   (the bottom `disc(R0) ⊕ ball(r)` extended up the flutes), certified by branch and bound
//!   over the parameter plane with a bound of the surface's second derivative (see
//!   `bottom_clash`): deeper than the tolerance anywhere on the part is a gouge. Only points
//!   of the part count, so a cutter overhanging an edge of the domain is over no material.
//!   On a part convex everywhere (k⁺ ≤ 0 on the sample grid) the cutter, a convex solid
//!   resting on the tangent plane, cannot gouge, and this check costs nothing.
//! - **Global**: the part's sample points (a grid) against the cutter's solid of revolution
//!   around the axis: a point at height z above the tip and distance ρ from the axis
//!   collides when ρ < (the solid's radius at z) − tolerance — with the flutes (a gouge), the
//!   shank or the holder (an interference).
//!
//! Where a check fails the inclination is raised in steps of 0.25° (to the strategy's largest),
//! then the azimuth turned by ±10°, ±20°, ±30°; the first pose that passes is kept and the
//! change reported. When none passes the point is refused with the reason. The raises are
//! tried one by one while a failing one costs nothing (it clashes where the last one did);
//! once checks get costly the search strides over 2° and halves back, and at every azimuth
//! before it looks between the strides (`adjust`).
//!
//! For a program on a machine the same search keeps the axis within the machine's rotary
//! travel: a pose out of travel is first turned to the nearest axis the machine reaches
//! (within the strategy's largest inclination) and the search starts there; a pose the
//! machine cannot tilt to fails as a clash would ([`ClashPart::Travel`] when that is all
//! that failed).

use glam::{DVec2, DVec3};

use super::contact::{ContactFrame, Pose, gouge_margin, place};
use super::orient::OrientOptions;
use super::second_bound::{FIRST_CELLS, SecondBound};
use crate::fiveaxis::Machine;
use crate::geom::{Cutter, LocalGeometry, ParametricSurface, Surface};

/// Which part of the cutter met the part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClashPart {
    /// The bottom or corner (a local or rear gouge).
    Bottom,
    /// The flank of the flutes (a gouge).
    Flank,
    /// The shank (an interference).
    Shank,
    /// The holder (an interference).
    Holder,
    /// No part of the cutter: the machine cannot tilt its axis there (its rotary travel;
    /// [`adjust`] with a machine to reach).
    Travel,
}

impl ClashPart {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Bottom => "bottom",
            Self::Flank => "flank",
            Self::Shank => "shank",
            Self::Holder => "holder",
            Self::Travel => "travel",
        }
    }
}

/// A failed check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clash {
    /// Where on the cutter.
    pub part: ClashPart,
    /// How far the part reaches into the cutter (mm).
    pub depth_mm: f64,
    /// The part's point (mm).
    pub at: DVec3,
}

/// The part sampled once for all checks.
#[derive(Clone, Debug)]
pub struct PartSamples {
    /// Grid points of the surface (mm).
    pub points: Vec<DVec3>,
    /// The largest concave normal curvature k⁺ found on the grid (1/mm; ≤ 0 when convex
    /// everywhere).
    pub k_concave_max: f64,
    /// K: a bound of the second derivative of the surface along any unit direction of the
    /// parameter plane, `|r_uu e_u² + 2 r_uv e_u e_v + r_vv e_v²| ≤ K` (mm per internal
    /// parameter unit²): the largest eigenvalue of `[[|r_uu|, |r_uv|], [|r_uv|, |r_vv|]]`
    /// over the grid, times [`SECOND_DERIVATIVE_ALLOWANCE`]. The plane, cylinder, sphere and
    /// torus have constant or trigonometric second derivatives whose largest values lie on
    /// the grid's rows; for a NURBS the allowance covers the variation between grid points.
    pub second_bound: f64,
    /// K near each cell of the bottom check's subdivision (from the same grid, with the same
    /// allowance): the bound [`bottom_clash`] uses, so that a place where the surface bends
    /// hard does not loosen the bound everywhere else.
    second_map: SecondBound,
    /// The grid's side n (`points` holds n × n, row i at `i·n`).
    side: usize,
    /// Blocks of up to [`BLOCK`] × [`BLOCK`] grid points: first row, first column, and a
    /// sphere (centre, radius mm) holding all their points, so the global check can pass a
    /// whole block over at once.
    blocks: Vec<(usize, usize, DVec3, f64)>,
    /// Cells the certified bottom checks against these samples have evaluated so far (the
    /// measure of a plan's checking work, [`PartSamples::cells_checked`]).
    checked: CellCount,
    /// Bottom checks that ran out of cells and reported their lowest bound as a clash.
    exhausted: CellCount,
    /// Poses checked against these samples (each a global check and, on a part with a
    /// concave place, a bottom check).
    poses: CellCount,
    /// Side-step trials (a walk across, a frame, a cross profile and a scallop) and cusps
    /// measured between paths: the path builder's other costly work, counted here so that
    /// one counter per job holds all of it ([`PartSamples::work_done`]).
    pub(crate) side_trials: CellCount,
    /// See [`PartSamples::side_trials`].
    pub(crate) cusps: CellCount,
}

/// A count that several checks may add to through a shared reference (relaxed atomics: it
/// only measures work); a clone starts from the same count.
#[derive(Debug, Default)]
pub(crate) struct CellCount(std::sync::atomic::AtomicU64);

impl Clone for CellCount {
    fn clone(&self) -> Self {
        Self(std::sync::atomic::AtomicU64::new(self.get()))
    }
}

impl CellCount {
    pub(crate) fn add(&self, n: usize) {
        self.0.fetch_add(n as u64, std::sync::atomic::Ordering::Relaxed);
    }
    pub(crate) fn get(&self) -> u64 {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// [`PartSamples::work_done`]'s weights, in bottom-check cells: a least-squares fit of the
/// CPU time of the 50 plans named there against their counts (a cell then costs about
/// 0.2 µs). The grid points a global check tests are not counted: they added nothing to the
/// fit beyond the poses.
pub const WORK_PER_POSE: u64 = 2;

/// See [`WORK_PER_POSE`].
pub const WORK_PER_SIDE_TRIAL: u64 = 6;

/// See [`WORK_PER_POSE`].
pub const WORK_PER_CUSP: u64 = 190;

/// Grid points per side of a block of [`PartSamples`].
const BLOCK: usize = 4;

/// Factor on the grid's largest second derivative for [`PartSamples::second_bound`].
pub const SECOND_DERIVATIVE_ALLOWANCE: f64 = 1.25;

impl PartSamples {
    /// An n × n grid over the domain (n clamped to [4, 200]).
    #[must_use]
    pub fn new(surface: &Surface, n: usize) -> Self {
        let n = n.clamp(4, 200);
        let dom = surface.domain();
        let mut points = Vec::with_capacity(n * n);
        let mut kmax = f64::NEG_INFINITY;
        let mut second = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                let uv = DVec2::new(
                    dom.u.min + dom.u.width() * i as f64 / (n - 1) as f64,
                    dom.v.min + dom.v.width() * j as f64 / (n - 1) as f64,
                );
                let d = surface.derivatives_at(uv);
                points.push(d.point);
                let (a, b, c) = (d.duu.length(), d.duv.length(), d.dvv.length());
                second.push(SECOND_DERIVATIVE_ALLOWANCE * (0.5 * (a + c) + (0.5 * (a - c)).hypot(b)));
                if let Some(g) = LocalGeometry::try_new(d) {
                    kmax = kmax.max(g.principal_curvatures().0);
                }
            }
        }
        let mut blocks = Vec::new();
        for i0 in (0..n).step_by(BLOCK) {
            for j0 in (0..n).step_by(BLOCK) {
                let block =
                    || (i0..(i0 + BLOCK).min(n)).flat_map(move |i| (j0..(j0 + BLOCK).min(n)).map(move |j| i * n + j));
                let count = block().count() as f64;
                let centre = block().map(|k| points[k]).sum::<DVec3>() / count;
                let radius = block().map(|k| (points[k] - centre).length()).fold(0.0, f64::max);
                blocks.push((i0, j0, centre, radius));
            }
        }
        let second_map = SecondBound::from_grid(&second, n);
        Self {
            points,
            k_concave_max: kmax,
            second_bound: second_map.global(),
            second_map,
            side: n,
            blocks,
            checked: CellCount::default(),
            exhausted: CellCount::default(),
            poses: CellCount::default(),
            side_trials: CellCount::default(),
            cusps: CellCount::default(),
        }
    }

    /// The bound of the second derivative near each cell of the bottom check
    /// ([`SecondBound`]), from this grid.
    #[must_use]
    pub fn second_map(&self) -> &SecondBound {
        &self.second_map
    }

    /// Cells evaluated so far by the certified bottom checks against these samples (each at
    /// most `MAX_CELLS` a check): the planner stops a plan whose checks grow beyond its
    /// budget (`paths::MAX_CHECK_CELLS`).
    #[must_use]
    pub fn cells_checked(&self) -> u64 {
        self.checked.get()
    }

    /// The path builders' work against these samples so far, in units of one bottom-check
    /// cell: the cells, plus [`WORK_PER_POSE`] a pose checked, [`WORK_PER_SIDE_TRIAL`] a
    /// side-step trial and [`WORK_PER_CUSP`] a cusp measured between paths. Unlike the cells
    /// alone it follows a plan's CPU time wherever that goes (a convex part has no bottom
    /// check at all; a tightly curved one spends most of its time in side steps and
    /// global checks): the 50 plans of the three example tables and two fuzz-found tables
    /// took 0.73–1.52 times what their work predicts.
    #[must_use]
    pub fn work_done(&self) -> u64 {
        self.checked.get()
            + WORK_PER_POSE * self.poses.get()
            + WORK_PER_SIDE_TRIAL * self.side_trials.get()
            + WORK_PER_CUSP * self.cusps.get()
    }
}

/// Most cells [`bottom_clash`] evaluates; beyond it the cell with the lowest bound is
/// reported as a clash (a refusal errs on the safe side).
const MAX_CELLS: usize = 40_000;
/// Cells [`bottom_clash`] reserves room for at its start (more are added as needed).
const CELLS_RESERVED: usize = 512;
/// Deepest subdivision of a first-grid cell: halvings of one side or the other (32, as many
/// as 16 levels of quarters).
const MAX_DEPTH: u32 = 32;

/// The cutter's convex solid near the part: the corner ball (radius r) swept over the solid
/// cylinder ("core") of radius R0 between the corner centres' height r and the flute length
/// — the bottom `disc(R0) ⊕ ball(r)` extended up the flutes. A flat end mill (r below twice
/// the tolerance) is taken with a corner of twice the tolerance, which differs from its
/// sharp rim by less than the tolerance.
#[derive(Clone, Copy, Debug)]
struct CutterBody {
    tip: DVec3,
    axis: DVec3,
    r: f64,
    r0: f64,
    top: f64,
}

impl CutterBody {
    fn new(cutter: &Cutter, tip: DVec3, axis: DVec3, tol_mm: f64) -> Self {
        let r = cutter.corner_radius_mm.max(2.0 * tol_mm).min(cutter.radius_mm);
        Self { tip, axis, r, r0: (cutter.radius_mm - r).max(0.0), top: cutter.flute_length_mm.max(r) }
    }

    /// Signed distance (mm, negative inside) of `p` and a unit subgradient of the distance
    /// to the core there (zero inside the core): the distance to the core − r. The core is
    /// the product of a disc (radius R0, ⊥ a) and an interval of a, so its nearest point
    /// clamps the axial and the radial coordinate separately.
    fn signed_distance(&self, p: DVec3) -> (f64, DVec3) {
        let w = p - self.tip;
        let z = w.dot(self.axis);
        let radial = w - z * self.axis;
        let rho = radial.length();
        let zc = z.clamp(self.r, self.top);
        let near = self.tip + zc * self.axis + if rho > self.r0 { radial * (self.r0 / rho) } else { radial };
        let d = (p - near).length();
        let grad = if d > 0.0 { (p - near) / d } else { DVec3::ZERO };
        (d - self.r, grad)
    }
}

/// One cell of the parameter plane: centre, half sizes, the gouge function's lower bound.
#[derive(Clone, Copy, Debug)]
struct Cell {
    centre: DVec2,
    half: DVec2,
    depth: u32,
    /// Halvings across u and v from the first grid, and the cell's place among the
    /// rectangles of that level (see [`SecondBound`]).
    level: (u32, u32),
    index: (u64, u64),
    /// K on the cell: [`SecondBound::at`].
    k2: f64,
    /// The gouge function at the centre (mm).
    g: f64,
    /// |∂g/∂u|·hu and |∂g/∂v|·hv at the centre (mm): what each side costs the bound.
    slope: DVec2,
    /// Lower bound of the gouge function over the cell (mm).
    bound: f64,
}

/// A cell waiting in [`bottom_clash`]'s heap: its bound and its index among the cells
/// (16 bytes to move in the heap instead of the cell's 72).
#[derive(Clone, Copy, Debug)]
struct Open {
    bound: f64,
    index: usize,
}

impl PartialEq for Open {
    fn eq(&self, other: &Self) -> bool {
        self.bound.total_cmp(&other.bound).is_eq()
    }
}
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Open {
    /// The lowest bound comes first out of the max-heap (the bound alone decides, so the
    /// heap pops in the same order as one holding the cells themselves).
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.bound.total_cmp(&self.bound)
    }
}

/// The bottom/rear gouge check, certified: a point of the part inside the cutter's solid
/// ([`CutterBody`]) by more than `tol_mm`, found by branch and bound over the parameter
/// plane, or `None` when there is none.
///
/// The gouge function is `g(u, v) = d(r(u, v)) − r`, d the distance to the core, a convex
/// set. d is a convex function of space, 1-Lipschitz, with the unit vector from the nearest
/// core point as its (sub)gradient ∇d(p); so for every point x of the part
/// `d(x) ≥ d(p) + ∇d(p)·(x − p)` (the supporting plane), inside the core too. On a cell of
/// centre c and half sizes (hu, hv), `r(c + δ) − r(c) = r_u δu + r_v δv + R` with
/// `|R| ≤ ½·K·|δ|²`, K the bound of |r_ee| along unit directions e of the parameter plane
/// on the cell: the largest at the part's grid points within one spacing of the cell, times
/// the allowance ([`SecondBound`]; a surface's worst place bounds only the cells near it).
/// Hence on the whole cell
///
/// `g ≥ g(c) − |g_u|·hu − |g_v|·hv − ½·K·(hu² + hv²)`,   `g_u = ∇d·r_u`, `g_v = ∇d·r_v`,
///
/// with no curvature of the cutter in it (the convexity of d carries it). A cell whose
/// bound is above −tol has no point below −tol and is dropped; a centre below −tol is a
/// gouge; the rest are halved across the side that costs the bound more (|g_u|·hu + ½·K·hu²
/// against the same in v), the lowest bound first. Halving one side at a time lets the
/// cells follow the contact's basin, narrow along the feed (where the corner's 1/r curves
/// g) and long across it (where g is as flat as the strip is wide). A pocket between
/// samples cannot be missed.
///
/// `hint`: a parameter pair to try first (where an earlier pose clashed). A gouge found
/// there is a gouge; without one the search runs as without the hint, so whether a clash is
/// reported never depends on it (only which one). Returns the clash with its parameters.
fn bottom_clash(
    surface: &Surface,
    body: &CutterBody,
    part: &PartSamples,
    tol_mm: f64,
    hint: Option<DVec2>,
) -> Option<(Clash, DVec2)> {
    /// Adds the cells a search evaluated to the count however it returns.
    struct Tally<'c>(&'c CellCount, usize);
    impl Drop for Tally<'_> {
        fn drop(&mut self) {
            self.0.add(self.1);
        }
    }
    let dom = surface.domain();
    if let Some(uv) = hint.filter(|&uv| dom.contains(uv)) {
        let at = surface.point_at(uv);
        let (g, _) = body.signed_distance(at);
        if g < -tol_mm {
            return Some((Clash { part: ClashPart::Bottom, depth_mm: -g, at }, uv));
        }
    }
    let make = |centre: DVec2, half: DVec2, depth: u32, level: (u32, u32), index: (u64, u64)| {
        // Only r, r_u and r_v enter the bound; to rounding is enough (a NURBS's power form).
        let (point, du, dv) = surface.tangents_fast_at(centre);
        let (g, grad) = body.signed_distance(point);
        let slope = DVec2::new(grad.dot(du).abs() * half.x, grad.dot(dv).abs() * half.y);
        let k2 = part.second_map.at(level, index);
        let bound = g - slope.x - slope.y - 0.5 * k2 * half.length_squared();
        (Cell { centre, half, depth, level, index, k2, g, slope, bound }, point)
    };
    let n = FIRST_CELLS;
    let mut evaluated = Tally(&part.checked, n * n);
    let half = DVec2::new(0.5 * dom.u.width() / n as f64, 0.5 * dom.v.width() / n as f64);
    let origin = DVec2::new(dom.u.min, dom.v.min);
    // Sized for a typical check (the examples' average 185–335 cells), so that the cells
    // are not copied as the vector grows.
    let mut heap = std::collections::BinaryHeap::with_capacity(CELLS_RESERVED / 2);
    let mut cells: Vec<Cell> = Vec::with_capacity(CELLS_RESERVED);
    let open = |heap: &mut std::collections::BinaryHeap<Open>, cells: &mut Vec<Cell>, cell: Cell| {
        heap.push(Open { bound: cell.bound, index: cells.len() });
        cells.push(cell);
    };
    for i in 0..n {
        for j in 0..n {
            let centre = origin + DVec2::new((2 * i + 1) as f64 * half.x, (2 * j + 1) as f64 * half.y);
            let (cell, at) = make(centre, half, 0, (0, 0), (i as u64, j as u64));
            if cell.g < -tol_mm {
                return Some((Clash { part: ClashPart::Bottom, depth_mm: -cell.g, at }, centre));
            }
            if cell.bound < -tol_mm {
                open(&mut heap, &mut cells, cell);
            }
        }
    }
    while let Some(Open { index, .. }) = heap.pop() {
        // Every index pushed is that of a cell pushed with it.
        let cell = cells[index];
        if evaluated.1 > MAX_CELLS || cell.depth >= MAX_DEPTH {
            // Out of budget: err on the safe side.
            part.exhausted.add(1);
            let at = surface.point_at(cell.centre);
            return Some((Clash { part: ClashPart::Bottom, depth_mm: -cell.bound, at }, cell.centre));
        }
        let cost_u = cell.slope.x + 0.5 * cell.k2 * cell.half.x * cell.half.x;
        let cost_v = cell.slope.y + 0.5 * cell.k2 * cell.half.y * cell.half.y;
        let across_u = cost_u >= cost_v;
        let (half, step, level) = if across_u {
            (
                DVec2::new(0.5 * cell.half.x, cell.half.y),
                DVec2::new(0.5 * cell.half.x, 0.0),
                (cell.level.0 + 1, cell.level.1),
            )
        } else {
            (
                DVec2::new(cell.half.x, 0.5 * cell.half.y),
                DVec2::new(0.0, 0.5 * cell.half.y),
                (cell.level.0, cell.level.1 + 1),
            )
        };
        for (sign, upper) in [(-1.0, 0), (1.0, 1)] {
            let index = if across_u {
                (2 * cell.index.0 + upper, cell.index.1)
            } else {
                (cell.index.0, 2 * cell.index.1 + upper)
            };
            let (child, at) = make(cell.centre + sign * step, half, cell.depth + 1, level, index);
            evaluated.1 += 1;
            if child.g < -tol_mm {
                return Some((Clash { part: ClashPart::Bottom, depth_mm: -child.g, at }, child.centre));
            }
            if child.bound < -tol_mm {
                open(&mut heap, &mut cells, child);
            }
        }
    }
    None
}

/// Most cells [`adjust`]'s trials of other poses may evaluate for one CC point (four
/// checks' worth of 40 000 cells); past it the point is refused with the clash of its pose.
pub const MAX_ADJUST_CELLS: u64 = 4 * MAX_CELLS as u64;

/// Share of the gouge tolerance allowed by [`adjust`]: the check measures how deep the
/// part reaches into the cutter, the independent re-computation how deep the cutter reaches
/// below the part; the two agree at the deepest point to first order, and the share keeps
/// the print's rounding and that second-order difference inside the tolerance.
pub const CHECK_SHARE: f64 = 0.9;

/// Checks the cutter placed at `frame` with `pose` (module docs); the deepest clash, or
/// `None` when it is clear to `tol_mm`.
#[must_use]
pub fn check(
    cutter: &Cutter,
    surface: &Surface,
    part: &PartSamples,
    frame: &ContactFrame,
    pose: &Pose,
    tol_mm: f64,
) -> Option<Clash> {
    check_hinted(cutter, surface, part, place(cutter, frame, pose), tol_mm, &mut Hint::default(), Find::Deepest)
}

/// Where the last pose tried clashed: the bottom check's parameters and the index of a
/// part sample inside the cutter. The next pose (a quarter degree on) is tested there first,
/// which answers most failing trials with one evaluation.
#[derive(Clone, Copy, Debug, Default)]
struct Hint {
    bottom: Option<DVec2>,
    global: Option<usize>,
}

/// How much of a clash a check must find.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Find {
    /// The deepest clash of the global check (and the bottom check's first): what a
    /// refusal or an adjustment reports.
    Deepest,
    /// Any clash: a trial pose of [`adjust`] only needs to know whether it passes.
    Any,
}

/// [`check`] trying the places in `hint` first and leaving there those of a clash found:
/// whether a clash is reported is the same as without the hint, only which one may differ.
/// With [`Find::Any`] the first clash found is returned.
/// `placed`: the tip and the unit axis ([`place`]).
fn check_hinted(
    cutter: &Cutter,
    surface: &Surface,
    part: &PartSamples,
    placed: (DVec3, DVec3),
    tol_mm: f64,
    hint: &mut Hint,
    find: Find,
) -> Option<Clash> {
    let (tip, axis) = placed;
    part.poses.add(1);
    let mut worst: Option<Clash> = None;
    // Local and rear: the part against the cutter's convex solid, certified.
    if part.k_concave_max > 0.0
        && let Some((c, uv)) =
            bottom_clash(surface, &CutterBody::new(cutter, tip, axis, tol_mm), part, tol_mm, hint.bottom)
    {
        hint.bottom = Some(uv);
        if find == Find::Any {
            return Some(c);
        }
        worst = Some(c);
    }
    // Global: the part's points against the solid of revolution. A block whose sphere
    // (centre c, radius ρb) lies wholly at or below the corner's height, wholly above the
    // holder, or wholly farther from the axis than the tool is wide over the block's heights
    // holds no colliding point (z and the distance to the axis are 1-Lipschitz in space)
    // and is passed over.
    let length = cutter.gauge_length_mm + cutter.holder_length_mm;
    let clash_at = |p: DVec3| {
        let w = p - tip;
        let z = w.dot(axis);
        if z <= cutter.corner_radius_mm {
            return None;
        }
        let rad = cutter.radius_at_height_mm(z)?;
        let rho = (w - z * axis).length();
        (rho < rad - tol_mm).then(|| {
            let part = if z <= cutter.flute_length_mm {
                ClashPart::Flank
            } else if z <= cutter.gauge_length_mm {
                ClashPart::Shank
            } else {
                ClashPart::Holder
            };
            Clash { part, depth_mm: rad - rho, at: p }
        })
    };
    if find == Find::Any
        && let Some(c) = hint.global.and_then(|k| part.points.get(k)).and_then(|&p| clash_at(p))
    {
        return Some(c);
    }
    let mut test = |k: usize, p: DVec3| {
        let Some(c) = clash_at(p) else { return false };
        hint.global = Some(k);
        if worst.is_none_or(|w| c.depth_mm > w.depth_mm) {
            worst = Some(c);
        }
        find == Find::Any
    };
    let n = part.side;
    if n * n == part.points.len() {
        for &(i0, j0, c, rb) in &part.blocks {
            let w = c - tip;
            let z = w.dot(axis);
            let rho = (w - z * axis).length();
            if z + rb <= cutter.corner_radius_mm
                || z - rb > length
                || rho - rb >= widest_between(cutter, z - rb, z + rb) - tol_mm
            {
                continue;
            }
            for i in i0..(i0 + BLOCK).min(n) {
                for k in i * n + j0..i * n + (j0 + BLOCK).min(n) {
                    if test(k, part.points[k]) {
                        return worst;
                    }
                }
            }
        }
    } else {
        for (k, &p) in part.points.iter().enumerate() {
            if test(k, p) {
                return worst;
            }
        }
    }
    worst
}

/// The widest the cutter's solid of revolution is (mm) at any height above the tip in
/// `[lo, hi]` (mm), or 0 when the interval misses it: R below the flute length (the corner
/// and a taper's cone never pass R), the shank's radius up to the gauge length, the
/// holder's above it.
fn widest_between(cutter: &Cutter, lo: f64, hi: f64) -> f64 {
    let (flutes, gauge) = (cutter.flute_length_mm.max(cutter.cone_height_mm()), cutter.gauge_length_mm);
    let top = gauge + cutter.holder_length_mm;
    if hi < 0.0 || lo > top {
        return 0.0;
    }
    let mut widest = 0.0f64;
    if lo <= flutes {
        widest = widest.max(cutter.radius_mm);
    }
    if lo <= gauge && hi > cutter.flute_length_mm {
        widest = widest.max(cutter.shank_radius_mm);
    }
    if hi > gauge {
        widest = widest.max(cutter.holder_radius_mm);
    }
    widest
}

/// How far inside the machine's rotary travel [`adjust`] keeps a pose's angles (rad; 0.1°):
/// the axis between two poses, interpolated as the program moves, may swing a little past
/// both (the chords are checked at their quarters, `certify_chords`), and this room keeps
/// it within the travel.
pub const REACH_MARGIN_RAD: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// What [`adjust`] changed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adjustment {
    /// The clash that was found first.
    pub clash: Clash,
    /// Inclination added (rad).
    pub raised_rad: f64,
    /// Azimuth turned (rad).
    pub turned_rad: f64,
}

/// Checks and, where needed, adjusts the pose (module docs). `Ok((pose, None))`: clear as
/// given; `Ok((pose, Some(adj)))`: clear after the adjustment; `Err(clash)`: refused.
///
/// `reach`: the machine whose rotary travel every pose kept must lie within (module docs),
/// or `None` for no machine.
///
/// # Errors
/// The first clash when no adjusted pose passes ([`ClashPart::Travel`] when the pose as
/// given was clear of the part but out of `reach`'s travel).
#[allow(clippy::too_many_arguments)]
pub fn adjust(
    cutter: &Cutter,
    surface: &Surface,
    part: &PartSamples,
    frame: &ContactFrame,
    pose: Pose,
    opts: &OrientOptions,
    tol_mm: f64,
    reach: Option<&Machine>,
) -> Result<(Pose, Option<Adjustment>), Clash> {
    let tol = CHECK_SHARE * tol_mm;
    let reachable = |p: &Pose| reach.is_none_or(|m| m.reaches_axis(p.axis(frame), REACH_MARGIN_RAD));
    // Where the last pose tried clashed at the bottom: the next one is tried there first
    // (a raise of 0.25° rarely clears the deepest point), which answers a failing trial with
    // one evaluation; a passing one is certified in full as before.
    let mut hint = Hint::default();
    let exhausted_before = part.exhausted.get();
    let first = match check_hinted(cutter, surface, part, place(cutter, frame, &pose), tol, &mut hint, Find::Deepest) {
        Some(clash) => clash,
        None if reachable(&pose) => return Ok((pose, None)),
        None => Clash { part: ClashPart::Travel, depth_mm: 0.0, at: frame.point },
    };
    // A check that ran out of cells certifies nothing either way, and the next pose (a
    // quarter degree on) would run out the same: the point is refused at once instead of
    // after up to 2 500 such checks.
    let exhausted = part.exhausted.get();
    if exhausted > exhausted_before {
        return Err(first);
    }
    // Up to 2 527 poses are tried, each check up to MAX_CELLS: the point is refused once its
    // trials have cost MAX_ADJUST_CELLS (a fold of the surface under the cutter made every
    // trial search deep before it clashed: 11 million cells a point).
    let cells_before = part.cells_checked();
    // Out of the machine's reach: first the pose whose axis is the nearest the machine
    // reaches (the least turn of the axis, so neighbouring points get neighbouring poses),
    // within the strategy's largest inclination, and the search below starts from it.
    let start = match reach {
        Some(m) if !reachable(&pose) => m
            .nearest_reachable_axis(pose.axis(frame), 2.0 * REACH_MARGIN_RAD)
            .map(|axis| Pose::from_axis(frame, axis))
            .filter(|p| p.inclination_rad <= opts.max_inclination_rad)
            .unwrap_or(pose),
        _ => pose,
    };
    let mut ok = |p: &Pose| {
        part.cells_checked() - cells_before <= MAX_ADJUST_CELLS
            && gouge_margin(cutter, frame, p) >= opts.margin_per_mm
            && reachable(p)
            && check_hinted(cutter, surface, part, place(cutter, frame, p), tol, &mut hint, Find::Any).is_none()
    };
    // The inclinations tried at each azimuth: the start's, then a quarter degree more each
    // time up to the largest.
    let deg = 0.25f64.to_radians();
    let top = opts.max_inclination_rad.max(start.inclination_rad);
    let mut raises = [0.0; RAISES];
    let mut n = 0;
    let mut inclination = start.inclination_rad;
    while n < RAISES {
        raises[n] = inclination;
        n += 1;
        if inclination >= top {
            break;
        }
        inclination = (inclination + deg).min(top);
    }
    // Every azimuth's raises as `Raises::first_strided` tries them first, then, when none
    // passed, those it left out.
    const TURNS_DEG: [f64; 7] = [0.0, 10.0, -10.0, 20.0, -20.0, 30.0, -30.0];
    let mut tried = [Raises::new(n); TURNS_DEG.len()];
    for between in [false, true] {
        for (turn, tried) in TURNS_DEG.into_iter().zip(&mut tried) {
            let at =
                |i: usize| Pose { azimuth_rad: start.azimuth_rad + f64::to_radians(turn), inclination_rad: raises[i] };
            // The pose as given failed the check above (the same computation again). A
            // check is cheap when it searched nothing: it failed where the last one clashed.
            let mut passes = |i: usize| {
                let (p, cells) = (at(i), part.cells_checked());
                (p != pose && ok(&p), part.cells_checked() == cells)
            };
            let found = if between { tried.first_left(&mut passes) } else { tried.first_strided(&mut passes) };
            if let Some(i) = found {
                let p = at(i);
                return Ok((
                    p,
                    Some(Adjustment {
                        clash: first,
                        raised_rad: p.inclination_rad - pose.inclination_rad,
                        turned_rad: p.azimuth_rad - pose.azimuth_rad,
                    }),
                ));
            }
        }
    }
    Err(first)
}

/// Most inclinations [`adjust`] tries at one azimuth: a quarter degree apart from the
/// start's, 90° in all.
const RAISES: usize = 361;

/// Raises [`adjust`] strides over at a time once the checks get costly: 2°.
pub const RAISE_STRIDE: usize = 8;

/// The raises `0..n` of one azimuth in [`adjust`] (index i: a raise of i quarter degrees),
/// and which of them have been tried.
#[derive(Clone, Copy, Debug)]
struct Raises {
    n: usize,
    tried: [u64; RAISES.div_ceil(64)],
}

impl Raises {
    fn new(n: usize) -> Self {
        Self { n: n.min(RAISES), tried: [0; RAISES.div_ceil(64)] }
    }

    /// `passes(i)`: whether raise i passes, and whether its check was cheap (it failed at
    /// once where the last one clashed, searching nothing).
    fn try_one(&mut self, i: usize, passes: &mut impl FnMut(usize) -> (bool, bool)) -> (bool, bool) {
        self.tried[i / 64] |= 1 << (i % 64);
        passes(i)
    }

    /// The first raise that passes, as a scan one by one finds it where the raises that
    /// pass follow those that fail (a gouge at the bottom or the rear clears as the axis
    /// tilts further), with fewer checks where they are costly. One by one up to
    /// [`RAISE_STRIDE`], and on while each failing check is cheap (the examples' raises, the
    /// same checks as a scan); from the first costly failure after that, every
    /// [`RAISE_STRIDE`]-th raise and the last up to the first that passes, then halving the
    /// stride between it and the last that failed. `None` when none of those passes
    /// ([`Self::first_left`] tries the others).
    fn first_strided(&mut self, passes: &mut impl FnMut(usize) -> (bool, bool)) -> Option<usize> {
        let last = self.n.checked_sub(1)?;
        let mut i = 0;
        let mut lo = loop {
            let (pass, cheap) = self.try_one(i, passes);
            if pass {
                return Some(i);
            }
            if i == last {
                return None;
            }
            if i >= RAISE_STRIDE && !cheap {
                break i;
            }
            i += 1;
        };
        let mut hi = loop {
            if lo == last {
                return None;
            }
            let i = (lo + RAISE_STRIDE).min(last);
            if self.try_one(i, passes).0 {
                break i;
            }
            lo = i;
        };
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if self.try_one(mid, passes).0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    }

    /// The first raise not yet tried that passes, trying them in order: one between two
    /// that fail (the holder meeting the part as the axis tilts further) that
    /// [`Self::first_strided`] strode over. With it a point is refused only where a scan
    /// one by one refuses it.
    fn first_left(&mut self, passes: &mut impl FnMut(usize) -> (bool, bool)) -> Option<usize> {
        let tried = self.tried;
        (0..self.n).filter(|&i| tried[i / 64] & (1 << (i % 64)) == 0).find(|&i| self.try_one(i, passes).0)
    }
}

#[cfg(test)]
mod tests {
    use super::{RAISE_STRIDE, Raises};

    /// The strided search and the raises it leaves: where the raises that pass follow
    /// those that fail, the first that passes, one by one while the failures are cheap and
    /// with at most a stride's raises one by one, one a stride after and a halving of the
    /// stride once they are not; where passing and failing raises are mixed, a raise that
    /// passes whenever one does.
    #[test]
    fn the_strided_search_finds_the_first_raise_that_passes() {
        let halvings = RAISE_STRIDE.ilog2() as usize;
        for n in 0..=361 {
            for k in 0..=n {
                for cheap in [true, false] {
                    let mut calls = 0;
                    let mut passes = |i: usize| {
                        calls += 1;
                        (i >= k, cheap)
                    };
                    let mut raises = Raises::new(n);
                    let found = raises.first_strided(&mut passes);
                    if k == n {
                        assert_eq!(found, None, "n {n}");
                        assert_eq!(raises.first_left(&mut passes), None, "n {n}");
                        continue;
                    }
                    assert_eq!(found, Some(k), "n {n} k {k}");
                    let most = if cheap {
                        k + 1
                    } else {
                        RAISE_STRIDE + 1 + k.saturating_sub(RAISE_STRIDE).div_ceil(RAISE_STRIDE) + halvings
                    };
                    assert!(calls <= most, "n {n} k {k}: {calls} checks, more than {most}");
                }
            }
        }
        // Mixed: passing raises among the first 40 as a seed draws them, and cheap failures.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..20_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            // One set in eight passes nowhere.
            let (n, set, none) = (1 + (seed % 40) as usize, seed >> 8, seed >> 61 == 0);
            let pass = |i: usize| !none && (set >> i) & 1 == 1;
            let mut passes = |i: usize| (pass(i), (seed >> (i % 64)) & 2 == 0);
            let mut raises = Raises::new(n);
            let found = raises.first_strided(&mut passes).or_else(|| raises.first_left(&mut passes));
            assert_eq!(found.is_some(), (0..n).any(pass), "n {n} set {set:x}");
            assert!(found.is_none_or(|i| i < n && pass(i)), "n {n} set {set:x}: {found:?}");
        }
    }
}
