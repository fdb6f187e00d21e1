//! `interpolab finish` as a script would use it: the CL data re-checked from the printed
//! numbers alone (tool geometry by `Cutter`'s profile), G-code, exit statuses and one-line
//! errors.
#![cfg(not(target_arch = "wasm32"))]

use std::path::PathBuf;
use std::process::{Command, Output};

use glam::DVec3;
use interpolab::geom::Cutter;

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_interpolab")).args(args).output().expect("runs")
}

fn example(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join("finish")
        .join(format!("{name}.json"))
        .display()
        .to_string()
}

fn temp(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("interpolab-finish-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p.display().to_string()
}

#[test]
fn cl_data_puts_every_cc_point_on_the_cutter_and_the_program_has_blocks() {
    let nc = temp("blade.nc", "");
    let o = run(&["finish", &example("naca-blade"), "--gcode", &nc]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "path,node,x,y,z,i,j,k,cc_x,cc_y,cc_z,u,v,lead_deg,tilt_deg,strip_mm,side_step_mm,scallop_mm,adjusted,lead_out"
    );
    let cutter = Cutter::fillet(4.0, 1.0).unwrap();
    let mut rows = 0;
    let mut paths = std::collections::BTreeSet::new();
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|c| if c.is_empty() { f64::NAN } else { c.parse().unwrap() }).collect();
        let tip = DVec3::new(v[2], v[3], v[4]);
        let axis = DVec3::new(v[5], v[6], v[7]);
        let cc = DVec3::new(v[8], v[9], v[10]);
        assert!((axis.length() - 1.0).abs() < 1e-12);
        // The CC point lies on the cutter's lower surface: its height above the tip equals
        // the profile's height at its distance from the axis.
        let w = cc - tip;
        let z = w.dot(axis);
        let rho = (w - z * axis).length();
        let on = cutter.bottom_height_mm(rho).expect("within the cutter radius");
        assert!((z - on).abs() < 1e-9, "row {rows}: CC point {z} vs profile {on} at ρ {rho}");
        assert!(v[15] > 0.0 && v[13] >= 3.0 - 1e-9, "strip and lead ≥ 3°: {line}");
        paths.insert(v[0] as i64);
        rows += 1;
    }
    assert!(rows > 500 && paths.len() > 20, "{rows} rows, {} paths", paths.len());
    let program = std::fs::read_to_string(&nc).unwrap();
    let g01 = program.lines().filter(|l| l.starts_with("G01 X")).count();
    assert!(g01 > 200 && program.contains(" A") && program.contains(" C") && program.ends_with("blocks)\n"));
}

