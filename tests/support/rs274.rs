//! LinuxCNC's own interpreter as the reference: runs Debian's standalone `rs274` on a program,
//! reads the canonical calls it prints, brings every position into our convention (machine
//! frame, mm, see `interpolab::gcode::interp::canon`) and compares them with ours.
//!
//! What `rs274 -g FILE` prints (LinuxCNC 2.9, `src/emc/sai/saicanon.cc`), as found by running it:
//!
//! - one call a line, `%5d ` (its own call counter) then the program's `N` word of the line being
//!   executed (`N..... ` when the line has none) then `NAME(args)`; numbers with 4 decimals;
//! - positions in **program coordinates** (before G92/G52, XY rotation and G54…G59.3) and in
//!   the **units in force** (G20: inch); the offsets come as separate calls, also in the units in
//!   force at the time they are printed. We convert every length to mm when the call arrives,
//!   as LinuxCNC's canonical layer does (`FROM_PROG_LEN`), so a later G20/G21 leaves it alone;
//! - `ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end, a, b, c)`
//!   with (first, second, axis) = (X, Y, Z) in G17, (Z, X, Y) in G18, (Y, Z, X) in G19;
//!   `rotation` is LinuxCNC's signed turn count (G2 negative in every plane);
//! - a move to the current position **is** printed (`G1` with no change, `G0` likewise);
//! - `NURBS_FEED(n, ...)`: only the number of control points (G5: 4, G5.1: 3, G5.2: the given
//!   points plus the start), neither the points nor the end;
//! - in G93 (inverse time) a per-minute `SET_FEED_RATE` before every move, computed as
//!   `max(0.1, length·F)` in program units, with `SET_FEED_MODE(0, 0)`; G95 is mode 1;
//! - a tool table's lengths are read as **inches** (this `rs274` reports its machine in inches);
//! - on an error: exit status 1, standard error `executing`, the message, the text of the line.
//!
//! So that every call names its source line, the program is run as a copy in which each line
//! starts with `N<LINE_BASE + line>` (an existing leading `N` word is replaced; `%` lines, blank
//! lines and lines too long to grow are left alone). LinuxCNC ignores `N` words, and
//! `tests/reference/rs274.rs` checks that numbering changes no call on LinuxCNC's samples.

use std::fmt::Write as _;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use glam::DVec3;
use interpolab::gcode::Plane;
use interpolab::gcode::interp::{Canon, FeedMode, Pose};

/// Added to a line number to make the `N` word of the numbered copy: a sub-program's own `N`
/// words (below it) are never taken for lines of the main program.
pub const LINE_BASE: u64 = 1_000_000_000;
/// LinuxCNC refuses lines of 255 characters or more; a line is numbered only if it stays shorter.
const MAX_NUMBERED_LINE: usize = 240;
/// mm per inch.
pub const MM_PER_INCH: f64 = 25.4;
/// Half a unit of `rs274`'s last printed decimal (it prints `%.4f`).
pub const PRINT_HALF_UNIT: f64 = 0.5e-4;
/// Added to every tolerance: floating-point noise of our own arithmetic.
pub const TOL_FLOOR: f64 = 1e-9;

/// How to run `rs274`.
#[derive(Clone, Debug)]
pub struct Rs274 {
    /// The program, `rs274` (found on PATH by default).
    pub program: PathBuf,
    /// A LinuxCNC tool table (`-t`); its lengths are read as inches. `None`: an empty table
    /// (never the sample configuration's table rs274 would otherwise load).
    pub tool_table: Option<PathBuf>,
    /// Directories searched for `o<name> call` files, in order (an INI file's
    /// `[RS274NGC] SUBROUTINE_PATH`). Without them `rs274` looks only in its working directory,
    /// which is an empty temporary directory here.
    pub subroutine_dirs: Vec<PathBuf>,
    /// Killed after this long.
    pub timeout: Duration,
    /// Killed when its standard output grows past this many bytes.
    pub max_output_bytes: u64,
    /// Address-space limit of the process (MiB).
    pub max_memory_mib: u64,
    /// Run a numbered copy so that every call names its line (see the module's notes).
    pub numbered: bool,
}

impl Default for Rs274 {
    fn default() -> Self {
        Self {
            program: PathBuf::from("rs274"),
            tool_table: None,
            subroutine_dirs: Vec::new(),
            timeout: Duration::from_secs(120),
            max_output_bytes: 1 << 30,
            max_memory_mib: 2048,
            numbered: true,
        }
    }
}

/// A pose with the bound on its rounding error: what `rs274` printed, normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefPose {
    /// Machine-frame position (mm) and rotary axes (degrees).
    pub pose: Pose,
    /// Bound on the error of `pose.xyz` from `rs274`'s 4 printed decimals (mm, per axis).
    pub tol_mm: f64,
    /// Bound on the error of `pose.abc` (degrees, per axis).
    pub tol_deg: f64,
}

/// The feed in force for a cutting move, as `rs274` gave it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefFeed {
    /// mm/min, or mm per revolution when `per_rev` (in G93 the per-minute rate LinuxCNC
    /// computed for this move).
    pub rate: f64,
    /// G95 (`SET_FEED_MODE(…, 1)`).
    pub per_rev: bool,
    /// Bound on the rounding error of `rate` (same unit).
    pub tol: f64,
    /// Program units were inches when the rate was given (for G93's 0.1-unit floor).
    pub inch: bool,
}

