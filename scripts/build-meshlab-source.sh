#!/usr/bin/env bash
# Builds, from a Debian source package, the parts of a MeshLab 2022.02 or later that
# GeoFilter's 2022 adapter is tested against (libmeshlab-common and the plugins io_base and
# filter_create), once per machine: trixie's 2022.02 by default, sid's 2025.07 with --suite
# sid. With --gui also the meshlab GUI and the plugins of its Smoothing menu (filter_select,
# filter_unsharp), for the screenshots; the tests do not need them.
#
#   build-meshlab-source.sh [--double] [--suite SUITE] [--gui]
#     --double   MeshLab with double-precision scalars (BUILD_WITH_DOUBLE_SCALAR), as
#                pymeshlab 2025.7 is built; kept in its own build folder.
#     --suite    another Debian suite's MeshLab (default trixie: 2022.02; sid had 2025.07),
#                to check the plugin against a later FilterPlugin release.
#     --gui      the GUI too (float only: pymeshlab's double build has none).
#
# Environment: GEOFILTER_CACHE_DIR  where sources and builds are kept (default
#                /var/cache/geofilter when writable, else ${XDG_CACHE_HOME:-~/.cache}/geofilter)
#              GEOFILTER_JOBS       parallel compile jobs (default 2: the machine is shared)
# The last two lines of stdout are  MESHLAB_SOURCE_DIR=<tree>  and  MESHLAB_BUILD_DIR=<dir>.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)

scalar=float suite=trixie with_gui=no
while [ $# -gt 0 ]; do
    case "$1" in
        --double) scalar=double ;;
        --suite) suite=${2:?--suite needs a Debian suite}; shift ;;
        --gui) with_gui=yes ;;
        *) echo "usage: $0 [--double] [--suite SUITE] [--gui]" >&2; exit 2 ;;
    esac
    shift
done
jobs=${GEOFILTER_JOBS:-2}

if [ -n "${GEOFILTER_CACHE_DIR:-}" ]; then
    cache=$GEOFILTER_CACHE_DIR
elif mkdir -p /var/cache/geofilter 2>/dev/null && [ -w /var/cache/geofilter ]; then
    cache=/var/cache/geofilter   # shared by every checkout on the machine
else
    cache=${XDG_CACHE_HOME:-$HOME/.cache}/geofilter
fi
mkdir -p "$cache"
cache=$(cd "$cache" && pwd)

# What the tests load next to GeoFilter (files through io_base, meshes from filter_create);
# the GUI and its smoothing menu only on request. libmeshlab-common and these two plugins
# take about 1.5 minutes on two cores, the GUI and the two other plugins longer.
plugins=(io_base filter_create)
gui=()
if [ "$with_gui" = yes ]; then
    [ "$scalar" = float ] || { echo "build-meshlab-source: --gui is float only (the GUI's precision)" >&2; exit 2; }
    plugins+=(filter_select filter_unsharp)
    gui=(meshlab)
fi
targets=(meshlab-common "${gui[@]}" "${plugins[@]}" copy-distrib-files)
# Configured with every plugin either mode builds, so that a later --gui builds only what it adds.
all_plugins=(io_base filter_create filter_select filter_unsharp)
plugin_dirs=$(printf 'meshlabplugins/%s;' "${all_plugins[@]}"); plugin_dirs=${plugin_dirs%;}

fetch_dest=$cache/meshlab-$suite-source
label=$suite; [ "$suite" = trixie ] && label=2022
build=$cache/meshlab-$label-$scalar-build
stamp=$build/.geofilter-build-complete
# Everything that changes what is built; a stamp with another signature means configure and
# build again (make then recompiles only what the change touched).
signature="plugins=$plugin_dirs scalar=$scalar script=5"

report() {
    echo "MESHLAB_SOURCE_DIR=$1"
    echo "MESHLAB_BUILD_DIR=$2"
}

