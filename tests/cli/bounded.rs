//! Issue 11's command-line cases: each ends at once with bounded memory, and a refusal is
//! one line naming the problem (exit status 2). Timing is not asserted; the numbers are in
//! docs/bounded-work.md.
#![cfg(not(target_arch = "wasm32"))]

use std::path::PathBuf;
use std::process::{Command, Output};

fn example(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples").join(format!("{name}.json")).display().to_string()
}

fn temp_file(name: &str, bytes: &[u8]) -> String {
    let dir = std::env::temp_dir().join(format!("interpolab-bounded-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write");
    p.display().to_string()
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_interpolab")).args(args).output().expect("runs")
}

/// Exit status 2 with one line on stderr that contains every one of `words`.
fn refused(o: &Output, words: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    for w in words {
        assert!(err.contains(w), "{w:?} not in: {err}");
    }
    for bad in ["NaN", " inf", "please report"] {
        assert!(!err.contains(bad), "{bad:?} in: {err}");
    }
}

fn frw_with(edit: impl Fn(&mut serde_json::Value)) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(example("floor-round-wall")).expect("example")).expect("json");
    edit(&mut v);
    v
}

#[test]
fn an_endless_file_is_refused_at_the_size_cap() {
    if std::path::Path::new("/dev/zero").exists() {
        refused(&run(&["run", "/dev/zero"]), &["larger than 64 MiB"]);
        // A program is streamed: its first "line" is refused at 64 KiB, long before the cap.
        refused(&run(&["replay", "/dev/zero"]), &["line 1", "longer than 65536 characters"]);
        refused(
            &run(&["simulate", "/dev/zero", "--cutter", "ball:3", "--stock", "0,0,0,10,10,10"]),
            &["line 1", "longer than 65536 characters"],
        );
    }
}

#[test]
fn bad_numbers_and_bytes_in_gcode_name_their_line() {
    let nines = format!("G90 G21\nG00 X0 Y0 Z5\nG01 X{} F100\nM30\n", "9".repeat(400));
    refused(&run(&["replay", &temp_file("nines.nc", nines.as_bytes())]), &["line 3", "too large"]);
    let bad = temp_file("bad-utf8.nc", b"G90 G21\nG00 X0 Y0 Z5\nG01 X1 \xff F100\nM30\n");
    refused(&run(&["replay", &bad]), &["line 3", "not UTF-8"]);
}

#[test]
fn scene_values_that_must_not_pass() {
    let text = std::fs::read_to_string(example("floor-round-wall")).expect("example");
    let dup = text.replacen("\"radius\": 50.0,", "\"radius\": 50.0, \"radius\": 3.0,", 1);
    refused(&run(&["run", &temp_file("dup.json", dup.as_bytes())]), &["surfaces[1].radius", "twice"]);
    let far = frw_with(|v| v["path"]["start"][2] = 1e308.into()).to_string();
    refused(&run(&["run", &temp_file("far.json", far.as_bytes())]), &["path.start", "1 km"]);
    let slow = frw_with(|v| v["motion"]["feed"] = 1e-13.into()).to_string();
    let o = run(&["run", &temp_file("slow.json", slow.as_bytes())]);
    refused(&o, &["motion", "raise motion.feed"]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("lower"), "a tiny feed is not to be lowered");
}

#[test]
fn gcode_options_are_checked_before_the_work() {
    let s = example("floor-round-wall");
    refused(&run(&["gcode", &s, "--kind", "g01", "--tolerance", "0.01", "--feed", "1e-9"]), &["feed", "1500"]);
    refused(
        &run(&["gcode", &s, "--kind", "g01", "--tolerance", "0.01", "--safe-z", "NaN"]),
        &["--safe-z", "needs a finite number"],
    );
    refused(&run(&["nurbs", &s, "--tolerance", "0.01", "--period", "1e-9"]), &["periods would be needed"]);
}

#[test]
fn a_blade_whose_error_jumps_is_refused_not_crept_along() {
    // NACA 9999 and the other thick sections: the step search used to place 200 000
    // nodes a rounding step apart at the jump of δ.
    for b in ["9999", "4999", "5950"] {
        refused(&run(&["steps", "--blade", b, "--tolerance", "0.01"]), &["underflow", "at s ="]);
    }
}

#[test]
fn a_ten_kilometre_move_is_checked_with_a_coarser_stated_spacing() {
    let p = temp_file("far.nc", b"G90 G21\nG00 X0 Y0 Z5\nG01 X10000000 F1000\nM30\n");
    let o = run(&["replay", &p, "--scene", &example("floor-round-wall")]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("samples") && out.contains("mm apart"), "{out}");
    assert!(out.contains("program → design"), "{out}");
}

