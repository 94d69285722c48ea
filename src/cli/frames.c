/* curray cli: the run over the frame stack (app.h). Every frame's files
 * are written atomically (c, r, d, b, f; info.txt's record last), and a
 * frame that fails part-way leaves none of them. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../base/fsutil.h"
#include "../output/fits.h"
#include "../output/output.h"
#include "../output/raypath.h"
#include "../output/types.h"
#include "../output/video.h"
#include "../render/mpi.h"
#include "app.h"

double cr_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int cr_has_type(const cr_run *run, char t)
{
    return cr_output_types_has(run->cli.output_type, t);
}

int cr_run_science(const cr_run *run)
{
    return cr_has_type(run, 'd') || cr_has_type(run, 'f') || cr_has_type(run, 's') ||
           cr_has_type(run, 'l');
}

int cr_frame_kept(const cr_run *run, int k)
{
    return run->resume.body && run->resume.body[k];
}

/* Progress of the whole run: frames finished plus the finished parts of the
 * frames in progress, as a number of frames. Caller holds run->lock. */
static double cr_run_work_done(const cr_run *run)
{
    double work = run->n_done;
    int k;
    for (k = 0; k < run->n_workers; k++)
        work += run->slot[k].frac;
    return work;
}

/* cr_stack_ops.progress: one line per worker with its frame's percentage
 * and the time left for the whole run, from the run's average speed so
 * far. Blocks of rows (an MPI run of one frame) print none. */
static void cr_progress(void *ctx, int worker, const cr_item *it, int rows_done, int rows_total)
{
    cr_run *run = ctx;
    double el = cr_now() - run->t_start, frac = (double)rows_done / rows_total, work;
    if (it->rows != run->cli.height)
        return;
    pthread_mutex_lock(&run->lock);
    run->slot[worker].frac = frac < 1.0 ? frac : 1.0;
    work = cr_run_work_done(run);
    pthread_mutex_unlock(&run->lock);
    if (rows_done >= rows_total)
        return;
    if (work > run->n_kept) /* frames kept by --resume took no time in this run */
        cr_log_progress(&run->log, "frame %d of %ld: %3.0f%%; run: %.0f s elapsed, about %.0f s "
                                   "left",
                        it->frame, run->cli.frames, 100.0 * frac, el,
                        el * ((double)run->cli.frames - work) / (work - run->n_kept));
    else
        cr_log_progress(&run->log, "frame %d of %ld: starting", it->frame, run->cli.frames);
}

/* cr_stack_ops.begin: the worker's frame in progress, none of it done yet
 * (it == NULL: it has none, after a failure). */
static void cr_begin(void *ctx, int worker, const cr_item *it)
{
    cr_run *run = ctx;
    pthread_mutex_lock(&run->lock);
    if (it)
        run->slot[worker].frame = it->frame;
    run->slot[worker].frac = 0.0;
    pthread_mutex_unlock(&run->lock);
}

/* cr_stack_ops.prepare: frame k of the scene, evaluated into the slot's
 * cr_frame_eval (which owns its spheres; made at the slot's first frame). */
static int cr_prepare_frame(void *ctx, int k, void **slot, const cr_frame **f, cr_err *err)
{
    cr_run *run = ctx;
    cr_frame_eval *e = *slot;
    if (!e && !(e = *slot = calloc(1, sizeof *e)))
        return cr_err_set(err, "out of memory");
    if (cr_frame_eval_at(e, &run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                         (int)run->cli.height, &run->ts, err))
        return -1;
    e->frame.science = cr_run_science(run);
    *f = &e->frame;
    return 0;
}

/* cr_stack_ops.release: a slot's cr_frame_eval. */
static void cr_release_frame(void *ctx, void *slot)
{
    (void)ctx;
    cr_frame_eval_free(slot);
    free(slot);
}

/* Remove the files of frame k already written, types among "crdbf": a frame
 * that fails part-way (a full disk) leaves no file. */
