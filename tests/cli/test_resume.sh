#!/usr/bin/env bash
# Output folders that already hold frames: stale frame files are
# reported and kept; --resume after kill -9 in the middle of frame 2 of 4
# gives the files of an uninterrupted run; a changed scene or size is refused.
#
#   bash tests/cli/test_resume.sh path/to/curray [repository root]
#
# "The same files" means: every c_<k>.png, r_<k>.png and d_<k>.csv byte for
# byte, and info.txt line for line after dropping the lines that hold times
# (Started, Resumed, and each frame's "wall time" and "rays per second").
# About 10 s (4 frames of 320x240 on one thread, twice).
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
[ -x "$CURRAY" ] || { echo "test_resume: no curray binary at $CURRAY" >&2; exit 2; }
. "$(dirname "$0")/lib.sh" test-resume
untimed() { grep -vE '^(Started|Resumed) |^  (wall time|rays per second) ' "$1"; }
# same_run A B: the frame files of 4 frames and the untimed info.txt agree
same_run() {
    local f
    for f in c_{0..3}.png r_{0..3}.png d_{0..3}.csv; do
        cmp -s "$1/$f" "$2/$f" || { echo "$f differs"; return 1; }
    done
    diff <(untimed "$1/info.txt") <(untimed "$2/info.txt") || return 1
}

cp "$ROOT/scenes/demo.yml" scene.yml
ARGS=(-s scene.yml -x 320 -y 240 -f 4 -t icrd --threads 1 -a)

# --- stale frames --------------------------------------------------------
run -s scene.yml -o stale -x 16 -y 12 -f 4 -t icrd -a
run -s scene.yml -o stale -x 16 -y 12 -f 2 -t icr -a
if [ $RC = 0 ] && has "stale holds 8 frame files that this run does not overwrite" &&
   has "c_<k>.png for k = 2-3; r_<k>.png for k = 2-3; d_<k>.csv for k = 0-3" &&
   grep -q "^  stale files  *c_<k>.png for k = 2-3; r_<k>.png for k = 2-3; d_<k>.csv for k = 0-3" stale/info.txt &&
   [ -f stale/c_3.png ] && [ -f stale/d_0.csv ]; then
    ok "stale frame files are reported (console, info.txt) and kept"
else
    bad "stale frame files" "rc $RC"
fi
run -s scene.yml -o stale -x 16 -y 12 -f 4 -t icrd -a
if [ $RC = 0 ] && ! has "does not overwrite" && ! grep -q "stale files" stale/info.txt; then
    ok "no warning when the run overwrites every frame file"
else
    bad "no stale warning" "rc $RC"
fi

# --- the uninterrupted reference -----------------------------------------
run "${ARGS[@]}" -o full
[ $RC = 0 ] || bad "uninterrupted run" "rc $RC"

# --- kill -9 in the middle of frame 2, then --resume ----------------------
"$CURRAY" "${ARGS[@]}" -o part </dev/null >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 6000); do
    grep -qx "Frame 1" part/info.txt 2>/dev/null && break
    sleep 0.01
done
kill -9 $pid 2>/dev/null
wait $pid 2>/dev/null
if grep -qx "Frame 1" part/info.txt && ! grep -qx "Frame 2" part/info.txt && [ ! -e part/c_2.png ]; then
    ok "killed with SIGKILL in the middle of frame 2 (frames 0 and 1 finished)"
else
    bad "kill in frame 2" "$(ls part; tail -3 part/info.txt)"
fi
# a temporary file of a killed curray goes; a user's file that looks alike stays
dead=$(sh -c 'echo $$')
: >"part/.c_2.png.tmp.$dead.1a.0"
: >"part/.notes.txt.tmp.$dead.1a.0"
run "${ARGS[@]}" -o part --resume
if [ $RC = 0 ] && has "resuming: 2 of 4 frames finished by the earlier run, 2 to render" &&
   same_run full part >"$WORK/diff.txt" 2>&1; then
    ok "--resume renders frames 2 and 3; the files equal the uninterrupted run's"
else
    bad "--resume after kill -9" "rc $RC; $(cat "$WORK/diff.txt")"
fi
if [ ! -e "part/.c_2.png.tmp.$dead.1a.0" ] && [ -e "part/.notes.txt.tmp.$dead.1a.0" ] &&
   has "removed 1 temporary file left by a curray that was killed"; then
    ok "temporary files of a killed curray are removed, other files kept"
else
    bad "dead temporaries" "$(ls -a part)"
fi
if grep -q "^Resumed " part/info.txt &&
   [ "$(grep '^Started ' part/info.txt)" != "" ]; then
    ok "info.txt keeps the first start and adds Resumed"
