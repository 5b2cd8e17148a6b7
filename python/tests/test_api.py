"""The rest of the reach, each checked against an independent result: meshes (files, arrays,
transforms, assemblies), features and sources, Booleans, profiles against their CSV, contours,
layers (one layer against the stack's PNG), export, trays."""
import csv
import json
import os

import numpy as np
import pytest

import hovox
from conftest import make_test_data


def test_mesh_files_arrays_and_transform(tmp_path, shared):
    box = hovox.generate.box(min=(0, 0, 0), max=(2, 3, 4))
    r = box.report()
    assert r["closed"] and r["facets"] == 12 and r["volume"] == pytest.approx(24)
    for name in ("b.stl", "b.obj"):
        box.save(tmp_path / name)
        back = hovox.load_mesh(tmp_path / name)
        assert back.report()["volume"] == pytest.approx(24) and back.count() == (12, 8)
    box.save(str(tmp_path / "a.stl"), ascii=True)
    assert hovox.load_mesh(str(tmp_path / "a.stl")).report()["format"] == "ascii"
    # from arrays, and the arrays back
    m = hovox.mesh(box.vertices, box.facets.astype(np.int64))
    assert np.array_equal(m.vertices, box.vertices) and m.report()["volume"] == pytest.approx(24)
    # transform: scale 2 in x, move by (1, 1, 1); a mirror keeps facets outward
    t = box.transform([[2, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [0, 0, 0, 1]])
    assert t.report()["bbox"] == {"min": (1, 1, 1), "max": (5, 4, 5)} and t.report()["volume"] == pytest.approx(48)
    mir = box.transform(np.diag([-1.0, 1, 1, 1])[:3])
    assert mir.report()["volume"] == pytest.approx(24)
    with pytest.raises(hovox.InvalidError):
        box.transform(np.zeros((3, 4)))
    bunny = hovox.load_mesh(os.path.join(shared, "meshes", "bunny_1500.stl"))
    assert bunny.report()["facets"] > 1000 and bunny.name.endswith("bunny_1500.stl")
    assert set(hovox.shapes()) >= {"sphere", "box", "holed-box", "gear", "knot"}
    assert hovox.generate("holed-box").report()["closed"] and hovox.generate.holed_box().count()[0] > 12
    with pytest.raises(AttributeError):
        hovox.generate.dodecahedron


def test_assembly_regions_and_materials():
    core = hovox.generate.box(min=(0, 0, 0), max=(10, 10, 10))
    shell = hovox.generate.box(min=(10, 0, 0), max=(20, 10, 10))
    asm = hovox.join_meshes([{"mesh": core, "name": "core", "material": "Agilus"},
                             {"mesh": shell, "name": "shell", "material": "Vero"}])
    assert [b["name"] for b in asm.bodies()] == ["core", "shell"]
    assert [b["material"] for b in asm.bodies()] == ["Agilus", "Vero"]
    assert [m["name"] for m in asm.materials()] == ["Agilus", "Vero"]
    model = hovox.voxelize(asm, voxel_size=1)
    regions = model.regions()
    assert [r["name"] for r in regions] == ["core", "shell"] and all(r["voxels"] > 0 for r in regions)
    obj = hovox.object(model)
    assert obj.materials().names() == ["Agilus", "Vero"] and len(obj.regions()) == 2
    g = obj.evaluate()
    f = g.fractions()
    occ = g.occupancy()
    core_mask = g.grid("region.core")
    assert np.all(f[core_mask & occ][:, 0] == 1) and np.all(f[~core_mask & occ][:, 1] == 1)
    assert hovox.voxelize(core, dims=8).regions() == []
    with pytest.raises(hovox.InvalidError, match="unknown key"):
        hovox.join_meshes([{"mesh": core, "nmae": "x"}])


def test_sources_features_and_booleans():
    mesh = hovox.generate.box(min=(-10, -10, 0), max=(10, 10, 20))
    model = hovox.voxelize(mesh, voxel_size=1)
    mats = hovox.materials([{"name": "A", "density": (1.18, "g/cm^3")}, "B", "C"])
    assert mats.property("A", "density") == (1.18, "g/cm^3") and mats.property("B", "density") is None
    assert mats.color("A")[3] == 1
    ax = hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1))
    assert ax.distance((3, 4, 7)) == pytest.approx(5) and ax.kind == "axis"
    assert hovox.plane(point=(0, 0, 0), normal=(0, 0, 1)).distance((1, 2, 3)) == pytest.approx(3)
    assert hovox.segment(from_=(0, 0, 0), to=(1, 0, 0)).distance((2, 0, 0)) == pytest.approx(1)
    assert hovox.point((1, 1, 1)).distance((1, 1, 3)) == pytest.approx(2)
    hs = hovox.halfspace(point=(0, 0, 10), normal=(0, 0, 1))
    assert hs.distance((0, 0, 13)) == pytest.approx(3) and hs.distance((0, 0, 4)) == pytest.approx(-6)
    signed = hovox.object(model, mats)
    signed.add_ags(feature=hs, d_neg=-5, d_grad=10, d_pos=0, ms=(1, 0, 0), me=(0, 1, 0))
    _, f = signed.evaluate().probe((0, 0, 10.5))
    assert f["B"] == pytest.approx(0.55, abs=0.02)  # d = 0.5: (0.5 + 5) / 10
    # f as a Python function, an expression, a dict, a table: the same linear f
    common = dict(feature=ax, d_neg=2, d_grad=8, d_pos=2, ms=(1, 0, 0), me=(0, 1, 0))
    srcs = [hovox.ags(f=lambda d: d / 8, **common), hovox.ags(f="d/dg", **common),
            hovox.ags(f={"kind": "linear", "a": 1 / 8}, **common),
            hovox.ags(f={"kind": "table", "points": [(0, 0), (8, 1)]}, **common)]
    d = np.linspace(0, 14, 57)
    ref = srcs[1].eval(d)
    for s in srcs:
        assert np.allclose(s.eval(d), ref, atol=1e-9)
    assert np.allclose(ref[:, 1], np.clip((d - 2) / 8, 0, 1), atol=1e-9)
    assert srcs[0].ranges() == (2, 8, 2) and srcs[0].moved(3).ranges() == (3, 8, 2)
    w = hovox.wu3(feature=ax, d_neg=0, d_grad=10, d_pos=0, f="0.5*d/dg", c=0.2)
    assert w.eval(10.0) == pytest.approx([0.5, 0.3, 0.2])
    # an object: add, move, delete, base, blend
    o = hovox.object(model, mats)
    s1 = o.add_ags(srcs[1])
    o.set_base((0, 0, 1))
    assert o.regions()[0]["base"] == [0, 0, 1] and o.regions()[0]["sources"] == 1
    o.move_ags(s1, 4)
    o.delete_ags(o.add_ags(feature=hovox.plane(point=(0, 0, 0), normal=(0, 0, 1)), d_neg=1, d_grad=0, d_pos=1,
                            ms=(0, 0, 1), me=(0, 0, 1)))
    o.set_blend("idw", 3)
    with pytest.raises(hovox.InvalidError):
        o.set_blend("closest")
    with pytest.raises(hovox.InvalidError, match="sums to"):
        o.set_base((0.5, 0.6, 0))
    g = o.evaluate()
    inside, f = g.probe((0, 0, 10))
    assert inside and f["A"] == pytest.approx(1)  # d = 0 < d- = 4 after the move
    # Booleans: operators are the methods
    other = hovox.object(hovox.voxelize(hovox.generate.box(min=(0, -10, 0), max=(20, 10, 20)), voxel_size=1), mats)
    other.set_base((0, 1, 0))
    for op, meth in ((lambda a, b: a & b, "intersect"), (lambda a, b: a | b, "union"),
                     (lambda a, b: a - b, "difference"), (lambda a, b: a + b, "merge")):
        x, y = op(o, other).evaluate(), getattr(o, meth)(other).evaluate()
        assert np.array_equal(x.fractions(), y.fractions()) and x.voxels() == y.voxels()
    assert (o & other).voxels() < o.voxels() < (o | other).voxels()
    sub = o.subtract(other).evaluate()
    assert sub.voxels("occupancy") == (o - other).voxels() - (o & other).voxels()
    with pytest.raises(TypeError):
        o & 3


