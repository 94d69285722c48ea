/* curray io: the orbit file of `curray orbit` (docs/scenes.md, "Orbits of
 * massive and charged particles"): the hole (metric) and one particle, its
 * charge-to-mass ratio, start and initial data, and how far and how densely
 * its worldline is written.
 *
 * Loading checks everything the integration needs (a speed below c, a start
 * outside the horizon, finite q/m, exactly one kind of initial data, and
 * that the constants allow the start): a loaded spec always starts
 * (cr_particle_spec_start). Errors read "FILE:LINE:COL: particle.KEY: ...".
 */
#ifndef CR_INPUT_PARTICLE_SPEC_H
#define CR_INPUT_PARTICLE_SPEC_H

#include <stddef.h>

#include "../base/error.h"
#include "core/particle.h"
#include "yamlutil.h"

/* The optional view section of an orbit file: the picture that
 * `curray orbit -t c` draws (docs/scenes.md, "The lensed picture"). */
typedef struct cr_orbit_view {
    int given;            /* the file has a view section */
    char scene[4096];     /* view.scene: a scene file (its camera, disc, spheres and sky),
                             relative to the orbit file's folder */
    char where[CR_ERR_MSG]; /* "FILE:LINE:COL: view.scene: " for messages about that scene */
    int by_tau;           /* view.color: proper_time (the default): from the first
                             row's colour to the last's */
    cr_rgb color;         /* view.color: [R, G, B], one colour */
    double line_width;    /* view.line_width: pixels, (0, 16], default 1.5 */
    int orders;           /* view.orders: images drawn, orders 0 .. orders - 1 (1 the
                             direct image only, 2 with the secondary, default 2; at most 4) */
} cr_orbit_view;

/* The kinds of initial data (exactly one in a file). */
enum {
    CR_PSPEC_VELOCITY = 0, /* 3-velocity measured by a static observer or the ZAMO */
    CR_PSPEC_CONSTANTS = 1, /* E, L, K and the signs of dr, dtheta */
    CR_PSPEC_CIRCULAR = 2  /* the circular equatorial geodesic at r */
};

typedef struct cr_particle_spec {
    cr_metric mt;
    double qm;              /* charge-to-mass ratio q/m */
    double r, theta, phi;   /* start, BL (radians) */
    double t0;              /* coordinate time at the start */
    int kind;               /* CR_PSPEC_* */
    double v[3];            /* CR_PSPEC_VELOCITY: (v_r, v_theta, v_phi) */
    int measured_by;        /* CR_PARTICLE_OBS_STATIC or _ZAMO */
    double E, L, K;         /* CR_PSPEC_CONSTANTS */
    int sr, sth;            /* signs of dr and dtheta (+1 outward, south) */
    int retrograde;         /* CR_PSPEC_CIRCULAR */
    double tau;             /* proper time to follow */
    double dtau;            /* output spacing in proper time */
    double tolerance;       /* DP5 tolerance */
    double r_max;           /* escape radius */
    double horizon_epsilon; /* the worldline ends at r+ + this */
    cr_orbit_view view;     /* the view section (view.given = 0: none) */
} cr_particle_spec;

/* Largest number of rows a worldline may have (tau / dtau). */
#define CR_PSPEC_MAX_ROWS 10000000.0

/* Load and check an orbit file (from a path, or from text named name). */
int cr_particle_spec_load(const char *path, cr_particle_spec *s, cr_err *err);
int cr_particle_spec_load_string(const char *text, size_t len, const char *name,
                                 cr_particle_spec *s, cr_err *err);

/* Parse and check one particle section: map (under key node key; NULL
 * when it has none) on the metric s->mt (the caller zeroes *s and sets
 * s->mt first; s->view is left alone). pre names the section in
 * messages ("particle" in an orbit file, "sphere[0].particle" in a scene:
 * "FILE:LINE:COL: pre.KEY: ..."). for_sphere: the section of a sphere's
 * motion: particle (docs/scenes.md), where dtau, an orbit file's output
 * spacing, is refused. The same checks as the loader: a spec it accepts
 * always starts (cr_particle_spec_start). */
int cr_particle_spec_parse(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *pre,
                           int for_sphere, cr_particle_spec *s, cr_err *err);

/* Start the particle of a loaded spec. Returns 1 (0 only for a spec that
 * did not come from the loader). */
int cr_particle_spec_start(const cr_particle_spec *s, cr_particle *p);

#endif
