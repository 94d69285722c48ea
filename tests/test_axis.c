/* No error pixels: the polar axis, extreme spins and observers in awkward
 * places (ERRATA items 2 and 4).
 *
 * - Figure 8.1.1 (31x31, a = 0, observer in the equatorial plane, the centre
 *   column aims over the poles): zero error pixels, the outcome map is mirror
 *   symmetric left-right and up-down, and no seam: every centre-column pixel
 *   has the outcome of its left and right neighbours except on outcome edges,
 *   and its step count and mean null error are within 10% and 10x of theirs.
 * - A sweep of the observer's theta over 0..180 deg (both poles included) for
 *   a in {0, 0.5, 0.998, 1} and Q in {0, 0.5} where a horizon exists, plus
 *   a^2 + Q^2 = 0.999 M^2, with a disc: zero error and zero limit pixels, and
 *   no ray above 20000 steps.
 * - Observer on the axis (theta = 0 and 180 deg), a = 0 and Q in {0, 0.6}:
 *   the image equals itself rotated by 90 deg about its centre, outcome and
 *   colour, pixel for pixel, except at most 0.5% of pixels that all lie on
 *   edges between outcomes or chessboard squares (pixels whose ray lands
 *   on a sector boundary within rounding); for a = 0.9 the outcome map is
 *   rotation symmetric to the same tolerance.
 * - Limits: a ray launched just outside the Schwarzschild shadow edge orbits
 *   the photon sphere; with raytracer.max_turns = 1 it ends as "limit" (horizon
 *   colour, no redshift) instead of escaping, and with max_steps = 300 every
 *   long ray of a frame ends as "limit" after exactly 300 steps.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "render/cpu.h"
#include "input/scene.h"
#include "testutil.h"

static void render_frame(cr_frame *f, cr_pixel *px)
{
    cr_err err;
    cr_frame_prepare(f);
    if (cr_cpu_render(f, 2, px, NULL, NULL, NULL, &err))
        fail_msg("%s", err.msg);
}

static int differs(const cr_pixel *a, const cr_pixel *b, int colour)
{
    return a->outcome != b->outcome || a->object != b->object ||
           (colour && (a->color.r != b->color.r || a->color.g != b->color.g ||
                       a->color.b != b->color.b));
}

/* Whether pixel (i, j) borders a pixel of another outcome (or colour). */
static int on_edge(const cr_pixel *px, int w, int h, int i, int j, int colour)
{
    int di, dj;
    for (dj = -1; dj <= 1; dj++)
        for (di = -1; di <= 1; di++) {
            int a = i + di, b = j + dj;
            if (a >= 0 && b >= 0 && a < w && b < h &&
                differs(&px[b * w + a], &px[j * w + i], colour))
                return 1;
        }
    return 0;
}

/* Under RK4 the step count of the centre column must match its neighbours
 * (the axis term of the step rule); under Mino the step count follows the
 * ray's impact parameter, which changes fast at the image centre, so there
 * the check is on the error monitor only. */
static void figure_8_1_1(int integrator)
{
    enum { N = 31 };
    char path[1024];
    cr_scene s;
    cr_err err;
    cr_frame f;
    cr_pixel px[N * N];
    int i, j, errors = 0, asym = 0, seam = 0;
    snprintf(path, sizeof path, "%s/scenes/fig-8.1.1-axis.yml", CR_SOURCE_DIR);
    if (cr_scene_load(path, &s, &err) || cr_scene_frame(&s, 0, 1, N, N, NULL, &f, NULL, &err))
        fail_msg("%s", err.msg);
    f.integrator = integrator;
    render_frame(&f, px);
    for (j = 0; j < N; j++)
        for (i = 0; i < N; i++) {
            const cr_pixel *p = &px[j * N + i];
            errors += p->outcome == CR_OUT_ERROR || p->outcome == CR_OUT_LIMIT;
            asym += p->outcome != px[j * N + (N - 1 - i)].outcome;
            asym += p->outcome != px[(N - 1 - j) * N + i].outcome;
        }
    for (j = 0; j < N; j++) {
        const cr_pixel *c = &px[j * N + N / 2], *l = c - 1, *r = c + 1;
        double st = 0.5 * (l->steps + r->steps), em = fmax(l->err_mean, r->err_mean);
        int bad_steps = integrator == CR_INTEG_RK4 && fabs(c->steps - st) > 0.1 * st;
        double floor = integrator == CR_INTEG_RK4 ? 1e-12 : f.tolerance;
        if ((differs(c, l, 0) || differs(c, r, 0)) && !on_edge(px, N, N, N / 2, j, 0))
            seam++;
        if (c->outcome == l->outcome && c->outcome == r->outcome &&
            (bad_steps || c->err_mean > 10.0 * em + floor)) {
            print_message("row %d: centre %u steps, error monitor %.3g; neighbours %u/%u, %.3g\n",
                          j, c->steps, c->err_mean, l->steps, r->steps, em);
            seam++;
        }
    }
    print_message("figure 8.1.1 (%s): %d error pixels, %d asymmetric, %d seam pixels; centre "
                  "pixel %s\n",
                  integrator == CR_INTEG_RK4 ? "rk4" : "mino", errors, asym, seam,
                  px[(N / 2) * N + N / 2].outcome == CR_OUT_HORIZON ? "horizon" : "?");
    assert_int_equal(errors, 0);
    assert_int_equal(asym, 0);
    assert_int_equal(seam, 0);
    cr_scene_free(&s);
}

