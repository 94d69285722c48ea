/* curray core: null geodesics of Kerr-Newman spacetime.
 *
 * Integrated system (section 2.3.2, 6.5): the state is
 *   y = (t, r, theta, phi, u^r, u^theta),
 * with u^t and u^phi given by the conserved E = u_t and L = u_phi through the
 * first-order equations (2.3.8)/(2.3.9), written in the better-conditioned
 * form of ERRATA.md and with sin^2(theta) cancelled analytically:
 *   u^t   = -(E A + L a W) / (Sigma Delta)
 *   u^phi = (-E a W + L (Delta - a^2 sin^2)/sin^2) / (Sigma Delta)
 * (A = (r^2+a^2)^2 - Delta a^2 sin^2, W = 2Mr - Q^2), and u^r, u^theta by the
 * second-order equations (2.3.10)/(2.3.11). E and L are exact constants of
 * this system by construction.
 */
#ifndef CR_CORE_GEODESIC_H
#define CR_CORE_GEODESIC_H

#include "coords.h"
#include "metric.h"

enum { CR_Y_T = 0, CR_Y_R, CR_Y_TH, CR_Y_PH, CR_Y_UR, CR_Y_UTH, CR_NY };

/* The constants of one ray: metric, E = u_t (2.3.5), L = u_phi (2.3.6), and
 * th_floor, the smallest angular distance from the polar axis the step
 * control needs to resolve (see cr_geo_step_size; set by cr_geo_set_floor). */
typedef struct cr_geo {
    cr_metric mt;
    double E, L;
    double th_floor;
} cr_geo;

/* All four velocity components u^mu at a state. */
CR_HD static inline void cr_geo_velocity(const cr_geo *g, const double *y,
                                         const cr_metric_point *p, double u[4])
{
    double a = g->mt.a;
    double sd = p->sigma * p->delta;
    /* L = 0 exactly on the axis, where the centrifugal term is 0/0 -> 0. */
    double lterm = g->L == 0.0 ? 0.0 : g->L * (p->delta - a * a * p->sin2) / p->sin2;
    u[0] = -(g->E * p->A_ + g->L * a * p->W_) / sd;
    u[1] = y[CR_Y_UR];
    u[2] = y[CR_Y_UTH];
    u[3] = (-g->E * a * p->W_ + lterm) / sd;
}

/* Right-hand side dy/dlambda. Also returns u^mu at y (for step control and
 * the null error) when u_out is not NULL, and the metric there when p_out is
 * not NULL. */
CR_HD static inline void cr_geo_rhs_full(const cr_geo *g, const double *y, double *dy,
                                         double *u_out, cr_metric_point *p_out)
{
    cr_metric_point p;
    cr_christoffel G;
    double u[4];
    double r = y[CR_Y_R];
    cr_metric_eval(&g->mt, r, y[CR_Y_TH], &p);
    cr_christoffel_eval(&g->mt, r, &p, &G);
    cr_geo_velocity(g, y, &p, u);
    {
        double ut2 = u[0] * u[0], ur2 = u[1] * u[1], uth2 = u[2] * u[2],
               uph2 = u[3] * u[3], utuph = u[0] * u[3], uruth = u[1] * u[2];
        dy[CR_Y_T] = u[0];
        dy[CR_Y_R] = u[1];
        dy[CR_Y_TH] = u[2];
        dy[CR_Y_PH] = u[3];
        /* (2.3.10) */
        dy[CR_Y_UR] = -G.r_tt * ut2 - G.r_rr * ur2 - G.r_thth * uth2 - G.r_phph * uph2 -
                      2.0 * G.r_tph * utuph - 2.0 * G.r_rth * uruth;
        /* (2.3.11) */
        dy[CR_Y_UTH] = -G.th_tt * ut2 - G.th_rr * ur2 - G.th_thth * uth2 -
                       G.th_phph * uph2 - 2.0 * G.th_tph * utuph - 2.0 * G.th_rth * uruth;
    }
    if (u_out) {
        u_out[0] = u[0];
        u_out[1] = u[1];
        u_out[2] = u[2];
        u_out[3] = u[3];
    }
    if (p_out)
        *p_out = p;
}

