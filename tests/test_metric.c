/* The Kerr-Newman metric, its Christoffel symbols and the observer frame.
 *
 * - Christoffel symbols (B.9)-(B.20) against central finite differences of
 *   the metric through (B.1), at random points and parameters (a^2 + Q^2 < M^2),
 *   including points near the poles and near the outer horizon.
 *   Tolerance: |analytic - numeric| <= 1e-6 (|numeric| + max_component).
 * - Horizon and ergosurface: Delta(r+) = 0, g_tt(r_E+) = 0.
 * - The static observer's frame is orthonormal under g to 1e-12, and pixel
 *   rays are null to 1e-12, at several positions and spins.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

/* Gamma^alpha_{beta gamma} for alpha in {r, theta} by (B.1) from central
 * differences of g in r and theta (the metric does not depend on t, phi). */
static void numeric_christoffel(const cr_metric *mt, double r, double th, double hr, double hth,
                                double out[2][4][4])
{
    double gp[4][4], gm[4][4], g[4][4], dg[4][4][4]; /* dg[d][mu][nu] = d_d g_mu nu */
    int a, b, c, d;
    memset(dg, 0, sizeof dg);
    cr_test_metric4(mt, r + hr, th, gp);
    cr_test_metric4(mt, r - hr, th, gm);
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++)
            dg[1][a][b] = (gp[a][b] - gm[a][b]) / (2.0 * hr);
    cr_test_metric4(mt, r, th + hth, gp);
    cr_test_metric4(mt, r, th - hth, gm);
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++)
            dg[2][a][b] = (gp[a][b] - gm[a][b]) / (2.0 * hth);
    cr_test_metric4(mt, r, th, g);
    for (a = 1; a <= 2; a++) {
        double ginv = 1.0 / g[a][a]; /* g^{rr}, g^{thth}: the metric is diagonal there */
        for (b = 0; b < 4; b++)
            for (c = 0; c < 4; c++) {
                d = a;
                out[a - 1][b][c] = 0.5 * ginv * (dg[c][d][b] + dg[b][d][c] - dg[d][b][c]);
            }
    }
}

/* The analytic symbols in the same [alpha][beta][gamma] layout. */
static void analytic_christoffel(const cr_metric *mt, double r, double th, double out[2][4][4])
{
    cr_metric_point p;
    cr_christoffel G;
    memset(out, 0, 2 * 16 * sizeof(double));
    cr_metric_eval(mt, r, th, &p);
    cr_christoffel_eval(mt, r, &p, &G);
    out[0][0][0] = G.r_tt;
    out[0][1][1] = G.r_rr;
    out[0][2][2] = G.r_thth;
    out[0][3][3] = G.r_phph;
    out[0][0][3] = out[0][3][0] = G.r_tph;
    out[0][1][2] = out[0][2][1] = G.r_rth;
    out[1][0][0] = G.th_tt;
    out[1][1][1] = G.th_rr;
    out[1][2][2] = G.th_thth;
    out[1][3][3] = G.th_phph;
    out[1][0][3] = out[1][3][0] = G.th_tph;
    out[1][1][2] = out[1][2][1] = G.th_rth;
}

static void check_point(const cr_metric *mt, double r, double th, double *worst)
{
    double num[2][4][4], ana[2][4][4], scale = 0.0;
    double rp = cr_metric_r_plus(mt);
    double hr = 1e-4 * fmin(r, r - rp), hth = 1e-5 * fmin(1.0, fmin(th, CR_PI - th) * 100.0);
    int a, b, c;
    numeric_christoffel(mt, r, th, hr, hth, num);
    analytic_christoffel(mt, r, th, ana);
    for (a = 0; a < 2; a++)
        for (b = 0; b < 4; b++)
            for (c = 0; c < 4; c++)
                scale = fmax(scale, fabs(num[a][b][c]));
    for (a = 0; a < 2; a++)
        for (b = 0; b < 4; b++)
            for (c = 0; c < 4; c++) {
                double err = fabs(ana[a][b][c] - num[a][b][c]) / (fabs(num[a][b][c]) + scale);
                if (err > *worst)
                    *worst = err;
                if (err > 1e-6)
                    fail_msg("Gamma^%s_%d%d at M=%g a=%g Q=%g r=%.17g th=%.17g: analytic %.12g, "
                             "numeric %.12g (rel %.3g)",
                             a ? "theta" : "r", b, c, mt->m, mt->a, mt->q, r, th, ana[a][b][c],
                             num[a][b][c], err);
            }
}

static void test_christoffel_finite_differences(void **state)
{
    uint64_t s = 0x9e3779b97f4a7c15ULL;
    double worst = 0.0;
    int n, k;
    (void)state;
    for (n = 0; n < 400; n++) {
        cr_metric mt;
        double rp, r, th, rho, phi;
        mt.m = 0.5 + 1.5 * cr_test_rand(&s);
        rho = 0.999 * mt.m * sqrt(cr_test_rand(&s)); /* sqrt(a^2 + Q^2) < M */
        phi = CR_TWO_PI * cr_test_rand(&s);
        mt.a = rho * cos(phi);
        mt.q = rho * sin(phi);
        rp = cr_metric_r_plus(&mt);
        for (k = 0; k < 6; k++) {
            switch (k) {
            case 0: /* near the horizon */
                r = rp * (1.0 + 1e-3 * (0.1 + cr_test_rand(&s)));
                th = 0.05 + 3.04 * cr_test_rand(&s);
                break;
            case 1: /* near the north pole */
                r = rp * (1.01 + 20.0 * cr_test_rand(&s));
                th = 1e-3 * (0.1 + cr_test_rand(&s));
                break;
            case 2: /* near the south pole */
                r = rp * (1.01 + 20.0 * cr_test_rand(&s));
                th = CR_PI - 1e-3 * (0.1 + cr_test_rand(&s));
                break;
            default:
                r = rp * (1.001 + 30.0 * cr_test_rand(&s));
                th = 0.01 + 3.12 * cr_test_rand(&s);
            }
            check_point(&mt, r, th, &worst);
        }
    }
    print_message("2400 points: worst relative difference %.3g (tolerance 1e-6)\n", worst);
}

