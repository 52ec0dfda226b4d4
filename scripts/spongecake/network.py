"""SpongeCake's parameter-mapping network (Wang et al. 2022, Sec. 5, Figs. 5-6): an
MLP with 3 hidden layers of 128 units that maps a stack's layer parameters to the
parameters of the two multiple-scattering lobes. One network per layer count.

Inputs, per layer (top first), as listed in Sec. 5: alpha, gamma (RGB), T, f0 (RGB),
the flake type k (0 surface, 1 fibre) and the orientation omega_p (3); alpha and T
enter as logarithms (they are sampled log-uniformly), and every input is
standardised with the training set's mean and standard deviation (stored). T is the
optical thickness T rho: the single scattering depends on T rho only (Eq. 12), and the
paper's layers have rho = 1. omega_p enters folded onto the upper hemisphere (z > 0; at
z = 0, y > 0, then x > 0), where the datasets draw it (validate/datasets/spongecake_*.toml,
distribution = "direction"): omega_p and -omega_p are the same SGGX medium (S holds
omega_p omega_p^T, Eq. 7), so they get the same lobes.
Outputs: the unconstrained vector of fit.lobes_from_vector (per layer alpha', T',
log W1 gamma' (RGB), f0' (RGB); then log W2), so the network's lobes have the
ranges of the per-material fit. T' is an optical thickness too (the paper's T' at
rho = 1), applied to each layer as the thickness T'/rho with the layer's own density
(lobes_for), so that the lobes depend on the medium only: (T, rho) and (T/c, c rho)
give the same BSDF. k and omega_p are passed through unchanged
(torch_model.modified_layers keeps them). Hidden activation: ReLU (the paper does
not name one). The last layer's bias starts at alpha' = T' = mid-range (log),
W1 gamma' = 0.3, f0' = 0.5, W2 = 0.05, so the first lobes are of the data's order.

Weights file (HDF5, mcref_format = "mcref-spongecake-network", format_version = 1):
datasets input_mean, input_std [12 L], linear<j>/weight [out, in] and linear<j>/bias
[out] for j = 0..3 (torch.nn.Linear, y = x W^T + b), history/{train_loss, val_loss}
[epochs] and validation_index; attributes layers (L), hidden, activation,
inputs, outputs, alpha_range, thickness_range (the lobes' output ranges), split, the
training settings, train_alpha_range and train_optical_thickness_range ([L, 2]: per
layer, the smallest and largest alpha and T rho of the training entries; predict.py
refuses a stack outside them unless --extrapolate; files written before them have
neither and are not checked) and the dataset's provenance (dataset, dataset_sha256, ...).
"""
import math

import h5py
import numpy as np
import torch

from spongecake import files, fit
from spongecake import torch_model as tm

FORMAT = "mcref-spongecake-network"
HIDDEN = (128, 128, 128)
INPUTS = ("log_alpha", "gamma_r", "gamma_g", "gamma_b", "log_thickness", "f0_r", "f0_g", "f0_b", "fiber",
          "omega_x", "omega_y", "omega_z")
OUTPUTS = ("alpha", "thickness", "log_q_r", "log_q_g", "log_q_b", "f0_r", "f0_g", "f0_b")  # fit.lobes_from_vector


def input_names(n_layers):
    return [f"layer{k}.{n}" for k in range(n_layers) for n in INPUTS]


def output_names(n_layers):
    return [f"layer{k}.{n}" for k in range(n_layers) for n in OUTPUTS] + ["log_w2"]


def _rgb(v):
    v = np.asarray(v, dtype=np.float64).reshape(-1)
    return np.repeat(v, 3) if v.size == 1 else v


def folded(w):
    """omega_p normalised and folded onto the upper hemisphere (the datasets' z >= 0; at
    z = 0, y > 0, then x > 0): omega_p and -omega_p are the same medium (Eq. 7)."""
    w = np.asarray(w, dtype=np.float64)
    w = w / np.linalg.norm(w)
    x, y, z = w
    return -w if z < 0 or (z == 0 and (y < 0 or (y == 0 and x < 0))) else w


def features(layers):
    """The raw (unstandardised) input vector of one stack of torch_model.FlakeLayer."""
    out = []
    for l in layers:
        out += [math.log(l.alpha), *_rgb(l.albedo), math.log(l.thickness * l.density), *_rgb(l.f0),
                float(bool(l.fiber)), *folded(l.orientation)]
    return out


def lobes_for(x, layers, split=(1.0, 1.0), normalise=True):
    """fit.lobes_from_vector of the network's outputs x (..., 8 L + 1) for `layers` (fields
    broadcasting against "...", e.g. batch_layers): T' is the modified layer's optical
    thickness, so its thickness is T'/rho with the layer's own density (module docstring)."""
    lobes = fit.lobes_from_vector(x, len(layers), split, normalise)
    lobes.thickness = [t / tm.as_tensor(l.density) for t, l in zip(lobes.thickness, layers)]
    return lobes


