# mcref.simulate returns exactly what `mcref simulate` writes; bad configs raise
# the CLI's one-line message; written tables are read by `mcref info`.
import os

import numpy as np
import pytest

import mcref

TAU_PLUS = """
[geometry]
kind = "micrograin"
tau0 = 0.4
beta = 0.8
tile = 40

[run]
seed = 5
batches = 3

[[measure]]
quantity = "tau_plus"
theta_i_deg = [0, 40, 80]
samples = 2000

[[measure]]
quantity = "ndf"
theta_m_bins = 6
phi_m_bins = 4
samples = 3000
"""

TAU_PLUS_DICT = {
    "geometry": {"kind": "micrograin", "tau0": 0.4, "beta": 0.8, "tile": 40},
    "run": {"seed": 5, "batches": 3},
    "measure": [
        {"quantity": "tau_plus", "theta_i_deg": [0, 40, 80], "samples": 2000},
        {"quantity": "ndf", "theta_m_bins": 6, "phi_m_bins": 4, "samples": 3000},
    ],
}


def same_tables(a, b):
    assert sorted(a.names) == sorted(b.names)  # files list groups by name
    for name in a.names:
        x, y = a[name], b[name]
        assert x.batches == y.batches and x.axis_names == y.axis_names
        for k in ("sum", "sum_sq", "value", "stderr"):
            assert np.array_equal(getattr(x, k), getattr(y, k)), (name, k)
        for ax, ay in zip(x.axes, y.axes):
            assert np.array_equal(ax.centres, ay.centres)


def test_simulate_equals_cli_bit_for_bit(cli, tmp_path):
    cfg = tmp_path / "exp.toml"
    cfg.write_text(TAU_PLUS)
    out = tmp_path / "cli.h5"
    code, _, err = cli("simulate", str(cfg), "-o", str(out), "--seed", "77", "--threads", "2", "--quiet")
    assert code == 0, err
    from_cli = mcref.read_tables(str(out))
    from_text = mcref.simulate(TAU_PLUS, seed=77, threads=1)
    from_dict = mcref.simulate(TAU_PLUS_DICT, seed=77, threads=2)
    from_file = mcref.simulate_file(str(cfg), seed=77)
    same_tables(from_cli, from_text)
    same_tables(from_cli, from_dict)
    same_tables(from_cli, from_file)
    assert from_text.provenance["seed"] == 77
    # A different seed gives different tables (the comparison can fail).
    other = mcref.simulate(TAU_PLUS, seed=78)
    assert not np.array_equal(other["tau_plus"].sum, from_cli["tau_plus"].sum)


def test_float_keys_round_trip_through_dict():
    # A dict's floats reach the experiment exactly (the canonical TOML text is re-parsed).
    tau0 = 0.1 + 0.2  # 0.30000000000000004
    text = mcref.parse_config(dict(TAU_PLUS_DICT, geometry={"kind": "micrograin", "tau0": tau0, "beta": 0.8, "tile": 40}))
    line = [l for l in text.splitlines() if l.strip().startswith("tau0")][0]
    assert float(line.split("=")[1]) == tau0


BAD = [
    ('tau0 = 0.4', 'tau0 = 1.5'),
    ('samples = 2000', 'samples = 2000\nsampels = 3'),
    ('quantity = "tau_plus"', 'quantity = "tau_minus"'),
    ('batches = 3', 'batches = "three"'),
    ('kind = "micrograin"', 'kind = "micrograin'),
]


@pytest.mark.parametrize("old,new", BAD)
def test_bad_configs_raise_the_cli_message(cli, tmp_path, old, new):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(TAU_PLUS.replace(old, new))
    code, _, err = cli("simulate", str(cfg), "-o", str(tmp_path / "x.h5"), "--quiet")
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mcref: error: ")
    with pytest.raises(mcref.ConfigError) as e:
        mcref.simulate_file(str(cfg))
    assert "mcref: error: " + str(e.value) == lines[0]
    assert "\n" not in str(e.value)
    # From text, the same message with the file named <string>.
    with pytest.raises(mcref.ConfigError) as e2:
        mcref.simulate(cfg.read_text())
    assert str(e2.value) == lines[0][len("mcref: error: "):].replace(str(cfg), "<string>", 1)
    assert not (tmp_path / "x.h5").exists()


