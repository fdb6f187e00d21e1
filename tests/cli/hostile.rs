//! Hostile names through the command line (issue 29; issue 26 item 4): every program the
//! commands write (`gcode` in every kind and dialect, `finish --gcode`) keeps the blocks it
//! has for a benign name and is read back by `replay` and `simulate`; the CSV outputs keep
//! their rows and give a spreadsheet no formula; the JSON outputs stay well-formed and carry
//! the name as it was. `tests/core/gcode/hostile.rs` holds the generated cases through the library.
#![allow(clippy::unwrap_used, clippy::expect_used, reason = "tests: a failure should fail the test")]

use std::path::{Path, PathBuf};
use std::process::Command;

fn run(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_interpolab")).args(args).output().expect("the binary runs");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("interpolab-hostile-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// An example scene (`examples/<rel>`) under another name, written to a file of its own.
fn scene_file(rel: &str, tag: &str, name: &str) -> PathBuf {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples").join(rel)).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["name"] = name.into();
    let p = tmp(&format!("{tag}.json"));
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

/// The issue's names (line feed, carriage return, the Unicode line, paragraph and next-line
/// separators, a `)` closing the comment early, `;`, `%`, control characters) and more: our
/// header keys, LinuxCNC's active comments, CSV formulas, markup, Unicode, a very long name.
fn names() -> Vec<String> {
    let mut v: Vec<String> = [
        "Dome\nG0 X999 Y999 Z-50\n(x",
        "a\rG0 X999 Y999 Z-50\r",
        "b\u{2028}G0 X999\u{2029}G1 Z-50\u{85}M30",
        "c) G0 X999 Y999 Z-50 (",
        "d; G0 X999",
        "%\ne\n%",
        "f\u{0}\u{1b}[2J\u{7}\u{b}\u{c}\u{7f}\u{9b}G0 X999",
        "MSG, hi",
        "DIALECT: SINUMERIK PROGRAMMED POINT: BALL TIP = BALL CENTRE - Z 5 ,=1+1;@SUM(A1) \"q\" <script>alert(1)</script> é😀\u{202e}",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    v.push("Z".repeat(50_000));
    v
}

/// The lines holding code, comments (`( … )`, `;` to the end) taken out.
fn code_lines(text: &str) -> Vec<String> {
    text.split('\n')
        .map(|line| {
            let mut code = String::new();
            let mut depth = 0usize;
            for c in line.chars() {
                match c {
                    ';' if depth == 0 => break,
                    '(' => depth += 1,
                    ')' => depth = depth.saturating_sub(1),
                    _ if depth == 0 => code.push(c),
                    _ => {}
                }
            }
            code.trim().to_owned()
        })
        .filter(|c| !c.is_empty())
        .collect()
}

fn assert_program_like(hostile: &str, benign: &str, what: &str) {
    assert!(hostile.bytes().all(|b| b == b'\n' || (0x20..0x7f).contains(&b)), "{what}: a byte outside printable ASCII");
    assert_eq!(code_lines(hostile), code_lines(benign), "{what}: the blocks differ");
    assert_eq!(hostile.lines().count(), benign.lines().count(), "{what}: the name took more than its line");
}

#[test]
fn gcode_programs_keep_their_blocks_and_read_back_for_any_name() {
    let benign_scene = scene_file("floor-round-wall.json", "gcode-benign", "Floor and round wall");
    let names = names();
    for kind in ["g01", "arcs", "nurbs"] {
        for dialect in ["fanuc", "sinumerik", "linuxcnc"] {
            let write = |scene: &Path, out: &Path| {
                let (code, _, err) = run(&[
                    "gcode",
                    s(scene),
                    "--kind",
                    kind,
                    "--dialect",
                    dialect,
                    "--tolerance",
                    "0.01",
                    "--out",
                    s(out),
                ]);
                assert_eq!(code, 0, "{kind} {dialect}: {err}");
                std::fs::read_to_string(out).unwrap()
            };
            let benign = write(&benign_scene, &tmp(&format!("benign-{kind}-{dialect}.nc")));
            for (i, name) in names.iter().enumerate() {
                let scene = scene_file("floor-round-wall.json", &format!("gcode-{i}"), name);
                let out = tmp(&format!("hostile-{i}-{kind}-{dialect}.nc"));
                let text = write(&scene, &out);
                assert_program_like(&text, &benign, &format!("{kind} {dialect} name {i}"));
                let (code, stdout, err) = run(&["replay", s(&out)]);
                assert_eq!(code, 0, "replay {kind} {dialect} name {i}: {err}");
                assert!(stdout.contains(&format!("dialect      {dialect} ")), "{stdout}");
            }
        }
    }
}

#[test]
fn simulate_reads_every_dialect_with_a_hostile_name_as_with_a_benign_one() {
    let name = &names()[0];
    for dialect in ["fanuc", "sinumerik", "linuxcnc"] {
        let mut removed = Vec::new();
        for (tag, n) in [("benign", "Floor and round wall"), ("hostile", name.as_str())] {
            let scene = scene_file("floor-round-wall.json", &format!("sim-{tag}-{dialect}"), n);
            let out = tmp(&format!("sim-{tag}-{dialect}.nc"));
            let (code, _, err) = run(&[
                "gcode",
                s(&scene),
                "--kind",
                "nurbs",
                "--dialect",
                dialect,
                "--tolerance",
                "0.01",
                "--out",
                s(&out),
            ]);
            assert_eq!(code, 0, "{err}");
            let (code, stdout, err) =
                run(&["simulate", s(&out), "--cutter", "ball:5", "--pitch", "1", "--stock=-60,-60,-10,60,60,10"]);
            assert_eq!(code, 0, "simulate {dialect} {tag}: {err}");
            assert!(!err.contains("UNSUPPORTED"), "simulate {dialect} {tag} left words out: {err}");
            let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
            removed.push(v["removed_volume_mm3"].as_f64().unwrap());
        }
        assert_eq!(removed[0], removed[1], "{dialect}");
        assert!(removed[0] > 1000.0, "{dialect}: {removed:?} mm³");
    }
}

#[test]
fn finish_gcode_keeps_its_blocks_and_reads_back_for_any_name() {
    let benign_scene =
        scene_file("finish/bicubic-patch.json", "finish-benign", "Gently curved bicubic patch (seed 001)");
    let write = |scene: &Path, tag: &str| {
        let out = tmp(&format!("finish-{tag}.nc"));
        let (code, csv, err) = run(&["finish", s(scene), "--gcode", s(&out)]);
        assert_eq!(code, 0, "{tag}: {err}");
        (std::fs::read_to_string(&out).unwrap(), csv, out)
    };
    let (benign, benign_csv, benign_out) = write(&benign_scene, "benign");
    // The benign name's parentheses no longer end the comment (issue 26 item 4).
    let (code, _, err) = run(&["replay", s(&benign_out)]);
    assert_ne!(code, 2, "replay refuses the program of a benign name: {err}");
    let names = names();
    for i in [0, 1, 3, 6, 8, 9] {
        let scene = scene_file("finish/bicubic-patch.json", &format!("finish-{i}"), &names[i]);
        let (text, csv, out) = write(&scene, &i.to_string());
        assert_program_like(&text, &benign, &format!("finish name {i}"));
        assert_eq!(csv, benign_csv, "name {i}: the CL data changed");
        let (code, stdout, err) = run(&["replay", s(&out)]);
        assert_ne!(code, 2, "replay name {i}: {err}");
        assert!(stdout.contains("dialect      fanuc "), "{stdout}");
        let (code, _, err) =
            run(&["simulate", s(&out), "--cutter", "fillet:5,1", "--pitch", "4", "--stock=-90,-120,-10,70,50,20"]);
        assert_eq!(code, 0, "simulate name {i}: {err}");
    }
}

/// A CSV line's cells as spreadsheets split them (`,`, and `;` in locales that use it).
fn cells(line: &str) -> impl Iterator<Item = &str> {
    line.split([',', ';']).map(|c| c.trim_start_matches(' '))
}

/// No cell a spreadsheet would run: one starting with `=` `+` `-` `@` must be a number.
fn assert_no_formula(csv: &str, what: &str) {
    for line in csv.lines() {
        for c in cells(line) {
            if c.starts_with(['=', '+', '-', '@', '\t', '\r']) {
                // A number, or a percentage (compare's "vs G01": -98%), as spreadsheets read it.
                let number = c.strip_suffix('%').unwrap_or(c);
                assert!(number.parse::<f64>().is_ok(), "{what}: the cell {c:?} in the line {line:?}");
            }
        }
    }
}

#[test]
fn csv_outputs_keep_their_rows_and_give_no_formula() {
    let name = "x\n=1+1,\"\n@SUM(A1);-2+3, =HYPERLINK(\"http://x\")\r+5\u{2028}\"a,b\"";
    let benign_scene = scene_file("floor-round-wall.json", "csv-benign", "Floor and round wall");
    let scene = scene_file("floor-round-wall.json", "csv-hostile", name);
    let tol = ["--tolerance", "0.01"];
    // Outputs that do not carry the name: byte for byte as with a benign name.
    for args in [vec!["run"], vec!["run", "--errors"], vec!["nurbs", tol[0], tol[1]]] {
        let with = |p: &Path| {
            let mut a = vec![args[0], s(p)];
            a.extend(&args[1..]);
            let (code, out, err) = run(&a);
            assert_eq!(code, 0, "{args:?}: {err}");
            out
        };
        assert_eq!(with(&scene), with(&benign_scene), "{args:?}");
    }
    // compare's table: the programs' sizes grow by the title's line, nothing else changes.
    let table = |p: &Path| {
        let (code, out, err) = run(&["compare", s(p), tol[0], tol[1], "--format", "csv"]);
        assert_eq!(code, 0, "compare: {err}");
        assert_no_formula(&out, "compare");
        let without_bytes: Vec<String> = out
            .lines()
            .map(|l| l.split(',').enumerate().filter(|(i, _)| *i != 3).map(|(_, c)| c).collect::<Vec<_>>().join(","))
            .collect();
        without_bytes
    };
    assert_eq!(table(&scene), table(&benign_scene));
    // Outputs whose comment lines carry it: the same rows, one comment line each, no formula.
    for cmd in ["steps", "chords"] {
        let with = |p: &Path| {
            let (code, out, err) = run(&[cmd, s(p), tol[0], tol[1]]);
            assert_eq!(code, 0, "{cmd}: {err}");
            out
        };
        let (hostile, benign) = (with(&scene), with(&benign_scene));
        assert_eq!(hostile.lines().count(), benign.lines().count(), "{cmd}: rows added\n{hostile}");
        for (h, b) in hostile.lines().zip(benign.lines()) {
            if b.starts_with('#') {
                // A line carrying the name opens no quoted field that could run over the rows.
                assert!(h.starts_with('#') && (h == b || !h.contains('"')), "{cmd}: {h:?}");
            } else {
                assert_eq!(h, b, "{cmd}: a row changed");
            }
        }
        assert_no_formula(&hostile, cmd);
        assert_no_formula(&benign, cmd);
        // Negative numbers stay numbers.
        assert!(hostile.lines().any(|l| !l.starts_with('#') && cells(l).any(|c| c.starts_with('-'))), "{cmd}");
    }
}

#[test]
fn json_outputs_are_well_formed_and_carry_the_name_as_it_was() {
    let name = "q\"uote\\ \n\r\u{0}\u{1f}\u{7f}\u{2028}\u{2029}</script><script>alert(1)</script> é😀 \u{202e}";
    let scene = scene_file("floor-round-wall.json", "json-hostile", name);
    let finish = scene_file("finish/naca-blade.json", "json-finish", name);
    let json = |args: &[&str]| -> serde_json::Value {
        let (code, out, err) = run(args);
        assert_eq!(code, 0, "{args:?}: {err}");
        serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: not JSON ({e}):\n{out}"))
    };
    assert_eq!(json(&["run", s(&scene), "--format", "json"])["scene"], name);
    assert_eq!(json(&["finish", s(&finish), "--format", "json"])["scene"], name);
    assert_eq!(
        json(&["steps", s(&scene), "--tolerance", "0.01", "--format", "json"])["design"],
        format!("{name} ({})", s(&scene))
    );
    assert_eq!(
        json(&["chords", s(&scene), "--tolerance", "0.01", "--format", "json"])["curve"],
        format!("ball-centre crease of {name} (param: chord length, mm)")
    );
    // simulate names its program by the file's path, which may be as hostile.
    let program = tmp("q\"uote\\ \n<script>é.nc");
    std::fs::write(&program, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X5\n").unwrap();
    let v = json(&["simulate", s(&program), "--cutter", "ball:1", "--pitch", "0.5", "--stock=-2,-2,-3,7,2,0"]);
    assert_eq!(v["program"], s(&program));
}