/// One canonical call of `rs274`, normalised.
#[derive(Clone, Debug, PartialEq)]
pub enum RefKind {
    /// `STRAIGHT_TRAVERSE`.
    Traverse { end: RefPose },
    /// `STRAIGHT_FEED`.
    Line { end: RefPose, feed: RefFeed },
    /// `ARC_FEED`. `center` is in the machine frame (mm); its coordinate along the plane's
    /// normal is the start's (NaN when the start is unknown, after a `NURBS_FEED`).
    Arc { end: RefPose, center: DVec3, plane: Plane, turns: i32, feed: RefFeed },
    /// `NURBS_FEED`: only the number of control points is printed.
    Nurbs { control_points: usize, feed: RefFeed },
    /// `STRAIGHT_PROBE` to its programmed end.
    Probe { end: RefPose },
    /// `RIGID_TAP` (G33.1) to its bottom (X Y Z only; the rotary axes stay).
    RigidTap { end: RefPose },
    /// `DWELL` (s).
    Dwell { seconds: f64 },
    /// `SELECT_TOOL` (T word).
    SelectTool { tool: i32 },
    /// `CHANGE_TOOL(index)` (M6): `index` is the tool's place in the tool table (1-based, in
    /// the file's order), `tool` the last selected tool.
    ChangeTool { index: i32, tool: i32 },
    /// `CHANGE_TOOL_NUMBER(index)` (M61 Q): `tool` is the number of the table's tool at that
    /// place (0 when it is 0 or not in the table).
    SetToolNumber { index: i32, tool: i32 },
    /// `USE_TOOL_LENGTH_OFFSET` (mm for X Y Z, degrees for A B C).
    ToolLengthOffset { offset: DVec3, abc: DVec3 },
    /// `SET_FEED_RATE`, in mm/min (mm/rev in G95).
    FeedRate { rate: f64 },
    /// `SET_FEED_MODE`: per revolution (G95) or per minute.
    FeedMode { per_rev: bool },
    /// The spindle after a `SET_SPINDLE_SPEED`, `START_SPINDLE_…` or `STOP_SPINDLE_TURNING`:
    /// signed rev/min (positive clockwise, zero stopped).
    Spindle { rpm: f64 },
    /// `USE_LENGTH_UNITS`.
    Units { inch: bool },
    /// `SET_G5X_OFFSET` (1 = G54 … 9 = G59.3), mm and degrees.
    G5xOffset { index: i32, offset: Pose },
    /// `SET_G92_OFFSET` (G92 and G52), mm and degrees.
    G92Offset { offset: Pose },
    /// `SET_XY_ROTATION` (degrees, counter-clockwise).
    XyRotation { degrees: f64 },
    /// `SELECT_PLANE`.
    Plane { plane: Plane },
    /// `PROGRAM_STOP`/`OPTIONAL_PROGRAM_STOP` (`end: false`), `PROGRAM_END`/`FINISH` (`end: true`).
    Stop { end: bool },
}

/// One call and where it comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct RefCall {
    /// `rs274`'s own counter of the call (first column of its output).
    pub seq: u32,
    /// The line of the main program being executed (numbered runs; `None` in a subroutine file
    /// or when not numbered).
    pub line: Option<u32>,
    /// What.
    pub kind: RefKind,
}

/// Where and why `rs274` stopped before the program's end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RefError {
    /// The line of the main program it was executing (numbered runs), else `None`.
    pub line: Option<u32>,
    /// LinuxCNC's message.
    pub text: String,
    /// The text of that line as `rs274` echoed it (our `N` prefix removed).
    pub source: String,
}

/// Everything one run gave.
#[derive(Clone, Debug, Default)]
pub struct RefRun {
    /// The calls that matter, in order.
    pub calls: Vec<RefCall>,
    /// Set when `rs274` stopped on an error.
    pub error: Option<RefError>,
    /// Lines of its standard output in the form of a call that could not be read (normally
    /// none: a sign that the parser misses something).
    pub unparsed: Vec<String>,
    /// Other lines of its standard output: the text of `(PRINT, …)` comments.
    pub printed: Vec<String>,
}

impl RefRun {
    /// The motions only.
    pub fn motions(&self) -> impl Iterator<Item = &RefCall> {
        self.calls.iter().filter(|c| c.kind.is_motion())
    }
}

impl RefKind {
    /// A call that moves the machine.
    pub fn is_motion(&self) -> bool {
        matches!(
            self,
            Self::Traverse { .. }
                | Self::Line { .. }
                | Self::Arc { .. }
                | Self::Nurbs { .. }
                | Self::Probe { .. }
                | Self::RigidTap { .. }
        )
    }
}

/// Is `rs274` here? (`scripts/setup.sh test` installs it.)
pub fn available() -> bool {
    Command::new("rs274").arg("-h").stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok()
}

/// Fails the calling test with the fix when `rs274` is missing.
pub fn require() {
    assert!(
        available(),
        "LinuxCNC's `rs274` is not installed: run `scripts/setup.sh test` (Debian package linuxcnc-uspace)"
    );
}

