/* curray core: observers that move, and the projections of their camera
 * (observer.motion, observer.projection; DESIGN "One observer construction").
 *
 * Tetrad. Every finite observer's orthonormal frame is the ZAMO tetrad
 * boosted by the observer's 3-velocity v measured by the ZAMO:
 *   ZAMO (zero angular momentum observer, Bardeen 1972), with
 *   A = (r^2 + a^2)^2 - Delta a^2 sin^2, alpha = sqrt(Delta Sigma / A) (the
 *   lapse), omega = -g_tphi / g_phph = a (2 M r - Q^2) / A:
 *     e_0 = (d_t + omega d_phi) / alpha,  e_r = d_r / sqrt(g_rr),
 *     e_th = d_th / sqrt(g_thth),          e_ph = d_phi / sqrt(g_phph);
 *   the pure Lorentz boost by v = v^i e_i (|v| < 1, gamma = 1/sqrt(1 - v^2)):
 *     e_0' = gamma (e_0 + v^i e_i),
 *     e_j' = e_j + gamma v_j e_0 + (gamma - 1) v_j v^k e_k / v^2.
 * e_0' is the observer's 4-velocity; e_r', e_th', e_ph' are its local axes
 * (the camera's x, y, z of camera.h), so aberration and Doppler shift follow
 * from the tetrad alone. On the polar axis (sin theta = 0) e_ph does not
 * exist (its row is left zero, as camera.h does for the static observer):
 * there an observer may move only along r.
 *
 * Motions (cr_motion), v in the ZAMO frame:
 *   static:   v = (0, 0, -omega sqrt(g_phph) / alpha), the boost that cancels
 *             the frame dragging (|v| < 1 exactly outside the ergosurface);
 *             camera.h builds its tetrad directly (the paper's), unchanged;
 *   zamo:     v = 0;
 *   orbit:    the circular equatorial geodesic of sense s at r (orbit.h):
 *             v = (0, 0, sqrt(g_phph) (Omega - omega) / alpha); needs
 *             theta = pi/2 and a timelike orbit there (cr_orbit_eval);
 *   infall:   the geodesic falling from rest at infinity, E = 1, L = 0,
 *             Carter constant 0 (so u^theta = 0): gamma = 1/alpha, radial,
 *             v = (-sqrt((r^2 + a^2)(2 M r - Q^2) / A), 0, 0)
 *             (1 - alpha^2 written without cancellation); Schwarzschild:
 *             v = sqrt(2M/r);
 *   velocity: v = (v_r, v_th, v_ph) as given.
 *
 * Inside the outer horizon (r- < r < r+; frame obs_inside) Delta < 0: no
 * static observer, no ZAMO (alpha^2 = Delta Sigma / A < 0) and no circular
 * orbit exist, and r is a time coordinate. The frame used there is the free
 * fall from rest at infinity itself, regular through r+
 * (cr_freefall_tetrad): with u the infall 4-velocity above (E = 1, L = 0,
 * Carter constant 0; u^r = -sqrt((r^2 + a^2)(2Mr - Q^2))/Sigma, u^t =
 * A/(Sigma Delta), u^phi = a (2Mr - Q^2)/(Sigma Delta), u_t = -1, u_phi = 0):
 *   e_0 = u,  e_r = (Delta d_r + Sigma u^r u)/sqrt(A),
 *   e_th = d_th / sqrt(Sigma),  e_ph = d_phi / sqrt(g_phph);
 * e_r is the unit vector orthogonal to u, e_th, e_ph, with g(e_r, e_r) =
 * (Delta Sigma + Sigma^2 (u^r)^2)/A = 1, written with the factor Delta so
 * that it is continuous across r+ in ingoing coordinates (it points to larger
 * r outside, where it equals the boosted ZAMO tetrad of infall). Motions
 * there: infall (this frame) and velocity (this frame boosted by v, v now
 * measured by the free-faller, not by a ZAMO); static, zamo and orbit are
 * refused by the scene's validation.
 *
 * Projections (cr_projection): pixel -> screen point (sx, sy) is linear,
 * (2 (i + 1/2)/W - 1) hx, (1 - 2 (j + 1/2)/H) hy (cr_camera_screen), with
 * (hx, hy) the frame's tan_half_h, tan_half_v; the screen point -> unit
 * direction n in the camera's forward F, right R, up U:
 *   rectilinear:     hx = tan(hfov/2);  n ~ F + sx R + sy U (normalised);
 *   fisheye:         hx = hfov/2 (equidistant: the angle from F is the
 *                    distance from the image centre), rho = |(sx, sy)|,
 *                    n = cos(rho) F + sin(rho) (sx R + sy U) / rho; the
 *                    picture is the image circle rho <= max(hx, hy) (<= pi),
 *                    points outside it are not traced (camera.h,
 *                    cr_camera_in_image);
 *   equirectangular: hx = pi, hy = pi/2; longitude sx, latitude sy,
 *                    n = cos(sy) (cos(sx) F + sin(sx) R) + sin(sy) U.
 * cr_projection_screen is the inverse (tests/test_observer.c).
 */
