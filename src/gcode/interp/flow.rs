//! Control flow: O-word subroutines, conditionals and loops (LinuxCNC), `M98`/`M99`
//! subprograms, `G65` macro calls and Macro B's `GOTO`, `IF`, `WHILE … DO … END` (FANUC).
//!
//! Lines are read once in order; a loop or a call jumps back or ahead by seeking its source to
//! a position seen or found. A construct being passed over (a false `if`, a `sub` met in the
//! main flow, the rest of a loop after `break`) is *skipped*: its lines are only looked at for
//! the O-word or `END` that closes it, never computed. A call to a subroutine not yet seen
//! searches the rest of the file (then its start, for FANUC programs placed before), then the
//! library of subroutine files.

use std::collections::HashMap;

use super::read::{Env, Flow as FanucFlow, OKind, Peek};
use super::source::SourcePos;
use super::{Interpreter, Loc, MAX_CALL_DEPTH, MAX_CONTROL_DEPTH, Open, Problem};

/// What is being skipped, and what ends the skip.
#[derive(Clone, Debug, PartialEq)]
enum Skip {
    /// A `sub` met in the main flow: to its `endsub`.
    Sub(String),
    /// A false `if`/`elseif`: to the next `elseif`, `else` or `endif` of the label.
    IfFalse(String),
    /// The rest of an `if` after its taken branch: to `endif`.
    ToEndIf(String),
    /// Out of a loop (`break`, a false `while`, `repeat 0`): to the loop's end.
    LoopEnd(String, LoopKind),
    /// Out of a FANUC `WHILE … DO m`: to `END m`.
    FanucEnd(u32),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LoopKind {
    While,
    Do,
    Repeat,
}

/// An open conditional or loop.
#[derive(Clone, Debug)]
struct Ctl {
    name: String,
    kind: CtlKind,
    /// Line where it opened (for messages).
    line: u32,
    /// Call depth it belongs to.
    depth: usize,
}

#[derive(Clone, Debug)]
enum CtlKind {
    If,
    While { start: SourcePos },
    Do { start: SourcePos },
    Repeat { body: SourcePos, left: u64 },
    FanucLoop { id: u32, start: SourcePos },
}

/// A subroutine call in progress.
#[derive(Clone, Debug)]
struct Call {
    /// Number of open files when called (a call into another file opens one more).
    files: usize,
    /// Where the caller continues (in the caller's file).
    back: SourcePos,
    /// The body's first line, for `M98 … L` repeats.
    body: SourcePos,
    /// Repeats left after this one.
    repeats: u64,
    /// The control stack's length at the call.
    ctl: usize,
    /// LinuxCNC O-word sub (`endsub`/`return`) or FANUC (`M99`).
    fanuc: bool,
}

/// The flow state.
#[derive(Debug, Default)]
pub(super) struct Flow {
    skip: Option<Skip>,
    ctl: Vec<Ctl>,
    calls: Vec<Call>,
    subs: HashMap<(u16, String), SourcePos>,
    programs: HashMap<(u16, String), SourcePos>,
    labels: HashMap<(u16, i64), SourcePos>,
    percent: u8,
}

impl Flow {
    pub fn in_call(&self) -> bool {
        !self.calls.is_empty()
    }

    pub fn skipping(&self) -> bool {
        self.skip.is_some()
    }

    pub fn skip_target(&self) -> String {
        match &self.skip {
            Some(Skip::Sub(n)) => format!("the endsub of o{n}"),
            Some(Skip::IfFalse(n) | Skip::ToEndIf(n)) => format!("the endif of o{n}"),
            Some(Skip::LoopEnd(n, _)) => format!("the end of the loop o{n}"),
            Some(Skip::FanucEnd(id)) => format!("END{id}"),
            None => String::new(),
        }
    }

    /// The line of the innermost open loop.
    pub fn innermost_loop(&self) -> Option<u32> {
        self.ctl.iter().rev().find(|c| !matches!(c.kind, CtlKind::If)).map(|c| c.line)
    }
}

/// The values a line's expressions read: parameters and the state's named system parameters.
pub(super) struct View<'s> {
    pub params: &'s super::params::Params,
    pub st: &'s super::state::State,
    pub depth: usize,
    /// Set when a line read a controller's HAL pin or INI value, which a program file does
    /// not hold (read as 0 and reported).
    pub outside: std::cell::Cell<bool>,
}

