//! Range and consistency checks of a [`Scene`], and conversion of its surfaces to the
//! internal [`Surface`] types (radians, unit frames).

use glam::{DVec2, DVec3};

use super::{DomainSpec, MachineSpec, Scene, SceneError, SurfaceSpec, ToolAxisSpec};
use crate::fiveaxis::{Machine, ToolAxisRule};
use crate::geom::{
    Cylinder, Domain, Frame, NurbsSurface, ParamRange, ParamUnit, Plane, Sphere, Surface, Torus, nurbs::NurbsError,
};
use crate::numerics::format::fmt_num;
use crate::numerics::limits::MAX_COORDINATE_MM;
use crate::numerics::tolerance;

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

fn positive(path: &str, x: f64, what: &str) -> Result<(), SceneError> {
    if x > 0.0 { Ok(()) } else { Err(SceneError::new(path, format!("must be > 0, got {x}"), format!("give {what}"))) }
}

fn direction(path: &str, a: [f64; 3]) -> Result<DVec3, SceneError> {
    let d = v3(a);
    if d.length() < tolerance::MIN_DIRECTION_LENGTH {
        return Err(SceneError::new(
            path,
            format!("the direction {a:?} has (almost) zero length"),
            "give a non-zero direction vector (it need not be unit length)",
        ));
    }
    Ok(d.normalize())
}

fn perpendicular(path: &str, d: DVec3, to: DVec3, to_name: &str) -> Result<(), SceneError> {
    let c = d.dot(to);
    if c.abs() > tolerance::PERPENDICULAR_COS {
        return Err(SceneError::new(
            path,
            format!(
                "must be perpendicular to {to_name}, but makes {:.4}° with it",
                c.clamp(-1.0, 1.0).acos().to_degrees()
            ),
            format!("give a direction at 90° to {to_name}"),
        ));
    }
    Ok(())
}

fn range(path: &str, r: [f64; 2], unit: &str, max_width: Option<f64>) -> Result<(), SceneError> {
    // Also refuses NaN ends.
    if r[1].partial_cmp(&r[0]) != Some(std::cmp::Ordering::Greater) {
        return Err(SceneError::new(
            path,
            format!("the range [{}, {}] is empty or reversed", r[0], r[1]),
            format!("give [from, to] in {unit} with from < to"),
        ));
    }
    if let Some(w) = max_width
        && r[1] - r[0] > w + crate::numerics::tolerance::FILE_DEGREE_SLACK_DEG
    {
        return Err(SceneError::new(
            path,
            format!("the range [{}, {}] spans {}°, more than one turn", r[0], r[1], r[1] - r[0]),
            "give at most 360° (exactly 360° makes the parameter wrap around)",
        ));
    }
    Ok(())
}

fn angle_domain(path: &str, d: &DomainSpec) -> Result<(), SceneError> {
    range(&format!("{path}.u"), d.u, "degrees", Some(360.0))?;
    range(&format!("{path}.v"), d.v, "degrees", Some(360.0))
}

