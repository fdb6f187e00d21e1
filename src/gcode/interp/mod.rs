//! The RS274/NGC interpreter: program text → [canonical motions](canon).
//!
//! It reads programs as LinuxCNC's interpreter does — RS274/NGC with LinuxCNC's parameters,
//! expressions, O-word subroutines and loops, coordinate systems, tool offsets, canned
//! cycles and splines — and the FANUC family's additions (`M98`/`M99` subprograms, Macro B
//! `IF`/`GOTO`/`WHILE`, `G65`, `G68` rotation, `G16` polar input, `G6.2` NURBS). Every mode,
//! offset and unit is applied, and one stream of [`Canon`] calls comes out, in machine
//! millimetres, each with the line it comes from (docs/interpreter.md).
//!
//! It streams: [`Interpreter`] reads a line at a time from a [`Source`] and hands out
//! canonical calls as an iterator, so memory follows what the consumer keeps, not the text.
//! Work is bounded: lines executed (loops), call depth and named parameters are capped, each
//! cap a one-line error naming the line.
//!
//! What cannot be modelled (probing's contact, spindle-synchronised motion, a machine's own M
//! codes) is reported once per code with its count and first line ([`Report`]) and the run
//! goes on; lines that are not G-code at all are reported and skipped, or refused with
//! [`Options::strict`].

pub mod canon;
pub mod comp;
pub mod cycles;
mod error;
mod exec;
mod flow;
pub mod params;
mod read;
pub mod source;
pub mod splines;
pub mod state;
pub mod tools;

use std::collections::{HashMap, VecDeque};

pub use canon::{Canon, Feed, FeedMode, Loc, Origin, Pose};
pub use error::{InterpError, Problem};
pub use source::{
    Library, NoLibrary, ReaderSource, SharedTextSource, Source, SourceError, SourcePos, TextLibrary, TextSource,
};

use params::Params;
use read::Reader;
use state::State;

/// Most lines executed in one run, loops and calls counted each time round: about 20 s of
/// work; a program beyond it loops without end (or is far larger than any real one).
pub const MAX_EXECUTED_LINES: u64 = 50_000_000;

/// Deepest nesting of subroutine calls (LinuxCNC allows 10; FANUC 4 for M98, 4 for G65).
pub const MAX_CALL_DEPTH: usize = 64;

/// Most open `if`/`while`/`repeat` levels at once.
pub const MAX_CONTROL_DEPTH: usize = 256;

/// Tolerance of a number that must be an integer (an L, P or D word, a code's tenths), as
/// LinuxCNC's `read_integer_value`: within 1e-4 of an integer.
pub(crate) const INTEGER_SLACK: f64 = 1e-4;

/// How to read a program.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Start in inches (as if the program began with G20); the default is mm, as LinuxCNC's
    /// `rs274` and most controllers set up in mm.
    pub inch: bool,
    /// Refuse lines that are not G-code (and codes that cannot be modelled) instead of
    /// reporting and skipping them.
    pub strict: bool,
    /// Skip lines starting with `/` (the block-delete switch; off by default, as in
    /// LinuxCNC's `rs274`).
    pub block_delete: bool,
    /// The tool table: `G43 H n` takes its length offsets, `G41 D n` half its diameter.
    pub tools: tools::ToolTable,
    /// Read FANUC's meaning where it differs from LinuxCNC's: `G4 P` in milliseconds (a
    /// whole number; `X` or a decimal `P` in seconds).
    pub fanuc: bool,
    /// Comments to keep (the first ones, with their lines), e.g. a header naming the
    /// programmed point; the rest are not held.
    pub keep_comments: usize,
    /// Most lines executed (loops counted each time round); `None` is
    /// [`MAX_EXECUTED_LINES`].
    pub max_lines: Option<u64>,
    /// Reads and executes every line the general way. By default a *plain motion line* —
    /// only axis words X Y Z A B C with plain numbers, in the modes in force (`X1`,
    /// `X10.5 Y-2`) — takes a shorter way through the reader and the executor that gives the
    /// same calls; this turns it off, for tests that compare the two.
    pub general_only: bool,
}

