#!/usr/bin/env bash
# bench/worldline.sh: the cost of a particle's worldline of 1,000 orbits
# (curray orbit, src/core/particle.h) at the default tolerance (1e-10):
# - isco: the circular prograde ISCO of a = 0.9 (Omega = 1 / (r^1.5 + a)),
# - eccentric: scenes/orbits/kerr-eccentric.yml's orbit (a = 0.9, from the
#   apoapsis r = 15 M), 1,000 radial periods,
# - charged: a bound orbit of q/m = 0.3 in Reissner-Nordstrom (Q = 0.5),
#   from r = 10 M at 0.35 c azimuthal (static observer), 1,000 turns of phi,
# and an unbound one for comparison (escape: radially out from r = 6 M at
# 0.8 c to r_max = 1e4 M). The proper time of 1,000 orbits comes from a short
# calibration run (the turns of phi, or the periapsis passages, in its CSV).
# Runs are interleaved; per case the median wall and CPU time (timecmd.py),
# the steps, and the CPU microseconds per orbit and per step.
#
# Usage: bench/worldline.sh [--runs R]
#   default: 5 runs
# Environment: CURRAY_BIN (default build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=5 size=1x1 threads=""
bench_args worldline.sh 15 "$@"
bench_bin worldline.sh "$root/build/curray"
bench_tmpdir

# orbit_file NAME TAU DTAU: the case's orbit file with that proper time
orbit_file() {
    case $1 in
    isco) printf 'metric: {m: 1, a: 0.9, q: 0}\nparticle:\n  r: isco\n  theta: 90\n  circular: prograde\n' ;;
    eccentric) printf 'metric: {m: 1, a: 0.9, q: 0}\nparticle:\n  r: 15\n  theta: 90\n  velocity: [0, 0, 0.27]\n' ;;
    charged) printf 'metric: {m: 1, a: 0, q: 0.5}\nparticle:\n  r: 10\n  theta: 90\n  charge_to_mass: 0.3\n  velocity: [0, 0, 0.35]\n' ;;
    escape) printf 'metric: {m: 1, a: 0, q: 0}\nparticle:\n  r: 6\n  theta: 90\n  velocity: [0.8, 0, 0]\n  r_max: 10000\n' ;;
    esac
    printf '  tau: %s\n  dtau: %s\n' "$2" "$3"
}

# orbits in a worldline CSV: periapsis passages (eccentric) or turns of phi
count_orbits() { # CSV KIND
    python3 - "$1" "$2" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
if sys.argv[2] == "eccentric":
    r = [float(x["r"]) for x in rows]
    print(sum(1 for i in range(1, len(r) - 1) if r[i] < r[i - 1] and r[i] <= r[i + 1]))
else:
    print(abs(float(rows[-1]["phi"]) - float(rows[0]["phi"])) / (2 * math.pi))
PY
}

cases="isco eccentric charged escape"
declare -A tau
for c in isco eccentric charged; do
    orbit_file $c 20000 0.5 >"$tmp/cal-$c.yml"
    "$bin" orbit -s "$tmp/cal-$c.yml" -o "$tmp/cal-$c" -q
    n=$(count_orbits "$tmp/cal-$c/orbit.csv" $c)
    tau[$c]=$(python3 -c "import math; print(math.ceil(1000 * 20000 / $n))")
    orbit_file $c "${tau[$c]}" 10 >"$tmp/$c.yml"
done
orbit_file escape 100000 10 >"$tmp/escape.yml"
for k in $(seq "$runs"); do
    for c in $cases; do
        o=$tmp/o-$c
        rm -rf "$o"
        python3 "$here/timecmd.py" "$tmp/t-$c.$k" -- "$bin" orbit -s "$tmp/$c.yml" -o "$o"
        steps=$(sed -n 's/.*rows, \([0-9]*\) steps.*/\1/p' "$tmp/t-$c.$k.log")
        echo "$(cat "$tmp/t-$c.$k") $steps" >>"$tmp/all-$c"
    done
done
for c in isco eccentric charged; do
    echo "$c: $(count_orbits "$tmp/o-$c/orbit.csv" $c) orbits in tau = ${tau[$c]} M"
done
echo "binary: $bin, $runs runs interleaved, $(bench_cores_model), load $(cut -d' ' -f1 /proc/loadavg)"
echo "| worldline | runs | tau (M) | steps | wall median (s) | CPU median (s) | CPU us/orbit | CPU us/step |"
echo "|---|---|---|---|---|---|---|---|"
python3 - "$tmp" "${tau[isco]}" "${tau[eccentric]}" "${tau[charged]}" <<'PY'
import statistics, sys
tmp = sys.argv[1]
taus = {"isco": sys.argv[2], "eccentric": sys.argv[3], "charged": sys.argv[4], "escape": "1e5"}
for c in ("isco", "eccentric", "charged", "escape"):
    rows = [l.split() for l in open(f"{tmp}/all-{c}")]
    # timecmd.py's wall user sys maxrss status, then the steps
    wall = statistics.median(float(x[0]) for x in rows)
    cpu = statistics.median(float(x[1]) + float(x[2]) for x in rows)
    steps = int(rows[0][5])
    per_orbit = f"{cpu / 1000 * 1e6:.0f}" if c != "escape" else ""
    print(f"| {c} | {len(rows)} | {taus[c]} | {steps} | {wall:.3f} | {cpu:.3f} | {per_orbit} | "
          f"{cpu / steps * 1e6:.2f} |")
PY
