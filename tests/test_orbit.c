/* Circular equatorial orbits, the general frequency ratio and the
 * Novikov-Thorne flux (src/core/orbit.h, src/core/shift.h).
 *
 * Known answers and tolerances (each test prints what it measured):
 * - Gauss-Legendre 8: exact for x^k, k <= 15, to 1e-15; the flux quadrature
 *   changes by < 1e-13 (relative) when its pieces are halved.
 * - Kerr (Bardeen, Press & Teukolsky 1972): r_isco (2.21) closed form, r_photon,
 *   r_mb, Omega, E, L (2.12)-(2.16) to 1e-12 relative; r_isco = 6 M (a = 0),
 *   1.2370 M (a = 0.998, prograde; +-5e-5, the published 4 decimals),
 *   9 M (a = 1, retrograde), 1 M (a = 1 prograde, to 1e-6: a double root).
 * - Reissner-Nordstrom r_isco: largest root of r^3 - 6 M r^2 + 9 Q^2 r
 *   - 4 Q^4/M (Newton in the test) to 1e-12; 4 M for Q = M.
 * - Kerr-Newman: g(u,u) = -1 to 1e-13, the radial geodesic equation with
 *   metric.h's Christoffel symbols to 1e-12 (relative to its largest term),
 *   E = -u_t and L = u_phi of the lowered u to 1e-12, dE/dr, dL/dr, dOmega/dr
 *   against central differences to 1e-6, dE/dr = dL/dr = 0 at r_isco.
 * - cr_shift_ratio with both ends static, and the frame's cr_redshift_static
 *   (the same ratio), equal the closed form sqrt(-g_tt)|e / sqrt(-g_tt)|o at
 *   random points outside the ergosurface and random null photons, to 1e-12.
 * - Plunging matter inside the ISCO (test_plunge): normalised, E and L of
 *   the ISCO conserved, the radial geodesic equation, continuous with the
 *   circular orbit at r_isco.
 * - Face-on Schwarzschild ring seen from infinity: g = sqrt(1 - 3M/r) to 1e-13
 *   (Kerr: 1/u^t of BPT).
 * - Edge-on Schwarzschild ring: max and min over photons of g =
 *   sqrt(1 - 3M/r) / (1 -+ sqrt(M / (r - 2M))) to 1e-13.
 * - Flux for Kerr against Page & Thorne's closed form to 1e-10 relative to
 *   its peak; peak radius to 1e-6 M and value to 1e-10; F(r_isco) = 0.
 * - The flux table against direct quadrature: |dF| < 1e-5 F_max.
 * - Energy conservation (Page & Thorne eq. 13 integrated): the luminosity at
 *   infinity of both faces, Integral 4 pi r F E dr = Mdot (1 - E(r_isco)),
 *   for Kerr-Newman, to 1e-8.
 * - SI temperature at 1e7 M against the Newtonian thin disc to 2e-4.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "core/orbit.h"
#include "core/shift.h"
#include "testutil.h"

static cr_metric mk(double a, double q)
{
    cr_metric mt;
    mt.m = 1.0;
    mt.a = a;
    mt.q = q;
    return mt;
}

static double rel(double x, double ref)
{
    return fabs(x - ref) / fmax(fabs(ref), 1e-300);
}

/* ---- Kerr references (BPT 1972, M = 1, spin a >= 0, upper sign prograde) -- */

static double bpt_isco(double a, int pro)
{
    double z1 = 1.0 + cbrt(1.0 - a * a) * (cbrt(1.0 + a) + cbrt(1.0 - a));
    double z2 = sqrt(3.0 * a * a + z1 * z1);
    double d = sqrt((3.0 - z1) * (3.0 + z1 + 2.0 * z2));
    return 3.0 + z2 + (pro ? -d : d);
}

static double bpt_photon(double a, int pro)
{
    return 2.0 * (1.0 + cos(2.0 / 3.0 * acos(pro ? -a : a)));
}

static double bpt_mb(double a, int pro)
{
    double sa = pro ? a : -a;
    return 2.0 - sa + 2.0 * sqrt(1.0 - sa);
}

/* Omega, E, L, u^t by BPT (2.12)-(2.16); pm = +1 prograde, -1 retrograde. */
static void bpt_orbit(double a, int pm, double r, double *om, double *E, double *L, double *ut)
{
    double r12 = sqrt(r), r34 = sqrt(r * r12), r32 = r * r12;
    double den = r34 * sqrt(r32 - 3.0 * r12 + pm * 2.0 * a);
    *om = pm / (r32 + pm * a);
    *E = (r32 - 2.0 * r12 + pm * a) / den;
    *L = pm * (r * r - pm * 2.0 * a * r12 + a * a) / den;
    *ut = (r32 + pm * a) / den;
}

static void test_quadrature(void **state)
{
    int k, i;
    double worst = 0.0, w1, w2;
    cr_metric mt = mk(0.998, 0.0);
    double rc, risco;
    (void)state;
    for (k = 0; k <= 15; k++) {
        double s = 0.0, exact = (k % 2) ? 0.0 : 2.0 / (k + 1);
        for (i = 0; i < 8; i++) {
            double x, w;
            cr_quad_gl8(i, &x, &w);
            s += w * pow(x, k);
        }
        worst = fmax(worst, fabs(s - exact));
    }
    print_message("GL8: worst |error| on x^0..x^15 over [-1,1] %.2g (tol 1e-15)\n", worst);
    assert_true(worst < 1e-15);
    /* the flux integral with pieces of CR_FLUX_DT and half of it */
    risco = cr_orbit_r_isco(&mt, 1);
    rc = cr_orbit_r_photon(&mt, 1) - CR_FLUX_RC_OFFSET;
    k = (int)ceil(log((1000.0 - rc) / (risco - rc)) / CR_FLUX_DT);
    w1 = cr_flux_J_(&mt, 1, rc, risco, 1000.0, k);
    w2 = cr_flux_J_(&mt, 1, rc, risco, 1000.0, 2 * k);
    print_message("flux J(1000), a = 0.998: %d vs %d pieces differ by %.2g relative "
                  "(tol 1e-13)\n", k, 2 * k, rel(w1, w2));
    assert_true(rel(w1, w2) < 1e-13);
}

