/* curray output: the lensed picture of a worldline (orbit_picture.h). */
#include "orbit_picture.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/atomic.h"
#include "../base/shortest.h"
#include "../core/lensing.h"

void cr_opic_point_of_row(const double *row, const cr_metric *mt, cr_opic_point *p)
{
    /* columns of cr_worldline_columns: tau, t, r, theta, phi, x, y, z, u^t, u^r,
       u^theta, u^phi */
    double k = 1.0 / mt->m;
    int i;
    p->tau = row[0] * k;
    p->t = row[1] * k;
    for (i = 0; i < 3; i++)
        p->x[i] = row[5 + i] * k;
    p->ut = row[8];
    /* dx/dtau is dimensionless: the same in units of M */
    cr_bl_vel_to_cart(mt->a, row[2], row[3], row[4], row[9], row[10], row[11], p->v);
}

void cr_opic_result_free(cr_opic_result *r)
{
    free(r->img);
    memset(r, 0, sizeof *r);
}

/* The work of one order. */
typedef struct opic_ctx {
    const cr_frame *fg; /* the probes' frame without objects (Newton) */
    const cr_frame *fo; /* with the scene's objects (what hides an image) */
    int order;
    double max_step;  /* pixels */
    double seed_step; /* grid spacing of a seed search, pixels */
    cr_opic_result *r;
    long first;       /* index in r->img of this order's first image */
    int broken;       /* the curve broke since the last image pushed */
    cr_err *err;
} opic_ctx;

static int push(opic_ctx *c, const cr_opic_image *im)
{
    cr_opic_result *r = c->r;
    cr_opic_image *q;
    if (r->n == r->cap) {
        long cap = r->cap ? 2 * r->cap : 1024;
        cr_opic_image *g = realloc(r->img, (size_t)cap * sizeof *g);
        if (!g)
            return cr_err_set(c->err, "out of memory for the images of the orbit (%ld)", cap);
        r->img = g;
        r->cap = cap;
    }
    q = &r->img[r->n];
    *q = *im;
    q->join = 0;
    if (r->n > c->first && !c->broken) {
        const cr_opic_image *p = &r->img[r->n - 1];
        q->join = hypot(q->i - p->i, q->j - p->j) <= CR_OPIC_JOIN;
    }
    c->broken = 0;
    r->n++;
    return 0;
}

/* The miss tolerance at point x (M): 1e-5 of its distance, at least 1e-5
 * (a few thousandths of a pixel at the scales of a picture, above the
 * rays' integration error at tolerance 1e-9). */