def test_facets_harmonic_and_contour_features():
    mesh = hovox.generate.box(min=(0, 0, 0), max=(20, 6, 6))
    model = hovox.voxelize(mesh, voxel_size=1)
    left = hovox.facets(mesh, normal=(-1, 0, 0), angle=5)
    assert left.distance((7.5, 3.5, 3.5), model) == pytest.approx(7.5, abs=0.5)
    h = model.harmonic(mesh, one={"normal": (1, 0, 0)}, zero={"normal": (-1, 0, 0)})
    # phi between the end caps of a bar is linear in x
    for x in (4.5, 10.5, 15.5):
        assert h.distance((x, 3.5, 3.5), model) == pytest.approx(x / 20, abs=0.06)
    c = model.contour()
    assert c.distance((10.5, 3.5, 3.5), model) > 1.5
    with pytest.raises(hovox.InvalidError, match="need the model"):
        c.distance((1, 1, 1))
    assert model.mask("surface").distance((10.5, 0.5, 0.5), model) == pytest.approx(0)


def test_profile_arrays_match_csv(graded_gear, tmp_path):
    g = graded_gear["graded"]
    p = g.profile(from_=(0, -39.4, 19.7), to=(0, 39.4, 19.7), samples=101, csv=tmp_path / "p.csv",
                  plot=str(tmp_path / "p.png"))
    assert p["fractions"].shape == (101, 3) and p["materials"] == ["A", "B", "C"]
    with open(tmp_path / "p.csv") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    head, body = rows[0], np.array(rows[1:], float)
    cols = {h: i for i, h in enumerate(head)}
    assert np.allclose(body[:, cols["A"]], p["fractions"][:, 0], atol=1e-6)
    assert np.allclose(p["xyz"][:, 1], np.linspace(-39.4, 39.4, 101))
    assert hovox.read_png(tmp_path / "p.png").shape[2] in (3, 4)
    with pytest.raises(hovox.InvalidError):
        g.profile(from_=(0, 0, 0), to=(0, 0, 0))


