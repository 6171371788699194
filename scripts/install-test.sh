#!/usr/bin/env bash
# The install test (issue 46): installs a built folder into an empty temporary prefix and uses it
# as someone without the source tree would, from a folder outside it:
#   1. PREFIX/bin/proxygrasp --help, run demo_sort (by name, from share/proxygrasp/levels), a
#      level by file path, and an unknown name (exit 2 naming the folders searched);
#   2. every installed header compiles alone against the prefix (pkg-config --cflags proxygrasp);
#   3. examples/contours and examples/camera build with find_package(proxygrasp) against the
#      prefix; embed_contours must push the box, embed_camera must refuse a missing camera with a
#      clear error and replay a recording made by the installed command;
#   4. cpack -G DEB: the packages' file lists and Depends; as root with apt, the packages are
#      installed, `proxygrasp --help` and `proxygrasp run demo_sort` run, and they are removed.
#   bash scripts/install-test.sh [build-folder]      default build/release (built beforehand)
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=$(pwd)
build=$(realpath "${1:-build/release}")
[ -f "$build/CMakeCache.txt" ] || { echo "install-test: $build is not a configured build folder" >&2; exit 2; }
start=$(date +%s)
work=$(mktemp -d /tmp/pg_install_test.XXXXXX)
installed_debs=""
cleanup() {
  if [ -n "$installed_debs" ]; then apt-get remove -y -qq proxygrasp-dev proxygrasp > /dev/null 2>&1 || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
prefix="$work/prefix"
fail() { echo "install-test: FAIL: $*" >&2; exit 1; }
step() { echo "== install-test: [$(($(date +%s) - start)) s] $*"; }

step "cmake --install into $prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
pg="$prefix/bin/proxygrasp"
[ -x "$pg" ] || fail "no $pg"

# 1. the installed command, from a folder outside the source tree with no levels/ of its own
mkdir -p "$work/elsewhere"
cd "$work/elsewhere"
step "installed command: --help, run demo_sort, run a level by path, an unknown name"
"$pg" --help > "$work/help.txt" || fail "proxygrasp --help"
grep -q "run" "$work/help.txt" || fail "--help lists no run"
"$pg" run demo_sort > "$work/run.txt" || { cat "$work/run.txt"; fail "proxygrasp run demo_sort"; }
grep -q "=> PASS" "$work/run.txt" || fail "run demo_sort printed no PASS"
grep -q "$prefix/share/proxygrasp/levels/demo_sort.toml" "$work/run.txt" ||
  { cat "$work/run.txt"; fail "run demo_sort did not play the installed level"; }
"$pg" run "$prefix/share/proxygrasp/levels/side_push.toml" > /dev/null || fail "run side_push by path"
set +e
"$pg" run side_psuh > "$work/bad.txt" 2>&1
rc=$?
set -e
[ "$rc" = 2 ] || fail "an unknown level name exited $rc, not 2"
grep -q "did you mean .side_push." "$work/bad.txt" || { cat "$work/bad.txt"; fail "no hint for a misspelt name"; }

# 2. the installed headers are the public ones (the build compiles each alone: proxygrasp_header_check
# in cmake/ProxygraspInstall.cmake), and all of them compile through the pkg-config file
step "installed headers: the public list, compiled through pkg-config proxygrasp"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig:$prefix/lib/$(gcc -print-multiarch)/pkgconfig"
cflags=$(pkg-config --cflags proxygrasp) || fail "pkg-config --cflags proxygrasp"
headers=$(cd "$prefix/include" && find proxygrasp -name '*.h' | sort)
[ -d "$build/header_check" ] || fail "$build has no header_check/ (a sanitizer build? use build/release)"
expected=$(ls "$build"/header_check/*.cpp | wc -l)
[ "$(echo "$headers" | wc -l)" = "$expected" ] || fail "$(echo "$headers" | wc -l) headers installed, $expected public"
echo "$headers" | sed 's/.*/#include <&>/' > "$work/all_headers.cpp"
# shellcheck disable=SC2086
g++ -std=c++20 -fsyntax-only -w $cflags "$work/all_headers.cpp" || fail "the installed headers do not compile"
echo "  $expected headers"
# the private headers stay out
for private in app/app.h bench/bench.h core/text.h sensing/tune.h; do
  [ ! -e "$prefix/include/proxygrasp/$private" ] || fail "private header $private is installed"
done

# 3. the examples against the prefix, with find_package
for example in contours camera; do
  step "examples/$example against the prefix (find_package)"
  cmake -S "$source_dir/examples/$example" -B "$work/ex-$example" -G Ninja \
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" > "$work/ex-$example.log" ||
    { cat "$work/ex-$example.log"; fail "configure examples/$example"; }
  cmake --build "$work/ex-$example" > "$work/ex-$example-build.log" ||
    { cat "$work/ex-$example-build.log"; fail "build examples/$example"; }
done
step "embed_contours side_push: the fingertip's contours push the box"
"$work/ex-contours/embed_contours" side_push > "$work/contours.txt" || fail "embed_contours"
cat "$work/contours.txt"
awk '$1 == "moved" && $2 == "box" { found = 1; if ($3 < 3.0) exit 1 } END { exit !found }' \
  "$work/contours.txt" || fail "embed_contours did not push the box 3 cm or more"
step "embed_camera: a missing camera is a clear error"
set +e
"$work/ex-camera/embed_camera" camera:63 > "$work/camera.txt" 2>&1
rc=$?
set -e
cat "$work/camera.txt"
[ "$rc" != 0 ] || fail "embed_camera camera:63 exited 0"
grep -q "cannot open camera:63" "$work/camera.txt" || fail "embed_camera's error does not name the camera"
step "embed_camera: a recording of side_push made by the installed command"
"$pg" run side_push --record "$work/side_push.mkv" > /dev/null || fail "run --record"
"$work/ex-camera/embed_camera" "$work/side_push.mkv" side_push > "$work/video.txt" ||
  { cat "$work/video.txt"; fail "embed_camera on the recording"; }
tail -1 "$work/video.txt"
awk '$1 == "moved" && $2 == "box" { found = 1; if ($3 < 3.0) exit 1 } END { exit !found }' \
  "$work/video.txt" || fail "embed_camera did not see the box pushed"

# 4. the Debian packages
step "cpack -G DEB"
(cd "$build" && cpack -G DEB -B "$work/deb" > "$work/cpack.log") || { cat "$work/cpack.log"; fail "cpack"; }
deb=$(ls "$work"/deb/proxygrasp_*.deb)
dev=$(ls "$work"/deb/proxygrasp-dev_*.deb)
# the listings into files first: grep -q would close a pipe dpkg-deb still writes to
dpkg-deb -c "$deb" > "$work/deb.list"
dpkg-deb -c "$dev" > "$work/dev.list"
for f in ./usr/bin/proxygrasp ./usr/share/proxygrasp/levels/demo_sort.toml \
         ./usr/share/proxygrasp/levels/shared/base.toml ./usr/share/proxygrasp/levels/recordings/grasp_turn.xml; do
  grep -q " $f\$" "$work/deb.list" || fail "$(basename "$deb") lacks $f"
done
! grep -q "/include/\|\.a\$" "$work/deb.list" || fail "$(basename "$deb") holds headers or libraries"
for f in ./usr/include/proxygrasp/run/simulation.h /proxygraspConfig.cmake /proxygrasp.pc \
         /libproxygrasp_run.a; do
  grep -q "$f\$" "$work/dev.list" || fail "$(basename "$dev") lacks $f"
done
depends=$(dpkg-deb -f "$deb" Depends)
echo "  $(basename "$deb") $(du -k "$deb" | cut -f1) KB, Depends: $depends"
for d in libopencv-core libbox2d libsdl2 liblo libtomlplusplus libc6; do
  echo "$depends" | grep -q "$d" || fail "$(basename "$deb") does not depend on $d"
done
echo "  $(basename "$dev") $(du -k "$dev" | cut -f1) KB, Depends: $(dpkg-deb -f "$dev" Depends)"
if [ "$(id -u)" = 0 ] && command -v apt-get > /dev/null && ! dpkg -s proxygrasp > /dev/null 2>&1; then
  step "apt install the packages, run, remove"
  installed_debs=1
  apt-get install -y -qq "$deb" "$dev" > "$work/apt.log" 2>&1 || { cat "$work/apt.log"; fail "apt install"; }
  proxygrasp --help > /dev/null || fail "installed proxygrasp --help"
  proxygrasp run demo_sort | grep -q "=> PASS" || fail "installed proxygrasp run demo_sort"
  # the example builds against /usr as well
  cmake -S "$source_dir/examples/contours" -B "$work/ex-usr" -G Ninja > /dev/null &&
    cmake --build "$work/ex-usr" > /dev/null || fail "examples/contours against the installed package"
  apt-get remove -y -qq proxygrasp-dev proxygrasp > /dev/null 2>&1 || fail "apt remove"
  installed_debs=""
  echo "  installed, ran, removed"
else
  echo "  skipped installing the packages (needs root, apt and no proxygrasp installed already)"
fi
echo "== install-test: passed in $(($(date +%s) - start)) s"