impl Env for View<'_> {
    fn numbered(&self, n: usize) -> f64 {
        let st = self.st;
        let s = st.scale();
        let axis = |v: &[f64; 6], i: usize| if i < 3 { v[i] / s } else { v[i] };
        match n {
            // LinuxCNC: the current position in the program frame (program units).
            5420..=5425 => axis(&st.prog, n - 5420),
            // FANUC: the block's end and the current position in work coordinates …
            5001..=5006 => axis(&st.prog, n - 5001),
            5041..=5046 => axis(&st.prog, n - 5041),
            // … and in machine coordinates.
            5021..=5026 => {
                let m = st.pose();
                let v = [m.xyz.x, m.xyz.y, m.xyz.z, m.abc.x, m.abc.y, m.abc.z];
                axis(&v, n - 5021)
            }
            _ => self.params.get(n),
        }
    }

    fn named(&self, name: &str) -> Option<f64> {
        if let Some(v) = self.params.named(name) {
            return Some(v);
        }
        if name.starts_with("_hal[") || name.starts_with("_ini[") {
            self.outside.set(true);
            return Some(0.0);
        }
        let st = self.st;
        let s = st.scale();
        let b = |c: bool| f64::from(u8::from(c));
        let pose = st.pose();
        Some(match name {
            "_x" => st.prog[0] / s,
            "_y" => st.prog[1] / s,
            "_z" => st.prog[2] / s,
            "_a" => st.prog[3],
            "_b" => st.prog[4],
            "_c" => st.prog[5],
            "_abs_x" => pose.xyz.x / s,
            "_abs_y" => pose.xyz.y / s,
            "_abs_z" => pose.xyz.z / s,
            "_abs_a" => pose.abc.x,
            "_abs_b" => pose.abc.y,
            "_abs_c" => pose.abc.z,
            "_metric" => b(!st.inch),
            "_imperial" => b(st.inch),
            "_absolute" => b(st.absolute),
            "_incremental" => b(!st.absolute),
            "_feed" => st.feed.rate / s,
            "_rpm" => st.speed_rpm,
            "_current_tool" => f64::from(st.tool),
            "_selected_tool" => f64::from(st.selected_tool),
            "_coord_system" => 530.0 + 10.0 * st.system as f64,
            "_call_level" => self.depth as f64,
            "_remap_level" => 0.0,
            "_task" => 0.0,
            "_vmajor" => 2.9,
            "_vminor" => 0.0,
            "_plane" => match st.plane {
                crate::gcode::path::Plane::Xy => 170.0,
                crate::gcode::path::Plane::Zx => 180.0,
                crate::gcode::path::Plane::Yz => 190.0,
            },
            "_inverse_time" => b(st.feed.mode == super::FeedMode::InverseTime),
            "_units_per_minute" => b(st.feed.mode == super::FeedMode::PerMinute),
            "_units_per_rev" => b(st.feed.mode == super::FeedMode::PerRevolution),
            "_spindle_on" => b(st.spindle_dir != 0),
            "_retract_r" => b(!st.retract_initial),
            "_retract_old_z" => b(st.retract_initial),
            _ => return None,
        })
    }
}

/// FANUC `G65`/`M98` argument letters → local variables `#1`…`#26` (argument specification I).
const G65_ARGS: [(u8, usize); 21] = [
    (b'a', 1),
    (b'b', 2),
    (b'c', 3),
    (b'i', 4),
    (b'j', 5),
    (b'k', 6),
    (b'd', 7),
    (b'e', 8),
    (b'f', 9),
    (b'h', 11),
    (b'm', 13),
    (b'q', 17),
    (b'r', 18),
    (b's', 19),
    (b't', 20),
    (b'u', 21),
    (b'v', 22),
    (b'w', 23),
    (b'x', 24),
    (b'y', 25),
    (b'z', 26),
];

