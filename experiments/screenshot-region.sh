#!/usr/bin/env bash
# The region filter in the MeshLab 2020.09 GUI, under Xvfb:
#   docs/screenshots/meshlab-2020.09-region.png
# meshlabserver first runs scripts/mlx/bunny_ear_region.mlx (one ear selected and exaggerated,
# the rest untouched; the selection saved as face flags) and Measure Selected Feature on the
# same selection (the ellipsoid layer, saved with its vertex colour); the GUI then opens the
# result and the ellipsoid side by side with the input, and the screen is captured.
# Needs: xvfb, imagemagick (import), xdotool if present (to size the window); the default build (build/meshlab-prefix);
# meshes/bunny00.off (scripts/fetch-meshes.sh).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/docs/screenshots
mesh=${GEOFILTER_SCREENSHOT_MESH:-$top/meshes/bunny00.off}
prefix=${GEOFILTER_BUILD_DIR:-$top/build}/meshlab-prefix
for tool in Xvfb import xvfb-run; do
    command -v "$tool" >/dev/null || { echo "screenshot-region: $tool missing (apt-get install xvfb imagemagick)" >&2; exit 1; }
done
[ -f "$mesh" ] || "$top/scripts/fetch-meshes.sh"
[ -x "$prefix/bin/meshlab" ] || { echo "screenshot-region: $prefix/bin/meshlab missing: run scripts/build.sh" >&2; exit 1; }

# shellcheck source=experiments/screenshot-display.sh
source "$top/experiments/screenshot-display.sh"

# The ear selection of bunny_ear_region.mlx, then Measure Selected Feature.
sed -n '1,/<\/filter>/p' "$top/scripts/mlx/bunny_ear_region.mlx" | sed '/<!--/,/-->/d' >"$work/measure.mlx"
cat >>"$work/measure.mlx" <<'MLX'
 <filter name="GeoFilter: Measure Selected Feature"/>
</FilterScript>
MLX
xvfb-run -a "$prefix/bin/meshlabserver" -i "$mesh" -s "$work/measure.mlx" \
    -o "$work/ellipsoid.ply" -l x -m vc >"$work/measure.log" 2>&1 ||
    { cat "$work/measure.log" >&2; exit 1; }
xvfb-run -a "$prefix/bin/meshlabserver" -i "$mesh" -s "$top/scripts/mlx/bunny_ear_region.mlx" \
    -o "$work/one-ear.ply" -m ff >"$work/region.log" 2>&1 ||
    { cat "$work/region.log" >&2; exit 1; }
grep -h '^LOG: .*GeoFilter' "$work/measure.log" "$work/region.log" | sed 's/^LOG: [0-9] /  /' | awk '!seen[$0]++'

private_display
sleep 2

home=$work/home
mkdir -p "$home/run" && chmod 700 "$home/run"
# A project turns both layers by the same matrix (about y) so that the selected ear faces the
# camera; the files themselves stay as meshlabserver wrote them.
angle=${GEOFILTER_SCREENSHOT_ANGLE:-45}
matrix=$(awk -v a="$angle" 'BEGIN { r = a * atan2(0, -1) / 180; c = cos(r); s = sin(r);
    printf "%g 0 %g 0 \n0 1 0 0 \n%g 0 %g 0 \n0 0 0 1 \n", c, s, -s, c }')
{
    echo '<!DOCTYPE MeshLabDocument>'
    echo '<MeshLabProject>'
    echo ' <MeshGroup>'
    for layer in one-ear ellipsoid; do
        echo "  <MLMesh label=\"$layer\" filename=\"$layer.ply\">"
        printf '   <MLMatrix44>\n%s</MLMatrix44>\n' "$matrix"
        echo '  </MLMesh>'
    done
    echo ' </MeshGroup>'
    echo ' <RasterGroup/>'
    echo '</MeshLabProject>'
} >"$work/region.mlp"
HOME=$home XDG_RUNTIME_DIR=$home/run "$prefix/bin/meshlab" "$work/region.mlp" >"$work/gui.log" 2>&1 &
pids+=($!)
if command -v xdotool >/dev/null; then
    win=$(timeout 60 xdotool search --sync --onlyvisible --name "^MeshLab" | head -n1) ||
        { echo "screenshot-region: no MeshLab window" >&2; cat "$work/gui.log" >&2; exit 1; }
    xdotool windowsize "$win" 1400 900
    sleep 5   # the meshes load after the window shows
else
    sleep 20  # no way to wait for the window: give it time
fi
mkdir -p "$out"
import -window root "$out/meshlab-2020.09-region.png"
echo "screenshot-region: $out/meshlab-2020.09-region.png"
