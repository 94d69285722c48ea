#!/usr/bin/env bash
# bench/observer.sh: the cost of a frame for every observer motion,
# side by side in one run: static, zamo, orbit, infall and an explicit
# velocity, on one scene (a = 0.9 M, observer at r = 30 M on the equator
# looking at the hole, the chessboard disc and the sky_grid.png sky at
# infinity, rectilinear 70 deg), only observer.motion changing. Runs are
# interleaved (each motion once per round); per motion it reports the median
# wall and CPU (user + sys) time, the integrator steps from info.txt, the CPU
# time per step, and the ratios to static. The motions see slightly different
# images (aberration: v = 0.002 c for the ZAMO, 0.18 c on the orbit, 0.26 c
# falling in, 0.3 c given), so the steps differ a little; CPU per step is the
# cost of the same work. --projection fisheye|equirectangular repeats it with
# that projection (hfov 180 deg for the fisheye).
#
# Usage: bench/observer.sh [--runs R] [--size WxH] [--threads T]
#                          [--projection P] [--backend cpu|cuda]
#   defaults: 5 runs, 320x240, curray's default threads, rectilinear, cpu
# Environment: CURRAY_BIN (default build-h13/curray, else build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=5 size=320x240 threads="" proj=rectilinear backend=cpu
BENCH_OPTS="--projection=proj --backend=backend" bench_args observer.sh 19 "$@"
bench_bin observer.sh "$root/build-h13/curray" "$root/build/curray"
bench_tmpdir
motions=(static zamo orbit infall velocity)
case $proj in
rectilinear) view="hfov: 70" ;;
fisheye) view="hfov: 180, projection: fisheye" ;;
equirectangular) view="projection: equirectangular" ;;
*) echo "observer.sh: unknown projection '$proj'" >&2; exit 2 ;;
esac
for m in "${motions[@]}"; do
    mv=$m
    [ "$m" = velocity ] && mv="[0.1, 0.1, -0.26]"
    cat >"$tmp/$m.yml" <<YML
metric: {m: 1, a: 0.9, q: 0}
horizon_color: [0, 0, 0]
observer: {r: 30, theta: 90, phi: 0, $view, motion: $mv}
accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 15]}
skymap: {image: $root/scenes/sky_grid.png}
YML
done
for r in $(seq "$runs"); do
    for m in "${motions[@]}"; do
        rm -rf "$tmp/o-$m"
        python3 "$here/timecmd.py" "$tmp/t-$m.$r" -- "$bin" -s "$tmp/$m.yml" -o "$tmp/o-$m" \
            -x "$w" -y "$h" -t ci -a true --backend "$backend" ${threads:+--threads "$threads"}
        steps=$(bench_info_steps "$tmp/o-$m")
        echo "$(cat "$tmp/t-$m.$r") $steps" >>"$tmp/all-$m"
    done
done
echo "projection $proj, $size, $runs runs, backend $backend, $(basename "$bin")"
echo
echo "| motion | runs | wall median (s) | CPU median (s) | steps | CPU/step (us) | wall / static | CPU / static | CPU per step / static |"
echo "|---|---|---|---|---|---|---|---|---|"
python3 - "$tmp" "$runs" "${motions[@]}" <<'PY'
import statistics, sys
tmp, runs, motions = sys.argv[1], sys.argv[2], sys.argv[3:]
rows = {}
for m in motions:
    rec = [l.split() for l in open(f"{tmp}/all-{m}")]
    wall = statistics.median(float(r[0]) for r in rec)
    cpu = statistics.median(float(r[1]) + float(r[2]) for r in rec)
    steps = statistics.median(int(r[5]) for r in rec)
    rows[m] = (wall, cpu, steps)
w0, c0, s0 = rows["static"]
for m in motions:
    wall, cpu, steps = rows[m]
    print(f"| {m} | {runs} | {wall:.3f} | {cpu:.3f} | {steps} | {1e6 * cpu / steps:.3f} | "
          f"{wall / w0:.3f} | {cpu / c0:.3f} | {(cpu / steps) / (c0 / s0):.3f} |")
PY
