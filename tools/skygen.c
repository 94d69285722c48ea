/* curray-skygen: deterministic equirectangular sky images (6.10).
 *
 *   curray-skygen stars OUT.png W H [seed]   star field with a faint galactic band
 *   curray-skygen grid  OUT.png W H          15 deg coordinate grid on coloured quadrants
 *
 * Pixel (x, y) covers the sky direction of (6.10.1): theta = y pi / H from the
 * +z pole down, phi = 2 pi - x 2 pi / W. Everything is computed from a fixed
 * PRNG (splitmix64) and the seed; no data files are read. The PNG is written
 * with zlib level 9 so that the images kept in scenes/ stay small.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/png_io.h"

#define SG_PI 3.14159265358979323846
#define SG_MAX_SIDE 32768

/* splitmix64: small, fast, and the same sequence everywhere. */
typedef struct sg_rng {
    uint64_t s;
} sg_rng;

static uint64_t sg_next(sg_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double sg_uniform(sg_rng *r)
{
    return (double)(sg_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

static double sg_clamp01(double v)
{
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

static uint8_t sg_byte(double v)
{
    return (uint8_t)lround(255.0 * sg_clamp01(v));
}

/* Unit direction of the centre of pixel (x, y). */
static void sg_direction(double x, double y, int w, int h, double d[3])
{
    double th = y * SG_PI / h;
    double ph = 2.0 * SG_PI - x * 2.0 * SG_PI / w;
    d[0] = sin(th) * cos(ph);
    d[1] = sin(th) * sin(ph);
    d[2] = cos(th);
}

/* --- smooth 3-D value noise, for the mottled galactic band --------------- */

static double sg_lattice(int64_t i, int64_t j, int64_t k, uint64_t seed)
{
    sg_rng r = {seed ^ ((uint64_t)i * 0x8da6b343u) ^ ((uint64_t)j * 0xd8163841u) ^
                ((uint64_t)k * 0xcb1ab31fu)};
    return (double)(sg_next(&r) >> 11) * (1.0 / 9007199254740992.0);
}

static double sg_smooth(double t)
{
    return t * t * (3.0 - 2.0 * t);
}

static double sg_noise(const double p[3], uint64_t seed)
{
    double f[3], u[3], v = 0.0;
    int64_t c[3];
    for (int a = 0; a < 3; a++) {
        double fl = floor(p[a]);
        c[a] = (int64_t)fl;
        f[a] = p[a] - fl;
        u[a] = sg_smooth(f[a]);
    }
    for (int corner = 0; corner < 8; corner++) {
        int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
        double wgt = (dx ? u[0] : 1.0 - u[0]) * (dy ? u[1] : 1.0 - u[1]) *
                     (dz ? u[2] : 1.0 - u[2]);
        v += wgt * sg_lattice(c[0] + dx, c[1] + dy, c[2] + dz, seed);
    }
    return v;
}

/* --- star field ---------------------------------------------------------- */

/* Band plane normal (tilted about 40 deg from +z) and a bright centre in it. */
static const double sg_band_n[3] = {0.42261826, -0.45315389, 0.78488557};
static const double sg_band_c[3] = {0.75470958, 0.65605903, 0.0};

/* 0..1: how close direction d lies to the galactic band. */
static double sg_band(const double d[3])
{
    double s = d[0] * sg_band_n[0] + d[1] * sg_band_n[1] + d[2] * sg_band_n[2];
    double a = asin(s < -1.0 ? -1.0 : s > 1.0 ? 1.0 : s); /* angle off the plane */
    return exp(-(a / 0.16) * (a / 0.16));
}

static void sg_add_star(float *img, int w, int h, double x, double y, double sigma,
                        const double col[3], double flux)
{
    /* An equirectangular image stretches the sky by 1/sin(theta) in x; the
     * blob is stretched alike so that the star is round on the sky. */
    double th = y * SG_PI / h;
    double st = sin(th);
    double sx = sigma / (st > 0.05 ? st : 0.05);
    double sy = sigma;
    int rx, ry;

    if (sx > 40.0)
        sx = 40.0;
    rx = (int)ceil(3.0 * sx);
    ry = (int)ceil(3.0 * sy);
    for (int j = (int)floor(y) - ry; j <= (int)floor(y) + ry; j++) {
        if (j < 0 || j >= h)
            continue;
        double dy = (j + 0.5 - y) / sy;
        for (int i = (int)floor(x) - rx; i <= (int)floor(x) + rx; i++) {
            double dx = (i + 0.5 - x) / sx;
            double g = flux * exp(-0.5 * (dx * dx + dy * dy));
            int ii = ((i % w) + w) % w; /* wraps around phi */
            float *p = img + 3 * ((size_t)j * w + ii);
            for (int c = 0; c < 3; c++)
                p[c] += (float)(g * col[c]);
        }
    }
}

static uint8_t *sg_stars(int w, int h, uint64_t seed)
{
    static const double tints[5][3] = {
        {0.70, 0.80, 1.00}, /* blue-white */
        {0.88, 0.92, 1.00},
        {1.00, 1.00, 1.00}, /* white */
        {1.00, 0.90, 0.72}, /* yellow */
        {1.00, 0.72, 0.48}, /* orange-red */
    };
    float *img = calloc((size_t)w * h * 3, sizeof *img);
    uint8_t *rgb = malloc((size_t)w * h * 3);
    sg_rng rng = {seed};
    double scale = (double)w * h / (2048.0 * 1024.0);
    long n_stars = (long)(5000.0 * scale);

    if (!img || !rgb) {
        free(img);
        free(rgb);
        return NULL;
    }
    if (n_stars < 300)
        n_stars = 300;

    /* Background: blue-black, a little lighter along the band, which is
     * mottled by two octaves of smooth noise and brightest near its centre. */
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            double d[3], p1[3], p2[3];
            sg_direction(x + 0.5, y + 0.5, w, h, d);
            for (int a = 0; a < 3; a++) {
                p1[a] = 4.0 * d[a] + 11.0;
                p2[a] = 11.0 * d[a] + 23.0;
            }
            double band = sg_band(d);
            double cdot = d[0] * sg_band_c[0] + d[1] * sg_band_c[1] + d[2] * sg_band_c[2];
            double core = exp(-2.5 * (1.0 - cdot));
            double mott = 0.55 * sg_noise(p1, seed) + 0.45 * sg_noise(p2, seed + 1);
            double glow = band * (0.35 + 0.65 * core) * (0.3 + 0.9 * mott);
            float *p = img + 3 * ((size_t)y * w + x);
            p[0] = (float)(0.010 + 0.16 * glow);
            p[1] = (float)(0.014 + 0.15 * glow);
            p[2] = (float)(0.035 + 0.17 * glow);
        }
    }

    /* Stars: uniform on the sphere, twice as dense along the band, most of
     * them faint (a power law in flux). */
    for (long s = 0; s < n_stars;) {
        double z = 2.0 * sg_uniform(&rng) - 1.0;
        double ph = 2.0 * SG_PI * sg_uniform(&rng);
        double u = sg_uniform(&rng);
        double t = sg_uniform(&rng);
        double keep = sg_uniform(&rng);
        double d[3] = {sqrt(1.0 - z * z) * cos(ph), sqrt(1.0 - z * z) * sin(ph), z};
        if (keep > 0.5 + 0.5 * sg_band(d))
            continue;
        double flux = 0.12 / pow(0.02 + u, 0.85);
        double sigma = 0.55 + 0.25 * (flux > 4.0 ? 4.0 : flux);
        double x = (2.0 * SG_PI - ph) * w / (2.0 * SG_PI);
        double y = acos(z) * h / SG_PI;
        sg_add_star(img, w, h, x, y, sigma, tints[(int)(t * 5.0) % 5], flux);
        s++;
    }

    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        rgb[i] = sg_byte(img[i]);
    free(img);
    return rgb;
}

/* --- coordinate grid ----------------------------------------------------- */

/* Distance in pixels from v (degrees) to the nearest multiple of 15 deg,
 * given the pixels per degree. */
static double sg_line_dist(double deg, double px_per_deg)
{
    double m = fmod(deg, 15.0);
    if (m < 0.0)
        m += 15.0;
    return (m < 7.5 ? m : 15.0 - m) * px_per_deg;
}

static uint8_t *sg_grid(int w, int h)
{
    /* Quadrants of phi 0-90, 90-180, 180-270, 270-360 deg. */
    static const double quad[4][3] = {
        {0.80, 0.22, 0.22}, /* red */
        {0.22, 0.65, 0.25}, /* green */
        {0.22, 0.35, 0.82}, /* blue */
        {0.85, 0.70, 0.15}, /* yellow */
    };
    uint8_t *rgb = malloc((size_t)w * h * 3);
    if (!rgb)
        return NULL;

    for (int y = 0; y < h; y++) {
        double th = (y + 0.5) * 180.0 / h;
        for (int x = 0; x < w; x++) {
            double ph = 360.0 - (x + 0.5) * 360.0 / w;
            int q = (int)floor(ph / 90.0) & 3;
            double c[3];
            for (int a = 0; a < 3; a++) /* north lighter, south darker */
                c[a] = th < 90.0 ? quad[q][a] + 0.4 * (1.0 - quad[q][a]) : 0.6 * quad[q][a];

            /* White lines every 15 deg, 1.5 px wide, 3 px for the equator and
             * the meridians phi = 0 and 180 deg; anti-aliased by coverage.
             * The poles themselves get no line. */
            double dth = sg_line_dist(th, h / 180.0);
            double dph = sg_line_dist(ph, w / 360.0);
            double near_eq = fabs(th - 90.0) * h / 180.0;
            double m180 = fmod(ph, 180.0);
            double near_m0 = fmin(m180, 180.0 - m180) * w / 360.0;
            double wth = near_eq < 2.0 ? 3.0 : 1.5;
            double wph = near_m0 < 2.0 ? 3.0 : 1.5;
            double cov = 0.0;
            if (th > 7.5 && th < 172.5)
                cov = sg_clamp01(wth / 2.0 + 0.5 - dth);
            cov = fmax(cov, sg_clamp01(wph / 2.0 + 0.5 - dph));
            uint8_t *p = rgb + 3 * ((size_t)y * w + x);
            for (int a = 0; a < 3; a++)
                p[a] = sg_byte(c[a] + cov * (1.0 - c[a]));
        }
    }
    return rgb;
}

/* --- command line ---------------------------------------------------------- */

static void sg_usage(FILE *f)
{
    fprintf(f, "usage: curray-skygen stars OUT.png WIDTH HEIGHT [SEED]\n"
               "       curray-skygen grid OUT.png WIDTH HEIGHT\n"
               "Writes an equirectangular sky image (theta = y pi / H, phi = 2 pi - x 2 pi / W).\n");
}

static int sg_parse_side(const char *s, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < 2 || v > SG_MAX_SIDE)
        return -1;
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    int w, h, grid;
    unsigned long long seed = 1;
    uint8_t *rgb;
    cr_err err;

    if (argc >= 2 && (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help"))) {
        sg_usage(stdout);
        return 0;
    }
    if (argc < 5 || argc > 6 || (strcmp(argv[1], "stars") && strcmp(argv[1], "grid")) ||
        (!strcmp(argv[1], "grid") && argc != 5)) {
        sg_usage(stderr);
        return 2;
    }
    grid = !strcmp(argv[1], "grid");
    if (sg_parse_side(argv[3], &w) || sg_parse_side(argv[4], &h)) {
        fprintf(stderr, "curray-skygen: width and height must be integers in 2..%d\n",
                SG_MAX_SIDE);
        return 2;
    }
    if (argc == 6) {
        char *end;
        seed = strtoull(argv[5], &end, 10);
        if (end == argv[5] || *end != '\0') {
            fprintf(stderr, "curray-skygen: the seed must be a non-negative integer\n");
            return 2;
        }
    }
    rgb = grid ? sg_grid(w, h) : sg_stars(w, h, (uint64_t)seed);
    if (!rgb) {
        fprintf(stderr, "curray-skygen: out of memory for %d x %d pixels\n", w, h);
        return 1;
    }
    if (cr_png_write_level(argv[2], w, h, rgb, 9, &err) != 0) {
        fprintf(stderr, "curray-skygen: %s\n", err.msg);
        free(rgb);
        return 1;
    }
    free(rgb);
    return 0;
}