static RUN_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary directory removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Result<Self, String> {
        let n = RUN_COUNTER.fetch_add(1, Ordering::Relaxed);
        let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        let dir = std::env::temp_dir().join(format!("interpolab-rs274-{}-{n}-{nanos}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        Ok(Self(dir))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl Rs274 {
    /// Runs `rs274` on a program file.
    ///
    /// # Errors
    /// When it cannot be run, runs out of time or output: a message saying which. An error
    /// *in the program* is not an `Err`: it is [`RefRun::error`].
    pub fn run(&self, program: &Path) -> Result<RefRun, String> {
        let text = std::fs::read(program).map_err(|e| format!("cannot read {}: {e}", program.display()))?;
        self.run_bytes(&text, program.file_name().and_then(|n| n.to_str()).unwrap_or("program.ngc"))
    }

    /// Runs `rs274` on program text.
    ///
    /// # Errors
    /// As [`Rs274::run`].
    pub fn run_text(&self, text: &str) -> Result<RefRun, String> {
        self.run_bytes(text.as_bytes(), "program.ngc")
    }

    fn run_bytes(&self, text: &[u8], name: &str) -> Result<RefRun, String> {
        let tmp = TempDir::new()?;
        let file = tmp.0.join(name);
        let body = if self.numbered { number_lines(text) } else { text.to_vec() };
        std::fs::write(&file, body).map_err(|e| format!("cannot write {}: {e}", file.display()))?;
        let table = match &self.tool_table {
            Some(t) => t.clone(),
            None => {
                let t = tmp.0.join("empty.tbl");
                std::fs::write(&t, "").map_err(|e| format!("cannot write {}: {e}", t.display()))?;
                t
            }
        };
        let mut args: Vec<String> =
            vec!["-t".into(), path_arg(&table)?, "-v".into(), path_arg(&tmp.0.join("rs274.var"))?];
        if !self.subroutine_dirs.is_empty() {
            let mut dirs = Vec::new();
            for d in &self.subroutine_dirs {
                let abs = std::fs::canonicalize(d).map_err(|e| format!("subroutine directory {}: {e}", d.display()))?;
                dirs.push(path_arg(&abs)?);
            }
            let ini = tmp.0.join("rs274.ini");
            std::fs::write(&ini, format!("[RS274NGC]\nSUBROUTINE_PATH = {}\n", dirs.join(":")))
                .map_err(|e| format!("cannot write {}: {e}", ini.display()))?;
            args.push("-i".into());
            args.push(path_arg(&ini)?);
        }
        args.push("-g".into());
        args.push(path_arg(&file)?);
        // The address-space limit through the shell, so no libc binding is needed.
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -v {} && exec \"$0\" \"$@\"", self.max_memory_mib * 1024))
            .arg(&self.program)
            .args(&args)
            .current_dir(&tmp.0)
            // Its tool data goes to $HOME/.tool.mmap: one per run, so that runs in parallel
            // (and a LinuxCNC on this machine) never share it.
            .env("HOME", &tmp.0)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", self.program.display()))?;
        let stdout = child.stdout.take().ok_or("no standard output")?;
        let mut stderr = child.stderr.take().ok_or("no standard error")?;
        let child = Arc::new(Mutex::new(child));
        let done = Arc::new(AtomicBool::new(false));
        let timed_out = Arc::new(AtomicBool::new(false));
        let watchdog = {
            let (child, done, timed_out, timeout) =
                (Arc::clone(&child), Arc::clone(&done), Arc::clone(&timed_out), self.timeout);
            thread::spawn(move || {
                let start = Instant::now();
                while !done.load(Ordering::Relaxed) {
                    if start.elapsed() > timeout {
                        timed_out.store(true, Ordering::Relaxed);
                        if let Ok(mut c) = child.lock() {
                            let _ = c.kill();
                        }
                        return;
                    }
                    thread::sleep(Duration::from_millis(20));
                }
            })
        };
        let err_reader = thread::spawn(move || {
            let mut buf = Vec::new();
            let _ = (&mut stderr).take(1 << 20).read_to_end(&mut buf);
            // Drain the rest so rs274 never blocks on a full pipe.
            let _ = std::io::copy(&mut stderr, &mut std::io::sink());
            buf
        });
        let tools = match &self.tool_table {
            Some(t) => {
                tool_numbers(&std::fs::read_to_string(t).map_err(|e| format!("cannot read {}: {e}", t.display()))?)
            }
            None => Vec::new(),
        };
        let mut parser = Parser::new(tools);
        let mut reader = BufReader::new(stdout);
        let mut line = String::new();
        let mut bytes = 0u64;
        let mut too_much = false;
        loop {
            line.clear();
            match reader.read_line(&mut line) {
                Ok(0) => break,
                Ok(n) => {
                    bytes += n as u64;
                    if bytes > self.max_output_bytes {
                        too_much = true;
                        if let Ok(mut c) = child.lock() {
                            let _ = c.kill();
                        }
                        break;
                    }
                    parser.line(line.trim_end_matches(['\n', '\r']));
                }
                Err(e) => return Err(format!("reading rs274's output: {e}")),
            }
        }
        // Drain what is left after a kill so the pipe closes.
        let _ = std::io::copy(&mut reader, &mut std::io::sink());
        done.store(true, Ordering::Relaxed);
        let _ = watchdog.join();
        let status = child
            .lock()
            .map_err(|_| "rs274's handle was poisoned")?
            .wait()
            .map_err(|e| format!("waiting for rs274: {e}"))?;
        let err = err_reader.join().map_err(|_| "the standard-error reader panicked")?;
        if timed_out.load(Ordering::Relaxed) {
            return Err(format!("rs274 took more than {} s", self.timeout.as_secs_f64()));
        }
        if too_much {
            return Err(format!("rs274 printed more than {} bytes", self.max_output_bytes));
        }
        let mut run = parser.finish();
        if !status.success() {
            let err = String::from_utf8_lossy(&err);
            run.error = Some(parse_error(&err, status.code()));
        }
        Ok(run)
    }
}

fn path_arg(p: &Path) -> Result<String, String> {
    p.to_str().map(str::to_owned).ok_or_else(|| format!("path {} is not UTF-8", p.display()))
}

/// The numbered copy of a program: each line that can carry one starts with
/// `N<LINE_BASE + line>` (after a leading `/`), replacing a leading `N` word.
pub fn number_lines(text: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len() + text.len() / 4);
    for (i, raw) in text.split_inclusive(|&b| b == b'\n').enumerate() {
        let content_end = raw.iter().rposition(|&b| b != b'\n' && b != b'\r').map_or(0, |p| p + 1);
        let content = &raw[..content_end];
        let lead = content.iter().take_while(|&&b| b == b' ' || b == b'\t').count();
        let rest = &content[lead..];
        let numberable = !rest.is_empty() && rest[0] != b'%' && content.len() + 12 <= MAX_NUMBERED_LINE;
        if !numberable {
            out.extend_from_slice(raw);
            continue;
        }
        let (slash, body) = if rest[0] == b'/' { (&rest[..1], &rest[1..]) } else { (&rest[..0], rest) };
        let body = strip_line_number(body);
        out.extend_from_slice(&content[..lead]);
        out.extend_from_slice(slash);
        out.extend_from_slice(format!("N{} ", LINE_BASE + i as u64 + 1).as_bytes());
        out.extend_from_slice(body);
        out.extend_from_slice(&raw[content_end..]);
    }
    out
}

/// `body` without a leading `N` word (`N`, blanks, digits, an optional `.digits`).
fn strip_line_number(body: &[u8]) -> &[u8] {
    if body.first().is_none_or(|&b| b != b'N' && b != b'n') {
        return body;
    }
    let mut i = 1;
    let skip_blank = |i: &mut usize| {
        while *i < body.len() && (body[*i] == b' ' || body[*i] == b'\t') {
            *i += 1;
        }
    };
    skip_blank(&mut i);
    let digits_start = i;
    while i < body.len() && body[i].is_ascii_digit() {
        i += 1;
    }
    if i == digits_start {
        return body; // not a line number: leave it for LinuxCNC to judge
    }
    if i < body.len() && body[i] == b'.' {
        i += 1;
        while i < body.len() && body[i].is_ascii_digit() {
            i += 1;
        }
    }
    &body[i..]
}

/// The `N` value of an echoed line (`N1000000012 G1 …` → 12), and the line without it.
fn split_numbered(text: &str) -> (Option<u32>, String) {
    let t = text.trim_start_matches([' ', '\t']);
    let (slash, t2) = t.strip_prefix('/').map_or(("", t), |r| ("/", r));
    if let Some(r) = t2.strip_prefix(['N', 'n']) {
        let digits: String = r.chars().take_while(char::is_ascii_digit).collect();
        if let Ok(v) = digits.parse::<u64>()
            && v > LINE_BASE
        {
            let rest = r[digits.len()..].strip_prefix(' ').unwrap_or(&r[digits.len()..]);
            return (u32::try_from(v - LINE_BASE).ok(), format!("{slash}{rest}"));
        }
    }
    (None, text.to_owned())
}

