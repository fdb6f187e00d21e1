//! `interpolab simulate` run as a user would: its CSV height map against an independent
//! Z-map of the same program (a dense brute force over ball positions), its statistics, PNG,
//! and one-line refusals.
#![cfg(not(target_arch = "wasm32"))]
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_interpolab"))
}

fn temp(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("interpolab-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn run(args: &[&str]) -> (i32, String, String) {
    let o = bin().args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn the_height_map_matches_an_independent_z_map() {
    // Two ball passes 1.2 mm apart at z = 4, a sloped move, a full G03 circle at z = 3.
    let prog = "G21 G90 G17\nG00 X-4 Y4 Z15\nG01 Z4 F600\nG01 X16\nG01 Y5.2\nG01 X-4\nG01 X16 Y12 Z6\n\
                G00 Z15\nG00 X14 Y9\nG01 Z3\nG03 X14 Y9 I-4 J0\nG00 Z15\nM30\n";
    let p = temp("zmap.nc", prog);
    let out = p.with_extension("csv");
    let png = p.with_extension("png");
    let pitch = 0.1;
    let (code, stdout, stderr) = run(&[
        "simulate",
        p.to_str().unwrap(),
        "--cutter",
        "ball:1.5",
        "--stock",
        "0,0,0,16,14,8",
        "--pitch",
        "0.1",
        "--design-z",
        "4",
        "--out",
        out.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let summary: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(summary["grid"]["nx"], 160);
    assert_eq!(summary["grid"]["ny"], 140);
    assert_eq!(summary["rapid_cuts"], 0);
    let png_bytes = std::fs::read(&png).unwrap();
    assert_eq!(&png_bytes[1..4], b"PNG");
    // Independent Z-map: ball tips densely along each cutting move (arc by angle).
    let r = 1.5f64;
    let mut tips: Vec<[f64; 3]> = Vec::new();
    let mut seg = |a: [f64; 3], b: [f64; 3]| {
        for k in 0..=4000 {
            let t = f64::from(k) / 4000.0;
            tips.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])]);
        }
    };
    seg([-4.0, 4.0, 15.0], [-4.0, 4.0, 4.0]);
    seg([-4.0, 4.0, 4.0], [16.0, 4.0, 4.0]);
    seg([16.0, 4.0, 4.0], [16.0, 5.2, 4.0]);
    seg([16.0, 5.2, 4.0], [-4.0, 5.2, 4.0]);
    seg([-4.0, 5.2, 4.0], [16.0, 12.0, 6.0]);
    seg([14.0, 9.0, 15.0], [14.0, 9.0, 3.0]);
    for k in 0..=20_000 {
        let th = std::f64::consts::TAU * f64::from(k) / 20_000.0;
        tips.push([10.0 + 4.0 * th.cos(), 9.0 + 4.0 * th.sin(), 3.0]);
    }
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), "i,j,x_mm,y_mm,top_mm,machined,deviation_mm");
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(str::to_owned).collect()).collect();
    assert_eq!(rows.len(), 160 * 140);
    let mut worst: f64 = 0.0;
    for row in rows.iter().step_by(7) {
        let (x, y, top): (f64, f64, f64) = (row[2].parse().unwrap(), row[3].parse().unwrap(), row[4].parse().unwrap());
        let mut z = 8.0f64;
        let mut d_of_z = f64::INFINITY;
        let mut wall_near = false;
        for t in &tips {
            let d = ((x - t[0]).powi(2) + (y - t[1]).powi(2)).sqrt();
            // A groove wall within the stock passes near this ray.
            wall_near |= (d - r).abs() < 0.05 && t[2] + r < 8.0;
            if d <= r && t[2] + r - (r * r - d * d).sqrt() < z {
                z = t[2] + r - (r * r - d * d).sqrt();
                d_of_z = d;
            }
        }
        // Compare off the groove walls (where the chords' lateral error, ≤ pitch/10, turns
        // into any vertical difference up to the wall's height): the lowest position is well
        // inside the cutter (slope below 2.1:1) or the ray is not cut at all.
        if !wall_near && (d_of_z < 0.9 * r || d_of_z.is_infinite()) {
            worst = worst.max((top - z).abs());
        }
        if !row[6].is_empty() {
            let dev: f64 = row[6].parse().unwrap();
            assert!((dev - (top - 4.0)).abs() < 2e-6, "{row:?}");
        }
    }
    // Documented error: chord tolerance pitch/10 for the arc (× the slope, ≤ 2.1 here), the
    // brute force's sample spacing ≤ 5 µm, output rounding 1 nm.
    assert!(worst < 2.1 * pitch / 10.0 + 0.005, "worst {worst}");
    // The circle at z = 3 gouges the z = 4 design by 1 mm.
    assert!((summary["gouge"]["worst_um"].as_f64().unwrap() + 1000.0).abs() < 1e-3, "{summary}");
}