static void test_figure_8_1_1(void **state)
{
    (void)state;
    figure_8_1_1(CR_INTEG_MINO);
    figure_8_1_1(CR_INTEG_RK4);
}

static void disc_frame(cr_frame *f, double a, double q, double th_deg, int w, int h, int sectors)
{
    cr_test_empty_frame(f, 1.0, a, q, 30.0, th_deg * CR_PI / 180.0);
    f->width = w;
    f->height = h;
    f->observer.hfov = 70.0 * CR_PI / 180.0;
    f->observer.vfov = 2.0 * atan(tan(35.0 * CR_PI / 180.0) * h / w);
    f->disc.enabled = 1;
    f->disc.r_in = 6.0;
    f->disc.r_out = 15.0;
    f->disc.n_radial = 2;
    f->disc.n_sectors = sectors;
    f->disc.color1 = cr_rgb_make(0, 255, 0);
    f->disc.color2 = cr_rgb_make(255, 0, 255);
    f->sky_color = cr_rgb_make(255, 255, 255);
}

static void test_theta_sweep_no_error_pixels(void **state)
{
    const double ths[] = {0, 1, 5, 30, 60, 89, 90, 91, 120, 150, 175, 179, 180};
    const double cases[][2] = {{0, 0}, {0, 0.5}, {0.5, 0}, {0.5, 0.5}, {0.998, 0}, {1.0, 0},
                               {0.9, 0.434741302}}; /* last: a^2 + Q^2 = 0.999 */
    enum { W = 24, H = 18 };
    cr_pixel px[W * H];
    int ic, it, i, frames = 0;
    unsigned worst = 0;
    (void)state;
    for (ic = 0; ic < 7; ic++)
        for (it = 0; it < 13; it++) {
            cr_frame f;
            int bad = 0;
            disc_frame(&f, cases[ic][0], cases[ic][1], ths[it], W, H, 12);
            render_frame(&f, px);
            for (i = 0; i < W * H; i++) {
                bad += px[i].outcome == CR_OUT_ERROR || px[i].outcome == CR_OUT_LIMIT ||
                       px[i].outcome == CR_OUT_NONE;
                if (px[i].steps > worst)
                    worst = px[i].steps;
            }
            if (bad)
                fail_msg("a=%g Q=%g theta=%g deg: %d error/limit pixels", cases[ic][0],
                         cases[ic][1], ths[it], bad);
            frames++;
        }
    print_message("%d frames, no error or limit pixels; most steps on one ray: %u\n", frames,
                  worst);
    assert_true(worst < 20000);
}

/* Compare the image with itself rotated by 90 deg; returns mismatches and
 * counts those off edges. */
static int rotation_mismatch(const cr_pixel *px, int n, int colour, int *off_edge)
{
    int i, j, bad = 0;
    *off_edge = 0;
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++)
            if (differs(&px[j * n + i], &px[(n - 1 - i) * n + j], colour)) {
                bad++;
                if (!on_edge(px, n, n, i, j, colour))
                    (*off_edge)++;
            }
    return bad;
}

