/* End-to-end: shipped scene files -> loader -> CPU backend -> pixels.
 *
 * Listing 7.1.1 (Schwarzschild, disc r = 6..15, observer r = 30) at 65x49
 * pixels, frame 8 of 18 (theta = 85 deg, figure 7.1.2):
 * - the centre pixel sees the horizon;
 * - both faces of the disc are visible: the top colour (0,255,0) and the
 *   bottom colour (255,0,255) (ERRATA item 3), the latter through lensing;
 * - no error or limit pixels;
 * - a = 0 is symmetric under phi -> -phi, so the image mirrored left-right has
 *   the same outcome and disc face at >= 99.5% of pixels, and every mismatch
 *   lies on an edge between outcomes (colours are not compared: the
 *   chessboard's sector parity flips under the mirror);
 * - redshift of disc pixels lies between the static values at r = 6 and
 *   r = 15: sqrt(1 - 2/r) / sqrt(1 - 2/30).
 * Listing 7.2.1 (a = 1) at the same frame is NOT mirror symmetric.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "cpu/render_cpu.h"
#include "io/scene.h"
#include "testutil.h"

#define W 65
#define H 49

static cr_pixel *render(const char *scene_file, int k, int n)
{
    char path[1024];
    cr_scene s;
    cr_err err;
    cr_frame f;
    cr_sphere sp[16];
    cr_trace_settings ts = {.integrator = CR_DEFAULT_INTEGRATOR,
                            .tolerance = CR_DEFAULT_TOLERANCE,
                            .step_multiplier = CR_DEFAULT_STEP_MULTIPLIER,
                            .horizon_epsilon = CR_DEFAULT_HORIZON_EPSILON,
                            .max_steps = CR_DEFAULT_MAX_STEPS,
                            .max_turns = CR_DEFAULT_MAX_TURNS};
    cr_pixel *px = calloc(W * H, sizeof *px);
    snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, scene_file);
    if (cr_scene_load(path, &s, &err))
        fail_msg("%s", err.msg);
    assert_true(s.n_spheres <= 16);
    if (cr_scene_frame(&s, k, n, W, H, &ts, &f, sp, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(cr_cpu_render(&f, 2, px, NULL, NULL, NULL, &err), 0);
    cr_scene_free(&s);
    return px;
}

static int is_edge(const cr_pixel *px, int i, int j)
{
    int di, dj;
    for (dj = -1; dj <= 1; dj++)
        for (di = -1; di <= 1; di++) {
            int a = i + di, b = j + dj;
            if (a < 0 || b < 0 || a >= W || b >= H)
                continue;
            if (px[b * W + a].outcome != px[j * W + i].outcome ||
                px[b * W + a].object != px[j * W + i].object)
                return 1;
        }
    return 0;
}

/* Fraction of pixels whose mirror image differs in outcome or disc face;
 * *off_edge counts mismatches that are not on an edge. */
static double mirror_mismatch(const cr_pixel *px, int *off_edge)
{
    int i, j, bad = 0;
    *off_edge = 0;
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            const cr_pixel *p = &px[j * W + i], *q = &px[j * W + (W - 1 - i)];
            if (p->outcome != q->outcome || p->object != q->object) {
                bad++;
                if (!is_edge(px, i, j))
                    (*off_edge)++;
            }
        }
    return (double)bad / (W * H);
}

static void test_schwarzschild_disc_listing(void **state)
{
    cr_pixel *px = render("listing-7.1.1-schwarzschild-disc.yml", 8, 18);
    const double z_in = sqrt(1.0 - 2.0 / 6.0) / sqrt(1.0 - 2.0 / 30.0),
                 z_out = sqrt(1.0 - 2.0 / 15.0) / sqrt(1.0 - 2.0 / 30.0);
    int i, top = 0, bottom = 0, off_edge, bad = 0;
    double mm, zmin = 1e9, zmax = -1e9;
    (void)state;
    assert_int_equal(px[(H / 2) * W + W / 2].outcome, CR_OUT_HORIZON);
    for (i = 0; i < W * H; i++) {
        cr_rgb c = px[i].color;
        top += c.r == 0 && c.g == 255 && c.b == 0;
        bottom += c.r == 255 && c.g == 0 && c.b == 255;
        bad += px[i].outcome == CR_OUT_ERROR || px[i].outcome == CR_OUT_LIMIT;
        if (px[i].outcome == CR_OUT_DISC) {
            zmin = fmin(zmin, px[i].redshift);
            zmax = fmax(zmax, px[i].redshift);
        }
    }
    mm = mirror_mismatch(px, &off_edge);
    print_message("top %d, bottom %d, error/limit %d pixels; mirror mismatch %.3f%% (%d off "
                  "edges); disc redshift %.5f..%.5f (static r=6..15: %.5f..%.5f)\n",
                  top, bottom, bad, 100.0 * mm, off_edge, zmin, zmax, z_in, z_out);
    assert_true(top > 50);
    assert_true(bottom > 5);
    assert_int_equal(bad, 0);
    assert_true(mm <= 0.005);
    assert_int_equal(off_edge, 0);
    assert_true(zmin >= z_in - 1e-9 && zmax <= z_out + 1e-9);
    assert_true(zmin < z_in + 0.02 && zmax > z_out - 0.02);
    free(px);
}

static void test_kerr_disc_is_not_mirror_symmetric(void **state)
{
    cr_pixel *px = render("listing-7.2.1-kerr-disc.yml", 8, 18);
    int off_edge;
    double mm = mirror_mismatch(px, &off_edge);
    (void)state;
    print_message("a = 1: mirror mismatch %.2f%% of pixels\n", 100.0 * mm);
    assert_true(mm > 0.02);
    free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_schwarzschild_disc_listing),
        cmocka_unit_test(test_kerr_disc_is_not_mirror_symmetric),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
