//! What a run prints: CSV and JSON rows in file units (scene-format output section).
//!
//! One number formatter for every output ([`fmt_num`], which lives in
//! [`crate::numerics::format`] so the paper modules can use it without this module): the shortest decimal that reads back
//! to the same f64, so files are exact and deterministic.

use std::io::{self, Write};

use crate::crease::{CreaseError, CreaseJob, Diagnostics, Row, StopReason};
use crate::numerics::sign::stock_positive;

pub use crate::numerics::format::{fmt_fixed, fmt_num, push_num};

/// Output format of `interpolab run`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated, header line first.
    Csv,
    /// One JSON document.
    Json,
}

/// The nine columns every run prints.
pub const COLUMNS: [&str; 9] = ["k", "t_ms", "x", "y", "z", "u1", "v1", "u2", "v2"];

/// Extra columns printed with `--errors` (all mm): measured e1, e2 and the estimates.
pub const ERROR_COLUMNS: [&str; 8] = ["e1", "e2", "est11_1", "est11_2", "est12_1", "est12_2", "est16_1", "est16_2"];

fn row_values(job: &CreaseJob, row: &Row, t_ms: f64) -> [f64; 8] {
    let uv = job.params_to_file(row.uv);
    [t_ms, row.p.x, row.p.y, row.p.z, uv[0].x, uv[0].y, uv[1].x, uv[1].y]
}

/// The `t_ms` column, from the scene's period in ms (the file's number, see
/// [`crate::numerics::units`]): k·Ts for a whole period, and for the shortened final row the
/// previous time plus its chord at the feed, Ts·|p_k − p_(k−1)|/f — the same expressions the
/// run's time `Row::t_s` is formed by in seconds, evaluated in ms so the printed digits do not
/// depend on a conversion's rounding.
struct RowClock {
    period_ms: f64,
    /// Time (ms) and centre of the row written last.
    prev: Option<(f64, glam::DVec3)>,
    /// Duration (ms) of the shortened final period, once written.
    final_period_ms: Option<f64>,
}

impl RowClock {
    fn t_ms(&mut self, job: &CreaseJob, row: &Row, shortened: bool) -> f64 {
        let t = match self.prev {
            Some((t_prev, p_prev)) if shortened => {
                let ms = self.period_ms * (row.p - p_prev).length() / job.feed_per_period_mm;
                self.final_period_ms = Some(ms);
                t_prev + ms
            }
            _ => row.k as f64 * self.period_ms,
        };
        self.prev = Some((t, row.p));
        t
    }
}

fn diag_values(d: &Diagnostics) -> [f64; 8] {
    // e1, e2 print seed 000's sign (negative = gouge, docs/scene-format.md); the core's is
    // overcut positive.
    [
        stock_positive(d.measured[0]),
        stock_positive(d.measured[1]),
        d.est11[0],
        d.est11[1],
        d.est12[0],
        d.est12[1],
        d.est16[0].unwrap_or(f64::NAN),
        d.est16[1].unwrap_or(f64::NAN),
    ]
}

/// Streams rows as they are computed.
pub struct RowWriter<W: Write> {
    out: W,
    format: Format,
    errors: bool,
    first: bool,
    /// The row being written (reused).
    line: String,
    clock: RowClock,
}

impl<W: Write> RowWriter<W> {
    /// Starts the output (CSV header, or the opening of the JSON document). `period_ms` is the
    /// scene's `motion.period` (ms), from which the `t_ms` column is printed.
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn new(
        mut out: W,
        format: Format,
        errors: bool,
        job: &CreaseJob,
        name: &str,
        period_ms: f64,
    ) -> io::Result<Self> {
        match format {
            Format::Csv => {
                let mut cols: Vec<&str> = COLUMNS.to_vec();
                if errors {
                    cols.extend(ERROR_COLUMNS);
                }
                writeln!(out, "{}", cols.join(","))?;
            }
            Format::Json => {
                write!(
                    out,
                    "{{\n  \"format\": \"interpolab-run/1\",\n  \"scene\": {},\n  \"feed_per_period_mm\": {},\n  \"columns\": [",
                    serde_json::to_string(name).unwrap_or_default(),
                    fmt_num(job.feed_per_period_mm)
                )?;
                let mut cols: Vec<&str> = COLUMNS.to_vec();
                if errors {
                    cols.extend(ERROR_COLUMNS);
                }
                let quoted: Vec<String> = cols.iter().map(|c| format!("\"{c}\"")).collect();
                write!(out, "{}],\n  \"rows\": [", quoted.join(", "))?;
            }
        }
        Ok(Self {
            out,
            format,
            errors,
            first: true,
            line: String::with_capacity(256),
            clock: RowClock { period_ms, prev: None, final_period_ms: None },
        })
    }

