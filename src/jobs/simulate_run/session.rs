//! Stocks of one program kept between runs of the simulation job, so a replay of the move
//! slider starts from the nearest kept stock instead of the block.

use std::sync::Mutex;

use super::codec::move_numbers;
use crate::geom::Cutter;
use crate::simulate::{MoveKind, Program, Simulation};

/// Most bytes of stocks a [`Session`] keeps for replays (the stocks themselves, as
/// [`DexelStock::memory_bytes`](crate::simulate::DexelStock::memory_bytes) counts them): 8 of a
/// 512 × 512 grid (6 MiB each), 2 of a 1024 × 1024 one.
pub const KEPT_STOCK_BYTES: usize = 64 << 20;
/// Most stocks a [`Session`] keeps (evenly spaced over the program).
pub const MAX_KEPT_STOCKS: usize = 8;

/// What makes two runs machine the same stock: the program's moves (their kinds, rapid
/// flags and every number by its bits), the stock block, the pitch, the cutter and the
/// sampling step asked for. Two runs with equal keys leave bit-identical stocks after every
/// move, so one may start from the other's kept stock.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct SessionKey(Vec<u64>);

impl SessionKey {
    /// The key of a run of `program` on the block `stock_mm` (mm) at pitch `pitch_mm` (mm)
    /// with `cutter`, 5-axis moves sampled every `sample_step` (mm; `None`: the default).
    pub(super) fn of(
        program: &Program,
        stock_mm: &[f64; 6],
        pitch_mm: f64,
        cutter: &Cutter,
        sample_step: Option<f64>,
    ) -> Self {
        let mut key = Vec::with_capacity(program.moves.len() * 26 + 16);
        for m in &program.moves {
            key.push(u64::from(matches!(m.kind, MoveKind::Joints { .. })) | (u64::from(m.rapid) << 1));
            key.extend(move_numbers(m).into_iter().map(f64::to_bits));
        }
        key.push(program.moves.len() as u64);
        key.extend(stock_mm.iter().map(|x| x.to_bits()));
        key.push(pitch_mm.to_bits());
        key.extend(cutter.numbers().map(f64::to_bits));
        key.push(sample_step.map_or(u64::MAX, f64::to_bits));
        Self(key)
    }
}

/// Stocks of one program kept between runs, so a replay to move k (the move slider) starts
/// from the nearest kept stock at or before k instead of the block: the simulation state
/// ([`Simulation`]: stock, counters, last pose) after every `every` moves, cloned as a run
/// passes them, at most [`MAX_KEPT_STOCKS`] and [`KEPT_STOCK_BYTES`] in all. A run of
/// another program (another key) replaces the session. In a browser the session lives in the
/// Web Worker, which the page keeps between jobs (`app::jobs`); natively in the process.
#[derive(Debug, Default)]
pub struct Session {
    key: Option<SessionKey>,
    /// Bumped with every new key: a run offers its stocks only to the session it started
    /// (another program's run may have replaced it meanwhile, natively on another thread).
    generation: u64,
    every: usize,
    /// Kept states, in move order.
    pub(super) kept: Vec<Simulation>,
    bytes: usize,
}

/// The process's (the worker's) session.
pub(super) static SESSION: Mutex<Option<Session>> = Mutex::new(None);

impl Session {
    /// Moves between kept stocks for a program of `moves` moves on a stock of `bytes` bytes:
    /// as many stocks as the budget holds, at most [`MAX_KEPT_STOCKS`], spread evenly
    /// (0: none fit).
    #[must_use]
    pub fn spacing(moves: usize, bytes: usize) -> usize {
        let slots = (KEPT_STOCK_BYTES / bytes.max(1)).min(MAX_KEPT_STOCKS);
        if slots == 0 || moves < 2 { 0 } else { moves.div_ceil(slots + 1).max(1) }
    }

    /// Moves of the stocks kept, in order.
    #[must_use]
    pub fn kept_moves(&self) -> Vec<usize> {
        self.kept.iter().map(|s| s.counters().moves).collect()
    }

    /// Bytes of the stocks kept.
    #[must_use]
    pub fn kept_bytes(&self) -> usize {
        self.bytes
    }

    /// The session's generation and the state to start a run of `key` to move `target`
    /// from: a copy of the kept state nearest at or before `target`, if any. A different key
    /// starts a new session for it (`moves` moves, `bytes` bytes a stock).
    pub(super) fn start(&mut self, key: SessionKey, target: usize, moves: usize, bytes: usize) -> SessionStart {
        if self.key.as_ref() != Some(&key) {
            let generation = self.generation.wrapping_add(1);
            *self = Self { key: Some(key), generation, every: Self::spacing(moves, bytes), kept: Vec::new(), bytes: 0 };
            return SessionStart { generation, kept: None };
        }
        SessionStart {
            generation: self.generation,
            kept: self.kept.iter().rev().find(|s| s.counters().moves <= target).cloned(),
        }
    }

    /// Keeps a copy of `sim` (a state of the run that started generation `generation`) if
    /// its move is on the spacing, not kept yet and within budget.
    pub(super) fn offer(&mut self, generation: u64, sim: &Simulation) {
        let k = sim.counters().moves;
        if generation != self.generation || self.every == 0 || k == 0 || !k.is_multiple_of(self.every) {
            return;
        }
        let bytes = sim.stock().memory_bytes();
        let at = self.kept.partition_point(|s| s.counters().moves < k);
        if self.kept.get(at).is_some_and(|s| s.counters().moves == k)
            || self.kept.len() >= MAX_KEPT_STOCKS
            || self.bytes + bytes > KEPT_STOCK_BYTES
        {
            return;
        }
        self.kept.insert(at, sim.clone());
        self.bytes += bytes;
    }
}

/// Where a run starts ([`Session::start`]).
pub(super) struct SessionStart {
    /// The session's generation, to offer the run's stocks to.
    pub(super) generation: u64,
    /// A copy of the kept state nearest at or before the run's target, if any.
    pub(super) kept: Option<Simulation>,
}
