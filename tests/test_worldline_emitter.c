/* Spheres on a particle's worldline (sphere.motion: particle; core/track.h,
 * core/sphere.h), seen with the light's travel time, against values
 * computed here independently:
 *
 * 1. Two code paths, one physics: a particle sphere on the circular
 *    prograde ISCO of a = 0.9 (particle.circular, its worldline integrated
 *    from t = -1500 M and tabulated) renders the same pixels as the
 *    motion: orbit sphere of the same place and phase (its closed-form rigid
 *    turn at Omega): outcome, object and colour identical, hit_r and the
 *    delay within 1e-7 M, g within 1e-7 relative; from r = 1000 M at 60 deg
 *    and from the observer at infinity, under mino, and under rk4 from
 *    r = 60 M. The worldline's phase error over 1500 M and the table's
 *    interpolation (h = 0.05 M: ~1e-10 M) are far below that. An inclined,
 *    eccentric particle sphere in units of M = 2 traces the same rays as in
 *    M = 1 (1e-9), and cr_cart_vel_to_bl inverts cr_bl_vel_to_cart.
 * 2. Radial infall from rest at r0 = 12 M (Schwarzschild, velocity
 *    [0, 0, 0] measured by the static observer, from t = 0), a sphere of
 *    R = 0.3 M on the line phi_f = 0.6 rad of the equator, seen from
 *    r_o = 40 M: for the pixel of the middle row whose ray (falling in)
 *    crosses that line nearest r = 6 M, the observer time t* at which it
 *    first sees the sphere is computed here from the cycloid t(eta) of the
 *    infall (MTW 31.10) and the ray by quadrature of dphi/dr, dt/dr: the
 *    smallest t_obs with min over the ray of |x(r) - c(t_obs - delay(r))|
 *    = R, by bisection. The renderer's switch from not-sphere to sphere,
 *    found by bisection on the frame's t_obs, must agree within 2e-5 M;
 *    at t* + 1 M hit_r within 1e-6 M, the delay within 1e-7 relative, and
 *    g within 1e-6 of g = 1 / (sqrt(f_o) u^t (1 - p_r dr/dt - L dphi/dt)),
 *    u of the translating sphere's matter at the hit point (the centre's
 *    dr/dt = -f sqrt(2/r - 2/r0) / sqrt(1 - 2/r0) carried rigidly). The
 *    sphere where it is at t_obs (no travel time) would switch the pixel
 *    tens of M earlier, and g differs from a static source's by > 1e-2:
 *    the checks can fail.
 * 2b. Flying out at 0.8 c from r = 6 M, seen from infinity on the axis
 *    ray: met just after its table starts and at r ~ 30 M (test_outgoing);
 *    and on the far side, seen through the lens at r ~ 30 M
 *    (test_outgoing_behind).
 * 3. An eccentric orbit (Schwarzschild, p = 10 M, e = 0.3, from periapsis,
 *    particle.constants), seen face-on from infinity (the flux then
 *    depends on r and dr/dt only): the light curve (the frame's flux,
 *    cr_lightcurve_compute, 160 x 160 pixels) at 12 phases t and at
 *    t + s T_r, T_r the radial period computed here by quadrature of
 *    dt/dchi over r = p / (1 + e cos chi) (Cutler, Kennefick & Poisson
 *    1994). The rms change over the phases, as a fraction of the curve's
 *    range, is at most 0.05 for s = 1 (the pixels' noise) and more than
 *    twice that for s = 0.96 and 1.04; the parabola through the three
 *    rms^2 puts the light curve's period within 1% of T_r (the Keplerian
 *    period and the azimuthal one are 34% and ~30% off).
 * 4. Bad input, refused naming file:line:col and the key: a speed >= c, a
 *    start inside the horizon, a non-finite q/m, no initial data, two kinds
 *    of it, dtau, the sphere's own r on a particle sphere, sphere.particle
 *    without motion: particle, motion: particle without sphere.particle, an
 *    animated metric, and a worldline longer than its table holds.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "input/scene.h"
#include "output/lightcurve.h"
#include "testutil.h"

static int load(const char *text, cr_scene *s, cr_err *e)
{
    return cr_scene_load_string(text, strlen(text), "wl.yml", s, e);
}

/* A scene loaded and frame 0 evaluated at w x h (integrator, default
 * tolerance), kept together so the frame may be traced at other t_obs. */
typedef struct loaded {
    cr_scene s;
    cr_frame_eval ev;
} loaded;

static void open_scene(loaded *l, const char *text, int w, int h, int integrator)
{
    cr_trace_settings ts = cr_trace_defaults();
    cr_err e;
    memset(l, 0, sizeof *l);
    ts.integrator = integrator;
    if (load(text, &l->s, &e) != 0)
        fail_msg("%s", e.msg);
    if (cr_frame_eval_at(&l->ev, &l->s, 0, 1, w, h, &ts, &e) != 0)
        fail_msg("%s", e.msg);
}

static void close_scene(loaded *l)
{
    cr_frame_eval_free(&l->ev);
    cr_scene_free(&l->s);
}