impl<'a> Interpreter<'a> {
    fn file_id(&self) -> u16 {
        self.files.last().map_or(0, |f| f.id)
    }

    fn tell(&self) -> SourcePos {
        self.files.last().map(|f| f.src.tell()).unwrap_or_default()
    }

    fn seek(&mut self, pos: SourcePos) -> Result<(), Problem> {
        match self.files.last_mut() {
            Some(f) => f.src.seek(pos).map_err(Problem::from),
            None => Ok(()),
        }
    }

    /// One line read at `loc` (its start at `pos`).
    pub(super) fn line_(&mut self, loc: Loc, pos: SourcePos) -> Result<(), Problem> {
        if self.flow.skip.is_some() {
            return self.skip_line(loc, pos);
        }
        let view = View {
            params: &self.params,
            st: &self.st,
            depth: self.flow.calls.len(),
            outside: std::cell::Cell::new(false),
        };
        let result = self.reader.read(&self.line, &view).map(|_| ());
        if view.outside.get() {
            self.report("#<_hal[…]>", loc, "a machine's HAL pin or INI value is not in the program: read as 0");
        }
        if let Err(p) = result {
            return self.unreadable(loc, pos, p);
        }
        let block = &self.reader.block;
        if block.percent {
            if block.percent_text {
                if self.opts.strict {
                    return Err(Problem::Rule("a '%' line with text after the mark is not G-code".into()));
                }
                self.report("% text", loc, "a line starting with '%' and text after it is not G-code: skipped");
            }
            self.flow.percent += 1;
            if self.flow.percent >= 2 && self.flow.calls.is_empty() && self.files.len() == 1 {
                // The second tape mark ends the program; what follows is not read.
                self.comp_release(loc, true)?;
                super::exec::program_end(self, loc);
                self.emit_stop(loc);
                self.finish(loc)?;
                self.done = true;
            }
            return Ok(());
        }
        if block.delete && self.opts.block_delete {
            return Ok(());
        }
        let mut block = self.reader.take_block();
        let result = self.after_read(loc, pos, &mut block);
        self.reader.put_block(block);
        result
    }

    fn after_read(&mut self, loc: Loc, pos: SourcePos, block: &mut super::read::Block) -> Result<(), Problem> {
        for (p, v) in block.assigns.drain(..) {
            self.params.assign(&p, v)?;
        }
        if let Some(n) = block.line_number {
            self.flow.labels.entry((loc.file, n.round() as i64)).or_insert(pos);
        }
        if let Some(o) = block.oword.take() {
            return self.oword(loc, pos, o);
        }
        if let Some(f) = block.flow.take() {
            self.fanuc_flow(loc, pos, f)?;
            if block.g.is_empty() && block.m.is_empty() && block.letters == 0 {
                return Ok(());
            }
        }
        // FANUC calls: M98, M99, G65.
        if block.m.contains(&98) {
            return self.m98(loc, block);
        }
        if block.m.contains(&99) {
            return self.m99(loc, block);
        }
        if block.g.contains(&650) {
            return self.g65(block);
        }
        super::exec::block(self, loc, block)
    }

    /// A line that cannot be read: refused in strict mode, else reported and skipped.
    fn unreadable(&mut self, loc: Loc, pos: SourcePos, p: Problem) -> Result<(), Problem> {
        let lexical = matches!(
            p,
            Problem::Char(_)
                | Problem::UnclosedComment
                | Problem::Expected(_)
                | Problem::NoValue(_)
                | Problem::BadNumber(_)
                | Problem::UnknownFunction(_)
                | Problem::UnknownOWord(_)
                | Problem::Trailing(_)
        );
        if self.opts.strict || !lexical {
            return Err(p);
        }
        if p == Problem::UnclosedComment {
            // The words before the comment still count.
            self.report("unclosed comment", loc, "a comment without ')' (read to the end of its line)");
            let mut block = self.reader.take_block();
            let r = self.after_read(loc, pos, &mut block);
            self.reader.put_block(block);
            return r;
        }
        self.report("not G-code", loc, &format!("a line that is not G-code was skipped (first: {p})"));
        Ok(())
    }

