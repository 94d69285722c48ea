/* curray web: the entry point of the WebAssembly build (web/), also built
 * natively for the tests.
 *
 * The page describes a scene key by key with the scene file's own keys and
 * units (cr_web_set, cr_web_set_word); cr_web_frame then evaluates it with
 * the command line's scene evaluation (cr_frame_eval_at: the same checks and
 * messages) into a cr_frame, and cr_web_trace traces pixels of that frame
 * with cr_trace_pixel. Every number the page shows comes from here: the
 * page computes nothing physical.
 *
 * Units: lengths in the scene's units of M; angles in degrees, converted as
 * the scene file's "X deg" is; colours 0xRRGGBB. A cr_web is one scene and
 * its evaluated frame; nothing is shared between two of them, so one per
 * Web Worker traces independently.
 */
#ifndef CR_WASM_WEB_H
#define CR_WASM_WEB_H

#include <stdint.h>

/* Most spheres a page scene holds. */
#define CR_WEB_MAX_SPHERES 16
/* Largest sky image, in pixels (as the scene loader's limit, smaller). */
#define CR_WEB_MAX_SKY_PIXELS (1L << 24)

typedef struct cr_web cr_web;

/* A scene with the scene file's defaults (metric and observer unset: set
 * them before cr_web_frame), or NULL when out of memory. */
cr_web *cr_web_new(void);
void cr_web_free(cr_web *w);

/* Set the number at key, a dotted scene-file key ("metric.a",
 * "observer.theta", "accretion.r_out", ...; web.c lists them) in the file's
 * units (angles in degrees). inf is allowed where the file allows it
 * (observer.r, skymap.boundary); NaN unsets an optional key (observer.vfov,
 * observer.vextent, accretion.r_in of the keplerian disc, accretion.color2:
 * then the complement of color1). Returns 0, or -1
 * for an unknown key (cr_web_message says so). */
int cr_web_set(cr_web *w, const char *key, double value);

/* Set a word: observer.motion (static, zamo, orbit, infall, velocity),
 * observer.projection, accretion.model, accretion.inside_isco,
 * raytracer.integrator; name: the scene's name in messages (the file the
 * page saves it as; default scene.yml). Returns 0, or -1 for an unknown key
 * or word. */
int cr_web_set_word(cr_web *w, const char *key, const char *word);

/* Room for a sky image of width x height pixels, RGB, row 0 at theta = 0,
 * which the caller fills; the scene then has a skymap. width = 0 removes the
 * sky image. NULL (and no sky) when the size is refused or out of memory. */
uint8_t *cr_web_sky(cr_web *w, int width, int height);

/* Remove every sphere; add one (its keys then are sphere.color,
 * sphere.n_lat, sphere.n_lon, sphere.r, sphere.theta, sphere.phi,
 * sphere.roll, sphere.pitch, sphere.yaw, sphere.radius, for the sphere added
 * last). cr_web_add_sphere returns -1 when CR_WEB_MAX_SPHERES are there. */
void cr_web_clear_spheres(cr_web *w);
int cr_web_add_sphere(cr_web *w);

/* Evaluate the scene into the frame to trace at width x height pixels (the
 * command line's cr_frame_eval_at, default raytracer settings unless set).
 * Returns 0, or -1 with the command line's message (cr_web_message). */
int cr_web_frame(cr_web *w, int width, int height);

/* The last message ("" when none). Owned by w. */
const char *cr_web_message(const cr_web *w);

/* Trace n pixels of the evaluated frame: pixel index p = j * width + i in
 * pix[k]. For each: rgb[9k..9k+8] the colour image's, the redshift map's and
 * the bolometric map's colours (c_, r_, b_ PNG files of the command line),
 * outcome[k] (cr_outcome), val[4k..4k+3] redshift, hit_r (units of M),
 * hit_phi, bolometric brightness as the CSV file has them (-1 where not
 * defined). Returns the number traced: n, or 0 without an evaluated frame
 * or for an index outside it (nothing written from that one on). */
int cr_web_trace(const cr_web *w, const int32_t *pix, int n, uint8_t *rgb, uint8_t *outcome,
                 double *val);

/* What the ray through image point (x, y) (pixel units; (i, j) is the
 * centre of pixel (i, j)) does, into out[0..CR_WEB_PROBE_N): see the
 * CR_WEB_PROBE_* indices. Returns 0, or -1 without an evaluated frame. */
enum {
    CR_WEB_PROBE_OUTCOME,  /* cr_outcome */
    CR_WEB_PROBE_REDSHIFT, /* g as the CSV has it, -1 where not defined */
    CR_WEB_PROBE_HIT_R,    /* units of M, -1 where nothing was hit */
    CR_WEB_PROBE_HIT_PHI,  /* radians */
    CR_WEB_PROBE_BOLO,     /* g^4 F / F_max on a keplerian disc, else -1 */
    CR_WEB_PROBE_STEPS,
    CR_WEB_PROBE_OBJECT,   /* sphere index, disc face, or -1 */
    CR_WEB_PROBE_E,        /* the backward ray's constants: E = -p_t */
    CR_WEB_PROBE_L,        /* L = p_phi */
    CR_WEB_PROBE_CARTER,   /* Carter constant (K of geodesic.h; eta at infinity) */
    CR_WEB_PROBE_R_PLUS,   /* the frame's r+ (units of M) */
    CR_WEB_PROBE_N
};
int cr_web_probe(const cr_web *w, double x, double y, double *out);

/* Look around without tracing: fill out_rgba (width x height of view's
 * frame, RGBA) with the colour that view's pixel (i, j) sees in sky_rgba,
 * the RGBA image of an evaluated equirectangular frame sky of the same
 * observer (its frame's size), nearest sky pixel; black where the view shows
 * nothing. view's frame gives the projection, fields of view and camera
 * angles; both frames must hold the same observer position and motion (the
 * caller's contract). The camera mapping (cr_camera_pixel_dir, then
 * cr_camera_dir_pixel) is exact at the corners and centre of cells of
 * cell x cell pixels and bilinear inside, where that is within 0.1 sky
 * pixels of exact at the centre (else exact in the whole cell); cell <= 1:
 * exact at every pixel. Returns 0, or -1 when a frame is missing, sky is not
 * equirectangular, view is at infinity, or out of memory. */
int cr_web_reproject(const cr_web *view, const cr_web *sky, const uint8_t *sky_rgba,
                     uint8_t *out_rgba, int cell);

/* The cell size the page reprojects with (cr_web_reproject). */
#define CR_WEB_LOOK_CELL 8

/* The evaluated frame's size, 0 without one. */
int cr_web_width(const cr_web *w);
int cr_web_height(const cr_web *w);

#endif
