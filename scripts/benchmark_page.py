"""docs/results/benchmark.md from a full run of scripts/benchmark.sh (its table, the preview
rows and the plot), under the stamp of the command that made them."""
import os
import sys

from geofilter_experiments import pages  # experiments/, on PYTHONPATH (scripts/benchmark.sh)

out, command = sys.argv[1], sys.argv[2]
with open(os.path.join(out, "benchmark.md")) as f:
    table = f.read().strip()
with open(os.path.join(out, "preview.md")) as f:
    preview = f.read().strip()
with open(os.path.join(out, "clouds.md")) as f:
    clouds = f.read().strip()
text = f"""# The solver benchmark

Meshes normalised to unit bounding-box diagonal; filters: lowpass (25, 50, 1, 1.1, 0), band
exaggeration (25, 60, 1, 3, 0), notch (630, 1260, 1, 0.01, 1.1), and the Butterworth lowpass
of order 4 and 8 at cutoff 25. *fast* is the factored solver as the adapters run it
(assembly; CHOLMOD analysis and factorisations; solve, with the CG iterations of the complex
pole pairs, or "1 exact": a pair solved by a single-precision complex LDLᵀ refined in double),
at the default tolerance 1e-7 of the diagonal, stopped on the guaranteed error bound. *peak
MiB* is the process's peak RSS (each case runs in a process of its own, mesh included). *PCG*
is the paper's Jacobi-PCG at the same accuracy, capped ("> cap": not converged). *floor* is
one factorisation and solve of M + hK (one implicit-Euler step, assembly included) by the same
code. *Taubin x50* is vcglib's `VertexCoordTaubin` (the code of MeshLab's *Taubin Smooth*), 50
steps, in the same run. Compare ratios within this run, not times across runs.

{table}

![time against vertex count](images/benchmark.png)

## Preview

A parameter change on a mesh already filtered once (MeshLab's Preview), what the filter cache
keeps between the two runs:

{preview}

## Point clouds

The lowpass on each large mesh's vertices alone, as a point cloud: the cloud's Laplacian (k-d
tree, each point's tangent plane fitted to its 30 nearest, its Delaunay fan among the nearest
15), then the same filter; next to it the same lowpass on the mesh. Each in a process of its
own (peak RSS).

{clouds}
"""
pages.write_page("benchmark", text, {"benchmark.png": os.path.join(out, "benchmark.png")}, command=command)
