//! Named numerical tolerances, one per kind of quantity.
//!
//! Lengths are in millimetres, angles in radians, parameters in the surface's internal
//! parameter units (radians for angular parameters, mm for plane parameters, knot units for
//! NURBS). Nothing else in the core hard-codes a small number: a solver that needs one takes
//! it from here (or from its options struct, whose defaults come from here).

/// Convergence of Newton solves on positions: a crease point or foot point is accepted when
/// its residual is below this length (mm). One picometre is ~1e-14 relative to a 100 mm part,
/// about a hundred times the f64 rounding floor, so Newton reaches it in a few iterations.
pub const NEWTON_LENGTH_MM: f64 = 1e-9;

/// Target of the Newton residual once converged; iterations continue (cheaply) until the
/// residual stops improving or drops below this (mm).
pub const NEWTON_LENGTH_FLOOR_MM: f64 = 1e-12;

/// Smallest usable length of a direction vector given in a scene (axis, normal, ref_dir).
pub const MIN_DIRECTION_LENGTH: f64 = 1e-9;

/// Largest cosine between two vectors that must be perpendicular in a scene
/// (`ref_dir` ⊥ `axis`, `u_axis` ⊥ `normal`). A looser value would silently bend the user's
/// frame; a tighter one would reject values typed with six decimals.
pub const PERPENDICULAR_COS: f64 = 1e-6;

/// Smallest angle between the two surface normals at which the crease is still considered
/// well defined (rad, 0.5°). Below it the surfaces touch tangentially: the crease direction
/// n1 × n2 is lost in rounding and the correction system (4) is singular.
pub const MIN_CREASE_ANGLE_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// |r_u × r_v| below this (mm² per parameter unit²) marks a singular point of a
/// parametrisation (a sphere pole, a collapsed NURBS edge), where no normal is defined.
pub const MIN_AREA_ELEMENT: f64 = 1e-12;

/// How far (relative to the domain width) a parameter may lie outside its range before a
/// contact point is said to have left the domain. Absorbs rounding at an exact edge.
pub const DOMAIN_SLACK: f64 = 1e-12;

/// A path's last period shorter than this (mm) is not emitted as a row of its own: the
/// previous row already lies on the end to this accuracy (the Newton residual of the end
/// point itself), and a row a picometre from its neighbour would only add a degenerate
/// segment to every curve built on the rows.
pub const END_MERGE_MM: f64 = 1e-9;

/// A `path.end` closer than this (mm) to the start point on the crease is the start itself:
/// the run goes round the closed crease once rather than stopping at once.
pub const END_AT_START_MM: f64 = 1e-6;

/// Knots closer than this (knot units, relative to the knot range) are treated as equal.
pub const KNOT_EQUAL_REL: f64 = 1e-12;

/// Floor of the measured interpolation error (mm) below which the paper's error bounds are
/// not resolvable: the rounding of a foot-point projection on parts ~100 mm in size.
pub const MEASUREMENT_FLOOR_MM: f64 = 1e-9;

/// A screening foot-point projection for the b·T warning ([`crate::crease::WorstError`])
/// counts as settled when its last Newton step moved the foot point less than this (mm).
/// Newton's step converges quadratically, so the foot point is then within about k·(1e-4)²
/// = 1e-8·k mm of the converged one (k the curvature, 1/mm), and the signed distance, which
/// is stationary at the foot point, within about k·1e-16 mm: far below
/// [`MEASUREMENT_FLOOR_MM`]. (Measured on the examples: at most 1.1e-14 mm from the full
/// projection.)
pub const SCREEN_STEP_MM: f64 = 1e-4;

/// The b·T warning's screen takes a row's distance from the squared distance's second-order
/// model at the row's contact parameters when the model's Newton step moves the point less
/// than this (mm); longer steps are projected. The model neglects a term that grows with the
/// step's cube: measured against the full projection on every example's rows, the distances
/// differ by at most 8.7e-13 mm with steps up to 2e-3 mm (6e-12 mm with steps up to 1e-2 mm),
/// far below [`MEASUREMENT_FLOOR_MM`]. The stepper's contact parameters lie 1e-8 to 9e-3 mm
/// from the foot points on the examples.
pub const SCREEN_MODEL_STEP_MM: f64 = 2e-3;

