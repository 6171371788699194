#!/usr/bin/env bash
# The README's test command: install what is missing, build (Release), run every test.
#   bash scripts/test.sh [preset]      preset: release (default), debug or asan
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
bash scripts/install-deps.sh
cmake --preset "$preset"
cmake --build --preset "$preset"
ctest --preset "$preset"
