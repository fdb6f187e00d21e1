//! JSON → [`Scene`]: structure and types, with key paths in every error. Ranges and
//! geometric consistency are checked afterwards by `build::validate`.

use serde_json::{Map, Value};

use super::{
    DEFAULT_MAX_STEPS, DEFAULT_TILT_LIMITS_DEG, DomainSpec, FORMAT, MachineSpec, MotionSpec, Orientation, PathSpec,
    Scene, SceneError, SurfaceSpec, ToleranceSpec, ToolAxisSpec, ToolSpec,
};
use crate::fiveaxis::MachineKind;

/// A JSON object being read: remembers which keys were taken so the rest can be reported
/// as unknown.
struct Obj<'a> {
    map: &'a Map<String, Value>,
    path: String,
    allowed: &'static [&'static str],
}

/// A JSON value with its key path.
struct At<'a> {
    v: &'a Value,
    path: String,
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() { key.to_owned() } else { format!("{path}.{key}") }
}

impl<'a> Obj<'a> {
    fn new(at: &At<'a>, allowed: &'static [&'static str]) -> Result<Self, SceneError> {
        match at.v {
            Value::Object(map) => {
                let obj = Self { map, path: at.path.clone(), allowed };
                obj.check_unknown()?;
                Ok(obj)
            }
            other => Err(SceneError::new(
                display_path(&at.path),
                format!("expected an object, got {}", kind(other)),
                "write it as { \"key\": value, … }",
            )),
        }
    }

    fn check_unknown(&self) -> Result<(), SceneError> {
        if let Some(key) = self.map.keys().find(|k| !self.allowed.contains(&k.as_str())) {
            let suggestion = closest(key, self.allowed).map_or_else(String::new, |s| format!("did you mean \"{s}\"? "));
            return Err(SceneError::new(
                join(&self.path, key),
                "unknown key",
                format!("{suggestion}allowed here: {}", self.allowed.join(", ")),
            ));
        }
        Ok(())
    }

    fn req(&self, key: &str, what: &str) -> Result<At<'a>, SceneError> {
        self.opt(key)
            .ok_or_else(|| SceneError::new(join(&self.path, key), "missing key", format!("add \"{key}\": {what}")))
    }

    fn opt(&self, key: &str) -> Option<At<'a>> {
        self.map.get(key).map(|v| At { v, path: join(&self.path, key) })
    }

    /// Like `opt`, but a JSON `null` counts as absent.
    fn opt_non_null(&self, key: &str) -> Option<At<'a>> {
        self.opt(key).filter(|a| !a.v.is_null())
    }
}

fn display_path(p: &str) -> String {
    if p.is_empty() { "(scene)".to_owned() } else { p.to_owned() }
}

/// Levenshtein-nearest allowed key within distance 2, for "did you mean".
fn closest<'k>(key: &str, allowed: &[&'k str]) -> Option<&'k str> {
    fn dist(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut prev: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut cur = vec![i + 1; b.len() + 1];
            for (j, &cb) in b.iter().enumerate() {
                cur[j + 1] = (prev[j] + usize::from(ca != cb)).min(prev[j + 1] + 1).min(cur[j] + 1);
            }
            prev = cur;
        }
        prev[b.len()]
    }
    allowed.iter().map(|a| (dist(key, a), *a)).filter(|(d, _)| *d <= 2).min_by_key(|(d, _)| *d).map(|(_, a)| a)
}

