/* curray core: colour of thermal emission (a blackbody's colour and brightness).
 *
 * From a blackbody emitter seen with frequency ratio g = nu_obs / nu_em to an
 * 8-bit sRGB pixel:
 *
 *   Planck spectrum B_nu(T), B_lambda(T)                 cr_planck_nu, cr_planck_lambda
 *   observed intensity I_nu,obs(nu) = g^3 I_nu,em(nu/g)   cr_bb_observed_nu (_lambda)
 *     (I_nu / nu^3 is invariant; for a blackbody this is exactly B_nu(nu, g T))
 *   CIE 1931 2-degree XYZ of a spectrum                   cr_cmf_integrate, cr_bb_xyz
 *   XYZ -> linear sRGB (D65)                              cr_xyz_to_linear_srgb
 *   exposure, gamut, tone mapping, sRGB encoding, 8 bit   cr_linear_srgb_to_rgb8
 *   bolometric intensity g^4 F                            cr_bolometric
 *
 * Units: SI throughout this header (m, Hz, K, W). B_nu in W m^-2 sr^-1 Hz^-1,
 * B_lambda in W m^-2 sr^-1 m^-1; X, Y, Z = integral of B_lambda times the
 * (dimensionless) colour-matching function over lambda in metres, so in
 * W m^-2 sr^-1. Y is radiance weighted by ybar, not photometric luminance
 * (multiply by 683 lm/W for cd/m^2); the exposure factor absorbs the scale.
 *
 * Colour-matching functions: the CIE 1931 2-degree standard observer
 * tabulated at 5 nm from 380 to 780 nm (81 rows), the values of CIE 15:2004
 * (the CIE 1-nm table, CIE 018:2019 / CIE_xyz_1931_2deg, sampled every 5 nm;
 * the 1-nm table reproduces the CIE's published column sums 106.865469489595,
 * 106.856917101172, 106.892251278636, and the 81 rows agree with the
 * 4-decimal CIE 15.2-1986 Table 2.1 to its last digit). Chosen over an
 * analytic fit (Wyman, Sloan & Shirley 2013) because the table IS the
 * standard: the only error is the plain 5-nm sum, which CIE 15 itself
 * prescribes; blackbody chromaticities agree with published Planckian-locus
 * values to 1e-4 in x and y (tests/test_colour.c). The multi-lobe fit,
 * evaluated against this table on the same 5-nm sum, moves the blackbody
 * chromaticity by 1.1e-2 at 1000 K, 2.4e-3 at 2000 K, 1.0e-3 at 3000 K and
 * <= 2.1e-4 from 5000 to 40000 K: too coarse for a cool (or redshifted) disc,
 * and 81 rows cost nothing.
 * The table is a function-scope static const array, constant-initialised,
 * so nvcc places it in device global memory (read through the read-only
 * cache) and the host reads its own copy: no global mutable state.
 */
#ifndef CR_CORE_COLOUR_H
#define CR_CORE_COLOUR_H

#include "defs.h"

/* SI constants: h, c, k exact (SI 2019); sigma = 2 pi^5 k^4 / (15 c^2 h^3),
 * CODATA 2018; Wien's displacement constant b (peak of B_lambda at b / T). */
#define CR_PLANCK_H 6.62607015e-34         /* J s */
#define CR_LIGHT_C 299792458.0             /* m / s */
#define CR_BOLTZMANN_K 1.380649e-23        /* J / K */
#define CR_STEFAN_BOLTZMANN 5.670374419e-8 /* W m^-2 K^-4 */
#define CR_WIEN_B 2.897771955e-3           /* m K */

/* The colour-matching table: CR_CMF_N rows at lambda = 380 + 5 i nm. */
#define CR_CMF_N 81
#define CR_CMF_LAMBDA0 380e-9 /* m */
#define CR_CMF_DLAMBDA 5e-9   /* m */

