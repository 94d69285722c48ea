/* curray output: s_<k>.csv (spectrum.h). */
#include "spectrum.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/atomic.h"
#include "../base/fsutil.h"
#include "../base/shortest.h"
#include "../core/disc.h"
#include "../core/spectrum.h"
#include "../core/trace.h"

void cr_spectrum_free(cr_spectrum *s)
{
    free(s->line_edges);
    free(s->line_sum);
    free(s->cont_edges);
    free(s->cont_sum);
    memset(s, 0, sizeof *s);
}

int cr_spectrum_check(const cr_scene *s, cr_err *err)
{
    if (!s->has_disc || s->disc_model != CR_DISC_KEPLERIAN)
        return cr_err_set(err,
                          "-t s: the spectrum is that of a Keplerian disc, and the scene has %s "
                          "(accretion: {model: keplerian, ...})",
                          s->has_disc ? "a chessboard disc" : "no disc");
    return 0;
}

void cr_spectrum_cont_range(const cr_frame *f, const cr_spectrum_spec *sp, double *lo,
                            double *hi)
{
    double kt = CR_BOLTZMANN_K * f->disc.t_peak / CR_KEV_J * sp->f_col;
    if (sp->cont_lo > 0.0 && sp->cont_hi > sp->cont_lo) {
        *lo = sp->cont_lo;
        *hi = sp->cont_hi;
    } else {
        *lo = 0.01 * kt;
        *hi = 30.0 * kt;
    }
}

/* One ray that met the disc at r with ratio g, for solid angle dom. */
static void cr_spectrum_add(cr_spectrum *s, const cr_frame *f, const cr_spectrum_spec *sp,
                            double g, double r, double dom, double *tail)
{
    const cr_disc *d = &f->disc;
    double F, T, e;
    int k;
    if (!(g > 0.0) || !(r >= d->r_in) || !(r <= d->r_out))
        return;
    s->rays++;
    s->inner_rays += r < 2.0 * d->r_in;
    e = g * s->e0;
    k = (int)floor((e - s->line_edges[0]) / (s->line_edges[s->n_line] - s->line_edges[0]) *
                   s->n_line);
    if (k >= 0 && k < s->n_line)
        s->line_sum[k] += cr_spec_line_weight(g, r, sp->line_q) * dom;
    F = cr_flux_table_F(&d->flux, r);
    T = F > 0.0 ? d->t_scale * sqrt(sqrt(F)) : 0.0;
    if (!(T > 0.0))
        return;
    /* the Planck tail at every bin edge once; above x = 700 it is 0 */
    for (k = 0; k <= s->n_cont; k++) {
        double x = s->cont_edges[k] * CR_KEV_J / (g * sp->f_col * CR_BOLTZMANN_K * T);
        tail[k] = x < 700.0 ? cr_spec_planck_tail(x) : 0.0;
        if (tail[k] == 0.0) {
            for (; k <= s->n_cont; k++)
                tail[k] = 0.0;
            break;
        }
    }
    {
        double kt = CR_BOLTZMANN_K * T, g2 = g * g;
        double scale = g2 * g2 * 2.0 * kt * kt * kt * kt /
                       (CR_PLANCK_H * CR_PLANCK_H * CR_PLANCK_H * CR_LIGHT_C * CR_LIGHT_C) * dom;
        for (k = 0; k < s->n_cont && tail[k] > 0.0; k++)
            s->cont_sum[k] += scale * (tail[k] - tail[k + 1]);
    }
}

int cr_spectrum_compute(const cr_frame *f, const cr_pixel *px, const cr_spectrum_spec *sp,
                        cr_spectrum *s, cr_err *err)
{
    int n = f->samples, i, j, a, b;
    double lo, hi, *tail;
    memset(s, 0, sizeof *s);
    if (!f->disc.enabled || f->disc.model != CR_DISC_KEPLERIAN)
        return cr_err_set(err, "-t s: the frame has no Keplerian disc");
    s->e0 = sp->line_e0;
    s->n_line = sp->line_bins;
    s->n_cont = sp->cont_bins;
    s->line_edges = malloc(sizeof(double) * (size_t)(s->n_line + 1));
    s->line_sum = calloc((size_t)s->n_line, sizeof(double));
    s->cont_edges = malloc(sizeof(double) * (size_t)(s->n_cont + 1));
    s->cont_sum = calloc((size_t)s->n_cont, sizeof(double));
    tail = malloc(sizeof(double) * (size_t)(s->n_cont + 1));
    if (!s->line_edges || !s->line_sum || !s->cont_edges || !s->cont_sum || !tail) {
        free(tail);
        cr_spectrum_free(s);
        return cr_err_set(err, "-t s: out of memory");
    }
    for (i = 0; i <= s->n_line; i++)
        s->line_edges[i] = sp->line_lo + (sp->line_hi - sp->line_lo) * i / s->n_line;
    cr_spectrum_cont_range(f, sp, &lo, &hi);
    for (i = 0; i <= s->n_cont; i++)
        s->cont_edges[i] = lo * pow(hi / lo, (double)i / s->n_cont);
    if (n < 2 || n > CR_MAX_SAMPLES)
        n = 1;
    for (j = 0; j < f->height; j++)
        for (i = 0; i < f->width; i++) {
            const cr_pixel *p = &px[(size_t)j * f->width + i];
            if (n == 1) {
                if (p->outcome == CR_OUT_DISC)
                    cr_spectrum_add(s, f, sp, p->redshift, p->hit_r,
                                    cr_spec_solid_angle(f, i, j, 1.0), tail);
                continue;
            }
            for (b = 0; b < n; b++)
                for (a = 0; a < n; a++) {
                    double x = i + cr_subpixel_offset(a, n), y = j + cr_subpixel_offset(b, n);
                    cr_pixel q = cr_trace_point(f, x, y);
                    if (q.outcome == CR_OUT_DISC)
                        cr_spectrum_add(s, f, sp, q.redshift, q.hit_r,
                                        cr_spec_solid_angle(f, x, y, 1.0 / n), tail);
                }
        }
    free(tail);
    return 0;
}