impl<'a> At<'a> {
    fn idx(&self, i: usize, v: &'a Value) -> At<'a> {
        At { v, path: format!("{}[{i}]", self.path) }
    }

    fn num(&self, what: &str) -> Result<f64, SceneError> {
        match self.v {
            Value::Number(n) => n.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                SceneError::new(&self.path, format!("{n} is not a finite number"), format!("give {what}"))
            }),
            Value::String(s) => Err(SceneError::new(
                &self.path,
                format!("expected a number, got the string \"{s}\""),
                format!("write {what} without quotes"),
            )),
            other => Err(SceneError::new(
                &self.path,
                format!("expected a number, got {}", kind(other)),
                format!("give {what}"),
            )),
        }
    }

    fn uint(&self, what: &str) -> Result<u64, SceneError> {
        match self.v {
            Value::Number(n) => n.as_u64().ok_or_else(|| {
                SceneError::new(&self.path, format!("{n} is not a whole number ≥ 0"), format!("give {what}"))
            }),
            other => Err(SceneError::new(
                &self.path,
                format!("expected a whole number, got {}", kind(other)),
                format!("give {what}"),
            )),
        }
    }

    fn string(&self, what: &str) -> Result<&'a str, SceneError> {
        match self.v {
            Value::String(s) => Ok(s),
            other => Err(SceneError::new(
                &self.path,
                format!("expected a string, got {}", kind(other)),
                format!("give {what}"),
            )),
        }
    }

    fn boolean(&self) -> Result<bool, SceneError> {
        match self.v {
            Value::Bool(b) => Ok(*b),
            other => Err(SceneError::new(
                &self.path,
                format!("expected true or false, got {}", kind(other)),
                "write true or false",
            )),
        }
    }

    fn array(&self, what: &str) -> Result<&'a Vec<Value>, SceneError> {
        match self.v {
            Value::Array(a) => Ok(a),
            other => Err(SceneError::new(
                &self.path,
                format!("expected an array, got {}", kind(other)),
                format!("give {what}"),
            )),
        }
    }

    fn fixed<const N: usize>(&self, what: &str) -> Result<[f64; N], SceneError> {
        let arr = self.array(what)?;
        if arr.len() != N {
            return Err(SceneError::new(
                &self.path,
                format!("expected {N} numbers, got {}", arr.len()),
                format!("give {what}"),
            ));
        }
        let mut out = [0.0; N];
        for (i, v) in arr.iter().enumerate() {
            out[i] = self.idx(i, v).num(what)?;
        }
        Ok(out)
    }

    fn vec3(&self, what: &str) -> Result<[f64; 3], SceneError> {
        self.fixed::<3>(&format!("{what} as [x, y, z]"))
    }

    fn orientation(&self) -> Result<Orientation, SceneError> {
        match self.string("\"outward\" or \"inward\"")? {
            "outward" => Ok(Orientation::Outward),
            "inward" => Ok(Orientation::Inward),
            other => Err(SceneError::new(
                &self.path,
                format!("\"{other}\" is not a normal rule"),
                "write \"outward\" (cutter outside) or \"inward\" (cutter inside)",
            )),
        }
    }

    fn domain(&self, u_unit: &str, v_unit: &str) -> Result<DomainSpec, SceneError> {
        let o = Obj::new(self, &["u", "v"])?;
        Ok(DomainSpec {
            u: o.req("u", &format!("[from, to] in {u_unit}"))?.fixed::<2>(&format!("[from, to] in {u_unit}"))?,
            v: o.req("v", &format!("[from, to] in {v_unit}"))?.fixed::<2>(&format!("[from, to] in {v_unit}"))?,
        })
    }
}

const TOP_KEYS: &[&str] =
    &["format", "name", "surfaces", "tool", "motion", "tolerance", "path", "machine", "tool_axis", "dynamics"];

/// The document as JSON (either scene kind), or where its syntax is wrong.
fn parse_json(text: &str) -> Result<Value, SceneError> {
    serde_json::from_str(text).map_err(|e| {
        SceneError::new(
            "(file)",
            format!("not valid JSON: {e}"),
            "fix the JSON syntax at that line and column (a scene is one JSON object)",
        )
    })
}

