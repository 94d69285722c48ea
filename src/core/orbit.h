/* curray core: circular equatorial orbits of Kerr-Newman and the
 * Novikov-Thorne / Page-Thorne disc flux (the Keplerian disc's physics).
 *
 * Units and signs: G = c = 1, signature (-+++), BL coordinates, lengths in the
 * unit of the metric (M = mt->m; the renderer uses M = 1). Test particles are
 * uncharged (they follow geodesics; the hole's charge Q enters only through
 * the metric). Only black holes, a^2 + Q^2 <= M^2, are covered.
 *
 * Sense of the orbit: s = +1 for orbits moving toward increasing phi
 * (Omega > 0, counter-clockwise about +z), s = -1 for the opposite sense.
 * Prograde (co-rotating with the hole) is s = sign(a), with s = +1 for a = 0;
 * cr_orbit_sense converts.
 *
 * The orbit's 4-velocity u^mu = u^t (1, 0, 0, Omega) is FUTURE-directed
 * (u^t > 0), and
 *     E = -u_t   (specific energy at infinity, > 0),
 *     L =  u_phi (specific angular momentum about +z, sign s for large r).
 * (For a ray, geodesic.h's E = u_t of the past-directed tangent -k is the
 * same "energy at infinity" convention: both are positive.)
 *
 * Closed forms at theta = pi/2. With D = sqrt(M r - Q^2), W = 2 M r - Q^2,
 *     N = r^2 - 3 M r + 2 Q^2 + 2 s a D          (N > 0: timelike orbit),
 *     Omega = s D / (r^2 + s a D),
 *     u^t   = (r^2 + s a D) / (r sqrt(N)),
 *     E     = (r^2 - 2 M r + Q^2 + s a D) / (r sqrt(N)),
 *     L     = (s D (r^2 + a^2) - a W) / (r sqrt(N)),
 *     E - Omega L = 1 / u^t.
 * Derivation: the Keplerian Omega of any stationary axisymmetric metric,
 * Omega = (-g_tphi,r +- sqrt(g_tphi,r^2 - g_tt,r g_phph,r)) / g_phph,r; at the
 * equator g_tt,r = -2k, g_tphi,r = 2ak, g_phph,r = 2(r - a^2 k) with
 * k = (M r - Q^2)/r^3, giving Omega = s k / (sqrt(k r) + s a k), the form
 * above (no cancellation for either sense); u^t from g(u,u) = -1, then
 * E = -(g_tt + g_tphi Omega) u^t, L = (g_tphi + g_phph Omega) u^t. For Q = 0
 * these are Bardeen, Press & Teukolsky 1972 (2.12)-(2.16) (their upper sign is
 * s a > 0), for a = 0 the Reissner-Nordstrom orbits. Checked symbolically
 * (sympy) when written, and numerically by tests/test_orbit.c.
 *
 * Stability: with
 *     I(r) = M r (r^2 - 6 M r + 9 Q^2 - 3 a^2) - 4 Q^2 (Q^2 - a^2) + 8 s a D^3,
 * dE/dr = I / (2 r^2 N^(3/2)) and dL/dr = (dE/dr) / Omega (exact identities),
 * so the marginally stable orbit r_isco is the root of I(r) = 0 outside the
 * photon orbit (I > 0: stable). Q = 0: r^2 - 6Mr - 3a^2 + 8 s a sqrt(Mr) = 0
 * (BPT 2.21); a = 0: r^3 - 6 M r^2 + 9 Q^2 r - 4 Q^4 / M = 0.
 *
 * Flux (Page & Thorne 1974 eq. 11b, Novikov & Thorne 1973): the energy per
 * unit proper time and unit proper area leaving EACH face of a thin disc with
 * zero torque at r0 (normally r_isco), measured by the orbiting matter,
 *     F(r) = Mdot/(4 pi sqrt(-g)) (-Omega_,r) / (E - Omega L)^2
 *            * Integral_{r0}^{r} (E - Omega L) L_,r dr',
 * with sqrt(-g) = r the equatorial volume element in (t, r, z, phi) (the same
 * for Kerr-Newman as for Kerr: det g = -Sigma^2 sin^2 theta). With the
 * identities above the integrand is s I / (2 r D N) and
 *     -Omega_,r / (E - Omega L)^2 = s (3 M r - 4 Q^2) / (2 r D N),
 * so
 *     F(r) / Mdot = (3 M r - 4 Q^2) / (16 pi r^2 D N) * J(r),
 *     J(r) = Integral_{r0}^{r} I(r') / (r' D(r') N(r')) dr'.
 * F/Mdot is in units of 1/length^2: with lengths in M, F is in units of
 * Mdot/M^2 (c = G = 1). In SI, F = (F/Mdot in M^-2) * Mdot c^6 / (G^2 M^2),
 * and the local effective temperature is sigma_SB T^4 = F.
 * Newtonian limit: F -> 3 M Mdot / (8 pi r^3) (1 - sqrt(r0/r)).
 */
