/* curray core: where a point of space is seen in a frame's image, through
 * the hole's lens (the lensed picture of `curray orbit -t c`).
 *
 * A point P (Cartesian, coords.h (2.2.8), lengths in units of M as every
 * frame) is seen at every image point whose backward ray passes through P.
 * There are infinitely many such points around a hole; they are told apart
 * by the image ORDER n, how the light wound round the hole from P to the
 * observer. Take the plane through the hole's centre, the observer's
 * direction o and P's (BL directions (sin th cos ph, sin th sin ph,
 * cos th)), P at angle psi from o in it, and the angle sigma that the ray's
 * direction, projected on that plane, sweeps from o (signed: towards P
 * positive, unwrapped). The ray reaches P at sigma = psi + 2 pi m: m = 0 is
 * the direct, primary image (order 0); m = -1 the secondary one (order 1),
 * light that went round the far side of the hole, seen beyond the shadow
 * from P's image; m = +1 order 2, m = -2 order 3, ... (order n: m = n / 2
 * for even n, -(n + 1) / 2 for odd n). A ray's points of order n are those
 * with sigma in [psi + 2 pi m - pi, psi + 2 pi m + pi). For the planar rays
 * of a spherical hole sigma is the orbit angle; the rays of a spinning one
 * leave the plane a little, which the half-turn margins absorb. Where P lies
 * almost on the line of sight (psi within CR_LENS_LINE of 0 or pi) the
 * plane is undefined, and the unsigned sweep is used instead: the arc length
 * of the ray's direction on the unit sphere, order n in [n pi, (n + 1) pi)
 * (exact for a spherical hole).
 *
 * cr_lens_probe traces the ray of one image point with the frame's
 * integrator and finds its closest approach to P among its points of order
 * n: the step's dense output sampled CR_LENS_SUB points a step, the best
 * sample of the whole ray refined by golden section on its step's dense
 * output (a copy of the ray at that step is kept). cr_lens_solve finds
 * the image point itself: Gauss-Newton on the image plane for the miss
 * vector x(i, j) - P across the ray (2 unknowns, zero at the solution), its
 * Jacobian by forward differences of CR_LENS_FD pixels, each step limited
 * and halved until the miss shrinks.
 *
 * cr_lens_flat_pixel gives the start of a search: where P would be seen
 * without the hole's bending, and where the hole's centre is seen; the
 * images of a spherical hole lie on the line through both (on P's side for
 * even orders, beyond the centre for odd ones), those of a spinning one
 * near it.
 *
 * The frame it runs on is made by cr_lens_frame: the scene's frame with its
 * boundaries moved beyond the points looked for (r_max, w_sky: the scene
 * may end nearer than the orbit), and either without objects (the ray
 * through empty space, smooth in (i, j): what Newton needs) or with them
 * (then a ray that ends on the disc or a sphere before reaching P shows that
 * object there: P is hidden). Compiles as C, under nvcc and for wasm. */
#ifndef CR_CORE_LENSING_H
#define CR_CORE_LENSING_H

#include "trace.h"

/* Highest image order looked for (orders 0 .. CR_LENS_MAX_ORDER). */
#define CR_LENS_MAX_ORDER 3
/* Within this angle (rad, 2 degrees) of the line of sight P's orders are
 * told by the unsigned sweep (header comment). */
#define CR_LENS_LINE 0.035
/* Dense-output samples per step where the closest approach is looked for:
 * Mino steps are long (tens a ray), RK4 steps short. */
#define CR_LENS_SUB_MINO 16
#define CR_LENS_SUB_RK4 2
/* Golden-section iterations refining the best sample (bracket x 0.618^n). */
#define CR_LENS_GOLDEN_ITERS 48
/* Forward-difference step of the Jacobian, pixels. */
#define CR_LENS_FD 1e-3
/* Newton iterations at most, and halvings of one step. */
#define CR_LENS_NEWTON_ITERS 40
#define CR_LENS_HALVINGS 12
/* A Newton run that stalls (no step reduces the miss) still succeeds when
 * the miss is within this factor of the tolerance: the rays' integration
 * error sets a floor under the miss. */
#define CR_LENS_TOL_STALL 10.0

