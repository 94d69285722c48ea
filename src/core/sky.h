/* curray core: the sky (cr_sky, defs.h): its equirectangular texture
 * (6.10) and the shading of a ray that escapes (its event is an end of the
 * ray, ray.h: cr_ray_escaping, cr_ray_misses_scene).
 */
#ifndef CR_CORE_SKY_H
#define CR_CORE_SKY_H

#include "pattern.h"
#include "ray.h"
#include "shift.h"

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

/* Bytes of the sky block (defs.h's cr_sky): ours and the other side's. */
CR_HD static inline size_t cr_sky_bytes(const cr_sky *sky)
{
    return (size_t)3 * ((size_t)sky->width * (size_t)sky->height +
                        (size_t)sky->other_width * (size_t)sky->other_height);
}

/* The other exterior's sky (other_width > 0) as a cr_sky of its own. */
CR_HD static inline cr_sky cr_sky_other(const cr_sky *sky)
{
    cr_sky o;
    o.rgb = sky->rgb + (size_t)3 * (size_t)sky->width * (size_t)sky->height;
    o.width = sky->other_width;
    o.height = sky->other_height;
    o.other_width = o.other_height = 0;
    return o;
}

/* Shade a ray that escapes, at its current state (after cr_ray_begin):
 * outcome sky, the texture in its sky direction (cr_ray_sky_direction) or
 * the plain sky colour, and the frequency ratio of a static source at
 * infinity, u_em = (1, 0, 0, 0) (for the static observer omega_r/omega_s =
 * 1/sqrt(-g_tt)|obs). A mirrored ray (ray.h: bound for the other exterior)
 * escapes to the other exterior's sky instead: outcome other side, the
 * texture of skymap.other_side in its direction there, the same frequency
 * ratio (a static source at that exterior's infinity). */
CR_HD static inline void cr_sky_shade(const cr_frame *f, const cr_ray *ray, cr_pixel *px)
{
    const double *y = cr_ray_y0(ray);
    double p[4], u_inf[4] = {1.0, 0.0, 0.0, 0.0};
    px->outcome = CR_OUT_SKY;
    if (cr_ray_mirrored(ray)) {
        double sth, sph;
        cr_sky other = cr_sky_other(&f->sky);
        cr_ray_sky_direction(f, ray, y, &sth, &sph);
        px->outcome = CR_OUT_OTHER_SIDE;
        px->color = cr_sky_sample(&other, sth, sph);
    } else if (f->sky.rgb) {
        double sth, sph;
        cr_ray_sky_direction(f, ray, y, &sth, &sph);
        px->color = cr_sky_sample(&f->sky, sth, sph);
    } else {
        px->color = f->sky_color;
    }
    cr_ray_momentum(ray, y, p);
    px->redshift = cr_frame_shift(f, ray->p_obs, p, u_inf);
}

#endif