#[test]
fn the_table_compares_every_strategy_and_layout() {
    let o = run(&["finish", &example("naca-blade"), "--table"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    for s in [
        "| matched | iso-scallop",
        "| matched | iso-parametric",
        "| fixed-lead 5.0° |",
        "| fixed-lead 10.0° |",
        "| principal |",
        "| ball |",
    ] {
        assert!(text.contains(s), "missing {s}:\n{text}");
    }
}

/// The blade with one control point moved under the others (a fuzz finding) turns a stretch
/// of the surface so the strategy's tool axes need A = 121° on a table whose A stops at 120°.
/// `finish --gcode` keeps every pose within the machine's reach (the gouge checks' search
/// goes on past a pose the table cannot tilt to): the program is written, every A word in it
/// within ±120°, and `replay` reads it back; the CL data alone, for no machine, has axes past
/// 120° (so the machine's reach, not the surface, made the difference). The job used to be
/// refused at the first path out of travel.
#[test]
fn a_program_keeps_its_tool_axes_within_the_machine_s_travel() {
    let text = std::fs::read_to_string(example("naca-blade")).expect("example");
    let mut scene: serde_json::Value = serde_json::from_str(&text).expect("json");
    assert_eq!(scene["machine"]["limits"]["a"], serde_json::json!([-120, 120]), "the example's table changed");
    scene["surfaces"][0]["points"][2][0][1] = serde_json::json!(1e-9);
    let p = temp("folded-blade.json", &scene.to_string());
    let nc = temp("folded-blade.nc", "");
    let o = run(&["finish", &p, "--gcode", &nc, "--out", &temp("folded-blade.csv", "")]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{err}");
    let program = std::fs::read_to_string(&nc).expect("program");
    let a: Vec<f64> = program
        .lines()
        .filter(|l| l.starts_with("G0"))
        .flat_map(str::split_whitespace)
        .filter_map(|w| w.strip_prefix('A'))
        .map(|v| v.parse::<f64>().expect("A value"))
        .collect();
    assert!(a.len() > 1000, "{} A words", a.len());
    let widest = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(widest <= 120.0, "A = {widest}° in the program");
    let back = run(&["replay", &nc]);
    assert_eq!(back.status.code(), Some(0), "{}", String::from_utf8_lossy(&back.stderr));
    let o = run(&["finish", &p, "--format", "json"]);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let columns = doc["columns"].as_array().expect("columns");
    let k = columns.iter().position(|c| c == "k").expect("k column");
    let steepest = doc["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .map(|r| r[k].as_f64().expect("k").clamp(-1.0, 1.0).acos().to_degrees())
        .fold(0.0f64, f64::max);
    assert!(steepest > 120.0, "the CL data's axes stay within {steepest}°: the case no longer tests the reach");
}

/// A cutter far too large for the mould (R 25 mm in a bowl of about 20 mm radius) has dozens
/// of CC points refused: standard error counts them in one line per reason (with the first and
/// last place), not a line each; the JSON names every one; the status is 1.
#[test]
fn refused_cc_points_are_counted_a_line_per_reason() {
    let text = std::fs::read_to_string(example("concave-mould")).expect("example");
    let mut scene: serde_json::Value = serde_json::from_str(&text).expect("json");
    scene["finish"]["cutter"] = serde_json::json!({ "radius": 25.0, "corner_radius": 1.0 });
    scene["finish"]["scallop"] = serde_json::json!(0.3);
    scene["finish"]["tolerance"] = serde_json::json!(0.02);
    scene["finish"]["max_step"] = serde_json::json!(2.0);
    let p = temp("big-cutter.json", &scene.to_string());
    let o = run(&["finish", &p, "--format", "json"]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let refused = doc["refused"].as_array().expect("refused");
    let mut reasons: Vec<&str> = refused.iter().map(|r| r["reason"].as_str().expect("reason")).collect();
    reasons.sort_unstable();
    reasons.dedup();
    assert!(
        refused.len() > 2 * reasons.len(),
        "{} refused for {} reasons: too few to test",
        refused.len(),
        reasons.len()
    );
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("CC point(s) refused")).collect();
    assert_eq!(lines.len(), reasons.len(), "{err}");
    let counted: usize = lines
        .iter()
        .map(|l| l.split(": ").nth(2).and_then(|t| t.split(' ').next()).and_then(|n| n.parse::<usize>().ok()).expect(l))
        .sum();
    assert_eq!(counted, refused.len(), "{err}");
    for r in &reasons {
        assert!(lines.iter().any(|l| l.contains(r)), "{r} not named in {err}");
    }
    assert!(!err.contains("-0.000"), "{err}");
}

#[test]
fn bad_input_gets_one_line_and_status_2() {
    let cases = [
        (r#"{"format":"interpolab-scene/1","surfaces":[],"finish":{}}"#, "exactly 1 surface"),
        (
            r#"{"format":"interpolab-scene/1","surfaces":[{"type":"plane","origin":[0,0,0],"normal":[0,0,1],"u_axis":[1,0,0],"domain":{"u":[0,10],"v":[0,10]}}],"finish":{"cutter":{"radius":5,"corner_radius":6},"scallop":0.01,"tolerance":0.001}}"#,
            "corner radius",
        ),
        (
            r#"{"format":"interpolab-scene/1","surfaces":[{"type":"plane","origin":[0,0,0],"normal":[0,0,1],"u_axis":[1,0,0],"domain":{"u":[0,10],"v":[0,10]}}],"finish":{"cutter":{"radius":5,"corner_radius":1},"scallop":-1,"tolerance":0.001}}"#,
            "finish.scallop",
        ),
        (
            r#"{"format":"interpolab-scene/1","surfaces":[{"type":"plane","origin":[0,0,0],"normal":[0,0,1],"u_axis":[1,0,0],"domain":{"u":[0,10],"v":[0,10]}}],"finish":{"cutter":{"radius":5,"corner_radius":1},"scallop":0.01,"tolerance":0.001,"strategy":"best"}}"#,
            "finish.strategy",
        ),
        (
            r#"{"format":"interpolab-scene/1","surfaces":[{"type":"plane","origin":[0,0,0],"normal":[0,0,1],"u_axis":[1,0,0],"domain":{"u":[0,10],"v":[0,10]}}],"finish":{"cutter":{"radius":5,"corner_radius":1},"scallop":0.01,"tolerance":0.001,"min_cross_curvature":-0.01}}"#,
            "finish.min_cross_curvature",
        ),
        (
            r#"{"format":"interpolab-scene/1","surfaces":[{"type":"plane","origin":[0,0,0],"normal":[0,0,1],"u_axis":[1,0,0],"domain":{"u":[0,10],"v":[0,10]}}],"finish":{"cutter":{"radius":5,"corner_radius":1},"scallop":0.01,"tolerance":0.001,"max_tilt":60}}"#,
            "finish.max_tilt",
        ),
    ];
    for (i, (json, needle)) in cases.iter().enumerate() {
        let p = temp(&format!("bad{i}.json"), json);
        let o = run(&["finish", &p]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{json}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{needle} not in {err}");
    }
    // A crease command on a finishing scene says which command to use.
    let o = run(&["run", &example("bicubic-patch")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("interpolab finish"));
}

/// Points of the cutter's surface (mm) for the tool at `tip` along `axis`: the flat bottom
/// every `d_mm` in radius, the corner every `deg`°, the flank every `d_mm` up the flutes, on
/// `meridians` meridians — the cutter's own geometry (R, r, flute length), not the core's.
fn cutter_points(cutter: &Cutter, tip: DVec3, axis: DVec3, meridians: u32, deg: f64, d_mm: f64) -> Vec<DVec3> {
    let e1 = interpolab::geom::any_perpendicular(axis);
    let e2 = axis.cross(e1);
    let (r, r0) = (cutter.corner_radius_mm, cutter.radius_mm - cutter.corner_radius_mm);
    let mut profile = vec![];
    let mut rho = 0.0;
    while rho < r0 {
        profile.push((rho, 0.0));
        rho += d_mm;
    }
    let mut b = 0.0f64;
    while b <= 90.0 {
        let t = b.to_radians();
        profile.push((r0 + r * t.sin(), r * (1.0 - t.cos())));
        b += deg;
    }
    let mut z = r + d_mm;
    while z <= cutter.flute_length_mm {
        profile.push((cutter.radius_mm, z));
        z += d_mm;
    }
    let mut pts = Vec::with_capacity(profile.len() * meridians as usize);
    for m in 0..meridians {
        let phi = std::f64::consts::TAU * f64::from(m) / f64::from(meridians);
        let e = phi.cos() * e1 + phi.sin() * e2;
        pts.extend(profile.iter().map(|&(rho, z)| tip + rho * e + z * axis));
    }
    pts
}

/// The CL rows of `finish FILE` (CSV): tool tip, axis, (u, v), whether a lead-out.
fn cl_rows(file: &str) -> Vec<(DVec3, DVec3, glam::DVec2, bool)> {
    let o = run(&["finish", file]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    text.lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> =
                line.split(',').map(|c| if c.is_empty() { f64::NAN } else { c.parse().unwrap() }).collect();
            (DVec3::new(v[2], v[3], v[4]), DVec3::new(v[5], v[6], v[7]), glam::DVec2::new(v[11], v[12]), v[19] == 1.0)
        })
        .collect()
}

/// The judges' check, from the printed CL data alone: no point of the cutter (bottom,
/// corner, flank; sampled densely from R, r and the flute length) lies below the design
/// surface by more than the tolerance E, on all three examples. The mould is the exact bowl
/// z = (x² + y²)/60 over |x|, |y| ≤ 30 (depth along the normal to first order); the patch
/// and the blade by closest-point projection, feet inside the domain (every 7th row and
/// every lead-out).
#[test]
fn no_point_of_the_cutter_is_below_the_design_surface_by_more_than_e() {
    use interpolab::geom::{ParametricSurface, ProjectOptions, project_point};
    use interpolab::scene::finish::FinishScene;
    for name in ["concave-mould", "bicubic-patch", "naca-blade"] {
        let file = example(name);
        let job = FinishScene::from_json(&std::fs::read_to_string(&file).unwrap()).unwrap().job().unwrap();
        let tol = job.options.gouge_tol_mm;
        let rows = cl_rows(&file);
        let mut worst = (0.0f64, 0usize);
        if name == "concave-mould" {
            for (i, &(tip, axis, _, _)) in rows.iter().enumerate() {
                for p in cutter_points(&job.cutter, tip, axis, 120, 1.0, 0.1) {
                    if p.x.abs() > 30.0 || p.y.abs() > 30.0 {
                        continue;
                    }
                    let f = (p.x * p.x + p.y * p.y) / 60.0;
                    let depth = (f - p.z) / (1.0 + (p.x / 30.0).powi(2) + (p.y / 30.0).powi(2)).sqrt();
                    if depth > worst.0 {
                        worst = (depth, i);
                    }
                }
            }
        } else {
            let dom = job.surface.domain();
            // Every 7th row and every lead-out (the cutter moved on past the far end).
            for (i, &(tip, axis, uv, _)) in rows.iter().enumerate().filter(|(i, r)| i % 7 == 0 || r.3) {
                for p in cutter_points(&job.cutter, tip, axis, 36, 3.0, 0.5) {
                    let foot = project_point(&job.surface, p, uv, ProjectOptions::default());
                    let inside = foot.uv.x > dom.u.min
                        && foot.uv.x < dom.u.max
                        && foot.uv.y > dom.v.min
                        && foot.uv.y < dom.v.max;
                    if inside && -foot.signed_distance > worst.0 {
                        worst = (-foot.signed_distance, i);
                    }
                }
            }
        }
        eprintln!("{name}: {} rows, deepest {:.6} mm (row {}), E {tol} mm", rows.len(), worst.0, worst.1);
        assert!(worst.0 <= tol, "{name}: row {} is {} mm below the surface, E = {tol} mm", worst.1, worst.0);
    }
}

/// `finish.start` through the command line: a curve inside the patch gives paths on both
/// sides and says so in the JSON (`start.second_side_first_path`); the first path runs
/// through the curve's points; a bad start is one line on stderr, exit status 2.
#[test]
fn a_start_curve_in_the_scene_starts_the_paths_and_a_bad_one_is_refused() {
    let text = std::fs::read_to_string(example("bicubic-patch")).expect("example");
    let mut scene: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    scene["finish"]["scallop"] = serde_json::json!(0.04);
    scene["finish"]["start"] = serde_json::json!({ "curve": [[0.2, 0.5], [0.8, 0.5]] });
    let file = temp("start-curve.json", &scene.to_string());
    let o = run(&["finish", &file, "--format", "json"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let out: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON out");
    assert_eq!(out["start"]["curve"], serde_json::json!([[0.2, 0.5], [0.8, 0.5]]));
    let second = out["start"]["second_side_first_path"].as_u64().expect("a second side") as usize;
    let cols: Vec<&str> = out["columns"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    let col = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    let rows = out["rows"].as_array().unwrap();
    let at = |r: &serde_json::Value, name: &str| r[col(name)].as_f64().unwrap();
    // Path 0 is the iso-line v = 0.5 (the curve, continued to the edges u = 0 and 1).
    let first: Vec<&serde_json::Value> = rows.iter().filter(|r| r[col("path")] == 0).collect();
    assert!(first.iter().all(|r| (at(r, "v") - 0.5).abs() < 1e-12), "path 0 off the curve");
    assert_eq!((at(first[0], "u"), at(first[first.len() - 1], "u")), (0.0, 1.0));
    // The paths before the second side lie above v = 0.5, from it on below.
    let passes = out["stats"]["passes"].as_u64().unwrap() as usize;
    assert!(second > 2 && second + 2 < passes, "{second} of {passes}");
    for r in rows {
        let p = r[col("path")].as_u64().unwrap() as usize;
        let v = at(r, "v");
        assert!(p == 0 || (p < second) == (v > 0.5), "path {p} at v {v}");
    }
    // Without the key the output has no "start" (unchanged for every scene written before).
    let o = run(&["finish", &example("bicubic-patch"), "--format", "json"]);
    let out: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON out");
    assert!(out.get("start").is_none());
    scene["finish"]["start"] = serde_json::json!({ "curve": [[0.2, 1.5], [0.8, 0.5]] });
    let file = temp("start-outside.json", &scene.to_string());
    let o = run(&["finish", &file]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("finish.start.curve[0]: (0.2, 1.5) is outside the surface's domain"), "{err}");
}
