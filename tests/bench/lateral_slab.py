#!/usr/bin/python3
"""Writes a laterally varying slab experiment for the benchmark scripts: bench_slab's lateral
field (density times 1 + a cos(2 pi x) cos(2 pi y) on a unit tile of 16 x 16 voxel columns; 16
voxel intervals in depth here, 32 there, the field being constant in depth; one
SGGX surface-like layer, alpha 0.5, T rho 5 on average, albedo 0.9), read through
geometry.density_vdb, and its laterally uniform twin.

  tests/bench/lateral_slab.py build/mcref OUT_DIR [--amplitude 0.5]

writes OUT_DIR/uniform.toml, OUT_DIR/uniform.vdb (mcref export-vdb of it), OUT_DIR/lateral.vdb
(its densities times the field, written by pyopenvdb) and OUT_DIR/lateral.toml, e.g. for

  tests/bench/estimator_efficiency.py build/mcref --experiments OUT_DIR/lateral.toml OUT_DIR/uniform.toml \\
      --estimators analog next_event next_event_mis --reps 5
"""
import argparse
import math
import os
import subprocess

import pyopenvdb as vdb

EXPERIMENT = """# The bench_slab lateral medium (tests/bench/lateral_slab.py).
[geometry]
kind = "slab"
backend = "openvdb"
tile = 1.0
lateral_voxels = 16
depth_voxels = 16
{density_vdb}
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
{density}
albedo = 0.9

[run]
seed = 4100
batches = 10

[[measure]]
quantity = "brdf"
theta_i_deg = [0, 30, 60, 80]
theta_o_bins = 12
phi_bins = 12
samples = 20000
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mcref")
    ap.add_argument("out")
    ap.add_argument("--amplitude", type=float, default=0.5)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    uniform = os.path.join(args.out, "uniform.toml")
    with open(uniform, "w") as f:
        f.write(EXPERIMENT.format(density_vdb="", density="density = 5.0"))
    exported = os.path.join(args.out, "uniform.vdb")
    subprocess.run([args.mcref, "export-vdb", uniform, "-o", exported, "--quiet"], check=True)
    grids, metadata = vdb.readAll(exported)
    for g in grids:
        if not g.name.endswith("_density"):
            continue
        acc = g.getAccessor()
        lo, hi = g.evalActiveVoxelBoundingBox()
        for i in range(lo[0], hi[0] + 1):
            for j in range(lo[1], hi[1] + 1):
                field = 1 + args.amplitude * math.cos(2 * math.pi * i / 16) * math.cos(2 * math.pi * j / 16)
                for k in range(lo[2], hi[2] + 1):
                    value, on = acc.probeValue((i, j, k))
                    if on:
                        acc.setValueOn((i, j, k), value * field)
    vdb.write(os.path.join(args.out, "lateral.vdb"), grids=grids, metadata=metadata)
    with open(os.path.join(args.out, "lateral.toml"), "w") as f:
        f.write(EXPERIMENT.format(density_vdb='density_vdb = "lateral.vdb"', density=""))


if __name__ == "__main__":
    main()