/// Something the program does that is not modelled, or a line skipped: reported once per
/// code with the number of times it occurred and where it first did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The code as written, upper case (`G38.2`, `M100`, `E`), or a kind of line
    /// (`not G-code`).
    pub code: String,
    /// What is not modelled or why the line was skipped.
    pub what: String,
    /// Times it occurred.
    pub count: u64,
    /// Where it first occurred.
    pub first: Loc,
}

/// A note about how the program was read, e.g. an inch-looking program with no units word.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// The line it is about.
    pub loc: Loc,
    /// The note, with what to do.
    pub text: String,
}

/// One open file: the main program or a subroutine file.
struct Open<'a> {
    id: u16,
    src: Box<dyn Source + 'a>,
}

/// The interpreter: an iterator over a program's canonical calls.
pub struct Interpreter<'a> {
    opts: Options,
    files: Vec<Open<'a>>,
    names: Vec<String>,
    library: Box<dyn Library<'a> + 'a>,
    reader: Reader,
    line: String,
    params: Params,
    st: State,
    queue: VecDeque<Canon>,
    reports: Vec<Report>,
    report_index: HashMap<String, usize>,
    warnings: Vec<Warning>,
    flow: flow::Flow,
    exec: exec::Exec,
    executed: u64,
    lines_read: u64,
    main_lines: u32,
    main_blocks: u64,
    done: bool,
    failed: bool,
    /// Last line read (for errors at the end).
    loc: Loc,
}

impl<'a> Interpreter<'a> {
    /// An interpreter of the program `main`, finding called files in `library`.
    pub fn new(main: Box<dyn Source + 'a>, library: Box<dyn Library<'a> + 'a>, opts: Options) -> Self {
        let st = State { inch: opts.inch, ..State::default() };
        let mut reader = Reader::default();
        reader.general_only = opts.general_only;
        Self {
            opts,
            files: vec![Open { id: 0, src: main }],
            names: vec![String::new()],
            library,
            reader,
            line: String::new(),
            params: Params::default(),
            st,
            queue: VecDeque::new(),
            reports: Vec::new(),
            report_index: HashMap::new(),
            warnings: Vec::new(),
            flow: flow::Flow::default(),
            exec: exec::Exec::default(),
            executed: 0,
            lines_read: 0,
            main_lines: 0,
            main_blocks: 0,

            done: false,
            failed: false,
            loc: Loc::default(),
        }
    }

    /// An interpreter of a program held in a string, without subroutine files.
    #[must_use]
    pub fn from_text(text: &'a str, opts: Options) -> Self {
        Self::new(Box::new(TextSource::new(text)), Box::new(NoLibrary), opts)
    }

    /// What was reported so far (codes not modelled, lines skipped).
    #[must_use]
    pub fn reports(&self) -> &[Report] {
        &self.reports
    }

    /// Notes about the reading so far.
    #[must_use]
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The name of a file by its [`Loc::file`] number (empty for the main program).
    #[must_use]
    pub fn file_name(&self, file: u16) -> &str {
        self.names.get(usize::from(file)).map_or("", String::as_str)
    }

    /// Lines read so far (each time round a loop counts).
    #[must_use]
    pub fn lines_read(&self) -> u64 {
        self.lines_read
    }

    /// Lines of the main program read so far (its last line number reached).
    #[must_use]
    pub fn main_lines(&self) -> u32 {
        self.main_lines
    }

    /// Lines of the main program holding more than comments, read so far.
    #[must_use]
    pub fn main_blocks(&self) -> u64 {
        self.main_blocks
    }

    /// The byte offset reached in the main program (for progress over a file of known size).
    #[must_use]
    pub fn main_offset(&self) -> u64 {
        self.files.first().map_or(0, |f| f.src.tell().offset)
    }

    /// The comments kept ([`Options::keep_comments`]).
    #[must_use]
    pub fn comments(&self) -> &[(Loc, String)] {
        &self.exec.comments
    }

