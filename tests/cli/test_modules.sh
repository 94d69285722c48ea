#!/usr/bin/env bash
# The output modules (src/output/module.h): the video writer (FFmpeg) and the
# FITS writer (cfitsio) are loaded only by a run that asks for -t v / -t f.
#
#   bash tests/cli/test_modules.sh path/to/curray build-folder fake-other-dir fake-gone-dir [root]
#
# build-folder holds curray_video.so and curray_fits.so (beside curray);
# fake-other-dir a curray_video.so of "another build" (tests/modules/
# fake_module.c), fake-gone-dir a curray_fits.so that needs a library the
# loader cannot find (libcr_gone.so). Checked:
# - curray itself needs neither FFmpeg nor cfitsio (ldd), the modules do;
# - a -t ic run loads neither module nor any of their libraries (LD_DEBUG=files
#   of the dynamic loader: every object it maps), while -t icv loads
#   curray_video.so and libavformat (not cfitsio) and writes c.mp4, and -t icf
#   loads curray_fits.so and libcfitsio (not FFmpeg) and writes f_<k>.fits;
# - with CURRAY_MODULE_DIR pointing at an empty folder, -t v and -t f are
#   refused before anything is traced or made (-t f, checked with the
#   options, as a usage error: exit status 2; -t v with the output folder:
#   1), naming the module and where it was looked for, while -t ic still renders; a module whose library is
#   missing is refused naming that library; a module of another build is
#   refused naming its version. About 3 s.
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
BUILD=$(cd "$2" && pwd)
OTHER=$(cd "$3" && pwd)
GONE=$(cd "$4" && pwd)
ROOT=$(cd "${5:-$(dirname "$0")/../..}" && pwd)
. "$(dirname "$0")/lib.sh" test-modules
cp "$ROOT/scenes/demo.yml" scene.yml

# the objects the dynamic loader mapped in the last ldrun: file=NAME lines
ldrun() { # DIR ARGS...: run curray writing into DIR with LD_DEBUG=files
    local d=$1
    shift
    rm -f ld.*
    OUT=$(LD_DEBUG=files LD_DEBUG_OUTPUT=$WORK/ld timeout 120 "$CURRAY" -s scene.yml -o "$d" \
          -x 32 -y 24 -a "$@" </dev/null 2>&1)
    RC=$?
    LOADED=$(cat ld.* 2>/dev/null | sed -n 's/.*file=\([^ ;]*\).*/\1/p' | sort -u)
}
loaded() { echo "$LOADED" | grep -q -- "$1"; }

L=$(ldd "$CURRAY")
if ! echo "$L" | grep -qE 'libav|libswscale|libcfitsio' &&
   ldd "$BUILD/curray_video.so" | grep -q libavformat &&
   ldd "$BUILD/curray_fits.so" | grep -q libcfitsio; then
    ok "curray needs neither FFmpeg nor cfitsio (ldd: $(echo "$L" | wc -l) objects); its modules do"
else
    bad "ldd curray" "$(echo "$L" | grep -E 'libav|libswscale|libcfitsio')"
fi

ldrun c -t ic
if [ $RC = 0 ] && [ -s c/c_0.png ] && [ -n "$LOADED" ] && loaded libyaml &&
   ! loaded curray_video && ! loaded curray_fits && ! loaded libav && ! loaded libcfitsio; then
    ok "-t ic maps no module and no FFmpeg or cfitsio library ($(echo "$LOADED" | wc -l) objects)"
else
    bad "-t ic loads nothing it does not need" "rc $RC; $(echo "$LOADED" | grep -E 'curray_|libav|cfitsio' | tr '\n' ' ')"
fi

ldrun v -t icv -f 2
if [ $RC = 0 ] && [ "$(head -c 8 v/c.mp4 | tail -c 4)" = ftyp ] && [ -s v/c_1.png ] &&
   loaded curray_video.so && loaded libavformat && ! loaded libcfitsio && ! loaded curray_fits; then
    ok "-t icv loads curray_video.so and FFmpeg (not cfitsio) and writes c.mp4"
else
    bad "-t icv" "rc $RC"
fi

ldrun f -t icf -f 2
if [ $RC = 0 ] && [ "$(head -c 9 f/f_1.fits)" = "SIMPLE  =" ] && [ -s f/f_0.fits ] &&
   loaded curray_fits.so && loaded libcfitsio && ! loaded libav && ! loaded curray_video; then
    ok "-t icf loads curray_fits.so and cfitsio (not FFmpeg) and writes f_0.fits, f_1.fits"
else
    bad "-t icf" "rc $RC"
fi

mkdir empty
export CURRAY_MODULE_DIR=$WORK/empty
run -s scene.yml -o nov -x 32 -y 24 -a -t icv
if [ $RC = 1 ] && has "-t v: cannot load curray's video module: curray_video.so is not in $WORK/empty" &&
   has CURRAY_MODULE_DIR && [ ! -e nov ]; then
    ok "-t v without its module: refused before tracing, naming the module and the folder"
else
    bad "-t v without its module" "rc $RC"
fi
run -s scene.yml -o nof -x 32 -y 24 -a -t icf
if [ $RC = 2 ] && has "-t f: cannot load curray's FITS module: curray_fits.so is not in $WORK/empty" &&
   [ ! -e nof ]; then
    ok "-t f without its module: refused before tracing, naming the module and the folder"
else
    bad "-t f without its module" "rc $RC"
fi
run -s scene.yml -o noc -x 32 -y 24 -a -t icd
[ $RC = 0 ] && [ -s noc/c_0.png ] && [ -s noc/d_0.csv ] &&
    ok "-t icd renders without any module" || bad "-t icd without modules" "rc $RC"

export CURRAY_MODULE_DIR=$GONE
run -s scene.yml -o gone -x 32 -y 24 -a -t icf
if [ $RC = 2 ] && has "cannot load curray's FITS module $GONE/curray_fits.so: libcr_gone.so" &&
   has "it needs cfitsio" && [ ! -e gone ]; then
    ok "a module whose library is missing: refused, naming the module and the library"
else
    bad "a module whose library is missing" "rc $RC"
fi
export CURRAY_MODULE_DIR=$OTHER
run -s scene.yml -o other -x 32 -y 24 -a -t icv
if [ $RC = 1 ] && has "cannot load curray's video module $OTHER/curray_video.so: it was built for curray 0.0.0-other" &&
   [ ! -e other ]; then
    ok "a module of another build: refused, naming its version"
else
    bad "a module of another build" "rc $RC"
fi
unset CURRAY_MODULE_DIR
finish
