#!/usr/bin/env python3
"""bench/compare_classes.py: compare two images pixel by pixel by class.

Usage:
  compare_classes.py [options] A B
    A, B          curray:PATH (a d_<k>.csv of `curray -t d`) or
                  kerrz:PATH  (the FITS table that `kerrz image --map status
                  --save PATH` writes)
  --name-a N, --name-b N   names in the report (default: the kinds)
  --hextent W --vextent H  full width and height in M of curray's image plane
                  (observer at infinity). With a kerrz input, every kerrz
                  sample (ax_alpha, ax_beta) is checked against the centre of
                  the curray pixel it is compared with; the largest offset is
                  reported, and one larger than --max-offset (in M, default
                  1e-4; kerrz stores float32) is an error.
  --bardeen SPIN,INCL[,Q]  (observer at infinity; needs --hextent) judge
                  each disagreement that involves "hole": from the pixel's
                  Bardeen constants (lambda = -alpha sin i, eta = beta^2 +
                  (alpha^2 - a^2) cos^2 i) the ray is captured iff the radial
                  potential R(r) has no root outside the horizon. A captured
                  ray cannot be sky, one with a turning point cannot be hole:
                  the report counts which image each such pixel proves wrong,
                  the agreement once the side proven wrong is corrected, and
                  how many of the other disagreements lie on edges.
  --png PATH      write a picture of the disagreements, if any (white: agree on sky,
                  grey: agree on disc, black: agree on hole; red: disagree on an
                  edge, blue: disagree away from edges; with --bardeen, magenta:
                  B proven wrong, green: A proven wrong)
  --markdown      print the summary as a markdown table as well
  --prefix P      prefix of the key=value lines (default "")

Classes: disc, hole, sky, other. curray's outcome column: horizon -> hole,
disc -> disc, sky -> sky, sphere/error/limit -> other. kerrz's status mapper
(found by rendering and tracing single rays, see bench/kerrz.sh): 2 -> hole
(event_horizon), 3 -> sky (infinity), 4 -> disc; anything else -> other.

Image-plane mapping (bench/kerrz.sh explains it): curray pixel (i, j), i left
to right, j top to bottom, is kerrz table row (H-1-j)*W + i: kerrz's table is
row-major with alpha fastest and beta growing from the first row, so its
first row is the bottom of the image. Both put +alpha right (+phi) and +beta
up (towards the +z pole); kerrz samples alpha_i = -A + 2A i/(W-1) (the end
points included), so curray's hextent must be 2A W/(W-1).

A disagreeing pixel is "on an edge" when, in either image, one of its 8
neighbours has a class other than its own in that image. "Interior" ones are
the rest; for those, the report also says whether the 5x5 block around the
pixel is of one class in A (deep inside a region of A).

Prints key=value lines (machine-readable) and, with --markdown, a table.
Standard library only.
"""
import argparse
import struct
import sys
import zlib

CLASSES = ("disc", "hole", "sky", "other")
CURRAY_MAP = {"horizon": "hole", "disc": "disc", "sky": "sky"}
KERRZ_MAP = {2: "hole", 3: "sky", 4: "disc"}


def die(msg):
    sys.stderr.write("compare_classes.py: %s\n" % msg)
    sys.exit(1)


def read_curray(path):
    """Returns (W, H, classes[j][i], counts of raw outcomes)."""
    pix = {}
    raw = {}
    W = H = 0
    try:
        f = open(path)
    except OSError as e:
        die("cannot read %s: %s" % (path, e))
    with f:
        head = f.readline().strip().split(",")
        # outcome is column 10; later columns (hit_r, hit_phi) may follow
        if len(head) < 10 or head[0] != "x" or head[1] != "y" or head[9] != "outcome":
            die("%s: not a curray d_<k>.csv (header %r)" % (path, ",".join(head)))
        for line in f:
            p = line.rstrip("\n").split(",")
            x, y, o = int(p[0]), int(p[1]), p[9]
            raw[o] = raw.get(o, 0) + 1
            pix[(x, y)] = CURRAY_MAP.get(o, "other")
            if x >= W:
                W = x + 1
            if y >= H:
                H = y + 1
    if len(pix) != W * H:
        die("%s: %d pixels, expected %d x %d" % (path, len(pix), W, H))
    img = [[pix[(i, j)] for i in range(W)] for j in range(H)]
    return W, H, img, raw, None


