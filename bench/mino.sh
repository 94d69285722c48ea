#!/usr/bin/env bash
# bench/mino.sh: the Mino-time integrator against the paper's RK4,
# every comparison measured side by side (cases alternate run by run, the
# order reversed every other run) in one run of this script.
#
#   (a) `make demo`'s scene (scenes/demo.yml) at 640x480 on 2 threads,
#       integrator mino vs rk4: wall time (and CPU time) medians and the
#       speed-up rk4 / mino (the target: >= 50); pixels classed
#       differently.
#   (b) a = 0.9, inclination 85 deg, static observer at r = 100, disc 6-15,
#       120x120, hfov = 2 atan(20/100) (bench/scenes/mino-r100.yml), one thread:
#       CPU microseconds per ray, steps per ray and CPU-ns per step for mino
#       (default tolerance, plus --tolerances), rk4 (c = 1/32) and rk4 with
#       c = 1/128 (the converged reference); pixels classed differently from
#       rk4 and from the reference. CPU per ray is the process's user+sys time
#       (wait4) less that of the same run at 1x1 pixel (start-up, scene, exit),
#       divided by the rays. Target: <= 5 us per ray at the default tolerance,
#       no pixel classed differently from rk4.
#   (c) the distance: the kerrz-disc scene (a = 0.9, 85 deg, disc 6-15) seen
#       from r = 30 (hfov 2 atan(20/30)), r = 1e6 (hfov 2 atan(20/1e6)) and
#       r: inf (hextent 40), so the same +-20 M plane fills the frame; mino;
#       time ratios r = 1e6 / r = 30 and inf / r = 30 (target <= 1.5), and the
#       classes of r = 1e6 against r = inf.
#
# Configurations: bench/scenes/mino.yml, rk4.yml, rk4-c128.yml (--tolerance
# writes a mino configuration into the work folder instead of mino.yml).
# Classes (disc/hole/sky) are compared by bench/compare_classes.py on each
# case's d_0.csv from a run with -t id. For the mino cases that run is an
# extra, untimed one (a warm-up), and the timed runs write info.txt only
# (-t i); for the slow rk4 cases it counts as their first timed run (writing
# the CSV costs well under 1 % of an rk4 frame).
#
# Usage: bench/mino.sh [--parts "a b c"] [--runs N] [--slow-runs N]
#                      [--tolerance T] [--tolerances "1e-6 1e-10"]
#                      [--size-c W] [--threads N] [--work DIR] [--out PREFIX]
#                      [--quick]
#   --parts "..."     which parts to run (a b c)
#   --runs N          timed runs of every mino case (5)
#   --slow-runs N     timed runs of the rk4 cases of (a) and (b), the class
#                     run included (3); the c = 1/128 reference of (b) runs
#                     once
#   --tolerance T     mino's raytracer.tolerance in every part (default: none
#                     given, curray's default)
#   --tolerances ".." extra mino tolerances for (b) ("1e-6 1e-10"; "" for none)
#   --size-c W        frame size of (c), W x W (320)
#   --threads N       threads of (a) and (c) (2); (b) always runs one thread
#   --work DIR        renders and logs (build-bench/mino-work)
#   --out PREFIX      PREFIX.md (report), PREFIX-runs.csv, PREFIX-compare-*.txt
#                     (default bench/results/mino-<date>)
#   --quick           a smoke test of the script, not a result: demo at 160x120,
#                     (b) at 40x40, (c) at 80x80, 1 run each, no extra tolerances
# Environment: CURRAY_BIN (binary), CURRAY_BENCH_BUILD (build folder).
# Output: the report (markdown) on stdout; commands and progress on stderr.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

parts="a b c" runs=5 slow=3 tol="" tols="1e-6 1e-10" size_c=320 nt=2 work="" out=""
wa=640 ha=480 wb=120
while [ $# -gt 0 ]; do
    case $1 in
    --parts) parts=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --slow-runs) slow=$2; shift 2 ;;
    --tolerance) tol=$2; shift 2 ;;
    --tolerances) tols=$2; shift 2 ;;
    --size-c) size_c=$2; shift 2 ;;
    --threads) nt=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --quick) runs=1 slow=1 tols="" wa=160 ha=120 wb=40 size_c=80; shift ;;
    -h | --help) sed -n '2,53p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
