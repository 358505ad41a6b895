#!/usr/bin/env bash
# The test command: installs what is needed, builds, and runs every test:
#   1. unit tests (GoogleTest, in random order), command-line tool tests, the Python
#      module's tests (pytest) and the meshlabserver integration tests under Xvfb, on the
#      normal build; then the Debian package (scripts/test-deb.sh: installs it, runs the
#      system meshlabserver and geofilter, removes it);
#   2. the unit and command-line tests again on a build with AddressSanitizer and
#      UndefinedBehaviorSanitizer;
#   3. the MeshLab 2022.02 plugin: MeshLab 2022.02 built from Debian trixie's source package
#      (cached in /var/cache/geofilter after the first run), the plugin built against it, and
#      its PluginManager test, which also compares results with the 2020.09 plugin.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh"

# No test may depend on the order tests run in.
export GTEST_SHUFFLE=1
echo "== tests (build: $build)"
(cd "$build" && ctest --output-on-failure --timeout 900 "$@")

echo "== the Debian package: installed, run through the system MeshLab and geofilter, removed"
"$top/scripts/test-deb.sh"

echo "== unit and command-line tests under AddressSanitizer + UndefinedBehaviorSanitizer"
asan="$build-asan"
source_dir=$(sed -n 's/^MESHLAB_SOURCE_DIR:PATH=//p' "$build/CMakeCache.txt")
cmake -S "$top" -B "$asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOFILTER_SANITIZE=ON \
    -DMESHLAB_SOURCE_DIR="$source_dir" -DGEOFILTER_BUILD_PLUGIN=OFF -DGEOFILTER_BUILD_BENCHMARK=OFF \
    -DGEOFILTER_BUILD_PYTHON=OFF >/dev/null
cmake --build "$asan" -j"$(nproc)"
(cd "$asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure --timeout 900 -L 'unit|cli')

echo "== MeshLab 2022.02 (FilterPlugin API) plugin"
"$top/scripts/test-meshlab2022.sh"
