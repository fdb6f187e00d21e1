//! The spline words as NURBS curves in the program frame (mm): LinuxCNC's G5 (cubic) and G5.1
//! (quadratic) Bézier blocks, and the multi-block curves — FANUC `G6.2`, LinuxCNC
//! `G5.2 … G5.3` and Sinumerik `BSPLINE` — read by a streaming [`SplineBuilder`].
//!
//! **G5 / G5.1** (LinuxCNC's `convert_spline`; G-code manual "G5 Cubic Spline", "G5.1
//! Quadratic Spline"): one Bézier each, as one clamped NURBS of degree 3 (4 control points)
//! or 2 (3 points) — what LinuxCNC hands to `NURBS_FEED` (`rs274` prints the count of control
//! points). For G5 the points are the start S, S + (I, J), E + (P, Q) and the end E; I J may
//! be left out (both), and then are the previous G5's −P, −Q (LinuxCNC keeps them in
//! `cycle_i/j`, zero before any G5). For G5.1 they are S, S + (I, J), E, and rs274 2.9 wants
//! both I and J. Both run in G17 only, move X and Y only (at the current Z), and are refused
//! with cutter compensation on, as LinuxCNC refuses them.
//!
//! **Multi-block curves**: the rules of our reader `gcode::parse` (`start_nurbs`,
//! `nurbs_block`, `finish_nurbs`, `parse/spline.rs`), moved here unchanged so that the
//! interpreter and the writers' read-back agree (the tests compare the curves and the
//! errors with `parse_program_in`):
//!
//! - FANUC `G6.2 [P order] [K knot] X Y Z [R weight]`, then `K X Y Z [R]` per control point
//!   (omitted axes keep the previous point's value, omitted weight 1), then exactly `order`
//!   blocks holding only K; knots non-decreasing, the first and last `order` equal (alarm
//!   1007); the first control point is the current position.
//! - LinuxCNC `G5.2 [P weight] [L order] X Y`, `X Y [P]` …, `G5.3`: XY only at the current Z,
//!   order 3 unless L (3 to 10), clamped uniform knots (LinuxCNC's `knot_vector_creator`).
//! - Sinumerik `BSPLINE [SD=2|3] X Y Z [PW=] [PL=]`: ends at the next motion command or the end
//!   of the program; equal knot spacing (one `PL` for the whole curve).
//!
//! Where this differs from LinuxCNC's own G5.2 (it refuses a point without `P` but the first,
//! needs X and Y together, takes `L` ≤ 3 as 3 and lets a later `L` change the order), ours is
//! the more forgiving reading of programs LinuxCNC also runs; what LinuxCNC's controller then
//! moves along is not the NURBS itself but biarcs through 4 points per control point
//! (`emccanon.cc` `NURBS_FEED`), within its blending tolerance of it.
//!
//! Lengths come in mm (the executor converts G20 programs); knots (`K`, `PL`) and weights are
//! as written. Errors carry the place they are about ([`SplineError::loc`]) — the current block,
//! or the block that opened the curve — and the executor prefixes it.

use glam::DVec3;
use thiserror::Error;

use super::canon::Loc;
use crate::gcode::path::Plane;
use crate::geom::nurbs::MAX_DEGREE;
use crate::geom::{NurbsCurve, NurbsError};
use crate::numerics::tolerance;

#[cfg(test)]
mod tests;

/// Largest Sinumerik point weight `PW` (the manual's range is 0 to 3).
const SINUMERIK_MAX_PW: f64 = 3.0;

/// Which multi-block spline a block opens.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplineKind {
    /// FANUC `G6.2` (explicit knots, closing K blocks).
    Fanuc,
    /// LinuxCNC `G5.2` … `G5.3` (implied uniform knots, XY).
    LinuxCnc,
    /// Sinumerik 840D `BSPLINE` (ends at the next motion command).
    Sinumerik,
}

/// A spline's words in one block: X Y Z in **mm** as written (the curves need G90, so
/// these are program-frame coordinates), the rest as written.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SplineWords {
    /// X (mm).
    pub x: Option<f64>,
    /// Y (mm).
    pub y: Option<f64>,
    /// Z (mm).
    pub z: Option<f64>,
    /// K: a knot (G6.2).
    pub k: Option<f64>,
    /// R: a weight (G6.2).
    pub r: Option<f64>,
    /// P: the order on a `G6.2` block; a weight in a `G5.2` curve.
    pub p: Option<f64>,
    /// L: the order on a `G5.2` block.
    pub l: Option<f64>,
    /// `SD=`: the degree on a `BSPLINE` block.
    pub sd: Option<f64>,
    /// `PL=`: the knot interval (as written).
    pub pl: Option<f64>,
    /// `PW=`: the point weight.
    pub pw: Option<f64>,
}