#ifndef CR_CORE_OBSERVER_H
#define CR_CORE_OBSERVER_H

#include "orbit.h"

/* The ZAMO tetrad at BL (r, th): e[a][mu] = BL component mu of e_a
 * (a = 0: e_0, then e_r, e_th, e_ph). On the axis (on_axis != 0) e_ph is
 * zero and e_0 = d_t / sqrt(-g_tt) (omega = 0 there). Requires r outside
 * the outer horizon. Also returns alpha, omega and sqrt(g_phph) (0 on the
 * axis) when the pointers are not NULL. */
CR_HD static inline void cr_zamo_tetrad(const cr_metric *mt, double r, double th, int on_axis,
                                        double e[4][4], double *alpha, double *omega,
                                        double *sqrt_gphph)
{
    cr_metric_point p;
    double al, om = 0.0, sp = 0.0;
    int a, b;
    cr_metric_eval(mt, r, th, &p);
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++)
            e[a][b] = 0.0;
    if (on_axis) {
        al = sqrt(-p.g_tt);
    } else {
        al = sqrt(p.delta * p.sigma / p.A_);
        om = mt->a * p.W_ / p.A_;
        sp = sqrt(p.g_phph);
        e[3][3] = 1.0 / sp;
    }
    e[0][0] = 1.0 / al;
    e[0][3] = om / al;
    e[1][1] = 1.0 / sqrt(p.g_rr);
    e[2][2] = 1.0 / sqrt(p.g_thth);
    if (alpha)
        *alpha = al;
    if (omega)
        *omega = om;
    if (sqrt_gphph)
        *sqrt_gphph = sp;
}

/* The free-fall frame of the header comment at BL (r, th), r != r+-: e[a][mu]
 * = BL contravariant component mu of leg a (rows e_0, e_r, e_th, e_ph; e_ph
 * zero on the axis) and low[a][0], low[a][1] = its covariant t and phi
 * components, which stay regular at r+ where the BL contravariant ones grow
 * as 1/Delta. Valid on both sides of r+ wherever 2Mr - Q^2 >= 0. */