fn parse_error(stderr: &str, code: Option<i32>) -> RefError {
    let lines: Vec<&str> = stderr.lines().filter(|l| *l != "executing").collect();
    match lines.as_slice() {
        [] => RefError {
            line: None,
            text: format!("rs274 exited with status {code:?} and no message"),
            source: String::new(),
        },
        [only] => RefError { line: None, text: (*only).to_owned(), source: String::new() },
        [.., text, src] => {
            let (line, source) = split_numbered(src);
            RefError { line, text: (*text).to_owned(), source }
        }
    }
}

/// The normalising state: what LinuxCNC's canonical layer keeps.
struct Parser {
    calls: Vec<RefCall>,
    unparsed: Vec<String>,
    printed: Vec<String>,
    inch: bool,
    g5x: [f64; 6],
    g92: [f64; 6],
    rotation_deg: f64,
    plane: Plane,
    feed_rate: f64,
    feed_inch: bool,
    per_rev: bool,
    speed: f64,
    direction: f64,
    selected_tool: i32,
    /// The tool table's tool numbers in the file's order (rs274 names tools by their place).
    tools: Vec<i32>,
    /// Rounding bounds of the offsets in force (mm), from the units they were printed in.
    g5x_tol: f64,
    g92_tol: f64,
    /// Where the machine is (mm, degrees), as far as the output tells.
    current: [f64; 6],
}

impl Parser {
    fn new(tools: Vec<i32>) -> Self {
        Self {
            tools,
            calls: Vec::new(),
            unparsed: Vec::new(),
            printed: Vec::new(),
            inch: false,
            g5x: [0.0; 6],
            g92: [0.0; 6],
            rotation_deg: 0.0,
            plane: Plane::Xy,
            feed_rate: 0.0,
            feed_inch: false,
            per_rev: false,
            speed: 0.0,
            direction: 0.0,
            selected_tool: 0,
            g5x_tol: PRINT_HALF_UNIT,
            g92_tol: PRINT_HALF_UNIT,
            current: [0.0; 6],
        }
    }

    fn finish(self) -> RefRun {
        RefRun { calls: self.calls, error: None, unparsed: self.unparsed, printed: self.printed }
    }

    fn unit(&self) -> f64 {
        if self.inch { MM_PER_INCH } else { 1.0 }
    }

    /// Program coordinates (units in force) → machine frame (mm), LinuxCNC's
    /// `rotate_and_offset_pos`: `rotate_z(p + g92) + g5x`.
    fn to_machine(&self, p: [f64; 6]) -> RefPose {
        let u = self.unit();
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        let x = p[0] * u + self.g92[0];
        let y = p[1] * u + self.g92[1];
        let xyz =
            DVec3::new(x * c - y * s + self.g5x[0], x * s + y * c + self.g5x[1], p[2] * u + self.g92[2] + self.g5x[2]);
        let abc = DVec3::new(
            p[3] + self.g92[3] + self.g5x[3],
            p[4] + self.g92[4] + self.g5x[4],
            p[5] + self.g92[5] + self.g5x[5],
        );
        // Each printed number is off by up to half a unit of its last decimal: the position
        // and the G92 offset before the rotation (a vector of that length per axis pair, so √2
        // when rotated), the G5x offset after it; a rotation printed to 1e-4° turns the point
        // by up to that much more.
        let rotated = self.rotation_deg != 0.0;
        let before = (PRINT_HALF_UNIT * u + self.g92_tol) * if rotated { std::f64::consts::SQRT_2 } else { 1.0 };
        let turn = if rotated { x.hypot(y) * PRINT_HALF_UNIT.to_radians() } else { 0.0 };
        let tol_mm = before + self.g5x_tol + turn + TOL_FLOOR;
        RefPose { pose: Pose { xyz, abc }, tol_mm, tol_deg: 3.0 * PRINT_HALF_UNIT + TOL_FLOOR }
    }

    /// Machine frame → program coordinates (units in force), the inverse of `to_machine`.
    fn to_program(&self, m: [f64; 6]) -> [f64; 6] {
        let u = self.unit();
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        let (dx, dy) = (m[0] - self.g5x[0], m[1] - self.g5x[1]);
        let x = (dx * c + dy * s - self.g92[0]) / u;
        let y = (-dx * s + dy * c - self.g92[1]) / u;
        let z = (m[2] - self.g5x[2] - self.g92[2]) / u;
        [x, y, z, m[3] - self.g5x[3] - self.g92[3], m[4] - self.g5x[4] - self.g92[4], m[5] - self.g5x[5] - self.g92[5]]
    }

    fn feed(&self) -> RefFeed {
        let u = if self.feed_inch { MM_PER_INCH } else { 1.0 };
        RefFeed {
            rate: self.feed_rate,
            per_rev: self.per_rev,
            tol: PRINT_HALF_UNIT * u + TOL_FLOOR,
            inch: self.feed_inch,
        }
    }

    fn set_current(&mut self, end: &RefPose) {
        self.current = [end.pose.xyz.x, end.pose.xyz.y, end.pose.xyz.z, end.pose.abc.x, end.pose.abc.y, end.pose.abc.z];
    }

    fn push(&mut self, seq: u32, line: Option<u32>, kind: RefKind) {
        self.calls.push(RefCall { seq, line, kind });
    }

    fn spindle(&mut self, seq: u32, line: Option<u32>) {
        let rpm = self.direction * self.speed;
        self.push(seq, line, RefKind::Spindle { rpm });
    }

    fn line(&mut self, text: &str) {
        if self.try_line(text).is_none() {
            let t = text.trim_start();
            let call_like =
                t.find(|c: char| !c.is_ascii_digit()).is_some_and(|d| d > 0 && t[d..].trim_start().starts_with('N'));
            if call_like { self.unparsed.push(text.to_owned()) } else { self.printed.push(text.to_owned()) }
        }
    }