/// A screened error of at least this fraction of b·T is measured again by the full
/// projection before it can raise or size the warning.
pub const SCREEN_FRACTION: f64 = 0.5;

/// Acceptance window ε of a step search (mm): a node is accepted when its segment's error
/// lies in `[E − ε, E]` for the tolerance E. Seed 002 stops its iterations at |δ − E| < 1e-6;
/// we keep the same width but place it below E so no accepted segment exceeds E.
pub const STEP_WINDOW_MM: f64 = 1e-6;

/// Relative cap of [`STEP_WINDOW_MM`]: for tolerances below 1 µm the window is this fraction
/// of E instead, so it stays meaningful (E = 1e-4 mm → ε = 1e-7 mm).
pub const STEP_WINDOW_REL: f64 = 1e-3;

/// Relative resolution (of the chord's parameter span) to which the peak of a chord's
/// deviation is located. The deviation is quadratic at its peak, so the peak value is found
/// to about the square of this, far below any machining tolerance.
pub const PEAK_PARAM_REL: f64 = 1e-5;

/// Smallest bracket, relative to the parameter scale, a step search may shrink to before it
/// reports that the error jumps across the tolerance (a step that underflows).
pub const STEP_PARAM_REL: f64 = 1e-13;

/// A step search that places a node where δ jumps across E, having advanced less than this
/// fraction of the path's range, has met a discontinuity of the error: shorter steps cannot
/// pass it, so the plan stops there instead of creeping on by rounding steps.
pub const STEP_STALL_REL: f64 = 1e-9;

/// A one-dimensional Newton iteration (on a curve's parameter, on a phase's time) stops when
/// its step is below this times (1 + |x|), x the iterate: a few units in the last place of x,
/// below which the steps are rounding noise.
pub const NEWTON_STEP_REL: f64 = 1e-15;

// --- NURBS paths and G-code (seed 004) ---

/// Default machine resolution of G-code output (mm): the least input increment of IS-B, to
/// which every coordinate, arc-centre offset and knot of a written program is rounded.
pub const GCODE_RESOLUTION_MM: f64 = 0.001;

/// Consecutive points closer than this (mm) count as the same point when fitting a curve
/// through them: the chord-length parameter would not advance.
pub const FIT_DUPLICATE_MM: f64 = 1e-9;

/// Pivot threshold of the banded linear solves of curve fitting, relative to the largest
/// entry of the matrix. A smaller pivot means the knot vector leaves a basis function without
/// data (Schoenberg–Whitney condition broken).
pub const FIT_PIVOT_REL: f64 = 1e-13;

/// Convergence of a point's projection onto a curve (mm): Newton stops when the step moves
/// the foot point by less than this. Far below any output resolution.
pub const CURVE_PROJECT_MM: f64 = 1e-10;

/// Relative accuracy of arc-length tables (of the total length): 3.5 nm on a 350 mm path,
/// far below any output resolution (arc length only assigns fit parameters and first
/// guesses). Much tighter, the table of a crease path — C¹ with a kink in |C'|' at every
/// period — refines into tens of thousands of cells (1e-10: 33 000 cells, 22 ms).
pub const ARC_LENGTH_REL: f64 = 1e-8;

/// Largest difference (mm) between the radii at the start and end of a G02/G03 arc that the
/// G-code reader accepts (and at least [`ARC_RADIUS_MISMATCH_REL`] of the radius). Written
/// arcs stay within about one resolution step; hand-written ones may be coarser.
pub const ARC_RADIUS_MISMATCH_MM: f64 = 0.002;

/// Relative radius mismatch of a G02/G03 arc the reader accepts (see
/// [`ARC_RADIUS_MISMATCH_MM`]).
pub const ARC_RADIUS_MISMATCH_REL: f64 = 1e-3;

/// Arcs flatter than this (sagitta over chord) are written as straight lines: their radius
/// would be too large to round to the resolution meaningfully.
pub const ARC_MIN_BULGE: f64 = 1e-6;

/// Rotary angles this far outside a travel limit (rad, ~2e-7°) still count as within it and
/// are clamped onto it: absorbs the rounding of an angle computed exactly at a limit.
pub const ANGLE_LIMIT_SLACK_RAD: f64 = 1e-9;

