#!/usr/bin/env bash
# Configures and builds everything (core, MeshLab plugin, tests, benchmark) in build/.
# Extra arguments go to the CMake configure step.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build" -j"$(nproc)"
