#!/usr/bin/env bash
# Do two versions of curray render the same bytes?
#
#   tools/compare-renders.sh [-k] A B     build A and B, render, compare
#   tools/compare-renders.sh --dirs X Y   compare two render folders only
#
# A and B are each a commit (anything `git rev-parse` takes: main, HEAD~1, a
# hash), WORKTREE (this checkout's files as they are, uncommitted changes
# included) or the path of a source folder.
#
# Each side is built once, CPU only (Release, -DCURRAY_CUDA=OFF
# -DCURRAY_TESTS=OFF, nice -n 10, -j 2), in a cache folder keyed by the
# commit hash, ${XDG_CACHE_HOME:-~/.cache}/curray-compare/<hash>; a commit's
# renders are kept there too, so comparing against a commit already rendered
# costs nothing but the other side (when both sides are the same commit, B is
# rendered afresh: a check of determinism). A WORKTREE or folder side keeps an
# incremental build in tree-<hash of its path> and is rendered afresh.
#
# Every scene of the side's scenes/ and bench/scenes/ (the files with a
# top-level metric: key; the others there are system configurations) is
# rendered at 64x48 in 2 frames (frame 1 of 2 is an animation's end) with
# -t icrdbf (info.txt, colour, redshift and bolometric PNG, CSV, FITS),
# under the default integrator and under raytracer.integrator: rk4 (with
# max_steps: 20000, which only far observers reach), and the
# ray paths of pixels (32,24) and (5,40) are traced (--trace) the same way.
# A run's console output and exit status are kept beside its files, so a
# scene that one side refuses (rk4 with the observer at infinity) is compared
# by its message.
#
# Every file is compared byte for byte; info.txt without its time lines
# (Started, Resumed, wall time, rays per second), the logs (log/curray.log,
# the console output) without time stamps, durations and speeds.
# Prints the first differences and exits 1 on any, 0 when all are equal,
# 2 on a usage or build error. The renders of a side that is not a cached
# commit are removed when all is equal, kept (and named above) otherwise, or
# always with -k. CURRAY_COMPARE_CACHE overrides the cache folder; it keeps
# the CURRAY_COMPARE_KEEP (default 12) entries used last, about 150 MB each.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
CACHE=${CURRAY_COMPARE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/curray-compare}
WIDTH=64
HEIGHT=48
FRAMES=2
TYPES=icrdbf
TRACES=("32,24" "5,40")
INTEGRATORS=(default rk4)
# The render plan (bump its first word when what is rendered changes):
# renders cached under another plan are not reused.
PLAN="v2 ${WIDTH}x${HEIGHT} f$FRAMES t$TYPES trace ${TRACES[*]} ${INTEGRATORS[*]}"
MAX_SHOWN=20
CACHE_KEEP=${CURRAY_COMPARE_KEEP:-12}

die() {
    echo "compare-renders: $*" >&2
    exit 2
}

usage() {
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
}

# A text output without its times: info.txt without its time lines; a log
# (the output folder's log/curray.log, a run's console output) without the
# time stamp that starts each line and with every duration ("0.03 s") and
# speed ("1.04e+05 rays/s") written as T.
strip_times() {
    case $1 in
    *.log)
        sed -E -e 's/^[0-9]{4}-[0-9]{2}-[0-9]{2} [0-9:.]+ //' \
            -e 's/[0-9][0-9.e+-]* rays\/s/T rays\/s/g' -e 's/[0-9][0-9.]* s([:,;)]|$)/T s\1/g' "$1"
        ;;
    *) grep -Ev '^(Started|Resumed) |^  (wall time|rays per second) ' "$1" || true ;;
    esac
}

