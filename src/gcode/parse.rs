//! Reading G-code: the programs we write and common hand-written ones — comments `( … )`
//! and `; …`, line numbers `N`, program numbers `O`, `%` tape marks, block delete `/`,
//! lower-case letters, spaces inside words, modal motion, plane, units and distance mode.
//!
//! Supported motion: G00, G01, G02/G03 (centre by I/J/K offsets from the start, or radius R,
//! negative R for more than 180°; helical when the normal axis moves) in G17/G18/G19, and
//! FANUC-style G06.2 NURBS (see `docs/nurbs-gcode.md`): the first block
//! `G06.2 [P order] [K knot] X Y Z [R weight] [F feed]`, one `K X Y Z [R]` block per further
//! control point (omitted axes keep the previous control point's value, an omitted weight
//! is 1), then exactly `order` blocks holding only `K`. The knots must be non-decreasing, the
//! first `order` and last `order` equal (FANUC alarm 1007), and the first control point is the
//! current position.
//!
//! Words with no effect on the path (spindle, coolant, tool number, feed mode G94, work
//! offset G54–G59, cancel codes G40/G49/G80, path modes G61/G64, dwell G04, high-speed modes
//! G05/G05.1, program end) are accepted. Words that would change the path but are not
//! modelled (cutter compensation, tool length offsets, canned cycles, coordinate rotation,
//! subprograms, extra axes …) are **reported** with their line ([`Unsupported`]) and their
//! effect is left out; the path is rebuilt from the rest. Malformed programs are errors
//! ([`ParseError`]) naming the line and what to change.
//!
//! The position before the first move is the origin (as a simulator without machine
//! position assumes); a program should start with a G00 positioning move. Numbers without a
//! decimal point are millimetres (`X10` = 10 mm, calculator-style input), not input
//! increments.

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

mod spline;

use glam::DVec3;
use thiserror::Error;

use super::dialect::Dialect;
use super::path::{ArcMove, LineMove, Motion, PathBlock, Plane, Segment, Toolpath};
use crate::geom::nurbs::MAX_DEGREE;
use crate::geom::{NurbsCurve, NurbsError};
use crate::numerics::tolerance;