static void test_observer_on_axis_rotation_symmetric(void **state)
{
    enum { N = 41 };
    const double cases[][3] = {{0, 0, 0}, {0, 0, 180}, {0, 0.6, 0}, {0, 0.6, 180}, {0.9, 0, 0},
                               {0.9, 0, 180}};
    cr_pixel px[N * N];
    int ic, i;
    (void)state;
    for (ic = 0; ic < 6; ic++) {
        cr_frame f;
        int off, bad, errors = 0, disc = 0, colour = cases[ic][0] == 0.0;
        disc_frame(&f, cases[ic][0], cases[ic][1], cases[ic][2], N, N, 8);
        render_frame(&f, px);
        for (i = 0; i < N * N; i++) {
            errors += px[i].outcome == CR_OUT_ERROR || px[i].outcome == CR_OUT_LIMIT;
            disc += px[i].outcome == CR_OUT_DISC;
        }
        bad = rotation_mismatch(px, N, colour, &off);
        print_message("a=%g Q=%g theta=%g: %d disc pixels, %d of %d differ from the 90 deg "
                      "rotation (%s compared), %d off edges\n",
                      cases[ic][0], cases[ic][1], cases[ic][2], disc, bad, N * N,
                      colour ? "outcome and colour" : "outcome", off);
        assert_int_equal(errors, 0);
        assert_true(disc > 100);
        assert_true(bad <= 0.005 * N * N);
        assert_int_equal(off, 0);
        assert_int_equal(px[(N / 2) * N + N / 2].outcome, CR_OUT_HORIZON);
    }
}

static void test_step_and_turn_limits(void **state)
{
    cr_frame f;
    cr_pixel px[16 * 16];
    double ro = 30.0, bc = sqrt(27.0), psi = asin(bc / ro * sqrt(1.0 - 2.0 / ro)) + 1e-9;
    double n[3], y[CR_NY];
    cr_geo g;
    cr_pixel p;
    int i, limited = 0;
    (void)state;
    cr_test_empty_frame(&f, 1.0, 0.0, 0.0, ro, 0.5 * CR_PI);
    n[0] = -cos(psi);
    n[1] = 0.0;
    n[2] = sin(psi);
    cr_camera_ray(&f, n, &g, y);
    p = cr_trace_ray(&f, &g, y);
    print_message("near-critical ray, default limits: %d after %u steps\n", p.outcome, p.steps);
    assert_int_equal(p.outcome, CR_OUT_SKY);
    f.max_turns = 1.0;
    cr_camera_ray(&f, n, &g, y);
    p = cr_trace_ray(&f, &g, y);
    print_message("with max_turns = 1: %d after %u steps\n", p.outcome, p.steps);
    assert_int_equal(p.outcome, CR_OUT_LIMIT);
    assert_true(p.redshift == -1.0);
    assert_true(p.color.r == f.limit_color.r && p.color.g == f.limit_color.g &&
                p.color.b == f.limit_color.b);
    assert_false(p.color.r == f.horizon_color.r && p.color.g == f.horizon_color.g &&
                 p.color.b == f.horizon_color.b);

    /* a step limit below what most rays need: 300 under RK4, 8 under Mino */
    for (i = 0; i < 2; i++) {
        int integ = i ? CR_INTEG_RK4 : CR_INTEG_MINO, k;
        unsigned lim = i ? 300 : 8;
        disc_frame(&f, 0.5, 0.0, 60.0, 16, 16, 12);
        f.integrator = integ;
        f.max_steps = lim;
        render_frame(&f, px);
        limited = 0;
        for (k = 0; k < 16 * 16; k++) {
            assert_true(px[k].steps <= lim);
            if (px[k].outcome == CR_OUT_LIMIT) {
                assert_int_equal(px[k].steps, lim);
                limited++;
            }
        }
        print_message("%s, max_steps = %u: %d of 256 rays ended as limit\n", i ? "rk4" : "mino",
                      lim, limited);
        assert_true(limited > 100);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_figure_8_1_1),
        cmocka_unit_test(test_theta_sweep_no_error_pixels),
        cmocka_unit_test(test_observer_on_axis_rotation_symmetric),
        cmocka_unit_test(test_step_and_turn_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
