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
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
runs=3 size=320x240 threads=""
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    -h | --help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "antialias.sh: unknown option '$1'" >&2; exit 2 ;;
    esac
done
bin=${CURRAY_BIN:-}
[ -n "$bin" ] || for b in "$root/build-aa/curray" "$root/build/curray"; do [ -x "$b" ] && bin=$b && break; done
[ -x "$bin" ] || { echo "antialias.sh: no curray binary (set CURRAY_BIN)" >&2; exit 1; }
w=${size%x*} h=${size#*x}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for n in 1 2 3; do printf 'raytracer: {samples: %d}\n' "$n" >"$tmp/c$n.yml"; done
for r in $(seq "$runs"); do
    for n in 1 2 3; do
        rm -rf "$tmp/o$n"
        python3 "$here/timecmd.py" "$tmp/t$n.$r" -- "$bin" -s "$root/scenes/demo.yml" \
            -c "$tmp/c$n.yml" -o "$tmp/o$n" -x "$w" -y "$h" -t ci -a true --backend cpu ${threads:+--threads "$threads"}
        steps=$(awk '$1 == "integrator" && $2 == "steps" {print $3; exit}' "$tmp/o$n/info.txt")
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