/// Checks every value of the scene; the first problem is returned with its key path.
pub(super) fn validate(s: &Scene) -> Result<(), SceneError> {
    for (i, spec) in s.surfaces.iter().enumerate() {
        build_surface(spec, &format!("surfaces[{i}]"))?;
    }
    positive("tool.radius", s.tool.radius, "the ball radius in mm")?;
    let r_eff = s.tool.radius + s.tool.allowance;
    if r_eff.is_nan() || r_eff <= 0.0 {
        return Err(SceneError::new(
            "tool.allowance",
            format!("R' = radius + allowance = {} mm is not positive", s.tool.radius + s.tool.allowance),
            "use an allowance greater than minus the radius",
        ));
    }
    positive("motion.feed", s.motion.feed, "the feed in mm/min")?;
    positive("motion.period", s.motion.period, "the interpolation period in ms")?;
    let f = s.feed_per_period_mm();
    if !(f >= crate::numerics::tolerance::NEWTON_LENGTH_MM) {
        return Err(SceneError::new(
            "motion",
            format!(
                "the feed per period F·Ts = {f:.3e} mm is below {:e} mm, the accuracy of a crease point: the cutter centre could not advance",
                crate::numerics::tolerance::NEWTON_LENGTH_MM
            ),
            "raise motion.feed (mm/min) or motion.period (ms)",
        ));
    }
    positive("tolerance.t1", s.tolerance.t1, "the tolerance on surface 1 in mm")?;
    positive("tolerance.t2", s.tolerance.t2, "the tolerance on surface 2 in mm")?;
    if !(s.tolerance.share > 0.0 && s.tolerance.share <= 1.0) {
        return Err(SceneError::new(
            "tolerance.share",
            format!("must lie in (0, 1], got {}", s.tolerance.share),
            "give the interpolation's share of the tolerance, e.g. 0.5",
        ));
    }
    for (key, v) in [("path.start", Some(s.path.start)), ("path.end", s.path.end), ("path.direction", s.path.direction)]
    {
        if let Some(v) = v
            && v.iter().any(|x| !x.is_finite())
        {
            return Err(SceneError::new(key, "holds a non-finite number", "give finite coordinates in mm"));
        }
        if let Some(v) = v
            && key != "path.direction"
            && v.iter().any(|x| x.abs() > crate::numerics::limits::MAX_COORDINATE_MM)
        {
            return Err(SceneError::new(
                key,
                format!("lies beyond ±{:e} mm (1 km) of the origin", crate::numerics::limits::MAX_COORDINATE_MM),
                "give the point in mm near the surfaces",
            ));
        }
    }
    if s.path.max_steps == 0 {
        return Err(SceneError::new(
            "path.max_steps",
            "must be at least 1",
            "give the largest number of periods to run",
        ));
    }
    if let Some(d) = s.path.direction {
        direction("path.direction", d)?;
    }
    if let Some(m) = &s.machine {
        validate_machine(m)?;
    }
    if let Some(t) = &s.tool_axis {
        build_tool_axis_checked(t)?;
    }
    Ok(())
}

/// Range checks of `machine`.
pub(super) fn validate_machine(m: &MachineSpec) -> Result<(), SceneError> {
    let names = m.kind.axis_names().map(str::to_ascii_lowercase);
    for (i, has) in m.kind.has_pivot().into_iter().enumerate() {
        if has && m.pivots[i].iter().any(|x| !x.is_finite()) {
            return Err(SceneError::new(
                format!("machine.pivots.{}", names[i]),
                "holds a non-finite number",
                "give finite coordinates in mm",
            ));
        }
        // A pivot a kilometre off turns every step's error into overflow (a pivot at −1e308
        // made the steps search for seconds before refusing).
        if has && m.pivots[i].iter().any(|x| x.abs() > MAX_COORDINATE_MM) {
            return Err(SceneError::new(
                format!("machine.pivots.{}", names[i]),
                format!("lies more than {} mm from the origin", fmt_num(MAX_COORDINATE_MM)),
                "give a point on the axis in mm, within the machine",
            ));
        }
    }
    if m.tool_length.is_finite() && m.tool_length > MAX_COORDINATE_MM {
        return Err(SceneError::new(
            "machine.tool_length",
            format!("is more than {} mm", fmt_num(MAX_COORDINATE_MM)),
            "give the distance from the last head axis to the tool tip in mm, e.g. 150",
        ));
    }
    if !(m.tool_length.is_finite() && m.tool_length >= 0.0) {
        return Err(SceneError::new(
            "machine.tool_length",
            format!("must be a length ≥ 0 in mm, got {}", m.tool_length),
            "give the distance from the last head axis to the tool tip in mm",
        ));
    }
    // Finite and ≥ 0 by now.
    if m.kind.uses_tool_length() && m.tool_length <= 0.0 {
        return Err(SceneError::new(
            "machine.tool_length",
            format!(
                "a {} machine swings the tool about its head axes, so it needs the tool length; got {}",
                m.kind.as_str(),
                m.tool_length
            ),
            "give the distance from the last head axis to the tool tip in mm, e.g. 150",
        ));
    }
    for (i, lim) in m.limits.iter().enumerate() {
        if let Some([lo, hi]) = *lim
            && !(lo.is_finite() && hi.is_finite() && lo < hi)
        {
            return Err(SceneError::new(
                format!("machine.limits.{}", names[i]),
                format!("the travel [{lo}, {hi}] is empty, reversed or not finite"),
                "give [min, max] in degrees with min < max, or null for unlimited travel",
            ));
        }
    }
    Ok(())
}

