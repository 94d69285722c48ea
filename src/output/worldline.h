/* curray io: the worldline of an orbit file (particle_spec.h), sampled at
 * equal steps of proper time, and its CSV (docs/outputs.md, "Worldlines").
 *
 * Rows: tau, t, r, theta, phi, x, y, z, u^t, u^r, u^theta, u^phi (proper
 * time, BL coordinate time and position with phi continuous, the Cartesian
 * position of coords.h, the 4-velocity), at tau = k dtau from 0 to the
 * span tau, and a last row where the worldline ended earlier (the horizon
 * stop or r_max) or where the span ends between two samples.
 */
#ifndef CR_OUTPUT_WORLDLINE_H
#define CR_OUTPUT_WORLDLINE_H

#include "../base/atomic.h"
#include "../base/error.h"
#include "../input/particle_spec.h"

#define CR_WL_COLS 12

/* Column names of the CSV header, in row order. */
extern const char *const cr_worldline_columns[CR_WL_COLS];

/* What a run found besides its rows. */
typedef struct cr_worldline_info {
    double E, L, K;  /* the constants of the worldline */
    int ended;       /* CR_PARTICLE_RUNNING (followed the whole span), _HORIZON, _ESCAPED */
    long steps;      /* integrator steps */
    long rows;
} cr_worldline_info;

/* Integrate the worldline of s, calling emit(ctx, row) for each row in
 * order (a non-zero return stops the run: -1, err untouched). Returns 0, or
 * -1 with err set when the integration fails. */
int cr_worldline_run(const cr_particle_spec *s, int (*emit)(void *ctx, const double *row),
                     void *ctx, cr_worldline_info *info, cr_err *err);

/* Write the worldline of s as CSV to path (atomically: a failed run leaves
 * no file). */
int cr_worldline_write_csv(const cr_particle_spec *s, const char *path, cr_worldline_info *info,
                           cr_err *err);

/* The same into the atomic file *a opened here for path, handing each row
 * to tap(ctx, row) as well (tap may be NULL; a non-zero return stops the
 * run with err set by tap), and leaving the complete file uncommitted on
 * success: the caller commits or aborts *a (cr_atomic_commit, _abort), so
 * that files written together appear together. On failure nothing is
 * left. */
int cr_worldline_write_csv_open(const cr_particle_spec *s, const char *path,
                                int (*tap)(void *ctx, const double *row), void *ctx,
                                cr_atomic *a, cr_worldline_info *info, cr_err *err);

#endif