    fn skip_line(&mut self, loc: Loc, pos: SourcePos) -> Result<(), Problem> {
        let Some(skip) = self.flow.skip.clone() else {
            return Ok(());
        };
        let peek = self.reader.peek(&self.line);
        if let Peek::N(n) = peek {
            self.flow.labels.entry((loc.file, n.round() as i64)).or_insert(pos);
        }
        match (&skip, &peek) {
            (_, Peek::O { name, kind: OKind::Sub }) => {
                self.flow
                    .subs
                    .entry((loc.file, name.clone()))
                    .or_insert_with(|| self.files.last().map(|f| f.src.tell()).unwrap_or_default());
            }
            (_, Peek::O { name, kind: OKind::Label }) => {
                self.flow
                    .programs
                    .entry((loc.file, name.clone()))
                    .or_insert_with(|| self.files.last().map(|f| f.src.tell()).unwrap_or_default());
            }
            _ => {}
        }
        match (skip, peek) {
            (Skip::Sub(n), Peek::O { name, kind: OKind::EndSub }) if n == name => self.flow.skip = None,
            (Skip::IfFalse(n), Peek::O { name, kind }) if n == name => match kind {
                OKind::ElseIf => {
                    // Compute this condition now.
                    let view = View {
                        params: &self.params,
                        st: &self.st,
                        depth: self.flow.calls.len(),
                        outside: std::cell::Cell::new(false),
                    };
                    let cond =
                        self.reader.read(&self.line, &view)?.oword.as_ref().and_then(|o| o.args.first().copied());
                    if cond.unwrap_or(0.0) != 0.0 {
                        self.flow.skip = None;
                    }
                }
                OKind::Else => self.flow.skip = None,
                OKind::EndIf => {
                    self.flow.skip = None;
                    self.pop_ctl(&n);
                }
                _ => {}
            },
            (Skip::ToEndIf(n), Peek::O { name, kind: OKind::EndIf }) if n == name => {
                self.flow.skip = None;
                self.pop_ctl(&n);
            }
            (Skip::LoopEnd(n, k), Peek::O { name, kind }) if n == name => {
                let end = match k {
                    LoopKind::While => kind == OKind::EndWhile,
                    LoopKind::Repeat => kind == OKind::EndRepeat,
                    LoopKind::Do => kind == OKind::While,
                };
                if end {
                    self.flow.skip = None;
                    self.pop_ctl(&n);
                }
            }
            (Skip::FanucEnd(id), Peek::End { id: e }) if id == e => {
                self.flow.skip = None;
                self.pop_fanuc(id);
            }
            _ => {}
        }
        Ok(())
    }

    fn pop_ctl(&mut self, name: &str) {
        if let Some(i) =
            self.flow.ctl.iter().rposition(|c| c.name == name && !matches!(c.kind, CtlKind::FanucLoop { .. }))
        {
            self.flow.ctl.truncate(i);
        }
    }

    fn pop_fanuc(&mut self, id: u32) {
        if let Some(i) =
            self.flow.ctl.iter().rposition(|c| matches!(c.kind, CtlKind::FanucLoop { id: j, .. } if j == id))
        {
            self.flow.ctl.truncate(i);
        }
    }

    fn push_ctl(&mut self, name: String, kind: CtlKind, line: u32) -> Result<(), Problem> {
        if self.flow.ctl.len() >= MAX_CONTROL_DEPTH {
            return Err(Problem::Cap(format!(
                "more than {MAX_CONTROL_DEPTH} if/while/repeat levels open at once; close them (endif, endwhile, endrepeat)"
            )));
        }
        self.flow.ctl.push(Ctl { name, kind, line, depth: self.flow.calls.len() });
        Ok(())
    }

    /// The innermost open construct of this call with the label.
    fn find_ctl(&self, name: &str) -> Option<usize> {
        let depth = self.flow.calls.len();
        self.flow
            .ctl
            .iter()
            .rposition(|c| c.depth == depth && c.name == name && !matches!(c.kind, CtlKind::FanucLoop { .. }))
    }

