/* curray core: tracing one ray, and cr_trace_pixel, the ONE implementation
 * both backends run for every pixel.
 *
 * Loop (chapter 6): from the observer's state, repeat
 *   break conditions (6.8): r <= r+ + eps -> horizon; r >= r_max moving
 *     outward -> sky; step or turn limit -> limit;
 *   h by (6.6.1); one RK4 step; non-finite result -> retry smaller, then error;
 *   events inside the step: the disc plane theta = pi/2 and every sphere
 *     surface are located by root finding on partial RK4 steps from the
 *     step's start, and the earliest hit ends the ray;
 *   continue through the polar axis; accumulate the null error (6.7.1).
 */
#ifndef CR_CORE_TRACE_H
#define CR_CORE_TRACE_H

#include "objects.h"

/* Defaults of the raytracer settings (E.2). */
#define CR_DEFAULT_STEP_MULTIPLIER 0.03125
#define CR_DEFAULT_HORIZON_EPSILON 0.5e-2
#define CR_DEFAULT_MAX_STEPS 200000L
#define CR_DEFAULT_MAX_TURNS 50.0
#define CR_DEFAULT_INTEGRATOR CR_INTEG_MINO
#define CR_DEFAULT_TOLERANCE 1e-8

/* The scene boundary when nothing else asks for more: beyond every photon
 * orbit of a Kerr-Newman hole (r <= 4M), so an outgoing ray there escapes. */
#define CR_MIN_R_MAX_OVER_M 6.0

/* Complete the derived fields of a frame whose scene and settings are set.
 * Requires a validated scene (a horizon, a static observer outside it).
 * Spheres must already be prepared (cr_sphere_prepare). */
CR_HD static inline void cr_frame_prepare(cr_frame *f)
{
    double rm = f->observer.r;
    int k;
    f->r_stop = cr_metric_r_plus(&f->metric) + f->horizon_epsilon;
    if (f->disc.enabled && f->disc.r_out > rm)
        rm = f->disc.r_out;
    for (k = 0; k < f->n_spheres; k++) {
        const double *c = f->spheres[k].center;
        /* Cartesian distance bounds BL r from above: |x|^2 = r^2 + a^2 sin^2 */
        double ext = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + f->spheres[k].radius;
        if (ext > rm)
            rm = ext;
    }
    rm += f->metric.m;
    if (rm < CR_MIN_R_MAX_OVER_M * f->metric.m)
        rm = CR_MIN_R_MAX_OVER_M * f->metric.m;
    if (f->sky_boundary > rm)
        rm = f->sky_boundary;
    f->r_max = rm;
    cr_camera_prepare(f);
}

/* Event kinds located inside a step. */
enum { CR_EV_DISC = -1 };

/* Value of event function ev (CR_EV_DISC or a sphere index) at state y. */
CR_HD static inline double cr_event_value(const cr_frame *f, int ev, const double *y)
{
    double x[3];
    if (ev == CR_EV_DISC)
        return y[CR_Y_TH] - 0.5 * CR_PI;
    cr_bl_to_cart(f->metric.a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], x);
    return cr_sphere_f(&f->spheres[ev], x);
}

/* Locate the root of event ev inside the step y -(h)-> with f(y) = v0 and
 * f(state at s_hi) = v1 of opposite sign, 0 < s_hi <= 1, by the Illinois
 * variant of regula falsi on partial RK4 steps. Returns the fraction s and the
 * state there in ys. */
CR_HD static inline double cr_event_locate(const cr_frame *f, const cr_geo *g, int ev,
                                           const double *y, const double *k1, double h,
                                           double v0, double s_hi, double v1, double *ys)
{
    double s_lo = 0.0, s = s_hi;
    int side = 0, it;
    cr_geo_rk4(g, y, k1, s_hi * h, ys);
    for (it = 0; it < 60; it++) {
        double v;
        s = (s_lo * v1 - s_hi * v0) / (v1 - v0);
        cr_geo_rk4(g, y, k1, s * h, ys);
        v = cr_event_value(f, ev, ys);
        if (v == 0.0 || s_hi - s_lo < 1e-12)
            break;
        if ((v < 0.0) == (v1 < 0.0)) {
            s_hi = s;
            v1 = v;
            if (side == -1)
                v0 *= 0.5;
            side = -1;
        } else {
            s_lo = s;
            v0 = v;
            if (side == 1)
                v1 *= 0.5;
            side = 1;
        }
        if (fabs(v) < 1e-13)
            break;
    }
    return s;
}