/* The closest approach of one ray to P among its points of one order. */
typedef struct cr_lens_hit {
    int found;     /* the ray has points of the order (before it ended) */
    double d;      /* their smallest distance to P (M); INFINITY when not found */
    double x[3];   /* the ray's point there (Cartesian) */
    double tan[3]; /* the ray's unit tangent there (Cartesian, either sense) */
    double delay;  /* t_obs - t of the light there (cr_ray_delay: renormalised
                      for the observer at infinity) */
    double sweep;  /* swept angle there (rad) */
    int outcome;   /* how the ray ended (cr_outcome): CR_OUT_DISC / _SPHERE
                      when an object stopped it (then only its points before
                      the object count) */
} cr_lens_hit;

/* What a probe looks for: P, and the window of its order's sweep. */
typedef struct cr_lens_target {
    double P[3];     /* Cartesian */
    int order;
    int plane;       /* 1: the signed sweep in the plane of o and P; 0: unsigned */
    double e1[3], e2[3]; /* the plane: o, and the unit vector towards P */
    double lo, hi;   /* the order's window of the sweep */
} cr_lens_target;

/* The BL direction (unit vector) of Cartesian point x on metric spin a:
 * the inverse of (2.2.8), r^2 = (R^2 - a^2 + sqrt((R^2 - a^2)^2 + 4 a^2
 * z^2)) / 2, cos th = z / r. */
CR_HD static inline void cr_lens_bl_dir(double a, const double x[3], double n[3])
{
    double R2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2], b = R2 - a * a;
    double r = sqrt(0.5 * (b + sqrt(b * b + 4.0 * a * a * x[2] * x[2])));
    double ct = r > 0.0 ? x[2] / r : 1.0, st, rho = sqrt(x[0] * x[0] + x[1] * x[1]);
    if (ct > 1.0)
        ct = 1.0;
    if (ct < -1.0)
        ct = -1.0;
    st = sqrt(1.0 - ct * ct);
    n[0] = rho > 0.0 ? st * x[0] / rho : 0.0;
    n[1] = rho > 0.0 ? st * x[1] / rho : 0.0;
    n[2] = ct;
}

/* The target of P's image of order `order` in frame f (header comment). */
CR_HD static inline void cr_lens_target_make(const cr_frame *f, const double P[3], int order,
                                             cr_lens_target *t)
{
    const cr_observer *o = &f->observer;
    double p[3], c, sn, psi, m;
    int k;
    for (k = 0; k < 3; k++)
        t->P[k] = P[k];
    t->order = order;
    t->e1[0] = sin(o->theta) * cos(o->phi);
    t->e1[1] = sin(o->theta) * sin(o->phi);
    t->e1[2] = cos(o->theta);
    cr_lens_bl_dir(f->metric.a, P, p);
    c = p[0] * t->e1[0] + p[1] * t->e1[1] + p[2] * t->e1[2];
    for (k = 0; k < 3; k++)
        t->e2[k] = p[k] - c * t->e1[k];
    sn = sqrt(t->e2[0] * t->e2[0] + t->e2[1] * t->e2[1] + t->e2[2] * t->e2[2]);
    psi = atan2(sn, c);
    t->plane = psi > CR_LENS_LINE && psi < CR_PI - CR_LENS_LINE;
    if (!t->plane) {
        t->lo = order * CR_PI;
        t->hi = (order + 1) * CR_PI;
        return;
    }
    for (k = 0; k < 3; k++)
        t->e2[k] /= sn;
    m = order % 2 ? -0.5 * (order + 1) : 0.5 * order;
    t->lo = psi + CR_TWO_PI * m - CR_PI;
    t->hi = psi + CR_TWO_PI * m + CR_PI;
}

/* The sweep (header comment) at the ray's direction n, from its value sw
 * at the previous direction n0. */
CR_HD static inline double cr_lens_sweep(const cr_lens_target *t, const double n0[3],
                                         const double n[3], double sw);

/* Whether the ray, at sweep sw, has passed its order's window for good
 * (unsigned: beyond hi; signed: beyond hi for m > 0, below lo for m < 0,
 * either for m = 0). */
CR_HD static inline int cr_lens_past(const cr_lens_target *t, double sw)
{
    if (!t->plane || t->order % 2 == 0)
        return sw >= t->hi || (t->plane && t->order == 0 && sw < t->lo);
    return sw < t->lo;
}

/* The BL direction of state y of the ray (unit vector). */
CR_HD static inline void cr_lens_dir(const cr_ray *ray, const double *y, double n[3])
{
    double r, th, ph;
    cr_ray_position(ray, y, &r, &th, &ph);
    n[0] = sin(th) * cos(ph);
    n[1] = sin(th) * sin(ph);
    n[2] = cos(th);
}

