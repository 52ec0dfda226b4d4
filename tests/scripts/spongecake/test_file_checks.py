# The scripts' checks of their files before any work (scripts/spongecake/files.py): an output
# that is an input (also through a symbolic link or '..') or an existing directory, fits
# of another dataset or of another Lambertian split, a dataset's part file, a seed torch
# cannot take and a file that is not HDF5 are each refused in one line naming the file
# (exit 2), before any fit or training step, with no file written and the inputs as they
# were. On the tiny dataset of test_pipeline.py (10 entries, seed 7).
import os
import subprocess

import h5py
import pytest

from test_pipeline import BINARY, run, tiny_dir

SEED = "100000000000000000000"  # > 2^64 - 1: torch raised "Overflow when unpacking long"


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The tiny dataset, fits of entry 9 (split 1,1 and 1,0) and a 1-epoch network."""
    d = tiny_dir(tmp_path_factory, "checks")
    out = d / "tiny.h5"
    p = subprocess.run([BINARY, "dataset", str(d / "tiny.toml"), "-o", str(out), "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    for name, split in (("fits.h5", "1,1"), ("fits_r.h5", "1,0")):
        p = run("fit_dataset.py", str(out), "-o", str(d / name), "--entries", "9", "--starts", "1",
                "--iterations", "2", "--split", split, "--quiet")
        assert p.returncode == 0, p.stderr
    p = run("train.py", str(out), "-o", str(d / "net.h5"), "--epochs", "1", "--seed", "1", "--quiet")
    assert p.returncode == 0, p.stderr
    return d


def snapshot(d):
    """Every file under d with its bytes (the test's inputs must stay as they were)."""
    return {str(p.relative_to(d)): (p.read_bytes() if p.is_file() and not p.is_symlink() else None)
            for p in d.rglob("*")}


def refused(p, *words):
    """One line on stderr naming the words, exit 2, nothing on stdout (no work done)."""
    assert p.returncode == 2, p.stderr
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "Traceback" not in p.stderr and "epoch" not in p.stdout and "entry " not in p.stdout, p.stdout
    for w in words:
        assert w in p.stderr, (w, p.stderr)


def test_an_output_is_never_an_input(tiny):
    d = tiny
    (d / "sub").mkdir(exist_ok=True)
    for name, target in (("fits_link.h5", "fits.h5"), ("data_link.h5", "tiny.h5")):
        if not (d / name).is_symlink():
            (d / name).symlink_to(target)
    before = snapshot(d)
    data, fits, net = str(d / "tiny.h5"), str(d / "fits.h5"), str(d / "net.h5")
    # train.py -o its --fits: the same path, a symbolic link to it, a path through '..'
    for o in (fits, str(d / "fits_link.h5"), str(d / "sub" / ".." / "fits.h5")):
        refused(run("train.py", data, "-o", o, "--fits", fits, "--epochs", "1"), "--fits", "fits.h5")
    # fit_dataset.py -o its dataset through a link
    refused(run("fit_dataset.py", data, "-o", str(d / "data_link.h5"), "--entries", "9", "--starts", "1",
                "--iterations", "1"), "DATA.h5")
    # figures.py --summary or -o/--prefix onto one of its three inputs
    refused(run("figures.py", data, fits, net, "-o", str(d), "--summary", fits), "--summary", "FITS.h5")
    refused(run("figures.py", data, fits, net, "-o", str(d), "--summary", str(d / "sub" / ".." / "net.h5")),
            "NET.h5")
    os.symlink("fits.h5", d / "p_errors.png")
    try:
        refused(run("figures.py", data, fits, net, "-o", str(d), "--prefix", "p"), "p_errors.png", "FITS.h5")
    finally:
        os.unlink(d / "p_errors.png")
    assert snapshot(d) == before


def test_outputs_are_checked_before_any_work(tiny):
    d = tiny
    (d / "adir").mkdir(exist_ok=True)
    before = snapshot(d)
    data, fits, net = str(d / "tiny.h5"), str(d / "fits.h5"), str(d / "net.h5")
    refused(run("fit_dataset.py", data, "-o", str(d / "adir"), "--entries", "9", "--starts", "1", "--iterations", "1"),
            "-o", "adir", "directory")
    refused(run("train.py", data, "-o", str(d / "adir"), "--epochs", "1"), "-o", "adir", "directory")
    refused(run("figures.py", data, fits, net, "-o", str(d), "--prefix", "q", "--summary", str(d / "adir")),
            "--summary", "adir")
    # fits of another dataset: refused before training (it was checked after the weights were written)
    other = d / "other_fits.h5"
    other.write_bytes((d / "fits.h5").read_bytes())
    with h5py.File(other, "a") as f:
        f.attrs["dataset_sha256"] = "0" * 64
    refused(run("train.py", data, "-o", str(d / "never.h5"), "--epochs", "1", "--fits", str(other)),
            "other_fits.h5", "dataset_sha256")
    other.unlink()
    assert snapshot(d) == before  # no never.h5, no q_*.png, no *.tmp left behind


def test_the_lambertian_split_of_the_fits_must_be_the_networks(tiny):
    d = tiny
    before = snapshot(d)
    data, fits_r, net = str(d / "tiny.h5"), str(d / "fits_r.h5"), str(d / "net.h5")
    refused(run("train.py", data, "-o", str(d / "never.h5"), "--epochs", "1", "--fits", fits_r),
            "fits_r.h5", "split = 1,0", "1,1")
    refused(run("figures.py", data, fits_r, net, "-o", str(d), "--prefix", "r"), "fits_r.h5", "split = 1,0", "1,1")
    assert snapshot(d) == before
    p = run("train.py", data, "-o", str(d / "net_r.h5"), "--epochs", "1", "--fits", fits_r, "--split", "1,0", "--quiet")
    assert p.returncode == 0, p.stderr


def test_bad_inputs_are_named(tiny):
    d = tiny
    # a part of an unfinished dataset run (sums only): refused up front, not a KeyError in the fit loop
    part_dir = d / "part"
    part_dir.mkdir(exist_ok=True)
    p = subprocess.run([BINARY, "dataset", str(d / "tiny.toml"), "-o", str(part_dir / "p.h5"), "--stop-after", "1",
                        "--quiet", "--threads", "1"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    part = part_dir / "p.h5.parts" / "entry-0.h5"
    assert part.is_file()
    with h5py.File(part) as f:
        assert f.attrs["storage"] == "sums"
    before = snapshot(d)
    refused(run("fit_dataset.py", str(part), "-o", str(d / "never.h5")), "entry-0.h5", "storage = 'sums'", "merge")
    refused(run("train.py", str(part), "-o", str(d / "never.h5"), "--epochs", "1"), "entry-0.h5", "storage = 'sums'")
    # seeds torch cannot take
    data = str(d / "tiny.h5")
    refused(run("fit_dataset.py", data, "-o", str(d / "never.h5"), "--seed", SEED), "--seed", SEED, "2^64 - 1")
    refused(run("train.py", data, "-o", str(d / "never.h5"), "--seed", SEED), "--seed", SEED, "2^64 - 1")
    # a file that is not HDF5, as each script's input: its name is in the message
    text = str(d / "tiny.toml")
    refused(run("fit_dataset.py", text, "-o", str(d / "never.h5")), "tiny.toml")
    refused(run("train.py", text, "-o", str(d / "never.h5")), "tiny.toml")
    refused(run("train.py", data, "-o", str(d / "never.h5"), "--fits", text), "tiny.toml")
    refused(run("figures.py", data, text, str(d / "net.h5"), "-o", str(d), "--prefix", "t"), "tiny.toml")
    refused(run("predict.py", text, text), "tiny.toml")
    refused(run("fit_dataset.py", "--report", text), "tiny.toml")
    assert snapshot(d) == before


def test_stage_outputs_are_checked_against_its_inputs(tiny):
    # stage.py writes OUTDIR/summary.json (and removed an old one first): a stage file there was
    # deleted; an OUTDIR that is a file gave a traceback; a seed torch cannot take failed late.
    d = tiny
    out = d / "stage_out"
    out.mkdir(exist_ok=True)
    stage_file = out / "summary.json"
    stage_file.write_text('seed = 1\n[[network]]\nname = "net"\ndataset = "../tiny.toml"\nepochs = 1\n'
                          "starts = 1\niterations = 1\n")
    before = snapshot(d)
    refused(run("stage.py", str(stage_file), str(out), "--mcref", BINARY, "--quiet"), "summary.json", "STAGE.toml")
    refused(run("stage.py", str(stage_file), str(d / "tiny.toml"), "--mcref", BINARY, "--quiet"), "tiny.toml",
            "not a directory")
    (d / "seed.toml").write_text(stage_file.read_text().replace("seed = 1", f"seed = {SEED}").replace("../", ""))
    refused(run("stage.py", str(d / "seed.toml"), str(d / "never"), "--mcref", BINARY, "--quiet"), "seed", SEED)
    (d / "seed.toml").unlink()
    assert snapshot(d) == before


def test_repeated_entries_and_counts_the_weights_file_cannot_store_are_refused(tiny):
    # fit_dataset.py fitted an entry given twice twice; train.py took --cells (or --batch)
    # above 2^63 - 1, trained, and crashed writing the weights.
    d = tiny
    before = snapshot(d)
    data = str(d / "tiny.h5")
    refused(run("fit_dataset.py", data, "-o", str(d / "never.h5"), "--entries", "9,3,9", "--starts", "1",
                "--iterations", "1"), "--entries = '9,3,9'", "[9] given more than once")
    for key in ("--cells", "--batch"):
        refused(run("train.py", data, "-o", str(d / "never.h5"), "--epochs", "1", key, SEED), f"{key} = {SEED}",
                "[1, 2^63 - 1]")
    assert snapshot(d) == before


ESTIMATOR_DATASET = """
[dataset]
experiment = "base_nee.toml"
tables = ["brdf", "brdf_btdf", "brdf_order1_volume", "brdf_btdf_order1_volume"]
[[parameter]]
key = "geometry.layer.0.alpha"
values = [0.3, 0.5]
"""


def test_a_dataset_of_another_estimator_is_refused(tiny):
    # The noise column's standard error of total - order 1 holds for the analog estimator
    # only (each path leaves once); the reader took next-event datasets without a word.
    from test_pipeline import BASE
    d = tiny
    (d / "base_nee.toml").write_text(BASE.replace('kind = "slab"', 'kind = "slab"\nestimator = "next_event_mis"')
                                     .replace("samples = 2000", "samples = 200"))
    (d / "nee.toml").write_text(ESTIMATOR_DATASET)
    nee = d / "nee.h5"
    p = subprocess.run([BINARY, "dataset", str(d / "nee.toml"), "-o", str(nee), "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    before = snapshot(d)
    for script, extra in (("fit_dataset.py", ["--starts", "1", "--iterations", "1"]), ("train.py", ["--epochs", "1"])):
        refused(run(script, str(nee), "-o", str(d / "never.h5"), *extra), "nee.h5", "entry 0",
                "geometry.estimator = 'next_event_mis'", "allowed: 'analog'")
    assert snapshot(d) == before


def test_predict_refuses_stacks_outside_the_training_ranges(tiny):
    # predict.py extrapolated silently: net.h5 was trained on alpha in [0.2, 1] (sampled) and
    # T rho = 2 (tiny.toml); the weights file now holds those ranges per layer.
    from test_pipeline import BASE
    from spongecake import network, train
    d = tiny
    _, attrs = network.load(str(d / "net.h5"))
    indices, stacks, _, _ = train.check_dataset(str(d / "tiny.h5"))
    alphas = [s[0].alpha for i, s in zip(indices, stacks) if not train.is_validation(i)]
    assert attrs["train_alpha_range"].tolist() == [[min(alphas), max(alphas)]]
    assert attrs["train_optical_thickness_range"].tolist() == [[2.0, 2.0]]
    inside = BASE.replace("alpha = 0.5", f"alpha = {0.5 * (min(alphas) + max(alphas))}")
    cases = {"inside": inside, "alpha": inside.replace(f"alpha = {0.5 * (min(alphas) + max(alphas))}", "alpha = 0.1"),
             "rho": inside.replace("thickness = 2.0", "thickness = 2.0\ndensity = 1.5"),
             "tau": inside.replace("thickness = 2.0", "thickness = 4.0\noptical_thickness = 2.0")}
    for name, text in cases.items():
        (d / f"{name}.toml").write_text(text)
    weights = str(d / "net.h5")
    assert run("predict.py", weights, str(d / "inside.toml")).returncode == 0
    assert run("predict.py", weights, str(d / "tau.toml")).returncode == 0  # T rho = 2, the training value
    refused(run("predict.py", weights, str(d / "alpha.toml")), "alpha.toml", "geometry.layer.0 alpha = 0.1",
            f"[{min(alphas):.6g}, {max(alphas):.6g}]", "net.h5", "--extrapolate")
    refused(run("predict.py", weights, str(d / "rho.toml")), "rho.toml", "geometry.layer.0 T rho", "= 3 ",
            "[2, 2]")
    for name in ("alpha", "rho"):
        p = run("predict.py", weights, str(d / f"{name}.toml"), "--extrapolate")
        assert p.returncode == 0 and "alpha" in p.stdout, p.stderr