/* Earliest sphere hit within the step y -> y1 (x0, x1 their Cartesian
 * positions). Catches both a sign change of |x - c|^2 - R^2 and a ray that
 * enters and leaves within the step (chord passing inside). Returns the
 * sphere index or -1; on a hit, *s_out and ys hold the located point. */
CR_HD static inline int cr_sphere_events(const cr_frame *f, const cr_geo *g, const double *y,
                                         const double *k1, double h, const double x0[3],
                                         const double x1[3], double *s_out, double *ys)
{
    int best = -1, k;
    double best_s = 2.0, tmp[CR_NY];
    for (k = 0; k < f->n_spheres; k++) {
        const cr_sphere *sp = &f->spheres[k];
        double v0 = cr_sphere_f(sp, x0), v1 = cr_sphere_f(sp, x1);
        double s_hi = 1.0, s;
        if (v0 == 0.0)
            continue;
        if ((v0 < 0.0) == (v1 < 0.0)) {
            /* both ends on one side: look for a dip inside at the chord's
             * closest approach to the centre */
            double d[3], w[3], dd = 0.0, wd = 0.0, t, xm[3];
            int i;
            if (v0 < 0.0)
                continue;
            for (i = 0; i < 3; i++) {
                d[i] = x1[i] - x0[i];
                w[i] = x0[i] - sp->center[i];
                dd += d[i] * d[i];
                wd += w[i] * d[i];
            }
            if (!(dd > 0.0))
                continue;
            t = -wd / dd;
            if (t <= 0.0 || t >= 1.0)
                continue;
            for (i = 0; i < 3; i++)
                xm[i] = x0[i] + t * d[i];
            if (cr_sphere_f(sp, xm) >= 0.0)
                continue;
            cr_geo_rk4(g, y, k1, t * h, tmp);
            v1 = cr_event_value(f, k, tmp);
            if (v1 >= 0.0)
                continue;
            s_hi = t;
        }
        if (s_hi >= best_s)
            continue;
        s = cr_event_locate(f, g, k, y, k1, h, v0, s_hi, v1, tmp);
        if (s < best_s) {
            int i;
            best_s = s;
            best = k;
            for (i = 0; i < CR_NY; i++)
                ys[i] = tmp[i];
        }
    }
    *s_out = best_s;
    return best;
}