else
    bad "Started/Resumed lines" "$(head -3 part/info.txt)"
fi
rm -f "part/.notes.txt.tmp.$dead.1a.0"

# a resumed run that finds everything done renders nothing and changes nothing
cp part/c_3.png c3.before
run "${ARGS[@]}" -o part --resume
if [ $RC = 0 ] && has "resuming: 4 of 4 frames finished by the earlier run, 0 to render" &&
   ! has "frame 3 of 4 done" && cmp -s c3.before part/c_3.png && same_run full part >/dev/null; then
    ok "--resume of a finished run renders nothing"
else
    bad "--resume of a finished run" "rc $RC"
fi

# a frame whose file went missing is rendered again; its record moves to the
# end of info.txt (records are in the order the frames finished)
rm part/r_1.png
run "${ARGS[@]}" -o part --resume
if [ $RC = 0 ] && has "resuming: 3 of 4 frames" && cmp -s full/r_1.png part/r_1.png &&
   [ "$(grep -E '^Frame [0-9]+$' part/info.txt | tr '\n' ' ')" = "Frame 0 Frame 2 Frame 3 Frame 1 " ] &&
   [ "$(tail -2 part/info.txt | head -1)" = "Finished 4 of 4 frames" ]; then
    ok "--resume renders again a frame with a missing file"
else
    bad "--resume with a missing file" "rc $RC"
fi

# --- files that do not match their records ---------------------------------
# info.txt records each file's size and CRC-32; a kept frame's files must
# match them, or the frame is rendered again (a truncated or empty file, a
# symbolic link, a changed byte); a folder in a frame file's place is refused
SMALL=(-s scene.yml -x 16 -y 12 -f 4 -t icrd -a)
run "${SMALL[@]}" -o ref
run "${SMALL[@]}" -o bad
if [ $RC = 0 ] && grep -qE '^  frame file  +c_1\.png [0-9]+ bytes, crc32 [0-9a-f]{8}$' bad/info.txt &&
   [ "$(grep -c '^  frame file ' bad/info.txt)" = 12 ]; then
    ok "info.txt records every frame file's size and CRC-32"
else
    bad "file lines in info.txt" "rc $RC; $(grep '^  frame file ' bad/info.txt | head -3)"
fi
truncate -s 50 bad/c_1.png
: >bad/d_2.csv
cp bad/r_3.png r3.copy
rm bad/r_3.png
ln -s ../r3.copy bad/r_3.png
run "${SMALL[@]}" -o bad --resume
same=1
for f in c_{0..3}.png r_{0..3}.png d_{0..3}.csv; do
    { cmp -s "ref/$f" "bad/$f" && [ ! -L "bad/$f" ]; } || same=0
done
if [ $RC = 0 ] && has "warning: --resume: 3 finished frames are rendered again" &&
   has "frame 1: c_1.png has 50 bytes, info.txt recorded" &&
   has "resuming: 1 of 4 frames finished by the earlier run, 3 to render" && [ $same = 1 ]; then
    ok "--resume renders again a truncated PNG, an empty CSV and a symbolic link"
else
    bad "--resume with damaged files" "rc $RC, same $same"
fi
# one byte changed, the size the same
printf 'X' | dd of=bad/d_0.csv bs=1 seek=100 conv=notrunc 2>/dev/null
run "${SMALL[@]}" -o bad --resume
if [ $RC = 0 ] && has "1 finished frame is rendered again: its files no longer matches info.txt" &&
   has "frame 0: d_0.csv has CRC-32" && cmp -s ref/d_0.csv bad/d_0.csv; then
    ok "--resume renders again a file with a changed byte (same size)"
else
    bad "--resume with a changed byte" "rc $RC"
fi
rm bad/c_2.png
mkdir bad/c_2.png
cp bad/info.txt info.before
run "${SMALL[@]}" -o bad --resume
if [ $RC = 1 ] && has "--resume: bad/c_2.png is a folder, where frame 2's file belongs; move it away, then run again" &&
   cmp -s info.before bad/info.txt && [ -d bad/c_2.png ]; then
    ok "--resume refuses a folder in a frame file's place, and changes nothing"
else
    bad "--resume with a folder" "rc $RC"
fi
rmdir bad/c_2.png
# records without sizes and checksums (an older curray) are not trusted
run "${SMALL[@]}" -o old
grep -v '^  frame file ' old/info.txt >old.txt && mv old.txt old/info.txt
run "${SMALL[@]}" -o old --resume
if [ $RC = 0 ] && has "4 finished frames are rendered again" && has "has no size and checksum in info.txt" &&
   has "resuming: 0 of 4 frames" && [ "$(grep -c '^  frame file ' old/info.txt)" = 12 ]; then
    ok "--resume renders again frames whose records have no checksum"
