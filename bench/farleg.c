/* bench/farleg.c: the far leg of sky-image rays, measured (bench/farleg.sh
 * builds and runs it). Not a test; counts and timings only.
 *
 *   farleg SCENE WIDTH HEIGHT        the leg's share and a looser tolerance
 *   farleg --pieces                  what a closed form of the leg would cost
 *
 * The far leg: the steps a ray of the scalar tracer takes from a state
 * beyond the scene radius (the objects' largest BL radius + M, at least
 * CR_MIN_R_MAX_OVER_M M: where a plain sky ends its rays) moving outward.
 * With a sky image the ray goes on to the sky boundary (infinity without
 * one) only for its direction. For frame 0 of SCENE at WIDTH x HEIGHT under
 * the default integrator this prints the steps a ray, the far leg's share,
 * and for the leg taken at 10, 100, 1000 and 10^4 times the tolerance (the
 * rest of the ray at the scene's): the steps saved, the sky pixels whose
 * colour changes against the default and against every step at tolerance
 * 1e-12, and the largest angle between a sky direction and the 1e-12 one.
 * Each ray is traced as cr_trace_loop traces it (trace.h's calls), the
 * tolerance swapped for the steps that start on the leg.
 *
 * --pieces times (this thread's CPU time, medians of 5) the pieces a closed
 * form of the leg would be made of: Carlson's R_F and R_J (the azimuth's
 * elliptic integral of the third kind needs both, at both ends), the Jacobi
 * amplitude by the AGM (the polar angle at the end), and 16-point
 * Gauss-Legendre sums of the remaining Mino time and pr in w = 1/r.
 */
#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/trace.h"
#include "input/scene.h"

typedef struct fl_res {
    long steps, far;
    double th, ph;
    cr_rgb c;
    int out;
} fl_res;

/* cr_trace_loop for pixel (i, j), with frame ffar's tolerance for the steps
 * that start beyond w_far moving outward. */
static fl_res fl_trace(const cr_frame *f, const cr_frame *ffar, double w_far, int i, int j)
{
    cr_ray ray;
    cr_pixel px;
    cr_monitor mon = {0, 0.0, 0.0};
    double x0[3] = {0.0, 0.0, 0.0}, turns = 0.0;
    fl_res r;
    memset(&r, 0, sizeof r);
    r.out = -1;
    r.th = r.ph = NAN;
    if (!cr_trace_point_ray(f, i, j, &ray, &px))
        return r;
    cr_trace_start(f, &ray, &px, x0);
    for (;;) {
        int far;
        if (cr_trace_ends(f, &ray, &px, &mon, r.steps, turns))
            break;
        far = ray.kind == CR_INTEG_MINO && ray.m[CR_M_W] <= w_far && ray.m[CR_M_DW] < 0.0;
        if (cr_ray_advance(far ? ffar : f, &ray) != 0) {
            px.outcome = CR_OUT_ERROR;
            break;
        }
        r.steps++;
        r.far += far;
        if (cr_trace_after_step(f, &ray, &px, x0, &turns))
            break;
    }
    r.c = px.color;
    r.out = px.outcome;
    if (px.outcome == CR_OUT_SKY)
        cr_ray_sky_direction(f, &ray, cr_ray_y0(&ray), &r.th, &r.ph);
    return r;
}

static double fl_angle(const fl_res *a, const fl_res *b)
{
    double dx = sin(a->th) * cos(a->ph) - sin(b->th) * cos(b->ph);
    double dy = sin(a->th) * sin(a->ph) - sin(b->th) * sin(b->ph);
    double dz = cos(a->th) - cos(b->th);
    return 2.0 * asin(fmin(1.0, 0.5 * sqrt(dx * dx + dy * dy + dz * dz)));
}

