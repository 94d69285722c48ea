/* curray core: shared definitions and plain-data types.
 *
 * Everything under src/core/ is header-only physics that compiles as C11 and
 * as CUDA C++ (nvcc). Rules: CR_HD static inline functions only, no
 * allocation, no I/O, no global mutable state, no VLAs or compound literals.
 *
 * Conventions (see DESIGN.md):
 *   - signature (-+++), G = c = 1; lengths in units of M when M = 1;
 *   - Boyer-Lindquist coordinates x^mu = (t, r, theta, phi), indices 0..3;
 *   - backward tracing: a ray starts at the observer with the PAST-directed
 *     tangent -k of the photon that arrives there (ERRATA item 1), so the
 *     conserved E = u_t (2.3.5) is positive for rays started outside the
 *     ergosphere and u^t < 0 along the ray;
 *   - all angles in radians.
 */
#ifndef CR_CORE_DEFS_H
#define CR_CORE_DEFS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __CUDACC__
#define CR_HD __host__ __device__
#else
#define CR_HD
#endif

#define CR_PI 3.14159265358979323846
#define CR_TWO_PI 6.28318530717958647692

/* An 8-bit sRGB colour. */
typedef struct cr_rgb {
    uint8_t r, g, b;
} cr_rgb;

/* Kerr-Newman parameters: mass M > 0, spin a = J/M, charge Q (geometrized
 * units). A horizon exists iff a^2 + Q^2 <= M^2. */
typedef struct cr_metric {
    double m, a, q;
} cr_metric;

/* How the observer moves (observer.motion; observer.h). Values are stable. */
typedef enum cr_motion {
    CR_MOTION_STATIC = 0,   /* at rest in BL coordinates (the paper's; default) */
    CR_MOTION_ZAMO = 1,     /* the zero angular momentum observer */
    CR_MOTION_ORBIT = 2,    /* circular equatorial geodesic (retrograde: sense) */
    CR_MOTION_INFALL = 3,   /* falling from rest at infinity, E = 1, L = 0 */
    CR_MOTION_VELOCITY = 4, /* the 3-velocity v measured by the ZAMO */
    CR_MOTION_COUNT_ = 5
} cr_motion;

/* How pixels map to directions (observer.projection; observer.h). */
typedef enum cr_projection {
    CR_PROJ_RECTILINEAR = 0, /* flat pinhole screen (the paper's; default) */
    CR_PROJ_FISHEYE = 1,     /* equidistant, fields of view up to 2 pi */
    CR_PROJ_EQUIRECT = 2,    /* full sphere, 2 pi x pi */
    CR_PROJ_COUNT_ = 3
} cr_projection;

/* An observer at BL position (r, theta, phi) moving as motion says (v: the
 * 3-velocity measured by the ZAMO, for CR_MOTION_VELOCITY; retrograde: the
 * sense of CR_MOTION_ORBIT), its camera mapping pixels by projection.
 * roll, pitch, yaw rotate the camera (section 6.4, see camera.h); hfov, vfov
 * are the full fields of view in (0, pi) (rectilinear), (0, 2 pi]
 * (fisheye), unused (equirectangular). All angles in radians.
 * r = +INFINITY is the observer at infinity (Bardeen 1973): its image is the
 * plane of impact coordinates (alpha, beta), of full extents hextent x
 * vextent in units of M, centred on the hole; only roll applies there
 * (pitch = yaw = 0) and hfov, vfov are unused. For a finite r, hextent and
 * vextent are unused. */
typedef struct cr_observer {
    double r, theta, phi;
    double roll, pitch, yaw;
    double hfov, vfov;
    double hextent, vextent;
    int motion;     /* cr_motion */
    int projection; /* cr_projection */
    int retrograde;
    double v[3];    /* (v_r, v_theta, v_phi), |v| < 1 */
} cr_observer;

/* Number of nodes of the disc flux table (orbit.h explains the choice). */
#define CR_FLUX_TABLE_N 128

