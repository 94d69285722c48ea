/* curray io: the files of one frame (6.9, 6.11): c_<k>.png, r_<k>.png and
 * d_<k>.csv, each written atomically (atomic.h). info.txt, the run's
 * summary, and the frame statistics are in info.h, included here so that a
 * caller writing a frame finds both. */
#ifndef CR_IO_OUTPUT_H
#define CR_IO_OUTPUT_H

#include <stdio.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "info.h"
#include "types.h"

/* Redshift colour of one pixel (6.9.1): R = 255 - 255 atan(z) 2/pi, G = 0,
 * B = 255 atan(z) 2/pi for z = omega_r/omega_s >= 0 (horizon z = 0: red);
 * green where the source lies inside the ergosphere (z = -1 on a disc or
 * sphere hit); black for the sky and for pixels without a source (error,
 * limit, outside). */
cr_rgb cr_redshift_color(const cr_pixel *p);
/* The same, but a sky pixel is coloured by (6.9.1) with its own ratio z (the
 * shift of light from a static emitter at infinity, E = 1, as seen by the
 * observer: 1/sqrt(-g_tt) for the static observer, Doppler-shifted for a
 * moving one), black only where that is undefined (scene key redshift_sky). */
cr_rgb cr_redshift_sky_color(const cr_pixel *p);

/* Bolometric map colour of one pixel: grey level 255 (log10(v) + 3) / 4,
 * clamped to 0..255, of v = g^4 F / F_max (cr_pixel.bolo) on a Keplerian
 * disc hit: v = 10 is white, 1e-3 and below (and plunging matter, v = 0)
 * black; black for every other pixel. */
cr_rgb cr_bolometric_color(const cr_pixel *p);

/* Image-order map colour of one pixel (n_<k>.png): a disc or sphere hit in
 * the colour of its order (cr_pixel.order): 0 orange (255, 176, 64), 1 blue
 * (64, 160, 255), 2 green (96, 255, 96), 3 magenta (255, 64, 255), 4 and
 * above white; black for every other pixel. */
cr_rgb cr_order_color(const cr_pixel *p);

/* The CSV's floating-point values of one pixel, -1 where the CSV writes
 * "undefined": redshift where no source was reached (outcome none, error,
 * limit or outside, or a NaN ratio); hit_r, hit_phi unless the ray hit the disc or a
 * sphere; bolometric unless it hit a Keplerian disc or a moving sphere
 * (cr_pixel.bolo >= 0);
 * delay (cr_pixel.delay) on a disc or sphere hit, NaN otherwise (a delay may
 * be -1: the CSV writes nan).
 * The one definition of these columns for the CSV, the FITS file (fits.h)
 * and the Python arrays. */
typedef struct cr_pixel_values {
    double redshift, hit_r, hit_phi, bolometric, delay;
    int order, theta_turns; /* cr_pixel's: -1 where no ray was traced to an
                               end (outcome none, outside, error) */
} cr_pixel_values;
/* (inline: the CSV writer calls it for every pixel, and the FITS module
 * (module.h) has it without the rest of the writers) */
static inline cr_pixel_values cr_pixel_csv_values(const cr_pixel *q)
{
    cr_pixel_values v;
    /* The ratio is meaningless where no source was reached. */
    int undefined = q->outcome == CR_OUT_NONE || q->outcome == CR_OUT_ERROR ||
                    q->outcome == CR_OUT_LIMIT || q->outcome == CR_OUT_OUTSIDE ||
                    q->redshift != q->redshift;
    /* where the ray hit the disc or a sphere */
    int hit = q->outcome == CR_OUT_DISC || q->outcome == CR_OUT_SPHERE;
    v.redshift = undefined ? -1.0 : q->redshift;
    v.hit_r = hit ? q->hit_r : -1.0;
    v.hit_phi = hit ? q->hit_phi : -1.0;
    /* g^4 F / F_max on a Keplerian disc hit, g^4 on a moving sphere's */
    v.bolometric = hit && q->bolo >= 0.0 ? q->bolo : -1.0;
    v.order = q->order;
    v.theta_turns = q->theta_turns;
    v.delay = hit ? q->delay : NAN;
    return v;
}

/* c_<k>.png, r_<k>.png, d_<k>.csv in dir. */
int cr_output_color_png(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err);
/* r_<k>.png: sky == 0 colours pixels by cr_redshift_color (the paper's
 * black sky), sky != 0 by cr_redshift_sky_color. */
int cr_output_redshift_png(const char *dir, int k, const cr_pixel *px, int w, int h, int sky,
                           cr_err *err);
/* b_<k>.png: the bolometric map (cr_bolometric_color). */
int cr_output_bolometric_png(const char *dir, int k, const cr_pixel *px, int w, int h,
                             cr_err *err);
/* CSV columns (6.11), one row per pixel, header line first:
 * x,y,r,g,b,steps,redshift,err_mean,err_std,outcome,hit_r,hit_phi,bolometric,
 * order,theta_turns,delay
 * (x, y pixel coordinates from the top-left; redshift -1 where undefined;
 * outcome as the word horizon/disc/sphere/sky/error/limit/outside; hit_r, hit_phi
 * the disc or sphere hit point, -1 otherwise; bolometric g^4 F / F_max on a
 * Keplerian disc hit, -1 otherwise; order and theta_turns the image order
 * and polar turning points (cr_pixel), -1 where no ray was traced to an end;
 * delay the coordinate-time delay t_obs - t of a disc or sphere hit, nan
 * otherwise). Every number is the shortest text that
 * reads back as the same double (cr_shortest_double, base/shortest.h). */
int cr_output_csv(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err);
/* The same CSV text written to an open stream, then flushed and checked
 * (cr_stream_check); name is used in the error message. */
int cr_output_csv_stream(FILE *fp, const char *name, const cr_pixel *px, int w, int h,
                         cr_err *err);

/* The output-type writers (types.h) of c, r, d and b: the functions above
 * for o's frame (r: sky coloured by its shift when o->scene->redshift_sky). */
int cr_output_write_color(const cr_frame_output *o, cr_err *err);
int cr_output_write_redshift(const cr_frame_output *o, cr_err *err);
int cr_output_write_csv(const cr_frame_output *o, cr_err *err);
int cr_output_write_bolometric(const cr_frame_output *o, cr_err *err);
/* n_<k>.png: the image-order map (cr_order_color). */
int cr_output_write_order(const cr_frame_output *o, cr_err *err);

#endif
