/* Blackbody colour (src/core/colour.h) against known answers.
 *
 * - Planckian locus: chromaticity (x, y) of blackbodies at 1000 .. 20000 K
 *   against published values, |dx|, |dy| <= 5e-4 (measured <= 1.3e-4).
 *   References: J. Walker's table of the CIE 1931 Planckian locus
 *   ("Colour Rendering of Spectra", specrend; 4 decimals) for 1000, 3000 and
 *   6500 K; Robertson's 1968 table of the locus in CIE 1960 (u, v)
 *   (5 decimals; x = 3u / (2u - 8v + 4), y = 2v / (2u - 8v + 4)) for 2000,
 *   4000, 5000, 10000 and 20000 K, where it agrees with Walker's to 1e-4.
 * - The table: ybar peaks at 1 at 555 nm; the three columns have equal sums
 *   to 2e-5 relative (measured 9e-6), so equal-energy white is at
 *   x = y = 1/3 to 1e-5.
 * - 6500 K is near white: linear sRGB normalised by its largest channel has
 *   every channel >= 0.93 (the 6500 K Planckian point lies 0.005 below D65
 *   in y, slightly magenta: measured G = 0.943).
 * - Cooler is redder, 1000 K to 40000 K in 250 K steps: x strictly
 *   decreases; in the displayed (gamut-mapped) linear sRGB, G/R strictly
 *   increases, and R/B strictly decreases wherever B > 0 (2000 K on in this
 *   grid; below, the locus is outside the sRGB gamut and B maps to 0); the
 *   8-bit pixels at equal luminance order accordingly.
 * - Wien: the peak of B_lambda is at b / T, b = 2.897771955e-3 m K, to 1e-6
 *   relative (golden-section search), and at 2.898e-3 / T to 1e-4.
 * - Stefan-Boltzmann: composite Simpson of B_nu over nu in [0, 50 kT/h]
 *   (4000 intervals) equals sigma T^4 / pi to 1e-6 relative.
 * - Shift: g^3 B_nu(nu/g, T) = B_nu(nu, g T) to 1e-13 relative; the XYZ of a
 *   blackbody at T seen with g equals that at g T to 1e-12 relative, so its
 *   chromaticity is the locus at g T; the integral of the observed spectrum
 *   is g^4 sigma T^4 / pi (cr_bolometric) to 1e-6.
 * - sRGB pieces: D65 to (1, 1, 1) within 2e-4, the transfer function's
 *   branches meet, known encodings, the tone curve's fixed points.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "core/colour.h"

static double rel(double a, double b)
{
    return fabs(a - b) / fabs(b);
}

static void bb_xy(double t, double g, double *x, double *y)
{
    double xyz[3];
    cr_bb_xyz(t, g, xyz);
    cr_xyz_chromaticity(xyz, x, y);
}

static void uv_to_xy(double u, double v, double xy[2])
{
    double d = 2.0 * u - 8.0 * v + 4.0;
    xy[0] = 3.0 * u / d;
    xy[1] = 2.0 * v / d;
}

#define LOCUS_TOL 5e-4

static void test_planckian_locus(void **state)
{
    struct {
        double t, x, y, u, v; /* (x, y) when u == 0, else Robertson's (u, v) */
        const char *src;
    } ref[] = {
        {1000.0, 0.6528, 0.3444, 0.0, 0.0, "Walker"},
        {2000.0, 0.0, 0.0, 0.30505, 0.35907, "Robertson"},
        {3000.0, 0.4369, 0.4041, 0.0, 0.0, "Walker"},
        {4000.0, 0.0, 0.0, 0.22511, 0.33439, "Robertson"},
        {5000.0, 0.0, 0.0, 0.21142, 0.32312, "Robertson"},
        {6500.0, 0.3135, 0.3237, 0.0, 0.0, "Walker"},
        {10000.0, 0.0, 0.0, 0.19032, 0.29326, "Robertson"},
        {20000.0, 0.0, 0.0, 0.18388, 0.27709, "Robertson"},
    };
    double worst = 0.0;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof ref / sizeof ref[0]; i++) {
        double r[2], x, y, d;
        if (ref[i].u > 0.0) {
            uv_to_xy(ref[i].u, ref[i].v, r);
        } else {
            r[0] = ref[i].x;
            r[1] = ref[i].y;
        }
        bb_xy(ref[i].t, 1.0, &x, &y);
        d = fmax(fabs(x - r[0]), fabs(y - r[1]));
        printf("  %6.0f K: x %.5f y %.5f  ref (%s) %.5f %.5f  |d| %.1e\n", ref[i].t, x, y,
               ref[i].src, r[0], r[1], d);
        worst = fmax(worst, d);
        assert_true(d <= LOCUS_TOL);
    }
    printf("  Planckian locus: worst |dx|,|dy| %.2e (tolerance %.0e)\n", worst, LOCUS_TOL);
}