/// A malformed program. Lines are 1-based.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ParseError {
    /// A `(` comment is not closed on its line.
    #[error("line {line}: the comment opened at column {col} is not closed; add ')' before the end of the line")]
    UnclosedComment {
        /// Line.
        line: usize,
        /// Column of the `(`.
        col: usize,
    },
    /// A word's value is not a number.
    #[error("line {line}: '{text}' is not a number after {letter}; write e.g. {letter}12.5")]
    BadNumber {
        /// Line.
        line: usize,
        /// The letter.
        letter: char,
        /// What was written.
        text: String,
    },
    /// A letter without a value.
    #[error("line {line}: the letter {letter} has no value; every word is a letter and a number, e.g. {letter}0")]
    MissingValue {
        /// Line.
        line: usize,
        /// The letter.
        letter: char,
    },
    /// A character that is not part of a word.
    #[error("line {line}: unexpected '{ch}' at column {col}{}", if matches!(ch, '#' | '[' | ']' | '=') { "; macro variables and expressions are not supported — write plain numbers" } else { "; a block is made of letter–number words" })]
    UnexpectedChar {
        /// Line.
        line: usize,
        /// Column.
        col: usize,
        /// The character.
        ch: char,
    },
    /// The same letter twice in one block.
    #[error("line {line}: {letter} appears twice in one block; keep one")]
    RepeatedWord {
        /// Line.
        line: usize,
        /// The letter.
        letter: char,
    },
    /// Two motion codes in one block.
    #[error("line {line}: {first} and {second} in the same block; a block has one motion code")]
    ConflictingMotion {
        /// Line.
        line: usize,
        /// First code.
        first: &'static str,
        /// Second code.
        second: &'static str,
    },
    /// Axis words before any motion code.
    #[error("line {line}: axis words but no motion mode yet; give G00, G01, G02, G03 or G06.2 first")]
    NoMotionMode {
        /// Line.
        line: usize,
    },
    /// A cutting move without a feed.
    #[error("line {line}: {code} move without a feed rate; give F (mm/min) on this or an earlier block")]
    MissingFeed {
        /// Line.
        line: usize,
        /// G code.
        code: &'static str,
    },
    /// F not positive.
    #[error("line {line}: feed F{value} must be positive")]
    BadFeed {
        /// Line.
        line: usize,
        /// Value.
        value: f64,
    },
    /// A number too large for a double (it would read as infinity).
    #[error(
        "line {line}: the {digits}-character number after {letter} is too large to be a value (beyond 1.8e308); check the line for a corrupted number"
    )]
    NumberTooLarge {
        /// Line.
        line: usize,
        /// The address letter.
        letter: char,
        /// Characters of the number as written.
        digits: usize,
    },
    /// Arc without centre or radius.
    #[error("line {line}: {code} needs the centre (I, J, K offsets from the start) or a radius R")]
    ArcNoCentre {
        /// Line.
        line: usize,
        /// G code.
        code: &'static str,
    },
    /// Start and end radius differ.
    #[error(
        "line {line}: the arc's end is not on its circle: radius {start_r:.4} mm at the start, {end_r:.4} mm at the end; correct the end point or the centre offsets"
    )]
    ArcRadius {
        /// Line.
        line: usize,
        /// Start radius.
        start_r: f64,
        /// End radius.
        end_r: f64,
    },
    /// R smaller than half the chord.
    #[error(
        "line {line}: radius R{r} is smaller than half the distance to the end point ({half_chord:.4} mm); no such arc exists"
    )]
    ArcRadiusTooSmall {
        /// Line.
        line: usize,
        /// R.
        r: f64,
        /// Half chord.
        half_chord: f64,
    },
    /// Arc of zero radius, or an R arc returning to its start.
    #[error("line {line}: degenerate arc ({what}); check the centre offsets and the end point")]
    ArcDegenerate {
        /// Line.
        line: usize,
        /// What is degenerate.
        what: &'static str,
    },
    /// G06.2 order out of range.
    #[error("line {line}: G06.2 order P{order} is not supported; use P2 to P{} (FANUC: P2 to P4)", MAX_DEGREE + 1)]
    NurbsOrder {
        /// Line.
        line: usize,
        /// P.
        order: f64,
    },
    /// A control-point block without K.
    #[error("line {line}: G06.2 control point without a knot K; every NURBS block carries one knot")]
    NurbsMissingKnot {
        /// Line.
        line: usize,
    },
    /// A knot smaller than the one before.
    #[error("line {line}: knot K{value} is smaller than the previous knot {previous}; knots must be non-decreasing")]
    NurbsKnotDecreasing {
        /// Line.
        line: usize,
        /// Value.
        value: f64,
        /// Previous knot.
        previous: f64,
    },
    /// First or last `order` knots not equal.
    #[error("line {line}: the {end} {order} knots of the G06.2 curve must be equal (clamped; FANUC alarm 1007)")]
    NurbsNotClamped {
        /// Line of the G06.2 word.
        line: usize,
        /// "first" or "last".
        end: &'static str,
        /// The order.
        order: usize,
    },
    /// First control point away from the current position.
    #[error(
        "line {line}: the first control point {first:?} is not the current position {position:?}; a G06.2 curve starts where the previous move ended"
    )]
    NurbsStartMismatch {
        /// Line.
        line: usize,
        /// First control point.
        first: [f64; 3],
        /// Current position.
        position: [f64; 3],
    },
    /// The curve ended before its closing knots.
    #[error(
        "line {line}: the G06.2 curve started here has {closing} closing knot blocks but order {order} needs {order}; end it with {order} blocks holding only K"
    )]
    NurbsIncomplete {
        /// Line of the G06.2 word.
        line: usize,
        /// Closing K blocks given.
        closing: usize,
        /// The order.
        order: usize,
    },
    /// A control point after closing knots began.
    #[error(
        "line {line}: control point after the closing knot blocks of the G06.2 curve; the closing K-only blocks come last"
    )]
    NurbsAfterEnd {
        /// Line.
        line: usize,
    },
    /// G06.2 in incremental mode.
    #[error("line {line}: G06.2 needs absolute coordinates; add G90 before it")]
    NurbsIncremental {
        /// Line.
        line: usize,
    },
    /// A non-positive weight.
    #[error("line {line}: weight R{value} must be positive")]
    NurbsWeight {
        /// Line.
        line: usize,
        /// Value.
        value: f64,
    },
    /// A dialect's spline (Sinumerik `BSPLINE`, LinuxCNC `G5.2`/`G5.3`) is malformed.
    #[error("line {line}: {what}")]
    Spline {
        /// Line.
        line: usize,
        /// What is wrong and what to change.
        what: String,
    },
    /// More moves than a path holds.
    #[error("line {line}: more than {max} moves; the program is too large to hold as one path — split it")]
    TooManyMoves {
        /// The line of the first move over the cap.
        line: usize,
        /// The cap.
        max: usize,
    },
    /// The interpreter could not read on ([`crate::gcode::interp`]).
    #[error("{0}")]
    Interp(crate::gcode::interp::InterpError),
    /// The NURBS is invalid otherwise.
    #[error("line {line}: invalid G06.2 curve: {source}")]
    Nurbs {
        /// Line of the G06.2 word.
        line: usize,
        /// What is wrong.
        source: NurbsError,
    },
}

