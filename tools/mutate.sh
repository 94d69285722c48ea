#!/usr/bin/env bash
# Mutation testing for curray (not part of CI).
#
# Applies the mutations of a list (default tools/mutations.txt; its header
# describes the format) one at a time to a private copy of the source tree,
# rebuilds it (CPU only) and runs the test suite; a mutation is "killed" when
# a test fails (or the suite times out) and "survived" when every test
# passes. Each mutated file is restored from a copy of its original before
# the next mutation. The working tree is never touched: the copy is made once,
# at the start, of every tracked and untracked-but-not-ignored file
# (git ls-files), so other work going on in the checkout does not matter.
# The copy's files get the current time (tar -m), so the first build
# recompiles everything: objects left by an interrupted run's mutant are
# never taken for up to date.
#
# Usage: tools/mutate.sh [mutations-file]
# Environment:
#   MUTATE_DIR      work folder (default: build-mutate in the repository root)
#   MUTATE_JOBS     parallel build and test jobs (default 2)
#   MUTATE_TIMEOUT  seconds for one whole ctest run (default 1200)
#   MUTATE_TEST_TIMEOUT  seconds for one test (ctest --timeout, default 300)
#   MUTATE_QUICK    regex of the tests run first, stopping at the first
#                   failure; the rest of the suite runs only when they all
#                   pass (default: the fast physics, e2e and io tests)
#   MUTATE_EXCLUDE  regex of tests left out (default: none); a survivor of a
#                   run with exclusions must be rerun without them
#   MUTATE_ONLY     regex: run only the mutations whose name matches
# Needs bash, git, cmake >= 3.20, ctest, python3 (for the literal text
# replacement) and timeout. Output: a line per mutation, a summary, and the
# table MUTATE_DIR/results.tsv (name, file, result, failing tests, seconds);
# the ctest log of each mutation is kept in MUTATE_DIR/logs/<name>.log.
set -u

root=$(git rev-parse --show-toplevel) || exit 2
list=${1:-$root/tools/mutations.txt}
work=${MUTATE_DIR:-$root/build-mutate}
jobs=${MUTATE_JOBS:-2}
suite_timeout=${MUTATE_TIMEOUT:-1200}
test_timeout=${MUTATE_TEST_TIMEOUT:-300}
quick=${MUTATE_QUICK:-'^(test_patterns|test_scenes_e2e|test_metric|test_geodesic|test_shadow|test_render|test_axis|test_scene|test_output|test_sysconfig|test_core_cxx)$'}
exclude=${MUTATE_EXCLUDE:-}
only=${MUTATE_ONLY:-}

case $list in /*) ;; *) list=$PWD/$list ;; esac
[ -r "$list" ] || { echo "mutate: cannot read $list" >&2; exit 2; }
for tool in cmake ctest python3 timeout; do
    command -v $tool >/dev/null || { echo "mutate: $tool not found" >&2; exit 2; }
done

tree=$work/tree      # the private copy of the sources
build=$work/build    # its CPU-only build
orig=$work/orig      # the original of the file being mutated
logs=$work/logs
results=$work/results.tsv
mkdir -p "$work" "$logs" || exit 2

# --- the private copy ---------------------------------------------------------
rm -rf "$tree" "$orig"
mkdir -p "$tree" "$orig"
(cd "$root" && git ls-files -co --exclude-standard -z |
    tar --null --ignore-failed-read -T - -cf - 2>/dev/null) | tar -C "$tree" -m -xf - || {
    echo "mutate: copying the sources failed" >&2
    exit 2
}
echo "mutate: sources copied to $tree ($(cd "$root" && git rev-parse --short HEAD), with the working tree's changes)"

# --- restoring ----------------------------------------------------------------
current=""   # file (relative) currently mutated, "" when none
restore() {
    if [ -n "$current" ]; then
        # a plain cp: the restored file is newer than the mutant's objects,
        # so the next build recompiles what depends on it
        cp "$orig/$current" "$tree/$current" && cmp -s "$orig/$current" "$tree/$current" || {
            echo "mutate: could not restore $current" >&2
            exit 3
        }
        current=""
    fi
}
trap 'restore; exit 130' INT TERM
trap 'restore' EXIT

# Literal replacement, the original exactly once. Exit 0 applied, 4 n/a.
apply() { # file original replacement
    python3 - "$1" "$2" "$3" <<'EOF'
import sys
def unescape(s):
    out, i = [], 0
    while i < len(s):
        if s[i] == '\\' and i + 1 < len(s) and s[i + 1] in 'n\\':
            out.append('\n' if s[i + 1] == 'n' else '\\')
            i += 2
        else:
            out.append(s[i])
            i += 1
    return ''.join(out)
path, old, new = sys.argv[1], unescape(sys.argv[2]), unescape(sys.argv[3])
text = open(path, encoding='utf-8').read()
n = text.count(old)
if n != 1:
    print('original text found %d times' % n)
    sys.exit(4)
open(path, 'w', encoding='utf-8').write(text.replace(old, new, 1))
EOF
}

# Run ctest with a selection; prints the failing tests; returns ctest's status
# (124 on the suite timeout).
run_ctest() { # log args...
    local log=$1
    shift
    (cd "$build" && timeout "$suite_timeout" ctest -j "$jobs" --timeout "$test_timeout" \
        --output-on-failure "$@") </dev/null >>"$log" 2>&1
}

failed_tests() { # log
    sed -n '/The following tests FAILED:/,$p' "$1" | sed -n 's/^[[:space:]]*[0-9]* - \([^ ]*\).*/\1/p' |
        sort -u | tr '\n' ' '
}

