#!/usr/bin/env bash
# bench/scaling.sh: how the CPU frame time scales, measured side by side.
# One scene (default schwarzschild-disc, listing 7.1.1 at theta = 85 deg) in
# four cases, interleaved run by run so load changes hit all of them alike:
#   T1  S x S, 1 thread
#   T2  S x S, 2 threads (the base case of the two ratios below)
#   R4  2S x 2S, 2 threads          (4x the pixels: time should grow 4x)
#   C2  S x S, 2 threads, c halved  (bench/scenes/c-half.yml, step_multiplier
#                                    0.015625: steps and time should double)
# and reports thread speed-up T1/T2 and efficiency (T1/T2)/2, and the time
# and step ratios R4/T2 and C2/T2, from the medians.
#
# Usage: bench/scaling.sh [--size S] [--runs N] [--scene NAME] [--threads N2] [--out PREFIX]
#        bench/scaling.sh --from PREFIX-runs.csv   (report again from earlier runs)
#   defaults: --size 256 --runs 3 --scene schwarzschild-disc --threads 2
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

size=256 runs=3 scene=schwarzschild-disc nt=2 out="" from=""
while [ $# -gt 0 ]; do
    case $1 in
    --size) size=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --threads) nt=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --from) from=$2; shift 2 ;;
    -h | --help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
if [ -n "$from" ]; then
    runs_csv=$from sum_csv=${from%-runs.csv}.csv
    start_uptime="(see load column)" end_uptime="(see load column)"
    scene=$(awk -F, 'NR == 2 {print $1}' "$runs_csv")
    nt=$(awk -F, 'NR == 3 {print $3}' "$runs_csv")
else
    [ -z "$out" ] && out="$BENCH_DIR/results/scaling-$(date +%Y%m%d-%H%M%S)"
    mkdir -p "$(dirname "$out")"
    bench_ensure_binary cpu
    bench_ensure_time
    runs_csv="$out-runs.csv" sum_csv="$out.csv"
    echo "$BENCH_RUNS_HEADER" >"$runs_csv"
    half="$BENCH_DIR/scenes/c-half.yml"
    big=$((2 * size))
    start_uptime=$(uptime)
    for r in $(seq 1 "$runs"); do
        bench_measure "$scene" "$size" "$size" cpu 1 - "$r" "$runs_csv"
        bench_measure "$scene" "$size" "$size" cpu "$nt" - "$r" "$runs_csv"
        bench_measure "$scene" "$big" "$big" cpu "$nt" - "$r" "$runs_csv"
        bench_measure "$scene" "$size" "$size" cpu "$nt" "$half" "$r" "$runs_csv"
    done
    end_uptime=$(uptime)
fi
bench_summarise "$runs_csv" >"$sum_csv"

echo "## curray CPU scaling: $scene"
echo
echo "Machine: $(awk -F': ' '/^model name/ {print $2; exit}' /proc/cpuinfo), $(nproc) online cores."
echo "Load (uptime) before: ${start_uptime#*load average: }; after: ${end_uptime#*load average: }."
echo
bench_markdown "$sum_csv"
echo
# rows of the summary, in order: T1, T2, R4, C2
awk -F, -v nt="$nt" '
NR == 1 { next }
{ t[NR - 1] = $8; s[NR - 1] = $12; ns[NR - 1] = $16; cn[NR - 1] = $22; cpu[NR - 1] = $20 }
END {
    printf "| ratio | measured | ideal |\n|---|---|---|\n"
    printf "| threads 1 -> %d: speed-up (time T1 / T%d) | %.2f | %d |\n", nt, nt, t[1] / t[2], nt
    printf "| threads 1 -> %d: parallel efficiency | %.0f %% | 100 %% |\n", nt, 100 * t[1] / t[2] / nt
    printf "| threads 1 -> %d: CPU share of the process (CPU %%) | %s -> %s | 100 -> %d |\n", nt, cpu[1], cpu[2], 100 * nt
    if (cn[1] != "" && cn[2] != "")
        printf "| threads 1 -> %d: CPU-ns/step ratio T%d / T1 (per-thread overhead; load-independent) | %.3f | 1 |\n", nt, nt, cn[2] / cn[1]
    printf "| pixels x4: time ratio | %.2f | 4 |\n", t[3] / t[2]
    printf "| pixels x4: photon-step ratio | %.3f | 4 |\n", s[3] / s[2]
    printf "| pixels x4: ns/step ratio | %.2f | 1 |\n", ns[3] / ns[2]
    printf "| c halved: photon-step ratio | %.3f | 2 |\n", s[4] / s[2]
    printf "| c halved: time ratio | %.2f | 2 |\n", t[4] / t[2]
    printf "| c halved: ns/step ratio | %.2f | 1 |\n", ns[4] / ns[2]
    if (cn[2] != "" && cn[3] != "" && cn[4] != "") {
        printf "| pixels x4: CPU-time ratio | %.2f | 4 |\n", cn[3] * s[3] / (cn[2] * s[2])
        printf "| c halved: CPU-time ratio | %.2f | 2 |\n", cn[4] * s[4] / (cn[2] * s[2])
    }
}' "$sum_csv"
echo
echo "Runs: $runs_csv; medians: $sum_csv"
