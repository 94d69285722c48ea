#!/usr/bin/env bash
# bench/kerrz.sh: curray side by side with the peer kerrz.
#
# Renders the same image with both programs: a = 0.9, inclination 85 deg,
# thin disc from r = 6 to 15 M, image plane +-20 M, 640 x 640, 2 threads;
# curray's observer is at infinity (bench/scenes/kerrz-disc.yml, r: inf,
# integrator mino unless --config says otherwise), kerrz's at r = 1e7 M (its
# default; kerrz 0.4.1 never finishes with --dist inf). Then:
#   1. times both, alternating (curray, kerrz, kerrz, curray, ...), --runs
#      each, and reports the medians of wall time and CPU time (user+sys, from
#      wait4) and curray time / kerrz time (ratio of the medians, and the
#      median of the per-run ratios);
#   2. compares the two images pixel by pixel (bench/compare_classes.py):
#      the fraction of pixels where both agree on disc / hole / sky, how many
#      of the others lie on an edge (a neighbour of another class in either
#      image), and, for pixels where one says hole, which program the ray's
#      own Bardeen constants prove wrong (a captured ray cannot be sky, a ray
#      with a radial turning point cannot be hole).
#
# kerrz is installed only here, into a virtual environment in the build folder
# (python3 -m venv + pip install kerrz-cli): it is a peer to measure against,
# never a dependency of curray.
#
# Image planes (found by rendering test images and tracing single rays with `kerrz trace`):
# kerrz image --alpha A --beta A --resolution n traces N = 2*floor(A)*n points
# per axis at alpha_i = -A + 2A i/(N-1) (both ends included); its table
# (--save, FITS) is row-major, alpha fastest, beta from -A upwards. Its alpha
# and beta are Bardeen's (lambda = -alpha sin i, eta = beta^2 + (alpha^2 -
# a^2) cos^2 i): +alpha is +phi (right), +beta is towards the +z pole (up),
# a > 0 turns counter-clockwise about +z and the flattened edge of the shadow
# is at negative alpha (left): curray's orientation, no flip but the row
# order. curray's pixel (i, j) is kerrz's row (N-1-j)*N + i when curray's
# hextent = vextent = 2A N/(N-1) (here 40*640/639 M).
#
# Usage: bench/kerrz.sh [--runs N] [--size W] [--threads N] [--dist R]
#                       [--tolerance T | --config FILE] [--kerrz-version V]
#                       [--work DIR] [--out PREFIX] [--no-timing] [--quick]
#   --runs N          timed runs of each program; medians reported (5)
#   --size W          image width = height in pixels, a multiple of 40 (640)
#   --threads N       threads for both programs (2)
#   --dist R          kerrz's observer distance in M (1e7)
#   --tolerance T     curray: integrator mino with raytracer.tolerance T
#                     (default: mino's default tolerance)
#   --config FILE     curray: this system configuration instead
#   --kerrz-version V the kerrz-cli release to install (0.4.1)
#   --work DIR        renders and logs ($CURRAY_BENCH_BUILD or build-bench,
#                     /kerrz-work)
#   --out PREFIX      results: PREFIX.md (report), PREFIX-runs.csv,
#                     PREFIX-compare.txt, PREFIX-diff.png
#                     (default bench/results/kerrz-<date>)
#   --no-timing       only the comparison
#   --quick           --size 160 --runs 1: a smoke test, not a result
# Environment: CURRAY_BIN (binary), CURRAY_BENCH_BUILD (build folder),
# KERRZ_VENV (virtual environment to use or create).
# Output: the report (markdown) on stdout; commands and progress on stderr.
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

runs=5 size=640 threads=2 dist=1e7 tol="" config="" kver=0.4.1 work="" out="" timing=1
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --dist) dist=$2; shift 2 ;;
    --tolerance) tol=$2; shift 2 ;;
    --config) config=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --kerrz-version) kver=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --no-timing) timing=0; shift ;;
    --quick) size=160 runs=1; shift ;;
    -h | --help) sed -n '2,55p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || die "--runs needs a positive integer, got '$runs'"
[[ $threads =~ ^[1-9][0-9]*$ ]] || die "--threads needs a positive integer, got '$threads'"
[[ $size =~ ^[1-9][0-9]*$ ]] && [ $((size % 40)) = 0 ] ||
    die "--size must be a positive multiple of 40 (kerrz draws 2*20*n pixels over +-20 M with an integer --resolution n), got '$size'"
[ -n "$tol" ] && [ -n "$config" ] && die "give --tolerance or --config, not both"
[ -z "$work" ] && work="$BUILD_DIR/kerrz-work"
[ -z "$out" ] && out="$BENCH_DIR/results/kerrz-$(date +%Y%m%d-%H%M%S)"
command -v python3 >/dev/null || die "python3 is needed (for the venv and bench/compare_classes.py)"
mkdir -p "$work" "$(dirname "$out")"
work=$(cd "$work" && pwd)
res=$((size / 40))
SPIN=0.9 INCL=85 RIN=6 ROUT=15 HALF=20

