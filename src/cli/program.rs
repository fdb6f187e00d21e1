//! Reading a program file for the commands: the reading options, the interpreter over a file
//! with the files beside it as subroutines, and the path `replay` and `simulate` take.

use std::io::BufReader;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use interpolab::gcode::interp::{Interpreter, Library, Options, ReaderSource, Source};
use interpolab::numerics::limits::MAX_PROGRAM_BYTES;

use super::Fatal;

/// Units a program without G20/G21 starts in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum UnitsArg {
    /// Millimetres (the default, as LinuxCNC's rs274).
    Mm,
    /// Inches.
    Inch,
}

/// Options of every command that reads a program through the interpreter.
#[derive(Args, Debug, Clone)]
pub(crate) struct ReadArgs {
    /// Units until the program's first G20/G21.
    #[arg(long, value_enum, default_value = "mm")]
    pub units: UnitsArg,
    /// Refuse lines that are not G-code and codes that are not modelled, instead of reporting
    /// and skipping them.
    #[arg(long)]
    pub strict: bool,
    /// Skip the lines that start with `/` (the block-delete switch on).
    #[arg(long)]
    pub block_delete: bool,
}

impl ReadArgs {
    /// The interpreter's options (a tool table comes from the tool options, `userprog::ToolArgs`).
    pub(crate) fn options(&self) -> Options {
        Options {
            inch: self.units == UnitsArg::Inch,
            strict: self.strict,
            block_delete: self.block_delete,
            ..Options::default()
        }
    }
}

/// Subroutine files in a directory.
pub(crate) struct DirLibrary {
    dir: PathBuf,
}

impl DirLibrary {
    pub(crate) fn beside(program: &Path) -> Self {
        Self { dir: program.parent().map(Path::to_path_buf).unwrap_or_default() }
    }
}

impl<'a> Library<'a> for DirLibrary {
    fn open(&mut self, name: &str) -> Option<Box<dyn Source + 'a>> {
        let entries =
            std::fs::read_dir(if self.dir.as_os_str().is_empty() { Path::new(".") } else { &self.dir }).ok()?;
        for e in entries.flatten() {
            let file_name = e.file_name();
            let file_name = file_name.to_string_lossy();
            let stem = file_name.rsplit_once('.').map_or(&*file_name, |(s, _)| s);
            if stem.eq_ignore_ascii_case(name) {
                let f = std::fs::File::open(e.path()).ok()?;
                return Some(Box::new(ReaderSource::new(BufReader::new(f), MAX_PROGRAM_BYTES)));
            }
        }
        None
    }
}

/// An interpreter over a program file, with its directory as the library.
pub(crate) fn open(path: &Path, opts: Options) -> Result<Interpreter<'static>, Fatal> {
    let f = std::fs::File::open(path).map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    let src = ReaderSource::new(BufReader::new(f), MAX_PROGRAM_BYTES);
    Ok(Interpreter::new(Box::new(src), Box::new(DirLibrary::beside(path)), opts))
}

/// Reads a program file into a path: FANUC and LinuxCNC programs through the interpreter,
/// streamed from the file (with the files beside it as subroutines), Sinumerik by its reader.
/// Returns the program, its dialect and whether that was given or guessed. Reading stops
/// with a refusal past `max_moves` moves (the command's own cap, at most
/// [`interpolab::gcode::read::MAX_PATH_MOVES`]). A Sinumerik program is read whole by its
/// own reader (held to the reader's caps).
pub(crate) fn read_path(
    path: &Path,
    dialect: Option<interpolab::gcode::Dialect>,
    read: &ReadArgs,
    max_moves: usize,
) -> Result<(interpolab::gcode::ParsedProgram, interpolab::gcode::Dialect, &'static str), Fatal> {
    read_path_weighed(path, dialect, read, &Weighing { max_work: max_moves, weight: &|_| 1, over: None })
}

/// How [`read_path_weighed`] weighs a program's moves as it reads them.
pub(crate) struct Weighing<'a> {
    /// The most work the command takes on (in the weight's units).
    pub max_work: usize,
    /// The work of one move (at least 1).
    pub weight: &'a dyn Fn(&interpolab::gcode::Motion) -> usize,
    /// The refusal past `max_work`, from the line reached (the reader's own otherwise).
    pub over: Option<&'a dyn Fn(usize) -> String>,
}