static void test_cmf_table(void **state)
{
    double sum[3] = {0.0, 0.0, 0.0}, bar[3], ymax = 0.0, lmax = 0.0, e[CR_CMF_N], xyz[3], x, y;
    int i, k;
    (void)state;
    for (i = 0; i < CR_CMF_N; i++) {
        cr_cie1931_cmf(i, bar);
        for (k = 0; k < 3; k++)
            sum[k] += bar[k];
        if (bar[1] > ymax) {
            ymax = bar[1];
            lmax = cr_cmf_lambda(i);
        }
        e[i] = 1.0;
    }
    printf("  column sums %.7f %.7f %.7f; ybar peak %.4f at %.0f nm\n", sum[0], sum[1], sum[2],
           ymax, lmax * 1e9);
    assert_true(ymax == 1.0);
    assert_true(fabs(lmax - 555e-9) < 1e-12);
    assert_true(rel(sum[0], sum[1]) < 2e-5 && rel(sum[2], sum[1]) < 2e-5);
    cr_cmf_integrate(e, xyz);
    cr_xyz_chromaticity(xyz, &x, &y);
    printf("  equal-energy white: x %.7f y %.7f\n", x, y);
    assert_true(fabs(x - 1.0 / 3.0) < 1e-5 && fabs(y - 1.0 / 3.0) < 1e-5);
}

static void linear_rgb(double t, double rgb[3])
{
    double xyz[3];
    cr_bb_xyz(t, 1.0, xyz);
    cr_xyz_to_linear_srgb(xyz, rgb);
}

static void test_6500_white(void **state)
{
    double rgb[3], m;
    cr_rgb p;
    (void)state;
    linear_rgb(6500.0, rgb);
    m = fmax(rgb[0], fmax(rgb[1], rgb[2]));
    printf("  6500 K linear sRGB / max: %.4f %.4f %.4f (each >= 0.93)\n", rgb[0] / m, rgb[1] / m,
           rgb[2] / m);
    assert_true(rgb[0] / m >= 0.93 && rgb[1] / m >= 0.93 && rgb[2] / m >= 0.93);
    /* exposure that puts the largest channel at the tone curve's white */
    p = cr_bb_rgb8(6500.0, 1.0, 4.0 / m, 4.0);
    printf("  6500 K at exposure 4/max, white 4: (%d, %d, %d)\n", p.r, p.g, p.b);
    assert_true(p.r >= 245 && p.g >= 245 && p.b >= 245);
}

