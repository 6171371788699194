#!/usr/bin/env bash
# Times `proxygrasp play --input mouse` with a flat hand held down and moved by a real X mouse
# (issue 17: "play --input mouse with a flat hand holds 60 Hz"). Runs the window on a virtual
# display (Xvfb, software rendering, as on a machine without a GPU) and drives it with xdotool:
# Shift + left button (a flat hand) pressed on the table, then moved round a circle for the
# whole run. Prints play's `--timing` line: the work per frame against the 16.7 ms of a frame,
# and fails unless the hand was down (one contact) in every timed frame.
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

# a display of its own: the first number without an X server's lock
n=77
while [ -e "/tmp/.X$n-lock" ] || [ -e "/tmp/.X11-unix/X$n" ]; do n=$((n + 1)); done
display=:$n
Xvfb "$display" -screen 0 1280x960x24 -nolisten tcp > /dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2> /dev/null || true' EXIT
export DISPLAY=$display
for _ in $(seq 50); do
  xdotool getmouselocation > /dev/null 2>&1 && break
  sleep 0.1
done

# the window fills the screen at 1280x960 from (0, 0); the table is drawn inside it
"$bin" play "$level" --input mouse --frames "$frames" --timing > /tmp/play-timing.out 2>&1 &
play=$!
window=""
for _ in $(seq 100); do
  window=$(xdotool search --onlyvisible --name proxygrasp 2> /dev/null | head -1 || true)
  [ -n "$window" ] && break
  sleep 0.1
done
[ -n "$window" ] || { echo "play-timing: the window did not open" >&2; cat /tmp/play-timing.out >&2; exit 1; }

sleep 0.3  # the window mapped and focused before the press (within play's untimed first second)
xdotool mousemove 640 480 keydown shift mousedown 1
# a circle of 200 px radius, a point every 16 ms, until play ends: one xdotool process moves the
# mouse 100 times, so that driving it costs the machine little beside play and the X server
turn=0
while kill -0 "$play" 2> /dev/null; do
  chain=$(awk -v t="$turn" 'BEGIN { for (s = 0; s < 100; ++s) { a = (t * 100 + s) * 0.05;
    printf "mousemove %d %d sleep 0.016 ", 640 + 200 * cos(a), 480 + 200 * sin(a) } }')
  # shellcheck disable=SC2086
  xdotool $chain 2> /dev/null || true
  turn=$((turn + 1))
done
xdotool mouseup 1 keyup shift 2> /dev/null || true
wait "$play" || true
cat /tmp/play-timing.out
# the hand must have been down: one contact in every timed frame
grep -q "per frame 1.00 contacts" /tmp/play-timing.out ||
  { echo "play-timing: the mouse hand was not down in every timed frame" >&2; exit 1; }
