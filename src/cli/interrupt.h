/* curray cli: Ctrl-C (SIGINT) and SIGTERM during a render.
 *
 * The first signal sets the run's cancel flag, cr_interrupt.count, a C11
 * atomic_int that the renderers poll (the CPU backend before every pixel, so
 * a render stops within a pixel, about 0.05 s at most). Frames whose files
 * are being written are finished and kept; the frame being traced leaves no
 * file; main exits with status 130.
 *
 * A second signal stops at once: a stopper thread (started by
 * cr_interrupt_install, woken by the handler through a semaphore) closes the
 * output gate so that no new file is started, removes the temporary files
 * of the writes in progress (".<name>.tmp.<pid>.*" in the output folder,
 * the video being encoded among them,
 * fsutil.h) and the complete files of frames not yet finished, and ends the
 * process with _exit(130) without waiting for the render or the writes.
 * Writers announce each output file (cr_interrupt_file_begin/end), so the
 * stopper knows which temporaries belong to writes in progress; it waits
 * until each of them has appeared and been removed, or its write has ended,
 * for at most 5 s.
 *
 * State: the signal handler can reach only statics, so cr_interrupt_install
 * stores a pointer to the run's cr_interrupt in one static atomic pointer
 * (interrupt.c); everything else is owned by the run. One cr_interrupt is
 * installed at a time. */
#ifndef CR_CLI_INTERRUPT_H
#define CR_CLI_INTERRUPT_H

#include <pthread.h>
#include <semaphore.h>
#include <stdatomic.h>

#include "../base/error.h"
#include "../base/log.h"

/* One writer (a worker) and the file it is writing. */
#define CR_INTERRUPT_SLOTS 65
#define CR_INTERRUPT_FILES 8
typedef struct cr_interrupt_slot {
    int frame;                               /* frame whose files are being written, -1: none */
    int n_kept;                              /* its files already complete */
    char kept[CR_INTERRUPT_FILES][64];
    char writing[64];                        /* file being written, "" when none */
    int removed;                             /* its temporary was removed by the stopper */
} cr_interrupt_slot;

typedef struct cr_interrupt {
    atomic_int count;    /* signals received; > 0: stop (the run's cancel flag) */
    atomic_int quit;     /* the stopper thread should end (cr_interrupt_remove) */
    sem_t wake;          /* posted by the handler at the second signal, and by remove */
    pthread_t stopper;
    int stopper_running;
    cr_log *log;
    const char *dir;     /* output folder */
    pthread_mutex_t lock; /* guards closed and slot[] */
    int closed;           /* no new file may be started */
    cr_interrupt_slot slot[CR_INTERRUPT_SLOTS];
} cr_interrupt;

/* Set up *in for output folder dir (both must outlive the render), install
 * the handlers for SIGINT and SIGTERM and start the stopper thread. Returns
 * 0, or -1 with err set (nothing installed). */
int cr_interrupt_install(cr_interrupt *in, const char *dir, cr_log *log, cr_err *err);

/* Restore the default actions (when a signal has come: an action that ends
 * the process with status 130, so that one more signal while the stopped
 * run exits is not a death by the signal), end the stopper thread, free what
 * install made. The count stays readable. */
void cr_interrupt_remove(cr_interrupt *in);

/* The videos (made after the last frame, with the handlers still installed)
 * failed with msg: log why and return the exit status, 130 when a signal
 * stopped them (every frame is kept; --resume makes the videos), else 1. */
int cr_interrupt_video_failed(cr_interrupt *in, cr_log *log, const char *msg, long frames,
                              const char *dir);

/* 1 once a signal has come (relaxed atomic load; any thread). */
int cr_interrupt_requested(cr_interrupt *in);

/* Writer `slot` (0 to CR_INTERRUPT_SLOTS-1, one per worker) starts frame k's
 * files. */
void cr_interrupt_frame_begin(cr_interrupt *in, int slot, int k);
/* ... is about to write the file `name` in the output folder. Returns 0, or
 * -1 when the gate is closed (a second signal): then it must not write. */
int cr_interrupt_file_begin(cr_interrupt *in, int slot, const char *name);
/* ... has ended that write: kept = 1 when the file is complete and belongs to
 * the frame (removed on a hard stop until the frame is done); frame_done = 1
 * when this write completes the frame (info.txt lists it), whose files are
 * then kept whatever happens. */
void cr_interrupt_file_end(cr_interrupt *in, int slot, int kept, int frame_done);
/* ... gives up the frame (it failed and removed its files itself). */
void cr_interrupt_frame_end(cr_interrupt *in, int slot);

#endif