static void test_redder_when_cooler(void **state)
{
    double t, rgb[3], xyz[3], x, y;
    double px = INFINITY, pgr = -INFINITY, pbr = -INFINITY, t_in = 0.0;
    cr_rgb c2, c20;
    (void)state;
    /* Below ~1900 K the locus leaves the sRGB gamut (linear B < 0); the
     * displayed colour is the gamut-mapped one, with B = 0 there. */
    for (t = 1000.0; t <= 40000.0; t += 250.0) {
        double gr, br;
        cr_bb_xyz(t, 1.0, xyz);
        cr_xyz_chromaticity(xyz, &x, &y);
        cr_xyz_to_linear_srgb(xyz, rgb);
        cr_srgb_desaturate_to_gamut(rgb);
        assert_true(rgb[0] > 0.0);
        gr = rgb[1] / rgb[0];
        br = rgb[2] / rgb[0];
        if (!(x < px && gr > pgr && (br == 0.0 || br > pbr)))
            printf("  not monotonic at %.0f K: x %.6f after %.6f, G/R %.6f after %.6f, B/R %.6f "
                   "after %.6f\n",
                   t, x, px, gr, pgr, br, pbr);
        assert_true(x < px);
        assert_true(gr > pgr);
        if (br > 0.0) {
            assert_true(br > pbr);
            if (t_in == 0.0)
                t_in = t;
        } else {
            assert_true(t_in == 0.0);
        }
        px = x;
        pgr = gr;
        pbr = br;
    }
    printf("  1000..40000 K, 250 K steps: x strictly decreasing, G/R strictly increasing; B > 0 "
           "from %.0f K on, and R/B strictly decreasing there\n",
           t_in);
    assert_true(t_in > 1000.0 && t_in <= 2000.0);
    /* 8 bits, each scaled to the same luminance (Y = 0.5 before tone mapping) */
    cr_bb_xyz(2000.0, 1.0, xyz);
    c2 = cr_bb_rgb8(2000.0, 1.0, 0.5 / xyz[1], INFINITY);
    cr_bb_xyz(20000.0, 1.0, xyz);
    c20 = cr_bb_rgb8(20000.0, 1.0, 0.5 / xyz[1], INFINITY);
    printf("  8 bit at Y = 0.5: 2000 K (%d, %d, %d), 20000 K (%d, %d, %d)\n", c2.r, c2.g, c2.b,
           c20.r, c20.g, c20.b);
    assert_true(c2.r > c2.g && c2.g > c2.b);
    assert_true(c20.b > c20.g && c20.g > c20.r);
}

/* Golden-section search for the maximum of B_lambda(T) in log lambda. */
static double wien_peak(double t)
{
    const double r = 0.5 * (sqrt(5.0) - 1.0);
    double a = log(1e-2 * CR_WIEN_B / t), b = log(1e2 * CR_WIEN_B / t);
    double c = b - r * (b - a), d = a + r * (b - a);
    double fc = cr_planck_lambda(exp(c), t), fd = cr_planck_lambda(exp(d), t);
    int it;
    for (it = 0; it < 200 && b - a > 1e-12; it++) {
        if (fc > fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = cr_planck_lambda(exp(c), t);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = cr_planck_lambda(exp(d), t);
        }
    }
    return exp(0.5 * (a + b));
}

static void test_wien(void **state)
{
    const double ts[] = {1000.0, 3000.0, 5772.0, 10000.0, 30000.0};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        double lm = wien_peak(ts[i]);
        printf("  %5.0f K: lambda_max T = %.10e m K, rel. to b %.1e (tol 1e-6), to 2.898e-3 "
               "%.1e (tol 1e-4)\n",
               ts[i], lm * ts[i], rel(lm * ts[i], CR_WIEN_B), rel(lm * ts[i], 2.898e-3));
        assert_true(rel(lm * ts[i], CR_WIEN_B) < 1e-6);
        assert_true(rel(lm * ts[i], 2.898e-3) < 1e-4);
    }
}

/* Composite Simpson of the observed spectrum g^3 B_nu(nu/g, T) over nu in
 * [0, 50 g k T / h] with n (even) intervals. */
static double simpson_bb(double t, double g, int n)
{
    double top = 50.0 * g * CR_BOLTZMANN_K * t / CR_PLANCK_H, h = top / n, s = 0.0;
    int i;
    for (i = 0; i <= n; i++) {
        double w = (i == 0 || i == n) ? 1.0 : ((i & 1) ? 4.0 : 2.0);
        s += w * cr_bb_observed_nu(i * h, g, t);
    }
    return s * h / 3.0;
}

