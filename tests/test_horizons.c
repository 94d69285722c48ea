/* Light and observers inside a Kerr-Newman hole (ray.h's ingoing chart,
 * observer.h's free-fall frame) against independent results.
 *
 * 1. The ingoing chart's rates against the BL equations: at 3000 random null
 *    states outside the horizon (a, Q random with a^2 + Q^2 < 1, r from
 *    r+ (1 + 1e-3) to 100 M, directions random in the ZAMO frame), the
 *    ingoing azimuth rate of cr_mino_rhs equals the BL rate plus
 *    (a/Delta) dr/dtau, and cr_mino_ingoing_dv equals Sigma u^t +
 *    ((r^2 + a^2)/Delta) Sigma u^r with u^t from geodesic.h, both to 1e-10
 *    relative to the magnitude of the terms.
 * 2. The null condition along rays that cross r+: from infalling observers
 *    between the horizons of four holes (Schwarzschild, Reissner-Nordstrom
 *    Q = 0.8, Kerr a = 0.9, Kerr-Newman a = 0.6, Q = 0.5) at tol 1e-12, the
 *    tangent of every state at fractions 1/4 .. 1 of every step, written in
 *    ingoing Kerr coordinates (v, r, theta, phi~) with the ingoing metric
 *    written out here, is null to 1e-10 (g(u,u) over the sum of the
 *    magnitudes of its terms) in the ingoing chart, and so is the BL
 *    tangent in the BL metric for the first 20 steps after the change to
 *    BL; each hole has rays that cross.
 * 3. Schwarzschild interior: a radial free-faller from rest at infinity at
 *    r = 1.5, 1, 0.5 M, a 360 deg fisheye 721 px wide (0.5 deg a pixel). In
 *    its frame a photon arriving from angle psi to the outward direction has
 *    E = 1 + cos(psi) sqrt(2M/r) and impact parameter b = r sin(psi) / E. It
 *    came from our exterior iff E > 0 (P(r+) = E r+^2), and from our sky iff
 *    also b < 3 sqrt(3) M; E < 0 is the other side. The two edges, found by
 *    bisection on traced rays along the image's centre row, lie within
 *    1e-3 px of those closed-form angles (found: below 1e-7 px).
 * 4. Reissner-Nordstrom Q = 0.8 M (r- = 0.4, r+ = 1.6): the same at r = 1.2
 *    and 0.6 M (E = 1 + cos(psi) sqrt(2M/r - Q^2/r^2), b_c = r_ph^2 /
 *    sqrt(r_ph^2 - 2 M r_ph + Q^2)); and one equatorial ray's path from
 *    r = 1.0 M out through r+ to 20 M against the exact radial integral
 *    phi(r) = int L dr / sqrt(E^2 r^4 - Delta L^2) (Gauss-Legendre), to
 *    1e-8 rad at every path point.
 * 5. Continuity across r+: an infalling observer of a Kerr-Newman hole
 *    (a = 0.6, Q = 0.3) at r+ (1 + 1e-6) (boosted ZAMO frame, outside) and at
 *    r+ (1 - 1e-6) (free-fall frame, inside), a disc from 3 to 15 M: the
 *    same 41 x 41 fisheye image; >= 99 % of the pixels end the same way
 *    (the boundary V = 0 counting as one: horizon outside, other side
 *    inside), and where both hit the disc the hit radius differs by less
 *    than 1e-3 relative and the azimuth by less than 1e-3 rad.
 * 6. The two frames agree: the free-fall tetrad at r = 3 M equals the
 *    boosted-ZAMO infall tetrad of observer.h to 1e-12, and is orthonormal
 *    inside (r between the horizons) to 1e-12.
 * 7. The shift of sky light seen from inside (Schwarzschild, r = 1 and
 *    r+ (1 - 1e-6)): 1/E with E = 1 + cos(psi) sqrt(2M/r), to 1e-9; the plunge
 *    animation [infall, r0, r1] against r(tau) in closed form (Schwarzschild)
 *    and the BL phi of a Kerr plunge against a quadrature of u^phi/|u^r|.
 * 8. Refused: static, zamo and orbit inside r+, an observer on r+ or r-,
 *    inside r- below the bounce Q^2/2M, static inside r-, below 1e-4 M,
 *    inside an extremal hole, |v| >= 1 inside, rk4 inside; each message
 *    names the key.
 * 9. Inside the inner horizon (each test's comment has its figures): the
 *    null condition along rays crossing r- and r+; an RN ray's path through
 *    r- (straight out, and turning inside r-) against the exact radial
 *    integral; which rays reach r = 0 against R(r); an RN plunge through r+
 *    and r- against tau(r) in closed form; continuity across r-.
 * 10. The other exterior's sky (skymap.other_side): pixels unchanged but the
 *    other side's, its sky where b < 3 sqrt(3) with g = 1/|E|, one path
 *    against the radial integral, and ray.h's mirror against the mirror
 *    image of a Kerr-Newman start made here.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "input/scene.h"
#include "testutil.h"

#define DEG (CR_PI / 180.0)

/* A prepared frame: infalling observer at (r, th, phi = 0) of a hole (1, a, q),
 * fisheye of full angle 360 deg, w x h pixels, tolerance tol; the horizon stop
 * halved within 2 epsilon of the observer, as the scene's validation does. */
static void fall_frame(cr_frame *f, double a, double q, double r, double th, int w, int h,
                       double tol)
{
    double gap;
    cr_test_empty_frame(f, 1.0, a, q, 30.0, th);
    f->observer.r = r;
    f->observer.motion = CR_MOTION_INFALL;
    f->observer.projection = CR_PROJ_FISHEYE;
    f->observer.hfov = CR_TWO_PI;
    f->observer.vfov = CR_TWO_PI * h / w;
    f->width = w;
    f->height = h;
    f->tolerance = tol;
    f->other_side_color.r = 96;
    f->other_side_color.b = 128;
    gap = fabs(r - cr_metric_r_plus(&f->metric));
    if (gap < 2.0 * f->horizon_epsilon)
        f->horizon_epsilon = 0.5 * gap;
    cr_frame_prepare(f);
}

/* ---- 1. the ingoing rates against BL ------------------------------------ */

static void test_ingoing_rhs_vs_bl(void **state)
{
    uint64_t seed = 0x1234567ULL;
    double worst_p = 0.0, worst_v = 0.0;
    int i;
    (void)state;
    for (i = 0; i < 3000; i++) {
        cr_metric mt;
        cr_metric_point p;
        cr_geo g;
        cr_mino c;
        double e[4][4], u[4], yb[CR_NY], y[CR_MN], d0[CR_MN], d1[CR_MN], n[3], len, rp, r, th;
        double a = 2.0 * cr_test_rand(&seed) - 1.0, q = 0.0, drt, sig, scale, want, k;
        int j;
        if (i % 2)
            q = (2.0 * cr_test_rand(&seed) - 1.0) * sqrt(1.0 - a * a) * 0.99;
        mt.m = 1.0;
        mt.a = a;
        mt.q = q;
        rp = cr_metric_r_plus(&mt);
        r = rp * (1.0 + 1e-3 + 100.0 * cr_test_rand(&seed) * cr_test_rand(&seed));
        th = 0.05 + (CR_PI - 0.1) * cr_test_rand(&seed);
        cr_zamo_tetrad(&mt, r, th, 0, e, NULL, NULL, NULL);
        do {
            for (j = 0; j < 3; j++)
                n[j] = 2.0 * cr_test_rand(&seed) - 1.0;
            len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        } while (len > 1.0 || len < 0.1);
        for (j = 0; j < 4; j++)
            u[j] = -e[0][j] + (n[0] * e[1][j] + n[1] * e[2][j] + n[2] * e[3][j]) / len;
        cr_metric_eval(&mt, r, th, &p);
        g.mt = mt;
        cr_geo_constants(&p, u, &g.E, &g.L);
        yb[CR_Y_T] = 0.0;
        yb[CR_Y_R] = r;
        yb[CR_Y_TH] = th;
        yb[CR_Y_PH] = 0.3;
        yb[CR_Y_UR] = u[1];
        yb[CR_Y_UTH] = u[2];
        cr_mino_from_bl(&g, yb, 1.0 / rp, &c, y);
        cr_mino_rhs(&c, y, d0);
        c.chart = CR_CHART_INGOING;
        cr_mino_rhs(&c, y, d1);
        for (j = 0; j < CR_MN; j++)
            if (j != CR_M_PR)
                assert_true(d0[j] == d1[j]);
        /* independent: dr/dtau = Sigma u^r, the BL u^t of geodesic.h */
        sig = p.sigma;
        drt = sig * u[1];
        cr_geo_velocity(&g, yb, &p, u);
        k = a / p.delta * drt;
        want = d0[CR_M_PR] + k;
        scale = fabs(d0[CR_M_PR]) + fabs(k) + fabs(a * g.E);
        worst_p = fmax(worst_p, fabs(d1[CR_M_PR] - want) / scale);
        want = sig * u[0] + (r * r + a * a) / p.delta * drt;
        scale = fabs(sig * u[0]) + fabs((r * r + a * a) / p.delta * drt);
        worst_v = fmax(worst_v, fabs(cr_mino_ingoing_dv(&c, y) - want) / scale);
    }
    printf("ingoing rates vs BL: worst relative error phi~ %.2e, v %.2e\n", worst_p, worst_v);
    assert_true(worst_p < 1e-10);
    assert_true(worst_v < 1e-10);
}

