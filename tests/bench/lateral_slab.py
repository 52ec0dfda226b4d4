#!/usr/bin/python3
"""Writes a laterally varying slab experiment for the benchmark scripts: bench_slab's lateral
field (density times 1 + a cos(2 pi x) cos(2 pi y) on a unit tile of 16 x 16 voxel columns; 16
voxel intervals in depth here, 32 there, the field being constant in depth; one
SGGX surface-like layer, alpha 0.5, T rho 5 on average, albedo 0.9), read through
geometry.density_vdb, and its laterally uniform twin.

  tests/bench/lateral_slab.py build/mcref OUT_DIR [--amplitude 0.5] [--lateral-voxels 16]
      [--depth-voxels 16] [--period 16] [--depth-period 0]

(--period: the field's lateral period in voxels; --depth-period > 0 multiplies the cosines by
cos(2 pi k / depth-period) at depth voxel k, a layer varying in depth as well; the defaults give
bench_slab's medium)

writes OUT_DIR/uniform.toml, OUT_DIR/uniform.vdb (mcref export-vdb of it), OUT_DIR/lateral.vdb
(its densities times the field, written by pyopenvdb) and OUT_DIR/lateral.toml, e.g. for

  tests/bench/estimator_efficiency.py build/mcref --experiments OUT_DIR/lateral.toml OUT_DIR/uniform.toml \\
      --estimators analog next_event next_event_mis --reps 5
"""
import argparse
import math
import os
import subprocess

import numpy as np
import pyopenvdb as vdb

EXPERIMENT = """# The bench_slab lateral medium (tests/bench/lateral_slab.py).
[geometry]
kind = "slab"
backend = "openvdb"
tile = 1.0
lateral_voxels = {lateral_voxels}
depth_voxels = {depth_voxels}
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
    ap.add_argument("--lateral-voxels", type=int, default=16)
    ap.add_argument("--depth-voxels", type=int, default=16)
    ap.add_argument("--period", type=float, default=16)
    ap.add_argument("--depth-period", type=float, default=0)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    sizes = dict(lateral_voxels=args.lateral_voxels, depth_voxels=args.depth_voxels)
    uniform = os.path.join(args.out, "uniform.toml")
    with open(uniform, "w") as f:
        f.write(EXPERIMENT.format(density_vdb="", density="density = 5.0", **sizes))
    exported = os.path.join(args.out, "uniform.vdb")
    subprocess.run([args.mcref, "export-vdb", uniform, "-o", exported, "--quiet"], check=True)
    grids, metadata = vdb.readAll(exported)
    for g in grids:
        if not g.name.endswith("_density"):
            continue
        lo, hi = g.evalActiveVoxelBoundingBox()
        shape = tuple(hi[a] - lo[a] + 1 for a in range(3))
        if g.activeVoxelCount() != math.prod(shape):
            raise SystemExit(f"{exported}: grid {g.name} is not dense over its bounding box")
        value = np.zeros(shape, dtype=np.float32)
        g.copyToArray(value, ijk=lo)
        i, j, k = (np.arange(lo[a], hi[a] + 1).reshape([-1 if b == a else 1 for b in range(3)]) for a in range(3))
        field = np.cos(2 * np.pi * i / args.period) * np.cos(2 * np.pi * j / args.period)
        if args.depth_period > 0:
            field = field * np.cos(2 * np.pi * k / args.depth_period)
        g.copyFromArray((value * (1 + args.amplitude * field)).astype(np.float32), ijk=lo)
    vdb.write(os.path.join(args.out, "lateral.vdb"), grids=grids, metadata=metadata)
    with open(os.path.join(args.out, "lateral.toml"), "w") as f:
        f.write(EXPERIMENT.format(density_vdb='density_vdb = "lateral.vdb"', density="", **sizes))


if __name__ == "__main__":
    main()
