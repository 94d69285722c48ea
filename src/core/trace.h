/* curray core: tracing one ray, and cr_trace_pixel, the ONE implementation
 * both backends run for every pixel.
 *
 * One loop (chapter 6) for both integrators (frame field integrator): from
 * the observer's state, repeat
 *   break conditions (6.8): at the horizon stop -> horizon; beyond the sky
 *     radius moving outward -> sky; step or turn limit -> limit;
 *   one step (cr_ray_advance):
 *     CR_INTEG_RK4: h by (6.6.1), one RK4 step in the affine parameter,
 *       non-finite result -> retry smaller, then error;
 *     CR_INTEG_MINO: one accepted Dormand-Prince 5(4) step in Mino time
 *       (mino.h), repeated smaller while its error estimate exceeds the
 *       tolerance;
 *   events inside the step (cr_ray_state_at gives the state at any fraction
 *     of it: partial RK4 steps from its start, or the DP5 dense output): the
 *     disc plane theta = pi/2 and every sphere surface are located by root
 *     finding, and the earliest hit ends the ray; under Mino the crossing of
 *     the sky radius is located the same way;
 *   continue through the polar axis (RK4; the Mino state passes it
 *     smoothly); accumulate the error monitor: the null error (6.7.1) under
 *     RK4, the first-integral residual of mino.h under Mino.
 */
#ifndef CR_CORE_TRACE_H
#define CR_CORE_TRACE_H

#include "disc.h"
#include "frame.h"
#include "sky.h"
#include "sphere.h"

/* Largest state of either integrator. */
#define CR_RAY_NY ((int)CR_MN > (int)CR_NY ? (int)CR_MN : (int)CR_NY)

/* One ray under either integrator: its constants, its state, and the step
 * from that state (to y1 / m1) while events are looked for inside it. */
typedef struct cr_ray {
    int kind; /* cr_integrator */
    /* CR_INTEG_RK4 */
    cr_geo g;
    double y[CR_NY], y1[CR_NY], k1[CR_NY], u[4];
    double h; /* the current step */
    /* CR_INTEG_MINO */
    cr_mino c;
    double m[CR_MN], m1[CR_MN];
    cr_dp5 st;     /* stages; st.k[0] = f(m) */
    double hm;     /* the current step */
    double h_next; /* the next trial step */
    /* Path recorder (cr_path, below): NULL except when one ray's path is
     * wanted (--trace, curray.trace); set by the ray's maker to NULL. */
    struct cr_path *path;
    /* Covariant momentum at the observer (cr_ray_momentum of the first
     * state), the observer's side of every frequency ratio (cr_frame_shift);
     * set by cr_ray_mino_start and cr_ray_from_bl. */
    double p_obs[4];
} cr_ray;

/* The state at fraction s in [0, 1] of the current step. */
CR_HD static inline void cr_ray_state_at(const cr_ray *ray, double s, double *ys)
{
    if (ray->kind == CR_INTEG_MINO)
        cr_dp5_dense(&ray->st, ray->m, ray->m1, ray->hm, s, ys);
    else
        cr_geo_rk4(&ray->g, ray->y, ray->k1, s * ray->h, ys);
}

/* Cartesian position (2.2.8) of a state of the ray's integrator. */
CR_HD static inline void cr_ray_cart(const cr_frame *f, const cr_ray *ray, const double *y,
                                     double x[3])
{
    if (ray->kind == CR_INTEG_MINO)
        cr_mino_cart(f->metric.a, y, x);
    else
        cr_bl_to_cart(f->metric.a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], x);
}

/* BL r, theta, phi of a state of the ray's integrator. */
CR_HD static inline void cr_ray_position(const cr_ray *ray, const double *y, double *r,
                                         double *th, double *ph)
{
    if (ray->kind == CR_INTEG_MINO) {
        double c, s;
        cr_mino_position(y, r, &c, &s, ph);
        *th = atan2(s, c);
    } else {
        *r = y[CR_Y_R];
        *th = y[CR_Y_TH];
        *ph = y[CR_Y_PH];
    }
}

/* Covariant momentum p_mu of the ray (its backward tangent -k, geodesic.h
 * convention: p_t = E, p_phi = L) at a state y of the ray's integrator. RK4:
 * p_r = g_rr u^r, p_theta = g_thth u^theta. Mino: dr/dtau = Sigma dr/dlambda
 * gives p_r = (dr/dtau) / Delta = -(dw/dtau) / D(w) (D = Delta / r^2), and
 * p_theta = dtheta/dtau = -(dn_z/dtau) / sin(theta) (0 on the axis). */
