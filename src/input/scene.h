/* curray input: scene files (appendix E.4) and their evaluation per frame.
 *
 * A cr_scene is the parsed file (scene_parse.c): every number that may be
 * animated is a cr_anim; the evaluation (scene_eval.c), cr_scene_frame() or
 * cr_frame_eval_at(), turns it into the plain cr_frame of frame k of n
 * (ERRATA "Animation": value = a + (b - a) k / (n - 1); a single frame takes a).
 *
 * Units: lengths in the scene's units of M (geometrized); angles are stored
 * in radians after unit conversion ("90", "90 deg", "1.570796 rad",
 * "0.5 pi"; a bare number is degrees). Colours 0..255.
 */
#ifndef CR_IO_SCENE_H
#define CR_IO_SCENE_H

#include <stddef.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "settings.h"

/* A value that may be animated: [linear, a, b] gives a != b; a plain value
 * has a == b. */
typedef struct cr_anim {
    double a, b;
} cr_anim;

static inline double cr_anim_at(cr_anim v, int k, int n)
{
    return n > 1 ? v.a + (v.b - v.a) * (double)k / (double)(n - 1) : v.a;
}

typedef struct cr_scene_sphere {
    cr_rgb color;
    int n_lat, n_lon;
    cr_anim r, theta, phi;       /* BL position; angles rad */
    cr_anim roll, pitch, yaw;    /* rad, default 0 */
    cr_anim radius;              /* Cartesian radius */
    int line;                    /* line of its `sphere:` key, for messages */
    int motion;                  /* cr_scene_sphere_motion (sphere.motion) */
    int retrograde;              /* motion orbit: against the hole's spin */
    int r_isco;                  /* motion orbit, r: isco (r is that orbit's ISCO) */
    double omega;                /* motion rotating: dphi/dt, 1 / the scene's length
                                    unit (default 0: at rest) */
    /* motion particle: the particle's initial data (sphere.particle, the
     * keys of an orbit file's particle section; owned), NULL otherwise;
     * r, theta, phi above are its start. wl: its worldline, samples of
     * cr_scene.track (core/track.h), in units of M as the core takes it. */
    struct cr_particle_spec *particle;
    cr_sphere_worldline wl;
} cr_scene_sphere;

/* How a sphere moves (sphere.motion; core/sphere.h). A moving one is seen
 * with the light's travel time at the frame's observer.t. */
typedef enum cr_scene_sphere_motion {
    CR_SPHERE_MOTION_STATIC = 0,   /* the paper's sphere: no time (default) */
    CR_SPHERE_MOTION_ORBIT = 1,    /* on the circular equatorial geodesic at its r */
    CR_SPHERE_MOTION_ROTATING = 2, /* turning rigidly about the axis at omega */
    CR_SPHERE_MOTION_PARTICLE = 3  /* carried along a massive (charged) particle's
                                      worldline from its initial data */
} cr_scene_sphere_motion;

/* The spectrum section (-t s, src/output/spectrum.h): a line profile and
 * the blackbody continuum of a Keplerian disc. Energies in keV. */
typedef struct cr_spectrum_spec {
    int given;                /* the scene has a spectrum section */
    double line_e0, line_q;   /* line.energy_kev (6.4), line.emissivity_index (3) */
    int line_bins;            /* line.bins (200), linear in energy */
    double line_lo, line_hi;  /* line.range (default 0.1 to 1.5 x energy_kev) */
    double f_col;             /* continuum.f_col (1.7) */
    int cont_bins;            /* continuum.bins (100), logarithmic in energy */
    double cont_lo, cont_hi;  /* continuum.range; 0, 0 (the default): 0.01 to 30 x
                                 f_col k T_peak of the frame's disc */
} cr_spectrum_spec;

/* The defaults of every spectrum key. */
cr_spectrum_spec cr_spectrum_defaults(void);

