/* curray cli: spreading a run over MPI ranks (mpi.h). */
#include "mpi.h"

#include <stdatomic.h>
#include <string.h>

#ifndef CURRAY_MPI

void cr_mpi_init(int *argc, char ***argv, int *rank, int *size, int *local_rank,
                 int *local_size)
{
    (void)argc, (void)argv;
    *rank = *local_rank = 0;
    *size = *local_size = 1;
}

void cr_mpi_finalize(void) {}

void cr_mpi_abort(int code)
{
    (void)code;
}

int cr_mpi_all_ok(int ok)
{
    return ok != 0;
}

const char *cr_mpi_host(void)
{
    return "localhost";
}

int cr_mpi_dispatch(const cr_mpi_ops *ops, int size, double *gather_s, double *gather_bytes)
{
    (void)ops, (void)size;
    *gather_s = *gather_bytes = 0.0;
    return 0;
}

int cr_mpi_serve(int width, cr_mpi_render_fn render, void *ctx, cr_err *err)
{
    (void)width, (void)render, (void)ctx;
    return cr_err_set(err, "this curray was built without MPI");
}

#else

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { CR_TAG_RESULT = 1, CR_TAG_ASSIGN, CR_TAG_PIXELS, CR_TAG_ERROR };
#define CR_MPI_PIECE ((size_t)1 << 30) /* bytes per message, below INT_MAX */

static char cr_host[MPI_MAX_PROCESSOR_NAME + 1] = "?";

void cr_mpi_init(int *argc, char ***argv, int *rank, int *size, int *local_rank,
                 int *local_size)
{
    MPI_Comm node;
    int provided, len = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    /* the ranks that share this node's memory, numbered in world order */
    *local_rank = 0;
    *local_size = 1;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, *rank, MPI_INFO_NULL, &node) ==
        MPI_SUCCESS) {
        MPI_Comm_rank(node, local_rank);
        MPI_Comm_size(node, local_size);
        MPI_Comm_free(&node);
    }
    if (MPI_Get_processor_name(cr_host, &len) != MPI_SUCCESS)
        strcpy(cr_host, "?");
}

void cr_mpi_finalize(void)
{
    MPI_Finalize();
}

void cr_mpi_abort(int code)
{
    MPI_Abort(MPI_COMM_WORLD, code);
}

int cr_mpi_all_ok(int ok)
{
    int all = 0;
    ok = ok != 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    return all;
}

const char *cr_mpi_host(void)
{
    return cr_host;
}

static void cr_send_big(const void *buf, size_t n, int dest)
{
    const char *p = buf;
    while (n > 0) {
        size_t m = n < CR_MPI_PIECE ? n : CR_MPI_PIECE;
        MPI_Send(p, (int)m, MPI_BYTE, dest, CR_TAG_PIXELS, MPI_COMM_WORLD);
        p += m;
        n -= m;
    }
}

