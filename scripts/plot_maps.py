"""2-D views of the BRDF/BTDF tables of a case.

<case>_table.png: the whole table as images, rows = incoming directions (θi, φi;
distinct channels within each), columns = outgoing cells (θo groups, φ within each),
the upper hemisphere (BRDF) beside the lower one (BTDF). First the simulation
(log colour scale), then per model its residual on a diverging scale.

<case>_lobes.png: polar lobes (angle: φ = φo − φi, 0 toward the light at the left;
radius: θo, or the angle from −z for a BTDF) at a few θi: simulation, the first
model, and the residual of each model, on a diverging scale with a stated range.
Values are the mean over the table's distinct channels."""
import itertools

import matplotlib.colors as mcolors
import matplotlib.pyplot as plt
import numpy as np

import plot_style as ps
from validation_data import channel_name, distinct_channels

LOBE_ANGLES = ("theta_i", "phi_i", "theta_o", "phi")
MAX_LOBE_ROWS = 3      # θi per table in the lobe figure
MAX_LOBE_MODELS = 3    # residual columns per table
REL_RANGES = (10, 25, 50, 100, 200, 500)  # % ; the colour range is the first above 95 % of |residual|
Z_RANGE = 5


def angle_table(t):
    return t.quantity in ("brdf", "btdf") and all(t.axis(n) is not None for n in LOBE_ANGLES)


def residual_norm(kind, r):
    """(norm, colourbar label) of a residual image: symmetric, range stated."""
    if kind == "z":
        lim, label = Z_RANGE, f"z = (sim − model)/σ\nrange ±{Z_RANGE}"
    else:
        a = np.abs(r[np.isfinite(r)])
        q = np.percentile(a, 95) if a.size else 0
        lim = next((x for x in REL_RANGES if x >= q), REL_RANGES[-1])
        label = f"model/sim − 1 (%)\nrange ±{lim:g} %"
    return mcolors.Normalize(-lim, lim), label


def _cmap(name, bad="0.85"):
    c = plt.get_cmap(name).copy()
    c.set_bad(bad)
    return c


def log_norm(*arrays):
    v = np.concatenate([a[np.isfinite(a) & (a > 0)].ravel() for a in arrays])
    top = v.max() if v.size else 1.0
    return mcolors.LogNorm(top * 1e-3, top, clip=True)


# ---------------------------------------------------------------- whole table

def table_matrix(t, a, chans):
    """rows (θi, φi, channel), columns (θo, φ) of array a shaped like table t."""
    order = [t.axis(n) for n in LOBE_ANGLES]
    c = t.axis("channel")
    if c is not None:
        a = np.take(a, chans, axis=c)
        order = order[:2] + [c] + order[2:]
    a = np.transpose(a, order)
    n_rows = a.shape[0] * a.shape[1] * (a.shape[2] if c is not None else 1)
    return a.reshape(n_rows, -1)


def table_blocks(case):
    """(upper, lower) pairs: a BRDF table with its BTDF partner (brdf_X <-> brdf_btdf_X)."""
    tables = [t for t in case.tables if angle_table(t)]
    by_name = {t.name: t for t in tables}
    blocks, used = [], set()
    for t in tables:
        if t.quantity == "brdf":
            partner = by_name.get(t.name.replace("brdf", "brdf_btdf", 1))
            blocks.append((t, partner))
            used.update({t.name, partner.name if partner else None})
    blocks += [(None, t) for t in tables if t.quantity == "btdf" and t.name not in used]
    return blocks


def _block_matrix(upper, lower, pick, chans):
    parts = [table_matrix(t, pick(t), chans) if t is not None and pick(t) is not None else None
             for t in (upper, lower)]
    rows = next(p.shape[0] for p in parts if p is not None)
    widths = [table_matrix(t, t.value, chans).shape[1] if t is not None else 0
              for t in (upper, lower)]
    out = []
    for p, w in zip(parts, widths):
        if w:
            out.append(p if p is not None else np.full((rows, w), np.nan))
    if len(out) == 2:
        out.insert(1, np.full((rows, 1), np.nan))  # the horizon between the hemispheres
    return np.hstack(out)