static void cr_remove_frame_files(const cr_run *run, int k, const char *types)
{
    char name[64], path[4096];
    for (; *types; types++) {
        if (cr_output_file_name(*types, k, name, sizeof name) == 0 &&
            cr_path_join(path, sizeof path, run->cli.output_dir, name) == 0)
            unlink(path);
    }
}

/* Write frame k's file of per-frame type t (types.h) from writer `slot`,
 * frame f traced into px, announced to the Ctrl-C handling (interrupt.h). */
static int cr_write_frame_file(cr_run *run, int slot, char t, int k, const cr_frame *f,
                               const cr_pixel *px, cr_err *err)
{
    const cr_output_type *type = cr_output_type_find(t);
    char name[64], note[512] = "";
    cr_frame_output o = {run->cli.output_dir, k, (int)run->cli.frames, f, px, &run->scene,
                         note, sizeof note};
    int rc;
    if (!type || !type->write || cr_output_file_name(t, k, name, sizeof name) != 0)
        return cr_err_set(err, "no frame file for output type '%c'", t);
    if (cr_interrupt_file_begin(&run->intr, slot, name))
        return cr_err_set(err, "interrupted");
    rc = type->write(&o, err);
    cr_interrupt_file_end(&run->intr, slot, rc == 0, 0);
    if (rc == 0 && note[0])
        cr_log_info(&run->log, "curray: warning: frame %d: %s", k, note);
    return rc;
}

/* Mark frame k finished with statistics st (traced on GPU `device`, or -1),
 * rewrite info.txt and print the frame's line. Returns 0, or -1 with err
 * set (the frame is then not finished). */
static int cr_finish_frame(cr_run *run, int slot, int device, int k, const cr_frame_stats *st,
                           cr_err *err)
{
    int rc = 0;
    pthread_mutex_lock(&run->lock);
    run->stats[k] = *st;
    run->stats[k].files = NULL; /* the caller's text, freed after this call */
    run->done[k] = 1;
    run->n_done++;
    run->slot[slot].frac = 0.0;
    if (!cr_has_type(run, 'i')) {
        cr_interrupt_frame_end(&run->intr, slot);
    } else if (cr_interrupt_file_begin(&run->intr, slot, "info.txt")) {
        rc = cr_err_set(err, "interrupted");
    } else {
        rc = cr_info_add_frame(&run->infotxt, st, err);
        cr_interrupt_file_end(&run->intr, slot, 0, rc == 0);
    }
    if (rc) {
        run->done[k] = 0;
        run->n_done--;
    } else {
        long long rays = st->rays > 0 ? st->rays : 1;
        char where[32] = "";
        if (device >= 0)
            snprintf(where, sizeof where, " on GPU %d", device);
        cr_log_info(&run->log,
                    "frame %d of %ld done%s in %.2f s: %.3g rays/s, %.1f steps/ray, "
                    "horizon %lld, disc %lld, sphere %lld, sky %lld, error %lld, limit %lld",
                    k, run->cli.frames, where, st->seconds,
                    (double)st->rays / (st->seconds > 0 ? st->seconds : 1e-9),
                    (double)st->steps / (double)rays, st->counts[CR_OUT_HORIZON],
                    st->counts[CR_OUT_DISC], st->counts[CR_OUT_SPHERE], st->counts[CR_OUT_SKY],
                    st->counts[CR_OUT_ERROR], st->counts[CR_OUT_LIMIT]);
        if (st->counts[CR_OUT_OUTSIDE] > 0) /* fisheye pixels beyond the image circle */
            cr_log_detail(&run->log, "frame %d: %lld pixels outside the fisheye's image circle "
                          "(black, not traced)", k, st->counts[CR_OUT_OUTSIDE]);
        if (st->counts[CR_OUT_ERROR] > 0)
            cr_log_info(&run->log, "curray: warning: frame %d: %lld of %lld rays %s", k,
                        st->counts[CR_OUT_ERROR], st->rays, CR_INFO_ERROR_ADVICE);
        if (st->counts[CR_OUT_LIMIT] > 0)
            cr_log_info(&run->log, "curray: warning: frame %d: %lld rays %s", k,
                        st->counts[CR_OUT_LIMIT], CR_INFO_LIMIT_ADVICE);
    }
    pthread_mutex_unlock(&run->lock);
    return rc;
}