static cr_pixel *trace_all(const cr_frame *f)
{
    cr_pixel *px = malloc(sizeof *px * (size_t)(f->width * f->height));
    int i;
    for (i = 0; i < f->width * f->height; i++)
        px[i] = cr_trace_pixel(f, i % f->width, i / f->width);
    return px;
}

/* ---- 1. the circular orbit, two code paths --------------------------- */

static double isco_prograde(double a)
{
    double z1 = 1.0 + cbrt(1.0 - a * a) * (cbrt(1.0 + a) + cbrt(1.0 - a));
    double z2 = sqrt(3.0 * a * a + z1 * z1);
    return 3.0 + z2 - sqrt((3.0 - z1) * (3.0 + z1 + 2.0 * z2));
}

static void same_as_orbit(const char *observer, int integrator, int w, int h)
{
    const double a = 0.9, t0 = -1500.0, phase = 0.3; /* phase at t = 0, rad */
    double om = 1.0 / (pow(isco_prograde(a), 1.5) + a), worst_r = 0.0, worst_t = 0.0,
           worst_g = 0.0;
    char one[2048], two[2048];
    loaded A, B;
    cr_pixel *p, *q;
    int i, hits = 0;
    snprintf(one, sizeof one,
             "metric: {m: 1, a: %g, q: 0}\n%s"
             "sphere:\n  color: [255, 200, 80]\n  resolution: [6, 8]\n  r: isco\n"
             "  theta: 90\n  phi: %.17g rad\n  radius: 0.5\n  motion: orbit\n",
             a, observer, phase);
    snprintf(two, sizeof two,
             "metric: {m: 1, a: %g, q: 0}\n%s"
             "sphere:\n  color: [255, 200, 80]\n  resolution: [6, 8]\n  radius: 0.5\n"
             "  motion: particle\n  particle:\n    r: isco\n    theta: 90\n"
             "    phi: %.17g rad\n    t: %g\n    circular: prograde\n    tau: 1200\n",
             a, observer, phase + om * t0, t0);
    open_scene(&A, one, w, h, integrator);
    open_scene(&B, two, w, h, integrator);
    p = trace_all(&A.ev.frame);
    q = trace_all(&B.ev.frame);
    for (i = 0; i < w * h; i++) {
        assert_int_equal(p[i].outcome, q[i].outcome);
        assert_int_equal(p[i].object, q[i].object);
        assert_memory_equal(&p[i].color, &q[i].color, sizeof p[i].color);
        if (p[i].outcome != CR_OUT_SPHERE)
            continue;
        hits++;
        worst_r = fmax(worst_r, fabs(p[i].hit_r - q[i].hit_r));
        worst_t = fmax(worst_t, fabs(p[i].delay - q[i].delay));
        worst_g = fmax(worst_g, fabs(p[i].redshift - q[i].redshift) / p[i].redshift);
        assert_true(fabs(q[i].bolo - pow(q[i].redshift, 4.0)) <= 1e-14 * q[i].bolo);
    }
    print_message("circular ISCO, particle against orbit: %d sphere pixels; worst hit_r %.3g M, "
                  "delay %.3g M, g %.3g\n",
                  hits, worst_r, worst_t, worst_g);
    assert_true(hits >= 20);
    assert_true(worst_r <= 1e-7);
    assert_true(worst_t <= 1e-7);
    assert_true(worst_g <= 1e-7);
    free(p);
    free(q);
    close_scene(&A);
    close_scene(&B);
}

static void test_circular(void **state)
{
    (void)state;
    same_as_orbit("observer: {r: 1000, theta: 60, phi: 0, hfov: 0.5, t: 40}\n", CR_INTEG_MINO,
                  48, 40);
    same_as_orbit("observer: {r: inf, theta: 75, phi: 0, hextent: 9, t: 10}\n", CR_INTEG_MINO,
                  48, 40);
    same_as_orbit("observer: {r: 60, theta: 80, phi: 0, hfov: 6, t: 71}\n", CR_INTEG_RK4, 40, 30);
}

/* ---- 2. radial infall: when a pixel first sees the sphere ----------- */

#define IRO 40.0   /* static observer, phi = 0 */
#define IR0 12.0   /* the fall starts from rest here at t = 0 */
#define IPHF 0.6   /* on this line of the equator, rad */
#define IRAD 0.3   /* sphere radius */
#define INP 3700   /* panels of the tabulated ray, 0.01 M each, from IRO in */

/* The equatorial ray of impact parameter b < 3 sqrt 3 (it falls in: no
 * turning point) from the observer inward, tabulated: Phi[k] = phi swept
 * and Dl[k] = t_obs - t at r = IRO - k / 100 by 8-point Gauss-Legendre
 * panels of dphi/dr = b / (r^2 s), dt/dr = 1 / (f s), s = sqrt(1 - b^2 f /
 * r^2), f = 1 - 2/r. */
typedef struct inray {
    double b;
    double Phi[INP + 1], Dl[INP + 1];
} inray;

