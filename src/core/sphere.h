/* curray core: spheres (cr_sphere, defs.h), defined in the Cartesian
 * coordinates (2.2.8) of coords.h: their frame, surface function and
 * chessboard colour.
 */
#ifndef CR_CORE_SPHERE_H
#define CR_CORE_SPHERE_H

#include "coords.h"
#include "pattern.h"

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

#endif