static void test_stefan_boltzmann(void **state)
{
    const double ts[] = {300.0, 1000.0, 5772.0, 1e4, 1e5};
    double worst = 0.0;
    size_t i;
    (void)state;
    /* sigma is CODATA's rounding of 2 pi^5 k^4 / (15 c^2 h^3) */
    {
        double k2 = CR_BOLTZMANN_K * CR_BOLTZMANN_K;
        double sig = 2.0 * pow(CR_PI, 5) * k2 * k2 /
                     (15.0 * CR_LIGHT_C * CR_LIGHT_C * pow(CR_PLANCK_H, 3));
        printf("  sigma from h, c, k: %.10e (CODATA %.9e)\n", sig, CR_STEFAN_BOLTZMANN);
        assert_true(rel(sig, CR_STEFAN_BOLTZMANN) < 1e-9);
    }
    for (i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        double t = ts[i], want = CR_STEFAN_BOLTZMANN * pow(t, 4) / CR_PI;
        double got = simpson_bb(t, 1.0, 4000), e = rel(got, want);
        printf("  %6.0f K: integral B_nu dnu = %.10e, sigma T^4/pi = %.10e, rel %.1e\n", t, got,
               want, e);
        worst = fmax(worst, e);
        assert_true(e < 1e-6);
        assert_true(rel(cr_bb_temperature(CR_STEFAN_BOLTZMANN * pow(t, 4)), t) < 1e-14);
    }
    printf("  Stefan-Boltzmann: worst rel %.1e (tolerance 1e-6)\n", worst);
}

static void test_g_shift(void **state)
{
    const double gs[] = {0.3, 0.5, 0.8, 1.0, 1.25, 2.0, 3.0};
    const double t = 4000.0;
    double worst_i = 0.0, worst_xyz = 0.0, worst_bol = 0.0;
    size_t i;
    int k;
    (void)state;
    for (i = 0; i < sizeof gs / sizeof gs[0]; i++) {
        double g = gs[i], a[3], b[3], xa, ya, xb, yb, bol, want;
        for (k = 0; k < 40; k++) {
            double nu = 1e12 * pow(10.0, 0.1 * k); /* 1e12 .. 8e15 Hz */
            double p = cr_bb_observed_nu(nu, g, t), q = cr_planck_nu(nu, g * t);
            if (q > 1e-300)
                worst_i = fmax(worst_i, rel(p, q));
        }
        cr_bb_xyz(t, g, a);
        cr_bb_xyz(g * t, 1.0, b);
        for (k = 0; k < 3; k++)
            worst_xyz = fmax(worst_xyz, rel(a[k], b[k]));
        cr_xyz_chromaticity(a, &xa, &ya);
        cr_xyz_chromaticity(b, &xb, &yb);
        bol = simpson_bb(t, g, 4000);
        want = cr_bolometric(g, CR_STEFAN_BOLTZMANN * pow(t, 4)) / CR_PI;
        worst_bol = fmax(worst_bol, rel(bol, want));
        printf("  g %.2f: (x, y) at T with g %.6f %.6f, at gT = %5.0f K %.6f %.6f\n", g, xa, ya,
               g * t, xb, yb);
        assert_true(fabs(xa - xb) < 1e-12 && fabs(ya - yb) < 1e-12);
    }
    printf("  g^3 B(nu/g, T) vs B(nu, gT): worst rel %.1e (tol 1e-13); XYZ %.1e (tol 1e-12); "
           "integral vs g^4 sigma T^4/pi %.1e (tol 1e-6)\n",
           worst_i, worst_xyz, worst_bol);
    assert_true(worst_i < 1e-13);
    assert_true(worst_xyz < 1e-12);
    assert_true(worst_bol < 1e-6);
    /* a 3250 K emitter approaching with g = 2 has the published 6500 K colour */
    {
        double x, y;
        bb_xy(3250.0, 2.0, &x, &y);
        printf("  3250 K with g = 2: %.5f %.5f (6500 K locus 0.3135 0.3237)\n", x, y);
        assert_true(fabs(x - 0.3135) <= LOCUS_TOL && fabs(y - 0.3237) <= LOCUS_TOL);
    }
}

/* --- the Planckian locus from 100 K to 1e9 K ---------------------------------
 * References, each independent of colour.h's table and Planck code:
 *  - Kim, Kim, Lee, Kim & Cho (2002, US patent 7024034 / "Design of advanced
 *    color temperature control system for HDTV applications", J. Korean
 *    Phys. Soc. 41, 865): cubic splines x_c(T), y_c(x_c), 1667 to 25000 K;
 *  - Krystek (1985, Color Res. Appl. 10, 38): rational (u, v)(T) in CIE 1960
 *    UCS, 1000 to 15000 K;
 *  - Planck's law integrated here (own code, Simpson, 1 nm from 360 to
 *    830 nm) against the multi-lobe fit of the CIE 1931 functions by Wyman,
 *    Sloan & Shirley (2013, JCGT 2(2), 1), 5000 K to 1e9 K (and 1e300 K),
 *    where the spectrum is smooth and the fit good (in its red tail it is
 *    not: no use below 5000 K);
 *  - the red end of the CIE 1931 spectral locus, x = 0.73469, y = 0.26531
 *    from 700 nm on (CIE 15), which a blackbody approaches as T -> 0: at
 *    100 to 200 K more than 99.9 % of the weighted spectrum is beyond 690 nm.
 * Between 200 and 1000 K no table is at hand: the locus must run
 * monotonically from the 1000 K point (Walker, test_planckian_locus) to
 * the spectral red end. Tolerances: 1e-3 in x and y against Kim and
 * Krystek (their own accuracy is a few 1e-4), 5e-4 against the fit, 2e-4
 * against the red end; the measured worst is printed. */
