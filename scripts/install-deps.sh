#!/usr/bin/env bash
# Installs the Debian 12 packages proxygrasp needs, and only those that are missing.
# Idempotent: runs `apt-get update` once, and only when something has to be installed.
# Works as root, or through sudo; otherwise prints the command to run.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake pkg-config git clang-format
  # the build tool the presets use, and a compiler cache: a second build, in any clone, compiles
  # only what changed (CMakeLists.txt)
  ninja-build ccache
  # libraries (see docs/architecture.md for where each is used)
  libbox2d-dev libopencv-dev libeigen3-dev libsdl2-dev libtomlplusplus-dev libcli11-dev libimgui-dev
  liblo-dev
  # depth cameras: Kinect v1 through libfreenect, OpenNI2 devices and ONI recordings
  # (docs/sensing.md, "Depth cameras"); the build works without them, those sources then say so
  libfreenect-dev libopenni2-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth liblo-tools
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  exit 0
fi

echo "install-deps: missing: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo_cmd=(sudo)
else
  echo "install-deps: need root to install them. Run:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update
"${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
echo "install-deps: done"
