#!/usr/bin/python3
"""Reproduces Figure 2 of Coroneo, Yoshihara & Wall from biofsi's own output: the substrate
concentration and the biofilm mesh after 0, 30 and 60 growth steps, one row per case (with the
flow's velocity as arrows where the run has a fluid, case (c)).

usage: scripts/figure2.py OUT.png CASE_DIR [CASE_DIR ...]
Run with Debian's /usr/bin/python3 (python3-matplotlib, python3-h5py). Each CASE_DIR holds a run's scalar_NNNNNN.h5 files (written at growth steps). Uses Debian's
python3-matplotlib and python3-h5py.
"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402

STEPS = (0, 30, 60)


def front_faces(coords, conn):
    """The z-min face of every element (VTK nodes 0,1,2,3) as x-y quads, and its node ids."""
    zmin = coords[:, 2].min()
    quads = conn[:, :4]
    keep = np.all(np.abs(coords[quads, 2] - zmin) < 1e-9, axis=1)
    return quads[keep], keep


def load(case_dir, step):
    path = os.path.join(case_dir, "scalar_%06d.h5" % step)
    with h5py.File(path, "r") as f:
        coords = f["coordinates"][...]
        conn = f["connectivity"][...]
        block = f["block"][...].reshape(-1)
        phi = f["phi"][...].reshape(-1)
        velocity = f["velocity"][...].reshape(-1, 3) if "velocity" in f else None
    return coords, conn, block, phi, velocity


def panel(ax, case_dir, step, vmax):
    coords, conn, block, phi, velocity = load(case_dir, step)
    quads, keep = front_faces(coords, conn)
    tri = Triangulation(coords[:, 0], coords[:, 1],
                        np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]))
    image = ax.tripcolor(tri, phi, shading="gouraud", cmap="viridis", vmin=0, vmax=vmax)
    biofilm = quads[block[keep] == 0]
    ax.add_collection(PolyCollection(coords[biofilm][:, :, :2], facecolors="none",
                                     edgecolors="k", linewidths=0.3))
    if velocity is not None:
        # Case (c)'s flow: arrows at every fourth front node above the biofilm.
        front = np.where(np.abs(coords[:, 2] - coords[:, 2].min()) < 1e-9)[0][::4]
        moving = front[np.hypot(velocity[front, 0], velocity[front, 1]) > 0]
        ax.quiver(coords[moving, 0], coords[moving, 1], velocity[moving, 0], velocity[moving, 1],
                  color="w", width=0.003, scale=1.5)
    ax.set_aspect("equal")
    ax.set_xlim(coords[:, 0].min(), coords[:, 0].max())
    ax.set_ylim(coords[:, 1].min(), coords[:, 1].max())
    # Two lines: long case names (c_shear_quasi_steady) would run into the next panel's title.
    ax.set_title("%s\ngrowth step %d" % (os.path.basename(case_dir.rstrip("/")), step), fontsize=8)
    ax.tick_params(labelsize=6)
    return image


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, cases = sys.argv[1], sys.argv[2:]
    fig, axes = plt.subplots(len(cases), len(STEPS), figsize=(3.2 * len(STEPS), 3.2 * len(cases)),
                             squeeze=False)
    for row, case_dir in enumerate(cases):
        for col, step in enumerate(STEPS):
            image = panel(axes[row][col], case_dir, step, 1.0)
    fig.colorbar(image, ax=axes, shrink=0.6, label="substrate concentration")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=150, bbox_inches="tight")
    os.replace(tmp, out)
    print("figure: " + out)


if __name__ == "__main__":
    main()
