/* Observers that move and the camera's projections (observer.h).
 *
 * Checked against formulas written out here, independently of observer.h:
 * - the boosted tetrad is orthonormal, g(e_a, e_b) = eta_ab within 1e-9, at
 *   2000 random points (Kerr-Newman holes, r from r+ + 0.02 M to 40 M, inside
 *   the ergosphere too) for every motion, and its e_0 is the motion's
 *   4-velocity: infall has u_t = -1, u_phi = 0 (E = 1, L = 0), u^theta = 0;
 *   the ZAMO has u_phi = 0; the orbit has u^r = u^theta = 0 and satisfies
 *   the circular-geodesic condition d_r g_tt + 2 Omega d_r g_tphi +
 *   Omega^2 d_r g_phph = 0 (central differences of the metric, 1e-6); an
 *   explicit v is what the ZAMO measures (ZAMO tetrad from omega =
 *   -g_tphi/g_phph, alpha^2 = (g_tphi^2 - g_tt g_phph)/g_phph), 1e-12;
 * - the ZAMO tetrad is the static one when a = 0 (1e-15), and the ZAMO
 *   tetrad boosted by the static observer's velocity is the paper's static
 *   tetrad (camera.h) for a != 0 (1e-12);
 * - aberration: the direction of each pixel of a moving observer, taken to
 *   the ZAMO frame through the ray's own momentum, follows
 *   cos th' = (cos th - v)/(1 - v cos th) (th: from v in the observer's
 *   frame, th': in the ZAMO's) with the azimuth about v unchanged, within
 *   1e-9, at r_o = 1e4 and 1e5 and also close to the hole (it is exact
 *   locally);
 * - the sky seen by an infalling observer: Schwarzschild g = 1/(1 + v n_r)
 *   with v = sqrt(2M/r) and n_r the outward component of the pixel's
 *   direction (special-relativistic Doppler from the static frame, where the
 *   sky at infinity shows g = 1/sqrt(1 - 2M/r)), 1e-12; Kerr-Newman: g =
 *   p.u / E with u the free-fall 4-velocity from the geodesic equations
 *   (u^t = A/(Delta Sigma), u^phi = a (2Mr - Q^2)/(Delta Sigma),
 *   u^r = -sqrt((r^2 + a^2)(2Mr - Q^2))/Sigma), 1e-12, both integrators;
 * - a full-sphere equirectangular image of a Schwarzschild hole from the
 *   equator is left-right and up-down symmetric (outcome and redshift), its
 *   shadow is the disc of angular radius psi, sin psi = 3 sqrt(3) M/r
 *   sqrt(1 - 2M/r), around the forward direction (pixels 1e-3 rad from the
 *   edge exempt); its layout is the paper's skymap (6.10.1): a static
 *   observer at theta = 90 deg, phi = 0 sees direction (theta_s, phi_s) at
 *   pixel x = (2 pi - phi_s) W / 2 pi, y = theta_s H / pi (1e-9 px);
 * - every projection inverts: cr_camera_dir_pixel(cr_camera_pixel_dir(i, j))
 *   = (i, j) within 1e-9 px at random rotations; the fisheye is
 *   equidistant; a direction outside the fisheye's image circle maps to no
 *   pixel;
 * - the fisheye's picture is its image circle: pixels outside it are
 *   "outside", untraced; pixels inside are traced at the equidistant angle
 *   (test_fisheye_image_circle);
 * - the scene keys (motion names, a velocity with animated components,
 *   retrograde, projection) and every refusal (|v| >= 1, orbit where none
 *   exists or off the equator, static inside the ergosphere, unknown
 *   projection or motion, fisheye fov > 360 deg, motion or projection at
 *   infinity, fov keys on an equirectangular view), each naming the key.
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

#define DEG (CR_PI / 180.0)

/* A prepared frame with an observer of the given motion and projection at
 * (r, th, phi = 0); v is used for CR_MOTION_VELOCITY. */
static void obs_frame(cr_frame *f, double a, double q, double r, double th, int motion,
                      const double v[3], int proj, double hfov, int w, int h)
{
    cr_test_empty_frame(f, 1.0, a, q, r, th);
    f->observer.motion = motion;
    f->observer.projection = proj;
    if (v) {
        f->observer.v[0] = v[0];
        f->observer.v[1] = v[1];
        f->observer.v[2] = v[2];
    }
    f->observer.hfov = hfov;
    f->observer.vfov = hfov * h / w;
    if (proj == CR_PROJ_RECTILINEAR)
        f->observer.vfov = 2.0 * atan(tan(0.5 * hfov) * h / w);
    f->width = w;
    f->height = h;
    cr_frame_prepare(f);
}

/* The ZAMO tetrad written out from the metric (not observer.h): rows e_0,
 * e_r, e_th, e_ph (BL components), off the axis. */
