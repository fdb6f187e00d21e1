//! Writing programs: G01 lines by equal-error chords, G02/G03 arcs by tolerance-driven arc
//! fitting, and FANUC-style G06.2 NURBS from a tolerance fit — each rounded to the machine
//! resolution and **checked after rounding** by reading the text back and measuring its
//! two-sided deviation from the design curve.
//!
//! Tolerance budget: rounding moves a point by at most `res·√3/2` (half a resolution step
//! per axis). A chord's end points, or a B-spline's control points (whose basis functions
//! are non-negative and sum to 1), move the whole piece by no more than that, so lines and
//! NURBS are fitted to `E − res·√3/2`; an arc's centre offsets are rounded as well, so arcs
//! get `E − res·√3`. If the measured deviation after rounding still exceeds E, the fit
//! tolerance is lowered by 10 % and the program rewritten (a few times at most). The
//! tolerance must be at least twice the resolution.
//!
//! Every program: a header of comments (what it is, the programmed point, tolerance,
//! resolution and the deviation achieved), `G21 G90 G94 G17`, a rapid to the safe height,
//! rapids above and down to the start point, the path, a rapid back to the safe height,
//! `M30`. The path begins exactly at the rapid's end point; all feed moves are the path.
//!
//! The words are the [`Dialect`]'s (FANUC by default; Sinumerik 840D `BSPLINE`, LinuxCNC
//! `G5.2`, see `docs/gcode-dialects.md`), and the check reads the text back with that
//! dialect's reader, so the deviation is the one the dialect's control would interpret.

use glam::DVec3;
use thiserror::Error;

use super::arcs::{ArcFitError, ArcFitOptions, Piece, fit_arcs};
use super::comment::{key_comment, safe_comment};
use super::dialect::Dialect;
use super::dialect::HeaderKey;
use super::kind::ProgramKind;
use super::parse::{ParseError, ParsedProgram};
use super::path::{Plane, Segment};
use super::read::parse_program_in;
use super::replay::{Deviation, DeviationOptions, ReplayError, deviation};
use crate::chords::{ChordError, equal_error_chords};
use crate::geom::{Curve3, NurbsCurve};
use crate::numerics::format::fmt_fixed;
use crate::numerics::measure::Translated;
use crate::numerics::tolerance;
use crate::nurbs_path::{ApproxOptions, FitError, approximate_curve};

/// Which point of the tool the program carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProgrammedPoint {
    /// The ball centre (cutter centre), as `interpolab run` prints it.
    BallCentre,
    /// The ball tip of a 3-axis ball end mill: centre − R·ẑ.
    BallTip {
        /// Ball radius R (mm).
        radius_mm: f64,
    },
}

impl ProgrammedPoint {
    /// Translation from the ball centre to the programmed point (mm).
    #[must_use]
    pub fn offset(self) -> DVec3 {
        match self {
            Self::BallCentre => DVec3::ZERO,
            Self::BallTip { radius_mm } => DVec3::new(0.0, 0.0, -radius_mm),
        }
    }

    /// The header comment's value naming the point: `BALL CENTRE`, `BALL TIP = BALL CENTRE -
    /// Z 5.000000`.
    #[must_use]
    pub fn value(self) -> String {
        match self {
            Self::BallCentre => "BALL CENTRE".to_owned(),
            Self::BallTip { radius_mm } => format!("BALL TIP = BALL CENTRE - Z {}", fmt_fixed(radius_mm, 6)),
        }
    }

    /// The text of the header comment naming the point (read back by
    /// [`ProgrammedPoint::from_comments`]): `PROGRAMMED POINT: ` and [`Self::value`]. Written
    /// by [`super::comment::key_comment`] only.
    #[must_use]
    pub fn comment(self) -> String {
        format!("{} {}", HeaderKey::ProgrammedPoint.as_str(), self.value())
    }

    /// The programmed point named by a header comment of ours, if any.
    #[must_use]
    pub fn from_comments(comments: &[(usize, String)]) -> Option<Self> {
        for (_, c) in comments {
            let c = c.trim();
            let Some(rest) = c.strip_prefix(HeaderKey::ProgrammedPoint.as_str()) else {
                continue;
            };
            if rest.contains("BALL TIP") {
                let r = rest.rsplit("- Z").next().and_then(|v| v.trim().parse::<f64>().ok())?;
                return Some(Self::BallTip { radius_mm: r });
            }
            if rest.contains("BALL CENTRE") {
                return Some(Self::BallCentre);
            }
        }
        None
    }
}