    fn oword(&mut self, loc: Loc, pos: SourcePos, o: super::read::OWord) -> Result<(), Problem> {
        let cond = o.args.first().copied().unwrap_or(0.0);
        let name = o.name;
        match o.kind {
            OKind::Sub => {
                let body = self.tell();
                self.flow.subs.entry((loc.file, name.clone())).or_insert(body);
                self.flow.skip = Some(Skip::Sub(name));
            }
            OKind::EndSub | OKind::Return => {
                if self.flow.calls.last().is_none_or(|c| c.fanuc) {
                    if o.kind == OKind::Return {
                        return Err(Problem::Rule(format!("o{name} return outside a subroutine")));
                    }
                    // An endsub reached in the main flow without a call: LinuxCNC refuses.
                    return Err(Problem::Rule(format!(
                        "o{name} endsub without a call; subroutines are entered by o{name} call"
                    )));
                }
                if let Some(v) = o.args.first() {
                    self.params.set_named("_value", *v)?;
                    self.params.set_named("_value_returned", 1.0)?;
                } else {
                    self.params.set_named("_value_returned", 0.0)?;
                }
                self.return_from_call()?;
            }
            OKind::Call => self.call(&name, &o.args, 0, false)?,
            OKind::If => {
                self.push_ctl(name.clone(), CtlKind::If, loc.line)?;
                if cond == 0.0 {
                    self.flow.skip = Some(Skip::IfFalse(name));
                }
            }
            OKind::ElseIf | OKind::Else => {
                // Reached at the end of the taken branch.
                if self.find_ctl(&name).is_none() {
                    return Err(Problem::Rule(format!("o{name} else/elseif without its if")));
                }
                self.flow.skip = Some(Skip::ToEndIf(name));
            }
            OKind::EndIf => {
                if self.find_ctl(&name).is_none() {
                    return Err(Problem::Rule(format!("o{name} endif without its if")));
                }
                self.pop_ctl(&name);
            }
            OKind::Do => {
                let top = self.find_ctl(&name).map(|i| &self.flow.ctl[i].kind);
                if !matches!(top, Some(CtlKind::Do { start }) if *start == pos) {
                    self.push_ctl(name, CtlKind::Do { start: pos }, loc.line)?;
                }
            }
            OKind::While => {
                let open = self.find_ctl(&name).map(|i| self.flow.ctl[i].kind.clone());
                match open {
                    Some(CtlKind::Do { start }) => {
                        // The closing `while` of a do-while loop.
                        if cond != 0.0 {
                            self.seek(start)?;
                        } else {
                            self.pop_ctl(&name);
                        }
                    }
                    Some(CtlKind::While { start }) if start == pos => {
                        if cond == 0.0 {
                            self.flow.skip = Some(Skip::LoopEnd(name, LoopKind::While));
                        }
                    }
                    _ => {
                        if cond != 0.0 {
                            self.push_ctl(name, CtlKind::While { start: pos }, loc.line)?;
                        } else {
                            self.push_ctl(name.clone(), CtlKind::While { start: pos }, loc.line)?;
                            self.flow.skip = Some(Skip::LoopEnd(name, LoopKind::While));
                        }
                    }
                }
            }
            OKind::EndWhile => match self.find_ctl(&name).map(|i| self.flow.ctl[i].kind.clone()) {
                Some(CtlKind::While { start }) => self.seek(start)?,
                _ => return Err(Problem::Rule(format!("o{name} endwhile without its while"))),
            },
            OKind::Repeat => {
                let n = cond.round();
                let body = self.tell();
                if n >= 1.0 {
                    self.push_ctl(name, CtlKind::Repeat { body, left: (n as u64).saturating_sub(1) }, loc.line)?;
                } else {
                    self.push_ctl(name.clone(), CtlKind::Repeat { body, left: 0 }, loc.line)?;
                    self.flow.skip = Some(Skip::LoopEnd(name, LoopKind::Repeat));
                }
            }
            OKind::EndRepeat => self.end_repeat(&name)?,
            OKind::Break => {
                let kind = match self.find_ctl(&name).map(|i| self.flow.ctl[i].kind.clone()) {
                    Some(CtlKind::While { .. }) => LoopKind::While,
                    Some(CtlKind::Do { .. }) => LoopKind::Do,
                    Some(CtlKind::Repeat { .. }) => LoopKind::Repeat,
                    _ => return Err(Problem::Rule(format!("o{name} break outside its loop"))),
                };
                self.flow.skip = Some(Skip::LoopEnd(name, kind));
            }
            OKind::Continue => match self.find_ctl(&name).map(|i| self.flow.ctl[i].kind.clone()) {
                Some(CtlKind::While { start } | CtlKind::Do { start }) => self.seek(start)?,
                Some(CtlKind::Repeat { .. }) => self.end_repeat(&name)?,
                _ => return Err(Problem::Rule(format!("o{name} continue outside its loop"))),
            },
            OKind::Label => {
                // A FANUC program number: the start of this program or of a subprogram met
                // in the main flow after the end (not reached: M30 ends the program first).
                let body = self.tell();
                self.flow.programs.entry((loc.file, name)).or_insert(body);
            }
        }
        Ok(())
    }

