#!/usr/bin/env bash
# Peak memory of a headless run against its length: the same level run for 60 s and for 600 s of
# simulated time (3,600 and 36,000 frames at 60 Hz), peak resident set size from /usr/bin/time -v.
#   bash scripts/memory.sh [LEVEL] [BINARY]
# Defaults: levels/side_push.toml and build/release/proxygrasp. Needs /usr/bin/time (package time).
set -euo pipefail
cd "$(dirname "$0")/.."
level="${1:-levels/side_push.toml}"
bin="${2:-build/release/proxygrasp}"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
declare -A rss
for frames in 3600 36000; do
  /usr/bin/time -v "$bin" run "$level" --frames "$frames" > /dev/null 2> "$log" || true
  rss[$frames]=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$log")
  echo "memory: $level, $frames frames ($((frames / 60)) s): peak RSS ${rss[$frames]} KB"
done
echo "memory: 600 s minus 60 s: $(( rss[36000] - rss[3600] )) KB"
