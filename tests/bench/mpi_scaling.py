#!/usr/bin/python3
"""Strong scaling of mcref under mpirun (issue #17), and rank 0's assembly.

The same dataset (24 slab entries of about 0.3 s of CPU) and the same simulate run
(8 batches) on 1 and 2 ranks of one thread each, REPEAT times, the order of
np = 1 and np = 2 alternating. For each repetition:
  wall efficiency = wall(1) / (2 x wall(2));
  CPU ratio       = CPU(1) / CPU(2), the CPU time (user + system) of all
                    ranks and of mpirun: 1 when the split adds no work.
Prints the median and range over the repetitions, and the load average
before and after (the machine may be shared: wall times then measure the
other jobs as much as mcref; CPU times much less so).

Then rank 0's assembly time per entry of a paper-sized SpongeCake entry
(32 x 32 x 32 x 32 bins, the dataset's tables), full and lean, timed as
`mcref merge` of the finished file (the same reads and writes as the
assembly from the parts), and the bytes per entry.

  tests/bench/mpi_scaling.py build/mcref [REPEAT]   (REPEAT 0: the assembly only)
"""
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

from timed_run import timed_run

MPIRUN = ["mpirun", "-q", "--allow-run-as-root", "--oversubscribe"]
BASE = """[geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = 0.8
[run]
seed = 1
batches = 2
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 40, 60]
theta_o_bins = 8
phi_bins = 8
samples = 200000
"""
DATASET = """[dataset]
experiment = "base.toml"
entries = 24
seed = 7
[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.1, 10.0]
distribution = "log_uniform"
"""


def spread(values):
    return f"median {statistics.median(values):.3f} [{min(values):.3f}, {max(values):.3f}]"


def main():
    mcref = os.path.realpath(sys.argv[1])
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    work = tempfile.mkdtemp(prefix="mcref_scaling_")
    os.chdir(work)
    try:
        open("base.toml", "w").write(BASE)
        open("ds.toml", "w").write(DATASET)
        verbs = {
            "dataset": ["dataset", "ds.toml", "-o", "out.h5", "--threads", "1", "--quiet"],
            "simulate": ["simulate", os.path.join(src, "validate/experiments/slab_single_layer.toml"), "-o", "out.h5",
                         "--threads", "1", "--quiet", "--set", "run.batches=8", "--set", "measure.0.samples=200000"],
        }
        print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
        for verb, args in verbs.items() if repeat > 0 else []:
            times = {1: [], 2: []}
            for r in range(repeat):
                for n in ((1, 2) if r % 2 == 0 else (2, 1)):
                    shutil.rmtree("out.h5.parts", ignore_errors=True)
                    if os.path.exists("out.h5"):
                        os.remove("out.h5")
                    times[n].append(timed_run(MPIRUN + ["-np", str(n), mcref] + args)[1:])  # (wall, CPU)
            wall = [a[0] / (2 * b[0]) for a, b in zip(times[1], times[2])]
            cpu = [a[1] / b[1] for a, b in zip(times[1], times[2])]
            print(f"{verb}: wall np=1 {spread([t[0] for t in times[1]])} s, np=2 {spread([t[0] for t in times[2]])} s; "
                  f"CPU np=1 {spread([t[1] for t in times[1]])} s, np=2 {spread([t[1] for t in times[2]])} s")
            print(f"{verb}: wall efficiency {spread(wall)}; CPU ratio {spread(cpu)} ({repeat} alternating repetitions)")
        print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
        os.mkdir("paper")
        for name in ("spongecake_base.toml", "spongecake_2layer.toml"):
            shutil.copy(os.path.join(src, "validate/datasets", name), "paper")
        base = open("paper/spongecake_base.toml").read()
        base = re.sub(r"^samples = \d+$", "samples = 1", base, flags=re.M)
        open("paper/spongecake_base.toml", "w").write(re.sub(r"^batches = 4$", "batches = 2", base, flags=re.M))
        ds = open("paper/spongecake_2layer.toml").read()
        open("paper/spongecake_2layer.toml", "w").write(re.sub(r"^entries = \d+$", "entries = 8", ds, flags=re.M))
        subprocess.run([mcref, "dataset", "paper/spongecake_2layer.toml", "-o", "paper.h5", "--quiet"], check=True)
        for lean in ([], ["--lean"]):
            if os.path.exists("merged.h5"):
                os.remove("merged.h5")
            _, wall, cpu = timed_run([mcref, "merge", "paper.h5", "-o", "merged.h5", "--quiet"] + lean)
            print(f"assembly{' (lean)' if lean else ''}: {wall / 8:.2f} s an entry ({cpu / 8:.2f} s CPU), "
                  f"{os.path.getsize('merged.h5') / 8 / 1e6:.1f} MB an entry")
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