static void kim_xy(double t, double xy[2])
{
    double x, t2 = t * t, t3 = t2 * t;
    if (t <= 4000.0)
        x = -0.2661239e9 / t3 - 0.2343589e6 / t2 + 0.8776956e3 / t + 0.179910;
    else
        x = -3.0258469e9 / t3 + 2.1070379e6 / t2 + 0.2226347e3 / t + 0.240390;
    if (t <= 2222.0)
        xy[1] = -1.1063814 * x * x * x - 1.34811020 * x * x + 2.18555832 * x - 0.20219683;
    else if (t <= 4000.0)
        xy[1] = -0.9549476 * x * x * x - 1.37418593 * x * x + 2.09137015 * x - 0.16748867;
    else
        xy[1] = 3.0817580 * x * x * x - 5.87338670 * x * x + 3.75112997 * x - 0.37001483;
    xy[0] = x;
}

static void krystek_xy(double t, double xy[2])
{
    double u = (0.860117757 + 1.54118254e-4 * t + 1.28641212e-7 * t * t) /
               (1.0 + 8.42420235e-4 * t + 7.08145163e-7 * t * t);
    double v = (0.317398726 + 4.22806245e-5 * t + 4.20481691e-8 * t * t) /
               (1.0 - 2.89741816e-5 * t + 1.61456053e-7 * t * t);
    uv_to_xy(u, v, xy);
}

/* Wyman, Sloan & Shirley's piecewise Gaussian. */
static double wss_g(double l, double mu, double s1, double s2)
{
    double d = (l - mu) / (l < mu ? s1 : s2);
    return exp(-0.5 * d * d);
}

static void wss_xy(double t, double xy[2])
{
    const double c2 = 1.438776877e-2; /* h c / k, m K */
    double sum[3] = {0.0, 0.0, 0.0};
    int i, n = 470;
    for (i = 0; i <= n; i++) {
        double l = 360.0 + i, lm = l * 1e-9;
        double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        /* B_lambda / T up to a constant: no overflow at any T */
        double b = w / (lm * lm * lm * lm * lm * (t * expm1(c2 / (lm * t))));
        sum[0] += b * (1.056 * wss_g(l, 599.8, 37.9, 31.0) + 0.362 * wss_g(l, 442.0, 16.0, 26.7) -
                       0.065 * wss_g(l, 501.1, 20.4, 26.2));
        sum[1] += b * (0.821 * wss_g(l, 568.8, 46.9, 40.5) + 0.286 * wss_g(l, 530.9, 16.3, 31.1));
        sum[2] += b * (1.217 * wss_g(l, 437.0, 11.8, 36.0) + 0.681 * wss_g(l, 459.0, 26.0, 13.8));
    }
    xy[0] = sum[0] / (sum[0] + sum[1] + sum[2]);
    xy[1] = sum[1] / (sum[0] + sum[1] + sum[2]);
}