static void zamo_ref(const cr_metric *mt, double r, double th, double e[4][4])
{
    double g[4][4], om, al;
    cr_test_metric4(mt, r, th, g);
    om = -g[0][3] / g[3][3];
    al = sqrt((g[0][3] * g[0][3] - g[0][0] * g[3][3]) / g[3][3]);
    memset(e, 0, 16 * sizeof(double));
    e[0][0] = 1.0 / al;
    e[0][3] = om / al;
    e[1][1] = 1.0 / sqrt(g[1][1]);
    e[2][2] = 1.0 / sqrt(g[2][2]);
    e[3][3] = 1.0 / sqrt(g[3][3]);
}

/* Lower an index: out_mu = g_mu nu u^nu. */
static void lower(const double g[4][4], const double *u, double *out)
{
    int i, j;
    for (i = 0; i < 4; i++) {
        out[i] = 0.0;
        for (j = 0; j < 4; j++)
            out[i] += g[i][j] * u[j];
    }
}

static double dot4(const double *p, const double *u)
{
    return p[0] * u[0] + p[1] * u[1] + p[2] * u[2] + p[3] * u[3];
}

/* ---- the tetrad ----------------------------------------------------------- */

static void test_tetrad_orthonormal(void **state)
{
    uint64_t seed = 0x13a5c0ffee;
    double worst = 0.0, worst_u = 0.0, worst_geo = 0.0, worst_v = 0.0;
    int n_motion[CR_MOTION_COUNT_] = {0}, it;
    (void)state;
    for (it = 0; it < 2000; it++) {
        double a = (2.0 * cr_test_rand(&seed) - 1.0) * 0.99;
        double q = cr_test_rand(&seed) * 0.99 * sqrt(1.0 - a * a);
        double th = 0.02 + cr_test_rand(&seed) * (CR_PI - 0.04);
        int motion = (int)(cr_test_rand(&seed) * CR_MOTION_COUNT_);
        cr_metric mt;
        double rp, r, v[3] = {0.0, 0.0, 0.0}, g[4][4], u_dn[4];
        cr_frame f;
        int i, j;
        mt.m = 1.0;
        mt.a = a;
        mt.q = q;
        rp = cr_metric_r_plus(&mt);
        r = rp + 0.02 + cr_test_rand(&seed) * 40.0;
        if (motion == CR_MOTION_ORBIT) {
            cr_orbit o;
            th = 0.5 * CR_PI;
            if (!cr_orbit_eval(&mt, cr_orbit_sense(&mt, it % 2), r, &o))
                continue;
        }
        if (motion == CR_MOTION_STATIC && !(cr_metric_minus_gtt(&mt, r, th) > 1e-3))
            continue;
        if (motion == CR_MOTION_VELOCITY) {
            double s = 0.999 * cr_test_rand(&seed), n = 0.0;
            for (i = 0; i < 3; i++) {
                v[i] = 2.0 * cr_test_rand(&seed) - 1.0;
                n += v[i] * v[i];
            }
            for (i = 0; i < 3; i++)
                v[i] *= s / sqrt(n);
        }
        obs_frame(&f, a, q, r, th, motion, v, CR_PROJ_RECTILINEAR, 1.0, 8, 8);
        f.observer.retrograde = it % 2 == 0;
        cr_frame_prepare(&f);
        n_motion[motion]++;
        cr_test_metric4(&mt, r, th, g);
        for (i = 0; i < 4; i++)
            for (j = 0; j < 4; j++) {
                double eta = i == j ? (i == 0 ? -1.0 : 1.0) : 0.0;
                double d = fabs(cr_test_dot(g, f.tetrad[i], f.tetrad[j]) - eta);
                worst = fmax(worst, d);
            }
        assert_true(f.tetrad[0][0] > 0.0); /* future-directed */
        lower(g, f.tetrad[0], u_dn);
        switch (motion) {
        case CR_MOTION_INFALL:
            worst_u = fmax(worst_u, fmax(fabs(u_dn[0] + 1.0), fabs(u_dn[3])));
            assert_true(f.tetrad[0][2] == 0.0 && f.tetrad[0][1] < 0.0);
            break;
        case CR_MOTION_ZAMO:
            worst_u = fmax(worst_u, fabs(u_dn[3]) / (1.0 + fabs(u_dn[0])));
            assert_true(f.tetrad[0][1] == 0.0 && f.tetrad[0][2] == 0.0);
            break;
        case CR_MOTION_STATIC:
            assert_true(f.tetrad[0][1] == 0.0 && f.tetrad[0][2] == 0.0 &&
                        f.tetrad[0][3] == 0.0);
            break;
        case CR_MOTION_ORBIT: {
            /* circular geodesic: the radial force vanishes */
            double gp[4][4], gm[4][4], h = 1e-5 * r, om = f.tetrad[0][3] / f.tetrad[0][0];
            double c[3];
            cr_orbit o;
            cr_orbit_eval(&mt, cr_orbit_sense(&mt, !f.observer.retrograde), r, &o);
            assert_true(f.tetrad[0][1] == 0.0 && f.tetrad[0][2] == 0.0);
            worst_u = fmax(worst_u, fabs(om - o.omega) / fabs(o.omega));
            cr_test_metric4(&mt, r + h, th, gp);
            cr_test_metric4(&mt, r - h, th, gm);
            c[0] = (gp[0][0] - gm[0][0]) / (2.0 * h);
            c[1] = (gp[0][3] - gm[0][3]) / (2.0 * h);
            c[2] = (gp[3][3] - gm[3][3]) / (2.0 * h);
            worst_geo = fmax(worst_geo, fabs(c[0] + 2.0 * om * c[1] + om * om * c[2]) /
                                            (fabs(c[0]) + fabs(2.0 * om * c[1]) +
                                             fabs(om * om * c[2])));
            break;
        }
        default: {
            /* what the ZAMO measures: v^i = (u . e_i) / (-u . e_0) */
            double z[4][4], ud[4];
            zamo_ref(&mt, r, th, z);
            lower(g, f.tetrad[0], ud);
            for (i = 0; i < 3; i++)
                worst_v = fmax(worst_v, fabs(dot4(ud, z[i + 1]) / -dot4(ud, z[0]) - v[i]));
        }
        }
    }
    print_message("boosted tetrads: |g(e_a, e_b) - eta_ab| <= %.2e (tol 1e-9); 4-velocity "
                  "checks %.2e (tol 1e-12); orbit radial force %.2e (tol 1e-6); ZAMO-measured "
                  "v %.2e (tol 1e-12); motions tried: static %d, zamo %d, orbit %d, infall %d, "
                  "velocity %d\n",
                  worst, worst_u, worst_geo, worst_v, n_motion[0], n_motion[1], n_motion[2],
                  n_motion[3], n_motion[4]);
    assert_true(worst <= 1e-9);
    assert_true(worst_u <= 1e-12);
    assert_true(worst_geo <= 1e-6);
    assert_true(worst_v <= 1e-12);
    for (it = 0; it < CR_MOTION_COUNT_; it++)
        assert_true(n_motion[it] > 100);
}

