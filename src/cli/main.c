/* curray: command-line front end.
 *
 * Reads the command line, the system configuration and the scene; checks
 * every frame before anything is rendered; asks to proceed (E.1); renders the
 * stack of frames on the CPU or on one host thread per enabled GPU (6.2);
 * writes c_<k>.png, r_<k>.png, d_<k>.csv and info.txt atomically, and the log
 * in <output folder>/log/. Frames are counted from 0 everywhere: file names,
 * console, log, info.txt and messages.
 *
 * Exit status: 0 done; 1 a run-time error (input, output, device); 2 a usage
 * error; 130 interrupted (Ctrl-C or SIGTERM: finished frames are kept, the
 * frame in progress leaves no file; a second Ctrl-C stops at once, still
 * without partial files); a crash dies by its signal after writing
 * <output folder>/log/crash-<time>-<pid>.log (crash.h).
 */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../render/cpu.h"
#include "../render/gpu.h"
#include "../base/memcheck.h"
#include "../output/fits.h"
#include "../base/fsutil.h"
#include "../base/log.h"
#include "../output/output.h"
#include "../output/raypath.h"
#include "../input/scene.h"
#include "../input/sysconfig.h"
#include "../output/video.h"
#include "cli.h"
#include "crash.h"
#include "example.h"
#include "interrupt.h"
#include "../render/mpi.h"
#include "lock.h"
#include "resume.h"

#define CR_EXIT_OK 0
#define CR_EXIT_ERROR 1
#define CR_EXIT_USAGE 2
#define CR_EXIT_INTERRUPTED 130

static double cr_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

struct cr_run;

/* One renderer: the CPU backend, or one GPU. */
typedef struct cr_worker {
    struct cr_run *run;
    int slot;   /* index among the workers (cr_interrupt slot) */
    int device; /* GPU number, or -1 for the CPU */
    int frame;  /* frame in progress, for progress lines */
    double frac; /* finished part of that frame, 0..1; guarded by run->lock */
    pthread_t tid;
} cr_worker;

/* Shared state of one run; workers take frames from next_frame (the frame
 * stack of 6.2). */
typedef struct cr_run {
    int argc;
    char **argv;
    cr_cli cli;
    cr_sysconfig cfg;
    cr_scene scene;
    cr_log log;
    int log_open;
    cr_run_info info;
    char hash[17];    /* the run hash (resume.h) */
    char *stale;      /* stale frame files in the output folder, or NULL */
    cr_resume resume; /* --resume: the frames kept from the earlier run */
    cr_dirlock dirlock; /* the output folder, this run's alone (lock.h) */
    int n_kept;       /* how many */
    char frame_types[16]; /* the per-frame types written (cr_output_frame_letters) */
    cr_frame ends[2];     /* frames 0 and n-1 (cr_check_frames), for info.txt */
    /* MPI (mpi.h; curray_mpi): this rank and the number of ranks (0 of 1
     * without MPI); a one-frame run spread by rows: its frame, the pixels
     * gathered on rank 0, the next block of rows and the rows finished */
    int mpi_rank, mpi_size;
    int mpi_local_rank, mpi_local_size; /* on this node (cr_gpu_for_local_rank) */
    int mpi_served;   /* rank 0 served every other rank to the end */
    cr_gpu_session *rank_gs; /* a rank > 0's GPU session, made at its first item */
    double gather_s, gather_bytes;
    cr_frame rows_frame;
    cr_sphere *rows_spheres;
    cr_pixel *rows_px;
    int chunk_rows;
    atomic_int next_chunk, rows_done;
    cr_info infotxt; /* info.txt: begun before the first frame, ended after the last */
    cr_trace_settings ts;
    char backend_name[64];
    char *settings; /* the run's settings as text, for the crash report */
    int use_cuda;
    int threads; /* CPU threads in use (--threads, else cpu.threads, else all cores) */
    int n_workers;
    int devices[CR_MAX_GPUS];
    cr_worker workers[CR_MAX_GPUS];
    cr_interrupt intr; /* Ctrl-C; intr.count is the run's cancel flag */
    pthread_mutex_t lock;
    atomic_int next_frame;
    cr_frame_stats *stats; /* per frame */
    char *done;            /* per frame */
    int n_done;
    int failed;
    cr_err fail_err;
    double t_start;
} cr_run;

/* Does the run write output type t? A video (v) is made from the colour
 * frames, so v implies c. */
static int cr_has_type(const cr_run *run, char t)
{
    return cr_output_types_has(run->cli.output_type, t);
}

/* Progress of the whole run: frames finished plus the finished parts of the
 * frames in progress, as a number of frames. Caller holds run->lock. */
static double cr_run_work_done(const cr_run *run)
{
    double work = run->n_done;
    int k;
    for (k = 0; k < run->n_workers; k++)
        work += run->workers[k].frac;
    return work;
}

/* cr_progress_fn: one line per worker with its frame's percentage and the
 * time left for the whole run, from the run's average speed so far. */
static void cr_progress(void *ctx, int rows_done, int rows_total)
{
    cr_worker *w = ctx;
    cr_run *run = w->run;
    double el = cr_now() - run->t_start, frac = (double)rows_done / rows_total, work;
    pthread_mutex_lock(&run->lock);
    w->frac = frac < 1.0 ? frac : 1.0;
    work = cr_run_work_done(run);
    pthread_mutex_unlock(&run->lock);
    if (rows_done >= rows_total)
        return;
    if (work > run->n_kept) /* frames kept by --resume took no time in this run */
        cr_log_progress(&run->log, "frame %d of %ld: %3.0f%%; run: %.0f s elapsed, about %.0f s "
                                   "left",
                        w->frame, run->cli.frames, 100.0 * frac, el,
                        el * ((double)run->cli.frames - work) / (work - run->n_kept));
    else
        cr_log_progress(&run->log, "frame %d of %ld: starting", w->frame, run->cli.frames);
}

