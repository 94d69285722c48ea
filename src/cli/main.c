/* curray: command-line front end.
 *
 * Reads the command line, the system configuration and the scene; checks
 * every frame before anything is rendered; asks to proceed (E.1); renders the
 * stack of frames on the CPU or on one host thread per enabled GPU (6.2);
 * writes c_<k>.png, r_<k>.png, d_<k>.csv and info.txt atomically.
 *
 * Exit status: 0 done; 1 a run-time error (input, output, device); 2 a usage
 * error; 130 interrupted (finished frames are kept, the frame in progress
 * leaves no file).
 */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "../cpu/render_cpu.h"
#include "../cuda/gpu.h"
#include "../io/fsutil.h"
#include "../io/log.h"
#include "../io/output.h"
#include "../io/scene.h"
#include "../io/sysconfig.h"
#include "cli.h"

#define CR_EXIT_OK 0
#define CR_EXIT_ERROR 1
#define CR_EXIT_USAGE 2
#define CR_EXIT_INTERRUPTED 130

/* The one piece of global state: set by SIGINT/SIGTERM, polled by the
 * renderers (a signal handler can reach nothing else). */
static volatile sig_atomic_t cr_cancel_flag;

static void cr_on_signal(int sig)
{
    (void)sig;
    cr_cancel_flag = 1;
}

static double cr_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Shared state of one run; workers take frames from next_frame (the frame
 * stack of 6.2). */
typedef struct cr_run {
    cr_cli cli;
    cr_sysconfig cfg;
    cr_scene scene;
    cr_log log;
    cr_run_info info;
    cr_trace_settings ts;
    int use_cuda;
    int threads;
    pthread_mutex_t lock;
    atomic_int next_frame;
    cr_frame_stats *stats; /* per frame */
    char *done;            /* per frame */
    int n_done;
    int failed;
    cr_err fail_err;
    double t_start;
} cr_run;

typedef struct cr_worker {
    cr_run *run;
    int device; /* GPU index, or -1 for the CPU */
    int frame;  /* frame in progress, for progress lines */
    double t_frame;
    pthread_t tid;
} cr_worker;

static int cr_has_type(const cr_run *run, char t)
{
    return strchr(run->cli.output_type, t) != NULL;
}

static void cr_progress(void *ctx, int rows_done, int rows_total)
{
    cr_worker *w = ctx;
    cr_run *run = w->run;
    double el = cr_now() - w->t_frame, frac = (double)rows_done / rows_total;
    if (rows_done >= rows_total)
        return;
    if (frac > 0.0)
        cr_log_progress(&run->log, "frame %d/%ld: %3.0f%%, %.0f s elapsed, about %.0f s left",
                        w->frame + 1, run->cli.frames, 100.0 * frac, el,
                        el * (1.0 - frac) / frac);
    else
        cr_log_progress(&run->log, "frame %d/%ld: starting", w->frame + 1, run->cli.frames);
}

/* Rewrite info.txt with the finished frames, in frame order. Caller holds
 * run->lock. */
static int cr_write_info(cr_run *run, cr_err *err)
{
    cr_frame_stats *list;
    int k, n = 0, rc;
    if (!cr_has_type(run, 'i'))
        return 0;
    list = malloc(sizeof *list * (size_t)(run->n_done > 0 ? run->n_done : 1));
    if (!list)
        return cr_err_set(err, "out of memory writing info.txt");
    for (k = 0; k < run->cli.frames; k++)
        if (run->done[k])
            list[n++] = run->stats[k];
    rc = cr_info_write(run->cli.output_dir, &run->info, &run->scene, &run->cfg, list, n, err);
    free(list);
    return rc;
}

/* Remove the files of frame k already written, types among "crd": a frame
 * that fails part-way (a full disk) leaves no file. */