static void inray_panel(double b, double r_lo, double r_hi, double *dphi, double *dt)
{
    double h = r_hi - r_lo, sp = 0.0, st = 0.0;
    int j;
    for (j = 0; j < 8; j++) {
        double x, w, r, f, sq;
        cr_quad_gl8(j, &x, &w);
        r = r_lo + 0.5 * h * (x + 1.0);
        f = 1.0 - 2.0 / r;
        sq = sqrt(1.0 - b * b * f / (r * r));
        sp += w * b / (r * r * sq);
        st += w / (f * sq);
    }
    *dphi = 0.5 * h * sp;
    *dt = 0.5 * h * st;
}

static void inray_make(inray *q, double b)
{
    int k;
    q->b = b;
    q->Phi[0] = q->Dl[0] = 0.0;
    for (k = 0; k < INP; k++) {
        double dp, dt;
        inray_panel(b, IRO - (k + 1) * 0.01, IRO - k * 0.01, &dp, &dt);
        q->Phi[k + 1] = q->Phi[k] + dp;
        q->Dl[k + 1] = q->Dl[k] + dt;
    }
}

/* phi swept and the delay at r (3 <= r <= IRO). */
static void inray_at(const inray *q, double r, double *phi, double *delay)
{
    int k = (int)floor((IRO - r) * 100.0);
    double dp, dt, r_k;
    if (k >= INP)
        k = INP - 1;
    r_k = IRO - k * 0.01;
    inray_panel(q->b, r, r_k, &dp, &dt);
    *phi = q->Phi[k] + dp;
    *delay = q->Dl[k] + dt;
}

/* The infalling centre's r at BL time t >= 0, from the cycloid (MTW 31.10):
 * r = (r0/2)(1 + cos eta), t = 2 ln|(c + tan(eta/2)) / (c - tan(eta/2))|
 * + 2 c (eta + (r0/4)(eta + sin eta)), c = sqrt(r0/2 - 1), by bisection in
 * eta (t grows with eta). */
static double infall_r(double t)
{
    double c = sqrt(IR0 / 2.0 - 1.0), lo = 0.0, hi = 2.0 * atan(c);
    int i;
    for (i = 0; i < 200; i++) {
        double e = 0.5 * (lo + hi), th = tan(0.5 * e);
        double te = 2.0 * log((c + th) / (c - th)) + 2.0 * c * (e + 0.25 * IR0 * (e + sin(e)));
        if (te > t)
            hi = e;
        else
            lo = e;
    }
    return 0.5 * IR0 * (1.0 + cos(0.5 * (lo + hi)));
}

/* |x(r) - c(T - delay(r))| - R for the ray at r (sgn: its phi's sign), the
 * sphere where it was when the ray passed (travel = 1) or where it is at T
 * (0); +1 before the fall starts. */
static double inray_gap(const inray *q, int sgn, double r, double T, int travel, double *dl)
{
    double ph, rc, dx, dy;
    inray_at(q, r, &ph, dl);
    if (T - (travel ? *dl : 0.0) < 0.0)
        return 1.0;
    rc = infall_r(T - (travel ? *dl : 0.0));
    dx = r * cos(sgn * ph) - rc * cos(IPHF);
    dy = r * sin(sgn * ph) - rc * sin(IPHF);
    return sqrt(dx * dx + dy * dy) - IRAD;
}

/* The smallest gap over the ray's points 3.5 <= r <= IRO - 1 at T: a scan
 * 0.005 M apart, then golden section about its best point. */
static double inray_min_gap(const inray *q, int sgn, double T, int travel)
{
    double best = INFINITY, rb = 0.0, r, dl, lo, hi, x1, x2, f1, f2;
    const double g = 0.6180339887498949;
    int i;
    for (r = IRO - 1.0; r >= 3.5; r -= 0.005) {
        double v = inray_gap(q, sgn, r, T, travel, &dl);
        if (v < best) {
            best = v;
            rb = r;
        }
    }
    lo = rb - 0.005;
    hi = rb + 0.005;
    x1 = hi - g * (hi - lo);
    x2 = lo + g * (hi - lo);
    f1 = inray_gap(q, sgn, x1, T, travel, &dl);
    f2 = inray_gap(q, sgn, x2, T, travel, &dl);
    for (i = 0; i < 60; i++) {
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = inray_gap(q, sgn, x1, T, travel, &dl);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = inray_gap(q, sgn, x2, T, travel, &dl);
        }
    }
    return fmin(best, fmin(f1, f2));
}

/* The first T in [lo, hi] at which the min gap reaches 0 (it is positive at
 * lo and negative at hi), by bisection. */
