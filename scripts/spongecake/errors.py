"""Errors of SpongeCake's multiple-scattering approximation over a dataset (Wang et
al. 2022, Sec. 5), and their distribution.

Per entry, the error of a prediction p of the multiple-scattering part ms (orders
>= 2) is relative to the multiple scattering,
    e_ms    = sum |p - ms| / sum |ms|      (= the paper's MAE / mean |ms|),
and relative to the whole BSDF (single scattering taken from the simulation, so
this is the error the multiple-scattering term adds),
    e_total = sum |p - ms| / sum |total|,
sums over every cell and channel of reflection and transmission. The cells are of
equal solid angle for a given incident direction (bins uniform in cos theta_o and
phi), so the sums are the paper's unweighted ones, not cosine-weighted energies.

Baselines: "no MS term" (single scattering alone, p = 0: e_ms = 1, e_total = the
multiple-scattering fraction) and "Lambertian alone" (W1 = 0, W2 at its MAE optimum,
a weighted median, exact). "noise" is the expected MAE of the exact ms against the
noisy table, sqrt(2/pi) mean(stderr) / mean |ms| (Gaussian approximation): no
prediction can be expected to go far below it. It is a LOWER BOUND, biased low by
15-18 %: the per-cell standard errors come from the table's few batches (4 in the
shipped datasets; the square root of a 3-degree-of-freedom variance estimate is low on
average), and the standard error of total - order 1 is sqrt(max(se_total^2 -
se_order1^2, 0)) of the two tables' separate estimates (dataset.py), which leaves out
the covariance of the two tallies as those batches show it. The datasets keep no
multiple-scattering-only table (unless `tables` names the order components) and no
per-batch values (sums over the batches; lean files value and stderr only), so it is not
estimated directly. Measured by an outside audit (30 seeds of one one-layer entry at the
reduced scale, 8 x 8 directions and bins, 4e4 paths in 4 batches, surface flakes,
omega_p tilted 17 deg, gamma 0.8, T 1; the spread of ms over the seeds against this
column): alpha = 0.05, 8.5 % of mean |ms| against 7.0 % reported; alpha = 0.5, 13.0 %
against 11.0 %. "sscheck" is the exact single-scattering
model at the cell centres against the simulated order 1 (bin averages), relative to
order 1: where it is large, the bins are too coarse for the lobes (sharp flakes) and
no model evaluated at the cell centres can match the table.
"""
import math

import numpy as np
import torch

from spongecake import torch_model as tm

ALBEDO_BINS = (0.0, 1 / 3, 2 / 3, 1.0 + 1e-12)        # mean gamma over layers and channels
THICKNESS_BINS = (0.0, 0.5, 2.0, math.inf)            # T summed over the layers
ALPHA_BINS = (0.0, 0.1, 0.3, 1.0 + 1e-12)             # the smallest alpha of the stack


def lambertian_alone(material, split=(1.0, 1.0)):
    """(MAE, W2) of W2 f_lambert alone at its optimum: sum |ms - W2 s| with s the lobe per
    unit W2 is minimised by the median of ms / s weighted by s."""
    s = tm.lambertian_lobe(split[0], split[1], material.wi, material.wo)[..., None].expand_as(material.ms)
    ms = material.ms.reshape(-1).numpy()
    s = s.reshape(-1).numpy()
    on = s > 0
    if not on.any():
        return float(np.mean(np.abs(ms))), 0.0
    r, w = ms[on] / s[on], s[on]
    order = np.argsort(r, kind="stable")
    c = np.cumsum(w[order])
    w2 = max(float(r[order][np.searchsorted(c, 0.5 * c[-1])]), 0.0)
    return float(np.mean(np.abs(ms - w2 * s))), w2


def single_scattering_check(material):
    """sscheck of the module docstring: sum |f_ss - order 1| / sum |order 1|."""
    order1 = material.total - material.ms
    ss = tm.single_scattering(material.layers, material.wi, material.wo)
    return float(torch.sum(torch.abs(ss - order1)) / torch.sum(torch.abs(order1)))