/* The Novikov-Thorne disc flux table, filled once per frame on the host by
 * cr_flux_table_fill and read per ray by cr_flux_table_F (orbit.h, where the
 * fields are described). Declared here so that it can travel in cr_frame. */
typedef struct cr_flux_table {
    cr_metric mt;
    int sense;
    double r0, r_out;
    double rc;
    double t0, dt;
    double J[CR_FLUX_TABLE_N];
    double dJdt[CR_FLUX_TABLE_N];
    double r_peak, F_max;
} cr_flux_table;

/* Disc models (accretion.model). Values are stable (written to info.txt). */
typedef enum cr_disc_model {
    CR_DISC_CHESSBOARD = 0, /* the paper's static chessboard (default) */
    CR_DISC_KEPLERIAN = 1,  /* circular equatorial geodesic orbits, blackbody
                               colour T(r) seen with the shift g */
    CR_DISC_MODEL_COUNT_ = 2
} cr_disc_model;

/* Thin accretion disc in the plane theta = pi/2 between BL radii r_in < r_out.
 * CR_DISC_CHESSBOARD: a chessboard of n_radial rings x n_sectors sectors
 * rotated by yaw about the polar axis; color1 is the top (theta < pi/2) face,
 * color2 the bottom.
 * CR_DISC_KEPLERIAN (fields below "keplerian", derived once per frame by
 * cr_disc_keplerian_prepare in disc.h): matter on circular orbits of sense
 * `sense` (+1: counter-clockwise about +z); r_in is the effective inner edge
 * max(requested r_in, r_isco), so rays pass through the disc plane inside the
 * ISCO (nothing there); T(r) = t_scale F(r)^(1/4) in K from the flux table,
 * peaking at t_peak; the colour is cr_bb_rgb8(T, g, exposure, white). */
typedef struct cr_disc {
    int enabled;
    cr_rgb color1, color2;
    int n_radial, n_sectors;
    double yaw;
    double r_in, r_out;
    /* keplerian */
    int model; /* cr_disc_model */
    int sense;
    double r_isco;   /* ISCO of that sense, units of M */
    double t_peak;   /* K, > 0 */
    double t_scale;  /* K (Mdot / M^2)^(-1/4) */
    double exposure; /* sr m^2 / W: linear sRGB luminance 1 for T = t_peak at g = 1 */
    double white;    /* tone-curve white point (linear) */
    cr_flux_table flux;
    /* physical inputs (accretion.mass_msun, mdot_edd): both > 0 to derive
       t_peak from the hole's mass (solar masses) and the accretion rate (in
       Eddington units), 0 when t_peak is given */
    double mass_msun, mdot_edd;
    /* inside the ISCO (accretion.inside_isco): plunge = 1 puts matter
       falling from the ISCO with its E_isco, L_isco (cr_orbit_plunge_velocity)
       between the horizon and r_in, dark (zero flux); 0: nothing there */
    int plunge;
    double E_isco, L_isco;
    double r_hit_in; /* derived (cr_frame_prepare): the smallest BL radius where
                        rays meet the disc: r+ with plunging matter, else r_in */
    int order_sel;   /* accretion.order N: N + 1, the disc is met only on
                        the ray's equator crossing of order N (0 the direct
                        image, 1 the first ring, ...), rays pass through it
                        on the others; 0 (the default, a zeroed frame's):
                        met on every crossing */
} cr_disc;

/* A particle sphere's worldline, tabulated in coordinate time (track.h):
 * samples off .. off + n - 1 of cr_frame.track at BL times t0 + i h, the
 * start's azimuth ph0, and bounds of the sphere's points at every time over
 * it: reach_lo <= |x| <= reach_hi, z_lo <= z <= z_hi (sphere.h,
 * cr_sphere_far); units of M. */
typedef struct cr_sphere_worldline {
    long off;
    int n;
    double t0, h, ph0;
    double reach_lo, reach_hi, z_lo, z_hi;
} cr_sphere_worldline;