/* cr_gpu_cancel_fn */
static int cr_cancelled(void *ctx)
{
    cr_worker *w = ctx;
    return cr_interrupt_requested(&w->run->intr);
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

/* Write frame k's file of per-frame type t (types.h), frame f traced into
 * px, announced to the Ctrl-C handling (interrupt.h). */
static int cr_write_frame_file(cr_worker *w, char t, int k, const cr_frame *f,
                               const cr_pixel *px, cr_err *err)
{
    cr_run *run = w->run;
    const cr_output_type *type = cr_output_type_find(t);
    cr_frame_output o = {run->cli.output_dir, k, (int)run->cli.frames, f, px, &run->scene};
    char name[64];
    int rc;
    if (!type || !type->write || cr_output_file_name(t, k, name, sizeof name) != 0)
        return cr_err_set(err, "no frame file for output type '%c'", t);
    if (cr_interrupt_file_begin(&run->intr, w->slot, name))
        return cr_err_set(err, "interrupted");
    rc = type->write(&o, err);
    cr_interrupt_file_end(&run->intr, w->slot, rc == 0, 0);
    return rc;
}

/* Mark frame k finished with statistics st, rewrite info.txt and print the
 * frame's line. Returns 0, or -1 with err set (the frame is then not
 * finished). */
static int cr_finish_frame(cr_worker *w, int k, const cr_frame_stats *st, cr_err *err)
{
    cr_run *run = w->run;
    int rc = 0;
    pthread_mutex_lock(&run->lock);
    run->stats[k] = *st;
    run->stats[k].files = NULL; /* the caller's text, freed after this call */
    run->done[k] = 1;
    run->n_done++;
    w->frac = 0.0;
    if (!cr_has_type(run, 'i')) {
        cr_interrupt_frame_end(&run->intr, w->slot);
    } else if (cr_interrupt_file_begin(&run->intr, w->slot, "info.txt")) {
        rc = cr_err_set(err, "interrupted");
    } else {
        rc = cr_info_add_frame(&run->infotxt, st, err);
        cr_interrupt_file_end(&run->intr, w->slot, 0, rc == 0);
    }
    if (rc) {
        run->done[k] = 0;
        run->n_done--;
    } else {
        long long rays = st->rays > 0 ? st->rays : 1;
        char where[32] = "";
        if (w->device >= 0)
            snprintf(where, sizeof where, " on GPU %d", w->device);
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
        if (st->counts[CR_OUT_LIMIT] > 0)
            cr_log_info(&run->log, "curray: warning: frame %d: %lld rays %s", k,
                        st->counts[CR_OUT_LIMIT], CR_INFO_LIMIT_ADVICE);
    }
    pthread_mutex_unlock(&run->lock);
    return rc;
}

/* Make frame k the worker's frame in progress, none of it done yet. */
static void cr_worker_frame(cr_worker *w, int k)
{
    pthread_mutex_lock(&w->run->lock);
    w->frame = k;
    w->frac = 0.0;
    pthread_mutex_unlock(&w->run->lock);
}

/* The worker has no part of a frame done (it failed or stopped). */
static void cr_worker_idle(cr_worker *w)
{
    pthread_mutex_lock(&w->run->lock);
    w->frac = 0.0;
    pthread_mutex_unlock(&w->run->lock);
}

/* Write the files of frame k, the frame f traced into px in `seconds`, and
 * mark it finished. Returns 0, or -1 with err set (err->msg is
 * "interrupted" after a second Ctrl-C); a frame that fails leaves none of
 * its files, and info.txt lists only the frames whose files are all
 * written. */
static int cr_output_frame(cr_worker *w, int k, const cr_frame *f, const cr_pixel *px,
                           double seconds, cr_err *err)
{
    cr_run *run = w->run;
    cr_frame_stats st;
    char types[16], written[16] = "", *files = NULL;
    int n_written = 0, i;
    cr_output_frame_letters(run->cli.output_type, types, sizeof types);
    cr_frame_stats_compute(px, (long long)f->width * f->height, seconds, &st);
    st.frame = k;
    cr_interrupt_frame_begin(&run->intr, w->slot, k);
    for (i = 0; types[i]; i++) {
        if (cr_write_frame_file(w, types[i], k, f, px, err))
            goto fail;
        written[n_written++] = types[i];
    }
    if (cr_has_type(run, 'i') && /* sizes and checksums for --resume */
        cr_frame_files_describe(run->cli.output_dir, k, written, &files, err))
        goto fail;
    st.files = files;
    if (cr_finish_frame(w, k, &st, err) == 0) {
        free(files);
        return 0;
    }
fail:
    free(files);
    cr_remove_frame_files(run, k, written);
    cr_interrupt_frame_end(&run->intr, w->slot);
    cr_worker_idle(w);
    return -1;
}

/* Render frame k on the CPU and write it. Returns 0, or -1 with err set
 * (err->msg is "interrupted" after Ctrl-C). */
static int cr_do_frame(cr_worker *w, int k, cr_pixel *px, cr_sphere *spheres, cr_err *err)
{
    cr_run *run = w->run;
    cr_frame f;
    double t0;
    if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                       (int)run->cli.height, &run->ts, &f, spheres, err))
        return -1;
    cr_worker_frame(w, k);
    t0 = cr_now();
    if (cr_cpu_render(&f, run->threads, px, cr_progress, w, &run->intr.count, err)) {
        cr_worker_idle(w);
        return -1;
    }
    return cr_output_frame(w, k, &f, px, cr_now() - t0, err);
}

/* Is frame k one that --resume keeps from the earlier run? */
static int cr_frame_kept(const cr_run *run, int k)
{
    return run->resume.body && run->resume.body[k];
}

/* Take the next frame from the stack: its number, or -1 when the run is over
 * (every frame taken, a worker failed, or Ctrl-C). Frames kept by --resume
 * are skipped. */
static int cr_next_frame(cr_run *run)
{
    int k, stop;
    do
        k = atomic_fetch_add(&run->next_frame, 1);
    while (k < run->cli.frames && cr_frame_kept(run, k));
    pthread_mutex_lock(&run->lock);
    stop = run->failed;
    pthread_mutex_unlock(&run->lock);
    if (stop || cr_interrupt_requested(&run->intr) || k >= run->cli.frames)
        return -1;
    return k;
}

/* Prepare frame k into *f (its spheres into spheres) and queue it on the GPU
 * session (asynchronous). */
static int cr_gpu_start(cr_worker *w, cr_gpu_session *gs, int k, cr_frame *f, cr_sphere *spheres,
                        cr_err *err)
{
    cr_run *run = w->run;
    if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                       (int)run->cli.height, &run->ts, f, spheres, err))
        return -1;
    return cr_gpu_session_launch(gs, f, err);
}

/* Every frame a GPU worker takes, through one session for the whole run
 * (device buffers and the sky texture stay on the device): frame k+1 is
 * queued before frame k's files are written, so the GPU traces while the
 * host writes (the session holds two frames' pixels). Returns 0, or -1 with
 * err set; frames in flight at a failure are stopped and leave no file. */
