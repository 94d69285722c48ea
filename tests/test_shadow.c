/* The shadow of Schwarzschild and Reissner-Nordstrom holes seen by a static
 * observer at r_o: its angular radius psi (measured from the direction to the
 * hole) satisfies
 *   sin(psi) = (b_c / r_o) sqrt(1 - 2M/r_o + Q^2/r_o^2),
 * b_c = r_ph^2 / sqrt(r_ph^2 - 2M r_ph + Q^2), r_ph = (3M + sqrt(9M^2 - 8Q^2))/2,
 * with psi > 90 deg inside the photon sphere (r_o < r_ph). The edge found by
 * bisection on traced rays (horizon inside, sky outside) must match to
 * 1e-8 rad, for rays in the equatorial plane and for rays over the pole.
 *
 * Kerr, observer in the equatorial plane: the shadow's edges along the image's
 * horizontal axis are the equatorial circular photon orbits with impact
 * parameters b = -a + 6M cos(acos(-a/M)/3) (prograde) and
 * b = a + 6M cos(acos(a/M)/3) (retrograde) (Bardeen 1973). The backward ray
 * of a photon with impact parameter b (angular momentum b E) leaves a static
 * observer with the local direction component n_phi = (b g_tt + g_tphi)/sqrt(Delta)
 * along e_phi, so the edge rays are at sin(psi) = |n_phi|. The prograde (short, flattened) edge must be
 * on the LEFT of the image: a > 0 turns counter-clockwise about +z and its
 * left side moves towards the observer (ERRATA item 1). Tolerance 1e-7 rad.
 *
 * Kerr and Kerr-Newman at any inclination, observer at r_o = 1e6 and at
 * infinity: the whole shadow edge lies within 0.5 px (of a 512 px, 16 M
 * image) of Bardeen's curve of the spherical photon orbits (see "The
 * Bardeen curve" below).
 *
 * A ZAMO at r_o = 8 M (observer.motion: zamo): the same critical
 * photons projected onto its screen (Grenzebach, Perlick & Lammerzahl 2014)
 * match the traced edge within 0.5 px (test_shadow_zamo_finite). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

static double analytic_psi(double m, double q, double ro)
{
    double rph = 0.5 * (3.0 * m + sqrt(9.0 * m * m - 8.0 * q * q));
    double bc = rph * rph / sqrt(rph * rph - 2.0 * m * rph + q * q);
    double s = bc / ro * sqrt(1.0 - 2.0 * m / ro + q * q / (ro * ro));
    double psi = asin(fmin(1.0, s));
    return ro < rph ? CR_PI - psi : psi;
}

/* Outcome of the ray at angle psi from the inward direction, turned towards
 * +phi (polar = 0) or towards -theta, over the pole (polar = 1). */
static int trace_at(const cr_frame *f, double psi, int polar)
{
    double n[3], y[CR_NY];
    cr_geo g;
    cr_pixel px;
    n[0] = -cos(psi);
    n[1] = polar ? -sin(psi) : 0.0;
    n[2] = polar ? 0.0 : sin(psi);
    cr_camera_ray(f, n, &g, y);
    px = cr_trace_ray(f, &g, y);
    return px.outcome;
}

static void check_shadow(double m, double q, double ro, int polar, double *worst)
{
    cr_frame f;
    double lo, hi, psi = analytic_psi(m, q, ro);
    int it;
    cr_test_empty_frame(&f, m, 0.0, q, ro, 0.5 * CR_PI);
    lo = psi - 0.05;
    hi = fmin(psi + 0.05, CR_PI - 1e-9);
    assert_int_equal(trace_at(&f, lo, polar), CR_OUT_HORIZON);
    assert_int_equal(trace_at(&f, hi, polar), CR_OUT_SKY);
    for (it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        int o = trace_at(&f, mid, polar);
        assert_true(o == CR_OUT_HORIZON || o == CR_OUT_SKY || o == CR_OUT_LIMIT);
        if (o == CR_OUT_LIMIT)
            break; /* orbiting: as close to the edge as the integration resolves */
        if (o == CR_OUT_HORIZON)
            lo = mid;
        else
            hi = mid;
    }
    print_message("M=%g Q=%-4g r_o=%-5g %s: psi analytic %.9f, traced %.9f, diff %.2e\n", m, q,
                  ro, polar ? "polar " : "equat.", psi, 0.5 * (lo + hi), 0.5 * (lo + hi) - psi);
    *worst = fmax(*worst, fabs(0.5 * (lo + hi) - psi));
    if (fabs(0.5 * (lo + hi) - psi) > 1e-8)
        fail_msg("shadow edge off by %.3g rad", 0.5 * (lo + hi) - psi);
}

