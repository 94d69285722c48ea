/* curray core: the path of one ray (--trace, curray.trace).
 *
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
 *              for a ray from inside the horizon (ray.h's ingoing chart) the
 *              recorder integrates the ingoing time v = t + G(r) (metric.h;
 *              regular through r+), 0 at the observer: the column is v
 *              while the ray is inside r+ + epsilon and BL t = v - G(r) from
 *              where it changes to BL on;
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
#ifndef CR_CORE_PATH_H
#define CR_CORE_PATH_H

#include "ray.h"

enum {
    CR_P_LAM = 0,
    CR_P_T = 1 + CR_RP_T, /* then the point of cr_ray_point (ray.h) */
    CR_P_R = 1 + CR_RP_R,
    CR_P_TH = 1 + CR_RP_TH,
    CR_P_PH = 1 + CR_RP_PH,
    CR_P_X = 1 + CR_RP_X,
    CR_P_Y = 1 + CR_RP_Y,
    CR_P_Z = 1 + CR_RP_Z,
    CR_P_UT = 1 + CR_RP_UT,
    CR_P_UR = 1 + CR_RP_UR,
    CR_P_UTH = 1 + CR_RP_UTH,
    CR_P_UPH = 1 + CR_RP_UPH,
    CR_PN = 1 + CR_RPN
};

typedef struct cr_path {
    double *pts; /* host buffer of cap points, point k at pts[k * CR_PN] */
    long cap;
    long n;  /* points the ray produced; n > cap: only the first cap stored */
    int sub; /* points per step, >= 1 */
    /* running values (set by cr_path_begin) */
    int started;     /* the first point is recorded */
    double lam;      /* parameter at the start of the current step */
    double t, dt;    /* t and dt/dparameter at the last point (mino from
                        inside the horizon: v and dv/dtau, cr_ray_point) */
    double ph;       /* phi at the last point */
} cr_path;

/* Columns T..UPH of state y of the ray's integrator into p (cr_ray_point:
 * T under rk4 only); returns dt/dparameter there (u^t under rk4, Sigma u^t
 * under mino), or NaN at w = 0 (mino at infinity: no finite point). */
CR_HD static inline double cr_path_eval(const cr_frame *f, const cr_ray *ray, const double *y,
                                        double *p)
{
    return cr_ray_point(f, ray, y, p + CR_P_T);
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
    const double *y = cr_ray_y0(ray);
    path->n = 0;
    path->started = 0;
    path->lam = 0.0;
    path->t = 0.0;

    if (path->sub < 1)
        path->sub = 1;
    path->dt = cr_path_eval(f, ray, y, p);
    if (path->dt == path->dt) {
        if (!cr_ray_has_t(ray))
            p[CR_P_T] = 0.0;
        path->t = p[CR_P_T];
        cr_path_store(path, p, 0.0);
    }
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
    double len = (sb - sa) * cr_ray_step_length(ray), T = 0.5 * len * (fa + fb), S = 0.0, S_prev = 0.0;
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
    int has_t = cr_ray_has_t(ray), k;
    double h = cr_ray_step_length(ray);
    cr_ray_state_at(ray, s_end, ys);
    if (cr_ray_beyond_stop(f, ray, ys) > 0.0) {
        double lo = 0.0, hi = s_end;
        for (k = 0; k < 60; k++) {
            double mid = 0.5 * (lo + hi);
            cr_ray_state_at(ray, mid, ys);
            if (cr_ray_beyond_stop(f, ray, ys) > 0.0)
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
        if (!has_t) { /* from infinity the path starts at the first finite point, t = 0 */
            path->t = path->started ? path->t + cr_path_dt(f, ray, s0, s1, path->dt, dt) : 0.0;
            p[CR_P_T] = path->t - cr_ray_t_shift(ray, p[CR_P_R]);
        } else {
            path->t = p[CR_P_T];
        }
        path->dt = dt;
        cr_path_store(path, p, path->lam + s1 * h);
    }
    path->lam += s_end * h;
}

#endif
