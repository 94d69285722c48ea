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
#include "track.h"

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

/* ---- moving spheres (cr_sphere.moving) -----------------------------------
 *
 * A moving sphere turns rigidly about the polar axis at omega = dphi/dt: at
 * BL coordinate time t it is the prepared sphere (its phi the phase at t = 0)
 * turned by omega t, and each of its points moves on phi = phi_0 + omega t
 * at fixed (r, theta), with 4-velocity u = u^t (1, 0, 0, omega) (a Killing
 * flow; for motion: orbit omega is the Keplerian circular orbit's at the
 * centre's r, so the centre moves on that geodesic and u there is the
 * orbit's). A ray meets it where it WAS when the ray passed: the state at
 * fraction s of a step is at BL time t = t_obs - cr_ray_delay_at(f, ray, s, y)
 * (the ray's own coordinate time), and the sphere is looked for there in
 * its own coordinates (cr_sphere_unturn: the point turned back by
 * -omega t), where it is the static prepared sphere.
 *
 * A particle sphere (cr_sphere.particle) is carried by its centre along a
 * tabulated worldline (track.h; omega = 0): at time t its centre is the
 * table's c(t), and it is the prepared sphere (centre c0 = the start's,
 * azimuth ph0) moved to c(t) and turned about the polar axis by the
 * centre's azimuth since the start, ph(t) - ph0 (for a circular orbit, the
 * rigid turn of motion: orbit). Its matter at point x moves with the
 * coordinate velocity of that rigid motion, dx/dt = dc/dt + dph/dt z^ x
 * (x - c) (the centre's u^mu at the centre), normalised there
 * (cr_sphere_particle_u). Outside the table's times there is no sphere. */

/* Largest angle (rad) a moving sphere turns through over one piece of a
 * step in which its hits are looked for (cr_sphere_turning): in each piece
 * the sphere is found as a static one is over a whole step. */
#define CR_SPHERE_MAX_TURN 0.25

/* The 4-velocity u^mu (BL) of a moving sphere's matter at (r, th): rigid
 * rotation at omega, u = u^t (1, 0, 0, omega) with u^t = 1 / sqrt(-(g_tt +
 * 2 omega g_tph + omega^2 g_phph)); the static observer's for omega = 0.
 * Returns 1, or 0 where that is not timelike (the matter would move at or
 * beyond the speed of light there; u untouched). */
CR_HD static inline int cr_sphere_velocity(const cr_metric *mt, double omega, double r,
                                           double th, double u[4])
{
    cr_metric_point q;
    double n;
    cr_metric_eval(mt, r, th, &q);
    n = -(q.g_tt + omega * (2.0 * q.g_tph + omega * q.g_phph));
    if (!(n > 0.0) || !cr_isfinite(n))
        return 0;
    u[0] = 1.0 / sqrt(n);
    u[1] = u[2] = 0.0;
    u[3] = omega * u[0];
    return 1;
}

/* BL r and theta of Cartesian point x (2.2.8): the root r^2 = (R2 +
 * sqrt(R2^2 + 4 a^2 z^2)) / 2, R2 = |x|^2 - a^2, of rho^2 / (r^2 + a^2) +
 * z^2 / r^2 = 1, and cos theta = z / r (theta = pi/2 on the disc r = 0). */
CR_HD static inline void cr_sphere_cart_to_bl(double a, const double x[3], double *r,
                                              double *th)
{
    double R2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - a * a;
    double r2 = 0.5 * (R2 + sqrt(R2 * R2 + 4.0 * a * a * x[2] * x[2]));
    double c;
    *r = sqrt(r2 > 0.0 ? r2 : 0.0);
    c = *r > 0.0 ? x[2] / *r : 0.0;
    *th = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
}

/* Samples per direction of a moving sphere's surface checked by
 * cr_sphere_too_fast: latitudes x 2 longitudes. */
#define CR_SPHERE_CHECK_N 24

/* Whether a moving sphere's matter would move at or beyond the speed of
 * light (cr_sphere_velocity not timelike) at some point of its surface
 * outside the horizon r+ (the prepared sphere: as it turns, each point
 * keeps its r and theta), tested on a grid of CR_SPHERE_CHECK_N latitudes x
 * 2 CR_SPHERE_CHECK_N longitudes and the centre. Returns 1 with that point's
 * r, th in *r_bad, *th_bad, else 0. */
