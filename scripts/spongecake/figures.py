#!/usr/bin/python3
"""SpongeCake's Figs. 9-10 and 12-13 (Wang et al. 2022, Sec. 5) in the form a
reduced dataset allows, for held-out entries of a trained network (train.py):

  <prefix>_bsdf.png    whole-BSDF images of the multiple scattering (orders >= 2), one
                       row of panels per entry: simulation, per-material fit, network,
                       fit - simulation, network - simulation. In each image the rows
                       are incident directions (theta_i major, phi_i minor) and the
                       columns outgoing bins (theta_o major, phi minor), upper then
                       lower hemisphere; values are the mean over the RGB channels,
                       in 1/sr. Differences on a diverging scale whose range (stated on
                       the colour bar) is the 99th percentile of |simulation|.
  <prefix>_lobes.png   lobes at fixed incidence (theta_i nearest 35 deg, first phi_i) over
                       (cos theta_o, phi) bins, upper and lower hemispheres, phi on the
                       table's own axis ([0, 180] deg where mcref folds it: stacks with
                       omega_p = z; else [0, 360]): the single scattering
                       (simulated order 1) + multiple scattering (simulated / network)
                       against the simulated total.
  <prefix>_errors.png  the held-out error relative to the multiple scattering against
                       mean albedo and against total thickness: network, fit, Lambertian
                       lobe alone, and the noise level.
The entries shown are the held-out entries at the median, the 90th percentile and
the maximum of the network's error (--show all: every one). It also prints the
held-out error distribution (errors.report) of the network, the fit, the Lambertian
lobe alone and no term.

--unseen: DATA.h5 is not the network's dataset (e.g. the paper's own materials,
validate/datasets/spongecake_paper_*.toml): every fitted entry is unseen by the
network and is used. --summary PATH writes the per-entry rows (errors.entry_row:
one number per method) and the figures' file names as JSON (scripts/spongecake/stage.py
gathers them for the report).

  /usr/bin/python3 scripts/spongecake/figures.py DATA.h5 FITS.h5 NET.h5 -o OUTDIR [--prefix NAME]
      [--unseen] [--show quantiles|all] [--summary PATH]
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import torch  # noqa: E402

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from spongecake import dataset, errors, files, fit, fit_dataset, network  # noqa: E402
from spongecake import torch_model as tm  # noqa: E402


def table_axes(path, index):
    """((theta_i, phi_i, theta_o, phi) sizes, theta_i, phi bin edges in radians) of an entry's brdf table."""
    with files.open_hdf5(path) as f:
        g = f[f"entries/{index}/brdf"]
        return g["value"].shape[:4], g["theta_i"][:], dataset.edges(g, "phi")


def image(values, shape):
    """(cells, 3) in the reader's order -> (theta_i phi_i, 2 theta_o phi) mean over channels."""
    n_ti, n_pi, n_to, n_ph = shape
    v = np.asarray(values).mean(-1).reshape(2, n_ti * n_pi, n_to * n_ph)
    return np.concatenate([v[0], v[1]], axis=1)


def predictions(path, index, material, fits, net, split):
    row = list(fits["index"]).index(index)
    with torch.no_grad():
        fitted = tm.multiple_scattering_lobes(material.layers, fit.lobes_from_vector(
            torch.as_tensor(fits["vector"][row]), len(material.layers), split), material.wi, material.wo)
        lobes = net.lobes([material.layers], split)
        predicted = tm.multiple_scattering_lobes(network.batch_layers([material.layers]), lobes, material.wi,
                                                 material.wo)[0]
    return fitted.numpy(), predicted.numpy()


def stack_text(layers):
    """The layers, top first: flake type, alpha, T, mean albedo."""
    return " / ".join(f"{'fiber' if l.fiber else 'surface'} a={l.alpha:.2f} T={l.thickness:.2f} g={np.mean(l.albedo):.2f}"
                      for l in layers)


def describe(material, index):
    return f"entry {index}: {stack_text(material.layers)}"


def bsdf_figure(out, shown):
    """shown: (title, sim, fitted, predicted, table_axes of the entry) per entry."""
    fig, axes = plt.subplots(len(shown), 5, figsize=(17, 2.8 * len(shown)), squeeze=False, layout="constrained")
    for r, (title, sim, fitted, predicted, (shape, _, _)) in enumerate(shown):
        ims = [image(v, shape) for v in (sim, fitted, predicted)]
        top = float(np.percentile(np.abs(ims[0]), 99)) or 1.0
        panels = [(ims[0], "simulation"), (ims[1], "per-material fit"), (ims[2], "network"),
                  (ims[1] - ims[0], "fit - simulation"), (ims[2] - ims[0], "network - simulation")]
        for c, (im, name) in enumerate(panels):
            ax = axes[r, c]
            diff = c >= 3
            h = ax.imshow(im, cmap="RdBu_r" if diff else "viridis", vmin=-top if diff else 0, vmax=top,
                          aspect="auto", interpolation="nearest")
            ax.axvline(im.shape[1] / 2 - 0.5, color="w", lw=0.5)
            ax.set_title(name if c else f"{title}\n{name}", fontsize=8, loc="left")
            ax.set_xticks([])
            ax.set_yticks([])
            fig.colorbar(h, ax=ax, fraction=0.046, pad=0.02).ax.tick_params(labelsize=6)
    fig.supxlabel("outgoing bin: upper hemisphere | lower hemisphere (theta_o major, phi minor)", fontsize=8)
    fig.supylabel("incident direction (theta_i major, phi_i minor)", fontsize=8)
    save(fig, out)