    /// The largest LinuxCNC `G64 P` path tolerance programmed (mm).
    #[must_use]
    pub fn blend_mm(&self) -> Option<f64> {
        self.exec.blend_mm
    }

    /// The state after the last line executed (units, modes, offsets, tool, position).
    #[must_use]
    pub fn state(&self) -> &State {
        &self.st
    }

    fn report(&mut self, code: &str, loc: Loc, what: &str) {
        if let Some(&i) = self.report_index.get(code) {
            self.reports[i].count += 1;
            return;
        }
        self.report_index.insert(code.to_owned(), self.reports.len());
        self.reports.push(Report { code: code.to_owned(), what: what.to_owned(), count: 1, first: loc });
    }

    fn error(&self, loc: Loc, problem: Problem) -> InterpError {
        let (loc, problem) = match problem {
            Problem::Located { loc, text } => (loc, Problem::Rule(text)),
            p => (loc, p),
        };
        let file = (loc.file != 0).then(|| self.file_name(loc.file).to_owned());
        InterpError { loc, file, problem }
    }

    /// Reads lines until a canonical call is queued or the program ends.
    fn fill(&mut self) -> Result<(), InterpError> {
        while self.queue.is_empty() && !self.done {
            let Some(file) = self.files.last_mut() else {
                self.done = true;
                break;
            };
            let id = file.id;
            let pos = file.src.next_line(&mut self.line).map_err(|e| {
                let loc = Loc { file: id, line: self.loc.line.saturating_add(1) };
                InterpError { loc, file: None, problem: Problem::from(e) }
            })?;
            let Some(pos) = pos else {
                let loc = self.loc;
                self.end_of_file(loc)?;
                continue;
            };
            self.loc = Loc { file: id, line: pos.line };
            self.lines_read += 1;
            if id == 0 && pos.line > self.main_lines {
                self.main_lines = pos.line;
                if has_code(&self.line) {
                    self.main_blocks += 1;
                }
            }
            self.executed += 1;
            let cap = self.opts.max_lines.unwrap_or(MAX_EXECUTED_LINES);
            if self.executed > cap {
                let why = self.flow.innermost_loop().map_or_else(
                    || "the program is larger than any real one".to_owned(),
                    |l| format!("the loop at line {l} seems to run without end"),
                );
                return Err(self.error(self.loc, Problem::Cap(format!("more than {cap} lines executed; {why}"))));
            }
            let loc = self.loc;
            self.line_(loc, pos).map_err(|p| self.error(loc, p))?;
        }
        Ok(())
    }

    fn end_of_file(&mut self, loc: Loc) -> Result<(), InterpError> {
        if self.files.len() > 1 || self.flow.in_call() {
            // A subroutine file or a called program ran off its end without returning.
            return Err(self.error(
                loc,
                Problem::Rule(
                    "the file ended inside a subroutine; end it with its endsub (LinuxCNC) or M99 (FANUC)".into(),
                ),
            ));
        }
        if self.flow.skipping() {
            let what = self.flow.skip_target();
            return Err(self.error(loc, Problem::Rule(format!("the file ended while looking for {what}"))));
        }
        self.finish(loc).map_err(|p| self.error(loc, p))?;
        self.done = true;
        Ok(())
    }

    /// The end of the program: what is still queued goes out, open constructs are checked.
    fn finish(&mut self, loc: Loc) -> Result<(), Problem> {
        exec::finish(self, loc)?;
        if !self.st.units_given {
            exec::inch_warning(self);
        }
        Ok(())
    }
}

/// A line holds something other than comments, spaces and tape marks.
fn has_code(line: &str) -> bool {
    let mut depth = 0u32;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => return false,
            c if depth == 0 && !c.is_whitespace() && c != '%' => return true,
            _ => {}
        }
    }
    false
}

impl Iterator for Interpreter<'_> {
    type Item = Result<Canon, InterpError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        if let Err(e) = self.fill() {
            self.failed = true;
            self.queue.clear();
            return Some(Err(e));
        }
        self.queue.pop_front().map(Ok)
    }
}

#[cfg(test)]
mod tests;
