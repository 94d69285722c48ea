# bench/lib.sh: shared helpers of the bench scripts (sourced, not run): run.sh, scaling.sh,
# ab.sh, farleg.sh, kerrz*.sh, mino.sh, packets.sh, mpi.sh, web.sh and the interleaved
# comparisons antialias.sh, horizons.sh, keplerian.sh, matter.sh, observer.sh.
# Timings only; nothing here is a test.

BENCH_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO_DIR=$(cd "$BENCH_DIR/.." && pwd)
BUILD_DIR=${CURRAY_BENCH_BUILD:-$REPO_DIR/build-bench}
CURRAY=${CURRAY_BIN:-$BUILD_DIR/curray}
ALL_SCENES="schwarzschild-disc kerr-disc starry-sky sphere"

die() { echo "bench: $*" >&2; exit 1; }

# Build the project's own binary (Release) when it is missing. For --backend
# cuda the build must have found nvcc; the binary's `-i` answers whether it can
# see a GPU.
bench_ensure_binary() {
    local backend=$1
    if [ ! -x "$CURRAY" ]; then
        [ -n "${CURRAY_BIN:-}" ] && die "CURRAY_BIN=$CURRAY is not an executable"
        echo "bench: building $CURRAY (Release)" >&2
        "$REPO_DIR/tools/install-deps.sh" >&2 || die "cannot install the build dependencies"
        cmake -S "$REPO_DIR" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DCURRAY_TESTS=OFF >&2 &&
            cmake --build "$BUILD_DIR" -j "$(nproc 2>/dev/null || echo 2)" --target curray >&2 ||
            die "build failed"
    fi
    if [ "$backend" = cuda ]; then
        if "$CURRAY" -i 2>&1 | grep -qE "no CUDA support|No CUDA GPU can be used"; then
            die "$CURRAY cannot use a CUDA device (built without nvcc, or no GPU): see '$CURRAY -i'"
        fi
    fi
}

# Peak memory comes from GNU time's "Maximum resident set size". Install the
# Debian package `time` when it is missing (as tools/install-deps.sh does for
# the build); without it, fall back to polling VmHWM in /proc/<pid>/status.
GNU_TIME=/usr/bin/time
# CURRAY_BENCH_OFFLINE=1 (a machine without a package registry, e.g. the GPU
# machine of tools/gpu-check.sh) skips the install.
bench_ensure_time() {
    if [ -x "$GNU_TIME" ] && "$GNU_TIME" -v true >/dev/null 2>&1; then return 0; fi
    [ -n "${CURRAY_BENCH_OFFLINE:-}" ] || "$REPO_DIR/tools/install-deps.sh" time >&2 2>&1 || true
    if [ -x "$GNU_TIME" ] && "$GNU_TIME" -v true >/dev/null 2>&1; then return 0; fi
    echo "bench: GNU time unavailable; peak memory read from /proc/<pid>/status (VmHWM, polled)" >&2
    GNU_TIME=""
}

load1() { cut -d' ' -f1 /proc/loadavg; }

# What the timed binary was built from, for the reports: the checkout's HEAD
# and whether src/ had uncommitted changes, or the CURRAY_BIN given.
bench_build_label() {
    if [ -n "${CURRAY_BIN:-}" ]; then
        echo "(binary CURRAY_BIN=$CURRAY_BIN)"
    elif git -C "$REPO_DIR" status --porcelain -- src 2>/dev/null | grep -q .; then
        echo "(built from the working tree at $(git -C "$REPO_DIR" rev-parse --short HEAD), with uncommitted changes in src/)"
    else
        echo "(built from $(git -C "$REPO_DIR" rev-parse --short HEAD 2>/dev/null || echo '?'), src/ clean)"
    fi
}

# bench_info_value INFO KEY: a number from the first frame of info.txt.
#   wall   the frame's wall time (s)
#   rays   rays traced
#   steps  integration steps of all rays (the line was "RK4 steps" before the
#          Mino integrator; any "... steps N" line but "steps per ray")
#   maxsteps  the largest steps of one ray ("steps per ray  X (max N)")
bench_info_value() {
    local info=$1 key=$2
    [ -f "$info" ] || die "no $info"
    case $key in
    wall) awk '/^  wall time/ {print $3; exit}' "$info" ;;
    rays) awk '/^  rays / {print $2; exit}' "$info" ;;
    steps) awk '/^  [A-Za-z0-9 -]*steps +[0-9]+ *$/ && !/per ray/ {print $NF; exit}' "$info" ;;
    maxsteps) awk '/^  steps per ray/ {gsub(/[()]/,""); print $NF; exit}' "$info" ;;
    *) die "bench_info_value: unknown key $key" ;;
    esac
}

