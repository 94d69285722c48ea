#!/usr/bin/env bash
# bench/keplerian.sh: what a Keplerian disc costs against the chessboard
# (the target: at most 1.2x). The same scene twice: scenes/keplerian-
# interstellar.yml (a = 0.6, 85 deg, starry sky, disc from the ISCO to 20 M)
# as shipped, and with its accretion section replaced by a chessboard of the
# same radii [r_isco, 20]. Runs alternate (keplerian, chessboard, chessboard,
# keplerian, ...); reported: the medians of the frame's render time (info.txt
# "wall time": the traced frame, the measure of the issue), of the process's
# wall and CPU (user + sys) time (with loading the sky and writing the PNG),
# the integrator steps (info.txt), and keplerian / chessboard as the ratio of
# the medians and the median of the per-run ratios.
#
# Usage: bench/keplerian.sh [--runs R] [--size WxH] [--threads T]
#   defaults: 7 runs, 640x360, curray's default threads
# Environment: CURRAY_BIN (binary; default build/curray).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
here=$BENCH_DIR root=$REPO_DIR
runs=7 size=640x360 threads=""
bench_args keplerian.sh 13 "$@"
bench_bin keplerian.sh "$root/build/curray"
bench_tmpdir
kep="$root/scenes/keplerian-interstellar.yml"
# the chessboard twin: same scene, accretion from the ISCO (info.txt) to 20
"$bin" -s "$kep" -o "$tmp/probe" -x 8 -y 8 -t i -a true -q true
risco=$(awk '$1 == "r_isco" {print $2; exit}' "$tmp/probe/info.txt")
sed '/^accretion:/,$d' "$kep" >"$tmp/chess.yml"
printf 'accretion:\n    color1: [0, 255, 0]\n    resolution: [2, 12]\n    radius: [%s, 20]\n' \
    "$risco" >>"$tmp/chess.yml"
cp "$kep" "$tmp/kep.yml"
sed -i "s|image: sky.png|image: $root/scenes/sky.png|" "$tmp/kep.yml" "$tmp/chess.yml"
one() { # name run
    rm -rf "$tmp/o$1"
    python3 "$here/timecmd.py" "$tmp/t$1.$2" -- "$bin" -s "$tmp/$1.yml" -o "$tmp/o$1" \
        -x "$w" -y "$h" -t ci -a true --backend cpu ${threads:+--threads "$threads"}
    steps=$(bench_info_steps "$tmp/o$1")
    frame=$(awk '$1 == "wall" && $2 == "time" {print $3; exit}' "$tmp/o$1/info.txt")
    echo "$2 $(cat "$tmp/t$1.$2") $steps $frame" >>"$tmp/all-$1"
}
for r in $(seq "$runs"); do
    if [ $((r % 2)) = 1 ]; then one kep "$r"; one chess "$r"; else one chess "$r"; one kep "$r"; fi
done
echo "$bin -s {keplerian-interstellar.yml, its chessboard twin} -x $w -y $h -t ci -a true --backend cpu${threads:+ --threads $threads}; $runs runs each, alternating; r_isco = $risco"
echo
python3 - "$tmp" <<'PY'
import statistics as st, sys
tmp = sys.argv[1]
rec = {n: {int(l.split()[0]): l.split()[1:] for l in open(f"{tmp}/all-{n}")} for n in ("kep", "chess")}
def col(n, f): return [f(v) for v in rec[n].values()]
# fields: wall user sys maxrss status steps frame
wall = lambda v: float(v[0]); cpu = lambda v: float(v[1]) + float(v[2]); frame = lambda v: float(v[6])
print("| disc | runs | frame time, info.txt (s) | process wall (s) | process CPU (s) | steps |")
print("|---|---|---|---|---|---|")
for n, name in (("kep", "keplerian"), ("chess", "chessboard")):
    print(f"| {name} | {len(rec[n])} | {st.median(col(n, frame)):.3f} | {st.median(col(n, wall)):.3f} "
          f"| {st.median(col(n, cpu)):.3f} | {int(st.median(col(n, lambda v: int(v[5]))))} |")
runs = sorted(rec["kep"])
for what, f in (("frame", frame), ("process wall", wall), ("process CPU", cpu)):
    m = st.median(col("kep", f)) / st.median(col("chess", f))
    p = st.median(f(rec["kep"][r]) / f(rec["chess"][r]) for r in runs)
    print(f"\nkeplerian / chessboard, {what} time: ratio of the medians **{m:.3f}**, median of the per-run ratios {p:.3f}", end="")
print()
PY
