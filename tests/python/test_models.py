# The vectorised models against values the C++ unit tests assert and against
# independent numpy evaluations of the printed formulas (quadrature, closed forms).
import numpy as np
import pytest

import mcref

mg, ls, rt, sg = mcref.micrograin, mcref.lambert_sphere, mcref.radiative_transfer, mcref.sggx


def gauss(a, b, n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def test_values_asserted_by_cpp_tests():
    # tests/models/test_radiative_transfer_h_function.cpp
    assert rt.h_isotropic(1.0, 1.0) == pytest.approx(2.90781, abs=5e-6)
    assert rt.h_isotropic(1.0, 0.5) == pytest.approx(2.01278, abs=5e-6)
    # tests/models/test_lambert_sphere_h_functions.cpp
    assert ls.h_exact(1, 1.0, 1.0) == pytest.approx(0.886, abs=5e-4)
    assert ls.h1_fit_conservative(1.0) == pytest.approx(np.exp(-0.0894878), abs=1e-15)
    # tests/models/test_micrograin_smith.cpp (README numbers)
    th = np.radians(80)
    assert mg.lambda_series(0.98, 1.0, th, 4) == pytest.approx(0.630, abs=5e-4)
    assert mg.lambda_quadrature(0.98, 1.0, th) == pytest.approx(0.686, abs=5e-4)


def test_vectorised_broadcasting():
    theta = np.linspace(0, 1.4, 7)
    v = mg.tau_plus_eq22(0.5, np.array([[0.5], [1.0]]), theta)
    assert v.shape == (2, 7)
    assert v[1, 3] == mg.tau_plus_eq22(0.5, 1.0, theta[3])
    assert isinstance(mg.ndf_eq17(0.5, 1.0, 0.2), float)


def test_micrograin_closed_forms_in_numpy():
    tau0, beta = 0.6, 0.7
    t = np.linspace(0, 1.5, 31)
    tan2 = np.tan(t) ** 2
    ggx = beta**2 / (np.pi * (beta**2 * np.cos(t) ** 2 + np.sin(t) ** 2) ** 2)
    d17 = -np.log(1 - tau0) * (1 - tau0) ** (tan2 / (beta**2 + tan2)) / tau0 * ggx  # LRPB23 Eq. 17
    assert np.allclose(mg.ndf_eq17(tau0, beta, t), d17, rtol=1e-12)
    gamma = np.sqrt(np.cos(t) ** 2 + beta**2 * np.sin(t) ** 2)
    tau_beta = 1 - (1 - tau0) ** (gamma / np.cos(t))  # Eq. 21
    assert np.allclose(mg.tau_plus_eq22(tau0, beta, t), 1 - np.sqrt((1 - tau_beta) * (1 - tau0)), rtol=1e-12)  # Eq. 22
    assert np.allclose(mg.ndf_anisotropic(tau0, beta, beta, t, 0.3), d17, rtol=1e-10)


def test_micrograin_ndf_normalised_and_vndf_normalised():
    tau0, beta = 0.5, 0.6
    x, w = gauss(0, np.pi / 2, 400)
    assert np.sum(w * 2 * np.pi * mg.ndf_eq17(tau0, beta, x) * np.cos(x) * np.sin(x)) == pytest.approx(1, abs=1e-6)
    # D_v(i, .) integrates to 1 over the normals (vNDF Eq. 6).
    tm, wt = gauss(0, np.pi / 2, 160)
    pm, wp = gauss(-np.pi, np.pi, 160)
    T, P = np.meshgrid(tm, pm, indexing="ij")
    dv = mg.vndf_eq13(tau0, beta, beta, 0.7, 0.0, T, P)
    assert np.sum(dv * np.sin(T) * np.outer(wt, wp)) == pytest.approx(1, abs=2e-3)


def test_g1_forms_and_tau_height():
    tau0, beta = 0.5, 1.0
    t = np.radians([10, 40, 70])
    assert np.allclose(mg.g1_smith_quadrature(tau0, beta, t), 1 / (1 + mg.lambda_quadrature(tau0, beta, t)))
    # tau(i, 0) equals tau+ (vNDF Eq. 4 / LRPB23 Eq. 22).
    assert np.allclose(mg.tau_height_sigma(tau0, beta, beta, t, 0.0, 0.0), mg.tau_plus_eq22(tau0, beta, t), rtol=1e-9)
    assert np.all(mg.g_dist(tau0, beta, beta, t, 0.0, 1.0) == 1.0)


def test_micrograin_bsdf_parts_add_up():
    grain, base = mg.MicroSurface("lambertian", kd=0.7), mg.MicroSurface("lambertian", kd=0.3)
    args = (0.5, 0.8, 0.4, 0.0, np.linspace(0.1, 1.2, 5), np.pi)
    total = mg.lrpb23(*args, grain, base)
    assert np.allclose(total, mg.lrpb23(*args, grain, base, part="grain") + mg.lrpb23(*args, grain, base, part="base"))
    assert np.all(total > 0)
    g = mg.gdist_grain(0.5, 0.8, 0.8, 0.4, 0.0, np.linspace(0.1, 1.2, 5), np.pi, grain)
    assert np.all(np.isfinite(g)) and np.all(g > 0)
    with pytest.raises(mcref.ConfigError, match="lambda"):
        mg.lrpb23(*args, grain, base, lambda_method="nope")


def test_chandrasekhar_isotropic():
    mu = np.linspace(0.05, 1, 9)
    a = 0.8
    h = rt.h_isotropic(a, mu)
    assert np.allclose(rt.chandrasekhar_isotropic(a, mu[:, None], mu[None, :]),
                       a * np.outer(h, h) / (4 * np.pi * (mu[:, None] + mu[None, :])), rtol=1e-12)
    assert np.allclose(rt.h_isotropic_table(a, mu), h, rtol=1e-12)
    # Chandrasekhar: directional albedo 2 pi int f mu_o dmu_o = 1 - H(mu_i) sqrt(1 - a).
    x, w = gauss(0, 1, 200)
    alb = 2 * np.pi * np.sum(w * rt.chandrasekhar_isotropic(a, 0.5, x) * x)
    assert alb == pytest.approx(1 - rt.h_isotropic(a, 0.5) * np.sqrt(1 - a), abs=1e-6)


def test_lambert_sphere():
    # Phase: normalised per steradian, mean cosine -4/9 (Eq. 1).
    t, w = gauss(0, np.pi, 400)
    p = ls.phase_eq1(np.cos(t))
    assert 2 * np.pi * np.sum(w * p * np.sin(t)) == pytest.approx(1, abs=1e-9)
    assert 2 * np.pi * np.sum(w * p * np.cos(t) * np.sin(t)) == pytest.approx(-4 / 9, abs=1e-9)
    c = np.linspace(0, 1, 11)
    s = np.sqrt(1 - c)
    kd = (-0.453029 * (1 - c) - 0.544162 * s + 1) / (1.42931 * s + 1)  # Eq. 40
    assert np.allclose(ls.kd_eq40(c), kd, rtol=1e-14)
    mi, mo, phi = 0.6, np.linspace(0.1, 1, 6), 0.4
    ss = ls.single_scattering_eq10(0.7, mi, mo, phi)
    cos_io = mi * mo + np.sqrt(1 - mi**2) * np.sqrt(1 - mo**2) * np.cos(phi)
    assert np.allclose(ss, 0.7 * ls.phase_eq1(-cos_io) / (mi + mo), rtol=1e-12)  # Eq. 10
    pub = ls.deon_brdf(0.7, mi, mo, phi, "deon_published")
    cor = ls.deon_brdf(0.7, mi, mo, phi, "deon_corrected")
    assert np.all(pub > ss) and not np.allclose(pub, cor)
    with pytest.raises(mcref.ConfigError, match="variant"):
        ls.deon_brdf(0.7, mi, mo, phi, "deon_typo")


def test_sggx_sigma_and_single_scattering():
    s = sg.Sggx.surface_like(0.3, [0, 0, 1])
    S = np.array(s.S)
    th, ph = np.linspace(0, 1.4, 8), 0.7
    w = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1)
    assert np.allclose(sg.sigma(s, th, ph), np.sqrt(np.einsum("ni,ij,nj->n", w, S, w)), rtol=1e-13)  # Eq. 3
    # sigma(w) = int <w.m>+ D(m) dm (Heitz 2015), by quadrature on the sphere.
    tm, wt = gauss(0, np.pi, 300)
    pm, wp = gauss(0, 2 * np.pi, 300)
    T, P = np.meshgrid(tm, pm, indexing="ij")
    m = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    w1 = w[3]
    proj = np.maximum(m @ w1, 0) * sg.ndf(s, T, P)
    assert np.sum(proj * np.sin(T) * np.outer(wt, wp)) == pytest.approx(sg.sigma(s, th[3], ph), rel=2e-3)
    # One layer, Eq. 11-12: f = F D(h)/4 G / (mu_i mu_o), G = (1 - exp(-tau (Li + Lo))) / (Li + Lo),
    # tau = T rho, Lambda = sigma / mu (the density is absorbed in G); F = 1 (f0 = albedo = 1).
    layer = sg.Layer.sggx(1.0, 2.0, s)
    ti, to = 0.5, np.linspace(0.1, 1.3, 5)
    f = sg.spongecake_ss_brdf([layer], ti, 0.0, to, np.pi)
    mi, mo = np.cos(ti), np.cos(to)
    li, lo = sg.sigma(s, ti, 0.0) / mi, sg.sigma(s, to, np.pi) / mo
    wi = np.array([np.sin(ti), 0, mi])
    wo = np.stack([-np.sin(to), 0 * to, mo], -1)
    h = (wi + wo) / np.linalg.norm(wi + wo, axis=-1, keepdims=True)
    d = sg.ndf(s, np.arccos(h[:, 2]), np.arctan2(h[:, 1], h[:, 0]))
    G = (1 - np.exp(-2.0 * (li + lo))) / (li + lo)
    assert np.allclose(f, d / 4 * G / (mi * mo), rtol=1e-10)
    # Two layers: more scattering than one; the substrate term adds.
    f2 = sg.spongecake_ss_brdf([layer, sg.Layer.isotropic(1.0, 1.0, 0.5)], ti, 0.0, to, np.pi)
    assert np.all(f2 > f)
    fs = sg.spongecake_ss_substrate([layer], 0.5, ti, 0.0, to, np.pi)
    assert np.all(fs > f)
    assert np.all(sg.spongecake_ss_btdf([layer], ti, 0.0, np.pi - to, np.pi) > 0)
    with pytest.raises(mcref.ConfigError):
        sg.Layer.hg(1.0, 1.0, 1.5)
