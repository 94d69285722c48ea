/* Patterns, orientations and per-ray statistics against expectations
 * computed independently here, so that a wrong sign, axis or count fails.
 * Every traced check runs under both integrators (mino and rk4).
 *
 * 1. Disc chessboard (parity, yaw, colour at the hit point): Schwarzschild,
 *    static observers at r = 40 M, theta = 0.5 rad (top face) and pi - 0.5
 *    (bottom face). A ray in the observer's meridian plane (n_phi = 0, so
 *    L = 0 and phi stays phi_o) meets the disc plane after sweeping
 *    psi = pi/2 - 0.5 rad; its radius there is found here from the orbit
 *    equation u'' + u = 3 M u^2 (u = 1/r, ' = d/dpsi, RK4 in psi with 4000
 *    steps), and the direction that hits the middle of a chosen ring by
 *    bisection. Disc: r = 6..26 M in 80 rings (0.25 M), 12 sectors, yaw
 *    0.65 sector (so that ignoring the yaw or flipping its sign moves every
 *    probe into a sector of the other parity). Probes at 3 positions inside
 *    every sector x 5 rings per face. Required: outcome disc, the face
 *    (object 0 top, 1 bottom), the colour of cell (ring i, sector j) by the
 *    documented rule (accent colour of the face when i + j is even, grey 128
 *    when odd), and the ratio sqrt(1 - 2/r)/sqrt(1 - 2/40) of the hit radius
 *    to 1e-6 relative (measured: 2e-9 mino at tol 1e-7, 1e-13 rk4).
 *    Also rays that pass over the pole (from theta = 0.5 towards -theta):
 *    they meet the top face on the far side, at phi_o + pi, after sweeping
 *    psi = 0.5 + pi/2 (same orbit equation), with 9 sectors so that the
 *    half-turn changes the sector's parity for half of the probes.
 * 2. Sphere chessboard (E.4, sphere.h): nearly flat space (M = 1e-6: bending
 *    below 1e-6 rad), a sphere of radius 4 at BL (12, 1.1, 0.5), observer at
 *    (30, 1.2, 0.2). Rays aimed at random points P = C + R d of the visible
 *    cap. Latitude and longitude of d are computed here from the sphere's
 *    definition: north pole -e_theta, longitude 0 along e_r, longitude 90 deg
 *    along e_phi at the centre (flat unit vectors), turned by roll about -x,
 *    then pitch about -z, then yaw about -y (right-hand rule, local axes
 *    x = e_r, y = e_theta, z = e_phi), as explicit rotation matrices; for
 *    the 90 deg turns also written out by hand. 6 latitude bands x 10
 *    longitude sectors. Required: outcome sphere and the colour of cell
 *    (lat band i, lon sector j), accent when i + j is even; probes within
 *    2e-3 rad of a cell edge are skipped. (Mino's steps in this nearly flat
 *    space are long: before spheres crossed within one step were searched
 *    for along the step, ~3 % of the probes missed the sphere.)
 * 3. Camera roll, pitch, yaw signs (camera.h): Schwarzschild, observer at
 *    r = 30 M on the equator, 41x41 pixels, 60 deg field. The shadow's
 *    centroid (horizon pixels) moves, for pitch +8 deg, up by
 *    tan(8 deg)/tan(30 deg) * 20.5 px; for yaw +8 deg, right by as much; with
 *    yaw 10 deg and roll +-30 deg it turns counterclockwise (roll > 0) or
 *    clockwise about the image centre: up or down by
 *    tan(10 deg) sin(30 deg)/tan(30 deg) * 20.5 px. Tolerance 25 % of the
 *    expected shift, 0.5 px across it.
 * 4. Kerr Cartesian coordinates (2.2.8), x = sqrt(r^2+a^2) sin th cos ph,
 *    y = sqrt(r^2+a^2) sin th sin ph, z = r cos th:
 *    - a sphere of radius 5 centred at the origin of a = 0.9, Q = 0.3 is
 *      met, by rays in the equatorial plane, at BL r = sqrt(25 - a^2); the
 *      pixel's ratio must be sqrt(-g_tt(r))/sqrt(-g_tt(30)) with the
 *      equatorial -g_tt = 1 - 2/r + Q^2/r^2, to 1e-7 relative;
 *    - the sky: a = 0.99, observer at r = 5 on the equator, sky boundary
 *      R = 7, rays in the equatorial plane at 60 deg from e_r. The expected
 *      sky azimuth is the Cartesian direction of motion at the ray's final
 *      radius, from phi(r) integrated here (dphi/dr = u^phi/u^r from the
 *      inverse metric and the ray's E, L; Simpson, 2000 intervals). The sky
 *      texture (36000 x 2) is a ramp in red around the expected column, so
 *      the sampled colour gives the azimuth to 1e-4 rad; required within
 *      3e-4 rad (a = 0.99 with rho = r instead of sqrt(r^2+a^2) is off by
 *      ~1e-2). Its two rows (centres at theta = pi/4, 3pi/4) are blue 0
 *      and 100: the sample at theta = pi/2 must be blue 50 +- 1;
 *    - unit checks of cr_bl_to_cart, cr_mino_cart, cr_bl_vel_to_cart,
 *      cr_sky_direction and cr_mino_sky_direction against (2.2.8) written
 *      out here and central differences of it, at random states.
 * 5. A sphere entered and left within one step: a radial ray of a
 *    Schwarzschild hole through a sphere of radius 0.3 on the line of sight
 *    (centre r = 20.00..22.59 in 8 positions), under rk4 with
 *    step_multiplier 2 (25 steps from r = 40 to the horizon) and mino with
 *    tolerance 1e-3 and the default. Required: outcome sphere, at the ratio
 *    of r = centre + 0.3 to 1e-6. Mino takes 2 steps (tol 1e-3) and 4
 *    (default) for this ray: a radial ray is nearly exact for it, so its
 *    steps are as long as the step growth allows.
 * 6. The ratio of an off-equator source with a != 0: a sphere of radius 5 at
 *    the origin of a = 0.9, Q = 0.3 seen from the north pole (r = 30): the
 *    centre pixel's ray runs down the axis and meets it at r = 5, theta = 0,
 *    ratio sqrt(-g_tt(5, 0))/sqrt(-g_tt(30, 0)), -g_tt = (Delta -
 *    a^2 sin^2)/Sigma written out here; and cr_redshift_static at random
 *    (r, theta) against the same formula, to 1e-12.
 * 7. err_mean and err_std: for rays of an empty Kerr-Newman scene the loop's
 *    primitives (cr_ray_begin, cr_ray_advance, cr_ray_commit) are stepped
 *    here and the monitor values collected; their mean and population
 *    standard deviation (two passes) must equal the pixel's to 1e-9
 *    relative, and its step count must agree.
 * 8. Null-error bounds: listing 7.1.1 (frame 8 of 18) and listing 7.2.1
 *    (frame 8 of 18) at 33x25 pixels: the largest err_mean and err_std over
 *    the image are below 10x what was measured (mino, whose monitor scales
 *    with the tolerance: err_mean 0.93 tol, err_std 0.57 tol at tol 1e-8 and
 *    1e-7 -> bounds 10 tol and 6 tol; rk4, c = 1/32: err_mean 8.6e-9,
 *    err_std 1.28e-8 -> bounds 9e-8 and 1.3e-7).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/cpu.h"
#include "input/scene.h"
#include "testutil.h"

#define DEG (CR_PI / 180.0)

static const char *integ_name(int integ)
{
    return integ == CR_INTEG_RK4 ? "rk4" : "mino";
}

/* A frame with metric (m, a, q), a static observer at (r, theta, phi) looking
 * at the hole, W x H pixels with field of view fov (both ways), nothing in
 * the scene, the given integrator and default settings. Not prepared. */
