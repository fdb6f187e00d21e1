#!/usr/bin/env bash
# The benchmarks of benches/native_and_wasm/, natively and as wasm32 under Node, from the
# same source: a 10 000-period crease recompute (recompute.rs), seed 001's paths on a whole
# example surface (fillet.rs), ray-interval updates per second of the cutting simulation and
# its worker job (simulate.rs), a million-line program through the interpreter (interp.rs),
# the feed planner on a 100 000-block program (plan.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
for bench in recompute fillet simulate interp plan; do
    cargo test --release --no-default-features --test native_and_wasm "$bench::" -- --ignored --nocapture 2>/dev/null | grep -E "^native"
    cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm "$bench::" -- --include-ignored --nocapture 2>/dev/null | grep -E "wasm32"
done