    fn end_repeat(&mut self, name: &str) -> Result<(), Problem> {
        let Some(i) = self.find_ctl(name) else {
            return Err(Problem::Rule(format!("o{name} endrepeat without its repeat")));
        };
        match &mut self.flow.ctl[i].kind {
            CtlKind::Repeat { body, left } if *left > 0 => {
                *left -= 1;
                let b = *body;
                self.seek(b)?;
            }
            CtlKind::Repeat { .. } => self.pop_ctl(name),
            _ => return Err(Problem::Rule(format!("o{name} endrepeat without its repeat"))),
        }
        Ok(())
    }

    /// Scans the current file for a line matching `want`, from here to the end and then from
    /// the start; returns the position after the line. The read position is restored.
    fn scan_for(&mut self, want: &dyn Fn(&Peek) -> bool) -> Result<Option<SourcePos>, Problem> {
        let here = self.tell();
        let fid = self.file_id();
        let mut found = None;
        for pass in 0..2 {
            if pass == 1 {
                self.seek(SourcePos { offset: 0, line: 1 })?;
            }
            while let Some(f) = self.files.last_mut() {
                let Some(at) = f.src.next_line(&mut self.line)? else { break };
                if pass == 1 && at.offset >= here.offset {
                    break;
                }
                self.executed += 1;
                let cap = self.opts.max_lines.unwrap_or(super::MAX_EXECUTED_LINES);
                if self.executed > cap {
                    return Err(Problem::Cap(format!("more than {cap} lines read while looking for a subroutine")));
                }
                let peek = self.reader.peek(&self.line);
                let after = self.tell();
                match &peek {
                    Peek::O { name, kind: OKind::Sub } => {
                        self.flow.subs.entry((fid, name.clone())).or_insert(after);
                    }
                    Peek::O { name, kind: OKind::Label } => {
                        self.flow.programs.entry((fid, name.clone())).or_insert(after);
                    }
                    Peek::N(n) => {
                        self.flow.labels.entry((fid, n.round() as i64)).or_insert(at);
                    }
                    _ => {}
                }
                if want(&peek) {
                    found = Some(if matches!(peek, Peek::N(_)) { at } else { after });
                    break;
                }
            }
            if found.is_some() {
                break;
            }
        }
        self.seek(here)?;
        Ok(found)
    }

