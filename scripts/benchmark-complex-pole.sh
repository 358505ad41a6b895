#!/usr/bin/env bash
# The complex-pole experiment: the factored solver as it is (a Cholesky factor of
# Kt + |r| I preconditioning CG on each complex pole pair) against an exact solve of each pair
# by a complex-symmetric LDL^T of Kt - r I (MUMPS: ZMUMPS with AMD or METIS, CMUMPS refined), on the 1M
# torus and the 1.1M subdivided human scan, for the filters with complex poles. One process
# per case, so that each peak memory is the case's own. Prints a markdown table (~30 min here).
#   scripts/benchmark-complex-pole.sh [--quick]   (--quick: the 280k scan only)
# Builds nothing: run scripts/build.sh first. Serialise with other work on a shared machine.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
bench="$build/tests/geofilter_complex_pole_benchmark"
[[ -x $bench ]] || { echo "benchmark-complex-pole.sh: $bench not built (needs libmumps-dev and MPI: scripts/build.sh)" >&2; exit 1; }
meshes=(torus "$top/meshes/man.off:3")
[[ ${1:-} == --quick ]] && meshes=("$top/meshes/man.off:2")
echo "| mesh | vertices | filter | pole pairs | method | assembly (s) | factorisation (s) | solve (s) | total (s) | pairs (s) | peak MiB |"
echo "|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
    for filter in lowpass exaggeration notch butterworth8; do
        for method in today ldlt-amd ldlt-metis ldlt-single; do
            "$bench" "$mesh" "$filter" "$method" | sed "s|$top/||"
        done
    done
done
