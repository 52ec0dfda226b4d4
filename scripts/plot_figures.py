"""Paper figures as the papers draw them: the cases that share a `figure` label
(e.g. the nine τ0/β of LRPB23 Fig. 9) overlaid in one axes, with the residual
panel under it: OUTDIR/plots/figure_<slug>.png. Colour: the case (one parameter
set, as the papers colour their curves); line style: the model; points: the
simulation. Cases with several curves contribute their first one, named in the
legend."""
import os
from collections import OrderedDict

import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
import numpy as np

import plot_curves
import plot_style as ps
from figure_slug import figure_slug
from validation_data import greek, load_case


def figure_groups(results):
    """figure label -> case entries of results.json, for labels shared by several cases."""
    groups = OrderedDict()
    for c in results["cases"]:
        if c.get("figure"):
            groups.setdefault(c["figure"], []).append(c)
    return OrderedDict((f, cs) for f, cs in groups.items() if len(cs) > 1)


def primary_table(case):
    """The table a figure overlays: the total BRDF when checked, else the first checked table."""
    return next((t for t in case.tables if t.name == "brdf"), case.tables[0])


def short_names(names):
    """Case names without their common prefix (cut at an underscore)."""
    prefix = os.path.commonprefix(names)
    prefix = prefix[:prefix.rfind("_") + 1] if "_" in prefix else ""
    return [n[len(prefix):] or n for n in names]


# The series a figure overlay shows, where not the first: the Fourier mode k = 1 of
# d'Eon's Fig. 2 / 5, the one where Eq. 22 as printed and corrected differ.
PREFERRED_SERIES = {"brdf_modes": "k = 1"}


def first_curve(table):
    """(channel label, View with one series) of the first non-zero curve (or of the
    preferred one, PREFERRED_SERIES), or None."""
    want = PREFERRED_SERIES.get(table.quantity)
    for chlabel, view in plot_curves.table_views(table):
        plot_curves.drop_zero_series(view, table)
        if view.series:
            preferred = [s for s in view.series if want and want in s.label]
            view.series = preferred[:1] or view.series[:1]
            return chlabel, view
    return None


def overlay_figure(label, cases):
    curves = []
    for case, short in zip(cases, short_names([c.name for c in cases])):
        t = primary_table(case)
        got = first_curve(t)
        if got:
            curves.append((short, t, got[0], got[1]))
    if not curves:
        return None
    model_names = list(dict.fromkeys(m.name for _, t, _, _ in curves for m in t.models))
    style = {m: ps.STYLES[k % len(ps.STYLES)] for k, m in enumerate(model_names)}
    kinds = ps.residual_kinds([m for _, t, _, _ in curves for m in t.models])
    fig = plt.figure(figsize=(ps.FIG_WIDTH, 6.2 + 1.2 * (len(kinds) - 1)))
    gs = fig.add_gridspec(1 + len(kinds), 1, height_ratios=[2.4] + [1] * len(kinds), hspace=0.07, left=0.08, right=0.64,
                          top=0.9, bottom=0.1)
    ax = fig.add_subplot(gs[0])
    raxes = {kind: fig.add_subplot(gs[1 + k], sharex=ax) for k, kind in enumerate(kinds)}
    scale, resid, case_handles = [], {kind: [] for kind in kinds}, []
    for j, (short, t, chlabel, view) in enumerate(curves):
        colour = ps.COLOURS[j % len(ps.COLOURS)]
        marker = ps.MARKERS[j % len(ps.MARKERS)]
        ser = view.series[0]
        y, e = ser.take(t.value), ser.take(t.stderr)
        x = view.x
        h = ax.errorbar(x, y, e, fmt=marker, ms=4, color=colour, capsize=0, elinewidth=0.8)
        h.lines[0].set_gid(f"sim|{short}")
        scale.append(y[np.abs(y) > 2 * e])
        for m in t.models:
            ym = ser.take(m.values)
            if np.all(np.isnan(ym)):
                continue
            ax.plot(x, ym, color=colour, ls=style[m.name], lw=1.4, gid=f"model|{short}|{m.name}")
            kind = ps.model_kind(m)
            r, re = ps.residual(kind, y, e, ym, None if m.z is None else ser.take(m.z))
            resid[kind].append(r)
            raxes[kind].errorbar(x, r, re, color=colour, ls=style[m.name], lw=1.1, marker=".", ms=3, elinewidth=0.6)
            scale.append(ym)
        detail = ", ".join(s for s in (ser.label, chlabel) if s)
        case_handles.append(Line2D([], [], color=colour, marker=marker, ls="none", ms=5,
                                   label=short + (f" ({detail})" if detail else "")))
    scale = np.concatenate(scale)
    if ps.wants_log(scale):
        ps.set_log_y(ax, scale)
    ref = curves[0][1]
    unit = f" ({ref.unit})" if ref.unit not in ("", "1") else ""
    ax.set_ylabel(greek(ref.quantity) + unit)
    rax = ps.finish_residual_axes(ax, raxes, resid)[-1]
    rax.set_xlabel(curves[0][3].xlabel)
    if curves[0][3].categorical:
        rax.set_xticks(curves[0][3].x)
        rax.set_xticklabels(curves[0][3].categorical)
    leg = fig.legend(handles=case_handles, loc="upper left", bbox_to_anchor=(0.66, 0.9), frameon=False,
                     title="cases: simulation (points)", fontsize=8.5)
    fig.add_artist(leg)
    fig.legend(handles=[Line2D([], [], color="k", ls=style[m], lw=1.4, label=m) for m in model_names],
               loc="lower left", bbox_to_anchor=(0.66, 0.1), frameon=False, title="models (lines)\n" + ps.RESIDUAL_KEY.replace(", ", ",\n"), fontsize=8.5,
               handlelength=3.0)
    fig.suptitle(f"{label}: {ref.name} of {len(curves)} cases overlaid")
    return fig


def write_figures(out, results):
    written = []
    for label, entries in figure_groups(results).items():
        fig = overlay_figure(label, [load_case(out, c) for c in entries])
        if fig is not None:
            name = f"figure_{figure_slug(label)}.png"
            ps.save(fig, os.path.join(out, "plots", name))
            written.append(name)
    return written
