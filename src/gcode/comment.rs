//! The one way text enters a program: as a comment made safe for the dialect.
//!
//! Every comment a writer of ours puts in a program — a scene's or job's name, a title, a
//! cutter's description, the writer's own header lines — is built here, by
//! [`safe_comment`] (any text) or [`key_comment`] (the header keys the readers look for), and
//! nowhere else (`tests/boundary/comments.rs` scans the writers for comment delimiters). So no
//! text, whoever wrote it, can end the comment early, start a new block, or hide a line
//! break the control would honour: a scene named `"Dome\nG0 X999 Y999 Z-50\n(x"` is the
//! comment `(DOME G0 X999 Y999 Z-50  _X)`, never a rapid move.
//!
//! The rule, the same for every dialect (a program is often carried from one control to
//! another by hand), character by character:
//!
//! | text | becomes | why |
//! |---|---|---|
//! | printable ASCII, space | itself | |
//! | `(` `)` | `_` | FANUC and LinuxCNC comment delimiters: a `)` ends the comment, a `(` inside one is refused (LinuxCNC: nested comment) |
//! | `;` | `_` | Sinumerik's and LinuxCNC's comment to the end of the line; FANUC's end of block as printed |
//! | `%` | `_` | the tape mark: at a line's start it ends the program, and a FANUC control reading through its serial port stops at the first `%` anywhere |
//! | any line break or white space: LF, CR, VT, FF, TAB, NEL U+0085, U+2028, U+2029, NBSP … | space | every one of them ends a line for some control, editor or transfer program |
//! | other control characters: C0, DEL, C1 | `_` | |
//! | any other character outside ASCII | `_` | controls read ISO/ASCII program text: FANUC's character set is ASCII, Sinumerik and LinuxCNC take other bytes but their screens and file transfers do not promise them; one `_` per character keeps the length visible |
//!
//! Then two kinds of text that are comments to us but more than comments to a reader:
//! - **LinuxCNC's active comments.** LinuxCNC acts on a comment that begins (after spaces,
//!   in any case) with `MSG,` `DEBUG,` `PRINT,` `LOG,` `LOGOPEN,` `LOGAPPEND,` `LOGCLOSE`
//!   `PY,` `PYRUN,` `PYRELOAD` or `ABORT,` (its interpreter's `convert_comment`: a message,
//!   a file opened for writing, Python run, the program aborted), and its AXIS screen on
//!   `AXIS,`; older versions on `PROBEOPEN`/`PROBECLOSE`. Such a text gets a leading `_`
//!   (`(_MSG, HELLO)`), so it stays a plain comment. Spaces before the comma are ignored
//!   when matching, so `MSG ,` is caught too.
//! - **Our own header keys** ([`HeaderKey`]: `DIALECT:` read by [`super::Dialect::guess`],
//!   `PROGRAMMED POINT:` read by [`super::ProgrammedPoint::from_comments`]). In any text but
//!   [`key_comment`]'s key their colon becomes `=` (`DIALECT= SINUMERIK`), so a name cannot
//!   change the dialect a program is read in or the point it is said to carry.
//!
//! Last, the text is capped at [`crate::numerics::limits::MAX_COMMENT_CHARS`] characters (the last
//! three `...` when cut): a comment line is then at most that plus its delimiters, well under
//! LinuxCNC's 256-character line and Sinumerik's 512. The work is bounded by the cap too:
//! at most that many characters of a text are looked at.
//!
//! Letter case is kept: the writers of seed 004 upper-case their whole program first (as
//! FANUC programs are written), the finishing program keeps lower case as before.

use super::dialect::{Dialect, HeaderKey};
use crate::numerics::limits::MAX_COMMENT_CHARS;

/// What a cut text ends with.
const CUT_MARK: &str = "...";

/// Starts of a comment that LinuxCNC (or its AXIS screen) acts on, lower case, spaces
/// removed (module docs).
const ACTIVE_STARTS: [&str; 14] = [
    "msg,",
    "debug,",
    "print,",
    "log,",
    "logopen,",
    "logappend,",
    "logclose",
    "py,",
    "pyrun,",
    "pyreload",
    "abort,",
    "probeopen",
    "probeclose",
    "axis,",
];

/// `text` as one whole comment of `dialect`, delimiters included, no line break: `(TEXT)`
/// for FANUC and LinuxCNC, `; TEXT` for Sinumerik, by the rule of the module docs. Any
/// text at all gives a comment that the dialect's control and [`super::parse_program_in`]
/// read as one comment on one line, holding no header key and no active comment.
///
/// ```
/// use interpolab::gcode::{Dialect, comment::safe_comment};
/// assert_eq!(safe_comment(Dialect::Fanuc, "Dome\nG0 X999 (x"), "(Dome G0 X999 _x)");
/// assert_eq!(safe_comment(Dialect::Sinumerik, "a;b\u{2028}c"), "; a_b c");
/// assert_eq!(safe_comment(Dialect::LinuxCnc, " msg, hi"), "( _msg, hi)");
/// ```
#[must_use]
pub fn safe_comment(dialect: Dialect, text: &str) -> String {
    delimit(dialect, &comment_text(text))
}

/// `text` made safe for the inside of a comment, without delimiters: what
/// [`safe_comment`] puts between them.
#[must_use]
pub fn comment_text(text: &str) -> String {
    let mut body = clean(text, MAX_COMMENT_CHARS);
    defuse_keys(&mut body);
    defuse_active(&mut body);
    body
}