static void test_locus_100k_to_1e9k(void **state)
{
    double worst_kim = 0.0, worst_kry = 0.0, worst_wss = 0.0, worst_red = 0.0;
    double px = 0.0, py = 1.0, lt;
    (void)state;
    /* 20 temperatures a decade, 1e2 to 1e9 K, and 1e300 K */
    for (lt = 2.0; lt <= 9.0 + 1e-9; lt += 0.05) {
        double t = pow(10.0, lt), x, y, r[2], d;
        bb_xy(t, 1.0, &x, &y);
        assert_true(x > 0.0 && y > 0.0);
        if (t <= 200.0) {
            d = fmax(fabs(x - 0.73469), fabs(y - 0.26531));
            worst_red = fmax(worst_red, d);
            assert_true(d <= 2e-4);
        }
        if (t >= 1000.0 && t <= 15000.0) {
            krystek_xy(t, r);
            d = fmax(fabs(x - r[0]), fabs(y - r[1]));
            worst_kry = fmax(worst_kry, d);
            assert_true(d <= 1e-3);
        }
        if (t >= 1667.0 && t <= 25000.0) {
            kim_xy(t, r);
            d = fmax(fabs(x - r[0]), fabs(y - r[1]));
            worst_kim = fmax(worst_kim, d);
            assert_true(d <= 1e-3);
        }
        if (t >= 5000.0) {
            wss_xy(t, r);
            d = fmax(fabs(x - r[0]), fabs(y - r[1]));
            worst_wss = fmax(worst_wss, d);
            assert_true(d <= 5e-4);
        }
        if (t <= 1000.0 && lt > 2.0) /* cooler is redder: x up, y down as T falls */
            assert_true(x < px && y > py);
        px = x;
        py = y;
    }
    printf("  locus 100 K .. 1e9 K: worst |d| against the red end %.1e (<= 200 K), Krystek "
           "%.1e, Kim %.1e, the fit %.1e (>= 5000 K)\n",
           worst_red, worst_kry, worst_kim, worst_wss);
    {
        double x, y, r[2], xyz[3];
        cr_bb_xyz(1e300, 1.0, xyz);
        assert_true(cr_isfinite(xyz[0]) && cr_isfinite(xyz[1]) && cr_isfinite(xyz[2]));
        bb_xy(1e300, 1.0, &x, &y);
        wss_xy(1e300, r);
        printf("  1e300 K: x %.5f y %.5f, the fit %.5f %.5f\n", x, y, r[0], r[1]);
        assert_true(fabs(x - r[0]) <= 5e-4 && fabs(y - r[1]) <= 5e-4);
    }
}

/* The displayed colour of a blackbody is never magenta: green below both
 * red and blue by more than 16 of 255 (a 6500 K blackbody is slightly
 * magenta inside the gamut, by 3). Every temperature from 50 K to 1e9 K
 * (20 a decade, and 1e300 K), at luminances 0.05 to 1e4 before tone mapping
 * (white point 4, as the Keplerian disc), with the exposure of the
 * temperature itself; never black either. */
static void test_no_magenta(void **state)
{
    static const double lums[] = {0.05, 0.25, 1.0, 4.0, 100.0, 1e4};
    double worst = -255.0, worst_t = 0.0;
    int j;
    (void)state;
    for (j = 0; j <= 147; j++) { /* 50 K * 10^(j / 20) up to 1e9 K, then 1e300 K */
        double t = j < 147 ? 50.0 * pow(10.0, 0.05 * j) : 1e300, xyz[3], rgb[3], lum;
        size_t i;
        cr_bb_xyz(t, 1.0, xyz);
        cr_xyz_to_linear_srgb(xyz, rgb);
        lum = cr_srgb_luminance(rgb);
        assert_true(lum > 0.0 && cr_isfinite(lum));
        for (i = 0; i < sizeof lums / sizeof lums[0]; i++) {
            cr_rgb p = cr_bb_rgb8(t, 1.0, lums[i] / lum, 4.0);
            int m = (p.r < p.b ? p.r : p.b) - p.g;
            if (m > worst) {
                worst = m;
                worst_t = t;
            }
            if (m > 16 || (p.r | p.g | p.b) == 0)
                printf("  %.4g K at luminance %g: (%d, %d, %d)\n", t, lums[i], p.r, p.g, p.b);
            assert_true(m <= 16);
            assert_true((p.r | p.g | p.b) != 0);
        }
    }
    printf("  50 K .. 1e9 K and 1e300 K: min(R, B) - G at most %.0f (at %.4g K), limit 16\n",
           worst, worst_t);
}