static int cr_gpu_frames(cr_worker *w, cr_sphere *spheres, cr_err *err)
{
    cr_run *run = w->run;
    cr_gpu_session *gs;
    /* frame k (being written) and frame k+1 (in flight), each with its spheres */
    cr_frame frames[2];
    cr_sphere *sph[2] = {spheres, malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1))};
    int k, next, cur = 0, rc = -1;
    if (!sph[1])
        return cr_err_set(err, "out of memory");
    gs = cr_gpu_session_create(w->device, (size_t)run->cli.width * (size_t)run->cli.height, err);
    if (!gs) {
        free(sph[1]);
        return -1;
    }
    k = cr_next_frame(run);
    if (k >= 0 && cr_gpu_start(w, gs, k, &frames[cur], sph[cur], err))
        goto done;
    for (; k >= 0; k = next) {
        const cr_pixel *px;
        double seconds = 0.0;
        cr_err next_err;
        int next_rc = 0;
        cr_worker_frame(w, k);
        px = cr_gpu_session_wait(gs, cr_progress, cr_cancelled, w, &seconds, err);
        if (!px) {
            cr_worker_idle(w);
            goto done;
        }
        {
            double trace_s, copy_s;
            cr_gpu_session_times(gs, &trace_s, &copy_s);
            cr_log_detail(&run->log, "frame %d on GPU %d: %.4f s tracing, %.4f s copying pixels",
                          k, w->device, trace_s, copy_s);
        }
        next = cr_next_frame(run);
        if (next >= 0)
            next_rc = cr_gpu_start(w, gs, next, &frames[!cur], sph[!cur], &next_err);
        /* frame k is written even when frame k+1 could not be started */
        if (cr_output_frame(w, k, &frames[cur], px, seconds, err))
            goto done;
        if (next_rc) {
            *err = next_err;
            goto done;
        }
        cur = !cur;
    }
    rc = 0;
done:
    cr_gpu_session_free(gs);
    free(sph[1]);
    return rc;
}

/* Record the run's first failure (later ones are consequences). */
static void cr_fail(cr_run *run, const cr_err *err)
{
    pthread_mutex_lock(&run->lock);
    if (!run->failed) {
        run->failed = 1;
        run->fail_err = *err;
    }
    pthread_mutex_unlock(&run->lock);
}

static void *cr_worker_main(void *arg)
{
    cr_worker *w = arg;
    cr_run *run = w->run;
    size_t npx = (size_t)run->cli.width * (size_t)run->cli.height;
    cr_pixel *px = w->device < 0 ? malloc(npx * sizeof *px) : NULL; /* GPU: the session's */
    cr_sphere *spheres = malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1));
    cr_err err;
    err.msg[0] = '\0';
    if ((w->device < 0 && !px) || !spheres) {
        cr_err_set(&err, "cannot allocate %.1f MiB for a %ldx%ld frame",
                   (double)(npx * sizeof *px) / (1 << 20), run->cli.width, run->cli.height);
        goto fail;
    }
    if (w->device >= 0) {
        if (cr_gpu_frames(w, spheres, &err))
            goto fail;
    } else {
        int k;
        while ((k = cr_next_frame(run)) >= 0)
            if (cr_do_frame(w, k, px, spheres, &err))
                goto fail;
    }
    free(px);
    free(spheres);
    return NULL;
fail:
    cr_fail(run, &err);
    free(px);
    free(spheres);
    return NULL;
}

/* Ask whether to proceed (E.1), only when someone can answer. */
static int cr_confirm(cr_run *run)
{
    char line[64];
    if (run->cfg.auto_accept || run->cfg.quiet || !isatty(STDIN_FILENO))
        return 1;
    fputs("Proceed with rendering? [Y/n] ", stdout);
    fflush(stdout);
    if (!fgets(line, sizeof line, stdin))
        return 0;
    return cr_cli_answer_yes(line);
}

static void cr_log_scene(cr_run *run)
{
    const cr_scene *s = &run->scene;
    const double deg = 180.0 / CR_PI;
    char range[48] = "";
    cr_log_info(&run->log, "scene %s: M = %g, a = %g, Q = %g%s", s->path, s->m.a, s->a.a, s->q.a,
                (s->m.a != s->m.b || s->a.a != s->a.b || s->q.a != s->q.b) ? " (animated)" : "");
    if (s->obs_at_infinity)
        cr_log_info(&run->log,
                    "observer at infinity, theta = %g deg, phi = %g deg, image plane %g M wide%s",
                    s->obs_theta.a * deg, s->obs_phi.a * deg, s->hextent.a,
                    run->cli.frames > 1 ? " (frame 0)" : "");
    else
        cr_log_info(&run->log, "observer at r = %g, theta = %g deg, phi = %g deg, hfov %g deg%s",
                    s->obs_r.a, s->obs_theta.a * deg, s->obs_phi.a * deg, s->hfov.a * deg,
                    run->cli.frames > 1 ? " (frame 0)" : "");
    if (s->has_disc)
        cr_log_info(&run->log, "disc from r = %g to %g, %dx%d squares", s->disc_r_in.a,
                    s->disc_r_out.a, s->disc_n_radial, s->disc_n_sectors);
    if (s->n_spheres)
        cr_log_info(&run->log, "%d sphere%s", s->n_spheres, s->n_spheres > 1 ? "s" : "");
    if (s->has_sky && s->sky_at_infinity)
        cr_log_info(&run->log, "sky map %s (%dx%d) at infinity", s->sky_image, s->sky_width,
                    s->sky_height);
    else if (s->has_sky)
        cr_log_info(&run->log, "sky map %s (%dx%d), boundary %g", s->sky_image, s->sky_width,
                    s->sky_height, s->sky_boundary.a);
    if (run->cli.frames > 1)
        snprintf(range, sizeof range, "s (0 to %ld)", run->cli.frames - 1);
    cr_log_info(&run->log, "%ld frame%s of %ldx%ld pixels, outputs '%s' into %s, backend %s",
                run->cli.frames, range, run->cli.width, run->cli.height, run->cli.output_type,
                run->cli.output_dir, run->info.backend);
    cr_log_detail(&run->log, "raytracer: integrator %s, tolerance %g (mino), step multiplier %g "
                             "(rk4), horizon epsilon %g, max steps %ld, max turns %g; %d CPU "
                             "threads",
                  cr_integrator_name(run->ts.integrator), run->ts.tolerance,
                  run->ts.step_multiplier, run->ts.horizon_epsilon, run->ts.max_steps,
                  run->ts.max_turns, run->threads);
}

/* Refuse, before anything large is allocated, a run whose buffers cannot fit
 * in memory: per worker a frame of cr_pixel (two for a GPU worker, whose
 * session holds the frame being written and the next one), plus the 8-bit
 * image written from it and the per-frame statistics. The limit is the physical memory, or
 * the address-space or data limit (ulimit -v, -d) when lower
 * (cr_cpu_memory_check, which the Python package uses too). */
static int cr_check_memory(const cr_run *run, int n_workers, cr_err *err)
{
    double px = (double)run->cli.width * (double)run->cli.height;
    double need = px * ((double)sizeof(cr_pixel) * n_workers * (run->use_cuda ? 2 : 1) + 3.0) +
                  (double)run->cli.frames * (double)(sizeof(cr_frame_stats) + 1);
    cr_err mem;
    /* and what else the run holds: each worker's FITS file while it is
     * written, the sky image once the scene is loaded, and the stacks of
     * the threads (the render threads of each worker, the workers, the
     * Ctrl-C stopper) */
    if (cr_has_type(run, 'f'))
        need += n_workers * cr_fits_memory((int)run->cli.width, (int)run->cli.height);
    if (run->scene.sky_rgb)
        need += 3.0 * (double)run->scene.sky_width * (double)run->scene.sky_height;
    need += (double)(n_workers * (run->use_cuda ? 1 : run->threads) + n_workers + 1) *
            cr_mem_thread_stack();
    if (cr_cpu_memory_check(need, &mem))
        return cr_err_set(err, "a %ldx%ld frame (%ld frame%s) %s; choose a smaller -x/-y",
                          run->cli.width, run->cli.height, run->cli.frames,
                          run->cli.frames > 1 ? "s" : "", mem.msg);
    return 0;
}

