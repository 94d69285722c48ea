#!/usr/bin/env bash
# cmake --install into a DESTDIR, and what a newcomer does with the result.
#
#   bash tests/build/test_install.sh path/to/cmake build-folder [repository root]
#
# The build folder's install (prefix /opt/curray under DESTDIR=<tmp>/stage)
# holds bin/curray and bin/curray_cpu, lib/curray/ with the output modules
# (curray_video.so, curray_fits.so, where the build made them: the installed
# curray writes -t fv with them), every shipped scene with the sky images
# beside it under share/curray/scenes, the man page share/man/man1/curray.1
# (naming every long option of curray -h; groff finds nothing to warn about,
# where groff is installed) and the README with docs/ under share/doc/curray.
# The installed curray's --example prints scenes/demo.yml byte for byte, and
# that scene renders; an installed scene with a sky image renders from
# another folder (its image found beside it).
set -u
CMAKE=$1
BUILD=$(cd "$2" && pwd)
ROOT=$(cd "${3:-$(dirname "$0")/../..}" && pwd)
. "$ROOT/tests/cli/lib.sh" test-install
P=$WORK/stage/opt/curray

OUT=$(DESTDIR=$WORK/stage "$CMAKE" --install "$BUILD" --prefix /opt/curray 2>&1)
RC=$?
if [ $RC = 0 ] && [ -x "$P/bin/curray" ] && [ -x "$P/bin/curray_cpu" ]; then
    ok "cmake --install into a DESTDIR: bin/curray, bin/curray_cpu"
else
    bad "cmake --install into a DESTDIR" "rc $RC"
fi
missing=""
for f in "$ROOT"/scenes/*.yml "$ROOT"/scenes/*.png; do
    [ -s "$P/share/curray/scenes/$(basename "$f")" ] || missing="$missing $(basename "$f")"
done
for f in share/man/man1/curray.1 share/doc/curray/README.md share/doc/curray/docs/physics.md \
         share/doc/curray/docs/scenes.md share/doc/curray/docs/images/demo.png; do
    [ -s "$P/$f" ] || missing="$missing $f"
done
[ -z "$missing" ] && ok "scenes, sky images, man page and docs installed" || bad "installed files" "missing:$missing"

OUT=$("$P/bin/curray" -h 2>&1)
undocumented=""
for o in $(echo "$OUT" | grep -o -- '--[a-z_]\+' | sort -u); do
    grep -qF -- "\\-\\-${o#--}" "$P/share/man/man1/curray.1" || undocumented="$undocumented $o"
done
[ -z "$undocumented" ] && ok "the man page names every long option of curray -h" ||
    bad "the man page names every long option" "missing:$undocumented"
if command -v groff >/dev/null; then
    OUT=$(groff -man -ww -z "$P/share/man/man1/curray.1" 2>&1)
    [ -z "$OUT" ] && ok "groff -man -ww: no warning" || bad "groff -man -ww" "warnings"
else
    echo "(groff not installed: the man page's formatting is not checked)"
fi

CURRAY=$P/bin/curray
run --example
if [ $RC = 0 ] && [ "$OUT" = "$(cat "$ROOT/scenes/demo.yml")" ]; then
    ok "curray --example prints scenes/demo.yml"
else
    bad "curray --example prints scenes/demo.yml" "rc $RC"
fi
"$CURRAY" --example >my.yml
run -s my.yml -o out/my -x 32 -y 24 -a -q
[ $RC = 0 ] && [ -s out/my/c_0.png ] && ok "the --example scene renders" || bad "the --example scene renders" "rc $RC"
mkdir elsewhere && cd elsewhere
run -s "$P/share/curray/scenes/listing-7.1.2-starry-sky.yml" -o sky -x 32 -y 24 -a -q
[ $RC = 0 ] && [ -s sky/c_0.png ] && ok "an installed scene with a sky image renders from another folder" ||
    bad "an installed scene with a sky image" "rc $RC"
# the output modules (a build with FFmpeg and cfitsio makes them): installed
# in lib/curray (or <libdir>/curray) and found from the installed program
if [ -e "$BUILD/curray_video.so" ] && [ -e "$BUILD/curray_fits.so" ]; then
    mods=$(cd "$P" && find . -name 'curray_*.so' | sort | tr '\n' ' ')
    CURRAY=$P/bin/curray
    run -s "$P/share/curray/scenes/demo.yml" -o vf -x 32 -y 24 -f 2 -a -q -t icfv
    if [ "$mods" = "./lib/curray/curray_fits.so ./lib/curray/curray_video.so " ] && [ $RC = 0 ] &&
       [ -s vf/c.mp4 ] && [ -s vf/f_1.fits ]; then
        ok "the modules installed in lib/curray; the installed curray writes -t fv with them"
    else
        bad "installed modules" "rc $RC; found: $mods"
    fi
else
    echo "(this build has no output modules: their install is not checked)"
fi
CURRAY=$P/bin/curray_cpu
run --version
[ $RC = 0 ] && has "curray " && ok "the installed curray_cpu runs" || bad "curray_cpu --version" "rc $RC"
finish
