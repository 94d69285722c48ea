/* The CPU backend is the reference for the GPU backend (DESIGN rule 3).
 *
 * One test body renders every case through cr_cpu_render and cr_gpu_render
 * and compares the images pixel by pixel, once for each integrator (mino and
 * rk4, the frame's integrator field). Cases: hand-built frames (the
 * Schwarzschild disc of listing 7.1.1 seen from theta = 85 deg, a Kerr
 * a = 0.998 disc, a Kerr-Newman scene with spheres and a sky texture, an
 * observer on the polar axis, and two observers at infinity: the a = 0.9
 * disc of the kerrz comparison (bench/kerrz.sh) on a +-20 M image plane, and a
 * Kerr-Newman scene with spheres and a sky texture at infinity) and frame 0
 * of every scene file in scenes/. The observer at infinity exists under mino
 * only (cr_trace_pixel traces it with mino whatever the frame's integrator
 * says, and the scene loader refuses rk4 there), so those cases run once.
 * Antialiasing (raytracer.samples) must do the same on both
 * backends: the moving-observer fisheye case again with 3 x 3 samples (the
 * image circle's edge is antialiased), and the scene files in bk_aa_scenes
 * (a Keplerian disc with plunging matter and physical inputs, mass in solar
 * masses and accretion rate in Eddington units) with 3 x 3 samples; these
 * run under mino only (the sub-rays go through the same cr_trace_point as
 * every ray, for either integrator) to keep the test short.
 *
 * Tolerance: outcome and colour identical for >= 99.9 % of the pixels. Device
 * code contracts multiply-adds into FMA and its sin/cos/atan2 round
 * differently from glibc, so a ray that passes within rounding error of an
 * edge may end on the other side of it: every mismatching pixel must lie on
 * an edge of the CPU image (a neighbour with another outcome, object or
 * colour). A mismatch where both backends hit the same face of the disc at
 * the same point (hit r relative and hit phi within BK_HIT_TOL) lies on a
 * colour boundary, such as a chessboard cell edge that a symmetric ray meets
 * at phi = 0 exactly: it is counted and printed apart ("same hit point") and
 * not held against the 0.1 %. Where both agree, the redshift must agree to
 * 1e-6 for >= 99.9 % of the pixels, and so must the bolometric brightness
 * bolo = g^4 F / F_max of Keplerian disc pixels (-1 elsewhere) to
 * BK_BOLO_TOL relative (of max(1, |bolo|)): with g to 1e-6, g^4 moves by
 * 4e-6 relative, and F(r) at a hit radius that differs by rounding by far
 * less. The first mismatches and the worst differences are printed.
 *
 * Without a usable CUDA device (or in a build without CUDA) the test prints
 * "SKIPPED: no CUDA device (<reason>)" and is reported as skipped. Setting
 * CURRAY_TEST_BACKENDS_CPU_AS_GPU=1 compares the CPU backend with itself
 * (one thread against all cores) instead, to exercise this test without a GPU.
 */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "render/cpu.h"
#include "render/gpu.h"
#include "input/scene.h"

#define BK_W 96
#define BK_H 64
#define BK_MAX_SPHERES 8
#define BK_MAX_REPORT 10
/* allowed fraction of mismatching pixels */
#define BK_MAX_MISMATCH 0.001
#define BK_Z_TOL 1e-6
#define BK_BOLO_TOL 1e-5
/* hit points closer than this (relative in r, radians in phi) are the same */
#define BK_HIT_TOL 1e-9

#define BK_DEG (CR_PI / 180.0)

typedef struct bk_case {
    char name[256];
    cr_frame f;
    cr_sphere spheres[BK_MAX_SPHERES];
    uint8_t *sky; /* owned procedural sky texture, or NULL */
} bk_case;

/* ---- hand-built frames -------------------------------------------------- */

static cr_rgb bk_rgb(int r, int g, int b)
{
    return cr_rgb_make(r, g, b);
}

/* Common part: metric, observer at (r, theta, phi = 0) with hfov 70 deg and
 * vfov by (E.4.1), white sky, black horizon, blue errors, default settings. */