static void test_zamo_is_static_when_a_is_zero(void **state)
{
    const double qs[] = {0.0, 0.5, 0.9}, rs[] = {2.5, 6.0, 1e4}, ths[] = {0.3, 1.2, 0.0};
    double worst = 0.0, worst_boost = 0.0;
    int i, k, a, b;
    (void)state;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++) {
            cr_frame fs, fz;
            obs_frame(&fs, 0.0, qs[i], rs[k], ths[k], CR_MOTION_STATIC, NULL,
                      CR_PROJ_RECTILINEAR, 1.0, 8, 8);
            obs_frame(&fz, 0.0, qs[i], rs[k], ths[k], CR_MOTION_ZAMO, NULL,
                      CR_PROJ_RECTILINEAR, 1.0, 8, 8);
            for (a = 0; a < 4; a++)
                for (b = 0; b < 4; b++)
                    worst = fmax(worst, fabs(fs.tetrad[a][b] - fz.tetrad[a][b]) /
                                            fmax(1.0, fabs(fs.tetrad[a][b])));
        }
    /* a != 0: the ZAMO tetrad boosted by the static observer's velocity is the
     * static tetrad of camera.h (static is the boost that cancels the
     * dragging) */
    for (i = 0; i < 3; i++) {
        const double spin[] = {0.5, 0.9, -0.99};
        cr_frame fs;
        double e[4][4], v[3], out[4][4];
        obs_frame(&fs, spin[i], 0.1, 2.3 + i, 1.0, CR_MOTION_STATIC, NULL, CR_PROJ_RECTILINEAR,
                  1.0, 8, 8);
        cr_zamo_tetrad(&fs.metric, fs.observer.r, fs.observer.theta, 0, e, NULL, NULL, NULL);
        assert_int_equal(cr_observer_zamo_velocity(&fs.metric, &fs.observer, 0, v), 1);
        assert_true(v[2] != 0.0 && fabs(v[2]) < 1.0);
        cr_boost_tetrad(e, v, out);
        for (a = 0; a < 4; a++)
            for (b = 0; b < 4; b++)
                worst_boost = fmax(worst_boost, fabs(out[a][b] - fs.tetrad[a][b]) /
                                                    fmax(1.0, fabs(fs.tetrad[a][b])));
    }
    print_message("a = 0: ZAMO vs static tetrad %.2e (tol 1e-15); a != 0: boosted ZAMO vs "
                  "static %.2e (tol 1e-12)\n",
                  worst, worst_boost);
    assert_true(worst <= 1e-15);
    assert_true(worst_boost <= 1e-12);
}

/* ---- aberration ------------------------------------------------------------ */

/* The worst deviation from the aberration formula over the pixels of a 360
 * deg fisheye of an observer moving with v (ZAMO frame) at (r, th). */
