//! [`Scene`] → JSON, keys in the format's documented order, optional keys written only when
//! set, so that parsing the output gives back the same scene.

use serde_json::{Map, Value, json};

use super::{DomainSpec, FORMAT, MachineSpec, Scene, SurfaceSpec, ToolAxisSpec};

fn domain(d: &DomainSpec) -> Value {
    json!({ "u": d.u, "v": d.v })
}

fn surface(s: &SurfaceSpec) -> Value {
    let mut m = Map::new();
    m.insert("type".into(), s.type_name().into());
    match s {
        SurfaceSpec::Plane { origin, normal, u_axis, domain: d } => {
            m.insert("origin".into(), json!(origin));
            m.insert("normal".into(), json!(normal));
            m.insert("u_axis".into(), json!(u_axis));
            m.insert("domain".into(), domain(d));
        }
        SurfaceSpec::Cylinder { origin, axis, radius, ref_dir, domain: d, normal } => {
            m.insert("origin".into(), json!(origin));
            m.insert("axis".into(), json!(axis));
            m.insert("radius".into(), json!(radius));
            if let Some(r) = ref_dir {
                m.insert("ref_dir".into(), json!(r));
            }
            m.insert("domain".into(), domain(d));
            m.insert("normal".into(), normal.as_str().into());
        }
        SurfaceSpec::Sphere { center, radius, axis, ref_dir, domain: d, normal } => {
            m.insert("center".into(), json!(center));
            m.insert("radius".into(), json!(radius));
            if let Some(a) = axis {
                m.insert("axis".into(), json!(a));
            }
            if let Some(r) = ref_dir {
                m.insert("ref_dir".into(), json!(r));
            }
            if let Some(d) = d {
                m.insert("domain".into(), domain(d));
            }
            m.insert("normal".into(), normal.as_str().into());
        }
        SurfaceSpec::Torus { center, axis, major_radius, minor_radius, ref_dir, domain: d, normal } => {
            m.insert("center".into(), json!(center));
            m.insert("axis".into(), json!(axis));
            m.insert("major_radius".into(), json!(major_radius));
            m.insert("minor_radius".into(), json!(minor_radius));
            if let Some(r) = ref_dir {
                m.insert("ref_dir".into(), json!(r));
            }
            if let Some(d) = d {
                m.insert("domain".into(), domain(d));
            }
            m.insert("normal".into(), normal.as_str().into());
        }
        SurfaceSpec::Nurbs { degree, knots_u, knots_v, points, weights, flip_normal } => {
            m.insert("degree".into(), json!(degree));
            m.insert("knots_u".into(), json!(knots_u));
            m.insert("knots_v".into(), json!(knots_v));
            m.insert("points".into(), json!(points));
            if let Some(w) = weights {
                m.insert("weights".into(), json!(w));
            }
            if *flip_normal {
                m.insert("flip_normal".into(), true.into());
            }
        }
    }
    Value::Object(m)
}

pub(super) fn to_value(s: &Scene) -> Value {
    let mut path = Map::new();
    path.insert("start".into(), json!(s.path.start));
    path.insert("end".into(), s.path.end.map_or(Value::Null, |e| json!(e)));
    path.insert("max_steps".into(), json!(s.path.max_steps));
    if let Some(d) = s.path.direction {
        path.insert("direction".into(), json!(d));
    }
    let mut m = Map::new();
    m.insert("format".into(), FORMAT.into());
    m.insert("name".into(), s.name.clone().into());
    m.insert("surfaces".into(), Value::Array(s.surfaces.iter().map(surface).collect()));
    m.insert("tool".into(), json!({ "radius": s.tool.radius, "allowance": s.tool.allowance }));
    m.insert("motion".into(), json!({ "feed": s.motion.feed, "period": s.motion.period }));
    m.insert("tolerance".into(), json!({ "t1": s.tolerance.t1, "t2": s.tolerance.t2, "share": s.tolerance.share }));
    m.insert("path".into(), Value::Object(path));
    if let Some(d) = &s.dynamics {
        m.insert("dynamics".into(), d.to_value());
    }
    if let Some(machine) = &s.machine {
        m.insert("machine".into(), machine_value(machine));
    }
    if let Some(t) = &s.tool_axis {
        m.insert("tool_axis".into(), tool_axis_value(t));
    }
    Value::Object(m)
}

/// A `machine` entry as the scene format writes it.
#[must_use]
pub fn machine_value(mc: &MachineSpec) -> Value {
    let names = mc.kind.axis_names().map(str::to_ascii_lowercase);
    let mut pivots = Map::new();
    for (i, has) in mc.kind.has_pivot().into_iter().enumerate() {
        if has {
            pivots.insert(names[i].clone(), json!(mc.pivots[i]));
        }
    }
    let mut limits = Map::new();
    for (name, lim) in names.iter().zip(mc.limits) {
        limits.insert(name.clone(), lim.map_or(Value::Null, |l| json!(l)));
    }
    let mut m = Map::new();
    m.insert("kind".into(), mc.kind.as_str().into());
    m.insert("pivots".into(), Value::Object(pivots));
    m.insert("tool_length".into(), json!(mc.tool_length));
    m.insert("limits".into(), Value::Object(limits));
    Value::Object(m)
}