static void test_srgb_pieces(void **state)
{
    double d65[3], rgb[3], lo, hi, v, prev;
    cr_rgb p;
    int k;
    (void)state;
    /* D65 white point (0.3127, 0.3290), Y = 1 */
    d65[0] = 0.3127 / 0.3290;
    d65[1] = 1.0;
    d65[2] = (1.0 - 0.3127 - 0.3290) / 0.3290;
    cr_xyz_to_linear_srgb(d65, rgb);
    printf("  D65 -> linear sRGB %.5f %.5f %.5f (tol 2e-4)\n", rgb[0], rgb[1], rgb[2]);
    for (k = 0; k < 3; k++)
        assert_true(fabs(rgb[k] - 1.0) < 2e-4);
    assert_true(fabs(cr_srgb_luminance(rgb) - 1.0) < 2e-4);
    /* the transfer function's two branches meet at 0.0031308 */
    lo = 12.92 * 0.0031308;
    hi = 1.055 * pow(0.0031308, 1.0 / 2.4) - 0.055;
    printf("  sRGB branches at 0.0031308: %.8f %.8f; encode(0.5) = %.5f, encode(0.18) = %.5f\n",
           lo, hi, cr_srgb_encode(0.5), cr_srgb_encode(0.18));
    assert_true(fabs(lo - hi) < 1e-6);
    assert_true(cr_srgb_encode(0.0) == 0.0 && cr_srgb_encode(1.0) == 1.0);
    assert_int_equal(cr_unit_to_u8(cr_srgb_encode(0.5)), 188);
    assert_int_equal(cr_unit_to_u8(cr_srgb_encode(0.18)), 118);
    /* tone curve: 0 -> 0, white -> 1, increasing, ~v for small v */
    assert_true(cr_tonemap_reinhard(0.0, 4.0) == 0.0);
    assert_true(fabs(cr_tonemap_reinhard(4.0, 4.0) - 1.0) < 1e-15);
    assert_true(rel(cr_tonemap_reinhard(1e-4, 4.0), 1e-4) < 2e-4);
    assert_true(fabs(cr_tonemap_reinhard(1.0, INFINITY) - 0.5) < 1e-15);
    prev = -1.0;
    for (v = 0.0; v <= 4.0; v += 0.01) {
        double o = cr_tonemap_reinhard(v, 4.0);
        assert_true(o > prev);
        prev = o;
    }
    /* gamut: a colour with negative blue keeps its luminance, min -> 0 */
    rgb[0] = 0.8;
    rgb[1] = 0.1;
    rgb[2] = -0.05;
    v = cr_srgb_luminance(rgb);
    cr_srgb_desaturate_to_gamut(rgb);
    printf("  into gamut: %.5f %.5f %.5f, luminance %.6f -> %.6f\n", rgb[0], rgb[1], rgb[2], v,
           cr_srgb_luminance(rgb));
    assert_true(fabs(cr_srgb_luminance(rgb) - v) < 1e-14);
    assert_true(fabs(fmin(rgb[0], fmin(rgb[1], rgb[2]))) < 1e-15);
    assert_true(rgb[0] > rgb[1] && rgb[1] > rgb[2]);
    /* whole chain: black, and linear white at the curve's white point */
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    p = cr_linear_srgb_to_rgb8(rgb, 1.0, 1.0);
    assert_true(p.r == 0 && p.g == 0 && p.b == 0);
    rgb[0] = rgb[1] = rgb[2] = 2.0;
    p = cr_linear_srgb_to_rgb8(rgb, 0.5, 1.0);
    assert_true(p.r == 255 && p.g == 255 && p.b == 255);
    /* no emission: black */
    p = cr_bb_rgb8(0.0, 1.0, 1.0, 1.0);
    assert_true(p.r == 0 && p.g == 0 && p.b == 0);
    assert_true(cr_planck_nu(0.0, 5000.0) == 0.0 && cr_planck_lambda(500e-9, 0.0) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planckian_locus), cmocka_unit_test(test_cmf_table),
        cmocka_unit_test(test_6500_white),      cmocka_unit_test(test_redder_when_cooler),
        cmocka_unit_test(test_wien),            cmocka_unit_test(test_stefan_boltzmann),
        cmocka_unit_test(test_g_shift),         cmocka_unit_test(test_srgb_pieces),
        cmocka_unit_test(test_locus_100k_to_1e9k), cmocka_unit_test(test_no_magenta),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
