#!/usr/bin/env bash
# Install what curray needs to build and test, when missing, with this
# machine's package manager; where there is none (or no right to use it),
# check with pkg-config and say what is missing.
# Usage: tools/install-deps.sh [extra-package ...]
# (.ci/run adds clang, libclang-rt-<N>-dev and valgrind for its sanitizer,
# fuzzing and valgrind checks; extra packages are given to the package
# manager as they are.)
#
# Needed for `make demo`: cmake, make, a C compiler, pkg-config, libyaml,
# libpng and zlib. Everything else is optional, and the build goes without
# it: cmocka (the tests, `make test`), FFmpeg's libraries (-t v videos),
# cfitsio (-t f FITS), MPI (curray_mpi), Python 3 with venv, NumPy, pytest and
# astropy (the Python package and its tests, test_python).
#
# Package managers: apt (Debian, Ubuntu), dnf (Fedora, RHEL), pacman (Arch),
# brew (macOS, Linuxbrew). apt, dnf and pacman need root or sudo. The exit
# status is 0 when everything `make demo` needs is present afterwards (the
# optional parts that are still missing are listed), 1 when some of it is
# missing (each named, with what to install).
set -euo pipefail

# Debian: every package, as dpkg names them. FFmpeg's libraries and cfitsio
# are optional for the build but installed so that CI builds and tests the
# video and FITS outputs. openssh-client: Open MPI's mpirun looks for ssh (or
# rsh) at start-up even for ranks on one machine (only recommended by
# openmpi-bin, so --no-install-recommends would leave it out).
apt_pkgs=(cmake make gcc pkg-config libyaml-dev libpng-dev zlib1g-dev libcmocka-dev
          libavcodec-dev libavformat-dev libswscale-dev libavutil-dev
          libopenmpi-dev openmpi-bin openssh-client
          libcfitsio-dev
          python3-dev python3-venv python3-numpy python3-pytest python3-astropy python3-setuptools
          python3-wheel
          clang lld-14 wasi-libc libclang-rt-14-dev-wasm32 nodejs)
# (the last line: the WebAssembly core and its browser explorer, web/, with
# their tests under node.)
# The others: what `make demo` needs, then the optional rest.
dnf_need=(cmake make gcc pkgconf-pkg-config libyaml-devel libpng-devel zlib-devel)
dnf_opt=(libcmocka-devel ffmpeg-free-devel cfitsio-devel openmpi-devel
         python3-devel python3-numpy python3-pytest python3-astropy python3-setuptools python3-wheel)
pacman_need=(cmake make gcc pkgconf libyaml libpng zlib)
pacman_opt=(cmocka ffmpeg cfitsio openmpi python python-numpy python-pytest python-astropy
            python-setuptools python-wheel)
brew_need=(cmake pkg-config libyaml libpng zlib)
brew_opt=(cmocka ffmpeg cfitsio open-mpi python numpy)

say() { echo "curray: $*"; }

# --- what is present, by pkg-config and PATH ------------------------------
# missing_need / missing_opt: "what (how it shows)" for each absent part.
check() {
    missing_need=() missing_opt=()
    command -v cmake >/dev/null || missing_need+=("cmake")
    command -v make >/dev/null || missing_need+=("make")
    command -v cc >/dev/null || command -v gcc >/dev/null || command -v clang >/dev/null ||
        missing_need+=("a C compiler (cc, gcc or clang)")
    local pc=""
    if command -v pkg-config >/dev/null; then pc=pkg-config
    elif command -v pkgconf >/dev/null; then pc=pkgconf
    else missing_need+=("pkg-config"); fi
    have() { [ -n "$pc" ] && "$pc" --exists "$@" 2>/dev/null; }
    have yaml-0.1 || missing_need+=("libyaml (pkg-config yaml-0.1)")
    have libpng || missing_need+=("libpng (pkg-config libpng)")
    have zlib || missing_need+=("zlib (pkg-config zlib)")
    have cmocka || missing_opt+=("cmocka, for make test (pkg-config cmocka)")
    have libavcodec libavformat libswscale libavutil ||
        missing_opt+=("FFmpeg's libraries, for -t v videos (pkg-config libavcodec libavformat libswscale libavutil)")
    have cfitsio || missing_opt+=("cfitsio, for -t f FITS (pkg-config cfitsio)")
    command -v mpicc >/dev/null || missing_opt+=("MPI, for curray_mpi (mpicc)")
    if ! command -v python3 >/dev/null; then
        missing_opt+=("Python 3, for the Python package (python3)")
    elif ! python3 -c "import venv, numpy, pytest, astropy, setuptools" 2>/dev/null; then
        missing_opt+=("Python's venv, numpy, pytest, astropy or setuptools, for test_python")
    fi
}

