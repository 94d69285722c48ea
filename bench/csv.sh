#!/usr/bin/env bash
# bench/csv.sh: what writing d_<k>.csv costs, two curray binaries side by side.
#
# Usage: bench/csv.sh OLD_CURRAY NEW_CURRAY [RUNS] [WIDTH HEIGHT] [SCENE]
#   defaults: 5 runs, 1280 x 960, scenes/demo.yml
#
# Per round, in this order: OLD -t d, NEW -t d, NEW -t i (the same frame
# traced, no CSV: the tracing's own cost). Each run is timed by
# bench/timecmd.py (wall time, user + sys CPU from wait4). Prints the median
# of RUNS rounds per case, the CSV's size, and the cost of the CSV itself
# (-t d minus -t i, by wall and by CPU time) for both binaries, with the
# ratio NEW/OLD. Timings only; the exactness tests are tests/test_shortest.c
# and tests/test_output.c. Say in BENCHMARKS.md how loaded the machine was
# (uptime is printed before and after).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
[ $# -ge 2 ] || { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
old=$(realpath "$1") new=$(realpath "$2")
runs=${3:-5} w=${4:-1280} h=${5:-960}
scene=$(realpath "${6:-$root/scenes/demo.yml}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$(dirname "$scene")"

echo "load before: $(uptime)"
for r in $(seq 1 "$runs"); do
    for c in old_d new_d new_i; do
        bin=$old
        [ "${c%_*}" = new ] && bin=$new
        t=${c#*_}
        rm -rf "$tmp/o"
        python3 "$here/timecmd.py" "$tmp/$c.$r" -- \
            "$bin" -s "$scene" -o "$tmp/o" -x "$w" -y "$h" -t "$t" -a true -q true
        [ "$t" = d ] && stat -c %s "$tmp/o/d_0.csv" > "$tmp/$c.size"
    done
done
echo "load after:  $(uptime)"

python3 - "$tmp" "$runs" <<'EOF'
import statistics, sys
tmp, runs = sys.argv[1], int(sys.argv[2])
med = {}
for c in ("old_d", "new_d", "new_i"):
    rows = [open("%s/%s.%d" % (tmp, c, r)).read().split() for r in range(1, runs + 1)]
    med[c] = (statistics.median(float(x[0]) for x in rows),
              statistics.median(float(x[1]) + float(x[2]) for x in rows))
size = {c: int(open("%s/%s.size" % (tmp, c)).read()) for c in ("old_d", "new_d")}
print("| case | wall s (median of %d) | CPU s (user+sys) | CSV bytes |" % runs)
print("| --- | ---: | ---: | ---: |")
for c, name in (("old_d", "OLD -t d"), ("new_d", "NEW -t d"), ("new_i", "NEW -t i (no CSV)")):
    print("| %s | %.3f | %.3f | %s |" % (name, med[c][0], med[c][1],
                                        "{:,}".format(size[c]) if c in size else "-"))
ow, oc = med["old_d"][0] - med["new_i"][0], med["old_d"][1] - med["new_i"][1]
nw, nc = med["new_d"][0] - med["new_i"][0], med["new_d"][1] - med["new_i"][1]
print()
print("CSV cost (-t d minus -t i): OLD wall %.3f s, CPU %.3f s; NEW wall %.3f s, CPU %.3f s; "
      "NEW/OLD wall %.2f, CPU %.2f; size NEW/OLD %.3f"
      % (ow, oc, nw, nc, nw / ow if ow else float("nan"), nc / oc if oc else float("nan"),
         size["new_d"] / size["old_d"]))
EOF