impl ParseError {
    /// The 1-based line the error is about (the one its message starts with), so a viewer
    /// can point at it.
    #[must_use]
    pub fn line(&self) -> usize {
        match self {
            Self::UnclosedComment { line, .. }
            | Self::BadNumber { line, .. }
            | Self::NumberTooLarge { line, .. }
            | Self::MissingValue { line, .. }
            | Self::UnexpectedChar { line, .. }
            | Self::RepeatedWord { line, .. }
            | Self::ConflictingMotion { line, .. }
            | Self::NoMotionMode { line, .. }
            | Self::MissingFeed { line, .. }
            | Self::BadFeed { line, .. }
            | Self::ArcNoCentre { line, .. }
            | Self::ArcRadius { line, .. }
            | Self::ArcRadiusTooSmall { line, .. }
            | Self::ArcDegenerate { line, .. }
            | Self::NurbsOrder { line, .. }
            | Self::NurbsMissingKnot { line, .. }
            | Self::NurbsKnotDecreasing { line, .. }
            | Self::NurbsNotClamped { line, .. }
            | Self::NurbsStartMismatch { line, .. }
            | Self::NurbsIncomplete { line, .. }
            | Self::NurbsAfterEnd { line, .. }
            | Self::NurbsIncremental { line, .. }
            | Self::NurbsWeight { line, .. }
            | Self::Spline { line, .. }
            | Self::Nurbs { line, .. } => *line,
            Self::Interp(e) => e.loc.line as usize,
            Self::TooManyMoves { line, .. } => *line,
        }
    }
}

/// A word that changes the path but is not modelled (its effect is left out), or a line
/// skipped: reported once per code with its first line and count.
#[derive(Clone, Debug, PartialEq)]
pub struct Unsupported {
    /// 1-based line where it first occurs.
    pub line: usize,
    /// The word as written (upper case), e.g. `G41`.
    pub word: String,
    /// What it does that is not modelled.
    pub reason: String,
    /// Times it occurs.
    pub count: u64,
}

/// A parsed program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParsedProgram {
    /// The moves.
    pub toolpath: Toolpath,
    /// Words reported as not modelled.
    pub unsupported: Vec<Unsupported>,
    /// Notes on the reading (line, text), e.g. an inch-looking program with no units word.
    pub warnings: Vec<(usize, String)>,
    /// Comments with their lines (text without the delimiters).
    pub comments: Vec<(usize, String)>,
    /// Lines of the text.
    pub lines: usize,
    /// Blocks holding at least one word.
    pub blocks: usize,
    /// The dialect it was read in.
    pub dialect: Dialect,
    /// The largest LinuxCNC `G64 P` path-blending tolerance programmed (mm): the control may
    /// leave the programmed path by up to this much at junctions.
    pub blend_mm: Option<f64>,
}

impl ParsedProgram {
    /// Number of blocks of each motion kind that describe the cut (G01, G02, G03, and every
    /// block of a G06.2 curve: control points plus closing knots).
    #[must_use]
    pub fn path_blocks(&self) -> usize {
        self.toolpath
            .cuts()
            .map(|b| match &b.segment {
                Segment::Nurbs(c) => self.dialect.nurbs_blocks(c),
                _ => 1,
            })
            .sum()
    }
}

