/* curray base: the shortest round-trip decimal of a double (shortest.h).
 *
 * Schubfach (R. Giulietti, "The Schubfach way to render doubles", 2020):
 * v = c 2^q has the rounding interval [vl, vr] of the reals that round to it
 * (halfway to the neighbouring doubles; closed when c is even). With
 * k = floor(log10(vr - vl)) roughly (exactly: floor(log10 2^q), or
 * floor(log10 (3/4) 2^q) at the lower edge of a binade), the interval
 * scaled by 10^-k contains one or two integers; if it contains a multiple of
 * ten, that one (one digit fewer) is the answer, else the integer of the
 * interval closest to v 10^-k. The products v 10^-k are computed as
 * round-to-odd approximations (rop) from 126-bit g ~ 10^-k 2^-r, exact
 * enough that every comparison comes out as with real numbers (the paper's
 * proof). All arithmetic is on unsigned 64-bit integers. */
#include "shortest.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "shortest_table.h"

#define CR_SF_Q_MIN (-1074)                 /* smallest binary exponent q */
#define CR_SF_C_MIN ((uint64_t)1 << 52)     /* smallest normal significand */
#define CR_SF_C_TINY 3                      /* subnormal c below this: see below */
#define CR_SF_K_MIN (-324)                  /* first k of cr_shortest_g */
#define CR_SF_MASK_63 (((uint64_t)1 << 63) - 1)

/* floor(x / 2^s) for any sign of x (C leaves >> of a negative value to the
 * implementation). */
static int cr_sf_floor_shift(int64_t x, int s)
{
    return (int)(x >= 0 ? x >> s : ~(~x >> s));
}

/* floor(e log10 2), floor(log10((3/4) 2^e)), floor(e log2 10): exact for the
 * exponents of doubles (|e| < 1800; Giulietti's constants). */
static int cr_sf_flog10pow2(int e)
{
    return cr_sf_floor_shift((int64_t)e * 661971961083LL, 41);
}

static int cr_sf_flog10_3q_pow2(int e)
{
    return cr_sf_floor_shift((int64_t)e * 661971961083LL - 274743187321LL, 41);
}

static int cr_sf_flog2pow10(int e)
{
    return cr_sf_floor_shift((int64_t)e * 913124641741LL, 38);
}

/* The high 64 bits of the 128-bit product a b. */
static uint64_t cr_sf_mul_high(uint64_t a, uint64_t b)
{
    uint64_t a0 = a & 0xffffffffu, a1 = a >> 32, b0 = b & 0xffffffffu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
    return p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
}

/* g cp / 2^127 (g = g1 2^63 + g0) rounded to odd: the low bit is set when
 * the product is not an integer. */
static uint64_t cr_sf_rop(uint64_t g1, uint64_t g0, uint64_t cp)
{
    uint64_t x1 = cr_sf_mul_high(g0, cp);
    uint64_t y0 = g1 * cp;
    uint64_t y1 = cr_sf_mul_high(g1, cp);
    uint64_t z = (y0 >> 1) + x1;
    uint64_t vbp = y1 + (z >> 63);
    return vbp | (((z & CR_SF_MASK_63) + CR_SF_MASK_63) >> 63);
}

/* The shortest decimal f 10^e of v = c 2^q (f may end in zeros). */
static void cr_sf_decimal(int q, uint64_t c, uint64_t *f, int *e)
{
    uint64_t out = c & 1, cb = c << 2, cbr = cb + 2, cbl, g1, g0, vb, vbl, vbr, s, t;
    int k, h;
    int64_t cmp;
    if (c != CR_SF_C_MIN || q == CR_SF_Q_MIN) {
        cbl = cb - 2;
        k = cr_sf_flog10pow2(q);
    } else { /* the lower neighbour is closer: the interval is asymmetric */
        cbl = cb - 1;
        k = cr_sf_flog10_3q_pow2(q);
    }
    h = q + cr_sf_flog2pow10(-k) + 2;
    g1 = cr_shortest_g[2 * (k - CR_SF_K_MIN)];
    g0 = cr_shortest_g[2 * (k - CR_SF_K_MIN) + 1];
    vb = cr_sf_rop(g1, g0, cb << h);
    vbl = cr_sf_rop(g1, g0, cbl << h);
    vbr = cr_sf_rop(g1, g0, cbr << h);
    s = vb >> 2;
    /* Java's version asks s >= 100 here, for its rule of at least two
       digits; s < 100 only happens for small subnormals, whose shortest
       form may have one digit (5e-323, not 4.9e-323) */
    {
        /* a multiple of ten in the interval: one digit fewer */
        uint64_t sp10 = 10 * cr_sf_mul_high(s, (uint64_t)115292150460684698ULL << 4);
        uint64_t tp10 = sp10 + 10;
        int upin = vbl + out <= sp10 << 2;
        int wpin = (tp10 << 2) + out <= vbr;
        if (upin != wpin) {
            *f = upin ? sp10 : tp10;
            *e = k;
            return;
        }
    }
    t = s + 1;
    {
        int uin = vbl + out <= s << 2;
        int win = (t << 2) + out <= vbr;
        if (uin != win) {
            *f = uin ? s : t;
            *e = k;
            return;
        }
    }
    /* both s and t lie in the interval: the closer one, ties to even */
    cmp = (int64_t)(vb - ((s + t) << 1));
    *f = cmp < 0 || (cmp == 0 && (s & 1) == 0) ? s : t;
    *e = k;
}

