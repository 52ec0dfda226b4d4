#!/usr/bin/python3
"""Trains SpongeCake's parameter-mapping network (network.py; Wang et al. 2022, Sec. 5)
on an mcref dataset of one layer count, writes its weights (HDF5) and reports the
held-out error beside the per-material fit's and the baselines' (errors.py).

As in the paper: loss = MAE between the simulated multiple-scattering part (orders
>= 2, every cell and channel of reflection and transmission) and the lobes
evaluated through the differentiable single-scattering model (torch_model.py);
Adam, learning rate 1e-3, mini-batches of 32 entries. Split by entry index:
entries with index % 10 == 9 are held out for validation (10 %), the rest train.
Deterministic for a seed: torch.manual_seed(seed) (initial weights), a
torch.Generator seeded with seed (shuffling, cell subsets), one torch thread.
--cells K (not in the paper; default: every cell) evaluates each mini-batch on K
random cells, an unbiased estimate of the same loss at a fraction of the cost; the
validation loss always uses every cell. --stream (not in the paper) reads each
mini-batch's entries from the file instead of holding the dataset in memory: the same
results (tested), for datasets that do not fit (README, "SpongeCake's multiple-scattering
approximation", Memory). On sparse (noisy, sharp) tables the training
first sits at the empty-lobes loss (MAE = mean |ms|) for tens of epochs before it
moves (validate/FINDINGS.md): give it hundreds of epochs.

  /usr/bin/python3 scripts/spongecake/train.py DATA.h5 -o NET.h5 [--epochs 50] [--seed 1]
      [--lr 1e-3] [--batch 32] [--cells K] [--split R,T] [--fits FITS.h5] [--stream] [--quiet]
--fits: a fit_dataset.py file of the same dataset and Lambertian split, for the fit's error
on the held-out entries. Every input and output is checked before the training starts.
"""
import argparse
import os
import sys

import numpy as np
import torch

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from spongecake import dataset, errors, files, fit, fit_dataset, network  # noqa: E402
from spongecake import torch_model as tm  # noqa: E402


INT_MAX = 2 ** 63 - 1


def is_validation(index):
    """The 90/10 split by entry index."""
    return index % 10 == 9


def load_dataset(path, stream=False):
    """(indices, stacks, wi, wo, ms) of every entry, ms a dataset.EntryStore (held in memory,
    or read per request with stream=True). Every entry is checked first (check_dataset)."""
    indices, stacks, wi, wo = check_dataset(path)
    return indices, stacks, wi, wo, dataset.EntryStore(path, indices, stream)


def check_dataset(path):
    """(indices, stacks, wi, wo) of every entry, reading no table values (dataset.check_entry):
    one layer count, one set of cells, the total tables present, T rho > 0."""
    indices = dataset.entry_indices(path)
    stacks, wi, wo = [], None, None
    for i in indices:
        layers, e_wi, e_wo, has_total = dataset.check_entry(path, i, for_network=True)
        if not has_total:
            raise ValueError(f"{path}: entry {i}: needs the total tables brdf and brdf_btdf (the dataset's `tables`)")
        if stacks and len(layers) != len(stacks[0]):
            raise ValueError(f"{path}: entries with {len(stacks[0])} and {len(layers)} layers; one network takes "
                             "one layer count")
        if wi is None:
            wi, wo = e_wi, e_wo
        elif not (np.array_equal(e_wi, wi) and np.array_equal(e_wo, wo)):
            raise ValueError(f"{path}: entry {i} has other directions than entry {indices[0]}")
        stacks.append(layers)
    return indices, stacks, torch.as_tensor(wi, dtype=tm.DTYPE), torch.as_tensor(wo, dtype=tm.DTYPE)


def _ms(ms, rows, cells=slice(None)):
    """ms (a (N, cells, 3) tensor or a dataset.EntryStore) of the given rows and cells."""
    return ms[rows][:, cells] if isinstance(ms, torch.Tensor) else ms.ms(rows, cells)


