#!/usr/bin/env bash
# bench/horizons.sh: the cost per ray of a frame inside the horizon against
# one outside, same scene and size: scenes/plunge-schwarzschild.yml (a
# Keplerian disc, the sky grid, 300 deg fisheye) with observer.r fixed at
# 3 M (outside r+ = 2 M), 1 M and 0.3 M (inside), scenes/plunge-kerr.yml
# (a = 0.6, r+ = 1.8 M, r- = 0.2 M) at 3 M, 1 M and 0.15 M (inside r-), and
# scenes/plunge-reissner-nordstrom.yml (Q = 0.8, r+ = 1.6 M, r- = 0.4 M) at
# 3 M, 1 M and 0.35 M (inside r-). Runs are interleaved; per
# case it reports the median wall and CPU time, the steps per ray (info.txt)
# and the CPU time per ray.
#
# Usage: bench/horizons.sh [--runs R] [--size WxH] [--threads T]
#   defaults: 3 runs, 320x180, curray's default threads
# Environment: CURRAY_BIN (default build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=3 size=320x180 threads=""
bench_args horizons.sh 15 "$@"
bench_bin horizons.sh "$root/build/curray"
bench_tmpdir
cases="schwarzschild:3 schwarzschild:1 schwarzschild:0.3 kerr:3 kerr:1 kerr:0.15
       reissner-nordstrom:3 reissner-nordstrom:1 reissner-nordstrom:0.35"
for c in $cases; do
    hole=${c%:*} r=${c#*:}
    sed -e "s|^  r: \[infall, .*\]|  r: $r|" -e "s|image: sky_grid.png|image: $root/scenes/sky_grid.png|" \
        "$root/scenes/plunge-$hole.yml" >"$tmp/$hole-$r.yml"
done
for k in $(seq "$runs"); do
    for c in $cases; do
        hole=${c%:*} r=${c#*:} o=$tmp/o-$hole-$r
        rm -rf "$o"
        python3 "$here/timecmd.py" "$tmp/t-$hole-$r.$k" -- "$bin" -s "$tmp/$hole-$r.yml" -o "$o" \
            -x "$w" -y "$h" -t ci -a true --backend cpu ${threads:+--threads "$threads"}
        steps=$(bench_info_steps "$o")
        rays=$(bench_info_rays "$o")
        echo "$(cat "$tmp/t-$hole-$r.$k") $steps $rays" >>"$tmp/all-$hole-$r"
    done
done
echo "| hole | r (M) | inside r+ | runs | wall median (s) | CPU median (s) | steps/ray | CPU us/ray |"
echo "|---|---|---|---|---|---|---|---|"
for c in $cases; do
    hole=${c%:*} r=${c#*:}
    python3 - "$tmp/all-$hole-$r" "$hole" "$r" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
# timecmd.py's wall user sys maxrss status, then steps and rays of info.txt
wall = statistics.median(float(x[0]) for x in rows)
cpu = statistics.median(float(x[1]) + float(x[2]) for x in rows)
steps, rays = float(rows[0][5]), float(rows[0][6])
# r+ and r- of each scene's hole (Schwarzschild, Kerr a = 0.6, RN Q = 0.8)
rp, rm = {"schwarzschild": (2.0, 0.0), "kerr": (1.8, 0.2), "reissner-nordstrom": (1.6, 0.4)}[sys.argv[2]]
r = float(sys.argv[3])
where = "inside r-" if r < rm else ("yes" if r < rp else "no")
print(f"| {sys.argv[2]} | {r:g} | {where} | {len(rows)} | {wall:.3f} | {cpu:.3f} | "
      f"{steps / rays:.1f} | {1e6 * cpu / rays:.2f} |")
PY
done
