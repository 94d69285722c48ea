/* curray cli: everything before the render (app.h): the command line, the
 * system configuration, the backend, the scene and its frames checked, the
 * output folder checked, the summary and the prompt (E.1), the output
 * folder, log file and crash handler. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../base/fsutil.h"
#include "../base/memcheck.h"
#include "../output/fits.h"
#include "../output/spectrum.h"
#include "../output/types.h"
#include "../output/video.h"
#include "../render/cpu.h"
#include "../render/gpu.h"
#include "../render/mpi.h"
#include "app.h"
#include "crash.h"
#include "example.h"

static int cr_prog_is_cpu(const char *argv0)
{
    const char *base = strrchr(argv0, '/');
    base = base ? base + 1 : argv0;
    return strcmp(base, "curray_cpu") == 0;
}

#ifndef CURRAY_MPI
static const char *cr_getenv(const char *name)
{
    return getenv(name);
}
#endif

/* A curray built without MPI that an MPI launcher started as one of several
 * processes (cr_cli_mpi_launched) would render the whole run in each of
 * them, into the same folder: refuse (1), pointing to curray_mpi. One
 * process (a size of 1) is fine (0). curray_mpi itself is started that way. */
static int cr_refuse_mpi_launch(const char *argv0)
{
#ifdef CURRAY_MPI
    (void)argv0;
    return 0;
#else
    char why[96], many[32] = "several";
    int n = cr_cli_mpi_launched(cr_getenv, why, sizeof why);
    if (n == 0)
        return 0;
    if (n > 1)
        snprintf(many, sizeof many, "%d", n);
    fprintf(stderr,
            "curray: %s was started by an MPI launcher as one of %s processes (%s), but it is "
            "built without MPI: each would render the whole run into the same folder. Under "
            "mpirun or srun start curray_mpi instead (mpirun -np %s curray_mpi ..., built when "
            "CMake finds MPI; see docs/clusters.md), or start it once, without the launcher\n",
            argv0, many, why, n > 1 ? many : "N");
    return 1;
#endif
}

/* Parse the command line and answer -h, --version and -i. Returns -1 when
 * the program should end now with *rc, else 0 (a render follows). */
int cr_command_line(cr_run *run, int *rc)
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
    if (cr_refuse_mpi_launch(run->argv[0])) {
        *rc = CR_EXIT_ERROR;
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
        if (!run->cli.config_path) {
            run->cli.config_path = "config.yml";
            run->config_found = 1;
        }
        if (cr_sysconfig_load(run->cli.config_path, &run->cfg, err))
            return -1;
    }
    if (run->cli.verbose >= 0)
        run->cfg.verbose = run->cli.verbose;
    if (run->cli.quiet >= 0)
        run->cfg.quiet = run->cli.quiet;
    if (run->cli.auto_accept >= 0)
        run->cfg.auto_accept = run->cli.auto_accept;
    run->threads = cr_backend_cpu_threads(run->cli.threads, run->cfg.cpu_threads);
    run->ts = run->cfg.raytracer;
    return 0;
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
 * (cr_backend_choose; in an MPI run one GPU per rank, cr_mpi_gpus). Fills
 * devices, n_workers, use_cuda and backend_name. */
