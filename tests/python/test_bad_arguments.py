# Bad arguments to the module raise a Python exception naming what is wrong,
# never crash the interpreter or give numbers from garbage (an outside audit
# found each of these: segfaults, a silent wrong layout). The crashes are run
# in a child interpreter, so that a regression fails the test instead of
# killing pytest.
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
    # Incidence outside [0, pi/2] (it gave tau+ = -0.42 at 2 rad).
    for values in ([0.1, 2.0], [-1.0, 0.5]):
        far = mcref.Table("tau_plus", "tau_plus", [points("theta_i", "rad", values), points("phi_i", "rad", [0.0])],
                          np.ones((2, 1)), np.ones((2, 1)), batches=2)
        with pytest.raises(mcref.ConfigError, match=r"axis theta_i holds .* rad; allowed \[0, pi/2\]"):
            mcref.evaluate_model("tau_plus_eq22", far, CFG)


def test_an_axis_needs_a_point():
    # Before, a table over it had no cell, and was written and read back.
    with pytest.raises(ValueError, match="axis theta_i needs at least 1 point"):
        mcref.Axis.points("theta_i", "rad", [])


@pytest.mark.parametrize("edges", [[0, float("nan"), 2], [2, 1, 0], [0, 1, 1], [0, float("inf")]])
def test_bin_edges_must_be_finite_and_increasing(edges):
    # Before, such an axis was written, and the file then called damaged by read_tables and `mcref info`.
    with pytest.raises(ValueError, match="bin edges must be finite and increasing"):
        mcref.Axis.bins("theta_i", "rad", edges)


def test_names_the_file_cannot_hold_are_refused(tmp_path):
    # Before: "writing failed (HDF5 error creating group ...; disk full?)".
    edges = [0.0, 0.5, 1.0]
    table = lambda name, axes=("theta_i",): mcref.Table(
        name, "tau_plus", [mcref.Axis.bins(a, "rad", edges) for a in axes], np.ones((2,) * len(axes)),
        np.ones((2,) * len(axes)), batches=2)
    bad = {
        "a slash": ([table("a/b")], r"table name \"a/b\" must be non-empty"),
        "empty": ([table("")], r"table name \"\" must be non-empty"),
        "twice": ([table("t"), table("t")], r"two tables are named \"t\""),
        "an axis twice": ([table("t", ("theta_i", "theta_i"))], r"axis name \"theta_i\""),
        "an axis named sum": ([table("t", ("sum",))], r"axis name \"sum\""),
    }
    for label, (tables, message) in bad.items():
        with pytest.raises(mcref.ConfigError, match=message):
            mcref.write_tables(str(tmp_path / "x.h5"), tables, config="# none", seed=1)
        assert os.listdir(tmp_path) == [], label
    # Names with a NUL (cut short in the file), and notes under the layout's own attribute
    # names (an HDF5 "disk full?" error, or a file that would not read back: storage).
    noted = lambda attributes: mcref.Table("t", "tau_plus", [mcref.Axis.bins("theta_i", "rad", edges)], np.ones(2),
                                           np.ones(2), batches=2, attributes=attributes)
    for label, tables, message in [("a NUL", [table("a\0b")], "table name"),
                                   ("batches", [noted({"batches": "3"})], r"attribute \"batches\""),
                                   ("storage", [noted({"storage": "lean"})], r"attribute \"storage\""),
                                   ("a NUL in a note", [noted({"k\0q": "v"})], "attribute")]:
        with pytest.raises(mcref.ConfigError, match=message):
            mcref.write_tables(str(tmp_path / "x.h5"), tables, config="# none", seed=1)
        assert os.listdir(tmp_path) == [], label
    mcref.write_tables(str(tmp_path / "x.h5"), [table("t"), table("u", ("theta_i", "phi_i"))], config="# none", seed=1)
    assert mcref.read_tables(str(tmp_path / "x.h5")).names == ["t", "u"]


def test_whole_number_arguments_are_not_truncated():
    # Before: lambda_series(..., 4.7) was n = 4, n = -1 gave 0 (G1 = 1), h_exact(1.9, ...) was m = 1.
    with pytest.raises(mcref.ConfigError, match=r"key 'n': = 4.7 must be a whole number in \[0, 64\]"):
        mcref.micrograin.lambda_series(0.5, 1.0, 1.0, 4.7)
    with pytest.raises(mcref.ConfigError, match=r"key 'n': = -1 must be a whole number"):
        mcref.micrograin.lambda_series(0.5, 1.0, 1.0, -1)
    with pytest.raises(mcref.ConfigError, match=r"key 'm': = 1.9 must be a whole number in \[0, 2\]"):
        mcref.lambert_sphere.h_exact(1.9, 0.5, 0.5)
    assert mcref.micrograin.lambda_series(0.5, 1.0, 1.0, 4.0) == mcref.micrograin.lambda_series(0.5, 1.0, 1.0)
    assert mcref.lambert_sphere.h_exact(np.array([0, 1]), 0.5, 0.5).shape == (2,)