CR_HD static inline int cr_sphere_too_fast(const cr_metric *mt, const cr_sphere *s,
                                           double *r_bad, double *th_bad)
{
    double rp = cr_metric_r_plus(mt), u[4], x[3], r, th;
    int i, j, k;
    for (i = 0; i <= CR_SPHERE_CHECK_N; i++) {
        double lat = CR_PI * i / CR_SPHERE_CHECK_N;
        for (j = 0; j < 2 * CR_SPHERE_CHECK_N; j++) {
            double lon = CR_PI * j / CR_SPHERE_CHECK_N;
            double d[3] = {sin(lat) * cos(lon), cos(lat), sin(lat) * sin(lon)};
            for (k = 0; k < 3; k++)
                x[k] = s->center[k] +
                       (i == 0 && j == 0 ? 0.0 : s->radius) *
                           (d[0] * s->axes[0][k] + d[1] * s->axes[1][k] + d[2] * s->axes[2][k]);
            cr_sphere_cart_to_bl(mt->a, x, &r, &th);
            if (r > rp && !cr_sphere_velocity(mt, s->omega, r, th, u)) {
                *r_bad = r;
                *th_bad = th;
                return 1;
            }
        }
    }
    return 0;
}

/* Cartesian point x (2.2.8) at BL time t in the sphere's own coordinates,
 * those of its prepared centre and axes: x turned by -omega t about the
 * polar axis (x itself for omega = 0, exactly). */
CR_HD static inline void cr_sphere_unturn(const cr_sphere *s, double t, const double x[3],
                                          double xl[3])
{
    double ang = s->omega * t, c = cos(ang), sn = sin(ang);
    xl[0] = c * x[0] + sn * x[1];
    xl[1] = c * x[1] - sn * x[0];
    xl[2] = x[2];
}

/* The place of particle sphere sp at BL time t: centre c, turn angle *ang
 * = ph(t) - ph0, and their rates dc/dt, *w = dph/dt (track.h). Returns 0
 * outside the table's times (no sphere then), else 1. */
CR_HD static inline int cr_sphere_pose(const cr_frame *f, const cr_sphere *sp, double t,
                                       double c[3], double *ang, double dc[3], double *w)
{
    if (!cr_track_at(f->track + sp->wl.off, sp->wl.n, sp->wl.t0, sp->wl.h, t, c,
                     ang, dc, w))
        return 0;
    *ang -= sp->wl.ph0;
    return 1;
}

/* Cartesian point x at BL time t in moving sphere sp's own coordinates:
 * cr_sphere_unturn for a turning one; for a particle sphere x taken back by
 * its pose (cr_sphere_pose), R_z(-ang) (x - c) + c0. Returns 0 where a
 * particle sphere has no place at t, else 1. */
CR_HD static inline int cr_sphere_local_at(const cr_frame *f, const cr_sphere *sp, double t,
                                           const double x[3], double xl[3])
{
    double c[3], dc[3], ang, w, d[3], cs, sn;
    if (!sp->particle) {
        cr_sphere_unturn(sp, t, x, xl);
        return 1;
    }
    if (!cr_sphere_pose(f, sp, t, c, &ang, dc, &w))
        return 0;
    cs = cos(ang);
    sn = sin(ang);
    d[0] = x[0] - c[0];
    d[1] = x[1] - c[1];
    d[2] = x[2] - c[2];
    xl[0] = cs * d[0] + sn * d[1] + sp->center[0];
    xl[1] = cs * d[1] - sn * d[0] + sp->center[1];
    xl[2] = d[2] + sp->center[2];
    return 1;
}

/* How far particle sphere sp moves between BL times ta and tb, as an angle
 * (compared with CR_SPHERE_MAX_TURN): the larger of its turn and its
 * centre's displacement over the larger of |c| and its radius; 0 where
 * both times lie on one side outside its table (no sphere in between: t is
 * monotonic along a ray outside the horizon) or one is NaN (no BL time: no
 * place either), INFINITY where one of them is outside (t = +infinity at
 * the start of a ray from the observer at infinity included) and the other
 * inside or beyond it (the piece is halved to find the table's end). */
