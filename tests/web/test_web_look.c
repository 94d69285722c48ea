/* Looking around (cr_web_reproject): the interpolated camera mapping (cells
 * of CR_WEB_LOOK_CELL pixels) against the exact one (cell = 1) on a sky of
 * random colours, so that any change of sky pixel shows. Views: the demo's
 * rectilinear camera turned in yaw and pitch, a view past the pole (the
 * mapping's singular point), a 360-degree fisheye (its rim), an
 * equirectangular view rolled, a moving observer (a boosted tetrad). Every
 * pixel takes a sky pixel whose centre lies within 1.5 sky pixels (of
 * latitude, pi / SH) of the exact one's on the sphere, or the same black
 * where nothing is seen; at least 90 % take the very same one (nearest-pixel
 * sampling flips between neighbours where the interpolation moves a point
 * across a pixel edge; the measured fractions are printed).
 * Also: the exact mapping sees, at yaw = pitch = roll = 0 with an
 * equirectangular view of the sky's own size, every sky pixel at itself. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "wasm/web.h"

#define CR_PI_ 3.14159265358979323846
#define SW 1024
#define SH 512

static int fails;

static void check(int ok, const char *what)
{
    if (!ok) {
        printf("FAIL: %s\n", what);
        fails++;
    }
}

/* the sky pixel a colour came from: colours are the pixel index */
static long sky_index(const uint8_t *c)
{
    return (long)c[0] | (long)c[1] << 8 | (long)c[2] << 16;
}

/* angle between the centres of sky pixels i and j (radians) */
static double sky_angle(long i, long j)
{
    double lo1 = (i % SW + 0.5) * 2.0 * CR_PI_ / SW, la1 = CR_PI_ / 2 - (i / SW + 0.5) * CR_PI_ / SH;
    double lo2 = (j % SW + 0.5) * 2.0 * CR_PI_ / SW, la2 = CR_PI_ / 2 - (j / SW + 0.5) * CR_PI_ / SH;
    double c = sin(la1) * sin(la2) + cos(la1) * cos(la2) * cos(lo1 - lo2);
    return acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
}

static cr_web *observer(const char *motion, double theta)
{
    cr_web *w = cr_web_new();
    cr_web_set(w, "metric.m", 1);
    cr_web_set(w, "metric.a", 0.7);
    cr_web_set(w, "observer.r", 12);
    cr_web_set(w, "observer.theta", theta);
    cr_web_set(w, "observer.phi", 30);
    cr_web_set_word(w, "observer.motion", motion);
    cr_web_set(w, "observer.v_r", -0.3);
    cr_web_set(w, "observer.v_phi", 0.4);
    return w;
}

static void compare(const char *name, const char *motion, double theta, const char *proj,
                    double hfov, double roll, double pitch, double yaw, int w, int h,
                    const uint8_t *sky_rgba)
{
    cr_web *sky = observer(motion, theta), *view = observer(motion, theta);
    uint8_t *a = malloc(4 * (size_t)w * h), *b = malloc(4 * (size_t)w * h);
    long same = 0, near = 0, far = 0, k;
    char what[160];
    cr_web_set_word(sky, "observer.projection", "equirectangular");
    cr_web_set_word(view, "observer.projection", proj);
    cr_web_set(view, "observer.hfov", hfov);
    cr_web_set(view, "observer.roll", roll);
    cr_web_set(view, "observer.pitch", pitch);
    cr_web_set(view, "observer.yaw", yaw);
    if (!a || !b || cr_web_frame(sky, SW, SH) || cr_web_frame(view, w, h)) {
        printf("FAIL: %s: %s%s\n", name, cr_web_message(sky), cr_web_message(view));
        fails++;
        return;
    }
    check(cr_web_reproject(view, sky, sky_rgba, a, 1) == 0, "exact reprojection");
    check(cr_web_reproject(view, sky, sky_rgba, b, CR_WEB_LOOK_CELL) == 0, "cell reprojection");
    for (k = 0; k < (long)w * h; k++) {
        long ia = sky_index(a + 4 * k), ib = sky_index(b + 4 * k);
        int ka = a[4 * k + 3] == 254, kb = b[4 * k + 3] == 254; /* sky, not black */
        if (ka == kb && (!ka || ia == ib))
            same++;
        else if (ka && kb && sky_angle(ia, ib) <= 1.5 * CR_PI_ / SH)
            near++;
        else
            far++;
    }
    printf("%s: %dx%d, %ld same, %ld within 1.5 sky pixels, %ld farther (%.4f same)\n", name, w,
           h, same, near, far, (double)same / ((double)w * h));
    snprintf(what, sizeof what, "%s: at least 90%% the same sky pixel", name);
    check(same >= 0.9 * w * h, what);
    snprintf(what, sizeof what, "%s: every other pixel within 1.5 sky pixels", name);
    check(far == 0, what);
    cr_web_free(sky);
    cr_web_free(view);
    free(a);
    free(b);
}

int main(void)
{
    uint8_t *sky = malloc(4 * SW * SH);
    long k;
    if (!sky)
        return 1;
    for (k = 0; k < SW * SH; k++) {
        sky[4 * k] = (uint8_t)(k & 255);
        sky[4 * k + 1] = (uint8_t)((k >> 8) & 255);
        sky[4 * k + 2] = (uint8_t)(k >> 16);
        sky[4 * k + 3] = 254; /* not the black of "nothing" */
    }
    compare("rectilinear", "static", 85, "rectilinear", 70, 0, 0, 0, 1280, 720, sky);
    compare("rectilinear turned", "static", 85, "rectilinear", 50, 10, 25, 140, 640, 360, sky);
    compare("past the pole", "static", 20, "rectilinear", 90, 0, -70, 0, 640, 480, sky);
    compare("fisheye 360", "zamo", 60, "fisheye", 360, 0, 0, 30, 512, 512, sky);
    compare("equirectangular rolled", "static", 90, "equirectangular", 360, 30, 0, 0, 800, 400,
            sky);
    compare("moving observer", "velocity", 70, "rectilinear", 100, 5, 10, -60, 640, 360, sky);
    {
        /* identity: an equirectangular view of the sky's size maps onto itself */
        cr_web *s = observer("static", 80), *v = observer("static", 80);
        uint8_t *o = malloc(4 * SW * SH);
        long bad = 0;
        cr_web_set_word(s, "observer.projection", "equirectangular");
        cr_web_set_word(v, "observer.projection", "equirectangular");
        if (!o || cr_web_frame(s, SW, SH) || cr_web_frame(v, SW, SH) ||
            cr_web_reproject(v, s, sky, o, 1))
            return 1;
        for (k = 0; k < SW * SH; k++)
            bad += sky_index(o + 4 * k) != k;
        printf("identity: %ld of %d pixels elsewhere\n", bad, SW * SH);
        check(bad == 0, "identity reprojection");
        cr_web_free(s);
        cr_web_free(v);
        free(o);
    }
    free(sky);
    printf("%s\n", fails ? "FAILED" : "PASSED");
    return fails != 0;
}
