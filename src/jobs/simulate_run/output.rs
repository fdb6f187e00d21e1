//! What a run of the simulation job hands back: the program made (the first partial output),
//! keyframes of the stock while it runs, and the stock and its measures at the end.

use crate::simulate::stock::Grid;
use crate::simulate::{Counters, HeightMap, Program, SimStats};

/// The program made, with the stock it is cut into (the first partial output).
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    /// The moves.
    pub program: Program,
    /// Stock block used (mm).
    pub stock_mm: [f64; 6],
    /// Pitch used (mm).
    pub pitch_mm: f64,
    /// The stock's grid.
    pub grid: Grid,
    /// The design: `"none"`, `"plane"`, `"scene surfaces"` or `"finish surface"`.
    pub design_name: &'static str,
    /// Moves the run goes to.
    pub target: usize,
    /// Moves between keyframes (0: no keyframes).
    pub keyframe_every: usize,
}

/// The stock after some moves, for the view (heights in `f32`, enough for drawing).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    /// Moves applied.
    pub moves: usize,
    /// The run's counts then.
    pub counters: Counters,
    /// Top of each ray (mm, row-major as [`HeightMap::top_mm`]).
    pub top_mm: Vec<f32>,
    /// Whether each ray was machined.
    pub machined: Vec<bool>,
}

impl Keyframe {
    /// The keyframe as a height map of `grid` (heights widened to `f64`).
    #[must_use]
    pub fn map(&self, grid: Grid) -> HeightMap {
        HeightMap {
            grid,
            top_mm: self.top_mm.iter().map(|&z| f64::from(z)).collect(),
            machined: self.machined.clone(),
            through: 0,
        }
    }
}

/// A partial output.
#[derive(Clone, Debug, PartialEq)]
pub enum Partial {
    /// The program is made.
    Prepared(Box<Prepared>),
    /// The stock after some moves.
    Keyframe(Keyframe),
}

/// The run's result at its target move.
#[derive(Clone, Debug, PartialEq)]
pub struct Finished {
    /// Counts of the run (from move 0, also when it started from a kept stock).
    pub counters: Counters,
    /// The move of the kept stock the run started from ([`Session`](super::session::Session);
    /// 0: the whole block).
    pub resumed_from: usize,
    /// The stock's height map.
    pub map: HeightMap,
    /// Its measures against the design.
    pub stats: SimStats,
}
