/* Image order (cr_pixel.order, theta_turns) and accretion.order against the
 * exact Schwarzschild orbit, for a face-on observer on the axis.
 *
 * A ray of impact parameter b from an observer on the polar axis moves in a
 * plane through the axis; the angle phi it has swept from the axis obeys
 * d phi / du = 1 / sqrt(P(u)), P(u) = 1/b^2 - u^2 + 2 M u^3, u = 1/r (M = 1).
 * It crosses the equatorial plane each time phi reaches pi/2 + k pi (order
 * k = 0, 1, ...) and passes the axis (a polar turning point of cos theta)
 * each time phi reaches k pi, k >= 1. For b above b_c = 3 sqrt(3) it turns
 * at the smallest root u_t of P and leaves, having swept 2 phi(u_t) - phi(u)
 * on the way out; below b_c it falls into the hole. The expected order and
 * hit radius of every pixel come from this quadrature (Gauss-Legendre over
 * a substitution that removes the turning point's square-root singularity,
 * Newton's method for the crossing), written here and nowhere in curray.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "input/scene.h"

#include "exact_orbit.h"

#define R_IN 6.0
#define R_OUT 20.0

/* What the exact orbit says of the ray of impact parameter b: the order of
 * its first crossing inside [r_in, r_out] (only crossing `only` when only
 * >= 0) and its radius; -1 when it meets no disc. */
static int exact_hit(double b, double u0, double r_stop, int only, double *r_hit)
{
    orbit o;
    orbit_make(&o, b, u0);
    for (int k = 0; k < 20; k++) {
        double r = crossing_r(&o, 0.5 * CR_PI + k * CR_PI, r_stop);
        if (r == 0.0)
            return -1;
        if (r >= R_IN && r <= R_OUT && (only < 0 || k == only)) {
            *r_hit = r;
            return k;
        }
    }
    return -1;
}

/* ---- the frames ----------------------------------------------------------- */

/* The frame of a scene text; sphere_buf (NULL without spheres) holds its
 * spheres, which the frame points to. */
static void frame_spheres(const char *text, int integ, double tol, cr_frame *f, int w, int h,
                          cr_sphere *sphere_buf)
{
    cr_scene s;
    cr_err err;
    cr_trace_settings ts = cr_trace_defaults();
    ts.integrator = integ;
    if (tol > 0.0)
        ts.tolerance = tol;
    memset(&s, 0, sizeof s);
    if (cr_scene_load_string(text, strlen(text), "order.yml", &s, &err))
        fail_msg("%s", err.msg);
    if (cr_scene_frame(&s, 0, 1, w, h, &ts, f, sphere_buf, &err))
        fail_msg("%s", err.msg);
    cr_scene_free(&s);
}

static void frame_from(const char *text, int integ, double tol, cr_frame *f, int w, int h)
{
    frame_spheres(text, integ, tol, f, w, h, NULL);
}

/* Impact parameter of image point (x, y) (pixel units, (i, j) the centre of
 * pixel (i, j)): at infinity the image-plane radius sqrt(alpha^2 + beta^2)
 * over the hextent x vextent plane; for the static observer on the axis at r
 * with a rectilinear hfov (square pixels), b = r sin(psi) / sqrt(1 - 2/r)
 * with psi the angle from the view axis (straight at the hole). */
typedef struct view {
    int w, h;
    double r;      /* INFINITY: at infinity */
    double extent; /* hextent (infinity) or tan(hfov / 2) */
} view;

static double view_b(const view *v, double x, double y)
{
    double sx = (2.0 * (x + 0.5) / v->w - 1.0), sy = (1.0 - 2.0 * (y + 0.5) / v->h);
    sy *= (double)v->h / v->w;
    if (isinf(v->r))
        return 0.5 * v->extent * sqrt(sx * sx + sy * sy);
    double psi = atan(v->extent * sqrt(sx * sx + sy * sy));
    return v->r * sin(psi) / sqrt(1.0 - 2.0 / v->r);
}

