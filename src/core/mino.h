/* curray core: null geodesics of Kerr-Newman in Mino time, integrated by
 * Dormand-Prince 5(4) with error control and dense output.
 *
 * Formulation (Carter 1968; Mino 2003; Gralla & Lupsasca 2020 for Kerr; for
 * Kerr-Newman only Delta changes, a photon has no charge). With Mino time tau,
 * d lambda = Sigma d tau, and the constants of the ray in the sign convention
 * of geodesic.h (E = u_t, L = u_phi of the past-directed tangent u, eta the
 * Carter constant K of cr_geo_carter):
 *   P(r)  = E (r^2 + a^2) + a L
 *   R(r)  = P^2 - Delta [eta + (L + a E)^2]         (dr/dtau)^2 = R
 *   Th(u) = eta - (eta + L^2 - a^2 E^2) u^2 - a^2 E^2 u^4,  u = cos(theta),
 *                                                  (du/dtau)^2 = Th
 *   Sigma dphi/dlambda = L / sin^2 + a E - a P / Delta.
 * (These are the textbook equations of the future-directed photon with
 * constants (-E, L), which is the same curve.)
 *
 * State, 9 components, all regular from the horizon to infinity and through
 * the polar axis:
 *   w = 1/r and dw/dtau: W(w) = w^4 R(1/w) = c4 + c2 w^2 + c1 w^3 + c0 w^4 is a
 *     polynomial (R has no r^3 term), (dw/dtau)^2 = W and
 *     d^2w/dtau^2 = W'(w)/2, smooth through radial turning points, with the
 *     observer at infinity the state w = 0;
 *   n = (sin th cos ps, sin th sin ps, cos th) and dn/dtau: the polar motion
 *     as a unit vector whose azimuth ps carries the L/sin^2 part of phi. With
 *     |dn/dtau|^2 = eta + L^2 + a^2 E^2 u^2 it obeys
 *       d^2n/dtau^2 = -(eta + L^2 + 2 a^2 E^2 n_z^2) n + a^2 E^2 n_z z_hat,
 *     a polynomial force: no 1/sin^2 stiffness at the axis, n_z'' =
 *     Th'(n_z)/2, and (n x n')_z = L is conserved exactly. A ray through the
 *     pole simply passes through n = +-z_hat;
 *   pr, the rest of phi: dpr/dtau = a E - a P/Delta = a w (-2ME + (E Q^2 - aL) w) / D(w),
 *     D = Delta/r^2 = 1 - 2Mw + (a^2+Q^2) w^2, regular outside the horizon.
 * The BL azimuth is phi = atan2(n_y, n_x) + pr, and theta = acos(n_z/|n|).
 * The same state and right-hand side carry a massive, charged particle
 * (particle.h): its R gains an r^3 term (c3), a^2 E^2 becomes a^2 (E^2 - 1)
 * and p1 a charge term; the DP5 below integrates both.
 *
 * Coordinate time. dt/dtau = -(r^2+a^2) P/Delta + a (L + a E sin^2) (the
 * backward ray: t decreases along it) diverges like -E/w^2 - 2ME/w at w = 0,
 * so t itself is not a state component. The component T is regular:
 *   t = T + S - 2M ln w,  S = (dw/dtau) / (E w)  (~ +-r far out),
 * and with dS/dtau = -E/w^2 + (c1 w/2 + c0 w^2)/E on the ray ((dw/dtau)^2 =
 * W), dT/dtau = a (L + aE) - a^2 E n_z^2 - (c1 w/2 + c0 w^2)/E
 *   + (2ME (d1 + d2 w) - (t1 + t3 w^2)) / D + 2M (dw/dtau - E) / w,
 * t1 = a^2 E + a L - E Q^2, t3 = a^3 (aE + L). The last term is written
 *   2M w (c2 + c1 w + c0 w^2) / (E + dw/dtau)   while dw/dtau >= E/2 (inward),
 * regular at w = 0 where the ray comes from infinity, as it stands for
 * dw/dtau <= -E/2 (outward), and in between as the first form plus
 * (1/2 - (dw/dtau)/E) times the difference of the two, 2M ((dw/dtau)^2 -
 * W) / (w (E + dw/dtau)) (0 on the exact ray): continuous however far the
 * state is off its first integral. T enters no error estimate (the
 * steps are those of the other components); where its own estimate says a
 * step did not resolve it (cr_mino_t_unresolved: near-radial rays, whose
 * other components are nearly polynomial, or steps into the horizon's 1/D)
 * its increment is recomputed by quadrature on the dense output
 * (cr_mino_t_quad), which also gives T inside a step.
 * The time is the delay t_obs - t (cr_mino_delay): at a static observer
 * t_obs = 0 (T starts at -S + 2M ln w_0); for the observer at infinity (T
 * starts at 0, E = 1) it is the delay renormalised as
 *   lim_{r_o -> inf} [t_o - t - r_o - 2M ln(r_o / M)]
 * (the divergent terms r_o + 2M ln r_o dropped, as Gralla & Lupsasca 2020
 * and AART, Cardenas-Avendano, Johnson & Lupsasca 2022, do), since near the
 * start S - r -> 0. t diverges at the horizon (1/D; D is clamped beyond the
 * stop): rays that end there report no time. T is light's (c3 = 0,
 * E^2 - W as above); particle.h integrates a particle's t itself.
 *
 * Conserved-quantity monitor (cr_mino_monitor): the larger of
 * |(dw/dtau)^2 - W(w)| and |(dn_z/dtau)^2 - Th(n_z)|, each divided by the sum
 * of the magnitudes of its terms (the polar one also by omega^2, the scale
 * of |dn/dtau|^2): the residuals of the first integrals (dr/dtau)^2 = R and
 * (du/dtau)^2 = Th, scaled to be dimensionless.
 */
