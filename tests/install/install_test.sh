#!/usr/bin/env bash
# Candela as a dependency, end to end (ctest: install.package, label "install"; docs/install.md):
#   1. cmake --install into a temporary prefix; the layout is checked, and the installed candela
#      reads the installed shaders (--version names them), not the source tree's;
#   2. tests/consumer (copied) is configured against that prefix with find_package(Candela),
#      built, and its tests run: a program linking Candela::engine, golden tests (forward and
#      deferred), and a golden test on an altered scene that must fail with its candidate and diff
#      written;
#   3. update-goldens of the consumer re-renders its golden, which equals the committed one;
#   4. cpack -G DEB; the packages' Depends are printed and checked; the candela package is
#      unpacked with dpkg-deb -x (no root, no system install) and its candela renders a sample
#      scene from the package's own copy, the image is checked for NaN/Inf, and every shader
#      program builds (`candela shaders check`).
#
#   install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR VERSION
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR VERSION" >&2
  exit 2
fi
build=$(realpath "$1")
src=$(realpath "$2")
work=$3
version=$4
rm -rf "$work"
mkdir -p "$work"
work=$(realpath "$work")
prefix=$work/prefix

step() { printf '\n== %s (at %d s)\n' "$1" "$SECONDS"; }
fail() {
  echo "install_test: FAIL: $*" >&2
  exit 1
}
# Runs a command, keeping its output in a log that is shown only if it fails.
logged() {
  local log=$1
  shift
  if ! "$@" >"$log" 2>&1; then
    cat "$log" >&2
    fail "'$*' failed (log: $log)"
  fi
}

step "cmake --install $build --prefix $prefix"
logged "$work/install.log" cmake --install "$build" --prefix "$prefix"
for f in bin/candela lib/libcandela_image_io.so lib/libcandela.a lib/libcandela_glad.a \
  include/candela/scene/gltf_loader.hpp include/candela/shader/shader_library.hpp include/candela/glad/gl.h \
  include/candela/KHR/khrplatform.h share/candela/shaders/common/scene_data.glsl share/candela/effects/ssao/ssao.frag \
  share/candela/gpu/bindings.h share/candela/samples/scenes/cornell_box.gltf share/candela/samples/scenes/cornell_box.bin \
  share/doc/candela/third_party_notes lib/cmake/Candela/CandelaConfig.cmake lib/cmake/Candela/CandelaConfigVersion.cmake \
  lib/cmake/Candela/CandelaTargets.cmake lib/cmake/Candela/CandelaGoldenTest.cmake lib/cmake/Candela/candela_golden_check.cmake; do
  [ -e "$prefix/$f" ] || fail "$f is not installed"
done
# The data directory holds shaders only: no C++ of the effects.
if stray=$(find "$prefix/share/candela" -name '*.cpp' -o -name '*.hpp' -o -name CMakeLists.txt | grep .); then
  fail "C++ sources installed with the shaders: $stray"
fi
echo "installed $(find "$prefix" -type f | wc -l) files, $(du -sh "$prefix" | cut -f1)"

step "the installed candela --version"
"$prefix/bin/candela" --version | tee "$work/version.txt"
grep -Eq "^candela $version \\(git ([0-9a-f]{12}|unknown)\\)$" "$work/version.txt" || fail "--version does not say 'candela $version (git HASH)'"
grep -qx "shaders: $prefix/share/candela/shaders" "$work/version.txt" || fail "the installed candela does not read $prefix/share/candela/shaders"
grep -qx "effects: $prefix/share/candela" "$work/version.txt" || fail "the installed candela does not read the effects' GLSL from $prefix/share/candela"
grep -q "^GL: " "$work/version.txt" || fail "--version printed no GL line"

step "the consumer project against $prefix"
# A copy, so that update-goldens below writes into the copy, never into the source tree.
cp -r "$src/tests/consumer" "$work/consumer-src"
logged "$work/consumer-configure.log" cmake -S "$work/consumer-src" -B "$work/consumer" -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix"
grep -q "Candela $version: $prefix/lib/cmake/Candela" "$work/consumer-configure.log" ||
  fail "the consumer did not find Candela $version in $prefix: $(grep 'Candela' "$work/consumer-configure.log")"
