/* The images of curray orbit's lensed picture around a spinning hole
 * (core/lensing.h, output/orbit_picture.h), checked by an independent
 * integration: for points around a = 0.9 M seen by a finite static observer
 * (r = 60 M, theta = 70 deg), the image points found with the Mino
 * integrator (Dormand-Prince in Mino time, tolerance 1e-9) are traced again
 * with the paper's RK4 in the affine parameter (BL state, step multiplier
 * 1/64, a different integrator and state) and that ray must pass within
 * 1e-3 M of the point (measured: 5e-5 M at most); each point's direct and
 * secondary images are found and lie on opposite sides of the hole's
 * centre. Also P's BL direction from its Cartesian position (the inverse of
 * (2.2.8), cr_lens_bl_dir) to 1e-13 for random points and spins. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/lensing.h"
#include "input/scene.h"
#include "output/orbit_picture.h"

#define W 160
#define H 120
#define PATH_CAP 400000

static const char *scene_text = "metric: {m: 1, a: 0.9, q: 0}\n"
                                "observer: {r: 60, theta: 70, phi: 0, hfov: 36}\n"
                                "horizon_color: [0, 0, 0]\n";

/* The smallest distance from P to the polyline of the path's points. */
static double path_distance(const cr_path *p, const double P[3])
{
    double best = INFINITY;
    long k, n = p->n < p->cap ? p->n : p->cap;
    for (k = 1; k < n; k++) {
        const double *a = p->pts + (k - 1) * CR_PN + CR_P_X, *b = p->pts + k * CR_PN + CR_P_X;
        double d[3], e[3], dd = 0.0, de = 0.0, u, q = 0.0;
        int i;
        for (i = 0; i < 3; i++) {
            d[i] = b[i] - a[i];
            e[i] = P[i] - a[i];
            dd += d[i] * d[i];
            de += d[i] * e[i];
        }
        u = dd > 0.0 ? de / dd : 0.0;
        u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
        for (i = 0; i < 3; i++)
            q += (e[i] - u * d[i]) * (e[i] - u * d[i]);
        if (q < best)
            best = q;
    }
    return sqrt(best);
}

static void test_kerr_images_by_rk4(void **state)
{
    /* BL r, theta, phi of the points: in the equator in front, beside and
     * behind the hole, and off it */
    static const double pts[][3] = {{8.0, 90.0, 20.0},  {8.0, 90.0, 100.0}, {9.0, 90.0, 170.0},
                                    {10.0, 60.0, 250.0}, {7.0, 120.0, 300.0}, {12.0, 80.0, 200.0}};
    cr_scene sc;
    cr_frame_eval ev;
    cr_frame rk;
    cr_err err;
    cr_orbit_view v;
    cr_path path;
    double worst = 0.0;
    int n = (int)(sizeof pts / sizeof pts[0]), k, checked = 0;
    (void)state;
    memset(&ev, 0, sizeof ev);
    memset(&v, 0, sizeof v);
    v.given = 1;
    v.orders = 2;
    v.line_width = 1.0;
    if (cr_scene_load_string(scene_text, strlen(scene_text), "kerr.yml", &sc, &err) ||
        cr_frame_eval_at(&ev, &sc, 0, 1, W, H, NULL, &err))
        fail_msg("%s", err.msg);
    /* the independent check: RK4, its boundary beyond the points */
    rk = ev.frame;
    rk.integrator = CR_INTEG_RK4;
    rk.step_multiplier = 1.0 / 64.0;
    rk.max_steps = 2000000;
    cr_lens_frame(&rk, 20.0, 0, 1e-9, &rk);
    path.pts = malloc((size_t)PATH_CAP * CR_PN * sizeof *path.pts);
    assert_non_null(path.pts);
    path.cap = PATH_CAP;
    for (k = 0; k < n; k++) {
        cr_opic_point p;
        cr_opic_result r;
        double th = pts[k][1] * CR_PI / 180.0, ph = pts[k][2] * CR_PI / 180.0, side[2][2];
        int found[2] = {0, 0};
        long m;
        memset(&p, 0, sizeof p);
        cr_bl_to_cart(0.9, pts[k][0], th, ph, p.x);
        if (cr_opic_trace(&ev.frame, &p, 1, &v, &r, &err))
            fail_msg("%s", err.msg);
        for (m = 0; m < r.n; m++) {
            const cr_opic_image *q = &r.img[m];
            double d;
            path.sub = 1;
            cr_trace_point_path(&rk, q->i, q->j, &path);
            assert_true(path.n <= path.cap);
            d = path_distance(&path, p.x);
            print_message("point %d order %d at (%.3f, %.3f): RK4 ray passes %.2e M from it\n", k,
                          q->order, q->i, q->j, d);
            assert_true(d < 1e-3);
            if (d > worst)
                worst = d;
            found[q->order] = 1;
            side[q->order][0] = q->i - (W - 1) / 2.0;
            side[q->order][1] = q->j - (H - 1) / 2.0;
            checked++;
        }
        assert_true(found[0] && found[1]);
        /* on opposite sides of the hole's centre (it is at the picture's
           centre: the camera looks at it) */
        assert_true(side[0][0] * side[1][0] + side[0][1] * side[1][1] < 0.0);
        cr_opic_result_free(&r);
    }
    print_message("%d images, the RK4 rays within %.2e M of their points\n", checked, worst);
    free(path.pts);
    cr_frame_eval_free(&ev);
    cr_scene_free(&sc);
}

/* cr_lens_bl_dir inverts (2.2.8): the BL direction of random points. */
static void test_bl_direction(void **state)
{
    int k;
    unsigned s = 12345u;
    (void)state;
    for (k = 0; k < 1000; k++) {
        double r, th, ph, a, x[3], n[3];
        s = s * 1103515245u + 12345u;
        r = 1.5 + 30.0 * (s >> 8) / 16777216.0;
        s = s * 1103515245u + 12345u;
        th = CR_PI * (s >> 8) / 16777216.0;
        s = s * 1103515245u + 12345u;
        ph = CR_TWO_PI * (s >> 8) / 16777216.0;
        s = s * 1103515245u + 12345u;
        a = (s >> 8) / 16777216.0;
        cr_bl_to_cart(a, r, th, ph, x);
        cr_lens_bl_dir(a, x, n);
        assert_true(fabs(n[0] - sin(th) * cos(ph)) < 1e-13);
        assert_true(fabs(n[1] - sin(th) * sin(ph)) < 1e-13);
        assert_true(fabs(n[2] - cos(th)) < 1e-13);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bl_direction),
        cmocka_unit_test(test_kerr_images_by_rk4),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
