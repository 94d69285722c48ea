/* Shared helpers for curray's tests: a deterministic PRNG and a prepared
 * frame with no objects, for tests that trace single rays. */
#ifndef CR_TESTS_TESTUTIL_H
#define CR_TESTS_TESTUTIL_H

#include <stdint.h>
#include <string.h>

#include "core/trace.h"
#include "input/settings.h" /* cr_trace_defaults */

/* xorshift64*: deterministic, so failures reproduce. */
static inline double cr_test_rand(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

/* A frame with metric (m, a, q), a static observer at (r, theta, phi = 0)
 * looking at the hole with a 90 deg field of view, nothing in the scene and
 * default raytracer settings, prepared. */
static inline void cr_test_empty_frame(cr_frame *f, double m, double a, double q, double r,
                                       double theta)
{
    memset(f, 0, sizeof *f);
    f->metric.m = m;
    f->metric.a = a;
    f->metric.q = q;
    f->observer.r = r;
    f->observer.theta = theta;
    f->observer.hfov = f->observer.vfov = 0.5 * CR_PI;
    f->width = f->height = 64;
    f->horizon_color.r = 255;
    f->error_color.b = 255;
    f->limit_color.r = f->limit_color.g = 255;
    f->integrator = cr_trace_defaults().integrator;
    f->tolerance = cr_trace_defaults().tolerance;
    f->step_multiplier = cr_trace_defaults().step_multiplier;
    f->horizon_epsilon = cr_trace_defaults().horizon_epsilon;
    f->max_steps = cr_trace_defaults().max_steps;
    f->max_turns = cr_trace_defaults().max_turns;
    cr_frame_prepare(f);
}

/* Full 4x4 metric g_{mu nu} at (r, theta). */
static inline void cr_test_metric4(const cr_metric *mt, double r, double th, double g[4][4])
{
    cr_metric_point p;
    memset(g, 0, 16 * sizeof(double));
    cr_metric_eval(mt, r, th, &p);
    g[0][0] = p.g_tt;
    g[0][3] = g[3][0] = p.g_tph;
    g[3][3] = p.g_phph;
    g[1][1] = p.g_rr;
    g[2][2] = p.g_thth;
}

static inline double cr_test_dot(const double g[4][4], const double *u, const double *v)
{
    double s = 0.0;
    int i, j;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            s += g[i][j] * u[i] * v[j];
    return s;
}

#endif