#[derive(Clone, Debug)]
struct Word {
    letter: char,
    value: f64,
    /// Value as written (for reports).
    text: String,
    /// A Sinumerik named word or keyword (`SD`, `PL`, `PW`, `BSPLINE`), upper case.
    name: Option<String>,
}

/// Splits one line into words and comments.
fn tokenize(
    line_no: usize,
    raw: &str,
    comments: &mut Vec<(usize, String)>,
    dialect: Dialect,
) -> Result<Vec<Word>, ParseError> {
    let chars: Vec<char> = raw.chars().collect();
    let mut words = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '(' {
            let start = i;
            let mut j = i + 1;
            while j < chars.len() && chars[j] != ')' {
                j += 1;
            }
            if j >= chars.len() {
                return Err(ParseError::UnclosedComment { line: line_no, col: start + 1 });
            }
            comments.push((line_no, chars[start + 1..j].iter().collect()));
            i = j + 1;
            continue;
        }
        if c == ';' {
            comments.push((line_no, chars[i + 1..].iter().collect()));
            break;
        }
        if c.is_whitespace() || (c == '/' && words.is_empty()) || (c == '%' && words.is_empty() && raw.trim() == "%") {
            i += 1;
            continue;
        }
        if !c.is_ascii_alphabetic() {
            return Err(ParseError::UnexpectedChar { line: line_no, col: i + 1, ch: c });
        }
        let letter = c.to_ascii_uppercase();
        if dialect == Dialect::Sinumerik && chars.get(i + 1).is_some_and(|n| n.is_ascii_alphabetic() || *n == '=') {
            words.push(spline::sinumerik_word(line_no, &chars, &mut i)?);
            continue;
        }
        i += 1;
        while i < chars.len() && (chars[i] == ' ' || chars[i] == '\t') {
            i += 1;
        }
        if i < chars.len() && matches!(chars[i], '#' | '[') {
            return Err(ParseError::UnexpectedChar { line: line_no, col: i + 1, ch: chars[i] });
        }
        let start = i;
        while i < chars.len()
            && (chars[i].is_ascii_digit() || chars[i] == '.' || ((chars[i] == '-' || chars[i] == '+') && i == start))
        {
            i += 1;
        }
        let text: String = chars[start..i].iter().collect();
        if text.is_empty() {
            return Err(ParseError::MissingValue { line: line_no, letter });
        }
        let value: f64 = match text.parse::<f64>() {
            Ok(v) if v.is_finite() && text.chars().any(|c| c.is_ascii_digit()) => v,
            Ok(v) if !v.is_finite() => {
                return Err(ParseError::NumberTooLarge { line: line_no, letter, digits: text.len() });
            }
            _ => {
                return Err(ParseError::BadNumber { line: line_no, letter, text });
            }
        };
        words.push(Word { letter, value, text, name: None });
    }
    Ok(words)
}

/// A G code as tenths (G06.2 → 62, G1 → 10).
fn g_tenths(v: f64) -> i64 {
    (v * 10.0).round() as i64
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Units {
    Mm,
    Inch,
}

/// A G06.2 curve being read.
struct NurbsBuild {
    line: usize,
    order: usize,
    knots: Vec<f64>,
    points: Vec<DVec3>,
    weights: Vec<f64>,
    closing: usize,
    /// The first block omitted K: take the second block's.
    first_knot_missing: bool,
    feed: f64,
}

struct State {
    pos: DVec3,
    motion: Option<Motion>,
    plane: Plane,
    units: Units,
    absolute: bool,
    feed: Option<f64>,
    nurbs: Option<NurbsBuild>,
    dialect: Dialect,
    /// A Sinumerik `BSPLINE` or LinuxCNC `G5.2` curve being read.
    spline: Option<spline::SplineBuild>,
}

/// G codes (in tenths: G54.1 → 541) with no effect on the path: G08/G09 look-ahead and exact
/// stop, G13.1/G15 polar cancels, G40 compensation cancel, G49 length offset cancel, G50
/// scaling cancel, G54–G59 and G54.1 work offsets, G61/G61.1/G64 path modes, G67 macro
/// cancel, G69 rotation cancel, G80 cycle cancel, G94 feed per minute, G98/G99 return level.
const HARMLESS_G: &[i64] =
    &[80, 90, 131, 150, 400, 490, 500, 540, 541, 550, 560, 570, 580, 590, 610, 611, 640, 670, 690, 800, 940, 980, 990];

fn unsupported_g(t: i64) -> &'static str {
    match t {
        280 | 290 | 300 => "reference-point return moves through an intermediate point",
        410 | 420 => "cutter radius compensation offsets the path",
        430 | 440 | 435 | 436 => "tool length compensation offsets Z by a stored length",
        520 | 920 | 921 => "a local or temporary coordinate system shifts the following moves",
        530 => "moves in machine coordinates",
        510 | 511 => "scaling or mirroring changes the path",
        680 | 681 => "coordinate rotation turns the path",
        160 => "polar coordinate input",
        901 => "absolute arc centres (G90.1) are not supported; use incremental I, J, K",
        950 => "feed per revolution",
        70..=79 => "this G code is not modelled",
        730 | 740 | 760 | 810..=890 => "canned cycles expand into moves that are not modelled",
        _ => "this G code is not modelled",
    }
}

