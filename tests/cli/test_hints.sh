#!/usr/bin/env bash
# Warnings for scenes that are valid but likely not what was meant
# (cr_scene_hints): a sky image not twice as wide as high, a sphere wholly
# inside the event horizon, -f N with nothing animated. Each case renders
# (exit 0) with the warning on the console; the cases next to them, and the
# shipped scenes with their header commands, give none.
#
#   bash tests/cli/test_hints.sh path/to/curray [repository root]
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
. "$(dirname "$0")/lib.sh" test-hints

# png W H FILE: a plain grey W x H PNG (Python 3 with zlib)
png() {
    python3 - "$1" "$2" "$3" <<'PY'
import struct, sys, zlib
w, h, path = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
raw = b"".join(b"\x00" + b"\x80\x80\x80" * w for _ in range(h))
chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                       + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
PY
}
png 64 64 square.png
png 64 32 twoone.png
png 100 20 wide.png
base='metric: {m: 1, a: 0.9, q: 0}
observer: {r: 30, theta: 85, phi: 0, hfov: 60}'
hint() { # name, text expected ("" for none of the three kinds), scene text, curray arguments
    local name=$1 text=$2 scene=$3
    shift 3
    printf '%s\n' "$scene" >s.yml
    rm -rf o
    run -s s.yml -o o -x 16 -y 12 -a "$@"
    local hints
    hints=$(echo "$OUT" | grep -E "curray: warning: (skymap.image|sphere [0-9]+ \(line|-f [0-9]+: nothing)" || true)
    if [ -z "$text" ]; then
        [ $RC = 0 ] && [ -z "$hints" ] && ok "$name: no warning" || bad "$name: no warning" "rc $RC: $hints"
    else
        [ $RC = 0 ] && [ "$hints" = "curray: warning: $text" ] && ok "$name" || bad "$name" "rc $RC: '$hints'"
    fi
}

hint "a square sky image is stretched" \
    "skymap.image square.png is 64x64 pixels, 1 times as wide as high: the sky map covers 360 x 180 deg, so it is stretched horizontally (an equirectangular image is twice as wide as high)" \
    "$base
skymap: {image: square.png}"
hint "a 5:1 sky image is stretched" \
    "skymap.image wide.png is 100x20 pixels, 5 times as wide as high: the sky map covers 360 x 180 deg, so it is stretched vertically (an equirectangular image is twice as wide as high)" \
    "$base
skymap: {image: wide.png}"
hint "a 2:1 sky image" "" "$base
skymap: {image: twoone.png}"

# a = 0.9: r+ = 1.436; the sphere's centre lies sqrt(r^2 + a^2 sin^2 theta)
# from the origin: 0.949 for r = 0.3 on the equator, 1.249 with radius 0.3
hint "a sphere wholly inside the horizon" \
    "sphere 0 (line 3) lies wholly inside the event horizon: no ray reaches it, so it cannot be seen" \
    "$base
sphere: {color: [0, 0, 255], resolution: [4, 8], r: 0.3, theta: 90, phi: 0, radius: 0.3}"
hint "... in every frame" \
    "sphere 0 (line 3) lies wholly inside the event horizon in every frame: no ray reaches it, so it cannot be seen" \
    "$base
sphere: {color: [0, 0, 255], resolution: [4, 8], r: 0.3, theta: 90, phi: [linear, 0, 90], radius: 0.3}" -f 3
hint "a sphere falling inside the horizon in the last frame" \
    "sphere 1 (line 4) lies wholly inside the event horizon in 1 of 4 frames (first in frame 3): it cannot be seen there" \
    "$base
sphere: {color: [0, 0, 255], resolution: [4, 8], r: 8, theta: 90, phi: 0, radius: 1}
sphere: {color: [0, 0, 255], resolution: [4, 8], r: [linear, 10, 0.3], theta: 90, phi: 0, radius: 0.3}" -f 4
hint "a sphere reaching out of the horizon (0.949 + 0.6 > 1.436)" "" "$base
sphere: {color: [0, 0, 255], resolution: [4, 8], r: 0.3, theta: 90, phi: 0, radius: 0.6}"

hint "-f 3 with nothing animated" \
    "-f 3: nothing in the scene is animated (no [linear, start, end] value), so all 3 frames are the same image" \
    "$base" -f 3
hint "-f 1 with nothing animated" "" "$base"
hint "-f 3 with one animated value" "" "metric: {m: 1, a: 0.9, q: 0}
observer: {r: 30, theta: [linear, 80, 90], phi: 0, hfov: 60}" -f 3
hint "-f 2 with only a sphere's radius animated" "" "$base
sphere: {color: [0, 0, 255], resolution: [4, 8], r: 8, theta: 90, phi: 0, radius: [linear, 1, 2]}" -f 2

# the shipped scenes, each with its header command's frame count
ln -s "$ROOT/scenes" scenes
for scene in scenes/*.yml; do
    f=$(sed -n '/^---/q; s/^#[[:space:]]\{1,\}curray -s .* -f \([0-9]\{1,\}\).*/\1/p' "$scene" | head -1)
    rm -rf o
    run -s "$scene" -o o -x 16 -y 12 -f "${f:-1}" -a
    hints=$(echo "$OUT" | grep -E "curray: warning: (skymap.image|sphere [0-9]+ \(line|-f [0-9]+: nothing)" || true)
    [ $RC = 0 ] && [ -z "$hints" ] && ok "$scene -f ${f:-1}: no warning" || bad "$scene: no warning" "rc $RC: $hints"
done
finish