int cr_spectrum_coverage_note(const cr_spectrum *s, char *msg, size_t n)
{
    if (s->inner_rays >= 10L * s->n_line)
        return 0;
    snprintf(msg, n,
             "-t s: only %ld rays meet the inner disc (r_in to 2 r_in), fewer than 10 per line "
             "bin (%d bins): the line profile is not converged; raise -x/-y or "
             "raytracer.samples, or use fewer bins (docs/outputs.md)",
             s->inner_rays, s->n_line);
    return 1;
}

static void cr_put(FILE *fp, double v)
{
    char buf[40];
    buf[cr_shortest_double(buf, v)] = '\0';
    fputs(buf, fp);
}

double cr_spectrum_part_total(const cr_spectrum *s, int line)
{
    const double *sum = line ? s->line_sum : s->cont_sum;
    int n = line ? s->n_line : s->n_cont;
    double t = 0.0;
    for (int k = 0; k < n; k++)
        t += sum[k];
    return t;
}

void cr_spectrum_row(const cr_spectrum *s, int line, int i, double total,
                     double v[CR_SPEC_COLS])
{
    const double *edges = line ? s->line_edges : s->cont_edges;
    double sum = line ? s->line_sum[i] : s->cont_sum[i];
    double lo = edges[i], hi = edges[i + 1], w = hi - lo;
    v[0] = lo;
    v[1] = hi;
    if (line) {
        v[2] = 0.5 * (lo + hi);
        v[3] = v[2] / s->e0;
        v[4] = sum / w;
        /* per unit g = E / E0: the bin's share over its width in g */
        v[5] = total > 0.0 ? sum / (total * w / s->e0) : 0.0;
    } else {
        v[2] = sqrt(lo * hi);
        v[3] = -1.0;
        v[4] = sum / w;
        v[5] = total > 0.0 ? sum / (total * w) : 0.0;
    }
}

int cr_output_spectrum_csv(const char *dir, int k, const cr_spectrum *s, cr_err *err)
{
    char path[4096], name[64];
    cr_atomic at;
    FILE *fp;
    snprintf(name, sizeof name, "s_%d.csv", k);
    if (cr_path_join(path, sizeof path, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    if (cr_atomic_open(&at, path, err) != 0)
        return -1;
    fp = at.fp;
    fputs("spectrum,bin,e_lo_kev,e_hi_kev,e_kev,g,flux,normalised\n", fp);
    for (int line = 1; line >= 0; line--) {
        double total = cr_spectrum_part_total(s, line), v[CR_SPEC_COLS];
        int n = line ? s->n_line : s->n_cont;
        for (int i = 0; i < n; i++) {
            cr_spectrum_row(s, line, i, total, v);
            fprintf(fp, "%s,%d", line ? "line" : "continuum", i);
            for (int c = 0; c < CR_SPEC_COLS; c++) {
                fputc(',', fp);
                if (!line && c == 3)
                    fputs("-1", fp);
                else
                    cr_put(fp, v[c]);
            }
            fputc('\n', fp);
        }
    }
    if (ferror(fp)) {
        int e = errno ? errno : EIO;
        cr_atomic_abort(&at);
        return cr_err_set(err, "writing %s: %s", path, strerror(e));
    }
    return cr_atomic_commit(&at, err);
}

int cr_output_write_spectrum(const cr_frame_output *o, cr_err *err)
{
    cr_spectrum s;
    int rc;
    if (cr_spectrum_compute(o->frame, o->px, &o->scene->spectrum, &s, err))
        return -1;
    rc = cr_output_spectrum_csv(o->dir, o->k, &s, err);
    if (rc == 0 && o->note && o->note_n > 0 && !cr_spectrum_coverage_note(&s, o->note, o->note_n))
        o->note[0] = '\0';
    cr_spectrum_free(&s);
    return rc;
}
