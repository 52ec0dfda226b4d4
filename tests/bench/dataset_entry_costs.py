#!/usr/bin/python3
"""Cost of single dataset entries of the SpongeCake datasets (issue #17).

Runs entries one at a time (mcref dataset --shard i/E selects entry i alone)
on one thread and prints CSV: dataset, entry, seconds (the entry's
simulation, as mcref reports it), wall (the whole process: it also plans and
validates every entry of the dataset), rays. `--paths-scale s`
multiplies the base experiment's samples per direction by s (1: the paper's
10^5 paths per incident direction); the cost is linear in the paths.

  tests/bench/dataset_entry_costs.py build/mcref --sample 30 --paths-scale 0.1 > costs.csv
"""
import argparse
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

DATASETS = {"spongecake_1layer.toml": 4000, "spongecake_2layer.toml": 12000}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mcref")
    ap.add_argument("--sample", type=int, default=50, help="entries in all, drawn in proportion to the datasets")
    ap.add_argument("--paths-scale", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=17)
    args = ap.parse_args()
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "validate", "datasets")
    work = tempfile.mkdtemp(prefix="mcref_costs_")
    try:
        for name in list(DATASETS) + ["spongecake_base.toml"]:
            shutil.copy(os.path.join(src, name), work)
        base = os.path.join(work, "spongecake_base.toml")
        text = open(base).read()
        samples = int(re.search(r"^samples = (\d+)$", text, re.M).group(1))
        scaled = max(1, round(samples * args.paths_scale))
        open(base, "w").write(re.sub(r"^samples = \d+$", f"samples = {scaled}", text, flags=re.M))
        total = sum(DATASETS.values())
        rng = random.Random(args.seed)
        print("dataset,entry,seconds,wall,rays")
        for name, entries in DATASETS.items():
            for i in sorted(rng.sample(range(entries), round(args.sample * entries / total))):
                out = os.path.join(work, "e.h5")
                t0 = time.perf_counter()
                r = subprocess.run([args.mcref, "dataset", os.path.join(work, name), "-o", out, "--shard",
                                    f"{i}/{entries}", "--threads", "1"], capture_output=True, text=True)
                wall = time.perf_counter() - t0
                if r.returncode != 0:
                    sys.exit(r.stderr.strip())
                m = re.search(r"entries \(.*\), ([0-9.e+]+) rays in ([0-9.]+) s", r.stderr)
                os.remove(out)
                print(f"{name},{i},{m.group(2)},{wall:.3f},{m.group(1)}", flush=True)
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
