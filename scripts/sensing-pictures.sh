#!/usr/bin/env bash
# The pictures of docs/sensing.md ("The sensing view"): every stage of the sensing chain on two
# real frames, written to docs/images/real/ with `proxygrasp sense --preview`. The footage stays in
# ../shared/real (its README asks that it not be copied into the repository), so these pictures
# are made here and not committed (.gitignore).
#   bash scripts/sensing-pictures.sh        (after a Release build: build/release/proxygrasp)
set -euo pipefail
cd "$(dirname "$0")/.."
real="${PROXYGRASP_REAL_DATA:-../shared/real}"
if [[ ! -d "$real" ]]; then
  echo "sensing-pictures: $real is absent: no real footage to draw (set PROXYGRASP_REAL_DATA)" >&2
  exit 1
fi
program=build/release/proxygrasp
if [[ ! -x "$program" ]]; then
  echo "sensing-pictures: $program is missing: build it first (cmake --preset release &&" \
       "cmake --build --preset release --target proxygrasp)" >&2
  exit 1
fi
mkdir -p docs/images/real
# The clips come without calibration: each is mapped linearly onto a table of 640x480 pixels
# times the scale its fingertips give (tests/sensing/testdata/real_labels.txt: 0.16 and 0.18 cm
# a pixel), as the tests map them.
# FTIR, bright: ten fingertips and two glowing arms (frame 80)
"$program" sense "$real/ccv-hand/seth_tests.avi" --frames 81 \
  --set table.width=102.4 --set table.height=76.8 \
  --preview docs/images/real/seth_80.png > /dev/null
# rear DI, dim: two hands a few grey levels above the table, four hot spots (frame 1800)
"$program" sense "$real/ccv-hand/t2.avi" --frames 1801 \
  --set table.width=115.2 --set table.height=86.4 \
  --preview docs/images/real/t2_1800.png > /dev/null
echo "sensing-pictures: wrote docs/images/real/seth_80.png and docs/images/real/t2_1800.png"