/* A sphere defined in the Cartesian coordinates (2.2.8). Centre at BL
 * (r, theta, phi); chessboard of n_lat latitude bands x n_lon longitude
 * sectors; orientation by roll, pitch, yaw about its local axes (E.4).
 * center[] and axes[][] are derived by cr_sphere_prepare (sphere.h):
 * axes[0] = longitude-zero direction, axes[1] = the sphere's north pole,
 * axes[2] = longitude +90 deg, all unit Cartesian vectors. */
typedef struct cr_sphere {
    cr_rgb color;
    int n_lat, n_lon;
    double r, theta, phi;
    double roll, pitch, yaw;
    double radius;
    double center[3];
    double axes[3][3];
    /* Motion (sphere.motion; sphere.h): moving = 0 is the paper's static
     * sphere (no time enters). moving = 1: the sphere turns rigidly about the
     * polar axis at omega = dphi/dt (1/M; the Keplerian circular orbit's
     * angular velocity for motion: orbit, 0 for a sphere at rest that is
     * still traced with the light's travel time): at BL coordinate time t it
     * is the sphere above (its phi the phase at t = 0) turned by omega t
     * about the polar axis.
     * particle = 1 (moving = 1, omega = 0): the sphere's centre moves on
     * the worldline wl; the sphere above is its place at wl.t0 (centre at
     * sample 0, azimuth wl.ph0 there), carried with the centre and turned
     * about the polar axis by the centre's azimuth since. */
    int moving;
    double omega;
    int particle;
    cr_sphere_worldline wl;
} cr_sphere;

/* One sample of a tabulated worldline (track.h): the Cartesian position x
 * (2.2.8) of the particle and its continuous BL azimuth ph, with their
 * coordinate-time rates v = dx/dt and w = dph/dt (from u^mu / u^t). */
typedef struct cr_track_point {
    double x[3], ph;
    double v[3], w;
} cr_track_point;

/* An equirectangular sky texture, rgb[3 * (y * width + x)], row y = 0 at the
 * sky's theta = 0 (6.10.1). The pointer is host or device memory, matching
 * the backend that traces the frame. other_width x other_height (0 x 0:
 * none) is the sky of the other exterior of the eternal hole
 * (skymap.other_side; ray.h's mirror), stored in the same block right after
 * ours, at rgb + 3 width height; 3 (width height + other_width
 * other_height) bytes in all (cr_sky_bytes, sky.h). */
typedef struct cr_sky {
    const uint8_t *rgb;
    int width, height;
    int other_width, other_height;
} cr_sky;

/* How a ray ended. Values are stable: they are written to CSV files. */
typedef enum cr_outcome {
    CR_OUT_NONE = 0,    /* not traced */
    CR_OUT_HORIZON = 1, /* reached r+ + epsilon */
    CR_OUT_DISC = 2,    /* hit the accretion disc */
    CR_OUT_SPHERE = 3,  /* hit a sphere */
    CR_OUT_SKY = 4,     /* left the scene boundary r_max outward */
    CR_OUT_ERROR = 5,   /* numerical failure (non-finite state) */
    CR_OUT_LIMIT = 6,   /* step or turn limit reached (e.g. photon-sphere orbit);
                           painted in limit_color */
    CR_OUT_OUTSIDE = 7, /* outside the picture: a fisheye pixel beyond its image
                           circle (cr_camera_in_image); not traced, black */
    CR_OUT_OTHER_SIDE = 8, /* a ray from inside the outer horizon that leaves the
                           interior through its past boundary away from our
                           exterior (toward the other exterior of the eternal
                           hole; ray.h); painted in other_side_color */
    CR_OUT_SINGULARITY = 9, /* a ray from inside the inner horizon that reached
                           r = 0 (closer than CR_R_SING, frame.h; ray.h): the central
                           singularity, or for a != 0 the ring or the disc
                           inside it, beyond which (r < 0) curray does not
                           follow it; painted in singularity_color */
    CR_OUT_COUNT_ = 10
} cr_outcome;

