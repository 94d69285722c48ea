/* curray io: worldlines of orbit files (worldline.h). */
#include "worldline.h"

#include <stdio.h>
#include <string.h>

#include "../base/atomic.h"
#include "../base/shortest.h"

const char *const cr_worldline_columns[CR_WL_COLS] = {
    "tau", "t", "r", "theta", "phi", "x", "y", "z", "u^t", "u^r", "u^theta", "u^phi"};

/* Integrator steps after which a run gives up (a worldline of 1,000
 * orbits takes about 10^5). */
#define CR_WL_MAX_STEPS 200000000L

static void row_of(const cr_particle_point *q, double *row)
{
    int k;
    row[0] = q->tau;
    row[1] = q->t;
    row[2] = q->r;
    row[3] = q->th;
    row[4] = q->ph;
    for (k = 0; k < 3; k++)
        row[5 + k] = q->x[k];
    for (k = 0; k < 4; k++)
        row[8 + k] = q->u[k];
}

static int put(int (*emit)(void *, const double *), void *ctx, const cr_particle_point *q,
               cr_worldline_info *info)
{
    double row[CR_WL_COLS];
    row_of(q, row);
    info->rows++;
    return emit(ctx, row);
}

int cr_worldline_run(const cr_particle_spec *s, int (*emit)(void *ctx, const double *row),
                     void *ctx, cr_worldline_info *info, cr_err *err)
{
    cr_particle p;
    cr_particle_point q;
    double last = 0.0;
    long k = 1;
    memset(info, 0, sizeof *info);
    if (!cr_particle_spec_start(s, &p))
        return cr_err_set(err, "the particle cannot start (a spec not checked by its loader)");
    info->E = p.E;
    info->L = p.L;
    info->K = p.K;
    cr_particle_current(&p, &q);
    if (put(emit, ctx, &q, info))
        return -1;
    for (;;) {
        int end = cr_particle_step(&p);
        double top = p.tau1 < s->tau ? p.tau1 : s->tau;
        if (end == CR_PARTICLE_FAILED)
            return cr_err_set(err,
                              "the integration failed at tau = %g, r = %g (a non-finite "
                              "state or a collapsed step)",
                              p.tau0, 1.0 / p.y0[CR_M_W]);
        for (; k * s->dtau <= top; k++) {
            last = k * s->dtau;
            cr_particle_at(&p, cr_particle_find_tau(&p, last), &q);
            if (put(emit, ctx, &q, info))
                return -1;
        }
        if (end != CR_PARTICLE_RUNNING || p.tau1 >= s->tau) {
            /* the end of the worldline or of the span, unless just written */
            if (top > last) {
                if (p.tau1 <= s->tau)
                    cr_particle_at(&p, 1.0, &q);
                else
                    cr_particle_at(&p, cr_particle_find_tau(&p, s->tau), &q);
                if (put(emit, ctx, &q, info))
                    return -1;
            }
            info->ended = p.tau1 <= s->tau ? end : CR_PARTICLE_RUNNING;
            break;
        }
        if (p.steps >= CR_WL_MAX_STEPS)
            return cr_err_set(err, "the integration took more than %ld steps by tau = %g",
                              CR_WL_MAX_STEPS, p.tau1);
    }
    info->steps = p.steps;
    return 0;
}

/* The CSV sink: one line per row, then the tap. */
typedef struct csv_sink {
    FILE *fp;
    int (*tap)(void *, const double *);
    void *ctx;
    int tapped; /* the tap stopped the run */
} csv_sink;

static int csv_row(void *ctx, const double *row)
{
    csv_sink *c = (csv_sink *)ctx;
    char line[CR_WL_COLS * 32], *e = line;
    int i;
    for (i = 0; i < CR_WL_COLS; i++) {
        if (i)
            *e++ = ',';
        e += cr_shortest_double(e, row[i]);
    }
    *e++ = '\n';
    if (fwrite(line, 1, (size_t)(e - line), c->fp) != (size_t)(e - line))
        return -1;
    if (c->tap && c->tap(c->ctx, row)) {
        c->tapped = 1;
        return -1;
    }
    return 0;
}

int cr_worldline_write_csv_open(const cr_particle_spec *s, const char *path,
                                int (*tap)(void *ctx, const double *row), void *ctx,
                                cr_atomic *a, cr_worldline_info *info, cr_err *err)
{
    csv_sink c;
    int i;
    if (cr_atomic_open(a, path, err))
        return -1;
    c.fp = a->fp;
    c.tap = tap;
    c.ctx = ctx;
    c.tapped = 0;
    for (i = 0; i < CR_WL_COLS; i++)
        fprintf(a->fp, "%s%s", i ? "," : "", cr_worldline_columns[i]);
    fputc('\n', a->fp);
    if (cr_worldline_run(s, csv_row, &c, info, err)) {
        if (!c.tapped && ferror(a->fp))
            cr_stream_check(a->fp, path, err);
        cr_atomic_abort(a);
        return -1;
    }
    return 0;
}

int cr_worldline_write_csv(const cr_particle_spec *s, const char *path, cr_worldline_info *info,
                           cr_err *err)
{
    cr_atomic a;
    if (cr_worldline_write_csv_open(s, path, NULL, NULL, &a, info, err))
        return -1;
    return cr_atomic_commit(&a, err);
}