/// Options of [`write_program`].
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramOptions {
    /// Machine resolution (mm, default [`tolerance::GCODE_RESOLUTION_MM`]); a power of ten
    /// from 1e-6 to 0.1. Coordinates, offsets and knots are rounded to it.
    pub resolution_mm: f64,
    /// Feed F (mm/min, default 1500).
    pub feed_mm_per_min: f64,
    /// Height of the safe plane above the highest point of the path (mm, default 5).
    pub clearance_mm: f64,
    /// Absolute safe height (mm); overrides the clearance when given.
    pub safe_z_mm: Option<f64>,
    /// Programmed point (default the ball centre).
    pub point: ProgrammedPoint,
    /// Title written into the header (default empty).
    pub title: String,
    /// Degree of G06.2 curves, 1 to 3 (default 3: order P4).
    pub degree: usize,
    /// Number the blocks N10, N20, … (default false).
    pub line_numbers: bool,
    /// Arc fitting options.
    pub arcs: ArcFitOptions,
    /// NURBS approximation options (the knot quantum is set to the resolution).
    pub approx: ApproxOptions,
    /// How the written program is checked.
    pub check: DeviationOptions,
    /// Most writes with a lowered fit tolerance before giving up (default 4).
    pub attempts: usize,
    /// The controller's dialect (default FANUC).
    pub dialect: Dialect,
}

impl Default for ProgramOptions {
    fn default() -> Self {
        Self {
            resolution_mm: tolerance::GCODE_RESOLUTION_MM,
            feed_mm_per_min: 1500.0,
            clearance_mm: 5.0,
            safe_z_mm: None,
            point: ProgrammedPoint::BallCentre,
            title: String::new(),
            degree: 3,
            line_numbers: false,
            arcs: ArcFitOptions::default(),
            approx: ApproxOptions::default(),
            check: DeviationOptions::default(),
            attempts: 4,
            dialect: Dialect::Fanuc,
        }
    }
}

impl ProgramOptions {
    /// Sets the resolution (mm).
    #[must_use]
    pub fn with_resolution(mut self, mm: f64) -> Self {
        self.resolution_mm = mm;
        self
    }
    /// Sets the feed (mm/min).
    #[must_use]
    pub fn with_feed(mut self, mm_per_min: f64) -> Self {
        self.feed_mm_per_min = mm_per_min;
        self
    }
    /// Sets the programmed point.
    #[must_use]
    pub fn with_point(mut self, point: ProgrammedPoint) -> Self {
        self.point = point;
        self
    }
    /// Sets the title.
    #[must_use]
    pub fn with_title(mut self, title: &str) -> Self {
        self.title = title.to_owned();
        self
    }
    /// Sets the G06.2 degree.
    #[must_use]
    pub fn with_degree(mut self, degree: usize) -> Self {
        self.degree = degree;
        self
    }
    /// Sets an absolute safe height (mm).
    #[must_use]
    pub fn with_safe_z(mut self, z: Option<f64>) -> Self {
        self.safe_z_mm = z;
        self
    }
    /// Sets the dialect.
    #[must_use]
    pub fn with_dialect(mut self, dialect: Dialect) -> Self {
        self.dialect = dialect;
        self
    }
    /// Sets block numbering.
    #[must_use]
    pub fn with_line_numbers(mut self, on: bool) -> Self {
        self.line_numbers = on;
        self
    }
}