static void bk_base(bk_case *c, const char *name, double m, double a, double q, double r,
                    double theta)
{
    cr_frame *f = &c->f;
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%s", name);
    f->metric.m = m;
    f->metric.a = a;
    f->metric.q = q;
    f->observer.r = r;
    f->observer.theta = theta;
    f->observer.hfov = 70.0 * BK_DEG;
    f->observer.vfov = 2.0 * atan(tan(0.5 * f->observer.hfov) * BK_H / BK_W);
    f->width = BK_W;
    f->height = BK_H;
    f->sky_color = bk_rgb(255, 255, 255);
    f->horizon_color = bk_rgb(0, 0, 0);
    f->error_color = bk_rgb(0, 0, 255);
    f->integrator = cr_trace_defaults().integrator;
    f->tolerance = cr_trace_defaults().tolerance;
    f->step_multiplier = cr_trace_defaults().step_multiplier;
    f->horizon_epsilon = cr_trace_defaults().horizon_epsilon;
    f->max_steps = cr_trace_defaults().max_steps;
    f->max_turns = cr_trace_defaults().max_turns;
}

/* The observer at infinity at inclination theta, with an image plane of
 * hextent M across (vextent by the image's aspect). */
static void bk_at_infinity(bk_case *c, double theta, double hextent)
{
    cr_frame *f = &c->f;
    f->observer.r = INFINITY;
    f->observer.theta = theta;
    f->observer.hfov = f->observer.vfov = 0.0;
    f->observer.hextent = hextent;
    f->observer.vextent = hextent * BK_H / BK_W;
}

/* Disc with color2 = 255 - color1 (E.4.2 with ERRATA 3). */
static void bk_disc(cr_frame *f, cr_rgb c1, int n_radial, int n_sectors, double r_in,
                    double r_out)
{
    f->disc.enabled = 1;
    f->disc.color1 = c1;
    f->disc.color2 = bk_rgb(255 - c1.r, 255 - c1.g, 255 - c1.b);
    f->disc.n_radial = n_radial;
    f->disc.n_sectors = n_sectors;
    f->disc.r_in = r_in;
    f->disc.r_out = r_out;
}

static void bk_sphere(bk_case *c, cr_rgb color, int n_lat, int n_lon, double r, double theta,
                      double phi, double radius, double roll, double pitch, double yaw)
{
    cr_sphere *s = &c->spheres[c->f.n_spheres++];
    memset(s, 0, sizeof *s);
    s->color = color;
    s->n_lat = n_lat;
    s->n_lon = n_lon;
    s->r = r;
    s->theta = theta;
    s->phi = phi;
    s->radius = radius;
    s->roll = roll;
    s->pitch = pitch;
    s->yaw = yaw;
    cr_sphere_prepare(s, c->f.metric.a);
    c->f.spheres = c->spheres;
}

/* Spheres in front of, beside (rotated) and behind the hole. */
static void bk_three_spheres(bk_case *c)
{
    bk_sphere(c, bk_rgb(0, 0, 255), 4, 8, 8.0, 90.0 * BK_DEG, 20.0 * BK_DEG, 2.0, 0.0, 0.0, 0.0);
    bk_sphere(c, bk_rgb(255, 128, 0), 6, 12, 10.0, 60.0 * BK_DEG, -50.0 * BK_DEG, 1.5,
              30.0 * BK_DEG, 20.0 * BK_DEG, 10.0 * BK_DEG);
    bk_sphere(c, bk_rgb(255, 0, 0), 4, 8, 12.0, 90.0 * BK_DEG, 180.0 * BK_DEG, 3.0, 0.0, 0.0,
              0.0);
}

/* A 64 x 32 equirectangular sky: a colour gradient with a chessboard;
 * boundary 0 puts it at infinity. */
static void bk_sky(bk_case *c, double boundary)
{
    int w = 64, h = 32, x, y;
    uint8_t *p = malloc((size_t)3 * w * h);
    assert_non_null(p);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int dark = ((x / 8) + (y / 8)) & 1;
            p[3 * (y * w + x) + 0] = (uint8_t)(x * 4);
            p[3 * (y * w + x) + 1] = (uint8_t)(y * 8);
            p[3 * (y * w + x) + 2] = (uint8_t)(dark ? 40 : 220);
        }
    c->sky = p;
    c->f.sky.rgb = p;
    c->f.sky.width = w;
    c->f.sky.height = h;
    c->f.sky_boundary = boundary;
}