/// [`read_path`] refusing as it reads once the moves weigh more than the command takes on.
pub(crate) fn read_path_weighed(
    path: &Path,
    dialect: Option<interpolab::gcode::Dialect>,
    read: &ReadArgs,
    weighing: &Weighing<'_>,
) -> Result<(interpolab::gcode::ParsedProgram, interpolab::gcode::Dialect, &'static str), Fatal> {
    use interpolab::gcode::{Dialect, ParseError, read_from_weighted};
    use interpolab::simulate::pipeline::{read_options, read_text};
    let (dialect, how) = dialect_of(path, dialect)?;
    // The simulation's pipeline, but streamed from the file with the files beside it as
    // subroutines (a Sinumerik program is read whole by its own reader).
    let parsed = if dialect == Dialect::Sinumerik {
        let text = super::read_capped(path, MAX_PROGRAM_BYTES, "G-code program")
            .map_err(|e| Fatal(format!("cannot read program {}: {e}", path.display())))?;
        read_text(&text, dialect, &read.options())
    } else {
        let it = open(path, read_options(dialect, &read.options()))?;
        read_from_weighted(it, dialect, weighing.max_work, weighing.weight)
    };
    let parsed = parsed.map_err(|e| match (e, weighing.over) {
        (ParseError::TooManyMoves { line, max }, Some(over)) if max == weighing.max_work => {
            Fatal(format!("{}: {}", path.display(), over(line)))
        }
        (e, _) => Fatal(format!("{}: {e}", path.display())),
    })?;
    Ok((parsed, dialect, how))
}

/// The dialect given, or guessed from the program's first bytes, and which of the two.
fn dialect_of(
    path: &Path,
    dialect: Option<interpolab::gcode::Dialect>,
) -> Result<(interpolab::gcode::Dialect, &'static str), Fatal> {
    use std::io::Read;

    use interpolab::simulate::pipeline::{DIALECT_GUESS_BYTES, guess_dialect};
    if let Some(d) = dialect {
        return Ok((d, "given"));
    }
    let f = std::fs::File::open(path).map_err(|e| Fatal(format!("cannot read program {}: {e}", path.display())))?;
    let mut head = Vec::new();
    f.take(DIALECT_GUESS_BYTES as u64)
        .read_to_end(&mut head)
        .map_err(|e| Fatal(format!("cannot read program {}: {e}", path.display())))?;
    Ok((guess_dialect(&head), "guessed from the text"))
}

/// [`read_path`] for a command that looks at each move once: every path block goes to
/// `each` and none is kept (the program comes back without its moves), refused as
/// [`read_path`] refuses at [`interpolab::gcode::read::MAX_PATH_MOVES`]. A Sinumerik program,
/// read whole by its own reader, is handed over block by block after it is read.
pub(crate) fn read_path_streamed(
    path: &Path,
    dialect: Option<interpolab::gcode::Dialect>,
    read: &ReadArgs,
    each: &mut dyn FnMut(&interpolab::gcode::PathBlock),
) -> Result<(interpolab::gcode::ParsedProgram, interpolab::gcode::Dialect, &'static str), Fatal> {
    use interpolab::gcode::{Dialect, read_streamed};
    use interpolab::simulate::pipeline::{read_options, read_text};
    let (dialect, how) = dialect_of(path, dialect)?;
    let parsed = if dialect == Dialect::Sinumerik {
        let text = super::read_capped(path, MAX_PROGRAM_BYTES, "G-code program")
            .map_err(|e| Fatal(format!("cannot read program {}: {e}", path.display())))?;
        read_text(&text, dialect, &read.options()).map(|mut p| {
            for b in p.toolpath.blocks.drain(..) {
                each(&b);
            }
            p
        })
    } else {
        let it = open(path, read_options(dialect, &read.options()))?;
        read_streamed(it, dialect, each)
    };
    let parsed = parsed.map_err(|e| Fatal(format!("{}: {e}", path.display())))?;
    Ok((parsed, dialect, how))
}

/// One line per report or warning of a program read into a path.
pub(crate) fn report_lines(p: &interpolab::gcode::ParsedProgram) -> Vec<String> {
    let mut lines = Vec::new();
    for (line, text) in &p.warnings {
        lines.push(format!("WARNING      line {line}: {text}"));
    }
    for u in &p.unsupported {
        let times = if u.count > 1 { format!(", {} times", u.count) } else { String::new() };
        lines.push(format!("UNSUPPORTED  line {}: {} ({}{times}); its effect is left out", u.line, u.word, u.reason));
    }
    lines
}

/// A location as reports print it: the line, or `file:line` in a subroutine file.
pub(crate) fn canon_loc(it: &Interpreter<'_>, loc: interpolab::gcode::interp::Loc) -> String {
    if loc.file == 0 { loc.line.to_string() } else { format!("{}:{}", it.file_name(loc.file), loc.line) }
}

/// The interpreter's reports and warnings, one line each, on standard error.
pub(crate) fn report(it: &Interpreter<'_>, program: &Path) {
    for line in report_lines_of(it, program) {
        eprintln!("{line}");
    }
}

/// [`report`]'s lines, for a command that prints them only once nothing more can be refused
/// (a refusal is one line).
pub(crate) fn report_lines_of(it: &Interpreter<'_>, program: &Path) -> Vec<String> {
    let name = program.display();
    let mut out = Vec::new();
    for w in it.warnings() {
        out.push(format!("{name}: warning: line {}: {}", canon_loc(it, w.loc), w.text));
    }
    for r in it.reports() {
        let times = if r.count == 1 { "once".to_owned() } else { format!("{} times", r.count) };
        out.push(format!("{name}: {} ({times}, first on line {}): {}", r.code, canon_loc(it, r.first), r.what));
    }
    out
}