def test_render_array_is_the_png(graded_gear, tmp_path):
    g = graded_gear["graded"]
    img = g.render(tmp_path / "r.png", size=(48, 40), surface=True)
    assert img.shape == (40, 48, 4) and img.dtype == np.float32
    png = hovox.read_png(tmp_path / "r.png")
    assert png.shape == (40, 48, 4) and np.array_equal(hovox.rgba8(img), png)


def test_contours(graded_gear):
    mesh = hovox.generate.gear()
    layers = hovox.contours(mesh, layer_height=2.0)
    assert len(layers) > 5
    mid = layers[len(layers) // 2]
    assert mid["loops"] == 2 and mid["holes"] == 1  # the outline and the bore
    areas = sorted(abs(c["area"]) for c in mid["contours"])
    assert areas[0] == pytest.approx(np.pi * 9.54 ** 2, rel=0.02)
    pts = mid["contours"][0]["points"]
    assert pts.shape[1] == 2 and pts.dtype == np.float64
    assert "contours" not in hovox.contours(mesh, layer_height=2.0, loops=False)[0]


def test_layers_and_one_layer_as_an_array(graded_gear, gear_mesh, tmp_path):
    g = graded_gear["graded"]
    rep = g.layers(gear_mesh, tmp_path / "stack", layers=(700, 703))
    assert rep["first"] == 700 and rep["last"] == 703 and set(rep["materials"]) == {"A", "B", "C"}
    # the model records its mesh (issue 28): cut without it, the same bytes
    g.layers(tmp_path / "own", layers=(700, 703))
    for f in ("manifest.json", "layer-00701.png"):
        assert (tmp_path / "own" / f).read_bytes() == (tmp_path / "stack" / f).read_bytes()
    png = hovox.read_png(tmp_path / "stack" / "layer-00701.png", indices=True)
    rgb = hovox.read_png(tmp_path / "stack" / "layer-00701.png")
    assert rgb.shape == png.shape + (3,)
    one = g.layer(gear_mesh, 701)
    assert one.dtype == np.uint8 and np.array_equal(one, png)
    assert set(np.unique(one)) <= {0, 1, 2, 3}
    fr = g.layer(gear_mesh, 701, mode="fractions")
    assert fr.shape == (3,) + png.shape
    inside = one > 0
    assert np.all(fr.astype(int).sum(axis=0)[inside] >= 253)
    mask = g.layer(gear_mesh, 701, mode="mask")
    assert set(np.unique(mask)) == {0, 1} and np.array_equal(mask == 1, inside)
    with pytest.raises(TypeError):
        g.layer(gear_mesh, 1, layers=(1, 2))


def test_export(graded_gear, tmp_path):
    g = graded_gear["graded"]
    r = g.export(tmp_path / "g.vti")
    assert r["occupied"] == g.voxels("occupancy") and r["bytes"] == os.path.getsize(tmp_path / "g.vti")
    r3 = g.export(str(tmp_path / "g.3mf"), bits=8, volumetric=True)
    back = hovox.load(tmp_path / "g.3mf")
    assert back.voxels("occupancy") == g.voxels("occupancy")
    assert np.max(np.abs(back.fractions() - g.fractions())) <= 1 / 255 + 1e-6
    assert r3["bytes"] > 0
    with pytest.raises(hovox.InvalidError, match="path is required"):
        g.export()


def test_tray(graded_gear, gear_mesh, tmp_path):
    gear_stl = tmp_path / "gear.stl"
    gear_mesh.save(gear_stl)
    pin = tmp_path / "pin.stl"
    hovox.generate.cylinder(base=(0, 0, 0), axis=2, length=3, radius=2).save(pin)
    t = hovox.tray(profile="j750", seed=1, resin={"A": "VeroCyan-V", "B": "VeroMagenta-V", "C": "Agilus30Clear"})
    assert t.add(model=graded_gear["path"], mesh=gear_stl) == 1
    assert t.add(mesh=pin, material="VeroPureWhite", copies=3) == 2
    plan = t.arrange(spacing=4)
    assert plan["parts"] == 4 and plan["layers"] > 1000
    rep = t.layers(tmp_path / "tray", layers=(50, 52))
    assert rep["first"] == 50 and rep["last"] == 52
    man = json.load(open(tmp_path / "tray" / "manifest.json"))
    assert (man["first"], man["last"]) == (50, 52) and len(man["parts"]) == 4  # copies counted
    layer = hovox.read_png(tmp_path / "tray" / "layer-00050.png", indices=True)
    assert layer.shape == (rep["height"], rep["width"]) and layer.max() > 0
    with pytest.raises(hovox.InvalidError):
        t.add(mesh=pin, copies=0)


def test_tray_resin_mapping_keeps_a_body_in_its_resin(cli, root, tmp_path):
    """issue 29 item 1: a tray's resin mapping is a resin for the body rule, from Python as from the
    CLI (the library's tray): badge.3mf asked for colour with resin={"PLA_Blue": "VeroCyan-V"} prints
    its grip in VeroCyan-V and paints the badge alone; the layer is the CLI's, byte for byte."""
    make_test_data(os.path.join(root, "tests", "colour", "colour_assembly.py"), tmp_path, capture_output=True)
    badge = tmp_path / "badge.3mf"
    r = cli("tray", "--part", "%s@60,60" % badge, "--colour-depth", "1", "--resin", "PLA_Blue=VeroCyan-V",
            "-o", tmp_path / "cli", "--layers", "74:75", "-q")
    assert r.returncode == 0, r.stderr
    t = hovox.tray(resin={"PLA_Blue": "VeroCyan-V"})
    t.add(mesh=badge, at=(60, 60), colour_depth=1)
    t.layers(tmp_path / "py", layers=(74, 75))
    f = "layer-00074.png"
    assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes()
    part = json.load(open(tmp_path / "py" / "manifest.json"))["parts"][0]
    assert part["materials"]["PLA_Blue"]["resin"] == "VeroCyan-V" and part["colour"]["skin_voxels"] == 3380


def test_mesh_layers_in_one_step(cli, shared, tmp_path):
    """issue 27 item 2: mesh.layers prints a mesh in its bodies' materials in one step, the bytes of
    `hovox layers PART.3mf -o DIR --material BODY=MATERIAL`; the size warning names the unit."""
    part = os.path.join(shared, "good", "core_in_shell.3mf")
    r = cli("layers", part, "-o", tmp_path / "cli", "--layers", "180:184", "--material", "core=Agilus30Black", "-q")
    assert r.returncode == 0, r.stderr
    m = hovox.load_mesh(part)
    rep = m.layers(tmp_path / "py", layers=(180, 184), materials={"core": "Agilus30Black"})
    assert (rep["first"], rep["last"], rep["warnings"]) == (180, 184, "")
    names = sorted(os.listdir(tmp_path / "cli"))
    assert names == sorted(os.listdir(tmp_path / "py")) and "layer-00182.png" in names
    for f in names:  # the layers and the manifest
        assert (tmp_path / "py" / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f
    man = json.load(open(tmp_path / "py" / "manifest.json"))
    assert [x["name"] for x in man["materials"]] == ["VeroWhite", "Agilus30Black"]
    assert m.bodies()[1]["material"] == "Agilus30"  # the mesh itself keeps its materials
    tiny = hovox.generate.box(min=(0, 0, 0), max=(0.2, 0.1, 0.05))
    rep = tiny.layers(tmp_path / "tiny", mode="mask")
    assert "smaller than 1 mm: if its unit is metres, unit m makes it 200 mm across" in rep["warnings"]
    with pytest.raises(hovox.Error, match="no body 'cor'"):
        m.layers(tmp_path / "x", materials={"cor": "A"})
    with pytest.raises(hovox.InvalidError, match="unknown option 'voxel_sise'"):
        m.layers(tmp_path / "x", voxel_sise=1)
    assert not os.path.exists(tmp_path / "x")
    # a tray part's bodies take materials the same way, and its report warns about the size
    tiny.save(tmp_path / "tiny.stl")
    t = hovox.tray(profile="j750", mode="mask")
    t.add(mesh=part, materials={"shell": "VeroCyan-V", "core": "Agilus30Black"}, at=(40, 40))
    t.add(mesh=tmp_path / "tiny.stl", material="VeroPureWhite", at=(100, 100))
    plan = t.arrange(arrange="no")
    assert plan["parts"] == 2 and "part 2 (tiny.stl)" in plan["warnings"] and "unit m" in plan["warnings"]


def test_mesh_layers_paints_a_coloured_mesh(cli, root, tmp_path):
    """issue 29 item 1: mesh.layers paints a coloured mesh as `hovox layers MESH` paints it (one rule
    in the library, hv_layers_mesh_model): a UV-textured cube's stack has the CLI's bytes, the
    manifest's colour included, by default and with colour_depth, core and intent; its report
    carries the colour's dE2000; colour_depth beside materials is refused."""
    make_test_data(os.path.join(root, "tests", "colour", "textured_cube.py"), tmp_path, capture_output=True)
    obj = tmp_path / "cube.obj"
    cube = hovox.load_mesh(obj)
    for name, args, kw in (("a", [], {}),
                           ("b", ["--colour-depth", "0.5", "--core", "#808080", "--intent", "relative"],
                            {"colour_depth": 0.5, "core": "#808080", "intent": "relative"})):
        r = cli("layers", obj, "-o", tmp_path / ("cli_" + name), "--layers", "150:153", "-q", *args)
        assert r.returncode == 0, r.stderr
        rep = cube.layers(tmp_path / ("py_" + name), layers=(150, 153), **kw)
        names = sorted(os.listdir(tmp_path / ("cli_" + name)))
        assert names == sorted(os.listdir(tmp_path / ("py_" + name))) and "layer-00151.png" in names
        for f in names:
            assert (tmp_path / ("py_" + name) / f).read_bytes() == (tmp_path / ("cli_" + name) / f).read_bytes(), f
        man = json.load(open(tmp_path / ("py_" + name) / "manifest.json"))
        c = rep["colour"]
        assert c["skin_voxels"] == man["colour"]["skin_voxels"] > 0
        assert abs(c["mean_de2000_achieved"] - man["colour"]["mean_de2000_achieved"]) < 1e-9
        assert 0 < c["mean_de2000_target"] <= c["max_de2000_target"]
    with pytest.raises(hovox.InvalidError, match="materials and colour_depth exclude each other"):
        cube.layers(tmp_path / "x", colour_depth=1, materials={"cube": "VeroClear"})
    assert not os.path.exists(tmp_path / "x")


LUA_REPORTS = r"""
local function keys(t)
    local k = {}
    for n in pairs(t or {}) do k[#k + 1] = n end
    table.sort(k)
    return table.concat(k, " ")
end
local function show(name, r)
    print(name .. "|" .. keys(r) .. "|" .. keys(r.materials) .. "|" .. keys(r.colour))
end
show("mesh", hovox.load_mesh("cube.obj"):layers{dir = "lua_m", layers = {150, 152}})
show("model", hovox.load("cube.vdb"):layers{dir = "lua_v", layers = {150, 152}})
show("scan", hovox.layers_scan("ph/phantom.nii", {range = {-480, 500}, lut = "col.csv", dpi = {100, 100},
                                                  layer_height = 2, layers = {20, 22}, dir = "lua_s"}))
show("mask", hovox.load_mesh("cube.obj"):layers{dir = "lua_k", layers = {150, 152}, mode = "mask"})
"""


def test_layers_reports_are_luas(cli, root, tmp_path):
    """issue 26 review (smend item 2): mesh.layers, model.layers and hovox.layers_scan build one report
    (layers_report in python/src/output.c), with the keys of Lua's (hv_lua_push_layers_report) for the
    same job: materials (mesh.layers had none), colour with skin_voxels for a painted mesh or model and
    printer_voxels for a scan's colour table, and the same material names."""
    make_test_data(os.path.join(root, "tests", "colour", "textured_cube.py"), tmp_path, capture_output=True)
    make_test_data(os.path.join(root, "tests", "io", "scan", "make_phantom.py"), tmp_path / "ph", "--size", "20,24,18",
                   "--spacing", "4,4,6", "--formats", "nii", capture_output=True)
    (tmp_path / "col.csv").write_text("HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n")
    r = cli("voxelize", tmp_path / "cube.obj", "--voxel-size", "0.5", "--colour-depth", "1", "-o",
            tmp_path / "cube.vdb", "-q")
    assert r.returncode == 0, r.stderr
    (tmp_path / "r.lua").write_text(LUA_REPORTS)
    r = cli("run", "r.lua", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lua = {}
    for line in r.stdout.splitlines():
        name, top, mats, colour = line.split("|")
        lua[name] = (top.split(), mats.split(), colour.split())
    cube = hovox.load_mesh(tmp_path / "cube.obj")
    py = {"mesh": cube.layers(tmp_path / "py_m", layers=(150, 152)),
          "model": hovox.load(tmp_path / "cube.vdb").layers(tmp_path / "py_v", layers=(150, 152)),
          "scan": hovox.layers_scan(tmp_path / "ph" / "phantom.nii", tmp_path / "py_s", range=(-480, 500),
                                    lut=str(tmp_path / "col.csv"), dpi=(100, 100), layer_height=2, layers=(20, 22)),
          "mask": cube.layers(tmp_path / "py_k", layers=(150, 152), mode="mask")}
    assert sorted(lua) == sorted(py)
    for name, rep in py.items():
        assert (sorted(rep), sorted(rep["materials"]), sorted(rep.get("colour", {}))) == lua[name], name
    assert "skin_voxels" in py["mesh"]["colour"] and "skin_voxels" in py["model"]["colour"]
    assert "printer_voxels" in py["scan"]["colour"] and "colour" not in py["mask"]
    assert len(py["mesh"]["materials"]) == 6 and py["mask"]["materials"] == {}


def test_a_turned_package_colour_through_a_chosen_profile(root, tmp_path):
    """issue 29 item 3: a colour printer's package (tests/colour/colour_package.py, written by Python):
    a <v:color> without a <v:composite>, turned 30 degrees (not axis-aligned), linear and nearest.
    hovox.load(path, icc, intent, resins) prints it through that colour map: every voxel's colour is
    the spec's sampling at its centre (the script's own sampler) and its fractions Pillow ImageCms's
    through that profile; the resins are the ones named; another profile moves the fractions."""
    script = os.path.join(root, "tests", "colour", "colour_package.py")
    make_test_data(script, "write", tmp_path, capture_output=True)
    ps = "/usr/share/color/icc/ghostscript/ps_cmyk.icc"
    means = {}
    for pkg, kw in (("turned.3mf", {}), ("turned.3mf", {"icc": ps, "resins": "C1,M1,Y1,K1,W1,X1"}),
                    ("nearest.3mf", {"intent": "relative"})):
        m = hovox.load(tmp_path / pkg, **kw)
        names = m.materials().names()
        assert names == (kw["resins"].split(",") if "resins" in kw else
                         ["VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus", "VeroPureWhite", "VeroClear"])
        tf = m.transform()
        lo = np.array(m.index_box()[0])
        occ = m.occupancy()
        rgb = np.stack([m.grid("colour." + c) for c in "rgb"], axis=-1)
        fr = m.fractions()
        voxels = []
        for ijk in np.argwhere(occ):
            centre = np.array(tf["origin"]) + (lo + ijk) * np.array(tf["voxel"])
            voxels.append([float(v) for v in centre] + [float(v) for v in rgb[tuple(ijk)]] +
                          [float(v) for v in fr[tuple(ijk)]])
        assert len(voxels) > 100
        means[(pkg, "icc" in kw)] = np.mean([v[6:] for v in voxels], axis=0)
        path = tmp_path / ("voxels_%d.json" % len(means))
        json.dump({"package": pkg, "voxels": voxels}, open(path, "w"))
        args = [a for k in ("icc", "intent") if k in kw for a in ("--" + k, kw[k])]
        make_test_data(script, "check", path, *args, capture_output=True)
    assert np.abs(means[("turned.3mf", True)] - means[("turned.3mf", False)]).max() > 0.02


def test_a_call_is_one_command(graded_gear, tmp_path):
    """A model loaded by one call may be saved over its file by the next; a call never writes over
    what it reads (a field feature's file)."""
    import shutil
    p = tmp_path / "m.vdb"
    shutil.copy(graded_gear["path"], p)
    m = hovox.load(p)
    m.add_grid("z", lambda c: c[:, 2])
    m.save(p)
    assert "z" in [g["name"] for g in hovox.load(p).grids()]
    types = {g["name"]: g["type"] for g in hovox.load(p).grids()}  # hv_grid_type_name's spellings
    assert types["z"] == "float" and types["occupancy"] == "bool"
    pin = tmp_path / "pin.stl"
    hovox.generate.cylinder(base=(0, 0, 0), axis=2, length=3, radius=2).save(pin)
    t = hovox.tray(profile="j750")
    t.add(mesh=pin, material="VeroPureWhite")
    with pytest.raises(hovox.InvalidError, match="is an input of this command"):
        t.layers(tmp_path / "stack", layers=(0, 1), arrange="all", stl=pin)  # the parts over a part's mesh
    assert hovox.load_mesh(pin).count()[0] > 0 and not (tmp_path / "stack").exists()


def test_mesh_place_as_the_command_line(tmp_path):
    """issue 27 item 3: Mesh.place takes voxelize's placement options as keywords."""
    box = hovox.generate.box(min=(0, 0, 0), max=(30, 20, 10))
    r = box.place(unit="cm", up="y").report()["bbox"]
    assert tuple(r["min"]) == pytest.approx((0, -100, 0)) and tuple(r["max"]) == pytest.approx((300, 0, 200))
    # the keys' order does not matter; rotations compose in list order
    p = box.place(translate=(1, 2, 3), rotate=["z:90", "x:90"], scale=2).report()["bbox"]
    assert tuple(p["min"]) == pytest.approx((-39, -18, 3)) and tuple(p["max"]) == pytest.approx((1, 2, 63))
    with pytest.raises(hovox.InvalidError, match="unit must be one of mm, cm, m, in, ft, um, got 'parsec'"):
        box.place(unit="parsec")
    with pytest.raises(TypeError):
        box.place("x:90")