/* Trace the backward ray (g, y) through the frame's scene. */
CR_HD static inline cr_pixel cr_trace_ray(const cr_frame *f, const cr_geo *g, double *y)
{
    cr_pixel px;
    double k1[CR_NY], y1[CR_NY], ys[CR_NY], u[4];
    double x0[3] = {0.0, 0.0, 0.0}, x1[3];
    double mean = 0.0, m2 = 0.0, turns = 0.0;
    long n_err = 0, steps = 0;
    int i;
    cr_metric_point p;

    px.redshift = -1.0;
    px.object = -1;
    px.outcome = CR_OUT_NONE;
    px.color = f->error_color;
    if (f->n_spheres > 0)
        cr_bl_to_cart(f->metric.a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], x0);

    for (;;) {
        double h, e;
        int tries, hit_sphere = -1, hit_disc = 0;
        double s_sphere = 2.0, s_disc = 2.0;

        if (y[CR_Y_R] <= f->r_stop) {
            px.outcome = CR_OUT_HORIZON;
            px.color = f->horizon_color;
            px.redshift = 0.0; /* light from the horizon is infinitely redshifted */
            break;
        }
        cr_geo_rhs_full(g, y, k1, u, &p);
        e = cr_geo_null_error(&p, u);
        if (e >= 0.0 && cr_isfinite(e)) {
            double d = e - mean;
            n_err++;
            mean += d / n_err;
            m2 += d * (e - mean);
        }
        if (y[CR_Y_R] >= f->r_max && u[1] > 0.0) {
            px.outcome = CR_OUT_SKY;
            if (f->sky.rgb) {
                double sth, sph;
                cr_sky_direction(f->metric.a, y, u[3], &sth, &sph);
                px.color = cr_sky_sample(&f->sky, sth, sph);
            } else {
                px.color = f->sky_color;
            }
            /* a static source at infinity: omega_r/omega_s = 1/sqrt(-g_tt)|obs */
            px.redshift = 1.0 / f->obs_sqrt_mgtt;
            break;
        }
        if (steps >= f->max_steps || turns >= f->max_turns) {
            px.outcome = CR_OUT_LIMIT;
            px.color = f->horizon_color;
            break;
        }
        h = cr_geo_step_size(g, f->step_multiplier, y[CR_Y_TH], u);
        for (tries = 0;; tries++) {
            int ok = 1;
            cr_geo_rk4(g, y, k1, h, y1);
            for (i = 0; i < CR_NY; i++)
                ok &= cr_isfinite(y1[i]);
            if (ok && y1[CR_Y_R] > 0.0)
                break;
            if (tries == 4) {
                px.outcome = CR_OUT_ERROR;
                break;
            }
            h *= 0.125;
        }
        if (px.outcome == CR_OUT_ERROR || !cr_isfinite(h))
            break;
        steps++;

        /* events inside this step */
        if (f->disc.enabled) {
            double v0 = y[CR_Y_TH] - 0.5 * CR_PI, v1 = y1[CR_Y_TH] - 0.5 * CR_PI;
            if (v0 != 0.0 && (v0 < 0.0) != (v1 < 0.0)) {
                double s = cr_event_locate(f, g, CR_EV_DISC, y, k1, h, v0, 1.0, v1, ys);
                double rr = ys[CR_Y_R];
                if (rr >= f->disc.r_in && rr <= f->disc.r_out) {
                    hit_disc = 1;
                    s_disc = s;
                }
            }
        }
        if (f->n_spheres > 0) {
            double ysp[CR_NY];
            cr_bl_to_cart(f->metric.a, y1[CR_Y_R], y1[CR_Y_TH], y1[CR_Y_PH], x1);
            hit_sphere = cr_sphere_events(f, g, y, k1, h, x0, x1, &s_sphere, ysp);
            if (hit_sphere >= 0 && (!hit_disc || s_sphere < s_disc)) {
                double xs[3];
                cr_bl_to_cart(f->metric.a, ysp[CR_Y_R], ysp[CR_Y_TH], ysp[CR_Y_PH], xs);
                px.outcome = CR_OUT_SPHERE;
                px.object = (int16_t)hit_sphere;
                px.color = cr_sphere_color(&f->spheres[hit_sphere], xs);
                px.redshift = cr_redshift_static(f, ysp[CR_Y_R], ysp[CR_Y_TH]);
                break;
            }
            for (i = 0; i < 3; i++)
                x0[i] = x1[i];
        }
        if (hit_disc) {
            int side = y[CR_Y_TH] < 0.5 * CR_PI ? 0 : 1;
            px.outcome = CR_OUT_DISC;
            px.object = (int16_t)side;
            px.color = cr_disc_color(&f->disc, ys[CR_Y_R], ys[CR_Y_PH], side);
            px.redshift = cr_redshift_static(f, ys[CR_Y_R], 0.5 * CR_PI);
            break;
        }

        turns += fabs(y1[CR_Y_PH] - y[CR_Y_PH]) / CR_TWO_PI;
        cr_geo_through_axis(y1);
        for (i = 0; i < CR_NY; i++)
            y[i] = y1[i];
    }
    px.steps = (uint32_t)steps;
    px.err_mean = n_err > 0 ? mean : 0.0;
    px.err_std = n_err > 0 ? sqrt(m2 / n_err) : 0.0;
    return px;
}

/* Trace pixel (i, j) of frame f (prepared by cr_frame_prepare). */
CR_HD static inline cr_pixel cr_trace_pixel(const cr_frame *f, int i, int j)
{
    double n[3], y[CR_NY];
    cr_geo g;
    cr_camera_pixel_dir(f, (double)i, (double)j, n);
    cr_camera_ray(f, n, &g, y);
    return cr_trace_ray(f, &g, y);
}

#endif
