#!/usr/bin/env bash
# Builds the release app and serves it on 127.0.0.1 (PORT, default 8765).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
export PATH="$HOME/.cargo/bin:$PATH"
port="${PORT:-8765}"
trunk build --release
printf '\n\033[1minterpolab is served at http://127.0.0.1:%s/\033[0m  (Ctrl-C stops it)\n\n' "$port"
exec python3 -m http.server "$port" --bind 127.0.0.1 --directory dist
