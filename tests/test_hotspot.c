/* Moving spheres (sphere.motion; core/sphere.h), seen with the light's
 * travel time, against values computed here independently:
 *
 * 1. At rest: a sphere with motion: rotating, omega: 0 (traced with every
 *    ray's coordinate time, its 4-velocity the static observer's) renders
 *    the same pixels as the static sphere of the same keys: colour,
 *    outcome, object, steps, hit point and delay identical, the frequency
 *    ratio within 1e-12 (one formula against the other), under mino and
 *    rk4, and from the observer at infinity.
 * 2. Moving: Schwarzschild, a sphere (R = 2 M) on the circular orbit at
 *    r = 8 M (Omega = r^-3/2), seen by a static observer at r_o = 40 M in
 *    the orbit's plane. For every pixel of the image's middle row (its ray
 *    stays in the equator) the ray is computed here by quadrature of
 *      dphi/dr = b / (r^2 sqrt(1 - b^2 f / r^2)),
 *      dt/dr  = 1 / (f sqrt(1 - b^2 f / r^2)),   f = 1 - 2M/r,
 *    inward from r_o (b from the pixel's direction, cr_camera_pixel_dir),
 *    and the sphere is looked for at the time t_obs - delay(r) of each
 *    point: the first root of |x(r) - c(t_obs - delay(r))|^2 - R^2. Pixels
 *    whose rays meet it on their way in must be sphere pixels with hit_r
 *    within 1e-6 M, the delay within 1e-6 relative and the frequency ratio
 *    g = 1 / (sqrt(f_o) u^t (1 - Omega L/E)) (u^t of the rigid rotation at
 *    the hit) within 1e-6; pixels whose rays pass the sphere's whole orbit
 *    by more than 0.05 M on their way in and turn outside it must not be
 *    sphere pixels. At least two sphere pixels are checked, and the test
 *    checks that the sphere where it is at t_obs (no travel time) would be
 *    met elsewhere, by far more than the tolerance: the check can fail.
 *    The same scene in units of M = 2 traces the same rays (hit_r, the
 *    delay, in units of M, and g the same, to 1e-9).
 *    Kerr (a = 0.9), a sphere on the ISCO: mino (long steps, the turning
 *    sphere looked for in pieces) and rk4 (short steps) see the same
 *    sphere pixels (at most 2 differ) with g within 2e-5.
 * 3. Bad input, refused naming the key: a motion faster than light, an
 *    orbit inside the photon orbit or the horizon, the orbit's keys on a
 *    sphere without that motion, the observer's time with nothing moving,
 *    non-finite values, an animated place of a moving sphere.
 * 4. An observer inside the horizon: a moving sphere refused (its light's
 *    travel time is not defined from there), the same sphere at rest
 *    accepted and seen, an infall through r+ refused at the first frame
 *    inside.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "input/scene.h"
#include "testutil.h"

static int load(const char *text, cr_scene *s, cr_err *e)
{
    return cr_scene_load_string(text, strlen(text), "hot.yml", s, e);
}

/* Trace every pixel of frame 0 of the scene text at w x h. */
static cr_pixel *render(const char *text, int w, int h, int integrator, double tol,
                        cr_frame *fout)
{
    cr_scene s;
    cr_err e;
    cr_frame_eval ev;
    cr_trace_settings ts = cr_trace_defaults();
    cr_pixel *px = malloc(sizeof *px * (size_t)(w * h));
    int i;
    memset(&ev, 0, sizeof ev);
    ts.integrator = integrator;
    if (tol > 0.0)
        ts.tolerance = tol;
    if (load(text, &s, &e) != 0)
        fail_msg("%s", e.msg);
    if (cr_frame_eval_at(&ev, &s, 0, 1, w, h, &ts, &e) != 0)
        fail_msg("%s", e.msg);
    for (i = 0; i < w * h; i++)
        px[i] = cr_trace_pixel(&ev.frame, i % w, i / w);
    if (fout) {
        *fout = ev.frame;
        fout->spheres = NULL;
    }
    cr_frame_eval_free(&ev);
    cr_scene_free(&s);
    return px;
}

