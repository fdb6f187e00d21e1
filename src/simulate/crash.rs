//! Crashes: the tool meeting the stock where it must not, found while the program runs
//! (material removed by the blocks before counts; the block's own cut is ordered as below).
//!
//! # The model
//!
//! Lengths from the tool tip along its axis: the *flutes* up to the flute length F (they cut,
//! in every move, rapids included), the *shank* (radius, length) above them, the *holder*
//! (radius, length) above the shank ([`crate::geom::Cutter`]). The shank and holder never
//! cut. Four kinds of crash ([`CrashKind`]):
//!
//! - **shank** / **holder**: the part meets stock. On a 3-axis move the part's swept solid (a
//!   flat cylinder swept along the move) is checked, ray by ray, against the stock *after*
//!   the flutes of the same move cut when the move descends or stays level (the flutes go
//!   first: a plunge deeper than F into a hole the flutes cut is not a crash of a shank no
//!   wider than they), and *before* it when it climbs (the flutes at a later instant are
//!   higher, and would otherwise hide material the part met earlier). 5-axis moves check the
//!   part at poses no point of it moves more than [`POSE_STEP_PITCHES`] pitches between,
//!   after the move's cut.
//! - **rapid**: any part of the tool entering stock in a rapid (G0): the flutes' swept solid
//!   against the stock before the move, and the shank and holder as above (a rapid whose
//!   shank meets stock is both a shank and a rapid crash).
//! - **plunge**: a feed move descending more steeply than [`PLUNGE_MIN_DEG`] into stock with
//!   a tool that does not cut at its centre ([`crate::geom::Cutter::centre_cutting`]): the
//!   stock before the move on the ray nearest the end of the tip's path, between the two tip
//!   heights.
//!
//! Contact within [`TOUCH_MM`] is a touch, not a crash: each part (and, for a rapid, the
//! flutes) is checked shrunk by it in radius and raised by it at its bottom. The *depth* of a
//! crash is the most stock along one vertical ray inside the offending part's swept solid
//! (mm); its *place* is that ray at the top of that stock.
//!
//! Each kind is reported once per block (consecutive moves from the same line, the deepest
//! kept), at most [`MAX_CRASHES`] reports with counts of all.

use glam::DVec3;

/// Contact (mm) below which a part touching the stock is a touch, not a crash.
pub const TOUCH_MM: f64 = 1e-3;

/// Most crash reports kept (later ones are counted only).
pub const MAX_CRASHES: usize = 10_000;

/// The shank and holder of a 5-axis move are checked at poses no point of them moves more
/// than this many pitches between: an interference narrower than that between two poses
/// can be missed (the flutes' cut is sampled at one pitch).
pub const POSE_STEP_PITCHES: f64 = 4.0;

/// Descent angle (degrees from the horizontal) above which a feed move into stock is a
/// plunge: a tool that does not cut at its centre can ramp in below it.
pub const PLUNGE_MIN_DEG: f64 = 5.0;

/// What met the stock.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CrashKind {
    /// The shank (above the flutes) met stock.
    Shank,
    /// The holder met stock.
    Holder,
    /// The flutes entered stock in a rapid (G0).
    Rapid,
    /// A tool that does not cut at its centre plunged into stock.
    Plunge,
}

impl CrashKind {
    /// Every kind, in report order.
    pub const ALL: [Self; 4] = [Self::Shank, Self::Holder, Self::Rapid, Self::Plunge];

    /// Its name in files and on the command line (`shank`, `holder`, `rapid`, `plunge`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Shank => "shank",
            Self::Holder => "holder",
            Self::Rapid => "rapid",
            Self::Plunge => "plunge",
        }
    }

    /// What touched, in words.
    #[must_use]
    pub fn part(self) -> &'static str {
        match self {
            Self::Shank => "the shank",
            Self::Holder => "the holder",
            Self::Rapid => "the tool in a rapid (G0)",
            Self::Plunge => "the centre of an end that does not cut there",
        }
    }

    /// Index in [`Self::ALL`].
    #[must_use]
    pub fn index(self) -> usize {
        match self {
            Self::Shank => 0,
            Self::Holder => 1,
            Self::Rapid => 2,
            Self::Plunge => 3,
        }
    }
}

/// One crash: a kind in one block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crash {
    /// What met the stock.
    pub kind: CrashKind,
    /// 1-based line of the block (0 for in-memory programs).
    pub line: usize,
    /// Index of the block's first move in the program.
    pub move_index: usize,
    /// Tool slot in the spindle ([`super::Simulation::set_tool`]).
    pub slot: u16,
    /// The most stock along one vertical ray inside the part (mm).
    pub depth_mm: f64,
    /// That ray at the top of that stock (mm).
    pub at_mm: DVec3,
    /// The tool tip at the end of the move where the deepest one was found (mm).
    pub tip_mm: DVec3,
}