fn unsupported_m(m: i64) -> Option<&'static str> {
    match m {
        0..=9 | 30 | 48 | 49 => None,
        98 | 99 => Some("subprogram calls and returns are not followed"),
        _ => Some("this M code is not modelled"),
    }
}

/// The reader of Sinumerik programs (and, before the interpreter, of every dialect).
pub(crate) fn parse_dialect_reader(text: &str, dialect: Dialect) -> Result<ParsedProgram, ParseError> {
    let mut out = ParsedProgram { dialect, ..ParsedProgram::default() };
    let mut st = State {
        pos: DVec3::ZERO,
        motion: None,
        plane: Plane::Xy,
        units: Units::Mm,
        absolute: true,
        feed: None,
        nurbs: None,
        dialect,
        spline: None,
    };
    for (idx, raw) in text.lines().enumerate() {
        let line = idx + 1;
        let words = tokenize(line, raw, &mut out.comments, dialect)?;
        if words.is_empty() {
            continue;
        }
        out.blocks += 1;
        block(line, &words, &mut st, &mut out)?;
    }
    out.lines = text.lines().count();
    if let Some(nb) = st.nurbs.take() {
        finish_nurbs(nb, &mut st, &mut out)?;
    }
    spline::end_of_program(&mut st, &mut out)?;
    Ok(out)
}

