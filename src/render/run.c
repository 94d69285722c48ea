/* curray render: the frame stack (run.h). */
#include "run.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cr_stack_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int cr_stack_block_rows(int frames, int height, int ranks)
{
    int rows;
    if (frames != 1 || ranks < 2)
        return height;
    rows = (int)(height / (16L * ranks));
    return rows < 1 ? 1 : rows;
}

int cr_stack_init(cr_stack *st, const cr_stack_ops *ops, int frames, int width, int height,
                  int block_rows, const char *skip, atomic_int *cancel, cr_backend *backends,
                  int n_backends, cr_err *err)
{
    memset(st, 0, sizeof *st);
    st->ops = *ops;
    st->frames = frames;
    st->width = width;
    st->height = height;
    st->block_rows = block_rows < 1 || block_rows > height ? height : block_rows;
    st->skip = skip;
    st->cancel = cancel;
    st->backends = backends;
    st->n_backends = n_backends;
    atomic_init(&st->next_item, 0);
    if (n_backends < 0 || n_backends > CR_STACK_MAX_WORKERS)
        return cr_err_set(err, "%d backends; the frame stack drives at most %d", n_backends,
                          CR_STACK_MAX_WORKERS);
    if (st->block_rows < height && frames != 1)
        return cr_err_set(err, "blocks of rows for a run of %d frames (only one frame is "
                               "assembled from blocks)",
                          frames);
    if (st->block_rows < height && !(skip && skip[0]) &&
        !(st->assembly = malloc(sizeof *st->assembly * (size_t)width * (size_t)height)))
        return cr_err_set(err, "out of memory for a %dx%d frame", width, height);
    pthread_mutex_init(&st->lock, NULL);
    return 0;
}

void cr_stack_free(cr_stack *st)
{
    free(st->assembly);
    st->assembly = NULL;
    pthread_mutex_destroy(&st->lock);
}

void cr_stack_fail(cr_stack *st, const cr_err *err)
{
    pthread_mutex_lock(&st->lock);
    if (!st->failed) {
        st->failed = 1;
        st->fail_err = *err;
    }
    pthread_mutex_unlock(&st->lock);
}

int cr_stack_failed(cr_stack *st, cr_err *err)
{
    int failed;
    pthread_mutex_lock(&st->lock);
    failed = st->failed;
    if (failed && err)
        *err = st->fail_err;
    pthread_mutex_unlock(&st->lock);
    return failed;
}

static int cr_stack_cancelled(const cr_stack *st)
{
    return st->cancel && atomic_load_explicit(st->cancel, memory_order_relaxed) != 0;
}

int cr_stack_take(cr_stack *st, cr_item *it)
{
    int per_frame = (st->height + st->block_rows - 1) / st->block_rows, c;
    do {
        c = atomic_fetch_add(&st->next_item, 1);
        it->frame = c / per_frame;
    } while (it->frame < st->frames && st->skip && st->skip[it->frame]);
    if (cr_stack_failed(st, NULL) || cr_stack_cancelled(st) || it->frame >= st->frames)
        return -1;
    it->row0 = (c % per_frame) * st->block_rows;
    it->rows = it->row0 + st->block_rows <= st->height ? st->block_rows : st->height - it->row0;
    if (it->rows < st->height && c == 0) {
        pthread_mutex_lock(&st->lock);
        st->t_first = cr_stack_now();
        pthread_mutex_unlock(&st->lock);
    }
    return 0;
}

/* What prepare left in a slot, freed. */
static void cr_stack_release(cr_stack *st, void **slot)
{
    if (*slot && st->ops.release)
        st->ops.release(st->ops.ctx, *slot);
    *slot = NULL;
}

