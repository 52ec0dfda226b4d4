"""scripts/plot_validation.py on a small synthetic validation run (results.json +
tables/<case>.h5 shaped like mcref's): the plots appear, 0 = 0 series are left
out and named, model lines never share colour and style, every distinct channel
is drawn."""
import json
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest

SCRIPTS = os.path.join(os.path.dirname(__file__), "..", "..", "scripts")
sys.path.insert(0, SCRIPTS)

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import plot_curves  # noqa: E402
import plot_figures  # noqa: E402
import plot_style  # noqa: E402
import matplotlib.pyplot  # noqa: E402
import validation_data  # noqa: E402

N_NDF_MODELS = 9  # more than the six line styles the old plots cycled through


def write_table(group, axes, value, stderr, quantity, units, **attrs):
    group.attrs["axes"] = ",".join(n for n, _, _ in axes)
    group.attrs["quantity"] = quantity
    group.attrs["units"] = units
    for k, v in attrs.items():
        group.attrs[k] = v
    for n, v, unit in axes:  # mcref's netCDF-CF layout: units, and (n, 2) bounds on binned axes
        group.create_dataset(n, data=np.asarray(v, dtype=float)).attrs["units"] = unit
        if unit == "rad" and n in ("theta_o", "phi"):
            step = v[1] - v[0]
            group.create_dataset(n + "_bounds", data=np.stack([v - step / 2, v + step / 2], axis=1))
    group.create_dataset("value", data=value)
    group.create_dataset("stderr", data=stderr)


def check(table, model, values, exact=False):
    return {"table": table, "quantity": "", "model": model, "exact": exact, "status": "measured",
            "model_values": [None if np.isnan(v) else float(v) for v in np.ravel(values)]}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("validate_out")
    os.makedirs(out / "tables")
    rng = np.random.default_rng(1)
    cases = []
    # Case 1: an NDF (1-D, many models), an albedo per component and channel (one
    # component identically zero), a BRDF table, and an all-zero delta table.
    with h5py.File(out / "tables" / "syn_a.h5", "w") as h5:
        theta = np.radians(np.linspace(3, 87, 12))
        ndf = np.exp(-6 * theta)[:, None] + 0.001
        write_table(h5.create_group("ndf"), [("theta_m", theta, "rad"), ("phi_m", [0.0], "rad")],
                    ndf, 0.01 * ndf, "ndf", "1/sr")
        comps = ["order1", "order2", "total"]
        ti = np.radians([0, 30, 60, 80])
        alb = np.zeros((4, 1, 3, 3))
        alb[:, :, 0, :] = 0.2 * np.array([1.0, 0.6, 0.3])
        alb[:, :, 2, :] = 0.5 * np.array([1.0, 0.6, 0.3])
        write_table(h5.create_group("brdf_albedo"), [("theta_i", ti, "rad"), ("phi_i", [0.0], "rad"),
                    ("component", [0, 1, 2], "index"), ("channel", [0, 1, 2], "RGB index")],
                    alb, 0.01 * alb, "albedo", "1", components=",".join(comps))
        write_table(h5.create_group("brdf_delta"), [("theta_i", ti, "rad"), ("phi_i", [0.0], "rad"),
                    ("component", [0, 1, 2], "index"), ("channel", [0, 1, 2], "RGB index")],
                    np.zeros_like(alb), np.zeros_like(alb), "albedo", "1", components=",".join(comps))
        to = np.radians(np.linspace(7.5, 82.5, 6))
        ph = np.radians(np.linspace(22.5, 337.5, 8))
        brdf = (0.3 + np.cos(ph)[None, None, None, :, None] * 0.1 + 0.0 * to[None, None, :, None, None]) \
            * np.ones((2, 1, 6, 8, 3)) * np.array([1.0, 0.6, 0.6])  # B carries G's walk
        write_table(h5.create_group("brdf"), [("theta_i", np.radians([0, 60]), "rad"), ("phi_i", [0.0], "rad"),
                    ("theta_o", to, "rad"), ("phi", ph, "rad"), ("channel", [0, 1, 2], "RGB index")],
                    brdf, 0.02 * brdf, "brdf", "1/sr")
    brdf_model = brdf * (1 + 0.01 * rng.standard_normal(brdf.shape))
    brdf_model[..., 2] = np.nan  # as mcref leaves a duplicate channel out
    checks = [check("ndf", f"ndf_model_{k}", ndf * (1 + 0.02 * k), exact=(k == 0)) for k in range(N_NDF_MODELS)]
    model_alb = alb * 1.05
    model_alb[:, :, 1, :] = np.nan
    checks += [check("brdf_albedo", "albedo_model", model_alb), check("brdf_delta", "albedo_model", np.zeros_like(alb)),
               check("brdf", "brdf_model", brdf_model)]
    cases.append({"name": "syn_a", "figure": "Test Fig. 1", "description": "", "tables": "tables/syn_a.h5",
                  "checks": checks})
    # Case 2: a visible filling factor in the same paper figure.
    with h5py.File(out / "tables" / "syn_b.h5", "w") as h5:
        th = np.radians(np.linspace(0, 85, 10))
        tau = 1 - 0.5 * np.cos(th)[:, None]
        write_table(h5.create_group("tau_plus"), [("theta_i", th, "rad"), ("phi_i", [0.0], "rad")],
                    tau, 0.005 * tau, "tau_plus", "1")
    cases.append({"name": "syn_b", "figure": "Test Fig. 1", "description": "", "tables": "tables/syn_b.h5",
                  "checks": [check("tau_plus", "tau_plus_eq22", tau, exact=True),
                             check("tau_plus", "tau_plus_approx", 1.02 * tau)]})
    with open(out / "results.json", "w") as f:
        json.dump({"suite": "syn", "title": "", "significance": 0.001, "cases": cases}, f)
    subprocess.run([sys.executable, os.path.join(SCRIPTS, "plot_validation.py"), str(out), "--quiet"], check=True)
    results = validation_data.load_results(str(out))
    return out, results


