//! A program read through the interpreter ([`super::interp`]) into the [`super::Toolpath`] the
//! replay, the deviation, the comparison and the simulation consume.
//!
//! Canonical calls become path blocks one for one: a traverse a G00 line, a feed a G01 line, an
//! arc a G02/G03 arc (several turns as one block per turn), a spline a NURBS block. Moves
//! of zero length in X, Y, Z are left out (a rotary-only move has no tool path here; the
//! canonical stream keeps it). Sinumerik programs are read by the dialect reader
//! ([`super::parse`]).

use glam::DVec3;

use super::dialect::Dialect;
use super::interp::{Canon, InterpError, Interpreter, Options};
use super::parse::{ParseError, ParsedProgram, Unsupported, parse_dialect_reader};
use super::path::{ArcMove, LineMove, Motion, PathBlock, Segment};

/// Most moves of a program held as a path (each 112 bytes, a [`PathBlock`]: 336 MB at the
/// cap); commands that need every move at once refuse a program with more, after reading that
/// many. [`read_streamed`] holds none and refuses at the same move. A million-line program is
/// a third of it.
pub const MAX_PATH_MOVES: usize = 3_000_000;

/// Header comments kept for [`super::write::ProgrammedPoint::from_comments`].
const KEPT_COMMENTS: usize = 64;

/// Parses a program.
///
/// # Errors
/// The first malformed line, as a [`ParseError`].
pub fn parse_program(text: &str) -> Result<ParsedProgram, ParseError> {
    parse_program_in(text, Dialect::Fanuc)
}

/// Parses a program in a controller's dialect, strictly (a line that is not G-code or a code
/// that is not modelled is refused): FANUC and LinuxCNC programs through the interpreter
/// ([`crate::gcode::interp`], via [`read_program`]), Sinumerik 840D
/// programs (`BSPLINE`, `SD=`, `PL=`, `PW=`, `G70`/`G71`/`G700`/`G710`) by the dialect reader
/// here; see `docs/gcode-dialects.md`. The product's writers prove their programs with it.
/// User programs are read leniently by [`read_program`].
///
/// # Errors
/// The first malformed line, as a [`ParseError`].
pub fn parse_program_in(text: &str, dialect: Dialect) -> Result<ParsedProgram, ParseError> {
    if dialect == Dialect::Sinumerik {
        return parse_dialect_reader(text, dialect);
    }
    let opts = crate::gcode::interp::Options { strict: true, ..crate::gcode::interp::Options::default() };
    read_program(text, dialect, &opts)
}

/// Reads a program in a dialect: FANUC and LinuxCNC through the interpreter, Sinumerik by
/// its own reader.
///
/// # Errors
/// The line that cannot be read, as [`ParseError::Interp`] (or the Sinumerik reader's
/// [`ParseError`]).
pub fn read_program(text: &str, dialect: Dialect, opts: &Options) -> Result<ParsedProgram, ParseError> {
    if dialect == Dialect::Sinumerik {
        return parse_dialect_reader(text, dialect);
    }
    let opts = Options {
        keep_comments: opts.keep_comments.max(KEPT_COMMENTS),
        fanuc: opts.fanuc || dialect == Dialect::Fanuc,
        ..opts.clone()
    };
    read_from(Interpreter::from_text(text, opts), dialect)
}

/// Reads the canonical calls of an interpreter (over a file, with its subroutine library)
/// into a program: memory for the moves, not for the text.
///
/// # Errors
/// The line that cannot be read, or [`ParseError::TooManyMoves`] past
/// [`MAX_PATH_MOVES`].
pub fn read_from(it: Interpreter<'_>, dialect: Dialect) -> Result<ParsedProgram, ParseError> {
    read_from_capped(it, dialect, MAX_PATH_MOVES)
}

/// [`read_from`] refusing past `max_moves` (at most [`MAX_PATH_MOVES`]): a command whose own
/// cap is lower stops reading there, not after the whole program.
///
/// # Errors
/// As [`read_from`], with the lower cap.
pub fn read_from_capped(it: Interpreter<'_>, dialect: Dialect, max_moves: usize) -> Result<ParsedProgram, ParseError> {
    read_from_weighted(it, dialect, max_moves, &|_| 1)
}

