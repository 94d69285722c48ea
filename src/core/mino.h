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
 * Coordinate time t (which diverges at w = 0) is not integrated.
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
    CR_MN
};

/* The constants of one ray and the coefficients derived from them. */
typedef struct cr_mino {
    double E, L, eta;      /* geodesic.h convention; eta = Carter constant */
    double a;              /* spin */
    double c4, c2, c1, c0; /* W(w) = c4 + c3 w + c2 w^2 + c1 w^3 + c0 w^4 */
    double c3;             /* 0 for light; the r^3 term of R of a massive or
                              charged particle (particle.h) */
    double kap;            /* eta + L^2 */
    double a2E2;           /* a^2 E^2 */
    double p1, p2;         /* dpr/dtau = a w (p1 + p2 w) / D(w) */
    double d1, d2;         /* D(w) = 1 + d1 w + d2 w^2 = Delta / r^2 */
    double d_min;          /* D at the horizon stop: D is clamped to it beyond
                              the stop, where rays end anyway */
    double omega;          /* sqrt(eta + L^2 + a^2 E^2) >= |dn/dtau|, floored */
    /* The chart of pr (cr_mino_rhs): CR_CHART_BL, or CR_CHART_INGOING, where
     * pr is phi~ - atan2(n_y, n_x) with the ingoing Kerr azimuth
     * phi~ = phi + F(r) (metric.h), regular through the future horizon. */
    int chart;
    double K;  /* eta + (L + a E)^2: R = P^2 - Delta K */
    double pa; /* w^2 P(1/w) = E + pa w^2 */
} cr_mino;

/* Charts of the azimuth pr (cr_mino.chart). */
enum { CR_CHART_BL = 0, CR_CHART_INGOING = 1 };

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

/* W(w) = w^4 R(1/w). */
CR_HD static inline double cr_mino_W(const cr_mino *c, double w)
{
    double w2 = w * w;
    return c->c4 + w * c->c3 + w2 * (c->c2 + w * (c->c1 + w * c->c0));
}

/* Th(u) = (du/dtau)^2 on the ray. */
CR_HD static inline double cr_mino_Th(const cr_mino *c, double u)
{
    double u2 = u * u;
    return c->eta - u2 * (c->kap - c->a2E2 + c->a2E2 * u2);
}

/* Ingoing chart: the rest of d phi~/dtau, and d v/dtau, of the backward ray
 * at state y. With dphi~ = dphi + (a/Delta) dr and dv = dt + ((r^2 + a^2)/Delta) dr,
 * dr/dtau = -(dw/dtau)/w^2, Delta = D/w^2 and Pw = w^2 P = E + pa w^2:
 *   d phi~/dtau - L/sin^2 part = a E - a (Pw + dw)/D,
 *   d v/dtau = -(1 + a^2 w^2) (Pw + dw)/(w^2 D) + a (L + a E sin^2 theta),
 * and on the ray Pw^2 - dw^2 = w^2 D K (from W = Pw^2 - w^2 D K), so
 *   (Pw + dw)/D = w^2 K/(Pw - dw),
 * the form used where |Pw - dw| >= |Pw + dw|: regular at D = 0 for light
 * that crossed the future horizon inward (backward: outward with dw < 0,
 * P > 0). Elsewhere (rays bound for the past boundary, dw -> Pw at D = 0,
 * which ray.h ends before D = 0) the direct form (Pw + dw)/(w^2 D). */
CR_HD static inline double cr_mino_ingoing_q(const cr_mino *c, const double *y)
{
    double w = y[CR_M_W], pw = c->E + c->pa * w * w, dw = y[CR_M_DW];
    double sum = pw + dw, dif = pw - dw;
    /* (Pw + dw) / (w^2 D), in whichever form is better conditioned (equal on
     * the ray): the regular one except where Pw - dw is the smaller (rays
     * bound for the other side, which end before D = 0; K = 0 radial rays,
     * where it is 0/0) */
    if (fabs(dif) >= fabs(sum))
        return c->K / dif;
    return sum / (w * w * (1.0 + w * (c->d1 + c->d2 * w)));
}

CR_HD static inline double cr_mino_ingoing_dv(const cr_mino *c, const double *y)
{
    double w = y[CR_M_W], nz = y[CR_M_NZ];
    double n2 = y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY] + nz * nz;
    double s2 = n2 > 0.0 ? 1.0 - nz * nz / n2 : 0.0;
    return -(1.0 + c->a * c->a * w * w) * cr_mino_ingoing_q(c, y) +
           c->a * (c->L + c->a * c->E * s2);
}

/* Right-hand side dy/dtau. */
CR_HD static inline void cr_mino_rhs(const cr_mino *c, const double *y, double *dy)
{
    double w = y[CR_M_W], nz = y[CR_M_NZ];
    double k = c->kap + 2.0 * c->a2E2 * nz * nz;
    double D = 1.0 + w * (c->d1 + c->d2 * w);
    if (D < c->d_min && c->chart == CR_CHART_BL)
        D = c->d_min;
    dy[CR_M_W] = y[CR_M_DW];
    dy[CR_M_DW] = 0.5 * c->c3 + w * (c->c2 + w * (1.5 * c->c1 + 2.0 * c->c0 * w));
    dy[CR_M_NX] = y[CR_M_DNX];
    dy[CR_M_NY] = y[CR_M_DNY];
    dy[CR_M_NZ] = y[CR_M_DNZ];
    dy[CR_M_DNX] = -k * y[CR_M_NX];
    dy[CR_M_DNY] = -k * y[CR_M_NY];
    dy[CR_M_DNZ] = (c->a2E2 - k) * nz;
    if (c->chart == CR_CHART_INGOING)
        dy[CR_M_PR] = c->a * (c->E - w * w * cr_mino_ingoing_q(c, y));
    else
        dy[CR_M_PR] = c->a * w * (c->p1 + c->p2 * w) / D;
}