impl SplineWords {
    fn has_axis(&self) -> bool {
        self.x.is_some() || self.y.is_some() || self.z.is_some()
    }
}

/// One block as the [`SplineBuilder`] needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplineBlock<'a> {
    /// Where the block is.
    pub loc: Loc,
    /// The block holds `G6.2`, `G5.2` or `BSPLINE`.
    pub open: Option<SplineKind>,
    /// The block holds `G5.3`.
    pub close: bool,
    /// Another motion code of group 1 in the block, as written (`"G01"`), if any.
    pub other_motion: Option<&'a str>,
    /// The current position (program frame, mm).
    pub position: DVec3,
    /// G90 (true) or G91.
    pub absolute: bool,
    /// The selected plane.
    pub plane: Plane,
    /// A feed rate is in force (set on this block or before).
    pub feed_set: bool,
    /// G20 is in force: the FANUC start-point tolerance is in inches then.
    pub inch: bool,
    /// The words.
    pub words: SplineWords,
}

/// A curve the builder has finished.
#[derive(Clone, Debug, PartialEq)]
pub struct FinishedSpline {
    /// The block that opened it.
    pub loc: Loc,
    /// The curve (program frame, mm); it starts at the position before that block.
    pub curve: NurbsCurve,
    /// Where it ends: the new current position.
    pub end: DVec3,
    /// Something to report about it, once.
    pub note: Option<SplineNote>,
}

/// Something to report about a finished curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SplineNote {
    /// A Sinumerik `BSPLINE` without `PL`: the control chooses the knot spacing itself; the
    /// curve was read with equal spacing.
    SpacingChosenByControl,
}

impl std::fmt::Display for SplineNote {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::SpacingChosenByControl => {
                f.write_str("without PL the control chooses the knot spacing itself; read with equal spacing")
            }
        }
    }
}

/// What [`SplineBuilder::block`] did with a block.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplineStep {
    /// The block belonged to the spline (a control point, a knot, the opening or closing
    /// block); false: the executor carries it out as usual (its motion, or nothing).
    pub taken: bool,
    /// A curve that ended at this block (before it, when the block starts something else).
    pub finished: Option<FinishedSpline>,
}

/// A malformed spline. The message does not say where; [`SplineError::loc`] does.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SplineError {
    /// G6.2 order out of range.
    #[error("G06.2 order P{order} is not supported; use P2 to P{} (FANUC: P2 to P4)", MAX_DEGREE + 1)]
    NurbsOrder {
        /// Where.
        at: Loc,
        /// P.
        order: f64,
    },
    /// A control point without K.
    #[error("G06.2 control point without a knot K; every NURBS block carries one knot")]
    NurbsMissingKnot {
        /// Where.
        at: Loc,
    },
    /// A knot smaller than the one before.
    #[error("knot K{value} is smaller than the previous knot {previous}; knots must be non-decreasing")]
    NurbsKnotDecreasing {
        /// Where.
        at: Loc,
        /// Value.
        value: f64,
        /// Previous knot.
        previous: f64,
    },
    /// First or last `order` knots not equal.
    #[error("the {end} {order} knots of the G06.2 curve must be equal (clamped; FANUC alarm 1007)")]
    NurbsNotClamped {
        /// The G6.2 block.
        at: Loc,
        /// "first" or "last".
        end: &'static str,
        /// The order.
        order: usize,
    },
    /// First control point away from the current position.
    #[error(
        "the first control point {first:?} is not the current position {position:?}; a G06.2 curve starts where the previous move ended"
    )]
    NurbsStartMismatch {
        /// Where.
        at: Loc,
        /// First control point (mm).
        first: [f64; 3],
        /// Current position (mm).
        position: [f64; 3],
    },
    /// The curve ended before its closing knots.
    #[error(
        "the G06.2 curve started here has {closing} closing knot blocks but order {order} needs {order}; end it with {order} blocks holding only K"
    )]
    NurbsIncomplete {
        /// The G6.2 block.
        at: Loc,
        /// Closing K blocks given.
        closing: usize,
        /// The order.
        order: usize,
    },
    /// A control point after the closing knots began, or coordinates after the curve ended.
    #[error("control point after the closing knot blocks of the G06.2 curve; the closing K-only blocks come last")]
    NurbsAfterEnd {
        /// Where.
        at: Loc,
    },
    /// G6.2 in incremental mode.
    #[error("G06.2 needs absolute coordinates; add G90 before it")]
    NurbsIncremental {
        /// Where.
        at: Loc,
    },
    /// A weight not positive.
    #[error("weight R{value} must be positive")]
    NurbsWeight {
        /// Where.
        at: Loc,
        /// Value.
        value: f64,
    },
    /// A spline without a feed rate.
    #[error("{code} move without a feed rate; give F (mm/min) on this or an earlier block")]
    MissingFeed {
        /// Where.
        at: Loc,
        /// The code.
        code: &'static str,
    },
    /// A G5.2 or BSPLINE rule broken (the message says which and what to change).
    #[error("{what}")]
    Spline {
        /// Where.
        at: Loc,
        /// What is wrong and what to change.
        what: String,
    },
    /// The curve is not a valid NURBS otherwise.
    #[error("invalid G06.2 curve: {source}")]
    Nurbs {
        /// The opening block.
        at: Loc,
        /// What is wrong.
        source: NurbsError,
    },
    /// G5 or G5.1 broken (LinuxCNC's rule, in its words where it has them).
    #[error("{code}: {what}")]
    Bezier {
        /// Where.
        at: Loc,
        /// `G5` or `G5.1`.
        code: &'static str,
        /// What is wrong and what to change.
        what: &'static str,
    },
}