/* Write the digits of f 10^e (f > 0) in %.17g's layout; returns the end. */
static char *cr_sf_layout(char *p, uint64_t f, int e)
{
    char dig[24];
    int n = 0, x;
    while (f % 10 == 0) {
        f /= 10;
        e++;
    }
    /* digits, most significant first */
    {
        char tmp[24];
        int m = 0;
        do {
            tmp[m++] = (char)('0' + f % 10);
            f /= 10;
        } while (f);
        while (m)
            dig[n++] = tmp[--m];
    }
    x = e + n - 1; /* decimal exponent of the first digit */
    if (x < -4 || x >= 17) {
        int ax = x < 0 ? -x : x;
        *p++ = dig[0];
        if (n > 1) {
            *p++ = '.';
            memcpy(p, dig + 1, (size_t)(n - 1));
            p += n - 1;
        }
        *p++ = 'e';
        *p++ = x < 0 ? '-' : '+';
        if (ax >= 100)
            *p++ = (char)('0' + ax / 100);
        *p++ = (char)('0' + ax / 10 % 10);
        *p++ = (char)('0' + ax % 10);
    } else if (x < 0) {
        *p++ = '0';
        *p++ = '.';
        for (int i = -1; i > x; i--)
            *p++ = '0';
        memcpy(p, dig, (size_t)n);
        p += n;
    } else if (n <= x + 1) {
        memcpy(p, dig, (size_t)n);
        p += n;
        for (int i = n; i <= x; i++)
            *p++ = '0';
    } else {
        memcpy(p, dig, (size_t)(x + 1));
        p += x + 1;
        *p++ = '.';
        memcpy(p, dig + x + 1, (size_t)(n - x - 1));
        p += n - x - 1;
    }
    return p;
}

int cr_shortest_double(char *out, double v)
{
    uint64_t bits, t, c, f;
    int bq, e;
    char *p = out;
    memcpy(&bits, &v, sizeof bits);
    t = bits & (CR_SF_C_MIN - 1);
    bq = (int)(bits >> 52) & 0x7ff;
    if (bq == 0x7ff) /* inf, nan: printf's words */
        return snprintf(out, CR_SHORTEST_MAX, "%g", v);
    if (bits >> 63)
        *p++ = '-';
    if (bq == 0 && t == 0) {
        *p++ = '0';
        *p = '\0';
        return (int)(p - out);
    }
    if (bq != 0) {
        int mq = -CR_SF_Q_MIN + 1 - bq; /* v = c 2^-mq */
        c = CR_SF_C_MIN | t;
        if (mq > 0 && mq < 53 && ((c >> mq) << mq) == c) {
            /* an integer below 2^53: its own digits are the shortest */
            f = c >> mq;
            e = 0;
        } else {
            cr_sf_decimal(-mq, c, &f, &e);
        }
    } else if (t < CR_SF_C_TINY) {
        /* the two smallest subnormals: the algorithm scales them by 10 and
           gives two digits (4.9e-324, 9.9e-324, Java's rule of at least two);
           one digit reads back already, and these are the closest */
        f = t == 1 ? 5 : 1;
        e = t == 1 ? -324 : -323;
    } else {
        cr_sf_decimal(CR_SF_Q_MIN, t, &f, &e);
    }
    p = cr_sf_layout(p, f, e);
    *p = '\0';
    return (int)(p - out);
}
