# mcref export-vdb's slab grids open in Debian's python3-openvdb (pyopenvdb):
# names, grid types, N x N lateral voxels (the periodic seam once), transforms,
# metadata and values against the experiment, computed here from its keys.
import math

import numpy as np
import pyopenvdb as vdb

N, NZ, TILE = 4, 6, 2.0
EXPERIMENT = f"""
[geometry]
kind = "slab"
backend = "openvdb"
tile = {TILE}
lateral_voxels = {N}
depth_voxels = {NZ}
[[geometry.layer]]
phase = "sggx_fiber"
alpha = 0.3
orientation_deg = [60, 30]
thickness = 0.5
density = 3.0
profile = "linear"
profile_top = 0.25
profile_bottom = 1.5
albedo = 0.9
[[geometry.layer]]
phase = "hg"
g = 0.4
thickness = 1.25
density = 2.0
albedo = 0.8
[run]
seed = 1
[[measure]]
quantity = "brdf"
theta_i_deg = [30]
samples = 10
"""


def fiber_s(alpha, theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    a = np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])
    return np.eye(3) + (alpha * alpha - 1) * np.outer(a, a)  # SpongeCake's fibre-like S


def export(cli, tmp_path):
    """EXPERIMENT through `mcref export-vdb`, read by pyopenvdb: (grids, metadata, grids by name)."""
    exp, out = tmp_path / "slab.toml", tmp_path / "slab.vdb"
    exp.write_text(EXPERIMENT)
    code, _, err = cli("export-vdb", str(exp), "-o", str(out), "--quiet")
    assert code == 0, err
    grids, meta = vdb.readAll(str(out))
    return grids, meta, {g.name: g for g in grids}


def test_slab_grids_round_trip_through_pyopenvdb(cli, tmp_path):
    grids, _, by_name = export(cli, tmp_path)
    assert sorted(by_name) == ["layer0_S_diag", "layer0_S_offdiag", "layer0_density", "layer1_density"]
    types = {n: g.valueTypeName for n, g in by_name.items()}
    assert types == {"layer0_S_diag": "vec3s", "layer0_S_offdiag": "vec3s", "layer0_density": "float",
                     "layer1_density": "float"}
    for g in grids:  # N x N laterally, depth_voxels + 1 planes in depth
        assert g.evalActiveVoxelBoundingBox() == ((0, 0, 0), (N - 1, N - 1, NZ)), g.name
    h = TILE / N
    # Layer 0: the top layer, z from -0.5 (k = 0, its bottom) to 0 (k = NZ, its top).
    d0 = by_name["layer0_density"]
    assert d0.gridClass == vdb.GridClass.FOG_VOLUME
    assert d0["phase"] == "sggx_fiber" and math.isclose(d0["lateral_period"], TILE)
    for ijk in [(0, 0, 0), (N - 1, 2, NZ), (1, N - 1, 3)]:
        assert np.allclose(d0.transform.indexToWorld(ijk), (ijk[0] * h, ijk[1] * h, -0.5 + ijk[2] * 0.5 / NZ))
    acc = d0.getConstAccessor()
    for k in range(NZ + 1):
        s = 1 - k / NZ  # relative depth from the layer's top
        expect = np.float32(3.0 * (0.25 + (1.5 - 0.25) * s))
        for i, j in [(0, 0), (N - 1, N - 1), (2, 1)]:
            assert acc.getValue((i, j, k)) == expect, (i, j, k)
    # Layer 1 below it: constant density 2, z from -1.75 to -0.5.
    d1 = by_name["layer1_density"]
    assert np.allclose(d1.transform.indexToWorld((1, 2, 0)), (h, 2 * h, -1.75))
    assert d1.getConstAccessor().getValue((3, 0, NZ)) == np.float32(2.0)
    assert math.isclose(d1["hg_g"], 0.4)
    # S of the tilted fibre layer (float32: to 1e-6).
    S = fiber_s(0.3, 60, 30)
    diag, off = by_name["layer0_S_diag"].getConstAccessor(), by_name["layer0_S_offdiag"].getConstAccessor()
    for ijk in [(0, 0, 0), (N - 1, N - 1, NZ), (2, 3, 4)]:
        assert np.allclose(diag.getValue(ijk), [S[0, 0], S[1, 1], S[2, 2]], rtol=1e-6, atol=0), ijk
        assert np.allclose(off.getValue(ijk), [S[0, 1], S[0, 2], S[1, 2]], rtol=1e-6, atol=1e-7), ijk
        assert off.getValue(ijk)[0] != 0 and off.getValue(ijk)[2] != 0  # tilted: all components present
    assert by_name["layer0_S_diag"]["components"] == "S_xx S_yy S_zz"
    assert by_name["layer0_S_offdiag"]["components"] == "S_xy S_xz S_yz"
    # Nothing stored at the seam i = N or j = N.
    for ijk in [(N, 0, 0), (0, N, 3), (N, N, NZ)]:
        assert not d0.getConstAccessor().isValueOn(ijk), ijk


