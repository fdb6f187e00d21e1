//! Executing a block: its words in RS274/NGC's order of execution (LinuxCNC's
//! `execute_block`): comment and message, feed mode, feed rate, spindle speed, tool select, M
//! codes (tool change, spindle, stops last), dwell, plane, units, cutter compensation, tool
//! length offset, coordinate system, path mode, distance modes, retract mode, then the
//! non-modal setting codes (G10, G28, G30, G52, G92 …) and finally the motion.

use glam::DVec3;

use super::canon::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use super::comp::{CompError, CutterComp, Emit, MoveKind, ProgMove, Refusal, Side};
use super::cycles::{self, CycleInput, CycleKind, CycleMove, CycleState, CycleWords, Retract, SpindleDir};
use super::read::Block;
use super::splines::{BezierBlock, FinishedSpline, SplineBlock, SplineBuilder, SplineKind, SplineWords};
use super::state::{Axes, CompSide, MotionMode, State, g_group};
use super::{INTEGER_SLACK, Interpreter, Problem, Warning};
use crate::gcode::path::Plane;

/// LinuxCNC's arc tolerances (`interp_internal.hh`), in mm: the start and end radius of a
/// centre-format arc may differ by `CENTER_ARC_RADIUS_TOLERANCE` (2·0.01·√2 mm, 2·0.001·√2
/// inch) — or by 0.1 % of the radius up to 100 times that — and a radius below
/// `RADIUS_TOLERANCE` (0.00005 inch) is zero.
const CENTER_ARC_TOL_MM: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2;
const CENTER_ARC_TOL_INCH: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2;
const RADIUS_TOL_INCH: f64 = 0.000_05;
const SPIRAL_REL_TOL: f64 = 0.001;

/// Most full turns of one arc (`P`): LinuxCNC has no cap; a few thousand turns is a spring.
const MAX_ARC_TURNS: f64 = 10_000.0;
/// An R arc whose half chord is within this fraction of its radius is the half circle: the
/// half chord is set to the radius so the centre's offset, √(r² − (c/2)²), is not the root of
/// a rounding error.
const HALF_CIRCLE_REL: f64 = 1e-12;

/// State of execution kept between blocks that the modal [`State`] does not hold.
#[derive(Debug, Default)]
pub(super) struct Exec {
    /// Cutting moves' machine bounding box and the largest per-minute feed (mm/min), for the
    /// inch-looking check.
    lo: Option<DVec3>,
    hi: DVec3,
    max_feed: f64,
    first_cut: Option<Loc>,
    /// Canned cycles' sticky words and initial level.
    cycles: CycleState,
    /// The multi-block spline being read.
    splines: SplineBuilder,
    /// Cutter radius compensation, from the first G41/G42 on (every move then goes through
    /// it, on or off, as LinuxCNC's rules need).
    comp: Option<CutterComp<Feed, Canon>>,
    comp_out: Vec<Emit<Feed, Canon>>,
    /// An error met while passing a call through the compensation's queue.
    deferred: Option<Problem>,
    /// The largest `G64 P` path tolerance programmed (mm).
    pub blend_mm: Option<f64>,
    /// Comments kept (line, text), at most [`super::Options::keep_comments`].
    pub comments: Vec<(Loc, String)>,
}

fn codes(g: &[i32]) -> String {
    g.iter().map(|t| gname(*t)).collect::<Vec<_>>().join(" ")
}

/// `G38.2` from 382, `G1` from 10.
pub(super) fn gname(t: i32) -> String {
    if t % 10 == 0 { format!("G{}", t / 10) } else { format!("G{}.{}", t / 10, t % 10) }
}

/// A spline error at the line it is about (the block that opened the curve, or this one).
fn spline_err(e: super::splines::SplineError) -> Problem {
    Problem::Located { loc: e.loc(), text: e.to_string() }
}

/// A compensation error at the line it names.
fn comp_err(e: CompError) -> Problem {
    let text = e.to_string();
    // Its message starts "line N: " or "line N of subroutine file F: ".
    let parsed = text.strip_prefix("line ").and_then(|rest| {
        let (head, tail) = rest.split_once(": ")?;
        let mut words = head.split(' ');
        let line: u32 = words.next()?.parse().ok()?;
        let file: u16 = if head.contains("file") { words.next_back()?.parse().ok()? } else { 0 };
        Some((Loc { file, line }, tail.to_owned()))
    });
    match parsed {
        Some((loc, text)) => Problem::Located { loc, text },
        None => Problem::Rule(text),
    }
}

impl Interpreter<'_> {
    /// Queues a call; one that does not move waits behind a move the compensation holds.
    fn emit(&mut self, c: Canon) {
        if c.end().is_none()
            && let Some(comp) = self.exec.comp.as_mut()
            && comp.held() > 0
        {
            let loc = c.loc();
            let mut out = std::mem::take(&mut self.exec.comp_out);
            if let Err(e) = comp.pass(c, loc, &mut out) {
                self.exec.deferred.get_or_insert(comp_err(e));
            }
            self.drain(&mut out);
            self.exec.comp_out = out;
            return;
        }
        self.emit_now(c);
    }

    /// Turns what the compensation released into canonical calls.
    fn drain(&mut self, out: &mut Vec<Emit<Feed, Canon>>) {
        let plane = self.exec.comp.as_ref().map_or(self.st.plane, CutterComp::plane);
        for e in out.drain(..) {
            match e {
                Emit::Pass(c) => self.emit_now(c),
                Emit::Move { mv, origin } => {
                    let mut q = self.st.prog;
                    q[..3].copy_from_slice(&mv.end.to_array());
                    q[3..].copy_from_slice(&mv.abc.to_array());
                    let end = self.st.to_machine(&q);
                    let loc = mv.loc;
                    let c = match mv.kind {
                        MoveKind::Traverse => Canon::Traverse { loc, end, origin },
                        MoveKind::Feed => Canon::Line { loc, end, feed: mv.tag, origin },
                        MoveKind::Arc { center, turns } => {
                            let mut cq = q;
                            cq[..3].copy_from_slice(&center.to_array());
                            let center = self.st.to_machine(&cq).xyz;
                            Canon::Arc { loc, end, center, plane, turns, feed: mv.tag, origin }
                        }
                    };
                    self.emit_now(c);
                }
            }
        }
    }

    /// A programmed G0/G1/G2/G3 move in the program frame: through the compensation once it
    /// has been used, else straight to the machine frame.
    fn prog_move(&mut self, loc: Loc, kind: MoveKind, end: Axes, feed: Feed) -> Result<(), Problem> {
        if let Some(comp) = self.exec.comp.as_mut() {
            let mv = ProgMove {
                kind,
                end: DVec3::new(end[0], end[1], end[2]),
                abc: DVec3::new(end[3], end[4], end[5]),
                loc,
                tag: feed,
            };
            let mut out = std::mem::take(&mut self.exec.comp_out);
            let r = comp.push(mv, &mut out).map_err(comp_err);
            self.drain(&mut out);
            self.exec.comp_out = out;
            r?;
            self.st.prog = end;
            return Ok(());
        }
        let m = self.st.to_machine(&end);
        let c = match kind {
            MoveKind::Traverse => Canon::Traverse { loc, end: m, origin: Origin::Programmed },
            MoveKind::Feed => Canon::Line { loc, end: m, feed, origin: Origin::Programmed },
            MoveKind::Arc { center, turns } => {
                let mut cq = end;
                cq[..3].copy_from_slice(&center.to_array());
                let center = self.st.to_machine(&cq).xyz;
                Canon::Arc { loc, end: m, center, plane: self.st.plane, turns, feed, origin: Origin::Programmed }
            }
        };
        self.emit_now(c);
        self.st.prog = end;
        Ok(())
    }

    /// Refuses what LinuxCNC refuses while compensation is on.
    fn refuse_if_comp(&self, what: Refusal, loc: Loc) -> Result<(), Problem> {
        match &self.exec.comp {
            Some(c) => c.refuse_if_on(what, loc).map_err(comp_err),
            None => Ok(()),
        }
    }

    /// Releases what compensation holds: at M0/M1/M60 (`end` false) or the program's end.
    pub(super) fn comp_release(&mut self, loc: Loc, end: bool) -> Result<(), Problem> {
        let Some(comp) = self.exec.comp.as_mut() else {
            return Ok(());
        };
        let mut out = std::mem::take(&mut self.exec.comp_out);
        let r = if end { comp.end_program(loc, &mut out) } else { comp.flush(loc, &mut out) };
        self.drain(&mut out);
        self.exec.comp_out = out;
        r.map_err(comp_err)
    }

    /// The program's end as a call.
    pub(super) fn emit_stop(&mut self, loc: Loc) {
        self.emit(Canon::Stop { loc, end: true });
    }

    fn emit_now(&mut self, c: Canon) {
        if let Canon::Line { end, feed, origin, .. } | Canon::Arc { end, feed, origin, .. } = &c
            && *origin != Origin::Probe
        {
            let e = &mut self.exec;
            let p = end.xyz;
            e.lo = Some(e.lo.map_or(p, |l| l.min(p)));
            e.hi = if e.first_cut.is_none() { p } else { e.hi.max(p) };
            if feed.mode == FeedMode::PerMinute {
                e.max_feed = e.max_feed.max(feed.rate);
            }
            if e.first_cut.is_none() {
                e.first_cut = Some(c.loc());
            }
        }
        self.queue.push_back(c);
    }

    fn length(&self, v: f64) -> f64 {
        v * self.st.scale()
    }
}

