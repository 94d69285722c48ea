#!/usr/bin/env python3
"""Per-pixel comparison of curray's g with kerrz's redshift map.

usage: compare_redshift.py CURRAY_CSV KERRZ_FITS

CURRAY_CSV: curray's d_0.csv of a Keplerian disc (redshift column = g).
KERRZ_FITS: the table of `kerrz image --map redshift,status --save T.fits`.
The two image planes are matched as in bench/compare_classes.py (whose
readers are used): curray pixel (i, j) is kerrz's table row (H-1-j)*W + i,
with curray's hextent = vextent = 2A W/(W-1). Pixels that both call disc
(curray outcome disc, kerrz status 4) are compared. Prints key=value lines:
n_both_disc, median/p95/max |dg|, the pixel of the largest difference and
how many disc pixels only one of them has.
"""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare_classes as cc  # noqa: E402


def main():
    if len(sys.argv) != 3:
        cc.die("usage: compare_redshift.py CURRAY_CSV KERRZ_FITS")
    cur = {}
    with open(sys.argv[1]) as f:
        head = f.readline().strip().split(",")
        iz, io = head.index("redshift"), head.index("outcome")
        for line in f:
            p = line.rstrip("\n").split(",")
            cur[(int(p[0]), int(p[1]))] = (p[io], float(p[iz]))
    cards, names, rows = cc.read_fits_table(sys.argv[2])
    for need in ("redshift", "status"):
        if need not in names:
            cc.die("%s: no column %s; render with --map redshift,status" % (sys.argv[2], need))
    iz, ist = names.index("redshift"), names.index("status")
    W = len(set(r[names.index("ax_alpha")] for r in rows))
    H = len(rows) // W
    if (W, H) != (max(x for x, _ in cur) + 1, max(y for _, y in cur) + 1):
        cc.die("the images differ in size: kerrz %dx%d" % (W, H))
    diffs, only_c, only_k = [], 0, 0
    for k, r in enumerate(rows):
        i, j = k % W, H - 1 - k // W
        o, g = cur[(i, j)]
        kd = cc.KERRZ_MAP.get(int(r[ist])) == "disc"
        if o == "disc" and kd:
            diffs.append((abs(g - r[iz]), i, j, g, r[iz]))
        else:
            only_c += o == "disc"
            only_k += kd
    if not diffs:
        cc.die("no pixel is disc in both images")
    d = sorted(x[0] for x in diffs)
    worst = max(diffs)
    print("n_both_disc=%d" % len(diffs))
    print("median_abs_dg=%.3g" % statistics.median(d))
    print("p95_abs_dg=%.3g" % d[int(0.95 * (len(d) - 1))])
    print("max_abs_dg=%.3g" % worst[0])
    print("max_at=pixel (%d, %d): curray g %.6f, kerrz %.6f" % worst[1:])
    print("disc_only_curray=%d" % only_c)
    print("disc_only_kerrz=%d" % only_k)


if __name__ == "__main__":
    main()
