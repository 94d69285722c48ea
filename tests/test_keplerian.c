/* Keplerian disc (accretion.model: keplerian): the shift g of circular-orbit emitters seen by
 * the frame's observer, through the whole pipeline (scene -> frame ->
 * cr_trace_loop). Known answers:
 *  - face-on Schwarzschild ring seen from infinity: the photons have L = 0,
 *    so g = 1/u^t = sqrt(1 - 3M/r) exactly (to the located hit radius);
 *  - edge-on ring: the extremes of g are those of photons leaving along the
 *    orbit, g = sqrt(1 - 3M/r) / (1 -+ sqrt(M/(r - 2M))) (b = L/E = +-r /
 *    sqrt(1 - 2M/r), Omega b = sqrt(M/(r - 2M))); they bound g of every
 *    photon from that radius, and a thin ring [r, r + dr] seen at
 *    inclination 89.5 deg lies inside them and within 1.5 % of them;
 *  - the approaching side (image left: the disc turns counter-clockwise
 *    about +z, image right is toward increasing phi) has g > 1;
 *  - Mino and RK4 give the same g on the same disc pixels, plunging matter
 *    included (its g needs the ray's p_r, from each integrator's state);
 *  - plunging matter (inside_isco: plunging), face-on Schwarzschild from
 *    infinity: a photon reaching the axis has L = 0 and Carter constant
 *    b^2 E^2 (b = sqrt(alpha^2 + beta^2), the pixel's impact parameter), so
 *    at the equator (1 - 2/r) p_r^2 = 1/(1 - 2/r) - b^2/r^2, p_r < 0 (inward:
 *    the direct image meets the plane before periapsis) and
 *    g = 1 / (u^t + p_r u^r) with u of the matter falling from r = 6 with
 *    E = sqrt(8/9), L = sqrt(12): u^t = E/(1 - 2/r), (u^r)^2 = E^2 -
 *    (1 - 2/r)(1 + L^2/r^2); the pixels are black and bolometric 0;
 *  - the bolometric value g^4 F / F_max of the face-on disc against
 *    g = sqrt(1 - 3/r) and the directly integrated flux (cr_orbit_flux);
 *  - the physical temperature scale: M = 10 M_sun, mdot = 0.1 Eddington,
 *    Schwarzschild: T_peak from Page & Thorne's closed form by hand;
 *  - the CSV of a Keplerian disc: redshift = g, hit_r, bolometric; the
 *    grey levels of b_<k>.png. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "output/output.h"
#include "input/scene.h"
#include "testutil.h"

static void frame_from(const char *text, int integ, int w, int h, cr_frame *f, cr_scene *s)
{
    cr_err err;
    cr_trace_settings ts = {.integrator = integ,
                            .tolerance = 1e-10,
                            .step_multiplier = cr_trace_defaults().step_multiplier / 4,
                            .horizon_epsilon = cr_trace_defaults().horizon_epsilon,
                            .max_steps = cr_trace_defaults().max_steps,
                            .max_turns = cr_trace_defaults().max_turns};
    if (cr_scene_load_string(text, strlen(text), "kep.yml", s, &err))
        fail_msg("%s", err.msg);
    if (cr_scene_frame(s, 0, 1, w, h, &ts, f, NULL, &err))
        fail_msg("%s", err.msg);
}

/* The pixel at fractional image position (x, y) for an observer at infinity. */
static cr_pixel trace_at(const cr_frame *f, double x, double y)
{
    cr_ray ray;
    double alpha, beta;
    cr_camera_screen(f, x, y, &alpha, &beta);
    cr_camera_ray_at_infinity(f, alpha, beta, &ray.c, ray.m);
    cr_ray_mino_start(f, &ray);
    return cr_trace_loop(f, &ray);
}

/* Face-on: bisect along the centre row for the inner edge of the direct
 * image, where the hit radius -> r_in; its g against sqrt(1 - 3/r_in). */