static void cr_remove_frame_files(const cr_run *run, int k, const char *types)
{
    char name[64], path[4096];
    for (; *types; types++) {
        snprintf(name, sizeof name, "%c_%d.%s", *types, k, *types == 'd' ? "csv" : "png");
        if (cr_path_join(path, sizeof path, run->cli.output_dir, name) == 0)
            unlink(path);
    }
}

/* Render and write one frame. Returns 0, or -1 with err set (err->msg is
 * "interrupted" after Ctrl-C); a frame that fails leaves none of its files,
 * and info.txt lists only the frames whose files are all written. */
static int cr_do_frame(cr_worker *w, int k, cr_pixel *px, cr_sphere *spheres, cr_err *err)
{
    cr_run *run = w->run;
    cr_frame f;
    cr_frame_stats st;
    double t0;
    char written[4] = "";
    int n_written = 0, rc;
    if (cr_scene_frame(&run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                       (int)run->cli.height, &run->ts, &f, spheres, err))
        return -1;
    w->frame = k;
    w->t_frame = t0 = cr_now();
    if (w->device < 0) {
        if (cr_cpu_render(&f, run->threads, px, cr_progress, w, &cr_cancel_flag, err))
            return -1;
    } else {
        if (cr_gpu_render_ex(w->device, &f, px, cr_progress, w, &cr_cancel_flag, err))
            return -1;
    }
    cr_frame_stats_compute(px, (long long)f.width * f.height, cr_now() - t0, &st);
    st.frame = k;
    if (cr_has_type(run, 'c')) {
        if (cr_output_color_png(run->cli.output_dir, k, px, f.width, f.height, err))
            goto fail;
        written[n_written++] = 'c';
    }
    if (cr_has_type(run, 'r')) {
        if (cr_output_redshift_png(run->cli.output_dir, k, px, f.width, f.height, err))
            goto fail;
        written[n_written++] = 'r';
    }
    if (cr_has_type(run, 'd')) {
        if (cr_output_csv(run->cli.output_dir, k, px, f.width, f.height, err))
            goto fail;
        written[n_written++] = 'd';
    }

    pthread_mutex_lock(&run->lock);
    run->stats[k] = st;
    run->done[k] = 1;
    run->n_done++;
    rc = cr_write_info(run, err);
    if (rc) {
        run->done[k] = 0;
        run->n_done--;
    } else {
        long long rays = st.rays > 0 ? st.rays : 1;
        char where[32] = "";
        if (w->device >= 0)
            snprintf(where, sizeof where, " on GPU %d", w->device);
        cr_log_info(&run->log,
                    "frame %d/%ld done%s in %.2f s: %.3g rays/s, %.1f steps/ray, "
                    "horizon %lld, disc %lld, sphere %lld, sky %lld, error %lld, limit %lld",
                    k + 1, run->cli.frames, where, st.seconds,
                    (double)st.rays / (st.seconds > 0 ? st.seconds : 1e-9),
                    (double)st.steps / (double)rays, st.counts[CR_OUT_HORIZON],
                    st.counts[CR_OUT_DISC], st.counts[CR_OUT_SPHERE], st.counts[CR_OUT_SKY],
                    st.counts[CR_OUT_ERROR], st.counts[CR_OUT_LIMIT]);
    }
    pthread_mutex_unlock(&run->lock);
    if (rc == 0)
        return 0;
fail:
    cr_remove_frame_files(run, k, written);
    return -1;
}

