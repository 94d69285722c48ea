/* curray io: the path of one pixel's ray (raypath.h). */
#include "raypath.h"

#include <stdio.h>
#include <stdlib.h>

#include "../base/atomic.h"
#include "../base/fsutil.h"

const char cr_raypath_csv_header[] = "param,t,r,theta,phi,x,y,z,ut,ur,utheta,uphi";

/* Whether the image takes pixel (i, j)'s ray as sky without tracing it: with
 * a plain-colour sky, a ray that never comes inside the scene radius 1/w_sky
 * (cr_ray_misses_scene), or that starts beyond it moving outward, ends at
 * once, with no step and at most the observer's point (none from the
 * observer at infinity). px: what the loop reported; n: the points recorded. */
static int cr_raypath_untraced(const cr_frame *f, const cr_pixel *px, long n)
{
    return n <= 1 && px->outcome == CR_OUT_SKY && px->steps == 0 && !f->sky.rgb &&
           f->w_sky > 0.0;
}

static int cr_raypath_record(const cr_frame *f, int i, int j, cr_raypath *out, cr_err *err)
{
    cr_path path;
    long cap = 4096;
    for (;;) {
        double *buf = realloc(out->pts, (size_t)cap * CR_PN * sizeof *buf);
        if (!buf) {
            cr_raypath_free(out);
            return cr_err_set(err, "out of memory for a ray path of %ld points", cap);
        }
        out->pts = buf;
        path.pts = buf;
        path.cap = cap;
        path.sub = cr_ray_path_sub(f);
        out->px = cr_trace_pixel_path(f, i, j, &path);
        if (path.n <= cap)
            break;
        cap = path.n; /* the same ray again (deterministic) with room for all */
    }
    out->n = path.n;
    return 0;
}

int cr_raypath_trace(const cr_frame *f, int i, int j, cr_raypath *out, cr_err *err)
{
    out->pts = NULL;
    out->n = 0;
    out->untraced = 0;
    if (i < 0 || j < 0 || i >= f->width || j >= f->height)
        return cr_err_set(err, "pixel (%d, %d) is outside the %dx%d frame (0 <= i < %d, "
                               "0 <= j < %d)",
                          i, j, f->width, f->height, f->width, f->height);
    if (cr_raypath_record(f, i, j, out, err))
        return -1;
    if (cr_raypath_untraced(f, &out->px, out->n)) {
        /* the same ray traced for its path alone, as with the sky at
         * infinity (w_sky = 0): in from its first finite point, past its
         * turning point, out to its last finite point; it meets nothing
         * (every object lies inside the scene radius it never reaches).
         * The pixel stays the image's. */
        cr_frame g = *f;
        cr_pixel px = out->px;
        g.w_sky = 0.0;
        cr_raypath_free(out);
        if (cr_raypath_record(&g, i, j, out, err))
            return -1;
        out->path_steps = out->px.steps;
        out->px = px;
        out->untraced = 1;
    }
    return 0;
}

void cr_raypath_free(cr_raypath *rp)
{
    free(rp->pts);
    rp->pts = NULL;
    rp->n = 0;
}

int cr_raypath_write_csv(const char *dir, const char *name, const cr_raypath *rp, cr_err *err)
{
    char path[4096];
    cr_atomic a;
    long k;
    int c;
    if (cr_path_join(path, sizeof path, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    if (cr_atomic_open(&a, path, err) != 0)
        return -1;
    fprintf(a.fp, "%s\n", cr_raypath_csv_header);
    for (k = 0; k < rp->n; k++)
        for (c = 0; c < CR_PN; c++)
            fprintf(a.fp, "%.17g%c", rp->pts[k * CR_PN + c], c + 1 < CR_PN ? ',' : '\n');
    return cr_atomic_commit(&a, err);
}