/* The conserved-quantity monitor described at the top of this file. */
CR_HD static inline double cr_mino_monitor(const cr_mino *c, const double *y)
{
    double w = y[CR_M_W], w2 = w * w, dw = y[CR_M_DW];
    double u = y[CR_M_NZ], u2 = u * u, du = y[CR_M_DNZ];
    double sr = dw * dw + fabs(c->c4) + fabs(w * c->c3) + w2 * (fabs(c->c2) + fabs(w) * (fabs(c->c1) + fabs(w * c->c0)));
    double st = du * du + c->omega * c->omega + fabs(c->eta) +
                u2 * (fabs(c->kap - c->a2E2) + c->a2E2 * u2);
    double er = sr > 0.0 ? fabs(dw * dw - cr_mino_W(c, w)) / sr : 0.0;
    double et = st > 0.0 ? fabs(du * du - cr_mino_Th(c, u)) / st : 0.0;
    return er > et ? er : et;
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
}

/* ---- Dormand-Prince 5(4) ------------------------------------------------ */

/* Stages of one step: k[0] = f(y0) (first same as last), k[6] = f(y1). */
typedef struct cr_dp5 {
    double k[7][CR_MN];
} cr_dp5;

/* One trial step of size h from y0 with st->k[0] = f(y0): fills the other
 * stages and y1, and returns the error estimate scaled by the tolerance
 * (accept when <= 1; NaN or INFINITY when the step failed). Error scales per
 * component: w relative (floor 1e-3), dw/dtau to E, n absolute, dn/dtau to
 * omega, pr absolute; the largest ratio counts. */
CR_HD static inline double cr_dp5_try(const cr_mino *c, double tol, double h, const double *y0,
                                      cr_dp5 *st, double *y1)
{
    const double a21 = 1.0 / 5.0;
    const double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
    const double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
    const double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                 a54 = -212.0 / 729.0;
    const double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                 a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
    const double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0,
                 b5 = -2187.0 / 6784.0, b6 = 11.0 / 84.0;
    const double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                 e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
    double (*k)[CR_MN] = st->k;
    double t[CR_MN];
    double err = 0.0, sc[CR_MN]; /* 1 / (tol * scale) */
    int i;
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * a21 * k[0][i];
    cr_mino_rhs(c, t, k[1]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a31 * k[0][i] + a32 * k[1][i]);
    cr_mino_rhs(c, t, k[2]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a41 * k[0][i] + a42 * k[1][i] + a43 * k[2][i]);
    cr_mino_rhs(c, t, k[3]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a51 * k[0][i] + a52 * k[1][i] + a53 * k[2][i] + a54 * k[3][i]);
    cr_mino_rhs(c, t, k[4]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a61 * k[0][i] + a62 * k[1][i] + a63 * k[2][i] + a64 * k[3][i] +
                            a65 * k[4][i]);
    cr_mino_rhs(c, t, k[5]);
    for (i = 0; i < CR_MN; i++)
        y1[i] = y0[i] + h * (b1 * k[0][i] + b3 * k[2][i] + b4 * k[3][i] + b5 * k[4][i] +
                             b6 * k[5][i]);
    cr_mino_rhs(c, y1, k[6]);

    {
        /* inverse scales: one division for w, one for dw/dtau */
        double w0 = fabs(y0[CR_M_W]), w1 = fabs(y1[CR_M_W]);
        double d0 = fabs(y0[CR_M_DW]), d1 = fabs(y1[CR_M_DW]);
        double itol = 1.0 / tol;
        double wm = w0 > w1 ? w0 : w1;
        wm = wm > 1e-3 ? wm : 1e-3;
        sc[CR_M_W] = itol / wm;
        sc[CR_M_DW] = itol / (fabs(c->E) + (d0 > d1 ? d0 : d1));
        sc[CR_M_NX] = sc[CR_M_NY] = sc[CR_M_NZ] = itol;
        sc[CR_M_DNX] = sc[CR_M_DNY] = sc[CR_M_DNZ] = itol / c->omega;
        sc[CR_M_PR] = itol;
    }
    for (i = 0; i < CR_MN; i++) {
        double e = h * (e1 * k[0][i] + e3 * k[2][i] + e4 * k[3][i] + e5 * k[4][i] +
                        e6 * k[5][i] + e7 * k[6][i]);
        double r = fabs(e) * sc[i];
        if (!(r <= err)) /* also propagates NaN */
            err = r;
    }
    return err;
}

/* Factor for the next step size after a step with scaled error err:
 * 0.9 err^(-1/4) within [0.2, 5] (the exponent 1/4 rather than 1/5 avoids a
 * pow() per step and errs on the small side). */
CR_HD static inline double cr_dp5_factor(double err)
{
    double fac;
    if (!(err == err))
        return 0.2;
    if (err <= 1.6e-4) /* 0.9 err^(-1/4) >= 5 */
        return 5.0;
    fac = 0.9 / sqrt(sqrt(err));
    return fac < 0.2 ? 0.2 : (fac > 5.0 ? 5.0 : fac);
}

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

/* A first trial step: a small fraction of the time scale of the angular
 * (1/omega) and radial (1/E) motion; the controller adapts from there. */
CR_HD static inline double cr_mino_first_step(const cr_mino *c, double tol)
{
    double rate = c->omega > fabs(c->E) ? c->omega : fabs(c->E);
    double f = 2.0 * sqrt(sqrt(tol)); /* ~ tol^(1/4) */
    return f / rate;
}

#endif
