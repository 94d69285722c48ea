/* The shortest round-trip decimal of a double (src/base/shortest.c), against
 * the C library: every text must read back (strtod) as the identical double,
 * bit for bit, and must have no more significant digits than the shortest
 * precision p at which printf's correctly rounded %.<p>g reads back; at equal
 * length the digits must be printf's (the closest decimal of that length).
 * Millions of random doubles of every binade (uniform bit patterns), the
 * subnormals, the edges of every binade (where the rounding interval is
 * lopsided), integers around 2^53, powers of ten, and the special values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/shortest.h"

static uint64_t g_rng = 0x9e3779b97f4a7c15ull;

static uint64_t next_u64(void) /* xorshift64 */
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return g_rng;
}

static double from_bits(uint64_t b)
{
    double v;
    memcpy(&v, &b, sizeof v);
    return v;
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* The significant digits of a decimal text, without leading and trailing
 * zeros, into d; returns their count. */
static int digits_of(const char *s, char *d)
{
    int n = 0, lead = 1;
    for (; *s && *s != 'e'; s++) {
        if (*s < '0' || *s > '9' || (*s == '0' && lead))
            continue;
        lead = 0;
        d[n++] = *s;
    }
    while (n > 0 && d[n - 1] == '0')
        n--;
    d[n] = '\0';
    return n;
}

/* Check v; full: also against printf's shortest precision (slower). */
static void check(double v, int full)
{
    char out[CR_SHORTEST_MAX + 8], ref[40], da[32], dr[32];
    int len, p;
    double back;
    memset(out, 'x', sizeof out);
    len = cr_shortest_double(out, v);
    assert_true(len > 0 && len < CR_SHORTEST_MAX);
    assert_int_equal((int)strlen(out), len);
    back = strtod(out, NULL);
    if (!same_bits(back, v))
        fail_msg("%a written as '%s' reads back as %a", v, out, back);
    if (!full)
        return;
    for (p = 1; p < 17; p++) {
        snprintf(ref, sizeof ref, "%.*g", p, v);
        if (same_bits(strtod(ref, NULL), v))
            break;
    }
    if (p == 17)
        snprintf(ref, sizeof ref, "%.17g", v);
    {
        int na = digits_of(out, da), nr = digits_of(ref, dr);
        if (na > nr)
            fail_msg("%a: '%s' has more digits than '%s'", v, out, ref);
        if (na == nr && strcmp(da, dr) != 0)
            fail_msg("%a: '%s' is not the closest of its length ('%s')", v, out, ref);
    }
}

static void test_special(void **state)
{
    static const struct {
        double v;
        const char *text;
    } cases[] = {
        {0.0, "0"},
        {-0.0, "-0"},
        {1.0, "1"},
        {-1.0, "-1"},
        {0.1, "0.1"},
        {0.3, "0.3"},
        {2.0 / 3.0, "0.6666666666666666"},
        {100.0, "100"},
        {12345.678, "12345.678"},
        {0.001, "0.001"},
        {1e-4, "0.0001"},
        {1e-5, "1e-05"},
        {1.5e-7, "1.5e-07"},
        {1e16, "10000000000000000"},
        {1e17, "1e+17"},
        {1e22, "1e+22"},
        {123456789012345678.0, "1.2345678901234568e+17"},
        {9007199254740992.0, "9007199254740992"},
        {5e-324, "5e-324"},
        {1e-323, "1e-323"},
        {2.2250738585072014e-308, "2.2250738585072014e-308"},
        {1.7976931348623157e308, "1.7976931348623157e+308"},
        {-6.02214076e23, "-6.02214076e+23"},
        {INFINITY, "inf"},
        {-INFINITY, "-inf"},
    };
    char out[CR_SHORTEST_MAX];
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cr_shortest_double(out, cases[i].v);
        assert_string_equal(out, cases[i].text);
        check(cases[i].v, 1);
    }
    cr_shortest_double(out, NAN);
    assert_true(strcmp(out, "nan") == 0 || strcmp(out, "-nan") == 0);
    assert_true(isnan(strtod(out, NULL)));
}

/* 4 million uniform bit patterns (every binade equally often, subnormals
 * rarely), each read back; every 16th also against printf. */
static void test_random_bits(void **state)
{
    (void)state;
    for (long i = 0; i < 4000000; i++) {
        double v = from_bits(next_u64());
        if (!isfinite(v))
            continue;
        check(v, (i & 15) == 0);
    }
}

/* Subnormals: 1 million random ones and the smallest 10,000, against printf. */
static void test_subnormals(void **state)
{
    (void)state;
    for (long i = 0; i < 1000000; i++)
        check(from_bits(next_u64() & 0x800fffffffffffffull), (i & 7) == 0);
    for (uint64_t t = 1; t <= 10000; t++) {
        check(from_bits(t), 1);
        check(-from_bits(t), 1);
    }
}

/* The edges of every binade: 2^e (lopsided interval), its neighbours, and
 * the largest double of each binade; integers around 2^53; powers of ten and
 * their neighbours; short decimals (values people type), against printf. */
static void test_edges(void **state)
{
    (void)state;
    for (uint64_t bq = 1; bq < 0x7ff; bq++) {
        uint64_t b = bq << 52;
        check(from_bits(b), 1);
        check(from_bits(b + 1), 1);
        check(from_bits(b - 1), 1);
        check(from_bits(b + 2), 1);
        check(-from_bits(b), 1);
    }
    for (int64_t n = -3000; n <= 3000; n++) {
        check(9007199254740992.0 + (double)n * 2.0, 1);
        check(9007199254740992.0 - (double)n, 1);
        check((double)n, 1);
    }
    for (int e = -325; e <= 308; e++) {
        double v = pow(10.0, e);
        check(v, 1);
        check(nextafter(v, 0.0), 1);
        check(nextafter(v, INFINITY), 1);
    }
    for (long i = 0; i < 200000; i++) {
        char text[40];
        long m = (long)(next_u64() % 1000000);
        int e = (int)(next_u64() % 40) - 20;
        snprintf(text, sizeof text, "%lde%d", m, e);
        check(strtod(text, NULL), 1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_special),
        cmocka_unit_test(test_random_bits),
        cmocka_unit_test(test_subnormals),
        cmocka_unit_test(test_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