/* ---- 1. at rest ------------------------------------------------------ */

static void same_pixels(const char *observer, int integrator)
{
    char a[1024], b[1024];
    const char *sphere = "sphere:\n  color: [0, 0, 255]\n  resolution: [4, 8]\n  r: 6\n"
                         "  theta: 80\n  phi: 20\n  radius: 1.5\n";
    cr_pixel *p, *q;
    int i, n = 48 * 36, hits = 0;
    snprintf(a, sizeof a, "metric: {m: 1, a: 0.9, q: 0}\n%s%s", observer, sphere);
    snprintf(b, sizeof b, "metric: {m: 1, a: 0.9, q: 0}\n%s%s  motion: rotating\n  omega: 0\n",
             observer, sphere);
    p = render(a, 48, 36, integrator, 0.0, NULL);
    q = render(b, 48, 36, integrator, 0.0, NULL);
    for (i = 0; i < n; i++) {
        assert_int_equal(p[i].outcome, q[i].outcome);
        assert_int_equal(p[i].object, q[i].object);
        assert_int_equal(p[i].steps, q[i].steps);
        assert_memory_equal(&p[i].color, &q[i].color, sizeof p[i].color);
        assert_memory_equal(&p[i].hit_r, &q[i].hit_r, sizeof(double));
        assert_memory_equal(&p[i].hit_phi, &q[i].hit_phi, sizeof(double));
        if (p[i].outcome == CR_OUT_SPHERE) {
            hits++;
            assert_memory_equal(&p[i].delay, &q[i].delay, sizeof(double));
            assert_true(fabs(p[i].redshift - q[i].redshift) <= 1e-12 * p[i].redshift);
            assert_true(p[i].bolo == -1.0);
            assert_true(fabs(q[i].bolo - pow(q[i].redshift, 4.0)) <= 1e-15);
        } else {
            assert_memory_equal(&p[i].redshift, &q[i].redshift, sizeof(double));
        }
    }
    print_message("at rest: %d sphere pixels\n", hits);
    assert_true(hits > 20);
    free(p);
    free(q);
}

static void test_at_rest(void **state)
{
    (void)state;
    same_pixels("observer: {r: 30, theta: 70, phi: 0, hfov: 40}\n", CR_INTEG_MINO);
    same_pixels("observer: {r: 30, theta: 70, phi: 0, hfov: 40}\n", CR_INTEG_RK4);
    same_pixels("observer: {r: inf, theta: 70, phi: 0, hextent: 24}\n", CR_INTEG_MINO);
}

/* ---- 2. moving: the independent ray --------------------------------- */

#define RO 40.0    /* observer */
#define RS 8.0     /* orbit */
#define RAD 2.0    /* sphere radius */
#define PHI0 0.5   /* phase at t = 0, rad */
#define TOBS 30.0  /* observer's time */

/* The equatorial ray of impact parameter b (>= 0), phi growing with
 * sgn = +1 or -1 along the backward ray: phi(r) - phi_o and the delay
 * t_obs - t(r) by composite 8-point Gauss-Legendre over [r, r_o] in the
 * variable r (smooth: only points before the turning point are asked
 * for, at least 1e-3 M from it). */
static void ray_at(double b, double r, double *dphi, double *delay)
{
    const int panels = 400;
    double h = (RO - r) / panels, sp = 0.0, st = 0.0;
    int i, j;
    for (i = 0; i < panels; i++)
        for (j = 0; j < 8; j++) {
            double x, w, rr, f, root;
            cr_quad_gl8(j, &x, &w);
            rr = r + h * (i + 0.5 * (x + 1.0));
            f = 1.0 - 2.0 / rr;
            root = sqrt(1.0 - b * b * f / (rr * rr));
            sp += 0.5 * h * w * b / (rr * rr * root);
            st += 0.5 * h * w / (f * root);
        }
    *dphi = sp;
    *delay = st;
}

/* Turning point of impact parameter b (largest root of r^3 - b^2 (r - 2)),
 * 0 when there is none (the ray falls in). */
