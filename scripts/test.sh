#!/usr/bin/env bash
# The README's test command: install what is missing, build (Release), run every test.
#   bash scripts/test.sh [preset]      preset: release (default), debug or asan
# With PROXYGRASP_PHASE_TIMES=FILE set (.ci/run sets it), the seconds of the build and of the tests
# are appended to FILE as "<preset> build <s>" and "<preset> tests <s>" lines.
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
bash scripts/install-deps.sh
start=$(date +%s)
bash scripts/configure.sh "$preset"
cmake --build --preset "$preset"
built=$(date +%s)
ctest --preset "$preset"
tested=$(date +%s)
if [ -n "${PROXYGRASP_PHASE_TIMES:-}" ]; then
  echo "$preset build $((built - start))" >> "$PROXYGRASP_PHASE_TIMES"
  echo "$preset tests $((tested - built))" >> "$PROXYGRASP_PHASE_TIMES"
fi
