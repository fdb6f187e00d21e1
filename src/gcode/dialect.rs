//! Controller dialects: the one seam between the program writers/readers and the words of a
//! particular control. See `docs/gcode-dialects.md` for each dialect's words and sources.
//!
//! A dialect is a plain enum with per-dialect functions rather than a trait: there are three
//! closed, known controllers; every `match` lists all of them, so adding a fourth makes the
//! compiler point at every place that must say something about it; the value is `Copy`,
//! comparable and printable, so options, tables and tests carry it as data. What differs:
//!
//! | | FANUC (default) | Sinumerik 840D | LinuxCNC |
//! |---|---|---|---|
//! | comments | `( … )` | `; …` | `( … )` |
//! | frame | `%`, `G21 G90 G94 G17`, `M30`, `%` | `G710 G90 G94 G17 G64`, `M30` | `%`, `G21 G90 G94 G17`, `G64 P…`, `M2`, `%` |
//! | motion words | `G00 G01 G02 G03` | `G0 G1 G2 G3` | `G0 G1 G2 G3` |
//! | NURBS | `G06.2` with explicit knots `K` | `BSPLINE SD= PL= PW=`, uniform knots | `G5.2 … G5.3`, uniform knots, XY only |

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use super::kind::ProgramKind;
use crate::geom::NurbsCurve;

/// A header comment the product's readers look for (written by `comment::key_comment`, defused in user text by `comment::safe_comment`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeaderKey {
    /// `DIALECT:` — the dialect a program is written in ([`super::Dialect::guess`]).
    Dialect,
    /// `PROGRAMMED POINT:` — the point of the tool the coordinates carry
    /// ([`super::ProgrammedPoint::from_comments`]).
    ProgrammedPoint,
}

impl HeaderKey {
    /// Both keys.
    pub const ALL: [Self; 2] = [Self::Dialect, Self::ProgrammedPoint];

    /// The key as written, colon included: `DIALECT:`, `PROGRAMMED POINT:`.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Dialect => "DIALECT:",
            Self::ProgrammedPoint => "PROGRAMMED POINT:",
        }
    }
}

/// A controller's G-code dialect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// FANUC (Series 15i/16i/18i/30i): `G06.2` NURBS with explicit knots. The default.
    #[default]
    Fanuc,
    /// Siemens Sinumerik 840D: `BSPLINE` with `SD=` degree, `PL=` knot interval, `PW=` weight.
    Sinumerik,
    /// LinuxCNC: `G5.2`/`G5.3` NURBS in the XY plane, `G64 P` blending tolerance.
    LinuxCnc,
}

/// A dialect name that is not one of ours.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("unknown G-code dialect '{0}'; use one of: fanuc, sinumerik, linuxcnc")]
pub struct UnknownDialect(pub String);

impl Dialect {
    /// All three, FANUC first.
    pub const ALL: [Self; 3] = [Self::Fanuc, Self::Sinumerik, Self::LinuxCnc];

    /// Command-line name: `fanuc`, `sinumerik`, `linuxcnc`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Fanuc => "fanuc",
            Self::Sinumerik => "sinumerik",
            Self::LinuxCnc => "linuxcnc",
        }
    }

    /// Human name of the controller.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Fanuc => "FANUC",
            Self::Sinumerik => "Sinumerik 840D",
            Self::LinuxCnc => "LinuxCNC",
        }
    }

    /// Table label of a program kind in this dialect's words (`G01`, `G1`, `G06.2`,
    /// `BSPLINE`, `G5.2` …).
    #[must_use]
    pub fn kind_label(self, kind: ProgramKind) -> &'static str {
        match (self, kind) {
            (Self::Fanuc, _) => kind.label(),
            (_, ProgramKind::Lines) => "G1",
            (_, ProgramKind::Arcs) => "G2/G3",
            (Self::Sinumerik, ProgramKind::Nurbs) => "BSPLINE",
            (Self::LinuxCnc, ProgramKind::Nurbs) => "G5.2",
        }
    }

    /// A motion word in this dialect: FANUC keeps the two-digit form (`G01`), the others
    /// write `G1`.
    #[must_use]
    pub fn motion_word(self, fanuc: &'static str) -> &'static str {
        if self == Self::Fanuc {
            return fanuc;
        }
        match fanuc {
            "G00" => "G0",
            "G01" => "G1",
            "G02" => "G2",
            "G03" => "G3",
            other => other,
        }
    }

    /// Whether the knots of a NURBS are written (FANUC `K`) or implied uniform (Sinumerik
    /// with one `PL` for every span, LinuxCNC always).
    #[must_use]
    pub fn uniform_knots(self) -> bool {
        self != Self::Fanuc
    }

    /// Degrees a NURBS of this dialect may have.
    #[must_use]
    pub fn nurbs_degrees(self) -> (usize, usize) {
        match self {
            // FANUC: order P2 to P4.
            Self::Fanuc => (1, 3),
            // Sinumerik: SD=3 (the default) or SD=2.
            Self::Sinumerik => (2, 3),
            // LinuxCNC: L is the order; the interpreter's default order is 3 and an L below 3
            // is not honoured by every version, so only orders 3 and 4.
            Self::LinuxCnc => (2, 3),
        }
    }

    /// Blocks a NURBS curve takes in this dialect: FANUC one per control point plus `order`
    /// closing knots; Sinumerik one per control point after the start (the start is the
    /// current position); LinuxCNC the same plus the closing `G5.3`.
    #[must_use]
    pub fn nurbs_blocks(self, c: &NurbsCurve) -> usize {
        match self {
            Self::Fanuc => c.len() + c.degree() + 1,
            Self::Sinumerik => c.len() - 1,
            Self::LinuxCnc => c.len(),
        }
    }

    /// The dialect of a program text, for readers not told: our own header comment
    /// (`DIALECT: …`), else words only one dialect uses (`BSPLINE`, `SD=`, `PL=`, `G710` →
    /// Sinumerik; `G5.2`, `G5.3` → LinuxCNC), else FANUC.
    #[must_use]
    pub fn guess(text: &str) -> Self {
        let upper = text.to_ascii_uppercase();
        for d in [Self::Sinumerik, Self::LinuxCnc, Self::Fanuc] {
            if upper.contains(&format!("{} {}", HeaderKey::Dialect.as_str(), d.as_str().to_ascii_uppercase())) {
                return d;
            }
        }
        let code_words = |line: &str| -> Vec<String> {
            // The line without comments, split into words.
            let mut s = String::new();
            let mut depth = 0usize;
            for c in line.chars() {
                match c {
                    ';' if depth == 0 => break,
                    '(' => depth += 1,
                    ')' => depth = depth.saturating_sub(1),
                    _ if depth == 0 => s.push(c),
                    _ => {}
                }
            }
            s.split_whitespace().map(str::to_owned).collect()
        };
        let mut linuxcnc = false;
        for line in upper.lines() {
            for w in code_words(line) {
                if w == "BSPLINE" || w.starts_with("SD=") || w.starts_with("PL=") || w.starts_with("PW=") || w == "G710"
                {
                    return Self::Sinumerik;
                }
                if matches!(w.as_str(), "G5.2" | "G5.3" | "G05.2" | "G05.3") {
                    linuxcnc = true;
                }
            }
        }
        if linuxcnc { Self::LinuxCnc } else { Self::Fanuc }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Dialect {
    type Err = UnknownDialect;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim().to_ascii_lowercase();
        Self::ALL.into_iter().find(|d| d.as_str() == t).ok_or_else(|| UnknownDialect(s.to_owned()))
    }
}
