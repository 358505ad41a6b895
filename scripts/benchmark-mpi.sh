#!/usr/bin/env bash
# Time and peak memory per rank of geofilter-mpi at 1, 2 and 4 ranks against geofilter, on
# procedural bumpy tori (binary PLY, written once into $build/benchmark-mpi). Prints a table.
#   scripts/benchmark-mpi.sh [--vertices 2000000 ...] [--ranks 1 2 4] [--preset lowpass]
#                            [--pole-solver direct|multigrid]
# Builds nothing: run scripts/build.sh first. Serialise with other work on a shared machine.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
exec /usr/bin/python3 -B "$top/tests/benchmark/benchmark_mpi.py" \
    --geofilter "$build/filter_geofilter/cli/geofilter" \
    --geofilter-mpi "$build/filter_geofilter/mpi/geofilter-mpi" \
    --workdir "$build/benchmark-mpi" "$@"
