//! `interpolab run`'s arguments read without clap, when they are plain.
//!
//! clap builds the whole command tree (fourteen subcommands and their options, a few hundred
//! allocations) before it looks at the first argument: about 0.3 M instructions and the
//! page faults of its code, a tenth of what the cheapest runs spend beyond the process
//! itself (docs/speed.md). A plain `run` — the subcommand, one scene path and options of
//! `run` in their `--name value` form, each at most once, values taken as they are — is read
//! here instead, to the same values clap would give (the tests compare the two). Anything
//! else (`--help`, `--format=json`, `--`, a repeated option, an unknown value, a path that
//! starts with `-`, an empty value, text that is not UTF-8) returns `None`, and clap parses
//! the arguments as before, with its own messages.

use std::ffi::OsString;
use std::path::PathBuf;

use super::{MethodArg, OutFormat};

/// The arguments of `interpolab run`, as clap's `Command::Run` carries them.
#[derive(Debug, PartialEq, Eq)]
pub(super) struct RunArgs {
    pub(super) scene: PathBuf,
    pub(super) format: OutFormat,
    pub(super) out: Option<PathBuf>,
    pub(super) errors: bool,
    pub(super) method: MethodArg,
    pub(super) turns: u32,
}

/// Digits a `--turns` value may have here: any nine-digit number fits in u32; longer ones
/// (and signs, spaces) go to clap, which decides.
const MAX_TURNS_DIGITS: usize = 9;

/// `args` is the whole command line, the program's name first. `Some` only for a plain
/// `run` (see the module's documentation).
pub(super) fn parse(args: &[OsString]) -> Option<RunArgs> {
    let mut words = args.get(1..)?.iter().map(|a| a.to_str());
    if words.next()?? != "run" {
        return None;
    }
    let mut scene = None;
    let mut format = None;
    let mut out = None;
    let mut errors = false;
    let mut method = None;
    let mut turns = None;
    while let Some(word) = words.next() {
        let word = word?;
        // A value that clap would read (empty, or looking like an option) goes to clap.
        let mut value = || words.next().flatten().filter(|v| !v.is_empty() && !v.starts_with('-'));
        match word {
            "--format" if format.is_none() => {
                format = Some(match value()? {
                    "csv" => OutFormat::Csv,
                    "json" => OutFormat::Json,
                    _ => return None,
                });
            }
            "--out" if out.is_none() => out = Some(PathBuf::from(value()?)),
            "--errors" if !errors => errors = true,
            "--method" if method.is_none() => {
                method = Some(match value()? {
                    "seed000" => MethodArg::Seed000,
                    "exact" => MethodArg::Exact,
                    _ => return None,
                });
            }
            "--turns" if turns.is_none() => {
                let v = value()?;
                if v.len() > MAX_TURNS_DIGITS || !v.bytes().all(|b| b.is_ascii_digit()) {
                    return None;
                }
                turns = Some(v.parse().ok()?);
            }
            w if scene.is_none() && !w.is_empty() && !w.starts_with('-') => scene = Some(PathBuf::from(w)),
            _ => return None,
        }
    }
    Some(RunArgs {
        scene: scene?,
        format: format.unwrap_or(OutFormat::Csv),
        out,
        errors,
        method: method.unwrap_or(MethodArg::Seed000),
        turns: turns.unwrap_or(1),
    })
}

#[cfg(test)]
mod tests {
    use super::{RunArgs, parse};
    use crate::cli::{Cli, Command};
    use clap::Parser;
    use std::ffi::OsString;

    fn argv(line: &str) -> Vec<OsString> {
        std::iter::once("interpolab").chain(line.split(' ').filter(|w| !w.is_empty())).map(OsString::from).collect()
    }

    /// What clap makes of the same command line, when it is a `run` clap accepts.
    fn by_clap(args: &[OsString]) -> Option<RunArgs> {
        match Cli::try_parse_from(args).ok()?.command? {
            Command::Run { scene, format, out, errors, method, turns } => {
                Some(RunArgs { scene, format, out, errors, method, turns })
            }
            _ => None,
        }
    }

    #[test]
    fn plain_runs_read_as_clap_reads_them() {
        let lines = [
            "run a.json",
            "run examples/torus-plane.json --format json",
            "run --format csv a.json",
            "run a.json --errors --method exact",
            "run --method seed000 --turns 3 a.json --out out.csv",
            "run a.json --turns 0",
            "run a.json --turns 007",
            "run a.json --turns 999999999",
            "run --errors --format json --out o.json --method exact --turns 2 x/y/z.json",
            "run ./-odd.json",
        ];
        for line in lines {
            let args = argv(line);
            let fast = parse(&args);
            assert!(fast.is_some(), "{line}: not read as a plain run");
            assert_eq!(fast, by_clap(&args), "{line}");
        }
    }

    #[test]
    fn anything_else_is_left_to_clap() {
        let lines = [
            "",
            "check a.json",
            "run",
            "run --errors",
            "run a.json b.json",
            "run a.json --format",
            "run a.json --format JSON",
            "run a.json --format=json",
            "run a.json --format json --format csv",
            "run a.json --errors --errors",
            "run a.json --method fast",
            "run a.json --turns -1",
            "run a.json --turns +2",
            "run a.json --turns 1e3",
            "run a.json --turns 4294967296",
            "run a.json --turns 1234567890",
            "run a.json --out --errors",
            "run -h",
            "run a.json --help",
            "run -- a.json",
            "run -a.json",
            "run a.json --version",
            "--version",
            "help run",
        ];
        for line in lines {
            assert_eq!(parse(&argv(line)), None, "{line}");
        }
        // Empty and non-UTF-8 words.
        let empty: Vec<OsString> = ["interpolab", "run", ""].iter().map(OsString::from).collect();
        assert_eq!(parse(&empty), None);
        let empty_out: Vec<OsString> =
            ["interpolab", "run", "a.json", "--out", ""].iter().map(OsString::from).collect();
        assert_eq!(parse(&empty_out), None);
        #[cfg(unix)]
        {
            use std::os::unix::ffi::OsStringExt;
            let bad = vec![OsString::from("interpolab"), OsString::from("run"), OsString::from_vec(vec![0x61, 0xff])];
            assert_eq!(parse(&bad), None);
        }
    }
}