/// [`read_from_capped`] with each move weighed (`weight`, at least 1 a move): reading stops
/// once the moves so far weigh `max_work` (a command whose work per move depends on its kind
/// — an arc measured against a design costs several lines — refuses as it reads, not after).
/// The error's `max` is `max_work`.
///
/// # Errors
/// As [`read_from`], past `max_work` (and past [`MAX_PATH_MOVES`] moves).
pub fn read_from_weighted(
    mut it: Interpreter<'_>,
    dialect: Dialect,
    max_work: usize,
    weight: &dyn Fn(&Motion) -> usize,
) -> Result<ParsedProgram, ParseError> {
    let mut out = ParsedProgram { dialect, ..ParsedProgram::default() };
    let mut pos = DVec3::ZERO;
    let mut tlo = DVec3::ZERO;
    let mut work = 0usize;
    for c in it.by_ref() {
        let c = c.map_err(ParseError::Interp)?;
        if work >= max_work {
            return Err(ParseError::TooManyMoves { line: c.loc().line as usize, max: max_work });
        }
        if out.toolpath.blocks.len() >= MAX_PATH_MOVES {
            return Err(ParseError::TooManyMoves { line: c.loc().line as usize, max: MAX_PATH_MOVES });
        }
        let before = out.toolpath.blocks.len();
        push(&mut out, &mut pos, &mut tlo, c);
        work = out.toolpath.blocks[before..].iter().fold(work, |w, b| w.saturating_add(weight(&b.motion).max(1)));
    }
    finish(&mut out, &it);
    Ok(out)
}

/// [`read_from`] for a command that looks at each move once (a summary): every path block
/// goes to `each` as it is made and is not kept, so memory does not grow with the program.
/// The program returned has everything but its moves (`toolpath` is empty). It is refused
/// where [`read_from`] refuses, past [`MAX_PATH_MOVES`] moves at the same line, so a command
/// answers alike whether it holds the moves or not.
///
/// # Errors
/// As [`read_from`].
pub fn read_streamed(
    mut it: Interpreter<'_>,
    dialect: Dialect,
    each: &mut dyn FnMut(&PathBlock),
) -> Result<ParsedProgram, ParseError> {
    let mut out = ParsedProgram { dialect, ..ParsedProgram::default() };
    let mut pos = DVec3::ZERO;
    let mut tlo = DVec3::ZERO;
    let mut moves = 0usize;
    for c in it.by_ref() {
        let c = c.map_err(ParseError::Interp)?;
        if moves >= MAX_PATH_MOVES {
            return Err(ParseError::TooManyMoves { line: c.loc().line as usize, max: MAX_PATH_MOVES });
        }
        push(&mut out, &mut pos, &mut tlo, c);
        moves += out.toolpath.blocks.len();
        for b in out.toolpath.blocks.drain(..) {
            each(&b);
        }
    }
    finish(&mut out, &it);
    Ok(out)
}

/// A program read a slice at a time (the app reads a big file over several frames, showing
/// the path as it grows).
pub struct ProgramReader {
    it: Option<Interpreter<'static>>,
    out: ParsedProgram,
    pos: DVec3,
    tlo: DVec3,
    len: u64,
    error: Option<ParseError>,
}

impl ProgramReader {
    /// A reader of `text` in `dialect` (Sinumerik programs are read at once).
    #[must_use]
    pub fn new(text: std::sync::Arc<str>, dialect: Dialect, opts: &Options) -> Self {
        let len = text.len() as u64;
        let mut r = Self {
            it: None,
            out: ParsedProgram { dialect, ..ParsedProgram::default() },
            pos: DVec3::ZERO,
            tlo: DVec3::ZERO,
            len,
            error: None,
        };
        if dialect == Dialect::Sinumerik {
            match parse_dialect_reader(&text, dialect) {
                Ok(p) => r.out = p,
                Err(e) => r.error = Some(e),
            }
            return r;
        }
        let opts = Options {
            keep_comments: opts.keep_comments.max(KEPT_COMMENTS),
            fanuc: opts.fanuc || dialect == Dialect::Fanuc,
            ..opts.clone()
        };
        let src = super::interp::SharedTextSource::new(text);
        r.it = Some(Interpreter::new(Box::new(src), Box::new(super::interp::NoLibrary), opts));
        r
    }

    /// Reads up to `calls` canonical calls; returns whether the program is read (or refused).
    pub fn step(&mut self, calls: usize) -> bool {
        let Some(it) = self.it.as_mut() else {
            return true;
        };
        for _ in 0..calls {
            match it.next() {
                Some(Ok(c)) => {
                    if self.out.toolpath.blocks.len() >= MAX_PATH_MOVES {
                        self.error =
                            Some(ParseError::TooManyMoves { line: c.loc().line as usize, max: MAX_PATH_MOVES });
                        self.it = None;
                        return true;
                    }
                    push(&mut self.out, &mut self.pos, &mut self.tlo, c);
                }
                Some(Err(e)) => {
                    self.error = Some(ParseError::Interp(e));
                    self.it = None;
                    return true;
                }
                None => {
                    finish(&mut self.out, it);
                    self.it = None;
                    return true;
                }
            }
        }
        false
    }