/// Parses the document's structure and types.
pub(super) fn parse(text: &str) -> Result<Scene, SceneError> {
    let root = parse_json(text)?;
    if let Some(key) = super::dupkeys::first_duplicate_key(text) {
        return Err(SceneError::new(
            key,
            "appears twice in the same object (the second would silently replace the first)",
            "keep one of the two values and delete the other",
        ));
    }
    let at = At { v: &root, path: String::new() };
    if root.get("finish").is_some() {
        return Err(SceneError::new(
            "finish",
            "this is a finishing scene (one surface and a fillet-end cutter), not a crease scene",
            "run it with `interpolab finish`",
        ));
    }
    let o = Obj::new(&at, TOP_KEYS)?;
    let (name, surfaces) = parse_head(
        &o,
        &SurfaceList {
            hint: "[surface 1, surface 2]",
            what: "the two surfaces",
            wrong_count: |n| format!("expected exactly 2 surfaces, got {n}"),
            fix: "give the two surfaces whose crease is cut",
        },
    )?;
    let [s0, s1] = surfaces;

    let tool_o = Obj::new(&o.req("tool", "{ \"radius\": …, \"allowance\": … }")?, &["radius", "allowance"])?;
    let tool = ToolSpec {
        radius: tool_o.req("radius", "the ball radius in mm")?.num("the ball radius in mm")?,
        allowance: match tool_o.opt("allowance") {
            Some(a) => a.num("the stock to leave in mm")?,
            None => 0.0,
        },
    };
    let motion_o = Obj::new(&o.req("motion", "{ \"feed\": …, \"period\": … }")?, &["feed", "period"])?;
    let motion = MotionSpec {
        feed: motion_o.req("feed", "the feed in mm/min")?.num("the feed in mm/min")?,
        period: motion_o.req("period", "the interpolation period in ms")?.num("the interpolation period in ms")?,
    };
    let tol_o = Obj::new(&o.req("tolerance", "{ \"t1\": …, \"t2\": …, \"share\": … }")?, &["t1", "t2", "share"])?;
    let tolerance = ToleranceSpec {
        t1: tol_o.req("t1", "the tolerance on surface 1 in mm")?.num("the tolerance on surface 1 in mm")?,
        t2: tol_o.req("t2", "the tolerance on surface 2 in mm")?.num("the tolerance on surface 2 in mm")?,
        share: tol_o.req("share", "the interpolation's share, 0 < b ≤ 1")?.num("a share 0 < b ≤ 1")?,
    };
    let path_o = Obj::new(
        &o.req("path", "{ \"start\": [x, y, z], \"end\": [x, y, z] or null }")?,
        &["start", "end", "max_steps", "direction"],
    )?;
    let path = PathSpec {
        start: path_o.req("start", "[x, y, z] in mm")?.vec3("the start point in mm")?,
        end: match path_o.req("end", "[x, y, z] in mm, or null to run until the crease closes")? {
            At { v: Value::Null, .. } => None,
            at => Some(at.vec3("the end point in mm, or null")?),
        },
        max_steps: match path_o.opt_non_null("max_steps") {
            Some(m) => m.uint("the largest number of periods to run")?,
            None => DEFAULT_MAX_STEPS,
        },
        direction: match path_o.opt_non_null("direction") {
            Some(d) => Some(d.vec3("the sense of travel at the start")?),
            None => None,
        },
    };
    let machine = o.opt_non_null("machine").map(|m| parse_machine(&m)).transpose()?;
    let tool_axis = o.opt_non_null("tool_axis").map(|t| parse_tool_axis(&t)).transpose()?;
    let dynamics = o
        .opt_non_null("dynamics")
        .map(|d| {
            crate::plan::Dynamics::from_value(d.v).map_err(|e| {
                let path = if e.path.is_empty() { "dynamics".to_owned() } else { format!("dynamics.{}", e.path) };
                SceneError::new(path, e.problem, e.fix)
            })
        })
        .transpose()?;
    Ok(Scene { name, surfaces: [s0, s1], tool, motion, tolerance, path, machine, tool_axis, dynamics })
}

/// A list of lists (a NURBS net's points or weights), rows then columns, each entry read by
/// `item`; `what` describes the outer and the inner lists for messages.
fn grid<T>(
    at: &At<'_>,
    what: [&str; 2],
    item: impl Fn(&At<'_>) -> Result<T, SceneError>,
) -> Result<Vec<Vec<T>>, SceneError> {
    let rows = at.array(what[0])?;
    let mut out = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let row_at = at.idx(i, row);
        let cols = row_at.array(what[1])?;
        let mut r = Vec::with_capacity(cols.len());
        for (j, c) in cols.iter().enumerate() {
            r.push(item(&row_at.idx(j, c))?);
        }
        out.push(r);
    }
    Ok(out)
}

/// How a scene kind's `surfaces` key is described in its messages.
struct SurfaceList {
    /// What to write when the key is missing.
    hint: &'static str,
    /// What the list holds, when it is not a list.
    what: &'static str,
    /// The message for a list of the wrong length.
    wrong_count: fn(usize) -> String,
    /// What to change then.
    fix: &'static str,
}

