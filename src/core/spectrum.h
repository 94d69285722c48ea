/* curray core: the observed spectrum of the Keplerian disc, per ray: what
 * one ray (a pixel or a sub-pixel sample) that met the disc at BL radius r
 * with frequency ratio g adds to a line profile and to the blackbody
 * continuum, and the solid angle the ray stands for. The sums over rays and
 * the file are src/output/spectrum.c's.
 *
 * Observed specific intensity I_E = g^3 I_E,em(E / g) (I / nu^3 invariant).
 *   Line of rest energy E0, emissivity r^-q: I_E,em = r^-q delta(E' - E0),
 *   so I_E = g^4 r^-q delta(E - g E0): the ray puts photon flux g^3 r^-q
 *   times its solid angle into the bin holding g E0 (energy flux g E0 times
 *   that).
 *   Blackbody with colour correction f_col (Shimura & Takahara 1995):
 *   I_E,em = B_E(E'; f_col T) / f_col^4, T = t_scale F(r)^(1/4) the
 *   Novikov-Thorne effective temperature; the energy flux into [E1, E2] is
 *   g^4 (2 (k T)^4 / (h^3 c^2)) [P(x1) - P(x2)] per unit solid angle, with
 *   x = E / (g f_col k T) and P(x) the integral of t^3 / (e^t - 1) from x
 *   to infinity (cr_spec_planck_tail), so that over all energies it is
 *   g^4 sigma T^4 / pi, whatever f_col: the bolometric image's g^4 F.
 * Units: SI (W m^-2 sr^-1 in each energy bin), energies in keV.
 */
#ifndef CR_CORE_SPECTRUM_H
#define CR_CORE_SPECTRUM_H

#include "camera.h"
#include "colour.h"

#define CR_KEV_J 1.602176634e-16 /* J per keV (exact, SI 2019) */

/* P(x) = integral from x to infinity of t^3 / (e^t - 1) dt, x >= 0;
 * P(0) = pi^4 / 15. Below x = 1 the series of t / (e^t - 1) in Bernoulli
 * numbers (radius 2 pi; below 1e-15 of P there), from it on the sum
 * over k of e^(-k x) (x^3 / k + 3 x^2 / k^2 + 6 x / k^3 + 6 / k^4). */
CR_HD static inline double cr_spec_planck_tail(double x)
{
    /* B_n / n! for n = 0, 1, 2, 4, ..., 20 (odd n > 1 vanish) */
    static const double bn[] = {1.0,
                                -0.5,
                                1.0 / 12.0,
                                -1.0 / 720.0,
                                1.0 / 30240.0,
                                -1.0 / 1209600.0,
                                1.0 / 47900160.0,
                                -691.0 / 1307674368000.0,
                                1.0 / 74724249600.0,
                                -3617.0 / 10670622842880000.0,
                                43867.0 / 5109094217170944000.0,
                                -174611.0 / 802857662698291200000.0};
    const double total = 6.4939394022668291491; /* pi^4 / 15 */
    if (!(x > 0.0))
        return total;
    if (x < 1.0) {
        /* integral from 0 to x of t^2 sum B_n t^n / n! = sum B_n x^(n+3) / (n! (n+3)) */
        double s = bn[0] * x * x * x / 3.0 + bn[1] * x * x * x * x / 4.0, xn = x * x * x;
        int i;
        for (i = 2; i < 12; i++) {
            int n = 2 * (i - 1);
            xn = i == 2 ? x * x * x * x * x : xn * x * x; /* x^(n + 3) */
            s += bn[i] * xn / (n + 3);
        }
        return total - s;
    }
    {
        double s = 0.0;
        int k;
        for (k = 1; k <= 64; k++) {
            double e = exp(-k * x), kk = (double)k;
            double term = e * (x * x * x / kk + 3.0 * x * x / (kk * kk) +
                               6.0 * x / (kk * kk * kk) + 6.0 / (kk * kk * kk * kk));
            s += term;
            if (term < 1e-17 * s)
                break;
        }
        return s;
    }
}

/* Energy flux per unit solid angle (W m^-2 sr^-1) that a ray with ratio g
 * from matter of effective temperature T (K) brings in the photon-energy
 * bin [e1, e2] (keV) with colour correction f_col (> 0). 0 where T or g is
 * not positive. */
CR_HD static inline double cr_spec_bb_bin(double g, double T, double f_col, double e1, double e2)
{
    double kt, x1, x2, scale;
    if (!(g > 0.0) || !(T > 0.0))
        return 0.0;
    kt = CR_BOLTZMANN_K * T;                 /* J */
    x1 = e1 * CR_KEV_J / (g * f_col * kt);
    x2 = e2 * CR_KEV_J / (g * f_col * kt);
    scale = 2.0 * kt * kt * kt * kt /
            (CR_PLANCK_H * CR_PLANCK_H * CR_PLANCK_H * CR_LIGHT_C * CR_LIGHT_C);
    return g * g * g * g * scale * (cr_spec_planck_tail(x1) - cr_spec_planck_tail(x2));
}

/* The same over all energies: g^4 sigma T^4 / pi. */
CR_HD static inline double cr_spec_bb_total(double g, double T)
{
    double g2 = g * g;
    return g > 0.0 && T > 0.0 ? g2 * g2 * CR_STEFAN_BOLTZMANN * T * T * T * T / CR_PI : 0.0;
}

/* Photon flux of a ray in the line of emissivity r^-q (per unit solid angle,
 * arbitrary units): g^3 r^-q, at photon energy g E0 (its energy flux is
 * g E0 times that). The photon flux is what kerrz lineprof gives. */
CR_HD static inline double cr_spec_line_weight(double g, double r, double q)
{
    return g > 0.0 && r > 0.0 ? g * g * g * pow(r, -q) : 0.0;
}

/* The solid angle (sr) that the image point (x, y) stands for in a square
 * of side h pixels around it (pixel units of cr_camera_screen): for a finite
 * observer |dn/dx x dn/dy| h^2 of the unit direction n(x, y) of
 * cr_camera_pixel_dir (central differences, any projection); for the
 * observer at infinity the image-plane area (alpha, beta) of the square in
 * M^2, which is the solid angle times (D / M)^2 at a distance D. */
CR_HD static inline double cr_spec_solid_angle(const cr_frame *f, double x, double y, double h)
{
    double a[3], b[3], c[3], d[3], u[3], v[3], w[3];
    int i;
    if (f->obs_at_inf)
        return f->observer.hextent / f->width * (f->observer.vextent / f->height) * h * h;
    cr_camera_pixel_dir(f, x + 0.5 * h, y, a);
    cr_camera_pixel_dir(f, x - 0.5 * h, y, b);
    cr_camera_pixel_dir(f, x, y + 0.5 * h, c);
    cr_camera_pixel_dir(f, x, y - 0.5 * h, d);
    for (i = 0; i < 3; i++) {
        u[i] = a[i] - b[i];
        v[i] = c[i] - d[i];
    }
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
    return sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

#endif
