/* Worldlines of massive and charged particles (src/core/particle.h).
 *
 * Known answers and tolerances (each test prints what it measured):
 * - Random worldlines, neutral and charged, in Kerr-Newman (tol 1e-11):
 *   u.u = -1 to 1e-10 of the sum of the magnitudes of its terms (which is 1
 *   or more; near the horizon u^t ~ 1/Delta and they cancel), the Carter constant from u^theta (polar form) and from
 *   u^r with the charge terms (radial form, (P^2 - (Sigma u^r)^2)/Delta -
 *   r^2 - (L - aE)^2) both equal the initial K to 1e-9 of K + L^2 + r^2
 *   (the radial form: plus (P^2 + (Sigma u^r)^2)/Delta), E and L from the
 *   lowered u plus the potential to 1e-10 of the magnitudes of their terms.
 * - The same worldlines against an independent integration: Hamilton's
 *   equations of H = g^{mu nu}(pi_mu - qm A_mu)(pi_nu - qm A_nu)/2 with the
 *   inverse metric written out here and numerical derivatives of H, by RK4
 *   in proper time (step 0.005): t, r, theta, phi and u^mu agree at tau = 40 to 1e-8
 *   (8 worldlines that last that long).
 * - The observers' 4-velocities: static with v = 0 is (1/sqrt(-g_tt), 0, 0,
 *   0) (shift.h), ZAMO with v = 0 has L = 0, both to 1e-14; a velocity
 *   measured by the static observer, seen by the ZAMO, adds relativistically
 *   to the static observer's own (collinear along e_phi) to 1e-13.
 * - Circular orbits of Kerr-Newman (orbit.h's Omega), both senses, over 100
 *   orbits: r constant to 1e-8 relative, theta = pi/2 to 1e-10, the measured
 *   dphi/dt equal to Omega to 1e-9 relative.
 * - ISCO (orbit.h's r_isco, a = 0.9): R has a triple root there (R, R', R''
 *   below 1e-8 of their scale); the circular orbit at r_isco keeps r to
 *   1e-3 over 100 orbits; perturbed orbits (u^r = 1e-3) 3 % outside stay
 *   within 10 % of r, 3 % inside plunge into the hole within 100 orbits.
 * - Charged circular orbits in Reissner-Nordstrom against the closed form
 *   (derived below): r constant to 1e-8, Omega to 1e-9; the neutral orbit's
 *   velocity given a charge leaves the circle (by more than 1e-3).
 * - Schwarzschild perihelion advance of the orbit r = 10..20 M over 10
 *   radial periods against 4 K(k) / sqrt(2M(u3 - u1)) computed here by
 *   Gauss-Legendre quadrature (and the AGM): 1e-9 relative (on Delta phi -
 *   2 pi: 1e-8); the radial period in coordinate time against the quadrature
 *   of dt/dphi = E / ((1 - 2Mu) L u^2) over the same variable: 1e-9.
 * - Radial infall from rest at r0 = 10 M to the horizon stop: proper time
 *   against the cycloid tau = sqrt(r0^3 / 8M) (eta + sin eta), r = r0 (1 +
 *   cos eta) / 2, to 1e-9 relative; the worldline ends there.
 * - Radial escape at 0.8 c from r0 = 6 M to r = 1e4 M: t and tau at each
 *   step's end and middle against their quadrature over r, 1e-9 relative.
 * - Refused starts: |v| >= 1, inside the horizon, non-finite q/m, constants
 *   that do not allow the position.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "core/particle.h"
#include "core/shift.h"
#include "testutil.h"

#define TOL 1e-11
#define EPS 1e-6

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

/* u.u with the metric at (r, th). */
static double udotu(const cr_metric *mt, double r, double th, const double u[4])
{
    cr_metric_point m;
    cr_metric_eval(mt, r, th, &m);
    return m.g_tt * u[0] * u[0] + 2.0 * m.g_tph * u[0] * u[3] + m.g_phph * u[3] * u[3] +
           m.g_rr * u[1] * u[1] + m.g_thth * u[2] * u[2];
}

/* The sum of the magnitudes of the terms of u.u (u.u + 1 is measured
 * against it: near the horizon u^t grows as 1/Delta and the terms cancel). */
static double uterms(const cr_metric *mt, double r, double th, const double u[4])
{
    cr_metric_point m;
    cr_metric_eval(mt, r, th, &m);
    return fabs(m.g_tt) * u[0] * u[0] + 2.0 * fabs(m.g_tph * u[0] * u[3]) +
           m.g_phph * u[3] * u[3] + m.g_rr * u[1] * u[1] + m.g_thth * u[2] * u[2];
}

/* ---- independent integrator: Hamilton's equations ------------------------ */

