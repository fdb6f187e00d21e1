//! The simulation job as text: its request, partial outputs and output, numbers by their
//! bits and large arrays packed as base64url of their little-endian bytes.

use glam::{DVec2, DVec3};
use serde_json::{Value, json};

use super::output::{Finished, Keyframe, Partial, Prepared};
use super::request::{DesignSpec, MAX_RAYS, ProgramSource, Request};
use crate::fillet::CcNode;
use crate::fillet::contact::{ContactFrame, Form2, Pose};
use crate::fiveaxis::{Joints, Machine, MachineKind};
use crate::gcode::ProgramKind;
use crate::geom::Cutter;
use crate::jobs::{DecodeError, JobError, Reader, bits_packed, f32s_packed, f64s_packed, num, nums, parse};
use crate::simulate::bench::BenchKind;
use crate::simulate::measure::Summary;
use crate::simulate::stock::Grid;
use crate::simulate::{Counters, HeightMap, MoveKind, Program, SimMove, SimStats};

/// A request as text ([`decode_request`] reads it).
#[must_use]
pub fn encode_request(r: &Request) -> String {
    let source = match &r.source {
        ProgramSource::Crease { scene, kind } => {
            json!({ "crease": scene, "kind": ProgramKind::ALL.iter().position(|k| k == kind).unwrap_or(0) })
        }
        ProgramSource::Steps { scene } => json!({ "steps": scene }),
        ProgramSource::Text { name, text } => json!({ "name": name, "text": text }),
        ProgramSource::Moves(p) => json!({ "moves": program_value(p) }),
        ProgramSource::Benchmark { kind, moves } => json!({ "benchmark": kind.key(), "count": moves }),
        ProgramSource::Finish { scene, cutter, passes, step_tol_mm } => json!({
            "finish": scene,
            "cutter": cutter_value(cutter),
            "passes": passes.iter().map(|p| nodes_value(p)).collect::<Vec<_>>(),
            "step_tol_mm": num(*step_tol_mm),
        }),
    };
    json!({
        "source": source,
        "cutter": cutter_value(&r.cutter),
        "pitch_mm": r.pitch_mm.map_or(Value::Null, num),
        "stock_mm": r.stock_mm.map_or(Value::Null, nums),
        "margin_mm": num(r.margin_mm),
        "max_sample_step_mm": r.max_sample_step_mm.map_or(Value::Null, num),
        "design": match &r.design {
            DesignSpec::None => Value::Null,
            DesignSpec::PlaneZ(z) => json!({ "plane_z_mm": num(*z) }),
            DesignSpec::Scene(s) => json!({ "scene": s }),
            DesignSpec::Finish(s) => json!({ "finish": s }),
        },
        "target": r.target,
        "keyframes": r.keyframes,
        "resume": r.resume,
    })
    .to_string()
}

/// A request read from text.
///
/// # Errors
/// What in the text is not a request.
pub fn decode_request(text: &str) -> Result<Request, DecodeError> {
    const W: &str = "simulate-run request";
    let v = parse(text, W)?;
    let r = Reader::new(&v, W)?;
    let s = Reader::new(r.value("source")?, "simulate-run request.source")?;
    let source = if let Ok(scene) = s.str("crease") {
        let kind = *ProgramKind::ALL.get(s.usize("kind")?).ok_or("simulate-run request.source.kind: out of range")?;
        ProgramSource::Crease { scene: scene.to_owned(), kind }
    } else if let Ok(scene) = s.str("steps") {
        ProgramSource::Steps { scene: scene.to_owned() }
    } else if let Ok(text) = s.str("text") {
        ProgramSource::Text { name: s.str("name")?.to_owned(), text: text.to_owned() }
    } else if let Ok(scene) = s.str("finish") {
        let passes = s
            .value("passes")?
            .as_array()
            .ok_or("simulate-run request.source.passes: not a list")?
            .iter()
            .map(nodes_of)
            .collect::<Result<Vec<_>, _>>()?;
        ProgramSource::Finish {
            scene: scene.to_owned(),
            cutter: cutter_of(&s.f64s("cutter")?).map_err(|e| format!("{W}.source.cutter: {e}"))?,
            passes,
            step_tol_mm: s.f64("step_tol_mm")?,
        }
    } else if let Ok(kind) = s.str("benchmark") {
        let (kind, moves) = BenchKind::parse(&format!("{kind}:{}", s.usize("count")?))
            .map_err(|e| format!("simulate-run request.source: {e}"))?;
        ProgramSource::Benchmark { kind, moves }
    } else {
        ProgramSource::Moves(program_of(s.value("moves")?)?)
    };
    let cutter = cutter_of(&r.f64s("cutter")?).map_err(|e| format!("{W}.cutter: {e}"))?;
    let stock_mm = match r.value("stock_mm")? {
        Value::Null => None,
        _ => Some(r.f64s("stock_mm")?.try_into().map_err(|_| format!("{W}.stock_mm: not six numbers"))?),
    };
    let design = match r.value("design")? {
        Value::Null => DesignSpec::None,
        d => {
            let d = Reader::new(d, "simulate-run request.design")?;
            if let Ok(s) = d.str("scene") {
                DesignSpec::Scene(s.to_owned())
            } else if let Ok(s) = d.str("finish") {
                DesignSpec::Finish(s.to_owned())
            } else {
                DesignSpec::PlaneZ(d.f64("plane_z_mm")?)
            }
        }
    };
    let target = match r.value("target")? {
        Value::Null => None,
        _ => Some(r.usize("target")?),
    };
    Ok(Request {
        source,
        cutter,
        pitch_mm: r.opt_f64("pitch_mm")?,
        stock_mm,
        margin_mm: r.f64("margin_mm")?,
        max_sample_step_mm: match r.value("max_sample_step_mm")? {
            Value::Null => None,
            _ => Some(r.f64("max_sample_step_mm")?),
        },
        design,
        target,
        keyframes: r.usize("keyframes")?,
        resume: r.value("resume")?.as_bool().ok_or(format!("{W}.resume: not true or false"))?,
    })
}

