#!/usr/bin/env bash
# The solver benchmark (not part of the test run; ~20 min here): builds, runs
# geofilter_benchmark on ~10k, ~100k and ~1M-vertex meshes, and plots the result.
# Writes results/benchmark/benchmark.md (the table), benchmark.dat and benchmark.png, and from
# a full run the page docs/results/benchmark.md.
# Extra arguments go to geofilter_benchmark (e.g. --pcg-seconds 60, --quick; --preview prints
# only the preview rows, in about a minute, --solve-profile only the triangular-solve profile at
# 1M vertices, in two minutes; neither writes anything; --denoise only Denoise on 160k-1M
# vertices against Denoise scoring on the whole mesh and Taubin, in ~13 minutes, into
# results/benchmark/denoise.md; --floor only each preset against the floor at 1M vertices,
# three alternated rounds, medians, in ~12 minutes, into results/benchmark/floor.md; --clouds
# only the point-cloud rows, in ~4 minutes, into results/benchmark/clouds.md, and the page
# again with the last full run's other tables).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build=${GEOFILTER_BUILD_DIR:-$top/build}
"$top/scripts/setup.sh"
"$top/scripts/build.sh" >/dev/null
"$build/tests/geofilter_benchmark" --meshes "$top/meshes" --out "$top/results/benchmark" \
    --pcg-seconds 30 --pcg-full-seconds 200 "$@"
case " $* " in
*" --preview "*|*" --region "*|*" --solve-profile "*|*" --denoise "*|*" --floor "*) ;;
*" --clouds "*)
   if [ -f "$top/results/benchmark/benchmark.md" ]; then
       PYTHONPATH="$top/experiments" /usr/bin/python3 "$top/scripts/benchmark_page.py" "$top/results/benchmark" \
           "scripts/benchmark.sh, its point-cloud rows from scripts/benchmark.sh --clouds"
   fi ;;
*) /usr/bin/python3 "$top/scripts/plot_benchmark.py" "$top/results/benchmark"
   # A full run is the page docs/results/benchmark.md; --quick and other partial runs are not.
   case " $* " in
   *" --quick "*) ;;
   *) PYTHONPATH="$top/experiments" /usr/bin/python3 "$top/scripts/benchmark_page.py" "$top/results/benchmark" \
          "scripts/benchmark.sh${*:+ $*}" ;;
   esac ;;
esac