/* The integrator that traces the rays (raytracer.integrator).
 *   CR_INTEG_MINO: Mino time, w = 1/r, the polar motion as a unit vector,
 *     Dormand-Prince 5(4) with error control (mino.h); the default.
 *   CR_INTEG_RK4: the paper's fixed-rule RK4 in the affine parameter
 *     (geodesic.h), kept to reproduce the paper. */
typedef enum cr_integrator {
    CR_INTEG_MINO = 0,
    CR_INTEG_RK4 = 1,
    CR_INTEG_COUNT_ = 2
} cr_integrator;

/* Whether the CPU backend may trace W rays at a time in vector lanes
 * (cpu.simd; src/render/cpu.h): auto picks the widest the CPU has, off
 * keeps the scalar path. Both give the same pixels. */
typedef enum cr_simd_mode {
    CR_SIMD_AUTO = 0,
    CR_SIMD_OFF = 1,
    CR_SIMD_COUNT_ = 2
} cr_simd_mode;

/* Largest raytracer.samples: samples^2 sub-pixel rays per pixel. */
#define CR_MAX_SAMPLES 16

/* Everything needed to trace every pixel of one frame: plain data, no
 * pointers but the sphere array, the worldline table and the sky texture
 * (all read-only).
 * Filled by the scene module for frame k, then completed by
 * cr_frame_prepare (frame.h), which derives the fields marked "derived". */