/// Executes one block.
pub(super) fn block(it: &mut Interpreter<'_>, loc: Loc, b: &mut Block) -> Result<(), Problem> {
    if !it.opts.general_only
        && b.letters != 0
        && b.letters & !PLAIN_AXES == 0
        && b.g.is_empty()
        && b.m.is_empty()
        && !b.has_comment
        && b.polar_r.is_none()
        && b.polar_a.is_none()
    {
        return plain_block(it, loc, b);
    }
    // One code per modal group (LinuxCNC: "two G codes used from same modal group").
    let mut seen: [Option<i32>; 24] = [None; 24];
    for &t in &b.g {
        match g_group(t) {
            // G80 beside another motion code gives way to it (LinuxCNC's `read_g`).
            Some(1) if t == 800 && seen[1].is_some() => {}
            Some(1) if seen[1] == Some(800) => seen[1] = Some(t),
            Some(grp) if grp != 0 => {
                if let Some(prev) = seen[grp as usize] {
                    return Err(Problem::Rule(format!(
                        "{} and {} in the same block: they are in one modal group; keep one",
                        gname(prev),
                        gname(t)
                    )));
                }
                seen[grp as usize] = Some(t);
            }
            Some(_) => {}
            None => {
                if it.opts.strict {
                    return Err(Problem::Rule(format!("{} is not a G code this interpreter knows", gname(t))));
                }
                it.report(&gname(t), loc, "a G code not modelled: its effect is left out");
            }
        }
    }
    let has = |t: i32| b.g.contains(&t);
    let motion_code = seen[1];

    // Axes this interpreter does not carry.
    const UVW: u32 = (1 << (b'u' - b'a')) | (1 << (b'v' - b'a')) | (1 << (b'w' - b'a'));
    for c in [b'u', b'v', b'w'].into_iter().filter(|_| b.letters & UVW != 0) {
        if let Some(v) = b.get(c)
            && v != 0.0
        {
            let name = (c.to_ascii_uppercase() as char).to_string();
            it.report(&name, loc, "the U, V and W axes are not modelled: their words are left out");
        }
    }
    if b.get(b'e').is_some() {
        it.report("E", loc, "E (an extruder or thread word) is not modelled: left out");
    }
    // 1. Comment: messages are reported so a viewer can show them.
    if b.has_comment && it.exec.comments.len() < it.opts.keep_comments {
        it.exec.comments.push((loc, b.comment.clone()));
    }
    if b.has_comment {
        let c = b.comment.trim_start();
        if c.len() >= 3 && c[..3].eq_ignore_ascii_case("msg") {
            it.report("MSG", loc, "an operator message (MSG comment)");
        }
    }
    // 2. Feed mode.
    if let Some(t) = seen[5] {
        it.st.feed.mode = match t {
            930 => FeedMode::InverseTime,
            950 => FeedMode::PerRevolution,
            _ => FeedMode::PerMinute,
        };
        if t == 950 {
            it.report("G95", loc, "feed per revolution: times follow from the spindle speed");
        }
    }
    // 3. Feed rate.
    if let Some(f) = b.get(b'f') {
        if f < 0.0 {
            return Err(Problem::Rule(format!("negative feed F{}; a feed is a speed ≥ 0", super::error::show(f))));
        }
        it.st.feed.rate = match it.st.feed.mode {
            FeedMode::InverseTime => f,
            _ => f * it.st.scale(),
        };
    } else if it.st.feed.mode == FeedMode::InverseTime
        && matches!(motion_code.or(motion_of(it.st.motion)), Some(10 | 20 | 30))
        && has_axes(b)
    {
        return Err(Problem::Rule("a feed move in inverse-time mode (G93) needs F on its own block".into()));
    }
    // 4. Spindle speed.
    if let Some(sv) = b.get(b's') {
        if sv < 0.0 {
            return Err(Problem::Rule("negative spindle speed S; give S ≥ 0 (direction is M3/M4)".into()));
        }
        it.st.speed_rpm = sv;
        spindle(it, loc);
    }
    // 5. Tool select.
    if let Some(t) = b.get(b't') {
        if t < 0.0 || t.fract() != 0.0 {
            return Err(Problem::Rule(format!("T{} is not a tool number (a whole number ≥ 0)", super::error::show(t))));
        }
        it.st.selected_tool = t as i32;
    }
    // 6. M codes (stops last).
    let mut stop: Option<i32> = None;
    for &m in &b.m {
        match m {
            6 => {
                it.refuse_if_comp(Refusal::ToolChange, loc)?;
                // The spindle stops for the change (LinuxCNC's M6); M3/M4 start it again.
                if it.st.spindle_dir != 0 {
                    it.st.spindle_dir = 0;
                    spindle(it, loc);
                }
                it.st.tool = it.st.selected_tool;
                let tool = it.st.tool;
                it.emit(Canon::ToolChange { loc, tool });
            }
            61 => {
                let q = b
                    .get(b'q')
                    .ok_or_else(|| Problem::Rule("M61 needs Q, the tool number now in the spindle".into()))?;
                it.st.tool = q.round() as i32;
                it.st.selected_tool = it.st.tool;
                let tool = it.st.tool;
                it.emit(Canon::ToolChange { loc, tool });
            }
            3..=5 => {
                it.st.spindle_dir = match m {
                    3 => 1,
                    4 => -1,
                    _ => 0,
                };
                spindle(it, loc);
            }
            0 | 1 | 2 | 30 | 60 => stop = Some(m),
            // Coolant, overrides, I/O, feed/speed override switches, spindle orient, clamps:
            // no effect on the path.
            7..=9 | 48..=53 | 62..=68 | 19 | 10 | 11 | 29 => {}
            70..=73 => it.report(&format!("M{m}"), loc, "saving and restoring modal state (M70–M73) is not modelled"),
            _ => {
                if it.opts.strict {
                    return Err(Problem::Rule(format!("M{m} is not modelled")));
                }
                let what = if (100..=199).contains(&m) {
                    "a user-defined M code (a machine's own program): not modelled, skipped"
                } else {
                    "an M code not modelled: skipped"
                };
                it.report(&format!("M{m}"), loc, what);
            }
        }
    }
    // 7. Dwell.
    if has(40) {
        let p = b
            .get(b'p')
            .or_else(|| b.get(b'x'))
            .ok_or_else(|| Problem::Rule("G4 needs P, the dwell in seconds".into()))?;
        if p < 0.0 {
            return Err(Problem::Rule("G4 with a negative time; P is seconds ≥ 0".into()));
        }
        it.emit(Canon::Dwell { loc, seconds: p });
    }
    // 8. Plane.
    if let Some(t) = seen[2] {
        it.st.plane = match t {
            180 | 181 => Plane::Zx,
            190 | 191 => Plane::Yz,
            _ => Plane::Xy,
        };
        if let Some(c) = it.exec.comp.as_mut() {
            c.set_plane(it.st.plane, loc).map_err(comp_err)?;
        }
    }
    // 9. Units.
    if let Some(t) = seen[6] {
        it.st.inch = t == 200;
        it.st.units_given = true;
        if let Some(c) = it.exec.comp.as_mut() {
            c.set_inch(it.st.inch);
        }
    }
    // 10. Cutter compensation.
    if let Some(t) = seen[7] {
        compensation(it, loc, b, t)?;
    }
    // 11. Tool length offset.
    if let Some(t) = seen[8] {
        it.refuse_if_comp(Refusal::ToolLengthOffset, loc)?;
        tool_length(it, loc, b, t)?;
    }
    // 12. Coordinate system.
    if let Some(t) = seen[12] {
        let sys = match t {
            540 => 1,
            550 => 2,
            560 => 3,
            570 => 4,
            580 => 5,
            590 => 6,
            591 => 7,
            592 => 8,
            593 => 9,
            _ => {
                it.report("G54.1", loc, "FANUC's additional work offsets are not modelled: G54 used");
                1
            }
        };
        if it.st.comp != CompSide::Off {
            return Err(Problem::Rule(
                "cannot change the coordinate system with cutter compensation on; give G40 first".into(),
            ));
        }
        it.st.keep_tool(|s| s.system = sys);
        it.params.set(5220, sys as f64);
    }
    // 13. Path control (G61, G64): the feed planner's business, not the path's; the largest
    // G64 P is kept (the control may leave the path by that much at junctions).
    if seen[13].is_some() {
        it.refuse_if_comp(Refusal::PathControlMode, loc)?;
    }
    if seen[13] == Some(640)
        && let Some(p) = b.get(b'p')
    {
        let p = it.length(p);
        it.exec.blend_mm = Some(it.exec.blend_mm.map_or(p, |b: f64| b.max(p)));
    }
    // 14. Distance modes and retract mode.
    if let Some(t) = seen[3] {
        it.st.absolute = t == 900;
    }
    if let Some(t) = seen[4] {
        it.st.arc_absolute = t == 901;
    }
    if let Some(t) = seen[10] {
        it.refuse_if_comp(Refusal::RetractMode, loc)?;
        it.st.retract_initial = t == 980;
    }
    // FANUC groups: rotation, polar input, scaling, mirror.
    if let Some(t) = seen[16] {
        if t == 680 {
            if it.st.plane != Plane::Xy {
                it.report("G68", loc, "G68 rotation outside G17 is not modelled");
            } else {
                let sc = it.st.scale();
                let c = [b.get(b'x').map_or(0.0, |v| v * sc), b.get(b'y').map_or(0.0, |v| v * sc)];
                let r = b.get(b'r').unwrap_or(0.0);
                it.st.keep_tool(|s| s.g68 = Some((c, r)));
            }
        } else {
            it.st.keep_tool(|s| s.g68 = None);
        }
    }
    if let Some(t) = seen[17] {
        it.st.polar = t == 160;
    }
    for grp in [18usize, 19] {
        if let Some(t) = seen[grp]
            && (t == 510 || t == 511)
        {
            it.report(&gname(t), loc, "scaling and mirror images are not modelled");
        }
    }
    if let Some(t) = seen[21]
        && t == 660
    {
        it.report("G66", loc, "modal macro calls are not modelled");
    }
    // 15. Non-modal codes.
    let mut axes_used = false;
    for t in b.g.iter().filter(|t| g_group(**t) == Some(0)) {
        match *t {
            40 | 90 => {}
            100 => {
                let p = b.get(b'p').unwrap_or(0.0).round();
                if p == 0.0 || p as usize == it.st.system {
                    it.refuse_if_comp(Refusal::CoordinateSystem, loc)?;
                }
                setup(it, b)?;
                axes_used = true;
            }
            280 | 300 => {
                it.refuse_if_comp(Refusal::ReferenceReturn, loc)?;
                home(it, loc, b, *t)?;
                axes_used = true;
            }
            281 | 301 => {
                it.refuse_if_comp(Refusal::SetReference, loc)?;
                let m = it.st.pose();
                let tlo = it.st.tlo;
                let base = if *t == 281 { 5161 } else { 5181 };
                let vals = [m.xyz.x + tlo.x, m.xyz.y + tlo.y, m.xyz.z + tlo.z, m.abc.x, m.abc.y, m.abc.z];
                for (i, v) in vals.into_iter().enumerate() {
                    it.params.set(base + i, v);
                }
            }
            520 | 920 | 921 | 922 | 923 => {
                it.refuse_if_comp(Refusal::AxisOffsets, loc)?;
                axis_offsets(it, b, *t);
                axes_used = *t == 520 || *t == 920;
            }
            530 => {}
            650 => {}
            _ => {}
        }
    }
    // Axis words that belong to G43.1 or G68 are not a move.
    if seen[8] == Some(431) || seen[16] == Some(680) {
        axes_used = true;
    }
    // 16. Motion. FANUC's G5 P… and G5.1 Q… (high-speed modes) hold no axis word: they are
    // not LinuxCNC's splines and leave the motion mode alone.
    let motion_code = motion_code.filter(|t| !matches!(t, 50 | 51) || has_axes(b));
    if spline_block(it, loc, b, motion_code)? {
        if let Some(t) = motion_code
            && !matches!(t, 62 | 52 | 53)
        {
            set_motion(it, t);
        }
    } else {
        if let Some(t) = motion_code {
            set_motion(it, t);
        }
        if !axes_used {
            motion(it, loc, b, has(530), motion_code)?;
        }
    }
    // 17. Stop.
    if let Some(m) = stop {
        let end = matches!(m, 2 | 30);
        it.comp_release(loc, end)?;
        if end {
            program_end(it, loc);
        }
        it.emit(Canon::Stop { loc, end });
        if end {
            it.finish(loc)?;
            it.done = true;
        }
    }
    let _ = codes;
    match it.exec.deferred.take() {
        Some(p) => Err(p),
        None => Ok(()),
    }
}