/* Planck's law per unit frequency: B_nu(T) = 2 h nu^3 / c^2 / (exp(h nu / k T) - 1),
 * W m^-2 sr^-1 Hz^-1. 0 for nu <= 0 or T <= 0. */
CR_HD static inline double cr_planck_nu(double nu, double t)
{
    double x;
    if (!(nu > 0.0) || !(t > 0.0))
        return 0.0;
    x = CR_PLANCK_H * nu / (CR_BOLTZMANN_K * t);
    return 2.0 * CR_PLANCK_H * nu * nu * nu / (CR_LIGHT_C * CR_LIGHT_C) / expm1(x);
}

/* Planck's law per unit wavelength divided by the temperature, B_lambda(T) / T
 * in W m^-2 sr^-1 m^-1 K^-1: finite for every finite T > 0 (B_lambda itself
 * exceeds the largest double above about 1e296 K, where it is the
 * Rayleigh-Jeans 2 c k T / lambda^4: T expm1(h c / lambda k T) tends to
 * h c / lambda k). 0 for lambda <= 0, T <= 0 or T = inf, and where the Wien
 * tail underflows (about T < lambda / 170 nm K). */
CR_HD static inline double cr_planck_lambda_per_t(double lambda, double t)
{
    double x, l2;
    if (!(lambda > 0.0) || !(t > 0.0) || !cr_isfinite(t))
        return 0.0;
    x = CR_PLANCK_H * CR_LIGHT_C / (lambda * CR_BOLTZMANN_K * t);
    l2 = lambda * lambda;
    return 2.0 * CR_PLANCK_H * CR_LIGHT_C * CR_LIGHT_C / (l2 * l2 * lambda) / (t * expm1(x));
}

/* Planck's law per unit wavelength: B_lambda(T) = 2 h c^2 / lambda^5 /
 * (exp(h c / lambda k T) - 1), W m^-2 sr^-1 m^-1; lambda in metres.
 * B_lambda = B_nu c / lambda^2 at nu = c / lambda. 0 for lambda <= 0 or T <= 0. */
CR_HD static inline double cr_planck_lambda(double lambda, double t)
{
    return t * cr_planck_lambda_per_t(lambda, t);
}

/* Observed specific intensity of a blackbody of temperature t seen with
 * frequency ratio g = nu_obs / nu_em > 0: I_nu,obs(nu) = g^3 B_nu(nu / g, t)
 * (Liouville: I_nu / nu^3 is conserved along the ray). Equal to
 * B_nu(nu, g t): an observed blackbody of temperature g t. */
CR_HD static inline double cr_bb_observed_nu(double nu, double g, double t)
{
    return g * g * g * cr_planck_nu(nu / g, t);
}

/* The same per unit observed wavelength: I_lambda,obs(lambda) =
 * I_nu,obs c / lambda^2 = g^5 B_lambda(g lambda, t) = B_lambda(lambda, g t). */
CR_HD static inline double cr_bb_observed_lambda(double lambda, double g, double t)
{
    double g2 = g * g;
    return g2 * g2 * g * cr_planck_lambda(g * lambda, t);
}

/* Row i (0 <= i < CR_CMF_N, clamped) of the CIE 1931 2-degree colour-matching
 * functions at lambda = 380 + 5 i nm: bar[0] = xbar, bar[1] = ybar, bar[2] = zbar. */
