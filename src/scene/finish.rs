//! Finishing scenes (seed 001): one surface, a fillet-end cutter and the path parameters, in
//! the same `interpolab-scene/1` format as crease scenes, told apart by the `finish` key
//! (`docs/scene-format.md`, "Finishing jobs"). Values in file units (mm, degrees, mm/min,
//! 1/mm for the curvature margin).

use super::SceneError;
use super::build::{build_machine, build_surface, validate_machine};
pub use super::finish_spec::{CutterSpec, FinishScene, FinishSpec, StartSpec};
use crate::fillet::paths::{curve_along, start_polyline};
use crate::fillet::{Edge, FeedDirection, FinishJob, FinishOptions, PathStart, Strategy};
use crate::fiveaxis::Machine;
use crate::geom::{Cutter, Surface};
use crate::numerics::format::fmt_num;

fn positive(path: &str, x: f64, what: &str) -> Result<(), SceneError> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(SceneError::new(path, format!("must be > 0, got {x}"), format!("give {what}")))
    }
}

impl FinishScene {
    /// Parses and validates a finishing scene.
    ///
    /// # Errors
    /// The first problem, with its key path and a fix.
    pub fn from_json(text: &str) -> Result<Self, SceneError> {
        let scene = super::parse::parse_finish(text)?;
        scene.job()?;
        Ok(scene)
    }

    /// The scene as `interpolab-scene/1` text: [`FinishScene::from_json`] of it gives this
    /// scene back exactly, every number bit for bit (how a finishing job crosses into a
    /// background worker, `jobs::fillet_row`).
    #[must_use]
    pub fn to_json(&self) -> String {
        super::write::finish_to_json(self)
    }

    /// Converts to core units, checking every value's range.
    ///
    /// # Errors
    /// The first problem, with its key path and a fix.
    pub fn job(&self) -> Result<FinishJob, SceneError> {
        let surface = build_surface(&self.surface, "surfaces[0]")?;
        let f = &self.finish;
        let c = &f.cutter;
        positive("finish.cutter.radius", c.radius, "the cutter radius R in mm")?;
        let big_r = c.radius;
        let dims = [
            ("flute_length", c.flute_length.unwrap_or(3.0 * big_r)),
            ("shank_radius", c.shank_radius.unwrap_or(big_r)),
            ("gauge_length", c.gauge_length.unwrap_or(6.0 * big_r)),
            ("holder_radius", c.holder_radius.unwrap_or(2.5 * big_r)),
            ("holder_length", c.holder_length.unwrap_or(6.0 * big_r)),
        ];
        for (k, v) in dims {
            positive(&format!("finish.cutter.{k}"), v, "a length in mm")?;
        }
        let cutter = Cutter::try_new(big_r, c.corner_radius, dims[0].1, dims[1].1, dims[2].1, dims[3].1, dims[4].1)
            .map_err(|e| SceneError::new("finish.cutter", e.to_string(), "change that dimension"))?;
        let strategy = match f.strategy.as_str() {
            "matched" => Strategy::Matched,
            "principal" => Strategy::PrincipalAxis,
            "ball" => Strategy::Ball,
            "fixed-lead" => {
                let lead = f.lead.unwrap_or(5.0);
                if !(lead.abs() < 80.0) {
                    return Err(SceneError::new(
                        "finish.lead",
                        format!("{lead}° is not a usable lead angle"),
                        "give a lead between -80 and 80 degrees",
                    ));
                }
                Strategy::FixedLead { lead_rad: lead.to_radians() }
            }
            other => {
                return Err(SceneError::new(
                    "finish.strategy",
                    format!("\"{other}\" is not a strategy"),
                    "use \"matched\", \"fixed-lead\", \"principal\" or \"ball\"",
                ));
            }
        };
        positive("finish.scallop", f.scallop, "the scallop height h in mm, e.g. 0.01")?;
        positive("finish.tolerance", f.tolerance, "the chord tolerance E in mm, e.g. 0.01")?;
        if f.scallop >= big_r {
            return Err(SceneError::new(
                "finish.scallop",
                format!("{} mm is not below the cutter radius {big_r} mm", f.scallop),
                "give a scallop height well below R, e.g. 0.01",
            ));
        }
        let mut options = FinishOptions::new(f.scallop, f.tolerance);
        if let Some(s) = f.max_step {
            positive("finish.max_step", s, "the longest forward step in mm")?;
            options.max_step_mm = s;
        }
        options.direction = match f.direction.as_str() {
            "u" => FeedDirection::U,
            "v" => FeedDirection::V,
            "auto" => FeedDirection::Auto,
            other => {
                return Err(SceneError::new(
                    "finish.direction",
                    format!("\"{other}\" is not a direction"),
                    "use \"u\", \"v\" or \"auto\"",
                ));
            }
        };
        if let Some(m) = f.margin {
            if !(m >= 0.0 && m.is_finite()) {
                return Err(SceneError::new(
                    "finish.margin",
                    format!("must be ≥ 0, got {m}"),
                    "give the curvature margin in 1/mm, e.g. 0.002",
                ));
            }
            options.orient.margin_per_mm = m;
        }
        if let Some(k) = f.min_cross_curvature {
            if !(k >= 0.0 && k.is_finite()) {
                return Err(SceneError::new(
                    "finish.min_cross_curvature",
                    format!("must be ≥ 0, got {k}"),
                    "give the smallest cross curvature in 1/mm, e.g. 0.0125 (0 turns the floor off)",
                ));
            }
            options.orient.min_cross_curvature_per_mm = k;
        }
        if let Some(a) = f.max_inclination {
            if !(a > 0.0 && a <= 80.0) {
                return Err(SceneError::new(
                    "finish.max_inclination",
                    format!("{a}° is outside (0°, 80°]"),
                    "give the largest inclination in degrees, e.g. 45",
                ));
            }
            options.orient.max_inclination_rad = a.to_radians();
        }
        if let Some(t) = f.max_tilt {
            if !(0.0..=MAX_TILT_DEG).contains(&t) {
                return Err(SceneError::new(
                    "finish.max_tilt",
                    format!("{t}° is outside [0°, {MAX_TILT_DEG}°]"),
                    "give the largest tilt in degrees, e.g. 10 (0: lead only)",
                ));
            }
            options.orient.max_azimuth_rad = t.to_radians();
        }
        if let Some(v) = f.feed {
            positive("finish.feed", v, "the feed in mm/min")?;
            options.feed_mm_per_min = v;
        }
        check_work(&surface, &cutter, &options)?;
        let start = start_of(f.start.as_ref(), &surface, options.direction)?;
        let machine = match &self.machine {
            Some(m) => {
                validate_machine(m)?;
                build_machine(m)
            }
            None => Machine::default(),
        };
        Ok(FinishJob { name: self.name.clone(), surface, cutter, strategy, options, machine, start })
    }
}

