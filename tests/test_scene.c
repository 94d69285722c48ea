/* Scene files (appendix E.4) and their evaluation per frame.
 *
 * - every key and its default, the angle units, animations at the first,
 *   middle and last frame and for a single frame;
 * - repeated `sphere:` sections and `spheres:` lists kept in file order, with
 *   no small cap (ERRATA item 5);
 * - the second disc colour by (E.4.2) with ERRATA item 3; the vfov (E.4.1);
 * - the listings of chapter 7 (line numbers removed, wraps kept) load and
 *   evaluate;
 * - every error path: the message names the file, line:col and key path;
 * - cr_scene_frame rejects impossible values (ERRATA item 4) and accepts the
 *   extremal hole and an observer on the polar axis;
 * - a sky image is loaded relative to the scene file's folder; a skymap
 *   without a boundary (or with boundary: inf) has its sky at infinity;
 * - the observer at infinity (r: inf): its spellings, hextent/vextent, the
 *   keys that apply only to one kind of observer, pitch = yaw = 0, the rk4
 *   integrator refused, no horizon named by metric.a / metric.q;
 * - the raytracer settings (integrator, tolerance) are checked and copied.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "core/trace.h"
#include "base/png_io.h"
#include "input/scene.h"

#define DATA CR_SOURCE_DIR "/tests/data/"
#define TMP CR_BINARY_DIR "/tests/test_scene_tmp"
#define NAME "scene.yml"
#define DEG (CR_PI / 180.0)
#define MAX_SPHERES 64

#define assert_contains(hay, needle)                                                            \
    do {                                                                                        \
        if (!strstr((hay), (needle)))                                                           \
            fail_msg("message \"%s\"\n  does not contain \"%s\"", (hay), (needle));             \
    } while (0)

#define assert_starts(hay, prefix)                                                              \
    do {                                                                                        \
        if (strncmp((hay), (prefix), strlen(prefix)) != 0)                                      \
            fail_msg("message \"%s\"\n  does not start with \"%s\"", (hay), (prefix));          \
    } while (0)

#define assert_near(a, b, tol)                                                                  \
    do {                                                                                        \
        double a_ = (a), b_ = (b);                                                              \
        if (!(fabs(a_ - b_) <= (tol)))                                                          \
            fail_msg("%s = %.17g, expected %.17g (tol %g)", #a, a_, b_, (double)(tol));        \
    } while (0)

static const char *MIN = "metric: {m: 1, a: 0, q: 0}\n"
                         "observer: {r: 30, theta: 90, phi: 0, hfov: 70}\n";

/* Block-style base used by the error cases: metric lines 1-4, observer 5-9,
 * so a key appended after it starts on line 10. */
#define OBSL "observer: {r: 30, theta: 90, phi: 0, hfov: 70}\n"
/* A metric section with m given, then an observer: m's value is on line 2
 * from column 6. */
#define MET(m) "metric:\n  m: " m "\n  a: 0\n  q: 0\n" OBSL
/* The observer keys but theta, after an observer's theta on line 3. */
#define OBS_REST "  r: 30\n  phi: 0\n  hfov: 70\n"

#define BASE                                                                                    \
    "metric:\n  m: 1\n  a: 0\n  q: 0\n"                                                          \
    "observer:\n  r: 30\n  theta: 90\n  phi: 0\n  hfov: 70\n"

static int load(const char *text, cr_scene *s, cr_err *e)
{
    e->msg[0] = '\0';
    return cr_scene_load_string(text, strlen(text), NAME, s, e);
}

static void load_ok(const char *text, cr_scene *s)
{
    cr_err e;
    if (load(text, s, &e) != 0)
        fail_msg("load failed: %s\n--- text:\n%s", e.msg, text);
}

/* Evaluate a loaded scene's frame k of n at 64 x 48; fails the test with the
 * message on error. */
static void frame_ok(const cr_scene *s, int k, int n, cr_frame *f, cr_sphere *buf)
{
    cr_err e;
    e.msg[0] = '\0';
    if (cr_scene_frame(s, k, n, 64, 48, NULL, f, buf, &e) != 0)
        fail_msg("frame %d of %d failed: %s", k, n, e.msg);
}

/* ---- keys and defaults ---------------------------------------------------- */

static void test_minimal_defaults(void **state)
{
    cr_scene s;
    (void)state;
    load_ok(MIN, &s);
    assert_string_equal(s.path, NAME);
    assert_true(s.m.a == 1.0 && s.m.b == 1.0);
    assert_true(s.a.a == 0.0 && s.q.a == 0.0);
    assert_true(s.obs_r.a == 30.0 && s.obs_r.b == 30.0);
    assert_near(s.obs_theta.a, 0.5 * CR_PI, 0.0);
    assert_true(s.obs_phi.a == 0.0);
    assert_true(s.roll.a == 0.0 && s.roll.b == 0.0);
    assert_true(s.pitch.a == 0.0 && s.yaw.a == 0.0);
    assert_near(s.hfov.a, 70.0 * DEG, 1e-15);
    assert_int_equal(s.has_vfov, 0);
    assert_int_equal(s.obs_at_infinity, 0);
    assert_int_equal(s.has_vextent, 0);
    assert_int_equal(s.has_disc, 0);
    assert_int_equal(s.has_sky, 0);
    assert_null(s.sky_image);
    assert_null(s.sky_rgb);
    assert_int_equal(s.n_spheres, 0);
    assert_null(s.spheres);
    assert_true(s.sky_color.r == 0 && s.sky_color.g == 0 && s.sky_color.b == 0);
    assert_true(s.horizon_color.r == 255 && s.horizon_color.g == 0 && s.horizon_color.b == 0);
    assert_true(s.error_color.r == 0 && s.error_color.g == 0 && s.error_color.b == 255);
    assert_int_equal(s.redshift_sky, 0); /* the paper's black sky in r_<k>.png */
    cr_scene_free(&s);
    cr_scene_free(&s); /* freeing twice is harmless */
    load_ok(BASE "redshift_sky: true\n", &s);
    assert_int_equal(s.redshift_sky, 1);
    cr_scene_free(&s);
}

static void test_full_scene_file(void **state)
{
    cr_scene s;
    cr_err e;
    const cr_scene_sphere *sp;
    (void)state;
    if (cr_scene_load(DATA "scene_full.yml", &s, &e))
        fail_msg("%s", e.msg);
    assert_string_equal(s.path, DATA "scene_full.yml");
    assert_true(s.m.a == 1.0);
    assert_true(s.a.a == 0.0 && s.a.b == 0.5);
    assert_true(s.q.a == 0.25 && s.q.b == 0.25);
    assert_true(s.obs_r.a == 30.0);
    assert_near(s.obs_theta.a, 0.5 * CR_PI, 1e-15);
    assert_near(s.obs_phi.a, CR_PI, 1e-15);
    assert_near(s.roll.a, 10.0 * DEG, 1e-15);
    assert_near(s.pitch.a, 5.0 * DEG, 1e-15);
    assert_near(s.yaw.a, -0.1, 1e-15);
    assert_near(s.hfov.a, 70.0 * DEG, 1e-15);
    assert_int_equal(s.has_vfov, 1);
    assert_near(s.vfov.a, 50.0 * DEG, 1e-15);

    assert_int_equal(s.has_disc, 1);
    assert_true(s.disc_color1.r == 0 && s.disc_color1.g == 255 && s.disc_color1.b == 0);
    assert_true(s.disc_color2.r == 255 && s.disc_color2.g == 0 && s.disc_color2.b == 255);
    assert_int_equal(s.disc_n_radial, 2);
    assert_int_equal(s.disc_n_sectors, 12);
    assert_true(s.disc_yaw.a == 0.0);
    assert_near(s.disc_yaw.b, 2.0 * CR_PI, 1e-15);
    assert_true(s.disc_r_in.a == 2.0 && s.disc_r_in.b == 6.0);
    assert_true(s.disc_r_out.a == 15.0 && s.disc_r_out.b == 15.0);

    assert_int_equal(s.n_spheres, 2);
    sp = &s.spheres[0];
    assert_true(sp->color.r == 255 && sp->color.g == 255 && sp->color.b == 0);
    assert_int_equal(sp->n_lat, 4);
    assert_int_equal(sp->n_lon, 8);
    assert_true(sp->r.a == 10.0);
    assert_near(sp->theta.a, 0.5 * CR_PI, 1e-15);
    assert_true(sp->phi.a == 0.0);
    assert_near(sp->phi.b, 2.0 * CR_PI, 1e-15);
    assert_near(sp->roll.a, 1.0 * DEG, 1e-15);
    assert_near(sp->pitch.a, 2.0 * DEG, 1e-15);
    assert_near(sp->yaw.a, 3.0 * DEG, 1e-15);
    assert_true(sp->radius.a == 3.0);
    assert_int_equal(sp->line, 29);
    sp = &s.spheres[1];
    assert_true(sp->color.r == 1 && sp->color.g == 2 && sp->color.b == 3);
    assert_int_equal(sp->n_lat, 5);
    assert_int_equal(sp->n_lon, 9);
    assert_true(sp->roll.a == 0.0 && sp->pitch.a == 0.0 && sp->yaw.a == 0.0);
    assert_true(sp->radius.a == 1.5);
    assert_int_equal(sp->line, 43);

    assert_true(s.sky_color.r == 0 && s.sky_color.g == 0 && s.sky_color.b == 1);
    assert_true(s.horizon_color.r == 0 && s.horizon_color.g == 0 && s.horizon_color.b == 0);
    assert_true(s.error_color.r == 0 && s.error_color.g == 0 && s.error_color.b == 255);
    cr_scene_free(&s);
}

static void test_angle_units(void **state)
{
    static const struct {
        const char *text;
        double rad;
    } cases[] = {
        {"90", 0.5 * CR_PI},
        {"90 deg", 0.5 * CR_PI},
        {"1.570796 rad", 1.570796},
        {"0.5 pi", 0.5 * CR_PI},
        {"\"90 deg\"", 0.5 * CR_PI},
        {"'0.5 pi'", 0.5 * CR_PI},
        {"90deg", 0.5 * CR_PI},
        {"90 DEG", 0.5 * CR_PI},
        {"180", CR_PI},
        {"1 pi", CR_PI},
        {"0", 0.0},
        {"45.5", 45.5 * DEG},
        {"+30", 30.0 * DEG},
        {"1e1", 10.0 * DEG},
        {"2.5E-1 pi", 0.25 * CR_PI},
        {".5 rad", 0.5},
        {"1. rad", 1.0},
        {"-45", -45.0 * DEG},
        {"-0.25 pi", -0.25 * CR_PI},
        {" 90 deg ", 0.5 * CR_PI},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[256];
        cr_scene s;
        snprintf(text, sizeof text,
                 "metric: {m: 1, a: 0, q: 0}\n"
                 "observer: {r: 30, theta: %s, phi: [linear, 0, %s], hfov: 70}\n",
                 cases[i].text, cases[i].text);
        load_ok(text, &s);
        assert_near(s.obs_theta.a, cases[i].rad, 1e-15);
        assert_near(s.obs_theta.b, cases[i].rad, 1e-15);
        assert_near(s.obs_phi.a, 0.0, 0.0);
        assert_near(s.obs_phi.b, cases[i].rad, 1e-15);
        cr_scene_free(&s);
    }
}