def batch_layers(stacks):
    """A list of stacks (each a list of FlakeLayer) as one stack of FlakeLayers whose fields
    have a leading batch axis (B, 1[, 3]), to broadcast against (cells, 3) directions."""
    def field(k, name, rgb=False):
        v = [_rgb(getattr(s[k], name)) if rgb else getattr(s[k], name) for s in stacks]
        t = torch.as_tensor(np.asarray(v, dtype=np.float64), dtype=tm.DTYPE)
        return t[:, None, :] if t.dim() == 2 else t[:, None]
    return [tm.FlakeLayer(fiber=field(k, "fiber").bool(), alpha=field(k, "alpha"), thickness=field(k, "thickness"),
                          albedo=field(k, "albedo", True), f0=field(k, "f0", True),
                          orientation=field(k, "orientation"), density=field(k, "density"))
            for k in range(len(stacks[0]))]


class Mapping(torch.nn.Module):
    """features (B, 12 L) -> fit.lobes_from_vector vectors (B, 8 L + 1)."""

    def __init__(self, n_layers, mean, std):
        super().__init__()
        self.n_layers = n_layers
        sizes = (12 * n_layers,) + HIDDEN + (8 * n_layers + 1,)
        self.linear = torch.nn.ModuleList(torch.nn.Linear(a, b, dtype=tm.DTYPE) for a, b in zip(sizes[:-1], sizes[1:]))
        self.register_buffer("mean", torch.as_tensor(mean, dtype=tm.DTYPE))
        self.register_buffer("std", torch.as_tensor(std, dtype=tm.DTYPE))
        with torch.no_grad():
            start = ([0.0, 0.0] + [math.log(0.3)] * 3 + [0.0] * 3) * n_layers + [math.log(0.05)]
            self.linear[-1].bias.copy_(torch.as_tensor(start, dtype=tm.DTYPE))

    def forward(self, x):
        h = (x - self.mean) / self.std
        for k, lin in enumerate(self.linear):
            h = lin(h)
            if k + 1 < len(self.linear):
                h = torch.relu(h)
        return h

    def lobes(self, stacks, split=(1.0, 1.0)):
        """Lobes (fields (B, 1[, 3])) for a list of stacks; normalised (W1 = max W1 gamma')."""
        x = self(torch.as_tensor(np.asarray([features(s) for s in stacks]), dtype=tm.DTYPE))
        return lobes_for(x[:, None, :], batch_layers(stacks), split)


def save(path, net, attrs, history, validation_index):
    with files.atomic_output(path) as tmp, h5py.File(tmp, "w") as f:
        f.attrs["mcref_format"] = FORMAT
        f.attrs["format_version"] = 1
        f.attrs["layers"] = net.n_layers
        f.attrs["hidden"] = list(HIDDEN)
        f.attrs["activation"] = "relu"
        f.attrs["inputs"] = input_names(net.n_layers)
        f.attrs["outputs"] = output_names(net.n_layers)
        f.attrs["alpha_range"] = list(fit.ALPHA_RANGE)
        f.attrs["thickness_range"] = list(fit.THICKNESS_RANGE)
        for k, v in attrs.items():
            f.attrs[k] = v
        f["input_mean"] = net.mean.numpy()
        f["input_std"] = net.std.numpy()
        for j, lin in enumerate(net.linear):
            f[f"linear{j}/weight"] = lin.weight.detach().numpy()
            f[f"linear{j}/bias"] = lin.bias.detach().numpy()
        for k, v in history.items():
            f[f"history/{k}"] = np.asarray(v, dtype=np.float64)
        f["validation_index"] = np.asarray(validation_index, dtype=np.int64)


def load(path):
    """(Mapping, attributes) from a weights file; errors name the file and what is wrong."""
    with files.open_hdf5(path) as f:
        if f.attrs.get("mcref_format") != FORMAT:
            raise ValueError(f"{path}: not a network weights file (mcref_format = {FORMAT!r} expected)")
        if int(f.attrs["format_version"]) != 1 or list(f.attrs["hidden"]) != list(HIDDEN):
            raise ValueError(f"{path}: format_version {f.attrs['format_version']}, hidden {list(f.attrs['hidden'])} "
                             f"(this script reads version 1, hidden {list(HIDDEN)})")
        net = Mapping(int(f.attrs["layers"]), f["input_mean"][:], f["input_std"][:])
        with torch.no_grad():
            for j, lin in enumerate(net.linear):
                lin.weight.copy_(torch.as_tensor(f[f"linear{j}/weight"][:]))
                lin.bias.copy_(torch.as_tensor(f[f"linear{j}/bias"][:]))
        attrs = dict(f.attrs)
    return net, attrs