static double first_contact(const inray *q, int sgn, double lo, double hi, int travel)
{
    int i;
    assert_true(inray_min_gap(q, sgn, lo, travel) > 0.0);
    assert_true(inray_min_gap(q, sgn, hi, travel) < 0.0);
    for (i = 0; i < 50; i++) {
        double mid = 0.5 * (lo + hi);
        if (inray_min_gap(q, sgn, mid, travel) < 0.0)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

static int sees_sphere(cr_frame *f, int i, int j, double T, cr_pixel *out)
{
    cr_pixel p;
    f->t_obs = T;
    p = cr_trace_pixel(f, i, j);
    if (out)
        *out = p;
    return p.outcome == CR_OUT_SPHERE;
}

static void test_infall(void **state)
{
    char text[1024];
    const int w = 161, h = 3, j = 1;
    double fo = 1.0 - 2.0 / IRO, best_rc = INFINITY, b = 0.0, T0 = 0.0, Tg, Tr, lo, hi;
    double Tnt, rh = 0.0, dlh = 0.0, dl, ph, rp, drdt, ut, dr, dph, pr, L, g, fh, gap;
    int i, pick = -1, sgn = 1, k;
    inray *q = malloc(sizeof *q);
    loaded A;
    cr_frame *f;
    cr_pixel p;
    (void)state;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: %g, theta: 90, phi: 0, hfov: 60, t: 0}\n"
             "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  radius: %g\n"
             "  motion: particle\n  particle:\n    r: %g\n    theta: 90\n"
             "    phi: %.17g rad\n    t: 0\n    velocity: [0, 0, 0]\n    tau: 200\n",
             IRO, IRAD, IR0, IPHF);
    open_scene(&A, text, w, h, CR_INTEG_MINO);
    f = &A.ev.frame;
    /* the pixel whose ray (falling in) crosses the line nearest r = 6 */
    for (i = 0; i < w; i++) {
        double n[3], bi, r;
        cr_camera_pixel_dir(f, i, j, n);
        assert_true(fabs(n[1]) < 1e-12);
        bi = IRO * fabs(n[2]) / sqrt(fo);
        if (n[2] <= 0.0 || bi >= 5.1)
            continue;
        inray_make(q, bi);
        for (r = IRO - 1.0; r > 3.5; r -= 0.01) {
            inray_at(q, r, &ph, &dl);
            if (ph >= IPHF) {
                if (fabs(r - 6.0) < fabs(best_rc - 6.0)) {
                    best_rc = r;
                    pick = i;
                    b = bi;
                }
                break;
            }
        }
    }
    assert_true(pick >= 0 && fabs(best_rc - 6.0) < 0.5);
    inray_make(q, b);
    /* a bracket of the first contact: the sphere reaches the crossing
     * (r_c) at about T0 + the delay there */
    inray_at(q, best_rc, &ph, &dl);
    for (T0 = 0.0; infall_r(T0) > best_rc; T0 += 0.1)
        ;
    lo = T0 + dl - 8.0;
    hi = T0 + dl;
    Tg = first_contact(q, sgn, lo, hi, 1);
    Tnt = first_contact(q, sgn, lo - dl, hi - dl, 0);
    /* the renderer: its switch from not-sphere to sphere */
    lo = Tg - 2.0;
    hi = Tg + 0.5;
    assert_false(sees_sphere(f, pick, j, lo, NULL));
    assert_true(sees_sphere(f, pick, j, hi, NULL));
    for (k = 0; k < 40; k++) {
        double mid = 0.5 * (lo + hi);
        if (sees_sphere(f, pick, j, mid, NULL))
            hi = mid;
        else
            lo = mid;
    }
    Tr = 0.5 * (lo + hi);
    /* just after: the hit, its delay and g */
    assert_true(sees_sphere(f, pick, j, Tg + 1.0, &p));
    for (rh = best_rc + 2.0; rh > best_rc - 2.0; rh -= 0.005)
        if (inray_gap(q, sgn, rh, Tg + 1.0, 1, &dl) < 0.0)
            break;
    {
        double a = rh, c = rh + 0.005;
        for (k = 0; k < 80; k++) {
            double mid = 0.5 * (a + c);
            if (inray_gap(q, sgn, mid, Tg + 1.0, 1, &dl) < 0.0)
                a = mid;
            else
                c = mid;
        }
        rh = 0.5 * (a + c);
        gap = inray_gap(q, sgn, rh, Tg + 1.0, 1, &dlh);
    }
    inray_at(q, rh, &ph, &dl);
    rp = infall_r(Tg + 1.0 - dlh);
    fh = 1.0 - 2.0 / rh;
    drdt = -(1.0 - 2.0 / rp) * sqrt(2.0 / rp - 2.0 / IR0) / sqrt(1.0 - 2.0 / IR0);
    /* the translation at the hit point, in BL rates (a = 0, equator) */
    dr = drdt * cos(sgn * ph - IPHF);
    dph = drdt * sin(IPHF - sgn * ph) / rh;
    ut = 1.0 / sqrt(fh - dr * dr / fh - rh * rh * dph * dph);
    L = -sgn * b;                                /* the photon's L / E, forward */
    pr = sqrt(1.0 - b * b * fh / (rh * rh)) / fh; /* outward at emission */
    g = 1.0 / (sqrt(fo) * ut * (1.0 - pr * dr - L * dph));
    print_message("infall: pixel %d (b = %.6f, crosses the line at r = %.2f): first sees the "
                  "sphere at t_obs = %.6f M (independent %.6f, without travel time %.3f); at "
                  "+1 M hit_r %.8f (%.8f), delay %.8f (%.8f), g %.8f (%.8f; static-source "
                  "g %.6f)\n",
                  pick, b, best_rc, Tr, Tg, Tnt, p.hit_r, rh, p.delay, dlh, p.redshift, g,
                  sqrt(fh / fo));
    assert_true(fabs(gap) < 1e-9);
    assert_true(fabs(Tr - Tg) <= 2e-5);
    assert_true(fabs(Tnt - Tg) > 10.0);
    assert_true(fabs(p.hit_r - rh) <= 1e-6);
    assert_true(fabs(p.delay - dlh) <= 1e-7 * dlh);
    assert_true(fabs(p.redshift - g) <= 1e-6 * g);
    assert_true(fabs(g - sqrt(fh / fo)) > 1e-2); /* the motion matters */
    free(q);
    close_scene(&A);
}