static void test_color2_default(void **state)
{
    cr_scene s;
    (void)state;
    load_ok(BASE "accretion: {color1: [10, 20, 30], resolution: [2, 12], radius: [6, 15]}\n",
            &s);
    assert_int_equal(s.has_disc, 1);
    /* (E.4.2) with ERRATA item 3: B2 = 255 - B1, not 255 - G1 */
    assert_int_equal(s.disc_color2.r, 245);
    assert_int_equal(s.disc_color2.g, 235);
    assert_int_equal(s.disc_color2.b, 225);
    assert_true(s.disc_yaw.a == 0.0 && s.disc_yaw.b == 0.0);
    cr_scene_free(&s);
}

static void test_animation(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_sphere buf[MAX_SPHERES];
    (void)state;
    load_ok("metric: {m: 1, a: [linear, 0, 0.9], q: 0}\n"
            "observer: {r: [linear, 40, 20], theta: [linear, 5, 175], phi: [linear, 0, 2 pi],\n"
            "           hfov: 70}\n"
            "accretion: {color1: [0, 255, 0], resolution: [2, 12], yaw: [linear, 0, 1 rad],\n"
            "            radius: [[linear, 2, 6], [linear, 15, 19]]}\n"
            "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90,\n"
            "         phi: [linear, 0, 360], radius: [linear, 1, 3]}\n",
            &s);
    /* cr_anim_at itself */
    assert_near(cr_anim_at(s.obs_theta, 0, 5), 5.0 * DEG, 1e-15);
    assert_near(cr_anim_at(s.obs_theta, 2, 5), 90.0 * DEG, 1e-15);
    assert_near(cr_anim_at(s.obs_theta, 4, 5), 175.0 * DEG, 1e-15);
    assert_near(cr_anim_at(s.obs_theta, 0, 1), 5.0 * DEG, 1e-15);

    /* first frame */
    frame_ok(&s, 0, 5, &f, buf);
    assert_true(f.metric.a == 0.0);
    assert_true(f.observer.r == 40.0);
    assert_near(f.observer.theta, 5.0 * DEG, 1e-15);
    assert_true(f.observer.phi == 0.0);
    assert_true(f.disc.r_in == 2.0 && f.disc.r_out == 15.0 && f.disc.yaw == 0.0);
    assert_true(f.spheres[0].radius == 1.0);
    /* middle frame */
    frame_ok(&s, 2, 5, &f, buf);
    assert_near(f.metric.a, 0.45, 1e-15);
    assert_near(f.observer.r, 30.0, 1e-13);
    assert_near(f.observer.theta, 90.0 * DEG, 1e-15);
    assert_near(f.observer.phi, CR_PI, 1e-15);
    assert_near(f.disc.r_in, 4.0, 1e-15);
    assert_near(f.disc.r_out, 17.0, 1e-15);
    assert_near(f.disc.yaw, 0.5, 1e-15);
    assert_near(f.spheres[0].phi, CR_PI, 1e-15);
    assert_near(f.spheres[0].radius, 2.0, 1e-15);
    /* last frame */
    frame_ok(&s, 4, 5, &f, buf);
    assert_near(f.metric.a, 0.9, 1e-15);
    assert_near(f.observer.r, 20.0, 1e-13);
    assert_near(f.observer.theta, 175.0 * DEG, 1e-14);
    assert_near(f.observer.phi, 2.0 * CR_PI, 1e-15);
    assert_near(f.disc.r_in, 6.0, 1e-15);
    assert_near(f.disc.r_out, 19.0, 1e-15);
    assert_near(f.disc.yaw, 1.0, 1e-15);
    assert_near(f.spheres[0].radius, 3.0, 1e-15);
    /* a single frame takes the start values */
    frame_ok(&s, 0, 1, &f, buf);
    assert_true(f.observer.r == 40.0);
    assert_near(f.observer.theta, 5.0 * DEG, 1e-15);
    assert_true(f.disc.r_in == 2.0);
    cr_scene_free(&s);
}

/* ---- spheres -------------------------------------------------------------- */

static void test_repeated_spheres(void **state)
{
    char text[8192];
    size_t o;
    int i;
    cr_scene s;
    cr_frame f;
    cr_sphere buf[MAX_SPHERES];
    (void)state;
    o = (size_t)snprintf(text, sizeof text, "%s", MIN); /* lines 1-2 */
    /* 5 `sphere:` sections, a `spheres:` list of 2, then 5 more sections:
     * 12 spheres, radius = 1 + position in file order */
    for (i = 0; i < 12; i++) {
        if (i == 5) {
            o += (size_t)snprintf(text + o, sizeof text - o, "spheres:\n");
        }
        if (i == 5 || i == 6) {
            o += (size_t)snprintf(text + o, sizeof text - o,
                                  "  - color: [%d, 0, 0]\n    resolution: [4, 8]\n"
                                  "    r: 10\n    theta: 90\n    phi: %d\n    radius: %d\n",
                                  i, 10 * i, 1 + i);
        } else {
            o += (size_t)snprintf(text + o, sizeof text - o,
                                  "sphere:\n  color: [%d, 0, 0]\n  resolution: [4, 8]\n"
                                  "  r: 10\n  theta: 90\n  phi: %d\n  radius: %d\n",
                                  i, 10 * i, 1 + i);
        }
    }
    load_ok(text, &s);
    assert_int_equal(s.n_spheres, 12);
    for (i = 0; i < 12; i++) {
        assert_int_equal(s.spheres[i].color.r, i);
        assert_true(s.spheres[i].radius.a == 1.0 + i);
        assert_near(s.spheres[i].phi.a, 10.0 * i * DEG, 1e-15);
    }
    assert_int_equal(s.spheres[0].line, 3);
    assert_int_equal(s.spheres[1].line, 10);
    assert_int_equal(s.spheres[5].line, 39); /* first list item */
    assert_int_equal(s.spheres[6].line, 45);
    assert_int_equal(s.spheres[7].line, 51);
    frame_ok(&s, 0, 1, &f, buf);
    assert_int_equal(f.n_spheres, 12);
    assert_ptr_equal(f.spheres, buf);
    for (i = 0; i < 12; i++) {
        double c2 = buf[i].center[0] * buf[i].center[0] + buf[i].center[1] * buf[i].center[1] +
                    buf[i].center[2] * buf[i].center[2];
        assert_true(buf[i].radius == 1.0 + i);
        assert_near(c2, 100.0, 1e-12); /* prepared: centre at r = 10, a = 0 */
    }
    cr_scene_free(&s);
}

static void test_many_spheres(void **state)
{
    /* no small cap (ERRATA item 5) */
    const int n = 1000;
    size_t cap = (size_t)n * 128 + 256, o;
    char *text = malloc(cap);
    cr_scene s;
    int i;
    (void)state;
    assert_non_null(text);
    o = (size_t)snprintf(text, cap, "%s", MIN);
    for (i = 0; i < n; i++)
        o += (size_t)snprintf(text + o, cap - o,
                              "sphere: {color: [1, 2, 3], resolution: [1, 1], r: 10, theta: 90, "
                              "phi: %d, radius: 0.1}\n",
                              i);
    load_ok(text, &s);
    assert_int_equal(s.n_spheres, n);
    assert_near(s.spheres[n - 1].phi.a, (n - 1) * DEG, 1e-12);
    assert_int_equal(s.spheres[n - 1].line, n + 2);
    cr_scene_free(&s);
    free(text);
}

static void test_spheres_list_flow(void **state)
{
    cr_scene s;
    (void)state;
    load_ok(BASE "spheres: [{color: [9, 9, 9], resolution: [2, 3], r: 5, theta: 0.25 pi,"
                 " phi: 1 rad, roll: 1, pitch: 2, yaw: 3, radius: 0.5}]\n",
            &s);
    assert_int_equal(s.n_spheres, 1);
    assert_int_equal(s.spheres[0].color.g, 9);
    assert_int_equal(s.spheres[0].n_lat, 2);
    assert_int_equal(s.spheres[0].n_lon, 3);
    assert_near(s.spheres[0].theta.a, 0.25 * CR_PI, 1e-15);
    assert_near(s.spheres[0].phi.a, 1.0, 0.0);
    assert_near(s.spheres[0].yaw.a, 3.0 * DEG, 1e-15);
    assert_true(s.spheres[0].radius.a == 0.5);
    assert_int_equal(s.spheres[0].line, 10);
    cr_scene_free(&s);
}

/* ---- the listings of chapter 7 -------------------------------------------- */

static void test_listings(void **state)
{
    static const char *files[] = {"scene_7_1_1.yml", "scene_7_1_3.yml", "scene_7_1_4.yml",
                                  "scene_7_1_5.yml", "scene_7_1_6.yml", "scene_7_2_1.yml",
                                  "scene_7_3_1.yml", "scene_full.yml"};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[512];
        cr_scene s;
        cr_err e;
        cr_frame f;
        cr_sphere buf[MAX_SPHERES];
        snprintf(path, sizeof path, "%s%s", DATA, files[i]);
        if (cr_scene_load(path, &s, &e))
            fail_msg("%s", e.msg);
        frame_ok(&s, 0, 20, &f, buf);
        frame_ok(&s, 10, 20, &f, buf);
        frame_ok(&s, 19, 20, &f, buf);
        frame_ok(&s, 0, 1, &f, buf);
        cr_scene_free(&s);
    }
}

static void test_listing_7_1_1_values(void **state)
{
    cr_scene s;
    cr_err e;
    (void)state;
    if (cr_scene_load(DATA "scene_7_1_1.yml", &s, &e))
        fail_msg("%s", e.msg);
    /* `sky_color: [255, 255,` continued on the next line */
    assert_true(s.sky_color.r == 255 && s.sky_color.g == 255 && s.sky_color.b == 255);
    assert_true(s.horizon_color.r == 0 && s.horizon_color.g == 0 && s.horizon_color.b == 0);
    assert_near(s.obs_theta.a, 5.0 * DEG, 1e-15);
    assert_near(s.obs_theta.b, 175.0 * DEG, 1e-15);
    assert_true(s.disc_color2.r == 255 && s.disc_color2.g == 0 && s.disc_color2.b == 255);
    cr_scene_free(&s);
}

/* ---- frame evaluation ------------------------------------------------------ */