static void face_on_case(const char *radius, double r_in)
{
    char text[512];
    cr_frame f;
    cr_scene s;
    double lo = 0.0, hi = 0.0, x, want = sqrt(1.0 - 3.0 / r_in);
    int w = 201, h = 201, it;
    cr_pixel p;
    snprintf(text, sizeof text,
             "metric: {m: 1, a: 0, q: 0}\n"
             "observer: {r: inf, theta: 0, phi: 0, hextent: 60}\n"
             "accretion: {model: keplerian, radius: %s}\n",
             radius);
    frame_from(text, CR_INTEG_MINO, w, h, &f, &s);
    /* centre column 100; the pixel scale is 60/201 M */
    /* from alpha = r_in + 3 (inside the direct image) inward in steps of
     * 0.05 M to the first ray that misses the disc: the inner edge */
    hi = 100.0 + (r_in + 3.0) / (60.0 / 201.0);
    assert_int_equal(trace_at(&f, hi, 100.0).outcome, CR_OUT_DISC);
    for (x = hi;; hi = x) {
        x = hi - 0.05 / (60.0 / 201.0);
        assert_true(x > 100.0);
        if (trace_at(&f, x, 100.0).outcome != CR_OUT_DISC)
            break;
    }
    lo = x;
    for (it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (trace_at(&f, mid, 100.0).outcome == CR_OUT_DISC)
            hi = mid;
        else
            lo = mid;
    }
    p = trace_at(&f, hi, 100.0);
    print_message("face-on r_in = %g: g = %.12f, sqrt(1-3/r) = %.12f, diff %.2e\n", r_in,
                  p.redshift, want, p.redshift - want);
    assert_int_equal(p.outcome, CR_OUT_DISC);
    assert_true(fabs(p.redshift - want) < 1e-6);
    cr_scene_free(&s);
}

static void test_face_on(void **state)
{
    (void)state;
    face_on_case("[30]", 6.0);    /* inner edge at the ISCO (6M) by default */
    face_on_case("[10, 30]", 10.0);
}

static void test_edge_on(void **state)
{
    const double r = 10.0, dr = 0.02;
    cr_frame f;
    cr_scene s;
    int w = 801, h = 41, i, j, imax = -1, imin = -1;
    double gmax = 0.0, gmin = 10.0;
    double sq = sqrt(1.0 / (r - 2.0)), g_blue = sqrt(1.0 - 3.0 / r) / (1.0 - sq),
           g_red = sqrt(1.0 - 3.0 / r) / (1.0 + sq);
    (void)state;
    frame_from("metric: {m: 1, a: 0, q: 0}\n"
               "observer: {r: inf, theta: 89.5, phi: 0, hextent: 30, vextent: 1.5}\n"
               "accretion: {model: keplerian, radius: [10, 10.02]}\n",
               CR_INTEG_MINO, w, h, &f, &s);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            cr_pixel p = cr_trace_pixel(&f, i, j);
            if (p.outcome != CR_OUT_DISC)
                continue;
            if (p.redshift > gmax) {
                gmax = p.redshift;
                imax = i;
            }
            if (p.redshift < gmin) {
                gmin = p.redshift;
                imin = i;
            }
        }
    print_message("edge-on r = %g (+%g), inclination 89.5 deg: g max %.6f at column %d "
                  "(formula %.6f), g min %.6f at column %d (formula %.6f)\n",
                  r, dr, gmax, imax, g_blue, gmin, imin, g_red);
    /* approaching side on the left and blueshifted */
    assert_true(imax >= 0 && imax < w / 2 && gmax > 1.0);
    assert_true(imin > w / 2 && gmin < 1.0);
    /* the formula is the extreme over every photon leaving the ring's
     * radius (|b| <= r / sqrt(1 - 2M/r), the tangential photon), so the
     * image's values lie inside it; a thin ring seen 0.5 deg off edge-on and
     * sampled at 30/801 M a pixel gets within 1.5 % of it (measured 1.1 %
     * blue, 0.6 % red) */
    assert_true(gmax < g_blue && gmax > g_blue * (1.0 - 1.5e-2));
    assert_true(gmin > g_red && gmin < g_red * (1.0 + 1.5e-2));
    cr_scene_free(&s);
}