for v in "$runs" "$slow" "$size_c" "$nt"; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || die "--runs, --slow-runs, --size-c and --threads need positive integers, got '$v'"
done
for p in $parts; do case $p in a | b | c) ;; *) die "--parts: unknown part '$p' (a, b, c)" ;; esac; done
[ -z "$work" ] && work="$BUILD_DIR/mino-work"
[ -z "$out" ] && out="$BENCH_DIR/results/mino-$(date +%Y%m%d-%H%M%S)"
command -v python3 >/dev/null || die "python3 is needed (bench/timecmd.py, bench/compare_classes.py)"
mkdir -p "$work" "$(dirname "$out")"
work=$(cd "$work" && pwd)
S=$BENCH_DIR/scenes

bench_ensure_binary cpu

mino_cfg=$S/mino.yml
if [ -n "$tol" ]; then
    mino_cfg=$work/mino-tol.yml
    printf '# written by bench/mino.sh\nraytracer:\n  integrator: mino\n  tolerance: %s\n' "$tol" >"$mino_cfg"
fi
tol_cfg() { # TOL -> path of a mino configuration with that tolerance
    local f="$work/mino-tol-$1.yml"
    printf '# written by bench/mino.sh\nraytracer:\n  integrator: mino\n  tolerance: %s\n' "$1" >"$f"
    echo "$f"
}

# --- cases: name|part|label|scene|config|width|height|threads|runs|csv_timed ---
# runs = timed runs besides the class run; csv_timed = 1: the class run is timed too
cases=()
has() { case " $parts " in *" $1 "*) return 0 ;; esac; return 1; }
if has a; then
    cases+=("a-mino|a|mino${tol:+ (tolerance $tol)}|$REPO_DIR/scenes/demo.yml|$mino_cfg|$wa|$ha|$nt|$runs|0")
    cases+=("a-rk4|a|rk4 (c = 1/32)|$REPO_DIR/scenes/demo.yml|$S/rk4.yml|$wa|$ha|$nt|$((slow - 1))|1")
fi
if has b; then
    cases+=("b-mino|b|mino, ${tol:-default} tolerance|$S/mino-r100.yml|$mino_cfg|$wb|$wb|1|$runs|0")
    for t in $tols; do
        cases+=("b-mino-$t|b|mino, tolerance $t|$S/mino-r100.yml|$(tol_cfg "$t")|$wb|$wb|1|$runs|0")
    done
    cases+=("b-rk4|b|rk4 (c = 1/32)|$S/mino-r100.yml|$S/rk4.yml|$wb|$wb|1|$((slow - 1))|1")
    cases+=("b-ref|b|rk4 (c = 1/128), reference|$S/mino-r100.yml|$S/rk4-c128.yml|$wb|$wb|1|0|1")
fi
if has c; then
    cases+=("c-r30|c|r = 30|$S/distance-r30.yml|$mino_cfg|$size_c|$size_c|$nt|$runs|0")
    cases+=("c-r1e6|c|r = 1e6|$S/distance-r1e6.yml|$mino_cfg|$size_c|$size_c|$nt|$runs|0")
    cases+=("c-inf|c|r = inf|$S/distance-inf.yml|$mino_cfg|$size_c|$size_c|$nt|$runs|0")
fi

runs_csv="$out-runs.csv" cases_csv="$work/cases.csv"
echo "case,part,kind,run,wall_s,user_s,sys_s,maxrss_kb,frame_s,steps,rays,load1_before" >"$runs_csv"
echo "case|part|label|scene|config|width|height|threads|runs|csv_timed" >"$cases_csv"
printf '%s\n' "${cases[@]}" >>"$cases_csv"