/* Case k of the hand-built frames; 0 when k is past the last. */
static int bk_builtin(int k, bk_case *c)
{
    switch (k) {
    case 0: /* listing 7.1.1 at theta = 85 deg (figure 7.1.2) */
        bk_base(c, "schwarzschild disc, theta 85 deg (listing 7.1.1)", 1.0, 0.0, 0.0, 30.0,
                85.0 * BK_DEG);
        bk_disc(&c->f, bk_rgb(0, 255, 0), 2, 12, 6.0, 15.0);
        break;
    case 1: /* figure 7.2.2 with a = 0.998: frame dragging, flattened shadow */
        bk_base(c, "kerr a=0.998 disc, theta 85 deg", 1.0, 0.998, 0.0, 30.0, 85.0 * BK_DEG);
        bk_disc(&c->f, bk_rgb(0, 255, 0), 4, 24, 2.0, 15.0);
        break;
    case 2: /* spheres in front of, beside and behind a Kerr-Newman hole,
             * with a sky texture */
        bk_base(c, "kerr-newman spheres + sky texture", 1.0, 0.6, 0.3, 25.0, 80.0 * BK_DEG);
        bk_three_spheres(c);
        bk_sky(c, 40.0);
        break;
    case 3: /* observer on the polar axis looking down at a Kerr disc */
        bk_base(c, "kerr a=0.9 disc, observer on the axis", 1.0, 0.9, 0.0, 20.0, 0.0);
        bk_disc(&c->f, bk_rgb(255, 255, 0), 3, 16, 3.0, 12.0);
        break;
    case 4: /* bench/kerrz.sh's scene: a = 0.9, 85 deg, disc 6-15 M, +-20 M */
        bk_base(c, "kerr a=0.9 disc, observer at infinity, 85 deg", 1.0, 0.9, 0.0, 0.0, 0.0);
        bk_at_infinity(c, 85.0 * BK_DEG, 40.0);
        bk_disc(&c->f, bk_rgb(0, 255, 0), 3, 24, 6.0, 15.0);
        break;
    case 5: /* spheres and a sky at infinity, seen from infinity, rolled */
        bk_base(c, "kerr-newman spheres + sky at infinity, observer at infinity", 1.0, 0.6, 0.3,
                0.0, 0.0);
        bk_at_infinity(c, 70.0 * BK_DEG, 36.0);
        c->f.observer.roll = 20.0 * BK_DEG;
        bk_three_spheres(c);
        bk_sky(c, 0.0);
        break;
    case 6: /* an observer moving inside the ergosphere (0.5 c radially
             * in, 0.3 c along -phi, as the ZAMO measures) with a 270 deg
             * fisheye (its corners outside the image circle), a disc and a sky
             * at infinity; case 7: the same with 3 x 3 samples */
    case 7:
        bk_base(c,
                k == 6 ? "moving observer in the ergosphere, 270 deg fisheye"
                       : "moving observer in the ergosphere, 270 deg fisheye, 3x3 samples",
                1.0, 0.95, 0.0, 1.8, 70.0 * BK_DEG);
        c->f.samples = k == 6 ? 1 : 3;
        c->f.observer.motion = CR_MOTION_VELOCITY;
        c->f.observer.v[0] = -0.5;
        c->f.observer.v[2] = -0.3;
        c->f.observer.projection = CR_PROJ_FISHEYE;
        c->f.observer.hfov = 270.0 * BK_DEG;
        c->f.observer.vfov = c->f.observer.hfov * BK_H / BK_W;
        bk_disc(&c->f, bk_rgb(0, 255, 0), 3, 24, 2.0, 10.0);
        bk_sky(c, 0.0);
        break;
    default:
        return 0;
    }
    cr_frame_prepare(&c->f);
    return 1;
}

/* ---- scene files -------------------------------------------------------- */

static int bk_cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Sorted names of the *.yml / *.yaml files in dir; returns the count. */
static int bk_scene_files(const char *dir, char ***out)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char **names = NULL;
    int n = 0;
    *out = NULL;
    if (!d)
        return 0;
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        char **grown;
        if (!((len > 4 && strcmp(e->d_name + len - 4, ".yml") == 0) ||
              (len > 5 && strcmp(e->d_name + len - 5, ".yaml") == 0)))
            continue;
        grown = realloc(names, sizeof *names * (n + 1));
        assert_non_null(grown);
        names = grown;
        names[n] = strdup(e->d_name);
        assert_non_null(names[n]);
        n++;
    }
    closedir(d);
    if (n > 1)
        qsort(names, n, sizeof *names, bk_cmp_str);
    *out = names;
    return n;
}

/* Load the scene file at path. Returns 0, or -1 after printing why (then
 * nothing is left to free). */