fn block(line: usize, words: &[Word], st: &mut State, out: &mut ParsedProgram) -> Result<(), ParseError> {
    let named = spline::named_words(line, words, out)?;
    let plain: Vec<Word> = words.iter().filter(|w| w.name.is_none()).cloned().collect();
    let words = &plain[..];
    let mut flags = spline::Flags::default();
    // One value per letter (G and M may repeat).
    let mut seen = [false; 26];
    let mut motion: Option<Motion> = None;
    let mut dwell = false;
    let mut consumes_p = false;
    let mut consumes_q = false;
    // An unmodelled code that moves the tool by itself (cycle, reference return, machine
    // coordinates) or redefines coordinates: its block's axis words are left out with it.
    let mut skip_axes = false;
    for w in words {
        let li = (w.letter as u8 - b'A') as usize;
        match w.letter {
            'G' => {
                let t = g_tenths(w.value);
                if spline::dialect_g(line, &w.text, t, st, &mut flags, out) {
                    continue;
                }
                let m = match t {
                    0 => Some(Motion::Rapid),
                    10 => Some(Motion::Linear),
                    20 => Some(Motion::ArcCw),
                    30 => Some(Motion::ArcCcw),
                    62 => Some(Motion::Nurbs),
                    _ => None,
                };
                if let Some(m) = m {
                    if let Some(prev) = motion {
                        return Err(ParseError::ConflictingMotion { line, first: prev.gcode(), second: m.gcode() });
                    }
                    motion = Some(m);
                    continue;
                }
                match t {
                    170 => st.plane = Plane::Xy,
                    180 => st.plane = Plane::Zx,
                    190 => st.plane = Plane::Yz,
                    200 => st.units = Units::Inch,
                    210 => st.units = Units::Mm,
                    900 => st.absolute = true,
                    910 => st.absolute = false,
                    40 => dwell = true,
                    50 => consumes_p = true,
                    51 => consumes_q = true,
                    _ if HARMLESS_G.contains(&t) => {}
                    _ => {
                        skip_axes |= matches!(t, 280 | 290 | 300 | 530 | 520 | 730 | 740 | 760 | 810..=890 | 920 | 921);
                        out.unsupported.push(Unsupported {
                            line,
                            word: format!("G{}", w.text),
                            reason: unsupported_g(t).into(),
                            count: 1,
                        });
                    }
                }
            }
            'M' => {
                let m = w.value.round() as i64;
                if let Some(reason) = unsupported_m(m) {
                    out.unsupported.push(Unsupported {
                        line,
                        word: format!("M{}", w.text),
                        reason: reason.into(),
                        count: 1,
                    });
                }
            }
            _ => {
                if seen[li] {
                    return Err(ParseError::RepeatedWord { line, letter: w.letter });
                }
                seen[li] = true;
            }
        }
    }
    consumes_p |= flags.blend;
    consumes_q |= flags.blend;
    let get = |l: char| words.iter().find(|w| w.letter == l).map(|w| w.value);
    let scale = if st.units == Units::Inch { 25.4 } else { 1.0 };
    if let Some(f) = get('F') {
        if !(f > 0.0 && f.is_finite()) {
            return Err(ParseError::BadFeed { line, value: f });
        }
        st.feed = Some(f * scale);
    }
    // Letters that are never modelled, whatever the mode.
    for w in words {
        let reason = match w.letter {
            'A' | 'B' | 'C' | 'U' | 'V' | 'W' => Some("extra axes are not modelled"),
            'E' => Some("this address is not modelled"),
            'L' if !spline::takes_l(st, &flags) => Some("this address is not modelled"),
            'Q' if !consumes_q => Some("this address is not modelled"),
            _ => None,
        };
        if let Some(reason) = reason {
            out.unsupported.push(Unsupported {
                line,
                word: format!("{}{}", w.letter, w.text),
                reason: reason.into(),
                count: 1,
            });
        }
    }
    if dwell || skip_axes {
        // G04 X/P is a time, not a move; a skipped code takes its block's words with it.
        return Ok(());
    }
    if spline::block(line, &get, motion, &named, &flags, st, out)? {
        return Ok(());
    }
    let nurbs_mode = st.nurbs.is_some();
    if let Some(m) = motion {
        if let Some(nb) = st.nurbs.take() {
            // A new motion code ends the curve being read (an error if it is incomplete).
            finish_nurbs(nb, st, out)?;
        }
        st.motion = Some(m);
        if m == Motion::Nurbs {
            return start_nurbs(line, st, &get);
        }
    } else if nurbs_mode {
        return nurbs_block(line, &get, st, out);
    } else if st.motion == Some(Motion::Nurbs) && get('K').is_some() {
        return Err(ParseError::NurbsAfterEnd { line });
    }
    if get('P').is_some() && !consumes_p {
        out.unsupported.push(Unsupported {
            line,
            word: "P".into(),
            reason: "P outside G04/G05/G06.2 is not modelled".into(),
            count: 1,
        });
    }
    let has_axis = ['X', 'Y', 'Z'].iter().any(|&l| get(l).is_some());
    if !has_axis {
        return Ok(());
    }
    let Some(m) = st.motion else {
        return Err(ParseError::NoMotionMode { line });
    };
    if m == Motion::Nurbs {
        // G06.2 finished with its closing knots; more coordinates need a new mode.
        return Err(ParseError::NurbsAfterEnd { line });
    }
    let mut end = if st.absolute { st.pos } else { DVec3::ZERO };
    for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = get(l) {
            end[i] = v * scale;
        }
    }
    if !st.absolute {
        end += st.pos;
    }
    let start = st.pos;
    let feed =
        if m == Motion::Rapid { None } else { Some(st.feed.ok_or(ParseError::MissingFeed { line, code: m.gcode() })?) };
    if matches!(m, Motion::Rapid | Motion::Linear) {
        for l in ['I', 'J', 'K', 'R'] {
            if let Some(w) = words.iter().find(|w| w.letter == l) {
                out.unsupported.push(Unsupported {
                    line,
                    word: format!("{l}{}", w.text),
                    reason: "centre or radius words have no meaning on a straight move".into(),
                    count: 1,
                });
            }
        }
    }
    let segment = match m {
        Motion::Rapid | Motion::Linear => Segment::Line(LineMove { start, end }),
        Motion::ArcCw | Motion::ArcCcw => Segment::Arc(arc(line, m, start, end, st.plane, &get, scale)?),
        Motion::Nurbs => return Ok(()),
    };
    if end != start {
        out.toolpath.blocks.push(PathBlock { line, motion: m, segment, feed_mm_per_min: feed });
    } else if let Segment::Arc(a) = &segment {
        // IJK full circle: end = start.
        out.toolpath.blocks.push(PathBlock { line, motion: m, segment: Segment::Arc(*a), feed_mm_per_min: feed });
    }
    st.pos = end;
    Ok(())
}

