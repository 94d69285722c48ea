/* curray core: the observer's frame and pixel -> initial ray (6.4, D).
 *
 * A moving observer (observer.motion other than static) uses the boosted
 * ZAMO tetrad of observer.h in place of the static frame below, and every
 * projection other than the paper's flat screen maps pixels to directions
 * as observer.h says; the camera axes and rotations are the same for all.
 *
 * Local orthonormal frame of the static observer (equivalent to D.25, see
 * ERRATA "Observer frame"):
 *   e_t   = d_t / sqrt(-g_tt)
 *   e_r   = d_r / sqrt(g_rr)
 *   e_th  = d_th / sqrt(g_thth)
 *   e_ph  = (d_ph - (g_tphi/g_tt) d_t) / sqrt(Delta sin^2 / (-g_tt))
 * The paper's local Cartesian axes are x = e_r, y = e_th, z = e_ph.
 *
 * Camera, before rotation: forward = -x (towards the hole), image right = +z
 * (towards +phi), image up = -y (towards the +z pole, decreasing theta).
 * Rotations (6.4 and E.4): roll about -x, then pitch about -z, then yaw about
 * -y, each by the right-hand rule, applied to the camera axes in that order.
 * Consequences: positive roll turns the camera clockwise as seen from behind
 * it, positive pitch tilts the view towards +theta (down in the image),
 * positive yaw turns the view towards -phi (left); yaw = 180 deg looks away
 * from the hole.
 *
 * Pixel (i, j), i = 0..W-1 left to right, j = 0..H-1 top to bottom, looks
 * through the point (sx, sy) of a screen at unit distance,
 *   sx = (2 (i + 1/2) / W - 1) tan(hfov/2),  sy = (1 - 2 (j + 1/2) / H) tan(vfov/2),
 * so the centre pixel of an odd-sized image looks straight ahead (the
 * rectilinear projection; observer.h has the others).
 */
#ifndef CR_CORE_CAMERA_H
#define CR_CORE_CAMERA_H

#include "coords.h"
#include "mino.h"
#include "observer.h"

/* Fill the observer-derived fields of f: tetrad, rotated camera axes, screen
 * half-extents, sqrt(-g_tt) at the observer, on-axis and at-infinity flags.
 * Requires a static observer outside the ergosurface, a moving one outside
 * the horizon with a velocity that exists there (|v| < 1, checked by the
 * scene validation), or one at r = +INFINITY (no tetrad needed there). A
 * moving observer's tetrad is the boosted ZAMO tetrad of observer.h;
 * obs_sqrt_mgtt is then 1 / u^t (sqrt(-g_tt) for the static observer, whose
 * u^t = 1/sqrt(-g_tt); positive everywhere outside the horizon, negative
 * between the horizons, where BL t runs backward along the infall, positive
 * again inside r-). An observer inside r+ (obs_inside; inside r- also
 * obs_inner) gets the free-fall frame of observer.h, boosted by its
 * velocity (measured in that frame) if it has one; its rays start in the
 * ingoing chart (ray.h). */
