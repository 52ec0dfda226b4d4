#!/usr/bin/python3
"""SpongeCake's multiple-scattering lobes for new layer parameters (Wang et al. 2022,
Sec. 5), from a trained network (train.py): reads the stack of an experiment file
(geometry.layer, as mcref's slab experiments; homogeneous SGGX layers, no substrate)
and prints the lobe parameters as JSON: per layer alpha', T', gamma' (RGB), f0' (RGB),
and W1, W2, the Lambertian split. T' ("thickness") is the thickness of the modified
layer at the layer's own density, as torch_model.multiple_scattering_lobes and
mcref.sggx.spongecake_ms_bsdf apply it; "optical_thickness" is T' rho, what the network
predicts (network.py): a layer given as (T, rho) or as (T/c, c rho) is the same medium
and gets the same BSDF. Keys the lobes cannot represent (density_vdb, depth profiles,
other phase functions, a substrate) are refused, naming the key. So is a layer whose
alpha or optical thickness T rho lies outside the range of the network's training entries
(the weights file's train_alpha_range and train_optical_thickness_range, per layer; files
written before train.py stored them are not checked): the network would extrapolate.
--extrapolate predicts anyway.

  /usr/bin/python3 scripts/spongecake/predict.py NET.h5 EXPERIMENT.toml [--extrapolate]
"""
import argparse
import json
import os
import sys

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from spongecake import dataset, network  # noqa: E402

RANGES = (("train_alpha_range", "alpha", lambda l: l.alpha),
          ("train_optical_thickness_range", "T rho (optical thickness)", lambda l: l.thickness * l.density))


def check_training_range(layers, attrs, experiment, weights):
    """Refuses a layer outside the ranges the network was trained on (attributes RANGES of the
    weights file, [L, 2] each; absent in older files: not checked), naming the layer and value."""
    for attr, name, value in RANGES:
        if attr not in attrs:
            continue
        for k, (l, (lo, hi)) in enumerate(zip(layers, [tuple(map(float, r)) for r in attrs[attr]])):
            v = value(l)
            if not lo <= v <= hi:
                raise ValueError(f"{experiment}: geometry.layer.{k} {name} = {v:.6g} (allowed: [{lo:.6g}, {hi:.6g}], "
                                 f"the range of the training entries of {weights}; --extrapolate predicts anyway)")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("weights", help="network weights (train.py)")
    p.add_argument("experiment", help="experiment file whose geometry.layer is the stack")
    p.add_argument("--extrapolate", action="store_true",
                   help="predict for alpha or T rho outside the training entries' ranges")
    a = p.parse_args(argv)
    try:
        net, attrs = network.load(a.weights)
        try:
            with open(a.experiment, "rb") as f:
                text = f.read().decode()
        except UnicodeDecodeError as e:
            raise ValueError(f"{a.experiment}: not a UTF-8 text file ({e})") from None
        layers = dataset.layers_from_config(text, a.experiment, for_network=True)
        if len(layers) != net.n_layers:
            raise ValueError(f"{a.experiment}: geometry.layer has {len(layers)} layers; the network of {a.weights} "
                             f"takes {net.n_layers}")
        if not a.extrapolate:
            check_training_range(layers, attrs, a.experiment, a.weights)
    except (OSError, KeyError, ValueError) as e:
        print(f"predict: {e}", file=sys.stderr)
        return 2
    split = tuple(float(v) for v in attrs["split"])
    lobes = net.lobes([layers], split)
    flat = lambda t: [float(v) for v in t.reshape(-1)]  # noqa: E731
    thickness = [flat(v)[0] for v in lobes.thickness]
    print(json.dumps({"alpha": [flat(v)[0] for v in lobes.alpha], "thickness": thickness,
                      "optical_thickness": [t * l.density for t, l in zip(thickness, layers)],
                      "albedo": [flat(v) for v in lobes.albedo], "f0": [flat(v) for v in lobes.f0],
                      "w1": flat(lobes.w1)[0], "w2": flat(lobes.w2)[0], "split": list(split)}, indent=1,
                     allow_nan=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
