/* Every scene in scenes/ renders with both integrators, and both agree with
 * a converged image (rk4 at a quarter or half of its default step).
 *
 * Reference: integrator rk4 with step_multiplier 1/128 (a quarter of the
 * default step of (6.6.1)), taken as the converged image; 1/64 (half the
 * default step) for an observer beyond REF_FAR_R, where rk4's steps grow in
 * number with the distance (at 1/128 the hot-spot scenes seen from r =
 * 1000 M took 131000 steps a ray, most of this test's time, too long for
 * CI's sanitizer runs). Compared with it:
 * mino at the default tolerance and rk4 at the default step_multiplier, all
 * other settings at their defaults, W x H pixels, frame 0 of each scene and,
 * when the scene is animated and CURRAY_TEST_FULL is set, also its middle
 * frame (frame 1 of 3; left out by default to keep the sanitizer runs of CI
 * short).
 *
 * Pixel class: the outcome; for a disc or sphere pixel also the object (disc
 * face, sphere index) and the colour (chessboard cell). Sky pixels are
 * compared by outcome only: a sky image's colour comes from the ray's
 * direction at the boundary (rk4) or its exact asymptotic direction (mino)
 * and may differ slightly; the sky colour agreement is printed, not required.
 *
 * Ill-conditioned pixels: where the scene puts a class boundary exactly
 * on a ray, the class is decided by rounding, and any two integrators (or
 * step sizes) may disagree there. Example: an observer in the disc plane
 * of a Schwarzschild hole (fig-8.1.1-axis, listing 7.1.1's middle frame)
 * sees every disc point at phi = pi exactly (each orbit plane contains the
 * observer, on the equator, so it meets the equator at phi = 0 and pi),
 * which is a sector boundary of the 12-sector chessboard. Such pixels are
 * found by rendering mino with the observer turned by +-DPHI about the axis
 * (an exact symmetry of hole and disc): a pixel whose class differs between
 * the two is ill-conditioned, and counts as agreeing when both the
 * reference's class and the compared image's class are among those two.
 *
 * Required, for each of the two images against the reference:
 * - at least 99.5 % of the pixels have the reference's class (or, where
 *   ill-conditioned, a class of the +-DPHI pair, as above);
 * - every pixel of another class borders (8-neighbourhood) a pixel of
 *   another class in the reference: differences only on class edges;
 * - no error pixels.
 * Printed per scene: the agreement fractions, the number of differing
 * pixels off an edge, the sky colour agreement, the render times and the
 * mean steps per ray.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/cpu.h"
#include "input/scene.h"
#include "input/sysconfig.h"
#include "testutil.h"

#define W 40
#define H 30
#define NPX (W * H)
#define THREADS 2
#define MAX_SPHERES 16
#define MIN_AGREEMENT 0.995
#define REF_DIV 128     /* the reference's step_multiplier is 1 / REF_DIV */
#define REF_DIV_FAR 64  /* ... for an observer beyond REF_FAR_R */
#define REF_FAR_R 500.0 /* M */
#define DPHI 1e-6 /* rad */

/* The images of one frame: the reference, the two compared with it, and
 * mino with the observer's phi -DPHI and +DPHI. */
enum { IMG_REF, IMG_MINO, IMG_RK4, IMG_MINUS, IMG_PLUS, IMG_N };
static const char *const img_name[IMG_N] = {"rk4/ref", "mino", "rk4", "mino-", "mino+"};

static int same_class(const cr_pixel *p, const cr_pixel *q)
{
    if (p->outcome != q->outcome)
        return 0;
    if (p->outcome != CR_OUT_DISC && p->outcome != CR_OUT_SPHERE)
        return 1;
    return p->object == q->object && p->color.r == q->color.r && p->color.g == q->color.g &&
           p->color.b == q->color.b;
}

/* Pixel (i, j) of img borders a pixel of another class. */
static int on_edge(const cr_pixel *img, int i, int j)
{
    int di, dj;
    for (dj = -1; dj <= 1; dj++)
        for (di = -1; di <= 1; di++) {
            if ((di == 0 && dj == 0) || i + di < 0 || i + di >= W || j + dj < 0 || j + dj >= H)
                continue;
            if (!same_class(&img[j * W + i], &img[(j + dj) * W + i + di]))
                return 1;
        }
    return 0;
}

static double seconds_since(const struct timespec *t0)
{
    struct timespec t1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (double)(t1.tv_sec - t0->tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0->tv_nsec);
}

/* Print the reference's classes (H horizon, D / d disc top / bottom face,
 * S sphere, . sky, E error, L limit) with the pixels where img differs
 * replaced by img's outcome (h, 1 / 2 disc top / bottom, s, k sky, e, l). */
