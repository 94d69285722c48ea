/* bench/micro_step.c: the cost of one RK4 photon-step in isolation, on one
 * core, and of the pieces it is made of. Not a test; timings only.
 *
 *   cc -O3 -std=c11 -I src bench/micro_step.c -lm -o build-bench/micro_step
 *   build-bench/micro_step [million-steps]
 *
 * It runs the same inline functions as cr_trace_ray (src/core/geodesic.h):
 * per step one cr_geo_rhs_full (k1, with u and the metric, as the tracer
 * does), the null error, the step size and one cr_geo_rk4 (three more
 * right-hand sides). The ray is a bound-ish photon near r = 8 of an a = 0.5
 * hole, reset every 4096 steps so it never leaves the region. For scale it
 * also times sincos() (4 per step in cr_metric_eval) and a division chain.
 * Times are this thread's CPU time (CLOCK_THREAD_CPUTIME_ID), medians of 5.
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "core/geodesic.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: load on a shared machine does not inflate it */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    long n = (argc > 1 ? atol(argv[1]) : 2) * 1000000L;
    cr_geo g = {{1.0, 0.5, 0.0}, 0.9, 3.0, 1e-8};
    const double y0[CR_NY] = {0.0, 8.0, 1.2, 0.0, -0.3, 0.05};
    double y[CR_NY], y1[CR_NY], k1[CR_NY], u[4], sink = 0.0, t[5], ts[5], tsc[5], tdv[5];
    cr_metric_point p;
    int rep, i;
    for (rep = 0; rep < 5; rep++) {
        double t0;
        long s;
        for (i = 0; i < CR_NY; i++)
            y[i] = y0[i];
        t0 = now();
        for (s = 0; s < n; s++) {
            double h;
            if ((s & 4095) == 0)
                for (i = 0; i < CR_NY; i++)
                    y[i] = y0[i];
            cr_geo_rhs_full(&g, y, k1, u, &p);
            sink += cr_geo_null_error(&p, u);
            h = cr_geo_step_size(&g, 0.03125, y[CR_Y_TH], u);
            cr_geo_rk4(&g, y, k1, h, y1);
            for (i = 0; i < CR_NY; i++)
                y[i] = y1[i];
        }
        t[rep] = (now() - t0) / (double)n;
        {
            double x = 0.1, sn, cs;
            t0 = now();
            for (s = 0; s < n; s++) {
                sincos(x, &sn, &cs);
                x += 1e-7 + 1e-3 * sn * cs; /* a dependency chain, like the tracer's */
            }
            ts[rep] = (now() - t0) / (double)n;
            sink += x;
        }
        {
            double x = 1.1;
            t0 = now();
            for (s = 0; s < 4 * n; s++)
                x = 1.0 + 1.0 / x; /* dependent divisions: latency-bound */
            tdv[rep] = (now() - t0) / (double)(4 * n);
            sink += x;
        }
        {
            volatile double x = 0.3;
            double acc = 0.0, sn, cs;
            t0 = now();
            for (s = 0; s < n; s++) {
                sincos(x + 1e-9 * (double)(s & 1023), &sn, &cs); /* independent calls */
                acc += sn + cs;
            }
            tsc[rep] = (now() - t0) / (double)n;
            sink += acc;
        }
    }
    qsort(t, 5, sizeof t[0], cmp);
    qsort(ts, 5, sizeof ts[0], cmp);
    qsort(tsc, 5, sizeof tsc[0], cmp);
    qsort(tdv, 5, sizeof tdv[0], cmp);
    printf("photon-step (rhs_full + null error + step size + rk4): %.1f ns (median of 5 x %ld)\n",
           1e9 * t[2], n);
    printf("sincos, dependent chain:   %.1f ns per call\n", 1e9 * ts[2]);
    printf("sincos, independent calls: %.1f ns per call\n", 1e9 * tsc[2]);
    printf("dependent 1/x + 1:         %.2f ns per division + addition (Zen 3: ~13.5 + 3 cycles)\n", 1e9 * tdv[2]);
    printf("(sink %g)\n", sink);
    return 0;
}
