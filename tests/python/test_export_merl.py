# mcref export-brdf --format merl: the file read back by an independent numpy
# reader (MERL's BRDFRead.cpp layout), its size, and its values at grid points
# against a numpy trilinear interpolation of the table; coarse tables refused.
import os

import numpy as np
import pytest

import mcref

SCALE = np.array([1.0, 1.15, 1.66]) / 1500  # MERL's RED/GREEN/BLUE_SCALE


def brdf_config(theta_o_bins=8, phi_bins=8, theta_i_deg=list(range(0, 90, 10))):
    return {
        "geometry": {"kind": "micrograin", "tau0": 0.4, "beta": 1.0, "tile": 30},
        "material": {"grain": {"type": "lambertian", "albedo": [0.2, 0.6, 0.4]},
                     "base": {"type": "lambertian", "albedo": 0.5}},
        "run": {"seed": 12, "batches": 2},
        "measure": [{"quantity": "brdf", "theta_i_deg": theta_i_deg, "theta_o_bins": theta_o_bins,
                     "phi_bins": phi_bins, "samples": 400}],
    }


def read_merl(path):
    """Independent reader: header 3 x int32, then 3 channel blocks of doubles times MERL's scale."""
    with open(path, "rb") as f:
        dims = np.frombuffer(f.read(12), dtype="<i4")
        data = np.frombuffer(f.read(), dtype="<f8")
    return dims, data.reshape(3, dims[0], dims[1], dims[2]) * SCALE[:, None, None, None]


def merl_directions(i, j, k):
    """theta_h = (i/90)^2 pi/2, theta_d = j pi/180, phi_d = k pi/180; wi = R_y(theta_h) d, wo = reflect(wi, h)."""
    th, td, pd = (i / 90.0) ** 2 * np.pi / 2, j * np.pi / 180, k * np.pi / 180
    d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)], -1)
    c, s = np.cos(th)[:, None], np.sin(th)[:, None]
    wi = np.stack([d[:, 0] * c[:, 0] + d[:, 2] * s[:, 0], d[:, 1], -d[:, 0] * s[:, 0] + d[:, 2] * c[:, 0]], -1)
    h = np.stack([s[:, 0], 0 * th, c[:, 0]], -1)
    wo = 2 * np.sum(wi * h, -1, keepdims=True) * h - wi
    return wi, wo


def lerp_weights(points, x):
    """Index of the lower point and weight, held constant outside the points."""
    x = np.clip(x, points[0], points[-1])
    i = np.clip(np.searchsorted(points, x, side="right") - 1, 0, len(points) - 2)
    return i, (x - points[i]) / (points[i + 1] - points[i])


def trilinear(table, ti, to, phi):
    v = table.value[:, 0]  # theta_i, theta_o, phi, channel
    pts = [table.axis("theta_i").centres, table.axis("theta_o").centres, table.axis("phi").centres]
    idx = [lerp_weights(p, x) for p, x in zip(pts, (ti, to, phi))]
    out = 0
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                w = 1.0
                ii = []
                for bit, (i, t) in zip((a, b, c), idx):
                    w = w * (t if bit else 1 - t)
                    ii.append(i + bit)
                out = out + w[:, None] * v[ii[0], ii[1], ii[2]]
    return out  # (n, 3)


def test_merl_round_trip(cli, tmp_path):
    tables = mcref.simulate(brdf_config(), seed=1)
    h5 = tmp_path / "brdf.h5"
    mcref.write_tables(str(h5), tables)
    out = tmp_path / "brdf.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out), "--quiet")
    assert code == 0, err
    assert os.path.getsize(out) == 3 * 4 + 90 * 90 * 180 * 3 * 8
    dims, rgb = read_merl(out)
    assert list(dims) == [90, 90, 180]
    rng = np.random.default_rng(0)
    i, j, k = rng.integers(0, 90, 4000), rng.integers(0, 90, 4000), rng.integers(0, 180, 4000)
    wi, wo = merl_directions(i, j, k)
    above = (wi[:, 2] > 1e-9) & (wo[:, 2] > 1e-9)
    got = rgb[:, i, j, k].T
    assert np.all(got[~above & (wi[:, 2] < -1e-9)] == 0)
    ti, to = np.arccos(np.clip(wi[:, 2], -1, 1)), np.arccos(np.clip(wo[:, 2], -1, 1))
    phi = np.abs(np.remainder(np.arctan2(wo[:, 1], wo[:, 0]) - np.arctan2(wi[:, 1], wi[:, 0]) + np.pi, 2 * np.pi) - np.pi)
    expected = trilinear(tables["brdf"], ti[above], to[above], phi[above])
    assert above.sum() > 1000
    assert np.allclose(got[above], expected, rtol=1e-10, atol=1e-14)
    assert np.mean(got[above] > 0) > 0.9  # the export is not empty (a few bins of this short run are 0)