def test_bad_dict_value_names_the_key():
    with pytest.raises(mcref.ConfigError, match=r"^<dict>: key 'geometry.tau0': .*\(0, 1\)"):
        mcref.simulate(dict(TAU_PLUS_DICT, geometry={"kind": "micrograin", "tau0": 2.0, "beta": 0.8}))
    with pytest.raises(mcref.ConfigError, match=r"key 'run.seed'.*not a TOML value"):
        mcref.simulate(dict(TAU_PLUS_DICT, run={"seed": object()}))


def test_write_tables_is_read_by_info_and_back(cli, tmp_path):
    t = mcref.simulate(TAU_PLUS, seed=3)
    path = tmp_path / "py.h5"
    mcref.write_tables(str(path), t)
    code, out, err = cli("info", str(path))
    assert code == 0, err
    assert "tau_plus" in out and "ndf" in out
    same_tables(t, mcref.read_tables(str(path)))
    assert not [p for p in os.listdir(tmp_path) if ".tmp" in p]  # no temporaries left


def test_info_gives_no_standard_error_for_one_batch(cli, tmp_path):
    """One batch has no standard error (NaN); info printed "max rel. stderr=0", as if exact."""
    s = np.arange(1.0, 5.0)
    tab = mcref.Table("one", "tau_plus", [mcref.Axis.bins("theta_i", "rad", np.linspace(0, 1, 5))], s, s * s, batches=1)
    path = tmp_path / "one.h5"
    mcref.write_tables(str(path), [tab])
    assert np.all(np.isnan(mcref.read_tables(str(path))["one"].stderr))
    code, out, err = cli("info", str(path))
    assert code == 0 and "batches=1  max rel. stderr=n/a (one batch)" in out, (out, err)


def test_write_new_table_from_arrays(cli, tmp_path):
    edges = np.linspace(0, np.pi / 2, 5)
    s = np.arange(4.0)
    tab = mcref.Table("mine", "tau_plus", [mcref.Axis.bins("theta_i", "rad", edges)], s, s * s / 2 + 1, batches=2,
                      units="1", description="made in Python")
    path = tmp_path / "mine.h5"
    mcref.write_tables(str(path), [tab], config="# none", seed=9)
    code, out, err = cli("info", str(path))
    assert code == 0 and "mine" in out, err
    assert "batches=2  max rel. stderr=" in out and "n/a" not in out, out
    back = mcref.read_tables(str(path))["mine"]
    assert np.array_equal(back.value, s / 2)
    assert np.array_equal(back.axis("theta_i").edges, edges)
    with pytest.raises(mcref.ConfigError, match="shape"):
        mcref.Table("bad", "tau_plus", [mcref.Axis.bins("theta_i", "rad", edges)], np.zeros(3), np.zeros(3), batches=1)


def test_write_refuses_a_directory(tmp_path):
    t = mcref.simulate(TAU_PLUS, seed=3)
    with pytest.raises(mcref.ConfigError):
        mcref.write_tables(str(tmp_path), t)


def test_evaluate_model_on_a_table():
    t = mcref.simulate(TAU_PLUS, seed=3)
    tab = t["tau_plus"]
    model = mcref.evaluate_model("tau_plus_eq22", tab, t.provenance["config"])
    theta = tab.axis("theta_i").centres
    assert np.allclose(model[:, 0], mcref.micrograin.tau_plus_eq22(0.4, 0.8, theta), rtol=1e-12, atol=0)
    with pytest.raises(mcref.ConfigError, match="unknown model"):
        mcref.evaluate_model("no_such_model", tab, t.provenance["config"])


BRDF_SMALL = """
[geometry]
kind = "micrograin"
tau0 = 0.4
beta = 1.0
tile = 20

[material.grain]
type = "lambertian"
albedo = 0.6

[material.base]
type = "lambertian"
albedo = 0.5

[run]
seed = 6
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [30, 70]
theta_o_bins = 3
phi_bins = 4
samples = 500
"""