/// The keys every scene opens with, crease or finishing: `format` (must be [`FORMAT`]),
/// `name` (optional) and `surfaces`, a list of exactly `N` surfaces — checked in that order.
fn parse_head<const N: usize>(o: &Obj<'_>, list: &SurfaceList) -> Result<(String, [SurfaceSpec; N]), SceneError> {
    let tag = o.req("format", &format!("\"{FORMAT}\""))?.string(&format!("\"{FORMAT}\""))?;
    if tag != FORMAT {
        return Err(SceneError::new(
            "format",
            format!("\"{tag}\" is not a format this version reads"),
            format!("write \"{FORMAT}\""),
        ));
    }
    let name = match o.opt_non_null("name") {
        Some(n) => n.string("a name for the scene")?.to_owned(),
        None => String::new(),
    };
    let surfaces_at = o.req("surfaces", list.hint)?;
    let items = surfaces_at.array(list.what)?;
    if items.len() != N {
        return Err(SceneError::new("surfaces", (list.wrong_count)(items.len()), list.fix));
    }
    let parsed =
        items.iter().enumerate().map(|(i, s)| parse_surface(&surfaces_at.idx(i, s))).collect::<Result<Vec<_>, _>>()?;
    let surfaces =
        parsed.try_into().map_err(|_| SceneError::new("surfaces", (list.wrong_count)(items.len()), list.fix))?;
    Ok((name, surfaces))
}

const KINDS: &str = "\"table-ac\", \"table-bc\", \"head-bc\" or \"head-a-table-c\"";

/// The required string `key` of an object, read before the object's other keys are checked
/// (it decides which keys are allowed).
fn tag<'a>(at: &At<'a>, key: &str, what: &str) -> Result<&'a str, SceneError> {
    let Value::Object(map) = at.v else {
        return Err(SceneError::new(
            display_path(&at.path),
            format!("expected an object, got {}", kind(at.v)),
            format!("write it as {{ \"{key}\": …, … }} with {key} {what}"),
        ));
    };
    match map.get(key) {
        Some(v) => At { v, path: join(&at.path, key) }.string(what),
        None => Err(SceneError::new(join(&at.path, key), "missing key", format!("add \"{key}\": {what}"))),
    }
}

/// `machine`: kind, pivots (keys named by the kind's axes), tool length, travel limits.
fn parse_machine(at: &At<'_>) -> Result<MachineSpec, SceneError> {
    let name = tag(at, "kind", KINDS)?;
    let kind = MachineKind::from_name(name).ok_or_else(|| {
        SceneError::new(
            join(&at.path, "kind"),
            format!("\"{name}\" is not a machine kind"),
            format!("use one of {KINDS}"),
        )
    })?;
    let o = Obj::new(at, &["kind", "pivots", "tool_length", "limits"])?;
    let (pivot_keys, limit_keys): (&'static [&'static str], &'static [&'static str]) = match kind {
        MachineKind::TableAC | MachineKind::HeadATableC => (&["a", "c"], &["a", "c"]),
        MachineKind::TableBC => (&["b", "c"], &["b", "c"]),
        MachineKind::HeadBC => (&["b"], &["b", "c"]),
    };
    let mut pivots = [[0.0; 3]; 2];
    if let Some(p) = o.opt_non_null("pivots") {
        let po = Obj::new(&p, pivot_keys)?;
        for (i, key) in pivot_keys.iter().enumerate() {
            if let Some(v) = po.opt_non_null(key) {
                pivots[i] = v.vec3("a point on that axis in mm")?;
            }
        }
    }
    let tool_length = match o.opt_non_null("tool_length") {
        Some(t) => t.num("the tool length in mm")?,
        None => 0.0,
    };
    let mut limits = [Some(DEFAULT_TILT_LIMITS_DEG), None];
    if let Some(l) = o.opt_non_null("limits") {
        let lo = Obj::new(&l, limit_keys)?;
        for (i, key) in limit_keys.iter().enumerate() {
            match lo.opt(key) {
                None => {}
                Some(At { v: Value::Null, .. }) => limits[i] = None,
                Some(r) => limits[i] = Some(r.fixed::<2>("[min, max] in degrees, or null for unlimited travel")?),
            }
        }
    }
    Ok(MachineSpec { kind, pivots, tool_length, limits })
}

const RULES: &str = "\"bisector\", \"normal1\" or \"fixed\"";