/* ---- 2b. flying out: a sphere far beyond where it started ------------ */

#define OR0 6.0  /* the particle starts here at t = 0, on the line phi = 0 */
#define OV 0.8   /* outward, measured by the static observer there */
#define ORAD 1.0 /* sphere radius */

/* E per unit mass of the outgoing particle and its t(r) - 0 from OR0 by
 * 8-point Gauss-Legendre panels (<= 0.05 M) of dt/dr = E / (f sqrt(E^2 -
 * f)), f = 1 - 2/r (a radial geodesic of Schwarzschild). */
static double out_energy(void)
{
    return sqrt(1.0 - 2.0 / OR0) / sqrt(1.0 - OV * OV);
}

static double out_t(double r)
{
    double E = out_energy(), t = 0.0, lo = OR0;
    int n = (int)ceil((r - OR0) / 0.05), k, j;
    for (k = 0; k < n; k++) {
        double hi = OR0 + (r - OR0) * (k + 1) / n, h = hi - lo;
        for (j = 0; j < 8; j++) {
            double x, w, rr, f;
            cr_quad_gl8(j, &x, &w);
            rr = lo + 0.5 * h * (x + 1.0);
            f = 1.0 - 2.0 / rr;
            t += 0.5 * h * w * E / (f * sqrt(E * E - f));
        }
        lo = hi;
    }
    return t;
}

