"""The 1-D comparisons of a case (<case>.png): per checked table and per distinct
channel, the simulation (points, 1-sigma bars) and every model (lines) over one
axis, with the residual panel under it. BRDF/BTDF tables are cut along the
plane of incidence, as in the papers. Panels where the simulation and every
model are identically zero are left out and named in a note."""
import itertools
from dataclasses import dataclass

import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
import numpy as np

import plot_style as ps
from validation_data import channel_name, distinct_channels, greek, identically_zero, value_label

# The axis along x for each quantity; the other axes become series.
X_AXIS = {"p1": "r", "ndf": "theta_m", "tau_plus": "theta_i", "tau_height": "h",
          "g1": "theta_i", "g1_conditional": "theta_m", "vndf": "theta_m", "phi_conditional": "phi_over_phi_q",
          "pore_visibility": "theta_o", "pore_visibility_independent": "theta_o",
          "phase": "mu", "brdf_modes": "theta_o", "spherical_albedo": "channel",
          "albedo": "theta_i", "transmittance": "theta_i", "energy_balance": "theta_i",
          "brdf": "theta_i", "btdf": "theta_i"}
# Which indices of an axis to draw as series (default: all, thinned to MAX_SERIES);
# negative indices count from the end. brdf_modes: two oblique theta_i (57 and 85 deg in
# the suite) with every mode k: at normal incidence k = 1, 2 vanish, and k = 1 is where
# Eq. 22 as printed is half the simulation (d'Eon's factor 2; three theta_i were thinned
# to 6 series that dropped k = 1).
PICK = {"brdf_modes": {"theta_i": [7, 15]}, "pore_visibility": {"phi": [0, -1]},
        "pore_visibility_independent": {"phi": [0, -1]}}
MAX_SERIES = 6
MAX_COLUMNS = 3
PANEL_HEIGHT = 4.1  # inches: comparison + residual + series key
RESIDUAL_HEIGHT = 1.1  # inches: a second residual panel (exact and approximate models)


@dataclass
class Series:
    label: str
    take: object  # take(array) -> 1-D array over x


@dataclass
class View:
    """One table cut to curves over x: for one channel (or None)."""
    x: np.ndarray
    xlabel: str
    series: list
    categorical: list = None  # tick labels when x is a categorical axis


def _index(table, fixed):
    return tuple(fixed.get(d, slice(None)) for d in range(len(table.axes)))


def _thin(combos, n=MAX_SERIES):
    if len(combos) <= n:
        return combos
    return [combos[i] for i in sorted(set(np.linspace(0, len(combos) - 1, n).round().astype(int)))]


def _picks(table, d):
    n = len(table.axes[d].values)
    want = PICK.get(table.quantity, {}).get(table.axes[d].name)
    return list(range(n)) if want is None else sorted({i % n for i in want if -n <= i < n})


def is_lobe_table(table):
    names = {a.name for a in table.axes}
    to = table.axis("theta_o")
    return (table.quantity in ("brdf", "btdf") and {"theta_i", "phi_i", "theta_o", "phi"} <= names
            and len(table.axes[to].values) >= 4)


def plane_view(table, ch):
    """theta_o signed along the plane of incidence: < 0 toward the light (the phi bin
    nearest 0), > 0 on the mirror side (the bin nearest 180°); for a BTDF the angle
    from -z. One series per (theta_i, phi_i)."""
    ti, pi, to, ph = (table.axis(n) for n in ("theta_i", "phi_i", "theta_o", "phi"))
    c = table.axis("channel")
    theta = np.degrees(table.axes[to].values)
    if table.quantity == "btdf":
        theta = 180.0 - theta
    order = np.argsort(theta, kind="stable")  # increasing (a BTDF's angle from -z falls with theta_o)
    theta = theta[order]
    phi = np.mod(table.axes[ph].values, 2 * np.pi)
    back = int(np.argmin(np.minimum(phi, 2 * np.pi - phi)))
    front = int(np.argmin(np.abs(phi - np.pi)))
    x = np.concatenate([-theta[::-1], theta])
    n_i, n_pi = len(table.axes[ti].values), len(table.axes[pi].values)
    combos = _thin(list(itertools.product(range(n_i), range(n_pi))), 4)
    series = []
    for i, j in combos:
        fixed = {ti: i, pi: j}
        if c is not None:
            fixed[c] = ch
        label = value_label(table, ti, i) + (", " + value_label(table, pi, j) if n_pi > 1 else "")

        def take(a, fixed=fixed):
            return np.concatenate([a[_index(table, {**fixed, ph: back})][order][::-1],
                                   a[_index(table, {**fixed, ph: front})][order]])
        series.append(Series(label, take))
    side = " from −z" if table.quantity == "btdf" else ""
    return View(x, f"θo{side} (deg), plane of incidence; < 0: light side", series)