    /// Calls subroutine `name` (O-word sub, or FANUC program number with `fanuc`).
    fn call(&mut self, name: &str, args: &[f64], repeats: u64, fanuc: bool) -> Result<(), Problem> {
        if self.flow.calls.len() >= MAX_CALL_DEPTH {
            return Err(Problem::Cap(format!(
                "calls nested more than {MAX_CALL_DEPTH} deep; a subroutine calls itself without end?"
            )));
        }
        let file = self.file_id();
        let key = (file, name.to_owned());
        let known = if fanuc { self.flow.programs.get(&key) } else { self.flow.subs.get(&key) }.copied();
        let found = match known {
            Some(p) => Some(p),
            None => {
                let n = name.to_owned();
                if fanuc {
                    self.scan_for(&|p| matches!(p, Peek::O { name, kind: OKind::Label } if *name == n))?
                } else {
                    self.scan_for(&|p| matches!(p, Peek::O { name, kind: OKind::Sub } if *name == n))?
                }
            }
        };
        let back = self.tell();
        let files = self.files.len();
        let body = if let Some(body) = found {
            body
        } else {
            // A file of its own: `name.ngc` (LinuxCNC) or `O1234` (FANUC).
            let candidates: Vec<String> = if fanuc {
                vec![format!("o{name}"), format!("o{name:0>4}"), name.to_owned()]
            } else {
                vec![name.to_owned()]
            };
            let mut opened = None;
            for c in &candidates {
                if let Some(src) = self.library.open(c) {
                    opened = Some((c.clone(), src));
                    break;
                }
            }
            let Some((fname, src)) = opened else {
                let what = if fanuc {
                    format!("program O{name} is neither in this file nor a file of its own (O{name}.nc); add it")
                } else {
                    format!(
                        "subroutine o<{name}> is not defined in this file and there is no file {name}.ngc beside it; give its file"
                    )
                };
                return Err(Problem::Rule(what));
            };
            let id = match self.names.iter().position(|n| *n == fname) {
                Some(i) => u16::try_from(i).unwrap_or(u16::MAX),
                None => {
                    self.names.push(fname);
                    u16::try_from(self.names.len() - 1).unwrap_or(u16::MAX)
                }
            };
            self.files.push(Open { id, src });
            let n = name.to_owned();
            let found = if fanuc {
                self.scan_for(&|p| matches!(p, Peek::O { name, kind: OKind::Label } if *name == n))?
            } else {
                self.scan_for(&|p| matches!(p, Peek::O { name, kind: OKind::Sub } if *name == n))?
            };
            // A FANUC program file may hold the program without its O number.
            match found {
                Some(b) => b,
                None if fanuc => SourcePos { offset: 0, line: 1 },
                None => {
                    self.files.pop();
                    return Err(Problem::Rule(format!("the file {name}.ngc does not define o<{name}> sub")));
                }
            }
        };
        self.flow.calls.push(Call { files, back, body, repeats, ctl: self.flow.ctl.len(), fanuc });
        self.params.push_frame(args);
        self.seek(body)
    }

    fn return_from_call(&mut self) -> Result<(), Problem> {
        let Some(call) = self.flow.calls.last_mut() else {
            return Ok(());
        };
        if call.repeats > 0 {
            call.repeats -= 1;
            let body = call.body;
            let ctl = call.ctl;
            self.flow.ctl.truncate(ctl);
            return self.seek(body);
        }
        let Some(call) = self.flow.calls.pop() else {
            return Ok(());
        };
        self.params.pop_frame();
        self.flow.ctl.truncate(call.ctl);
        self.files.truncate(call.files);
        self.seek(call.back)
    }

    fn m98(&mut self, loc: Loc, block: &super::read::Block) -> Result<(), Problem> {
        let Some(p) = block.get(b'p') else {
            return Err(Problem::Rule("M98 needs P, the number of the program to call".into()));
        };
        let p = p.round() as i64;
        let (program, mut repeats) = match block.get(b'l').or(block.get(b'k')) {
            Some(l) => (p, l.round().max(1.0) as u64),
            // P with more than four digits: the first ones are the repeat count (P31234: O1234
            // three times).
            None if p >= 10_000 => (p % 10_000, ((p / 10_000).max(1)) as u64),
            None => (p, 1),
        };
        if repeats > super::MAX_EXECUTED_LINES {
            repeats = super::MAX_EXECUTED_LINES;
        }
        // Other words of the block run first (FANUC executes the block, then calls).
        let mut rest = block.clone();
        rest.m.retain(|&m| m != 98);
        rest.remove(b'p');
        rest.remove(b'l');
        if !rest.is_empty() {
            super::exec::block(self, loc, &mut rest)?;
        }
        self.call(&program.to_string(), &[], repeats - 1, true)
    }

