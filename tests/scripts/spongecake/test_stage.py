# scripts/spongecake/stage.py (run.sh's SpongeCake stage) end to end on a tiny stage
# file: a network set (the tiny 10-entry dataset of test_pipeline.py, 3 epochs) and a
# materials set (2 explicit stacks the network never saw). Checks summary.json (scale,
# one row per entry, distributions, figures), that a second run finds every step up to
# date and writes the same rows, that a changed setting reruns only what depends on it,
# and the rejection of a bad stage file (one line, exit 2, nothing created).
import json
import os
import subprocess

import pytest

from test_pipeline import BINARY, DATASET, run, tiny_dir

MATERIALS = """
[dataset]
experiment = "base.toml"
seed = 3
tables = ["brdf", "brdf_btdf", "brdf_order1_volume", "brdf_btdf_order1_volume"]
[[parameter]]
key = "geometry.layer"
values = [
  [{ phase = "sggx_surface", alpha = 0.4, thickness = 1.0, albedo = 0.9 }],
  [{ phase = "sggx_fiber", alpha = 0.6, thickness = 3.0, albedo = [0.9, 0.5, 0.2], orientation = [1.0, 0.0, 0.0] }],
]
"""
STAGE = """
seed = 2
[[network]]
name = "net"
dataset = "tiny.toml"
epochs = {epochs}
cells = 64
starts = 1
iterations = 5
[[materials]]
name = "paper"
dataset = "materials.toml"
network = "net"
starts = 1
iterations = 5
labels = ["first", "second"]
figure = "Fig. X"
"""


def stage(*args):
    return run("stage.py", *map(str, args))


@pytest.fixture(scope="module")
def tiny_stage(tmp_path_factory):
    d = tiny_dir(tmp_path_factory, "stage")
    (d / "materials.toml").write_text(MATERIALS)
    (d / "stage.toml").write_text(STAGE.format(epochs=3))
    p = stage(d / "stage.toml", d / "out", "--mcref", BINARY, "--threads", 2, "--jobs", 2, "--quiet")
    assert p.returncode == 0, p.stderr
    return d, p


def summary(d):
    with open(d / "out" / "summary.json") as f:
        return json.load(f)


def test_summary(tiny_stage):
    d, p = tiny_stage
    assert p.stderr.count("\n") == 1 and "spongecake stage: 2 sets (net, paper)" in p.stderr  # --quiet: one line
    s = summary(d)
    assert s["format"] == "mcref-spongecake-summary" and s["seed"] == 2
    net, paper = s["sets"]
    assert net["kind"] == "network" and paper["kind"] == "materials" and paper["network"] == "net"
    assert net["scale"] == dict(net["scale"], entries=10, incident_directions=[2, 2], outgoing_bins=[4, 4],
                                paths_per_direction=4000, max_order=20, fitted_entries=1, fit_starts=1,
                                fit_iterations=5, epochs=3, cells_per_batch=64, batch=32, train_entries=9, seed=2)
    assert [r["entry"] for r in net["rows"]] == [9]  # the held-out entry
    assert [(r["entry"], r["label"]) for r in paper["rows"]] == [(0, "first"), (1, "second")]
    assert paper["layers"] == 1 and paper["figure"] == "Fig. X"
    for row in net["rows"] + paper["rows"]:
        for m in ("network", "fit", "lambert", "none", "noise", "sscheck"):
            assert row[f"{m}_ms"] is None or row[f"{m}_ms"] >= 0
        assert row["none_ms"] == 1.0 and row["fit_ms"] <= row["lambert_ms"] + 1e-9
    assert paper["distribution"]["fit"]["ms"][2] == max(r["fit_ms"] for r in paper["rows"])
    for t in (net, paper):
        for f in t["figures"]:
            assert (d / "out" / f).stat().st_size > 0


def test_second_run_is_up_to_date_and_a_change_reruns_what_depends_on_it(tiny_stage):
    d, _ = tiny_stage
    first = summary(d)
    p = stage(d / "stage.toml", d / "out", "--mcref", BINARY, "--threads", 2)
    assert p.returncode == 0, p.stderr
    assert "0 steps run, 7 up to date" in p.stderr and "net fits: up to date" in p.stderr
    again = summary(d)
    assert [t["rows"] for t in again["sets"]] == [t["rows"] for t in first["sets"]]
    (d / "stage2.toml").write_text(STAGE.format(epochs=4))
    p = stage(d / "stage2.toml", d / "out", "--mcref", BINARY, "--threads", 2)
    assert p.returncode == 0, p.stderr
    # the network and both figure steps depend on the epochs; the fits do not
    assert "3 steps run, 4 up to date" in p.stderr and "net network: running" in p.stderr
    assert summary(d)["sets"][0]["scale"]["epochs"] == 4


NET = "[[network]]\nname = 'a'\ndataset = 'tiny.toml'\nepochs = 1\n"
MAT = "[[materials]]\nname = 'b'\ndataset = 'materials.toml'\nnetwork = 'a'\n"


