"""Models as NumPy arrays: dense fractions against `hovox probe` at every voxel centre and against
the sparse leaves; boxes; leaves viewed without a copy; probe points as arrays; add_grid; a field
built from an array against the same samples read from a .vti file."""
import os

import numpy as np
import pytest

import hovox


def centres_of_box(model, box=None):
    (i0, j0, k0), (i1, j1, k1) = model.index_box(box)
    t = model.transform()
    ii, jj, kk = np.meshgrid(np.arange(i0, i1 + 1), np.arange(j0, j1 + 1), np.arange(k0, k1 + 1), indexing="ij")
    idx = np.stack([ii, jj, kk], axis=-1).reshape(-1, 3)
    return np.asarray(t["origin"]) + idx * np.asarray(t["voxel"]), idx


def test_fractions_equal_cli_probe_at_every_voxel_centre(graded_gear, cli, tmp_path):
    g = graded_gear["graded"]
    frac = g.fractions()
    occ = g.occupancy()
    pts, _ = centres_of_box(g)
    assert frac.shape == occ.shape + (3,) and frac.dtype == np.float32 and occ.dtype == np.bool_
    # the CLI on the saved model (fractions stored as half floats: compare with its reading of the file)
    csv = tmp_path / "pts.csv"
    np.savetxt(csv, pts, delimiter=",", fmt="%.17g")
    r = cli("probe", graded_gear["path"], "--points", csv)
    assert r.returncode == 0, r.stderr
    rows = np.loadtxt(r.stdout.splitlines()[1:], delimiter=",")
    assert rows.shape == (pts.shape[0], 7)
    loaded = hovox.load(graded_gear["path"])
    lf = loaded.fractions().reshape(-1, 3)
    # at an occupied voxel's centre probe's trilinear weights all fall on that voxel, so it reads
    # the voxel's fractions; at other centres it says outside (its fractions there come from the
    # renormalised weights of neighbours a rounding error away, not from the voxel)
    inside_cli = rows[:, 3].astype(bool)
    assert np.array_equal(inside_cli, loaded.occupancy().reshape(-1))
    # %.6g printing: within half a unit of the sixth digit
    err = np.abs(rows[inside_cli, 4:] - lf[inside_cli])
    assert np.all(err <= 5e-7 * np.maximum(1, np.abs(lf[inside_cli])) + 1e-12), err.max()
    # in memory: probe at the same centres gives the dense arrays (to the rounding of the centre's
    # index coordinates, which puts a weight of ~1e-16 on neighbours)
    inside, f = g.probe(pts)
    occ1 = occ.reshape(-1)
    assert np.array_equal(inside, occ1)
    assert np.max(np.abs(f[occ1] - frac.reshape(-1, 3)[occ1])) < 1e-6
    assert np.allclose(frac[occ].sum(axis=1), 1, atol=1e-6)
    assert np.all(frac[~occ] == 0)


def test_dense_equals_sparse_leaves(graded_gear):
    g = graded_gear["graded"]
    names = g.materials().names()
    (lo, hi) = g.index_box()
    frac = g.fractions()
    origins, masks, vals = g.leaves("material." + names[1])
    assert vals.shape == (len(origins), 8, 8, 8) and not vals.flags.writeable
    bits = np.unpackbits(masks.view(np.uint8), bitorder="little").reshape(-1, 8, 8, 8).astype(bool)
    dense = np.zeros(frac.shape[:3], np.float32)
    for o, b, v in zip(origins, bits, vals):
        x, y, z = np.nonzero(b)
        dense[o[0] + x - lo[0], o[1] + y - lo[1], o[2] + z - lo[2]] = v[x, y, z]
    assert np.array_equal(dense, frac[..., 1])
    assert int(bits.sum()) == g.voxels()


