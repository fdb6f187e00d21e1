//! What a run of the simulation job is asked: where its program comes from, the cutter,
//! the stock and grid, the design it is measured against, and how far it goes.

use crate::fillet::CcNode;
use crate::gcode::ProgramKind;
use crate::geom::Cutter;
use crate::simulate::Program;
use crate::simulate::bench::BenchKind;

/// Most rays a run simulates (a 1024 × 1024 grid, 24 MiB of stock); above it the run is
/// refused before it starts.
pub const MAX_RAYS: usize = 1024 * 1024;
/// Longest side (rays) of the grid an automatic pitch aims at.
pub const AUTO_GRID_SIDE: f64 = 256.0;
/// Pitch range offered (mm).
pub const PITCH_RANGE_MM: (f64, f64) = (0.02, 0.5);

/// Where the program comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgramSource {
    /// The crease of the scene in this JSON text as a program of this kind (ball centres,
    /// written by [`write_program`](crate::gcode::write_program) within
    /// [`PROGRAM_TOL_MM`](super::program::PROGRAM_TOL_MM), moved down by the cutter radius to
    /// the tool tip).
    Crease {
        /// `interpolab-scene/1` text.
        scene: String,
        /// G01, G02/G03 or G06.2.
        kind: ProgramKind,
    },
    /// The scene's seed-002 five-axis tool steps within
    /// [`PROGRAM_TOL_MM`](super::program::PROGRAM_TOL_MM), joints interpolated linearly.
    Steps {
        /// `interpolab-scene/1` text.
        scene: String,
    },
    /// A G-code program's text (a file the user opened); a program of ball centres (its
    /// header says so) is moved down by the cutter radius.
    Text {
        /// Its name, for messages.
        name: String,
        /// The program.
        text: String,
    },
    /// Moves already made (an earlier run's
    /// [`Prepared::program`](super::output::Prepared::program)).
    Moves(Program),
    /// A seed-001 finishing program: its passes' CC nodes, planned in the job pass by pass into
    /// seed-002 steps ([`FinishProgram::plan_pass`](crate::simulate::FinishProgram::plan_pass))
    /// on the machine and surface of the finishing scene, joints interpolated linearly — off
    /// the page's thread.
    Finish {
        /// The finishing scene (`FinishScene::to_json`): its surface and machine.
        scene: String,
        /// The cutter that machines the passes (the strategy's).
        cutter: Cutter,
        /// The CC nodes of every pass, in travel order.
        passes: Vec<Vec<CcNode>>,
        /// Tolerance E (mm) of the steps.
        step_tol_mm: f64,
    },
    /// A benchmark program built in the job from its kind and move count
    /// ([`crate::simulate::bench`]): the browser's measurement of the native benchmark,
    /// without the program's text handed to the worker.
    Benchmark {
        /// Which program.
        kind: BenchKind,
        /// Its moves (at most [`crate::simulate::bench::MAX_BENCH_MOVES`]).
        moves: usize,
    },
}

/// What the machined stock is compared with.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignSpec {
    /// Nothing: heights only.
    None,
    /// The plane z = value (mm), material below.
    PlaneZ(f64),
    /// The surfaces of the scene in this JSON text.
    Scene(String),
    /// The machined surface of the seed-001 finishing scene in this JSON text
    /// (`FinishScene::to_json`), material on the side away from the cutter.
    Finish(String),
}

/// A run.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The program.
    pub source: ProgramSource,
    /// The cutter.
    pub cutter: Cutter,
    /// Pitch (mm); `None`: automatic (at most [`AUTO_GRID_SIDE`] rays a side).
    pub pitch_mm: Option<f64>,
    /// Stock block `x0, y0, z0, x1, y1, z1` (mm); `None`: the program's box plus margin.
    pub stock_mm: Option<[f64; 6]>,
    /// Margin (mm) around the program's box of an automatic stock.
    pub margin_mm: f64,
    /// Largest step (mm) between the sampled poses of a flat or fillet cutter's 5-axis move;
    /// `None`: one pitch. Between two poses the cutter leaves a cusp of about s²/(8r), so a
    /// program judged on a scallop h needs s well under √(8·r·h) (a ball's moves are swept
    /// in closed form and ignore it).
    pub max_sample_step_mm: Option<f64>,
    /// The design.
    pub design: DesignSpec,
    /// Move to machine up to (`None`: all).
    pub target: Option<usize>,
    /// Most keyframes to hand back (0: none).
    pub keyframes: usize,
    /// Whether the run may start from a stock an earlier run of the same program kept
    /// ([`Session`](super::session::Session); a replay of the move slider) instead of the
    /// block. Every run keeps stocks for later ones; a program's first run starts from the
    /// block so it sends all its keyframes.
    pub resume: bool,
}

impl Request {
    /// The benchmark program `kind` of `moves` moves as the benchmarks machine it (the CLI's
    /// `simulate --benchmark`, `benches/native_and_wasm/simulate.rs`): a ball of
    /// [`crate::simulate::bench::BALL_MM`] on the benchmark block at `pitch_mm` (mm), no
    /// design, no keyframes, from the block.
    ///
    /// # Errors
    /// None for the benchmark's ball (the cutter's constructor is fallible in general).
    pub fn benchmark(kind: BenchKind, moves: usize, pitch_mm: f64) -> Result<Self, crate::geom::CutterError> {
        Ok(Self {
            source: ProgramSource::Benchmark { kind, moves },
            cutter: Cutter::ball(crate::simulate::bench::BALL_MM)?,
            pitch_mm: Some(pitch_mm),
            stock_mm: Some(BenchKind::stock_mm()),
            margin_mm: 0.0,
            max_sample_step_mm: None,
            design: DesignSpec::None,
            target: None,
            keyframes: 0,
            resume: false,
        })
    }
}
