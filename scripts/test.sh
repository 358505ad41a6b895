#!/usr/bin/env bash
# The test command: installs what is needed, builds, and runs every test:
#   1. unit tests (GoogleTest, in random order), command-line tool tests, geofilter-mpi's
#      tests under mpirun (1, 2 and 3 ranks against geofilter; bad input), the Python
#      module's tests (pytest) and the meshlabserver integration tests under Xvfb, on the
#      normal build; then the Debian package (scripts/test-deb.sh: installs it, runs the
#      system meshlabserver and geofilter, removes it);
#   2. the unit and command-line tests again on a build with AddressSanitizer and
#      UndefinedBehaviorSanitizer (all but the quality checks on real scans and large meshes,
#      label `large`, which step 1 runs);
#   3. the MeshLab 2022.02 plugin: MeshLab 2022.02 built from Debian trixie's source package
#      (cached in /var/cache/geofilter after the first run), the plugin built against it, and
#      its PluginManager test, which also compares results with the 2020.09 plugin;
#   4. the same against MeshLab 2025.07 (Debian sid's source package, cached the same way), in
#      float (the GUI's precision) and in double (pymeshlab 2025.7's): every filter run
#      through pymeshlab's FunctionSet by python name and python keyword names.
#
#   test.sh --quick   the edit loop: the unit, command-line and Python tests on a build
#                     without the plugin and MPI (build-quick/), no sanitizer, no MeshLab.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
export CCACHE_BASEDIR="$top" CCACHE_NOHASHDIR=true

if [ "${1:-}" = --quick ]; then
    shift
    quick=${GEOFILTER_BUILD_DIR:-$top/build-quick}
    "$top/scripts/setup.sh"
    GEOFILTER_BUILD_DIR=$quick "$top/scripts/build.sh" -DGEOFILTER_BUILD_PLUGIN=OFF -DGEOFILTER_BUILD_MPI=OFF
    export GTEST_SHUFFLE=1
    cd "$quick"
    exec ctest -j"$(nproc)" --output-on-failure --timeout 900 -L 'unit|cli|python' "$@"
fi

build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
# (CCACHE_BASEDIR above: ccache, which CMake compiles through when installed, keys its cache
# on paths relative to this checkout and ignores the working directory, so that a clean clone
# anywhere on the machine reuses what an earlier run compiled.)
# geofilter-mpi and its tests (label mpi) are required here: setup.sh installs MPI and PETSc,
# so their absence is an error, not a suite that silently vanishes.
"$top/scripts/build.sh" -DGEOFILTER_REQUIRE_MPI=ON

# No test may depend on the order tests run in.
export GTEST_SHUFFLE=1
echo "== tests (build: $build)"
# Two tests at a time (one per core): the tests that need more say so (PROCESSORS: an MPI
# run claims a core per rank; RESOURCE_LOCK: one X server at a time).
ctest_jobs=-j"$(nproc)"
(cd "$build" && ctest "$ctest_jobs" --output-on-failure --timeout 900 "$@")

echo "== the Debian package: installed, run through the system MeshLab and geofilter, removed"
"$top/scripts/test-deb.sh"

echo "== unit and command-line tests under AddressSanitizer + UndefinedBehaviorSanitizer"
asan="$build-asan"
# Only what the sanitizer runs is built (not geofilter-mpi: Open MPI's own allocations would
# drown the leak report). Without the plugin nothing of MeshLab is needed: this build is
# configured and built with no network at all (a network namespace of its own) wherever the
# machine allows one.
offline=()
if unshare -rn true 2>/dev/null; then
    offline=(unshare -rn)
    echo "(configured and built with no network: ${offline[*]})"
fi
# -O1 with line tables only: the sanitizers' reports keep file and line, and the build takes
# about half the time of -O2 with full debug information. Every target a unity build (files
# compiled several to a unit: the headers and Eigen's instantiations once per unit), which no
# other tree shares: 392 -> 267 s for this build from an empty compiler cache.
"${offline[@]}" cmake -S "$top" -B "$asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOFILTER_SANITIZE=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=6 \
    -DGEOFILTER_BUILD_PLUGIN=OFF -DGEOFILTER_BUILD_PYTHON=OFF -DGEOFILTER_BUILD_MPI=OFF >/dev/null
"${offline[@]}" cmake --build "$asan" -j"$(nproc)"
(cd "$asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest "$ctest_jobs" --output-on-failure --timeout 900 -L 'unit|cli' -LE large)

echo "== MeshLab 2022.02 (FilterPlugin API) plugin"
"$top/scripts/test-meshlab2022.sh"

echo "== MeshLab 2025.07 plugin, float (the GUI's precision)"
"$top/scripts/test-meshlab2022.sh" --suite sid

echo "== MeshLab 2025.07 plugin, double (pymeshlab 2025.7's precision)"
"$top/scripts/test-meshlab2022.sh" --suite sid --double
