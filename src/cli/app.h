/* curray cli: the state of one command-line run and its steps (main.c calls
 * them in order: parse, configure, plan, confirm, run, videos, report).
 *
 * setup.c: the command line, the configuration, the backend choice, the
 * checks before anything is rendered, the summary, the output folder.
 * frames.c: the run itself over the frame stack (render/run.h): each
 * frame's files, info.txt, progress lines; MPI ranks; --trace; videos; the
 * last line. Frames are counted from 0 everywhere. */
#ifndef CR_CLI_APP_H
#define CR_CLI_APP_H

#include <pthread.h>

#include "../base/limits.h"
#include "../base/log.h"
#include "../input/scene.h"
#include "../input/sysconfig.h"
#include "../output/info.h"
#include "../render/backend.h"
#include "../render/run.h"
#include "cli.h"
#include "interrupt.h"
#include "lock.h"
#include "resume.h"

#define CR_EXIT_OK 0
#define CR_EXIT_ERROR 1
#define CR_EXIT_USAGE 2
#define CR_EXIT_INTERRUPTED 130

/* The frame a writer slot has in progress, for the progress lines. */
typedef struct cr_slot_progress {
    int frame;
    double frac; /* its finished part, 0..1; guarded by cr_run.lock */
} cr_slot_progress;

typedef struct cr_run {
    int argc;
    char **argv;
    cr_cli cli;
    cr_sysconfig cfg;
    int config_found; /* config.yml was read from the current folder (no -c) */
    cr_scene scene;
    cr_log log;
    int log_open;
    cr_run_info info;
    char hash[17];        /* the run hash (resume.h) */
    char *stale;          /* stale frame files in the output folder, or NULL */
    cr_resume resume;     /* --resume: the frames kept from the earlier run */
    cr_dirlock dirlock;   /* the output folder, this run's alone (lock.h) */
    int n_kept;           /* how many */
    char frame_types[16]; /* the per-frame types written (cr_output_frame_letters) */
    cr_frame ends[2];     /* frames 0 and n-1 (cr_check_frames), for info.txt */
    /* MPI (render/mpi.h): this rank and the number of ranks (0 of 1 without
     * MPI), on this node too (cr_gpu_for_local_rank) */
    int mpi_rank, mpi_size;
    int mpi_local_rank, mpi_local_size;
    int mpi_served;  /* rank 0 served every other rank to the end */
    cr_info infotxt; /* info.txt: begun before the first frame, ended after the last */
    cr_trace_settings ts;
    char backend_name[64];
    char *settings; /* the run's settings as text, for the crash report */
    int use_cuda;
    int threads;    /* CPU threads in use (--threads, else cpu.threads, else all cores) */
    int n_workers;  /* backends of this process; slot n_workers writes other ranks' frames */
    int devices[CR_MAX_GPUS];
    cr_backend backends[CR_MAX_GPUS];
    cr_slot_progress slot[CR_MAX_GPUS + 1];
    cr_interrupt intr; /* Ctrl-C; intr.count is the run's cancel flag */
    cr_stack stack;
    pthread_mutex_t lock;  /* guards slot[], stats, done, n_done and info.txt */
    cr_frame_stats *stats; /* per frame */
    char *done;            /* per frame */
    char *kept;            /* per frame: kept by --resume, not traced */
    int n_done;
    int failed;
    cr_err fail_err;
    double t_start;
} cr_run;

double cr_now(void);

/* Does the run write output type t? A video (v) is made from the colour
 * frames, so v implies c. */
int cr_has_type(const cr_run *run, char t);
/* Whether the run's output types read pixels for their values (-t d, the
 * CSV; -t f, FITS; -t s, the spectrum; -t l, the light curve): its frames
 * are science frames (cr_frame.science). */
int cr_run_science(const cr_run *run);

/* Is frame k one that --resume keeps from the earlier run? */
int cr_frame_kept(const cr_run *run, int k);

/* setup.c. Each returns 0 to go on, or -1 when the run ends now with *rc. */
int cr_command_line(cr_run *run, int *rc);

/* `curray orbit ...` (orbit.c): argv[0] is "orbit". Returns the exit status. */
int cr_orbit_command(int argc, char **argv);
int cr_configure_run(cr_run *run, int *rc);
int cr_plan(cr_run *run, int *rc);
int cr_confirm_run(cr_run *run, int *rc);

/* frames.c */
int cr_render_frames(cr_run *run, cr_err *err);
int cr_mpi_rank_main(cr_run *run);
int cr_trace_paths(cr_run *run);
int cr_make_videos(cr_run *run, cr_err *err);
int cr_report(cr_run *run);

#endif
