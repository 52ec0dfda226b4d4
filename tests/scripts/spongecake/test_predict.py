# predict.py and the network's reading of a stack (network.py, dataset.layers_from_config),
# with a network of random weights (torch seed 5, input mean 0 and deviation 1, so every
# input moves the outputs; no training and no mcref binary needed):
# - the lobes depend on the medium only: a layer given as (T, rho), (T/2, 2 rho) or
#   (4 T, optical_thickness = T rho) gives the same BSDF, in predict.py and in training;
# - omega_p and -omega_p (the same SGGX medium) give the same lobes;
# - a stack the lobes cannot represent, or a value out of range, is refused in one line
#   naming the file and the key, exit 2, nothing on stdout.
import json

import numpy as np
import pytest
import torch

from spongecake import dataset, network, train
from spongecake import torch_model as tm
from test_fit import grid
from test_pipeline import run

WI, WO = grid(3, 3, 4, 4)

LAYER = """
[geometry]
kind = "slab"
{geometry}
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.3
albedo = [0.9, 0.6, 0.3]
f0 = 0.8
{layer}
"""


@pytest.fixture(scope="module")
def weights(tmp_path_factory):
    torch.manual_seed(5)
    net = network.Mapping(1, torch.zeros(12), torch.ones(12))
    path = tmp_path_factory.mktemp("predict") / "net.h5"
    network.save(str(path), net, {"split": [1.0, 1.0], "dataset": "none"}, {"train_loss": [1.0]}, [])
    return path


def predict(weights, tmp_path, name, layer, geometry=""):
    toml = tmp_path / f"{name}.toml"
    toml.write_text(LAYER.format(layer=layer, geometry=geometry))
    return run("predict.py", str(weights), str(toml)), toml


def bsdf(p, toml):
    """The multiple-scattering lobes predict.py printed, on the stack of its experiment file."""
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    layers = dataset.layers_from_config(toml.read_text(), str(toml))
    lobes = tm.Lobes(out["alpha"], out["thickness"], out["albedo"], out["f0"], w1=out["w1"], w2=out["w2"],
                     split_reflection=out["split"][0], split_transmission=out["split"][1])
    return tm.multiple_scattering_lobes(layers, lobes, WI, WO), out


def test_the_lobes_depend_on_the_medium_only(weights, tmp_path):
    orientation = "orientation = [0.6, 0.0, 0.8]"
    reference, out = bsdf(*predict(weights, tmp_path, "a", f"thickness = 1.0\ndensity = 1.0\n{orientation}"))
    for name, layer in (("b", "thickness = 0.5\ndensity = 2.0"), ("c", "thickness = 4.0\noptical_thickness = 1.0")):
        value, other = bsdf(*predict(weights, tmp_path, name, f"{layer}\n{orientation}"))
        assert torch.allclose(value, reference, rtol=1e-12, atol=0), name
        assert other["optical_thickness"] == pytest.approx(out["optical_thickness"], rel=1e-12)
    assert float(reference.abs().max()) > 0
    # training sees the same: the mini-batch loss of the two descriptions on one table is the same
    net, _ = network.load(str(weights))
    a = dataset.layers_from_config(LAYER.format(layer=f"thickness = 1.0\n{orientation}", geometry=""), "a")
    b = dataset.layers_from_config(LAYER.format(layer=f"thickness = 0.5\ndensity = 2.0\n{orientation}", geometry=""),
                                   "b")
    ms = torch.stack([reference * 1.1, reference * 1.1])
    loss = train.batch_loss(net, [a, b], WI, WO, ms, (1.0, 1.0)).detach()
    assert float(loss[0]) == pytest.approx(float(loss[1]), rel=1e-12)


def test_opposite_orientations_give_the_same_lobes(weights, tmp_path):
    for w in ([0.6, 0.0, 0.8], [0.3, -0.5, 0.0], [0.0, 0.0, 1.0]):
        up, _ = predict(weights, tmp_path, "up", f"orientation = {w}")
        down, _ = predict(weights, tmp_path, "down", f"orientation = {[-v for v in w]}")
        assert up.returncode == 0 and down.returncode == 0, up.stderr + down.stderr
        assert json.loads(up.stdout) == json.loads(down.stdout), w
    # folded onto the hemisphere the datasets draw omega_p from (z >= 0; on the equator y > 0)
    assert np.allclose(network.folded([-0.6, 0.0, -0.8]), [0.6, 0.0, 0.8])
    w = np.array([0.3, -0.5, 0.0]) / np.linalg.norm([0.3, -0.5, 0.0])
    assert np.allclose(network.folded(w), -w) and np.allclose(network.folded(-w), -w)


@pytest.mark.parametrize("geometry, layer, key", [
    ('backend = "openvdb"\ndensity_vdb = "x.vdb"', "", "geometry.density_vdb"),
    ('substrate = "lambertian"', "", "geometry.substrate"),
    ("", 'profile = "linear"\nprofile_top = 1.0\nprofile_bottom = 0.0', "geometry.layer.0.profile"),
    ("", "g = 0.3", "geometry.layer.0.g"),
    ("", "orientation = [0.0, 0.0, 0.0]", "geometry.layer.0.orientation"),
    ("", "orientation = [1.0, 0.0]", "geometry.layer.0.orientation"),
    ("", "density = 0.0", "geometry.layer.0.density"),
    ("", "density = -1.0", "geometry.layer.0.density"),
    ("", "thickness = 0.0\noptical_thickness = 1.0", "geometry.layer.0.thickness"),
    ("", "optical_thickness = 0.0", "geometry.layer.0.optical_thickness"),
    ("", "density = 1.0\noptical_thickness = 1.0", "geometry.layer.0.optical_thickness"),
    ("", 'albedo = "x"', "geometry.layer.0.albedo"),
    ("", "f0 = [0.5, 2.0, 0.5]", "geometry.layer.0.f0"),
])
def test_refused_stacks_name_the_key(weights, tmp_path, geometry, layer, key):
    text = LAYER.format(layer=layer, geometry=geometry)
    if layer.startswith("albedo") or layer.startswith("f0"):
        text = text.replace("albedo = [0.9, 0.6, 0.3]\n" if layer.startswith("albedo") else "f0 = 0.8\n", "")
    toml = tmp_path / "bad.toml"
    toml.write_text(text)
    p = run("predict.py", str(weights), str(toml))
    assert p.returncode == 2 and p.stdout == "", p.stdout
    assert len(p.stderr.strip().splitlines()) == 1 and "bad.toml" in p.stderr and key in p.stderr, p.stderr
    assert "allowed" in p.stderr or "not a key" in p.stderr, p.stderr


def test_alpha_zero_is_refused(weights, tmp_path):
    toml = tmp_path / "alpha.toml"
    toml.write_text(LAYER.format(layer="", geometry="").replace("alpha = 0.3", "alpha = 0.0"))
    p = run("predict.py", str(weights), str(toml))
    assert p.returncode == 2 and p.stdout == "" and "geometry.layer.0.alpha = 0.0" in p.stderr, p.stderr
    assert "[0.0001, 1000]" in p.stderr and len(p.stderr.strip().splitlines()) == 1