CR_HD static inline void cr_freefall_tetrad(const cr_metric *mt, double r, double th,
                                            int on_axis, double e[4][4], double low[4][2])
{
    cr_metric_point p;
    double u[4], ur, sA, k;
    int a, b;
    cr_metric_eval(mt, r, th, &p);
    for (a = 0; a < 4; a++) {
        for (b = 0; b < 4; b++)
            e[a][b] = 0.0;
        low[a][0] = low[a][1] = 0.0;
    }
    ur = -sqrt((r * r + mt->a * mt->a) * fmax(p.W_, 0.0)) / p.sigma;
    u[0] = p.A_ / (p.sigma * p.delta);
    u[1] = ur;
    u[2] = 0.0;
    u[3] = mt->a * p.W_ / (p.sigma * p.delta);
    sA = sqrt(p.A_);
    k = p.sigma * ur / sA;
    for (b = 0; b < 4; b++) {
        e[0][b] = u[b];
        e[1][b] = k * u[b];
    }
    e[1][1] = (p.delta + p.sigma * ur * ur) / sA;
    e[2][2] = 1.0 / sqrt(p.sigma);
    low[0][0] = -1.0; /* u_t = -E, E = 1; u_phi = L = 0 */
    low[1][0] = -k;   /* (Sigma u^r u_t)/sqrt(A); g_tr = 0 */
    if (!on_axis) {
        double sp = sqrt(p.g_phph);
        e[3][3] = 1.0 / sp;
        low[3][0] = p.g_tph / sp;
        low[3][1] = sp;
    }
}

/* The worldline of the infall motion (E = 1, L = 0, Carter constant 0, so
 * theta stays fixed), from BL radius r0 down to r (r0 >= r, 2Mr - Q^2 > 0
 * on the way, through r+ if need be), with W = 2Mr - Q^2:
 *   proper time  tau = int_r^r0 Sigma / sqrt((r^2 + a^2) W) dr   (u^r = -sqrt((r^2+a^2) W)/Sigma),
 *   ingoing azimuth  phi~(r0) - phi~(r) = int_r^r0 a / (sqrt(r^2 + a^2) (sqrt(W) + sqrt(r^2 + a^2))) dr
 * (d phi~/dr = (u^phi + (a/Delta) u^r)/u^r, the 1/Delta cancelled: regular at
 * r+). Gauss-Legendre, 4 points on each of n pieces (n = 2000: the
 * integrands are smooth, relative error ~1e-14 for r >= 1e-3 M). Host code
 * (scene evaluation of an animated plunge). */
CR_HD static inline void cr_infall_worldline(const cr_metric *mt, double th, double r0, double r,
                                             double *tau, double *dphi)
{
    const double x4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                          0.8611363115940526};
    const double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                          0.3478548451374538};
    const int n = 2000;
    double h = (r0 - r) / n, c2 = cos(th) * cos(th), a2 = mt->a * mt->a, st = 0.0, sp = 0.0;
    int i, j;
    for (i = 0; i < n; i++)
        for (j = 0; j < 4; j++) {
            double x = r + h * (i + 0.5 + 0.5 * x4[j]);
            double ra = sqrt(x * x + a2), W = sqrt(fmax(2.0 * mt->m * x - mt->q * mt->q, 0.0));
            st += w4[j] * (x * x + a2 * c2) / (ra * W);
            sp += w4[j] * mt->a / (ra * (W + ra));
        }
    *tau = 0.5 * h * st;
    *dphi = 0.5 * h * sp;
}

/* The tetrad e (rows e_0, e_1, e_2, e_3, BL components) boosted by the
 * 3-velocity v = v^i e_i (|v| < 1), written to out (may not alias e). */
CR_HD static inline void cr_boost_tetrad(const double e[4][4], const double v[3],
                                         double out[4][4])
{
    double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    double gam = 1.0 / sqrt(1.0 - v2);
    /* (gamma - 1) / v^2 = gamma^2 / (gamma + 1), finite as v -> 0 */
    double k = gam * gam / (gam + 1.0);
    int i, j, mu;
    for (mu = 0; mu < 4; mu++) {
        out[0][mu] = gam * (e[0][mu] + v[0] * e[1][mu] + v[1] * e[2][mu] + v[2] * e[3][mu]);
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (i = 0; i < 3; i++)
                s += v[i] * e[i + 1][mu];
            out[j + 1][mu] = e[j + 1][mu] + gam * v[j] * e[0][mu] + k * v[j] * s;
        }
    }
}

