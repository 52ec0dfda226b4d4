# The reduced pipeline end to end on a tiny mcref dataset (10 one-layer entries,
# 2 x 2 incident directions, 4 x 4 bins, 4000 paths each): the dataset reader,
# fit_dataset.py (fits, HDF5 file, error report), train.py (weights, held-out
# report), figures.py and predict.py; and their rejection of bad input (one line,
# exit 2, nothing written).
import hashlib
import json
import os
import subprocess
import sys

import h5py
import numpy as np
import pytest
import torch

from spongecake import dataset, fit, fit_dataset, network

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(fit.__file__)))
BINARY = os.environ.get("MCREF_BINARY")

BASE = """
[geometry]
kind = "slab"
delta_transmission = true
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.5
thickness = 2.0
albedo = [0.95, 0.8, 0.5]
f0 = 1.0
orientation = [0.6, 0.0, 0.8]
[run]
seed = 1
batches = 2
[[measure]]
quantity = "brdf"
theta_i_deg = [30, 60]
phi_i_deg = [0, 90]
theta_o_bins = 4
phi_bins = 4
max_order = 20
samples = 2000
"""
DATASET = """
[dataset]
experiment = "base.toml"
entries = 10
seed = 7
tables = ["brdf", "brdf_btdf", "brdf_order1_volume", "brdf_btdf_order1_volume", "brdf_order2", "brdf_order3",
          "brdf_order4plus", "brdf_btdf_order2", "brdf_btdf_order3", "brdf_btdf_order4plus"]
[[parameter]]
key = "geometry.layer.0.alpha"
range = [0.2, 1.0]
[[parameter]]
key = "geometry.layer.0.phase"
choices = ["sggx_surface", "sggx_fiber"]
"""


def run(script, *args):
    env = dict(os.environ, PYTHONPATH=SCRIPTS)
    return subprocess.run([sys.executable, os.path.join(SCRIPTS, "spongecake", script), *args], capture_output=True,
                          text=True, env=env)