static void test_frame_fields(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_sphere buf[MAX_SPHERES];
    cr_trace_settings ts;
    cr_err e;
    (void)state;
    if (cr_scene_load(DATA "scene_full.yml", &s, &e))
        fail_msg("%s", e.msg);
    ts.integrator = CR_INTEG_RK4;
    ts.tolerance = 1e-6;
    ts.step_multiplier = 0.01;
    ts.horizon_epsilon = 1e-3;
    ts.max_steps = 1234;
    ts.max_turns = 7.0;
    ts.samples = 1;
    if (cr_scene_frame(&s, 1, 3, 320, 200, &ts, &f, buf, &e))
        fail_msg("%s", e.msg);
    assert_true(f.metric.m == 1.0 && f.metric.a == 0.25 && f.metric.q == 0.25);
    assert_true(f.observer.r == 30.0);
    assert_near(f.observer.hfov, 70.0 * DEG, 1e-15);
    assert_near(f.observer.vfov, 50.0 * DEG, 1e-15);
    assert_near(f.observer.roll, 10.0 * DEG, 1e-15);
    assert_int_equal(f.disc.enabled, 1);
    assert_int_equal(f.disc.n_radial, 2);
    assert_int_equal(f.disc.n_sectors, 12);
    assert_true(f.disc.color2.r == 255 && f.disc.color2.b == 255);
    assert_int_equal(f.n_spheres, 2);
    assert_int_equal(buf[1].n_lon, 9);
    assert_null(f.sky.rgb);
    assert_true(f.sky_boundary == 0.0);
    assert_true(f.sky_color.b == 1);
    assert_int_equal(f.width, 320);
    assert_int_equal(f.height, 200);
    assert_true(f.step_multiplier == 0.01 && f.horizon_epsilon == 1e-3);
    assert_true(f.max_steps == 1234 && f.max_turns == 7.0);
    assert_int_equal(f.integrator, CR_INTEG_RK4);
    assert_true(f.tolerance == 1e-6);
    /* prepared */
    assert_near(f.r_stop, cr_metric_r_plus(&f.metric) + 1e-3, 1e-15);
    {
        /* a plain sky: the scene ends 1 M beyond its farthest object (the
         * disc, or a sphere's Cartesian extent), not at the observer's 30 M */
        double rm = f.disc.r_out;
        int k;
        for (k = 0; k < f.n_spheres; k++) {
            const double *c = f.spheres[k].center;
            rm = fmax(rm, sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + f.spheres[k].radius);
        }
        assert_near(f.r_max, fmax(rm + 1.0, 6.0), 1e-12);
        assert_true(f.r_max < 30.0);
        assert_near(f.w_sky, 1.0 / f.r_max, 1e-15);
    }
    assert_true(f.obs_sqrt_mgtt > 0.0);
    assert_near(f.tan_half_h, tan(35.0 * DEG), 1e-14);
    assert_int_equal(f.obs_on_axis, 0);
    /* defaults of the raytracer settings with ts == NULL */
    if (cr_scene_frame(&s, 0, 1, 320, 200, NULL, &f, buf, &e))
        fail_msg("%s", e.msg);
    assert_true(f.step_multiplier == cr_trace_defaults().step_multiplier);
    assert_true(f.horizon_epsilon == cr_trace_defaults().horizon_epsilon);
    assert_true(f.max_steps == cr_trace_defaults().max_steps);
    assert_true(f.max_turns == cr_trace_defaults().max_turns);
    assert_int_equal(f.integrator, cr_trace_defaults().integrator);
    assert_int_equal(f.integrator, CR_INTEG_MINO);
    assert_true(f.tolerance == cr_trace_defaults().tolerance);
    cr_scene_free(&s);
}

static void test_vfov_default(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_err e;
    (void)state;
    load_ok("metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 90}\n", &s);
    if (cr_scene_frame(&s, 0, 1, 200, 100, NULL, &f, NULL, &e))
        fail_msg("%s", e.msg);
    /* (E.4.1): tan(vfov/2) / tan(hfov/2) = h / b */
    assert_near(f.observer.vfov, 2.0 * atan(0.5), 1e-15);
    assert_near(tan(0.5 * f.observer.vfov) / tan(0.5 * f.observer.hfov), 0.5, 1e-15);
    if (cr_scene_frame(&s, 0, 1, 100, 300, NULL, &f, NULL, &e))
        fail_msg("%s", e.msg);
    assert_near(tan(0.5 * f.observer.vfov) / tan(0.5 * f.observer.hfov), 3.0, 1e-14);
    cr_scene_free(&s);
}

/* Load metric/observer (+ extra) and expect frame k of n to fail with a
 * message containing what (and "frame K of N: " when n > 1). */
static void frame_rejects(const char *metric, const char *observer, const char *extra, int k,
                          int n, int w, int h, const char *what)
{
    char text[2048];
    cr_scene s;
    cr_frame f;
    cr_sphere buf[MAX_SPHERES];
    cr_err e;
    snprintf(text, sizeof text, "metric: {%s}\nobserver: {%s}\n%s", metric, observer,
             extra ? extra : "");
    load_ok(text, &s);
    e.msg[0] = '\0';
    if (cr_scene_frame(&s, k, n, w, h, NULL, &f, buf, &e) == 0)
        fail_msg("frame %d of %d accepted, expected \"%s\"\n--- text:\n%s", k, n, what, text);
    assert_starts(e.msg, NAME ": ");
    if (n > 1) {
        char fr[64];
        snprintf(fr, sizeof fr, NAME ": frame %d of %d: ", k, n);
        assert_starts(e.msg, fr);
    }
    assert_contains(e.msg, what);
    cr_scene_free(&s);
}

static void frame_accepts(const char *metric, const char *observer, const char *extra,
                          cr_frame *f)
{
    char text[2048];
    cr_scene s;
    cr_sphere buf[MAX_SPHERES];
    snprintf(text, sizeof text, "metric: {%s}\nobserver: {%s}\n%s", metric, observer,
             extra ? extra : "");
    load_ok(text, &s);
    frame_ok(&s, 0, 1, f, buf);
    cr_scene_free(&s);
}

#define OBS "r: 30, theta: 90, phi: 0, hfov: 70"
#define SCHW "m: 1, a: 0, q: 0"

static void test_frame_rejects_metric(void **state)
{
    (void)state;
    frame_rejects("m: 0, a: 0, q: 0", OBS, NULL, 0, 1, 64, 48, "metric.m = 0: the mass M");
    frame_rejects("m: -1, a: 0, q: 0", OBS, NULL, 0, 1, 64, 48, "must be positive");
    frame_rejects("m: 1, a: 1.1, q: 0", OBS, NULL, 0, 1, 64, 48, "no event horizon");
    frame_rejects("m: 1, a: 0, q: -1.01", OBS, NULL, 0, 1, 64, 48, "no event horizon");
    frame_rejects("m: 1, a: 0.8, q: 0.61", OBS, NULL, 0, 1, 64, 48, "a^2 + q^2");
    frame_rejects("m: 1, a: 1.0000001, q: 0", OBS, NULL, 0, 1, 64, 48, "no event horizon");
    /* animated: fine at first, impossible at the last frame */
    frame_rejects("m: 1, a: [linear, 0, 2], q: 0", OBS, NULL, 9, 10, 64, 48,
                  "no event horizon");
    frame_rejects("m: [linear, 1, -1], a: 0, q: 0", OBS, NULL, 3, 4, 64, 48, "mass M");
}

static void test_frame_extremal_accepted(void **state)
{
    cr_frame f;
    (void)state;
    frame_accepts("m: 1, a: 1, q: 0", OBS, NULL, &f); /* listing 7.2.1 */
    assert_true(f.metric.a == 1.0);
    assert_near(f.r_stop, 1.0 + cr_trace_defaults().horizon_epsilon, 1e-15);
    frame_accepts("m: 1, a: 0, q: 1", OBS, NULL, &f); /* listing 7.3.1 */
    frame_accepts("m: 1, a: -1, q: 0", OBS, NULL, &f);
    /* 0.6^2 + 0.8^2 rounds above 1 in doubles: still extremal */
    frame_accepts("m: 1, a: 0.6, q: 0.8", OBS, NULL, &f);
    assert_true(isfinite(f.r_stop));
    assert_near(f.metric.m, 1.0, 1e-15);
    frame_accepts("m: 2, a: 1.2, q: 1.6", OBS, NULL, &f);
    assert_true(isfinite(f.r_stop));
}

static void test_frame_rejects_observer(void **state)
{
    (void)state;
    /* at and inside the horizon r+ = 2M */
    frame_rejects(SCHW, "r: 2, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64, 48,
                  "observer.r = 2 is on the event horizon");
    frame_rejects(SCHW, "r: 1, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64, 48,
                  "event horizon");
    frame_rejects(SCHW, "r: -5, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64, 48,
                  "event horizon");
    /* Kerr a = 0.9: r+ = 1.436, r_E+(90 deg) = 2: static observer impossible */
    frame_rejects("m: 1, a: 0.9, q: 0", "r: 1.8, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64,
                  48, "inside the ergosphere");
    frame_rejects("m: 1, a: 0.9, q: 0", "r: 2, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64,
                  48, "inside the ergosphere");
    frame_rejects("m: 1, a: 0.9, q: 0", "r: 1.4, theta: 90, phi: 0, hfov: 70", NULL, 0, 1, 64,
                  48, "event horizon");
    /* animated into the horizon: named frame */
    frame_rejects(SCHW, "r: [linear, 30, 1], theta: 90, phi: 0, hfov: 70", NULL, 9, 10, 64, 48,
                  "event horizon");
    /* theta outside 0..180 deg */
    frame_rejects(SCHW, "r: 30, theta: 200, phi: 0, hfov: 70", NULL, 0, 1, 64, 48,
                  "observer.theta = 200 deg lies outside 0 to 180 deg");
    frame_rejects(SCHW, "r: 30, theta: -1, phi: 0, hfov: 70", NULL, 0, 1, 64, 48,
                  "observer.theta");
}

static void test_frame_on_axis_accepted(void **state)
{
    cr_frame f;
    (void)state;
    frame_accepts(SCHW, "r: 30, theta: 0, phi: 0, hfov: 70", NULL, &f);
    assert_int_equal(f.obs_on_axis, 1);
    frame_accepts(SCHW, "r: 30, theta: 180, phi: 0, hfov: 70", NULL, &f);
    assert_int_equal(f.obs_on_axis, -1);
    frame_accepts(SCHW, "r: 30, theta: 1 pi, phi: 0, hfov: 70", NULL, &f);
    assert_int_equal(f.obs_on_axis, -1);
    /* on the axis of a fast Kerr hole the ergosphere touches the horizon:
     * r = 1.8 is outside r+ = 1.436 there */
    frame_accepts("m: 1, a: 0.9, q: 0", "r: 1.8, theta: 0, phi: 0, hfov: 70", NULL, &f);
    assert_int_equal(f.obs_on_axis, 1);
    /* just above the horizon (listing 7.1.5) */
    frame_accepts(SCHW, "r: 2.1, theta: 85, phi: 0, yaw: 180, hfov: 70", NULL, &f);
}

static void test_frame_rejects_fov(void **state)
{
    (void)state;
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: 0", NULL, 0, 1, 64, 48,
                  "observer.hfov = 0 deg: a field of view must lie between 0 and 180 deg");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: 180", NULL, 0, 1, 64, 48,
                  "observer.hfov = 180 deg");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: -10", NULL, 0, 1, 64, 48,
                  "observer.hfov");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: 1.1 pi", NULL, 0, 1, 64, 48,
                  "observer.hfov");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: 70, vfov: 180", NULL, 0, 1, 64, 48,
                  "observer.vfov = 180 deg");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: 70, vfov: 0 rad", NULL, 0, 1, 64, 48,
                  "observer.vfov = 0 deg");
    frame_rejects(SCHW, "r: 30, theta: 90, phi: 0, hfov: [linear, 70, 180]", NULL, 1, 2, 64, 48,
                  "observer.hfov");
}

static void test_frame_rejects_objects(void **state)
{
    (void)state;
    frame_rejects(SCHW, OBS, "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                             "radius: [15, 6]}\n",
                  0, 1, 64, 48, "accretion.radius: the inner radius 15 must be below the outer");
    frame_rejects(SCHW, OBS, "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                             "radius: [6, 6]}\n",
                  0, 1, 64, 48, "must be below the outer radius 6");
    frame_rejects(SCHW, OBS, "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                             "radius: [-1, 6]}\n",
                  0, 1, 64, 48, "the inner radius -1 is negative");
    frame_rejects(SCHW, OBS, "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                             "radius: [[linear, 2, 20], 15]}\n",
                  4, 5, 64, 48, "accretion.radius");
    frame_rejects(SCHW, OBS, "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, "
                             "theta: 90, phi: 0, radius: 0}\n",
                  0, 1, 64, 48, "sphere 0 (line 3): radius = 0 must be positive");
    frame_rejects(SCHW, OBS, "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, "
                             "theta: 90, phi: 0, radius: 1}\n"
                             "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, "
                             "theta: 90, phi: 0, radius: -2}\n",
                  0, 1, 64, 48, "sphere 1 (line 4): radius = -2 must be positive");
    frame_rejects(SCHW, OBS, "sphere: {color: [1, 2, 3], resolution: [4, 8], r: -1, "
                             "theta: 90, phi: 0, radius: 1}\n",
                  0, 1, 64, 48, "r = -1 must not be negative");
    frame_rejects(SCHW, OBS, NULL, 0, 1, 0, 48, "the image size 0 x 48 must be positive");
    frame_rejects(SCHW, OBS, NULL, 0, 1, 64, -1, "image size");
}

