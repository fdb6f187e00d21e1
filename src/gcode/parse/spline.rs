//! The spline words of the Sinumerik and LinuxCNC dialects (see `docs/gcode-dialects.md`):
//!
//! - **Sinumerik 840D** `BSPLINE`: modal; the current position is the first control point,
//!   every following block with axis words adds one (omitted axes keep the previous control
//!   point's value); `SD=` the degree (3 by default, or 2), `PW=` the point's weight (1 when
//!   omitted, 0 < PW ≤ 3), `PL=` the parameter interval length — the knot spacing. The curve
//!   is clamped (it starts at the start point and ends at the last control point) and ends
//!   with the next motion command (G0, G1, …) or the end of the program. The manual does not
//!   say which knot interval a block's `PL` belongs to near the clamped ends, so we read only
//!   curves whose `PL` is the same on every block (equal knot spacing, where every reading
//!   gives the same curve) and refuse different values; a curve without `PL` (spacing chosen
//!   by the control) is read with equal spacing and reported as not modelled.
//! - **LinuxCNC** `G5.2`/`G5.3`: the current position is the first control point; `G5.2`
//!   and the blocks after it add control points `X Y` with weight `P` (1 when omitted; a
//!   `G5.2 P…` without X/Y sets the first point's weight) and order `L` (degree + 1, default
//!   3) on the `G5.2` block; `G5.3` ends the curve and clears the motion mode. The knots are
//!   implied: clamped and uniform (LinuxCNC's `nurbs_G5_knot_vector_creator`: `order` zeros,
//!   1, 2, …, then `order` times the last). Planar in XY at the current Z; a Z word inside
//!   the curve is refused. `G64 P` (path blending tolerance) is recorded in
//!   [`super::ParsedProgram::blend_mm`].

use glam::DVec3;

use super::{ParseError, ParsedProgram, State, Units, Unsupported, Word};
use crate::gcode::dialect::Dialect;
use crate::gcode::path::{Motion, PathBlock, Plane, Segment};
use crate::geom::NurbsCurve;
use crate::geom::nurbs::MAX_DEGREE;
use crate::numerics::tolerance;

/// Largest Sinumerik point weight `PW` (the manual's range is 0 to 3).
const SINUMERIK_MAX_PW: f64 = 3.0;

/// A spline being read.
pub(in crate::gcode) struct SplineBuild {
    line: usize,
    degree: usize,
    points: Vec<DVec3>,
    weights: Vec<f64>,
    /// The `PL` value and the line it was first given on (Sinumerik).
    pl: Option<(usize, f64)>,
    feed: f64,
}

/// What the G codes of a block asked for, beyond [`super::block`]'s own.
#[derive(Default)]
pub(super) struct Flags {
    /// LinuxCNC `G5.2`.
    open: bool,
    /// LinuxCNC `G5.3`.
    close: bool,
    /// LinuxCNC `G64`: P and Q are its tolerances.
    pub(super) blend: bool,
}

/// The Sinumerik named words of a block.
#[derive(Default)]
pub(super) struct Named {
    bspline: bool,
    sd: Option<f64>,
    pl: Option<f64>,
    pw: Option<f64>,
}

/// Reads a Sinumerik word starting at a letter followed by a letter or `=`: a keyword
/// (`BSPLINE`), a named value (`SD=3`, `PL=12.5`, `PW=1.0`) or an axis with `=` (`X=10`).
pub(super) fn sinumerik_word(line: usize, chars: &[char], i: &mut usize) -> Result<Word, ParseError> {
    let start = *i;
    while *i < chars.len() && (chars[*i].is_ascii_alphabetic() || chars[*i] == '_') {
        *i += 1;
    }
    let name: String = chars[start..*i].iter().collect::<String>().to_ascii_uppercase();
    let letter = name.chars().next().unwrap_or('?');
    if *i < chars.len() && chars[*i] == '=' {
        *i += 1;
        let vs = *i;
        while *i < chars.len()
            && (chars[*i].is_ascii_digit() || chars[*i] == '.' || ((chars[*i] == '-' || chars[*i] == '+') && *i == vs))
        {
            *i += 1;
        }
        let text: String = chars[vs..*i].iter().collect();
        let value = match text.parse::<f64>() {
            Ok(v) if v.is_finite() && text.chars().any(|c| c.is_ascii_digit()) => v,
            _ => {
                let shown = if text.is_empty() { chars[vs..].iter().take(12).collect() } else { text };
                return Err(ParseError::BadNumber { line, letter, text: shown });
            }
        };
        let name = (name.len() > 1).then_some(name);
        return Ok(Word { letter, value, text, name });
    }
    Ok(Word { letter, value: 0.0, text: String::new(), name: Some(name) })
}

