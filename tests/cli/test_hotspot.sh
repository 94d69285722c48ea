#!/usr/bin/env bash
# Moving spheres on the command line: the shipped hot-spot scene's light
# curve (-t l) against the frame's own pixels (d_<k>.csv: the flux is the
# sum of the bolometric column times the pixel's image-plane area, the
# centroid its weighted mean position, to 1e-12 relative), --resume of a
# run that lost a light-curve file, and refused scenes: exit 1 naming the
# key, nothing written (not even the output folder).
#
#   bash tests/cli/test_hotspot.sh path/to/curray path/to/source
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
. "$(dirname "$0")/lib.sh" test-hotspot

# --- the shipped scene -------------------------------------------------------------
run -s "$SRC/scenes/hot-spot-isco.yml" -o iso -x 24 -y 24 -f 2 -t cl -a true -q true
if [ $RC = 0 ] && [ -f iso/l_0.csv ] && [ -f iso/l_1.csv ] && [ -f iso/c_1.png ]; then
    ok "hot-spot-isco.yml: l_<k>.csv written"
else
    bad "hot-spot-isco.yml: l_<k>.csv written" "rc $RC"
fi

# --- the light curve equals the sum of the frame's pixels --------------------------
# the shipped scene's spot seen from the observer at infinity, where every
# pixel stands for the same image-plane area
sed -e 's/^  r: 1000$/  r: inf/' -e 's/^  hfov: .*/  hextent: 14/' \
    "$SRC/scenes/hot-spot-isco.yml" > inf.yml
run -s inf.yml -o hs -x 48 -y 48 -f 3 -t idl -a true -q true
if [ $RC = 0 ] && [ -f hs/l_0.csv ] && [ -f hs/l_2.csv ] && grep -q 'r: inf' inf.yml; then
    ok "at infinity: l_<k>.csv written"
else
    bad "at infinity: l_<k>.csv written" "rc $RC"
fi
for k in 0 1 2; do
    if python3 - hs/d_$k.csv hs/l_$k.csv $k <<'PY'
import csv, math, sys
px = list(csv.DictReader(open(sys.argv[1])))
rows = list(csv.reader(open(sys.argv[2])))
k = int(sys.argv[3])
assert rows[0] == "frame,t_obs,flux,x,y,sx,sy,pixels".split(","), rows[0]
assert len(rows) == 2, rows
frame, t, flux, x, y, sx, sy, n = rows[1]
area = (14 / 48) * (14 / 48)  # hextent / width, square pixels, M^2
w = [(int(p["x"]), int(p["y"]), float(p["bolometric"])) for p in px
     if float(p["bolometric"]) > 0 and p["outcome"] == "sphere"]
assert len(w) > 0 and int(n) == len(w), (n, len(w))
F = sum(b * area for _, _, b in w)
X = sum(i * b * area for i, _, b in w) / F
Y = sum(j * b * area for _, j, b in w) / F
assert int(frame) == k and abs(float(t) - k * 0.8709548107302603) < 1e-12, (frame, t)
for got, want in ((float(flux), F), (float(x), X), (float(y), Y)):
    assert abs(got - want) <= 1e-12 * abs(want), (got, want)
# the image-plane centroid: alpha = (x + 0.5 - W/2) * 14 / W, beta upward
assert abs(float(sx) - (X + 0.5 - 24) * 14 / 48) < 1e-9, (sx, X)
assert abs(float(sy) + (Y + 0.5 - 24) * 14 / 48) < 1e-9, (sy, Y)
PY
    then ok "frame $k: flux and centroid from the pixels"; else bad "frame $k: flux and centroid" "python"; fi
done

# t_obs is written in the scene's length unit (here M = 2 of it)
sed -e 's/^  m: 1$/  m: 2/' inf.yml > m2.yml
run -s m2.yml -o m2 -x 16 -y 16 -f 2 -t l -a true -q true
if [ $RC = 0 ] && grep -q '^  m: 2$' m2.yml && [ "$(sed -n 2p m2/l_1.csv | cut -d, -f2)" = 0.8709548107302603 ]; then
    ok "t_obs in the scene's unit"