static int fl_scene(const char *path, int w, int h)
{
    static cr_sphere buf[64];
    const double facs[] = {1.0, 10.0, 100.0, 1000.0, 1e4};
    cr_scene s;
    cr_frame f, fref, ffar;
    cr_err err;
    cr_trace_settings ts = cr_trace_defaults();
    double ro, rs;
    int i, j, k;
    if (cr_scene_load(path, &s, &err) != 0 || cr_scene_frame(&s, 0, 1, w, h, &ts, &f, buf, &err) != 0) {
        fprintf(stderr, "farleg: %s\n", err.msg);
        return 1;
    }
    ro = f.disc.enabled ? f.disc.r_out : 0.0;
    for (i = 0; i < f.n_spheres; i++) {
        const double *c = f.spheres[i].center;
        double e = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + f.spheres[i].radius;
        ro = e > ro ? e : ro;
    }
    rs = ro + f.metric.m;
    if (rs < CR_MIN_R_MAX_OVER_M * f.metric.m)
        rs = CR_MIN_R_MAX_OVER_M * f.metric.m;
    fref = f;
    fref.tolerance = 1e-12;
    printf("%s, %dx%d, tolerance %g, sky %s, far leg beyond r = %g M\n", path, w, h, f.tolerance,
           f.w_sky > 0.0 ? "boundary" : "at infinity", rs);
    for (k = 0; k < 5; k++) {
        long st = 0, st0 = 0, far0 = 0, far_rays = 0, sky = 0, vs_def = 0, vs_ref = 0, cls = 0;
        double emax = 0.0, emax0 = 0.0;
        ffar = f;
        ffar.tolerance = f.tolerance * facs[k];
        for (j = 0; j < h; j++)
            for (i = 0; i < w; i++) {
                fl_res a = fl_trace(&f, &f, 1.0 / rs, i, j);
                fl_res b = fl_trace(&f, &ffar, 1.0 / rs, i, j);
                fl_res c = fl_trace(&fref, &fref, 1.0 / rs, i, j);
                st += b.steps;
                st0 += a.steps;
                far0 += a.far;
                far_rays += a.far > 0;
                if (a.out != b.out) {
                    cls++;
                    continue;
                }
                if (b.out != CR_OUT_SKY || c.out != CR_OUT_SKY)
                    continue;
                sky++;
                vs_def += a.c.r != b.c.r || a.c.g != b.c.g || a.c.b != b.c.b;
                vs_ref += c.c.r != b.c.r || c.c.g != b.c.g || c.c.b != b.c.b;
                emax = fmax(emax, fl_angle(&b, &c));
                emax0 = fmax(emax0, fl_angle(&a, &c));
            }
        if (k == 0)
            printf("  %.2f steps a ray; the far leg %.1f %% of the steps (%.1f a ray on it, %ld rays)\n",
                   (double)st0 / (w * h), 100.0 * far0 / st0, far_rays ? (double)far0 / far_rays : 0.0,
                   far_rays);
        printf("  leg at %5g x tol: %.2f steps a ray (%4.1f %% fewer); of %ld sky pixels %ld change colour "
               "(%ld against tol 1e-12); largest direction error %.2e rad (default %.2e); "
               "%ld outcomes change\n",
               facs[k], (double)st / (w * h), 100.0 * (1.0 - (double)st / st0), sky, vs_def, vs_ref,
               emax, emax0, cls);
    }
    cr_scene_free(&s);
    return 0;
}

/* ---- --pieces ------------------------------------------------------------ */

static double fl_rf(double x, double y, double z)
{
    for (;;) {
        double sx = sqrt(x), sy = sqrt(y), sz = sqrt(z), l = sx * (sy + sz) + sy * sz, a, dx, dy, dz;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        a = (x + y + z) / 3.0;
        dx = 1.0 - x / a;
        dy = 1.0 - y / a;
        dz = 1.0 - z / a;
        if (fmax(fabs(dx), fmax(fabs(dy), fabs(dz))) < 1e-3) {
            double e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
            return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / sqrt(a);
        }
    }
}

static double fl_rc(double x, double y)
{
    for (;;) {
        double l = 2.0 * sqrt(x) * sqrt(y) + y, a, s;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        a = (x + y + y) / 3.0;
        s = (y - a) / a;
        if (fabs(s) < 1e-3)
            return (1.0 + s * s * (0.3 + s * (1.0 / 7.0 + s * (0.375 + s * 9.0 / 22.0)))) / sqrt(a);
    }
}