#ifndef CR_CORE_MINO_H
#define CR_CORE_MINO_H

#include "geodesic.h"

enum {
    CR_M_W = 0, /* w = 1/r */
    CR_M_DW,    /* dw/dtau */
    CR_M_NX,    /* n */
    CR_M_NY,
    CR_M_NZ,
    CR_M_DNX, /* dn/dtau */
    CR_M_DNY,
    CR_M_DNZ,
    CR_M_PR, /* phi - atan2(n_y, n_x) */
    CR_M_T,  /* t - S + 2M ln w (coordinate time, above) */
    CR_MN
};

/* The components in the step's error estimate: all but T. */
#define CR_M_NERR ((int)CR_M_T)

/* Charts of the azimuth pr (cr_mino.chart). */
enum { CR_CHART_BL = 0, CR_CHART_INGOING = 1 };

/* The lane-generic part (mino_lane.h) for one ray, scalar: cr_mino (the
 * constants of one ray and the coefficients derived from them), cr_mino_W,
 * cr_mino_Th, cr_mino_ingoing_q, cr_mino_rhs, cr_mino_monitor, cr_dp5 (the
 * stages of a step), cr_dp5_try, cr_dp5_factor, cr_dp5_control,
 * cr_mino_project (an accepted step's dw/dtau back on its first integral)
 * and the predicates of the ray's ends and counts. */
#define CR_L double
#define CR_LM int
#define CR_LN(x) x
#define CR_LHD CR_HD
#define CR_LSEL(m, a, b) ((m) ? (a) : (b))
#define CR_LABS(x) fabs(x)
#define CR_LSQRT(x) sqrt(x)
#define CR_LBC(x) (x)
#define CR_LANY(m) (m)
#include "mino_lane.h"
#undef CR_L
#undef CR_LM
#undef CR_LN
#undef CR_LHD
#undef CR_LSEL
#undef CR_LABS
#undef CR_LSQRT
#undef CR_LBC
#undef CR_LANY

/* BL time t at state y (w > 0), relative to the observer's: T + S - 2M ln w
 * (top of this file). */
CR_HD static inline double cr_mino_t(const cr_mino *c, const double *y)
{
    double w = y[CR_M_W];
    return y[CR_M_T] + y[CR_M_DW] / (c->E * w) - 2.0 * c->m * log(w);
}

/* The coordinate-time delay t_obs - t of state y (the emission time before
 * the observer's; renormalised at infinity, top of this file). */
CR_HD static inline double cr_mino_delay(const cr_mino *c, const double *y)
{
    return -cr_mino_t(c, y);
}

/* Start T of a state whose other components are set: t = 0 at a
 * state with w > 0 (a static observer), the renormalised start at w = 0
 * (the observer at infinity). */
CR_HD static inline void cr_mino_t_start(const cr_mino *c, double *y)
{
    double w = y[CR_M_W];
    y[CR_M_T] = w > 0.0 ? -y[CR_M_DW] / (c->E * w) + 2.0 * c->m * log(w) : 0.0;
}

/* Fill the coefficients for constants (E, L, eta) on metric mt; w_stop =
 * 1/(r+ + epsilon) is where rays end at the horizon. */
