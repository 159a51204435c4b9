#!/usr/bin/python3
"""Compares two growth runs of the same scene along the biofilm-fluid interface: the interface
height, the substrate flux density into the biofilm and the wall shear stress at each interface
node, at the growth steps both runs wrote. Made for case (c): the paper's transient inner loops
(c_shear.yaml) against the quasi-steady approximation (c_shear_quasi_steady.yaml).

usage: scripts/compare_interfaces.py RUN_DIR REFERENCE_DIR [STEP ...]
Each directory holds a run's scalar_NNNNNN.h5 files; both runs must use the same mesh (node
numbering). Without STEP, every step both wrote. Differences are RUN minus REFERENCE; "rel" divides
the largest difference by the reference's largest magnitude along the interface (for the height,
by the reference's largest rise since step 0). Uses Debian's python3-h5py and python3-numpy.
"""
import os
import re
import sys

import h5py
import numpy as np


def steps_in(run_dir):
    found = (re.fullmatch(r"scalar_(\d{6})\.h5", name) for name in os.listdir(run_dir))
    return {int(m.group(1)) for m in found if m}


def read(run_dir, step):
    with h5py.File(os.path.join(run_dir, "scalar_%06d.h5" % step), "r") as f:
        return {key: f[key][...] for key in
                ("coordinates", "connectivity", "block", "flux_density", "wall_shear_stress")}


def interface_nodes(fields):
    """Nodes shared by a biofilm (block 0) and a fluid element, on the front plane, sorted by x."""
    conn, block, coords = fields["connectivity"], fields["block"].reshape(-1), fields["coordinates"]
    in_biofilm = np.zeros(len(coords), bool)
    in_fluid = np.zeros(len(coords), bool)
    in_biofilm[conn[block == 0].reshape(-1)] = True
    in_fluid[conn[block != 0].reshape(-1)] = True
    front = np.abs(coords[:, 2] - coords[:, 2].min()) < 1e-9
    nodes = np.where(in_biofilm & in_fluid & front)[0]
    return nodes[np.argsort(coords[nodes, 0])]


def line(name, x, run, reference, scale):
    diff = run - reference
    worst = np.argmax(np.abs(diff))
    relative = "%.2f%%" % (100 * abs(diff[worst]) / scale) if scale > 0 else "-"
    return "  %-13s mean %+.4g (reference %.4g), largest |difference| %.4g (%s) at x = %.4g" % (
        name, diff.mean(), reference.mean(), abs(diff[worst]), relative, x[worst])


def compare(run_dir, reference_dir, step, start_height):
    run, ref = read(run_dir, step), read(reference_dir, step)
    if run["coordinates"].shape != ref["coordinates"].shape:
        sys.exit("compare_interfaces: %s and %s are not the same mesh" % (run_dir, reference_dir))
    nodes = interface_nodes(ref)
    height_run = run["coordinates"][nodes, 1]
    height_ref = ref["coordinates"][nodes, 1]
    rise_ref = height_ref - start_height
    print("growth step %d (%d interface nodes):" % (step, len(nodes)))
    x = ref["coordinates"][nodes, 0]
    print(line("height rise", x, height_run - start_height, rise_ref, np.abs(rise_ref).max()))
    for key, name in (("flux_density", "flux density"), ("wall_shear_stress", "wall shear")):
        a, b = run[key].reshape(-1)[nodes], ref[key].reshape(-1)[nodes]
        print(line(name, x, a, b, np.abs(b).max()))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    run_dir, reference_dir = sys.argv[1], sys.argv[2]
    common = sorted(steps_in(run_dir) & steps_in(reference_dir))
    steps = [int(s) for s in sys.argv[3:]] or common
    missing = [s for s in steps if s not in common]
    if missing or not steps:
        sys.exit("compare_interfaces: step(s) %s not written by both runs (both wrote %s)" %
                 (missing, common))
    start = read(reference_dir, 0) if 0 in common else read(reference_dir, steps[0])
    start_height = start["coordinates"][interface_nodes(start), 1]
    for step in steps:
        compare(run_dir, reference_dir, step, start_height)


if __name__ == "__main__":
    main()