static int cr_prog_is_cpu(const char *argv0)
{
    const char *base = strrchr(argv0, '/');
    base = base ? base + 1 : argv0;
    return strcmp(base, "curray_cpu") == 0;
}

/* Parse the command line and answer -h, --version and -i. Returns -1 when
 * the program should end now with *rc, else 0 (a render follows). */
static int cr_command_line(cr_run *run, int *rc)
{
    cr_err err;
    err.msg[0] = '\0';
    *rc = CR_EXIT_OK;
    if (cr_cli_parse(run->argc, run->argv, cr_prog_is_cpu(run->argv[0]), &run->cli, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        *rc = CR_EXIT_USAGE;
        return -1;
    }
    if (run->cli.help) {
        cr_cli_usage(run->argv[0], stdout);
        return -1;
    }
    if (run->cli.version) {
        printf("curray %s\n", CURRAY_VERSION);
        return -1;
    }
    if (run->cli.example) {
        fputs(cr_example_scene, stdout);
        return -1;
    }
    if (run->cli.info) {
        cr_gpu_print_info(stdout);
        if (!run->cli.scene_path) {
            printf("\nNo scene file specified, no raytracing will be performed.\n");
            return -1;
        }
    }
    if (cr_cli_check_render(&run->cli, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        *rc = CR_EXIT_USAGE;
        return -1;
    }
    if (run->cli.trace)
        run->cli.output_type = ""; /* --trace writes only the path files */
    return 0;
}

/* The system configuration: -c, else config.yml when present, else the
 * defaults; then the command line's overrides, the thread count in use and
 * the trace settings. */
static int cr_configure(cr_run *run, cr_err *err)
{
    cr_sysconfig_defaults(&run->cfg);
    if (run->cli.config_path || access("config.yml", F_OK) == 0) {
        if (!run->cli.config_path)
            run->cli.config_path = "config.yml";
        if (cr_sysconfig_load(run->cli.config_path, &run->cfg, err))
            return -1;
    }
    if (run->cli.verbose >= 0)
        run->cfg.verbose = run->cli.verbose;
    if (run->cli.quiet >= 0)
        run->cfg.quiet = run->cli.quiet;
    if (run->cli.auto_accept >= 0)
        run->cfg.auto_accept = run->cli.auto_accept;
    run->threads = run->cli.threads > 0 ? (int)run->cli.threads
                                        : (run->cfg.cpu_threads > 0 ? run->cfg.cpu_threads
                                                                    : cr_cpu_cores());
    if (run->threads > CR_SYSCONFIG_MAX_THREADS)
        run->threads = CR_SYSCONFIG_MAX_THREADS; /* all cores of a machine with more */
    run->ts = run->cfg.raytracer;
    return 0;
}

/* An MPI run traces on GPUs on every rank or on none (so its files are a
 * one-process run's on that backend): given the n GPUs chosen on this rank
 * (run->devices), every rank says whether it has one (a collective call,
 * made once by every rank when the backend is not cpu: see
 * cr_mpi_skip_gpus). When all do, this rank's GPU is the one of its local
 * rank (cr_gpu_for_local_rank) and 1 is returned; else 0 with the reason in
 * err. */
static int cr_mpi_gpus(cr_run *run, int n, cr_err *err)
{
    cr_err note;
    if (!cr_mpi_all_ok(n > 0)) {
        if (n > 0)
            cr_err_set(err, "another MPI rank has no usable GPU (an MPI run traces on GPUs on "
                            "every rank or on none)");
        return 0;
    }
    run->devices[0] = cr_gpu_for_local_rank(run->devices, n, run->mpi_local_rank,
                                            run->mpi_local_size, &note);
    cr_log_detail(&run->log, "MPI rank %d (local rank %d of %d on %s) traces on GPU %d",
                  run->mpi_rank, run->mpi_local_rank, run->mpi_local_size, cr_mpi_host(),
                  run->devices[0]);
    if (note.msg[0])
        cr_log_info(&run->log, "curray: warning: %s", note.msg);
    return 1;
}

/* A rank that stops before cr_choose_backend still takes part in
 * cr_mpi_gpus' collective call, so that the ranks' collective calls pair
 * up (cr_mpi_ready's comes next on every rank). */
static void cr_mpi_skip_gpus(const cr_run *run)
{
    if (run->mpi_size > 1 && run->cli.backend != CR_BACKEND_CPU)
        cr_mpi_all_ok(0);
}

/* CUDA when asked for or (auto) when an enabled GPU is usable, else the CPU
 * (cr_gpu_choose; in an MPI run one GPU per rank, cr_mpi_gpus). Fills
 * devices, n_workers, use_cuda and backend_name. */
static int cr_choose_backend(cr_run *run)
{
    cr_err gerr;
    int n;
    run->use_cuda = 0;
    run->n_workers = 1;
    if (run->cli.backend != CR_BACKEND_CPU) {
        n = cr_gpu_choose(run->cfg.gpu_enabled, CR_MAX_GPUS, run->devices, CR_MAX_GPUS, &gerr);
        if (run->mpi_size > 1)
            n = cr_mpi_gpus(run, n, &gerr);
        if (n > 0) {
            run->use_cuda = 1;
            run->n_workers = n;
            if (gerr.msg[0])
                cr_log_info(&run->log, "curray: warning: %s", gerr.msg);
        } else if (run->cli.backend == CR_BACKEND_CUDA && run->mpi_size > 1) {
            cr_log_error(&run->log, "curray: MPI rank %d on %s: --backend cuda: %s",
                         run->mpi_rank, cr_mpi_host(), gerr.msg);
            return -1;
        } else if (run->cli.backend == CR_BACKEND_CUDA) {
            cr_log_error(&run->log, "curray: --backend cuda: %s", gerr.msg);
            return -1;
        } else {
            cr_log_detail(&run->log, "using the CPU: %s", gerr.msg);
        }
    }
    if (run->use_cuda)
        snprintf(run->backend_name, sizeof run->backend_name, "cuda (%d GPU%s)", run->n_workers,
                 run->n_workers > 1 ? "s" : "");
    else
        snprintf(run->backend_name, sizeof run->backend_name, "cpu (%d thread%s)", run->threads,
                 run->threads > 1 ? "s" : "");
    return 0;
}

/* Every frame must be possible before any is rendered. */
static int cr_check_frames(cr_run *run, cr_err *err)
{
    cr_sphere *tmp = malloc(sizeof *tmp * (size_t)(run->scene.n_spheres + 1));
    cr_frame f;
    int k, rc = 0;
    if (!tmp)
        return cr_err_set(err, "out of memory");
    int shrunk = -1;
    double eps_min = 0.0;
    for (k = 0; k < run->cli.frames && rc == 0; k++) {
        rc = cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                            (int)run->cli.height, &run->ts, &f, tmp, err);
        if (rc == 0 && (k == 0 || k == run->cli.frames - 1)) {
            /* the first and last frame, for info.txt (spheres not kept) */
            run->ends[k > 0] = f;
            run->ends[k > 0].spheres = NULL;
            if (run->cli.frames == 1)
                run->ends[1] = run->ends[0];
        }
        if (rc == 0 && f.horizon_epsilon < run->ts.horizon_epsilon &&
            (shrunk < 0 || f.horizon_epsilon < eps_min)) {
            shrunk = k;
            eps_min = f.horizon_epsilon;
        }
    }
    if (rc == 0 && shrunk >= 0)
        cr_log_info(&run->log,
                    "curray: warning: the observer is closer to the horizon than 2 x "
                    "raytracer.horizon_epsilon = %g M (frame %d): rays stop halfway between "
                    "it and r+ instead, from %g M above r+",
                    run->ts.horizon_epsilon, shrunk, eps_min);
    if (rc == 0) {
        cr_err hints[8];
        int h, nh = cr_scene_hints(&run->scene, (int)run->cli.frames, hints, 8);
        for (h = 0; h < nh; h++)
            cr_log_info(&run->log, "curray: warning: %s", hints[h].msg);
    }
    free(tmp);
    return rc;
}

/* The run's settings as text, for a crash report: the command line, the
 * folder it ran in, and the settings in use. malloc'ed; NULL when out of
 * memory. */
static char *cr_settings_text(const cr_run *run)
{
    char *text = NULL, cwd[4096];
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    int k;
    if (!fp)
        return NULL;
    fputs("command line:", fp);
    for (k = 0; k < run->argc; k++)
        fprintf(fp, " %s", run->argv[k]);
    fprintf(fp, "\nworking folder: %s\n", getcwd(cwd, sizeof cwd) ? cwd : "(unknown)");
    fprintf(fp, "scene: %s\nconfiguration: %s\n", run->cli.scene_path,
            run->cli.config_path ? run->cli.config_path : "(built-in defaults)");
    fprintf(fp, "output: %s, types '%s'; %ld frame%s of %ldx%ld pixels\n", run->cli.output_dir,
            run->cli.output_type, run->cli.frames, run->cli.frames > 1 ? "s" : "",
            run->cli.width, run->cli.height);
    fprintf(fp, "backend: %s", run->backend_name);
    for (k = 0; run->use_cuda && k < run->n_workers; k++)
        fprintf(fp, "%s%d", k ? ", " : "; GPUs ", run->devices[k]);
    fprintf(fp, "\nraytracer: integrator %s, tolerance %g, step multiplier %g, horizon epsilon "
                "%g, max steps %ld, max turns %g\n",
            cr_integrator_name(run->ts.integrator), run->ts.tolerance, run->ts.step_multiplier,
            run->ts.horizon_epsilon, run->ts.max_steps, run->ts.max_turns);
    if (fclose(fp) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

/* Create the output folder, start the log file in <output>/log and install
 * the crash handler. */
static int cr_prepare_output(cr_run *run, cr_err *err)
{
    char log_dir[4096];
    cr_err lerr;
    if (cr_mkdir_p(run->cli.output_dir, err) ||
        cr_dirlock_take(&run->dirlock, run->cli.output_dir, err) < 0)
        return -1;
    if (cr_path_join(log_dir, sizeof log_dir, run->cli.output_dir, "log") != 0)
        log_dir[0] = '\0';
    if (cr_log_attach(&run->log, log_dir, run->cfg.keep_log, &lerr))
        cr_log_error(&run->log, "curray: warning: %s (logging to the console only)", lerr.msg);
    run->settings = cr_settings_text(run);
    if (cr_crash_install(log_dir, CURRAY_VERSION, run->settings ? run->settings : "", &lerr))
        cr_log_error(&run->log, "curray: warning: %s (no crash report)", lerr.msg);
    return 0;
}

/* --- MPI (mpi.h) ------------------------------------------------------------
 * Rank 0 renders in threads (its workers) while its main thread serves the
 * other ranks; a run of several frames hands out whole frames from the same
 * stack as its own workers (cr_next_frame), a one-frame run blocks of rows. */

/* The next block of rows of a one-frame MPI run: 0, or -1 when none is left
 * or the run stops. About 16 blocks per rank, so that the slow rows near the
 * hole even out. */
static int cr_next_rows(cr_run *run, int *row0, int *rows)
{
    int c = atomic_fetch_add(&run->next_chunk, 1), stop;
    pthread_mutex_lock(&run->lock);
    stop = run->failed;
    pthread_mutex_unlock(&run->lock);
    *row0 = c * run->chunk_rows;
    if (stop || cr_interrupt_requested(&run->intr) || *row0 >= run->cli.height ||
        cr_frame_kept(run, 0))
        return -1;
    *rows = *row0 + run->chunk_rows <= run->cli.height ? run->chunk_rows
                                                        : (int)run->cli.height - *row0;
    return 0;
}

static int cr_mpi_next(void *ctx, int *k, int *row0, int *rows)
{
    cr_run *run = ctx;
    *k = 0;
    if (run->cli.frames == 1)
        return cr_next_rows(run, row0, rows);
    *k = cr_next_frame(run);
    *row0 = 0;
    *rows = (int)run->cli.height;
    return *k < 0 ? -1 : 0;
}

/* Another rank's pixels: a whole frame is written at once (by the writer
 * slot after rank 0's workers), a block of rows goes into frame 0. */
static int cr_mpi_deliver(void *ctx, int rank, int k, int row0, int rows, const cr_pixel *px,
                          double seconds, cr_err *err)
{
    cr_run *run = ctx;
    size_t w = (size_t)run->cli.width;
    (void)rank;
    if (run->cli.frames == 1) {
        memcpy(run->rows_px + (size_t)row0 * w, px, (size_t)rows * w * sizeof *px);
        atomic_fetch_add(&run->rows_done, rows);
        return 0;
    }
    {
        /* the frame the other rank traced, made here again for its files */
        cr_frame f;
        cr_sphere *spheres = malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1));
        int rc = -1;
        if (!spheres)
            cr_err_set(err, "out of memory");
        else if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                                (int)run->cli.height, &run->ts, &f, spheres, err) == 0)
            rc = cr_output_frame(&run->workers[run->n_workers], k, &f, px, seconds, err);
        free(spheres);
        if (rc) {
            cr_fail(run, err);
            return -1;
        }
    }
    return 0;
}

