# The module builds and imports from the build tree, with its submodules.
import mcref


def test_import_and_submodules():
    assert mcref.__file__.endswith(".so")
    for sub in ("micrograin", "sggx", "lambert_sphere", "radiative_transfer", "samplers"):
        assert hasattr(mcref, sub)
    assert issubclass(mcref.ConfigError, ValueError)


def test_docstrings_name_equations():
    assert "Eq. 22" in mcref.micrograin.tau_plus_eq22.__doc__
    assert "Eq. 17" in mcref.micrograin.ndf_eq17.__doc__
    assert "WITHOUT the cosine" in mcref.lambert_sphere.__doc__
