#!/usr/bin/python3
"""False FAILs and power of an exact model's verdict over many seeds.

Simulates one experiment with seeds FIRST..FIRST+N-1 (batch values kept),
evaluates a model on its table, and judges it as `mcref validate` does, with the
table's batch values (the sign-flip test or Box's approximation) and without
them (the chi2 with the cells taken as independent), for the model as it is and
scaled by 1 + each --bias. Prints one line per seed to --rows (JSON lines) if
given, and a summary. README, "Validation status", gives the figures it made:

  PYTHONPATH=build/python /usr/bin/python3 tests/validate/verdict_rates.py \\
      validate/experiments/tau_plus.toml --table tau_plus --model tau_plus_eq22 \\
      --set geometry.tau0=0.2 --set geometry.beta=0.3 --first 1000 --seeds 300
"""
import argparse
import json
import sys

import mcref


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("experiment")
    ap.add_argument("--table", required=True)
    ap.add_argument("--model", required=True)
    ap.add_argument("--set", action="append", default=[], dest="sets", help="key=value (as mcref --set)")
    ap.add_argument("--first", type=int, default=1000, help="first seed")
    ap.add_argument("--seeds", type=int, default=100, help="number of seeds")
    ap.add_argument("--bias", type=float, action="append", default=None, help="relative model bias (repeatable; default 0.01 0.02)")
    ap.add_argument("--significance", type=float, default=1e-3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--rows", help="write one JSON line per seed here")
    a = ap.parse_args()
    if a.seeds < 1:
        ap.error("--seeds must be at least 1")
    biases = [0.0] + (a.bias if a.bias is not None else [0.01, 0.02])
    config = mcref.parse_config(open(a.experiment).read())
    rows = []
    out = open(a.rows, "w") if a.rows else None
    for seed in range(a.first, a.first + a.seeds):
        f = mcref.simulate(config, seed=seed, threads=a.threads, sets=a.sets, keep_batch_values=True)
        t = f[a.table]
        model = mcref.evaluate_model(a.model, t, f.provenance["config"])
        row = {"seed": seed}
        for bias in biases:
            for use in (True, False):
                v = mcref.judge(t, model * (1 + bias), significance=a.significance, use_batch_values=use)
                row[f"{'batches' if use else 'independent'} {bias:g}"] = {
                    k: v[k] for k in ("status", "p_value", "max_abs_z", "effective_dof", "joint_test")}
        rows.append(row)
        if out:
            out.write(json.dumps(row) + "\n")
            out.flush()
    n = len(rows)
    print(f"{a.experiment} {' '.join(a.sets)}: {a.model} on {a.table}, seeds {a.first}-{a.first + n - 1}")
    for key in rows[0]:
        if key == "seed":
            continue
        r = [row[key] for row in rows]
        fails = sum(x["status"] == "FAIL" for x in r)
        p = sorted(x["p_value"] for x in r)
        dof = sorted(x["effective_dof"] for x in r)[n // 2]
        print(f"  {key:16s} ({r[0]['joint_test']}): FAIL {fails}/{n}; p < 0.05 in {sum(x < 0.05 for x in p) / n:.3f}, "
              f"p < 0.01 in {sum(x < 0.01 for x in p) / n:.3f}; median effective dof {dof:.3g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
