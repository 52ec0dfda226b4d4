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


def chi2_bins(theta, phi, density, theta_max, bins=(8, 16), order=16):
    """Pearson chi2 of the samples' (theta, phi) counts against n times the density's integral
    over each bin (Gauss-Legendre, order^2 points per bin; the density per steradian), bins
    expecting fewer than 5 pooled into one; returns (chi2, degrees of freedom, the 1e-3 upper
    quantile by Wilson-Hilferty, and the expected mass, which must be 1)."""
    t_edges, p_edges = np.linspace(0, theta_max, bins[0] + 1), np.linspace(-np.pi, np.pi, bins[1] + 1)
    x, w = np.polynomial.legendre.leggauss(order)
    expected = np.zeros(bins)
    for i in range(bins[0]):
        tt = (t_edges[i + 1] - t_edges[i]) / 2 * x + (t_edges[i + 1] + t_edges[i]) / 2
        wt = (t_edges[i + 1] - t_edges[i]) / 2 * w
        for j in range(bins[1]):
            pp = (p_edges[j + 1] - p_edges[j]) / 2 * x + (p_edges[j + 1] + p_edges[j]) / 2
            wp = (p_edges[j + 1] - p_edges[j]) / 2 * w
            T, P = np.meshgrid(tt, pp, indexing="ij")
            expected[i, j] = np.sum(density(T, P) * np.sin(T) * np.outer(wt, wp))
    mass = expected.sum()
    counts, _, _ = np.histogram2d(theta, phi, [t_edges, p_edges])
    expected *= len(theta)
    ok = expected >= 5
    obs = np.append(counts[ok], counts[~ok].sum())
    exp = np.append(expected[ok], expected[~ok].sum())
    keep = exp > 0
    chi2 = np.sum((obs[keep] - exp[keep]) ** 2 / exp[keep])
    dof = keep.sum() - 1
    z = 3.0902  # the normal's 1e-3 upper quantile
    bound = dof * (1 - 2 / (9 * dof) + z * np.sqrt(2 / (9 * dof))) ** 3
    return chi2, dof, bound, mass


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
    # The whole distribution: chi2 over 8 x 16 (theta_m, phi_m) bins against D_v (seed 5, 1e5 samples).
    chi2, dof, bound, mass = chi2_bins(t, p, lambda T, P: mg.vndf_eq13(tau0, beta, beta, ti, 0.0, T, P), np.pi / 2)
    assert abs(mass - 1) < 1e-3 and chi2 < bound, (chi2, dof, bound, mass)


def test_sggx_samplers():
    # pdf = the model at each sample, and the samples follow it: chi2 over 8 x 16 (theta, phi)
    # bins of the sphere (seed 2, 2e4 samples each; a pdf that ignored the flakes' tilt fails).
    s = sg.Sggx.surface_like(0.4, [0.3, 0, 1])
    m, pdf = sm.sggx_visible_normal(s, 0.6, 0.2, seed=2, n=20000)
    t, p = theta_phi(m)
    assert np.allclose(pdf, sg.visible_ndf(s, 0.6, 0.2, t, p), rtol=1e-9)
    chi2, dof, bound, mass = chi2_bins(t, p, lambda T, P: sg.visible_ndf(s, 0.6, 0.2, T, P), np.pi)
    assert abs(mass - 1) < 1e-3 and chi2 < bound, (chi2, dof, bound, mass)
    tilted = sg.Sggx.surface_like(0.4, [0, 0, 1])
    chi2, dof, bound, _ = chi2_bins(t, p, lambda T, P: sg.visible_ndf(tilted, 0.6, 0.2, T, P), np.pi)
    assert chi2 > bound, (chi2, dof, bound)
    wo, pdf = sm.sggx_phase(s, 0.6, 0.2, seed=2, n=20000)
    t, p = theta_phi(wo)
    assert np.allclose(pdf, sg.specular_flake_phase(s, 0.6, 0.2, t, p), rtol=1e-9)
    assert np.allclose(np.linalg.norm(wo, axis=1), 1)
    chi2, dof, bound, mass = chi2_bins(t, p, lambda T, P: sg.specular_flake_phase(s, 0.6, 0.2, T, P), np.pi)
    assert abs(mass - 1) < 1e-3 and chi2 < bound, (chi2, dof, bound, mass)


def test_lambert_sphere_phase_sampler():
    d = np.array([0.0, 0.0, -1.0])
    wo, pdf = sm.lambert_sphere_phase(d, seed=4, n=200000)
    mu = wo @ d
    assert np.allclose(pdf, ls.phase_eq1(mu), rtol=1e-12)
    se = np.std(mu) / np.sqrt(mu.size)
    assert abs(np.mean(mu) - (-4 / 9)) < 5 * se  # mean cosine of Eq. 1
