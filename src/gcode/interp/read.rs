//! Reading one line into a [`Block`]: comments, block delete, line numbers, words whose values
//! are numbers, parameters, expressions or functions, parameter assignments, O-words and the
//! FANUC Macro B statements (`IF … GOTO`, `IF … THEN`, `WHILE … DO`, `END`, `GOTO`).
//!
//! As in LinuxCNC, spaces and tabs outside comments do not count (`G 1 X 1 0` is `G1 X10`),
//! letters are read in either case, and every value is computed while the line is read, with
//! the parameters as they were before the line: the line's assignments take effect after it
//! is read ([`Block::assigns`]). Expressions follow LinuxCNC's operators and precedence:
//! `**`; `*` `/` `MOD`; `+` `-`; `EQ NE GT GE LT LE`; `AND OR XOR`, left to right within a
//! level; functions `ABS ACOS ASIN ATAN[y]/[x] COS EXP FIX FUP LN ROUND SIN SQRT TAN EXISTS`,
//! angles in degrees. FANUC's assignment without brackets (`#1=#2+1`) is read too.

use super::error::Problem;
use super::params::{ParamRef, Params};

/// Most nested brackets and functions in one value (a line of `[[[[…` is refused, not
/// recursed into).
const MAX_DEPTH: usize = 64;

/// Most G or M words on one line.
const MAX_CODES: usize = 32;

/// Two numbers closer than this are equal to the expression operators `EQ` and `NE`.
const EQUAL_SLACK: f64 = 1e-6;

/// Values a line's expressions read.
pub(crate) trait Env {
    /// `#n`.
    fn numbered(&self, n: usize) -> f64;
    /// `#<name>`, `None` when it has no value.
    fn named(&self, name: &str) -> Option<f64>;
}

/// 10^0 … 10^22, each exactly a double (5^22 < 2^53).
const EXACT_TENS: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// A plain decimal number at `s[i..]` — an optional sign, digits with at most one point, at
/// most 19 digits whose value is below 2^53 and at most 22 after the point — and the index
/// after it; `None` for anything else (the expression reader's business). Exact: the digits
/// as an integer, divided once by an exact power of ten.
fn plain_number_at(s: &[u8], mut i: usize) -> Option<(f64, usize)> {
    let negative = s.get(i) == Some(&b'-');
    if matches!(s.get(i), Some(b'+' | b'-')) {
        i += 1;
    }
    let mut mantissa: u64 = 0;
    let mut digits = 0u32;
    while i < s.len() && s[i].is_ascii_digit() {
        // Up to 19 digits cannot overflow; beyond, the number is not plain.
        mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(s[i] - b'0'));
        digits += 1;
        i += 1;
    }
    let mut after_point = 0u32;
    if s.get(i) == Some(&b'.') {
        i += 1;
        while i < s.len() && s[i].is_ascii_digit() {
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(s[i] - b'0'));
            after_point += 1;
            i += 1;
        }
        if s.get(i) == Some(&b'.') {
            return None;
        }
    }
    let digits = digits + after_point;
    if digits == 0 || digits > 19 || mantissa >= 1 << 53 || after_point > 22 {
        return None;
    }
    let v = mantissa as f64 / EXACT_TENS[after_point as usize];
    Some((if negative { -v } else { v }, i))
}

/// The letters of a plain motion line: the axes X Y Z A B C (bits as [`Block::letters`]).
const PLAIN_LETTERS: u32 = (1 << (b'x' - b'a'))
    | (1 << (b'y' - b'a'))
    | (1 << (b'z' - b'a'))
    | 1
    | (1 << (b'b' - b'a'))
    | (1 << (b'c' - b'a'));

/// Reads a *plain motion line* into a cleared block — axis words X Y Z A B C (either case),
/// each once, each followed at once by a plain number ([`plain_number_at`]), words apart or
/// separated by spaces and tabs — and says whether it was one. Most lines of a big program
/// are, and the general reader (the comment and space stripping, the word table, the
/// statements and expressions) gives them the same block: only the letters and their
/// values. Anything else (a comment, another letter, a space inside a word, a sign without a
/// digit, an exponent, a second point, a repeated axis …) leaves the line to the general
/// reader; what is written into the block then does not matter, it is cleared again.
fn plain_line(s: &[u8], b: &mut Block) -> bool {
    let mut i = 0;
    let mut any = false;
    loop {
        while i < s.len() && (s[i] == b' ' || s[i] == b'\t') {
            i += 1;
        }
        let Some(&c) = s.get(i) else {
            return any;
        };
        let c = c.to_ascii_lowercase();
        if !c.is_ascii_lowercase() {
            return false;
        }
        let bit = 1u32 << (c - b'a');
        if bit & PLAIN_LETTERS == 0 || b.letters & bit != 0 {
            return false;
        }
        // The general reader wants a value to start right after the letter.
        if !s.get(i + 1).is_some_and(|n| matches!(n, b'.' | b'-' | b'+') || n.is_ascii_digit()) {
            return false;
        }
        let Some((v, after)) = plain_number_at(s, i + 1) else {
            return false;
        };
        // A word ends at a space, a tab, the next letter or the line's end: anything else
        // (`X1e3`, `X1#2`, `X1(…)`) is the general reader's to read or refuse.
        if s.get(after).is_some_and(|n| !(matches!(n, b' ' | b'\t') || n.is_ascii_alphabetic())) {
            return false;
        }
        b.words[(c - b'a') as usize] = v;
        b.letters |= bit;
        any = true;
        i = after;
    }
}

