#!/usr/bin/env bash
# tools/gpu-check.sh: the GPU checks of curray in one prepared script, for a
# session that is lent a GPU machine (the device tool: /work/.library/device/).
# That machine has no package registry and no libpng/libyaml/libcmocka, so
# everything is built HERE, statically for sm_90 (H100/H200), and carried.
#
#   1. Here (no GPU needed, about 80 s on 2 cores):
#        tools/gpu-check.sh build
#      builds, from a snapshot of HEAD (git archive, in build-gpu-check/src,
#      so others' uncommitted edits do not matter: commit yours first),
#      build-gpu-check/{default,r128,r64} (curray; default also test_backends,
#      with libcmocka copied into build-gpu-check/lib) with CURRAY_STATIC=ON,
#      CURRAY_CUDA_ARCHS=90 and CURRAY_CUDA_MAXRREG "" / 128 / 64.
#      GPU_CHECK_BASE=REV adds build-gpu-check/base: REV's curray, for a
#      before/after table (bench-base against bench-default).
#   2. On the GPU machine, ONE device-tool call:
#        run(command="tools/gpu-check.sh run", carry=["build-gpu-check"],
#            timeout_s=300)
#      or, for the checks alone (a, b and c below: the kernel's registers,
#      ctest -L gpu and the CLI on CPU and GPU, about 15 s; no benchmarks):
#        run(command="tools/gpu-check.sh quick", carry=["build-gpu-check"],
#            timeout_s=120)
#      It writes under $OUT (at most 8 files come back): summary.txt (the
#      short table, also printed last), ctest.log, bench.md (every benchmark
#      table) and gpu-check.tar.gz (every log, CSV and info.txt). On an H200
#      (2026-11-30) the whole run took about 60-80 s. GPU_CHECK_BUDGET (s,
#      default 380) caps it: each stage gets at most what is left, and is
#      skipped when under 20 s are left. GPU_CHECK_SIZES picks the sizes of
#      the main table (default "1024 2048"). Then call give_back.
#
# What `run` does, in order (times measured on the H200):
#   a. curray -i for each variant (device, registers and local memory per
#      thread and occupancy as the CUDA runtime reports them)      ~2 s
#   b. ctest -L gpu --output-on-failure (test_backends: every case and scene,
#      CPU against GPU, under mino and rk4)                        ~5 s
#   c. the CLI through the per-run session: a 3-frame render of scenes/demo.yml
#      on the CPU and on the GPU, with mino and with rk4, compared pixel by
#      pixel (outcome and colour, d_<k>.csv)                       ~3 s
#      and the scenes of scene_compare_list, every frame at 64x36 compared the
#      same way: the plunges scenes/plunge-reissner-nordstrom.yml (through r+
#      and r-) and plunge-kerr.yml (through r+), 240 frames each (rays crossing
#      horizons, the ingoing chart, other side and singularity outcomes on the
#      GPU), and the moving sphere of scenes/hot-spot-isco.yml, 32 frames (the
#      light-travel time and the matter's Doppler shift)       not yet timed
#   d. the split of a frame's GPU time into tracing and pixel copy (-v) at
#      1024 and 4096                                               ~5 s
#   e. Mino vs rk4 on the GPU (kerr-disc, and kerrz-disc for mino), and a
#      tolerance sweep (1e-5, 1e-9)                                ~10 s
#   f. bench/run.sh --backend cuda on the 4 bench scenes, 3 runs     ~15 s
#   g. the variants (base, r128, r64): bench/run.sh at 1024, 3 runs  ~6 s each
#   h. 12 frames of kerr-disc at 1024x1024 written as PNG+CSV, to see tracing
#      overlap writing                                             ~18 s
set -uo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
bdir=$root/build-gpu-check

build_variant() { # NAME MAXRREG SOURCE TARGETS...
    local name=$1 rreg=$2 src=$3
    shift 3
    cmake -S "$src" -B "$bdir/$name" -DCMAKE_BUILD_TYPE=Release -DCURRAY_STATIC=ON -DCURRAY_CUDA=ON \
        -DCURRAY_CUDA_ARCHS=90 -DCURRAY_CUDA_MAXRREG="$rreg" -DCURRAY_CUDA_PTXAS_VERBOSE=ON \
        -DCURRAY_TESTS=ON >"$bdir/$name.cmake.log" 2>&1 || {
        cat "$bdir/$name.cmake.log"
        return 1
    }
    cmake --build "$bdir/$name" -j"$(nproc 2>/dev/null || echo 2)" --target "$@" \
        >"$bdir/$name.build.log" 2>&1 || {
        tail -40 "$bdir/$name.build.log"
        return 1
    }
    grep -A3 "entry function '_Z19cr_gpu_trace_kernel" "$bdir/$name.build.log" | head -4
    # only what the checks use travels: drop objects and other build output
    find "$bdir/$name" -name '*.o' -delete
}