static void test_frame_bad_index(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_err e;
    (void)state;
    load_ok(MIN, &s);
    assert_int_equal(cr_scene_frame(&s, 5, 5, 64, 48, NULL, &f, NULL, &e), -1);
    assert_string_equal(e.msg, NAME ": frame 5 of 5 does not exist (frames are 0 to n-1)");
    assert_int_equal(cr_scene_frame(&s, -1, 5, 64, 48, NULL, &f, NULL, &e), -1);
    assert_int_equal(cr_scene_frame(&s, 0, 0, 64, 48, NULL, &f, NULL, &e), -1);
    cr_scene_free(&s);
}

static void test_frame_objects_in_horizon_allowed(void **state)
{
    cr_frame f;
    (void)state;
    /* a disc and a sphere reaching inside the horizon (figure 7.1.4) */
    frame_accepts(SCHW, OBS, "accretion: {color1: [0, 255, 0], resolution: [2, 12], "
                             "radius: [0, 15]}\n"
                             "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 0, "
                             "theta: 90, phi: 0, radius: 2.1}\n",
                  &f);
    assert_int_equal(f.disc.enabled, 1);
    assert_true(f.disc.r_in == 0.0);
    assert_int_equal(f.n_spheres, 1);
}

static void test_frame_rejects_settings(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_trace_settings ts = {.integrator = cr_trace_defaults().integrator,
                            .tolerance = cr_trace_defaults().tolerance,
                            .step_multiplier = cr_trace_defaults().step_multiplier,
                            .horizon_epsilon = cr_trace_defaults().horizon_epsilon,
                            .max_steps = cr_trace_defaults().max_steps,
                            .max_turns = cr_trace_defaults().max_turns};
    cr_err e;
    (void)state;
    load_ok(MIN, &s);
    ts.step_multiplier = 0.0;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_contains(e.msg, "step_multiplier");
    ts.step_multiplier = cr_trace_defaults().step_multiplier;
    ts.horizon_epsilon = -1.0;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_contains(e.msg, "horizon_epsilon");
    ts.horizon_epsilon = cr_trace_defaults().horizon_epsilon;
    ts.max_steps = 0;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_contains(e.msg, "max_steps");
    ts.max_steps = cr_trace_defaults().max_steps;
    {
        const double bad[] = {0.0, -1e-8, NAN, INFINITY, -INFINITY};
        size_t i;
        for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
            ts.tolerance = bad[i];
            assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
            assert_starts(e.msg, NAME ": raytracer.tolerance = ");
            assert_contains(e.msg, "must be positive");
        }
    }
    ts.tolerance = cr_trace_defaults().tolerance;
    ts.integrator = CR_INTEG_COUNT_;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_string_equal(e.msg, NAME ": raytracer.integrator = 2 is not an integrator (expected "
                                    "one of: mino, rk4)");
    ts.integrator = -1;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_contains(e.msg, "raytracer.integrator = -1");
    /* both integrators run a finite observer */
    ts.integrator = CR_INTEG_RK4;
    ts.tolerance = 1e-3;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), 0);
    assert_int_equal(f.integrator, CR_INTEG_RK4);
    assert_true(f.tolerance == 1e-3);
    ts.integrator = CR_INTEG_MINO;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), 0);
    assert_int_equal(f.integrator, CR_INTEG_MINO);
    cr_scene_free(&s);
}

/* ---- evaluation: the owned sphere array, the Keplerian disc once ----------- */

/* cr_frame_eval_at gives the frame cr_scene_frame gives, with the spheres in
 * its own array (grown for a scene with more spheres, kept for one with
 * fewer); a failed evaluation leaves the frame zeroed; free empties it. */
static void test_frame_eval_owns_spheres(void **state)
{
    static const char *two = BASE "sphere: {color: [1, 2, 3], resolution: [2, 2], r: 10, "
                                  "theta: 90, phi: 0, radius: 1}\n"
                                  "sphere: {color: [4, 5, 6], resolution: [3, 3], r: 12, "
                                  "theta: 80, phi: 30, radius: 2}\n";
    static const char *three = BASE "spheres:\n"
                                    "  - {color: [1, 2, 3], resolution: [2, 2], r: 10, theta: 90, "
                                    "phi: 0, radius: 1}\n"
                                    "  - {color: [1, 2, 3], resolution: [2, 2], r: 11, theta: 90, "
                                    "phi: 0, radius: 1}\n"
                                    "  - {color: [1, 2, 3], resolution: [2, 2], r: 12, theta: 90, "
                                    "phi: 0, radius: 1}\n";
    cr_scene s2, s3, s0;
    cr_frame f;
    cr_sphere buf[2];
    cr_frame_eval e;
    cr_err err;
    (void)state;
    memset(&e, 0, sizeof e);
    load_ok(two, &s2);
    load_ok(three, &s3);
    load_ok(MIN, &s0);
    frame_ok(&s2, 0, 1, &f, buf);
    assert_int_equal(cr_frame_eval_at(&e, &s2, 0, 1, 64, 48, NULL, &err), 0);
    assert_int_equal(e.frame.n_spheres, 2);
    assert_ptr_equal(e.frame.spheres, e.spheres);
    assert_int_equal(e.n_room, 2);
    assert_memory_equal(e.spheres, buf, sizeof buf);
    f.spheres = e.frame.spheres; /* the only field that may differ */
    assert_memory_equal(&f, &e.frame, sizeof f);
    assert_int_equal(cr_frame_eval_at(&e, &s3, 0, 1, 64, 48, NULL, &err), 0);
    assert_int_equal(e.frame.n_spheres, 3);
    assert_int_equal(e.n_room, 3);
    assert_true(e.frame.spheres[2].r == 12.0 / e.frame.metric.m);
    assert_int_equal(cr_frame_eval_at(&e, &s0, 0, 1, 64, 48, NULL, &err), 0);
    assert_int_equal(e.frame.n_spheres, 0);
    assert_null(e.frame.spheres);
    assert_int_equal(e.n_room, 3);
    assert_int_equal(cr_frame_eval_at(&e, &s2, 3, 2, 64, 48, NULL, &err), -1);
    assert_contains(err.msg, "frame 3 of 2 does not exist");
    assert_null(e.frame.spheres);
    assert_int_equal(e.frame.width, 0);
    cr_frame_eval_free(&e);
    assert_null(e.spheres);
    assert_int_equal(e.n_room, 0);
    cr_frame_eval_free(&e); /* twice is harmless */
    cr_scene_free(&s2);
    cr_scene_free(&s3);
    cr_scene_free(&s0);
}

/* The frame's Keplerian disc is cr_scene_keplerian's (the derivation
 * info.txt uses too): the same sense, ISCO, effective inner edge and peak
 * temperature for the frame's metric and radii; a refused disc still has
 * its sense and ISCO, and the reason names the key. */
static void test_keplerian_derived_once(void **state)
{
    static const char *const texts[] = {
        "metric: {m: 2, a: 1.2, q: 0}\n" OBSL "accretion: {model: keplerian, radius: [40]}\n",
        "metric: {m: 2, a: 1.2, q: 0.3}\n" OBSL
        "accretion: {model: keplerian, radius: [5, 40], retrograde: true, mass_msun: 10, "
        "mdot_edd: 0.1}\n",
        "metric: {m: 1, a: -0.5, q: 0}\n" OBSL
        "accretion: {model: keplerian, radius: [2, 30], inside_isco: plunging}\n",
    };
    (void)state;
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        cr_scene s;
        cr_frame f;
        cr_disc d;
        char why[256];
        load_ok(texts[i], &s);
        frame_ok(&s, 0, 1, &f, NULL);
        memset(&d, 0, sizeof d);
        d.enabled = 1;
        d.model = CR_DISC_KEPLERIAN;
        d.r_in = s.disc_r_in.a / s.m.a;
        d.r_out = s.disc_r_out.a / s.m.a;
        assert_int_equal(cr_scene_keplerian(&s, &f.metric, s.m.a, &d, why, sizeof why), 0);
        assert_int_equal(d.sense, f.disc.sense);
        assert_true(d.r_isco == f.disc.r_isco);
        assert_true(fabs(d.r_in - f.disc.r_in) <= 1e-14 * f.disc.r_in);
        assert_true(d.r_in >= d.r_isco);
        assert_true(fabs(d.t_peak - f.disc.t_peak) <= 1e-12 * f.disc.t_peak);
        assert_true(d.t_peak > 0.0);
        cr_scene_free(&s);
    }
    {
        cr_scene s;
        cr_frame f;
        cr_disc d;
        cr_metric mt;
        char why[256];
        cr_err e;
        load_ok("metric: {m: 1, a: 0, q: 0}\n" OBSL
                "accretion: {model: keplerian, radius: [5]}\n",
                &s);
        assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, NULL, &f, NULL, &e), -1);
        memset(&d, 0, sizeof d);
        memset(&mt, 0, sizeof mt);
        mt.m = 1.0;
        d.r_out = 5.0;
        assert_int_equal(cr_scene_keplerian(&s, &mt, 1.0, &d, why, sizeof why), -1);
        assert_true(fabs(d.r_isco - 6.0) < 1e-12);
        assert_int_equal(d.sense, 1);
        assert_starts(why, "accretion.radius: the prograde ISCO r_isco = 6 lies at or beyond");
        assert_string_equal(e.msg + strlen(NAME ": "), why);
        cr_scene_free(&s);
    }
}

/* ---- the Keplerian disc's exposure and horizon ----------------------------- */

/* accretion.exposure: a factor on the disc's light (animated too), so the
 * frame's exposure is the default one times it, and a pixel's colour the
 * blackbody chain at that exposure; the horizon is black next to a
 * Keplerian disc unless horizon_color says otherwise, and stays the paper's
 * red next to the chessboard. */
