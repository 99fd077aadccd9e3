#!/usr/bin/env python3
"""Plots the grid SDF's error against the analytic torus by cell size (docs/sdf/grid_error.png)
from the CSV that tests/benchmarks/sdf_grid_error prints (docs/sdf/grid_error.csv).

Usage: build/release/tests/benchmarks/sdf_grid_error > docs/sdf/grid_error.csv
       scripts/sdf_grid_figure.py docs/sdf/grid_error.csv docs/sdf/grid_error.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    source, out = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(source)))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    styles = {"analytic": "-", "mesh": "--", "mesh_refined": "-.", "openvdb": ":"}
    names = {"analytic": "analytic grid", "mesh": "mesh grid",
             "mesh_refined": "mesh grid, 4x cells, band refined to the cell",
             "openvdb": "OpenVDB level set"}
    for origin in ("analytic", "mesh", "mesh_refined", "openvdb"):
        picked = [r for r in rows if r["source"] == origin]
        if not picked:
            continue
        cells = [float(r["cell"]) for r in picked]
        for how, marker in (("trilinear", "o"), ("tricubic", "s")):
            ax.loglog(cells, [float(r[how + "_mean"]) for r in picked], styles[origin],
                      marker=marker, label="%s, %s, mean" % (names[origin], how))
    ax.set_xlabel("cell size [m]")
    ax.set_ylabel("|grid - exact| within 5 cm of the surface [m]")
    ax.set_title("Grid SDF of a torus (0.4, 0.15): error against cell size")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