/// An O-word's keyword.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OKind {
    Sub,
    EndSub,
    Call,
    Return,
    Do,
    While,
    EndWhile,
    If,
    ElseIf,
    Else,
    EndIf,
    Repeat,
    EndRepeat,
    Break,
    Continue,
    /// A FANUC program number alone (`O1234`): the start of a program or subprogram.
    Label,
}

/// An O-word: `o100 while [#1 lt 3]`, `o<name> call [1] [2]`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct OWord {
    /// The label: a number as text (`100`) or a name (`<name>` without the brackets).
    pub name: String,
    /// The keyword.
    pub kind: OKind,
    /// Values after the keyword (call arguments, a condition, a count, a return value).
    pub args: Vec<f64>,
}

/// A FANUC Macro B statement.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Flow {
    /// `GOTO n`, or `IF [c] GOTO n` with its condition's value.
    Goto { target: f64, cond: Option<f64> },
    /// `IF [c] THEN #i = v`: the assignment is in [`Block::assigns`] only when c holds.
    IfThen,
    /// `WHILE [c] DO m`.
    While { cond: f64, id: u32 },
    /// `DO m` without a condition (an endless loop, left by `GOTO`).
    Do { id: u32 },
    /// `END m`.
    End { id: u32 },
}

/// One line read.
#[derive(Clone, Debug, Default)]
pub(crate) struct Block {
    /// The line starts with `/` (block delete).
    pub delete: bool,
    /// `N` number, if any.
    pub line_number: Option<f64>,
    /// G codes in tenths (`G38.2` → 382), in the order written.
    pub g: Vec<i32>,
    /// M codes.
    pub m: Vec<i32>,
    /// Values of the letter words A…Z (G, M, N, O are kept elsewhere); a value counts only
    /// when its letter's bit is set in `letters` (so clearing a line writes none of them).
    words: [f64; 26],
    /// Polar distance `@`.
    pub polar_r: Option<f64>,
    /// Polar angle `^` (degrees).
    pub polar_a: Option<f64>,
    /// Parameter assignments, applied after the line is read.
    pub assigns: Vec<(ParamRef, f64)>,
    /// The O-word of the line.
    pub oword: Option<OWord>,
    /// The FANUC statement of the line.
    pub flow: Option<Flow>,
    /// The first comment's text (without the parentheses), for `MSG`, `DEBUG`, `PRINT`.
    pub comment: String,
    /// There is a comment.
    pub has_comment: bool,
    /// The line holds a `%` tape mark; `percent_text` is what followed it.
    pub percent: bool,
    /// Text after a `%` mark on its line (a line that is not G-code).
    pub percent_text: bool,
    /// Letters read (a bit per letter), for "any axis word" tests.
    pub letters: u32,
}

impl Block {
    fn clear(&mut self) {
        self.delete = false;
        self.line_number = None;
        self.g.clear();
        self.m.clear();
        self.polar_r = None;
        self.polar_a = None;
        self.assigns.clear();
        self.oword = None;
        self.flow = None;
        self.comment.clear();
        self.has_comment = false;
        self.percent = false;
        self.percent_text = false;
        self.letters = 0;
    }

    /// The value of a letter's word.
    pub fn get(&self, letter: u8) -> Option<f64> {
        let k = (letter.to_ascii_lowercase() - b'a') as usize;
        (self.letters & (1 << k) != 0).then(|| self.words[k])
    }

    /// Takes a letter's word out of the block.
    pub fn remove(&mut self, letter: u8) -> Option<f64> {
        let v = self.get(letter);
        self.letters &= !(1 << (letter.to_ascii_lowercase() - b'a'));
        v
    }

    /// The line has nothing to do.
    pub fn is_empty(&self) -> bool {
        self.g.is_empty()
            && self.m.is_empty()
            && self.letters == 0
            && self.polar_r.is_none()
            && self.polar_a.is_none()
            && self.assigns.is_empty()
            && self.oword.is_none()
            && self.flow.is_none()
            && !self.has_comment
    }
}

/// Reads lines into blocks, reusing its buffers.
#[derive(Debug, Default)]
pub(crate) struct Reader {
    /// Every line through the general reader: [`plain_line`] is not tried
    /// ([`super::Options::general_only`]).
    pub general_only: bool,
    code: Vec<u8>,
    /// The line read last.
    pub block: Box<Block>,
    /// A second block the reader works in while the last one is executed
    /// ([`Reader::take_block`]): handing a block over moves a pointer, not the block.
    spare: Option<Box<Block>>,
}

/// The light view of a line used while skipping (inside a false `IF`, a `sub` being passed):
/// its O-word label and keyword, or its FANUC loop keyword, without computing anything.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Peek {
    /// An O-word.
    O { name: String, kind: OKind },
    /// FANUC `WHILE … DO m` / `DO m`.
    Do { id: u32 },
    /// FANUC `END m`.
    End { id: u32 },
    /// FANUC `N` number (a `GOTO` target).
    N(f64),
    /// Anything else.
    Other,
}

impl Reader {
    /// The block read last, taken out to be executed while the reader may read other lines
    /// (a call searching for its subroutine) into its spare block; give it back with
    /// [`Reader::put_block`].
    pub fn take_block(&mut self) -> Box<Block> {
        let spare = self.spare.take().unwrap_or_default();
        std::mem::replace(&mut self.block, spare)
    }

    /// Gives back the block [`Reader::take_block`] took.
    pub fn put_block(&mut self, block: Box<Block>) {
        self.spare = Some(std::mem::replace(&mut self.block, block));
    }