static void frame_init(cr_frame *f, double m, double a, double q, double r, double th,
                       double ph, int integ)
{
    memset(f, 0, sizeof *f);
    f->metric.m = m;
    f->metric.a = a;
    f->metric.q = q;
    f->observer.r = r;
    f->observer.theta = th;
    f->observer.phi = ph;
    f->observer.hfov = f->observer.vfov = 60.0 * DEG;
    f->width = f->height = 41;
    f->horizon_color.r = 255;
    f->error_color.b = 255;
    f->sky_color.g = 17;
    f->integrator = integ;
    f->tolerance = cr_trace_defaults().tolerance;
    f->step_multiplier = cr_trace_defaults().step_multiplier;
    f->horizon_epsilon = cr_trace_defaults().horizon_epsilon;
    f->max_steps = cr_trace_defaults().max_steps;
    f->max_turns = cr_trace_defaults().max_turns;
}

/* Give f the green/magenta chessboard disc (ERRATA 3) of n_rad rings and
 * n_sec sectors from r_in to r_out, turned by yaw, then prepare f. */
static void chessboard_disc(cr_frame *f, int n_rad, int n_sec, double yaw, double r_in,
                            double r_out)
{
    f->disc.enabled = 1;
    f->disc.color1 = cr_rgb_make(0, 255, 0);
    f->disc.color2 = cr_rgb_make(255, 0, 255);
    f->disc.n_radial = n_rad;
    f->disc.n_sectors = n_sec;
    f->disc.yaw = yaw;
    f->disc.r_in = r_in;
    f->disc.r_out = r_out;
    cr_frame_prepare(f);
}

/* Trace the ray that leaves the observer of a prepared frame in the local
 * unit direction n = (n_r, n_theta, n_phi). */
static cr_pixel trace_dir(const cr_frame *f, const double n[3])
{
    cr_geo g;
    double y[CR_NY];
    cr_camera_ray(f, n, &g, y);
    return cr_trace_ray(f, &g, y);
}

static int rgb_is(cr_rgb c, int r, int g, int b)
{
    return c.r == r && c.g == g && c.b == b;
}

/* -g_tt of Kerr-Newman at (r, theta), from (2.2.1)-(2.2.3) written out. */
static double kn_minus_gtt(double m, double a, double q, double r, double th)
{
    double s = sin(th), c = cos(th);
    double sigma = r * r + a * a * c * c;
    double delta = r * r - 2.0 * m * r + a * a + q * q;
    return (delta - a * a * s * s) / sigma;
}

/* (2.2.8) written out. */
static void cart(double a, double r, double th, double ph, double x[3])
{
    double rho = sqrt(r * r + a * a);
    x[0] = rho * sin(th) * cos(ph);
    x[1] = rho * sin(th) * sin(ph);
    x[2] = r * cos(th);
}

/* --- 1. the disc's chessboard ------------------------------------------- */

/* Radius where the Schwarzschild (M = 1) ray from a static observer at r_o,
 * leaving at angle alpha from the inward radial direction, has swept the
 * angle psi_hit in its orbit plane; 0 when it falls in first. Orbit equation
 * u'' = -u + 3 u^2 with u(0) = 1/r_o, u'(0) = u sqrt(1 - 2u) cot(alpha). */
static double binet_r_hit(double r_o, double alpha, double psi_hit)
{
    const int n = 4000;
    double h = psi_hit / n, u = 1.0 / r_o, v = u * sqrt(1.0 - 2.0 * u) / tan(alpha);
    int i;
    for (i = 0; i < n; i++) {
        double k1u = v, k1v = -u + 3.0 * u * u;
        double u2 = u + 0.5 * h * k1u, v2 = v + 0.5 * h * k1v;
        double k2u = v2, k2v = -u2 + 3.0 * u2 * u2;
        double u3 = u + 0.5 * h * k2u, v3 = v + 0.5 * h * k2v;
        double k3u = v3, k3v = -u3 + 3.0 * u3 * u3;
        double u4 = u + h * k3u, v4 = v + h * k3v;
        double k4u = v4, k4v = -u4 + 3.0 * u4 * u4;
        u += h * (k1u + 2.0 * k2u + 2.0 * k3u + k4u) / 6.0;
        v += h * (k1v + 2.0 * k2v + 2.0 * k3v + k4v) / 6.0;
        if (u > 0.5)
            return 0.0;
    }
    return 1.0 / u;
}

/* The angle alpha from the inward radial direction at which the ray hits the
 * equatorial plane at radius r_t after sweeping psi_hit (bisection). */