/// The axis letters X Y Z A B C (bits as `Block::letters`).
const PLAIN_AXES: u32 = (1 << (b'x' - b'a'))
    | (1 << (b'y' - b'a'))
    | (1 << (b'z' - b'a'))
    | 1
    | (1 << (b'b' - b'a'))
    | (1 << (b'c' - b'a'));

/// [`block`] for a block of axis words only (no G or M code, no other letter, no comment, no
/// polar word): of the steps before the motion only the inverse-time check can act on it —
/// every other step reads a code, a letter or a comment it does not have — so it goes
/// straight to the motion in the modes in force, as [`block`] would.
fn plain_block(it: &mut Interpreter<'_>, loc: Loc, b: &Block) -> Result<(), Problem> {
    if it.st.feed.mode == FeedMode::InverseTime && matches!(motion_of(it.st.motion), Some(10 | 20 | 30)) {
        return Err(Problem::Rule("a feed move in inverse-time mode (G93) needs F on its own block".into()));
    }
    if !spline_block(it, loc, b, None)? {
        motion(it, loc, b, false, None)?;
    }
    match it.exec.deferred.take() {
        Some(p) => Err(p),
        None => Ok(()),
    }
}

fn motion_of(m: MotionMode) -> Option<i32> {
    Some(match m {
        MotionMode::Rapid => 0,
        MotionMode::Linear => 10,
        MotionMode::ArcCw => 20,
        MotionMode::ArcCcw => 30,
        _ => return None,
    })
}

