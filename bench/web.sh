#!/usr/bin/env bash
# WebAssembly against native: the per-ray cost of the web entry point's
# tracing (bench/web_bench.c: cr_web_trace over every pixel, one thread),
# built natively (gcc -O3, the Release flags) and for wasm32 with clang's
# wasm32-wasi (-O2 as cmake/wasm.cmake builds the page's core, -O3, -O3
# -msimd128) and with Emscripten (emcc -O3), the wasm run in Node (V8, the
# engine of Chromium). Rounds interleave the variants; the table gives the
# median over rounds x runs of the CPU time per ray (process CPU time: a
# loaded machine inflates wall time, not this) and its ratio to native.
# Then the same for looking around (web_bench look: cr_web_reproject of a
# 1280x720 view from a 1024x512 sky, 20 frames).
# Usage: bench/web.sh [BUILD_DIR] [rounds] [W H]   (default build 3 320 180)
# The browser figures (workers, preview, refinement, looking around) are
# bench/web_page.py's.
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/lib.sh
build=${1:-build} rounds=${2:-3} W=${3:-320} H=${4:-180}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# the sources the page's core is built from (cmake/wasm.cmake), the same natively
hostsrc=$(sed -n '/^set(CURRAY_WASM_HOST_SOURCES/,/)/p' cmake/wasm.cmake |
          sed 's/set(CURRAY_WASM_HOST_SOURCES//; s/)//' | tr '\n' ' ')
src="bench/web_bench.c src/wasm/web.c $hostsrc"
flags="-std=c11 -D_POSIX_C_SOURCE=200809L -DCURRAY_VERSION=\"bench\" -Isrc"
flags="$flags -ffunction-sections -fdata-sections -Wl,--gc-sections"
wflags="$flags -isystem $build/wasm-include"
# shellcheck disable=SC2086
gcc -O3 -DNDEBUG $flags -isystem "$build/wasm-include" $src -lm -o "$out/native"
variants="native"
for v in "O2:-O2" "O3:-O3" "O3-simd:-O3 -msimd128 -mnontrapping-fptoint"; do
  name=${v%%:*} opt=${v#*:}
  # shellcheck disable=SC2086
  clang --target=wasm32-wasi $opt $wflags $src -o "$out/wasi-$name.wasm" && variants="$variants wasi-$name"
done
if command -v emcc >/dev/null; then
  # shellcheck disable=SC2086
  NODE_PATH=/usr/share/nodejs emcc -O3 -sALLOW_MEMORY_GROWTH=1 $wflags $src -o "$out/emcc-O3.js" 2>"$out/emcc.err" &&
    variants="$variants emcc-O3" || echo "emcc failed: $(head -1 "$out/emcc.err")"
fi
run() {
  case $1 in
    native) "$out/native" "$2" "$W" "$H" 3 ;;
    wasi-*) node --no-warnings tests/web/run_wasi.mjs "$out/$1.wasm" "$2" "$W" "$H" 3 ;;
    emcc-*) node --no-experimental-fetch "$out/$1.js" "$2" "$W" "$H" 3 ;;
  esac
}
echo "machine: $(bench_cores_model); load $(load3)"
echo "node $(node --version), $(clang --version | head -1), $(gcc --version | head -1)"
for scene in demo kerr; do
  for r in $(seq "$rounds"); do
    for v in $variants; do
      run "$v" "$scene" | awk -v v="$v" '/^run/ {print v, $4, $6, $8}' >> "$out/$scene.txt"
    done
  done
  echo
  echo "scene $scene ${W}x${H}, $rounds rounds x 3 runs; ns per ray (median), ratio to native (CPU)"
  printf '%-12s %10s %10s %8s\n' variant wall cpu ratio
  for v in $variants; do
    awk -v v="$v" '$1 == v {print $2, $3, $4}' "$out/$scene.txt" | sort -n -k2 |
      awk '{w[NR] = $1; c[NR] = $2} END {m = int((NR + 1) / 2); print w[m], c[m]}' > "$out/m"
    read -r wall cpu < "$out/m"
    [ "$v" = native ] && ncpu=$cpu nwall=$wall
    case $v in
      # Emscripten's process CPU clock is the wall clock: compare wall times
      emcc-*) printf '%-12s %10.0f %10s %8.2f (wall / native wall)\n' "$v" "$wall" - \
                "$(echo "$wall / $nwall" | bc -l)" ;;
      *) printf '%-12s %10.0f %10.0f %8.2f\n' "$v" "$wall" "$cpu" "$(echo "$cpu / $ncpu" | bc -l)" ;;
    esac
  done
  # the same image from every build (outcomes and colours summed)
  if [ "$(awk '{print $4}' "$out/$scene.txt" | sort -u | wc -l)" != 1 ]; then
    echo "the builds traced different images"; exit 1
  fi
done
# looking around: one 1280x720 reprojection from the 1024x512 sky, ms a frame
echo
echo "looking around, 1280x720 from 1024x512, 20 frames; ms a frame (median)"
printf '%-12s %10s %10s\n' variant wall cpu
for v in $variants; do
  run_look() {
    case $1 in
      native) "$out/native" look 1280 720 20 ;;
      wasi-*) node --no-warnings tests/web/run_wasi.mjs "$out/$1.wasm" look 1280 720 20 ;;
      emcc-*) node --no-experimental-fetch "$out/$1.js" look 1280 720 20 ;;
    esac
  }
  run_look "$v" | awk '/^frame/ {print $4, $6}' | sort -n -k2 |
    awk -v v="$v" '{w[NR] = $1; c[NR] = $2} END {m = int((NR + 1) / 2);
      printf "%-12s %10.1f %10s\n", v, w[m], v ~ /^emcc/ ? "-" : sprintf("%.1f", c[m])}'
done
echo "load after: $(load3)"