static double alpha_for_radius(double r_o, double psi_hit, double r_t)
{
    double lo = 1e-3, hi = 0.9;
    int it;
    assert_true(binet_r_hit(r_o, lo, psi_hit) < r_t);
    assert_true(binet_r_hit(r_o, hi, psi_hit) > r_t);
    for (it = 0; it < 80; it++) {
        double mid = 0.5 * (lo + hi);
        if (binet_r_hit(r_o, mid, psi_hit) < r_t)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

static void test_disc_chessboard(void **state)
{
    const double r_o = 40.0, th_top = 0.5, r_in = 6.0, r_out = 26.0;
    const int n_rad = 80, n_sec = 12;
    const double sec = CR_TWO_PI / n_sec, yaw = 0.65 * sec;
    static const int rings[] = {0, 9, 30, 51, 79};
    static const double frac[] = {0.25, 0.5, 0.75};
    double alpha[5];
    int integ, face, k, s, q;
    (void)state;
    for (k = 0; k < 5; k++) {
        double r_t = r_in + (rings[k] + 0.5) * (r_out - r_in) / n_rad;
        alpha[k] = alpha_for_radius(r_o, 0.5 * CR_PI - th_top, r_t);
        assert_true(fabs(binet_r_hit(r_o, alpha[k], 0.5 * CR_PI - th_top) / r_t - 1.0) < 1e-12);
    }
    for (integ = 0; integ < 2; integ++) {
        double worst = 0.0;
        int probes = 0;
        for (face = 0; face < 2; face++) {
            for (s = 0; s < n_sec; s++)
                for (q = 0; q < 3; q++) {
                    cr_frame f;
                    double ph = yaw + (s + frac[q]) * sec;
                    frame_init(&f, 1.0, 0.0, 0.0, r_o, face ? CR_PI - th_top : th_top, ph,
                               integ);
                    chessboard_disc(&f, n_rad, n_sec, yaw, r_in, r_out);
                    for (k = 0; k < 5; k++) {
                        /* towards +theta from the top, -theta from below */
                        double n[3] = {-cos(alpha[k]), (face ? -1.0 : 1.0) * sin(alpha[k]), 0.0};
                        double r_t = r_in + (rings[k] + 0.5) * (r_out - r_in) / n_rad;
                        double z = sqrt(1.0 - 2.0 / r_t) / sqrt(1.0 - 2.0 / r_o);
                        cr_pixel px = trace_dir(&f, n);
                        int accent = ((rings[k] + s) % 2) == 0;
                        cr_rgb want = accent ? (face ? f.disc.color2 : f.disc.color1)
                                             : cr_rgb_make(128, 128, 128);
                        if (px.outcome != CR_OUT_DISC || px.object != face ||
                            !rgb_is(px.color, want.r, want.g, want.b) ||
                            !(fabs(px.redshift / z - 1.0) < 1e-6))
                            fail_msg("%s, %s face, ring %d sector %d (phi %.4f): outcome %d "
                                     "object %d colour (%d,%d,%d), want disc %d (%d,%d,%d); "
                                     "ratio %.12f, want %.12f (r = %.4f)",
                                     integ_name(integ), face ? "bottom" : "top", rings[k], s, ph,
                                     px.outcome, px.object, px.color.r, px.color.g, px.color.b,
                                     face, want.r, want.g, want.b, px.redshift, z, r_t);
                        worst = fmax(worst, fabs(px.redshift / z - 1.0));
                        probes++;
                    }
                }
        }
        print_message("disc chessboard, %s: %d probes right; worst ratio error %.2g (tol 1e-6)\n",
                      integ_name(integ), probes, worst);
    }
}

/* Rays that pass over the pole: from theta_o = 0.5 towards -theta (up), in
 * the meridian plane, they cross the axis and meet the disc's top face on
 * the far side, at phi_o + pi, after sweeping psi = 0.5 + pi/2. 9 sectors
 * (an odd number, so that phi and phi + pi fall in sectors of both
 * parities). Under rk4 the ray is continued through the axis by
 * cr_geo_through_axis, under mino it passes through n = z_hat. */
static void test_disc_over_the_pole(void **state)
{
    const double r_o = 40.0, th_o = 0.5, r_in = 6.0, r_out = 26.0;
    const double psi_hit = th_o + 0.5 * CR_PI;
    const int n_rad = 80, n_sec = 9;
    const double sec = CR_TWO_PI / n_sec, yaw = 0.3, ring = (r_out - r_in) / n_rad;
    static const double frac[] = {0.25, 0.75};
    double alpha[4], r_hit[4];
    int integ, n_al = 0, s, q, k;
    double al;
    (void)state;
    /* four directions whose hit lies inside a ring, away from its edges */
    for (al = 0.2; al < 0.9 && n_al < 4; al += 0.0137) {
        double r = binet_r_hit(r_o, al, psi_hit), fr = (r - r_in) / ring;
        if (r > r_in + 1.0 && r < r_out - 1.0 && fabs(fr - floor(fr + 0.5)) > 0.1 &&
            (n_al == 0 || r > r_hit[n_al - 1] + 2.0)) {
            alpha[n_al] = al;
            r_hit[n_al++] = r;
        }
    }
    assert_int_equal(n_al, 4);
    for (integ = 0; integ < 2; integ++) {
        int probes = 0;
        for (s = 0; s < n_sec; s++)
            for (q = 0; q < 2; q++) {
                cr_frame f;
                double ph = yaw + (s + frac[q]) * sec;
                double u = fmod(ph + CR_PI - yaw, CR_TWO_PI);
                int sector = (int)floor(u / sec);
                frame_init(&f, 1.0, 0.0, 0.0, r_o, th_o, ph, integ);
                chessboard_disc(&f, n_rad, n_sec, yaw, r_in, r_out);
                for (k = 0; k < 4; k++) {
                    double n[3] = {-cos(alpha[k]), -sin(alpha[k]), 0.0};
                    int rg = (int)floor((r_hit[k] - r_in) / ring);
                    double z = sqrt(1.0 - 2.0 / r_hit[k]) / sqrt(1.0 - 2.0 / r_o);
                    cr_rgb want = ((rg + sector) % 2) == 0 ? f.disc.color1
                                                           : cr_rgb_make(128, 128, 128);
                    cr_pixel px = trace_dir(&f, n);
                    if (px.outcome != CR_OUT_DISC || px.object != 0 ||
                        !rgb_is(px.color, want.r, want.g, want.b) ||
                        !(fabs(px.redshift / z - 1.0) < 1e-6))
                        fail_msg("%s: over the pole, ring %d sector %d (phi_o %.4f, hit at "
                                 "phi_o + pi, r = %.4f): outcome %d object %d colour "
                                 "(%d,%d,%d), want top face (%d,%d,%d); ratio %.10f, want "
                                 "%.10f",
                                 integ_name(integ), rg, sector, ph, r_hit[k], px.outcome,
                                 px.object, px.color.r, px.color.g, px.color.b, want.r, want.g,
                                 want.b, px.redshift, z);
                    probes++;
                }
            }
        print_message("disc over the pole, %s: %d probes right (hits at r = %.2f, %.2f, %.2f, "
                      "%.2f on the far side)\n",
                      integ_name(integ), probes, r_hit[0], r_hit[1], r_hit[2], r_hit[3]);
    }
}

/* --- 2. the sphere's chessboard ----------------------------------------- */

/* v <- rotation of v by angle t about the unit axis k, right-hand rule, as a
 * matrix. */
static void rot_about(const double k[3], double t, double v[3])
{
    double c = cos(t), s = sin(t), C = 1.0 - c, R[3][3], w[3];
    int i;
    R[0][0] = c + k[0] * k[0] * C;
    R[0][1] = k[0] * k[1] * C - k[2] * s;
    R[0][2] = k[0] * k[2] * C + k[1] * s;
    R[1][0] = k[1] * k[0] * C + k[2] * s;
    R[1][1] = c + k[1] * k[1] * C;
    R[1][2] = k[1] * k[2] * C - k[0] * s;
    R[2][0] = k[2] * k[0] * C - k[1] * s;
    R[2][1] = k[2] * k[1] * C + k[0] * s;
    R[2][2] = c + k[2] * k[2] * C;
    for (i = 0; i < 3; i++)
        w[i] = R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2];
    memcpy(v, w, sizeof w);
}

typedef struct orient {
    const char *name;
    double roll, pitch, yaw;
    /* hand-written local (x = e_r, y = e_th, z = e_ph) components of lon 0,
     * north, lon 90; all zero: use the rotation matrices */
    double hand[3][3];
} orient;

static void test_sphere_chessboard(void **state)
{
    static const orient ors[] = {
        {"no turn", 0, 0, 0, {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}}},
        /* yaw about -y (the north axis): lon 0 -> +z, lon 90 -> -x */
        {"yaw 90", 0, 0, 90, {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}}},
        /* pitch about -z: lon 0 -> -y, north -> -x */
        {"pitch 90", 0, 90, 0, {{0, -1, 0}, {-1, 0, 0}, {0, 0, 1}}},
        /* roll about -x: north -> +z, lon 90 -> +y */
        {"roll 90", 90, 0, 0, {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}}},
        {"roll 20 pitch 35 yaw 50", 20, 35, 50, {{0}}},
        {"roll -70 pitch -20 yaw 160", -70, -20, 160, {{0}}},
    };
    const double R = 4.0, rc = 12.0, thc = 1.1, phc = 0.5;
    const int n_lat = 6, n_lon = 10;
    int integ, o;
    uint64_t seed = 12345;
    (void)state;
    for (integ = 0; integ < 2; integ++)
        for (o = 0; o < (int)(sizeof ors / sizeof ors[0]); o++) {
            cr_frame f;
            cr_sphere sp;
            double e[3][3], ax[3][3], C[3], O[3], eo[3][3];
            int i, k, probes = 0, skipped = 0, accents = 0;
            memset(&sp, 0, sizeof sp);
            sp.color = cr_rgb_make(0, 0, 255);
            sp.n_lat = n_lat;
            sp.n_lon = n_lon;
            sp.r = rc;
            sp.theta = thc;
            sp.phi = phc;
            sp.roll = ors[o].roll * DEG;
            sp.pitch = ors[o].pitch * DEG;
            sp.yaw = ors[o].yaw * DEG;
            sp.radius = R;
            cr_sphere_prepare(&sp, 0.0);
            frame_init(&f, 1e-6, 0.0, 0.0, 30.0, 1.2, 0.2, integ);
            f.spheres = &sp;
            f.n_spheres = 1;
            cr_frame_prepare(&f);
            /* flat unit vectors e_r, e_th, e_ph at the centre and the observer */
            e[0][0] = sin(thc) * cos(phc); e[0][1] = sin(thc) * sin(phc); e[0][2] = cos(thc);
            e[1][0] = cos(thc) * cos(phc); e[1][1] = cos(thc) * sin(phc); e[1][2] = -sin(thc);
            e[2][0] = -sin(phc);           e[2][1] = cos(phc);            e[2][2] = 0.0;
            eo[0][0] = sin(1.2) * cos(0.2); eo[0][1] = sin(1.2) * sin(0.2); eo[0][2] = cos(1.2);
            eo[1][0] = cos(1.2) * cos(0.2); eo[1][1] = cos(1.2) * sin(0.2); eo[1][2] = -sin(1.2);
            eo[2][0] = -sin(0.2);           eo[2][1] = cos(0.2);            eo[2][2] = 0.0;
            for (k = 0; k < 3; k++) {
                C[k] = rc * e[0][k];
                O[k] = 30.0 * eo[0][k];
            }
            /* the sphere's axes (lon 0, north, lon 90) in local components */
            {
                double loc[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
                const double mx[3] = {-1, 0, 0}, mz[3] = {0, 0, -1}, my[3] = {0, -1, 0};
                int hand = ors[o].hand[0][0] != 0 || ors[o].hand[0][1] != 0 ||
                           ors[o].hand[0][2] != 0;
                for (i = 0; i < 3; i++) {
                    if (hand) {
                        memcpy(loc[i], ors[o].hand[i], sizeof loc[i]);
                    } else {
                        rot_about(mx, sp.roll, loc[i]);
                        rot_about(mz, sp.pitch, loc[i]);
                        rot_about(my, sp.yaw, loc[i]);
                    }
                    for (k = 0; k < 3; k++)
                        ax[i][k] = loc[i][0] * e[0][k] + loc[i][1] * e[1][k] + loc[i][2] * e[2][k];
                }
            }
            for (i = 0; i < 4000 && probes < 150; i++) {
                double d[3], P[3], v[3], n[3], len = 0.0, dl, vl = 0.0, oc = 0.0, ocl = 0.0;
                double c0, c1, c2, lat, lon, fl, fo;
                cr_pixel px;
                int bl, bo;
                cr_rgb want;
                for (k = 0; k < 3; k++) {
                    d[k] = 2.0 * cr_test_rand(&seed) - 1.0;
                    len += d[k] * d[k];
                }
                if (len > 1.0 || len < 1e-4)
                    continue;
                dl = sqrt(len);
                for (k = 0; k < 3; k++) {
                    d[k] /= dl;
                    P[k] = C[k] + R * d[k];
                    v[k] = P[k] - O[k];
                    vl += v[k] * v[k];
                    oc += d[k] * (O[k] - C[k]);
                    ocl += (O[k] - C[k]) * (O[k] - C[k]);
                }
                /* on the visible cap, away from the limb */
                if (oc / sqrt(ocl) < R / sqrt(ocl) + 0.15)
                    continue;
                vl = sqrt(vl);
                for (k = 0; k < 3; k++)
                    n[k] = (v[0] * eo[k][0] + v[1] * eo[k][1] + v[2] * eo[k][2]) / vl;
                c0 = d[0] * ax[0][0] + d[1] * ax[0][1] + d[2] * ax[0][2];
                c1 = d[0] * ax[1][0] + d[1] * ax[1][1] + d[2] * ax[1][2];
                c2 = d[0] * ax[2][0] + d[1] * ax[2][1] + d[2] * ax[2][2];
                lat = acos(fmax(-1.0, fmin(1.0, c1)));
                lon = atan2(c2, c0);
                if (lon < 0.0)
                    lon += CR_TWO_PI;
                fl = lat / CR_PI * n_lat;
                fo = lon / CR_TWO_PI * n_lon;
                /* skip probes within 2e-3 rad of a cell edge */
                if (fabs(fl - floor(fl + 0.5)) * CR_PI / n_lat < 2e-3 ||
                    fabs(fo - floor(fo + 0.5)) * CR_TWO_PI / n_lon * sin(lat) < 2e-3) {
                    skipped++;
                    continue;
                }
                bl = (int)floor(fl);
                bo = (int)floor(fo);
                want = ((bl + bo) % 2) == 0 ? sp.color : cr_rgb_make(128, 128, 128);
                accents += ((bl + bo) % 2) == 0;
                px = trace_dir(&f, n);
                if (px.outcome != CR_OUT_SPHERE || px.object != 0 ||
                    !rgb_is(px.color, want.r, want.g, want.b))
                    fail_msg("%s, sphere %s: probe d = (%.4f, %.4f, %.4f), lat %.4f lon %.4f "
                             "(cell %d, %d): outcome %d colour (%d,%d,%d), want sphere "
                             "(%d,%d,%d)",
                             integ_name(integ), ors[o].name, d[0], d[1], d[2], lat, lon, bl, bo,
                             px.outcome, px.color.r, px.color.g, px.color.b, want.r, want.g,
                             want.b);
                probes++;
            }
            assert_true(probes >= 100);
            assert_true(accents > 20 && probes - accents > 20);
            print_message("sphere chessboard, %s, %s: %d probes right (%d accent), %d near "
                          "edges skipped\n",
                          integ_name(integ), ors[o].name, probes, accents, skipped);
        }
}

