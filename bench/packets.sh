#!/usr/bin/env bash
# bench/packets.sh: the CPU's packet path against its scalar path, and the
# early stop against the scene boundary at the observer, side by side.
#
#   (a) the A100 scene (bench/scenes/mino-r100.yml: a = 0.9, 85 deg, static
#       observer at r = 100 M, disc 6-15 M), SIZE x SIZE (120), 1 thread:
#       cpu.simd off (scalar), AVX2 (CURRAY_TEST_CPU_FEATURES=avx2 hides
#       AVX-512) and auto (the widest the CPU has);
#   (b) with --before BIN (a curray built before the early stop, e.g. the
#       commit before it): the a = 0.9 disc seen from r = 30, 100 and 1e6 M
#       (bench/scenes/distance-r30, mino-r100, distance-r1e6), DSIZE x DSIZE
#       (200), 1 thread, both with cpu.simd off (BIN too where it knows the
#       key): BIN against this curray; steps per ray from info.txt.
#   (c) `make demo`'s render (scenes/demo.yml, 640 x 480, every core): this
#       curray with cpu.simd off and auto, and with --before BIN that one.
#   With --packets-before BIN (another curray with the packet path, e.g. an
#   older commit's), table (a) has BIN's AVX2 and auto paths too, in the same
#   interleaved runs.
# Every case runs --runs times (5), interleaved (case 1, case 2, ..., case 1,
# ...), each a whole process timed by bench/timecmd.py (wall, user + sys CPU
# from wait4); the report gives medians and the ratios of the medians, and
# the 1-minute load average before and after.
#
# Usage: bench/packets.sh [--runs N] [--size N] [--dsize N] [--before BIN]
#                         [--packets-before BIN] [--out PREFIX]
# Environment: CURRAY_BIN (default build-bench/curray, built when missing).
# Output: the report (markdown) on stdout and in PREFIX.md with the raw runs
# in PREFIX-runs.csv (default bench/results/packets-<date>).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
runs=5 size=120 dsize=200 before="" pbefore="" out=""
while [ $# -gt 0 ]; do
    case $1 in
    --runs) runs=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --dsize) dsize=$2; shift 2 ;;
    --before) before=$2; shift 2 ;;
    --packets-before) pbefore=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h | --help) sed -n '2,28p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
[[ $runs =~ ^[1-9][0-9]*$ ]] || die "--runs needs a positive integer, got '$runs'"
bench_ensure_binary cpu
[ -z "$before" ] || [ -x "$before" ] || die "--before $before is not an executable"
[ -z "$pbefore" ] || [ -x "$pbefore" ] || die "--packets-before $pbefore is not an executable"
out=${out:-$BENCH_DIR/results/packets-$(date -u +%Y%m%d-%H%M)}
mkdir -p "$(dirname "$out")"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
S=$BENCH_DIR/scenes
printf 'cpu: {simd: off}\n' >"$work/off.yml"
printf 'cpu: {simd: auto}\n' >"$work/auto.yml"
: >"$work/empty.yml"

# case: name|binary|scene|config|size (or WxH)|threads|environment
D=$REPO_DIR/scenes/demo.yml
cases=("a-scalar|$CURRAY|$S/mino-r100.yml|$work/off.yml|$size|1|"
       "a-avx2|$CURRAY|$S/mino-r100.yml|$work/auto.yml|$size|1|CURRAY_TEST_CPU_FEATURES=avx2"
       "a-auto|$CURRAY|$S/mino-r100.yml|$work/auto.yml|$size|1|"
       "c-scalar|$CURRAY|$D|$work/off.yml|640x480|0|"
       "c-auto|$CURRAY|$D|$work/auto.yml|640x480|0|")
if [ -n "$pbefore" ]; then
    cases+=("a-pb-avx2|$pbefore|$S/mino-r100.yml|$work/auto.yml|$size|1|CURRAY_TEST_CPU_FEATURES=avx2"
            "a-pb-auto|$pbefore|$S/mino-r100.yml|$work/auto.yml|$size|1|")
fi
# the older binary on the scalar path too when it knows cpu.simd
bcfg=$work/empty.yml
if [ -n "$before" ] && "$before" -s "$S/mino-r100.yml" -c "$work/off.yml" -o "$work/probe" -x 1 -y 1 \
    -t i -a true -q true >/dev/null 2>&1; then
    bcfg=$work/off.yml
