/* curray: command-line front end.
 *
 * Reads the command line, the system configuration and the scene; checks
 * every frame before anything is rendered; asks to proceed (E.1); renders the
 * stack of frames on the CPU or on one host thread per enabled GPU (6.2);
 * writes c_<k>.png, r_<k>.png, d_<k>.csv and info.txt atomically, and the log
 * in <output folder>/log/. Frames are counted from 0 everywhere: file names,
 * console, log, info.txt and messages.
 *
 * The steps, in order (app.h): parse, configure, plan, confirm, run,
 * videos, report. A run of several MPI ranks is the same program on every
 * rank: rank 0 runs every step, the others trace what rank 0 hands out; a
 * run of one process is rank 0 of 1.
 *
 * Exit status: 0 done; 1 a run-time error (input, output, device); 2 a usage
 * error; 130 interrupted (Ctrl-C or SIGTERM: finished frames are kept, the
 * frame in progress leaves no file; a second Ctrl-C stops at once, still
 * without partial files); a crash dies by its signal after writing
 * <output folder>/log/crash-<time>-<pid>.log (crash.h).
 */
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "../render/mpi.h"
#include "app.h"
#include "crash.h"

/* Everything up to the render: configuration, backend, scene, frames,
 * summary, prompt, output folder. Returns -1 with *rc when the run ends
 * before rendering. */
static int cr_prepare(cr_run *run, int *rc)
{
    if (cr_configure_run(run, rc) || cr_plan(run, rc))
        return -1;
    if (run->mpi_rank > 0)
        return 0; /* the other MPI ranks only trace */
    return cr_confirm_run(run, rc);
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

/* Rank 0's render, then (all frames done) the videos. Returns the exit
 * status. */
static int cr_run_frames(cr_run *run)
{
    cr_err err;
    int rc;
    if (cr_render_frames(run, &err)) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        return CR_EXIT_ERROR;
    }
    rc = cr_report(run);
    if (rc == CR_EXIT_OK && cr_has_type(run, 'v') && cr_make_videos(run, &err))
        rc = cr_interrupt_video_failed(&run->intr, &run->log, err.msg, run->cli.frames,
                                       run->cli.output_dir);
    return rc;
}

/* What the run holds, freed; info.txt synced (its records are on disk).
 * Returns rc, or CR_EXIT_ERROR when info.txt cannot be synced. */
static int cr_run_end(cr_run *run, int rc)
{
    cr_err err;
    cr_interrupt_remove(&run->intr);
    if (cr_info_end(&run->infotxt, &err) && run->log_open) {
        cr_log_error(&run->log, "curray: %s", err.msg);
        rc = CR_EXIT_ERROR;
    }
    cr_crash_uninstall();
    cr_dirlock_release(&run->dirlock);
    free(run->settings);
    free(run->stale);
    cr_resume_free(&run->resume);
    free(run->stats);
    free(run->done);
    free(run->kept);
    cr_scene_free(&run->scene);
    if (run->log_open)
        cr_log_close(&run->log);
    return rc;
}

int main(int argc, char **argv)
{
    cr_run run;
    int rc, ready = 0;

    if (argc > 1 && strcmp(argv[1], "orbit") == 0)
        return cr_orbit_command(argc - 1, argv + 1);
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
        if (run.cli.trace)
            rc = run.mpi_rank == 0 ? cr_trace_paths(&run) : rc;
        else if (run.mpi_rank > 0)
            rc = cr_mpi_rank_main(&run);
        else
            rc = cr_run_frames(&run);
    }
    rc = cr_run_end(&run, rc);
    /* rank 0 stopped before every rank was told to stop (Ctrl-C, a rank
     * died): end them all; the finished frames are on disk */
    if (run.mpi_size > 1 && run.mpi_rank == 0 && ready && !run.cli.trace && !run.mpi_served)
        cr_mpi_abort(rc);
    cr_mpi_finalize();
    return rc;
}