/// Validates `tool_axis` and converts it (degrees → radians, unit vector).
fn build_tool_axis_checked(t: &ToolAxisSpec) -> Result<ToolAxisRule, SceneError> {
    match *t {
        ToolAxisSpec::Bisector => Ok(ToolAxisRule::Bisector),
        ToolAxisSpec::Normal1 { lead, tilt } => {
            for (key, a) in [("lead", lead), ("tilt", tilt)] {
                if !(a.is_finite() && a.abs() < 90.0) {
                    return Err(SceneError::new(
                        format!("tool_axis.{key}"),
                        format!("{a}° would lay the tool axis into or past the surface's tangent plane"),
                        "give an angle between -90 and 90 degrees",
                    ));
                }
            }
            Ok(ToolAxisRule::Normal1 { lead_rad: lead.to_radians(), tilt_rad: tilt.to_radians() })
        }
        ToolAxisSpec::Fixed { vector } => {
            if vector.iter().any(|x| !x.is_finite()) {
                return Err(SceneError::new(
                    "tool_axis.vector",
                    "holds a non-finite number",
                    "give a finite direction [i, j, k]",
                ));
            }
            Ok(ToolAxisRule::Fixed { axis: direction("tool_axis.vector", vector)? })
        }
    }
}

/// The machine of a `machine` entry in internal units (radians). Call after validation.
#[must_use]
pub fn build_machine(m: &MachineSpec) -> Machine {
    Machine {
        kind: m.kind,
        pivots_mm: m.pivots.map(v3),
        tool_length_mm: m.tool_length,
        limits_rad: m.limits.map(|l| l.map(|[lo, hi]| [lo.to_radians(), hi.to_radians()])),
    }
}

/// The `machine` entry describing a machine (the inverse of [`build_machine`]; angles rounded
/// to 1e-9° so limits typed in whole degrees come back whole).
#[must_use]
pub fn machine_spec(m: &Machine) -> MachineSpec {
    let deg = |r: f64| (r.to_degrees() * 1e9).round() / 1e9;
    MachineSpec {
        kind: m.kind,
        pivots: m.pivots_mm.map(|p| p.to_array()),
        tool_length: m.tool_length_mm,
        limits: m.limits_rad.map(|l| l.map(|[lo, hi]| [deg(lo), deg(hi)])),
    }
}

/// The tool-axis rule of a `tool_axis` entry in internal units.
///
/// # Errors
/// An angle outside (−90°, 90°) or a zero vector, with its key path.
pub fn build_tool_axis(t: &ToolAxisSpec) -> Result<ToolAxisRule, SceneError> {
    build_tool_axis_checked(t)
}

fn map_nurbs(path: &str, e: NurbsError) -> SceneError {
    let (key, fix) = match &e {
        NurbsError::Degree(_) => ("degree", "use degrees between 1 and 9"),
        NurbsError::TooFewPoints { .. } => ("points", "add control points or lower the degree"),
        NurbsError::KnotCount { .. }
        | NurbsError::Decreasing { .. }
        | NurbsError::NotClamped { .. }
        | NurbsError::EndRepeated { .. }
        | NurbsError::Multiplicity { .. }
        | NurbsError::EmptyRange => {
            ("knots", "give a clamped, non-decreasing knot vector with (points + degree + 1) values")
        }
        NurbsError::Weight { .. } => ("weights", "make every weight a positive number"),
        NurbsError::WeightShape => ("weights", "give one weight per control point, in the same nested shape"),
        NurbsError::Ragged { .. } => ("points", "give every row of the control net the same number of points"),
    };
    SceneError::new(format!("{path}.{key}"), e.to_string(), fix)
}