static void test_kerr_radii(void **state)
{
    const double as[] = {0.0, 0.1, 0.5, 0.9, 0.998, 0.9999, 1.0};
    double worst = 0.0, r;
    int i, pro;
    (void)state;
    for (i = 0; i < (int)(sizeof as / sizeof as[0]); i++)
        for (pro = 0; pro <= 1; pro++) {
            int sgn;
            for (sgn = -1; sgn <= 1; sgn += 2) { /* the hole spinning either way */
                cr_metric mt = mk(sgn * as[i], 0.0);
                int s = cr_orbit_sense(&mt, pro);
                double ri = cr_orbit_r_isco(&mt, s), rp = cr_orbit_r_photon(&mt, s),
                       rm = cr_orbit_r_mb(&mt, s);
                double tol = (as[i] >= 0.9999 && pro) ? 2e-4 : 1e-12;
                if (as[i] == 1.0 && pro)
                    continue; /* the double root: below */
                if (rel(ri, bpt_isco(as[i], pro)) > tol || rel(rp, bpt_photon(as[i], pro)) > tol ||
                    rel(rm, bpt_mb(as[i], pro)) > tol)
                    print_message("MISMATCH a=%g pro=%d: isco %.15g/%.15g photon %.15g/%.15g "
                                  "mb %.15g/%.15g\n", mt.a, pro, ri, bpt_isco(as[i], pro), rp,
                                  bpt_photon(as[i], pro), rm, bpt_mb(as[i], pro));
                assert_true(rel(ri, bpt_isco(as[i], pro)) < tol);
                assert_true(rel(rp, bpt_photon(as[i], pro)) < tol);
                assert_true(rel(rm, bpt_mb(as[i], pro)) < tol);
                if (tol == 1e-12) {
                    worst = fmax(worst, rel(ri, bpt_isco(as[i], pro)));
                    worst = fmax(worst, rel(rp, bpt_photon(as[i], pro)));
                    worst = fmax(worst, rel(rm, bpt_mb(as[i], pro)));
                }
            }
        }
    print_message("Kerr r_isco, r_photon, r_mb vs BPT closed forms: worst relative %.2g "
                  "(tol 1e-12; a = 0.9999 prograde 2e-4)\n", worst);
    {
        cr_metric m0 = mk(0.0, 0.0), m1 = mk(0.998, 0.0), m2 = mk(1.0, 0.0);
        r = cr_orbit_r_isco(&m0, 1);
        print_message("r_isco: a=0 %.15g (6), ", r);
        assert_true(fabs(r - 6.0) < 1e-12);
        r = cr_orbit_r_isco(&m1, 1);
        print_message("a=0.998 pro %.15g (1.2370 +- 5e-5), ", r);
        assert_true(fabs(r - 1.2370) < 5e-5);
        r = cr_orbit_r_isco(&m2, -1);
        print_message("a=1 retro %.15g (9, 1e-12), ", r);
        assert_true(fabs(r - 9.0) < 1e-12);
        r = cr_orbit_r_isco(&m2, 1);
        print_message("a=1 pro %.15g (1, 1e-6)\n", r);
        assert_true(fabs(r - 1.0) < 1e-6);
    }
}

static void test_kerr_orbits(void **state)
{
    uint64_t seed = 12;
    double worst = 0.0;
    int n;
    (void)state;
    for (n = 0; n < 2000; n++) {
        double a = cr_test_rand(&seed), om, E, L, ut;
        int pro = n & 1, pm = pro ? 1 : -1;
        cr_metric mt = mk(a, 0.0);
        double rp = cr_orbit_r_photon(&mt, pm);
        double r = rp * (1.0 + 1e-3) + 60.0 * pow(cr_test_rand(&seed), 2.0);
        cr_orbit o;
        assert_int_equal(cr_orbit_eval(&mt, pm, r, &o), 1);
        bpt_orbit(a, pm, r, &om, &E, &L, &ut);
        worst = fmax(worst, rel(o.omega, om));
        worst = fmax(worst, rel(o.E, E));
        worst = fmax(worst, rel(o.L, L));
        worst = fmax(worst, rel(o.ut, ut));
    }
    print_message("Kerr Omega, E, L, u^t vs BPT (2.12)-(2.16), 2000 orbits with "
                  "r_photon(1+1e-3) < r < 61: worst relative %.2g (tol 1e-12)\n", worst);
    assert_true(worst < 1e-12);
    {
        cr_metric mt = mk(0.5, 0.0);
        cr_orbit o;
        assert_int_equal(cr_orbit_eval(&mt, 1, 0.99 * cr_orbit_r_photon(&mt, 1), &o), 0);
        assert_int_equal(cr_orbit_eval(&mt, 1, 0.5, &o), 0);
    }
}

/* Largest root of r^3 - 6 r^2 + 9 Q^2 r - 4 Q^4 (M = 1) by Newton from 6. */
static double rn_isco_ref(double q)
{
    double r = 6.0, q2 = q * q;
    int i;
    for (i = 0; i < 100; i++) {
        double f = ((r - 6.0) * r + 9.0 * q2) * r - 4.0 * q2 * q2;
        double d = (3.0 * r - 12.0) * r + 9.0 * q2;
        r -= f / d;
    }
    return r;
}

static void test_rn_isco(void **state)
{
    const double qs[] = {0.0, 0.2, 0.5, 0.8, 0.95, 1.0};
    int i;
    (void)state;
    for (i = 0; i < (int)(sizeof qs / sizeof qs[0]); i++) {
        cr_metric mt = mk(0.0, qs[i]);
        double r = cr_orbit_r_isco(&mt, 1), ref = rn_isco_ref(qs[i]);
        double rr = cr_orbit_r_isco(&mt, -1);
        print_message("RN Q=%.2f: r_isco %.15g, cubic root %.15g, diff %.2g (tol 1e-12)\n",
                      qs[i], r, ref, fabs(r - ref));
        assert_true(fabs(r - ref) < 1e-12);
        assert_true(fabs(rr - r) < 1e-12); /* no spin: both senses alike */
    }
    {
        cr_metric mt = mk(0.0, 1.0);
        assert_true(fabs(cr_orbit_r_isco(&mt, 1) - 4.0) < 1e-12);
    }
}