#[test]
fn refusals_are_one_line_messages() {
    let p = temp("bad.nc", "G21 G90\nG01 X1 Y1 Z1 F100\nG41 D1\nG01 X2\n");
    let base = ["simulate", p.to_str().unwrap(), "--stock", "0,0,0,10,10,10"];
    let (code, _, err) = run(&[&base[..], &["--cutter", "cone:3"]].concat());
    assert_eq!(code, 2);
    assert!(err.contains("ball:R, flat:R or fillet:R,r") && err.lines().count() == 1, "{err}");
    let (code, _, err) = run(&[&base[..], &["--cutter", "fillet:3,4"]].concat());
    assert_eq!(code, 2);
    assert!(err.contains("corner radius"), "{err}");
    let (code, _, err) = run(&[&base[..], &["--cutter", "ball:3", "--pitch", "0.0005"]].concat());
    assert_eq!(code, 2);
    assert!(err.contains("raise the pitch"), "{err}");
    let (code, _, err) = run(&["simulate", p.to_str().unwrap(), "--stock", "0,0,0,10,10", "--cutter", "ball:3"]);
    assert_eq!(code, 2);
    assert!(err.contains("6 comma-separated"), "{err}");
    // Unsupported words are named by line, and the run goes on.
    let (code, out, err) = run(&[&base[..], &["--cutter", "ball:3"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("line 3: G41"), "{err}");
    assert!(out.contains("\"moves\""));
}

#[test]
fn five_axis_steps_of_a_scene_gouge_no_deeper_than_their_tolerance() {
    // The seed-002 steps at E = 0.01 mm hold every segment's swept ball within E of the
    // surfaces; the simulated cut (joints linear on the head B/C machine, sampled at least
    // every pitch) must then not go below the scene's surfaces by more than E.
    let scene = format!("{}/examples/torus-plate-head-bc.json", env!("CARGO_MANIFEST_DIR"));
    let (code, out, err) = run(&[
        "simulate",
        &scene,
        "--steps",
        "0.01",
        "--cutter",
        "ball:4",
        "--stock",
        "-70,-70,-20,70,70,12",
        "--pitch",
        "0.5",
    ]);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(s["design"], "scene surfaces");
    assert!(s["moves"].as_u64().unwrap() > 100, "{s}");
    // Numbers as every command prints them (shortest round trip, no `.0`), lengths to 1e-6 mm.
    assert!(out.contains("\"x0_mm\": -70,") && out.contains("\"pitch_mm\": 0.5,"), "{out}");
    assert!(!out.contains(".0,") && !out.contains(".0\n") && !out.contains("0000000"), "{out}");
    // The ball's 5-axis moves are cut in swept segments within half a pitch.
    assert_eq!(s["sweep_tol_mm"], 0.25);
    assert!(s["sweep_sagitta_mm"].as_f64().unwrap() < 0.25 * 3.0 / 8.0, "{s}");
    let worst = s["gouge"]["worst_um"].as_f64().unwrap_or(0.0);
    assert!(worst >= -10.0 - 1e-3, "worst gouge {worst} µm deeper than the 10 µm tolerance");
    assert!(s["removed_volume_mm3"].as_f64().unwrap() > 1000.0);
}

#[test]
fn the_crease_programs_of_a_scene_gouge_no_deeper_than_their_tolerance() {
    // `interpolab gcode` writes ball-centre programs of the floor/round-wall crease within
    // E = 0.01 mm (G01, arcs, G06.2); simulated with the scene's ball into a block, none may
    // cut below the floor or into the wall by more than E (the Z rays see the floor).
    let scene = format!("{}/examples/floor-round-wall.json", env!("CARGO_MANIFEST_DIR"));
    for kind in ["g01", "arcs", "nurbs"] {
        let (code, program, err) = run(&["gcode", &scene, "--kind", kind, "--tolerance", "0.01"]);
        assert_eq!(code, 0, "{err}");
        let p = temp(&format!("frw-{kind}.nc"), &program);
        let (code, out, err) = run(&[
            "simulate",
            p.to_str().unwrap(),
            "--cutter",
            "ball:5",
            "--stock",
            "-52,-52,-2,52,52,8",
            "--pitch",
            "0.2",
            "--scene",
            &scene,
        ]);
        assert_eq!(code, 0, "{kind}: {err}");
        let s: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(s["programmed_point"], "ball centre", "{kind}");
        assert!(s["chord_error_mm"].as_f64().unwrap() <= 0.02 + 1e-12, "{kind}: {s}");
        let worst = s["gouge"]["worst_um"].as_f64().unwrap_or(0.0);
        assert!(worst >= -10.0, "{kind}: gouge {worst} µm");
        // The programs rapid down to the cutting depth inside the block: a rapid crash, on
        // stderr and in the JSON, with the line it happens on.
        assert!(s["rapid_cuts"].as_u64().unwrap() >= 1, "{kind}: {s}");
        assert!(s["crashes"]["by_kind"]["rapid"].as_u64().unwrap() >= 1, "{kind}: {s}");
        assert!(s["crashes"]["first"]["line"].as_u64().unwrap() >= 1, "{kind}: {s}");
        assert!(err.contains("crash(es)") && err.contains("rapid (G0)"), "{kind}: {err}");
        // The floor ring the ball's bottom sweeps is machined to z = 0 (radius 45 around Z).
        assert!(s["machined_rays"].as_u64().unwrap() > 10_000, "{kind}");
    }
}

/// A small finishing scene (seed 001): a convex cylinder patch of radius 40 mm, about 7 × 6 mm,
/// a fillet-end mill R 3, r 1 mm, scallop h = 10 µm, chord tolerance E = 0.5 µm, paths along u.
const SMALL_FINISH: &str = r#"{"format":"interpolab-scene/1","name":"small convex cylinder","surfaces":[{"type":"cylinder","origin":[0,0,-40],"axis":[0,1,0],"radius":40,"domain":{"u":[265,275],"v":[0,6]},"normal":"outward"}],
"finish":{"cutter":{"radius":3,"corner_radius":1},"scallop":0.01,"tolerance":0.0005,"direction":"u"}}"#;

/// A finishing program whose run, at the pitch asked, would pass what the command has left
/// (its meter stops it a twentieth of the way in) is simulated on a coarser grid of the same
/// stock instead, said in one line and in the JSON (`pitch_asked_mm`), not refused after
/// its paths and planning.
#[test]
fn a_finishing_run_too_fine_for_the_work_left_runs_on_a_coarser_grid() {
    let scene = temp("small-finish-fine.json", SMALL_FINISH);
    let asked = 0.015;
    let (code, out, err) = run(&[
        "simulate",
        scene.to_str().unwrap(),
        "--finish",
        "0.001",
        "--pitch",
        &asked.to_string(),
        "--sample-step",
        "0.05",
    ]);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value = serde_json::from_str(&out).unwrap();
    let pitch = s["grid"]["pitch_mm"].as_f64().unwrap();
    assert_eq!(s["pitch_asked_mm"].as_f64(), Some(asked), "{s}");
    assert!(pitch > asked && pitch < 0.1, "{s}");
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("simulated at pitch")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains(&format!("at pitch {asked} mm the run would take about"))
            && lines[0].contains(&format!("simulated at pitch {pitch} mm instead")),
        "{err}"
    );
    // The coarser run machined the whole program on the same stock block.
    assert!(s["removed_volume_mm3"].as_f64().unwrap() > 10.0, "{s}");
    let x0 = -40.0 * 5f64.to_radians().sin() - 3.0 - 2.0;
    assert!((s["grid"]["x0_mm"].as_f64().unwrap() - x0).abs() < 1e-3, "{s}");
    // At a pitch that fits, no such line and no such key.
    let (code, out, err) = run(&["simulate", scene.to_str().unwrap(), "--finish", "0.001", "--pitch", "0.1"]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("simulated at pitch"), "{err}");
    assert!(!out.contains("pitch_asked_mm"), "{out}");
}