/// Why a program could not be written. Every message says what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ProgramError {
    /// Tolerance not positive.
    #[error("the tolerance must be a positive length in mm, got {0}; give e.g. --tolerance 0.01")]
    BadTolerance(f64),
    /// Resolution not a power of ten.
    #[error("the resolution must be a power of ten from 0.000001 to 0.1 mm, got {0}; give e.g. --resolution 0.001")]
    BadResolution(f64),
    /// Tolerance too small for the resolution.
    #[error("the tolerance {tol_mm} mm is below twice the resolution {resolution_mm} mm: rounding alone moves points by up to {:.6} mm; raise --tolerance to at least {} or use a finer --resolution", resolution_mm * 3f64.sqrt() / 2.0, 2.0 * resolution_mm)]
    BelowResolution {
        /// Tolerance.
        tol_mm: f64,
        /// Resolution.
        resolution_mm: f64,
    },
    /// Feed not positive once written, or absurdly large.
    #[error(
        "the feed must be a finite number of mm/min from {min_mm_per_min} (the smallest the program's decimals can write) to 1e6; give e.g. --feed 1500"
    )]
    BadFeed {
        /// Smallest feed the program can write (mm/min).
        min_mm_per_min: f64,
    },
    /// Safe Z not a usable height.
    #[error("the safe Z height must be a finite number of mm within ±1e6 mm; give e.g. --safe-z 10")]
    BadSafeZ,
    /// G06.2 degree out of range.
    #[error("G06.2 takes order P2 to P4 (degree 1 to 3), not degree {0}; use --degree 3")]
    Degree(usize),
    /// A dialect's NURBS degree out of range.
    #[error("{dialect} NURBS take degree {lo} to {hi}, not {degree}; use --degree 3")]
    DialectDegree {
        /// The dialect's controller name.
        dialect: &'static str,
        /// Degree asked for.
        degree: usize,
        /// Lowest degree.
        lo: usize,
        /// Highest degree.
        hi: usize,
    },
    /// LinuxCNC G5.2 asked for a path that is not planar in XY.
    #[error(
        "LinuxCNC G5.2 NURBS lie in the XY plane at one Z, but this path's Z varies by {dz_mm:.4} mm from its start, more than half the tolerance {tol_mm} mm; write it for LinuxCNC with --kind g01 or --kind arcs (G1/G2/G3 move Z too), or as a 3-D NURBS with --dialect fanuc or sinumerik"
    )]
    NotPlanar {
        /// Largest |z − z_start| of the path (mm).
        dz_mm: f64,
        /// Tolerance (mm).
        tol_mm: f64,
    },
    /// Chords failed.
    #[error("G01 chords: {0}")]
    Chords(ChordError),
    /// Arcs failed.
    #[error("G02/G03 arcs: {0}")]
    Arcs(ArcFitError),
    /// NURBS fit failed.
    #[error("G06.2 fit: {0}")]
    Fit(FitError),
    /// The program could not be read back (a bug).
    #[error("the written program does not read back ({0}); please report this")]
    ReadBack(ParseError),
    /// The deviation could not be measured.
    #[error("checking the program: {0}")]
    Check(ReplayError),
    /// The tolerance was not met after rounding.
    #[error(
        "the {kind} program deviates {achieved_mm:.6} mm after rounding, more than the tolerance {tol_mm} mm, after {attempts} attempts; raise --tolerance or use a finer --resolution"
    )]
    NotMet {
        /// Kind label.
        kind: &'static str,
        /// Tolerance.
        tol_mm: f64,
        /// Best deviation achieved.
        achieved_mm: f64,
        /// Attempts made.
        attempts: usize,
    },
}

/// A written and checked program.
#[derive(Clone, Debug)]
pub struct Program {
    /// Kind.
    pub kind: ProgramKind,
    /// Dialect it is written in.
    pub dialect: Dialect,
    /// The program text.
    pub text: String,
    /// The text read back.
    pub parsed: ParsedProgram,
    /// Two-sided deviation of the rounded program from the design curve (mm).
    pub deviation: Deviation,
    /// The tolerance asked for (mm).
    pub tol_mm: f64,
    /// The tolerance the geometry was fitted to before rounding (mm).
    pub fit_tol_mm: f64,
    /// Blocks describing the path (G01/G02/G03 moves; G06.2: control points + closing knots;
    /// BSPLINE: control points after the start; G5.2: those and the closing G5.3).
    pub path_blocks: usize,
    /// LinuxCNC `G64 P` blending tolerance written (mm): the control may leave the programmed
    /// path by this much more; `deviation + blend ≤ tol` by construction. `None` elsewhere.
    pub blend_mm: Option<f64>,
    /// The fitted NURBS before rounding (G06.2 only).
    pub nurbs: Option<NurbsCurve>,
    /// Writes made (1 when the first met the tolerance).
    pub attempts: usize,
}

impl Program {
    /// Size of the text in bytes.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.text.len()
    }

    /// The program's NURBS curves (G06.2, BSPLINE, G5.2) as read back from its text by the
    /// dialect's reader (control points and weights rounded to the resolution, knots as the
    /// dialect implies them): what a control would run, unlike [`Program::nurbs`], the fit
    /// before rounding.
    pub fn read_back_curves(&self) -> impl Iterator<Item = &NurbsCurve> {
        self.parsed.toolpath.cuts().filter_map(|b| match &b.segment {
            Segment::Nurbs(c) => Some(c),
            _ => None,
        })
    }
}