CR_HD static inline void cr_cie1931_cmf(int i, double bar[3])
{
    static const double t[CR_CMF_N][3] = {
        {0.001368, 3.9e-05, 0.006450001}, /* 380 */
        {0.002236, 6.4e-05, 0.01054999}, /* 385 */
        {0.004243, 0.00012, 0.02005001}, /* 390 */
        {0.00765, 0.000217, 0.03621}, /* 395 */
        {0.01431, 0.000396, 0.06785001}, /* 400 */
        {0.02319, 0.00064, 0.1102}, /* 405 */
        {0.04351, 0.00121, 0.2074}, /* 410 */
        {0.07763, 0.00218, 0.3713}, /* 415 */
        {0.13438, 0.004, 0.6456}, /* 420 */
        {0.21477, 0.0073, 1.0390501}, /* 425 */
        {0.2839, 0.0116, 1.3856}, /* 430 */
        {0.3285, 0.01684, 1.62296}, /* 435 */
        {0.34828, 0.023, 1.74706}, /* 440 */
        {0.34806, 0.0298, 1.7826}, /* 445 */
        {0.3362, 0.038, 1.77211}, /* 450 */
        {0.3187, 0.048, 1.7441}, /* 455 */
        {0.2908, 0.06, 1.6692}, /* 460 */
        {0.2511, 0.0739, 1.5281}, /* 465 */
        {0.19536, 0.09098, 1.28764}, /* 470 */
        {0.1421, 0.1126, 1.0419}, /* 475 */
        {0.09564, 0.13902, 0.8129501}, /* 480 */
        {0.05795001, 0.1693, 0.6162}, /* 485 */
        {0.03201, 0.20802, 0.46518}, /* 490 */
        {0.0147, 0.2586, 0.3533}, /* 495 */
        {0.0049, 0.323, 0.272}, /* 500 */
        {0.0024, 0.4073, 0.2123}, /* 505 */
        {0.0093, 0.503, 0.1582}, /* 510 */
        {0.0291, 0.6082, 0.1117}, /* 515 */
        {0.06327, 0.71, 0.07824999}, /* 520 */
        {0.1096, 0.7932, 0.05725001}, /* 525 */
        {0.1655, 0.862, 0.04216}, /* 530 */
        {0.2257499, 0.9148501, 0.02984}, /* 535 */
        {0.2904, 0.954, 0.0203}, /* 540 */
        {0.3597, 0.9803, 0.0134}, /* 545 */
        {0.4334499, 0.9949501, 0.008749999}, /* 550 */
        {0.5120501, 1.0, 0.005749999}, /* 555 */
        {0.5945, 0.995, 0.0039}, /* 560 */
        {0.6784, 0.9786, 0.002749999}, /* 565 */
        {0.7621, 0.952, 0.0021}, /* 570 */
        {0.8425, 0.9154, 0.0018}, /* 575 */
        {0.9163, 0.87, 0.001650001}, /* 580 */
        {0.9786, 0.8163, 0.0014}, /* 585 */
        {1.0263, 0.757, 0.0011}, /* 590 */
        {1.0567, 0.6949, 0.001}, /* 595 */
        {1.0622, 0.631, 0.0008}, /* 600 */
        {1.0456, 0.5668, 0.0006}, /* 605 */
        {1.0026, 0.503, 0.00034}, /* 610 */
        {0.9384, 0.4412, 0.00024}, /* 615 */
        {0.8544499, 0.381, 0.00019}, /* 620 */
        {0.7514, 0.321, 0.0001}, /* 625 */
        {0.6424, 0.265, 4.999999e-05}, /* 630 */
        {0.5419, 0.217, 3e-05}, /* 635 */
        {0.4479, 0.175, 2e-05}, /* 640 */
        {0.3608, 0.1382, 1e-05}, /* 645 */
        {0.2835, 0.107, 0.0}, /* 650 */
        {0.2187, 0.0816, 0.0}, /* 655 */
        {0.1649, 0.061, 0.0}, /* 660 */
        {0.1212, 0.04458, 0.0}, /* 665 */
        {0.0874, 0.032, 0.0}, /* 670 */
        {0.0636, 0.0232, 0.0}, /* 675 */
        {0.04677, 0.017, 0.0}, /* 680 */
        {0.0329, 0.01192, 0.0}, /* 685 */
        {0.0227, 0.00821, 0.0}, /* 690 */
        {0.01584, 0.005723, 0.0}, /* 695 */
        {0.01135916, 0.004102, 0.0}, /* 700 */
        {0.008110916, 0.002929, 0.0}, /* 705 */
        {0.005790346, 0.002091, 0.0}, /* 710 */
        {0.004109457, 0.001484, 0.0}, /* 715 */
        {0.002899327, 0.001047, 0.0}, /* 720 */
        {0.00204919, 0.00074, 0.0}, /* 725 */
        {0.001439971, 0.00052, 0.0}, /* 730 */
        {0.0009999493, 0.0003611, 0.0}, /* 735 */
        {0.0006900786, 0.0002492, 0.0}, /* 740 */
        {0.0004760213, 0.0001719, 0.0}, /* 745 */
        {0.0003323011, 0.00012, 0.0}, /* 750 */
        {0.0002348261, 8.48e-05, 0.0}, /* 755 */
        {0.0001661505, 6e-05, 0.0}, /* 760 */
        {0.000117413, 4.24e-05, 0.0}, /* 765 */
        {8.307527e-05, 3e-05, 0.0}, /* 770 */
        {5.870652e-05, 2.12e-05, 0.0}, /* 775 */
        {4.150994e-05, 1.499e-05, 0.0}, /* 780 */
    };
    if (i < 0)
        i = 0;
    if (i >= CR_CMF_N)
        i = CR_CMF_N - 1;
    bar[0] = t[i][0];
    bar[1] = t[i][1];
    bar[2] = t[i][2];
}