/// The crashes of a run, as it goes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CrashLog {
    list: Vec<Crash>,
    counts: [usize; 4],
    /// Per kind, the report of the block being run, when it has one.
    open: [Option<usize>; 4],
}

impl CrashLog {
    /// A new block starts: its crashes are reported apart from the last one's.
    pub fn begin_block(&mut self) {
        self.open = [None; 4];
    }

    /// Records a crash of the block being run: a kind already reported in it keeps the
    /// deepest.
    pub fn record(&mut self, c: Crash) {
        let k = c.kind.index();
        // An open report past the cap is `usize::MAX`: counted, not kept.
        if let Some(i) = self.open[k] {
            if let Some(old) = self.list.get_mut(i)
                && c.depth_mm > old.depth_mm
            {
                *old = Crash { move_index: old.move_index, ..c };
            }
            return;
        }
        self.counts[k] += 1;
        if self.list.len() < MAX_CRASHES {
            self.open[k] = Some(self.list.len());
            self.list.push(c);
        } else {
            self.open[k] = Some(usize::MAX);
        }
    }

    /// The reports kept, in the order the program ran.
    #[must_use]
    pub fn list(&self) -> &[Crash] {
        &self.list
    }

    /// Blocks with a crash of each kind ([`CrashKind::ALL`]'s order), dropped ones included.
    #[must_use]
    pub fn counts(&self) -> [usize; 4] {
        self.counts
    }

    /// Blocks with a crash of a kind.
    #[must_use]
    pub fn count(&self, kind: CrashKind) -> usize {
        self.counts[kind.index()]
    }

    /// All crash reports, dropped ones included.
    #[must_use]
    pub fn total(&self) -> usize {
        self.counts.iter().sum()
    }

    /// Reports counted but not kept (past [`MAX_CRASHES`]).
    #[must_use]
    pub fn dropped(&self) -> usize {
        self.total() - self.list.len()
    }

    /// The reports as CSV: `line,kind,part,tool_slot,depth_mm,x_mm,y_mm,z_mm,tip_x_mm,tip_y_mm,tip_z_mm`
    /// (lengths to the micrometre's thousandth).
    #[must_use]
    pub fn csv(&self, tool_number: impl Fn(u16) -> Option<i32>) -> String {
        let mut s = String::from("line,kind,part,tool,depth_mm,x_mm,y_mm,z_mm,tip_x_mm,tip_y_mm,tip_z_mm\n");
        let nm = |v: f64| (v * 1e6).round() / 1e6 + 0.0;
        for c in &self.list {
            let tool = tool_number(c.slot).map_or_else(String::new, |t| t.to_string());
            s.push_str(&format!(
                "{},{},\"{}\",{},{},{},{},{},{},{},{}\n",
                c.line,
                c.kind.name(),
                c.kind.part(),
                tool,
                nm(c.depth_mm),
                nm(c.at_mm.x),
                nm(c.at_mm.y),
                nm(c.at_mm.z),
                nm(c.tip_mm.x),
                nm(c.tip_mm.y),
                nm(c.tip_mm.z)
            ));
        }
        s
    }

    /// One line for a person: the counts per kind and the first crash, or `None` without
    /// crashes.
    #[must_use]
    pub fn summary(&self) -> Option<String> {
        let total = self.total();
        if total == 0 {
            return None;
        }
        let kinds: Vec<String> = CrashKind::ALL
            .iter()
            .filter(|k| self.count(**k) > 0)
            .map(|k| format!("{} {}", self.count(*k), k.name()))
            .collect();
        let first = self.list.first().map_or_else(String::new, |c| {
            format!(
                "; the first at line {}: {} {:.3} mm into the stock at ({:.3}, {:.3}, {:.3}) mm",
                c.line,
                c.kind.part(),
                c.depth_mm,
                c.at_mm.x,
                c.at_mm.y,
                c.at_mm.z
            )
        });
        Some(format!("{total} crash(es) ({}){first}", kinds.join(", ")))
    }
}

/// A part of a tool that does not cut: a cylinder around the axis between two heights above
/// the tip (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    /// Radius (mm).
    pub radius_mm: f64,
    /// Height of its bottom above the tip (mm).
    pub from_mm: f64,
    /// Height of its top above the tip (mm).
    pub to_mm: f64,
}

impl Part {
    /// The part shrunk by [`TOUCH_MM`] (radius, bottom and top), `None` when nothing is left.
    #[must_use]
    pub fn checked(&self) -> Option<Self> {
        let p = Self {
            radius_mm: self.radius_mm - TOUCH_MM,
            from_mm: self.from_mm + TOUCH_MM,
            to_mm: self.to_mm - TOUCH_MM,
        };
        (p.radius_mm > 0.0 && p.to_mm > p.from_mm).then_some(p)
    }
}