fn arc(
    line: usize,
    m: Motion,
    start: DVec3,
    end: DVec3,
    plane: Plane,
    get: &dyn Fn(char) -> Option<f64>,
    scale: f64,
) -> Result<ArcMove, ParseError> {
    let ccw = m == Motion::ArcCcw;
    let code = m.gcode();
    let (sa, sb, _) = plane.split(start);
    let (ea, eb, _) = plane.split(end);
    let center = if let Some(r) = get('R') {
        let r = r * scale;
        let (da, db) = (ea - sa, eb - sb);
        let chord = da.hypot(db);
        if !(chord > 0.0) || r == 0.0 {
            return Err(ParseError::ArcDegenerate {
                line,
                what: "R format needs an end point different from the start and R ≠ 0",
            });
        }
        let half = 0.5 * chord;
        if r.abs() < half * (1.0 - crate::numerics::tolerance::ROUNDING_REL) {
            return Err(ParseError::ArcRadiusTooSmall { line, r: r / scale, half_chord: half / scale });
        }
        let h = (r * r - half * half).max(0.0).sqrt();
        // Left normal of the chord; a counter-clockwise arc of at most 180° has its centre on
        // the left, a clockwise one on the right; negative R takes the other side.
        let (la, lb) = (-db / chord, da / chord);
        let side = if ccw { 1.0 } else { -1.0 } * r.signum();
        let (ma, mb) = (0.5 * (sa + ea), 0.5 * (sb + eb));
        plane.join(ma + side * h * la, mb + side * h * lb, 0.0)
    } else {
        let off = [get('I'), get('J'), get('K')];
        let (ia, ib, _) = plane.axes();
        if off[ia].is_none() && off[ib].is_none() {
            return Err(ParseError::ArcNoCentre { line, code });
        }
        let mut c = start;
        for (i, o) in off.iter().enumerate() {
            if let Some(v) = o {
                c[i] += v * scale;
            }
        }
        c
    };
    let a = ArcMove { start, end, center, plane, ccw };
    let (rs, re) = (a.radius_start(), a.radius_end());
    if !(rs > 0.0 && re > 0.0) {
        return Err(ParseError::ArcDegenerate { line, what: "zero radius" });
    }
    let allowed = tolerance::ARC_RADIUS_MISMATCH_MM.max(tolerance::ARC_RADIUS_MISMATCH_REL * rs);
    if (rs - re).abs() > allowed {
        return Err(ParseError::ArcRadius { line, start_r: rs / scale, end_r: re / scale });
    }
    Ok(a)
}

