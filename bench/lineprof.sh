#!/usr/bin/env bash
# bench/lineprof.sh: the line profile of a = 0.998 at 30 deg, curray -t s
# against kerrz lineprof side by side (kerrz-cli from PyPI, installed here
# into a virtual environment: a peer to measure against, never a dependency).
#
# Both: emissivity r^-3 (kerrz's default, checked: a FITS table of r^-3
# gives the same profile to 5e-5), disc from the ISCO (1.2369 M) to 20 M,
# photon flux normalised to unit integral over g. curray: observer at
# infinity, image plane 44 x 40 M at W x (10/11 W) pixels, 200 bins over
# g = 0.1 .. 2 (E0 = 1 keV). kerrz twice: its defaults, and converged
# (--ngstar 20000 --nrsteps 40000: the red wing moves by 0.2 % from the
# defaults to this, by < 0.05 % beyond). kerrz's output is a histogram: the
# value at grid point g_i is the mean over the bin [g_(i-1), g_i] (its first
# moment, sum f_i g_i dg, exceeds the converged mean g by dg/2 for every
# --ng from 250 to 4000), so it is integrated onto curray's bins as such.
# Reported: the peak g of each, the blue and red wing g (where the profile
# falls to 10 % of its peak, linear interpolation between bin centres,
# outermost), the mean g, their relative differences from the converged
# kerrz, the shape L1 distance sum |a - b| dg, and the wall time of each
# program (one run each).
# Usage: bench/lineprof.sh [--size W] [--threads N] [--work DIR]
# Environment: CURRAY_BIN (default build/curray), KERRZ_VENV.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
size=880 threads=2 work=${TMPDIR:-/tmp}/curray-lineprof
while [ $# -gt 0 ]; do
    case $1 in
    --size) size=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h | --help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "lineprof: unknown option '$1'" >&2; exit 2 ;;
    esac
done
curray=${CURRAY_BIN:-$here/../build/curray}
venv=${KERRZ_VENV:-$work/kerrz-venv}
mkdir -p "$work"
if [ ! -x "$venv/bin/kerrzcli" ]; then
    python3 -m venv "$venv" >&2
    "$venv/bin/pip" install -q kerrz-cli==0.4.1 numpy >&2
fi
h=$((size * 10 / 11))
cat >"$work/lp.yml" <<YML
metric: {m: 1, a: 0.998, q: 0}
observer: {r: inf, theta: 30, phi: 0, hextent: 44, vextent: 40}
accretion: {model: keplerian, radius: [20], temperature: 1e7}
spectrum:
  line: {energy_kev: 1, emissivity_index: 3, bins: 200, range: [0.1, 2]}
  continuum: {bins: 4}
YML
printf 'cpu:\n  threads: %s\n' "$threads" >"$work/cfg.yml"
kerrz=("$venv/bin/kerrzcli" lineprof --spin 0.998 --incl 30 --rin 1.2369 --rout 20
    --nthreads "$threads")
t0=$(date +%s.%N)
"$curray" -s "$work/lp.yml" -c "$work/cfg.yml" -o "$work/curray-$size" -x "$size" -y "$h" -t s -a true >&2
t1=$(date +%s.%N)
"${kerrz[@]}" -o "$work/kerrz.dat" >"$work/kerrz.log" 2>&1
t2=$(date +%s.%N)
"${kerrz[@]}" --ngstar 20000 --nrsteps 40000 -o "$work/kerrz-conv.dat" >"$work/kerrz-conv.log" 2>&1
t3=$(date +%s.%N)
"$venv/bin/python" - "$work/curray-$size/s_0.csv" "$work/kerrz.dat" "$work/kerrz-conv.dat" "$size" \
    "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)" "$(echo "$t3 - $t2" | bc)" <<'PY'
import sys, numpy as np
rows = [l.strip().split(',') for l in open(sys.argv[1]) if l.startswith('line,')]
lo = np.array([float(r[2]) for r in rows]); hi = np.array([float(r[3]) for r in rows])
c = np.array([float(r[7]) for r in rows])
edges = np.append(lo, hi[-1]); w = hi - lo; mid = 0.5 * (lo + hi)
def kerrz_on_bins(path):
    k = np.loadtxt(path, delimiter=',')
    g, f = k[:, 0], k[:, 1]
    ke = np.append(g[0] - (g[1] - g[0]), g)   # kerrz's bin i is [g_(i-1), g_i]
    ck = np.concatenate([[0], np.cumsum(f * np.diff(ke))])
    kb = np.diff(np.interp(edges, ke, ck)) / w
    return kb / (kb * w).sum()
def feats(f):
    p = np.argmax(f); lvl = 0.1 * f[p]
    above = np.nonzero(f >= lvl)[0]; i, j = above[0], above[-1]
    red = mid[i - 1] + (lvl - f[i - 1]) / (f[i] - f[i - 1]) * (mid[i] - mid[i - 1]) if i > 0 else mid[i]
    blue = mid[j] + (lvl - f[j]) / (f[j + 1] - f[j]) * (mid[j + 1] - mid[j]) if j + 1 < len(f) else mid[j]
    return mid[p], blue, red, (f * w * mid).sum()
kd, kc = kerrz_on_bins(sys.argv[2]), kerrz_on_bins(sys.argv[3])
fc, fd, fk = feats(c), feats(kd), feats(kc)
print("| quantity | curray (%s px wide) | kerrz 0.4.1 defaults | kerrz converged | curray vs converged |"
      % sys.argv[4])
print("|---|---|---|---|---|")
names = ("peak g", "blue wing g (10 %)", "red wing g (10 %)", "mean g")
for name, a, d, b in zip(names, fc, fd, fk):
    print("| %s | %.4f | %.4f | %.4f | %+.2f %% |" % (name, a, d, b, 100 * (a - b) / b))
print("| shape L1 distance to kerrz, sum abs(a - b) dg | | %.4f | %.4f | |"
      % ((np.abs(c - kd) * w).sum(), (np.abs(c - kc) * w).sum()))
print("| wall time (s) | %.1f | %.1f | %.1f | |" % tuple(float(x) for x in sys.argv[5:8]))
PY