/// Decimal places of a power-of-ten resolution.
fn decimals(res: f64) -> Option<usize> {
    if !(res.is_finite() && res > 0.0) {
        return None;
    }
    let d = -res.log10();
    let di = d.round();
    if !(0.0..=6.0).contains(&di)
        || (10f64.powf(-di) - res).abs() > crate::numerics::tolerance::ROUNDING_REL * res
        || di < 1.0
    {
        return None;
    }
    Some(di as usize)
}

/// Text lines with optional block numbers, numbers at a fixed resolution, and modal axis
/// words (an axis is written only when its rounded value changes).
struct Emitter {
    d: usize,
    dialect: Dialect,
    numbered: bool,
    n: u32,
    text: String,
    /// Last written axis values as text.
    axes: [String; 3],
}

impl Emitter {
    fn num(&self, x: f64) -> String {
        fmt_fixed(x, self.d)
    }
    /// The f64 a reader gets back from the written text of x.
    fn q(&self, x: f64) -> f64 {
        self.num(x).parse().unwrap_or(x)
    }
    fn qv(&self, p: DVec3) -> DVec3 {
        DVec3::new(self.q(p.x), self.q(p.y), self.q(p.z))
    }
    /// A comment line of any text, upper case, by [`safe_comment`].
    fn comment(&mut self, c: &str) {
        let line = safe_comment(self.dialect, &c.to_ascii_uppercase());
        self.raw(&line);
    }
    /// A header comment the readers look for, by [`key_comment`].
    fn key_comment(&mut self, key: HeaderKey, value: &str) {
        let line = key_comment(self.dialect, key, &value.to_ascii_uppercase());
        self.raw(&line);
    }
    fn raw(&mut self, s: &str) {
        self.text.push_str(s);
        self.text.push('\n');
    }
    fn block(&mut self, s: &str) {
        if self.numbered {
            self.n += 10;
            self.text.push_str(&format!("N{} ", self.n));
        }
        self.raw(s);
    }
    /// Axis words for p: only changed axes unless `all`.
    fn axis_words(&mut self, p: DVec3, all: bool) -> String {
        let mut w = Vec::new();
        for (i, l) in ["X", "Y", "Z"].iter().enumerate() {
            let v = self.num(p[i]);
            if all || v != self.axes[i] {
                w.push(format!("{l}{v}"));
            }
            self.axes[i] = v;
        }
        w.join(" ")
    }
}

/// The body of a program (path blocks), with the first point of the path.
struct Body {
    start: DVec3,
    text: Emitter,
    path_blocks: usize,
    top_z: f64,
}

fn sample_top(design: &dyn Curve3) -> f64 {
    let (a, b) = design.range();
    (0..=256).map(|i| design.point_at(a + (b - a) * i as f64 / 256.0).z).fold(f64::NEG_INFINITY, f64::max)
}

