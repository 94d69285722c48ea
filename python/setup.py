"""Build curray's C extension from the repository's own sources.

The extension compiles the same files as the command line's library
(src/core headers, the scene/configuration loaders, the CPU backend, the
backend interface and the frame stack),
so ``pip install ./python`` needs the repository around this folder and the
libraries the command line links: libyaml, libpng, zlib (Debian:
libyaml-dev libpng-dev zlib1g-dev; tools/install-deps.sh installs them).

The CUDA backend (src/render/gpu.cu) goes in, as in the CMake build's
CURRAY_CUDA=AUTO, when nvcc is found and this machine has an NVIDIA driver
(so pip spends no nvcc time where no GPU can run it); environment variables
choose otherwise:
  CURRAY_CUDA=0      the CPU only (src/render/gpu_stub.c: backend="cuda" says
                     the build has no CUDA); =1: CUDA whenever nvcc is found,
                     or fail; unset or auto: nvcc (PATH, $CUDA_HOME/bin,
                     /usr/local/cuda/bin) and a driver (/proc/driver/nvidia/
                     version, else libcuda.so.1 known to the loader)
  CURRAY_NVIDIA_DRIVER_FILE  the file that stands for the driver (tests)
  CURRAY_CUDA_ARCHS  "80;90" (the default, CMake's): SASS for each, PTX for
                     the newest
  CURRAY_GPU_LIB     a libcurray_gpu.a built by CMake with CUDA (position-
                     independent): linked instead of compiling gpu.cu again
                     (nvcc takes about a minute; tests/python/run.sh uses it)
"""
import os
import re
import shutil
import subprocess

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
    "base/error.c", "base/fsutil.c", "base/atomic.c", "base/log.c", "base/memcheck.c",
    "base/png_io.c",
    "base/shortest.c",
    "input/names.c", "input/scene_parse.c", "input/scene_eval.c", "input/settings.c",
    "input/yamlutil.c", "input/sysconfig.c", "input/particle_spec.c",
    "output/info.c", "output/raypath.c", "output/output.c", "output/spectrum.c", "output/worldline.c",
    "output/orbit_picture.c",
    "render/cpu.c", "render/backend.c", "render/run.c",
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

def env_switch(name):
    """None (unset or "auto"), True or False from an environment variable."""
    v = os.environ.get(name, "").strip().lower()
    if v in ("", "auto"):
        return None
    if v in ("1", "on", "yes", "true"):
        return True
    if v in ("0", "off", "no", "false"):
        return False
    raise SystemExit("curray setup.py: %s=%r: expected 0, 1 or auto" % (name, v))


def find_nvcc():
    for d in (os.environ.get("CUDA_HOME"), os.environ.get("CUDA_PATH")):
        if d and os.access(os.path.join(d, "bin", "nvcc"), os.X_OK):
            return os.path.join(d, "bin", "nvcc")
    nvcc = shutil.which("nvcc")
    if nvcc:
        return nvcc
    return "/usr/local/cuda/bin/nvcc" if os.access("/usr/local/cuda/bin/nvcc", os.X_OK) else None


def cudart_static(nvcc):
    """The static CUDA runtime of nvcc's toolkit (the command line links it
    too: the extension then needs only the driver, libcuda.so.1)."""
    root = os.path.dirname(os.path.dirname(os.path.realpath(nvcc)))
    for sub in ("lib64", "lib", os.path.join("targets", "x86_64-linux", "lib"),
                os.path.join("targets", "sbsa-linux", "lib")):
        p = os.path.join(root, sub, "libcudart_static.a")
        if os.path.exists(p):
            return p
    raise SystemExit("curray setup.py: no libcudart_static.a under %s (set CURRAY_CUDA=0 to "
                     "build without CUDA)" % root)


def cuda_archs():
    """CMake's CURRAY_CUDA_ARCHS: nvcc -gencode flags and gpu_config.h."""
    archs = [a for a in os.environ.get("CURRAY_CUDA_ARCHS", "80;90").replace(",", ";").split(";")
             if a.strip()]
    if not archs or not all(re.match(r"^[0-9]+$", a.strip()) for a in archs):
        raise SystemExit("curray setup.py: CURRAY_CUDA_ARCHS=%r: expected numbers like 80;90"
                         % os.environ.get("CURRAY_CUDA_ARCHS"))
    archs = sorted({int(a) for a in archs})
    for a in archs:
        if a < 70:
            raise SystemExit("curray setup.py: CUDA architecture %d is older than 7.0 (Volta), "
                             "which the kernel needs (__grid_constant__)" % a)
    flags = ["--generate-code=arch=compute_%d,code=[sm_%d]" % (a, a) for a in archs]
    flags.append("--generate-code=arch=compute_%d,code=[compute_%d]" % (archs[-1], archs[-1]))
    config = ("/* Written by python/setup.py (as CMake writes it from gpu_config.h.in). */\n"
              "#ifndef CR_CUDA_GPU_CONFIG_H\n#define CR_CUDA_GPU_CONFIG_H\n"
              "#define CR_GPU_SASS_ARCHS {%s0}\n#define CR_GPU_PTX_ARCHS {%d, 0}\n"
              "#define CR_GPU_ARCHS_TEXT \"%s compute_%d (PTX)\"\n#define CR_GPU_FMAD 1\n"
              "#define CR_GPU_REGCAP_TEXT \"\"\n#endif\n"
              % ("".join("%d, " % a for a in archs), archs[-1],
                 " ".join("sm_%d" % a for a in archs), archs[-1]))
    return flags, config