/* Inverse BL metric of Kerr-Newman (written out here, not from metric.h):
 * g^tt = -A/(Sigma Delta), g^tph = -a W/(Sigma Delta),
 * g^phph = (Delta - a^2 s^2)/(Sigma Delta s^2), g^rr = Delta/Sigma,
 * g^thth = 1/Sigma, A = (r^2+a^2)^2 - Delta a^2 s^2, W = 2Mr - Q^2. */
static double ham(const cr_metric *mt, double qm, double r, double th, const double pi[4])
{
    double a = mt->a, s = sin(th), c = cos(th), s2 = s * s;
    double sig = r * r + a * a * c * c;
    double del = r * r + a * a + mt->q * mt->q - 2.0 * mt->m * r;
    double A = (r * r + a * a) * (r * r + a * a) - del * a * a * s2;
    double W = 2.0 * mt->m * r - mt->q * mt->q;
    double At = -mt->q * r / sig, Aph = mt->q * r * a * s2 / sig;
    double kt = pi[0] - qm * At, kph = pi[3] - qm * Aph, kr = pi[1], kth = pi[2];
    return 0.5 * (-A / (sig * del) * kt * kt - 2.0 * a * W / (sig * del) * kt * kph +
                  (del - a * a * s2) / (sig * del * s2) * kph * kph + del / sig * kr * kr +
                  kth * kth / sig);
}

/* z = (t, r, th, ph, pi_r, pi_th); pi_t, pi_ph constant in pc. */
static void ham_rhs(const cr_metric *mt, double qm, const double pc[2], const double *z,
                    double *dz)
{
    double pi[4] = {pc[0], z[4], z[5], pc[1]};
    double hr = 1e-5 * z[1], hth = 1e-5;
    int mu;
    for (mu = 0; mu < 4; mu++) {
        double save = pi[mu], hp = 1e-6 * (fabs(save) + 1.0), up, dn;
        pi[mu] = save + hp;
        up = ham(mt, qm, z[1], z[2], pi);
        pi[mu] = save - hp;
        dn = ham(mt, qm, z[1], z[2], pi);
        pi[mu] = save;
        dz[mu] = (up - dn) / (2.0 * hp);
    }
    dz[4] = -(ham(mt, qm, z[1] + hr, z[2], pi) - ham(mt, qm, z[1] - hr, z[2], pi)) / (2.0 * hr);
    dz[5] = -(ham(mt, qm, z[1], z[2] + hth, pi) - ham(mt, qm, z[1], z[2] - hth, pi)) /
            (2.0 * hth);
}

/* dx/dtau from H is linear in pi: the finite differences above are exact up
 * to rounding; the forces carry an O(h^2) ~ 1e-10 error. */
static void ham_integrate(const cr_metric *mt, double qm, double r, double th, double ph,
                          const double u[4], double tau_end, double out[8])
{
    cr_metric_point m;
    double At, Aph, pc[2], z[6], k1[6], k2[6], k3[6], k4[6], tmp[6], h = 0.005;
    long n = (long)ceil(tau_end / h), i;
    int j;
    h = tau_end / n;
    cr_metric_eval(mt, r, th, &m);
    cr_particle_potential(mt, r, th, &At, &Aph);
    pc[0] = m.g_tt * u[0] + m.g_tph * u[3] + qm * At;
    pc[1] = m.g_tph * u[0] + m.g_phph * u[3] + qm * Aph;
    z[0] = 0.0;
    z[1] = r;
    z[2] = th;
    z[3] = ph;
    z[4] = m.g_rr * u[1];
    z[5] = m.g_thth * u[2];
    for (i = 0; i < n; i++) {
        ham_rhs(mt, qm, pc, z, k1);
        for (j = 0; j < 6; j++)
            tmp[j] = z[j] + 0.5 * h * k1[j];
        ham_rhs(mt, qm, pc, tmp, k2);
        for (j = 0; j < 6; j++)
            tmp[j] = z[j] + 0.5 * h * k2[j];
        ham_rhs(mt, qm, pc, tmp, k3);
        for (j = 0; j < 6; j++)
            tmp[j] = z[j] + h * k3[j];
        ham_rhs(mt, qm, pc, tmp, k4);
        for (j = 0; j < 6; j++)
            z[j] += h * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]) / 6.0;
    }
    for (j = 0; j < 4; j++)
        out[j] = z[j];
    ham_rhs(mt, qm, pc, z, k1); /* dx/dtau = u at the end */
    for (j = 0; j < 4; j++)
        out[4 + j] = k1[j];
}

/* Run p until proper time tau_x; fills q there. Returns 0 if it ended first. */
static int run_to_tau(cr_particle *p, double tau_x, cr_particle_point *q)
{
    while (p->tau1 < tau_x) {
        if (cr_particle_step(p) != CR_PARTICLE_RUNNING && p->tau1 < tau_x)
            return 0;
    }
    cr_particle_at(p, cr_particle_find_tau(p, tau_x), q);
    return 1;
}

/* ---- random worldlines --------------------------------------------------- */

