#!/usr/bin/env bash
# The region rows of the benchmark (a few minutes, not the 20-minute benchmark):
# a region of 1% of a ~1M-vertex mesh against the whole-mesh filter.
# Writes results/benchmark/region.md. Extra arguments go to geofilter_benchmark
# (--quick: the small meshes, seconds).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh" >/dev/null
"$build/tests/geofilter_benchmark" --region --meshes "$top/meshes" --out "$top/results/benchmark" "$@"
