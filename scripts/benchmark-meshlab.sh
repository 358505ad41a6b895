#!/usr/bin/env bash
# GeoFilter's filters against 50 steps of MeshLab's Taubin Smooth through Debian's
# meshlabserver 2020.09 on a ~384k-vertex mesh, I/O included, in alternated rounds (about
# 5 minutes). Writes results/benchmark/meshlabserver.md and docs/results/meshlabserver.md.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh" >/dev/null
GEOFILTER_MESHLAB_PREFIX=${GEOFILTER_MESHLAB_PREFIX:-$build/meshlab-prefix} \
GEOFILTER_FILTER_TABLE="$build/filter_table.json" \
PYTHONPATH="$top/tests/integration:$top/tests/support:$top/experiments" \
    /usr/bin/python3 "$top/tests/benchmark/benchmark_meshlabserver.py" --meshes "$top/meshes" \
    --out "$top/results/benchmark" "$@"