run_echo() { echo "+ $*" >&2; "$@"; }

# --- curray ----------------------------------------------------------------
bench_ensure_binary cpu

# --- kerrz, in its own virtual environment ------------------------------------
bench_kerrz_setup "$kver"

# --- the scene and the configuration -------------------------------------------
scene="$work/kerrz-disc-$size.yml"
bench_kerrz_scene "$BENCH_DIR/scenes/kerrz-disc.yml" "$scene" "$HALF" "$size"
if [ -z "$config" ]; then
    config="$work/curray-config.yml"
    {
        echo "# written by bench/kerrz.sh"
        echo "raytracer:"
        echo "  integrator: mino"
        [ -n "$tol" ] && echo "  tolerance: $tol"
    } >"$config"
fi

CUR_ARGS=(-s "$scene" -x "$size" -y "$size" -a true -q true --backend cpu --threads "$threads" -c "$config")
KZ_ARGS=(image --spin "$SPIN" --incl "$INCL" --alpha "$HALF" --beta "$HALF" --resolution "$res"
    --dist "$dist" --thin-disc "rin:$RIN,rout:$ROUT" --map status --nthreads "$threads")

# --- the comparison renders (also the warm-up) --------------------------------
echo "bench: comparison renders (untimed)" >&2
rm -rf "$work/curray-d"
run_echo "$CURRAY" "${CUR_ARGS[@]}" -o "$work/curray-d" -t id >"$work/curray-d.log" 2>&1 ||
    { cat "$work/curray-d.log" >&2; die "curray failed"; }
run_echo "$KERRZ" "${KZ_ARGS[@]}" --save "$work/kerrz.fits" -o "$work/kerrz.pgm" >"$work/kerrz-save.log" 2>&1 ||
    { cat "$work/kerrz-save.log" >&2; die "kerrz failed"; }
[ -s "$work/curray-d/d_0.csv" ] || die "curray wrote no $work/curray-d/d_0.csv"
[ -s "$work/kerrz.fits" ] || die "kerrz wrote no $work/kerrz.fits"
grep -q "r *inf" "$work/curray-d/info.txt" || echo "bench: warning: curray's observer is not at infinity (see $work/curray-d/info.txt)" >&2

echo "bench: comparing" >&2
run_echo python3 "$BENCH_DIR/compare_classes.py" "curray:$work/curray-d/d_0.csv" "kerrz:$work/kerrz.fits" \
    --name-a curray --name-b kerrz --hextent "$ext" --vextent "$ext" --bardeen "$SPIN,$INCL" \
    --png "$out-diff.png" --markdown >"$out-compare.txt" ||
    die "the comparison failed"

# --- timing, alternating ----------------------------------------------------
runs_csv="$out-runs.csv"
echo "prog,run,wall_s,user_s,sys_s,maxrss_kb,frame_s,steps,rays,load1_before" >"$runs_csv"
time_one() { # PROG RUN
    local prog=$1 r=$2 t="$work/time-$1-$2" l0 fs="" st="" ry=""
    l0=$(load1)
    if [ "$prog" = curray ]; then
        rm -rf "$work/curray-t"
        python3 "$BENCH_DIR/timecmd.py" "$t" -- "$CURRAY" "${CUR_ARGS[@]}" -o "$work/curray-t" -t i ||
            { cat "$t.log" >&2; die "curray failed: $CURRAY ${CUR_ARGS[*]} -o $work/curray-t -t i"; }
        fs=$(bench_info_value "$work/curray-t/info.txt" wall)
        st=$(bench_info_value "$work/curray-t/info.txt" steps)
        ry=$(bench_info_value "$work/curray-t/info.txt" rays)
    else
        python3 "$BENCH_DIR/timecmd.py" "$t" -- "$KERRZ" "${KZ_ARGS[@]}" -o "$work/kerrz-t.pgm" ||
            { cat "$t.log" >&2; die "kerrz failed: $KERRZ ${KZ_ARGS[*]} -o $work/kerrz-t.pgm"; }
    fi
    read -r w u s m rc <"$t"
    echo "$prog,$r,$w,$u,$s,$m,$fs,$st,$ry,$l0" >>"$runs_csv"
    printf 'bench: %-6s run %s: wall %.3f s, CPU %.3f s, load %s\n' "$prog" "$r" "$w" \
        "$(awk -v a="$u" -v b="$s" 'BEGIN {print a + b}')" "$l0" >&2
}
start_uptime=$(uptime)
if [ "$timing" = 1 ]; then
    echo "bench: timing, $runs runs each, alternating:" >&2
    echo "+ $CURRAY ${CUR_ARGS[*]} -o $work/curray-t -t i" >&2
    echo "+ $KERRZ ${KZ_ARGS[*]} -o $work/kerrz-t.pgm" >&2
    for r in $(seq 1 "$runs"); do
        if [ $((r % 2)) = 1 ]; then
            time_one curray "$r"; time_one kerrz "$r"
        else
            time_one kerrz "$r"; time_one curray "$r"
        fi
    done