    fn try_line(&mut self, text: &str) -> Option<()> {
        let t = text.trim_start();
        let digits = t.find(|c: char| !c.is_ascii_digit())?;
        let seq: u32 = t[..digits].parse().ok()?;
        let t = t[digits..].trim_start().strip_prefix('N')?;
        let (line, t) = if let Some(r) = t.strip_prefix(".....") {
            (None, r)
        } else {
            let d = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
            let n: u64 = t[..d].parse().ok()?;
            let line = if n > LINE_BASE { u32::try_from(n - LINE_BASE).ok() } else { None };
            (line, &t[d..])
        };
        let t = t.trim_start();
        let open = t.find('(')?;
        let name = &t[..open];
        let args = t[open + 1..].strip_suffix(')')?;
        let nums = || -> Vec<f64> {
            args.split([',', ' ']).filter(|s| !s.is_empty()).filter_map(|s| s.parse::<f64>().ok()).collect()
        };
        match name {
            "USE_LENGTH_UNITS" => {
                self.inch = args == "CANON_UNITS_INCHES";
                let inch = self.inch;
                self.push(seq, line, RefKind::Units { inch });
            }
            "SET_G5X_OFFSET" => {
                let v = nums();
                let (index, o) = (*v.first()? as i32, six(v.get(1..)?)?);
                let u = self.unit();
                self.g5x = [o[0] * u, o[1] * u, o[2] * u, o[3], o[4], o[5]];
                self.g5x_tol = PRINT_HALF_UNIT * u;
                let offset = pose6(self.g5x);
                self.push(seq, line, RefKind::G5xOffset { index, offset });
            }
            "SET_G92_OFFSET" => {
                let o = six(&nums())?;
                let u = self.unit();
                self.g92 = [o[0] * u, o[1] * u, o[2] * u, o[3], o[4], o[5]];
                self.g92_tol = PRINT_HALF_UNIT * u;
                let offset = pose6(self.g92);
                self.push(seq, line, RefKind::G92Offset { offset });
            }
            "SET_XY_ROTATION" => {
                self.rotation_deg = *nums().first()?;
                let degrees = self.rotation_deg;
                self.push(seq, line, RefKind::XyRotation { degrees });
            }
            "SELECT_PLANE" => {
                self.plane = match args {
                    "CANON_PLANE_XY" => Plane::Xy,
                    "CANON_PLANE_XZ" => Plane::Zx,
                    "CANON_PLANE_YZ" => Plane::Yz,
                    _ => return None,
                };
                let plane = self.plane;
                self.push(seq, line, RefKind::Plane { plane });
            }
            "SET_FEED_RATE" => {
                self.feed_rate = *nums().first()? * self.unit();
                self.feed_inch = self.inch;
                let rate = self.feed_rate;
                self.push(seq, line, RefKind::FeedRate { rate });
            }
            "SET_FEED_MODE" => {
                let v = nums();
                self.per_rev = *v.get(1)? != 0.0;
                let per_rev = self.per_rev;
                self.push(seq, line, RefKind::FeedMode { per_rev });
            }
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" | "STRAIGHT_PROBE" => {
                let p = six(&nums())?;
                let end = self.to_machine(p);
                let kind = match name {
                    "STRAIGHT_TRAVERSE" => RefKind::Traverse { end },
                    "STRAIGHT_FEED" => RefKind::Line { end, feed: self.feed() },
                    _ => RefKind::Probe { end },
                };
                if name == "STRAIGHT_PROBE" {
                    // rs274 leaves the tool backed off 0.254 mm (0.01 in) from the probe
                    // point toward where it came from.
                    let from = self.to_program(self.current);
                    let d = DVec3::new(from[0] - p[0], from[1] - p[1], from[2] - p[2]);
                    let mut back = p;
                    if d.length() > 0.0 {
                        let step = d / d.length() * if self.inch { 0.01 } else { 0.254 };
                        back[0] += step.x;
                        back[1] += step.y;
                        back[2] += step.z;
                    }
                    let b = self.to_machine(back);
                    self.set_current(&b);
                } else {
                    self.set_current(&end);
                }
                self.push(seq, line, kind);
            }
            "ARC_FEED" => {
                let v = nums();
                if v.len() != 9 {
                    return None;
                }
                let (fe, se, fa, sa, rot, ae) = (v[0], v[1], v[2], v[3], v[4], v[5]);
                let start = self.to_program(self.current);
                let (end_p, center_p) = match self.plane {
                    Plane::Xy => ([fe, se, ae], [fa, sa, start[2]]),
                    Plane::Zx => ([se, ae, fe], [sa, start[1], fa]),
                    Plane::Yz => ([ae, fe, se], [start[0], fa, sa]),
                };
                let end = self.to_machine([end_p[0], end_p[1], end_p[2], v[6], v[7], v[8]]);
                let center = self.to_machine([center_p[0], center_p[1], center_p[2], 0.0, 0.0, 0.0]).pose.xyz;
                let kind = RefKind::Arc { end, center, plane: self.plane, turns: rot as i32, feed: self.feed() };
                self.set_current(&end);
                self.push(seq, line, kind);
            }
            "NURBS_FEED" => {
                let control_points: usize = args.split(',').next()?.trim().parse().ok()?;
                // Neither the points nor the end are printed: the start of what follows is
                // unknown in the plane (G5, G5.1 and G5.2 move X and Y only).
                self.current[0] = f64::NAN;
                self.current[1] = f64::NAN;
                let feed = self.feed();
                self.push(seq, line, RefKind::Nurbs { control_points, feed });
            }
            "RIGID_TAP" => {
                let v = nums();
                let cur = self.to_program(self.current);
                let end = self.to_machine([*v.first()?, *v.get(1)?, *v.get(2)?, cur[3], cur[4], cur[5]]);
                self.push(seq, line, RefKind::RigidTap { end });
            }
            "DWELL" => {
                let seconds = *nums().first()?;
                self.push(seq, line, RefKind::Dwell { seconds });
            }
            "SELECT_TOOL" => {
                self.selected_tool = *nums().first()? as i32;
                let tool = self.selected_tool;
                self.push(seq, line, RefKind::SelectTool { tool });
            }
            "CHANGE_TOOL" => {
                let index = *nums().first()? as i32;
                let tool = self.selected_tool;
                self.push(seq, line, RefKind::ChangeTool { index, tool });
            }
            "CHANGE_TOOL_NUMBER" => {
                let index = *nums().first()? as i32;
                let tool = usize::try_from(index - 1).ok().and_then(|i| self.tools.get(i)).copied().unwrap_or(0);
                self.push(seq, line, RefKind::SetToolNumber { index, tool });
            }
            "USE_TOOL_LENGTH_OFFSET" => {
                let v = nums();
                let u = self.unit();
                let offset = DVec3::new(*v.first()?, *v.get(1)?, *v.get(2)?) * u;
                let abc = DVec3::new(*v.get(3)?, *v.get(4)?, *v.get(5)?);
                self.push(seq, line, RefKind::ToolLengthOffset { offset, abc });
            }
            "SET_SPINDLE_SPEED" => {
                self.speed = *nums().get(1)?;
                self.spindle(seq, line);
            }
            "START_SPINDLE_CLOCKWISE" => {
                self.direction = 1.0;
                self.spindle(seq, line);
            }
            "START_SPINDLE_COUNTERCLOCKWISE" => {
                self.direction = -1.0;
                self.spindle(seq, line);
            }
            "STOP_SPINDLE_TURNING" => {
                self.direction = 0.0;
                self.spindle(seq, line);
            }
            "PROGRAM_STOP" | "OPTIONAL_PROGRAM_STOP" => self.push(seq, line, RefKind::Stop { end: false }),
            "PROGRAM_END" | "FINISH" => self.push(seq, line, RefKind::Stop { end: true }),
            // Every other call (comments, coolant, ON_RESET, …) is read and left out.
            _ => {}
        }
        Some(())
    }
}

