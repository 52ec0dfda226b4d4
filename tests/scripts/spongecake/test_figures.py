# figures.py's lobes at fixed incidence are drawn over each entry's own phi axis: mcref folds
# phi into [0, 180] deg for a stack with omega_p = z and keeps [0, 360] otherwise, and one
# dataset can hold both (validate/datasets/spongecake_paper_*.toml). They were drawn over
# [0, 360] always, so a folded entry's mirror lobe (phi = 180) showed at 270-360.
import os
import subprocess

import matplotlib.pyplot as plt
import numpy as np
import pytest
import torch

from spongecake import figures, network
from test_pipeline import BINARY, run, tiny_dir

MATERIALS = """
[dataset]
experiment = "base.toml"
seed = 3
tables = ["brdf", "brdf_btdf", "brdf_order1_volume", "brdf_btdf_order1_volume"]
[[parameter]]
key = "geometry.layer"
values = [
  [{ phase = "sggx_surface", alpha = 0.4, thickness = 1.0, albedo = 0.9, orientation = [0.0, 0.0, 1.0] }],
  [{ phase = "sggx_fiber", alpha = 0.6, thickness = 3.0, albedo = 0.9, orientation = [1.0, 0.0, 0.0] }],
]
"""


@pytest.fixture
def drawn(monkeypatch):
    """The figures figures.py closes, kept to be looked at."""
    kept = []
    monkeypatch.setattr(plt, "close", lambda fig=None: kept.append(fig))
    return kept


def extents(fig):
    """The phi range (degrees) of each row's lobe images."""
    return [tuple(ax.images[0].get_extent()[:2]) for ax in fig.axes if ax.images]


def test_lobes_use_each_entrys_phi_axis(tmp_path, drawn):
    n_ti, n_pi, n_to, n_ph = 2, 1, 2, 4
    cells = 2 * n_ti * n_pi * n_to * n_ph
    v = np.ones((cells, 3))
    theta_i = np.radians([30.0, 60.0])
    folded = ((n_ti, n_pi, n_to, n_ph), theta_i, np.linspace(0, np.pi, n_ph + 1))
    full = ((n_ti, n_pi, n_to, n_ph), theta_i, np.linspace(0, 2 * np.pi, n_ph + 1))
    figures.lobes_figure(str(tmp_path / "l.png"), [("a", v, v, v, v, folded), ("b", v, v, v, v, full)])
    assert os.path.getsize(tmp_path / "l.png") > 0 and os.listdir(tmp_path) == ["l.png"]
    assert extents(drawn[-1]) == [(0.0, 180.0)] * 4 + [(0.0, 360.0)] * 4


def test_figures_draws_a_folded_and_an_unfolded_entry_on_their_axes(tmp_path_factory, drawn):
    d = tiny_dir(tmp_path_factory, "figures")
    (d / "materials.toml").write_text(MATERIALS)
    data = d / "materials.h5"
    p = subprocess.run([BINARY, "dataset", str(d / "materials.toml"), "-o", str(data), "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    p = run("fit_dataset.py", str(data), "-o", str(d / "fits.h5"), "--starts", "1", "--iterations", "2", "--quiet")
    assert p.returncode == 0, p.stderr
    torch.manual_seed(5)  # a network of random weights, from no dataset: every entry is unseen
    network.save(str(d / "net.h5"), network.Mapping(1, torch.zeros(12), torch.ones(12)),
                 {"split": [1.0, 1.0], "dataset": "none", "dataset_sha256": "none"}, {"train_loss": [1.0]}, [])
    assert figures.main([str(data), str(d / "fits.h5"), str(d / "net.h5"), "-o", str(d), "--prefix", "m",
                         "--unseen", "--show", "all"]) == 0
    # the lobes figure: 4 panels per entry (each with a colour bar), entries 0 (omega_p = z) and 1
    lobes = [f for f in drawn if f is not None and sum(1 for ax in f.axes if ax.images) == 8
             and any("order 1 + network ms" in ax.get_title(loc="left") for ax in f.axes)]
    assert len(lobes) == 1
    assert extents(lobes[0]) == [(0.0, 180.0)] * 4 + [(0.0, 360.0)] * 4
