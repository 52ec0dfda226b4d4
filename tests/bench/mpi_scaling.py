#!/usr/bin/python3
"""Strong scaling of mcref under mpirun (issue #17), and rank 0's assembly.

Each case runs on 1 and 2 ranks of one thread each, REPEAT times, the order of
np = 1 and np = 2 alternating. For each repetition:
  wall efficiency = wall(1) / (2 x wall(2));
  CPU ratio       = CPU(1) / CPU(2), the CPU time (user + system) of all
                    ranks and of mpirun: 1 when the split adds no work.
The cases:
  start-up   `mpirun -np N mcref --version`: what launching N ranks costs;
  dataset    64 slab entries of small tables (about 0.3 s of CPU each, slab
             thickness 0.5-2): the scheduler, its messages, the tail;
  paper      8 SpongeCake 2-layer entries with the paper's 32^4-bin tables at
             1/10 of the paper's paths, written --lean: rank 0's assembly of
             404 MB parts beside the computation;
  simulate   a slab run of 8 batches (4 * 10^6 paths per direction and batch).
Prints a Markdown table of the median [range] over the repetitions, with the
load average (1, 5, 15 min) before and after: the machine may be shared, and
then wall times measure the other jobs as much as mcref (CPU times much less).

Then rank 0's assembly time per paper-sized entry (32 x 32 x 32 x 32 bins,
the dataset's tables), full and lean, timed as `mcref merge` of a finished
file (the same reads and writes as the assembly from the parts), and the
bytes per entry.

  tests/bench/mpi_scaling.py build/mcref [REPEAT] [CASE ...]   (REPEAT 0: the assembly only)
"""
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

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
entries = 64
seed = 7
[[parameter]]
key = "geometry.layer.0.thickness"
range = [0.5, 2.0]
distribution = "log_uniform"
"""


def paper_dataset(src, folder, entries, paths_scale, batches=4):
    """spongecake_2layer.toml cut to `entries` entries at `paths_scale` of the paper's paths, in `folder`."""
    os.mkdir(folder)
    for name in ("spongecake_base.toml", "spongecake_2layer.toml"):
        shutil.copy(os.path.join(src, "validate/datasets", name), folder)
    base = open(f"{folder}/spongecake_base.toml").read()
    samples = int(re.search(r"^samples = (\d+)$", base, re.M).group(1))
    base = re.sub(r"^samples = \d+$", f"samples = {max(1, round(samples * paths_scale))}", base, flags=re.M)
    open(f"{folder}/spongecake_base.toml", "w").write(re.sub(r"^batches = 4$", f"batches = {batches}", base, flags=re.M))
    ds = open(f"{folder}/spongecake_2layer.toml").read()
    open(f"{folder}/spongecake_2layer.toml", "w").write(re.sub(r"^entries = \d+$", f"entries = {entries}", ds, flags=re.M))
    return f"{folder}/spongecake_2layer.toml"


def cell(values, digits=2):
    return f"{statistics.median(values):.{digits}f} [{min(values):.{digits}f}, {max(values):.{digits}f}]"


def load():
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def main():
    mcref = os.path.realpath(sys.argv[1])
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    only = set(sys.argv[3:])
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    work = tempfile.mkdtemp(prefix="mcref_scaling_")
    os.chdir(work)
    t_start = time.perf_counter()
    try:
        open("base.toml", "w").write(BASE)
        open("ds.toml", "w").write(DATASET)
        paper = paper_dataset(src, "paper_bench", 8, 0.1)
        cases = {
            "start-up": ["--version"],
            "dataset": ["dataset", "ds.toml", "-o", "out.h5", "--threads", "1", "--quiet"],
            "paper": ["dataset", paper, "-o", "out.h5", "--threads", "1", "--quiet", "--lean"],
            "simulate": ["simulate", os.path.join(src, "validate/experiments/slab_single_layer.toml"), "-o", "out.h5",
                         "--threads", "1", "--quiet", "--set", "run.batches=8", "--set", "measure.0.samples=4000000"],
        }
        rows = []
        print(f"load average before: {load()}", flush=True)
        for case, args in cases.items() if repeat > 0 else []:
            if only and case not in only:
                continue
            times = {1: [], 2: []}
            for r in range(repeat):
                for n in ((1, 2) if r % 2 == 0 else (2, 1)):
                    shutil.rmtree("out.h5.parts", ignore_errors=True)
                    if os.path.exists("out.h5"):
                        os.remove("out.h5")
                    times[n].append(timed_run(MPIRUN + ["-np", str(n), mcref] + args)[1:])  # (wall, CPU)
            wall = [a[0] / (2 * b[0]) for a, b in zip(times[1], times[2])]
            cpu = [a[1] / b[1] for a, b in zip(times[1], times[2])]
            rows.append(f"| `{case}` | {cell([t[0] for t in times[1]])} s | {cell([t[0] for t in times[2]])} s | "
                        f"{cell(wall)} | {cell([t[1] for t in times[1]])} s | {cell([t[1] for t in times[2]])} s | "
                        f"{cell(cpu)} |")
            print(f"{case}: done at load {load()}", file=sys.stderr, flush=True)
        if rows:
            print(f"\n{repeat} alternating repetitions, median [range]; one thread per rank\n")
            print("| run | wall np = 1 | wall np = 2 | wall efficiency T1 / (2 T2) | CPU np = 1 | "
                  "CPU np = 2 (all ranks) | CPU ratio CPU1 / CPU2 |")
            print("|---|---|---|---|---|---|---|")
            print("\n".join(rows) + "\n")
        print(f"load average after: {load()}", flush=True)
        if only and "assembly" not in only:
            return
        one_path = paper_dataset(src, "paper", 8, 0, batches=2)
        subprocess.run([mcref, "dataset", one_path, "-o", "paper.h5", "--quiet"], check=True)
        for lean in ([], ["--lean"]):
            if os.path.exists("merged.h5"):
                os.remove("merged.h5")
            _, wall, cpu = timed_run([mcref, "merge", "paper.h5", "-o", "merged.h5", "--quiet"] + lean)
            print(f"assembly{' (lean)' if lean else ''}: {wall / 8:.2f} s an entry ({cpu / 8:.2f} s CPU), "
                  f"{os.path.getsize('merged.h5') / 8 / 1e6:.1f} MB an entry")
    finally:
        shutil.rmtree(work)
        print(f"(the script took {time.perf_counter() - t_start:.0f} s)")


if __name__ == "__main__":
    main()