    /// Strips comments and spaces into `self.code` (lower case), keeping the first comment.
    /// Read byte by byte: every byte that matters is ASCII, and the bytes of a multi-byte
    /// character are never ASCII, so only such a character outside a comment is decoded.
    fn normalize(&mut self, raw: &str) -> Result<(), Problem> {
        self.code.clear();
        let b = &mut self.block;
        // A line that starts with '%' is a tape mark: what follows on it is not G-code. Most
        // lines start with a letter, which is not one; any other line is trimmed to see.
        let starts_plain = raw.as_bytes().first().is_some_and(|c| c.is_ascii_alphanumeric());
        if !starts_plain && let Some(rest) = raw.trim_start().strip_prefix('%') {
            b.percent = true;
            b.percent_text = !rest.trim().is_empty();
            return Ok(());
        }
        let bytes = raw.as_bytes();
        // Most lines are ASCII without comments: every printable byte is code, lower-cased,
        // and spaces and control characters are left out.
        let special = bytes.iter().fold(false, |any, &c| any | (c >= 0x80) | (c == b'(') | (c == b';'));
        if !special {
            self.code.extend(bytes.iter().map(u8::to_ascii_lowercase));
            self.code.retain(|c| c.wrapping_sub(b'!') <= b'~' - b'!');
            return Ok(());
        }
        let mut depth = 0usize;
        let mut first = true;
        // Where the comment being read started (after its '(').
        let mut opened = 0;
        let mut i = 0;
        while i < bytes.len() {
            let c = bytes[i];
            i += 1;
            if depth > 0 {
                match c {
                    b'(' => depth += 1,
                    b')' => {
                        depth -= 1;
                        if depth == 0 && first {
                            b.comment.push_str(&raw[opened..i - 1]);
                            first = false;
                        }
                    }
                    _ => {}
                }
                continue;
            }
            // Most bytes: a printable character of the code (a letter, a digit, a sign …).
            if c > b' ' && c < 0x7f && c != b'(' && c != b';' {
                self.code.push(c.to_ascii_lowercase());
                continue;
            }
            match c {
                b'(' => {
                    depth = 1;
                    opened = i;
                    b.has_comment = true;
                }
                b';' => {
                    b.has_comment = true;
                    if first {
                        b.comment.push_str(&raw[i..]);
                    }
                    break;
                }
                // Spaces and control characters (tabs, a carriage return, DEL).
                c if c.is_ascii() => {}
                _ => {
                    // A character of several bytes: only the byte-order mark is passed over.
                    let ch = raw[i - 1..].chars().next().unwrap_or(char::REPLACEMENT_CHARACTER);
                    if ch != '\u{feff}' {
                        return Err(Problem::Char(ch));
                    }
                    i += ch.len_utf8() - 1;
                }
            }
        }
        if depth > 0 {
            if first {
                b.comment.push_str(&raw[opened..]);
            }
            // LinuxCNC refuses an unclosed comment; a viewer reads the rest of the line as
            // its text (reported by the caller).
            return Err(Problem::UnclosedComment);
        }
        Ok(())
    }

    /// Reads a line fully, computing every value with `env`.
    pub fn read(&mut self, raw: &str, env: &dyn Env) -> Result<&Block, Problem> {
        self.block.clear();
        if !self.general_only && plain_line(raw.as_bytes(), &mut self.block) {
            return Ok(&self.block);
        }
        self.block.clear();
        match self.normalize(raw) {
            Ok(()) => {}
            Err(Problem::UnclosedComment) => {
                // Keep the words before the comment; the caller reports it.
                let code = std::mem::take(&mut self.code);
                let r = Parser { s: &code, i: 0, env, depth: 0 }.line(&mut self.block);
                self.code = code;
                r?;
                return Err(Problem::UnclosedComment);
            }
            Err(e) => return Err(e),
        }
        if self.block.percent {
            return Ok(&self.block);
        }
        let code = std::mem::take(&mut self.code);
        let r = Parser { s: &code, i: 0, env, depth: 0 }.line(&mut self.block);
        self.code = code;
        r.map(|()| &*self.block)
    }

    /// Looks at a line without computing anything (for skipping).
    pub fn peek(&mut self, raw: &str) -> Peek {
        self.block.clear();
        if self.normalize(raw).is_err() && self.code.is_empty() {
            return Peek::Other;
        }
        let s = &self.code[..];
        let mut i = 0;
        if s.first() == Some(&b'/') {
            i += 1;
        }
        let mut n = None;
        if s.get(i) == Some(&b'n') {
            let st = i + 1;
            let mut j = st;
            while j < s.len() && (s[j].is_ascii_digit() || s[j] == b'.') {
                j += 1;
            }
            n = std::str::from_utf8(&s[st..j]).ok().and_then(|t| t.parse::<f64>().ok());
            i = j;
        }
        let rest = &s[i..];
        if rest.first() == Some(&b'o')
            && let Some((name, after)) = o_label(&rest[1..])
        {
            if let Some(kind) = o_keyword(after) {
                return Peek::O { name, kind };
            }
            if after.iter().all(u8::is_ascii_alphanumeric) {
                let suffix = String::from_utf8_lossy(after);
                return Peek::O { name: format!("{name}{suffix}"), kind: OKind::Label };
            }
        }
        if rest.starts_with(b"while") || rest.starts_with(b"do") {
            if let Some(p) = find_word(rest, b"do") {
                return Peek::Do { id: leading_int(&rest[p + 2..]).unwrap_or(0) };
            }
        } else if let Some(r) = rest.strip_prefix(b"end")
            && !r.starts_with(b"sub")
            && let Some(id) = leading_int(r)
        {
            return Peek::End { id };
        }
        n.map_or(Peek::Other, Peek::N)
    }
}