/// Validates one surface and converts it to internal units. `path` names it in errors
/// (`surfaces[0]`).
///
/// # Errors
/// The first problem, with its key path.
pub fn build_surface(spec: &SurfaceSpec, path: &str) -> Result<Surface, SceneError> {
    let p = |k: &str| format!("{path}.{k}");
    let deg = |r: [f64; 2]| ParamRange::new(r[0].to_radians(), r[1].to_radians(), ParamUnit::Angle);
    let finite = |key: &str, vals: &[f64]| -> Result<(), SceneError> {
        if vals.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(SceneError::new(p(key), "holds a non-finite number", "give finite numbers"))
        }
    };
    match spec {
        SurfaceSpec::Plane { origin, normal, u_axis, domain } => {
            finite("origin", origin)?;
            let n = direction(&p("normal"), *normal)?;
            let u = direction(&p("u_axis"), *u_axis)?;
            perpendicular(&p("u_axis"), u, n, "the plane's normal")?;
            range(&p("domain.u"), domain.u, "mm", None)?;
            range(&p("domain.v"), domain.v, "mm", None)?;
            Ok(Surface::Plane(Plane::new(v3(*origin), n, u, domain.u, domain.v)))
        }
        SurfaceSpec::Cylinder { origin, axis, radius, ref_dir, domain, normal } => {
            finite("origin", origin)?;
            let a = direction(&p("axis"), *axis)?;
            positive(&p("radius"), *radius, "the radius in mm")?;
            let r = ref_dir.map(|r| direction(&p("ref_dir"), r)).transpose()?;
            if let Some(r) = r {
                perpendicular(&p("ref_dir"), r, a, "the axis")?;
            }
            range(&p("domain.u"), domain.u, "degrees", Some(360.0))?;
            range(&p("domain.v"), domain.v, "mm", None)?;
            Ok(Surface::Cylinder(Cylinder {
                origin: v3(*origin),
                frame: Frame::from_axis(a, r),
                radius: *radius,
                sign: normal.sign(),
                domain: Domain { u: deg(domain.u), v: ParamRange::new(domain.v[0], domain.v[1], ParamUnit::Length) },
            }))
        }
        SurfaceSpec::Sphere { center, radius, axis, ref_dir, domain, normal } => {
            finite("center", center)?;
            positive(&p("radius"), *radius, "the radius in mm")?;
            let a = axis.map(|a| direction(&p("axis"), a)).transpose()?.unwrap_or(DVec3::Z);
            let r = ref_dir.map(|r| direction(&p("ref_dir"), r)).transpose()?;
            if let Some(r) = r {
                perpendicular(&p("ref_dir"), r, a, "the axis")?;
            }
            let d = domain.unwrap_or(DomainSpec { u: [-180.0, 180.0], v: [-90.0, 90.0] });
            angle_domain(&p("domain"), &d)?;
            if d.v[0] < -90.0 - crate::numerics::tolerance::FILE_DEGREE_SLACK_DEG
                || d.v[1] > 90.0 + crate::numerics::tolerance::FILE_DEGREE_SLACK_DEG
            {
                return Err(SceneError::new(
                    p("domain.v"),
                    format!("latitude range [{}, {}] leaves [-90, 90]", d.v[0], d.v[1]),
                    "give latitudes between -90 and 90 degrees",
                ));
            }
            Ok(Surface::Sphere(Sphere {
                center: v3(*center),
                frame: Frame::from_axis(a, r),
                radius: *radius,
                sign: normal.sign(),
                domain: Domain {
                    u: deg(d.u),
                    v: ParamRange::new(d.v[0].to_radians(), d.v[1].to_radians(), ParamUnit::Angle),
                },
            }))
        }
        SurfaceSpec::Torus { center, axis, major_radius, minor_radius, ref_dir, domain, normal } => {
            finite("center", center)?;
            let a = direction(&p("axis"), *axis)?;
            positive(&p("minor_radius"), *minor_radius, "the tube radius in mm")?;
            positive(&p("major_radius"), *major_radius, "the axis-to-tube distance in mm")?;
            if major_radius <= minor_radius {
                return Err(SceneError::new(
                    p("major_radius"),
                    format!(
                        "{major_radius} mm is not larger than minor_radius {minor_radius} mm (the torus would cross its axis)"
                    ),
                    "make major_radius larger than minor_radius",
                ));
            }
            let r = ref_dir.map(|r| direction(&p("ref_dir"), r)).transpose()?;
            if let Some(r) = r {
                perpendicular(&p("ref_dir"), r, a, "the axis")?;
            }
            let d = domain.unwrap_or(DomainSpec { u: [-180.0, 180.0], v: [-180.0, 180.0] });
            angle_domain(&p("domain"), &d)?;
            Ok(Surface::Torus(Torus {
                center: v3(*center),
                frame: Frame::from_axis(a, r),
                major_radius: *major_radius,
                minor_radius: *minor_radius,
                sign: normal.sign(),
                domain: Domain { u: deg(d.u), v: deg(d.v) },
            }))
        }
        SurfaceSpec::Nurbs { degree, knots_u, knots_v, points, weights, flip_normal } => {
            for (key, k) in [("knots_u", knots_u), ("knots_v", knots_v)] {
                finite(key, k)?;
            }
            for (i, row) in points.iter().enumerate() {
                for (j, pt) in row.iter().enumerate() {
                    finite(&format!("points[{i}][{j}]"), pt)?;
                }
            }
            let pts: Vec<Vec<DVec3>> = points.iter().map(|r| r.iter().map(|&x| v3(x)).collect()).collect();
            // Map knot problems to the vector that has them.
            let n_u = points.len();
            let n_v = points.first().map_or(0, Vec::len);
            if let Some((row, r)) = points.iter().enumerate().find(|(_, r)| r.len() != n_v) {
                return Err(map_nurbs(path, NurbsError::Ragged { row, got: r.len(), expected: n_v }));
            }
            // One knot vector against its count of control points and degree; a problem is
            // reported at that direction's keys.
            let check = |knots: &[f64], n: usize, deg: usize, keys: [&str; 2], along: &str| {
                crate::geom::nurbs::validate_knots(knots, n, deg).map_err(|e| {
                    let mut err = map_nurbs(path, e);
                    if err.path.ends_with(".knots") {
                        err.path = p(keys[0]);
                    } else if err.path.ends_with(".degree") {
                        err.path = p(keys[1]);
                    } else if err.path.ends_with(".points") {
                        err.problem = format!("{along}: {}", err.problem);
                    }
                    err
                })
            };
            check(knots_u, n_u, degree[0], ["knots_u", "degree[0]"], "along u")?;
            check(knots_v, n_v, degree[1], ["knots_v", "degree[1]"], "along v (each row)")?;
            let surface = NurbsSurface::try_new(
                *degree,
                knots_u.clone(),
                knots_v.clone(),
                &pts,
                weights.as_deref(),
                *flip_normal,
            )
            .map_err(|e| map_nurbs(path, e))?;
            Ok(Surface::Nurbs(surface))
        }
    }
}

/// Parameters of a point given in file units on `surface`, converted to internal units.
#[must_use]
pub fn params_from_file(surface: &Surface, uv_file: DVec2) -> DVec2 {
    use crate::geom::ParametricSurface;
    let d = surface.domain();
    DVec2::new(d.u.unit.from_file(uv_file.x), d.v.unit.from_file(uv_file.y))
}