/// Cells a side of the area estimate of [`check_work`] (midpoint rule).
const AREA_GRID: usize = 24;

/// Largest `finish.max_tilt` a scene may give (degrees): the matched cutter's meridian
/// turned off the feed by more than this meets the surface with the corner's far side.
pub const MAX_TILT_DEG: f64 = 45.0;

/// A part whose extent is below this (mm) is not held against its cutter's radius
/// (`check_work`): a small or nearly flat patch may be finished with a cutter larger
/// than itself.
pub const MIN_EXTENT_FOR_RADIUS_MM: f64 = 50.0;

/// Refuses, before any path is built, a cutter larger than the whole part (its radius over
/// the part's extent, corner to corner, or [`MIN_EXTENT_FOR_RADIUS_MM`]), or a surface whose CC points could not stay under the cap
/// ([`FinishOptions::max_nodes`]): every path has a CC point at least every max step, and no
/// strip is wider than the cutter's diameter seen at the steepest inclination allowed,
/// 2R / cos(max inclination), so the paths need at least area / (2R / cos · max step) CC
/// points; the area is estimated on a 24 × 24 grid and halved, so the refusal errs on the
/// side of trying. (A surface of a kilometre — one control point mistyped — otherwise ran
/// for minutes until the cap stopped it.)
fn check_work(surface: &Surface, cutter: &Cutter, options: &FinishOptions) -> Result<(), SceneError> {
    use crate::geom::ParametricSurface;
    let dom = surface.domain();
    let n = AREA_GRID as f64;
    let (du, dv) = (dom.u.width() / n, dom.v.width() / n);
    let mut area_mm2 = 0.0;
    let (mut lo, mut hi) = (glam::DVec3::splat(f64::INFINITY), glam::DVec3::splat(f64::NEG_INFINITY));
    for i in 0..AREA_GRID {
        for j in 0..AREA_GRID {
            let uv = glam::DVec2::new(dom.u.min + (i as f64 + 0.5) * du, dom.v.min + (j as f64 + 0.5) * dv);
            let (p, ru, rv) = surface.tangents_fast_at(uv);
            area_mm2 += ru.cross(rv).length() * du * dv;
            (lo, hi) = (lo.min(p), hi.max(p));
        }
    }
    // A cutter wider than the whole part: every gouge check covers all of it and the job's
    // cost grows with R (a fuzz case's R = 10⁸ mm on the 100 × 80 mm patch ran past 30 s,
    // R = 1 000 mm was refused by its checks after 9 s), and no such cutter finishes a
    // curved part. The grid's box is within a cell of the surface's.
    let extent_mm = (hi - lo).length();
    if extent_mm.is_finite() && cutter.radius_mm > extent_mm.max(MIN_EXTENT_FOR_RADIUS_MM) {
        return Err(SceneError::new(
            "finish.cutter.radius",
            format!(
                "{} mm is larger than the whole part (about {} mm corner to corner)",
                fmt_num(cutter.radius_mm),
                fmt_num((extent_mm * 10.0).round() / 10.0)
            ),
            "give the radius of a cutter that fits the part (a mistyped value?)",
        ));
    }
    let widest_mm = 2.0 * cutter.radius_mm / options.orient.max_inclination_rad.cos();
    let least = 0.5 * area_mm2 / (widest_mm * options.max_step_mm);
    if least <= options.max_nodes as f64 {
        return Ok(());
    }
    let what = if area_mm2.is_finite() {
        format!(
            "the surface's area of about {:.3e} mm² needs at least {:.3e} CC points with a {} mm cutter and a max step of {} mm, more than the {} allowed",
            area_mm2, least, cutter.radius_mm, options.max_step_mm, options.max_nodes
        )
    } else {
        "the surface's area is not finite (a control point or dimension too large)".to_owned()
    };
    Err(SceneError::new(
        "surfaces[0]",
        what,
        "check the surface's size (a mistyped control point?), or raise finish.max_step or the cutter radius",
    ))
}

