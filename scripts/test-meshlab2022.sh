#!/usr/bin/env bash
# Tests the MeshLab 2022.02 plugin: builds MeshLab 2022.02 (cached, scripts/build-meshlab-source.sh),
# the 2020.09 plugin of the default build (the comparison's reference), this repository in
# build-2022/ against that MeshLab, and runs `ctest -L meshlab2022` there.
#
#   test-meshlab2022.sh [--double] [--suite SUITE] [extra ctest arguments]
#     --double  against a double-precision MeshLab (as pymeshlab 2025.7 is built),
#               in build-2022-double/
#     --suite   against another Debian suite's MeshLab (sid: 2025.07), in build-2022-SUITE[-double]/
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
jobs=${GEOFILTER_JOBS:-2}

ml_args=() suffix=""
while [ $# -gt 0 ]; do
    case "$1" in
        --double) ml_args+=(--double); suffix=$suffix-double ;;
        --suite) ml_args+=(--suite "${2:?--suite needs a Debian suite}"); [ "$2" = trixie ] || suffix=-$2$suffix; shift ;;
        *) break ;;
    esac
    shift
done

# The comparison test replays cases with the 2020.09 plugin: keep it built from this tree.
build2020=${GEOFILTER_BUILD_DIR:-$top/build}
[ -f "$build2020/CMakeCache.txt" ] || nice cmake -S "$top" -B "$build2020" -DCMAKE_BUILD_TYPE=Release
nice cmake --build "$build2020" -j"$jobs" --target filter_geofilter

out=$("$top/scripts/build-meshlab-source.sh" "${ml_args[@]}")
src=$(sed -n 's/^MESHLAB_SOURCE_DIR=//p' <<<"$out")
mlbuild=$(sed -n 's/^MESHLAB_BUILD_DIR=//p' <<<"$out")
[ -n "$src" ] && [ -n "$mlbuild" ] || { echo "test-meshlab2022: build-meshlab-source.sh gave no folders" >&2; exit 1; }

build=$top/build-2022$suffix
nice cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release \
    -DMESHLAB_SOURCE_DIR="$src" -DMESHLAB_BUILD_DIR="$mlbuild" \
    -DGEOFILTER_MESHLAB2020_PREFIX="$build2020/meshlab-prefix"
# Only what the meshlab2022 label runs (the plugin and its test program).
nice cmake --build "$build" -j"$jobs" --target filter_geofilter geofilter_meshlab2022_tests
cd "$build"
ctest -L meshlab2022 --output-on-failure --timeout 900 "$@"
