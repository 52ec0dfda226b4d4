#!/usr/bin/python3
"""Prints the README's validation status table (Markdown) from OUTDIR/results.json and,
when the run has one, a table of SpongeCake's multiple-scattering approximation from
OUTDIR/spongecake/summary.json (scripts/spongecake/stage.py): per set, its scale and
the median (90th percentile) error of each method, relative to the multiple scattering.

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


print("| model | kind | simulation | checks | verdict | smallest p | worst χ²/dof | max \\|z\\| | worst rms rel. error |")
print("|---|---|---|---|---|---|---|---|---|")
for r in summarize(results):
    fails = r["counts"]["FAIL"]
    verdict = f"FAIL ({fails})" if fails else r["verdict"]
    figures = ", ".join(r["figures"][:3]) + (", …" if len(r["figures"]) > 3 else "")
    print(f"| `{r['model']}` | {'exact' if r['exact'] else 'approximate'} | {figures} | "
          f"{r['checks']} | {verdict} | {fmt(r['smallest_p'], '.2g')} | {fmt(r['chi2_per_dof'], '.2f')} | {fmt(r['max_abs_z'], '.1f')} | "
          f"{fmt(r['rms_rel_error'], '.1f', 100, ' %')} |")


sponge = os.path.join(sys.argv[1], "spongecake", "summary.json")
if os.path.exists(sponge):
    with open(sponge) as f:
        sets = json.load(f)["sets"]

    def med(d, what="ms"):
        v = d.get(what, [None, None])
        return "–" if v[0] is None else f"{100 * v[0]:.0f} %" + ("" if v[1] is None else f" ({100 * v[1]:.0f} %)")

    print()
    print("SpongeCake's multiple-scattering approximation (Sec. 5): error relative to the multiple scattering, "
          "median (90th percentile) over the entries judged; the last two columns relative to the whole BSDF:")
    print()
    print("| set | layers | scale | entries judged | network | per-material fit | Lambertian alone | noise level | "
          "network, of BSDF | no MS term, of BSDF |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for t in sets:
        sc, d = t["scale"], t["distribution"]
        scale = (f"{sc['entries']} entries, {sc['incident_directions'][0]}×{sc['incident_directions'][1]} dir., "
                 f"{sc['outgoing_bins'][0]}×{sc['outgoing_bins'][1]} bins, {sc['paths_per_direction']:.0e} paths, "
                 f"{sc['epochs']} epochs")
        judged = f"{len(t['rows'])} " + ("held out" if t["kind"] == "network" else f"unseen ({t['figure']})")
        print(f"| `{t['name']}` | {t['layers']} | {scale} | {judged} | {med(d['network'])} | {med(d['fit'])} | "
              f"{med(d['lambert'])} | {med(d['noise'])} | {med(d['network'], 'total')} | {med(d['none'], 'total')} |")