/// `finish.start` checked and in core units: an edge that agrees with `finish.direction`, or
/// a curve of at least 2 points inside the domain that differ in the parameter the paths run
/// along.
fn start_of(spec: Option<&StartSpec>, surface: &Surface, direction: FeedDirection) -> Result<PathStart, SceneError> {
    use crate::geom::ParametricSurface;
    match spec {
        None => Ok(PathStart::FirstBoundary),
        Some(StartSpec::Boundary(name)) => {
            let Some(edge) = Edge::from_name(name) else {
                return Err(SceneError::new(
                    "finish.start",
                    format!("\"{name}\" is not an edge"),
                    "use \"u0\", \"u1\", \"v0\" or \"v1\" (the edge u = u_min, u_max, v = v_min, v_max), or { \"curve\": [[u, v], …] }",
                ));
            };
            let along = edge.along();
            let clash = match direction {
                FeedDirection::U => along != 0,
                FeedDirection::V => along != 1,
                FeedDirection::Auto => false,
            };
            if clash {
                // The edges whose paths run along the asked direction are those of the other
                // parameter.
                let (runs, other) = if along == 0 { ('u', 'v') } else { ('v', 'u') };
                return Err(SceneError::new(
                    "finish.start",
                    format!(
                        "the edge {name} is a path along {runs}, but finish.direction asks for paths along {other}"
                    ),
                    format!("start on the edge {runs}0 or {runs}1, or set finish.direction to \"{runs}\" or \"auto\""),
                ));
            }
            Ok(PathStart::Boundary(edge))
        }
        Some(StartSpec::Curve(file_pts)) => {
            let dom = surface.domain();
            let pts: Vec<glam::DVec2> =
                file_pts.iter().map(|p| super::build::params_from_file(surface, glam::DVec2::from(*p))).collect();
            for (i, p) in pts.iter().enumerate() {
                if !dom.contains(*p) {
                    let f = |r: crate::geom::ParamRange| {
                        format!("[{}, {}]{}", r.unit.to_file(r.min), r.unit.to_file(r.max), r.unit.suffix())
                    };
                    return Err(SceneError::new(
                        format!("finish.start.curve[{i}]"),
                        format!(
                            "({}, {}) is outside the surface's domain u in {}, v in {}",
                            file_pts[i][0],
                            file_pts[i][1],
                            f(dom.u),
                            f(dom.v)
                        ),
                        "give the point's parameters inside the domain (degrees for angles)",
                    ));
                }
            }
            let along = curve_along(surface, &pts, direction);
            start_polyline(surface, &pts, along).map_err(|e| {
                let reason = match &e {
                    crate::fillet::FinishError::BadStart { reason } => reason.clone(),
                    other => other.to_string(),
                };
                SceneError::new(
                    "finish.start.curve",
                    reason,
                    "give 2 or more [u, v] points inside the surface's domain",
                )
            })?;
            Ok(PathStart::Curve(pts))
        }
    }
}

/// The finishing examples shipped in `examples/` (compiled in).
pub const FINISH_PRESETS: &[super::Preset] = &[
    super::Preset { id: "finish-bicubic-patch", json: include_str!("../../examples/finish/bicubic-patch.json") },
    super::Preset { id: "finish-concave-mould", json: include_str!("../../examples/finish/concave-mould.json") },
    super::Preset { id: "finish-naca-blade", json: include_str!("../../examples/finish/naca-blade.json") },
];