cmd_build() {
    command -v nvcc >/dev/null || [ -x /usr/local/cuda/bin/nvcc ] || {
        echo "gpu-check: no nvcc here" >&2
        exit 1
    }
    mkdir -p "$bdir/lib"
    # Build from a snapshot of the last commit (git archive HEAD), not from the
    # working tree, which others may be editing; it travels in the build
    # folder, and `run` takes its scenes and scripts from there too.
    rm -rf "$bdir"
    mkdir -p "$bdir/lib" "$bdir/src"
    git -C "$root" archive HEAD | tar -x -C "$bdir/src" || exit 1
    echo "gpu-check: building commit $(git -C "$root" rev-parse --short HEAD)"
    git -C "$root" rev-parse --short HEAD >"$bdir/src/COMMIT"
    build_variant default "" "$bdir/src" curray test_backends || exit 1
    build_variant r128 128 "$bdir/src" curray || exit 1
    build_variant r64 64 "$bdir/src" curray || exit 1
    # GPU_CHECK_BASE=REV: also the curray of an earlier commit, benchmarked
    # side by side with this one (a before/after of a change)
    if [ -n "${GPU_CHECK_BASE:-}" ]; then
        mkdir -p "$bdir/src-base"
        git -C "$root" archive "$GPU_CHECK_BASE" | tar -x -C "$bdir/src-base" || exit 1
        git -C "$root" rev-parse --short "$GPU_CHECK_BASE" >"$bdir/src-base/COMMIT"
        build_variant base "" "$bdir/src-base" curray || exit 1
    fi
    # test_backends links libcmocka.so.0 dynamically (Debian ships no .a)
    cp -L "$(ldconfig -p | awk '/libcmocka\.so\.0 / {print $NF; exit}')" "$bdir/lib/" || exit 1
    du -sh "$bdir"
    echo "gpu-check: built; now, with a GPU lent:"
    echo '  run(command="tools/gpu-check.sh run", carry=["build-gpu-check"], timeout_s=560)'
}

# ---- on the GPU machine -------------------------------------------------------

# GPU_CHECK_BUDGET (seconds, default 380): the whole run's budget. A stage
# gets at most what is left of it (less 10 s for packing the results) and is
# skipped when under 20 s are left, so the run ends inside the device call.
stage() { # NAME SECONDS COMMAND...: run with a time limit, log to $work/NAME.log
    local name=$1 secs=$2 t0 rc left
    shift 2
    t0=$(date +%s)
    left=$((deadline - t0 - 10))
    if [ "$left" -lt 20 ]; then
        echo "== $name: skipped, ${left}s of the budget left" | tee -a "$work/stages.log"
        return 0
    fi
    [ "$secs" -gt "$left" ] && secs=$left
    echo "== $name ($(date +%T), limit ${secs}s): $*" | tee -a "$work/stages.log"
    # shell functions run in a child bash (exported below), so timeout can stop them
    timeout -k 5 "$secs" bash -c '"$@"' stage "$@" >"$work/$name.log" 2>&1
    rc=$?
    echo "   $name: exit $rc in $(($(date +%s) - t0)) s" | tee -a "$work/stages.log"
    return $rc
}

# d_<k>.csv of two renders: pixels whose outcome or colour differ
csv_diff() {
    awk -F, 'NR == FNR { if (FNR > 1) a[$1 "," $2] = $3 "," $4 "," $5 "," $10; next }
             FNR > 1 { n++; if (a[$1 "," $2] != $3 "," $4 "," $5 "," $10) d++ }
             END { printf "%d of %d pixels differ (%.4f %%)\n", d, n, n ? 100 * d / n : 0 }' "$1" "$2"
}