def read_fits_table(path):
    """The first BINTABLE of a FITS file: (header dict, column names, rows)."""
    try:
        b = open(path, "rb").read()
    except OSError as e:
        die("cannot read %s: %s" % (path, e))
    pos = 0
    while pos < len(b):
        cards = {}
        while True:
            blk = b[pos:pos + 2880]
            if len(blk) < 2880:
                die("%s: truncated FITS header" % path)
            pos += 2880
            end = False
            for k in range(36):
                c = blk[k * 80:(k + 1) * 80].decode("ascii", "replace")
                key = c[:8].strip()
                if key == "END":
                    end = True
                    break
                if c[8:10] == "= ":
                    cards[key] = c[10:].split("/")[0].strip().strip("'").strip()
            if end:
                break
        if cards.get("XTENSION") == "BINTABLE":
            n1, n2, nf = int(cards["NAXIS1"]), int(cards["NAXIS2"]), int(cards["TFIELDS"])
            names = [cards["TTYPE%d" % (k + 1)] for k in range(nf)]
            codes = {"1E": "f", "1D": "d", "1J": "i", "1I": "h", "1K": "q", "1B": "B"}
            try:
                fmt = ">" + "".join(codes[cards["TFORM%d" % (k + 1)]] for k in range(nf))
            except KeyError as e:
                die("%s: unsupported column format %s" % (path, e))
            if struct.calcsize(fmt) != n1:
                die("%s: row size %d does not match the columns" % (path, n1))
            data = b[pos:pos + n1 * n2]
            if len(data) != n1 * n2:
                die("%s: truncated table" % path)
            return cards, names, list(struct.iter_unpack(fmt, data))
        naxis = int(cards.get("NAXIS", "0"))
        if naxis:
            sz = abs(int(cards["BITPIX"])) // 8
            for k in range(naxis):
                sz *= int(cards["NAXIS%d" % (k + 1)])
            pos += (sz + 2879) // 2880 * 2880
    die("%s: no binary table (was it written by kerrz --save?)" % path)


def read_kerrz(path):
    cards, names, rows = read_fits_table(path)
    for need in ("ax_alpha", "ax_beta", "status"):
        if need not in names:
            die("%s: no column %s (columns: %s); render with --map status" % (path, need, ", ".join(names)))
    ia, ib, ist = names.index("ax_alpha"), names.index("ax_beta"), names.index("status")
    alphas = sorted(set(r[ia] for r in rows))
    betas = sorted(set(r[ib] for r in rows))
    W, H = len(alphas), len(betas)
    if W * H != len(rows):
        die("%s: %d rows are not a %d x %d grid" % (path, len(rows), W, H))
    raw = {}
    img = [[None] * W for _ in range(H)]
    pos = [[None] * W for _ in range(H)]
    for k, r in enumerate(rows):
        i, jb = k % W, k // W          # alpha fastest, beta from the first row up
        j = H - 1 - jb                 # curray's rows go top to bottom
        s = int(r[ist])
        raw[s] = raw.get(s, 0) + 1
        img[j][i] = KERRZ_MAP.get(s, "other")
        pos[j][i] = (r[ia], r[ib])
    meta = {"r_obs": cards.get("R_OBS"), "incl": cards.get("INCL_OBS"), "spin": cards.get("SPIN"),
            "version": cards.get("KZVERSN")}
    return W, H, img, raw, (pos, meta)


def load(spec):
    kind, _, path = spec.partition(":")
    if kind == "curray":
        return read_curray(path)
    if kind == "kerrz":
        return read_kerrz(path)
    die("input %r: expected curray:PATH or kerrz:PATH" % spec)


def edge_mask(img, W, H):
    """True where one of the 8 neighbours has another class."""
    m = [[False] * W for _ in range(H)]
    for j in range(H):
        row = img[j]
        for i in range(W):
            c = row[i]
            for dj in (-1, 0, 1):
                jj = j + dj
                if jj < 0 or jj >= H:
                    continue
                r2 = img[jj]
                for di in (-1, 0, 1):
                    ii = i + di
                    if 0 <= ii < W and r2[ii] != c:
                        m[j][i] = True
                        break
                if m[j][i]:
                    break
    return m


def uniform5(img, W, H, i, j):
    c = img[j][i]
    for jj in range(max(0, j - 2), min(H, j + 3)):
        for ii in range(max(0, i - 2), min(W, i + 3)):
            if img[jj][ii] != c:
                return False
    return True