/* A static observer at finite distance on the axis (theta = 0): every ray
 * has L = 0, so g = u^t_obs / u^t_em = sqrt(1 - 3M/r) / sqrt(1 - 2M/r_o) for
 * Schwarzschild, at every disc pixel, with r its hit radius (hit_r). Checks
 * the observer's side of g (its 4-velocity), which the observer at infinity
 * cannot see. */
static void test_static_observer_on_axis(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: 50, theta: 0, phi: 0, hfov: 40}\n"
                               "accretion: {model: keplerian, radius: [6, 20]}\n";
    enum { W = 33, H = 33 };
    int integ, i, j, n = 0;
    double worst = 0.0;
    (void)state;
    for (integ = 0; integ < 2; integ++) {
        cr_scene s;
        cr_frame f;
        frame_from(text, integ ? CR_INTEG_RK4 : CR_INTEG_MINO, W, H, &f, &s);
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                cr_pixel p = cr_trace_pixel(&f, i, j);
                double want;
                if (p.outcome != CR_OUT_DISC)
                    continue;
                want = sqrt(1.0 - 3.0 / p.hit_r) / sqrt(1.0 - 2.0 / 50.0);
                worst = fmax(worst, fabs(p.redshift - want));
                n++;
            }
        cr_scene_free(&s);
    }
    print_message("static observer on the axis at r = 50: %d disc pixels, worst |g - "
                  "sqrt(1-3/r)/sqrt(1-2/50)| = %.2e (tol 1e-9)\n",
                  n, worst);
    assert_true(n > 100);
    assert_true(worst < 1e-9);
}

static void test_integrators_agree(void **state)
{
    const char *text = "metric: {m: 1, a: 0.6, q: 0.2}\n"
                       "observer: {r: 60, theta: 80, phi: 0, hfov: 30}\n"
                       "accretion: {model: keplerian, radius: [15], temperature: 6000, "
                       "inside_isco: plunging}\n";
    cr_frame fm, fr;
    cr_scene sm, sr;
    int w = 48, h = 24, i, j, n = 0, blue = 0, plunge = 0;
    double worst = 0.0;
    (void)state;
    frame_from(text, CR_INTEG_MINO, w, h, &fm, &sm);
    frame_from(text, CR_INTEG_RK4, w, h, &fr, &sr);
    for (j = 0; j < h; j++)
        for (i = 0; i < w; i++) {
            cr_pixel a = cr_trace_pixel(&fm, i, j), b = cr_trace_pixel(&fr, i, j);
            if (a.outcome != CR_OUT_DISC || b.outcome != CR_OUT_DISC)
                continue;
            n++;
            blue += a.redshift > 1.0;
            /* plunging matter: g uses the ray's p_r, from each integrator's
             * own state (g_rr u^r under rk4, -(dw/dtau)/D under mino) */
            plunge += a.hit_r < fm.disc.r_isco;
            if (fabs(a.redshift - b.redshift) > worst)
                worst = fabs(a.redshift - b.redshift);
        }
    print_message("mino vs rk4: %d disc pixels (%d on plunging matter), worst |dg| %.3g, %d with "
                  "g > 1\n",
                  n, plunge, worst, blue);
    assert_true(n > 50 && blue > 0 && plunge > 5);
    assert_true(worst < 1e-5);
    cr_scene_free(&sm);
    cr_scene_free(&sr);
}

/* Face-on Schwarzschild disc with plunging matter, seen from infinity:
 * the pixels of the centre row whose rays meet the plane inside the ISCO
 * against the closed form of the header. */