def case_figure(run, name):
    out, results = run
    entry = next(c for c in results["cases"] if c["name"] == name)
    return plot_curves.case_figure(validation_data.load_case(str(out), entry))


def test_plot_files_appear(run):
    out, _ = run
    files = set(os.listdir(out / "plots"))
    for f in ("syn_a.png", "syn_a_table.png", "syn_a_lobes.png", "syn_b.png", "figure_test_fig_1.png"):
        assert f in files
    assert not any(f.endswith(".tmp.png") for f in files)
    assert "syn_b_table.png" not in files  # no BRDF table in that case


def gids(fig):
    return [(ax, line.get_gid()) for ax in fig.axes for line in ax.get_lines() if line.get_gid()]


def test_zero_component_and_table_are_skipped_and_named(run):
    fig = case_figure(run, "syn_a")
    drawn = [g for _, g in gids(fig)]
    assert any("order1" in g for g in drawn) and any("total" in g for g in drawn)
    assert not any("order2" in g for g in drawn)
    assert not any("brdf_delta" in g for g in drawn)
    assert not any("brdf_delta" in ax.get_title() for ax in fig.axes)
    note = next(t.get_text() for t in fig.texts if t.get_gid() == "skipped")
    assert "brdf_delta" in note and "order2" in note


def model_lines_per_axes(fig):
    per = {}
    for ax, g in gids(fig):
        if g.startswith("model|"):
            per.setdefault(ax, [])
    for ax in per:
        per[ax] = [(matplotlib.colors.to_hex(line.get_color()), str(line.get_linestyle()), line.get_gid())
                   for line in ax.get_lines() if (line.get_gid() or "").startswith("model|")]
    return per


def test_model_lines_never_share_colour_and_style(run):
    out, results = run
    ndf_models = 0
    figs = [case_figure(run, "syn_a"), case_figure(run, "syn_b")]
    figs.append(plot_figures.overlay_figure("Test Fig. 1", [validation_data.load_case(str(out), c)
                                                            for c in results["cases"]]))
    for fig in figs:
        for ax, lines in model_lines_per_axes(fig).items():
            pairs = [(c, s) for c, s, _ in lines]
            assert len(pairs) == len(set(pairs)), lines
            ndf_models = max(ndf_models, len({g for _, _, g in lines if "ndf_model" in g}))
    assert ndf_models == N_NDF_MODELS