fn has_axes(b: &Block) -> bool {
    const AXES: u32 = (1 << 23) | (1 << 24) | (1 << 25) | 1 | (1 << 1) | (1 << 2);
    b.letters & AXES != 0 || b.polar_r.is_some() || b.polar_a.is_some()
}

fn set_motion(it: &mut Interpreter<'_>, t: i32) {
    let m = match t {
        0 => MotionMode::Rapid,
        10 => MotionMode::Linear,
        20 => MotionMode::ArcCw,
        30 => MotionMode::ArcCcw,
        50 => MotionMode::Cubic,
        51 => MotionMode::Quadratic,
        52 => MotionMode::LinuxNurbs,
        62 => MotionMode::FanucNurbs,
        800 => MotionMode::None,
        382..=385 => MotionMode::Probe(t),
        330 | 331 | 760 | 700..=722 => MotionMode::Synchronised(t),
        _ => MotionMode::Cycle(t),
    };
    if !matches!(m, MotionMode::Cycle(_)) {
        it.exec.cycles.leave();
    }
    it.st.motion = m;
}

/// What the end of a program resets (LinuxCNC's `convert_stop` for M2/M30): the spindle
/// stops, feed per minute, G17, G90 … The offsets and the position stay.
pub(super) fn program_end(it: &mut Interpreter<'_>, loc: Loc) {
    it.st.spindle_dir = 0;
    it.st.speed_rpm = 0.0;
    it.emit(Canon::Spindle { loc, rpm: 0.0 });
    it.st.feed.mode = FeedMode::PerMinute;
    it.st.plane = Plane::Xy;
    it.st.absolute = true;
}

fn spindle(it: &mut Interpreter<'_>, loc: Loc) {
    let rpm = it.st.speed_rpm * f64::from(it.st.spindle_dir);
    it.st.feed.spindle_rpm = it.st.speed_rpm * f64::from(it.st.spindle_dir.abs());
    it.emit(Canon::Spindle { loc, rpm });
}

fn compensation(it: &mut Interpreter<'_>, loc: Loc, b: &Block, t: i32) -> Result<(), Problem> {
    match t {
        400 => {
            it.st.comp = CompSide::Off;
            if let Some(comp) = it.exec.comp.as_mut() {
                let mut out = std::mem::take(&mut it.exec.comp_out);
                let r = comp.stop(loc, &mut out);
                it.drain(&mut out);
                it.exec.comp_out = out;
                r.map_err(comp_err)?;
            }
        }
        410 | 420 | 411 | 421 => {
            let radius = if t % 10 == 1 {
                // G41.1/G42.1 D: the diameter itself.
                let d = b.get(b'd').ok_or_else(|| Problem::Rule(format!("{} needs D, the tool diameter", gname(t))))?;
                0.5 * it.length(d)
            } else {
                let n = match b.get(b'd') {
                    Some(d) if d < 0.0 || (d - d.round()).abs() > INTEGER_SLACK => {
                        return Err(Problem::Rule(format!(
                            "{} D{} is not a tool number (a whole number ≥ 0)",
                            gname(t),
                            super::error::show(d)
                        )));
                    }
                    Some(d) => d.round() as i32,
                    None => it.st.tool,
                };
                match it.opts.tools.get(n) {
                    Some(td) => 0.5 * td.diameter_mm,
                    None => {
                        if n != 0 {
                            it.report(
                                &format!("{} D{n}", gname(t)),
                                loc,
                                "the tool is not in the tool table (give one with --tools): compensated with radius 0, the programmed path",
                            );
                        }
                        0.0
                    }
                }
            };
            let side = if t / 10 == 41 { Side::Left } else { Side::Right };
            let plane = it.st.plane;
            let inch = it.st.inch;
            let comp = it.exec.comp.get_or_insert_with(|| {
                let mut c = CutterComp::new(plane);
                c.set_inch(inch);
                c
            });
            let position = DVec3::new(it.st.prog[0], it.st.prog[1], it.st.prog[2]);
            comp.start(side, radius, position, loc).map_err(comp_err)?;
            it.st.comp = if side == Side::Left { CompSide::Left } else { CompSide::Right };
            it.st.comp_radius = radius;
        }
        _ => {}
    }
    Ok(())
}

fn tool_length(it: &mut Interpreter<'_>, loc: Loc, b: &Block, t: i32) -> Result<(), Problem> {
    let table = |n: i32| it.opts.tools.get(n).map_or(DVec3::ZERO, |td| td.offset_mm);
    let tlo = match t {
        430 | 440 => {
            let n = b.get(b'h').map_or(it.st.tool, |h| h.round() as i32);
            let o = table(n);
            if t == 440 { -o } else { o }
        }
        431 => {
            let sc = it.st.scale();
            DVec3::new(
                b.get(b'x').map_or(0.0, |v| v * sc),
                b.get(b'y').map_or(0.0, |v| v * sc),
                b.get(b'z').map_or(0.0, |v| v * sc),
            )
        }
        432 => {
            let n = b.get(b'h').map_or(it.st.tool, |h| h.round() as i32);
            it.st.tlo + table(n)
        }
        _ => DVec3::ZERO,
    };
    // The spindle does not move: the tip it holds now reads that much lower (LinuxCNC's
    // `convert_tool_length_offset` moves the current point by old − new).
    let d = it.st.tlo - tlo;
    it.st.prog[0] += d.x;
    it.st.prog[1] += d.y;
    it.st.prog[2] += d.z;
    it.st.tlo = tlo;
    for (i, v) in [tlo.x, tlo.y, tlo.z].into_iter().enumerate() {
        it.params.set(5401 + i, v);
    }
    it.emit(Canon::ToolLengthOffset { loc, offset: tlo });
    Ok(())
}