def _label_table_axes(ax, block, chans):
    ref = block[0] or block[1]
    ti, pi, to, ph = (ref.axis(n) for n in LOBE_ANGLES)
    n_i, n_pi = len(ref.axes[ti].values), len(ref.axes[pi].values)
    nch = max(len(chans), 1)
    centres, labels = [], []
    for i, j in itertools.product(range(n_i), range(n_pi)):
        row = (i * n_pi + j) * nch
        centres.append(row + (nch - 1) / 2)
        labels.append(f"{np.degrees(ref.axes[ti].values[i]):.0f}°"
                      + (f", {np.degrees(ref.axes[pi].values[j]):.0f}°" if n_pi > 1 else ""))
        if row:
            ax.axhline(row - 0.5, color="w", lw=0.6)
    ax.set_yticks(centres)
    ax.set_yticklabels(labels, fontsize=8)
    xt, xl, x0 = [], [], 0
    for t in block:
        if t is None:
            continue
        n_to, n_ph = len(t.axes[to].values), len(t.axes[ph].values)
        theta = np.degrees(t.axes[to].values)
        for k in range(n_to):
            if k % 2 == 0:
                xt.append(x0 + k * n_ph + (n_ph - 1) / 2)
                xl.append(f"{theta[k]:.0f}")
            if k:
                ax.axvline(x0 + k * n_ph - 0.5, color="w", lw=0.3)
        x0 += n_to * n_ph + 1
    ax.set_xticks(xt)
    ax.set_xticklabels(xl, fontsize=8)


def table_figure(case):
    blocks = table_blocks(case)
    if not blocks:
        return None
    panels = []  # (block, chans, kind of panel, model index)
    for b in blocks:
        ref = b[0] or b[1]
        chans = [k for k in distinct_channels(ref) if k is not None]
        n_models = max(len(t.models) for t in b if t is not None)
        panels += [(b, chans, "sim", None)] + [(b, chans, "model", k) for k in range(n_models)]
    heights = [0.55 + 0.075 * _block_matrix(p[0][0], p[0][1], lambda t: t.value, p[1]).shape[0] for p in panels]
    fig, axs = plt.subplots(len(panels), 1, figsize=(ps.FIG_WIDTH, sum(heights) + 0.8 + 0.35 * len(panels)),
                            gridspec_kw={"height_ratios": heights}, squeeze=False, layout="constrained")
    for ax, (block, chans, what, k) in zip(axs[:, 0], panels):
        ref = block[0] or block[1]
        names = " | ".join(t.name for t in block if t is not None)
        chan_note = (" (rows within each θi: " + ", ".join(channel_name(c, len(ref.axes[ref.axis('channel')].values))
                                                          for c in chans) + ")") if len(chans) > 1 else ""
        if what == "sim":
            m = _block_matrix(block[0], block[1], lambda t: t.value, chans)
            im = ax.imshow(m, aspect="auto", interpolation="nearest", cmap=_cmap("magma"), norm=log_norm(m))
            ax.set_title(f"{names}: simulation{chan_note}", loc="left")
            unit = ps_unit(ref) if sum(t is not None for t in block) == 1 else f"f_r | f_t ({ref.unit})"
            fig.colorbar(im, ax=ax, pad=0.01, fraction=0.03).set_label(unit, fontsize=8)
        else:
            def pick(t, part):
                if k >= len(t.models):
                    return None
                r, _ = ps.residual(ps.residual_kind([t.models[k]]), t.value, t.stderr, t.models[k].values, t.models[k].z)
                return r if part == "r" else t.models[k]
            models = [pick(t, "m") for t in block if t is not None]
            kind = ps.residual_kind([m for m in models if m is not None])
            m = _block_matrix(block[0], block[1], lambda t: pick(t, "r"), chans)
            norm, label = residual_norm(kind, m)
            im = ax.imshow(m, aspect="auto", interpolation="nearest", cmap=_cmap("RdBu_r"), norm=norm)
            ax.set_title(" | ".join(x.name for x in models if x is not None) + ": residual, " + label.replace("\n", ", "), loc="left")
            fig.colorbar(im, ax=ax, pad=0.01, fraction=0.03, extend="both").set_label(label.split("\n")[0], fontsize=8)
        _label_table_axes(ax, block, chans)
        ax.set_ylabel("θi" + (", φi" if len(ref.axes[ref.axis("phi_i")].values) > 1 else ""))
    hemis = " | ".join(h for h, t in zip(("upper hemisphere (BRDF)", "lower hemisphere (BTDF, θo from +z)"), blocks[0])
                       if t is not None)
    ph = blocks[0][0] or blocks[0][1]
    phi_edges = ph.axes[ph.axis("phi")].edges
    phi_span = np.degrees(phi_edges[-1] if phi_edges is not None else ph.axes[ph.axis("phi")].values[-1])
    phi_text = "φ = 0…180° (folded)" if phi_span <= 180.5 else "φ = 0…360°"
    axs[-1, 0].set_xlabel(f"outgoing cells: θo (deg) groups, {phi_text} within each\n{hemis}")
    fig.suptitle(f"{case.name}: whole BRDF/BTDF tables (grey: no significant simulated value)")
    return fig


