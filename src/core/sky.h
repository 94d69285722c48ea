/* curray core: the sky (cr_sky, defs.h): the direction an escaping ray
 * leaves in and the equirectangular texture sampled there (6.10).
 */
#ifndef CR_CORE_SKY_H
#define CR_CORE_SKY_H

#include "coords.h"
#include "geodesic.h"
#include "pattern.h"

/* Sky direction (6.10.3)/(6.10.4) of an escaping ray: polar angle and
 * azimuth in [0, 2pi) of its Cartesian direction of motion. With backward
 * tracing this is the direction of the source on the sky. */
CR_HD static inline void cr_sky_direction(double a, const double *y, double uph,
                                          double *sky_th, double *sky_ph)
{
    double v[3], len;
    cr_bl_vel_to_cart(a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], y[CR_Y_UR], y[CR_Y_UTH], uph, v);
    len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    *sky_th = acos(fmax(-1.0, fmin(1.0, v[2] / len)));
    *sky_ph = atan2(v[1], v[0]);
    if (*sky_ph < 0.0)
        *sky_ph += CR_TWO_PI;
}

/* Bilinear sample of the equirectangular sky at (theta, phi) by (6.10.1):
 * image y = theta h / pi, x = (2pi - phi) b / (2pi), pixel centres at +1/2,
 * wrapping in x and clamping in y. */
CR_HD static inline cr_rgb cr_sky_sample(const cr_sky *sky, double th, double ph)
{
    double fx = (CR_TWO_PI - ph) / CR_TWO_PI * sky->width - 0.5;
    double fy = th / CR_PI * sky->height - 0.5;
    double x0f = floor(fx), y0f = floor(fy);
    double tx = fx - x0f, ty = fy - y0f;
    int x0 = (int)x0f, y0 = (int)y0f, x1, y1, k;
    double c[3];
    const uint8_t *p00, *p01, *p10, *p11;
    x0 %= sky->width;
    if (x0 < 0)
        x0 += sky->width;
    x1 = (x0 + 1) % sky->width;
    y1 = y0 + 1;
    if (y0 < 0)
        y0 = 0;
    if (y0 > sky->height - 1)
        y0 = sky->height - 1;
    if (y1 < 0)
        y1 = 0;
    if (y1 > sky->height - 1)
        y1 = sky->height - 1;
    p00 = sky->rgb + 3 * ((size_t)y0 * sky->width + x0);
    p01 = sky->rgb + 3 * ((size_t)y0 * sky->width + x1);
    p10 = sky->rgb + 3 * ((size_t)y1 * sky->width + x0);
    p11 = sky->rgb + 3 * ((size_t)y1 * sky->width + x1);
    for (k = 0; k < 3; k++)
        c[k] = (1.0 - ty) * ((1.0 - tx) * p00[k] + tx * p01[k]) +
               ty * ((1.0 - tx) * p10[k] + tx * p11[k]);
    return cr_rgb_make((int)(c[0] + 0.5), (int)(c[1] + 0.5), (int)(c[2] + 0.5));
}

#endif