/* Critical angle psi between horizon (smaller) and sky (larger) for rays
 * turned by psi from the inward direction towards +phi (side = +1, image
 * right) or -phi (side = -1, image left), observer in the equatorial plane. */
static double kerr_edge(const cr_frame *f, int side)
{
    double lo = 0.0, hi = 0.5 * CR_PI;
    int it;
    for (it = 0; it < 48; it++) {
        double mid = 0.5 * (lo + hi), n[3], y[CR_NY];
        cr_geo g;
        cr_pixel px;
        n[0] = -cos(mid);
        n[1] = 0.0;
        n[2] = side * sin(mid);
        cr_camera_ray(f, n, &g, y);
        px = cr_trace_ray(f, &g, y);
        if (px.outcome == CR_OUT_LIMIT)
            break;
        if (px.outcome == CR_OUT_HORIZON)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

static void test_shadow_kerr_equatorial_edges(void **state)
{
    const double spins[] = {0.3, 0.7, 0.9, 0.998};
    const double ro = 30.0;
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        double a = spins[i];
        double b_pro = -a + 6.0 * cos(acos(-a) / 3.0), b_retro = a + 6.0 * cos(acos(a) / 3.0);
        cr_frame f;
        cr_metric_point p;
        double n_pro, n_retro, left, right;
        cr_test_empty_frame(&f, 1.0, a, 0.0, ro, 0.5 * CR_PI);
        cr_metric_eval(&f.metric, ro, 0.5 * CR_PI, &p);
        /* prograde photon: angular momentum +b; retrograde: -b */
        n_pro = (b_pro * p.g_tt + p.g_tph) / sqrt(p.delta);
        n_retro = (-b_retro * p.g_tt + p.g_tph) / sqrt(p.delta);
        left = kerr_edge(&f, -1);
        right = kerr_edge(&f, +1);
        print_message("a=%-5g left edge %.9f (prograde, analytic %.9f), right edge %.9f "
                      "(retrograde, analytic %.9f)\n",
                      a, left, asin(fabs(n_pro)), right, asin(fabs(n_retro)));
        /* the prograde photon arrives moving towards +phi: it is seen on the left */
        assert_true(n_pro < 0.0 && n_retro > 0.0);
        assert_true(left < right);
        assert_true(fabs(left - asin(fabs(n_pro))) < 1e-7);
        assert_true(fabs(right - asin(fabs(n_retro))) < 1e-7);
    }
}

static void test_shadow_schwarzschild(void **state)
{
    const double ros[] = {30.0, 10.0, 4.0, 2.9, 2.2};
    double worst = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 5; i++) {
        check_shadow(1.0, 0.0, ros[i], 0, &worst);
        check_shadow(1.0, 0.0, ros[i], 1, &worst);
    }
}

static void test_shadow_reissner_nordstrom(void **state)
{
    const double qs[] = {0.5, 0.9, 1.0};
    const double ros[] = {25.0, 6.0, 2.4};
    double worst = 0.0;
    int i, k;
    (void)state;
    for (k = 0; k < 3; k++)
        for (i = 0; i < 3; i++)
            check_shadow(1.0, qs[k], ros[i], i == 1, &worst);
}

