/* curray core: scene objects, their patterns, the sky and the redshift.
 *
 * Cartesian coordinates (2.2.8): x = sqrt(r^2+a^2) sin th cos ph,
 * y = sqrt(r^2+a^2) sin th sin ph, z = r cos th. Spheres live in these
 * coordinates (a flat-space approximation near the hole, as in the paper);
 * the disc is tested in BL coordinates.
 */
#ifndef CR_CORE_OBJECTS_H
#define CR_CORE_OBJECTS_H

#include "camera.h"
#include "shift.h"

/* Chessboard grey between accent squares. */
#define CR_GREY_LEVEL 128

CR_HD static inline void cr_bl_to_cart(double a, double r, double th, double ph, double x[3])
{
    double rho = sqrt(r * r + a * a), s = sin(th);
    x[0] = rho * s * cos(ph);
    x[1] = rho * s * sin(ph);
    x[2] = r * cos(th);
}

/* Cartesian velocity of a BL velocity (u^r, u^th, u^ph) at (r, th, ph) by the
 * Jacobian of (2.2.8), equation (6.10.2). */
CR_HD static inline void cr_bl_vel_to_cart(double a, double r, double th, double ph,
                                           double ur, double uth, double uph, double v[3])
{
    double rho = sqrt(r * r + a * a);
    double st = sin(th), ct = cos(th), sp = sin(ph), cp = cos(ph);
    double drho = rho > 0.0 ? r / rho : 0.0;
    v[0] = drho * st * cp * ur + rho * ct * cp * uth - rho * st * sp * uph;
    v[1] = drho * st * sp * ur + rho * ct * sp * uth + rho * st * cp * uph;
    v[2] = ct * ur - r * st * uth;
}

CR_HD static inline cr_rgb cr_rgb_make(int r, int g, int b)
{
    cr_rgb c;
    c.r = (uint8_t)r;
    c.g = (uint8_t)g;
    c.b = (uint8_t)b;
    return c;
}

/* Chessboard: square (i, j) takes the accent colour when i + j is even. */
CR_HD static inline cr_rgb cr_chess(int i, int j, cr_rgb accent)
{
    return ((i + j) & 1) ? cr_rgb_make(CR_GREY_LEVEL, CR_GREY_LEVEL, CR_GREY_LEVEL) : accent;
}

