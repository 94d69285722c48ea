/* curray core: spheres (cr_sphere, defs.h), defined in the Cartesian
 * coordinates (2.2.8) of coords.h: their frame and surface function, the
 * event that finds the earliest sphere hit inside a step, and the shading of
 * a hit (chessboard colour, static redshift, hit columns).
 */
#ifndef CR_CORE_SPHERE_H
#define CR_CORE_SPHERE_H

#include "pattern.h"
#include "ray.h"
#include "shift.h"

/* Derive the sphere's Cartesian centre and orientation. Its local axes start
 * as the paper's x = e_r, y = e_th, z = e_ph at the centre's (theta, phi) and
 * are turned by roll, pitch, yaw like the camera. The sphere's north pole is
 * local -y, longitude zero is local +x, longitude 90 deg local +z: a sphere
 * with no rotation has the latitude/longitude lines of the BL theta/phi. */
CR_HD static inline void cr_sphere_prepare(cr_sphere *s, double a)
{
    double st = sin(s->theta), ct = cos(s->theta), sp = sin(s->phi), cp = cos(s->phi);
    double loc[3][3];
    double e[3][3];
    int i, k;
    cr_bl_to_cart(a, s->r, s->theta, s->phi, s->center);
    /* Cartesian unit vectors e_r, e_th, e_ph at (theta, phi) */
    e[0][0] = st * cp; e[0][1] = st * sp; e[0][2] = ct;
    e[1][0] = ct * cp; e[1][1] = ct * sp; e[1][2] = -st;
    e[2][0] = -sp;     e[2][1] = cp;      e[2][2] = 0.0;
    /* sphere axes in local (x, y, z) components: lon 0, north, lon 90 */
    loc[0][0] = 1.0; loc[0][1] = 0.0;  loc[0][2] = 0.0;
    loc[1][0] = 0.0; loc[1][1] = -1.0; loc[1][2] = 0.0;
    loc[2][0] = 0.0; loc[2][1] = 0.0;  loc[2][2] = 1.0;
    cr_rotate_rpy(loc, 3, s->roll, s->pitch, s->yaw);
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++)
            s->axes[i][k] = loc[i][0] * e[0][k] + loc[i][1] * e[1][k] + loc[i][2] * e[2][k];
}

/* Squared distance from the sphere's centre minus radius^2 at Cartesian x. */
CR_HD static inline double cr_sphere_f(const cr_sphere *s, const double x[3])
{
    double d0 = x[0] - s->center[0], d1 = x[1] - s->center[1], d2 = x[2] - s->center[2];
    return d0 * d0 + d1 * d1 + d2 * d2 - s->radius * s->radius;
}

/* Colour of the sphere's surface at (or near) Cartesian point x. */
CR_HD static inline cr_rgb cr_sphere_color(const cr_sphere *s, const double x[3])
{
    double d[3], c[3], len, lat, lon;
    int k;
    for (k = 0; k < 3; k++)
        d[k] = x[k] - s->center[k];
    for (k = 0; k < 3; k++)
        c[k] = d[0] * s->axes[k][0] + d[1] * s->axes[k][1] + d[2] * s->axes[k][2];
    len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(len > 0.0))
        return s->color;
    lat = acos(fmax(-1.0, fmin(1.0, c[1] / len))); /* 0 at the north pole */
    lon = atan2(c[2], c[0]);
    if (lon < 0.0)
        lon += CR_TWO_PI;
    return cr_chess(cr_bin(lat / CR_PI, s->n_lat), cr_bin(lon / CR_TWO_PI, s->n_lon),
                    s->color);
}

/* Value of sphere k's surface function (cr_sphere_f) at state y of the
 * ray's integrator. */
CR_HD static inline double cr_sphere_value(const cr_frame *f, const cr_ray *ray, int k,
                                           const double *y)
{
    double x[3];
    cr_ray_cart(f, ray, y, x);
    return cr_sphere_f(&f->spheres[k], x);
}

/* Locate the root of sphere k's surface function inside the current step,
 * where the value is v0 at its start and v1 of opposite sign at fraction
 * s_hi, 0 < s_hi <= 1, by regula falsi (cr_falsi) on cr_ray_state_at.
 * Returns the fraction s and the state there in ys. */
CR_HD static inline double cr_sphere_locate(const cr_frame *f, const cr_ray *ray, int k,
                                            double v0, double s_hi, double v1, double *ys)
{
    cr_falsi z;
    cr_falsi_start(&z, v0, s_hi, v1);
    while (cr_falsi_next(&z)) {
        cr_ray_state_at(ray, z.s, ys);
        if (!cr_falsi_update(&z, cr_sphere_value(f, ray, k, ys)))
            break;
    }
    return z.s;
}

/* Smallest value of sphere event k along the current step, by golden-section
 * search of the step fraction on cr_ray_state_at (the squared distance to a
 * sphere along one step is unimodal). Returns the value, *s_min its place. */
