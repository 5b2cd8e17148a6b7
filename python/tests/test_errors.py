"""Errors as Python exceptions with the library's message and status: one class per status, the
CLI's refusals word for word (keywords spelt as the CLI's options without '--'), freed objects,
bad arguments; never a crash."""
import re

import numpy as np
import pytest

import hovox


def test_exception_classes():
    assert issubclass(hovox.InvalidError, hovox.Error) and issubclass(hovox.InvalidError, ValueError)
    assert issubclass(hovox.FileError, OSError) and issubclass(hovox.NotFoundError, LookupError)
    assert issubclass(hovox.ClosedError, hovox.InvalidError)
    codes = {c.status for c in (hovox.InvalidError, hovox.BadInputError, hovox.FileError, hovox.NoMemoryError,
                                hovox.LimitError, hovox.CancelledError, hovox.NotFoundError, hovox.UnsupportedError,
                                hovox.InternalError)}
    assert codes == set(range(1, 10))
    assert hovox.status_name(3) == "HV_ERR_IO"


def test_status_and_message(tmp_path):
    with pytest.raises(hovox.FileError) as e:
        hovox.load_mesh(tmp_path / "missing.stl")
    assert e.value.status == 3 and e.value.status_name == "HV_ERR_IO" and "missing.stl" in str(e.value)
    (tmp_path / "bad.stl").write_bytes(b"solid x\nfacet normal 0 0 1\n")
    with pytest.raises(hovox.BadInputError, match="bad.stl"):
        hovox.load_mesh(str(tmp_path / "bad.stl"))
    with pytest.raises(hovox.FileError):
        hovox.load(tmp_path / "none.vdb")


def test_unknown_shape_names_the_shapes():
    """The library's message, the CLI's too (tests/cli/cases/generate_unknown_key)."""
    with pytest.raises(hovox.InvalidError) as e:
        hovox.generate("blob")
    assert str(e.value) == "unknown shape 'blob' (shapes: sphere, box, holed-box, torus, cylinder, knot, gear)"


def test_load_on_a_mesh_names_load_mesh(tmp_path):
    """hovox.load on a mesh says it is one and names hovox.load_mesh, not "bad magic number"."""
    hovox.generate.box().save(tmp_path / "b.stl")
    with pytest.raises(hovox.BadInputError) as e:
        hovox.load(tmp_path / "b.stl")
    assert str(e.value) == (str(tmp_path / "b.stl") + ": a mesh, not a model (a .vdb file or a 3MF Volumetric "
                            "package): voxelize the mesh instead; hovox.load_mesh reads it")
    assert len(hovox.load_mesh(tmp_path / "b.stl").facets) == 12


def test_same_refusals_as_the_cli(cli, root, tmp_path, gear_mesh):
    """The twelve pairs of tests/cli/cases/front_ends_agree.sh, from Python."""
    m = hovox.load(root + "/tests/data/models/linear2.vdb")
    box = hovox.generate.box()
    b = tmp_path / "b.stl"
    box.save(b)
    M = root + "/tests/data/models/linear2.vdb"
    o = str(tmp_path)
    cases = [
        (lambda: m.render(o + "/x.png", step=5), ["render", M, "-o", o + "/x.png", "--step", "5"]),
        (lambda: m.render(o + "/x.png", fov=180), ["render", M, "-o", o + "/x.png", "--fov", "180"]),
        (lambda: m.render(o + "/x.png", density=-1), ["render", M, "-o", o + "/x.png", "--density", "-1"]),
        (lambda: m.render(o + "/x.png", background="nope"), ["render", M, "-o", o + "/x.png", "--background", "nope"]),
        (lambda: m.layers(box, o + "/s", mode="gray"), ["layers", M, "--mesh", b, "-o", o + "/s", "--mode", "gray"]),
        (lambda: m.layers(box, o + "/s", seed=-2), ["layers", M, "--mesh", b, "-o", o + "/s", "--seed", "-2"]),
        (lambda: m.layers(box, o + "/s", layer_height=0),
         ["layers", M, "--mesh", b, "-o", o + "/s", "--layer-height", "0"]),
        (lambda: hovox.voxelize(box, adjacency=7), ["voxelize", b, "-o", o + "/v.vdb", "--adjacency", "7"]),
        (lambda: m.export(o + "/x.vtu", coarsen=0), ["export", M, "-o", o + "/x.vtu", "--coarsen", "0"]),
        (lambda: hovox.contours(box, layer_height=0), ["contours", b, "-o", o + "/c.svg", "--layer-height", "0"]),
        (lambda: m.profile(from_=(0, 0, 0), to=(1, 1, 1), samples=1),
         ["profile", M, "--from", "0,0,0", "--to", "1,1,1", "--samples", "1", "-o", o + "/p.csv"]),
        (lambda: hovox.generate.sphere(radius=-1), ["generate", "sphere", "radius=-1", "-o", o + "/s.stl"]),
    ]
    for call, args in cases:
        r = cli(*args)
        assert r.returncode == 2, (args, r.stderr)
        msg = re.sub(r"^hovox [a-z]*: ", "", r.stderr.strip())
        msg = re.sub(r" \(see 'hovox [a-z]* --help'\)$", "", msg)
        msg = re.sub(r"--([a-z]+)-([a-z]+)", r"\1_\2", msg)
        msg = re.sub(r"--([a-z]+)", r"\1", msg)
        with pytest.raises(hovox.InvalidError) as e:
            call()
        assert str(e.value) == msg