/// A run's output as text ([`decode_output`] reads it).
#[must_use]
pub fn encode_output(out: &Result<Finished, JobError>) -> String {
    let f = match out {
        Err(e) => return e.encode(),
        Ok(f) => f,
    };
    let s = &f.stats;
    // A run without a design (or whose design is over no ray) has no deviation on any
    // ray: the two arrays (2.4 MB of text at 512 × 512) are left out, `null` instead.
    let (dev, has) = if s.deviation_mm.iter().any(Option::is_some) {
        let dev: Vec<f64> = s.deviation_mm.iter().map(|d| d.unwrap_or(0.0)).collect();
        let has: Vec<bool> = s.deviation_mm.iter().map(Option::is_some).collect();
        (f64s_packed(&dev), bits_packed(&has))
    } else {
        (Value::Null, Value::Null)
    };
    json!({
        "counters": counters_value(&f.counters),
        "resumed_from": f.resumed_from,
        "map": {
            "grid": grid_value(&f.map.grid),
            "top_mm": f64s_packed(&f.map.top_mm),
            "machined": bits_packed(&f.map.machined),
            "through": f.map.through,
        },
        "stats": {
            "machined_rays": s.machined_rays,
            "through_rays": s.through_rays,
            "split_rays": s.split_rays,
            "deviation_mm": dev,
            "has_deviation": has,
            "scallop": {
                "count": s.scallop.count,
                "max_mm": num(s.scallop.max_mm),
                "mean_mm": num(s.scallop.mean_mm),
                "p95_mm": num(s.scallop.p95_mm),
            },
            "worst_gouge": s.worst_gouge.map_or(Value::Null, |(d, at)| nums([d, at.x, at.y])),
            "gouge_rays": s.gouge_rays,
        },
    })
    .to_string()
}

/// A run's output read from text.
///
/// # Errors
/// What in the text is not an output.
pub fn decode_output(text: &str) -> Result<Result<Finished, JobError>, DecodeError> {
    const W: &str = "simulate-run output";
    let v = parse(text, W)?;
    if let Some(e) = JobError::decode(&v, W)? {
        return Ok(Err(e));
    }
    let r = Reader::new(&v, W)?;
    let m = Reader::new(r.value("map")?, "simulate-run output.map")?;
    let grid = grid_of(m.value("grid")?)?;
    let n = grid.len();
    let map = HeightMap {
        grid,
        top_mm: m.f64s_packed("top_mm", n)?,
        machined: m.bits_packed("machined", n)?,
        through: m.usize("through")?,
    };
    let s = Reader::new(r.value("stats")?, "simulate-run output.stats")?;
    // `null`: no ray has a deviation (a run without a design).
    let (dev, has) = match s.value("deviation_mm")? {
        Value::Null => (vec![0.0; n], vec![false; n]),
        _ => (s.f64s_packed("deviation_mm", n)?, s.bits_packed("has_deviation", n)?),
    };
    let sc = Reader::new(s.value("scallop")?, "simulate-run output.stats.scallop")?;
    let worst_gouge = match s.value("worst_gouge")? {
        Value::Null => None,
        _ => match s.f64s("worst_gouge")?[..] {
            [d, x, y] => Some((d, DVec2::new(x, y))),
            _ => return Err(format!("{W}.stats.worst_gouge: not three numbers").into()),
        },
    };
    let stats = SimStats {
        machined_rays: s.usize("machined_rays")?,
        through_rays: s.usize("through_rays")?,
        split_rays: s.usize("split_rays")?,
        deviation_mm: dev.into_iter().zip(has).map(|(d, h)| h.then_some(d)).collect(),
        scallop: Summary {
            count: sc.usize("count")?,
            max_mm: sc.f64("max_mm")?,
            mean_mm: sc.f64("mean_mm")?,
            p95_mm: sc.f64("p95_mm")?,
        },
        worst_gouge,
        gouge_rays: s.usize("gouge_rays")?,
    };
    Ok(Ok(Finished {
        counters: counters_of(r.value("counters")?)?,
        resumed_from: r.usize("resumed_from")?,
        map,
        stats,
    }))
}