    /// Writes one row of a whole period (with its diagnostics when the writer prints errors).
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn row(&mut self, job: &CreaseJob, row: &Row, diag: Option<&Diagnostics>) -> io::Result<()> {
        self.write_row(job, row, diag, false)
    }

    /// Writes the shortened final row of a run that ended on an exact point (the
    /// interpolator's `final_period_s` is set once it has produced that row).
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn final_row(&mut self, job: &CreaseJob, row: &Row, diag: Option<&Diagnostics>) -> io::Result<()> {
        self.write_row(job, row, diag, true)
    }

    /// Duration (ms) of the shortened final period, once [`Self::final_row`] wrote it.
    #[must_use]
    pub fn final_period_ms(&self) -> Option<f64> {
        self.clock.final_period_ms
    }

    fn write_row(&mut self, job: &CreaseJob, row: &Row, diag: Option<&Diagnostics>, shortened: bool) -> io::Result<()> {
        let t_ms = self.clock.t_ms(job, row, shortened);
        // The whole line is built in one reused buffer and written at once: no allocation
        // per number or per row.
        let line = &mut self.line;
        line.clear();
        let (sep, empty) = match self.format {
            Format::Csv => (",", ""),
            Format::Json => {
                line.push_str(if self.first { "\n    [" } else { ",\n    [" });
                (", ", "null")
            }
        };
        push_index(line, row.k);
        let field = |line: &mut String, v: f64| {
            line.push_str(sep);
            if v.is_finite() { push_num(line, v) } else { line.push_str(empty) }
        };
        for v in row_values(job, row, t_ms) {
            field(line, v);
        }
        if self.errors {
            for v in diag.map_or([f64::NAN; 8], diag_values) {
                field(line, v);
            }
        }
        line.push_str(match self.format {
            Format::Csv => "\n",
            Format::Json => "]",
        });
        self.out.write_all(line.as_bytes())?;
        self.first = false;
        Ok(())
    }

    /// Ends the output with the run's outcome and, when `path.end` was not reached, the
    /// note saying what to change (JSON only; CSV has no footer).
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn finish(self, outcome: &Result<StopReason, CreaseError>, note: Option<&str>) -> io::Result<W> {
        self.finish_exact(outcome, note, None)
    }