static int bk_load_scene(const char *path, const char *name, cr_scene *s)
{
    cr_err err;
    if (cr_scene_load(path, s, &err) != 0) {
        printf("FAIL scenes/%s: cannot load: %s\n", name, err.msg);
        return -1;
    }
    if (s->n_spheres > BK_MAX_SPHERES) {
        printf("FAIL scenes/%s: %d spheres, this test handles %d\n", name, s->n_spheres,
               BK_MAX_SPHERES);
        cr_scene_free(s);
        return -1;
    }
    return 0;
}

/* Frame 0 of the loaded scene s, named name, with the given integrator and
 * samples x samples rays per pixel into c (the scene must stay loaded while
 * c is used: the sky texture is the scene's). Returns 0, or -1 after
 * printing why. */
static int bk_from_scene(const cr_scene *s, const char *name, int integrator, int samples,
                         bk_case *c)
{
    cr_trace_settings ts;
    cr_err err;
    memset(c, 0, sizeof *c);
    if (samples > 1)
        snprintf(c->name, sizeof c->name, "scenes/%s, %dx%d samples", name, samples, samples);
    else
        snprintf(c->name, sizeof c->name, "scenes/%s", name);
    ts.integrator = integrator;
    ts.tolerance = cr_trace_defaults().tolerance;
    ts.step_multiplier = cr_trace_defaults().step_multiplier;
    ts.horizon_epsilon = cr_trace_defaults().horizon_epsilon;
    ts.max_steps = cr_trace_defaults().max_steps;
    ts.max_turns = cr_trace_defaults().max_turns;
    ts.samples = samples;
    if (cr_scene_frame(s, 0, 1, BK_W, BK_H, &ts, &c->f, c->spheres, &err) != 0) {
        printf("FAIL %s: frame 0: %s\n", c->name, err.msg);
        return -1;
    }
    return 0;
}

/* Scene files rendered again with 3 x 3 samples: a Keplerian disc with
 * plunging matter inside the ISCO and physical inputs (mass_msun, mdot_edd),
 * whose Doppler-shifted colour, g and bolometric map must agree. */
static const char *const bk_aa_scenes[] = {"keplerian-face-on.yml"};

/* ---- the comparison ----------------------------------------------------- */

static int bk_same(const cr_pixel *a, const cr_pixel *b)
{
    return a->outcome == b->outcome && a->color.r == b->color.r && a->color.g == b->color.g &&
           a->color.b == b->color.b;
}

/* Pixel (i, j) of the reference image has a neighbour (8-neighbourhood) that
 * ended differently: another outcome, object or colour. */
static int bk_on_edge(const cr_pixel *img, int w, int h, int i, int j)
{
    const cr_pixel *p = &img[(size_t)j * w + i];
    int di, dj;
    for (dj = -1; dj <= 1; dj++)
        for (di = -1; di <= 1; di++) {
            const cr_pixel *q;
            if ((di == 0 && dj == 0) || i + di < 0 || i + di >= w || j + dj < 0 || j + dj >= h)
                continue;
            q = &img[(size_t)(j + dj) * w + i + di];
            if (!bk_same(p, q) || p->object != q->object)
                return 1;
        }
    return 0;
}

/* Both rays ended on the same face of the disc at the same point (hit r and
 * phi fix a point of the plane theta = pi/2), so a colour difference can only
 * come from a colour boundary through that point. */
static int bk_same_hit(const cr_pixel *a, const cr_pixel *b)
{
    double dphi;
    if (a->outcome != CR_OUT_DISC || b->outcome != CR_OUT_DISC || a->object != b->object)
        return 0;
    dphi = fabs(remainder(a->hit_phi - b->hit_phi, 2.0 * CR_PI));
    return fabs(a->hit_r - b->hit_r) <= BK_HIT_TOL * fabs(a->hit_r) && dphi <= BK_HIT_TOL;
}

static int bk_color_diff(const cr_pixel *a, const cr_pixel *b)
{
    int d = abs(a->color.r - b->color.r), e = abs(a->color.g - b->color.g),
        g = abs(a->color.b - b->color.b);
    return d > e ? (d > g ? d : g) : (e > g ? e : g);
}

static void bk_print_pixel(const char *who, const cr_pixel *p)
{
    printf("%s outcome %d object %d colour (%d,%d,%d) redshift %.12g steps %u", who,
           p->outcome, p->object, p->color.r, p->color.g, p->color.b, p->redshift, p->steps);
}

/* Compare image got against the reference ref of frame f; print a summary,
 * return the number of failed requirements (0 = pass). */
