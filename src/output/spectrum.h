/* curray output: s_<k>.csv, the observed spectrum of the frame's Keplerian
 * disc summed over the image (-t s): the line profile of the scene's
 * spectrum.line and the blackbody continuum of spectrum.continuum (scene.h
 * cr_spectrum_spec; the physics per ray in core/spectrum.h).
 *
 * Every ray that met the disc at r >= r_in (the effective inner edge;
 * plunging matter does not emit) adds its share, weighted by the solid angle
 * it stands for (cr_spec_solid_angle; the image-plane area in M^2 for the
 * observer at infinity). With raytracer.samples = n > 1 the n x n sub-rays
 * of every pixel count, each for 1/n^2 of the pixel: they are traced again
 * on the CPU for the spectrum (the pixels keep only the centre sub-ray's
 * values). */
#ifndef CR_OUTPUT_SPECTRUM_H
#define CR_OUTPUT_SPECTRUM_H

#include "../core/defs.h"
#include "../base/error.h"
#include "../input/scene.h"
#include "types.h"

typedef struct cr_spectrum {
    double e0;                   /* the line's rest energy, keV */
    int n_line, n_cont;          /* bins */
    double *line_edges;          /* n_line + 1, keV, linear */
    double *line_sum;            /* n_line: sum of g^3 r^-q dOmega (photon flux) of the
                                    rays in the bin */
    double *cont_edges;          /* n_cont + 1, keV, logarithmic */
    double *cont_sum;            /* n_cont: energy flux in the bin, W m^-2 (x (D/M)^2 at
                                    infinity) */
    long rays;                   /* rays that met the emitting disc */
    long inner_rays;             /* of those, between r_in and 2 r_in */
} cr_spectrum;

/* The spectrum of frame f traced into px (f->width x f->height, as the
 * backends trace it) with the settings sp. Returns 0, or -1 with err set
 * (no Keplerian disc, out of memory); free with cr_spectrum_free. */
int cr_spectrum_compute(const cr_frame *f, const cr_pixel *px, const cr_spectrum_spec *sp,
                        cr_spectrum *out, cr_err *err);
void cr_spectrum_free(cr_spectrum *s);

/* The continuum range of sp for frame f: sp's, or by default 0.01 to 30 x
 * f_col k T_peak (keV). */
void cr_spectrum_cont_range(const cr_frame *f, const cr_spectrum_spec *sp, double *lo,
                            double *hi);

/* Whether a scene can have -t s: 0, or -1 with the message (no Keplerian disc). */
int cr_spectrum_check(const cr_scene *s, cr_err *err);

/* A warning for the console when too few rays cover the inner disc for a
 * converged line profile (fewer rays between r_in and 2 r_in than 10 per
 * line bin): returns 1 with the text in msg, else 0. */
int cr_spectrum_coverage_note(const cr_spectrum *s, char *msg, size_t n);

/* s_<k>.csv: the writer of output type s (types.h). Columns
 * spectrum,bin,e_lo_kev,e_hi_kev,e_kev,g,flux,normalised: the line rows
 * ("line": e_kev the bin's middle, g = e_kev / energy_kev, flux the photon
 * flux, the sum of g^3 r^-q dOmega per keV, normalised so that its integral
 * over g is 1, as kerrz lineprof normalises) then the continuum rows ("continuum": e_kev the
 * bin's geometric middle, g -1, flux the energy flux per keV in W m^-2
 * keV^-1, normalised so that its integral over E in keV is 1). */
int cr_output_write_spectrum(const cr_frame_output *o, cr_err *err);
/* The values of bin i of the line (line = 1) or the continuum (line = 0)
 * as s_<k>.csv writes them after its spectrum and bin columns: e_lo_kev,
 * e_hi_kev, e_kev, g (-1 for the continuum), flux, normalised; total is
 * cr_spectrum_part_total of the same part. The CSV and curray.spectrum
 * (Python) both take their values from here. */
#define CR_SPEC_COLS 6
double cr_spectrum_part_total(const cr_spectrum *s, int line);
void cr_spectrum_row(const cr_spectrum *s, int line, int i, double total,
                     double v[CR_SPEC_COLS]);

int cr_output_spectrum_csv(const char *dir, int k, const cr_spectrum *s, cr_err *err);

#endif
