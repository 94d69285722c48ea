/* End-to-end test of every shipped scene (the .yml files in scenes/) -> loader -> CPU
 * backend -> the real writers (c_<k>.png, r_<k>.png, d_<k>.csv, info.txt) in
 * a temporary folder -> read back (cr_png_read, CSV parsed here) -> facts that
 * must hold by physics, not by comparison with earlier output.
 *
 * Every scene is rendered at 49x37 pixels (odd, so that the centre pixel looks
 * straight ahead and the centre row lies in the plane of e_r and e_phi), at
 * the frame of its figure when it is animated. Checked for every scene:
 * - no error or limit pixels;
 * - every pixel's err_mean and err_std (the error monitor) below 10x the
 *   largest measured (mino: 7 tol and 4 tol; rk4: 5e-7 and 4e-6);
 * - the files round-trip: PNG pixels == pixel colours, one CSV row per pixel
 *   in row order with the pixel's colour, steps, ratio (bit-exact) and
 *   outcome, info.txt with the frame's pixel counts; the redshift PNG is
 *   (6.9.1) of the CSV ratio, red (255,0,0) on the horizon, black on the sky;
 * - ratios: 0 on the horizon, 1/sqrt(-g_tt)|obs on the sky, and on a disc
 *   between the static values sqrt(-g_tt) at r_in and r_out (equatorial
 *   -g_tt = 1 - 2M/r + Q^2/r^2 for every Kerr-Newman hole);
 * - vfov from (E.4.1) when the scene gives none.
 * Scene by scene (numbers in the comments are for 49x37):
 * - 7.1.4: every disc pixel, traced again here by an independent loop (half
 *   the step, linear interpolation at the disc plane), has the ratio
 *   sqrt(1 - 2/r_hit)/sqrt(1 - 2/30), and the ratio grows with r_hit;
 * - 7.1.5: sky in the middle, horizon at the corners and, along the centre
 *   row, exactly outside the escape cone sin(psi) = 3 sqrt(3) sqrt(1-2/r)/r;
 *   blueshift (ratio > 1) on the far disc, up to the value at r = 15;
 * - 7.1.6 / 7.3.1 at phi = 180 deg (frame 18 of 36): an Einstein ring of
 *   the sphere round the horizon; the shadow's edge along the centre row at
 *   the analytic angle (b_c = 3 sqrt(3) M; 4 M for Q = M), so the Q = M
 *   shadow is smaller; at phi = 0 (frame 0) the sphere covers the centre;
 * - 7.2.1 (a = M) at theta = 85 deg: not mirror symmetric, and the flattened
 *   edge of the shadow is on the LEFT (ERRATA item 1);
 * - 7.1.3: no horizon pixel, the sphere's image edge is the photon-sphere
 *   shadow, every sphere pixel has the ratio of r = 2.1, and both poles of the
 *   sphere are seen, including points within 12 deg of each pole, which are
 *   hidden without lensing;
 * - 7.1.2: the shadow's edge along the centre row at the analytic angle,
 *   and a night sky of many colours from sky.png round it;
 * - the sky map (tests/data/scene_grid_sky_away.yml, grid sky, observer at
 *   r = 1000 looking away from the hole): each pixel shows the sky image at
 *   the direction it looks, per (6.10.1)-(6.10.4); shifting the observer's
 *   phi by 0.1 sky-image pixel changes sky colours only slightly (bilinear);
 * - animation: listing 7.1.1 with 3 frames has theta = 5, 90, 175 deg;
 *   frame 1 is up/down mirror symmetric (disc faces swapped), and frame 2 is
 *   frame 0 upside down, faces swapped.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "render/cpu.h"
#include "output/output.h"
#include "base/png_io.h"
#include "input/scene.h"
#include "input/sysconfig.h"
#include "testutil.h"
#include "testfs.h"

#define W 49
#define H 37
#define NPX (W * H)
#define CX (W / 2)
#define CY (H / 2)
#define MAX_SPHERES 16
#define THREADS 2
#define MAX_SHOTS 32
#define DEG (CR_PI / 180.0)

/* |a - b| <= tol, naming both values when not (cmocka 1.1.5 has no
 * assert_double_equal). */