/// `100` or `<name>` after an `o`; returns the label and the rest.
fn o_label(s: &[u8]) -> Option<(String, &[u8])> {
    if s.first() == Some(&b'<') {
        let end = s.iter().position(|&c| c == b'>')?;
        let name = std::str::from_utf8(&s[1..end]).ok()?.to_owned();
        Some((name, &s[end + 1..]))
    } else {
        let end = s.iter().position(|c| !c.is_ascii_digit()).unwrap_or(s.len());
        if end == 0 {
            return None;
        }
        // Leading zeros do not count: O0100 is O100.
        let digits = std::str::from_utf8(&s[..end]).ok()?.trim_start_matches('0');
        Some((if digits.is_empty() { "0".to_owned() } else { digits.to_owned() }, &s[end..]))
    }
}

const O_KEYWORDS: [(&[u8], OKind); 15] = [
    (b"endsub", OKind::EndSub),
    (b"endwhile", OKind::EndWhile),
    (b"endif", OKind::EndIf),
    (b"endrepeat", OKind::EndRepeat),
    (b"elseif", OKind::ElseIf),
    (b"else", OKind::Else),
    (b"sub", OKind::Sub),
    (b"call", OKind::Call),
    (b"return", OKind::Return),
    (b"do", OKind::Do),
    (b"while", OKind::While),
    (b"if", OKind::If),
    (b"repeat", OKind::Repeat),
    (b"break", OKind::Break),
    (b"continue", OKind::Continue),
];

fn o_keyword(s: &[u8]) -> Option<OKind> {
    O_KEYWORDS.iter().find(|(k, _)| s.starts_with(k)).map(|(_, kind)| *kind)
}

fn find_word(s: &[u8], w: &[u8]) -> Option<usize> {
    // The last occurrence outside brackets.
    let mut depth = 0i32;
    let mut found = None;
    for i in 0..s.len() {
        match s[i] {
            b'[' => depth += 1,
            b']' => depth -= 1,
            _ if depth == 0 && s[i..].starts_with(w) => found = Some(i),
            _ => {}
        }
    }
    found
}

fn leading_int(s: &[u8]) -> Option<u32> {
    let end = s.iter().position(|c| !c.is_ascii_digit()).unwrap_or(s.len());
    std::str::from_utf8(&s[..end]).ok()?.parse().ok()
}

struct Parser<'s, 'e> {
    s: &'s [u8],
    i: usize,
    env: &'e dyn Env,
    depth: usize,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Op {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    fn precedence(self) -> u8 {
        match self {
            Self::Pow => 6,
            Self::Mul | Self::Div | Self::Mod => 5,
            Self::Add | Self::Sub => 4,
            Self::Eq | Self::Ne | Self::Gt | Self::Ge | Self::Lt | Self::Le => 3,
            Self::And | Self::Or | Self::Xor => 2,
        }
    }
}

impl Parser<'_, '_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn rest(&self) -> &[u8] {
        &self.s[self.i.min(self.s.len())..]
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    fn eat_word(&mut self, w: &[u8]) -> bool {
        if self.rest().starts_with(w) {
            self.i += w.len();
            true
        } else {
            false
        }
    }

    fn text_from(&self, start: usize) -> String {
        String::from_utf8_lossy(&self.s[start..self.i.min(self.s.len())]).into_owned()
    }

    fn line(&mut self, b: &mut Block) -> Result<(), Problem> {
        if self.eat(b'/') {
            b.delete = true;
        }
        if self.peek() == Some(b'n') && self.s.get(self.i + 1).is_some_and(|c| c.is_ascii_digit() || *c == b'.') {
            self.i += 1;
            b.line_number = Some(self.number()?);
        }
        if self.peek() == Some(b'o') {
            return self.oword(b);
        }
        // FANUC statements start with GOTO, IF, WHILE, DO or END.
        if matches!(self.peek(), Some(b'g' | b'i' | b'w' | b'd' | b'e')) && self.fanuc_statement(b)? {
            return Ok(());
        }
        while let Some(c) = self.peek() {
            match c {
                b'#' => {
                    self.i += 1;
                    let p = self.param_ref()?;
                    if !self.eat(b'=') {
                        return Err(Problem::Expected("'=' after a parameter at the start of a word (#1=5)"));
                    }
                    let v = self.assigned_value()?;
                    b.assigns.push((p, v));
                }
                b'@' | b'^' => {
                    self.i += 1;
                    let v = self.real_value()?;
                    let slot = if c == b'@' { &mut b.polar_r } else { &mut b.polar_a };
                    if slot.is_some() {
                        return Err(Problem::Repeated(c as char));
                    }
                    *slot = Some(v);
                }
                b'a'..=b'z' => {
                    self.i += 1;
                    let starts_value = self
                        .peek()
                        .is_some_and(|n| matches!(n, b'[' | b'#' | b'.' | b'-' | b'+') || n.is_ascii_alphanumeric());
                    if !starts_value {
                        return Err(Problem::NoValue(c.to_ascii_uppercase() as char));
                    }
                    // Most words hold a plain number: read it without the expression reader.
                    let v = match self.plain_number() {
                        Some(v) => v,
                        None => self.real_value()?,
                    };
                    self.word(b, c, v)?;
                }
                _ => return Err(Problem::Char(c as char)),
            }
        }
        Ok(())
    }