/// The named words of a block; names we do not model are reported.
pub(super) fn named_words(line: usize, words: &[Word], out: &mut ParsedProgram) -> Result<Named, ParseError> {
    let mut n = Named::default();
    for w in words {
        let Some(name) = &w.name else { continue };
        let slot = match name.as_str() {
            "BSPLINE" => {
                n.bspline = true;
                continue;
            }
            "SD" => &mut n.sd,
            "PL" => &mut n.pl,
            "PW" => &mut n.pw,
            other => {
                let reason = match other {
                    "ASPLINE" | "CSPLINE" | "POLY" => "A and C splines and polynomial interpolation are not modelled",
                    _ => "this Sinumerik command is not modelled",
                };
                let word = if w.text.is_empty() { other.to_owned() } else { format!("{other}={}", w.text) };
                out.unsupported.push(Unsupported { line, word, reason: reason.into(), count: 1 });
                continue;
            }
        };
        if slot.is_some() {
            return Err(ParseError::Spline { line, what: format!("{name}= appears twice in one block; keep one") });
        }
        *slot = Some(w.value);
    }
    Ok(n)
}

/// Handles the dialect's own G codes (in tenths); true when the code was taken.
pub(super) fn dialect_g(
    line: usize,
    text: &str,
    t: i64,
    st: &mut State,
    flags: &mut Flags,
    out: &mut ParsedProgram,
) -> bool {
    match (st.dialect, t) {
        // G70/G700 inch, G71/G710 metric (G700/G710 also for feeds).
        (Dialect::Sinumerik, 700 | 7000) => st.units = Units::Inch,
        (Dialect::Sinumerik, 710 | 7100) => st.units = Units::Mm,
        // G60 exact stop.
        (Dialect::Sinumerik, 600) => {}
        (Dialect::Sinumerik, 6410 | 6420 | 6430 | 6440 | 6450) => out.unsupported.push(Unsupported {
            line,
            word: format!("G{text}"),
            reason: "corner rounding (G641–G645) moves the path by a machine-data tolerance; use G64".into(),
            count: 1,
        }),
        (Dialect::LinuxCnc, 52) => flags.open = true,
        (Dialect::LinuxCnc, 53) => flags.close = true,
        (Dialect::LinuxCnc, 640) => flags.blend = true,
        // G61 exact path: no blending from here on.
        (Dialect::LinuxCnc, 610) => {}
        _ => return false,
    }
    true
}

/// Whether an `L` word belongs to a LinuxCNC `G5.2` block.
pub(super) fn takes_l(st: &State, flags: &Flags) -> bool {
    st.dialect == Dialect::LinuxCnc && (flags.open || st.spline.is_some())
}

fn err(line: usize, what: String) -> ParseError {
    ParseError::Spline { line, what }
}

/// The dialect's part of a block after its G codes, feed and unmodelled letters: true when
/// the block was taken (a spline block), false when the common reader goes on.
pub(super) fn block(
    line: usize,
    get: &dyn Fn(char) -> Option<f64>,
    motion: Option<Motion>,
    named: &Named,
    flags: &Flags,
    st: &mut State,
    out: &mut ParsedProgram,
) -> Result<bool, ParseError> {
    match st.dialect {
        Dialect::Fanuc => Ok(false),
        Dialect::Sinumerik => sinumerik_block(line, get, motion, named, st, out),
        Dialect::LinuxCnc => linuxcnc_block(line, get, motion, flags, st, out),
    }
}

fn scale(st: &State) -> f64 {
    if st.units == Units::Inch { 25.4 } else { 1.0 }
}

/// Adds the control point of a block's axis words (omitted axes keep the previous point's).
fn add_point(sp: &mut SplineBuild, get: &dyn Fn(char) -> Option<f64>, scale: f64, weight: f64) {
    let mut p = sp.points[sp.points.len() - 1];
    for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if let Some(v) = get(l) {
            p[i] = v * scale;
        }
    }
    sp.points.push(p);
    sp.weights.push(weight);
}