static void cr_recv_big(void *buf, size_t n, int src)
{
    char *p = buf;
    while (n > 0) {
        size_t m = n < CR_MPI_PIECE ? n : CR_MPI_PIECE;
        MPI_Recv(p, (int)m, MPI_BYTE, src, CR_TAG_PIXELS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        p += m;
        n -= m;
    }
}

static double cr_mpi_now(void)
{
    return MPI_Wtime();
}

/* A buffer of at least n pixels. */
static cr_pixel *cr_grow(cr_pixel **buf, size_t *cap, size_t n)
{
    if (n > *cap) {
        cr_pixel *p = realloc(*buf, n * sizeof *p);
        if (!p)
            return NULL;
        *buf = p;
        *cap = n;
    }
    return *buf;
}

int cr_mpi_dispatch(const cr_mpi_ops *ops, int size, double *gather_s, double *gather_bytes)
{
    const struct timespec nap = {0, 1000000}; /* 1 ms between polls */
    cr_pixel *buf = NULL;
    size_t cap = 0;
    int active = size - 1, delivering = 1;
    *gather_s = *gather_bytes = 0.0;
    while (active > 0) {
        MPI_Status st;
        long long hdr[4];
        int flag = 0, src, a[3] = {-1, 0, 0};
        if (ops->stop(ops->ctx)) {
            free(buf);
            return -1;
        }
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) {
            nanosleep(&nap, NULL);
            continue;
        }
        src = st.MPI_SOURCE;
        if (st.MPI_TAG == CR_TAG_ERROR) {
            char msg[CR_ERR_MSG];
            int n = 0;
            MPI_Get_count(&st, MPI_CHAR, &n);
            if (n < 0 || n >= (int)sizeof msg)
                n = (int)sizeof msg - 1;
            MPI_Recv(msg, n, MPI_CHAR, src, CR_TAG_ERROR, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            msg[n] = '\0';
            ops->failed(ops->ctx, src, msg);
            active--;
            continue;
        }
        MPI_Recv(hdr, 4, MPI_LONG_LONG, src, CR_TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (hdr[2] > 0) {
            size_t n = (size_t)hdr[2] * (size_t)ops->width;
            double t0 = cr_mpi_now();
            cr_err err;
            if (!cr_grow(&buf, &cap, n)) {
                ops->failed(ops->ctx, 0, "out of memory for a rank's pixels");
                free(buf);
                return -1;
            }
            cr_recv_big(buf, n * sizeof *buf, src);
            *gather_s += cr_mpi_now() - t0;
            *gather_bytes += (double)(n * sizeof *buf);
            if (delivering && ops->deliver(ops->ctx, src, (int)hdr[0], (int)hdr[1], (int)hdr[2],
                                           buf, (double)hdr[3] * 1e-9, &err))
                delivering = 0;
        }
        if (!delivering || ops->next(ops->ctx, &a[0], &a[1], &a[2]) != 0)
            a[0] = -1;
        MPI_Send(a, 3, MPI_INT, src, CR_TAG_ASSIGN, MPI_COMM_WORLD);
        if (a[0] < 0)
            active--;
    }
    free(buf);
    return 0;
}

int cr_mpi_serve(int width, cr_mpi_render_fn render, void *ctx, cr_err *err)
{
    long long hdr[4] = {-1, 0, 0, 0};
    cr_pixel *buf = NULL;
    size_t cap = 0;
    for (;;) {
        int a[3];
        double seconds = 0.0;
        MPI_Send(hdr, 4, MPI_LONG_LONG, 0, CR_TAG_RESULT, MPI_COMM_WORLD);
        if (hdr[2] > 0)
            cr_send_big(buf, (size_t)hdr[2] * (size_t)width * sizeof *buf, 0);
        MPI_Recv(a, 3, MPI_INT, 0, CR_TAG_ASSIGN, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (a[0] < 0)
            break;
        if (!cr_grow(&buf, &cap, (size_t)a[2] * (size_t)width))
            cr_err_set(err, "out of memory for %d rows of %d pixels", a[2], width);
        if (!buf || cap < (size_t)a[2] * (size_t)width ||
            render(ctx, a[0], a[1], a[2], buf, &seconds, err)) {
            char msg[CR_ERR_MSG];
            snprintf(msg, sizeof msg, "%s", err->msg);
            MPI_Send(msg, (int)strlen(msg), MPI_CHAR, 0, CR_TAG_ERROR, MPI_COMM_WORLD);
            free(buf);
            return -1;
        }
        hdr[0] = a[0];
        hdr[1] = a[1];
        hdr[2] = a[2];
        hdr[3] = (long long)(seconds * 1e9);
    }
    free(buf);
    return 0;
}

#endif

/* ---- the frame stack's source and sink (both builds) -------------------- */

typedef struct cr_mpi_stack {
    cr_stack *st;
    int writer;
    cr_backend b; /* a rank > 0's backend, opened at its first item */
    int device, threads, opened;
} cr_mpi_stack;

static int cr_mpi_stack_next(void *ctx, int *k, int *row0, int *rows)
{
    cr_mpi_stack *m = ctx;
    cr_item it;
    if (cr_stack_take(m->st, &it))
        return -1;
    *k = it.frame;
    *row0 = it.row0;
    *rows = it.rows;
    return 0;
}

static int cr_mpi_stack_deliver(void *ctx, int rank, int k, int row0, int rows,
                                const cr_pixel *px, double seconds, cr_err *err)
{
    cr_mpi_stack *m = ctx;
    cr_traced t;
    (void)rank;
    memset(&t, 0, sizeof t);
    t.item.frame = k;
    t.item.row0 = row0;
    t.item.rows = rows;
    t.px = px;
    t.seconds = seconds;
    t.device = -1;
    return cr_stack_deliver(m->st, m->writer, &t, err);
}

static void cr_mpi_stack_failed(void *ctx, int rank, const char *msg)
{
    cr_err e;
    cr_err_set(&e, "MPI rank %d: %s", rank, msg);
    cr_stack_fail(((cr_mpi_stack *)ctx)->st, &e);
}

static int cr_mpi_stack_stop(void *ctx)
{
    const cr_stack *st = ((cr_mpi_stack *)ctx)->st;
    return st->cancel && atomic_load(st->cancel) != 0;
}

int cr_mpi_dispatch_stack(cr_stack *st, int writer, int size, double *gather_s,
                          double *gather_bytes)
{
    cr_mpi_stack m;
    cr_mpi_ops ops;
    memset(&m, 0, sizeof m);
    m.st = st;
    m.writer = writer;
    ops.ctx = &m;
    ops.width = st->width;
    ops.next = cr_mpi_stack_next;
    ops.deliver = cr_mpi_stack_deliver;
    ops.failed = cr_mpi_stack_failed;
    ops.stop = cr_mpi_stack_stop;
    return cr_mpi_dispatch(&ops, size, gather_s, gather_bytes);
}

static int cr_mpi_stack_render(void *ctx, int k, int row0, int rows, cr_pixel *px,
                               double *seconds, cr_err *err)
{
    cr_mpi_stack *m = ctx;
    cr_item it;
    if (!m->opened) {
        if (cr_backend_open(&m->b, m->device, m->threads, m->st->width, m->st->height, err))
            return -1;
        m->opened = 1;
    }
    it.frame = k;
    it.row0 = row0;
    it.rows = rows;
    return cr_stack_trace(m->st, &m->b, &it, px, seconds, err);
}

int cr_mpi_serve_stack(cr_stack *st, int device, int threads, cr_err *err)
{
    cr_mpi_stack m;
    int rc;
    memset(&m, 0, sizeof m);
    m.st = st;
    m.device = device;
    m.threads = threads;
    rc = cr_mpi_serve(st->width, cr_mpi_stack_render, &m, err);
    cr_backend_close(&m.b);
    return rc;
}
