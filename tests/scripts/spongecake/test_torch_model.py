# The torch SpongeCake model (scripts/spongecake/torch_model.py) equals the C++
# model through the pybind11 module: single scattering (Eq. 8-16, Sec. 4.4) and
# the multiple-scattering lobes (Sec. 5), every flake type, one and two layers,
# reflection and transmission, light from either side.
# Seed 16; per stack 4 random materials x 1500 random direction pairs (uniform
# on the sphere for wi and wo), 3 channels; tolerance 1e-6 relative.
import numpy as np
import pytest
import torch

import mcref
from spongecake import torch_model as tm

sg = mcref.sggx
STACKS = [("surface",), ("fiber",), ("surface", "surface"), ("surface", "fiber"), ("fiber", "surface"),
          ("fiber", "fiber")]
RTOL = 1e-6


def random_layer(rng, kind):
    return dict(type=kind, alpha=float(np.exp(rng.uniform(np.log(0.01), 0))), thickness=float(np.exp(rng.uniform(np.log(0.05), np.log(10)))),
                density=float(rng.uniform(0.5, 2)), albedo=rng.uniform(0, 1, 3).tolist(), f0=rng.uniform(0, 1, 3).tolist(),
                orientation=(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 1)))


def torch_layer(p):
    return tm.FlakeLayer(fiber=p["type"] == "fiber", alpha=p["alpha"], thickness=p["thickness"], density=p["density"],
                         albedo=p["albedo"], f0=p["f0"], orientation=p["orientation"])


def random_directions(rng, n):
    theta_i, theta_o = np.arccos(rng.uniform(-1, 1, n)), np.arccos(rng.uniform(-1, 1, n))
    phi_i, phi_o = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 2 * np.pi, n)
    return theta_i, phi_i, theta_o, phi_o


def assert_close(t, c):
    assert np.all(np.isfinite(t))
    err = np.abs(t - c)
    bad = err > RTOL * np.abs(c)
    assert not bad.any(), f"{bad.sum()} of {bad.size} differ; worst {np.max(err / np.maximum(np.abs(c), 1e-300)):.3g}"


def cases():
    rng = np.random.default_rng(16)
    for kinds in STACKS:
        for m in range(4):
            yield kinds, [random_layer(rng, k) for k in kinds], random_directions(rng, 1500), rng


@pytest.mark.parametrize("kinds", STACKS, ids=["-".join(s) for s in STACKS])
def test_single_scattering_equals_cpp(kinds):
    n_reflection = n_transmission = 0
    for k, params, (ti, pi, to, po), _ in cases():
        if k != kinds:
            continue
        layers = [sg.FlakeLayer(**p) for p in params]
        cpp = np.stack([sg.spongecake_ss_brdf(sg.flake_stack(layers, c), ti, pi, to, po) +
                        sg.spongecake_ss_btdf(sg.flake_stack(layers, c), ti, pi, to, po) for c in range(3)], axis=-1)
        wi, wo = tm.spherical_direction(ti, pi), tm.spherical_direction(to, po)
        t = tm.single_scattering([torch_layer(p) for p in params], wi, wo).numpy()
        assert_close(t, cpp)
        same = (np.cos(ti) > 0) == (np.cos(to) > 0)
        n_reflection += int(np.sum(same & (cpp[:, 0] > 0)))
        n_transmission += int(np.sum(~same & (cpp[:, 0] > 0)))
    assert n_reflection > 1000 and n_transmission > 1000


@pytest.mark.parametrize("kinds", STACKS, ids=["-".join(s) for s in STACKS])
def test_lobes_equal_cpp(kinds):
    for k, params, (ti, pi, to, po), rng in cases():
        if k != kinds:
            continue
        mod = [random_layer(rng, "surface") for _ in params]
        w1, w2, split_r, split_t = rng.uniform(0, 2), rng.uniform(0, 0.5), rng.uniform(0, 1), rng.uniform(0, 1)
        lobes = sg.MultipleScatteringLobes([sg.ModifiedLayer(m["alpha"], m["thickness"], m["albedo"], m["f0"]) for m in mod],
                                           w1, w2, split_r, split_t)
        layers = [sg.FlakeLayer(**p) for p in params]
        cpp = np.stack([sg.spongecake_ms_bsdf(layers, lobes, c, ti, pi, to, po) for c in range(3)], axis=-1)
        tl = tm.Lobes(alpha=[m["alpha"] for m in mod], thickness=[m["thickness"] for m in mod],
                      albedo=[m["albedo"] for m in mod], f0=[m["f0"] for m in mod], w1=w1, w2=w2,
                      split_reflection=split_r, split_transmission=split_t)
        t = tm.multiple_scattering_lobes([torch_layer(p) for p in params], tl,
                                         tm.spherical_direction(ti, pi), tm.spherical_direction(to, po)).numpy()
        assert_close(t, cpp)