#ifndef CR_CORE_ORBIT_H
#define CR_CORE_ORBIT_H

#include "metric.h"

/* Orbit sense s (+1: Omega > 0) of a prograde (prograde != 0) or retrograde
 * orbit about a hole of spin a; for a = 0 "prograde" is s = +1. */
CR_HD static inline int cr_orbit_sense(const cr_metric *mt, int prograde)
{
    int sp = mt->a < 0.0 ? -1 : 1;
    return prograde ? sp : -sp;
}

/* One circular orbit at BL radius r, theta = pi/2 (see the closed forms
 * above). omega = dphi/dt, ut = u^t > 0, E = -u_t, L = u_phi. */
typedef struct cr_orbit {
    double omega, ut, E, L;
} cr_orbit;

/* D = sqrt(M r - Q^2) and N = r^2 - 3 M r + 2 Q^2 + 2 s a D at r. Returns 0
 * where M r <= Q^2 (D undefined), 1 otherwise. */
CR_HD static inline int cr_orbit_dn_(const cr_metric *mt, int s, double r, double *D,
                                     double *N)
{
    double d2 = mt->m * r - mt->q * mt->q;
    *D = *N = NAN;
    if (!(d2 > 0.0))
        return 0;
    *D = sqrt(d2);
    *N = r * r - 3.0 * mt->m * r + 2.0 * mt->q * mt->q + 2.0 * s * mt->a * *D;
    return 1;
}

/* The circular orbit of sense s at r. Returns 1 and fills *o when a timelike
 * circular geodesic exists there (r outside the outer horizon and outside
 * the photon orbit of that sense: N > 0), else 0 (*o all NaN). Stable
 * or not: compare r with cr_orbit_r_isco. */
CR_HD static inline int cr_orbit_eval(const cr_metric *mt, int s, double r, cr_orbit *o)
{
    double D, N, sqN, rs, den, a = mt->a, M = mt->m, Q2 = mt->q * mt->q;
    double rp = cr_metric_r_plus(mt);
    o->omega = o->ut = o->E = o->L = NAN;
    if (!(r > rp) || !cr_isfinite(r) || !cr_orbit_dn_(mt, s, r, &D, &N) || !(N > 0.0))
        return 0;
    sqN = sqrt(N);
    rs = r * r + s * a * D;
    den = 1.0 / (r * sqN);
    o->omega = s * D / rs;
    o->ut = rs * den;
    o->E = (r * r - 2.0 * M * r + Q2 + s * a * D) * den;
    o->L = (s * D * (r * r + a * a) - a * (2.0 * M * r - Q2)) * den;
    return 1;
}

/* Contravariant 4-velocity u^mu = u^t (1, 0, 0, Omega) of an orbit. */
CR_HD static inline void cr_orbit_velocity(const cr_orbit *o, double u[4])
{
    u[0] = o->ut;
    u[1] = 0.0;
    u[2] = 0.0;
    u[3] = o->ut * o->omega;
}

/* I(r) of the header comment: dE/dr = I / (2 r^2 N^(3/2)); I > 0 where the
 * circular orbit is stable. NaN where M r <= Q^2. */