static double aberration_worst(double a, double r, double th, const double v[3])
{
    const int w = 33, h = 33;
    cr_frame f;
    double z[4][4], g[4][4], speed, vh[3], worst = 0.0;
    int i, j, k;
    obs_frame(&f, a, 0.0, r, th, CR_MOTION_VELOCITY, v, CR_PROJ_FISHEYE, CR_TWO_PI, w, h);
    zamo_ref(&f.metric, r, th, z);
    cr_test_metric4(&f.metric, r, th, g);
    speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (k = 0; k < 3; k++)
        vh[k] = v[k] / speed;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double n[3], y[CR_NY], p[4], N[3], c, cp, np[3], Np[3], ln = 0.0, lN = 0.0, pe0;
            double sx, sy;
            cr_geo ge;
            cr_camera_screen(&f, i, j, &sx, &sy);
            if (sx * sx + sy * sy > CR_PI * CR_PI)
                continue; /* beyond 180 deg from forward: the same directions again */
            cr_camera_pixel_dir(&f, i, j, n);
            cr_camera_ray(&f, n, &ge, y);
            p[0] = ge.E;
            p[1] = g[1][1] * y[CR_Y_UR];
            p[2] = g[2][2] * y[CR_Y_UTH];
            p[3] = ge.L;
            /* look direction in the ZAMO frame: n_i = (p . e_i) / (p . e_0) */
            pe0 = dot4(p, z[0]);
            for (k = 0; k < 3; k++)
                N[k] = dot4(p, z[k + 1]) / pe0;
            c = n[0] * vh[0] + n[1] * vh[1] + n[2] * vh[2];
            cp = N[0] * vh[0] + N[1] * vh[1] + N[2] * vh[2];
            worst = fmax(worst, fabs(cp - (c - speed) / (1.0 - speed * c)));
            for (k = 0; k < 3; k++) {
                np[k] = n[k] - c * vh[k];
                Np[k] = N[k] - cp * vh[k];
                ln += np[k] * np[k];
                lN += Np[k] * Np[k];
            }
            if (ln > 1e-12)
                for (k = 0; k < 3; k++)
                    worst = fmax(worst, fabs(np[k] / sqrt(ln) - Np[k] / sqrt(lN)));
        }
    return worst;
}

static void test_aberration(void **state)
{
    const double dirs[4][3] = {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}, {0.6, -0.48, 0.64}};
    const double speeds[] = {0.3, 0.9, 0.99};
    const double rs[] = {1e4, 1e5, 6.0, 1.8};
    double worst = 0.0;
    int d, s, k;
    (void)state;
    for (k = 0; k < 4; k++)
        for (d = 0; d < 4; d++)
            for (s = 0; s < 3; s++) {
                double v[3], w;
                int i;
                for (i = 0; i < 3; i++)
                    v[i] = speeds[s] * dirs[d][i];
                /* r = 1.8 at a = 0.9, theta = 80 deg: inside the ergosphere */
                w = aberration_worst(0.9, rs[k], 80.0 * DEG, v);
                worst = fmax(worst, w);
            }
    print_message("aberration cos th' = (cos th - v)/(1 - v cos th), azimuth kept: worst "
                  "%.2e over 33x33 fisheye pixels, 4 directions x 3 speeds x r_o = 1e4, 1e5, "
                  "6, 1.8 (tol 1e-9)\n",
                  worst);
    assert_true(worst <= 1e-9);
}

/* ---- Doppler: the sky seen while falling ---------------------------------- */

/* Kerr-Newman free fall from rest at infinity (E = 1, L = 0, Carter 0),
 * from the geodesic equations. */
static void infall_u(const cr_metric *mt, double r, double th, double u[4])
{
    cr_metric_point p;
    double w;
    cr_metric_eval(mt, r, th, &p);
    w = 2.0 * mt->m * r - mt->q * mt->q;
    u[0] = p.A_ / (p.delta * p.sigma);
    u[1] = -sqrt((r * r + mt->a * mt->a) * w) / p.sigma;
    u[2] = 0.0;
    u[3] = mt->a * w / (p.delta * p.sigma);
}

static void infall_sky(double a, double q, double r, double th, int integ, double *worst,
                       int *n_sky)
{
    const int w = 21, h = 21;
    cr_frame f;
    double u[4], g[4][4];
    int i, j;
    obs_frame(&f, a, q, r, th, CR_MOTION_INFALL, NULL, CR_PROJ_FISHEYE, CR_TWO_PI, w, h);
    f.integrator = integ;
    infall_u(&f.metric, r, th, u);
    cr_test_metric4(&f.metric, r, th, g);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double n[3], y[CR_NY], p[4], want;
            cr_geo ge;
            cr_pixel px = cr_trace_pixel(&f, i, j);
            if (px.outcome != CR_OUT_SKY)
                continue;
            cr_camera_pixel_dir(&f, i, j, n);
            if (a == 0.0 && q == 0.0) {
                want = 1.0 / (1.0 + sqrt(2.0 / r) * n[0]);
            } else {
                cr_camera_ray(&f, n, &ge, y);
                p[0] = ge.E;
                p[1] = g[1][1] * y[CR_Y_UR];
                p[2] = g[2][2] * y[CR_Y_UTH];
                p[3] = ge.L;
                want = dot4(p, u) / p[0];
            }
            *worst = fmax(*worst, fabs(px.redshift / want - 1.0));
            (*n_sky)++;
        }
}