static void test_plunging(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: inf, theta: 0, phi: 0, hextent: 30}\n"
                               "accretion: {model: keplerian, radius: [20], inside_isco: plunging}\n";
    static const char none[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: inf, theta: 0, phi: 0, hextent: 30}\n"
                               "accretion: {model: keplerian, radius: [20]}\n";
    const double E = sqrt(8.0 / 9.0), L = sqrt(12.0);
    cr_frame f, f0;
    cr_scene s, s0;
    int n = 0, i;
    double worst = 0.0, g_in = 0.0, g_out = 0.0, r_in_last = 0.0;
    (void)state;
    frame_from(text, CR_INTEG_MINO, 401, 401, &f, &s);
    frame_from(none, CR_INTEG_MINO, 401, 401, &f0, &s0);
    for (i = 0; i < 2000; i++) {
        double x = 200.0 + 200.0 * i / 2000.0, alpha, beta, b, r, A, pr, ut, ur2, g;
        cr_pixel p = trace_at(&f, x, 200.0), p0 = trace_at(&f0, x, 200.0);
        if (p.outcome != CR_OUT_DISC)
            continue;
        if (p.hit_r >= 6.0) {
            if (g_out == 0.0 && r_in_last > 0.0)
                g_out = p.redshift;
            assert_int_equal(p0.outcome, CR_OUT_DISC);
            continue;
        }
        /* without plunging matter the ray passes through (and may meet the
         * disc beyond the ISCO on a later crossing) */
        assert_true(p0.outcome != CR_OUT_DISC || p0.hit_r >= 6.0);
        assert_true(p.color.r == 0 && p.color.g == 0 && p.color.b == 0);
        assert_true(p.bolo == 0.0);
        cr_camera_screen(&f, x, 200.0, &alpha, &beta);
        b = sqrt(alpha * alpha + beta * beta);
        r = p.hit_r;
        A = 1.0 - 2.0 / r;
        pr = -sqrt((1.0 / A - b * b / (r * r)) / A);
        ut = E / A;
        ur2 = E * E - A * (1.0 + L * L / (r * r));
        g = 1.0 / (ut + pr * -sqrt(ur2 > 0.0 ? ur2 : 0.0));
        worst = fmax(worst, fabs(p.redshift - g));
        g_in = p.redshift;
        r_in_last = r;
        n++;
    }
    print_message("plunging matter, face-on Schwarzschild: %d pixels inside the ISCO, worst |g - "
                  "closed form| %.2e (tol 1e-7); across the ISCO g = %.6f (r = %.4f) -> %.6f\n",
                  n, worst, g_in, r_in_last, g_out);
    assert_true(n > 20);
    assert_true(worst < 1e-7);
    /* continuous across the ISCO: within the change of one pixel step */
    assert_true(fabs(g_in - g_out) < 0.01);
    cr_scene_free(&s);
    cr_scene_free(&s0);
}

/* The bolometric value of a face-on disc seen from infinity: g^4 F / F_max
 * with g = sqrt(1 - 3/r) and F by direct quadrature (tol 2e-5: the flux
 * table's interpolation error is below 1e-5 of F_max). */
static void test_bolometric(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: inf, theta: 0, phi: 0, hextent: 50}\n"
                               "accretion: {model: keplerian, radius: [20]}\n";
    cr_frame f;
    cr_scene s;
    int i, n = 0;
    double worst = 0.0, top = 0.0;
    (void)state;
    frame_from(text, CR_INTEG_MINO, 201, 201, &f, &s);
    for (i = 0; i < 101; i++) {
        cr_pixel p = cr_trace_pixel(&f, 100 + i, 100);
        double g, want;
        if (p.outcome != CR_OUT_DISC)
            continue;
        g = sqrt(1.0 - 3.0 / p.hit_r);
        want = g * g * g * g * cr_orbit_flux(&f.metric, 1, 6.0, p.hit_r) / f.disc.flux.F_max;
        worst = fmax(worst, fabs(p.bolo - want));
        top = fmax(top, p.bolo);
        n++;
    }
    print_message("bolometric g^4 F / F_max, face-on: %d pixels, worst error %.2e (tol 2e-5), "
                  "largest %.4f\n",
                  n, worst, top);
    assert_true(n > 20 && top > 0.2);
    assert_true(worst < 2e-5);
    cr_scene_free(&s);
}