/* cr_stack_ops.deliver: write the files of a traced frame (from the frame
 * traced, t->frame) and mark it finished. Returns 0, or -1 with err set (err->msg is "interrupted" after
 * a second Ctrl-C); a frame that fails leaves none of its files, and
 * info.txt lists only the frames whose files are all written. */
static int cr_output_frame(void *ctx, int slot, const cr_traced *t, cr_err *err)
{
    cr_run *run = ctx;
    const cr_frame *f = t->frame;
    int k = t->item.frame;
    cr_frame_stats st;
    char types[16], written[16] = "", *files = NULL;
    int n_written = 0, i;
    if (t->split)
        cr_log_detail(&run->log, "frame %d on GPU %d: %.4f s tracing, %.4f s copying pixels", k,
                      t->device, t->trace_s, t->copy_s);
    cr_output_frame_letters(run->cli.output_type, types, sizeof types);
    cr_frame_stats_compute(t->px, (long long)f->width * f->height, t->seconds, &st);
    st.frame = k;
    cr_interrupt_frame_begin(&run->intr, slot, k);
    for (i = 0; types[i]; i++) {
        if (cr_write_frame_file(run, slot, types[i], k, f, t->px, err))
            goto fail;
        written[n_written++] = types[i];
    }
    if (cr_has_type(run, 'i') && /* sizes and checksums for --resume */
        cr_frame_files_describe(run->cli.output_dir, k, written, &files, err))
        goto fail;
    st.files = files;
    if (cr_finish_frame(run, slot, t->device, k, &st, err) == 0) {
        free(files);
        return 0;
    }
fail:
    free(files);
    cr_remove_frame_files(run, k, written);
    cr_interrupt_frame_end(&run->intr, slot);
    cr_begin(run, slot, NULL);
    return -1;
}

static const cr_stack_ops cr_frame_ops = {NULL,        cr_prepare_frame, cr_output_frame,
                                          cr_begin,    cr_progress,      cr_release_frame};

/* Open a backend per worker: the chosen GPUs, or the CPU threads. */
static int cr_open_backends(cr_run *run, cr_err *err)
{
    int k;
    for (k = 0; k < run->n_workers; k++)
        if (cr_backend_open(&run->backends[k], run->use_cuda ? run->devices[k] : -1,
                            run->threads, (int)run->cli.width, (int)run->cli.height, err))
            return -1;
    return 0;
}

static void cr_close_backends(cr_run *run)
{
    int k;
    for (k = 0; k < run->n_workers; k++)
        cr_backend_close(&run->backends[k]);
}

/* Rank 0 (a run of one process is rank 0 of 1): the frame stack on this
 * process's backends, in threads, while this thread serves the other MPI
 * ranks from the same stack; then a frame assembled from their blocks of
 * rows is written. */
static void cr_run_stack(cr_run *run)
{
    cr_stack_ops ops = cr_frame_ops;
    double gather_s = 0.0, gather_bytes = 0.0;
    cr_err err;
    ops.ctx = run;
    if (cr_stack_init(&run->stack, &ops, (int)run->cli.frames, (int)run->cli.width,
                      (int)run->cli.height,
                      cr_stack_block_rows((int)run->cli.frames, (int)run->cli.height,
                                          run->mpi_size),
                      run->kept, &run->intr.count, run->backends, run->n_workers, &err) ||
        cr_open_backends(run, &err)) {
        cr_stack_fail(&run->stack, &err);
    } else {
        cr_stack_start(&run->stack);
        run->mpi_served = cr_mpi_dispatch_stack(&run->stack, run->n_workers, run->mpi_size,
                                                &gather_s, &gather_bytes) == 0;
        cr_stack_join(&run->stack);
        if (run->mpi_size > 1)
            cr_log_detail(&run->log, "MPI: %d ranks; rank 0 received %.1f MiB of pixels in %.3f s",
                          run->mpi_size, gather_bytes / (1 << 20), gather_s);
        cr_stack_finish(&run->stack);
    }
    cr_close_backends(run);
    run->failed = cr_stack_failed(&run->stack, &run->fail_err);
    cr_stack_free(&run->stack);
}

