/* The science outputs of a disc hit at the DEFAULT tolerance against the
 * exact Schwarzschild orbit, for rays close to the photon sphere (the most
 * sensitive: a relative error e in the ray's Carter constant moves the hit
 * of a ray that winds near r = 3 M by about e / (b - b_c) in orbital angle).
 *
 * Reference (written here, nothing of curray's but the ray's start: its
 * position and direction n, dn/dtau and impact parameter b = sqrt(kap) / E):
 * with M = 1 and u = 1/r the orbit lies in the plane of n and dn/dtau and
 *   d psi / du = 1 / sqrt(G(u)),  G(u) = 1/b^2 - u^2 + 2 u^3
 *             = 2 (u - u1)(u - u2)(u - u3),  u1 < 0 < u2 < u3,
 *   d t / du  = 1 / (b u^2 (1 - 2u) sqrt(G(u)))   (Darwin 1959).
 * The angle psi from the start to the turning point u2 is F(u0) =
 * int_u0^u2 du / sqrt(G) in closed form by Carlson's R_F (checked against
 * adaptive Gauss-Legendre quadrature below); the ray crosses the equatorial
 * plane where its position direction cos(psi) n0 + sin(psi) t0 has no z
 * part, psi_k = psi_0 + k pi, and the radius there is the u of psi_k
 * (bisection on F: F(u0) - F(u) on the way in, F(u0) + F(u) after the
 * turn). The azimuth of the hit is that direction's. The delay t_obs - t is
 * the time integral, by adaptive quadrature over u = u2 - v^2 (regular at
 * the turning point), for the observer at infinity renormalised as curray
 * does (mino.h): t_o - t - r_o - 2 ln r_o as r_o -> infinity, i.e. the
 * integrand's 1/u^2 + 2/u subtracted near u = 0 and integrated in closed
 * form. The frequency ratio of the Keplerian disc (matter on circular
 * orbits, u^t = 1/sqrt(1 - 3/r), Omega = r^(-3/2)) seen by a static
 * observer at r_o: g = E / sqrt(1 - 2/r_o) / (u^t (E - Omega L_phys)), the
 * photon's physical azimuthal momentum L_phys = -L (curray's L is u_phi of
 * the past-directed tangent, geodesic.h).
 *
 * 1. The reference functions: F by R_F against quadrature to 1e-12; the
 *    renormalised delay at infinity against a far observer's delay minus
 *    r_o + 2 ln r_o (r_o = 1e7: agree to 1e-5).
 * 2. 96 rays, impact parameters b_c + 10^(-5..-1) in random directions of
 *    the image, from a static observer at r = 30 M and from infinity
 *    (inclinations 85 and 60 deg), each hitting a Keplerian disc [6, 20] M
 *    at its first crossing inside it (of any order: up to 3 crossings
 *    before): at the default tolerance the hit is of the predicted order,
 *    and hit_r, g, hit_phi and the delay within the bounds B_* below, in a
 *    science frame (cr_frame.science) and, within B_IMG_*, in a colour one;
 *    the science frame takes more steps, but fewer than 1.5 times as many.
 * 3. Listing 7.1.1's scene at 64x48 in frame 8 of 18 (theta = 85 deg, figure
 *    7.1.2), pixel (29, 16), a lensed image near the photon sphere, in a
 *    science frame: hit_r
 *    within B_PIXEL relative of the exact orbit's (which itself agrees with
 *    the independent reference 13.673223546 M of the defect report to 1e-8).
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
#include "testutil.h"

#define B_C 5.196152422706632 /* 3 sqrt(3) */

/* The bounds at the default tolerance (1e-7) of a science frame
 * (cr_frame.science, set by the command line for -t d and -t f and by the
 * Python module: its steps at half the tolerance, CR_SCIENCE_TOL):
 * relative for hit_r and g, radians for hit_phi, relative to max(|delay|,
 * hit_r) for the delay; the listing's pixel, relative. Measured 7.0e-8
 * (hit_r), 1.3e-8 (g), 3e-14 (hit_phi), 2.6e-8 (delay), 1.9e-8 (pixel).
 * A colour frame (science 0) keeps the steps of the tolerance itself: its
 * values within B_IMG_* (measured 1.7e-7 hit_r, 4.7e-8 g, 5.7e-7 delay).
 * Before the accepted-step projection (mino_lane.h) the same rays were off
 * by up to 1.3e-2 (hit_r), 3.0e-3 (g), 2.5e-3 (delay) and the pixel by
 * 1.2e-6; before the science frames and the quadrature of T at every hit
 * of a science frame (ray.h) by 1.7e-7 (hit_r) and 4.9e-6 (delay). */
