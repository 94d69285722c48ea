/* libFuzzer target: the scene loader (appendix E.4) and the per-frame checks.
 *
 * Each input is a scene file's text. It is loaded with cr_scene_load_string;
 * a scene that loads is evaluated for frames 0 and 1 of 2 at 4x4 pixels with
 * the default raytracer settings (cr_scene_frame, which includes
 * cr_frame_prepare). Besides crashes and sanitizer reports, the target aborts
 * when a contract of scene.h is broken: a failure without a message, a failed
 * load that leaves something in *out, or an accepted frame with non-finite
 * numbers (but observer.r and r_max of the observer at infinity, r: inf).
 *
 * Sky images are read from the file system (relative to the current folder).
 * They are not what is fuzzed here: an input naming a device or a pseudo-file
 * is skipped, so that no input can block on a terminal or a pipe, and stdin
 * is /dev/null. tests/fuzz/replay.c runs this same function over files in
 * ordinary builds (the regression test).
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/trace.h"
#include "input/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                             \
    do {                                                                                        \
        if (!(cond)) {                                                                          \
            fprintf(stderr, "fuzz_scene: contract broken: %s (line %d)\n", #cond, __LINE__);    \
            abort();                                                                            \
        }                                                                                       \
    } while (0)

/* 1 when text[0..n) contains word. */
static int contains(const uint8_t *text, size_t n, const char *word)
{
    size_t w = strlen(word), i;
    for (i = 0; i + w <= n; i++)
        if (memcmp(text + i, word, w) == 0)
            return 1;
    return 0;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    if (!freopen("/dev/null", "r", stdin))
        fclose(stdin);
    return 0;
}

static int all_zero(const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;
    for (i = 0; i < n; i++)
        if (b[i])
            return 0;
    return 1;
}

static void check_frame(const cr_frame *f, int n_spheres)
{
    int i;
    CHECK(f->width == 4 && f->height == 4);
    CHECK(f->metric.m > 0.0 && isfinite(f->metric.a) && isfinite(f->metric.q));
    CHECK(f->observer.theta >= 0.0 && f->observer.theta <= CR_PI);
    if (isinf(f->observer.r)) {
        /* the observer at infinity: an image plane of finite extents, no
         * field of view, only roll; the boundary is at infinity too */
        CHECK(f->observer.r > 0.0);
        CHECK(f->observer.hextent > 0.0 && isfinite(f->observer.hextent));
        CHECK(f->observer.vextent > 0.0 && isfinite(f->observer.vextent));
        CHECK(f->observer.hfov == 0.0 && f->observer.vfov == 0.0);
        CHECK(f->observer.pitch == 0.0 && f->observer.yaw == 0.0);
        CHECK(f->observer.motion == CR_MOTION_STATIC &&
              f->observer.projection == CR_PROJ_RECTILINEAR);
        CHECK(f->integrator != CR_INTEG_RK4);
        CHECK(isfinite(f->r_max) || f->r_max == INFINITY);
    } else {
        CHECK(isfinite(f->observer.r) && f->observer.r > 0.0);
        /* the largest field of view by projection (observer.projection): below 180
         * deg on the flat screen, up to 360 deg for the fisheye, 360 x 180
         * for the panorama */
        double fov_max = f->observer.projection == CR_PROJ_RECTILINEAR ? CR_PI
                                                                       : CR_TWO_PI * (1 + 1e-12);
        CHECK(f->observer.hfov > 0.0 && f->observer.hfov < fov_max);
        CHECK(f->observer.vfov > 0.0 && f->observer.vfov < fov_max);
        if (f->observer.motion != CR_MOTION_VELOCITY)
            CHECK(f->observer.v[0] == 0.0 && f->observer.v[1] == 0.0 && f->observer.v[2] == 0.0);
        CHECK(f->observer.v[0] * f->observer.v[0] + f->observer.v[1] * f->observer.v[1] +
                  f->observer.v[2] * f->observer.v[2] < 1.0);
        CHECK(isfinite(f->r_max));
        for (i = 0; i < 16; i++)
            CHECK(isfinite(f->tetrad[i / 4][i % 4]));
    }
    CHECK(f->tolerance > 0.0 && isfinite(f->tolerance));
    CHECK(f->sky_boundary >= 0.0 && isfinite(f->sky_boundary));
    CHECK(isfinite(f->r_stop));
    /* 1/u^t: negative between the horizons, where BL t runs backward along
     * the free fall (camera.h), and only there (inside r- it is positive
     * again), under mino */
    CHECK((f->obs_inside && !f->obs_inner ? f->obs_sqrt_mgtt < 0.0 : f->obs_sqrt_mgtt > 0.0) &&
          isfinite(f->obs_sqrt_mgtt));
    CHECK(!f->obs_inner || f->obs_inside);
    if (f->obs_inside)
        CHECK(f->integrator == CR_INTEG_MINO &&
              (f->obs_inner ? f->observer.r > 0.0 && f->observer.r < cr_metric_r_minus(&f->metric)
                            : f->observer.r > cr_metric_r_minus(&f->metric)) &&
              f->observer.r < cr_metric_r_plus(&f->metric) &&
              (f->observer.motion == CR_MOTION_INFALL ||
               f->observer.motion == CR_MOTION_VELOCITY));
    CHECK(isfinite(f->tan_half_h) && isfinite(f->tan_half_v));
    for (i = 0; i < 9; i++)
        CHECK(isfinite(f->cam[i / 3][i % 3]));
    CHECK(f->n_spheres == n_spheres);
    if (f->disc.enabled)
        CHECK(f->disc.r_in >= 0.0 && f->disc.r_in < f->disc.r_out);
    for (i = 0; i < f->n_spheres; i++)
        CHECK(f->spheres[i].radius > 0.0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cr_scene s;
    cr_err err;
    cr_frame f;
    cr_sphere *buf;
    int k;

    if (contains(data, size, "/dev") || contains(data, size, "/proc") ||
        contains(data, size, "/sys") || contains(data, size, "tty") ||
        contains(data, size, "/fd"))
        return 0;
    err.msg[0] = '\0';
    if (cr_scene_load_string((const char *)data, size, "fuzz.yml", &s, &err)) {
        CHECK(err.msg[0] != '\0');
        CHECK(memchr(err.msg, '\0', sizeof err.msg) != NULL);
        CHECK(all_zero(&s, sizeof s));
        return 0;
    }
    CHECK(s.n_spheres >= 0);
    CHECK(s.n_spheres == 0 || s.spheres != NULL);
    buf = malloc(sizeof *buf * (size_t)(s.n_spheres + 1));
    if (buf) {
        for (k = 0; k < 2; k++) {
            err.msg[0] = '\0';
            if (cr_scene_frame(&s, k, 2, 4, 4, NULL, &f, buf, &err))
                CHECK(err.msg[0] != '\0');
            else
                check_frame(&f, s.n_spheres);
        }
        free(buf);
    }
    cr_scene_free(&s);
    return 0;
}
