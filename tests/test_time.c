/* Coordinate time along rays (cr_ray_delay, ray.h; the regularised time of
 * mino.h) against values computed here independently, by quadrature of the
 * BL integrals (nothing of curray's integrators):
 *
 * 1. Schwarzschild radial rays: the delay t_obs - t at r equals the exact
 *    r*(r_o) - r*(r), r* = r + 2M ln(r/2M - 1), from a static observer at
 *    r_o = 40 M (mino and rk4) and, renormalised (t_o - t - r_o - 2M ln r_o
 *    as r_o -> infinity: -2M ln 2 - r*(r)), from the observer at infinity;
 *    points from r = 30 M down to 2.2 M.
 * 2. A Schwarzschild ray from infinity with impact parameter b = 5.4 M
 *    (turning point at 3.44 M, close to the photon sphere): the delay at
 *    r = 20, 6 M on the way in and 4, 6, 20, 60 M on the way out, against the
 *    quadrature of dt/dr = 1 / ((1 - 2M/r) sqrt(1 - b^2 (1 - 2M/r) / r^2))
 *    over each monotonic leg (substitutions remove the turning point's
 *    inverse square root), renormalised like 1.
 * 3. Kerr, a = 0.9: rays with no radial and no polar turning point before
 *    they cross the equator, from the observer at infinity (inclination
 *    60 deg) and from a static observer at r_o = 100 M (80 deg). The
 *    reference: the Mino time of the crossing from the polar integral
 *    tau = int du / sqrt(Theta(u)), the crossing radius from
 *    int dr / sqrt(R(r)) = tau, and the delay
 *      int (r^2 + a^2) P / (Delta sqrt(R)) dr - a (L + a E) tau
 *        + a^2 E int u^2 du / sqrt(Theta)
 *    (renormalised at infinity like 1), all by composite Gauss-Legendre.
 *    Both the crossing radius and the delay are compared.
 * Tolerances are stated per check, relative to the delay's magnitude
 * (floored at 1 M).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

/* ---- composite Gauss-Legendre ----------------------------------------- */

typedef double (*fun1)(double x, const void *ctx);

static double quad(fun1 f, const void *ctx, double a, double b, int panels)
{
    static const double x8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                 0.9602898564975363};
    static const double w8[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                 0.1012285362903763};
    double h = (b - a) / panels, sum = 0.0;
    int p, k;
    for (p = 0; p < panels; p++) {
        double c = a + (p + 0.5) * h, s = 0.0;
        for (k = 0; k < 4; k++)
            s += w8[k] * (f(c - 0.5 * h * x8[k], ctx) + f(c + 0.5 * h * x8[k], ctx));
        sum += 0.5 * h * s;
    }
    return sum;
}

/* ---- walking a ray to the k-th crossing of a radius ------------------- */

/* The step fraction of the last located crossing. */
static double s_at;

/* Value whose sign change marks r = rh: rh/r - 1 (-1 at w = 0). */
static double radius_value(const cr_ray *ray, const double *y, double rh)
{
    double r, th, ph;
    cr_ray_position(ray, y, &r, &th, &ph);
    return rh / r - 1.0;
}

/* Step the ray with the trace loop's functions to the k-th crossing of
 * r = rh (k = 1, 2, ...), located by regula falsi on cr_ray_state_at; the
 * state there into ys. Returns 0 on success. */
static int walk_to_radius(const cr_frame *f, cr_ray *ray, double rh, int k, double *ys)
{
    double turns = 0.0;
    long steps = 0;
    int seen = 0;
    while (steps++ < 100000) {
        double v0, v1;
        if (cr_ray_at_horizon(f, ray))
            return -1;
        cr_ray_begin(ray);
        if (cr_ray_escaping(f, ray) || cr_ray_advance(f, ray) != 0)
            return -1;
        v0 = radius_value(ray, cr_ray_y0(ray), rh);
        v1 = radius_value(ray, cr_ray_y1(ray), rh);
        if (v0 != 0.0 && (v0 < 0.0) != (v1 < 0.0) && ++seen == k) {
            cr_falsi z;
            cr_falsi_start(&z, v0, 1.0, v1);
            while (cr_falsi_next(&z)) {
                cr_ray_state_at(ray, z.s, ys);
                if (!cr_falsi_update(&z, radius_value(ray, ys, rh)))
                    break;
            }
            s_at = z.s;
            return 0;
        }
        cr_ray_commit(f, ray, &turns);
    }
    return -1;
}