static void test_horizon_and_ergosurface(void **state)
{
    const double as[] = {0.0, 0.5, 0.9, 0.998, 1.0}, qs[] = {0.0, 0.3, 0.0, 0.0, 0.0};
    int i;
    (void)state;
    for (i = 0; i < 5; i++) {
        cr_metric mt = {1.0, as[i], qs[i]};
        double rp = cr_metric_r_plus(&mt), th;
        cr_metric_point p;
        cr_metric_eval(&mt, rp, 1.0, &p);
        assert_true(fabs(p.delta) < 1e-12);
        for (th = 0.1; th < 3.1; th += 0.5)
            assert_true(fabs(cr_metric_minus_gtt(&mt, cr_metric_r_ergo(&mt, th), th)) < 1e-12);
        /* identity g_tt g_phph - g_tph^2 = -Delta sin^2 */
        cr_metric_eval(&mt, 7.3, 0.8, &p);
        assert_true(fabs(p.g_tt * p.g_phph - p.g_tph * p.g_tph + p.delta * p.sin2) <
                    1e-12 * p.g_phph);
    }
    {
        cr_metric naked = {1.0, 0.9, 0.5};
        assert_true(isnan(cr_metric_r_plus(&naked)));
    }
}

static void test_observer_frame_orthonormal(void **state)
{
    const double spins[] = {0.0, 0.5, 0.9, 0.998, 1.0};
    const double rs[] = {30.0, 10.0, 4.2};
    const double ths[] = {0.5 * CR_PI, 0.3, 2.9, 1e-3};
    const double eta[4] = {-1.0, 1.0, 1.0, 1.0};
    int is, ir, it, a, b;
    (void)state;
    for (is = 0; is < 5; is++)
        for (ir = 0; ir < 3; ir++)
            for (it = 0; it < 4; it++) {
                cr_frame f;
                double g[4][4], worst = 0.0;
                cr_test_empty_frame(&f, 1.0, spins[is], spins[is] < 0.95 ? 0.2 : 0.0, rs[ir],
                                    ths[it]);
                f.observer.roll = 0.3;
                f.observer.pitch = -0.2;
                f.observer.yaw = 0.7;
                cr_frame_prepare(&f);
                cr_test_metric4(&f.metric, f.observer.r, f.observer.theta, g);
                for (a = 0; a < 4; a++)
                    for (b = 0; b < 4; b++) {
                        double d = cr_test_dot(g, f.tetrad[a], f.tetrad[b]) -
                                   (a == b ? eta[a] : 0.0);
                        worst = fmax(worst, fabs(d));
                    }
                if (worst > 1e-12)
                    fail_msg("frame not orthonormal at a=%g r=%g th=%g: %.3g", spins[is],
                             rs[ir], ths[it], worst);
                /* camera axes stay orthonormal after roll/pitch/yaw */
                for (a = 0; a < 3; a++)
                    for (b = 0; b < 3; b++) {
                        double d = f.cam[a][0] * f.cam[b][0] + f.cam[a][1] * f.cam[b][1] +
                                   f.cam[a][2] * f.cam[b][2] - (a == b);
                        assert_true(fabs(d) < 1e-14);
                    }
                /* pixel rays are null, corners included */
                for (a = 0; a < 4; a++) {
                    double n[3], y[CR_NY], u[4], dy[CR_NY];
                    cr_geo geo;
                    cr_metric_point p;
                    cr_camera_pixel_dir(&f, (a & 1) ? 63 : 0, (a & 2) ? 63 : 0, n);
                    cr_camera_ray(&f, n, &geo, y);
                    cr_geo_rhs_full(&geo, y, dy, u, &p);
                    assert_true(fabs(cr_geo_null_norm(&p, u)) < 1e-12);
                    assert_true(u[0] < 0.0); /* past-directed: backward tracing */
                }
            }
}

/* With no rotation the camera looks at the hole, image up is -theta and
 * image right is +phi (DESIGN "Conventions"); yaw = 180 deg looks outward. */
static void test_camera_conventions(void **state)
{
    cr_frame f;
    double n[3];
    (void)state;
    cr_test_empty_frame(&f, 1.0, 0.0, 0.0, 30.0, 0.5 * CR_PI);
    f.width = f.height = 3;
    cr_frame_prepare(&f);
    cr_camera_pixel_dir(&f, 1, 1, n);
    assert_true(fabs(n[0] + 1.0) < 1e-15);
    cr_camera_pixel_dir(&f, 1, 0, n); /* top centre: towards -theta */
    assert_true(n[1] < 0.0 && fabs(n[2]) < 1e-15);
    cr_camera_pixel_dir(&f, 2, 1, n); /* right centre: towards +phi */
    assert_true(n[2] > 0.0 && fabs(n[1]) < 1e-15);
    f.observer.yaw = CR_PI;
    cr_frame_prepare(&f);
    cr_camera_pixel_dir(&f, 1, 1, n);
    assert_true(fabs(n[0] - 1.0) < 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_christoffel_finite_differences),
        cmocka_unit_test(test_horizon_and_ergosurface),
        cmocka_unit_test(test_observer_frame_orthonormal),
        cmocka_unit_test(test_camera_conventions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
