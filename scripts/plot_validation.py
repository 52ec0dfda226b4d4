#!/usr/bin/python3
"""Plots of a validation run: one PNG per case under OUTDIR/plots/.

Reads OUTDIR/results.json (checks, model values per cell) and the simulated
tables OUTDIR/tables/<case>.h5 (value, stderr, axes). Simulation: points
with 1-sigma error bars; models: lines over the same cells (bin averages).
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy.

usage: /usr/bin/python3 scripts/plot_validation.py OUTDIR [--quiet]
"""
import itertools
import json
import os
import sys
import warnings

try:
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    warnings.filterwarnings("ignore", message=".*converting a masked element to nan.*")
    import matplotlib.pyplot as plt
    import numpy as np
except ImportError as e:  # pragma: no cover
    sys.exit(f"plot_validation.py: missing module ({e}); run scripts/setup.sh "
             "and use /usr/bin/python3")

# The axis along x for each quantity; other axes become series.
X_AXIS = {"p1": "r", "ndf": "theta_m", "tau_plus": "theta_i", "tau_height": "h",
          "g1": "theta_i", "g1_conditional": "theta_m", "vndf": "theta_m",
          "pore_visibility": "theta_o", "pore_visibility_independent": "theta_o",
          "phase": "mu", "brdf_modes": "theta_o", "spherical_albedo": "channel",
          "albedo": "theta_i", "transmittance": "theta_i", "energy_balance": "theta_i"}
# Optional: which indices of an axis to draw as series (others: all), per
# quantity; negative indices count from the end.
PICK = {"brdf_modes": {"theta_i": [0, 11], "channel": [2]},
        "albedo": {"component": [0, -1], "channel": [0], "phi_i": [0]},
        "transmittance": {"component": [0, -1], "channel": [0], "phi_i": [0]}}
# BRDF/BTDF tables are drawn as lobes in the plane of incidence, as in the
# papers: theta_o signed, negative on the side of the light (phi bin 0),
# positive on the mirror side (last phi bin); one series per theta_i.
LOBES = {"brdf", "btdf"}
MAX_COLUMNS = 3
MAX_SERIES = 6
STYLES = ["-", "--", ":", "-.", (0, (5, 1)), (0, (3, 1, 1, 1, 1, 1))]


def load_table(group):
    names = group.attrs["axes"]
    names = names.decode() if isinstance(names, bytes) else names
    axes = []
    for n in names.split(","):
        ds = group[n]
        unit = ds.attrs.get("units", ds.attrs.get("unit", ""))  # "unit": files before the CF names
        unit = unit.decode() if isinstance(unit, bytes) else unit
        axes.append((n, np.asarray(ds), unit))
    return axes, np.asarray(group["value"]), np.asarray(group["stderr"])


def label_value(name, v, unit):
    return f"{name}={np.degrees(v):.0f}°" if unit == "rad" else f"{name}={v:.3g}"


def plot_table(ax, quantity, axes, value, stderr, models):
    names = [a[0] for a in axes]
    xname = X_AXIS.get(quantity, names[-1])
    xi = names.index(xname) if xname in names else len(names) - 1
    x = axes[xi][1]
    xdeg = axes[xi][2] == "rad"
    xs = np.degrees(x) if xdeg else x
    others = [d for d in range(len(axes)) if d != xi and len(axes[d][1]) > 0]
    pick = PICK.get(quantity, {})
    def indices(d):
        n = len(axes[d][1])
        return sorted({i % n for i in pick.get(axes[d][0], range(n)) if -n <= i < n})
    combos = list(itertools.product(*[indices(d) for d in others]))
    if len(combos) > MAX_SERIES:
        pick = np.linspace(0, len(combos) - 1, MAX_SERIES).round().astype(int)
        combos = [combos[i] for i in sorted(set(pick))]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for s, combo in enumerate(combos):
        sl = [slice(None)] * len(axes)
        for d, i in zip(others, combo):
            sl[d] = i
        sl = tuple(sl)
        c = colours[s % len(colours)]
        label = ", ".join(label_value(axes[d][0], axes[d][1][i], axes[d][2])
                          for d, i in zip(others, combo) if len(axes[d][1]) > 1)
        ax.errorbar(xs, value[sl], yerr=stderr[sl], fmt="o", ms=3, color=c, capsize=2,
                    label=("sim " + label).strip())
        for m, (mname, mvals) in enumerate(models):
            ax.plot(xs, mvals[sl], linestyle=STYLES[m % len(STYLES)], color=c, lw=1.2,
                    label=mname if s == 0 else None)
    ax.set_xlabel(xname + (" (deg)" if xdeg else ""))
    ax.set_ylabel(quantity)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6)


