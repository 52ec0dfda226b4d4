# Bad arguments to the module raise a Python exception naming what is wrong,
# never crash the interpreter or give numbers from garbage (an outside audit
# found each of these: segfaults, a silent wrong layout, a lost Ctrl-C). The
# crashes are run in a child interpreter, so that a regression fails the test
# instead of killing pytest.
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import mcref

SGGX = mcref.sggx.Sggx.surface_like(0.3)
CFG = {"geometry": {"kind": "micrograin", "tau0": 0.5, "beta": 1.0, "tile": 40},
       "measure": [{"quantity": "tau_plus", "theta_i_deg": [0, 40], "samples": 100}]}


def child(code):
    """Runs `code` in a fresh interpreter with this one's module path; returns (exit code, stdout, stderr)."""
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120,
                       env=dict(os.environ))
    return p.returncode, p.stdout, p.stderr


@pytest.mark.parametrize("call", [
    "mcref.sggx.ndf(mcref.sggx.Sggx.surface_like(0.3), 'abc', 0.0)",
    "mcref.sggx.ndf(mcref.sggx.Sggx.surface_like(0.3), [0.1, 'x'], 0.0)",
    "mcref.lambert_sphere.deon_brdf(0.5, 'a', 0.5, 0.0)",
    "mcref.lambert_sphere.deon_brdf(0.5, {}, 0.5, 0.0)",
    "mcref.radiative_transfer.h_isotropic_table(0.5, 'abc')",
])
def test_non_numbers_are_a_type_error(call):
    code, out, err = child(f"""
        import mcref
        try:
            {call}
        except TypeError as e:
            print('TypeError:', e)
        """)
    assert code == 0, f"exit {code}: {err}"
    assert "TypeError: expected a number or an array of numbers" in out


@pytest.mark.parametrize("call, key", [
    ("mcref.samplers.micrograin_vndf(1.5, 1, 1, 0.3, 0, seed=1, n=3)", "tau0"),
    ("mcref.samplers.micrograin_vndf(0.5, 1, 1, float('nan'), 0, seed=1, n=3)", "theta_i"),
    ("mcref.samplers.micrograin_vndf(0.5, -1, 1, 0.3, 0, seed=1, n=3)", "beta_x"),
    ("mcref.samplers.micrograin_ndf(0.0, 1, 1, seed=1, n=3)", "tau0"),
    ("mcref.samplers.lambert_sphere_phase((0, 0, 0), seed=1, n=3)", "propagation"),
])
def test_sampler_parameters_out_of_range_are_refused(call, key):
    code, out, err = child(f"""
        import mcref
        try:
            {call}
        except mcref.ConfigError as e:
            print('ConfigError:', e)
        """)
    assert code == 0, f"exit {code}: {err}"
    assert f"ConfigError: <python>: key '{key}'" in out


def test_uniforms_and_a_seed_are_not_both_taken():
    with pytest.raises(mcref.ConfigError, match="either uniforms u or a seed"):
        mcref.samplers.micrograin_ndf(0.5, 1, 1, u=np.full((2, 2), 0.5), seed=1, n=50)


@pytest.mark.parametrize("seed", [-1, 1.5, True, 2**64, "1"])
def test_sampler_seeds_must_be_integers_in_range(seed):
    with pytest.raises(mcref.ConfigError, match=r"key 'seed'.*must be an integer in \[0, 18446744073709551615\]"):
        mcref.samplers.micrograin_ndf(0.5, 1, 1, seed=seed, n=3)
    a = mcref.samplers.micrograin_ndf(0.5, 1, 1, seed=np.int64(3), n=3)[0]
    assert np.array_equal(a, mcref.samplers.micrograin_ndf(0.5, 1, 1, seed=3, n=3)[0])


@pytest.mark.parametrize("seed", [-1, 1.0, 2**63, 2**64])
def test_simulate_seeds_must_be_integers_in_range(seed):
    with pytest.raises(mcref.ConfigError, match=r"key 'seed'.*must be an integer in \[0, 9223372036854775807\]"):
        mcref.simulate(CFG, seed=seed)