@pytest.mark.parametrize("kw,why", [
    ({"theta_o_bins": 4}, "at least 8 theta_o bins"),
    ({"phi_bins": 4}, "at least 8 phi bins"),
    ({"theta_i_deg": [0, 30, 60, 80]}, "steps <= 15 deg"),
])
def test_coarse_tables_refused(cli, tmp_path, kw, why):
    h5 = tmp_path / "coarse.h5"
    cfg = brdf_config(**kw)
    cfg["measure"][0]["samples"] = 10
    mcref.write_tables(str(h5), mcref.simulate(cfg))
    out = tmp_path / "x.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out))
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "too coarse" in lines[0] and why in lines[0], err
    assert not out.exists()


def test_bad_arguments(cli, tmp_path):
    h5 = tmp_path / "t.h5"
    cfg = brdf_config()
    cfg["measure"][0]["samples"] = 10
    mcref.write_tables(str(h5), mcref.simulate(cfg))
    for args, msg in [(["--table", "nope", "--format", "merl"], "no table 'nope'"),
                      (["--table", "brdf", "--format", "exr"], "not a known format"),
                      (["--table", "brdf_albedo", "--format", "merl"], "not a brdf table")]:
        code, _, err = cli("export-brdf", str(h5), *args, "-o", str(tmp_path / "o.binary"))
        assert code == 2 and msg in err and len(err.strip().splitlines()) == 1, err


def test_anisotropic_table_refused(cli, tmp_path):
    """A table of an anisotropic slab (phi over [0, 2 pi)) would be folded into [0, pi],
    half of it lost: refused in one line, exit 2, nothing written."""
    cfg = {
        "geometry": {"kind": "slab", "layer": [{"phase": "sggx_fiber", "alpha": 0.5, "orientation": [1, 0, 0],
                                                "optical_thickness": 1.0, "albedo": 0.8}]},
        "run": {"seed": 4, "batches": 2},
        "measure": [{"quantity": "brdf", "theta_i_deg": [0, 15, 30, 45, 60, 75], "phi_i_deg": [0],
                     "theta_o_bins": 8, "phi_bins": 16, "samples": 50}],
    }
    tables = mcref.simulate(cfg)
    assert tables["brdf"].axis("phi").edges[-1] > 6.28  # the sample is anisotropic: phi is not folded
    h5 = tmp_path / "aniso.h5"
    mcref.write_tables(str(h5), tables)
    out = tmp_path / "aniso.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out))
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "anisotropic" in lines[0] and "MERL" in lines[0], err
    assert not out.exists()


def constant_table(theta_i, theta_o_deg=np.linspace(0, 90, 9), phi_deg=np.linspace(0, 180, 9)):
    """A brdf table made in Python whose every cell is 1, theta_i the given axis; theta_o, phi bins."""
    axes = [theta_i, mcref.Axis.points("phi_i", "rad", [0.0]), mcref.Axis.bins("theta_o", "rad", np.radians(theta_o_deg)),
            mcref.Axis.bins("phi", "rad", np.radians(phi_deg)), mcref.Axis.points("channel", "RGB index", [0, 1, 2])]
    shape = tuple(len(a.centres) for a in axes)
    return mcref.Table("brdf", "brdf", axes, 2 * np.ones(shape), 2 * np.ones(shape), batches=2, units="1/sr")


def test_theta_i_given_as_bins_is_read_at_its_centres(cli, tmp_path):
    """theta_i as bins (9 edges, 8 rows): the exporter took the 9 edges as points and read one row past
    the array (an outside audit: valgrind's invalid reads, and 184549 cells of the file not 1). Now every
    cell is 1."""
    h5 = tmp_path / "bins.h5"
    edges = np.radians([0, 5, 15, 30, 45, 60, 75, 85, 90])  # centres 2.5 ... 87.5 deg, steps <= 15 deg
    mcref.write_tables(str(h5), [constant_table(mcref.Axis.bins("theta_i", "rad", edges))])
    out = tmp_path / "bins.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out), "--quiet")
    assert code == 0, err
    dims, rgb = read_merl(out)
    wi, wo = merl_directions(*(a.ravel() for a in np.meshgrid(np.arange(90), np.arange(90), np.arange(180), indexing="ij")))
    above = ((wi[:, 2] > 1e-9) & (wo[:, 2] > 1e-9)).reshape(90, 90, 180)
    assert above.sum() > 10**5
    assert np.allclose(rgb[:, above], 1.0, rtol=1e-12, atol=0), np.unique(rgb[:, above])  # 1 through MERL's scale