def entry_row(index, fiber, alpha, albedo, thickness, losses, mean_abs_ms, mean_abs_total, noise_mae,
              ss_check=math.nan):
    """One entry's description (per layer: fiber flag, alpha, RGB albedo, thickness) and errors:
    for each method name -> MAE in `losses`, and for "none", "noise" and "sscheck", the keys
    <name>_ms and <name>_total (see the module docstring); NaN where ms is empty."""
    ok = mean_abs_ms > 0
    losses = dict(losses, none=mean_abs_ms)
    row = {"entry": int(index), "type": "/".join("fiber" if f else "surface" for f in fiber),
           "alpha": float(np.min(alpha)), "albedo": float(np.mean(albedo)), "thickness": float(np.sum(thickness)),
           "mean_abs_ms": float(mean_abs_ms), "noise_ms": noise_mae / mean_abs_ms if ok else math.nan,
           "sscheck_ms": ss_check, "sscheck_total": ss_check}
    for name, loss in losses.items():
        row[f"{name}_ms"] = loss / mean_abs_ms if ok else math.nan
        row[f"{name}_total"] = loss / mean_abs_total
    return row


def _label(value, edges, fmt):
    for lo, hi in zip(edges[:-1], edges[1:]):
        if lo <= value < hi:
            return f"[{fmt(lo)}, {fmt(hi)})"
    return "other"


def groups(rows):
    """(heading, label -> row indices) for: all entries, flake type(s) (top/bottom),
    smallest roughness alpha, mean albedo, total thickness."""
    def by(key):
        out = {}
        for i, r in enumerate(rows):
            out.setdefault(key(r), []).append(i)
        return dict(sorted(out.items()))
    short = lambda v: f"{v:.2g}" if math.isfinite(v) else "inf"  # noqa: E731
    return [("all", {"all": list(range(len(rows)))}),
            ("flake type", by(lambda r: r["type"])),
            ("alpha", by(lambda r: _label(r["alpha"], ALPHA_BINS, lambda v: f"{min(v, 1):.2g}"))),
            ("mean albedo", by(lambda r: _label(r["albedo"], ALBEDO_BINS, lambda v: f"{min(v, 1):.2f}"))),
            ("thickness", by(lambda r: _label(r["thickness"], THICKNESS_BINS, short)))]


def distribution(values):
    """(median, 90th percentile, worst) of the finite values, or NaNs."""
    v = np.asarray([x for x in values if math.isfinite(x)])
    if v.size == 0:
        return math.nan, math.nan, math.nan
    return float(np.median(v)), float(np.percentile(v, 90)), float(np.max(v))


def report(rows, methods, relative_to="ms"):
    """Text table: for each group and method (column suffix `_<relative_to>` of the rows),
    median / 90th percentile / worst of the error over the entries with a non-empty
    multiple-scattering table, in %."""
    usable = [r for r in rows if r["mean_abs_ms"] > 0]
    head = f"{'group':<28}{'n':>5}" + "".join(f"  {m + ' med/p90/max %':>24}" for m in methods)
    what = "the multiple scattering (sum|p-ms|/sum|ms|)" if relative_to == "ms" else "the whole BSDF (sum|p-ms|/sum|total|)"
    lines = [f"errors relative to {what}; {len(rows) - len(usable)} of {len(rows)} entries with an empty "
             "multiple-scattering table left out"]
    if "noise" in methods:
        lines.append("(noise: a lower bound, from the tables' per-cell standard errors over few batches; 15-18 % low "
                     "where measured, errors.py)")
    if "sscheck" in methods:
        lines.append("(sscheck: the exact single scattering at the cell centres against the simulated order 1, "
                     "relative to order 1: the resolution limit)")
    lines.append(head)
    for heading, members in groups(usable):
        for label, idx in members.items():
            cells = []
            for m in methods:
                med, p90, worst = distribution([usable[i][f"{m}_{relative_to}"] for i in idx])
                cells.append(f"{100 * med:7.1f}/{100 * p90:6.1f}/{100 * worst:6.1f}")
            name = label if heading == "all" else f"{heading} {label}"
            lines.append(f"{name:<28}{len(idx):>5}" + "".join(f"  {c:>24}" for c in cells))
    return "\n".join(lines)