def slice_view(table, ch):
    names = [a.name for a in table.axes]
    xname = X_AXIS.get(table.quantity, names[-1])
    xi = names.index(xname) if xname in names else len(names) - 1
    c = table.axis("channel")
    ax = table.axes[xi]
    if ax.name == "channel":
        x = np.arange(len(ax.values), dtype=float)
        cats = [channel_name(k, len(ax.values)) for k in range(len(ax.values))]
        xlabel = "channel"
    else:
        cats = None
        x = np.degrees(ax.values) if ax.unit == "rad" else ax.values
        xlabel = greek(ax.name) + (" (deg)" if ax.unit == "rad" else (f" ({ax.unit})" if ax.unit not in ("", "1") else ""))
    others = [d for d in range(len(table.axes)) if d not in (xi, c) and len(table.axes[d].values) > 0]
    combos = _thin(list(itertools.product(*[_picks(table, d) for d in others])))
    series = []
    for combo in combos:
        fixed = dict(zip(others, combo))
        if c is not None and c != xi:
            fixed[c] = ch
        label = ", ".join(value_label(table, d, i) for d, i in zip(others, combo) if len(table.axes[d].values) > 1)
        series.append(Series(label, lambda a, fixed=fixed: a[_index(table, fixed)]))
    return View(x, xlabel, series, cats)


def phi_conditional_views(table):
    """phi_conditional (the vNDF paper's Fig. 5): one panel per (θi′, θm′), over φ′ − φi′ in degrees,
    from −φq to φq (the table's axis is φ/φq)."""
    di, dm, du = (table.axis(n) for n in ("theta_i", "theta_m", "phi_over_phi_q"))
    out = []
    for i, ti in enumerate(table.axes[di].values):
        for j, tm in enumerate(table.axes[dm].values):
            p = np.tan(ti) * np.tan(tm)
            phi_q = np.pi if p <= 1 else np.arccos(-1 / p)  # the visibility bound (Listing 3, line 8)
            fixed = {di: i, dm: j}
            series = [Series("", lambda a, fixed=fixed: a[_index(table, fixed)])]
            label = f"θi′ = {np.degrees(ti):.0f}°, θm′ = {np.degrees(tm):.0f}°"
            out.append((label, View(np.degrees(table.axes[du].values * phi_q), "φ′ − φi′ (deg)", series)))
    return out


def table_views(table):
    """(channel label, View) per distinct channel of a table."""
    if table.quantity == "phi_conditional":
        return phi_conditional_views(table)
    xname = X_AXIS.get(table.quantity)
    lobes = is_lobe_table(table)
    if not lobes and xname == "channel":
        return [("", slice_view(table, None))]
    c = table.axis("channel")
    chans = distinct_channels(table)
    out = []
    for ch in chans:
        label = "" if ch is None or len(chans) == 1 and len(table.axes[c].values) == 1 else \
            "channel " + channel_name(ch, len(table.axes[c].values))
        out.append((label, plane_view(table, ch) if lobes else slice_view(table, ch)))
    return out


def drop_zero_series(view, table):
    """Removes the 0 = 0 series; returns their labels."""
    keep, gone = [], []
    for s in view.series:
        if identically_zero(s.take(table.value), [s.take(m.values) for m in table.models]):
            gone.append(s.label or "all")
        else:
            keep.append(s)
    view.series = keep
    return gone


def draw_comparison(ax, raxes, table, view, styles, tag, ylabel=None):
    """Simulation points and model lines on ax, residuals on raxes (kind -> axes, one per
    ps.residual_kinds(table.models), top to bottom). styles: model name -> (colour,
    linestyle, marker-index). tag: gid prefix naming the panel."""
    n = len(view.series)
    scale_values, residuals = [], {kind: [] for kind in raxes}
    cat = view.categorical is not None
    local = {m.name: j for j, m in enumerate(table.models)}
    for s, ser in enumerate(view.series):
        y, e = ser.take(table.value), ser.take(table.stderr)
        sig = y[np.abs(y) > 2 * e]
        scale_values.append(sig)
        if cat:
            for k, xk in enumerate(view.x):
                col = ps.CHANNEL_COLOURS.get(view.categorical[k], "k")
                h = ax.errorbar([xk], [y[k]], [e[k]], fmt="o", ms=6, color=col, capsize=3,
                                label="sim" if k == 0 and s == 0 else None)
                h.lines[0].set_gid(f"sim|{tag}|{view.categorical[k]}|{ser.label}")
        else:
            h = ax.errorbar(view.x, y, e, fmt=ps.MARKERS[s % len(ps.MARKERS)], ms=3.5, color=ps.sim_colour(s, n),
                            capsize=0, elinewidth=0.8, label=("sim " + ser.label).strip())
            h.lines[0].set_gid(f"sim|{tag}|{ser.label}")
        for m in table.models:
            ym = ser.take(m.values)
            if np.all(np.isnan(ym)):
                continue
            colour, style, k = styles[m.name]
            scale_values.append(ym)
            kind = ps.model_kind(m)
            rax = raxes[kind]
            r, re = ps.residual(kind, y, e, ym, None if m.z is None else ser.take(m.z))
            residuals[kind].append(r)
            if cat:
                dx = 0.1 * (local[m.name] + 1)
                ax.plot(view.x + dx, ym, ls="none", marker=ps.MARKERS[(k + 1) % len(ps.MARKERS)], ms=5,
                        color=colour, gid=f"model|{tag}|{m.name}|{ser.label}")
                rax.errorbar(view.x + dx, r, re, ls="none", marker=ps.MARKERS[(k + 1) % len(ps.MARKERS)], ms=4,
                             color=colour, elinewidth=0.7)
            else:
                c = ps.shade(colour, s, n)
                ax.plot(view.x, ym, color=c, ls=style, lw=1.4, gid=f"model|{tag}|{m.name}|{ser.label}")
                rax.errorbar(view.x, r, re, color=c, ls=style, lw=1.1, marker=".", ms=3, elinewidth=0.6)
    scale_values = np.concatenate(scale_values) if scale_values else np.array([])
    if ps.wants_log(scale_values):
        ps.set_log_y(ax, scale_values)
    every = ps.finish_residual_axes(ax, raxes, residuals)
    rax = every[-1]
    rax.set_xlabel(view.xlabel)
    if cat:
        for a in every:
            a.set_xticks(view.x)
            a.set_xticklabels(view.categorical)
            a.set_xlim(view.x[0] - 0.4, view.x[-1] + 0.2 + 0.1 * len(table.models))
    unit = f" ({table.unit})" if table.unit not in ("", "1") else ""
    ax.set_ylabel(ylabel or greek(table.quantity) + unit)
    handles, labels = ax.get_legend_handles_labels()
    if any(labels) and (n > 1 or cat):  # the series key, under the residual panel
        rax.legend(handles, labels, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.42), frameon=False,
                   handlelength=1.2, columnspacing=0.8, fontsize=8.5)


