"""Per-material fit of SpongeCake's multiple-scattering lobes (Wang et al. 2022,
Sec. 5): for one material (its layers and its simulated multiple-scattering
part, orders >= 2, reflection and transmission), the lobe parameters (alpha',
T', gamma', f0' per layer, W1, W2) minimising the paper's loss, the MAE over
every cell and channel between the simulated part and
W1 f_ss'(wi, wo) + W2 f_lambert(wi, wo). Its loss is an upper bound on the floor of
the form itself (the best any network predicting the parameters could do), not the
floor: the loss is not convex and the optimiser is limited (fit_dataset.py's defaults,
3 starts x 10 iterations per smoothing stage). Measured on held-out one-layer entry 199
of the default run (validate/FINDINGS.md): starts 0.988, 0.991 and 0.992 of mean |ms|,
while the network reached 0.943 and a fit started from the network's lobes 0.880
(6 starts x 30 iterations: 0.877).

Optimiser: L-BFGS (strong Wolfe line search, torch) on the MAE smoothed as
mean(sqrt(r^2 + delta^2) - delta), delta decreasing to 0 (the MAE itself), from
several starts (the loss is not convex): start 0 is the material's own parameters with W1 = 0.5,
W2 = 0.05; the others are drawn from a torch.Generator seeded with `seed`.
Deterministic for a seed (one torch thread).

Output ranges (the paper states none; ours): alpha' in [0.01, 1] and T' in
[0.01, 100] (log scale), gamma', f0' in [0, 1], W1, W2 >= 0, through smooth maps
of unconstrained variables. W1 and gamma' enter only as W1 gamma'_c (Eq. 11), so
only those products are identifiable: the optimiser works on them (q = W1 gamma' >= 0)
and reports W1 = max q, gamma' = q / W1.

A library (put scripts/ on PYTHONPATH; the module `mcref` is not needed); the
command line over a dataset is fit_dataset.py.
"""
import argparse
import math
from dataclasses import dataclass

import torch

from spongecake import torch_model as tm

ALPHA_RANGE = (0.01, 1.0)
THICKNESS_RANGE = (0.01, 100.0)


@dataclass
class Material:
    """A material and its cells: layers (torch_model.FlakeLayer), directions wi, wo
    (cells, 3) and the simulated multiple-scattering part ms (cells, 3); from a
    dataset also the simulated total (all orders) and the standard error of ms."""
    layers: list
    wi: torch.Tensor
    wo: torch.Tensor
    ms: torch.Tensor
    total: torch.Tensor = None
    ms_stderr: torch.Tensor = None


def _log_range(a, lo, hi):
    return lo * (hi / lo) ** torch.sigmoid(a)


def _logit(u):
    return math.log(u / (1 - u))


def lobes_from_vector(x, n_layers, split=(1.0, 1.0), normalise=True):
    """The unconstrained vector x (..., 8 n_layers + 1) as torch_model.Lobes (fields of the
    batch shape "..."). Per layer (8 entries): alpha', T', log q (3), f0' (3), with
    q_c = W1 gamma'_c; then log W2. Since W1 and gamma' enter only as those products,
    q >= 0 covers the whole range of (W1 >= 0, gamma' in [0, 1]); normalise=True returns
    W1 = max q (over layers and channels), gamma' = q / W1 (the form's own parameters),
    normalise=False W1 = 1, gamma' = q (the same values, for the optimiser)."""
    alpha, thickness, q, f0 = [], [], [], []
    for k in range(n_layers):
        v = x[..., 8 * k:8 * k + 8]
        alpha.append(_log_range(v[..., 0], *ALPHA_RANGE))
        thickness.append(_log_range(v[..., 1], *THICKNESS_RANGE))
        q.append(torch.exp(v[..., 2:5]))
        f0.append(torch.sigmoid(v[..., 5:8]))
    if normalise:
        w1 = torch.amax(torch.stack(q, dim=-2), dim=(-2, -1))
        albedo = [t / w1[..., None] for t in q]
    else:
        w1, albedo = torch.ones(x.shape[:-1], dtype=tm.DTYPE), q
    return tm.Lobes(alpha, thickness, albedo, f0, w1=w1, w2=torch.exp(x[..., -1]),
                    split_reflection=split[0], split_transmission=split[1])


def vector_from_lobes(lobes, n_layers, margin=1e-6):
    """Inverse of lobes_from_vector; bounded values are clamped to [margin, 1 - margin]
    of their (log) range, where the maps' slopes are not yet flat."""
    def inv_log(v, lo, hi):
        u = (math.log(min(max(float(v), lo), hi)) - math.log(lo)) / (math.log(hi) - math.log(lo))
        return _logit(min(max(u, margin), 1 - margin))

    def inv_unit(v):
        return _logit(min(max(float(v), margin), 1 - margin))

    x = []
    for k in range(n_layers):
        x += [inv_log(lobes.alpha[k], *ALPHA_RANGE), inv_log(lobes.thickness[k], *THICKNESS_RANGE)]
        x += [math.log(max(float(lobes.w1) * float(v), margin)) for v in torch.as_tensor(lobes.albedo[k]).reshape(3)]
        x += [inv_unit(v) for v in torch.as_tensor(lobes.f0[k]).reshape(3)]
    x += [math.log(max(float(lobes.w2), margin))]
    return torch.tensor(x, dtype=tm.DTYPE)


