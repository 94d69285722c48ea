/* Keplerian disc (issue 12): the shift g of circular-orbit emitters seen by
 * the frame's observer, through the whole pipeline (scene -> frame ->
 * cr_trace_loop). Known answers:
 *  - face-on Schwarzschild ring seen from infinity: the photons have L = 0,
 *    so g = 1/u^t = sqrt(1 - 3M/r) exactly (to the located hit radius);
 *  - edge-on ring: the extremes of g are those of photons leaving along the
 *    orbit, g = sqrt(1 - 3M/r) / (1 -+ sqrt(M/(r - 2M))) (b = L/E = +-r /
 *    sqrt(1 - 2M/r), Omega b = sqrt(M/(r - 2M))); they bound g of every
 *    photon from that radius, and a thin ring [r, r + dr] seen at
 *    inclination 89.5 deg lies inside them and within 1.5 % of them;
 *  - the approaching side (image left: the disc turns counter-clockwise
 *    about +z, image right is toward increasing phi) has g > 1;
 *  - Mino and RK4 give the same g on the same disc pixels. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "io/scene.h"
#include "testutil.h"

static void frame_from(const char *text, int integ, int w, int h, cr_frame *f, cr_scene *s)
{
    cr_err err;
    cr_trace_settings ts = {.integrator = integ,
                            .tolerance = 1e-10,
                            .step_multiplier = CR_DEFAULT_STEP_MULTIPLIER / 4,
                            .horizon_epsilon = CR_DEFAULT_HORIZON_EPSILON,
                            .max_steps = CR_DEFAULT_MAX_STEPS,
                            .max_turns = CR_DEFAULT_MAX_TURNS};
    if (cr_scene_load_string(text, strlen(text), "kep.yml", s, &err))
        fail_msg("%s", err.msg);
    if (cr_scene_frame(s, 0, 1, w, h, &ts, f, NULL, &err))
        fail_msg("%s", err.msg);
}

/* The pixel at fractional image position (x, y) for an observer at infinity. */
static cr_pixel trace_at(const cr_frame *f, double x, double y)
{
    cr_ray ray;
    double alpha, beta;
    cr_camera_screen(f, x, y, &alpha, &beta);
    cr_mino_from_infinity(f, alpha, beta, &ray.c, ray.m);
    cr_ray_mino_start(f, &ray);
    return cr_trace_loop(f, &ray);
}

/* Face-on: bisect along the centre row for the inner edge of the direct
 * image, where the hit radius -> r_in; its g against sqrt(1 - 3/r_in). */
static void face_on_case(const char *radius, double r_in)
{
    char text[512];
    cr_frame f;
    cr_scene s;
    double lo = 0.0, hi = 0.0, x, want = sqrt(1.0 - 3.0 / r_in);
    int w = 201, h = 201, it;
    cr_pixel p;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: inf, theta: 0, phi: 0, hextent: 60}\n"
             "accretion: {model: keplerian, radius: %s}\n",
             radius);
    frame_from(text, CR_INTEG_MINO, w, h, &f, &s);
    /* centre column 100; the pixel scale is 60/201 M */
    /* from alpha = r_in + 3 (inside the direct image) inward in steps of
     * 0.05 M to the first ray that misses the disc: the inner edge */
    hi = 100.0 + (r_in + 3.0) / (60.0 / 201.0);
    assert_int_equal(trace_at(&f, hi, 100.0).outcome, CR_OUT_DISC);
    for (x = hi;; hi = x) {
        x = hi - 0.05 / (60.0 / 201.0);
        assert_true(x > 100.0);
        if (trace_at(&f, x, 100.0).outcome != CR_OUT_DISC)
            break;
    }
    lo = x;
    for (it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (trace_at(&f, mid, 100.0).outcome == CR_OUT_DISC)
            hi = mid;
        else
            lo = mid;
    }
    p = trace_at(&f, hi, 100.0);
    print_message("face-on r_in = %g: g = %.12f, sqrt(1-3/r) = %.12f, diff %.2e\n", r_in,
                  p.redshift, want, p.redshift - want);
    assert_int_equal(p.outcome, CR_OUT_DISC);
    assert_true(fabs(p.redshift - want) < 1e-6);
    cr_scene_free(&s);
}

static void test_face_on(void **state)
{
    (void)state;
    face_on_case("[30]", 6.0);    /* inner edge at the ISCO (6M) by default */
    face_on_case("[10, 30]", 10.0);
}