def captured(al, be, a, incl, q):
    """True when the ray with impact coordinates (al, be) of a distant observer
    at inclination incl (rad) falls into the hole: R(r) > 0 for all r >= r+,
    sampled densely (log-spaced) with the minimum refined; None when R comes
    within a hair of 0 (a ray on the critical curve)."""
    import math
    si, ci = math.sin(incl), math.cos(incl)
    lam = -al * si
    eta = be * be + (al * al - a * a) * ci * ci
    k = eta + (lam - a) ** 2
    rp = 1.0 + math.sqrt(max(0.0, 1.0 - a * a - q * q))

    def R(r):
        return (r * r + a * a - a * lam) ** 2 - (r * r - 2.0 * r + a * a + q * q) * k

    rmax = 4.0 + 2.0 * math.sqrt(k + lam * lam) + 2.0 * abs(a)
    n = 1500
    best, rb = None, rp
    for m in range(n + 1):
        r = rp * math.exp(math.log(rmax / rp) * m / n)
        v = R(r)
        if best is None or v < best:
            best, rb = v, r
    if best <= 0.0:
        return False
    # refine the minimum (golden section) around the best sample
    lo, hi = max(rp, rb * 0.99), rb * 1.01
    for _ in range(60):
        m1, m2 = lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo)
        if R(m1) < R(m2):
            hi = m2
        else:
            lo = m1
    best = min(best, R(0.5 * (lo + hi)))
    scale = (rb * rb + a * a) ** 2 + 1.0
    if abs(best) < 1e-9 * scale:
        return None
    return best > 0.0