@pytest.mark.parametrize("theta_i, why", [
    (mcref.Axis.points("theta_i", "deg", list(range(0, 90, 10))), "is in \"deg\""),
    (mcref.Axis.points("theta_i", "rad", list(np.radians(range(80, -1, -10)))), "is not increasing (80 then 70 deg)"),
])
def test_angles_not_in_increasing_radians_are_refused(cli, tmp_path, theta_i, why):
    """Degrees were refused as "anisotropic", and descending angles as "too coarse ... largest step 0 deg"."""
    h5 = tmp_path / "t.h5"
    mcref.write_tables(str(h5), [constant_table(theta_i)])
    out = tmp_path / "t.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out))
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and why in lines[0] and "theta_i" in lines[0], err
    assert not out.exists()


def test_delta_lobes_left_out_are_named_in_a_warning(cli, tmp_path):
    """A smooth conductor under a thin layer reflects much of the light as a mirror (a delta lobe,
    in brdf_delta, never in the bins): the export succeeds without it and says so on stderr, with the
    largest energy left out. Before, it said nothing. A table without delta lobes gives no warning."""
    slab = {"geometry": {"kind": "slab", "substrate": "conductor",
                         "layer": [{"phase": "isotropic", "optical_thickness": 0.2, "albedo": 0.8}]},
            "run": {"seed": 3, "batches": 2},
            "measure": [{"quantity": "brdf", "theta_i_deg": [0, 15, 30, 45, 60, 75], "theta_o_bins": 8,
                         "phi_bins": 8, "samples": 400}]}
    tables = mcref.simulate(slab)
    delta = tables["brdf_delta"].value[:, 0, -1, :]  # theta_i, channel: the total component
    assert delta.max() > 0.3  # the premise: the mirror carries energy
    h5 = tmp_path / "mirror.h5"
    mcref.write_tables(str(h5), tables)
    out = tmp_path / "mirror.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out), "--quiet")
    assert code == 0 and out.exists(), err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "warning: brdf_delta: delta lobes" in lines[0] and str(out) in lines[0], err
    assert f"up to {delta.max():.3g} of the incident energy" in lines[0], (err, delta.max())
    # Without the delta table in the file the export cannot check: it says so (it said nothing).
    h5 = tmp_path / "alone.h5"
    mcref.write_tables(str(h5), [tables["brdf"]])
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(tmp_path / "a.binary"),
                       "--quiet")
    assert code == 0 and "no table brdf_delta" in err and "cannot be checked" in err, err
    # The diffuse micrograin table of the round trip: no delta lobes, no warning.
    h5 = tmp_path / "diffuse.h5"
    mcref.write_tables(str(h5), mcref.simulate(brdf_config(), seed=1))
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(tmp_path / "d.binary"),
                       "--quiet")
    assert code == 0 and err == "", err


def test_the_format_is_required(cli, tmp_path):
    code, _, err = cli("export-brdf", str(tmp_path / "t.h5"), "--table", "brdf", "-o", str(tmp_path / "o.binary"))
    assert code == 2 and "the output format is required (--format merl)" in err, err


@pytest.mark.parametrize("change, why", [
    ("nan", "holds nan"), ("negative", "holds -1"), ("phi", "has phi over [-180, 0] deg"),
])
def test_cells_and_azimuths_merl_cannot_hold_are_refused(cli, tmp_path, change, why):
    """A NaN, infinite or negative cell was spread over thousands of MERL cells, and a phi axis over
    [-pi, 0] (of the right width) held one value everywhere; both exported with exit 0."""
    theta_i = mcref.Axis.points("theta_i", "rad", list(np.radians(range(0, 90, 10))))
    if change == "phi":
        t = constant_table(theta_i, phi_deg=np.linspace(-180, 0, 9))
    else:
        t = constant_table(theta_i)
        value = 2 * np.ones(t.value.shape)
        value[3, 0, 2, 4, 1] = np.nan if change == "nan" else -2
        t = mcref.Table("brdf", "brdf", t.axes, value, 2 * np.ones(t.value.shape), batches=2, units="1/sr")
    h5 = tmp_path / "t.h5"
    mcref.write_tables(str(h5), [t])
    out = tmp_path / "t.binary"
    code, _, err = cli("export-brdf", str(h5), "--table", "brdf", "--format", "merl", "-o", str(out))
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and why in lines[0], err
    assert not out.exists()