CR_HD static inline void cr_geo_rhs(const cr_geo *g, const double *y, double *dy)
{
    cr_geo_rhs_full(g, y, dy, 0, 0);
}

/* One classical RK4 step (6.5.4)-(6.5.8) of size h from y, given k1 = f(y).
 * Writes the new state to y1 (may not alias y). */
CR_HD static inline void cr_geo_rk4(const cr_geo *g, const double *y, const double *k1,
                                    double h, double *y1)
{
    double k2[CR_NY], k3[CR_NY], k4[CR_NY], tmp[CR_NY];
    int i;
    for (i = 0; i < CR_NY; i++)
        tmp[i] = y[i] + 0.5 * h * k1[i];
    cr_geo_rhs(g, tmp, k2);
    for (i = 0; i < CR_NY; i++)
        tmp[i] = y[i] + 0.5 * h * k2[i];
    cr_geo_rhs(g, tmp, k3);
    for (i = 0; i < CR_NY; i++)
        tmp[i] = y[i] + h * k3[i];
    cr_geo_rhs(g, tmp, k4);
    for (i = 0; i < CR_NY; i++)
        y1[i] = y[i] + h * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0;
}

/* Step size rule (6.6.1), h = c / max(|u^t|, |u^r|, |u^theta|, |u^phi|),
 * extended by one term for the polar axis: |u^theta| / s with
 * s = max(min(theta, pi - theta), th_floor). Near the axis u^phi ~ L/sin^2
 * spikes within a few steps; (6.6.1) alone sizes the step at its start and
 * jumps over the spike. The extra term makes theta change by at most a
 * fraction c of the distance to the axis per step, down to the ray's closest
 * possible approach th_floor, so a ray reaches the axis region in
 * O(log(theta/th_floor)/c) steps and is resolved there. Away from the axis
 * (s of order 1) the term never binds. */
CR_HD static inline double cr_geo_step_size(const cr_geo *g, double c, double th,
                                            const double u[4])
{
    double m = fabs(u[0]);
    double s = th < CR_PI - th ? th : CR_PI - th;
    if (s < g->th_floor)
        s = g->th_floor;
    if (fabs(u[1]) > m)
        m = fabs(u[1]);
    if (fabs(u[2]) > m)
        m = fabs(u[2]);
    if (fabs(u[3]) > m)
        m = fabs(u[3]);
    if (fabs(u[2]) / s > m)
        m = fabs(u[2]) / s;
    return c / m;
}

/* Null error (6.7.1): |1 + (g_rr ur^2 + g_thth uth^2 + g_phph uph^2
 * + 2 g_tphi ut uph) / (g_tt ut^2)|. Returns -1 where g_tt ut^2 vanishes
 * (exactly on the ergosurface), where the ratio is undefined. */
CR_HD static inline double cr_geo_null_error(const cr_metric_point *p, const double u[4])
{
    double den = p->g_tt * u[0] * u[0];
    double num = p->g_rr * u[1] * u[1] + p->g_thth * u[2] * u[2] +
                 p->g_phph * u[3] * u[3] + 2.0 * p->g_tph * u[0] * u[3];
    if (den == 0.0)
        return -1.0;
    return fabs(1.0 + num / den);
}

/* Scale-free null norm g(u,u) / (|g_tt| ut^2 + g_rr ur^2 + g_thth uth^2
 * + g_phph uph^2 + 2|g_tphi ut uph|): zero for an exact null vector, bounded
 * by 1 in magnitude and well defined everywhere outside the horizon (unlike
 * (6.7.1) at the ergosurface). Used by the tests. */
CR_HD static inline double cr_geo_null_norm(const cr_metric_point *p, const double u[4])
{
    double tt = p->g_tt * u[0] * u[0], rr = p->g_rr * u[1] * u[1],
           hh = p->g_thth * u[2] * u[2], pp = p->g_phph * u[3] * u[3],
           tp = 2.0 * p->g_tph * u[0] * u[3];
    return (tt + rr + hh + pp + tp) / (fabs(tt) + rr + hh + pp + fabs(tp));
}

