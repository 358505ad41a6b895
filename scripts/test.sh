#!/usr/bin/env bash
# The test command: installs what is needed, builds, and runs every test (unit tests,
# then the meshlabserver integration tests under Xvfb).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh"
cd "$build"
ctest --output-on-failure --timeout 900 "$@"