#define assert_near(a, b, tol)                                                              \
    do {                                                                                    \
        double a_ = (a), b_ = (b);                                                          \
        if (!(fabs(a_ - b_) <= (tol)))                                                      \
            fail_msg("%s = %.17g, expected %.17g +- %g", #a, a_, b_, (double)(tol));        \
    } while (0)

/* --- one rendered frame, with its files read back ------------------------ */

typedef struct csv_row {
    int x, y, r, g, b;
    unsigned long steps;
    double z, err_mean, err_std;
    char outcome[16];
    double hit_r, hit_phi;
} csv_row;

typedef struct shot {
    char path[1024];
    int k, n;
    double dphi; /* added to the observer's phi (radians) */
    cr_scene scene;
    cr_frame f;
    cr_sphere sp[MAX_SPHERES];
    cr_pixel *px;
    uint8_t *c_png, *r_png; /* read back */
    csv_row *csv;           /* read back */
    char *info;             /* info.txt, read back */
    long long counts[CR_OUT_COUNT_];
    char dir[512];
    double seconds;
} shot;

static char g_tmp[256];
static shot *g_shots[MAX_SHOTS];
static int g_n_shots;

static int group_setup(void **state)
{
    (void)state;
    snprintf(g_tmp, sizeof g_tmp, "/tmp/cr_test_scenes_e2e.XXXXXX");
    return mkdtemp(g_tmp) ? 0 : -1;
}

static int group_teardown(void **state)
{
    int i;
    (void)state;
    for (i = 0; i < g_n_shots; i++) {
        shot *s = g_shots[i];
        cr_scene_free(&s->scene);
        free(s->px);
        free(s->c_png);
        free(s->r_png);
        free(s->csv);
        free(s->info);
        free(s);
    }
    g_n_shots = 0;
    cr_test_rm_rf(g_tmp);
    return 0;
}

static char *read_text(const char *path)
{
    FILE *fp = fopen(path, "rb");
    char *buf;
    long n;
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    buf = malloc((size_t)n + 1);
    if (buf) {
        n = (long)fread(buf, 1, (size_t)n, fp);
        buf[n] = '\0';
    }
    fclose(fp);
    return buf;
}

static csv_row *read_csv(const char *path)
{
    FILE *fp = fopen(path, "r");
    char line[512];
    csv_row *rows;
    int i = 0;
    if (!fp)
        fail_msg("%s is missing", path);
    rows = calloc(NPX, sizeof *rows);
    assert_non_null(fgets(line, sizeof line, fp));
    assert_string_equal(line,
                        "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,"
                        "bolometric,order,theta_turns,delay\n");
    while (fgets(line, sizeof line, fp)) {
        csv_row *r;
        if (i >= NPX)
            fail_msg("%s: more than %d rows", path, NPX);
        r = &rows[i++];
        if (sscanf(line, "%d,%d,%d,%d,%d,%lu,%lf,%lf,%lf,%15[a-z],%lf,%lf", &r->x, &r->y, &r->r,
                   &r->g, &r->b, &r->steps, &r->z, &r->err_mean, &r->err_std, r->outcome,
                   &r->hit_r, &r->hit_phi) != 12)
            fail_msg("%s: row %d unreadable: %s", path, i, line);
    }
    fclose(fp);
    if (i != NPX)
        fail_msg("%s: %d rows for %d pixels", path, i, NPX);
    return rows;
}

/* Render frame k of n of the scene file at path (observer phi + dphi), write
 * every output through the real writers into its own folder, read them back.
 * Frames are cached: the tests share them. */
static shot *render(const char *path, int k, int n, double dphi)
{
    cr_sysconfig cfg;
    cr_trace_settings ts;
    cr_frame_stats st;
    cr_run_info run;
    cr_err err;
    char file[1024];
    struct timespec t0, t1;
    shot *s;
    int w, h, i;

    for (i = 0; i < g_n_shots; i++)
        if (!strcmp(g_shots[i]->path, path) && g_shots[i]->k == k && g_shots[i]->n == n &&
            g_shots[i]->dphi == dphi)
            return g_shots[i];
    assert_true(g_n_shots < MAX_SHOTS);
    s = calloc(1, sizeof *s);
    snprintf(s->path, sizeof s->path, "%s", path);
    s->k = k;
    s->n = n;
    s->dphi = dphi;
    if (cr_scene_load(path, &s->scene, &err))
        fail_msg("%s", err.msg);
    assert_true(s->scene.n_spheres <= MAX_SPHERES);
    s->scene.obs_phi.a += dphi;
    s->scene.obs_phi.b += dphi;
    cr_sysconfig_defaults(&cfg);
    ts.integrator = cfg.raytracer.integrator;
    ts.tolerance = cfg.raytracer.tolerance;
    ts.step_multiplier = cfg.raytracer.step_multiplier;
    ts.horizon_epsilon = cfg.raytracer.horizon_epsilon;
    ts.max_steps = cfg.raytracer.max_steps;
    ts.max_turns = cfg.raytracer.max_turns;
    ts.samples = cfg.raytracer.samples;
    if (cr_scene_frame(&s->scene, k, n, W, H, &ts, &s->f, s->sp, &err))
        fail_msg("%s", err.msg);
    s->px = calloc(NPX, sizeof *s->px);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (cr_cpu_render(&s->f, THREADS, s->px, NULL, NULL, NULL, &err))
        fail_msg("%s: %s", path, err.msg);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    s->seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    for (i = 0; i < NPX; i++)
        s->counts[s->px[i].outcome < CR_OUT_COUNT_ ? s->px[i].outcome : CR_OUT_NONE]++;

    /* the real writers, as the CLI calls them */
    snprintf(s->dir, sizeof s->dir, "%s/%d", g_tmp, g_n_shots);
    assert_int_equal(mkdir(s->dir, 0700), 0);
    cr_frame_stats_compute(s->px, NPX, s->seconds, &st);
    st.frame = k;
    memset(&run, 0, sizeof run);
    run.scene_path = path;
    run.backend = "cpu (test)";
    run.width = W;
    run.height = H;
    run.frames = n;
    run.output_types = "icrd";
    run.version = "test";
    run.first = run.last = &s->f;
    {
        /* each per-frame type of "crd" through its row of the output table */
        cr_frame_output o = {s->dir, k, n, &s->f, s->px, &s->scene, NULL, 0};
        for (const char *t = "crd"; *t; t++)
            if (cr_output_type_find(*t)->write(&o, &err))
                fail_msg("%s: %c: %s", path, *t, err.msg);
    }
    if (cr_info_write(s->dir, &run, &s->scene, &cfg, &st, 1, &err))
        fail_msg("%s: %s", path, err.msg);

    /* read back */
    snprintf(file, sizeof file, "%s/c_%d.png", s->dir, k);
    if (cr_png_read(file, 0, &s->c_png, &w, &h, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    snprintf(file, sizeof file, "%s/r_%d.png", s->dir, k);
    if (cr_png_read(file, 0, &s->r_png, &w, &h, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    snprintf(file, sizeof file, "%s/d_%d.csv", s->dir, k);
    s->csv = read_csv(file);
    snprintf(file, sizeof file, "%s/info.txt", s->dir);
    s->info = read_text(file);
    if (!s->info)
        fail_msg("%s is missing", file);
    g_shots[g_n_shots++] = s;
    return s;
}

static shot *render_scene(const char *name, int k, int n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, name);
    return render(path, k, n, 0.0);
}

#define PX(s, i, j) ((s)->px[(j) * W + (i)])
#define OUT(s, i, j) ((int)PX(s, i, j).outcome)

/* --- analytic helpers ---------------------------------------------------- */

/* -g_tt at (r, theta), written out from (2.2.1). */
static double minus_gtt(double m, double a, double q, double r, double th)
{
    double sig = r * r + a * a * cos(th) * cos(th);
    return 1.0 - (2.0 * m * r - q * q) / sig;
}

/* Static-source ratio omega_r/omega_s of a source on the equator at r. */
static double z_eq(const cr_frame *f, double r)
{
    const cr_metric *mt = &f->metric;
    double src = minus_gtt(mt->m, mt->a, mt->q, r, 0.5 * CR_PI);
    double obs = minus_gtt(mt->m, mt->a, mt->q, f->observer.r, f->observer.theta);
    return src > 0.0 ? sqrt(src) / sqrt(obs) : 0.0;
}

/* Screen coordinates of pixel (i, j) (camera.h's documented mapping). */
static double screen_x(const cr_frame *f, int i)
{
    return (2.0 * (i + 0.5) / W - 1.0) * tan(0.5 * f->observer.hfov);
}

static double screen_y(const cr_frame *f, int j)
{
    return (1.0 - 2.0 * (j + 0.5) / H) * tan(0.5 * f->observer.vfov);
}

/* tan of the angular radius of the shadow of a static (a = 0) hole seen by a
 * static observer at r: sin(alpha) = b_c sqrt(-g_tt(r)) / r, with b_c the
 * impact parameter of the photon sphere r_ph = (3M + sqrt(9M^2 - 8Q^2))/2,
 * b_c = r_ph / sqrt(1 - 2M/r_ph + Q^2/r_ph^2). For r below the photon sphere
 * the same angle, measured from the outward direction, bounds the escape cone. */
static double shadow_tan(double m, double q, double r)
{
    double rph = 0.5 * (3.0 * m + sqrt(9.0 * m * m - 8.0 * q * q));
    double bc = rph / sqrt(1.0 - 2.0 * m / rph + q * q / (rph * rph));
    double s = bc * sqrt(1.0 - 2.0 * m / r + q * q / (r * r)) / r;
    return s / sqrt(1.0 - s * s);
}

/* (6.9.1), written out here. */
static void redshift_rgb(double z, int rgb[3])
{
    double b = 255.0 * atan(z) * 2.0 / CR_PI;
    rgb[0] = (int)lround(255.0 - b);
    rgb[1] = 0;
    rgb[2] = (int)lround(b);
}

static int rgb_is(const uint8_t *p, int r, int g, int b)
{
    return p[0] == r && p[1] == g && p[2] == b;
}

static int rgb_eq(cr_rgb c, cr_rgb d)
{
    return c.r == d.r && c.g == d.g && c.b == d.b;
}

/* --- an independent, simpler trace of one pixel -------------------------- */

/* Same initial ray as the renderer (camera.h), then RK4 at half the step
 * size with events found by linear interpolation between step ends (no root
 * finding). Returns the outcome and, for a disc, the hit radius, for a
 * sphere the Cartesian hit point. */
typedef struct mhit {
    int outcome;
    double r;      /* disc: BL radius of the hit */
    double x[3];   /* sphere: Cartesian hit point */
    int sphere;
} mhit;

static mhit manual_trace(const cr_frame *f, int i, int j)
{
    double n[3], y[CR_NY], y1[CR_NY], k1[CR_NY], u[4], x0[3], x1[3];
    cr_geo g;
    cr_metric_point p;
    mhit m;
    long step;
    int k, c;
    memset(&m, 0, sizeof m);
    m.sphere = -1;
    cr_camera_pixel_dir(f, i, j, n);
    cr_camera_ray(f, n, &g, y);
    for (step = 0; step < 4 * f->max_steps; step++) {
        double h;
        if (y[CR_Y_R] <= f->r_stop) {
            m.outcome = CR_OUT_HORIZON;
            return m;
        }
        cr_geo_rhs_full(&g, y, k1, u, &p);
        if (y[CR_Y_R] >= f->r_max && u[1] > 0.0) {
            m.outcome = CR_OUT_SKY;
            return m;
        }
        h = cr_geo_step_size(&g, 0.5 * f->step_multiplier, y[CR_Y_TH], u);
        cr_geo_rk4(&g, y, k1, h, y1);
        if (f->disc.enabled) {
            double v0 = y[CR_Y_TH] - 0.5 * CR_PI, v1 = y1[CR_Y_TH] - 0.5 * CR_PI;
            if (v0 * v1 < 0.0) {
                double s = v0 / (v0 - v1), r = y[CR_Y_R] + s * (y1[CR_Y_R] - y[CR_Y_R]);
                if (r >= f->disc.r_in && r <= f->disc.r_out) {
                    m.outcome = CR_OUT_DISC;
                    m.r = r;
                    return m;
                }
            }
        }
        cr_bl_to_cart(f->metric.a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], x0);
        cr_bl_to_cart(f->metric.a, y1[CR_Y_R], y1[CR_Y_TH], y1[CR_Y_PH], x1);
        for (k = 0; k < f->n_spheres; k++) {
            double f0 = cr_sphere_f(&f->spheres[k], x0), f1 = cr_sphere_f(&f->spheres[k], x1);
            if (f0 > 0.0 && f1 <= 0.0) {
                double s = f0 / (f0 - f1);
                for (c = 0; c < 3; c++)
                    m.x[c] = x0[c] + s * (x1[c] - x0[c]);
                m.outcome = CR_OUT_SPHERE;
                m.sphere = k;
                return m;
            }
        }
        cr_geo_through_axis(y1);
        memcpy(y, y1, sizeof y);
    }
    m.outcome = CR_OUT_LIMIT;
    return m;
}

/* --- every scene --------------------------------------------------------- */

/* The frame each shipped scene is checked at: its figure's frame when it is
 * animated, else its only frame. */
static const struct {
    const char *name;
    int k, n;
} g_frames[] = {
    {"demo.yml", 0, 1},
    {"grid-sky-kerr.yml", 0, 1},
    {"listing-7.1.1-schwarzschild-disc.yml", 8, 18}, /* theta = 85 deg, figure 7.1.2 */
    {"listing-7.1.2-starry-sky.yml", 0, 1},
    {"listing-7.1.3-sphere-around-horizon.yml", 0, 1},
    {"listing-7.1.4-redshift.yml", 0, 1},
    {"listing-7.1.5-blueshift.yml", 0, 1},
    {"listing-7.1.6-sphere-orbit.yml", 18, 36}, /* phi = 180 deg, figure 7.1.10 */
    {"listing-7.2.1-kerr-disc.yml", 8, 18},     /* theta = 85 deg, figure 7.2.2 */
    {"listing-7.3.1-reissner-nordstrom-sphere.yml", 18, 36}, /* figure 7.3.1 */
};
#define N_FRAMES ((int)(sizeof g_frames / sizeof g_frames[0]))

static const char *const g_outcome_words[CR_OUT_COUNT_] = {
    "none", "horizon", "disc", "sphere", "sky", "error", "limit", "outside"};

/* Round trip of the files and the facts every scene must satisfy. */
static void check_shot(const shot *s, const char *name)
{
    const cr_frame *f = &s->f;
    const cr_metric *mt = &f->metric;
    double obs = sqrt(minus_gtt(mt->m, mt->a, mt->q, f->observer.r, f->observer.theta));
    double z_sky = 1.0 / obs;
    char want[256];
    int i, k, bad_disc = 0, bad_sphere = 0;
    double zmin = 1e300, zmax = -1e300;
    /* Error monitor bounds: 10x the largest values measured over every
     * scene at 49x37 (mino: err_mean 0.67 tol, err_std 0.41 tol, at tol 1e-8
     * and 1e-7; rk4 at c = 1/32: err_mean 4.3e-8, err_std 3.7e-7). */
    const int mino = f->integrator == CR_INTEG_MINO;
    const double err_mean_max = mino ? 7.0 * f->tolerance : 5e-7;
    const double err_std_max = mino ? 4.0 * f->tolerance : 4e-6;
    double worst_mean = 0.0, worst_std = 0.0;

    /* a moving observer sees Doppler shifts: the sky's g is 1/E of
     * each ray (p.u_obs = 1 for the camera's rays, u_em static at infinity),
     * and sources are not bounded by the static range */
    const int moving = f->observer.motion != CR_MOTION_STATIC;

    /* vfov from (E.4.1) when the scene has none (the fisheye's is linear) */
    if (!s->scene.has_vfov && f->observer.projection == CR_PROJ_RECTILINEAR)
        assert_near(tan(0.5 * f->observer.vfov) / tan(0.5 * f->observer.hfov),
                            (double)H / W, 1e-12);
    if (!s->scene.has_vfov && f->observer.projection == CR_PROJ_FISHEYE)
        assert_near(f->observer.vfov / f->observer.hfov, (double)H / W, 1e-12);

    assert_int_equal(s->counts[CR_OUT_ERROR], 0);
    assert_int_equal(s->counts[CR_OUT_LIMIT], 0);
    assert_int_equal(s->counts[CR_OUT_NONE], 0);

    for (i = 0; i < NPX; i++) {
        const cr_pixel *p = &s->px[i];
        const csv_row *r = &s->csv[i];
        const uint8_t *c = s->c_png + 3 * i, *z = s->r_png + 3 * i;
        /* colour PNG and CSV against the pixel */
        assert_true(rgb_is(c, p->color.r, p->color.g, p->color.b));
        assert_int_equal(r->x, i % W);
        assert_int_equal(r->y, i / W);
        assert_true(r->r == p->color.r && r->g == p->color.g && r->b == p->color.b);
        assert_int_equal(r->steps, p->steps);
        assert_string_equal(r->outcome, g_outcome_words[p->outcome]);
        assert_true(r->z == p->redshift);
        assert_true(r->err_mean == p->err_mean && r->err_std == p->err_std);
        if (!(r->err_mean >= 0.0 && r->err_mean < err_mean_max && r->err_std >= 0.0 &&
              r->err_std < err_std_max))
            fail_msg("%s: pixel %d: err_mean %.3g, err_std %.3g, bounds %.3g, %.3g", name, i,
                     r->err_mean, r->err_std, err_mean_max, err_std_max);
        worst_mean = fmax(worst_mean, r->err_mean);
        worst_std = fmax(worst_std, r->err_std);
        /* hit point: exact in the CSV for disc and sphere pixels, -1 elsewhere */
        if (p->outcome == CR_OUT_DISC || p->outcome == CR_OUT_SPHERE) {
            assert_true(r->hit_r == p->hit_r && r->hit_phi == p->hit_phi);
            assert_true(r->hit_phi >= 0.0 && r->hit_phi < CR_TWO_PI);
            assert_true(r->hit_r >= f->r_stop);
        } else {
            assert_true(r->hit_r == -1.0 && r->hit_phi == -1.0);
        }

        switch (p->outcome) {
        case CR_OUT_OUTSIDE: {
            /* a fisheye pixel beyond the image circle of angular radius
             * max(hfov, vfov)/2, written here in pixels: not traced, black
             * everywhere, redshift -1 */
            double dx = (i % W + 0.5 - 0.5 * W) * f->observer.hfov / W,
                   dy = (i / W + 0.5 - 0.5 * H) * f->observer.vfov / H;
            assert_int_equal(f->observer.projection, CR_PROJ_FISHEYE);
            assert_true(hypot(dx, dy) > 0.5 * fmax(f->observer.hfov, f->observer.vfov));
            assert_true(r->z == -1.0 && p->steps == 0);
            assert_true(rgb_is(z, 0, 0, 0) && rgb_is(c, 0, 0, 0));
            break;
        }
        case CR_OUT_HORIZON:
            assert_true(r->z == 0.0);
            assert_true(rgb_is(z, 255, 0, 0));
            assert_true(rgb_eq(p->color, s->scene.horizon_color));
            break;
        case CR_OUT_SKY:
            if (moving) {
                double n[3], y[CR_NY];
                cr_geo g;
                cr_camera_pixel_dir(f, i % W, i / W, n);
                cr_camera_ray(f, n, &g, y);
                assert_near(r->z, 1.0 / g.E, 1e-10 / g.E);
            } else {
                assert_near(r->z, z_sky, 1e-12 * z_sky);
            }
            if (s->scene.redshift_sky && r->z >= 0.0) { /* the sky by its own z (6.9.1) */
                int want_rgb[3];
                redshift_rgb(r->z, want_rgb);
                assert_true(rgb_is(z, want_rgb[0], want_rgb[1], want_rgb[2]));
            } else {
                assert_true(rgb_is(z, 0, 0, 0));
            }
            if (!s->scene.has_sky)
                assert_true(rgb_eq(p->color, s->scene.sky_color));
            break;
        case CR_OUT_DISC:
        case CR_OUT_SPHERE: {
            int want_rgb[3];
            /* a Keplerian disc's or a moving sphere's g (moving matter) may
             * exceed the sky's */
            const int kep = p->outcome == CR_OUT_DISC && f->disc.model == CR_DISC_KEPLERIAN;
            const int spm = p->outcome == CR_OUT_SPHERE && f->spheres[p->object].moving;
            assert_true(r->z > 0.0 && (kep || spm || moving || r->z < z_sky));
            redshift_rgb(r->z, want_rgb);
            assert_true(rgb_is(z, want_rgb[0], want_rgb[1], want_rgb[2]));
            zmin = fmin(zmin, r->z);
            zmax = fmax(zmax, r->z);
            if (kep) {
                /* between the horizon (plunging matter) or r_in and r_out;
                 * g^4 F / F_max >= 0, and 0 with a black pixel inside r_in
                 * (zero flux) */
                bad_disc += !(p->hit_r >= f->disc.r_hit_in && p->hit_r <= f->disc.r_out);
                bad_disc += !(p->bolo >= 0.0);
                bad_disc += p->hit_r < f->disc.r_in &&
                            (p->bolo != 0.0 || p->color.r || p->color.g || p->color.b);
            } else if (p->outcome == CR_OUT_DISC) {
                cr_rgb acc = p->object ? s->scene.disc_color2 : s->scene.disc_color1;
                assert_true(p->object == 0 || p->object == 1);
                bad_disc += !(p->hit_r >= f->disc.r_in && p->hit_r <= f->disc.r_out);
                bad_disc += !moving && (r->z < z_eq(f, f->disc.r_in) - 1e-9 ||
                                        r->z > z_eq(f, f->disc.r_out) + 1e-9);
                assert_true(rgb_eq(p->color, acc) ||
                            (p->color.r == 128 && p->color.g == 128 && p->color.b == 128));
            } else {
                const cr_sphere *sp = &f->spheres[p->object];
                assert_true(p->object >= 0 && p->object < f->n_spheres);
                assert_true(rgb_eq(p->color, sp->color) ||
                            (p->color.r == 128 && p->color.g == 128 && p->color.b == 128));
                if (mt->a == 0.0 && !moving) { /* BL r is the Cartesian distance */
                    double dc = sqrt(sp->center[0] * sp->center[0] +
                                     sp->center[1] * sp->center[1] +
                                     sp->center[2] * sp->center[2]);
                    bad_sphere += r->z < z_eq(f, fmax(dc - sp->radius, f->r_stop)) - 1e-6 ||
                                  r->z > z_eq(f, dc + sp->radius) + 1e-6;
                    bad_sphere += p->hit_r < dc - sp->radius - 1e-9 * (dc + sp->radius) ||
                                  p->hit_r > dc + sp->radius + 1e-9 * (dc + sp->radius);
                }
            }
            break;
        }
        default:
            fail_msg("%s: pixel %d has outcome %d", name, i, p->outcome);
        }
    }
    assert_int_equal(bad_disc, 0);
    assert_int_equal(bad_sphere, 0);

    /* info.txt describes this frame */
    snprintf(want, sizeof want,
             "horizon %lld, disc %lld, sphere %lld, sky %lld, error %lld, limit %lld\n",
             s->counts[CR_OUT_HORIZON], s->counts[CR_OUT_DISC], s->counts[CR_OUT_SPHERE],
             s->counts[CR_OUT_SKY], s->counts[CR_OUT_ERROR], s->counts[CR_OUT_LIMIT]);
    if (s->counts[CR_OUT_OUTSIDE] > 0)
        snprintf(want + strlen(want) - 1, sizeof want - strlen(want) + 1,
                 ", outside the image %lld\n", s->counts[CR_OUT_OUTSIDE]);
    if (!strstr(s->info, want))
        fail_msg("%s: info.txt lacks '%s'", name, want);
    snprintf(want, sizeof want, "Finished 1 of %d frames", s->n);
    assert_non_null(strstr(s->info, want));
    snprintf(want, sizeof want, "Frame %d\n", s->k);
    assert_non_null(strstr(s->info, want));
    for (k = 0; k < f->n_spheres; k++)
        assert_true(f->spheres[k].radius > 0.0);
    print_message("%-44s frame %2d/%-2d %5.2f s: horizon %4lld disc %4lld sphere %4lld sky %4lld"
                  "; source ratio %.4f..%.4f, sky %.4f; err_mean <= %.2g, err_std <= %.2g\n",
                  name, s->k, s->n, s->seconds, s->counts[CR_OUT_HORIZON],
                  s->counts[CR_OUT_DISC], s->counts[CR_OUT_SPHERE], s->counts[CR_OUT_SKY],
                  zmin < 1e300 ? zmin : 0.0, zmax > -1e300 ? zmax : 0.0, z_sky, worst_mean,
                  worst_std);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void test_every_shipped_scene(void **state)
{
    char dirpath[1024], *names[64];
    DIR *d;
    struct dirent *e;
    int n = 0, i, j, listings = 0;
    (void)state;
    snprintf(dirpath, sizeof dirpath, "%s/scenes", CR_SOURCE_DIR);
    d = opendir(dirpath);
    assert_non_null(d);
    while ((e = readdir(d)) != NULL) {
        size_t l = strlen(e->d_name);
        if (l > 4 && !strcmp(e->d_name + l - 4, ".yml") && n < 64)
            names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, (size_t)n, sizeof names[0], cmp_str);
    /* the table names only existing scenes, so renamed files are noticed */
    for (j = 0; j < N_FRAMES; j++) {
        int found = 0;
        for (i = 0; i < n; i++)
            found |= !strcmp(names[i], g_frames[j].name);
        if (!found)
            fail_msg("scenes/%s is missing", g_frames[j].name);
    }
    for (i = 0; i < n; i++) {
        int k = 0, nf = 1;
        for (j = 0; j < N_FRAMES; j++)
            if (!strcmp(names[i], g_frames[j].name)) {
                k = g_frames[j].k;
                nf = g_frames[j].n;
            }
        listings += !strncmp(names[i], "listing-7.", 10);
        check_shot(render_scene(names[i], k, nf), names[i]);
        free(names[i]);
    }
    assert_true(listings >= 8); /* every listing of chapter 7, named in g_frames */
}

/* --- 7.1.4: redshift of a static disc ------------------------------------ */

typedef struct rz {
    double r, z;
} rz;

static int cmp_rz(const void *a, const void *b)
{
    double d = ((const rz *)a)->r - ((const rz *)b)->r;
    return (d > 0) - (d < 0);
}

static void test_redshift_listing_7_1_4(void **state)
{
    shot *s = render_scene("listing-7.1.4-redshift.yml", 0, 1);
    const cr_frame *f = &s->f;
    rz *list = calloc(NPX, sizeof *list);
    int i, j, n = 0, disc = 0, agree = 0, inversions = 0;
    double worst = 0.0, zmin = 1e9, zmax = -1e9;
    (void)state;
    assert_near(f->disc.r_in, 2.0, 0);
    assert_near(f->observer.r, 30.0, 0);
    assert_true(s->counts[CR_OUT_HORIZON] > 20);
    assert_true(s->counts[CR_OUT_SKY] > 20);
    /* centre: horizon (red in r_0.png), corners: sky (black) */
    assert_int_equal(OUT(s, CX, CY), CR_OUT_HORIZON);
    assert_true(rgb_is(s->r_png + 3 * (CY * W + CX), 255, 0, 0));
    assert_int_equal(OUT(s, 0, 0), CR_OUT_SKY);
    assert_true(rgb_is(s->r_png, 0, 0, 0));
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            double z = s->csv[j * W + i].z, zr;
            mhit m;
            if (OUT(s, i, j) != CR_OUT_DISC)
                continue;
            disc++;
            zmin = fmin(zmin, z);
            zmax = fmax(zmax, z);
            m = manual_trace(f, i, j);
            if (m.outcome != CR_OUT_DISC)
                continue;
            agree++;
            zr = sqrt(1.0 - 2.0 / m.r) / sqrt(1.0 - 2.0 / 30.0);
            worst = fmax(worst, fabs(z - zr));
            list[n].r = m.r;
            list[n].z = z;
            n++;
        }
    qsort(list, (size_t)n, sizeof *list, cmp_rz);
    for (i = 1; i < n; i++)
        inversions += list[i].z < list[i - 1].z - 1e-4;
    print_message("7.1.4: %d disc pixels, %d confirmed by the independent trace; hit r "
                  "%.3f..%.3f; ratio %.4f..%.4f (analytic r=2..15: 0..%.4f); worst |z - "
                  "sqrt(1-2/r)/sqrt(1-2/30)| = %.2e; %d inversions in r order\n",
                  disc, agree, n ? list[0].r : 0.0, n ? list[n - 1].r : 0.0, zmin, zmax,
                  z_eq(f, 15.0), worst, inversions);
    assert_true(disc > 100);
    assert_true(agree >= disc - disc / 50); /* edges may differ */
    assert_true(worst < 1e-3);
    assert_int_equal(inversions, 0);
    /* the whole analytic range is seen: outer edge, and close to the horizon */
    assert_true(zmax <= z_eq(f, 15.0) + 1e-9 && zmax > z_eq(f, 14.0));
    assert_true(zmin < z_eq(f, 3.0));
    free(list);
}

/* --- 7.1.5: looking out from r = 2.1 ------------------------------------- */

static void test_blueshift_listing_7_1_5(void **state)
{
    shot *s = render_scene("listing-7.1.5-blueshift.yml", 0, 1);
    const cr_frame *f = &s->f;
    double tc = shadow_tan(1.0, 0.0, 2.1), margin = 0.5 * (screen_x(f, 1) - screen_x(f, 0));
    double z15 = z_eq(f, 15.0), zmax = 0.0, zmin = 1e9;
    int i, j, blue = 0, inside = 0, outside = 0, horizon_out = 0;
    (void)state;
    /* sky (white) in the middle, the horizon round it: the top corners; the
     * bottom corners may see the disc just outside the horizon */
    assert_int_equal(OUT(s, CX, CY), CR_OUT_SKY);
    assert_true(rgb_is(s->c_png + 3 * (CY * W + CX), 255, 255, 255));
    assert_int_equal(OUT(s, 0, 0), CR_OUT_HORIZON);
    assert_int_equal(OUT(s, W - 1, 0), CR_OUT_HORIZON);
    /* the forward direction is e_r: a ray escapes exactly inside the cone
     * round it of half-angle psi_c; outside, it falls back into the hole
     * and can meet only the disc inside r = 3 (the photon sphere) */
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            double sx = screen_x(f, i), sy = screen_y(f, j), t = sqrt(sx * sx + sy * sy);
            int o = OUT(s, i, j);
            if (t < tc - margin) {
                assert_int_not_equal(o, CR_OUT_HORIZON);
                inside++;
            } else if (t > tc + margin) {
                assert_int_not_equal(o, CR_OUT_SKY);
                if (o == CR_OUT_DISC)
                    assert_true(s->csv[j * W + i].z < z_eq(f, 3.0));
                outside++;
                horizon_out += o == CR_OUT_HORIZON;
            }
        }
    for (i = 0; i < NPX; i++) {
        const uint8_t *rp = s->r_png + 3 * i;
        if (s->px[i].outcome == CR_OUT_HORIZON)
            assert_true(rgb_is(rp, 255, 0, 0));
        if (s->px[i].outcome != CR_OUT_DISC)
            continue;
        zmax = fmax(zmax, s->csv[i].z);
        zmin = fmin(zmin, s->csv[i].z);
        if (s->csv[i].z > 1.0) {
            blue++;
            assert_true(rp[2] > rp[0]); /* bluer than purple */
        }
    }
    print_message("7.1.5: escape cone psi_c = %.2f deg: %d pixels inside (none horizon), %d "
                  "outside (none sky, %d horizon); disc ratio %.3f..%.3f (r = 15: %.3f), %d "
                  "blueshifted disc pixels\n",
                  atan(tc) / DEG, inside, outside, horizon_out, zmin, zmax, z15, blue);
    assert_true(inside > NPX / 2 && horizon_out > 50);
    assert_true(blue > 100);
    assert_true(zmax <= z15 + 1e-9 && zmax > 0.95 * z15);
}

/* --- 7.1.6 and 7.3.1: sphere behind and in front of the hole -------------- */

/* Along the centre row, the horizon exactly inside the analytic shadow. */
static int shadow_row_check(const shot *s, double tan_alpha)
{
    double margin = 0.3 * (screen_x(&s->f, 1) - screen_x(&s->f, 0));
    int i, n = 0;
    for (i = 0; i < W; i++) {
        double sx = fabs(screen_x(&s->f, i));
        if (sx < tan_alpha - margin)
            assert_int_equal(OUT(s, i, CY), CR_OUT_HORIZON);
        else if (sx > tan_alpha + margin)
            assert_int_not_equal(OUT(s, i, CY), CR_OUT_HORIZON);
        n += OUT(s, i, CY) == CR_OUT_HORIZON;
    }
    return n;
}

/* An Einstein ring: walking from the centre up, down, left and right, the
 * outcomes run horizon, (sky between the shadow and the ring), sphere, sky
 * to the image's edge. */
static void ring_check(const shot *s)
{
    static const int dir[4][2] = {{0, -1}, {0, 1}, {-1, 0}, {1, 0}};
    static const int seq[4] = {CR_OUT_HORIZON, CR_OUT_SKY, CR_OUT_SPHERE, CR_OUT_SKY};
    int d;
    for (d = 0; d < 4; d++) {
        int i = CX, j = CY, stage = 0, run[4] = {0, 0, 0, 0};
        for (; i >= 0 && j >= 0 && i < W && j < H; i += dir[d][0], j += dir[d][1]) {
            while (stage < 4 && OUT(s, i, j) != seq[stage])
                stage++;
            if (stage == 4)
                fail_msg("ring: outcome %d at (%d, %d) out of order", OUT(s, i, j), i, j);
            run[stage]++;
        }
        assert_true(run[0] > 0 && run[2] > 0 && run[3] > 0);
    }
}

static void test_sphere_ring_listings_7_1_6_and_7_3_1(void **state)
{
    shot *front = render_scene("listing-7.1.6-sphere-orbit.yml", 0, 36);
    shot *behind = render_scene("listing-7.1.6-sphere-orbit.yml", 18, 36);
    shot *rn = render_scene("listing-7.3.1-reissner-nordstrom-sphere.yml", 18, 36);
    double ts = shadow_tan(1.0, 0.0, 25.0), tq = shadow_tan(1.0, 1.0, 25.0);
    double pitch = screen_x(&behind->f, 1) - screen_x(&behind->f, 0);
    int row_s, row_q;
    (void)state;
    assert_near(front->f.spheres[0].phi, 0.0, 0);
    assert_near(behind->f.spheres[0].phi, CR_PI, 1e-12);
    assert_near(rn->f.spheres[0].phi, CR_PI, 1e-12);
    /* in front: the sphere covers the centre */
    assert_int_equal(OUT(front, CX, CY), CR_OUT_SPHERE);
    /* behind: a ring round the horizon */
    ring_check(behind);
    ring_check(rn);
    row_s = shadow_row_check(behind, ts);
    row_q = shadow_row_check(rn, tq);
    print_message("7.1.6/7.3.1 at phi = 180: shadow radius %.2f px (Q = 0) and %.2f px "
                  "(Q = M) analytic; centre row horizon %d and %d px; horizon %lld and %lld "
                  "px (pi r^2: %.0f and %.0f); sphere %lld and %lld px\n",
                  ts / pitch, tq / pitch, row_s, row_q, behind->counts[CR_OUT_HORIZON],
                  rn->counts[CR_OUT_HORIZON], CR_PI * (ts / pitch) * (ts / pitch),
                  CR_PI * (tq / pitch) * (tq / pitch), behind->counts[CR_OUT_SPHERE],
                  rn->counts[CR_OUT_SPHERE]);
    assert_true(row_q < row_s);
    assert_true(rn->counts[CR_OUT_HORIZON] < behind->counts[CR_OUT_HORIZON]);
    /* the shadow areas follow the analytic radii */
    assert_true(fabs(behind->counts[CR_OUT_HORIZON] / (CR_PI * ts * ts / (pitch * pitch)) - 1.0) <
                0.1);
    assert_true(fabs(rn->counts[CR_OUT_HORIZON] / (CR_PI * tq * tq / (pitch * pitch)) - 1.0) <
                0.1);
}

/* --- 7.2.1: Kerr, a = M, theta = 85 deg ---------------------------------- */

static void test_kerr_listing_7_2_1(void **state)
{
    shot *s = render_scene("listing-7.2.1-kerr-disc.yml", 8, 18);
    int i, j, lo = W, hi = -1, mismatch = 0, left_row = 0, right_row = 0;
    (void)state;
    assert_near(s->f.observer.theta, 85.0 * DEG, 1e-12);
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            const cr_pixel *p = &PX(s, i, j), *q = &PX(s, W - 1 - i, j);
            mismatch += p->outcome != q->outcome || p->object != q->object;
            if (p->outcome == CR_OUT_HORIZON) {
                lo = i < lo ? i : lo;
                hi = i > hi ? i : hi;
            }
        }
    /* the extent of the shadow left and right of the centre in the centre row */
    for (i = CX; i >= 0 && OUT(s, i, CY) == CR_OUT_HORIZON; i--)
        left_row++;
    for (i = CX; i < W && OUT(s, i, CY) == CR_OUT_HORIZON; i++)
        right_row++;
    print_message("7.2.1 (a = M, theta = 85): mirror mismatch %.1f%%; shadow extends %d px "
                  "left and %d px right of the centre column (centre row: %d and %d)\n",
                  100.0 * mismatch / NPX, CX - lo, hi - CX, left_row, right_row);
    assert_true(mismatch > NPX / 50);
    /* flattened (prograde) edge on the left: closer to the centre */
    assert_true(hi - CX >= CX - lo + 3);
    assert_true(right_row >= left_row + 3);
}

/* --- 7.1.3: sphere just outside the horizon ------------------------------- */

static void test_sphere_around_horizon_listing_7_1_3(void **state)
{
    shot *s = render_scene("listing-7.1.3-sphere-around-horizon.yml", 0, 1);
    const cr_frame *f = &s->f;
    const cr_sphere *sp = &f->spheres[0];
    double ta = shadow_tan(1.0, 0.0, 10.0), z21 = z_eq(f, 2.1);
    double pitch = screen_x(f, 1) - screen_x(f, 0), colmin = 180.0, colmax = 0.0;
    int i, j, near_n = 0, near_s = 0, top = 0, bottom = 0, agree = 0, n = 0;
    (void)state;
    assert_near(sp->radius, 2.1, 0);
    assert_int_equal(s->counts[CR_OUT_HORIZON], 0);
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            double sx = screen_x(f, i), sy = screen_y(f, j), t = sqrt(sx * sx + sy * sy);
            int o = OUT(s, i, j);
            /* inside the photon sphere, the sphere's edge is the shadow's */
            if (t < ta - 0.3 * pitch)
                assert_int_equal(o, CR_OUT_SPHERE);
            else if (t > ta + 0.3 * pitch)
                assert_int_equal(o, CR_OUT_SKY);
            if (o != CR_OUT_SPHERE)
                continue;
            assert_near(s->csv[j * W + i].z, z21, 1e-9);
            {
                mhit m = manual_trace(f, i, j);
                double d[3], len, col;
                int c;
                if (m.outcome != CR_OUT_SPHERE)
                    continue;
                n++;
                for (c = 0; c < 3; c++)
                    d[c] = m.x[c] - sp->center[c];
                len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                col = acos((d[0] * sp->axes[1][0] + d[1] * sp->axes[1][1] +
                            d[2] * sp->axes[1][2]) / len) / DEG;
                colmin = fmin(colmin, col);
                colmax = fmax(colmax, col);
                near_n += col < 12.0;
                near_s += col > 168.0;
                top += col < 45.0;
                bottom += col > 135.0;
                /* the renderer's colour is the chessboard at this point,
                 * away from the square edges */
                if (fmod(col, 45.0) > 2.0 && fmod(col, 45.0) < 43.0) {
                    double lon = atan2(d[0] * sp->axes[2][0] + d[1] * sp->axes[2][1] +
                                           d[2] * sp->axes[2][2],
                                       d[0] * sp->axes[0][0] + d[1] * sp->axes[0][1] +
                                           d[2] * sp->axes[0][2]) / DEG;
                    double lm = fmod(lon + 360.0, 45.0);
                    if (lm > 2.0 && lm < 43.0) {
                        cr_rgb want = cr_sphere_color(sp, m.x);
                        assert_true(rgb_eq(want, PX(s, i, j).color));
                        agree++;
                    }
                }
            }
        }
    print_message("7.1.3: sphere image radius %.2f px (shadow of r = 3); %d sphere pixels "
                  "traced again: colatitude %.1f..%.1f deg, %d in the top band, %d in the "
                  "bottom band, %d within 12 deg of the north pole, %d of the south pole "
                  "(hidden without lensing); %d colours checked\n",
                  ta / pitch, n, colmin, colmax, top, bottom, near_n, near_s, agree);
    assert_true(n > 500);
    assert_true(top > 50 && bottom > 50);
    assert_true(near_n > 0 && near_s > 0);
    assert_true(agree > n / 2);
}