#[test]
fn json_output_states_the_final_period() {
    let o = run(&["run", &example("rational-nurbs-vault"), "--format", "json"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let rows = v["rows"].as_array().expect("rows");
    let (last, prev) = (&rows[rows.len() - 1], &rows[rows.len() - 2]);
    let ms = v["stop"]["final_period_ms"].as_f64().expect("final_period_ms");
    let dt = last[1].as_f64().expect("t") - prev[1].as_f64().expect("t");
    assert!((ms - dt).abs() < 1e-9 && ms > 0.0 && ms < 4.0, "{ms} vs {dt}");
    assert_eq!(v["stop"]["reason"], "left_domain");
    assert_eq!(last[5].as_f64(), Some(1.0), "u1 on its bound 1");
}

/// A numeric option given `nan`, `inf` or an overflowing number is refused while the
/// arguments are read (one line, status 2, naming the option and the text given), on every
/// command that takes numbers: no work starts and no output is written.
#[test]
fn non_finite_option_values_are_refused_before_any_work() {
    let frw = example("floor-round-wall");
    let cases: [&[&str]; 5] = [
        &[
            "simulate",
            "--benchmark",
            "three-axis:10",
            "--cutter",
            "ball:3",
            "--stock",
            "0,0,0,51.2,51.2,20",
            "--pitch",
            "nan",
        ],
        &["steps", &frw, "--tolerance", "inf"],
        &["gcode", &frw, "--tolerance", "1e999"],
        &["nurbs", &frw, "--tolerance", "NaN"],
        &["finish", &example_finish("bicubic-patch"), "--gcode-tolerance=-inf"],
    ];
    for args in cases {
        let o = run(args);
        let last = args.last().copied().unwrap_or_default();
        let (option, given) = last.split_once('=').unwrap_or((args[args.len() - 2], last));
        refused(&o, &["needs a finite number", option]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains(given), "the non-number is not repeated: {err}");
        assert!(o.stdout.is_empty(), "{args:?}: output was written");
    }
}

fn example_finish(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/finish").join(format!("{name}.json")).display().to_string()
}

/// The NACA blade with one control point mistyped far away: at 10⁶ mm the surface's area
/// alone says the paths cannot fit the CC-point cap, before any path is built; at 2·10⁵ mm
/// the pilot's lines, built and checked, say the paths would need far more CC points than the
/// cap (it ran for minutes, refusing every point, before the checks had caps; until the
/// checks bounded the surface's bend near each cell, they were what refused it).
#[test]
fn a_finishing_surface_with_a_mistyped_control_point_is_refused_early() {
    let text = std::fs::read_to_string(example_finish("naca-blade")).expect("example");
    for (x, words) in [
        (1e6, &["surfaces[0]", "area", "CC points", "mistyped control point"][..]),
        (2e5, &["would number", "CC points", "mistyped control point"][..]),
    ] {
        let mut v: serde_json::Value = serde_json::from_str(&text).expect("json");
        v["surfaces"][0]["points"][6][4][0] = serde_json::json!(x);
        let path = temp_file(&format!("blade-{x}.json"), v.to_string().as_bytes());
        refused(&run(&["finish", &path]), words);
        refused(&run(&["finish", &path, "--table"]), words);
        // With a stock of its own (the automatic one, sized from the surface, is refused
        // first: too many rays).
        refused(
            &run(&["simulate", &path, "--finish", "0.005", "--pitch", "0.5", "--stock", "-60,-60,-10,60,60,60"]),
            words,
        );
        let o = run(&["simulate", &path, "--finish", "0.005", "--pitch", "0.5"]);
        refused(&o, if x < 1e6 { &["rays, more than"][..] } else { words });
    }
}

/// A cutter wider than the whole part (a fuzz case: R = 10⁸ mm on the 100 × 80 mm patch ran
/// past 30 s; R = 1 000 mm was refused by its checks after 9 s) is refused when the scene is
/// read, by every command that finishes; a radius under the part's extent is not.
#[test]
fn a_cutter_larger_than_the_part_is_refused_when_read() {
    let text = std::fs::read_to_string(example_finish("bicubic-patch")).expect("example");
    for radius in [1e8, 1000.0] {
        let mut v: serde_json::Value = serde_json::from_str(&text).expect("json");
        v["finish"]["cutter"]["radius"] = serde_json::json!(radius);
        let path = temp_file(&format!("patch-r{radius}.json"), v.to_string().as_bytes());
        let words = &["finish.cutter.radius", "larger than the whole part", "mm corner to corner"][..];
        refused(&run(&["finish", &path]), words);
        refused(&run(&["finish", &path, "--table"]), words);
        refused(&run(&["simulate", &path, "--finish", "0.005", "--pitch", "0.5"]), words);
    }
    let mut v: serde_json::Value = serde_json::from_str(&text).expect("json");
    v["finish"]["cutter"]["radius"] = serde_json::json!(50.0);
    let path = temp_file("patch-r50.json", v.to_string().as_bytes());
    let o = run(&["finish", &path, "--format", "json"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("finish.cutter.radius"), "{err}");
    assert!(!o.stdout.is_empty(), "no CL data: {err}");
}

/// The mould's finishing program on a grid of 0.1 mm would do some 4·10⁹ units of work
/// (100 times its run at 1 mm), six times a run's cap. The job's pilot says so before the
/// paths are built: the refusal names the estimate, not moves machined.
#[test]
fn a_finishing_simulation_over_its_work_is_refused_before_its_paths() {
    let o = run(&["simulate", &example_finish("concave-mould"), "--finish", "0.005", "--pitch", "0.1"]);
    refused(&o, &["before the paths are built", "ray updates", "raise the pitch"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains(" moves"), "{err}");
}

#[test]
fn measuring_many_arcs_against_a_design_is_refused_before_the_work() {
    // 70 000 full circles weigh 1.4 million line-equivalents, over the 1.2 million cap:
    // refused in one line as it is read, at the first circle past the cap (the rapid weighs
    // 1 and each circle 20: 60 000 circles on lines 4–60 003 weigh 1 200 001, so line 60 004
    // is not read on), before any sampling; 1 000 of them are measured.
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/floor-round-wall.json");
    let circles = |n: usize| {
        let mut t = String::from("G21 G90\nG0 X0 Y0 Z1\nG1 F100\n");
        t.push_str(&"G2 X0 Y0 I5 J0\n".repeat(n));
        t.push_str("M30\n");
        t
    };
    let big = temp_file("circles.nc", circles(70_000).as_bytes());
    refused(&run(&["replay", &big, "--scene", scene]), &["line 60004:", "1200000 line-equivalents", "without --scene"]);
    let small = temp_file("few-circles.nc", circles(1_000).as_bytes());
    let o = run(&["replay", &small, "--scene", scene]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A refusal quoting user text stays one printable line: a scene key with a carriage return
/// and a NUL in it (a fuzz finding: the key was echoed raw, and a terminal or a script
/// splitting on line breaks saw two lines) is shown with a space for the line break and `_`
/// for the NUL.
#[test]
fn a_refusal_quoting_control_characters_stays_one_printable_line() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/floor-round-wall.json"))
        .expect("example");
    assert!(text.contains("\"period\""));
    let bad = text.replacen("\"period\"", "\"pe\\riod\\u0000\"", 1);
    let p = temp_file("control-key.json", bad.as_bytes());
    let o = run(&["steps", &p, "--tolerance", "0.01"]);
    refused(&o, &["pe iod_", "unknown key", "period"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.trim_end_matches('\n').chars().any(char::is_control), "{err:?}");
}

/// A machine pivot far off the part (a fuzz finding: −1e308 mm made `steps` search for two
/// seconds before refusing with an error of 2e292 mm) is refused when the scene is read,
/// naming the key.
#[test]
fn a_machine_pivot_a_kilometre_off_is_refused_with_the_scene() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/torus-plate-head-bc.json"))
        .expect("example");
    let mut scene: serde_json::Value = serde_json::from_str(&text).expect("json");
    assert!(scene["machine"]["pivots"]["b"].is_array(), "{}", scene["machine"]);
    scene["machine"]["pivots"]["b"][1] = serde_json::json!(-1e308);
    let p = temp_file("far-pivot.json", scene.to_string().as_bytes());
    refused(
        &run(&["steps", &p, "--tolerance", "0.01"]),
        &["machine.pivots.b", "more than 1000000 mm", "from the origin"],
    );
}

#[test]
fn timing_a_program_past_the_plan_cap_is_refused_at_its_line_and_periods_past_theirs_before_a_file() {
    // 1.6 million reversals: every move is a piece of its own (a reversal is a stop, not a
    // blend), so the 1 500 001st piece is the 1 499 999th move after the rapid, on line
    // 3 + 1 499 999.
    let mut text = String::from("G21 G90\nG0 X0 Y0 Z1\n");
    text.push_str("G1 F100 X1\n");
    for k in 1..1_600_000 {
        text.push_str(if k % 2 == 1 { "X2\n" } else { "X1\n" });
    }
    let p = temp_file("reversals.nc", text.as_bytes());
    refused(&run(&["time", &p]), &["line 1500002:", "more than 1500000 pieces", "split it"]);
    // A 1 km move at 1 mm/min takes 60 000 000 s: 6e10 periods of 1 ms. The line that is
    // not G-code is reported, but not before the refusal (which is one line).
    let slow = temp_file("slow.nc", b"G21 G90\nG1 F1 X1000000\nnot g-code\n");
    let csv = std::env::temp_dir().join(format!("interpolab-bounded-{}-periods.csv", std::process::id()));
    refused(
        &run(&["time", &slow, "--periods", &csv.display().to_string()]),
        &["--periods", "more than 20000000", "--period"],
    );
    assert!(!csv.exists(), "a file was written before the refusal");
    // Without --periods the same program is timed, and the line reported.
    let o = run(&["time", &slow]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("not G-code"), "{err}");
}