/* The same to the first crossing of the equatorial plane (the disc event). */
static int walk_to_equator(const cr_frame *f, cr_ray *ray, double *ys)
{
    double turns = 0.0;
    long steps = 0;
    while (steps++ < 100000) {
        double v0, v1;
        if (cr_ray_at_horizon(f, ray))
            return -1;
        cr_ray_begin(ray);
        if (cr_ray_escaping(f, ray) || cr_ray_advance(f, ray) != 0)
            return -1;
        v0 = cr_ray_event_value(f, ray, CR_EV_DISC, cr_ray_y0(ray));
        v1 = cr_ray_event_value(f, ray, CR_EV_DISC, cr_ray_y1(ray));
        if (v0 != 0.0 && (v0 < 0.0) != (v1 < 0.0)) {
            s_at = cr_ray_event_locate(f, ray, CR_EV_DISC, v0, 1.0, v1, ys);
            return 0;
        }
        cr_ray_commit(f, ray, &turns);
    }
    return -1;
}

static const uint8_t sky_texel[3] = {0, 0, 0};

static void frame(cr_frame *f, double a, double r, double theta, int integrator)
{
    cr_test_empty_frame(f, 1.0, a, 0.0, r, theta);
    f->observer.hextent = f->observer.vextent = 40.0;
    f->integrator = integrator;
    f->sky.rgb = sky_texel; /* a sky image: rays are followed to infinity */
    f->sky.width = f->sky.height = 1;
    cr_frame_prepare(f);
    f->w_obj = 0.0; /* no object: the time is wanted along the whole ray */
}

static double rel_err(double got, double want)
{
    return fabs(got - want) / fmax(1.0, fabs(want));
}

/* ---- 1. Schwarzschild radial rays ------------------------------------- */

static double rstar(double r)
{
    return r + 2.0 * log(r / 2.0 - 1.0);
}

static void test_radial(void **state)
{
    const double rh[5] = {30.0, 12.0, 6.0, 3.0, 2.2};
    const double tol[3] = {1e-8, 1e-8, 1e-6}; /* static mino, infinity mino, static rk4 */
    int which, i;
    (void)state;
    for (which = 0; which < 3; which++) {
        double worst = 0.0;
        for (i = 0; i < 5; i++) {
            cr_frame f;
            cr_ray ray;
            double ys[CR_RAY_NY], want, got;
            frame(&f, 0.0, which == 1 ? INFINITY : 40.0, 1.1,
                  which == 2 ? CR_INTEG_RK4 : CR_INTEG_MINO);
            if (which == 1) {
                cr_camera_ray_at_infinity(&f, 0.0, 0.0, &ray.c, ray.m);
                cr_ray_mino_start(&f, &ray);
                want = -2.0 * log(2.0) - rstar(rh[i]);
            } else {
                double n[3] = {-1.0, 0.0, 0.0}, yb[CR_NY];
                cr_geo g;
                cr_camera_ray(&f, n, &g, yb);
                cr_ray_from_bl(&f, &g, yb, &ray);
                want = rstar(40.0) - rstar(rh[i]);
            }
            assert_int_equal(walk_to_radius(&f, &ray, rh[i], 1, ys), 0);
            got = cr_ray_delay_at(&f, &ray, s_at, ys);
            print_message("radial %s r = %4.1f: delay %.12f, exact %.12f, error %.2e\n",
                          which == 0 ? "mino r_o=40" : which == 1 ? "mino r_o=inf" : "rk4 r_o=40 ",
                          rh[i], got, want, rel_err(got, want));
            worst = fmax(worst, rel_err(got, want));
        }
        assert_true(worst <= tol[which]);
    }
}

/* ---- 2. Schwarzschild ray with a turning point ------------------------ */

typedef struct sch {
    double b, wmin; /* impact parameter; 1/r at the turning point */
} sch;