logged "$work/consumer-build.log" cmake --build "$work/consumer"
ctest --test-dir "$work/consumer" --output-on-failure | tee "$work/consumer-ctest.log" || fail "the consumer's tests failed"
grep -q "100% tests passed, 0 tests failed out of 6" "$work/consumer-ctest.log" || fail "the consumer's tests did not all pass (6 expected)"
"$work/consumer/scene_info" "$src/tests/consumer/scenes/box_on_floor.gltf"

step "update-goldens re-renders the consumer's golden"
golden=$work/consumer-src/goldens/box_on_floor.png
rm "$golden"
if ctest --test-dir "$work/consumer" -R '^golden.box_on_floor$' >"$work/no-golden.log" 2>&1; then
  fail "golden.box_on_floor passed without its golden"
fi
logged "$work/update-goldens.log" cmake --build "$work/consumer" --target update-goldens
[ -f "$golden" ] || fail "update-goldens did not write $golden"
"$prefix/bin/candela" compare "$golden" "$src/tests/consumer/goldens/box_on_floor.png" --check >"$work/update-compare.log" ||
  fail "the re-rendered golden differs from the committed one: $(cat "$work/update-compare.log")"
[ -z "$(ls "$work/consumer/candela-golden" | grep -v '^golden.altered\.')" ] || fail "update-goldens left files: $(ls "$work/consumer/candela-golden")"

step "cpack -G DEB"
logged "$work/cpack.log" cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/pkg"
runtime_deb=$work/pkg/candela_${version}_amd64.deb
dev_deb=$work/pkg/libcandela-dev_${version}_amd64.deb
[ -f "$runtime_deb" ] || fail "no $runtime_deb: $(ls "$work/pkg")"
[ -f "$dev_deb" ] || fail "no $dev_deb: $(ls "$work/pkg")"
for deb in "$runtime_deb" "$dev_deb"; do
  echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB"
  dpkg-deb -f "$deb" Package Version Depends Recommends
done
depends=$(dpkg-deb -f "$runtime_deb" Depends)
# What the command links (dpkg-shlibdeps) must be there: the two headless GL backends, the window.
depends_names=$(sed 's/ *([^)]*)//g; s/, */\n/g' <<<"$depends")
for pkg in libc6 libstdc++6 libegl1 libosmesa6 libglfw3 libpng16-16; do
  grep -Fqx "$pkg" <<<"$depends_names" || fail "the candela package does not depend on $pkg: $depends"
done
dev_depends=$(dpkg-deb -f "$dev_deb" Depends)
grep -Fq "candela (= $version)" <<<"$dev_depends" || fail "libcandela-dev does not depend on candela (= $version)"
dpkg-deb -c "$dev_deb" >"$work/dev-contents.txt"
grep -q "usr/lib/cmake/Candela/CandelaConfig.cmake" "$work/dev-contents.txt" || fail "libcandela-dev has no CandelaConfig.cmake"

step "the unpacked candela package renders"
dpkg-deb -x "$runtime_deb" "$work/root"
candela=$work/root/usr/bin/candela
"$candela" --version | tee "$work/deb-version.txt"
grep -qx "shaders: $work/root/usr/share/candela/shaders" "$work/deb-version.txt" ||
  fail "the unpacked candela does not read its own shaders ($work/root/usr/share/candela/shaders)"
scene=$work/root/usr/share/candela/samples/scenes/cornell_box.gltf
"$candela" render "$scene" -o "$work/cornell_box.exr" --size 64x64
[ -s "$work/cornell_box.exr" ] || fail "candela render wrote no $work/cornell_box.exr"
# compare X X --check: exit 4 on any non-finite value (NaN/Inf), 0 otherwise.
"$candela" compare "$work/cornell_box.exr" "$work/cornell_box.exr" --check || fail "cornell_box.exr has NaN/Inf (exit $?)"
# Every program and tracer variant, from the package's shaders, through glslang and the driver.
logged "$work/shaders-check.log" "$candela" shaders check
tail -n 1 "$work/shaders-check.log"

step "ok"
