//! The `interpolab run` and `check` commands as a script would use them: the output
//! contract of the scene format, exit statuses, and one-line errors on standard error.
#![cfg(not(target_arch = "wasm32"))]

use std::path::PathBuf;
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_interpolab"))
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.json"))
}

fn temp_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("interpolab-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn run_prints_the_nine_columns_one_row_per_period() {
    let path = example("floor-round-wall");
    let o = run(&["run", path.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("k,t_ms,x,y,z,u1,v1,u2,v2"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().expect("number")).collect()).collect();
    assert_eq!(rows.len(), 2829, "row 0, 2827 whole periods of one turn and the final shorter one");
    let last = rows.len() - 1;
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 9);
        assert_eq!(r[0], k as f64);
        if k < last {
            assert!((r[1] - 4.0 * k as f64).abs() < 1e-9, "t_ms = k·Ts");
        }
        // u2 is the cylinder's angle in degrees, v2 its height in mm.
        let angle = r[3].atan2(r[2]).to_degrees().rem_euclid(360.0);
        assert!((angle - r[7]).abs() < 1e-6 || (angle - r[7]).abs() > 359.99, "u2 in degrees: {} vs {angle}", r[7]);
        assert!((r[8] - 5.0).abs() < 1e-9, "v2 = contact height = R'");
    }
    assert!(stderr(&o).contains("closed on itself"), "the stop reason is reported: {}", stderr(&o));
    // The loop closes exactly on its first point, with a final period of its own duration:
    // the chord at the programmed feed (f = 0.1 mm per 4 ms).
    assert_eq!(rows[last][2..9], rows[0][2..9], "the last row is the first point");
    let chord = ((rows[last][2] - rows[last - 1][2]).powi(2)
        + (rows[last][3] - rows[last - 1][3]).powi(2)
        + (rows[last][4] - rows[last - 1][4]).powi(2))
    .sqrt();
    assert!(chord > 0.0 && chord < 0.1, "{chord}");
    assert!((rows[last][1] - rows[last - 1][1] - 4.0 * chord / 0.1).abs() < 1e-9, "final period's time");
    // The 2π·45 mm loop is covered: whole periods plus the partial one.
    let length = (last - 1) as f64 * 0.1 + chord;
    assert!((length - 2.0 * std::f64::consts::PI * 45.0).abs() < 1e-3, "{length}");
}

#[test]
fn run_with_errors_adds_measured_errors_and_estimates() {
    let path = example("crossing-cylinders");
    let o = run(&["run", path.to_str().expect("utf8"), "--errors"]);
    assert!(o.status.success());
    let text = stdout(&o);
    let header = text.lines().next().expect("header");
    assert_eq!(header, "k,t_ms,x,y,z,u1,v1,u2,v2,e1,e2,est11_1,est11_2,est12_1,est12_2,est16_1,est16_2");
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().expect("number")).collect();
        assert_eq!(v.len(), 17);
        assert!(v[9].abs() <= 0.005 && v[10].abs() <= 0.005, "within b·T: {line}");
        assert!(v[15] >= 0.0 && v[16] >= 0.0);
    }
}

#[test]
fn json_output_is_one_valid_document_with_the_stop_reason() {
    let path = example("bspline-floor-wall");
    let out = temp_file("run.json", "");
    let o = run(&["run", path.to_str().expect("utf8"), "--format", "json", "--out", out.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).is_empty(), "--out writes the file, not stdout");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("valid JSON");
    assert_eq!(v["format"], "interpolab-run/1");
    assert_eq!(v["stop"]["reason"], "reached_end");
    assert_eq!(v["columns"].as_array().expect("columns").len(), 9);
    let rows = v["rows"].as_array().expect("rows");
    assert!(rows.len() > 100);
    assert_eq!(rows[0].as_array().expect("row").len(), 9);
}

#[test]
fn a_bad_scene_exits_2_with_one_line_naming_key_and_fix() {
    let text = std::fs::read_to_string(example("floor-round-wall"))
        .expect("example")
        .replace("\"radius\": 50.0", "\"radius\": -50.0");
    let p = temp_file("bad.json", &text);
    for cmd in ["run", "check"] {
        let o = run(&[cmd, p.to_str().expect("utf8")]);
        assert_eq!(o.status.code(), Some(2), "{cmd}");
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        assert!(err.contains("surfaces[1].radius") && err.contains("must be > 0") && err.contains("give"), "{err}");
    }
    let missing = run(&["run", "/nonexistent/scene.json"]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(stderr(&missing).contains("cannot read scene file"));
}

#[test]
fn a_crease_that_cannot_be_continued_exits_2_after_writing_its_rows() {
    // Equal crossing cylinders run into tangential contact (see crease_failures.rs).
    let text = std::fs::read_to_string(example("crossing-cylinders"))
        .expect("example")
        .replace("\"radius\": 20.0", "\"radius\": 30.0")
        .replace("\"v\": [10, 80]", "\"v\": [-80, 80]")
        .replace("[25.0, 0.0, 35.0]", "[35.0, 0.0, 35.0]");
    let p = temp_file("tangential.json", &text);
    let o = run(&["run", p.to_str().expect("utf8")]);
    assert_eq!(o.status.code(), Some(2));
    let rows = stdout(&o).lines().count() - 1;
    assert!(rows > 100, "rows computed before the failure are written ({rows})");
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("period") && (err.contains("tangentially") || err.contains("lower motion.feed")), "{err}");
}

