"""SpongeCake in PyTorch (float64, differentiable): single scattering of a stack
of SGGX flake layers (Wang et al. 2022, Eq. 8-16, layers Sec. 4.4) and the
multiple-scattering lobes of Sec. 5. The same formulas, branches and guards as
the C++ model (models/sggx/single_scattering.cpp, multiple_scattering_lobes.cpp);
tests/scripts/spongecake/test_torch_model.py checks the two agree.

Conventions as in mcref: z is the macro normal, wi (toward the light) and wo
(toward the receiver) point away from the surface, wo.z < 0 with wi.z > 0 is
transmission; values are BSDFs in 1/sr without the cosine.

Shapes: directions are tensors (..., 3). A layer is a FlakeLayer whose fields
broadcast against the direction batch shape "...": alpha, thickness, density
and fiber (bool) of shape (...) or scalars, albedo and f0 of shape (..., 3)
(RGB), orientation (..., 3). Results have shape (..., 3): one value per channel.
So one call can evaluate one material on many directions, or a mini-batch of
materials (leading batch axis) at once.
"""
import math
from dataclasses import dataclass, replace
from typing import Sequence

import torch

DTYPE = torch.float64


def as_tensor(x):
    return torch.as_tensor(x, dtype=DTYPE)


@dataclass
class FlakeLayer:
    """One SGGX flake layer (Sec. 5 parameters); fiber=False is surface-like."""
    fiber: object
    alpha: object
    thickness: object
    albedo: object
    f0: object
    orientation: object
    density: object = 1.0


@dataclass
class Lobes:
    """The two added lobes of Sec. 5: per layer (alpha', T', gamma', f0'), scalar
    weights w1, w2, and the Lambertian lobe's split (reflection / pi on the side
    of wi, transmission / pi on the other side; see multiple_scattering_lobes.h)."""
    alpha: Sequence
    thickness: Sequence
    albedo: Sequence
    f0: Sequence
    w1: object
    w2: object
    split_reflection: float = 1.0
    split_transmission: float = 1.0


def spherical_direction(theta, phi):
    theta, phi = as_tensor(theta), as_tensor(phi)
    s = torch.sin(theta)
    return torch.stack([s * torch.cos(phi), s * torch.sin(phi), torch.cos(theta)], dim=-1)


def sggx_matrices(fiber, alpha, orientation):
    """(S, S^-1, sqrt(det S)) in closed form, a = alpha, wp = orientation normalised:
    surface-like S = a^2 I + (1 - a^2) wp wp^T, S^-1 = (I - wp wp^T) / a^2 + wp wp^T, sqrt det = a^2;
    fibre-like S = I + (a^2 - 1) wp wp^T, S^-1 = I - wp wp^T + wp wp^T / a^2, sqrt det = a."""
    alpha = as_tensor(alpha)
    a2 = (alpha * alpha)[..., None, None]
    wp = as_tensor(orientation)
    wp = wp / torch.linalg.norm(wp, dim=-1, keepdim=True)
    outer = wp[..., :, None] * wp[..., None, :]
    eye = torch.eye(3, dtype=DTYPE)
    fiber = as_tensor(fiber).bool()
    S = torch.where(fiber[..., None, None], eye + (a2 - 1) * outer, a2 * eye + (1 - a2) * outer)
    S_inv = torch.where(fiber[..., None, None], eye - outer + outer / a2, (eye - outer) / a2 + outer)
    sqrt_det = torch.where(fiber, alpha, alpha * alpha)
    return S, S_inv, sqrt_det


def quadratic_form(S, w):
    return (w[..., None, :] @ S @ w[..., :, None])[..., 0, 0]


def projected_area(S, w):
    """sigma(w) = sqrt(w^T S w) (Eq. 3, 7)."""
    return torch.sqrt(torch.clamp(quadratic_form(S, w), min=0.0))


def ndf(S_inv, sqrt_det, m):
    """D(m) = 1 / (pi sqrt(det S) (m^T S^-1 m)^2), m not necessarily unit (Eq. 7, general form)."""
    q = quadratic_form(S_inv, m) / (m * m).sum(-1)
    return 1.0 / (math.pi * sqrt_det * q * q)


def schlick(f0, cos_theta):
    k = 1 - torch.clamp(cos_theta, 0.0, 1.0)
    return f0 + (1 - f0) * k ** 5


def reduced_phase(S_inv, sqrt_det, albedo, f0, wi, wo):
    """F(h) D(h) / 4 per channel (Eq. 11), F = gamma Schlick(f0, |wi.h|); 0 where wi + wo = 0."""
    s = wi + wo
    n2 = (s * s).sum(-1)
    ok = n2 > 1e-24
    h = s / torch.sqrt(torch.where(ok, n2, torch.ones_like(n2)))[..., None]
    h = torch.where(ok[..., None], h, torch.tensor([0.0, 0.0, 1.0], dtype=DTYPE))
    F = as_tensor(albedo) * schlick(as_tensor(f0), torch.abs((wi * h).sum(-1))[..., None])
    value = F * (ndf(S_inv, sqrt_det, h) / 4)[..., None]
    return torch.where(ok[..., None], value, torch.zeros_like(value))


