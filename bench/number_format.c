/* bench/number_format.c: what one double costs the CSV, by method.
 *
 *   printf17   snprintf "%.17g" (the CSV before the shortest form)
 *   tryg       the shortest of "%.15g", "%.16g", "%.17g" that strtod reads
 *              back (exact, nearly shortest, no table)
 *   shortest   cr_shortest_double (src/base/shortest.c, Schubfach)
 *
 * Values like a CSV's: redshift ratios in [0.2, 5), hit radii in [2, 40),
 * azimuths in [0, 2 pi), error monitors 2^-60..2^-20 (full 53-bit
 * significands), and a quarter of them -1 or 0 (the CSV's fast paths are not
 * used here: every value goes through the method). Prints ns per value, the
 * median of ROUNDS rounds, with the methods interleaved in each round, and the
 * mean text length. Timings only; the exactness test is tests/test_shortest.c.
 *
 * Build and run: bench/number_format.sh */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/shortest.h"

#define N_VALUES 1000000
#define ROUNDS 7

static uint64_t g_rng = 0x2545f4914f6cdd1dull;

static double uniform(void)
{
    g_rng ^= g_rng << 13;
    g_rng ^= g_rng >> 7;
    g_rng ^= g_rng << 17;
    return (double)(g_rng >> 11) / 9007199254740992.0;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int fmt_printf17(char *out, double v)
{
    return snprintf(out, 32, "%.17g", v);
}

static int fmt_tryg(char *out, double v)
{
    int n = 0;
    for (int p = 15; p <= 17; p++) {
        n = snprintf(out, 32, "%.*g", p, v);
        if (p == 17 || strtod(out, NULL) == v)
            break;
    }
    return n;
}

static int fmt_shortest(char *out, double v)
{
    return cr_shortest_double(out, v);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(void)
{
    static const char *const names[] = {"printf17", "tryg", "shortest"};
    int (*const fns[])(char *, double) = {fmt_printf17, fmt_tryg, fmt_shortest};
    enum { M = 3 };
    double *v = malloc(sizeof *v * N_VALUES), t[M][ROUNDS];
    long long chars[M] = {0};
    char buf[64];
    volatile int sink = 0;
    if (!v)
        return 1;
    for (int i = 0; i < N_VALUES; i++) {
        switch (i % 8) {
        case 0: v[i] = -1.0; break;
        case 1: v[i] = 0.2 + 4.8 * uniform(); break;
        case 2: v[i] = 2.0 + 38.0 * uniform(); break;
        case 3: v[i] = 6.283185307179586 * uniform(); break;
        case 4: v[i] = ldexp(1.0 + uniform(), -60 + (int)(40.0 * uniform())); break;
        case 5: v[i] = ldexp(1.0 + uniform(), -50); break;
        case 6: v[i] = 0.0; break;
        default: v[i] = 0.2 + 4.8 * uniform(); break;
        }
    }
    for (int r = 0; r < ROUNDS; r++)
        for (int m = 0; m < M; m++) {
            double t0 = now();
            long long c = 0;
            for (int i = 0; i < N_VALUES; i++)
                c += fns[m](buf, v[i]);
            t[m][r] = (now() - t0) / N_VALUES * 1e9;
            chars[m] = c;
            sink += buf[0];
        }
    printf("%-10s %12s %12s\n", "method", "ns/value", "chars/value");
    for (int m = 0; m < M; m++) {
        qsort(t[m], ROUNDS, sizeof t[m][0], cmp_double);
        printf("%-10s %12.1f %12.2f\n", names[m], t[m][ROUNDS / 2],
               (double)chars[m] / N_VALUES);
    }
    free(v);
    return sink == 12345;
}