static double miss_tol(const double x[3])
{
    return 1e-5 * (1.0 + sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
}

/* Newton from (i, j); on success the image into *im. */
static int solve_from(opic_ctx *c, const cr_opic_point *p, double i, double j, cr_opic_image *im)
{
    cr_lens_hit h, ho;
    cr_lens_target t;
    double tol = miss_tol(p->x);
    c->r->solves++;
    cr_lens_target_make(c->fg, p->x, c->order, &t);
    if (!cr_lens_solve(c->fg, &t, tol, c->max_step, &i, &j, &h))
        return 0;
    im->tau = p->tau;
    im->t = p->t;
    im->i = i;
    im->j = j;
    im->t_obs = p->t + h.delay;
    im->order = c->order;
    im->row = 1;
    im->join = 0;
    /* the same ray with the scene's objects: does one end it before P? */
    cr_lens_probe(c->fo, i, j, &t, &ho);
    im->visible = ho.found && ho.d <= 100.0 * tol;
    return 1;
}

/* The best few starts of a search (smallest miss first). */
#define OPIC_SEEDS 4
typedef struct opic_seeds {
    double d[OPIC_SEEDS], i[OPIC_SEEDS], j[OPIC_SEEDS];
} opic_seeds;

static void seeds_init(opic_seeds *s)
{
    int k;
    for (k = 0; k < OPIC_SEEDS; k++)
        s->d[k] = INFINITY;
}

static void seeds_try(opic_ctx *c, const cr_lens_target *t, double i, double j, opic_seeds *s)
{
    cr_lens_hit h;
    int k;
    cr_lens_probe(c->fg, i, j, t, &h);
    if (!h.found || !(h.d < s->d[OPIC_SEEDS - 1]))
        return;
    for (k = OPIC_SEEDS - 1; k > 0 && h.d < s->d[k - 1]; k--) {
        s->d[k] = s->d[k - 1];
        s->i[k] = s->i[k - 1];
        s->j[k] = s->j[k - 1];
    }
    s->d[k] = h.d;
    s->i[k] = i;
    s->j[k] = j;
}

static int seeds_solve(opic_ctx *c, const cr_opic_point *p, const opic_seeds *s,
                       cr_opic_image *im)
{
    int k;
    for (k = 0; k < OPIC_SEEDS && s->d[k] < INFINITY; k++)
        if (solve_from(c, p, s->i[k], s->j[k], im))
            return 1;
    return 0;
}

/* A search for P's image without a nearby start: first along the line
 * from the hole's centre through P's flat-space pixel (cr_lens_flat_pixel;
 * beyond the centre for odd orders), every half pixel out to the image's
 * diagonal, then the rays of a grid over the image and a quarter of its
 * size around it; Newton from the best few rays of each. */
static int seed(opic_ctx *c, const cr_opic_point *p, cr_opic_image *im)
{
    const cr_frame *f = c->fg;
    double mx = 0.25 * f->width, my = 0.25 * f->height, s = c->seed_step, i, j, pi, pj, ci, cj;
    opic_seeds best;
    cr_lens_target tg;
    cr_lens_target_make(f, p->x, c->order, &tg);
    seeds_init(&best);
    if (cr_lens_flat_pixel(f, p->x, &pi, &pj, &ci, &cj)) {
        /* the line, then lines turned by up to 45 degrees either way (the
           images of a spinning hole lie off it) */
        static const double turn[] = {0.0, 10.0, -10.0, 20.0, -20.0, 30.0, -30.0, 45.0, -45.0};
        double u0 = pi - ci, v0 = pj - cj, len = hypot(u0, v0), t;
        double L = 0.6 * hypot(f->width, f->height);
        unsigned q;
        if (len > 0.0) {
            u0 /= len;
            v0 /= len;
            if (c->order % 2) {
                u0 = -u0;
                v0 = -v0;
            }
            for (q = 0; q < sizeof turn / sizeof turn[0]; q++) {
                double a = turn[q] * CR_PI / 180.0;
                double ui = u0 * cos(a) - v0 * sin(a), uj = u0 * sin(a) + v0 * cos(a);
                seeds_init(&best);
                for (t = 0.0; t <= L; t += 0.5)
                    seeds_try(c, &tg, ci + t * ui, cj + t * uj, &best);
                if (seeds_solve(c, p, &best, im))
                    return 1;
            }
        }
    }
    seeds_init(&best);
    for (j = -my; j <= f->height - 1 + my; j += s)
        for (i = -mx; i <= f->width - 1 + mx; i += s)
            seeds_try(c, &tg, i, j, &best);
    return seeds_solve(c, p, &best, im);
}

/* The point at the middle of [a, b] in proper time by cubic Hermite
 * interpolation of positions and times with their tau-derivatives. */
static void midpoint(const cr_opic_point *a, const cr_opic_point *b, cr_opic_point *m)
{
    double h = b->tau - a->tau;
    int k;
    m->tau = 0.5 * (a->tau + b->tau);
    m->t = 0.5 * (a->t + b->t) + 0.125 * h * (a->ut - b->ut);
    m->ut = 0.5 * (a->ut + b->ut); /* only for further halvings */
    for (k = 0; k < 3; k++) {
        m->x[k] = 0.5 * (a->x[k] + b->x[k]) + 0.125 * h * (a->v[k] - b->v[k]);
        m->v[k] = h > 0.0 ? 1.5 * (b->x[k] - a->x[k]) / h - 0.25 * (a->v[k] + b->v[k])
                          : a->v[k];
    }
}

/* Halve [a, b] while the images ia, ib lie more than CR_OPIC_GAP apart,
 * pushing the midpoints' images in tau order (not ib). */
static int refine(opic_ctx *c, const cr_opic_point *a, const cr_opic_image *ia,
                  const cr_opic_point *b, const cr_opic_image *ib, int depth)
{
    cr_opic_point m;
    cr_opic_image im;
    if (hypot(ib->i - ia->i, ib->j - ia->j) <= CR_OPIC_GAP || depth >= CR_OPIC_DEPTH ||
        c->r->solves >= CR_OPIC_MAX_SOLVES)
        return 0;
    midpoint(a, b, &m);
    if (!solve_from(c, &m, 0.5 * (ia->i + ib->i), 0.5 * (ia->j + ib->j), &im) &&
        !solve_from(c, &m, ia->i, ia->j, &im) && !solve_from(c, &m, ib->i, ib->j, &im)) {
        c->broken = 1;
        return 0;
    }
    im.row = 0;
    if (refine(c, a, ia, &m, &im, depth + 1) || push(c, &im))
        return -1;
    return refine(c, &m, &im, b, ib, depth + 1);
}

/* Continue from a's image ia to b's: Newton for b from ia, and where it
 * fails the interval halved (the midpoint continued from ia first), down
 * to CR_OPIC_DEPTH halvings: an image that moves fast (a secondary one,
 * squeezed against the shadow) is followed in short steps. Pushes the
 * images between a and b (midpoints, refine's too) in tau order, and b's
 * into *ib (not pushed). Returns 1, 0 when it lost the image, -1 on
 * error. */
static int reach(opic_ctx *c, const cr_opic_point *a, const cr_opic_image *ia,
                 const cr_opic_point *b, cr_opic_image *ib, int depth)
{
    cr_opic_point m;
    cr_opic_image im;
    int r;
    if (solve_from(c, b, ia->i, ia->j, ib))
        return refine(c, a, ia, b, ib, depth) ? -1 : 1;
    if (depth >= CR_OPIC_DEPTH || c->r->solves >= CR_OPIC_MAX_SOLVES)
        return 0;
    midpoint(a, b, &m);
    r = reach(c, a, ia, &m, &im, depth + 1);
    if (r <= 0)
        return r;
    im.row = 0;
    if (push(c, &im))
        return -1;
    return reach(c, &m, &im, b, ib, depth + 1);
}

static int trace_order(opic_ctx *c, const cr_opic_point *pts, long n)
{
    long k, retry_at = 0, backoff = 1, prev = -1; /* prev: index of the last row image */
    c->first = c->r->n;
    c->broken = 0;
    for (k = 0; k < n; k++) {
        cr_opic_image im;
        int ok = 0;
        if (prev >= 0) {
            /* from the image extrapolated along the last two, or by halvings */
            cr_opic_image q1 = c->r->img[c->r->n - 1];
            double gi = q1.i, gj = q1.j;
            if (c->r->n - 1 > c->first && c->r->img[c->r->n - 2].tau < q1.tau) {
                const cr_opic_image *q0 = &c->r->img[c->r->n - 2];
                double u = (pts[k].tau - q1.tau) / (q1.tau - q0->tau);
                if (u > 4.0)
                    u = 4.0;
                gi += u * (q1.i - q0->i);
                gj += u * (q1.j - q0->j);
            }
            if (solve_from(c, &pts[k], gi, gj, &im)) {
                if (refine(c, &pts[prev], &q1, &pts[k], &im, 0))
                    return -1;
                ok = 1;
            } else {
                ok = reach(c, &pts[prev], &q1, &pts[k], &im, 0);
                if (ok < 0)
                    return -1;
            }
        }
        if (!ok && k >= retry_at) {
            c->broken = 1;
            ok = seed(c, &pts[k], &im);
            if (!ok) {
                retry_at = k + backoff;
                backoff = backoff < 64 ? 2 * backoff : 64;
            }
        }
        if (!ok) {
            c->r->lost++;
            c->broken = 1;
            prev = -1;
            continue;
        }
        backoff = 1;
        if (push(c, &im))
            return -1;
        prev = k;
    }
    return 0;
}

/* One order's work in a thread of its own. */
typedef struct opic_job {
    opic_ctx c;
    const cr_opic_point *pts;
    long n;
    cr_opic_result r;
    cr_err err;
    int rc;
    pthread_t tid;
    int started;
} opic_job;

static void *run_job(void *arg)
{
    opic_job *j = (opic_job *)arg;
    j->rc = trace_order(&j->c, j->pts, j->n);
    return NULL;
}

int cr_opic_trace(const cr_frame *f, const cr_opic_point *pts, long n, const cr_orbit_view *v,
                  cr_opic_result *r, cr_err *err)
{
    cr_frame fg, fo;
    opic_job job[CR_LENS_MAX_ORDER + 1];
    double reach = 0.0;
    long k, total = 0;
    int order, orders = v->orders < CR_LENS_MAX_ORDER + 1 ? v->orders : CR_LENS_MAX_ORDER + 1;
    int side = f->width > f->height ? f->width : f->height, rc = 0;
    memset(r, 0, sizeof *r);
    for (k = 0; k < n; k++) {
        double d = sqrt(pts[k].x[0] * pts[k].x[0] + pts[k].x[1] * pts[k].x[1] +
                        pts[k].x[2] * pts[k].x[2]);
        if (d > reach)
            reach = d;
    }
    /* tolerance 1e-9: the rays' error well below the miss tolerance */
    cr_lens_frame(f, reach, 0, 1e-9, &fg);
    cr_lens_frame(f, reach, 1, 1e-9, &fo);
    /* the orders are independent: one thread each (the same images with
       any number of cores), the calling thread where none can start */
    for (order = 0; order < orders; order++) {
        opic_job *j = &job[order];
        memset(j, 0, sizeof *j);
        j->c.fg = &fg;
        j->c.fo = &fo;
        j->c.order = order;
        j->c.max_step = 0.1 * side;
        j->c.seed_step = side / 32.0 > 2.0 ? side / 32.0 : 2.0;
        j->c.r = &j->r;
        j->c.err = &j->err;
        j->pts = pts;
        j->n = n;
        j->started = order > 0 && pthread_create(&j->tid, NULL, run_job, j) == 0;
    }
    for (order = 0; order < orders; order++)
        if (!job[order].started)
            run_job(&job[order]);
    for (order = 0; order < orders; order++) {
        if (job[order].started)
            pthread_join(job[order].tid, NULL);
        if (job[order].rc && !rc) {
            cr_err_set(err, "%s", job[order].err.msg);
            rc = -1;
        }
        total += job[order].r.n;
    }
    if (!rc && total > 0) {
        r->img = malloc((size_t)total * sizeof *r->img);
        if (!r->img)
            rc = cr_err_set(err, "out of memory for the images of the orbit (%ld)", total);
    }
    for (order = 0; order < orders; order++) {
        cr_opic_result *q = &job[order].r;
        if (!rc && q->n > 0) {
            memcpy(r->img + r->n, q->img, (size_t)q->n * sizeof *q->img);
            r->n += q->n;
        }
        r->solves += q->solves;
        r->lost += q->lost;
        cr_opic_result_free(q);
    }
    r->cap = r->n;
    if (rc)
        cr_opic_result_free(r);
    return rc;
}

cr_rgb cr_opic_tau_color(double tau, double tau0, double tau1)
{
    /* five stops of the viridis ramp */
    static const double stops[5][3] = {
        {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    double u = tau1 > tau0 ? (tau - tau0) / (tau1 - tau0) : 0.0, x;
    int k;
    cr_rgb c;
    if (!(u > 0.0))
        u = 0.0;
    if (u > 1.0)
        u = 1.0;
    x = u * 4.0;
    k = x >= 4.0 ? 3 : (int)x;
    x -= k;
    c.r = (uint8_t)lround(stops[k][0] + x * (stops[k + 1][0] - stops[k][0]));
    c.g = (uint8_t)lround(stops[k][1] + x * (stops[k + 1][1] - stops[k][1]));
    c.b = (uint8_t)lround(stops[k][2] + x * (stops[k + 1][2] - stops[k][2]));
    return c;
}

/* Distance from (px, py) to the segment a-b. */
static double seg_dist(double px, double py, double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy, u = 0.0;
    if (l2 > 0.0) {
        u = ((px - ax) * dx + (py - ay) * dy) / l2;
        u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
    }
    return hypot(px - ax - u * dx, py - ay - u * dy);
}

/* Draw segment a-b (pixels) of width w into the coverage and colour
 * buffers: a pixel keeps the largest coverage any segment gives it. */
static void draw_seg(float *cov, cr_rgb *col, int W, int H, double ax, double ay, double bx,
                     double by, double w, cr_rgb c)
{
    double rad = 0.5 * w + 0.5;
    int i0 = (int)floor(fmin(ax, bx) - rad), i1 = (int)ceil(fmax(ax, bx) + rad);
    int j0 = (int)floor(fmin(ay, by) - rad), j1 = (int)ceil(fmax(ay, by) + rad);
    int i, j;
    if (i1 < 0 || j1 < 0 || i0 >= W || j0 >= H)
        return;
    if (i0 < 0)
        i0 = 0;
    if (j0 < 0)
        j0 = 0;
    if (i1 >= W)
        i1 = W - 1;
    if (j1 >= H)
        j1 = H - 1;
    for (j = j0; j <= j1; j++)
        for (i = i0; i <= i1; i++) {
            /* the pixel's centre is at (i, j) */
            double a = rad - seg_dist(i, j, ax, ay, bx, by);
            float v = (float)(a > 1.0 ? 1.0 : a);
            if (v > cov[(size_t)j * W + i]) {
                cov[(size_t)j * W + i] = v;
                col[(size_t)j * W + i] = c;
            }
        }
}

void cr_opic_draw(const cr_frame *f, const cr_pixel *px, const cr_opic_result *r,
                  const cr_orbit_view *v, double tau0, double tau1, uint8_t *rgb)
{
    int W = f->width, H = f->height;
    size_t np = (size_t)W * H, p;
    float *cov = calloc(np, sizeof *cov);
    cr_rgb *col = malloc(np * sizeof *col);
    long k;
    for (p = 0; p < np; p++) {
        rgb[3 * p] = px[p].color.r;
        rgb[3 * p + 1] = px[p].color.g;
        rgb[3 * p + 2] = px[p].color.b;
    }
    if (!cov || !col) { /* the picture without the orbit rather than none */
        free(cov);
        free(col);
        return;
    }
    for (k = 0; k < r->n; k++) {
        const cr_opic_image *q = &r->img[k], *o = k > 0 ? &r->img[k - 1] : NULL;
        cr_rgb c;
        if (!q->visible)
            continue;
        if (o && q->join && o->visible) {
            c = v->by_tau ? cr_opic_tau_color(0.5 * (o->tau + q->tau), tau0, tau1) : v->color;
            draw_seg(cov, col, W, H, o->i, o->j, q->i, q->j, v->line_width, c);
        } else {
            c = v->by_tau ? cr_opic_tau_color(q->tau, tau0, tau1) : v->color;
            draw_seg(cov, col, W, H, q->i, q->j, q->i, q->j, v->line_width, c);
        }
    }
    for (p = 0; p < np; p++)
        if (cov[p] > 0.0f) {
            double a = cov[p];
            rgb[3 * p] = (uint8_t)lround(rgb[3 * p] + a * (col[p].r - rgb[3 * p]));
            rgb[3 * p + 1] = (uint8_t)lround(rgb[3 * p + 1] + a * (col[p].g - rgb[3 * p + 1]));
            rgb[3 * p + 2] = (uint8_t)lround(rgb[3 * p + 2] + a * (col[p].b - rgb[3 * p + 2]));
        }
    free(cov);
    free(col);
}

int cr_opic_write_csv(const cr_opic_result *r, const char *path, cr_err *err)
{
    cr_atomic a;
    long k;
    if (cr_atomic_open(&a, path, err))
        return -1;
    fputs("tau,t,order,i,j,t_obs,visible,row\n", a.fp);
    for (k = 0; k < r->n; k++) {
        const cr_opic_image *q = &r->img[k];
        char line[256], *e = line;
        e += cr_shortest_double(e, q->tau);
        *e++ = ',';
        e += cr_shortest_double(e, q->t);
        e += sprintf(e, ",%d,", q->order);
        e += cr_shortest_double(e, q->i);
        *e++ = ',';
        e += cr_shortest_double(e, q->j);
        *e++ = ',';
        e += cr_shortest_double(e, q->t_obs);
        e += sprintf(e, ",%d,%d\n", q->visible, q->row);
        fwrite(line, 1, (size_t)(e - line), a.fp);
    }
    return cr_atomic_commit(&a, err);
}

int cr_opic_view_open(cr_opic_view *v, const cr_particle_spec *spec, const char *orbit_name,
                      int w, int h, cr_err *err)
{
    const cr_orbit_view *ov = &spec->view;
    cr_err e;
    double rows;
    memset(v, 0, sizeof *v);
    if (!ov->given)
        return cr_err_set(err,
                          "%s: the lensed picture needs a camera: the orbit file has no view section "
                          "(view: {scene: FILE}, a scene file whose observer takes the "
                          "picture)",
                          orbit_name);
    if (w < 1 || h < 1 || w > CR_OPIC_MAX_SIDE || h > CR_OPIC_MAX_SIDE)
        return cr_err_set(err, "the picture's size %d x %d is not 1 to %d pixels a side", w, h,
                          CR_OPIC_MAX_SIDE);
    if (cr_scene_load(ov->scene, &v->sc, &e))
        return cr_err_set(err, "%s%s", ov->where, e.msg);
    if (v->sc.m.a != v->sc.m.b || v->sc.a.a != v->sc.a.b || v->sc.q.a != v->sc.q.b ||
        v->sc.m.a != spec->mt.m || v->sc.a.a != spec->mt.a || v->sc.q.a != spec->mt.q) {
        cr_err_set(err,
                   "%sthe scene's metric (m %g, a %g, q %g) is not the orbit file's (m %g, "
                   "a %g, q %g): the picture needs the same hole",
                   ov->where, v->sc.m.a, v->sc.a.a, v->sc.q.a, spec->mt.m, spec->mt.a,
                   spec->mt.q);
        cr_scene_free(&v->sc);
        return -1;
    }
    if ((v->sc.disc_exposure_auto &&
         cr_scene_auto_exposure(&v->sc, 1, w, h, NULL, NULL, &e)) ||
        cr_frame_eval_at(&v->ev, &v->sc, 0, 1, w, h, NULL, &e)) {
        cr_err_set(err, "%s%s", ov->where, e.msg);
        cr_frame_eval_free(&v->ev);
        cr_scene_free(&v->sc);
        return -1;
    }
    v->spec = spec;
    v->err = err;
    v->stride = 1;
    rows = floor(spec->tau / spec->dtau) + 2.0;
    if (rows > CR_OPIC_MAX_POINTS)
        v->stride = (long)ceil(rows / CR_OPIC_MAX_POINTS);
    return 0;
}

int cr_opic_view_row(void *ctx, const double *row)
{
    cr_opic_view *v = (cr_opic_view *)ctx;
    int i;
    if (v->seen++ % v->stride == 0) {
        if (v->n == v->cap) {
            long cap = v->cap ? 2 * v->cap : 1024;
            cr_opic_point *g = realloc(v->pts, (size_t)cap * sizeof *g);
            if (!g)
                return cr_err_set(v->err, "out of memory for the orbit's picture");
            v->pts = g;
            v->cap = cap;
        }
        cr_opic_point_of_row(row, &v->spec->mt, &v->pts[v->n++]);
        v->have_last = 0;
        return 0;
    }
    for (i = 0; i < CR_WL_COLS; i++)
        v->last[i] = row[i];
    v->have_last = 1;
    return 0;
}

int cr_opic_view_picture(cr_opic_view *v, const cr_pixel *px, uint8_t *rgb, cr_opic_result *r,
                         cr_err *err)
{
    memset(r, 0, sizeof *r);
    /* the last row, when the thinning left it out */
    v->stride = 1;
    if (v->have_last) {
        v->have_last = 0;
        if (cr_opic_view_row(v, v->last))
            return cr_err_set(err, "%s", v->err->msg);
    }
    if (v->n < 1)
        return cr_err_set(err, "the worldline has no rows to draw");
    if (cr_opic_trace(&v->ev.frame, v->pts, v->n, &v->spec->view, r, err))
        return -1;
    cr_opic_draw(&v->ev.frame, px, r, &v->spec->view, v->pts[0].tau, v->pts[v->n - 1].tau, rgb);
    return 0;
}

void cr_opic_view_free(cr_opic_view *v)
{
    free(v->pts);
    if (v->spec) {
        cr_frame_eval_free(&v->ev);
        cr_scene_free(&v->sc);
    }
    memset(v, 0, sizeof *v);
}
