#!/usr/bin/env bash
# bench/startup.sh: what starting curray costs, two binaries side by side
# (the output modules: a run that writes no video or FITS maps neither FFmpeg
# nor cfitsio; src/output/module.h).
#
# Usage: bench/startup.sh OLD_CURRAY NEW_CURRAY [RUNS] [WIDTH HEIGHT] [SCENE]
#   defaults: 20 runs, 160 x 120, scenes/demo.yml
#
# Per round, in this order: OLD --version, NEW --version (start-up and exit
# only), OLD -t c, NEW -t c (one small colour frame, 2 threads as curray
# chooses on this machine), NEW -t cf (the same frame and its FITS file: the
# module loaded). Each run is timed by bench/timecmd.py (wall time, user + sys
# CPU from wait4). Prints the median of RUNS rounds per case and the number
# of shared objects each binary maps at start (ldd). Timings only; the tests
# are tests/cli/test_modules.sh. Say in BENCHMARKS.md how loaded the machine
# was (uptime is printed before and after).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
[ $# -ge 2 ] || { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
old=$(realpath "$1") new=$(realpath "$2")
runs=${3:-20} w=${4:-160} h=${5:-120}
scene=$(realpath "${6:-$root/scenes/demo.yml}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$(dirname "$scene")"
cases="old_version new_version old_c new_c new_cf"

echo "load before: $(uptime)"
for r in $(seq 1 "$runs"); do
    for c in $cases; do
        bin=$old
        [ "${c%%_*}" = new ] && bin=$new
        t=${c#*_}
        rm -rf "$tmp/o"
        if [ "$t" = version ]; then
            python3 "$here/timecmd.py" "$tmp/$c.$r" -- "$bin" --version
        else
            python3 "$here/timecmd.py" "$tmp/$c.$r" -- \
                "$bin" -s "$scene" -o "$tmp/o" -x "$w" -y "$h" -t "$t" -a true -q true
        fi
    done
done
echo "load after:  $(uptime)"
echo "shared objects at start (ldd): OLD $(ldd "$old" | wc -l), NEW $(ldd "$new" | wc -l)"

python3 - "$tmp" "$runs" "$w" "$h" <<'PY'
import statistics, sys
tmp, runs, w, h = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
names = {"old_version": "OLD --version", "new_version": "NEW --version",
         "old_c": "OLD -t c %sx%s" % (w, h), "new_c": "NEW -t c %sx%s" % (w, h),
         "new_cf": "NEW -t cf %sx%s (FITS module loaded)" % (w, h)}
med = {}
print("| case | wall s (median of %d) | CPU s (user+sys, median) |" % runs)
print("| --- | ---: | ---: |")
for c, name in names.items():
    rows = [open("%s/%s.%d" % (tmp, c, r)).read().split() for r in range(1, runs + 1)]
    med[c] = (statistics.median(float(x[0]) for x in rows),
              statistics.median(float(x[1]) + float(x[2]) for x in rows))
    print("| %s | %.4f | %.4f |" % (name, med[c][0], med[c][1]))
print()
print("start-up CPU saved (--version, OLD - NEW): %.4f s; -t c frame NEW/OLD CPU %.2f, wall %.2f"
      % (med["old_version"][1] - med["new_version"][1], med["new_c"][1] / med["old_c"][1],
         med["new_c"][0] / med["old_c"][0]))
PY