static void test_random_worldlines(void **state)
{
    uint64_t seed = 0x9e3779b97f4a7c15ULL;
    int n, checked = 0, compared = 0;
    double worst_uu = 0.0, worst_k = 0.0, worst_kr = 0.0, worst_el = 0.0, worst_h = 0.0;
    (void)state;
    for (n = 0; n < 24; n++) {
        double a = 1.6 * cr_test_rand(&seed) - 0.8;
        double q = 0.8 * cr_test_rand(&seed) - 0.4;
        cr_metric mt = mk(a, q);
        double qm = (n % 2) ? 4.0 * cr_test_rand(&seed) - 2.0 : 0.0;
        double r0 = 7.0 + 8.0 * cr_test_rand(&seed);
        double th0 = 0.6 + 1.9 * cr_test_rand(&seed);
        double v[3], u[4], E0, L0, K0;
        cr_particle p;
        cr_particle_point pt;
        int kind = n % 4 < 2 ? CR_PARTICLE_OBS_ZAMO : CR_PARTICLE_OBS_STATIC;
        long steps = 0;
        /* bound-ish: near the local circular speed, some radial and polar motion */
        v[0] = 0.2 * (cr_test_rand(&seed) - 0.5);
        v[1] = 0.2 * (cr_test_rand(&seed) - 0.5);
        v[2] = (cr_test_rand(&seed) < 0.3 ? -1.0 : 1.0) * (0.8 + 0.3 * cr_test_rand(&seed)) /
               sqrt(r0 - 2.0);
        assert_true(cr_particle_observer_u(&mt, kind, r0, th0, v, u));
        assert_true(fabs(udotu(&mt, r0, th0, u) + 1.0) < 1e-13);
        assert_true(cr_particle_start_u(&p, &mt, qm, TOL, EPS, 1e4, 0.0, r0, th0, 0.3, u));
        E0 = p.E;
        L0 = p.L;
        K0 = p.K;
        while (p.tau1 < 2000.0 && cr_particle_step(&p) == CR_PARTICLE_RUNNING) {
            double E, L, K, Kr, At, Aph, P, del, sig, la, scale, se, sl;
            cr_metric_point mp;
            cr_particle_current(&p, &pt);
            steps++;
            worst_uu = fmax(worst_uu, fabs(udotu(&mt, pt.r, pt.th, pt.u) + 1.0) /
                                          uterms(&mt, pt.r, pt.th, pt.u));
            cr_particle_constants(&mt, qm, pt.r, pt.th, pt.u, &E, &L, &K);
            scale = fabs(K0) + L0 * L0 + pt.r * pt.r;
            /* E and L against the magnitudes of their terms */
            cr_metric_eval(&mt, pt.r, pt.th, &mp);
            cr_particle_potential(&mt, pt.r, pt.th, &At, &Aph);
            se = fabs(mp.g_tt * pt.u[0]) + fabs(mp.g_tph * pt.u[3]) + fabs(qm * At);
            sl = fabs(mp.g_tph * pt.u[0]) + fabs(mp.g_phph * pt.u[3]) + fabs(qm * Aph);
            worst_el = fmax(worst_el, fmax(fabs(E - E0) / se, fabs(L - L0) / (1.0 + sl)));
            worst_k = fmax(worst_k, fabs(K - K0) / scale);
            /* the radial form, with the charge terms */
            P = E0 * (pt.r * pt.r + a * a) - a * L0 - qm * q * pt.r;
            del = pt.r * pt.r + a * a + q * q - 2.0 * pt.r;
            sig = pt.r * pt.r + a * a * cos(pt.th) * cos(pt.th);
            la = L0 - a * E0;
            Kr = (P * P - sig * sig * pt.u[1] * pt.u[1]) / del - pt.r * pt.r - la * la;
            worst_kr = fmax(worst_kr, fabs(Kr - K0) /
                                          (scale + (P * P + sig * sig * pt.u[1] * pt.u[1]) / del));
        }
        assert_true(steps > 20);
        /* against Hamilton's equations, over the first tau = 40 */
        if (compared < 8) {
            double z[8];
            int mu;
            assert_true(cr_particle_start_u(&p, &mt, qm, TOL, EPS, 1e4, 0.0, r0, th0, 0.3, u));
            if (!run_to_tau(&p, 40.0, &pt)) {
                checked++;
                continue; /* plunged or escaped before tau = 40 */
            }
            compared++;
            ham_integrate(&mt, qm, r0, th0, 0.3, u, 40.0, z);
            worst_h = fmax(worst_h, fabs(z[0] - pt.t) / (1.0 + fabs(z[0])));
            worst_h = fmax(worst_h, fabs(z[1] - pt.r) / z[1]);
            worst_h = fmax(worst_h, fabs(z[2] - pt.th));
            worst_h = fmax(worst_h, fabs(z[3] - pt.ph));
            for (mu = 0; mu < 4; mu++)
                worst_h = fmax(worst_h, fabs(z[4 + mu] - pt.u[mu]) / (1.0 + fabs(pt.u[mu])));
        }
        checked++;
    }
    printf("random worldlines: %d (%d against Hamilton), |u.u+1| %.2e, K(theta) %.2e, K(r, charge) %.2e, E/L %.2e, "
           "vs Hamilton %.2e\n",
           checked, compared, worst_uu, worst_k, worst_kr, worst_el, worst_h);
    assert_true(compared == 8);
    assert_true(worst_uu < 1e-10);
    assert_true(worst_k < 1e-9);
    assert_true(worst_kr < 1e-9);
    assert_true(worst_el < 1e-10);
    assert_true(worst_h < 1e-8);
}