/// A partial output read from text.
///
/// # Errors
/// What in the text is not a partial output.
pub fn decode_partial(text: &str) -> Result<Partial, DecodeError> {
    const W: &str = "simulate-run partial";
    let v = parse(text, W)?;
    let r = Reader::new(&v, W)?;
    if let Ok(p) = r.value("prepared") {
        let p = Reader::new(p, "simulate-run partial.prepared")?;
        let design_name = match p.str("design")? {
            "none" => "none",
            "plane" => "plane",
            "scene surfaces" => "scene surfaces",
            "finish surface" => "finish surface",
            other => return Err(format!("{W}.prepared.design: \"{other}\" is not a design").into()),
        };
        return Ok(Partial::Prepared(Box::new(Prepared {
            program: program_of(p.value("program")?)?,
            stock_mm: p.f64s("stock_mm")?.try_into().map_err(|_| format!("{W}.prepared.stock_mm: not six numbers"))?,
            pitch_mm: p.f64("pitch_mm")?,
            grid: grid_of(p.value("grid")?)?,
            design_name,
            target: p.usize("target")?,
            keyframe_every: p.usize("keyframe_every")?,
        })));
    }
    let k = Reader::new(r.value("keyframe")?, "simulate-run partial.keyframe")?;
    let n = k.usize("rays")?;
    if n > MAX_RAYS {
        return Err(format!("{W}.keyframe.rays: {n} is more than {MAX_RAYS}").into());
    }
    Ok(Partial::Keyframe(Keyframe {
        moves: k.usize("moves")?,
        counters: counters_of(k.value("counters")?)?,
        top_mm: k.f32s_packed("top_mm", n)?,
        machined: k.bits_packed("machined", n)?,
    }))
}

/// A partial output as text ([`decode_partial`] reads it).
#[must_use]
pub fn encode_partial(p: &Partial) -> String {
    match p {
        Partial::Prepared(p) => json!({ "prepared": {
            "program": program_value(&p.program),
            "stock_mm": nums(p.stock_mm),
            "pitch_mm": num(p.pitch_mm),
            "grid": grid_value(&p.grid),
            "design": p.design_name,
            "target": p.target,
            "keyframe_every": p.keyframe_every,
        }}),
        Partial::Keyframe(k) => json!({ "keyframe": {
            "moves": k.moves,
            "counters": counters_value(&k.counters),
            "rays": k.top_mm.len(),
            "top_mm": f32s_packed(&k.top_mm),
            "machined": bits_packed(&k.machined),
        }}),
    }
    .to_string()
}

fn cutter_value(c: &Cutter) -> Value {
    nums(c.numbers())
}

fn cutter_of(c: &[f64]) -> Result<Cutter, DecodeError> {
    Cutter::from_numbers(c).map_err(DecodeError::from)
}

/// Numbers of a CC node: uv, point, normal, feed, cross, the surface's form (3), pose (2),
/// tip, axis, strip, side step and scallop (NaN: none), lead-out (1) or CC point (0).
const NODE_NUMBERS: usize = 2 + 3 * 4 + 3 + 2 + 3 + 3 + 3 + 1;

/// A pass's CC nodes, packed (what planning needs of them; the gouge checks' record of an
/// adjustment stays on the page).
fn nodes_value(nodes: &[CcNode]) -> Value {
    let mut d = Vec::with_capacity(nodes.len() * NODE_NUMBERS);
    for n in nodes {
        let f = &n.frame;
        d.extend([f.uv.x, f.uv.y]);
        for v in [f.point, f.normal, f.feed, f.cross] {
            d.extend([v.x, v.y, v.z]);
        }
        d.extend([f.surface_form.ff, f.surface_form.fc, f.surface_form.cc]);
        d.extend([n.pose.inclination_rad, n.pose.azimuth_rad]);
        d.extend([n.tip.x, n.tip.y, n.tip.z, n.axis.x, n.axis.y, n.axis.z]);
        d.extend([n.strip_mm, n.side_step_mm.unwrap_or(f64::NAN), n.scallop_mm.unwrap_or(f64::NAN)]);
        d.push(if n.lead_out { 1.0 } else { 0.0 });
    }
    json!({ "count": nodes.len(), "data": f64s_packed(&d) })
}

