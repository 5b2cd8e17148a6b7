"""The README's install commands, verbatim, as on a fresh Debian 12 (a fresh HOME; another
python3 first on PATH, as pyenv puts one, that the commands must not take: they name Debian's):
pip builds the package offline with Debian's setuptools into a virtual environment that sees
Debian's NumPy, and the installed package works from its own directory, loading the plugins it
carries."""
import os
import re
import shutil
import subprocess

import pytest


def readme_block(root, marker):
    with open(os.path.join(root, "README.md"), encoding="utf-8") as f:
        m = re.search(r"<!-- %s -->\n```[a-z]*\n(.*?)```" % re.escape(marker), f.read(), re.S)
    assert m, "README has no block marked %s" % marker
    return m.group(1)


@pytest.mark.skipif(not os.path.exists("/usr/bin/python3"), reason="needs Debian's python3")
def test_readme_install_commands_verbatim(root, tmp_path):
    script = readme_block(root, "python-install")
    home = tmp_path / "home"
    home.mkdir()
    decoy = tmp_path / "decoy"
    decoy.mkdir()
    (decoy / "python3").write_text("#!/bin/sh\necho 'a python3 without NumPy (pyenv): not the one to take' >&2\nexit 1\n")
    (decoy / "python3").chmod(0o755)
    env = {"HOME": str(home), "PATH": str(decoy) + ":/usr/bin:/bin", "LANG": "C.UTF-8", "PIP_NO_INDEX": "1",
           "PIP_DISABLE_PIP_VERSION_CHECK": "1"}
    r = subprocess.run(["sh", "-e", "-c", script], cwd=root, env=env, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    py = home / ".venvs" / "hovox" / "bin" / "python"
    assert r.stdout.strip().splitlines()[-1] == subprocess.run(
        [str(py), "-c", "import hovox; print(hovox.version)"], env=env, capture_output=True, text=True).stdout.strip()
    # from another directory: the installed copy, with its plugins (the OpenVDB one writes .vdb)
    check = (
        "import hovox, os\n"
        "assert os.path.dirname(hovox.__file__).startswith(os.environ['HOME']), hovox.__file__\n"
        "m = hovox.voxelize(hovox.generate.sphere(), dims=16)\n"
        "m.save('s.vdb')\n"
        "maps = open('/proc/self/maps').read()\n"
        "lib = [l.split()[-1] for l in maps.splitlines() if l.endswith('hovox-vdb.so')][0]\n"
        "assert lib == os.path.join(os.path.dirname(hovox.__file__), 'plugins', 'hovox-vdb.so'), lib\n"
        "print(hovox.load('s.vdb').voxels())\n")
    work = tmp_path / "work"
    work.mkdir()
    r = subprocess.run([str(py), "-c", check], cwd=work, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert int(r.stdout) > 0
    shutil.rmtree(home / ".venvs")


def test_extension_not_older_than_the_library(cli):
    """`make python` relinks the extension when only libhovox.a changed (setup.py lists the library
    among the extension's dependencies): an extension older than the library it links is stale and
    makes false differences between the CLI and Python."""
    import hovox._hovox
    lib = os.path.join(os.path.dirname(cli.exe), "libhovox.a")
    if not os.path.exists(lib):
        pytest.skip("no libhovox.a beside %s" % cli.exe)
    assert os.path.getmtime(hovox._hovox.__file__) >= os.path.getmtime(lib), (hovox._hovox.__file__, lib)