/* ---- The Bardeen curve (Bardeen 1973) at r_o = 1e6 and at infinity ------
 *
 * Spherical photon orbits of Kerr-Newman, textbook convention (future-
 * directed photon, E = 1, lambda = L/E, eta the Carter constant):
 *   R(r) = (r^2 + a^2 - a lambda)^2 - Delta [eta + (lambda - a)^2],
 *   Delta = r^2 - 2Mr + a^2 + Q^2.
 * R = R' = 0 at r = r_p gives, with A = r^2 + a^2 - a lambda and
 * C = eta + (lambda - a)^2: A^2 = Delta C and 4 r A = Delta' C, so
 *   A = 4 r Delta / Delta',  lambda = (r^2 + a^2 - A) / a,
 *   eta = 16 r^2 Delta / Delta'^2 - (lambda - a)^2   (a != 0).
 * Seen from infinity at inclination theta_o the orbit r_p is the image point
 *   alpha = -lambda / sin(theta_o),
 *   beta  = +-sqrt(eta + a^2 cos^2(theta_o) - lambda^2 cot^2(theta_o)),
 * over the r_p where beta^2 >= 0. curray's backward ray has L = -lambda
 * (geodesic.h), and cr_camera_ray_at_infinity gives it L = alpha sin(theta_o):
 * the same alpha. Image right = +alpha (+phi), up = +beta (+z): the
 * prograde orbits (lambda > 0 for a > 0, smaller r_p) make the flattened
 * edge on the LEFT (checked below).
 *
 * Method: from the shadow's centre c = ((alpha_min + alpha_max)/2, 0) along
 * N_DIR directions psi in the image plane, the edge of the traced shadow is
 * found by bisection on the outcome (horizon inside, sky outside) to 1e-9 M,
 * and compared with the curve's distance from c along psi (the curve point
 * with that polar angle about c, by bisection on r_p; the curve is
 * star-shaped about c). Image: 16 M x 16 M at BP_PX x BP_PX pixels, so one
 * pixel is 1/32 M; the traced edge must be within 0.5 px of the curve.
 *
 * Observer at infinity: observer.r = INFINITY, hextent = vextent = 16 M, each
 * point traced by cr_camera_ray_at_infinity + cr_trace_loop.
 * Static observer at r_o = 1e6: hfov = vfov = 2 atan(8 M / r_o), and the
 * image point (alpha, beta) is looked at through the screen point
 * (sx, sy) = (alpha, beta) / r_o, i.e. the fractional pixel of
 * cr_camera_pixel_dir, traced by cr_camera_ray + cr_trace_ray. This
 * small-angle mapping alpha = r_o tan(angle) neglects terms of relative size
 * M/r_o = 1e-6 (about 2e-4 px here). */

#define BP_PX 512
#define BP_EXTENT 16.0
#define BP_N_DIR 48
#define BP_RO_FAR 1e6
#define BP_RO_ZAMO 8.0

typedef struct bardeen {
    double m, a, q, th_o;
    double ro;          /* 0: the image plane at infinity; > 0: the ZAMO at r_o */
    double r1, r2;      /* the orbit radii at the curve's ends (beta = 0) */
    double ac;          /* centre alpha */
    double ang1, ang2;  /* polar angle about the centre at r1, r2 (0 or pi) */
} bardeen;

/* alpha and beta^2 of the orbit at radius r. */
static void bardeen_point(const bardeen *b, double r, double *alpha, double *beta2)
{
    double a = b->a, m = b->m;
    double delta = r * r - 2.0 * m * r + a * a + b->q * b->q, ddelta = 2.0 * r - 2.0 * m;
    double A = 4.0 * r * delta / ddelta;
    double lam = (r * r + a * a - A) / a;
    double eta = 16.0 * r * r * delta / (ddelta * ddelta) - (lam - a) * (lam - a);
    double s = sin(b->th_o), c = cos(b->th_o);
    double theta = eta + a * a * c * c - lam * lam * c * c / (s * s); /* Th(theta_o) */
    *alpha = -lam / s;
    *beta2 = theta;
    if (b->ro > 0.0) {
        /* the ZAMO's screen (Grenzebach, Perlick & Lammerzahl 2014): the
         * outgoing photon p = (-1, sqrt(R)/Delta, +-sqrt(Th), lambda) seen in
         * the ZAMO frame e_0 = (d_t + omega d_phi)/alpha, e_i = d_i/sqrt(g_ii),
         * at the screen point (n_ph, -n_th)/(-n_r) of n_i = (p.e_i)/(p.e_0);
         * times r_o, to share the image-plane units above */
        double ro = b->ro, so = s * s, sig = ro * ro + a * a * c * c;
        double del = ro * ro - 2.0 * m * ro + a * a + b->q * b->q;
        double big = (ro * ro + a * a) * (ro * ro + a * a) - del * a * a * so;
        double P = ro * ro + a * a - a * lam;
        double R = P * P - del * (eta + (lam - a) * (lam - a));
        double k = ro * sqrt(sig / del) * del / sqrt(R); /* r_o sqrt(g_rr) Delta / sqrt(R) */
        *alpha = -lam * k / sqrt(big * so / sig);
        *beta2 = theta * k * k / sig;
    }
}

