"""Shared fixtures of the hovox Python tests: the CLI binary ($HOVOX, default build/hovox), the
repository root, the shared test meshes ($HOVOX_SHARED/meshes) and small models made once."""
import os
import subprocess

import pytest

import hovox

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Run the hovox CLI: cli(*args) -> CompletedProcess (text, not checked)."""
    exe = os.environ.get("HOVOX") or os.path.join(ROOT, "build", "hovox")
    assert os.access(exe, os.X_OK), "no hovox binary at %s (set HOVOX)" % exe

    def run(*args, **kw):
        return subprocess.run([exe] + [str(a) for a in args], capture_output=True, text=True, **kw)

    run.exe = exe
    return run


def make_test_data(*args, **kw):
    """Run a script that makes test data (NumPy, nibabel, Pillow: not code under test) with Debian's
    python3, checked; under `make sanitize` without the ASan preload, whose leak check would stop
    the interpreter at exit."""
    env = {k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "PYTHONMALLOC")}
    return subprocess.run(["/usr/bin/python3"] + [str(a) for a in args], check=True, env=env, **kw)


@pytest.fixture(scope="session")
def shared():
    return os.path.join(ROOT, os.environ.get("HOVOX_SHARED") or "tests/data")


@pytest.fixture(scope="session")
def gear_mesh():
    return hovox.generate.gear(teeth=24, root=34.5, tip=39.45, bore=9.54, height=39.45)


@pytest.fixture(scope="session")
def mats():
    return hovox.materials([{"name": "A", "color": "#1f77b4", "density": 1180, "youngs_modulus": 2.0e9},
                            {"name": "B", "color": "#ff7f0e"}, "C"])


def grade_gear(mesh, mats, dims=40):
    model = hovox.voxelize(mesh, dims=dims)
    obj = hovox.object(model, mats)
    obj.add_ags(feature=hovox.axis(origin=(0, 0, 0), direction=(0, 0, 1)), d_neg=9.54, d_grad=9.54, d_pos=20.37,
                f="d/dg", ms=(0, 0.9, 0.1), me=(0.9, 0, 0.1))
    obj.add_ags(feature=hovox.plane(point=(0, 0, 0), normal=(0, 0, 1)), d_neg=3.18, d_grad=22.26, d_pos=14.01,
                f="d/dg", ms=(0, 0.9, 0.1), me=(0.9, 0, 0.1))
    return model, obj, obj.evaluate()


@pytest.fixture(scope="session")
def graded_gear(gear_mesh, mats, tmp_path_factory):
    """A small graded gear (40 voxels across), its .vdb file and its voxelized model."""
    model, obj, graded = grade_gear(gear_mesh, mats)
    path = str(tmp_path_factory.mktemp("gear") / "gear.vdb")
    graded.save(path)
    return {"model": model, "object": obj, "graded": graded, "path": path}
