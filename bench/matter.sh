#!/usr/bin/env bash
# bench/matter.sh: the cost of a frame with a moving sphere (seen with the
# light's travel time, sphere.motion) against the same frame with the sphere
# static, side by side. Scenes: scenes/hot-spot-isco.yml (a = 0.9, a spot of
# radius 0.4 M on the ISCO, seen from r = 1000 M at 60 deg; frame k = 7 of its
# 32, t_obs = 6.1 M) as shipped ("orbit") and with its motion and observer.t/dt
# removed ("static": the spot at its phase of t = 0), the same spot as
# motion: particle ("particle": its worldline tabulated, core/track.h; the
# same pixels as orbit), and the same three from the observer at infinity
# (hextent 14 M). Runs are interleaved; per case it
# reports the median wall and CPU time, the steps per ray (info.txt), the
# sphere pixels and the moving/static and particle/orbit ratios of the CPU
# medians.
#
# Usage: bench/matter.sh [--runs R] [--size WxH] [--threads T]
#   defaults: 5 runs, 320x320, curray's default threads
# Environment: CURRAY_BIN (default build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=5 size=320x320 threads=""
bench_args matter.sh 14 "$@"
bench_bin matter.sh "$root/build/curray"
bench_tmpdir
src=$root/scenes/hot-spot-isco.yml
# frame 7 of the orbit: observer.t = 7 dt, one frame
dt=$(awk '$1 == "dt:" {print $2}' "$src")
t7=$(python3 -c "print(7 * $dt)")
sed -e "s/^  t: 0$/  t: $t7/" -e '/^  dt:/d' "$src" >"$tmp/far-orbit.yml"
# static: r: isco goes with motion: orbit only, so the ISCO's radius (Bardeen,
# Press & Teukolsky) as a number
risco=$(python3 -c "
a = 0.9
z1 = 1 + (1 - a * a) ** (1 / 3) * ((1 + a) ** (1 / 3) + (1 - a) ** (1 / 3))
z2 = (3 * a * a + z1 * z1) ** 0.5
print(repr(3 + z2 - ((3 - z1) * (3 + z1 + 2 * z2)) ** 0.5))")
sed -e '/^  t: /d' -e '/^  dt:/d' -e '/^  motion: orbit/d' -e "s/^  r: isco/  r: $risco/" "$src" \
    >"$tmp/far-static.yml"
# particle: the same spot on the same orbit as motion: particle (its
# worldline integrated from t = -1500 M, circular: prograde, and tabulated;
# the same pixels as orbit, test_worldline_emitter), phase -Omega 1500 there
ph0=$(python3 -c "
import math
print(repr(-1500.0 / ($risco ** 1.5 + 0.9)))")
awk -v ph0="$ph0" '
    /^sphere:/ { sp = 1 }
    sp && /^  (r|theta|phi): / { next }
    sp && /^  motion: orbit/ {
        print "  motion: particle"; print "  particle:"; print "    r: isco"
        print "    theta: 90"; print "    phi: " ph0 " rad"; print "    t: -1500"
        print "    circular: prograde"; print "    tau: 1200"; next }
    { print }' "$tmp/far-orbit.yml" >"$tmp/far-particle.yml"
for m in orbit static particle; do
    sed -e 's/^  r: 1000$/  r: inf/' -e 's/^  hfov: .*/  hextent: 14/' "$tmp/far-$m.yml" >"$tmp/inf-$m.yml"
done
cases="far-static far-orbit far-particle inf-static inf-orbit inf-particle"
for k in $(seq "$runs"); do
    for c in $cases; do
        o=$tmp/o-$c
        rm -rf "$o"
        python3 "$here/timecmd.py" "$tmp/t-$c.$k" -- "$bin" -s "$tmp/$c.yml" -o "$o" \
            -x "$w" -y "$h" -t id -a true --backend cpu ${threads:+--threads "$threads"}
        steps=$(bench_info_steps "$o")
        rays=$(bench_info_rays "$o")
        sph=$(awk -F, '$10 == "sphere"' "$o/d_0.csv" | wc -l)
        echo "$(cat "$tmp/t-$c.$k") $steps $rays $sph" >>"$tmp/all-$c"
    done
done
echo "binary: $bin, $w x $h, $runs runs interleaved, $(nproc) CPUs, load $(cut -d' ' -f1 /proc/loadavg)"
echo "| observer | sphere | runs | wall median (s) | CPU median (s) | steps/ray | sphere pixels | CPU moving/static | CPU particle/orbit |"
echo "|---|---|---|---|---|---|---|---|---|"
python3 - "$tmp" $cases <<'PY'
import statistics, sys
tmp, cases = sys.argv[1], sys.argv[2:]
cpu = {}
for c in cases:
    rows = [l.split() for l in open(f"{tmp}/all-{c}")]
    # timecmd.py's wall user sys maxrss status, then steps, rays, sphere pixels
    wall = statistics.median(float(x[0]) for x in rows)
    cpu[c] = statistics.median(float(x[1]) + float(x[2]) for x in rows)
    steps, rays, sph = float(rows[0][5]), float(rows[0][6]), int(rows[0][7])
    obs, kind = c.split("-")
    ratio = f"{cpu[c] / cpu[obs + '-static']:.3f}" if kind != "static" else ""
    vs_orbit = f"{cpu[c] / cpu[obs + '-orbit']:.3f}" if kind == "particle" else ""
    where = "r = 1000 M" if obs == "far" else "at infinity"
    print(f"| {where} | {kind} | {len(rows)} | {wall:.3f} | {cpu[c]:.3f} | {steps / rays:.2f} | "
          f"{sph} | {ratio} | {vs_orbit} |")
PY
