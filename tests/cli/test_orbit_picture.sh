#!/usr/bin/env bash
# curray orbit -t c: the lensed picture of a worldline, checked against
# Schwarzschild light bending computed here independently (Darwin's orbit
# integral phi = int du / sqrt(1/b^2 - u^2 + 2u^3), u = 1/r, by Simpson's
# rule, inverted for the impact parameter b by bisection). For the observer
# at infinity a point P at angle psi from the line of sight has its direct
# image at b_0 with phi(b_0) = psi along the projection of P on the image
# plane, and its secondary image at b_1 with phi(b_1) = 2 pi - psi on the
# other side of the shadow. A circular orbit of radius R = 10 M:
# - face-on: the images lie on two rings, b_0 = 10.956 M and b_1 = 5.666 M;
#   every image in orbit_image.csv within 0.02 px of its ring, every pixel
#   drawn within 1 px (half the line width plus the antialiasing) of one,
#   the coverage-weighted radius of each ring within 0.25 px, and both rings
#   closed (drawn in every 10-degree sector); t_obs - t the same all round a
#   ring (1e-5 M), the secondary's light later than the direct image's by
#   the difference of the two rays' time integrals (dt/du = 1 / ((1 - 2u)
#   u^2 b sqrt(1/b^2 - u^2 + 2u^3)), 1e-4 M; 25.9347 M);
# - seen from 80 degrees: every image where the formula puts it (0.02 px),
#   the far side of the orbit above the shadow and the near side below it;
# - seen from 89 degrees, where the orbit passes within 1 degree of the line
#   of sight (the images close to the Einstein ring): those images too
#   (0.05 px), the far side's direct images above the shadow;
# - a sphere in front of the near side hides its direct images (visible 0)
#   and leaves the far side's;
# and the refused requests: exit 1 or 2 naming the option or key, nothing
# written.
#
#   bash tests/cli/test_orbit_picture.sh path/to/curray
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
. "$(dirname "$0")/lib.sh" test-orbit-picture

cat > darwin.py <<'PY'
import math, struct, zlib
BC = 3 * math.sqrt(3)  # the critical impact parameter (M = 1)
def F(u, b):
    return 1 / (b * b) - u * u + 2 * u ** 3
def simpson(f, a, c, n=1000):
    h = (c - a) / n
    s = f(a) + f(c)
    for k in range(1, n):
        s += (4 if k % 2 else 2) * f(a + k * h)
    return s * h / 3
def periapsis(b):  # the smallest positive root of F, b > BC
    lo, hi = 0.0, 1.0 / 3
    for _ in range(200):
        m = 0.5 * (lo + hi)
        if F(m, b) > 0: lo = m
        else: hi = m
    return lo
def tail(b, uR):  # int_uR^u0 du / sqrt(F), u0 the periapsis: u = u0 - (u0 - uR) w^2
    u0 = periapsis(b)
    d = max(u0 - uR, 0.0)
    def g(w):
        if w == 0:
            return 2 * math.sqrt(d) / math.sqrt(2 * u0 * (1 - 3 * u0))
        return 2 * d * w / math.sqrt(max(F(u0 - d * w * w, b), 1e-300))
    return simpson(g, 0.0, 1.0)
def phi_in(b, R):  # swept from infinity to radius R, inbound
    if b <= BC:
        return simpson(lambda u: 1 / math.sqrt(F(u, b)), 0.0, 1.0 / R)
    return tail(b, 0.0) - tail(b, 1.0 / R)
def phi_out(b, R):  # ... outbound, after the periapsis
    return tail(b, 0.0) + tail(b, 1.0 / R)
def bisect(f, lo, hi, target):  # f(lo) < target < f(hi)
    for _ in range(60):
        m = 0.5 * (lo + hi)
        if f(m) < target: lo = m
        else: hi = m
    return 0.5 * (lo + hi)
def b_image(psi, R, order):
    """impact parameter of P's image of order 0 (swept psi) or 1 (2 pi - psi)"""
    bmax = R / math.sqrt(1 - 2 / R)  # periapsis at R: phi_in = phi_out there
    target = psi if order == 0 else 2 * math.pi - psi
    if phi_out(bmax, R) >= target:  # inbound: phi_in grows with b
        return bisect(lambda b: phi_in(b, R), 1e-9, bmax, target)
    # outbound: phi_out falls from infinity (b -> BC) to phi_in(bmax)
    return bisect(lambda b: -phi_out(b, R), BC * (1 + 1e-12), bmax, -target)