static void cr_mpi_failed(void *ctx, int rank, const char *msg)
{
    cr_err e;
    cr_err_set(&e, "MPI rank %d: %s", rank, msg);
    cr_fail(ctx, &e);
}

static int cr_mpi_stop(void *ctx)
{
    return cr_interrupt_requested(&((cr_run *)ctx)->intr);
}

/* Trace rows [row0, row0 + rows) of the prepared frame f into out (rows x
 * width pixels): through the GPU session gs when there is one (MPI with
 * GPUs), else with the CPU threads. w (may be NULL) is the worker whose
 * Ctrl-C stops the rows. Returns 0, or -1 with err set. */
static int cr_trace_rows(cr_run *run, cr_gpu_session *gs, const cr_frame *f, int row0, int rows,
                         cr_pixel *out, cr_worker *w, cr_err *err)
{
    const cr_pixel *px;
    if (!gs)
        return cr_cpu_render_rows(f, row0, rows, run->threads, out, NULL, NULL,
                                  w ? &run->intr.count : NULL, err);
    if (cr_gpu_session_launch_rows(gs, f, row0, rows, err))
        return -1;
    px = cr_gpu_session_wait(gs, NULL, w ? cr_cancelled : NULL, w, NULL, err);
    if (!px)
        return -1;
    memcpy(out, px, (size_t)rows * (size_t)f->width * sizeof *out);
    return 0;
}

