//! The five-axis and chord commands end to end: the joint values `interpolab steps` prints
//! are turned back into swept tool tips with the conventions of docs/fiveaxis.md, written
//! out here independently of the library, and every segment is checked against the
//! tolerance; Example 1, Table 1 and the chord commands print what they promise; bad input
//! exits with status 2 and a message.
#![cfg(not(target_arch = "wasm32"))]
#![allow(clippy::unwrap_used, reason = "tests: an error should fail the test")]

use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_interpolab");

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

fn stdout_of(args: &[&str]) -> String {
    let out = run(args);
    assert!(out.status.success(), "{args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

type V = [f64; 3];

fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: V, k: f64) -> V {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn norm(a: V) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
/// Right-hand rotations about X, Y, Z by t (rad).
fn rx(t: f64, v: V) -> V {
    let (s, c) = t.sin_cos();
    [v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]]
}
fn ry(t: f64, v: V) -> V {
    let (s, c) = t.sin_cos();
    [c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]]
}
fn rz(t: f64, v: V) -> V {
    let (s, c) = t.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]]
}

/// Rows of a `steps` CSV (comment lines skipped) as numbers by column name.
fn parse_steps(csv: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_owned).collect();
    let rows = lines.map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap_or(f64::NAN)).collect()).collect();
    (header, rows)
}

/// Signed errors (gouge +) of a ball of radius 4 centred at c in the torus-plane corner.
fn torus_plane_errors(c: V) -> [f64; 2] {
    let rho = (c[0] * c[0] + c[1] * c[1]).sqrt();
    let d_torus = ((rho - 40.0).powi(2) + c[2] * c[2]).sqrt() - 15.0;
    let n = [0.0, -0.20791169081775934, 0.9781476007338057];
    let d_plane = c[0] * n[0] + c[1] * n[1] + (c[2] - 4.0) * n[2];
    [4.0 - d_torus, 4.0 - d_plane]
}

/// Checks a `steps` CSV: at every node the printed tip equals forward kinematics of the
/// printed joints, and between nodes the swept ball stays within E (≥ 0.9 E but the last).
fn check_steps(csv: &str, tol: f64, forward: impl Fn(V, f64, f64) -> (V, V)) {
    let (h, rows) = parse_steps(csv);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (x, t, c) = (col("X"), h.len() - 16, h.len() - 15);
    let tip = col("tip_x");
    let joints = |r: &Vec<f64>| ([r[x], r[x + 1], r[x + 2]], r[t].to_radians(), r[c].to_radians());
    for r in &rows {
        let (q, a, cc) = joints(r);
        let (p, _) = forward(q, a, cc);
        let printed = [r[tip], r[tip + 1], r[tip + 2]];
        assert!(norm(add(p, scale(printed, -1.0))) < 1e-9, "printed tip {printed:?} vs forward {p:?}");
    }
    assert!(rows.len() > 10);
    for (k, w) in rows.windows(2).enumerate() {
        let (qa, aa, ca) = joints(&w[0]);
        let (qb, ab, cb) = joints(&w[1]);
        let mut worst = 0.0f64;
        for i in 0..=400 {
            let s = f64::from(i) / 400.0;
            let q = add(scale(qa, 1.0 - s), scale(qb, s));
            let (p, axis) = forward(q, aa + s * (ab - aa), ca + s * (cb - ca));
            for e in torus_plane_errors(add(p, scale(axis, 4.0))) {
                worst = worst.max(e.abs());
            }
        }
        assert!(worst <= tol * (1.0 + 1e-6), "segment {k}: {worst} > {tol}");
        if k + 2 < rows.len() {
            assert!(worst >= 0.9 * tol, "segment {k}: {worst} < 0.9·{tol}");
        }
    }
}

#[test]
fn steps_joints_recompute_to_swept_tools_within_tolerance_on_a_table_machine() {
    // Default machine (table-ac, both axes through the workpiece origin): the workpiece is
    // turned by C then A, so tip_W = Rz(−c)·Rx(−a)·(X, Y, Z) and axis_W = Rz(−c)·Rx(−a)·Z.
    let csv = stdout_of(&["steps", "examples/torus-plane.json", "--tolerance", "0.01"]);
    assert!(csv.contains("node,s,X,Y,Z,A,C,"), "{csv}");
    check_steps(&csv, 0.01, |q, a, c| (rz(-c, rx(-a, q)), rz(-c, rx(-a, [0.0, 0.0, 1.0]))));
}

