/* The Mino-time integrator (src/core/mino.h) against analytic results.
 *
 * 1. Right-hand side: at 4000 random null states of Kerr-Newman holes
 *    (a up to 1, Q != 0 with a^2 + Q^2 <= 1, r from 1e-3 M above the
 *    horizon to 1e4 M, theta down to 1e-8 rad from either pole), made in the
 *    ZAMO frame from the paper's BL quantities, the state of
 *    cr_mino_from_bl satisfies its first integrals (monitor <= 1e-12) and
 *    its derivatives dr/dtau, dtheta/dtau, dphi/dtau, d^2r/dtau^2,
 *    d^2theta/dtau^2 equal Sigma u^r, Sigma u^theta, Sigma u^phi and
 *    Sigma d(Sigma u^r)/dlambda, Sigma d(Sigma u^theta)/dlambda from the BL
 *    equations of geodesic.h (d lambda = Sigma d tau), to 1e-12 relative to
 *    the magnitude of the terms, times kap = 1 + (r^2 + a^2)/Delta (the
 *    rounding of the 1/Delta terms near the horizon, on both sides).
 * 2. Error control: along 600 rays (finite observers at 20 M and 1000 M and
 *    the observer at infinity, random a, Q) the first-integral monitor stays
 *    below 5 tol for tol = 1e-6, 1e-8, 1e-10. The sky direction of
 *    Schwarzschild rays from infinity, compared with the exact deflection
 *    (elliptic integral), and of Kerr-Newman rays, compared with a run at
 *    tol = 1e-13, is within 100 tol and improves by a factor within
 *    [20, 500] per factor 100 in tol (global error ~ tol). cr_dp5_dense is
 *    exact at the start of a step, within 1 ulp of |y0| + |y1| at its end,
 *    and its error at mid-step scales like h^5: ratio within [24, 40] (32
 *    ideal) as h halves.
 * 3. Darwin: for a = Q = 0, the radius where a ray first (direct image) and
 *    second (first higher-order image) crosses the equatorial plane equals
 *    the radius from the exact orbit equation
 *      d psi/du = (1/b^2 - u^2 + 2 u^3)^(-1/2),  u = 1/r  (M = 1),
 *    integrated in closed form by Carlson's R_F (checked against quadrature
 *    and the weak-field series), to 1e-7 relative at the default tol 1e-8
 *    and to 1e-9 at tol 1e-10 (observer at infinity at inclinations 0, 40,
 *    80 deg, and a static observer at r = 1e4 M at 60 deg). The crossing is
 *    located with the trace loop's own functions (cr_ray_advance,
 *    cr_ray_event_locate on the dense output); cr_trace_loop itself must hit a
 *    disc annulus r_pred (1 +- 1e-6) on the right face and miss the annuli
 *    just inside and outside it.
 * 4. The observer at infinity: for a = 0 the shadow is a circle (edge radii
 *    in 5 directions agree to 1e-8 M) of radius b_c = sqrt(27) M
 *    (Reissner-Nordstrom: r_ph^2 / sqrt(r_ph^2 - 2 r_ph + Q^2)): the
 *    hit/escape edge found by bisection at inclinations 0, 45, 90 deg lies
 *    within 1e-7 M of it.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "testutil.h"

/* ---- exact Schwarzschild orbits (M = 1) -------------------------------- */

/* Carlson's R_F(x, y, z) by duplication (Carlson 1995), to ~1e-16. */
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

/* The orbit of impact parameter b > sqrt(27): G(u) = 1/b^2 - u^2 + 2 u^3 =
 * 2 (u - u1)(u - u2)(u - u3) with u1 < 0 < u2 < u3; u2 = 1/r_min. */
typedef struct darwin {
    double b, u1, u2, u3;
} darwin;

static double darwin_G(const darwin *d, double u)
{
    return 1.0 / (d->b * d->b) - u * u + 2.0 * u * u * u;
}

static void darwin_init(darwin *d, double b)
{
    /* u^3 - u^2/2 + 1/(2 b^2) = 0; u = t + 1/6: t^3 + p t + q = 0 */
    double p = -1.0 / 12.0, q = -1.0 / 108.0 + 0.5 / (b * b);
    double m = 2.0 * sqrt(-p / 3.0), th = acos(fmax(-1.0, fmin(1.0, 1.5 * q / p * sqrt(-3.0 / p))));
    double u[3];
    int k, it;
    for (k = 0; k < 3; k++) {
        u[k] = 1.0 / 6.0 + m * cos(th / 3.0 - CR_TWO_PI * k / 3.0);
        for (it = 0; it < 3; it++) { /* polish by Newton */
            double g = 1.0 / (b * b) - u[k] * u[k] + 2.0 * u[k] * u[k] * u[k];
            double dg = -2.0 * u[k] + 6.0 * u[k] * u[k];
            if (dg != 0.0)
                u[k] -= g / dg;
        }
    }
    /* k = 0: largest, k = 1: middle, k = 2: smallest */
    d->b = b;
    d->u3 = u[0];
    d->u2 = u[1];
    d->u1 = u[2];
}

/* F(y) = int_y^u2 du / sqrt(G(u)) for u1 <= y <= u2: substituting
 * s = 1/(u2 - u) turns it into 2 R_F over [s0, inf), which scales to
 * sqrt(2 (u2 - y)) R_F((u2-u1)(u3-u2), (y-u1)(u3-u2), (u3-y)(u2-u1)). */
static double darwin_F(const darwin *d, double y)
{
    double a = d->u2 - d->u1, c = d->u3 - d->u2;
    if (y >= d->u2)
        return 0.0;
    return sqrt(2.0 * (d->u2 - y)) * carlson_rf(a * c, (y - d->u1) * c, (d->u3 - y) * a);
}

/* The same integral by Gauss-Legendre quadrature after u = u2 - v^2 (which
 * removes the turning-point singularity): an independent check of darwin_F. */