/* The angle between unit vectors a and b, accurate at small angles. */
CR_HD static inline double cr_lens_angle(const double a[3], const double b[3])
{
    double c[3], dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), dot);
}

CR_HD static inline double cr_lens_sweep(const cr_lens_target *t, const double n0[3],
                                         const double n[3], double sw)
{
    double a, d;
    if (!t->plane)
        return sw + cr_lens_angle(n0, n);
    a = atan2(n[0] * t->e2[0] + n[1] * t->e2[1] + n[2] * t->e2[2],
              n[0] * t->e1[0] + n[1] * t->e1[1] + n[2] * t->e1[2]);
    d = a - sw;
    d -= CR_TWO_PI * floor(d / CR_TWO_PI + 0.5); /* the nearest turn: unwrapped */
    return sw + d;
}

/* The Cartesian point x and BL direction n of state y of the ray: for a
 * BL Mino state from its unit vector and pr with one sincos (what
 * cr_ray_cart and cr_lens_dir give, without their atan2: the probes' cost
 * is mostly here), else by those. */
CR_HD static inline void cr_lens_point(const cr_frame *f, const cr_ray *ray, const double *y,
                                       double x[3], double n[3])
{
    if (ray->kind == CR_INTEG_MINO && !cr_ray_ingoing(ray)) {
        double nx = y[CR_M_NX], ny = y[CR_M_NY], nz = y[CR_M_NZ];
        double s = sqrt(nx * nx + ny * ny), len = sqrt(s * s + nz * nz);
        double r = 1.0 / y[CR_M_W], a = f->metric.a, sp, cp, c, si, rho;
        sp = sin(y[CR_M_PR]);
        cp = cos(y[CR_M_PR]);
        if (s > 0.0) {
            c = (nx * cp - ny * sp) / s; /* cos(atan2(ny, nx) + pr) */
            si = (ny * cp + nx * sp) / s;
        } else {
            c = cp;
            si = sp;
        }
        n[0] = s / len * c;
        n[1] = s / len * si;
        n[2] = nz / len;
        rho = sqrt(r * r + a * a);
        x[0] = rho * n[0];
        x[1] = rho * n[1];
        x[2] = r * n[2];
        return;
    }
    cr_ray_cart(f, ray, y, x);
    cr_lens_dir(ray, y, n);
}

/* Squared distance to P of the ray's point at fraction s of the current
 * step; its point into x, its BL direction into n, its state into ys. */
CR_HD static inline double cr_lens_d2_at(const cr_frame *f, const cr_ray *ray, double s,
                                         const double P[3], double x[3], double n[3],
                                         double *ys)
{
    double d2 = 0.0;
    int k;
    cr_ray_state_at(ray, s, ys);
    cr_lens_point(f, ray, ys, x, n);
    for (k = 0; k < 3; k++)
        d2 += (x[k] - P[k]) * (x[k] - P[k]);
    return d2 == d2 ? d2 : INFINITY; /* w = 0 (at infinity): no finite point */
}

/* The best sample so far of a probe: the step it lies in (a copy of the
 * ray with that step), its fraction and the sweep around it. */
typedef struct cr_lens_best {
    cr_ray ray;
    double s_end;        /* the step's end fraction (a hit's) */
    int sub, kb;         /* samples of the step, the best one's index */
    double sw[3];        /* sweep at samples kb - 1, kb, kb + 1 (clamped) */
} cr_lens_best;

/* Sample the current step up to fraction s_end for points of t's order
 * nearer to P than h->d (squared distance at the samples), sweep and n (the
 * direction at the step's start) carried from step to step; a better sample
 * is kept in *b and h->d, h->found. */
CR_HD static inline void cr_lens_scan_step(const cr_frame *f, const cr_ray *ray, double s_end,
                                           const cr_lens_target *t, double *sweep, double n[3],
                                           cr_lens_hit *h, cr_lens_best *b)
{
    int sub = f->integrator == CR_INTEG_MINO ? CR_LENS_SUB_MINO : CR_LENS_SUB_RK4;
    double ys[CR_RAY_NY], x[3], sw[CR_LENS_SUB_MINO + 1];
    double best = h->d * h->d, nk[3];
    int k, kb = -1;
    for (k = 0; k <= sub; k++) {
        double d2 = cr_lens_d2_at(f, ray, s_end * k / sub, t->P, x, nk, ys);
        if (k > 0) {
            *sweep = cr_lens_sweep(t, n, nk, *sweep);
            n[0] = nk[0];
            n[1] = nk[1];
            n[2] = nk[2];
        }
        sw[k] = *sweep;
        if (sw[k] >= t->lo && sw[k] < t->hi && d2 < best) {
            best = d2;
            kb = k;
        }
    }
    if (kb < 0)
        return;
    h->found = 1;
    h->d = sqrt(best);
    b->ray = *ray;
    b->s_end = s_end;
    b->sub = sub;
    b->kb = kb;
    b->sw[0] = sw[kb > 0 ? kb - 1 : 0];
    b->sw[1] = sw[kb];
    b->sw[2] = sw[kb < sub ? kb + 1 : sub];
}