/* Rank 0's worker in a one-frame run: blocks of rows into rows_px, on its
 * GPU (a session for the run) or its CPU threads. */
static void *cr_rows_main(void *arg)
{
    cr_worker *w = arg;
    cr_run *run = w->run;
    size_t width = (size_t)run->cli.width;
    cr_gpu_session *gs = NULL;
    int row0, rows;
    cr_err err;
    if (w->device >= 0 &&
        !(gs = cr_gpu_session_create(w->device, width * (size_t)run->cli.height, &err))) {
        cr_fail(run, &err);
        return NULL;
    }
    while (cr_next_rows(run, &row0, &rows) == 0) {
        if (cr_trace_rows(run, gs, &run->rows_frame, row0, rows,
                          run->rows_px + (size_t)row0 * width, w, &err)) {
            cr_fail(run, &err);
            break;
        }
        atomic_fetch_add(&run->rows_done, rows);
    }
    cr_gpu_session_free(gs);
    return NULL;
}

/* Rank 0 of an MPI run: its workers in threads, the other ranks served from
 * this thread, then (one frame) the gathered frame written. */
static void cr_mpi_frames(cr_run *run)
{
    cr_mpi_ops ops = {run, (int)run->cli.width, cr_mpi_next, cr_mpi_deliver, cr_mpi_failed,
                      cr_mpi_stop};
    cr_worker *writer = &run->workers[run->n_workers];
    size_t npx = (size_t)run->cli.width * (size_t)run->cli.height;
    void *(*local)(void *) = run->cli.frames > 1 ? cr_worker_main : cr_rows_main;
    int k, started = 0, one = run->cli.frames == 1 && !cr_frame_kept(run, 0);
    double t0 = cr_now();
    cr_err err;
    writer->run = run;
    writer->slot = run->n_workers;
    writer->device = -1;
    atomic_init(&run->next_chunk, 0);
    atomic_init(&run->rows_done, 0);
    if (one) {
        run->chunk_rows = (int)(run->cli.height / (16L * run->mpi_size));
        if (run->chunk_rows < 1)
            run->chunk_rows = 1;
        run->rows_px = malloc(npx * sizeof *run->rows_px);
        run->rows_spheres = malloc(sizeof *run->rows_spheres * (size_t)(run->scene.n_spheres + 1));
        if (!run->rows_px || !run->rows_spheres) {
            cr_err_set(&err, "out of memory for a %ldx%ld frame", run->cli.width,
                       run->cli.height);
            cr_fail(run, &err);
        } else if (cr_scene_frame(&run->scene, 0, 1, (int)run->cli.width, (int)run->cli.height,
                                  &run->ts, &run->rows_frame, run->rows_spheres, &err)) {
            cr_fail(run, &err);
        }
    }
    for (k = 0; k < run->n_workers; k++)
        if (pthread_create(&run->workers[k].tid, NULL, local, &run->workers[k]) == 0)
            started++;
        else
            break;
    if (started == 0) {
        cr_err_set(&err, "cannot start a worker thread");
        cr_fail(run, &err);
    }
    run->mpi_served = cr_mpi_dispatch(&ops, run->mpi_size, &run->gather_s,
                                      &run->gather_bytes) == 0;
    for (k = 0; k < started; k++)
        pthread_join(run->workers[k].tid, NULL);
    cr_log_detail(&run->log, "MPI: %d ranks; rank 0 received %.1f MiB of pixels in %.3f s",
                  run->mpi_size, run->gather_bytes / (1 << 20), run->gather_s);
    if (one && atomic_load(&run->rows_done) == run->cli.height && !run->failed &&
        !cr_interrupt_requested(&run->intr) &&
        cr_output_frame(&run->workers[0], 0, &run->rows_frame, run->rows_px, cr_now() - t0,
                        &err))
        cr_fail(run, &err);
    free(run->rows_px);
    free(run->rows_spheres);
    run->rows_px = NULL;
    run->rows_spheres = NULL;
}

/* A rank > 0: trace rows [row0, row0 + rows) of frame k into px, on its
 * GPU (run->rank_gs, made at the first item) or its CPU threads. */
static int cr_mpi_render(void *ctx, int k, int row0, int rows, cr_pixel *px, double *seconds,
                         cr_err *err)
{
    cr_run *run = ctx;
    cr_frame f;
    double t0;
    int rc = -1;
    cr_sphere *spheres;
    if (run->use_cuda && !run->rank_gs &&
        !(run->rank_gs = cr_gpu_session_create(
              run->devices[0], (size_t)run->cli.width * (size_t)run->cli.height, err)))
        return -1;
    spheres = malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1));
    if (!spheres)
        return cr_err_set(err, "out of memory");
    if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                       (int)run->cli.height, &run->ts, &f, spheres, err) == 0) {
        t0 = cr_now();
        rc = cr_trace_rows(run, run->rank_gs, &f, row0, rows, px, NULL, err);
        *seconds = cr_now() - t0;
    }
    free(spheres);
    return rc;
}

/* A rank > 0's whole run: trace what rank 0 hands out. */
static int cr_mpi_rank_main(cr_run *run)
{
    cr_err err;
    int rc = cr_mpi_serve((int)run->cli.width, cr_mpi_render, run, &err);
    cr_gpu_session_free(run->rank_gs);
    run->rank_gs = NULL;
    if (rc) {
        cr_log_error(&run->log, "curray: MPI rank %d on %s: %s", run->mpi_rank, cr_mpi_host(),
                     err.msg);
        return CR_EXIT_ERROR;
    }
    return CR_EXIT_OK;
}