#define B_HIT_R 1e-7
#define B_G 1e-7
#define B_PHI 1e-12
#define B_DELAY 1e-7
#define B_PIXEL 1e-7
#define B_IMG_HIT_R 2e-7
#define B_IMG_DELAY 1e-6

/* ---- adaptive Gauss-Legendre quadrature ---------------------------------- */

#define AQ_N 12
static double aq_x[AQ_N], aq_w[AQ_N];

static void aq_init(void)
{
    for (int i = 0; i < AQ_N; i++) {
        double x = cos(CR_PI * (i + 0.75) / (AQ_N + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = x, dx;
            for (int k = 2; k <= AQ_N; k++) {
                double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = AQ_N * (x * p1 - p0) / (x * x - 1.0);
            dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        aq_x[i] = x;
        aq_w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
}

typedef double (*aq_fn)(const void *ctx, double x);

static double aq_panel(aq_fn f, const void *ctx, double a, double b)
{
    double s = 0.0, c = 0.5 * (a + b), h = 0.5 * (b - a);
    for (int i = 0; i < AQ_N; i++)
        s += aq_w[i] * f(ctx, c + h * aq_x[i]);
    return h * s;
}

static double aq_rec(aq_fn f, const void *ctx, double a, double b, double whole, int depth)
{
    double m = 0.5 * (a + b), l = aq_panel(f, ctx, a, m), r = aq_panel(f, ctx, m, b);
    if (depth >= 24 || fabs(l + r - whole) <= 1e-14 * fabs(l + r))
        return l + r;
    return aq_rec(f, ctx, a, m, l, depth + 1) + aq_rec(f, ctx, m, b, r, depth + 1);
}

/* int_a^b f to about 1e-14 relative (12-point panels halved until two
 * levels agree). */
static double aq(aq_fn f, const void *ctx, double a, double b)
{
    if (a == b)
        return 0.0;
    return aq_rec(f, ctx, a, b, aq_panel(f, ctx, a, b), 0);
}

/* ---- the exact orbit ------------------------------------------------------ */

/* Carlson's R_F(x, y, z) by duplication (Carlson 1995). */
static double carlson_rf(double x, double y, double z)
{
    double ave, dx, dy, dz, e2, e3;
    for (;;) {
        double sx = sqrt(x), sy = sqrt(y), sz = sqrt(z);
        double lam = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        ave = (x + y + z) / 3.0;
        dx = (ave - x) / ave;
        dy = (ave - y) / ave;
        dz = (ave - z) / ave;
        if (fmax(fabs(dx), fmax(fabs(dy), fabs(dz))) < 1e-4)
            break;
    }
    e2 = dx * dy - dz * dz;
    e3 = dx * dy * dz;
    return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / sqrt(ave);
}

typedef struct orbit {
    double b, u1, u2, u3;
} orbit;

static double orbit_G(const orbit *o, double u)
{
    return 1.0 / (o->b * o->b) - u * u + 2.0 * u * u * u;
}

/* The roots of G for b > b_c (trigonometric solution, polished by Newton). */
static void orbit_init(orbit *o, double b)
{
    double p = -1.0 / 12.0, q = -1.0 / 108.0 + 0.5 / (b * b);
    double m = 2.0 * sqrt(-p / 3.0), th = acos(fmax(-1.0, fmin(1.0, 1.5 * q / p * sqrt(-3.0 / p))));
    double u[3];
    for (int k = 0; k < 3; k++) {
        u[k] = 1.0 / 6.0 + m * cos(th / 3.0 - CR_TWO_PI * k / 3.0);
        for (int it = 0; it < 4; it++) {
            double g = 1.0 / (b * b) - u[k] * u[k] + 2.0 * u[k] * u[k] * u[k];
            double dg = -2.0 * u[k] + 6.0 * u[k] * u[k];
            if (dg != 0.0)
                u[k] -= g / dg;
        }
    }
    o->b = b;
    o->u3 = u[0];
    o->u2 = u[1];
    o->u1 = u[2];
}

/* F(y) = int_y^u2 du / sqrt(G), y <= u2, by R_F. */
static double orbit_F(const orbit *o, double y)
{
    double a = o->u2 - o->u1, c = o->u3 - o->u2;
    if (y >= o->u2)
        return 0.0;
    return sqrt(2.0 * (o->u2 - y)) * carlson_rf(a * c, (y - o->u1) * c, (o->u3 - y) * a);
}

/* Integrands over v, u = u2 - v^2: dpsi and dt per dv. */
static double dpsi_dv(const void *ctx, double v)
{
    const orbit *o = ctx;
    double u = o->u2 - v * v;
    return 2.0 / sqrt(2.0 * (u - o->u1) * (o->u3 - u));
}

static double dt_dv(const void *ctx, double v)
{
    const orbit *o = ctx;
    double u = o->u2 - v * v;
    return dpsi_dv(ctx, v) / (o->b * u * u * (1.0 - 2.0 * u));
}

/* dt/du - 1/u^2 - 2/u (no cancellation: with q = b sqrt(G),
 * dt/du = 1/(u^2 (1 - 2u) q) and 1 - q = b^2 u^2 (1 - 2u) / (1 + q)). */
static double dt_du_ren(const void *ctx, double u)
{
    const orbit *o = ctx;
    double q = o->b * sqrt(orbit_G(o, u)), b2 = o->b * o->b;
    return (b2 * (1.0 - 2.0 * u) / (1.0 + q) + 4.0 * q) / ((1.0 - 2.0 * u) * q);
}

/* F by quadrature (the check of orbit_F). */
static double orbit_F_quad(const orbit *o, double y)
{
    return aq(dpsi_dv, o, 0.0, sqrt(o->u2 - y));
}

/* T(y) = int_y^u2 dt/du du. */
static double orbit_T(const orbit *o, double y)
{
    return y >= o->u2 ? 0.0 : aq(dt_dv, o, 0.0, sqrt(o->u2 - y));
}

/* The time from the observer at u0 (0: at infinity, renormalised) inward
 * to u <= u2. */
static double orbit_t_in(const orbit *o, double u0, double u)
{
    double um = 0.5 * o->u2;
    if (u0 > 0.0)
        return orbit_T(o, u0) - orbit_T(o, u);
    if (u <= um)
        return aq(dt_du_ren, o, 0.0, u) - 1.0 / u + 2.0 * log(u);
    return aq(dt_du_ren, o, 0.0, um) - 1.0 / um + 2.0 * log(um) + orbit_T(o, um) - orbit_T(o, u);
}

/* The u at orbital angle psi from u0 (0 when the ray has escaped), and
 * whether it is still on the way in. */
static double orbit_u_at(const orbit *o, double u0, double psi, int *inbound)
{
    double F0 = orbit_F(o, u0), target, lo, hi;
    *inbound = psi <= F0;
    if (*inbound) {
        target = F0 - psi;
        lo = u0;
    } else {
        target = psi - F0;
        lo = 0.0;
        if (target > orbit_F(o, 0.0))
            return 0.0;
    }
    hi = o->u2;
    for (int it = 0; it < 200; it++) { /* F decreases from lo to hi */
        double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi)
            break;
        if (orbit_F(o, mid) > target)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* What the exact orbit predicts for a ray's disc hit. */
typedef struct exact_hit {
    int order; /* -1: no crossing inside [r_in, r_out] */
    double r, phi, delay, g;
} exact_hit;

/* The exact hit of the Schwarzschild (M = 1) ray whose Mino start is m with
 * constants c (moving inward), on a disc [r_in, r_out] in the equatorial
 * plane, seen by a static observer at u0 = m[W] (0: at infinity). */
static exact_hit exact_disc_hit(const cr_mino *c, const double *m, double r_in, double r_out)
{
    exact_hit x = {-1, 0.0, 0.0, 0.0, 0.0};
    double n0[3] = {m[CR_M_NX], m[CR_M_NY], m[CR_M_NZ]};
    double t0[3] = {m[CR_M_DNX], m[CR_M_DNY], m[CR_M_DNZ]};
    double len = sqrt(t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]);
    double u0 = m[CR_M_W], psi0;
    orbit o;
    for (int i = 0; i < 3; i++)
        t0[i] /= len;
    orbit_init(&o, sqrt(c->kap) / c->E);
    psi0 = fmod(atan2(t0[2], n0[2]) + 0.5 * CR_PI, CR_PI);
    if (psi0 <= 0.0)
        psi0 += CR_PI;
    for (int k = 0; k < 12; k++) {
        double psi = psi0 + k * CR_PI, u, r;
        int inbound;
        u = orbit_u_at(&o, u0, psi, &inbound);
        if (u == 0.0)
            break;
        r = 1.0 / u;
        if (r >= r_in && r <= r_out) {
            double p[3], ut = 1.0 / sqrt(1.0 - 3.0 * u), om = pow(r, -1.5);
            for (int i = 0; i < 3; i++)
                p[i] = cos(psi) * n0[i] + sin(psi) * t0[i];
            x.order = k;
            x.r = r;
            x.phi = atan2(p[1], p[0]);
            if (x.phi < 0.0)
                x.phi += CR_TWO_PI;
            x.delay = inbound ? orbit_t_in(&o, u0, u) : orbit_t_in(&o, u0, o.u2) + orbit_T(&o, u);
            x.g = c->E / sqrt(1.0 - 2.0 * u0) / (ut * (c->E + om * c->L));
            return x;
        }
    }
    return x;
}

/* ---- frames --------------------------------------------------------------- */

static void frame_from(const char *text, cr_frame *f, int w, int h, int science)
{
    cr_scene s;
    cr_err err;
    cr_trace_settings ts = cr_trace_defaults(); /* the default tolerance */
    memset(&s, 0, sizeof s);
    if (cr_scene_load_string(text, strlen(text), "accuracy.yml", &s, &err))
        fail_msg("%s", err.msg);
    if (cr_scene_frame(&s, 0, 1, w, h, &ts, f, NULL, &err))
        fail_msg("%s", err.msg);
    cr_scene_free(&s);
    f->science = science;
}

/* The ray through image point (x, y) and its impact parameter. */
static double point_b(const cr_frame *f, double x, double y, cr_ray *ray)
{
    cr_pixel px;
    assert_true(cr_trace_point_ray(f, x, y, ray, &px));
    assert_int_equal(ray->kind, CR_INTEG_MINO);
    return sqrt(ray->c.kap) / ray->c.E;
}

/* ---- 1. the reference functions ------------------------------------------- */

static void test_reference(void **state)
{
    const double bs[5] = {B_C + 1e-6, B_C + 1e-3, 5.5, 8.0, 100.0};
    double worst = 0.0;
    (void)state;
    aq_init();
    for (int i = 0; i < 5; i++) {
        orbit o;
        orbit_init(&o, bs[i]);
        assert_true(o.u1 < 0.0 && 0.0 < o.u2 && o.u2 < o.u3);
        for (double y = 0.0; y < o.u2; y += 0.15 * o.u2) {
            double e = fabs(orbit_F(&o, y) - orbit_F_quad(&o, y)) / orbit_F(&o, y);
            worst = fmax(worst, e);
        }
    }
    print_message("F by Carlson's R_F vs quadrature: worst relative difference %.3g "
                  "(bound 1e-12)\n", worst);
    assert_true(worst < 1e-12);
    /* the renormalised delay at infinity is the limit of the far observer's:
     * delay(r_o) - r_o - 2 ln r_o = delay(inf) - (b^2/2 + 4)/r_o + O(r_o^-2)
     * (the subtracted integrand is b^2/2 + 4 at u = 0; the next term is O(u^2)) */
    for (int i = 0; i < 5; i++) {
        orbit o;
        double r_o = 1e4, far, inf, e;
        orbit_init(&o, bs[i]);
        inf = orbit_t_in(&o, 0.0, o.u2) + orbit_T(&o, 0.1 * o.u2);
        far = orbit_t_in(&o, 1.0 / r_o, o.u2) + orbit_T(&o, 0.1 * o.u2) - r_o - 2.0 * log(r_o);
        e = fabs(far - (inf - (0.5 * bs[i] * bs[i] + 4.0) / r_o));
        print_message("b = %.9g: renormalised delay %.12g; from r_o = 1e4 %.12g, minus the 1/r_o "
                      "term off by %.3g (bound (b^2 + 100) / r_o^2)\n", bs[i], inf, far, e);
        assert_true(e < (bs[i] * bs[i] + 100.0) / (r_o * r_o));
    }
}

/* ---- 2. rays near the photon sphere --------------------------------------- */

typedef struct worst {
    double r, g, phi, delay;
    long steps;
    int n;
} worst;

/* Trace n rays of frame f near the critical curve, each at b_c + 10^(-5..-1)
 * in a random direction chi of the image plane from its centre, against
 * the exact hit. */
static void near_critical(const cr_frame *f, int n, uint64_t *seed, worst *wo, double b_r,
                          double b_t)
{
    double cx = 0.5 * f->width - 0.5, cy = 0.5 * f->height - 0.5;
    int done = 0, tries = 0;
    while (done < n) {
        double chi = CR_TWO_PI * cr_test_rand(seed), db = pow(10.0, -5.0 + 4.0 * cr_test_rand(seed));
        double lo = 0.0, hi = 0.5 * f->width, e_r, e_g, e_ph, e_t;
        cr_ray ray;
        cr_pixel px;
        exact_hit x;
        assert_true(++tries < 20 * n);
        assert_true(point_b(f, cx + hi * cos(chi), cy + hi * sin(chi), &ray) > B_C + db);
        for (int it = 0; it < 200; it++) { /* b increases along the line */
            double mid = 0.5 * (lo + hi);
            if (point_b(f, cx + mid * cos(chi), cy + mid * sin(chi), &ray) < B_C + db)
                lo = mid;
            else
                hi = mid;
        }
        point_b(f, cx + hi * cos(chi), cy + hi * sin(chi), &ray);
        assert_true(ray.m[CR_M_DW] > 0.0); /* moving inward */
        x = exact_disc_hit(&ray.c, ray.m, f->disc.r_hit_in, f->disc.r_out);
        if (x.order < 0)
            continue; /* misses the disc: draw another */
        px = cr_trace_loop(f, &ray);
        if (px.outcome != CR_OUT_DISC || px.order != x.order)
            fail_msg("b_c + %.3g, chi %.6f: outcome %s order %d, exact: disc of order %d at "
                     "r = %.12g", db, chi, cr_outcome_name(px.outcome), px.order, x.order, x.r);
        e_r = fabs(px.hit_r - x.r) / x.r;
        e_g = fabs(px.redshift - x.g) / x.g;
        e_ph = fabs(remainder(px.hit_phi - x.phi, CR_TWO_PI));
        e_t = fabs(px.delay - x.delay) / fmax(fabs(x.delay), x.r);
        if (!(e_r <= b_r && e_g <= B_G && e_ph <= B_PHI && e_t <= b_t))
            print_message("b_c + %.3g, order %d: hit_r %.12g (exact %.12g, %.2g), g %.12g "
                          "(%.12g, %.2g), hit_phi %.12g (%.12g, %.2g), delay %.12g (%.12g, "
                          "%.2g)\n", db, x.order, px.hit_r, x.r, e_r, px.redshift, x.g, e_g,
                          px.hit_phi, x.phi, e_ph, px.delay, x.delay, e_t);
        wo->r = fmax(wo->r, e_r);
        wo->g = fmax(wo->g, e_g);
        wo->phi = fmax(wo->phi, e_ph);
        wo->delay = fmax(wo->delay, e_t);
        wo->steps += px.steps;
        wo->n++;
        done++;
    }
}

static void test_near_photon_sphere(void **state)
{
    static const char *const scenes[4] = {
        "metric: {m: 1, a: 0, q: 0}\n"
        "observer: {r: 30, theta: 85, phi: 0, hfov: 40}\n"
        "accretion: {model: keplerian, radius: [6, 20]}\n",
        "metric: {m: 1, a: 0, q: 0}\n"
        "observer: {r: 30, theta: 60, phi: 0, hfov: 40}\n"
        "accretion: {model: keplerian, radius: [6, 20]}\n",
        "metric: {m: 1, a: 0, q: 0}\n"
        "observer: {r: inf, theta: 85, phi: 0, hextent: 16}\n"
        "accretion: {model: keplerian, radius: [6, 20]}\n",
        "metric: {m: 1, a: 0, q: 0}\n"
        "observer: {r: inf, theta: 60, phi: 0, hextent: 16}\n"
        "accretion: {model: keplerian, radius: [6, 20]}\n",
    };
    uint64_t seed0 = 271828;
    long steps[2] = {0, 0};
    (void)state;
    aq_init();
    /* the same rays in a colour frame (science 0) and in a science frame */
    for (int science = 0; science < 2; science++) {
        double b_r = science ? B_HIT_R : B_IMG_HIT_R, b_t = science ? B_DELAY : B_IMG_DELAY;
        uint64_t seed = seed0;
        worst all = {0};
        for (int s = 0; s < 4; s++) {
            cr_frame f;
            worst wo = {0};
            frame_from(scenes[s], &f, 64, 64, science);
            assert_true(f.tolerance == cr_trace_defaults().tolerance);
            near_critical(&f, 24, &seed, &wo, b_r, b_t);
            print_message("%s frame, %s %d rays b_c + 10^(-5..-1): worst hit_r %.3g, g %.3g "
                          "(relative), hit_phi %.3g rad, delay %.3g (of max(|delay|, r)); %.1f "
                          "steps a ray (bounds %.0e, %.0e, %.0e, %.0e)\n",
                          science ? "science" : "colour", s < 2 ? "r_o = 30," : "infinity,", wo.n,
                          wo.r, wo.g, wo.phi, wo.delay, (double)wo.steps / wo.n, b_r, B_G, B_PHI,
                          b_t);
            all.r = fmax(all.r, wo.r);
            all.g = fmax(all.g, wo.g);
            all.phi = fmax(all.phi, wo.phi);
            all.delay = fmax(all.delay, wo.delay);
            steps[science] += wo.steps;
        }
        assert_true(all.r <= b_r);
        assert_true(all.g <= B_G);
        assert_true(all.phi <= B_PHI);
        assert_true(all.delay <= b_t);
    }
    /* the science frame's finer steps: more of them, but not twice as many */
    print_message("steps: colour %ld, science %ld (%.3f)\n", steps[0], steps[1],
                  (double)steps[1] / steps[0]);
    assert_true(steps[1] > steps[0] && steps[1] < 1.5 * steps[0]);
}

/* ---- 3. listing 7.1.1's pixel --------------------------------------------- */

static void test_listing_pixel(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_err err;
    cr_ray ray;
    cr_pixel px;
    exact_hit x;
    double e;
    (void)state;
    aq_init();
    memset(&s, 0, sizeof s);
    if (cr_scene_load(CR_SOURCE_DIR "/scenes/listing-7.1.1-schwarzschild-disc.yml", &s, &err))
        fail_msg("%s", err.msg);
    /* frame 8 of 18: theta = 85 deg (figure 7.1.2) */
    if (cr_scene_frame(&s, 8, 18, 64, 48, NULL, &f, NULL, &err))
        fail_msg("%s", err.msg);
    cr_scene_free(&s);
    f.science = 1;
    assert_true(cr_trace_point_ray(&f, 29.0, 16.0, &ray, &px));
    x = exact_disc_hit(&ray.c, ray.m, f.disc.r_hit_in, f.disc.r_out);
    px = cr_trace_pixel(&f, 29, 16);
    assert_int_equal(px.outcome, CR_OUT_DISC);
    e = fabs(px.hit_r - x.r) / x.r;
    assert_int_equal(px.order, x.order);
    print_message("listing 7.1.1, 64x48, pixel (29, 16): hit_r %.12g, exact %.12g (order %d), "
                  "rel. error %.3g (bound %.0e)\n", px.hit_r, x.r, x.order, e, B_PIXEL);
    assert_true(fabs(x.r - 13.673223546) < 1e-8);
    assert_true(e <= B_PIXEL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference),
        cmocka_unit_test(test_near_photon_sphere),
        cmocka_unit_test(test_listing_pixel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