# The checks of the whole stage file and of its datasets before anything runs: a TOML
# type that is not a table array gave a traceback; a dataset with no held-out entries,
# a materials set on its network's own dataset and a cells count the weights file cannot
# store failed after simulating, fitting or training; labels of the wrong count passed.
@pytest.mark.parametrize("text, message", [
    ("seed = -1\n", "seed = -1"),
    ("network = 3\n", "network = 3 (allowed: tables [[network]])"),
    ("network = [1]\n", "network = [1] (allowed: tables [[network]])"),
    ("materials = 'x'\n" + NET, "materials = 'x' (allowed: tables [[materials]])"),
    (NET.replace("tiny.toml", "few.toml"), "network.0.dataset"),
    (NET.replace("tiny.toml", "few.toml"), "9 entries (allowed: at least 10"),
    (NET + MAT.replace("materials.toml", "tiny.toml"), "materials.0.dataset"),
    (NET + MAT.replace("materials.toml", "tiny.toml"), "the dataset of its network 'a'"),
    (NET + MAT.replace("materials.toml", "copy.toml"), "the dataset of its network 'a'"),
    (NET + MAT + "labels = ['x']\n", "materials.0.labels: 1 labels (allowed: one per entry"),
    (NET + MAT + "labels = [1, 2]\n", "materials.0.labels = [1, 2]: expected strings"),
    (NET + "cells = 100000000000000000000\n", "network.0.cells = 100000000000000000000: allowed <= 2^63 - 1"),
    (NET.replace("tiny.toml", "badrange.toml"), "network.0.dataset"),
    (NET.replace("tiny.toml", "badrange.toml"), "geometry.layer.0.alpha"),
    ("[[network]]\nname = 'a'\ndataset = 'tiny.toml'\n", "network.0.epochs: required"),
    ("[[network]]\nname = 'a'\ndataset = 'missing.toml'\nepochs = 1\n", "no such file"),
    ("[[network]]\nname = 'a'\ndataset = 'tiny.toml'\nepochs = 0\n", "network.0.epochs = 0: allowed >= 1"),
    ("[[network]]\nname = 'a'\ndataset = 'tiny.toml'\nepochs = 1\nfit = 'some'\n", "network.0.fit = 'some'"),
    ("[[network]]\nname = 'a'\ndataset = 'tiny.toml'\nepochs = 1\n[[materials]]\nname = 'b'\n"
     "dataset = 'tiny.toml'\nnetwork = 'c'\n", "materials.0.network = 'c'"),
])
def test_bad_stage_file(tiny_stage, tmp_path, text, message):
    d, _ = tiny_stage
    (d / "few.toml").write_text(DATASET.replace("entries = 10", "entries = 9"))
    (d / "copy.toml").write_text(DATASET)
    (d / "badrange.toml").write_text(DATASET.replace("range = [0.2, 1.0]", "range = [-0.2, 1.0]"))
    bad = d / "bad.toml"
    bad.write_text(text)
    p = stage(bad, tmp_path / "out", "--mcref", BINARY)
    assert p.returncode == 2 and message in p.stderr and "bad.toml" in p.stderr, p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and not (tmp_path / "out").exists()


def test_stale_parts_are_replaced_and_other_errors_leave_files_alone(tmp_path_factory):
    # Parts of another dataset (its TOML changed after an interrupted run) made the
    # stage fail; any error with "exists and" in it made it delete the output.
    from spongecake.stage import Stage, StageError
    d = tiny_dir(tmp_path_factory, "stale")
    out = d / "out"
    out.mkdir()
    (d / "other.toml").write_text((d / "tiny.toml").read_text().replace("seed = ", "seed = 9"))
    subprocess.run([BINARY, "dataset", str(d / "other.toml"), "-o", str(out / "x.h5"), "--stop-after", "1", "--quiet"],
                   check=True)
    s = Stage(str(out), BINARY, 1, 1, True)
    s.dataset("x", str(d / "tiny.toml"))
    assert (out / "x.h5").exists() and not (out / "x.h5.parts").exists()
    # A file where the parts directory goes: mcref's error is raised, the output left alone.
    os.remove(out / "x.h5")
    (out / "x.h5.parts").write_text("not a directory")
    with pytest.raises(StageError):
        s.dataset("x", str(d / "tiny.toml"))
    assert (out / "x.h5.parts").read_text() == "not a directory"


def test_each_step_is_recorded_as_it_finishes(tmp_path):
    # stage.json was written at the end of each phase only: a stage interrupted (Ctrl-C,
    # SIGTERM) after a network had finished trained it again. Now each step is recorded
    # at once, also when the steps of a phase finish on several threads.
    import concurrent.futures
    import sys

    from spongecake.stage import Stage
    s = Stage(str(tmp_path), BINARY or "mcref", 1, 2, True)

    def cmd(k):
        return [sys.executable, "-c", f"open({str(tmp_path / f'{k}.txt')!r}, 'w').write('{k}')"]

    def step(k):
        s.cached(f"step {k}", cmd(k), [], [str(tmp_path / f"{k}.txt")])
        with open(tmp_path / "stage.json") as f:
            assert f"step {k}" in json.load(f)  # on disk before the phase ends

    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        list(pool.map(step, range(8)))
    with open(tmp_path / "stage.json") as f:
        assert sorted(json.load(f)) == sorted(f"step {k}" for k in range(8))
    again = Stage(str(tmp_path), BINARY or "mcref", 1, 2, True)  # a new run finds them up to date
    assert all(again.cached(f"step {k}", cmd(k), [], [str(tmp_path / f"{k}.txt")]) == ("", False) for k in range(8))
