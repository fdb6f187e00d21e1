#!/usr/bin/env bash
# Installs what this project needs and a fresh machine lacks, skipping what is there.
# Nothing prebuilt is downloaded from the internet: tools are built from crates.io, the
# browser and LinuxCNC's reference interpreter come from Debian, the test driver from npm.
#
#   scripts/setup.sh build   # enough to build and serve the app
#   scripts/setup.sh test    # also the browser, rs274 and npm packages the tests need
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
what="${1:-test}"

# Tool versions, in one place. wasm-bindgen-cli must equal the wasm-bindgen in Cargo.lock.
TRUNK_VERSION="0.21.14"   # newest trunk that builds with Rust 1.95 (0.22 needs 1.96.1)
WASM_BINDGEN_VERSION="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)"

say() { printf '\033[1m== %s\033[0m\n' "$*"; }

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    say "adding the wasm32-unknown-unknown target"
    rustup target add wasm32-unknown-unknown
fi

if ! trunk --version 2>/dev/null | grep -q " $TRUNK_VERSION\$"; then
    say "building trunk $TRUNK_VERSION from crates.io (about 6 minutes on 2 cores)"
    cargo install --locked trunk --version "$TRUNK_VERSION"
fi

if ! wasm-bindgen --version 2>/dev/null | grep -q " $WASM_BINDGEN_VERSION\$"; then
    say "building wasm-bindgen-cli $WASM_BINDGEN_VERSION from crates.io (about 2–3 minutes)"
    # Its own lock file pins a webpki-roots release the registry here lacks; fall back to a
    # fresh resolution of the same, exactly pinned, wasm-bindgen-cli version.
    cargo install --locked wasm-bindgen-cli --version "=$WASM_BINDGEN_VERSION" \
        || cargo install wasm-bindgen-cli --version "=$WASM_BINDGEN_VERSION"
fi

# wasm-opt for release web builds (Trunk's post_build hook web/wasm-opt.mjs): binaryen's
# JS/wasm build from npm, pinned in web/package-lock.json. (Trunk would download a prebuilt
# binary; Debian's binaryen 108 produces a broken module.)
if [ ! -x web/node_modules/.bin/wasm-opt ]; then
    if command -v npm >/dev/null 2>&1; then
        say "installing wasm-opt (npm: binaryen) for release web builds"
        (cd web && npm ci --no-audit --no-fund --loglevel=error)
    else
        say "npm not found: release web builds will not be shrunk by wasm-opt"
    fi
fi

if [ "$what" = "test" ]; then
    if ! command -v chromium >/dev/null 2>&1; then
        say "installing Debian's chromium for the browser tests"
        sudo_cmd=""
        [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
        $sudo_cmd apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq chromium
    fi
    # LinuxCNC's standalone interpreter `rs274` and its sample programs
    # (/usr/share/linuxcnc/ncfiles): the reference the G-code interpreter is compared with
    # (tests/reference/, scripts/corpus.py).
    if ! command -v rs274 >/dev/null 2>&1; then
        say "installing Debian's linuxcnc-uspace (LinuxCNC's rs274 interpreter and sample programs)"
        sudo_cmd=""
        [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
        $sudo_cmd apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends linuxcnc-uspace
    fi
    if [ ! -d e2e/node_modules/playwright-core ] || [ ! -d e2e/node_modules/pngjs ]; then
        say "installing the end-to-end test driver (npm: playwright-core, pngjs; no browser download)"
        (cd e2e && npm ci --no-audit --no-fund --loglevel=error)
    fi
fi