def loss(material, lobes):
    """The paper's loss: mean absolute difference over every cell and channel."""
    return torch.mean(torch.abs(tm.multiple_scattering_lobes(material.layers, lobes, material.wi, material.wo) - material.ms))


def starts(material, count, seed):
    n = len(material.layers)
    own = tm.Lobes([l.alpha for l in material.layers], [l.thickness for l in material.layers],
                   [l.albedo for l in material.layers], [l.f0 for l in material.layers], w1=0.5, w2=0.05)
    out = [vector_from_lobes(own, n, margin=0.05)]
    g = torch.Generator().manual_seed(seed)
    for _ in range(count - 1):
        x = []
        for _ in range(n):
            u = 0.05 + 0.9 * torch.rand(5, generator=g, dtype=tm.DTYPE)  # alpha', T', f0' in their ranges
            log_q = math.log(0.02) + (math.log(1.0) - math.log(0.02)) * torch.rand(3, generator=g, dtype=tm.DTYPE)
            x.append(torch.cat([torch.log(u[:2] / (1 - u[:2])), log_q, torch.log(u[2:] / (1 - u[2:]))]))
        w2 = math.log(1e-3) + (math.log(0.5) - math.log(1e-3)) * torch.rand(1, generator=g, dtype=tm.DTYPE)
        out.append(torch.cat(x + [w2]))
    return out


def smoothed_loss(material, lobes, delta):
    """mean(sqrt(r^2 + delta^2) - delta): the MAE smoothed at scale delta (-> MAE as delta -> 0)."""
    r = tm.multiple_scattering_lobes(material.layers, lobes, material.wi, material.wo) - material.ms
    return torch.mean(torch.sqrt(r * r + delta * delta) - delta)


# Continuation in the smoothing scale, relative to mean |ms|: L-BFGS stalls on the
# kinks of the plain MAE, so each stage minimises a smoothed MAE from the previous
# stage's result, and the last stage is the MAE itself (delta = 0).
SMOOTHING = (1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 0.0)


def fit(material, n_starts=4, seed=1, iterations=200, split=(1.0, 1.0), x0=None):
    """Best of n_starts runs (L-BFGS per smoothing stage, `iterations` each); returns
    (loss, Lobes, unconstrained vector, per-start losses). x0 (optional) replaces the starts."""
    torch.set_num_threads(1)
    if n_starts < 1 or iterations < 1:
        raise ValueError(f"fit: starts = {n_starts}, iterations = {iterations} (allowed: >= 1)")
    n = len(material.layers)
    scale = float(torch.mean(torch.abs(material.ms)))
    best, losses = None, []
    for x_start in ([x0] if x0 is not None else starts(material, n_starts, seed)):
        x = x_start.clone().requires_grad_(True)
        for relative in SMOOTHING:
            opt = torch.optim.LBFGS([x], lr=1, max_iter=iterations, history_size=20, line_search_fn="strong_wolfe",
                                    tolerance_grad=1e-14, tolerance_change=1e-16)

            def closure():
                opt.zero_grad()
                value = smoothed_loss(material, lobes_from_vector(x, n, split, normalise=False), relative * scale)
                value.backward()
                return value

            opt.step(closure)
        with torch.no_grad():
            value = float(loss(material, lobes_from_vector(x, n, split, normalise=False)))
        losses.append(value)
        if math.isfinite(value) and (best is None or value < best[0]):
            best = (value, x.detach().clone())
    if best is None:
        raise RuntimeError("fit: every start ended with a non-finite loss")
    return best[0], lobes_from_vector(best[1], n, split), best[1], losses


# torch.manual_seed and torch.Generator.manual_seed take seeds in [0, 2^64 - 1].
SEED_RANGE = (0, 2 ** 64 - 1)


def check_seed(seed, key="--seed"):
    if not SEED_RANGE[0] <= seed <= SEED_RANGE[1]:
        raise ValueError(f"{key} = {seed} (allowed: an integer in [0, 2^64 - 1] = [{SEED_RANGE[0]}, {SEED_RANGE[1]}])")


def parse_split(text):
    try:
        r, t = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--split = {text!r}: expected two numbers R,T")
    if not (r >= 0 and t >= 0 and math.isfinite(r) and math.isfinite(t)):
        raise argparse.ArgumentTypeError(f"--split = {text!r}: R and T must be finite and >= 0")
    return r, t