    /// As [`Self::finish`]; when the run ended on an exact end point with a final period of
    /// its own, `final_period_ms` is that period's duration (ms) and the JSON `stop` object
    /// carries it as `final_period_ms` (an addition to format 1).
    ///
    /// # Errors
    /// I/O errors of `out`.
    pub fn finish_exact(
        mut self,
        outcome: &Result<StopReason, CreaseError>,
        note: Option<&str>,
        final_period_ms: Option<f64>,
    ) -> io::Result<W> {
        if self.format == Format::Json {
            let stop = match outcome {
                Ok(r) => format!(
                    "{{ \"ok\": true, \"reason\": \"{}\", \"message\": {}{}{} }}",
                    r.tag(),
                    serde_json::to_string(&r.to_string()).unwrap_or_default(),
                    note.map_or(String::new(), |n| format!(
                        ", \"note\": {}",
                        serde_json::to_string(n).unwrap_or_default()
                    )),
                    final_period_ms
                        .filter(|ms| ms.is_finite())
                        .map_or(String::new(), |ms| format!(", \"final_period_ms\": {}", fmt_num(ms)))
                ),
                Err(e) => format!(
                    "{{ \"ok\": false, \"reason\": \"error\", \"message\": {} }}",
                    serde_json::to_string(&e.to_string()).unwrap_or_default()
                ),
            };
            write!(self.out, "\n  ],\n  \"stop\": {stop}\n}}\n")?;
        }
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Appends the decimal digits of `k` (as `{}` prints it) without going through `fmt`.
fn push_index(out: &mut String, k: u64) {
    let mut digits = [0u8; 20];
    let mut at = digits.len();
    let mut rest = k;
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    for &d in &digits[at..] {
        out.push(char::from(d));
    }
}

/// Characters a spreadsheet takes, at the start of a cell, as the start of a formula (OWASP's
/// list for CSV injection; TAB and CR are turned into spaces before this is asked).
const FORMULA_STARTS: [char; 4] = ['=', '+', '-', '@'];

/// Invisible characters that reorder or hide text (bidirectional overrides and isolates,
/// zero-width characters, the byte-order mark): shown as `_` in one-line text.
fn invisible(c: char) -> bool {
    matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2060}'..='\u{2064}' | '\u{2066}'..='\u{2069}' | '\u{feff}')
}

/// One character of user text on one line of a text output: every line break and white
/// space a space, every control or invisible character `_`.
fn line_char(c: char) -> char {
    if c.is_whitespace() {
        ' '
    } else if c.is_control() || invisible(c) {
        '_'
    } else {
        c
    }
}

/// A user's text (a scene's name, a file's path) on one line of a text report — a Markdown
/// heading or table line, a summary line: every line break (LF, CR, VT, FF, NEL, U+2028,
/// U+2029) and white space a space, every control character (C0, DEL, C1) and invisible one
/// (bidirectional overrides, zero widths) `_`; everything else, non-ASCII too, kept.
/// At most [`crate::numerics::limits::MAX_COMMENT_CHARS`] characters (`...` at the end when cut). A
/// text without those characters, of at most that length, is returned as it is.
#[must_use]
pub fn one_line(text: &str) -> String {
    let cap = crate::numerics::limits::MAX_COMMENT_CHARS;
    let mut out = String::new();
    for (n, c) in text.chars().enumerate() {
        if n == cap {
            let cut: String = out.chars().take(cap - 3).collect();
            return cut + "...";
        }
        out.push(line_char(c));
    }
    out
}

/// A refusal or warning as one line of standard error, whatever user text it quotes (a key
/// with a carriage return flipped into it, a NUL in a path): [`one_line`]'s characters, not
/// cut (a message names the problem and what to change, and may be long).
#[must_use]
pub fn message_line(text: &str) -> String {
    if text.chars().all(|c| line_char(c) == c) {
        return text.to_owned();
    }
    text.chars().map(line_char).collect()
}

/// A user's text on a `#` comment line of a CSV output (`# interpolab steps: NAME`), so a
/// spreadsheet that opens the file runs nothing and the rows stay rows: [`one_line`]
/// (no line break can start a row), `"` as `'` (a quote cannot open a field that runs on
/// over the following lines), and every piece after a `,` or `;` (the field separators of
/// spreadsheets in different locales) that would begin, after spaces, with `=` `+` `-` or
/// `@` gets a `'` before that character, as spreadsheets mark text. The first piece shares
/// its field with the line's `#`. Numeric cells of the outputs never pass here: they stay
/// the numbers they are (`-3.5`).
#[must_use]
pub fn csv_comment_text(text: &str) -> String {
    let line = one_line(text).replace('"', "'");
    let mut out = String::with_capacity(line.len() + 8);
    let mut field_start = false;
    for c in line.chars() {
        if field_start && c != ' ' {
            if FORMULA_STARTS.contains(&c) {
                out.push('\'');
            }
            field_start = false;
        }
        out.push(c);
        if c == ',' || c == ';' {
            field_start = true;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::push_index;

    #[test]
    fn indices_print_as_display_does() {
        let mut k = 1u64;
        let mut samples = vec![0, 9, 10, 99, 100, 101, 999_999, u64::MAX, u64::MAX - 1];
        for _ in 0..200 {
            // A fixed pseudo-random walk over all magnitudes.
            k = k.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            samples.push(k >> (k % 64));
        }
        for k in samples {
            let mut s = String::from("x");
            push_index(&mut s, k);
            assert_eq!(s, format!("x{k}"));
        }
    }
}

#[cfg(test)]
mod text_tests {
    use super::{csv_comment_text, one_line};

    #[test]
    fn benign_text_is_kept_and_hostile_text_stays_on_its_line_without_formulas() {
        let benign = "Torus ring through a tilted plate, on a head B/C machine (µm, 30°)";
        assert_eq!(one_line(benign), benign);
        assert_eq!(csv_comment_text(benign), benign);
        assert_eq!(one_line("a\nb\r\u{2028}c\u{85}d\u{0}e\u{202e}"), "a b  c d_e_");
        assert_eq!(csv_comment_text("x,=1+1; @A1,  -2,\"q\""), "x,'=1+1; '@A1,  '-2,'q'");
        let long = one_line(&"y".repeat(1000));
        assert_eq!(long.chars().count(), crate::numerics::limits::MAX_COMMENT_CHARS);
        assert!(long.ends_with("..."));
    }
}
