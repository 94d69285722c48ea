/* The spectrum of -t s (src/output/spectrum.c, core/spectrum.h): the line
 * profile of a face-on Schwarzschild disc against the profile that follows
 * from g(r) = sqrt(1 - 3M/r) and the emissivity over the exact image of the
 * disc (exact_orbit.h); flux conservation (the continuum's integral over
 * energy equals the bolometric image summed with its solid angles); the
 * antialiasing samples counted (samples 2 equals the image of twice the
 * size); the Planck tail against quadrature; bad spectrum keys refused. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/spectrum.h"
#include "core/trace.h"
#include "exact_orbit.h"
#include "input/scene.h"
#include "testfs.h"
#include "output/spectrum.h"

static void frame_from(const char *text, int samples, int w, int h, cr_frame *f, cr_scene *s)
{
    cr_err err;
    cr_trace_settings ts = cr_trace_defaults();
    ts.tolerance = 1e-9;
    ts.samples = samples;
    if (cr_scene_load_string(text, strlen(text), "spec.yml", s, &err))
        fail_msg("%s", err.msg);
    if (cr_scene_frame(s, 0, 1, w, h, &ts, f, NULL, &err))
        fail_msg("%s", err.msg);
}

static cr_pixel *render(const cr_frame *f)
{
    cr_pixel *px = malloc(sizeof *px * (size_t)f->width * f->height);
    assert_non_null(px);
    for (int j = 0; j < f->height; j++)
        for (int i = 0; i < f->width; i++)
            px[(size_t)j * f->width + i] = cr_trace_pixel(f, i, j);
    return px;
}

/* P(x) against Simpson's rule on t^3 / (e^t - 1) (1e-10 relative). */
static void test_planck_tail(void **state)
{
    const double xs[] = {0.0, 1e-6, 0.01, 0.5, 0.999, 1.0, 1.001, 2.0, 5.0, 20.0, 60.0};
    (void)state;
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
        double x = xs[i], hi = x + 80.0, s = 0.0;
        int n = 400000;
        double h = (hi - x) / n;
        for (int k = 0; k <= n; k++) {
            double t = x + k * h, v = t > 0.0 ? t * t * t / expm1(t) : 0.0;
            s += v * (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
        }
        s *= h / 3.0;
        if (fabs(cr_spec_planck_tail(x) - s) > 1e-10 * s)
            fail_msg("P(%g) = %.15g, quadrature %.15g", x, cr_spec_planck_tail(x), s);
    }
    assert_true(fabs(cr_spec_planck_tail(0.0) - pow(CR_PI, 4) / 15.0) < 1e-15);
}

#define LINE_BINS 40
#define G_LO 0.70
#define G_HI 0.96

static const char *const face_on =
    "metric: {m: 1, a: 0, q: 0}\n"
    "observer: {r: inf, theta: 0, phi: 0, hextent: 70}\n"
    "accretion: {model: keplerian, radius: [6, 30]}\n"
    "spectrum:\n"
    "  line: {energy_kev: 1, emissivity_index: %g, bins: 40, range: [0.70, 0.96]}\n";

/* The face-on Schwarzschild disc from infinity: every ray has L = 0, so g
 * depends on r alone, g = sqrt(1 - 3/r), r(g) = 3 / (1 - g^2). The expected
 * photon flux in a bin is the integral over the image plane of
 * g^3 r^-q [r in the bin] 2 pi b db, with r(b) the radius of the ray's first
 * crossing on the disc (any order) from the exact orbit; by the midpoint rule
 * over b, then normalised as the CSV. The render samples the same plane
 * with pixels, so the bins agree to the pixel sampling: the normalised
 * profile within 3 % in L1 and its cumulative within 0.005 at every bin. */