/// `tool_axis`: a rule and its parameters.
fn parse_tool_axis(at: &At<'_>) -> Result<ToolAxisSpec, SceneError> {
    match tag(at, "rule", RULES)? {
        "bisector" => {
            Obj::new(at, &["rule"])?;
            Ok(ToolAxisSpec::Bisector)
        }
        "normal1" => {
            let o = Obj::new(at, &["rule", "lead", "tilt"])?;
            let angle = |key: &str| -> Result<f64, SceneError> {
                o.opt_non_null(key).map_or(Ok(0.0), |a| a.num(&format!("the {key} angle in degrees")))
            };
            Ok(ToolAxisSpec::Normal1 { lead: angle("lead")?, tilt: angle("tilt")? })
        }
        "fixed" => {
            let o = Obj::new(at, &["rule", "vector"])?;
            Ok(ToolAxisSpec::Fixed { vector: o.req("vector", "[i, j, k]")?.vec3("the tool axis direction")? })
        }
        other => Err(SceneError::new(
            join(&at.path, "rule"),
            format!("\"{other}\" is not a tool-axis rule"),
            format!("use one of {RULES}"),
        )),
    }
}

const TYPES: &str = "plane, cylinder, sphere, torus or nurbs";

fn parse_surface(at: &At<'_>) -> Result<SurfaceSpec, SceneError> {
    let Value::Object(map) = at.v else {
        return Err(SceneError::new(
            &at.path,
            format!("expected a surface object, got {}", kind(at.v)),
            format!("give {{ \"type\": …, … }} with type {TYPES}"),
        ));
    };
    let ty = match map.get("type") {
        Some(t) => At { v: t, path: join(&at.path, "type") }.string(TYPES)?,
        None => {
            return Err(SceneError::new(
                join(&at.path, "type"),
                "missing key",
                format!("add \"type\": one of {TYPES}"),
            ));
        }
    };
    match ty {
        "plane" => {
            let o = Obj::new(at, &["type", "origin", "normal", "u_axis", "domain"])?;
            Ok(SurfaceSpec::Plane {
                origin: o.req("origin", "[x, y, z] in mm")?.vec3("a point of the plane in mm")?,
                normal: o.req("normal", "[x, y, z] toward the cutter")?.vec3("the normal toward the cutter")?,
                u_axis: o.req("u_axis", "[x, y, z] in the plane")?.vec3("the u direction, in the plane")?,
                domain: o.req("domain", "{ \"u\": [a, b], \"v\": [a, b] } in mm")?.domain("mm", "mm")?,
            })
        }
        "cylinder" => {
            let o = Obj::new(at, &["type", "origin", "axis", "radius", "ref_dir", "domain", "normal"])?;
            Ok(SurfaceSpec::Cylinder {
                origin: o.req("origin", "[x, y, z] on the axis, in mm")?.vec3("a point on the axis in mm")?,
                axis: o.req("axis", "[x, y, z]")?.vec3("the axis direction")?,
                radius: o.req("radius", "the radius in mm")?.num("the radius in mm")?,
                ref_dir: o.opt_non_null("ref_dir").map(|a| a.vec3("the direction of u = 0, ⊥ axis")).transpose()?,
                domain: o.req("domain", "{ \"u\": [deg, deg], \"v\": [mm, mm] }")?.domain("degrees", "mm")?,
                normal: o.req("normal", "\"outward\" or \"inward\"")?.orientation()?,
            })
        }
        "sphere" => {
            let o = Obj::new(at, &["type", "center", "radius", "axis", "ref_dir", "domain", "normal"])?;
            Ok(SurfaceSpec::Sphere {
                center: o.req("center", "[x, y, z] in mm")?.vec3("the centre in mm")?,
                radius: o.req("radius", "the radius in mm")?.num("the radius in mm")?,
                axis: o.opt_non_null("axis").map(|a| a.vec3("the polar axis")).transpose()?,
                ref_dir: o.opt_non_null("ref_dir").map(|a| a.vec3("the direction of u = 0, ⊥ axis")).transpose()?,
                domain: o.opt_non_null("domain").map(|a| a.domain("degrees", "degrees")).transpose()?,
                normal: o.req("normal", "\"outward\" or \"inward\"")?.orientation()?,
            })
        }
        "torus" => {
            let o = Obj::new(
                at,
                &["type", "center", "axis", "major_radius", "minor_radius", "ref_dir", "domain", "normal"],
            )?;
            Ok(SurfaceSpec::Torus {
                center: o.req("center", "[x, y, z] in mm")?.vec3("the centre in mm")?,
                axis: o.req("axis", "[x, y, z]")?.vec3("the axis direction")?,
                major_radius: o.req("major_radius", "axis-to-tube distance in mm")?.num("the major radius in mm")?,
                minor_radius: o.req("minor_radius", "tube radius in mm")?.num("the minor radius in mm")?,
                ref_dir: o.opt_non_null("ref_dir").map(|a| a.vec3("the direction of u = 0, ⊥ axis")).transpose()?,
                domain: o.opt_non_null("domain").map(|a| a.domain("degrees", "degrees")).transpose()?,
                normal: o.req("normal", "\"outward\" or \"inward\"")?.orientation()?,
            })
        }
        "nurbs" => {
            let o = Obj::new(at, &["type", "degree", "knots_u", "knots_v", "points", "weights", "flip_normal"])?;
            let deg_at = o.req("degree", "[p, q]")?;
            let deg = deg_at.array("[p, q]")?;
            if deg.len() != 2 {
                return Err(SceneError::new(
                    &deg_at.path,
                    format!("expected 2 degrees, got {}", deg.len()),
                    "give [p, q], the degrees in u and v",
                ));
            }
            let p = deg_at.idx(0, &deg[0]).uint("the degree in u")?;
            let q = deg_at.idx(1, &deg[1]).uint("the degree in v")?;
            let knots = |key: &str| -> Result<Vec<f64>, SceneError> {
                let k = o.req(key, "the knot vector")?;
                let arr = k.array("the knot vector, an array of numbers")?;
                arr.iter().enumerate().map(|(i, v)| k.idx(i, v).num("a knot value")).collect()
            };
            let pts_at = o.req("points", "the control net [[[x, y, z], …], …]")?;
            let points = grid(&pts_at, ["the control net, rows along u", "a row of control points"], |a| {
                a.vec3("a control point in mm")
            })?;
            let weights = match o.opt_non_null("weights") {
                Some(w_at) => Some(grid(&w_at, ["weights of the same shape as points", "a row of weights"], |a| {
                    a.num("a weight > 0")
                })?),
                None => None,
            };
            Ok(SurfaceSpec::Nurbs {
                degree: [usize::try_from(p).unwrap_or(usize::MAX), usize::try_from(q).unwrap_or(usize::MAX)],
                knots_u: knots("knots_u")?,
                knots_v: knots("knots_v")?,
                points,
                weights,
                flip_normal: match o.opt_non_null("flip_normal") {
                    Some(b) => b.boolean()?,
                    None => false,
                },
            })
        }
        other => Err(SceneError::new(
            join(&at.path, "type"),
            format!("\"{other}\" is not a surface type"),
            format!("use one of {TYPES}"),
        )),
    }
}

