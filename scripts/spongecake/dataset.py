"""One entry of an mcref dataset file of SpongeCake slabs (validate/datasets/
spongecake_*.toml; README "Reference datasets") as a fit.Material: its layers
(from the entry's effective experiment config) and the simulated
multiple-scattering part (orders >= 2) of its reflection and transmission tables.
Entries simulated with another estimator than the analog one (geometry.estimator) are
refused: the standard error of the multiple scattering assumes each path leaves once.

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

from spongecake import files
from spongecake import torch_model as tm
from spongecake.fit import Material

HEMISPHERES = ("brdf", "brdf_btdf")


def entry_indices(path):
    """The entry indices of a dataset file; refuses other files and a dataset's part
    (storage = "sums": sums only, no values) with one line naming the file."""
    with files.open_hdf5(path) as f:
        if f.attrs.get("mcref_format", b"") not in ("mcref-dataset", b"mcref-dataset"):
            raise ValueError(f"{path}: not an mcref dataset file (mcref_format = 'mcref-dataset' expected)")
        storage = f.attrs.get("storage", "full")
        storage = storage.decode() if isinstance(storage, bytes) else str(storage)
        if storage == "sums":
            raise ValueError(f"{path}: storage = 'sums': a part of a dataset run (DATA.h5.parts/), whose tables hold "
                             "sums only (allowed: storage 'full' or 'lean'); finish the run with `mcref dataset` "
                             "(or `mcref merge` the shards) and give the assembled file")
        if "parameters/index" not in f:
            raise ValueError(f"{path}: no parameters/index (not a complete mcref dataset file)")
        return [int(i) for i in f["parameters/index"][:]]


# The keys of a slab layer that the lobes represent, and mcref's ranges for them (README,
# "Experiment files: microflake slabs"); any other key is refused rather than ignored.
LAYER_KEYS = ("phase", "alpha", "thickness", "density", "optical_thickness", "albedo", "f0", "orientation",
              "orientation_deg", "profile")
ALPHA_RANGE = (1e-4, 1e3)
THICKNESS_MAX = 1e9
DENSITY_MAX = 1e9
OPTICAL_THICKNESS_MAX = 1e6


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _number(layer, key, at, lo, hi, default=None, lo_open=False):
    v = layer.get(key, default)
    if v is None:
        raise ValueError(f"{at}.{key}: required (allowed: a number in [{lo:g}, {hi:g}])")
    if not _is_number(v) or not (lo < v if lo_open else lo <= v) or v > hi:
        raise ValueError(f"{at}.{key} = {v!r} (allowed: a number in {'(' if lo_open else '['}{lo:g}, {hi:g}])")
    return float(v)


def _rgb(layer, key, at):
    v = layer.get(key, 1.0)
    values = [v] * 3 if _is_number(v) else v if isinstance(v, list) and len(v) == 3 else None
    if values is None or not all(_is_number(x) and 0 <= x <= 1 for x in values):
        raise ValueError(f"{at}.{key} = {v!r} (allowed: a number or [r, g, b], each in [0, 1])")
    return [float(x) for x in values]


def _orientation(layer, at):
    """omega_p, normalised; orientation_deg = [theta, phi] as in mcref."""
    if "orientation" in layer and "orientation_deg" in layer:
        raise ValueError(f"{at}.orientation_deg: given with orientation (allowed: one of the two)")
    if "orientation_deg" in layer:
        v = layer["orientation_deg"]
        if not (isinstance(v, list) and len(v) == 2 and all(_is_number(x) for x in v)):
            raise ValueError(f"{at}.orientation_deg = {v!r} (allowed: [theta, phi] in degrees)")
        t, p = (math.radians(float(x)) for x in v)
        return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]
    v = layer.get("orientation", [0.0, 0.0, 1.0])
    if not (isinstance(v, list) and len(v) == 3 and all(_is_number(x) for x in v)) or \
            not 0 < math.sqrt(sum(float(x) ** 2 for x in v)) < math.inf:
        raise ValueError(f"{at}.orientation = {v!r} (allowed: a non-zero [x, y, z])")
    return [float(x) for x in v]


def layers_from_config(config_text, where, for_network=False):
    """The FlakeLayers of an experiment (geometry.layer), every key checked against what the
    lobes represent (homogeneous SGGX layers, no substrate) and against mcref's ranges;
    for_network: each layer's optical thickness T rho must be > 0 as well (the network's
    input is its logarithm, network.py)."""
    try:
        g = tomllib.loads(config_text).get("geometry", {})
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{where}: {e}") from None
    if g.get("kind") != "slab":
        raise ValueError(f"{where}: geometry.kind = {g.get('kind')!r} (allowed: 'slab')")
    if g.get("substrate", "none") != "none":
        raise ValueError(f"{where}: geometry.substrate = {g.get('substrate')!r} (allowed: 'none', as in Sec. 5)")
    if "density_vdb" in g:
        raise ValueError(f"{where}: geometry.density_vdb = {g['density_vdb']!r} (allowed: none; the lobes take "
                         "homogeneous layers, whose density is the layer's density or optical_thickness)")
    if not isinstance(g.get("layer", []), list):
        raise ValueError(f"{where}: geometry.layer = {g.get('layer')!r} (allowed: an array of tables [[geometry.layer]])")
    layers = []
    for k, l in enumerate(g.get("layer", [])):
        at = f"{where}: geometry.layer.{k}"
        if not isinstance(l, dict):
            raise ValueError(f"{at} = {l!r} (allowed: a table)")
        if l.get("phase") not in ("sggx_surface", "sggx_fiber"):
            raise ValueError(f"{at}.phase = {l.get('phase')!r} (allowed: 'sggx_surface', 'sggx_fiber')")
        for key in l:
            if key not in LAYER_KEYS:
                raise ValueError(f"{at}.{key}: not a key the lobes can represent (allowed: {', '.join(LAYER_KEYS)})")
        if l.get("profile", "constant") != "constant":
            raise ValueError(f"{at}.profile = {l.get('profile')!r} (allowed: 'constant')")
        alpha = _number(l, "alpha", at, *ALPHA_RANGE)
        thickness = _number(l, "thickness", at, 0.0, THICKNESS_MAX, default=1.0, lo_open=True)
        if "optical_thickness" in l and "density" in l:
            raise ValueError(f"{at}.optical_thickness: given with density (allowed: one of the two)")
        if "optical_thickness" in l:
            key, tau = "optical_thickness", _number(l, "optical_thickness", at, 0.0, OPTICAL_THICKNESS_MAX)
            density = tau / thickness
        else:
            key, density = "density", _number(l, "density", at, 0.0, DENSITY_MAX, default=1.0)
            if thickness * density > OPTICAL_THICKNESS_MAX:
                raise ValueError(f"{at}.density = {density!r}: T rho = {thickness * density:g} (allowed: "
                                 f"<= {OPTICAL_THICKNESS_MAX:g})")
        if for_network and not thickness * density > 0:
            top = OPTICAL_THICKNESS_MAX if key == "optical_thickness" else DENSITY_MAX
            raise ValueError(f"{at}.{key} = {l.get(key, 1.0)!r} (allowed for the network: a number in (0, {top:g}]; "
                             "its input is log(T rho))")
        layers.append(tm.FlakeLayer(fiber=l["phase"] == "sggx_fiber", alpha=alpha, thickness=thickness,
                                    density=density, albedo=_rgb(l, "albedo", at), f0=_rgb(l, "f0", at),
                                    orientation=_orientation(l, at)))
    if not layers:
        raise ValueError(f"{where}: no geometry.layer")
    return layers


def _multiple_scattering(entry, base, where):
    """(ms, its standard error, the total or None, the group giving the axes). The standard
    error of total - order 1 is sqrt(max(se_total^2 - se_order1^2, 0)): under the analog
    estimator (the only one _open_entry lets through; the next-event ones score a path at
    several orders) each path leaves once, so its order-1 and higher-order scores never
    share a cell, and the covariance of the two estimates is the variance of the order-1
    one (up to a mean-product term of relative size 1/paths). Both standard errors are
    estimated from the table's few batches, so this one is low on average: errors.py's
    "noise" is a lower bound."""
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
    return cell_directions(group["theta_i"][:], group["phi_i"][:], edges(group, "theta_o"), edges(group, "phi"))


def edges(group, axis):
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


def _open_entry(f, path, index, for_network=False):
    where = f"{path}: entry {index}"
    if f"entries/{index}" not in f:
        raise ValueError(f"{where}: no such entry")
    entry = f[f"entries/{index}"]
    if "config" not in entry.attrs:
        raise ValueError(f"{where}: no config attribute (not an entry of an mcref dataset file)")
    config = entry.attrs["config"]
    config = config.decode() if isinstance(config, bytes) else config
    layers = layers_from_config(config, where, for_network)
    estimator = tomllib.loads(config)["geometry"].get("estimator", "analog")
    if estimator != "analog":
        raise ValueError(f"{where}: geometry.estimator = {estimator!r} (allowed: 'analog', the default: the standard "
                         "error of the multiple scattering assumes each path leaves once, _multiple_scattering)")
    return entry, layers, where


def check_entry(path, index, for_network=False):
    """(layers, wi, wo, has_total) of an entry, reading its config and axes but no table values:
    the checks of read_material (layers, tables present with their values, axes), cheaply,
    before any work. for_network: as layers_from_config's."""
    with files.open_hdf5(path) as f:
        entry, layers, where = _open_entry(f, path, index, for_network)
        names, wis, wos, has_total = set(entry.keys()), [], [], True
        for base in HEMISPHERES:
            orders = [f"{base}_order2", f"{base}_order3", f"{base}_order4plus"]
            if all(n in names for n in orders):
                group, used = entry[orders[0]], orders + ([base] if base in names else [])
            elif base in names and f"{base}_order1_volume" in names:
                group, used = entry[base], [base, f"{base}_order1_volume"]
            else:
                raise ValueError(f"{where}: needs tables {', '.join(orders)} or {base} and {base}_order1_volume "
                                 f"(the dataset's `tables`); it has {sorted(names)}")
            for n in used:
                if not isinstance(entry[n], h5py.Group) or "value" not in entry[n] or "stderr" not in entry[n]:
                    raise ValueError(f"{where}: table {n} has no value and stderr (allowed: a dataset file of "
                                     "storage 'full' or 'lean', not sums only)")
            has_total = has_total and base in names
            wi, wo = _directions(group)
            wis.append(wi)
            wos.append(wo)
    return layers, np.concatenate(wis), np.concatenate(wos), has_total


def read_material(path, index):
    """Entry `index` of the dataset file as a fit.Material (every cell of reflection and transmission)."""
    with files.open_hdf5(path) as f:
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
    with files.open_hdf5(path) as f:
        for key in ("mcref_version", "git_commit", "seed", "entries", "dataset_config", "experiment_file"):
            if key in f.attrs:
                v = f.attrs[key]
                out["dataset_" + key] = v.decode() if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v
    return out