/* Render every frame; Ctrl-C handling is installed from the start of the
 * render to the end of the videos. */
int cr_render_frames(cr_run *run, cr_err *err)
{
    int k;
    run->stats = calloc((size_t)run->cli.frames, sizeof *run->stats);
    run->done = calloc((size_t)run->cli.frames, 1);
    run->kept = calloc((size_t)run->cli.frames, 1);
    if (!run->stats || !run->done || !run->kept)
        return cr_err_set(err, "out of memory for %ld frames", run->cli.frames);
    for (k = 0; k < run->cli.frames; k++)
        run->done[k] = run->kept[k] = (char)cr_frame_kept(run, k);
    run->n_done = run->n_kept;
    if (cr_interrupt_install(&run->intr, run->cli.output_dir, &run->log, err))
        return -1;
    pthread_mutex_init(&run->lock, NULL);
    run->t_start = cr_now();
    for (k = 0; k <= run->n_workers; k++) {
        run->slot[k].frame = 0;
        run->slot[k].frac = 0.0;
    }
    cr_run_stack(run);
    pthread_mutex_destroy(&run->lock);
    return 0; /* Ctrl-C handling stays for the videos; main removes it */
}

/* A rank > 0's whole run: trace what rank 0 hands out, on its GPU or its
 * CPU threads. */
int cr_mpi_rank_main(cr_run *run)
{
    cr_stack st;
    cr_stack_ops ops = cr_frame_ops;
    cr_err err;
    int rc;
    ops.ctx = run;
    rc = cr_stack_init(&st, &ops, (int)run->cli.frames, (int)run->cli.width,
                       (int)run->cli.height, (int)run->cli.height, NULL, NULL, NULL, 0, &err);
    if (rc == 0) {
        rc = cr_mpi_serve_stack(&st, run->use_cuda ? run->devices[0] : -1, run->threads, &err);
        cr_stack_free(&st);
    }
    if (rc) {
        cr_log_error(&run->log, "curray: MPI rank %d on %s: %s", run->mpi_rank, cr_mpi_host(),
                     err.msg);
        return CR_EXIT_ERROR;
    }
    return CR_EXIT_OK;
}

/* After every frame is finished: c.mp4 from the colour frames and, when
 * redshift frames were asked for too, r.mp4 from them (video.h); then, with
 * video.keep_frames false, the PNG frames they were made from are removed. */
int cr_make_videos(cr_run *run, cr_err *err)
{
    const char *prefix[2] = {"c", "r"};
    int i, k, padded, n = (int)run->cli.frames;
    char name[64], path[4096];
    double t0;
    for (i = 0; i < 2; i++) {
        if (i == 1 && !cr_has_type(run, 'r'))
            break;
        snprintf(name, sizeof name, "%s.mp4", prefix[i]);
        t0 = cr_now();
        if (cr_interrupt_file_begin(&run->intr, 0, name)) /* a second Ctrl-C */
            return cr_err_set(err, "interrupted");
        k = cr_video_from_pngs(run->cli.output_dir, prefix[i], n, run->cfg.video_fps, name,
                               &padded, &run->intr.count, err);
        cr_interrupt_file_end(&run->intr, 0, 0, 0);
        if (k)
            return -1;
        cr_log_info(&run->log, "video %s: %d frame%s at %d fps, H.264 in %.2f s%s", name, n,
                    n > 1 ? "s" : "", run->cfg.video_fps, cr_now() - t0,
                    padded ? " (the odd frame size is padded to even by repeating the last "
                             "row or column)"
                           : "");
        for (k = 0; !run->cfg.video_keep_frames && k < n; k++) {
            snprintf(name, sizeof name, "%s_%d.png", prefix[i], k);
            if (cr_path_join(path, sizeof path, run->cli.output_dir, name) == 0)
                unlink(path);
        }
    }
    return 0;
}