static void test_keplerian_exposure_and_horizon(void **state)
{
    cr_scene s0, s2, sa, sc, sh;
    cr_frame f0, f2, fa, fc, fh;
    (void)state;
    load_ok("metric: {m: 1, a: 0.5, q: 0}\n" OBSL "accretion: {model: keplerian, radius: [20]}\n",
            &s0);
    load_ok("metric: {m: 1, a: 0.5, q: 0}\n" OBSL
            "accretion: {model: keplerian, radius: [20], exposure: 2.5}\n",
            &s2);
    load_ok("metric: {m: 1, a: 0.5, q: 0}\n" OBSL
            "accretion: {model: keplerian, radius: [20], exposure: [linear, 1, 4]}\n",
            &sa);
    frame_ok(&s0, 0, 1, &f0, NULL);
    frame_ok(&s2, 0, 1, &f2, NULL);
    assert_true(f0.disc.exposure > 0.0);
    assert_true(fabs(f2.disc.exposure - 2.5 * f0.disc.exposure) <= 1e-15 * f2.disc.exposure);
    for (int k = 0; k < 3; k++) {
        frame_ok(&sa, k, 3, &fa, NULL);
        assert_true(fabs(fa.disc.exposure - (1.0 + 1.5 * k) * f0.disc.exposure) <=
                    1e-15 * fa.disc.exposure);
    }
    {
        /* a disc point's colour is the chain at the scaled exposure */
        double r = 8.0, g = 1.1, bolo, F = cr_flux_table_F(&f2.disc.flux, r);
        double T = f2.disc.t_scale * sqrt(sqrt(F));
        cr_rgb c = cr_disc_keplerian_color(&f2.disc, r, g, &bolo);
        cr_rgb want = cr_bb_rgb8(T, g, 2.5 * f0.disc.exposure, f0.disc.white);
        cr_rgb plain = cr_disc_keplerian_color(&f0.disc, r, g, &bolo);
        assert_int_equal(c.r, want.r);
        assert_int_equal(c.g, want.g);
        assert_int_equal(c.b, want.b);
        assert_true(c.r + c.g + c.b > plain.r + plain.g + plain.b); /* brighter */
    }
    /* horizons: black by default next to the Keplerian disc, red next to
     * the chessboard, as given when given */
    assert_int_equal(s0.horizon_color.r, 0);
    assert_int_equal(s0.horizon_color.g, 0);
    assert_int_equal(s0.horizon_color.b, 0);
    load_ok("metric: {m: 1, a: 0, q: 0}\n" OBSL
            "accretion: {color1: [0, 255, 0], resolution: [2, 12], radius: [6, 15]}\n",
            &sc);
    frame_ok(&sc, 0, 1, &fc, NULL);
    assert_int_equal(fc.horizon_color.r, 255);
    assert_int_equal(fc.horizon_color.g, 0);
    assert_int_equal(fc.horizon_color.b, 0);
    load_ok("metric: {m: 1, a: 0, q: 0}\n" OBSL "accretion: {model: keplerian, radius: [20]}\n"
            "horizon_color: [255, 0, 0]\n",
            &sh);
    frame_ok(&sh, 0, 1, &fh, NULL);
    assert_int_equal(fh.horizon_color.r, 255);
    assert_int_equal(fh.horizon_color.g, 0);
    cr_scene_free(&s0);
    cr_scene_free(&s2);
    cr_scene_free(&sa);
    cr_scene_free(&sc);
    cr_scene_free(&sh);
}

/* The extended Reinhard curve v (1 + v / w^2) / (1 + v), written out. */
static double reinhard(double v, double w)
{
    return v * (1.0 + v / (w * w)) / (1.0 + v);
}

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y);
}

/* The 99th percentile (nearest rank) of the luminance (Rec. 709 weights) of
 * frame f's lit disc pixels at w x h, at the frame's exposure, from each
 * pixel's hit radius and g through the blackbody's XYZ. */
static double disc_p99(const cr_frame *f, int w, int h, long *lit)
{
    double *v = malloc(sizeof *v * (size_t)w * h), p;
    long m = 0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            cr_pixel px = cr_trace_pixel(f, i, j);
            double F, xyz[3], rgb[3], L;
            if (px.outcome != CR_OUT_DISC || !(px.redshift > 0.0))
                continue;
            F = cr_flux_table_F(&f->disc.flux, px.hit_r);
            if (!(F > 0.0))
                continue;
            cr_bb_xyz(f->disc.t_scale * sqrt(sqrt(F)), px.redshift, xyz);
            cr_xyz_to_linear_srgb(xyz, rgb);
            L = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
            if (L > 0.0)
                v[m++] = L * f->disc.exposure;
        }
    qsort(v, (size_t)m, sizeof *v, cmp_dbl);
    p = m > 0 ? v[(long)ceil(0.99 * m) - 1] : 0.0;
    free(v);
    *lit = m;
    return p;
}

/* exposure: auto: found once from frame 0 traced 192 pixels across, the
 * 99th percentile of the lit disc's luminance lands where the tone curve
 * gives 0.8 of white; every frame of an animation gets the same factor;
 * -x/-y of one aspect give the same factor; a scene whose disc is not seen
 * keeps 1. */
static void test_keplerian_auto_exposure(void **state)
{
    static const char *text = "metric: {m: 1, a: 0.9, q: 0}\n"
                              "observer: {r: 80, theta: [linear, 5, 60], phi: 0, hfov: 40}\n"
                              "accretion: {model: keplerian, radius: [25], mass_msun: 1e10, "
                              "mdot_edd: 0.01, exposure: auto}\n";
    cr_scene s;
    cr_frame f, f1;
    cr_err e;
    long lit, lit2;
    double found, p;
    (void)state;
    load_ok(text, &s);
    assert_int_equal(cr_scene_auto_exposure(&s, 4, 640, 480, NULL, &lit, &e), 0);
    found = s.disc_exposure_found;
    assert_true(found > 1.0 && lit > 1000);
    /* the rule, checked on the preview frame with the factor applied */
    assert_int_equal(cr_scene_frame(&s, 0, 4, 192, 144, NULL, &f, NULL, &e), 0);
    p = disc_p99(&f, 192, 144, &lit2);
    assert_int_equal(lit2, lit);
    print_message("auto exposure %.6g from %ld lit pixels: p99 %.6g -> tone curve %.9f\n", found,
                  lit, p, reinhard(p, f.disc.white));
    assert_true(fabs(reinhard(p, f.disc.white) - 0.8) < 1e-12);
    /* fixed across the animation: every frame's factor is the same */
    for (int k = 1; k < 4; k++) {
        assert_int_equal(cr_scene_frame(&s, k, 4, 64, 48, NULL, &f1, NULL, &e), 0);
        assert_true(f1.disc.exposure == f.disc.exposure);
    }
    /* another size of the same aspect, and a second call: the same factor */
    assert_int_equal(cr_scene_auto_exposure(&s, 4, 64, 48, NULL, &lit, &e), 0);
    assert_true(s.disc_exposure_found == found);
    cr_scene_free(&s);
    /* nothing of the disc in view (looking away from it): factor 1 */
    load_ok("metric: {m: 1, a: 0, q: 0}\n"
            "observer: {r: 80, theta: 90, phi: 0, hfov: 20, yaw: 180}\n"
            "accretion: {model: keplerian, radius: [25], exposure: auto}\n",
            &s);
    assert_int_equal(cr_scene_auto_exposure(&s, 1, 64, 48, NULL, &lit, &e), 0);
    assert_int_equal(lit, 0);
    assert_true(s.disc_exposure_found == 1.0);
    cr_scene_free(&s);
}

/* ---- the observer at infinity ---------------------------------------------- */

#define INF_OBS "observer: {r: inf, theta: 85, phi: 0, hextent: 40}\n"

static void test_observer_at_infinity(void **state)
{
    static const char *spellings[] = {"inf",  "+inf",     "infinity", "Infinity", "INF",
                                      "+Inf", "INFINITY", ".inf",     "+.inf",    "\"inf\"",
                                      "'infinity'", "\" inf \""};
    cr_scene s;
    cr_frame f;
    cr_sphere buf[MAX_SPHERES];
    cr_err e;
    char text[512];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof spellings / sizeof spellings[0]; i++) {
        snprintf(text, sizeof text,
                 "metric: {m: 1, a: 0.9, q: 0}\n"
                 "observer: {r: %s, theta: 85, phi: 0, hextent: 40}\n",
                 spellings[i]);
        load_ok(text, &s);
        assert_int_equal(s.obs_at_infinity, 1);
        assert_true(isinf(s.obs_r.a) && s.obs_r.a > 0.0 && s.obs_r.b == s.obs_r.a);
        assert_true(s.hextent.a == 40.0 && s.hextent.b == 40.0);
        assert_int_equal(s.has_vextent, 0);
        assert_int_equal(s.has_vfov, 0);
        cr_scene_free(&s);
    }
    /* the frame: r = +inf, the extents, no field of view; vextent from the
     * aspect ratio (square pixels) */
    load_ok("metric: {m: 1, a: 0.9, q: 0}\n" INF_OBS, &s);
    e.msg[0] = '\0';
    if (cr_scene_frame(&s, 0, 1, 200, 100, NULL, &f, buf, &e))
        fail_msg("%s", e.msg);
    assert_true(isinf(f.observer.r) && f.observer.r > 0.0);
    assert_true(f.observer.hextent == 40.0);
    assert_true(f.observer.vextent == 20.0);
    assert_true(f.observer.hfov == 0.0 && f.observer.vfov == 0.0);
    assert_true(f.observer.pitch == 0.0 && f.observer.yaw == 0.0);
    assert_near(f.observer.theta, 85.0 * DEG, 1e-15);
    assert_int_equal(f.integrator, cr_trace_defaults().integrator);
    /* its boundary is at infinity too */
    assert_true(isfinite(f.r_max) || f.r_max == INFINITY);
    assert_true(isfinite(f.r_stop));
    assert_true(f.obs_sqrt_mgtt > 0.0 && isfinite(f.obs_sqrt_mgtt));
    if (cr_scene_frame(&s, 0, 1, 100, 300, NULL, &f, buf, &e))
        fail_msg("%s", e.msg);
    assert_true(f.observer.vextent == 120.0);
    cr_scene_free(&s);

    /* vextent given; roll, and pitch = yaw = 0, allowed; hextent animated;
     * theta on the axis; an extremal hole */
    load_ok("metric: {m: 1, a: 1, q: 0}\n"
            "observer: {r: inf, theta: [linear, 0, 90], phi: 10, roll: [linear, 0, 30],\n"
            "           pitch: 0, yaw: 0 deg, hextent: [linear, 40, 20], vextent: 30}\n",
            &s);
    assert_int_equal(s.has_vextent, 1);
    frame_ok(&s, 0, 3, &f, buf);
    assert_true(f.observer.hextent == 40.0 && f.observer.vextent == 30.0);
    assert_true(f.observer.theta == 0.0 && f.observer.roll == 0.0);
    frame_ok(&s, 2, 3, &f, buf);
    assert_true(f.observer.hextent == 20.0 && f.observer.vextent == 30.0);
    assert_near(f.observer.roll, 30.0 * DEG, 1e-15);
    assert_near(f.observer.theta, 90.0 * DEG, 1e-15);
    cr_scene_free(&s);

    /* a finite r keeps hfov/vfov and leaves the extents 0 */
    load_ok(MIN, &s);
    frame_ok(&s, 0, 1, &f, buf);
    assert_true(f.observer.r == 30.0 && isfinite(f.r_max));
    assert_true(f.observer.hextent == 0.0 && f.observer.vextent == 0.0);
    cr_scene_free(&s);
}