fi
[ -z "$before" ] || cases+=("c-before|$before|$D|$bcfg|640x480|0|")
if [ -n "$before" ]; then
    for d in r30 r100 r1e6; do
        sc=$S/distance-$d.yml
        [ $d = r100 ] && sc=$S/mino-r100.yml
        cases+=("b-$d-before|$before|$sc|$bcfg|$dsize|1|")
        cases+=("b-$d-after|$CURRAY|$sc|$work/off.yml|$dsize|1|")
    done
fi
load0=$(cut -d' ' -f1 /proc/loadavg)
echo "case,run,wall_s,cpu_s,steps_per_ray" >"$out-runs.csv"
for ((r = 1; r <= runs; r++)); do
    for c in "${cases[@]}"; do
        IFS='|' read -r name bin scene cfg sz nt envs <<<"$c"
        o=$work/$name
        rm -rf "$o"
        w=${sz%x*} h=${sz#*x}
        topt=(--threads "$nt")
        [ "$nt" = 0 ] && topt=()
        env $envs python3 "$BENCH_DIR/timecmd.py" "$work/t" -- "$bin" -s "$scene" -c "$cfg" \
            -o "$o" -x "$w" -y "$h" -t i -a true -q true "${topt[@]}" ||
            die "$name failed: $(tail -3 "$work/t.log")"
        read -r wall user sys _ _ <"$work/t"
        spr=$(awk '/^  steps per ray/ {print $4; exit}' "$o/info.txt")
        echo "$name,$r,$wall,$(awk -v u="$user" -v s="$sys" 'BEGIN{printf "%.4f", u + s}'),$spr" \
            >>"$out-runs.csv"
        echo "bench: $name run $r: wall $wall s, user $user s, steps/ray $spr" >&2
    done
done
load1=$(cut -d' ' -f1 /proc/loadavg)

python3 - "$out-runs.csv" "$load0" "$load1" "$runs" "$size" "$dsize" "$(uname -m) $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')" <<'EOF' | tee "$out.md"
import csv, statistics, sys
path, l0, l1, runs, size, dsize, mach = sys.argv[1:]
rows = list(csv.DictReader(open(path)))
by = {}
for r in rows:
    by.setdefault(r["case"], []).append(r)
med = lambda name, key: statistics.median(float(r[key]) for r in by[name])
print(f"Machine: {mach}; 1-minute load {l0} before, {l1} after; {runs} runs per case, interleaved; medians.\n")
print(f"(a) A100 scene, {size}x{size}, 1 thread\n")
print("| path | CPU s | wall s | CPU vs scalar | wall vs scalar | steps/ray |")
print("| --- | ---: | ---: | ---: | ---: | ---: |")
for name, label in (("a-scalar", "scalar (cpu.simd: off)"), ("a-avx2", "AVX2, 4 lanes"), ("a-auto", "auto (widest)"),
                    ("a-pb-avx2", "--packets-before, AVX2"), ("a-pb-auto", "--packets-before, auto")):
    if name not in by:
        continue
    c, w = med(name, "cpu_s"), med(name, "wall_s")
    print(f"| {label} | {c:.4f} | {w:.4f} | {med('a-scalar','cpu_s')/c:.2f}x fewer | {med('a-scalar','wall_s')/w:.2f}x | {by[name][0]['steps_per_ray']} |")
print(f"\n(c) make demo's render (scenes/demo.yml, 640x480, every core)\n")
print("| curray | CPU s | wall s | steps/ray |")
print("| --- | ---: | ---: | ---: |")
for name, label in (("c-before", "before (--before)"), ("c-scalar", "this, cpu.simd: off"), ("c-auto", "this, cpu.simd: auto")):
    if name in by:
        print(f"| {label} | {med(name,'cpu_s'):.3f} | {med(name,'wall_s'):.3f} | {by[name][0]['steps_per_ray']} |")
if "b-r30-before" in by:
    print(f"\n(b) early stop, {dsize}x{dsize}, 1 thread, scalar path\n")
    print("| observer | steps/ray before | after | CPU s before | after | CPU after/before | wall before | after |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for d, lab in (("r30", "r = 30"), ("r100", "r = 100"), ("r1e6", "r = 1e6")):
        b, a = f"b-{d}-before", f"b-{d}-after"
        print(f"| {lab} | {by[b][0]['steps_per_ray']} | {by[a][0]['steps_per_ray']} | {med(b,'cpu_s'):.3f} | {med(a,'cpu_s'):.3f} | {med(a,'cpu_s')/med(b,'cpu_s'):.2f} | {med(b,'wall_s'):.3f} | {med(a,'wall_s'):.3f} |")
EOF
echo "bench: raw runs in $out-runs.csv" >&2
