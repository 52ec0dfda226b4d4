"""The checks of a validation run (OUTDIR/results.json) rolled up per model:
the summary of scripts/report.py and the README's table (scripts/status_table.py).

Verdict of a model: FAIL if any of its checks fails, else "measured" if any is
only measured (approximate model without a tolerance), else "pass" if any
passes, else "n/a" (every check compared a simulation and a model both
identically zero). Worst figures are over the checks that are not n/a.
"""
STATUSES = ("pass", "FAIL", "measured", "n/a")


def status_counts(checks):
    counts = dict.fromkeys(STATUSES, 0)
    for c in checks:
        counts[c["status"]] += 1
    return counts


def _worst(values):
    values = [v for v in values if v is not None]
    return max(values) if values else None


def summarize(results):
    """One dict per model (first-seen order): model, exact, description, cases,
    checks, counts (per status), verdict, figures, the worst chi2_per_dof,
    max_abs_z, max_rel_error and rms_rel_error, and for an exact model the
    smallest p of its joint tests (smallest_p; None for approximate models,
    which p does not judge)."""
    by_model = {}
    for case in results["cases"]:
        for c in case["checks"]:
            m = by_model.setdefault((c["model"], c["exact"]), {"description": c["description"], "cases": [],
                                                               "checks": [], "figures": []})
            if case["name"] not in m["cases"]:
                m["cases"].append(case["name"])
            if case["figure"] and case["figure"] not in m["figures"]:
                m["figures"].append(case["figure"])
            m["checks"].append(c)
    rows = []
    for (model, exact), m in by_model.items():
        counts = status_counts(m["checks"])
        judged = [c for c in m["checks"] if c["status"] != "n/a"]
        verdict = next((s for s in ("FAIL", "measured", "pass") if counts[s]), "n/a")
        row = {"model": model, "exact": exact, "description": m["description"], "cases": m["cases"],
               "checks": len(m["checks"]), "counts": counts, "verdict": verdict, "figures": m["figures"]}
        for key in ("chi2_per_dof", "max_abs_z", "max_rel_error", "rms_rel_error"):
            row[key] = _worst(c[key] for c in judged)
        p_values = [c["p_value"] for c in judged if c.get("p_value") is not None and c["cells"] > 0]
        row["smallest_p"] = min(p_values) if exact and p_values else None
        rows.append(row)
    return rows