# run_case NAME KIND RUN W H: KIND = csv (the -t id run), time (-t i), base (1x1)
run_case() {
    local name=$1 kind=$2 r=$3 line part label scene cfg w h th n
    for line in "${cases[@]}"; do [ "${line%%|*}" = "$name" ] && break; done
    IFS='|' read -r _ part label scene cfg w h th n _ <<<"$line"
    local o="$work/$name-$kind" types=i
    [ "$kind" = csv ] && types=id
    [ "$kind" = base ] && w=1 h=1
    rm -rf "$o"
    local args=("$CURRAY" -s "$scene" -c "$cfg" -o "$o" -x "$w" -y "$h" -t "$types" -a true -q true --backend cpu --threads "$th")
    if [ "$r" = 1 ]; then echo "+ ${args[*]}" >&2; fi
    local l0
    l0=$(load1)
    python3 "$BENCH_DIR/timecmd.py" "$o.time" -- "${args[@]}" ||
        { cat "$o.time.log" >&2; die "curray failed: ${args[*]}"; }
    local wall u s m rc fs st ry
    read -r wall u s m rc <"$o.time"
    fs=$(bench_info_value "$o/info.txt" wall)
    st=$(bench_info_value "$o/info.txt" steps)
    ry=$(bench_info_value "$o/info.txt" rays)
    [ -n "$st" ] && [ -n "$ry" ] || die "no steps/rays in $o/info.txt"
    echo "$name,$part,$kind,$r,$wall,$u,$s,$m,$fs,$st,$ry,$l0" >>"$runs_csv"
    printf 'bench: %-14s %-4s run %s: wall %7.3f s, CPU %7.3f s, %s steps, load %s\n' "$name" "$kind" "$r" "$wall" \
        "$(awk -v a="$u" -v b="$s" 'BEGIN {print a + b}')" "$st" "$l0" >&2
}

start_uptime=$(uptime)
for p in $parts; do
    names=() nruns=()
    for line in "${cases[@]}"; do
        IFS='|' read -r name part _ _ _ _ _ _ n _ <<<"$line"
        [ "$part" = "$p" ] && names+=("$name") && nruns+=("$n")
    done
    echo "bench: part ($p): ${names[*]}" >&2
    # the class images (a warm-up for mino; the first timed run for rk4)
    for name in "${names[@]}"; do run_case "$name" csv 1; done
    # timed runs, alternating; (b) also times each case at 1x1 (its baseline)
    maxr=0
    for n in "${nruns[@]}"; do [ "$n" -gt "$maxr" ] && maxr=$n; done
    for r in $(seq 1 "$maxr"); do
        order=("${!names[@]}")
        if [ $((r % 2)) = 0 ]; then
            order=()
            for ((k = ${#names[@]} - 1; k >= 0; k--)); do order+=("$k"); done
        fi
        for k in "${order[@]}"; do
            [ "$r" -le "${nruns[$k]}" ] || continue
            run_case "${names[$k]}" time "$r"
            if [ "$p" = b ]; then run_case "${names[$k]}" base "$r"; fi
        done
    done
    if [ "$p" = b ]; then
        for r in $(seq 1 "$runs"); do run_case b-ref base "$r"; done
    fi
    # the classes
    cmp_classes() { # A B
        python3 "$BENCH_DIR/compare_classes.py" "curray:$work/$1-csv/d_0.csv" "curray:$work/$2-csv/d_0.csv" \
            --name-a "$1" --name-b "$2" --markdown --png "$out-diff-$1-vs-$2.png" >"$out-compare-$1-vs-$2.txt" ||
            die "comparing $1 with $2 failed"
    }
    case $p in
    a) cmp_classes a-mino a-rk4 ;;
    b)
        for name in "${names[@]}"; do
            case $name in b-mino*) cmp_classes "$name" b-rk4; cmp_classes "$name" b-ref ;; esac
        done
        cmp_classes b-rk4 b-ref
        ;;
    c) cmp_classes c-r1e6 c-inf ;;
    esac
done
end_uptime=$(uptime)

{
    echo "## curray: Mino-time integrator vs the paper's RK4"
    echo
    echo "Machine: $(awk -F': ' '/^model name/ {print $2; exit}' /proc/cpuinfo), $(nproc) online cores." \
        "Load (uptime) before: ${start_uptime#*load average: }; after: ${end_uptime#*load average: }."
    echo "curray: $("$CURRAY" --version 2>&1 | head -1) $(bench_build_label); binary $CURRAY."
    echo
    python3 "$BENCH_DIR/mino_report.py" "$runs_csv" "$cases_csv" "$out"
} | tee "$out.md"
