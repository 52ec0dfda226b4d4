#!/usr/bin/python3
"""Projects the wall time of the paper-scale SpongeCake datasets under mpirun
(issue #17) from measured entry costs (dataset_entry_costs.py's CSV).

Simulates the dynamic scheduler of sim/dataset/entry_scheduler: entries in
index order, each to the first rank that is free, one core per rank
(--threads 1). Each dataset's entry costs are drawn with replacement from its
measured sample (bootstrap, --draws times). Then adds rank 0's serial
assembly of DATA.h5 (measured seconds per entry, full and lean), and
reports the rate at which the ranks write parts while they compute.

  tests/bench/project_schedule.py costs.csv --paths-scale 0.1 --entry-bytes 1.7e8 \\
      --fixed-seconds 7.4 --assembly-s 0.85 --lean-assembly-s 0.65 --cores 64 1024
(costs.csv: dataset_entry_costs.py's output; lines starting with # are skipped.)
"""
import argparse
import csv
import heapq
import random
import statistics

DATASETS = {"spongecake_1layer.toml": 4000, "spongecake_2layer.toml": 12000}


def makespan(costs, cores):
    free = [0.0] * cores  # when each rank is free again
    for c in costs:  # queue order: the next entry goes to the first free rank
        heapq.heappush(free, heapq.heappop(free) + c)
    return max(free)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("costs")
    ap.add_argument("--column", default="cpu", help="the CSV column of an entry's cost (cpu: CPU seconds; seconds: wall)")
    ap.add_argument("--paths-scale", type=float, default=1.0, help="the paths scale the costs were measured at")
    ap.add_argument("--fixed-seconds", type=float, default=0.0,
                    help="an entry's cost without paths (samples = 1): kept as is, the rest scaled by 1/paths-scale")
    ap.add_argument("--entry-bytes", type=float, required=True, help="bytes of one entry in DATA.h5 (full storage)")
    ap.add_argument("--assembly-s", type=float, required=True, help="rank 0's assembly seconds per entry (full)")
    ap.add_argument("--lean-assembly-s", type=float, default=0, help="the same writing lean storage")
    ap.add_argument("--cores", type=int, nargs="+", default=[64, 1024])
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    measured = {name: [] for name in DATASETS}
    for row in csv.DictReader(line for line in open(args.costs) if not line.startswith("#")):
        s = float(row[args.column])
        measured[row["dataset"]].append(args.fixed_seconds + max(0.0, s - args.fixed_seconds) / args.paths_scale)
    rng = random.Random(args.seed)
    total = sum(statistics.mean(v) * DATASETS[n] for n, v in measured.items() if v)
    print("entries measured: " + ", ".join(f"{n} {len(v)}" for n, v in measured.items()))
    for n, v in measured.items():
        if v:
            q = sorted(v)
            print(f"  {n}: cost per entry at paper paths (1 core): mean {statistics.mean(v):.1f} s, "
                  f"min {q[0]:.1f}, median {statistics.median(v):.1f}, max {q[-1]:.1f} s")
    print(f"whole dataset on 1 core: {total / 3600:.1f} h ({sum(DATASETS.values())} entries)")
    for cores in args.cores:
        spans = []
        for _ in range(args.draws):
            span = 0.0
            for n, entries in DATASETS.items():  # one job per dataset file, one after the other
                span += makespan([rng.choice(measured[n]) for _ in range(entries)], cores)
            spans.append(span)
        compute = statistics.median(spans)
        assembly = {"full": args.assembly_s * sum(DATASETS.values()),
                    "lean": args.lean_assembly_s * sum(DATASETS.values())}
        write_rate = cores * args.entry_bytes / (total / sum(DATASETS.values())) / 1e6
        print(f"{cores} cores: compute {compute / 3600:.2f} h (draws {min(spans) / 3600:.2f}-{max(spans) / 3600:.2f} h; "
              f"ideal {total / cores / 3600:.2f} h, scheduling efficiency {total / cores / compute:.3f}); "
              f"rank 0 assembly {assembly['full'] / 60:.1f} min full" +
              (f", {assembly['lean'] / 60:.1f} min lean" if args.lean_assembly_s else "") +
              f"; parts written at {write_rate:.0f} MB/s on average while computing; "
              f"rank 0 answers {cores / (total / sum(DATASETS.values())):.1f} requests/s; "
              f"wall (compute, then assembly) {(compute + assembly['full']) / 3600:.2f} h full" +
              (f", {(compute + assembly['lean']) / 3600:.2f} h lean" if args.lean_assembly_s else ""))


if __name__ == "__main__":
    main()