static double r_turn(double b)
{
    double lo = 3.0, hi = RO, mid;
    int i;
    if (b <= sqrt(27.0))
        return 0.0;
    for (i = 0; i < 200; i++) {
        mid = 0.5 * (lo + hi);
        if (mid * mid * mid - b * b * (mid - 2.0) > 0.0)
            hi = mid;
        else
            lo = mid;
    }
    return hi;
}

/* |x(r) - c(t)|^2 - R^2 for the ray at r, with the sphere where it was at
 * the ray's time there (travel = 1) or where it is at t_obs (0). */
static double ray_value(double b, int sgn, double r, int travel, double *delay)
{
    double dphi, d, om = pow(RS, -1.5), ph, phs, dx, dy;
    ray_at(b, r, &dphi, &d);
    ph = sgn * dphi;
    phs = PHI0 + om * (TOBS - (travel ? d : 0.0));
    dx = r * cos(ph) - RS * cos(phs);
    dy = r * sin(ph) - RS * sin(phs);
    *delay = d;
    return dx * dx + dy * dy - RAD * RAD;
}

/* The first root in r of ray_value inward from r_o down to r_end: 0 with
 * none; *dmin the smallest value on the scan. */
static double ray_hit(double b, int sgn, double r_end, int travel, double *delay, double *vmin)
{
    double r = RO - 1.0, v0, v, dl, step = 0.02;
    v0 = ray_value(b, sgn, r, travel, &dl);
    *vmin = v0;
    for (; r - step > r_end; r -= step) {
        v = ray_value(b, sgn, r - step, travel, &dl);
        if (v < *vmin)
            *vmin = v;
        if (v < 0.0 && v0 >= 0.0) {
            double lo = r - step, hi = r;
            int i;
            for (i = 0; i < 80; i++) {
                double mid = 0.5 * (lo + hi);
                if (ray_value(b, sgn, mid, travel, &dl) < 0.0)
                    lo = mid;
                else
                    hi = mid;
            }
            ray_value(b, sgn, 0.5 * (lo + hi), travel, delay);
            return 0.5 * (lo + hi);
        }
        v0 = v;
    }
    return 0.0;
}

/* tol: the integrator's tolerance (0: the default); eps: the tolerance of
 * hit_r (M), and relative of the delay and g, eps / 10 */
static void moving(double tol, double eps)
{
    char text[1024];
    const int w = 161, h = 3, j = 1;
    cr_frame f;
    cr_pixel *px;
    int i, checked = 0, misses = 0, moved = 0;
    double worst_r = 0.0, worst_t = 0.0, worst_g = 0.0;
    double om = pow(RS, -1.5), fo = 1.0 - 2.0 / RO;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: %g, theta: 90, phi: 0, hfov: 60, t: %g}\n"
             "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  r: %g\n  theta: 90\n"
             "  phi: %.17g rad\n  radius: %g\n  motion: orbit\n",
             RO, TOBS, RS, PHI0, RAD);
    px = render(text, w, h, CR_INTEG_MINO, tol, &f);
    for (i = 0; i < w; i++) {
        const cr_pixel *p = &px[j * w + i];
        double n[3], b, rt, r_end, delay = 0.0, vmin, rh, v2;
        int sgn;
        cr_camera_pixel_dir(&f, i, j, n);
        assert_true(fabs(n[1]) < 1e-12); /* in the equator */
        b = RO * fabs(n[2]) / sqrt(fo);
        sgn = n[2] >= 0.0 ? 1 : -1;
        rt = r_turn(b);
        r_end = rt > 0.0 ? rt + 1e-3 : 2.0 + 1e-3;
        rh = ray_hit(b, sgn, r_end, 1, &delay, &vmin);
        if (rh > 0.0) {
            /* expected: a hit on the way in */
            double ut = 1.0 / sqrt(1.0 - 2.0 / rh - om * om * rh * rh);
            double L_E = -sgn * b; /* the photon's L / E (forward) */
            double g = 1.0 / (sqrt(fo) * ut * (1.0 - om * L_E));
            double rs, dls;
            assert_int_equal(p->outcome, CR_OUT_SPHERE);
            worst_r = fmax(worst_r, fabs(p->hit_r - rh));
            worst_t = fmax(worst_t, fabs(p->delay - delay) / delay);
            worst_g = fmax(worst_g, fabs(p->redshift - g) / g);
            assert_true(fabs(p->bolo - pow(p->redshift, 4.0)) <= 1e-14 * p->bolo);
            /* the same sphere without travel time is met elsewhere or not */
            rs = ray_hit(b, sgn, r_end, 0, &dls, &v2);
            if (rs == 0.0 || fabs(rs - rh) > 1e-2)
                moved++;
            checked++;
        } else if (vmin > 0.05 && (rt == 0.0 || rt > RS + RAD + 0.05)) {
            /* well clear of the sphere on the way in, and turning outside
             * its orbit (or falling in, the sphere not met before) */
            if (rt > 0.0) {
                assert_true(p->outcome != CR_OUT_SPHERE);
                misses++;
            }
        }
    }
    print_message("moving sphere, tolerance %g: %d hit pixels checked (%d of them elsewhere "
                  "without travel time), %d clear misses; worst hit_r %.3g M, delay %.3g, "
                  "g %.3g (relative)\n",
                  tol, checked, moved, misses, worst_r, worst_t, worst_g);
    assert_true(worst_r <= eps);
    assert_true(worst_t <= 0.1 * eps);
    assert_true(worst_g <= 0.1 * eps);
    assert_true(checked >= 2);
    assert_true(moved >= 2);
    assert_true(misses >= 10);
    free(px);
}

