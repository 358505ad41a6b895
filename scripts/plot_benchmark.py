#!/usr/bin/python3
"""Log-log plot of the solver benchmark: time against vertex count, per filter and method.

    plot_benchmark.py [RESULTS_DIR]      (default results/benchmark; reads benchmark.dat,
                                          writes benchmark.png next to it)
"""
import os
import shlex
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

folder = sys.argv[1] if len(sys.argv) > 1 else "results/benchmark"
rows = []
with open(os.path.join(folder, "benchmark.dat")) as f:
    for line in f:
        if line.startswith("#") or not line.strip():
            continue
        n, name, fast, pcg, capped, floor, taubin = shlex.split(line)
        rows.append((int(n), name, float(fast), float(pcg), capped == "1", float(floor), float(taubin)))

fig, ax = plt.subplots(figsize=(7.5, 5))
styles = {"lowpass": "o", "band exaggeration": "s", "notch": "^"}
colors = {"fast": "tab:blue", "pcg": "tab:red", "floor": "tab:green", "taubin": "tab:gray"}
for name, marker in styles.items():
    sel = sorted((r for r in rows if r[1] == name), key=lambda r: r[0])
    if not sel:
        continue
    n = [r[0] for r in sel]
    ax.plot(n, [r[2] for r in sel], marker=marker, color=colors["fast"], label=f"factored, {name}")
    ax.plot(n, [r[5] for r in sel], marker=marker, color=colors["floor"], ls=":", label=f"floor M + hK, {name}")
    for r in sel:  # PCG: hollow where it was capped (a lower bound)
        ax.plot(r[0], r[3], marker=marker, color=colors["pcg"], mfc="none" if r[4] else colors["pcg"], ls="none")
taubin = sorted({(r[0], r[6]) for r in rows})
ax.plot([t[0] for t in taubin], [t[1] for t in taubin], color=colors["taubin"], ls="--", label="vcglib Taubin, 50 steps")
ax.plot([], [], color=colors["pcg"], marker="o", ls="none", label="paper's Jacobi-PCG (hollow: capped, a lower bound)")
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("vertices")
ax.set_ylabel("seconds (2 cores)")
ax.set_title("GeoFilter solvers: time against mesh size")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=7, loc="lower right")
fig.tight_layout()
out = os.path.join(folder, "benchmark.png")
fig.savefig(out, dpi=110)
print(f"wrote {out}")