/* The centre's r at BL time t >= 0 (t(r) grows with r; r - OR0 <= t). */
static double out_rc(double t)
{
    double lo = OR0, hi = OR0 + t + 1.0;
    int i;
    for (i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (out_t(mid) > t)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* The renormalised delay of the observer at infinity (cr_ray_delay) for the
 * radial ray out from r: t_o - t = r*(r_o) - r*(r), r* = r + 2 ln(r/2 - 1),
 * less r_o + 2 ln r_o as r_o -> infinity. */
static double out_delay(double r)
{
    return -2.0 * log(2.0) - r - 2.0 * log(0.5 * r - 1.0);
}

/* r - R - r_c(t) on the axis ray at r: the ray's point against the sphere's
 * near side at the ray's time there (travel) or at T; +1 before t = 0. */
static double out_gap(double r, double T, int travel)
{
    double t = travel ? T - out_delay(r) : T;
    return t < 0.0 ? 1.0 : r - ORAD - out_rc(t);
}

/* Where the axis ray, traced in from r_from (outside the sphere then),
 * first meets the sphere. */
static double out_hit(double T, int travel, double r_from)
{
    double r = r_from, lo, hi;
    int i;
    assert_true(out_gap(r, T, travel) > 0.0);
    while (r > OR0 && out_gap(r, T, travel) > 0.0)
        r -= 0.01;
    lo = r;
    hi = r + 0.01;
    for (i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (out_gap(mid, T, travel) > 0.0)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* A particle flying out from r = 6 M at 0.8 c (Schwarzschild, on the line
 * towards the observer at infinity), a sphere of R = 1 M: the middle pixel
 * of 3 x 3 (the axis ray) at two times, the sphere met at t = 0.5 M just
 * after its table starts (the ray's steps there reach back before it) and
 * at r ~ 30 M, five times beyond where it started (the scene's radius must
 * hold the whole worldline, and the ray's first step from infinity
 * reaches inside the sphere). hit_r within tol M of the independent value
 * (the near side where the ray passes it: r - R = r_c(T - delay(r)), r_c by
 * quadrature of the radial geodesic), the delay within tol M, and g within
 * tol of 1 / (u^t (1 - (dr/dt) / f)) at the hit (u of the translating
 * matter: the centre's dr/dt); tol 1e-7 in a science frame, 1e-6 in a
 * colour one. The worldline's t comes within tol only if its steps are
 * limited by t's quadrature too (from r = 23.6 to 49.5 M in one step, its t
 * was 2e-3 M off). Without the travel time the sphere would be met several
 * M away. */
static void outgoing(int science, double tol)
{
    char text[1024];
    const double t_emit[2] = {0.5, 0.0}; /* the second: when the centre is at r = 30 */
    double E = out_energy();
    int n;
    loaded A;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: inf, theta: 90, phi: 0, hextent: 3, t: 0}\n"
             "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  radius: %g\n"
             "  motion: particle\n  particle:\n    r: %g\n    theta: 90\n"
             "    phi: 0\n    t: 0\n    velocity: [%g, 0, 0]\n    tau: 40\n",
             ORAD, OR0, OV);
    open_scene(&A, text, 3, 3, CR_INTEG_MINO);
    A.ev.frame.science = science;
    for (n = 0; n < 2; n++) {
        double te = n == 0 ? t_emit[0] : out_t(30.0), rc = out_rc(te);
        double T = te + out_delay(rc + ORAD), rh = out_hit(T, 1, rc + ORAD + 3.0);
        double rnt = out_hit(T, 0, rc + ORAD + 3.0);
        double rp = out_rc(T - out_delay(rh)), fp = 1.0 - 2.0 / rp, fh = 1.0 - 2.0 / rh;
        double drdt = fp * sqrt(E * E - fp) / E, ut = 1.0 / sqrt(fh - drdt * drdt / fh);
        double g = 1.0 / (ut * (1.0 - drdt / fh));
        cr_pixel p;
        assert_true(sees_sphere(&A.ev.frame, 1, 1, T, &p));
        print_message("outgoing (%s frame): t_obs %.6f M (the centre at r = %.4f when the light left): "
                      "hit_r %.9f (independent %.9f; without travel time %.4f), delay %.9f "
                      "(%.9f), g %.9f (%.9f)\n",
                      science ? "science" : "colour", T, rc, p.hit_r, rh, rnt, p.delay, out_delay(rh), p.redshift, g);
        assert_true(fabs(p.hit_r - rh) <= tol);
        assert_true(fabs(p.delay - out_delay(rh)) <= tol);
        assert_true(fabs(p.redshift - g) <= tol * g);
        assert_true(fabs(rnt - rh) > 1.0);
    }
    close_scene(&A);
}

/* The same particle flying out on the far side (phi = pi), R = 2 M, seen
 * from infinity through the hole's lens when it is near r = 30 M, five times
 * beyond its start: its light reaches the camera only on rays that pass the
 * hole and go out again to r ~ 30 M, so the scene's radius must hold the
 * whole worldline. At least 4 pixels of the middle row of 201 x 3 over
 * +-20 M (rays in the equator) see it, and at each the hit lies on the
 * sphere where the quadrature puts its centre when the light left
 * (|x_hit - c(T - delay)| = R within 1e-6 M, science frame). */
static void test_outgoing_behind(void **state)
{
    char text[1024];
    const double R = 2.0, T = 78.0;
    loaded A;
    cr_frame *f;
    int i, seen = 0;
    double worst = 0.0;
    (void)state;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: inf, theta: 90, phi: 0, hextent: 40, t: %g}\n"
             "sphere:\n  color: [0, 0, 255]\n  resolution: [1, 1]\n  radius: %g\n"
             "  motion: particle\n  particle:\n    r: %g\n    theta: 90\n"
             "    phi: 180\n    t: 0\n    velocity: [%g, 0, 0]\n    tau: 60\n",
             T, R, OR0, OV);
    open_scene(&A, text, 201, 3, CR_INTEG_MINO);
    f = &A.ev.frame;
    f->science = 1;
    for (i = 0; i < 201; i++) {
        cr_pixel p = cr_trace_pixel(f, i, 1);
        double rc, dx, dy, d;
        if (p.outcome != CR_OUT_SPHERE)
            continue;
        seen++;
        rc = out_rc(T - p.delay); /* the centre at (-rc, 0, 0) */
        dx = p.hit_r * cos(p.hit_phi) + rc;
        dy = p.hit_r * sin(p.hit_phi);
        d = sqrt(dx * dx + dy * dy);
        worst = fmax(worst, fabs(d - R));
    }
    print_message("outgoing behind the hole: %d of the middle row's 201 pixels see it at t_obs = %g M; "
                  "worst |x_hit - c(t)| - R %.3g M\n",
                  seen, T, worst);
    assert_true(seen >= 4);
    assert_true(worst <= 1e-6);
    close_scene(&A);
}

static void test_outgoing(void **state)
{
    (void)state;
    outgoing(1, 1e-7);
    outgoing(0, 1e-6);
}

/* ---- 3. an eccentric orbit: the light curve's period ---------------- */

/* The frame's flux (the light curve's, cr_lightcurve_compute) at T. */
static double flux_at(cr_frame *f, double T)
{
    cr_lightcurve_point pt;
    cr_pixel *px;
    f->t_obs = T;
    px = trace_all(f);
    cr_lightcurve_compute(f, px, &pt);
    free(px);
    return pt.flux;
}

static void test_eccentric(void **state)
{
    const double p = 10.0, e = 0.3;
    const int nph = 12, w = 160;
    double E = sqrt(((p - 2.0) * (p - 2.0) - 4.0 * e * e) / (p * (p - 3.0 - e * e)));
    double L = p / sqrt(p - 3.0 - e * e), Tr = 0.0, F0[12], lo = INFINITY, hi = -INFINITY;
    double shifts[3] = {1.0, 0.96, 1.04}, rms[3], sm;
    char text[1024];
    loaded A;
    int k, n = 4000, m;
    (void)state;
    /* T_r = int_0^2pi dt/dchi, r = p / (1 + e cos chi) (Cutler, Kennefick &
     * Poisson 1994): periodic and smooth, so the trapezoid rule converges
     * geometrically */
    for (k = 0; k < n; k++) {
        double c = cos(CR_TWO_PI * k / n);
        Tr += p * p / ((p - 2.0 - 2.0 * e * c) * (1.0 + e * c) * (1.0 + e * c)) *
              sqrt(((p - 2.0) * (p - 2.0) - 4.0 * e * e) / (p - 6.0 - 2.0 * e * c));
    }
    Tr *= CR_TWO_PI / n;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: inf, theta: 0, phi: 0, hextent: 34, t: 100}\n"
             "sphere:\n  color: [255, 200, 80]\n  resolution: [1, 1]\n  radius: 2\n"
             "  motion: particle\n  particle:\n    r: %.17g\n    theta: 90\n    t: 0\n"
             "    constants: {E: %.17g, L: %.17g, K: 0, radial: outward}\n    tau: 1200\n",
             p / (1.0 + e), E, L);
    open_scene(&A, text, w, w, CR_INTEG_MINO);
    for (k = 0; k < nph; k++) {
        F0[k] = flux_at(&A.ev.frame, 100.0 + k * Tr / nph);
        lo = fmin(lo, F0[k]);
        hi = fmax(hi, F0[k]);
    }
    for (m = 0; m < 3; m++) {
        double sum = 0.0;
        for (k = 0; k < nph; k++) {
            double d = flux_at(&A.ev.frame, 100.0 + k * Tr / nph + shifts[m] * Tr) - F0[k];
            sum += d * d;
        }
        rms[m] = sqrt(sum / nph) / (hi - lo);
    }
    /* the light curve's period: the minimum of rms^2 (a parabola in the
     * shift, plus the pixels' noise floor) through the three shifts */
    sm = 1.0 + 0.04 * (rms[1] * rms[1] - rms[2] * rms[2]) /
                   (2.0 * (rms[1] * rms[1] - 2.0 * rms[0] * rms[0] + rms[2] * rms[2]));
    print_message("eccentric orbit p = %g, e = %g: T_r = %.6f M (Keplerian %.3f); the flux "
                  "varies by %.3f of its largest over the orbit; its rms change, over %d "
                  "phases, of its range: %.4f after T_r, %.4f after 0.96 T_r, %.4f after 1.04 "
                  "T_r: the light curve's period %.5f T_r\n",
                  p, e, Tr, CR_TWO_PI * pow(p / (1.0 - e * e), 1.5), (hi - lo) / hi, nph, rms[0],
                  rms[1], rms[2], sm);
    assert_true((hi - lo) / hi > 0.2); /* it does vary */
    assert_true(rms[0] <= 0.05);
    assert_true(rms[1] > 2.0 * rms[0] && rms[2] > 2.0 * rms[0]);
    assert_true(fabs(sm - 1.0) <= 0.01);
    close_scene(&A);
}

