//! Seed 004's comparison, for any design curve and tolerance: the G01, G02/G03 and G06.2
//! programs' size (path blocks, bytes), their worst deviation after rounding, and the
//! smoothness of the feed they allow; and the real-time interpolation of the G06.2 curve by
//! each parameter update. One function for the app's table and the command line.
//!
//! Feed smoothness of a program, at its junctions between consecutive cutting moves:
//! - the largest **turn** θ between the end tangent of one move and the start tangent of the
//!   next: at feed F the velocity jumps by `2F·sin(θ/2)` there, so the control must slow
//!   down (a polyline turns at every block);
//! - the largest **curvature jump** Δκ: the centripetal acceleration jumps by `F²·Δκ`
//!   (infinite jerk) — lines and arcs meet with different curvatures, a C² cubic NURBS is one
//!   block without junctions.
//!
//! and, for the G06.2 curve, the feed fluctuation of real-time interpolation (see
//! [`crate::nurbs_path::realtime`]).

use glam::DVec3;

use super::dialect::Dialect;
use super::kind::ProgramKind;
use super::path::{PathBlock, Toolpath};
use super::write::{Program, ProgramError, ProgramOptions, write_program};
use crate::geom::Curve3;
use crate::numerics::format::fmt_fixed;
use crate::nurbs_path::realtime::{FeedStats, RealtimeOptions, Update, interpolate_realtime};

/// Options of [`compare`].
#[derive(Clone, Debug, PartialEq)]
pub struct CompareOptions {
    /// Options of the three programs (resolution, feed, point, …).
    pub program: ProgramOptions,
    /// Period of the real-time runs (ms, default 4); the feed is the program's.
    pub period_ms: f64,
    /// Chord tolerance of the real-time runs' feed limit (mm); `None` (default) runs at F.
    pub chord_tol_mm: Option<f64>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self { program: ProgramOptions::default(), period_ms: 4.0, chord_tol_mm: None }
    }
}

/// Tangent and curvature continuity at the junctions of a program's cutting moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Junctions {
    /// Junctions between consecutive cutting moves.
    pub count: usize,
    /// Largest turn of the tangent (deg).
    pub max_turn_deg: f64,
    /// Largest jump of the curvature (1/mm).
    pub max_curvature_jump: f64,
}

impl Junctions {
    /// Largest velocity jump at feed F (mm/min): `2F·sin(θ/2)`.
    #[must_use]
    pub fn velocity_jump(&self, feed_mm_per_min: f64) -> f64 {
        2.0 * feed_mm_per_min * (0.5 * self.max_turn_deg.to_radians()).sin()
    }
    /// Largest centripetal-acceleration jump at feed F (mm/s²): `(F/60)²·Δκ`, F given in
    /// the program's mm/min.
    #[must_use]
    pub fn acceleration_jump(&self, feed_mm_per_min: f64) -> f64 {
        crate::numerics::units::mm_per_s_from_mm_per_min(feed_mm_per_min).powi(2) * self.max_curvature_jump
    }
}

fn end_state(b: &PathBlock, at_end: bool) -> (DVec3, f64) {
    let c = b.segment.curve();
    let (lo, hi) = c.range();
    let [_, d1, _] = c.derivatives_at(if at_end { hi } else { lo });
    (d1.normalize_or_zero(), c.curvature_at(if at_end { hi } else { lo }))
}

/// Measures the junctions of a toolpath's cutting moves.
#[must_use]
pub fn junctions(path: &Toolpath) -> Junctions {
    let cuts: Vec<&PathBlock> = path.cuts().collect();
    let mut j = Junctions::default();
    for w in cuts.windows(2) {
        let (t0, k0) = end_state(w[0], true);
        let (t1, k1) = end_state(w[1], false);
        let turn = t0.dot(t1).clamp(-1.0, 1.0).acos().to_degrees();
        j.count += 1;
        j.max_turn_deg = j.max_turn_deg.max(turn);
        j.max_curvature_jump = j.max_curvature_jump.max((k1 - k0).abs());
    }
    j
}

/// One row of the comparison.
#[derive(Clone, Debug)]
pub struct CompareRow {
    /// The kind.
    pub kind: ProgramKind,
    /// Blocks describing the path.
    pub path_blocks: usize,
    /// Blocks of the whole program (with header, approach and end).
    pub total_blocks: usize,
    /// Bytes of the program.
    pub bytes: usize,
    /// Worst two-sided deviation after rounding (mm).
    pub deviation_mm: f64,
    /// Junction continuity.
    pub junctions: Junctions,
    /// The program.
    pub program: Program,
}