/// G10 L2 / L20: a coordinate system's offsets (LinuxCNC's `convert_setup`).
fn setup(it: &mut Interpreter<'_>, b: &Block) -> Result<(), Problem> {
    let l = b.get(b'l').map_or(-1.0, f64::round) as i32;
    match l {
        2 | 20 => {}
        1 | 10 | 11 => return tool_setup(it, b, l),
        _ => return Err(Problem::Rule("G10 needs L2 or L20 (coordinate systems) or L1, L10, L11 (tools)".into())),
    }
    let p = b.get(b'p').unwrap_or(0.0);
    if !(0.0..=9.0).contains(&p.round()) || (p - p.round()).abs() > INTEGER_SLACK {
        return Err(Problem::Rule(format!(
            "G10 L{l} P{} is not a coordinate system; use P0 (current) or P1 (G54) to P9 (G59.3)",
            super::error::show(p)
        )));
    }
    let sys = if p.round() == 0.0 { it.st.system } else { p.round() as usize };
    let sc = it.st.scale();
    let letters = [b'x', b'y', b'z', b'a', b'b', b'c'];
    let given: Vec<Option<f64>> =
        letters.iter().enumerate().map(|(i, &c)| b.get(c).map(|v| if i < 3 { v * sc } else { v })).collect();
    let r = b.get(b'r');
    if l == 20 && r.is_some() {
        return Err(Problem::Rule("R is not allowed with G10 L20; set a rotation with G10 L2 R".into()));
    }
    let active = sys == it.st.system;
    it.st.keep_tool(|st| {
        if l == 2 {
            for (i, g) in given.iter().enumerate() {
                if let Some(v) = g {
                    st.g5x[sys][i] = *v;
                }
            }
            if let Some(r) = r {
                st.rotation_deg[sys] = r;
            }
        } else {
            // L20: the offsets that make the current position read as the given values.
            let saved = st.system;
            let m = st.pose();
            st.system = sys;
            let mut target = st.to_program(&m);
            for (i, g) in given.iter().enumerate() {
                if let Some(v) = g {
                    target[i] = *v;
                }
            }
            let mut probe = st.clone();
            probe.g5x[sys] = [0.0; 6];
            let zero = probe.to_machine(&target);
            let off = [
                m.xyz.x - zero.xyz.x,
                m.xyz.y - zero.xyz.y,
                m.xyz.z - zero.xyz.z,
                m.abc.x - zero.abc.x,
                m.abc.y - zero.abc.y,
                m.abc.z - zero.abc.z,
            ];
            for (i, g) in given.iter().enumerate() {
                if g.is_some() {
                    st.g5x[sys][i] = off[i];
                }
            }
            st.system = saved;
        }
    });
    let _ = active;
    for i in 0..6 {
        it.params.set(5201 + sys * 20 + i, it.st.g5x[sys][i]);
    }
    it.params.set(5210 + sys * 20, it.st.rotation_deg[sys]);
    Ok(())
}

/// G10 L1 / L10 / L11: a tool table entry set from the program (LinuxCNC's
/// `convert_setup_tool`). L1 takes the offsets as given; L10 (and L11, in G59.3's frame)
/// the offsets that make the current position read as the given values with that tool.
fn tool_setup(it: &mut Interpreter<'_>, b: &Block, l: i32) -> Result<(), Problem> {
    let p = b.get(b'p').unwrap_or(-1.0);
    if p < 1.0 || (p - p.round()).abs() > INTEGER_SLACK {
        return Err(Problem::Rule(format!("G10 L{l} needs P, the tool number (a whole number ≥ 1)")));
    }
    let n = p.round() as i32;
    let sc = it.st.scale();
    let mut entry = it
        .opts
        .tools
        .get(n)
        .cloned()
        .unwrap_or_else(|| super::tools::ToolEntry::new(n, super::tools::ToolShape::Flat, 0.0));
    let given = |c: u8| b.get(c).map(|v| v * sc);
    if l == 1 {
        for (i, c) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = given(c) {
                entry.offset_mm[i] = v;
            }
        }
    } else {
        // The spindle stays where it is: new offset = spindle − where the value lies.
        let saved = it.st.system;
        if l == 11 {
            it.st.system = 9;
        }
        let spindle = it.st.pose().xyz + it.st.tlo;
        for (i, c) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = b.get(c) {
                let mut q = it.st.prog;
                q[i] = v * sc;
                let at = if l == 11 {
                    let mut probe = it.st.clone();
                    probe.g5x[9] = [0.0; 6];
                    probe.g92 = [0.0; 6];
                    probe.rotation_deg[9] = 0.0;
                    probe.to_machine(&q).xyz
                } else {
                    it.st.to_machine(&q).xyz
                };
                entry.offset_mm[i] = spindle[i] - at[i];
            }
        }
        it.st.system = saved;
    }
    if let Some(r) = given(b'r') {
        entry.diameter_mm = 2.0 * r.abs();
    }
    it.opts.tools.set(entry).map_err(|e| Problem::Rule(e.to_string()))?;
    Ok(())
}

/// G52, G92, G92.1, G92.2, G92.3.
fn axis_offsets(it: &mut Interpreter<'_>, b: &Block, t: i32) {
    let sc = it.st.scale();
    let letters = [b'x', b'y', b'z', b'a', b'b', b'c'];
    let given: Vec<Option<f64>> =
        letters.iter().enumerate().map(|(i, &c)| b.get(c).map(|v| if i < 3 { v * sc } else { v })).collect();
    match t {
        520 => it.st.keep_tool(|st| {
            for (i, g) in given.iter().enumerate() {
                if let Some(v) = g {
                    st.g92[i] = *v;
                }
            }
        }),
        920 => it.st.keep_tool(|st| {
            // The offset that makes the current position read as the given values.
            let m = st.pose();
            let mut probe = st.clone();
            probe.g92 = [0.0; 6];
            let mut target = st.prog;
            for (i, g) in given.iter().enumerate() {
                if let Some(v) = g {
                    target[i] = *v;
                }
            }
            let at = probe.to_program(&m);
            for (i, g) in given.iter().enumerate() {
                if g.is_some() {
                    st.g92[i] = at[i] - target[i];
                }
            }
        }),
        921 | 922 => it.st.keep_tool(|st| st.g92 = [0.0; 6]),
        _ => {
            let saved: Axes = std::array::from_fn(|i| it.params.get(5211 + i));
            it.st.keep_tool(|st| st.g92 = saved);
        }
    }
    if t != 922 && t != 923 {
        for i in 0..6 {
            it.params.set(5211 + i, it.st.g92[i]);
        }
        it.params.set(5210, f64::from(u8::from(t != 921)));
    }
}

/// The end of a move in program coordinates (LinuxCNC's `find_ends`): absolute or
/// incremental, polar `@ ^`, FANUC G16 polar.
fn find_end(st: &State, b: &Block) -> Result<Axes, Problem> {
    let sc = st.scale();
    let mut end = st.prog;
    let letters = [b'x', b'y', b'z', b'a', b'b', b'c'];
    for (i, &c) in letters.iter().enumerate() {
        if let Some(v) = b.get(c) {
            let v = if i < 3 { v * sc } else { v };
            end[i] = if st.absolute { v } else { st.prog[i] + v };
        }
    }
    if b.polar_r.is_some() || b.polar_a.is_some() {
        if b.get(b'x').is_some() || b.get(b'y').is_some() {
            return Err(Problem::Rule("X or Y with polar coordinates (@ ^); give one or the other".into()));
        }
        let (px, py) = (st.prog[0], st.prog[1]);
        if st.absolute {
            let theta = match b.polar_a {
                Some(a) => a.to_radians(),
                None => {
                    if px == 0.0 && py == 0.0 {
                        return Err(Problem::Rule("polar distance @ at the origin needs an angle ^".into()));
                    }
                    py.atan2(px)
                }
            };
            let r = b.polar_r.map_or(px.hypot(py), |r| r * sc);
            end[0] = r * theta.cos();
            end[1] = r * theta.sin();
        } else {
            if px == 0.0 && py == 0.0 {
                return Err(Problem::Rule("incremental polar motion at the origin is indeterminate".into()));
            }
            let theta = py.atan2(px) + b.polar_a.map_or(0.0, f64::to_radians);
            let r = px.hypot(py) + b.polar_r.map_or(0.0, |r| r * sc);
            end[0] = r * theta.cos();
            end[1] = r * theta.sin();
        }
    }
    if st.polar && st.plane == Plane::Xy && (b.get(b'x').is_some() || b.get(b'y').is_some()) {
        // FANUC G16: X is the radius, Y the angle (degrees) about the program origin.
        let r = if b.get(b'x').is_some() { end[0] } else { st.prog[0].hypot(st.prog[1]) };
        let a = b.get(b'y').map_or_else(|| st.prog[1].atan2(st.prog[0]), f64::to_radians);
        end[0] = r * a.cos();
        end[1] = r * a.sin();
    }
    Ok(end)
}