/* Index of x in n equal bins of [0, 1), clamped to 0..n-1. */
CR_HD static inline int cr_bin(double x, int n)
{
    int i = (int)floor(x * n);
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

/* Colour of the disc at BL radius r, azimuth ph, on the top (side 0) or
 * bottom (side 1) face. */
CR_HD static inline cr_rgb cr_disc_color(const cr_disc *d, double r, double ph, int side)
{
    double u = fmod(ph - d->yaw, CR_TWO_PI);
    if (u < 0.0)
        u += CR_TWO_PI;
    return cr_chess(cr_bin((r - d->r_in) / (d->r_out - d->r_in), d->n_radial),
                    cr_bin(u / CR_TWO_PI, d->n_sectors), side ? d->color2 : d->color1);
}

/* Derive the sphere's Cartesian centre and orientation. Its local axes start
 * as the paper's x = e_r, y = e_th, z = e_ph at the centre's (theta, phi) and
 * are turned by roll, pitch, yaw like the camera. The sphere's north pole is
 * local -y, longitude zero is local +x, longitude 90 deg local +z: a sphere
 * with no rotation has the latitude/longitude lines of the BL theta/phi. */
CR_HD static inline void cr_sphere_prepare(cr_sphere *s, double a)
{
    double st = sin(s->theta), ct = cos(s->theta), sp = sin(s->phi), cp = cos(s->phi);
    double loc[3][3];
    double e[3][3];
    int i, k;
    cr_bl_to_cart(a, s->r, s->theta, s->phi, s->center);
    /* Cartesian unit vectors e_r, e_th, e_ph at (theta, phi) */
    e[0][0] = st * cp; e[0][1] = st * sp; e[0][2] = ct;
    e[1][0] = ct * cp; e[1][1] = ct * sp; e[1][2] = -st;
    e[2][0] = -sp;     e[2][1] = cp;      e[2][2] = 0.0;
    /* sphere axes in local (x, y, z) components: lon 0, north, lon 90 */
    loc[0][0] = 1.0; loc[0][1] = 0.0;  loc[0][2] = 0.0;
    loc[1][0] = 0.0; loc[1][1] = -1.0; loc[1][2] = 0.0;
    loc[2][0] = 0.0; loc[2][1] = 0.0;  loc[2][2] = 1.0;
    cr_rotate_rpy(loc, 3, s->roll, s->pitch, s->yaw);
    for (i = 0; i < 3; i++)
        for (k = 0; k < 3; k++)
            s->axes[i][k] = loc[i][0] * e[0][k] + loc[i][1] * e[1][k] + loc[i][2] * e[2][k];
}

/* Squared distance from the sphere's centre minus radius^2 at Cartesian x. */
CR_HD static inline double cr_sphere_f(const cr_sphere *s, const double x[3])
{
    double d0 = x[0] - s->center[0], d1 = x[1] - s->center[1], d2 = x[2] - s->center[2];
    return d0 * d0 + d1 * d1 + d2 * d2 - s->radius * s->radius;
}

/* Colour of the sphere's surface at (or near) Cartesian point x. */
CR_HD static inline cr_rgb cr_sphere_color(const cr_sphere *s, const double x[3])
{
    double d[3], c[3], len, lat, lon;
    int k;
    for (k = 0; k < 3; k++)
        d[k] = x[k] - s->center[k];
    for (k = 0; k < 3; k++)
        c[k] = d[0] * s->axes[k][0] + d[1] * s->axes[k][1] + d[2] * s->axes[k][2];
    len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(len > 0.0))
        return s->color;
    lat = acos(fmax(-1.0, fmin(1.0, c[1] / len))); /* 0 at the north pole */
    lon = atan2(c[2], c[0]);
    if (lon < 0.0)
        lon += CR_TWO_PI;
    return cr_chess(cr_bin(lat / CR_PI, s->n_lat), cr_bin(lon / CR_TWO_PI, s->n_lon),
                    s->color);
}

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

/* The frame's observer's 4-velocity u^mu (BL components): e_t of its tetrad
 * (camera.h), (1, 0, 0, 0) for the observer at infinity. */
CR_HD static inline void cr_frame_observer_velocity(const cr_frame *f, double u[4])
{
    int k;
    for (k = 0; k < 4; k++)
        u[k] = f->obs_at_inf ? (k == 0 ? 1.0 : 0.0) : f->tetrad[0][k];
}

/* g = nu_obs / nu_em (shift.h, the one frequency ratio) of a photon with
 * covariant momentum p at the emitter and p_obs at the observer (any common
 * scale and sign: the ray's backward tangent -k serves; cr_ray keeps its
 * p_obs) emitted by matter of 4-velocity u_em and received by the frame's
 * observer. A moving observer (observer.h) may have u^r, u^theta != 0, so
 * p_obs must be the ray's own momentum there; for an observer with
 * u^r = u^theta = 0 (static, ZAMO, orbit, at infinity) only the conserved
 * p_t, p_phi of p_obs enter, and p itself serves. -1 where the ratio is
 * undefined (cr_shift_ratio). */
CR_HD static inline double cr_frame_shift(const cr_frame *f, const double p_obs[4],
                                          const double p[4], const double u_em[4])
{
    double u_obs[4];
    cr_frame_observer_velocity(f, u_obs);
    return cr_shift_ratio(p_obs, u_obs, p, u_em);
}

/* Redshift omega_r/omega_s (3.5.1, 6.9) of light with covariant momentum p
 * (p_obs at the observer, as for cr_frame_shift) from a static source at (r, th) seen by the frame's observer: the one
 * frequency ratio with the static emitter's 4-velocity. For the static
 * observer it equals sqrt(-g_tt)|source / sqrt(-g_tt)|observer (ERRATA) to
 * rounding, whatever p (tests/test_patterns.c). Returns -1 for a source
 * inside the ergosurface, where no static source exists. */
CR_HD static inline double cr_redshift_static(const cr_frame *f, const double p_obs[4],
                                              const double p[4], double r, double th)
{
    double u_em[4];
    if (!cr_shift_static_velocity(&f->metric, r, th, u_em))
        return -1.0;
    return cr_frame_shift(f, p_obs, p, u_em);
}

#endif