def test_factories_check_their_arguments_as_experiments_do():
    with pytest.raises(mcref.ConfigError, match=r"key 'wp': must be a finite, non-zero vector"):
        mcref.sggx.Sggx.surface_like(0.3, (0, 0, 0))
    with pytest.raises(mcref.ConfigError, match=r"key 'albedo': = 1.5 is out of range; allowed \[0, 1\]"):
        mcref.sggx.Layer.sggx(1.0, 1.0, SGGX, albedo=1.5)
    with pytest.raises(mcref.ConfigError, match=r"key 'albedo': = 1.5 is out of range"):
        mcref.sggx.Layer.isotropic(1.0, 1.0, albedo=1.5)
    with pytest.raises(mcref.ConfigError, match=r"key 'kd': = 2 is out of range; allowed \[0, 1\]"):
        mcref.micrograin.MicroSurface("lambertian", kd=2)
    with pytest.raises(mcref.ConfigError, match=r"key 'alpha': = -1 is out of range; allowed \(0, 4\]"):
        mcref.micrograin.MicroSurface("rough_conductor", alpha=-1)
    with pytest.raises(mcref.ConfigError, match=r"key 'quantity': \"nonsense\" is predicted by no model"):
        mcref.models("nonsense")
    with pytest.raises(mcref.ConfigError, match=r"key 'kind': \"slabs\" must be one of"):
        mcref.models("brdf", "slabs")
    assert mcref.models("g1", "slab") == [] and mcref.models("g1")