# bench_measure SCENE W H BACKEND THREADS CONFIG RUN CSV
# Renders one frame (info.txt only, so PNG/CSV writing is not timed) and
# appends one row to CSV:
#   scene,backend,threads,width,height,config,run,frame_s,process_s,rays,steps,
#   max_steps_ray,peak_rss_kb,cpu_pct,load1_before
# frame_s is curray's own render time of the frame (info.txt "wall time");
# process_s the whole process (loading, set-up, exit).
bench_measure() {
    local scene=$1 w=$2 h=$3 backend=$4 threads=$5 config=$6 run=$7 csv=$8
    local sfile="$BENCH_DIR/scenes/$scene.yml"
    [ -f "$sfile" ] || die "no scene $sfile"
    local out tfile
    out=$(mktemp -d "${TMPDIR:-/tmp}/curray-bench.XXXXXX")
    tfile="$out/time.txt"
    local args=(-s "$sfile" -o "$out/frame" -x "$w" -y "$h" -t i -a true -q true --backend "$backend")
    [ "$threads" != "" ] && [ "$threads" != "-" ] && args+=(--threads "$threads")
    if [ "$config" != "" ] && [ "$config" != "-" ]; then
        args+=(-c "$config")
    else
        # no config.yml from the current folder: built-in defaults
        args+=(-c "$BENCH_DIR/scenes/defaults.yml")
    fi
    local l0 rss="" cpu="" t0 t1 pid rc
    l0=$(load1)
    t0=$(date +%s.%N)
    if [ -n "$GNU_TIME" ]; then
        # `|| rc=$?`: the callers run under set -e, which would end the script
        # here, silently, on a failed render
        rc=0
        "$GNU_TIME" -v -o "$tfile" "$CURRAY" "${args[@]}" >"$out/stdout" 2>&1 || rc=$?
    else
        "$CURRAY" "${args[@]}" >"$out/stdout" 2>&1 &
        pid=$!
        while kill -0 "$pid" 2>/dev/null; do
            local v
            v=$(awk '/^VmHWM:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
            [ -n "$v" ] && rss=$v
            sleep 0.2
        done
        rc=0
        wait "$pid" || rc=$?
    fi
    t1=$(date +%s.%N)
    if [ "$rc" != 0 ]; then
        cat "$out/stdout" >&2
        rm -rf "$out"
        die "curray failed (exit $rc): $CURRAY ${args[*]}"
    fi
    if [ -n "$GNU_TIME" ]; then
        rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$tfile")
        cpu=$(awk -F': ' '/Percent of CPU this job got/ {sub("%","",$2); print $2}' "$tfile")
    fi
    local info="$out/frame/info.txt"
    local frame_s rays steps maxs
    frame_s=$(bench_info_value "$info" wall)
    rays=$(bench_info_value "$info" rays)
    steps=$(bench_info_value "$info" steps)
    maxs=$(bench_info_value "$info" maxsteps)
    rm -rf "$out"
    [ -n "$frame_s" ] && [ -n "$steps" ] || die "could not read $info"
    local process_s
    process_s=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f", b - a}')
    echo "$scene,$backend,${threads:--},$w,$h,$(basename "${config:--}"),$run,$frame_s,$process_s,$rays,$steps,$maxs,${rss:-},${cpu:-},$l0" >>"$csv"
    printf 'bench: %-18s %5sx%-5s %-4s threads=%-2s cfg=%-12s run %s: %8.3f s, %s steps, load %s\n' \
        "$scene" "$w" "$h" "$backend" "${threads:--}" "$(basename "${config:--}")" "$run" "$frame_s" "$steps" "$l0" >&2
}

BENCH_RUNS_HEADER="scene,backend,threads,width,height,config,run,frame_s,process_s,rays,steps,max_steps_ray,peak_rss_kb,cpu_pct,load1_before"

# bench_summarise RUNS_CSV: one line per (scene,backend,threads,size,config)
# with medians over runs, in the order first seen:
#   scene,backend,threads,width,height,config,runs,frame_s_median,frame_s_min,
#   frame_s_max,rays,steps,steps_identical,rays_per_s,steps_per_s,ns_per_step,
#   steps_per_ray,max_steps_ray,peak_rss_mib,cpu_pct_median,load1_median,cpu_ns_per_step
bench_summarise() {
    awk -F, '
    function median(s,   a, n, i, j, t) {
        n = split(s, a, " ")
        for (i = 2; i <= n; i++) { t = a[i] + 0; for (j = i - 1; j >= 1 && a[j] + 0 > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
        if (n % 2) return a[(n + 1) / 2]
        return (a[n / 2] + a[n / 2 + 1]) / 2
    }
    NR == 1 { next }
    {
        k = $1 "," $2 "," $3 "," $4 "," $5 "," $6
        if (!(k in n)) { order[++nk] = k; n[k] = 0; same[k] = 1; st[k] = $11; lo[k] = $8; hi[k] = $8 }
        n[k]++; ft[k] = ft[k] " " $8; cp[k] = cp[k] " " $14; ld[k] = ld[k] " " $15
        if ($14 != "") cn[k] = cn[k] " " 1e9 * ($14 / 100) * $9 / $11
        if ($8 + 0 < lo[k]) lo[k] = $8; if ($8 + 0 > hi[k]) hi[k] = $8
        if ($11 != st[k]) same[k] = 0
        if ($13 + 0 > rss[k]) rss[k] = $13 + 0
        rays[k] = $10; mx[k] = $12
    }
    END {
        print "scene,backend,threads,width,height,config,runs,frame_s_median,frame_s_min,frame_s_max,rays,steps,steps_identical,rays_per_s,steps_per_s,ns_per_step,steps_per_ray,max_steps_ray,peak_rss_mib,cpu_pct_median,load1_median,cpu_ns_per_step"
        for (i = 1; i <= nk; i++) {
            k = order[i]; t = median(ft[k])
            printf "%s,%d,%.3f,%.3f,%.3f,%d,%.0f,%s,%.0f,%.4g,%.1f,%.1f,%d,%.1f,%s,%.2f,%s\n", k, n[k], t, lo[k], hi[k], rays[k], st[k],
                same[k] ? "yes" : "no", rays[k] / t, st[k] / t, 1e9 * t / st[k], st[k] / rays[k], mx[k], rss[k] / 1024,
                median(cp[k]), median(ld[k]), (cn[k] == "" ? "" : sprintf("%.1f", median(cn[k])))
        }
    }' "$1"
}

# bench_markdown SUMMARY_CSV: the summary as a markdown table.
bench_markdown() {
    awk -F, '
    NR == 1 { next }
    NR == 2 {
        print "| scene | size | backend | threads | c | runs | frame time, median [min-max] (s) | rays/s | photon-steps | photon-steps/s | ns/step | CPU-ns/step | steps/ray (max) | peak RSS (MiB) | CPU % | load |"
        print "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    }
    {
        c = ($6 == "-" ? "default" : $6)
        printf "| %s | %sx%s | %s | %s | %s | %s | %.3f [%.3f-%.3f] | %.0f | %.4g%s | %.4g | %.1f | %s | %.1f (%d) | %.1f | %s | %.2f |\n",
            $1, $4, $5, $2, $3, c, $7, $8, $9, $10, $14, $12, ($13 == "yes" ? "" : " (varied)"), $15, $16, ($22 == "" ? "n/a" : $22), $17, $18, $19, $20, $21
    }' "$1"
}

# kerrz (the peer of bench/kerrz.sh and bench/kerrz_redshift.sh), kerrz-cli
# release $1 from PyPI in its own virtual environment (KERRZ_VENV, default
# $BUILD_DIR/kerrz-venv; created and filled here, never a dependency of
# curray). Sets venv, KERRZ (the static binary inside the wheel: the kerrzcli
# entry point would add a Python start-up to every timed run) and kz_version.
bench_kerrz_setup() {
    local kver=$1
    venv=${KERRZ_VENV:-$BUILD_DIR/kerrz-venv}
    if [ ! -x "$venv/bin/python" ]; then
        echo "bench: creating $venv for kerrz-cli $kver" >&2
        echo "+ python3 -m venv $venv" >&2
        python3 -m venv "$venv" >&2 ||
            die "python3 -m venv failed (Debian: apt-get install python3-venv)"
    fi
    if ! "$venv/bin/python" -c "import importlib.metadata as m, sys; sys.exit(m.version('kerrz-cli') != '$kver')" 2>/dev/null; then
        echo "+ $venv/bin/python -m pip install kerrz-cli==$kver" >&2
        "$venv/bin/python" -m pip install --disable-pip-version-check -q "kerrz-cli==$kver" >&2 ||
            die "pip install kerrz-cli==$kver failed"
    fi
    KERRZ=$("$venv/bin/python" -c "import kerrz_cli; print(kerrz_cli.KERRZ_PATH)") ||
        die "cannot locate the kerrz binary in $venv"
    [ -x "$KERRZ" ] || die "$KERRZ is not executable"
    kz_version=$("$KERRZ" --version 2>&1 | head -1)
    echo "bench: kerrz: $KERRZ ($kz_version)" >&2
}

# curray's image-plane extent (hextent = vextent, in M) that matches kerrz's
# `image --alpha A --beta A` grid of N points per axis: kerrz samples
# alpha_i = -A + 2A i/(N-1), both ends included, so the pixel pitch is
# 2A/(N-1) and N pixels span 2A N/(N-1). Rows: curray's row j is kerrz's
# beta row N-1-j (bench/compare_classes.py).
bench_kerrz_extent() { # A N
    python3 -c "print(repr(2 * $1 * $2 / ($2 - 1)))"
}

# Copy bench scene SRC to DST with hextent = vextent = bench_kerrz_extent A N
# (sets ext).
bench_kerrz_scene() { # SRC DST A N
    ext=$(bench_kerrz_extent "$3" "$4")
    sed -e "s/^\( *hextent:\).*/\1 $ext/" -e "s/^\( *vextent:\).*/\1 $ext/" "$1" >"$2"
    grep -q "hextent: $ext" "$2" && grep -q "vextent: $ext" "$2" ||
        die "could not set the image extents in $2"
}

# --- the interleaved comparison scripts (antialias, horizons, keplerian,
# matter, observer): their common preamble ------------------------------------

# bench_args NAME HELP_LAST ARGS...: parse --runs R, --size WxH, --threads T
# into runs, size and threads (the caller sets their defaults first), the
# options BENCH_OPTS names ("--option=variable ...", each taking a value)
# into those variables, and -h/--help (print lines 2 to HELP_LAST of the
# script's header comment, exit 0); anything else: "NAME: unknown option",
# exit 2. Then w and h from size.
bench_args() {
    local name=$1 last=$2 o v
    shift 2
    while [ $# -gt 0 ]; do
        case $1 in
        --runs) runs=$2; shift 2 ;;
        --size) size=$2; shift 2 ;;
        --threads) threads=$2; shift 2 ;;
        -h | --help) sed -n "2,${last}p" "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *)
            v=""
            for o in ${BENCH_OPTS:-}; do [ "$1" = "${o%%=*}" ] && v=${o#*=}; done
            [ -n "$v" ] || { echo "$name: unknown option '$1'" >&2; exit 2; }
            printf -v "$v" '%s' "$2"
            shift 2 ;;
        esac
    done
    w=${size%x*} h=${size#*x}
}

# bench_bin NAME CANDIDATE...: bin = CURRAY_BIN, else the first executable
# candidate; exit 1 with "NAME: no curray binary (set CURRAY_BIN)" when that
# is not an executable.
bench_bin() {
    local name=$1 b
    shift
    bin=${CURRAY_BIN:-}
    if [ -z "$bin" ]; then
        for b in "$@"; do [ -x "$b" ] && bin=$b && break; done
    fi
    [ -x "$bin" ] || { echo "$name: no curray binary (set CURRAY_BIN)" >&2; exit 1; }
}

# bench_tmpdir: tmp = a fresh folder, removed when the script exits.
bench_tmpdir() {
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
}

# bench_info_steps DIR, bench_info_rays DIR: the integrator steps and the
# rays of DIR/info.txt (its "integrator steps N" and "rays N" lines).
bench_info_steps() { awk '$1 == "integrator" && $2 == "steps" {print $3; exit}' "$1/info.txt"; }
bench_info_rays() { awk '$1 == "rays" {print $2; exit}' "$1/info.txt"; }

# The machine for a report's header: "N cores, <CPU model>", and the load
# averages "L1 L5 L15".
bench_cores_model() { echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"; }
load3() { cut -d' ' -f1-3 /proc/loadavg; }

# bench_median: the median of the numbers on stdin, one a line.
bench_median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : 0.5 * (v[NR / 2] + v[NR / 2 + 1])}'; }
