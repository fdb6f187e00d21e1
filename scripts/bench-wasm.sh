#!/usr/bin/env bash
# Time to recompute a 10 000-period crease path, natively and as wasm32 under Node, from
# the same source (tests/bench_recompute.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
cargo test --release --no-default-features --test bench_recompute -- --ignored --nocapture 2>/dev/null | grep -E "^native"
cargo test --release --no-default-features --target wasm32-unknown-unknown --test bench_recompute -- --include-ignored --nocapture 2>/dev/null | grep -E "wasm32"
# Seed 001: a whole example surface's iso-scallop paths (tests/bench_fillet.rs).
cargo test --release --no-default-features --test bench_fillet -- --ignored --nocapture 2>/dev/null | grep -E "^native"
cargo test --release --no-default-features --target wasm32-unknown-unknown --test bench_fillet -- --include-ignored --nocapture 2>/dev/null | grep -E "wasm32"
# Ray-interval updates per second of the cutting simulation (tests/bench_simulate.rs).
cargo test --release --no-default-features --test bench_simulate -- --ignored --nocapture 2>/dev/null | grep -E "^native"
cargo test --release --no-default-features --target wasm32-unknown-unknown --test bench_simulate -- --include-ignored --nocapture 2>/dev/null | grep -E "wasm32"
