#!/usr/bin/env bash
# bench/number_format.sh: build and run bench/number_format.c (ns per double
# by method: %.17g, the shortest of %.15g/%.16g/%.17g that reads back, and
# cr_shortest_double), -O2 like the Release build. Timings only.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${TMPDIR:-/tmp}/curray-number-format.$$
trap 'rm -f "$out"' EXIT
${CC:-cc} -O2 -I"$here/../src" -o "$out" "$here/number_format.c" "$here/../src/base/shortest.c" -lm
"$out"