/* ---- 2. the null condition across r+ ------------------------------------ */

/* g(u,u) / sum |terms| of the tangent (dv, dr, dth, dph~) at (r, th) in the
 * ingoing Kerr-Newman metric
 *   ds^2 = -(1 - W/Sigma) dv^2 + 2 dv dr - 2 a s^2 dr dph~ - 2 a s^2 (W/Sigma) dv dph~
 *          + Sigma dth^2 + (A s^2/Sigma) dph~^2,   W = 2Mr - Q^2. */
static double ingoing_null(double a, double q, double r, double th, const double t[4])
{
    double s2 = sin(th) * sin(th), c2 = cos(th) * cos(th);
    double sig = r * r + a * a * c2, W = 2.0 * r - q * q, del = r * r + a * a - W;
    double A = (r * r + a * a) * (r * r + a * a) - del * a * a * s2;
    double terms[6];
    double sum = 0.0, mag = 0.0;
    int i;
    terms[0] = -(1.0 - W / sig) * t[0] * t[0];
    terms[1] = 2.0 * t[0] * t[1];
    terms[2] = -2.0 * a * s2 * t[1] * t[3];
    terms[3] = -2.0 * a * s2 * W / sig * t[0] * t[3];
    terms[4] = sig * t[2] * t[2];
    terms[5] = A * s2 / sig * t[3] * t[3];
    for (i = 0; i < 6; i++) {
        sum += terms[i];
        mag += fabs(terms[i]);
    }
    return sum / mag;
}

/* The null norm of Mino state y of ray: in the ingoing chart the tangent
 * d/dtau (v, r, th, ph~) in the ingoing metric above; in BL (after the ray
 * left the interior) the BL tangent in the BL metric (cr_geo_null_norm: the
 * ingoing form is ill-conditioned there for outgoing rays, whose dv is the
 * small difference of two large BL terms). */
static double state_null(const cr_frame *f, const cr_ray *ray, const double *y)
{
    double d[CR_MN], t[4], w = y[CR_M_W], nx = y[CR_M_NX], ny = y[CR_M_NY], nz = y[CR_M_NZ];
    double rho2 = nx * nx + ny * ny, n2 = rho2 + nz * nz, r, th;
    cr_mino_rhs(&ray->c, y, d);
    r = 1.0 / w;
    th = atan2(sqrt(rho2), nz);
    t[1] = -d[CR_M_W] / (w * w);
    /* dth/dtau of the unit vector n/|n| */
    t[2] = ((nz * (nx * d[CR_M_NX] + ny * d[CR_M_NY]) - rho2 * d[CR_M_NZ]) / sqrt(rho2)) / n2;
    t[3] = (nx * d[CR_M_NY] - ny * d[CR_M_NX]) / rho2 + d[CR_M_PR];
    if (ray->c.chart == CR_CHART_INGOING) {
        t[0] = cr_mino_ingoing_dv(&ray->c, y);
        return ingoing_null(f->metric.a, f->metric.q, r, th, t);
    }
    {
        cr_metric_point p;
        cr_geo g;
        double yb[CR_NY], u[4];
        cr_metric_eval(&f->metric, r, th, &p);
        g.mt = f->metric;
        g.E = ray->c.E;
        g.L = ray->c.L;
        yb[CR_Y_R] = r;
        yb[CR_Y_TH] = th;
        yb[CR_Y_UR] = t[1] / p.sigma;
        yb[CR_Y_UTH] = t[2] / p.sigma;
        cr_geo_velocity(&g, yb, &p, u);
        return cr_geo_null_norm(&p, u);
    }
}

static void test_null_across_horizon(void **state)
{
    const double holes[4][3] = {{0.0, 0.0, 1.0}, {0.0, 0.8, 1.2}, {0.9, 0.0, 1.2},
                                {0.6, 0.5, 1.1}};
    int hi;
    (void)state;
    for (hi = 0; hi < 4; hi++) {
        cr_frame f;
        double worst = 0.0;
        int crossed = 0, px;
        fall_frame(&f, holes[hi][0], holes[hi][1], holes[hi][2], 70.0 * DEG, 9, 9, 1e-12);
        assert_true(f.obs_inside);
        for (px = 0; px < 81; px++) {
            cr_ray ray;
            double n[3], yb[CR_NY], turns = 0.0;
            cr_geo g;
            int steps, after = -1;
            if (!cr_camera_in_image(&f, px % 9, px / 9))
                continue;
            cr_camera_pixel_dir(&f, px % 9, px / 9, n);
            cr_camera_ray(&f, n, &g, yb);
            cr_ray_from_bl(&f, &g, yb, &ray);
            for (steps = 0; steps < 5000 && after < 20; steps++) {
                int k;
                if (cr_ray_at_horizon(&f, &ray) || cr_ray_other_side(&ray) ||
                    cr_ray_escaping(&f, &ray))
                    break;
                cr_ray_begin(&ray);
                assert_int_equal(cr_ray_advance(&f, &ray), 0);
                for (k = 1; k <= 4; k++) {
                    double ys[CR_MN];
                    cr_ray_state_at(&ray, 0.25 * k, ys);
                    worst = fmax(worst, fabs(state_null(&f, &ray, ys)));
                }
                cr_ray_commit(&f, &ray, &turns);
                if (ray.crossed && after < 0) {
                    after = 0;
                    crossed++;
                }
                if (after >= 0)
                    after++;
            }
        }
        printf("a = %g, Q = %g, r = %g: %d of the rays cross r+, worst null norm %.2e\n",
               holes[hi][0], holes[hi][1], holes[hi][2], crossed, worst);
        assert_true(crossed > 10);
        assert_true(worst < 1e-10);
    }
}

/* ---- 3, 4. the edges of our universe seen from inside -------------------- */

/* Outcome class along the centre row at fractional pixel x: 0 other side,
 * 1 horizon, 2 sky. */
static int row_class(const cr_frame *f, double x)
{
    cr_pixel p = cr_trace_point(f, x, 0.5 * (f->height - 1));
    if (p.outcome == CR_OUT_OTHER_SIDE)
        return 0;
    if (p.outcome == CR_OUT_HORIZON)
        return 1;
    assert_int_equal(p.outcome, CR_OUT_SKY);
    return 2;
}