/* E = g_tt u^t + g_tphi u^phi (2.3.5) and L = g_phph u^phi + g_tphi u^t (2.3.6). */
CR_HD static inline void cr_geo_constants(const cr_metric_point *p, const double u[4],
                                          double *E, double *L)
{
    *E = p->g_tt * u[0] + p->g_tph * u[3];
    *L = p->g_phph * u[3] + p->g_tph * u[0];
}

/* Carter constant of a null geodesic,
 * K = p_theta^2 + cos^2(theta) (L^2/sin^2(theta) - a^2 E^2), p_theta = Sigma u^theta.
 * (Charge enters only through Delta and leaves this form unchanged.) */
CR_HD static inline double cr_geo_carter(const cr_geo *g, const double *y)
{
    double s = sin(y[CR_Y_TH]), c = cos(y[CR_Y_TH]), a2 = g->mt.a * g->mt.a;
    double sigma = y[CR_Y_R] * y[CR_Y_R] + a2 * c * c;
    double pth = sigma * y[CR_Y_UTH];
    double l2 = g->L == 0.0 ? 0.0 : g->L * g->L / (s * s);
    return pth * pth + c * c * (l2 - a2 * g->E * g->E);
}

/* Set g->th_floor from the ray's constants: near the axis (cos^2 ~ 1) the
 * theta turning point has sin^2(theta_min) ~ L^2 / (K + L^2 + a^2 E^2) with K
 * the Carter constant; never below 1e-8 rad. A ray with L = 0 exactly has no
 * u^phi spike and passes straight through the axis, where the equations are
 * analytic: the axis term is not needed (th_floor = pi/2, it never binds). */
CR_HD static inline void cr_geo_set_floor(cr_geo *g, const double *y)
{
    double K, den, sm;
    if (g->L == 0.0) {
        g->th_floor = 0.5 * CR_PI;
        return;
    }
    K = cr_geo_carter(g, y);
    den = K + g->L * g->L + g->mt.a * g->mt.a * g->E * g->E;
    sm = den > 0.0 ? fabs(g->L) / sqrt(den) : 1.0;
    g->th_floor = sm >= 1.0 ? 0.5 * CR_PI : asin(sm);
    if (g->th_floor < 1e-8)
        g->th_floor = 1e-8;
}

/* Continue a ray through the polar axis (ERRATA item 2). The equations are
 * even under theta -> -theta (with u^theta -> -u^theta), and BL theta < 0 or
 * theta > pi names the same point as (|theta| or 2pi - theta, phi + pi). Maps
 * the state back into [0, pi]; returns 1 when it reflected. */
CR_HD static inline int cr_geo_through_axis(double *y)
{
    double th = y[CR_Y_TH];
    if (th >= 0.0 && th <= CR_PI)
        return 0;
    th = fmod(th, CR_TWO_PI);
    if (th < 0.0)
        th += CR_TWO_PI;
    if (th > CR_PI) {
        y[CR_Y_TH] = CR_TWO_PI - th;
        y[CR_Y_UTH] = -y[CR_Y_UTH];
        y[CR_Y_PH] += CR_PI;
    } else {
        y[CR_Y_TH] = th;
    }
    return 1;
}

/* Sky direction (6.10.3)/(6.10.4) of an escaping ray: polar angle and
 * azimuth in [0, 2pi) of its Cartesian direction of motion. With backward
 * tracing this is the direction of the source on the sky. */
CR_HD static inline void cr_sky_direction(double a, const double *y, double uph,
                                          double *sky_th, double *sky_ph)
{
    double v[3], len;
    cr_bl_vel_to_cart(a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], y[CR_Y_UR], y[CR_Y_UTH], uph, v);
    len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    *sky_th = acos(fmax(-1.0, fmin(1.0, v[2] / len)));
    *sky_ph = atan2(v[1], v[0]);
    if (*sky_ph < 0.0)
        *sky_ph += CR_TWO_PI;
}

#endif