/// Writes a program of `kind` for `design` (ball-centre path) within `tol_mm`.
///
/// # Errors
/// [`ProgramError`]: bad tolerance, resolution, feed or degree; a failed fit; or the
/// tolerance not met after rounding.
pub fn write_program(
    kind: ProgramKind,
    design: &dyn Curve3,
    tol_mm: f64,
    opts: &ProgramOptions,
) -> Result<Program, ProgramError> {
    if !(tol_mm.is_finite() && tol_mm > 0.0) {
        return Err(ProgramError::BadTolerance(tol_mm));
    }
    let res = opts.resolution_mm;
    let d = decimals(res).ok_or(ProgramError::BadResolution(res))?;
    if tol_mm < 2.0 * res * (1.0 - crate::numerics::tolerance::ROUNDING_REL) {
        return Err(ProgramError::BelowResolution { tol_mm, resolution_mm: res });
    }
    // The feed as written (rounded to the resolution's decimals) must still be positive, or
    // the program would not read back.
    let feed = opts.feed_mm_per_min;
    let written: f64 = crate::numerics::format::fmt_fixed(feed, d).parse().unwrap_or(0.0);
    if !(feed.is_finite() && feed > 0.0 && written > 0.0 && feed <= crate::numerics::limits::MAX_FEED_MM_PER_MIN) {
        return Err(ProgramError::BadFeed { min_mm_per_min: 10f64.powi(-(d as i32)) });
    }
    if let Some(z) = opts.safe_z_mm
        && !(z.is_finite() && z.abs() <= crate::numerics::limits::MAX_COORDINATE_MM)
    {
        return Err(ProgramError::BadSafeZ);
    }
    let dialect = opts.dialect;
    if kind == ProgramKind::Nurbs && dialect == Dialect::Fanuc && !(1..=3).contains(&opts.degree) {
        return Err(ProgramError::Degree(opts.degree));
    }
    let (lo, hi) = dialect.nurbs_degrees();
    if kind == ProgramKind::Nurbs && !(lo..=hi).contains(&opts.degree) {
        return Err(ProgramError::DialectDegree { dialect: dialect.label(), degree: opts.degree, lo, hi });
    }
    let moved = Translated { inner: design, offset: opts.point.offset() };
    let design: &dyn Curve3 = &moved;
    let allowance = match kind {
        ProgramKind::Arcs => res * 3f64.sqrt(),
        _ => res * 3f64.sqrt() / 2.0,
    };
    let mut fit_tol = tol_mm - allowance;
    // LinuxCNC G5.2 is planar: refuse a path whose Z leaves the start's by more than half
    // the tolerance before any fitting (the other half is for the XY fit and rounding).
    let plane_z = if kind == ProgramKind::Nurbs && dialect == Dialect::LinuxCnc {
        let (a, _) = design.range();
        let z0 = fmt_fixed(design.point_at(a).z, d).parse::<f64>().unwrap_or(design.point_at(a).z);
        let dz = z_spread(design, z0);
        if !(dz <= 0.5 * tol_mm) {
            return Err(ProgramError::NotPlanar { dz_mm: dz, tol_mm });
        }
        Some((z0, dz))
    } else {
        None
    };
    let mut best: Option<f64> = None;
    for attempt in 1..=opts.attempts.max(1) {
        let (body, nurbs) = match (kind, plane_z) {
            (ProgramKind::Lines, _) => (lines_body(design, fit_tol, d, opts)?, None),
            (ProgramKind::Arcs, _) => (arcs_body(design, fit_tol, d, opts)?, None),
            (ProgramKind::Nurbs, Some((z0, dz))) => {
                // The path flattened to the plane z = z0, fitted in XY so that with the Z
                // offset the distance stays within the fit tolerance.
                let flat = FlatZ { inner: design, z_mm: z0 };
                let xy_tol = (fit_tol * fit_tol - dz * dz).max(0.0).sqrt();
                let (b, c) = nurbs_body(&flat, xy_tol, d, opts)?;
                (b, Some(c))
            }
            (ProgramKind::Nurbs, None) => {
                let (b, c) = nurbs_body(design, fit_tol, d, opts)?;
                (b, Some(c))
            }
        };
        let text_without = assemble(kind, &body, tol_mm, fit_tol, None, d, opts);
        let parsed = parse_program_in(&text_without, dialect).map_err(ProgramError::ReadBack)?;
        let dev = deviation(&parsed.toolpath, design, &opts.check).map_err(ProgramError::Check)?;
        if dev.max_mm() <= tol_mm {
            let text = assemble(kind, &body, tol_mm, fit_tol, Some(&dev), d, opts);
            let parsed = parse_program_in(&text, dialect).map_err(ProgramError::ReadBack)?;
            // The header comment with the deviation comes before every block: the worst
            // move's line moves down by the lines it takes.
            let mut dev = dev;
            dev.program_line += text.lines().count() - text_without.lines().count();
            let blend_mm = parsed.blend_mm;
            return Ok(Program {
                kind,
                dialect,
                blend_mm,
                text,
                parsed,
                deviation: dev,
                tol_mm,
                fit_tol_mm: fit_tol,
                path_blocks: body.path_blocks,
                nurbs,
                attempts: attempt,
            });
        }
        best = Some(best.map_or(dev.max_mm(), |b: f64| b.min(dev.max_mm())));
        fit_tol *= 0.9;
    }
    Err(ProgramError::NotMet {
        kind: dialect.kind_label(kind),
        tol_mm,
        achieved_mm: best.unwrap_or(f64::NAN),
        attempts: opts.attempts.max(1),
    })
}

fn new_emitter(d: usize, opts: &ProgramOptions) -> Emitter {
    Emitter {
        d,
        dialect: opts.dialect,
        numbered: opts.line_numbers,
        n: 0,
        text: String::new(),
        axes: Default::default(),
    }
}