/* Compare every pixel with the exact orbit: disc or not, order and
 * theta_turns (= order for an observer on the axis), hit radius within
 * r_tol (relative). Pixels within a small fraction of a pixel of an edge
 * (the exact answer changes within +-0.02 px in b) are left out and
 * counted; returns the number of order-`want` hits compared. */
static int compare_pixels(const cr_frame *f, const view *v, int only, double r_tol, int want)
{
    double u0 = isinf(v->r) ? 0.0 : 1.0 / v->r, db = 0.02 * view_b(v, v->w - 1, 0) / (0.5 * v->w);
    int compared = 0, skipped = 0, of_want = 0;
    double worst = 0.0;
    for (int j = 0; j < v->h; j++)
        for (int i = 0; i < v->w; i++) {
            double b = view_b(v, i, j), r, rm, rp;
            int n = exact_hit(b, u0, f->r_stop, only, &r);
            cr_pixel px;
            if (exact_hit(b - db, u0, f->r_stop, only, &rm) != n ||
                exact_hit(b + db, u0, f->r_stop, only, &rp) != n) {
                skipped++;
                continue;
            }
            px = cr_trace_pixel(f, i, j);
            compared++;
            if (n < 0) {
                if (px.outcome == CR_OUT_DISC)
                    fail_msg("pixel (%d, %d), b = %.9g: disc hit at r = %.9g of order %d, "
                             "the exact orbit meets no disc",
                             i, j, b, px.hit_r, px.order);
                continue;
            }
            if (px.outcome != CR_OUT_DISC || px.order != n || px.theta_turns != n)
                fail_msg("pixel (%d, %d), b = %.9g: outcome %s, order %d, theta_turns %d; "
                         "exact: disc of order %d at r = %.9g",
                         i, j, b, cr_outcome_name(px.outcome), px.order, px.theta_turns, n, r);
            if (fabs(px.hit_r - r) > r_tol * r)
                fail_msg("pixel (%d, %d), b = %.9g, order %d: hit_r %.12g, exact %.12g", i, j, b,
                         n, px.hit_r, r);
            if (fabs(px.hit_r - r) / r > worst)
                worst = fabs(px.hit_r - r) / r;
            of_want += n == want;
        }
    print_message("%d pixels compared, %d within 0.02 px of an edge left out, %d of order %d; "
                  "worst |hit_r - exact| / exact %.3g (allowed %.3g)\n",
                  compared, skipped, of_want, want, worst, r_tol);
    assert_true(skipped < v->w * v->h / 20);
    return of_want;
}

/* Whether the exact orbit of impact parameter b (observer at infinity)
 * meets the disc on its order-1 crossing, as the first disc crossing. */
static int exact_in_ring(double b, double r_stop)
{
    double r;
    return exact_hit(b, 0.0, r_stop, -1, &r) == 1;
}

/* The end of an interval where in(x) holds: in(lo) true, in(hi) false. */
#define BISECT(lo, hi, in)                                                                         \
    for (int it_ = 0; it_ < 50; it_++) {                                                           \
        double x = 0.5 * ((lo) + (hi));                                                            \
        if (in)                                                                                    \
            (lo) = x;                                                                              \
        else                                                                                       \
            (hi) = x;                                                                              \
    }

static const char *const face_on_inf =
    "metric: {m: 1, a: 0, q: 0}\n"
    "observer: {r: inf, theta: 0, phi: 0, hextent: 16}\n"
    "accretion: {color1: [255, 255, 255], resolution: [8, 8], radius: [6, 20]%s}\n";

/* Mino, observer at infinity: every pixel, then the order-1 ring's inner
 * and outer edges along the centre row within 0.5 px. */