/* T_peak from mass_msun = 10, mdot_edd = 0.1, Schwarzschild. By hand (the
 * constants of orbit.h: CODATA 2018 G, sigma_SB, m_p, sigma_T, IAU M_sun):
 * Page & Thorne's closed form at a = 0, x = sqrt(r/M), x0 = sqrt(6),
 *   F M^2 / Mdot = 3 / (8 pi) [x - x0 - (sqrt3/2) ln((x - sqrt3)/(x0 - sqrt3))
 *                  + (sqrt3/2) ln((x + sqrt3)/(x0 + sqrt3))] / (x^4 (x^3 - 3x)),
 * peaks at r = 9.550928 M with F_max = 1.3678110819830e-5 Mdot/M^2;
 * eta = 1 - sqrt(8/9) = 0.05719095841794; Mdot_Edd = 4 pi G M m_p /
 * (sigma_T c eta) = 2.4456941748372e16 kg/s; sigma T^4 = F_max (0.1
 * Mdot_Edd) c^6 / (G M)^2 gives T_peak = 3948869.6997 K (mpmath, 30
 * digits). Tolerance 1e-7 relative (F_max of the table search to 1e-10). */
static void test_physical_temperature(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: 100, theta: 80, phi: 0, hfov: 20}\n"
                               "accretion: {model: keplerian, radius: [100], mass_msun: 10, "
                               "mdot_edd: 0.1}\n";
    cr_frame f;
    cr_scene s;
    (void)state;
    frame_from(text, CR_INTEG_MINO, 8, 8, &f, &s);
    print_message("T_peak (10 M_sun, 0.1 Eddington, a = 0) = %.6f K, by hand 3948869.6997 K, "
                  "rel. diff %.2e (tol 1e-7); r_peak %.6f (9.550928)\n",
                  f.disc.t_peak, f.disc.t_peak / 3948869.6997 - 1.0, f.disc.flux.r_peak);
    assert_true(fabs(f.disc.t_peak / 3948869.6997 - 1.0) < 1e-7);
    assert_true(fabs(f.disc.flux.r_peak - 9.550928) < 1e-5);
    cr_scene_free(&s);
}

/* The CSV of a Keplerian disc frame: every disc row's redshift is the
 * pixel's g (the Keplerian ratio recomputed from hit_r would need the ray;
 * here: equal to the traced pixel, and within the bounds of the edge-on
 * extremes is tested above), its bolometric column g^4 F(hit_r) / F_max from
 * the direct quadrature and g (tol 2e-5), and every other row -1. */
/* Extreme peak temperatures through the disc's own chain (exposure from
 * cr_disc_keplerian_prepare, cr_disc_keplerian_color): at 1e300 K no disc
 * pixel is black (the XYZ of such a peak is near the largest double), and at
 * 50 to 700 K no disc pixel is magenta (green below both red and blue by
 * more than 16), in an edge-on view whose approaching side is blueshifted
 * (the brightest pixels). */
static void test_extreme_temperatures(void **state)
{
    static const double temps[] = {1e300, 50.0, 300.0, 700.0};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof temps / sizeof temps[0]; i++) {
        char text[512];
        cr_frame f;
        cr_scene s;
        int x, y, n_disc = 0, n_lit = 0, worst = -255;
        snprintf(text, sizeof text,
                 "metric: {m: 1, a: 0.9, q: 0}\n"
                 "observer: {r: inf, theta: 80, phi: 0, hextent: 50}\n"
                 "accretion: {model: keplerian, radius: [20], temperature: %.17g}\n",
                 temps[i]);
        frame_from(text, CR_INTEG_MINO, 48, 24, &f, &s);
        for (y = 0; y < 24; y++)
            for (x = 0; x < 48; x++) {
                cr_pixel p = trace_at(&f, x + 0.5, y + 0.5);
                int m;
                if (p.outcome != CR_OUT_DISC)
                    continue;
                n_disc++;
                n_lit += (p.color.r | p.color.g | p.color.b) != 0;
                m = (p.color.r < p.color.b ? p.color.r : p.color.b) - p.color.g;
                worst = m > worst ? m : worst;
            }
        print_message("peak %.4g K: %d disc pixels, %d not black, min(R, B) - G at most %d\n",
                      temps[i], n_disc, n_lit, worst);
        assert_true(n_disc > 50);
        /* a cool disc is dark but near its peak: the Wien tail falls by
         * orders of magnitude with a few per cent of temperature */
        assert_true(temps[i] > 1e9 ? n_lit == n_disc : n_lit > 0);
        assert_true(worst <= 16);
        cr_scene_free(&s);
    }
}

