//! Hostile text through every program writer (issue 29; issue 26 item 4): a name made of
//! line breaks of every kind, control characters, comment delimiters, tape marks, blocks,
//! our own header keys, LinuxCNC's active comments, arbitrary Unicode or a hundred thousand
//! characters leaves every written program's blocks exactly those written for a benign name,
//! and the product's reader (`parse_program_in` in the program's dialect, which
//! `Dialect::guess` must find again) reads it back without a refusal.
//!
//! The writers, through the library: the seed-004 crease programs (`gcode::write_program`,
//! G01 / arcs / NURBS × FANUC / Sinumerik / LinuxCNC), the same through the background job
//! the app's NURBS & G-code tab downloads its programs from (`jobs::program_row`, encoded and
//! decoded as the Web Worker does), and the five-axis finishing program
//! (`fillet::program::FinishGcode`, what `finish --gcode` writes). `tests/cli/hostile.rs`
//! drives the command line.

use std::sync::OnceLock;

use interpolab::crease::{CreaseCurve, CreaseJob};
use interpolab::fillet::program::FinishGcode;
use interpolab::fillet::{PartSamples, iso_scallop};
use interpolab::gcode::HeaderKey;
use interpolab::gcode::comment::{comment_text, safe_comment};
use interpolab::gcode::{
    CompareOptions, Dialect, ParsedProgram, ProgramKind, ProgramOptions, ProgrammedPoint, crease_design,
    parse_program_in, write_program,
};
use interpolab::jobs::program_row::{DesignSpec, ProgramRow, Request};
use interpolab::jobs::{JobKind, NoProgress, run_encoded};
use interpolab::numerics::limits::MAX_COMMENT_CHARS;
use interpolab::scene::finish::FinishScene;
use interpolab::scene::{PRESETS, Scene};
use proptest::prelude::*;

/// Pieces of hostile text: every line break and control character, the comment delimiters
/// and tape mark, blocks, our header keys, LinuxCNC's active comments, CSV formula starts,
/// markup, characters outside ASCII.
const PIECES: &[&str] = &[
    "\n",
    "\r",
    "\r\n",
    "\u{b}",
    "\u{c}",
    "\t",
    "\u{85}",
    "\u{2028}",
    "\u{2029}",
    "\0",
    "\u{1b}",
    "\u{7f}",
    "\u{80}",
    "\u{9f}",
    "(",
    ")",
    ";",
    "%",
    "\n%\n",
    "G0 X999 Y999 Z-50",
    "\nG0 X999 Y999 Z-50\n(",
    ")G0 X999 Y999 Z-50(",
    "; G1 Z-50",
    "M30",
    "M2",
    "/",
    "N10 ",
    "#1=5",
    "[#1]",
    "DIALECT: SINUMERIK",
    "DIALECT: LINUXCNC",
    "dialect: fanuc",
    "PROGRAMMED POINT: BALL TIP = BALL CENTRE - Z 5",
    "programmed point: ball centre",
    "MSG,hello",
    "py,import os",
    "  LogOpen,/tmp/x",
    "ABORT,stop",
    "PYRELOAD",
    "AXIS,hide",
    "=1+1",
    "@SUM(A1)",
    "+1",
    "-2+3",
    ",=HYPERLINK(\"http://x\")",
    "\"",
    "'",
    "<script>alert(1)</script>",
    "<img src=x onerror=alert(1)>",
    "&amp;",
    "é",
    "°",
    "µ",
    "😀",
    "\u{202e}",
    "\u{200b}",
    "\u{feff}",
    "\u{fffd}",
    "Floor and round wall",
    " ",
];

/// Text a user could give as a name: pieces, arbitrary characters (controls and every
/// plane of Unicode included), printable ASCII, and long repeats.
fn hostile() -> impl Strategy<Value = String> {
    let piece = prop_oneof![
        4 => proptest::sample::select(PIECES).prop_map(str::to_owned),
        2 => prop::collection::vec(any::<char>(), 0..24).prop_map(String::from_iter),
        1 => "[ -~]{0,16}",
        1 => (proptest::sample::select(PIECES), 1usize..4000).prop_map(|(p, n)| p.repeat(n)),
    ];
    prop::collection::vec(piece, 0..10).prop_map(|v| v.concat())
}