def write_png(path, rgb, W, H):
    raw = bytearray()
    for j in range(H):
        raw.append(0)
        for i in range(W):
            raw.extend(rgb[j][i])

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(bytes(raw), 6)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser(description="compare two images by pixel class (disc/hole/sky)")
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--name-a")
    ap.add_argument("--name-b")
    ap.add_argument("--hextent", type=float)
    ap.add_argument("--vextent", type=float)
    ap.add_argument("--max-offset", type=float, default=1e-4)
    ap.add_argument("--bardeen")
    ap.add_argument("--png")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--prefix", default="")
    o = ap.parse_args()
    na = o.name_a or o.a.partition(":")[0]
    nb = o.name_b or o.b.partition(":")[0]
    Wa, Ha, A, rawa, xa = load(o.a)
    Wb, Hb, B, rawb, xb = load(o.b)
    if (Wa, Ha) != (Wb, Hb):
        die("the images differ in size: %s %dx%d, %s %dx%d" % (na, Wa, Ha, nb, Wb, Hb))
    W, H = Wa, Ha
    P = o.prefix
    out = []

    # the image planes: each kerrz sample against curray's pixel centre
    for extra, name in ((xa, na), (xb, nb)):
        if extra is None:
            continue
        pos, meta = extra
        out.append("%skerrz_meta=%s" % (P, ",".join("%s:%s" % kv for kv in sorted(meta.items()))))
        if o.hextent is None:
            continue
        hx = o.hextent
        vx = o.vextent if o.vextent is not None else hx * H / W
        worst = 0.0
        for j in range(H):
            for i in range(W):
                al = (2.0 * (i + 0.5) / W - 1.0) * hx / 2.0
                be = (1.0 - 2.0 * (j + 0.5) / H) * vx / 2.0
                ka, kb = pos[j][i]
                worst = max(worst, abs(ka - al), abs(kb - be))
        out.append("%sgrid_max_offset_M=%.3g" % (P, worst))
        if worst > o.max_offset:
            die("%s's samples are up to %.3g M away from curray's pixel centres (hextent %.17g, vextent %.17g): "
                "the image planes do not match" % (name, worst, hx, vx))

    ea = edge_mask(A, W, H)
    eb = edge_mask(B, W, H)
    n = W * H
    agree = 0
    conf = {}
    dis_edge = dis_int = dis_int_deep_a = 0
    pairs_int = {}
    bbox = None
    rgb = [[None] * W for _ in range(H)] if o.png else None
    dis_list = []
    base = {"sky": (255, 255, 255), "disc": (150, 150, 150), "hole": (0, 0, 0), "other": (255, 200, 0)}
    for j in range(H):
        for i in range(W):
            a, b = A[j][i], B[j][i]
            conf[(a, b)] = conf.get((a, b), 0) + 1
            if a == b:
                agree += 1
                if rgb is not None:
                    rgb[j][i] = base[a]
                continue
            dis_list.append((i, j, a, b, ea[j][i] or eb[j][i]))
            if ea[j][i] or eb[j][i]:
                dis_edge += 1
                if rgb is not None:
                    rgb[j][i] = (255, 0, 0)
            else:
                dis_int += 1
                pairs_int[(a, b)] = pairs_int.get((a, b), 0) + 1
                if uniform5(A, W, H, i, j):
                    dis_int_deep_a += 1
                if bbox is None:
                    bbox = [i, i, j, j]
                else:
                    bbox = [min(bbox[0], i), max(bbox[1], i), min(bbox[2], j), max(bbox[3], j)]
                if rgb is not None:
                    rgb[j][i] = (0, 0, 255)
    dis = n - agree
    if o.bardeen:
        import math
        if o.hextent is None:
            die("--bardeen needs --hextent (and --vextent)")
        f = [float(x) for x in o.bardeen.split(",")]
        spin, incl, qq = f[0], math.radians(f[1]), (f[2] if len(f) > 2 else 0.0)
        hx = o.hextent
        vx = o.vextent if o.vextent is not None else hx * H / W
        wrong = {na: 0, nb: 0}
        judged = undecided = fixable = 0
        rest = rest_edge = 0
        for i, j, a, b, edge in dis_list:
            proven = False
            if "hole" in (a, b):
                al = (2.0 * (i + 0.5) / W - 1.0) * hx / 2.0
                be = (1.0 - 2.0 * (j + 0.5) / H) * vx / 2.0
                c = captured(al, be, spin, incl, qq)
                if c is None:
                    undecided += 1
                else:
                    judged += 1
                    bad = []
                    for name, cls in ((na, a), (nb, b)):
                        if (c and cls == "sky") or (not c and cls == "hole"):
                            wrong[name] += 1
                            bad.append(name)
                    if len(bad) == 1:
                        fixable += 1
                        proven = True
                        if rgb is not None:
                            rgb[j][i] = (255, 0, 255) if bad[0] == nb else (0, 160, 0)
            if not proven:
                rest += 1
                rest_edge += 1 if edge else 0
        out.append("%sbardeen_judged=%d" % (P, judged))
        out.append("%sbardeen_undecided=%d" % (P, undecided))
        out.append("%sbardeen_wrong_%s=%d" % (P, na, wrong[na]))
        out.append("%sbardeen_wrong_%s=%d" % (P, nb, wrong[nb]))
        out.append("%sagree_frac_bardeen_fixed=%.6f" % (P, (agree + fixable) / n))
        out.append("%sdisagree_not_proven=%d" % (P, rest))
        out.append("%sdisagree_not_proven_on_edges=%d" % (P, rest_edge))
    out.append("%swidth=%d" % (P, W))
    out.append("%sheight=%d" % (P, H))
    out.append("%spixels=%d" % (P, n))
    out.append("%sraw_%s=%s" % (P, na, ",".join("%s:%d" % (k, v) for k, v in sorted(rawa.items(), key=str))))
    out.append("%sraw_%s=%s" % (P, nb, ",".join("%s:%d" % (k, v) for k, v in sorted(rawb.items(), key=str))))
    out.append("%sagree=%d" % (P, agree))
    out.append("%sagree_frac=%.6f" % (P, agree / n))
    out.append("%sdisagree=%d" % (P, dis))
    out.append("%sdisagree_on_edges=%d" % (P, dis_edge))
    out.append("%sdisagree_interior=%d" % (P, dis_int))
    out.append("%sdisagree_on_edges_frac=%.6f" % (P, dis_edge / dis if dis else 1.0))
    out.append("%sdisagree_interior_deep_in_%s=%d" % (P, na, dis_int_deep_a))
    out.append("%sinterior_pairs=%s" % (P, ",".join("%s>%s:%d" % (a, b, c) for (a, b), c in sorted(pairs_int.items()))))
    out.append("%sinterior_bbox=%s" % (P, "none" if bbox is None else "x%d-%d,y%d-%d" % tuple(bbox)))
    out.append("%sconfusion=%s" % (P, ",".join("%s>%s:%d" % (a, b, c) for (a, b), c in sorted(conf.items()))))
    print("\n".join(out))
    if o.png and dis:
        write_png(o.png, rgb, W, H)
    if o.markdown:
        print()
        print("| %s \\ %s | %s |" % (na, nb, " | ".join(CLASSES)))
        print("|---|%s" % ("---|" * len(CLASSES)))
        for a in CLASSES:
            print("| %s | %s |" % (a, " | ".join(str(conf.get((a, b), 0)) for b in CLASSES)))
        print()
        print("| pixels | agree | disagree | of which on edges | interior (not on an edge) |")
        print("|---|---|---|---|---|")
        print("| %d | %d (%.4f %%) | %d (%.4f %%) | %d (%s) | %d%s |" % (
            n, agree, 100.0 * agree / n, dis, 100.0 * dis / n, dis_edge,
            ("%.1f %%" % (100.0 * dis_edge / dis)) if dis else "-", dis_int,
            "" if not dis_int else " (%s; bbox %s)" % (
                ", ".join("%s %s / %s %s: %d" % (na, a, nb, b, c) for (a, b), c in sorted(pairs_int.items())),
                "x %d-%d, y %d-%d" % tuple(bbox))))


if __name__ == "__main__":
    main()
