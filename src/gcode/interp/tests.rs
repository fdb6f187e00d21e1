//! The interpreter on programs whose motions are known in closed form.

use glam::DVec3;

use super::*;

fn run(text: &str) -> Result<Vec<Canon>, InterpError> {
    Interpreter::from_text(text, Options::default()).collect()
}

fn run_with(text: &str, opts: Options) -> (Result<Vec<Canon>, InterpError>, Vec<Report>, Vec<Warning>) {
    let mut it = Interpreter::from_text(text, opts);
    let r: Result<Vec<Canon>, InterpError> = it.by_ref().collect();
    (r, it.reports().to_vec(), it.warnings().to_vec())
}

/// End points (x, y, z) of the motions.
fn ends(c: &[Canon]) -> Vec<DVec3> {
    c.iter().filter_map(|c| c.end().map(|p| p.xyz)).collect()
}

fn near(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn o_word_loops_conditionals_and_calls() {
    let text = "\
o<square> sub
  g1 x#1 y0
  g1 x#1 y#1
  o<square> return [#1 * 2]
o<square> endsub
g0 x0 y0 z0
f100
#1 = 0
o10 while [#1 lt 3]
  #1 = [#1 + 1]
  o20 if [#1 eq 2]
    g1 z-2
  o20 elseif [#1 eq 3]
    g1 z-3
  o20 else
    g1 z-1
  o20 endif
o10 endwhile
o30 repeat [2]
  g91 g1 x1
o30 endrepeat
g90
o<square> call [5]
g1 x#<_value>
#2 = 0
o40 do
  #2 = [#2 + 1]
  o41 if [#2 gt 10]
    o40 break
  o41 endif
o40 while [1]
g1 y#2
m2
";
    let c = run(text).unwrap_or_else(|e| panic!("{e}"));
    let want = [
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(0.0, 0.0, -2.0),
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::new(1.0, 0.0, -3.0),
        DVec3::new(2.0, 0.0, -3.0),
        DVec3::new(5.0, 0.0, -3.0),
        DVec3::new(5.0, 5.0, -3.0),
        DVec3::new(10.0, 5.0, -3.0),
        DVec3::new(10.0, 11.0, -3.0),
    ];
    let got = ends(&c);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(near(*g, w), "{got:?}");
    }
    // The call's arguments are restored afterwards: #1 is the loop's 3 again.
    assert!(c.iter().any(|c| matches!(c, Canon::Stop { end: true, .. })));
}

#[test]
fn fanuc_macro_b_and_subprograms() {
    let text = "\
%
O0001 (MAIN)
G21 G90 G0 X0 Y0 Z5
F200
#100 = 1
WHILE [#100 LE 3] DO1
  G1 X#100
  #100 = #100 + 1
END1
IF [#100 EQ 4] GOTO 50
G1 Y99
N50 G1 Y1
M98 P1000 L2
G65 P2000 A7 B8
#1 = 0
N60 #1 = #1 + 1
IF [#1 LT 3] GOTO 60
G1 Z#1
M30
O1000
G91 G1 X10
G90
M99
O2000
G1 X#1 Y#2
M99
%
";
    let c = run(text).unwrap_or_else(|e| panic!("{e}"));
    let xs: Vec<DVec3> = ends(&c);
    let want = [
        DVec3::new(0.0, 0.0, 5.0),
        DVec3::new(1.0, 0.0, 5.0),
        DVec3::new(2.0, 0.0, 5.0),
        DVec3::new(3.0, 0.0, 5.0),
        DVec3::new(3.0, 1.0, 5.0),
        DVec3::new(13.0, 1.0, 5.0),
        DVec3::new(23.0, 1.0, 5.0),
        DVec3::new(7.0, 8.0, 5.0),
        DVec3::new(7.0, 8.0, 3.0),
    ];
    assert_eq!(xs.len(), want.len(), "{xs:?}");
    for (g, w) in xs.iter().zip(want) {
        assert!(near(*g, w), "{xs:?}");
    }
}

#[test]
fn offsets_rotation_and_units_reach_the_machine_frame() {
    // G10 L2 R rotates the system about its origin; G92 shifts before the rotation.
    let text =
        "G21 G10 L2 P2 X10 Y20 Z0 R90\nG55 G0 X1 Y0 Z0\nG92 X0 Y0\nG0 X1 Y0\nG92.1\nG20 G0 X1 Y0\nG53 G0 X0 Y0 Z0\n";
    let c = run(text).unwrap_or_default();
    let e = ends(&c);
    assert!(near(e[0], DVec3::new(10.0, 21.0, 0.0)), "{e:?}");
    // G92 made (1, 0) read as (0, 0): X1 is then 2 from the system's origin, rotated.
    assert!(near(e[1], DVec3::new(10.0, 22.0, 0.0)), "{e:?}");
    assert!(near(e[2], DVec3::new(10.0, 20.0 + 25.4, 0.0)), "{e:?}");
    assert!(near(e[3], DVec3::ZERO), "{e:?}");
    // G10 L20: the current position reads as the given value.
    let c = run("G0 X5 Y5\nG10 L20 P1 X0 Y0\nG0 X1 Y1\n").unwrap_or_default();
    assert!(near(ends(&c)[1], DVec3::new(6.0, 6.0, 0.0)));
    // G52 is a local offset of the given values.
    let c = run("G52 X100\nG0 X1\nG52 X0\nG0 X1\n").unwrap_or_default();
    assert!(near(ends(&c)[0], DVec3::new(101.0, 0.0, 0.0)) && near(ends(&c)[1], DVec3::new(1.0, 0.0, 0.0)));
    // FANUC G68 rotates about its centre.
    let c = run("G0 X0 Y0\nG68 X10 Y0 R90\nG0 X20 Y0\nG69\nG0 X20 Y0\n").unwrap_or_default();
    assert!(near(ends(&c)[1], DVec3::new(10.0, 10.0, 0.0)) && near(ends(&c)[2], DVec3::new(20.0, 0.0, 0.0)));
}

#[test]
fn incremental_polar_and_stored_positions() {
    let c = run("G91 G0 X1 Y1\nX1\nG90 G0 @2 ^90\nG91 G0 ^90\nG90 G28.1\nG0 X9 Y9 Z9\nG28 Z1\n").unwrap_or_default();
    let e = ends(&c);
    assert!(near(e[0], DVec3::new(1.0, 1.0, 0.0)) && near(e[1], DVec3::new(2.0, 1.0, 0.0)));
    assert!(near(e[2], DVec3::new(0.0, 2.0, 0.0)), "{e:?}");
    assert!(near(e[3], DVec3::new(-2.0, 0.0, 0.0)), "{e:?}");
    // G28 Z1: through Z1, then only Z home (stored at the G28.1: (-2, 0, 0)).
    assert!(near(e[5], DVec3::new(9.0, 9.0, 1.0)) && near(e[6], DVec3::new(9.0, 9.0, 0.0)), "{e:?}");
}

#[test]
fn arcs_follow_linuxcnc_formats_and_tolerances() {
    let c = run("G0 X0 Y0\nG2 X10 Y0 R5 F100\nG3 X0 Y0 I-5 J0 P3\nG18 G2 X0 Z10 K5\n").unwrap_or_default();
    let arcs: Vec<(DVec3, i32)> = c
        .iter()
        .filter_map(|c| if let Canon::Arc { center, turns, .. } = c { Some((*center, *turns)) } else { None })
        .collect();
    assert!(near(arcs[0].0, DVec3::new(5.0, 0.0, 0.0)) && arcs[0].1 == -1);
    assert!(near(arcs[1].0, DVec3::new(5.0, 0.0, 0.0)) && arcs[1].1 == 3);
    assert!(near(arcs[2].0, DVec3::new(0.0, 0.0, 5.0)) && arcs[2].1 == -1);
    // A Fusion 360 arc whose radii differ by 0.1 µm reads; one whose end is 0.1 mm off does not.
    assert!(run("G0 X0 Y0\nG2 X10.0000001 Y0 I5 J0 F100\n").is_ok());
    // Beyond LinuxCNC's tolerance: refused when strict, else drawn and reported.
    let strict = Options { strict: true, ..Options::default() };
    let e = run_with("G0 X0 Y0\nG2 X10.1 Y0 I5 J0 F100\n", strict.clone())
        .0
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.starts_with("line 2:") && e.contains("not on its circle"), "{e}");
    let (r, reports, _) = run_with("G0 X0 Y0\nG2 X10.1 Y0 I5 J0 F100\n", Options::default());
    assert!(r.is_ok() && reports.iter().any(|r| r.code == "arc radius" && r.first.line == 2), "{reports:?}");
    let e = run_with("G0 X0 Y0\nG2 X10 Y0 R4 F100\n", strict).0.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("smaller than half"), "{e}");
}

#[test]
fn what_cannot_be_modelled_is_reported_once_with_its_count() {
    let mut text = String::from("G0 X0\n<<<<<<< HEAD\n% vfd enable\n");
    for _ in 0..500 {
        text.push_str("M100 P1\nG1 X1 E5 F10\n");
    }
    text.push_str("Post Process Timed: 00:00:01\n");
    let (r, reports, _) = run_with(&text, Options::default());
    assert!(r.is_ok(), "{r:?}");
    let m100 = reports.iter().find(|r| r.code == "M100").map(|r| (r.count, r.first.line));
    assert_eq!(m100, Some((500, 4)));
    let skipped = reports.iter().find(|r| r.code == "not G-code").map(|r| (r.count, r.first.line));
    assert_eq!(skipped, Some((2, 2)), "{reports:?}");
    assert!(reports.iter().any(|r| r.code == "% text"));
    let (r, _, _) = run_with(&text, Options { strict: true, ..Options::default() });
    assert_eq!(r.err().map(|e| e.loc.line), Some(2));
}

#[test]
fn an_inch_looking_program_without_units_is_warned() {
    let text = "G90\nG0 X0 Y0 Z0.1\nG1 Z-0.05 F5\nG1 X2 Y1.5\nM2\n";
    let (_, _, w) = run_with(text, Options::default());
    assert_eq!(w.len(), 1);
    assert!(w[0].text.contains("--units inch") && w[0].loc.line == 3, "{w:?}");
    let (r, _, w) = run_with(text, Options { inch: true, ..Options::default() });
    assert!(w.is_empty());
    assert!(near(ends(&r.unwrap_or_default())[2], DVec3::new(50.8, 38.1, -1.27)));
    let (_, _, w) = run_with(&format!("G21\n{text}"), Options::default());
    assert!(w.is_empty(), "a program that says G21 is millimetres");
}

#[test]
fn endless_work_is_refused_naming_the_line() {
    let opts = Options { max_lines: Some(100_000), ..Options::default() };
    let e = run_with("#1=0\no1 while [1]\n#1=[#1+1]\no1 endwhile\n", opts).0.err();
    let e = e.map(|e| (e.loc.line, e.to_string())).unwrap_or_default();
    assert!(e.1.contains("loop at line 2"), "{e:?}");
    let e = run("o<r> sub\no<r> call\no<r> endsub\no<r> call\n").err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("nested more than"), "{e}");
    let e = run("G1 X1 F10\nGOTO 99\n").err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.starts_with("line 2:") && e.contains("N99"), "{e}");
}

#[test]
fn subroutine_files_come_from_the_library() {
    let mut lib = TextLibrary::new();
    lib.add("dir/Drill.ngc", "o<drill> sub\ng0 x#1\no<drill> endsub\nm2\n");
    lib.add("O1234.nc", "O1234\nG0 Y7\nM99\n");
    let mut it = Interpreter::new(
        Box::new(TextSource::new("o<drill> call [3]\nM98 P1234\nG0 Z1\n")),
        Box::new(lib),
        Options::default(),
    );
    let c: Vec<Canon> = it.by_ref().collect::<Result<_, _>>().unwrap_or_default();
    let e = ends(&c);
    assert!(
        near(e[0], DVec3::new(3.0, 0.0, 0.0))
            && near(e[1], DVec3::new(3.0, 7.0, 0.0))
            && near(e[2], DVec3::new(3.0, 7.0, 1.0)),
        "{e:?}"
    );
    assert_eq!(c[0].loc().file, 1);
    assert_eq!(it.file_name(1), "drill");
}

#[test]
fn fanuc_manual_examples_give_their_closed_forms() {
    // Macro B's summation example: the sum of 1 to 10 in #1.
    let c = run("O9500\n#1=0\n#2=1\nWHILE[#2LE10]DO1\n#1=#1+#2\n#2=#2+1\nEND1\nG1 X#1 F100\nM30\n").unwrap_or_default();
    assert!(near(ends(&c)[0], DVec3::new(55.0, 0.0, 0.0)), "{:?}", ends(&c));
    // M98 P51002: program 1002 five times (repeat count in the leading digits).
    let c = run("G91 F100\nM98 P51002\nM30\nO1002\nG1 X2\nM99\n").unwrap_or_default();
    let e = ends(&c);
    assert_eq!(e.len(), 5);
    assert!(near(e[4], DVec3::new(10.0, 0.0, 0.0)), "{e:?}");
    // G68 rotates a square about its centre: the corners land where the rotation puts them.
    let c = run("G90 G0 X0 Y0\nG68 X5 Y5 R90\nG1 X10 Y0 F100\nG1 X10 Y10\nG69\n").unwrap_or_default();
    let e = ends(&c);
    assert!(near(e[1], DVec3::new(10.0, 10.0, 0.0)) && near(e[2], DVec3::new(0.0, 10.0, 0.0)), "{e:?}");
    // G65 with arguments A (#1) and B (#2), a local of the macro.
    let c =
        run("G90 F100\nG65 P9010 A3 B4\nG1 Y#1\nM30\nO9010\n#3=SQRT[#1*#1+#2*#2]\nG1 X#3\nM99\n").unwrap_or_default();
    let e = ends(&c);
    assert!(near(e[0], DVec3::new(5.0, 0.0, 0.0)), "{e:?}");
    assert!(near(e[1], DVec3::new(5.0, 0.0, 0.0)), "the caller's #1 is its own again: {e:?}");
}
