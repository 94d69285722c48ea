/* curray core: the Kerr-Newman metric in Boyer-Lindquist coordinates.
 *
 * (2.2.1)-(2.2.3): Sigma = r^2 + a^2 cos^2(theta), Delta = r^2 + a^2 + Q^2 - 2Mr,
 *   g_tt   = -(Delta - a^2 sin^2)/Sigma
 *   g_tphi = -a sin^2 (r^2 + a^2 - Delta)/Sigma = -a sin^2 (2Mr - Q^2)/Sigma
 *   g_phph = ((r^2 + a^2)^2 - Delta a^2 sin^2) sin^2 / Sigma
 *   g_rr   = Sigma/Delta,  g_thth = Sigma.
 * Identity used throughout: g_tt g_phph - g_tphi^2 = -Delta sin^2(theta).
 */
#ifndef CR_CORE_METRIC_H
#define CR_CORE_METRIC_H

#include "defs.h"

/* Metric components and the shared subexpressions at one point (r, theta).
 * A_ = (r^2 + a^2)^2 - Delta a^2 sin^2 and W_ = 2Mr - Q^2 are kept because the
 * right-hand side needs them. */
typedef struct cr_metric_point {
    double sin_th, cos_th, sin2, cos2;
    double sigma, delta, A_, W_;
    double g_tt, g_tph, g_phph, g_rr, g_thth;
} cr_metric_point;

CR_HD static inline void cr_metric_eval(const cr_metric *mt, double r, double th,
                                        cr_metric_point *p)
{
    double a2 = mt->a * mt->a;
    double r2a2 = r * r + a2;
    p->sin_th = sin(th);
    p->cos_th = cos(th);
    p->sin2 = p->sin_th * p->sin_th;
    p->cos2 = p->cos_th * p->cos_th;
    p->sigma = r * r + a2 * p->cos2;
    p->W_ = 2.0 * mt->m * r - mt->q * mt->q;
    p->delta = r2a2 - p->W_;
    p->A_ = r2a2 * r2a2 - p->delta * a2 * p->sin2;
    p->g_tt = -(p->delta - a2 * p->sin2) / p->sigma;
    p->g_tph = -mt->a * p->sin2 * p->W_ / p->sigma;
    p->g_phph = p->A_ * p->sin2 / p->sigma;
    p->g_rr = p->sigma / p->delta;
    p->g_thth = p->sigma;
}

/* Outer horizon r+ (2.2.5). Returns NaN when no horizon exists. */
CR_HD static inline double cr_metric_r_plus(const cr_metric *mt)
{
    double d = mt->m * mt->m - mt->a * mt->a - mt->q * mt->q;
    if (d < 0.0)
        return NAN;
    return mt->m + sqrt(d);
}

/* Inner horizon r- = M - sqrt(M^2 - a^2 - Q^2) (0 for Schwarzschild). Returns
 * NaN when no horizon exists. */
CR_HD static inline double cr_metric_r_minus(const cr_metric *mt)
{
    double d = mt->m * mt->m - mt->a * mt->a - mt->q * mt->q;
    if (d < 0.0)
        return NAN;
    return mt->m - sqrt(d);
}

/* Ingoing Kerr coordinates (v, r, theta, phi~) from Boyer-Lindquist ones:
 *   v = t + G(r),  phi~ = phi + F(r),  dG/dr = (r^2 + a^2)/Delta, dF/dr = a/Delta,
 * with the integration constants fixed by
 *   F(r) = a/(r+ - r-) ln|(r - r+)/(r - r-)|,
 *   G(r) = r + (r+^2 + a^2)/(r+ - r-) ln|r - r+| - (r-^2 + a^2)/(r+ - r-) ln|r - r-|
 * (partial fractions of 1/Delta = 1/((r - r+)(r - r-)), r+^2 + a^2 = 2 M r+ - Q^2).
 * The same formulas relate the BL chart inside the horizon (r- < r < r+,
 * where t and phi are another patch) to the ingoing one, which covers both
 * and is regular at r+. Needs r+ > r- (not extremal) and r != r+-; the r-
 * term is dropped when r- = 0 (its coefficient (r-^2 + a^2) is then 0). */
CR_HD static inline void cr_metric_ingoing_shift(const cr_metric *mt, double r, double *F,
                                                 double *G)
{
    double rp = cr_metric_r_plus(mt), rm = cr_metric_r_minus(mt), a2 = mt->a * mt->a;
    double k = 1.0 / (rp - rm);
    double lp = log(fabs(r - rp)), lm = rm != 0.0 ? log(fabs(r - rm)) : 0.0;
    if (F)
        *F = mt->a * k * (lp - lm);
    if (G)
        *G = r + k * ((rp * rp + a2) * lp - (rm * rm + a2) * lm);
}

/* Outer static limit r_E+ (2.2.6) at polar angle th. */
CR_HD static inline double cr_metric_r_ergo(const cr_metric *mt, double th)
{
    double c = cos(th);
    double d = mt->m * mt->m - mt->q * mt->q - mt->a * mt->a * c * c;
    return mt->m + sqrt(d > 0.0 ? d : 0.0);
}

/* -g_tt, positive exactly where a static observer can exist (outside the
 * ergosurface). */
CR_HD static inline double cr_metric_minus_gtt(const cr_metric *mt, double r, double th)
{
    cr_metric_point p;
    cr_metric_eval(mt, r, th, &p);
    return -p.g_tt;
}

/* The twelve non-zero Christoffel symbols Gamma^r and Gamma^theta,
 * (B.9)-(B.20). Off-diagonal ones are stored once; the geodesic equations
 * (2.3.10)/(2.3.11) carry their factor 2. */
typedef struct cr_christoffel {
    double r_tt, r_rr, r_thth, r_phph, r_tph, r_rth;
    double th_tt, th_rr, th_thth, th_phph, th_tph, th_rth;
} cr_christoffel;

CR_HD static inline void cr_christoffel_eval(const cr_metric *mt, double r,
                                             const cr_metric_point *p,
                                             cr_christoffel *G)
{
    double M = mt->m, a = mt->a, a2 = a * a, Q2 = mt->q * mt->q;
    double sig = p->sigma, del = p->delta;
    double isig = 1.0 / sig;
    double isig3 = isig * isig * isig;
    double sc = p->sin_th * p->cos_th;
    double r2a2 = r * r + a2;
    double ds3 = del * isig3;
    double k = M * r * r - Q2 * r - M * a2 * p->cos2; /* (B.9), (B.13) */

    G->r_tt = ds3 * k;
    G->r_rr = (-M * r * r + Q2 * r + a2 * r + (M - r) * a2 * p->cos2) / (del * sig);
    G->r_thth = -del * isig * r;
    G->r_phph = ds3 * p->sin2 *
                (sig * ((r - M) * a2 * p->sin2 - 2.0 * r * r2a2) + r * p->A_);
    G->r_tph = -ds3 * a * p->sin2 * k;
    G->r_rth = -isig * a2 * sc;

    G->th_tt = -isig3 * a2 * sc * p->W_;
    G->th_rr = isig * a2 * sc / del;
    G->th_thth = -isig * a2 * sc;
    G->th_phph = isig3 * sc *
                 (r2a2 * (del * a2 * p->sin2 - r2a2 * r2a2) + sig * del * a2 * p->sin2);
    G->th_tph = isig3 * a * sc * p->W_ * r2a2;
    G->th_rth = isig * r;
}

#endif