cli_compare() { # the CLI on CPU and GPU, 3 frames, each integrator
    local integ k
    for integ in mino rk4; do
        for be in cpu cuda; do
            "$bdir/default/curray" -s "$root/scenes/demo.yml" -c "$root/bench/scenes/$integ.yml" \
                -o "$work/cli-$integ-$be" -x 160 -y 120 -f 3 -t crdi -a true --backend "$be" ||
                return 1
        done
        for k in 0 1 2; do
            echo -n "$integ frame $k, CPU vs GPU: "
            csv_diff "$work/cli-$integ-cpu/d_$k.csv" "$work/cli-$integ-cuda/d_$k.csv"
        done
        grep -E "^  wall time" "$work/cli-$integ-cuda/info.txt" | head -3
    done
    scene_compare
}

# The scenes whose every frame is compared on CPU and GPU at 64x36: the plunges
# through r+ (Kerr) and r+ and r- (RN), and the moving spheres (light-travel
# time, Doppler from the matter's 4-velocity; hot-spot-eccentric on a tabulated
# particle worldline, core/track.h), as SCENE:FRAMES.
scene_compare_list="plunge-reissner-nordstrom:240 plunge-kerr:240 hot-spot-isco:32 hot-spot-eccentric:32"

scene_compare() { # each scene of scene_compare_list on CPU and GPU, every frame
    local item sc nf be k d tot worst wk
    for item in $scene_compare_list; do
        sc=${item%%:*} nf=${item##*:}
        for be in cpu cuda; do
            "$bdir/default/curray" -s "$root/scenes/$sc.yml" -o "$work/$sc-$be" -x 64 -y 36 \
                -f "$nf" -t di -a true -q true --backend "$be" || return 1
        done
        tot=0 worst=0 wk=0
        for k in $(seq 0 $((nf - 1))); do
            d=$(csv_diff "$work/$sc-cpu/d_$k.csv" "$work/$sc-cuda/d_$k.csv" | cut -d' ' -f1)
            case $d in '' | *[!0-9]*) echo "$sc frame $k: no d_$k.csv to compare"; return 1 ;; esac
            tot=$((tot + d))
            [ "$d" -gt "$worst" ] && worst=$d wk=$k
        done
        echo "$sc ($nf frames at 64x36, CPU vs GPU): $tot pixels differ in outcome or colour" \
            "in all, at most $worst in one frame (frame $wk)"
        rm -f "$work/$sc"-*/d_*.csv
    done
}

gpu_split() { # frame time split into tracing and the pixel copy to the host
    local n
    for n in 1024 4096; do
        "$bdir/default/curray" -s "$root/bench/scenes/kerr-disc.yml" \
            -c "$root/bench/scenes/defaults.yml" -o "$work/split$n" -x $n -y $n -f 3 -t i \
            -a true -v true --backend cuda 2>&1 | grep -E "s tracing" | sed "s/^/${n}x$n: /"
    done
}

