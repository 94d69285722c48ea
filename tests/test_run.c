/* The frame stack (src/render/run.h) over a fake backend, and the CPU
 * backend behind backend.h:
 * - order: one backend traces frames 0..n-1 in order, frame k+1 launched
 *   before frame k is delivered (the pipeline) with frame k's own prepared
 *   frame, every frame delivered once;
 * - the first failure is the run's and stops the handing out of items;
 *   a frame whose successor cannot be launched is still delivered;
 * - the cancel flag stops the run: no item is taken after it is set;
 * - progress: every row of every frame counted once, begin once per item;
 * - skipped frames, frames over several workers, blocks of rows assembled
 *   into one frame, cr_stack_trace;
 * - the CPU backend: two items in flight, a third refused, its pixels equal
 *   cr_cpu_render's bit for bit, a set cancel flag gives "interrupted".
 * Threaded: run under ThreadSanitizer by .ci/run. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render/backend.h"
#include "render/cpu.h"
#include "render/gpu.h"
#include "render/run.h"
#include "testutil.h"

#define W 5
#define H 4
#define MAX_EVENTS 512

/* What the fake backend and the sink saw, in order: "L3" launch of frame
 * 3, "D3" delivery of frame 3. Shared by every worker (guarded). */
typedef struct record {
    pthread_mutex_t lock;
    char ev[MAX_EVENTS][8];
    int n_ev;
    int delivered[64];  /* deliveries per frame */
    long rows_seen;     /* progress: rows reported finished, summed */
    int begins, idles;
    int fail_wait_at;   /* the fake's wait fails on this frame (-1: never) */
    int fail_deliver_at; /* the sink fails on this frame (-1: never) */
    int fail_prepare_at; /* prepare fails on this frame (-1: never) */
    int cancel_after;   /* the sink sets the cancel flag after this frame (-1: never) */
    int slots_made, slots_released; /* what prepare put in a slot, and release freed */
    atomic_int cancel;
    cr_pixel frame[W * H]; /* the last frame delivered */
} record;

static void rec_event(record *r, char what, int k)
{
    pthread_mutex_lock(&r->lock);
    if (r->n_ev < MAX_EVENTS)
        snprintf(r->ev[r->n_ev++], sizeof r->ev[0], "%c%d", what, k);
    pthread_mutex_unlock(&r->lock);
}

/* ---- the fake backend: pixel (i, j) of frame k has steps 1000 k + j and
 * object i; progress once per row ---------------------------------------- */

typedef struct fake {
    record *r;
    int k[CR_BACKEND_IN_FLIGHT], row0[CR_BACKEND_IN_FLIGHT], rows[CR_BACKEND_IN_FLIGHT];
    int first, n;
    cr_pixel px[W * H];
} fake;

static int fake_launch(void *impl, const cr_frame *f, int row0, int rows, cr_err *err)
{
    fake *b = impl;
    int s;
    if (b->n == CR_BACKEND_IN_FLIGHT)
        return cr_err_set(err, "fake: three in flight");
    s = (b->first + b->n) % CR_BACKEND_IN_FLIGHT;
    b->k[s] = (int)f->max_steps; /* the frame number, as prepare put it */
    b->row0[s] = row0;
    b->rows[s] = rows;
    b->n++;
    rec_event(b->r, 'L', (int)f->max_steps);
    return 0;
}

static const cr_pixel *fake_wait(void *impl, cr_progress_fn progress, void *ctx,
                                 atomic_int *cancel, double *seconds, cr_err *err)
{
    fake *b = impl;
    int s = b->first, j, i;
    if (b->n == 0) {
        cr_err_set(err, "fake: nothing in flight");
        return NULL;
    }
    b->first = (b->first + 1) % CR_BACKEND_IN_FLIGHT;
    b->n--;
    if (cancel && atomic_load(cancel)) {
        b->n = 0;
        cr_err_set(err, "interrupted");
        return NULL;
    }
    if (b->k[s] == b->r->fail_wait_at) {
        b->n = 0;
        cr_err_set(err, "fake: frame %d failed", b->k[s]);
        return NULL;
    }
    for (j = 0; j < b->rows[s]; j++) {
        for (i = 0; i < W; i++) {
            cr_pixel *p = &b->px[j * W + i];
            memset(p, 0, sizeof *p);
            p->steps = (uint32_t)(1000 * b->k[s] + b->row0[s] + j);
            p->object = (int16_t)i;
        }
        if (progress)
            progress(ctx, j + 1, b->rows[s]);
    }
    if (seconds)
        *seconds = 0.5;
    return b->px;
}

