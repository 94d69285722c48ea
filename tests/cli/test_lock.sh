#!/usr/bin/env bash
# One run per output folder (cli/lock.h): a second curray into a folder that a
# running curray writes is refused, naming the folder, and leaves the first
# run's files alone; a lock file left by a dead process does not block; a
# live holder of the lock (flock(1) here) refuses too; the lock file goes
# when the run ends.
#
#   bash tests/cli/test_lock.sh path/to/curray [repository root]
#
# About 10 s (one run of 4 frames of 320x240 on one thread, in the background).
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
[ -x "$CURRAY" ] || { echo "test_lock: no curray binary at $CURRAY" >&2; exit 2; }
. "$(dirname "$0")/lib.sh" test-lock
cp "$ROOT/scenes/demo.yml" scene.yml

# --- a second run while the first renders ---------------------------------
"$CURRAY" -s scene.yml -o a -x 320 -y 240 -f 4 -t icr --threads 1 -a </dev/null >a.out 2>&1 &
pid=$!
for _ in $(seq 1 6000); do
    [ -e a/.curray.lock ] && break
    sleep 0.01
done
run -s scene.yml -o a -x 16 -y 12 -f 2 -t icd -a
if [ $RC = 1 ] && has "output folder a is in use by another curray (process $pid)" &&
   [ ! -e a/d_0.csv ]; then
    ok "a second run into a folder in use is refused, naming the folder and the process"
else
    bad "second run refused" "rc $RC; $(ls a)"
fi
run -s scene.yml -o a -x 16 -y 12 -f 2 -t icd -a --resume
if [ $RC = 1 ] && has "output folder a is in use by another curray"; then
    ok "--resume into a folder in use is refused"
else
    bad "--resume refused" "rc $RC"
fi
wait $pid
rc_a=$?
if [ $rc_a = 0 ] && grep -q "^Finished 4 of 4 frames$" a/info.txt && grep -q "^  frame size  *320 x 240" a/info.txt &&
   [ -e a/c_3.png ] && [ ! -e a/.curray.lock ]; then
    ok "the first run finishes undisturbed, and its lock file is gone"
else
    bad "first run" "rc $rc_a; $(cat a.out | tail -3); $(ls -a a)"
fi

# --- a lock file left by a dead process -----------------------------------
mkdir stale
dead=$(sh -c 'echo $$')
echo "pid $dead" >stale/.curray.lock
run -s scene.yml -o stale -x 16 -y 12 -t ic -a
if [ $RC = 0 ] && [ -e stale/c_0.png ] && [ ! -e stale/.curray.lock ]; then
    ok "a lock file of a dead process does not block"
else
    bad "stale lock" "rc $RC"
fi

# --- another process holds the lock ---------------------------------------
if command -v flock >/dev/null; then
    mkdir held
    # the sleep itself holds the lock (fd 9), so that killing it frees the folder
    (exec 9>held/.curray.lock && flock -n 9 && exec sleep 30) &
    fl=$!
    for _ in $(seq 1 500); do [ -e held/.curray.lock ] && break; sleep 0.01; done
    sleep 0.2
    run -s scene.yml -o held -x 16 -y 12 -t ic -a
    if [ $RC = 1 ] && has "output folder held is in use by another process" && [ ! -e held/c_0.png ]; then
        ok "a folder locked by another process is refused"
    else
        bad "held lock" "rc $RC"
    fi
    kill $fl 2>/dev/null
    wait $fl 2>/dev/null
    run -s scene.yml -o held -x 16 -y 12 -t ic -a
    if [ $RC = 0 ] && [ -e held/c_0.png ]; then ok "once the holder ends, the folder is free"; else bad "released" "rc $RC"; fi
else
    echo "FAIL no flock(1) to hold a lock"; failed=$((failed + 1))
fi

# --- a new folder: two runs that both create it ---------------------------
"$CURRAY" -s scene.yml -o new -x 320 -y 240 -f 2 -t ic --threads 1 -a </dev/null >new.out 2>&1 &
pid=$!
for _ in $(seq 1 6000); do [ -e new/.curray.lock ] && break; sleep 0.01; done
run -s scene.yml -o new -x 16 -y 12 -t ic -a
wait $pid
rc_n=$?
if [ $RC = 1 ] && has "output folder new is in use" && [ $rc_n = 0 ] && grep -q "^Finished 2 of 2 frames$" new/info.txt; then
    ok "a folder the first run created is locked from the start"
else
    bad "new folder" "rc $RC, first $rc_n"
fi
finish