static void test_moving(void **state)
{
    (void)state;
    moving(1e-10, 1e-7);
    moving(0.0, 1e-4); /* the default tolerance, 1e-7 */
}

/* The moving scene in units of M = 2 (every length and time doubled, omega
 * halved by the orbit) traces the same rays: the same outcomes, hit_r, delay
 * (both in units of M, as every pixel value) and g, to 1e-9 relative. */
static void test_units(void **state)
{
    char one[1024], two[1024];
    const char *fmt = "metric: {m: %g, a: %g, q: 0}\n"
                      "observer: {r: %g, theta: 80, phi: 0, hfov: 40, t: %g}\n"
                      "sphere:\n  color: [0, 0, 255]\n  resolution: [4, 8]\n  r: %g\n"
                      "  theta: 90\n  phi: 0.5 rad\n  radius: %g\n  motion: orbit\n";
    cr_pixel *p, *q;
    int i, hits = 0;
    (void)state;
    snprintf(one, sizeof one, fmt, 1.0, 0.5, RO, TOBS, RS, RAD);
    snprintf(two, sizeof two, fmt, 2.0, 1.0, 2 * RO, 2 * TOBS, 2 * RS, 2 * RAD);
    p = render(one, 40, 30, CR_INTEG_MINO, 0.0, NULL);
    q = render(two, 40, 30, CR_INTEG_MINO, 0.0, NULL);
    for (i = 0; i < 40 * 30; i++) {
        assert_int_equal(p[i].outcome, q[i].outcome);
        if (p[i].outcome != CR_OUT_SPHERE)
            continue;
        hits++;
        assert_true(fabs(q[i].hit_r - p[i].hit_r) <= 1e-9 * p[i].hit_r);
        assert_true(fabs(q[i].delay - p[i].delay) <= 1e-9 * fabs(p[i].delay));
        assert_true(fabs(q[i].redshift - p[i].redshift) <= 1e-9 * p[i].redshift);
    }
    assert_true(hits > 20);
    free(p);
    free(q);
}

/* Kerr, a = 0.9: a sphere (R = 0.6 M) on the ISCO seen from r = 60 M at
 * 75 deg, traced by mino (long steps: the turning sphere is looked for in
 * pieces, cr_sphere_turning) and by rk4 (short steps, one piece each): the
 * same sphere pixels but for at most 2 of the image's edge cases, and g
 * within 2e-5 relative (rk4's error at its default step; g of the rigid rotation's 4-velocity in Kerr,
 * frame dragging included, the same function in both: the check is of
 * where and when the rays meet the sphere). */