static void test_infall_sky_shift(void **state)
{
    double worst = 0.0;
    int n_sky = 0, integ;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        infall_sky(0.0, 0.0, 6.0, 1.0, integ, &worst, &n_sky);
        infall_sky(0.0, 0.0, 2.5, 0.5 * CR_PI, integ, &worst, &n_sky); /* inside r = 3M */
        infall_sky(0.9, 0.2, 1.7, 0.5 * CR_PI, integ, &worst, &n_sky); /* ergosphere */
        infall_sky(0.7, 0.0, 8.0, 0.4, integ, &worst, &n_sky);
    }
    print_message("infalling observer, sky pixels: |g / predicted - 1| <= %.2e over %d pixels "
                  "(tol 1e-12)\n",
                  worst, n_sky);
    assert_true(n_sky > 500);
    assert_true(worst <= 1e-12);
}

/* ---- projections ---------------------------------------------------------- */

static void test_equirect_symmetric(void **state)
{
    const int w = 72, h = 36;
    const double r = 8.0;
    double psi = asin(3.0 * sqrt(3.0) / r * sqrt(1.0 - 2.0 / r));
    cr_frame f;
    cr_pixel *px = malloc(sizeof *px * w * h);
    int i, j, n_h = 0, n_edge = 0;
    (void)state;
    assert_non_null(px);
    obs_frame(&f, 0.0, 0.0, r, 0.5 * CR_PI, CR_MOTION_STATIC, NULL, CR_PROJ_EQUIRECT, 0.0, w,
              h);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++)
            px[j * w + i] = cr_trace_pixel(&f, i, j);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            const cr_pixel *p = &px[j * w + i], *lr = &px[j * w + (w - 1 - i)],
                           *ud = &px[(h - 1 - j) * w + i];
            double n[3], ang;
            assert_int_equal(p->outcome, lr->outcome);
            assert_int_equal(p->outcome, ud->outcome);
            assert_true(fabs(p->redshift - lr->redshift) <= 1e-12);
            assert_true(fabs(p->redshift - ud->redshift) <= 1e-12);
            cr_camera_pixel_dir(&f, i, j, n);
            ang = acos(fmin(1.0, -n[0])); /* forward is -e_r */
            n_h += p->outcome == CR_OUT_HORIZON;
            if (fabs(ang - psi) < 1e-3) {
                n_edge++;
                continue;
            }
            assert_int_equal(p->outcome, ang < psi ? CR_OUT_HORIZON : CR_OUT_SKY);
        }
    print_message("equirectangular 72x36, a = 0, r = 8: left-right and up-down symmetric; %d "
                  "shadow pixels within psi = %.4f rad of forward (%d within 1e-3 rad of the "
                  "edge exempt)\n",
                  n_h, psi, n_edge);
    assert_true(n_h > 100);
    free(px);
}

/* Paper's skymap layout (6.10.1): row y at theta_s = y pi / H, column x at
 * phi_s = 2 pi - x 2 pi / W, for the static observer at theta = 90 deg,
 * phi = 0 looking at the hole (local e_r = +x, e_th = -z, e_ph = +y). */
static void test_equirect_is_skymap_layout(void **state)
{
    const int w = 64, h = 32;
    cr_frame f;
    double worst = 0.0;
    int i, j;
    (void)state;
    obs_frame(&f, 0.0, 0.0, 50.0, 0.5 * CR_PI, CR_MOTION_STATIC, NULL, CR_PROJ_EQUIRECT, 0.0,
              w, h);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double n[3], d[3], ph, th, x, y, dx;
            cr_camera_pixel_dir(&f, i, j, n);
            d[0] = n[0];
            d[1] = n[2];
            d[2] = -n[1];
            ph = atan2(d[1], d[0]);
            if (ph < 0.0)
                ph += CR_TWO_PI;
            th = acos(d[2]);
            x = (CR_TWO_PI - ph) * w / CR_TWO_PI;
            y = th * h / CR_PI;
            dx = fmod(x - (i + 0.5) + 1.5 * w, (double)w) - 0.5 * w;
            worst = fmax(worst, fmax(fabs(dx), fabs(y - (j + 0.5))));
        }
    print_message("equirectangular pixel centres vs the skymap layout (6.10.1): %.2e px (tol "
                  "1e-9)\n",
                  worst);
    assert_true(worst <= 1e-9);
}

