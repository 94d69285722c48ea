#!/usr/bin/env bash
# bench/farleg.sh: the far leg of sky-image rays (bench/farleg.c): its share
# of the steps, what a looser tolerance on it saves and changes, and what
# the pieces of a closed form of it cost. Not a test.
#
#   (1) scenes/grid-sky-kerr.yml without its sky boundary (sky at infinity),
#       scenes/grid-sky-kerr.yml and scenes/listing-7.1.2-starry-sky.yml,
#       SIZE (160x120);
#   (2) farleg --pieces.
#
# Usage: bench/farleg.sh [--size WxH] [--out FILE]
# Environment: CURRAY_BENCH_BUILD (default build-bench): a configured build
# folder whose static libraries (curray_input, curray_output, curray_cpu,
# curray_png, curray_base) farleg links; they are built when missing.
# Output: the report on stdout and in FILE (default
# bench/results/farleg-<date>.txt).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
size=160x120 out=""
while [ $# -gt 0 ]; do
    case $1 in
    --size) size=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h | --help) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
[[ $size =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || die "--size needs WxH, got '$size'"
out=${out:-$BENCH_DIR/results/farleg-$(date -u +%Y%m%d-%H%M).txt}
B=$BUILD_DIR
if [ ! -f "$B/CMakeCache.txt" ]; then
    cmake -S "$REPO_DIR" -B "$B" -DCMAKE_BUILD_TYPE=Release -DCURRAY_TESTS=OFF >&2 || die "cmake failed"
fi
cmake --build "$B" -j2 --target curray_input curray_output curray_cpu >&2 || die "build failed"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
${CC:-cc} -O2 -std=c11 -I"$REPO_DIR/src" -I"$B/src" -I"$B" "$BENCH_DIR/farleg.c" -o "$work/farleg" \
    "$B/libcurray_output.a" "$B/libcurray_input.a" "$B/src/render/libcurray_cpu.a" -lyaml \
    "$B/libcurray_png.a" -lpng16 -lz -ldl "$B/libcurray_base.a" -lm -lpthread || die "cannot build farleg"
sed '/boundary:/d' "$REPO_DIR/scenes/grid-sky-kerr.yml" >"$work/grid-sky-kerr-infinity.yml"
cp "$REPO_DIR/scenes/sky_grid.png" "$work/"
w=${size%x*} h=${size#*x}
{
    echo "Machine: $(uname -m) $(bench_cores_model); load $(load3); $(git -C "$REPO_DIR" rev-parse --short HEAD)"
    echo "(grid-sky-kerr-infinity.yml: scenes/grid-sky-kerr.yml without its 'boundary:' line)"
    for sc in "$work/grid-sky-kerr-infinity.yml" "$REPO_DIR/scenes/grid-sky-kerr.yml" \
        "$REPO_DIR/scenes/listing-7.1.2-starry-sky.yml"; do
        (cd "$(dirname "$sc")" && "$work/farleg" "$sc" "$w" "$h")
    done
    "$work/farleg" --pieces
} | sed "s|$work/||; s|$REPO_DIR/||" | tee "$out"