def test_a_dict_integer_beyond_64_bits_names_its_key():
    with pytest.raises(mcref.ConfigError, match=r"^<dict>: key 'run.seed': = 1180591620717411303424 is out of range"):
        mcref.simulate(dict(CFG, run={"seed": 2**70}))


def test_argument_values_are_shown_with_every_digit():
    with pytest.raises(mcref.ConfigError, match=r"key 'c': = 1.0000001 is out of range; allowed \[0, 1\]"):
        mcref.lambert_sphere.deon_brdf(1.0000001, 0.5, 0.5, 0.0)


def test_evaluate_model_refuses_a_table_laid_out_otherwise():
    real = mcref.simulate(CFG, seed=1, threads=1)["tau_plus"]
    theta, phi = real.axis("theta_i"), real.axis("phi_i")
    points = lambda name, unit, v: mcref.Axis.points(name, unit, list(v))
    bad = {
        # One axis fewer (this crashed the interpreter).
        "fewer axes": [points("theta_i", "rad", theta.centres)],
        # The axes swapped: read by position, they gave other numbers silently.
        "swapped": [points("phi_i", "rad", phi.centres), points("theta_i", "rad", theta.centres)],
        # Degrees: read as radians, silently.
        "degrees": [points("theta_i", "deg", np.degrees(theta.centres)), points("phi_i", "rad", phi.centres)],
    }
    for label, axes in bad.items():
        shape = tuple(len(a.centres) for a in axes)
        code, out, err = child(f"""
            import mcref, numpy as np
            axes = [mcref.Axis.points(n, u, v) for n, u, v in {[(a.name, a.unit, list(a.centres)) for a in axes]!r}]
            t = mcref.Table("tau_plus", "tau_plus", axes, np.ones({shape}), np.ones({shape}), batches=2)
            try:
                mcref.evaluate_model("tau_plus_eq22", t, {CFG!r})
            except mcref.ConfigError as e:
                print("ConfigError:", e)
            """)
        assert code == 0, f"{label}: exit {code}: {err}"
        assert "key 'table': table \"tau_plus\" is tau_plus over" in out, f"{label}: {out}"
        assert "the experiment's is tau_plus over (theta_i points in rad, phi_i points in rad)" in out, f"{label}: {out}"
    # The same layout with other values is evaluated, as the simulated table is.
    same = mcref.Table("tau_plus", "tau_plus", [points("theta_i", "rad", [0.1, 0.5]), points("phi_i", "rad", [0.0])],
                       np.ones((2, 1)), np.ones((2, 1)), batches=2)
    assert np.allclose(mcref.evaluate_model("tau_plus_eq22", same, CFG)[:, 0],
                       mcref.micrograin.tau_plus_eq22(0.5, 1.0, np.array([0.1, 0.5])), rtol=1e-12, atol=0)


@pytest.mark.parametrize("edges", [[0, float("nan"), 2], [2, 1, 0], [0, 1, 1], [0, float("inf")]])
def test_bin_edges_must_be_finite_and_increasing(edges):
    # Before, such an axis was written, and the file then called damaged by read_tables and `mcref info`.
    with pytest.raises(ValueError, match="bin edges must be finite and increasing"):
        mcref.Axis.bins("theta_i", "rad", edges)


def test_ctrl_c_after_a_write_is_a_keyboard_interrupt(tmp_path):
    # The first write used to install the CLI's handlers for SIGINT and SIGTERM
    # (remove the temporaries, then die): Ctrl-C then killed the interpreter,
    # and a user's own SIGTERM handler was replaced.
    code, out, err = child(f"""
        import mcref, os, signal, time
        got = []
        signal.signal(signal.SIGTERM, lambda s, f: got.append(s))
        mcref.write_tables({str(tmp_path / 'x.h5')!r}, mcref.simulate({CFG!r}, seed=2, threads=1))
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.2)
        print('SIGTERM handled' if got else 'SIGTERM not handled')
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        except KeyboardInterrupt:
            print('KeyboardInterrupt')
        """)
    assert code == 0, f"exit {code} (signal {-code if code < 0 else 0}): {err}"
    assert out.split() == ["SIGTERM", "handled", "KeyboardInterrupt"], out
    assert sorted(os.listdir(tmp_path)) == ["x.h5"]
