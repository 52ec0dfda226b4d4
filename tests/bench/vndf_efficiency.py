#!/usr/bin/python3
"""The vNDF paper's Fig. 6 claim in numbers: the table and plot of
bench_micrograin_vndf_efficiency's JSON output (issue #15 part 6).

Per (tau0, beta, light) and theta_i: the efficiency ratio
eff = (var_NDF t_NDF) / (var_vNDF t_vNDF) (> 1: vNDF sampling more efficient),
its median and range over the repetitions, and the variance and time ratios
beside it; the two estimators' means must agree (same integral): their
difference in standard errors is printed as z.

usage:
  build-lto/bench_micrograin_vndf_efficiency --benchmark_repetitions=5 \\
      --benchmark_out=eff.json --benchmark_out_format=json
  /usr/bin/python3 tests/bench/vndf_efficiency.py eff.json [plot.png]
"""
import collections
import json
import math
import re
import statistics
import sys


def load(path):
    with open(path) as f:
        data = json.load(f)
    runs = collections.defaultdict(list)
    for b in data["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        m = re.match(r"pair/tau0:([\d.]+)/beta:([\d.]+)/(sky|sun)/theta_i:([\d.]+)", b["run_name"])
        if m:
            runs[(float(m[1]), float(m[2]), m[3], float(m[4]))].append(b)
    return data.get("context", {}), runs


def summary(runs):
    rows = []
    for key in sorted(runs, key=lambda k: (k[2], k[0], k[1], k[3])):
        reps = runs[key]
        eff = [r["eff_ratio"] for r in reps]
        n = sum(r["samples"] for r in reps)
        # Pooled means and variances over the repetitions (equal sample counts per repetition).
        mean = {s: statistics.fmean(r[f"mean_{s}"] for r in reps) for s in ("ndf", "vndf")}
        var = {s: statistics.fmean(r[f"var_{s}"] for r in reps) for s in ("ndf", "vndf")}
        se = math.sqrt(var["ndf"] / n + var["vndf"] / n)
        rows.append(dict(tau0=key[0], beta=key[1], light=key[2], theta=key[3], reps=len(reps),
                         eff=statistics.median(eff), eff_lo=min(eff), eff_hi=max(eff),
                         var_ratio=statistics.median(r["var_ratio"] for r in reps),
                         time_ratio=statistics.median(r["time_ratio"] for r in reps),
                         ndf_ns=statistics.median(r["ndf_ns"] for r in reps),
                         vndf_ns=statistics.median(r["vndf_ns"] for r in reps),
                         mean=mean["vndf"], z=(mean["vndf"] - mean["ndf"]) / se if se > 0 else 0.0))
    return rows


def table(rows):
    out = ["| light | tau0 | beta | theta_i | eff ratio, median [range] | var NDF / var vNDF | t vNDF / t NDF | "
           "estimate | z (means) |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['light']} | {r['tau0']:g} | {r['beta']:g} | {r['theta']:g} | "
                   f"{r['eff']:.3g} [{r['eff_lo']:.3g}, {r['eff_hi']:.3g}] | {r['var_ratio']:.3g} | "
                   f"{r['time_ratio']:.2f} | {r['mean']:.4g} | {r['z']:+.1f} |")
    return "\n".join(out)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lights = sorted({r["light"] for r in rows})
    fig, axes = plt.subplots(1, len(lights), figsize=(5.5 * len(lights), 4.2), squeeze=False)
    for ax, light in zip(axes[0], lights):
        for mat in sorted({(r["tau0"], r["beta"]) for r in rows if r["light"] == light}):
            rs = [r for r in rows if r["light"] == light and (r["tau0"], r["beta"]) == mat]
            x = [r["theta"] for r in rs]
            y = [r["eff"] for r in rs]
            err = [[r["eff"] - r["eff_lo"] for r in rs], [r["eff_hi"] - r["eff"] for r in rs]]
            ax.errorbar(x, y, err, marker="o", ms=4, capsize=3, label=f"τ0 = {mat[0]:g}, β = {mat[1]:g}")
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_yscale("log")
        ax.set_xlabel("θi (deg)")
        ax.set_ylabel("efficiency vNDF / NDF  (var·time ratio)")
        ax.set_title(f"{light}: gold grains, G_dist grain term")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle("vNDF paper Fig. 6 claim: efficiency of vNDF over NDF sampling (median, range over repetitions)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")


def main(argv):
    if len(argv) not in (1, 2):
        sys.exit(__doc__)
    context, runs = load(argv[0])
    if not runs:
        sys.exit(f"vndf_efficiency.py: {argv[0]}: no pair/... benchmark runs")
    rows = summary(runs)
    print(f"host: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
          f"load average {context.get('load_avg', '?')}")
    print(table(rows))
    if len(argv) == 2:
        plot(rows, argv[1])
        print(f"plot: {argv[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
