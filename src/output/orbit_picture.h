/* curray output: the lensed picture of a worldline (`curray orbit -t c`;
 * docs/outputs.md, "The lensed picture of an orbit").
 *
 * Each point of the worldline is shown where its light reaches the camera
 * of the view's scene: for every image order n drawn (core/lensing.h: 0 the
 * direct image, 1 the secondary one beyond the shadow, ...) the image point
 * whose ray passes through it, found by Newton's method on the image plane
 * (cr_lens_solve) from the image of the previous point (or, at the first
 * point and after a loss, from the best ray of a coarse grid over the image
 * and a margin around it). Between two points whose images lie more than
 * CR_OPIC_GAP pixels apart the worldline is cut in half (cubic Hermite
 * interpolation of the rows' positions and 4-velocities) and the midpoint
 * solved too, down to CR_OPIC_DEPTH halvings, so that the drawn curve
 * follows the images where they move fast (an Einstein ring as the
 * particle passes behind the hole). An image whose ray meets the disc or a
 * sphere of the scene before the point is hidden (not drawn; its row in
 * orbit_image.csv says visible 0).
 *
 * The picture is the scene's colour image (c_<k>.png's pixels) with the
 * images drawn over it as antialiased lines of the view's width, in its
 * colour or coloured by proper time. Nothing here prints. */
#ifndef CR_OUTPUT_ORBIT_PICTURE_H
#define CR_OUTPUT_ORBIT_PICTURE_H

#include <stdint.h>

#include "../base/error.h"
#include "../core/defs.h"
#include "../input/particle_spec.h"
#include "../input/scene.h"
#include "worldline.h"

/* Largest image gap between neighbouring solved points (pixels) before the
 * worldline is cut in half, and the most halvings of one row interval. */
#define CR_OPIC_GAP 1.0
#define CR_OPIC_DEPTH 14
/* Neighbouring images farther apart than this (pixels) after the halvings
 * are not joined by a line (the image jumped: it was hidden, or left
 * through a caustic). */
#define CR_OPIC_JOIN 4.0
/* Most points of the worldline taken from its rows (a longer worldline is
 * thinned evenly), and most Newton solutions of one image order. */
#define CR_OPIC_MAX_POINTS 20000
#define CR_OPIC_MAX_SOLVES 400000L

/* A point of the worldline in units of M: proper time, coordinate time,
 * Cartesian position (coords.h) and its derivatives d/dtau (u^t and the
 * Cartesian velocity). */
typedef struct cr_opic_point {
    double tau, t, x[3], ut, v[3];
} cr_opic_point;

/* A point of the worldline from a row of cr_worldline_run (its columns,
 * lengths in units of the orbit file's m, which are divided by it). */
void cr_opic_point_of_row(const double *row, const cr_metric *mt, cr_opic_point *p);

/* One image of a point: where (pixels, the convention of --trace: the
 * centre of pixel (I, J) at (I, J), I from the left, J from the top), when
 * its light arrives, whether it is seen. */
typedef struct cr_opic_image {
    double tau, t;  /* the worldline point */
    double i, j;    /* its image point */
    double t_obs;   /* t + the light's delay (renormalised at infinity, cr_ray_delay) */
    int order;
    int visible;    /* 0: the disc or a sphere is in front of it */
    int row;        /* 1: a point of the worldline's rows, 0: a halving's midpoint */
    int join;       /* joined by a line to the previous image of its order */
} cr_opic_image;

typedef struct cr_opic_result {
    cr_opic_image *img; /* every image found, order by order, each in tau order */
    long n, cap;
    long solves;        /* Newton solutions tried */
    long lost;          /* row points without an image, over the orders drawn */
} cr_opic_result;

/* Find the images of the n points pts (tau increasing) in the prepared
 * frame f (units of M) for the view's orders, each order in a thread of its
 * own (the same images however many run). Returns 0, or -1 with err set
 * (out of memory). Free r with cr_opic_result_free. */
int cr_opic_trace(const cr_frame *f, const cr_opic_point *pts, long n, const cr_orbit_view *v,
                  cr_opic_result *r, cr_err *err);
void cr_opic_result_free(cr_opic_result *r);

/* The colour of proper time tau on a worldline from tau0 to tau1 (a
 * perceptually ordered ramp from violet through teal to yellow). */
cr_rgb cr_opic_tau_color(double tau, double tau0, double tau1);

/* The picture: the frame's pixels px (width x height of f) with r's
 * visible, joined images drawn over them, into rgb (3 bytes a pixel, row 0
 * at the top). tau0, tau1: the span of the colour ramp. */
void cr_opic_draw(const cr_frame *f, const cr_pixel *px, const cr_opic_result *r,
                  const cr_orbit_view *v, double tau0, double tau1, uint8_t *rgb);

/* The picture's default size (pixels) and the largest side (curray orbit's
 * -x, -y; curray.orbit_picture's width, height). */
#define CR_OPIC_DEFAULT_W 320
#define CR_OPIC_DEFAULT_H 240
#define CR_OPIC_MAX_SIDE 8192

/* The whole picture of an orbit file, the one path of `curray orbit -t c`
 * and of the Python binding: cr_opic_view_open loads the view's scene,
 * cr_opic_view_row takes the worldline's rows as cr_worldline_run emits
 * them (every stride-th kept, at most CR_OPIC_MAX_POINTS), and
 * cr_opic_view_picture draws them over the scene's pixels. */
typedef struct cr_opic_view {
    const cr_particle_spec *spec;
    cr_scene sc;
    cr_frame_eval ev;      /* frame 0 of 1 of the view's scene at the picture's size */
    cr_opic_point *pts;    /* the rows kept, in units of M */
    long n, cap, seen, stride;
    double last[CR_WL_COLS]; /* the latest row not kept */
    int have_last;
    cr_err *err;           /* where cr_opic_view_row reports running out of memory */
} cr_opic_view;

/* Load the view section's scene of spec (loaded from the orbit file
 * orbit_name) as frame 0 of 1 at w x h, checked against the orbit file's
 * metric, into v, which keeps spec and err. Returns 0, or -1 with err set
 * (naming view.scene, or saying the file has no view section) and nothing
 * to free. */
int cr_opic_view_open(cr_opic_view *v, const cr_particle_spec *spec, const char *orbit_name,
                      int w, int h, cr_err *err);

/* A row of the worldline (cr_worldline_run's emit, or the tap of
 * cr_worldline_write_csv_open; ctx is the view). Returns 0, or -1 with the
 * view's err set (out of memory). */
int cr_opic_view_row(void *ctx, const double *row);

/* The picture of the rows taken: px the scene's pixels (cr_cpu_render of
 * v->ev.frame), into rgb (3 bytes a pixel, row 0 at the top) and the images
 * into r (free it with cr_opic_result_free). Returns 0, or -1 with err set
 * (no rows, out of memory). */
int cr_opic_view_picture(cr_opic_view *v, const cr_pixel *px, uint8_t *rgb, cr_opic_result *r,
                         cr_err *err);

void cr_opic_view_free(cr_opic_view *v);

/* orbit_image.csv: a header, then one row an image,
 * tau,t,order,i,j,t_obs,visible; written atomically. */
int cr_opic_write_csv(const cr_opic_result *r, const char *path, cr_err *err);

#endif
