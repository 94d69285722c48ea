/* The shadow of Schwarzschild and Reissner-Nordstrom holes seen by a static
 * observer at r_o: its angular radius psi (measured from the direction to the
 * hole) satisfies
 *   sin(psi) = (b_c / r_o) sqrt(1 - 2M/r_o + Q^2/r_o^2),
 * b_c = r_ph^2 / sqrt(r_ph^2 - 2M r_ph + Q^2), r_ph = (3M + sqrt(9M^2 - 8Q^2))/2,
 * with psi > 90 deg inside the photon sphere (r_o < r_ph). The edge found by
 * bisection on traced rays (horizon inside, sky outside) must match to
 * 1e-8 rad, for rays in the equatorial plane and for rays over the pole.
 *
 * Kerr, observer in the equatorial plane: the shadow's edges along the image's
 * horizontal axis are the equatorial circular photon orbits with impact
 * parameters b = -a + 6M cos(acos(-a/M)/3) (prograde) and
 * b = a + 6M cos(acos(a/M)/3) (retrograde) (Bardeen 1973). The backward ray
 * of a photon with impact parameter b (angular momentum b E) leaves a static
 * observer with the local direction component n_phi = (b g_tt + g_tphi)/sqrt(Delta)
 * along e_phi, so the edge rays are at sin(psi) = |n_phi|. The prograde (short, flattened) edge must be
 * on the LEFT of the image: a > 0 turns counter-clockwise about +z and its
 * left side moves towards the observer (ERRATA item 1). Tolerance 1e-7 rad. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

static double analytic_psi(double m, double q, double ro)
{
    double rph = 0.5 * (3.0 * m + sqrt(9.0 * m * m - 8.0 * q * q));
    double bc = rph * rph / sqrt(rph * rph - 2.0 * m * rph + q * q);
    double s = bc / ro * sqrt(1.0 - 2.0 * m / ro + q * q / (ro * ro));
    double psi = asin(fmin(1.0, s));
    return ro < rph ? CR_PI - psi : psi;
}

/* Outcome of the ray at angle psi from the inward direction, turned towards
 * +phi (polar = 0) or towards -theta, over the pole (polar = 1). */
static int trace_at(const cr_frame *f, double psi, int polar)
{
    double n[3], y[CR_NY];
    cr_geo g;
    cr_pixel px;
    n[0] = -cos(psi);
    n[1] = polar ? -sin(psi) : 0.0;
    n[2] = polar ? 0.0 : sin(psi);
    cr_camera_ray(f, n, &g, y);
    px = cr_trace_ray(f, &g, y);
    return px.outcome;
}

static void check_shadow(double m, double q, double ro, int polar, double *worst)
{
    cr_frame f;
    double lo, hi, psi = analytic_psi(m, q, ro);
    int it;
    cr_test_empty_frame(&f, m, 0.0, q, ro, 0.5 * CR_PI);
    lo = psi - 0.05;
    hi = fmin(psi + 0.05, CR_PI - 1e-9);
    assert_int_equal(trace_at(&f, lo, polar), CR_OUT_HORIZON);
    assert_int_equal(trace_at(&f, hi, polar), CR_OUT_SKY);
    for (it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        int o = trace_at(&f, mid, polar);
        assert_true(o == CR_OUT_HORIZON || o == CR_OUT_SKY || o == CR_OUT_LIMIT);
        if (o == CR_OUT_LIMIT)
            break; /* orbiting: as close to the edge as the integration resolves */
        if (o == CR_OUT_HORIZON)
            lo = mid;
        else
            hi = mid;
    }
    print_message("M=%g Q=%-4g r_o=%-5g %s: psi analytic %.9f, traced %.9f, diff %.2e\n", m, q,
                  ro, polar ? "polar " : "equat.", psi, 0.5 * (lo + hi), 0.5 * (lo + hi) - psi);
    *worst = fmax(*worst, fabs(0.5 * (lo + hi) - psi));
    if (fabs(0.5 * (lo + hi) - psi) > 1e-8)
        fail_msg("shadow edge off by %.3g rad", 0.5 * (lo + hi) - psi);
}

/* Critical angle psi between horizon (smaller) and sky (larger) for rays
 * turned by psi from the inward direction towards +phi (side = +1, image
 * right) or -phi (side = -1, image left), observer in the equatorial plane. */
static double kerr_edge(const cr_frame *f, int side)
{
    double lo = 0.0, hi = 0.5 * CR_PI;
    int it;
    for (it = 0; it < 48; it++) {
        double mid = 0.5 * (lo + hi), n[3], y[CR_NY];
        cr_geo g;
        cr_pixel px;
        n[0] = -cos(mid);
        n[1] = 0.0;
        n[2] = side * sin(mid);
        cr_camera_ray(f, n, &g, y);
        px = cr_trace_ray(f, &g, y);
        if (px.outcome == CR_OUT_LIMIT)
            break;
        if (px.outcome == CR_OUT_HORIZON)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

static void test_shadow_kerr_equatorial_edges(void **state)
{
    const double spins[] = {0.3, 0.7, 0.9, 0.998};
    const double ro = 30.0;
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        double a = spins[i];
        double b_pro = -a + 6.0 * cos(acos(-a) / 3.0), b_retro = a + 6.0 * cos(acos(a) / 3.0);
        cr_frame f;
        cr_metric_point p;
        double n_pro, n_retro, left, right;
        cr_test_empty_frame(&f, 1.0, a, 0.0, ro, 0.5 * CR_PI);
        cr_metric_eval(&f.metric, ro, 0.5 * CR_PI, &p);
        /* prograde photon: angular momentum +b; retrograde: -b */
        n_pro = (b_pro * p.g_tt + p.g_tph) / sqrt(p.delta);
        n_retro = (-b_retro * p.g_tt + p.g_tph) / sqrt(p.delta);
        left = kerr_edge(&f, -1);
        right = kerr_edge(&f, +1);
        print_message("a=%-5g left edge %.9f (prograde, analytic %.9f), right edge %.9f "
                      "(retrograde, analytic %.9f)\n",
                      a, left, asin(fabs(n_pro)), right, asin(fabs(n_retro)));
        /* the prograde photon arrives moving towards +phi: it is seen on the left */
        assert_true(n_pro < 0.0 && n_retro > 0.0);
        assert_true(left < right);
        assert_true(fabs(left - asin(fabs(n_pro))) < 1e-7);
        assert_true(fabs(right - asin(fabs(n_retro))) < 1e-7);
    }
}

static void test_shadow_schwarzschild(void **state)
{
    const double ros[] = {30.0, 10.0, 4.0, 2.9, 2.2};
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 5; i++) {
        check_shadow(1.0, 0.0, ros[i], 0, &worst);
        check_shadow(1.0, 0.0, ros[i], 1, &worst);
    }
}

static void test_shadow_reissner_nordstrom(void **state)
{
    const double qs[] = {0.5, 0.9, 1.0};
    const double ros[] = {25.0, 6.0, 2.4};
    double worst = 0.0;
    int i, k;
    (void)state;
    for (k = 0; k < 3; k++)
        for (i = 0; i < 3; i++)
            check_shadow(1.0, qs[k], ros[i], i == 1, &worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shadow_schwarzschild),
        cmocka_unit_test(test_shadow_reissner_nordstrom),
        cmocka_unit_test(test_shadow_kerr_equatorial_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