static void test_edge_on(void **state)
{
    const double r = 10.0, dr = 0.02;
    cr_frame f;
    cr_scene s;
    int w = 801, h = 41, i, j, imax = -1, imin = -1;
    double gmax = 0.0, gmin = 10.0;
    double sq = sqrt(1.0 / (r - 2.0)), g_blue = sqrt(1.0 - 3.0 / r) / (1.0 - sq),
           g_red = sqrt(1.0 - 3.0 / r) / (1.0 + sq);
    (void)state;
    frame_from("metric: {m: 1, a: 0, q: 0}\n"
               "observer: {r: inf, theta: 89.5, phi: 0, hextent: 30, vextent: 1.5}\n"
               "accretion: {model: keplerian, radius: [10, 10.02]}\n",
               CR_INTEG_MINO, w, h, &f, &s);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            cr_pixel p = cr_trace_pixel(&f, i, j);
            if (p.outcome != CR_OUT_DISC)
                continue;
            if (p.redshift > gmax) {
                gmax = p.redshift;
                imax = i;
            }
            if (p.redshift < gmin) {
                gmin = p.redshift;
                imin = i;
            }
        }
    print_message("edge-on r = %g (+%g), inclination 89.5 deg: g max %.6f at column %d "
                  "(formula %.6f), g min %.6f at column %d (formula %.6f)\n",
                  r, dr, gmax, imax, g_blue, gmin, imin, g_red);
    /* approaching side on the left and blueshifted */
    assert_true(imax >= 0 && imax < w / 2 && gmax > 1.0);
    assert_true(imin > w / 2 && gmin < 1.0);
    /* the formula is the extreme over every photon leaving the ring's
     * radius (|b| <= r / sqrt(1 - 2M/r), the tangential photon), so the
     * image's values lie inside it; a thin ring seen 0.5 deg off edge-on and
     * sampled at 30/801 M a pixel gets within 1.5 % of it (measured 1.1 %
     * blue, 0.6 % red) */
    assert_true(gmax < g_blue && gmax > g_blue * (1.0 - 1.5e-2));
    assert_true(gmin > g_red && gmin < g_red * (1.0 + 1.5e-2));
    cr_scene_free(&s);
}

/* A static observer at finite distance on the axis (theta = 0): every ray
 * has L = 0, so g = u^t_obs / u^t_em = sqrt(1 - 3M/r) / sqrt(1 - 2M/r_o) for
 * Schwarzschild, at every disc pixel, with r its hit radius (hit_r). Checks
 * the observer's side of g (its 4-velocity), which the observer at infinity
 * cannot see. */
static void test_static_observer_on_axis(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: 50, theta: 0, phi: 0, hfov: 40}\n"
                               "accretion: {model: keplerian, radius: [6, 20]}\n";
    enum { W = 33, H = 33 };
    int integ, i, j, n = 0;
    double worst = 0.0;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        cr_scene s;
        cr_frame f;
        frame_from(text, integ ? CR_INTEG_RK4 : CR_INTEG_MINO, W, H, &f, &s);
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                cr_pixel p = cr_trace_pixel(&f, i, j);
                double want;
                if (p.outcome != CR_OUT_DISC)
                    continue;
                want = sqrt(1.0 - 3.0 / p.hit_r) / sqrt(1.0 - 2.0 / 50.0);
                worst = fmax(worst, fabs(p.redshift - want));
                n++;
            }
        cr_scene_free(&s);
    }
    print_message("static observer on the axis at r = 50: %d disc pixels, worst |g - "
                  "sqrt(1-3/r)/sqrt(1-2/50)| = %.2e (tol 1e-9)\n",
                  n, worst);
    assert_true(n > 100);
    assert_true(worst < 1e-9);
}

static void test_integrators_agree(void **state)
{
    const char *text = "metric: {m: 1, a: 0.6, q: 0.2}\n"
                       "observer: {r: 60, theta: 80, phi: 0, hfov: 30}\n"
                       "accretion: {model: keplerian, radius: [4, 15], temperature: 6000}\n";
    cr_frame fm, fr;
    cr_scene sm, sr;
    int w = 48, h = 24, i, j, n = 0, blue = 0;
    double worst = 0.0;
    (void)state;
    frame_from(text, CR_INTEG_MINO, w, h, &fm, &sm);
    frame_from(text, CR_INTEG_RK4, w, h, &fr, &sr);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            cr_pixel a = cr_trace_pixel(&fm, i, j), b = cr_trace_pixel(&fr, i, j);
            if (a.outcome != CR_OUT_DISC || b.outcome != CR_OUT_DISC)
                continue;
            n++;
            blue += a.redshift > 1.0;
            if (fabs(a.redshift - b.redshift) > worst)
                worst = fabs(a.redshift - b.redshift);
        }
    print_message("mino vs rk4: %d disc pixels, worst |dg| %.3g, %d with g > 1\n", n, worst,
                  blue);
    assert_true(n > 50 && blue > 0);
    assert_true(worst < 1e-5);
    cr_scene_free(&sm);
    cr_scene_free(&sr);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_face_on),
        cmocka_unit_test(test_edge_on),
        cmocka_unit_test(test_integrators_agree),
        cmocka_unit_test(test_static_observer_on_axis),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
