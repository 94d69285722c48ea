/* Null geodesics: conserved quantities along traced rays and the order of
 * convergence of the integrator.
 *
 * With the default step multiplier c = 1/32, along rays of Kerr-Newman holes (several a, Q, directions, including rays
 * that pass near the photon region and rays that cross the polar axis):
 * - the scale-free null norm stays below 1e-6;
 * - the Carter constant K keeps |K - K0| <= 1e-6 (|K0| + L^2 + a^2 E^2);
 * - E and L recomputed from u^mu by (2.3.5)/(2.3.6) equal the ray's constants
 *   to 1e-10 (they are exact constants of the integrated system; this checks
 *   that the first-order equations (2.3.8)/(2.3.9) invert (2.3.5)/(2.3.6)).
 * Convergence: the state at a fixed affine parameter, compared with a run at
 * c/64, shrinks by 2^4 = 16 (accepted: 12..20) each time c is halved.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

typedef struct run_stats {
    double max_null, max_dK, max_dEL;
    int axis_crossings;
    double min_axis; /* closest angular distance to the polar axis */
    long steps;
} run_stats;

/* Integrate with step multiplier c until lambda_end (exactly; 0 = no limit),
 * r <= r_stop or r >= r_max, recording conservation. */
static void integrate(const cr_frame *f, const cr_geo *g, double *y, double c, double lambda_end,
                      run_stats *st)
{
    double lam = 0.0, K0 = cr_geo_carter(g, y);
    double Kscale = fabs(K0) + g->L * g->L + g->mt.a * g->mt.a * g->E * g->E;
    memset(st, 0, sizeof *st);
    st->min_axis = CR_PI;
    for (;;) {
        double k1[CR_NY], y1[CR_NY], u[4], h, E, L;
        cr_metric_point p;
        cr_geo_rhs_full(g, y, k1, u, &p);
        st->min_axis = fmin(st->min_axis, fmin(y[CR_Y_TH], CR_PI - y[CR_Y_TH]));
        st->max_null = fmax(st->max_null, fabs(cr_geo_null_norm(&p, u)));
        st->max_dK = fmax(st->max_dK, fabs(cr_geo_carter(g, y) - K0) / Kscale);
        cr_geo_constants(&p, u, &E, &L);
        st->max_dEL = fmax(st->max_dEL, fmax(fabs(E - g->E), fabs(L - g->L)) /
                                            (fabs(g->E) + fabs(g->L)));
        if (y[CR_Y_R] <= f->r_stop || (y[CR_Y_R] >= f->r_max && u[1] > 0.0))
            break;
        if (lambda_end > 0.0 && lam >= lambda_end)
            break;
        h = cr_geo_step_size(g, c, y[CR_Y_TH], u);
        if (lambda_end > 0.0 && lam + h > lambda_end)
            h = lambda_end - lam;
        cr_geo_rk4(g, y, k1, h, y1);
        lam += h;
        st->axis_crossings += cr_geo_through_axis(y1);
        memcpy(y, y1, sizeof y1);
        st->steps++;
    }
}

static void start_ray(cr_frame *f, double m, double a, double q, double r, double th,
                      double nx, double ny, double nz, cr_geo *g, double *y)
{
    double n[3], len = sqrt(nx * nx + ny * ny + nz * nz);
    cr_test_empty_frame(f, m, a, q, r, th);
    /* integrate() stops outgoing rays at r_max: beyond the start here (with
     * a plain sky the frame's own r_max is the empty scene's 6 M) */
    if (f->r_max < r + 1.0)
        f->r_max = r + 1.0;
    n[0] = nx / len;
    n[1] = ny / len;
    n[2] = nz / len;
    cr_camera_ray(f, n, g, y);
}

static void test_conservation_along_rays(void **state)
{
    const double params[][3] = {{1, 0, 0}, {1, 0.5, 0}, {1, 0.9, 0.3}, {1, 0.998, 0}, {1, 0, 0.8}};
    double worst_null = 0.0, worst_K = 0.0, worst_EL = 0.0;
    int ip, k;
    uint64_t s = 12345;
    (void)state;
    for (ip = 0; ip < 5; ip++)
        for (k = 0; k < 40; k++) {
            cr_frame f;
            cr_geo g;
            double y[CR_NY];
            run_stats st;
            /* directions within ~25 deg of the hole: many pass close to it */
            double nx = -1.0, ny = 0.5 * (cr_test_rand(&s) - 0.5),
                   nz = 0.5 * (cr_test_rand(&s) - 0.5);
            start_ray(&f, params[ip][0], params[ip][1], params[ip][2], 25.0,
                      0.2 + 2.7 * cr_test_rand(&s), nx, ny, nz, &g, y);
            integrate(&f, &g, y, cr_trace_defaults().step_multiplier, 0.0, &st);
            worst_null = fmax(worst_null, st.max_null);
            worst_K = fmax(worst_K, st.max_dK);
            worst_EL = fmax(worst_EL, st.max_dEL);
        }
    print_message("200 rays: worst null norm %.3g (tol 1e-6), Carter drift %.3g (tol 1e-6), "
                  "E/L mismatch %.3g (tol 1e-10)\n",
                  worst_null, worst_K, worst_EL);
    assert_true(worst_null < 1e-6);
    assert_true(worst_K < 1e-6);
    assert_true(worst_EL < 1e-10);
}

