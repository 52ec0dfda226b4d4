# mcref.judge: a table against a model's values, as `mcref validate` judges;
# Table.batch_values, kept by simulate(..., keep_batch_values=True).
import numpy as np
import pytest

import mcref

# 16 field realizations (batches): the sign-flip test enumerates every pattern.
TAU_PLUS = {
    "geometry": {"kind": "micrograin", "tau0": 0.3, "beta": 0.8, "tile": 40},
    "run": {"seed": 11, "batches": 16},
    "measure": [{"quantity": "tau_plus", "theta_i_deg": [0, 30, 60, 80], "samples": 4000}],
}


@pytest.fixture(scope="module")
def kept():
    return mcref.simulate(TAU_PLUS, keep_batch_values=True)["tau_plus"]


def test_batch_values_are_the_batches(kept):
    bv = kept.batch_values
    assert bv.shape == (16,) + tuple(kept.shape)
    total = np.zeros(kept.shape)
    for b in range(16):  # in batch order, as the sums were made: the same bits
        total = total + bv[b]
    assert np.array_equal(total, kept.sum)
    plain = mcref.simulate(TAU_PLUS)["tau_plus"]
    assert plain.batch_values is None
    assert np.array_equal(plain.sum, kept.sum) and np.array_equal(plain.sum_sq, kept.sum_sq)


def test_batch_values_survive_a_file(kept, tmp_path):
    mcref.write_tables(tmp_path / "t.h5", [kept])
    back = mcref.read_tables(tmp_path / "t.h5")["tau_plus"]
    assert np.array_equal(back.batch_values, kept.batch_values)


# The exact Eq. 22 against the simulation (seed 11): its verdict, the test used,
# and the model moved by 6 standard errors failing. The cells share the 16 fields, so the sign-flip
# test is used, and the chi2 that takes them as independent is available too.
def test_judge_exact_model(kept):
    model = mcref.evaluate_model("tau_plus_eq22", kept, TAU_PLUS)
    v = mcref.judge(kept, model)
    assert v["joint_test"] == "sign-flip"
    assert v["status"] == "pass", v["reason"]
    assert v["cells"] == 4 and v["z"].shape == tuple(kept.shape)
    assert 1 <= v["effective_dof"] <= 4
    w = mcref.judge(kept, model, use_batch_values=False)
    assert w["joint_test"] == "independent" and w["effective_dof"] == 4
    assert np.array_equal(w["z"], v["z"])
    # Moved by 6 median relative standard errors (8.4 % here, not the 20 % it was): FAIL. The 4
    # cells share the 16 fields (1.3 independent cells' worth), so a common shift weighs as one
    # cell: 4 standard errors give p = 0.002, 6 give 1.5e-4 (Student t, 15 degrees of freedom).
    moved = 6 * np.median(kept.stderr / np.abs(kept.value))
    off = mcref.judge(kept, model * (1 + moved))
    assert off["status"] == "FAIL", (moved, off["reason"])
    # Below the sign-flip test's smallest p (its batches allow no less), Box decides, and says so.
    low = mcref.judge(kept, model, significance=1e-9)
    assert low["joint_test"] == "Box" and "Box" in low["reason"], low
    measured = mcref.judge(kept, model, exact=False)
    assert measured["status"] == "measured"
    assert mcref.judge(kept, model, exact=False, tolerance=0.5)["status"] == "pass"


def test_judge_bad_arguments(kept):
    model = mcref.evaluate_model("tau_plus_eq22", kept, TAU_PLUS)
    with pytest.raises(mcref.ConfigError, match="significance"):
        mcref.judge(kept, model, significance=0)
    with pytest.raises(mcref.ConfigError, match="tolerance"):
        mcref.judge(kept, model, tolerance=-1)
    with pytest.raises(mcref.ConfigError, match="model.*shape"):
        mcref.judge(kept, model[:2])
    with pytest.raises(mcref.ConfigError, match="model_stderr.*shape"):
        mcref.judge(kept, model, model_stderr=np.ones(3))
    # A negative or NaN model error (a negative one passed a model 3x off).
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(mcref.ConfigError, match="model_stderr.*allowed"):
            mcref.judge(kept, model * 3, model_stderr=np.full(model.shape, bad))


def test_batch_values_in_xarray(kept):
    xr = pytest.importorskip("xarray")
    ds = kept.to_xarray()
    assert ds["batch_values"].dims == ("batch",) + tuple(kept.axis_names)
    assert np.array_equal(ds["batch_values"].values, kept.batch_values)
    assert list(ds["batch"].values) == list(range(16))
