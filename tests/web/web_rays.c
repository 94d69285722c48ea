/* Random rays of random scenes through the web entry point (src/wasm/web.h),
 * one line per ray, for comparing the WebAssembly build with the native one
 * (tests/web/compare_rays.py). The same source is compiled natively and
 * for wasm32; both must print the same outcomes, and redshifts within
 * 1e-12 relative.
 *
 * Usage: web_rays [n_scenes [rays_per_scene [seed]]]   (default 100 100 1)
 * Lines: "S k msg" for a scene the evaluation refuses (its message), and
 * "R k i j outcome redshift hit_r hit_phi bolo rgb" for each ray, numbers
 * with 17 significant digits. A last line "T traced refused" counts them.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "wasm/web.h"

/* splitmix64: the same sequence on every target */
static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* uniform in [lo, hi) */
static double uni(uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(rng_next(s) >> 11) * (1.0 / 9007199254740992.0));
}

static int pick(uint64_t *s, int n)
{
    return (int)(rng_next(s) % (uint64_t)n);
}

/* A random scene: spin and charge with a horizon (some scenes refused on
 * purpose: near-extremal, inside the ergosphere, orbits that do not exist),
 * an observer near or far or at infinity with any motion and projection, a
 * chessboard or keplerian disc, spheres, a synthetic sky image. */
static void random_scene(cr_web *w, uint64_t *s)
{
    static const char *const motions[] = {"static", "zamo", "orbit", "infall", "velocity"};
    static const char *const projections[] = {"rectilinear", "fisheye", "equirectangular"};
    double a = uni(s, -0.99, 0.99), q = uni(s, 0.0, 0.5);
    int inf = pick(s, 8) == 0, k;
    double m = uni(s, 0.5, 2.0);
    cr_web_set(w, "metric.m", m);
    cr_web_set(w, "metric.a", a * m);
    cr_web_set(w, "metric.q", (a * a + q * q <= 1.0 ? q : 0.1) * m);
    cr_web_set(w, "observer.r", inf ? INFINITY : uni(s, 2.5, 60.0) * m);
    cr_web_set(w, "observer.theta", uni(s, 5.0, 175.0));
    cr_web_set(w, "observer.phi", uni(s, 0.0, 360.0));
    cr_web_set(w, "observer.roll", uni(s, -30.0, 30.0));
    cr_web_set(w, "observer.pitch", inf ? 0.0 : uni(s, -20.0, 20.0));
    cr_web_set(w, "observer.yaw", inf ? 0.0 : uni(s, -20.0, 20.0));
    cr_web_set(w, "observer.hfov", uni(s, 20.0, 100.0));
    cr_web_set(w, "observer.vfov", NAN);
    cr_web_set(w, "observer.hextent", uni(s, 10.0, 40.0) * m);
    cr_web_set(w, "observer.vextent", NAN);
    cr_web_set_word(w, "observer.motion", inf ? "static" : motions[pick(s, 5)]);
    cr_web_set(w, "observer.v_r", uni(s, -0.5, 0.5));
    cr_web_set(w, "observer.v_theta", uni(s, -0.4, 0.4));
    cr_web_set(w, "observer.v_phi", uni(s, -0.5, 0.5));
    cr_web_set(w, "observer.retrograde", pick(s, 2));
    cr_web_set_word(w, "observer.projection", inf ? "rectilinear" : projections[pick(s, 3)]);
    if (!inf && pick(s, 3) == 0)
        cr_web_set(w, "observer.hfov", uni(s, 120.0, 360.0));
    if (!inf && pick(s, 4) == 0)
        cr_web_set(w, "observer.theta", 90.0); /* orbits live in the equator */
    k = pick(s, 3);
    cr_web_set(w, "accretion.enabled", k > 0);
    if (k == 1) {
        cr_web_set_word(w, "accretion.model", "chessboard");
        cr_web_set(w, "accretion.color1", (double)(rng_next(s) & 0xffffff));
        cr_web_set(w, "accretion.color2", (double)(rng_next(s) & 0xffffff));
        cr_web_set(w, "accretion.n_radial", 1 + pick(s, 6));
        cr_web_set(w, "accretion.n_sectors", 1 + pick(s, 24));
        cr_web_set(w, "accretion.yaw", uni(s, 0.0, 90.0));
        cr_web_set(w, "accretion.r_in", uni(s, 1.0, 6.0) * m);
        cr_web_set(w, "accretion.r_out", uni(s, 8.0, 30.0) * m);
    } else if (k == 2) {
        cr_web_set_word(w, "accretion.model", "keplerian");
        cr_web_set(w, "accretion.r_in", pick(s, 2) ? NAN : uni(s, 3.0, 8.0) * m);
        cr_web_set(w, "accretion.r_out", uni(s, 12.0, 30.0) * m);
        cr_web_set(w, "accretion.retrograde", pick(s, 2));
        cr_web_set(w, "accretion.temperature", uni(s, 3e3, 3e4));
        cr_web_set_word(w, "accretion.inside_isco", "nothing");
    }
    cr_web_clear_spheres(w);
    for (k = pick(s, 3); k > 0; k--) {
        cr_web_add_sphere(w);
        cr_web_set(w, "sphere.color", (double)(rng_next(s) & 0xffffff));
        cr_web_set(w, "sphere.n_lat", 1 + pick(s, 8));
        cr_web_set(w, "sphere.n_lon", 1 + pick(s, 8));
        cr_web_set(w, "sphere.r", uni(s, 5.0, 20.0) * m);
        cr_web_set(w, "sphere.theta", uni(s, 30.0, 150.0));
        cr_web_set(w, "sphere.phi", uni(s, 0.0, 360.0));
        cr_web_set(w, "sphere.yaw", uni(s, 0.0, 90.0));
        cr_web_set(w, "sphere.radius", uni(s, 0.5, 3.0) * m);
    }
    if (pick(s, 2)) {
        int sw = 64, sh = 32, x, y;
        uint8_t *rgb = cr_web_sky(w, sw, sh);
        for (y = 0; y < sh && rgb; y++)
            for (x = 0; x < sw; x++) {
                rgb[3 * (y * sw + x)] = (uint8_t)(x * 4);
                rgb[3 * (y * sw + x) + 1] = (uint8_t)(y * 8);
                rgb[3 * (y * sw + x) + 2] = (uint8_t)(((x / 8 + y / 8) & 1) * 255);
            }
        cr_web_set(w, "skymap.boundary", pick(s, 2) ? INFINITY : uni(s, 40.0, 100.0) * m);
    } else {
        cr_web_sky(w, 0, 0);
    }
    cr_web_set(w, "redshift_sky", pick(s, 2));
}