static void test_order_face_on_infinity(void **state)
{
    enum { W = 128, H = 128 };
    char text[512];
    cr_frame f;
    view v = {W, H, INFINITY, 16.0};
    double y0 = 0.5 * H - 0.5; /* beta = 0 */
    double px_m = 16.0 / W;    /* M per pixel */
    (void)state;
    snprintf(text, sizeof text, face_on_inf, "");
    frame_from(text, CR_INTEG_MINO, 1e-10, &f, W, H);
    assert_true(compare_pixels(&f, &v, -1, 1e-6, 1) > 50);

    /* the ring along the row beta = 0, right of the centre: its exact
     * edges in b (the first interval of b above b_c where the first disc
     * crossing is of order 1) against curray's (bisection on rays at
     * fractional x), in pixels */
    {
        double b = B_CRIT, b_in, b_out, lo, hi, x0 = 0.5 * W - 0.5, xs[2], mid;
        while (!exact_in_ring(b, f.r_stop) && b < 8.0)
            b += 0.002;
        assert_true(b < 8.0);
        lo = b, hi = B_CRIT;
        BISECT(lo, hi, exact_in_ring(x, f.r_stop));
        b_in = 0.5 * (lo + hi);
        lo = b, hi = b;
        while (exact_in_ring(hi, f.r_stop))
            hi += 0.002;
        BISECT(lo, hi, exact_in_ring(x, f.r_stop));
        b_out = 0.5 * (lo + hi);
        mid = x0 + 0.5 * (b_in + b_out) / px_m;
        for (int e = 0; e < 2; e++) {
            double far = e == 0 ? x0 + (b_in - 1.0) / px_m : x0 + (b_out + 1.0) / px_m;
            cr_pixel p;
            lo = mid, hi = far;
            p = cr_trace_point(&f, mid, y0);
            assert_true(p.outcome == CR_OUT_DISC && p.order == 1);
            BISECT(lo, hi, (p = cr_trace_point(&f, x, y0), p.outcome == CR_OUT_DISC && p.order == 1));
            xs[e] = 0.5 * (lo + hi);
        }
        print_message("order-1 ring on beta = 0: b from %.6f to %.6f M (exact %.6f to %.6f, "
                      "%.2f px wide): edges off by %.4f and %.4f px\n",
                      (xs[0] - x0) * px_m, (xs[1] - x0) * px_m, b_in, b_out,
                      (b_out - b_in) / px_m, xs[0] - (x0 + b_in / px_m), xs[1] - (x0 + b_out / px_m));
        assert_true(fabs(xs[0] - (x0 + b_in / px_m)) < 0.5);
        assert_true(fabs(xs[1] - (x0 + b_out / px_m)) < 0.5);
        /* the ring is several pixels wide, so 0.5 px means something */
        assert_true((b_out - b_in) / px_m > 3.0);
    }
}

/* ---- polar turning points before a sphere hit ------------------------------ */

/* The exact Schwarzschild ray from an observer at infinity at inclination
 * th_o (phi_o = 0) through image point (alpha, beta) moves in the plane
 * through the hole spanned by the observer's direction n_o and the unit
 * offset p = (alpha e_alpha + beta e_beta) / b, b = |(alpha, beta)|, e_beta
 * the image's up (the projection of the z axis), so that z . p = beta
 * sin(th_o) / b. At swept angle psi (0 at infinity) it is at
 * r(psi) (cos psi n_o + sin psi p), u = 1/r obeying Binet's equation
 * u'' = 3 u^2 - u (M = 1), u(0) = 0, u'(0) = 1/b, integrated here by RK4 in
 * psi (steps of 1e-4 rad). Its polar angle is extremal where the position
 * is along the plane's projection of the z axis, psi = psi_z + k pi with
 * psi_z = atan2(z . p, cos th_o), and it crosses the equator a quarter turn
 * from each, at psi_z +- pi/2 + k pi. The sphere of centre c and radius R is met at the
 * first psi where |x - c| <= R (bisection within the step). Fills the
 * numbers of turning points and of crossings before it; returns 1 for a
 * hit, 0 for a ray that reaches r_stop or leaves, -1 when the hit or an
 * event lies within margin of another or the ray grazes the sphere (the
 * pixel is left out). */