static void test_kn_orbits_geodesic(void **state)
{
    uint64_t seed = 1212;
    double wn = 0.0, wg = 0.0, wel = 0.0, wd = 0.0, wisco = 0.0;
    int n;
    (void)state;
    for (n = 0; n < 1000; n++) {
        double a = 2.0 * cr_test_rand(&seed) - 1.0;
        double qmax = sqrt(1.0 - a * a), q = qmax * (2.0 * cr_test_rand(&seed) - 1.0);
        int s = (n & 1) ? 1 : -1;
        cr_metric mt = mk(a, q);
        double rp = cr_orbit_r_photon(&mt, s), risco = cr_orbit_r_isco(&mt, s);
        double r = rp + 0.02 + 40.0 * pow(cr_test_rand(&seed), 2.0);
        cr_orbit o;
        cr_metric_point p;
        cr_christoffel G;
        double u[4], g4[4][4], nrm, big, acc, ut_dn, up_dn;
        double dE, dL, dO, h = 1e-6 * r;
        cr_orbit op, om;

        assert_true(risco >= rp);
        assert_int_equal(cr_orbit_eval(&mt, s, r, &o), 1);
        cr_orbit_velocity(&o, u);
        cr_test_metric4(&mt, r, 0.5 * CR_PI, g4);
        nrm = cr_test_dot(g4, u, u);
        big = fabs(g4[0][0]) * u[0] * u[0] + 2.0 * fabs(g4[0][3] * u[0] * u[3]) +
              g4[3][3] * u[3] * u[3];
        wn = fmax(wn, fabs(nrm + 1.0) / big);
        /* radial geodesic equation: du^r/dtau = 0 for u^r = u^theta = 0 */
        cr_metric_eval(&mt, r, 0.5 * CR_PI, &p);
        cr_christoffel_eval(&mt, r, &p, &G);
        acc = G.r_tt * u[0] * u[0] + 2.0 * G.r_tph * u[0] * u[3] + G.r_phph * u[3] * u[3];
        big = fabs(G.r_tt * u[0] * u[0]) + fabs(2.0 * G.r_tph * u[0] * u[3]) +
              fabs(G.r_phph * u[3] * u[3]);
        wg = fmax(wg, fabs(acc) / big);
        /* E = -u_t, L = u_phi */
        ut_dn = g4[0][0] * u[0] + g4[0][3] * u[3];
        up_dn = g4[3][0] * u[0] + g4[3][3] * u[3];
        wel = fmax(wel, fabs(-ut_dn - o.E) / fabs(o.E));
        wel = fmax(wel, fabs(up_dn - o.L) / fmax(fabs(o.L), 1.0));
        /* derivatives */
        cr_orbit_derivs(&mt, s, r, &dE, &dL, &dO);
        assert_int_equal(cr_orbit_eval(&mt, s, r + h, &op), 1);
        assert_int_equal(cr_orbit_eval(&mt, s, r - h, &om), 1);
        wd = fmax(wd, fabs(dE - (op.E - om.E) / (2 * h)) / fmax(fabs(dE), 1e-3));
        wd = fmax(wd, fabs(dL - (op.L - om.L) / (2 * h)) / fmax(fabs(dL), 1e-3));
        wd = fmax(wd, fabs(dO - (op.omega - om.omega) / (2 * h)) / fabs(dO));
        /* at the ISCO both E and L are stationary */
        if (risco - rp > 1e-3) {
            double hh = 1e-5;
            cr_orbit a1, a2;
            assert_int_equal(cr_orbit_eval(&mt, s, risco + hh, &a1), 1);
            assert_int_equal(cr_orbit_eval(&mt, s, risco - hh, &a2), 1);
            wisco = fmax(wisco, fabs(a1.E - a2.E) / (2 * hh));
            wisco = fmax(wisco, fabs(a1.L - a2.L) / (2 * hh));
        }
    }
    print_message("Kerr-Newman, 1000 orbits: |g(u,u)+1| %.2g (tol 1e-13), radial geodesic "
                  "residual %.2g (tol 1e-12), E/L vs lowered u %.2g (tol 1e-12), "
                  "derivatives vs differences %.2g (tol 1e-6), |dE/dr|,|dL/dr| at r_isco "
                  "(differences, h = 1e-5) %.2g (tol 1e-8)\n",
                  wn, wg, wel, wd, wisco);
    assert_true(wn < 1e-13);
    assert_true(wg < 1e-12);
    assert_true(wel < 1e-12);
    assert_true(wd < 1e-6);
    assert_true(wisco < 1e-8);
}

/* A null covector at (r, th) with p_t = -1, p_phi = l and a fraction f in
 * (0, 1) of the remaining momentum in p_theta (the rest in p_r > 0).
 * Returns 0 when l is not allowed there. */
static int null_covector(const cr_metric *mt, double r, double th, double l, double f,
                         double p[4])
{
    cr_metric_point q;
    double ds, gtt, gtp, gpp, rest;
    cr_metric_eval(mt, r, th, &q);
    ds = q.delta * q.sin2;
    gtt = -q.g_phph / ds; /* inverse of the t-phi block: det = -Delta sin^2 */
    gtp = q.g_tph / ds;
    gpp = -q.g_tt / ds;
    rest = -(gtt - 2.0 * gtp * l + gpp * l * l); /* = g^rr p_r^2 + g^thth p_th^2 */
    if (!(rest > 0.0))
        return 0;
    p[0] = -1.0;
    p[3] = l;
    p[2] = sqrt(f * rest * q.g_thth);
    p[1] = sqrt((1.0 - f) * rest * q.g_rr);
    return 1;
}