static int cr_choose_backend(cr_run *run)
{
    cr_err gerr;
    int n;
    run->use_cuda = 0;
    run->n_workers = 1;
    if (run->cli.backend != CR_BACKEND_CPU) {
        n = cr_backend_choose(run->cli.backend, run->cfg.gpu_enabled, CR_MAX_GPUS, run->devices,
                              CR_MAX_GPUS, &gerr);
        if (n < 0)
            n = 0; /* --backend cuda without a GPU: refused below, after MPI's collective */
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
        snprintf(run->backend_name, sizeof run->backend_name, "cpu (%d thread%s, %s)",
                 run->threads, run->threads > 1 ? "s" : "",
                 cr_cpu_simd_name(cr_cpu_simd_configure(run->cfg.raytracer.simd)));
    return 0;
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
        need += 3.0 * ((double)run->scene.sky_width * (double)run->scene.sky_height +
                       (double)run->scene.sky_other_width * (double)run->scene.sky_other_height);
    need += (double)(n_workers * (run->use_cuda ? 1 : run->threads) + n_workers + 1) *
            cr_mem_thread_stack();
    if (cr_cpu_memory_check(need, &mem))
        return cr_err_set(err, "a %ldx%ld frame (%ld frame%s) %s; choose a smaller -x/-y",
                          run->cli.width, run->cli.height, run->cli.frames,
                          run->cli.frames > 1 ? "s" : "", mem.msg);
    return 0;
}

/* Every frame must be possible before any is rendered. */
static int cr_check_frames(cr_run *run, cr_err *err)
{
    cr_frame_eval e = {0};
    const cr_frame *f = &e.frame;
    int k, rc = 0;
    int shrunk = -1;
    double eps_min = 0.0;
    for (k = 0; k < run->cli.frames && rc == 0; k++) {
        rc = cr_frame_eval_at(&e, &run->scene, k, (int)run->cli.frames, (int)run->cli.width,
                              (int)run->cli.height, &run->ts, err);
        if (rc == 0 && (k == 0 || k == run->cli.frames - 1)) {
            /* the first and last frame, for info.txt (spheres not kept) */
            run->ends[k > 0] = *f;
            run->ends[k > 0].spheres = NULL;
            if (run->cli.frames == 1)
                run->ends[1] = run->ends[0];
        }
        if (rc == 0 && f->horizon_epsilon < run->ts.horizon_epsilon &&
            (shrunk < 0 || f->horizon_epsilon < eps_min)) {
            shrunk = k;
            eps_min = f->horizon_epsilon;
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
    cr_frame_eval_free(&e);
    return rc;
}

/* accretion.exposure: auto: the factor for the whole run, from a preview of
 * frame 0 (cr_scene_auto_exposure), before any frame is evaluated. */
static int cr_exposure(cr_run *run, cr_err *err)
{
    long lit;
    if (!run->scene.disc_exposure_auto)
        return 0;
    if (cr_scene_auto_exposure(&run->scene, (int)run->cli.frames, (int)run->cli.width,
                               (int)run->cli.height, &run->ts, &lit, err))
        return -1;
    if (lit > 0)
        cr_log_detail(&run->log, "accretion.exposure: auto: %.6g from %ld lit disc pixels of frame "
                                 "0 traced %d pixels across",
                      run->scene.disc_exposure_found, lit, CR_AUTO_EXPOSURE_WIDTH);
    else
        cr_log_info(&run->log, "curray: warning: accretion.exposure: auto: no lit disc pixel in "
                               "frame 0 (traced %d pixels across), so the exposure is 1",
                    CR_AUTO_EXPOSURE_WIDTH);
    return 0;
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

/* The observer's motion for the summary: "static", "zamo", "orbit
 * (prograde)", "infall", "velocity [v_r, v_theta, v_phi] c (ZAMO frame)". */
static void cr_summary_motion(const cr_scene *s, const cr_observer *o, char *buf, size_t n)
{
    if (s->obs_motion == CR_MOTION_VELOCITY)
        snprintf(buf, n, "moving at [%g, %g, %g] c (v_r, v_theta, v_phi in the ZAMO frame)",
                 o->v[0], o->v[1], o->v[2]);
    else if (s->obs_motion == CR_MOTION_ORBIT)
        snprintf(buf, n, "on a %s circular orbit", s->obs_retrograde ? "retrograde" : "prograde");
    else if (s->obs_motion == CR_MOTION_INFALL)
        snprintf(buf, n, "falling in from rest at infinity");
    else if (s->obs_motion == CR_MOTION_ZAMO)
        snprintf(buf, n, "zamo (zero angular momentum)");
    else
        snprintf(buf, n, "static");
}

/* The observer's view for the summary: the projection with the fields of
 * view frame 0 uses (the vertical one derived when not given). */
static void cr_summary_view(const cr_observer *o, char *buf, size_t n)
{
    const double deg = 180.0 / CR_PI;
    if (o->projection == CR_PROJ_EQUIRECT)
        snprintf(buf, n, "equirectangular projection, the full sphere (360 x 180 deg)");
    else
        snprintf(buf, n, "%s projection, %.4g x %.4g deg",
                 o->projection == CR_PROJ_FISHEYE ? "fisheye (equidistant)" : "rectilinear",
                 o->hfov * deg, o->vfov * deg);
}

/* The disc for the summary, in the scene's units (m: frame 0's M; the
 * frame's radii are in units of M). */
static void cr_summary_disc(const cr_scene *s, const cr_frame *f, double m, char *buf, size_t n)
{
    const cr_disc *d = &f->disc;
    const char *sense = s->disc_retrograde ? "retrograde" : "prograde";
    char from[96], lum[128], expo[48] = "";
    if (s->disc_model != CR_DISC_KEPLERIAN) {
        snprintf(buf, n, "chessboard disc from r = %g to %g, %dx%d squares", d->r_in * m,
                 d->r_out * m, s->disc_n_radial, s->disc_n_sectors);
        return;
    }
    if (s->disc_has_r_in && d->r_in > d->r_isco)
        snprintf(from, sizeof from, "r = %g", d->r_in * m);
    else if (s->disc_has_r_in)
        snprintf(from, sizeof from, "the ISCO r = %.6g (the inner radius %g lies inside it)",
                 d->r_isco * m, cr_anim_at(s->disc_r_in, 0, 1));
    else
        snprintf(from, sizeof from, "the ISCO r = %.6g", d->r_isco * m);
    if (s->disc_mass_msun > 0.0)
        snprintf(lum, sizeof lum, "%g solar masses at %g Eddington: peak temperature %.4g K",
                 s->disc_mass_msun, s->disc_mdot_edd, d->t_peak);
    else
        snprintf(lum, sizeof lum, "peak temperature %g K", d->t_peak);
    if (s->disc_exposure_auto)
        snprintf(expo, sizeof expo, ", exposure auto (%.4g)", s->disc_exposure_found);
    else if (s->disc_exposure.a != 1.0 || s->disc_exposure.b != 1.0)
        snprintf(expo, sizeof expo, ", exposure %g", cr_anim_at(s->disc_exposure, 0, 1));
    snprintf(buf, n, "keplerian disc (%s orbits) from %s to %g, %s%s%s", sense, from,
             d->r_out * m, lum, s->disc_plunge ? ", plunging matter inside the ISCO" : "",
             expo);
}

/* The summary before "Proceed?" (E.1): the configuration file when one is
 * read, the scene with frame 0's values (the observer's motion and view,
 * the disc as traced), the sky, and the run. */
static void cr_log_scene(cr_run *run)
{
    const cr_scene *s = &run->scene;
    const cr_frame *f = &run->ends[0];
    const double deg = 180.0 / CR_PI, m = cr_anim_at(s->m, 0, (int)run->cli.frames);
    const char *f0 = run->cli.frames > 1 ? " (frame 0)" : "";
    char range[48] = "", motion[128], view[128], disc[400];
    if (run->config_found)
        cr_log_info(&run->log, "configuration config.yml (found in the current folder; -c FILE "
                               "reads another)");
    else if (run->cli.config_path)
        cr_log_info(&run->log, "configuration %s", run->cli.config_path);
    cr_log_info(&run->log, "scene %s: M = %g, a = %g, Q = %g%s", s->path, s->m.a, s->a.a, s->q.a,
                (s->m.a != s->m.b || s->a.a != s->a.b || s->q.a != s->q.b) ? " (animated)" : "");
    if (s->obs_at_infinity) {
        cr_log_info(&run->log,
                    "observer at infinity, theta = %g deg, phi = %g deg, image plane %g wide, %g high%s",
                    s->obs_theta.a * deg, s->obs_phi.a * deg, f->observer.hextent * m,
                    f->observer.vextent * m, f0);
    } else {
        cr_summary_motion(s, &f->observer, motion, sizeof motion);
        cr_summary_view(&f->observer, view, sizeof view);
        cr_log_info(&run->log, "observer at r = %g, theta = %g deg, phi = %g deg, %s, %s%s",
                    s->obs_r.a, s->obs_theta.a * deg, s->obs_phi.a * deg, motion, view, f0);
    }
    if (s->roll.a != 0.0 || s->pitch.a != 0.0 || s->yaw.a != 0.0)
        cr_log_info(&run->log, "camera roll = %g deg, pitch = %g deg, yaw = %g deg%s",
                    s->roll.a * deg, s->pitch.a * deg, s->yaw.a * deg, f0);
    if (s->has_disc) {
        cr_summary_disc(s, f, m, disc, sizeof disc);
        cr_log_info(&run->log, "%s%s", disc, f0);
    }
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
        if (!cr_video_available(err))
            return -1;
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

/* The configuration and the log (console now, the file once the output
 * folder exists, log.h). */
int cr_configure_run(cr_run *run, int *rc)
{
    cr_err err;
    err.msg[0] = '\0';
    *rc = CR_EXIT_ERROR;
    if (cr_configure(run, &err)) {
        fprintf(stderr, "curray: configuration file %s\n", err.msg);
        cr_mpi_skip_gpus(run);
        return -1;
    }
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
    return 0;
}

/* The backend, the memory the run needs, the scene and every frame of it
 * checked before any is rendered (on every MPI rank). */
int cr_plan(cr_run *run, int *rc)
{
    cr_err err;
    err.msg[0] = '\0';
    *rc = CR_EXIT_ERROR;
    if (cr_choose_backend(run))
        return -1;
    if (cr_check_memory(run, run->n_workers, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if (cr_scene_load(run->cli.scene_path, &run->scene, &err) || cr_exposure(run, &err) ||
        cr_check_frames(run, &err)) {
        cr_log_error(&run->log, "curray: scene file %s", err.msg);
        return -1;
    }
    if (cr_output_types_has(run->cli.output_type, 's') && cr_spectrum_check(&run->scene, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    if (run->scene.sky_rgb && cr_check_memory(run, run->n_workers, &err)) { /* with the sky */
        cr_log_error(&run->log, "curray: %s", err.msg);
        return -1;
    }
    return 0;
}

/* What info.txt describes besides the scene and configuration. */
static void cr_describe_run(cr_run *run)
{
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
}

/* Rank 0: the output folder checked, info.txt's header, the summary and
 * the prompt; then the output folder, the log file and the crash handler. */
int cr_confirm_run(cr_run *run, int *rc)
{
    cr_err err;
    int n;
    err.msg[0] = '\0';
    *rc = CR_EXIT_ERROR;
    cr_describe_run(run);
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