impl SplineError {
    /// The block the error is about: the current one, or the one that opened the curve.
    #[must_use]
    pub fn loc(&self) -> Loc {
        match self {
            Self::NurbsOrder { at, .. }
            | Self::NurbsMissingKnot { at }
            | Self::NurbsKnotDecreasing { at, .. }
            | Self::NurbsNotClamped { at, .. }
            | Self::NurbsStartMismatch { at, .. }
            | Self::NurbsIncomplete { at, .. }
            | Self::NurbsAfterEnd { at }
            | Self::NurbsIncremental { at }
            | Self::NurbsWeight { at, .. }
            | Self::MissingFeed { at, .. }
            | Self::Spline { at, .. }
            | Self::Nurbs { at, .. }
            | Self::Bezier { at, .. } => *at,
        }
    }
}

/// A FANUC curve being read.
#[derive(Clone, Debug, PartialEq)]
struct FanucBuild {
    at: Loc,
    order: usize,
    knots: Vec<f64>,
    points: Vec<DVec3>,
    weights: Vec<f64>,
    closing: usize,
    /// The first block omitted K: take the second block's.
    first_knot_missing: bool,
}

/// A LinuxCNC or Sinumerik curve being read (implied knots).
#[derive(Clone, Debug, PartialEq)]
struct UniformBuild {
    kind: SplineKind,
    at: Loc,
    degree: usize,
    points: Vec<DVec3>,
    weights: Vec<f64>,
    /// The `PL` value and the block it was first given on (Sinumerik).
    pl: Option<(Loc, f64)>,
}

#[derive(Clone, Debug, Default, PartialEq)]
enum State {
    /// No spline mode.
    #[default]
    Idle,
    /// A G6.2 curve is open.
    Fanuc(FanucBuild),
    /// A G6.2 curve has ended; the motion mode is still G6.2, so coordinates are refused.
    FanucDone,
    /// A G5.2 or BSPLINE curve is open.
    Uniform(UniformBuild),
}

/// Reads the multi-block splines one block at a time, and keeps the G5 continuity.
///
/// The executor calls [`SplineBuilder::block`] for every block while
/// [`SplineBuilder::is_active`] or when the block holds a spline code (`G6.2`, `G5.2`,
/// `G5.3`, `BSPLINE`), before carrying out the block's own motion, and
/// [`SplineBuilder::end_of_program`] at the end. G5 and G5.1 blocks go to
/// [`SplineBuilder::cubic`] and [`SplineBuilder::quadratic`] (after `block` has seen them as
/// another motion). Blocks whose axis words are not a position — G4, G10, G28/G30, G53, G92 —
/// are not passed, as our reader leaves them out of a curve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplineBuilder {
    state: State,
    /// LinuxCNC's `cycle_i/j` as G5 leaves them: −P, −Q of the last G5 (mm).
    g5_ij: [f64; 2],
}