    fn word(&mut self, b: &mut Block, c: u8, v: f64) -> Result<(), Problem> {
        match c {
            b'g' => {
                if b.g.len() >= MAX_CODES {
                    return Err(Problem::TooManyCodes);
                }
                let t = (v * 10.0).round();
                if (v * 10.0 - t).abs() > super::INTEGER_SLACK || !(0.0..=10_000.0).contains(&t) {
                    return Err(Problem::BadCode('G', v));
                }
                b.g.push(t as i32);
            }
            b'm' => {
                if b.m.len() >= MAX_CODES {
                    return Err(Problem::TooManyCodes);
                }
                let t = v.round();
                if (v - t).abs() > super::INTEGER_SLACK || !(0.0..=100_000.0).contains(&t) {
                    return Err(Problem::BadCode('M', v));
                }
                b.m.push(t as i32);
            }
            b'n' => b.line_number = Some(v),
            b'o' => return Err(Problem::Expected("an O-word at the start of its line")),
            _ => {
                let k = (c - b'a') as usize;
                if b.letters & (1 << k) != 0 {
                    return Err(Problem::Repeated(c.to_ascii_uppercase() as char));
                }
                b.words[k] = v;
                b.letters |= 1 << k;
            }
        }
        Ok(())
    }

    /// FANUC `IF`, `WHILE`, `DO`, `END`, `GOTO` at the start of a line (after `N`).
    fn fanuc_statement(&mut self, b: &mut Block) -> Result<bool, Problem> {
        let r = self.rest();
        if r.starts_with(b"goto") {
            self.i += 4;
            b.flow = Some(Flow::Goto { target: self.real_value()?, cond: None });
            return Ok(true);
        }
        if r.starts_with(b"if[") {
            self.i += 2;
            // `IF [a] AND [b] GOTO n`: the condition may join bracketed terms.
            let first = self.real_value()?;
            let cond = self.binary_tail(first, 0, false)?;
            if self.eat_word(b"goto") {
                b.flow = Some(Flow::Goto { target: self.real_value()?, cond: Some(cond) });
                return Ok(true);
            }
            if self.eat_word(b"then") {
                b.flow = Some(Flow::IfThen);
                if cond != 0.0 {
                    // The statement after THEN: an assignment (or words).
                    self.line_rest(b)?;
                } else {
                    self.i = self.s.len();
                }
                return Ok(true);
            }
            return Err(Problem::Expected("GOTO or THEN after IF [ … ]"));
        }
        if r.starts_with(b"while[") {
            self.i += 5;
            let cond = self.real_value()?;
            if !self.eat_word(b"do") {
                return Err(Problem::Expected("DO after WHILE [ … ]"));
            }
            b.flow = Some(Flow::While { cond, id: self.loop_id()? });
            return Ok(true);
        }
        if r.starts_with(b"do") && r.get(2).is_some_and(u8::is_ascii_digit) {
            self.i += 2;
            b.flow = Some(Flow::Do { id: self.loop_id()? });
            return Ok(true);
        }
        if r.starts_with(b"end") && r.get(3).is_some_and(u8::is_ascii_digit) {
            self.i += 3;
            b.flow = Some(Flow::End { id: self.loop_id()? });
            return Ok(true);
        }
        Ok(false)
    }

    fn line_rest(&mut self, b: &mut Block) -> Result<(), Problem> {
        while let Some(c) = self.peek() {
            if c == b'#' {
                self.i += 1;
                let p = self.param_ref()?;
                if !self.eat(b'=') {
                    return Err(Problem::Expected("'=' after the parameter in IF … THEN #i = …"));
                }
                let v = self.assigned_value()?;
                b.assigns.push((p, v));
            } else if c.is_ascii_lowercase() {
                self.i += 1;
                let v = self.real_value()?;
                self.word(b, c, v)?;
            } else {
                return Err(Problem::Char(c as char));
            }
        }
        Ok(())
    }

    fn loop_id(&mut self) -> Result<u32, Problem> {
        let st = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        self.text_from(st).parse().map_err(|_| Problem::Expected("a loop number (DO1, END1)"))
    }

    fn oword(&mut self, b: &mut Block) -> Result<(), Problem> {
        self.i += 1;
        let (name, rest_len) = match o_label(self.rest()) {
            Some((name, after)) => (name, after.len()),
            None => return Err(Problem::Expected("a number or <name> after O")),
        };
        self.i = self.s.len() - rest_len;
        let Some(kind) = o_keyword(self.rest()) else {
            // A FANUC program number, possibly with a letter suffix (`O7997A`).
            if self.rest().iter().all(u8::is_ascii_alphanumeric) {
                let name = format!("{name}{}", self.text_from(self.i));
                self.i = self.s.len();
                b.oword = Some(OWord { name, kind: OKind::Label, args: Vec::new() });
                return Ok(());
            }
            return Err(Problem::UnknownOWord(self.text_from(self.i)));
        };
        let kw_len = O_KEYWORDS.iter().find(|(_, k)| *k == kind).map_or(0, |(w, _)| w.len());
        self.i += kw_len;
        let mut args = Vec::new();
        match kind {
            OKind::Call => {
                while self.peek() == Some(b'[') {
                    if args.len() >= super::params::CALL_ARGS {
                        return Err(Problem::TooManyArgs);
                    }
                    args.push(self.real_value()?);
                }
            }
            OKind::While | OKind::If | OKind::ElseIf | OKind::Repeat => {
                if self.peek() != Some(b'[') {
                    return Err(Problem::Expected("a condition in brackets, e.g. o100 if [#1 gt 0]"));
                }
                args.push(self.real_value()?);
            }
            OKind::Return | OKind::EndSub if self.peek() == Some(b'[') => {
                args.push(self.real_value()?);
            }
            _ => {}
        }
        if self.i < self.s.len() {
            return Err(Problem::Trailing(self.text_from(self.i)));
        }
        b.oword = Some(OWord { name, kind, args });
        Ok(())
    }