/// A curve moved onto the plane z = `z_mm` (its Z dropped).
struct FlatZ<'a> {
    inner: &'a dyn Curve3,
    z_mm: f64,
}

impl Curve3 for FlatZ<'_> {
    fn derivatives_at(&self, t: f64) -> [DVec3; 3] {
        let [mut p, mut d1, mut d2] = self.inner.derivatives_at(t);
        p.z = self.z_mm;
        d1.z = 0.0;
        d2.z = 0.0;
        [p, d1, d2]
    }
    fn range(&self) -> (f64, f64) {
        self.inner.range()
    }
}

/// Largest |z − z0| over the curve (mm): dense samples, the worst refined by golden section.
fn z_spread(design: &dyn Curve3, z0: f64) -> f64 {
    let (a, b) = design.range();
    let mut f = |t: f64| (design.point_at(t).z - z0).abs();
    crate::numerics::maximise::max_on_interval(&mut f, a, b, Z_SPREAD_SAMPLES, 20).0
}

/// Samples of the planarity check of LinuxCNC G5.2 programs.
const Z_SPREAD_SAMPLES: usize = 1024;

fn assemble(
    kind: ProgramKind,
    body: &Body,
    tol_mm: f64,
    fit_tol: f64,
    dev: Option<&Deviation>,
    d: usize,
    opts: &ProgramOptions,
) -> String {
    let mut e = new_emitter(d, opts);
    let dialect = opts.dialect;
    // Sinumerik programs are files of the control's program memory: no tape marks.
    if dialect != Dialect::Sinumerik {
        e.raw("%");
    }
    if !opts.title.is_empty() {
        e.comment(&opts.title);
    }
    e.comment(&format!(
        "INTERPOLAB {} PROGRAM: {}",
        dialect.kind_label(kind),
        match (kind, dialect) {
            (ProgramKind::Lines, _) => "EQUAL-ERROR CHORDS",
            (ProgramKind::Arcs, _) => "TOLERANCE-FITTED ARCS AND LINES",
            (ProgramKind::Nurbs, Dialect::Fanuc) => "FANUC-STYLE NURBS, KNOTS IN MM OF ARC LENGTH",
            (ProgramKind::Nurbs, Dialect::Sinumerik) => "B-SPLINE, EQUAL KNOT INTERVALS PL IN MM OF ARC LENGTH",
            (ProgramKind::Nurbs, Dialect::LinuxCnc) => "NURBS IN THE XY PLANE, IMPLIED UNIFORM KNOTS",
        }
    ));
    if dialect != Dialect::Fanuc {
        e.key_comment(HeaderKey::Dialect, dialect.as_str());
    }
    e.key_comment(HeaderKey::ProgrammedPoint, &opts.point.value());
    e.comment(&format!(
        "TOLERANCE {} MM, RESOLUTION {} MM, FIT TOLERANCE {} MM",
        fmt_fixed(tol_mm, 6),
        fmt_fixed(opts.resolution_mm, 6),
        fmt_fixed(fit_tol, 6)
    ));
    if let Some(dev) = dev {
        e.comment(&format!(
            "MAX DEVIATION AFTER ROUNDING {} MM, PATH BLOCKS {}",
            fmt_fixed(dev.max_mm(), 6),
            body.path_blocks
        ));
    }
    match dialect {
        Dialect::Fanuc => e.block("G21 G90 G94 G17"),
        // G710: metric for lengths and feeds; G64: continuous path without corner rounding.
        Dialect::Sinumerik => e.block("G710 G90 G94 G17 G64"),
        Dialect::LinuxCnc => {
            e.block("G21 G90 G94 G17");
            // Blending may take the control off the programmed path by P: give it what the
            // measured deviation leaves of the tolerance, or exact path mode if nothing.
            if let Some(dev) = dev {
                let res = opts.resolution_mm;
                let slack = ((tol_mm - dev.max_mm()) / res).floor() * res;
                if slack >= res {
                    e.comment(&format!(
                        "G64 P: PATH BLENDING WITHIN {} MM, SO DEVIATION + BLENDING <= TOLERANCE",
                        e.num(slack)
                    ));
                    e.block(&format!("G64 P{}", e.num(slack)));
                } else {
                    e.block("G61");
                }
            }
        }
    }
    let safe = opts.safe_z_mm.unwrap_or(body.top_z + opts.clearance_mm);
    let start = body.start;
    let rapid = dialect.motion_word("G00");
    e.block(&format!("{rapid} Z{}", e.num(safe)));
    e.block(&format!("{rapid} X{} Y{}", e.num(start.x), e.num(start.y)));
    e.block(&format!("{rapid} Z{}", e.num(start.z)));
    if e.numbered {
        for l in body.text.text.lines() {
            e.block(l);
        }
    } else {
        e.text.push_str(&body.text.text);
    }
    e.block(&format!("{rapid} Z{}", e.num(safe)));
    match dialect {
        Dialect::Fanuc => {
            e.block("M30");
            e.raw("%");
        }
        Dialect::Sinumerik => e.block("M30"),
        Dialect::LinuxCnc => {
            e.block("M2");
            e.raw("%");
        }
    }
    e.text
}

