#!/usr/bin/env bash
# The summary curray prints before "Proceed with rendering?": the
# configuration file when one is read (config.yml found in the current
# folder, or -c), the observer's motion and projection with the fields of
# view frame 0 uses, the disc as it is traced (a Keplerian disc from its ISCO
# with its peak temperature, a chessboard with its squares), the image plane
# at infinity. Each case compares whole lines.
#
#   bash tests/cli/test_summary.sh path/to/curray [repository root]
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
. "$(dirname "$0")/lib.sh" test-summary

# line NAME TEXT: OUT (the last run's output) has TEXT as a whole line
line() {
    if [ "$RC" = 0 ] && printf '%s\n' "$OUT" | grep -qxF -- "$2"; then ok "$1"; else bad "$1" "rc $RC: no line '$2'"; fi
}
# nothing NAME TEXT: no line of OUT contains TEXT
nothing() {
    if [ "$RC" = 0 ] && ! printf '%s\n' "$OUT" | grep -qF -- "$2"; then ok "$1"; else bad "$1" "rc $RC: '$2' printed"; fi
}
summary() { rm -rf o; run -s "$@" -o o -x 8 -y 6 -t c -a true; }
# At 8x6 the rectilinear vfov is 2 atan(tan(hfov/2) 6/8) (38.55 deg for 50,
# 104.8 for 120), the fisheye's hfov 6/8 (112.5 for 150, 270 for 360).

summary "$ROOT/scenes/keplerian-interstellar.yml"
line "keplerian disc from the ISCO, with its temperature" \
    "keplerian disc (prograde orbits) from the ISCO r = 3.82907 to 20, peak temperature 5500 K"
nothing "no chessboard squares for a keplerian disc" "squares"
line "static rectilinear observer, vfov from the aspect ratio" \
    "observer at r = 60, theta = 85 deg, phi = 0 deg, static, rectilinear projection, 50 x 38.55 deg"
nothing "no configuration line without a configuration file" "configuration"

summary "$ROOT/scenes/keplerian-face-on.yml"
line "keplerian disc from the mass and accretion rate, plunging" \
    "keplerian disc (prograde orbits) from the ISCO r = 2.32088 to 25, 1e+10 solar masses at 0.01 Eddington: peak temperature 2.169e+04 K, plunging matter inside the ISCO, exposure auto (5.454)"

summary "$ROOT/scenes/observer-static-panorama.yml"
line "the panorama: equirectangular, no hfov 0" \
    "observer at r = 15, theta = 80 deg, phi = 0 deg, static, equirectangular projection, the full sphere (360 x 180 deg)"
line "chessboard disc" "chessboard disc from r = 3 to 10, 2x12 squares"

summary "$ROOT/scenes/observer-orbit.yml"
line "orbiting observer, fisheye" \
    "observer at r = 6, theta = 90 deg, phi = 0 deg, on a prograde circular orbit, fisheye (equidistant) projection, 150 x 112.5 deg"
summary "$ROOT/scenes/observer-velocity.yml"
line "observer with a velocity" \
    "observer at r = 20, theta = 85 deg, phi = 0 deg, moving at [0, 0, 0.8] c (v_r, v_theta, v_phi in the ZAMO frame), rectilinear projection, 120 x 104.8 deg"
summary "$ROOT/scenes/observer-infall.yml"
line "infalling observer" \
    "observer at r = 20, theta = 60 deg, phi = 0 deg, falling in from rest at infinity, fisheye (equidistant) projection, 360 x 270 deg"
summary "$ROOT/scenes/observer-zamo-ergosphere.yml"
line "zamo" \
    "observer at r = 1.8, theta = 60 deg, phi = 0 deg, zamo (zero angular momentum), fisheye (equidistant) projection, 360 x 270 deg"

# the observer at infinity in the scene's units (m = 2), a camera roll, a
# retrograde disc whose inner radius lies inside its ISCO, and a config.yml
# in the current folder that would otherwise be read silently
printf 'metric: {m: 2, a: 0, q: 0}\nobserver: {r: inf, theta: 85, phi: 0, hextent: 40, roll: 10}\naccretion: {model: keplerian, radius: [10, [linear, 40, 50]], retrograde: true}\n' >inf.yml
printf 'raytracer: {samples: 2}\n' >config.yml
rm -rf o
run -s inf.yml -o o -x 8 -y 6 -t c -a true -f 2
line "config.yml found in the current folder is named" \
    "configuration config.yml (found in the current folder; -c FILE reads another)"
line "image plane at infinity" "observer at infinity, theta = 85 deg, phi = 0 deg, image plane 40 wide, 30 high (frame 0)"
line "camera angles" "camera roll = 10 deg, pitch = 0 deg, yaw = 0 deg (frame 0)"
line "retrograde disc, inner radius inside the ISCO, frame 0" \
    "keplerian disc (retrograde orbits) from the ISCO r = 12 (the inner radius 10 lies inside it) to 40, peak temperature 10000 K (frame 0)"
mv config.yml c.yml
rm -rf o
run -s inf.yml -c c.yml -o o -x 8 -y 6 -t c -a true
line "-c names its file" "configuration c.yml"
finish