static void line_case(double q)
{
    enum { W = 480, H = 480 };
    char text[512];
    cr_scene s;
    cr_frame f;
    cr_pixel *px;
    cr_spectrum sp;
    cr_err err;
    double want[LINE_BINS] = {0}, tw = 0.0, tg = 0.0, l1 = 0.0, cw = 0.0, cg = 0.0, dmax = 0.0;
    double w = (G_HI - G_LO) / LINE_BINS;
    int nb = 40000;
    snprintf(text, sizeof text, face_on, q);
    frame_from(text, 1, W, H, &f, &s);
    px = render(&f);
    assert_int_equal(cr_spectrum_compute(&f, px, &s.spectrum, &sp, &err), 0);
    for (int i = 0; i < nb; i++) {
        double b = (i + 0.5) * 35.0 / nb, r, g;
        int k;
        orbit o;
        (void)o;
        {
            /* the first crossing of the ray on the disc [6, 30] */
            orbit_make(&o, b, 0.0);
            r = 0.0;
            for (int n = 0; n < 6; n++) {
                double rr = crossing_r(&o, 0.5 * CR_PI + n * CR_PI, f.r_stop);
                if (rr == 0.0)
                    break;
                if (rr >= 6.0 && rr <= 30.0) {
                    r = rr;
                    break;
                }
            }
        }
        if (r == 0.0)
            continue;
        g = sqrt(1.0 - 3.0 / r);
        k = (int)floor((g - G_LO) / w);
        if (k >= 0 && k < LINE_BINS)
            want[k] += g * g * g * pow(r, -q) * 2.0 * CR_PI * b * (35.0 / nb);
    }
    for (int k = 0; k < LINE_BINS; k++) {
        tw += want[k];
        tg += sp.line_sum[k];
    }
    assert_true(tw > 0.0 && tg > 0.0);
    for (int k = 0; k < LINE_BINS; k++) {
        double a = want[k] / (tw * w), c = sp.line_sum[k] / (tg * w);
        l1 += fabs(a - c) * w;
        cw += want[k] / tw;
        cg += sp.line_sum[k] / tg;
        if (fabs(cw - cg) > dmax)
            dmax = fabs(cw - cg);
    }
    /* and the absolute scale: the image-plane area is the pixel area */
    print_message("q = %g: line profile L1 distance %.4f (allowed 0.03), largest cumulative "
                  "difference %.4f (allowed 0.005), total photon flux %.6g, exact %.6g\n",
                  q, l1, dmax, tg, tw);
    assert_true(l1 < 0.03);
    assert_true(dmax < 0.005);
    assert_true(fabs(tg - tw) < 0.005 * tw);
    cr_spectrum_free(&sp);
    free(px);
    cr_scene_free(&s);
}

static void test_line_face_on_schwarzschild(void **state)
{
    (void)state;
    line_case(3.0);
    line_case(0.0);
}

/* The continuum's integral over energy (sum of its bins, each the exact
 * integral of the blackbody over the bin) equals the bolometric image summed
 * with the pixels' solid angles, sum of g^4 F / F_max dOmega times
 * sigma t_scale^4 F_max / pi: for a tilted Kerr disc from infinity and from a
 * finite observer (solid angles of the camera), to 1e-6 (the range holds all
 * but ~1e-9 of the flux). */
static void conservation_case(const char *text)
{
    enum { W = 120, H = 90 };
    cr_scene s;
    cr_frame f;
    cr_pixel *px;
    cr_spectrum sp;
    cr_err err;
    double cont = 0.0, bolo = 0.0, scale;
    frame_from(text, 1, W, H, &f, &s);
    px = render(&f);
    assert_int_equal(cr_spectrum_compute(&f, px, &s.spectrum, &sp, &err), 0);
    for (int k = 0; k < sp.n_cont; k++)
        cont += sp.cont_sum[k];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            const cr_pixel *p = &px[j * W + i];
            if (p->outcome == CR_OUT_DISC && p->bolo > 0.0 && p->hit_r >= f.disc.r_in)
                bolo += p->bolo * cr_spec_solid_angle(&f, i, j, 1.0);
        }
    scale = CR_STEFAN_BOLTZMANN * pow(f.disc.t_scale, 4) * f.disc.flux.F_max / CR_PI;
    print_message("continuum integral %.12g, bolometric image %.12g (relative %.2g)\n", cont,
                  bolo * scale, fabs(cont - bolo * scale) / (bolo * scale));
    assert_true(bolo > 0.0);
    assert_true(fabs(cont - bolo * scale) < 1e-6 * bolo * scale);
    cr_spectrum_free(&sp);
    free(px);
    cr_scene_free(&s);
}

static void test_flux_conservation(void **state)
{
    (void)state;
    conservation_case("metric: {m: 1, a: 0.9, q: 0}\n"
                      "observer: {r: inf, theta: 60, phi: 0, hextent: 40}\n"
                      "accretion: {model: keplerian, radius: [15], inside_isco: plunging, "
                      "mass_msun: 10, mdot_edd: 0.1}\n"
                      "spectrum: {continuum: {f_col: 1.7, bins: 300, range: [1e-6, 100]}}\n");
    conservation_case("metric: {m: 1, a: 0.7, q: 0}\n"
                      "observer: {r: 40, theta: 75, phi: 0, hfov: 50}\n"
                      "accretion: {model: keplerian, radius: [15], temperature: 2e6}\n"
                      "spectrum: {continuum: {f_col: 2.4, bins: 200, range: [1e-7, 20]}}\n");
}

/* raytracer.samples = 2: every sub-ray counts with a quarter of its pixel's
 * solid angle, so the spectrum of W x H at samples 2 is that of 2W x 2H at
 * samples 1 (the same rays, 1e-9). */