/* The closest approach near the best sample b: golden section on
 * [s_{kb-1}, s_{kb+1}] of its step's dense output; the point, distance,
 * tangent, delay and sweep there into h. */
CR_HD static inline void cr_lens_refine(const cr_frame *f, const cr_lens_target *t,
                                        const cr_lens_best *b, cr_lens_hit *h)
{
    const cr_ray *ray = &b->ray;
    double se = b->s_end, sub = b->sub, ys[CR_RAY_NY], x[3], nn[3], len;
    double lo = se * (b->kb > 0 ? b->kb - 1 : 0) / sub;
    double hi = se * (b->kb < b->sub ? b->kb + 1 : b->sub) / sub, sb = se * b->kb / sub;
    double best = cr_lens_d2_at(f, ray, sb, t->P, x, nn, ys), e, xa[3], xb[3], sa, sz, u;
    cr_golden g;
    int it, k;
    cr_golden_start(&g, lo, hi);
    g.f1 = cr_lens_d2_at(f, ray, g.x1, t->P, x, nn, ys);
    g.f2 = cr_lens_d2_at(f, ray, g.x2, t->P, x, nn, ys);
    for (it = 0; it < CR_LENS_GOLDEN_ITERS; it++) {
        if (cr_golden_shrink(&g) == 1)
            g.f1 = cr_lens_d2_at(f, ray, g.x1, t->P, x, nn, ys);
        else
            g.f2 = cr_lens_d2_at(f, ray, g.x2, t->P, x, nn, ys);
    }
    if ((g.f1 < g.f2 ? g.f1 : g.f2) < best)
        sb = g.f1 < g.f2 ? g.x1 : g.x2;
    h->d = sqrt(cr_lens_d2_at(f, ray, sb, t->P, h->x, nn, ys));
    h->delay = cr_ray_delay_at(f, ray, sb, ys);
    /* the tangent by a central difference on the dense output */
    e = 1e-6 * se;
    sa = sb - e > 0.0 ? sb - e : 0.0;
    sz = sb + e < se ? sb + e : se;
    cr_lens_d2_at(f, ray, sa, t->P, xa, nn, ys);
    cr_lens_d2_at(f, ray, sz, t->P, xb, nn, ys);
    for (k = 0; k < 3; k++)
        h->tan[k] = xb[k] - xa[k];
    len = sqrt(h->tan[0] * h->tan[0] + h->tan[1] * h->tan[1] + h->tan[2] * h->tan[2]);
    for (k = 0; k < 3; k++)
        h->tan[k] = len > 0.0 ? h->tan[k] / len : 0.0;
    /* the sweep there, linear between the samples */
    u = sb * sub / se - b->kb;
    h->sweep = u < 0.0 ? b->sw[1] + u * (b->sw[1] - b->sw[0]) : b->sw[1] + u * (b->sw[2] - b->sw[1]);
}

/* Trace the ray of image point (i, j) of frame f (pixel units of
 * cr_camera_screen) and find its closest approach to t's P among its points
 * of t's order (header comment) into *h. The ray is followed until it has
 * swept beyond the order's window (cr_lens_past) or ends (horizon, sky,
 * limit, an object of f, an error). */