/// The lines of a program that hold code, with their comments (`( … )`, and `;` to the
/// line's end) taken out and the rest trimmed: the blocks as a control executes them, in
/// order (lines holding only a comment left out).
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
        .filter(|code| !code.is_empty())
        .collect()
}

/// A comment LinuxCNC would act on (its interpreter's `convert_comment`): after leading
/// white space, in any case, one of these starts.
fn active_in_linuxcnc(comment: &str) -> bool {
    let lc = comment.trim_start().to_ascii_lowercase();
    ["msg,", "debug,", "print,", "log,", "logopen,", "logappend,", "logclose", "py,", "pyrun,", "pyreload", "abort,"]
        .iter()
        .any(|w| lc.starts_with(w))
}

/// What must hold of a program written with a hostile name against the same program written
/// with a benign one, read in `dialect`.
fn assert_same_blocks(hostile: &str, benign: &str, dialect: Dialect, name: &str) -> Result<(), TestCaseError> {
    // Printable ASCII and line feeds only: no other line break, control or byte a control
    // might read differently.
    if let Some(b) = hostile.bytes().find(|&b| b != b'\n' && !(0x20..0x7f).contains(&b)) {
        return Err(TestCaseError::fail(format!("byte {b:#04x} in the program for {name:?}")));
    }
    prop_assert_eq!(code_lines(hostile), code_lines(benign), "blocks differ for the name {:?}", name);
    prop_assert_eq!(Dialect::guess(hostile), dialect, "dialect guessed for {:?}", name);
    let h = parse_program_in(hostile, dialect);
    prop_assert!(h.is_ok(), "the reader refuses the program for {:?}: {:?}", name, h.as_ref().err());
    let (h, b) = (h.unwrap_or_default(), read(benign, dialect));
    // The same moves (and, but for an empty title's missing line, on the same lines).
    let moves = |p: &ParsedProgram| -> Vec<String> {
        p.toolpath.blocks.iter().map(|b| format!("{:?} {:?} {:?}", b.motion, b.segment, b.feed_mm_per_min)).collect()
    };
    prop_assert_eq!(moves(&h), moves(&b));
    prop_assert_eq!(h.blocks, b.blocks);
    // A name is one comment line, never more (an empty title is left out by the writer).
    if !name.is_empty() {
        prop_assert_eq!(&h.toolpath, &b.toolpath);
        prop_assert_eq!(h.lines, b.lines);
        prop_assert_eq!(h.comments.len(), b.comments.len());
    }
    prop_assert_eq!(&h.unsupported, &b.unsupported);
    prop_assert_eq!(ProgrammedPoint::from_comments(&h.comments), ProgrammedPoint::from_comments(&b.comments));
    for (line, c) in &h.comments {
        prop_assert!(!active_in_linuxcnc(c), "line {}: LinuxCNC would act on the comment {:?}", line, c);
        prop_assert!(c.len() <= MAX_COMMENT_CHARS + 1, "line {}: a comment of {} characters", line, c.len());
    }
    Ok(())
}

fn read(text: &str, dialect: Dialect) -> ParsedProgram {
    parse_program_in(text, dialect).expect("the benign program reads back")
}

fn preset_json(id: &str) -> &'static str {
    PRESETS.iter().find(|p| p.id == id).expect("preset").json
}

/// The floor-and-round-wall scene (its crease lies in a plane, so LinuxCNC's XY-only G5.2
/// can carry it too) under another name.
fn scene_named(name: &str) -> String {
    let mut v: serde_json::Value = serde_json::from_str(preset_json("floor-round-wall")).expect("json");
    v["name"] = name.into();
    v.to_string()
}

fn crease() -> &'static CreaseCurve {
    static C: OnceLock<CreaseCurve> = OnceLock::new();
    C.get_or_init(|| {
        let scene = Scene::from_json(preset_json("floor-round-wall")).expect("scene");
        crease_design(&CreaseJob::from_scene(&scene).expect("job")).expect("crease")
    })
}