/* W(w) = 1 - b^2 w^2 + 2 b^2 w^3 (E = 1). */
static double sch_W(const sch *s, double w)
{
    return 1.0 - s->b * s->b * w * w * (1.0 - 2.0 * w);
}

/* Inward leg from infinity to the turning point, w = wmin (1 - x^2),
 * x in [0, 1]: integrand of int (F / sqrt(W) - 1/w^2 - 2/w) dw, F = 1 / (w^2
 * (1 - 2w)), times dw/dx; the subtraction computed in long double. */
static double sch_leg_far(double x, const void *ctx)
{
    const sch *s = ctx;
    long double w = s->wmin * (1.0 - x * x);
    long double W = sch_W(s, (double)w);
    long double g;
    if (w < 1e-7L) {
        /* series: F/sqrt(W) - 1/w^2 - 2/w = 4 + b^2/2 + O(w) */
        g = 4.0L + 0.5L * s->b * s->b;
    } else {
        g = (1.0L / ((1.0L - 2.0L * w) * sqrtl(W)) - 1.0L - 2.0L * w) / (w * w);
    }
    return (double)(g * 2.0L * s->wmin * x);
}

/* Outward leg from the turning point to r: r = rmin + x^2, integrand of
 * int dt/dr dr times dr/dx. */
typedef struct sch_out {
    const sch *s;
} sch_out;

static double sch_leg_out(double x, const void *ctx)
{
    const sch *s = ctx;
    double rmin = 1.0 / s->wmin, r = rmin + x * x;
    double q = 1.0 - s->b * s->b * (1.0 - 2.0 / r) / (r * r);
    if (x == 0.0)
        return 0.0; /* the limit of 2x / sqrt(q) is finite; the node never falls here */
    return 2.0 * x / ((1.0 - 2.0 / r) * sqrt(q));
}

/* Plain dt/dr from r1 to r2 on a monotonic leg away from the turning point. */
static double sch_dtdr(double r, const void *ctx)
{
    const sch *s = ctx;
    return 1.0 / ((1.0 - 2.0 / r) * sqrt(1.0 - s->b * s->b * (1.0 - 2.0 / r) / (r * r)));
}

static void test_turning_point(void **state)
{
    sch s;
    double lo, hi, far, rmin;
    int i;
    const double pts[6][2] = {{20.0, 1}, {6.0, 1}, {4.0, 2}, {6.0, 2}, {20.0, 2}, {60.0, 2}};
    double worst = 0.0;
    (void)state;
    s.b = 5.4;
    /* turning point: the largest root below 1/3 of W */
    lo = 0.0;
    hi = 1.0 / 3.0;
    for (i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (sch_W(&s, mid) > 0.0)
            lo = mid;
        else
            hi = mid;
    }
    s.wmin = lo;
    rmin = 1.0 / s.wmin;
    far = quad(sch_leg_far, &s, 0.0, 1.0, 400) - rmin - 2.0 * log(rmin);
    for (i = 0; i < 6; i++) {
        cr_frame f;
        cr_ray ray;
        double ys[CR_RAY_NY], r = pts[i][0], want, got;
        int leg = (int)pts[i][1];
        frame(&f, 0.0, INFINITY, 0.0, CR_INTEG_MINO);
        cr_camera_ray_at_infinity(&f, s.b, 0.0, &ray.c, ray.m);
        cr_ray_mino_start(&f, &ray);
        if (leg == 1)
            want = far - quad(sch_dtdr, &s, rmin + 1.0, r, 400) -
                   quad(sch_leg_out, &s, 0.0, 1.0, 400);
        else
            want = far + quad(sch_leg_out, &s, 0.0, 1.0, 400) + quad(sch_dtdr, &s, rmin + 1.0, r, 400);
        assert_int_equal(walk_to_radius(&f, &ray, r, leg, ys), 0);
        got = cr_ray_delay_at(&f, &ray, s_at, ys);
        print_message("b = 5.4, r_min = %.6f, r = %4.1f leg %d: delay %.12f, quadrature %.12f, "
                      "error %.2e\n",
                      rmin, r, leg, got, want, rel_err(got, want));
        worst = fmax(worst, rel_err(got, want));
    }
    assert_true(worst <= 3e-7);
}