static void test_projections_invert(void **state)
{
    uint64_t seed = 77;
    double worst = 0.0;
    int proj, it;
    (void)state;
    for (proj = 0; proj < CR_PROJ_COUNT_; proj++)
        for (it = 0; it < 20; it++) {
            const double fovs[] = {1.5, 2.9};
            const double ffov[] = {CR_TWO_PI, 200.0 * DEG, 90.0 * DEG};
            double v[3] = {0.3, -0.2, 0.5};
            double hfov = proj == CR_PROJ_RECTILINEAR ? fovs[it % 2]
                                                      : proj == CR_PROJ_FISHEYE ? ffov[it % 3]
                                                                                : 0.0;
            cr_frame f;
            int k;
            obs_frame(&f, 0.9, 0.1, 3.0 + 20.0 * cr_test_rand(&seed), 1.3, CR_MOTION_VELOCITY,
                      v, proj, hfov, 40, 30);
            f.observer.roll = cr_test_rand(&seed) * 6.0;
            f.observer.pitch = cr_test_rand(&seed) * 3.0 - 1.5;
            f.observer.yaw = cr_test_rand(&seed) * 6.0;
            cr_frame_prepare(&f);
            for (k = 0; k < 200; k++) {
                double i = cr_test_rand(&seed) * 40.0 - 0.5, j = cr_test_rand(&seed) * 30.0 - 0.5;
                double n[3], i2 = -1.0, j2 = -1.0, sx, sy;
                cr_camera_screen(&f, i, j, &sx, &sy);
                if (proj == CR_PROJ_FISHEYE && sx * sx + sy * sy >= CR_PI * CR_PI)
                    continue; /* beyond 180 deg: not one-to-one */
                cr_camera_pixel_dir(&f, i, j, n);
                if (proj == CR_PROJ_FISHEYE &&
                    hypot(sx, sy) > 0.5 * fmax(f.observer.hfov, f.observer.vfov)) {
                    /* a direction beyond the image circle is not in the picture */
                    assert_int_equal(cr_camera_dir_pixel(&f, n, &i2, &j2), 0);
                    continue;
                }
                assert_true(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) < 1e-14);
                assert_int_equal(cr_camera_dir_pixel(&f, n, &i2, &j2), 1);
                worst = fmax(worst, fmax(fabs(i2 - i), fabs(j2 - j)));
                if (proj == CR_PROJ_FISHEYE) {
                    /* equidistant: the angle from forward is the screen radius */
                    double c = n[0] * f.cam[0][0] + n[1] * f.cam[0][1] + n[2] * f.cam[0][2];
                    assert_true(fabs(acos(fmax(-1.0, fmin(1.0, c))) - hypot(sx, sy)) < 1e-7);
                }
            }
        }
    print_message("pixel -> direction -> pixel, 3 projections x 20 random cameras x 200 "
                  "points: %.2e px (tol 1e-9)\n",
                  worst);
    assert_true(worst <= 1e-9);
}

static void test_fisheye_edges(void **state)
{
    cr_frame f;
    double n[3];
    (void)state;
    /* 360 deg, odd size: the centre looks forward, the middle of the right
     * edge is ~180 deg round, straight up is the middle of the top edge at
     * 90 deg x (1 - 1/H) of the full 180 */
    obs_frame(&f, 0.0, 0.0, 10.0, 0.5 * CR_PI, CR_MOTION_ZAMO, NULL, CR_PROJ_FISHEYE,
              CR_TWO_PI, 21, 21);
    cr_camera_pixel_dir(&f, 10, 10, n);
    assert_true(fabs(n[0] + 1.0) < 1e-15); /* -e_r: at the hole */
    cr_camera_pixel_dir(&f, 20, 10, n);
    assert_true(fabs(acos(-n[0]) - CR_PI * 20.0 / 21.0) < 1e-12);
    assert_true(n[2] > 0.0 && fabs(n[1]) < 1e-15); /* turned through +phi */
}

/* The fisheye's picture is its image circle (camera.h cr_camera_in_image):
 * every pixel of a traced image whose centre lies farther from the image
 * centre than half the longer side (the circle of angular radius
 * max(hfov, vfov)/2 with square pixels; written here in pixels, not through
 * the screen coordinates of camera.h) has outcome "outside" and the values
 * of an untraced pixel; every other pixel is traced, and looks at the angle
 * from forward that the equidistant formula gives, (distance from the centre
 * in px) x hfov / W, within 1e-9 rad. Pixels within 1e-9 px of the circle
 * are exempt. Rectilinear and equirectangular images have no point outside. */
