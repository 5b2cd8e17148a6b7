"""Wu's three examples written in Python (samples/python/) give models byte-identical to the Lua
samples' (samples/*.lua) except for the .vdb header's random UUID, checked to be the only
difference; the README's Python example runs verbatim."""
import os
import re
import subprocess
import sys

import pytest

SAMPLES = ["wu_gear", "wu_mmo", "wu_shaft"]


def sample_args(path):
    with open(path, encoding="utf-8") as f:
        m = re.search(r"^(?:--|#) test-args: (.*)$", f.read(), re.M)
    return m.group(1).split() if m else []


def env():
    e = dict(os.environ)
    e["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    return e


def uuid_span(data):
    """The header's UUID: 36 ASCII characters 8-4-4-4-12 hex digits after the fixed fields."""
    m = re.search(rb"[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}", data[:64])
    assert m, "no UUID in the header"
    return m.span()


@pytest.mark.parametrize("name", SAMPLES)
def test_python_sample_models_equal_lua_samples(name, root, cli, tmp_path):
    lua, py = os.path.join(root, "samples", name + ".lua"), os.path.join(root, "samples", "python", name + ".py")
    args = sample_args(lua)
    assert sample_args(py) == args, "the Python sample names other test arguments than the Lua one"
    lo, po = tmp_path / "lua", tmp_path / "py"
    lo.mkdir()
    po.mkdir()
    r = cli("run", lua, lo, *args, cwd=root)
    assert r.returncode == 0, r.stderr
    p = subprocess.run([sys.executable, py, str(po)] + args, capture_output=True, text=True, cwd=root, env=env())
    assert p.returncode == 0, p.stderr
    assert "outputs in" in p.stdout
    vdbs = sorted(f for f in os.listdir(lo) if f.endswith(".vdb"))
    assert vdbs and vdbs == sorted(f for f in os.listdir(po) if f.endswith(".vdb"))
    for f in vdbs:
        a, b = (lo / f).read_bytes(), (po / f).read_bytes()
        assert len(a) == len(b), f
        sa, sb = uuid_span(a), uuid_span(b)
        assert sa == sb and a[:sa[0]] == b[:sb[0]], f
        assert a[sa[1]:] == b[sb[1]:], "%s differs after the header's UUID" % f
    # the same printed figures (probes and stack statistics) where both print them
    # (Lua prints a refusal as "bad argument #1 to 'hovox.ags' (MESSAGE)", Python as MESSAGE)
    lua_lines = {re.sub(r"bad argument #\d+ to '[^']*' \((.*)\)$", r"\1", l) for l in r.stdout.splitlines()
                 if not l.startswith("outputs in")}
    py_lines = set(p.stdout.splitlines())
    assert lua_lines <= py_lines, lua_lines - py_lines
    # and the same CSV profiles
    for f in sorted(x for x in os.listdir(lo) if x.endswith(".csv")):
        assert (lo / f).read_bytes() == (po / f).read_bytes(), f


def readme_block(root, marker):
    with open(os.path.join(root, "README.md"), encoding="utf-8") as f:
        text = f.read()
    m = re.search(r"<!-- %s -->\n```[a-z]*\n(.*?)```" % re.escape(marker), text, re.S)
    assert m, "README has no block marked %s" % marker
    return m.group(1)


def test_readme_python_example_runs_verbatim(root, tmp_path):
    code = readme_block(root, "python-example")
    script = tmp_path / "example.py"
    script.write_text(code)
    p = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, cwd=root, env=env())
    assert p.returncode == 0, p.stderr
    for f in ("gear.vdb", "radial.csv", "radial.png", "cut.png"):
        assert (tmp_path / f).stat().st_size > 0, f


def test_lua_models_do_not_depend_on_the_hash_seed(cli, tmp_path):
    """A Lua table's traversal order follows a hash seed that changes from run to run; a material's
    properties are stored in key order, so the same script writes the same model every run, and
    the same as Python writes from a dict in any order."""
    script = tmp_path / "m.lua"
    script.write_text(
        "local mats = hovox.materials{ {name = 'A', density = 1180, youngs_modulus = 2e9, poisson_ratio = 0.38,\n"
        "    shore_a = 60, thermal_k = 0.2, cte = 1e-4}, 'B' }\n"
        "local m = hovox.voxelize(hovox.generate.box{}, {dims = 8})\n"
        "hovox.object(m, mats):evaluate():save(arg[1])\n")
    runs = []
    for i in range(6):
        out = tmp_path / ("lua%d.vdb" % i)
        r = cli("run", script, out)
        assert r.returncode == 0, r.stderr
        runs.append(out.read_bytes())
    import hovox
    mats = hovox.materials([{"cte": 1e-4, "name": "A", "thermal_k": 0.2, "poisson_ratio": 0.38, "shore_a": 60,
                             "youngs_modulus": 2e9, "density": 1180}, "B"])
    hovox.object(hovox.voxelize(hovox.generate.box(), dims=8), mats).evaluate().save(tmp_path / "py.vdb")
    runs.append((tmp_path / "py.vdb").read_bytes())
    tails = {data[uuid_span(data)[1]:] for data in runs}
    assert len(tails) == 1