CR_HD static inline double cr_sphere_moved(const cr_frame *f, const cr_sphere *sp, double ta,
                                           double tb)
{
    double ca[3], cb[3], da[3], db[3], aa, ab, wa, wb, t_end, d2 = 0.0, c2 = 0.0;
    int ia = cr_sphere_pose(f, sp, ta, ca, &aa, da, &wa);
    int ib = cr_sphere_pose(f, sp, tb, cb, &ab, db, &wb), k;
    if (!ia || !ib) {
        t_end = sp->wl.t0 + (double)(sp->wl.n - 1) * sp->wl.h;
        if ((ta < sp->wl.t0 && tb < sp->wl.t0) || (ta > t_end && tb > t_end) ||
            !(ta == ta) || !(tb == tb))
            return 0.0;
        return INFINITY;
    }
    for (k = 0; k < 3; k++) {
        d2 += (cb[k] - ca[k]) * (cb[k] - ca[k]);
        c2 += ca[k] * ca[k];
    }
    return fmax(fabs(ab - aa), sqrt(d2) / fmax(sqrt(c2), sp->radius));
}

/* BL time t_obs - delay of the ray's state y at fraction s of its current
 * step (NaN where the ray has no BL time: cr_ray_delay). */
CR_HD static inline double cr_sphere_ray_time(const cr_frame *f, const cr_ray *ray, double s,
                                              const double *y)
{
    /* at the step's ends T is the state's own (cr_ray_time_step; an end
     * beyond every object moving outward, whose T it may leave unresolved,
     * is no sphere's hit) */
    if (s <= 0.0 || s >= 1.0)
        return f->t_obs - cr_ray_delay(ray, y);
    return f->t_obs - cr_ray_delay_at(f, ray, s, y);
}

/* The point of state y (fraction s of the current step) in sphere k's own
 * coordinates: its Cartesian position, taken back for a moving sphere by
 * the sphere's motion at the state's time (cr_sphere_local_at). Returns 0
 * where a moving sphere has no time there, or a particle sphere no place
 * (no hit can be there), else 1. */
CR_HD static inline int cr_sphere_local(const cr_frame *f, const cr_ray *ray, int k, double s,
                                        const double *y, double xl[3])
{
    const cr_sphere *sp = &f->spheres[k];
    double x[3], t;
    cr_ray_cart(f, ray, y, x);
    if (!sp->moving) {
        xl[0] = x[0];
        xl[1] = x[1];
        xl[2] = x[2];
        return 1;
    }
    t = cr_sphere_ray_time(f, ray, s, y);
    if (!cr_isfinite(t))
        return 0;
    return cr_sphere_local_at(f, sp, t, x, xl);
}

/* Value of sphere k's surface function (cr_sphere_f) at state y, fraction
 * s of the ray's current step: at the sphere's place at the state's time
 * (cr_sphere_local); 1 (outside) where a moving sphere has none. */
CR_HD static inline double cr_sphere_value(const cr_frame *f, const cr_ray *ray, int k, double s,
                                           const double *y)
{
    double xl[3];
    if (!cr_sphere_local(f, ray, k, s, y, xl))
        return 1.0;
    return cr_sphere_f(&f->spheres[k], xl);
}

/* Locate the root of sphere k's surface function inside the current step,
 * where the value is v0 at fraction s_lo and v1 of opposite sign at s_hi,
 * s_lo < s_hi <= 1, by regula falsi (cr_falsi) on cr_ray_state_at.
 * Returns the fraction s and the state there in ys. */
CR_HD static inline double cr_sphere_locate(const cr_frame *f, const cr_ray *ray, int k,
                                            double s_lo, double v0, double s_hi, double v1,
                                            double *ys)
{
    cr_falsi z;
    cr_falsi_start(&z, v0, s_hi, v1);
    z.s_lo = s_lo;
    while (cr_falsi_next(&z)) {
        cr_ray_state_at(ray, z.s, ys);
        if (!cr_falsi_update(&z, cr_sphere_value(f, ray, k, z.s, ys)))
            break;
    }
    return z.s;
}

/* Smallest value of sphere event k along fractions [lo, hi] of the current
 * step, by golden-section search on cr_ray_state_at (the squared distance to
 * a sphere along one step, or one piece of a step, is unimodal). Returns the
 * value, *s_min its place. */