/// A comparison at one tolerance.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Tolerance (mm).
    pub tol_mm: f64,
    /// Feed (mm/min).
    pub feed_mm_per_min: f64,
    /// One row per program kind.
    pub rows: Vec<CompareRow>,
    /// Real-time interpolation of the (rounded) G06.2 curve, one per update.
    pub realtime: Vec<FeedStats>,
    /// Programs the dialect cannot carry, with the reason (a LinuxCNC G5.2 program of a path
    /// that is not planar in XY); their rows are left out.
    pub notes: Vec<String>,
}

impl CompareOptions {
    /// The options of the real-time runs with `update`: the program's feed, this period and
    /// chord tolerance, statistics only.
    #[must_use]
    pub fn realtime(&self, update: Update) -> RealtimeOptions {
        RealtimeOptions::default()
            .with_feed(self.program.feed_mm_per_min, self.period_ms)
            .with_update(update)
            .with_chord_tol(self.chord_tol_mm)
            .with_samples(false)
    }
}

/// Writes the three programs for `design` at `tol_mm`, checks them, and runs the G06.2 curve
/// with each real-time update.
///
/// The same as [`compare_row`] for each kind in [`ProgramKind::ALL`] followed by
/// [`realtime_stats`] of the G06.2 row: an interactive caller may run those steps one at a
/// time (one per frame) and assemble the same [`Comparison`].
///
/// # Errors
/// The first program that cannot be written ([`ProgramError`]).
pub fn compare(design: &dyn Curve3, tol_mm: f64, opts: &CompareOptions) -> Result<Comparison, ProgramError> {
    let mut rows = Vec::new();
    let mut realtime = Vec::new();
    let mut notes = Vec::new();
    for kind in ProgramKind::ALL {
        let row = match compare_row(kind, design, tol_mm, opts) {
            Ok(row) => row,
            Err(e @ ProgramError::NotPlanar { .. }) => {
                let d = opts.program.dialect;
                notes.push(format!("{} ({d}) not written: {e}", d.kind_label(kind)));
                continue;
            }
            Err(e) => return Err(e),
        };
        realtime.extend(realtime_stats(&row.program, opts));
        rows.push(row);
    }
    Ok(Comparison { tol_mm, feed_mm_per_min: opts.program.feed_mm_per_min, rows, realtime, notes })
}

/// One row of the comparison: writes and checks the program of `kind`, and measures its
/// junctions.
///
/// # Errors
/// [`ProgramError`] when the program cannot be written.
pub fn compare_row(
    kind: ProgramKind,
    design: &dyn Curve3,
    tol_mm: f64,
    opts: &CompareOptions,
) -> Result<CompareRow, ProgramError> {
    let program = write_program(kind, design, tol_mm, &opts.program)?;
    Ok(CompareRow {
        kind,
        path_blocks: program.path_blocks,
        total_blocks: program.parsed.blocks,
        bytes: program.bytes(),
        deviation_mm: program.deviation.max_mm(),
        junctions: junctions(&program.parsed.toolpath),
        program,
    })
}

/// Real-time interpolation statistics of a program's G06.2 curves as read back from its
/// text (rounded), one entry per curve and update ([`Update::ALL`] order); empty for a
/// program without G06.2 moves. A curve that cannot be run (it stalls) is left out.
#[must_use]
pub fn realtime_stats(program: &Program, opts: &CompareOptions) -> Vec<FeedStats> {
    let mut out = Vec::new();
    for c in program.read_back_curves() {
        for update in Update::ALL {
            if let Ok(run) = interpolate_realtime(c, &opts.realtime(update)) {
                out.push(run.stats);
            }
        }
    }
    out
}

/// Output style of [`format_comparison`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableStyle {
    /// A Markdown table (docs).
    Markdown,
    /// Comma-separated values with a header line.
    Csv,
}

/// The comparison as text: the programs table, then the real-time table; the last column
/// names the dialect.
#[must_use]
pub fn format_comparison(c: &Comparison, style: TableStyle) -> String {
    format_comparisons(std::slice::from_ref(c), style)
}

/// Comparisons in several dialects (same design and tolerance) as one programs table and
/// one real-time table, the dialect in the last column; "vs G01" is against the line
/// program of the same dialect. In Markdown, programs a dialect cannot carry are listed
/// under the programs table.
#[must_use]
pub fn format_comparisons(cs: &[Comparison], style: TableStyle) -> String {
    format_comparisons_with(cs, &ExtraColumns::default(), style)
}