/* The fractional pixel x in (lo, hi) where the class changes from below c to c. */
static double row_edge(const cr_frame *f, double lo, double hi, int c)
{
    int it;
    assert_true(row_class(f, lo) < c && row_class(f, hi) >= c);
    for (it = 0; it < 40; it++) {
        double mid = 0.5 * (lo + hi);
        if (row_class(f, mid) >= c)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* Closed form: the angle alpha from the camera's forward (-e_r, down) where
 * E = 1 + cos(psi) vr = 0 (psi = pi - alpha), and where b = r sin(psi) / E =
 * b_c with E > 0 (bisection on psi in (0, psi_0)). vr = |u^r| = the infall
 * speed term sqrt(2M/r - Q^2/r^2). */
static void closed_edges(double r, double vr, double bc, double *al_other, double *al_sky)
{
    double psi0 = acos(-1.0 / vr), lo = 0.0, hi = psi0;
    int it;
    for (it = 0; it < 200; it++) {
        double mid = 0.5 * (lo + hi);
        double b = r * sin(mid) / (1.0 + cos(mid) * vr);
        if (b < bc)
            lo = mid;
        else
            hi = mid;
    }
    *al_other = CR_PI - psi0;
    *al_sky = CR_PI - 0.5 * (lo + hi);
}

/* Pixel x (fractional, centre row) of the angle alpha from forward, 360 deg
 * fisheye of width w: sx = (2 (x + 1/2)/w - 1) pi = alpha. */
static double alpha_pixel(double al, int w)
{
    return (al / CR_PI + 1.0) * 0.5 * w - 0.5;
}

static void check_edges(double q, double r, double bc, double *worst)
{
    cr_frame f;
    const int w = 721;
    double vr = sqrt(2.0 / r - q * q / (r * r)), ao, as, xo, xs, to, ts;
    fall_frame(&f, 0.0, q, r, 90.0 * DEG, w, 3, 1e-9);
    f.sky_color.g = 255;
    closed_edges(r, vr, bc, &ao, &as);
    xo = alpha_pixel(ao, w);
    xs = alpha_pixel(as, w);
    to = row_edge(&f, 0.5 * (w - 1), xo + 0.5 * (xs - xo), 1);
    ts = row_edge(&f, xo + 0.5 * (xs - xo), w - 1.0, 2);
    printf("Q = %g, r = %g: other side edge %.4f deg (closed %.4f), sky edge %.4f deg "
           "(closed %.4f): off by %.1e and %.1e px\n",
           q, r, (to + 0.5) / (0.5 * w) * 180.0 - 180.0, ao / DEG,
           (ts + 0.5) / (0.5 * w) * 180.0 - 180.0, as / DEG, to - xo, ts - xs);
    *worst = fmax(*worst, fmax(fabs(to - xo), fabs(ts - xs)));
}

static void test_schwarzschild_interior(void **state)
{
    double worst = 0.0;
    (void)state;
    check_edges(0.0, 1.5, sqrt(27.0), &worst);
    check_edges(0.0, 1.0, sqrt(27.0), &worst);
    check_edges(0.0, 0.5, sqrt(27.0), &worst);
    assert_true(worst < 1e-3);
}

static double rn_bc(double q)
{
    double rph = 0.5 * (3.0 + sqrt(9.0 - 8.0 * q * q));
    return rph * rph / sqrt(rph * rph - 2.0 * rph + q * q);
}

static void test_rn_interior(void **state)
{
    double worst = 0.0;
    (void)state;
    check_edges(0.8, 1.2, rn_bc(0.8), &worst);
    check_edges(0.8, 0.6, rn_bc(0.8), &worst);
    assert_true(worst < 1e-3);
}

/* phi(r1) - phi(r0) = int_r0^r1 L dr / sqrt(E^2 r^4 - Delta L^2) (R(r) of
 * the equatorial ray), 4-point Gauss-Legendre on 4000 equal pieces (the
 * integrand is smooth: no turning point on the way out, and Delta = 0 is
 * nothing special). */
static double rn_phi(double E, double L, double q, double r0, double r1)
{
    static const double x4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                 0.8611363115940526};
    static const double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                 0.3478548451374538};
    double sum = 0.0, h = (r1 - r0) / 4000.0;
    int i, j;
    for (i = 0; i < 4000; i++)
        for (j = 0; j < 4; j++) {
            double r = r0 + h * (i + 0.5 + 0.5 * x4[j]);
            double del = r * r - 2.0 * r + q * q;
            sum += 0.5 * h * w4[j] * L / sqrt(E * E * r * r * r * r - del * L * L);
        }
    return sum;
}

/* v(r1) - v(r0) along the same ray: dv/dr = -r^2 K / ((P + sqrt R) sqrt R)
 * with P = E r^2, K = L^2, R = P^2 - Delta K (a = 0: (P - sqrt R)/Delta =
 * K/(P + sqrt R), regular at r+). */
static double rn_v(double E, double L, double q, double r0, double r1)
{
    static const double x4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                 0.8611363115940526};
    static const double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                 0.3478548451374538};
    double sum = 0.0, h = (r1 - r0) / 4000.0;
    int i, j;
    for (i = 0; i < 4000; i++)
        for (j = 0; j < 4; j++) {
            double r = r0 + h * (i + 0.5 + 0.5 * x4[j]);
            double del = r * r - 2.0 * r + q * q, P = E * r * r, sR = sqrt(P * P - del * L * L);
            sum += 0.5 * h * w4[j] * (-r * r * L * L / ((P + sR) * sR));
        }
    return sum;
}

/* Traces the ray of frame f's camera direction outward e_r cos(psi) +
 * e_ph sin(psi) (in the observer's equatorial plane), recording its path
 * into pts (room for 4000 points, 8 a step). */
static cr_pixel trace_in_plane(const cr_frame *f, double psi, cr_path *path, double *pts)
{
    const double n[3] = {cos(psi), 0.0, sin(psi)};
    cr_geo g;
    double yb[CR_NY];
    cr_ray ray;
    cr_camera_ray(f, n, &g, yb);
    cr_ray_from_bl(f, &g, yb, &ray);
    path->pts = pts;
    path->cap = 4000;
    path->sub = 8;
    ray.path = path;
    return cr_trace_loop(f, &ray);
}

static void test_rn_ray_path(void **state)
{
    cr_frame f;
    cr_path path;
    static double pts[4000 * CR_PN];
    const double q = 0.8, r0 = 1.0, psi = 40.0 * DEG;
    double E, L, worst = 0.0, vr, worst_t = 0.0, rp = 0.0, rm, lp, lm;
    cr_pixel px;
    int i, checked = 0, inside = 0, in_bl = 0;
    (void)state;
    fall_frame(&f, 0.0, q, r0, 90.0 * DEG, 101, 101, 1e-11);
    f.observer.projection = CR_PROJ_RECTILINEAR;
    cr_frame_prepare(&f);
    px = trace_in_plane(&f, psi, &path, pts);
    assert_int_equal(px.outcome, CR_OUT_SKY);
    /* independent constants: the free-fall frame of observer.h written here */
    vr = sqrt(2.0 / r0 - q * q / (r0 * r0));
    E = 1.0 + cos(psi) * vr;
    L = sin(psi) * r0;
    rp = cr_metric_r_plus(&f.metric);
    rm = cr_metric_r_minus(&f.metric);
    for (i = 1; i < path.n && i < path.cap; i++) {
        const double *p = pts + i * CR_PN;
        double want = rn_phi(E, L, q, r0, p[CR_P_R]), v = rn_v(E, L, q, r0, p[CR_P_R]), G;
        worst = fmax(worst, fabs(p[CR_P_PH] - want));
        /* the time column: v while the ray is in the ingoing chart, then BL
         * t = v - G(r) (G written out here: partial fractions of r^2/Delta)
         * from the step after it changes to BL beyond 2 (r+ + epsilon) on */
        lp = log(fabs(p[CR_P_R] - rp));
        lm = log(fabs(p[CR_P_R] - rm));
        G = p[CR_P_R] + (rp * rp * lp - rm * rm * lm) / (rp - rm);
        if (!in_bl && fabs(p[CR_P_T] - (v - G)) < fabs(p[CR_P_T] - v)) {
            in_bl = 1;
            assert_true(p[CR_P_R] > 2.0 * f.r_stop);
        }
        if (in_bl)
            v -= G;
        worst_t = fmax(worst_t, fabs(p[CR_P_T] - v) / (1.0 + fabs(v)));
        checked++;
        inside += p[CR_P_R] < cr_metric_r_plus(&f.metric);
    }
    printf("RN ray from r = %g through r+ = %g: %d path points (%d inside), worst |dphi| = "
           "%.2e rad, worst relative error of v (then t) %.2e\n",
           r0, cr_metric_r_plus(&f.metric), checked, inside, worst, worst_t);
    assert_true(inside >= 4 && checked > inside + 4);
    assert_true(worst < 1e-8);
    assert_true(worst_t < 1e-7 && in_bl);
}

/* ---- 5. continuity across r+ --------------------------------------------- */