static void print_map(const cr_pixel *ref, const cr_pixel *img)
{
    int i, j;
    for (j = 0; j < H; j++) {
        char line[W + 1];
        for (i = 0; i < W; i++) {
            const cr_pixel *a = &ref[j * W + i], *b = &img[j * W + i];
            int oa = a->outcome < CR_OUT_COUNT_ ? a->outcome : 0,
                ob = b->outcome < CR_OUT_COUNT_ ? b->outcome : 0;
            line[i] = ".HDS.EL"[oa];
            if (oa == CR_OUT_DISC && a->object)
                line[i] = 'd';
            if (!same_class(a, b)) {
                line[i] = "?h1skel"[ob];
                if (ob == CR_OUT_DISC && b->object)
                    line[i] = '2';
            }
        }
        line[W] = '\0';
        printf("    |%s|\n", line);
    }
}

/* Compare img with the reference ref (the pair minus, plus marks the
 * ill-conditioned pixels); print one line; return the number of failed
 * requirements. */
static int compare(const char *label, const char *name, const cr_pixel *ref, const cr_pixel *img,
                   const cr_pixel *minus, const cr_pixel *plus, double seconds)
{
    long differ = 0, off_edge = 0, errors = 0, sky = 0, sky_same = 0, steps = 0, ill = 0;
    int worst_sky = 0, i, j, failures = 0, first_i = -1, first_j = -1;
    double agree;
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            const cr_pixel *a = &ref[j * W + i], *b = &img[j * W + i];
            steps += b->steps;
            if (b->outcome == CR_OUT_ERROR)
                errors++;
            if (!same_class(a, b)) {
                const cr_pixel *m = &minus[j * W + i], *p = &plus[j * W + i];
                if (!same_class(m, p) && (same_class(a, m) || same_class(a, p)) &&
                    (same_class(b, m) || same_class(b, p))) {
                    ill++;
                    continue;
                }
                differ++;
                if (!on_edge(ref, i, j)) {
                    if (off_edge++ == 0) {
                        first_i = i;
                        first_j = j;
                    }
                }
            } else if (a->outcome == CR_OUT_SKY) {
                int d = abs(a->color.r - b->color.r), e = abs(a->color.g - b->color.g),
                    f = abs(a->color.b - b->color.b);
                d = d > e ? d : e;
                d = d > f ? d : f;
                sky++;
                sky_same += d == 0;
                worst_sky = d > worst_sky ? d : worst_sky;
            }
        }
    agree = 1.0 - (double)differ / NPX;
    printf("  %-45s %-4s vs the reference: %7.3f %% agree (%ld px differ, %ld off an edge; %ld "
           "ill-conditioned), sky colour same on %5.1f %% (max diff %d), %4.1f s, %5.0f "
           "steps/ray\n",
           label, name, 100.0 * agree, differ, off_edge, ill,
           sky > 0 ? 100.0 * (double)sky_same / (double)sky : 100.0, worst_sky, seconds,
           (double)steps / NPX);
    if (agree < MIN_AGREEMENT) {
        printf("FAIL %s, %s: %.3f %% of the pixels agree with the reference, at least %.1f %% required\n",
               label, name, 100.0 * agree, 100.0 * MIN_AGREEMENT);
        failures++;
    }
    if (off_edge > 0) {
        printf("FAIL %s, %s: %ld differing pixels are not on a class edge of the reference, the first "
               "at (%d,%d): reference outcome %d object %d colour (%d,%d,%d), %s outcome %d "
               "object %d colour (%d,%d,%d)\n",
               label, name, off_edge, first_i, first_j, ref[first_j * W + first_i].outcome,
               ref[first_j * W + first_i].object, ref[first_j * W + first_i].color.r,
               ref[first_j * W + first_i].color.g, ref[first_j * W + first_i].color.b, name,
               img[first_j * W + first_i].outcome, img[first_j * W + first_i].object,
               img[first_j * W + first_i].color.r, img[first_j * W + first_i].color.g,
               img[first_j * W + first_i].color.b);
        failures++;
    }
    if (errors > 0) {
        printf("FAIL %s, %s: %ld error pixels\n", label, name, errors);
        failures++;
    }
    if (failures > 0)
        print_map(ref, img);
    return failures;
}

