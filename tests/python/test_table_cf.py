# Table files follow the netCDF-CF names (sim/hdf5/table_file.h): xarray with
# the h5netcdf engine (Debian's python3-xarray, python3-h5netcdf) opens each
# table group with named dimensions, units on the axes and the data, bounds for
# the bins and labels on the channel and component axes; the values are the
# file's, bit for bit. Files written before the CF names still read.
import os

import h5py
import numpy as np
import pytest
import xarray as xr

import mcref

SLAB = """
[geometry]
kind = "slab"
[[geometry.layer]]
phase = "sggx_surface"
alpha = 0.5
thickness = 1.0
density = 1.0
albedo = [0.9, 0.5, 0.2]
[run]
seed = 5
batches = 2
[[measure]]
quantity = "brdf"
theta_i_deg = [20, 50]
theta_o_bins = 4
phi_bins = 3
samples = 300
"""


@pytest.fixture(scope="module")
def table_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("cf")
    (d / "slab.toml").write_text(SLAB)
    path = str(d / "slab.h5")
    mcref.write_tables(path, mcref.simulate_file(str(d / "slab.toml"), quiet=True))
    return path


def text(a):
    return a.decode() if isinstance(a, bytes) else str(a)


def test_xarray_sees_dims_units_bounds_and_labels(table_file):
    with h5py.File(table_file, "r") as f:
        names = list(f.keys())
        groups = {n: (dict(f[n].attrs), {k: np.asarray(f[n][k]) for k in ("value", "stderr")}) for n in names}
    assert "brdf" in names and "brdf_albedo" in names
    tables = mcref.read_tables(table_file)
    seen_bins = seen_channel = seen_component = False
    for name in names:
        attrs, raw = groups[name]
        axes = text(attrs["axes"]).split(",")
        t = tables[name]
        with xr.open_dataset(table_file, group=name, engine="h5netcdf", decode_coords="all") as ds:
            assert list(ds["value"].dims) == axes, name
            for var in ("value", "stderr"):
                assert ds[var].attrs["units"] == text(attrs["units"]) == t.units, (name, var)
                assert np.array_equal(ds[var].values, raw[var], equal_nan=True), (name, var)
            for a in axes:
                ax = t.axis(a)
                coord = ds[a]
                assert coord.attrs["units"] == ax.unit, (name, a)
                assert np.array_equal(coord.values, ax.centres), (name, a)
                if ax.edges is None:
                    assert "bounds" not in coord.attrs, (name, a)
                    continue
                seen_bins = True
                # (decode_coords="all" moves the bounds attribute into the encoding)
                assert coord.encoding.get("bounds", coord.attrs.get("bounds")) == a + "_bounds", (name, a)
                bounds = ds.coords[a + "_bounds"]
                assert bounds.dims == (a, "bnds") and bounds.shape == (len(ax), 2), (name, a)
                assert np.array_equal(bounds.values[:, 0], ax.edges[:-1]) and np.array_equal(bounds.values[:, 1], ax.edges[1:])
            if "channel" in axes:
                seen_channel = True
                assert list(ds["value"].coords["channel_label"].values) == ["R", "G", "B"], name
                assert ds["value"].sel(channel=ds["channel"][2]).coords["channel_label"].item() == "B"
            if "component" in axes:
                seen_component = True
                labels = text(attrs["components"]).split(",")
                assert list(ds["value"].coords["component_label"].values) == labels, name
            # The module's own view of a table is the file's view.
            xr.testing.assert_equal(t.to_xarray(), ds)
    assert seen_bins and seen_channel and seen_component


def test_files_from_before_the_cf_names_still_read(table_file, tmp_path):
    # The layout of mcref before the CF names, rewritten from the new file:
    # attribute unit (and kind) on the axes, <axis>_edges, no bounds.
    old = str(tmp_path / "old.h5")
    with h5py.File(table_file, "r") as f, h5py.File(old, "w") as g:
        for k, v in f.attrs.items():
            if k != "sim_fingerprint":
                g.attrs[k] = v
        for name in f:
            src, dst = f[name], g.create_group(name)
            for k, v in src.attrs.items():
                dst.attrs[k] = v
            data = [dst.create_dataset(k, data=np.asarray(src[k])) for k in ("value", "stderr", "sum", "sum_sq")]
            for d, a in enumerate(text(src.attrs["axes"]).split(",")):
                scale = dst.create_dataset(a, data=np.asarray(src[a]))
                scale.attrs["unit"] = src[a].attrs["units"]
                scale.make_scale(a)
                for ds in data:
                    ds.dims[d].attach_scale(scale)
                if a + "_bounds" in src:
                    b = np.asarray(src[a + "_bounds"])
                    dst.create_dataset(a + "_edges", data=np.append(b[:, 0], b[-1, 1])).attrs["unit"] = src[a].attrs["units"]
    new, back = mcref.read_tables(table_file), mcref.read_tables(old)
    assert back.provenance["sim_fingerprint"] == ""
    assert back.names == new.names
    for name in new.names:
        a, b = new[name], back[name]
        assert a.axis_names == b.axis_names
        for x in a.axis_names:
            assert a.axis(x).unit == b.axis(x).unit
            assert np.array_equal(a.axis(x).centres, b.axis(x).centres)
            assert (a.axis(x).edges is None) == (b.axis(x).edges is None)
            if a.axis(x).edges is not None:
                assert np.array_equal(a.axis(x).edges, b.axis(x).edges)
        assert np.array_equal(a.sum, b.sum) and np.array_equal(a.value, b.value, equal_nan=True)
