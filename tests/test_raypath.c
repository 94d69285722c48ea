/* The path of one pixel's ray (output/raypath.h, --trace, curray.trace) for
 * the observer at infinity with a plain-colour sky, where the image takes a
 * ray that never comes inside the scene radius as sky without a step: its
 * path is traced anyway, in from infinity, past its turning point and out
 * again. Checked against Schwarzschild's exact turning point: a null ray of
 * impact parameter b (b^2 = alpha^2 + beta^2 at infinity for a = 0) turns at
 * the largest root r0 of r^3 - b^2 r + 2 M b^2 = 0, and its path is null
 * (g(u, u) = 0) at every point; the pixel it reports stays the image's. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "input/scene.h"
#include "output/raypath.h"

#define W 32
#define H 18

static void load_frame(const char *text, cr_frame *f, cr_scene *s)
{
    cr_err err;
    err.msg[0] = '\0';
    if (cr_scene_load_string(text, strlen(text), "test.yml", s, &err) ||
        cr_scene_frame(s, 0, 1, W, H, NULL, f, NULL, &err))
        fail_msg("%s", err.msg);
}

/* The largest root of r^3 - b^2 r + 2 b^2 (M = 1), by bisection: it lies
 * in [3, b] for b > sqrt(27) (the cubic is negative at 3 and positive at b). */
static double turning_point(double b)
{
    double lo = 3.0, hi = b;
    for (int k = 0; k < 200; k++) {
        double mid = 0.5 * (lo + hi);
        if (mid * mid * mid - b * b * mid + 2.0 * b * b > 0.0)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* |g(u, u)| over the sum of the magnitudes of its terms at point p, with
 * Schwarzschild's metric (M = 1) written out. */
static double null_residual(const double *p)
{
    double r = p[CR_P_R], s = sin(p[CR_P_TH]), t[4], num = 0.0, den = 0.0;
    t[0] = -(1.0 - 2.0 / r) * p[CR_P_UT] * p[CR_P_UT];
    t[1] = p[CR_P_UR] * p[CR_P_UR] / (1.0 - 2.0 / r);
    t[2] = r * r * p[CR_P_UTH] * p[CR_P_UTH];
    t[3] = r * r * s * s * p[CR_P_UPH] * p[CR_P_UPH];
    for (int k = 0; k < 4; k++) {
        num += t[k];
        den += fabs(t[k]);
    }
    return fabs(num) / den;
}

static void test_untraced_ray_has_its_path(void **state)
{
    static const char scene[] = "metric: {m: 1, a: 0, q: 0}\n"
                                "observer: {r: inf, theta: 85, phi: 0, hextent: 40}\n"
                                "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                                "radius: [6, 15]}\n";
    /* corners and edges of the 40 M wide plane: b from 19.4 to 22.1 M, all
     * beyond the scene radius 16 M (disc 15 M + M) */
    static const int pix[][2] = {{0, 0}, {31, 0}, {0, 17}, {31, 17}, {0, 9}, {31, 9}};
    cr_frame f;
    cr_scene s;
    (void)state;
    load_frame(scene, &f, &s);
    assert_true(f.w_sky > 0.0 && !f.sky.rgb);
    for (size_t n = 0; n < sizeof pix / sizeof pix[0]; n++) {
        int i = pix[n][0], j = pix[n][1];
        double alpha = (2.0 * (i + 0.5) / W - 1.0) * 20.0;
        double beta = (1.0 - 2.0 * (j + 0.5) / H) * 20.0 * H / W;
        double b = sqrt(alpha * alpha + beta * beta), r0 = turning_point(b), rmin = INFINITY;
        cr_pixel img = cr_trace_pixel(&f, i, j);
        cr_raypath rp;
        cr_err err;
        long k, kmin = 0;
        double worst = 0.0;
        assert_true(r0 > 16.0); /* never inside the scene radius */
        assert_int_equal(cr_raypath_trace(&f, i, j, &rp, &err), 0);
        /* the image's pixel: sky, untraced */
        assert_int_equal(img.outcome, CR_OUT_SKY);
        assert_int_equal(img.steps, 0);
        assert_int_equal(rp.px.outcome, CR_OUT_SKY);
        assert_int_equal(rp.px.steps, 0);
        assert_memory_equal(&rp.px.color, &img.color, sizeof img.color);
        assert_true(rp.untraced);
        /* the path: 8 points per step of the ray traced for it, less the
         * points at w <= 0 (r infinite) of its first and last step */
        assert_true(rp.n > 16);
        assert_true(rp.n <= 8 * (long)rp.path_steps && rp.n > 8 * ((long)rp.path_steps - 2));
        for (k = 0; k < rp.n; k++) {
            const double *p = rp.pts + k * CR_PN;
            for (int c = 0; c < CR_PN; c++)
                assert_true(isfinite(p[c]));
            if (p[CR_P_R] < rmin) {
                rmin = p[CR_P_R];
                kmin = k;
            }
            worst = fmax(worst, null_residual(p));
            if (k > 0) /* backward in time, forward in the parameter */
                assert_true(p[CR_P_LAM] > p[CR_P_LAM - CR_PN] && p[CR_P_T] < p[CR_P_T - CR_PN]);
        }
        print_message("pixel (%d, %d): b = %.6f, r0 = %.9f, path r %.6g -> min %.9f -> %.6g, "
                      "%ld points, null residual %.2g\n",
                      i, j, b, r0, rp.pts[CR_P_R], rmin, rp.pts[(rp.n - 1) * CR_PN + CR_P_R],
                      rp.n, worst);
        /* in from far out (the first finite point), out to far out */
        assert_true(rp.pts[CR_P_R] > 50.0 * r0 && rp.pts[CR_P_UR] < 0.0);
        assert_true(rp.pts[(rp.n - 1) * CR_PN + CR_P_R] > 50.0 * r0 &&
                    rp.pts[(rp.n - 1) * CR_PN + CR_P_UR] > 0.0);
        assert_true(kmin > 0 && kmin < rp.n - 1);
        /* no sample lies inside the turning point; the closest one is at it
         * within the spacing of the dense output (1e-3; measured 3e-5) */
        assert_true(rmin >= r0 * (1.0 - 1e-9));
        assert_true(rmin <= r0 * (1.0 + 1e-3));
        assert_true(worst < 1e-6);
        cr_raypath_free(&rp);
    }
    cr_scene_free(&s);
}

/* A ray that does come inside the scene radius keeps the image's own path
 * (the same steps as the image's pixel). */
static void test_traced_ray_unchanged(void **state)
{
    static const char scene[] = "metric: {m: 1, a: 0, q: 0}\n"
                                "observer: {r: inf, theta: 85, phi: 0, hextent: 40}\n";
    cr_frame f;
    cr_scene s;
    cr_raypath rp;
    cr_err err;
    (void)state;
    load_frame(scene, &f, &s);
    cr_pixel img = cr_trace_pixel(&f, 10, 10);
    assert_int_equal(cr_raypath_trace(&f, 10, 10, &rp, &err), 0);
    assert_false(rp.untraced);
    assert_true(img.steps > 0);
    assert_int_equal(rp.px.steps, img.steps);
    assert_int_equal(rp.px.outcome, img.outcome);
    assert_int_equal(rp.n, 8 * (long)img.steps);
    cr_raypath_free(&rp);
    cr_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_untraced_ray_has_its_path),
        cmocka_unit_test(test_traced_ray_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
