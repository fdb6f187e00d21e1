//! What can go wrong reading a program: [`Problem`] says what, [`InterpError`] adds where.

use std::fmt;

use thiserror::Error;

use super::canon::Loc;
use super::params::ParamError;
use super::source::SourceError;
use crate::numerics::format::fmt_num;

/// A number as messages print it: the shortest round-trip decimal, exponent form for the huge
/// and tiny, words for what is not a number.
pub(crate) fn show(x: f64) -> String {
    if x.is_nan() {
        "not-a-number".into()
    } else if x.is_infinite() {
        if x > 0.0 { "infinity".into() } else { "-infinity".into() }
    } else if x == 0.0 {
        "0".into()
    } else {
        fmt_num(x)
    }
}

/// What is wrong with a line, in the words of someone who wrote it.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum Problem {
    /// A character that belongs to no word.
    #[error("unexpected '{}'; a block is made of words (a letter and a value), comments and parameter settings", .0.escape_default())]
    Char(char),
    /// `(` without `)`.
    #[error("the comment is not closed; add ')' before the end of the line")]
    UnclosedComment,
    /// Something else was expected.
    #[error("expected {0}")]
    Expected(&'static str),
    /// A letter without a value.
    #[error("the letter {0} has no value; every word is a letter and a value, e.g. {0}0")]
    NoValue(char),
    /// A malformed number.
    #[error("'{0}' is not a number")]
    BadNumber(String),
    /// A number beyond f64.
    #[error("a {0}-digit number is too large to be a value; check the line for a corrupted number")]
    NumberTooLarge(usize),
    /// The same letter twice.
    #[error("{0} appears twice in one block; keep one")]
    Repeated(char),
    /// A G or M value that is no code.
    #[error("{0}{v} is not a code ({0} codes are whole numbers or tenths)", v = show(*.1))]
    BadCode(char, f64),
    /// Too many G or M words.
    #[error("more G or M words on one line than any block needs")]
    TooManyCodes,
    /// A function name not known.
    #[error(
        "unknown function '{0}'; the functions are ABS ACOS ASIN ATAN COS EXP FIX FUP LN ROUND SIN SQRT TAN EXISTS"
    )]
    UnknownFunction(String),
    /// A function outside its domain.
    #[error("{0} of {v} is not defined", v = show(*.1))]
    Domain(&'static str, f64),
    /// Division by zero.
    #[error("division by zero")]
    DivideByZero,
    /// A value that is not finite.
    #[error("the value is too large (not a finite number)")]
    NotFinite,
    /// Brackets nested too deep.
    #[error("brackets or functions nested more than 64 deep")]
    TooDeep,
    /// A parameter problem.
    #[error("{0}")]
    Param(ParamError),
    /// An O-word keyword not known.
    #[error(
        "unknown O-word keyword '{0}'; use sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break or continue"
    )]
    UnknownOWord(String),
    /// Text after an O-word.
    #[error("unexpected '{0}' after the O-word")]
    Trailing(String),
    /// More call arguments than #1–#30.
    #[error("more than 30 arguments in a call")]
    TooManyArgs,
    /// A rule of the language or the machine, said in full.
    #[error("{0}")]
    Rule(String),
    /// A cap on work.
    #[error("{0}")]
    Cap(String),
    /// A problem found at another line than the one being read (a move held by cutter
    /// compensation is refused when the next one shows its corner).
    #[error("{text}")]
    Located {
        /// The line it is about.
        loc: Loc,
        /// What.
        text: String,
    },
}

impl From<ParamError> for Problem {
    fn from(e: ParamError) -> Self {
        Self::Param(e)
    }
}

/// A program that cannot be read on: the problem and the line.
#[derive(Clone, Debug, PartialEq)]
pub struct InterpError {
    /// Where (file 0 is the main program).
    pub loc: Loc,
    /// The file's name when the line is in a subroutine file.
    pub file: Option<String>,
    /// What.
    pub problem: Problem,
}

impl InterpError {
    /// The error at a line of the main program.
    #[must_use]
    pub fn at(loc: Loc, problem: Problem) -> Self {
        Self { loc, file: None, problem }
    }
}

impl fmt::Display for InterpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.file {
            Some(name) => write!(f, "{name} line {}: {}", self.loc.line, self.problem),
            None => write!(f, "line {}: {}", self.loc.line, self.problem),
        }
    }
}

impl std::error::Error for InterpError {}

impl From<SourceError> for Problem {
    fn from(e: SourceError) -> Self {
        Self::Rule(e.to_string())
    }
}