def test_leaves_are_views_that_keep_the_model_alive(graded_gear, gear_mesh, mats):
    import gc
    import weakref
    _, _, g = __import__("conftest").grade_gear(gear_mesh, mats, dims=24)
    ref = weakref.ref(g)
    origins, masks, vals = g.leaves("material.A")
    assert type(vals.base).__name__ == "_View" and type(origins.base).__name__ == "_View"
    expect = g.fractions()  # a copy
    with pytest.raises(BufferError):
        g.free()
    del g
    gc.collect()
    assert ref() is not None  # the arrays keep it
    assert float(vals.sum()) > 0 and origins.shape[1] == 3
    del origins, masks
    assert ref() is not None
    del vals
    gc.collect()
    assert ref() is None
    assert expect.shape[3] == 3


def test_box_and_grid(graded_gear):
    g = graded_gear["graded"]
    box = ((-10, -10, 5), (10, 10, 15))
    (lo, hi) = g.index_box(box)
    f = g.fractions(box=box)
    assert f.shape[:3] == tuple(h - l + 1 for l, h in zip(lo, hi))
    full = g.fractions()
    (flo, _) = g.index_box()
    off = [a - b for a, b in zip(lo, flo)]
    assert np.array_equal(f, full[off[0]:off[0] + f.shape[0], off[1]:off[1] + f.shape[1], off[2]:off[2] + f.shape[2]])
    pts, _ = centres_of_box(g, box)
    assert np.all(pts >= np.array(box[0]) - 1e-9) and np.all(pts <= np.array(box[1]) + 1e-9)
    a = g.grid("material.A", box=box)
    assert a.shape == f.shape[:3] and np.array_equal(a, f[..., 0])
    s = g.grid("surface", box=box)
    assert s.dtype == np.bool_
    with pytest.raises(hovox.InvalidError, match="holds no voxel centre"):
        g.fractions(box=((0, 0, 0), (0.01, 0.01, 0.01)))
    with pytest.raises(hovox.NotFoundError):
        g.grid("nope")


def test_add_grid_from_array_and_callable(graded_gear, tmp_path):
    m = hovox.load(graded_gear["path"])
    c = m.centres()
    assert c.shape == (m.voxels("occupancy"), 3)
    n = m.add_grid("r", np.hypot(c[:, 0], c[:, 1]))
    assert n == len(c)
    m.add_grid("z", lambda p: p[:, 2])
    dense_r, dense_z = m.grid("r"), m.grid("z")
    occ = m.occupancy()
    pts, _ = centres_of_box(m)
    assert np.allclose(dense_r.reshape(-1)[occ.reshape(-1)], np.hypot(pts[occ.reshape(-1), 0], pts[occ.reshape(-1), 1]),
                       rtol=1e-6)
    assert np.allclose(dense_z.reshape(-1)[occ.reshape(-1)], pts[occ.reshape(-1), 2], rtol=1e-6)
    with pytest.raises(hovox.InvalidError):
        m.add_grid("bad", np.zeros(3))  # not the voxel count
    with pytest.raises(hovox.InvalidError, match="not finite|finite"):
        m.add_grid("nan", np.full(len(c), np.nan))
    assert [g["name"] for g in m.grids()].count("bad") == 0
    rep = m.export(str(tmp_path / "r.vti"), grids="r")
    assert "r" in rep["arrays"] and rep["bytes"] > 0


def write_vti(path, values, origin, spacing):
    """A VTK XML image (ASCII point data), written here without VTK."""
    nx, ny, nz = values.shape
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n')
        f.write('<ImageData WholeExtent="0 %d 0 %d 0 %d" Origin="%.17g %.17g %.17g" Spacing="%.17g %.17g %.17g">\n'
                % ((nx - 1, ny - 1, nz - 1) + tuple(origin) + tuple(spacing)))
        f.write('<Piece Extent="0 %d 0 %d 0 %d">\n<PointData Scalars="s">\n' % (nx - 1, ny - 1, nz - 1))
        f.write('<DataArray type="Float64" Name="s" format="ascii">\n')
        # VTK orders points x fastest: values[i, j, k] at index i + nx (j + ny k)
        f.write(" ".join("%.17g" % v for v in values.transpose(2, 1, 0).reshape(-1)))
        f.write('\n</DataArray>\n</PointData>\n<CellData/>\n</Piece>\n</ImageData>\n</VTKFile>\n')


