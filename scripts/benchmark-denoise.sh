#!/usr/bin/env bash
# Denoise with nothing selected on large meshes (issue 10; ~13 min, not the 20-minute solver
# benchmark): noise of 0.3 mean edge lengths along the normals of a 160k and a 1M-vertex torus
# and of the man scan subdivided to 280k; Denoise as shipped (scoring on patches above 100k
# vertices) against Denoise scoring on the whole mesh, the chosen lowpass alone and 10 steps
# of vcglib's Taubin, with each result's distance to the clean mesh.
# Writes results/benchmark/denoise.md. Extra arguments go to geofilter_benchmark
# (--quick: the 17k-vertex scan only, seconds).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh" >/dev/null
"$build/tests/geofilter_benchmark" --denoise --meshes "$top/meshes" --out "$top/results/benchmark" "$@"
