"""Build curray's C extension from the repository's own sources.

The extension compiles the same files as the command line's library
(src/core headers, the scene/configuration loaders and the CPU backend),
so ``pip install ./python`` needs the repository around this folder and the
libraries the command line links: libyaml, libpng, zlib (Debian:
libyaml-dev libpng-dev zlib1g-dev; tools/install-deps.sh installs them).
"""
import os
import re

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
# the repository: around this folder, or CURRAY_SOURCE_DIR for a copy of it
# built elsewhere (tests/python/run.sh builds a copy inside the build folder)
ROOT = os.environ.get("CURRAY_SOURCE_DIR") or os.path.dirname(HERE)
SRC = os.path.join(ROOT, "src")


def version():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as fp:
        m = re.search(r"project\(curray VERSION ([0-9.]+)", fp.read())
    return m.group(1) if m else "0"


LIB_SOURCES = [
    "io/error.c", "io/scene.c", "io/yamlutil.c", "io/sysconfig.c", "io/png_io.c",
    "io/fsutil.c", "io/atomic.c", "io/info.c", "io/log.c", "io/raypath.c", "io/output.c",
    "cpu/render_cpu.c",
]

ext = Extension(
    "curray._curray",
    sources=["curray/_curray.c"],
    include_dirs=[SRC],
    define_macros=[("_POSIX_C_SOURCE", "200809L"), ("CURRAY_VERSION", '"%s"' % version())],
    # the command line's Release flags (CMake: -O3 -DNDEBUG), after Python's own
    extra_compile_args=["-std=c11", "-O3", "-DNDEBUG", "-Wall", "-Wextra",
                        "-Wno-missing-field-initializers", "-Wno-cast-function-type"],
    libraries=["yaml", "png", "z", "m", "pthread"],
)

class BuildExt(build_ext):
    """Adds the repository's C sources (outside this folder, so absolute
    paths, which setuptools refuses in setup() arguments) at build time."""

    def build_extension(self, e):
        e.sources = list(e.sources) + [os.path.join(SRC, s) for s in LIB_SOURCES]
        super().build_extension(e)


setup(version=version(), ext_modules=[ext], cmdclass={"build_ext": BuildExt})