const BENIGN: &str = "Floor and round wall (pocket corner, paper settings)";
const TOL_MM: f64 = 0.01;

fn options(dialect: Dialect, title: &str) -> ProgramOptions {
    ProgramOptions::default().with_dialect(dialect).with_title(title)
}

/// The nine crease programs written with the benign title, and with the tip as the
/// programmed point (so the header's key has a value a name could fake).
fn benign_programs() -> &'static Vec<(ProgramKind, Dialect, ProgramOptions, String)> {
    static P: OnceLock<Vec<(ProgramKind, Dialect, ProgramOptions, String)>> = OnceLock::new();
    P.get_or_init(|| {
        let mut out = Vec::new();
        for kind in ProgramKind::ALL {
            for dialect in Dialect::ALL {
                let opts = options(dialect, BENIGN).with_point(ProgrammedPoint::BallTip { radius_mm: 5.0 });
                let p = write_program(kind, crease(), TOL_MM, &opts).expect("benign program");
                out.push((kind, dialect, opts, p.text));
            }
        }
        out
    })
}

/// The finishing program of the bicubic patch example, planned once (its first paths).
fn finish_program() -> &'static FinishGcode {
    static F: OnceLock<FinishGcode> = OnceLock::new();
    F.get_or_init(|| {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finish/bicubic-patch.json"),
        )
        .expect("example");
        let job = FinishScene::from_json(&text).expect("finish scene").job().expect("job");
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        let mut set = iso_scallop(&job.setup(&part)).expect("paths");
        set.paths.truncate(4);
        FinishGcode::plan(&job.machine, &job.surface, &job.cutter, &set, job.options.feed_mm_per_min, 0.01)
            .expect("planned")
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// The comment function alone: any text is one comment on one line of the dialect,
    /// read back as exactly one comment and no block, holding no header key, no active
    /// comment, at most the cap.
    #[test]
    fn any_text_is_one_comment_of_any_dialect(text in hostile()) {
        for dialect in Dialect::ALL {
            let c = safe_comment(dialect, &text);
            prop_assert!(c.bytes().all(|b| (0x20..0x7f).contains(&b)), "{:?}", c);
            let body = match dialect {
                Dialect::Sinumerik => c.strip_prefix("; "),
                _ => c.strip_prefix('(').and_then(|b| b.strip_suffix(')')),
            };
            let body = body.unwrap_or_else(|| panic!("{dialect}: not delimited: {c:?}"));
            prop_assert!(!body.contains(['(', ')', ';', '%']), "{:?}", body);
            prop_assert!(body.len() <= MAX_COMMENT_CHARS);
            prop_assert_eq!(body, comment_text(&text));
            for key in HeaderKey::ALL {
                prop_assert!(!body.to_ascii_uppercase().contains(key.as_str()), "{:?}", body);
            }
            prop_assert!(!active_in_linuxcnc(body), "{:?}", body);
            let parsed = parse_program_in(&c, dialect);
            prop_assert!(parsed.is_ok(), "{:?}: {:?}", c, parsed.err());
            let parsed = parsed.unwrap_or_default();
            prop_assert_eq!(parsed.blocks, 0);
            prop_assert_eq!(parsed.comments.len(), 1);
            prop_assert_eq!(parsed.lines, 1);
        }
    }

    /// The crease writer, every kind and dialect: a hostile title changes no block.
    #[test]
    fn a_hostile_title_changes_no_block_of_a_crease_program(text in hostile()) {
        for (kind, dialect, opts, benign) in benign_programs() {
            let p = write_program(*kind, crease(), TOL_MM, &opts.clone().with_title(&text));
            prop_assert!(p.is_ok(), "{kind:?} {dialect}: {:?}", p.as_ref().err());
            let p = p.unwrap_or_else(|_| unreachable!());
            assert_same_blocks(&p.text, benign, *dialect, &text)?;
        }
    }

    /// The five-axis finishing program (`finish --gcode`): a hostile scene name changes no
    /// block, and the program reads back as FANUC, as `replay` and `simulate` read it.
    #[test]
    fn a_hostile_name_changes_no_block_of_the_finishing_program(text in hostile()) {
        let f = finish_program();
        assert_same_blocks(&f.text(&text), &f.text("Gently curved bicubic patch (seed 001)"), Dialect::Fanuc, &text)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, failure_persistence: None, ..ProptestConfig::default() })]

    /// The app's downloads: the NURBS & G-code tab's programs come from the `program-row`
    /// job, its request and output crossing as text (as to and from the Web Worker), the
    /// scene's name as the title. A hostile name changes no block of any of them.
    #[test]
    fn a_hostile_scene_name_changes_no_block_of_the_apps_programs(
        text in hostile(), kind in 0usize..3, dialect in 0usize..3,
    ) {
        let (kind, dialect) = (ProgramKind::ALL[kind], Dialect::ALL[dialect]);
        let program = |name: &str| -> String {
            let request = Request {
                design: DesignSpec::Scene(scene_named(name)),
                kind,
                tol_mm: TOL_MM,
                options: CompareOptions {
                    // As the tab: the scene's name is the title ("scene" when it has none).
                    program: options(dialect, if name.is_empty() { "scene" } else { name }),
                    ..CompareOptions::default()
                },
                // Not timed: the blocks are the question here.
                machine: None,
            };
            let out = run_encoded(ProgramRow::NAME, &ProgramRow::encode_request(&request), &mut NoProgress)
                .expect("the job runs");
            let row = ProgramRow::decode_output(&out).expect("decodes").expect("a program");
            row.row.program.text
        };
        assert_same_blocks(&program(&text), &program(BENIGN), dialect, &text)?;
    }

    /// A hostile name survives the scene file and the share link unchanged (JSON escapes it).
    #[test]
    fn a_hostile_name_survives_the_scene_file_and_the_share_link(text in hostile()) {
        let scene = Scene::from_json(&scene_named(&text)).expect("scene");
        prop_assert_eq!(&scene.name, &text);
        let again = Scene::from_json(&scene.to_json()).expect("written scene reads back");
        prop_assert_eq!(&again.name, &text);
        let linked = Scene::from_link_fragment(&scene.to_link_fragment()).expect("link").expect("a scene");
        prop_assert_eq!(&linked.name, &text);
        let stem = interpolab::scene::file_stem(&text);
        prop_assert!(stem.as_deref().is_none_or(|s| !s.is_empty()
            && s.len() <= interpolab::scene::MAX_FILE_STEM_CHARS
            && s.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-')
            && !s.starts_with('-') && !s.ends_with('-') && !s.contains("--")), "{:?}", stem);
    }
}