static void *cr_worker_main(void *arg)
{
    cr_worker *w = arg;
    cr_run *run = w->run;
    size_t npx = (size_t)run->cli.width * (size_t)run->cli.height;
    cr_pixel *px = malloc(npx * sizeof *px);
    cr_sphere *spheres = malloc(sizeof *spheres * (size_t)(run->scene.n_spheres + 1));
    cr_err err;
    err.msg[0] = '\0';
    if (!px || !spheres) {
        cr_err_set(&err, "cannot allocate %.1f MiB for a %ldx%ld frame",
                   (double)(npx * sizeof *px) / (1 << 20), run->cli.width, run->cli.height);
        goto fail;
    }
    for (;;) {
        int k = atomic_fetch_add(&run->next_frame, 1);
        int stop;
        pthread_mutex_lock(&run->lock);
        stop = run->failed;
        pthread_mutex_unlock(&run->lock);
        if (stop || cr_cancel_flag || k >= run->cli.frames)
            break;
        if (cr_do_frame(w, k, px, spheres, &err))
            goto fail;
    }
    free(px);
    free(spheres);
    return NULL;
fail:
    pthread_mutex_lock(&run->lock);
    if (!run->failed) {
        run->failed = 1;
        run->fail_err = err;
    }
    pthread_mutex_unlock(&run->lock);
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
    return line[0] == '\n' || line[0] == 'y' || line[0] == 'Y';
}

static void cr_log_scene(cr_run *run)
{
    const cr_scene *s = &run->scene;
    const double deg = 180.0 / CR_PI;
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
    cr_log_info(&run->log, "%ld frame%s of %ldx%ld pixels, outputs '%s' into %s, backend %s",
                run->cli.frames, run->cli.frames > 1 ? "s" : "", run->cli.width,
                run->cli.height, run->cli.output_type, run->cli.output_dir, run->info.backend);
    cr_log_detail(&run->log, "raytracer: integrator %s, tolerance %g (mino), step multiplier %g "
                             "(rk4), horizon epsilon %g, max steps %ld, max turns %g; %d CPU "
                             "threads",
                  cr_integrator_name(run->ts.integrator), run->ts.tolerance,
                  run->ts.step_multiplier, run->ts.horizon_epsilon, run->ts.max_steps,
                  run->ts.max_turns, run->threads);
}

/* Refuse, before anything large is allocated, a run whose buffers cannot fit
 * in memory: per worker a frame of cr_pixel, plus the 8-bit image written
 * from it and the per-frame statistics. The limit is the physical memory, or
 * the address-space or data limit (ulimit -v, -d) when lower. */
static int cr_check_memory(const cr_run *run, int n_workers, cr_err *err)
{
    const double gib = 1024.0 * 1024.0 * 1024.0;
    double px = (double)run->cli.width * (double)run->cli.height;
    double need = px * ((double)sizeof(cr_pixel) * n_workers + 3.0) +
                  (double)run->cli.frames * (double)(sizeof(cr_frame_stats) + 1);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double have = pages > 0 && page > 0 ? (double)pages * (double)page : 0.0;
    const char *what = "the machine's memory";
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (have <= 0.0 || (double)rl.rlim_cur < have)) {
        have = (double)rl.rlim_cur;
        what = "the address-space limit (ulimit -v)";
    }
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (have <= 0.0 || (double)rl.rlim_cur < have)) {
        have = (double)rl.rlim_cur;
        what = "the data-size limit (ulimit -d)";
    }
    if (have > 0.0 && need > have)
        return cr_err_set(err,
                          "a %ldx%ld frame (%ld frame%s) needs about %.2f GiB of memory, more "
                          "than the %.2f GiB of %s; choose a smaller -x/-y",
                          run->cli.width, run->cli.height, run->cli.frames,
                          run->cli.frames > 1 ? "s" : "", need / gib, have / gib, what);
    return 0;
}

static int cr_prog_is_cpu(const char *argv0)
{
    const char *base = strrchr(argv0, '/');
    base = base ? base + 1 : argv0;
    return strcmp(base, "curray_cpu") == 0;
}