static void test_samples_count(void **state)
{
    static const char *const text =
        "metric: {m: 1, a: 0.5, q: 0}\n"
        "observer: {r: 30, theta: 70, phi: 0, hfov: 60}\n"
        "accretion: {model: keplerian, radius: [12], temperature: 1e7}\n"
        "spectrum: {line: {bins: 30}, continuum: {bins: 20}}\n";
    cr_scene s1, s2;
    cr_frame f1, f2;
    cr_pixel *p1, *p2;
    cr_spectrum a, b;
    cr_err err;
    (void)state;
    frame_from(text, 2, 40, 30, &f1, &s1);
    frame_from(text, 1, 80, 60, &f2, &s2);
    p1 = render(&f1);
    p2 = render(&f2);
    assert_int_equal(cr_spectrum_compute(&f1, p1, &s1.spectrum, &a, &err), 0);
    assert_int_equal(cr_spectrum_compute(&f2, p2, &s2.spectrum, &b, &err), 0);
    assert_true(a.rays > 1000);
    assert_int_equal(a.rays, b.rays);
    for (int k = 0; k < a.n_line; k++)
        assert_true(fabs(a.line_sum[k] - b.line_sum[k]) <= 1e-9 * fabs(b.line_sum[k]) + 1e-300);
    for (int k = 0; k < a.n_cont; k++)
        assert_true(fabs(a.cont_sum[k] - b.cont_sum[k]) <= 1e-9 * fabs(b.cont_sum[k]) + 1e-300);
    cr_spectrum_free(&a);
    cr_spectrum_free(&b);
    free(p1);
    free(p2);
    cr_scene_free(&s1);
    cr_scene_free(&s2);
}

/* s_<k>.csv of a spectrum given by hand, every value against the
 * definitions worked out here: the line (E0 = 6.4 keV, bins [2, 3, 4, 5, 6]
 * keV holding photon fluxes 1, 2, 3, 4) has flux = sum / width, g = middle /
 * E0 and normalised = sum / (total x width / E0), so that sum of normalised
 * x dg is 1 (normalised 0.64, 1.28, 1.92, 2.56); the continuum (bins
 * [1, 2, 4, 8] keV holding 1, 1, 2) has normalised = sum / (total x width),
 * of integral 1 over E (0.25, 0.125, 0.125), e_kev the geometric middle. */
static void test_csv_values(void **state)
{
    double le[] = {2, 3, 4, 5, 6}, ls[] = {1, 2, 3, 4}, ce[] = {1, 2, 4, 8}, cs[] = {1, 1, 2};
    static const char *const want[] = {
        "spectrum,bin,e_lo_kev,e_hi_kev,e_kev,g,flux,normalised",
        "line,0,2,3,2.5,0.390625,1,0.64",
        "line,1,3,4,3.5,0.546875,2,1.28",
        "line,2,4,5,4.5,0.703125,3,1.92",
        "line,3,5,6,5.5,0.859375,4,2.56",
        "continuum,0,1,2,1.4142135623730951,-1,1,0.25",
        "continuum,1,2,4,2.8284271247461903,-1,0.5,0.125",
        "continuum,2,4,8,5.656854249492381,-1,0.5,0.125",
    };
    char dir[] = "/tmp/curray-test-spectrum-XXXXXX", path[4096], line[256];
    cr_spectrum s;
    cr_err err;
    FILE *fp;
    size_t n = 0;
    double integral = 0.0;
    (void)state;
    memset(&s, 0, sizeof s);
    s.e0 = 6.4;
    s.n_line = 4;
    s.n_cont = 3;
    s.line_edges = le;
    s.line_sum = ls;
    s.cont_edges = ce;
    s.cont_sum = cs;
    assert_non_null(mkdtemp(dir));
    assert_int_equal(cr_output_spectrum_csv(dir, 3, &s, &err), 0);
    snprintf(path, sizeof path, "%s/s_3.csv", dir);
    fp = fopen(path, "r");
    assert_non_null(fp);
    while (fgets(line, sizeof line, fp)) {
        double lo, hi, mid, g, flux, norm;
        line[strcspn(line, "\n")] = '\0';
        assert_true(n < sizeof want / sizeof want[0]);
        if (strcmp(line, want[n]) != 0)
            fail_msg("s_3.csv line %zu: '%s', expected '%s'", n + 1, line, want[n]);
        if (sscanf(line, "line,%*d,%lf,%lf,%lf,%lf,%lf,%lf", &lo, &hi, &mid, &g, &flux, &norm) ==
            6)
            integral += norm * (hi - lo) / s.e0;
        n++;
    }
    fclose(fp);
    assert_int_equal(n, sizeof want / sizeof want[0]);
    assert_true(fabs(integral - 1.0) < 1e-12);
    cr_test_rm_rf(dir);
}