static int exact_sphere(double alpha, double beta, double th_o, const double c[3], double R,
                        double r_stop, int *turns, int *cross)
{
    const double h = 1e-4, margin = 2e-3;
    double b = hypot(alpha, beta), zp = beta * sin(th_o) / b, psi_z, psi_e, u = 0.0;
    double v = 1.0 / b;
    double no[3] = {sin(th_o), 0.0, cos(th_o)}, pe[3], eb[3], ea[3] = {0.0, 1.0, 0.0};
    double dmin = INFINITY, psi = 0.0;
    /* e_beta = the z axis less its part along n_o, normalised; e_alpha = y */
    for (int i = 0; i < 3; i++)
        eb[i] = (i == 2 ? 1.0 : 0.0) - cos(th_o) * no[i];
    for (int i = 0; i < 3; i++) {
        eb[i] /= sin(th_o);
        pe[i] = (alpha * ea[i] + beta * eb[i]) / b;
    }
    psi_z = atan2(zp, cos(th_o));
    if (psi_z < 0.0)
        psi_z += CR_PI;
    /* the first equator crossing, a quarter turn from a polar extreme */
    psi_e = psi_z < 0.5 * CR_PI ? psi_z + 0.5 * CR_PI : psi_z - 0.5 * CR_PI;
    for (int n = 0; n < 100000; n++) {
        double k1u = v, k1v = 3 * u * u - u, u2 = u + 0.5 * h * k1u, v2 = v + 0.5 * h * k1v;
        double k2u = v2, k2v = 3 * u2 * u2 - u2, u3 = u + 0.5 * h * k2u, v3 = v + 0.5 * h * k2v;
        double k3u = v3, k3v = 3 * u3 * u3 - u3, u4 = u + h * k3u, v4 = v + h * k3v;
        double k4u = v4, k4v = 3 * u4 * u4 - u4, un, d, x[3];
        un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
        v = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
        u = un;
        psi += h;
        if (u > 1.0 / r_stop)
            return 0;
        if (u <= 0.0)
            return dmin - R < margin ? -1 : 0; /* left for infinity */
        for (int i = 0; i < 3; i++)
            x[i] = (cos(psi) * no[i] + sin(psi) * pe[i]) / u - c[i];
        d = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (d < dmin)
            dmin = d;
        if (d <= R) {
            /* the hit lies within this step, psi - h .. psi: to within h */
            double t = (psi - psi_z) / CR_PI, e = (psi - psi_e) / CR_PI;
            if (fabs(t - floor(t + 0.5)) * CR_PI < margin ||
                fabs(e - floor(e + 0.5)) * CR_PI < margin)
                return -1;
            *turns = psi > psi_z ? 1 + (int)floor(t) : 0;
            *cross = psi > psi_e ? 1 + (int)floor(e) : 0;
            return 1;
        }
    }
    return -1;
}

/* A sphere beyond the north pole as seen from the observer (at infinity,
 * 60 deg): rays of the image's upper half pass over the pole, a polar
 * turning point, shortly before they meet it; at mino's default tolerance
 * the step that ends on the sphere holds that turning point for many of
 * them. Every pixel's outcome, theta_turns and order against the exact
 * ray (pixels within 2e-3 rad of swept angle of an event, or grazing the
 * sphere, left out). */