typedef struct cr_scene {
    char *path; /* the file it was read from */

    cr_anim m, a, q; /* metric: required */

    cr_anim obs_r, obs_theta, obs_phi; /* required */
    int obs_at_infinity;               /* r: inf (not animatable): obs_r = +inf, the
                                          observer at infinity (Bardeen's image plane) */
    int obs_r_infall;                  /* r: [infall, r_start, r_end] (obs_r = start,
                                          end): frame k at proper time k/(n-1) of the
                                          way along the free fall of motion infall,
                                          phi following it (scene_eval.c) */
    cr_anim roll, pitch, yaw;          /* optional, default 0; at infinity
                                          pitch = yaw = 0 (it can only roll) */
    cr_anim hfov;                      /* required for a finite r; unused at infinity */
    cr_anim vfov;                      /* optional: has_vfov == 0 -> from (E.4.1) */
    int has_vfov;
    cr_anim hextent;                   /* r: inf only, required: full width of the image
                                          plane (impact parameter alpha), a length like r */
    cr_anim vextent;                   /* r: inf only, optional: has_vextent == 0 ->
                                          hextent * height / width (square pixels) */
    int has_vextent;
    int obs_motion;      /* cr_motion, default CR_MOTION_STATIC (observer.motion) */
    cr_anim obs_v[3];    /* CR_MOTION_VELOCITY: (v_r, v_theta, v_phi) measured by
                            the ZAMO, each animatable */
    int obs_retrograde;  /* CR_MOTION_ORBIT: against the hole's spin */
    int obs_projection;  /* cr_projection, default CR_PROJ_RECTILINEAR */
    cr_anim obs_t;       /* observer.t: the observer's time of frame k is
                            obs_t(k) + k obs_dt (default 0; only with a moving
                            sphere), in the scene's length unit */
    double obs_dt;       /* observer.dt, default 0 */

    int has_disc;
    cr_rgb disc_color1, disc_color2; /* color2 defaults to (E.4.2) with ERRATA 3 */
    int disc_n_radial, disc_n_sectors;
    cr_anim disc_yaw;                /* default 0 */
    cr_anim disc_r_in, disc_r_out;
    int disc_model;          /* cr_disc_model; CR_DISC_CHESSBOARD by default */
    int disc_retrograde;     /* keplerian: orbits against the hole's spin */
    double disc_temperature; /* keplerian: peak temperature, K, > 0 (default 1e4) */
    int disc_has_r_in;       /* keplerian: 0 when the inner radius is omitted (the ISCO) */
    int disc_plunge;         /* keplerian: inside_isco: plunging (1) or nothing (0) */
    double disc_mass_msun;   /* keplerian: hole's mass in solar masses, 0 = unset */
    double disc_mdot_edd;    /* keplerian: accretion rate in Eddington units, 0 = unset */
    int disc_order;          /* accretion.order: the disc only in that image order
                                (cr_disc.order_sel), -1 (default) in all */
    cr_anim disc_exposure;   /* keplerian: factor on the disc's light, > 0 (default 1;
                                0 in both ends, as in a zeroed scene, also means 1) */
    int disc_exposure_auto;  /* keplerian: exposure: auto (cr_scene_auto_exposure) */
    double disc_exposure_found; /* the factor auto exposure chose (0: not computed yet) */

    int has_sky;
    char *sky_image;      /* path as resolved relative to the scene file's folder */
    cr_anim sky_boundary; /* R of 6.10, > 0, when sky_at_infinity == 0 */
    int sky_at_infinity;  /* boundary omitted or inf: the sky at infinity (frame
                             sky_boundary = 0: the ray's asymptotic direction) */
    uint8_t *sky_rgb;     /* loaded pixels, width*height*3, row 0 = theta 0; with
                             skymap.other_side that image's pixels follow */
    int sky_width, sky_height;
    char *sky_other_image; /* skymap.other_side, resolved as sky_image; NULL: none */
    int sky_other_width, sky_other_height; /* 0 without it */

    cr_scene_sphere *spheres; /* in file order */
    int n_spheres;
    cr_track_point *track;    /* the worldline tables of motion: particle spheres,
                                 n_track samples in all (NULL, 0: none) */
    long n_track;

    cr_rgb sky_color;     /* default black */
    cr_rgb horizon_color; /* default red; black next to a keplerian disc */
    cr_rgb error_color;   /* default blue */
    cr_rgb limit_color;   /* default yellow */
    cr_rgb other_side_color; /* default purple (96, 0, 128) */
    cr_rgb singularity_color; /* default white (255, 255, 255) */
    cr_spectrum_spec spectrum; /* spectrum: (given = 0: the defaults) */
    int redshift_sky;     /* redshift_sky: colour the sky in r_<k>.png by its
                             shift (cr_redshift_sky_color); default 0, black as
                             in the paper (6.9) */
} cr_scene;

/* Read and check a scene file, including loading its sky image. On failure
 * returns -1 with a message naming the file, line, column and key, and leaves
 * *out zeroed (nothing to free). */
int cr_scene_load(const char *path, cr_scene *out, cr_err *err);

/* Same from a string already in memory (name is used in messages; relative
 * sky image paths resolve against the current directory). */
int cr_scene_load_string(const char *text, size_t len, const char *name, cr_scene *out,
                         cr_err *err);

void cr_scene_free(cr_scene *s);