int main(int argc, char **argv)
{
    cr_run run;
    cr_err err;
    cr_worker workers[CR_MAX_GPUS];
    int n_workers = 0, k, rc = CR_EXIT_ERROR, log_open = 0;
    int devices[CR_MAX_GPUS];
    struct sigaction sa;
    char backend_name[64];

    memset(&run, 0, sizeof run);
    err.msg[0] = '\0';
    /* A reader that goes away (curray ... | head) must not kill a render
     * half-way: console writes then just fail. */
    signal(SIGPIPE, SIG_IGN);
    if (cr_cli_parse(argc, argv, cr_prog_is_cpu(argv[0]), &run.cli, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_USAGE;
    }
    if (run.cli.help) {
        cr_cli_usage(argv[0], stdout);
        return CR_EXIT_OK;
    }
    if (run.cli.version) {
        printf("curray %s\n", CURRAY_VERSION);
        return CR_EXIT_OK;
    }
    if (run.cli.info) {
        cr_gpu_print_info(stdout);
        if (!run.cli.scene_path) {
            printf("\nNo scene file specified, no raytracing will be performed.\n");
            return CR_EXIT_OK;
        }
    }
    if (cr_cli_check_render(&run.cli, &err)) {
        fprintf(stderr, "curray: %s\n", err.msg);
        return CR_EXIT_USAGE;
    }

    /* system configuration: -c, else config.yml when present, else defaults */
    cr_sysconfig_defaults(&run.cfg);
    if (run.cli.config_path || access("config.yml", F_OK) == 0) {
        if (!run.cli.config_path)
            run.cli.config_path = "config.yml";
        if (cr_sysconfig_load(run.cli.config_path, &run.cfg, &err)) {
            fprintf(stderr, "curray: configuration file %s\n", err.msg);
            return CR_EXIT_ERROR;
        }
    }
    if (run.cli.verbose >= 0)
        run.cfg.verbose = run.cli.verbose;
    if (run.cli.quiet >= 0)
        run.cfg.quiet = run.cli.quiet;
    if (run.cli.auto_accept >= 0)
        run.cfg.auto_accept = run.cli.auto_accept;
    run.threads = run.cli.threads > 0 ? (int)run.cli.threads
                                      : (run.cfg.cpu_threads > 0 ? run.cfg.cpu_threads
                                                                 : cr_cpu_cores());
    run.ts.integrator = run.cfg.integrator;
    run.ts.tolerance = run.cfg.tolerance;
    run.ts.step_multiplier = run.cfg.step_multiplier;
    run.ts.horizon_epsilon = run.cfg.horizon_epsilon;
    run.ts.max_steps = run.cfg.max_steps;
    run.ts.max_turns = run.cfg.max_turns;

    if (cr_log_open(&run.log, "log", run.cfg.keep_log, run.cfg.verbose, run.cfg.quiet, &err))
        fprintf(stderr, "curray: warning: %s (logging to the console only)\n", err.msg);
    log_open = 1;
    cr_log_detail(&run.log, "curray %s, configuration %s", CURRAY_VERSION,
                  run.cli.config_path ? run.cli.config_path : "(built-in defaults)");

    /* backend */
    if (run.cli.backend != CR_BACKEND_CPU) {
        cr_err gerr;
        int n = cr_gpu_count(&gerr), i;
        for (i = 0; i < n && i < CR_MAX_GPUS; i++)
            if (run.cfg.gpu_enabled[i])
                devices[n_workers++] = i;
        if (n_workers > 0) {
            run.use_cuda = 1;
        } else if (run.cli.backend == CR_BACKEND_CUDA) {
            cr_log_error(&run.log, "curray: --backend cuda: %s",
                         n == 0 ? gerr.msg : "no enabled GPU (see gpus: in the configuration)");
            goto done;
        } else {
            cr_log_detail(&run.log, "using the CPU: %s",
                          n == 0 ? gerr.msg : "no GPU enabled in the configuration");
        }
    }
    if (run.use_cuda)
        snprintf(backend_name, sizeof backend_name, "cuda (%d GPU%s)", n_workers,
                 n_workers > 1 ? "s" : "");
    else
        snprintf(backend_name, sizeof backend_name, "cpu (%d thread%s)", run.threads,
                 run.threads > 1 ? "s" : "");

    if (cr_check_memory(&run, run.use_cuda ? n_workers : 1, &err)) {
        cr_log_error(&run.log, "curray: %s", err.msg);
        goto done;
    }
    if (cr_scene_load(run.cli.scene_path, &run.scene, &err)) {
        cr_log_error(&run.log, "curray: scene file %s", err.msg);
        goto done;
    }
    /* every frame must be possible before any is rendered */
    {
        cr_sphere *tmp = malloc(sizeof *tmp * (size_t)(run.scene.n_spheres + 1));
        cr_frame f;
        if (!tmp) {
            cr_log_error(&run.log, "curray: out of memory");
            goto done;
        }
        for (k = 0; k < run.cli.frames; k++)
            if (cr_scene_frame(&run.scene, k, (int)run.cli.frames, (int)run.cli.width,
                               (int)run.cli.height, &run.ts, &f, tmp, &err))
                break;
        free(tmp);
        if (k < run.cli.frames) {
            cr_log_error(&run.log, "curray: scene file %s", err.msg);
            goto done;
        }
    }

    run.info.scene_path = run.cli.scene_path;
    run.info.config_path = run.cli.config_path;
    run.info.backend = backend_name;
    run.info.width = (int)run.cli.width;
    run.info.height = (int)run.cli.height;
    run.info.frames = (int)run.cli.frames;
    run.info.output_types = run.cli.output_type;
    run.info.version = CURRAY_VERSION;
    cr_log_scene(&run);

    if (!cr_confirm(&run)) {
        cr_log_info(&run.log, "not rendering (declined)");
        rc = CR_EXIT_OK;
        goto done;
    }
    if (cr_mkdir_p(run.cli.output_dir, &err)) {
        cr_log_error(&run.log, "curray: %s", err.msg);
        goto done;
    }

    run.stats = calloc((size_t)run.cli.frames, sizeof *run.stats);
    run.done = calloc((size_t)run.cli.frames, 1);
    if (!run.stats || !run.done) {
        cr_log_error(&run.log, "curray: out of memory for %ld frames", run.cli.frames);
        goto done;
    }
    pthread_mutex_init(&run.lock, NULL);
    atomic_init(&run.next_frame, 0);

    memset(&sa, 0, sizeof sa);
    sa.sa_handler = cr_on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    run.t_start = cr_now();
    if (!run.use_cuda)
        n_workers = 1;
    for (k = 0; k < n_workers; k++) {
        workers[k].run = &run;
        workers[k].device = run.use_cuda ? devices[k] : -1;
        workers[k].frame = 0;
    }
    if (n_workers == 1) {
        cr_worker_main(&workers[0]);
    } else {
        int started = 0;
        for (k = 0; k < n_workers; k++) {
            if (pthread_create(&workers[k].tid, NULL, cr_worker_main, &workers[k]) != 0)
                break;
            started++;
        }
        if (started == 0)
            cr_worker_main(&workers[0]);
        for (k = 0; k < started; k++)
            pthread_join(workers[k].tid, NULL);
    }
    pthread_mutex_destroy(&run.lock);

    if (cr_cancel_flag) {
        cr_log_error(&run.log, "curray: interrupted; %d of %ld frames finished and kept in %s",
                     run.n_done, run.cli.frames, run.cli.output_dir);
        rc = CR_EXIT_INTERRUPTED;
    } else if (run.failed) {
        cr_log_error(&run.log, "curray: %s", run.fail_err.msg);
        if (run.n_done)
            cr_log_error(&run.log, "curray: %d of %ld frames were finished and kept in %s",
                         run.n_done, run.cli.frames, run.cli.output_dir);
    } else {
        cr_log_info(&run.log, "done: %ld frame%s in %.2f s, outputs in %s", run.cli.frames,
                    run.cli.frames > 1 ? "s" : "", cr_now() - run.t_start, run.cli.output_dir);
        rc = CR_EXIT_OK;
    }

done:
    free(run.stats);
    free(run.done);
    cr_scene_free(&run.scene);
    if (log_open)
        cr_log_close(&run.log);
    return rc;
}