static void test_kerr_integrators(void **state)
{
    const char *text = "metric: {m: 1, a: 0.9, q: 0}\n"
                       "observer: {r: 60, theta: 75, phi: 0, hfov: 12, t: 40}\n"
                       "sphere:\n  color: [255, 200, 80]\n  resolution: [4, 8]\n  r: isco\n"
                       "  theta: 90\n  phi: 0\n  radius: 0.6\n  motion: orbit\n";
    cr_pixel *p, *q;
    int i, both = 0, differ = 0;
    double worst = 0.0;
    (void)state;
    p = render(text, 48, 48, CR_INTEG_MINO, 0.0, NULL);
    q = render(text, 48, 48, CR_INTEG_RK4, 0.0, NULL);
    for (i = 0; i < 48 * 48; i++) {
        int a = p[i].outcome == CR_OUT_SPHERE, b = q[i].outcome == CR_OUT_SPHERE;
        if (a && b) {
            both++;
            worst = fmax(worst, fabs(p[i].redshift - q[i].redshift) / q[i].redshift);
        } else if (a != b) {
            differ++;
        }
    }
    print_message("kerr: %d sphere pixels in both, %d in one, worst g %.3g\n", both, differ,
                  worst);
    assert_true(both > 30);
    assert_true(differ <= 2);
    assert_true(worst <= 2e-5); /* rk4 at its default step: 5e-6 measured */
    free(p);
    free(q);
}

/* ---- 3. bad input ---------------------------------------------------- */

static void refused(const char *sphere_keys, const char *observer_extra, const char *want)
{
    char text[1024];
    cr_scene s;
    cr_err e;
    cr_frame_eval ev;
    int rc;
    memset(&ev, 0, sizeof ev);
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: 40, theta: 90, phi: 0, hfov: 60%s}\n"
             "%s",
             observer_extra, sphere_keys);
    rc = load(text, &s, &e);
    if (rc == 0) {
        rc = cr_frame_eval_at(&ev, &s, 0, 1, 32, 32, NULL, &e);
        cr_frame_eval_free(&ev);
        cr_scene_free(&s);
    }
    if (rc == 0 || !strstr(e.msg, want))
        fail_msg("expected a refusal naming '%s', got rc %d: %s", want, rc, e.msg);
}

#define SPH(extra) "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  theta: 90\n  phi: 0\n" \
                   "  radius: 1\n" extra

static void test_bad_input(void **state)
{
    (void)state;
    /* faster than light: v = omega r / sqrt(1 - 2/r) > 1 at r = 8 */
    refused(SPH("  r: 8\n  motion: rotating\n  omega: 0.2\n"), "", "speed of light");
    /* at rest inside the ergosphere is no matter at rest: Kerr case below */
    /* inside the photon orbit, inside the horizon */
    refused(SPH("  r: 2.5\n  motion: orbit\n"), "", "motion: orbit at r = 2.5");
    refused(SPH("  r: 1.5\n  motion: orbit\n"), "", "no circular orbit");
    /* the orbit's keys without the orbit */
    refused(SPH("  r: 8\n  retrograde: true\n"), "", "].retrograde");
    refused(SPH("  r: 8\n  omega: 0.01\n"), "", "].omega");
    refused(SPH("  r: isco\n"), "", "].r");
    refused(SPH("  r: isco\n  motion: rotating\n"), "", "].r");
    refused(SPH("  r: 8\n  motion: orbit\n  omega: 0.01\n"), "", "].omega");
    /* the observer's time with nothing moving, or with no sphere at all */
    refused(SPH("  r: 8\n"), ", t: 10", "observer.t");
    refused("", ", dt: 1", "observer.dt");
    /* non-finite values */
    refused(SPH("  r: 8\n  motion: rotating\n  omega: .nan\n"), "", "].omega");
    refused(SPH("  r: 8\n  motion: orbit\n"), ", t: .inf", "observer.t");
    refused(SPH("  r: 8\n  motion: orbit\n"), ", dt: .nan", "observer.dt");
    /* a moving sphere's place is not animated; an orbit is equatorial */
    refused(SPH("  r: [linear, 8, 9]\n  motion: orbit\n"), "", "].r");
    refused("sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  theta: 80\n  phi: 0\n"
            "  radius: 1\n  r: 8\n  motion: orbit\n",
            "", "].theta");
    refused(SPH("  r: 8\n  motion: wobbling\n"), "", "].motion");
}

