#!/usr/bin/env bash
# The README's main command: install what is missing, build Release, play the default demo level
# in a window. With no display, `play` runs the demo headless and writes a video and a PNG instead,
# and says where they are.
#   bash scripts/play.sh [LEVEL] [play options...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/configure.sh release
# only what it plays: the proxygrasp program (the test command builds the rest)
cmake --build --preset release --target proxygrasp
exec build/release/proxygrasp play "$@"