/* The last line of the run, and its exit status. */
int cr_report(cr_run *run)
{
    if (atomic_load(&run->intr.count) > 0) {
        cr_log_error(&run->log, "curray: interrupted; %d of %ld frames finished and kept in %s%s",
                     run->n_done, run->cli.frames, run->cli.output_dir,
                     run->mpi_size > 1        ? ""
                     : cr_has_type(run, 'i') ? "; the same command with --resume renders the rest"
                                             : "; add i to -t (info.txt) to make a run resumable");
        if (run->mpi_size > 1)
            cr_log_error(&run->log, "curray: an MPI run stops when mpirun ends it: a rank died or "
                                    "the job was cancelled (mpirun's message says which rank); "
                                    "the same command with --resume renders the rest");
        return CR_EXIT_INTERRUPTED;
    }
    if (run->failed) {
        cr_log_error(&run->log, "curray: %s", run->fail_err.msg);
        if (run->n_done)
            cr_log_error(&run->log, "curray: %d of %ld frames were finished and kept in %s",
                         run->n_done, run->cli.frames, run->cli.output_dir);
        return CR_EXIT_ERROR;
    }
    cr_log_info(&run->log, "done: %ld frame%s in %.2f s, outputs in %s", run->cli.frames,
                run->cli.frames > 1 ? "s" : "", cr_now() - run->t_start, run->cli.output_dir);
    return CR_EXIT_OK;
}

/* --trace I,J: the path of pixel (I, J)'s ray in each frame k, traced on the
 * CPU by the image's own loop (raypath.h) and written atomically to
 * trace_<I>_<J>_<k>.csv; no image. Returns the exit status. */
int cr_trace_paths(cr_run *run)
{
    cr_frame_eval e = {0};
    cr_err err;
    int k;
    for (k = 0; k < run->cli.frames; k++) {
        cr_raypath rp;
        char name[96];
        int i = (int)run->cli.trace_i, j = (int)run->cli.trace_j;
        snprintf(name, sizeof name, "trace_%d_%d_%d.csv", i, j, k);
        if (cr_frame_eval_at(&e, &run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                             (int)run->cli.height, &run->ts, &err))
            goto fail;
        e.frame.science = 1; /* the path and its hit, read for their values */
        if (cr_raypath_trace(&e.frame, i, j, &rp, &err))
            goto fail;
        if (cr_raypath_write_csv(run->cli.output_dir, name, &rp, &err)) {
            cr_raypath_free(&rp);
            goto fail;
        }
        if (rp.untraced)
            cr_log_info(&run->log,
                        "frame %d: pixel (%d, %d): %s, never inside the scene radius r = %g "
                        "(the image takes it as sky untraced); its path traced to infinity in "
                        "%u steps, %ld points in %s",
                        k, i, j, cr_outcome_name(rp.px.outcome), 1.0 / e.frame.w_sky *
                            cr_anim_at(run->scene.m, k, (int)run->cli.frames),
                        rp.path_steps, rp.n, name);
        else
            cr_log_info(&run->log, "frame %d: pixel (%d, %d): %s after %u steps, %ld points in %s",
                        k, i, j, cr_outcome_name(rp.px.outcome), rp.px.steps, rp.n, name);
        cr_raypath_free(&rp);
    }
    cr_frame_eval_free(&e);
    return CR_EXIT_OK;
fail:
    cr_log_error(&run->log, "curray: %s", err.msg);
    cr_frame_eval_free(&e);
    return CR_EXIT_ERROR;
}