fn six(v: &[f64]) -> Option<[f64; 6]> {
    Some([*v.first()?, *v.get(1)?, *v.get(2)?, *v.get(3)?, *v.get(4)?, *v.get(5)?])
}

fn pose6(v: [f64; 6]) -> Pose {
    Pose { xyz: DVec3::new(v[0], v[1], v[2]), abc: DVec3::new(v[3], v[4], v[5]) }
}

/// A LinuxCNC subroutine file rather than a program: its first line of code is
/// `o<name> sub` with the file's own name (how `o<name> call` finds it).
pub fn is_subroutine_file(path: &Path) -> bool {
    let (Some(stem), Ok(text)) = (path.file_stem().and_then(|s| s.to_str()), std::fs::read_to_string(path)) else {
        return false;
    };
    let first = text.lines().map(str::trim).find(|l| !l.is_empty() && !l.starts_with(';') && !l.starts_with('('));
    first.is_some_and(|l| {
        let l = l.to_ascii_lowercase().replace([' ', '\t'], "");
        l.starts_with(&format!("o<{}>sub", stem.to_ascii_lowercase()))
    })
}

/// The tool numbers of a LinuxCNC tool table, in the file's order (`T<n> P<p> … ;comment` a
/// line; blank and comment lines skipped).
pub fn tool_numbers(table: &str) -> Vec<i32> {
    table
        .lines()
        .filter_map(|l| {
            let t = l.trim_start();
            let rest = t.strip_prefix(['T', 't'])?;
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            digits.parse().ok()
        })
        .collect()
}

/// Parses `rs274`'s standard output and standard error (for tests of the parser itself).
pub fn parse_output(stdout: &str, stderr: &str, failed: bool, tools: Vec<i32>) -> RefRun {
    let mut p = Parser::new(tools);
    for l in stdout.lines() {
        p.line(l);
    }
    let mut run = p.finish();
    if failed {
        run.error = Some(parse_error(stderr, Some(1)));
    }
    run
}

// ---------------------------------------------------------------------------------------------
// Comparison

/// One comparable event, from either side.
#[derive(Clone, Debug)]
enum Event {
    Traverse { end: Pose },
    Line { end: Pose, rate: Option<(f64, bool)> },
    Arc { end: Pose, center: DVec3, plane: Plane, turns: i32, rate: Option<(f64, bool)> },
    Spline { control_points: usize },
    Probe { end: Pose },
    Dwell { seconds: f64 },
    ToolChange { tool: i32 },
    ToolLengthOffset { offset: DVec3 },
    Spindle { rpm: f64 },
    Stop { end: bool },
}

impl Event {
    fn name(&self) -> &'static str {
        match self {
            Self::Traverse { .. } => "traverse",
            Self::Line { .. } => "line",
            Self::Arc { .. } => "arc",
            Self::Spline { .. } => "spline",
            Self::Probe { .. } => "probe",
            Self::Dwell { .. } => "dwell",
            Self::ToolChange { .. } => "tool change",
            Self::ToolLengthOffset { .. } => "tool length offset",
            Self::Spindle { .. } => "spindle",
            Self::Stop { .. } => "stop",
        }
    }
}

struct Theirs {
    event: Event,
    at: String,
    tol_mm: f64,
    tol_deg: f64,
    feed_tol: f64,
    feed_inch: bool,
}

fn fmt_pose(p: &Pose) -> String {
    format!("X{:.6} Y{:.6} Z{:.6} A{:.6} B{:.6} C{:.6}", p.xyz.x, p.xyz.y, p.xyz.z, p.abc.x, p.abc.y, p.abc.z)
}

fn their_events(theirs: &[RefCall]) -> Vec<Theirs> {
    let mut out = Vec::new();
    let mut last_rpm = 0.0;
    for c in theirs {
        let at = match c.line {
            Some(l) => format!("rs274 call {} (line {l})", c.seq),
            None => format!("rs274 call {}", c.seq),
        };
        let mut push = |event, tol_mm, tol_deg, feed: Option<&RefFeed>| {
            out.push(Theirs {
                event,
                at: at.clone(),
                tol_mm,
                tol_deg,
                feed_tol: feed.map_or(0.0, |f| f.tol),
                feed_inch: feed.is_some_and(|f| f.inch),
            });
        };
        match &c.kind {
            RefKind::Traverse { end } => push(Event::Traverse { end: end.pose }, end.tol_mm, end.tol_deg, None),
            RefKind::Line { end, feed } => {
                push(
                    Event::Line { end: end.pose, rate: Some((feed.rate, feed.per_rev)) },
                    end.tol_mm,
                    end.tol_deg,
                    Some(feed),
                );
            }
            RefKind::Arc { end, center, plane, turns, feed } => push(
                Event::Arc {
                    end: end.pose,
                    center: *center,
                    plane: *plane,
                    turns: *turns,
                    rate: Some((feed.rate, feed.per_rev)),
                },
                end.tol_mm,
                end.tol_deg,
                Some(feed),
            ),
            RefKind::Nurbs { control_points, .. } => {
                push(Event::Spline { control_points: *control_points }, 0.0, 0.0, None)
            }
            RefKind::Probe { end } => push(Event::Probe { end: end.pose }, end.tol_mm, end.tol_deg, None),
            RefKind::Dwell { seconds } => push(Event::Dwell { seconds: *seconds }, 0.0, 0.0, None),
            RefKind::ChangeTool { tool, .. } | RefKind::SetToolNumber { tool, .. } => {
                push(Event::ToolChange { tool: *tool }, 0.0, 0.0, None);
            }
            RefKind::ToolLengthOffset { offset, .. } => {
                push(Event::ToolLengthOffset { offset: *offset }, MM_PER_INCH * PRINT_HALF_UNIT + TOL_FLOOR, 0.0, None);
            }
            RefKind::Spindle { rpm } if *rpm != last_rpm => {
                last_rpm = *rpm;
                push(Event::Spindle { rpm: *rpm }, 0.0, 0.0, None);
            }
            RefKind::Stop { end } => push(Event::Stop { end: *end }, 0.0, 0.0, None),
            _ => {}
        }
    }
    out
}