CR_HD static inline void cr_camera_prepare(cr_frame *f)
{
    const cr_observer *o = &f->observer;
    cr_metric_point p;
    int a, b;
    double s = sin(o->theta);
    for (a = 0; a < 4; a++)
        for (b = 0; b < 4; b++)
            f->tetrad[a][b] = 0.0;
    f->obs_on_axis = 0;
    f->obs_inside = f->obs_inner = 0;
    if (fabs(s) < 1e-10)
        f->obs_on_axis = cos(o->theta) > 0.0 ? 1 : -1;
    /* forward, right, up */
    f->cam[0][0] = -1.0; f->cam[0][1] = 0.0;  f->cam[0][2] = 0.0;
    f->cam[1][0] = 0.0;  f->cam[1][1] = 0.0;  f->cam[1][2] = 1.0;
    f->cam[2][0] = 0.0;  f->cam[2][1] = -1.0; f->cam[2][2] = 0.0;
    f->obs_at_inf = isinf(o->r) && o->r > 0.0;
    if (f->obs_at_inf) {
        /* Bardeen's image plane: the screen coordinates are the impact
         * coordinates (alpha, beta) in M; only roll turns it. */
        cr_rotate_rpy(f->cam, 3, o->roll, 0.0, 0.0);
        f->obs_sqrt_mgtt = 1.0;
        f->tan_half_h = 0.5 * o->hextent;
        f->tan_half_v = 0.5 * o->vextent;
        return;
    }
    f->obs_inside = o->r < cr_metric_r_plus(&f->metric);
    f->obs_inner = o->r < cr_metric_r_minus(&f->metric);
    if (f->obs_inside) {
        /* between the horizons: the free-fall frame (observer.h), boosted by
         * v for a velocity; its covariant legs for E and L (cr_camera_ray) */
        double e[4][4], low[4][2], el[4][4], bl[4][4], v[3] = {0.0, 0.0, 0.0};
        cr_freefall_tetrad(&f->metric, o->r, o->theta, f->obs_on_axis, e, low);
        if (o->motion == CR_MOTION_VELOCITY) {
            for (a = 0; a < 3; a++)
                v[a] = o->v[a];
        }
        for (a = 0; a < 4; a++) {
            el[a][0] = low[a][0];
            el[a][1] = low[a][1];
            el[a][2] = el[a][3] = 0.0;
        }
        cr_boost_tetrad(e, v, f->tetrad);
        cr_boost_tetrad(el, v, bl);
        for (a = 0; a < 4; a++) {
            f->tetrad_low[a][0] = bl[a][0];
            f->tetrad_low[a][1] = bl[a][1];
        }
        f->obs_sqrt_mgtt = 1.0 / f->tetrad[0][0];
    } else if (o->motion != CR_MOTION_STATIC) {
        double e[4][4], v[3];
        cr_zamo_tetrad(&f->metric, o->r, o->theta, f->obs_on_axis, e, NULL, NULL, NULL);
        cr_observer_zamo_velocity(&f->metric, o, f->obs_on_axis, v);
        cr_boost_tetrad(e, v, f->tetrad);
        f->obs_sqrt_mgtt = 1.0 / f->tetrad[0][0];
    } else {
        cr_metric_eval(&f->metric, o->r, o->theta, &p);
        f->obs_sqrt_mgtt = sqrt(-p.g_tt);
        f->tetrad[0][0] = 1.0 / f->obs_sqrt_mgtt;
        f->tetrad[1][1] = 1.0 / sqrt(p.g_rr);
        f->tetrad[2][2] = 1.0 / sqrt(p.g_thth);
        if (!f->obs_on_axis) {
            double n = sqrt(p.delta * p.sin2 / -p.g_tt);
            f->tetrad[3][0] = -(p.g_tph / p.g_tt) / n;
            f->tetrad[3][3] = 1.0 / n;
        }
    }
    cr_rotate_rpy(f->cam, 3, o->roll, o->pitch, o->yaw);
    if (o->projection == CR_PROJ_EQUIRECT) {
        f->tan_half_h = CR_PI;
        f->tan_half_v = 0.5 * CR_PI;
    } else if (o->projection == CR_PROJ_FISHEYE) {
        f->tan_half_h = 0.5 * o->hfov;
        f->tan_half_v = 0.5 * o->vfov;
    } else {
        f->tan_half_h = tan(0.5 * o->hfov);
        f->tan_half_v = tan(0.5 * o->vfov);
    }
}

/* Screen coordinates of pixel (i, j): on the screen at unit distance of a
 * finite observer, or the impact coordinates (alpha, beta) in M of the
 * observer at infinity (then tan_half_h, tan_half_v are the half extents). */
CR_HD static inline void cr_camera_screen(const cr_frame *f, double i, double j, double *sx,
                                          double *sy)
{
    *sx = (2.0 * (i + 0.5) / f->width - 1.0) * f->tan_half_h;
    *sy = (1.0 - 2.0 * (j + 0.5) / f->height) * f->tan_half_v;
}

/* Angular radius (rad) of a fisheye's image circle: max(hfov, vfov) / 2,
 * at most pi (the validated fovs are <= 360 deg). With square pixels
 * (vfov = hfov H / W) the circle's diameter is the image's longer side, so
 * the stated fields of view stay true along both centre lines; on a square
 * image it is the inscribed circle. */
