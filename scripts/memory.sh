#!/usr/bin/env bash
# Peak memory of a run against its length: the same level run for 60 s and for 600 s of simulated
# time (3,600 and 36,000 frames at 60 Hz), peak resident set size from /usr/bin/time -v.
#   bash scripts/memory.sh [--play] [LEVEL] [BINARY]
# Defaults: levels/side_push.toml and build/release/proxygrasp. `proxygrasp run` headless, or with
# --play the window (`play --input script --frames N`) under xvfb-run, whose peak RSS is that of
# its largest process, proxygrasp. Needs /usr/bin/time (package time), and xvfb for --play.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=run
if [ "${1:-}" = "--play" ]; then
  mode=play
  shift
fi
level="${1:-levels/side_push.toml}"
bin="${2:-build/release/proxygrasp}"
log="$(mktemp)"
shot="$(mktemp --suffix=.png)"
trap 'rm -f "$log" "$shot"' EXIT
declare -A rss
for frames in 3600 36000; do
  if [ "$mode" = play ]; then
    /usr/bin/time -v xvfb-run -a -s "-screen 0 1280x960x24" \
      "$bin" play "$level" --input script --frames "$frames" --screenshot "$shot" \
      > /dev/null 2> "$log" || true
  else
    /usr/bin/time -v "$bin" run "$level" --frames "$frames" > /dev/null 2> "$log" || true
  fi
  rss[$frames]=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$log")
  echo "memory: $mode $level, $frames frames ($((frames / 60)) s): peak RSS ${rss[$frames]} KB"
done
echo "memory: $mode, 600 s minus 60 s: $(( rss[36000] - rss[3600] )) KB"
