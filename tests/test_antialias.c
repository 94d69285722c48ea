/* Antialiasing (raytracer.samples): cr_trace_pixel with
 * f->samples = n traces n x n stratified sub-rays (sub-pixel centres at
 * ((a + 0.5) / n, (b + 0.5) / n) of the pixel) and averages their colours in
 * linear light; everything else comes from the sub-ray of
 * cr_subpixel_centre; steps is the sum over the sub-rays. Checked here:
 *  - samples 0 (unset), 1 and out of range give bit-identical pixels;
 *  - n = 3 on the edge of the shadow (horizon colour red, sky blue): the
 *    colour is the linear-light mix by the fraction of sub-rays that hit the
 *    horizon, counted here by tracing the sub-rays one by one through the
 *    camera functions; interior pixels keep their colour exactly; outcome,
 *    redshift and error monitor are the centre ray's;
 *  - the cost (steps) grows as n^2;
 *  - raytracer.samples in the system configuration: default 1, range 1..16. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "input/sysconfig.h"
#include "testutil.h"

#define AA_W 24

static void aa_frame(cr_frame *f, int samples)
{
    /* Schwarzschild, observer at r = 12 M: the shadow covers the middle of
     * the 90 deg view, with a sharp edge between horizon and sky */
    cr_test_empty_frame(f, 1.0, 0.0, 0.0, 12.0, 0.5 * CR_PI);
    f->width = f->height = AA_W;
    f->horizon_color.r = 255;
    f->horizon_color.g = f->horizon_color.b = 0;
    f->sky_color.r = f->sky_color.g = 0;
    f->sky_color.b = 255;
    cr_frame_prepare(f);
    f->samples = samples;
}

static int same_pixel(const cr_pixel *a, const cr_pixel *b)
{
    return a->outcome == b->outcome && a->object == b->object && a->steps == b->steps &&
           a->color.r == b->color.r && a->color.g == b->color.g && a->color.b == b->color.b &&
           !memcmp(&a->redshift, &b->redshift, sizeof a->redshift) &&
           !memcmp(&a->err_mean, &b->err_mean, sizeof a->err_mean) &&
           !memcmp(&a->err_std, &b->err_std, sizeof a->err_std);
}

static void test_one_sample_identical(void **state)
{
    cr_frame f0, f1, fbad;
    int i, j;
    (void)state;
    aa_frame(&f0, 0);
    aa_frame(&f1, 1);
    aa_frame(&fbad, CR_MAX_SAMPLES + 1);
    for (j = 0; j < AA_W; j += 3)
        for (i = 0; i < AA_W; i++) {
            cr_pixel a = cr_trace_pixel(&f0, i, j), b = cr_trace_pixel(&f1, i, j),
                     c = cr_trace_pixel(&fbad, i, j);
            assert_true(same_pixel(&a, &b));
            assert_true(same_pixel(&a, &c));
        }
}

/* The sub-ray (a, b) of pixel (i, j), traced by hand through the camera. */
static cr_pixel sub_ray(const cr_frame *f, int i, int j, int a, int b, int n)
{
    double dir[3], y[CR_NY];
    cr_geo g;
    double x = i + ((a + 0.5) / n - 0.5), yy = j + ((b + 0.5) / n - 0.5);
    cr_camera_pixel_dir(f, x, yy, dir);
    cr_camera_ray(f, dir, &g, y);
    return cr_trace_ray(f, &g, y);
}