/// Columns a caller adds to the programs table (e.g. the time on a machine, from
/// [`crate::plan`]): headers, then one cell per header for every row of every comparison
/// (rows without cells get empty ones), and notes printed under the Markdown table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ExtraColumns {
    /// Headers, inserted before the dialect column.
    pub heads: Vec<String>,
    /// `cells[c][r]`: the cells of row r of comparison c.
    pub cells: Vec<Vec<Vec<String>>>,
    /// Lines under the Markdown table.
    pub notes: Vec<String>,
}

/// [`format_comparisons`] with extra columns.
#[must_use]
pub fn format_comparisons_with(cs: &[Comparison], extra: &ExtraColumns, style: TableStyle) -> String {
    let mut head: Vec<String> = [
        "program",
        "path blocks",
        "vs G01",
        "bytes",
        "max deviation mm",
        "junctions",
        "max turn deg",
        "velocity jump mm/min",
        "max curvature jump 1/mm",
        "accel jump mm/s2",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    head.extend(extra.heads.iter().cloned());
    head.push("dialect".to_owned());
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut notes: Vec<&str> = Vec::new();
    for (ci, c) in cs.iter().enumerate() {
        notes.extend(c.notes.iter().map(String::as_str));
        let lines_blocks = c.rows.iter().find(|r| r.kind == ProgramKind::Lines).map(|r| r.path_blocks);
        for (ri, r) in c.rows.iter().enumerate() {
            let mut more: Vec<String> = extra.cells.get(ci).and_then(|c| c.get(ri)).cloned().unwrap_or_default();
            more.resize(extra.heads.len(), String::new());
            let vs = match lines_blocks {
                Some(l) if l > 0 => format!("{:+.0}%", 100.0 * (r.path_blocks as f64 - l as f64) / l as f64),
                _ => String::new(),
            };
            rows.push(vec![
                r.program.dialect.kind_label(r.kind).to_owned(),
                r.path_blocks.to_string(),
                vs,
                r.bytes.to_string(),
                fmt_fixed(r.deviation_mm, 6),
                r.junctions.count.to_string(),
                fmt_fixed(r.junctions.max_turn_deg, 3),
                fmt_fixed(r.junctions.velocity_jump(c.feed_mm_per_min), 1),
                fmt_fixed(r.junctions.max_curvature_jump, 4),
                fmt_fixed(r.junctions.acceleration_jump(c.feed_mm_per_min), 2),
            ]);
            if let Some(row) = rows.last_mut() {
                row.extend(more);
                row.push(r.program.dialect.as_str().to_owned());
            }
        }
    }
    let mut out = table(&head, &rows, style);
    if style == TableStyle::Markdown {
        for n in notes.into_iter().chain(extra.notes.iter().map(String::as_str)) {
            out.push_str(&format!("\n{n}\n"));
        }
    }
    out.push('\n');
    head = [
        "G06.2 update",
        "periods",
        "max feed fluctuation",
        "RMS feed fluctuation",
        "max chord error mm",
        "feed-limited periods",
        "dialect",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    let rt: Vec<Vec<String>> = cs
        .iter()
        .flat_map(|c| {
            let d = c.rows.first().map_or(Dialect::Fanuc, |r| r.program.dialect);
            c.realtime.iter().map(move |s| (d, s))
        })
        .map(|(d, s)| {
            vec![
                s.update.as_str().to_owned(),
                s.periods.to_string(),
                format!("{:.2e}", s.max_fluctuation),
                format!("{:.2e}", s.rms_fluctuation),
                format!("{:.2e}", s.max_chord_error_mm),
                s.limited_periods.to_string(),
                d.as_str().to_owned(),
            ]
        })
        .collect();
    out.push_str(&table(&head, &rt, style));
    out
}

fn table(head: &[String], rows: &[Vec<String>], style: TableStyle) -> String {
    let mut out = String::new();
    match style {
        TableStyle::Csv => {
            out.push_str(&head.iter().map(|h| h.replace(' ', "_")).collect::<Vec<_>>().join(","));
            out.push('\n');
            for r in rows {
                out.push_str(&r.join(","));
                out.push('\n');
            }
        }
        TableStyle::Markdown => {
            out.push_str(&format!("| {} |\n", head.join(" | ")));
            out.push_str(&format!("|{}\n", head.iter().map(|_| "---|").collect::<String>()));
            for r in rows {
                out.push_str(&format!("| {} |\n", r.join(" | ")));
            }
        }
    }
    out
}