def lobes_figure(out, shown):
    """shown: (title, total, single, sim_ms, predicted, table_axes of the entry) per entry. phi
    is drawn over the entry's own phi bin edges, which span [0, 180] deg where mcref folds phi
    (omega_p = z) and [0, 360] where it does not: entries of one file may differ."""
    fig, axes = plt.subplots(len(shown), 4, figsize=(13, 3.2 * len(shown)), squeeze=False, layout="constrained")
    for r, (title, total, single, sim_ms, predicted, (shape, theta_i, phi_edges)) in enumerate(shown):
        n_ti, n_pi, n_to, n_ph = shape
        k_theta = int(np.argmin(np.abs(np.degrees(theta_i) - 35)))
        phi_extent = (float(np.degrees(phi_edges[0])), float(np.degrees(phi_edges[-1])))

        def lobe(v):
            v = np.asarray(v).mean(-1).reshape(2, n_ti, n_pi, n_to, n_ph)[:, k_theta, 0]
            return np.concatenate([v[0], v[1]], axis=0)  # rows: theta_o upper then lower
        ims = [lobe(total), lobe(single + sim_ms), lobe(single + predicted)]
        top = float(np.max(ims[0])) or 1.0
        names = ["simulated total", "order 1 + simulated ms", "order 1 + network ms", "(order 1 + network) - total"]
        for c, im in enumerate(ims + [ims[2] - ims[0]]):
            ax = axes[r, c]
            h = ax.imshow(im, cmap="RdBu_r" if c == 3 else "viridis", vmin=-top if c == 3 else 0, vmax=top,
                          aspect="auto", interpolation="nearest", extent=(*phi_extent, -1, 1))
            ax.axhline(0, color="w", lw=0.5)
            ax.set_title(names[c] if c else f"{title}, theta_i = {np.degrees(theta_i[k_theta]):.0f} deg\n{names[c]}",
                         fontsize=8, loc="left")
            ax.set_xlabel("phi (deg)", fontsize=7)
            if c == 0:
                ax.set_ylabel("cos theta_o (bins)", fontsize=7)
            else:
                ax.set_yticklabels([])
            ax.tick_params(labelsize=6)
            fig.colorbar(h, ax=ax, fraction=0.046, pad=0.02).ax.tick_params(labelsize=6)
    save(fig, out)


def save(fig, out):
    """The figure as a PNG, written whole or not at all."""
    try:
        with files.atomic_output(out) as tmp:
            fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight")
    finally:
        plt.close(fig)