fn sinumerik_block(
    line: usize,
    get: &dyn Fn(char) -> Option<f64>,
    motion: Option<Motion>,
    named: &Named,
    st: &mut State,
    out: &mut ParsedProgram,
) -> Result<bool, ParseError> {
    if named.bspline {
        if let Some(m) = motion {
            return Err(err(
                line,
                format!("BSPLINE and {} in the same block; a block has one motion command", m.gcode()),
            ));
        }
        finish(st, out)?;
        if !st.absolute {
            return Err(err(line, "BSPLINE needs absolute coordinates here; add G90 before it".to_owned()));
        }
        let sd = named.sd.unwrap_or(3.0);
        let (lo, hi) = Dialect::Sinumerik.nurbs_degrees();
        if !(sd.fract() == 0.0 && (lo as f64..=hi as f64).contains(&sd)) {
            return Err(err(line, format!("SD={sd} is not a BSPLINE degree; write SD=2 or SD=3")));
        }
        let feed = st.feed.ok_or(ParseError::MissingFeed { line, code: "BSPLINE" })?;
        st.spline =
            Some(SplineBuild { line, degree: sd as usize, points: vec![st.pos], weights: vec![1.0], pl: None, feed });
        st.motion = Some(Motion::Nurbs);
    } else if st.spline.is_none() {
        for (name, v) in [("SD", named.sd), ("PL", named.pl), ("PW", named.pw)] {
            if let Some(v) = v {
                out.unsupported.push(Unsupported {
                    line,
                    word: format!("{name}={v}"),
                    reason: "SD, PL and PW act only in BSPLINE mode".into(),
                    count: 1,
                });
            }
        }
        return Ok(false);
    } else if motion.is_some() {
        // A new motion command ends the curve; the common reader takes the block.
        finish(st, out)?;
        return Ok(false);
    }
    let scale = scale(st);
    let Some(sp) = st.spline.as_mut() else {
        return Ok(false);
    };
    if let Some(sd) = named.sd
        && (sd.fract() != 0.0 || sd.round() as i64 != sp.degree as i64)
    {
        return Err(err(
            line,
            format!("SD={sd} inside a BSPLINE curve of degree {}; give SD on its first block", sp.degree),
        ));
    }
    if let Some(pl) = named.pl {
        if !(pl > 0.0) {
            return Err(err(line, format!("PL={pl} must be a positive knot interval (mm)")));
        }
        match sp.pl {
            None => sp.pl = Some((line, pl)),
            Some((l0, p0)) if (pl - p0).abs() > tolerance::KNOT_EQUAL_REL * p0.max(1.0) => {
                return Err(err(
                    line,
                    format!(
                        "PL={pl} differs from PL={p0} of line {l0}; interpolab reads BSPLINE curves with one PL (equal knot intervals) only — write the same PL on every block"
                    ),
                ));
            }
            Some(_) => {}
        }
    }
    let has_axis = ['X', 'Y', 'Z'].iter().any(|&l| get(l).is_some());
    if has_axis {
        let w = named.pw.unwrap_or(1.0);
        if !(w > 0.0 && w <= SINUMERIK_MAX_PW) {
            return Err(err(line, format!("PW={w} is outside the point-weight range; give 0 < PW ≤ 3")));
        }
        add_point(sp, get, scale, w);
    } else if named.pw.is_some() {
        return Err(err(line, "PW without a control point; write it in the block of its X, Y, Z".to_owned()));
    }
    Ok(true)
}