def batch_loss(net, stacks, wi, wo, ms, split):
    """The paper's loss on a mini-batch: mean |lobes - ms| over entries, cells, channels."""
    layers = network.batch_layers(stacks)
    x = net(torch.as_tensor(np.asarray([network.features(s) for s in stacks]), dtype=tm.DTYPE))
    lobes = network.lobes_for(x[:, None, :], layers, split, normalise=False)
    return torch.abs(tm.multiple_scattering_lobes(layers, lobes, wi, wo) - ms).mean(dim=(-2, -1))


def train(stacks, wi, wo, ms, train_rows, val_rows, epochs, seed, lr=1e-3, batch=32, cells=None, split=(1.0, 1.0),
          log=None):
    """(net, history): Adam on the training rows; history holds the mean training loss per
    epoch (over its mini-batches) and the validation loss (every cell) after each epoch."""
    torch.set_num_threads(1)
    torch.manual_seed(seed)
    g = torch.Generator().manual_seed(seed)
    f = torch.as_tensor(np.asarray([network.features(stacks[i]) for i in train_rows]))
    std = f.std(dim=0)
    net = network.Mapping(len(stacks[0]), f.mean(dim=0), torch.where(std > 0, std, torch.ones_like(std)))
    opt = torch.optim.Adam(net.parameters(), lr=lr)
    history = {"train_loss": [], "val_loss": []}
    for epoch in range(epochs):
        order = [train_rows[int(k)] for k in torch.randperm(len(train_rows), generator=g)]
        total = 0.0
        for b in range(0, len(order), batch):
            rows = order[b:b + batch]
            c = slice(None) if cells is None else torch.randperm(wi.shape[0], generator=g)[:cells]
            loss = batch_loss(net, [stacks[i] for i in rows], wi[c], wo[c], _ms(ms, rows, c), split).mean()
            opt.zero_grad()
            loss.backward()
            opt.step()
            total += float(loss) * len(rows)
        history["train_loss"].append(total / len(order))
        history["val_loss"].append(float(evaluate(net, stacks, wi, wo, ms, val_rows, split).mean()) if val_rows else np.nan)
        if log:
            log(f"epoch {epoch + 1}/{epochs}: train MAE {history['train_loss'][-1]:.5g}, "
                f"validation MAE {history['val_loss'][-1]:.5g}")
    return net, history


def evaluate(net, stacks, wi, wo, ms, rows, split=(1.0, 1.0), chunk=1):
    """Per-entry MAE of the network's lobes on the given rows, every cell, `chunk` entries at
    a time (1: the memory of one entry's cells, 2.1 M at the paper's 32 x 32)."""
    with torch.no_grad():
        return torch.cat([batch_loss(net, [stacks[i] for i in rows[b:b + chunk]], wi, wo, _ms(ms, rows[b:b + chunk]), split)
                          for b in range(0, len(rows), chunk)])


def read_floor(fits_path, data_path, attrs, split, n_layers):
    """{entry index: fit loss} of a fits file (--fits), checked to come from the dataset
    (its SHA-256) with the same Lambertian split and layer count; {} without one."""
    if not fits_path:
        return {}
    d, fattrs = fit_dataset.read(fits_path)
    if fattrs.get("dataset_sha256") != attrs["dataset_sha256"]:
        raise ValueError(f"--fits {fits_path}: dataset_sha256 = {fattrs.get('dataset_sha256')!r} (allowed: the "
                         f"SHA-256 of {data_path}, {attrs['dataset_sha256']}: fits of that dataset)")
    fit_dataset.check_split(fits_path, fattrs, split, "--split")
    if int(fattrs.get("layers", n_layers)) != n_layers:
        raise ValueError(f"--fits {fits_path}: layers = {fattrs['layers']} (allowed: {n_layers}, the dataset's)")
    return dict(zip((int(i) for i in d["index"]), d["loss"]))