const FINISH_TOP_KEYS: &[&str] = &["format", "name", "surfaces", "finish", "machine"];
const FINISH_KEYS: &[&str] = &[
    "cutter",
    "strategy",
    "lead",
    "scallop",
    "tolerance",
    "max_step",
    "direction",
    "margin",
    "min_cross_curvature",
    "max_inclination",
    "max_tilt",
    "feed",
    "start",
];
const CUTTER_KEYS: &[&str] =
    &["radius", "corner_radius", "flute_length", "shank_radius", "gauge_length", "holder_radius", "holder_length"];

const START_HINT: &str = "\"u0\", \"u1\", \"v0\", \"v1\" or { \"curve\": [[u, v], …] }";

/// `finish.start`: an edge's name or `{ "curve": [[u, v], …] }` (at most
/// [`crate::numerics::limits::MAX_START_CURVE_POINTS`] points, read before they are counted further).
fn parse_start(at: &At<'_>) -> Result<super::finish_spec::StartSpec, SceneError> {
    use super::finish_spec::StartSpec;
    if let Value::String(name) = at.v {
        return Ok(StartSpec::Boundary(name.clone()));
    }
    if !at.v.is_object() {
        return Err(SceneError::new(
            display_path(&at.path),
            format!("expected an edge's name or a curve, got {}", kind(at.v)),
            format!("write {START_HINT}"),
        ));
    }
    let o = Obj::new(at, &["curve"])?;
    let curve = o.req("curve", "[[u, v], [u, v], …]")?;
    let items = curve.array("the start curve's points [u, v] in the surface's parameters")?;
    let max = crate::numerics::limits::MAX_START_CURVE_POINTS;
    if items.len() > max {
        return Err(SceneError::new(
            display_path(&curve.path),
            format!("{} points, more than {max}", items.len()),
            format!("give at most {max} points"),
        ));
    }
    let pts = items
        .iter()
        .enumerate()
        .map(|(i, p)| curve.idx(i, p).fixed::<2>("[u, v] in the surface's parameters (degrees for angles)"))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(StartSpec::Curve(pts))
}