typedef struct cr_frame {
    cr_metric metric;
    cr_observer observer;
    cr_disc disc;
    const cr_sphere *spheres;
    int n_spheres;
    const cr_track_point *track; /* the worldline samples of particle spheres
                                    (cr_sphere.particle), n_track in all; host
                                    or device memory as the sky texture */
    long n_track;
    cr_sky sky;          /* sky.rgb == NULL: plain sky_color */
    double sky_boundary; /* R of 6.10; 0 when unset */
    cr_rgb sky_color, horizon_color, error_color;
    cr_rgb limit_color;  /* rays that end on max_steps or max_turns */
    cr_rgb other_side_color; /* rays that end as CR_OUT_OTHER_SIDE */
    cr_rgb singularity_color; /* rays that end as CR_OUT_SINGULARITY */
    int width, height;
    double t_obs;           /* the observer's BL coordinate time of the frame
                               (observer.t, units of M; renormalised as
                               cr_ray_delay for the observer at infinity):
                               a moving sphere is met at t_obs - the ray's
                               delay (sphere.h); 0 when nothing moves */

    /* raytracer settings (system configuration; their defaults and limits:
       src/input/settings.def) */
    int integrator;         /* cr_integrator */
    double tolerance;       /* CR_INTEG_MINO: relative and absolute local
                               error tolerance per step, > 0 */
    double step_multiplier; /* c of (6.6.1), > 0 (CR_INTEG_RK4) */
    double horizon_epsilon; /* epsilon of 6.8, > 0 */
    long max_steps;         /* steps before CR_OUT_LIMIT */
    double max_turns;       /* accumulated |dphi|/2pi before CR_OUT_LIMIT */
    int samples;            /* antialiasing: samples x samples sub-pixel rays
                               per pixel (cr_trace_pixel); 1 (or any value
                               outside 2..CR_MAX_SAMPLES) traces one ray */
    int science;            /* the frame's pixels are read for their values
                               (hit_r, hit_phi, g, delay: CSV, FITS, the
                               spectrum and light curve, Python),
                               not only for colours: its Mino steps take the
                               tighter tolerance of cr_ray_tolerance (ray.h);
                               0 (colour images, today's steps) unless the
                               caller sets it after the frame is made */

    /* derived */
    double r_stop;        /* r+ + epsilon */
    double r_max;         /* scene boundary (6.8, 6.10): beyond the objects
                             (and, with a sky image, the observer and the sky
                             boundary); INFINITY for the observer at infinity */
    double w_stop;        /* 1 / r_stop (CR_INTEG_MINO) */
    double w_sky;         /* CR_INTEG_MINO: an outgoing ray ends as sky at
                             w = 1/r <= w_sky; 0 (at infinity) when the sky
                             image has no boundary or the observer is at
                             infinity, else 1 / r_max as for RK4 */
    double w_obj;         /* CR_INTEG_MINO: 1 / (the largest BL radius an
                             object of the scene reaches: disc r_out, sphere
                             extents), INFINITY with none; a ray moving
                             outward at w < w_obj meets nothing more, so its
                             time is not needed (ray.h) */
    int obs_at_inf;       /* observer.r is +INFINITY */
    double obs_sqrt_mgtt; /* sqrt(-g_tt) at the static observer; 1/u^t of a
                             moving one (camera.h) */
    double tan_half_h, tan_half_v; /* screen half-extents (observer.h):
                             tan(fov/2) rectilinear, fov/2 fisheye, pi and
                             pi/2 equirectangular */
    double cam[3][3];     /* camera forward, right, up in the observer's local
                             orthonormal (e_r, e_theta, e_phi) basis */
    double tetrad[4][4];  /* BL components of the observer's e_t (its
                             4-velocity), e_r, e_theta, e_phi (observer.h) */
    int obs_on_axis;      /* +1 north pole, -1 south pole, 0 otherwise */
    int obs_inside;       /* the observer is between the horizons, r- < r < r+
                             (observer.h: the free-fall frame; ray.h: the
                             ingoing chart) */
    double tetrad_low[4][2]; /* obs_inside: the covariant t and phi components
                             of the tetrad's legs (regular where the BL
                             contravariant ones grow as 1/Delta) */
    double w_other;       /* obs_inside: 1 / (r+ - epsilon), where a ray bound
                             for the other side ends */
    int obs_inner;        /* the observer is inside the inner horizon,
                             0 < r < r- (obs_inside is set too) */
    double w_minus;       /* 1 / r- (INFINITY when r- = 0): rays from inside
                             r- leave it at w < w_minus */
    double w_sing;        /* 1 / CR_R_SING: a ray from inside r- that gets
                             there ends as CR_OUT_SINGULARITY */
} cr_frame;

/* Result for one pixel. redshift = omega_r / omega_s (6.9), -1 where it is
 * not defined (source inside the ergosphere, error, limit). err_mean and
 * err_std are the mean and standard deviation of the null error (6.7.1) over
 * the ray's steps. object: sphere index for CR_OUT_SPHERE, 0 top / 1 bottom
 * face for CR_OUT_DISC, -1 otherwise. hit_r, hit_phi: the BL radius (units
 * of M) and azimuth (radians, in [0, 2 pi)) of the point where the ray hit
 * the disc or a sphere, located inside the step as the colour is; -1 (never a
 * valid value of either) for every other outcome. 72 bytes. */
typedef struct cr_pixel {
    double redshift;
    double err_mean, err_std;
    double hit_r, hit_phi;
    double bolo; /* Keplerian disc hits: the bolometric brightness g^4 F(r) /
                    F_max (cr_bolometric; F_max the disc's peak flux), 0 on
                    plunging matter; moving sphere hits: g^4, the
                    bolometric intensity of a surface of unit intensity in
                    its rest frame (sphere.h); -1 for every other outcome,
                    disc or sphere */
    double delay; /* disc and sphere hits: the coordinate-time delay t_obs - t
                     of the light from the hit (cr_ray_delay; renormalised for
                     the observer at infinity); NaN for every other outcome */
    uint32_t steps;
    int16_t object;
    /* the image order: equator crossings (theta = pi/2) before the hit, or
       before the ray ended without one; polar turning points (sign changes
       of d cos(theta)) before the same point; both capped at CR_COUNT_MAX */
    int16_t order, theta_turns;
    uint8_t outcome;
    cr_rgb color;
} cr_pixel;

