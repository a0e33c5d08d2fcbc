#!/usr/bin/env python3
"""Plot the meshes written by `shellflow mesh OUTDIR`: the x-y section (z = 0 face) of the
fluid and space meshes, the shell mesh, and histograms of element quality.

usage: plot_mesh.py OUTDIR [-o OUTDIR/meshes.png]
Reads OUTDIR/{fluid,space,shell}.vtu (whichever exist) with meshio.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402

TETS = ("tetra", "tetra10", "VTK_LAGRANGE_TETRAHEDRON", "tetra20")
TRIS = ("triangle", "triangle6", "VTK_LAGRANGE_TRIANGLE", "triangle10")


def section_edges(points, cells, z0, tol):
    """Edges (vertex pairs) of the cells' faces lying in the plane z = z0."""
    edges = set()
    on = np.abs(points[:, 2] - z0) < tol
    for c in cells:
        v = [i for i in c[:4] if on[i]]
        for i in range(len(v)):
            for j in range(i + 1, len(v)):
                edges.add((min(v[i], v[j]), max(v[i], v[j])))
    return np.array(sorted(edges))


def first_block(m, names):
    for block in m.cells:
        if block.type in names:
            return block.data, m.cell_data.get("quality", [None])[0]
    return None, None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir")
    parser.add_argument("-o", "--output")
    args = parser.parse_args(argv)
    output = args.output or os.path.join(args.outdir, "meshes.png")

    fig = plt.figure(figsize=(12, 8))
    grid = fig.add_gridspec(2, 3, height_ratios=[2.2, 1])
    ax_section = fig.add_subplot(grid[0, :])
    ax_section.set_aspect("equal")
    colours = {"fluid": ("k", 0.25), "space": ("r", 1.0)}
    hist_axes = [fig.add_subplot(grid[1, i]) for i in range(3)]
    for k, key in enumerate(("fluid", "space", "shell")):
        path = os.path.join(args.outdir, key + ".vtu")
        if not os.path.exists(path):
            hist_axes[k].set_visible(False)
            continue
        m = meshio.read(path)
        pts = m.points
        cells, quality = first_block(m, TETS)
        if cells is not None:
            z0 = pts[:, 2].min()
            tol = 1e-9 * max(1.0, np.ptp(pts))
            e = section_edges(pts, cells, z0, tol)
            colour, width = colours[key]
            if len(e):
                segs = np.stack([pts[e[:, 0], :2], pts[e[:, 1], :2]], axis=1)
                from matplotlib.collections import LineCollection

                ax_section.add_collection(LineCollection(segs, colors=colour, linewidths=width,
                                                         label=f"{key} mesh (z = {z0:g})"))
        else:
            cells, quality = first_block(m, TRIS)
            if cells is not None:
                # The shell lies in the plane y = 0: draw it as a thick line on the section.
                ax_section.plot(pts[:, 0], pts[:, 1], "b.", ms=3, label="shell nodes")
        if quality is not None:
            lo, hi = float(quality.min()), float(quality.max())
            if hi - lo < 1e-6:  # all elements alike (structured mesh)
                lo, hi = lo - 0.01, hi + 0.01
            hist_axes[k].hist(quality, bins=40, range=(lo, hi), color="0.4")
            hist_axes[k].set_title(f"{key}: {len(cells)} elements, {len(pts)} nodes\n"
                                   f"quality min {quality.min():.3f}, mean {quality.mean():.3f}",
                                   fontsize=9)
            hist_axes[k].set_xlabel("element quality")
    ax_section.autoscale()
    ax_section.set_xlabel("x [m]")
    ax_section.set_ylabel("y [m]")
    ax_section.legend(loc="upper right", fontsize=8)
    ax_section.set_title("x-y section of the meshes")
    fig.tight_layout()
    fig.savefig(output, dpi=130)
    print(f"plot_mesh: wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