def model_styles(names):
    """name -> (colour, linestyle, index): distinct colour and style per model of a figure."""
    return {m: ps.model_style(k) + (k,) for k, m in enumerate(names)}


def model_legend(fig, styles, top):
    handles = [Line2D([], [], color=c, ls=st, lw=1.6, label=m) for m, (c, st, _) in styles.items()]
    if handles:
        fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, top), ncol=min(len(handles), 3),
                   frameon=False, handlelength=3.0, title="models (lighter shades: later series); simulation: points with ±1σ bars\n" + ps.RESIDUAL_KEY)


def case_figure(case):
    """The per-case figure, or None when nothing is left to draw."""
    panels, skipped = [], []
    for t in case.tables:
        gone_all = []
        for chlabel, view in table_views(t):
            gone = drop_zero_series(view, t)
            if view.series:
                panels.append((t, chlabel, view))
                if gone:
                    gone_all.append(", ".join(gone) + (f" ({chlabel})" if chlabel else ""))
            else:
                gone_all.append("all" + (f" ({chlabel})" if chlabel else ""))
        if gone_all:
            skipped.append(t.name if all(g.startswith("all") for g in gone_all) and
                           not any(p[0] is t for p in panels) else f"{t.name}: " + "; ".join(gone_all))
    names = list(dict.fromkeys(m.name for t, _, _ in panels for m in t.models))
    styles = model_styles(names)
    cols = min(max(len(panels), 1), MAX_COLUMNS)
    rows = max((len(panels) + cols - 1) // cols, 1)
    legend_rows = (len(names) + 2) // 3
    top_in = 0.75 + 0.19 * legend_rows + 0.35
    note_in = 0.45 if skipped else 0.15
    extra = max(len(ps.residual_kinds(t.models)) for t, _, _ in panels) - 1 if panels else 0
    height = top_in + rows * (PANEL_HEIGHT + RESIDUAL_HEIGHT * extra) + note_in
    width = min(ps.FIG_WIDTH, 1.0 + 3.5 * cols)
    fig = plt.figure(figsize=(width, height))
    gs = fig.add_gridspec(rows, cols, left=0.8 / width, right=1 - 0.15 / width, top=1 - top_in / height,
                          bottom=(note_in + 0.45) / height, hspace=0.62, wspace=0.36)
    for p, (t, chlabel, view) in enumerate(panels):
        kinds = ps.residual_kinds(t.models)
        sub = gs[p // cols, p % cols].subgridspec(1 + len(kinds), 1, height_ratios=[2.3] + [1.0] * len(kinds), hspace=0.08)
        ax = fig.add_subplot(sub[0])
        raxes = {kind: fig.add_subplot(sub[1 + k], sharex=ax) for k, kind in enumerate(kinds)}
        draw_comparison(ax, raxes, t, view, styles, f"{t.name}|{chlabel}")
        ax.set_title(t.name + (f" — {chlabel}" if chlabel else ""))
    fig.suptitle(case.name + (f"  ({case.figure})" if case.figure else ""), y=1 - 0.12 / height)
    model_legend(fig, styles, 1 - 0.35 / height)
    if skipped:
        fig.text(0.01, 0.12 / height, "not drawn, n/a (simulation and every model identically zero): "
                 + " | ".join(skipped), fontsize=8.5, wrap=True, gid="skipped")
    return fig