CR_HD static inline double cr_sphere_dip(const cr_frame *f, const cr_ray *ray, int k, double lo,
                                         double hi, double *s_min, double *ys)
{
    cr_golden g;
    int it;
    cr_golden_start(&g, lo, hi);
    cr_ray_state_at(ray, g.x1, ys);
    g.f1 = cr_sphere_value(f, ray, k, g.x1, ys);
    cr_ray_state_at(ray, g.x2, ys);
    g.f2 = cr_sphere_value(f, ray, k, g.x2, ys);
    for (it = 0; it < 40 && g.f1 >= 0.0 && g.f2 >= 0.0; it++) {
        int which = cr_golden_shrink(&g);
        double x = which == 1 ? g.x1 : g.x2;
        cr_ray_state_at(ray, x, ys);
        if (which == 1)
            g.f1 = cr_sphere_value(f, ray, k, x, ys);
        else
            g.f2 = cr_sphere_value(f, ray, k, x, ys);
    }
    *s_min = g.f1 < g.f2 ? g.x1 : g.x2;
    return g.f1 < g.f2 ? g.f1 : g.f2;
}

/* The earliest hit of sphere k within fractions [sa, sb] of the current
 * step, xa and xb the sphere's own coordinates (cr_sphere_local) of the
 * states there, before best (a hit of another sphere found already).
 * Catches both a sign change of |x - c|^2 - R^2 and a ray that enters and
 * leaves within [sa, sb]: under RK4 (short, nearly straight steps) where the
 * chord passes inside the sphere; under Mino (a step may cross much of the
 * scene, and its fraction is not proportional to the distance along the
 * chord) where the chord passes within R plus a quarter of its length, the
 * closest approach is found by cr_sphere_dip. Returns the located fraction
 * with its state in ys, or 2 (none). */
CR_HD static inline double cr_sphere_piece(const cr_frame *f, const cr_ray *ray, int k, double sa,
                                           double sb, const double xa[3], const double xb[3],
                                           double best, double *ys)
{
    const cr_sphere *sp = &f->spheres[k];
    double v0 = cr_sphere_f(sp, xa), v1 = cr_sphere_f(sp, xb);
    double s_hi = sb;
    if (v0 == 0.0)
        return 2.0;
    if ((v0 < 0.0) == (v1 < 0.0)) {
        /* both ends on one side: look for a dip inside at the chord's
         * closest approach to the centre */
        double d[3], w[3], dd = 0.0, wd = 0.0, t, xm[3];
        int i;
        if (v0 < 0.0)
            return 2.0;
        for (i = 0; i < 3; i++) {
            d[i] = xb[i] - xa[i];
            w[i] = xa[i] - sp->center[i];
            dd += d[i] * d[i];
            wd += w[i] * d[i];
        }
        if (!(dd > 0.0))
            return 2.0;
        t = -wd / dd;
        if (cr_ray_long_steps(ray)) {
            double dist2 = 0.0, slack = sp->radius + 0.25 * sqrt(dd);
            t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
            for (i = 0; i < 3; i++) {
                xm[i] = xa[i] + t * d[i] - sp->center[i];
                dist2 += xm[i] * xm[i];
            }
            if (dist2 >= slack * slack)
                return 2.0;
            v1 = cr_sphere_dip(f, ray, k, sa, sb, &t, ys);
        } else {
            if (t <= 0.0 || t >= 1.0)
                return 2.0;
            for (i = 0; i < 3; i++)
                xm[i] = xa[i] + t * d[i];
            if (cr_sphere_f(sp, xm) >= 0.0)
                return 2.0;
            t = sa + t * (sb - sa);
            cr_ray_state_at(ray, t, ys);
            v1 = cr_sphere_value(f, ray, k, t, ys);
        }
        if (v1 >= 0.0)
            return 2.0;
        s_hi = t;
    }
    if (s_hi >= best)
        return 2.0;
    return cr_sphere_locate(f, ray, k, sa, v0, s_hi, v1, ys);
}

