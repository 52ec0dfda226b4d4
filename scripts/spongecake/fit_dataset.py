#!/usr/bin/python3
"""Per-material fits over a whole SpongeCake dataset (Wang et al. 2022, Sec. 5): fits
every entry (fit.fit, several seeded starts), stores the fitted lobe parameters and
losses in HDF5 with the dataset's provenance, and prints the distribution of the
error (errors.py): the two lobes at their per-material fit (the best the optimiser
found: an upper bound on the form's floor, fit.py), the Lambertian lobe alone, and no
multiple-scattering term, by flake type, albedo and thickness.

  /usr/bin/python3 scripts/spongecake/fit_dataset.py DATA.h5 -o FITS.h5 [--entries 0,1,...]
      [--starts 3] [--seed 1] [--iterations 10] [--split R,T] [--quiet]
  /usr/bin/python3 scripts/spongecake/fit_dataset.py --report FITS.h5     (prints the report again)

FITS.h5 (mcref_format = "mcref-spongecake-fits", format_version = 1): root attributes
dataset, dataset_sha256 and the dataset's own provenance (dataset_git_commit, ...),
seed, starts, iterations, split; one row per entry, in entry order:
  index [n]; loss [n] (MAE of the fit); start_losses [n, starts]; lambertian_loss,
  lambertian_w2 [n]; mean_abs_ms, mean_abs_total, noise_mae, ss_check [n] (errors.py);
  vector [n, 8L+1] (fit.lobes_from_vector); lobes/{alpha, thickness} [n, L],
  lobes/{albedo, f0} [n, L, 3], lobes/{w1, w2} [n]; layers/{fiber, alpha, thickness,
  density} [n, L], layers/{albedo, f0, orientation} [n, L, 3] (the entry's stack).
Written to a temporary file and renamed into place once every fit is done; -o is checked
against the input before any fit (not the dataset, through links or '..' either).
"""
import argparse
import collections
import math
import os
import sys

import h5py
import numpy as np
import torch

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from spongecake import dataset, errors, files, fit  # noqa: E402

FORMAT = "mcref-spongecake-fits"
METHODS = ("fit", "lambert", "none", "noise", "sscheck")


def fit_entry(index, material, starts, seed, iterations, split):
    """fit.fit and the Lambertian baseline of one entry, as a dict of arrays for the file."""
    loss, lobes, vector, start_losses = fit.fit(material, starts, seed, iterations, split)
    lambert_loss, lambert_w2 = errors.lambertian_alone(material, split)
    layers = material.layers
    return {"index": index, "loss": loss, "start_losses": start_losses, "lambertian_loss": lambert_loss,
            "lambertian_w2": lambert_w2, "mean_abs_ms": float(torch.mean(torch.abs(material.ms))),
            "mean_abs_total": float(torch.mean(torch.abs(material.total))),
            "noise_mae": math.sqrt(2 / math.pi) * float(torch.mean(material.ms_stderr)),
            "ss_check": errors.single_scattering_check(material), "vector": vector.numpy(),
            "lobes/alpha": [float(a) for a in lobes.alpha], "lobes/thickness": [float(t) for t in lobes.thickness],
            "lobes/albedo": [np.asarray(a, dtype=np.float64) for a in lobes.albedo],
            "lobes/f0": [np.asarray(f, dtype=np.float64) for f in lobes.f0], "lobes/w1": float(lobes.w1),
            "lobes/w2": float(lobes.w2), "layers/fiber": [int(bool(l.fiber)) for l in layers],
            "layers/alpha": [l.alpha for l in layers], "layers/thickness": [l.thickness for l in layers],
            "layers/density": [l.density for l in layers], "layers/albedo": [l.albedo for l in layers],
            "layers/f0": [l.f0 for l in layers], "layers/orientation": [l.orientation for l in layers]}


def write(path, fits, attrs):
    with files.atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["mcref_format"] = FORMAT
        f.attrs["format_version"] = 1
        for k, v in attrs.items():
            f.attrs[k] = v
        for key in fits[0]:
            f.create_dataset(key, data=np.asarray([r[key] for r in fits]))


def row(r):
    """errors.entry_row of one fit_entry result (or one row of a fits file)."""
    return errors.entry_row(r["index"], r["layers/fiber"], r["layers/alpha"], r["layers/albedo"], r["layers/thickness"],
                            {"fit": r["loss"], "lambert": r["lambertian_loss"]}, r["mean_abs_ms"],
                            r["mean_abs_total"], r["noise_mae"], r.get("ss_check", math.nan))


