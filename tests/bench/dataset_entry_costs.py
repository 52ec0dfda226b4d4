#!/usr/bin/python3
"""Cost of single dataset entries of the SpongeCake datasets (issues #17, #21).

Runs entries one at a time: `mcref dataset --shard i/(E/2) --stop-after 1`,
for i < E/2 (E entries), computes entry i alone and writes its part; the
shard's other entry, i + E/2, is left, so nothing is assembled. Prints CSV,
one row an entry:
  seconds  the entry's wall time as mcref reports it (simulation and part write);
  cpu      the entry's process CPU time (user + system, all threads): the CPU
           time of the run less that of a run which stops before any entry
           (`--stop-after 0`: it plans and validates every entry of the
           dataset; median of 3). CPU time depends less than wall time on the
           other jobs of a shared machine;
  wall     the whole process's wall time;
  rays     rays traced.
`--paths-scale s` multiplies the base experiment's samples per direction by s
(1: the paper's 10^5 paths per incident direction; 0: one path, the entry's
fixed cost). `--subset K` runs K entries spread over the sample (for a
second run at another scale); `--part K/N` runs every N-th of them, from the
K-th (N processes side by side); `--skip R` leaves out the first R rows. `--orders` also keeps the tables of orders 2,
3 and 4+ and adds columns: ms_cells, the reflection and transmission cells
the multiple scattering (orders >= 2) reaches, and ms_rse, their median
relative standard error, sqrt(se2^2 + se3^2 + se4+^2) / (v2 + v3 + v4+)
(a path has one order, so the orders' covariance is negligible); total_rse,
the same for the total tables. Each stderr rests on run.batches (4) batches.

  tests/bench/dataset_entry_costs.py build/mcref --sample 50 --paths-scale 0.1 > costs.csv
  tests/bench/dataset_entry_costs.py build/mcref --subset 6 --paths-scale 1 --threads 2 --orders
"""
import argparse
import os
import random
import re
import shutil
import statistics
import tempfile

from timed_run import timed_run

DATASETS = {"spongecake_1layer.toml": 4000, "spongecake_2layer.toml": 12000}
ORDERS = ["order2", "order3", "order4plus"]


def value_and_stderr(table):
    """A part's table (its sums only, storage "sums"): the mean over batches and its standard error."""
    import numpy as np
    n = float(table.attrs["batches"])
    s, ss = table["sum"][()], table["sum_sq"][()]
    mean = s / n
    return mean, np.sqrt(np.maximum(0.0, (ss - n * mean * mean) / (n - 1)) / n)


def relative_errors(part):
    """Cells the multiple scattering reaches; median relative stderr there, and over the total's cells."""
    import h5py
    import numpy as np
    with h5py.File(part, "r") as f:
        (entry,) = f["entries"].values()
        ms, total = [], []
        for hemi in ("brdf", "brdf_btdf"):
            orders = [value_and_stderr(entry[f"{hemi}_{o}"]) for o in ORDERS]
            v = sum(o[0] for o in orders)
            se = np.sqrt(sum(o[1] ** 2 for o in orders))
            ms.append((se[v > 0] / v[v > 0]).ravel())
            tv, ts = value_and_stderr(entry[hemi])
            total.append((ts[tv > 0] / tv[tv > 0]).ravel())
    ms, total = np.concatenate(ms), np.concatenate(total)
    return ms.size, float(np.median(ms)), float(np.median(total))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mcref")
    ap.add_argument("--sample", type=int, default=50, help="entries in all, drawn in proportion to the datasets")
    ap.add_argument("--subset", type=int, default=0, help="run only this many entries, spread over the sample")
    ap.add_argument("--skip", type=int, default=0, help="leave out the sample's first rows (already measured)")
    ap.add_argument("--part", default="0/1", help="K/N: only rows k with k %% N == K (to run N processes side by side)")
    ap.add_argument("--paths-scale", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--orders", action="store_true", help="keep the order tables; report relative standard errors")
    ap.add_argument("--seed", type=int, default=17)
    args = ap.parse_args()
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "validate", "datasets")
    work = tempfile.mkdtemp(prefix="mcref_costs_")
    try:
        for name in list(DATASETS) + ["spongecake_base.toml"]:
            shutil.copy(os.path.join(src, name), work)
            if args.orders and name in DATASETS:
                path = os.path.join(work, name)
                extra = "".join(f', "{h}_{o}"' for h in ("brdf", "brdf_btdf") for o in ORDERS)
                text = re.sub(r"^(tables = \[.*)\]$", lambda m: m.group(1) + extra + "]", open(path).read(), flags=re.M)
                open(path, "w").write(text)
        base = os.path.join(work, "spongecake_base.toml")
        text = open(base).read()
        samples = int(re.search(r"^samples = (\d+)$", text, re.M).group(1))
        scaled = max(1, round(samples * args.paths_scale))
        open(base, "w").write(re.sub(r"^samples = \d+$", f"samples = {scaled}", text, flags=re.M))
        total = sum(DATASETS.values())
        rng = random.Random(args.seed)
        sample = [(name, i) for name, entries in DATASETS.items()
                  for i in sorted(rng.sample(range(entries // 2), round(args.sample * entries / total)))]
        if args.subset:
            sample = [sample[k * len(sample) // args.subset] for k in range(args.subset)]
        k, n = (int(x) for x in args.part.split("/"))
        sample = sample[args.skip:][k::n]
        out = os.path.join(work, "e.h5")
        planning = {}
        for name, entries in DATASETS.items():
            cmd = [args.mcref, "dataset", os.path.join(work, name), "-o", out, "--shard", f"0/{entries // 2}",
                   "--threads", str(args.threads), "--stop-after", "0"]
            planning[name] = statistics.median(timed_run(cmd)[2] for _ in range(3))
        print(f"# samples {scaled} per direction and batch, {args.threads} threads; CPU of planning (subtracted): " +
              ", ".join(f"{n} {s:.2f} s" for n, s in planning.items()))
        print("dataset,entry,seconds,cpu,wall,rays" + (",ms_cells,ms_rse,total_rse" if args.orders else ""))
        for name, i in sample:
            entries = DATASETS[name]
            shutil.rmtree(out + ".parts", ignore_errors=True)
            err, wall, cpu = timed_run([args.mcref, "dataset", os.path.join(work, name), "-o", out, "--shard",
                                  f"{i}/{entries // 2}", "--threads", str(args.threads), "--stop-after", "1"])
            m = re.search(r"entries \(1 simulated.*\), ([0-9.e+]+) rays in ([0-9.]+) s", err)
            row = f"{name},{i},{m.group(2)},{cpu - planning[name]:.2f},{wall:.3f},{m.group(1)}"
            if args.orders:
                (part,) = [os.path.join(out + ".parts", f) for f in os.listdir(out + ".parts") if f.endswith(".h5")]
                cells, ms_rse, total_rse = relative_errors(part)
                row += f",{cells},{ms_rse:.4f},{total_rse:.4f}"
            print(row, flush=True)
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