#[test]
fn check_summarises_length_periods_curvature_and_errors() {
    let path = example("floor-round-wall");
    let o = run(&["check", path.to_str().expect("utf8")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("periods      2828"), "2827 whole periods and the final one: {text}");
    // The chord polygon of the 2π·45 = 282.7433 mm loop.
    assert!(text.contains("length       282.743"), "{text}");
    assert!(text.contains("0.020000 to 0.020000 1/mm"), "cylinder's normal curvature 1/50 along the crease: {text}");
    assert_eq!(text.matches("within").count(), 2, "{text}");
    // A tolerance tighter than the paper's bound (16) is flagged with exit status 1.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("example")).expect("json");
    v["tolerance"]["t1"] = 0.00001.into();
    v["tolerance"]["t2"] = 0.00001.into();
    let p = temp_file("tight.json", &v.to_string());
    let o = run(&["check", p.to_str().expect("utf8")]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    assert!(stdout(&o).contains("EXCEEDED"));
}

#[test]
fn a_run_that_misses_path_end_says_which_path_direction_reaches_it() {
    // A straight V-groove along x from x = −40 toward x = +40; the sense of n1 × n2 is −x.
    let groove = include_str!("../data/groove-end-behind-start.json");
    let p = temp_file("groove.json", groove);
    let o = run(&["run", p.to_str().expect("utf8"), "--format", "json"]);
    assert!(o.status.success(), "stopping at a domain edge is a normal end: {}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    assert_eq!(v["stop"]["reason"], "left_domain");
    let note = v["stop"]["note"].as_str().expect("a note");
    assert!(note.contains("path.direction to [1.000, 0.000, 0.000]"), "{note}");
    assert!(stderr(&o).lines().any(|l| l.contains("note: path.end was not reached")), "{}", stderr(&o));
    let o = run(&["check", p.to_str().expect("utf8")]);
    assert!(stdout(&o).contains("note         path.end was not reached"), "{}", stdout(&o));

    let p = temp_file("groove-fixed.json", &groove.replace("\"max_steps\"", "\"direction\": [1, 0, 0], \"max_steps\""));
    let o = run(&["run", p.to_str().expect("utf8"), "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    assert_eq!(v["stop"]["reason"], "reached_end");
    assert!(v["stop"].get("note").is_none(), "{}", v["stop"]);
    assert!(!stderr(&o).contains("note:"), "{}", stderr(&o));
}

#[test]
fn a_feed_too_long_for_the_crease_is_warned_about_with_the_fix() {
    // A boss of radius 8 mm on a floor cut at 30 m/min with a 10 ms period: f = 5 mm per
    // period around a centre circle of radius 13 mm, far beyond what b·T allows.
    let scene = r#"{
      "format": "interpolab-scene/1", "name": "fast boss",
      "surfaces": [
        { "type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1], "u_axis": [1, 0, 0], "domain": { "u": [-100, 100], "v": [-100, 100] } },
        { "type": "cylinder", "origin": [0, 0, 0], "axis": [0, 0, 1], "radius": 8.0, "domain": { "u": [0, 360], "v": [0, 50] }, "normal": "outward" }
      ],
      "tool": { "radius": 5, "allowance": 0 }, "motion": { "feed": 30000, "period": 10 },
      "tolerance": { "t1": 0.01, "t2": 0.01, "share": 0.5 },
      "path": { "start": [13, 0, 5], "end": null, "max_steps": 1000 }
    }"#;
    let p = temp_file("fast-boss.json", scene);
    let o = run(&["run", p.to_str().expect("utf8"), "--errors"]);
    assert!(o.status.success(), "a warning, not an error: {}", stderr(&o));
    let warning = stderr(&o).lines().find(|l| l.contains("warning:")).map(str::to_owned).expect("a warning");
    assert!(warning.contains("surface 2") && warning.contains("lower motion.feed or motion.period"), "{warning}");
    // The warning's number is the largest |e2| of the rows (column 11 of --errors).
    let worst_e2 = stdout(&o)
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(10).expect("e2").parse::<f64>().expect("number").abs())
        .fold(0.0, f64::max);
    assert!(worst_e2 > 0.005, "{worst_e2}");
    assert!(warning.contains(&format!("{worst_e2:.3e} mm")), "{warning} vs {worst_e2:.3e}");
    // The precise mode puts every row on the crease: no warning.
    let o = run(&["run", p.to_str().expect("utf8"), "--method", "exact"]);
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
    // Nor on the examples, at the paper's feed.
    let o = run(&["run", example("crossing-cylinders").to_str().expect("utf8")]);
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}