/* --- 7.1.2: starry sky ---------------------------------------------------- */

static void test_starry_sky_listing_7_1_2(void **state)
{
    shot *s = render_scene("listing-7.1.2-starry-sky.yml", 0, 1);
    double ta = shadow_tan(1.0, 0.0, 50.0);
    double pitch = screen_x(&s->f, 1) - screen_x(&s->f, 0);
    int i, row, dark = 0, distinct = 0, black = 0;
    static unsigned char seen[1 << 15];
    (void)state;
    assert_true(s->scene.has_sky);
    assert_near(s->f.r_max, 51.0, 1e-12); /* observer r + M; R = 50 is below it */
    assert_int_equal(OUT(s, CX, CY), CR_OUT_HORIZON);
    row = shadow_row_check(s, ta);
    memset(seen, 0, sizeof seen);
    for (i = 0; i < NPX; i++) {
        cr_rgb c = s->px[i].color;
        unsigned key = (unsigned)(c.r >> 3) << 10 | (unsigned)(c.g >> 3) << 5 | (c.b >> 3);
        if (s->px[i].outcome != CR_OUT_SKY)
            continue;
        distinct += !seen[key];
        seen[key] = 1;
        dark += c.r < 128 && c.g < 128 && c.b < 128;
        black += c.r == 0 && c.g == 0 && c.b == 0;
    }
    print_message("7.1.2: shadow radius %.2f px analytic, centre row %d horizon px; sky pixels "
                  "take %d distinct colours (5 bits per channel), %d dark, %d pure black\n",
                  ta / pitch, row, distinct, dark, black);
    assert_true(distinct > 10);            /* not the plain sky colour */
    assert_true(black < s->counts[CR_OUT_SKY] / 10);
    assert_true(dark > s->counts[CR_OUT_SKY] / 2); /* a night sky */
}

