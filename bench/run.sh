#!/usr/bin/env bash
# bench/run.sh: what a frame costs. Renders the fixed scenes of bench/scenes/
# at fixed sizes with the project's own binary (built into build-bench/ when
# missing) and reports, per scene, size and backend: frame time (median of
# --runs), rays/s, photon-steps (RK4 steps, from info.txt), photon-steps/s,
# ns per photon-step, mean steps per ray and peak resident memory.
#
# Usage: bench/run.sh [--runs N] [--sizes "512 1024"] [--scenes "a b"]
#                     [--threads N] [--backend cpu|cuda] [--config FILE]
#                     [--out PREFIX] [--quick]
#   --runs N        runs per scene and size; the table shows the median (3)
#   --sizes "..."   square frame sizes in pixels ("512 1024")
#   --scenes "..."  names in bench/scenes/ (all: schwarzschild-disc kerr-disc
#                   starry-sky sphere)
#   --threads N     CPU threads (default: curray's default, all online cores)
#   --backend B     cpu (default) or cuda
#   --config FILE   system configuration passed with -c (default:
#                   bench/scenes/defaults.yml, the built-in defaults)
#   --out PREFIX    results go to PREFIX-runs.csv (every run) and PREFIX.csv
#                   (medians); default bench/results/<backend>-<date>
#   --quick         256x256, 1 run: a smoke test of the script, not a result
# Environment: CURRAY_BIN (binary to time), CURRAY_BENCH_BUILD (build folder).
# Output: a markdown table on stdout; progress on stderr.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

runs=3 sizes="512 1024" scenes=$ALL_SCENES threads="-" backend=cpu config="-" out=""
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --scenes) scenes=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --backend) backend=$2; shift 2 ;;
    --config) config=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --out) out=$2; shift 2 ;;
    --quick) runs=1 sizes=256; shift ;;
    -h | --help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
case $backend in cpu | cuda) ;; *) die "--backend is cpu or cuda" ;; esac
[[ $runs =~ ^[1-9][0-9]*$ ]] || die "--runs needs a positive integer"
[ -z "$out" ] && out="$BENCH_DIR/results/$backend-$(date +%Y%m%d-%H%M%S)"
mkdir -p "$(dirname "$out")"

bench_ensure_binary "$backend"
bench_ensure_time

runs_csv="$out-runs.csv" sum_csv="$out.csv"
echo "$BENCH_RUNS_HEADER" >"$runs_csv"
echo "bench: $("$CURRAY" --version 2>&1 | head -1); load before: $(cat /proc/loadavg)" >&2
start_uptime=$(uptime)
# Runs are interleaved (run 1 of every case, then run 2, ...) so a change in
# the machine's load spreads over all cases instead of hitting one.
for r in $(seq 1 "$runs"); do
    for s in $sizes; do
        for sc in $scenes; do
            bench_measure "$sc" "$s" "$s" "$backend" "$threads" "$config" "$r" "$runs_csv"
        done
    done
done
end_uptime=$(uptime)
bench_summarise "$runs_csv" >"$sum_csv"

echo "## curray benchmark: backend $backend, $(date '+%Y-%m-%d %H:%M %Z')"
echo
if [ "$backend" = cpu ]; then
    echo "Machine: $(awk -F': ' '/^model name/ {print $2; exit}' /proc/cpuinfo), $(nproc) online cores; threads: ${threads/-/all cores}."
else
    echo "Device: $("$CURRAY" -i 2>&1 | grep -v '^$' | head -3 | tr '\n' ' ')"
fi
echo "Load (uptime) before: ${start_uptime#*load average: }; after: ${end_uptime#*load average: }."
echo
bench_markdown "$sum_csv"
echo
echo "frame time = curray's render time of the frame (info.txt; the CPU backend notices the end of a frame"
echo "within 0.25 s); ns/step = frame time / photon-steps (throughput of the whole machine); CPU-ns/step ="
echo "(user+sys CPU time of the process) / photon-steps, the cost per step that load on a shared machine"
echo "does not inflate (CPU backend only); CPU % = GNU time's share of a core; load = 1-min load average"
echo "before the run; peak RSS = GNU time's maximum resident set size. Runs: $runs_csv; medians: $sum_csv"