CR_HD static inline void cr_lens_probe(const cr_frame *f, double i, double j,
                                       const cr_lens_target *t, cr_lens_hit *h)
{
    cr_ray ray;
    cr_pixel px;
    cr_monitor mon;
    cr_lens_best best;
    double x0[3] = {0.0, 0.0, 0.0}, turns = 0.0, sweep = 0.0, n[3];
    long steps = 0;
    h->found = 0;
    h->d = INFINITY;
    h->x[0] = h->x[1] = h->x[2] = NAN;
    h->tan[0] = h->tan[1] = h->tan[2] = 0.0;
    h->delay = h->sweep = NAN;
    h->outcome = CR_OUT_NONE;
    if (!cr_trace_point_ray(f, i, j, &ray, &px)) {
        h->outcome = CR_OUT_OUTSIDE;
        return;
    }
    ray.path = 0;
    mon.n = 0;
    mon.mean = mon.m2 = 0.0;
    cr_trace_start(f, &ray, &px, x0);
    cr_lens_dir(&ray, cr_ray_y0(&ray), n);
    for (;;) {
        cr_hit disc, sphere;
        int what;
        if (cr_lens_past(t, sweep))
            break;
        if (cr_trace_ends(f, &ray, &px, &mon, steps, turns)) {
            h->outcome = px.outcome;
            break;
        }
        if (cr_ray_advance(f, &ray) != 0) {
            h->outcome = CR_OUT_ERROR;
            break;
        }
        steps++;
        what = cr_trace_find_hit(f, &ray, x0, &disc, &sphere);
        cr_lens_scan_step(f, &ray, what == CR_OUT_SPHERE ? sphere.s
                                   : what == CR_OUT_DISC ? disc.s
                                                         : 1.0,
                          t, &sweep, n, h, &best);
        if (what != CR_OUT_NONE) {
            h->outcome = what;
            break;
        }
        cr_trace_move(f, &ray, &turns);
    }
    if (h->found)
        cr_lens_refine(f, t, &best, h);
}

/* Where the point x (Cartesian) would be seen in flat space, into (*i, *j)
 * (pixels), and the hole's centre into (*ci, *cj): the impact coordinates
 * (alpha, beta) = (x . right, x . up) and (0, 0) for the observer at
 * infinity; for a finite one the directions to them, straight lines from
 * the observer in coords.h's Cartesian space, through the camera
 * (cr_camera_dir_pixel: the observer's motion and the bending left out).
 * Returns 0 where the camera does not show one of them. */
CR_HD static inline int cr_lens_flat_pixel(const cr_frame *f, const double x[3], double *i,
                                           double *j, double *ci, double *cj)
{
    const cr_observer *o = &f->observer;
    double st = sin(o->theta), ct = cos(o->theta), sp = sin(o->phi), cp = cos(o->phi);
    double er[3], et[3], ep[3], d[3], n[3], c[3] = {-1.0, 0.0, 0.0};
    int k;
    er[0] = st * cp;
    er[1] = st * sp;
    er[2] = ct;
    et[0] = ct * cp;
    et[1] = ct * sp;
    et[2] = -st;
    ep[0] = -sp;
    ep[1] = cp;
    ep[2] = 0.0;
    if (f->obs_at_inf) {
        double v[2];
        for (k = 1; k < 3; k++) {
            /* cam[k] (local e_r, e_th, e_ph components) . x in Cartesian */
            int m;
            v[k - 1] = 0.0;
            for (m = 0; m < 3; m++)
                v[k - 1] += (f->cam[k][0] * er[m] + f->cam[k][1] * et[m] + f->cam[k][2] * ep[m]) *
                            x[m];
        }
        *i = 0.5 * (v[0] / f->tan_half_h + 1.0) * f->width - 0.5;
        *j = 0.5 * (1.0 - v[1] / f->tan_half_v) * f->height - 0.5;
        *ci = 0.5 * f->width - 0.5;
        *cj = 0.5 * f->height - 0.5;
        return 1;
    }
    {
        double O[3];
        cr_bl_to_cart(f->metric.a, o->r, o->theta, o->phi, O);
        for (k = 0; k < 3; k++)
            d[k] = x[k] - O[k];
    }
    n[0] = d[0] * er[0] + d[1] * er[1] + d[2] * er[2];
    n[1] = d[0] * et[0] + d[1] * et[1] + d[2] * et[2];
    n[2] = d[0] * ep[0] + d[1] * ep[1] + d[2] * ep[2];
    return cr_camera_dir_pixel(f, n, i, j) && cr_camera_dir_pixel(f, c, ci, cj);
}

/* The frame the probes run on (header comment): f (prepared) with its
 * scene boundary beyond radius r_reach (the largest Cartesian distance of
 * the points looked for) and, objects == 0, without disc and spheres and
 * with a plain sky; tolerance at most tol (Mino). */