/* --- 3. camera roll, pitch and yaw -------------------------------------- */

/* Centroid (i, j) of the horizon pixels of a 41x41 image. */
static void shadow_centroid(int integ, double roll, double pitch, double yaw, double *ci,
                            double *cj)
{
    cr_frame f;
    double si = 0.0, sj = 0.0;
    int i, j, n = 0;
    frame_init(&f, 1.0, 0.0, 0.0, 30.0, 0.5 * CR_PI, 0.0, integ);
    f.observer.roll = roll * DEG;
    f.observer.pitch = pitch * DEG;
    f.observer.yaw = yaw * DEG;
    cr_frame_prepare(&f);
    for (j = 0; j < f.height; j++)
        for (i = 0; i < f.width; i++)
            if (cr_trace_pixel(&f, i, j).outcome == CR_OUT_HORIZON) {
                si += i;
                sj += j;
                n++;
            }
    assert_true(n > 50);
    *ci = si / n;
    *cj = sj / n;
}

static void test_camera_rotation_signs(void **state)
{
    const double px_per_tan = 20.5 / tan(30.0 * DEG);
    const double d8 = tan(8.0 * DEG) * px_per_tan;
    const double t10 = tan(10.0 * DEG) * px_per_tan;
    int integ;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        double i0, j0, i1, j1;
        shadow_centroid(integ, 0, 0, 0, &i0, &j0);
        assert_true(fabs(i0 - 20.0) < 0.05 && fabs(j0 - 20.0) < 0.05);
        /* pitch > 0 tilts the view towards +theta: the hole moves up */
        shadow_centroid(integ, 0, 8, 0, &i1, &j1);
        print_message("%s: pitch +8: shadow moves (%+.2f, %+.2f) px, expected (0, %+.2f)\n",
                      integ_name(integ), i1 - i0, j1 - j0, -d8);
        assert_true(fabs(i1 - i0) < 0.5);
        assert_true(fabs((j1 - j0) + d8) < 0.25 * d8);
        /* yaw > 0 turns the view towards -phi (left): the hole moves right */
        shadow_centroid(integ, 0, 0, 8, &i1, &j1);
        print_message("%s: yaw +8: shadow moves (%+.2f, %+.2f) px, expected (%+.2f, 0)\n",
                      integ_name(integ), i1 - i0, j1 - j0, d8);
        assert_true(fabs((i1 - i0) - d8) < 0.25 * d8);
        assert_true(fabs(j1 - j0) < 0.5);
        /* roll > 0 turns the camera clockwise seen from behind: the picture
         * turns counterclockwise, the hole (right of centre after yaw 10)
         * moves up; roll < 0 moves it down */
        shadow_centroid(integ, 30, 0, 10, &i1, &j1);
        print_message("%s: yaw 10, roll +30: shadow at (%+.2f, %+.2f) px, expected (%+.2f, "
                      "%+.2f)\n",
                      integ_name(integ), i1 - i0, j1 - j0, t10 * cos(30 * DEG),
                      -t10 * sin(30 * DEG));
        assert_true(fabs((i1 - i0) - t10 * cos(30 * DEG)) < 0.25 * t10);
        assert_true(fabs((j1 - j0) + t10 * sin(30 * DEG)) < 0.25 * t10);
        shadow_centroid(integ, -30, 0, 10, &i1, &j1);
        print_message("%s: yaw 10, roll -30: shadow at (%+.2f, %+.2f) px\n", integ_name(integ),
                      i1 - i0, j1 - j0);
        assert_true(fabs((i1 - i0) - t10 * cos(30 * DEG)) < 0.25 * t10);
        assert_true(fabs((j1 - j0) - t10 * sin(30 * DEG)) < 0.25 * t10);
    }
}