static void test_continuity(void **state)
{
    cr_frame fo, fi;
    const int w = 41;
    int i, j, same = 0, total = 0, disc = 0;
    double worst_r = 0.0, worst_p = 0.0, rp;
    (void)state;
    {
        cr_metric mt = {1.0, 0.6, 0.3};
        rp = cr_metric_r_plus(&mt);
    }
    fall_frame(&fo, 0.6, 0.3, rp * (1.0 + 1e-6), 60.0 * DEG, w, w, 1e-9);
    fall_frame(&fi, 0.6, 0.3, rp * (1.0 - 1e-6), 60.0 * DEG, w, w, 1e-9);
    assert_false(fo.obs_inside);
    assert_true(fi.obs_inside);
    fo.disc.enabled = fi.disc.enabled = 1;
    fo.disc.r_in = fi.disc.r_in = 3.0;
    fo.disc.r_out = fi.disc.r_out = 15.0;
    fo.disc.r_hit_in = fi.disc.r_hit_in = 3.0;
    fo.disc.n_radial = fi.disc.n_radial = 2;
    fo.disc.n_sectors = fi.disc.n_sectors = 8;
    for (j = 0; j < w; j++)
        for (i = 0; i < w; i++) {
            cr_pixel po, pi;
            int co, ci;
            if (!cr_camera_in_image(&fo, i, j))
                continue;
            po = cr_trace_point(&fo, i, j);
            pi = cr_trace_point(&fi, i, j);
            /* the boundary V = 0 is "horizon" from outside, "other side" from
             * inside (ray.h): one class */
            co = po.outcome == CR_OUT_OTHER_SIDE ? CR_OUT_HORIZON : po.outcome;
            ci = pi.outcome == CR_OUT_OTHER_SIDE ? CR_OUT_HORIZON : pi.outcome;
            total++;
            same += co == ci;
            if (co == CR_OUT_DISC && ci == CR_OUT_DISC) {
                double dp = fabs(po.hit_phi - pi.hit_phi);
                /* no delay from inside: the observer's BL t is the
                 * interior's own (ray.h, cr_ray_delay) */
                assert_true(isnan(pi.delay));
                worst_r = fmax(worst_r, fabs(po.hit_r - pi.hit_r) / po.hit_r);
                worst_p = fmax(worst_p, fmin(dp, CR_TWO_PI - dp));
                disc++;
            }
        }
    printf("continuity at r+ (1 -+ 1e-6): %d of %d pixels in the same class, %d on the disc "
           "in both: worst relative change of the hit radius %.2e, of its azimuth %.2e rad\n",
           same, total, disc, worst_r, worst_p);
    assert_true(same >= 0.99 * total);
    assert_true(disc > total / 20);
    assert_true(worst_r < 1e-3 && worst_p < 1e-3);
}

/* ---- 6. the frames ------------------------------------------------------- */

static void test_freefall_frame(void **state)
{
    cr_metric mt = {1.0, 0.7, 0.4};
    cr_observer o;
    double e[4][4], low[4][2], z[4][4], v[3], b[4][4], g[4][4];
    int i, j, k;
    (void)state;
    memset(&o, 0, sizeof o);
    o.r = 3.0;
    o.theta = 1.0;
    o.motion = CR_MOTION_INFALL;
    cr_freefall_tetrad(&mt, 3.0, 1.0, 0, e, low);
    cr_zamo_tetrad(&mt, 3.0, 1.0, 0, z, NULL, NULL, NULL);
    cr_observer_zamo_velocity(&mt, &o, 0, v);
    cr_boost_tetrad(z, v, b);
    for (i = 0; i < 4; i++)
        for (k = 0; k < 4; k++)
            assert_true(fabs(e[i][k] - b[i][k]) < 1e-12 * (1.0 + fabs(b[i][k])));
    /* orthonormal inside, and the covariant legs are g e */
    {
        double r = 0.5 * (cr_metric_r_plus(&mt) + cr_metric_r_minus(&mt));
        cr_freefall_tetrad(&mt, r, 1.0, 0, e, low);
        cr_test_metric4(&mt, r, 1.0, g);
        for (i = 0; i < 4; i++) {
            for (j = 0; j < 4; j++) {
                double d = cr_test_dot(g, e[i], e[j]);
                double want = i == j ? (i == 0 ? -1.0 : 1.0) : 0.0;
                assert_true(fabs(d - want) < 1e-12);
            }
            for (k = 0; k < 2; k++) {
                int mu = k == 0 ? 0 : 3, nu;
                double s = 0.0;
                for (nu = 0; nu < 4; nu++)
                    s += g[mu][nu] * e[i][nu];
                assert_true(fabs(s - low[i][k]) < 1e-12);
            }
        }
    }
}

/* ---- 7. the sky's shift from inside, and the plunge's worldline ---------- */

/* The frequency ratio of sky light (a static source at infinity) seen by a
 * Schwarzschild free-faller inside r+: g = 1/E, E = 1 + cos(psi) sqrt(2M/r),
 * along the centre row, at r = 1 and just inside r+ (2 (1 - 1e-6)), to 1e-9
 * relative. */
static void test_inside_sky_shift(void **state)
{
    const double rs[2] = {1.0, 2.0 * (1.0 - 1e-6)};
    int ri, x, n = 0;
    double worst = 0.0;
    (void)state;
    for (ri = 0; ri < 2; ri++) {
        cr_frame f;
        const int w = 181;
        fall_frame(&f, 0.0, 0.0, rs[ri], 90.0 * DEG, w, 3, 1e-10);
        for (x = 0; x < w; x += 3) {
            cr_pixel p = cr_trace_point(&f, x, 1.0);
            double al = (2.0 * (x + 0.5) / w - 1.0) * CR_PI, psi = CR_PI - fabs(al);
            double want = 1.0 / (1.0 + cos(psi) * sqrt(2.0 / rs[ri]));
            if (p.outcome != CR_OUT_SKY)
                continue;
            worst = fmax(worst, fabs(p.redshift - want) / want);
            n++;
        }
    }
    printf("sky shift from inside: %d pixels, worst relative error %.2e\n", n, worst);
    assert_true(n > 50);
    assert_true(worst < 1e-9);
}

/* observer.r = [infall, r0, r1]: frame k of n at proper time k/(n-1) of the
 * way. Schwarzschild: r(tau) = (r0^1.5 - 1.5 sqrt(2) tau)^(2/3) (M = 1), to
 * 1e-9 relative. Kerr a = 0.9 on the equator: the BL phi of the frame at
 * r = 3 against int_3^10 a sqrt(2r) / (Delta sqrt(r^2 + a^2)) dr (u^phi / |u^r|
 * of the infall, Simpson with 20000 intervals), to 1e-9 rad. */