CR_HD static inline double cr_camera_fisheye_radius(const cr_frame *f)
{
    return fmin(fmax(f->tan_half_h, f->tan_half_v), CR_PI);
}

/* Whether image point (i, j) (pixel units of cr_camera_screen) is in the
 * picture: always, except under the fisheye, whose picture is its image
 * circle: the points at most cr_camera_fisheye_radius from the forward
 * direction (the screen radius |(sx, sy)| is that angle). A point outside
 * it (a corner, or beyond 180 deg, where directions would repeat) is not
 * traced: cr_trace_point gives it CR_OUT_OUTSIDE. The rectilinear screen
 * (hfov <= 170 deg) and the equirectangular sphere show a distinct
 * direction at every point, so they have no such points. */
CR_HD static inline int cr_camera_in_image(const cr_frame *f, double i, double j)
{
    double sx, sy, R;
    if (f->obs_at_inf || f->observer.projection != CR_PROJ_FISHEYE)
        return 1;
    cr_camera_screen(f, i, j, &sx, &sy);
    R = cr_camera_fisheye_radius(f);
    return sx * sx + sy * sy <= R * R;
}

/* Unit direction, in the observer's local (e_r, e_th, e_ph) basis, in which
 * pixel (i, j) looks (finite observers), under the frame's projection. */
CR_HD static inline void cr_camera_pixel_dir(const cr_frame *f, double i, double j,
                                             double n[3])
{
    double sx, sy, c[3];
    double len;
    int k;
    cr_camera_screen(f, i, j, &sx, &sy);
    if (f->observer.projection == CR_PROJ_RECTILINEAR) {
        /* the paper's screen, kept operation for operation */
        for (k = 0; k < 3; k++)
            n[k] = f->cam[0][k] + sx * f->cam[1][k] + sy * f->cam[2][k];
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (k = 0; k < 3; k++)
            n[k] /= len;
        return;
    }
    cr_projection_dir(f->observer.projection, sx, sy, c);
    for (k = 0; k < 3; k++)
        n[k] = c[0] * f->cam[0][k] + c[1] * f->cam[1][k] + c[2] * f->cam[2][k];
}

/* The inverse of cr_camera_pixel_dir: the fractional pixel (i, j) in which
 * the local direction n (any length > 0) is seen. Returns 0 where the
 * projection does not show n (cr_projection_screen; for the fisheye also a
 * direction farther from forward than cr_camera_fisheye_radius, outside the
 * image circle), else 1. */
CR_HD static inline int cr_camera_dir_pixel(const cr_frame *f, const double n[3], double *i,
                                            double *j)
{
    double c[3], sx, sy;
    int k;
    for (k = 0; k < 3; k++)
        c[k] = n[0] * f->cam[k][0] + n[1] * f->cam[k][1] + n[2] * f->cam[k][2];
    if (!cr_projection_screen(f->observer.projection, c, &sx, &sy))
        return 0;
    if (f->observer.projection == CR_PROJ_FISHEYE &&
        sx * sx + sy * sy > cr_camera_fisheye_radius(f) * cr_camera_fisheye_radius(f))
        return 0;
    *i = 0.5 * (sx / f->tan_half_h + 1.0) * f->width - 0.5;
    *j = 0.5 * (1.0 - sy / f->tan_half_v) * f->height - 0.5;
    return 1;
}

/* Initial state and constants of the backward ray that looks in the local
 * unit direction n: the tangent is the past-directed -k = -e_t + n^i e_i of
 * the photon with unit energy in the observer's frame arriving from n.
 *
 * On the axis (sin theta = 0) e_ph does not exist; every direction there has
 * L = 0, and the ray leaving the pole horizontally towards Cartesian azimuth
 * psi is the ray at phi = psi moving in theta. */