/* Render frame k of n of scene s with each integrator and compare. */
static int check_frame(const cr_scene *s, const char *label, int k, int n, double *total)
{
    cr_sysconfig cfg;
    cr_sphere sp[MAX_SPHERES];
    cr_pixel *img[IMG_N];
    double secs[IMG_N];
    int m, failures = 0;
    int ref_div = !s->obs_at_infinity && fmax(s->obs_r.a, s->obs_r.b) > REF_FAR_R ? REF_DIV_FAR
                                                                                 : REF_DIV;
    cr_sysconfig_defaults(&cfg);
    for (m = 0; m < IMG_N; m++) {
        cr_trace_settings ts;
        cr_scene turned = *s; /* shallow: cr_scene_frame only reads it */
        cr_frame f;
        cr_err err;
        struct timespec t0;
        double dphi = m == IMG_MINUS ? -DPHI : m == IMG_PLUS ? DPHI : 0.0;
        turned.obs_phi.a += dphi;
        turned.obs_phi.b += dphi;
        ts.integrator = (m == IMG_REF || m == IMG_RK4) ? CR_INTEG_RK4 : CR_INTEG_MINO;
        ts.tolerance = cfg.raytracer.tolerance;
        ts.step_multiplier = m == IMG_REF ? 1.0 / ref_div : cfg.raytracer.step_multiplier;
        ts.horizon_epsilon = cfg.raytracer.horizon_epsilon;
        ts.max_steps = cfg.raytracer.max_steps;
        ts.max_turns = cfg.raytracer.max_turns;
        ts.samples = cfg.raytracer.samples;
        img[m] = calloc(NPX, sizeof *img[m]);
        assert_non_null(img[m]);
        if (cr_scene_frame(&turned, k, n, W, H, &ts, &f, sp, &err))
            fail_msg("%s: %s", label, err.msg);
        clock_gettime(CLOCK_MONOTONIC, &t0);
        if (cr_cpu_render(&f, THREADS, img[m], NULL, NULL, NULL, &err))
            fail_msg("%s, %s: %s", label, img_name[m], err.msg);
        secs[m] = seconds_since(&t0);
        *total += secs[m];
    }
    {
        long cnt[CR_OUT_COUNT_] = {0}, steps = 0;
        int i;
        for (i = 0; i < NPX; i++) {
            cnt[img[IMG_REF][i].outcome < CR_OUT_COUNT_ ? img[IMG_REF][i].outcome : 0]++;
            steps += img[IMG_REF][i].steps;
        }
        printf("%s: reference rk4/%d horizon %ld, disc %ld, sphere %ld, sky %ld, error %ld, "
               "limit %ld; %.1f s, %.0f steps/ray\n",
               label, ref_div, cnt[CR_OUT_HORIZON], cnt[CR_OUT_DISC], cnt[CR_OUT_SPHERE], cnt[CR_OUT_SKY],
               cnt[CR_OUT_ERROR], cnt[CR_OUT_LIMIT], secs[IMG_REF], (double)steps / NPX);
        if (cnt[CR_OUT_ERROR] > 0) {
            printf("FAIL %s: the reference has error pixels\n", label);
            failures++;
        }
    }
    for (m = IMG_MINO; m <= IMG_RK4; m++)
        failures += compare(label, img_name[m], img[IMG_REF], img[m], img[IMG_MINUS],
                            img[IMG_PLUS], secs[m]);
    for (m = 0; m < IMG_N; m++)
        free(img[m]);
    return failures;
}

/* Frames k of n and k2 of n2 of s differ (observer, disc or spheres). */
static int frames_differ(const cr_scene *s, int k, int n, int k2, int n2)
{
    cr_frame f, g;
    cr_sphere sf[MAX_SPHERES], sg[MAX_SPHERES];
    cr_err err;
    memset(sf, 0, sizeof sf);
    memset(sg, 0, sizeof sg);
    if (cr_scene_frame(s, k, n, W, H, NULL, &f, sf, &err) ||
        cr_scene_frame(s, k2, n2, W, H, NULL, &g, sg, &err))
        fail_msg("%s", err.msg);
    return memcmp(&f.metric, &g.metric, sizeof f.metric) != 0 ||
           memcmp(&f.observer, &g.observer, sizeof f.observer) != 0 ||
           memcmp(&f.disc, &g.disc, sizeof f.disc) != 0 ||
           memcmp(sf, sg, sizeof sf[0] * (size_t)s->n_spheres) != 0;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void test_integrators_agree(void **state)
{
    char *names[64];
    int n = 0, k, failures = 0, frames = 0;
    double total = 0.0;
    struct timespec t0;
    DIR *d = opendir(CR_SOURCE_DIR "/scenes");
    struct dirent *e;
    (void)state;
    assert_non_null(d);
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len > 4 && strcmp(e->d_name + len - 4, ".yml") == 0) {
            assert_true(n < 64);
            names[n] = strdup(e->d_name);
            assert_non_null(names[n]);
            n++;
        }
    }
    closedir(d);
    qsort(names, n, sizeof names[0], cmp_str);
    assert_true(n > 0);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (k = 0; k < n; k++) {
        char path[1024], label[256];
        cr_scene s;
        cr_err err;
        snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, names[k]);
        if (cr_scene_load(path, &s, &err))
            fail_msg("%s", err.msg);
        assert_true(s.n_spheres <= MAX_SPHERES);
        snprintf(label, sizeof label, "%s frame 0", names[k]);
        failures += check_frame(&s, label, 0, 1, &total);
        frames++;
        if (getenv("CURRAY_TEST_FULL") && frames_differ(&s, 0, 1, 1, 3)) {
            snprintf(label, sizeof label, "%s frame 1 of 3", names[k]);
            failures += check_frame(&s, label, 1, 3, &total);
            frames++;
        }
        cr_scene_free(&s);
        free(names[k]);
    }
    printf("%d scenes, %d frames at %dx%d, %.1f s rendering, %.1f s in all; %d failed "
           "requirement%s\n",
           n, frames, W, H, total, seconds_since(&t0), failures, failures == 1 ? "" : "s");
    assert_int_equal(failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_integrators_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