/// G28 / G30: through the intermediate point to the stored position.
fn home(it: &mut Interpreter<'_>, loc: Loc, b: &Block, t: i32) -> Result<(), Problem> {
    if it.st.comp != CompSide::Off {
        return Err(Problem::Rule("G28/G30 with cutter compensation on; give G40 first".into()));
    }
    let mid = find_end(&it.st, b)?;
    let end = it.st.to_machine(&mid);
    it.emit(Canon::Traverse { loc, end, origin: Origin::Reference });
    it.st.prog = mid;
    let base = if t == 280 { 5161 } else { 5181 };
    let tlo = it.st.tlo;
    let stored = Pose {
        xyz: DVec3::new(it.params.get(base), it.params.get(base + 1), it.params.get(base + 2)) - tlo,
        abc: DVec3::new(it.params.get(base + 3), it.params.get(base + 4), it.params.get(base + 5)),
    };
    let home = it.st.to_program(&stored);
    let letters = [b'x', b'y', b'z', b'a', b'b', b'c'];
    let any = letters.iter().any(|&c| b.get(c).is_some());
    let mut target = mid;
    for (i, &c) in letters.iter().enumerate() {
        if !any || b.get(c).is_some() {
            target[i] = home[i];
        }
    }
    let end = it.st.to_machine(&target);
    it.emit(Canon::Traverse { loc, end, origin: Origin::Reference });
    it.st.prog = target;
    Ok(())
}

fn motion(it: &mut Interpreter<'_>, loc: Loc, b: &Block, machine: bool, code: Option<i32>) -> Result<(), Problem> {
    let moving = has_axes(b);
    let mode = it.st.motion;
    if !moving {
        // G2/G3 with only centre words is a full circle; anything else without axes does
        // nothing (LinuxCNC).
        let full_circle = matches!(mode, MotionMode::ArcCw | MotionMode::ArcCcw)
            && code.is_some()
            && (b.get(b'i').is_some() || b.get(b'j').is_some() || b.get(b'k').is_some());
        if !full_circle {
            return Ok(());
        }
    }
    if machine {
        it.refuse_if_comp(Refusal::MachineCoordinates, loc)?;
        // G53: this block's coordinates are machine positions (absolute only).
        if !matches!(mode, MotionMode::Rapid | MotionMode::Linear) {
            return Err(Problem::Rule("G53 is only allowed with G0 or G1".into()));
        }
        if !it.st.absolute {
            return Err(Problem::Rule("G53 is not allowed in incremental mode (G91)".into()));
        }
        let mut m = it.st.pose();
        let tlo = it.st.tlo;
        let sc = it.st.scale();
        for (i, c) in [b'x', b'y', b'z'].into_iter().enumerate() {
            if let Some(v) = b.get(c) {
                m.xyz[i] = v * sc - tlo[i];
            }
        }
        for (i, c) in [b'a', b'b', b'c'].into_iter().enumerate() {
            if let Some(v) = b.get(c) {
                m.abc[i] = v;
            }
        }
        let end = it.st.to_program(&m);
        return straight(it, loc, end, mode == MotionMode::Rapid, Origin::Programmed);
    }
    match mode {
        MotionMode::None => {
            if it.opts.strict || code.is_some() {
                return Err(Problem::Rule(
                    "axis words with no motion mode (G80 or none yet); give G0, G1, G2 or G3".into(),
                ));
            }
            Err(Problem::Rule("axis words but no motion mode yet; give G0, G1, G2 or G3 first".into()))
        }
        MotionMode::Rapid | MotionMode::Linear => {
            let end = find_end(&it.st, b)?;
            straight(it, loc, end, mode == MotionMode::Rapid, Origin::Programmed)
        }
        MotionMode::ArcCw | MotionMode::ArcCcw => arc(it, loc, b, mode == MotionMode::ArcCcw),
        MotionMode::Probe(t) => {
            it.refuse_if_comp(Refusal::Probe, loc)?;
            it.report(&gname(t), loc, "probing: the move is taken to its programmed end (no contact is simulated)");
            let end = find_end(&it.st, b)?;
            let feed = it.st.feed;
            let m = it.st.to_machine(&end);
            it.emit(Canon::Line { loc, end: m, feed, origin: Origin::Probe });
            // As LinuxCNC's stand-alone interpreter models it: the probe trips at the end of
            // its move (#5061… hold that point, program units), #5070 says it did not close,
            // and the tool backs off 0.254 mm (0.01 inch) toward where it came from.
            let sc = it.st.scale();
            for i in 0..6 {
                it.params.set(5061 + i, if i < 3 { end[i] / sc } else { end[i] });
            }
            it.params.set(5070, 0.0);
            let start = it.st.prog;
            let d = DVec3::new(start[0] - end[0], start[1] - end[1], start[2] - end[2]);
            let mut after = end;
            if d.length() > 0.0 {
                // 0.254 mm, which is also the 0.01 inch of an inch program.
                let back = d / d.length() * 0.254;
                after[0] += back.x;
                after[1] += back.y;
                after[2] += back.z;
                let m = it.st.to_machine(&after);
                it.emit(Canon::Traverse { loc, end: m, origin: Origin::Probe });
            }
            it.st.prog = after;
            Ok(())
        }
        MotionMode::Synchronised(t) => {
            it.report(
                &gname(t),
                loc,
                "spindle-synchronised motion (threading, rigid tapping): drawn as a straight feed",
            );
            let end = find_end(&it.st, b)?;
            straight(it, loc, end, false, Origin::Programmed)
        }
        MotionMode::Cycle(t) => cycle(it, loc, b, t),
        MotionMode::Cubic | MotionMode::Quadratic => bezier(it, loc, b, mode == MotionMode::Cubic),
        // Blocks of a multi-block spline are taken by `spline_block`; coordinates after a
        // finished G6.2 are refused there.
        MotionMode::LinuxNurbs | MotionMode::FanucNurbs => Ok(()),
    }
}

fn straight(it: &mut Interpreter<'_>, loc: Loc, end: Axes, rapid: bool, origin: Origin) -> Result<(), Problem> {
    if origin == Origin::Programmed {
        let (kind, feed) = if rapid { (MoveKind::Traverse, it.st.feed) } else { (MoveKind::Feed, check_feed(it)?) };
        return it.prog_move(loc, kind, end, feed);
    }
    let m = it.st.to_machine(&end);
    if rapid {
        it.emit(Canon::Traverse { loc, end: m, origin });
    } else {
        let feed = check_feed(it)?;
        it.emit(Canon::Line { loc, end: m, feed, origin });
    }
    it.st.prog = end;
    Ok(())
}

fn check_feed(it: &Interpreter<'_>) -> Result<super::Feed, Problem> {
    let f = it.st.feed;
    if f.rate <= 0.0 {
        return Err(Problem::Rule(
            "a feed move without a feed rate; give F (mm/min, or in/min after G20) on this or an earlier block — a feed must be positive".into(),
        ));
    }
    Ok(f)
}

/// The end of an R-format arc is its start (LinuxCNC compares exactly).
#[expect(clippy::float_cmp, reason = "LinuxCNC refuses an R arc whose end equals its start exactly")]
fn same_point(ea: f64, eb: f64, sa: f64, sb: f64) -> bool {
    ea == sa && eb == sb
}

