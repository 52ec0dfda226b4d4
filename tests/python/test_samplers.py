# Samplers return (samples, pdf): the pdf is the model's density at the sample,
# and the samples follow it (fixed seeds; bounds at many standard errors).
import numpy as np
import pytest

import mcref

mg, sm, ls, sg = mcref.micrograin, mcref.samplers, mcref.lambert_sphere, mcref.sggx


def test_uniforms_or_seed():
    u = np.random.default_rng(1).random((100, 2))
    a = sm.micrograin_ndf(0.5, 0.7, 0.7, u=u)
    b = sm.micrograin_ndf(0.5, 0.7, 0.7, u=u)
    assert np.array_equal(a[0], b[0]) and a[0].shape == (100, 3)
    c = sm.micrograin_ndf(0.5, 0.7, 0.7, seed=3, n=50)
    assert c[0].shape == (50, 3) and np.array_equal(c[0], sm.micrograin_ndf(0.5, 0.7, 0.7, seed=3, n=50)[0])
    with pytest.raises(mcref.ConfigError, match=r"shape \(n, 2\)"):
        sm.micrograin_ndf(0.5, 0.7, 0.7, u=np.zeros((4, 3)))
    with pytest.raises(mcref.ConfigError, match=r"\[0, 1\)"):
        sm.micrograin_ndf(0.5, 0.7, 0.7, u=np.ones((4, 2)))


def theta_phi(v):
    return np.arccos(np.clip(v[:, 2], -1, 1)), np.arctan2(v[:, 1], v[:, 0])


def test_micrograin_ndf_sampler():
    tau0, beta = 0.5, 0.7
    m, pdf = sm.micrograin_ndf(tau0, beta, beta, seed=11, n=200000)
    t, p = theta_phi(m)
    assert np.allclose(pdf, mg.ndf_eq17(tau0, beta, t) * np.cos(t), rtol=1e-9)
    # Empirical CDF of theta against Eq. 19 (Kolmogorov bound, n = 2e5: 1.95/sqrt(n) at 0.1 %).
    ts = np.sort(t)
    ecdf = np.arange(1, ts.size + 1) / ts.size
    assert np.max(np.abs(ecdf - mg.ndf_cdf_theta(tau0, beta, ts))) < 1.95 / np.sqrt(ts.size)


def test_micrograin_vndf_sampler():
    tau0, beta, ti = 0.5, 0.8, 1.0
    m, pdf = sm.micrograin_vndf(tau0, beta, beta, ti, 0.0, seed=5, n=100000)
    t, p = theta_phi(m)
    assert np.allclose(pdf, mg.vndf_eq13(tau0, beta, beta, ti, 0.0, t, p), rtol=1e-9)
    assert np.all(pdf > 0)
    # The mean of the sample's cos theta_m equals the quadrature mean of D_v.
    tm, wt = np.polynomial.legendre.leggauss(200)
    tm, wt = np.pi / 4 * (tm + 1), np.pi / 4 * wt
    pm, wp = np.polynomial.legendre.leggauss(200)
    pm, wp = np.pi * pm, np.pi * wp
    T, P = np.meshgrid(tm, pm, indexing="ij")
    dv = mg.vndf_eq13(tau0, beta, beta, ti, 0.0, T, P) * np.sin(T) * np.outer(wt, wp)
    mean = np.sum(dv * np.cos(T)) / np.sum(dv)
    se = np.std(m[:, 2]) / np.sqrt(len(m))
    assert abs(np.mean(m[:, 2]) - mean) < 5 * se + 1e-4


def test_sggx_samplers():
    s = sg.Sggx.surface_like(0.4, [0.3, 0, 1])
    m, pdf = sm.sggx_visible_normal(s, 0.6, 0.2, seed=2, n=20000)
    t, p = theta_phi(m)
    assert np.allclose(pdf, sg.visible_ndf(s, 0.6, 0.2, t, p), rtol=1e-9)
    wo, pdf = sm.sggx_phase(s, 0.6, 0.2, seed=2, n=20000)
    t, p = theta_phi(wo)
    assert np.allclose(pdf, sg.specular_flake_phase(s, 0.6, 0.2, t, p), rtol=1e-9)
    assert np.allclose(np.linalg.norm(wo, axis=1), 1)


def test_lambert_sphere_phase_sampler():
    d = np.array([0.0, 0.0, -1.0])
    wo, pdf = sm.lambert_sphere_phase(d, seed=4, n=200000)
    mu = wo @ d
    assert np.allclose(pdf, ls.phase_eq1(mu), rtol=1e-12)
    se = np.std(mu) / np.sqrt(mu.size)
    assert abs(np.mean(mu) - (-4 / 9)) < 5 * se  # mean cosine of Eq. 1