static void test_observer_at_infinity_rejects(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_err e;
    cr_trace_settings ts = {.integrator = CR_INTEG_RK4,
                            .tolerance = cr_trace_defaults().tolerance,
                            .step_multiplier = cr_trace_defaults().step_multiplier,
                            .horizon_epsilon = cr_trace_defaults().horizon_epsilon,
                            .max_steps = cr_trace_defaults().max_steps,
                            .max_turns = cr_trace_defaults().max_turns};
    (void)state;
#define INF_R "r: inf, theta: 85, phi: 0"
    frame_rejects(SCHW, INF_R ", hextent: 0", NULL, 0, 1, 64, 48,
                  "observer.hextent = 0: the width of the image plane must be positive");
    frame_rejects(SCHW, INF_R ", hextent: -20", NULL, 0, 1, 64, 48, "observer.hextent = -20");
    frame_rejects(SCHW, INF_R ", hextent: [linear, 40, -40]", NULL, 2, 3, 64, 48,
                  "observer.hextent = -40");
    frame_rejects(SCHW, INF_R ", hextent: 40, vextent: 0", NULL, 0, 1, 64, 48,
                  "observer.vextent = 0: the height of the image plane must be positive");
    frame_rejects(SCHW, INF_R ", hextent: 40, vextent: -1", NULL, 0, 1, 64, 48,
                  "observer.vextent = -1");
    frame_rejects(SCHW, INF_R ", hextent: 1e308", NULL, 0, 1, 1, 64, "observer.vextent = inf");
    frame_rejects(SCHW, "r: inf, theta: 200, phi: 0, hextent: 40", NULL, 0, 1, 64, 48,
                  "observer.theta = 200 deg");
    /* no horizon: named by metric.a and metric.q */
    frame_rejects("m: 1, a: 1.1, q: 0", INF_R ", hextent: 40", NULL, 0, 1, 64, 48,
                  "metric.a = 1.1, metric.q = 0: a^2 + q^2 = 1.21 exceeds m^2 = 1, so there is "
                  "no event horizon");
    frame_rejects("m: 1, a: 0.6, q: 0.9", INF_R ", hextent: 40", NULL, 0, 1, 64, 48,
                  "metric.a = 0.6, metric.q = 0.9: a^2 + q^2 = 1.17");
    frame_rejects("m: 1, a: 0, q: [linear, 0, 2]", INF_R ", hextent: 40", NULL, 1, 2, 64, 48,
                  "metric.a = 0, metric.q = 2:");
    /* the ergosphere check does not apply (it would for a finite r) */
    {
        cr_frame f2;
        frame_accepts("m: 1, a: 1, q: 0", "r: inf, theta: 90, phi: 0, hextent: 40", NULL, &f2);
        assert_true(isinf(f2.observer.r));
    }
    /* rk4 cannot start at infinity */
    load_ok("metric: {m: 1, a: 0.9, q: 0}\n" INF_OBS, &s);
    e.msg[0] = '\0';
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_string_equal(e.msg, NAME ": raytracer.integrator = rk4: the rk4 integrator cannot "
                                    "start at infinity (observer.r: inf); use mino, or give "
                                    "observer.r a finite value");
    ts.integrator = CR_INTEG_MINO;
    if (cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e))
        fail_msg("%s", e.msg);
    ts.tolerance = 0.0;
    assert_int_equal(cr_scene_frame(&s, 0, 1, 8, 8, &ts, &f, NULL, &e), -1);
    assert_contains(e.msg, "raytracer.tolerance = 0 must be positive");
    cr_scene_free(&s);
#undef INF_R
}

/* ---- sky image ------------------------------------------------------------ */

static void write_file(const char *path, const char *text)
{
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(text, fp);
    assert_int_equal(fclose(fp), 0);
}

static void test_skymap(void **state)
{
    static const uint8_t rgb[2 * 4 * 3] = {
        1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24,
    };
    cr_scene s;
    cr_frame f;
    cr_err e;
    char text[1024];
    (void)state;
    mkdir(TMP, 0777);
    if (cr_png_write(TMP "/sky.png", 4, 2, rgb, &e))
        fail_msg("%s", e.msg);
    /* relative to the scene file's folder, whatever the current folder */
    write_file(TMP "/sky_scene.yml", BASE "skymap:\n  image: sky.png\n  boundary: 50\n");
    if (cr_scene_load(TMP "/sky_scene.yml", &s, &e))
        fail_msg("%s", e.msg);
    assert_int_equal(s.has_sky, 1);
    assert_string_equal(s.sky_image, TMP "/sky.png");
    assert_int_equal(s.sky_width, 4);
    assert_int_equal(s.sky_height, 2);
    assert_non_null(s.sky_rgb);
    assert_memory_equal(s.sky_rgb, rgb, sizeof rgb);
    assert_true(s.sky_boundary.a == 50.0);
    frame_ok(&s, 0, 1, &f, NULL);
    assert_ptr_equal(f.sky.rgb, s.sky_rgb);
    assert_int_equal(f.sky.width, 4);
    assert_int_equal(f.sky.height, 2);
    assert_true(f.sky_boundary == 50.0);
    assert_true(f.r_max >= 50.0);
    cr_scene_free(&s);

    /* an absolute path from a string */
    snprintf(text, sizeof text, BASE "skymap: {image: %s, boundary: [linear, 40, 60]}\n",
             TMP "/sky.png");
    load_ok(text, &s);
    assert_int_equal(s.sky_width, 4);
    assert_true(s.sky_boundary.a == 40.0 && s.sky_boundary.b == 60.0);
    cr_scene_free(&s);

    /* boundary <= 0 is rejected per frame */
    snprintf(text, sizeof text, BASE "skymap: {image: %s, boundary: [linear, 10, -10]}\n",
             TMP "/sky.png");
    load_ok(text, &s);
    frame_ok(&s, 0, 3, &f, NULL);
    assert_int_equal(cr_scene_frame(&s, 1, 3, 64, 48, NULL, &f, NULL, &e), -1);
    assert_string_equal(e.msg, NAME ": frame 1 of 3: skymap.boundary = 0 must be positive");
    cr_scene_free(&s);

    /* no boundary, or boundary: inf: the sky at infinity (frame boundary 0) */
    write_file(TMP "/sky_inf.yml", BASE "skymap:\n  image: sky.png\n");
    if (cr_scene_load(TMP "/sky_inf.yml", &s, &e))
        fail_msg("%s", e.msg);
    assert_int_equal(s.has_sky, 1);
    assert_int_equal(s.sky_at_infinity, 1);
    frame_ok(&s, 0, 1, &f, NULL);
    assert_ptr_equal(f.sky.rgb, s.sky_rgb);
    assert_true(f.sky_boundary == 0.0);
    assert_true(isfinite(f.r_max));
    cr_scene_free(&s);
    {
        static const char *infs[] = {"inf", "+Infinity", ".inf"};
        size_t i;
        for (i = 0; i < sizeof infs / sizeof infs[0]; i++) {
            snprintf(text, sizeof text, BASE "skymap: {image: %s, boundary: %s}\n",
                     TMP "/sky.png", infs[i]);
            load_ok(text, &s);
            assert_int_equal(s.sky_at_infinity, 1);
            frame_ok(&s, 0, 1, &f, NULL);
            assert_true(f.sky_boundary == 0.0);
            cr_scene_free(&s);
        }
    }
    /* a finite boundary keeps its meaning */
    snprintf(text, sizeof text, BASE "skymap: {image: %s, boundary: 75}\n", TMP "/sky.png");
    load_ok(text, &s);
    assert_int_equal(s.sky_at_infinity, 0);
    frame_ok(&s, 0, 1, &f, NULL);
    assert_true(f.sky_boundary == 75.0 && f.r_max >= 75.0);
    cr_scene_free(&s);
    /* with the observer at infinity */
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0.5, q: 0}\n" INF_OBS "skymap: {image: %s}\n", TMP "/sky.png");
    load_ok(text, &s);
    frame_ok(&s, 0, 1, &f, NULL);
    assert_true(f.sky_boundary == 0.0 && isinf(f.observer.r));
    cr_scene_free(&s);

    /* a missing image: the png message behind the scene location */
    write_file(TMP "/sky_missing.yml", BASE "skymap:\n  image: no_such_sky.png\n  boundary: 50\n");
    assert_int_equal(cr_scene_load(TMP "/sky_missing.yml", &s, &e), -1);
    assert_starts(e.msg, TMP "/sky_missing.yml:11:10: skymap.image: ");
    assert_contains(e.msg, "no_such_sky.png");
    assert_null(s.sky_rgb);
    assert_null(s.path);

    /* not a PNG */
    write_file(TMP "/not_a_png.png", "hello, I am text\n");
    snprintf(text, sizeof text, BASE "skymap: {image: %s, boundary: 5}\n",
             TMP "/not_a_png.png");
    assert_int_equal(load(text, &s, &e), -1);
    assert_starts(e.msg, NAME ":10:17: skymap.image: ");
    assert_contains(e.msg, "not_a_png.png");
}

/* ---- errors --------------------------------------------------------------- */

typedef struct err_case {
    const char *text;
    const char *start; /* the message starts with this: "scene.yml:L:C: key: " */
    const char *part;  /* and contains this */
} err_case;

static void check_errors(const err_case *c, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        cr_scene s;
        cr_err e;
        memset(&s, 0x5a, sizeof s);
        if (load(c[i].text, &s, &e) == 0) {
            cr_scene_free(&s);
            fail_msg("case %zu accepted, expected \"%s%s\"\n--- text:\n%s", i, c[i].start,
                     c[i].part, c[i].text);
        }
        if (strncmp(e.msg, c[i].start, strlen(c[i].start)) != 0 || !strstr(e.msg, c[i].part))
            fail_msg("case %zu: message\n  \"%s\"\nexpected to start with \"%s\" and contain "
                     "\"%s\"\n--- text:\n%s",
                     i, e.msg, c[i].start, c[i].part, c[i].text);
        /* *out is left zeroed */
        assert_null(s.path);
        assert_null(s.spheres);
        assert_int_equal(s.n_spheres, 0);
    }
}

static void test_error_exact_message(void **state)
{
    cr_scene s;
    cr_err e;
    (void)state;
    assert_int_equal(load("metric: {m: 1, a: 0, q: 0}\n"
                          "observer:\n"
                          "  r: 30\n"
                          "  theta: ninety\n"
                          "  phi: 0\n"
                          "  hfov: 70\n",
                          &s, &e),
                     -1);
    assert_string_equal(e.msg, "scene.yml:4:10: observer.theta: expected an angle like 90, "
                               "\"90 deg\", \"1.57 rad\" or \"0.5 pi\", got \"ninety\"");
    assert_int_equal(load(BASE "accretion:\n"
                               "  colour: [0, 255, 0]\n",
                          &s, &e),
                     -1);
    assert_string_equal(e.msg, "scene.yml:11:3: unknown key 'colour' in accretion (expected one "
                               "of: color1, color2, resolution, yaw, radius, model, order, retrograde, "
                               "temperature, inside_isco, mass_msun, mdot_edd, exposure)");
    assert_int_equal(load("metric: {m: 1, a: 0, q: 0}\n"
                          "observer:\n"
                          "  r: 30\n"
                          "  theta: 90\n"
                          "  phi: 0\n",
                          &s, &e),
                     -1);
    assert_string_equal(e.msg, "scene.yml:2:1: observer: missing required key 'hfov'");
    /* the same from a file: the message names the file */
    assert_int_equal(cr_scene_load(DATA "scene_bad_theta.yml", &s, &e), -1);
    assert_string_equal(e.msg, DATA "scene_bad_theta.yml:4:10: observer.theta: expected an angle "
                                    "like 90, \"90 deg\", \"1.57 rad\" or \"0.5 pi\", got "
                                    "\"ninety\"");
}