/// A tool axis whose sine to the C axis is below this is *on* the C axis (the kinematic
/// singularity): C is then free and keeps its previous value.
pub const SINGULAR_AXIS_SIN: f64 = 1e-12;

/// Checks `|a - b| <= tol` and panics with both values and the difference otherwise.
/// For tests and debug assertions.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "assert_near failed: {} = {a:e}, {} = {b:e}, |diff| = {:e} > tol {tol:e}",
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "assert_near failed ({}): {} = {a:e}, {} = {b:e}, |diff| = {:e} > tol {tol:e}",
            format!($($msg)+),
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
}

// --- Fillet-end finishing (seed 001) ---

/// Smallest inclination α (rad, 3°) of a fillet-end or flat end mill's axis from the
/// surface normal. At α = 0 the flat bottom lies in the tangent plane: the contact point is
/// not unique and the effective cutting curvature across the feed is zero. Below a few
/// degrees the flat bottom, tilted by less than the surface normal turns over a millimetre
/// of path, shapes the scallop more than the corner does and the strip model fails (the
/// brute force measured 1.6·h at 0.5° on the blade, 0.93·h–0.94·h at 3°).
pub const FILLET_MIN_INCLINATION_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// Smallest cross curvature Δκ (1/mm) the `matched` orientation leaves between the swept
/// cutter and the surface across the feed (the cutter's effective curvature across the feed
/// at least the surface's plus this). The scallop at a given side step is ∝ Δκ, so an error
/// δ of the curvature across the feed costs δ/Δκ of the scallop: the gouge adjustment's 0.25°
/// raise adds ≈ 0.001 /mm at α ≈ 6° (R 5, r 1), a 1°–2° turn of the next path on the mould's
/// walls 0.0002–0.0004 /mm. At the mould's unfloored Δκ ≈ 0.0036–0.0045 /mm that was 10–29 %;
/// at 0.01 /mm the brute force still measured 0.942·h (turns of 1°–1.5°), at 0.0125 /mm
/// 0.983·h–1.041·h (both with the sections' poses every 0.1 mm; 0.978·h–1.008·h at 0.025 mm,
/// 0.959·h–1.021·h over 117 dense sections). The floor also keeps the cutter clear enough of the bowl that the gouge
/// checks adjust no node there. It leaves the blade untouched (Δκ ≥ 0.017 /mm) and only the
/// widest strips of the patch (2.53 → 2.46 mm; same passes). docs/fillet.md, "The mould's
/// scallop".
pub const FILLET_MIN_CROSS_CURVATURE_PER_MM: f64 = 0.0125;

/// Corner radius (mm) used for the meridian curvature 1/r of a flat end mill (r = 0): its rim
/// is a sharp edge, whose curvature is taken as 1/(this) instead of infinite.
pub const FILLET_SHARP_EDGE_MM: f64 = 1e-6;

/// Resolution (mm) to which heights of the cutter's profile and scallops are solved: 1 nm,
/// far below any scallop height worth machining (≥ 1 µm).
pub const FILLET_HEIGHT_MM: f64 = 1e-9;

// --- Small numbers that were written inside functions (issue 13), named here ---

/// Resolution of a 1-D Brent search (for a segment's worst point, a curvature peak),
/// relative to the searched parameter range: the value at a smooth peak is then exact to about
/// the square of this.
pub const PARAM_SEARCH_REL: f64 = 1e-9;

/// Relative slack of a comparison between two numbers that should be equal but were formed by
/// different roundings (a resolution against its power of ten, a tolerance against twice the
/// resolution, an arc radius against half its chord, a chord error against its tolerance).
pub const ROUNDING_REL: f64 = 1e-9;

/// Two unit vectors whose angle has a sine below this are parallel: the spherical
/// interpolation between them is the first one (the formula divides by the sine).
pub const PARALLEL_SIN: f64 = 1e-12;

/// Floor of the swept-error maximiser relative to the step tolerance E: an interval whose
/// error leaves the straight line between its ends by less than E/1000 is not split further.
pub const SWEPT_FLOOR_REL_TOL: f64 = 1e-3;

/// Default absolute floor of the sampled maximiser (`numerics::maximise::MaxOptions::floor`,
/// in the function's unit, mm for every error it is used on).
pub const MAX_FLOOR: f64 = 1e-9;

/// Shortest trial length (mm) of an arc fit's piece: the search starts at least this long.
pub const ARC_MIN_TRIAL_MM: f64 = 1e-9;

