#!/usr/bin/env bash
# Builds the command line as it is shipped: release, without the app, linked statically
# (glibc's crt-static), into target/cli/interpolab.
#
# A statically linked process starts in about half the time of the dynamically linked one
# (no loader, no shared libraries to map and relocate: `interpolab --version` 0.5 ms instead
# of 1.1 ms of CPU), which is a third of a whole `run` on the examples. Only the final
# binary gets the flag (`cargo rustc`), so the library and every dependency are the ones
# `cargo build --release` already built; the native app (default features) stays dynamic,
# since winit and wgpu load their system libraries at run time.
#
#   scripts/build-cli.sh        # then: target/cli/interpolab run examples/torus-plane.json
set -euo pipefail
cd "$(dirname "$0")/.."
nice -n 5 cargo rustc --release --no-default-features --bin interpolab -- -C target-feature=+crt-static
mkdir -p target/cli
cp target/release/interpolab target/cli/interpolab
# Put the ordinary (dynamic) build back in target/release; its artefact is still cached.
nice -n 5 cargo build --release --no-default-features --bin interpolab
echo "target/cli/interpolab: $(file -b target/cli/interpolab | grep -o "static-pie linked\|statically linked\|dynamically linked")"