#[test]
fn steps_joints_recompute_to_swept_tools_within_tolerance_on_a_head_machine() {
    // head-bc with o_B = (0, 0, 40), L = 160: axis = Rz(c)·Ry(b)·Z,
    // tip = Q + Rz(c)·o_B − L·axis.
    let csv = stdout_of(&[
        "steps",
        "examples/torus-plate-head-bc.json",
        "--tolerance",
        "0.02",
        "--method",
        "anderson-bjorck",
    ]);
    assert!(csv.contains("node,s,X,Y,Z,B,C,"), "{csv}");
    check_steps(&csv, 0.02, |q, b, c| {
        let axis = rz(c, ry(b, [0.0, 0.0, 1.0]));
        (add(add(q, rz(c, [0.0, 0.0, 40.0])), scale(axis, -160.0)), axis)
    });
}

#[test]
fn steps_json_carries_the_machine_and_a_summary() {
    let out = stdout_of(&["steps", "examples/torus-plate-head-bc.json", "--tolerance", "0.05", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["machine"]["kind"], "head-bc");
    assert_eq!(v["machine"]["tool_length"], 160.0);
    assert_eq!(v["columns"][5], "B");
    let n = v["rows"].as_array().unwrap().len();
    assert_eq!(v["summary"]["nodes"], n);
    assert!(v["summary"]["worst_mm"].as_f64().unwrap() <= 0.05);
}

#[test]
fn steps_json_adds_the_plans_time_on_the_structures_preset_at_the_scenes_feed() {
    let out = stdout_of(&["steps", "examples/torus-plate-head-bc.json", "--tolerance", "0.05", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let t = &v["time"];
    assert_eq!((t["machine"].as_str(), t["feed_along"].as_str()), (Some("head-bc"), Some("tip")), "{t}");
    // The scene's motion.feed.
    assert_eq!(t["feed_mm_per_min"], 1500.0, "{t}");
    let cycle = t["cycle_s"].as_f64().unwrap();
    let segments: Vec<f64> = t["segment_s"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert_eq!(segments.len() + 1, v["rows"].as_array().unwrap().len());
    let sum: f64 = segments.iter().sum();
    assert!((sum - cycle).abs() <= 1e-9 * cycle, "{sum} vs {cycle}");
    // At least the tip chords at F, and the rotary bound.
    let by_feed = t["tip_path_mm"].as_f64().unwrap() / (1500.0 / 60.0);
    assert!(cycle >= by_feed && cycle >= t["rotary_bound_s"].as_f64().unwrap(), "{t}");
    assert!((t["feed_s"].as_f64().unwrap() - by_feed).abs() <= 1e-9 * by_feed, "{t}");
    // --no-jerk is never slower; a bad feed or machine is refused before any work.
    let free = stdout_of(&[
        "steps",
        "examples/torus-plate-head-bc.json",
        "--tolerance",
        "0.05",
        "--format",
        "json",
        "--no-jerk",
    ]);
    let free: serde_json::Value = serde_json::from_str(&free).unwrap();
    assert!(free["time"]["cycle_s"].as_f64().unwrap() <= cycle, "{}", free["time"]);
    for (flag, value, says) in [
        ("--feed", "0", "give e.g. 1000"),
        ("--feed", "-5", "more than 0"),
        ("--machine", "lathe", "neither a preset nor a file"),
    ] {
        let arg = format!("{flag}={value}");
        let out = run(&["steps", "--example1", "--tolerance", "0.01", &arg]);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says) && err.lines().count() == 1, "{flag} {value}: {err}");
    }
}

#[test]
fn example1_times_both_plans_and_the_csv_says_the_time_in_a_comment() {
    let out = stdout_of(&["example1"]);
    let times: Vec<f64> = out
        .lines()
        .filter_map(|l| l.trim().strip_prefix("time: "))
        .map(|l| l.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    // docs/feed-planning.md: 1.0168 s before, 2.1662 s after on table-ac at 1000 mm/min.
    assert_eq!(times.len(), 2, "{out}");
    assert!((times[0] - 1.0168).abs() < 1e-4 && (times[1] - 2.1662).abs() < 1e-4, "{times:?}");
    let csv = stdout_of(&["steps", "--example1", "--tolerance", "0.01"]);
    let line = csv.lines().find(|l| l.starts_with("# time: ")).unwrap();
    assert!(line.contains("2.1662 s on table-ac at F 1000 mm/min"), "{line}");
}

#[test]
fn example1_shows_the_gouge_then_the_inserted_steps() {
    let out = stdout_of(&["example1"]);
    assert!(out.contains("Before: one block P1 -> P2"), "{out}");
    let total = out.lines().find(|l| l.contains("total error δ = δt + δn")).unwrap();
    let gouge: f64 = total.split_whitespace().rev().nth(2).unwrap().parse().unwrap();
    assert!(gouge > 1.0, "{total}");
    let after = out.lines().find(|l| l.starts_with("After:")).unwrap();
    assert!(after.contains("inserts"), "{after}");
    let worst: f64 = out
        .lines()
        .find(|l| l.contains("worst |δ| after"))
        .unwrap()
        .split_whitespace()
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    assert!((0.009..=0.01).contains(&worst), "{worst}");
}

#[test]
fn table1_prints_iterations_and_times_for_every_method() {
    let out = stdout_of(&["table1", "--tolerances", "0.1,0.001", "--repeat", "1"]);
    let iterations = |name: &str| -> Vec<u64> {
        let row = out.lines().find(|l| l.starts_with(&format!("| {name}"))).unwrap();
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        vec![cells[2].parse().unwrap(), cells[5].parse().unwrap()]
    };
    let (b, g, s, a) =
        (iterations("bisection"), iterations("golden"), iterations("secant"), iterations("anderson-bjorck"));
    assert!(s[1] < g[1] && g[1] < b[1], "at 0.001 mm: bisection {b:?}, golden {g:?}, secant {s:?}");
    assert!(a[1] < s[1]);
    assert!(out.contains("NACA 2412"));
}

#[test]
fn chords_on_the_parabola_and_the_comparison_table() {
    let csv = stdout_of(&["chords", "--curve", "parabola", "--tolerance", "0.05"]);
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).skip(1).collect();
    assert_eq!(rows.len(), 18, "{csv}");
    let table = stdout_of(&["chords", "--table"]);
    for name in ["parabola", "hyperbola", "ellipse"] {
        assert!(table.contains(name), "{table}");
    }
    assert!(table.contains("| 0.05 | equal-error | 18 |"), "{table}");
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let cases: [(&[&str], &str); 5] = [
        (&["steps", "examples/torus-plane.json", "--tolerance", "0"], "tolerance"),
        (&["steps", "no-such-scene.json", "--tolerance", "0.01"], "cannot read"),
        (&["steps", "--blade", "12", "--tolerance", "0.01"], "NACA"),
        (&["chords", "--curve", "ellipse", "--tolerance", "0"], "tolerance"),
        (&["table1", "--tolerances", "0.1,-1", "--repeat", "1"], "tolerances"),
    ];
    for (args, needle) in cases {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // A machine whose A axis cannot reach the bisector: the error names the axis.
    let mut scene: serde_json::Value = serde_json::from_str(include_str!("../../examples/torus-plane.json")).unwrap();
    scene["machine"] = serde_json::json!({ "kind": "table-ac", "limits": { "a": [-10, 10] } });
    let path = std::env::temp_dir().join(format!("interpolab-out-of-travel-{}.json", std::process::id()));
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = run(&["steps", path.to_str().unwrap(), "--tolerance", "0.01"]);
    let _ = std::fs::remove_file(&path);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("outside its travel") && err.contains("A ="), "{err}");
}

#[test]
fn bound_tip_adds_the_tip_column_and_keeps_every_error_within_e() {
    let tol = 0.01;
    let plain = stdout_of(&["steps", "examples/torus-plane.json", "--tolerance", "0.01"]);
    let csv = stdout_of(&["steps", "examples/torus-plane.json", "--tolerance", "0.01", "--bound-tip"]);
    let (h, rows) = parse_steps(&csv);
    assert_eq!(h.last().map(String::as_str), Some("tip_design_mm"), "{h:?}");
    assert!(rows.len() > parse_steps(&plain).1.len(), "bounding the tip needs more nodes");
    assert!(
        csv.lines().filter(|l| l.ends_with(",tip") || l.contains(",tip,")).count() > 10,
        "segments ended by the tip"
    );
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (x, a, c, tip) = (col("X"), col("A"), col("C"), col("tip_design_mm"));
    for (k, w) in rows.windows(2).enumerate() {
        assert!(w[1][tip] <= tol * (1.0 + 1e-9), "segment {k}: tip {} mm from the design tip path", w[1][tip]);
        // The swept ball, recomputed from the printed joints (table-ac through the origin).
        let mut worst = 0.0f64;
        for i in 0..=200 {
            let s = f64::from(i) / 200.0;
            let q =
                add(scale([w[0][x], w[0][x + 1], w[0][x + 2]], 1.0 - s), scale([w[1][x], w[1][x + 1], w[1][x + 2]], s));
            let (ta, tc) =
                ((w[0][a] + s * (w[1][a] - w[0][a])).to_radians(), (w[0][c] + s * (w[1][c] - w[0][c])).to_radians());
            let (p, axis) = (rz(-tc, rx(-ta, q)), rz(-tc, rx(-ta, [0.0, 0.0, 1.0])));
            for e in torus_plane_errors(add(p, scale(axis, 4.0))) {
                worst = worst.max(e.abs());
            }
        }
        assert!(worst <= tol * (1.0 + 1e-6), "segment {k}: ball error {worst} > {tol}");
    }
}
