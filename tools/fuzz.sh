#!/usr/bin/env bash
# Run curray's libFuzzer targets (tests/fuzz) for a while each.
#
#   tools/fuzz.sh [SECONDS per target, default 60] [BUILD dir, default build-fuzz] [TARGET...]
#
# Builds the targets when needed (clang; CC=clang cmake -DCURRAY_FUZZ=ON),
# seeds each target with the shipped scenes or configurations (fuzz_cli:
# its regressions alone), its regressions (tests/fuzz/regressions/<target>)
# and its dictionary (tests/fuzz/<target>.dict, else tests/fuzz/yaml.dict),
# and keeps the corpus it grows in BUILD/corpus/<target> for the next run.
# The fuzzers run in BUILD/fuzz-work, where the sky images the seed scenes
# name (sky.png, sky_grid.png) are tiny, so that loading them stays cheap.
# Prints libFuzzer's final statistics per target. Exits 1 when a target
# crashed, leaked, timed out or broke a contract: the input is saved as
# BUILD/crash-<target>-* (or leak-, timeout-); fix the bug and add the input to
# tests/fuzz/regressions/<target>/, which every ordinary build replays.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
SECONDS_EACH=${1:-60}
BUILD=${2:-build-fuzz}
shift $(($# > 2 ? 2 : $#))
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(scene sysconfig cli)

if [ ! -f "$BUILD/CMakeCache.txt" ]; then
    CC=clang cmake -S . -B "$BUILD" -DCURRAY_FUZZ=ON -DCURRAY_CUDA=OFF -DCURRAY_TESTS=OFF \
        -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build "$BUILD" -j "$(nproc 2>/dev/null || echo 2)" \
    --target curray-skygen $(printf 'fuzz_%s ' "${TARGETS[@]}") >/dev/null
BUILD=$(cd "$BUILD" && pwd)

WORKDIR=$BUILD/fuzz-work
SEEDS=$BUILD/fuzz-seeds
rm -rf "$WORKDIR" "$SEEDS"
mkdir -p "$WORKDIR" "$SEEDS/scene" "$SEEDS/sysconfig" "$SEEDS/cli"
"$BUILD/tools/curray-skygen" grid "$WORKDIR/sky.png" 16 8 >/dev/null
cp "$WORKDIR/sky.png" "$WORKDIR/sky_grid.png"
cp scenes/*.yml tests/data/scene*.yml "$SEEDS/scene/"
cp tests/data/config*.yml "$SEEDS/sysconfig/"

status=0
for t in "${TARGETS[@]}"; do
    mkdir -p "$BUILD/corpus/$t" "tests/fuzz/regressions/$t"
    echo "== fuzz_$t: ${SECONDS_EACH} s"
    dict=$ROOT/tests/fuzz/$t.dict
    [ -f "$dict" ] || dict=$ROOT/tests/fuzz/yaml.dict
    log=$BUILD/fuzz-$t.log
    # -timeout: one input taking 10 s is a hang; -rss_limit_mb: a runaway
    # allocation is a finding too.
    if (cd "$WORKDIR" && "$BUILD/tests/fuzz/fuzz_$t" -max_total_time="$SECONDS_EACH" \
        -dict="$dict" -max_len=8192 -timeout=10 -rss_limit_mb=2048 \
        -print_final_stats=1 -artifact_prefix="$BUILD/" \
        "$BUILD/corpus/$t" "$ROOT/tests/fuzz/regressions/$t" "$SEEDS/$t") >"$log" 2>&1; then
        :
    else
        status=1
        echo "fuzz_$t FOUND A PROBLEM (see $log):"
        grep -E "ERROR|SUMMARY|contract broken|Test unit written" "$log" | head -20 || true
    fi
    grep -E "^#[0-9]+[[:space:]]+DONE|^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" "$log" || true
    echo "corpus: $(ls "$BUILD/corpus/$t" | wc -l) inputs in $BUILD/corpus/$t"
done
exit $status
