//! The interpreter against LinuxCNC's own: every LinuxCNC sample program and every feature
//! program of ours (tests/data/ngc) read by both, canonical call for call — end points, arc
//! centres and turns, feeds, spline control-point counts, dwells, tool changes and offsets,
//! spindle and stops equal within what `rs274` prints (1e-4 of the program's unit) — and the
//! programs LinuxCNC refuses refused by ours at the same line.

use std::path::{Path, PathBuf};

use crate::support::rs274::{self, RefRun, Rs274, compare, is_subroutine_file};
use interpolab::gcode::interp::tools::{TableUnits, ToolTable};
use interpolab::gcode::interp::{Canon, InterpError, Interpreter, Library, Options, Source, TextSource};

/// Subroutine files found by name in a list of directories (as LinuxCNC's SUBROUTINE_PATH).
struct Dirs(Vec<PathBuf>);

impl<'a> Library<'a> for Dirs {
    fn open(&mut self, name: &str) -> Option<Box<dyn Source + 'a>> {
        for d in &self.0 {
            for entry in std::fs::read_dir(d).ok()?.flatten() {
                let p = entry.path();
                let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("");
                if stem.eq_ignore_ascii_case(name) && p.extension().is_some_and(|e| e.eq_ignore_ascii_case("ngc")) {
                    let text: &'static str = Box::leak(std::fs::read_to_string(&p).ok()?.into_boxed_str());
                    return Some(Box::new(TextSource::new(text)));
                }
            }
        }
        None
    }
}

fn ours(path: &Path, dirs: &[PathBuf], tools: Option<&Path>) -> (Vec<Canon>, Option<InterpError>) {
    let text: &'static str = Box::leak(std::fs::read_to_string(path).unwrap_or_default().into_boxed_str());
    let tools = tools.map_or_else(ToolTable::default, |t| {
        // rs274 without an INI reads a table's lengths in inches (its machine units).
        ToolTable::from_linuxcnc(&std::fs::read_to_string(t).unwrap_or_default(), TableUnits::Inch)
            .unwrap_or_else(|e| panic!("{}: {e}", t.display()))
    });
    let opts = Options { tools, ..Options::default() };
    let it = Interpreter::new(Box::new(TextSource::new(text)), Box::new(Dirs(dirs.to_vec())), opts);
    let mut calls = Vec::new();
    for c in it {
        match c {
            Ok(c) => calls.push(c),
            Err(e) => return (calls, Some(e)),
        }
    }
    (calls, None)
}

/// Runs both and compares; `Ok(true)` when LinuxCNC read the program to its end.
fn check(path: &Path, dirs: &[PathBuf], tools: Option<&Path>) -> Result<bool, String> {
    let reference =
        Rs274 { tool_table: tools.map(Path::to_path_buf), subroutine_dirs: dirs.to_vec(), ..Rs274::default() };
    let theirs: RefRun = reference.run(path)?;
    let (mine, err) = ours(path, dirs, tools);
    let name = path.display();
    match (&theirs.error, &err) {
        (None, Some(e)) => Err(format!("{name}: LinuxCNC reads it to the end, ours stops: {e}")),
        (None, None) => compare(&mine, &theirs.calls).map(|()| true).map_err(|e| format!("{name}: {e}")),
        (Some(t), _) => {
            // Until LinuxCNC's error both agree; after it ours may go on (a viewer reads past
            // what LinuxCNC refuses: a tool missing from its table, an axis it lacks …), and
            // LinuxCNC may not print the calls waiting in its queue when it stops.
            if let Some(e) = &err
                && t.line.is_some_and(|l| e.loc.file == 0 && e.loc.line < l)
            {
                return Err(format!(
                    "{name}: ours stops at line {} ({e}) before LinuxCNC's error at line {:?} ({})",
                    e.loc.line, t.line, t.text
                ));
            }
            match compare(&mine, &theirs.calls) {
                Ok(()) => Ok(false),
                Err(m) if m.starts_with("we have") => Ok(false),
                Err(m) => Err(format!("{name} (LinuxCNC stops at line {:?}: {}): {m}", t.line, t.text)),
            }
        }
    }
}

fn programs_in(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            programs_in(&p, out);
        } else if p.extension().is_some_and(|e| e == "ngc") && !is_subroutine_file(&p) {
            out.push(p);
        }
    }
}

fn subdirs(dir: &Path, out: &mut Vec<PathBuf>) {
    out.push(dir.to_path_buf());
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).filter(|p| p.is_dir()).collect();
    entries.sort();
    for p in entries {
        subdirs(&p, out);
    }
}