fi
end_uptime=$(uptime)

# --- the report ---------------------------------------------------------------
report() {
    echo "## curray vs kerrz: a = $SPIN, inclination $INCL deg, disc $RIN-$ROUT M, +-$HALF M, ${size}x$size, $threads threads"
    echo
    echo "Machine: $(awk -F': ' '/^model name/ {print $2; exit}' /proc/cpuinfo), $(nproc) online cores." \
        "Load (uptime) before: ${start_uptime#*load average: }; after: ${end_uptime#*load average: }."
    echo "curray: $("$CURRAY" --version 2>&1 | head -1) $(bench_build_label), configuration:" \
        "$(grep -v '^#' "$config" | tr '\n' ' ' | sed 's/  */ /g')"
    echo "kerrz: $kz_version (kerrz-cli $kver from PyPI, in $venv)"
    echo
    echo '```'
    echo "$CURRAY ${CUR_ARGS[*]} -o OUT -t i        # timed (-t id for the comparison)"
    echo "$KERRZ ${KZ_ARGS[*]} -o OUT.pgm   # timed (--save T.fits for the comparison)"
    echo '```'
    echo
    if [ "$timing" = 1 ]; then
        python3 - "$runs_csv" <<'EOF'
import csv, statistics as st, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def col(p, k): return [float(r[k]) for r in rows if r["prog"] == p and r[k] != ""]
med = st.median
cw, kw = col("curray", "wall_s"), col("kerrz", "wall_s")
cc = [float(r["user_s"]) + float(r["sys_s"]) for r in rows if r["prog"] == "curray"]
kc = [float(r["user_s"]) + float(r["sys_s"]) for r in rows if r["prog"] == "kerrz"]
runs = sorted(set(int(r["run"]) for r in rows))
def by(p, k):
    d = {}
    for r in rows:
        if r["prog"] == p:
            d[int(r["run"])] = float(r[k]) if k != "cpu" else float(r["user_s"]) + float(r["sys_s"])
    return d
pw = [by("curray", "wall_s")[i] / by("kerrz", "wall_s")[i] for i in runs]
pc = [by("curray", "cpu")[i] / by("kerrz", "cpu")[i] for i in runs]
steps = col("curray", "steps"); rays = col("curray", "rays"); fs = col("curray", "frame_s")
print("| program | runs | wall time, median [min-max] (s) | CPU time user+sys, median (s) | peak RSS (MiB) |")
print("|---|---|---|---|---|")
for p, w, c in (("curray", cw, cc), ("kerrz", kw, kc)):
    rss = max(float(r["maxrss_kb"]) for r in rows if r["prog"] == p) / 1024
    print("| %s | %d | %.3f [%.3f-%.3f] | %.3f | %.1f |" % (p, len(w), med(w), min(w), max(w), med(c), rss))
print()
print("| ratio curray / kerrz | wall time | CPU time |")
print("|---|---|---|")
print("| of the medians | **%.2f** | %.2f |" % (med(cw) / med(kw), med(cc) / med(kc)))
print("| median of the per-run ratios (side by side) | %.2f | %.2f |" % (med(pw), med(pc)))
print()
if steps and rays:
    print("curray: %.1f steps per ray (%d steps, %d rays); frame time in info.txt %.3f s (median); "
          "%.0f CPU-ns per step, %.2f CPU-us per ray (whole process)." % (
              steps[0] / rays[0], steps[0], rays[0], med(fs), 1e9 * med(cc) / steps[0], 1e6 * med(cc) / rays[0]))
    print()
EOF
    fi
    echo "### Pixel classes (disc / hole / sky)"
    echo
    awk -F= '/^(agree_frac|disagree|disagree_on_edges|disagree_interior|disagree_on_edges_frac|grid_max_offset_M|bardeen_[a-z_]*|agree_frac_bardeen_fixed|disagree_not_proven|disagree_not_proven_on_edges|interior_pairs|interior_bbox)=/ {print "- " $1 ": " $2}' "$out-compare.txt"
    echo
    sed -n '/^|/,$p' "$out-compare.txt"
    echo
    echo "A disagreeing pixel is on an edge when one of its 8 neighbours has another class in either image."
    echo "bardeen_wrong_X: disagreements involving 'hole' where the ray's Bardeen constants prove X wrong"
    echo "(captured: R(r) > 0 for all r > r+, so not sky; a turning point outside the horizon: not hole)."
    echo "disagree_not_proven(_on_edges): the disagreements left when those are set aside (and how many lie on edges)."
    echo "Picture of the disagreements: $out-diff.png (magenta: kerrz proven wrong, green: curray proven wrong;"
    echo "the rest red on an edge, blue interior). Runs: $runs_csv."
}
report | tee "$out.md"
