#!/usr/bin/env bash
# CTest's test_python: the Python package (python/) built and tested with
# pytest in a virtual environment.
#   tests/python/run.sh <build folder> <curray binary> [<ON|OFF> <libcurray_gpu.a>]
# The environment is <build folder>/pyenv, made on first use with the system
# Python's packages visible (--system-site-packages: numpy, pytest, astropy
# from Debian, installed by tools/install-deps.sh); the package is built from
# a copy of python/ inside the build folder (the source tree stays clean) and
# installed into it on every run, so the test sees the current C sources.
# With ON (the CMake build has CUDA) the package links that build's CUDA
# backend, libcurray_gpu.a (python/setup.py CURRAY_GPU_LIB: no second nvcc
# compile, about a minute); with OFF it is built without CUDA, as the
# command line was (CURRAY_CUDA=0).
# Anything missing is a FAILURE with the reason, never a silent pass.
set -euo pipefail
fail() { echo "test_python FAILED: $*" >&2; exit 1; }
build=$(cd "$1" && pwd)
bin=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
cuda=()
case "${3:-OFF}" in
  ON) [ -f "${4:-}" ] || fail "the CUDA backend library '${4:-}' was not built"
      cuda=(CURRAY_CUDA=1 "CURRAY_GPU_LIB=$(cd "$(dirname "$4")" && pwd)/$(basename "$4")") ;;
  *) cuda=(CURRAY_CUDA=0) ;;
esac
src=$(cd "$(dirname "$0")/../.." && pwd)
py=${CURRAY_PYTHON:-}
if [ -z "$py" ]; then
  if [ -x /usr/bin/python3 ]; then py=/usr/bin/python3; else py=$(command -v python3 || true); fi
fi
[ -n "$py" ] || fail "no python3 found (Debian: python3; run tools/install-deps.sh)"
venv=$build/pyenv
if [ ! -x "$venv/bin/python" ]; then
  "$py" -m venv --system-site-packages "$venv" ||
    fail "cannot create a virtual environment with $py (Debian: python3-venv; tools/install-deps.sh)"
fi
"$venv/bin/python" -c "import numpy, pytest, astropy, setuptools" ||
  fail "the environment $venv lacks numpy, pytest, astropy or setuptools (Debian: python3-numpy python3-pytest python3-astropy python3-setuptools; tools/install-deps.sh)"
rm -rf "$build/python-src"
cp -r "$src/python" "$build/python-src"
rm -rf "$build/python-src/build" "$build/python-src"/*.egg-info
env "${cuda[@]}" CURRAY_SOURCE_DIR="$src" "$venv/bin/python" -m pip install -q \
  --no-build-isolation --no-deps --no-index "$build/python-src" || fail "pip could not build and install python/"
cd "$build"
CURRAY_BIN=$bin CURRAY_SOURCE_DIR=$src PYTHONDONTWRITEBYTECODE=1 \
  exec "$venv/bin/python" -m pytest -q -p no:cacheprovider "$src/tests/python"
