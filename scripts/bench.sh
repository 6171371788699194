#!/usr/bin/env bash
# Builds proxygrasp in Release and runs `proxygrasp bench`, pinned to core 0 when taskset is there,
# writing the figures to out/bench.json (docs/performance.md, "proxygrasp bench").
#   bash scripts/bench.sh [bench options...]     e.g. --frames 240 --repeat 3
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release
cmake --build --preset release --target proxygrasp
mkdir -p out
pin=()
if command -v taskset > /dev/null; then pin=(taskset -c 0); fi
exec "${pin[@]}" build/release/proxygrasp bench --json out/bench.json "$@"