    /// The value of an assignment: LinuxCNC's real value, or FANUC's bracketless expression.
    fn assigned_value(&mut self) -> Result<f64, Problem> {
        let first = self.real_value()?;
        self.binary_tail(first, 0, true)
    }

    /// A plain decimal (`12`, `-6.789`, `.5`, `+1.`): a sign, at most 19 digits with at most
    /// one point among them, and a value below 2^53 over a power of ten up to 10^22 — both
    /// exact doubles, so one division rounds their quotient as parsing the text does. `None`
    /// (nothing read) for anything else, which [`Parser::number`] reads in full.
    fn plain_number(&mut self) -> Option<f64> {
        let (v, i) = plain_number_at(self.s, self.i)?;
        self.i = i;
        Some(v)
    }

    fn number(&mut self) -> Result<f64, Problem> {
        if let Some(v) = self.plain_number() {
            return Ok(v);
        }
        let st = self.i;
        if matches!(self.peek(), Some(b'+' | b'-')) {
            self.i += 1;
        }
        // Not a plain decimal: two points, no digit, or too many digits for the fast path.
        let mut digits = 0;
        let mut dots = 0;
        while let Some(c) = self.peek() {
            if c.is_ascii_digit() {
                digits += 1;
            } else if c == b'.' {
                dots += 1;
            } else {
                break;
            }
            self.i += 1;
        }
        let text = self.text_from(st);
        if dots > 1 {
            return Err(Problem::BadNumber(text));
        }
        if digits == 0 {
            self.i = st;
            return Err(Problem::BadNumber(text));
        }
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(Problem::NumberTooLarge(text.len())),
            Err(_) => Err(Problem::BadNumber(text)),
        }
    }

    fn real_value(&mut self) -> Result<f64, Problem> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(Problem::TooDeep);
        }
        let r = self.real_value_inner();
        self.depth -= 1;
        r
    }

    fn real_value_inner(&mut self) -> Result<f64, Problem> {
        match self.peek() {
            Some(b'[') => {
                self.i += 1;
                let first = self.real_value()?;
                let v = self.binary_tail(first, 0, false)?;
                if !self.eat(b']') {
                    return Err(Problem::Expected("']' closing the expression"));
                }
                Ok(v)
            }
            Some(b'#') => {
                self.i += 1;
                match self.param_ref()? {
                    ParamRef::Numbered(n) => Ok(self.env.numbered(n)),
                    ParamRef::Named(name) => {
                        self.env.named(&name).ok_or(Problem::Param(super::params::ParamError::Undefined(name)))
                    }
                }
            }
            Some(b'-') => {
                self.i += 1;
                if self.peek().is_some_and(|c| c.is_ascii_digit() || c == b'.') {
                    self.i -= 1;
                    return self.number();
                }
                Ok(-self.real_value()?)
            }
            Some(b'+') => {
                self.i += 1;
                self.real_value()
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_lowercase() => self.function(),
            Some(_) | None => Err(Problem::Expected("a value")),
        }
    }

    fn param_ref(&mut self) -> Result<ParamRef, Problem> {
        if self.eat(b'<') {
            let st = self.i;
            while self.peek().is_some_and(|c| c != b'>') {
                self.i += 1;
            }
            let name = self.text_from(st);
            if !self.eat(b'>') || name.is_empty() {
                return Err(Problem::Expected("a name closed by '>' after #<"));
            }
            return Ok(ParamRef::Named(name));
        }
        let v = self.real_value()?;
        Params::index(v).map(ParamRef::Numbered).map_err(Problem::Param)
    }

    fn function(&mut self) -> Result<f64, Problem> {
        const NAMES: [&[u8]; 14] = [
            b"abs", b"acos", b"asin", b"atan", b"cos", b"exp", b"fix", b"fup", b"ln", b"round", b"sin", b"sqrt",
            b"tan", b"exists",
        ];
        let Some(name) =
            NAMES.iter().find(|n| self.rest().starts_with(n) && self.s.get(self.i + n.len()) == Some(&b'['))
        else {
            let st = self.i;
            while self.peek().is_some_and(|c| c.is_ascii_lowercase()) {
                self.i += 1;
            }
            return Err(Problem::UnknownFunction(self.text_from(st)));
        };
        self.i += name.len();
        if *name == b"exists" {
            // EXISTS[#<name>]: does the named parameter have a value?
            self.i += 1;
            if !self.eat(b'#') {
                return Err(Problem::Expected("a named parameter in EXISTS[#<name>]"));
            }
            let p = self.param_ref()?;
            if !self.eat(b']') {
                return Err(Problem::Expected("']' closing EXISTS["));
            }
            return Ok(match p {
                ParamRef::Named(n) => f64::from(u8::from(self.env.named(&n).is_some())),
                ParamRef::Numbered(_) => 1.0,
            });
        }
        let a = self.real_value()?;
        let deg = std::f64::consts::PI / 180.0;
        let v = match *name {
            b"abs" => a.abs(),
            b"acos" => {
                if !(-1.0..=1.0).contains(&a) {
                    return Err(Problem::Domain("ACOS", a));
                }
                a.acos() / deg
            }
            b"asin" => {
                if !(-1.0..=1.0).contains(&a) {
                    return Err(Problem::Domain("ASIN", a));
                }
                a.asin() / deg
            }
            b"atan" => {
                if self.eat(b'/') {
                    let x = self.real_value()?;
                    a.atan2(x) / deg
                } else {
                    a.atan() / deg
                }
            }
            b"cos" => (a * deg).cos(),
            b"exp" => a.exp(),
            b"fix" => a.floor(),
            b"fup" => a.ceil(),
            b"ln" => {
                if a <= 0.0 {
                    return Err(Problem::Domain("LN", a));
                }
                a.ln()
            }
            b"round" => a.round(),
            b"sin" => (a * deg).sin(),
            b"sqrt" => {
                if a < 0.0 {
                    return Err(Problem::Domain("SQRT", a));
                }
                a.sqrt()
            }
            _ => (a * deg).tan(),
        };
        finite(v)
    }

    fn operator(&mut self, bare: bool) -> Option<Op> {
        const OPS: [(&[u8], Op); 15] = [
            (b"**", Op::Pow),
            (b"*", Op::Mul),
            (b"/", Op::Div),
            (b"mod", Op::Mod),
            (b"+", Op::Add),
            (b"-", Op::Sub),
            (b"eq", Op::Eq),
            (b"ne", Op::Ne),
            (b"gt", Op::Gt),
            (b"ge", Op::Ge),
            (b"lt", Op::Lt),
            (b"le", Op::Le),
            (b"and", Op::And),
            (b"or", Op::Or),
            (b"xor", Op::Xor),
        ];
        let r = self.rest();
        let (w, op) = OPS.iter().find(|(w, _)| r.starts_with(w))?;
        if bare && w[0].is_ascii_lowercase() {
            // Outside brackets a word operator must be followed by a value, or it is the
            // next word of the line (`#1=5 G1` is not `5 GE …`).
            let next = r.get(w.len()).copied();
            if !next.is_some_and(|c| matches!(c, b'[' | b'#' | b'.' | b'-' | b'+') || c.is_ascii_digit()) {
                return None;
            }
            // Without brackets only the arithmetic operators are read.
            if !matches!(op, Op::Mod) {
                return None;
            }
        }
        self.i += w.len();
        Some(*op)
    }

    /// Precedence climbing: reads `op value` pairs binding tighter than `min`.
    fn binary_tail(&mut self, mut lhs: f64, min: u8, bare: bool) -> Result<f64, Problem> {
        loop {
            let save = self.i;
            let Some(op) = self.operator(bare) else {
                return Ok(lhs);
            };
            if op.precedence() <= min {
                self.i = save;
                return Ok(lhs);
            }
            let mut rhs = self.real_value()?;
            loop {
                let save2 = self.i;
                let Some(next) = self.operator(bare) else {
                    break;
                };
                self.i = save2;
                if next.precedence() > op.precedence() {
                    rhs = self.binary_tail(rhs, op.precedence(), bare)?;
                } else {
                    break;
                }
            }
            lhs = apply(op, lhs, rhs)?;
        }
    }
}

