#!/usr/bin/env bash
# MPI: mpirun -np 2 curray_mpi gives the files of a one-process
# run, byte for byte, for a 3-frame run (frames spread over the ranks) and a
# 1-frame run (rows spread over the ranks); more ranks than rows is refused;
# a rank killed with SIGKILL ends the run, the finished frames are kept and
# complete, and curray --resume finishes them into the one-process files.
# The backend: --backend auto gives the one-process run's; --backend cuda
# gives the one-process GPU run's files where a GPU is usable, and is
# refused by each rank where none is (the case on CI).
#
#   bash tests/cli/test_mpi.sh path/to/curray path/to/curray_mpi [repository root]
#
# info.txt is compared without its times (Started, wall time, rays per
# second) and its backend line (which names the ranks), record by record
# after sorting by frame (an MPI run records frames in the order they
# finish). mpirun runs with --oversubscribe (the ranks may outnumber the
# cores), and --allow-run-as-root as root. About 15 s on two cores.
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
CURRAY_MPI=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
ROOT=$(cd "${3:-$(dirname "$0")/../..}" && pwd)
command -v mpirun >/dev/null || { echo "test_mpi: no mpirun (Debian: openmpi-bin)" >&2; exit 1; }
. "$(dirname "$0")/lib.sh" test-mpi
MPIRUN=(mpirun --oversubscribe -np 2)
[ "$(id -u)" = 0 ] && MPIRUN+=(--allow-run-as-root)
# Open MPI's own allocations are not curray's: no leak check under ASan
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

# info.txt without times and backend, records sorted by frame
untimed() {
    awk '/^Frame [0-9]+$/ { k = $2 } /^Finished / { next }
         /^(Started|Resumed) |^  (wall time|rays per second|backend) / { next }
         { printf "%08d %s\n", (k == "" ? -1 : k), $0 }' "$1" | sort -s -k1,1
}
# same DIR_A DIR_B FRAMES: every frame file and the untimed info.txt agree
same() {
    local f k
    for ((k = 0; k < $3; k++)); do
        for f in c_$k.png r_$k.png d_$k.csv; do
            cmp -s "$1/$f" "$2/$f" || { echo "$f differs"; return 1; }
        done
    done
    diff <(untimed "$1/info.txt") <(untimed "$2/info.txt")
}

cp "$ROOT/scenes/listing-7.1.6-sphere-orbit.yml" orbit.yml
cp "$ROOT/scenes/listing-7.2.1-kerr-disc.yml" kerr.yml

# --- 3 frames: frames over the ranks -------------------------------------
"$CURRAY" -s orbit.yml -o one3 -x 96 -y 72 -f 3 -t icrd -a >/dev/null 2>&1
OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s orbit.yml -o mpi3 -x 96 -y 72 -f 3 -t icrd -a 2>&1)
RC=$?
if [ $RC = 0 ] && has "on each of 2 MPI ranks" && same one3 mpi3 3 >diff3.txt 2>&1; then
    ok "3 frames on 2 ranks: the files of a one-process run, byte for byte"
else
    bad "3 frames on 2 ranks" "rc $RC; $(cat diff3.txt)"
fi

# --- 1 frame: rows over the ranks ----------------------------------------
"$CURRAY" -s kerr.yml -o one1 -x 97 -y 73 -t icrd -a -v >/dev/null 2>&1
OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s kerr.yml -o mpi1 -x 97 -y 73 -t icrd -a -v 2>&1)
RC=$?
if [ $RC = 0 ] && has "rank 0 received" && same one1 mpi1 1 >diff1.txt 2>&1; then
    ok "1 frame on 2 ranks (rows spread): the files of a one-process run, byte for byte"
else
    bad "1 frame on 2 ranks" "rc $RC; $(cat diff1.txt)"
fi

# --- the backend: --backend auto is the one-process run's (the CPU here
# when no GPU is usable); --backend cuda traces on every rank's GPU (local
# rank k on the k-th usable GPU of its node, modulo their number), or, when
# a rank has none, is refused by that rank before anything is written --------
backend() { sed -n 's/^  backend  *//p' "$1/info.txt"; }
b1=$(backend one3)
bm=$(backend mpi3)
if [ -n "$b1" ] && [ "$bm" = "$b1 on each of 2 MPI ranks" ]; then
    ok "--backend auto: the one-process backend on each rank ($bm)"
else
    bad "--backend auto on 2 ranks" "one process '$b1', MPI '$bm'"
fi
if "$CURRAY" -s kerr.yml -o gpu1 -x 97 -y 73 -t icrd -a --backend cuda >gpu1.log 2>&1; then
    # a usable GPU: both ranks share it (or take one each) and the files are
    # the one-process GPU run's, for frames and for rows spread over ranks
    "$CURRAY" -s orbit.yml -o gpu3 -x 96 -y 72 -f 3 -t icrd -a --backend cuda >/dev/null 2>&1
    OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s orbit.yml -o mgpu3 -x 96 -y 72 -f 3 -t icrd -a --backend cuda 2>&1)
    RC=$?
    OUT+=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s kerr.yml -o mgpu1 -x 97 -y 73 -t icrd -a --backend cuda 2>&1)
    RC=$((RC + $?))
    if [ $RC = 0 ] && same gpu3 mgpu3 3 >diffg.txt 2>&1 && same gpu1 mgpu1 1 >>diffg.txt 2>&1 &&
       [ "$(backend mgpu1)" = "$(backend gpu1) on each of 2 MPI ranks" ]; then
        ok "--backend cuda on 2 ranks: the files of a one-process GPU run (3 frames; 1 frame by rows)"
    else
        bad "--backend cuda on 2 ranks" "rc $RC; $(cat diffg.txt)"
    fi