/* ---- circular orbits ----------------------------------------------------- */

/* Integrate n orbits of angular speed omega from (r0, pi/2) with u; returns
 * the largest |r - r0| / r0 and |theta - pi/2|, the measured dphi/dt. */
static int circular_run(const cr_metric *mt, double qm, double r0, const double u[4],
                        double omega, double norbits, double *dr, double *dth, double *om_meas)
{
    cr_particle p;
    cr_particle_point pt;
    double t_end = norbits * CR_TWO_PI / fabs(omega);
    *dr = *dth = 0.0;
    if (!cr_particle_start_u(&p, mt, qm, TOL, EPS, 1e4, 0.0, r0, 0.5 * CR_PI, 0.0, u))
        return 0;
    while (p.t1 < t_end) {
        if (cr_particle_step(&p) != CR_PARTICLE_RUNNING)
            return 0;
        cr_particle_current(&p, &pt);
        *dr = fmax(*dr, fabs(pt.r - r0) / r0);
        *dth = fmax(*dth, fabs(pt.th - 0.5 * CR_PI));
    }
    cr_particle_at(&p, cr_particle_find_t(&p, t_end), &pt);
    *om_meas = pt.ph / pt.t;
    return 1;
}

static void test_circular_kn(void **state)
{
    const double spins[3] = {0.0, 0.7, -0.9}, charges[3] = {0.0, 0.3, 0.4};
    int i, sgn;
    (void)state;
    for (i = 0; i < 3; i++)
        for (sgn = -1; sgn <= 1; sgn += 2) {
            cr_metric mt = mk(spins[i], charges[i]);
            double r0 = 1.5 * cr_orbit_r_isco(&mt, sgn), u[4], dr, dth, om;
            cr_orbit o;
            assert_true(cr_orbit_eval(&mt, sgn, r0, &o));
            cr_orbit_velocity(&o, u);
            assert_true(circular_run(&mt, 0.0, r0, u, o.omega, 100.0, &dr, &dth, &om));
            printf("circular a=%.1f Q=%.1f s=%+d r=%.4f: dr/r %.2e dth %.2e Omega %.12f vs "
                   "%.12f (%.2e)\n",
                   spins[i], charges[i], sgn, r0, dr, dth, om, o.omega, rel(om, o.omega));
            assert_true(dr < 1e-8);
            assert_true(dth < 1e-10);
            assert_true(rel(om, o.omega) < 1e-9);
        }
}