def find_driver():
    """Where an NVIDIA driver shows, or None: the kernel module's version file
    (CURRAY_NVIDIA_DRIVER_FILE stands in for it), else the driver library
    libcuda.so.1 that the loader can open. (Not ctypes.util.find_library:
    it also finds the toolkit's stubs/libcuda.so, which runs nothing.)"""
    f = os.environ.get("CURRAY_NVIDIA_DRIVER_FILE", "/proc/driver/nvidia/version")
    if os.path.exists(f):
        return f
    if "CURRAY_NVIDIA_DRIVER_FILE" in os.environ:
        return None
    import ctypes
    try:
        ctypes.CDLL("libcuda.so.1")
    except OSError:
        return None
    return "libcuda.so.1"


def cuda_choice(want, lib, nvcc, driver):
    """(compile or link CUDA?, why) from CURRAY_CUDA (None: auto, True, False),
    CURRAY_GPU_LIB, nvcc's path and the driver's (None when not found); the
    why is the one line setup.py prints. Raises SystemExit when CUDA is asked
    for (CURRAY_CUDA=1 or CURRAY_GPU_LIB) but nvcc is missing."""
    if want is False:
        return False, "CURRAY_CUDA=0"
    if (want or lib) and not nvcc:
        raise SystemExit("curray setup.py: CURRAY_CUDA=1 or CURRAY_GPU_LIB but nvcc (and "
                         "its CUDA runtime) was not found (PATH, $CUDA_HOME/bin, "
                         "/usr/local/cuda/bin)")
    if want:
        return True, "CURRAY_CUDA=1"
    if lib:
        return True, "CURRAY_GPU_LIB=%s" % lib
    if not nvcc:
        return False, "nvcc not found"
    if not driver:
        return False, ("CURRAY_CUDA unset: nvcc found (%s) but no NVIDIA driver on this machine; "
                       "CURRAY_CUDA=1 builds it anyway" % nvcc)
    return True, "CURRAY_CUDA unset: nvcc and an NVIDIA driver (%s) found" % driver


class BuildExt(build_ext):
    """Adds the repository's C sources (outside this folder, so absolute
    paths, which setuptools refuses in setup() arguments) at build time, and
    the CUDA backend or its stub (see the top of this file)."""

    def build_extension(self, e):
        e.sources = list(e.sources) + [os.path.join(SRC, s) for s in LIB_SOURCES]
        want = env_switch("CURRAY_CUDA")
        lib = os.environ.get("CURRAY_GPU_LIB")
        nvcc = find_nvcc() if want is not False else None
        use, why = cuda_choice(want, lib, nvcc,
                               find_driver() if nvcc and want is None and not lib else None)
        print("curray: CUDA backend: %s (%s)" % ("built" if use else "not built, CPU backend only",
                                                 why))
        if not use:
            nvcc = None
        if nvcc and lib:
            e.extra_objects = list(e.extra_objects) + [os.path.abspath(lib)]
        elif nvcc:
            e.sources.append(os.path.join(SRC, "render", "gpu_select.c"))
            e.extra_objects = list(e.extra_objects) + [self.nvcc_compile(nvcc)]
        else:
            e.sources += [os.path.join(SRC, "render", s) for s in ("gpu_stub.c", "gpu_select.c")]
        if nvcc:
            e.extra_objects.append(cudart_static(nvcc))
            e.libraries = list(e.libraries) + ["dl", "rt", "stdc++"]
        super().build_extension(e)

    def nvcc_compile(self, nvcc):
        """gpu.cu with the CMake build's flags (Release, no fast math), as
        position-independent code for the shared extension."""
        flags, config = cuda_archs()
        out = os.path.join(os.path.abspath(self.build_temp), "curray_cuda")
        os.makedirs(out, exist_ok=True)
        with open(os.path.join(out, "gpu_config.h"), "w") as fp:
            fp.write(config)
        obj = os.path.join(out, "gpu.o")
        cmd = [nvcc, "-O3", "-DNDEBUG", "-D_POSIX_C_SOURCE=200809L",
               '-DCURRAY_VERSION="%s"' % version(), "-I" + out, "-I" + SRC] + flags + [
               "-Xcompiler=-fPIC,-Wall,-Wextra", "-c", os.path.join(SRC, "render", "gpu.cu"),
               "-o", obj]
        print("curray: compiling the CUDA backend (about a minute): " + " ".join(cmd))
        subprocess.check_call(cmd)
        return obj


setup(version=version(), ext_modules=[ext], cmdclass={"build_ext": BuildExt})