def held_out_rows(path, indices, losses, val_rows, floor, split):
    """errors.entry_row per held-out entry (read one at a time): the network, the per-material
    fit (where `floor`, read_floor's, has the entry), the Lambertian lobe alone."""
    out = []
    for r, loss in zip(val_rows, losses):
        i = indices[r]
        m = dataset.read_material(path, i)
        ms_mean = float(torch.mean(torch.abs(m.ms)))
        named = {"network": float(loss), "lambert": errors.lambertian_alone(m, split)[0]}
        if i in floor:
            named["fit"] = float(floor[i])
        out.append(errors.entry_row(i, [l.fiber for l in m.layers], [l.alpha for l in m.layers], [l.albedo for l in m.layers],
                                    [l.thickness for l in m.layers], named, ms_mean,
                                    float(torch.mean(torch.abs(m.total))),
                                    float(np.sqrt(2 / np.pi) * torch.mean(m.ms_stderr)),
                                    errors.single_scattering_check(m)))
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("data", help="mcref dataset file (SpongeCake slabs, one layer count)")
    p.add_argument("-o", "--output", required=True, help="weights file to write (HDF5)")
    p.add_argument("--epochs", type=int, default=50)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--batch", type=int, default=32)
    p.add_argument("--cells", type=int, help="random cells per mini-batch (default: every cell)")
    p.add_argument("--split", type=fit.parse_split, default=(1.0, 1.0), help="Lambertian split R,T (default 1,1)")
    p.add_argument("--fits", help="fit_dataset.py file of the same dataset (the fit's error on the held-out entries)")
    p.add_argument("--stream", action="store_true", help="read mini-batches from the file (less memory, same results)")
    p.add_argument("-q", "--quiet", action="store_true")
    a = p.parse_args(argv)
    try:
        for key, v in (("--epochs", a.epochs), ("--batch", a.batch), ("--cells", 1 if a.cells is None else a.cells)):
            if not 1 <= v <= INT_MAX:  # the weights file stores them as int64 attributes
                raise ValueError(f"{key} = {v} (allowed: an integer in [1, 2^63 - 1])")
        if not (a.lr > 0 and np.isfinite(a.lr)):
            raise ValueError(f"--lr = {a.lr} (allowed: a finite number > 0)")
        fit.check_seed(a.seed)
        files.check_outputs([("-o", a.output)], [("DATA.h5", a.data), ("--fits", a.fits)])
        indices, stacks, wi, wo = check_dataset(a.data)
        attrs = dataset.provenance(a.data)
        floor = read_floor(a.fits, a.data, attrs, a.split, len(stacks[0]))
        if all(is_validation(i) for i in indices):
            raise ValueError(f"{a.data}: entries {indices} are all held out (index % 10 == 9; allowed: a dataset "
                             "with training entries)")
    except (OSError, KeyError, ValueError) as e:
        print(f"train: {e}", file=sys.stderr)
        return 2
    ms = dataset.EntryStore(a.data, indices, a.stream)
    val_rows = [r for r, i in enumerate(indices) if is_validation(i)]
    train_rows = [r for r, i in enumerate(indices) if not is_validation(i)]
    net, history = train(stacks, wi, wo, ms, train_rows, val_rows, a.epochs, a.seed, a.lr, a.batch, a.cells, a.split,
                         None if a.quiet else lambda s: print(s, flush=True))
    per_layer = lambda f: np.asarray([[f(l) for l in stacks[r]] for r in train_rows])  # noqa: E731  (entries, L)
    for key, f in (("train_alpha_range", lambda l: l.alpha), ("train_optical_thickness_range",
                                                             lambda l: l.thickness * l.density)):
        v = per_layer(f)
        attrs[key] = np.stack([v.min(axis=0), v.max(axis=0)], axis=-1)  # [L, 2]: what predict.py accepts
    attrs.update({"seed": a.seed, "epochs": a.epochs, "lr": a.lr, "batch": a.batch,
                  "cells": -1 if a.cells is None else a.cells, "split": list(a.split), "optimizer": "adam",
                  "loss": "MAE over every cell and channel (reflection and transmission), orders >= 2",
                  "validation": "entries with index % 10 == 9", "train_entries": len(train_rows),
                  "script": "scripts/spongecake/train.py"})
    network.save(a.output, net, attrs, history, [indices[r] for r in val_rows])
    if val_rows:
        rows = held_out_rows(a.data, indices, evaluate(net, stacks, wi, wo, ms, val_rows, a.split), val_rows,
                             floor, a.split)
        methods = ["network"] + (["fit"] if all("fit_ms" in r for r in rows) else []) + ["lambert", "none"]
        print(f"held-out entries ({len(val_rows)}):")
        print(errors.report(rows, methods + ["noise", "sscheck"], "ms"))
        print(errors.report(rows, methods, "total"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
