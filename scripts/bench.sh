#!/usr/bin/env bash
# Builds proxygrasp in Release and runs `proxygrasp bench`, pinned to core 0 when taskset is there,
# writing the figures to out/bench.json (docs/performance.md, "proxygrasp bench"). With --docs
# first, the figures then replace the generated section of docs/performance.md
# (scripts/bench-docs.py).
#   bash scripts/bench.sh [--docs] [bench options...]     e.g. --frames 240 --repeat 3
set -euo pipefail
cd "$(dirname "$0")/.."
docs=0
if [ "${1:-}" = "--docs" ]; then
  docs=1
  shift
fi
bash scripts/configure.sh release
cmake --build --preset release --target proxygrasp
mkdir -p out
pin=()
if command -v taskset > /dev/null; then pin=(taskset -c 0); fi
"${pin[@]}" build/release/proxygrasp bench --json out/bench.json "$@"
if [ "$docs" = 1 ]; then python3 scripts/bench-docs.py out/bench.json docs/performance.md; fi