static void test_isco(void **state)
{
    cr_metric mt = mk(0.9, 0.0);
    int sgn;
    (void)state;
    for (sgn = -1; sgn <= 1; sgn += 2) {
        double ri = cr_orbit_r_isco(&mt, sgn), u[4], dr, dth, om, R, R1, R2, sc;
        cr_orbit o;
        cr_mino c;
        cr_particle p;
        int k;
        assert_true(cr_orbit_eval(&mt, sgn, ri, &o));
        /* the triple root of R at the ISCO: R(r) = sum c_k r^(4-k) (W's
         * coefficients: c4 r^4 + c3 r^3 + c2 r^2 + c1 r + c0) */
        cr_particle_coeffs(&c, &mt, o.E, o.L, 0.0, 0.0, 0.5);
        R = (((c.c4 * ri + c.c3) * ri + c.c2) * ri + c.c1) * ri + c.c0;
        R1 = ((4.0 * c.c4 * ri + 3.0 * c.c3) * ri + 2.0 * c.c2) * ri + c.c1;
        R2 = (12.0 * c.c4 * ri + 6.0 * c.c3) * ri + 2.0 * c.c2;
        sc = fabs(c.c4) * ri * ri * ri * ri + fabs(c.c3) * ri * ri * ri + fabs(c.c2) * ri * ri +
             fabs(c.c1) * ri + fabs(c.c0);
        printf("isco s=%+d r=%.10f: R %.2e R' %.2e R'' %.2e (scale %.2e)\n", sgn, ri, R, R1,
               R2, sc);
        assert_true(fabs(R) < 1e-8 * sc);
        assert_true(fabs(R1) * ri < 1e-8 * sc);
        assert_true(fabs(R2) * ri * ri < 1e-8 * sc);
        cr_orbit_velocity(&o, u);
        assert_true(circular_run(&mt, 0.0, ri, u, o.omega, 100.0, &dr, &dth, &om));
        printf("  on the isco over 100 orbits: dr/r %.2e, Omega rel %.2e\n", dr,
               rel(om, o.omega));
        assert_true(dr < 1e-3);
        assert_true(rel(om, o.omega) < 1e-5);
        /* perturbed just outside (bounded) and just inside (plunges) */
        for (k = -1; k <= 1; k += 2) {
            double r0 = ri * (1.0 + 0.03 * k), t_end, rmin = r0, rmax = r0, v[3];
            cr_particle_point pt;
            int end;
            assert_true(cr_orbit_eval(&mt, sgn, r0, &o));
            cr_orbit_velocity(&o, u);
            /* add a radial kick in the ZAMO frame: rebuild u from v */
            {
                double e[4][4], alpha, omg, sp;
                cr_zamo_tetrad(&mt, r0, 0.5 * CR_PI, 0, e, &alpha, &omg, &sp);
                v[0] = 1e-3;
                v[1] = 0.0;
                v[2] = sp * (o.omega - omg) / alpha;
            }
            assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_ZAMO, r0, 0.5 * CR_PI, v, u));
            assert_true(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, r0, 0.5 * CR_PI,
                                            0.0, u));
            t_end = 100.0 * CR_TWO_PI / fabs(o.omega);
            end = CR_PARTICLE_RUNNING;
            while (p.t1 < t_end && (end = cr_particle_step(&p)) == CR_PARTICLE_RUNNING) {
                cr_particle_current(&p, &pt);
                rmin = fmin(rmin, pt.r);
                rmax = fmax(rmax, pt.r);
            }
            printf("  r0 = r_isco (1 %+.2f), kicked: r in [%.4f, %.4f], %s\n", 0.03 * k, rmin,
                   rmax, end == CR_PARTICLE_HORIZON ? "plunged" : "still orbiting");
            if (k > 0) {
                assert_int_equal(end, CR_PARTICLE_RUNNING);
                assert_true(rmin > 0.9 * r0 && rmax < 1.1 * r0);
            } else {
                assert_int_equal(end, CR_PARTICLE_HORIZON);
            }
        }
    }
}

/* Charged circular orbits of Reissner-Nordstrom (M = 1). With f = 1 - 2/r +
 * Q^2/r^2 and e = qm Q, the radial Lorentz-force equation at u^r = u^th = 0,
 *   Gamma^r_tt (u^t)^2 + Gamma^r_phph (u^ph)^2 = qm F^r_t u^t,
 * Gamma^r_tt = f f'/2, Gamma^r_phph = -f r, F^r_t = f Q / r^2, together with
 * -f (u^t)^2 + r^2 (u^ph)^2 = -1, gives for X = u^t
 *   (3/r - 2 Q^2/r^2 - 1) X^2 - (e/r) X + 1 = 0,
 * and Omega = sqrt(f X^2 - 1) / (r X), E = f X + e / r. */
static int rn_circular(double Q, double e, double r, double *X, double *Om)
{
    double f = 1.0 - 2.0 / r + Q * Q / (r * r), A = 3.0 / r - 2.0 * Q * Q / (r * r) - 1.0;
    double B = -e / r, disc = B * B - 4.0 * A, x1, x2;
    if (disc < 0.0)
        return 0;
    x1 = (-B + sqrt(disc)) / (2.0 * A);
    x2 = (-B - sqrt(disc)) / (2.0 * A);
    *X = x1 > 0.0 ? x1 : x2;
    if (!(*X > 0.0) || f * *X * *X - 1.0 <= 0.0)
        return 0;
    *Om = sqrt(f * *X * *X - 1.0) / (r * *X);
    return 1;
}

static void test_charged_circular_rn(void **state)
{
    const double qms[4] = {1.0, -1.0, 1.8, -3.0};
    double Q = 0.5, r0 = 9.0;
    cr_metric mt = mk(0.0, Q);
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        double X = 0.0, Om = 0.0, u[4], dr, dth, om, E, L, K;
        assert_true(rn_circular(Q, qms[i] * Q, r0, &X, &Om));
        u[0] = X;
        u[1] = u[2] = 0.0;
        u[3] = X * Om;
        cr_particle_constants(&mt, qms[i], r0, 0.5 * CR_PI, u, &E, &L, &K);
        assert_true(circular_run(&mt, qms[i], r0, u, Om, 100.0, &dr, &dth, &om));
        printf("RN charged circular q/m=%+.1f: E %.12f (closed %.12f) dr/r %.2e Omega %.12f vs "
               "%.12f (%.2e)\n",
               qms[i], E, (1.0 - 2.0 / r0 + Q * Q / (r0 * r0)) * X + qms[i] * Q / r0, dr, om,
               Om, rel(om, Om));
        assert_true(rel(E, (1.0 - 2.0 / r0 + Q * Q / (r0 * r0)) * X + qms[i] * Q / r0) < 1e-12);
        assert_true(dr < 1e-8);
        assert_true(rel(om, Om) < 1e-9);
    }
    {
        /* the neutral circular velocity with a charge is not circular */
        double u[4], dr, dth, om;
        cr_orbit o;
        assert_true(cr_orbit_eval(&mt, 1, r0, &o));
        cr_orbit_velocity(&o, u);
        assert_true(circular_run(&mt, 1.0, r0, u, o.omega, 5.0, &dr, &dth, &om));
        printf("neutral velocity with q/m = 1: dr/r %.2e\n", dr);
        assert_true(dr > 1e-3);
    }
}

