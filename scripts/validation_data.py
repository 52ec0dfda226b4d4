"""The data of a validation run, as the plots read it: per case, its simulated
tables (OUTDIR/tables/<case>.h5: value, stderr, axes) with the model values
that results.json holds for each checked table."""
import json
import os
from dataclasses import dataclass, field

import h5py
import numpy as np

CHANNEL_NAMES = ["R", "G", "B"]


@dataclass
class Axis:
    name: str
    values: np.ndarray
    unit: str
    edges: np.ndarray = None  # bin edges, when the table stores them


@dataclass
class Model:
    name: str
    exact: bool
    values: np.ndarray  # shaped like the table; NaN where the model predicts nothing
    z: np.ndarray = None  # the report's z per cell (validate/metrics.h), shaped like the table; NaN where not compared


@dataclass
class Table:
    name: str
    quantity: str
    unit: str
    axes: list
    value: np.ndarray
    stderr: np.ndarray
    models: list = field(default_factory=list)
    components: list = field(default_factory=list)  # names along a "component" axis

    def axis(self, name):
        return next((i for i, a in enumerate(self.axes) if a.name == name), None)


@dataclass
class Case:
    name: str
    figure: str
    tables: list  # checked tables, in the order of their first check


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def units_of(obj):
    """netCDF-CF `units`, falling back to the older `unit`."""
    for key in ("units", "unit"):
        if key in obj.attrs:
            return _text(obj.attrs[key])
    return ""


def edges_of(group, n):
    """Bin edges of axis n: the CF `<n>_bounds` (n, 2), or the older `<n>_edges`; None if unbinned."""
    if n + "_bounds" in group:
        b = np.asarray(group[n + "_bounds"])
        return np.append(b[:, 0], b[-1, 1])
    return np.asarray(group[n + "_edges"]) if n + "_edges" in group else None


def load_table(group, name):
    axes = []
    for n in _text(group.attrs["axes"]).split(","):
        edges = edges_of(group, n)
        axes.append(Axis(n, np.asarray(group[n]), units_of(group[n]), edges))
    comps = _text(group.attrs.get("components", ""))
    return Table(name, _text(group.attrs.get("quantity", name)), units_of(group), axes,
                 np.asarray(group["value"], dtype=float), np.asarray(group["stderr"], dtype=float),
                 components=comps.split(",") if comps else [])


def load_case(out, case):
    tables = {}
    with h5py.File(os.path.join(out, case["tables"]), "r") as h5:
        for chk in case["checks"]:
            name = chk["table"]
            if name not in tables:
                tables[name] = load_table(h5[name], name)
            t = tables[name]
            values = np.array([np.nan if v is None else v for v in chk["model_values"]], dtype=float)
            z = chk.get("z")  # (results.json of older mcref: none)
            z = np.array([np.nan if v is None else v for v in z], dtype=float).reshape(t.value.shape) if z else None
            t.models.append(Model(chk["model"], bool(chk.get("exact", False)), values.reshape(t.value.shape), z))
    return Case(case["name"], case.get("figure", ""), list(tables.values()))


class RunError(Exception):
    """An OUTDIR that is not a readable validation run (one line, naming the file)."""


def load_results(out):
    """OUTDIR/results.json, checked before anything is plotted: a JSON object
    with a list of cases, each with its name, table file (present) and checks."""
    path = os.path.join(out, "results.json")
    try:
        with open(path) as f:
            results = json.load(f)
    except OSError as e:
        raise RunError(f"{path}: {e.strerror} (run `mcref validate SUITE -o {out}` first)")
    except ValueError as e:
        raise RunError(f"{path}: not valid JSON ({e})")
    if not isinstance(results, dict) or not isinstance(results.get("cases"), list):
        raise RunError(f"{path}: not a results.json of mcref validate (no list \"cases\")")
    for i, case in enumerate(results["cases"]):
        if not isinstance(case, dict) or not all(k in case for k in ("name", "tables", "checks")):
            raise RunError(f"{path}: cases.{i} lacks name, tables or checks (not a results.json of mcref validate?)")
        if not os.path.isfile(os.path.join(out, case["tables"])):
            raise RunError(f"{os.path.join(out, case['tables'])}: missing (the tables of case \"{case['name']}\")")
        check_provenance(out, path, case)
    return results


def check_provenance(out, path, case):
    """The case's table file is the one results.json judged: a validate run that
    stopped early (a full disk, Ctrl-C) leaves new tables beside the old
    results.json, whose z values and verdicts are not theirs."""
    stated = case.get("provenance")
    if not isinstance(stated, dict):  # (results.json of older mcref: not stated)
        return
    tables = os.path.join(out, case["tables"])
    try:
        with h5py.File(tables, "r") as h5:
            found = {k: _text(h5.attrs[k]) if k != "seed" else int(h5.attrs[k])
                     for k in ("created", "seed", "config") if k in h5.attrs}
    except OSError as e:
        raise RunError(f"{tables}: cannot be read ({e})")
    for key, value in found.items():
        if key in stated and stated[key] != value:
            raise RunError(f"{tables}: not the tables {path} judged ({key} {value!r} there, {stated[key]!r} in "
                           f"results.json; a validate run stopped before it finished): run `mcref validate SUITE -o "
                           f"{out}` again, it reuses the tables that are current")


def identically_zero(sim, models):
    """Simulation and every model are zero (or not predicted) on these cells: a 0 = 0 check."""
    return not np.any(sim) and all(np.all((m == 0) | np.isnan(m)) for m in models)


def distinct_channels(table):
    """Indices along the channel axis whose simulation differs from every earlier channel
    (several channels often carry the same walk); all indices without a channel axis: [None]."""
    c = table.axis("channel")
    if c is None:
        return [None]
    keep = []
    for k in range(len(table.axes[c].values)):
        sk = np.take(table.value, k, axis=c)
        if not any(np.array_equal(sk, np.take(table.value, j, axis=c)) for j in keep):
            keep.append(k)
    return keep


def channel_name(k, n):
    return CHANNEL_NAMES[k] if n == 3 else f"channel {k}"


def value_label(table, d, i):
    """'θi = 30°' style label of index i along axis d; component and channel by name."""
    axis = table.axes[d]
    v = axis.values[i]
    if axis.name == "component" and i < len(table.components):
        return table.components[i]
    if axis.name == "channel":
        return channel_name(i, len(axis.values))
    if axis.unit == "rad":
        return f"{greek(axis.name)} = {np.degrees(v):.0f}°"
    return f"{greek(axis.name)} = {v:.3g}"


GREEK = {"theta_i": "θi", "theta_o": "θo", "theta_m": "θm", "phi": "φ", "phi_i": "φi", "phi_m": "φm",
         "phi_m_rel": "φm − φi", "phi_over_phi_q": "φ/φq", "phi_conditional": "p(φ′ | θ′)", "mu": "μ", "tau_plus": "τ⁺", "tau_height": "τ(i, h)", "g1": "G1",
         "g1_conditional": "G1(i | m)", "ndf": "D(m)", "vndf": "Dv(i, m)", "p1": "p¹(r)",
         "brdf": "f_r", "btdf": "f_t", "brdf_modes": "f⁽ᵏ⁾", "albedo": "albedo",
         "transmittance": "transmittance", "energy_balance": "scattered energy",
         "spherical_albedo": "k_d (spherical albedo)", "phase": "2π p(μ) (per unit μ)",
         "pore_visibility": "pore visibility", "pore_visibility_independent": "pore visibility (independent)"}


def greek(name):
    return GREEK.get(name, name)
