/* curray core: the frame (cr_frame, defs.h; the defaults and limits of its
 * raytracer settings: src/input/settings.def): its lengths in units of M, and
 * the derived fields every ray reads (cr_frame_prepare).
 */
#ifndef CR_CORE_FRAME_H
#define CR_CORE_FRAME_H

#include "camera.h"

/* The scene boundary when nothing else asks for more: beyond every photon
 * orbit of a Kerr-Newman hole (r <= 4M), so an outgoing ray there escapes. */
#define CR_MIN_R_MAX_OVER_M 6.0

/* Inside the inner horizon: a ray that comes closer to r = 0 than this (in
 * units of M) ends as CR_OUT_SINGULARITY (ray.h). w = 1/r cannot pass r = 0
 * (a != 0: the disc inside the ring, beyond which r < 0), and a ray that
 * turns inside this radius is taken for one that does not: for
 * Reissner-Nordstrom rays with K < E^2 1e-24 / Q^2 (the turning radius is
 * (K Q^2 / E^2)^(1/4) for small K), for Kerr those with Carter constant
 * 0 < eta < 2e-6 K / a^2 (turning radius a^2 eta / (2 M K)). */
#define CR_R_SING 1e-6
/* The smallest observer.r inside the horizon, in units of M (100 CR_R_SING:
 * its rays start well away from where they would end). */
#define CR_R_SING_OBS 1e-4

/* Express every length of a frame in units of M (DESIGN "Conventions"), so
 * that an image never depends on the choice of M: divides the metric, the
 * observer's r and image-plane extents, the disc radii, the sky boundary and
 * the observer's time by M, and sets M = 1. Spheres are scaled by cr_sphere_to_units_of_m.
 * The dimensionless settings (horizon_epsilon, step_multiplier, tolerance)
 * are read in units of M. Call before cr_frame_prepare. */
CR_HD static inline void cr_frame_to_units_of_m(cr_frame *f)
{
    double k = 1.0 / f->metric.m;
    f->metric.a *= k;
    f->metric.q *= k;
    f->metric.m = 1.0;
    f->observer.r *= k;
    f->observer.hextent *= k;
    f->observer.vextent *= k;
    f->disc.r_in *= k;
    f->disc.r_out *= k;
    f->sky_boundary *= k;
    f->t_obs *= k;
}

/* The same for a sphere prepared (cr_sphere_prepare) on a metric of mass m
 * (its angular velocity, a rate, is multiplied by m). */
CR_HD static inline void cr_sphere_to_units_of_m(cr_sphere *s, double m)
{
    double k = 1.0 / m;
    int i;
    s->r *= k;
    s->radius *= k;
    s->omega *= m; /* 1 / time */
    for (i = 0; i < 3; i++)
        s->center[i] *= k;
}

/* Complete the derived fields of a frame whose scene and settings are set.
 * Requires a validated scene (a horizon, a static observer outside the
 * ergosurface or at infinity, a moving one outside r+ or, under Mino, an
 * infalling or velocity observer inside r+, r != r+-, r > 0, 2Mr > Q^2).
 * Spheres must already be prepared
 * (cr_sphere_prepare). */
CR_HD static inline void cr_frame_prepare(cr_frame *f)
{
    int at_inf = isinf(f->observer.r) && f->observer.r > 0.0;
    /* With a plain sky an outgoing ray beyond every object and every photon
     * orbit has its outcome (sky), its colour and its frequency ratio (from
     * E alone, u_em = (1, 0, 0, 0)) settled: the scene ends there, whatever
     * the observer's distance or the sky boundary. A sky image needs the
     * direction at the boundary (6.10), so the observer and the boundary
     * count there. */
    int plain = !f->sky.rgb;
    double rm = at_inf || plain ? 0.0 : f->observer.r, ro = 0.0;
    int k;
    f->r_stop = cr_metric_r_plus(&f->metric) + f->horizon_epsilon;
    f->w_stop = 1.0 / f->r_stop;
    /* from inside the horizon: where rays bound for the other side end */
    f->w_other = 1.0 / (cr_metric_r_plus(&f->metric) - f->horizon_epsilon);
    /* from inside r-: where rays leave it, and where they end at r = 0 */
    f->w_minus = 1.0 / cr_metric_r_minus(&f->metric);
    f->w_sing = 1.0 / (CR_R_SING * f->metric.m);
    if (f->disc.enabled)
        ro = f->disc.r_out;
    for (k = 0; k < f->n_spheres; k++) {
        const double *c = f->spheres[k].center;
        /* Cartesian distance bounds BL r from above: |x|^2 = r^2 + a^2 sin^2 */
        double ext = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + f->spheres[k].radius;
        if (f->spheres[k].particle && f->spheres[k].wl.reach_hi > ext) /* over its worldline */
            ext = f->spheres[k].wl.reach_hi;
        if (ext > ro)
            ro = ext;
    }
    f->w_obj = ro > 0.0 ? 1.0 / ro : INFINITY;
    if (ro > rm)
        rm = ro;
    rm += f->metric.m;
    if (rm < CR_MIN_R_MAX_OVER_M * f->metric.m)
        rm = CR_MIN_R_MAX_OVER_M * f->metric.m;
    if (!plain && f->sky_boundary > rm)
        rm = f->sky_boundary;
    f->r_max = at_inf ? INFINITY : rm;
    f->w_sky = (f->sky.rgb && !(f->sky_boundary > 0.0)) ? 0.0 : 1.0 / rm;
    f->disc.r_hit_in = f->disc.plunge ? cr_metric_r_plus(&f->metric) : f->disc.r_in;
    cr_camera_prepare(f);
}

#endif