/* L of the ray leaving the observer at direction (-1, ny, nz) (normalized). */
static double ray_L(double a, double ny, double nz)
{
    cr_frame f;
    cr_geo g;
    double y[CR_NY];
    start_ray(&f, 1.0, a, 0.1, 20.0, CR_PI / 3.0, -1.0, ny, nz, &g, y);
    return g.L;
}

/* Rays aimed over the pole: with L = 0 they cross the axis, with small L they
 * swing around it within a tiny angle. Both must conserve as well as the
 * other rays (ERRATA item 2). */
static void test_conservation_through_axis(void **state)
{
    const double spins[] = {0.0, 0.6, 0.99};
    int is, k, crossings = 0, near = 0;
    double worst_null = 0.0, worst_K = 0.0;
    (void)state;
    for (is = 0; is < 3; is++) {
        const double ny = -0.35;
        double z0 = 0.0, z1 = 0.01, L0 = ray_L(spins[is], ny, z0), L1 = ray_L(spins[is], ny, z1);
        int it;
        for (it = 0; it < 50 && L1 != L0 && fabs(L1) > 1e-16; it++) { /* secant: L(nz) = 0 */
            double z2 = z1 - L1 * (z1 - z0) / (L1 - L0);
            z0 = z1;
            L0 = L1;
            z1 = z2;
            L1 = ray_L(spins[is], ny, z1);
        }
        for (k = 0; k < 12; k++) {
            cr_frame f;
            cr_geo g;
            double y[CR_NY], dz = k == 0 ? 0.0 : (k % 2 ? 1.0 : -1.0) * 1e-6 * (1 << (k / 2));
            run_stats st;
            start_ray(&f, 1.0, spins[is], 0.1, 20.0, CR_PI / 3.0, -1.0, ny, z1 + dz, &g, y);
            integrate(&f, &g, y, cr_trace_defaults().step_multiplier, 0.0, &st);
            crossings += st.axis_crossings;
            near += st.min_axis < 1e-3;
            worst_null = fmax(worst_null, st.max_null);
            worst_K = fmax(worst_K, st.max_dK);
        }
    }
    print_message("36 rays over the pole: %d crossed the axis, %d came within 1e-3 rad of it; "
                  "worst null norm %.3g, Carter drift %.3g (tol 1e-6)\n",
                  crossings, near, worst_null, worst_K);
    assert_true(crossings >= 3);
    assert_true(near >= 30);
    assert_true(worst_null < 1e-6);
    assert_true(worst_K < 1e-6);
}

static void test_fourth_order_convergence(void **state)
{
    const double lam_end = 25.0;
    double ref[CR_NY] = {0.0}, err[4];
    int i, k;
    (void)state;
    for (k = -1; k < 4; k++) {
        cr_frame f;
        cr_geo g;
        double y[CR_NY], c = k < 0 ? (1.0 / 8.0) / 64.0 : (1.0 / 8.0) / (1 << k);
        run_stats st;
        start_ray(&f, 1.0, 0.9, 0.2, 20.0, 1.3, -1.0, 0.2, 0.35, &g, y);
        integrate(&f, &g, y, c, lam_end, &st);
        if (k < 0) {
            memcpy(ref, y, sizeof ref);
            assert_true(ref[CR_Y_R] < 19.0); /* still near the hole at lambda_end */
            continue;
        }
        err[k] = 0.0;
        for (i = CR_Y_R; i <= CR_Y_PH; i++)
            err[k] = fmax(err[k], fabs(y[i] - ref[i]));
    }
    for (k = 0; k < 3; k++) {
        double ratio = err[k] / err[k + 1];
        print_message("c = 1/%d: error %.3e, ratio to c/2 %.2f\n", 8 << k, err[k], ratio);
        assert_true(ratio > 12.0 && ratio < 20.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conservation_along_rays),
        cmocka_unit_test(test_conservation_through_axis),
        cmocka_unit_test(test_fourth_order_convergence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