def reflection_G(tau, li, lo):
    """Eq. 12: (1 - exp(-tau (Li + Lo))) / (Li + Lo); 0 for tau <= 0."""
    s = li + lo
    return torch.where(tau > 0, -torch.expm1(-tau * s) / s, torch.zeros_like(s))


def transmission_G(tau, li, lo):
    """Eq. 16 with |cos|: (exp(-tau Lo) - exp(-tau Li)) / (Li - Lo) = tau exp(-tau min) (1 - e^-x)/x."""
    x = tau * torch.abs(li - lo)
    pos = x > 0
    x_safe = torch.where(pos, x, torch.ones_like(x))
    phi = torch.where(pos, -torch.expm1(-x_safe) / x_safe, torch.ones_like(x))
    g = tau * torch.exp(-tau * torch.minimum(li, lo)) * phi
    return torch.where(tau > 0, g, torch.zeros_like(g))


def single_scattering(layers: Sequence[FlakeLayer], wi, wo):
    """Sum over the layers of each layer's single-scattering lobe, attenuated by the
    layers crossed before and after it (Sec. 4.4): reflection (Eq. 8-12) when wi, wo
    are on the same side, transmission (Eq. 15-16, |cos| form) otherwise. (..., 3)."""
    wi, wo = as_tensor(wi), as_tensor(wo)
    mi, mo = torch.abs(wi[..., 2]), torch.abs(wo[..., 2])
    valid = (mi > 0) & (mo > 0)
    mi_s = torch.where(valid, mi, torch.ones_like(mi))
    mo_s = torch.where(valid, mo, torch.ones_like(mo))
    from_top = wi[..., 2] > 0
    reflection = (wi[..., 2] > 0) == (wo[..., 2] > 0)
    n = len(layers)
    S, tau, li, lo, depth_i, depth_o = [], [], [], [], [], []
    for layer in layers:
        Sk, Sk_inv, sqrt_det = sggx_matrices(layer.fiber, layer.alpha, layer.orientation)
        t = as_tensor(layer.thickness) * as_tensor(layer.density)
        lik, lok = projected_area(Sk, wi) / mi_s, projected_area(Sk, wo) / mo_s
        S.append((Sk_inv, sqrt_det))
        tau.append(t)
        li.append(lik)
        lo.append(lok)
        depth_i.append(torch.where(t > 0, t * lik, torch.zeros_like(lik)))
        depth_o.append(torch.where(t > 0, t * lok, torch.zeros_like(lok)))
    total = 0.0
    for k, layer in enumerate(layers):
        zero = torch.zeros_like(depth_i[k])
        above_i = sum((depth_i[j] for j in range(k)), zero)
        below_i = sum((depth_i[j] for j in range(k + 1, n)), zero)
        above_o = sum((depth_o[j] for j in range(k)), zero)
        below_o = sum((depth_o[j] for j in range(k + 1, n)), zero)
        before_i = torch.where(from_top, above_i, below_i)
        before_o = torch.where(from_top, above_o, below_o)
        after_o = torch.where(from_top, below_o, above_o)
        attenuation = torch.exp(-(before_i + torch.where(reflection, before_o, after_o)))
        g = torch.where(reflection, reflection_G(tau[k], li[k], lo[k]), transmission_G(tau[k], li[k], lo[k]))
        lobe = reduced_phase(*S[k], layer.albedo, layer.f0, wi, wo) * (attenuation * g / (mi_s * mo_s))[..., None]
        total = total + lobe
    return torch.where(valid[..., None], total, torch.zeros_like(total))


def lambertian_lobe(split_reflection, split_transmission, wi, wo):
    """split_reflection / pi (same side), split_transmission / pi (opposite sides); 0 at grazing. (...)."""
    wi, wo = as_tensor(wi), as_tensor(wo)
    same = (wi[..., 2] > 0) == (wo[..., 2] > 0)
    v = torch.where(same, as_tensor(split_reflection), as_tensor(split_transmission)) / math.pi
    v = v * torch.ones_like(wi[..., 2])
    return torch.where((wi[..., 2] == 0) | (wo[..., 2] == 0), torch.zeros_like(v), v)


def modified_layers(layers: Sequence[FlakeLayer], lobes: Lobes):
    """The stack with alpha, T, gamma, f0 from the lobes; type, orientation, density kept."""
    if not (len(lobes.alpha) == len(lobes.thickness) == len(lobes.albedo) == len(lobes.f0) == len(layers)):
        raise ValueError(f"lobes: one (alpha, thickness, albedo, f0) per layer expected, stack has {len(layers)} layers")
    return [replace(l, alpha=a, thickness=t, albedo=g, f0=f)
            for l, a, t, g, f in zip(layers, lobes.alpha, lobes.thickness, lobes.albedo, lobes.f0)]


def multiple_scattering_lobes(layers: Sequence[FlakeLayer], lobes: Lobes, wi, wo):
    """Sec. 5: W1 f_ss'(wi, wo) + W2 f_lambert(wi, wo), per channel (..., 3)."""
    ss = single_scattering(modified_layers(layers, lobes), wi, wo)
    lam = lambertian_lobe(lobes.split_reflection, lobes.split_transmission, wi, wo)
    return as_tensor(lobes.w1)[..., None] * ss + (as_tensor(lobes.w2) * lam)[..., None]
