#!/usr/bin/env python3
"""bench/compare_hits.py: the error distribution of a render's science
columns against a reference render of the same scene and size.

Usage: compare_hits.py TEST.csv REF.csv [--label TEXT]

Both are d_<k>.csv files (docs/outputs.md). Over the pixels that hit the
disc or a sphere in both (same outcome), prints one markdown table row per
column: hit_r (error relative to the reference's hit_r), hit_phi (absolute,
rad, wrapped to [-pi, pi)), redshift (relative) and, when both files have
it, delay (relative to max(1, |delay|)): median, 99th percentile and
maximum, and the pixel with the maximum. Pixels whose outcome differs are
counted. Standard library only.
"""
import csv
import math
import sys


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {(int(r["x"]), int(r["y"])): r for r in rows}


def pct(v, p):
    if not v:
        return float("nan")
    s = sorted(v)
    k = min(len(s) - 1, max(0, int(math.ceil(p / 100.0 * len(s))) - 1))
    return s[k]


def main():
    args = sys.argv[1:]
    label = ""
    if "--label" in args:
        i = args.index("--label")
        label = args[i + 1]
        del args[i : i + 2]
    if len(args) != 2:
        sys.stderr.write(__doc__)
        return 2
    a, b = load(args[0]), load(args[1])
    diff = 0
    cols = {"hit_r": [], "hit_phi": [], "redshift": [], "delay": []}
    for key, ra in a.items():
        rb = b.get(key)
        if rb is None:
            continue
        if ra["outcome"] != rb["outcome"]:
            diff += 1
            continue
        if ra["outcome"] not in ("disc", "sphere"):
            continue
        ref = float(rb["hit_r"])
        cols["hit_r"].append((abs(float(ra["hit_r"]) - ref) / ref, key))
        d = float(ra["hit_phi"]) - float(rb["hit_phi"])
        d = (d + math.pi) % (2.0 * math.pi) - math.pi
        cols["hit_phi"].append((abs(d), key))
        g = float(rb["redshift"])
        if g > 0.0:
            cols["redshift"].append((abs(float(ra["redshift"]) - g) / g, key))
        if "delay" in ra and "delay" in rb and ra["delay"] not in ("", "nan") and rb["delay"] not in ("", "nan"):
            t = float(rb["delay"])
            cols["delay"].append((abs(float(ra["delay"]) - t) / max(1.0, abs(t)), key))
    n = len(cols["hit_r"])
    for name, v in cols.items():
        if not v:
            continue
        e = [x for x, _ in v]
        worst = max(v)
        print("| %s | %s | %d | %.2e | %.2e | %.2e | (%d,%d) | %d |"
              % (label, name, n, pct(e, 50), pct(e, 99), worst[0], worst[1][0], worst[1][1], diff))
    return 0


if __name__ == "__main__":
    sys.exit(main())