def plot_lobes(ax, quantity, axes, value, stderr, models):
    names = [a[0] for a in axes]
    ti, pi, to, ph = (names.index(n) for n in ("theta_i", "phi_i", "theta_o", "phi"))
    ch = names.index("channel") if "channel" in names else None
    theta_o = np.degrees(axes[to][1])
    if quantity == "btdf":
        theta_o = 180.0 - theta_o  # angle from -z
    x = np.concatenate([-theta_o[::-1], theta_o])
    n_i = len(axes[ti][1])
    rows = sorted(set(np.linspace(0, n_i - 1, min(n_i, 4)).round().astype(int)))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    def lobe(data, i):
        sl = [0] * len(axes)
        sl[ti], sl[to] = i, slice(None)
        back, front = list(sl), list(sl)
        back[ph], front[ph] = 0, len(axes[ph][1]) - 1
        return np.concatenate([data[tuple(back)][::-1], data[tuple(front)]])

    for s, i in enumerate(rows):
        c = colours[s % len(colours)]
        ax.errorbar(x, lobe(value, i), yerr=lobe(stderr, i), fmt="o", ms=3, color=c, capsize=2,
                    label=f"sim theta_i={np.degrees(axes[ti][1][i]):.0f}°")
        for m, (mname, mvals) in enumerate(models):
            ax.plot(x, lobe(mvals, i), linestyle=STYLES[m % len(STYLES)], color=c, lw=1.2,
                    label=mname if s == 0 else None)
    ax.set_xlabel("theta_o (deg), plane of incidence; < 0 toward the light")
    ax.set_ylabel(quantity + " (1/sr)" + (", channel 0" if ch is not None else ""))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    quiet = "--quiet" in sys.argv
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    with open(os.path.join(out, "results.json")) as f:
        results = json.load(f)
    os.makedirs(os.path.join(out, "plots"), exist_ok=True)
    for case in results["cases"]:
        tables = []
        for chk in case["checks"]:
            if chk["table"] not in tables:
                tables.append(chk["table"])
        cols = min(len(tables), MAX_COLUMNS)
        rows = (len(tables) + cols - 1) // cols
        fig, axs = plt.subplots(rows, cols, figsize=(5.5 * cols, 4.2 * rows), squeeze=False)
        for ax in axs.flat[len(tables):]:
            ax.set_visible(False)
        with h5py.File(os.path.join(out, case["tables"]), "r") as h5:
            for ax, name in zip(axs.flat, tables):
                axes, value, stderr = load_table(h5[name])
                models = [(c["model"], np.array([np.nan if v is None else v for v in c["model_values"]],
                                                dtype=float).reshape(value.shape))
                          for c in case["checks"] if c["table"] == name]
                quantity = next(c["quantity"] for c in case["checks"] if c["table"] == name)
                lobes = quantity in LOBES and {"theta_i", "phi_i", "theta_o", "phi"} <= {a[0] for a in axes}
                (plot_lobes if lobes else plot_table)(ax, quantity, axes, value, stderr, models)
                ax.set_title(name, fontsize=9)
        title = case["name"] + (f" ({case['figure']})" if case["figure"] else "")
        fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        path = os.path.join(out, "plots", case["name"] + ".png")
        fig.savefig(path + ".tmp.png", dpi=110)
        os.replace(path + ".tmp.png", path)
        plt.close(fig)
    if not quiet:
        print(f"plot_validation.py: {len(results['cases'])} plots in {os.path.join(out, 'plots')}",
              file=sys.stderr)


if __name__ == "__main__":
    main()
