#!/usr/bin/env bash
# Builds the Debian package meshlab-geofilter (the MeshLab 2020.09 plugin for Debian 12's
# MeshLab and the geofilter tool) and prints its path. Install it with
#   apt-get install ./build/meshlab-geofilter_*.deb
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh" >&2
"$top/scripts/build.sh" >&2
(cd "$build" && cpack -G DEB >&2)
ls -t "$build"/meshlab-geofilter_*.deb | head -n 1
