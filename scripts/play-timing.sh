#!/usr/bin/env bash
# Times `proxygrasp play --input mouse` with a flat hand held down and moved by a real X mouse
# (issue 17: "play --input mouse with a flat hand holds 60 Hz"). Runs the window on a virtual
# display (Xvfb, software rendering, as on a machine without a GPU) and drives it with xdotool:
# Shift + left button (a flat hand) pressed on the table, then moved round a circle for the
# whole run. Prints play's `--timing` line: the work per frame against the 16.7 ms of a frame.
#
#   bash scripts/play-timing.sh [LEVEL] [FRAMES]      (defaults: levels/demo_sort.toml, 1200)
#
# Needs the packages xvfb and xdotool (apt-get install -y xvfb xdotool); not part of the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
level=${1:-levels/demo_sort.toml}
frames=${2:-1200}
bin=build/release/proxygrasp
for tool in Xvfb xdotool; do
  command -v "$tool" > /dev/null || { echo "play-timing: $tool is missing (apt-get install -y xvfb xdotool)" >&2; exit 2; }
done
[ -x "$bin" ] || { echo "play-timing: $bin is missing (cmake --build --preset release)" >&2; exit 2; }

display=:77
Xvfb "$display" -screen 0 1280x960x24 > /dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2> /dev/null || true' EXIT
export DISPLAY=$display
sleep 1

# the window fills the screen at 1280x960 from (0, 0); the table is drawn inside it
"$bin" play "$level" --input mouse --frames "$frames" --timing > /tmp/play-timing.out 2>&1 &
play=$!
window=""
for _ in $(seq 50); do
  window=$(xdotool search --name proxygrasp 2> /dev/null | head -1 || true)
  [ -n "$window" ] && break
  sleep 0.1
done
[ -n "$window" ] || { echo "play-timing: the window did not open" >&2; cat /tmp/play-timing.out >&2; exit 1; }

xdotool mousemove 640 480 keydown shift mousedown 1
# a circle of 200 px radius, a point every 10 ms, until play ends
step=0
while kill -0 "$play" 2> /dev/null; do
  read -r x y < <(awk -v s="$step" 'BEGIN { a = s * 0.05; printf "%d %d\n", 640 + 200 * cos(a), 480 + 200 * sin(a) }')
  xdotool mousemove "$x" "$y" 2> /dev/null || true
  step=$((step + 1))
  sleep 0.01
done
xdotool mouseup 1 keyup shift 2> /dev/null || true
wait "$play" || true
cat /tmp/play-timing.out
