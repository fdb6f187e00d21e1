//! No program writer builds a comment itself: every comment of a written program comes from
//! `gcode::comment` (`safe_comment`, `key_comment`), which makes any text safe .
//! As `core_boundary.rs` scans the core for imports, this scans the writers' sources.
//!
//! The rule, checkable on the text: a *writer* is any source file whose string literals hold
//! a program's frame words (`G90`, `G21`, `G710`, `M30`) — found by scanning, so a new writer
//! cannot slip past — other than the readers (which must name those words to read them)
//! and the comment module itself. In a writer's code (comments and `#[cfg(test)]` modules
//! left out) no string or character literal may open or close a comment line: none may begin
//! with `(` or `;`, hold an escaped line break followed by `(` or `;` or preceded by `)`, or
//! be the character `(`, `)` or `;`. That is how a comment line is built by hand
//! (`"(interpolab finish: {})\n"`, `push('(')`, `"; "`), and the comment module is the one
//! file allowed to.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("readable source tree") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// A literal of the source: its line (1-based), whether it is a character literal, and its
/// text as written between the quotes (escapes left as written: `\n` is two characters).
#[derive(Debug)]
struct Literal {
    line: usize,
    is_char: bool,
    text: String,
}

/// The string, raw string, byte string and character literals of `code`, comments skipped;
/// scanning stops at the first `#[cfg(test)]` outside a literal (the test module).
fn literals(code: &str) -> Vec<Literal> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
            continue;
        }
        if ch == '/' && c.get(i + 1) == Some(&'/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
            continue;
        }
        if ch == '/' && c.get(i + 1) == Some(&'*') {
            i += 2;
            while i + 1 < c.len() && !(c[i] == '*' && c[i + 1] == '/') {
                if c[i] == '\n' {
                    line += 1;
                }
                i += 1;
            }
            i += 2;
            continue;
        }
        if ch == '#' && c[i..].iter().take(12).collect::<String>() == "#[cfg(test)]" {
            break;
        }
        // Raw strings: r"…", r#"…"#, br"…".
        if ch == 'r' && (i == 0 || !ident(c[i - 1]) || (c[i - 1] == 'b' && (i < 2 || !ident(c[i - 2])))) {
            let mut j = i + 1;
            while c.get(j) == Some(&'#') {
                j += 1;
            }
            if c.get(j) == Some(&'"') {
                let hashes = j - i - 1;
                let start = j + 1;
                let mut k = start;
                let close: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
                while k < c.len() && c[k..].iter().take(close.len()).collect::<String>() != close {
                    k += 1;
                }
                let text: String = c[start..k.min(c.len())].iter().collect();
                out.push(Literal { line, is_char: false, text: text.clone() });
                line += text.matches('\n').count();
                i = k + close.len();
                continue;
            }
        }
        if ch == '"' {
            let start = i + 1;
            let mut k = start;
            while k < c.len() && c[k] != '"' {
                if c[k] == '\\' {
                    k += 1;
                }
                k += 1;
            }
            let text: String = c[start..k.min(c.len())].iter().collect();
            out.push(Literal { line, is_char: false, text: text.clone() });
            line += text.matches('\n').count();
            i = k + 1;
            continue;
        }
        if ch == '\'' {
            // A character literal ('x', '\n', '\u{2028}') or a lifetime ('a).
            if c.get(i + 1) == Some(&'\\') {
                let mut k = i + 2;
                while k < c.len() && c[k] != '\'' {
                    k += 1;
                }
                out.push(Literal { line, is_char: true, text: c[i + 1..k].iter().collect() });
                i = k + 1;
                continue;
            }
            if c.get(i + 2) == Some(&'\'') {
                out.push(Literal { line, is_char: true, text: c[i + 1].to_string() });
                i += 3;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Why a literal builds a comment line by hand, if it does.
fn builds_comment(l: &Literal) -> Option<&'static str> {
    let t = l.text.as_str();
    if l.is_char {
        return matches!(t, "(" | ")" | ";").then_some("a comment delimiter as a character");
    }
    if t.starts_with('(') {
        return Some("a literal opening a comment");
    }
    if t.starts_with(';') {
        return Some("a literal opening a `;` comment");
    }
    if t.contains("\\n(") || t.contains("\\n;") {
        return Some("a line break followed by a comment opener");
    }
    if t.contains(")\\n") {
        return Some("a comment closer followed by a line break");
    }
    None
}

const FRAME_WORDS: [&str; 4] = ["G90", "G21", "G710", "M30"];

/// Files that name the frame words to read programs, not to write them; and the one file
/// that builds comments.
const NOT_WRITERS: [&str; 4] = ["gcode/parse.rs", "gcode/parse/spline.rs", "gcode/dialect.rs", "gcode/comment.rs"];

#[test]
fn no_writer_builds_a_comment_but_through_the_comment_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut writers = Vec::new();
    let mut problems = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).expect("under src").to_string_lossy().replace('\\', "/");
        if rel.ends_with("/tests.rs") || NOT_WRITERS.contains(&rel.as_str()) {
            continue;
        }
        let text = std::fs::read_to_string(f).expect("readable");
        let lits = literals(&text);
        if !lits.iter().any(|l| !l.is_char && FRAME_WORDS.iter().any(|w| l.text.contains(w))) {
            continue;
        }
        writers.push(rel.clone());
        for l in &lits {
            if let Some(why) = builds_comment(l) {
                problems.push(format!("src/{rel}:{}: {why}: {:?}", l.line, l.text));
            }
        }
    }
    // The writers this test must find: the seed-004 programs and the finishing program.
    for known in ["gcode/write.rs", "fillet/program.rs"] {
        assert!(writers.iter().any(|w| w == known), "the scan did not find the writer {known}; found {writers:?}");
    }
    assert!(
        problems.is_empty(),
        "program writers build comments themselves; write them with gcode::comment::safe_comment:\n{}",
        problems.join("\n")
    );
}

#[test]
fn the_scan_sees_a_comment_built_by_hand() {
    // The finishing writer as it was before issue 29, and the other ways of building one.
    let code = r###"
        let mut text = format!("(interpolab finish: {})\nG90 G21 G94\n", name);
        text.push_str(&format!("(pass {pi})\n"));
        text.push('(');
        out.push_str("; ");
        let s = r#"M30\n(end)"#;
        // a comment "(not code)" is not code
    "###;
    let lits = literals(code);
    let flagged: Vec<usize> = lits.iter().filter(|l| builds_comment(l).is_some()).map(|l| l.line).collect();
    assert_eq!(flagged, vec![2, 3, 4, 5, 6], "{lits:?}");
    assert!(lits.iter().any(|l| l.text.contains("G90")));
    // Benign literals: words, numbers, an opening parenthesis inside a message.
    let ok = literals(r#"let m = format!("{word} X{:.4}", x); let e = "cannot write (disk full)"; let c = 'x';"#);
    assert!(ok.iter().all(|l| builds_comment(l).is_none()), "{ok:?}");
}

#[test]
fn tests_modules_are_not_scanned() {
    let lits = literals("let a = \"G90\";\n#[cfg(test)]\nmod tests { const P: &str = \"(x)\\nG90\"; }");
    assert_eq!(lits.len(), 1);
}