CR_HD static inline void cr_ray_momentum(const cr_ray *ray, const double *y, double p[4])
{
    if (ray->kind == CR_INTEG_MINO) {
        double w = y[CR_M_W], st = sqrt(y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY]);
        p[0] = ray->c.E;
        p[1] = -y[CR_M_DW] / (1.0 + w * (ray->c.d1 + w * ray->c.d2));
        p[2] = st > 0.0 ? -y[CR_M_DNZ] / st : 0.0;
        p[3] = ray->c.L;
    } else {
        cr_metric_point q;
        cr_metric_eval(&ray->g.mt, y[CR_Y_R], y[CR_Y_TH], &q);
        p[0] = ray->g.E;
        p[1] = q.g_rr * y[CR_Y_UR];
        p[2] = q.g_thth * y[CR_Y_UTH];
        p[3] = ray->g.L;
    }
}

/* Event kinds located inside a step: the disc plane, the sky radius (Mino
 * only), or a sphere index >= 0. */
enum { CR_EV_DISC = -1, CR_EV_SKY = -2 };

/* Value of event function ev at state y of the ray's integrator. The disc's
 * is theta - pi/2 under RK4 and -cos(theta) (same sign) under Mino. */
CR_HD static inline double cr_event_value(const cr_frame *f, const cr_ray *ray, int ev,
                                          const double *y)
{
    double x[3];
    if (ev == CR_EV_DISC)
        return ray->kind == CR_INTEG_MINO ? -y[CR_M_NZ] : y[CR_Y_TH] - 0.5 * CR_PI;
    if (ev == CR_EV_SKY)
        return y[CR_M_W] - f->w_sky;
    cr_ray_cart(f, ray, y, x);
    return cr_sphere_f(&f->spheres[ev], x);
}

/* Locate the root of event ev inside the current step, where the value is v0
 * at its start and v1 of opposite sign at fraction s_hi, 0 < s_hi <= 1, by
 * the Illinois variant of regula falsi on cr_ray_state_at. Returns the
 * fraction s and the state there in ys. */