fn lines_body(design: &dyn Curve3, fit_tol: f64, d: usize, opts: &ProgramOptions) -> Result<Body, ProgramError> {
    let nodes = equal_error_chords(design, fit_tol).map_err(ProgramError::Chords)?;
    let mut e = new_emitter(d, opts);
    e.numbered = false;
    let pts: Vec<DVec3> = nodes.iter().map(|&t| design.point_at(t)).collect();
    let start = pts[0];
    e.axis_words(start, true);
    let mut blocks = 0;
    let mut first = true;
    for p in &pts[1..] {
        let words = e.axis_words(*p, false);
        if words.is_empty() {
            continue;
        }
        let f = if first { format!(" F{}", e.num(opts.feed_mm_per_min)) } else { String::new() };
        first = false;
        e.block(&format!("{} {words}{f}", opts.dialect.motion_word("G01")));
        blocks += 1;
    }
    let top = pts.iter().map(|p| p.z).fold(sample_top(design), f64::max);
    Ok(Body { start, text: e, path_blocks: blocks, top_z: top })
}

fn arcs_body(design: &dyn Curve3, fit_tol: f64, d: usize, opts: &ProgramOptions) -> Result<Body, ProgramError> {
    let pieces = fit_arcs(design, fit_tol, &opts.arcs).map_err(ProgramError::Arcs)?;
    let mut e = new_emitter(d, opts);
    e.numbered = false;
    let (ta, _) = design.range();
    let start = design.point_at(ta);
    e.axis_words(start, true);
    let mut pos = e.qv(start);
    let mut plane = Plane::Xy;
    let mut blocks = 0;
    let mut first = true;
    for fp in &pieces {
        let end = e.qv(fp.piece.end());
        if end == pos {
            continue;
        }
        let f = if first { format!(" F{}", e.num(opts.feed_mm_per_min)) } else { String::new() };
        match &fp.piece {
            Piece::Line(_) => {
                let words = e.axis_words(end, false);
                e.block(&format!("{} {words}{f}", opts.dialect.motion_word("G01")));
            }
            Piece::Arc(arc) => {
                // Centre moved onto the bisector of the rounded chord, then rounded.
                let (sa, sb, _) = arc.plane.split(pos);
                let (ea, eb, _) = arc.plane.split(end);
                let (ca, cb, _) = arc.plane.split(arc.center);
                let (ma, mb) = (0.5 * (sa + ea), 0.5 * (sb + eb));
                let (va, vb) = (eb - sb, -(ea - sa));
                let l = va.hypot(vb);
                let (ca, cb) = if l > 0.0 {
                    let k = ((ca - ma) * va + (cb - mb) * vb) / (l * l);
                    (ma + k * va, mb + k * vb)
                } else {
                    (ca, cb)
                };
                let (ia, ib, _) = arc.plane.axes();
                let letters = ['I', 'J', 'K'];
                let plane_word = if arc.plane != plane {
                    plane = arc.plane;
                    format!("{} ", arc.plane.gcode())
                } else {
                    String::new()
                };
                let words = e.axis_words(end, false);
                let code = opts.dialect.motion_word(if arc.ccw { "G03" } else { "G02" });
                let off_a = e.num(ca - sa);
                let off_b = e.num(cb - sb);
                // Offsets in X, Y, Z order.
                let mut offs = [(ia, letters[ia], off_a), (ib, letters[ib], off_b)];
                offs.sort_by_key(|o| o.0);
                e.block(&format!(
                    "{plane_word}{code} {words} {}{} {}{}{f}",
                    offs[0].1, offs[0].2, offs[1].1, offs[1].2
                ));
            }
        }
        first = false;
        blocks += 1;
        pos = end;
    }
    Ok(Body { start, text: e, path_blocks: blocks, top_z: sample_top(design) })
}

