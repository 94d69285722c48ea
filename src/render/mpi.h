/* curray cli: spreading a run over MPI ranks (curray_mpi only).
 *
 * The work is a list of items, each a block of rows of one frame: a whole
 * frame per item when the run has several frames, a block of rows of frame
 * 0 when it has one. Rank 0 hands items out one at a time to whichever rank
 * asks (dynamic, so that slow rows or frames do not stall the others),
 * renders items itself in its own threads meanwhile, receives every rank's
 * pixels and writes every output; the other ranks only trace.
 *
 * Messages (MPI_COMM_WORLD): a rank > 0 sends RESULT (an empty result the
 * first time: a request), rank 0 answers ASSIGN {k, row0, rows} (k < 0:
 * stop); a result is the header {k, row0, rows, nanoseconds} followed by
 * the pixels in pieces of at most 1 GiB, or ERROR with a message.
 *
 * Every MPI call is made by the main thread of its rank (MPI_THREAD_FUNNELED).
 * Without CURRAY_MPI the functions are stubs for a run of one rank. */
#ifndef CR_CLI_MPI_H
#define CR_CLI_MPI_H

#include <stddef.h>

#include "../core/defs.h"
#include "../base/error.h"
#include "run.h"

/* MPI_Init (threads: funnelled); rank and size of MPI_COMM_WORLD, and the
 * rank on this node and the number of ranks there (MPI_Comm_split_type
 * with MPI_COMM_TYPE_SHARED; for choosing GPUs, cr_gpu_for_local_rank).
 * Without MPI: rank 0 of 1, local rank 0 of 1. */
void cr_mpi_init(int *argc, char ***argv, int *rank, int *size, int *local_rank,
                 int *local_size);
void cr_mpi_finalize(void);
/* End every rank at once (after an interrupt or a failure on rank 0). */
void cr_mpi_abort(int code);
/* 1 when every rank passes ok != 0 (a collective call). */
int cr_mpi_all_ok(int ok);
/* The host name of this rank (for messages). */
const char *cr_mpi_host(void);

/* Rank 0's side. next: the next item for a rank (0, or -1 when there is
 * none left); deliver: rank r's pixels of an item (0, or -1 with err: the
 * run failed, items are no longer handed out); failed: a rank reported an
 * error; stop: 1 when rank 0 stops at once (Ctrl-C) without waiting for the
 * other ranks. */
typedef struct cr_mpi_ops {
    void *ctx;
    int width;
    int (*next)(void *ctx, int *k, int *row0, int *rows);
    int (*deliver)(void *ctx, int rank, int k, int row0, int rows, const cr_pixel *px,
                   double seconds, cr_err *err);
    void (*failed)(void *ctx, int rank, const char *msg);
    int (*stop)(void *ctx);
} cr_mpi_ops;

/* Serve the other ranks until each one has been told to stop (or stop()).
 * *gather_s: seconds spent receiving pixels, *gather_bytes their size.
 * Returns 0, or -1 when stopped early. */
int cr_mpi_dispatch(const cr_mpi_ops *ops, int size, double *gather_s, double *gather_bytes);

/* A rank > 0's side: ask for items and render each with render() into a
 * buffer of rows x width pixels, until told to stop. A failure is sent to
 * rank 0 and ends the loop (-1). */
typedef int (*cr_mpi_render_fn)(void *ctx, int k, int row0, int rows, cr_pixel *px,
                                double *seconds, cr_err *err);
int cr_mpi_serve(int width, cr_mpi_render_fn render, void *ctx, cr_err *err);

/* MPI as a source and sink of the frame stack's items (run.h). Rank 0:
 * cr_mpi_dispatch over st: the items of cr_stack_take go to the other
 * ranks, their pixels to cr_stack_deliver as worker `writer`, a rank's
 * failure becomes the run's ("MPI rank R: <its message>"), and the
 * stack's cancel flag stops at once. With size 1 it returns at once. */
int cr_mpi_dispatch_stack(cr_stack *st, int writer, int size, double *gather_s,
                          double *gather_bytes);

/* A rank > 0: cr_mpi_serve, each item traced with cr_stack_trace(st) on
 * a backend (device, threads; backend.h) opened at the first item and
 * closed at the end. */
int cr_mpi_serve_stack(cr_stack *st, int device, int threads, cr_err *err);

#endif
