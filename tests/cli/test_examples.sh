#!/usr/bin/env bash
# The commands in the headers of the shipped scenes run as copied.
#
#   bash tests/cli/test_examples.sh path/to/curray [repository root]
#
# Every scenes/*.yml has at least one header line "#   curray -s scenes/... "
# naming that scene; no two scenes' commands share an output folder (-o),
# and none writes into a bare "out" that the others would overwrite; every
# command's outputs include info.txt (i, the default icr has it), so a
# stopped run can be continued with --resume. Each command is then run from a
# folder that holds the repository's scenes/, with curray for "curray", at
# 24x16 pixels (-x/-y appended: the last one counts) and -a -q added: it must
# exit 0 and leave c_<f-1>.png and info.txt recording every frame in its
# folder; the same command with --resume added must exit 0 and render no
# frame again. Then Ctrl-C of the flyby's command says how to continue
# (--resume, or adding i to -t without info.txt). About 15 s.
set -u

CURRAY=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
ROOT=$(cd "${2:-$(dirname "$0")/../..}" && pwd)
. "$(dirname "$0")/lib.sh" test-examples
ln -s "$ROOT/scenes" scenes

declare -A owner
n=0
for scene in "$ROOT"/scenes/*.yml; do
    name=scenes/$(basename "$scene")
    cmds=$(sed -n '/^---/q; s/^#[[:space:]]\{1,\}\(curray -s .*\)$/\1/p' "$scene")
    if [ -z "$cmds" ]; then
        bad "$name has a command in its header" "no '#   curray -s ...' line before ---"
        continue
    fi
    while IFS= read -r cmd; do
        n=$((n + 1))
        read -r -a argv <<<"$cmd"
        s="" o="" t=icr f=1
        for ((k = 1; k < ${#argv[@]}; k++)); do
            case ${argv[k]} in
            -s) s=${argv[k + 1]} ;;
            -o) o=${argv[k + 1]} ;;
            -t) t=${argv[k + 1]} ;;
            -f) f=${argv[k + 1]} ;;
            esac
        done
        if [ "$s" != "$name" ]; then
            bad "$name: its command renders it" "-s $s"
            continue
        fi
        case $o in
        "" | out | out/) bad "$name: its own output folder" "-o '$o'"; continue ;;
        esac
        if [ -n "${owner[$o]:-}" ]; then
            bad "$name: its own output folder" "-o $o is also ${owner[$o]}'s"
            continue
        fi
        owner[$o]=$name
        case $t in
        *i*) ;;
        *) bad "$name: resumable outputs" "-t $t has no i (info.txt), so --resume cannot continue it"; continue ;;
        esac
        run "${argv[@]:1}" -x 24 -y 16 -a -q
        last=$((f - 1))
        if [ $RC = 0 ] && [ -s "$o/c_$last.png" ] && grep -q "^Finished $f of $f frames" "$o/info.txt"; then
            ok "$name: '$cmd' runs as copied"
        else
            bad "$name: '$cmd' runs as copied" "rc $RC; $(ls "$o" 2>&1 | tr '\n' ' ')"
            continue
        fi
        before=$(stat -c %Y.%i "$o/c_$last.png")
        run "${argv[@]:1}" -x 24 -y 16 -a -q --resume
        if [ $RC = 0 ] && [ "$(stat -c %Y.%i "$o/c_$last.png")" = "$before" ]; then
            ok "$name: the same command with --resume keeps the finished frames"
        else
            bad "$name: --resume" "rc $RC"
        fi
    done <<<"$cmds"
done
[ $n -ge 19 ] && ok "$n header commands found" || bad "header commands" "only $n found"

# Ctrl-C during a copied example says how to go on: with info.txt among the
# outputs the same command with --resume, which then finishes the run;
# without it, to add i to -t.
interrupt() { # folder, then curray's arguments: OUT (its output), RC
    local dir=$1
    shift
    "$CURRAY" "$@" -o "$dir" -a -q </dev/null >"$dir.log" 2>&1 &
    local pid=$!
    for _ in $(seq 600); do [ -e "$dir/c_0.png" ] && break; sleep 0.1; done
    kill -INT "$pid" 2>/dev/null
    wait "$pid"
    RC=$?
    OUT=$(cat "$dir.log")
}
flyby=(-s scenes/observer-orbit.yml -x 64 -y 48 -f 60 --threads 1)
interrupt out/int "${flyby[@]}" -t ic
if [ $RC = 130 ] && has "frames finished and kept in out/int; the same command with --resume renders the rest"; then
    ok "Ctrl-C of the flyby points to --resume"
else
    bad "Ctrl-C of the flyby points to --resume" "rc $RC"
fi
run "${flyby[@]}" -t ic -o out/int -a -q --resume
[ $RC = 0 ] && grep -q "^Finished 60 of 60 frames" out/int/info.txt && [ -s out/int/c_59.png ] &&
    ok "... and --resume finishes it" || bad "--resume after Ctrl-C" "rc $RC"
interrupt out/int-c "${flyby[@]}" -t c
if [ $RC = 130 ] && has "frames finished and kept in out/int-c; add i to -t (info.txt) to make a run resumable"; then
    ok "Ctrl-C of a run without info.txt says to add i to -t"
else
    bad "Ctrl-C of a run without info.txt says to add i to -t" "rc $RC"
fi
finish
