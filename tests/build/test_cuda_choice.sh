#!/usr/bin/env bash
# CMake's choice of the CUDA backend (CURRAY_CUDA=AUTO|ON|OFF), from the one
# STATUS line it prints: the project is configured (not built) in temporary
# folders with CURRAY_TESTS=OFF.
#
#   bash tests/build/test_cuda_choice.sh path/to/cmake [repository root]
#
#   OFF                                  not built (CURRAY_CUDA=OFF)
#   AUTO, no driver (a missing file)     not built: "no NVIDIA driver" with
#                                        nvcc, "nvcc not found" without
#   AUTO, a driver (an existing file)    built with nvcc (about 10 s of
#                                        nvcc's compiler checks), else not
#   a bad value                          refused, naming it
#   an old build folder's CURRAY_CUDA:BOOL=ON becomes AUTO
set -u
CMAKE=$1
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
. "$ROOT/tests/cli/lib.sh" test-cuda-choice
have_nvcc=no
if command -v nvcc >/dev/null || [ -x /usr/local/cuda/bin/nvcc ]; then have_nvcc=yes; fi
echo "nvcc here: $have_nvcc"
configure() { # folder, then cmake options
    local b=$1
    shift
    OUT=$("$CMAKE" -S "$ROOT" -B "$b" -DCURRAY_TESTS=OFF "$@" 2>&1)
    RC=$?
}
line() { echo "$OUT" | grep "curray: CUDA backend:" || true; }
expect() { # name, then the text the one STATUS line must hold
    local n
    n=$(line | wc -l)
    if [ $RC = 0 ] && [ "$n" = 1 ] && line | grep -qF "$2"; then ok "$1: $(line)"; else bad "$1" "rc $RC, $n lines"; fi
}

configure off -DCURRAY_CUDA=OFF
expect "OFF" "not built, CPU backend only (CURRAY_CUDA=OFF)"

configure nodriver -DCURRAY_CUDA=AUTO -DCURRAY_NVIDIA_DRIVER_FILE="$WORK/no-such-driver"
if [ $have_nvcc = yes ]; then
    expect "AUTO without a driver" "not built, CPU backend only (CURRAY_CUDA=AUTO: nvcc found"
    line | grep -q "no NVIDIA driver on this machine; -DCURRAY_CUDA=ON builds it anyway" ||
        bad "AUTO without a driver says how to build it anyway" "$(line)"
else
    expect "AUTO without nvcc" "not built, CPU backend only (nvcc not found)"
fi

echo "NVRM version: a stand-in for the kernel module's file" >driver-version
configure driver -DCURRAY_NVIDIA_DRIVER_FILE="$WORK/driver-version"
if [ $have_nvcc = yes ]; then
    expect "AUTO (the default) with a driver" "CUDA backend: built (CURRAY_CUDA=AUTO: nvcc and an NVIDIA driver ($WORK/driver-version) found"
else
    expect "AUTO with a driver but no nvcc" "not built, CPU backend only (nvcc not found)"
fi

configure badvalue -DCURRAY_CUDA=maybe
if [ $RC != 0 ] && echo "$OUT" | grep -qF "curray: CURRAY_CUDA=maybe: expected AUTO, ON or OFF"; then
    ok "a bad value is refused"
else
    bad "a bad value is refused" "rc $RC"
fi

mkdir old && printf 'CURRAY_CUDA:BOOL=ON\n' >old/CMakeCache.txt
configure old -DCURRAY_NVIDIA_DRIVER_FILE="$WORK/no-such-driver"
if [ $RC = 0 ] && grep -q "^CURRAY_CUDA:STRING=AUTO$" old/CMakeCache.txt && line | grep -q "not built"; then
    ok "an old build folder's boolean ON becomes AUTO"
else
    bad "an old build folder's boolean ON becomes AUTO" "rc $RC; $(grep CURRAY_CUDA: old/CMakeCache.txt)"
fi
finish
