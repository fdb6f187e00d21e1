//! The three kinds of program seed 004 compares (lines, arcs, NURBS). They sit in a file of
//! their own, below both the writers and the [`super::Dialect`] that names them in its words,
//! so that `dialect.rs` need not import `write.rs` (which imports `parse.rs`, which imports
//! `dialect.rs`): the files of `gcode` import each other without a cycle.

/// The three program kinds of seed 004's comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProgramKind {
    /// G01 straight lines (equal-error chords).
    Lines,
    /// G02/G03 arcs and G01 lines.
    Arcs,
    /// G06.2 NURBS.
    Nurbs,
}

impl ProgramKind {
    /// All three, in the comparison's order.
    pub const ALL: [Self; 3] = [Self::Lines, Self::Arcs, Self::Nurbs];

    /// Command-line name: `g01`, `arcs`, `nurbs`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Lines => "g01",
            Self::Arcs => "arcs",
            Self::Nurbs => "nurbs",
        }
    }

    /// Table label: `G01`, `G02/G03`, `G06.2`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Lines => "G01",
            Self::Arcs => "G02/G03",
            Self::Nurbs => "G06.2",
        }
    }
}
