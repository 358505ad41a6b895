#!/usr/bin/env bash
# Screenshots of the GeoFilter plugin in the MeshLab 2020.09, 2022.02 and 2025.07 GUIs, under Xvfb:
#   docs/screenshots/meshlab-<version>-menu.png       Filters > Smoothing, Fairing and Deformation
#   docs/screenshots/meshlab-<version>-geofilter.png  the GeoFilter: Lowpass dialog on the bunny
#   docs/screenshots/meshlab-<version>-preview.png    Preview ticked, the feature radius raised
#
# Needs: xvfb, xdotool, imagemagick (import); the default build (build/meshlab-prefix, from
# scripts/build.sh), build-2022/ (scripts/test-meshlab2022.sh) and build-2022-sid/
# (scripts/test-meshlab2022.sh --suite sid: MeshLab 2025.07, float, the GUI's precision);
# meshes/bunny00.off (scripts/fetch-meshes.sh). The tests build MeshLab 2022+ without its
# GUI: this script adds the GUI to those cached builds (scripts/build-meshlab-source.sh --gui).
#
#   screenshots.sh [WHICH...]   WHICH: 2020.09, build-2022, build-2022-sid (default: all three),
#                               to redo some pictures and leave the others as they are
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/docs/screenshots
mesh=${GEOFILTER_SCREENSHOT_MESH:-$top/meshes/bunny00.off}
ml2020=${GEOFILTER_BUILD_DIR:-$top/build}/meshlab-prefix/bin/meshlab

for tool in Xvfb xdotool import; do
    command -v "$tool" >/dev/null || { echo "screenshots: $tool missing (apt-get install xvfb xdotool imagemagick)" >&2; exit 1; }
done
[ -f "$mesh" ] || "$top/scripts/fetch-meshes.sh"
which=("$@"); [ $# -gt 0 ] || which=(2020.09 build-2022 build-2022-sid)
shoot2020=0 builds2022=()
for w in "${which[@]}"; do
    # The MeshLab 2022+ builds to show, each with the test-meshlab2022.sh arguments that make it.
    case "$w" in
        2020.09) shoot2020=1 ;;
        build-2022) builds2022+=("build-2022:") ;;
        build-2022-sid) builds2022+=("build-2022-sid:--suite sid") ;;
        *) echo "screenshots: unknown $w (2020.09, build-2022 or build-2022-sid)" >&2; exit 2 ;;
    esac