/* ---- 3. Kerr rays without turning points ------------------------------ */

typedef struct kerr {
    double a, E, L, eta, uo; /* constants; cos(theta) at the observer */
} kerr;

static double kerr_Th(const kerr *k, double u)
{
    double a2E2 = k->a * k->a * k->E * k->E;
    return k->eta - (k->eta + k->L * k->L - a2E2) * u * u - a2E2 * u * u * u * u;
}

/* W(w) = w^4 R(1/w), R = P^2 - Delta (eta + (L - aE)^2)... in the sign
 * convention of geodesic.h: P = E (r^2 + a^2) + a L, C = eta + (L + aE)^2. */
static double kerr_W(const kerr *k, double w)
{
    double a = k->a, P = k->E * (1.0 + a * a * w * w) + a * k->L * w * w;
    double C = k->eta + (k->L + a * k->E) * (k->L + a * k->E);
    double D = 1.0 - 2.0 * w + a * a * w * w;
    return P * P - D * w * w * C;
}

static double kerr_dtau_du(double u, const void *ctx)
{
    return 1.0 / sqrt(kerr_Th(ctx, u));
}

static double kerr_u2_du(double u, const void *ctx)
{
    return u * u / sqrt(kerr_Th(ctx, u));
}

static double kerr_dtau_dw(double w, const void *ctx)
{
    return 1.0 / sqrt(kerr_W(ctx, w));
}

/* (r^2 + a^2) P / Delta d tau in w, renormalised at w = 0: int of
 * [F / sqrt(W) - E/w^2 - 2ME/w] dw with F = (r^2+a^2) P / Delta, in long
 * double (the subtraction), for the observer at infinity (E = 1). */
static double kerr_dt_dw_inf(double w, const void *ctx)
{
    const kerr *k = ctx;
    long double a = k->a, lw = w;
    long double p = (1.0L + a * a * lw * lw) * (k->E * (1.0L + a * a * lw * lw) + a * k->L * lw * lw);
    long double D = 1.0L - 2.0L * lw + a * a * lw * lw;
    long double W = kerr_W(k, w);
    return (double)((p / (D * sqrtl(W)) - k->E * (1.0L + 2.0L * lw)) / (lw * lw));
}

/* The plain integrand (r^2 + a^2) P / (Delta sqrt(R)) dr in w: F/sqrt(W) dw. */
static double kerr_dt_dw(double w, const void *ctx)
{
    const kerr *k = ctx;
    double a = k->a;
    double p = (1.0 + a * a * w * w) * (k->E * (1.0 + a * a * w * w) + a * k->L * w * w);
    double D = 1.0 - 2.0 * w + a * a * w * w;
    return p / (D * sqrt(kerr_W(k, w)) * w * w);
}

/* Reference crossing radius and delay for a ray from w = wo (0: infinity)
 * moving inward and toward the equator with neither turning point. */
static void kerr_reference(const kerr *k, double wo, double *r_cross, double *delay)
{
    double tau = quad(kerr_dtau_du, k, 0.0, k->uo, 200), lo = wo, hi = 1.0 / 2.0, wh, dt;
    int i;
    for (i = 0; i < 100; i++) {
        double mid = 0.5 * (lo + hi);
        if (quad(kerr_dtau_dw, k, wo, mid, 200) < tau)
            lo = mid;
        else
            hi = mid;
    }
    wh = 0.5 * (lo + hi);
    if (wo == 0.0)
        dt = quad(kerr_dt_dw_inf, k, 0.0, wh, 400) - 1.0 / wh + 2.0 * log(wh);
    else
        dt = quad(kerr_dt_dw, k, wo, wh, 400);
    dt += -k->a * (k->L + k->a * k->E) * tau +
          k->a * k->a * k->E * quad(kerr_u2_du, k, 0.0, k->uo, 200);
    *r_cross = 1.0 / wh;
    *delay = dt;
}