/* MPI: every rank checks the run (same arguments, same files); a one-frame
 * run needs a row per rank. */
static int cr_mpi_check(cr_run *run, cr_err *err)
{
    if (run->mpi_size < 2)
        return 0;
    if (run->cli.frames == 1 && run->mpi_size > run->cli.height)
        return cr_err_set(err,
                          "%d MPI ranks for a one-frame run of %ld rows: more ranks than rows; "
                          "use at most %ld ranks, or a taller frame",
                          run->mpi_size, run->cli.height, run->cli.height);
    return 0;
}

/* Do all ranks go on? (prepared: this rank's cr_prepare succeeded.) */
static int cr_mpi_ready(cr_run *run, int prepared, int *rc)
{
    int all;
    if (run->mpi_size < 2)
        return prepared;
    all = cr_mpi_all_ok(prepared);
    if (!all && prepared) {
        if (run->mpi_rank == 0)
            cr_log_error(&run->log, "curray: another MPI rank could not prepare the run (its "
                                    "message is above); nothing rendered");
        *rc = run->mpi_rank == 0 ? CR_EXIT_ERROR : CR_EXIT_OK;
    }
    return all;
}

/* Render every frame with the chosen workers; Ctrl-C handling is installed
 * from the start of the render to the end of the videos. */
static int cr_render_frames(cr_run *run, cr_err *err)
{
    int k, started = 0;
    run->stats = calloc((size_t)run->cli.frames, sizeof *run->stats);
    run->done = calloc((size_t)run->cli.frames, 1);
    if (!run->stats || !run->done)
        return cr_err_set(err, "out of memory for %ld frames", run->cli.frames);
    for (k = 0; k < run->cli.frames; k++)
        run->done[k] = (char)cr_frame_kept(run, k);
    run->n_done = run->n_kept;
    if (cr_interrupt_install(&run->intr, run->cli.output_dir, &run->log, err))
        return -1;
    pthread_mutex_init(&run->lock, NULL);
    atomic_init(&run->next_frame, 0);
    run->t_start = cr_now();
    for (k = 0; k < run->n_workers; k++) {
        run->workers[k].run = run;
        run->workers[k].slot = k;
        run->workers[k].device = run->use_cuda ? run->devices[k] : -1;
        run->workers[k].frame = 0;
        run->workers[k].frac = 0.0;
    }
    if (run->mpi_size > 1) {
        cr_mpi_frames(run);
    } else if (run->n_workers == 1) {
        cr_worker_main(&run->workers[0]);
    } else {
        for (k = 0; k < run->n_workers; k++) {
            if (pthread_create(&run->workers[k].tid, NULL, cr_worker_main, &run->workers[k]))
                break;
            started++;
        }
        if (started == 0)
            cr_worker_main(&run->workers[0]);
        for (k = 0; k < started; k++)
            pthread_join(run->workers[k].tid, NULL);
    }
    pthread_mutex_destroy(&run->lock);
    return 0; /* Ctrl-C handling stays for the videos; main removes it */
}

/* After every frame is finished: c.mp4 from the colour frames and, when
 * redshift frames were asked for too, r.mp4 from them (video.h); then, with
 * video.keep_frames false, the PNG frames they were made from are removed. */
static int cr_make_videos(cr_run *run, cr_err *err)
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
static int cr_report(cr_run *run)
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

/* What the output folder holds already (resume.h): the run hash for
 * info.txt; stale frame files, reported on the console and in info.txt and
 * never deleted; with --resume, the earlier run's finished frames (a record
 * in its info.txt, whose hash must match, and every file present), which
 * this run keeps. */
static int cr_check_folder(cr_run *run, cr_err *err)
{
    const char *dir = run->cli.output_dir;
    char video[64] = "";
    int n, k;
    cr_output_frame_letters(run->cli.output_type, run->frame_types, sizeof run->frame_types);
    if (cr_has_type(run, 'v')) {
        if (!cr_video_available())
            return cr_err_set(err, "-t v: %s", CR_VIDEO_UNAVAILABLE);
        snprintf(video, sizeof video, "video fps %d", run->cfg.video_fps);
    }
    if (cr_run_hash(&run->scene, &run->cfg, run->cli.width, run->cli.height, run->cli.frames,
                    run->cli.output_type, run->use_cuda, video, run->hash, err))
        return -1;
    run->info.hash = run->hash;
    if (cr_dirlock_take(&run->dirlock, dir, err) < 0 || /* 1: no folder yet, taken once made */
        (cr_has_type(run, 'i') && cr_info_path_check(dir, err)))
        return -1;
    n = cr_stale_scan(dir, (int)run->cli.frames, run->frame_types, &run->stale);
    if (n < 0)
        return cr_err_set(err, "out of memory scanning %s", dir);
    if (n > 0) {
        run->info.stale = run->stale;
        cr_log_info(&run->log,
                    "curray: warning: %s holds %d frame file%s that this run does not "
                    "overwrite, from an earlier run: %s; curray leaves them as they are "
                    "(delete them yourself if they are not wanted)",
                    dir, n, n > 1 ? "s" : "", run->stale);
    }
    if (!run->cli.resume)
        return 0;
    if (!cr_has_type(run, 'i'))
        return cr_err_set(err, "--resume needs info.txt, which records the frames an earlier run "
                               "finished: add i to -t (and use the same -t as that run)");
    if (cr_resume_load(&run->resume, dir, run->hash, (int)run->cli.frames, err))
        return -1;
    run->info.started = run->resume.started[0] ? run->resume.started : NULL;
    if ((k = cr_resume_verify(&run->resume, dir, run->frame_types, err)) < 0)
        return -1;
    if (k > 0)
        cr_log_info(&run->log, "curray: warning: --resume: %d finished frame%s rendered again: "
                    "%s no longer match%s info.txt (%s)", k, k > 1 ? "s are" : " is",
                    k > 1 ? "their files" : "its files", k > 1 ? "" : "es", run->resume.why);
    run->n_kept = run->resume.n_records;
    cr_log_info(&run->log, "resuming: %d of %ld frame%s finished by the earlier run, %ld to render",
                run->n_kept, run->cli.frames, run->cli.frames > 1 ? "s" : "",
                run->cli.frames - run->n_kept);
    return 0;
}

/* Everything up to the render: configuration, backend, scene, frames,
 * summary, prompt, output folder. Returns -1 with *rc when the run ends
 * before rendering. */