    fn m99(&mut self, loc: Loc, block: &super::read::Block) -> Result<(), Problem> {
        let mut rest = block.clone();
        rest.m.retain(|&m| m != 99);
        let target = rest.remove(b'p');
        if !rest.is_empty() {
            super::exec::block(self, loc, &mut rest)?;
        }
        if !self.flow.calls.last().is_some_and(|c| c.fanuc) {
            // M99 in the main program: a FANUC control starts it again, forever.
            self.report("M99", loc, "M99 in the main program repeats it without end on a FANUC; read once");
            self.finish(loc)?;
            self.done = true;
            return Ok(());
        }
        if let Some(n) = target {
            // M99 P n: return to the caller's block N n.
            let Some(call) = self.flow.calls.pop() else { return Ok(()) };
            self.params.pop_frame();
            self.flow.ctl.truncate(call.ctl);
            self.files.truncate(call.files);
            self.seek(call.back)?;
            return self.goto(loc, n);
        }
        self.return_from_call()
    }

    fn g65(&mut self, block: &super::read::Block) -> Result<(), Problem> {
        let Some(p) = block.get(b'p') else {
            return Err(Problem::Rule("G65 needs P, the number of the macro program to call".into()));
        };
        let repeats = block.get(b'l').map_or(1, |l| l.round().max(1.0) as u64);
        let mut args = [0.0; super::params::CALL_ARGS];
        for (letter, n) in G65_ARGS {
            if let Some(v) = block.get(letter) {
                args[n - 1] = v;
            }
        }
        // Arguments not given are vacant on a FANUC; here they read as 0.
        self.call(&(p.round() as i64).to_string(), &args, repeats - 1, true)
    }

    fn goto(&mut self, loc: Loc, target: f64) -> Result<(), Problem> {
        let n = target.round() as i64;
        let key = (self.file_id(), n);
        let pos = match self.flow.labels.get(&key) {
            Some(p) => *p,
            None => match self.scan_for(&|p| matches!(p, Peek::N(m) if m.round() as i64 == n))? {
                Some(p) => p,
                None => return Err(Problem::Rule(format!("GOTO {n}: no block N{n} in this program"))),
            },
        };
        // Loops left by the jump are closed when their lines are met again.
        let depth = self.flow.calls.len();
        self.flow.ctl.retain(|c| {
            c.depth != depth || !matches!(c.kind, CtlKind::FanucLoop { .. }) || c.line < loc.line.min(pos.line)
        });
        self.seek(pos)
    }

    fn fanuc_flow(&mut self, loc: Loc, pos: SourcePos, f: FanucFlow) -> Result<(), Problem> {
        match f {
            FanucFlow::Goto { target, cond } => {
                if cond.is_none_or(|c| c != 0.0) {
                    self.goto(loc, target)?;
                }
            }
            FanucFlow::IfThen => {}
            FanucFlow::While { cond, id } => self.fanuc_loop(loc, pos, cond, id)?,
            FanucFlow::Do { id } => self.fanuc_loop(loc, pos, 1.0, id)?,
            FanucFlow::End { id } => {
                let open =
                    self.flow.ctl.iter().rposition(|c| matches!(c.kind, CtlKind::FanucLoop { id: j, .. } if j == id));
                match open.map(|i| self.flow.ctl[i].kind.clone()) {
                    Some(CtlKind::FanucLoop { start, .. }) => self.seek(start)?,
                    _ => return Err(Problem::Rule(format!("END{id} without its DO{id}"))),
                }
            }
        }
        Ok(())
    }

    /// `WHILE [c] DO m` (or `DO m`): enter the loop, or skip to `END m`.
    fn fanuc_loop(&mut self, loc: Loc, pos: SourcePos, cond: f64, id: u32) -> Result<(), Problem> {
        let open = self
            .flow
            .ctl
            .iter()
            .rposition(|c| matches!(c.kind, CtlKind::FanucLoop { id: j, start } if j == id && start == pos));
        if open.is_none() {
            self.push_ctl(format!("DO{id}"), CtlKind::FanucLoop { id, start: pos }, loc.line)?;
        }
        if cond == 0.0 {
            self.flow.skip = Some(Skip::FanucEnd(id));
        }
        Ok(())
    }
}
