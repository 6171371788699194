#!/usr/bin/env bash
# Configures a build folder from its preset: cmake --preset PRESET. The presets build with Ninja;
# a folder that an older checkout configured with another generator (Unix Makefiles) is cleared
# first, since CMake refuses to switch a folder's generator.
#   bash scripts/configure.sh [preset]      preset: release (default), debug or asan
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
cache="build/$preset/CMakeCache.txt"
if [ -f "$cache" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
  echo "configure: build/$preset was made with another generator; clearing it for Ninja"
  rm -rf "build/$preset"
fi
cmake --preset "$preset"
