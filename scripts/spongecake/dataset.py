"""One entry of an mcref dataset file of SpongeCake slabs (validate/datasets/
spongecake_*.toml; README "Reference datasets") as a fit.Material: its layers
(from the entry's effective experiment config) and the simulated
multiple-scattering part (orders >= 2) of its reflection and transmission tables.

The multiple-scattering part of a table <t> (brdf, brdf_btdf) is taken from the
entry's tables, first match wins:
  <t>_order2 + <t>_order3 + <t>_order4plus        (the components themselves), or
  <t> - <t>_order1_volume                         (total minus single scattering:
                                                   the same per-path sums, no substrate)
The model is evaluated at the cell centres: incident directions (theta_i, phi_i)
are points; outgoing bins are uniform in cos(theta_o) and in phi = phi_o - phi_i,
so the centre is the mean of the edge cosines and the mean of the edge azimuths.
"""
import hashlib
import math
import os
import tomllib

import h5py
import numpy as np
import torch

from spongecake import torch_model as tm
from spongecake.fit import Material

HEMISPHERES = ("brdf", "brdf_btdf")


def entry_indices(path):
    with h5py.File(path, "r") as f:
        if f.attrs.get("mcref_format", b"") not in ("mcref-dataset", b"mcref-dataset"):
            raise ValueError(f"{path}: not an mcref dataset file (mcref_format = 'mcref-dataset' expected)")
        return [int(i) for i in f["parameters/index"][:]]


def _rgb(layer, key, where):
    v = layer.get(key, 1.0)
    v = [float(v)] * 3 if isinstance(v, (int, float)) else [float(x) for x in v]
    if len(v) != 3:
        raise ValueError(f"{where}.{key} = {layer.get(key)}: expected a number or [r, g, b]")
    return v


def layers_from_config(config_text, where):
    """The FlakeLayers of an entry's effective experiment (geometry.layer)."""
    g = tomllib.loads(config_text).get("geometry", {})
    if g.get("kind") != "slab":
        raise ValueError(f"{where}: geometry.kind = {g.get('kind')!r} (allowed: 'slab')")
    if g.get("substrate", "none") != "none":
        raise ValueError(f"{where}: geometry.substrate = {g.get('substrate')!r} (allowed: 'none', as in Sec. 5)")
    layers = []
    for k, l in enumerate(g.get("layer", [])):
        at = f"{where}: geometry.layer.{k}"
        if l.get("phase") not in ("sggx_surface", "sggx_fiber"):
            raise ValueError(f"{at}.phase = {l.get('phase')!r} (allowed: 'sggx_surface', 'sggx_fiber')")
        if l.get("profile", "constant") != "constant":
            raise ValueError(f"{at}.profile = {l.get('profile')!r} (allowed: 'constant')")
        thickness = float(l.get("thickness", 1.0))
        density = float(l["optical_thickness"]) / thickness if "optical_thickness" in l else float(l.get("density", 1.0))
        if "orientation_deg" in l:
            t, p = (math.radians(float(v)) for v in l["orientation_deg"])
            orientation = [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]
        else:
            orientation = [float(v) for v in l.get("orientation", [0.0, 0.0, 1.0])]
        layers.append(tm.FlakeLayer(fiber=l["phase"] == "sggx_fiber", alpha=float(l["alpha"]), thickness=thickness,
                                    density=density, albedo=_rgb(l, "albedo", at), f0=_rgb(l, "f0", at),
                                    orientation=orientation))
    if not layers:
        raise ValueError(f"{where}: no geometry.layer")
    return layers


def _multiple_scattering(entry, base, where):
    """(ms, its standard error, the total or None, the group giving the axes). The standard
    error of total - order 1 is sqrt(max(se_total^2 - se_order1^2, 0)): each path leaves
    once, so its order-1 and higher-order scores never share a cell, and the covariance
    of the two estimates is the variance of the order-1 one (up to a mean-product term
    of relative size 1/paths)."""
    names = set(entry.keys())
    value = lambda n: np.asarray(entry[n]["value"], dtype=np.float64)  # noqa: E731
    se = lambda n: np.asarray(entry[n]["stderr"], dtype=np.float64)  # noqa: E731
    total = value(base) if base in names else None
    orders = [f"{base}_order2", f"{base}_order3", f"{base}_order4plus"]
    if all(n in names for n in orders):
        return (sum(value(n) for n in orders), np.sqrt(sum(se(n) ** 2 for n in orders)), total,
                entry[orders[0]])
    if total is not None and f"{base}_order1_volume" in names:
        first = f"{base}_order1_volume"
        return (total - value(first), np.sqrt(np.maximum(se(base) ** 2 - se(first) ** 2, 0.0)), total,
                entry[base])
    raise ValueError(f"{where}: needs tables {', '.join(orders)} or {base} and {base}_order1_volume "
                     f"(the dataset's `tables`); it has {sorted(names)}")