fn err(at: Loc, what: String) -> SplineError {
    SplineError::Spline { at, what }
}

impl SplineBuilder {
    /// No curve open.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether blocks must go through [`SplineBuilder::block`]: a curve is open, or the
    /// motion mode is a finished G6.2.
    #[must_use]
    pub fn is_active(&self) -> bool {
        self.state != State::Idle
    }

    /// Whether a curve is being read.
    #[must_use]
    pub fn is_open(&self) -> bool {
        matches!(self.state, State::Fanuc(_) | State::Uniform(_))
    }

    /// Reads one block (see [`SplineStep`]).
    ///
    /// # Errors
    /// The first broken rule, as our reader names it.
    pub fn block(&mut self, b: &SplineBlock<'_>) -> Result<SplineStep, SplineError> {
        match b.open {
            Some(SplineKind::LinuxCnc) => return self.linuxcnc(b),
            Some(SplineKind::Sinumerik) => return self.sinumerik(b),
            Some(SplineKind::Fanuc) => {}
            None => {}
        }
        if b.close {
            return self.linuxcnc(b);
        }
        if let State::Uniform(u) = &self.state {
            let linuxcnc = u.kind == SplineKind::LinuxCnc;
            if b.open == Some(SplineKind::Fanuc) {
                // G6.2 inside a G5.2 or BSPLINE curve: as any other motion code there (an
                // error, or the end of the curve), then the start of the FANUC curve.
                let as_motion = SplineBlock { open: None, other_motion: Some("G06.2"), ..*b };
                let step = if linuxcnc { self.linuxcnc(&as_motion)? } else { self.sinumerik(&as_motion)? };
                let position = step.finished.as_ref().map_or(b.position, |f| f.end);
                let next = self.fanuc(&SplineBlock { position, ..*b })?;
                return Ok(SplineStep { taken: next.taken, finished: step.finished });
            }
            return if linuxcnc { self.linuxcnc(b) } else { self.sinumerik(b) };
        }
        self.fanuc(b)
    }

    /// The end of the program: a Sinumerik curve ends there; a G5.2 or G6.2 curve must have
    /// been closed.
    ///
    /// # Errors
    /// An unclosed LinuxCNC curve, an incomplete FANUC one, or a curve too short.
    pub fn end_of_program(&mut self) -> Result<Option<FinishedSpline>, SplineError> {
        match std::mem::take(&mut self.state) {
            State::Fanuc(nb) => finish_fanuc(nb).map(Some),
            State::Uniform(u) if u.kind == SplineKind::LinuxCnc => {
                Err(err(u.at, "the G5.2 curve started here is not closed; end it with G5.3".to_owned()))
            }
            State::Uniform(u) => finish_uniform(u).map(Some),
            State::Idle | State::FanucDone => Ok(None),
        }
    }

    fn fanuc(&mut self, b: &SplineBlock<'_>) -> Result<SplineStep, SplineError> {
        let w = &b.words;
        if b.open == Some(SplineKind::Fanuc) || b.other_motion.is_some() {
            // A new motion code ends the curve being read (an error if it is incomplete).
            let finished = match std::mem::take(&mut self.state) {
                State::Fanuc(nb) => Some(finish_fanuc(nb)?),
                _ => None,
            };
            if b.open == Some(SplineKind::Fanuc) {
                // The new curve starts where the one it ended stops.
                let position = finished.as_ref().map_or(b.position, |f| f.end);
                self.state = State::Fanuc(start_fanuc(&SplineBlock { position, ..*b })?);
                return Ok(SplineStep { taken: true, finished });
            }
            return Ok(SplineStep { taken: false, finished });
        }
        match &mut self.state {
            State::Fanuc(nb) => {
                let done = fanuc_block(nb, b)?;
                if done {
                    let State::Fanuc(nb) = std::mem::replace(&mut self.state, State::FanucDone) else {
                        return Ok(SplineStep::default());
                    };
                    return Ok(SplineStep { taken: true, finished: Some(finish_fanuc(nb)?) });
                }
                Ok(SplineStep { taken: true, finished: None })
            }
            State::FanucDone if w.k.is_some() || w.has_axis() => Err(SplineError::NurbsAfterEnd { at: b.loc }),
            _ => Ok(SplineStep::default()),
        }
    }