static void test_csv(void **state)
{
    static const char text[] = "metric: {m: 1, a: 0, q: 0}\n"
                               "observer: {r: inf, theta: 0, phi: 0, hextent: 50}\n"
                               "accretion: {model: keplerian, radius: [20]}\n";
    enum { W = 24, H = 24 };
    cr_frame f;
    cr_scene s;
    cr_pixel px[W * H];
    cr_err err;
    char line[512];
    FILE *fp = tmpfile();
    int i, rows = 0, disc = 0;
    double worst = 0.0;
    (void)state;
    assert_non_null(fp);
    frame_from(text, CR_INTEG_MINO, W, H, &f, &s);
    for (i = 0; i < W * H; i++)
        px[i] = cr_trace_pixel(&f, i % W, i / W);
    assert_int_equal(cr_output_csv_stream(fp, "kep.csv", px, W, H, &err), 0);
    rewind(fp);
    assert_non_null(fgets(line, sizeof line, fp));
    assert_string_equal(line, "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,"
                              "bolometric,order,theta_turns,delay\n");
    while (fgets(line, sizeof line, fp)) {
        int x, y;
        double z, hr, hp, bolo;
        char out[16];
        assert_int_equal(sscanf(line, "%d,%d,%*d,%*d,%*d,%*d,%lf,%*f,%*f,%15[a-z],%lf,%lf,%lf", &x,
                                &y, &z, out, &hr, &hp, &bolo),
                         7);
        rows++;
        if (strcmp(out, "disc") != 0) {
            assert_true(bolo == -1.0);
            continue;
        }
        disc++;
        assert_true(z == px[y * W + x].redshift && hr == px[y * W + x].hit_r);
        worst = fmax(worst, fabs(bolo - pow(1.0 - 3.0 / hr, 2.0) *
                                            cr_orbit_flux(&f.metric, 1, 6.0, hr) /
                                            f.disc.flux.F_max));
    }
    print_message("CSV: %d rows, %d disc rows, bolometric column vs g^4 F / F_max worst %.2e "
                  "(tol 2e-5)\n",
                  rows, disc, worst);
    assert_int_equal(rows, W * H);
    assert_true(disc > 50);
    assert_true(worst < 2e-5);
    fclose(fp);
    cr_scene_free(&s);
}

/* b_<k>.png's grey level 255 (log10 v + 3) / 4 of v = cr_pixel.bolo on a
 * disc hit, clamped; black elsewhere (exact bytes). */
static void test_bolometric_png(void **state)
{
    static const struct {
        int outcome;
        double v;
        int grey;
    } cases[] = {{CR_OUT_DISC, 10.0, 255},  {CR_OUT_DISC, 100.0, 255}, {CR_OUT_DISC, 1.0, 191},
                 {CR_OUT_DISC, 0.1, 128},   {CR_OUT_DISC, 1e-3, 0},    {CR_OUT_DISC, 1e-5, 0},
                 {CR_OUT_DISC, 0.0, 0},     {CR_OUT_DISC, -1.0, 0},    {CR_OUT_SKY, 1.0, 0},
                 {CR_OUT_SPHERE, 1.0, 0},   {CR_OUT_HORIZON, 1.0, 0}};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        cr_pixel p;
        cr_rgb c;
        memset(&p, 0, sizeof p);
        p.outcome = (uint8_t)cases[k].outcome;
        p.bolo = cases[k].v;
        c = cr_bolometric_color(&p);
        assert_int_equal(c.r, cases[k].grey);
        assert_int_equal(c.g, cases[k].grey);
        assert_int_equal(c.b, cases[k].grey);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_face_on),
        cmocka_unit_test(test_edge_on),
        cmocka_unit_test(test_integrators_agree),
        cmocka_unit_test(test_static_observer_on_axis),
        cmocka_unit_test(test_plunging),
        cmocka_unit_test(test_bolometric),
        cmocka_unit_test(test_physical_temperature),
        cmocka_unit_test(test_extreme_temperatures),
        cmocka_unit_test(test_csv),
        cmocka_unit_test(test_bolometric_png),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