static int bk_compare(const char *name, const char *other, const cr_frame *f, const cr_pixel *ref,
                      const cr_pixel *got)
{
    int w = f->width, h = f->height, i, j, failures = 0;
    long n = (long)w * h, mismatch = 0, off_edge = 0, z_bad = 0, reported = 0, same_hit = 0;
    long bolo_bad = 0, n_bolo = 0;
    long count[CR_OUT_COUNT_] = {0};
    double worst_dz = 0.0, worst_db = 0.0;
    int worst_dz_i = -1, worst_dz_j = -1, worst_dc = 0, worst_dc_i = -1, worst_dc_j = -1;
    long max_bad = (long)floor(BK_MAX_MISMATCH * (double)n);

    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            const cr_pixel *a = &ref[(size_t)j * w + i], *b = &got[(size_t)j * w + i];
            if (a->outcome < CR_OUT_COUNT_)
                count[a->outcome]++;
            if (!bk_same(a, b)) {
                int edge = bk_on_edge(ref, w, h, i, j), dc = bk_color_diff(a, b);
                int boundary = bk_same_hit(a, b);
                if (boundary)
                    same_hit++;
                else
                    mismatch++;
                if (!edge)
                    off_edge++;
                if (dc > worst_dc) {
                    worst_dc = dc;
                    worst_dc_i = i;
                    worst_dc_j = j;
                }
                if (reported++ < BK_MAX_REPORT) {
                    printf("  mismatch at (%d,%d)%s%s:\n    ", i, j,
                           edge ? " on an edge" : " NOT ON AN EDGE",
                           boundary ? ", same hit point" : "");
                    bk_print_pixel("cpu:", a);
                    printf("\n    ");
                    bk_print_pixel(other, b);
                    printf("\n");
                }
            } else {
                double dz = fabs(a->redshift - b->redshift);
                double db = fabs(a->bolo - b->bolo) / fmax(1.0, fabs(a->bolo));
                if (!(dz <= BK_Z_TOL)) /* also catches NaN */
                    z_bad++;
                if (!(db <= BK_BOLO_TOL))
                    bolo_bad++;
                if (!(db <= worst_db))
                    worst_db = db;
                n_bolo += a->bolo >= 0.0;
                if (!(dz <= worst_dz)) {
                    worst_dz = dz;
                    worst_dz_i = i;
                    worst_dz_j = j;
                }
            }
        }

    printf("%s: %ld pixels (horizon %ld, disc %ld, sphere %ld, sky %ld, error %ld, limit %ld, "
           "outside %ld); "
           "%ld mismatch%s (%.3f %%, %ld off an edge) and %ld with the same hit point on a "
           "colour boundary; worst colour difference %d",
           name, n, count[CR_OUT_HORIZON], count[CR_OUT_DISC], count[CR_OUT_SPHERE],
           count[CR_OUT_SKY], count[CR_OUT_ERROR], count[CR_OUT_LIMIT], count[CR_OUT_OUTSIDE],
           mismatch,
           mismatch == 1 ? "" : "es", 100.0 * (double)mismatch / (double)n, off_edge, same_hit,
           worst_dc);
    if (worst_dc_i >= 0)
        printf(" at (%d,%d)", worst_dc_i, worst_dc_j);
    printf("; worst redshift difference %.3g", worst_dz);
    if (worst_dz_i >= 0)
        printf(" at (%d,%d)", worst_dz_i, worst_dz_j);
    printf(" (%ld above %g)", z_bad, BK_Z_TOL);
    if (n_bolo > 0)
        printf("; bolometric on %ld pixels, worst relative difference %.3g (%ld above %g)",
               n_bolo, worst_db, bolo_bad, BK_BOLO_TOL);
    printf("\n");

    if (mismatch > max_bad) {
        printf("FAIL %s: %ld mismatching pixels, at most %ld allowed\n", name, mismatch, max_bad);
        failures++;
    }
    if (off_edge > 0) {
        printf("FAIL %s: %ld mismatching pixels are not on an edge of the CPU image\n", name,
               off_edge);
        failures++;
    }
    if (z_bad > max_bad) {
        printf("FAIL %s: %ld pixels differ in redshift by more than %g\n", name, z_bad,
               BK_Z_TOL);
        failures++;
    }
    if (bolo_bad > max_bad) {
        printf("FAIL %s: %ld pixels differ in bolometric brightness by more than %g\n", name,
               bolo_bad, BK_BOLO_TOL);
        failures++;
    }
    return failures;
}

