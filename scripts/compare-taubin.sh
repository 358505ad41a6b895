#!/usr/bin/env bash
# GeoFilter Lowpass side by side with MeshLab's Taubin, cotangent Laplacian and HC Laplacian
# smoothing (issue 5). For bunny00, diplodocus and fandisk_large (meshes/, scaled to unit
# bounding-box diagonal): Gaussian noise along the normals at 0.1 %, 0.25 % and 0.5 % of the
# diagonal (seeded), then every method through the private prefix's meshlabserver (under Xvfb):
#   - GeoFilter Lowpass with s1 from the mean edge length h (r = 3 h, s1 = 2/r^2, s2 = 2 s1,
#     G0 = 1, G1 = 1.1, Ginf = 0), plus the best r/h of a small sweep;
#   - Taubin Smooth (lambda 0.5, mu -0.53), Laplacian Smooth (cotangent weights) and
#     HC Laplacian Smooth, each at the best step count of a sweep.
# The "best" settings are chosen against the clean mesh (an oracle), and labelled so.
# Writes results/taubin/comparison.md (RMS and max vertex distance, RMS distance to the clean
# surface, volume change, mean face-normal error, time), sweeps.json (every sweep point) and
# <mesh>.png (noisy, GeoFilter, Taubin, clean at 0.25 % noise). About 5-8 minutes on 2 shared cores.
# Options are passed to scripts/compare_taubin.py (--help); needs a built prefix (scripts/build.sh).
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
exec /usr/bin/python3 "$top/scripts/compare_taubin.py" "$@"