static double null_norm_dn(const cr_metric *mt, double r, double th, const double p[4])
{
    cr_metric_point q;
    double ds, t;
    cr_metric_eval(mt, r, th, &q);
    ds = q.delta * q.sin2;
    t = (-q.g_phph * p[0] * p[0] + 2.0 * q.g_tph * p[0] * p[3] - q.g_tt * p[3] * p[3]) / ds;
    return (t + p[1] * p[1] / q.g_rr + p[2] * p[2] / q.g_thth) /
           (fabs(t) + p[1] * p[1] / q.g_rr + p[2] * p[2] / q.g_thth);
}

/* Matter plunging from the ISCO (cr_orbit_plunge_velocity), random
 * Kerr-Newman holes and senses, radii between r+ and r_isco:
 * - g(u, u) = -1 with the full metric (tol 1e-12 relative to its terms);
 * - u_t = -E_isco, u_phi = L_isco after lowering (tol 1e-12): the conserved
 *   quantities of the geodesic;
 * - the radial geodesic equation u^r d(u^r)/dr = -Gamma^r_mn u^m u^n, the
 *   left side by a central difference of (u^r)^2 / 2 (tol 1e-6 relative);
 * - u^r <= 0, u^t > 0;
 * - continuity with the circular orbit: at r_isco u^t, u^phi equal the
 *   circular orbit's (tol 1e-12) and |u^r| < 1e-7 (the square root of the
 *   rounding of (u^r)^2 ~ 1e-16); just inside, u^t, u^phi within 1e-5 at
 *   r_isco (1 - 1e-7), and u^r grows as (r_isco - r)^(3/2) (the ISCO is an
 *   inflection point of the potential): u^r at 4e-3 and 1e-3 r_isco below
 *   r_isco have the ratio 8 (tol 2 %; closer in, the rounding of (u^r)^2
 *   dominates). */
static void test_plunge(void **state)
{
    uint64_t seed = 4242;
    double wn = 0.0, wel = 0.0, wg = 0.0, wc = 0.0, wc6 = 0.0, wur = 0.0, wratio = 0.0;
    int n;
    (void)state;
    for (n = 0; n < 500; n++) {
        double a = 2.0 * cr_test_rand(&seed) - 1.0;
        double q = 0.95 * sqrt(1.0 - a * a) * (2.0 * cr_test_rand(&seed) - 1.0);
        int s = (n & 1) ? 1 : -1, k;
        cr_metric mt = mk(a, q);
        double rp = cr_metric_r_plus(&mt), risco = cr_orbit_r_isco(&mt, s);
        double r = rp + 0.01 + (risco - rp - 0.02) * cr_test_rand(&seed);
        double u[4] = {0}, up[4] = {0}, um[4] = {0}, u4[4] = {0}, uc[4], g4[4][4], nrm, big;
        double h = 1e-5 * r, lhs, rhs;
        cr_orbit o;
        cr_metric_point p;
        cr_christoffel G;
        if (!(risco - rp > 0.05))
            continue;
        assert_int_equal(cr_orbit_eval(&mt, s, risco, &o), 1);
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, r, u), 1);
        assert_true(u[0] > 0.0 && u[1] <= 0.0 && u[2] == 0.0);
        cr_test_metric4(&mt, r, 0.5 * CR_PI, g4);
        nrm = cr_test_dot(g4, u, u);
        big = fabs(g4[0][0]) * u[0] * u[0] + 2.0 * fabs(g4[0][3] * u[0] * u[3]) +
              g4[3][3] * u[3] * u[3] + g4[1][1] * u[1] * u[1];
        wn = fmax(wn, fabs(nrm + 1.0) / big);
        wel = fmax(wel, fabs(-(g4[0][0] * u[0] + g4[0][3] * u[3]) - o.E) / o.E);
        wel = fmax(wel, fabs(g4[3][0] * u[0] + g4[3][3] * u[3] - o.L) / fmax(fabs(o.L), 1.0));
        /* radial geodesic equation */
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, r + h, up), 1);
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, r - h, um), 1);
        lhs = 0.5 * (up[1] * up[1] - um[1] * um[1]) / (2.0 * h);
        cr_metric_eval(&mt, r, 0.5 * CR_PI, &p);
        cr_christoffel_eval(&mt, r, &p, &G);
        rhs = -(G.r_tt * u[0] * u[0] + 2.0 * G.r_tph * u[0] * u[3] + G.r_phph * u[3] * u[3] +
                G.r_rr * u[1] * u[1]);
        big = fabs(G.r_tt * u[0] * u[0]) + fabs(2.0 * G.r_tph * u[0] * u[3]) +
              fabs(G.r_phph * u[3] * u[3]) + fabs(G.r_rr * u[1] * u[1]);
        wg = fmax(wg, fabs(lhs - rhs) / big);
        /* continuity at the ISCO */
        cr_orbit_velocity(&o, uc);
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, risco, up), 1);
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, risco * (1.0 - 1e-7), um), 1);
        for (k = 0; k < 4; k += 3) {
            wc = fmax(wc, fabs(up[k] - uc[k]) / fmax(fabs(uc[k]), 1.0));
            wc6 = fmax(wc6, fabs(um[k] - uc[k]) / fmax(fabs(uc[k]), 1.0));
        }
        wur = fmax(wur, fabs(up[1]));
        /* the power law of u^r below the ISCO */
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, risco * (1.0 - 1e-3), um), 1);
        assert_int_equal(cr_orbit_plunge_velocity(&mt, o.E, o.L, risco * (1.0 - 4e-3), u4), 1);
        assert_true(um[1] < 0.0);
        wratio = fmax(wratio, fabs(u4[1] / um[1] / 8.0 - 1.0));
    }
    print_message("plunging from the ISCO, 500 random holes: |g(u,u)+1| %.2g (tol 1e-12), "
                  "E/L vs lowered u %.2g (tol 1e-12), radial geodesic residual %.2g (tol "
                  "1e-6), u^t, u^phi - circular at r_isco %.2g (tol 1e-12), at r_isco (1 - "
                  "1e-7) %.2g (tol 1e-5); |u^r| at r_isco %.2g (tol 1e-7); u^r(4e-3 below) / "
                  "u^r(1e-3 below) = 8 to %.2g (tol 0.02)\n",
                  wn, wel, wg, wc, wc6, wur, wratio);
    assert_true(wn < 1e-12);
    assert_true(wel < 1e-12);
    assert_true(wg < 1e-6);
    assert_true(wc < 1e-12);
    assert_true(wc6 < 1e-5);
    assert_true(wur < 1e-7);
    assert_true(wratio < 0.02);
    {
        cr_metric mt = mk(0.5, 0.0);
        double u[4] = {7, 7, 7, 7};
        assert_int_equal(cr_orbit_plunge_velocity(&mt, 0.9, 3.0, cr_metric_r_plus(&mt), u), 0);
        assert_true(u[0] == 7.0);
    }
}

