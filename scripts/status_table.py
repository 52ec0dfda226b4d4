#!/usr/bin/python3
"""Prints the README's validation status table (Markdown) from OUTDIR/results.json.

usage: /usr/bin/python3 scripts/status_table.py out
"""
import collections
import json
import os
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__)
with open(os.path.join(sys.argv[1], "results.json")) as f:
    results = json.load(f)
rows = collections.OrderedDict()
for case in results["cases"]:
    for c in case["checks"]:
        key = (c["model"], c["exact"])
        r = rows.setdefault(key, {"cases": 0, "pass": 0, "fail": 0, "rms_rel": 0.0, "max_z": 0.0,
                                  "chi2": 0.0, "figures": [], "description": c["description"]})
        r["cases"] += 1
        r["pass"] += c["status"] == "pass"
        r["fail"] += c["status"] == "FAIL"
        r["rms_rel"] = max(r["rms_rel"], c["rms_rel_error"] or 0.0)
        r["chi2"] = max(r["chi2"], c["chi2_per_dof"] or 0.0)
        r["max_z"] = max(r["max_z"], c["max_abs_z"] or 0.0)
        if case["figure"] and case["figure"] not in r["figures"]:
            r["figures"].append(case["figure"])
print("| model | kind | simulation | checks | verdict | worst χ²/dof | max \\|z\\| | worst rms rel. error |")
print("|---|---|---|---|---|---|---|---|")
for (model, exact), r in rows.items():
    if exact:
        verdict = "pass" if r["fail"] == 0 else f"FAIL ({r['fail']})"
    else:
        verdict = "measured" if r["fail"] == 0 else f"FAIL ({r['fail']})"
    figures = ", ".join(r["figures"][:3]) + (", …" if len(r["figures"]) > 3 else "")
    print(f"| `{model}` | {'exact' if exact else 'approximate'} | {figures} | "
          f"{r['cases']} | {verdict} | {r['chi2']:.2f} | {r['max_z']:.1f} | {100 * r['rms_rel']:.1f} % |")