/* Wavelength of table row i, metres. */
CR_HD static inline double cr_cmf_lambda(int i)
{
    return CR_CMF_LAMBDA0 + CR_CMF_DLAMBDA * i;
}

/* Tristimulus values of a spectrum given per unit wavelength (W m^-2 sr^-1 m^-1,
 * or any unit per metre) at the CR_CMF_N table wavelengths:
 * xyz[k] = integral s(lambda) bar_k(lambda) dlambda, by the plain sum over
 * the 5 nm rows times 5 nm that CIE 15 prescribes for this table (the
 * functions are below 4e-3 of their peaks at 380 and 780 nm). */
CR_HD static inline void cr_cmf_integrate(const double s_lambda[CR_CMF_N], double xyz[3])
{
    double bar[3];
    int i;
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (i = 0; i < CR_CMF_N; i++) {
        double w = CR_CMF_DLAMBDA * s_lambda[i];
        cr_cie1931_cmf(i, bar);
        xyz[0] += w * bar[0];
        xyz[1] += w * bar[1];
        xyz[2] += w * bar[2];
    }
}

/* XYZ of a blackbody of temperature tg (K) divided by tg (W m^-2 sr^-1 K^-1):
 * the integral of cr_planck_lambda_per_t against the table, as
 * cr_cmf_integrate. Finite for every finite tg, so that its chromaticity
 * and its brightness relative to another temperature never overflow. */
CR_HD static inline void cr_bb_xyz_per_t(double tg, double xyz[3])
{
    double bar[3];
    int i;
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (i = 0; i < CR_CMF_N; i++) {
        double w = CR_CMF_DLAMBDA * cr_planck_lambda_per_t(cr_cmf_lambda(i), tg);
        cr_cie1931_cmf(i, bar);
        xyz[0] += w * bar[0];
        xyz[1] += w * bar[1];
        xyz[2] += w * bar[2];
    }
}

/* XYZ (W m^-2 sr^-1) of the observed spectrum of a blackbody of temperature
 * t (K) seen with frequency ratio g > 0: the observed spectrum is the
 * blackbody of g t (cr_bb_observed_lambda), integrated against the table as
 * cr_cmf_integrate. Overflows (inf) only where the value exceeds the
 * largest double, g t above about 1e303 K. */
CR_HD static inline void cr_bb_xyz(double t, double g, double xyz[3])
{
    double tg = g * t;
    int k;
    cr_bb_xyz_per_t(tg, xyz);
    for (k = 0; k < 3; k++)
        xyz[k] = xyz[k] > 0.0 ? xyz[k] * tg : 0.0;
}