@pytest.mark.parametrize("exact", [True, False])
def test_field_from_array_equals_field_from_vti(tmp_path, exact):
    mesh = hovox.generate.box(min=(0, 0, 0), max=(20, 12, 8))
    model = hovox.voxelize(mesh, voxel_size=1.0 if exact else 0.7)
    rng = np.random.default_rng(7)
    # exact: spacing 0.5 and origin -3.25 on 1 mm voxels put every centre at a cell coordinate
    # that is a binary fraction, so both samplings are exact; else general positions
    spacing, origin = ((0.5, 0.5, 0.5), (-3.25, -3.25, -3.25)) if exact else ((0.9, 0.8, 0.75), (-2.3, -1.7, -1.9))
    shape = (54, 38, 30) if exact else (32, 24, 18)
    values = rng.uniform(-5, 40, shape)
    path = str(tmp_path / "s.vti")
    write_vti(path, values, origin, spacing)
    fa, ra = model.field(values=values, spacing=spacing, origin=origin, name="s")
    ff, rf = model.field(file=path, array="s")
    assert ra["voxels"] == rf["voxels"] and ra["filled"] == rf["filled"] == 0
    assert ra["file_lo"] == rf["file_lo"] and ra["file_hi"] == rf["file_hi"]
    pts = model.centres()
    da = np.array([fa.distance(p, model) for p in pts[::7]])
    df = np.array([ff.distance(p, model) for p in pts[::7]])
    if exact:
        assert np.array_equal(da, df)
    else:  # both round a double sum to float: within one float rounding step
        assert np.all(np.abs(da - df) <= 2 * np.spacing(np.abs(df).astype(np.float32)))
    # graded from either: the same fractions (to the same rounding)
    mats = hovox.materials(["A", "B"])
    out = []
    for feat in (fa, ff):
        o = hovox.object(model, mats)
        o.add_ags(feature=feat, d_neg=0, d_grad=40, d_pos=0, ms=(1, 0), me=(0, 1))
        out.append(o.evaluate().fractions())
    if exact:
        assert np.array_equal(out[0], out[1])
    else:
        assert np.max(np.abs(out[0] - out[1])) < 1e-6
    # float32 arrays and a scalar spacing are accepted; a field that misses voxels is refused
    f32, _ = model.field(values=values.astype(np.float32), spacing=spacing[0], origin=origin) if exact else (None, None)
    with pytest.raises(hovox.BadInputError, match="lie outside it"):
        model.field(values=values[:, :, :12], spacing=spacing, origin=origin)
    fn, rn = model.field(values=values[:, :, :12], spacing=spacing, origin=origin, outside="nearest")
    assert rn["filled"] > 0
    with pytest.raises(hovox.InvalidError, match="finite"):
        bad = values.copy()
        bad[1, 2, 3] = np.nan
        model.field(values=bad, spacing=spacing, origin=origin)


def test_probe_points_array(graded_gear):
    g = graded_gear["graded"]
    pts = np.array([[0, 15, 20], [0, 0, 20], [100, 0, 0]], float)
    inside, f = g.probe(pts)
    assert inside.tolist() == [True, False, False]
    one_in, one = g.probe((0, 15, 20))
    assert one_in and [one[k] for k in "ABC"] == f[0].tolist()
    assert np.all(f[2] == 0)
    with pytest.raises(ValueError):
        g.probe(np.zeros((3, 2)))
    with pytest.raises(hovox.InvalidError):
        g.probe((0, np.nan, 0))