fn nurbs_body(
    design: &dyn Curve3,
    fit_tol: f64,
    d: usize,
    opts: &ProgramOptions,
) -> Result<(Body, NurbsCurve), ProgramError> {
    let res = opts.resolution_mm;
    let approx = if opts.dialect.uniform_knots() {
        opts.approx.with_degree(opts.degree).with_uniform_knots(true)
    } else {
        opts.approx.with_degree(opts.degree).with_knot_quantum(Some(res))
    };
    let fit = approximate_curve(design, fit_tol, &approx).map_err(ProgramError::Fit)?;
    let c = fit.curve;
    let mut e = new_emitter(d, opts);
    e.numbered = false;
    match opts.dialect {
        Dialect::Fanuc => {}
        Dialect::Sinumerik => return Ok((sinumerik_nurbs(&c, e, design, opts), c)),
        Dialect::LinuxCnc => return Ok((linuxcnc_nurbs(&c, e, opts), c)),
    }
    let order = c.degree() + 1;
    let knots = c.knots();
    let n = c.len();
    for (i, &knot) in knots.iter().enumerate().take(n) {
        let p = c.control_point(i);
        let words = e.axis_words(p, true);
        let k = e.num(knot);
        let w = e.num(c.weight(i));
        if i == 0 {
            e.block(&format!("G06.2 P{order} K{k} {words} R{w} F{}", e.num(opts.feed_mm_per_min)));
        } else {
            e.block(&format!("K{k} {words} R{w}"));
        }
    }
    for &k in &knots[n..] {
        let k = e.num(k);
        e.block(&format!("K{k}"));
    }
    let top = (0..n).map(|i| c.control_point(i).z).fold(sample_top(design), f64::max);
    let start = c.control_point(0);
    Ok((Body { start, text: e, path_blocks: n + order, top_z: top }, c))
}

/// Sinumerik `BSPLINE`: the start point (the rapid's end) is the first control point; one
/// block per further control point with its weight `PW` and the knot interval `PL` — the
/// same on every block, since the fit has equal spans (so the curve does not depend on which
/// interval a block's `PL` is taken for; rounding `PL` only rescales the parameter).
fn sinumerik_nurbs(c: &NurbsCurve, mut e: Emitter, design: &dyn Curve3, opts: &ProgramOptions) -> Body {
    let n = c.len();
    let p = c.degree();
    let knots = c.knots();
    let spans = (n - p).max(1);
    let pl = e.q((knots[knots.len() - 1] - knots[0]) / spans as f64).max(opts.resolution_mm);
    let pl = e.num(pl);
    e.axis_words(c.control_point(0), true);
    for i in 1..n {
        let words = e.axis_words(c.control_point(i), true);
        let w = e.num(c.weight(i));
        if i == 1 {
            e.block(&format!("BSPLINE SD={p} {words} PW={w} PL={pl} F{}", e.num(opts.feed_mm_per_min)));
        } else {
            e.block(&format!("{words} PW={w} PL={pl}"));
        }
    }
    let top = (0..n).map(|i| c.control_point(i).z).fold(sample_top(design), f64::max);
    Body { start: c.control_point(0), text: e, path_blocks: Dialect::Sinumerik.nurbs_blocks(c), top_z: top }
}

/// LinuxCNC `G5.2`/`G5.3`: the start point is the first control point; `G5.2` carries the
/// second with its weight `P` and the order `L`, one block `X Y P` per further control point,
/// then `G5.3`. The knots are implied uniform, which the equal-span fit matches; Z stays at
/// the start's (the curve was fitted in that plane).
fn linuxcnc_nurbs(c: &NurbsCurve, mut e: Emitter, opts: &ProgramOptions) -> Body {
    let n = c.len();
    let order = c.degree() + 1;
    for i in 1..n {
        let q = c.control_point(i);
        let words = format!("X{} Y{}", e.num(q.x), e.num(q.y));
        let w = e.num(c.weight(i));
        if i == 1 {
            e.block(&format!("G5.2 {words} P{w} L{order} F{}", e.num(opts.feed_mm_per_min)));
        } else {
            e.block(&format!("{words} P{w}"));
        }
    }
    e.block("G5.3");
    let start = c.control_point(0);
    Body { start, text: e, path_blocks: Dialect::LinuxCnc.nurbs_blocks(c), top_z: start.z }
}
