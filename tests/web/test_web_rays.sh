#!/bin/sh
# test_web_rays: 100 random scenes x 100 random rays (10,000 rays, plus the
# scenes the evaluation refuses, with their messages) through the web entry
# point, natively and as wasm32 under Node's WASI; compare_rays.py compares.
# Usage: test_web_rays.sh NATIVE_EXE RAYS_WASM NODE PYTHON TESTS_WEB_DIR
set -eu
native=$1 wasm=$2 node=$3 python=$4 dir=$5
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$native" 100 100 1 > "$out/native.txt"
"$node" --no-warnings "$dir/run_wasi.mjs" "$wasm" 100 100 1 > "$out/wasm.txt"
"$python" "$dir/compare_rays.py" "$out/native.txt" "$out/wasm.txt" 10000