def test_unknown_keyword_lists_the_options(gear_mesh):
    with pytest.raises(hovox.InvalidError, match=r"unknown option 'dimz' \(options: dims, voxel_size, adjacency"):
        hovox.voxelize(gear_mesh, dimz=3)
    with pytest.raises(hovox.InvalidError, match="unknown option 'dgrad'"):
        hovox.ags(feature=hovox.point(0, 0, 0), dgrad=3, ms=(1, 0), me=(0, 1))


def test_bad_values(mats, gear_mesh):
    ax = hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1))
    with pytest.raises(hovox.InvalidError, match="leaves \\[0, 1\\]"):
        hovox.ags(feature=ax, d_neg=9.54, d_grad=9.54, d_pos=20.37, f="0.105*d", ms=(0, 0.9, 0.1), me=(0.9, 0, 0.1))
    with pytest.raises(hovox.InvalidError, match="sums to"):
        hovox.ags(feature=ax, d_neg=1, d_grad=1, d_pos=1, ms=(0, 0.9, 0.2), me=(0.9, 0, 0.1))
    with pytest.raises(hovox.InvalidError, match="feature must be"):
        hovox.ags(feature="z", d_neg=1, d_grad=1, d_pos=1, ms=(1, 0), me=(0, 1))
    with pytest.raises(hovox.InvalidError, match="no material|name"):
        hovox.materials([{"color": "#fff"}])
    with pytest.raises(TypeError):
        hovox.voxelize("not a mesh")
    with pytest.raises(hovox.InvalidError, match="cannot be a"):
        hovox.voxelize(gear_mesh, dims=object())
    with pytest.raises(hovox.InvalidError):
        hovox.mesh(np.zeros((3, 3)), np.array([[0, 1, 5]]))


def test_python_f_errors_propagate(mats):
    ax = hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1))

    def boom(d):
        raise ZeroDivisionError("f blew up")
    with pytest.raises(ZeroDivisionError, match="f blew up"):
        hovox.ags(feature=ax, d_neg=1, d_grad=2, d_pos=1, f=boom, ms=(1, 0, 0), me=(0, 1, 0))
    with pytest.raises(TypeError, match="not a number"):
        hovox.ags(feature=ax, d_neg=1, d_grad=2, d_pos=1, f=lambda d: "x", ms=(1, 0, 0), me=(0, 1, 0))
    with pytest.raises(hovox.InvalidError, match="leaves"):
        hovox.ags(feature=ax, d_neg=1, d_grad=2, d_pos=1, f=lambda d: d, ms=(1, 0, 0), me=(0, 1, 0))


def test_freed_objects_raise(gear_mesh, mats):
    mesh = hovox.generate.sphere()
    model = hovox.voxelize(mesh, dims=16)
    ms = hovox.materials(["A", "B"])
    feat = hovox.point(0, 0, 0)
    obj = hovox.object(model, ms)
    src = obj.add_ags(feature=feat, d_neg=1, d_grad=2, d_pos=1, ms=(1, 0), me=(0, 1))
    for o in (mesh, model, ms, feat, src, obj):
        o.free()
        assert o.closed
        o.free()  # twice is fine
    for call in (lambda: mesh.report(), lambda: model.fractions(), lambda: ms.names(), lambda: len(ms),
                 lambda: feat.distance((0, 0, 0)), lambda: src.eval(1.0), lambda: obj.evaluate(),
                 lambda: hovox.voxelize(mesh), lambda: hovox.object(model, ms), lambda: obj.voxels()):
        with pytest.raises(hovox.ClosedError, match="was freed"):
            call()
    with hovox.generate.box() as b:
        assert b.count()[0] == 12
    assert b.closed
    with pytest.raises(hovox.ClosedError):
        b.count()


def test_option_dicts_with_odd_keys(gear_mesh):
    model = hovox.voxelize(gear_mesh, dims=8)
    with pytest.raises(TypeError, match="option names must be strings"):
        model.harmonic(gear_mesh, one={1: 2}, zero={"normal": (0, 0, 1)})
    with pytest.raises(TypeError, match="facet selection"):
        model.harmonic(gear_mesh, one=[1], zero={"normal": (0, 0, 1)})