complete() {
    [ -f "$stamp" ] && [ "$(sed -n 2p "$stamp")" = "$signature" ] || return 1
    local src d; src=$(sed -n 1p "$stamp")
    [ -f "$src/src/common/plugins/interfaces/filter_plugin.h" ] || return 1
    # MeshLab's project is src/ in 2022.02, the top folder (building into src/) from 2023.12.
    d=$build/distrib; [ -d "$d" ] || d=$build/src/distrib
    [ -f "$d/libmeshlab-common.so" ] || return 1
    [ ${#gui[@]} -eq 0 ] || [ -x "$d/meshlab" ] || return 1
    for p in "${plugins[@]}"; do [ -f "$d/plugins/lib$p.so" ] || return 1; done
}

if complete; then
    echo "build-meshlab-source: cached build is complete" >&2
    report "$(sed -n 1p "$stamp")" "$build"
    exit 0
fi

# Two checkouts building at once would trample the same folder: take turns.
exec 9>"$cache/.meshlab-$label-$scalar.lock"
flock 9
if complete; then   # someone else finished it while we waited
    report "$(sed -n 1p "$stamp")" "$build"
    exit 0
fi

# What MeshLab's CMake needs for this subset (Debian trixie's Build-Depends, minus the
# libraries of the plugins left out).
needed=(cmake g++ make dpkg-dev xz-utils qtbase5-dev libqt5opengl5-dev libglew-dev
        libeigen3-dev libglu1-mesa-dev)
missing=()
for p in "${needed[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "build-meshlab-source: missing packages (install them as root): ${missing[*]}" >&2
        exit 1
    fi
    echo "build-meshlab-source: installing ${missing[*]}" >&2
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi

src=$("$top/scripts/fetch-debian-source.sh" meshlab "$suite" "$fetch_dest" | tail -n1)
if [ ! -f "$src/src/common/plugins/interfaces/filter_plugin.h" ]; then
    echo "build-meshlab-source: $src is not a MeshLab 2022+ tree (no src/common/plugins/interfaces/filter_plugin.h)" >&2
    exit 1
fi
ver=$(tr -d ' \n' <"$src/ML_VERSION")
[ "$suite" != trixie ] || [ "$ver" = 2022.02 ] ||
    echo "build-meshlab-source: NOTE: trixie has MeshLab $ver, not 2022.02; building that" >&2
project=$src; [ -f "$project/CMakeLists.txt" ] || project=$src/src

double=OFF; [ "$scalar" = double ] && double=ON
start=$(date +%s)
rm -f "$stamp"
# The optional external libraries (CGAL, libigl, levmar, u3d, ...; downloads from 2023.12 on)
# are off: none of the chosen plugins uses one. Options are given under both spellings
# (2022.02's, and 2023.12's MESHLAB_/VCG_ prefixed ones); each release ignores the other's.
# libmeshlab-common as a unity build, in about half the time (why, and which files stay out:
# scripts/cmake/meshlab_unity_build.cmake).
# MeshLab's own code unoptimised: the tests use it to read files and make meshes, never time it
# (GeoFilter's plugin, built by its own tree, keeps -O2): 110 -> 89 s for trixie's float build.
nice cmake -S "$project" -B "$build" -DCMAKE_BUILD_TYPE=Release --no-warn-unused-cli \
    -DCMAKE_CXX_FLAGS_RELEASE="-O0 -DNDEBUG" -DCMAKE_C_FLAGS_RELEASE="-O0 -DNDEBUG" \
    -DCMAKE_PROJECT_INCLUDE="$top/scripts/cmake/meshlab_unity_build.cmake" \
    -DMESHLAB_PLUGINS="$plugin_dirs" \
    -DALLOW_OPTIONAL_EXTERNAL_MESHLAB_LIBRARIES=OFF -DMESHLAB_ALLOW_OPTIONAL_EXTERNAL_LIBRARIES=OFF \
    -DALLOW_BUNDLED_EIGEN=OFF -DVCG_ALLOW_BUNDLED_EIGEN=OFF \
    -DALLOW_BUNDLED_GLEW=OFF -DMESHLAB_ALLOW_BUNDLED_SOURCE_GLEW=OFF \
    -DBUILD_WITH_DOUBLE_SCALAR=$double -DMESHLAB_BUILD_WITH_DOUBLE_SCALAR=$double >&2
nice cmake --build "$build" -j"$jobs" --target "${targets[@]}" >&2
printf '%s\n%s\n' "$src" "$signature" >"$stamp"
complete || { echo "build-meshlab-source: build finished but outputs are missing in $build/distrib" >&2; exit 1; }
echo "build-meshlab-source: built in $(( $(date +%s) - start )) s" >&2
report "$src" "$build"
