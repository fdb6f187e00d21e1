//! `interpolab simulate` and `replay` on a user's program with its tools and machine, run as a
//! user would: a CAMotics project (its tools, its workpiece, its files), a LinuxCNC tool
//! table with shapes in the remarks, the tool map, the automatic stock, the per-block
//! nonlinear error table and its exit status, one-line refusals.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

use std::path::PathBuf;
use std::process::Command;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("interpolab-userprog-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn temp(name: &str, text: &str) -> PathBuf {
    let p = dir().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn run(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_interpolab")).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// Two tools: a pocket floor with a 6 mm flat end mill, then a groove with a 90° V cutter.
const TWO_TOOLS: &str = "G21 G90 G17\nT1 M6\nG0 Z10\nG0 X5 Y5\nG1 Z-2 F500\nG1 X25\nG1 Y15\nG1 X5\nG1 Y5\nG0 Z10\n\
                         T2 M6\nG0 X2 Y22\nG1 Z-1.5 F300\nG1 X28\nG0 Z10\nM30\n";

#[test]
fn a_camotics_project_machines_its_files_with_its_tools_into_its_workpiece() {
    temp("two-tools.nc", TWO_TOOLS);
    let project = temp(
        "job.camotics",
        r#"{
  "units": "metric",
  "tools": {
    "1": {"units": "metric", "shape": "cylindrical", "length": 20, "diameter": 6, "description": "6 mm end mill"},
    "2": {"units": "imperial", "shape": "conical", "length": 0.25, "diameter": 0.5}
  },
  "workpiece": {"automatic": false, "margin": 5, "bounds": {"min": [0, 0, -6], "max": [30, 26, 0]}},
  "files": ["two-tools.nc"]
}"#,
    );
    let map = dir().join("tools.csv");
    let (code, out, err) = run(&[
        "simulate",
        "--project",
        project.to_str().unwrap(),
        "--pitch",
        "0.25",
        "--tool-map",
        map.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    assert_eq!(v["stock"]["z0_mm"], -6.0);
    assert_eq!(v["stock"]["z1_mm"], 0.0);
    assert_eq!(v["grid"]["nx"], 120);
    assert_eq!(v["grid"]["ny"], 104);
    let tools = v["tools"].as_array().unwrap();
    assert_eq!(tools.len(), 2, "{out}");
    assert_eq!(tools[0]["cutter"], "flat R 3 mm");
    // CAMotics' conical tool: an included angle of 2·atan(R / length) = 90°.
    assert!(tools[1]["cutter"].as_str().unwrap().starts_with("V R 6.35 mm, 90°"), "{}", tools[1]["cutter"]);
    let total = v["removed_volume_mm3"].as_f64().unwrap();
    let parts: f64 = tools.iter().map(|t| t["removed_volume_mm3"].as_f64().unwrap()).sum();
    assert!((total - parts).abs() < 1e-5, "{total} vs {parts}");
    // The flat end mill's pocket: a 20 × 10 mm rectangle of passes with R 3 (its inside
    // 14 × 4 mm is not cut), 2 mm deep: (26·16 − 14·4 − (4 − π)·9) mm² × 2 mm at the pitch's
    // resolution.
    let pocket = (26.0 * 16.0 - 14.0 * 4.0 - (4.0 - std::f64::consts::PI) * 9.0) * 2.0;
    let t1 = tools[0]["removed_volume_mm3"].as_f64().unwrap();
    assert!((t1 - pocket).abs() < 0.03 * pocket, "{t1} vs {pocket}");
    // The tool map: the V groove's rays (y 20.5 … 23.5) are tool 2's, the pocket's tool 1's.
    let csv = std::fs::read_to_string(&map).unwrap();
    let mut by_tool = [0usize; 3];
    for row in csv.lines().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        let y: f64 = f[3].parse().unwrap();
        match f[4] {
            "1" => {
                by_tool[1] += 1;
                assert!(y < 18.0, "{row}");
            }
            "2" => {
                by_tool[2] += 1;
                assert!((y - 22.0).abs() <= 1.5, "{row}");
            }
            "" => by_tool[0] += 1,
            other => panic!("{other}"),
        }
    }
    assert!(by_tool[1] > 4000 && by_tool[2] > 500, "{by_tool:?}");
}

#[test]
fn an_automatic_workpiece_is_the_cuts_box_as_camotics_makes_it() {
    let prog = temp("two-tools-auto.nc", TWO_TOOLS);
    let tbl = temp("auto.tbl", "T1 P1 D6 ;flat\nT2 P2 D4 ;v90\n");
    let (code, out, err) =
        run(&["simulate", prog.to_str().unwrap(), "--tools", tbl.to_str().unwrap(), "--pitch", "0.5"]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    // The feed moves' tips widened by their tool's radius: the end mill's x 5…25, y 5…15 by
    // 3 mm, the V's x 2…28 at y 22 by 2 mm: x 0…30, y 2…24, z from −2 up to the top, set at
    // z = 0 (2 mm thick: not thickened); then 5 % of the size added below and on both sides
    // in x and y.
    let (lo, hi) = ([0.0, 2.0, -2.0], [30.0, 24.0, 0.0]);
    let m = [0.05 * (hi[0] - lo[0]), 0.05 * (hi[1] - lo[1]), 0.05 * (hi[2] - lo[2])];
    assert!((v["grid"]["x0_mm"].as_f64().unwrap() - (lo[0] - m[0])).abs() < 1e-9, "{out}");
    assert!((v["grid"]["y0_mm"].as_f64().unwrap() - (lo[1] - m[1])).abs() < 1e-9, "{out}");
    assert!((v["stock"]["z0_mm"].as_f64().unwrap() - (lo[2] - m[2])).abs() < 1e-9, "{out}");
    assert_eq!(v["stock"]["z1_mm"], 0.0);
    assert!(v["stock"]["from"].as_str().unwrap().starts_with("automatic"));
    assert_eq!(v["tools"][1]["cutter"], "V R 2 mm, 90°");
}

/// Three blocks: a plain XY move, one turning C by 60° at a radius of 20 mm (a large
/// nonlinear error), one turning A by 0.1° (a small one).
const ROTARY: &str = "G21 G90 G94\nG0 X20 Y0 Z5 A0 C0\nG1 X22 F300\nG1 X20 C60\nG1 Y1 A0.1\nM30\n";

#[test]
fn replay_lists_the_blocks_over_the_tolerance_with_their_lines() {
    let prog = temp("rotary.ngc", ROTARY);
    let (code, out, err) = run(&["replay", prog.to_str().unwrap(), "--machine", "table-ac", "--tolerance", "0.01"]);
    assert_eq!(code, 1, "{out}{err}");
    let rows: Vec<&str> = out.lines().skip_while(|l| !l.trim_start().starts_with("line")).skip(1).collect();
    assert_eq!(rows.len(), 1, "{out}");
    let f: Vec<&str> = rows[0].split_whitespace().collect();
    assert_eq!(f[0], "4");
    assert_eq!(f[6], "*");
    // Line 4 turns the part 60° about C with the tip 20 → 22 mm from the axis (chord 20.0998
    // mm): the swept tip runs on the spiral r(τ) = 22 − 2τ, θ(τ) = −60°·τ in the workpiece;
    // its largest distance from the chord, searched here densely.
    let (p0, p1) = ([22.0f64, 0.0], [20.0 * (-60f64).to_radians().cos(), 20.0 * (-60f64).to_radians().sin()]);
    let mut want: f64 = 0.0;
    for k in 0..=100_000 {
        let tau = f64::from(k) / 100_000.0;
        let (r, th) = (22.0 - 2.0 * tau, (-60f64).to_radians() * tau);
        let q = [r * th.cos(), r * th.sin()];
        let d = [p1[0] - p0[0], p1[1] - p0[1]];
        let t = (((q[0] - p0[0]) * d[0] + (q[1] - p0[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
        want = want.max((q[0] - p0[0] - t * d[0]).hypot(q[1] - p0[1] - t * d[1]));
    }
    let got: f64 = f[5].parse().unwrap();
    assert!((got - want).abs() < 2e-6, "{got} vs {want}");
    assert!(out.contains(&format!("nonlinear    max {} mm at line 4", f[5])), "{out}");
    let (code, out, _) = run(&["replay", prog.to_str().unwrap(), "--machine", "table-ac", "--tolerance", "5", "--all"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("tolerance    5 mm: 0 of 2 blocks over"), "{out}");
}

#[test]
fn bad_tools_and_machines_are_refused_in_one_line() {
    let prog = temp("refuse.ngc", "G21 G90\nG0 X0 Y0 Z5\nT9 M6\nG1 Z-1 F100\nM30\n");
    let p = prog.to_str().unwrap();
    for (args, needle) in [
        (vec!["simulate", p, "--machine", "table-xy", "--cutter", "ball:1"], "--machine table-xy: not a machine"),
        (vec!["simulate", p, "--tool", "1:cone:3"], "'cone' is not a shape"),
        (vec!["simulate", p, "--tool", "1:flat:3"], "line 3: tool 9 is not in the tool table"),
        (vec!["replay", p, "--machine", "head-bc", "--tolerance=-1"], "--tolerance -1"),
    ] {
        let (code, out, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // A CAMotics spheroid has no model: the message says what to give instead.
    let proj =
        temp("sphere.camotics", r#"{"tools": {"9": {"shape": "spheroid", "diameter": 4}}, "files": ["refuse.ngc"]}"#);
    let (code, _, err) = run(&["simulate", "--project", proj.to_str().unwrap(), "--cutter", "flat:1"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("tool 9: its shape is not modelled") && err.contains("--tool 9:ball:4"), "{err}");
}