static void test_edge_mix(void **state)
{
    cr_frame f1, f3;
    int i, j, a, b, edges = 0, inner = 0;
    const int n = 3;
    (void)state;
    aa_frame(&f1, 1);
    aa_frame(&f3, n);
    for (j = AA_W / 2 - 2; j <= AA_W / 2 + 1; j++)
        for (i = 0; i < AA_W; i++) {
            cr_pixel p = cr_trace_pixel(&f3, i, j), c = cr_trace_pixel(&f1, i, j);
            int hits = 0;
            unsigned long steps = 0;
            for (b = 0; b < n; b++)
                for (a = 0; a < n; a++) {
                    cr_pixel s = sub_ray(&f3, i, j, a, b, n);
                    assert_true(s.outcome == CR_OUT_HORIZON || s.outcome == CR_OUT_SKY);
                    hits += s.outcome == CR_OUT_HORIZON;
                    steps += s.steps;
                }
            /* the centre sub-ray is the samples = 1 ray */
            assert_int_equal(p.outcome, c.outcome);
            assert_int_equal(p.object, c.object);
            assert_memory_equal(&p.redshift, &c.redshift, sizeof p.redshift);
            assert_memory_equal(&p.err_mean, &c.err_mean, sizeof p.err_mean);
            assert_int_equal(p.steps, steps);
            assert_int_equal(p.color.g, 0);
            assert_int_equal(p.color.r, cr_unit_to_u8(cr_srgb_encode(hits / 9.0)));
            assert_int_equal(p.color.b, cr_unit_to_u8(cr_srgb_encode((9 - hits) / 9.0)));
            if (hits == 0 || hits == 9) {
                assert_int_equal(p.color.r, c.color.r);
                assert_int_equal(p.color.b, c.color.b);
                inner++;
            } else {
                /* strictly between, and brighter than a gamma-space mix */
                assert_true(p.color.r > 0 && p.color.r < 255);
                assert_true(p.color.b > 0 && p.color.b < 255);
                assert_true(p.color.r > (int)(255.0 * hits / 9.0 + 0.5) - 1);
                edges++;
            }
        }
    print_message("antialias: %d edge pixels mixed, %d interior pixels kept\n", edges, inner);
    assert_true(edges >= 4);
    assert_true(inner >= 4);
}

static void test_cost_n_squared(void **state)
{
    unsigned long long tot[4] = {0, 0, 0, 0};
    int n, i, j;
    (void)state;
    for (n = 1; n <= 3; n++) {
        cr_frame f;
        aa_frame(&f, n);
        for (j = 0; j < AA_W; j += 4)
            for (i = 0; i < AA_W; i += 2)
                tot[n] += cr_trace_pixel(&f, i, j).steps;
    }
    for (n = 2; n <= 3; n++) {
        double ratio = (double)tot[n] / (double)tot[1];
        print_message("antialias: steps N=%d / N=1 = %.3f (N^2 = %d)\n", n, ratio, n * n);
        assert_true(ratio > 0.85 * n * n && ratio < 1.15 * n * n);
    }
}

static void test_config_key(void **state)
{
    static const char *bad[] = {"raytracer: {samples: 0}\n", "raytracer: {samples: -1}\n",
                                "raytracer: {samples: 2.5}\n", "raytracer: {samples: abc}\n",
                                "raytracer: {samples: 17}\n"};
    cr_sysconfig c;
    cr_err err;
    size_t k;
    (void)state;
    assert_int_equal(cr_sysconfig_load_string("", 0, "c.yml", &c, &err), 0);
    assert_int_equal(c.raytracer.samples, 1);
    assert_int_equal(cr_sysconfig_load_string("raytracer: {samples: 1}\n", 24, "c.yml", &c, &err),
                     0);
    assert_int_equal(c.raytracer.samples, 1);
    assert_int_equal(cr_sysconfig_load_string("raytracer: {samples: 16}\n", 25, "c.yml", &c, &err),
                     0);
    assert_int_equal(c.raytracer.samples, 16);
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(cr_sysconfig_load_string(bad[k], strlen(bad[k]), "c.yml", &c, &err), -1);
        assert_non_null(strstr(err.msg, "c.yml:1:"));
        assert_non_null(strstr(err.msg, "raytracer.samples"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_sample_identical),
        cmocka_unit_test(test_edge_mix),
        cmocka_unit_test(test_cost_n_squared),
        cmocka_unit_test(test_config_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