/* Render case c through the CPU and through the other backend (device >= 0:
 * that CUDA device; -1: the CPU again with one thread) and compare. */
static int bk_run_case(const bk_case *c, int device)
{
    char name[300];
    size_t n = (size_t)c->f.width * c->f.height;
    cr_pixel *ref = calloc(n, sizeof *ref), *got = calloc(n, sizeof *got);
    cr_err err;
    int failures;
    assert_non_null(ref);
    assert_non_null(got);
    if (cr_cpu_render(&c->f, 0, ref, NULL, NULL, NULL, &err) != 0)
        fail_msg("%s: cr_cpu_render: %s", c->name, err.msg);
    if (device >= 0) {
        if (cr_gpu_render(device, &c->f, got, &err) != 0)
            fail_msg("%s: cr_gpu_render: %s", c->name, err.msg);
    } else if (cr_cpu_render(&c->f, 1, got, NULL, NULL, NULL, &err) != 0) {
        fail_msg("%s: cr_cpu_render (1 thread): %s", c->name, err.msg);
    }
    snprintf(name, sizeof name, "%s [%s]", c->name,
             c->f.obs_at_inf || c->f.integrator == CR_INTEG_MINO ? "mino" : "rk4");
    failures = bk_compare(name, device >= 0 ? "gpu:" : "cpu1:", &c->f, ref, got);
    free(ref);
    free(got);
    return failures;
}

static void test_cpu_vs_gpu(void **state)
{
    cr_err err;
    const char *self = getenv("CURRAY_TEST_BACKENDS_CPU_AS_GPU");
    static const int integrators[] = {CR_INTEG_MINO, CR_INTEG_RK4};
    int device = -1, failures = 0, n_cases = 0, n_runs = 0, k, n_files, m;
    char **files;
    bk_case *c;
    (void)state;

    if (self && strcmp(self, "1") == 0) {
        printf("CURRAY_TEST_BACKENDS_CPU_AS_GPU=1: comparing the CPU backend with itself\n");
    } else {
        int count = cr_gpu_count(&err);
        if (count <= 0) {
            printf("SKIPPED: no CUDA device (%s)\n", err.msg);
            fflush(stdout);
            skip();
        }
        for (device = 0; device < 64; device++)
            if (cr_gpu_usable(device, NULL))
                break;
        assert_true(device < 64);
        printf("comparing the CPU backend with CUDA device #%d\n", device);
    }

    c = malloc(sizeof *c);
    assert_non_null(c);
    for (k = 0; bk_builtin(k, c); k++) {
        for (m = 0; m < 2; m++) {
            if ((c->f.obs_at_inf || c->f.samples > 1) && integrators[m] != CR_INTEG_MINO)
                continue; /* traced with mino whatever the field says; antialiasing: mino only */
            c->f.integrator = integrators[m];
            failures += bk_run_case(c, device);
            n_runs++;
        }
        free(c->sky);
        n_cases++;
    }

    n_files = bk_scene_files(CR_SOURCE_DIR "/scenes", &files);
    for (k = 0; k < n_files; k++) {
        char path[4096];
        cr_scene s;
        snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, files[k]);
        if (bk_load_scene(path, files[k], &s) == 0) {
            for (m = 0; m < 2; m++) {
                if (s.obs_at_infinity && integrators[m] != CR_INTEG_MINO)
                    continue;
                if (bk_from_scene(&s, files[k], integrators[m], 1, c) == 0)
                    failures += bk_run_case(c, device);
                else
                    failures++;
                n_runs++;
            }
            cr_scene_free(&s);
        } else {
            failures++;
        }
        free(files[k]);
        n_cases++;
    }
    free(files);

    for (k = 0; k < (int)(sizeof bk_aa_scenes / sizeof bk_aa_scenes[0]); k++) {
        char path[4096];
        cr_scene s;
        snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, bk_aa_scenes[k]);
        if (bk_load_scene(path, bk_aa_scenes[k], &s) != 0) {
            failures++;
            continue;
        }
        if (bk_from_scene(&s, bk_aa_scenes[k], CR_INTEG_MINO, 3, c) == 0)
            failures += bk_run_case(c, device);
        else
            failures++;
        n_runs++;
        n_cases++;
        cr_scene_free(&s);
    }
    free(c);
    printf("%d cases, %d renders compared, %d failed requirement%s\n", n_cases, n_runs,
           failures, failures == 1 ? "" : "s");
    assert_int_equal(failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cpu_vs_gpu),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