static void test_static_is_special_case(void **state)
{
    uint64_t seed = 99;
    double worst = 0.0, wnull = 0.0;
    int n, done = 0;
    (void)state;
    for (n = 0; n < 4000 && done < 500; n++) {
        double a = 2.0 * cr_test_rand(&seed) - 1.0;
        double q = sqrt(1.0 - a * a) * (2.0 * cr_test_rand(&seed) - 1.0);
        cr_metric mt = mk(a, q);
        double rp = cr_metric_r_plus(&mt);
        double ro = rp + 0.05 + 100.0 * cr_test_rand(&seed), tho = 0.05 + 3.0 * cr_test_rand(&seed);
        double re = rp + 0.05 + 30.0 * cr_test_rand(&seed), the = 0.05 + 3.0 * cr_test_rand(&seed);
        double l = 4.0 * cr_test_rand(&seed) - 2.0, po[4] = {0}, pe[4] = {0}, uo[4], ue[4], g, ref;
        cr_frame f;
        if (!cr_shift_static_velocity(&mt, ro, tho, uo) ||
            !cr_shift_static_velocity(&mt, re, the, ue))
            continue;
        if (!null_covector(&mt, ro, tho, l, cr_test_rand(&seed), po) ||
            !null_covector(&mt, re, the, l, cr_test_rand(&seed), pe))
            continue;
        wnull = fmax(wnull, fabs(null_norm_dn(&mt, ro, tho, po)));
        wnull = fmax(wnull, fabs(null_norm_dn(&mt, re, the, pe)));
        cr_test_empty_frame(&f, 1.0, a, q, ro, tho);
        /* the frame's redshift of a static source (shift.h) against the
         * closed form sqrt(-g_tt)|e / sqrt(-g_tt)|o (ERRATA) */
        ref = sqrt(cr_metric_minus_gtt(&mt, re, the)) / sqrt(cr_metric_minus_gtt(&mt, ro, tho));
        worst = fmax(worst, rel(cr_redshift_static(&f, pe, pe, re, the), ref));
        g = cr_shift_ratio(po, uo, pe, ue);
        worst = fmax(worst, rel(g, ref));
        /* the ray's covector -k gives the same ratio */
        {
            double mo[4], me[4];
            int k;
            for (k = 0; k < 4; k++) {
                mo[k] = -po[k];
                me[k] = -pe[k];
            }
            assert_true(rel(cr_shift_ratio(mo, uo, me, ue), g) < 1e-15);
        }
        done++;
    }
    print_message("static source, static camera (%d random pairs outside the ergosurface): "
                  "|cr_shift_ratio / closed form - 1| and |cr_redshift_static / closed form - 1| "
                  "worst %.2g (tol 1e-12); photons "
                  "null to %.2g\n", done, worst, wnull);
    assert_true(done >= 400);
    assert_true(worst < 1e-12);
    assert_true(wnull < 1e-14);
    {
        cr_metric mt = mk(0.9, 0.0);
        double u[4] = {7, 7, 7, 7};
        assert_int_equal(cr_shift_static_velocity(&mt, 1.5, 0.5 * CR_PI, u), 0);
        assert_true(u[0] == 7.0);
    }
}

/* A photon reaching an observer on the axis has p_phi = p(d/dphi) = 0 there
 * (d/dphi vanishes on the axis), and p_phi is conserved, so p_phi = 0 at
 * the emitter: g = p_t / (p_t u^t + 0) = 1 / u^t for the observer at rest at
 * infinity (u_obs = (1, 0, 0, 0), where p_t has the same value). Whatever
 * p_r and p_theta (Carter constant) the image needs, g is the same. */
static void test_face_on_ring(void **state)
{
    const double rs[] = {4.0, 6.0, 10.0, 20.0, 100.0};
    const double uobs[4] = {1.0, 0.0, 0.0, 0.0};
    double worst = 0.0, wk = 0.0;
    int i, k;
    (void)state;
    for (i = 0; i < (int)(sizeof rs / sizeof rs[0]); i++) {
        cr_metric mt = mk(0.0, 0.0);
        cr_orbit o;
        double u[4], pe[4] = {0}, pinf[4] = {-1.0, 0.0, 0.0, 0.0}, g = 0.0;
        assert_int_equal(cr_orbit_eval(&mt, 1, rs[i], &o), 1);
        cr_orbit_velocity(&o, u);
        for (k = 1; k <= 9; k++) {
            double gk;
            assert_int_equal(null_covector(&mt, rs[i], 0.5 * CR_PI, 0.0, 0.1 * k, pe), 1);
            assert_true(fabs(null_norm_dn(&mt, rs[i], 0.5 * CR_PI, pe)) < 1e-15);
            gk = cr_shift_ratio(pinf, uobs, pe, u);
            if (k > 1)
                assert_true(gk == g);
            g = gk;
        }
        print_message("face-on Schwarzschild ring r = %5.1f M: g = %.17g, sqrt(1-3M/r) = "
                      "%.17g\n", rs[i], g, sqrt(1.0 - 3.0 / rs[i]));
        worst = fmax(worst, rel(g, sqrt(1.0 - 3.0 / rs[i])));
    }
    for (i = 0; i < 40; i++) { /* Kerr: 1/u^t of BPT */
        double a = 0.025 * i, om, E, L, ut, r = 10.0, u[4], pe[4] = {0};
        double pinf[4] = {-1.0, 0.0, 0.0, 0.0};
        int pm = (i & 1) ? 1 : -1;
        cr_metric mt = mk(a, 0.0);
        cr_orbit o;
        r = cr_orbit_r_isco(&mt, pm) + 0.1 * i;
        assert_int_equal(cr_orbit_eval(&mt, pm, r, &o), 1);
        cr_orbit_velocity(&o, u);
        assert_int_equal(null_covector(&mt, r, 0.5 * CR_PI, 0.0, 0.5, pe), 1);
        bpt_orbit(a, pm, r, &om, &E, &L, &ut);
        wk = fmax(wk, rel(cr_shift_ratio(pinf, uobs, pe, u), 1.0 / ut));
    }
    print_message("face-on: worst relative error %.2g (Schwarzschild), %.2g (Kerr vs 1/u^t "
                  "of BPT) (tol 1e-13)\n", worst, wk);
    assert_true(worst < 1e-13);
    assert_true(wk < 1e-13);
}

