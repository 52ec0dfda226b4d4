#!/usr/bin/python3
"""Renders OUTDIR/report.html from a validation run, without simulating.

Reads OUTDIR/results.json (written by `mcref validate`), the plots under
OUTDIR/plots/ that scripts/plot_validation.py made from that results.json
(OUTDIR/plots/plots.json, scripts/plot_manifest.py) and the list of the papers'
figures no case reproduces (validate/figures_not_reproduced.toml). The page:
headline counts, one summary row per model (scripts/model_summary.py) with the
per-check table behind it, SpongeCake's multiple-scattering approximation when
OUTDIR/spongecake/summary.json exists (scripts/spongecake/stage.py: its scale, one
number per material and method, the distributions and the figures), the figure index
(paper figure -> cases -> plots, and the figures not reproduced), then one section
per case.
Needs Debian's python3-jinja2 (scripts/setup.sh).

usage: /usr/bin/python3 scripts/report.py OUTDIR [--quiet]
"""
import json
import math
import os
import sys
import tomllib

try:
    import jinja2
except ImportError as e:  # pragma: no cover
    sys.exit(f"report.py: missing module ({e}); run scripts/setup.sh and use /usr/bin/python3")

from figure_slug import figure_slug
import plot_manifest
from model_summary import STATUSES, status_counts, summarize

HERE = os.path.dirname(os.path.abspath(__file__))
NOT_REPRODUCED = os.path.join(HERE, "..", "validate", "figures_not_reproduced.toml")
TEMPLATE = "report.html.j2"


def fail(message):
    sys.exit(f"report.py: {message}")


def error_colour(value, good, bad):
    """Background colour of an error: green at or below `good`, red at or
    above `bad`, through yellow on a log scale in between; none if unknown."""
    if value is None:
        return ""
    t = 0.0 if value <= good else 1.0 if value >= bad else math.log(value / good) / math.log(bad / good)
    return f"hsl({120 * (1 - t):.0f}, 70%, 82%)"


def p_green(significance):
    """The p from which an exact model's p is green: 0.05, or twice the
    significance when that is larger (green must stay above red)."""
    return min(1.0, max(0.05, 2 * significance))


def p_colour(p, significance):
    """Background colour of an exact model's p: green at or above p_green, red at
    or below the significance level, through yellow on a log scale; none if unknown."""
    if p is None:
        return ""
    return error_colour(1 / max(p, 1e-300), 1 / p_green(significance), 1 / significance)


def case_plots(case_names, plot_files):
    """Plot files per case: <case>.png and <case>_<anything>.png, each given to
    the longest case name it fits (a case named like another's prefix does
    not take its plots)."""
    plots = {name: [] for name in case_names}
    for f in sorted(plot_files):
        stem = f[:-4]
        owners = [n for n in case_names if stem == n or stem.startswith(n + "_")]
        if owners:
            plots[max(owners, key=len)].append(f)
    for files in plots.values():  # <case>.png first
        files.sort(key=lambda f: (f.count("_"), f))
    return plots


def figure_index(cases, plots, plot_files):
    """Paper figure label -> its cases (in suite order) and its figure-level plot."""
    index = {}
    for case in cases:
        label = case["figure"] or "(no figure label)"
        entry = index.setdefault(label, {"label": label, "cases": [], "plot": None})
        entry["cases"].append({"name": case["name"], "plots": plots[case["name"]]})
        figure_plot = f"figure_{figure_slug(label)}.png"
        if case["figure"] and figure_plot in plot_files:
            entry["plot"] = figure_plot
    return sorted(index.values(), key=lambda e: e["label"].lower())


def budget_groups(budget):
    """The error budget of a case (results.json "error_budget"), grouped per
    model and table: rows in % of the simulated albedo, Delta = model - sim =
    Delta(order 1) - sim orders >= 2, and the shares of the summed |Delta| over
    theta_i from the model's masking terms and from single scattering."""
    groups = []
    for b in budget:
        b = {k: math.nan if v is None else v for k, v in b.items()}  # null: not finite
        key = f"{b['model']} on {b['table']}"
        if not groups or groups[-1]["key"] != key:
            groups.append({"key": key, "model": b["model"], "table": b["table"], "rows": [], "masking": 0.0, "single": 0.0})
        g = groups[-1]
        g["masking"] += abs(b["order1_error"]) if math.isfinite(b["order1_error"]) else 0.0
        g["single"] += abs(b["multiple"]) if math.isfinite(b["multiple"]) else 0.0
        pct = 100 / b["sim"] if b["sim"] else math.nan
        g["rows"].append(dict(b, total_pct=(b["model_value"] - b["sim"]) * pct, order1_pct=b["order1_error"] * pct,
                              multiple_pct=-b["multiple"] * pct))
    for g in groups:
        both = max(g["masking"] + g["single"], 1e-300)
        g["masking_share"], g["single_share"] = g["masking"] / both, g["single"] / both
    return groups


def load_not_reproduced(path, suite):
    """The figures no case reproduces, when the list describes `suite` (its
    `suite` key); none for another suite, whose cases it does not know."""
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(f"{path}: {e}")
    if not isinstance(data.get("suite"), str):
        fail(f"{path}: suite: the name of the suite the list describes (a string) is required")
    if data["suite"] != suite:
        return []
    rows = data.get("figure", [])
    for i, row in enumerate(rows):
        for key in ("paper", "figure", "reason"):
            if not isinstance(row.get(key), str) or not row[key]:
                fail(f"{path}: figure.{i}.{key}: a non-empty string is required")
    return rows