def test_evaluate_model_reports_its_rule_accuracy():
    """return_accuracy: the adaptive cell rule's record (as results.json's
    rule_accuracy) for a model it evaluates; None for a fixed-rule model."""
    t = mcref.simulate(BRDF_SMALL, seed=2)
    config = t.provenance["config"]
    for name in ("brdf", "brdf_albedo"):
        tab = t[name]
        values, acc = mcref.evaluate_model("gdist_total_union" if name == "brdf" else "gdist_albedo", tab, config,
                                           return_accuracy=True)
        assert np.array_equal(values, mcref.evaluate_model("gdist_total_union" if name == "brdf" else "gdist_albedo",
                                                           tab, config), equal_nan=True)
        assert set(acc) == {"target", "integrals", "unconverged", "worst_rel_error", "worst_cell"}
        assert acc["target"] == 5e-7 and acc["integrals"] > 0 and 0 <= acc["worst_cell"] < values.size
        assert acc["unconverged"] == 0 and 0 < acc["worst_rel_error"] <= acc["target"]
    tau = mcref.simulate(TAU_PLUS, seed=3)
    values, acc = mcref.evaluate_model("tau_plus_eq22", tau["tau_plus"], tau.provenance["config"], return_accuracy=True)
    assert acc is None and values.shape == tuple(tau["tau_plus"].shape)


def test_to_xarray():
    xr = pytest.importorskip("xarray")  # optional dependency
    t = mcref.simulate(TAU_PLUS, seed=3)["ndf"]
    ds = t.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert np.array_equal(ds["value"].values, t.value) and np.array_equal(ds["sum_sq"].values, t.sum_sq)
    assert list(ds["value"].dims) == t.axis_names
    edges = t.axis("theta_m").edges
    assert ds["theta_m"].attrs == {"units": "rad", "bounds": "theta_m_bounds"}
    assert np.array_equal(ds["theta_m_bounds"].values, np.stack([edges[:-1], edges[1:]], axis=1))


def test_a_path_given_as_text_is_pointed_to_simulate_file():
    with pytest.raises(mcref.ConfigError, match="simulate_file"):
        mcref.simulate("validate/experiments/tau_plus.toml")


SLAB = """
[geometry]
kind = "slab"

[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 2.0
albedo = 0.8

[run]
seed = 3
batches = 2

[[measure]]
quantity = "brdf"
theta_i_deg = [30]
theta_o_bins = 4
phi_bins = 4
samples = 2000
"""


def test_only_the_named_tables(cli, tmp_path):
    # tables= and --table give the named tables only, the bits of the full run's.
    cfg = tmp_path / "slab.toml"
    cfg.write_text(SLAB)
    names = ["brdf_btdf_albedo", "brdf"]
    out = tmp_path / "two.h5"
    code, _, err = cli("simulate", str(cfg), "-o", str(out), "--table", names[0], "--table", names[1], "--quiet")
    assert code == 0, err
    from_cli = mcref.read_tables(str(out))
    from_python = mcref.simulate(SLAB, tables=names)
    full = mcref.simulate(SLAB)
    assert sorted(from_cli.names) == sorted(names) and sorted(from_python.names) == sorted(names)
    assert len(full.names) > len(names)
    same_tables(from_cli, from_python)
    for name in names:
        assert np.array_equal(full[name].sum, from_python[name].sum) and full[name].batches == from_python[name].batches


def test_a_table_the_experiment_does_not_write_is_refused(cli, tmp_path):
    cfg = tmp_path / "slab.toml"
    cfg.write_text(SLAB)
    out = tmp_path / "x.h5"
    code, _, err = cli("simulate", str(cfg), "-o", str(out), "--table", "brdf", "--table", "brdf_order5", "--quiet")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1
    assert lines[0].startswith("mcref: error: command line: key '--table': \"brdf_order5\" is not a table"), lines[0]
    assert "brdf_btdf_order4plus" in lines[0]  # the tables it writes
    assert not out.exists()
    with pytest.raises(mcref.ConfigError, match=r"^<python>: key 'tables': \"brdf_order5\" is not a table"):
        mcref.simulate(SLAB, tables=["brdf_order5"])