/* Edge-on Schwarzschild ring, observer at rest at infinity in the plane:
 * photons in the plane, p_theta = 0, emitted in the orbiter's rest frame at
 * angle psi from e_r toward e_phi. g = -p_t for unit local energy
 * (p . u_em = -1). g = 1/(u^t (1 - Omega b)), b = p_phi/(-p_t), is monotonic
 * in b, and |b| is largest for tangential emission (p^r = 0), |b| =
 * r/sqrt(1 - 2M/r); those photons escape for r > 3M, and as the emitter goes
 * round the ring the direct image's b sweeps through both. Hence
 *     g_max,min = sqrt(1 - 3M/r) / (1 -+ v),  v = sqrt(M / (r - 2M)),
 * v being the orbital speed measured by the static observer (the special-
 * relativistic Doppler factor times the gravitational sqrt(1 - 2M/r)). */
static void test_edge_on_ring(void **state)
{
    const double rs[] = {4.0, 6.0, 10.0, 30.0};
    const double uobs[4] = {1.0, 0.0, 0.0, 0.0};
    double worst = 0.0;
    int i, k;
    (void)state;
    for (i = 0; i < (int)(sizeof rs / sizeof rs[0]); i++) {
        double r = rs[i], g4[4][4], u[4], ud[4], v[4], er[4] = {0, 0, 0, 0}, nv;
        double gmax = -1.0, gmin = 1e300, v0, fmax_, fmin_;
        cr_metric mt = mk(0.0, 0.0);
        cr_orbit o;
        int mu, nu;
        assert_int_equal(cr_orbit_eval(&mt, 1, r, &o), 1);
        cr_orbit_velocity(&o, u);
        cr_test_metric4(&mt, r, 0.5 * CR_PI, g4);
        for (mu = 0; mu < 4; mu++) {
            ud[mu] = 0.0;
            for (nu = 0; nu < 4; nu++)
                ud[mu] += g4[mu][nu] * u[nu];
        }
        /* e_phi of the orbiter: (u_phi, 0, 0, -u_t) normalised (u . e_phi = 0) */
        v[0] = ud[3];
        v[1] = v[2] = 0.0;
        v[3] = -ud[0];
        nv = sqrt(cr_test_dot(g4, v, v));
        for (mu = 0; mu < 4; mu++)
            v[mu] /= nv;
        er[1] = 1.0 / sqrt(g4[1][1]);
        assert_true(fabs(cr_test_dot(g4, u, v)) < 1e-15);
        for (k = 0; k <= 2000; k++) { /* outgoing: psi in [-pi/2, pi/2] */
            double psi = CR_PI * (k / 2000.0 - 0.5), kup[4], p[4], g;
            for (mu = 0; mu < 4; mu++)
                kup[mu] = u[mu] + cos(psi) * er[mu] + sin(psi) * v[mu];
            for (mu = 0; mu < 4; mu++) {
                p[mu] = 0.0;
                for (nu = 0; nu < 4; nu++)
                    p[mu] += g4[mu][nu] * kup[nu];
            }
            assert_true(fabs(cr_test_dot(g4, kup, kup)) < 1e-13 * g4[3][3] * kup[3] * kup[3] + 1e-13);
            g = cr_shift_ratio(p, uobs, p, u); /* p_t is the same at infinity */
            gmax = fmax(gmax, g);
            gmin = fmin(gmin, g);
        }
        v0 = sqrt(1.0 / (r - 2.0));
        fmax_ = sqrt(1.0 - 3.0 / r) / (1.0 - v0);
        fmin_ = sqrt(1.0 - 3.0 / r) / (1.0 + v0);
        print_message("edge-on Schwarzschild ring r = %4.1f M: g in [%.15f, %.15f], formula "
                      "[%.15f, %.15f]\n", r, gmin, gmax, fmin_, fmax_);
        worst = fmax(worst, fmax(rel(gmax, fmax_), rel(gmin, fmin_)));
    }
    print_message("edge-on: worst relative error %.2g (tol 1e-13)\n", worst);
    assert_true(worst < 1e-13);
}

/* Page & Thorne 1974 closed form for Kerr (M = 1), signed spin as = s a
 * (retrograde orbits are prograde ones of the opposite spin):
 * F/Mdot = 3/(8 pi) / (x^4 (x^3 - 3x + 2as)) [x - x0 - 3/2 as ln(x/x0)
 *   - sum_i 3 (x_i - as)^2 / (x_i prod_{j != i}(x_i - x_j)) ln((x - x_i)/(x0 - x_i))],
 * x = sqrt(r), x0 = sqrt(r_isco), x_i the roots of x^3 - 3x + 2as = 0. */