/* --- 4. Kerr Cartesian coordinates -------------------------------------- */

/* A sphere of radius R centred at the Cartesian origin of (2.2.8). */
static void origin_sphere(cr_sphere *sp, double a, double R)
{
    memset(sp, 0, sizeof *sp);
    sp->color = cr_rgb_make(0, 0, 255);
    sp->n_lat = 4;
    sp->n_lon = 4;
    sp->r = 0.0;
    sp->theta = 0.0;
    sp->radius = R;
    cr_sphere_prepare(sp, a);
}

static void test_kerr_cartesian_sphere(void **state)
{
    const double a = 0.9, q = 0.3, R = 5.0, r_o = 30.0;
    const double r_hit = sqrt(R * R - a * a);
    const double z = sqrt(1.0 - 2.0 / r_hit + q * q / (r_hit * r_hit)) /
                     sqrt(1.0 - 2.0 / r_o + q * q / (r_o * r_o));
    static const double alphas[] = {0.0, 0.05, -0.05, 0.1, -0.1, 0.15, -0.15};
    int integ, k;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        cr_frame f;
        cr_sphere sp;
        double worst = 0.0;
        origin_sphere(&sp, a, R);
        frame_init(&f, 1.0, a, q, r_o, 0.5 * CR_PI, 0.3, integ);
        f.spheres = &sp;
        f.n_spheres = 1;
        cr_frame_prepare(&f);
        for (k = 0; k < 7; k++) {
            double n[3] = {-cos(alphas[k]), 0.0, sin(alphas[k])};
            cr_pixel px = trace_dir(&f, n);
            if (px.outcome != CR_OUT_SPHERE || !(fabs(px.redshift / z - 1.0) < 1e-7))
                fail_msg("%s: equatorial ray %g rad: outcome %d ratio %.12f, want sphere at "
                         "r = sqrt(R^2 - a^2) = %.6f, ratio %.12f",
                         integ_name(integ), alphas[k], px.outcome, px.redshift, r_hit, z);
            worst = fmax(worst, fabs(px.redshift / z - 1.0));
        }
        print_message("Kerr sphere at the origin, %s: equatorial hits at r = sqrt(R^2 - a^2), "
                      "worst ratio error %.2g (tol 1e-7)\n",
                      integ_name(integ), worst);
    }
}

/* Equatorial metric pieces of Kerr-Newman (M = 1): g_tt, g_tph, g_phph,
 * g_rr at (r, pi/2), from (2.2.1)-(2.2.3). */
static void eq_metric(double a, double q, double r, double *gtt, double *gtp, double *gpp,
                      double *grr)
{
    double delta = r * r - 2.0 * r + a * a + q * q, W = 2.0 * r - q * q;
    *gtt = -(delta - a * a) / (r * r);
    *gtp = -a * W / (r * r);
    *gpp = ((r * r + a * a) * (r * r + a * a) - delta * a * a) / (r * r);
    *grr = r * r / delta;
}

/* dphi/dr of an equatorial null ray with u_t = E, u_phi = L, moving outward. */
static double eq_dphi_dr(double a, double q, double E, double L, double r)
{
    double gtt, gtp, gpp, grr, det, itt, itp, ipp, uph, ur2;
    eq_metric(a, q, r, &gtt, &gtp, &gpp, &grr);
    det = gtt * gpp - gtp * gtp;
    itt = gpp / det;
    itp = -gtp / det;
    ipp = gtt / det;
    uph = itp * E + ipp * L;
    ur2 = -(itt * E * E + 2.0 * itp * E * L + ipp * L * L) / grr;
    assert_true(ur2 > 0.0);
    return uph / sqrt(ur2);
}