# compare_dirs X Y: every file of X and Y byte for byte (text outputs
# without their time lines); prints the first differences; returns 1 on any.
compare_dirs() {
    local x=$1 y=$2 f n=0 nfiles=0 lx ly
    [ -d "$x" ] || die "no folder '$x'"
    [ -d "$y" ] || die "no folder '$y'"
    lx=$(cd "$x" && find . -type f | LC_ALL=C sort)
    ly=$(cd "$y" && find . -type f | LC_ALL=C sort)
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        n=$((n + 1))
        [ "$n" -le "$MAX_SHOWN" ] && echo "only in $x: ${f#./}"
    done < <(LC_ALL=C comm -23 <(echo "$lx") <(echo "$ly"))
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        n=$((n + 1))
        [ "$n" -le "$MAX_SHOWN" ] && echo "only in $y: ${f#./}"
    done < <(LC_ALL=C comm -13 <(echo "$lx") <(echo "$ly"))
    while IFS= read -r f; do
        [ -n "$f" ] || continue
        nfiles=$((nfiles + 1))
        case $f in
        */info.txt | info.txt | *.log)
            if ! cmp -s <(strip_times "$x/$f") <(strip_times "$y/$f"); then
                n=$((n + 1))
                if [ "$n" -le "$MAX_SHOWN" ]; then
                    echo "differs: ${f#./} (times ignored)"
                    diff <(strip_times "$x/$f") <(strip_times "$y/$f") | head -6 | sed 's/^/    /'
                fi
            fi
            ;;
        *)
            if ! cmp -s "$x/$f" "$y/$f"; then
                n=$((n + 1))
                if [ "$n" -le "$MAX_SHOWN" ]; then
                    echo "differs: ${f#./}"
                    case $f in
                    *.csv) diff "$x/$f" "$y/$f" | head -6 | sed 's/^/    /' ;;
                    *) cmp "$x/$f" "$y/$f" 2>&1 | head -1 | sed 's/^/    /' || true ;;
                    esac
                fi
            fi
            ;;
        esac
    done < <(LC_ALL=C comm -12 <(echo "$lx") <(echo "$ly"))
    if [ "$n" -gt 0 ]; then
        [ "$n" -gt "$MAX_SHOWN" ] && echo "... $((n - MAX_SHOWN)) more differences"
        echo "DIFFERENT: $n difference(s) between $x and $y"
        return 1
    fi
    echo "identical: $nfiles files in $x and $y"
    return 0
}

# resolve SIDE: sets side_src (source folder), side_key (cache key) and
# side_commit (the hash, or empty for a folder).
resolve() {
    local s=$1 h
    side_commit=
    if [ "$s" = WORKTREE ]; then
        side_src=$ROOT
    elif [ -d "$s" ] && [ -f "$s/CMakeLists.txt" ]; then
        side_src=$(cd "$s" && pwd)
    elif h=$(git -C "$ROOT" rev-parse --verify --quiet "$s^{commit}"); then
        side_commit=$h
        side_key=$h
        side_src=$CACHE/$h/src
        return 0
    else
        die "'$s' is neither a commit, WORKTREE nor a source folder"
    fi
    side_key=tree-$(printf '%s' "$side_src" | sha1sum | cut -c1-16)
}

# build: makes $CACHE/$side_key/build/curray from $side_src.
build() {
    local dir=$CACHE/$side_key log
    mkdir -p "$dir"
    log=$dir/build.log
    if [ -n "$side_commit" ] && [ ! -f "$dir/src.ok" ]; then
        rm -rf "$dir/src"
        mkdir -p "$dir/src"
        git -C "$ROOT" archive "$side_commit" | tar -x -C "$dir/src"
        touch "$dir/src.ok"
    fi
    if [ -n "$side_commit" ] && [ -f "$dir/build.ok" ] && [ -x "$dir/build/curray" ]; then
        echo "== $side_label: cached build $dir/build"
        return 0
    fi
    echo "== $side_label: building in $dir/build (log: $log)"
    if ! { nice -n 10 cmake -S "$side_src" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release \
        -DCURRAY_CUDA=OFF -DCURRAY_TESTS=OFF &&
        nice -n 10 cmake --build "$dir/build" -j 2 --target curray; } >"$log" 2>&1; then
        tail -20 "$log" >&2
        die "$side_label: the build failed (log: $log)"
    fi
    [ -n "$side_commit" ] && touch "$dir/build.ok"
    return 0
}

# run_one OUT NAME ARGS...: one curray run from the work folder, its console
# output in OUT/NAME.log and its exit status in OUT/NAME.status.
run_one() {
    local out=$1 name=$2 rc=0
    shift 2
    nice -n 10 ./curray "$@" >"$out/$name.log" 2>&1 </dev/null || rc=$?
    echo "$rc" >"$out/$name.status"
}