    fn linuxcnc(&mut self, b: &SplineBlock<'_>) -> Result<SplineStep, SplineError> {
        let w = &b.words;
        let at = b.loc;
        let open = b.open == Some(SplineKind::LinuxCnc);
        if open && b.close {
            return Err(err(at, "G5.2 and G5.3 in the same block; close the curve on its own block".to_owned()));
        }
        let mut finished = None;
        if open {
            if let Some(m) = b.other_motion {
                return Err(err(at, format!("G5.2 and {m} in the same block; a block has one motion code")));
            }
            let order = w.l.unwrap_or(3.0);
            match &self.state {
                State::Uniform(u) if u.kind == SplineKind::LinuxCnc => {
                    if w.l.is_some() && (order.fract() != 0.0 || order.round() as i64 != u.degree as i64 + 1) {
                        return Err(err(at, format!("L{order} changes the order inside a G5.2 curve; give L once")));
                    }
                }
                _ => {
                    // Another kind of curve ends here.
                    finished = self.end_other()?;
                    if !b.absolute {
                        return Err(err(at, "G5.2 needs absolute coordinates here; add G90 before it".to_owned()));
                    }
                    if b.plane != Plane::Xy {
                        return Err(err(at, "G5.2 is read in the XY plane only; select G17 before it".to_owned()));
                    }
                    if !(order.fract() == 0.0 && (3.0..=(MAX_DEGREE + 1) as f64).contains(&order)) {
                        return Err(err(
                            at,
                            format!(
                                "G5.2 order L{order} is not supported; use L3 (quadratic) or L4 (cubic) — LinuxCNC does not honour orders below 3 in every version"
                            ),
                        ));
                    }
                    if !b.feed_set {
                        return Err(SplineError::MissingFeed { at, code: "G5.2" });
                    }
                    self.state = State::Uniform(UniformBuild {
                        kind: SplineKind::LinuxCnc,
                        at,
                        degree: order as usize - 1,
                        points: vec![finished.as_ref().map_or(b.position, |f: &FinishedSpline| f.end)],
                        weights: vec![1.0],
                        pl: None,
                    });
                }
            }
        }
        if b.close {
            let State::Uniform(u) = std::mem::take(&mut self.state) else {
                return Err(err(at, "G5.3 without an open G5.2 curve".to_owned()));
            };
            if u.kind != SplineKind::LinuxCnc {
                self.state = State::Uniform(u);
                return Err(err(at, "G5.3 without an open G5.2 curve".to_owned()));
            }
            return Ok(SplineStep { taken: true, finished: Some(finish_uniform(u)?) });
        }
        let State::Uniform(u) = &mut self.state else {
            return Ok(SplineStep { taken: false, finished });
        };
        if let Some(m) = b.other_motion {
            return Err(err(
                at,
                format!("{m} inside the G5.2 curve of line {}; close the curve with G5.3 first", u.at.line),
            ));
        }
        if w.z.is_some() {
            return Err(err(
                at,
                "Z inside a G5.2 curve: LinuxCNC NURBS are planar in XY; move Z before G5.2, or use G1/G2/G3"
                    .to_owned(),
            ));
        }
        let weight = w.p.unwrap_or(1.0);
        if !(weight > 0.0 && weight.is_finite()) {
            return Err(SplineError::NurbsWeight { at, value: weight });
        }
        if w.x.is_some() || w.y.is_some() {
            add_point(u, w, weight);
        } else if open && w.p.is_some() {
            // `G5.2 P…` without X/Y: the weight of the first control point.
            u.weights[0] = weight;
        }
        Ok(SplineStep { taken: true, finished })
    }