static int fake_times(const void *impl, double *trace_s, double *copy_s)
{
    (void)impl;
    *trace_s = 0.25;
    *copy_s = 0.25;
    return 1;
}

static void fake_close(void *impl)
{
    free(impl);
}

static const cr_backend_ops fake_ops = {fake_launch, fake_wait, fake_times, fake_close};

static void fake_open(cr_backend *b, record *r)
{
    fake *f = calloc(1, sizeof *f);
    assert_non_null(f);
    f->r = r;
    b->ops = &fake_ops;
    b->impl = f;
    b->device = 7;
}

/* ---- the sink ------------------------------------------------------------ */

/* The frame lives in the slot (a cr_frame of its own, made at the slot's
 * first prepare, as the command line's cr_frame_eval). */
static int sink_prepare(void *ctx, int k, void **slot, const cr_frame **out, cr_err *err)
{
    record *r = ctx;
    cr_frame *f = *slot;
    if (k == r->fail_prepare_at)
        return cr_err_set(err, "prepare: frame %d refused", k);
    if (!f) {
        f = malloc(sizeof *f);
        assert_non_null(f);
        *slot = f;
        pthread_mutex_lock(&r->lock);
        r->slots_made++;
        pthread_mutex_unlock(&r->lock);
    }
    memset(f, 0, sizeof *f);
    f->width = W;
    f->height = H;
    f->max_steps = k;
    *out = f;
    return 0;
}

static void sink_release(void *ctx, void *slot)
{
    record *r = ctx;
    free(slot);
    pthread_mutex_lock(&r->lock);
    r->slots_released++;
    pthread_mutex_unlock(&r->lock);
}

static int sink_deliver(void *ctx, int worker, const cr_traced *t, cr_err *err)
{
    record *r = ctx;
    (void)worker;
    assert_int_equal(t->item.row0, 0);
    assert_int_equal(t->item.rows, H);
    /* the frame traced, not the next one prepared meanwhile */
    assert_non_null(t->frame);
    assert_int_equal((int)t->frame->max_steps, t->item.frame);
    if (t->item.frame == r->fail_deliver_at)
        return cr_err_set(err, "deliver: frame %d refused", t->item.frame);
    rec_event(r, 'D', t->item.frame);
    pthread_mutex_lock(&r->lock);
    r->delivered[t->item.frame]++;
    memcpy(r->frame, t->px, sizeof r->frame);
    pthread_mutex_unlock(&r->lock);
    if (t->item.frame == r->cancel_after)
        atomic_store(&r->cancel, 1);
    return 0;
}

static void sink_begin(void *ctx, int worker, const cr_item *it)
{
    record *r = ctx;
    (void)worker;
    pthread_mutex_lock(&r->lock);
    if (it)
        r->begins++;
    else
        r->idles++;
    pthread_mutex_unlock(&r->lock);
}

static void sink_progress(void *ctx, int worker, const cr_item *it, int rows_done,
                          int rows_total)
{
    record *r = ctx;
    (void)worker;
    (void)it;
    (void)rows_total;
    pthread_mutex_lock(&r->lock);
    if (rows_done > 0)
        r->rows_seen++; /* the fake reports each row once, 1, 2, ... */
    pthread_mutex_unlock(&r->lock);
}

static const cr_stack_ops sink_ops = {NULL, sink_prepare, sink_deliver, sink_begin,
                                      sink_progress, sink_release};

static record *rec_new(void)
{
    record *r = calloc(1, sizeof *r);
    assert_non_null(r);
    pthread_mutex_init(&r->lock, NULL);
    r->fail_wait_at = r->fail_deliver_at = r->fail_prepare_at = r->cancel_after = -1;
    atomic_init(&r->cancel, 0);
    return r;
}

static void rec_free(record *r)
{
    /* every slot that prepare filled was released */
    assert_int_equal(r->slots_released, r->slots_made);
    pthread_mutex_destroy(&r->lock);
    free(r);
}

/* Run `frames` frames on n fake backends; returns whether the run failed,
 * its first failure in *err. */