def tailh(b, uR, h):  # int_uR^u0 h(u) du / sqrt(F), u = u0 - (u0 - uR) w^2
    u0 = periapsis(b)
    d = max(u0 - uR, 0.0)
    def g(w):
        u = u0 - d * w * w
        if w == 0:
            return 2 * math.sqrt(d) / math.sqrt(2 * u0 * (1 - 3 * u0)) * h(u0)
        return 2 * d * w / math.sqrt(max(F(u, b), 1e-300)) * h(u)
    return simpson(g, 0.0, 1.0)
def dt_reg(u, b):  # dt/du - (1/u^2 + 2/u) along the ray (its limit at u = 0)
    if u == 0:
        return 4 + b * b / 2
    s = math.sqrt(1 - b * b * u * u + 2 * b * b * u ** 3)
    return (1 / ((1 - 2 * u) * s) - 1 - 2 * u) / (u * u)
def G0(a, c):  # int_a^c (1/u^2 + 2/u) du
    return (1 / a - 1 / c) + 2 * math.log(c / a)
def t_ray(b, R, outbound):
    """coordinate time from infinity to radius R along the ray of impact
    parameter b (dt/du = 1 / ((1 - 2u) u^2 b sqrt(F))), less the integral
    of 1/u^2 + 2/u from 0 to 1/R, the same for every ray: the difference of
    two rays' t_ray is the difference of their light's delays"""
    uR, h = 1.0 / R, lambda u: 1 / ((1 - 2 * u) * u * u * b)
    if b <= BC:
        return simpson(lambda u: dt_reg(u, b), 0.0, uR)
    u0 = periapsis(b)
    ua = u0 / 2
    t_in = (simpson(lambda u: dt_reg(u, b), 0.0, ua) + tailh(b, ua, h) - G0(ua, u0)
            - (tailh(b, uR, h) - G0(uR, u0)))
    return t_in + (2 * tailh(b, uR, h) if outbound else 0.0)
def inbound(psi, R):  # the direct image's light reaches R before its periapsis
    return phi_out(R / math.sqrt(1 - 2 / R), R) >= psi
def image(P, th_o, order, W, H, hext):
    """expected pixel (i, j) of P's image for the observer at infinity at
    theta th_o, phi 0 (right = e_phi, up = -e_theta)"""
    o = (math.sin(th_o), 0.0, math.cos(th_o))
    right = (0.0, 1.0, 0.0)
    up = (-math.cos(th_o), 0.0, math.sin(th_o))
    r = math.sqrt(sum(p * p for p in P))
    c = sum(p * q for p, q in zip(P, o)) / r
    psi = math.acos(max(-1.0, min(1.0, c)))
    a, bb = sum(p * q for p, q in zip(P, right)), sum(p * q for p, q in zip(P, up))
    n = math.hypot(a, bb)
    b = b_image(psi, r, order) * (1 if order == 0 else -1)
    scale = hext / W  # M per pixel, square pixels
    return (W - 1) / 2 + b * a / n / scale, (H - 1) / 2 - b * bb / n / scale
def read_png(path):
    """8-bit RGB, non-interlaced (what curray writes): rows of (r, g, b)"""
    d = open(path, "rb").read()
    assert d[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, W = 8, b"", 0
    while pos < len(d):
        n, t = struct.unpack(">I4s", d[pos:pos + 8])
        if t == b"IHDR":
            W, H, depth, ctype = struct.unpack(">IIBB", d[pos + 8:pos + 18])
            assert depth == 8 and ctype == 2
        if t == b"IDAT":
            idat += d[pos + 8:pos + 8 + n]
        pos += 12 + n
    raw, rows, prev, st = zlib.decompress(idat), [], [0] * (3 * W), 3 * W + 1
    for y in range(H):
        f, line = raw[y * st], list(raw[y * st + 1:(y + 1) * st])
        for x in range(3 * W):
            a = line[x - 3] if x >= 3 else 0
            b, c = prev[x], prev[x - 3] if x >= 3 else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[3 * x:3 * x + 3]) for x in range(W)])
        prev = line
    return rows