/* Whether moving sphere k cannot be met within a piece of the current step
 * from state y0 (world Cartesian x0) to y1 (x1): the piece's chord stays
 * beyond the ball |x| <= |c| + R
 * about the origin that holds the sphere at every time, or beyond the slab
 * |z - c_z| <= R, by a quarter of its length under Mino (cr_sphere_piece's
 * slack); or the piece starts and ends inside the sphere's smallest BL
 * radius, sqrt((|c| - R)^2 - a^2) (for a particle sphere the ball, slab and
 * radius of its bounds over the table: wl.reach_hi, wl.z_lo .. wl.z_hi,
 * wl.reach_lo)
 * (|x|^2 = r^2 + a^2 sin^2 theta <= r^2 +
 * a^2), moving inward at both ends: leaving that radius and coming back
 * within it would take two radial turning points, which light outside
 * the horizon never has (it has no bound orbits there). */
CR_HD static inline int cr_sphere_far(const cr_frame *f, const cr_ray *ray, int k,
                                      const double x0[3], const double x1[3], const double *y0,
                                      const double *y1)
{
    const cr_sphere *sp = &f->spheres[k];
    const double *c = sp->center;
    double d[3], dd = 0.0, xd = 0.0, t, dist2 = 0.0, slack;
    double cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), rho = cn + sp->radius;
    double lo = cn - sp->radius, a = f->metric.a;
    double z_hi = c[2] + sp->radius, z_lo = c[2] - sp->radius;
    int i;
    if (sp->particle) {
        rho = sp->wl.reach_hi;
        lo = sp->wl.reach_lo;
        z_hi = sp->wl.z_hi;
        z_lo = sp->wl.z_lo;
    }
    for (i = 0; i < 3; i++) {
        d[i] = x1[i] - x0[i];
        dd += d[i] * d[i];
        xd += x0[i] * d[i];
    }
    slack = cr_ray_long_steps(ray) ? 0.25 * sqrt(dd) : 0.0;
    if (fmin(x0[2], x1[2]) > z_hi + slack || fmax(x0[2], x1[2]) < z_lo - slack)
        return 1;
    t = dd > 0.0 ? -xd / dd : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    for (i = 0; i < 3; i++) {
        double xm = x0[i] + t * d[i];
        dist2 += xm * xm;
    }
    if (dist2 >= (rho + slack) * (rho + slack))
        return 1;
    if (lo > fabs(a)) {
        /* BL r at the step's ends: 1 / w under Mino (BL here: no event is
         * looked for in the ingoing chart), r under RK4 */
        double r2_lo = lo * lo - a * a;
        if (ray->kind == CR_INTEG_MINO)
            return y0[CR_M_DW] > 0.0 && y1[CR_M_DW] > 0.0 &&
                   y0[CR_M_W] * y0[CR_M_W] * r2_lo > 1.0 && y1[CR_M_W] * y1[CR_M_W] * r2_lo > 1.0;
        return y0[CR_Y_UR] < 0.0 && y1[CR_Y_UR] < 0.0 && y0[CR_Y_R] * y0[CR_Y_R] < r2_lo &&
               y1[CR_Y_R] * y1[CR_Y_R] < r2_lo;
    }
    return 0;
}

/* Pieces of a step that a turning sphere's hits are looked for in, at
 * most, and how often a piece may be halved to turn by at most
 * CR_SPHERE_MAX_TURN. */
#define CR_SPHERE_MAX_PIECES 64
#define CR_SPHERE_MAX_HALVINGS 8

/* The earliest hit before best of turning sphere k (omega != 0) or
 * particle sphere k within the current step (x0, x1 the world Cartesian
 * positions at its ends), or 2. The step is walked in pieces from its
 * start: a piece that cr_sphere_far rules out is passed over whole; one that
 * may meet the sphere is halved until the sphere turns (or, a particle
 * sphere, moves: cr_sphere_moved) by at most CR_SPHERE_MAX_TURN over it
 * (judged on the dense output's own T) and looked at as a static sphere is
 * over a step (cr_sphere_piece), at the states' times. A particle sphere's
 * piece with an end where it has no place (outside its table) is passed
 * over. The next trial piece is twice the last; the last of
 * CR_SPHERE_MAX_PIECES pieces takes the rest of the step. */