def test_a_tables_arrays_are_read_only_copies():
    # Before: t.sum[0] = 5 was accepted and lost (each access returns a copy).
    t = mcref.simulate(CFG, seed=1, threads=1)["tau_plus"]
    for name in ("value", "stderr", "sum", "sum_sq"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(t, name)[0] = 5
    s = t.sum.copy()
    s[0] = 5  # a copy of one's own is writable
    assert s[0, 0] == 5


def test_paths_may_be_pathlib_paths(tmp_path):
    t = mcref.simulate(CFG, seed=1, threads=1)
    mcref.write_tables(tmp_path / "x.h5", t)
    assert mcref.read_tables(tmp_path / "x.h5").names == t.names
    (tmp_path / "e.toml").write_text('[geometry]\nkind = "micrograin"\ntau0 = 0.5\nbeta = 1.0\ntile = 40\n\n'
                                     '[[measure]]\nquantity = "tau_plus"\ntheta_i_deg = [0]\nsamples = 100\n')
    assert mcref.simulate_file(tmp_path / "e.toml", seed=1, threads=1).names == ["tau_plus"]


def test_sample_counts_beyond_the_memory_budget_are_refused():
    # n = 2^62: n * k wrapped round to 0, and the sampler returned empty arrays.
    with pytest.raises(mcref.ConfigError, match="key 'n'.*budget"):
        mcref.samplers.lambert_sphere_phase(seed=1, n=2**62)


def test_tables_are_not_written_onto_their_experiment_file(tmp_path):
    # Before: the TOML was replaced by the HDF5 file (the CLI's -o refuses it).
    exp = tmp_path / "e.toml"
    exp.write_text('[geometry]\nkind = "micrograin"\ntau0 = 0.5\nbeta = 1.0\ntile = 40\n\n'
                   '[[measure]]\nquantity = "tau_plus"\ntheta_i_deg = [0]\nsamples = 100\n')
    before = exp.read_bytes()
    t = mcref.simulate_file(exp, seed=1, threads=1)
    with pytest.raises(mcref.ConfigError, match="is the input"):
        mcref.write_tables(exp, t)
    assert exp.read_bytes() == before and sorted(os.listdir(tmp_path)) == ["e.toml"]


@pytest.mark.parametrize("call, key", [
    ("tau_plus_eq22(-0.5, 1.0, 0.3)", "tau0"),  # gave -0.514
    ("ndf_eq16(0.5, 0.0, 0.3)", "beta"),
    ("ndf_eq17(np.array([0.5, 1.0]), 1.0, 0.3)", "tau0"),
    ("vndf_eq13(0.5, 1.0, -1.0, 0.3, 0.0, 0.2, 0.0)", "beta_y"),
    ("g1_smith_series_n4(0.5, float('nan'), 0.3)", "beta"),
])
def test_grain_field_parameters_outside_the_models_domain_are_refused(call, key):
    with pytest.raises(mcref.ConfigError, match=f"key '{key}': .* is out of range"):
        eval("mcref.micrograin." + call)


@pytest.mark.parametrize("call, key", [
    # What each gave before (they took any value): the numbers of a formula outside its domain.
    ("lambert_sphere.single_scattering_eq10(2.0, 0.5, 0.5, 0.0)", "c"),  # 0.424
    ("lambert_sphere.deon_fast_eq41(0.5, 1.5, 0.5, 0.0)", "mu_i"),  # 0.0529
    ("lambert_sphere.deon_brdf(0.5, 0.5, np.array([0.5, 1.5]), 0.0)", "mu_o"),  # 0.0498
    ("lambert_sphere.phase_eq1(1.5)", "mu"),  # 0
    ("lambert_sphere.albedo_from_kd(1.2)", "kd"),  # nan
    ("lambert_sphere.kd_eq40(-0.2)", "c"),  # -0.0545
    ("lambert_sphere.h0_at_infinity(1.5)", "c"),  # inf
    ("lambert_sphere.h_exact(0, 1.5, 0.5)", "c"),  # a ValueError from the quadrature
    ("radiative_transfer.chandrasekhar_isotropic(0.5, -0.2, 0.5)", "mu_i"),  # 0
    ("radiative_transfer.h_isotropic_table(0.5, 1.5)", "mu"),  # 1.286, extrapolated
    ("radiative_transfer.h_isotropic(1.5, 0.5)", "albedo"),  # a ValueError without the value
    ("micrograin.p1_eq10(-1.0, 1.0)", "r"),  # -0.272
    ("micrograin.tau_plus_eq22(0.5, 1.0, 2.0)", "theta"),  # -0.626
    ("micrograin.g_dist(0.5, 1.0, 1.0, -0.3, 0.0, 0.5)", "theta_i"),
    ("micrograin.lrpb23(0.5, 1.0, 0.3, 0.0, 2.0, 3.1, mcref.micrograin.MicroSurface(), "
     "mcref.micrograin.MicroSurface())", "theta_o"),  # -0.0955
    ("micrograin.ggx_ndf(-0.3, 0.2)", "alpha"),  # 1.81
    ("micrograin.ndf_eq17(0.5, 1.0, 2.0)", "theta_m"),  # a normal below the macro surface
    ("micrograin.ggx_ndf(0.3, -0.2)", "theta_m"),
    ("micrograin.ndf_anisotropic(0.5, 1.0, 2.0, 0.3, float('nan'))", "phi_m"),
    ("micrograin.vndf_eq13(0.5, 1.0, 1.0, 0.3, 0.0, 1.7, 0.0)", "theta_m"),
    ("micrograin.tau_plus_anisotropic(0.5, 1.0, 2.0, 0.3, float('inf'))", "phi"),
    ("micrograin.g_dist(0.5, 1.0, 1.0, 0.3, 0.0, 1.5)", "h"),  # 1
    ("micrograin.projected_cap_area(0.3, -2.0)", "h"),  # -9.42
    ("sggx.hg_phase(1.5, 0.3, 0.0, 0.4, 0.0)", "g"),  # -0.0064
    ("sggx.spongecake_ss_substrate([mcref.sggx.Layer.isotropic(1.0, 1.0)], 2.0, 0.3, 0.0, 0.4, 3.1)",
     "substrate_albedo"),  # 0.113
])
def test_model_arguments_outside_their_domain_are_refused(call, key):
    with pytest.raises(mcref.ConfigError, match=f"key '{key}': = .* is out of range; allowed"):
        eval("mcref." + call)


def test_model_arguments_at_the_ends_of_their_domain_are_taken():
    # The checks refuse only what is outside: the closed ends give the formulas' values.
    ls, rt = mcref.lambert_sphere, mcref.radiative_transfer
    assert ls.phase_eq1(-1.0) > 0 and ls.phase_eq1(1.0) == 0.0
    assert np.isfinite(ls.single_scattering_eq10(1.0, 0.0, 1.0, 0.0))
    assert rt.h_isotropic(1.0, 0.0) == pytest.approx(1.0, abs=1e-12)
    assert rt.h_isotropic_table(0.0, np.array([0.0, 1.0])) == pytest.approx([1.0, 1.0], abs=1e-12)


def test_a_table_file_iterates_over_its_names():
    # Before: list(TableFile) raised TypeError, while `in` and [name] took names.
    t = mcref.simulate(CFG, seed=1, threads=1)
    assert list(t) == t.names and all(name in t for name in t)


def test_layers_and_written_seeds_name_what_is_wrong(tmp_path):
    # Before: "key 'layer': layer thickness must be >= 0" without the value, and seed=-1 a pybind TypeError.
    with pytest.raises(mcref.ConfigError, match=r"key 'thickness': = -0.5 must be >= 0"):
        mcref.sggx.Layer.isotropic(-0.5, 1.0)
    with pytest.raises(mcref.ConfigError, match=r"key 'density': = -2 is out of range"):
        mcref.sggx.Layer.hg(1.0, -2.0, 0.3)
    assert mcref.sggx.Layer.isotropic(float("inf"), 1.0, 0.5).optical_thickness == float("inf")
    table = mcref.simulate(CFG, seed=1, threads=1)["tau_plus"]
    with pytest.raises(mcref.ConfigError, match=r"key 'seed': = -1 must be an integer"):
        mcref.write_tables(tmp_path / "x.h5", [table], seed=-1)
    assert not (tmp_path / "x.h5").exists()