CR_HD static inline void cr_lens_frame(const cr_frame *f, double r_reach, int objects,
                                       double tol, cr_frame *out)
{
    double rm = r_reach + 2.0 * f->metric.m;
    *out = *f;
    if (!objects) {
        out->disc.enabled = 0;
        out->n_spheres = 0;
        out->spheres = 0;
    }
    /* only the outcome sky matters, not its colour or direction: the rays end
       beyond rm moving out (also with a sky image at infinity, w_sky = 0) */
    out->sky.rgb = 0;
    if (out->tolerance > tol)
        out->tolerance = tol;
    if (!(out->r_max >= rm))
        out->r_max = rm;
    if (!(out->w_sky > 0.0 && out->w_sky <= 1.0 / rm))
        out->w_sky = 1.0 / rm;
    if (out->w_obj > 1.0 / rm)
        out->w_obj = 1.0 / rm; /* the delay is wanted out to P */
}

/* Where t's P is seen in t's image order: Gauss-Newton from image point
 * (*i, *j) (pixels) until the ray's closest approach is within tol (M) of
 * P; each step at most max_step pixels. Returns 1 with (*i, *j) the image
 * point and *h its probe, or 0 (no convergence: no image of that order
 * within reach of the start, or a start whose ray has no point of the
 * order) with (*i, *j) unchanged. f: a frame of cr_lens_frame without
 * objects. */
CR_HD static inline int cr_lens_solve(const cr_frame *f, const cr_lens_target *t, double tol,
                                      double max_step, double *i, double *j, cr_lens_hit *h)
{
    const double *P = t->P;
    double ci = *i, cj = *j;
    cr_lens_hit h0, hx, hy;
    int it, k;
    cr_lens_probe(f, ci, cj, t, &h0);
    if (!h0.found)
        return 0;
    for (it = 0; it < CR_LENS_NEWTON_ITERS; it++) {
        double J[3][2], m[3], a11 = 0.0, a12 = 0.0, a22 = 0.0, b1 = 0.0, b2 = 0.0, det;
        double di, dj, len, u;
        int halve;
        if (h0.d <= tol) {
            *i = ci;
            *j = cj;
            *h = h0;
            return 1;
        }
        cr_lens_probe(f, ci + CR_LENS_FD, cj, t, &hx);
        cr_lens_probe(f, ci, cj + CR_LENS_FD, t, &hy);
        if (!hx.found || !hy.found)
            return 0;
        for (k = 0; k < 3; k++) {
            m[k] = h0.x[k] - P[k];
            J[k][0] = (hx.x[k] - h0.x[k]) / CR_LENS_FD;
            J[k][1] = (hy.x[k] - h0.x[k]) / CR_LENS_FD;
        }
        /* Across the ray only: the closest approach slides along the ray
         * as (i, j) move, which changes nothing of the miss (perpendicular
         * to the ray there) but would dominate the normal equations. */
        {
            const double *T = h0.tan;
            double tm = T[0] * m[0] + T[1] * m[1] + T[2] * m[2];
            double t0 = T[0] * J[0][0] + T[1] * J[1][0] + T[2] * J[2][0];
            double t1 = T[0] * J[0][1] + T[1] * J[1][1] + T[2] * J[2][1];
            for (k = 0; k < 3; k++) {
                m[k] -= tm * T[k];
                J[k][0] -= t0 * T[k];
                J[k][1] -= t1 * T[k];
            }
        }
        for (k = 0; k < 3; k++) {
            a11 += J[k][0] * J[k][0];
            a12 += J[k][0] * J[k][1];
            a22 += J[k][1] * J[k][1];
            b1 -= J[k][0] * m[k];
            b2 -= J[k][1] * m[k];
        }
        det = a11 * a22 - a12 * a12;
        if (!(det > 1e-14 * (a11 * a22)) || !(det > 0.0))
            return 0;
        di = (a22 * b1 - a12 * b2) / det;
        dj = (a11 * b2 - a12 * b1) / det;
        len = sqrt(di * di + dj * dj);
        if (!(len == len))
            return 0;
        if (len > max_step) {
            di *= max_step / len;
            dj *= max_step / len;
        }
        for (halve = 0, u = 1.0; halve <= CR_LENS_HALVINGS; halve++, u *= 0.5) {
            cr_lens_hit hn;
            cr_lens_probe(f, ci + u * di, cj + u * dj, t, &hn);
            if (hn.found && hn.d < h0.d) {
                ci += u * di;
                cj += u * dj;
                h0 = hn;
                break;
            }
        }
        if (halve > CR_LENS_HALVINGS)
            break; /* no step reduces the miss: the integration's noise, or a
                      minimum of the miss above tol */
    }
    if (h0.d <= CR_LENS_TOL_STALL * tol) {
        *i = ci;
        *j = cj;
        *h = h0;
        return 1;
    }
    return 0;
}

#endif
