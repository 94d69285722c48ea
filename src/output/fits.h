/* curray io: f_<k>.fits, one FITS file per frame (-t f), written with
 * cfitsio into memory and then atomically like every output (atomic.h).
 *
 * Layout: an empty primary HDU carrying the frame's keywords (metric,
 * observer, field of view, integrator, units), then one image extension per
 * quantity, each width x height, EXTNAME and BUNIT set, with the values the
 * CSV has (cr_pixel_csv_values, output.h):
 *   REDSHIFT  float64  nu_obs / nu_em (the CSV's redshift; NaN where the CSV
 *                      has -1: no source reached)
 *   HIT_R     float64  BL radius of the disc or sphere hit, units of M (NaN
 *                      for other outcomes)
 *   HIT_PHI   float64  BL azimuth of the hit, rad in [0, 2 pi) (NaN likewise)
 *   BOLO      float64  g^4 F / F_max of a Keplerian disc hit (the CSV's
 *                      bolometric; NaN likewise)
 *   OUTCOME   uint8    the outcome code; keywords OUTCOME0..7 name the codes
 *   STEPS     uint32   integrator steps of the pixel (BZERO 2147483648)
 *   NULLERR   float64  mean error monitor along the ray (CSV err_mean)
 *   NULLSTD   float64  its standard deviation (CSV err_std)
 *   ORDER     int16    equator crossings before the hit or end (CSV order; -1:
 *                      none)
 *   THTURNS   int16    polar turning points before it (CSV theta_turns)
 *   DELAY     float64  coordinate-time delay of the hit, units of M (CSV
 *                      delay; NaN: none)
 * FITS rows count from the bottom of the image (the FITS convention, so
 * viewers show it upright): FITS row 1 is the PNG's last row; with astropy
 * data[::-1] is the image in the CSV's row order.
 *
 * cfitsio is optional at build time (CMake finds it or not); without it
 * cr_fits_available() is 0 and cr_output_fits fails with a message saying so.
 * With it the CMake build makes this file a module, curray_fits.so
 * (module.h), that the program loads only when a run writes FITS
 * (CURRAY_FITS_MODULE_HOST: the program's side; CURRAY_FITS_MODULE: the
 * module's), or links it in (static builds). */
#ifndef CR_IO_FITS_H
#define CR_IO_FITS_H

#include "../core/defs.h"
#include "../base/error.h"
#include "../input/scene.h"
#include "types.h"

/* 1 when this build writes FITS (linked with cfitsio, or curray_fits.so
 * loaded: the first call loads it); else 0 with err (may be NULL) set to the
 * message -t f gets: CR_FITS_MISSING, or why the module cannot be loaded
 * (naming it and the library missing). */
int cr_fits_available(cr_err *err);

/* The message -t f gets from a build without cfitsio. */
#define CR_FITS_MISSING                                                                         \
    "-t f: this curray was built without cfitsio, so it cannot write FITS; install it "         \
    "(Debian: libcfitsio-dev, tools/install-deps.sh) and build again"

/* The bytes a pixel of the file's image extensions (the sum over the
 * quantities above of their value's size) and the number of its HDUs (the
 * primary and one a quantity): from the table the writer writes. */
int cr_fits_pixel_bytes(void);
int cr_fits_hdus(void);

/* The memory cr_output_fits holds while it writes a w x h frame, bytes: the
 * whole file, built in memory before it is written out (cr_fits_pixel_bytes()
 * a pixel, plus a few 2880-byte header blocks for each of cr_fits_hdus()),
 * and a row. */
double cr_fits_memory(int w, int h);

/* Write dir/f_<k>.fits for frame k of n, the frame f (made from scene s)
 * traced into px (f->width x f->height, row 0 at the top): the keywords come
 * from f (units of M, integrator, tolerance, samples), the scene file's name
 * and M in the scene's unit from s. Returns 0, or -1 with err set (nothing
 * is left behind). */
int cr_output_fits(const char *dir, int k, int n, const cr_scene *s, const cr_frame *f,
                   const cr_pixel *px, cr_err *err);

/* The output-type writer of f (types.h): cr_output_fits of o. */
int cr_output_write_fits(const cr_frame_output *o, cr_err *err);

#endif