/* Evaluate frame k of n (0 <= k < n) at width x height pixels into *f
 * (spheres written to sphere_buf, which must hold s->n_spheres entries and
 * outlive f), including cr_frame_prepare. The program's callers (the
 * command line, Python, the web build) evaluate frames with
 * cr_frame_eval_at below, which owns the spheres; this is its step (and
 * the tests'). ts == NULL takes the defaults
 * (cr_trace_defaults). Messages name the frame as "frame k of n" (k counted
 * from 0, like the output files) when n > 1. Returns -1 with a clear message when this frame's values
 * are physically impossible (ERRATA item 4): no horizon (M <= 0 or
 * a^2 + Q^2 > M^2), observer at or inside the horizon or inside the
 * ergosphere, a field of view outside (0, 180) deg, an image-plane extent
 * <= 0 (observer at infinity), a disc with r_in >= r_out or r_in < 0, a
 * sphere radius <= 0, a setting out of range (tolerance <= 0, ...), the rk4
 * integrator with the observer at infinity, ...
 * The observer at infinity gives observer.r = +INFINITY, hextent and vextent
 * set, hfov = vfov = 0; r_max may then be +INFINITY. */
int cr_scene_frame(const cr_scene *s, int k, int n, int width, int height,
                   const cr_trace_settings *ts, cr_frame *f, cr_sphere *sphere_buf, cr_err *err);

/* Hints about a valid scene that is likely not what was meant, for the
 * caller to show as warnings: a sky image that is not twice as wide as high
 * (stretched onto the 360 x 180 deg sky), a sphere wholly inside the event
 * horizon in some or all of the n frames (never seen), n > 1 frames with
 * nothing animated (n equal images). Writes up to max_hints messages, in that
 * order, and returns their number (0: nothing to say). */
int cr_scene_hints(const cr_scene *s, int n, cr_err *hints, int max_hints);

/* 1 when any number of the scene is animated ([linear, a, b] with a != b) or
 * the observer's time runs on over the frames (observer.dt: moving spheres). */
int cr_scene_animated(const cr_scene *s);
/* Automatic exposure of the Keplerian disc (accretion.exposure: auto), once
 * for the whole run: frame 0 of n is traced on the CPU at a preview size of
 * CR_AUTO_EXPOSURE_WIDTH pixels across (the height from width x height, one
 * sample a pixel, the disc at exposure 1), and the factor is chosen that
 * puts the CR_AUTO_EXPOSURE_PERCENTILE-th percentile of the luminance of its
 * lit disc pixels (before tone mapping) at CR_AUTO_EXPOSURE_LEVEL of the
 * tone curve's white. It depends only on the scene, the raytracer settings,
 * n and the aspect ratio: the same for every frame of an animation, for any
 * -x/-y of that aspect, on every backend and MPI rank, and again on
 * --resume. Stores it in s->disc_exposure_found (1 when no disc pixel is
 * lit) and returns 0; does nothing without exposure: auto; -1 with err set
 * when frame 0 cannot be evaluated or memory runs out. *lit receives the
 * number of lit disc pixels it used (may be NULL). */
#define CR_AUTO_EXPOSURE_WIDTH 192
#define CR_AUTO_EXPOSURE_PERCENTILE 99.0
#define CR_AUTO_EXPOSURE_LEVEL 0.8
int cr_scene_auto_exposure(cr_scene *s, int n, int width, int height,
                           const cr_trace_settings *ts, long *lit, cr_err *err);

/* An evaluated frame with the sphere array it points into, owned together:
 * cr_frame_eval_at evaluates frame k of n into e->frame (as cr_scene_frame),
 * growing e's sphere array when the scene has more spheres than it holds.
 * e->frame (and every copy of it) stays valid until the next
 * cr_frame_eval_at or cr_frame_eval_free of e. A zeroed cr_frame_eval is
 * empty and ready. On failure e->frame is zeroed. */
typedef struct cr_frame_eval {
    cr_frame frame;
    cr_sphere *spheres; /* owned; room for n_room spheres */
    int n_room;
} cr_frame_eval;

int cr_frame_eval_at(cr_frame_eval *e, const cr_scene *s, int k, int n, int width, int height,
                     const cr_trace_settings *ts, cr_err *err);
void cr_frame_eval_free(cr_frame_eval *e);

/* The Keplerian disc's per-frame data (the scene's accretion model is
 * keplerian), as cr_scene_frame derives it: given the
 * metric mt and d->r_in (when the scene gives it), d->r_out in units of M,
 * sets d's sense, r_isco, t_peak (given, or derived from the mass and
 * accretion rate), the effective inner edge d->r_in = max(r_in, r_isco)
 * (the ISCO when the scene leaves r_in out) and the flux table
 * (cr_disc_keplerian_prepare). m is the scene's M, for radii in the scene's
 * units in messages. Returns -1 with why[0..n) saying what is impossible
 * (inner radius inside the horizon, ISCO beyond the outer radius, plunging
 * matter with r_in outside the ISCO, too extremal a hole); sense and r_isco
 * are set even then. */
int cr_scene_keplerian(const cr_scene *s, const cr_metric *mt, double m, cr_disc *d, char *why,
                       size_t n);

#endif
