/* curray output: l_<k>.csv, one frame's point of a light curve and of the
 * centroid track (-t l): the total flux of the frame's emitting pixels and
 * its image-plane centroid. A run of frames at observer.t + k observer.dt
 * (a moving sphere) gives the light curve and the track, one row a frame.
 *
 * The emitting pixels are those with a bolometric value (cr_pixel.bolo > 0:
 * a moving sphere's g^4, a Keplerian disc's g^4 F / F_max). Each counts
 * with the solid angle it stands for (cr_spec_solid_angle; for the observer
 * at infinity the image-plane area in M^2):
 *   flux   = sum bolo dOmega,
 *   x, y   = sum i bolo dOmega / flux, the same for j: pixel indices (column
 *            from the left, row from the top, 0 the first pixel's centre),
 *   sx, sy = the same mean of the screen coordinates (cr_camera_screen): the
 *            impact coordinates (alpha, beta) in M of the observer at
 *            infinity, the screen at unit distance of a finite observer
 *            (tangents of the angles off the camera's axis, rectilinear);
 * the centroid columns are nan when the flux is 0. With raytracer.samples
 * n > 1 each pixel counts with its centre sub-ray's value (cr_pixel). */
#ifndef CR_OUTPUT_LIGHTCURVE_H
#define CR_OUTPUT_LIGHTCURVE_H

#include "../core/defs.h"
#include "../base/error.h"
#include "types.h"

typedef struct cr_lightcurve_point {
    double t_obs;       /* the frame's observer time, units of M */
    double flux;
    double x, y;        /* centroid, pixel indices */
    double sx, sy;      /* centroid, screen coordinates */
    long pixels;        /* emitting pixels */
} cr_lightcurve_point;

/* The point of frame f traced into px (f->width x f->height pixels). */
void cr_lightcurve_compute(const cr_frame *f, const cr_pixel *px, cr_lightcurve_point *p);

/* l_<k>.csv in dir: the header "frame,t_obs,flux,x,y,sx,sy,pixels" and one
 * row; t_obs in the scene's length unit (m_scene: M in it). Atomic. */
int cr_output_lightcurve_csv(const char *dir, int k, double m_scene,
                             const cr_lightcurve_point *p, cr_err *err);

/* The per-frame writer of -t l (types.h). */
int cr_output_write_lightcurve(const cr_frame_output *o, cr_err *err);

#endif