/// Parses a finishing scene's structure and types (`docs/scene-format.md`, finishing jobs).
pub(super) fn parse_finish(text: &str) -> Result<super::finish_spec::FinishScene, SceneError> {
    use super::finish_spec::{CutterSpec, FinishScene, FinishSpec};
    let root = parse_json(text)?;
    let at = At { v: &root, path: String::new() };
    if root.get("finish").is_none() && root.is_object() {
        return Err(SceneError::new(
            "finish",
            "missing key: this is not a finishing scene",
            "add \"finish\": { \"cutter\": …, \"scallop\": … } (docs/scene-format.md), or run a crease scene with `interpolab run`",
        ));
    }
    let o = Obj::new(&at, FINISH_TOP_KEYS)?;
    let (name, [surface]) = parse_head(
        &o,
        &SurfaceList {
            hint: "[the surface to finish]",
            what: "the surface to finish",
            wrong_count: |n| format!("a finishing scene machines exactly 1 surface, got {n}"),
            fix: "give the one surface to finish",
        },
    )?;
    let f = Obj::new(&o.req("finish", "{ \"cutter\": …, \"scallop\": … }")?, FINISH_KEYS)?;
    let c = Obj::new(&f.req("cutter", "{ \"radius\": …, \"corner_radius\": … }")?, CUTTER_KEYS)?;
    let opt_num = |obj: &Obj<'_>, key: &str, what: &str| -> Result<Option<f64>, SceneError> {
        obj.opt_non_null(key).map(|a| a.num(what)).transpose()
    };
    let cutter = CutterSpec {
        radius: c.req("radius", "the cutter radius R in mm")?.num("the cutter radius R in mm")?,
        corner_radius: c.req("corner_radius", "the corner radius r in mm")?.num("the corner radius r in mm")?,
        flute_length: opt_num(&c, "flute_length", "the flute length in mm")?,
        shank_radius: opt_num(&c, "shank_radius", "the shank radius in mm")?,
        gauge_length: opt_num(&c, "gauge_length", "the gauge length in mm")?,
        holder_radius: opt_num(&c, "holder_radius", "the holder radius in mm")?,
        holder_length: opt_num(&c, "holder_length", "the holder length in mm")?,
    };
    let strategy = match f.opt_non_null("strategy") {
        Some(s) => s.string("\"matched\", \"fixed-lead\", \"principal\" or \"ball\"")?.to_owned(),
        None => "matched".to_owned(),
    };
    let direction = match f.opt_non_null("direction") {
        Some(s) => s.string("\"u\", \"v\" or \"auto\"")?.to_owned(),
        None => "auto".to_owned(),
    };
    let finish = FinishSpec {
        cutter,
        strategy,
        lead: opt_num(&f, "lead", "the lead angle in degrees")?,
        scallop: f.req("scallop", "the scallop height h in mm")?.num("the scallop height h in mm")?,
        tolerance: f.req("tolerance", "the chord tolerance E in mm")?.num("the chord tolerance E in mm")?,
        max_step: opt_num(&f, "max_step", "the longest forward step in mm")?,
        direction,
        margin: opt_num(&f, "margin", "the curvature margin in 1/mm")?,
        min_cross_curvature: opt_num(&f, "min_cross_curvature", "the smallest cross curvature in 1/mm")?,
        max_inclination: opt_num(&f, "max_inclination", "the largest inclination in degrees")?,
        max_tilt: opt_num(&f, "max_tilt", "the largest tilt in degrees")?,
        feed: opt_num(&f, "feed", "the feed in mm/min")?,
        start: f.opt_non_null("start").map(|s| parse_start(&s)).transpose()?,
    };
    let machine = o.opt_non_null("machine").map(|m| parse_machine(&m)).transpose()?;
    Ok(FinishScene { name, surface, finish, machine })
}