/* ---- Schwarzschild perihelion advance ------------------------------------ */

static double agm(double x, double y)
{
    int i;
    for (i = 0; i < 40; i++) {
        double m = 0.5 * (x + y);
        y = sqrt(x * y);
        x = m;
    }
    return x;
}

static void test_perihelion(void **state)
{
    cr_metric mt = mk(0.0, 0.0);
    double rp = 10.0, ra = 20.0, u1 = 1.0 / ra, u2 = 1.0 / rp, u3 = 0.5 - u1 - u2;
    double L = 1.0 / sqrt(u1 * u2 + u1 * u3 + u2 * u3);
    double E = sqrt(1.0 - 2.0 * u1 * u2 * u3 * L * L);
    double k2 = (u2 - u1) / (u3 - u1), dphi_q = 0.0, dphi_agm, ph_peri[11], t_peri[11];
    double T_q = 0.0;
    int n = 0, i, j;
    cr_particle p;
    (void)state;
    /* Delta phi = 2 Int_0^{pi/2} 2 dchi / sqrt(2 M (u3 - u1 - (u2 - u1) sin^2 chi)),
     * u = u1 + (u2 - u1) sin^2 chi: 8-point Gauss-Legendre on 16 pieces */
    for (i = 0; i < 16; i++)
        for (j = 0; j < 8; j++) {
            double x, w, h = 0.5 * CR_PI / 16, chi, s;
            cr_quad_gl8(j, &x, &w);
            chi = (i + 0.5) * h + 0.5 * h * x;
            s = sin(chi);
            dphi_q += 0.5 * h * w * 4.0 / sqrt(2.0 * (u3 - u1 - (u2 - u1) * s * s));
            /* the radial period in t: dt/dphi = E / ((1 - 2 M u) L u^2) */
            {
                double u = u1 + (u2 - u1) * s * s;
                T_q += 0.5 * h * w * 4.0 / sqrt(2.0 * (u3 - u)) * E / ((1.0 - 2.0 * u) * L * u * u);
            }
        }
    dphi_agm = 4.0 * (0.5 * CR_PI / agm(1.0, sqrt(1.0 - k2))) / sqrt(2.0 * (u3 - u1));
    assert_true(rel(dphi_q, dphi_agm) < 1e-13);
    /* start at periapsis moving out; record phi at each later periapsis
     * (dw/dlambda from + to -) */
    assert_true(cr_particle_start_constants(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, rp, 0.5 * CR_PI,
                                            0.0, E, L, 0.0, 1, 1));
    ph_peri[0] = t_peri[0] = 0.0;
    while (n < 10) {
        assert_int_equal(cr_particle_step(&p), CR_PARTICLE_RUNNING);
        if (p.y0[CR_M_DW] > 0.0 && p.y1[CR_M_DW] <= 0.0) {
            cr_falsi z;
            double ys[CR_MN];
            cr_particle_point pt;
            cr_falsi_start(&z, p.y0[CR_M_DW], 1.0, p.y1[CR_M_DW]);
            while (cr_falsi_next(&z)) {
                cr_dp5_dense(&p.st, p.y0, p.y1, p.hm, z.s, ys);
                if (!cr_falsi_update(&z, ys[CR_M_DW]))
                    break;
            }
            cr_particle_at(&p, z.s, &pt);
            ph_peri[++n] = pt.ph;
            t_peri[n] = pt.t;
        }
    }
    {
        double meas = (ph_peri[10] - ph_peri[0]) / 10.0;
        printf("perihelion r=%g..%g: Delta phi %.12f, quadrature %.12f (AGM %.12f), advance "
               "%.10f vs %.10f (%.2e)\n",
               rp, ra, meas, dphi_q, dphi_agm, meas - CR_TWO_PI, dphi_q - CR_TWO_PI,
               rel(meas - CR_TWO_PI, dphi_q - CR_TWO_PI));
        assert_true(rel(meas, dphi_q) < 1e-9);
        assert_true(rel(meas - CR_TWO_PI, dphi_q - CR_TWO_PI) < 1e-8);
        printf("  radial period in t: %.10f vs quadrature %.10f (%.2e)\n", t_peri[10] / 10.0, T_q,
               rel(t_peri[10] / 10.0, T_q));
        assert_true(rel(t_peri[10] / 10.0, T_q) < 1e-9);
        /* every period the same */
        for (i = 1; i <= 10; i++)
            assert_true(fabs(ph_peri[i] - ph_peri[i - 1] - dphi_q) < 1e-8);
    }
}

