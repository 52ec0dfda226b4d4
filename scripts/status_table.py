#!/usr/bin/python3
"""Prints the README's validation status table (Markdown) from OUTDIR/results.json.

usage: /usr/bin/python3 scripts/status_table.py out
"""
import json
import os
import sys

from model_summary import summarize

if len(sys.argv) != 2:
    sys.exit(__doc__)
with open(os.path.join(sys.argv[1], "results.json")) as f:
    results = json.load(f)


def fmt(v, spec, scale=1.0, unit=""):
    return "–" if v is None else f"{scale * v:{spec}}{unit}"


print("| model | kind | simulation | checks | verdict | worst χ²/dof | max \\|z\\| | worst rms rel. error |")
print("|---|---|---|---|---|---|---|---|")
for r in summarize(results):
    fails = r["counts"]["FAIL"]
    verdict = f"FAIL ({fails})" if fails else r["verdict"]
    figures = ", ".join(r["figures"][:3]) + (", …" if len(r["figures"]) > 3 else "")
    print(f"| `{r['model']}` | {'exact' if r['exact'] else 'approximate'} | {figures} | "
          f"{r['checks']} | {verdict} | {fmt(r['chi2_per_dof'], '.2f')} | {fmt(r['max_abs_z'], '.1f')} | "
          f"{fmt(r['rms_rel_error'], '.1f', 100, ' %')} |")