/* A whole frame to the sink; without t->frame, the frame prepared again. */
static int cr_stack_sink(cr_stack *st, int worker, const cr_traced *t, cr_err *err)
{
    cr_traced u = *t;
    void *slot = NULL;
    int rc = -1;
    if (u.frame || st->ops.prepare(st->ops.ctx, u.item.frame, &slot, &u.frame, err) == 0)
        rc = st->ops.deliver(st->ops.ctx, worker, &u, err);
    cr_stack_release(st, &slot);
    if (rc)
        cr_stack_fail(st, err);
    return rc;
}

int cr_stack_deliver(cr_stack *st, int worker, const cr_traced *t, cr_err *err)
{
    size_t w = (size_t)st->width;
    if (t->item.rows == st->height)
        return cr_stack_sink(st, worker, t, err);
    if (!st->assembly)
        return cr_err_set(err, "a block of rows %d to %d for a run of whole frames",
                          t->item.row0, t->item.row0 + t->item.rows - 1);
    memcpy(st->assembly + (size_t)t->item.row0 * w, t->px,
           sizeof *t->px * (size_t)t->item.rows * w);
    pthread_mutex_lock(&st->lock);
    st->assembled_rows += t->item.rows;
    pthread_mutex_unlock(&st->lock);
    return 0;
}

void cr_stack_finish(cr_stack *st)
{
    cr_traced t;
    cr_err err;
    if (!st->assembly || st->assembled_rows != st->height || cr_stack_failed(st, NULL) ||
        cr_stack_cancelled(st))
        return;
    memset(&t, 0, sizeof t);
    t.item.frame = 0;
    t.item.rows = st->height;
    t.px = st->assembly;
    t.seconds = cr_stack_now() - st->t_first;
    t.device = st->n_backends > 0 ? st->backends[0].device : -1;
    cr_stack_sink(st, 0, &t, &err);
}

/* ---- one worker: a backend fed from the stack ---------------------------- */

/* A worker's frames: slot cur holds the frame of the item being waited for
 * (and then delivered), the other one the next item's, each in what the
 * caller's prepare keeps in slot[]. A slot keeps its frame for the next item
 * of the same frame. */
typedef struct cr_worker {
    cr_stack *st;
    int index;
    cr_backend *b;
    cr_item item; /* the item being waited for */
    int cur;
    const cr_frame *f[2];
    int f_k[2]; /* the frame number in each slot, -1: none */
    void *slot[2];
} cr_worker;

static void cr_worker_progress(void *ctx, int rows_done, int rows_total)
{
    cr_worker *w = ctx;
    if (w->st->ops.progress)
        w->st->ops.progress(w->st->ops.ctx, w->index, &w->item, rows_done, rows_total);
}

static void cr_worker_begin(cr_worker *w, const cr_item *it)
{
    if (w->st->ops.begin)
        w->st->ops.begin(w->st->ops.ctx, w->index, it);
}

/* Frame k prepared into slot s (kept when the slot holds it already). */
static int cr_worker_prepare(cr_worker *w, int s, int k, cr_err *err)
{
    if (w->f_k[s] == k)
        return 0;
    w->f_k[s] = -1;
    if (w->st->ops.prepare(w->st->ops.ctx, k, &w->slot[s], &w->f[s], err))
        return -1;
    w->f_k[s] = k;
    return 0;
}

static int cr_worker_launch(cr_worker *w, int s, const cr_item *it, cr_err *err)
{
    if (cr_worker_prepare(w, s, it->frame, err))
        return -1;
    return cr_backend_launch(w->b, w->f[s], it->row0, it->rows, err);
}

/* The item just waited for, to the sink (its pixels px, its time). */
static int cr_worker_deliver(cr_worker *w, const cr_pixel *px, double seconds, cr_err *err)
{
    cr_traced t;
    t.item = w->item;
    t.frame = w->f[w->cur];
    t.px = px;
    t.seconds = seconds;
    t.device = w->b->device;
    t.split = cr_backend_times(w->b, &t.trace_s, &t.copy_s);
    return cr_stack_deliver(w->st, w->index, &t, err);
}

/* The pipeline: item n+1 is launched before item n's pixels are delivered;
 * item n is delivered even when item n+1 could not be launched. */