CR_HD static inline double cr_event_locate(const cr_frame *f, const cr_ray *ray, int ev,
                                           double v0, double s_hi, double v1, double *ys)
{
    double s_lo = 0.0, s = s_hi;
    int side = 0, it;
    for (it = 0; it < 60; it++) {
        double v;
        s = (s_lo * v1 - s_hi * v0) / (v1 - v0);
        cr_ray_state_at(ray, s, ys);
        v = cr_event_value(f, ray, ev, ys);
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
    g.f1 = cr_event_value(f, ray, k, ys);
    cr_ray_state_at(ray, g.x2, ys);
    g.f2 = cr_event_value(f, ray, k, ys);
    for (it = 0; it < 40 && g.f1 >= 0.0 && g.f2 >= 0.0; it++) {
        int which = cr_golden_shrink(&g);
        cr_ray_state_at(ray, which == 1 ? g.x1 : g.x2, ys);
        if (which == 1)
            g.f1 = cr_event_value(f, ray, k, ys);
        else
            g.f2 = cr_event_value(f, ray, k, ys);
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
            if (ray->kind == CR_INTEG_MINO) {
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
                v1 = cr_event_value(f, ray, k, tmp);
            }
            if (v1 >= 0.0)
                continue;
            s_hi = t;
        }
        if (s_hi >= best_s)
            continue;
        s = cr_event_locate(f, ray, k, v0, s_hi, v1, tmp);
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

/* Start a Mino ray from a BL state (RK4 layout) and constants. */
CR_HD static inline void cr_ray_mino_start(const cr_frame *f, cr_ray *ray)
{
    ray->kind = CR_INTEG_MINO;
    ray->path = 0;
    if (fabs(ray->m[CR_M_NZ]) < 1e-15) /* cos(pi/2) rounded: on the disc plane */
        ray->m[CR_M_NZ] = 0.0;
    cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
    ray->h_next = cr_mino_first_step(&ray->c, f->tolerance);
    cr_ray_momentum(ray, ray->m, ray->p_obs);
}

/* The ray of the frame's integrator from the BL state y and constants g made
 * by cr_camera_ray. */
CR_HD static inline void cr_ray_from_bl(const cr_frame *f, const cr_geo *g, const double *y,
                                        cr_ray *ray)
{
    int i;
    ray->path = 0;
    ray->g = *g;
    for (i = 0; i < CR_NY; i++)
        ray->y[i] = y[i];
    if (f->integrator == CR_INTEG_MINO) {
        cr_mino_from_bl(g, y, f->w_stop, &ray->c, ray->m);
        cr_ray_mino_start(f, ray);
    } else {
        ray->kind = CR_INTEG_RK4;
        cr_ray_momentum(ray, ray->y, ray->p_obs);
    }
}

/* Derivatives at the current state, and the error monitor there (negative
 * where it is undefined). */
CR_HD static inline double cr_ray_begin(cr_ray *ray)
{
    cr_metric_point p;
    if (ray->kind == CR_INTEG_MINO)
        return cr_mino_monitor(&ray->c, ray->m);
    cr_geo_rhs_full(&ray->g, ray->y, ray->k1, ray->u, &p);
    return cr_geo_null_error(&p, ray->u);
}

CR_HD static inline int cr_ray_at_horizon(const cr_frame *f, const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO ? ray->m[CR_M_W] >= f->w_stop
                                      : ray->y[CR_Y_R] <= f->r_stop;
}

/* Whether a hit located at BL radius r counts. A Mino step can carry the
 * ray past the horizon stop r+ + epsilon, where the ray ends (6.8), so an
 * event located beyond it is not seen; RK4 keeps the paper's rule (the stop
 * is checked at step starts only), so its images stay as they were. */
CR_HD static inline int cr_ray_outside_stop(const cr_frame *f, const cr_ray *ray, double r)
{
    return ray->kind != CR_INTEG_MINO || r >= f->r_stop;
}

CR_HD static inline int cr_ray_escaping(const cr_frame *f, const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO
               ? ray->m[CR_M_W] <= f->w_sky && ray->m[CR_M_DW] < 0.0
               : ray->y[CR_Y_R] >= f->r_max && ray->u[1] > 0.0;
}

/* Whether a Mino ray that comes in from beyond the sky radius never gets
 * inside it: then R(r) < 0 at r = 1/w_sky, so it turns at a larger radius
 * and leaves again, and ends as sky by the rule above without meeting
 * anything. Only taken when the sky is a plain colour (no direction is
 * needed); the image of an observer at infinity is mostly such rays. */
CR_HD static inline int cr_ray_misses_scene(const cr_frame *f, const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && !f->sky.rgb && f->w_sky > 0.0 &&
           ray->m[CR_M_W] < f->w_sky && ray->m[CR_M_DW] > 0.0 &&
           cr_mino_W(&ray->c, f->w_sky) < 0.0;
}

/* One step from the current state to y1 / m1. Returns 0, or -1 when the
 * integration failed (non-finite state, step size collapsed). */
CR_HD static inline int cr_ray_advance(const cr_frame *f, cr_ray *ray)
{
    int tries, i;
    if (ray->kind == CR_INTEG_MINO) {
        double h = ray->h_next;
        for (tries = 0;; tries++) {
            double err = cr_dp5_try(&ray->c, f->tolerance, h, ray->m, &ray->st, ray->m1);
            double fac = cr_dp5_factor(err);
            if (err <= 1.0) {
                ray->hm = h;
                ray->h_next = h * (tries > 0 && fac > 1.0 ? 1.0 : fac);
                return 0;
            }
            h *= fac;
            if (tries == 60 || !(h > 0.0))
                return -1;
        }
    }
    ray->h = cr_geo_step_size(&ray->g, f->step_multiplier, ray->y[CR_Y_TH], ray->u);
    for (tries = 0;; tries++) {
        int ok = 1;
        cr_geo_rk4(&ray->g, ray->y, ray->k1, ray->h, ray->y1);
        for (i = 0; i < CR_NY; i++)
            ok &= cr_isfinite(ray->y1[i]);
        if (ok && ray->y1[CR_Y_R] > 0.0)
            break;
        if (tries == 4)
            return -1;
        ray->h *= 0.125;
    }
    return cr_isfinite(ray->h) ? 0 : -1;
}

/* Move the ray to the end of the current step (no hit inside it): under
 * RK4 through the polar axis, under Mino cut at the sky radius when the step
 * crosses it. Adds the turns made around the axis to *turns. */
CR_HD static inline void cr_ray_commit(const cr_frame *f, cr_ray *ray, double *turns)
{
    int i;
    if (ray->kind == CR_INTEG_MINO) {
        double d0 = ray->m1[CR_M_NX] - ray->m[CR_M_NX], d1 = ray->m1[CR_M_NY] - ray->m[CR_M_NY],
               d2 = ray->m1[CR_M_NZ] - ray->m[CR_M_NZ];
        *turns += sqrt(d0 * d0 + d1 * d1 + d2 * d2) / CR_TWO_PI;
        if (ray->m1[CR_M_W] < f->w_sky && ray->m1[CR_M_DW] < 0.0 &&
            ray->m[CR_M_W] > f->w_sky) {
            double ys[CR_RAY_NY];
            cr_event_locate(f, ray, CR_EV_SKY, ray->m[CR_M_W] - f->w_sky, 1.0,
                            ray->m1[CR_M_W] - f->w_sky, ys);
            for (i = 0; i < CR_MN; i++)
                ray->m[i] = ys[i];
            ray->m[CR_M_W] = f->w_sky;
            if (!(ray->m[CR_M_DW] < 0.0))
                ray->m[CR_M_DW] = -1e-300;
            cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
            return;
        }
        for (i = 0; i < CR_MN; i++) {
            ray->m[i] = ray->m1[i];
            ray->st.k[0][i] = ray->st.k[6][i];
        }
        return;
    }
    *turns += fabs(ray->y1[CR_Y_PH] - ray->y[CR_Y_PH]) / CR_TWO_PI;
    cr_geo_through_axis(ray->y1);
    for (i = 0; i < CR_NY; i++)
        ray->y[i] = ray->y1[i];
}

/* ---- The path of one ray (--trace, curray.trace) ------------------------
 * An optional recorder of cr_trace_loop: with ray->path set, the loop stores
 * points of the very ray it traces (no second integration): the observer's
 * point, then `sub` points per accepted step (fractions 1/sub .. 1 of it by
 * cr_ray_state_at, the step's end exact), and a located disc or sphere hit as
 * the last point. The host owns the buffer; the core never allocates. With
 * ray->path NULL (every image) the loop only tests the pointer once per step.
 * A ray that leaves to a sky at infinity (a sky image without a boundary)
 * ends its path at its last finite point (r large, w > 0).
 * Columns of a point (lengths in M, angles in rad):
 *   CR_P_LAM   the ray's parameter from the observer: the affine parameter of
 *              the backward tangent under rk4, Mino time tau (d lambda =
 *              Sigma d tau) under mino;
 *   CR_P_T     BL coordinate time: rk4 integrates it (t = 0 at the observer);
 *              mino does not (it diverges at w = 0), so the recorder
 *              integrates dt/dtau = Sigma u^t over each recorded interval
 *              (Romberg on the dense output, cr_path_dt); a ray from an
 *              observer at infinity starts its path at its first finite point
 *              (the end of the first step's first part) with t = 0 there;
 *   CR_P_R, CR_P_TH, CR_P_PH   BL position, theta in [0, pi], phi continuous
 *              (not reduced to [0, 2 pi));
 *   CR_P_X..CR_P_Z   Cartesian position (2.2.8);
 *   CR_P_UT..CR_P_UPH   u^mu = dx^mu/dlambda of the backward tangent (affine
 *              lambda, the convention of geodesic.h: u_t = E, u_phi = L), so
 *              that g(u, u) = 0 can be checked point by point. */
enum {
    CR_P_LAM = 0,
    CR_P_T,
    CR_P_R,
    CR_P_TH,
    CR_P_PH,
    CR_P_X,
    CR_P_Y,
    CR_P_Z,
    CR_P_UT,
    CR_P_UR,
    CR_P_UTH,
    CR_P_UPH,
    CR_PN
};

typedef struct cr_path {
    double *pts; /* host buffer of cap points, point k at pts[k * CR_PN] */
    long cap;
    long n;  /* points the ray produced; n > cap: only the first cap stored */
    int sub; /* points per step, >= 1 */
    /* running values (set by cr_path_begin) */
    int started;     /* the first point is recorded */
    double lam;      /* parameter at the start of the current step */
    double t, dt;    /* t and dt/dparameter at the last point */
    double ph;       /* phi at the last point */
} cr_path;

/* Columns R..UPH (and T under rk4) of state y of the ray's integrator into
 * p; returns dt/dparameter there (u^t under rk4, Sigma u^t under mino), or
 * NaN at w = 0 (mino at infinity: no finite point). */
CR_HD static inline double cr_path_eval(const cr_frame *f, const cr_ray *ray, const double *y,
                                        double *p)
{
    cr_metric_point q;
    double u[4], a = f->metric.a;
    if (ray->kind == CR_INTEG_MINO) {
        double r, c, s, ph, w = y[CR_M_W], psi, dth, sig;
        cr_geo g;
        if (!(w > 0.0))
            return NAN;
        cr_mino_position(y, &r, &c, &s, &ph);
        psi = atan2(y[CR_M_NY], y[CR_M_NX]);
        /* dtheta/dtau = dn/dtau . e_theta for the unit vector n */
        dth = (y[CR_M_DNX] * c * cos(psi) + y[CR_M_DNY] * c * sin(psi) - y[CR_M_DNZ] * s) /
              sqrt(y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY] + y[CR_M_NZ] * y[CR_M_NZ]);
        sig = r * r + a * a * c * c;
        p[CR_P_R] = r;
        p[CR_P_TH] = atan2(s, c);
        p[CR_P_PH] = ph;
        cr_mino_cart(a, y, p + CR_P_X);
        g.mt = f->metric;
        g.E = ray->c.E;
        g.L = ray->c.L;
        g.th_floor = 0.0;
        {
            double yb[CR_NY];
            yb[CR_Y_UR] = -y[CR_M_DW] / (w * w * sig);
            yb[CR_Y_UTH] = dth / sig;
            cr_metric_eval(&f->metric, r, p[CR_P_TH], &q);
            cr_geo_velocity(&g, yb, &q, u);
        }
        p[CR_P_UT] = u[0];
        p[CR_P_UR] = u[1];
        p[CR_P_UTH] = u[2];
        p[CR_P_UPH] = u[3];
        return sig * u[0];
    } else {
        double yb[CR_NY], dy[CR_NY];
        int i;
        for (i = 0; i < CR_NY; i++)
            yb[i] = y[i];
        cr_geo_through_axis(yb);
        cr_geo_rhs_full(&ray->g, yb, dy, u, &q);
        p[CR_P_T] = yb[CR_Y_T];
        p[CR_P_R] = yb[CR_Y_R];
        p[CR_P_TH] = yb[CR_Y_TH];
        p[CR_P_PH] = yb[CR_Y_PH];
        cr_bl_to_cart(a, yb[CR_Y_R], yb[CR_Y_TH], yb[CR_Y_PH], p + CR_P_X);
        for (i = 0; i < 4; i++)
            p[CR_P_UT + i] = u[i];
        return u[0];
    }
}

/* Store point p (CR_PN values) with parameter lam; phi made continuous with
 * the previous point. */
CR_HD static inline void cr_path_store(cr_path *path, double *p, double lam)
{
    int i;
    p[CR_P_LAM] = lam;
    if (path->started)
        p[CR_P_PH] += CR_TWO_PI * floor((path->ph - p[CR_P_PH]) / CR_TWO_PI + 0.5);
    path->ph = p[CR_P_PH];
    path->started = 1;
    if (path->n < path->cap)
        for (i = 0; i < CR_PN; i++)
            path->pts[path->n * CR_PN + i] = p[i];
    path->n++;
}

/* The observer's point (none at w = 0). */
CR_HD static inline void cr_path_begin(const cr_frame *f, const cr_ray *ray, cr_path *path)
{
    double p[CR_PN];
    const double *y = ray->kind == CR_INTEG_MINO ? ray->m : ray->y;
    path->n = 0;
    path->started = 0;
    path->lam = 0.0;
    path->t = 0.0;
    if (path->sub < 1)
        path->sub = 1;
    path->dt = cr_path_eval(f, ray, y, p);
    if (path->dt == path->dt) {
        if (ray->kind == CR_INTEG_MINO)
            p[CR_P_T] = 0.0;
        path->t = p[CR_P_T];
        cr_path_store(path, p, 0.0);
    }
}

/* How far state y of the ray's integrator lies beyond the horizon stop
 * r+ + epsilon (> 0 beyond it). */
CR_HD static inline double cr_path_beyond_stop(const cr_frame *f, const cr_ray *ray,
                                               const double *y)
{
    return ray->kind == CR_INTEG_MINO ? y[CR_M_W] - f->w_stop : f->r_stop - y[CR_Y_R];
}

/* Mino: the integral of dt/dtau over the fractions [sa, sb] of the current
 * step, whose ends have dt/dtau = fa, fb: Romberg's Simpson values from
 * trapezoid sums with 1, 2, 4, ... intervals until two agree to 1e-12
 * relative (at most 2^12 intervals). A Mino step can span much of the ray
 * (dt/dtau = Sigma u^t grows as r^2 far out and as 1/Delta near the
 * horizon), so a fixed rule is not enough. */
CR_HD static inline double cr_path_dt(const cr_frame *f, const cr_ray *ray, double sa,
                                      double sb, double fa, double fb)
{
    double len = (sb - sa) * ray->hm, T = 0.5 * len * (fa + fb), S = 0.0, S_prev = 0.0;
    double ys[CR_RAY_NY], q[CR_PN];
    int n = 1, it, k;
    for (it = 0; it < 12; it++) {
        double sum = 0.0;
        for (k = 0; k < n; k++) {
            cr_ray_state_at(ray, sa + (k + 0.5) * (sb - sa) / n, ys);
            sum += cr_path_eval(f, ray, ys, q);
        }
        sum = 0.5 * T + 0.5 * len / n * sum; /* trapezoid with 2n intervals */
        S = (4.0 * sum - T) / 3.0;
        T = sum;
        n *= 2;
        if (it >= 2 && fabs(S - S_prev) <= 1e-12 * fabs(S))
            break;
        S_prev = S;
    }
    return S;
}

/* Points of the current step up to fraction s_end (1, or a located hit). A
 * step that ends beyond the horizon stop is cut where it crosses the stop
 * (bisection on the step's states), so a path into the hole ends at
 * r+ + epsilon like its ray. */
CR_HD static inline void cr_path_step(const cr_frame *f, const cr_ray *ray, cr_path *path,
                                      double s_end)
{
    double p[CR_PN], ys[CR_RAY_NY];
    int mino = ray->kind == CR_INTEG_MINO, k;
    double h = mino ? ray->hm : ray->h;
    cr_ray_state_at(ray, s_end, ys);
    if (cr_path_beyond_stop(f, ray, ys) > 0.0) {
        double lo = 0.0, hi = s_end;
        for (k = 0; k < 60; k++) {
            double mid = 0.5 * (lo + hi);
            cr_ray_state_at(ray, mid, ys);
            if (cr_path_beyond_stop(f, ray, ys) > 0.0)
                hi = mid;
            else
                lo = mid;
        }
        s_end = hi;
    }
    for (k = 1; k <= path->sub; k++) {
        double s0 = s_end * (k - 1) / path->sub, s1 = s_end * k / path->sub, dt;
        cr_ray_state_at(ray, s1, ys);
        dt = cr_path_eval(f, ray, ys, p);
        if (!(dt == dt))
            break; /* w <= 0: a ray leaving to the sky at infinity has no finite point */
        if (mino) /* from infinity the path starts at the first finite point, t = 0 */
            p[CR_P_T] =
                path->started ? path->t + cr_path_dt(f, ray, s0, s1, path->dt, dt) : 0.0;
        path->t = p[CR_P_T];
        path->dt = dt;
        cr_path_store(path, p, path->lam + s1 * h);
    }
    path->lam += s_end * h;
}

/* Trace a ray through the frame's scene (with ray->path set, recording its
 * path as described above). */
CR_HD static inline cr_pixel cr_trace_loop(const cr_frame *f, cr_ray *ray)
{
    cr_pixel px;
    double ys[CR_RAY_NY];
    double x0[3] = {0.0, 0.0, 0.0}, x1[3];
    double mean = 0.0, m2 = 0.0, turns = 0.0;
    long n_err = 0, steps = 0;
    int i, mino = ray->kind == CR_INTEG_MINO;
    const double *y = mino ? ray->m : ray->y;
    const double *y1 = mino ? ray->m1 : ray->y1;

    px.redshift = -1.0;
    px.hit_r = px.hit_phi = -1.0;
    px.bolo = -1.0;
    px.object = -1;
    px.outcome = CR_OUT_NONE;
    px.color = f->error_color;
    if (f->n_spheres > 0)
        cr_ray_cart(f, ray, y, x0);
    if (ray->path)
        cr_path_begin(f, ray, ray->path);

    for (;;) {
        double e;
        int hit_sphere = -1, hit_disc = 0;
        double s_sphere = 2.0, s_disc = 2.0;

        if (cr_ray_at_horizon(f, ray)) {
            px.outcome = CR_OUT_HORIZON;
            px.color = f->horizon_color;
            px.redshift = 0.0; /* light from the horizon is infinitely redshifted */
            break;
        }
        e = cr_ray_begin(ray);
        if (e >= 0.0 && cr_isfinite(e)) {
            double d = e - mean;
            n_err++;
            mean += d / n_err;
            m2 += d * (e - mean);
        }
        if (cr_ray_escaping(f, ray) || (steps == 0 && cr_ray_misses_scene(f, ray))) {
            px.outcome = CR_OUT_SKY;
            if (f->sky.rgb) {
                double sth, sph;
                if (mino)
                    cr_mino_sky_direction(&ray->c, y, &sth, &sph);
                else
                    cr_sky_direction(f->metric.a, y, ray->u[3], &sth, &sph);
                px.color = cr_sky_sample(&f->sky, sth, sph);
            } else {
                px.color = f->sky_color;
            }
            /* a static source at infinity, u_em = (1, 0, 0, 0): for the static
             * observer omega_r/omega_s = 1/sqrt(-g_tt)|obs */
            {
                double p[4], u_inf[4] = {1.0, 0.0, 0.0, 0.0};
                cr_ray_momentum(ray, y, p);
                px.redshift = cr_frame_shift(f, ray->p_obs, p, u_inf);
            }
            break;
        }
        if (steps >= f->max_steps || turns >= f->max_turns) {
            px.outcome = CR_OUT_LIMIT;
            px.color = f->limit_color;
            break;
        }
        if (cr_ray_advance(f, ray) != 0) {
            px.outcome = CR_OUT_ERROR;
            break;
        }
        steps++;

        /* events inside this step */
        if (f->disc.enabled) {
            double v0 = cr_event_value(f, ray, CR_EV_DISC, y),
                   v1 = cr_event_value(f, ray, CR_EV_DISC, y1);
            if (v0 != 0.0 && (v0 < 0.0) != (v1 < 0.0)) {
                double s = cr_event_locate(f, ray, CR_EV_DISC, v0, 1.0, v1, ys);
                double rr, th, ph;
                cr_ray_position(ray, ys, &rr, &th, &ph);
                if (rr >= f->disc.r_hit_in && rr <= f->disc.r_out &&
                    cr_ray_outside_stop(f, ray, rr)) {
                    hit_disc = 1;
                    s_disc = s;
                }
            }
        }
        if (f->n_spheres > 0) {
            double ysp[CR_RAY_NY];
            cr_ray_cart(f, ray, y1, x1);
            hit_sphere = cr_sphere_events(f, ray, x0, x1, &s_sphere, ysp);
            if (hit_sphere >= 0) {
                double rr, th, ph;
                cr_ray_position(ray, ysp, &rr, &th, &ph);
                if (!cr_ray_outside_stop(f, ray, rr))
                    hit_sphere = -1;
            }
            if (hit_sphere >= 0 && (!hit_disc || s_sphere < s_disc)) {
                double xs[3], rr, th, ph, p[4];
                cr_ray_cart(f, ray, ysp, xs);
                cr_ray_position(ray, ysp, &rr, &th, &ph);
                px.outcome = CR_OUT_SPHERE;
                px.object = (int16_t)hit_sphere;
                px.hit_r = rr;
                px.hit_phi = cr_wrap_2pi(ph);
                px.color = cr_sphere_color(&f->spheres[hit_sphere], xs);
                cr_ray_momentum(ray, ysp, p);
                px.redshift = cr_redshift_static(f, ray->p_obs, p, rr, th);
                if (ray->path)
                    cr_path_step(f, ray, ray->path, s_sphere);
                break;
            }
            for (i = 0; i < 3; i++)
                x0[i] = x1[i];
        }
        if (hit_disc) {
            double rr, th, ph, p[4];
            int side = cr_event_value(f, ray, CR_EV_DISC, y) < 0.0 ? 0 : 1;
            cr_ray_position(ray, ys, &rr, &th, &ph);
            px.outcome = CR_OUT_DISC;
            px.object = (int16_t)side;
            if (ray->path)
                cr_path_step(f, ray, ray->path, s_disc);
            px.hit_r = rr;
            px.hit_phi = cr_wrap_2pi(ph);
            cr_ray_momentum(ray, ys, p);
            if (f->disc.model == CR_DISC_KEPLERIAN) {
                px.redshift = cr_disc_keplerian_g(f, ray->p_obs, p, rr);
                px.color = cr_disc_keplerian_color(&f->disc, rr, px.redshift, &px.bolo);
            } else {
                px.color = cr_disc_color(&f->disc, rr, ph, side);
                px.redshift = cr_redshift_static(f, ray->p_obs, p, rr, 0.5 * CR_PI);
            }
            break;
        }
        if (ray->path)
            cr_path_step(f, ray, ray->path, 1.0);
        cr_ray_commit(f, ray, &turns);
    }
    px.steps = (uint32_t)steps;
    px.err_mean = n_err > 0 ? mean : 0.0;
    px.err_std = n_err > 0 ? sqrt(m2 / n_err) : 0.0;
    return px;
}

/* Trace the backward ray with BL state y and constants g (as made by
 * cr_camera_ray) through the frame's scene, with the frame's integrator. */
CR_HD static inline cr_pixel cr_trace_ray(const cr_frame *f, const cr_geo *g, const double *y)
{
    cr_ray ray;
    cr_ray_from_bl(f, g, y, &ray);
    return cr_trace_loop(f, &ray);
}

/* Trace the one ray through image point (x, y) of frame f, in pixel units of
 * cr_camera_screen / cr_camera_pixel_dir: (i, j) is the centre of pixel
 * (i, j) (those functions add 0.5). A point outside the picture
 * (cr_camera_in_image: beyond a fisheye's image circle) is not traced: its
 * pixel has outcome CR_OUT_OUTSIDE, colour black, steps 0, redshift, hit_r,
 * hit_phi and bolo -1, object -1, err_mean = err_std = 0, and an empty path. */
CR_HD static inline cr_pixel cr_trace_point_path(const cr_frame *f, double x, double y,
                                                cr_path *path)
{
    double n[3], yb[CR_NY];
    cr_geo g;
    cr_ray ray;
    if (!cr_camera_in_image(f, x, y)) {
        cr_pixel px;
        px.redshift = px.hit_r = px.hit_phi = px.bolo = -1.0;
        px.err_mean = px.err_std = 0.0;
        px.steps = 0;
        px.object = -1;
        px.outcome = CR_OUT_OUTSIDE;
        px.color = cr_rgb_make(0, 0, 0);
        if (path) {
            path->n = 0;
            path->started = 0;
        }
        return px;
    }
    if (f->obs_at_inf) {
        double alpha, beta;
        cr_camera_screen(f, x, y, &alpha, &beta);
        cr_camera_ray_at_infinity(f, alpha, beta, &ray.c, ray.m);
        cr_ray_mino_start(f, &ray);
    } else {
        cr_camera_pixel_dir(f, x, y, n);
        cr_camera_ray(f, n, &g, yb);
        cr_ray_from_bl(f, &g, yb, &ray);
    }
    ray.path = path;
    return cr_trace_loop(f, &ray);
}

CR_HD static inline cr_pixel cr_trace_point(const cr_frame *f, double x, double y)
{
    return cr_trace_point_path(f, x, y, 0);
}

/* Offset from the pixel centre, in pixels, of sub-pixel row or column a of
 * an n x n stratified grid: the sub-pixel centres are at ((a + 0.5) / n) of
 * the pixel, so the offset is (a + 0.5) / n - 0.5; exactly 0 for the middle
 * one of an odd n. */
CR_HD static inline double cr_subpixel_offset(int a, int n)
{
    return (a + 0.5) / n - 0.5;
}

/* The sub-ray whose outcome, redshift, object and error monitor a pixel
 * reports with n x n samples: a = b = n / 2 (integer division), the centre
 * sub-ray for odd n (the very ray of samples = 1), and for even n the one of
 * the four central sub-rays right of and below the centre (offset +0.5 / n
 * in x and in y, image rows counted downward). */
CR_HD static inline int cr_subpixel_centre(int n)
{
    return n / 2;
}

/* Trace pixel (i, j) of frame f (prepared by cr_frame_prepare).
 * With f->samples = n in 2..CR_MAX_SAMPLES (antialiasing) it traces the
 * n x n sub-rays of a stratified regular grid (sub-pixel centres at
 * ((a + 0.5) / n, (b + 0.5) / n) of the pixel, a, b = 0..n-1) through the
 * same camera code. The colour is their mean in linear light (each 8-bit
 * sRGB colour decoded to linear, averaged, encoded back and rounded); steps
 * is the sum of all sub-rays' steps (the pixel's cost); outcome, object,
 * redshift, err_mean and err_std are those of the sub-ray of
 * cr_subpixel_centre. Any other value of samples traces the one ray through
 * the pixel centre, exactly as without antialiasing. */
CR_HD static inline cr_pixel cr_trace_pixel(const cr_frame *f, int i, int j)
{
    int n = f->samples, c, k;
    double sum[3] = {0.0, 0.0, 0.0};
    unsigned long steps = 0;
    cr_pixel px;
    if (n < 2 || n > CR_MAX_SAMPLES)
        n = 1; /* offset 0: the ray through (double)i, (double)j */
    c = cr_subpixel_centre(n);
    px.steps = 0;
    /* one call site for every sub-ray (one inlined trace in the kernel) */
    for (k = 0; k < n * n; k++) {
        int a = k % n, b = k / n;
        cr_pixel s = cr_trace_point(f, i + cr_subpixel_offset(a, n), j + cr_subpixel_offset(b, n));
        if (a == c && b == c)
            px = s;
        if (n > 1) {
            sum[0] += cr_srgb_decode(s.color.r / 255.0);
            sum[1] += cr_srgb_decode(s.color.g / 255.0);
            sum[2] += cr_srgb_decode(s.color.b / 255.0);
            steps += s.steps;
        }
    }
    if (n == 1)
        return px;
    for (k = 0; k < 3; k++)
        sum[k] = cr_srgb_encode(sum[k] / (n * n));
    px.color.r = cr_unit_to_u8(sum[0]);
    px.color.g = cr_unit_to_u8(sum[1]);
    px.color.b = cr_unit_to_u8(sum[2]);
    px.steps = steps > 0xffffffffUL ? 0xffffffffu : (uint32_t)steps;
    return px;
}

/* The path (cr_path) of the ray that pixel (i, j) reports: with antialiasing
 * the sub-ray of cr_subpixel_centre, else the pixel's one ray. Returns that
 * ray's cr_pixel (its outcome, hit point, redshift). */
CR_HD static inline cr_pixel cr_trace_pixel_path(const cr_frame *f, int i, int j, cr_path *path)
{
    int n = f->samples;
    double off;
    if (n < 2 || n > CR_MAX_SAMPLES)
        n = 1;
    off = cr_subpixel_offset(cr_subpixel_centre(n), n);
    return cr_trace_point_path(f, i + off, j + off, path);
}

#endif