def _directions(group):
    axes = group.attrs["axes"]
    axes = (axes.decode() if isinstance(axes, bytes) else axes).split(",")
    if axes != ["theta_i", "phi_i", "theta_o", "phi", "channel"]:
        raise ValueError(f"{group.name}: axes {axes}, expected theta_i,phi_i,theta_o,phi,channel")
    return cell_directions(group["theta_i"][:], group["phi_i"][:], _edges(group, "theta_o"), _edges(group, "phi"))


def _edges(group, axis):
    """Bin edges: the CF `<axis>_bounds` (n, 2) of current tables, or `<axis>_edges` of older ones."""
    if axis + "_bounds" in group:
        b = group[axis + "_bounds"][:]
        return np.append(b[:, 0], b[-1, 1])
    return group[axis + "_edges"][:]


def cell_directions(theta_i, phi_i, theta_o_edges, phi_edges):
    """(wi, wo) of every (theta_i, phi_i, theta_o bin, phi bin) cell, row-major, as (cells, 3) arrays."""
    e, pe = np.asarray(theta_o_edges), np.asarray(phi_edges)
    mu = 0.5 * (np.cos(e[:-1]) + np.cos(e[1:]))  # signed: negative below the stack
    ph = 0.5 * (pe[:-1] + pe[1:])
    T, P, M, F = np.meshgrid(theta_i, phi_i, mu, ph, indexing="ij")
    wi = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    s = np.sqrt(np.maximum(0.0, 1 - M * M))
    wo = np.stack([s * np.cos(P + F), s * np.sin(P + F), M], -1)
    return wi.reshape(-1, 3), wo.reshape(-1, 3)


def _open_entry(f, path, index):
    where = f"{path}: entry {index}"
    if f"entries/{index}" not in f:
        raise ValueError(f"{where}: no such entry")
    entry = f[f"entries/{index}"]
    config = entry.attrs["config"]
    return entry, layers_from_config(config.decode() if isinstance(config, bytes) else config, where), where


def check_entry(path, index):
    """(layers, wi, wo, has_total) of an entry, reading its config and axes but no table values:
    the checks of read_material (layers, tables present, axes), cheaply, before any work."""
    with h5py.File(path, "r") as f:
        entry, layers, where = _open_entry(f, path, index)
        names, wis, wos, has_total = set(entry.keys()), [], [], True
        for base in HEMISPHERES:
            orders = [f"{base}_order2", f"{base}_order3", f"{base}_order4plus"]
            if all(n in names for n in orders):
                group = entry[orders[0]]
            elif base in names and f"{base}_order1_volume" in names:
                group = entry[base]
            else:
                raise ValueError(f"{where}: needs tables {', '.join(orders)} or {base} and {base}_order1_volume "
                                 f"(the dataset's `tables`); it has {sorted(names)}")
            has_total = has_total and base in names
            wi, wo = _directions(group)
            wis.append(wi)
            wos.append(wo)
    return layers, np.concatenate(wis), np.concatenate(wos), has_total


def read_material(path, index):
    """Entry `index` of the dataset file as a fit.Material (every cell of reflection and transmission)."""
    with h5py.File(path, "r") as f:
        entry, layers, where = _open_entry(f, path, index)
        wis, wos, mss, ses, totals = [], [], [], [], []
        for base in HEMISPHERES:
            ms, se, total, group = _multiple_scattering(entry, base, where)
            wi, wo = _directions(group)
            wis.append(wi)
            wos.append(wo)
            mss.append(ms.reshape(-1, 3))
            ses.append(se.reshape(-1, 3))
            totals.append(None if total is None else total.reshape(-1, 3))
    cat = lambda xs: torch.as_tensor(np.concatenate(xs), dtype=tm.DTYPE)  # noqa: E731
    return Material(layers, cat(wis), cat(wos), cat(mss), None if any(t is None for t in totals) else cat(totals),
                    cat(ses))


class EntryStore:
    """The multiple-scattering part ms of a dataset's entries (rows: positions in `indices`),
    held in memory (stream=False: every entry read once, ms stacked as (N, cells, 3)) or read
    from the file on each request (stream=True: memory of the requested rows' cells plus one
    entry while it is read). Both give the same values."""

    def __init__(self, path, indices, stream=False):
        self.path, self.indices, self.stream = path, list(indices), stream
        self.held = None if stream else torch.stack([read_material(path, i).ms for i in self.indices])

    def ms(self, rows, cells=slice(None)):
        """ms of the given rows at the given cells (an index tensor or a slice), (len(rows), cells, 3)."""
        if self.held is not None:
            return self.held[rows][:, cells]
        return torch.stack([read_material(self.path, self.indices[r]).ms[cells] for r in rows])


def provenance(path):
    """The dataset file's identity for files derived from it: its absolute path, SHA-256 of
    its bytes (the fingerprint) and the root attributes saying what made it."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    out = {"dataset": os.path.abspath(path), "dataset_sha256": h.hexdigest()}
    with h5py.File(path, "r") as f:
        for key in ("mcref_version", "git_commit", "seed", "entries", "dataset_config", "experiment_file"):
            if key in f.attrs:
                v = f.attrs[key]
                out["dataset_" + key] = v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v
    return out