report() { # exit status: 0 when make demo can build
    check
    local m
    for m in "${missing_opt[@]+"${missing_opt[@]}"}"; do say "optional, not found: $m"; done
    if [ ${#missing_need[@]} -gt 0 ]; then
        for m in "${missing_need[@]}"; do say "needed, not found: $m" >&2; done
        say "install those (the development packages, with their headers) and run this again;" \
            "make demo needs them" >&2
        return 1
    fi
    return 0
}

# root, or sudo; empty when neither (then nothing can be installed)
as_root() {
    if [ "$(id -u)" = 0 ]; then echo run
    elif command -v sudo >/dev/null; then echo sudo
    fi
}
run() { "$@"; }

if command -v apt-get >/dev/null && command -v dpkg-query >/dev/null; then
    pkgs=("${apt_pkgs[@]}" "$@")
    missing=()
    for p in "${pkgs[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && exit 0
    root=$(as_root)
    if [ -z "$root" ]; then
        say "not root and no sudo, so these Debian packages cannot be installed: ${missing[*]}"
        report
        exit
    fi
    say "installing missing Debian packages: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    $root apt-get update -qq
    $root apt-get install -y -qq --no-install-recommends "${missing[@]}"
    exit 0
fi

# Another package manager: install what make demo needs (must succeed), then
# the optional rest (what its repositories lack is skipped, with a word).
install_with() { # manager [extra-package ...]
    local pm=$1 root
    shift
    check
    [ ${#missing_need[@]} -eq 0 ] && [ ${#missing_opt[@]} -eq 0 ] && [ $# -eq 0 ] && return 0
    case $pm in
    brew) root=run ;;
    *) root=$(as_root) ;;
    esac
    if [ -z "$root" ]; then
        say "not root and no sudo, so $pm cannot install anything"
        return 0
    fi
    case $pm in
    dnf) need=("${dnf_need[@]}") opt=("${dnf_opt[@]}") ;;
    pacman) need=("${pacman_need[@]}") opt=("${pacman_opt[@]}") ;;
    brew) need=("${brew_need[@]}") opt=("${brew_opt[@]}") ;;
    esac
    say "installing with $pm: ${need[*]} $*"
    case $pm in
    dnf)
        $root dnf install -y "${need[@]}" "$@"
        $root dnf install -y --setopt=skip_missing_names_on_install=True "${opt[@]}" ||
            say "dnf could not install some optional packages (${opt[*]}); going on" ;;
    pacman)
        $root pacman -S --needed --noconfirm "${need[@]}" "$@"
        $root pacman -S --needed --noconfirm "${opt[@]}" ||
            say "pacman could not install some optional packages (${opt[*]}); going on" ;;
    brew)
        brew install "${need[@]}" "$@"
        brew install "${opt[@]}" || say "brew could not install some optional packages (${opt[*]}); going on" ;;
    esac
}

for pm in dnf pacman brew; do
    if command -v "$pm" >/dev/null; then
        install_with "$pm" "$@"
        report
        exit
    fi
done

say "no package manager found (apt, dnf, pacman or brew); checking with pkg-config"
[ $# -eq 0 ] || say "cannot install the extra packages asked for: $*"
report
