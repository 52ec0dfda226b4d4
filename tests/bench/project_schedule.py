#!/usr/bin/python3
"""Projects the wall time of the paper-scale SpongeCake datasets under mpirun
(issue #17) from measured entry costs (dataset_entry_costs.py's CSV).

Simulates the dynamic scheduler of sim/dataset/entry_scheduler: entries in
index order, each to the first rank that is free, one core per rank
(--threads 1). Each dataset's entry costs are drawn with replacement from its
measured sample (bootstrap, --draws times). Rank 0's assembly
(sim/dataset/entry_assembler) runs beside the computation, on a thread of its
own: entry i is appended once it and every entry before it are finished and
the previous append is done, at --assembly-s seconds an entry (full storage)
or --lean-assembly-s (lean). After the last append, the whole file is read
once more for its seal (--seal-s seconds an entry). The two dataset files
run as two jobs, one after the other. Also reports the rate at which the
ranks write parts while they compute, and rank 0's request rate.

  tests/bench/project_schedule.py costs.csv --entry-bytes 403.9e6 --assembly-s 0.9 \\
      --lean-assembly-s 0.6 --seal-s 0.1 --lean-seal-s 0.03 --cores 64 1024
(costs.csv: dataset_entry_costs.py's output; lines starting with # are skipped.
With costs measured at a fraction of the paper's paths, --paths-scale and
--fixed-seconds scale them up.)
"""
import argparse
import csv
import heapq
import random
import statistics

DATASETS = {"spongecake_1layer.toml": 4000, "spongecake_2layer.toml": 12000}


def finish_times(costs, cores):
    """When each entry (in index order) finishes: the next entry goes to the first free rank."""
    free = [0.0] * cores
    done = []
    for c in costs:
        t = heapq.heappop(free) + c
        done.append(t)
        heapq.heappush(free, t)
    return done


def assembled(done, per_entry):
    """When rank 0's assembly appends the last entry: in index order, each once finished."""
    w = 0.0
    for t in done:
        w = max(w, t) + per_entry
    return w


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("costs")
    ap.add_argument("--column", default="cpu", help="the CSV column of an entry's cost (cpu: CPU seconds; seconds: wall)")
    ap.add_argument("--paths-scale", type=float, default=1.0, help="the paths scale the costs were measured at")
    ap.add_argument("--fixed-seconds", type=float, default=0.0,
                    help="an entry's cost without paths (samples = 1): kept as is, the rest scaled by 1/paths-scale")
    ap.add_argument("--entry-bytes", type=float, required=True, help="bytes of one entry in DATA.h5 (full storage)")
    ap.add_argument("--assembly-s", type=float, required=True, help="rank 0's assembly seconds per entry (full)")
    ap.add_argument("--lean-assembly-s", type=float, required=True, help="the same writing lean storage")
    ap.add_argument("--seal-s", type=float, required=True, help="seconds per entry of the final seal (full)")
    ap.add_argument("--lean-seal-s", type=float, required=True, help="the same for a lean file")
    ap.add_argument("--cores", type=int, nargs="+", default=[64, 1024])
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    measured = {name: [] for name in DATASETS}
    for row in csv.DictReader(line for line in open(args.costs) if not line.startswith("#")):
        s = float(row[args.column])
        measured[row["dataset"]].append(args.fixed_seconds + max(0.0, s - args.fixed_seconds) / args.paths_scale)
    rng = random.Random(args.seed)
    entries = sum(DATASETS.values())
    total = sum(statistics.mean(v) * DATASETS[n] for n, v in measured.items() if v)
    mean_cost = total / entries
    print("entries measured: " + ", ".join(f"{n} {len(v)}" for n, v in measured.items()))
    for n, v in measured.items():
        if v:
            q = sorted(v)
            print(f"  {n}: cost per entry at paper paths (1 core): mean {statistics.mean(v):.1f} s, "
                  f"min {q[0]:.1f}, median {statistics.median(v):.1f}, max {q[-1]:.1f} s")
    print(f"whole dataset on 1 core: {total / 3600:.1f} core-hours ({entries} entries, mean {mean_cost:.1f} s)")
    storage = {"full": (args.assembly_s, args.seal_s), "lean": (args.lean_assembly_s, args.lean_seal_s)}
    for kind, (a, seal) in storage.items():
        print(f"{kind}: rank 0 appends {1 / a:.2f} entries/s, as fast as {mean_cost / a:.0f} cores compute them; "
              f"final seal {seal * entries / 3600:.2f} h")
    print("| cores | compute (median of draws) | ideal | scheduling efficiency | wall, full | wall, lean | "
          "limit | parts written at | requests/s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for cores in args.cores:
        spans, walls = [], {k: [] for k in storage}
        for _ in range(args.draws):
            span, wall = 0.0, {k: 0.0 for k in storage}
            for n, count in DATASETS.items():  # one job per dataset file, one after the other
                done = finish_times([rng.choice(measured[n]) for _ in range(count)], cores)
                span += max(done)
                for k, (a, seal) in storage.items():
                    wall[k] += assembled(done, a) + seal * count
            spans.append(span)
            for k in storage:
                walls[k].append(wall[k])
        compute = statistics.median(spans)
        w = {k: statistics.median(v) for k, v in walls.items()}
        limit = "assembly" if cores * storage["full"][0] > mean_cost else "compute"
        limit_lean = "assembly" if cores * storage["lean"][0] > mean_cost else "compute"
        print(f"| {cores} | {compute / 3600:.2f} h | {total / cores / 3600:.2f} h | {total / cores / compute:.3f} | "
              f"{w['full'] / 3600:.2f} h | {w['lean'] / 3600:.2f} h | {limit} (full), {limit_lean} (lean) | "
              f"{cores * args.entry_bytes / mean_cost / 1e9:.2f} GB/s | {cores / mean_cost:.1f} |")


if __name__ == "__main__":
    main()