static int run_fake(record *r, int frames, int n, const char *skip, cr_err *err)
{
    cr_backend b[8];
    cr_stack st;
    cr_stack_ops ops = sink_ops;
    int k, failed;
    ops.ctx = r;
    for (k = 0; k < n; k++)
        fake_open(&b[k], r);
    assert_int_equal(cr_stack_init(&st, &ops, frames, W, H, H, skip, &r->cancel, b, n, err),
                     0);
    cr_stack_run(&st);
    failed = cr_stack_failed(&st, err);
    cr_stack_free(&st);
    for (k = 0; k < n; k++)
        cr_backend_close(&b[k]);
    return failed;
}

static void expect_events(const record *r, const char *const *want, int n)
{
    int k;
    for (k = 0; k < n && k < r->n_ev; k++)
        if (strcmp(r->ev[k], want[k]) != 0)
            fail_msg("event %d: %s, expected %s", k, r->ev[k], want[k]);
    assert_int_equal(r->n_ev, n);
}

static void test_order_and_pipeline(void **state)
{
    static const char *const want[] = {"L0", "L1", "D0", "L2", "D1", "L3", "D2", "D3"};
    record *r = rec_new();
    cr_err err;
    int k;
    (void)state;
    assert_int_equal(run_fake(r, 4, 1, NULL, &err), 0);
    expect_events(r, want, 8);
    for (k = 0; k < 4; k++)
        assert_int_equal(r->delivered[k], 1);
    assert_int_equal(r->frame[2 * W + 3].steps, 3002); /* frame 3, row 2 */
    assert_int_equal(r->frame[2 * W + 3].object, 3);
    rec_free(r);
}

static void test_progress_counts(void **state)
{
    record *r = rec_new();
    cr_err err;
    (void)state;
    assert_int_equal(run_fake(r, 6, 1, NULL, &err), 0);
    assert_int_equal(r->rows_seen, 6 * H); /* every row of every frame once */
    assert_int_equal(r->begins, 6);
    assert_int_equal(r->idles, 0);
    rec_free(r);
}

static void test_first_failure_stops(void **state)
{
    static const char *const want[] = {"L0", "L1", "D0", "L2", "D1"};
    record *r = rec_new();
    cr_err err;
    (void)state;
    r->fail_wait_at = 2;
    assert_int_equal(run_fake(r, 10, 1, NULL, &err), 1);
    assert_string_equal(err.msg, "fake: frame 2 failed");
    expect_events(r, want, 5); /* nothing launched after the failure */
    assert_int_equal(r->delivered[2] + r->delivered[3], 0);
    assert_int_equal(r->idles, 1);
    rec_free(r);
}

static void test_first_failure_kept(void **state)
{
    cr_stack st;
    cr_stack_ops ops = sink_ops;
    cr_err a, b, got;
    cr_item it;
    (void)state;
    assert_int_equal(cr_stack_init(&st, &ops, 3, W, H, H, NULL, NULL, NULL, 0, &got), 0);
    assert_int_equal(cr_stack_failed(&st, &got), 0);
    assert_int_equal(cr_stack_take(&st, &it), 0);
    assert_int_equal(it.frame, 0);
    cr_err_set(&a, "first");
    cr_err_set(&b, "second");
    cr_stack_fail(&st, &a);
    cr_stack_fail(&st, &b);
    assert_int_equal(cr_stack_failed(&st, &got), 1);
    assert_string_equal(got.msg, "first");
    assert_int_equal(cr_stack_take(&st, &it), -1);
    cr_stack_free(&st);
}

static void test_deliver_failure_and_launch_failure(void **state)
{
    static const char *const want1[] = {"L0", "L1"};
    static const char *const want2[] = {"L0", "L1", "D0", "D1"};
    record *r = rec_new();
    cr_err err;
    (void)state;
    r->fail_deliver_at = 0; /* the sink refuses frame 0: frame 1 is in flight, dropped */
    assert_int_equal(run_fake(r, 5, 1, NULL, &err), 1);
    assert_string_equal(err.msg, "deliver: frame 0 refused");
    expect_events(r, want1, 2);
    rec_free(r);
    r = rec_new();
    r->fail_prepare_at = 2; /* frame 2 cannot be launched: frame 1 is still delivered */
    assert_int_equal(run_fake(r, 5, 1, NULL, &err), 1);
    assert_string_equal(err.msg, "prepare: frame 2 refused");
    expect_events(r, want2, 4);
    rec_free(r);
}