def images(path):
    import csv
    r = list(csv.reader(open(path)))
    assert r[0] == "tau,t,order,i,j,t_obs,visible,row".split(","), r[0]
    return [dict(zip(r[0], map(float, x))) for x in r[1:]]
PY

R=10
orbit() { # name, scene file, extra view keys
    cat > o-$1.yml <<YML
metric: {m: 1, a: 0, q: 0}
particle: {r: $R, theta: 90, circular: prograde, tau: 200, dtau: 2}
view: {scene: $2, color: [255, 255, 255], line_width: 1${3:-}}
YML
}

# --- face-on: two rings ------------------------------------------------------------
cat > face.yml <<'YML'
metric: {m: 1, a: 0, q: 0}
observer: {r: inf, theta: 0, phi: 0, hextent: 40}
horizon_color: [0, 0, 0]
YML
orbit ring face.yml
run orbit -s o-ring.yml -o ring -t c -x 200 -y 200
if [ $RC = 0 ] && [ -f ring/orbit.png ] && [ -f ring/orbit_image.csv ] && [ -f ring/orbit.csv ]; then
    ok "face-on: written"
else
    bad "face-on: written" "rc $RC"
fi
if python3 - <<'PY'
import math
from darwin import *
W = H = 200; s = 40 / W; c = (W - 1) / 2
rb = [b_image(math.pi / 2, 10, k) / s for k in (0, 1)]
print("rings b0 = %.6f M, b1 = %.6f M" % (rb[0] * s, rb[1] * s))
im = images("ring/orbit_image.csv")
worst = [0, 0]
for q in im:
    k = int(q["order"])
    d = abs(math.hypot(q["i"] - c, q["j"] - c) - rb[k])
    worst[k] = max(worst[k], d)
    assert q["visible"] == 1
