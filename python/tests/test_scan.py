"""Scanned volumes from Python (issue 30 item 3): hovox.layers_scan prints a volume as `hovox layers VOLUME`
does, the same bytes (every layer and the manifest), straight from its data and through its model with a
clean-up; a colour table reports its dE2000; refusals are the library's."""
import filecmp
import os
import subprocess

import pytest

import hovox
from conftest import make_test_data

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


@pytest.fixture(scope="module")
def phantom(tmp_path_factory):
    d = tmp_path_factory.mktemp("ph")
    make_test_data(os.path.join(ROOT, "tests/io/scan/make_phantom.py"), d, "--size", "20,24,18", "--spacing", "4,4,6",
                   "--formats", "nii", stdout=subprocess.DEVNULL)
    (d / "bone.csv").write_text("HU,VeroClear,Agilus30,VeroWhite\n-1000,1,0,0\n0,0,1,0\n300,0,1,0\n1000,0,0,1\n")
    (d / "col.csv").write_text("HU,colour\n-1000,#ffffff00\n30,#d08070\n1000,#f0f0e0\n")
    return d


def same_stack(a, b):
    names = sorted(os.listdir(a))
    assert names == sorted(os.listdir(b))
    assert len(names) > 10
    for n in names:
        assert filecmp.cmp(os.path.join(a, n), os.path.join(b, n), shallow=False), n


@pytest.mark.parametrize("case", [
    (["--iso", "-480", "--lut", "bone.csv"], dict(iso=-480, lut="bone.csv")),
    (["--range", "-480,500", "--lut", "col.csv", "--intent", "relative"],
     dict(range=(-480, 500), lut="col.csv", intent="relative")),
    (["--labels", "1000,30", "--lut", "bone.csv", "--keep-largest"], dict(labels=[1000, 30], lut="bone.csv",
                                                                          keep_largest=True)),
])
def test_layers_scan_gives_the_cli_bytes(phantom, tmp_path, case):
    cli, kw = case
    vol = str(phantom / "phantom.nii")
    args = [a if not a.endswith(".csv") else str(phantom / a) for a in cli]
    subprocess.run([os.environ["HOVOX"], "layers", vol] + args + ["--dpi", "100,100", "--layer-height", "2", "-o",
                    str(tmp_path / "cli"), "-q"], check=True, stdout=subprocess.DEVNULL)
    kw = dict(kw, lut=str(phantom / kw["lut"]))
    r = hovox.layers_scan(vol, tmp_path / "py", dpi=(100, 100), layer_height=2, **kw)
    same_stack(tmp_path / "cli", tmp_path / "py")
    assert r["object_pixels"] > 0 and r["layers"] == r["last"]
    assert set(r["materials"]) in ({"VeroClear", "Agilus30", "VeroWhite"},
                                   {"VeroCyan-V", "VeroMagenta-V", "VeroYellow-V", "VeroBlackPlus", "VeroPureWhite",
                                    "VeroClear"})
    if kw["lut"].endswith("col.csv"):
        assert r["colour"]["printer_voxels"] == r["object_pixels"]
        assert 0 < r["colour"]["mean_de2000_target"] <= r["colour"]["max_de2000_target"]
    else:
        assert "colour" not in r


def test_layers_scan_refusals(phantom, tmp_path):
    vol = str(phantom / "phantom.nii")
    with pytest.raises(hovox.InvalidError, match="one of iso, range or labels"):
        hovox.layers_scan(vol, tmp_path / "a", lut=str(phantom / "bone.csv"))
    with pytest.raises(hovox.InvalidError, match="materials come from lut"):
        hovox.layers_scan(vol, tmp_path / "b", iso=1)
    with pytest.raises(hovox.InvalidError, match="labels"):
        hovox.layers_scan(vol, tmp_path / "c", labels=[], mode="mask")
    with pytest.raises(hovox.FileError):
        hovox.layers_scan(str(phantom / "none.nii"), tmp_path / "d", iso=1, mode="mask")
    assert not os.path.exists(tmp_path / "d")
