/* curray render: the frame stack (6.2): a run's work items traced on its
 * backends, with pipelining, progress and the run's first failure.
 *
 * A work item is the rows [row0, row0 + rows) of frame k. The plan hands
 * them out in order from one atomic counter: whole frames, or, for a run of
 * one frame spread over several MPI ranks, blocks of rows that the stack
 * assembles into the frame. Each backend is driven by one worker (a thread
 * of its own, or the calling thread): it takes an item, has the caller
 * prepare the frame (prepare) and launches it; then, for each item, waits
 * for its pixels, takes and launches the next item, and only then hands the
 * pixels to the sink (deliver), so that a backend traces the next frame
 * while the last is written. The first failure is kept (later ones are its
 * consequences) and stops the handing out of items, as does the cancel
 * flag; a worker stops at its first failure.
 *
 * MPI (mpi.h) is another source and sink of the same items: rank 0 hands
 * items out with cr_stack_take and hands the other ranks' pixels to
 * cr_stack_deliver; a run of one process is the same run with no other
 * rank. Nothing here prints or exits. */
#ifndef CR_RENDER_RUN_H
#define CR_RENDER_RUN_H

#include <pthread.h>
#include <stdatomic.h>

#include "../base/error.h"
#include "../core/defs.h"
#include "backend.h"

/* Frames per run and backends per process, at most. */
#define CR_STACK_MAX_WORKERS 64

typedef struct cr_item {
    int frame;      /* k, from 0 */
    int row0, rows; /* rows [row0, row0 + rows) of the frame */
} cr_item;

/* An item's pixels, handed to the sink. */
typedef struct cr_traced {
    cr_item item;
    const cr_frame *frame; /* the prepared frame the item was traced from; NULL in what
                            * cr_stack_deliver is given (the stack prepares it again) */
    const cr_pixel *px;    /* item.rows * width pixels, row-major */
    double seconds;     /* the backend's time for the item; for a frame assembled from
                         * blocks, the wall time from the first block taken to the last in */
    int device;         /* the CUDA device of the worker's backend, or -1 (the CPU, or
                         * another MPI rank) */
    int split;          /* 1: trace_s and copy_s split seconds (cr_backend_times) */
    double trace_s, copy_s;
} cr_traced;

/* The caller's part. Every function is called from worker threads (and
 * from the thread that calls cr_stack_deliver); worker is the index of the
 * backend (0 .. n_backends - 1) or what cr_stack_deliver was given. */
typedef struct cr_stack_ops {
    void *ctx;
    /* Frame k, evaluated into a slot of the caller's: *slot is what the
     * caller keeps there (NULL at a slot's first prepare; the caller puts
     * there what owns the frame and its spheres, e.g. a cr_frame_eval of
     * input/scene.h, and reuses it for the slot's next frame); *f is set to
     * the frame, which stays valid until the slot's next prepare or its
     * release. 0, or -1 with err set. */
    int (*prepare)(void *ctx, int k, void **slot, const cr_frame **f, cr_err *err);
    /* A whole frame's pixels: t->item is {k, 0, height}, t->frame the frame
     * traced. 0, or -1 with err set (the run then fails with err). */
    int (*deliver)(void *ctx, int worker, const cr_traced *t, cr_err *err);
    /* The worker begins waiting for item it (may be NULL: the worker has
     * no item in progress any more, after a failure). May be NULL. */
    void (*begin)(void *ctx, int worker, const cr_item *it);
    /* Progress of the worker's item in progress (cr_progress_fn). May be
     * NULL. */
    void (*progress)(void *ctx, int worker, const cr_item *it, int rows_done, int rows_total);
    /* Free what prepare left in a slot (called once for each slot whose
     * *slot prepare set, when the slot is done with). May be NULL. */
    void (*release)(void *ctx, void *slot);
} cr_stack_ops;

typedef struct cr_stack {
    /* set by cr_stack_init */
    cr_stack_ops ops;
    int frames, width, height; /* the run's frames, each width x height */
    int block_rows;            /* rows per item; height: whole frames */
    const char *skip;          /* skip[k] != 0: frame k is not traced (NULL: none) */
    atomic_int *cancel;        /* non-zero: stop (may be NULL) */
    cr_backend *backends;
    int n_backends;
    /* state */
    atomic_int next_item;
    pthread_mutex_t lock; /* guards failed, fail_err and the assembly */
    int failed;
    cr_err fail_err;
    pthread_t tid[CR_STACK_MAX_WORKERS];
    int started; /* worker threads running */
    cr_pixel *assembly;    /* the frame assembled from blocks of rows, or NULL */
    int assembled_rows;
    double t_first;        /* when its first block was taken */
} cr_stack;

/* Rows per item: the whole height, except for a run of one frame over
 * ranks > 1 MPI ranks, which is cut into about 16 blocks per rank so that
 * the slow rows near the hole even out. */
int cr_stack_block_rows(int frames, int height, int ranks);

/* Set up a run of `frames` frames of width x height over backends[0 ..
 * n_backends) (n_backends may be 0: items then only go out through
 * cr_stack_take), items of block_rows rows (cr_stack_block_rows; blocks
 * shorter than the height only with frames == 1). Returns 0, or -1 with
 * err set (out of memory for the assembled frame, too many backends). */
int cr_stack_init(cr_stack *st, const cr_stack_ops *ops, int frames, int width, int height,
                  int block_rows, const char *skip, atomic_int *cancel, cr_backend *backends,
                  int n_backends, cr_err *err);
void cr_stack_free(cr_stack *st);

/* Run one worker per backend: in threads (cr_stack_start then
 * cr_stack_join), or all of cr_stack_run in the calling thread when there
 * is one backend. cr_stack_start falls back to the calling thread when no
 * thread can be started. */
void cr_stack_start(cr_stack *st);
void cr_stack_join(cr_stack *st);
void cr_stack_run(cr_stack *st);

/* After cr_stack_join: the frame assembled from blocks, handed to the sink
 * (as worker 0) when every row came in and the run neither failed nor was
 * cancelled. A no-op for a run of whole frames. */
void cr_stack_finish(cr_stack *st);

/* The next item: 0, or -1 when none is left, the run failed or the cancel
 * flag is set. Skipped frames are passed over. */
int cr_stack_take(cr_stack *st, cr_item *it);

/* An item's pixels into the run: a whole frame goes to the sink (with
 * t->frame NULL, the frame is prepared here again), a block into the
 * assembled frame. 0, or -1 with err set (the run's failure is recorded
 * too). */
int cr_stack_deliver(cr_stack *st, int worker, const cr_traced *t, cr_err *err);

/* Record a failure: the first one is the run's. */
void cr_stack_fail(cr_stack *st, const cr_err *err);

/* 1 when the run failed; *err (may be NULL) receives the first failure. */
int cr_stack_failed(cr_stack *st, cr_err *err);

/* One item traced on backend b without pipelining, into out (it->rows *
 * width pixels): prepare, launch, wait (no progress; cancel is the
 * stack's). *seconds: the backend's time. For an MPI rank > 0. Returns 0,
 * or -1 with err set. */
int cr_stack_trace(cr_stack *st, cr_backend *b, const cr_item *it, cr_pixel *out,
                   double *seconds, cr_err *err);

#endif