static double pt_flux(double as, double r)
{
    double x = sqrt(r), risco = bpt_isco(fabs(as), as >= 0.0), x0 = sqrt(risco);
    double th = acos(as) / 3.0, xr[3], b;
    int i;
    xr[0] = 2.0 * cos(th - CR_PI / 3.0);
    xr[1] = 2.0 * cos(th + CR_PI / 3.0);
    xr[2] = -2.0 * cos(th);
    b = x - x0 - 1.5 * as * log(x / x0);
    for (i = 0; i < 3; i++) {
        double xi = xr[i], xj = xr[(i + 1) % 3], xk = xr[(i + 2) % 3];
        b -= 3.0 * (xi - as) * (xi - as) / (xi * (xi - xj) * (xi - xk)) *
             log((x - xi) / (x0 - xi));
    }
    return 3.0 / (8.0 * CR_PI) * b / (x * x * x * x * (x * x * x - 3.0 * x + 2.0 * as));
}

/* Golden-section maximum of F on [lo, hi]: pt_flux (table = 0) or
 * cr_orbit_flux. */
static double peak(const cr_metric *mt, int s, double lo, double hi, int pt, double *fm)
{
    const double gr = 0.61803398874989484820;
    double r0 = lo, x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1, f2;
    int i;
#define PEAK_F(r) (pt ? pt_flux(s * mt->a, (r)) : cr_orbit_flux(mt, s, r0, (r)))
    f1 = PEAK_F(x1);
    f2 = PEAK_F(x2);
    for (i = 0; i < 100; i++) {
        if (f1 < f2) {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + gr * (hi - lo);
            f2 = PEAK_F(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - gr * (hi - lo);
            f1 = PEAK_F(x1);
        }
    }
#undef PEAK_F
    *fm = fmax(f1, f2);
    return f1 > f2 ? x1 : x2;
}

static void test_flux_page_thorne(void **state)
{
    const double as[] = {0.0, 0.3, 0.5, 0.9, 0.998, -0.5, -0.998};
    int i, k;
    (void)state;
    for (i = 0; i < (int)(sizeof as / sizeof as[0]); i++) {
        cr_metric mt = mk(fabs(as[i]), 0.0);
        int s = as[i] >= 0.0 ? 1 : -1;
        double risco = cr_orbit_r_isco(&mt, s), fpt, fcr, rpt, rcr, worst = 0.0;
        rpt = peak(&mt, s, risco, 200.0, 1, &fpt);
        rcr = peak(&mt, s, risco, 200.0, 0, &fcr);
        for (k = 0; k <= 400; k++) {
            double r = risco * pow(1000.0 / risco, k / 400.0);
            worst = fmax(worst, fabs(cr_orbit_flux(&mt, s, risco, r) - pt_flux(as[i], r)) / fpt);
        }
        print_message("a*s = %6.3f: r_isco %.6f; peak r %.9f (PT %.9f), F_max %.12e (PT %.12e, "
                      "rel %.2g); |F - F_PT|/F_max over [r_isco, 1000] %.2g; F(r_isco) = %g\n",
                      as[i], risco, rcr, rpt, fcr, fpt, rel(fcr, fpt), worst,
                      cr_orbit_flux(&mt, s, risco, risco));
        assert_true(fabs(rcr - rpt) < 1e-6);
        assert_true(rel(fcr, fpt) < 1e-10);
        assert_true(worst < 1e-10);
        assert_true(cr_orbit_flux(&mt, s, risco, risco) == 0.0);
        assert_true(cr_orbit_flux(&mt, s, risco, risco * (1.0 + 1e-6)) < 1e-9 * fpt);
    }
}

static void test_flux_table(void **state)
{
    const double cs[][4] = {/* a, q, s, r_out */
                            {0.0, 0.0, 1, 1000.0}, {0.998, 0.0, 1, 1000.0},
                            {0.998, 0.0, 1, 1e4},  {0.6, 0.7, 1, 500.0},
                            {0.6, 0.7, -1, 500.0}, {0.0, 1.0, 1, 50.0},
                            {0.9, 0.0, 1, 8.0},
                            {0.9999, 0.0, 1, 1e4}};
    int i, k;
    double worst_all = 0.0;
    static cr_flux_table tab;
    (void)state;
    print_message("sizeof(cr_flux_table) = %zu bytes\n", sizeof tab);
    for (i = 0; i < (int)(sizeof cs / sizeof cs[0]); i++) {
        cr_metric mt = mk(cs[i][0], cs[i][1]);
        int s = (int)cs[i][2];
        double risco = cr_orbit_r_isco(&mt, s), worst = 0.0, fm, rm;
        assert_int_equal(cr_flux_table_fill(&tab, &mt, s, risco, cs[i][3]), 1);
        for (k = 0; k <= 5000; k++) {
            double r = risco + (cs[i][3] - risco) * pow(k / 5000.0, 3.0);
            double d = fabs(cr_flux_table_F(&tab, r) - cr_orbit_flux(&mt, s, risco, r));
            worst = fmax(worst, d / tab.F_max);
        }
        rm = peak(&mt, s, risco, cs[i][3], 0, &fm);
        print_message("table a=%.4f Q=%.2f s=%+d r_out=%g: r_isco %.6f, peak r %.6f F_max %.6e "
                      "(search %.6f, %.6e); |F_table - F|/F_max %.2g\n",
                      cs[i][0], cs[i][1], s, cs[i][3], risco, tab.r_peak, tab.F_max, rm, fm, worst);
        assert_true(rel(tab.F_max, fm) < 1e-12);
        assert_true(worst < 1e-5);
        worst_all = fmax(worst_all, worst);
        assert_true(cr_flux_table_F(&tab, risco) == 0.0);
        assert_true(cr_flux_table_F(&tab, 0.5 * risco) == 0.0);
        assert_true(cr_flux_table_F(&tab, cs[i][3] * 1.01) == 0.0);
        assert_true(fabs(cr_flux_tscale_peak(&tab, 1e4) * sqrt(sqrt(tab.F_max)) - 1e4) < 1e-9);
    }
    print_message("flux table: worst |F_table - F| / F_max %.2g (tol 1e-5)\n", worst_all);
    {
        cr_metric mt = mk(0.5, 0.0);
        double risco = cr_orbit_r_isco(&mt, 1);
        assert_int_equal(cr_flux_table_fill(&tab, &mt, 1, 0.99 * risco, 100.0), 0);
        assert_int_equal(cr_flux_table_fill(&tab, &mt, 1, risco, risco), 0);
        mt.a = 1.0; /* extremal: outside the table's range (CR_FLUX_MIN_GAP) */
        assert_int_equal(cr_flux_table_fill(&tab, &mt, 1, cr_orbit_r_isco(&mt, 1), 100.0), 0);
        mt.a = 0.5;
        /* a zero-torque edge outside the ISCO is allowed */
        assert_int_equal(cr_flux_table_fill(&tab, &mt, 1, 2.0 * risco, 100.0), 1);
        assert_true(tab.r_peak > 2.0 * risco);
    }
}

/* Page & Thorne's energy law (their eq. 13), integrated from the ISCO (zero
 * torque) to infinity, where the torque term 2 pi r Omega W ~ Mdot M/r
 * vanishes: Mdot (1 - E(r_isco)) = Integral 4 pi r F E dr (both faces, each
 * local energy redshifted by E on average for isotropic emission). Done in
 * v = 1/sqrt(r) (F r^3 has a sqrt(1/r) term at infinity, smooth in v):
 * Integral_0^{1/sqrt(r_isco)} 8 pi F E r^(7/2) dv. */
static void test_flux_luminosity(void **state)
{
    const double cs[][3] = {{0.0, 0.0, 1}, {0.9, 0.0, 1}, {0.9, 0.0, -1},
                            {0.7, 0.5, 1},  {0.0, 0.9, 1}, {-0.4, 0.8, 1}};
    int i, k, j;
    (void)state;
    for (i = 0; i < (int)(sizeof cs / sizeof cs[0]); i++) {
        cr_metric mt = mk(cs[i][0], cs[i][1]);
        int s = (int)cs[i][2];
        double risco = cr_orbit_r_isco(&mt, s), u1 = 1.0 / sqrt(risco), sum = 0.0, eta;
        const int npieces = 200;
        cr_orbit o;
        for (k = 0; k < npieces; k++) {
            double ua = u1 * k / npieces, ub = u1 * (k + 1) / npieces;
            for (j = 0; j < 8; j++) {
                double x, w, uu, r;
                cr_quad_gl8(j, &x, &w);
                uu = 0.5 * (ua + ub) + 0.5 * (ub - ua) * x;
                r = 1.0 / (uu * uu);
                assert_int_equal(cr_orbit_eval(&mt, s, r, &o), 1);
                sum += 0.5 * (ub - ua) * w * 8.0 * CR_PI * cr_orbit_flux(&mt, s, risco, r) * o.E *
                       r * r * sqrt(r);
            }
        }
        assert_int_equal(cr_orbit_eval(&mt, s, risco, &o), 1);
        eta = 1.0 - o.E;
        print_message("a=%.2f Q=%.2f s=%+d: luminosity/Mdot %.12f, 1 - E(r_isco) %.12f, "
                      "rel %.2g (tol 1e-8)\n", cs[i][0], cs[i][1], s, sum, eta, rel(sum, eta));
        assert_true(rel(sum, eta) < 1e-8);
    }
}

/* Far out, F -> 3 M Mdot/(8 pi r^3) (1 - sqrt(r_isco/r)) (Shakura-Sunyaev with
 * zero torque at r_isco), corrections O(sqrt(M/r)) (Page-Thorne's logarithms
 * shift the bracket x - x0 by about -1.5 for a = 0). At r = 1e7 M, in SI, for
 * M = 10 M_sun and Mdot = 0.1 Mdot_Edd: T from the table and
 * cr_flux_tscale_si against (3 G M Mdot (1 - sqrt(r_in/r)) / (8 pi sigma R^3))^(1/4),
 * R = r G M / c^2. */
static void test_flux_si(void **state)
{
    cr_metric mt = mk(0.0, 0.0);
    static cr_flux_table tab;
    double risco = cr_orbit_r_isco(&mt, 1), M = 10.0 * CR_SI_M_SUN, r = 1e7, eta, mdot, T, Tn,
           R, Tpeak;
    cr_orbit o;
    (void)state;
    assert_int_equal(cr_orbit_eval(&mt, 1, risco, &o), 1);
    eta = 1.0 - o.E;
    mdot = 0.1 * cr_flux_mdot_edd_si(M, eta);
    assert_int_equal(cr_flux_table_fill(&tab, &mt, 1, risco, 1e3), 1);
    T = cr_flux_tscale_si(M, mdot) * sqrt(sqrt(cr_orbit_flux(&mt, 1, risco, r)));
    R = r * CR_SI_G * M / (CR_SI_C * CR_SI_C);
    Tn = sqrt(sqrt(3.0 * CR_SI_G * M * mdot * (1.0 - sqrt(risco / r)) /
                   (8.0 * CR_PI * CR_SI_SIGMA_SB * R * R * R)));
    Tpeak = cr_flux_tscale_si(M, mdot) * sqrt(sqrt(tab.F_max));
    print_message("M = 10 M_sun, Mdot = 0.1 Mdot_Edd (eta %.5f, %.4g kg/s): T(1e7 M) = %.6g K, "
                  "Newtonian %.6g K, rel %.2g (tol 2e-4); peak T %.4g K at r = %.4f M\n",
                  eta, mdot, T, Tn, rel(T, Tn), Tpeak, tab.r_peak);
    assert_true(rel(T, Tn) < 2e-4);
    assert_true(fabs(eta - (1.0 - sqrt(8.0 / 9.0))) < 1e-14);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quadrature),
        cmocka_unit_test(test_kerr_radii),
        cmocka_unit_test(test_kerr_orbits),
        cmocka_unit_test(test_rn_isco),
        cmocka_unit_test(test_kn_orbits_geodesic),
        cmocka_unit_test(test_plunge),
        cmocka_unit_test(test_static_is_special_case),
        cmocka_unit_test(test_face_on_ring),
        cmocka_unit_test(test_edge_on_ring),
        cmocka_unit_test(test_flux_page_thorne),
        cmocka_unit_test(test_flux_table),
        cmocka_unit_test(test_flux_luminosity),
        cmocka_unit_test(test_flux_si),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