static void test_kerr_cartesian_sky(void **state)
{
    const double a = 0.99, q = 0.0, r_o = 5.0, ph_o = 1.0, Rb = 7.0;
    const int tw = 36000, th_ = 2;
    uint8_t *tex = malloc((size_t)tw * th_ * 3);
    int integ, side;
    (void)state;
    assert_non_null(tex);
    for (integ = 0; integ < 2; integ++)
        for (side = -1; side <= 1; side += 2) {
            cr_frame f;
            cr_geo g;
            cr_ray ray;
            cr_pixel px;
            double n[3] = {0.5, 0.0, side * sqrt(0.75)}, y[CR_NY];
            double r_f, ph, dph, rho, vx, vy, sky_ph, fx, fx_meas, dphi;
            int x, row, xc, i;
            const int N = 2000;
            frame_init(&f, 1.0, a, q, r_o, 0.5 * CR_PI, ph_o, integ);
            f.sky_boundary = Rb;
            f.sky.rgb = tex; /* a sky image: the boundary is the scene's edge */
            cr_frame_prepare(&f);
            assert_true(f.r_max == Rb);
            cr_camera_ray(&f, n, &g, y);
            cr_ray_from_bl(&f, &g, y, &ray);
            /* trace once with any sky to find the final radius, then build
             * the texture round the expected azimuth there */
            memset(tex, 0, (size_t)tw * th_ * 3);
            f.sky.rgb = tex;
            f.sky.width = tw;
            f.sky.height = th_;
            {
                cr_ray probe = ray;
                px = cr_trace_loop(&f, &probe);
                assert_int_equal(px.outcome, CR_OUT_SKY);
                r_f = integ == CR_INTEG_MINO ? 1.0 / probe.m[CR_M_W] : probe.y[CR_Y_R];
            }
            assert_true(r_f >= Rb - 1e-9 && r_f < Rb + 0.2);
            /* phi(r_f) by Simpson's rule on dphi/dr */
            {
                double hs = (r_f - r_o) / N, sum = 0.0;
                for (i = 0; i <= N; i++) {
                    double w = (i == 0 || i == N) ? 1.0 : (i % 2 ? 4.0 : 2.0);
                    sum += w * eq_dphi_dr(a, q, g.E, g.L, r_o + i * hs);
                }
                ph = ph_o + sum * hs / 3.0;
            }
            dph = eq_dphi_dr(a, q, g.E, g.L, r_f);
            rho = sqrt(r_f * r_f + a * a);
            vx = r_f / rho * cos(ph) - rho * sin(ph) * dph;
            vy = r_f / rho * sin(ph) + rho * cos(ph) * dph;
            sky_ph = atan2(vy, vx);
            if (sky_ph < 0.0)
                sky_ph += CR_TWO_PI;
            fx = (CR_TWO_PI - sky_ph) / CR_TWO_PI * tw - 0.5;
            xc = (int)floor(fx + 0.5);
            assert_true(xc > 200 && xc < tw - 200);
            for (row = 0; row < th_; row++)
                for (x = xc - 127; x <= xc + 127; x++) {
                    uint8_t *p = tex + 3 * ((size_t)row * tw + x);
                    p[0] = (uint8_t)(x - xc + 128);
                    p[1] = 255;
                    p[2] = (uint8_t)(100 * row); /* theta = pi/2 lies half-way */
                }
            px = cr_trace_loop(&f, &ray);
            assert_int_equal(px.outcome, CR_OUT_SKY);
            if (px.color.g != 255)
                fail_msg("%s, side %d: sky colour (%d,%d,%d) outside the window round the "
                         "expected azimuth %.6f",
                         integ_name(integ), side, px.color.r, px.color.g, px.color.b, sky_ph);
            /* row centres at theta = pi/4 and 3pi/4 (6.10.1): blue 50 */
            if (abs((int)px.color.b - 50) > 1)
                fail_msg("%s, side %d: sky colour (%d,%d,%d): blue %d is not 50, the value "
                         "half-way between the rows at theta = pi/2",
                         integ_name(integ), side, px.color.r, px.color.g, px.color.b,
                         px.color.b);
            fx_meas = (double)px.color.r - 128.0 + xc;
            dphi = (fx_meas - fx) * CR_TWO_PI / tw;
            print_message("Kerr sky at R = %g, %s, %s ray: final r %.5f, sky phi %.6f, measured "
                          "off by %.2g rad (tol 3e-4)\n",
                          Rb, integ_name(integ), side > 0 ? "prograde" : "retrograde", r_f,
                          sky_ph, dphi);
            assert_true(fabs(dphi) < 3e-4);
        }
    free(tex);
}

/* The unit direction of d/dt of (2.2.8) along BL (r, th, ph)(t), by central
 * differences with step eps. */
static void cart_dir_fd(double a, const double p0[3], const double dp[3], double eps,
                        double v[3])
{
    double xp[3], xm[3], len = 0.0;
    int k;
    cart(a, p0[0] + eps * dp[0], p0[1] + eps * dp[1], p0[2] + eps * dp[2], xp);
    cart(a, p0[0] - eps * dp[0], p0[1] - eps * dp[1], p0[2] - eps * dp[2], xm);
    for (k = 0; k < 3; k++) {
        v[k] = xp[k] - xm[k];
        len += v[k] * v[k];
    }
    for (k = 0; k < 3; k++)
        v[k] /= sqrt(len);
}

/* BL (r, th, ph) of a Mino state, from the state's definition (mino.h:
 * w = 1/r, n = (sin th cos ps, sin th sin ps, cos th), phi = ps + pr). */
static void mino_bl(const double *m, double p[3])
{
    p[0] = 1.0 / m[CR_M_W];
    p[1] = acos(m[CR_M_NZ] / sqrt(m[CR_M_NX] * m[CR_M_NX] + m[CR_M_NY] * m[CR_M_NY] +
                                  m[CR_M_NZ] * m[CR_M_NZ]));
    p[2] = atan2(m[CR_M_NY], m[CR_M_NX]) + m[CR_M_PR];
}

static void test_kerr_cartesian_units(void **state)
{
    uint64_t seed = 777;
    double worst_x = 0.0, worst_v = 0.0, worst_s = 0.0;
    int it;
    (void)state;
    for (it = 0; it < 300; it++) {
        double a = 0.2 + 0.79 * cr_test_rand(&seed);
        double r = 2.2 + 20.0 * cr_test_rand(&seed);
        double th = 0.2 + 2.7 * cr_test_rand(&seed);
        double ph = CR_TWO_PI * cr_test_rand(&seed);
        double dp[3], x[3], xw[3], v[3], vw[3], vl = 0.0, sth, sph;
        double yb[CR_NY], m[CR_MN], dm[CR_MN], mp[CR_MN], mm[CR_MN], p0[3], pp[3], pm[3];
        double xp[3], xm[3], len = 0.0, d[3];
        cr_frame f;
        cr_geo g;
        cr_mino c;
        double nn[3];
        int k;
        /* positions */
        cr_bl_to_cart(a, r, th, ph, x);
        cart(a, r, th, ph, xw);
        for (k = 0; k < 3; k++)
            worst_x = fmax(worst_x, fabs(x[k] - xw[k]) / r);
        /* velocities: the Jacobian against central differences */
        for (k = 0; k < 3; k++)
            dp[k] = 2.0 * cr_test_rand(&seed) - 1.0;
        cr_bl_vel_to_cart(a, r, th, ph, dp[0], dp[1], dp[2], v);
        cart_dir_fd(a, (double[3]){r, th, ph}, dp, 1e-5, vw);
        for (k = 0; k < 3; k++)
            vl += v[k] * v[k];
        for (k = 0; k < 3; k++)
            worst_v = fmax(worst_v, fabs(v[k] / sqrt(vl) - vw[k]));
        /* sky directions of a ray from a static observer at (r + 5, th, ph)
         * under both integrators: the direction of d/dlambda of (2.2.8) */
        frame_init(&f, 1.0, a, 0.0, r + 5.0, th, ph, CR_INTEG_RK4);
        cr_frame_prepare(&f);
        for (k = 0; k < 3; k++)
            nn[k] = 2.0 * cr_test_rand(&seed) - 1.0;
        {
            double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            for (k = 0; k < 3; k++)
                nn[k] /= l;
        }
        cr_camera_ray(&f, nn, &g, yb);
        {
            double k1[CR_NY], u[4];
            cr_metric_point pt;
            cr_geo_rhs_full(&g, yb, k1, u, &pt);
            cr_sky_direction(a, yb, u[3], &sth, &sph);
            cart_dir_fd(a, (double[3]){yb[CR_Y_R], yb[CR_Y_TH], yb[CR_Y_PH]},
                        (double[3]){u[1], u[2], u[3]}, 1e-6, vw);
            worst_s = fmax(worst_s, fabs(cos(sth) - vw[2]));
            worst_s = fmax(worst_s, fabs(sin(sth) * cos(sph) - vw[0]));
            worst_s = fmax(worst_s, fabs(sin(sth) * sin(sph) - vw[1]));
        }
        /* Mino: position and direction of motion from the state's definition */
        cr_mino_from_bl(&g, yb, f.w_stop, &c, m);
        cr_mino_cart(a, m, x);
        mino_bl(m, p0);
        cart(a, p0[0], p0[1], p0[2], xw);
        for (k = 0; k < 3; k++)
            worst_x = fmax(worst_x, fabs(x[k] - xw[k]) / r);
        cr_mino_rhs(&c, m, dm);
        for (k = 0; k < CR_MN; k++) {
            mp[k] = m[k] + 1e-6 * dm[k];
            mm[k] = m[k] - 1e-6 * dm[k];
        }
        mino_bl(mp, pp);
        mino_bl(mm, pm);
        cart(a, pp[0], pp[1], pp[2], xp);
        cart(a, pm[0], pm[1], pm[2], xm);
        for (k = 0; k < 3; k++) {
            d[k] = xp[k] - xm[k];
            len += d[k] * d[k];
        }
        cr_mino_sky_direction(&c, m, &sth, &sph);
        worst_s = fmax(worst_s, fabs(cos(sth) - d[2] / sqrt(len)));
        worst_s = fmax(worst_s, fabs(sin(sth) * cos(sph) - d[0] / sqrt(len)));
        worst_s = fmax(worst_s, fabs(sin(sth) * sin(sph) - d[1] / sqrt(len)));
    }
    print_message("(2.2.8): positions off by %.2g r, velocity directions by %.2g, sky "
                  "directions (rk4 and mino) by %.2g (tol 1e-12, 1e-7, 1e-6)\n",
                  worst_x, worst_v, worst_s);
    assert_true(worst_x < 1e-12);
    assert_true(worst_v < 1e-7);
    assert_true(worst_s < 1e-6);
}