cli_overlap() { # 12 frames written as PNG and CSV: is the GPU kept busy?
    "$bdir/default/curray" -s "$root/bench/scenes/kerr-disc.yml" \
        -c "$root/bench/scenes/defaults.yml" -o "$work/overlap" -x 1024 -y 1024 -f 12 \
        -t crdi -a true --backend cuda || return 1
    awk '/^  wall time/ {s += $3; n++} END {printf "sum of the %d frames'"'"' GPU times: %.2f s\n", n, s}' \
        "$work/overlap/info.txt"
    rm -f "$work"/overlap/*.csv "$work"/overlap/*.png
}

bench_run() { # VARIANT OUTNAME ARGS...
    local v=$1 name=$2
    shift 2
    CURRAY_BIN=$bdir/$v/curray CURRAY_BENCH_OFFLINE=1 "$root/bench/run.sh" --backend cuda \
        --out "$work/bench-$name" "$@"
}

cmd_run() {
    : "${OUT:?gpu-check run: OUT is not set (run it through the device tool)}"
    [ -x "$bdir/default/curray" ] || {
        echo "gpu-check: no $bdir/default/curray: run 'tools/gpu-check.sh build' here first" >&2
        exit 1
    }
    # scenes, scripts and sources of the commit that was built
    [ -d "$bdir/src" ] && root=$bdir/src
    work=$(mktemp -d /tmp/gpu-check.XXXXXX)
    deadline=$(($(date +%s) + ${GPU_CHECK_BUDGET:-380}))
    export root bdir work
    export scene_compare_list
    export -f csv_diff cli_compare scene_compare cli_overlap bench_run gpu_split
    shopt -s nullglob
    export LD_LIBRARY_PATH=$bdir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
    # the build's CTest files and test_backends (CR_SOURCE_DIR) name the folder
    # it was built in: make that path lead here when the checkout lies elsewhere
    local src
    src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$bdir/default/CMakeCache.txt")
    if [ -n "$src" ] && [ "$src" != "$root" ] && [ ! -e "$src" ]; then
        mkdir -p "$(dirname "$src")" && ln -s "$root" "$src"
    fi
    {
        echo "gpu-check on $(hostname) at $(date -u +%FT%TZ), commit $(cat "$root/COMMIT" 2>/dev/null)"
        nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.mem,temperature.gpu --format=csv 2>&1
    } >"$work/summary.txt"

    local v
    for v in default base r128 r64; do
        [ -x "$bdir/$v/curray" ] || continue
        echo "--- $v" >>"$work/info.log"
        timeout 60 "$bdir/$v/curray" -i >>"$work/info.log" 2>&1
    done
    stage ctest 150 ctest --test-dir "$bdir/default" -L gpu --output-on-failure -V
    cp "$work/ctest.log" "$OUT/ctest.log" 2>/dev/null
    stage cli-compare 120 cli_compare
    # quick: only the checks above (registers, test_backends, the CLI on CPU
    # and GPU), about 15 s; the benchmarks below are skipped
    [ -n "${quick:-}" ] || cmd_bench
    cmd_summary
}

cmd_bench() {
    stage split 60 gpu_split
    stage mino-rk4-mino 60 bench_run default mino --scenes "kerr-disc kerrz-disc" --sizes 1024 \
        --runs 3 --config "$root/bench/scenes/mino.yml"
    # rk4 cannot start at infinity (kerrz-disc's observer): kerr-disc only
    stage mino-rk4-rk4 90 bench_run default rk4 --scenes kerr-disc --sizes 1024 \
        --runs 3 --config "$root/bench/scenes/rk4.yml"
    # frame time against steps per ray: is the cost per step or per ray?
    for tol in 1e-5 1e-9; do
        printf 'raytracer:\n  integrator: mino\n  tolerance: %s\n' "$tol" >"$work/tol$tol.yml"
        stage "tol-$tol" 60 bench_run default "tol$tol" --scenes "kerr-disc starry-sky" \
            --sizes 1024 --runs 3 --config "$work/tol$tol.yml"
    done
    stage bench-default 120 bench_run default all --sizes "${GPU_CHECK_SIZES:-1024 2048}" --runs 3
    for v in base r128 r64; do
        [ -x "$bdir/$v/curray" ] && stage "bench-$v" 60 bench_run "$v" "$v" --sizes 1024 --runs 3
    done
    stage cli-overlap 60 cli_overlap
}

cmd_summary() {
    for f in "$work"/bench-*.log "$work"/mino-rk4-*.log "$work"/tol-*.log; do
        [ -f "$f" ] && { echo "### $(basename "$f" .log)"; sed -n '/^## curray benchmark/,$p' "$f"; echo; }
    done >"$OUT/bench.md"
    {
        echo
        echo "kernel resources (curray -i):"
        grep -E "^--- |^Name:|^Can be used|^Kernel|^No CUDA" "$work/info.log"
        echo
        echo "stages:"
        cat "$work/stages.log"
        echo
        echo "test_backends:"
        grep -E "PASSED|FAILED|SKIPPED|worst|mismatch" "$work/ctest.log" | head -30
        echo
        echo "CLI, CPU vs GPU and overlap:"
        echo "tracing and pixel copy (curray -v):"
        cat "$work/split.log" 2>/dev/null
        cat "$work/cli-compare.log" "$work/cli-overlap.log" 2>/dev/null | grep -vE "^\s*$" |
            grep -E "differ|wall time|sum of|done:" | head -20
        echo
        echo "benchmarks (frame time median, ns/step):"
        for f in "$work"/bench-*.csv; do
            case $f in *-runs.csv) continue ;; esac
            echo "# $(basename "$f" .csv)"
            cat "$f"
        done
    } >>"$work/summary.txt"
    cp "$work/summary.txt" "$OUT/summary.txt"
    tar -czf "$OUT/gpu-check.tar.gz" -C "$work" --exclude='*.png' --exclude='d_*.csv' . 2>/dev/null
    cat "$work/summary.txt"
}

case ${1:-} in
build) cmd_build ;;
run) cmd_run ;;
quick) quick=1 cmd_run ;;
*)
    sed -n '2,46p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