fn linuxcnc_block(
    line: usize,
    get: &dyn Fn(char) -> Option<f64>,
    motion: Option<Motion>,
    flags: &Flags,
    st: &mut State,
    out: &mut ParsedProgram,
) -> Result<bool, ParseError> {
    let scale = scale(st);
    if flags.blend {
        match get('P') {
            Some(p) if p >= 0.0 => out.blend_mm = Some(out.blend_mm.unwrap_or(0.0).max(p * scale)),
            _ => out.unsupported.push(Unsupported {
                line,
                word: "G64".into(),
                reason:
                    "G64 without a P tolerance lets LinuxCNC leave the path by an unbounded amount; write G64 P<mm>"
                        .into(),
                count: 1,
            }),
        }
    }
    if flags.open && flags.close {
        return Err(err(line, "G5.2 and G5.3 in the same block; close the curve on its own block".to_owned()));
    }
    if flags.open {
        if let Some(m) = motion {
            return Err(err(line, format!("G5.2 and {} in the same block; a block has one motion code", m.gcode())));
        }
        let order = get('L').unwrap_or(3.0);
        match &st.spline {
            Some(sp) => {
                if get('L').is_some() && (order.fract() != 0.0 || order.round() as i64 != sp.degree as i64 + 1) {
                    return Err(err(line, format!("L{order} changes the order inside a G5.2 curve; give L once")));
                }
            }
            None => {
                if !st.absolute {
                    return Err(err(line, "G5.2 needs absolute coordinates here; add G90 before it".to_owned()));
                }
                if st.plane != Plane::Xy {
                    return Err(err(line, "G5.2 is read in the XY plane only; select G17 before it".to_owned()));
                }
                if !(order.fract() == 0.0 && (3.0..=(MAX_DEGREE + 1) as f64).contains(&order)) {
                    return Err(err(
                        line,
                        format!(
                            "G5.2 order L{order} is not supported; use L3 (quadratic) or L4 (cubic) — LinuxCNC does not honour orders below 3 in every version"
                        ),
                    ));
                }
                let feed = st.feed.ok_or(ParseError::MissingFeed { line, code: "G5.2" })?;
                st.spline = Some(SplineBuild {
                    line,
                    degree: order as usize - 1,
                    points: vec![st.pos],
                    weights: vec![1.0],
                    pl: None,
                    feed,
                });
            }
        }
        st.motion = Some(Motion::Nurbs);
    }
    if flags.close {
        if st.spline.is_none() {
            return Err(err(line, "G5.3 without an open G5.2 curve".to_owned()));
        }
        finish(st, out)?;
        // LinuxCNC clears the motion mode: the next move needs its own G code.
        st.motion = None;
        return Ok(true);
    }
    let Some(sp) = st.spline.as_mut() else {
        return Ok(false);
    };
    if let Some(m) = motion {
        return Err(err(
            line,
            format!("{} inside the G5.2 curve of line {}; close the curve with G5.3 first", m.gcode(), sp.line),
        ));
    }
    if get('Z').is_some() {
        return Err(err(
            line,
            "Z inside a G5.2 curve: LinuxCNC NURBS are planar in XY; move Z before G5.2, or use G1/G2/G3".to_owned(),
        ));
    }
    let w = get('P').unwrap_or(1.0);
    if !(w > 0.0 && w.is_finite()) {
        return Err(ParseError::NurbsWeight { line, value: w });
    }
    if get('X').is_some() || get('Y').is_some() {
        add_point(sp, get, scale, w);
    } else if flags.open && get('P').is_some() {
        // `G5.2 P…` without X/Y: the weight of the first control point.
        sp.weights[0] = w;
    }
    Ok(true)
}

/// Ends the curve being read, if any, and adds it to the path.
fn finish(st: &mut State, out: &mut ParsedProgram) -> Result<(), ParseError> {
    let Some(sp) = st.spline.take() else {
        return Ok(());
    };
    let line = sp.line;
    let n = sp.points.len();
    let p = sp.degree;
    let name = if st.dialect == Dialect::Sinumerik { "BSPLINE" } else { "G5.2" };
    if n < p + 1 {
        return Err(err(
            line,
            format!(
                "the {name} curve started here has {n} control points with its start point; degree {p} needs at least {}",
                p + 1
            ),
        ));
    }
    if st.dialect == Dialect::Sinumerik && sp.pl.is_none() {
        out.unsupported.push(Unsupported {
            line,
            word: "BSPLINE".into(),
            reason: "without PL the control chooses the knot spacing itself; read with equal spacing".into(),
            count: 1,
        });
    }
    let h = sp.pl.map_or(1.0, |(_, v)| v);
    let spans = n - p;
    let mut knots = vec![0.0; p + 1];
    knots.extend((1..spans).map(|j| j as f64 * h));
    knots.extend(std::iter::repeat_n(spans as f64 * h, p + 1));
    let curve = NurbsCurve::try_new(p, knots, &sp.points, Some(&sp.weights))
        .map_err(|source| ParseError::Nurbs { line, source })?;
    st.pos = sp.points[n - 1];
    out.toolpath.blocks.push(PathBlock {
        line,
        motion: Motion::Nurbs,
        segment: Segment::Nurbs(curve),
        feed_mm_per_min: Some(sp.feed),
    });
    Ok(())
}

/// The end of the text: a Sinumerik curve ends there; a LinuxCNC one must have been closed.
pub(super) fn end_of_program(st: &mut State, out: &mut ParsedProgram) -> Result<(), ParseError> {
    if st.dialect == Dialect::LinuxCnc
        && let Some(sp) = &st.spline
    {
        return Err(err(sp.line, "the G5.2 curve started here is not closed; end it with G5.3".to_owned()));
    }
    finish(st, out)
}