CR_HD static inline double cr_sphere_turning(const cr_frame *f, const cr_ray *ray, int k,
                                             const double x0[3], const double x1[3],
                                             double best, double *ys)
{
    const cr_sphere *sp = &f->spheres[k];
    double sa = 0.0, len = 1.0, ya[CR_RAY_NY], yb[CR_RAY_NY], xa[3], xb[3], la[3], lb[3];
    double ta, tb, s;
    int pieces, have_la = 0, i;
    for (i = 0; i < CR_RAY_NY; i++)
        ya[i] = cr_ray_y0(ray)[i];
    for (i = 0; i < 3; i++)
        xa[i] = x0[i];
    ta = f->t_obs - cr_ray_delay(ray, ya);
    for (pieces = 1; sa < 1.0 && sa < best; pieces++) {
        double sb;
        int h, far = 0;
        len = fmin(len, 1.0 - sa);
        for (h = 0;; h++) {
            sb = pieces == CR_SPHERE_MAX_PIECES ? 1.0 : (sa + len >= 1.0 ? 1.0 : sa + len);
            if (sb >= 1.0) {
                for (i = 0; i < CR_RAY_NY; i++)
                    yb[i] = cr_ray_y1(ray)[i];
                for (i = 0; i < 3; i++)
                    xb[i] = x1[i];
            } else {
                cr_ray_state_at(ray, sb, yb);
                cr_ray_cart(f, ray, yb, xb);
            }
            tb = f->t_obs - cr_ray_delay(ray, yb); /* the dense T: for the size */
            if (cr_sphere_far(f, ray, k, xa, xb, ya, yb)) {
                far = 1;
                break;
            }
            if (!((sp->particle ? cr_sphere_moved(f, sp, ta, tb) : fabs(sp->omega * (tb - ta))) >
                  CR_SPHERE_MAX_TURN) ||
                h == CR_SPHERE_MAX_HALVINGS || (sb >= 1.0 && pieces == CR_SPHERE_MAX_PIECES))
                break;
            len *= 0.5;
        }
        if (!far) {
            /* the sphere's own coordinates at both ends, at their times */
            if ((!have_la && !cr_sphere_local(f, ray, k, sa, ya, la)) ||
                !cr_sphere_local(f, ray, k, sb, yb, lb)) {
                if (!sp->particle)
                    return 2.0; /* no time: none further on either */
                far = 1;
            } else {
                s = cr_sphere_piece(f, ray, k, sa, sb, la, lb, best, ys);
                if (s <= 1.0)
                    return s;
                for (i = 0; i < 3; i++)
                    la[i] = lb[i];
            }
        }
        have_la = !far;
        sa = sb;
        ta = tb;
        len *= 2.0;
        for (i = 0; i < CR_RAY_NY; i++)
            ya[i] = yb[i];
        for (i = 0; i < 3; i++)
            xa[i] = xb[i];
    }
    return 2.0;
}

/* Earliest sphere hit within the current step (x0, x1 the Cartesian
 * positions at its ends): for each sphere the earliest hit of the whole
 * step as one piece (cr_sphere_piece) for a static sphere or one at rest
 * (looked for at the states' times all the same), of cr_sphere_turning's
 * pieces for a turning one or a particle sphere. Returns the sphere index or -1; on a hit,
 * *s_out and ys hold the located point. */
