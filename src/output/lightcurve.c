/* curray output: l_<k>.csv (lightcurve.h). */
#include "lightcurve.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../base/atomic.h"
#include "../base/fsutil.h"
#include "../base/shortest.h"
#include "../core/spectrum.h" /* cr_spec_solid_angle */

void cr_lightcurve_compute(const cr_frame *f, const cr_pixel *px, cr_lightcurve_point *p)
{
    double sum = 0.0, sx = 0.0, sy = 0.0, ax = 0.0, ay = 0.0;
    long n = 0;
    for (int j = 0; j < f->height; j++)
        for (int i = 0; i < f->width; i++) {
            const cr_pixel *q = &px[(size_t)j * (size_t)f->width + (size_t)i];
            double w, a, b;
            if (!(q->bolo > 0.0) || !isfinite(q->bolo))
                continue;
            w = q->bolo * cr_spec_solid_angle(f, i, j, 1.0);
            cr_camera_screen(f, i, j, &a, &b);
            sum += w;
            sx += w * i;
            sy += w * j;
            ax += w * a;
            ay += w * b;
            n++;
        }
    p->t_obs = f->t_obs;
    p->flux = sum;
    p->pixels = n;
    p->x = sum > 0.0 ? sx / sum : NAN;
    p->y = sum > 0.0 ? sy / sum : NAN;
    p->sx = sum > 0.0 ? ax / sum : NAN;
    p->sy = sum > 0.0 ? ay / sum : NAN;
}

static void cr_put(FILE *fp, double v)
{
    char buf[40];
    if (v != v) {
        fputs("nan", fp);
        return;
    }
    buf[cr_shortest_double(buf, v)] = '\0';
    fputs(buf, fp);
}

int cr_output_lightcurve_csv(const char *dir, int k, double m_scene,
                             const cr_lightcurve_point *p, cr_err *err)
{
    char path[4096], name[64];
    const double v[6] = {p->t_obs * m_scene, p->flux, p->x, p->y, p->sx, p->sy};
    cr_atomic at;
    FILE *fp;
    snprintf(name, sizeof name, "l_%d.csv", k);
    if (cr_path_join(path, sizeof path, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    if (cr_atomic_open(&at, path, err) != 0)
        return -1;
    fp = at.fp;
    fprintf(fp, "frame,t_obs,flux,x,y,sx,sy,pixels\n%d", k);
    for (int c = 0; c < 6; c++) {
        fputc(',', fp);
        cr_put(fp, v[c]);
    }
    fprintf(fp, ",%ld\n", p->pixels);
    if (ferror(fp)) {
        int e = errno ? errno : EIO;
        cr_atomic_abort(&at);
        return cr_err_set(err, "writing %s: %s", path, strerror(e));
    }
    return cr_atomic_commit(&at, err);
}

int cr_output_write_lightcurve(const cr_frame_output *o, cr_err *err)
{
    cr_lightcurve_point p;
    cr_lightcurve_compute(o->frame, o->px, &p);
    return cr_output_lightcurve_csv(o->dir, o->k, cr_anim_at(o->scene->m, o->k, o->n), &p, err);
}