/* The 3-velocity v, measured by the ZAMO at (o->r, o->theta), of an observer
 * of motion o->motion (header comment); CR_MOTION_VELOCITY copies o->v. The
 * orbit's sense is cr_orbit_sense(mt, !o->retrograde). Returns 1, or 0 where
 * that motion does not exist there: no timelike circular orbit (off the
 * equator, or inside the photon orbit). The caller checks |v| < 1 (a static
 * observer inside the ergosurface gets |v| >= 1). */
CR_HD static inline int cr_observer_zamo_velocity(const cr_metric *mt, const cr_observer *o,
                                                  int on_axis, double v[3])
{
    double e[4][4], alpha, omega, sp;
    cr_metric_point p;
    v[0] = v[1] = v[2] = 0.0;
    cr_zamo_tetrad(mt, o->r, o->theta, on_axis, e, &alpha, &omega, &sp);
    switch (o->motion) {
    case CR_MOTION_STATIC:
        v[2] = -omega * sp / alpha;
        return 1;
    case CR_MOTION_ORBIT: {
        cr_orbit orb;
        if (fabs(o->theta - 0.5 * CR_PI) > 1e-9 ||
            !cr_orbit_eval(mt, cr_orbit_sense(mt, !o->retrograde), o->r, &orb))
            return 0;
        v[2] = sp * (orb.omega - omega) / alpha;
        return 1;
    }
    case CR_MOTION_INFALL: {
        double r2a2 = o->r * o->r + mt->a * mt->a;
        cr_metric_eval(mt, o->r, o->theta, &p);
        v[0] = -sqrt(r2a2 * p.W_ / p.A_);
        return 1;
    }
    case CR_MOTION_VELOCITY:
        v[0] = o->v[0];
        v[1] = o->v[1];
        v[2] = o->v[2];
        return 1;
    default: /* CR_MOTION_ZAMO */
        return 1;
    }
}

/* Unit direction n (components along the camera's forward, right, up) of
 * screen point (sx, sy) under projection proj (header comment). */
CR_HD static inline void cr_projection_dir(int proj, double sx, double sy, double n[3])
{
    if (proj == CR_PROJ_FISHEYE) {
        double rho = sqrt(sx * sx + sy * sy);
        double s = rho > 0.0 ? sin(rho) / rho : 1.0;
        n[0] = cos(rho);
        n[1] = s * sx;
        n[2] = s * sy;
    } else if (proj == CR_PROJ_EQUIRECT) {
        double c = cos(sy);
        n[0] = c * cos(sx);
        n[1] = c * sin(sx);
        n[2] = sin(sy);
    } else {
        double len = sqrt(1.0 + sx * sx + sy * sy);
        n[0] = 1.0 / len;
        n[1] = sx / len;
        n[2] = sy / len;
    }
}

/* The inverse: the screen point (sx, sy) of the direction n (forward, right,
 * up components, any length > 0). Returns 0 where the projection does not
 * show n (rectilinear: n not in front; fisheye: n straight behind, where
 * every azimuth meets), else 1. Fisheye angles are in [0, pi], equirectangular
 * longitudes in (-pi, pi], latitudes in [-pi/2, pi/2]. */
CR_HD static inline int cr_projection_screen(int proj, const double n[3], double *sx,
                                             double *sy)
{
    double h = sqrt(n[1] * n[1] + n[2] * n[2]);
    if (proj == CR_PROJ_FISHEYE) {
        double rho = atan2(h, n[0]);
        if (h == 0.0) {
            *sx = *sy = 0.0;
            return n[0] > 0.0;
        }
        *sx = rho * n[1] / h;
        *sy = rho * n[2] / h;
        return 1;
    }
    if (proj == CR_PROJ_EQUIRECT) {
        *sx = atan2(n[1], n[0]);
        *sy = atan2(n[2], sqrt(n[0] * n[0] + n[1] * n[1]));
        return 1;
    }
    if (!(n[0] > 0.0))
        return 0;
    *sx = n[1] / n[0];
    *sy = n[2] / n[0];
    return 1;
}

#endif