    fn sinumerik(&mut self, b: &SplineBlock<'_>) -> Result<SplineStep, SplineError> {
        let w = &b.words;
        let at = b.loc;
        let mut finished = None;
        if b.open == Some(SplineKind::Sinumerik) {
            if let Some(m) = b.other_motion {
                return Err(err(at, format!("BSPLINE and {m} in the same block; a block has one motion command")));
            }
            finished = self.end_other()?;
            if !b.absolute {
                return Err(err(at, "BSPLINE needs absolute coordinates here; add G90 before it".to_owned()));
            }
            let sd = w.sd.unwrap_or(3.0);
            if !(sd.fract() == 0.0 && (2.0..=3.0).contains(&sd)) {
                return Err(err(at, format!("SD={sd} is not a BSPLINE degree; write SD=2 or SD=3")));
            }
            if !b.feed_set {
                return Err(SplineError::MissingFeed { at, code: "BSPLINE" });
            }
            self.state = State::Uniform(UniformBuild {
                kind: SplineKind::Sinumerik,
                at,
                degree: sd as usize,
                points: vec![finished.as_ref().map_or(b.position, |f: &FinishedSpline| f.end)],
                weights: vec![1.0],
                pl: None,
            });
        } else if b.other_motion.is_some() {
            // A new motion command ends the curve; the executor takes the block.
            return Ok(SplineStep { taken: false, finished: self.end_other()? });
        }
        let State::Uniform(u) = &mut self.state else {
            return Ok(SplineStep { taken: false, finished });
        };
        if let Some(sd) = w.sd
            && (sd.fract() != 0.0 || sd.round() as i64 != u.degree as i64)
        {
            return Err(err(
                at,
                format!("SD={sd} inside a BSPLINE curve of degree {}; give SD on its first block", u.degree),
            ));
        }
        if let Some(pl) = w.pl {
            if !(pl > 0.0) {
                return Err(err(at, format!("PL={pl} must be a positive knot interval (mm)")));
            }
            match u.pl {
                None => u.pl = Some((at, pl)),
                Some((l0, p0)) if (pl - p0).abs() > tolerance::KNOT_EQUAL_REL * p0.max(1.0) => {
                    return Err(err(
                        at,
                        format!(
                            "PL={pl} differs from PL={p0} of line {}; interpolab reads BSPLINE curves with one PL (equal knot intervals) only — write the same PL on every block",
                            l0.line
                        ),
                    ));
                }
                Some(_) => {}
            }
        }
        if w.has_axis() {
            let weight = w.pw.unwrap_or(1.0);
            if !(weight > 0.0 && weight <= SINUMERIK_MAX_PW) {
                return Err(err(at, format!("PW={weight} is outside the point-weight range; give 0 < PW ≤ 3")));
            }
            add_point(u, w, weight);
        } else if w.pw.is_some() {
            return Err(err(at, "PW without a control point; write it in the block of its X, Y, Z".to_owned()));
        }
        Ok(SplineStep { taken: true, finished })
    }

    /// Ends whatever curve is open because another kind starts.
    fn end_other(&mut self) -> Result<Option<FinishedSpline>, SplineError> {
        match std::mem::take(&mut self.state) {
            State::Fanuc(nb) => finish_fanuc(nb).map(Some),
            State::Uniform(u) if u.kind == SplineKind::LinuxCnc => {
                let at = u.at;
                self.state = State::Uniform(u);
                Err(err(at, "the G5.2 curve started here is not closed; end it with G5.3".to_owned()))
            }
            State::Uniform(u) => finish_uniform(u).map(Some),
            State::Idle | State::FanucDone => Ok(None),
        }
    }

    /// G5: the cubic Bézier from `b.position` to `end` (X, Y from the block, resolved to
    /// absolute mm by the executor; Z is the start's). `i`, `j`, `p`, `q` are the block's
    /// I J P Q (mm).
    ///
    /// # Errors
    /// LinuxCNC's refusals: plane not G17, Z (or A B C — `other_axis`) in the block, only one
    /// of I J, P or Q missing, cutter compensation on, no feed.
    pub fn cubic(&mut self, b: &BezierBlock) -> Result<NurbsCurve, SplineError> {
        let code = "G5";
        bezier_checks(b, code)?;
        let ij = match (b.i, b.j) {
            (Some(i), Some(j)) => [i, j],
            (None, None) => self.g5_ij,
            _ => {
                return Err(bezier(
                    b.loc,
                    code,
                    "give both I and J, or neither (then the curve continues the previous G5's end tangent)",
                ));
            }
        };
        let (Some(p), Some(q)) = (b.p, b.q) else {
            return Err(bezier(b.loc, code, "give both P and Q, the end's control offset from the end point"));
        };
        let s = b.position;
        let e = DVec3::new(b.end_xy[0], b.end_xy[1], s.z);
        let points = [s, s + DVec3::new(ij[0], ij[1], 0.0), e + DVec3::new(p, q, 0.0), e];
        let curve = NurbsCurve::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &points, None)
            .map_err(|source| SplineError::Nurbs { at: b.loc, source })?;
        self.g5_ij = [-p, -q];
        Ok(curve)
    }

    /// G5.1: the quadratic Bézier from `b.position` to `end` with the control point at the
    /// start plus (I, J).
    ///
    /// # Errors
    /// As [`SplineBuilder::cubic`]; rs274 2.9 wants both I and J.
    pub fn quadratic(&mut self, b: &BezierBlock) -> Result<NurbsCurve, SplineError> {
        let code = "G5.1";
        bezier_checks(b, code)?;
        let (Some(i), Some(j)) = (b.i, b.j) else {
            return Err(bezier(
                b.loc,
                code,
                "give both I and J, the control point's offset from the start (LinuxCNC 2.9 needs both)",
            ));
        };
        let s = b.position;
        let e = DVec3::new(b.end_xy[0], b.end_xy[1], s.z);
        let points = [s, s + DVec3::new(i, j, 0.0), e];
        NurbsCurve::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &points, None)
            .map_err(|source| SplineError::Nurbs { at: b.loc, source })
    }
}

