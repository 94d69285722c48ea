#!/usr/bin/env bash
# bench/ab.sh: two curray binaries on the same scenes, side by side: per
# scene, the median CPU time (user + sys, bench/timecmd.py) of --runs frames
# of each (A and B alternate run by run, the order reversed every other run),
# the integration steps (info.txt) and CPU-ns per step, and B / A.
# Frames write info.txt only (-t i) unless --types says more; one thread,
# CPU backend.
#
# Usage: bench/ab.sh A_BIN B_BIN [--runs N] [--size WxH] [--config FILE]
#                    [--types T] [--work DIR] SCENE...
#   A_BIN, B_BIN   the two curray binaries (e.g. main's and a branch's)
#   --runs N       frames per binary and scene (7)
#   --size WxH     frame size (120x120)
#   --config FILE  system configuration for -c (default: bench/scenes/mino.yml)
#   --types T      output types for -t (i; e.g. id for the CSV's science frames)
#   --work DIR     renders and logs (build-bench/ab-work)
# Output: a markdown table on stdout.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

case ${1:-} in -h | --help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
[ $# -ge 3 ] || die "usage: bench/ab.sh A_BIN B_BIN [options] SCENE... (see --help)"
A=$1 B=$2
shift 2
[ -x "$A" ] || die "not an executable: $A"
[ -x "$B" ] || die "not an executable: $B"
runs=7 size=120x120 cfg="$BENCH_DIR/scenes/mino.yml" work="$BUILD_DIR/ab-work" types=i scenes=()
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --config) cfg=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --types) types=$2; shift 2 ;;
    *) scenes+=("$1"); shift ;;
    esac
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || die "--runs needs a positive integer, got '$runs'"
[[ $types =~ ^[a-z]+$ && $types == *i* ]] || die "--types needs letters of -t with i (info.txt: the steps), got '$types'"
[[ $size =~ ^([1-9][0-9]*)x([1-9][0-9]*)$ ]] || die "--size needs WxH, got '$size'"
w=${BASH_REMATCH[1]} h=${BASH_REMATCH[2]}
mkdir -p "$work"

one() { # BIN SCENE OUT -> "cpu_s"
    local bin=$1 scene=$2 o=$3
    rm -rf "$o" && mkdir -p "$o"
    python3 "$BENCH_DIR/timecmd.py" "$o/time" -- "$bin" -s "$scene" -c "$cfg" -o "$o" -x "$w" -y "$h" \
        -t "$types" -a true -q true --backend cpu --threads 1 || die "$bin failed on $scene (see $o/time.log)"
    awk '{printf "%.6f\n", $2 + $3}' "$o/time"
}

echo "| scene | ${w}x${h} | A CPU s | B CPU s | B / A | A steps | B steps | A ns/step | B ns/step |"
echo "|---|---|---|---|---|---|---|---|---|"
for s in "${scenes[@]}"; do
    n=$(basename "$s" .yml)
    : >"$work/$n-A" && : >"$work/$n-B"
    for ((k = 0; k < runs; k++)); do
        if ((k % 2 == 0)); then order="A B"; else order="B A"; fi
        for x in $order; do
            if [ "$x" = A ]; then bin=$A; else bin=$B; fi
            one "$bin" "$s" "$work/$n-$x-run" >>"$work/$n-$x"
        done
    done
    ta=$(bench_median <"$work/$n-A") tb=$(bench_median <"$work/$n-B")
    sa=$(bench_info_value "$work/$n-A-run/info.txt" steps)
    sb=$(bench_info_value "$work/$n-B-run/info.txt" steps)
    awk -v n="$n" -v ta="$ta" -v tb="$tb" -v sa="$sa" -v sb="$sb" -v sz="${w}x${h}" 'BEGIN {
        printf "| %s | %s | %.4f | %.4f | %.3f | %d | %d | %.1f | %.1f |\n", n, sz, ta, tb, tb / ta, sa, sb,
            1e9 * ta / sa, 1e9 * tb / sb }'
done
echo
echo "A: $A ($("$A" --version 2>&1 | head -1)); B: $B ($("$B" --version 2>&1 | head -1)); $runs frames each, medians; $(nproc) cores, $(uname -m)."