static int cr_worker_loop(cr_worker *w, cr_err *err)
{
    int more = 1;
    if (cr_stack_take(w->st, &w->item))
        return 0; /* nothing left for this worker */
    w->cur = 0;
    if (cr_worker_launch(w, w->cur, &w->item, err))
        return -1;
    while (more) {
        const cr_pixel *px;
        double seconds = 0.0;
        cr_item next;
        cr_err next_err;
        int next_rc = 0;
        cr_worker_begin(w, &w->item);
        px = cr_backend_wait(w->b, cr_worker_progress, w, w->st->cancel, &seconds, err);
        if (!px) {
            cr_worker_begin(w, NULL);
            return -1;
        }
        more = cr_stack_take(w->st, &next) == 0;
        if (more)
            next_rc = cr_worker_launch(w, !w->cur, &next, &next_err);
        if (cr_worker_deliver(w, px, seconds, err))
            return -1;
        if (next_rc) {
            *err = next_err;
            return -1;
        }
        w->item = next;
        w->cur = !w->cur;
    }
    return 0;
}

static void *cr_worker_main(void *arg)
{
    cr_worker w;
    cr_stack *st = ((cr_worker *)arg)->st;
    cr_err err;
    w = *(cr_worker *)arg;
    free(arg);
    err.msg[0] = '\0';
    w.f_k[0] = w.f_k[1] = -1;
    w.slot[0] = w.slot[1] = NULL;
    if (cr_worker_loop(&w, &err))
        cr_stack_fail(st, &err);
    cr_stack_release(st, &w.slot[0]);
    cr_stack_release(st, &w.slot[1]);
    return NULL;
}

static cr_worker *cr_worker_new(cr_stack *st, int k)
{
    cr_worker *w = calloc(1, sizeof *w);
    if (w) {
        w->st = st;
        w->index = k;
        w->b = &st->backends[k];
    }
    return w;
}

void cr_stack_start(cr_stack *st)
{
    cr_err err;
    int k;
    st->started = 0;
    for (k = 0; k < st->n_backends; k++) {
        cr_worker *w = cr_worker_new(st, k);
        if (!w || pthread_create(&st->tid[k], NULL, cr_worker_main, w) != 0) {
            free(w);
            break;
        }
        st->started++;
    }
    if (st->started == 0 && st->n_backends > 0) {
        cr_worker *w = cr_worker_new(st, 0);
        if (w) {
            cr_worker_main(w);
        } else {
            cr_err_set(&err, "out of memory for a worker");
            cr_stack_fail(st, &err);
        }
    }
}

void cr_stack_join(cr_stack *st)
{
    int k;
    for (k = 0; k < st->started; k++)
        pthread_join(st->tid[k], NULL);
    st->started = 0;
}

void cr_stack_run(cr_stack *st)
{
    if (st->n_backends == 1) {
        cr_worker *w = cr_worker_new(st, 0);
        cr_err err;
        if (w) {
            cr_worker_main(w);
        } else {
            cr_err_set(&err, "out of memory for a worker");
            cr_stack_fail(st, &err);
        }
    } else {
        cr_stack_start(st);
        cr_stack_join(st);
    }
    cr_stack_finish(st);
}

int cr_stack_trace(cr_stack *st, cr_backend *b, const cr_item *it, cr_pixel *out,
                   double *seconds, cr_err *err)
{
    const cr_pixel *px = NULL;
    const cr_frame *f = NULL;
    void *slot = NULL;
    if (st->ops.prepare(st->ops.ctx, it->frame, &slot, &f, err) == 0 &&
        cr_backend_launch(b, f, it->row0, it->rows, err) == 0)
        px = cr_backend_wait(b, NULL, NULL, st->cancel, seconds, err);
    if (px)
        memcpy(out, px, sizeof *out * (size_t)it->rows * (size_t)f->width);
    cr_stack_release(st, &slot);
    return px ? 0 : -1;
}