/// A G5 or G5.1 block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierBlock {
    /// Where.
    pub loc: Loc,
    /// The current position (program frame, mm).
    pub position: DVec3,
    /// The end's X and Y (program frame, mm, absolute).
    pub end_xy: [f64; 2],
    /// I (mm).
    pub i: Option<f64>,
    /// J (mm).
    pub j: Option<f64>,
    /// P (mm), G5.
    pub p: Option<f64>,
    /// Q (mm), G5.
    pub q: Option<f64>,
    /// The selected plane.
    pub plane: Plane,
    /// A word of an axis other than X and Y on the block (`Z`, `A`, `B`, `C`).
    pub other_axis: Option<char>,
    /// Cutter radius compensation is on.
    pub cutter_comp: bool,
    /// A usable feed: F non-zero in G94/G95, or F on this block in G93.
    pub feed_ok: bool,
}

fn bezier(at: Loc, code: &'static str, what: &'static str) -> SplineError {
    SplineError::Bezier { at, code, what }
}

fn bezier_checks(b: &BezierBlock, code: &'static str) -> Result<(), SplineError> {
    if b.cutter_comp {
        return Err(bezier(
            b.loc,
            code,
            "splines cannot run with cutter radius compensation on; cancel it with G40 first",
        ));
    }
    if !b.feed_ok {
        return Err(bezier(b.loc, code, "no feed rate: program F (or F on the block in G93) before the spline"));
    }
    if b.plane != Plane::Xy {
        return Err(bezier(b.loc, code, "splines must be in the XY plane (LinuxCNC); select G17 before them"));
    }
    if b.other_axis.is_some() {
        return Err(bezier(
            b.loc,
            code,
            "splines move X and Y only (LinuxCNC: may not have motion in Z, A, B, or C); move the other axes on a block of their own",
        ));
    }
    Ok(())
}

fn add_point(u: &mut UniformBuild, w: &SplineWords, weight: f64) {
    let mut p = u.points[u.points.len() - 1];
    for (i, v) in [w.x, w.y, w.z].into_iter().enumerate() {
        if let Some(v) = v {
            p[i] = v;
        }
    }
    u.points.push(p);
    u.weights.push(weight);
}

fn start_fanuc(b: &SplineBlock<'_>) -> Result<FanucBuild, SplineError> {
    let at = b.loc;
    let w = &b.words;
    if !b.absolute {
        return Err(SplineError::NurbsIncremental { at });
    }
    let order = w.p.unwrap_or(4.0);
    if !(order.fract() == 0.0 && (2.0..=(MAX_DEGREE + 1) as f64).contains(&order)) {
        return Err(SplineError::NurbsOrder { at, order });
    }
    let mut first = b.position;
    for (i, v) in [w.x, w.y, w.z].into_iter().enumerate() {
        if let Some(v) = v {
            first[i] = v;
        }
    }
    let tol = tolerance::NURBS_START_MATCH_MM * if b.inch { 25.4 } else { 1.0 };
    if (first - b.position).abs().max_element() > tol {
        return Err(SplineError::NurbsStartMismatch { at, first: first.to_array(), position: b.position.to_array() });
    }
    let weight = w.r.unwrap_or(1.0);
    if !(weight > 0.0 && weight.is_finite()) {
        return Err(SplineError::NurbsWeight { at, value: weight });
    }
    if !b.feed_set {
        return Err(SplineError::MissingFeed { at, code: "G06.2" });
    }
    Ok(FanucBuild {
        at,
        order: order as usize,
        knots: vec![w.k.unwrap_or(0.0)],
        points: vec![first],
        weights: vec![weight],
        closing: 0,
        first_knot_missing: w.k.is_none(),
    })
}