static int cr_prepare(cr_run *run, int *rc)
{
    cr_err err;
    int n;
    err.msg[0] = '\0';
    *rc = CR_EXIT_ERROR;
    if (cr_configure(run, &err)) {
        fprintf(stderr, "curray: configuration file %s\n", err.msg);
        cr_mpi_skip_gpus(run);
        return -1;
    }
    /* console now, the file once the output folder exists (log.h) */
    cr_log_hold(&run->log, run->cfg.verbose, run->cfg.quiet || run->mpi_rank > 0);
    run->log_open = 1;
    if (cr_mpi_check(run, &err)) {
        if (run->mpi_rank == 0) /* every rank finds the same */
            cr_log_error(&run->log, "curray: %s", err.msg);
        cr_mpi_skip_gpus(run);
        return -1;
    }
    cr_log_detail(&run->log, "curray %s, configuration %s", CURRAY_VERSION,
                  run->cli.config_path ? run->cli.config_path : "(built-in defaults)");
    if (cr_choose_backend(run))
        return -1;
    if (cr_check_memory(run, run->n_workers, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if (cr_scene_load(run->cli.scene_path, &run->scene, &err) || cr_check_frames(run, &err)) {
        cr_log_error(&run->log, "curray: scene file %s", err.msg);
        return -1;
    }
    if (run->scene.sky_rgb && cr_check_memory(run, run->n_workers, &err)) { /* with the sky */
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if (run->mpi_rank > 0)
        return 0; /* the other MPI ranks only trace */
    if (run->mpi_size > 1) {
        size_t n = strlen(run->backend_name);
        snprintf(run->backend_name + n, sizeof run->backend_name - n, " on each of %d MPI ranks",
                 run->mpi_size);
    }
    run->info.scene_path = run->cli.scene_path;
    run->info.config_path = run->cli.config_path;
    run->info.backend = run->backend_name;
    run->info.width = (int)run->cli.width;
    run->info.height = (int)run->cli.height;
    run->info.frames = (int)run->cli.frames;
    run->info.output_types = run->cli.output_type;
    run->info.version = CURRAY_VERSION;
    run->info.first = &run->ends[0];
    run->info.last = &run->ends[1];
    if (cr_check_folder(run, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if (cr_has_type(run, 'i')) {
        /* info.txt shows the CPU threads in use, not the file's value */
        cr_sysconfig used = run->cfg;
        used.cpu_threads = run->threads;
        if (cr_info_begin(&run->infotxt, run->cli.output_dir, &run->info, &run->scene, &used,
                          &err)) {
            cr_log_error(&run->log, "curray: %s", err.msg);
            return -1;
        }
    }
    cr_log_scene(run);
    if (!cr_confirm(run)) {
        cr_log_info(&run->log, "not rendering (declined)");
        *rc = CR_EXIT_OK;
        return -1;
    }
    if (cr_prepare_output(run, &err) ||
        cr_info_resume(&run->infotxt, run->resume.body, run->resume.order, run->n_kept, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if ((n = cr_remove_dead_temps(run->cli.output_dir)) > 0)
        cr_log_info(&run->log, "removed %d temporary file%s left by a curray that was killed", n,
                    n > 1 ? "s" : "");
    return 0;
}

/* --trace I,J: the path of pixel (I, J)'s ray in each frame k, traced on the
 * CPU by the image's own loop (raypath.h) and written atomically to
 * trace_<I>_<J>_<k>.csv; no image. Returns the exit status. */
static int cr_trace_paths(cr_run *run)
{
    cr_sphere *spheres = malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1));
    cr_err err;
    int k;
    if (!spheres) {
        cr_log_error(&run->log, "curray: out of memory");
        return CR_EXIT_ERROR;
    }
    for (k = 0; k < run->cli.frames; k++) {
        cr_frame f;
        cr_raypath rp;
        char name[96];
        int i = (int)run->cli.trace_i, j = (int)run->cli.trace_j;
        snprintf(name, sizeof name, "trace_%d_%d_%d.csv", i, j, k);
        if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                           (int)run->cli.height, &run->ts, &f, spheres, &err) ||
            cr_raypath_trace(&f, i, j, &rp, &err))
            goto fail;
        if (cr_raypath_write_csv(run->cli.output_dir, name, &rp, &err)) {
            cr_raypath_free(&rp);
            goto fail;
        }
        cr_log_info(&run->log, "frame %d: pixel (%d, %d): %s after %u steps, %ld points in %s", k,
                    i, j, cr_outcome_name(rp.px.outcome), rp.px.steps, rp.n, name);
        cr_raypath_free(&rp);
    }
    free(spheres);
    return CR_EXIT_OK;
fail:
    cr_log_error(&run->log, "curray: %s", err.msg);
    free(spheres);
    return CR_EXIT_ERROR;
}

int main(int argc, char **argv)
{
    cr_run run;
    cr_err err;
    int rc, ready = 0;

    memset(&run, 0, sizeof run);
    cr_mpi_init(&argc, &argv, &run.mpi_rank, &run.mpi_size, &run.mpi_local_rank,
                &run.mpi_local_size);
    run.argc = argc;
    run.argv = argv;
    /* A reader that goes away (curray ... | head) must not kill a render
     * half-way: console writes then just fail. */
    signal(SIGPIPE, SIG_IGN);
    if (cr_command_line(&run, &rc) == 0 &&
        (ready = cr_mpi_ready(&run, cr_prepare(&run, &rc) == 0, &rc)) != 0) {
        if (run.cli.trace) {
            if (run.mpi_rank == 0)
                rc = cr_trace_paths(&run);
        } else if (run.mpi_rank > 0) {
            rc = cr_mpi_rank_main(&run);
        } else if (cr_render_frames(&run, &err)) {
            cr_log_error(&run.log, "curray: %s", err.msg);
            rc = CR_EXIT_ERROR;
        } else {
            rc = cr_report(&run);
            if (rc == CR_EXIT_OK && cr_has_type(&run, 'v') && cr_make_videos(&run, &err))
                rc = cr_interrupt_video_failed(&run.intr, &run.log, err.msg, run.cli.frames,
                                               run.cli.output_dir);
        }
    }
    cr_interrupt_remove(&run.intr);
    if (cr_info_end(&run.infotxt, &err) && run.log_open) { /* fsync: the records are on disk */
        cr_log_error(&run.log, "curray: %s", err.msg);
        rc = CR_EXIT_ERROR;
    }
    cr_crash_uninstall();
    cr_dirlock_release(&run.dirlock);
    free(run.settings);
    free(run.stale);
    cr_resume_free(&run.resume);
    free(run.stats);
    free(run.done);
    cr_scene_free(&run.scene);
    if (run.log_open)
        cr_log_close(&run.log);
    /* rank 0 stopped before every rank was told to stop (Ctrl-C, a rank
     * died): end them all; the finished frames are on disk */
    if (run.mpi_size > 1 && run.mpi_rank == 0 && ready && !run.cli.trace && !run.mpi_served)
        cr_mpi_abort(rc);
    cr_mpi_finalize();
    return rc;
}