static void test_cancel_stops(void **state)
{
    static const char *const want[] = {"L0", "L1", "D0", "L2", "D1"};
    record *r = rec_new();
    cr_err err;
    (void)state;
    r->cancel_after = 1; /* frame 2 was launched before 1 was delivered: it stops */
    assert_int_equal(run_fake(r, 10, 1, NULL, &err), 1);
    assert_string_equal(err.msg, "interrupted");
    expect_events(r, want, 5);
    rec_free(r);
}

static void test_skip(void **state)
{
    static const char skip[5] = {0, 1, 0, 1, 0};
    record *r = rec_new();
    cr_err err;
    (void)state;
    assert_int_equal(run_fake(r, 5, 1, skip, &err), 0);
    assert_int_equal(r->delivered[0] + r->delivered[2] + r->delivered[4], 3);
    assert_int_equal(r->delivered[1] + r->delivered[3], 0);
    rec_free(r);
}

static void test_many_workers(void **state)
{
    record *r = rec_new();
    cr_err err;
    int k;
    (void)state;
    assert_int_equal(run_fake(r, 40, 3, NULL, &err), 0);
    for (k = 0; k < 40; k++)
        assert_int_equal(r->delivered[k], 1);
    assert_int_equal(r->rows_seen, 40 * H);
    rec_free(r);
}

/* One frame in blocks of one row: the local backend takes some, "another
 * rank" (this thread, cr_stack_take and cr_stack_deliver) the others; the
 * assembled frame reaches the sink once, at cr_stack_finish. */
static void test_blocks_assembled(void **state)
{
    record *r = rec_new();
    cr_backend b;
    cr_stack st;
    cr_stack_ops ops = sink_ops;
    cr_item it;
    cr_err err;
    cr_pixel rowpx[W];
    int rows = cr_stack_block_rows(1, H, 2), i, j;
    (void)state;
    assert_int_equal(rows, 1); /* 4 rows over 2 ranks: 16 blocks a rank asked, 1 row each */
    assert_int_equal(cr_stack_block_rows(3, H, 2), H);
    assert_int_equal(cr_stack_block_rows(1, H, 1), H);
    ops.ctx = r;
    fake_open(&b, r);
    assert_int_equal(cr_stack_init(&st, &ops, 1, W, H, rows, NULL, &r->cancel, &b, 1, &err),
                     0);
    /* the other rank's block first */
    assert_int_equal(cr_stack_take(&st, &it), 0);
    assert_int_equal(it.row0, 0);
    assert_int_equal(it.rows, 1);
    for (i = 0; i < W; i++) {
        memset(&rowpx[i], 0, sizeof rowpx[i]);
        rowpx[i].steps = 0;
        rowpx[i].object = (int16_t)i;
    }
    {
        cr_traced t;
        memset(&t, 0, sizeof t);
        t.item = it;
        t.px = rowpx;
        t.device = -1;
        assert_int_equal(cr_stack_deliver(&st, 1, &t, &err), 0);
    }
    cr_stack_start(&st);
    cr_stack_join(&st);
    assert_int_equal(r->delivered[0], 0); /* not before finish */
    cr_stack_finish(&st);
    assert_int_equal(r->delivered[0], 1);
    for (j = 0; j < H; j++)
        for (i = 0; i < W; i++) {
            assert_int_equal(r->frame[j * W + i].steps, j);
            assert_int_equal(r->frame[j * W + i].object, i);
        }
    assert_int_equal(cr_stack_failed(&st, NULL), 0);
    cr_stack_free(&st);
    cr_backend_close(&b);
    rec_free(r);
}

static void test_trace_one(void **state)
{
    record *r = rec_new();
    cr_backend b;
    cr_stack st;
    cr_stack_ops ops = sink_ops;
    cr_item it = {3, 1, 2};
    cr_pixel out[2 * W];
    double seconds = 0.0;
    cr_err err;
    (void)state;
    ops.ctx = r;
    fake_open(&b, r);
    assert_int_equal(cr_stack_init(&st, &ops, 5, W, H, H, NULL, NULL, NULL, 0, &err), 0);
    assert_int_equal(cr_stack_trace(&st, &b, &it, out, &seconds, &err), 0);
    assert_int_equal(out[0].steps, 3001);
    assert_int_equal(out[W + 4].steps, 3002);
    assert_true(seconds == 0.5);
    cr_stack_free(&st);
    cr_backend_close(&b);
    rec_free(r);
}

/* ---- the CPU backend ------------------------------------------------------ */