static void sphere_turns_case(int integ)
{
    enum { W = 64, H = 64 };
    static const char *const text =
        "metric: {m: 1, a: 0, q: 0}\n"
        "observer: {r: inf, theta: 60, phi: 0, hextent: 40}\n"
        "sphere: {color: [0, 0, 255], resolution: [4, 8], r: 20, theta: 13, phi: 180, "
        "radius: 4}\n";
    const double th_o = 60.0 * CR_PI / 180.0, thc = 13.0 * CR_PI / 180.0, R = 4.0;
    const double c[3] = {-20.0 * sin(thc), 0.0, 20.0 * cos(thc)};
    cr_frame f;
    cr_sphere sph[1];
    int compared = 0, skipped = 0, turned = 0;
    frame_spheres(text, integ, 0.0, &f, W, H, sph);
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double alpha = 20.0 * (2.0 * (i + 0.5) / W - 1.0);
            double beta = 20.0 * (1.0 - 2.0 * (j + 0.5) / H);
            int turns = 0, cross = 0, hit = exact_sphere(alpha, beta, th_o, c, R, f.r_stop,
                                                         &turns, &cross);
            cr_pixel px;
            if (hit < 0 || (hit == 0 && hypot(alpha, beta) < B_CRIT + 0.05)) {
                skipped++;
                continue;
            }
            px = cr_trace_pixel(&f, i, j);
            compared++;
            if ((px.outcome == CR_OUT_SPHERE) != hit)
                fail_msg("pixel (%d, %d) (alpha %.4f, beta %.4f): outcome %s, exact %s", i, j,
                         alpha, beta, cr_outcome_name(px.outcome), hit ? "sphere" : "no sphere");
            if (!hit)
                continue;
            if (px.theta_turns != turns || px.order != cross)
                fail_msg("pixel (%d, %d) (alpha %.4f, beta %.4f): theta_turns %d, order %d; "
                         "exact %d turning points and %d equator crossings before the sphere",
                         i, j, alpha, beta, px.theta_turns, px.order, turns, cross);
            turned += turns > 0;
        }
    print_message("sphere: %d pixels compared, %d left out, %d sphere hits after a polar "
                  "turning point\n",
                  compared, skipped, turned);
    assert_true(skipped < W * H / 10);
    assert_true(turned > 50);
}

static void test_sphere_turns_mino(void **state)
{
    (void)state;
    sphere_turns_case(CR_INTEG_MINO);
}

/* accretion.order: 1: the disc only where the ray crosses the plane for the
 * second time; the direct image is gone (rays pass through the disc). */
static void test_disc_order_only(void **state)
{
    enum { W = 100, H = 100 };
    char text[512];
    cr_frame f;
    view v = {W, H, INFINITY, 16.0};
    int n1;
    (void)state;
    snprintf(text, sizeof text, face_on_inf, ", order: 1");
    frame_from(text, CR_INTEG_MINO, 1e-10, &f, W, H);
    n1 = compare_pixels(&f, &v, 1, 1e-6, 1);
    /* the order-1 disc covers what the direct image hid: more pixels than
     * the visible ring of the full disc */
    assert_true(n1 > 500);
    for (int i = 0; i < W * H; i++) {
        cr_pixel p = cr_trace_pixel(&f, i % W, i / W);
        assert_true(p.outcome != CR_OUT_DISC || p.order == 1);
    }
}

/* rk4 (and mino) from a static observer on the axis at r = 200 M. */
static void finite_case(int integ, double tol, double r_tol)
{
    enum { W = 64, H = 64 };
    const char *text = "metric: {m: 1, a: 0, q: 0}\n"
                       "observer: {r: 200, theta: 0, phi: 0, hfov: 4.6}\n"
                       "accretion: {color1: [255, 255, 255], resolution: [8, 8], "
                       "radius: [6, 20]}\n";
    cr_frame f;
    view v = {W, H, 200.0, tan(2.3 * CR_PI / 180.0)};
    frame_from(text, integ, tol, &f, W, H);
    assert_true(compare_pixels(&f, &v, -1, r_tol, 1) > 10);
}

/* rk4 at its default step multiplier */
static void test_order_rk4_finite(void **state)
{
    (void)state;
    finite_case(CR_INTEG_RK4, 0.0, 1e-6);
}

static void test_order_mino_finite(void **state)
{
    (void)state;
    finite_case(CR_INTEG_MINO, 1e-10, 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_face_on_infinity),
        cmocka_unit_test(test_sphere_turns_mino),
        cmocka_unit_test(test_disc_order_only),
        cmocka_unit_test(test_order_mino_finite),
        cmocka_unit_test(test_order_rk4_finite),
    };
    gl_init();
    if (getenv("CR_TEST_ONLY")) /* a glob of test names, to run a few alone */
        cmocka_set_test_filter(getenv("CR_TEST_ONLY"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