static void fisheye_circle_case(double hfov, int w, int h, int samples)
{
    cr_frame f;
    double R_px = 0.5 * (w > h ? w : h), worst = 0.0;
    long n_out = 0, n_in = 0, n_edge = 0;
    int i, j;
    obs_frame(&f, 0.0, 0.0, 10.0, 0.5 * CR_PI, CR_MOTION_ZAMO, NULL, CR_PROJ_FISHEYE,
              hfov * DEG, w, h);
    f.samples = samples;
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            double d = hypot(i + 0.5 - 0.5 * w, j + 0.5 - 0.5 * h);
            cr_pixel px = cr_trace_pixel(&f, i, j);
            if (fabs(d - R_px) < 1e-9) {
                n_edge++;
                continue;
            }
            if (d > R_px) {
                /* with samples > 1 the colour is the mean of the sub-rays, and
                 * steps their sum: black and 0 where every sub-ray (at most
                 * sqrt(2)/2 px from the centre) is outside too */
                int all_out = samples < 2 || d > R_px + 0.75;
                n_out++;
                if (px.outcome != CR_OUT_OUTSIDE || px.redshift != -1.0 || px.hit_r != -1.0 ||
                    px.hit_phi != -1.0 || px.bolo != -1.0 || px.object != -1 ||
                    (all_out && (px.steps != 0 || px.color.r || px.color.g || px.color.b)))
                    fail_msg("fisheye %g deg %dx%d: pixel (%d,%d) %.3f px from the centre "
                             "(circle %.1f px): outcome %d steps %u redshift %g", hfov, w, h, i,
                             j, d, R_px, px.outcome, px.steps, px.redshift);
            } else {
                double n[3], c, want = d * hfov * DEG / w;
                n_in++;
                /* (an outgoing ray from beyond the scene's radius ends as sky
                 * before its first step: steps 0 but traced) */
                if (px.outcome == CR_OUT_OUTSIDE || px.outcome == CR_OUT_NONE)
                    fail_msg("fisheye %g deg %dx%d: pixel (%d,%d) inside the circle not "
                             "traced (outcome %d)", hfov, w, h, i, j, px.outcome);
                cr_camera_pixel_dir(&f, i, j, n);
                c = n[0] * f.cam[0][0] + n[1] * f.cam[0][1] + n[2] * f.cam[0][2];
                worst = fmax(worst, fabs(acos(fmax(-1.0, fmin(1.0, c))) - want));
            }
        }
    print_message("fisheye %g deg, %dx%d, %d x %d samples: %ld pixels outside the circle of "
                  "%.1f px (all 'outside', untraced), %ld inside (all traced), %ld on it; "
                  "angle from forward vs equidistant: %.2e rad (tol 1e-9)\n",
                  hfov, w, h, samples, samples, n_out, R_px, n_in, n_edge, worst);
    assert_true(n_out > 0 && n_in > 0);
    assert_true(worst <= 1e-9);
}

static void test_fisheye_image_circle(void **state)
{
    cr_frame f;
    int proj, i, j;
    (void)state;
    fisheye_circle_case(360.0, 41, 41, 1); /* beyond 180 deg in the corners */
    fisheye_circle_case(360.0, 40, 40, 3); /* even size: no pixel centre forward */
    fisheye_circle_case(200.0, 48, 32, 1); /* circle cut by the top and bottom */
    fisheye_circle_case(200.0, 30, 30, 1);
    for (proj = CR_PROJ_RECTILINEAR; proj <= CR_PROJ_EQUIRECT; proj += CR_PROJ_EQUIRECT) {
        obs_frame(&f, 0.9, 0.0, 10.0, 1.2, CR_MOTION_ZAMO, NULL, proj, 170.0 * DEG, 33, 17);
        for (j = 0; j <= 4 * 17; j++)
            for (i = 0; i <= 4 * 33; i++) /* pixel centres and the image's own corners */
                assert_int_equal(cr_camera_in_image(&f, 0.25 * i - 0.5, 0.25 * j - 0.5), 1);
    }
}

/* ---- scene keys ------------------------------------------------------------ */

#define MET "metric: {m: 2, a: 1.8, q: 0}\n"

static int scene_frame(const char *text, int k, int n, cr_frame *f, cr_err *e)
{
    cr_scene s;
    int rc;
    e->msg[0] = '\0';
    if (cr_scene_load_string(text, strlen(text), "scene.yml", &s, e) != 0)
        return -1;
    rc = cr_scene_frame(&s, k, n, 40, 20, NULL, f, NULL, e);
    cr_scene_free(&s);
    return rc;
}

static void expect_error(const char *text, const char *needle1, const char *needle2)
{
    cr_frame f;
    cr_err e;
    if (scene_frame(text, 0, 1, &f, &e) == 0)
        fail_msg("accepted:\n%s", text);
    if (!strstr(e.msg, needle1) || (needle2 && !strstr(e.msg, needle2)))
        fail_msg("message \"%s\" lacks \"%s\" / \"%s\"", e.msg, needle1,
                 needle2 ? needle2 : "");
}