CR_HD static inline double cr_sphere_dip(const cr_frame *f, const cr_ray *ray, int k,
                                         double *s_min, double *ys)
{
    cr_golden g;
    int it;
    cr_golden_start(&g, 0.0, 1.0);
    cr_ray_state_at(ray, g.x1, ys);
    g.f1 = cr_sphere_value(f, ray, k, ys);
    cr_ray_state_at(ray, g.x2, ys);
    g.f2 = cr_sphere_value(f, ray, k, ys);
    for (it = 0; it < 40 && g.f1 >= 0.0 && g.f2 >= 0.0; it++) {
        int which = cr_golden_shrink(&g);
        cr_ray_state_at(ray, which == 1 ? g.x1 : g.x2, ys);
        if (which == 1)
            g.f1 = cr_sphere_value(f, ray, k, ys);
        else
            g.f2 = cr_sphere_value(f, ray, k, ys);
    }
    *s_min = g.f1 < g.f2 ? g.x1 : g.x2;
    return g.f1 < g.f2 ? g.f1 : g.f2;
}

/* Earliest sphere hit within the current step (x0, x1 the Cartesian
 * positions at its ends). Catches both a sign change of |x - c|^2 - R^2 and
 * a ray that enters and leaves within the step: under RK4 (short, nearly
 * straight steps) where the chord passes inside the sphere; under Mino (a
 * step may cross much of the scene, and its fraction is not proportional to
 * the distance along the chord) where the chord passes within R plus a
 * quarter of its length, the step's closest approach is found by
 * cr_sphere_dip.
 * Returns the sphere index or -1; on a hit, *s_out and ys hold the located
 * point. */
CR_HD static inline int cr_sphere_events(const cr_frame *f, const cr_ray *ray,
                                         const double x0[3], const double x1[3], double *s_out,
                                         double *ys)
{
    int best = -1, k;
    double best_s = 2.0, tmp[CR_RAY_NY];
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
            if (cr_ray_long_steps(ray)) {
                double dist2 = 0.0, slack = sp->radius + 0.25 * sqrt(dd);
                t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
                for (i = 0; i < 3; i++) {
                    xm[i] = x0[i] + t * d[i] - sp->center[i];
                    dist2 += xm[i] * xm[i];
                }
                if (dist2 >= slack * slack)
                    continue;
                v1 = cr_sphere_dip(f, ray, k, &t, tmp);
            } else {
                if (t <= 0.0 || t >= 1.0)
                    continue;
                for (i = 0; i < 3; i++)
                    xm[i] = x0[i] + t * d[i];
                if (cr_sphere_f(sp, xm) >= 0.0)
                    continue;
                cr_ray_state_at(ray, t, tmp);
                v1 = cr_sphere_value(f, ray, k, tmp);
            }
            if (v1 >= 0.0)
                continue;
            s_hi = t;
        }
        if (s_hi >= best_s)
            continue;
        s = cr_sphere_locate(f, ray, k, v0, s_hi, v1, tmp);
        if (s < best_s) {
            int i;
            best_s = s;
            best = k;
            for (i = 0; i < CR_RAY_NY; i++)
                ys[i] = tmp[i];
        }
    }
    *s_out = best_s;
    return best;
}

/* The spheres' event of the current step: the earliest sphere hit inside
 * it (cr_sphere_events) at a radius the ray reaches (cr_ray_outside_stop).
 * x0 is the Cartesian position at the step's start; it is moved to the
 * step's end. Returns 1 with h set on a hit, else 0. */
CR_HD static inline int cr_sphere_event(const cr_frame *f, const cr_ray *ray, double x0[3],
                                        cr_hit *h)
{
    double x1[3], rr, th, ph;
    int k, i, hit = 0;
    if (f->n_spheres <= 0)
        return 0;
    cr_ray_cart(f, ray, cr_ray_y1(ray), x1);
    k = cr_sphere_events(f, ray, x0, x1, &h->s, h->y);
    if (k >= 0) {
        cr_ray_position(ray, h->y, &rr, &th, &ph);
        if (cr_ray_outside_stop(f, ray, rr)) {
            h->index = k;
            hit = 1;
        }
    }
    for (i = 0; i < 3; i++)
        x0[i] = x1[i];
    return hit;
}

/* Shade a sphere hit h: outcome, sphere index, hit radius and azimuth, delay, the
 * chessboard colour there and the redshift of a static source (6.9). */
CR_HD static inline void cr_sphere_shade(const cr_frame *f, const cr_ray *ray, const cr_hit *h,
                                         cr_pixel *px)
{
    double xs[3], rr, th, ph, p[4];
    cr_ray_cart(f, ray, h->y, xs);
    cr_ray_position(ray, h->y, &rr, &th, &ph);
    px->outcome = CR_OUT_SPHERE;
    px->object = (int16_t)h->index;
    px->hit_r = rr;
    px->hit_phi = cr_wrap_2pi(ph);
    px->delay = cr_ray_delay_at(ray, h->s, h->y);
    px->color = cr_sphere_color(&f->spheres[h->index], xs);
    cr_ray_momentum(ray, h->y, p);
    px->redshift = cr_redshift_static(f, ray->p_obs, p, rr, th);
}

#endif