/* --- sky map: direction and bilinear smoothness -------------------------- */

static void test_sky_map(void **state)
{
    char path[1024];
    shot *s, *t;
    uint8_t *img;
    int iw, ih, i, j, uniform = 0, in_range = 0, max_change = 0, changed = 0;
    double shift;
    cr_err err;
    (void)state;
    snprintf(path, sizeof path, "%s/scenes/sky_grid.png", CR_SOURCE_DIR);
    if (cr_png_read(path, 0, &img, &iw, &ih, &err))
        fail_msg("%s", err.msg);
    snprintf(path, sizeof path, "%s/tests/data/scene_grid_sky_away.yml", CR_SOURCE_DIR);
    s = render(path, 0, 1, 0.0);
    shift = 0.1 * CR_TWO_PI / iw; /* a tenth of a sky-image pixel */
    t = render(path, 0, 1, shift);
    assert_int_equal(s->counts[CR_OUT_SKY], NPX);
    assert_int_equal(t->counts[CR_OUT_SKY], NPX);
    assert_near(t->f.observer.phi - s->f.observer.phi, shift, 1e-15);

    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            /* looking away from the hole from (theta, phi) = (90, 0) deg:
             * forward +x, right -y, up +z, so the pixel looks along
             * (1, -sx, sy), sky theta = acos(n_z), phi = atan2(n_y, n_x) (6.10.4) */
            double sx = screen_x(&s->f, i), sy = screen_y(&s->f, j);
            double len = sqrt(1.0 + sx * sx + sy * sy);
            double th = acos(sy / len), ph = atan2(-sx, 1.0), fx, fy;
            const uint8_t *got = s->c_png + 3 * (j * W + i), *mid;
            int x0, y0, dx, dy, c, lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0}, uni = 1;
            if (ph < 0.0)
                ph += CR_TWO_PI;
            /* (6.10.1): y = theta h / pi, x = (2 pi - phi) b / (2 pi) */
            fx = (CR_TWO_PI - ph) / CR_TWO_PI * iw;
            fy = th / CR_PI * ih;
            x0 = (int)floor(fx);
            y0 = (int)floor(fy);
            mid = img + 3 * ((size_t)(y0 < ih ? y0 : ih - 1) * iw + (x0 % iw));
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++) {
                    int xx = ((x0 + dx) % iw + iw) % iw, yy = y0 + dy;
                    const uint8_t *q;
                    yy = yy < 0 ? 0 : (yy >= ih ? ih - 1 : yy);
                    q = img + 3 * ((size_t)yy * iw + xx);
                    for (c = 0; c < 3; c++) {
                        lo[c] = q[c] < lo[c] ? q[c] : lo[c];
                        hi[c] = q[c] > hi[c] ? q[c] : hi[c];
                        uni &= q[c] == mid[c];
                    }
                }
            /* the colour lies within the image's colours around the point; where
             * they are all one colour it is exactly that colour */
            for (c = 0; c < 3; c++)
                assert_true(got[c] >= lo[c] && got[c] <= hi[c]);
            in_range++;
            if (uni) {
                uniform++;
                for (c = 0; c < 3; c++)
                    assert_int_equal(got[c], lo[c]);
            }
            /* smoothness under the tiny shift */
            for (c = 0; c < 3; c++) {
                int dch = abs((int)got[c] - (int)t->c_png[3 * (j * W + i) + c]);
                max_change = dch > max_change ? dch : max_change;
                changed += dch > 0;
            }
        }
    /* the centre looks at (90, 0) deg: the crossing of the equator and the
     * meridian phi = 0, both drawn white */
    assert_true(rgb_is(s->c_png + 3 * (CY * W + CX), 255, 255, 255));
    print_message("sky map: %d pixels within their 3x3 sky-image neighbourhood, %d of them in "
                  "uniform squares matched exactly; shift of 0.1 image px: max channel change "
                  "%d, %d channels changed\n",
                  in_range, uniform, max_change, changed);
    assert_true(uniform > NPX / 2);
    assert_true(changed > 0);
    assert_true(max_change <= 30); /* bilinear: at most 0.1 x 255 plus rounding */
    free(img);
}