CR_HD static inline void cr_camera_ray(const cr_frame *f, const double n[3], cr_geo *g,
                                       double y[CR_NY])
{
    const cr_observer *o = &f->observer;
    cr_metric_point p;
    double u[4];
    int k;
    g->mt = f->metric;
    y[CR_Y_T] = 0.0;
    y[CR_Y_R] = o->r;
    y[CR_Y_TH] = o->theta;
    y[CR_Y_PH] = o->phi;
    for (k = 0; k < 4; k++)
        u[k] = -f->tetrad[0][k] + n[0] * f->tetrad[1][k] + n[1] * f->tetrad[2][k] +
               n[2] * f->tetrad[3][k];
    if (f->obs_on_axis) {
        /* Horizontal part n_th e_th + n_ph e_ph at the pole, as a Cartesian
         * vector: e_th = (cos th cos ph, cos th sin ph, 0), e_ph = (-sin ph, cos ph, 0). */
        double ct = f->obs_on_axis > 0 ? 1.0 : -1.0;
        double hx = n[1] * ct * cos(o->phi) - n[2] * sin(o->phi);
        double hy = n[1] * ct * sin(o->phi) + n[2] * cos(o->phi);
        double hl = sqrt(hx * hx + hy * hy);
        y[CR_Y_TH] = f->obs_on_axis > 0 ? 0.0 : CR_PI;
        y[CR_Y_PH] = hl > 0.0 ? atan2(hy, hx) : o->phi;
        u[2] = ct * hl * f->tetrad[2][2];
        u[3] = 0.0;
    }
    y[CR_Y_UR] = u[1];
    y[CR_Y_UTH] = u[2];
    if (f->obs_inside) {
        /* from the covariant legs: regular near r+ (camera_prepare) */
        g->E = -f->tetrad_low[0][0];
        g->L = -f->tetrad_low[0][1];
        for (k = 0; k < 3; k++) {
            g->E += n[k] * f->tetrad_low[k + 1][0];
            g->L += n[k] * f->tetrad_low[k + 1][1];
        }
    } else {
        cr_metric_eval(&f->metric, o->r, y[CR_Y_TH], &p);
        cr_geo_constants(&p, u, &g->E, &g->L);
    }
    if (f->obs_on_axis)
        g->L = 0.0;
    cr_geo_set_floor(g, y);
}

/* Mino state and constants of the ray that reaches the observer at infinity
 * at impact coordinates (alpha, beta) (Bardeen 1973): alpha along the image
 * right, beta along the image up (cam[1], cam[2] of the frame, in units of
 * M). The photon has unit energy at infinity (E = 1), so
 *   dn/dtau = alpha e_right + beta e_up  (Cartesian),  L = (n x dn/dtau)_z,
 * which is the textbook lambda = -alpha sin(theta_o) with the sign of
 * geodesic.h, and eta = |dn/dtau|^2 - L^2 - a^2 cos^2(theta_o)
 * = beta^2 + (alpha^2 - a^2) cos^2(theta_o) for roll = 0. */
CR_HD static inline void cr_camera_ray_at_infinity(const cr_frame *f, double alpha,
                                                   double beta, cr_mino *c, double *y)
{
    const cr_observer *o = &f->observer;
    double st = sin(o->theta), ct = cos(o->theta), sp = sin(o->phi), cp = cos(o->phi);
    double v[3], d[3], L, eta;
    int k;
    for (k = 0; k < 3; k++)
        v[k] = alpha * f->cam[1][k] + beta * f->cam[2][k];
    /* local (e_r, e_th, e_ph) -> Cartesian */
    d[0] = v[0] * st * cp + v[1] * ct * cp - v[2] * sp;
    d[1] = v[0] * st * sp + v[1] * ct * sp + v[2] * cp;
    d[2] = v[0] * ct - v[1] * st;
    y[CR_M_W] = 0.0;
    y[CR_M_DW] = 1.0;
    y[CR_M_NX] = st * cp;
    y[CR_M_NY] = st * sp;
    y[CR_M_NZ] = ct;
    y[CR_M_DNX] = d[0];
    y[CR_M_DNY] = d[1];
    y[CR_M_DNZ] = d[2];
    y[CR_M_PR] = 0.0;
    L = y[CR_M_NX] * d[1] - y[CR_M_NY] * d[0];
    eta = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - L * L -
          f->metric.a * f->metric.a * ct * ct;
    cr_mino_init(c, &f->metric, 1.0, L, eta, f->w_stop);
    cr_mino_t_start(c, y);
}

#endif