/// An arc fit that halves its trial piece below this fraction of the path length (at least
/// 1 mm) stops: the path cannot be held by arcs there.
pub const ARC_MIN_PIECE_REL: f64 = 1e-7;

/// A G06.2 block's first control point may differ from the current position by this much
/// (mm, times 25.4 for inch programs): the rounding of a written coordinate, far below the
/// least input increment.
pub const NURBS_START_MATCH_MM: f64 = 1e-6;

/// Finest spacing (mm) of the design samples a replayed program is compared with, and the
/// smallest cell of their search grid.
pub const REPLAY_MIN_SPACING_MM: f64 = 1e-3;

/// Slack (degrees, file units) of a scene's angular range checks (at most 360° wide, sphere
/// latitudes within ±90°): absorbs the rounding of a typed value.
pub const FILE_DEGREE_SLACK_DEG: f64 = 1e-9;

/// An angular domain this close (rad) to one full turn is periodic.
pub const FULL_TURN_SLACK_RAD: f64 = 1e-9;

/// The crease Newton iteration gives up as tangential when the sine of the angle between the
/// normals falls below this fraction of the accepted minimum (far from it, not rounding).
pub const TANGENTIAL_GIVE_UP_REL: f64 = 1e-3;

/// |w1 × w2|² (unit-free: the w are unit surface normals' combinations) below which the
/// interpolator's correction system is singular (the normals are parallel to about 1e-9 rad).
pub const CORRECTION_SINGULAR_SIN2: f64 = 1e-18;

/// Slack (mm) of the cap on one correction step, so a step exactly at the cap passes.
pub const CORRECTION_SLACK_MM: f64 = 1e-9;

/// Default floor of a chord's deviation search, relative to the chord tolerance
/// (`chords::ChordOptions::deviation_floor_rel`).
pub const CHORD_DEVIATION_FLOOR_REL: f64 = 1e-3;

/// Step of central finite differences on a planar test curve, relative to its parameter range.
pub const FD_STEP_REL: f64 = 1e-5;

/// A bisection on a parameter stops when its bracket is narrower than this, relative to the
/// parameter's magnitude (at least 1): a few ulps.
pub const BISECTION_REL: f64 = 1e-15;

/// A curve typed as expressions whose points all lie within this distance (mm) of the first
/// has no extent to follow.
pub const MIN_CURVE_EXTENT_MM: f64 = 1e-9;

/// A 2×2 or 3×3 determinant below this fraction of the product of its rows' sizes marks a
/// singular system (`linalg::solve2`, `solve3`).
pub const SINGULAR_DET_REL: f64 = 1e-14;

/// Pivot threshold of the small dense eliminations (`linalg`), relative to the matrix's scale.
pub const DENSE_PIVOT_REL: f64 = 1e-13;

/// Error shares of a knot refinement are floored at this fraction of the tolerance, so a span
/// that already fits exactly still gets a share.
pub const ERROR_SHARE_FLOOR_REL: f64 = 1e-6;

/// Shortest initial span (mm) of an approximation's knot vector.
pub const MIN_SPAN_MM: f64 = 1e-6;

/// A real-time interpolator's Newton step on the curve parameter has converged when it moves
/// less than this fraction of the parameter range.
pub const PARAM_NEWTON_REL: f64 = 1e-14;

/// Default convergence of a foot-point projection onto a surface (mm): the Newton step moved
/// the foot point by less than this (`geom::ProjectOptions::step_tol_mm`).
pub const FOOT_STEP_MM: f64 = 1e-11;

/// A foot-point Newton step is kept when the squared distance grows by at most this fraction
/// (rounding of an already-converged step) …
pub const DESCENT_SLACK_REL: f64 = 1e-15;

/// … plus this (mm²), for a distance of zero.
pub const DESCENT_SLACK_MM2: f64 = 1e-30;

/// A corner radius within this fraction of the cutter radius makes a ball end mill.
pub const CORNER_IS_RADIUS_REL: f64 = 1e-12;

/// Slack of the barycentric tests of a ray against a surface's triangles (`geom::ray_hit`),
/// so a ray through the shared edge of two triangles is not missed by both.
pub const RAY_TRIANGLE_SLACK: f64 = 1e-9;
