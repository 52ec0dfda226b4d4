"""What the validation plots share: fonts, how models and series are told apart,
the residual under each comparison, the y scale, and atomic saving.

Models: model k of a figure gets colour COLOURS[k % 9] and line style
STYLES[k % 8], so any two models differ in colour and in style (k < 8) and no
two share both (k < 72). Series of one model (θi, component, ...) are lighter
shades of its colour; the simulation is black/grey with one marker per series.
"""
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.colors as mcolors
import matplotlib.pyplot as plt
import numpy as np

# Figures are drawn at the size the report shows them (<= 10 in at DPI = 1100 px),
# so 9 pt text stays 9 pt on the page.
DPI = 110
FIG_WIDTH = 10.0
plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 9,
                     "xtick.labelsize": 8.5, "ytick.labelsize": 8.5, "figure.titlesize": 11})

COLOURS = [c for c in plt.rcParams["axes.prop_cycle"].by_key()["color"] if c != "#7f7f7f"]  # grey is the simulation's
STYLES = ["-", "--", "-.", ":", (0, (6, 1, 1, 1, 1, 1)), (0, (8, 2)), (0, (3, 1, 1, 1)), (0, (1, 3))]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]
CHANNEL_COLOURS = {"R": "#d62728", "G": "#2ca02c", "B": "#1f77b4"}


def model_style(k):
    """(colour, linestyle) of the k-th model of a figure."""
    return COLOURS[k % len(COLOURS)], STYLES[k % len(STYLES)]


def shade(colour, s, n):
    """Series s of n: the model's colour, lighter for later series."""
    t = 0.0 if n <= 1 else 0.6 * s / (n - 1)
    return tuple((1 - t) * np.array(mcolors.to_rgb(colour)) + t)


def sim_colour(s, n):
    g = 0.0 if n <= 1 else 0.55 * s / (n - 1)
    return (g, g, g)


def residual_kind(models):
    """z for tables whose models are all exact (agreement within the error bars is the
    claim); the model's relative error otherwise (its size is the finding)."""
    return "z" if models and all(m.exact for m in models) else "rel"


def residual_kinds(models):
    """The residual panels of a curve: z for its exact models, the relative error for its
    approximate ones (both when it has both)."""
    kinds = [k for k, want in (("z", True), ("rel", False)) if any(m.exact == want for m in models)]
    return kinds or ["z"]


def model_kind(model):
    return "z" if model.exact else "rel"


RESIDUAL_LABEL = {"z": "z", "rel": "model/sim−1 (%)"}
# Said once per figure, in the model legend's title: the axis labels stay short enough for the panels.
RESIDUAL_KEY = "residuals: z = (sim − model)/σ for exact models, model/sim − 1 in % for approximate ones"
SIGNAL_SIGMAS = 5  # the report's relative error is over cells with |sim| > 5 σ (validate/metrics.cpp)


def residual(kind, sim, se, model, z=None):
    """Residual and its 1-sigma error bar. z: the report's z where given (results.json:
    Student's t of the batches mapped to a normal quantile, with the model's own noise),
    else (sim - model) / σ. rel is over the cells of the report's relative error, where
    |sim| > 5 σ (elsewhere the ratio would be noise), so its largest |value| is the
    report's max rel. error."""
    with np.errstate(divide="ignore", invalid="ignore"):
        if kind == "z":
            r = z if z is not None else np.where(se > 0, (sim - model) / se, np.nan)
            return r, None
        ok = np.abs(sim) > SIGNAL_SIGMAS * se
        r = np.where(ok, 100 * (model / sim - 1), np.nan)
        e = np.where(ok, 100 * np.abs(model) * se / sim ** 2, np.nan)
        return r, e


def scale_residual_axis(ax, kind, values):
    """Reference lines and the axis label; symlog, said in the label, when a few large
    residuals would flatten the small ones."""
    finite = np.abs(values[np.isfinite(values)]) if values.size else np.array([])
    big = finite.max() if finite.size else 0.0
    lin = 3 if kind == "z" else 5
    label = RESIDUAL_LABEL[kind]
    if kind == "z":
        for y in (-2, 2):
            ax.axhline(y, color="0.6", lw=0.8, ls=":")
    if big > 10 * lin:
        ax.set_yscale("symlog", linthresh=lin)
        top = 10 ** np.ceil(np.log10(big))
        ticks = [t for t in (-1e4, -1e3, -100, -10, 0, 10, 100, 1e3, 1e4) if abs(t) <= top and (t == 0 or abs(t) >= 10)]
        ax.set_yticks(ticks)
        ax.set_yticklabels([f"{t:g}" for t in ticks])
        ax.set_ylim(-top, top)
        label += f"\n(log beyond ±{lin})"
    ax.axhline(0, color="k", lw=0.8)
    ax.set_ylabel(label, fontsize=8)


def finish_residual_axes(ax, raxes, residuals):
    """Scales each residual panel (raxes: kind -> axes, top to bottom; residuals: kind -> list
    of arrays), keeps the x labels of the lowest panel only, grids them all; returns
    [ax, *residual panels]."""
    for kind, rax in raxes.items():
        scale_residual_axis(rax, kind, np.concatenate(residuals[kind]) if residuals[kind] else np.array([]))
    every = [ax] + list(raxes.values())
    for a in every[:-1]:
        a.tick_params(labelbottom=False)
    for a in every:
        a.grid(alpha=0.3)
    return every


def wants_log(values):
    """Log y when the positive values span more than a decade."""
    v = values[np.isfinite(values) & (values > 0)]
    return v.size > 1 and v.max() > 10 * v.min()


LOG_DECADES = 5


def set_log_y(ax, values):
    """Log y over at most LOG_DECADES decades below the largest value."""
    v = values[np.isfinite(values) & (values > 0)]
    ax.set_yscale("log")
    ax.set_ylim(max(v.min(), v.max() * 10.0 ** -LOG_DECADES) / 1.5, v.max() * 1.5)


def save(fig, path):
    """Write to a temporary name and rename: never a half-written PNG."""
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=DPI, bbox_inches="tight")  # legends placed below the axes stay in the image
    os.replace(tmp, path)
    plt.close(fig)