# render_all BIN SRC DEST: every scene under every integrator into DEST.
# Runs in a work folder holding links src -> SRC and curray -> BIN, so that
# the paths curray records (scene file, sky image) are the same for every side.
render_all() {
    local bin=$1 src=$2 dest=$3 work scene name integ t out
    work=$(mktemp -d "${TMPDIR:-/tmp}/curray-compare.XXXXXX")
    ln -s "$src" "$work/src"
    ln -s "$bin" "$work/curray"
    mkdir -p "$work/cfg" "$work/out"
    printf 'auto_accept: true\n' >"$work/cfg/default.yml"
    # rk4 with max_steps 20000: above every shipped scene's longest ray
    # (15215 steps, listing 7.2.1) but a tenth of the default 200000 that
    # every ray of a far observer (bench/scenes/distance-r1e6.yml) runs into
    printf 'auto_accept: true\nraytracer:\n  integrator: rk4\n  max_steps: 20000\n' >"$work/cfg/rk4.yml"
    (
        cd "$work"
        for scene in src/scenes/*.yml src/bench/scenes/*.yml; do
            grep -q '^metric:' "$scene" || continue
            name=${scene#src/}
            name=${name%.yml}
            name=${name//\//_}
            for integ in "${INTEGRATORS[@]}"; do
                out=out/$name/$integ
                mkdir -p "$out"
                run_one "$out" render -s "$scene" -o "$out/render" -x $WIDTH -y $HEIGHT \
                    -f $FRAMES -t $TYPES -c cfg/$integ.yml -q true -a true --threads 2
                for t in "${TRACES[@]}"; do
                    run_one "$out" "trace-${t/,/-}" -s "$scene" -o "$out/trace-${t/,/-}" \
                        -x $WIDTH -y $HEIGHT -f $FRAMES --trace "$t" -c cfg/$integ.yml \
                        -q true -a true --threads 2
                done
            done
        done
    )
    rm -rf "$dest"
    mv "$work/out" "$dest"
    rm -rf "$work"
}

# prune_cache: removes the cache entries but the CACHE_KEEP used last. An
# entry that a run is using stays: every run holds a shared lock on its
# sides' <entry>.use until it exits.
prune_cache() {
    local d
    { ls -1dt "$CACHE"/*/ 2>/dev/null || true; } | tail -n +$((CACHE_KEEP + 1)) | while IFS= read -r d; do
        d=${d%/}
        (flock -n 8 || exit 0; rm -rf "$d" "$d.lock" "$d.use") 8>"$d.use"
    done
}

# side SPEC LABEL: builds and renders one side; sets side_out.
side() {
    side_label=$2
    resolve "$1"
    mkdir -p "$CACHE"
    # in use until this run exits (prune_cache leaves it alone)
    local use_fd
    exec {use_fd}>"$CACHE/$side_key.use"
    flock -s "$use_fd"
    # one build and one render at a time per cache entry, across processes
    exec 9>"$CACHE/$side_key.lock"
    flock 9
    mkdir -p "$CACHE/$side_key"
    touch "$CACHE/$side_key"
    build
    local dir=$CACHE/$side_key plan_key
    plan_key=$(printf '%s' "$PLAN" | sha1sum | cut -c1-12)
    if [ -n "$side_commit" ] && [ "$side_key" != "${first_key:-}" ]; then
        side_out=$dir/renders-$plan_key
        if [ -f "$side_out.ok" ]; then
            echo "== $side_label: cached renders $side_out"
            flock -u 9
            return 0
        fi
    else
        side_out=$(mktemp -d "${TMPDIR:-/tmp}/curray-compare-$side_label.XXXXXX")
        tree_outs+=("$side_out")
    fi
    echo "== $side_label: rendering into $side_out"
    local t0=$SECONDS
    render_all "$dir/build/curray" "$side_src" "$side_out"
    case $side_out in "$dir"/renders-*) touch "$side_out.ok" ;; esac
    echo "== $side_label: rendered in $((SECONDS - t0)) s"
    flock -u 9
}

keep=0
if [ "${1:-}" = --dirs ]; then
    [ $# -eq 3 ] || usage
    compare_dirs "$2" "$3"
    exit $?
fi
if [ "${1:-}" = -k ]; then
    keep=1
    shift
fi
[ $# -eq 2 ] || usage
command -v cmake >/dev/null || die "cmake not found"
tree_outs=()
status=2
cleanup() {
    if [ "$keep" = 0 ] && [ "$status" = 0 ] && [ ${#tree_outs[@]} -gt 0 ]; then
        rm -rf "${tree_outs[@]}"
    fi
}
trap cleanup EXIT
mkdir -p "$CACHE"
prune_cache
side "$1" A
a_out=$side_out
first_key=$side_key
side "$2" B
b_out=$side_out
status=0
compare_dirs "$a_out" "$b_out" || status=1
exit $status