/* ---- 4. bad input ---------------------------------------------------- */

/* The scene of a particle sphere whose particle section (indented four
 * spaces) is body, with extra sphere keys before it. */
static void refused(const char *metric, const char *extra, const char *body, const char *want)
{
    char text[2048];
    cr_scene s;
    cr_err e;
    snprintf(text, sizeof text,
             "metric: %s\n"
             "observer: {r: 40, theta: 90, phi: 0, hfov: 30, t: 0}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  radius: 0.5\n%s"
             "  motion: particle\n  particle:\n%s",
             metric, extra, body);
    assert_int_equal(load(text, &s, &e), -1);
    if (!strstr(e.msg, want))
        fail_msg("message\n  \"%s\"\nexpected to contain \"%s\"\n--- text:\n%s", e.msg, want,
                 text);
    assert_true(strncmp(e.msg, "wl.yml:", 7) == 0);
    print_message("refused: %s\n", e.msg);
}

static void test_bad_input(void **state)
{
    const char *M = "{m: 1, a: 0.5, q: 0}";
    char text[1024];
    cr_scene s;
    cr_err e;
    (void)state;
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0.6, 0, 0.8]\n    tau: 10\n",
            "wl.yml:11:5: sphere[0].particle.velocity: speed 1 is not below the speed of light");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 1.5]\n    tau: 10\n",
            "sphere[0].particle.velocity: speed 1.5 is not below");
    refused(M, "", "    r: 1.5\n    theta: 90\n    velocity: [0, 0, 0]\n    measured_by: zamo\n"
                   "    tau: 10\n",
            "wl.yml:9:5: sphere[0].particle.r: the start r = 1.5 is not outside the horizon");
    refused(M, "", "    charge_to_mass: .nan\n    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    tau: 10\n",
            "sphere[0].particle.charge_to_mass");
    refused(M, "", "    charge_to_mass: .inf\n    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    tau: 10\n",
            "sphere[0].particle.charge_to_mass");
    refused(M, "", "    r: 10\n    theta: 90\n    tau: 10\n",
            "sphere[0].particle: no initial data");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    constants: {E: 0.95, L: 3, K: 0}\n    tau: 10\n",
            "wl.yml:12:5: sphere[0].particle.constants: contradicts sphere[0].particle.velocity");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n    dtau: 1\n",
            "sphere[0].particle.dtau: is the output spacing of an orbit file");
    refused(M, "  r: 10\n", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n",
            "wl.yml:7:3: sphere[0].r: a motion: particle sphere starts where its particle does");
    refused("{m: 1, a: [linear, 0, 0.5], q: 0}", "",
            "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n",
            "sphere[0].particle: motion: particle follows a worldline of one hole");
    refused(M, "", "    r: 10\n    theta: 90\n    circular: prograde\n    tau: 1e6\n",
            "wl.yml:12:5: sphere[0].particle.tau: the worldline spans more than t =");
    /* the particle's keys without the motion, the motion without them */
    snprintf(text, sizeof text,
             "metric: %s\nobserver: {r: 40, theta: 90, phi: 0, hfov: 30}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  r: 10\n  theta: 90\n"
             "  phi: 0\n  radius: 0.5\n  particle: {r: 10, theta: 90, velocity: [0, 0, 0], "
             "tau: 10}\n",
             M);
    assert_int_equal(load(text, &s, &e), -1);
    assert_non_null(strstr(e.msg, "wl.yml:10:3: sphere[0].particle: applies only to motion: "
                                  "particle"));
    snprintf(text, sizeof text,
             "metric: %s\nobserver: {r: 40, theta: 90, phi: 0, hfov: 30}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  radius: 0.5\n"
             "  motion: particle\n",
             M);
    assert_int_equal(load(text, &s, &e), -1);
    assert_non_null(strstr(e.msg, "wl.yml:7:11: sphere[0].particle: motion: particle needs the "
                                  "particle's initial data"));
}

