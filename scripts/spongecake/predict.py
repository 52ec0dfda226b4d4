#!/usr/bin/python3
"""SpongeCake's multiple-scattering lobes for new layer parameters (Wang et al. 2022,
Sec. 5), from a trained network (train.py): reads the stack of an experiment file
(geometry.layer, as mcref's slab experiments; no substrate) and prints the lobe
parameters as JSON: per layer alpha', T', gamma' (RGB), f0' (RGB), and W1, W2, the
Lambertian split. Evaluate the lobes with torch_model.multiple_scattering_lobes or
mcref.sggx.spongecake_ms_bsdf.

  /usr/bin/python3 scripts/spongecake/predict.py NET.h5 EXPERIMENT.toml
"""
import argparse
import json
import os
import sys

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from spongecake import dataset, network  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("weights", help="network weights (train.py)")
    p.add_argument("experiment", help="experiment file whose geometry.layer is the stack")
    a = p.parse_args(argv)
    try:
        net, attrs = network.load(a.weights)
        with open(a.experiment) as f:
            layers = dataset.layers_from_config(f.read(), a.experiment)
        if len(layers) != net.n_layers:
            raise ValueError(f"{a.experiment}: geometry.layer has {len(layers)} layers; the network of {a.weights} "
                             f"takes {net.n_layers}")
    except (OSError, KeyError, ValueError) as e:
        print(f"predict: {e}", file=sys.stderr)
        return 2
    split = tuple(float(v) for v in attrs["split"])
    lobes = net.lobes([layers], split)
    flat = lambda t: [float(v) for v in t.reshape(-1)]  # noqa: E731
    print(json.dumps({"alpha": [flat(v)[0] for v in lobes.alpha], "thickness": [flat(v)[0] for v in lobes.thickness],
                      "albedo": [flat(v) for v in lobes.albedo], "f0": [flat(v) for v in lobes.f0],
                      "w1": flat(lobes.w1)[0], "w2": flat(lobes.w2)[0], "split": list(split)}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