static double fl_rj(double x, double y, double z, double p)
{
    double sum = 0.0, fac = 1.0;
    for (;;) {
        double sx = sqrt(x), sy = sqrt(y), sz = sqrt(z), l = sx * (sy + sz) + sy * sz;
        double al = p * (sx + sy + sz) + sx * sy * sz, be = p * (p + l) * (p + l), a, dx, dy, dz, dp;
        sum += fac * fl_rc(al * al, be);
        fac *= 0.25;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        p = 0.25 * (p + l);
        a = 0.2 * (x + y + z + p + p);
        dx = (a - x) / a;
        dy = (a - y) / a;
        dz = (a - z) / a;
        dp = (a - p) / a;
        if (fmax(fmax(fabs(dx), fabs(dy)), fmax(fabs(dz), fabs(dp))) < 1e-3) {
            double ea = dx * (dy + dz) + dy * dz, eb = dx * dy * dz, ec = dp * dp, ed = ea - 3.0 * ec;
            double ee = eb + 2.0 * dp * (ea - ec);
            return 3.0 * sum + fac * (1.0 + ed * (-3.0 / 14.0 + 9.0 / 88.0 * ed - 4.5 / 26.0 * ee) +
                                      eb * (1.0 / 6.0 + dp * (-9.0 / 22.0 + dp * 3.0 / 26.0)) -
                                      dp * ea * ec / 3.0) /
                                   (a * sqrt(a));
        }
    }
}

/* Jacobi amplitude am(u | m) by the AGM (descending Landen). */
static double fl_am(double u, double m)
{
    double a[16], c[16], b, phi;
    int n = 0, i;
    a[0] = 1.0;
    b = sqrt(1.0 - m);
    c[0] = sqrt(m);
    while (fabs(c[n]) > 1e-16 && n < 15) {
        a[n + 1] = 0.5 * (a[n] + b);
        c[n + 1] = 0.5 * (a[n] - b);
        b = sqrt(a[n] * b);
        n++;
    }
    phi = ldexp(a[n] * u, n);
    for (i = n; i > 0; i--)
        phi = 0.5 * (phi + asin(c[i] / a[i] * sin(phi)));
    return phi;
}

static double fl_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int fl_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static volatile double fl_sink;

static double fl_time(int which)
{
    const int n = 200000;
    double t[5], t0;
    int r, i, k;
    for (r = 0; r < 5; r++) {
        t0 = fl_now();
        for (i = 0; i < n; i++) {
            double e = 1e-7 * i, q = 0.0, w = 0.16 + 1e-9 * i;
            switch (which) {
            case 0:
                q = fl_rf(0.3 + e, 0.9, 1.0);
                break;
            case 1:
                q = fl_rj(0.3 + e, 0.9, 1.0, 1.5);
                break;
            case 2:
                q = fl_am(1.2 + e, 0.03);
                break;
            default:
                /* the remaining Mino time and pr of an a = 0.9, b ~ 5 ray from r = 6 */
                for (k = 0; k < 16; k++) {
                    double x = w * (0.5 + 0.03 * k), W = 1.0 - 27.0 * x * x + 54.0 * x * x * x -
                                                          0.5 * x * x * x * x;
                    q += 0.06 / sqrt(W) +
                         0.06 * 0.9 * x * (2.0 + 0.3 * x) / ((1.0 - 2.0 * x + 0.81 * x * x) * sqrt(W));
                }
            }
            fl_sink += q;
        }
        t[r] = (fl_now() - t0) / n;
    }
    qsort(t, 5, sizeof t[0], fl_cmp);
    return 1e9 * t[2];
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--pieces") == 0) {
        double rf = fl_time(0), rj = fl_time(1), am = fl_time(2), gl = fl_time(3);
        printf("Carlson R_F %.0f ns, R_J %.0f ns; Jacobi am (AGM) %.0f ns; 16-point Gauss-Legendre "
               "of the Mino time and pr %.0f ns\n",
               rf, rj, am, gl);
        printf("a closed-form far leg, at least: 2 (R_F + R_J) + am + 2 x the quadrature (with its "
               "check) = %.0f ns a ray\n",
               2.0 * (rf + rj) + am + 2.0 * gl);
        return 0;
    }
    if (argc != 4) {
        fprintf(stderr, "usage: farleg SCENE WIDTH HEIGHT | farleg --pieces\n");
        return 2;
    }
    return fl_scene(argv[1], atoi(argv[2]), atoi(argv[3]));
}
