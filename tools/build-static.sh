#!/bin/sh
# Build curray for a GPU machine that lacks libpng, libyaml and zlib: those
# three are linked from their static archives (Debian ships libpng16.a,
# libyaml.a and libz.a in the -dev packages), the CUDA runtime is always
# static, and libstdc++/libgcc are linked statically. The result needs only
# the C library (and, to use a GPU, the NVIDIA driver's libcuda.so.1, which
# the CUDA runtime loads at run time).
#
# usage: tools/build-static.sh [build-dir]   (default: build-static)
# Extra CMake options may be given in CMAKE_ARGS, e.g.
#   CMAKE_ARGS="-DCURRAY_CUDA_ARCHS=80;86;90" tools/build-static.sh
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build-static}
case $build in /*) ;; *) build=$root/$build ;; esac

# The binary is for GPU machines, so the CUDA backend goes in whenever nvcc
# is here, whether or not this machine has a driver (CMake's AUTO would leave
# it out); CMAKE_ARGS may still say -DCURRAY_CUDA=OFF.
cuda=AUTO
if command -v nvcc >/dev/null || [ -x /usr/local/cuda/bin/nvcc ]; then cuda=ON; fi
# shellcheck disable=SC2086 # CMAKE_ARGS is a list of options
cmake -S "$root" -B "$build" -DCURRAY_STATIC=ON -DCMAKE_BUILD_TYPE=Release -DCURRAY_CUDA=$cuda ${CMAKE_ARGS:-}
cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target curray

echo "ldd $build/curray:"
ldd "$build/curray"
if ldd "$build/curray" | grep -E 'libpng|libyaml|libz\.|libcuda|libcudart|libstdc\+\+|libgcc_s'; then
    echo "build-static.sh: the binary above still needs a shared library it should not" >&2
    exit 1
fi
echo "build-static.sh: $build/curray needs only the C library"
