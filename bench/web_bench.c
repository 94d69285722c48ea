/* Per-ray cost of the web entry point's tracing (cr_web_trace, that is
 * cr_trace_pixel one ray a pixel), built natively and for wasm32 from this
 * one source (bench/web.sh). Traces every pixel of a W x H frame of a scene
 * set as the page sets it, `runs` times, and prints per run the wall and
 * process CPU time per ray (CLOCK_PROCESS_CPUTIME_ID; under Node's WASI that
 * is the process's CPU time too) and the steps, so that a loaded machine can
 * be read by CPU time.
 *
 * With "look" as the first argument it times cr_web_reproject instead: a
 * W x H view (the demo's observer, field of view 70 deg) from a 1024 x 512
 * equirectangular sky, one frame per yaw 0..runs-1 deg; per frame the wall
 * and CPU time in ms.
 *
 * Usage: web_bench demo|kerr|look W H runs
 *   demo: scenes/demo.yml (the page's start-up scene)
 *   kerr: a = 0.9 seen from r = 30 at 84 deg, keplerian disc to 18 M */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "wasm/web.h"

static double now(clockid_t c)
{
    struct timespec t;
    clock_gettime(c, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    const char *name = argc > 1 ? argv[1] : "demo";
    int w = argc > 2 ? atoi(argv[2]) : 320, h = argc > 3 ? atoi(argv[3]) : 180;
    int runs = argc > 4 ? atoi(argv[4]) : 3, r, n = w * h, k;
    cr_web *s = cr_web_new();
    int32_t *pix = malloc(sizeof *pix * (size_t)n);
    uint8_t *rgb = malloc(9 * (size_t)n), *out = malloc((size_t)n);
    double *val = malloc(4 * sizeof *val * (size_t)n);
    if (!s || !pix || !rgb || !out || !val || n < 1)
        return 1;
    cr_web_set(s, "metric.m", 1);
    cr_web_set(s, "observer.phi", 0);
    if (!strcmp(name, "look")) {
        cr_web *sky = cr_web_new();
        uint8_t *srgba = malloc(4 * 1024 * 512), *vrgba = malloc(4 * (size_t)n);
        if (!sky || !srgba || !vrgba)
            return 1;
        for (k = 0; k < 4 * 1024 * 512; k++)
            srgba[k] = (uint8_t)(k * 7);
        cr_web_set(sky, "metric.m", 1);
        cr_web_set(sky, "observer.r", 30);
        cr_web_set(sky, "observer.theta", 85);
        cr_web_set(sky, "observer.phi", 0);
        cr_web_set_word(sky, "observer.projection", "equirectangular");
        cr_web_set(s, "observer.r", 30);
        cr_web_set(s, "observer.theta", 85);
        cr_web_set(s, "observer.hfov", 70);
        if (cr_web_frame(sky, 1024, 512))
            return 1;
        printf("look %dx%d from 1024x512\n", w, h);
        for (r = 0; r < runs; r++) {
            double t0, c0;
            cr_web_set(s, "observer.yaw", r);
            t0 = now(CLOCK_MONOTONIC);
            c0 = now(CLOCK_PROCESS_CPUTIME_ID);
            if (cr_web_frame(s, w, h) || cr_web_reproject(s, sky, srgba, vrgba, runs < 0 ? 1 : CR_WEB_LOOK_CELL))
                return 1;
            printf("frame %d wall_ms %.2f cpu_ms %.2f\n", r, 1e3 * (now(CLOCK_MONOTONIC) - t0),
                   1e3 * (now(CLOCK_PROCESS_CPUTIME_ID) - c0));
        }
        return 0;
    }
    if (!strcmp(name, "demo")) {
        cr_web_set(s, "observer.r", 30);
        cr_web_set(s, "observer.theta", 85);
        cr_web_set(s, "observer.hfov", 70);
        cr_web_set(s, "accretion.enabled", 1);
        cr_web_set(s, "accretion.color1", 0x00ff00);
        cr_web_set(s, "accretion.n_radial", 2);
        cr_web_set(s, "accretion.n_sectors", 12);
        cr_web_set(s, "accretion.r_in", 6);
        cr_web_set(s, "accretion.r_out", 15);
        cr_web_set(s, "sky_color", 0xffffff);
        cr_web_set(s, "horizon_color", 0);
    } else {
        cr_web_set(s, "metric.a", 0.9);
        cr_web_set(s, "observer.r", 30);
        cr_web_set(s, "observer.theta", 84);
        cr_web_set(s, "observer.hfov", 45);
        cr_web_set(s, "accretion.enabled", 1);
        cr_web_set_word(s, "accretion.model", "keplerian");
        cr_web_set(s, "accretion.r_in", 0.0 / 0.0);
        cr_web_set(s, "accretion.r_out", 18);
        cr_web_set(s, "accretion.temperature", 9000);
    }
    if (cr_web_frame(s, w, h)) {
        fprintf(stderr, "%s\n", cr_web_message(s));
        return 1;
    }
    for (k = 0; k < n; k++)
        pix[k] = k;
    printf("scene %s %dx%d\n", name, w, h);
    for (r = 0; r < runs; r++) {
        double t0 = now(CLOCK_MONOTONIC), c0 = now(CLOCK_PROCESS_CPUTIME_ID), t1, c1;
        unsigned long check = 0;
        if (cr_web_trace(s, pix, n, rgb, out, val) != n)
            return 1;
        t1 = now(CLOCK_MONOTONIC);
        c1 = now(CLOCK_PROCESS_CPUTIME_ID);
        for (k = 0; k < n; k++)
            check += out[k] + rgb[9 * k];
        printf("run %d wall_ns_per_ray %.1f cpu_ns_per_ray %.1f check %lu\n", r,
               1e9 * (t1 - t0) / n, 1e9 * (c1 - c0) / n, check);
    }
    cr_web_free(s);
    free(pix);
    free(rgb);
    free(out);
    free(val);
    return 0;
}