/// One block inside a G6.2 curve; true when its last closing knot arrived.
fn fanuc_block(nb: &mut FanucBuild, b: &SplineBlock<'_>) -> Result<bool, SplineError> {
    let at = b.loc;
    let w = &b.words;
    let Some(k) = w.k else {
        if w.has_axis() || w.r.is_some() {
            return Err(SplineError::NurbsMissingKnot { at });
        }
        return Ok(false);
    };
    if nb.first_knot_missing {
        nb.knots[0] = k;
        nb.first_knot_missing = false;
    }
    let previous = nb.knots[nb.knots.len() - 1];
    if k < previous {
        return Err(SplineError::NurbsKnotDecreasing { at, value: k, previous });
    }
    if w.has_axis() || w.r.is_some() {
        if nb.closing > 0 {
            return Err(SplineError::NurbsAfterEnd { at });
        }
        let mut p = nb.points[nb.points.len() - 1];
        for (i, v) in [w.x, w.y, w.z].into_iter().enumerate() {
            if let Some(v) = v {
                p[i] = v;
            }
        }
        let weight = w.r.unwrap_or(1.0);
        if !(weight > 0.0 && weight.is_finite()) {
            return Err(SplineError::NurbsWeight { at, value: weight });
        }
        nb.points.push(p);
        nb.weights.push(weight);
        nb.knots.push(k);
        Ok(false)
    } else {
        nb.knots.push(k);
        nb.closing += 1;
        Ok(nb.closing == nb.order)
    }
}

fn finish_fanuc(nb: FanucBuild) -> Result<FinishedSpline, SplineError> {
    let at = nb.at;
    let o = nb.order;
    if nb.closing != o {
        return Err(SplineError::NurbsIncomplete { at, closing: nb.closing, order: o });
    }
    let k = &nb.knots;
    let eq = |a: f64, b: f64| (a - b).abs() <= tolerance::KNOT_EQUAL_REL * (k[k.len() - 1] - k[0]).abs().max(1.0);
    if k[..o].iter().any(|&x| !eq(x, k[0])) {
        return Err(SplineError::NurbsNotClamped { at, end: "first", order: o });
    }
    if k[k.len() - o..].iter().any(|&x| !eq(x, k[k.len() - 1])) {
        return Err(SplineError::NurbsNotClamped { at, end: "last", order: o });
    }
    let curve = NurbsCurve::try_new(o - 1, nb.knots, &nb.points, Some(&nb.weights))
        .map_err(|source| SplineError::Nurbs { at, source })?;
    let end = curve.point_at(curve.range().1);
    Ok(FinishedSpline { loc: at, curve, end, note: None })
}

fn finish_uniform(u: UniformBuild) -> Result<FinishedSpline, SplineError> {
    let at = u.at;
    let n = u.points.len();
    let p = u.degree;
    let name = if u.kind == SplineKind::Sinumerik { "BSPLINE" } else { "G5.2" };
    if n < p + 1 {
        return Err(err(
            at,
            format!(
                "the {name} curve started here has {n} control points with its start point; degree {p} needs at least {}",
                p + 1
            ),
        ));
    }
    let note = (u.kind == SplineKind::Sinumerik && u.pl.is_none()).then_some(SplineNote::SpacingChosenByControl);
    let h = u.pl.map_or(1.0, |(_, v)| v);
    let spans = n - p;
    let mut knots = vec![0.0; p + 1];
    knots.extend((1..spans).map(|j| j as f64 * h));
    knots.extend(std::iter::repeat_n(spans as f64 * h, p + 1));
    let curve = NurbsCurve::try_new(p, knots, &u.points, Some(&u.weights))
        .map_err(|source| SplineError::Nurbs { at, source })?;
    Ok(FinishedSpline { loc: at, curve, end: u.points[n - 1], note })
}
