#!/usr/bin/env bash
# accretion.exposure: auto end to end: one factor for the whole run, from
# frame 0 (every frame of an animation shares it, info.txt and the summary
# show it), the same at another -x/-y of the same aspect, and --resume
# reproduces a frame rendered again byte for byte. The Keplerian disc's
# horizon is black by default (CSV), the chessboard's stays red.
#
#   bash tests/cli/test_exposure.sh path/to/curray [repository root]
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
. "$(dirname "$0")/lib.sh" test-exposure

cat >auto.yml <<'YML'
metric: {m: 1, a: 0.9, q: 0}
observer: {r: 80, theta: [linear, 5, 60], phi: 0, hfov: 40}
accretion: {model: keplerian, radius: [25], mass_msun: 1e10, mdot_edd: 0.01, exposure: auto}
YML
exposure_line() { grep '^  exposure ' "$1/info.txt"; }

run -s auto.yml -o a -x 48 -y 36 -f 3 -t icd -a true
line=$(exposure_line a 2>/dev/null)
if [ "$RC" = 0 ] && [[ "$line" =~ ^\ \ exposure\ +auto:\ [0-9.]+\ \(frame\ 0\ traced\ 192\ pixels\ across ]] &&
    has "exposure auto ("; then
    ok "auto exposure in info.txt and the summary ($line)"
else
    bad "auto exposure in info.txt and the summary" "rc $RC, '$line'"
fi
# a larger image of the same aspect: the same factor (and frame 0 brighter
# than at exposure 1)
run -s auto.yml -o b -x 96 -y 72 -f 3 -t ic -a true
if [ "$RC" = 0 ] && [ "$(exposure_line b)" = "$line" ]; then
    ok "the same factor at 96x72 as at 48x36"
else
    bad "the same factor at another size" "rc $RC: '$(exposure_line b)' vs '$line'"
fi
# --resume: frame 2 rendered again gives the same bytes
cp a/c_2.png c_2.orig.png
cp a/d_2.csv d_2.orig.csv
rm a/c_2.png
run -s auto.yml -o a -x 48 -y 36 -f 3 -t icd -a true --resume
if [ "$RC" = 0 ] && cmp -s a/c_2.png c_2.orig.png && cmp -s a/d_2.csv d_2.orig.csv &&
    [ "$(exposure_line a)" = "$line" ]; then
    ok "--resume renders frame 2 again byte for byte with the same exposure"
else
    bad "--resume reproduces the auto exposure" "rc $RC"
fi
# exposure 1 (the default) against auto: the auto frame is brighter
sed 's/, exposure: auto//' auto.yml >one.yml
run -s one.yml -o one -x 48 -y 36 -f 3 -t id -a true
sum_rgb() { awk -F, 'NR > 1 && $10 == "disc" { s += $3 + $4 + $5 } END { print s + 0 }' "$1"; }
s1=$(sum_rgb one/d_0.csv) sa=$(sum_rgb a/d_0.csv)
if [ "$RC" = 0 ] && awk -v a="$sa" -v b="$s1" 'BEGIN { exit !(a > 1.2 * b && b > 0) }'; then
    ok "auto exposure brightens the dim disc (disc RGB sum $s1 -> $sa)"
else
    bad "auto exposure brightens the disc" "rc $RC: $s1 -> $sa"
fi
# horizons: black next to a Keplerian disc, red next to the chessboard
horizon_rgb() { awk -F, 'NR > 1 && $10 == "horizon" { print $3 "," $4 "," $5; exit }' "$1"; }
printf 'metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 80, phi: 0, hfov: 40}\naccretion: {model: keplerian, radius: [20]}\n' >kh.yml
printf 'metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 80, phi: 0, hfov: 40}\naccretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 15]}\n' >ch.yml
run -s kh.yml -o kh -x 16 -y 12 -t d -a true
k=$(horizon_rgb kh/d_0.csv)
run -s ch.yml -o ch -x 16 -y 12 -t d -a true
c=$(horizon_rgb ch/d_0.csv)
if [ "$k" = "0,0,0" ] && [ "$c" = "255,0,0" ]; then
    ok "horizon black next to the keplerian disc, red next to the chessboard"
else
    bad "default horizon colours" "keplerian '$k', chessboard '$c'"
fi
finish