/* --- animation ------------------------------------------------------------ */

static void test_animation_listing_7_1_1(void **state)
{
    char path[1024];
    cr_scene sc;
    cr_frame f;
    cr_err err;
    shot *s0, *s1, *s2;
    int i, j, k, bad1 = 0, bad2 = 0, centre_disc = 0;
    static const double want[3] = {5.0, 90.0, 175.0};
    (void)state;
    snprintf(path, sizeof path, "%s/scenes/listing-7.1.1-schwarzschild-disc.yml", CR_SOURCE_DIR);
    if (cr_scene_load(path, &sc, &err))
        fail_msg("%s", err.msg);
    for (k = 0; k < 3; k++) {
        if (cr_scene_frame(&sc, k, 3, W, H, NULL, &f, NULL, &err))
            fail_msg("%s", err.msg);
        assert_near(f.observer.theta, want[k] * DEG, 1e-14);
    }
    /* a single frame takes the start value */
    assert_int_equal(cr_scene_frame(&sc, 0, 1, W, H, NULL, &f, NULL, &err), 0);
    assert_near(f.observer.theta, 5.0 * DEG, 1e-15);
    assert_int_not_equal(cr_scene_frame(&sc, 3, 3, W, H, NULL, &f, NULL, &err), 0);
    cr_scene_free(&sc);

    s0 = render_scene("listing-7.1.1-schwarzschild-disc.yml", 0, 3);
    s1 = render_scene("listing-7.1.1-schwarzschild-disc.yml", 1, 3);
    s2 = render_scene("listing-7.1.1-schwarzschild-disc.yml", 2, 3);
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            const cr_pixel *p = &PX(s1, i, j), *q = &PX(s1, i, H - 1 - j);
            const cr_pixel *a = &PX(s0, i, j), *b = &PX(s2, i, H - 1 - j);
            /* theta = 90: z -> -z maps the image on itself upside down, with
             * the disc's faces swapped; the centre row lies in the disc plane */
            if (j != CY) {
                int same = p->outcome == q->outcome &&
                           (p->outcome != CR_OUT_DISC || p->object == 1 - q->object);
                bad1 += !same;
            } else {
                centre_disc += p->outcome == CR_OUT_DISC;
            }
            /* theta = 5 and 175 deg are mirror images of each other */
            bad2 += !(a->outcome == b->outcome &&
                      (a->outcome != CR_OUT_DISC || a->object == 1 - b->object));
        }
    print_message("7.1.1 with 3 frames: theta = 5, 90, 175 deg; frame 1 up/down mismatches "
                  "%d (centre row, in the disc plane: %d disc pixels); frame 0 vs frame 2 "
                  "flipped: %d mismatches\n",
                  bad1, centre_disc, bad2);
    assert_true(bad1 <= NPX / 200);
    assert_true(bad2 <= NPX / 200);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_shipped_scene),
        cmocka_unit_test(test_redshift_listing_7_1_4),
        cmocka_unit_test(test_blueshift_listing_7_1_5),
        cmocka_unit_test(test_sphere_ring_listings_7_1_6_and_7_3_1),
        cmocka_unit_test(test_kerr_listing_7_2_1),
        cmocka_unit_test(test_sphere_around_horizon_listing_7_1_3),
        cmocka_unit_test(test_starry_sky_listing_7_1_2),
        cmocka_unit_test(test_sky_map),
        cmocka_unit_test(test_animation_listing_7_1_1),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