/// The issue's own case: the block a name tried to add is nowhere but in a comment.
#[test]
fn the_issues_name_is_a_comment_in_every_program() {
    let name = "Dome\nG0 X999 Y999 Z-50\n(x";
    let f = finish_program().text(name);
    assert!(f.starts_with("(interpolab finish: Dome G0 X999 Y999 Z-50 _x)\n"), "{}", &f[..80]);
    for (kind, dialect, opts, _) in benign_programs() {
        let p = write_program(*kind, crease(), TOL_MM, &opts.clone().with_title(name)).expect("program");
        let parsed = read(&p.text, *dialect);
        assert!(
            parsed.toolpath.blocks.iter().all(|b| b.segment.end().x.abs() < 999.0),
            "{kind:?} {dialect}: a move to X999 in\n{}",
            p.text
        );
        assert!(p.text.contains("DOME G0 X999 Y999 Z-50 _X"), "{}", p.text);
    }
}

/// What the cut leaves: a very long name is cut to the cap, and the program's first
/// comment ends with the mark.
#[test]
fn a_very_long_name_is_cut_to_the_cap() {
    let name = "x".repeat(100_000);
    let f = finish_program().text(&name);
    let first = f.lines().next().expect("a line");
    assert_eq!(first.len(), MAX_COMMENT_CHARS + 2);
    assert!(first.ends_with("...)"), "{first}");
}