def test_batched_materials_equal_one_by_one():
    # A leading batch axis of materials (for mini-batches) gives the same values.
    rng = np.random.default_rng(17)
    params = [[random_layer(rng, k) for k in ("fiber", "surface")] for _ in range(5)]
    ti, pi, to, po = random_directions(rng, 200)
    wi, wo = tm.spherical_direction(ti, pi), tm.spherical_direction(to, po)
    one = torch.stack([tm.single_scattering([torch_layer(p) for p in ps], wi, wo) for ps in params])
    batched = []
    for j in range(2):
        col = [ps[j] for ps in params]
        batched.append(tm.FlakeLayer(fiber=torch.tensor([p["type"] == "fiber" for p in col])[:, None],
                                     alpha=torch.tensor([p["alpha"] for p in col], dtype=torch.float64)[:, None],
                                     thickness=torch.tensor([p["thickness"] for p in col], dtype=torch.float64)[:, None],
                                     density=torch.tensor([p["density"] for p in col], dtype=torch.float64)[:, None],
                                     albedo=torch.tensor([p["albedo"] for p in col], dtype=torch.float64)[:, None, :],
                                     f0=torch.tensor([p["f0"] for p in col], dtype=torch.float64)[:, None, :],
                                     orientation=torch.tensor([p["orientation"] for p in col], dtype=torch.float64)[:, None, :]))
    assert torch.allclose(tm.single_scattering(batched, wi, wo), one, rtol=1e-12, atol=0)


def test_gradients_match_finite_differences():
    rng = np.random.default_rng(18)
    ti, pi, to, po = random_directions(rng, 40)
    wi, wo = tm.spherical_direction(ti, pi), tm.spherical_direction(to, po)

    def f(alpha, thickness, albedo, f0, w1, w2):
        layers = [tm.FlakeLayer(fiber=False, alpha=0.4, thickness=1.0, albedo=[0.5] * 3, f0=[0.5] * 3, orientation=(0.2, 0, 1)),
                  tm.FlakeLayer(fiber=True, alpha=0.3, thickness=2.0, albedo=[0.5] * 3, f0=[0.5] * 3, orientation=(0, 1, 0.5))]
        lobes = tm.Lobes(alpha=[alpha, 0.5], thickness=[thickness, 1.5], albedo=[albedo, [0.4] * 3], f0=[f0, [0.9] * 3],
                         w1=w1, w2=w2, split_reflection=1.0, split_transmission=0.5)
        return tm.multiple_scattering_lobes(layers, lobes, wi, wo)

    args = tuple(torch.tensor(v, dtype=torch.float64, requires_grad=True)
                 for v in (0.3, 0.8, [0.7, 0.5, 0.2], [0.1, 0.5, 0.9], 1.2, 0.3))
    assert torch.autograd.gradcheck(f, args, eps=1e-6, atol=1e-5, rtol=1e-4)


def test_module_rejects_bad_lobes_naming_the_key():
    layers = [sg.FlakeLayer("surface", 0.3, 1.0)]
    bad = sg.MultipleScatteringLobes([sg.ModifiedLayer(0.3, 1.0, [0.5, 0.5, 0.5], [1, 1, 1])], 1.0, -1.0)
    with pytest.raises(mcref.ConfigError, match=r"w2 = -1 .*\[0, inf\)"):
        sg.spongecake_ms_bsdf(layers, bad, 0, 0.1, 0.0, 0.2, 0.0)
    with pytest.raises(mcref.ConfigError, match="albedo"):
        sg.FlakeLayer("fiber", 0.3, 1.0, albedo=[1.5, 0, 0])
    with pytest.raises(mcref.ConfigError, match="flake type"):
        sg.FlakeLayer("sphere", 0.3, 1.0)
