/* curray core: a particle's worldline tabulated in BL coordinate time, the
 * table a sphere of motion: particle moves on (sphere.h).
 *
 * The worldline (particle.h) is sampled at n uniformly spaced coordinate
 * times t_i = t0 + i h, i = 0 .. n - 1, from its start t0 to its end t_end:
 * where its proper time reaches tau, or where it reached the horizon stop
 * r+ + eps or r_max (particle.h). Each sample (cr_track_point, defs.h) holds
 * the Cartesian position x (2.2.8), the continuous azimuth ph and their
 * rates dx/dt, dph/dt = u^i / u^t at that time. Between samples x(t) and
 * ph(t) are the cubic Hermite interpolants of the values and rates at both
 * ends (error ~ h^4 |x''''| / 384); outside [t0, t_end] there is no point.
 */
#ifndef CR_CORE_TRACK_H
#define CR_CORE_TRACK_H

#include "coords.h"
#include "particle.h"

/* Most samples in one table, and the spacing sought (units of M): the
 * spacing is the larger of CR_TRACK_H and span / (CR_TRACK_MAX - 1). */
#define CR_TRACK_MAX 65536
#define CR_TRACK_H 0.05

/* The point of table tab (n >= 2 samples at t0 + i h) at time t: position
 * x, azimuth *ph and their rates v = dx/dt, *w = dph/dt, by cubic Hermite
 * interpolation. Returns 0 (nothing set) where t is outside [t0, t0 + (n -
 * 1) h] or not finite, else 1. */
CR_HD static inline int cr_track_at(const cr_track_point *tab, int n, double t0, double h,
                                    double t, double x[3], double *ph, double v[3], double *w)
{
    double u = (t - t0) / h, s, s2, h00, h10, h01, h11, d00, d10, d01, d11;
    const cr_track_point *p, *q;
    int i, k;
    if (!(u >= 0.0 && u <= (double)(n - 1)) || n < 2)
        return 0;
    i = (int)u;
    if (i > n - 2)
        i = n - 2;
    s = u - (double)i;
    s2 = s * s;
    p = &tab[i];
    q = &tab[i + 1];
    h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
    h10 = s * (1.0 - s) * (1.0 - s);
    h01 = s2 * (3.0 - 2.0 * s);
    h11 = s2 * (s - 1.0);
    /* their derivatives in s (d/dt = d/ds / h) */
    d00 = 6.0 * s2 - 6.0 * s;
    d10 = 3.0 * s2 - 4.0 * s + 1.0;
    d01 = -d00;
    d11 = 3.0 * s2 - 2.0 * s;
    for (k = 0; k < 3; k++) {
        x[k] = h00 * p->x[k] + h10 * h * p->v[k] + h01 * q->x[k] + h11 * h * q->v[k];
        v[k] = (d00 * p->x[k] + d01 * q->x[k]) / h + d10 * p->v[k] + d11 * q->v[k];
    }
    *ph = h00 * p->ph + h10 * h * p->w + h01 * q->ph + h11 * h * q->w;
    *w = (d00 * p->ph + d01 * q->ph) / h + d10 * p->w + d11 * q->w;
    return 1;
}

/* The sample of worldline point q (particle.h) on metric spin a. */
CR_HD static inline void cr_track_sample(double a, const cr_particle_point *q,
                                         cr_track_point *out)
{
    int k;
    cr_bl_vel_to_cart(a, q->r, q->th, q->ph, q->u[1] / q->u[0], q->u[2] / q->u[0],
                      q->u[3] / q->u[0], out->v);
    for (k = 0; k < 3; k++)
        out->x[k] = q->x[k];
    out->ph = q->ph;
    out->w = q->u[3] / q->u[0];
}

/* The coordinate time *t_end at which particle p (just started) ends: its
 * proper time reaches tau (> 0), or it reaches the horizon stop or r_max
 * (*ended: particle.h's CR_PARTICLE_*, RUNNING for tau). p is stepped
 * there, or only until its t passes t_max (then *t_end > t_max: too long
 * for the caller's table). Returns 0, or -1 where the integration failed. */
CR_HD static inline int cr_track_span(cr_particle *p, double tau, double t_max, double *t_end,
                                      int *ended)
{
    while (!p->ended && p->tau1 < tau && !(p->t1 > t_max))
        cr_particle_step(p);
    if (p->t1 > t_max && p->ended != CR_PARTICLE_FAILED) {
        *t_end = p->t1;
        *ended = CR_PARTICLE_RUNNING;
        return 0;
    }
    if (p->ended == CR_PARTICLE_FAILED)
        return -1;
    if (p->tau1 >= tau && p->hm > 0.0) {
        double ys[CR_MN], tq;
        cr_particle_dense(p, cr_particle_find_tau(p, tau), ys, t_end, &tq);
        *ended = CR_PARTICLE_RUNNING;
    } else {
        *t_end = p->t1;
        *ended = p->ended;
    }
    return cr_isfinite(*t_end) ? 0 : -1;
}

/* The number of samples of a table over [t0, t_end] (CR_TRACK_H, capped by
 * CR_TRACK_MAX) and its spacing *h. */
CR_HD static inline int cr_track_count(double t0, double t_end, double *h)
{
    double span = t_end - t0, m = ceil(span / CR_TRACK_H);
    int n = m + 1.0 > (double)CR_TRACK_MAX ? CR_TRACK_MAX : (int)m + 1;
    if (n < 2)
        n = 2;
    *h = span / (double)(n - 1);
    return n;
}

/* Fill out[0 .. n - 1] with the samples of particle p (just started, at
 * p->t0; the same start as cr_track_span's) at t0 + i h, h = (t_end - t0) /
 * (n - 1): p is stepped along (the same steps as cr_track_span's), each
 * sample located in its step by cr_particle_find_t. Returns 0, or -1 where
 * the integration failed before t_end. */
CR_HD static inline int cr_track_fill(cr_particle *p, double t_end, int n, cr_track_point *out)
{
    double t0 = p->t0, h = (t_end - t0) / (double)(n - 1);
    cr_particle_point q;
    int i = 1;
    cr_particle_current(p, &q);
    cr_track_sample(p->mt.a, &q, &out[0]);
    while (i < n) {
        int ended = cr_particle_step(p);
        if (ended == CR_PARTICLE_FAILED)
            return -1;
        for (; i < n; i++) {
            double ti = i == n - 1 ? t_end : t0 + (double)i * h;
            if (ti > p->t1 && !ended)
                break;
            /* past the last step's end only by rounding */
            cr_particle_at(p, ti >= p->t1 ? 1.0 : cr_particle_find_t(p, ti), &q);
            cr_track_sample(p->mt.a, &q, &out[i]);
        }
        if (ended)
            break;
    }
    return i == n ? 0 : -1;
}

#endif