CR_HD static inline double cr_orbit_stability(const cr_metric *mt, int s, double r)
{
    double D, N, M = mt->m, a = mt->a, Q2 = mt->q * mt->q;
    if (!cr_orbit_dn_(mt, s, r, &D, &N))
        return NAN;
    return M * r * (r * r - 6.0 * M * r + 9.0 * Q2 - 3.0 * a * a) - 4.0 * Q2 * (Q2 - a * a) +
           8.0 * s * a * D * D * D;
}

/* dE/dr, dL/dr and dOmega/dr of the orbit of sense s at r (NaN where no
 * timelike orbit exists). dOmega/dr = -s r (3 M r - 4 Q^2) / (2 D (r^2 + s a D)^2). */
CR_HD static inline void cr_orbit_derivs(const cr_metric *mt, int s, double r, double *dE,
                                         double *dL, double *dOmega)
{
    double D, N, rs;
    if (!cr_orbit_dn_(mt, s, r, &D, &N) || !(N > 0.0)) {
        *dE = *dL = *dOmega = NAN;
        return;
    }
    rs = r * r + s * mt->a * D;
    *dE = cr_orbit_stability(mt, s, r) / (2.0 * r * r * N * sqrt(N));
    *dL = *dE * rs / (s * D);
    *dOmega = -s * r * (3.0 * mt->m * r - 4.0 * mt->q * mt->q) / (2.0 * D * rs * rs);
}

/* Fixed iteration count of the bisections below: 200 halvings of a bracket
 * of a few M reach the spacing of doubles long before the end (then the
 * midpoint stops moving), so the result is the root to machine precision
 * wherever the function has a simple sign change. */
#define CR_ORBIT_BISECT_ITERS 200

/* Radius of the circular photon orbit of sense s: the outermost root of
 * N(r) = 0, found by bisection on [r+, 5 M] (N(r+) <= 0 for a black hole,
 * N(5M) >= 10 - 2 sqrt(5) > 0). Circular timelike orbits exist for
 * r > r_photon. Returns the upper end of the final bracket (N > 0 there);
 * r+ when N(r+) >= 0 (extremal co-rotating limit); NaN without a horizon. */
CR_HD static inline double cr_orbit_r_photon(const cr_metric *mt, int s)
{
    double lo = cr_metric_r_plus(mt), hi = 5.0 * mt->m, D, N;
    int i;
    if (!cr_isfinite(lo))
        return NAN;
    if (!cr_orbit_dn_(mt, s, lo, &D, &N) || N >= 0.0)
        return lo;
    for (i = 0; i < CR_ORBIT_BISECT_ITERS; i++) {
        double mid = 0.5 * (lo + hi);
        if (!cr_orbit_dn_(mt, s, mid, &D, &N) || !(N > 0.0))
            lo = mid;
        else
            hi = mid;
    }
    return hi;
}

/* Radius of the innermost stable circular orbit (marginally stable orbit)
 * of sense s: the root of I(r) = 0 (equivalently dE/dr = dL/dr = 0) by
 * bisection on [r_photon, 10 M]; I < 0 (unstable) just outside the photon
 * orbit and I(10 M) > 0 for every black hole (r_isco <= 9 M, reached by the
 * retrograde orbit of a = M, Q = 0). Returns r_photon when I >= 0 there (the
 * extremal co-rotating limit, r_isco = r_photon = r+); NaN without a horizon.
 * Kerr: Bardeen, Press & Teukolsky (2.21); see tests/test_orbit.c. */