/* ---- 4. an observer inside the horizon ----------------------------------- */

/* Frame k of n of text at 24 x 24: 0 or -1 with e set; with seen, the
 * pixels whose object is sphere 0 counted into *seen. */
static int frame_of(const char *text, int k, int n, cr_err *e, int *seen)
{
    cr_scene s;
    cr_frame_eval ev;
    int rc;
    memset(&ev, 0, sizeof ev);
    if (load(text, &s, e))
        return -1;
    rc = cr_frame_eval_at(&ev, &s, k, n, 24, 24, NULL, e);
    if (rc == 0 && seen) {
        int p;
        *seen = 0;
        for (p = 0; p < 24 * 24; p++) {
            cr_pixel q = cr_trace_pixel(&ev.frame, p % 24, p / 24);
            *seen += q.outcome == CR_OUT_SPHERE && q.object == 0;
        }
    }
    cr_frame_eval_free(&ev);
    cr_scene_free(&s);
    return rc;
}

/* A moving sphere seen from inside r+ is refused, naming the sphere, the
 * observer's r and r+: the ray's delay, and so the time at which it meets
 * the sphere, is not defined there (it would never be seen). The same
 * sphere at rest is accepted and seen from there (the refusal is the
 * motion's only), and an observer falling in through r+ over an animation
 * is refused in the first frame inside (r+ = 2 M; r = 40 -> 1.6 over 11
 * frames: 40 - 3.84 k < 2 first at k = 10). */
static void test_inside_horizon(void **state)
{
    static const char head[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: %s, theta: 90, phi: 0, hfov: 120, motion: "
                               "infall}\n"
                               "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n"
                               "  theta: 90\n  phi: 180\n  radius: 2\n  r: 8\n%s";
    char text[1024];
    cr_err e;
    int seen = -1;
    (void)state;
    snprintf(text, sizeof text, head, "1.6", "  motion: orbit\n");
    assert_int_not_equal(frame_of(text, 0, 1, &e, NULL), 0);
    if (!strstr(e.msg, "sphere 0 (line 3): a moving sphere") ||
        !strstr(e.msg, "(observer.r = 1.6 < r+ = 2)"))
        fail_msg("unexpected message: %s", e.msg);
    snprintf(text, sizeof text, head, "1.6", "  motion: rotating\n  omega: 0\n");
    assert_int_not_equal(frame_of(text, 0, 1, &e, NULL), 0);
    assert_non_null(strstr(e.msg, "observer.r = 1.6 < r+ = 2"));
    /* at rest: accepted, and seen (the observer faces the hole, the
       sphere at r = 8 beyond it; 20 of the 24 x 24 pixels) */
    snprintf(text, sizeof text, head, "1.6", "");
    if (frame_of(text, 0, 1, &e, &seen))
        fail_msg("the static sphere was refused: %s", e.msg);
    assert_true(seen > 0);
    /* outside r+ the moving one is accepted */
    snprintf(text, sizeof text, head, "2.1", "  motion: orbit\n");
    if (frame_of(text, 0, 1, &e, NULL))
        fail_msg("refused outside r+: %s", e.msg);
    snprintf(text, sizeof text, head, "[linear, 40, 1.6]", "  motion: orbit\n");
    assert_int_equal(frame_of(text, 9, 11, &e, NULL), 0);
    assert_int_not_equal(frame_of(text, 10, 11, &e, NULL), 0);
    assert_non_null(strstr(e.msg, "frame 10 of 11: sphere 0 (line 3): a moving sphere"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_at_rest),
        cmocka_unit_test(test_moving),
        cmocka_unit_test(test_units),
        cmocka_unit_test(test_kerr_integrators),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_inside_horizon),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