/// G2/G3: centre by I J K (or absolute with G90.1) or by R, turns by P, helical along the
/// plane's normal, LinuxCNC's tolerances (`arc_data_ijk`, `arc_data_r`).
fn arc(it: &mut Interpreter<'_>, loc: Loc, b: &Block, ccw: bool) -> Result<(), Problem> {
    let feed = check_feed(it)?;
    let mut notes: Vec<(&str, String)> = Vec::new();
    let st = &it.st;
    let end = find_end(st, b)?;
    let plane = st.plane;
    let (ia, ib, _) = plane.axes();
    let start = st.prog;
    let (sa, sb) = (start[ia], start[ib]);
    let (ea, eb) = (end[ia], end[ib]);
    let sc = st.scale();
    let p = b.get(b'p').unwrap_or(1.0);
    if p < 1.0 || (p - p.round()).abs() > INTEGER_SLACK {
        return Err(Problem::Rule(format!("P{} on an arc must be a whole number of turns ≥ 1", super::error::show(p))));
    }
    if p > MAX_ARC_TURNS {
        return Err(Problem::Cap(format!("an arc of more than {MAX_ARC_TURNS} turns (P); split it")));
    }
    let turns = p.round() as i32;
    let (abs_tol, zero_tol) = if st.inch {
        (CENTER_ARC_TOL_INCH * 25.4, RADIUS_TOL_INCH * 25.4)
    } else {
        (CENTER_ARC_TOL_MM, RADIUS_TOL_INCH * 25.4)
    };
    let offset_letters = [b'i', b'j', b'k'];
    let (ca, cb) = if let Some(r) = b.get(b'r') {
        if b.get(offset_letters[ia]).is_some() || b.get(offset_letters[ib]).is_some() {
            return Err(Problem::Rule("an arc with both R and centre words (I J K); give one".into()));
        }
        let r = r * sc;
        if same_point(ea, eb, sa, sb) {
            return Err(Problem::Rule(
                "an R-format arc ending where it starts has no defined centre; use I J K for a full circle".into(),
            ));
        }
        let abs_r = r.abs();
        let (ma, mb) = (0.5 * (sa + ea), 0.5 * (sb + eb));
        let mut half = (ma - ea).hypot(mb - eb);
        if half - abs_r > zero_tol {
            let what = format!(
                "radius R{} is smaller than half the distance to the end point ({} mm); no such arc exists",
                super::error::show(r / sc),
                super::error::show(half)
            );
            if it.opts.strict {
                return Err(Problem::Rule(what));
            }
            // LinuxCNC refuses it; a viewer draws the half circle over the chord and says so.
            notes.push(("R arc", format!("{what} (LinuxCNC refuses it): drawn as the half circle")));
        }
        if half / abs_r > 1.0 - HALF_CIRCLE_REL {
            half = abs_r;
        }
        let base = (eb - sb).atan2(ea - sa);
        let theta = if (!ccw && r > 0.0) || (ccw && r < 0.0) {
            base - std::f64::consts::FRAC_PI_2
        } else {
            base + std::f64::consts::FRAC_PI_2
        };
        let off = abs_r * (half / abs_r).asin().cos();
        (ma + off * theta.cos(), mb + off * theta.sin())
    } else {
        let oa = b.get(offset_letters[ia]);
        let ob = b.get(offset_letters[ib]);
        if oa.is_none() && ob.is_none() {
            return Err(Problem::Rule(format!(
                "an arc needs its centre ({}{} offsets from the start) or a radius R",
                offset_letters[ia].to_ascii_uppercase() as char,
                offset_letters[ib].to_ascii_uppercase() as char
            )));
        }
        let (oa, ob) = (oa.unwrap_or(0.0) * sc, ob.unwrap_or(0.0) * sc);
        let c = if st.arc_absolute { (oa, ob) } else { (sa + oa, sb + ob) };
        let r1 = (c.0 - sa).hypot(c.1 - sb);
        let r2 = (c.0 - ea).hypot(c.1 - eb);
        if r1 < zero_tol || r2 < zero_tol {
            return Err(Problem::Rule(format!(
                "zero-radius arc (radius {} mm at the start, {} mm at the end); check the centre offsets",
                super::error::show(r1),
                super::error::show(r2)
            )));
        }
        let abs_err = (r1 - r2).abs();
        let rel_err = abs_err / r1.max(r2);
        if abs_err > 100.0 * abs_tol || (rel_err > SPIRAL_REL_TOL && abs_err > abs_tol) {
            let what = format!(
                "the arc's end is not on its circle: radius {} mm at the start, {} mm at the end (LinuxCNC allows {} mm); correct the end point or the centre",
                super::error::show(r1),
                super::error::show(r2),
                super::error::show(abs_tol)
            );
            if it.opts.strict {
                return Err(Problem::Rule(what));
            }
            // LinuxCNC refuses it; a viewer draws the spiral from one radius to the other.
            notes.push(("arc radius", format!("{what} — LinuxCNC refuses it; drawn as a spiral")));
        }
        c
    };
    for (code, what) in notes {
        it.report(code, loc, &what);
    }
    let st = &it.st;
    let mut center = start;
    center[ia] = ca;
    center[ib] = cb;
    if plane != Plane::Xy && st.xy_rotation_deg() != 0.0 {
        it.report("rotated arc", loc, "an arc outside G17 under a rotated coordinate system is not modelled exactly");
    }
    let turns = if ccw { turns } else { -turns };
    let center = DVec3::new(center[0], center[1], center[2]);
    it.prog_move(loc, MoveKind::Arc { center, turns }, end, feed)
}

/// The end of the program: a spline still open is finished (Sinumerik) or refused.
pub(super) fn finish(it: &mut Interpreter<'_>, loc: Loc) -> Result<(), Problem> {
    it.comp_release(loc, true)?;
    if let Some(f) = it.exec.splines.end_of_program().map_err(spline_err)? {
        emit_spline(it, f)?;
    }
    Ok(())
}