CR_HD static inline double cr_orbit_r_isco(const cr_metric *mt, int s)
{
    double lo = cr_orbit_r_photon(mt, s), hi = 10.0 * mt->m;
    int i;
    if (!cr_isfinite(lo))
        return NAN;
    if (cr_orbit_stability(mt, s, lo) >= 0.0)
        return lo;
    for (i = 0; i < CR_ORBIT_BISECT_ITERS; i++) {
        double mid = 0.5 * (lo + hi);
        if (cr_orbit_stability(mt, s, mid) < 0.0)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Radius of the marginally bound orbit (E = 1) of sense s, by bisection on
 * [r_photon, 6 M] (E -> infinity at r_photon, E < 1 for r > r_mb, and
 * r_mb <= 3 + 2 sqrt(2) M < 6 M). Kerr: r_mb = 2M - s a + 2 sqrt(M (M - s a)).
 * NaN without a horizon. */
CR_HD static inline double cr_orbit_r_mb(const cr_metric *mt, int s)
{
    double lo = cr_orbit_r_photon(mt, s), hi = 6.0 * mt->m;
    int i;
    cr_orbit o;
    if (!cr_isfinite(lo))
        return NAN;
    for (i = 0; i < CR_ORBIT_BISECT_ITERS; i++) {
        double mid = 0.5 * (lo + hi);
        if (!cr_orbit_eval(mt, s, mid, &o) || o.E > 1.0)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* ---- plunging matter inside the ISCO ------------------------------------- */

/* 4-velocity u^mu of matter falling freely in the equatorial plane from the
 * ISCO with the ISCO orbit's constants E = -u_t and L = u_phi (cr_orbit_eval
 * at r_isco), at BL radius r (r+ < r <= r_isco). From the
 * geodesic equations: E and L are conserved (stationary, axisymmetric), so
 * with the inverse of the (t, phi) block at the equator (determinant
 * -Delta),
 *     u^t   = (g_phph E + g_tphi L) / Delta,
 *     u^phi = -(g_tphi E + g_tt L) / Delta,
 * and the radial component follows from g(u, u) = -1:
 *     g_rr (u^r)^2 = -1 + E u^t - L u^phi,
 * taken inward (u^r <= 0) and clamped at 0, which it equals at r_isco (the
 * circular orbit there; just inside, (u^r)^2 grows as (r_isco - r)^3).
 * Returns 1 and fills u (future-directed: u^t > 0) for r+ < r; 0 (u
 * untouched) at or inside the horizon or where a value is not finite. */
CR_HD static inline int cr_orbit_plunge_velocity(const cr_metric *mt, double E, double L,
                                                 double r, double u[4])
{
    cr_metric_point q;
    double ut, uph, ur2;
    if (!(r > cr_metric_r_plus(mt)))
        return 0;
    cr_metric_eval(mt, r, 0.5 * CR_PI, &q);
    ut = (q.g_phph * E + q.g_tph * L) / q.delta;
    uph = -(q.g_tph * E + q.g_tt * L) / q.delta;
    ur2 = (-1.0 + E * ut - L * uph) / q.g_rr;
    if (!cr_isfinite(ut) || !cr_isfinite(uph) || !cr_isfinite(ur2) || !(ut > 0.0))
        return 0;
    u[0] = ut;
    u[1] = ur2 > 0.0 ? -sqrt(ur2) : 0.0;
    u[2] = 0.0;
    u[3] = uph;
    return 1;
}

/* ---- quadrature ---------------------------------------------------------- */

/* Node i (0..7) and weight of the 8-point Gauss-Legendre rule on [-1, 1]
 * (exact for polynomials of degree <= 15). Kept in a function, not a global
 * table, so device code can use it. */
CR_HD static inline void cr_quad_gl8(int i, double *x, double *w)
{
    const double xs[4] = {0.18343464249564980494, 0.52553240991632898582,
                          0.79666647741362673959, 0.96028985649753623168};
    const double ws[4] = {0.36268378337836198297, 0.31370664587788728734,
                          0.22238103445337447054, 0.10122853629037625915};
    int k = i < 4 ? 3 - i : i - 4;
    *x = i < 4 ? -xs[k] : xs[k];
    *w = ws[k];
}

/* ---- Novikov-Thorne / Page-Thorne flux ------------------------------------ */

/* The flux integral J (header comment) is done in the variable
 * t = ln(r - r_c), r_c = r_photon - 0.01 M: its integrand I/(r D N) has its
 * nearest singularity at the photon orbit (N = 0), which this variable moves
 * to a fixed distance, so the same spacing in t serves a = 0 and a -> M
 * (and the 0.01 M offset keeps t finite when r0 = r_photon at a = M). */
#define CR_FLUX_RC_OFFSET 0.01

/* dJ/dt = (r - r_c) I / (r D N) at r. */
CR_HD static inline double cr_flux_dJ_dt_(const cr_metric *mt, int s, double rc, double r)
{
    double D, N;
    if (!cr_orbit_dn_(mt, s, r, &D, &N))
        return NAN;
    return (r - rc) * cr_orbit_stability(mt, s, r) / (r * D * N);
}

/* J over [ra, rb] (ra, rb > rc) by the 8-point Gauss-Legendre rule on n equal
 * pieces in t = ln(r - rc). */
CR_HD static inline double cr_flux_J_(const cr_metric *mt, int s, double rc, double ra,
                                      double rb, int n)
{
    double ta = log(ra - rc), tb = log(rb - rc), h = (tb - ta) / n, sum = 0.0;
    int k, i;
    for (k = 0; k < n; k++) {
        double mid = ta + (k + 0.5) * h;
        for (i = 0; i < 8; i++) {
            double x, w;
            cr_quad_gl8(i, &x, &w);
            sum += w * cr_flux_dJ_dt_(mt, s, rc, rc + exp(mid + 0.5 * h * x));
        }
    }
    return 0.5 * h * sum;
}

/* The factor (3 M r - 4 Q^2) / (16 pi r^2 D N) with F / Mdot = factor * J. */
CR_HD static inline double cr_flux_factor_(const cr_metric *mt, int s, double r)
{
    double D, N;
    if (!cr_orbit_dn_(mt, s, r, &D, &N))
        return NAN;
    return (3.0 * mt->m * r - 4.0 * mt->q * mt->q) / (16.0 * CR_PI * r * r * D * N);
}

/* Largest piece of the direct quadrature in t (the GL8 error is then below
 * 1e-14 relative for every black hole; tests/test_orbit.c halves it). */
#define CR_FLUX_DT 0.02

/* F(r) / Mdot of the disc of sense s with zero torque at r0 (r0 >= r_isco),
 * evaluated directly: in units of 1/length^2 (Mdot/M^2 for M = 1), per face.
 * 0 for r <= r0. Host use (a few thousand metric evaluations a call): the
 * renderer reads the table below instead. */
CR_HD static inline double cr_orbit_flux(const cr_metric *mt, int s, double r0, double r)
{
    double rc = cr_orbit_r_photon(mt, s) - CR_FLUX_RC_OFFSET * mt->m;
    double span;
    int n;
    if (!(r > r0))
        return 0.0;
    span = log((r - rc) / (r0 - rc));
    n = (int)ceil(span / CR_FLUX_DT);
    if (n < 1)
        n = 1;
    return cr_flux_factor_(mt, s, r) * cr_flux_J_(mt, s, rc, r0, r, n);
}

/* Number of nodes of the flux table. The table is plain data meant to travel
 * in the frame (the CUDA kernel receives cr_frame by value, 4 KiB of kernel
 * parameters before CUDA 12.1), hence fixed and small: 2 x 128 doubles. Cubic
 * Hermite interpolation in t with exact node derivatives keeps the error of
 * F below 1e-5 of its peak (so below 3e-6 in T) for a up to 0.9999 and
 * r_out/r0 up to 10^4; it is worst in the first interval at the ISCO of a
 * near-extremal hole (tests/test_orbit.c measures it; 64 nodes give 8e-5). */
/* CR_FLUX_TABLE_N (128) is defined in defs.h. */

/* The disc's flux, computed once per frame on the host by cr_flux_table_fill
 * and read per ray by cr_flux_table_F. Why a CR_HD header and not a .c file:
 * the integrand, the table and its interpolation are one formula used on
 * both sides (fill on the host, read on the device); keeping them in one
 * core header writes it once (DESIGN rule 1), and the fill needs no
 * allocation or I/O, so it obeys the core rules. */
/* typedef struct cr_flux_table (defs.h, so that it travels in cr_frame):
 *   cr_metric mt; int sense;   s
 *   double r0, r_out;          zero-torque (inner) radius, outer radius
 *   double rc;                 r_photon - 0.01 M: t = ln(r - rc)
 *   double t0, dt;             node k at t0 + k dt, k = 0..CR_FLUX_TABLE_N-1
 *   double J[], dJdt[];        J and the exact dJ/dt at the nodes
 *   double r_peak, F_max;      where F / Mdot is largest on [r0, r_out], and
 *                              that value */

/* Golden-section iterations of the peak search (flat maximum: the radius
 * settles to ~1e-8 relative, the value to machine precision). */
#define CR_FLUX_PEAK_ITERS 100

/* Smallest r0 - r_photon the table accepts, in M. The ISCO approaches the
 * photon orbit as |a| -> M (0.163 M at a = 0.998, 0.062 M at 0.9999) and the
 * flux then piles up within a sliver above it that 128 nodes do not resolve
 * (a = M: the peak lies 0.0012 M above r_isco = M). The gap falls below
 * 0.02 M only for |a| > 0.99999 M or so; such a hole gets no table (round the
 * spin to 0.9999, or Thorne's limit 0.998). */
#define CR_FLUX_MIN_GAP 0.02

/* Fill the table for the disc of sense s between r0 and r_out. r0 must lie
 * at or outside the ISCO of that sense (the zero-torque inner edge; normally
 * r0 = cr_orbit_r_isco): returns 0, leaving *tab undefined, when
 * r0 < r_isco (1 - 1e-12), r0 - r_photon < CR_FLUX_MIN_GAP M, r_out <= r0,
 * or a value is not finite; 1 on success. */
CR_HD static inline int cr_flux_table_fill(cr_flux_table *tab, const cr_metric *mt, int s,
                                           double r0, double r_out)
{
    double risco = cr_orbit_r_isco(mt, s);
    cr_golden gs;
    int k, i, m;
    if (!cr_isfinite(risco) || !(r0 >= risco * (1.0 - 1e-12)) || !(r_out > r0) ||
        !cr_isfinite(r_out) || !(r0 - cr_orbit_r_photon(mt, s) >= CR_FLUX_MIN_GAP * mt->m))
        return 0;
    tab->mt = *mt;
    tab->sense = s;
    tab->r0 = r0;
    tab->r_out = r_out;
    tab->rc = cr_orbit_r_photon(mt, s) - CR_FLUX_RC_OFFSET * mt->m;
    tab->t0 = log(r0 - tab->rc);
    tab->dt = (log(r_out - tab->rc) - tab->t0) / (CR_FLUX_TABLE_N - 1);
    m = (int)ceil(tab->dt / CR_FLUX_DT);
    if (m < 1)
        m = 1;
    tab->J[0] = 0.0;
    for (k = 0; k < CR_FLUX_TABLE_N; k++) {
        double r = tab->rc + exp(tab->t0 + k * tab->dt);
        if (k == CR_FLUX_TABLE_N - 1)
            r = r_out;
        /* at the ISCO, I = 0: exactly 0 (also where N = 0 there, a = M) */
        tab->dJdt[k] = (k == 0 && r0 <= risco) ? 0.0 : cr_flux_dJ_dt_(mt, s, tab->rc, r);
        if (k > 0) {
            double rprev = tab->rc + exp(tab->t0 + (k - 1) * tab->dt);
            if (k == 1)
                rprev = r0;
            tab->J[k] = tab->J[k - 1] + cr_flux_J_(mt, s, tab->rc, rprev, r, m);
        }
        if (!cr_isfinite(tab->J[k]) || !cr_isfinite(tab->dJdt[k]))
            return 0;
    }
    /* the peak of F by golden section (defs.h) on the directly integrated
     * F, as the smallest value of -F */
    cr_golden_start(&gs, r0, r_out);
    gs.f1 = -cr_orbit_flux(mt, s, r0, gs.x1);
    gs.f2 = -cr_orbit_flux(mt, s, r0, gs.x2);
    for (i = 0; i < CR_FLUX_PEAK_ITERS; i++) {
        if (cr_golden_shrink(&gs) == 1)
            gs.f1 = -cr_orbit_flux(mt, s, r0, gs.x1);
        else
            gs.f2 = -cr_orbit_flux(mt, s, r0, gs.x2);
    }
    tab->r_peak = gs.f1 < gs.f2 ? gs.x1 : gs.x2;
    tab->F_max = -(gs.f1 < gs.f2 ? gs.f1 : gs.f2);
    {
        double fe = cr_orbit_flux(mt, s, r0, r_out);
        if (fe > tab->F_max) {
            tab->r_peak = r_out;
            tab->F_max = fe;
        }
    }
    return cr_isfinite(tab->F_max) && tab->F_max > 0.0;
}

/* F(r) / Mdot from the table (cubic Hermite in t), in units of
 * 1/length^2, per face; 0 outside [r0, r_out] (no emission inside the zero-
 * torque radius: plunging matter, or nothing; none beyond the disc). */
CR_HD static inline double cr_flux_table_F(const cr_flux_table *tab, double r)
{
    double t, u, h00, h10, h01, h11, J;
    int k;
    if (!(r > tab->r0) || !(r <= tab->r_out))
        return 0.0;
    t = (log(r - tab->rc) - tab->t0) / tab->dt;
    k = (int)floor(t);
    if (k < 0)
        k = 0;
    if (k > CR_FLUX_TABLE_N - 2)
        k = CR_FLUX_TABLE_N - 2;
    u = t - k;
    h00 = (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u);
    h10 = u * (1.0 - u) * (1.0 - u);
    h01 = u * u * (3.0 - 2.0 * u);
    h11 = u * u * (u - 1.0);
    J = h00 * tab->J[k] + h01 * tab->J[k + 1] +
        tab->dt * (h10 * tab->dJdt[k] + h11 * tab->dJdt[k + 1]);
    return cr_flux_factor_(&tab->mt, tab->sense, r) * J;
}

/* Local effective temperature T = t_scale * F^(1/4) (sigma_SB T^4 = F). Two
 * normalisations of t_scale:
 *  - by the peak temperature: t_scale = T_peak / F_max^(1/4)
 *    (cr_flux_tscale_peak), so T(r_peak) = T_peak in the unit of T_peak;
 *  - physical (cr_flux_tscale_si): M in kg, Mdot in kg/s, F / Mdot from the
 *    table for M = 1 (units M^-2): sigma T^4 = (F/Mdot) Mdot c^6 / (G^2 M^2),
 *    T in kelvin. */
CR_HD static inline double cr_flux_tscale_peak(const cr_flux_table *tab, double T_peak)
{
    return T_peak / sqrt(sqrt(tab->F_max));
}

#define CR_SI_G 6.67430e-11          /* m^3 kg^-1 s^-2 (CODATA 2018) */
#define CR_SI_C 299792458.0          /* m/s */
#define CR_SI_SIGMA_SB 5.670374419e-8 /* W m^-2 K^-4 */
#define CR_SI_M_SUN 1.98847e30       /* kg (IAU 2015 nominal GM_sun / G) */
#define CR_SI_M_P 1.67262192369e-27  /* kg, proton mass */
#define CR_SI_SIGMA_T 6.6524587321e-29 /* m^2, Thomson cross section */

CR_HD static inline double cr_flux_tscale_si(double M_kg, double Mdot_kg_s)
{
    double c2 = CR_SI_C * CR_SI_C;
    double gm = CR_SI_G * M_kg;
    return sqrt(sqrt(Mdot_kg_s * c2 * c2 * c2 / (gm * gm * CR_SI_SIGMA_SB)));
}

/* Eddington accretion rate in kg/s of a hole of mass M_kg whose disc
 * converts a fraction eta of the rest mass to radiation:
 * Mdot_Edd = L_Edd / (eta c^2), L_Edd = 4 pi G M m_p c / sigma_T. For the thin
 * disc eta = 1 - E(r0) (cr_orbit_eval at r0 = r_isco). */
CR_HD static inline double cr_flux_mdot_edd_si(double M_kg, double eta)
{
    return 4.0 * CR_PI * CR_SI_G * M_kg * CR_SI_M_P / (CR_SI_SIGMA_T * CR_SI_C * eta);
}

#endif