static void test_kerr(void **state)
{
    int which;
    (void)state;
    for (which = 0; which < 2; which++) {
        cr_frame f;
        cr_ray ray;
        kerr k;
        double ys[CR_RAY_NY], want_r, want_t, got_r, got_t, th, ph, wo, x;
        int i;
        if (which == 0) {
            frame(&f, 0.9, INFINITY, 60.0 * CR_PI / 180.0, CR_INTEG_MINO);
            cr_camera_ray_at_infinity(&f, 2.0, 3.0, &ray.c, ray.m);
            if (!(ray.m[CR_M_DNZ] < 0.0))
                cr_camera_ray_at_infinity(&f, 2.0, -3.0, &ray.c, ray.m);
            cr_ray_mino_start(&f, &ray);
            wo = 0.0;
        } else {
            double n[3] = {-0.97, 0.2, 0.1}, yb[CR_NY], l;
            cr_geo g;
            l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (i = 0; i < 3; i++)
                n[i] /= l;
            frame(&f, 0.9, 100.0, 80.0 * CR_PI / 180.0, CR_INTEG_MINO);
            cr_camera_ray(&f, n, &g, yb);
            cr_ray_from_bl(&f, &g, yb, &ray);
            wo = 0.01;
        }
        k.a = 0.9;
        k.E = ray.c.E;
        k.L = ray.c.L;
        k.eta = ray.c.eta;
        k.uo = ray.m[CR_M_NZ];
        /* the ray moves toward the equator and inward, with no turning point */
        assert_true(ray.m[CR_M_DNZ] < 0.0 && k.uo > 0.0 && ray.m[CR_M_DW] > 0.0);
        for (i = 0; i <= 100; i++) {
            assert_true(kerr_Th(&k, k.uo * i / 100.0) > 0.0);
        }
        kerr_reference(&k, wo, &want_r, &want_t);
        for (i = 0; i <= 100; i++) {
            x = wo + (1.0 / want_r - wo) * i / 100.0;
            assert_true(kerr_W(&k, x) > 0.0);
        }
        assert_int_equal(walk_to_equator(&f, &ray, ys), 0);
        cr_ray_position(&ray, ys, &got_r, &th, &ph);
        got_t = cr_ray_delay_at(&f, &ray, s_at, ys);
        print_message("kerr a = 0.9 %s: crossing r %.12f (quadrature %.12f, error %.2e), "
                      "delay %.12f (quadrature %.12f, error %.2e)\n",
                      which == 0 ? "from infinity" : "r_o = 100    ", got_r, want_r,
                      fabs(got_r - want_r) / want_r, got_t, want_t, rel_err(got_t, want_t));
        assert_true(fabs(got_r - want_r) / want_r <= 1e-7);
        assert_true(rel_err(got_t, want_t) <= 1e-7);
        /* the same ray through cr_trace_loop onto a disc: the pixel's delay */
        {
            cr_frame fd = f;
            cr_ray r2;
            cr_pixel px;
            fd.disc.enabled = 1;
            fd.disc.r_in = 2.0;
            fd.disc.r_out = 200.0;
            fd.disc.n_radial = 2;
            fd.disc.n_sectors = 12;
            cr_frame_prepare(&fd);
            if (which == 0) {
                cr_camera_ray_at_infinity(&fd, 2.0, 3.0, &r2.c, r2.m);
                if (!(r2.m[CR_M_DNZ] < 0.0))
                    cr_camera_ray_at_infinity(&fd, 2.0, -3.0, &r2.c, r2.m);
                cr_ray_mino_start(&fd, &r2);
            } else {
                double n[3] = {-0.97, 0.2, 0.1}, yb[CR_NY], l;
                cr_geo g;
                l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                for (i = 0; i < 3; i++)
                    n[i] /= l;
                cr_camera_ray(&fd, n, &g, yb);
                cr_ray_from_bl(&fd, &g, yb, &r2);
            }
            px = cr_trace_loop(&fd, &r2);
            assert_int_equal(px.outcome, CR_OUT_DISC);
            print_message("  cr_trace_loop: hit_r %.12f, delay %.12f (error %.2e)\n", px.hit_r,
                          px.delay, rel_err(px.delay, want_t));
            assert_true(rel_err(px.delay, want_t) <= 1e-7);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_radial),
        cmocka_unit_test(test_turning_point),
        cmocka_unit_test(test_kerr),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