def errors_figure(out, rows, label):
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), layout="constrained")
    for ax, key, name in ((axes[0], "albedo", "mean albedo"), (axes[1], "thickness", "total thickness T")):
        for method, style in (("network", "o"), ("fit", "s"), ("lambert", "^"), ("noise", "x")):
            pts = [(r[key], 100 * r[f"{method}_ms"]) for r in rows if f"{method}_ms" in r and np.isfinite(r[f"{method}_ms"])]
            if pts:
                x, y = zip(*pts)
                ax.plot(x, y, style, ms=4, mfc="none", label=method)
        ax.set_xlabel(name)
        ax.set_ylabel("error / multiple scattering (%)")
        ax.set_yscale("log")
        if key == "thickness":
            ax.set_xscale("log")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{label}: held-out entries, sum|p - ms| / sum|ms|", fontsize=9)
    save(fig, out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("data")
    p.add_argument("fits")
    p.add_argument("weights")
    p.add_argument("-o", "--output", required=True, help="output directory (exists)")
    p.add_argument("--prefix", default="spongecake")
    p.add_argument("--unseen", action="store_true", help="DATA.h5 is not the network's dataset: use every fitted entry")
    p.add_argument("--show", choices=("quantiles", "all"), default="quantiles",
                   help="entries drawn: the median, 90th percentile and worst of the network's error, or all")
    p.add_argument("--summary", help="JSON file to write: per-entry errors and the figures' names")
    a = p.parse_args(argv)
    base = os.path.join(a.output, a.prefix)
    names = [f"{a.prefix}_{k}.png" for k in ("bsdf", "lobes", "errors")]
    try:
        if not os.path.isdir(a.output):
            raise ValueError(f"-o {a.output}: not a directory")
        inputs = [("DATA.h5", a.data), ("FITS.h5", a.fits), ("NET.h5", a.weights)]
        outputs = [("-o", os.path.join(a.output, n)) for n in names]
        files.check_outputs(outputs + ([("--summary", a.summary)] if a.summary else []), inputs)
        net, attrs = network.load(a.weights)
        fits, fattrs = fit_dataset.read(a.fits)
        fit_dataset.check_split(a.fits, fattrs, attrs["split"], f"the network {a.weights}")
        sha = dataset.provenance(a.data)["dataset_sha256"]
        if fattrs.get("dataset_sha256") != sha:
            raise ValueError(f"{a.fits}: the fits must come from {a.data} (dataset_sha256 differs)")
        if a.unseen:
            if attrs.get("dataset_sha256") == sha:
                raise ValueError(f"--unseen: {a.data} is the network's own dataset; leave --unseen out")
            held = [int(j) for j in fits["index"]]
        else:
            if attrs.get("dataset_sha256") != sha:
                raise ValueError(f"{a.weights}: the weights must come from {a.data} (dataset_sha256), or give --unseen")
            with files.open_hdf5(a.weights) as f:
                held = [int(i) for i in f["validation_index"][:] if int(i) in set(int(j) for j in fits["index"])]
        if not held:
            raise ValueError(f"{a.fits}: fits none of the network's held-out entries")
        available = set(dataset.entry_indices(a.data))  # a dataset file, not a part
        for i in held:
            if i not in available:
                raise ValueError(f"{a.fits}: entry {i} is not in {a.data}")
            dataset.check_entry(a.data, i, for_network=True)
        if int(fattrs.get("layers", net.n_layers)) != net.n_layers:
            raise ValueError(f"{a.fits}: stacks of {fattrs['layers']} layers; the network of {a.weights} takes {net.n_layers}")
    except (OSError, KeyError, ValueError) as e:
        print(f"figures: {e}", file=sys.stderr)
        return 2
    split = tuple(float(v) for v in attrs["split"])
    rows = []  # one entry in memory at a time; the entries drawn are read again below
    for i in held:
        m = dataset.read_material(a.data, i)
        fitted, predicted = predictions(a.data, i, m, fits, net, split)
        ms, total = m.ms.numpy(), m.total.numpy()
        k = list(fits["index"]).index(i)
        rows.append(errors.entry_row(i, [l.fiber for l in m.layers], [l.alpha for l in m.layers], [l.albedo for l in m.layers],
                                     [l.thickness for l in m.layers],
                                     {"network": float(np.mean(np.abs(predicted - ms))), "fit": float(fits["loss"][k]),
                                      "lambert": float(fits["lambertian_loss"][k])},
                                     float(np.mean(np.abs(ms))), float(np.mean(np.abs(total))), float(fits["noise_mae"][k]),
                                     errors.single_scattering_check(m)))
        rows[-1]["stack"] = stack_text(m.layers)
    print(f"{'unseen' if a.unseen else 'held-out'} entries with a fit ({len(rows)}):")
    print(errors.report(rows, ["network", "fit", "lambert", "none", "noise", "sscheck"], "ms"))
    print(errors.report(rows, ["network", "fit", "lambert", "none"], "total"))
    usable = sorted((r for r in rows if np.isfinite(r["network_ms"])), key=lambda r: r["network_ms"])
    picks = []
    for q in (0.5, 0.9, 1.0):
        r = usable[min(len(usable) - 1, int(round(q * (len(usable) - 1))))]
        if r["entry"] not in [x["entry"] for x in picks]:
            picks.append(r)
    if a.show == "all":
        picks = [r for r in rows if np.isfinite(r["network_ms"])]
    bsdf, lobes = [], []
    for r in picks:
        m = dataset.read_material(a.data, r["entry"])
        fitted, predicted = predictions(a.data, r["entry"], m, fits, net, split)
        title = f"{describe(m, r['entry'])}; network {100 * r['network_ms']:.0f} %, fit {100 * r['fit_ms']:.0f} %"
        axes = table_axes(a.data, r["entry"])
        bsdf.append((title, m.ms.numpy(), fitted, predicted, axes))
        single = m.total.numpy() - m.ms.numpy()
        lobes.append((f"entry {r['entry']}", m.total.numpy(), single, m.ms.numpy(), predicted, axes))
    bsdf_figure(base + "_bsdf.png", bsdf)
    lobes_figure(base + "_lobes.png", lobes)
    errors_figure(base + "_errors.png", rows, a.prefix)
    if a.summary:
        write_summary(a.summary, rows, [r["entry"] for r in picks], names, a.unseen)
    print(f"figures: {', '.join(os.path.join(a.output, n) for n in names)} ({len(held)} entries)")
    return 0


def write_summary(path, rows, shown, names, unseen):
    """--summary: the rows (NaN as null) and the figures, written whole then renamed."""
    clean = [{k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in r.items()} for r in rows]
    with files.atomic_output(path) as tmp, open(tmp, "w") as f:
        json.dump({"unseen": unseen, "rows": clean, "shown": shown, "figures": names}, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
