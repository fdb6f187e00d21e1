#!/usr/bin/env bash
# Runs every check and test of the project; CI runs exactly this (.ci/run).
#   format, lints (native and wasm32), the core's tests natively and compiled to wasm32
#   under Node, the app's headless tests, doc tests, the release web build, and the
#   end-to-end test in headless Chromium.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh test
export PATH="$HOME/.cargo/bin:$PATH"
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
# Property tests draw the same cases on every run here, so a red CI is reproducible; change
# the seed (or leave it out: random) for exploration, as README's fuzzing section says.
export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261123}"
start=$(date +%s)
say() { printf '\n\033[1m== %s (%ss)\033[0m\n' "$*" "$(( $(date +%s) - start ))"; }

say "format"
cargo fmt --all --check

say "module graph: no cycle between modules, nor between the files of a directory"
python3 scripts/modgraph.py --files > /dev/null

say "API docs: every intra-doc link resolves (core, then with the app)"
RUSTDOCFLAGS="-D warnings" cargo doc --no-default-features --lib --no-deps --locked
RUSTDOCFLAGS="-D warnings" cargo doc --lib --no-deps --locked

say "lints: native, with the app"
cargo clippy --lib --bins --locked -- -D warnings
# Tests and benches may unwrap and compare floats exactly: a failure there is the point.
cargo clippy --tests --benches --locked -- -D warnings -A clippy::unwrap_used -A clippy::expect_used -A clippy::float_cmp
say "lints: the core for wasm32, and the app for wasm32"
cargo clippy --no-default-features --target wasm32-unknown-unknown --lib --locked -- -D warnings
cargo clippy --target wasm32-unknown-unknown --lib --bins --locked -- -D warnings
# The page's WebGPU build (feature `webgpu`, binary interpolab-webgpu; web/index.html).
cargo clippy --no-default-features --features webgpu --target wasm32-unknown-unknown --lib --bins --locked -- -D warnings
# The Web Worker's module (the core alone, feature `worker`; Trunk builds it beside the app).
cargo clippy --no-default-features --features worker --target wasm32-unknown-unknown --lib --bins --locked -- -D warnings

say "core tests, native (no GUI dependency)"
cargo test --no-default-features --locked

say "app tests, native (headless frames)"
cargo test --locked --lib --test app_headless

say "core tests compiled to wasm32, run under Node (same sources)"
# Without debuginfo the test modules stay small and load fast.
CARGO_PROFILE_DEV_DEBUG=false cargo test --no-default-features --target wasm32-unknown-unknown --tests --locked

say "release web build (trunk)"
trunk build --release

say "end-to-end in headless Chromium"
port="${E2E_PORT:-8797}"
python3 -m http.server "$port" --bind 127.0.0.1 --directory dist >/dev/null 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
for _ in $(seq 50); do
    curl -fs "http://127.0.0.1:$port/" >/dev/null 2>&1 && break
    sleep 0.1
done
node e2e/e2e.mjs "http://127.0.0.1:$port/"
# A share link with a hostile scene name: every program the app offers downloaded and its
# blocks checked, the page's title and markup unchanged (issue 29).
node e2e/hostile.mjs "http://127.0.0.1:$port/"
# The "Your program" tab: a multi-tool program with its tool table and subroutine file,
# simulated; LinuxCNC's impeller through its machine; a 180 000-line program (issues 21, 22).
node e2e/userprog.mjs "http://127.0.0.1:$port/"

say "all checks passed"