/* Chromaticity x = X / (X + Y + Z), y = Y / (X + Y + Z); (0, 0) for black. */
CR_HD static inline void cr_xyz_chromaticity(const double xyz[3], double *x, double *y)
{
    double s = xyz[0] + xyz[1] + xyz[2];
    *x = s > 0.0 ? xyz[0] / s : 0.0;
    *y = s > 0.0 ? xyz[1] / s : 0.0;
}

/* CIE XYZ to linear sRGB, IEC 61966-2-1 (Rec. 709 primaries, D65 white):
 * the standard's matrix. XYZ of D65 with Y = 1 maps to (1, 1, 1) to 2e-4.
 * Colours outside the sRGB gamut come out with negative components. */
CR_HD static inline void cr_xyz_to_linear_srgb(const double xyz[3], double rgb[3])
{
    double x = xyz[0], y = xyz[1], z = xyz[2];
    rgb[0] = 3.2406 * x - 1.5372 * y - 0.4986 * z;
    rgb[1] = -0.9689 * x + 1.8758 * y + 0.0415 * z;
    rgb[2] = 0.0557 * x - 0.2040 * y + 1.0570 * z;
}

/* Relative luminance of linear sRGB (the Y row of the inverse matrix). */
CR_HD static inline double cr_srgb_luminance(const double rgb[3])
{
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/* Bring a linear sRGB colour with a negative component into the gamut by
 * mixing it with the grey of the same luminance, just enough that the
 * smallest component is 0: luminance and dominant hue stay, saturation is
 * lost (a 1000 K blackbody has B < 0). Colours already inside, and colours
 * with luminance <= 0, are left alone but for clamping negatives to 0. */
CR_HD static inline void cr_srgb_desaturate_to_gamut(double rgb[3])
{
    double lum = cr_srgb_luminance(rgb);
    double mn = fmin(rgb[0], fmin(rgb[1], rgb[2]));
    int k;
    if (mn >= 0.0)
        return;
    if (lum > 0.0) {
        double s = lum / (lum - mn); /* mixes rgb -> lum + s (rgb - lum), min -> 0 */
        for (k = 0; k < 3; k++)
            rgb[k] = lum + s * (rgb[k] - lum);
    }
    for (k = 0; k < 3; k++)
        rgb[k] = rgb[k] > 0.0 ? rgb[k] : 0.0;
}

/* Gamut mapping for display: cr_srgb_desaturate_to_gamut, and then, for a
 * colour that was outside the gamut and came out with green below both red
 * and blue (a hue on the purple side of a primary), the smaller of red and
 * blue lowered to green. The deep red of a blackbody below about 800 K lies
 * just on the purple side of the sRGB red primary as seen from D65;
 * desaturating it keeps a little blue and no green, which per-channel tone
 * mapping of a bright pixel turns into magenta (255, 0, 255), a colour no
 * blackbody has. Lowered, it is the red primary's hue, and bright pixels go
 * to (255, 0, 0). Colours inside the gamut are unchanged (a 6500 K
 * blackbody, slightly magenta, stays so). */
CR_HD static inline void cr_srgb_gamut_map(double rgb[3])
{
    int outside = rgb[0] < 0.0 || rgb[1] < 0.0 || rgb[2] < 0.0;
    cr_srgb_desaturate_to_gamut(rgb);
    if (outside && rgb[1] < rgb[0] && rgb[1] < rgb[2]) {
        if (rgb[0] < rgb[2])
            rgb[0] = rgb[1];
        else
            rgb[2] = rgb[1];
    }
}

/* Tone mapping, per channel: the extended Reinhard curve (Reinhard et al.
 * 2002, eq. 4) v (1 + v / w^2) / (1 + v), which maps 0 to 0 and the white
 * point w > 0 to 1, is increasing, close to v for v << 1, and compresses
 * highlights; w = INFINITY gives v / (1 + v). Applied to each channel, so a
 * very bright coloured emitter saturates toward white, as on film.
 * Inputs are >= 0 (after cr_srgb_desaturate_to_gamut); output clamped to [0, 1]. */
CR_HD static inline double cr_tonemap_reinhard(double v, double white)
{
    double out;
    if (!(v > 0.0))
        return 0.0;
    out = v * (1.0 + v / (white * white)) / (1.0 + v);
    return out < 1.0 ? out : 1.0;
}

/* The sRGB transfer function (IEC 61966-2-1 encoding) of a linear value in
 * [0, 1] (clamped): 12.92 v below 0.0031308, else 1.055 v^(1/2.4) - 0.055. */
CR_HD static inline double cr_srgb_encode(double v)
{
    if (!(v > 0.0))
        return 0.0;
    if (v >= 1.0)
        return 1.0;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

/* The inverse of cr_srgb_encode: an encoded value in [0, 1] (clamped) to
 * linear light: e / 12.92 up to 0.04045, else ((e + 0.055) / 1.055)^2.4. */
CR_HD static inline double cr_srgb_decode(double e)
{
    if (!(e > 0.0))
        return 0.0;
    if (e >= 1.0)
        return 1.0;
    return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4);
}

/* An encoded value in [0, 1] to 8 bits, rounded to nearest. */
CR_HD static inline uint8_t cr_unit_to_u8(double e)
{
    double v = e * 255.0 + 0.5;
    return (uint8_t)(v <= 0.0 ? 0 : (v >= 255.0 ? 255 : (int)v));
}

/* Linear sRGB (any scale) to an 8-bit pixel: multiply by exposure (> 0; 1
 * maps linear 1 to the tone curve's input 1), bring into the gamut
 * (cr_srgb_gamut_map), tone-map each channel with white point white,
 * sRGB-encode, round. */
CR_HD static inline cr_rgb cr_linear_srgb_to_rgb8(const double rgb_in[3], double exposure,
                                                  double white)
{
    double rgb[3];
    cr_rgb out;
    int k;
    for (k = 0; k < 3; k++)
        rgb[k] = rgb_in[k] * exposure;
    cr_srgb_gamut_map(rgb);
    for (k = 0; k < 3; k++)
        rgb[k] = cr_srgb_encode(cr_tonemap_reinhard(rgb[k], white));
    out.r = cr_unit_to_u8(rgb[0]);
    out.g = cr_unit_to_u8(rgb[1]);
    out.b = cr_unit_to_u8(rgb[2]);
    return out;
}

/* The whole chain for a blackbody disc element: temperature t (K) at
 * emission, frequency ratio g, exposure in sr m^2 / W (multiplies the
 * linear sRGB of cr_bb_xyz), tone-curve white point white. */
CR_HD static inline cr_rgb cr_bb_rgb8(double t, double g, double exposure, double white)
{
    double xyz[3], rgb[3];
    cr_bb_xyz(t, g, xyz);
    cr_xyz_to_linear_srgb(xyz, rgb);
    return cr_linear_srgb_to_rgb8(rgb, exposure, white);
}

/* Effective temperature (K) of a surface radiating flux f (W m^-2) as a
 * blackbody on one face: f = sigma T^4. 0 for f <= 0. */
CR_HD static inline double cr_bb_temperature(double f)
{
    return f > 0.0 ? pow(f / CR_STEFAN_BOLTZMANN, 0.25) : 0.0;
}

/* Bolometric (frequency-integrated) observed intensity of an emitter of
 * flux f seen with frequency ratio g: I_obs = g^4 I_em, and I_em = f / pi
 * for a blackbody surface (integral of B_nu = sigma T^4 / pi). Returns
 * g^4 f, the quantity the bolometric map is proportional to (divide by pi
 * for W m^-2 sr^-1). */
CR_HD static inline double cr_bolometric(double g, double f)
{
    double g2 = g * g;
    return g2 * g2 * f;
}

#endif