int main(int argc, char **argv)
{
    int n_scenes = argc > 1 ? atoi(argv[1]) : 100;
    int n_rays = argc > 2 ? atoi(argv[2]) : 100;
    uint64_t s = argc > 3 ? (uint64_t)strtoull(argv[3], NULL, 10) : 1;
    const int width = 160, height = 90;
    long traced = 0, refused = 0;
    int k;
    for (k = 0; k < n_scenes; k++) {
        cr_web *w = cr_web_new();
        int r;
        if (!w)
            return 1;
        random_scene(w, &s);
        if (cr_web_frame(w, width, height)) {
            printf("S %d %s\n", k, cr_web_message(w));
            refused++;
            cr_web_free(w);
            k--; /* every traced scene counts: draw another */
            if (refused > 20L * n_scenes)
                return 1;
            continue;
        }
        for (r = 0; r < n_rays; r++) {
            int32_t p = (int32_t)pick(&s, width * height);
            uint8_t rgb[9], out;
            double v[4];
            if (cr_web_trace(w, &p, 1, rgb, &out, v) != 1)
                return 1;
            printf("R %d %d %d %d %.17g %.17g %.17g %.17g %02x%02x%02x%02x%02x%02x%02x%02x%02x\n",
                   k, p % width, p / width, out, v[0], v[1], v[2], v[3], rgb[0], rgb[1], rgb[2],
                   rgb[3], rgb[4], rgb[5], rgb[6], rgb[7], rgb[8]);
            traced++;
        }
        cr_web_free(w);
    }
    printf("T %ld %ld\n", traced, refused);
    return 0;
}
