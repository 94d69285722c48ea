#!/usr/bin/env bash
# bench/antialias.sh: the cost of antialiasing (raytracer.samples N, N x N
# rays per pixel) on `make demo`'s scene, N = 1, 2, 3 side by side.
# Runs are interleaved (N = 1, 2, 3, 1, 2, 3, ...); per N it reports the
# median wall and CPU (user + sys) time, the integrator steps from info.txt
# (the sum over all sub-rays), and the ratios to N = 1 (expected about N^2).
#
# Usage: bench/antialias.sh [--runs R] [--size WxH] [--threads T]
#   defaults: 3 runs, 320x240, curray's default threads
# Environment: CURRAY_BIN (default build-aa/curray, else build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=3 size=320x240 threads=""
bench_args antialias.sh 11 "$@"
bench_bin antialias.sh "$root/build-aa/curray" "$root/build/curray"
bench_tmpdir
for n in 1 2 3; do printf 'raytracer: {samples: %d}\n' "$n" >"$tmp/c$n.yml"; done
for r in $(seq "$runs"); do
    for n in 1 2 3; do
        rm -rf "$tmp/o$n"
        python3 "$here/timecmd.py" "$tmp/t$n.$r" -- "$bin" -s "$root/scenes/demo.yml" \
            -c "$tmp/c$n.yml" -o "$tmp/o$n" -x "$w" -y "$h" -t ci -a true --backend cpu ${threads:+--threads "$threads"}
        steps=$(bench_info_steps "$tmp/o$n")
        echo "$(cat "$tmp/t$n.$r") $steps" >>"$tmp/all$n"
    done
done
echo "| N | rays/pixel | runs | wall median (s) | CPU median (s) | steps | CPU / N=1 | steps / N=1 |"
echo "|---|---|---|---|---|---|---|---|"
python3 - "$tmp" "$runs" <<'PY'
import statistics, sys
tmp, runs = sys.argv[1], sys.argv[2]
rows = {}
for n in (1, 2, 3):
    rec = [l.split() for l in open(f"{tmp}/all{n}")]
    wall = statistics.median(float(r[0]) for r in rec)
    cpu = statistics.median(float(r[1]) + float(r[2]) for r in rec)
    steps = statistics.median(int(r[5]) for r in rec)
    rows[n] = (wall, cpu, steps)
for n in (1, 2, 3):
    wall, cpu, steps = rows[n]
    print(f"| {n} | {n*n} | {runs} | {wall:.3f} | {cpu:.3f} | {steps} | "
          f"{cpu / rows[1][1]:.2f} | {steps / rows[1][2]:.2f} |")
PY