CR_HD static inline int cr_sphere_events(const cr_frame *f, const cr_ray *ray,
                                         const double x0[3], const double x1[3], double *s_out,
                                         double *ys)
{
    int best = -1, k, i;
    double best_s = 2.0, tmp[CR_RAY_NY];
    for (k = 0; k < f->n_spheres; k++) {
        const cr_sphere *sp = &f->spheres[k];
        double xa[3], xb[3], s;
        if (sp->moving && (sp->omega != 0.0 || sp->particle)) {
            s = cr_sphere_turning(f, ray, k, x0, x1, best_s, tmp);
        } else {
            if (sp->moving) {
                double ta = cr_sphere_ray_time(f, ray, 0.0, cr_ray_y0(ray));
                double tb = cr_sphere_ray_time(f, ray, 1.0, cr_ray_y1(ray));
                if (!cr_isfinite(ta) || !cr_isfinite(tb))
                    continue; /* no BL time: nothing drawn there (ray.h) */
                cr_sphere_unturn(sp, ta, x0, xa);
                cr_sphere_unturn(sp, tb, x1, xb);
            } else {
                for (i = 0; i < 3; i++) {
                    xa[i] = x0[i];
                    xb[i] = x1[i];
                }
            }
            s = cr_sphere_piece(f, ray, k, 0.0, 1.0, xa, xb, best_s, tmp);
        }
        if (s < best_s) {
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

/* The 4-velocity u^mu (BL) of particle sphere sp's matter at Cartesian
 * point x (BL r, th) at BL time t: its rigid motion's coordinate velocity
 * there, dx/dt = dc/dt + dph/dt z^ x (x - c) (cr_sphere_pose), in BL rates
 * (cr_cart_vel_to_bl) and normalised, u = u^t (1, dr/dt, dth/dt, dph/dt)
 * with u^t = 1 / sqrt(-g(dx/dt, dx/dt)); at the centre, the worldline's own
 * u^mu. Returns 1, or 0 where the sphere has no place at t or that is not
 * timelike (u untouched). */
CR_HD static inline int cr_sphere_particle_u(const cr_frame *f, const cr_sphere *sp, double t,
                                             const double x[3], double r, double th,
                                             double u[4])
{
    double c[3], dc[3], ang, w, v[3], dr, dth, dph, n;
    cr_metric_point q;
    if (!cr_sphere_pose(f, sp, t, c, &ang, dc, &w))
        return 0;
    v[0] = dc[0] - w * (x[1] - c[1]);
    v[1] = dc[1] + w * (x[0] - c[0]);
    v[2] = dc[2];
    cr_cart_vel_to_bl(f->metric.a, r, th, x, v, &dr, &dth, &dph);
    cr_metric_eval(&f->metric, r, th, &q);
    n = -(q.g_tt + dph * (2.0 * q.g_tph + dph * q.g_phph) + q.g_rr * dr * dr +
          q.g_thth * dth * dth);
    if (!(n > 0.0) || !cr_isfinite(n))
        return 0;
    u[0] = 1.0 / sqrt(n);
    u[1] = dr * u[0];
    u[2] = dth * u[0];
    u[3] = dph * u[0];
    return 1;
}

/* Shade a sphere hit h: outcome, sphere index, hit radius and azimuth, delay,
 * the chessboard colour there (in the sphere's own coordinates at the hit's
 * time: the pattern moves with a moving sphere) and the frequency ratio: of
 * a static source (6.9) for a static sphere; for a moving one the one
 * frequency ratio with its matter's 4-velocity at the hit point
 * (cr_sphere_velocity; cr_sphere_particle_u for a particle sphere), and bolo = g^4, the bolometric intensity of a
 * surface of unit intensity in its rest frame (I / nu^4 is invariant for
 * the frequency-integrated intensity). */
CR_HD static inline void cr_sphere_shade(const cr_frame *f, const cr_ray *ray, const cr_hit *h,
                                         cr_pixel *px)
{
    const cr_sphere *sp = &f->spheres[h->index];
    double xs[3], rr, th, ph, p[4], u[4];
    int i, ok;
    cr_ray_position(ray, h->y, &rr, &th, &ph);
    px->outcome = CR_OUT_SPHERE;
    px->object = (int16_t)h->index;
    px->hit_r = rr;
    px->hit_phi = cr_wrap_2pi(ph);
    px->delay = cr_ray_delay_at(f, ray, h->s, h->y);
    cr_ray_cart(f, ray, h->y, xs);
    if (sp->moving) {
        double xl[3];
        if (!cr_sphere_local_at(f, sp, f->t_obs - px->delay, xs, xl))
            for (i = 0; i < 3; i++) /* at its table's very end (not met outside it) */
                xl[i] = sp->center[i];
        px->color = cr_sphere_color(sp, xl);
    } else {
        px->color = cr_sphere_color(sp, xs);
    }
    cr_ray_momentum(ray, h->y, p);
    if (!sp->moving) {
        px->redshift = cr_redshift_static(f, ray->p_obs, p, rr, th);
        return;
    }
    ok = sp->particle ? cr_sphere_particle_u(f, sp, f->t_obs - px->delay, xs, rr, th, u)
                      : cr_sphere_velocity(&f->metric, sp->omega, rr, th, u);
    px->redshift = ok ? cr_frame_shift(f, ray->p_obs, p, u) : -1.0;
    if (px->redshift > 0.0) {
        double g2 = px->redshift * px->redshift;
        px->bolo = g2 * g2;
    }
}

#endif