def test_density_edited_in_pyopenvdb_is_simulated(cli, tmp_path):
    """export-vdb, files written by pyopenvdb, and density_vdb: the unedited grids give the
    original tables bit for bit, a lateral variation changes them, the file is left untouched,
    the provenance names its content, and a changed S is refused."""
    import mcref

    grids, meta, by_name = export(cli, tmp_path)
    vdb.write(str(tmp_path / "unedited.vdb"), grids=grids, metadata=meta)
    # Layer 1 (constant density 2): times 1 + 0.5 cos(2 pi i / N) cos(2 pi j / N), whose mean over
    # i, j in [0, N) is 1, so the layer's mean density stays 2.
    acc = by_name["layer1_density"].getAccessor()
    for i in range(N):
        for j in range(N):
            for k in range(NZ + 1):
                acc.setValueOn((i, j, k), 2.0 * (1 + 0.5 * math.cos(2 * math.pi * i / N) * math.cos(2 * math.pi * j / N)))
    edited = tmp_path / "edited.vdb"
    vdb.write(str(edited), grids=grids, metadata=meta)
    text = EXPERIMENT.replace("tile =", 'density_vdb = "edited.vdb"\ntile =')
    for key in ['density = 3.0\n', 'profile = "linear"\n', 'profile_top = 0.25\n', 'profile_bottom = 1.5\n',
                'density = 2.0\n']:
        assert key in text
        text = text.replace(key, "")
    lateral = tmp_path / "lateral.toml"
    lateral.write_text(text)
    (tmp_path / "unedited.toml").write_text(text.replace("edited.vdb", "unedited.vdb"))
    before = edited.read_bytes()
    out = tmp_path / "t.h5"
    for toml, h5 in [(lateral, out), (tmp_path / "unedited.toml", tmp_path / "unedited.h5"),
                     (tmp_path / "slab.toml", tmp_path / "original.h5")]:
        code, _, err = cli("simulate", str(toml), "-o", str(h5), "--quiet")
        assert code == 0, err
    original, unedited, lateral_tables = (mcref.read_tables(str(tmp_path / f)) for f in ("original.h5", "unedited.h5", "t.h5"))
    for name in original.names:
        assert np.array_equal(original[name].sum, unedited[name].sum), name
    assert not np.array_equal(original["brdf"].sum, lateral_tables["brdf"].sum)
    assert edited.read_bytes() == before  # the input is untouched
    config = lateral_tables.provenance["config"]
    assert f'# geometry.density_vdb read from "edited.vdb": bytes={len(before)} fnv1a64=' in config
    # An S edited in the file is refused (S comes from alpha and orientation), naming file, grid and voxel.
    by_name["layer0_S_diag"].getAccessor().setValueOn((1, 2, 3), (1.0, 1.0, 1.0))
    vdb.write(str(edited), grids=grids, metadata=meta)
    code, _, err = cli("simulate", str(lateral), "-o", str(tmp_path / "u.h5"), "--quiet")
    assert code != 0
    assert f"{edited}: key 'layer0_S_diag': voxel (1, 2, 3) holds (1, 1, 1), not the experiment's" in err
    assert not (tmp_path / "u.h5").exists()
