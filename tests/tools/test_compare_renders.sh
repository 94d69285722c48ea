#!/usr/bin/env bash
# tools/compare-renders.sh --dirs, without building anything: two small
# render folders, equal, equal but for info.txt's time lines, and with a
# planted difference in each kind of file; the script must tell them apart.
#
#   bash tests/tools/test_compare_renders.sh [repository root]
set -u
ROOT=$(cd "${1:-$(dirname "$0")/../..}" && pwd)
CMP=$ROOT/tools/compare-renders.sh
WORK=$(mktemp -d "${TMPDIR:-/tmp}/curray-test-compare.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 2
failed=0

# make DIR: a render folder as compare-renders.sh writes them
make() {
    mkdir -p "$1/scene/rk4/render" "$1/scene/rk4/trace-1-2"
    printf 'curray 1.0 - relativistic raytracer, run summary\nStarted                  %s\n\nFrame 0\n  wall time              %s s\n  rays                   12\n  rays per second        %s\n' \
        "$2" "$3" "$4" >"$1/scene/rk4/render/info.txt"
    printf '\x89PNG\r\n\x1a\n\0\0\0\rIHDR' >"$1/scene/rk4/render/c_0.png"
    printf 'x,y,r\n0,0,1\n1,0,2\n' >"$1/scene/rk4/render/d_0.csv"
    printf 'SIMPLE  =                    T' >"$1/scene/rk4/render/f_0.fits"
    printf '0\n' >"$1/scene/rk4/render.status"
    : >"$1/scene/rk4/render.log"
    printf 's,t,r\n0,0,30\n' >"$1/scene/rk4/trace-1-2/trace_1_2_0.csv"
    mkdir -p "$1/scene/rk4/render/log"
    printf '%s [info] frame 0 of 2 done in %s s: %s rays/s, 12.6 steps/ray, horizon 136\n%s [info] done: 2 frames in %s s, outputs in o\n' \
        "$2" "$3" "$4" "$2" "$3" >"$1/scene/rk4/render/log/curray.log"
}

# check NAME WANT_RC WANT_TEXT: run --dirs a b
check() {
    local out rc
    out=$(bash "$CMP" --dirs a b 2>&1)
    rc=$?
    if [ "$rc" != "$2" ]; then
        echo "FAIL $1: exit status $rc, expected $2"; echo "$out" | sed 's/^/     | /'; failed=1
    elif [[ "$out" != *"$3"* ]]; then
        echo "FAIL $1: output lacks '$3'"; echo "$out" | sed 's/^/     | /'; failed=1
    else
        echo "ok   $1"
    fi
}

make a "2026-01-01 10:00:00.123" 0.100 120
make b "2026-01-01 10:00:00.123" 0.100 120
check "equal folders" 0 "identical: 8 files"
make b "2027-12-31 23:59:59.999" 9.999 1.04e+05
check "info.txt and the log differ in their times only" 0 "identical: 8 files"
make b "2026-01-02 11:00:00.5" 2 3
printf 'Resumed                  now\n' >>b/scene/rk4/render/info.txt
check "a Resumed line only" 0 "identical"
make b "2026-01-02 11:00:00.5" 2 3
sed -i 's/rays                   12/rays                   13/' b/scene/rk4/render/info.txt
check "info.txt differs in a counted line" 1 "differs: scene/rk4/render/info.txt (times ignored)"
make b "2026-01-02 11:00:00.5" 2 3
printf '\x89PNG\r\n\x1a\n\0\0\0\rIHDX' >b/scene/rk4/render/c_0.png
check "one byte of a PNG" 1 "differs: scene/rk4/render/c_0.png"
make b "2026-01-02 11:00:00.5" 2 3
printf 'x,y,r\n0,0,1\n1,0,2.0000000000000004\n' >b/scene/rk4/render/d_0.csv
check "one number of a CSV" 1 "> 1,0,2.0000000000000004"
make b "2026-01-02 11:00:00.5" 2 3
printf 'SIMPLE  =                    F' >b/scene/rk4/render/f_0.fits
check "one byte of a FITS file" 1 "differs: scene/rk4/render/f_0.fits"
make b "2026-01-02 11:00:00.5" 2 3
printf '1\n' >b/scene/rk4/render.status
check "the exit status" 1 "differs: scene/rk4/render.status"
make b "2026-01-02 11:00:00.5" 2 3
printf 'curray: a warning\n' >b/scene/rk4/render.log
check "the console output" 1 "differs: scene/rk4/render.log"
make b "2026-01-01 10:00:00.123" 1 1
sed -i 's/horizon 136/horizon 137/' b/scene/rk4/render/log/curray.log
check "a count in the log" 1 "differs: scene/rk4/render/log/curray.log (times ignored)"
make b "2026-01-02 11:00:00.5" 2 3
rm b/scene/rk4/trace-1-2/trace_1_2_0.csv
check "a file missing on one side" 1 "only in a: scene/rk4/trace-1-2/trace_1_2_0.csv"
make b "2026-01-02 11:00:00.5" 2 3
touch b/scene/rk4/render/c_1.png
check "a file only on the other side" 1 "only in b: scene/rk4/render/c_1.png"
rm -rf b
out=$(bash "$CMP" --dirs a b 2>&1); rc=$?
if [ "$rc" = 2 ] && [[ "$out" == *"no folder 'b'"* ]]; then echo "ok   a missing folder"; else
    echo "FAIL a missing folder: exit status $rc: $out"; failed=1; fi

# the cache keeps the entries used last: CURRAY_COMPARE_KEEP=2 of 4 (the
# unknown commits are refused after the pruning, before anything is built)
for i in 1 2 3 4; do mkdir -p "cache/k$i"; touch -d "2026-01-01 10:0$i:00" "cache/k$i"; done
CURRAY_COMPARE_CACHE=$WORK/cache CURRAY_COMPARE_KEEP=2 bash "$CMP" no-such-commit-a no-such-commit-b >prune.out 2>&1
rc=$?
left=$(cd cache && ls -d k*/ | tr -d / | tr '\n' ' ')
if [ "$rc" = 2 ] && [ "$left" = "k3 k4 " ] && grep -q "'no-such-commit-a' is neither a commit" prune.out; then
    echo "ok   the cache keeps the entries used last"
else
    echo "FAIL the cache keeps the entries used last: exit status $rc, left: $left"; cat prune.out; failed=1
fi
# an entry another run is using (its shared lock on <entry>.use held) stays
rm -rf cache
for i in 1 2 3 4; do mkdir -p "cache/k$i"; touch -d "2026-01-01 10:0$i:00" "cache/k$i"; done
(exec 7>cache/k1.use; flock -s 7; exec sleep 30) &
holder=$!
sleep 0.5
CURRAY_COMPARE_CACHE=$WORK/cache CURRAY_COMPARE_KEEP=2 bash "$CMP" no-such-commit-a no-such-commit-b >prune.out 2>&1
kill "$holder" 2>/dev/null
wait "$holder" 2>/dev/null
left=$(cd cache && ls -d k*/ | tr -d / | tr '\n' ' ')
if [ "$left" = "k1 k3 k4 " ]; then
    echo "ok   an entry in use is not pruned"
else
    echo "FAIL an entry in use is not pruned: left: $left"; failed=1
fi
exit $failed