else
    OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s kerr.yml -o nogpu -x 8 -y 6 -a --backend cuda 2>&1)
    RC=$?
    if [ $RC != 0 ] && has "MPI rank 0 on " && has "MPI rank 1 on " && has ": --backend cuda: " && [ ! -e nogpu ]; then
        ok "--backend cuda on 2 ranks without a usable GPU is refused by each rank (no GPU here: the GPU MPI run is not tested)"
    else
        bad "--backend cuda without a GPU" "rc $RC"
    fi
fi

# --- more ranks than rows --------------------------------------------------
OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" -s kerr.yml -o rows -x 8 -y 1 -a 2>&1)
RC=$?
if [ $RC != 0 ] && has "2 MPI ranks for a one-frame run of 1 rows: more ranks than rows" && [ ! -e rows ]; then
    ok "more ranks than rows of a one-frame run is refused"
else
    bad "more ranks than rows" "rc $RC"
fi

# --- plain curray under mpirun ----------------------------------------------
# curray has no MPI: under mpirun each process would render the whole run
# into the same folder. Each refuses, pointing to curray_mpi; nothing is
# written. One process under mpirun (-np 1) renders.
OUT=$(timeout 120 "${MPIRUN[@]}" "$CURRAY" -s kerr.yml -o dup -x 8 -y 6 -t ic -a 2>&1)
RC=$?
if [ $RC != 0 ] && has "was started by an MPI launcher as one of 2 processes (OMPI_COMM_WORLD_SIZE=2), but it is built without MPI" &&
    has "start curray_mpi instead (mpirun -np 2 curray_mpi" && [ ! -e dup ]; then
    ok "plain curray under mpirun -np 2 is refused, pointing to curray_mpi"
else
    bad "plain curray under mpirun -np 2" "rc $RC"
fi
ONE=(mpirun -np 1)
[ "$(id -u)" = 0 ] && ONE+=(--allow-run-as-root)
OUT=$(timeout 120 "${ONE[@]}" "$CURRAY" -s kerr.yml -o one -x 8 -y 6 -t ic -a 2>&1)
RC=$?
if [ $RC = 0 ] && [ -s one/c_0.png ]; then
    ok "plain curray under mpirun -np 1 renders"
else
    bad "plain curray under mpirun -np 1" "rc $RC"
fi

# --- a rank dies ---------------------------------------------------------------
ARGS=(-s orbit.yml -x 320 -y 240 -f 6 -t icrd -a --threads 1)
"$CURRAY" "${ARGS[@]}" -o one6 >/dev/null 2>&1
timeout 120 "${MPIRUN[@]}" "$CURRAY_MPI" "${ARGS[@]}" -o dead >dead.log 2>&1 &
job=$!
for _ in $(seq 1 6000); do
    grep -qx "Frame 1" dead/info.txt 2>/dev/null && break
    sleep 0.01
done
killed=""
for p in $(pgrep -f "$CURRAY_MPI"); do
    if tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then
        kill -9 "$p" && killed=$p
    fi
done
wait $job
RC=$?
OUT=$(cat dead.log)
n=$(grep -cE '^Frame [0-9]+$' dead/info.txt)
complete=1
for f in dead/c_*.png dead/r_*.png dead/d_*.csv; do
    cmp -s "$f" "one6/$(basename "$f")" || complete=0
done
# Rank 0 traces items too: when rank 1 dies holding no item (it may have
# finished its last one just before the kill), rank 0 completes the run.
# Either way every kept frame is whole and nothing temporary is left.
ended=0
if has "interrupted; $n of 6 frames finished and kept in dead" && [ "$n" -ge 2 ] && [ "$n" -le 6 ]; then
    ended=1
elif has "done: 6 frames in" && [ "$n" = 6 ]; then
    ended=1
fi
if [ -n "$killed" ] && [ $RC != 0 ] && has "exited on signal 9" && [ $ended = 1 ] &&
   [ $complete = 1 ] && ! ls -a dead | grep -q '\.tmp\.'; then
    ok "rank 1 killed: the run ends with a message, $n finished frames kept whole, no temporaries"
else
    bad "a rank dies" "rc $RC, killed '$killed', $n frames, complete $complete"
fi
OUT=$(timeout 120 "$CURRAY" "${ARGS[@]}" -o dead --resume 2>&1)
RC=$?
if [ $RC = 0 ] && has "resuming: $n of 6 frames" && same one6 dead 6 >diff6.txt 2>&1; then
    ok "--resume after the dead rank gives the files of an uninterrupted run"
else
    bad "--resume after a dead rank" "rc $RC; $(cat diff6.txt)"
fi

finish