#[test]
fn a_finishing_program_leaves_its_scallop_and_no_gouge_beyond_its_tolerances() {
    // The five-axis program `finish --gcode` writes for the scene (steps within 1 µm, joints
    // linear on the default table A/C), machined with the fillet cutter and measured against
    // the cylinder itself: the scallop between passes is the finish's h, and nothing is cut
    // below the surface by more than the tolerances.
    let scene = temp("small-finish.json", SMALL_FINISH);
    let csv = scene.with_extension("csv");
    let (h_mm, chord_mm, step_mm, pitch_mm, sample_mm, corner_mm) = (0.01, 0.0005, 0.001, 0.1, 0.05, 1.0);
    let (code, out, err) = run(&[
        "simulate",
        scene.to_str().unwrap(),
        "--finish",
        &step_mm.to_string(),
        "--pitch",
        &pitch_mm.to_string(),
        "--sample-step",
        &sample_mm.to_string(),
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(s["design"], "finish surface", "{s}");
    assert_eq!(s["cutter"], "fillet R 3 mm, r 1 mm", "{s}");
    assert!(s["finish"]["passes"].as_u64().unwrap() >= 3, "{s}");
    assert_eq!(s["finish"]["label"], "matched, iso-scallop", "{s}");
    assert_eq!(s["finish"]["pose_step_mm"].as_f64(), Some(sample_mm), "--sample-step is the step used: {s}");
    assert!(s["removed_volume_mm3"].as_f64().unwrap() > 10.0, "{s}");
    // The default stock: the part's box widened by R + 2 mm in x and y. The patch spans
    // x = ±40·sin 5°, y = 0 … 6.
    let x0 = -40.0 * 5f64.to_radians().sin() - 3.0 - 2.0;
    assert!((s["grid"]["x0_mm"].as_f64().unwrap() - x0).abs() < 1e-3, "{s}");
    assert!((s["grid"]["y0_mm"].as_f64().unwrap() + 5.0).abs() < 1e-9, "{s}");
    // Every ray with a deviation lies over the patch (none beside it).
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut dev = Vec::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[6].is_empty() {
            continue;
        }
        let (x, y, d): (f64, f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap(), f[6].parse().unwrap());
        assert!(x.abs() <= 40.0 * 5f64.to_radians().sin() + 1e-6 && (-1e-6..=6.0 + 1e-6).contains(&y), "({x}, {y})");
        // The deviation is the distance from the cylinder, recomputed in closed form.
        let top: f64 = f[4].parse().unwrap();
        let closed = (x * x + (top + 40.0).powi(2)).sqrt() - 40.0;
        assert!((d - closed).abs() < 1e-6, "({x}, {y}): {d} against the closed form {closed}");
        dev.push((x, y, d));
    }
    assert!(dev.len() > 3000, "{} rays over the part", dev.len());
    // Interior: 1 mm from the ends of the passes, half a millimetre from the first and last.
    let half = 40.0 * 5f64.to_radians().sin();
    let inner: Vec<f64> =
        dev.iter().filter(|(x, y, _)| x.abs() < half - 1.0 && *y > 0.5 && *y < 5.5).map(|(_, _, d)| *d).collect();
    let max = inner.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = inner.iter().copied().fold(f64::INFINITY, f64::min);
    // Upper bound: the paths' own scallop (within 5 % of h by brute force, docs/fillet.md),
    // the steps' tolerance (the tip between blocks), the chord tolerance of the CC nodes, and
    // the cusp between two sampled poses along the feed, s²/(8r) (the corner's curvature).
    let upper = 1.05 * h_mm + step_mm + chord_mm + sample_mm * sample_mm / (8.0 * corner_mm);
    // Lower bound: a crest read at a ray up to half a pitch from it (the profile falls by
    // about Δκ·(w/2)·(p/2) there, 1.2 µm here) — 0.85 h.
    assert!(max <= upper && max >= 0.85 * h_mm, "interior scallop max {max} mm, h {h_mm} mm, bound {upper} mm");
    // No gouge beyond the tolerances the program was written to (steps and chords).
    assert!(min >= -(step_mm + chord_mm), "interior deviation min {min} mm");
    let worst = s["gouge"]["worst_um"].as_f64().unwrap_or(0.0);
    assert!(worst >= -(step_mm + chord_mm) * 1e3, "worst gouge {worst} µm: {s}");
    // The JSON's interior band (the core's, from the passes' contact points) is this
    // test's band here (the passes run along x over the whole patch, the first at y = 0,
    // the last at y = 6): the same rays, the same largest scallop (µm to 1e-3).
    let band = &s["interior"];
    assert_eq!((band["end_mm"].as_f64(), band["side_mm"].as_f64()), (Some(1.0), Some(0.5)), "{band}");
    let inner_pos = inner.iter().filter(|d| **d >= 0.0).count();
    let rays = band["scallop_um"]["rays"].as_u64().unwrap() as f64;
    assert!((rays - inner_pos as f64).abs() <= 0.05 * inner_pos as f64, "{band}: {inner_pos} rays here");
    let band_max = band["scallop_um"]["max"].as_f64().unwrap() * 1e-3;
    assert!(band_max <= upper && band_max >= 0.85 * h_mm, "interior band max {band_max} mm: {band}");
    assert!(
        band_max < s["scallop_um"]["max"].as_f64().unwrap() * 1e-3
            || s["scallop_um"]["max"] == band["scallop_um"]["max"],
        "{s}"
    );
}

/// Without `--sample-step` a finishing program's fillet poses are at most √(2·r·h) apart
/// (cusps s²/(8r) ≤ h/4) when that is finer than the pitch, and one pitch apart otherwise.
#[test]
fn a_finishing_program_samples_its_poses_from_its_scallop_height() {
    let scene = temp("small-finish-step.json", SMALL_FINISH);
    let (h_mm, corner_mm) = (0.01_f64, 1.0_f64);
    let step = |pitch: &str| {
        let (code, out, err) = run(&["simulate", scene.to_str().unwrap(), "--finish", "0.001", "--pitch", pitch]);
        assert_eq!(code, 0, "{err}");
        let s: serde_json::Value = serde_json::from_str(&out).unwrap();
        s["finish"]["pose_step_mm"].as_f64()
    };
    let want = (2.0 * corner_mm * h_mm).sqrt();
    let got = step("0.5").expect("a pose step below the pitch");
    assert!((got - want).abs() < 1e-12, "pose step {got} mm, want √(2·r·h) = {want} mm");
    assert_eq!(step("0.125"), None, "a pitch finer than √(2·r·h) is the step itself");
}

#[test]
fn finish_refusals_are_one_line_messages() {
    let scene = temp("small-finish-refusals.json", SMALL_FINISH);
    let p = scene.to_str().unwrap();
    for (args, want) in [
        (vec!["simulate", p, "--finish", "0"], "step tolerance must be a positive length"),
        (vec!["simulate", p, "--finish", "0.01", "--sample-step=-1"], "--sample-step -1"),
        (vec!["simulate", p, "--finish", "0.01", "--margin=-3"], "--margin -3"),
        (vec!["simulate", p], "--cutter is required"),
        (vec!["simulate", p, "--cutter", "ball:3"], "--stock is required"),
    ] {
        let (code, _, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

#[test]
fn crashes_are_listed_by_line_with_the_tool_body_from_the_cutter_or_a_tool_table() {
    // A flat 6 mm tool with 10 mm flutes: line 6 drags the shank 5 mm deep through the
    // block (15 mm below the top), line 9 rapids 2 mm into it; the same through a LinuxCNC
    // table whose remark gives the body.
    let prog = "G21 G90\nT1 M6 G0 Z5\nG0 X20 Y20\nG1 Z-8 F100\nG1 Z-15\nG1 X30\nG0 Z5\nG0 X5 Y5\nG0 Z-2\nG0 Z5\nM2\n";
    let p = temp("crash.nc", prog);
    let csv = p.with_extension("csv");
    let table = temp("crash.tbl", "T1 P1 D6 Z0 ;flat flute=10 shank=3:20 holder=10:40\n");
    let runs = [vec!["--cutter", "flat:3,flute=10,shank=3:20,holder=10:40"], vec!["--tools", table.to_str().unwrap()]];
    for extra in runs {
        let mut args = vec!["simulate", p.to_str().unwrap(), "--stock", "0,0,-30,40,40,0", "--pitch", "0.25"];
        args.extend(extra.iter().copied());
        args.extend(["--crashes", csv.to_str().unwrap()]);
        let (code, out, err) = run(&args);
        assert_eq!(code, 0, "{err}");
        let s: serde_json::Value = serde_json::from_str(&out).unwrap();
        let c = &s["crashes"];
        assert_eq!(c["first"]["line"], 6, "{c}");
        assert_eq!(c["first"]["kind"], "shank");
        assert!((c["first"]["depth_mm"].as_f64().unwrap() - 5.0).abs() < 1e-6, "{c}");
        assert!(c["by_kind"]["rapid"].as_u64().unwrap() >= 1 && c["by_kind"]["holder"] == 0, "{c}");
        assert_eq!(err.lines().filter(|l| l.contains("crash(es)")).count(), 1, "one summary line: {err}");
        assert!(err.contains("the first at line 6: the shank 5.000 mm"), "{err}");
        let text = std::fs::read_to_string(&csv).unwrap();
        let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len() as u64, c["total"].as_u64().unwrap());
        assert_eq!((rows[0][0], rows[0][1]), ("6", "shank"));
        let rapid = rows.iter().find(|r| r[0] == "9").unwrap();
        assert_eq!(rapid[1], "rapid");
        assert!((rapid[4].parse::<f64>().unwrap() - 2.0).abs() < 1e-6, "{rapid:?}");
        assert!(s.to_string().contains("flutes 10 mm, shank R 3 × 20 mm, holder R 10 × 40 mm"), "{s}");
    }
    // Without lengths the body is the default, said to be assumed; a bad word is refused.
    let (code, out, _) = run(&["simulate", p.to_str().unwrap(), "--stock", "0,0,-30,40,40,0", "--cutter", "flat:3"]);
    assert_eq!(code, 0);
    assert!(out.contains("assumed"), "{out}");
    let (code, _, err) =
        run(&["simulate", p.to_str().unwrap(), "--stock", "0,0,-30,40,40,0", "--cutter", "flat:3,shank=3"]);
    assert_ne!(code, 0);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("radius:length"), "{err}");
}

#[test]
fn the_command_line_and_the_app_s_job_simulate_a_program_of_every_dialect_alike() {
    // One pipeline (`simulate::pipeline`): the same program text read in the dialect guessed
    // from its head, its points moved to the tip, chorded at a tenth of the pitch, machined
    // and measured — by `interpolab simulate` from a file and by the app's job
    // (`jobs::simulate_run`) from the text it is handed. Their height maps and measures are
    // the same, byte for byte in the CSV.
    use interpolab::gcode::Dialect;
    use interpolab::geom::Cutter;
    use interpolab::jobs::simulate_run::SimulateRun;
    use interpolab::jobs::simulate_run::request::{DesignSpec, ProgramSource, Request};
    use interpolab::jobs::{JobKind, NoProgress};
    use interpolab::simulate::heights_csv;
    use interpolab::simulate::pipeline::guess_dialect;

    let scene = format!("{}/examples/floor-round-wall.json", env!("CARGO_MANIFEST_DIR"));
    let scene_text = std::fs::read_to_string(&scene).unwrap();
    let hand = format!("{}/tests/data/gcode/hand_written/program.nc", env!("CARGO_MANIFEST_DIR"));
    let mut programs = vec![("hand-written".to_owned(), std::fs::read_to_string(&hand).unwrap(), false)];
    for d in Dialect::ALL {
        for kind in ["g01", "arcs", "nurbs"] {
            let (code, program, err) =
                run(&["gcode", &scene, "--kind", kind, "--tolerance", "0.01", "--dialect", d.as_str()]);
            assert_eq!(code, 0, "{d:?} {kind}: {err}");
            assert_eq!(guess_dialect(program.as_bytes()), d, "{kind}: the header names the dialect");
            programs.push((format!("{}-{kind}", d.as_str()), program, true));
        }
    }
    let (cutter, stock, pitch) = ("ball:5", [-52.0, -52.0, -2.0, 52.0, 52.0, 8.0], 0.4);
    for (name, text, with_design) in programs {
        let p = temp(&format!("alike-{name}.nc"), &text);
        let csv = p.with_extension("csv");
        let stock_arg = stock.map(|x: f64| x.to_string()).join(",");
        let mut args = vec![
            "simulate",
            p.to_str().unwrap(),
            "--cutter",
            cutter,
            "--stock",
            &stock_arg,
            "--pitch",
            "0.4",
            "--out",
            csv.to_str().unwrap(),
        ];
        if with_design {
            args.extend(["--scene", &scene]);
        }
        let (code, out, err) = run(&args);
        assert_eq!(code, 0, "{name}: {err}");
        let s: serde_json::Value = serde_json::from_str(&out).unwrap();
        let req = Request {
            source: ProgramSource::Text { name: name.clone(), text },
            cutter: Cutter::ball(5.0).unwrap(),
            pitch_mm: Some(pitch),
            stock_mm: Some(stock),
            margin_mm: 0.0,
            max_sample_step_mm: None,
            design: if with_design { DesignSpec::Scene(scene_text.clone()) } else { DesignSpec::None },
            target: None,
            keyframes: 0,
            resume: false,
        };
        let f = SimulateRun::run(&req, &mut NoProgress).unwrap();
        let job_csv = heights_csv(&f.map, with_design.then_some(&f.stats));
        assert!(job_csv == std::fs::read_to_string(&csv).unwrap(), "{name}: the height maps differ");
        assert_eq!(s["moves"].as_u64().unwrap(), f.counters.moves as u64, "{name}");
        assert_eq!(s["ray_updates"].as_u64().unwrap(), f.counters.ray_updates, "{name}");
        assert_eq!(s["removed_volume_mm3"].as_f64().unwrap(), (f.counters.removed_mm3 * 1e6).round() / 1e6, "{name}");
        assert_eq!(s["machined_rays"].as_u64().unwrap(), f.stats.machined_rays as u64, "{name}");
        assert_eq!(s["rapid_cuts"].as_u64().unwrap(), f.counters.rapid_cuts as u64, "{name}");
        assert_eq!(s["design"], if with_design { "scene surfaces" } else { "none" }, "{name}");
        if with_design {
            assert_eq!(s["programmed_point"], "ball centre", "{name}");
            let um = |mm: f64| (mm * 1e6).round() / 1e3;
            assert_eq!(s["scallop_um"]["rays"].as_u64().unwrap(), f.stats.scallop.count as u64, "{name}");
            assert_eq!(s["scallop_um"]["max"].as_f64().unwrap(), um(f.stats.scallop.max_mm), "{name}");
            assert_eq!(s["scallop_um"]["p95"].as_f64().unwrap(), um(f.stats.scallop.p95_mm), "{name}");
            assert!(f.stats.machined_rays > 10_000, "{name}: the floor ring is machined");
        }
    }
}