#[test]
fn our_feature_programs_read_as_linuxcnc_reads_them() {
    rs274::require();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ngc");
    let tools = dir.join("tools.tbl");
    let mut files = Vec::new();
    programs_in(&dir, &mut files);
    assert!(files.len() >= 25, "feature programs: {}", files.len());
    let mut failures = Vec::new();
    let mut refused = 0;
    for f in &files {
        match check(f, std::slice::from_ref(&dir), Some(&tools)) {
            Ok(true) => {}
            Ok(false) => refused += 1,
            Err(e) => failures.push(e),
        }
    }
    assert!(failures.is_empty(), "{} of {} differ:\n{}", failures.len(), files.len(), failures.join("\n"));
    assert!(refused >= 4, "the *-refused programs are refused by LinuxCNC");
}

#[test]
fn linuxcnc_sample_programs_read_as_linuxcnc_reads_them() {
    rs274::require();
    let root = Path::new("/usr/share/linuxcnc/ncfiles");
    let mut files = Vec::new();
    programs_in(root, &mut files);
    assert!(files.len() >= 40, "LinuxCNC's samples: {} programs found", files.len());
    let mut dirs = Vec::new();
    subdirs(root, &mut dirs);
    let mut failures = Vec::new();
    let mut to_the_end = 0;
    // Not modelled, and reported as such (docs/interpreter.md): lathe roughing and finishing
    // cycles G70–G72.
    let lathe_cycles = ["lathe_g7x_face_boring.ngc", "lathe_g7x_quadrants.ngc", "lathe_g70_71_demo.ngc"];
    for f in &files {
        if f.file_name().is_some_and(|n| lathe_cycles.iter().any(|l| n == *l)) {
            continue;
        }
        match check(f, &dirs, None) {
            Ok(true) => to_the_end += 1,
            Ok(false) => {}
            Err(e) => failures.push(e),
        }
    }
    eprintln!("{to_the_end} of {} samples read to the end by LinuxCNC and equal", files.len());
    assert!(failures.is_empty(), "{} of {} differ:\n{}", failures.len(), files.len(), failures.join("\n"));
}

mod random_text {
    use interpolab::gcode::interp::{Interpreter, Options};
    use proptest::prelude::*;

    /// Pieces of G-code, valid and not, glued into lines.
    fn piece() -> impl Strategy<Value = String> {
        prop_oneof![
            Just("G0".to_owned()),
            Just("G1".to_owned()),
            Just("G2".to_owned()),
            Just("G3".to_owned()),
            Just("G91".to_owned()),
            Just("G20".to_owned()),
            Just("G41 D1".to_owned()),
            Just("G40".to_owned()),
            Just("G81 R1 Z-1".to_owned()),
            Just("G92 X0".to_owned()),
            Just("G10 L2 P1 R30".to_owned()),
            Just("G5.2 L3".to_owned()),
            Just("G5.3".to_owned()),
            Just("G6.2 P4 K0".to_owned()),
            Just("o1 while [#1 lt 3]".to_owned()),
            Just("o1 endwhile".to_owned()),
            Just("#1=[#1+1]".to_owned()),
            Just("o<s> call [1]".to_owned()),
            Just("o<s> sub".to_owned()),
            Just("o<s> endsub".to_owned()),
            Just("WHILE [#2 LT 2] DO1".to_owned()),
            Just("END1".to_owned()),
            Just("GOTO 10".to_owned()),
            Just("M98 P1".to_owned()),
            Just("M99".to_owned()),
            Just("(".to_owned()),
            Just(")".to_owned()),
            Just("%".to_owned()),
            (prop::sample::select(vec!['X', 'Y', 'Z', 'I', 'J', 'K', 'R', 'F', 'P', 'Q', 'A', 'N']), -1e3f64..1e3)
                .prop_map(|(l, v)| format!("{l}{v:.3}")),
            "[ -~]{0,12}",
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        /// Any text: the interpreter ends (a program or one error), never panics, and every
        /// position it hands out is finite.
        #[test]
        fn any_text_ends_in_calls_or_one_error(lines in prop::collection::vec(prop::collection::vec(piece(), 0..6), 0..40)) {
            let text: String = lines.iter().map(|l| l.join(" ") + "\n").collect();
            let opts = Options { max_lines: Some(200_000), ..Options::default() };
            let mut errors = 0;
            for c in Interpreter::from_text(&text, opts) {
                match c {
                    Ok(c) => {
                        if let Some(p) = c.end() {
                            prop_assert!(p.xyz.is_finite() && p.abc.is_finite(), "{c:?}\n{text}");
                        }
                    }
                    Err(e) => {
                        errors += 1;
                        prop_assert!(e.to_string().starts_with("line ") || e.to_string().contains(" line "), "{e}");
                    }
                }
            }
            prop_assert!(errors <= 1);
        }
    }
}
