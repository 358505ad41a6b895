#!/usr/bin/env bash
# The main job: installs what is needed, builds the MeshLab plugin, and filters the
# Stanford bunny through Debian's meshlabserver (private prefix, under Xvfb) with two
# GeoFilter scripts:
#   scripts/mlx/bunny_lowpass.mlx  Lowpass, features smaller than the feature radius r = 0.1 removed
#   scripts/mlx/bunny_ears.mlx     Band Exaggeration, s1 measured from the selected ear (a script
#                                  from before the radius existed: it runs as it did)
# Results go to results/demo/: the filtered meshes (PLY), meshlabserver's logs and
# demo.png, a rendering of input and outputs side by side.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
out="$top/results/demo"
"$top/scripts/setup.sh"
"$top/scripts/build.sh"
mkdir -p "$out"
server="$build/meshlab-prefix/bin/meshlabserver"
for job in bunny_lowpass bunny_ears; do
    echo "demo: meshlabserver -i meshes/bunny00.off -s scripts/mlx/$job.mlx -o results/demo/$job.ply"
    if ! xvfb-run -a "$server" -i "$top/meshes/bunny00.off" -o "$out/$job.ply" -s "$top/scripts/mlx/$job.mlx" \
            >"$out/$job.log" 2>&1; then
        cat "$out/$job.log" >&2
        echo "demo: meshlabserver failed on $job" >&2
        exit 1
    fi
    # meshlabserver repeats its whole log after each filter: show each GeoFilter line once.
    grep '^LOG: .*GeoFilter' "$out/$job.log" | sed 's/^LOG: [0-9] /  /' | awk '!seen[$0]++'
done
"$top/experiments/run" geofilter_experiments.render_meshes "$out/demo.png" \
    "$top/meshes/bunny00.off=input: bunny00 (37,706 vertices)" \
    "$out/bunny_lowpass.ply=Lowpass, feature radius 0.1" \
    "$out/bunny_ears.ply=Band exaggeration, s1 from the ear"
echo "demo: results in $out (bunny_lowpass.ply, bunny_ears.ply, demo.png, logs)"