def tiny_dir(tmp_path_factory, name):
    """A new directory holding base.toml and tiny.toml (BASE, DATASET); skips without MCREF_BINARY."""
    if not BINARY:
        pytest.skip("needs MCREF_BINARY (ctest sets it)")
    d = tmp_path_factory.mktemp(name)
    (d / "base.toml").write_text(BASE)
    (d / "tiny.toml").write_text(DATASET)
    return d


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    d = tiny_dir(tmp_path_factory, "tiny")
    out = d / "tiny.h5"
    p = subprocess.run([BINARY, "dataset", str(d / "tiny.toml"), "-o", str(out), "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return d, out


def test_reader(tiny):
    d, out = tiny
    assert dataset.entry_indices(str(out)) == list(range(10))
    m = comps_material = dataset.read_material(str(out), 1)
    assert m.wi.shape == (2 * 2 * 2 * 4 * 4, 3) and m.ms.shape == m.wi.shape == m.total.shape == m.ms_stderr.shape
    assert m.layers[0].albedo == [0.95, 0.8, 0.5]
    # total - order 1 equals the sum of the order components (same per-path sums).
    copy = d / "copy.h5"
    copy.write_bytes(out.read_bytes())
    with h5py.File(copy, "a") as f:
        e = f["entries/1"]
        comps = sum(e[f"brdf_order{k}"]["value"][:] for k in ("2", "3", "4plus"))
        diff = e["brdf"]["value"][:] - e["brdf_order1_volume"]["value"][:]
        assert np.allclose(comps, diff, rtol=1e-12, atol=1e-14)
        del e["brdf_order2"]  # the reader falls back on total - order 1
    m = dataset.read_material(str(copy), 1)
    assert torch.allclose(m.ms, comps_material.ms, rtol=1e-12, atol=1e-14)
    assert float(torch.mean(m.ms)) > 0 and float(torch.mean(m.ms_stderr)) > 0
    # The fit beats the empty lobes (loss = mean |ms|) by a wide margin.
    loss, _, _, _ = fit.fit(m, n_starts=2, seed=1, iterations=30)
    assert loss < 0.5 * float(torch.mean(torch.abs(m.ms)))


def test_fit_dataset_cli(tiny):
    d, out = tiny
    fits = d / "fits.h5"
    p = run("fit_dataset.py", str(out), "-o", str(fits), "--entries", "1,9", "--starts", "2", "--iterations", "20")
    assert p.returncode == 0, p.stderr
    assert "median" not in p.stderr and "errors relative to the multiple scattering" in p.stdout
    assert "flake type" in p.stdout and "mean albedo" in p.stdout and "thickness" in p.stdout
    rows = fit_dataset.rows(str(fits))
    assert [r["entry"] for r in rows] == [1, 9] and all(r["none_ms"] == 1.0 for r in rows)
    d5, attrs = fit_dataset.read(str(fits))
    assert attrs["dataset_sha256"] == hashlib.sha256(out.read_bytes()).hexdigest()
    assert attrs["seed"] == 1 and attrs["starts"] == 2 and attrs["layers"] == 1
    assert d5["start_losses"].shape == (2, 2) and d5["lobes/albedo"].shape == (2, 1, 3) and d5["vector"].shape == (2, 9)
    # the stored loss is the loss of the stored lobes on the entry
    m = dataset.read_material(str(out), 9)
    lobes = fit.lobes_from_vector(torch.as_tensor(d5["vector"][1]), 1)
    assert float(fit.loss(m, lobes)) == pytest.approx(d5["loss"][1], rel=1e-12)
    assert d5["loss"][1] == min(d5["start_losses"][1])
    again = run("fit_dataset.py", "--report", str(fits))
    assert again.returncode == 0 and again.stdout in p.stdout


def test_train_cli(tiny):
    d, out = tiny
    fits = d / "fits9.h5"
    assert run("fit_dataset.py", str(out), "-o", str(fits), "--entries", "9", "--starts", "1", "--iterations", "10",
               "--quiet").returncode == 0
    weights = d / "net.h5"
    p = run("train.py", str(out), "-o", str(weights), "--epochs", "3", "--seed", "2", "--fits", str(fits))
    assert p.returncode == 0, p.stderr
    assert "held-out entries (1)" in p.stdout and "network med" in p.stdout and "fit med" in p.stdout
    net, attrs = network.load(str(weights))
    assert attrs["epochs"] == 3 and attrs["train_entries"] == 9 and attrs["validation"] == "entries with index % 10 == 9"
    with h5py.File(weights) as f:
        assert list(f["validation_index"][:]) == [9] and f["history/train_loss"].shape == (3,)
    p2 = run("train.py", str(out), "-o", str(d / "net2.h5"), "--epochs", "3", "--seed", "2", "--quiet")
    with h5py.File(weights) as a, h5py.File(d / "net2.h5") as b:
        assert np.array_equal(a["linear3/weight"][:], b["linear3/weight"][:]) and p2.returncode == 0
    # --stream (mini-batches read from the file) gives the same weights and histories as the
    # dataset held in memory, with every cell and with random cells per batch
    for extra in ([], ["--cells", "20"]):
        paths = []
        for stream in ([], ["--stream"]):
            paths.append(d / f"net_{len(extra)}_{len(stream)}.h5")
            p = run("train.py", str(out), "-o", str(paths[-1]), "--epochs", "3", "--seed", "2", "--quiet", *extra, *stream)
            assert p.returncode == 0, p.stderr
        with h5py.File(paths[0]) as a, h5py.File(paths[1]) as b:
            names = []
            a.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            assert "history/val_loss" in names and "linear0/weight" in names
            for n in names:
                assert np.array_equal(a[n][()], b[n][()]), n
    # the figures of the held-out entry and the evaluation for new layer parameters
    p = run("figures.py", str(out), str(fits), str(weights), "-o", str(d), "--prefix", "tiny")
    assert p.returncode == 0, p.stderr
    assert all((d / f"tiny_{k}.png").stat().st_size > 0 for k in ("bsdf", "lobes", "errors"))
    (d / "stack.toml").write_text(BASE)
    p = run("predict.py", str(weights), str(d / "stack.toml"))
    assert p.returncode == 0, p.stderr
    lobes = json.loads(p.stdout)
    assert len(lobes["alpha"]) == 1 and len(lobes["albedo"][0]) == 3 and max(max(lobes["albedo"][0]), 0) <= 1
    p = run("predict.py", str(weights), str(d / "base.toml").replace("base", "missing"))
    assert p.returncode == 2 and "missing.toml" in p.stderr


def test_bad_input(tmp_path):
    p = run("fit_dataset.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "f.h5"))
    assert p.returncode == 2 and "missing.h5" in p.stderr and len(p.stderr.strip().splitlines()) == 1
    p = run("fit_dataset.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "f.h5"), "--starts", "0")
    assert p.returncode == 2 and "--starts = 0" in p.stderr and ">= 1" in p.stderr
    p = run("fit_dataset.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "f.h5"), "--split", "1,-1")
    assert p.returncode == 2 and "--split" in p.stderr
    p = run("fit_dataset.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "nodir" / "f.h5"))
    assert p.returncode == 2 and "nodir" in p.stderr
    p = run("train.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "n.h5"), "--epochs", "0")
    assert p.returncode == 2 and "--epochs = 0" in p.stderr
    p = run("train.py", str(tmp_path / "missing.h5"), "-o", str(tmp_path / "n.h5"))
    assert p.returncode == 2 and "missing.h5" in p.stderr
    assert sorted(os.listdir(tmp_path)) == []


def test_bad_dataset_entries(tiny):
    d, out = tiny
    p = run("fit_dataset.py", str(out), "-o", str(d / "never.h5"), "--entries", "5,12")
    assert p.returncode == 2 and "[12]" in p.stderr and not (d / "never.h5").exists()
    p = run("train.py", str(out), "-o", str(d / "never.h5"), "--fits", str(out))
    assert p.returncode == 2 and "not a fits file" in p.stderr and not (d / "never.h5").exists()