fn finite(v: f64) -> Result<f64, Problem> {
    if v.is_finite() { Ok(v) } else { Err(Problem::NotFinite) }
}

fn apply(op: Op, a: f64, b: f64) -> Result<f64, Problem> {
    let t = |c: bool| f64::from(u8::from(c));
    let eps = EQUAL_SLACK;
    let v = match op {
        Op::Pow => {
            if a < 0.0 && b.fract() != 0.0 {
                return Err(Problem::Domain("**", a));
            }
            a.powf(b)
        }
        Op::Mul => a * b,
        Op::Div => {
            if b == 0.0 {
                return Err(Problem::DivideByZero);
            }
            a / b
        }
        Op::Mod => {
            if b == 0.0 {
                return Err(Problem::DivideByZero);
            }
            // LinuxCNC's MOD is never negative for a positive divisor.
            let r = a % b;
            if r < 0.0 { r + b.abs() } else { r }
        }
        Op::Add => a + b,
        Op::Sub => a - b,
        // Comparisons as LinuxCNC makes them: equal within 1e-6.
        Op::Eq => t((a - b).abs() < eps),
        Op::Ne => t((a - b).abs() >= eps),
        Op::Gt => t(a > b),
        Op::Ge => t(a >= b),
        Op::Lt => t(a < b),
        Op::Le => t(a <= b),
        Op::And => t(a != 0.0 && b != 0.0),
        Op::Or => t(a != 0.0 || b != 0.0),
        Op::Xor => t((a != 0.0) != (b != 0.0)),
    };
    finite(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct E;
    impl Env for E {
        fn numbered(&self, n: usize) -> f64 {
            n as f64 * 10.0
        }
        fn named(&self, name: &str) -> Option<f64> {
            (name == "x").then_some(2.5)
        }
    }

    fn value(text: &str) -> Result<f64, Problem> {
        let mut r = Reader::default();
        r.read(&format!("X{text}"), &E).map(|b| b.get(b'x').unwrap_or(f64::NAN))
    }

    #[test]
    fn numbers_read_as_their_text_parses_bit_for_bit() {
        // Written by a generator over digit counts 1–22 and points anywhere (the fast path's
        // edges: 2^53, 19 digits, 22 after the point, and past each), signs and zeros.
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut texts: Vec<String> = [
            "0",
            "-0",
            "+0",
            "0.",
            ".5",
            "-.5",
            "1.",
            "007",
            "9007199254740991",
            "9007199254740992",
            "9007199254740993",
            "0.1",
            "0.3",
            "123456.789012",
            "-25.4",
            "0.0000000000000000000001",
            "1234567890123456789",
            "12345678901234567890",
            "99999999999999999999999",
            "4.9406564584124654",
            "2.2250738585072014",
            "0.00000000000000000000000001",
        ]
        .iter()
        .map(|t| (*t).to_owned())
        .collect();
        for _ in 0..20_000 {
            let n = (next() % 24 + 1) as usize;
            let mut t: String = (0..n).map(|_| char::from(b'0' + (next() % 10) as u8)).collect();
            if next() % 4 != 0 {
                t.insert((next() as usize) % (n + 1), '.');
            }
            match next() % 3 {
                0 => t.insert(0, '-'),
                1 => t.insert(0, '+'),
                _ => {}
            }
            texts.push(t);
        }
        for t in &texts {
            let want: f64 = t.parse().unwrap();
            let got = value(t).unwrap();
            assert_eq!(got.to_bits(), want.to_bits(), "{t}: {got} against {want}");
        }
    }

    #[test]
    fn precedence_and_associativity_follow_linuxcnc() {
        let cases = [
            ("[1+2*3]", 7.0),
            ("[[1+2]*3]", 9.0),
            ("[2**3**2]", 64.0),
            ("[8/2/2]", 2.0),
            ("[10-4-3]", 3.0),
            ("[7 mod 3]", 1.0),
            ("[-7 mod 3]", 2.0),
            ("[1+1 eq 2]", 1.0),
            ("[1 lt 2 and 3 gt 4]", 0.0),
            ("[1 lt 2 or 3 gt 4]", 1.0),
            ("[1 xor 1]", 0.0),
            ("[#2+#<x>]", 22.5),
            ("##1", 100.0),
            ("#[1+1]", 20.0),
            ("sin[30]", 0.5),
            ("atan[1]/[1]", 45.0),
            ("[abs[-2]+sqrt[16]+fix[2.7]+fup[2.1]+round[2.5]]", 2.0 + 4.0 + 2.0 + 3.0 + 3.0),
            ("-#1", -10.0),
            ("-[1+1]", -2.0),
            ("exists[#<x>]", 1.0),
            ("exists[#<y>]", 0.0),
        ];
        for (text, want) in cases {
            let got = value(text).unwrap_or(f64::NAN);
            assert!((got - want).abs() < 1e-12, "{text}: {got} != {want}");
        }
    }

    #[test]
    fn bad_values_name_the_problem() {
        assert!(matches!(value("[1/0]"), Err(Problem::DivideByZero)));
        assert!(matches!(value("sqrt[-1]"), Err(Problem::Domain("SQRT", _))));
        assert!(matches!(value("#<nope>"), Err(Problem::Param(_))));
        assert!(matches!(value("foo[1]"), Err(Problem::UnknownFunction(_))));
        assert!(matches!(value(&"[".repeat(200)), Err(Problem::TooDeep)));
        assert!(matches!(value("[1+2"), Err(Problem::Expected(_))));
    }

    #[test]
    fn lines_read_as_linuxcnc_reads_them() {
        let mut r = Reader::default();
        let b = r.read("n10 g 1 x 1 0 (a comment) y-2.5 ; tail", &E).cloned().unwrap_or_default();
        assert_eq!(b.g, vec![10]);
        assert_eq!((b.get(b'x'), b.get(b'y')), (Some(10.0), Some(-2.5)));
        assert_eq!(b.comment, "a comment");
        let b = r.read("#1=[#2+1] #<a>=5 G38.2 Z-1", &E).cloned().unwrap_or_default();
        assert_eq!(b.assigns, vec![(ParamRef::Numbered(1), 21.0), (ParamRef::Named("a".into()), 5.0)]);
        assert_eq!(b.g, vec![382]);
        let b = r.read("#100=#1+2*#2 mod 3", &E).cloned().unwrap_or_default();
        assert_eq!(b.assigns, vec![(ParamRef::Numbered(100), 10.0 + (40.0_f64 % 3.0))]);
        let b = r.read("O100 WHILE [#1 LT 3]", &E).cloned().unwrap_or_default();
        assert_eq!(b.oword, Some(OWord { name: "100".into(), kind: OKind::While, args: vec![0.0] }));
        let b = r.read("o<my_sub> call [1] [2+3]", &E).cloned().unwrap_or_default();
        assert_eq!(b.oword, Some(OWord { name: "my_sub".into(), kind: OKind::Call, args: vec![1.0, 5.0] }));
        let b = r.read("IF [#1 GT 5] GOTO 20", &E).cloned().unwrap_or_default();
        assert_eq!(b.flow, Some(Flow::Goto { target: 20.0, cond: Some(1.0) }));
        let b = r.read("WHILE [#1 LT 5] DO1", &E).cloned().unwrap_or_default();
        assert_eq!(b.flow, Some(Flow::While { cond: 0.0, id: 1 }));
        let b = r.read("END1", &E).cloned().unwrap_or_default();
        assert_eq!(b.flow, Some(Flow::End { id: 1 }));
        assert!(matches!(r.read("G1 X1 X2", &E), Err(Problem::Repeated('X'))));
        assert!(r.read("% vfd enable", &E).is_ok_and(|b| b.percent && b.percent_text));
        assert!(matches!(r.read("G1 X1 (open", &E), Err(Problem::UnclosedComment)));
        assert_eq!(r.peek("o100 endwhile"), Peek::O { name: "100".into(), kind: OKind::EndWhile });
        assert_eq!(r.peek("N20 WHILE [#1 LT 5] DO2"), Peek::Do { id: 2 });
        assert_eq!(r.peek("N30 END2"), Peek::End { id: 2 });
        assert_eq!(r.peek("N40 G1 X1"), Peek::N(40.0));
    }
}