static void test_errors_syntax_and_shape(void **state)
{
    static const err_case cases[] = {
        /* YAML syntax */
        {"metric:\n\tm: 1\n", "scene.yml:2:1: YAML syntax error: ", "cannot start any token"},
        {"metric: {m: 1, a: 0, q: 0\nobserver: x\n", "scene.yml:", "YAML syntax error"},
        {"metric: [1, 2\n", "scene.yml:", "YAML syntax error"},
        {"metric:\n  m: 1\n a: 2\n", "scene.yml:3:", "YAML syntax error"},
        {"metric: *nothing\n", "scene.yml:1:9: YAML syntax error: ", "undefined alias"},
        {"metric: \"open\n", "scene.yml:", "YAML syntax error"},
        {"metric: \xff\n", "scene.yml:1:9: YAML syntax error: ", "0xFF"},
        {"a: b: c\n", "scene.yml:1:5: YAML syntax error: ", "mapping values are not allowed"},
        /* empty files and documents that are not a mapping */
        {"", "scene.yml: the scene file is empty", ""},
        {"# only a comment\n\n", "scene.yml: the scene file is empty", ""},
        {"---\n", "scene.yml: the scene file is empty", ""},
        {"- 1\n- 2\n", "scene.yml:1:1: a scene must be a mapping of keys",
         "got a list of 2 items"},
        {"hello\n", "scene.yml:1:1: a scene must be a mapping", "got \"hello\""},
        {BASE "---\nfoo: 1\n", "scene.yml:11:1: a second YAML document starts here", ""},
        /* keys */
        {BASE "foo: 1\n", "scene.yml:10:1: unknown key 'foo' at the top level",
         "(expected one of: metric, observer, accretion, skymap, sphere, spheres, sky_color, "
         "horizon_color, error_color, limit_color, redshift_sky, other_side_color, spectrum, "
         "singularity_color)"},
        {BASE "observer: {}\n", "scene.yml:10:1: observer: ",
         "duplicate key 'observer' (first given at line 5, column 1)"},
        {"metric: {m: 1, a: 0, q: 0, m: 2}\n" OBSL, "scene.yml:1:28: metric.m: ", "duplicate key 'm'"},
        {BASE "[a]: 1\n", "scene.yml:10:1: ", "expected a key name, got a list of 1 item"},
        {"observer: {r: 30, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:1:1: missing required key 'metric'", ""},
        {"metric: {m: 1, a: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:1:1: metric: missing required key 'q'", ""},
        {"metric:\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:1:1: metric: missing required key 'm'", ""},
        {"metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, Theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:19: unknown key 'Theta' in observer", "roll, pitch, yaw, hfov, vfov"},
        /* wrong node types */
        {"metric: 5\n" OBSL, "scene.yml:1:9: metric: ", "expected a mapping of keys, got \"5\""},
        {"metric: [1, 0, 0]\n" OBSL, "scene.yml:1:9: metric: ", "got a list of 3 items"},
        {"metric: &a [*a]\n" OBSL, "scene.yml:1:9: metric: ", "expected a mapping of keys"},
        {BASE "accretion: [1]\n", "scene.yml:10:12: accretion: ", "expected a mapping of keys"},
        {BASE "spheres: 5\n", "scene.yml:10:10: spheres: ",
         "expected a list of spheres, got \"5\""},
        {BASE "spheres:\n  - 1\n", "scene.yml:11:5: spheres[0]: ", "expected a mapping of keys"},
        {BASE "sphere: [1]\n", "scene.yml:10:9: sphere[0]: ", "expected a mapping of keys"},
    };
    (void)state;
    check_errors(cases, sizeof cases / sizeof cases[0]);
}

static void test_errors_values(void **state)
{
    static const err_case cases[] = {
        {BASE "redshift_sky: 2\n", "scene.yml:10:15: redshift_sky: ", "expected true or false"},
        /* numbers */
        {MET("nan"), "scene.yml:2:6: metric.m: ", "expected a finite number, got \"nan\""},
        {MET(".nan"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET("inf"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET(".inf"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET("-.Inf"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET("Infinity"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET("1e999"), "scene.yml:2:6: metric.m: ",
         "expected a finite number, got \"1e999\""},
        {MET("-1e400"), "scene.yml:2:6: metric.m: ", "expected a finite number"},
        {MET("1 kg"), "scene.yml:2:6: metric.m: ",
         "expected a plain number without a unit, got \"1 kg\""},
        {BASE "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 3 deg}\n",
         "scene.yml:10:82: sphere[0].radius: ", "without a unit"},
        {MET("one"), "scene.yml:2:6: metric.m: ", "expected a number, got \"one\""},
        {MET("0x10"), "scene.yml:2:6: metric.m: ", "expected a number"},
        {MET("1,5"), "scene.yml:2:6: metric.m: ", "expected a number"},
        {MET("\"\""), "scene.yml:2:6: metric.m: ", "expected a number, got \"\""},
        {"metric:\n  m:\n  a: 0\n  q: 0\n" OBSL, "scene.yml:2:", "metric.m: expected a number, got nothing"},
        {MET("\"1\\0\""), "scene.yml:2:6: metric.m: ", "got \"1\\x00\""},
        {MET("{x: 1}"), "scene.yml:2:6: metric.m: ", "got a mapping"},
        {MET("[1, 2]"), "scene.yml:2:6: metric.m: ",
         "expected a number or an animation [linear, start, end], got a list of 2 items"},
        {MET("[]"), "scene.yml:2:6: metric.m: ", "got an empty list"},
        /* animations */
        {MET("[cubic, 0, 1]"), "scene.yml:2:7: metric.m[0]: ",
         "unknown animation \"cubic\""},
        {MET("[linear, 0]"), "scene.yml:2:6: metric.m: ",
         "expected an animation [linear, start, end], got a list of 2 items"},
        {MET("[linear, 0, 1, 2]"), "scene.yml:2:6: metric.m: ", "got a list of 4"},
        {MET("[linear, 0, x]"), "scene.yml:2:18: metric.m[2]: ",
         "expected a number, got \"x\""},
        {MET("[linear, 1 pi, 2]"), "scene.yml:2:15: metric.m[1]: ", "without a unit"},
        {MET("[linear, [linear, 0, 1], 2]"), "scene.yml:2:15: metric.m[1]: ",
         "expected a number, got a list of 3 items"},
        /* angles */
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  theta: 90 grad\n" OBS_REST,
         "scene.yml:3:10: observer.theta: ",
         "unknown angle unit 'grad' (expected deg, rad or pi), got \"90 grad\""},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  theta: inf deg\n" OBS_REST,
         "scene.yml:3:10: observer.theta: ", "expected a finite angle, got \"inf deg\""},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  theta: 1e308 pi\n" OBS_REST,
         "scene.yml:3:10: observer.theta: ", "expected a finite angle"},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  theta: pi\n" OBS_REST,
         "scene.yml:3:10: observer.theta: ", "expected an angle like 90"},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  theta: 90 deg deg\n" OBS_REST,
         "scene.yml:3:10: observer.theta: ", "expected an angle like 90"},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  phi: [linear, 0, 2 pie]\n  r: 30\n  theta: 90\n  hfov: 70\n",
         "scene.yml:3:20: observer.phi[2]: ", "unknown angle unit 'pie'"},
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  r: 30 deg\n  theta: 90\n  phi: 0\n  hfov: 70\n", "scene.yml:3:6: observer.r: ",
         "expected a plain number without a unit, got \"30 deg\""},
        {"metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70, "
         "roll: [linear, a, b]}\n",
         "scene.yml:2:63: observer.roll[1]: ", "expected an angle"},
        /* colours */
        {BASE "sky_color: [1, 2]\n", "scene.yml:10:12: sky_color: ",
         "expected a colour [R, G, B], got a list of 2 items"},
        {BASE "sky_color: [1, 2, 3, 4]\n", "scene.yml:10:12: sky_color: ", "got a list of 4"},
        {BASE "sky_color: red\n", "scene.yml:10:12: sky_color: ", "got \"red\""},
        {BASE "horizon_color: {r: 1}\n", "scene.yml:10:16: horizon_color: ", "got a mapping"},
        {BASE "sky_color: [1, 2, 256]\n", "scene.yml:10:19: sky_color[2]: ",
         "expected a colour component, an integer from 0 to 255, got \"256\""},
        {BASE "error_color: [1, -1, 2]\n", "scene.yml:10:18: error_color[1]: ",
         "an integer from 0 to 255, got \"-1\""},
        {BASE "sky_color: [1, 2, 2.5]\n", "scene.yml:10:19: sky_color[2]: ", "got \"2.5\""},
        {BASE "sky_color: [1, 2, [linear, 0, 255]]\n", "scene.yml:10:19: sky_color[2]: ",
         "got a list of 3 items"},
        {BASE "sky_color: [1, 2, 99999999999999999999999]\n", "scene.yml:10:19: sky_color[2]: ",
         "from 0 to 255"},
        /* accretion */
        {BASE "accretion:\n  resolution: [2, 12]\n  radius: [6, 15]\n",
         "scene.yml:10:1: accretion: missing required key 'color1'", ""},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  radius: [6, 15]\n",
         "scene.yml:10:1: accretion: missing required key 'resolution'", ""},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n",
         "scene.yml:10:1: accretion: missing required key 'radius'", ""},
        {BASE "accretion:\n", "scene.yml:10:1: accretion: missing required key 'color1'", ""},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2.5, 12]\n  radius: [6, 15]\n",
         "scene.yml:12:16: accretion.resolution[0]: ",
         "expected a positive integer, got \"2.5\""},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 0]\n  radius: [6, 15]\n",
         "scene.yml:12:19: accretion.resolution[1]: ", "expected a positive integer, got \"0\""},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 1e3]\n  radius: [6, 15]\n",
         "scene.yml:12:19: accretion.resolution[1]: ", "positive integer"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 3000000000]\n"
              "  radius: [6, 15]\n",
         "scene.yml:12:19: accretion.resolution[1]: ", "positive integer"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2]\n  radius: [6, 15]\n",
         "scene.yml:12:15: accretion.resolution: ",
         "expected a resolution [radial divisions, sectors], got a list of 1 item"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [[linear, 1, 2], 3]\n"
              "  radius: [6, 15]\n",
         "scene.yml:12:16: accretion.resolution[0]: ", "got a list of 3 items"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n  radius: [6]\n",
         "scene.yml:13:11: accretion.radius: ",
         "expected radii [inner, outer] (each a number or [linear, start, end])"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n"
              "  radius: [linear, 2, 6]\n",
         "scene.yml:13:11: accretion.radius: ", "got a list of 3 items"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n"
              "  radius: [6, 15 deg]\n",
         "scene.yml:13:15: accretion.radius[1]: ", "without a unit"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n"
              "  radius: [[linear, 2], 15]\n",
         "scene.yml:13:12: accretion.radius[0]: ",
         "expected an animation [linear, start, end], got a list of 2 items"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  resolution: [2, 12]\n  yaw: 10 grad\n"
              "  radius: [6, 15]\n",
         "scene.yml:13:8: accretion.yaw: ", "unknown angle unit 'grad'"},
        {BASE "accretion:\n  color1: [0, 255, 0]\n  color2: [0, 256, 0]\n  resolution: [2, 12]\n"
              "  radius: [6, 15]\n",
         "scene.yml:12:15: accretion.color2[1]: ", "from 0 to 255"},
        /* skymap */
        {BASE "skymap:\n  boundary: 20\n", "scene.yml:10:1: skymap: missing required key 'image'",
         ""},
        {BASE "skymap:\n  image: sky.png\n  boundary: -inf\n",
         "scene.yml:12:13: skymap.boundary: ",
         "expected a positive number or inf (the sky at infinity), got \"-inf\""},
        {BASE "skymap:\n  image: sky.png\n  boundary: [linear, 50, inf]\n",
         "scene.yml:12:26: skymap.boundary[2]: ",
         "inf (the sky at infinity) cannot be animated"},
        {BASE "skymap:\n  image: sky.png\n  boundary: nan\n",
         "scene.yml:12:13: skymap.boundary: ", "expected a finite number, got \"nan\""},
        {BASE "skymap:\n  image: sky.png\n  boundary: far\n",
         "scene.yml:12:13: skymap.boundary: ", "expected a number, got \"far\""},
        {BASE "skymap:\n  image: \"\"\n  boundary: 20\n", "scene.yml:11:10: skymap.image: ",
         "expected a non-empty text, got \"\""},
        {BASE "skymap:\n  image: [a.png]\n  boundary: 20\n", "scene.yml:11:10: skymap.image: ",
         "got a list of 1 item"},
        {BASE "skymap:\n  image: sky.png\n  boundary: 20 deg\n",
         "scene.yml:12:13: skymap.boundary: ", "without a unit"},
        {BASE "skymap:\n  image: sky.png\n  boundary: 20\n  size: 3\n",
         "scene.yml:13:3: unknown key 'size' in skymap",
         "(expected one of: image, boundary, other_side)"},
        /* spheres */
        {BASE "sphere:\n  color: [1, 2, 3]\n  resolution: [4, 8]\n  r: 10\n  theta: 90\n"
              "  phi: 0\n",
         "scene.yml:10:1: sphere[0]: missing required key 'radius'", ""},
        {BASE "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1}\n"
              "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: x}\n",
         "scene.yml:11:82: sphere[1].radius: ", "expected a number, got \"x\""},
        {BASE "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1, colour: [1, 1, 1]}\n",
         "scene.yml:10:85: unknown key 'colour' in sphere[0]",
         "(expected one of: color, resolution, r, theta, phi, roll, pitch, yaw, radius, motion, "
         "retrograde, omega, particle)"},
        {BASE "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1, r: 2}\n",
         "scene.yml:10:85: sphere[0].r: ", "duplicate key 'r' (first given at line 10, column "
                                         "48)"},
        {BASE "spheres:\n  - {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1}\n  - {color: [1, 2], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1}\n",
         "scene.yml:12:13: spheres[1].color: ", "expected a colour [R, G, B]"},
        {BASE "sphere: {color: [1, 2, 3], resolution: [0, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1}\n",
         "scene.yml:10:41: sphere[0].resolution[0]: ", "expected a positive integer"},
        {BASE "sphere: {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, "
              "radius: 1, yaw: 1 grad}\n",
         "scene.yml:10:90: sphere[0].yaw: ", "unknown angle unit"},
    };
    (void)state;
    check_errors(cases, sizeof cases / sizeof cases[0]);
}