else
    bad "--resume of records without checksums" "rc $RC"
fi

# --- a resume of 100,000 frames takes seconds --------------------------------
# (a scan of info.txt that is quadratic in its size took over 9 minutes). The
# run hash is taken from the refusal of an info.txt with another hash; the
# records are made with awk; -t i has no frame files to check. The limit,
# 30 s, is far above a linear scan (well under a second) and far below a
# quadratic one.
N=100000
BIG=(-s scene.yml -o big -x 2 -y 2 -f $N -t i -a)
mkdir big
printf 'curray\nRun\n  run hash               0000000000000000\n\n' >big/info.txt
run "${BIG[@]}" --resume
hash=$(printf '%s\n' "$OUT" | sed -n "s/.*this run's is \([0-9a-f]\{16\}\).*/\1/p")
awk -v n=$N -v h="$hash" 'BEGIN {
    printf "curray - relativistic raytracer, run summary\nStarted                  2026-01-01 00:00:00 +0000\n\nRun\n  run hash               %s\n\n", h
    for (k = 0; k < n; k++)
        printf "Frame %d\n  wall time              0.001 s\n  rays                   4\n  pixels                 horizon 0, disc 0, sphere 0, sky 4, error 0, limit 0\nFinished %d of %d frames%s\n\n", k, k + 1, n, k + 1 < n ? " (run incomplete)" : ""
}' >big/info.txt
t0=$(date +%s)
OUT=$(timeout 30 "$CURRAY" "${BIG[@]}" --resume </dev/null 2>&1)
RC=$?
t1=$(date +%s)
if [ $RC = 0 ] && has "resuming: $N of $N frames finished by the earlier run, 0 to render" &&
   [ "$(grep -c '^Frame ' big/info.txt)" = $N ] &&
   [ "$(tail -2 big/info.txt | head -1)" = "Finished $N of $N frames" ]; then
    ok "--resume of $N frames in $((t1 - t0)) s (limit 30 s)"
else
    OUT=$(printf '%s\n' "$OUT" | tail -3)
    bad "--resume of $N frames" "rc $RC (124: over 30 s) after $((t1 - t0)) s"
fi
rm -rf big

# --- refusals ---------------------------------------------------------------
sed 's/theta: 85 deg/theta: 80 deg/' scene.yml >changed.yml
cp changed.yml scene2.yml
refused "--resume with a changed scene is refused" "--resume: part/info.txt is from another run" \
    -s scene2.yml -o part -x 320 -y 240 -f 4 -t icrd --threads 1 -a --resume
cmp -s c3.before part/c_3.png && ok "the refused run changed nothing" || bad "refused run" "c_3.png changed"
refused "--resume with another size is refused" "is from another run" \
    -s scene.yml -o part -x 320 -y 200 -f 4 -t icrd --threads 1 -a --resume
# the raytracer settings are in the hash by value: samples 1 written out is
# the default run (resumed), samples 2 is another run (refused)
printf 'raytracer:\n  samples: 1\n' >s1.yml
printf 'raytracer:\n  samples: 2\n' >s2.yml
run "${ARGS[@]}" -o part -c s1.yml --resume
if [ $RC = 0 ] && has "resuming: 4 of 4 frames finished by the earlier run, 0 to render"; then
    ok "--resume with the default samples written in a config file resumes"
else
    bad "--resume with samples: 1" "rc $RC"
fi
refused "--resume with other samples is refused" "is from another run" \
    "${ARGS[@]}" -o part -c s2.yml --resume
# the sky image's bytes are in the hash: the same scene file naming a changed
# sky.png is another run
cp "$ROOT/scenes/listing-7.1.2-starry-sky.yml" sky.yml
cp "$ROOT/scenes/sky.png" sky.png
SKY=(-s sky.yml -o skyrun -x 16 -y 12 -t i -a)
run "${SKY[@]}"
run "${SKY[@]}" --resume
if [ $RC = 0 ] && has "resuming: 1 of 1 frame finished by the earlier run, 0 to render"; then
    ok "--resume with the same sky image resumes"
else
    bad "--resume with the same sky image" "rc $RC"
fi
cp "$ROOT/scenes/sky_grid.png" sky.png
refused "--resume with a changed sky image is refused" "is from another run" "${SKY[@]}" --resume
refused "--resume with no earlier run is refused" \
    "--resume: no earlier run to resume in empty (no info.txt)" "${ARGS[@]}" -o empty --resume
refused "--resume without output type i is refused" "--resume needs info.txt" \
    -s scene.yml -o part -x 320 -y 240 -f 4 -t crd --threads 1 -a --resume
finish