def ps_unit(t):
    return f"{'f_r' if t.quantity == 'brdf' else 'f_t'} ({t.unit})"


# ---------------------------------------------------------------- polar lobes

def _polar_grid(t):
    """Angular edges (full circle) and radial edges (deg) of a table; a φ range folded
    into [0, π] is mirrored (the lobe is symmetric about the plane of incidence)."""
    to, ph = t.axis("theta_o"), t.axis("phi")
    pe = t.axes[ph].edges if t.axes[ph].edges is not None else _edges(t.axes[ph].values)
    re = np.degrees(t.axes[to].edges if t.axes[to].edges is not None else _edges(t.axes[to].values))
    if t.quantity == "btdf":
        re = 180.0 - re
    folded = pe[-1] <= np.pi + 1e-6
    if folded:
        pe = np.concatenate([pe, 2 * np.pi - pe[::-1][1:]])
    return pe, re, folded


def _edges(c):
    mid = (c[1:] + c[:-1]) / 2
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _lobe(t, a, i, j, chans, folded):
    """(θo, φ) image at incoming (i, j), mean over the distinct channels."""
    fixed = {t.axis("theta_i"): i, t.axis("phi_i"): j}
    c = t.axis("channel")
    a = np.take(np.take(a, i, axis=t.axis("theta_i")), j, axis=t.axis("phi_i") - 1)
    rest = [n for d, n in enumerate(x.name for x in t.axes) if d not in fixed]
    if c is not None:
        a = np.take(a, chans, axis=rest.index("channel")).mean(axis=rest.index("channel"))
    img = a if rest.index("theta_o") < rest.index("phi") else a.T
    return np.hstack([img, img[:, ::-1]]) if folded else img


def _lobe_stderr(t, i, j, chans, folded):
    """An upper bound on the standard error of the channels' mean: the channels come
    from the same paths, so their errors are not independent (dividing by the count,
    as for independent ones, gave |z| up to 5-6 on tables whose check passes at 3.3)."""
    return np.sqrt(_lobe(t, t.stderr ** 2, i, j, chans, folded))


def lobe_tables(case):
    out = []
    for t in case.tables:
        if angle_table(t) and len(t.axes[t.axis("theta_o")].values) >= 4 and len(t.axes[t.axis("phi")].values) >= 4:
            out.append(t)
    return out