static void test_errors_observer_at_infinity(void **state)
{
    static const err_case cases[] = {
        /* hfov / vfov with r: inf */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, hfov: 70}\n",
         "scene.yml:2:52: observer.hfov: ",
         "an observer at infinity (r: inf) has no field of view; give the width of its image "
         "plane with hextent"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:39: observer.hfov: ", "with hextent"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, vfov: 30}\n",
         "scene.yml:2:52: observer.vfov: ", "has no field of view"},
        /* hextent required */
        {"metric: {m: 1, a: 0, q: 0}\nobserver:\n  r: inf\n  theta: 90\n  phi: 0\n",
         "scene.yml:2:1: observer: missing required key 'hextent' (the observer at infinity, "
         "r: inf, needs the full width of its image plane",
         ""},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, vextent: 30}\n",
         "scene.yml:2:1: observer: missing required key 'hextent'", ""},
        /* hextent / vextent with a finite r */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: 30, theta: 90, phi: 0, hfov: 70, hextent: 40}\n",
         "scene.yml:2:48: observer.hextent: ",
         "applies only to the observer at infinity (r: inf); an observer at a finite r takes "
         "hfov (and vfov)"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: 30, theta: 90, phi: 0, hfov: 70, vextent: 40}\n",
         "scene.yml:2:48: observer.vextent: ", "applies only to the observer at infinity"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: 30, theta: 90, phi: 0, hextent: 40}\n",
         "scene.yml:2:38: observer.hextent: ", "applies only to the observer at infinity"},
        {"metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0}\n",
         "scene.yml:2:1: observer: missing required key 'hfov'", ""},
        /* inf is not animatable, -inf is no distance */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: [linear, inf, 30], theta: 90, phi: 0, hextent: 40}\n",
         "scene.yml:2:24: observer.r[1]: ",
         "inf (the observer at infinity) cannot be animated: write it as a plain value, or "
         "animate between finite numbers"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: [linear, 30, +Infinity], theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:28: observer.r[2]: ", "cannot be animated"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: -inf, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:15: observer.r: ",
         "expected a positive number or inf (the observer at infinity), got \"-inf\""},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: infinite, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:15: observer.r: ", "expected a number, got \"infinite\""},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: nan, theta: 90, phi: 0, hfov: 70}\n",
         "scene.yml:2:15: observer.r: ", "expected a finite number, got \"nan\""},
        /* only roll */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, pitch: 10}\n",
         "scene.yml:2:59: observer.pitch: ",
         "must be 0: an observer at infinity (r: inf) always looks at the hole and can only "
         "roll"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, yaw: [linear, 0, 10]}\n",
         "scene.yml:2:57: observer.yaw: ", "can only roll"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, yaw: 180}\n",
         "scene.yml:2:57: observer.yaw: ", "can only roll"},
        /* extents are numbers */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: wide}\n",
         "scene.yml:2:48: observer.hextent: ", "expected a number, got \"wide\""},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: inf}\n",
         "scene.yml:2:48: observer.hextent: ", "expected a finite number, got \"inf\""},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40 deg}\n",
         "scene.yml:2:48: observer.hextent: ", "without a unit"},
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: 90, phi: 0, hextent: 40, vextent: [linear, 1]}\n",
         "scene.yml:2:61: observer.vextent: ", "expected an animation [linear, start, end]"},
        /* inf stays an error for every other number */
        {"metric: {m: 1, a: 0, q: 0}\n"
         "observer: {r: inf, theta: inf, phi: 0, hextent: 40}\n",
         "scene.yml:2:27: observer.theta: ", "expected a finite angle"},
    };
    (void)state;
    check_errors(cases, sizeof cases / sizeof cases[0]);
}

static void test_errors_files(void **state)
{
    cr_scene s;
    cr_err e;
    (void)state;
    memset(&s, 0x5a, sizeof s);
    assert_int_equal(cr_scene_load(DATA "no_such_scene.yml", &s, &e), -1);
    assert_string_equal(e.msg, DATA "no_such_scene.yml: cannot open: No such file or directory");
    assert_null(s.path);
    assert_int_equal(cr_scene_load(DATA, &s, &e), -1); /* a folder */
    assert_starts(e.msg, DATA);
    assert_int_equal(cr_scene_load("", &s, &e), -1);
    assert_int_equal(cr_scene_load(NULL, &s, &e), -1);
}

/* Odd inputs never crash or leak (run under ASan/valgrind). */
static void test_odd_inputs(void **state)
{
    static const char *texts[] = {
        "metric: &a {m: *a, a: 0, q: 0}\n",
        "? [a, b]\n: c\n",
        "!!binary metric: 1\n",
        "metric: !!map {m: 1, a: 0, q: 0}\nobserver: !foo {r: 30, theta: 90, phi: 0, hfov: 70}\n",
        "%YAML 1.1\n---\nmetric: {m: 1, a: 0, q: 0}\n",
        "%YAML 9.9\n---\nmetric: {}\n",
        "metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n"
        "sphere: &s {color: [1, 2, 3], resolution: [4, 8], r: 10, theta: 90, phi: 0, radius: 1}\n"
        "sphere: *s\nspheres: [*s, *s]\n",
        "\xef\xbb\xbfmetric: {m: 1, a: 0, q: 0}\n",
        "metric: {m: 1, a: 0, q: 0}\r\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\r\n",
        "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]"
        "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n",
        "metric: {m: 1e-400, a: 0, q: 0}\nobserver: {r: 1e308, theta: 90, phi: 0, hfov: 70}\n",
        "metric: {m: [linear, -1e308, 1e308], a: 0, q: 0}\n"
        "observer: {r: 30, theta: 90, phi: 0, hfov: 70}\n",
        "metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n"
        "skymap: {image: /dev/null, boundary: 5}\n",
        "metric: {m: 1, a: 0, q: 0}\nobserver: {r: 30, theta: 90, phi: 0, hfov: 70}\n"
        "skymap: {image: \"a\\0b\", boundary: 5}\n",
    };
    char deep[20000];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        cr_scene s;
        cr_err e;
        if (load(texts[i], &s, &e) == 0) {
            cr_frame f;
            cr_sphere buf[MAX_SPHERES];
            int k;
            for (k = 0; k < 3; k++)
                (void)cr_scene_frame(&s, k, 3, 16, 16, NULL, &f, buf, &e);
            cr_scene_free(&s);
        } else {
            assert_true(strlen(e.msg) > 0);
        }
    }
    /* deep nesting */
    memset(deep, '[', sizeof deep / 2);
    memset(deep + sizeof deep / 2, ']', sizeof deep / 2 - 1);
    deep[sizeof deep - 1] = '\0';
    {
        cr_scene s;
        cr_err e;
        assert_int_equal(load(deep, &s, &e), -1);
    }
    /* every prefix of a full scene: truncated files */
    {
        char *text = NULL;
        long n;
        FILE *fp = fopen(DATA "scene_full.yml", "rb");
        assert_non_null(fp);
        fseek(fp, 0, SEEK_END);
        n = ftell(fp);
        fseek(fp, 0, SEEK_SET);
        text = malloc((size_t)n + 1);
        assert_non_null(text);
        assert_int_equal(fread(text, 1, (size_t)n, fp), (size_t)n);
        fclose(fp);
        for (i = 0; i <= (size_t)n; i++) {
            cr_scene s;
            cr_err e;
            if (cr_scene_load_string(text, i, NAME, &s, &e) == 0)
                cr_scene_free(&s);
        }
        free(text);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_minimal_defaults),
        cmocka_unit_test(test_keplerian_exposure_and_horizon),
        cmocka_unit_test(test_keplerian_auto_exposure),
        cmocka_unit_test(test_full_scene_file),
        cmocka_unit_test(test_angle_units),
        cmocka_unit_test(test_color2_default),
        cmocka_unit_test(test_animation),
        cmocka_unit_test(test_repeated_spheres),
        cmocka_unit_test(test_many_spheres),
        cmocka_unit_test(test_spheres_list_flow),
        cmocka_unit_test(test_listings),
        cmocka_unit_test(test_listing_7_1_1_values),
        cmocka_unit_test(test_frame_fields),
        cmocka_unit_test(test_vfov_default),
        cmocka_unit_test(test_frame_rejects_metric),
        cmocka_unit_test(test_frame_extremal_accepted),
        cmocka_unit_test(test_frame_rejects_observer),
        cmocka_unit_test(test_frame_on_axis_accepted),
        cmocka_unit_test(test_frame_rejects_fov),
        cmocka_unit_test(test_frame_rejects_objects),
        cmocka_unit_test(test_frame_bad_index),
        cmocka_unit_test(test_frame_objects_in_horizon_allowed),
        cmocka_unit_test(test_frame_rejects_settings),
        cmocka_unit_test(test_frame_eval_owns_spheres),
        cmocka_unit_test(test_keplerian_derived_once),
        cmocka_unit_test(test_observer_at_infinity),
        cmocka_unit_test(test_observer_at_infinity_rejects),
        cmocka_unit_test(test_skymap),
        cmocka_unit_test(test_error_exact_message),
        cmocka_unit_test(test_errors_syntax_and_shape),
        cmocka_unit_test(test_errors_values),
        cmocka_unit_test(test_errors_observer_at_infinity),
        cmocka_unit_test(test_errors_files),
        cmocka_unit_test(test_odd_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