/* ---- radial infall ------------------------------------------------------- */

static void test_radial_infall(void **state)
{
    cr_metric mt = mk(0.0, 0.0);
    double r0 = 10.0, v[3] = {0.0, 0.0, 0.0}, u[4], eta, tau_ex, rs;
    cr_particle p;
    cr_particle_point pt;
    (void)state;
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, r0, 0.5 * CR_PI, v, u));
    assert_true(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, r0, 0.5 * CR_PI, 0.0, u));
    while (cr_particle_step(&p) == CR_PARTICLE_RUNNING)
        ;
    assert_int_equal(p.ended, CR_PARTICLE_HORIZON);
    cr_particle_current(&p, &pt);
    rs = 2.0 + EPS;
    eta = acos(2.0 * rs / r0 - 1.0);
    tau_ex = sqrt(r0 * r0 * r0 / 8.0) * (eta + sin(eta));
    printf("radial infall from r0=%g: end r %.9f, tau %.12f vs cycloid %.12f (%.2e), t %.3f, "
           "%ld steps\n",
           r0, pt.r, pt.tau, tau_ex, rel(pt.tau, tau_ex), pt.t, p.steps);
    assert_true(fabs(pt.r - rs) < 1e-9);
    assert_true(rel(pt.tau, tau_ex) < 1e-9);
    /* at a middle radius too: tau(r = 6) */
    assert_true(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, r0, 0.5 * CR_PI, 0.0, u));
    {
        double r6 = 6.0, e6 = acos(2.0 * r6 / r0 - 1.0), t6 = sqrt(r0 * r0 * r0 / 8.0) * (e6 + sin(e6));
        assert_true(run_to_tau(&p, t6, &pt));
        printf("  at tau(r=6) = %.9f: r %.12f\n", t6, pt.r);
        assert_true(fabs(pt.r - r6) < 1e-8);
    }
}

/* ---- escape: t and tau far out -------------------------------------------- */

/* t(r) and tau(r) of the radial escape from r0 with energy E (Schwarzschild):
 * dt/dr = E / (f sqrt(E^2 - f)), dtau/dr = 1 / sqrt(E^2 - f), f = 1 - 2/r, by
 * 8-point Gauss-Legendre panels 1 % of r wide. */
static void escape_times(double r0, double E, double r, double *t, double *tau)
{
    double lo = r0;
    *t = *tau = 0.0;
    while (lo < r) {
        double hi = fmin(r, lo * 1.01), h = hi - lo;
        int j;
        for (j = 0; j < 8; j++) {
            double x, w, rr, f, sq;
            cr_quad_gl8(j, &x, &w);
            rr = lo + 0.5 * h * (x + 1.0);
            f = 1.0 - 2.0 / rr;
            sq = sqrt(E * E - f);
            *t += 0.5 * h * w * E / (f * sq);
            *tau += 0.5 * h * w / sq;
        }
        lo = hi;
    }
}

/* A particle flying out radially at 0.8 c (measured by the static observer
 * at r0 = 6 M) to r_max = 1e4 M: t and tau at every step's end and at its
 * middle (dense output) against escape_times, 1e-9 relative. The state's own
 * error control allows steps from r to several r there, over which t and tau
 * need their own (cr_particle_time_err_). */
static void test_escape(void **state)
{
    cr_metric mt = mk(0.0, 0.0);
    double r0 = 6.0, v[3] = {0.8, 0.0, 0.0}, u[4], E = sqrt(1.0 - 2.0 / r0) / 0.6;
    double worst_t = 0.0, worst_tau = 0.0;
    cr_particle p;
    cr_particle_point pt;
    int half;
    (void)state;
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, r0, 0.5 * CR_PI, v, u));
    assert_true(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, r0, 0.5 * CR_PI, 0.0, u));
    cr_particle_current(&p, &pt);
    while (cr_particle_step(&p) == CR_PARTICLE_RUNNING || p.ended == CR_PARTICLE_ESCAPED) {
        for (half = 0; half < 2; half++) {
            double t, tau;
            cr_particle_at(&p, half ? 1.0 : 0.5, &pt);
            escape_times(r0, E, pt.r, &t, &tau);
            worst_t = fmax(worst_t, rel(pt.t, t));
            worst_tau = fmax(worst_tau, rel(pt.tau, tau));
        }
        if (p.ended)
            break;
    }
    assert_int_equal(p.ended, CR_PARTICLE_ESCAPED);
    printf("escape at 0.8 c from r0 = 6 to r = %g in %ld steps: t (%.6g) within %.2e, tau "
           "within %.2e\n",
           pt.r, p.steps, pt.t, worst_t, worst_tau);
    assert_true(fabs(pt.r - 1e4) < 1e-6);
    assert_true(worst_t < 1e-9);
    assert_true(worst_tau < 1e-9);
}