static void test_scene_keys(void **state)
{
    cr_frame f;
    cr_err e;
    (void)state;
    /* zamo inside the ergosphere (r = 3.6 = 1.8 M, r_E+ = 2 M at the equator) */
    assert_int_equal(scene_frame(MET "observer: {r: 3.6, theta: 90, phi: 0, hfov: 90, motion: "
                                     "zamo, projection: fisheye}\n",
                                 0, 1, &f, &e),
                     0);
    assert_int_equal(f.observer.motion, CR_MOTION_ZAMO);
    assert_int_equal(f.observer.projection, CR_PROJ_FISHEYE);
    assert_true(fabs(f.observer.r - 1.8) < 1e-15);  /* units of M */
    assert_true(fabs(f.tan_half_v - 0.25 * CR_PI * 20 / 40) < 1e-15); /* square pixels */
    /* infall and a retrograde orbit */
    assert_int_equal(scene_frame(MET "observer: {r: 3.6, theta: 20, phi: 0, hfov: 90, motion: "
                                     "infall}\n",
                                 0, 1, &f, &e),
                     0);
    assert_int_equal(f.observer.motion, CR_MOTION_INFALL);
    assert_int_equal(scene_frame(MET "observer: {r: 20, theta: 90, phi: 0, hfov: 90, motion: "
                                     "orbit, retrograde: true}\n",
                                 0, 1, &f, &e),
                     0);
    assert_true(f.observer.retrograde == 1 && f.tetrad[0][3] < 0.0);
    /* a velocity with an animated component, frame 2 of 3 */
    assert_int_equal(scene_frame(MET "observer: {r: 30, theta: 90, phi: 0, motion: "
                                     "[[linear, 0, -0.8], 0.1, 0], projection: "
                                     "equirectangular}\n",
                                 2, 3, &f, &e),
                     0);
    assert_true(f.observer.v[0] == -0.8 && f.observer.v[1] == 0.1 && f.observer.v[2] == 0.0);
    assert_true(f.tan_half_h == CR_PI && f.tan_half_v == 0.5 * CR_PI);
    assert_int_equal(scene_frame(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 360, "
                                     "projection: fisheye, motion: static}\n",
                                 0, 1, &f, &e),
                     0);
    assert_true(f.tan_half_h == CR_PI);
}

static void test_scene_errors(void **state)
{
    (void)state;
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, motion: [0.6, 0, 0.8]}\n",
                 "observer.motion", "below 1");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, motion: "
                     "[[linear, 1.2, 0], 0, 0]}\n",
                 "observer.motion", "below 1");
    /* prograde photon orbit of a = 0.9 is at about 1.56 M (3.12 here) */
    expect_error(MET "observer: {r: 3, theta: 90, phi: 0, hfov: 90, motion: orbit}\n",
                 "observer.motion = orbit", "no timelike circular orbit");
    expect_error(MET "observer: {r: 30, theta: 60, phi: 0, hfov: 90, motion: orbit}\n",
                 "observer.motion = orbit", "equatorial");
    expect_error(MET "observer: {r: 3.6, theta: 90, phi: 0, hfov: 90}\n", "observer.r",
                 "inside the ergosphere");
    expect_error(MET "observer: {r: 3.6, theta: 90, phi: 0, hfov: 90, motion: static}\n",
                 "observer.r", "no static observer");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, projection: cube}\n",
                 "observer.projection", "unknown projection");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, motion: float}\n",
                 "observer.motion", "unknown motion");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 361, projection: fisheye}\n",
                 "observer.hfov", "360");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 200, vfov: 400, projection: "
                     "fisheye}\n",
                 "observer.vfov", "360");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 179}\n", "observer.hfov",
                 "flat screen");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, projection: "
                     "equirectangular}\n",
                 "observer.hfov", "full sphere");
    expect_error(MET "observer: {r: inf, theta: 90, phi: 0, hextent: 30, motion: zamo}\n",
                 "observer.motion", "is static");
    expect_error(MET "observer: {r: inf, theta: 90, phi: 0, hextent: 30, projection: "
                     "fisheye}\n",
                 "observer.projection", "flat image plane");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, retrograde: true}\n",
                 "observer.retrograde", "motion: orbit");
    expect_error(MET "observer: {r: 30, theta: 0, phi: 0, hfov: 90, motion: [0, 0.1, 0]}\n",
                 "observer.motion", "polar axis");
    expect_error(MET "observer: {r: 30, theta: 90, phi: 0, hfov: 90, motion: [linear, 0, 1]}\n",
                 "observer.motion[0]", NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetrad_orthonormal),
        cmocka_unit_test(test_zamo_is_static_when_a_is_zero),
        cmocka_unit_test(test_aberration),
        cmocka_unit_test(test_infall_sky_shift),
        cmocka_unit_test(test_equirect_symmetric),
        cmocka_unit_test(test_equirect_is_skymap_layout),
        cmocka_unit_test(test_projections_invert),
        cmocka_unit_test(test_fisheye_edges),
        cmocka_unit_test(test_fisheye_image_circle),
        cmocka_unit_test(test_scene_keys),
        cmocka_unit_test(test_scene_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