fn start_nurbs(line: usize, st: &mut State, get: &dyn Fn(char) -> Option<f64>) -> Result<(), ParseError> {
    if !st.absolute {
        return Err(ParseError::NurbsIncremental { line });
    }
    let order = get('P').unwrap_or(4.0);
    if !(order.fract() == 0.0 && (2.0..=(MAX_DEGREE + 1) as f64).contains(&order)) {
        return Err(ParseError::NurbsOrder { line, order });
    }
    let scale = if st.units == Units::Inch { 25.4 } else { 1.0 };
    let mut p0 = st.pos;
    for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = get(l) {
            p0[i] = v * scale;
        }
    }
    let first = p0;
    let tol = crate::numerics::tolerance::NURBS_START_MATCH_MM * scale.max(1.0);
    if (first - st.pos).abs().max_element() > tol {
        return Err(ParseError::NurbsStartMismatch { line, first: first.to_array(), position: st.pos.to_array() });
    }
    let w = get('R').unwrap_or(1.0);
    if !(w > 0.0 && w.is_finite()) {
        return Err(ParseError::NurbsWeight { line, value: w });
    }
    let feed = st.feed.ok_or(ParseError::MissingFeed { line, code: "G06.2" })?;
    let k = get('K');
    st.nurbs = Some(NurbsBuild {
        line,
        order: order as usize,
        knots: vec![k.unwrap_or(0.0)],
        points: vec![first],
        weights: vec![w],
        closing: 0,
        first_knot_missing: k.is_none(),
        feed,
    });
    Ok(())
}

fn nurbs_block(
    line: usize,
    get: &dyn Fn(char) -> Option<f64>,
    st: &mut State,
    out: &mut ParsedProgram,
) -> Result<(), ParseError> {
    let scale = if st.units == Units::Inch { 25.4 } else { 1.0 };
    let Some(nb) = st.nurbs.as_mut() else {
        return Ok(());
    };
    let has_axis = ['X', 'Y', 'Z'].iter().any(|&l| get(l).is_some());
    let Some(k) = get('K') else {
        if has_axis || get('R').is_some() {
            return Err(ParseError::NurbsMissingKnot { line });
        }
        return Ok(());
    };
    if nb.first_knot_missing {
        nb.knots[0] = k;
        nb.first_knot_missing = false;
    }
    let prev = nb.knots[nb.knots.len() - 1];
    if k < prev {
        return Err(ParseError::NurbsKnotDecreasing { line, value: k, previous: prev });
    }
    if has_axis || get('R').is_some() {
        if nb.closing > 0 {
            return Err(ParseError::NurbsAfterEnd { line });
        }
        let mut p = nb.points[nb.points.len() - 1];
        for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
            if let Some(v) = get(l) {
                p[i] = v * scale;
            }
        }
        let w = get('R').unwrap_or(1.0);
        if !(w > 0.0 && w.is_finite()) {
            return Err(ParseError::NurbsWeight { line, value: w });
        }
        nb.points.push(p);
        nb.weights.push(w);
        nb.knots.push(k);
    } else {
        if nb.closing >= nb.order {
            return Err(ParseError::NurbsAfterEnd { line });
        }
        nb.knots.push(k);
        nb.closing += 1;
        if nb.closing == nb.order {
            let nb = st.nurbs.take();
            if let Some(nb) = nb {
                finish_nurbs(nb, st, out)?;
                // Still in G06.2 mode: further coordinates are an error until a new motion.
                st.motion = Some(Motion::Nurbs);
            }
        }
    }
    Ok(())
}

fn finish_nurbs(nb: NurbsBuild, st: &mut State, out: &mut ParsedProgram) -> Result<(), ParseError> {
    let line = nb.line;
    if nb.closing != nb.order {
        return Err(ParseError::NurbsIncomplete { line, closing: nb.closing, order: nb.order });
    }
    let k = &nb.knots;
    let o = nb.order;
    let eq = |a: f64, b: f64| (a - b).abs() <= tolerance::KNOT_EQUAL_REL * (k[k.len() - 1] - k[0]).abs().max(1.0);
    if k[..o].iter().any(|&x| !eq(x, k[0])) {
        return Err(ParseError::NurbsNotClamped { line, end: "first", order: o });
    }
    if k[k.len() - o..].iter().any(|&x| !eq(x, k[k.len() - 1])) {
        return Err(ParseError::NurbsNotClamped { line, end: "last", order: o });
    }
    let curve = NurbsCurve::try_new(o - 1, nb.knots.clone(), &nb.points, Some(&nb.weights))
        .map_err(|source| ParseError::Nurbs { line, source })?;
    let end = curve.point_at(curve.range().1);
    out.toolpath.blocks.push(PathBlock {
        line,
        motion: Motion::Nurbs,
        segment: Segment::Nurbs(curve),
        feed_mm_per_min: Some(nb.feed),
    });
    st.pos = end;
    Ok(())
}