/* The largest count cr_pixel.order and theta_turns hold. */
#define CR_COUNT_MAX 32767

CR_HD static inline int cr_isfinite(double x)
{
    return x - x == 0.0;
}

/* Golden-section search for the smallest value of a unimodal function on
 * [lo, hi], written once for every user (the sphere dip inside a step, the
 * peak of the disc flux). The bracket holds interior points x1 < x2 with
 * their values f1, f2; the caller evaluates the function, since C has no
 * closures: cr_golden_start sets x1, x2 (evaluate both), then each
 * cr_golden_shrink narrows the bracket and returns 1 when the one new point
 * is x1 (evaluate it into f1) or 2 when it is x2 (into f2). */
typedef struct cr_golden {
    double lo, hi, x1, x2, f1, f2;
} cr_golden;

#define CR_GOLDEN_RATIO_INV 0.61803398874989484820

CR_HD static inline void cr_golden_start(cr_golden *g, double lo, double hi)
{
    g->lo = lo;
    g->hi = hi;
    g->x1 = hi - CR_GOLDEN_RATIO_INV * (hi - lo);
    g->x2 = lo + CR_GOLDEN_RATIO_INV * (hi - lo);
}

CR_HD static inline int cr_golden_shrink(cr_golden *g)
{
    if (g->f1 < g->f2) {
        g->hi = g->x2;
        g->x2 = g->x1;
        g->f2 = g->f1;
        g->x1 = g->hi - CR_GOLDEN_RATIO_INV * (g->hi - g->lo);
        return 1;
    }
    g->lo = g->x1;
    g->x1 = g->x2;
    g->f1 = g->f2;
    g->x2 = g->lo + CR_GOLDEN_RATIO_INV * (g->hi - g->lo);
    return 2;
}

/* Root of a function of the step fraction s on [0, s_hi] whose values v0 at
 * s = 0 and v1 at s_hi have opposite signs, by the Illinois variant of
 * regula falsi, written once for every event located inside a step (the
 * disc plane and the sky radius in ray.h, the spheres in sphere.h). The
 * caller evaluates the function, as for cr_golden: cr_falsi_start, then
 * while cr_falsi_next gives a new point z.s, evaluate the function there and
 * pass the value to cr_falsi_update, which returns 0 once the root is found
 * (value 0 or below 1e-13 in magnitude, or a bracket narrower than 1e-12).
 * At most 60 points; z.s is the last one. */
typedef struct cr_falsi {
    double s_lo, s_hi, v0, v1, s;
    int side, it;
} cr_falsi;

CR_HD static inline void cr_falsi_start(cr_falsi *z, double v0, double s_hi, double v1)
{
    z->s_lo = 0.0;
    z->s_hi = s_hi;
    z->v0 = v0;
    z->v1 = v1;
    z->s = s_hi;
    z->side = 0;
    z->it = 0;
}

CR_HD static inline int cr_falsi_next(cr_falsi *z)
{
    if (z->it >= 60)
        return 0;
    z->it++;
    z->s = (z->s_lo * z->v1 - z->s_hi * z->v0) / (z->v1 - z->v0);
    return 1;
}

CR_HD static inline int cr_falsi_update(cr_falsi *z, double v)
{
    if (v == 0.0 || z->s_hi - z->s_lo < 1e-12)
        return 0;
    if ((v < 0.0) == (z->v1 < 0.0)) {
        z->s_hi = z->s;
        z->v1 = v;
        if (z->side == -1)
            z->v0 *= 0.5;
        z->side = -1;
    } else {
        z->s_lo = z->s;
        z->v0 = v;
        if (z->side == 1)
            z->v1 *= 0.5;
        z->side = 1;
    }
    return !(fabs(v) < 1e-13);
}

#endif