SPONGECAKE_FORMAT = "mcref-spongecake-summary"
SPONGECAKE_METHODS = (("network", "network"), ("fit", "per-material fit"), ("lambert", "Lambertian alone"),
                      ("none", "no MS term"), ("noise", "noise level"), ("sscheck", "order-1 check"))


def load_spongecake(out_dir):
    """OUTDIR/spongecake/summary.json (scripts/spongecake/stage.py), or None if there is none."""
    path = os.path.join(out_dir, "spongecake", "summary.json")
    if not os.path.exists(path):
        return None
    try:
        with open(path) as f:
            summary = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        fail(f"{path}: {e}")
    if summary.get("format") != SPONGECAKE_FORMAT or summary.get("format_version") != 1:
        fail(f"{path}: format {summary.get('format')!r} version {summary.get('format_version')!r} "
             f"(expected {SPONGECAKE_FORMAT!r} version 1)")
    for i, s in enumerate(summary.get("sets", [])):
        for key in ("name", "kind", "scale", "rows", "distribution", "figures"):
            if key not in s:
                fail(f"{path}: sets.{i}.{key} is missing")
    return summary


def render(out_dir, not_reproduced_path=NOT_REPRODUCED):
    """The report page for OUTDIR, as a string."""
    path = os.path.join(out_dir, "results.json")
    try:
        with open(path) as f:
            results = json.load(f)
    except OSError as e:
        fail(f"{path}: {e.strerror} (run `mcref validate SUITE -o {out_dir}` first)")
    except json.JSONDecodeError as e:
        fail(f"{path}: not valid JSON ({e})")
    if not isinstance(results, dict):
        fail(f"{path}: not a JSON object (not a results.json of mcref validate?)")
    for key in ("title", "significance", "cases"):
        if key not in results:
            fail(f"{path}: key \"{key}\" is missing (not a results.json of mcref validate?)")
    try:
        return render_results(out_dir, results, not_reproduced_path)
    except (KeyError, TypeError, AttributeError, jinja2.UndefinedError) as e:
        fail(f"{path}: not a results.json of this mcref ({type(e).__name__}: {e})")


def render_results(out_dir, results, not_reproduced_path):
    cases = results["cases"]
    # Only the plots made from this results.json (scripts/plot_manifest.py).
    plot_files, why = plot_manifest.read(out_dir)
    if why:
        print(f"report.py: warning: no plots shown: {why}", file=sys.stderr)
    plots = case_plots([c["name"] for c in cases], plot_files)
    checks = [dict(c, case=case["name"], figure=case["figure"]) for case in cases for c in case["checks"]]
    # Checks whose model is a numerical integral by the adaptive cell rule (rule_accuracy).
    ruled = [c for c in checks if "rule_accuracy" in c]
    rules = {"checks": len(ruled), "short": [c for c in ruled if c["rule_accuracy"]["unconverged"] > 0],
             "target": max((c["rule_accuracy"]["target"] for c in ruled), default=None),
             "worst": max((c["rule_accuracy"]["worst_rel_error"] for c in ruled), default=None)}
    models = summarize(results)
    for m in models:
        # An exact model is judged by its joint test's p and the |z| bound: one noisy cell
        # near zero can give it a large relative error while it passes, so that is not coloured.
        m["rel_colour"] = "" if m["exact"] else error_colour(m["max_rel_error"], 0.01, 0.5)
        # An exact model's chi2/dof is not coloured either: on correlated cells (they share the
        # batches' geometry) a true model can reach a large one. Its joint test's p is.
        m["chi2_colour"] = "" if m["exact"] else error_colour(m["chi2_per_dof"], 1.5, 10)
        m["p_colour"] = p_colour(m["smallest_p"], results["significance"])
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(HERE), autoescape=True,
                             undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True)
    env.filters["g"] = lambda v, spec=".3g": "–" if v is None else format(v, spec)
    env.filters["pct"] = lambda v, spec=".1f": "–" if v is None else format(100 * v, spec) + " %"
    env.filters["deg"] = lambda v: "–" if v is None else f"{math.degrees(v):.1f}"
    env.filters["css"] = lambda status: "na" if status == "n/a" else status
    env.filters["budget"] = budget_groups
    return env.get_template(TEMPLATE).render(
        results=results, cases=cases, checks=checks, models=models, counts=status_counts(checks), rules=rules,
        statuses=STATUSES, plots=plots, index=figure_index(cases, plots, plot_files),
        not_reproduced=load_not_reproduced(not_reproduced_path, results.get("suite")), spongecake=load_spongecake(out_dir),
        spongecake_methods=SPONGECAKE_METHODS, p_green=p_green(results["significance"]))


def main(argv):
    args = [a for a in argv if a != "--quiet"]
    if len(args) != 1 or args[0].startswith("-"):
        sys.exit(__doc__)
    out_dir = args[0]
    html = render(out_dir)
    target = os.path.join(out_dir, "report.html")
    tmp = f"{target}.tmp.{os.getpid()}"  # written whole, then renamed: never half a page
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(html)
        os.replace(tmp, target)
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        fail(f"{target}: {e.strerror}")
    if "--quiet" not in argv:
        print(f"report.py: {target}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