print("largest image offset from its ring: %.2e px, %.2e px" % tuple(worst))
assert max(worst) < 0.02, worst
assert sum(q["row"] for q in im if q["order"] == 0) == 101  # every row has its direct image
assert sum(q["row"] for q in im if q["order"] == 1) == 101
px = read_png("ring/orbit.png")
far, wsum, rsum, sectors = 0.0, [0, 0], [0, 0], [set(), set()]
for j in range(H):
    for i in range(W):
        v = px[j][i][0] / 255
        if v == 0:
            continue
        r = math.hypot(i - c, j - c)
        k = 0 if abs(r - rb[0]) < abs(r - rb[1]) else 1
        far = max(far, abs(r - rb[k]))
        wsum[k] += v; rsum[k] += v * r
        sectors[k].add(int(math.degrees(math.atan2(j - c, i - c)) // 10))
print("drawn pixels: farthest %.3f px from a ring; weighted radii off by %.3f, %.3f px"
      % (far, rsum[0] / wsum[0] - rb[0], rsum[1] / wsum[1] - rb[1]))
assert far <= 1.0 + 1e-9, far
assert all(abs(rsum[k] / wsum[k] - rb[k]) < 0.25 for k in (0, 1))
assert all(len(sectors[k]) == 36 for k in (0, 1)), [len(x) for x in sectors]
# the light's delays: the same all round each ring, the secondary's longer by
# the time integral's difference of the two rays
dl = [[q["t_obs"] - q["t"] for q in im if q["order"] == k] for k in (0, 1)]
want = t_ray(rb[1] * s, 10, True) - t_ray(rb[0] * s, 10, not inbound(math.pi / 2, 10))
got = sum(dl[1]) / len(dl[1]) - sum(dl[0]) / len(dl[0])
print("delays: spread %.1e, %.1e M; secondary later by %.6f M (integral %.6f M)"
      % (max(dl[0]) - min(dl[0]), max(dl[1]) - min(dl[1]), got, want))
assert all(max(d) - min(d) < 1e-5 for d in dl)
assert abs(got - want) < 1e-4
PY
then ok "face-on: the direct and secondary rings of Darwin's integral"; else bad "face-on: rings" "python check"; fi

# --- seen from 80 degrees: the far side above the shadow ---------------------------
cat > tilt.yml <<'YML'
metric: {m: 1, a: 0, q: 0}
observer: {r: inf, theta: 80, phi: 0, hextent: 40}
horizon_color: [0, 0, 0]
YML
orbit tilt tilt.yml
run orbit -s o-tilt.yml -o tilt -t c -x 240 -y 200
if [ $RC = 0 ] && python3 - <<'PY'
import math
from darwin import *
W, H, th = 240, 200, math.radians(80)
om = 10 ** -1.5  # the circular orbit's dphi/dt
im = [q for q in images("tilt/orbit_image.csv") if q["row"] == 1]
worst, above, below = 0.0, None, None
for q in im[::6]:
    ph = om * q["t"]
    P = (10 * math.cos(ph), 10 * math.sin(ph), 0.0)
    ei, ej = image(P, th, int(q["order"]), W, H, 40)
    worst = max(worst, math.hypot(q["i"] - ei, q["j"] - ej))
print("largest offset from the expected image: %.2e px (%d images)" % (worst, len(im[::6])))
assert worst < 0.02, worst
# the far side (phi = pi) and the near side (phi = 0) of the orbit
for q in im:
    if q["order"] != 0:
        continue
    ph = math.fmod(om * q["t"], 2 * math.pi)
    if abs(ph - math.pi) < 0.05:
        above = q
    if abs(ph) < 1e-9:
        below = q
cy = (H - 1) / 2
print("far side seen %.2f M above the centre, near side %.2f M below"
      % ((cy - above["j"]) * 40 / W, (below["j"] - cy) * 40 / W))
assert (cy - above["j"]) * 40 / W > BC  # above the shadow
assert (below["j"] - cy) * 40 / W > 0
px = read_png("tilt/orbit.png")
assert px[round(above["j"])][round(above["i"])][0] > 128
PY
then ok "80 degrees: every image as the formula says, the far side above the hole"
else bad "80 degrees" "rc $RC"; fi

# --- seen from 89 degrees: near the line of sight the unsigned sweep tells the orders
cat > edge.yml <<'YML'
metric: {m: 1, a: 0, q: 0}
observer: {r: inf, theta: 89, phi: 0, hextent: 40}
horizon_color: [0, 0, 0]
YML
orbit edge edge.yml
run orbit -s o-edge.yml -o edge -t c -x 240 -y 200
if [ $RC = 0 ] && python3 - <<'PY'
import math
from darwin import *
W, H, th = 240, 200, math.radians(89)
om = 10 ** -1.5
o = (math.sin(th), 0.0, math.cos(th))
im = images("edge/orbit_image.csv")
near, rows = [], []
for q in im:
    ph = om * q["t"]
    P = (10 * math.cos(ph), 10 * math.sin(ph), 0.0)
    psi = math.degrees(math.acos(sum(a * b for a, b in zip(P, o)) / 10))
    if psi < 2 or psi > 178:  # within 2 degrees of the line of sight
        near.append((q, P))
    elif q["row"] == 1:
        rows.append((q, P))
worst = 0.0
for q, P in near[::10] + rows[::8]:
    ei, ej = image(P, th, int(q["order"]), W, H, 40)
    worst = max(worst, math.hypot(q["i"] - ei, q["j"] - ej))
print("%d images within 2 degrees of the line of sight; largest offset of %d checked: %.2e px"
      % (len(near), len(near[::10]) + len(rows[::8]), worst))
assert len(near) > 20 and worst < 0.05, worst
# the point straight behind the hole (phi nearest pi): its direct image above
# the shadow, on the Einstein ring; the secondary below it
cy = (H - 1) / 2
far = {k: min((x for x in near if x[0]["order"] == k and x[1][0] < 0), key=lambda x: abs(x[1][1]))[0]
       for k in (0, 1)}
print("straight behind: direct image %.2f M above the centre, secondary %.2f M below"
      % ((cy - far[0]["j"]) * 40 / W, (far[1]["j"] - cy) * 40 / W))
assert (cy - far[0]["j"]) * 40 / W > BC and (far[1]["j"] - cy) * 40 / W > BC
PY
then ok "89 degrees: the Einstein-ring images of the far side above the hole"
else bad "89 degrees" "rc $RC"; fi

# --- a sphere in front of the near side hides it ------------------------------------
# the near point (10, 0, 0) seen along the line of sight (sin 80, 0, cos 80):
# a sphere of radius 2 centred 10 M towards the observer from it
python3 - > hide.yml <<'PY'
import math
c = (10 + 10 * math.sin(math.radians(80)), 0.0, 10 * math.cos(math.radians(80)))
r = math.sqrt(sum(x * x for x in c))
print("""metric: {m: 1, a: 0, q: 0}
observer: {r: inf, theta: 80, phi: 0, hextent: 40}
horizon_color: [0, 0, 0]
sphere: {color: [0, 0, 255], resolution: [4, 8], r: %.12g, theta: %.12g rad, phi: 0, radius: 2}"""
      % (r, math.acos(c[2] / r)))
PY
orbit hide hide.yml
run orbit -s o-hide.yml -o hide -t c -x 120 -y 100
if [ $RC = 0 ] && python3 - <<'PY'
import math
from darwin import images
om = 10 ** -1.5
im = [q for q in images("hide/orbit_image.csv") if q["order"] == 0 and q["row"] == 1]
def at(ph):
    return min(im, key=lambda q: abs(math.remainder(om * q["t"] - ph, 2 * math.pi)))
assert at(0.0)["visible"] == 0, at(0.0)
assert at(math.pi)["visible"] == 1
assert at(math.pi / 2)["visible"] == 1
PY
then ok "a sphere in front hides the near side's direct image"; else bad "hidden images" "rc $RC"; fi

# --- the view without -t c is not used ------------------------------------------------
run orbit -s o-ring.yml -o plain
if [ $RC = 0 ] && [ -f plain/orbit.csv ] && [ ! -e plain/orbit.png ]; then ok "no -t: orbit.csv only"
else bad "no -t: orbit.csv only" "rc $RC"; fi

# --- refused: the option or key named, nothing written ------------------------------
printf 'metric: {m: 1, a: 0.5, q: 0}\nobserver: {r: inf, theta: 80, phi: 0, hextent: 40}\n' > spin.yml
printf 'metric: {m: 1, a: 0, q: 0}\nobserver: {r: inf, theta: 80, phi: 0, hextent: 40, fov: 3}\n' > broken.yml
n=0
refuse_view() { # name, expected status, expected text, orbit file text, extra args
    n=$((n + 1))
    printf '%s\n' "$4" > bad$n.yml
    run orbit -s bad$n.yml -o bad$n ${5:--t c}
    if [ $RC = $2 ] && has "$3" && [ ! -e bad$n ]; then ok "$1"; else bad "$1" "rc $RC"; fi
}
P='metric: {m: 1, a: 0, q: 0}
particle: {r: 10, theta: 90, circular: prograde, tau: 20}'
refuse_view "-t r does not apply" 2 "-t: 'r' is not an output of curray orbit" "$P
view: {scene: face.yml}" "-t cr"
refuse_view "-t empty" 2 "-t: empty output type" "$P" "--output_type="
refuse_view "-t c without a camera" 1 "bad3.yml: the lensed picture needs a camera: the orbit file has no view section" "$P"
refuse_view "view without a scene" 1 "bad4.yml:3:1: view: missing required key 'scene'" "$P
view: {color: [1, 2, 3]}"
refuse_view "missing scene file" 1 "bad5.yml:3:15: view.scene: " "$P
view: {scene: nowhere.yml}"
refuse_view "another hole" 1 "view.scene: the scene's metric (m 1, a 0.5, q 0) is not the orbit file's" "$P
view: {scene: spin.yml}"
refuse_view "bad colour" 1 "view.color: expected proper_time or a colour" "$P
view: {scene: face.yml, color: blue}"
refuse_view "bad colour component" 1 "view.color[2]" "$P
view: {scene: face.yml, color: [0, 0, 256]}"
refuse_view "line width" 1 "view.line_width: expected a width in pixels in (0, 16], got 0" "$P
view: {scene: face.yml, line_width: 0}"
refuse_view "orders" 1 "view.orders" "$P
view: {scene: face.yml, orders: 5}"
refuse_view "unknown view key" 1 "unknown key 'colour'" "$P
view: {scene: face.yml, colour: [1, 2, 3]}"
refuse_view "a bad scene" 1 "bad12.yml:3:15: view.scene: broken.yml:2" "$P
view: {scene: broken.yml}"
refuse_view "-x 0" 2 "-x: expected a size from 1 to 8192 pixels, got '0'" "$P
view: {scene: face.yml}" "-t c -x 0"
finish