/// A header comment the product's readers look for: `key` and `value` (`(DIALECT:
/// SINUMERIK)`); the value passes the same rule as [`safe_comment`].
#[must_use]
pub fn key_comment(dialect: Dialect, key: HeaderKey, value: &str) -> String {
    let value = clean(value, MAX_COMMENT_CHARS.saturating_sub(key.as_str().len() + 1));
    let mut value = value;
    defuse_keys(&mut value);
    delimit(dialect, &format!("{} {value}", key.as_str()))
}

fn delimit(dialect: Dialect, body: &str) -> String {
    match dialect {
        Dialect::Sinumerik => format!("; {body}"),
        Dialect::Fanuc | Dialect::LinuxCnc => format!("({body})"),
    }
}

/// One character of a comment by the table of the module docs.
fn safe_char(c: char) -> char {
    match c {
        '(' | ')' | ';' | '%' => '_',
        ' ' => ' ',
        c if c.is_ascii_graphic() => c,
        c if c.is_whitespace() => ' ',
        _ => '_',
    }
}

/// The characters of `text` by [`safe_char`], at most `cap` of them (the last three
/// [`CUT_MARK`] when the text was longer). Looks at no more than `cap + 1` characters.
fn clean(text: &str, cap: usize) -> String {
    let mut out = String::with_capacity(cap.min(text.len()));
    for (n, c) in text.chars().enumerate() {
        if n == cap {
            let keep = cap.saturating_sub(CUT_MARK.len());
            out.truncate(keep);
            out.push_str(&CUT_MARK[..cap.min(CUT_MARK.len())]);
            return out;
        }
        out.push(safe_char(c));
    }
    out
}

/// Every header key in `body` (ASCII, any case) loses its colon to `=`.
fn defuse_keys(body: &mut String) {
    for key in HeaderKey::ALL {
        let k = key.as_str();
        let mut from = 0;
        while let Some(at) = find_ascii_ci(&body[from..], k) {
            let colon = from + at + k.len() - 1;
            body.replace_range(colon..=colon, "=");
            from = colon + 1;
        }
    }
}

/// A leading `_` for a body LinuxCNC would act on (module docs).
fn defuse_active(body: &mut String) {
    let start = body.len() - body.trim_start_matches(' ').len();
    let squeezed: String =
        body[start..].chars().filter(|c| *c != ' ').take(16).map(|c| c.to_ascii_lowercase()).collect();
    if ACTIVE_STARTS.iter().any(|a| squeezed.starts_with(a)) {
        body.insert(start, '_');
        if body.len() > MAX_COMMENT_CHARS {
            // Stay within the cap: cut again, with the mark.
            body.truncate(MAX_COMMENT_CHARS - CUT_MARK.len());
            body.push_str(CUT_MARK);
        }
    }
}

/// Byte offset of the first case-insensitive occurrence of the ASCII `needle` in the ASCII
/// `hay`.
fn find_ascii_ci(hay: &str, needle: &str) -> Option<usize> {
    let (h, n) = (hay.as_bytes(), needle.as_bytes());
    if n.is_empty() || h.len() < n.len() {
        return None;
    }
    (0..=h.len() - n.len()).find(|&i| h[i..i + n.len()].eq_ignore_ascii_case(n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_line_break_and_control_character_becomes_one_character_of_the_line() {
        for c in ['\n', '\r', '\u{b}', '\u{c}', '\t', '\u{85}', '\u{2028}', '\u{2029}'] {
            assert_eq!(comment_text(&format!("a{c}b")), "a b", "{:?}", c);
        }
        for c in ['\0', '\u{1b}', '\u{7f}', '\u{80}', '\u{9f}', 'é', '°', '\u{202e}', '\u{feff}', '😀'] {
            assert_eq!(comment_text(&format!("a{c}b")), "a_b", "{:?}", c);
        }
    }

    #[test]
    fn delimiters_and_tape_marks_are_replaced_in_every_dialect() {
        for d in Dialect::ALL {
            let c = safe_comment(d, "x) G0 X9 (y; z % w");
            let body = c.strip_prefix('(').and_then(|b| b.strip_suffix(')')).or_else(|| c.strip_prefix("; "));
            assert_eq!(body, Some("x_ G0 X9 _y_ z _ w"), "{d}: {c}");
        }
    }

    #[test]
    fn active_comments_and_header_keys_are_defused() {
        assert_eq!(comment_text("MSG,hi"), "_MSG,hi");
        assert_eq!(comment_text("  Py ,import os"), "  _Py ,import os");
        assert_eq!(comment_text("pyreloaded"), "_pyreloaded");
        assert_eq!(comment_text("message"), "message");
        assert_eq!(comment_text("a dialect: sinumerik b"), "a dialect= sinumerik b");
        assert_eq!(comment_text("Programmed Point: BALL TIP"), "Programmed Point= BALL TIP");
        assert_eq!(key_comment(Dialect::Sinumerik, HeaderKey::Dialect, "SINUMERIK"), "; DIALECT: SINUMERIK");
    }

    #[test]
    fn long_text_is_cut_to_the_cap_with_a_mark() {
        let long = "A".repeat(10 * MAX_COMMENT_CHARS);
        let t = comment_text(&long);
        assert_eq!(t.len(), MAX_COMMENT_CHARS);
        assert!(t.ends_with(CUT_MARK));
        let exact = "B".repeat(MAX_COMMENT_CHARS);
        assert_eq!(comment_text(&exact), exact);
        let active = format!("msg,{}", "C".repeat(MAX_COMMENT_CHARS));
        assert_eq!(comment_text(&active).len(), MAX_COMMENT_CHARS);
    }
}
