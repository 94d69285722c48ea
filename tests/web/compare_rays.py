#!/usr/bin/env python3
"""Compare two outputs of web_rays (native, wasm): the same scenes refused
with the same messages, every ray's outcome identical, redshift, hit radius,
hit azimuth and bolometric brightness within REL relative (absolute below
1), colours identical. Prints the first mismatches and the worst
difference; exits 1 on any mismatch or when fewer than MIN_RAYS rays were
compared.

Usage: compare_rays.py NATIVE.txt WASM.txt [min_rays]
"""
import sys

REL = 1e-12


def load(path):
    with open(path) as f:
        return [line.rstrip("\n") for line in f if line.strip()]


def main():
    a, b = load(sys.argv[1]), load(sys.argv[2])
    min_rays = int(sys.argv[3]) if len(sys.argv) > 3 else 10000
    bad = []
    worst = (0.0, "")
    rays = 0
    if len(a) != len(b):
        bad.append("line counts differ: %d native, %d wasm" % (len(a), len(b)))
    for n, (x, y) in enumerate(zip(a, b), 1):
        if x[0] != "R" or y[0] != "R":
            if x != y:
                bad.append("line %d:\n  native %s\n  wasm   %s" % (n, x, y))
            continue
        fx, fy = x.split(), y.split()
        rays += 1
        if fx[1:5] != fy[1:5] or fx[9] != fy[9]:
            bad.append("line %d (outcome or colour):\n  native %s\n  wasm   %s" % (n, x, y))
            continue
        for k, name in zip(range(5, 9), ("redshift", "hit_r", "hit_phi", "bolo")):
            u, v = float(fx[k]), float(fy[k])
            d = abs(u - v) / max(1.0, abs(u))
            if d > worst[0]:
                worst = (d, "line %d %s: %r vs %r" % (n, name, u, v))
            if not d <= REL:
                bad.append("line %d (%s, relative difference %.3g):\n  native %s\n  wasm   %s"
                           % (n, name, d, x, y))
    print("compared %d rays; worst relative difference %.3g %s" % (rays, worst[0], worst[1]))
    for m in bad[:10]:
        print("MISMATCH " + m)
    if bad:
        print("%d mismatches" % len(bad))
        return 1
    if rays < min_rays:
        print("only %d rays compared, expected at least %d" % (rays, min_rays))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