/* ---- observers ----------------------------------------------------------- */

static void test_observers(void **state)
{
    cr_metric mt = mk(0.8, 0.3);
    double v[3] = {0.0, 0.0, 0.0}, u[4], us[4], E, L, K, e[4][4], al, om, sp;
    double r = 5.0, th = 1.1, vs, vz;
    (void)state;
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, r, th, v, u));
    assert_true(cr_shift_static_velocity(&mt, r, th, us));
    printf("static at rest: u %.15f %.1e %.1e %.1e vs %.15f\n", u[0], u[1], u[2], u[3], us[0]);
    assert_true(rel(u[0], us[0]) < 1e-14 && fabs(u[1]) < 1e-14 && fabs(u[2]) < 1e-14 &&
                fabs(u[3]) < 1e-14);
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_ZAMO, r, th, v, u));
    cr_particle_constants(&mt, 0.0, r, th, u, &E, &L, &K);
    assert_true(fabs(L) < 1e-14);
    /* v_ph = 0.4 for the static observer; the static observer moves with
     * vs = -omega sqrt(g_phph) / alpha for the ZAMO: the particle moves for
     * the ZAMO with (vs + 0.4) / (1 + 0.4 vs) */
    v[2] = 0.4;
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, r, th, v, u));
    cr_zamo_tetrad(&mt, r, th, 0, e, &al, &om, &sp);
    vs = -om * sp / al;
    {
        cr_metric_point m;
        double ut, uph; /* the particle's velocity for the ZAMO: u . e_ph / -(u . e_0) */
        cr_metric_eval(&mt, r, th, &m);
        ut = m.g_tt * u[0] + m.g_tph * u[3];
        uph = m.g_tph * u[0] + m.g_phph * u[3];
        vz = (uph * e[3][3]) / -(ut * e[0][0] + uph * e[0][3]);
    }
    printf("static + 0.4: ZAMO sees %.15f, addition %.15f\n", vz, (vs + 0.4) / (1.0 + 0.4 * vs));
    assert_true(fabs(vz - (vs + 0.4) / (1.0 + 0.4 * vs)) < 1e-13);
}

/* ---- refused starts ------------------------------------------------------ */

static void test_refused(void **state)
{
    cr_metric mt = mk(0.6, 0.2);
    double v[3] = {0.0, 0.0, 1.0}, u[4], rp = cr_metric_r_plus(&mt);
    cr_particle p;
    (void)state;
    assert_false(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_ZAMO, 8.0, 1.0, v, u));
    v[2] = 0.3;
    v[0] = 0.96;
    assert_false(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, 8.0, 1.0, v, u));
    v[0] = 0.0;
    /* no static observer inside the ergosurface */
    assert_false(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_STATIC, 1.01 * rp + 0.05, 1.5, v, u));
    assert_true(cr_particle_observer_u(&mt, CR_PARTICLE_OBS_ZAMO, 8.0, 1.0, v, u));
    assert_false(cr_particle_start_u(&p, &mt, NAN, TOL, EPS, 1e4, 0.0, 8.0, 1.0, 0.0, u));
    assert_false(cr_particle_start_u(&p, &mt, INFINITY, TOL, EPS, 1e4, 0.0, 8.0, 1.0, 0.0, u));
    assert_false(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, 0.9 * rp, 1.0, 0.0, u));
    u[0] *= 1.001; /* not normalised */
    assert_false(cr_particle_start_u(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, 8.0, 1.0, 0.0, u));
    /* E = 0.9, L = 3 allow r = 8? R(8) < 0 for a too small L? pick forbidden */
    assert_false(cr_particle_start_constants(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, 8.0, 1.5, 0.0,
                                             0.5, 3.0, 0.0, 1, 1));
    assert_true(cr_particle_start_constants(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, 8.0, 0.5 * CR_PI,
                                            0.0, 0.97, 3.5, 0.0, 1, 1));
    /* polar potential negative: K = 0 off the equator with L != 0 */
    assert_false(cr_particle_start_constants(&p, &mt, 0.0, TOL, EPS, 1e4, 0.0, 8.0, 1.0, 0.0,
                                             0.97, 3.5, 0.0, 1, 1));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_worldlines), cmocka_unit_test(test_circular_kn),
        cmocka_unit_test(test_isco),           cmocka_unit_test(test_charged_circular_rn),
        cmocka_unit_test(test_perihelion),     cmocka_unit_test(test_radial_infall),
        cmocka_unit_test(test_escape),
        cmocka_unit_test(test_observers),      cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, 0, 0);
}
