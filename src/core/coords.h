/* curray core: the Cartesian coordinates (2.2.8) of Boyer-Lindquist points
 * and velocities, rotations of local frames, and angles.
 *
 * x = sqrt(r^2+a^2) sin th cos ph, y = sqrt(r^2+a^2) sin th sin ph,
 * z = r cos th. Spheres live in these coordinates (a flat-space
 * approximation near the hole, as in the paper); the disc is tested in BL
 * coordinates.
 */
#ifndef CR_CORE_COORDS_H
#define CR_CORE_COORDS_H

#include "defs.h"

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

/* The inverse: BL rates (dr, dth, dph) of Cartesian velocity v at the
 * point x = (2.2.8) of (r, th): from d(x^2 + y^2) = 2 (r sin^2 dr + (r^2 +
 * a^2) sin cos dth) and dz = cos dr - r sin dth, dr = (r q + (r^2 + a^2)
 * cos v_z) / Sigma and dth = (cos q - r sin^2 v_z) / (sin Sigma), q = x v_x
 * + y v_y; dph = (x v_y - y v_x) / (x^2 + y^2). On the axis (sin th = 0)
 * dph is 0 and dth takes the speed across it, |(v_x, v_y)| / sqrt(r^2 +
 * a^2), its sign that of cos th (away from the pole). */
CR_HD static inline void cr_cart_vel_to_bl(double a, double r, double th, const double x[3],
                                           const double v[3], double *dr, double *dth,
                                           double *dph)
{
    double st = sin(th), ct = cos(th), sigma = r * r + a * a * ct * ct;
    double q = x[0] * v[0] + x[1] * v[1], rho2 = x[0] * x[0] + x[1] * x[1];
    *dr = (r * q + (r * r + a * a) * ct * v[2]) / sigma;
    if (st > 0.0 && rho2 > 0.0) {
        *dth = (ct * q - r * st * st * v[2]) / (st * sigma);
        *dph = (x[0] * v[1] - x[1] * v[0]) / rho2;
    } else {
        *dth = sqrt(v[0] * v[0] + v[1] * v[1]) / sqrt(r * r + a * a);
        if (ct < 0.0)
            *dth = -*dth;
        *dph = 0.0;
    }
}

/* Rotate v (3 components) by angle ang about the unit axis k (right-hand
 * rule, Rodrigues' formula). */
CR_HD static inline void cr_rotate(double v[3], const double k[3], double ang)
{
    double c = cos(ang), s = sin(ang);
    double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    double x[3];
    x[0] = k[1] * v[2] - k[2] * v[1];
    x[1] = k[2] * v[0] - k[0] * v[2];
    x[2] = k[0] * v[1] - k[1] * v[0];
    v[0] = v[0] * c + x[0] * s + k[0] * kv * (1.0 - c);
    v[1] = v[1] * c + x[1] * s + k[1] * kv * (1.0 - c);
    v[2] = v[2] * c + x[2] * s + k[2] * kv * (1.0 - c);
}

/* Apply roll about -x, pitch about -z, yaw about -y (in that order) to n
 * vectors of a local (x, y, z) frame. Shared by the camera and the spheres. */
CR_HD static inline void cr_rotate_rpy(double (*v)[3], int n, double roll, double pitch,
                                       double yaw)
{
    const double mx[3] = {-1.0, 0.0, 0.0}, mz[3] = {0.0, 0.0, -1.0},
                 my[3] = {0.0, -1.0, 0.0};
    int i;
    for (i = 0; i < n; i++) {
        cr_rotate(v[i], mx, roll);
        cr_rotate(v[i], mz, pitch);
        cr_rotate(v[i], my, yaw);
    }
}

/* phi reduced to [0, 2 pi) (the hit azimuth of cr_pixel). */
CR_HD static inline double cr_wrap_2pi(double phi)
{
    double p = fmod(phi, CR_TWO_PI);
    if (p < 0.0)
        p += CR_TWO_PI;
    return p < CR_TWO_PI ? p : 0.0; /* -tiny + 2 pi rounds to 2 pi */
}

#endif