/* The particle scene in units of M = 2 (every length and time doubled; E,
 * the velocity and angles unchanged) traces the same rays: outcomes, hit_r,
 * delay (in units of M) and g the same to 1e-9 relative. */
static void test_units(void **state)
{
    const char *fmt = "metric: {m: %g, a: %g, q: 0}\n"
                      "observer: {r: %g, theta: 75, phi: 0, hfov: 30, t: %g}\n"
                      "sphere:\n  color: [0, 0, 255]\n  resolution: [4, 8]\n  radius: %g\n"
                      "  motion: particle\n  particle:\n    r: %g\n    theta: 70\n"
                      "    phi: 10\n    t: %g\n    velocity: [0.1, 0.1, 0.35]\n"
                      "    measured_by: zamo\n    tau: %g\n";
    char one[1024], two[1024];
    loaded A, B;
    cr_pixel *p, *q;
    int i, hits = 0;
    (void)state;
    snprintf(one, sizeof one, fmt, 1.0, 0.6, 30.0, 5.0, 1.0, 8.0, -25.0, 100.0);
    snprintf(two, sizeof two, fmt, 2.0, 1.2, 60.0, 10.0, 2.0, 16.0, -50.0, 200.0);
    open_scene(&A, one, 40, 30, CR_INTEG_MINO);
    open_scene(&B, two, 40, 30, CR_INTEG_MINO);
    p = trace_all(&A.ev.frame);
    q = trace_all(&B.ev.frame);
    for (i = 0; i < 40 * 30; i++) {
        assert_int_equal(p[i].outcome, q[i].outcome);
        if (p[i].outcome != CR_OUT_SPHERE)
            continue;
        hits++;
        assert_true(fabs(q[i].hit_r - p[i].hit_r) <= 1e-9 * p[i].hit_r);
        assert_true(fabs(q[i].delay - p[i].delay) <= 1e-9 * fabs(p[i].delay));
        assert_true(fabs(q[i].redshift - p[i].redshift) <= 1e-9 * p[i].redshift);
    }
    print_message("units: %d sphere pixels the same in M = 1 and M = 2\n", hits);
    assert_true(hits >= 10);
    free(p);
    free(q);
    close_scene(&A);
    close_scene(&B);
}

/* cr_cart_vel_to_bl inverts cr_bl_vel_to_cart (the Jacobian of (2.2.8),
 * 6.10.2): random BL points and rates of Kerr (a = 0.9) round-trip to
 * 1e-12 (relative to the rates' size), off the axis. */
static void test_cart_velocity(void **state)
{
    uint64_t seed = 24;
    int n;
    (void)state;
    for (n = 0; n < 10000; n++) {
        double a = 0.9, r = 1.5 + 30.0 * cr_test_rand(&seed);
        double th = 0.01 + (CR_PI - 0.02) * cr_test_rand(&seed);
        double ph = CR_TWO_PI * cr_test_rand(&seed), x[3], v[3], dr, dth, dph;
        double u[3] = {cr_test_rand(&seed) - 0.5, (cr_test_rand(&seed) - 0.5) / r,
                       (cr_test_rand(&seed) - 0.5) / r};
        double scale = fabs(u[0]) + r * (fabs(u[1]) + fabs(u[2]));
        cr_bl_to_cart(a, r, th, ph, x);
        cr_bl_vel_to_cart(a, r, th, ph, u[0], u[1], u[2], v);
        cr_cart_vel_to_bl(a, r, th, x, v, &dr, &dth, &dph);
        assert_true(fabs(dr - u[0]) <= 1e-12 * scale);
        assert_true(r * fabs(dth - u[1]) <= 1e-12 * scale / sin(th));
        assert_true(r * fabs(dph - u[2]) <= 1e-12 * scale / sin(th));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_circular),
        cmocka_unit_test(test_infall),
        cmocka_unit_test(test_outgoing),
        cmocka_unit_test(test_outgoing_behind),
        cmocka_unit_test(test_eccentric),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_units),
        cmocka_unit_test(test_cart_velocity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
