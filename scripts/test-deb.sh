#!/usr/bin/env bash
# Tests the Debian package as a user gets it: builds meshlab-geofilter, installs it with
# apt-get, runs the SYSTEM /usr/bin/meshlabserver with a GeoFilter script and the installed
# /usr/bin/geofilter, checks both against the build tree's results, then removes the
# package and checks that nothing of it is left. Needs root (it installs a package).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
work=$(mktemp -d)
plugin_dir=$(dirname "$(dpkg -S libmeshlab-common.so | sed 's/^[^:]*: //' | head -n 1)")/plugins

if dpkg-query -W -f='${Status}' meshlab-geofilter 2>/dev/null | grep -q "install ok installed"; then
    echo "test-deb: meshlab-geofilter is already installed; remove it first (apt-get remove meshlab-geofilter)" >&2
    exit 1
fi
deb=$("$top/scripts/package.sh")
echo "== test-deb: $deb"
dpkg-deb --field "$deb" Package Version Depends
installed=0
cleanup() {
    if [ "$installed" = 1 ]; then DEBIAN_FRONTEND=noninteractive apt-get remove --purge -y -q meshlab-geofilter >/dev/null; fi
    rm -rf "$work"
}
trap cleanup EXIT

DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$deb" >/dev/null
installed=1
for f in /usr/bin/geofilter "$plugin_dir/libfilter_geofilter.so"; do
    [ -f "$f" ] || { echo "test-deb: FAIL: $f was not installed" >&2; exit 1; }
done

# The system meshlabserver finds the plugin in the system folder; its result must be the
# build tree's (same script, same input, private prefix).
script="$top/scripts/mlx/bunny_lowpass.mlx"
xvfb-run -a /usr/bin/meshlabserver -i "$top/meshes/bunny00.off" -o "$work/system.ply" -s "$script" >"$work/system.log" 2>&1 \
    || { cat "$work/system.log" >&2; echo "test-deb: FAIL: system meshlabserver failed" >&2; exit 1; }
grep -q "GeoFilter: Lowpass: solver" "$work/system.log" \
    || { cat "$work/system.log" >&2; echo "test-deb: FAIL: the system meshlabserver did not run GeoFilter" >&2; exit 1; }
xvfb-run -a "$build/meshlab-prefix/bin/meshlabserver" -i "$top/meshes/bunny00.off" -o "$work/build.ply" -s "$script" \
    >"$work/build.log" 2>&1 || { cat "$work/build.log" >&2; exit 1; }
cmp "$work/system.ply" "$work/build.ply" \
    || { echo "test-deb: FAIL: the installed plugin's result differs from the build tree's" >&2; exit 1; }
cmp -s "$work/system.ply" "$top/meshes/bunny00.off" && { echo "test-deb: FAIL: nothing was filtered" >&2; exit 1; }

/usr/bin/geofilter lowpass --radius 0.1 "$top/meshes/bunny00.off" "$work/tool.ply" 2>"$work/tool.log"
"$build/filter_geofilter/cli/geofilter" lowpass --radius 0.1 "$top/meshes/bunny00.off" "$work/tool-build.ply" 2>/dev/null
cmp "$work/tool.ply" "$work/tool-build.ply" \
    || { echo "test-deb: FAIL: the installed geofilter's result differs from the build tree's" >&2; exit 1; }

DEBIAN_FRONTEND=noninteractive apt-get remove --purge -y -q meshlab-geofilter >/dev/null
installed=0
for f in /usr/bin/geofilter "$plugin_dir/libfilter_geofilter.so"; do
    [ ! -e "$f" ] || { echo "test-deb: FAIL: $f is still there after removal" >&2; exit 1; }
done
dpkg-query -W -f='${Status}' meshlab-geofilter 2>/dev/null | grep -q "install ok installed" \
    && { echo "test-deb: FAIL: the package is still installed" >&2; exit 1; }
echo "test-deb: 3 passed, 0 failed (installed, ran through /usr/bin/meshlabserver and /usr/bin/geofilter, removed)"
