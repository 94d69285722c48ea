/* curray io: the path of one pixel's ray (--trace i,j, curray.trace).
 *
 * The path comes from the image's own trace loop (trace.h, cr_path): the
 * core records into a buffer owned here, which grows and the ray is traced
 * again when it was too short (tracing is deterministic). */
#ifndef CR_IO_RAYPATH_H
#define CR_IO_RAYPATH_H

#include <stddef.h>

#include "../core/trace.h"
#include "../base/error.h"

/* Points per integrator step: cr_ray_path_sub (ray.h). */

typedef struct cr_raypath {
    double *pts; /* n points of CR_PN columns (trace.h CR_P_*), malloc'ed */
    long n;
    cr_pixel px; /* what the traced ray reports (outcome, hit_r, hit_phi, ...) */
    int untraced;   /* the image takes this ray as sky untraced (below) */
    unsigned path_steps; /* then: the steps of the ray traced for its path */
} cr_raypath;

/* Trace the ray of pixel (i, j) of the prepared frame f (0 <= i < width,
 * 0 <= j < height, checked) with its path. Returns 0, or -1 with err set
 * (pixel outside the frame, out of memory); out->pts is then NULL.
 * From the observer at infinity with a plain-colour sky, the image takes a
 * ray that never comes inside the scene radius as sky without a step
 * (cr_ray_misses_scene): such a ray (untraced = 1) is traced again for its
 * path alone, to infinity as for a sky image without a boundary, so that
 * its path holds the incoming leg from its first finite point, the turning
 * point and the outgoing leg to its last finite point (path_steps steps);
 * px stays the image's (outcome sky, steps 0). */
int cr_raypath_trace(const cr_frame *f, int i, int j, cr_raypath *out, cr_err *err);

void cr_raypath_free(cr_raypath *rp);

/* The CSV header line (no newline): param,t,r,theta,phi,x,y,z,ut,ur,utheta,uphi */
extern const char cr_raypath_csv_header[];

/* Write the path as CSV to dir/name atomically: the header line, then one
 * row per point with every value in %.17g (exact round trip). */
int cr_raypath_write_csv(const char *dir, const char *name, const cr_raypath *rp, cr_err *err);

#endif
