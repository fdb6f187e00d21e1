#!/usr/bin/env bash
# Builds the command line as it is shipped: release, without the app, linked statically
# (glibc's crt-static) and not position-independent, into target/cli/interpolab.
#
# Measured (docs/speed.md, "Third round"):
# - static: no loader, no shared libraries to map and relocate (`interpolab --version`
#   0.5 ms instead of 1.1 ms of CPU);
# - not position-independent (`-C relocation-model=static`): a static-pie binary applies
#   its ~4 000 relative relocations at every start, writing (and so copying) the pages of
#   its vtables and constant tables; at a fixed address there are none (`--version`: 94 → 79
#   page faults, 0.43 M → 0.37 M instructions).
# Fat LTO was tried and is not used: 2 % fewer instructions on the analytic scenes, 4–8 %
# more on the NURBS ones (the NURBS evaluation is generated differently).
# Both flags reach only the final binary (`cargo rustc`), so the library and every
# dependency are the ones `cargo build --release` already built; the native app (default
# features) stays dynamic, since winit and wgpu load their system libraries at run time.
#
#   scripts/build-cli.sh        # then: target/cli/interpolab run examples/torus-plane.json
set -euo pipefail
cd "$(dirname "$0")/.."
nice -n 5 cargo rustc --release --no-default-features --bin interpolab -- \
    -C target-feature=+crt-static -C relocation-model=static
mkdir -p target/cli
cp target/release/interpolab target/cli/interpolab
# Put the ordinary (dynamic) build back in target/release; its artefact is still cached.
nice -n 5 cargo build --release --no-default-features --bin interpolab
echo "target/cli/interpolab: $(file -b target/cli/interpolab | grep -o "static-pie linked\|statically linked\|dynamically linked")"
