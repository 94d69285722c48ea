#!/bin/sh
# Render docs/gallery.md's images: every scene in scenes/ at 320x240 with the
# real command line, into out/gallery/<scene>/, then copy the frames the
# gallery shows into docs/images/gallery/. Animated scenes are rendered with
# the frame count that puts a frame on the paper's figure (-f 18: frame 8 is
# theta = 85 deg; -f 36: frame 18 is phi = 180 deg), and every frame of a run
# is rendered: 18 + 18 + 36 + 36 frames of the animated scenes, 7 of the rest.
# Each render prints its time.
#
# usage: tools/render-gallery.sh [curray binary]
#   default: build/curray, which `make` builds
set -eu
bin=${1:-}
case $bin in
"" | /*) ;;
*) bin=$PWD/$bin ;; # relative to where the script was started
esac
cd "$(dirname "$0")/.."
bin=${bin:-build/curray}
if [ ! -x "$bin" ]; then
    if [ -e "$bin" ]; then
        echo "render-gallery.sh: '$bin' is not executable" >&2
    else
        echo "render-gallery.sh: no curray binary at '$bin'; run 'make' first, or name the binary:" >&2
        echo "  tools/render-gallery.sh path/to/curray" >&2
    fi
    exit 1
fi
W=320
H=240
dst=docs/images/gallery
mkdir -p "$dst"

render() { # scene frames types
    name=$(basename "$1" .yml)
    start=$(date +%s)
    "$bin" -s "$1" -o "out/gallery/$name" -x $W -y $H -f "$2" -t "$3" -a true -q true
    echo "$name: $2 frame(s) in $(($(date +%s) - start)) s"
}
pick() { # scene-name source-file target-name
    cp "out/gallery/$1/$2" "$dst/$3"
}

render scenes/demo.yml 1 c
pick demo c_0.png demo.png
render scenes/listing-7.1.2-starry-sky.yml 1 c
pick listing-7.1.2-starry-sky c_0.png listing-7.1.2-starry-sky.png
render scenes/listing-7.1.3-sphere-around-horizon.yml 1 c
pick listing-7.1.3-sphere-around-horizon c_0.png listing-7.1.3-sphere-around-horizon.png
render scenes/listing-7.1.4-redshift.yml 1 cr
pick listing-7.1.4-redshift c_0.png listing-7.1.4-redshift.png
pick listing-7.1.4-redshift r_0.png listing-7.1.4-redshift-r.png
render scenes/listing-7.1.5-blueshift.yml 1 cr
pick listing-7.1.5-blueshift c_0.png listing-7.1.5-blueshift.png
pick listing-7.1.5-blueshift r_0.png listing-7.1.5-blueshift-r.png
render scenes/grid-sky-kerr.yml 1 c
pick grid-sky-kerr c_0.png grid-sky-kerr.png
render scenes/fig-8.1.1-axis.yml 1 c
pick fig-8.1.1-axis c_0.png fig-8.1.1-axis.png
render scenes/listing-7.1.1-schwarzschild-disc.yml 18 c
pick listing-7.1.1-schwarzschild-disc c_0.png listing-7.1.1-schwarzschild-disc-theta5.png
pick listing-7.1.1-schwarzschild-disc c_8.png listing-7.1.1-schwarzschild-disc-theta85.png
render scenes/listing-7.2.1-kerr-disc.yml 18 c
pick listing-7.2.1-kerr-disc c_0.png listing-7.2.1-kerr-disc-theta5.png
pick listing-7.2.1-kerr-disc c_8.png listing-7.2.1-kerr-disc-theta85.png
render scenes/listing-7.1.6-sphere-orbit.yml 36 c
pick listing-7.1.6-sphere-orbit c_0.png listing-7.1.6-sphere-orbit-phi0.png
pick listing-7.1.6-sphere-orbit c_9.png listing-7.1.6-sphere-orbit-phi90.png
pick listing-7.1.6-sphere-orbit c_18.png listing-7.1.6-sphere-orbit-phi180.png
render scenes/listing-7.3.1-reissner-nordstrom-sphere.yml 36 c
pick listing-7.3.1-reissner-nordstrom-sphere c_18.png listing-7.3.1-reissner-nordstrom-sphere.png

# Moving observers and projections, each at its own size, into
# docs/gallery/ (shown in docs/gallery.md).
observer() { # scene frames types width height, then pairs "source-file target-name"
    name=$(basename "$1" .yml)
    W=$4 H=$5 render "$1" "$2" "$3"
    shift 5
    mkdir -p docs/gallery
    while [ $# -ge 2 ]; do
        cp "out/gallery/$name/$1" "docs/gallery/$2"
        shift 2
    done
}
observer scenes/observer-static-panorama.yml 1 c 640 320 c_0.png observer-static-panorama.png
observer scenes/observer-zamo-ergosphere.yml 1 c 360 360 c_0.png observer-zamo-ergosphere.png
observer scenes/observer-orbit.yml 60 c 320 180 c_0.png observer-orbit-0.png \
    c_20.png observer-orbit-20.png c_57.png observer-orbit-57.png
observer scenes/observer-infall.yml 10 cr 320 320 c_0.png observer-infall-0.png \
    c_9.png observer-infall-9.png r_9.png observer-infall-redshift-9.png
observer scenes/observer-velocity.yml 1 c 480 270 c_0.png observer-velocity.png
W=320
H=240
echo "gallery: $(du -ch "$dst"/*.png | tail -1)"

# The Keplerian discs at 640x360 into docs/gallery/ (shown in
# docs/gallery.md): the colour image and the bolometric map b_0.png of each.
W=640
H=360
dst=docs/gallery
mkdir -p "$dst"
for s in keplerian-interstellar keplerian-face-on keplerian-kerr-newman; do
    render scenes/$s.yml 1 cb
    pick $s c_0.png $s.png
    pick $s b_0.png $s-b.png
done
echo "disc gallery: $(du -ch "$dst"/*.png | tail -1)"