CR_HD static inline void cr_mino_init(cr_mino *c, const cr_metric *mt, double E, double L,
                                      double eta, double w_stop)
{
    double a = mt->a, M = mt->m, Q2 = mt->q * mt->q;
    double aEL = a * E + L;
    double C = eta + aEL * aEL;
    double om2;
    c->E = E;
    c->L = L;
    c->eta = eta;
    c->a = a;
    c->c4 = E * E;
    c->c3 = 0.0;
    c->c2 = 2.0 * E * a * aEL - C;
    c->c1 = 2.0 * M * C;
    c->c0 = a * a * aEL * aEL - (a * a + Q2) * C;
    c->kap = eta + L * L;
    c->a2E2 = a * a * E * E;
    c->m = M;
    c->tc = a * aEL;
    c->ta = a * a * E;
    c->tg1 = 0.5 * c->c1 / E;
    c->tg2 = c->c0 / E;
    c->td1 = -4.0 * M * M * E - (a * a * E + a * L - E * Q2);
    c->td2 = 2.0 * M * E * (a * a + Q2);
    c->t3 = a * a * a * aEL;
    c->p1 = -2.0 * M * E;
    c->p2 = E * Q2 - a * L;
    c->d1 = -2.0 * M;
    c->d2 = a * a + Q2;
    c->d_min = 1.0 + w_stop * (c->d1 + c->d2 * w_stop);
    om2 = c->kap + c->a2E2;
    c->omega = sqrt(om2 > 0.0 ? om2 : 0.0);
    if (c->omega < 1e-3 * fabs(E))
        c->omega = 1e-3 * fabs(E);
    c->chart = CR_CHART_BL;
    c->K = C;
    c->pa = a * aEL;
}

/* Ingoing chart: d v/dtau of the backward ray at state y (cr_mino_ingoing_q,
 * mino_lane.h, has the derivation). */
CR_HD static inline double cr_mino_ingoing_dv(const cr_mino *c, const double *y)
{
    double w = y[CR_M_W], nz = y[CR_M_NZ];
    double n2 = y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY] + nz * nz;
    double s2 = n2 > 0.0 ? 1.0 - nz * nz / n2 : 0.0;
    return -(1.0 + c->a * c->a * w * w) * cr_mino_ingoing_q(c, y) +
           c->a * (c->L + c->a * c->E * s2);
}

/* BL position of a state: r (INFINITY at w = 0), cos and sin of theta, phi. */
CR_HD static inline void cr_mino_position(const double *y, double *r, double *cth,
                                          double *sth, double *ph)
{
    double nx = y[CR_M_NX], ny = y[CR_M_NY], nz = y[CR_M_NZ];
    double s = sqrt(nx * nx + ny * ny);
    double len = sqrt(s * s + nz * nz);
    *r = 1.0 / y[CR_M_W];
    *cth = nz / len;
    *sth = s / len;
    *ph = atan2(ny, nx) + y[CR_M_PR];
}

/* Cartesian position (2.2.8) of a state with w > 0. */
CR_HD static inline void cr_mino_cart(double a, const double *y, double x[3])
{
    double r, cth, sth, ph, rho;
    cr_mino_position(y, &r, &cth, &sth, &ph);
    rho = sqrt(r * r + a * a);
    x[0] = rho * sth * cos(ph);
    x[1] = rho * sth * sin(ph);
    x[2] = r * cth;
}

/* Polar angle and azimuth in [0, 2pi) of the Cartesian direction of motion
 * of a state (the sky direction of 6.10.3/6.10.4): at w = 0 the ray moves
 * radially and this is the direction of n rotated by pr; at w > 0 it is the
 * direction of d/dtau of the Cartesian position (2.2.8). */
CR_HD static inline void cr_mino_sky_direction(const cr_mino *c, const double *y,
                                               double *sky_th, double *sky_ph)
{
    double v[3], len;
    double w = y[CR_M_W];
    double cp = cos(y[CR_M_PR]), sp = sin(y[CR_M_PR]);
    double nx = cp * y[CR_M_NX] - sp * y[CR_M_NY], ny = sp * y[CR_M_NX] + cp * y[CR_M_NY];
    if (w == 0.0) {
        v[0] = nx;
        v[1] = ny;
        v[2] = y[CR_M_NZ];
    } else {
        /* X = rho(w) Rot(pr) (n_x, n_y), Z = n_z / w with rho = sqrt(1 + a^2 w^2)/w */
        double a2 = c->a * c->a, dw = y[CR_M_DW];
        double rho = sqrt(1.0 + a2 * w * w) / w;
        double drho = -dw / (w * w * sqrt(1.0 + a2 * w * w));
        double dpr, dy[CR_MN];
        double dnx, dny;
        cr_mino_rhs(c, y, dy);
        dpr = dy[CR_M_PR];
        dnx = cp * y[CR_M_DNX] - sp * y[CR_M_DNY] - dpr * ny;
        dny = sp * y[CR_M_DNX] + cp * y[CR_M_DNY] + dpr * nx;
        v[0] = drho * nx + rho * dnx;
        v[1] = drho * ny + rho * dny;
        v[2] = y[CR_M_DNZ] / w - y[CR_M_NZ] * dw / (w * w);
    }
    len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    *sky_th = acos(fmax(-1.0, fmin(1.0, v[2] / len)));
    *sky_ph = atan2(v[1], v[0]);
    if (*sky_ph < 0.0)
        *sky_ph += CR_TWO_PI;
}