def lobes_figure(case):
    tables = lobe_tables(case)
    if not tables:
        return None
    rows = []
    for t in tables:
        n_i, n_pi = len(t.axes[t.axis("theta_i")].values), len(t.axes[t.axis("phi_i")].values)
        combos = list(itertools.product(range(n_i), range(n_pi)))
        pick = sorted(set(np.linspace(0, len(combos) - 1, min(len(combos), MAX_LOBE_ROWS)).round().astype(int)))
        rows += [(t, combos[p]) for p in pick]
    n_models = min(MAX_LOBE_MODELS, max(len(t.models) for t in tables))
    ncols = 2 + n_models
    size = min(ps.FIG_WIDTH / ncols, 2.4)
    fig = plt.figure(figsize=(size * ncols + 0.9, size * 1.15 * len(rows) + 0.9), layout="constrained")
    sub = fig.subfigures(len(rows), 1, squeeze=False)[:, 0]
    for sf, (t, (i, j)) in zip(sub, rows):
        chans = [k for k in distinct_channels(t) if k is not None] or [None]
        pe, re, folded = _polar_grid(t)
        P, R = np.meshgrid(pe, re)
        sim = _lobe(t, t.value, i, j, chans, folded)
        se = _lobe_stderr(t, i, j, chans, folded)
        # Exact models first: they are the ones a pass rests on.
        models = sorted(t.models, key=lambda m: not m.exact)[:MAX_LOBE_MODELS]
        axes = sf.subplots(1, ncols, subplot_kw={"projection": "polar"})
        for ax in axes:
            ax.set_theta_zero_location("W")
            ax.set_theta_direction(-1)
            ax.set_xticks(np.radians([0, 90, 180, 270]))
            ax.set_xticklabels(["0", "90", "180", "270"], fontsize=7.5)
            ax.set_yticks([30, 60])
            ax.set_yticklabels([])
            ax.set_ylim(min(re), max(re))
        mimg = [_lobe(t, m.values, i, j, chans, folded) for m in models]
        norm = log_norm(sim)
        im = axes[0].pcolormesh(P, R, sim, cmap=_cmap("magma"), norm=norm, shading="flat", antialiased=False)
        axes[0].set_title("simulation", fontsize=8.5)
        if mimg:
            axes[1].pcolormesh(P, R, mimg[0], cmap=_cmap("magma"), norm=norm, shading="flat", antialiased=False)
            axes[1].set_title(models[0].name, fontsize=8.5)
        cb = sf.colorbar(im, ax=axes[:2], location="left", fraction=0.04, pad=0.02)
        cb.set_label(ps_unit(t), fontsize=8)
        for k in range(n_models):
            ax = axes[2 + k]
            if k >= len(mimg):
                ax.set_visible(False)
                continue
            kind = ps.residual_kind([models[k]])
            r, _ = ps.residual(kind, sim, se, mimg[k])
            norm_r, label = residual_norm(kind, r)
            imr = ax.pcolormesh(P, R, r, cmap=_cmap("RdBu_r"), norm=norm_r, shading="flat", antialiased=False)
            ax.set_title(models[k].name, fontsize=8.5)
            cb = sf.colorbar(imr, ax=ax, location="bottom", fraction=0.05, pad=0.04, extend="both")
            cb.set_label(label, fontsize=8)
        ti, pi = t.axes[t.axis("theta_i")], t.axes[t.axis("phi_i")]
        sf.suptitle(f"{t.name}: θi = {np.degrees(ti.values[i]):.0f}°"
                    + (f", φi = {np.degrees(pi.values[j]):.0f}°" if len(pi.values) > 1 else "")
                    + (f"; mean of {len(chans)} channels" if len(chans) > 1 else ""), fontsize=9)
    fig.suptitle(f"{case.name}: lobes\nangle φ = φo − φi (0 = toward the light, left); radius θo"
                 + (" (BTDF: from −z)" if any(t.quantity == "btdf" for t in tables) else "") + ", rings at 30°, 60°")
    return fig
