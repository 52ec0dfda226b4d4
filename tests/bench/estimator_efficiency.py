#!/usr/bin/python3
"""Error^2 x time of the slab walk's estimators on SpongeCake dataset entries (issue #21, item 4).

For each chosen entry of validate/datasets/spongecake_{1,2}layer.toml, gets its
effective experiment (`mcref dataset --shard i/(E/2) --stop-after 1` on a base
reduced to one path), keeps every `--stride-theta`-th incident elevation and
every `--stride-phi`-th azimuth of the 32 x 32 (the dataset's 10^5 paths per
direction, 4 batches, 32 x 32 outgoing bins, max_order 20 are kept), and runs
`mcref simulate --threads 1` with each estimator ([geometry] estimator), the
estimators alternating, `--reps` times each. Per run it reads:
  cpu    the process's CPU time (user + system);
  ms     median relative standard error of the multiple scattering (orders 2, 3
         and 4+ added, their stderrs in quadrature) over the reflection and
         transmission cells it reaches (value > 0);
  total  the same for the total BRDF/BTDF;
and prints, per entry and estimator, the medians over the repetitions of cpu,
ms, total, ms^2 x cpu and total^2 x cpu, then the gain (analog's error^2 x time
over the other's) per repetition pair: median and range. The medians are over
different cells (an estimator that reaches more cells adds dim ones, whose errors
are large), so `paired` is the fairer gain: per repetition pair, the median over
the cells both reach of analog's rse^2 x cpu over the other's; median and range.

  tests/bench/estimator_efficiency.py build/mcref --entries 1:357 2:220 2:2279 2:4423 --reps 5

--experiments runs whole experiment files instead (their own directions and paths), e.g.
the OpenVDB depth-profile slab:

  tests/bench/estimator_efficiency.py build/mcref --experiments validate/experiments/slab_openvdb_profile.toml \
      --estimators analog next_event next_event_mis --reps 5
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import tempfile

import numpy as np

from timed_run import timed_run

DATASETS = {"1": ("spongecake_1layer.toml", 4000), "2": ("spongecake_2layer.toml", 12000)}
ORDERS = ["order2", "order3", "order4plus"]


def entry_config(mcref, work, layers, index):
    """The effective experiment of one entry, as TOML text."""
    import h5py
    name, entries = DATASETS[layers]
    out = os.path.join(work, f"cfg{layers}_{index}.h5")
    subprocess.run([mcref, "dataset", os.path.join(work, name), "-o", out, "--shard", f"{index}/{entries // 2}",
                    "--stop-after", "1", "--quiet"], check=True, stderr=subprocess.DEVNULL)
    parts = out + ".parts"
    (part,) = [os.path.join(parts, f) for f in os.listdir(parts)]
    with h5py.File(part, "r") as f:
        config = f[f"entries/{index}"].attrs["config"]
    shutil.rmtree(parts)
    return config.decode() if isinstance(config, bytes) else config


def direction_settings(base, stride_theta, stride_phi):
    """--set overrides: every stride-th incident elevation and azimuth of the base, its paths per direction."""
    import tomllib
    m = tomllib.loads(base)["measure"][0]
    keep = lambda v, stride: "[" + ", ".join(repr(x) for x in v[stride // 2::stride]) + "]"
    return ["--set", f"measure.0.theta_i_deg={keep(m['theta_i_deg'], stride_theta)}",
            "--set", f"measure.0.phi_i_deg={keep(m['phi_i_deg'], stride_phi)}",
            "--set", f"measure.0.samples={m['samples']}"]


def errors(path):
    """Per-cell relative stderr of the multiple scattering and of the total (NaN where the value is 0)."""
    import h5py
    ms, total = [], []
    with h5py.File(path, "r") as f:
        for hemi in (h for h in ("brdf", "brdf_btdf") if h in f):  # (no transmission above a substrate)
            v = sum(f[f"{hemi}_{o}"]["value"][()] for o in ORDERS)
            se = np.sqrt(sum(f[f"{hemi}_{o}"]["stderr"][()] ** 2 for o in ORDERS))
            ms.append(np.where(v > 0, se / np.where(v > 0, v, 1), np.nan).ravel())
            tv, ts = f[hemi]["value"][()], f[hemi]["stderr"][()]
            total.append(np.where(tv > 0, ts / np.where(tv > 0, tv, 1), np.nan).ravel())
    return np.concatenate(ms), np.concatenate(total)


def paired(cpu_a, rse_a, cpu_b, rse_b):
    """Median over the cells both reach of (rse_a^2 cpu_a) / (rse_b^2 cpu_b)."""
    both = np.isfinite(rse_a) & np.isfinite(rse_b) & (rse_a > 0) & (rse_b > 0)
    return float(np.median(rse_a[both] ** 2 * cpu_a / (rse_b[both] ** 2 * cpu_b))) if both.any() else float("nan")


def span(x):
    return f"{statistics.median(x):.2f},{min(x):.2f}-{max(x):.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mcref")
    which = ap.add_mutually_exclusive_group(required=True)
    which.add_argument("--entries", nargs="+", help="LAYERS:INDEX, e.g. 1:357 2:220")
    which.add_argument("--experiments", nargs="+", help="experiment TOML files, run as they are")
    ap.add_argument("--estimators", nargs="+", default=["analog", "next_event"],
                    help="values of [geometry] estimator, or KEY=VALUE for another [geometry] key (e.g. walk=wave), "
                         "several joined by + (e.g. walk=wave+next_event_mis)")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--stride-theta", type=int, default=4)
    ap.add_argument("--stride-phi", type=int, default=8)
    args = ap.parse_args()
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "validate", "datasets")
    work = tempfile.mkdtemp(prefix="mcref_estimators_")
    try:
        settings = []
        if args.entries:
            for name, _ in DATASETS.values():
                shutil.copy(os.path.join(src, name), work)
            base = open(os.path.join(src, "spongecake_base.toml")).read()
            settings = direction_settings(base, args.stride_theta, args.stride_phi)
            open(os.path.join(work, "spongecake_base.toml"), "w").write(
                re.sub(r"^samples = \d+$", "samples = 1", base, flags=re.M))
        directions = (f"every {args.stride_theta}th theta_i, every {args.stride_phi}th phi_i" if args.entries
                      else "the experiments' own")
        print(f"# directions: {directions}; {args.reps} alternating repetitions, 1 thread; error = median relative stderr")
        print("entry,estimator,cpu,ms_cells,ms,total,ms2_cpu,total2_cpu,gain_ms,gain_ms_range,gain_total,"
              "gain_total_range,paired_ms,paired_ms_range,paired_total,paired_total_range")
        for spec in args.entries or args.experiments:
            if args.entries:
                layers, index = spec.split(":")
                exp = os.path.join(work, "entry.toml")
                open(exp, "w").write(entry_config(args.mcref, work, layers, int(index)))
            else:
                exp = os.path.abspath(spec)
            runs = {e: [] for e in args.estimators}
            cells = {e: [] for e in args.estimators}
            for rep in range(args.reps):
                order = args.estimators if rep % 2 == 0 else args.estimators[::-1]
                for est in order:
                    out = os.path.join(work, "run.h5")
                    sets = []
                    for item in est.split("+"):
                        key, value = item.split("=") if "=" in item else ("estimator", item)
                        sets += ["--set", f"geometry.{key}=\"{value}\""]
                    _, _, cpu = timed_run([args.mcref, "simulate", exp, "-o", out, "--threads", "1", "--quiet"] + sets + settings)
                    ms, total = errors(out)
                    runs[est].append((cpu, np.nanmedian(ms), np.nanmedian(total), int(np.sum(ms > 0))))
                    cells[est].append((cpu, ms, total))
            ref = runs[args.estimators[0]]
            for est in args.estimators:
                r = runs[est]
                med = lambda k: statistics.median(x[k] for x in r)
                gain_ms = [(a[1] ** 2 * a[0]) / (b[1] ** 2 * b[0]) for a, b in zip(ref, r)]
                gain_t = [(a[2] ** 2 * a[0]) / (b[2] ** 2 * b[0]) for a, b in zip(ref, r)]
                paired_ms = [paired(a[0], a[1], b[0], b[1]) for a, b in zip(cells[args.estimators[0]], cells[est])]
                paired_t = [paired(a[0], a[2], b[0], b[2]) for a, b in zip(cells[args.estimators[0]], cells[est])]
                print(f"{spec},{est},{med(0):.3f},{med(3)},{med(1):.4f},{med(2):.4f},{statistics.median(x[1] ** 2 * x[0] for x in r):.4f},"
                      f"{statistics.median(x[2] ** 2 * x[0] for x in r):.4f},{statistics.median(gain_ms):.2f},"
                      f"{min(gain_ms):.2f}-{max(gain_ms):.2f},{statistics.median(gain_t):.2f},"
                      f"{min(gain_t):.2f}-{max(gain_t):.2f},{span(paired_ms)},{span(paired_t)}", flush=True)
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
