"""OUTDIR/plots/plots.json: the plots scripts/plot_validation.py made, and the
results.json they were made from (its SHA-256). scripts/report.py shows only
those plots, and none when results.json has changed since (a later `mcref
validate`, e.g. with --case, into the same OUTDIR): plots of other cases or
runs left in plots/ are never shown as this run's."""
import hashlib
import json
import os

NAME = "plots.json"


def results_digest(out):
    with open(os.path.join(out, "results.json"), "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def write(out, plots):
    """Records `plots` (file names under OUTDIR/plots/) as made from the current results.json."""
    path = os.path.join(out, "plots", NAME)
    tmp = f"{path}.tmp.{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump({"results_sha256": results_digest(out), "plots": sorted(plots)}, f, indent=1)
    os.replace(tmp, path)


def read(out):
    """(plots, why): the plot files made from the current results.json, or an
    empty set and the reason there are none to show ("" if no plots were made)."""
    path = os.path.join(out, "plots", NAME)
    if not os.path.exists(path):
        return set(), ""
    try:
        with open(path) as f:
            manifest = json.load(f)
        digest, plots = manifest["results_sha256"], manifest["plots"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        return set(), f"{path} is unreadable ({e}); rerun scripts/plot_validation.py {out}"
    if digest != results_digest(out):
        return set(), (f"the plots in {os.path.dirname(path)} were made from another results.json; "
                       f"rerun scripts/plot_validation.py {out}")
    return {p for p in plots if os.path.exists(os.path.join(out, "plots", p))}, ""