fn tool_axis_value(t: &ToolAxisSpec) -> Value {
    match t {
        ToolAxisSpec::Bisector => json!({ "rule": "bisector" }),
        ToolAxisSpec::Normal1 { lead, tilt } => json!({ "rule": "normal1", "lead": lead, "tilt": tilt }),
        ToolAxisSpec::Fixed { vector } => json!({ "rule": "fixed", "vector": vector }),
    }
}

/// A finishing scene (seed 001) as the format writes it: optional keys only when set, so
/// parsing the output gives back the same scene, every number bit for bit (serde_json writes
/// the shortest text that reads back to the same `f64`, and reads with `float_roundtrip`).
pub(super) fn finish_to_json(s: &super::finish_spec::FinishScene) -> String {
    let f = &s.finish;
    let c = &f.cutter;
    let mut cutter = Map::new();
    cutter.insert("radius".into(), json!(c.radius));
    cutter.insert("corner_radius".into(), json!(c.corner_radius));
    for (k, v) in [
        ("flute_length", c.flute_length),
        ("shank_radius", c.shank_radius),
        ("gauge_length", c.gauge_length),
        ("holder_radius", c.holder_radius),
        ("holder_length", c.holder_length),
    ] {
        if let Some(v) = v {
            cutter.insert(k.into(), json!(v));
        }
    }
    let mut finish = Map::new();
    finish.insert("cutter".into(), Value::Object(cutter));
    finish.insert("strategy".into(), f.strategy.clone().into());
    let opt = |m: &mut Map<String, Value>, k: &str, v: Option<f64>| {
        if let Some(v) = v {
            m.insert(k.into(), json!(v));
        }
    };
    opt(&mut finish, "lead", f.lead);
    finish.insert("scallop".into(), json!(f.scallop));
    finish.insert("tolerance".into(), json!(f.tolerance));
    opt(&mut finish, "max_step", f.max_step);
    finish.insert("direction".into(), f.direction.clone().into());
    opt(&mut finish, "margin", f.margin);
    opt(&mut finish, "min_cross_curvature", f.min_cross_curvature);
    opt(&mut finish, "max_inclination", f.max_inclination);
    opt(&mut finish, "max_tilt", f.max_tilt);
    opt(&mut finish, "feed", f.feed);
    match &f.start {
        None => {}
        Some(super::finish_spec::StartSpec::Boundary(name)) => {
            finish.insert("start".into(), name.clone().into());
        }
        Some(super::finish_spec::StartSpec::Curve(pts)) => {
            finish.insert("start".into(), json!({ "curve": pts }));
        }
    }
    let mut m = Map::new();
    m.insert("format".into(), FORMAT.into());
    m.insert("name".into(), s.name.clone().into());
    m.insert("surfaces".into(), Value::Array(vec![surface(&s.surface)]));
    m.insert("finish".into(), Value::Object(finish));
    if let Some(machine) = &s.machine {
        m.insert("machine".into(), machine_value(machine));
    }
    let mut out = String::new();
    pretty(&Value::Object(m), 0, &mut out);
    out.push('\n');
    out
}

pub(super) fn to_json(s: &Scene) -> String {
    let mut out = String::new();
    pretty(&to_value(s), 0, &mut out);
    out.push('\n');
    out
}

/// Depth of array nesting below `v` (0 for a scalar); `None` if it holds an object.
fn array_depth(v: &Value) -> Option<usize> {
    match v {
        Value::Object(_) => None,
        Value::Array(a) => {
            let mut d = 0;
            for x in a {
                d = d.max(array_depth(x)?);
            }
            Some(d + 1)
        }
        _ => Some(0),
    }
}

/// Pretty printer that keeps short numeric arrays (points, ranges, rows of a control net)
/// on one line, so a scene file stays readable by eye.
fn pretty(v: &Value, indent: usize, out: &mut String) {
    let pad = |n: usize| "  ".repeat(n);
    match v {
        Value::Object(m) if !m.is_empty() => {
            out.push_str("{\n");
            for (i, (k, x)) in m.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                out.push_str(&serde_json::to_string(k).unwrap_or_default());
                out.push_str(": ");
                pretty(x, indent + 1, out);
                if i + 1 < m.len() {
                    out.push(',');
                }
                out.push('\n');
            }
            out.push_str(&pad(indent));
            out.push('}');
        }
        Value::Array(a) if !a.is_empty() && array_depth(v).is_none_or(|d| d > 2) => {
            out.push_str("[\n");
            for (i, x) in a.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                pretty(x, indent + 1, out);
                if i + 1 < a.len() {
                    out.push(',');
                }
                out.push('\n');
            }
            out.push_str(&pad(indent));
            out.push(']');
        }
        Value::Array(a) => {
            out.push('[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                pretty(x, indent, out);
            }
            out.push(']');
        }
        other => out.push_str(&serde_json::to_string(other).unwrap_or_default()),
    }
}

pub(super) fn to_json_compact(s: &Scene) -> String {
    serde_json::to_string(&to_value(s)).unwrap_or_default()
}
