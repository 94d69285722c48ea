/* curray input: the words of the scene and configuration formats for the
 * core's enumerations, each written once (names.c): observer.motion,
 * observer.projection, raytracer.integrator, accretion.model,
 * accretion.inside_isco, and the outcomes that CSV files, info.txt, FITS
 * headers and Python show.
 *
 * Word i of a kind names the enumerator of value i (cr_motion, cr_projection,
 * cr_integrator, cr_disc_model, cr_outcome of core/defs.h). */
#ifndef CR_INPUT_NAMES_H
#define CR_INPUT_NAMES_H

#include <stddef.h>

typedef enum cr_names {
    CR_NAMES_MOTION = 0,     /* static, zamo, orbit, infall (CR_MOTION_VELOCITY is a
                                list, not a word) */
    CR_NAMES_PROJECTION = 1, /* rectilinear, fisheye, equirectangular */
    CR_NAMES_INTEGRATOR = 2, /* mino, rk4 */
    CR_NAMES_DISC_MODEL = 3, /* chessboard, keplerian */
    CR_NAMES_INSIDE_ISCO = 4, /* nothing, plunging (cr_disc.plunge 0 or 1) */
    CR_NAMES_OUTCOME = 5,    /* none, horizon, disc, sphere, sky, error, limit, outside */
    CR_NAMES_SIMD = 6,       /* auto, off (cpu.simd, cr_simd_mode) */
    CR_NAMES_COUNT_ = 7
} cr_names;

/* The word of value v of kind, or "unknown" when v has none. */
const char *cr_name(cr_names kind, int v);

/* The value whose word is exactly text[0..len), or -1 when none is. */
int cr_name_parse(cr_names kind, const char *text, size_t len);

/* The same in any letter case, with blanks and tabs around the word
 * ignored (the configuration's words: raytracer.integrator). */
int cr_name_parse_folded(cr_names kind, const char *text, size_t len);

/* Number of words of kind: the values 0 .. n-1 have one. */
int cr_names_count(cr_names kind);

/* Every word of kind in value order, joined by ", " ("mino, rk4"), for
 * messages. */
const char *cr_names_list(cr_names kind);

/* The configuration name of an integrator ("mino", "rk4"), the same word
 * that raytracer.integrator takes and info.txt shows; "unknown" for a value
 * outside cr_integrator. */
const char *cr_integrator_name(int integrator);

/* The cr_integrator named by text[0..len) (any letter case, surrounding
 * blanks ignored), or -1 when it names none. */
int cr_integrator_parse(const char *text, size_t len);

/* The valid names, "mino, rk4", for messages. */
const char *cr_integrator_names(void);

/* Names of outcomes as used in CSV and info.txt; "unknown" outside
 * cr_outcome. */
const char *cr_outcome_name(int outcome);

#endif