/* Pixels equal bit for bit, field by field (the padding is not written). */
static void expect_pixels(const cr_pixel *a, const cr_pixel *b, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        assert_memory_equal(&a[k].redshift, &b[k].redshift, 6 * sizeof(double));
        assert_int_equal(a[k].steps, b[k].steps);
        assert_int_equal(a[k].object, b[k].object);
        assert_int_equal(a[k].outcome, b[k].outcome);
        assert_memory_equal(&a[k].color, &b[k].color, sizeof a[k].color);
    }
}

static void test_cpu_backend(void **state)
{
    enum { CW = 12, CH = 10 };
    cr_frame f;
    cr_backend b;
    cr_pixel ref[CW * CH];
    const cr_pixel *px;
    cr_err err;
    atomic_int cancel;
    double seconds = -1.0, ts, cs;
    (void)state;
    cr_test_empty_frame(&f, 1.0, 0.5, 0.0, 20.0, 0.45 * CR_PI);
    f.width = CW;
    f.height = CH;
    cr_frame_prepare(&f);
    assert_int_equal(cr_cpu_render(&f, 2, ref, NULL, NULL, NULL, &err), 0);
    assert_int_equal(cr_backend_open(&b, -1, 2, CW, CH, &err), 0);
    assert_int_equal(b.device, -1);
    assert_int_equal(cr_backend_launch(&b, &f, 0, CH, &err), 0);
    assert_int_equal(cr_backend_launch(&b, &f, 3, 4, &err), 0);
    assert_int_equal(cr_backend_launch(&b, &f, 0, CH, &err), -1); /* a third in flight */
    px = cr_backend_wait(&b, NULL, NULL, NULL, &seconds, &err);
    assert_non_null(px);
    assert_true(seconds >= 0.0);
    expect_pixels(px, ref, CW * CH);
    px = cr_backend_wait(&b, NULL, NULL, NULL, NULL, &err);
    assert_non_null(px);
    expect_pixels(px, ref + 3 * CW, 4 * CW);
    assert_int_equal(cr_backend_times(&b, &ts, &cs), 0);
    assert_null(cr_backend_wait(&b, NULL, NULL, NULL, NULL, &err)); /* none in flight */
    /* rows outside the frame; a cancelled wait */
    assert_int_equal(cr_backend_launch(&b, &f, 8, 3, &err), -1);
    assert_string_equal(err.msg, "rows 8 to 10 of a frame of 10 rows");
    atomic_init(&cancel, 1);
    assert_int_equal(cr_backend_launch(&b, &f, 0, CH, &err), 0);
    assert_null(cr_backend_wait(&b, NULL, NULL, &cancel, NULL, &err));
    assert_string_equal(err.msg, "interrupted");
    cr_backend_close(&b);
    cr_backend_close(&b); /* closed twice: ignored */
}

static void test_choose(void **state)
{
    int enabled[2] = {1, 1}, devices[2];
    cr_err why;
    (void)state;
    assert_int_equal(cr_backend_choose(CR_BACKEND_CPU, enabled, 2, devices, 2, &why), 0);
    assert_string_equal(why.msg, "");
    if (!cr_gpu_built()) {
        assert_int_equal(cr_backend_choose(CR_BACKEND_CUDA, enabled, 2, devices, 2, &why), -1);
        assert_non_null(strstr(why.msg, "no CUDA support"));
        assert_int_equal(cr_backend_choose(CR_BACKEND_AUTO, enabled, 2, devices, 2, &why), 0);
        assert_non_null(strstr(why.msg, "no CUDA support"));
    }
    assert_int_equal(cr_backend_cpu_threads(3, 5), 3);
    assert_int_equal(cr_backend_cpu_threads(0, 5), 5);
    assert_int_equal(cr_backend_cpu_threads(0, 0), cr_cpu_cores() < CR_SYSCONFIG_MAX_THREADS
                                                       ? cr_cpu_cores()
                                                       : CR_SYSCONFIG_MAX_THREADS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_and_pipeline),
        cmocka_unit_test(test_progress_counts),
        cmocka_unit_test(test_first_failure_stops),
        cmocka_unit_test(test_first_failure_kept),
        cmocka_unit_test(test_deliver_failure_and_launch_failure),
        cmocka_unit_test(test_cancel_stops),
        cmocka_unit_test(test_skip),
        cmocka_unit_test(test_many_workers),
        cmocka_unit_test(test_blocks_assembled),
        cmocka_unit_test(test_trace_one),
        cmocka_unit_test(test_cpu_backend),
        cmocka_unit_test(test_choose),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