static double darwin_F_quad(const darwin *d, double y)
{
    static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                 0.5384693101056831, 0.9061798459386640};
    static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                 0.4786286704993665, 0.2369268850561891};
    const int n = 4000;
    double vmax = sqrt(d->u2 - y), sum = 0.0;
    int i, k;
    for (i = 0; i < n; i++) {
        double lo = vmax * i / n, hi = vmax * (i + 1) / n;
        for (k = 0; k < 5; k++) {
            double v = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x5[k];
            double f = 2.0 / sqrt(2.0 * (d->u2 - v * v - d->u1) * (d->u3 - d->u2 + v * v));
            sum += 0.5 * (hi - lo) * w5[k] * f;
        }
    }
    return sum;
}

/* The u (= 1/r) at orbital angle psi from a start at u0 moving inward
 * (psi = F(u0) - F(u) before the turning point, F(u0) + F(u) after it);
 * 0 when the ray escapes before psi. */
static double darwin_u_at(const darwin *d, double u0, double psi)
{
    double F0 = darwin_F(d, u0), target, lo, hi;
    int inbound = psi <= F0, it;
    if (inbound) {
        target = F0 - psi;
        lo = u0;
    } else {
        target = psi - F0;
        lo = 0.0;
        if (target > darwin_F(d, 0.0))
            return 0.0;
    }
    hi = d->u2;
    for (it = 0; it < 200; it++) { /* F decreases from lo to hi */
        double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi)
            break;
        if (darwin_F(d, mid) > target)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* ---- helpers ----------------------------------------------------------- */

static const uint8_t sky_texel[3] = {0, 0, 255};

/* A frame (M = 1) with the observer at r (INFINITY allowed) and polar angle
 * theta, Mino integrator at tolerance tol, and (when sky is set) a 1x1 sky
 * texture, so that rays leave for the sky at infinity (w = 0). */
static void make_frame(cr_frame *f, double a, double q, double r, double theta, double tol,
                       int sky)
{
    cr_test_empty_frame(f, 1.0, a, q, r, theta);
    f->observer.hextent = f->observer.vextent = 40.0;
    f->integrator = CR_INTEG_MINO;
    f->tolerance = tol;
    if (sky) {
        f->sky.rgb = sky_texel;
        f->sky.width = f->sky.height = 1;
    }
    cr_frame_prepare(f);
}

/* What stepping a ray with the trace loop's own functions (cr_ray_advance,
 * cr_ray_commit, the disc event located on the dense output) saw. */
typedef struct walk {
    double max_mon; /* largest first-integral monitor */
    long steps;
    int outcome;
    int n_cross;        /* crossings of the equatorial plane recorded */
    double r_cross[4];  /* their BL radii */
    int side[4];        /* 0 from above (top face), 1 from below */
} walk;

static void walk_ray(const cr_frame *f, cr_ray *ray, walk *wk)
{
    double turns = 0.0;
    memset(wk, 0, sizeof *wk);
    for (;;) {
        double e, v0, v1;
        if (cr_ray_at_horizon(f, ray)) {
            wk->outcome = CR_OUT_HORIZON;
            break;
        }
        e = cr_ray_begin(ray);
        if (!(e <= wk->max_mon))
            wk->max_mon = e;
        if (cr_ray_escaping(f, ray)) {
            wk->outcome = CR_OUT_SKY;
            break;
        }
        if (wk->steps >= f->max_steps || turns >= f->max_turns) {
            wk->outcome = CR_OUT_LIMIT;
            break;
        }
        if (cr_ray_advance(f, ray) != 0) {
            wk->outcome = CR_OUT_ERROR;
            break;
        }
        wk->steps++;
        v0 = cr_ray_event_value(f, ray, CR_EV_DISC, ray->m);
        v1 = cr_ray_event_value(f, ray, CR_EV_DISC, ray->m1);
        if (v0 != 0.0 && (v0 < 0.0) != (v1 < 0.0) && wk->n_cross < 4) {
            double ys[CR_RAY_NY], r, th, ph;
            cr_ray_event_locate(f, ray, CR_EV_DISC, v0, 1.0, v1, ys);
            cr_ray_position(ray, ys, &r, &th, &ph);
            wk->r_cross[wk->n_cross] = r;
            wk->side[wk->n_cross] = v0 < 0.0 ? 0 : 1;
            wk->n_cross++;
        }
        cr_ray_commit(f, ray, &turns);
    }
}

/* The Mino ray of the observer at infinity at impact coordinates (alpha, beta). */
static void ray_from_infinity(const cr_frame *f, double alpha, double beta, cr_ray *ray)
{
    cr_camera_ray_at_infinity(f, alpha, beta, &ray->c, ray->m);
    cr_ray_mino_start(f, ray);
}

/* Unit vector of polar angle th and azimuth ph. */
static void unit_vec(double th, double ph, double v[3])
{
    v[0] = sin(th) * cos(ph);
    v[1] = sin(th) * sin(ph);
    v[2] = cos(th);
}

/* Angle between two vectors. */
static double angle_between(const double u[3], const double v[3])
{
    double c[3], cr, dt;
    c[0] = u[1] * v[2] - u[2] * v[1];
    c[1] = u[2] * v[0] - u[0] * v[2];
    c[2] = u[0] * v[1] - u[1] * v[0];
    cr = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    dt = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    return atan2(cr, dt);
}

/* Image-plane axes of the observer at infinity at (theta, phi), roll = 0
 * (DESIGN.md: right = +phi, up = -theta), as Cartesian unit vectors. */
static void image_axes(double th, double ph, double n0[3], double right[3], double up[3])
{
    unit_vec(th, ph, n0);
    right[0] = -sin(ph);
    right[1] = cos(ph);
    right[2] = 0.0;
    up[0] = -cos(th) * cos(ph);
    up[1] = -cos(th) * sin(ph);
    up[2] = sin(th);
}

/* ---- 1. the right-hand side against the BL equations -------------------- */

/* A random null BL state: a photon in the ZAMO frame at (r, th) with random
 * direction (n_r, n_th, n_ph) and energy; the backward tangent is
 * u = -scale (e_t + n^i e_i), so E = u_t = scale (alpha - n_ph g_tph /
 * sqrt(g_phph)), L = u_phi = -scale n_ph sqrt(g_phph). */
static void random_null_state(uint64_t *s, int kind, cr_geo *g, double *yb)
{
    cr_metric_point p;
    double a, q, rp, r, th, nr, nth, nph, len, scale, alpha;
    switch (kind % 4) {
    case 0: /* extreme Kerr */
        a = 1.0;
        q = 0.0;
        break;
    case 1: /* Kerr-Newman up to the extreme */
        a = cr_test_rand(s);
        q = sqrt(1.0 - a * a) * cr_test_rand(s);
        break;
    case 2: /* Reissner-Nordstrom */
        a = 0.0;
        q = cr_test_rand(s);
        break;
    default:
        a = cr_test_rand(s);
        q = 0.0;
    }
    g->mt.m = 1.0;
    g->mt.a = a;
    g->mt.q = q;
    rp = cr_metric_r_plus(&g->mt);
    r = rp + pow(10.0, -3.0 + 7.0 * cr_test_rand(s));
    switch ((kind / 4) % 3) {
    case 0:
        th = pow(10.0, -8.0 + 7.0 * cr_test_rand(s));
        break;
    case 1:
        th = CR_PI - pow(10.0, -8.0 + 7.0 * cr_test_rand(s));
        break;
    default:
        th = CR_PI * cr_test_rand(s);
    }
    do {
        nr = 2.0 * cr_test_rand(s) - 1.0;
        nth = 2.0 * cr_test_rand(s) - 1.0;
        nph = 2.0 * cr_test_rand(s) - 1.0;
        len = sqrt(nr * nr + nth * nth + nph * nph);
    } while (len > 1.0 || len < 1e-3);
    nr /= len;
    nth /= len;
    nph /= len;
    scale = 0.5 + 1.5 * cr_test_rand(s);
    cr_metric_eval(&g->mt, r, th, &p);
    alpha = sqrt(p.sigma * p.delta / p.A_);
    g->E = scale * (alpha - nph * p.g_tph / sqrt(p.g_phph));
    g->L = -scale * nph * sqrt(p.g_phph);
    g->th_floor = 0.0;
    yb[CR_Y_T] = 0.0;
    yb[CR_Y_R] = r;
    yb[CR_Y_TH] = th;
    yb[CR_Y_PH] = 2.0 * CR_PI * cr_test_rand(s);
    yb[CR_Y_UR] = -scale * nr / sqrt(p.g_rr);
    yb[CR_Y_UTH] = -scale * nth / sqrt(p.sigma);
}

static double rel_err(double x, double y, double scale)
{
    return fabs(x - y) / fmax(scale, fmax(fabs(x), fabs(y)));
}

static void test_rhs_matches_bl(void **state)
{
    const int n = 4000;
    const char *names[6] = {"monitor", "dr/dtau", "dth/dtau", "dph/dtau", "d2r/dtau2",
                            "d2th/dtau2"};
    const double tols[6] = {1e-12, 1e-12, 1e-12, 1e-12, 1e-12, 1e-12};
    double worst[6] = {0.0};
    double where[6][3] = {{0.0}};
    uint64_t s = 20240611;
    int i, k, bad = 0;
    (void)state;
    for (i = 0; i < n; i++) {
        cr_geo g;
        cr_mino c;
        cr_metric_point p;
        double yb[CR_NY], dyb[CR_NY], u[4], y[CR_MN], dy[CR_MN], e[6];
        double r, th, a, sig, ct, st, dsig, P, del, aEL;
        double w, w1, w2, x, yy, z, x1, y1, z1, x2, y2, z2, sx, s1, s2, Lz, N, D, N1, D1;
        double mr1, mth1, mph1, mr2, mth2, br2, bth2, sc, kap;
        random_null_state(&s, i, &g, yb);
        r = yb[CR_Y_R];
        th = yb[CR_Y_TH];
        a = g.mt.a;
        cr_geo_rhs_full(&g, yb, dyb, u, &p);
        cr_mino_from_bl(&g, yb, 1.0 / (cr_metric_r_plus(&g.mt) + 1e-9), &c, y);
        cr_mino_rhs(&c, y, dy);
        sig = p.sigma;
        ct = p.cos_th;
        st = p.sin_th;
        del = p.delta;
        aEL = a * g.E + g.L;
        P = g.E * (r * r + a * a) + a * g.L;

        /* the BL state is null: the first integrals hold at the start */
        e[0] = cr_mino_monitor(&c, y);

        /* dr/dtau = -w'/w^2 */
        w = y[CR_M_W];
        w1 = dy[CR_M_W];
        w2 = dy[CR_M_DW];
        mr1 = -w1 / (w * w);
        sc = sqrt(P * P + fabs(del) * (fabs(c.eta) + aEL * aEL));
        e[1] = rel_err(mr1, sig * u[1], sc);

        /* theta = atan2(s, z), s = sqrt(x^2 + y^2) */
        x = y[CR_M_NX];
        yy = y[CR_M_NY];
        z = y[CR_M_NZ];
        x1 = dy[CR_M_NX];
        y1 = dy[CR_M_NY];
        z1 = dy[CR_M_NZ];
        x2 = dy[CR_M_DNX];
        y2 = dy[CR_M_DNY];
        z2 = dy[CR_M_DNZ];
        sx = sqrt(x * x + yy * yy);
        Lz = x * y1 - yy * x1;
        s1 = (x * x1 + yy * y1) / sx;
        s2 = (Lz * Lz / (sx * sx) + x * x2 + yy * y2) / sx;
        N = z * s1 - sx * z1;
        D = sx * sx + z * z;
        mth1 = N / D;
        e[2] = rel_err(mth1, sig * u[2], c.omega);

        /* phi = atan2(n_y, n_x) + pr */
        mph1 = Lz / (sx * sx) + dy[CR_M_PR];
        sc = fabs(g.L) / (st * st) + fabs(a * g.E) + fabs(a * P / del);
        e[3] = rel_err(mph1, sig * u[3], sc);

        /* d^2r/dtau^2 = -w''/w^2 + 2 w'^2/w^3 against
         * Sigma d(Sigma u^r)/dlambda = Sigma (Sigma' u^r + Sigma du^r/dlambda) */
        dsig = 2.0 * r * u[1] - 2.0 * a * a * ct * st * u[2];
        mr2 = -w2 / (w * w) + 2.0 * w1 * w1 / (w * w * w);
        br2 = sig * (dsig * u[1] + sig * dyb[CR_Y_UR]);
        sc = fabs(sig * dsig * u[1]) + fabs(sig * sig * dyb[CR_Y_UR]) + fabs(w2 / (w * w)) +
             2.0 * w1 * w1 / (w * w * w);
        e[4] = rel_err(mr2, br2, sc);

        /* d^2theta/dtau^2 = (N' D - N D') / D^2 */
        N1 = z * s2 - sx * z2;
        D1 = 2.0 * (sx * s1 + z * z1);
        mth2 = (N1 * D - N * D1) / (D * D);
        bth2 = sig * (dsig * u[2] + sig * dyb[CR_Y_UTH]);
        sc = fabs(sig * dsig * u[2]) + fabs(sig * sig * dyb[CR_Y_UTH]) + c.omega * c.omega;
        e[5] = rel_err(mth2, bth2, sc);

        /* near the horizon both sides are sums of terms ~ 1/Delta that
         * cancel: rounding grows like kap = 1 + (r^2 + a^2)/Delta (up to
         * ~1e6 at r - r+ = 1e-3 of an extreme hole), so errors are
         * measured in units of kap */
        kap = 1.0 + (r * r + a * a) / del;
        for (k = 1; k < 6; k++)
            e[k] /= kap;
        for (k = 0; k < 6; k++) {
            if (!(e[k] <= worst[k])) {
                worst[k] = e[k];
                where[k][0] = r - cr_metric_r_plus(&g.mt);
                where[k][1] = fmin(th, CR_PI - th);
                where[k][2] = sqrt(a * a + g.mt.q * g.mt.q);
            }
            if (!(e[k] <= tols[k]) && bad++ < 10)
                print_message("MISMATCH %s: a=%.17g Q=%.17g r=%.17g th=%.17g ur=%.17g "
                              "uth=%.17g E=%.17g L=%.17g: error %.3g\n",
                              names[k], a, g.mt.q, r, th, yb[CR_Y_UR], yb[CR_Y_UTH], g.E, g.L,
                              e[k]);
        }
    }
    for (k = 0; k < 6; k++)
        print_message("%-10s worst %.3g (tol %.0e) at r - r+ = %.3g, "
                      "angle to axis %.3g, sqrt(a^2+Q^2) = %.3g\n",
                      names[k], worst[k], tols[k], where[k][0], where[k][1], where[k][2]);
    for (k = 0; k < 6; k++)
        assert_true(worst[k] <= tols[k]);
}

/* ---- 2. error control ---------------------------------------------------- */

/* A random ray towards the hole (impact parameter up to ~12 M) of a random
 * Kerr-Newman hole, seen by a static observer at r_o or (r_o = INFINITY) the
 * observer at infinity. */
static void random_ray(uint64_t *s, double r_o, double tol, cr_frame *f, cr_ray *ray)
{
    double a = cr_test_rand(s), q = 0.8 * sqrt(1.0 - a * a) * cr_test_rand(s);
    double th = 0.05 + (CR_PI - 0.1) * cr_test_rand(s);
    double x = 2.0 * cr_test_rand(s) - 1.0, z = 2.0 * cr_test_rand(s) - 1.0;
    make_frame(f, a, q, r_o, th, tol, 1);
    if (isinf(r_o)) {
        ray_from_infinity(f, 12.0 * x, 12.0 * z, ray);
    } else {
        double n[3], y[CR_NY], len;
        cr_geo g;
        n[0] = -1.0;
        n[1] = 12.0 / r_o * z;
        n[2] = 12.0 / r_o * x;
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        n[0] /= len;
        n[1] /= len;
        n[2] /= len;
        cr_camera_ray(f, n, &g, y);
        cr_ray_from_bl(f, &g, y, ray);
    }
}

static void test_monitor_follows_tolerance(void **state)
{
    const double tols[3] = {1e-6, 1e-8, 1e-10};
    const double obs_r[3] = {20.0, 1000.0, INFINITY};
    const double bound = 5.0;
    int it, io, k;
    (void)state;
    for (it = 0; it < 3; it++) {
        uint64_t s = 4242;
        double worst = 0.0;
        long steps = 0;
        int counts[CR_OUT_COUNT_] = {0};
        for (io = 0; io < 3; io++)
            for (k = 0; k < 200; k++) {
                cr_frame f;
                cr_ray ray;
                walk wk;
                random_ray(&s, obs_r[io], tols[it], &f, &ray);
                walk_ray(&f, &ray, &wk);
                counts[wk.outcome]++;
                steps += wk.steps;
                if (!(wk.max_mon <= worst))
                    worst = wk.max_mon;
            }
        print_message("tol %.0e: 600 rays (%d horizon, %d sky, %d limit, %d error), %.1f steps "
                      "per ray, worst monitor %.3g = %.1f tol (bound %.0f tol)\n",
                      tols[it], counts[CR_OUT_HORIZON], counts[CR_OUT_SKY], counts[CR_OUT_LIMIT],
                      counts[CR_OUT_ERROR], (double)steps / 600.0, worst, worst / tols[it], bound);
        assert_int_equal(counts[CR_OUT_ERROR], 0);
        assert_true(counts[CR_OUT_HORIZON] > 50 && counts[CR_OUT_SKY] > 50);
        assert_true(worst <= bound * tols[it]);
    }
}

/* Sky direction (unit vector) where a ray that ended as sky points. */
static void sky_vec(const cr_ray *ray, double v[3])
{
    double th, ph;
    cr_mino_sky_direction(&ray->c, ray->m, &th, &ph);
    unit_vec(th, ph, v);
}

static void test_global_error_follows_tolerance(void **state)
{
    const double tols[3] = {1e-6, 1e-8, 1e-10};
    const int n = 40;
    double err_s[3] = {0.0}, err_k[3] = {0.0};
    int it, k;
    (void)state;
    for (it = 0; it < 3; it++) {
        uint64_t s = 99;
        for (k = 0; k < n; k++) {
            /* Schwarzschild, observer at infinity: the ray sweeps the angle
             * 2 F(0) (Darwin) in the plane of n0 and the impact vector */
            double th_o = CR_PI * cr_test_rand(&s), ph_o = CR_TWO_PI * cr_test_rand(&s);
            double chi = CR_TWO_PI * cr_test_rand(&s), rr = cr_test_rand(&s);
            double b = sqrt(27.0) + 0.05 + 25.0 * rr * rr;
            double n0[3], rt[3], up[3], t[3], v[3], ex[3], phi;
            cr_frame f;
            cr_ray ray;
            walk wk;
            darwin d;
            int i;
            make_frame(&f, 0.0, 0.0, INFINITY, th_o, tols[it], 1);
            f.observer.phi = ph_o;
            cr_frame_prepare(&f);
            ray_from_infinity(&f, b * cos(chi), b * sin(chi), &ray);
            walk_ray(&f, &ray, &wk);
            assert_int_equal(wk.outcome, CR_OUT_SKY);
            image_axes(th_o, ph_o, n0, rt, up);
            darwin_init(&d, b);
            phi = 2.0 * darwin_F(&d, 0.0);
            for (i = 0; i < 3; i++) {
                t[i] = cos(chi) * rt[i] + sin(chi) * up[i];
                ex[i] = cos(phi) * n0[i] + sin(phi) * t[i];
            }
            sky_vec(&ray, v);
            err_s[it] = fmax(err_s[it], angle_between(v, ex));
        }
        for (k = 0; k < n; k++) {
            /* Kerr-Newman, observer at infinity: against tol = 1e-13 */
            double a = cr_test_rand(&s), q = 0.8 * sqrt(1.0 - a * a) * cr_test_rand(&s);
            double th_o = 0.05 + (CR_PI - 0.1) * cr_test_rand(&s);
            double chi = CR_TWO_PI * cr_test_rand(&s), b = 8.0 + 20.0 * cr_test_rand(&s);
            double v[3], vr[3];
            cr_frame f;
            cr_ray ray;
            walk wk;
            make_frame(&f, a, q, INFINITY, th_o, 1e-13, 1);
            ray_from_infinity(&f, b * cos(chi), b * sin(chi), &ray);
            walk_ray(&f, &ray, &wk);
            assert_int_equal(wk.outcome, CR_OUT_SKY);
            sky_vec(&ray, vr);
            f.tolerance = tols[it];
            ray_from_infinity(&f, b * cos(chi), b * sin(chi), &ray);
            walk_ray(&f, &ray, &wk);
            assert_int_equal(wk.outcome, CR_OUT_SKY);
            sky_vec(&ray, v);
            err_k[it] = fmax(err_k[it], angle_between(v, vr));
        }
        print_message("tol %.0e: worst sky-direction error, Schwarzschild vs Darwin %.3g rad, "
                      "Kerr-Newman vs tol 1e-13 %.3g rad\n",
                      tols[it], err_s[it], err_k[it]);
    }
    for (it = 0; it < 2; it++) {
        double rs = err_s[it] / err_s[it + 1], rk = err_k[it] / err_k[it + 1];
        print_message("tol %.0e -> %.0e: error ratio %.1f (Schwarzschild), %.1f (Kerr-Newman); "
                      "accepted [20, 500]\n",
                      tols[it], tols[it + 1], rs, rk);
        assert_true(rs >= 20.0 && rs <= 500.0);
        assert_true(rk >= 20.0 && rk <= 500.0);
    }
    /* and the error is of the order of the tolerance */
    for (it = 0; it < 3; it++)
        assert_true(err_s[it] < 100.0 * tols[it] && err_k[it] < 100.0 * tols[it]);
}

/* Mid-step error of the dense output against the exact solution (n of a
 * Schwarzschild ray is a harmonic oscillator: n'' = -(eta + L^2) n) or,
 * for w (and every component under Kerr-Newman), against 400 substeps. */
static void test_dense_output(void **state)
{
    const double spins[2][2] = {{0.0, 0.0}, {0.9, 0.3}};
    int is, j, i;
    (void)state;
    for (is = 0; is < 2; is++) {
        cr_frame f;
        cr_geo g;
        cr_mino c;
        double n[3] = {-0.6, 0.5, 0.62}, yb[CR_NY], y0[CR_MN], err[4], len, h0, sc[CR_MN];
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (i = 0; i < 3; i++)
            n[i] /= len;
        make_frame(&f, spins[is][0], spins[is][1], 8.0, 1.1, 1e-8, 0);
        cr_camera_ray(&f, n, &g, yb);
        cr_mino_from_bl(&g, yb, f.w_stop, &c, y0);
        for (i = 0; i < CR_MN; i++)
            sc[i] = 1.0;
        sc[CR_M_W] = y0[CR_M_W];
        sc[CR_M_DW] = fabs(c.E);
        sc[CR_M_DNX] = sc[CR_M_DNY] = sc[CR_M_DNZ] = c.omega;
        h0 = 0.4 / c.omega;
        for (j = 0; j < 4; j++) {
            double h = h0 / (1 << j), y1[CR_MN], ys[CR_MN], ref[CR_MN], tmp[CR_MN];
            cr_dp5 st, sub;
            int k;
            cr_mino_rhs(&c, y0, st.k[0]);
            cr_dp5_try(&c, 1.0, h, y0, &st, y1);
            /* the ends */
            cr_dp5_dense(&st, y0, y1, h, 0.0, ys);
            for (i = 0; i < CR_MN; i++)
                assert_true(ys[i] == y0[i]);
            cr_dp5_dense(&st, y0, y1, h, 1.0, ys);
            for (i = 0; i < CR_MN; i++)
                assert_true(fabs(ys[i] - y1[i]) <= 2.3e-16 * (fabs(y0[i]) + fabs(y1[i])));
            /* the middle */
            cr_dp5_dense(&st, y0, y1, h, 0.5, ys);
            memcpy(ref, y0, sizeof ref);
            for (k = 0; k < 400; k++) {
                cr_mino_rhs(&c, ref, sub.k[0]);
                cr_dp5_try(&c, 1.0, 0.5 * h / 400.0, ref, &sub, tmp);
                memcpy(ref, tmp, sizeof ref);
            }
            if (spins[is][0] == 0.0) {
                double om = sqrt(c.kap), cs = cos(0.5 * h * om), sn = sin(0.5 * h * om);
                for (i = 0; i < 3; i++) {
                    ref[CR_M_NX + i] = cs * y0[CR_M_NX + i] + sn / om * y0[CR_M_DNX + i];
                    ref[CR_M_DNX + i] = cs * y0[CR_M_DNX + i] - sn * om * y0[CR_M_NX + i];
                }
                assert_true(ref[CR_M_PR] == 0.0);
            }
            err[j] = 0.0;
            for (i = 0; i < CR_MN; i++)
                err[j] = fmax(err[j], fabs(ys[i] - ref[i]) / sc[i]);
        }
        for (j = 0; j < 3; j++) {
            double ratio = err[j] / err[j + 1];
            print_message("a=%g Q=%g: dense output at mid-step, h omega = %.3f: error %.3e, "
                          "ratio to h/2 %.2f (accepted [24, 40])\n",
                          spins[is][0], spins[is][1], h0 * c.omega / (1 << j), err[j], ratio);
            assert_true(ratio >= 24.0 && ratio <= 40.0);
        }
    }
}

/* ---- 3. Darwin's exact deflection ---------------------------------------- */

static void test_darwin_functions(void **state)
{
    /* Carlson (1995), section 3: R_F(1, 2, 0) and R_F(2, 3, 4) */
    const double bs[4] = {5.2, 5.5, 8.0, 100.0};
    double worst = 0.0;
    int i;
    (void)state;
    assert_true(fabs(carlson_rf(1.0, 2.0, 0.0) - 1.3110287771461) < 1e-13);
    assert_true(fabs(carlson_rf(2.0, 3.0, 4.0) - 0.58408284167715) < 1e-13);
    for (i = 0; i < 4; i++) {
        darwin d;
        double y;
        darwin_init(&d, bs[i]);
        assert_true(d.u1 < 0.0 && 0.0 < d.u2 && d.u2 < d.u3);
        assert_true(fabs(darwin_G(&d, d.u2)) < 1e-15);
        for (y = 0.0; y < d.u2; y += 0.3 * d.u2) {
            double e = fabs(darwin_F(&d, y) - darwin_F_quad(&d, y));
            worst = fmax(worst, e);
        }
    }
    /* weak field: deflection 2F(0) - pi = 4/b + 15 pi/(4 b^2) + 128/(3 b^3) + O(b^-4) */
    {
        darwin d;
        double b = 1e4, defl;
        darwin_init(&d, b);
        defl = 2.0 * darwin_F(&d, 0.0) - CR_PI;
        defl -= 4.0 / b + 3.75 * CR_PI / (b * b) + 128.0 / (3.0 * b * b * b);
        print_message("b = 1e4: deflection minus its weak-field series %.3g (tol 1e-12)\n",
                      defl);
        assert_true(fabs(defl) < 1e-12);
    }
    print_message("F by Carlson's R_F vs quadrature: worst difference %.3g (tol 1e-12)\n", worst);
    assert_true(worst < 1e-12);
}

/* Radii of the first two equatorial crossings of the Schwarzschild ray that
 * starts at u0 = 1/r0 moving inward from the position direction n0 towards
 * the unit tangential direction t, with impact parameter b (0 where the ray
 * escapes first). The orbit lies in the plane of n0 and t: the position
 * direction at orbital angle psi is cos(psi) n0 + sin(psi) t. */
static void darwin_crossings(double b, double u0, const double n0[3], const double t[3],
                             double r_pred[2])
{
    darwin d;
    double psi = fmod(atan2(t[2], n0[2]) + 0.5 * CR_PI, CR_PI);
    int k;
    if (psi <= 0.0)
        psi += CR_PI;
    darwin_init(&d, b);
    for (k = 0; k < 2; k++) {
        double u = darwin_u_at(&d, u0, psi + k * CR_PI);
        r_pred[k] = u > 0.0 ? 1.0 / u : 0.0;
    }
}

/* Outcome and face of the frame's ray for (alpha, beta) (observer at
 * infinity) or BL state y, g, with a disc [r_in, r_out]. */
static cr_pixel trace_with_disc(cr_frame *f, double r_in, double r_out, const double *ab,
                                const cr_geo *g, const double *y)
{
    f->disc.enabled = 1;
    f->disc.r_in = r_in;
    f->disc.r_out = r_out;
    f->disc.n_radial = f->disc.n_sectors = 1;
    f->disc.color1.g = 255;
    f->disc.color2.r = 255;
    cr_frame_prepare(f);
    if (ab) {
        cr_ray ray;
        ray_from_infinity(f, ab[0], ab[1], &ray);
        return cr_trace_loop(f, &ray);
    }
    return cr_trace_ray(f, g, y);
}

typedef struct darwin_stats {
    double worst[2][2]; /* [tol 1e-8, 1e-10][direct, higher order] */
    int n[2], e2e;
    double worst_hit; /* cr_pixel.hit_r against Darwin, direct crossings */
} darwin_stats;

/* Check one ray of frame f (a = Q = 0) against the predicted crossings. */
static void darwin_check(const cr_frame *f0, const double *ab, const cr_geo *g, const double *y,
                         const double r_pred[2], int order, darwin_stats *ds)
{
    const double tol[2] = {1e-8, 1e-10}, bound[2] = {1e-7, 1e-9}, band = 1e-6;
    const double rp = r_pred[order];
    int it;
    for (it = 0; it < 2; it++) {
        cr_frame f = *f0;
        cr_ray ray;
        walk wk;
        double e;
        f.tolerance = tol[it];
        f.disc.enabled = 0;
        cr_frame_prepare(&f);
        if (ab)
            ray_from_infinity(&f, ab[0], ab[1], &ray);
        else
            cr_ray_from_bl(&f, g, y, &ray);
        walk_ray(&f, &ray, &wk);
        assert_true(wk.n_cross > order);
        assert_int_equal(wk.side[order], order); /* from above first, then from below */
        e = fabs(wk.r_cross[order] - rp) / rp;
        if (!(e <= bound[it]))
            print_message("MISMATCH order %d, tol %.0e: r traced %.15g, Darwin %.15g, "
                          "rel. error %.3g\n",
                          order, tol[it], wk.r_cross[order], rp, e);
        ds->worst[it][order] = fmax(ds->worst[it][order], e);
        assert_true(e <= bound[it]);
    }
    ds->n[order]++;
    /* the trace loop itself, at the default tolerance: hits the annulus
     * r_pred (1 +- band) on the right face, and misses those beside it */
    if (order == 1 && fabs(r_pred[0] - rp) < 4.0 * band * rp)
        return;
    {
        cr_frame f = *f0;
        cr_pixel px;
        f.tolerance = cr_trace_defaults().tolerance;
        px = trace_with_disc(&f, rp * (1.0 - band), rp * (1.0 + band), ab, g, y);
        assert_int_equal(px.outcome, CR_OUT_DISC);
        assert_int_equal(px.object, order);
        assert_true(px.hit_r >= rp * (1.0 - band) && px.hit_r <= rp * (1.0 + band));
        assert_true(px.hit_phi >= 0.0 && px.hit_phi < CR_TWO_PI);
        if (order == 0) {
            /* a wide disc: cr_pixel's hit radius is Darwin's r of the first
             * crossing (bound 1e-7 relative at the default tolerance) */
            double e;
            px = trace_with_disc(&f, 0.5 * rp, 2.0 * rp, ab, g, y);
            assert_int_equal(px.outcome, CR_OUT_DISC);
            e = fabs(px.hit_r - rp) / rp;
            ds->worst_hit = fmax(ds->worst_hit, e);
            if (!(e <= 1e-7))
                print_message("hit_r %.15g, Darwin %.15g, rel. error %.3g\n", px.hit_r, rp, e);
            assert_true(e <= 1e-7);
        }
        px = trace_with_disc(&f, rp * (1.0 + band), rp * (1.0 + 3.0 * band), ab, g, y);
        assert_true(px.outcome != CR_OUT_DISC);
        px = trace_with_disc(&f, rp * (1.0 - 3.0 * band), rp * (1.0 - band), ab, g, y);
        assert_true(px.outcome != CR_OUT_DISC);
        ds->e2e++;
    }
}

static void test_darwin_disc_radius(void **state)
{
    const double incl[3] = {0.0, 40.0, 80.0};
    const double b_c = sqrt(27.0);
    darwin_stats ds;
    uint64_t s = 314159;
    int ii, k, order;
    (void)state;
    memset(&ds, 0, sizeof ds);
    /* the observer at infinity */
    for (ii = 0; ii < 3; ii++) {
        double th_o = incl[ii] * CR_PI / 180.0, ph_o = 0.3;
        double n0[3], rt[3], up[3];
        cr_frame f;
        make_frame(&f, 0.0, 0.0, INFINITY, th_o, cr_trace_defaults().tolerance, 1);
        f.observer.phi = ph_o;
        cr_frame_prepare(&f);
        image_axes(th_o, ph_o, n0, rt, up);
        for (order = 0; order < 2; order++)
            for (k = 0; k < 8; k++) {
                double chi = CR_TWO_PI * cr_test_rand(&s), t[3], ab[2], r_pred[2], b;
                int i;
                b = order == 0 ? b_c + 0.3 + 20.0 * cr_test_rand(&s)
                               : b_c + pow(10.0, -3.0 + 2.0 * cr_test_rand(&s));
                for (i = 0; i < 3; i++)
                    t[i] = cos(chi) * rt[i] + sin(chi) * up[i];
                darwin_crossings(b, 0.0, n0, t, r_pred);
                if (!(r_pred[order] > 0.0 && r_pred[order] < 1e3)) {
                    k--; /* this one escapes first, or crosses too far out: draw again */
                    continue;
                }
                ab[0] = b * cos(chi);
                ab[1] = b * sin(chi);
                darwin_check(&f, ab, NULL, NULL, r_pred, order, &ds);
            }
    }
    /* a static observer at r_o = 1e4, inclination 60 deg: the ray leaving at
     * angle psi from the inward direction has b = r_o sin(psi)/sqrt(1 - 2/r_o) */
    {
        const double r_o = 1e4, th_o = CR_PI / 3.0, ph_o = 0.0;
        double n0[3], et[3], ep[3];
        cr_frame f;
        make_frame(&f, 0.0, 0.0, r_o, th_o, cr_trace_defaults().tolerance, 1);
        unit_vec(th_o, ph_o, n0);
        et[0] = cos(th_o) * cos(ph_o);
        et[1] = cos(th_o) * sin(ph_o);
        et[2] = -sin(th_o);
        ep[0] = -sin(ph_o);
        ep[1] = cos(ph_o);
        ep[2] = 0.0;
        for (order = 0; order < 2; order++)
            for (k = 0; k < 8; k++) {
                double chi = CR_TWO_PI * cr_test_rand(&s), t[3], nl[3], r_pred[2], b, sp, y[CR_NY];
                cr_geo g;
                int i;
                b = order == 0 ? b_c + 0.3 + 20.0 * cr_test_rand(&s)
                               : b_c + pow(10.0, -3.0 + 2.0 * cr_test_rand(&s));
                sp = b * sqrt(1.0 - 2.0 / r_o) / r_o;
                nl[0] = -sqrt(1.0 - sp * sp);
                nl[1] = sp * cos(chi);
                nl[2] = sp * sin(chi);
                for (i = 0; i < 3; i++)
                    t[i] = cos(chi) * et[i] + sin(chi) * ep[i];
                darwin_crossings(b, 1.0 / r_o, n0, t, r_pred);
                if (!(r_pred[order] > 0.0 && r_pred[order] < 1e3)) {
                    k--;
                    continue;
                }
                cr_camera_ray(&f, nl, &g, y);
                darwin_check(&f, NULL, &g, y, r_pred, order, &ds);
            }
    }
    print_message("%d direct and %d higher-order crossings vs Darwin: worst rel. error in r "
                  "%.3g / %.3g at tol 1e-8 (bound 1e-7), %.3g / %.3g at tol 1e-10 (bound 1e-9); "
                  "%d rays traced by cr_trace_loop hit r (1 +- 1e-6) on the right face and "
                  "missed the annuli beside it; their hit_r vs Darwin on a wide disc: worst "
                  "rel. error %.3g (bound 1e-7)\n",
                  ds.n[0], ds.n[1], ds.worst[0][0], ds.worst[0][1], ds.worst[1][0],
                  ds.worst[1][1], ds.e2e, ds.worst_hit);
}

/* ---- 4. the shadow seen from infinity ------------------------------------ */

/* The step-size controller's contract (mino_lane.h): the factor is
 * 0.9 err^(-1/4) clamped to [0.2, 5], and a try whose error estimate is not
 * a number (a stage that left the domain, e.g. inside the horizon's 1/D) is
 * rejected and retried 0.2 times as long, never continued with a NaN step. */
static void test_step_controller(void **state)
{
    double h, h_next;
    (void)state;
    assert_true(fabs(cr_dp5_factor(1.0) - 0.9) <= 1e-15);
    assert_true(fabs(cr_dp5_factor(0.01) - 0.9 / sqrt(0.1)) <= 1e-14);
    assert_true(cr_dp5_factor(1e-12) == 5.0);
    assert_true(cr_dp5_factor(1e6) == 0.2);
    assert_true(cr_dp5_factor(NAN) == 0.2);
    h = 0.5;
    h_next = 7.0;
    assert_false(cr_dp5_control(NAN, 0, &h, &h_next));
    assert_true(fabs(h - 0.1) <= 1e-15);
    assert_true(h_next == 7.0);
    h = 0.5;
    assert_true(cr_dp5_control(0.01, 1, &h, &h_next)); /* accepted after a retry: not grown */
    assert_true(h == 0.5 && h_next == 0.5);
}

static void test_shadow_from_infinity(void **state)
{
    const double qs[2] = {0.0, 0.6}, incl[3] = {0.0, 45.0, 90.0};
    const double chis[5] = {0.0, 1.0, 2.2, 3.5, 4.9};
    double worst = 0.0;
    int iq, ii, ic;
    (void)state;
    for (iq = 0; iq < 2; iq++) {
        double q = qs[iq], rph = 0.5 * (3.0 + sqrt(9.0 - 8.0 * q * q));
        double bc = rph * rph / sqrt(rph * rph - 2.0 * rph + q * q);
        for (ii = 0; ii < 3; ii++) {
            cr_frame f;
            double lo_all = 1e9, hi_all = 0.0;
            make_frame(&f, 0.0, q, INFINITY, incl[ii] * CR_PI / 180.0, cr_trace_defaults().tolerance, 0);
            for (ic = 0; ic < 5; ic++) {
                double lo = bc - 0.1, hi = bc + 0.1, edge;
                int it;
                for (it = 0; it < 40; it++) {
                    double mid = 0.5 * (lo + hi);
                    cr_ray ray;
                    cr_pixel px;
                    ray_from_infinity(&f, mid * cos(chis[ic]), mid * sin(chis[ic]), &ray);
                    px = cr_trace_loop(&f, &ray);
                    assert_true(px.outcome == CR_OUT_HORIZON || px.outcome == CR_OUT_SKY ||
                                px.outcome == CR_OUT_LIMIT);
                    if (it == 0)
                        assert_true(px.outcome != CR_OUT_LIMIT);
                    if (px.outcome == CR_OUT_LIMIT)
                        break; /* orbiting: as close as the integration resolves */
                    if (px.outcome == CR_OUT_HORIZON)
                        lo = mid;
                    else
                        hi = mid;
                }
                edge = 0.5 * (lo + hi);
                lo_all = fmin(lo_all, edge);
                hi_all = fmax(hi_all, edge);
                worst = fmax(worst, fabs(edge - bc));
            }
            print_message("Q=%g, inclination %2.0f deg: shadow radius %.10f .. %.10f over 5 "
                          "directions, b_c = %.10f\n",
                          q, incl[ii], lo_all, hi_all, bc);
            assert_true(hi_all - lo_all < 1e-8); /* a circle */
        }
    }
    print_message("worst |edge - b_c| = %.3g M (tol 1e-7)\n", worst);
    assert_true(worst < 1e-7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rhs_matches_bl),
        cmocka_unit_test(test_monitor_follows_tolerance),
        cmocka_unit_test(test_global_error_follows_tolerance),
        cmocka_unit_test(test_dense_output),
        cmocka_unit_test(test_darwin_functions),
        cmocka_unit_test(test_darwin_disc_radius),
        cmocka_unit_test(test_shadow_from_infinity),
        cmocka_unit_test(test_step_controller),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