/* --- 5. a sphere entered and left within one step ----------------------- */

/* Outcome and ratio check of a radial ray through a sphere of radius R at
 * r = rc; returns 1 when right. */
static int one_step_sphere(int integ, double tol, double rc, double R, long *steps_empty,
                           cr_pixel *out)
{
    const double r_o = 40.0, r_hit = rc + R;
    const double z = sqrt(1.0 - 2.0 / r_hit) / sqrt(1.0 - 2.0 / r_o);
    double n[3] = {-1.0, 0.0, 0.0};
    cr_frame f, g;
    cr_sphere sp;
    memset(&sp, 0, sizeof sp);
    sp.color = cr_rgb_make(0, 0, 255);
    sp.n_lat = sp.n_lon = 2;
    sp.r = rc;
    sp.theta = 0.5 * CR_PI;
    sp.phi = 0.4;
    sp.radius = R;
    cr_sphere_prepare(&sp, 0.0);
    frame_init(&f, 1.0, 0.0, 0.0, r_o, 0.5 * CR_PI, 0.4, integ);
    f.step_multiplier = 2.0;
    f.tolerance = tol;
    g = f;
    cr_frame_prepare(&g);
    *steps_empty = trace_dir(&g, n).steps; /* the same ray without the sphere */
    f.spheres = &sp;
    f.n_spheres = 1;
    cr_frame_prepare(&f);
    *out = trace_dir(&f, n);
    return out->outcome == CR_OUT_SPHERE && fabs(out->redshift / z - 1.0) < 1e-6;
}

static void test_sphere_within_one_step(void **state)
{
    const double R = 0.3;
    int k, ok;
    long steps;
    cr_pixel px;
    (void)state;
    /* rk4, step_multiplier 2: steps of ~2 M in r */
    for (k = 0; k < 8; k++) {
        double rc = 20.0 + 0.37 * k;
        if (!one_step_sphere(CR_INTEG_RK4, 1e-8, rc, R, &steps, &px))
            fail_msg("rk4: sphere of radius %g at r = %g on the line of sight: outcome %d, "
                     "ratio %.10f, want sphere at r = %g",
                     R, rc, px.outcome, px.redshift, rc + R);
    }
    print_message("rk4 (step_multiplier 2): the radial ray from r = 40 reaches the horizon in "
                  "%ld steps; a sphere of radius %g on it is hit at 8 positions\n",
                  steps, R);
    assert_true(steps < 30); /* long steps, or the test means nothing */
    /* mino, tolerance 1e-3 and the default */
    {
        const double tols[] = {1e-3, cr_trace_defaults().tolerance};
        int t;
        for (t = 0; t < 2; t++) {
            long steps_mino = 0;
            for (k = 0; k < 8; k++) {
                double rc = 20.0 + 0.37 * k;
                ok = one_step_sphere(CR_INTEG_MINO, tols[t], rc, R, &steps, &px);
                steps_mino = steps;
                if (!ok)
                    fail_msg("mino, tol %g: sphere of radius %g at r = %g on the line of "
                             "sight: outcome %d, ratio %.10f, want sphere at r = %g",
                             tols[t], R, rc, px.outcome, px.redshift, rc + R);
            }
            print_message("mino (tol %g): the radial ray reaches the horizon in %ld steps; the "
                          "sphere is hit at 8 positions\n",
                          tols[t], steps_mino);
            assert_true(steps_mino < 10);
        }
    }
}

/* --- 6. ratio of an off-equator source with a != 0 ---------------------- */

static void test_redshift_off_equator(void **state)
{
    const double a = 0.9, q = 0.3, R = 5.0, r_o = 30.0;
    uint64_t seed = 4242;
    double worst = 0.0;
    int integ, it;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        cr_frame f;
        cr_sphere sp;
        cr_pixel px;
        double z = sqrt(kn_minus_gtt(1.0, a, q, R, 0.0)) / sqrt(kn_minus_gtt(1.0, a, q, r_o, 0.0));
        origin_sphere(&sp, a, R);
        frame_init(&f, 1.0, a, q, r_o, 0.0, 0.0, integ);
        f.spheres = &sp;
        f.n_spheres = 1;
        cr_frame_prepare(&f);
        px = cr_trace_pixel(&f, 20, 20);
        print_message("%s: ray down the axis meets the sphere at r = 5: ratio %.12f, want "
                      "%.12f (equator would give %.12f)\n",
                      integ_name(integ), px.redshift, z,
                      sqrt(kn_minus_gtt(1.0, a, q, R, 0.5 * CR_PI)) /
                          sqrt(kn_minus_gtt(1.0, a, q, r_o, 0.0)));
        assert_int_equal(px.outcome, CR_OUT_SPHERE);
        assert_true(fabs(px.redshift / z - 1.0) < 1e-9);
    }
    for (it = 0; it < 1000; it++) {
        cr_frame f;
        double a2 = 0.95 * cr_test_rand(&seed), q2 = 0.3 * cr_test_rand(&seed);
        double ro = 8.0 + 50.0 * cr_test_rand(&seed), tho = 0.05 + 3.0 * cr_test_rand(&seed);
        double r = 2.1 + 30.0 * cr_test_rand(&seed), th = CR_PI * cr_test_rand(&seed);
        double want, got, pk[4];
        /* any photon: the ratio of two static 4-velocities uses only p_t */
        pk[0] = 0.1 + 3.0 * cr_test_rand(&seed);
        pk[1] = 4.0 * cr_test_rand(&seed) - 2.0;
        pk[2] = 4.0 * cr_test_rand(&seed) - 2.0;
        pk[3] = 8.0 * cr_test_rand(&seed) - 4.0;
        frame_init(&f, 1.0, a2, q2, ro, tho, 0.0, CR_INTEG_MINO);
        cr_frame_prepare(&f);
        want = kn_minus_gtt(1.0, a2, q2, r, th) > 0.0
                   ? sqrt(kn_minus_gtt(1.0, a2, q2, r, th)) /
                         sqrt(kn_minus_gtt(1.0, a2, q2, ro, tho))
                   : -1.0;
        got = cr_redshift_static(&f, pk, pk, r, th);
        worst = fmax(worst, fabs(got - want) / fabs(want));
    }
    /* cr_redshift_static is the general ratio (p.u_obs)/(p.u_em) of shift.h
     * with both 4-velocities static: equal to the closed form to rounding
     * (a few ulp of the divisions and square roots) */
    print_message("cr_redshift_static (the general shift, both ends static) vs the closed form "
                  "sqrt(-g_tt)|s / sqrt(-g_tt)|o at 1000 random (r, theta, p): worst %.2g "
                  "(tol 1e-14)\n",
                  worst);
    assert_true(worst < 1e-14);
}

