#!/usr/bin/env bash
# curray orbit: the worldline CSV of an orbit file, and the refused files.
# A good file writes <out>/orbit.csv with the header and rows whose values
# are checked here independently (the circular orbit at the ISCO of a = 0.9:
# r constant, dphi/dtau = u^phi = the closed form of Bardeen, Press &
# Teukolsky, t = u^t tau); each bad file exits 1 naming the key (file, line
# and column) and writes nothing, not even the output folder.
#
#   bash tests/cli/test_orbit.sh path/to/curray
set -u
CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
. "$(dirname "$0")/lib.sh" test-orbit

# --- a good file -----------------------------------------------------------------
cat > isco.yml <<'YML'
metric: {m: 1, a: 0.9, q: 0}
particle:
  r: isco
  theta: 90
  circular: prograde
  tau: 200
  dtau: 0.5
YML
run orbit -s isco.yml -o out
if [ $RC = 0 ] && [ -f out/orbit.csv ] && has "whole proper time"; then
    ok "isco: written"
else
    bad "isco: written" "rc $RC"
fi
if python3 - out/orbit.csv <<'PY'
import csv, math, sys
rows = list(csv.reader(open(sys.argv[1])))
assert rows[0] == "tau,t,r,theta,phi,x,y,z,u^t,u^r,u^theta,u^phi".split(","), rows[0]
v = [[float(x) for x in r] for r in rows[1:]]
assert len(v) == 401, len(v)
a, M = 0.9, 1.0
# BPT (2.21): r_isco, then u^t and Omega (2.12)-(2.16), prograde
z1 = 1 + (1 - a * a) ** (1 / 3) * ((1 + a) ** (1 / 3) + (1 - a) ** (1 / 3))
z2 = math.sqrt(3 * a * a + z1 * z1)
ri = 3 + z2 - math.sqrt((3 - z1) * (3 + z1 + 2 * z2))
om = 1 / (ri ** 1.5 + a)
ut = (ri ** 1.5 + a) / (ri ** 0.75 * math.sqrt(ri ** 1.5 - 3 * ri ** 0.5 + 2 * a))
for k, r in enumerate(v):
    tau, t, rr, th, ph, x, y, z, u0, u1, u2, u3 = r
    assert abs(tau - 0.5 * k) < 1e-12, (k, tau)
    assert abs(rr - ri) < 1e-8, rr
    assert abs(th - math.pi / 2) < 1e-12
    assert abs(t - ut * tau) < 1e-7 * (1 + t), (t, ut * tau)
    assert abs(ph - om * t) < 1e-7 * (1 + ph), (ph, om * t)
    assert abs(u0 - ut) < 1e-9 and abs(u3 - om * ut) < 1e-9
    rho = math.sqrt(rr * rr + a * a)
    assert abs(x - rho * math.cos(ph)) < 1e-9 and abs(y - rho * math.sin(ph)) < 1e-9
PY
then ok "isco: values"; else bad "isco: values" "python check"; fi

# a plunge ends at the horizon, its last row there
cat > fall.yml <<'YML'
metric: {m: 1, a: 0, q: 0}
particle: {r: 10, theta: 90, velocity: [0, 0, 0], tau: 100, dtau: 1}
YML
run orbit -s fall.yml -o fall
if [ $RC = 0 ] && has "reached the horizon" &&
    python3 -c "
import csv, math
v = [[float(x) for x in r] for r in list(csv.reader(open('fall/orbit.csv')))[1:]]
eta = math.acos(2 * (2 + 1e-6) / 10 - 1)
tau = math.sqrt(1000 / 8) * (eta + math.sin(eta))
assert len(v) == 35 and abs(v[-1][0] - tau) < 1e-7 and abs(v[-1][2] - 2 - 1e-6) < 1e-9, v[-1]"; then
    ok "infall: ends at the horizon at the cycloid's proper time"
else
    bad "infall: ends at the horizon" "rc $RC"
fi