fn nodes_of(v: &Value) -> Result<Vec<CcNode>, DecodeError> {
    let r = Reader::new(v, "simulate-run request.source.passes[]")?;
    let n = r.usize("count")?;
    let d = r.f64s_packed("data", n.checked_mul(NODE_NUMBERS).ok_or("simulate-run request: too many CC nodes")?)?;
    let v3 = |s: &[f64]| DVec3::new(s[0], s[1], s[2]);
    let opt = |x: f64| (!x.is_nan()).then_some(x);
    Ok(d.chunks_exact(NODE_NUMBERS)
        .map(|c| CcNode {
            frame: ContactFrame {
                uv: DVec2::new(c[0], c[1]),
                point: v3(&c[2..5]),
                normal: v3(&c[5..8]),
                feed: v3(&c[8..11]),
                cross: v3(&c[11..14]),
                surface_form: Form2 { ff: c[14], fc: c[15], cc: c[16] },
            },
            pose: Pose { inclination_rad: c[17], azimuth_rad: c[18] },
            tip: v3(&c[19..22]),
            axis: v3(&c[22..25]),
            strip_mm: c[25],
            side_step_mm: opt(c[26]),
            scallop_mm: opt(c[27]),
            adjusted: None,
            lead_out: c[28] != 0.0,
        })
        .collect())
}

/// A grid as JSON.
pub(crate) fn grid_value(g: &Grid) -> Value {
    json!({ "x0_mm": num(g.x0_mm), "y0_mm": num(g.y0_mm), "pitch_mm": num(g.pitch_mm), "nx": g.nx, "ny": g.ny })
}

/// A grid read from JSON, at most [`MAX_RAYS`] rays.
pub(crate) fn grid_of(v: &Value) -> Result<Grid, DecodeError> {
    let g = Reader::new(v, "simulate-run grid")?;
    let grid = Grid {
        x0_mm: g.f64("x0_mm")?,
        y0_mm: g.f64("y0_mm")?,
        pitch_mm: g.f64("pitch_mm")?,
        nx: g.usize("nx")?,
        ny: g.usize("ny")?,
    };
    if grid.nx.checked_mul(grid.ny).is_none_or(|n| n > MAX_RAYS) {
        return Err(format!("simulate-run grid: {} × {} rays is more than {MAX_RAYS}", grid.nx, grid.ny).into());
    }
    Ok(grid)
}

/// A run's counts as JSON.
pub(crate) fn counters_value(c: &Counters) -> Value {
    json!({
        "moves": c.moves,
        "samples": c.samples,
        "rays_visited": c.rays_visited,
        "ray_updates": c.ray_updates,
        "joint_updates": c.joint_updates,
        "crash_visits": c.crash_visits,
        "removed_mm3": num(c.removed_mm3),
        "rapid_cuts": c.rapid_cuts,
        "first_rapid_cut_line": c.first_rapid_cut_line,
        "sweep_sagitta_mm": num(c.sweep_sagitta_mm),
    })
}

/// A run's counts read from JSON.
pub(crate) fn counters_of(v: &Value) -> Result<Counters, DecodeError> {
    let c = Reader::new(v, "simulate-run counters")?;
    let u64_of = |k: &str| -> Result<u64, DecodeError> {
        c.value(k)?.as_u64().ok_or_else(|| format!("simulate-run counters.{k}: not a count").into())
    };
    Ok(Counters {
        moves: c.usize("moves")?,
        samples: u64_of("samples")?,
        rays_visited: u64_of("rays_visited")?,
        ray_updates: u64_of("ray_updates")?,
        joint_updates: u64_of("joint_updates")?,
        crash_visits: u64_of("crash_visits")?,
        removed_mm3: c.f64("removed_mm3")?,
        rapid_cuts: c.usize("rapid_cuts")?,
        first_rapid_cut_line: match c.value("first_rapid_cut_line")? {
            Value::Null => None,
            _ => Some(c.usize("first_rapid_cut_line")?),
        },
        sweep_sagitta_mm: c.f64("sweep_sagitta_mm")?,
    })
}