    /// The fraction of the file read (0 to 1).
    #[must_use]
    pub fn progress(&self) -> f64 {
        match &self.it {
            Some(it) if self.len > 0 => (it.main_offset() as f64 / self.len as f64).min(1.0),
            Some(_) => 0.0,
            None => 1.0,
        }
    }

    /// The program read so far.
    #[must_use]
    pub fn program(&self) -> &ParsedProgram {
        &self.out
    }

    /// The program, or the line that could not be read.
    ///
    /// # Errors
    /// As [`read_program`].
    pub fn into_result(self) -> Result<ParsedProgram, ParseError> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.out),
        }
    }
}

impl std::fmt::Debug for ProgramReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProgramReader")
            .field("moves", &self.out.toolpath.blocks.len())
            .field("progress", &self.progress())
            .finish()
    }
}

/// Adds one canonical call to the path.
pub(crate) fn push(out: &mut ParsedProgram, pos: &mut DVec3, tlo: &mut DVec3, c: Canon) {
    let line = c.loc().line as usize;
    match c {
        Canon::Traverse { end, .. } | Canon::Line { end, .. } => {
            let rapid = matches!(c, Canon::Traverse { .. });
            let feed = if let Canon::Line { feed, .. } = &c { Some(feed.rate) } else { None };
            if end.xyz != *pos {
                let motion = if rapid { Motion::Rapid } else { Motion::Linear };
                out.toolpath.blocks.push(PathBlock {
                    line,
                    motion,
                    segment: Segment::Line(LineMove { start: *pos, end: end.xyz }),
                    feed_mm_per_min: if rapid { None } else { feed },
                });
            }
            *pos = end.xyz;
        }
        Canon::Arc { end, center, plane, turns, feed, .. } => {
            let ccw = turns > 0;
            let motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
            let last = ArcMove { start: *pos, end: end.xyz, center, plane, ccw };
            let extra = turns.unsigned_abs().saturating_sub(1);
            let (_, _, ni) = plane.axes();
            if extra > 0 {
                // Full turns first, the normal axis advancing with the angle.
                let partial = last.sweep().abs();
                let total = partial + std::f64::consts::TAU * f64::from(extra);
                let dn = end.xyz[ni] - pos[ni];
                let mut s = *pos;
                for _ in 0..extra {
                    let mut e = s;
                    e[ni] += dn * std::f64::consts::TAU / total;
                    let mut cc = center;
                    cc[ni] = s[ni];
                    let seg = ArcMove { start: s, end: e, center: cc, plane, ccw };
                    out.toolpath.blocks.push(PathBlock {
                        line,
                        motion,
                        segment: Segment::Arc(seg),
                        feed_mm_per_min: Some(feed.rate),
                    });
                    s = e;
                }
                let mut cc = center;
                cc[ni] = s[ni];
                let seg = ArcMove { start: s, end: end.xyz, center: cc, plane, ccw };
                out.toolpath.blocks.push(PathBlock {
                    line,
                    motion,
                    segment: Segment::Arc(seg),
                    feed_mm_per_min: Some(feed.rate),
                });
            } else {
                out.toolpath.blocks.push(PathBlock {
                    line,
                    motion,
                    segment: Segment::Arc(last),
                    feed_mm_per_min: Some(feed.rate),
                });
            }
            *pos = end.xyz;
        }
        Canon::Spline { curve, end, feed, .. } => {
            out.toolpath.blocks.push(PathBlock {
                line,
                motion: Motion::Nurbs,
                segment: Segment::Nurbs(*curve),
                feed_mm_per_min: Some(feed.rate),
            });
            *pos = end.xyz;
        }
        Canon::ToolLengthOffset { offset, .. } => {
            // The spindle stays: the tip's position reads old − new further along the axis.
            *pos += *tlo - offset;
            *tlo = offset;
        }
        Canon::Dwell { .. } | Canon::ToolChange { .. } | Canon::Spindle { .. } | Canon::Stop { .. } => {}
    }
}

/// The reports, comments and counts after the last call.
pub(crate) fn finish(out: &mut ParsedProgram, it: &Interpreter<'_>) {
    out.unsupported = it
        .reports()
        .iter()
        .map(|r| Unsupported {
            line: r.first.line as usize,
            word: r.code.clone(),
            reason: r.what.clone(),
            count: r.count,
        })
        .collect();
    out.warnings = it.warnings().iter().map(|w| (w.loc.line as usize, w.text.clone())).collect();
    out.comments = it.comments().iter().map(|(l, c)| (l.line as usize, c.clone())).collect();
    out.lines = it.main_lines() as usize;
    out.blocks = it.main_blocks() as usize;
    out.blend_mm = it.blend_mm();
}

impl From<InterpError> for ParseError {
    fn from(e: InterpError) -> Self {
        Self::Interp(e)
    }
}
