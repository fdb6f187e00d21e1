#!/usr/bin/env bash
# Builds the command line as it is shipped: profile `cli` (release with fat LTO and one
# codegen unit), without the app, linked statically (glibc's crt-static) and not
# position-independent, into target/cli/interpolab.
#
# Why each, measured (docs/speed.md, "Third round"):
# - static: no loader, no shared libraries to map and relocate (`interpolab --version`
#   0.5 ms instead of 1.1 ms of CPU);
# - not position-independent (`-C relocation-model=static`): a static-pie binary applies
#   its 4 000 relative relocations at every start, writing (and so copying) the pages of its
#   vtables and constant tables; a fixed address has none (94 → 79 page faults, about
#   0.05 ms less per process);
# - fat LTO: the row writer, the number formatter and the geometry inline across crates
#   (4 % fewer instructions per `run`).
# The two codegen flags reach only the final binary (`cargo rustc`); with LTO they apply to
# the whole program, which is generated there. The native app (default features) stays an
# ordinary dynamic release build: winit and wgpu load their system libraries at run time.
#
#   scripts/build-cli.sh        # then: target/cli/interpolab run examples/torus-plane.json
set -euo pipefail
cd "$(dirname "$0")/.."
nice -n 5 cargo rustc --profile cli --no-default-features --bin interpolab -- \
    -C target-feature=+crt-static -C relocation-model=static
echo "target/cli/interpolab: $(file -b target/cli/interpolab | grep -o "static-pie linked\|statically linked\|dynamically linked")"