static void test_plunge_worldline(void **state)
{
    const char *sch = "metric: {m: 1, a: 0, q: 0}\n"
                      "observer: {r: [infall, 12, 0.5], theta: 90, phi: 0, hfov: 90, "
                      "motion: infall}\n";
    const char *kerr = "metric: {m: 1, a: 0.9, q: 0}\n"
                       "observer: {r: [infall, 10, 3], theta: 90, phi: 0, hfov: 90, "
                       "motion: infall}\n";
    cr_scene s;
    cr_frame f;
    cr_err e;
    double tau_total, worst = 0.0, want, sum = 0.0, h, a = 0.9;
    int k, i;
    (void)state;
    assert_int_equal(cr_scene_load_string(sch, strlen(sch), "scene.yml", &s, &e), 0);
    tau_total = (pow(12.0, 1.5) - pow(0.5, 1.5)) / (1.5 * sqrt(2.0));
    for (k = 0; k < 7; k++) {
        double tau = tau_total * k / 6.0;
        assert_int_equal(cr_scene_frame(&s, k, 7, 20, 20, NULL, &f, NULL, &e), 0);
        want = pow(pow(12.0, 1.5) - 1.5 * sqrt(2.0) * tau, 2.0 / 3.0);
        worst = fmax(worst, fabs(f.observer.r - want) / want);
        assert_true(f.obs_inside == (want < 2.0));
    }
    cr_scene_free(&s);
    printf("plunge r(tau): worst relative error %.2e\n", worst);
    assert_true(worst < 1e-9);
    assert_int_equal(cr_scene_load_string(kerr, strlen(kerr), "scene.yml", &s, &e), 0);
    assert_int_equal(cr_scene_frame(&s, 2, 3, 20, 20, NULL, &f, NULL, &e), 0);
    cr_scene_free(&s);
    assert_true(fabs(f.observer.r - 3.0) < 1e-12);
    h = 7.0 / 20000;
    for (i = 0; i <= 20000; i++) {
        double r = 3.0 + i * h, del = r * r - 2.0 * r + a * a;
        double v = a * sqrt(2.0 * r) / (del * sqrt(r * r + a * a));
        sum += v * (i == 0 || i == 20000 ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    sum *= h / 3.0;
    printf("Kerr plunge phi at r = 3: %.12f (quadrature %.12f)\n", f.observer.phi, sum);
    assert_true(fabs(f.observer.phi - sum) < 1e-9);
    /* off the equator (theta = 60 deg, Sigma = r^2 + a^2 / 4): the middle frame
     * of three sits at half the proper time, by Simpson here */
    {
        const char *k60 = "metric: {m: 1, a: 0.9, q: 0}\n"
                          "observer: {r: [infall, 10, 3], theta: 60, phi: 0, hfov: 90, "
                          "motion: infall}\n";
        double t_all = 0.0, t_mid = 0.0, rmid, hh;
        assert_int_equal(cr_scene_load_string(k60, strlen(k60), "scene.yml", &s, &e), 0);
        assert_int_equal(cr_scene_frame(&s, 1, 3, 20, 20, NULL, &f, NULL, &e), 0);
        cr_scene_free(&s);
        rmid = f.observer.r;
        for (k = 0; k < 2; k++) {
            double lo = k == 0 ? 3.0 : rmid, acc = 0.0;
            hh = (10.0 - lo) / 20000;
            for (i = 0; i <= 20000; i++) {
                double r = lo + i * hh;
                double v = (r * r + 0.25 * a * a) / sqrt((r * r + a * a) * 2.0 * r);
                acc += v * (i == 0 || i == 20000 ? 1.0 : (i % 2 ? 4.0 : 2.0));
            }
            if (k == 0)
                t_all = acc * hh / 3.0;
            else
                t_mid = acc * hh / 3.0;
        }
        printf("Kerr plunge at 60 deg: middle frame r = %.10f, proper time %.12f of %.12f\n", rmid,
               t_mid, t_all);
        assert_true(fabs(t_mid - 0.5 * t_all) < 1e-9 * t_all);
    }
}

/* ---- 9. inside the inner horizon ------------------------------------------ */

/* The null condition along rays from observers inside r- that cross r- and
 * r+: RN Q = 0.8 at r = 0.36 (r- = 0.4, bounce 0.32), Kerr-Newman a = 0.6,
 * Q = 0.5 at r = 0.3 (r- = 0.3755), Kerr a = 0.9 at r = 0.4 (r- = 0.5641),
 * tol 1e-12, every state at fractions 1/4 .. 1 of every step while in the
 * ingoing chart and for 20 steps beyond r+ + epsilon, as test 2 (there in
 * the BL metric: the ingoing form is ill-conditioned for outgoing rays; states
 * within 0.01 M of r = 0 left out: the
 * ingoing metric's terms there are of order a^2 / r^2 against 1 and the
 * ratio measures their cancellation, not the ray). Each hole has rays that
 * cross r- and rays that go on through r+, and some rays turn inside r-
 * first. */
static void test_null_across_inner(void **state)
{
    const double holes[3][3] = {{0.0, 0.8, 0.36}, {0.6, 0.5, 0.3}, {0.9, 0.0, 0.4}};
    int hi, turned_all = 0;
    (void)state;
    for (hi = 0; hi < 3; hi++) {
        cr_frame f;
        double worst = 0.0;
        int cross_m = 0, cross_p = 0, px, turned = 0;
        fall_frame(&f, holes[hi][0], holes[hi][1], holes[hi][2], 70.0 * DEG, 11, 11, 1e-12);
        assert_true(f.obs_inside && f.obs_inner);
        for (px = 0; px < 121; px++) {
            cr_ray ray;
            double n[3], yb[CR_NY], turns = 0.0;
            cr_geo g;
            int steps, was_in = 1, in_dw = 0, after = 0;
            if (!cr_camera_in_image(&f, px % 11, px / 11))
                continue;
            cr_camera_pixel_dir(&f, px % 11, px / 11, n);
            cr_camera_ray(&f, n, &g, yb);
            cr_ray_from_bl(&f, &g, yb, &ray);
            assert_int_equal(ray.inner, 1);
            for (steps = 0; steps < 5000 && cr_ray_ingoing(&ray) && after < 20; steps++) {
                int k;
                if (cr_ray_at_horizon(&f, &ray) || cr_ray_other_side(&ray) ||
                    cr_ray_singular(&ray))
                    break;
                after += ray.out;
                cr_ray_begin(&ray);
                in_dw |= ray.m[CR_M_DW] > 0.0;
                assert_int_equal(cr_ray_advance(&f, &ray), 0);
                for (k = 1; k <= 4; k++) {
                    double ys[CR_MN];
                    cr_ray_state_at(&ray, 0.25 * k, ys);
                    if (ys[CR_M_W] < 100.0) {
                        /* beyond r+ + epsilon (out) in the BL metric, as
                         * test 2 does after the change to BL */
                        cr_ray rb = ray;
                        if (ray.out)
                            rb.c.chart = CR_CHART_BL;
                        worst = fmax(worst, fabs(state_null(&f, &rb, ys)));
                    }
                }
                cr_ray_commit(&f, &ray, &turns);
                if (was_in && !ray.inner) {
                    cross_m++;
                    was_in = 0;
                    turned += in_dw;
                }
            }
            cross_p += ray.out;
        }
        printf("a = %g, Q = %g, r = %g: %d rays cross r- (%d after a turn inside), %d go on "
               "through r+, worst null norm %.2e\n",
               holes[hi][0], holes[hi][1], holes[hi][2], cross_m, turned, cross_p, worst);
        assert_true(cross_m > 10 && cross_p > 10);
        assert_true(worst < 1e-10);
        turned_all += turned;
    }
    assert_true(turned_all > 0);
}

/* phi(r) of an equatorial RN ray (a = 0, so phi~ = phi) with one turning
 * point r_t, from r0 inward to r_t and back out to r: int L dr / sqrt(R),
 * R = E^2 r^4 - Delta L^2, each leg with r = r_t + s^2 (dr / sqrt(R) =
 * 2 s ds / sqrt(R), regular at the turning point), 4-point Gauss-Legendre
 * on 4000 pieces. */
static double rn_phi_leg(double E, double L, double q, double rt, double r1)
{
    static const double x4[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                 0.8611363115940526};
    static const double w4[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                 0.3478548451374538};
    double sum = 0.0, s1 = sqrt(r1 - rt), h = s1 / 4000.0;
    int i, j;
    for (i = 0; i < 4000; i++)
        for (j = 0; j < 4; j++) {
            double sv = h * (i + 0.5 + 0.5 * x4[j]), r = rt + sv * sv;
            double del = r * r - 2.0 * r + q * q;
            sum += 0.5 * h * w4[j] * 2.0 * sv * L / sqrt(E * E * r * r * r * r - del * L * L);
        }
    return sum;
}

/* An RN ray's path through r- against the exact radial integral: Q = 0.8,
 * observer (infall) at r0 = 0.36 M inside r- = 0.4; (1) the equatorial ray
 * with local direction 40 deg from outward: straight out through r- and r+
 * to the sky, phi(r) = int_r0^r L dr / sqrt(R) (rn_phi) and the time column
 * v(r) (rn_v) at every path point, to 1e-8 rad and 1e-7 relative while in
 * the ingoing chart; (2) the ray 170 deg from outward: in to its turning
 * point r_t (the root of R, bisection), out through r- and r+: phi against
 * the two legs of rn_phi_leg, to 1e-8 rad. Constants from the free-fall
 * frame written here: E = 1 + cos(psi) sqrt(2M/r0 - Q^2/r0^2), L = r0 sin(psi). */
static void test_rn_ray_inner(void **state)
{
    const double q = 0.8, r0 = 0.36, psis[2] = {40.0 * DEG, 170.0 * DEG};
    int k;
    (void)state;
    for (k = 0; k < 2; k++) {
        cr_frame f;
        cr_path path;
        static double pts[4000 * CR_PN];
        double E, L, worst = 0.0, worst_t = 0.0, vr, rt = r0, phi_t = 0.0, rmin = r0;
        double r_prev = r0;
        double psi = psis[k];
        cr_pixel px;
        int i, checked = 0, inner = 0, between = 0, turned = 0;
        fall_frame(&f, 0.0, q, r0, 90.0 * DEG, 101, 101, 1e-11);
        f.observer.projection = CR_PROJ_RECTILINEAR;
        cr_frame_prepare(&f);
        assert_true(f.obs_inner);
        px = trace_in_plane(&f, psi, &path, pts);
        assert_int_equal(px.outcome, CR_OUT_SKY);
        vr = sqrt(2.0 / r0 - q * q / (r0 * r0));
        E = 1.0 + cos(psi) * vr;
        L = sin(psi) * r0;
        if (k == 1) {
            /* the turning point: R(r) = 0 below r0 (R(r0) > 0, R < 0 near r = 0) */
            double lo = 1e-6, hi = r0;
            int it;
            for (it = 0; it < 200; it++) {
                double mid = 0.5 * (lo + hi), del = mid * mid - 2.0 * mid + q * q;
                if (E * E * mid * mid * mid * mid - del * L * L > 0.0)
                    hi = mid;
                else
                    lo = mid;
            }
            rt = hi;
            phi_t = rn_phi_leg(E, L, q, rt, r0);
        }
        for (i = 1; i < path.n && i < path.cap; i++) {
            const double *p = pts + i * CR_PN;
            double r = p[CR_P_R], want;
            rmin = fmin(rmin, r);
            if (k == 0)
                want = rn_phi(E, L, q, r0, r);
            else {
                /* the outward leg from the first point beyond the one before */
                turned |= r > r_prev;
                want = turned ? phi_t + rn_phi_leg(E, L, q, rt, r)
                              : phi_t - rn_phi_leg(E, L, q, rt, r);
            }
            r_prev = r;
            if (r > 20.0)
                break;
            if (k == 1) {
                /* at the turn r alone cannot tell the legs apart (dphi/dr is
                 * infinite there): the nearer leg counts */
                double l = rn_phi_leg(E, L, q, rt, r);
                worst = fmax(worst, fmin(fabs(p[CR_P_PH] - (phi_t - l)),
                                         fabs(p[CR_P_PH] - (phi_t + l))));
            } else
                worst = fmax(worst, fabs(p[CR_P_PH] - want));
            if (k == 0 && r < cr_metric_r_plus(&f.metric)) {
                double v = rn_v(E, L, q, r0, r);
                worst_t = fmax(worst_t, fabs(p[CR_P_T] - v) / (1.0 + fabs(v)));
            }
            checked++;
            inner += r < cr_metric_r_minus(&f.metric);
            between += r > cr_metric_r_minus(&f.metric) && r < cr_metric_r_plus(&f.metric);
        }
        printf("RN ray from r = %g, %g deg from outward%s: %d path points (%d inside r-, %d "
               "between the horizons), worst |dphi| = %.2e rad, worst relative error of v "
               "%.2e\n",
               r0, psi / DEG, k ? " (turning inside r-)" : "", checked, inner, between, worst,
               worst_t);
        if (k == 1) {
            printf("  turning point r_t = %.10f, path minimum %.10f\n", rt, rmin);
            assert_true(fabs(rmin - rt) < 1e-3 && turned);
        }
        assert_true(inner >= 4 && between >= 4 && checked > inner + between + 4);
        assert_true(worst < 1e-8);
        assert_true(worst_t < 1e-7);
    }
}

/* Which rays from inside r- reach r = 0, against R(r) = P^2 - Delta K: a
 * backward ray that starts inward reaches r = CR_R_SING iff R > 0 all the
 * way from the observer down (R sampled on 20000 log-spaced points of
 * [CR_R_SING, r_obs]); one that starts outward never does. Kerr a = 0.9 at
 * r = 0.3 M, theta = 60 deg
 * (rays with Carter constant eta < 0 go through the disc r = 0; R(0) =
 * -a^2 eta) and Reissner-Nordstrom Q = 0.8 at r = 0.36 (R(0) = -Q^2 K: only
 * K = 0 rays, the centre pixel looking straight in), 61 x 61 fisheye of
 * 300 deg; pixels whose sampled minimum of R lies within 1e-9 of 0 (edge)
 * are left out. Every other pixel's outcome must match. */
static void test_singularity_outcome(void **state)
{
    const double holes[2][4] = {{0.9, 0.0, 0.3, 60.0}, {0.0, 0.8, 0.36, 90.0}};
    int hi;
    (void)state;
    for (hi = 0; hi < 2; hi++) {
        cr_frame f;
        const int w = 61;
        int px, sing = 0, other = 0, bad = 0, edge = 0;
        double a = holes[hi][0], q = holes[hi][1], ro = holes[hi][2];
        fall_frame(&f, a, q, ro, holes[hi][3] * DEG, w, w, 1e-10);
        f.observer.hfov = f.observer.vfov = 300.0 * DEG;
        cr_frame_prepare(&f);
        for (px = 0; px < w * w; px++) {
            cr_ray ray;
            cr_pixel p;
            double n[3], yb[CR_NY], E, L, K, rmin = INFINITY;
            cr_geo g;
            int j, want;
            if (!cr_camera_in_image(&f, px % w, px / w))
                continue;
            cr_camera_pixel_dir(&f, px % w, px / w, n);
            cr_camera_ray(&f, n, &g, yb);
            cr_ray_from_bl(&f, &g, yb, &ray);
            E = ray.c.E;
            L = ray.c.L;
            K = ray.c.eta + (L + a * E) * (L + a * E);
            for (j = 0; j <= 20000; j++) {
                /* log-spaced from CR_R_SING (where the ray ends) to r_obs */
                double r = CR_R_SING * pow(ro / CR_R_SING, j / 20000.0);
                double P = E * (r * r + a * a) + a * L;
                double del = r * r - 2.0 * r + a * a + q * q;
                rmin = fmin(rmin, (P * P - del * K) / (P * P + fabs(del * K) + 1e-300));
            }
            want = ray.m[CR_M_DW] > 0.0 && rmin > 0.0;
            p = cr_trace_loop(&f, &ray);
            if (fabs(rmin) < 1e-9) {
                edge++;
                continue;
            }
            sing += p.outcome == CR_OUT_SINGULARITY;
            other += p.outcome != CR_OUT_SINGULARITY;
            assert_true(p.outcome != CR_OUT_ERROR);
            if ((p.outcome == CR_OUT_SINGULARITY) != want) {
                bad++;
                printf("  pixel (%d, %d): %s, predicted %s (min R ratio %.3e)\n", px % w,
                       px / w, cr_outcome_name(p.outcome), want ? "singularity" : "not",
                       rmin);
            }
        }
        printf("a = %g, Q = %g, r = %g: %d rays reach r = 0, %d do not, %d at the edge, %d "
               "misclassified\n",
               a, q, ro, sing, other, edge, bad);
        assert_int_equal(bad, 0);
        assert_true(sing > 0 && other > 0);
    }
}

/* A plunge through r+ and r- of an RN hole (Q = 0.8: r+ = 1.6, r- = 0.4,
 * bounce 0.32): observer.r = [infall, 2, 0.33], 41 frames, r(tau) against the
 * closed form tau(r) = T(r0) - T(r), T(x) = (2x - Q^2)^(3/2)/6 + Q^2 (2x -
 * Q^2)^(1/2)/2 (dtau/dr = -r/sqrt(2Mr - Q^2)), inverted by bisection, to
 * 1e-8 relative; the last frames lie inside r-, and each frame traces. */
static double rn_T(double x, double q)
{
    double u = 2.0 * x - q * q;
    return u * sqrt(u) / 6.0 + 0.5 * q * q * sqrt(u);
}

static void test_plunge_inner(void **state)
{
    const char *rn = "metric: {m: 1, a: 0, q: 0.8}\n"
                     "observer: {r: [infall, 2, 0.33], theta: 90, phi: 0, hfov: 300, "
                     "motion: infall, projection: fisheye}\n";
    cr_scene s;
    cr_frame f;
    cr_err e;
    const double q = 0.8;
    double total = rn_T(2.0, q) - rn_T(0.33, q), worst = 0.0;
    int k, inner = 0;
    (void)state;
    assert_int_equal(cr_scene_load_string(rn, strlen(rn), "scene.yml", &s, &e), 0);
    for (k = 0; k < 41; k++) {
        double want_tau = total * k / 40.0, lo = 0.33, hi = 2.0;
        int it;
        cr_pixel p;
        for (it = 0; it < 200; it++) {
            double mid = 0.5 * (lo + hi);
            if (rn_T(2.0, q) - rn_T(mid, q) > want_tau)
                lo = mid;
            else
                hi = mid;
        }
        assert_int_equal(cr_scene_frame(&s, k, 41, 9, 9, NULL, &f, NULL, &e), 0);
        worst = fmax(worst, fabs(f.observer.r - 0.5 * (lo + hi)) / f.observer.r);
        inner += f.obs_inner;
        assert_true(f.obs_inner == (f.observer.r < 0.4));
        p = cr_trace_point(&f, 4, 4);
        assert_true(p.outcome != CR_OUT_ERROR);
    }
    cr_scene_free(&s);
    printf("RN plunge through r+ and r-: %d of 41 frames inside r-, worst relative error of "
           "r(tau) %.2e\n",
           inner, worst);
    assert_true(inner >= 2);
    assert_true(worst < 1e-8);
}

/* Continuity across r-: the same free-faller (Kerr-Newman a = 0.6, Q = 0.3,
 * theta = 60 deg, a disc from 3 to 15 M) at r- (1 + 1e-6), between the
 * horizons, and at r- (1 - 1e-6), inside r-: the same 41 x 41 fisheye image,
 * >= 99 % of the pixels ending the same way, disc hits within 1e-3 relative
 * in radius and 1e-3 rad in azimuth (the frame is the same free-fall frame
 * on both sides; only the rays' first stretch, across r-, differs). */
static void test_continuity_inner(void **state)
{
    cr_frame fo, fi;
    const int w = 41;
    int i, j, same = 0, total = 0, disc = 0;
    double worst_r = 0.0, worst_p = 0.0, rm;
    (void)state;
    {
        cr_metric mt = {1.0, 0.6, 0.3};
        rm = cr_metric_r_minus(&mt);
    }
    fall_frame(&fo, 0.6, 0.3, rm * (1.0 + 1e-6), 60.0 * DEG, w, w, 1e-9);
    fall_frame(&fi, 0.6, 0.3, rm * (1.0 - 1e-6), 60.0 * DEG, w, w, 1e-9);
    assert_true(fo.obs_inside && !fo.obs_inner);
    assert_true(fi.obs_inner);
    fo.disc.enabled = fi.disc.enabled = 1;
    fo.disc.r_in = fi.disc.r_in = 3.0;
    fo.disc.r_out = fi.disc.r_out = 15.0;
    fo.disc.r_hit_in = fi.disc.r_hit_in = 3.0;
    fo.disc.n_radial = fi.disc.n_radial = 2;
    fo.disc.n_sectors = fi.disc.n_sectors = 8;
    for (j = 0; j < w; j++)
        for (i = 0; i < w; i++) {
            cr_pixel po, pi;
            if (!cr_camera_in_image(&fo, i, j))
                continue;
            po = cr_trace_point(&fo, i, j);
            pi = cr_trace_point(&fi, i, j);
            total++;
            same += po.outcome == pi.outcome;
            if (po.outcome == CR_OUT_DISC && pi.outcome == CR_OUT_DISC) {
                double dp = fabs(po.hit_phi - pi.hit_phi);
                /* no delay from inside: the observer's BL t is the
                 * interior's own (ray.h, cr_ray_delay) */
                assert_true(isnan(pi.delay));
                worst_r = fmax(worst_r, fabs(po.hit_r - pi.hit_r) / po.hit_r);
                worst_p = fmax(worst_p, fmin(dp, CR_TWO_PI - dp));
                disc++;
            }
        }
    printf("continuity at r- (1 +- 1e-6): %d of %d pixels in the same class, %d on the disc "
           "in both: worst relative change of the hit radius %.2e, of its azimuth %.2e rad\n",
           same, total, disc, worst_r, worst_p);
    assert_true(same >= 0.99 * total);
    assert_true(disc > total / 50);
    assert_true(worst_r < 1e-3 && worst_p < 1e-3);
}

/* ---- 10. the other exterior's sky ----------------------------------------- */

/* skymap.other_side (ray.h's mirror): a Schwarzschild free-faller at r = 1
 * (and Reissner-Nordstrom Q = 0.8 from inside r-, r = 0.36, whose view has
 * no other side) at theta = 70 deg with a disc from 3 to 15 M that the
 * centre row's rays cross, 181 x 3 fisheye of 360 deg, our sky a one-texel green
 * image, the other side's a one-texel blue one. Every pixel that ends as sky,
 * disc or horizon without the second image ends the same with it, bit for
 * bit; every `other side` pixel ends as `other side` with the other sky's
 * blue where b = r sin(psi)/|E| < 3 sqrt(3) (E = 1 + cos(psi) sqrt(2M/r) < 0:
 * the mirror of our sky's edge) and the horizon colour beyond, its frequency
 * ratio 1/|E| to 1e-9 on the blue ones. And one equatorial ray (psi = 150 deg
 * from outward, E < 0) traced with its path: the path's phi (in the other
 * exterior's mirror coordinates) against -int L dr / sqrt(E^2 r^4 - Delta
 * L^2) from r0 out to 20 M (rn_phi with -L), to 1e-8 rad. */
static void test_other_side_sky(void **state)
{
    static const uint8_t tex[6] = {0, 255, 0, 0, 0, 255};
    const double holes[2][2] = {{0.0, 1.0}, {0.8, 0.36}};
    int hi;
    (void)state;
    for (hi = 0; hi < 2; hi++) {
        cr_frame f0, f1;
        const int w = 181;
        double q = holes[hi][0], r0 = holes[hi][1], vr = sqrt(2.0 / r0 - q * q / (r0 * r0));
        double worst = 0.0;
        int x, same = 0, other = 0, blue = 0, bad = 0, disc = 0;
        fall_frame(&f0, 0.0, q, r0, 70.0 * DEG, w, 3, 1e-10);
        f0.sky.rgb = tex;
        f0.sky.width = f0.sky.height = 1;
        /* a disc that rays of the centre row cross (off the equator): none
         * of it is in the other exterior */
        f0.disc.enabled = 1;
        f0.disc.r_in = f0.disc.r_hit_in = 3.0;
        f0.disc.r_out = 15.0;
        f0.disc.n_radial = 2;
        f0.disc.n_sectors = 8;
        cr_frame_prepare(&f0);
        f1 = f0;
        f1.sky.other_width = f1.sky.other_height = 1;
        for (x = 0; x < w; x++) {
            cr_pixel a = cr_trace_point(&f0, x, 1.0), b = cr_trace_point(&f1, x, 1.0);
            double al = (2.0 * (x + 0.5) / w - 1.0) * CR_PI, psi = CR_PI - fabs(al);
            double E = 1.0 + cos(psi) * vr, bb = r0 * sin(psi) / fabs(E);
            if (a.outcome != CR_OUT_OTHER_SIDE) {
                disc += a.outcome == CR_OUT_DISC;
                same += a.outcome == b.outcome && a.color.r == b.color.r &&
                        a.color.g == b.color.g && a.color.b == b.color.b &&
                        a.redshift == b.redshift && a.hit_r == b.hit_r;
                bad += !(a.outcome == b.outcome && a.redshift == b.redshift);
                continue;
            }
            other++;
            assert_int_equal(b.outcome, CR_OUT_OTHER_SIDE);
            assert_true(E < 0.0);
            if (fabs(bb - sqrt(27.0)) < 1e-3)
                continue; /* the edge */
            if (bb < sqrt(27.0)) {
                assert_true(b.color.b == 255 && b.color.g == 0);
                worst = fmax(worst, fabs(b.redshift - 1.0 / fabs(E)) * fabs(E));
                blue++;
            } else
                assert_true(b.color.r == f1.horizon_color.r && b.color.g == f1.horizon_color.g &&
                            b.color.b == f1.horizon_color.b && b.redshift == 0.0);
        }
        printf("Q = %g, r = %g: %d pixels unchanged by skymap.other_side (%d on the disc), %d "
               "other side (%d on its sky), worst relative error of g = 1/|E| %.2e\n",
               q, r0, same, disc, other, blue, worst);
        assert_int_equal(bad, 0);
        assert_int_equal(same + other, w);
        assert_true(disc > 0);
        if (hi == 0)
            assert_true(blue > 10 && other > blue);
        else
            assert_int_equal(other, 0);
        assert_true(worst < 1e-9);
    }
    {
        cr_frame f;
        cr_path path;
        static double pts[4000 * CR_PN];
        const double r0 = 1.0, psi = 150.0 * DEG;
        double n[3], E, L, worst = 0.0;
        cr_geo g;
        double yb[CR_NY];
        cr_ray ray;
        cr_pixel px;
        int i, checked = 0;
        fall_frame(&f, 0.0, 0.0, r0, 90.0 * DEG, 101, 101, 1e-11);
        f.observer.projection = CR_PROJ_RECTILINEAR;
        f.observer.phi = 0.7; /* the mirror's phi is -0.7 */
        f.sky.rgb = tex;
        f.sky.width = f.sky.height = 1;
        f.sky.other_width = f.sky.other_height = 1;
        cr_frame_prepare(&f);
        n[0] = cos(psi);
        n[1] = 0.0;
        n[2] = sin(psi);
        cr_camera_ray(&f, n, &g, yb);
        cr_ray_from_bl(&f, &g, yb, &ray);
        assert_true(ray.mirror);
        path.pts = pts;
        path.cap = 4000;
        path.sub = 8;
        ray.path = &path;
        px = cr_trace_loop(&f, &ray);
        assert_int_equal(px.outcome, CR_OUT_OTHER_SIDE);
        E = 1.0 + cos(psi) * sqrt(2.0 / r0);
        L = sin(psi) * r0;
        assert_true(E < 0.0 && r0 * sin(psi) / fabs(E) < sqrt(27.0));
        for (i = 1; i < path.n && i < path.cap; i++) {
            const double *p = pts + i * CR_PN;
            if (p[CR_P_R] > 20.0)
                break;
            double d = p[CR_P_PH] - (-0.7 + rn_phi(-E, -L, 0.0, r0, p[CR_P_R]));
            d = remainder(d, CR_TWO_PI);
            worst = fmax(worst, fabs(d));
            checked++;
        }
        printf("a ray to the other exterior's sky: %d path points, worst |dphi| %.2e rad\n",
               checked, worst);
        assert_true(checked > 20);
        assert_true(worst < 1e-8);
    }    /* Kerr-Newman (a = 0.6, Q = 0.3, r = 1.2, theta = 70 deg, phi = 0.7): every
     * centre-row ray bound for the other side, mirrored by ray.h, against
     * the mirror image made here from its BL start (E, L -> -E, -L, phi ->
     * -phi, u^r, u^theta kept) and started as an ordinary ray bound for our
     * horizon: the same Mino state to 1e-12 (pr mod 2 pi), and the same end
     * (outcome, redshift to 1e-9). */
    {
        cr_frame fa, fb;
        const int w = 61;
        int x, n = 0;
        double worst_s = 0.0, worst_z = 0.0;
        fall_frame(&fa, 0.6, 0.3, 1.2, 70.0 * DEG, w, 3, 1e-10);
        fa.observer.phi = 0.7;
        fa.sky.rgb = tex;
        fa.sky.width = fa.sky.height = 1;
        cr_frame_prepare(&fa);
        fb = fa;
        fa.sky.other_width = fa.sky.other_height = 1;
        for (x = 0; x < w; x++) {
            cr_ray ra, rb;
            cr_geo g, g2;
            double n3[3], yb[CR_NY], yb2[CR_NY];
            cr_pixel pa, pb;
            int i;
            cr_camera_pixel_dir(&fa, x, 1, n3);
            cr_camera_ray(&fa, n3, &g, yb);
            cr_ray_from_bl(&fa, &g, yb, &ra);
            if (!ra.mirror)
                continue;
            g2 = g;
            g2.E = -g.E;
            g2.L = -g.L;
            for (i = 0; i < CR_NY; i++)
                yb2[i] = yb[i];
            yb2[CR_Y_PH] = -yb[CR_Y_PH];
            cr_ray_from_bl(&fb, &g2, yb2, &rb);
            assert_true(rb.exit_out && !rb.mirror);
            for (i = 0; i < CR_M_T; i++) {
                double d = ra.m[i] - rb.m[i];
                if (i == CR_M_PR)
                    d = remainder(d, CR_TWO_PI);
                worst_s = fmax(worst_s, fabs(d));
            }
            pa = cr_trace_loop(&fa, &ra);
            pb = cr_trace_loop(&fb, &rb);
            assert_int_equal(pa.outcome, CR_OUT_OTHER_SIDE);
            assert_true(pb.outcome == CR_OUT_SKY || pb.outcome == CR_OUT_HORIZON);
            worst_z = fmax(worst_z, fabs(pa.redshift - pb.redshift));
            n++;
        }
        printf("Kerr-Newman: %d rays mirrored, worst state difference %.2e, redshift %.2e\n", n,
               worst_s, worst_z);
        assert_true(n > 5);
        assert_true(worst_s < 1e-12 && worst_z < 1e-9);
    }
}

/* ---- bad input ----------------------------------------------------------- */

static void expect_refused(const char *text, const char *n1, const char *n2)
{
    cr_scene s;
    cr_frame f;
    cr_err e;
    int rc;
    e.msg[0] = '\0';
    assert_int_equal(cr_scene_load_string(text, strlen(text), "scene.yml", &s, &e), 0);
    rc = cr_scene_frame(&s, 0, 1, 40, 20, NULL, &f, NULL, &e);
    cr_scene_free(&s);
    if (rc == 0)
        fail_msg("accepted:\n%s", text);
    if (!strstr(e.msg, n1) || (n2 && !strstr(e.msg, n2)))
        fail_msg("message \"%s\" lacks \"%s\" / \"%s\"", e.msg, n1, n2 ? n2 : "");
}

static void test_refused(void **state)
{
    cr_scene s;
    cr_frame f;
    cr_err e;
    const char *ok = "metric: {m: 1, a: 0.6, q: 0.3}\n"
                     "observer: {r: 1.2, theta: 90, phi: 0, hfov: 90, motion: infall}\n";
    (void)state;
    expect_refused("metric: {m: 1, a: 0, q: 0}\nobserver: {r: 1, theta: 90, phi: 0, hfov: 90}\n",
                   "observer.r = 1", "stay at rest");
    expect_refused("metric: {m: 1, a: 0, q: 0}\n"
                   "observer: {r: 2, theta: 90, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r", "on the event horizon");
    expect_refused("metric: {m: 1, a: 0, q: 0.8}\n"
                   "observer: {r: 0.3, theta: 90, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 0.3", "bounces there, inside r- = 0.4");
    expect_refused("metric: {m: 1, a: 0, q: 0.8}\n"
                   "observer: {r: 0.36, theta: 90, phi: 0, hfov: 90}\n",
                   "observer.r = 0.36", "inside the inner horizon r- = 0.4");
    expect_refused("metric: {m: 1, a: 0.9, q: 0}\n"
                   "observer: {r: 5e-5, theta: 60, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 5e-05", "disc inside the ring");
    expect_refused("metric: {m: 1, a: 0.6, q: 0}\n"
                   "observer: {r: 0.2, theta: 60, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 0.2", "on the inner horizon");
    expect_refused("metric: {m: 1, a: 0, q: 0.8}\n"
                   "observer: {r: 0.4, theta: 90, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 0.4", "on the inner horizon");
    expect_refused("metric: {m: 1, a: 0.6, q: 0}\n"
                   "observer: {r: 1.2, theta: 90, phi: 0, hfov: 90, motion: zamo}\n",
                   "observer.motion = zamo", "inside the event horizon");
    expect_refused("metric: {m: 1, a: 0.6, q: 0}\n"
                   "observer: {r: 1.2, theta: 90, phi: 0, hfov: 90, motion: orbit}\n",
                   "observer.motion = orbit", "inside the event horizon");
    expect_refused("metric: {m: 1, a: 0, q: 0}\n"
                   "observer: {r: 0, theta: 90, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 0", "singularity");
    expect_refused("metric: {m: 1, a: 1, q: 0}\n"
                   "observer: {r: 0.5, theta: 90, phi: 0, hfov: 90, motion: infall}\n",
                   "observer.r = 0.5", "extremal");
    expect_refused("metric: {m: 1, a: 0, q: 0}\n"
                   "observer: {r: 1, theta: 90, phi: 0, hfov: 90, motion: [0.6, 0, 0.8]}\n",
                   "observer.motion", "below 1");
    /* rk4 cannot cross */
    {
        cr_trace_settings ts = cr_trace_defaults();
        ts.integrator = CR_INTEG_RK4;
        assert_int_equal(cr_scene_load_string(ok, strlen(ok), "scene.yml", &s, &e), 0);
        assert_int_not_equal(cr_scene_frame(&s, 0, 1, 40, 20, &ts, &f, NULL, &e), 0);
        assert_non_null(strstr(e.msg, "raytracer.integrator = rk4"));
        assert_int_equal(cr_scene_frame(&s, 0, 1, 40, 20, NULL, &f, NULL, &e), 0);
        assert_true(f.obs_inside);
        cr_scene_free(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ingoing_rhs_vs_bl),   cmocka_unit_test(test_freefall_frame),
        cmocka_unit_test(test_null_across_horizon), cmocka_unit_test(test_schwarzschild_interior),
        cmocka_unit_test(test_rn_interior),         cmocka_unit_test(test_rn_ray_path),
        cmocka_unit_test(test_continuity),          cmocka_unit_test(test_inside_sky_shift),
        cmocka_unit_test(test_plunge_worldline),    cmocka_unit_test(test_null_across_inner),
        cmocka_unit_test(test_rn_ray_inner),        cmocka_unit_test(test_singularity_outcome),
        cmocka_unit_test(test_plunge_inner),        cmocka_unit_test(test_continuity_inner),
        cmocka_unit_test(test_other_side_sky),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
