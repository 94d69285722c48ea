#!/usr/bin/env python3
"""Do two d_<k>.csv files hold the same values?

Usage: tools/csv-values-equal.py A.csv B.csv [more pairs...]

The CSV's number text changed from %.17g to the shortest form that reads
back exactly (src/base/shortest.h), so two renders of the same frame by a
version before and one after differ in bytes but must not differ in value.
This compares line by line: the same header, the same number of rows, every
field that is not a floating-point column equal as text, and every
floating-point column (redshift, err_mean, err_std, hit_r, hit_phi,
bolometric) the identical double, bit for bit (Python's float() rounds
correctly; -0 and 0 differ; NaN equals NaN). Prints the first differences
and exits 1 on any, 0 when every pair holds the same values.
"""
import math
import struct
import sys

FLOAT_COLUMNS = {"redshift", "err_mean", "err_std", "hit_r", "hit_phi", "bolometric"}


def bits(text):
    v = float(text)
    if math.isnan(v):
        return "nan"
    return struct.pack("<d", v)


def compare(a_path, b_path):
    bad = 0
    with open(a_path) as fa, open(b_path) as fb:
        ha, hb = fa.readline(), fb.readline()
        if ha != hb:
            print("%s, %s: headers differ" % (a_path, b_path))
            return 1
        cols = ha.rstrip("\n").split(",")
        is_float = [c in FLOAT_COLUMNS for c in cols]
        n = 0
        for la, lb in zip(fa, fb):
            n += 1
            va, vb = la.rstrip("\n").split(","), lb.rstrip("\n").split(",")
            if len(va) != len(vb) or len(va) != len(cols):
                print("%s line %d: field counts %d, %d" % (a_path, n + 1, len(va), len(vb)))
                bad += 1
            else:
                for c, x, y, f in zip(cols, va, vb, is_float):
                    if (bits(x) != bits(y)) if f else (x != y):
                        if bad < 10:
                            print("%s line %d, %s: %s vs %s" % (a_path, n + 1, c, x, y))
                        bad += 1
        if fa.readline() or fb.readline():
            print("%s, %s: row counts differ" % (a_path, b_path))
            bad += 1
    print("%s vs %s: %d rows, %d differences" % (a_path, b_path, n, bad))
    return 1 if bad else 0


def main():
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        return 2
    rc = 0
    for i in range(0, len(args), 2):
        rc |= compare(args[i], args[i + 1])
    return rc


if __name__ == "__main__":
    sys.exit(main())
