#!/usr/bin/env bash
# The README's main command: install what is missing, build Release, play the default demo level.
# With no display it runs the demo headless and writes a video and a PNG instead.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release
cmake --build --preset release
exe=build/release/proxygrasp
if "$exe" play --help >/dev/null 2>&1; then
  exec "$exe" play "$@"
fi
# until the app exists, show what the command offers
exec "$exe" --help
