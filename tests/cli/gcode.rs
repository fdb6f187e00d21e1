//! The `gcode`, `replay`, `compare` and `nurbs` commands, run as a user would.
#![cfg(not(target_arch = "wasm32"))]
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

use std::path::PathBuf;
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_interpolab"))
}

fn example(name: &str) -> String {
    format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("interpolab-gcode-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

fn run(cmd: &mut Command) -> (i32, String, String) {
    let Output { status, stdout, stderr } = cmd.output().expect("the binary runs");
    (
        status.code().unwrap_or(-1),
        String::from_utf8_lossy(&stdout).into_owned(),
        String::from_utf8_lossy(&stderr).into_owned(),
    )
}

#[test]
fn written_programs_replay_within_their_tolerance() {
    for kind in ["g01", "arcs", "nurbs"] {
        let out = tmp(&format!("vault-{kind}.nc"));
        let (code, _, err) = run(bin()
            .args(["gcode", &example("rational-nurbs-vault.json"), "--kind", kind, "--tolerance", "0.01", "--out"])
            .arg(&out));
        assert_eq!(code, 0, "{kind}: {err}");
        assert!(err.contains("max deviation"), "{err}");
        let (code, text, err) = run(bin().arg("replay").arg(&out).args([
            "--scene",
            &example("rational-nurbs-vault.json"),
            "--tolerance",
            "0.01",
        ]));
        assert_eq!(code, 0, "{kind}: {text}{err}");
        assert!(text.contains("within the tolerance 0.01 mm"), "{text}");
        assert!(text.contains("program → design") && text.contains("design → program"), "{text}");
    }
}

#[test]
fn replay_reports_a_deviation_above_the_tolerance_with_status_1() {
    let out = tmp("vault-g01-coarse.nc");
    let (code, _, err) = run(bin()
        .args(["gcode", &example("rational-nurbs-vault.json"), "--kind", "g01", "--tolerance", "0.05", "--out"])
        .arg(&out));
    assert_eq!(code, 0, "{err}");
    let (code, text, _) = run(bin().arg("replay").arg(&out).args([
        "--scene",
        &example("rational-nurbs-vault.json"),
        "--tolerance",
        "0.01",
    ]));
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("EXCEEDS the tolerance 0.01 mm"), "{text}");
}

#[test]
fn replay_names_the_line_of_a_malformed_program_and_exits_2() {
    let p = tmp("bad.nc");
    std::fs::write(&p, "G21 G90\nG0 X0 Y0 Z0\nG2 X10 Y0 F100\n").expect("write");
    let (code, _, err) = run(bin().arg("replay").arg(&p));
    assert_eq!(code, 2);
    assert!(err.contains("line 3:") && err.contains("centre"), "{err}");
}

/// `replay` without a design streams the moves through its summary and holds none; with a
/// design it holds them all. Both print the same summary of the same program, in every
/// dialect (the path blocks of a curve depend on it) and with the dialect guessed or given.
#[test]
fn replay_summarises_alike_whether_it_holds_the_moves_or_streams_them() {
    let scene = example("rational-nurbs-vault.json");
    for dialect in ["fanuc", "linuxcnc", "sinumerik"] {
        for kind in ["g01", "arcs", "nurbs"] {
            if dialect == "linuxcnc" && kind == "nurbs" {
                continue; // G5.2 is XY only; the vault's curve is not flat.
            }
            let out = tmp(&format!("vault-{dialect}-{kind}.nc"));
            let (code, _, err) = run(bin()
                .args(["gcode", &scene, "--kind", kind, "--dialect", dialect, "--tolerance", "0.01", "--out"])
                .arg(&out));
            assert_eq!(code, 0, "{dialect} {kind}: {err}");
            for given in [None, Some(dialect)] {
                let mut streamed = bin();
                streamed.arg("replay").arg(&out);
                let mut held = bin();
                held.arg("replay").arg(&out).args(["--scene", &scene]);
                if let Some(d) = given {
                    streamed.args(["--dialect", d]);
                    held.args(["--dialect", d]);
                }
                let (code, streamed, err) = run(&mut streamed);
                assert_eq!(code, 0, "{dialect} {kind}: {err}");
                let (code, held, err) = run(&mut held);
                assert!(code == 0 || code == 1, "{dialect} {kind}: {err}");
                let summary: Vec<&str> = held.lines().take_while(|l| !l.starts_with("design")).collect();
                assert!(summary.len() >= 5 && summary[2].starts_with("moves"), "{held}");
                assert_eq!(streamed.lines().collect::<Vec<_>>(), summary, "{dialect} {kind} {given:?}");
            }
        }
    }
}

#[test]
fn replay_lists_unsupported_words_and_exits_1() {
    let p = tmp("comp.nc");
    std::fs::write(&p, "G21 G90\nG0 X0 Y0\nG41 D1 G1 X10 F200\nG40 G1 X20\n").expect("write");
    let (code, text, _) = run(bin().arg("replay").arg(&p));
    assert_eq!(code, 1, "{text}");
    assert!(text.contains("UNSUPPORTED  line 3: G41"), "{text}");
    assert!(text.contains("cutting 20.0000 mm"), "{text}");
}

#[test]
fn replay_reads_the_programmed_point_from_the_header() {
    let out = tmp("floor-tip.nc");
    let scene = example("bspline-floor-wall.json");
    let (code, _, err) = run(bin()
        .args(["gcode", &scene, "--kind", "nurbs", "--tolerance", "0.01", "--point", "tip", "--out"])
        .arg(&out));
    assert_eq!(code, 0, "{err}");
    let (code, text, _) = run(bin().arg("replay").arg(&out).args(["--scene", &scene, "--tolerance", "0.01"]));
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("ball tip"), "{text}");
    // Read as a centre path it is a ball radius (3 mm) off.
    let (code, text, _) =
        run(bin().arg("replay").arg(&out).args(["--scene", &scene, "--tolerance", "0.01", "--point", "centre"]));
    assert_eq!(code, 1, "{text}");
}