/* Mino state and constants of the ray with BL state yb (geodesic.h layout)
 * and constants g, as made by cr_camera_ray. */
CR_HD static inline void cr_mino_from_bl(const cr_geo *g, const double *yb, double w_stop,
                                         cr_mino *c, double *y)
{
    double r = yb[CR_Y_R], th = yb[CR_Y_TH], ph = yb[CR_Y_PH];
    double st = sin(th), ct = cos(th), sp = sin(ph), cp = cos(ph);
    double a = g->mt.a;
    double sigma = r * r + a * a * ct * ct;
    double vth = sigma * yb[CR_Y_UTH];
    double vph = g->L == 0.0 ? 0.0 : g->L / st;
    y[CR_M_W] = 1.0 / r;
    y[CR_M_DW] = -sigma * yb[CR_Y_UR] / (r * r);
    y[CR_M_NX] = st * cp;
    y[CR_M_NY] = st * sp;
    y[CR_M_NZ] = ct;
    y[CR_M_DNX] = vth * ct * cp - vph * sp;
    y[CR_M_DNY] = vth * ct * sp + vph * cp;
    y[CR_M_DNZ] = -vth * st;
    y[CR_M_PR] = 0.0;
    cr_mino_init(c, &g->mt, g->E, g->L, cr_geo_carter(g, yb), w_stop);
    cr_mino_t_start(c, y);
}

/* ---- Dormand-Prince 5(4) ------------------------------------------------ */

/* Dense output of the last step (Dormand & Prince's continuous extension,
 * 4th order): the state at fraction s in [0, 1] of the step y0 -> y1 of size
 * h, exact at both ends. */
CR_HD static inline void cr_dp5_dense(const cr_dp5 *st, const double *y0, const double *y1,
                                      double h, double s, double *ys)
{
    const double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
                 d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
                 d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
    const double (*k)[CR_MN] = st->k;
    double s1 = 1.0 - s;
    int i;
    for (i = 0; i < CR_MN; i++) {
        double dy = y1[i] - y0[i];
        double bs = h * k[0][i] - dy;
        double r4 = dy - h * k[6][i] - bs;
        double r5 = h * (d1 * k[0][i] + d3 * k[2][i] + d4 * k[3][i] + d5 * k[4][i] +
                         d6 * k[5][i] + d7 * k[6][i]);
        ys[i] = y0[i] + s * (dy + s1 * (bs + s * (r4 + s1 * r5)));
    }
}

/* T at fraction s of the last step y0 -> y1 of size h: T(y0) plus the
 * integral of dT/dtau over the dense output (cr_dp5_dense), by 5-point
 * Gauss-Legendre on 2, 4, 8, ... panels until two agree to 1e-13 (1 +
 * |integral|) (at most 64 panels). */
CR_HD static inline double cr_mino_t_quad(const cr_mino *c, const cr_dp5 *st, const double *y0,
                                          const double *y1, double h, double s)
{
    const double x5[3] = {0.0, 0.5384693101056831, 0.9061798459386640};
    const double w5[3] = {0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
    double prev = 0.0, q = 0.0, ys[CR_MN];
    int n, p, k;
    for (n = 2; n <= 64; n *= 2) {
        double ph = s / n;
        q = 0.0;
        for (p = 0; p < n; p++) {
            double mid = (p + 0.5) * ph;
            for (k = 0; k < 5; k++) {
                int j = k < 3 ? k : k - 2;
                double x = k < 3 ? x5[k] : -x5[j];
                cr_dp5_dense(st, y0, y1, h, mid + 0.5 * ph * x, ys);
                q += w5[j] * cr_mino_dT(c, ys);
            }
        }
        q *= 0.5 * ph * h;
        if (n > 2 && fabs(q - prev) <= 1e-13 * (1.0 + fabs(q)))
            break;
        prev = q;
    }
    return y0[CR_M_T] + q;
}

/* A first trial step: a small fraction of the time scale of the angular
 * (1/omega) and radial (1/E) motion; the controller adapts from there. */
CR_HD static inline double cr_mino_first_step(const cr_mino *c, double tol)
{
    double rate = c->omega > fabs(c->E) ? c->omega : fabs(c->E);
    double f = 2.0 * sqrt(sqrt(tol)); /* ~ tol^(1/4) */
    return f / rate;
}

#endif
