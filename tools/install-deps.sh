#!/usr/bin/env bash
# Install the Debian packages curray needs to build and test, when missing.
# Usage: tools/install-deps.sh [extra-package ...]
# (.ci/run adds clang, libclang-rt-<N>-dev and valgrind for its sanitizer,
# fuzzing and valgrind checks.)
set -euo pipefail
# FFmpeg's libraries are optional for the build (-t v videos) but installed
# here so that CI builds and tests the video output. cfitsio (-t f FITS) likewise.
# Python 3 with venv, NumPy, pytest and astropy: the Python package and its
# tests (test_python). openssh-client: Open MPI's mpirun looks for ssh (or
# rsh) at start-up even for ranks on one machine (only recommended by
# openmpi-bin, so --no-install-recommends would leave it out).
pkgs=(cmake make gcc pkg-config libyaml-dev libpng-dev zlib1g-dev libcmocka-dev
      libavcodec-dev libavformat-dev libswscale-dev libavutil-dev
      libopenmpi-dev openmpi-bin openssh-client
      libcfitsio-dev
      python3-dev python3-venv python3-numpy python3-pytest python3-astropy python3-setuptools
      python3-wheel
      clang lld-14 wasi-libc libclang-rt-14-dev-wasm32 nodejs "$@")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "curray: installing missing Debian packages: ${missing[*]}"
sudo=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null || { echo "curray: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