static double bardeen_beta2(const bardeen *b, double r)
{
    double al, b2;
    bardeen_point(b, r, &al, &b2);
    return b2;
}

/* Polar angle in [0, pi] about the centre of the upper point of orbit r. */
static double bardeen_angle(const bardeen *b, double r)
{
    double al, b2;
    bardeen_point(b, r, &al, &b2);
    return atan2(sqrt(fmax(b2, 0.0)), al - b->ac);
}

/* The root of beta^2 between lo (sign slo) and hi. */
static double bardeen_root(const bardeen *b, double lo, double hi)
{
    int slo = bardeen_beta2(b, lo) >= 0.0, it;
    for (it = 0; it < 200 && hi - lo > 1e-15; it++) {
        double mid = 0.5 * (lo + hi);
        if ((bardeen_beta2(b, mid) >= 0.0) == slo)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

static void bardeen_init(bardeen *b, double m, double a, double q, double th_o, double ro)
{
    double rp = m + sqrt(m * m - a * a - q * q), dr = fmin(1e-3 * m, 0.05 * fabs(a));
    double r, al1, al2, tmp;
    int found = 0;
    b->m = m;
    b->a = a;
    b->q = q;
    b->th_o = th_o;
    b->ro = ro;
    /* photon orbits lie in (r+, 4M]: find the interval with beta^2 >= 0 (its
     * width shrinks with a, so does the scan's step) */
    for (r = rp + dr; r < 4.0 * m + dr; r += dr) {
        int in = bardeen_beta2(b, r) >= 0.0, was = bardeen_beta2(b, r - dr) >= 0.0;
        if (in && !was) {
            b->r1 = bardeen_root(b, r - dr, r);
            found |= 1;
        } else if (!in && was && r - dr > rp + dr) {
            b->r2 = bardeen_root(b, r - dr, r);
            found |= 2;
        }
    }
    assert_int_equal(found, 3);
    bardeen_point(b, b->r1, &al1, &tmp);
    bardeen_point(b, b->r2, &al2, &tmp);
    b->ac = 0.5 * (al1 + al2);
    b->ang1 = al1 < al2 ? CR_PI : 0.0;
    b->ang2 = CR_PI - b->ang1;
}

/* Distance from the centre to the curve along the image direction psi. */
static double bardeen_radius(const bardeen *b, double psi)
{
    double ang = fabs(atan2(sin(psi), cos(psi))); /* symmetric about beta = 0 */
    double lo = b->r1, hi = b->r2, al, b2;
    int it;
    for (it = 0; it < 200 && hi - lo > 1e-15; it++) {
        double mid = 0.5 * (lo + hi);
        /* the angle runs monotonically from ang1 at r1 to ang2 at r2 */
        if ((bardeen_angle(b, mid) - ang) * (b->ang1 - ang) > 0.0)
            lo = mid;
        else
            hi = mid;
    }
    bardeen_point(b, 0.5 * (lo + hi), &al, &b2);
    return hypot(al - b->ac, sqrt(fmax(b2, 0.0)));
}

/* Outcome of the ray seen at image point (alpha, beta) in M. */
static int bardeen_trace(const cr_frame *f, double alpha, double beta)
{
    cr_pixel px;
    if (f->obs_at_inf) {
        cr_ray ray;
        cr_camera_ray_at_infinity(f, alpha, beta, &ray.c, ray.m);
        cr_ray_mino_start(f, &ray);
        px = cr_trace_loop(f, &ray);
    } else {
        /* the fractional pixel whose screen point is (alpha, beta) / r_o */
        double i = (alpha / f->observer.r / f->tan_half_h + 1.0) * 0.5 * f->width - 0.5;
        double j = (1.0 - beta / f->observer.r / f->tan_half_v) * 0.5 * f->height - 0.5;
        double n[3], y[CR_NY];
        cr_geo g;
        cr_camera_pixel_dir(f, i, j, n);
        cr_camera_ray(f, n, &g, y);
        px = cr_trace_ray(f, &g, y);
    }
    return px.outcome;
}

/* Trace the shadow's edge along BP_N_DIR directions and return the worst
 * offset from the curve in pixels; *left_flat reports that the prograde
 * orbits (r1) form the left end of the curve and that the traced shadow's
 * left edge is nearer the hole's direction (alpha = 0) than its right one. */
/* where: 0 a static observer at BP_RO_FAR, 1 the observer at infinity, 2 a
 * ZAMO at BP_RO_ZAMO (the curve projected onto its screen). */
static double bardeen_check(double a, double q, double th_deg, int where, int *left_flat)
{
    const double px = BP_EXTENT / BP_PX;
    cr_frame f;
    bardeen b;
    double worst = 0.0, sum = 0.0, r_left = 0.0, r_right = 0.0;
    int k;
    const double ro = where == 1 ? INFINITY : where == 2 ? BP_RO_ZAMO : BP_RO_FAR;
    bardeen_init(&b, 1.0, a, q, th_deg * CR_PI / 180.0, where == 2 ? ro : 0.0);
    cr_test_empty_frame(&f, 1.0, a, q, ro, b.th_o);
    f.width = f.height = BP_PX;
    if (where == 1) {
        f.observer.hextent = f.observer.vextent = BP_EXTENT;
    } else {
        f.observer.hfov = f.observer.vfov = 2.0 * atan(0.5 * BP_EXTENT / ro);
        if (where == 2)
            f.observer.motion = CR_MOTION_ZAMO;
    }
    cr_frame_prepare(&f);
    for (k = 0; k < BP_N_DIR; k++) {
        double psi = CR_TWO_PI * k / BP_N_DIR, cp = cos(psi), sp = sin(psi);
        double rc = bardeen_radius(&b, psi), lo = 0.8 * rc, hi = 1.2 * rc, edge, d;
        int it;
        assert_int_equal(bardeen_trace(&f, b.ac + lo * cp, lo * sp), CR_OUT_HORIZON);
        assert_int_equal(bardeen_trace(&f, b.ac + hi * cp, hi * sp), CR_OUT_SKY);
        for (it = 0; it < 40 && hi - lo > 1e-9; it++) {
            double mid = 0.5 * (lo + hi);
            int o = bardeen_trace(&f, b.ac + mid * cp, mid * sp);
            assert_true(o == CR_OUT_HORIZON || o == CR_OUT_SKY || o == CR_OUT_LIMIT);
            if (o == CR_OUT_LIMIT)
                break; /* orbiting: as close to the edge as the integration resolves */
            if (o == CR_OUT_HORIZON)
                lo = mid;
            else
                hi = mid;
        }
        edge = 0.5 * (lo + hi);
        d = (edge - rc) / px;
        sum += fabs(d);
        if (fabs(d) > fabs(worst))
            worst = d;
        if (k == 0)
            r_right = edge;
        if (2 * k == BP_N_DIR)
            r_left = edge;
    }
    /* the traced edges on the image's horizontal axis: alpha = ac -+ r */
    *left_flat = b.ang1 == CR_PI && fabs(b.ac - r_left) < fabs(b.ac + r_right);
    print_message("a=%-5g Q=%-4g theta_o=%2g deg %s: shadow centre alpha %+.4f M, edges at "
                  "alpha %+.4f M and %+.4f M; worst offset %+.2e px, mean |offset| %.2e px (%d "
                  "directions, 1 px = %g M)\n",
                  a, q, th_deg, where == 1 ? "r_o=inf" : where == 2 ? "ZAMO r_o=8" : "r_o=1e6", b.ac, b.ac - r_left,
                  b.ac + r_right, worst,
                  sum / BP_N_DIR, BP_N_DIR, px);
    return worst;
}

static void test_shadow_bardeen_curve(void **state)
{
    /* a = 0.9; a near-extremal spin; a Kerr-Newman hole */
    const double spins[] = {0.9, 0.998, 0.6}, charges[] = {0.0, 0.0, 0.7};
    const double incl[] = {85.0, 60.0};
    double worst = 0.0;
    int i, k, inf;
    (void)state;
    /* the curve itself: edge-on, its ends are the equatorial circular orbits
     * (alpha = -b_pro on the left, +b_retro on the right, as in
     * test_shadow_kerr_equatorial_edges); for a -> 0 it is the circle of
     * radius b_c (3 sqrt(3) M; for Q = 0.7 the formula of analytic_psi), to
     * O(a^2) */
    {
        bardeen b;
        double al1, al2, tmp, a = 0.9;
        bardeen_init(&b, 1.0, a, 0.0, 0.5 * CR_PI, 0.0);
        bardeen_point(&b, b.r1, &al1, &tmp);
        bardeen_point(&b, b.r2, &al2, &tmp);
        assert_true(fabs(al1 - (a - 6.0 * cos(acos(-a) / 3.0))) < 1e-9);
        assert_true(fabs(al2 - (a + 6.0 * cos(acos(a) / 3.0))) < 1e-9);
        for (k = 0; k < 2; k++) {
            double q = k ? 0.7 : 0.0;
            double rph = 0.5 * (3.0 + sqrt(9.0 - 8.0 * q * q));
            double bc = rph * rph / sqrt(rph * rph - 2.0 * rph + q * q);
            bardeen_init(&b, 1.0, 1e-3, q, 60.0 * CR_PI / 180.0, 0.0);
            for (i = 0; i < 8; i++)
                assert_true(fabs(bardeen_radius(&b, 0.4 * i) - bc) < 1e-5);
        }
    }
    for (i = 0; i < 3; i++)
        for (k = 0; k < 2; k++)
            for (inf = 0; inf < 2; inf++) {
                int left_flat;
                double d = bardeen_check(spins[i], charges[i], incl[k], inf, &left_flat);
                assert_true(left_flat);
                if (fabs(d) > fabs(worst))
                    worst = d;
            }
    print_message("worst offset from the Bardeen curve: %+.2e px (allowed 0.5 px)\n", worst);
    assert_true(fabs(worst) < 0.5);
}

/* The shadow seen by a ZAMO at r_o = 8 M: the critical photons'
 * (lambda, eta) from R = R' = 0 projected onto the ZAMO's screen
 * (bardeen_point with ro > 0) against the traced edge of the boosted-ZAMO
 * camera, within 0.5 px of a 512 px image 2 atan(1) wide. The projection is
 * first checked on its own: for a -> 0 it is the circle of angular radius
 * psi of analytic_psi (to O(a^2)). */
static void test_shadow_zamo_finite(void **state)
{
    const double spins[] = {0.9, 0.998, 0.6}, charges[] = {0.0, 0.0, 0.7};
    const double incl[] = {85.0, 60.0};
    double worst = 0.0;
    int i, k;
    (void)state;
    for (k = 0; k < 2; k++) {
        bardeen b;
        double q = k ? 0.7 : 0.0, psi = analytic_psi(1.0, q, BP_RO_ZAMO);
        bardeen_init(&b, 1.0, 1e-3, q, 60.0 * CR_PI / 180.0, BP_RO_ZAMO);
        for (i = 0; i < 8; i++)
            assert_true(fabs(bardeen_radius(&b, 0.4 * i) - BP_RO_ZAMO * tan(psi)) < 1e-4);
    }
    for (i = 0; i < 3; i++)
        for (k = 0; k < 2; k++) {
            int left_flat;
            double d = bardeen_check(spins[i], charges[i], incl[k], 2, &left_flat);
            assert_true(left_flat);
            if (fabs(d) > fabs(worst))
                worst = d;
        }
    print_message("worst offset of the ZAMO's shadow from the projected critical curve: %+.2e "
                  "px (allowed 0.5 px)\n",
                  worst);
    assert_true(fabs(worst) < 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shadow_schwarzschild),
        cmocka_unit_test(test_shadow_reissner_nordstrom),
        cmocka_unit_test(test_shadow_kerr_equatorial_edges),
        cmocka_unit_test(test_shadow_bardeen_curve),
        cmocka_unit_test(test_shadow_zamo_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
