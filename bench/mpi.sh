#!/usr/bin/env bash
# bench/mpi.sh: how a run scales with MPI ranks, side by side.
# Cases, interleaved run by run so that load changes hit all alike:
#   P1   curray, one process, --threads 1            (the reference)
#   M1   mpirun -np 1 curray_mpi --threads 1         (MPI's own cost)
#   M2   mpirun -np 2 curray_mpi --threads 1         (two ranks, one core each)
#   T2   curray, one process, --threads 2            (the same two cores as threads)
# each for an animation (F frames of S pixels: frames spread over the ranks)
# and for one frame of twice the size in each direction (rows spread).
# Every case runs --backend cpu (an MPI run would use GPUs where every rank
# has one).
# Prints the median wall time of each case, the ratios, and the gather cost
# that rank 0 reports with -v (pixels received and the time spent receiving).
#
# Usage: bench/mpi.sh [--runs N] [--size WxH] [--frames F] [--build DIR]
#   defaults: --runs 3 --size 320x240 --frames 8 --build build
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
root=$REPO_DIR
runs=3 size=320x240 frames=8 build=$root/build
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --build) build=$(cd "$2" && pwd); shift 2 ;;
    -h | --help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/mpi.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    esac
done
for b in curray curray_mpi; do
    [ -x "$build/$b" ] || { echo "bench/mpi.sh: no $build/$b (build with MPI found: libopenmpi-dev)" >&2; exit 1; }
done
w=${size%x*} h=${size#*x}
mpirun=(mpirun --oversubscribe)
[ "$(id -u)" = 0 ] && mpirun+=(--allow-run-as-root)
work=$(mktemp -d "${TMPDIR:-/tmp}/curray-bench-mpi.XXXXXX")
trap 'rm -rf "$work"' EXIT
scene=$root/scenes/listing-7.1.6-sphere-orbit.yml

# run CASE KIND: one timed run; appends "case seconds" to $work/times, the
# gather line of MPI runs to $work/gather
run() {
    local args t0 t1 log=$work/log
    if [ "$2" = anim ]; then args=(-s "$scene" -x "$w" -y "$h" -f "$frames"); else args=(-s "$scene" -x $((2 * w)) -y $((2 * h))); fi
    args+=(--backend cpu) # CPU scaling, also on a machine with a GPU
    args+=(-t icr -a -v -o "$work/out-$1-$2")
    rm -rf "$work/out-$1-$2"
    t0=$(date +%s.%N)
    case $1 in
    P1) "$build/curray" "${args[@]}" --threads 1 >"$log" 2>&1 ;;
    T2) "$build/curray" "${args[@]}" --threads 2 >"$log" 2>&1 ;;
    M1) "${mpirun[@]}" -np 1 "$build/curray_mpi" "${args[@]}" --threads 1 >"$log" 2>&1 ;;
    M2) "${mpirun[@]}" -np 2 "$build/curray_mpi" "${args[@]}" --threads 1 >"$log" 2>&1 ;;
    esac
    t1=$(date +%s.%N)
    echo "$2 $1 $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }')" >>"$work/times"
    grep -h "rank 0 received" "$log" | sed "s/^/$2 $1: /" >>"$work/gather" || true
}
: >"$work/times"
: >"$work/gather"
echo "machine: $(bench_cores_model); load $(load3)"
echo "animation: $frames frames of ${w}x$h; one frame: $((2 * w))x$((2 * h)); scene listing 7.1.6; $runs runs each"
for ((r = 0; r < runs; r++)); do
    for kind in anim one; do
        for c in P1 M1 M2 T2; do run $c $kind; done
    done
done
for kind in anim one; do
    declare -A m=()
    for c in P1 M1 M2 T2; do
        m[$c]=$(awk -v k=$kind -v c=$c '$1 == k && $2 == c { print $3 }' "$work/times" | bench_median)
    done
    printf '%-5s P1 %7.3f s  M1 %7.3f s  M2 %7.3f s  T2 %7.3f s   P1/M2 %.2f  M1/M2 %.2f  T2/M2 %.2f\n' \
        "$kind" "${m[P1]}" "${m[M1]}" "${m[M2]}" "${m[T2]}" \
        "$(awk -v a="${m[P1]}" -v b="${m[M2]}" 'BEGIN { print a / b }')" \
        "$(awk -v a="${m[M1]}" -v b="${m[M2]}" 'BEGIN { print a / b }')" \
        "$(awk -v a="${m[T2]}" -v b="${m[M2]}" 'BEGIN { print a / b }')"
done
echo "gather (rank 0, -v), last run of each:"
for kind in anim one; do grep "^$kind M2" "$work/gather" | tail -1; done
