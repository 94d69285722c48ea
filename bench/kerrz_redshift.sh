#!/usr/bin/env bash
# bench/kerrz_redshift.sh: curray's Keplerian-disc shift g against kerrz's
# redshift map, pixel by pixel.
#
# Scene (bench/scenes/kerrz-keplerian.yml): a = 0.9, inclination 85 deg,
# thin disc of prograde circular orbits from r = 6 to 15 M, image plane
# +-20 M; curray's observer at infinity, kerrz's at r = 1e7 M (its default).
# kerrz: `kerrz image --map redshift,status --thin-disc rin:6,rout:15 --save`.
# Image planes: kerrz samples alpha_i = -A + 2A i/(N-1) with both ends, so
# curray's hextent = vextent = 2A N/(N-1) (bench_kerrz_extent, lib.sh) puts
# its pixel centres on kerrz's grid, and curray's row j is kerrz's beta row
# N-1-j (bench/compare_classes.py, bench/kerrz.sh). Pixels that both call
# disc are compared (bench/compare_redshift.py): the median |dg| must be at
# most 1e-3 (the issue's bound); the script exits 1 otherwise.
#
# Usage: bench/kerrz_redshift.sh [--size N] [--kerrz-version V] [--work DIR]
#   --size N   image width = height, a multiple of 40 (default 320)
# Environment: as bench/kerrz.sh (CURRAY_BIN, CURRAY_BENCH_BUILD, KERRZ_VENV).
set -euo pipefail
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

size=320 kver=0.4.1 work=""
while [ $# -gt 0 ]; do
    case $1 in
    --size) size=$2; shift 2 ;;
    --kerrz-version) kver=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h | --help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
    esac
done
[[ $size =~ ^[1-9][0-9]*$ ]] && [ $((size % 40)) = 0 ] ||
    die "--size must be a positive multiple of 40, got '$size'"
[ -z "$work" ] && work="$BUILD_DIR/kerrz-redshift-work"
mkdir -p "$work"
HALF=20
bench_ensure_binary cpu
bench_kerrz_setup "$kver"

scene="$work/kerrz-keplerian-$size.yml"
bench_kerrz_scene "$BENCH_DIR/scenes/kerrz-keplerian.yml" "$scene" "$HALF" "$size"
rm -rf "$work/curray"
cur=("$CURRAY" -s "$scene" -o "$work/curray" -x "$size" -y "$size" -t id -a true -q true --backend cpu)
kz=("$KERRZ" image --spin 0.9 --incl 85 --alpha "$HALF" --beta "$HALF" --resolution $((size / 40))
    --thin-disc rin:6,rout:15 --map redshift,status --save "$work/kerrz.fits" -o "$work/kerrz.pgm")
echo "+ ${cur[*]}" >&2
"${cur[@]}" >"$work/curray.log" 2>&1 || { cat "$work/curray.log" >&2; die "curray failed"; }
echo "+ ${kz[*]}" >&2
"${kz[@]}" >"$work/kerrz.log" 2>&1 || { cat "$work/kerrz.log" >&2; die "kerrz failed"; }
res=$(python3 "$BENCH_DIR/compare_redshift.py" "$work/curray/d_0.csv" "$work/kerrz.fits") ||
    die "the comparison failed"
echo "## curray g vs kerrz redshift: a = 0.9, 85 deg, Keplerian disc 6-15 M, ${size}x$size"
echo
echo "curray: $("$CURRAY" --version 2>&1 | head -1); kerrz: $kz_version (kerrz-cli $kver)"
echo
echo '```'
echo "${cur[*]}"
echo "${kz[*]}"
echo '```'
echo
echo "$res" | sed 's/^/- /'
med=$(echo "$res" | awk -F= '$1 == "median_abs_dg" {print $2}')
awk -v m="$med" 'BEGIN {exit !(m <= 1e-3)}' || die "median |dg| = $med exceeds 1e-3"