/// Numbers of a line move: from, to.
const LINE_NUMBERS: usize = 6;
/// Numbers of a joints move: the machine (kind, two pivots, tool length, two limits as
/// flag, low, high) and the two joint sets (xyz, two rotary).
const JOINTS_NUMBERS: usize = 14 + 10;

/// Every number of a move, in the order [`program_of`] reads them: a line's two tips (6),
/// a 5-axis move's machine (kind, pivots, tool length, limits: 14) and its two joint sets
/// (10).
pub(super) fn move_numbers(m: &SimMove) -> Vec<f64> {
    match m.kind {
        MoveKind::Line { from, to } => vec![from.x, from.y, from.z, to.x, to.y, to.z],
        MoveKind::Joints { machine, from, to } => {
            let mut data = Vec::with_capacity(24);
            let kind = MachineKind::ALL.iter().position(|k| *k == machine.kind).unwrap_or(0);
            data.push(kind as f64);
            for v in machine.pivots_mm {
                data.extend([v.x, v.y, v.z]);
            }
            data.push(machine.tool_length_mm);
            for l in machine.limits_rad {
                match l {
                    Some([lo, hi]) => data.extend([1.0, lo, hi]),
                    None => data.extend([0.0, 0.0, 0.0]),
                }
            }
            for j in [from, to] {
                data.extend([j.xyz_mm.x, j.xyz_mm.y, j.xyz_mm.z, j.rotary_rad[0], j.rotary_rad[1]]);
            }
            data
        }
    }
}

fn program_value(p: &Program) -> Value {
    let data: Vec<f64> = p.moves.iter().flat_map(move_numbers).collect();
    json!({
        "count": p.moves.len(),
        "joints": bits_packed(&p.moves.iter().map(|m| matches!(m.kind, MoveKind::Joints { .. })).collect::<Vec<_>>()),
        "rapid": bits_packed(&p.moves.iter().map(|m| m.rapid).collect::<Vec<_>>()),
        "lines": p.moves.iter().map(|m| m.line).collect::<Vec<_>>(),
        "data": f64s_packed(&data),
        "numbers": data.len(),
        "chord_error_mm": num(p.chord_error_mm),
    })
}

fn program_of(v: &Value) -> Result<Program, DecodeError> {
    const W: &str = "simulate-run program";
    let r = Reader::new(v, W)?;
    // The count is bounded by the text: every move has its flags, line and numbers in it.
    let n = r.usize("count")?;
    let joints = r.bits_packed("joints", n)?;
    let rapid = r.bits_packed("rapid", n)?;
    let lines: Vec<usize> = r
        .value("lines")?
        .as_array()
        .and_then(|a| a.iter().map(|x| x.as_u64().and_then(|x| usize::try_from(x).ok())).collect())
        .ok_or_else(|| format!("{W}.lines: not a list of line numbers"))?;
    let numbers = r.usize("numbers")?;
    let expected: usize = joints.iter().map(|j| if *j { JOINTS_NUMBERS } else { LINE_NUMBERS }).sum();
    if lines.len() != n || numbers != expected {
        return Err(format!("{W}: {} lines and {numbers} numbers for {n} moves", lines.len()).into());
    }
    let data = r.f64s_packed("data", numbers)?;
    let mut at = 0;
    let mut take = |k: usize| {
        let s = &data[at..at + k];
        at += k;
        s
    };
    let v3 = |s: &[f64]| DVec3::new(s[0], s[1], s[2]);
    let mut moves = Vec::with_capacity(n);
    for i in 0..n {
        let kind = if joints[i] {
            let d = take(JOINTS_NUMBERS);
            let kind = *MachineKind::ALL.get(d[0] as usize).ok_or_else(|| format!("{W}: move {i}: no machine kind"))?;
            let limit = |s: &[f64]| (s[0] != 0.0).then_some([s[1], s[2]]);
            let machine = Machine {
                kind,
                pivots_mm: [v3(&d[1..4]), v3(&d[4..7])],
                tool_length_mm: d[7],
                limits_rad: [limit(&d[8..11]), limit(&d[11..14])],
            };
            let j = |s: &[f64]| Joints { xyz_mm: v3(s), rotary_rad: [s[3], s[4]] };
            MoveKind::Joints { machine, from: j(&d[14..19]), to: j(&d[19..24]) }
        } else {
            let d = take(LINE_NUMBERS);
            MoveKind::Line { from: v3(&d[0..3]), to: v3(&d[3..6]) }
        };
        moves.push(SimMove { kind, line: lines[i], rapid: rapid[i] });
    }
    Ok(Program { moves, chord_error_mm: r.f64("chord_error_mm")? })
}