else
    bad "t_obs in the scene's unit" "rc $RC"
fi

# --- --resume writes a lost light-curve file again, the same -----------------------
cp hs/l_1.csv l_1.before
rm hs/l_1.csv
run -s inf.yml -o hs -x 48 -y 48 -f 3 -t idl -a true -q true --resume
if [ $RC = 0 ] && cmp -s hs/l_1.csv l_1.before; then ok "--resume: l_1.csv again, the same"
else bad "--resume: l_1.csv again" "rc $RC"; fi

# --- refused scenes: exit 1, the key named, nothing written ------------------------
n=0
refuse() { # name, expected text, scene text
    n=$((n + 1))
    printf '%s\n' "$3" > bad$n.yml
    run -s bad$n.yml -o bad$n -x 16 -y 16 -t cl -a true
    if [ $RC = 1 ] && has "$2" && [ ! -e bad$n ]; then ok "$1"; else bad "$1" "rc $RC"; fi
}
H='metric: {m: 1, a: 0.9, q: 0}
observer: {r: inf, theta: 60, phi: 0, hextent: 14}'
S='sphere:
  color: [255, 200, 80]
  resolution: [1, 1]
  theta: 90
  phi: 0
  radius: 0.4'
refuse "faster than light" "would move at or beyond the speed of light" "$H
$S
  r: 8
  motion: rotating
  omega: 0.5"
refuse "orbit inside the horizon" "motion: orbit at r = 1.2: no circular orbit" "$H
$S
  r: 1.2
  motion: orbit"
refuse "orbit inside the photon orbit" "motion: orbit at r = 1.5: no circular orbit" "$H
$S
  r: 1.5
  motion: orbit"
refuse "retrograde without the orbit" "bad4.yml:10:3: sphere[0].retrograde: applies only to motion: orbit" "$H
$S
  r: 8
  retrograde: true"
refuse "observer.t without a moving sphere" "observer.t: the observer's time needs a moving object" "metric: {m: 1, a: 0.9, q: 0}
observer: {r: inf, theta: 60, phi: 0, hextent: 14, t: 5}
$S
  r: 8"
refuse "observer.dt without any sphere" "observer.dt: the observer's time needs a moving object" "metric: {m: 1, a: 0.9, q: 0}
observer: {r: inf, theta: 60, phi: 0, hextent: 14, dt: 1}"
refuse "omega not finite" "bad7.yml:11:10: sphere[0].omega: expected a finite number" "$H
$S
  r: 8
  motion: rotating
  omega: .nan"
refuse "time not finite" "observer.dt: expected a finite number" "metric: {m: 1, a: 0.9, q: 0}
observer: {r: inf, theta: 60, phi: 0, hextent: 14, dt: .inf}
$S
  r: isco
  motion: orbit"
refuse "at rest in the ergosphere" "no matter is at rest inside the ergosphere" "$H
$S
  r: 1.8
  motion: rotating
  omega: 0"
refuse "seen from inside the horizon" "sphere 0 (line 3): a moving sphere is seen with the light's travel time from the observer's BL time, which does not exist inside the event horizon (observer.r = 1.2 < r+ = 1.43589)" "metric: {m: 1, a: 0.9, q: 0}
observer: {r: 1.2, theta: 60, phi: 0, hfov: 90, motion: infall}
$S
  r: 8
  motion: orbit"
# falling in through r+ over the frames: refused before frame 0 is written
printf '%s\n' "metric: {m: 1, a: 0.9, q: 0}
observer: {r: [linear, 12, 1.2], theta: 60, phi: 0, hfov: 90, motion: infall}
$S
  r: 8
  motion: orbit" > fall.yml
run -s fall.yml -o fall -x 16 -y 16 -f 3 -t cl -a true
if [ $RC = 1 ] && has "frame 2 of 3: sphere 0 (line 3): a moving sphere" && [ ! -e fall ]; then
    ok "falling in through r+: refused, nothing written"
else bad "falling in through r+" "rc $RC"; fi
finish