def test_every_distinct_channel_is_drawn(run):
    fig = case_figure(run, "syn_a")
    titles = {ax.get_title() for ax in fig.axes}
    for table, channels in (("brdf_albedo", "RGB"), ("brdf", "RG")):
        for ch in channels:
            assert f"{table} — channel {ch}" in titles
            assert any(g.startswith(f"sim|{table}|channel {ch}|") for _, g in gids(fig))
    assert "brdf — channel B" not in titles  # the same walk as G: drawn once


def test_edges_from_cf_bounds_and_from_older_edges(tmp_path):
    """Bin edges come from `<axis>_bounds` (n, 2), or from `<axis>_edges` in older files."""
    with h5py.File(tmp_path / "t.h5", "w") as f:
        f.create_dataset("a/phi_bounds", data=np.array([[0.0, 1.0], [1.0, 3.0]]))
        f.create_dataset("b/phi_edges", data=np.array([0.0, 1.0, 3.0]))
        f.create_group("c")
        for g in ("a", "b"):
            assert np.array_equal(validation_data.edges_of(f[g], "phi"), [0.0, 1.0, 3.0])
        assert validation_data.edges_of(f["c"], "phi") is None


def test_plane_of_incidence_runs_left_to_right_for_a_btdf():
    """A BTDF's angle from -z, 180 - theta_o, falls as theta_o rises: the plane view
    sorts it, so that the light side runs -90..0 and the mirror side 0..90 (the
    lines jumped from -88 to +88 across the panel)."""
    phi = np.radians([0.0, 90.0, 180.0])
    ax = lambda n, v: validation_data.Axis(n, np.asarray(v, dtype=float), "rad")
    value = np.arange(4 * 3, dtype=float).reshape(1, 1, 4, 3)  # theta_i, phi_i, theta_o, phi
    for quantity, theta_o_deg, angles in (("btdf", [100.0, 120.0, 140.0, 160.0], [80.0, 60.0, 40.0, 20.0]),
                                          ("brdf", [10.0, 30.0, 50.0, 70.0], [10.0, 30.0, 50.0, 70.0])):
        angles = np.array(angles)
        axes = [ax("theta_i", [0.3]), ax("phi_i", [0.0]), ax("theta_o", np.radians(theta_o_deg)), ax("phi", phi)]
        table = validation_data.Table("t", quantity, "1/sr", axes, value, value)
        view = plot_curves.plane_view(table, 0)
        assert np.all(np.diff(view.x) > 0), (quantity, view.x)
        assert np.allclose(np.abs(view.x), np.concatenate([np.sort(angles)[::-1], np.sort(angles)]))
        y = view.series[0].take(value)
        # Each x keeps its own cell: the mirror side (phi = 180 deg, index 2) at theta_o's own angle.
        for xi, yi in zip(view.x, y):
            k = int(np.argmin(np.abs(angles - abs(xi))))
            assert yi == value[0, 0, k, 0 if xi < 0 else 2], (quantity, xi, yi)


def test_exact_and_approximate_models_get_their_own_residual_panels(run):
    # syn_b's tau_plus has an exact and an approximate model: z for the one, % for the other.
    fig = case_figure(run, "syn_b")
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert sum(label.startswith(plot_style.RESIDUAL_LABEL["z"]) for label in labels) == 1, labels
    assert sum(label.startswith(plot_style.RESIDUAL_LABEL["rel"]) for label in labels) == 1, labels


def test_relative_residual_is_the_reports_relative_error():
    # Over the cells where |sim| > 5 sigma only, as validate/metrics.cpp's max_rel_error.
    sim, se, model = np.array([2.0, 2.0, 0.04]), np.array([0.01, 0.01, 0.01]), np.array([1.0, 4.0, 1.0])
    r, _ = plot_style.residual("rel", sim, se, model)
    assert r[0] == pytest.approx(-50) and r[1] == pytest.approx(100) and np.isnan(r[2])


def test_a_logarithmic_residual_axis_says_so():
    fig, (lin, log) = matplotlib.pyplot.subplots(2)
    plot_style.scale_residual_axis(lin, "rel", np.array([-4.0, 3.0]))
    plot_style.scale_residual_axis(log, "rel", np.array([-4.0, 900.0]))
    assert "log" not in lin.get_ylabel() and lin.get_yscale() == "linear"
    assert "log beyond ±5" in log.get_ylabel() and log.get_yscale() == "symlog"