/* Bad spectrum keys: refused with a message naming the key. */
static void test_bad_spectrum_keys(void **state)
{
    static const char *const kep = "metric: {m: 1, a: 0, q: 0}\n"
                                   "observer: {r: 30, theta: 70, phi: 0, hfov: 60}\n"
                                   "accretion: {model: keplerian, radius: [12]}\n";
    static const struct {
        const char *disc, *spec, *msg;
    } cases[] = {
        {NULL, "spectrum: {line: {bins: 10}}\n",
         "spec.yml:3:1: spectrum: the spectrum is that of a Keplerian disc, and this scene has "
         "no disc; add accretion: {model: keplerian, ...} or remove spectrum"},
        {"accretion: {color1: [255, 0, 0], resolution: [2, 2], radius: [6, 12]}\n",
         "spectrum: {line: {bins: 10}}\n",
         "spec.yml:4:1: spectrum: the spectrum is that of a Keplerian disc, and this scene has "
         "a chessboard disc; add accretion: {model: keplerian, ...} or remove spectrum"},
        {"", "spectrum: {line: {energy_kev: 0}}\n",
         "spectrum.line.energy_kev: the line's rest energy must be positive (keV), got 0"},
        {"", "spectrum: {line: {energy_kev: -6.4}}\n",
         "spectrum.line.energy_kev: the line's rest energy must be positive (keV), got -6.4"},
        {"", "spectrum: {line: {bins: 0}}\n", "spectrum.line.bins"},
        {"", "spectrum: {continuum: {bins: -3}}\n", "spectrum.continuum.bins"},
        {"", "spectrum: {line: {range: [8, 3]}}\n",
         "spectrum.line.range: the range [8, 3] keV is empty: the low end must be below the "
         "high end"},
        {"", "spectrum: {continuum: {range: [2, 2]}}\n",
         "spectrum.continuum.range: the range [2, 2] keV is empty"},
        {"", "spectrum: {line: {range: [0, 3]}}\n",
         "spectrum.line.range[0]: a photon energy must be positive (keV), got 0"},
        {"", "spectrum: {continuum: {range: [1, -3]}}\n",
         "spectrum.continuum.range[1]: a photon energy must be positive (keV), got -3"},
        {"", "spectrum: {continuum: {f_col: 0}}\n",
         "spectrum.continuum.f_col: the colour correction f_col must be positive"},
        {"", "spectrum: {lines: {}}\n", "unknown key 'lines' in spectrum"},
    };
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[1024];
        cr_scene s;
        cr_err err;
        snprintf(text, sizeof text, "%s%s%s",
                 cases[i].disc && !cases[i].disc[0] ? kep
                                                    : "metric: {m: 1, a: 0, q: 0}\n"
                                                      "observer: {r: 30, theta: 70, phi: 0, "
                                                      "hfov: 60}\n",
                 cases[i].disc ? cases[i].disc : "", cases[i].spec);
        memset(&s, 0, sizeof s);
        err.msg[0] = '\0';
        if (cr_scene_load_string(text, strlen(text), "spec.yml", &s, &err) == 0)
            fail_msg("case %zu accepted: %s", i, text);
        if (!strstr(err.msg, cases[i].msg))
            fail_msg("case %zu: '%s' does not hold '%s'", i, err.msg, cases[i].msg);
    }
    /* -t s on a scene without a Keplerian disc */
    {
        static const char *const chess = "metric: {m: 1, a: 0, q: 0}\n"
                                         "observer: {r: 30, theta: 70, phi: 0, hfov: 60}\n"
                                         "accretion: {color1: [255, 0, 0], resolution: [2, 2], "
                                         "radius: [6, 12]}\n";
        cr_scene s;
        cr_err err;
        assert_int_equal(cr_scene_load_string(chess, strlen(chess), "spec.yml", &s, &err), 0);
        assert_int_equal(cr_spectrum_check(&s, &err), -1);
        assert_string_equal(err.msg, "-t s: the spectrum is that of a Keplerian disc, and the "
                                     "scene has a chessboard disc (accretion: {model: "
                                     "keplerian, ...})");
        cr_scene_free(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planck_tail),
        cmocka_unit_test(test_line_face_on_schwarzschild),
        cmocka_unit_test(test_flux_conservation),
        cmocka_unit_test(test_samples_count),
        cmocka_unit_test(test_csv_values),
        cmocka_unit_test(test_bad_spectrum_keys),
    };
    gl_init();
    return cmocka_run_group_tests(tests, NULL, NULL);
}