# The whole suite (quick part first, stopping at the first failure).
# Sets verdict and tests.
suite() { # log
    local log=$1 ex rc
    : >"$log"
    ex=$exclude
    if [ -n "$ex" ]; then
        run_ctest "$log" -R "$quick" -E "$ex" --stop-on-failure
    else
        run_ctest "$log" -R "$quick" --stop-on-failure
    fi
    rc=$?
    if [ $rc -eq 0 ]; then
        if [ -n "$ex" ]; then ex="$quick|$ex"; else ex=$quick; fi
        run_ctest "$log" -E "$ex" --stop-on-failure
        rc=$?
    fi
    tests=$(failed_tests "$log")
    if [ $rc -eq 0 ]; then
        verdict=survived
    elif [ $rc -eq 124 ]; then
        verdict=killed
        tests="(suite timeout) $tests"
    else
        verdict=killed
    fi
}

# --- baseline -------------------------------------------------------------------
echo "mutate: configuring and building $build"
cmake -S "$tree" -B "$build" -DCURRAY_CUDA=OFF -DCMAKE_BUILD_TYPE=Release >"$logs/_configure.log" 2>&1 ||
    { echo "mutate: cmake failed, see $logs/_configure.log" >&2; exit 2; }
cmake --build "$build" -j "$jobs" >"$logs/_build.log" 2>&1 ||
    { echo "mutate: the unmutated tree does not build, see $logs/_build.log" >&2; exit 2; }
t0=$(date +%s)
suite "$logs/_baseline.log"
if [ "$verdict" != survived ]; then
    echo "mutate: the unmutated tree fails tests ($tests), see $logs/_baseline.log" >&2
    exit 2
fi
echo "mutate: baseline passes ($(($(date +%s) - t0)) s)${exclude:+, tests left out: $exclude}"

# --- the mutations --------------------------------------------------------------
printf 'name\tfile\tresult\tfailing tests\tseconds\n' >"$results"
n_killed=0 n_survived=0 n_na=0 n_build=0
survivors=""
# the whole list is read before the first test runs: a test that reads its
# standard input or an inherited descriptor (ctest passes them on) must not
# move through the rest of the list (a shared file offset once skipped and
# repeated lines, seen as "bad line" for a well-formed one)
mapfile -t mutation_lines <"$list"
for line in "${mutation_lines[@]}"; do
    case $line in '' | '#'*) continue ;; esac
    tabs=${line//[!$'\t']/}
    IFS=$'\t' read -r name file old new <<<"$line"
    if [ ${#tabs} -ne 3 ] || [ -z "$file" ] || [ -z "$old" ]; then
        echo "mutate: bad line (need 4 TAB-separated fields): $line" >&2
        continue
    fi
    if [ -n "$only" ] && ! [[ $name =~ $only ]]; then
        continue
    fi
    t0=$(date +%s)
    log=$logs/$name.log
    if [ ! -f "$tree/$file" ]; then
        why="no file $file"
        verdict=n/a
    else
        mkdir -p "$orig/$(dirname "$file")"
        cp "$tree/$file" "$orig/$file"
        current=$file
        if why=$(apply "$tree/$file" "$old" "$new"); then
            if cmake --build "$build" -j "$jobs" >"$log" 2>&1; then
                suite "$log"
                why=$tests
            else
                verdict=build-error
                why="does not compile"
            fi
        else
            verdict=n/a
            current="" # nothing was changed
        fi
        restore
    fi
    dt=$(($(date +%s) - t0))
    case $verdict in
    killed) n_killed=$((n_killed + 1)) ;;
    survived) n_survived=$((n_survived + 1)); survivors="$survivors $name" ;;
    build-error) n_build=$((n_build + 1)) ;;
    *) n_na=$((n_na + 1)) ;;
    esac
    printf '%-30s %-12s %4ds  %s\n' "$name" "$verdict" "$dt" "$why"
    printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$file" "$verdict" "$why" "$dt" >>"$results"
done

# leave the build of the unmutated tree behind
cmake --build "$build" -j "$jobs" >"$logs/_build_final.log" 2>&1

echo
echo "mutate: $n_killed killed, $n_survived survived, $n_build did not compile, $n_na not applicable"
[ -n "$survivors" ] && echo "mutate: survivors:$survivors"
[ -n "$exclude" ] && [ -n "$survivors" ] &&
    echo "mutate: tests were left out ($exclude): rerun the survivors without MUTATE_EXCLUDE"
echo "mutate: table in $results, logs in $logs"
exit 0