/// Our events; inverse-time feeds become the per-minute rate LinuxCNC computes for the move
/// (length·F in program units, at least 0.1 unit/min), which needs the program's unit: taken
/// from the matching call of theirs.
fn our_events(ours: &[Canon]) -> Vec<(Event, String, Option<f64>)> {
    let mut out = Vec::new();
    let mut last_rpm = 0.0;
    let mut start = Pose::default();
    for c in ours {
        let at = format!("our call at line {} (file {})", c.loc().line, c.loc().file);
        match c {
            // Our probe's back-off: LinuxCNC's stand-alone canon moves the position without a call.
            Canon::Traverse { origin: interpolab::gcode::interp::Origin::Probe, .. } => {}
            Canon::Traverse { end, .. } => out.push((Event::Traverse { end: *end }, at, None)),
            Canon::Line { end, feed, origin, .. } => {
                if *origin == interpolab::gcode::interp::Origin::Probe {
                    out.push((Event::Probe { end: *end }, at, None));
                } else {
                    let length = straight_length(&start, end);
                    out.push((Event::Line { end: *end, rate: our_rate(feed) }, at, inverse_length(feed, length)));
                }
            }
            Canon::Arc { end, center, plane, turns, feed, .. } => {
                let length = arc_length(&start, end, *center, *plane, *turns);
                out.push((
                    Event::Arc { end: *end, center: *center, plane: *plane, turns: *turns, rate: our_rate(feed) },
                    at,
                    inverse_length(feed, length),
                ));
            }
            Canon::Spline { curve, .. } => out.push((Event::Spline { control_points: curve.len() }, at, None)),
            Canon::Dwell { seconds, .. } => out.push((Event::Dwell { seconds: *seconds }, at, None)),
            Canon::ToolChange { tool, .. } => out.push((Event::ToolChange { tool: *tool }, at, None)),
            Canon::ToolLengthOffset { offset, .. } => out.push((Event::ToolLengthOffset { offset: *offset }, at, None)),
            Canon::Spindle { rpm, .. } => {
                if *rpm != last_rpm {
                    last_rpm = *rpm;
                    out.push((Event::Spindle { rpm: *rpm }, at, None));
                }
            }
            Canon::Stop { end, .. } => out.push((Event::Stop { end: *end }, at, None)),
        }
        if let Some(e) = c.end() {
            start = e;
        }
    }
    out
}

fn our_rate(feed: &interpolab::gcode::interp::Feed) -> Option<(f64, bool)> {
    match feed.mode {
        FeedMode::PerMinute => Some((feed.rate, false)),
        FeedMode::PerRevolution => Some((feed.rate, true)),
        // Filled in against theirs, where the program's unit is known.
        FeedMode::InverseTime => None,
    }
}

/// For an inverse-time feed: (length of the move in mm) × F, to be floored in program units.
fn inverse_length(feed: &interpolab::gcode::interp::Feed, length_mm: f64) -> Option<f64> {
    (feed.mode == FeedMode::InverseTime).then_some(length_mm * feed.rate)
}

/// LinuxCNC's length of a straight move for inverse time: X Y Z if they move, else A B C.
fn straight_length(a: &Pose, b: &Pose) -> f64 {
    let d = b.xyz - a.xyz;
    if d.abs().max_element() > 1e-7 { d.length() } else { (b.abc - a.abc).length() }
}

/// Length of an arc (helical: the hypotenuse of the turned length and the rise).
fn arc_length(start: &Pose, end: &Pose, center: DVec3, plane: Plane, turns: i32) -> f64 {
    let (i, j, k) = plane_axes(plane);
    let (s, e, c) = (start.xyz, end.xyz, center);
    let a0 = (s[j] - c[j]).atan2(s[i] - c[i]);
    let a1 = (e[j] - c[j]).atan2(e[i] - c[i]);
    let r = (s[i] - c[i]).hypot(s[j] - c[j]);
    let tau = std::f64::consts::TAU;
    let mut sweep = a1 - a0;
    if turns > 0 {
        if sweep <= 0.0 {
            sweep += tau;
        }
        sweep += tau * f64::from(turns - 1);
    } else {
        if sweep >= 0.0 {
            sweep -= tau;
        }
        sweep -= tau * f64::from(-turns - 1);
    }
    (r * sweep).hypot(e[k] - s[k])
}

/// Indices (first, second, normal) of a plane's axes.
pub fn plane_axes(plane: Plane) -> (usize, usize, usize) {
    match plane {
        Plane::Xy => (0, 1, 2),
        Plane::Zx => (2, 0, 1),
        Plane::Yz => (1, 2, 0),
    }
}

fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn poses_near(ours: &Pose, theirs: &Pose, tol_mm: f64, tol_deg: f64) -> Option<String> {
    for i in 0..3 {
        if !near(ours.xyz[i], theirs.xyz[i], tol_mm) {
            return Some(format!(
                "{} differs by {:.3e} mm (allowed {:.1e})",
                ["X", "Y", "Z"][i],
                ours.xyz[i] - theirs.xyz[i],
                tol_mm
            ));
        }
        if !near(ours.abc[i], theirs.abc[i], tol_deg) {
            return Some(format!(
                "{} differs by {:.3e}° (allowed {:.1e})",
                ["A", "B", "C"][i],
                ours.abc[i] - theirs.abc[i],
                tol_deg
            ));
        }
    }
    None
}