/// A program with no G20/G21 whose cuts span only a few units at a low feed reads like
/// inches read as millimetres: warn, naming the option that reads it in inches.
pub(super) fn inch_warning(it: &mut Interpreter<'_>) {
    let e = &it.exec;
    let (Some(lo), Some(first)) = (e.lo, e.first_cut) else {
        return;
    };
    if it.opts.inch {
        return;
    }
    let span = e.hi - lo;
    let size = span.max_element();
    if size > 0.0 && size < 30.0 && e.max_feed > 0.0 && e.max_feed < 150.0 {
        let text = format!(
            "no G20/G21: read as millimetres, but the cuts span only {} × {} × {} mm at feeds up to {} mm/min — if the program is in inches, read it with --units inch (25.4 × larger)",
            super::error::show(round3(span.x)),
            super::error::show(round3(span.y)),
            super::error::show(round3(span.z)),
            super::error::show(round3(e.max_feed))
        );
        it.warnings.push(Warning { loc: first, text });
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// A canned cycle block: its moves from [`cycles::expand`], mapped to the machine.
fn cycle(it: &mut Interpreter<'_>, loc: Loc, b: &Block, t: i32) -> Result<(), Problem> {
    it.refuse_if_comp(Refusal::CannedCycle, loc)?;
    let Some(kind) = CycleKind::from_g(f64::from(t) / 10.0) else {
        it.report(&gname(t), loc, "this canned cycle is not modelled");
        return Ok(());
    };
    let st = &it.st;
    let sc = st.scale();
    let len = |c: u8| b.get(c).map(|v| v * sc);
    let rotary = [b'a', b'b', b'c'].into_iter().find(|&c| b.get(c).is_some()).map(|c| c.to_ascii_uppercase() as char);
    let input = CycleInput {
        kind,
        plane: st.plane,
        position: DVec3::new(st.prog[0], st.prog[1], st.prog[2]),
        incremental: !st.absolute,
        retract: if st.retract_initial { Retract::OldZ } else { Retract::RPlane },
        spindle: match st.spindle_dir {
            1 => SpindleDir::Clockwise,
            -1 => SpindleDir::CounterClockwise,
            _ => SpindleDir::Stopped,
        },
        feed_rate: st.feed.rate,
        inverse_time: st.feed.mode == FeedMode::InverseTime,
        cutter_comp: st.comp != CompSide::Off,
        unit_mm: sc,
        words: CycleWords {
            x: len(b'x'),
            y: len(b'y'),
            z: len(b'z'),
            r: len(b'r'),
            q: len(b'q'),
            p: b.get(b'p'),
            i: len(b'i'),
            j: len(b'j'),
            k: len(b'k'),
            l: b.get(b'l'),
            polar_radius: b.polar_r.map(|r| r * sc),
            polar_angle_deg: b.polar_a,
            rotary,
        },
    };
    let mut moves = Vec::new();
    // Haas and FANUC programs drill without R (from where the tool is) or without a dwell P;
    // LinuxCNC refuses both. Read leniently, R at the current height and P as 0, and say so.
    let mut input = input;
    let mut outcome = cycles::expand(&input, &mut it.exec.cycles, &mut moves);
    for _ in 0..2 {
        let what = match &outcome {
            Err(cycles::CycleError::MissingR { .. }) if !it.opts.strict => {
                let n = input.plane.axes().2;
                input.words.r = Some(if input.incremental { 0.0 } else { input.position[n] });
                "a canned cycle without R (LinuxCNC refuses it): R taken as the current height"
            }
            Err(cycles::CycleError::MissingP { .. }) if !it.opts.strict => {
                input.words.p = Some(0.0);
                "a dwelling canned cycle without P (LinuxCNC refuses it): no dwell"
            }
            _ => break,
        };
        it.report(&format!("{} lenient", kind.name()), loc, what);
        moves.clear();
        outcome = cycles::expand(&input, &mut it.exec.cycles, &mut moves);
    }
    let outcome = outcome.map_err(|e| Problem::Rule(e.to_string()))?;
    let feed = it.st.feed;
    for m in moves {
        match m {
            CycleMove::Rapid(p) | CycleMove::OperatorRetract(p) => {
                let mut q = it.st.prog;
                q[..3].copy_from_slice(&p.to_array());
                let end = it.st.to_machine(&q);
                it.emit(Canon::Traverse { loc, end, origin: Origin::Cycle });
                it.st.prog = q;
            }
            CycleMove::Feed(p) => {
                let mut q = it.st.prog;
                q[..3].copy_from_slice(&p.to_array());
                let end = it.st.to_machine(&q);
                it.emit(Canon::Line { loc, end, feed, origin: Origin::Cycle });
                it.st.prog = q;
            }
            CycleMove::Dwell { seconds } => it.emit(Canon::Dwell { loc, seconds }),
            CycleMove::SpindleStop => it.emit(Canon::Spindle { loc, rpm: 0.0 }),
            CycleMove::SpindleStart { clockwise } => {
                let rpm = if clockwise { it.st.speed_rpm } else { -it.st.speed_rpm };
                it.emit(Canon::Spindle { loc, rpm });
            }
            CycleMove::SpindleOrient { .. } => {}
            CycleMove::ProgramStop => it.emit(Canon::Stop { loc, end: false }),
        }
    }
    it.st.prog[..3].copy_from_slice(&outcome.end.to_array());
    if let Some(note) = outcome.note {
        it.report(&format!("{} note", kind.name()), loc, &note.to_string());
    }
    Ok(())
}

/// A curve in the program frame, mapped to the machine frame (an affine map: the control
/// points move, knots and weights stay).
fn curve_to_machine(st: &State, c: &crate::geom::NurbsCurve) -> Result<crate::geom::NurbsCurve, Problem> {
    let pts: Vec<DVec3> = (0..c.len())
        .map(|i| {
            let p = c.control_point(i);
            let mut q = st.prog;
            q[..3].copy_from_slice(&p.to_array());
            st.to_machine(&q).xyz
        })
        .collect();
    let w: Vec<f64> = (0..c.len()).map(|i| c.weight(i)).collect();
    crate::geom::NurbsCurve::try_new(c.degree(), c.knots().to_vec(), &pts, Some(&w))
        .map_err(|e| Problem::Rule(format!("the spline cannot be placed in the machine frame: {e}")))
}

fn emit_spline(it: &mut Interpreter<'_>, f: FinishedSpline) -> Result<(), Problem> {
    let feed = check_feed(it)?;
    let curve = curve_to_machine(&it.st, &f.curve)?;
    let mut q = it.st.prog;
    q[..3].copy_from_slice(&f.end.to_array());
    let end = it.st.to_machine(&q);
    it.emit(Canon::Spline { loc: f.loc, curve: Box::new(curve), end, feed });
    it.st.prog = q;
    if let Some(note) = f.note {
        it.report("spline note", f.loc, &note.to_string());
    }
    Ok(())
}

/// Multi-block splines (G6.2, G5.2 … G5.3): a block of a curve (or one that opens or closes
/// one) goes to the [`SplineBuilder`]; returns whether it took the block.
fn spline_block(it: &mut Interpreter<'_>, loc: Loc, b: &Block, code: Option<i32>) -> Result<bool, Problem> {
    let open = match code {
        Some(62) => Some(SplineKind::Fanuc),
        Some(52) => Some(SplineKind::LinuxCnc),
        _ => None,
    };
    let close = code == Some(53);
    if !(it.exec.splines.is_active() || open.is_some() || close) {
        return Ok(false);
    }
    if open.is_some() {
        it.refuse_if_comp(Refusal::Spline, loc)?;
    }
    let other = code.filter(|t| !matches!(t, 62 | 52 | 53)).map(gname);
    let sc = it.st.scale();
    let len = |c: u8| b.get(c).map(|v| v * sc);
    let sb = SplineBlock {
        loc,
        open,
        close,
        other_motion: other.as_deref(),
        position: DVec3::new(it.st.prog[0], it.st.prog[1], it.st.prog[2]),
        absolute: it.st.absolute,
        plane: it.st.plane,
        feed_set: it.st.feed.rate > 0.0,
        inch: it.st.inch,
        words: SplineWords {
            x: len(b'x'),
            y: len(b'y'),
            z: len(b'z'),
            k: b.get(b'k'),
            r: b.get(b'r'),
            p: b.get(b'p'),
            l: b.get(b'l'),
            ..SplineWords::default()
        },
    };
    let step = it.exec.splines.block(&sb).map_err(spline_err)?;
    if let Some(f) = step.finished {
        emit_spline(it, f)?;
    }
    Ok(step.taken)
}

/// G5 / G5.1: one Bézier.
fn bezier(it: &mut Interpreter<'_>, loc: Loc, b: &Block, cubic: bool) -> Result<(), Problem> {
    let st = &it.st;
    let sc = st.scale();
    let end = find_end(st, b)?;
    let other_axis =
        [b'z', b'a', b'b', b'c'].into_iter().find(|&c| b.get(c).is_some()).map(|c| c.to_ascii_uppercase() as char);
    let len = |c: u8| b.get(c).map(|v| v * sc);
    let bb = BezierBlock {
        loc,
        position: DVec3::new(st.prog[0], st.prog[1], st.prog[2]),
        end_xy: [end[0], end[1]],
        i: len(b'i'),
        j: len(b'j'),
        p: len(b'p'),
        q: len(b'q'),
        plane: st.plane,
        other_axis,
        cutter_comp: st.comp != CompSide::Off,
        feed_ok: st.feed.rate > 0.0,
    };
    let end3 = DVec3::new(end[0], end[1], st.prog[2]);
    let curve = if cubic { it.exec.splines.cubic(&bb) } else { it.exec.splines.quadratic(&bb) }.map_err(spline_err)?;
    emit_spline(it, FinishedSpline { loc, curve, end: end3, note: None })
}
