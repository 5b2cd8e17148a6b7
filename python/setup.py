"""Build of the hovox Python package: the extension hovox._hovox (python/src/*.c) linked with the
repository's static library (build/libhovox.a, made by `make` first when missing), and the
C++ bridge plugins (build/plugins/*.so) copied into the package, where the library looks for them
(beside the file that holds it). Environment: HOVOX_BUILD (the build directory, default
<repository>/build), HOVOX_SAN=1 (ASan + UBSan, with `make sanitize`), HOVOX_WERROR=1."""
import glob
import os
import re
import shlex
import shutil
import subprocess

import numpy
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BUILD = os.path.abspath(os.environ.get("HOVOX_BUILD") or os.path.join(ROOT, "build"))
SAN = os.environ.get("HOVOX_SAN") == "1"
WERROR = os.environ.get("HOVOX_WERROR") == "1"


def make(*args):
    """Run the repository's Makefile with this build's directory and flags."""
    cmd = ["make", "--no-print-directory", "-C", ROOT, "BUILD=" + os.path.relpath(BUILD, ROOT)]
    if SAN:
        cmd.append("SAN=1")
    return subprocess.run(cmd + list(args), check=True, stdout=subprocess.PIPE, text=True).stdout


def version():
    with open(os.path.join(ROOT, "include", "hovox", "core.h"), encoding="utf-8") as f:
        return re.search(r'#define HV_VERSION_STRING "([^"]+)"', f.read()).group(1)


class BuildExt(build_ext):
    def run(self):
        # the library and its plugins, built by the Makefile when missing (`make python` keeps
        # them current; a build with other flags is not redone here)
        plugins = glob.glob(os.path.join(BUILD, "plugins", "*.so"))
        if not os.path.exists(os.path.join(BUILD, "libhovox.a")) or not plugins:
            make(os.path.relpath(os.path.join(BUILD, "libhovox.a"), ROOT), "plugins")
        libs = shlex.split(make("-s", "print-LIBS").strip())
        for ext in self.extensions:
            ext.extra_objects = [os.path.join(BUILD, "libhovox.a")]
            ext.extra_link_args = libs
            # build_ext relinks only when a source or a dependency is newer than the extension, and
            # extra_objects are not among them: a library changed alone left a stale extension
            ext.depends = list(ext.depends) + ext.extra_objects
        super().run()
        for ext in self.extensions:
            dest = os.path.join(os.path.dirname(self.get_ext_fullpath(ext.name)), "plugins")
            os.makedirs(dest, exist_ok=True)
            for p in glob.glob(os.path.join(BUILD, "plugins", "*.so")):
                shutil.copy2(p, dest)


cflags = ["-std=gnu11", "-Wall", "-Wextra", "-Wshadow", "-Wno-missing-field-initializers", "-Wno-cast-function-type",
          "-fvisibility=hidden", "-g"]
if WERROR:
    cflags.append("-Werror")
if SAN:
    cflags += ["-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=undefined", "-O1"]

setup(
    version=version(),
    ext_modules=[
        Extension(
            "hovox._hovox",
            sources=sorted(glob.glob(os.path.join("src", "*.c"))),
            depends=[os.path.join("src", "hvpy.h")] + glob.glob(os.path.join(ROOT, "include", "hovox", "*.h")),
            include_dirs=[os.path.join(ROOT, "include"), numpy.get_include()],
            extra_compile_args=cflags,
        )
    ],
    cmdclass={"build_ext": BuildExt},
)