done
[ "$shoot2020" = 0 ] || [ -x "$ml2020" ] || { echo "screenshots: $ml2020 missing: run scripts/build.sh" >&2; exit 1; }
for b in "${builds2022[@]}"; do
    dir=$top/${b%%:*}
    [ -f "$dir/CMakeCache.txt" ] ||
        { echo "screenshots: ${b%%:*}/ missing: run scripts/test-meshlab2022.sh ${b#*:}" >&2; exit 1; }
    # shellcheck disable=SC2086  # the suite arguments, split on purpose
    "$top/scripts/build-meshlab-source.sh" --gui ${b#*:} >/dev/null
done

# shellcheck source=experiments/screenshot-display.sh
source "$top/experiments/screenshot-display.sh"

private_display
for _ in $(seq 50); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.2; done

# MeshLab 2022+ finds plugins and shaders next to its executable: a private folder with a copy
# of the build's GUI (its RUNPATH still finds libmeshlab-common.so), the build's plugins and
# ours, so that nothing is added to the cached MeshLab build. Prints "version executable".
private_meshlab() { # GeoFilter build folder configured against MeshLab 2022+
    local cache=$1/CMakeCache.txt distrib plugin version p
    cached() { sed -n "s/^$1:[A-Z]*=//p" "$cache"; }
    distrib=$(cached MESHLAB_2022_DISTRIB_DIR)
    plugin=$(cached GEOFILTER_MESHLAB2022_PLUGIN_DIR)/libfilter_geofilter.so
    version=$(cached MESHLAB_2022_VERSION)
    [ -x "$distrib/meshlab" ] && [ -f "$plugin" ] && [ -n "$version" ] ||
        { echo "screenshots: the MeshLab GUI or plugin of $1 is missing: run scripts/test-meshlab2022.sh" >&2; return 1; }
    p=$work/meshlab-$version
    mkdir -p "$p/plugins"
    cp "$distrib/meshlab" "$p/"
    ln -s "$distrib/shaders" "$p/shaders"
    for f in "$distrib"/plugins/*.so "$plugin"; do ln -s "$f" "$p/plugins/"; done
    echo "$version $p/meshlab"
}

wait_window() { # name regex -> window id
    timeout 60 xdotool search --sync --onlyvisible --name "$1" | head -n1
}

# The main window. MeshLab 2025.07 (not 2020.09 or 2022.02) first asks, on a fresh HOME,
# whether it may send usage statistics, in a dialog over the main window: answer No, and take
# the main window only once no such question is up.
wait_main() { # version -> window id
    local w q
    for _ in $(seq 120); do
        q=$(xdotool search --onlyvisible --name '^Send Anonymous Statistics$' 2>/dev/null | head -n1 || true)
        if [ -n "$q" ]; then
            # No window manager here (windowactivate needs one): focus it and press No.
            xdotool windowfocus --sync "$q" key alt+n >/dev/null 2>&1 || true
        else
            w=$(xdotool search --onlyvisible --name "^MeshLab $1" 2>/dev/null | head -n1 || true)
            if [ -n "$w" ]; then
                sleep 2   # the question comes with the main window's first show
                q=$(xdotool search --onlyvisible --name '^Send Anonymous Statistics$' 2>/dev/null | head -n1 || true)
                [ -n "$q" ] || { echo "$w"; return 0; }
                continue
            fi
        fi
        sleep 0.5
    done
    return 1
}

shoot() { # version executable
    local version=$1 exe=$2 home=$work/home-$1
    mkdir -p "$home/run" && chmod 700 "$home/run"
    # A fresh HOME: no saved window layout or recent files from earlier sessions.
    HOME=$home XDG_RUNTIME_DIR=$home/run "$exe" "$mesh" >"$work/$version.log" 2>&1 &
    local pid=$!
    pids+=($pid)
    local win
    win=$(wait_main "$version") || { echo "screenshots: no MeshLab $version window" >&2; cat "$work/$version.log" >&2; exit 1; }
    xdotool windowsize "$win" 1400 900
    sleep 3   # the mesh loads after the window shows
    xdotool windowfocus --sync "$win"

    # Filters (Alt+L) > the 7th entry below "Show current filter script": the menu's order is
    # fixed in MeshLab's mainwindow_Init.cpp, the same in both versions.
    xdotool key alt+l
    sleep 1
    xdotool key Down Down Down Down Down Down Down Right
    sleep 1
    import -window root "$out/meshlab-$version-menu.png"
    xdotool key Escape Escape Escape
    sleep 0.5

    # The dialog, opened by name through MeshLab's filter search (Ctrl+F): the submenu's
    # entries are sorted with every other plugin's, so their positions vary between installs.
    # The search ranks its matches by their descriptions too, so the exact name need not come
    # first: take the next match until the dialog that opens is the Lowpass's (the filter dock
    # shows one filter at a time, so a wrong one is simply replaced).
    local dialog="" k
    for k in 1 2 3 4; do
        xdotool key ctrl+f
        sleep 1
        xdotool type --delay 40 "GeoFilter: Lowpass"
        sleep 1
        xdotool key $(printf 'Down %.0s' $(seq "$k")) Return
        sleep 2
        dialog=$(xdotool search --onlyvisible --name "^GeoFilter: Lowpass$" 2>/dev/null | head -n1 || true)
        [ -z "$dialog" ] || break
    done
    [ -n "$dialog" ] || { echo "screenshots: the GeoFilter dialog did not open in $version" >&2; exit 1; }
    # 2020.09 opens its filter dock over the menu bar: put both where the bunny stays visible.
    xdotool windowmove "$dialog" 522 100
    sleep 1
    import -window root "$out/meshlab-$version-geofilter.png"

    # Preview: tick the box under the parameters (the dialog's last row above its buttons),
    # then type a larger feature radius as a percentage of the diagonal (8 %); the filter
    # reruns through its cache at each change.
    local X Y WIDTH HEIGHT SCREEN preview_from_bottom radius_field_x radius_field_y
    dialog_layout "$version"
    eval "$(xdotool getwindowgeometry --shell "$dialog")"
    xdotool mousemove $((X + 16)) $((Y + HEIGHT - preview_from_bottom)) click 1
    sleep 4
    xdotool mousemove $((X + radius_field_x)) $((Y + radius_field_y)) click --repeat 3 1
    xdotool type --delay 60 "8"
    xdotool key Tab
    sleep 6
    import -window root "$out/meshlab-$version-preview.png"
    kill "$pid"
    wait "$pid" 2>/dev/null || true
    echo "screenshots: $out/meshlab-$version-menu.png, $out/meshlab-$version-geofilter.png, $out/meshlab-$version-preview.png"
}

# Where the dialog's Preview box and the feature radius's percentage field are, from its
# frame's corner: the Preview box this far above the frame's bottom (2025.07 puts its PyMeshLab
# box under it), the field at this offset. Measured on this script's own screenshots.
dialog_layout() { # version
    case "$1" in
        2020.09) preview_from_bottom=82 radius_field_x=387 radius_field_y=183 ;;
        2022.02) preview_from_bottom=82 radius_field_x=461 radius_field_y=168 ;;
        *) preview_from_bottom=180 radius_field_x=461 radius_field_y=168 ;;
    esac
}

mkdir -p "$out"
[ "$shoot2020" = 0 ] || shoot 2020.09 "$ml2020"
for b in "${builds2022[@]}"; do
    read -r version exe < <(private_meshlab "$top/${b%%:*}") || exit 1
    [ -n "${exe:-}" ] || exit 1
    shoot "$version" "$exe"
done