#[test]
fn compare_prints_the_program_and_update_tables() {
    let (code, text, err) = run(bin().args(["compare", "--profile", "parabola", "--tolerance", "0.01"]));
    assert_eq!(code, 0, "{err}");
    for needle in ["| G01 |", "| G02/G03 |", "| G06.2 |", "| first |", "| second |", "| corrected |"] {
        assert!(text.contains(needle), "{needle} missing:\n{text}");
    }
    let (code, csv, _) =
        run(bin().args(["compare", &example("sphere-plane.json"), "--tolerance", "0.01", "--format", "csv"]));
    assert_eq!(code, 0);
    assert!(csv.starts_with("program,path_blocks,"), "{csv}");
}

#[test]
fn nurbs_prints_one_row_per_period() {
    let (code, csv, err) =
        run(bin().args(["nurbs", &example("bspline-floor-wall.json"), "--tolerance", "0.01", "--update", "second"]));
    assert_eq!(code, 0, "{err}");
    let rows = csv.lines().count() - 1;
    assert!(err.contains(&format!("{rows} periods")), "{err}");
    assert!(csv.starts_with("k,t_ms,u,x,y,z,"), "{csv}");
}

#[test]
fn bad_requests_exit_2_with_the_fix() {
    let (code, _, err) =
        run(bin().args(["gcode", &example("sphere-plane.json"), "--kind", "g01", "--tolerance", "0.0015"]));
    assert_eq!(code, 2);
    assert!(err.contains("at least 0.002"), "{err}");
    let (code, _, err) = run(bin().args(["gcode", "--kind", "nurbs", "--tolerance", "0.01"]));
    assert_eq!(code, 2);
    assert!(err.contains("--profile parabola"), "{err}");
    let (code, _, err) =
        run(bin().args(["gcode", "--profile", "parabola", "--kind", "nurbs", "--tolerance", "0.01", "--point", "tip"]));
    assert_eq!(code, 2);
    assert!(err.contains("--tool-radius"), "{err}");
    let (code, _, err) = run(bin().args(["replay", "/nonexistent/program.nc"]));
    assert_eq!(code, 2);
    assert!(err.contains("cannot read program"), "{err}");
}