/// Compares our canonical calls with `rs274`'s, in order: every motion's kind and end
/// point, an arc's plane, centre (in the plane) and turns, the feed of cutting moves (G93 as
/// LinuxCNC's per-minute rate), spline control-point counts, dwells, tool changes (M6, M61),
/// tool length offsets, spindle changes (consecutive repeats merged on both sides) and stops.
/// Positions agree within `rs274`'s printing precision ([`RefPose::tol_mm`]). Nothing is
/// skipped: LinuxCNC prints a move to the current position, so ours must too.
///
/// # Errors
/// The first difference: its index among the compared events, both sides' calls (our line,
/// `rs274`'s call number and line) and both values.
pub fn compare(ours: &[Canon], theirs: &[RefCall]) -> Result<(), String> {
    let ours = our_events(ours);
    let theirs = their_events(theirs);
    let mut msg = String::new();
    for (i, ((o, o_at, o_inv), t)) in ours.iter().zip(&theirs).enumerate() {
        let t_ev = &t.event;
        let why: Option<String> = match (o, t_ev) {
            (Event::Traverse { end: a }, Event::Traverse { end: b })
            | (Event::Probe { end: a }, Event::Probe { end: b }) => poses_near(a, b, t.tol_mm, t.tol_deg),
            (Event::Line { end: a, rate: ra }, Event::Line { end: b, rate: rb }) => {
                poses_near(a, b, t.tol_mm, t.tol_deg).or_else(|| feed_differs(*ra, *o_inv, *rb, t))
            }
            (
                Event::Arc { end: a, center: ca, plane: pa, turns: na, rate: ra },
                Event::Arc { end: b, center: cb, plane: pb, turns: nb, rate: rb },
            ) => {
                if pa != pb {
                    Some(format!("plane {pa:?} against {pb:?}"))
                } else if na != nb {
                    Some(format!("turns {na} against {nb}"))
                } else {
                    let (i0, i1, _) = plane_axes(*pa);
                    let centre = [i0, i1].into_iter().find(|&k| !near(ca[k], cb[k], t.tol_mm)).map(|k| {
                        format!(
                            "centre {} differs: ({:.6}, {:.6}, {:.6}) against ({:.6}, {:.6}, {:.6})",
                            ["X", "Y", "Z"][k],
                            ca.x,
                            ca.y,
                            ca.z,
                            cb.x,
                            cb.y,
                            cb.z
                        )
                    });
                    poses_near(a, b, t.tol_mm, t.tol_deg).or(centre).or_else(|| feed_differs(*ra, *o_inv, *rb, t))
                }
            }
            (Event::Spline { control_points: a }, Event::Spline { control_points: b }) => {
                (a != b).then(|| format!("{a} control points against {b}"))
            }
            (Event::Dwell { seconds: a }, Event::Dwell { seconds: b }) => {
                (!near(*a, *b, PRINT_HALF_UNIT + TOL_FLOOR)).then(|| format!("dwell {a} s against {b} s"))
            }
            (Event::ToolChange { tool: a }, Event::ToolChange { tool: b }) => {
                (a != b).then(|| format!("tool {a} against {b}"))
            }
            (Event::ToolLengthOffset { offset: a }, Event::ToolLengthOffset { offset: b }) => {
                (!(0..3).all(|k| near(a[k], b[k], t.tol_mm))).then(|| format!("offset {a:?} mm against {b:?} mm"))
            }
            (Event::Spindle { rpm: a }, Event::Spindle { rpm: b }) => {
                (!near(*a, *b, PRINT_HALF_UNIT + TOL_FLOOR)).then(|| format!("spindle {a} rev/min against {b}"))
            }
            (Event::Stop { end: a }, Event::Stop { end: b }) => {
                (a != b).then(|| format!("stop end={a} against end={b}"))
            }
            _ => Some(format!("{} against {}", o.name(), t_ev.name())),
        };
        if let Some(why) = why {
            let _ = write!(msg, "event {i}: {o_at} against {}: {why}", t.at);
            if let (Some(a), Some(b)) = (event_end(o), event_end(t_ev)) {
                let _ = write!(msg, "; ours {} | theirs {}", fmt_pose(&a), fmt_pose(&b));
            }
            return Err(msg);
        }
    }
    if ours.len() != theirs.len() {
        let (more, who, next) = if ours.len() > theirs.len() {
            (ours.len() - theirs.len(), "we have", format!("{} {}", ours[theirs.len()].1, ours[theirs.len()].0.name()))
        } else {
            (
                theirs.len() - ours.len(),
                "rs274 has",
                format!("{} {}", theirs[ours.len()].at, theirs[ours.len()].event.name()),
            )
        };
        return Err(format!(
            "{who} {more} more events after the {} that agree; the first: {next}",
            ours.len().min(theirs.len())
        ));
    }
    Ok(())
}

fn event_end(e: &Event) -> Option<Pose> {
    match e {
        Event::Traverse { end } | Event::Line { end, .. } | Event::Arc { end, .. } | Event::Probe { end } => Some(*end),
        _ => None,
    }
}

fn feed_differs(
    ours: Option<(f64, bool)>,
    inverse: Option<f64>,
    theirs: Option<(f64, bool)>,
    t: &Theirs,
) -> Option<String> {
    let (rb, per_rev_b) = theirs?;
    let (ra, per_rev_a) = match (ours, inverse) {
        (Some(r), _) => r,
        (None, Some(length_times_f)) => {
            let floor = 0.1 * if t.feed_inch { MM_PER_INCH } else { 1.0 };
            (length_times_f.max(floor), false)
        }
        (None, None) => return Some("no feed on our side".into()),
    };
    if per_rev_a != per_rev_b {
        return Some(format!("feed per revolution {per_rev_a} against {per_rev_b}"));
    }
    // A rate computed from a printed length (G93) carries the length's rounding too.
    let tol = if inverse.is_some() { t.feed_tol + ra.abs() * 1e-6 } else { t.feed_tol };
    (!near(ra, rb, tol)).then(|| format!("feed {ra} against {rb}"))
}

/// The calls of a run, one a line (for failure messages).
pub fn describe(calls: &[RefCall]) -> String {
    let mut s = String::new();
    for c in calls {
        let _ = writeln!(s, "{:5} line {:?}: {:?}", c.seq, c.line, c.kind);
    }
    s
}