/* --- 7. err_mean and err_std -------------------------------------------- */

static void test_error_statistics(void **state)
{
    double *vals = malloc((size_t)(cr_trace_defaults().max_steps + 1) * sizeof *vals);
    int integ, i;
    (void)state;
    assert_non_null(vals);
    for (integ = 0; integ < 2; integ++) {
        cr_frame f;
        double worst_m = 0.0, worst_s = 0.0;
        frame_init(&f, 1.0, 0.7, 0.2, 30.0, 1.2, 0.0, integ);
        cr_frame_prepare(&f);
        /* the loop below has the trace loop's ends but the step-0 miss: keep
         * the boundary beyond the observer, where no ray starts outside it */
        f.r_max = f.observer.r + 1.0;
        f.w_sky = 1.0 / f.r_max;
        for (i = 0; i < 6; i++) {
            double n[3], y[CR_NY], mean = 0.0, var = 0.0, turns = 0.0;
            cr_geo g;
            cr_ray ray, mine;
            cr_pixel px;
            long nv = 0, steps = 0, k;
            cr_camera_pixel_dir(&f, 4.0 + 6.5 * i, 14.0 + 2.0 * i, n);
            cr_camera_ray(&f, n, &g, y);
            cr_ray_from_bl(&f, &g, y, &ray);
            mine = ray;
            px = cr_trace_loop(&f, &ray);
            /* the loop's steps, the statistics kept here */
            for (;;) {
                double e;
                if (cr_ray_at_horizon(&f, &mine))
                    break;
                e = cr_ray_begin(&mine);
                if (e >= 0.0 && isfinite(e))
                    vals[nv++] = e;
                if (cr_ray_escaping(&f, &mine))
                    break;
                assert_true(steps < f.max_steps);
                assert_int_equal(cr_ray_advance(&f, &mine), 0);
                steps++;
                cr_ray_commit(&f, &mine, &turns);
            }
            assert_true(nv > 10);
            for (k = 0; k < nv; k++)
                mean += vals[k];
            mean /= nv;
            for (k = 0; k < nv; k++)
                var += (vals[k] - mean) * (vals[k] - mean);
            var /= nv;
            assert_int_equal(px.steps, steps);
            assert_true(sqrt(var) > 0.1 * mean); /* a sequence worth testing on */
            worst_m = fmax(worst_m, fabs(px.err_mean - mean) / mean);
            worst_s = fmax(worst_s, fabs(px.err_std - sqrt(var)) / sqrt(var));
            if (i == 0)
                print_message("%s: ray of %ld steps: err_mean %.4g, err_std %.4g; here %.4g, "
                              "%.4g\n",
                              integ_name(integ), steps, px.err_mean, px.err_std, mean,
                              sqrt(var));
        }
        print_message("%s: err_mean, err_std against two-pass statistics: worst %.2g, %.2g "
                      "(tol 1e-9)\n",
                      integ_name(integ), worst_m, worst_s);
        assert_true(worst_m < 1e-9);
        assert_true(worst_s < 1e-9);
    }
    free(vals);
}

/* --- 8. null-error bounds ----------------------------------------------- */

static void test_null_error_bounds(void **state)
{
    static const char *const scenes[] = {"listing-7.1.1-schwarzschild-disc.yml",
                                         "listing-7.2.1-kerr-disc.yml"};
    const int w = 33, h = 25;
    int integ, k, i;
    (void)state;
    for (integ = 0; integ < 2; integ++)
        for (k = 0; k < 2; k++) {
            char path[1024];
            cr_scene s;
            cr_err err;
            cr_frame f;
            cr_sphere sp[4];
            cr_trace_settings ts = {.integrator = integ,
                                    .tolerance = cr_trace_defaults().tolerance,
                                    .step_multiplier = cr_trace_defaults().step_multiplier,
                                    .horizon_epsilon = cr_trace_defaults().horizon_epsilon,
                                    .max_steps = cr_trace_defaults().max_steps,
                                    .max_turns = cr_trace_defaults().max_turns};
            cr_pixel *px = calloc((size_t)w * h, sizeof *px);
            double mm = 0.0, ms = 0.0, bm, bs;
            /* 10x the largest values measured: mino (monitor ~ tol)
             * err_mean 0.93 tol, err_std 0.57 tol (at tol 1e-8 and 1e-7);
             * rk4 (c = 1/32) err_mean 8.6e-9, err_std 1.28e-8 */
            if (integ == CR_INTEG_MINO) {
                bm = 10.0 * cr_trace_defaults().tolerance;
                bs = 6.0 * cr_trace_defaults().tolerance;
            } else {
                bm = 9e-8;
                bs = 1.3e-7;
            }
            snprintf(path, sizeof path, "%s/scenes/%s", CR_SOURCE_DIR, scenes[k]);
            if (cr_scene_load(path, &s, &err))
                fail_msg("%s", err.msg);
            if (cr_scene_frame(&s, 8, 18, w, h, &ts, &f, sp, &err))
                fail_msg("%s", err.msg);
            assert_int_equal(cr_cpu_render(&f, 2, px, NULL, NULL, NULL, &err), 0);
            for (i = 0; i < w * h; i++) {
                mm = fmax(mm, px[i].err_mean);
                ms = fmax(ms, px[i].err_std);
            }
            print_message("%s, %s: largest err_mean %.3g (bound %.2g), err_std %.3g (bound "
                          "%.2g)\n",
                          scenes[k], integ_name(integ), mm, bm, ms, bs);
            assert_true(mm > 0.0 && mm < bm);
            assert_true(ms > 0.0 && ms < bs);
            cr_scene_free(&s);
            free(px);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_disc_chessboard),
        cmocka_unit_test(test_disc_over_the_pole),
        cmocka_unit_test(test_sphere_chessboard),
        cmocka_unit_test(test_camera_rotation_signs),
        cmocka_unit_test(test_kerr_cartesian_sphere),
        cmocka_unit_test(test_kerr_cartesian_sky),
        cmocka_unit_test(test_kerr_cartesian_units),
        cmocka_unit_test(test_sphere_within_one_step),
        cmocka_unit_test(test_redshift_off_equator),
        cmocka_unit_test(test_error_statistics),
        cmocka_unit_test(test_null_error_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