def read(path):
    """Every dataset of a fits file, as {name: array}, and its attributes."""
    with files.open_hdf5(path) as f:
        if f.attrs.get("mcref_format") != FORMAT:
            raise ValueError(f"{path}: not a fits file (mcref_format = {FORMAT!r} expected)")
        d = {}
        f.visititems(lambda name, obj: d.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
        return d, dict(f.attrs)


def check_split(path, attrs, split, what):
    """The Lambertian split a fits file was made with (attribute split) must be `split`, the
    one its lobes are evaluated with (what: whose split that is)."""
    fitted = tuple(float(v) for v in attrs.get("split", (1.0, 1.0)))
    if fitted != tuple(float(v) for v in split):
        raise ValueError(f"{path}: split = {','.join(f'{v:g}' for v in fitted)} (allowed: "
                         f"{','.join(f'{float(v):g}' for v in split)}, the Lambertian split of {what}; fit again with "
                         "fit_dataset.py --split)")


def rows(path):
    """errors.entry_row of every entry of a fits file. Files without ss_check (older
    fit_dataset.py) get it from their dataset file, if it is still there unchanged."""
    d, attrs = read(path)
    if "ss_check" not in d and os.path.exists(attrs["dataset"]) and \
            dataset.provenance(attrs["dataset"])["dataset_sha256"] == attrs["dataset_sha256"]:
        d["ss_check"] = [errors.single_scattering_check(dataset.read_material(attrs["dataset"], int(i)))
                         for i in d["index"]]
    return [row({k: v[i] for k, v in d.items()}) for i in range(len(d["index"]))]


def print_report(entry_rows, methods=METHODS):
    print(errors.report(entry_rows, methods, "ms"))
    print(errors.report(entry_rows, [m for m in methods if m not in ("noise", "sscheck")], "total"))


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("data", nargs="?", help="mcref dataset file (SpongeCake slabs)")
    p.add_argument("-o", "--output", help="fits file to write (HDF5)")
    p.add_argument("--report", metavar="FITS.h5", help="print the error distribution of a fits file and stop")
    p.add_argument("--entries", help="comma-separated entry indices (default: all)")
    p.add_argument("--starts", type=int, default=3)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--iterations", type=int, default=10, help="L-BFGS iterations per smoothing stage")
    p.add_argument("--split", type=fit.parse_split, default=(1.0, 1.0), help="Lambertian split R,T (default 1,1)")
    p.add_argument("-q", "--quiet", action="store_true")
    a = p.parse_args(argv)
    try:
        if a.report:
            print_report(rows(a.report))
            return 0
        if not a.data or not a.output:
            raise ValueError("needs DATA.h5 and -o FITS.h5 (or --report FITS.h5)")
        if a.starts < 1 or a.iterations < 1:
            raise ValueError(f"--starts = {a.starts}, --iterations = {a.iterations} "
                             "(allowed: starts, iterations >= 1)")
        fit.check_seed(a.seed)
        files.check_outputs([("-o", a.output)], [("DATA.h5", a.data)])
        available = dataset.entry_indices(a.data)
        try:
            entries = available if a.entries is None else [int(v) for v in a.entries.split(",")]
        except ValueError:
            raise ValueError(f"--entries = {a.entries!r}: expected comma-separated entry indices")
        repeated = sorted(i for i, n in collections.Counter(entries).items() if n > 1)
        if repeated:
            raise ValueError(f"--entries = {a.entries!r}: {repeated} given more than once (allowed: each entry once)")
        missing = [i for i in entries if i not in available]
        if missing:
            raise ValueError(f"{a.data}: --entries {missing} not in the file (entries: {available[:10]}...)")
        headers = [dataset.check_entry(a.data, i) for i in entries]  # every entry checked first, no values read
        counts = {len(layers) for layers, _, _, _ in headers}
        if len(counts) != 1:
            raise ValueError(f"{a.data}: entries with {sorted(counts)} layers; one fits file takes one layer count")
        if not all(has_total for _, _, _, has_total in headers):
            raise ValueError(f"{a.data}: needs the total tables brdf and brdf_btdf (the dataset's `tables`)")
        attrs = dataset.provenance(a.data)
    except (OSError, KeyError, ValueError) as e:
        print(f"fit_dataset: {e}", file=sys.stderr)
        return 2
    fits, entry_rows = [], []
    for i in entries:  # one entry in memory at a time
        r = fit_entry(i, dataset.read_material(a.data, i), a.starts, a.seed, a.iterations, a.split)
        fits.append(r)
        entry_rows.append(row(r))
        if not a.quiet:
            e = entry_rows[-1]
            print(f"entry {i}: {e['type']}, fit {100 * e['fit_ms']:.1f} %, Lambertian {100 * e['lambert_ms']:.1f} %, "
                  f"noise {100 * e['noise_ms']:.1f} % of the multiple scattering", flush=True)
    attrs.update({"seed": a.seed, "starts": a.starts, "iterations": a.iterations, "split": list(a.split),
                  "layers": counts.pop(), "loss": "MAE over every cell and channel (reflection and transmission), "
                  "orders >= 2, model at the cell centres", "script": "scripts/spongecake/fit_dataset.py"})
    write(a.output, fits, attrs)
    print_report(entry_rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