# --- refused files: exit 1, the key named, nothing written -------------------------
n=0
refuse() { # name, expected text, orbit file text
    n=$((n + 1))
    printf '%s\n' "$3" > bad$n.yml
    run orbit -s bad$n.yml -o bad$n
    if [ $RC = 1 ] && has "$2" && [ ! -e bad$n ]; then ok "$1"; else bad "$1" "rc $RC"; fi
}
M='metric: {m: 1, a: 0.6, q: 0.3}'
refuse "speed of light" "bad1.yml:3:3: particle.velocity: speed 1 is not below the speed of light" "$M
particle:
  velocity: [0.6, 0, 0.8]
  r: 10
  theta: 90
  tau: 10"
refuse "faster than light" "particle.velocity: speed" "$M
particle: {velocity: [0, 2, 0], r: 10, theta: 90, tau: 10}"
refuse "inside the horizon" "particle.r: the start r = 1.5 is not outside the horizon" "$M
particle: {velocity: [0, 0, 0], measured_by: zamo, r: 1.5, theta: 90, tau: 10}"
refuse "q/m nan" "particle.charge_to_mass" "$M
particle: {charge_to_mass: .nan, velocity: [0, 0, 0], r: 10, theta: 90, tau: 10}"
refuse "q/m inf" "particle.charge_to_mass" "$M
particle: {charge_to_mass: inf, velocity: [0, 0, 0], r: 10, theta: 90, tau: 10}"
refuse "no initial data" "particle: no initial data" "$M
particle: {r: 10, theta: 90, tau: 10}"
refuse "velocity and constants" "particle.constants: contradicts particle.velocity" "$M
particle: {r: 10, theta: 90, tau: 10, velocity: [0, 0, 0], constants: {E: 0.95, L: 3.5, K: 0}}"
refuse "circular and constants" "particle.circular: contradicts particle.constants" "$M
particle: {r: 10, theta: 90, tau: 10, constants: {E: 0.95, L: 3.5, K: 0}, circular: prograde}"
refuse "circular with a charge" "particle.circular: the circular orbit of orbit.h is a neutral" "$M
particle: {r: 10, theta: 90, tau: 10, charge_to_mass: 1, circular: prograde}"
refuse "measured_by without velocity" "particle.measured_by: goes with particle.velocity only" "$M
particle: {r: 10, theta: 90, tau: 10, measured_by: zamo, circular: prograde}"
refuse "constants not allowed there" "particle.constants: these E, L, K do not allow the start" "$M
particle: {r: 10, theta: 90, tau: 10, constants: {E: 0.5, L: 3.5, K: 0}}"
refuse "static observer in the ergosphere" "particle.velocity: no static observer" "metric: {m: 1, a: 0.99, q: 0}
particle: {r: 1.5, theta: 90, tau: 10, velocity: [0, 0, 0]}"
refuse "unknown key" "unknown key 'speed'" "$M
particle: {r: 10, theta: 90, tau: 10, speed: 0.5}"
refuse "missing tau" "missing required key 'tau'" "$M
particle: {r: 10, theta: 90, velocity: [0, 0, 0]}"
refuse "no horizon" "metric: a^2 + q^2" "metric: {m: 1, a: 0.9, q: 0.6}
particle: {r: 10, theta: 90, tau: 10, velocity: [0, 0, 0]}"
refuse "circular off the equator" "particle.theta: a circular orbit lies in the equator" "$M
particle: {r: 10, theta: 80, tau: 10, circular: prograde}"
refuse "too many rows" "particle.dtau: tau / dtau" "$M
particle: {r: 10, theta: 90, tau: 1e9, dtau: 1, circular: prograde}"

# --- usage -----------------------------------------------------------------------
run orbit -s isco.yml
if [ $RC = 2 ] && has "-o is required"; then ok "usage: no -o"; else bad "usage: no -o" "rc $RC"; fi
run orbit -s missing.yml -o m
if [ $RC = 1 ] && has "missing.yml" && [ ! -e m ]; then ok "missing file"; else bad "missing file" "rc $RC"; fi
finish
