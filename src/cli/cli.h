/* curray cli: the command line (E.1). */
#ifndef CR_CLI_CLI_H
#define CR_CLI_CLI_H

#include <stdio.h>

#include "../base/error.h"
#include "../render/backend.h" /* cr_backend_choice */

/* Parsed command line. Tri-state booleans: -1 = not given (use the system
 * configuration), 0 = false, 1 = true. */
typedef struct cr_cli {
    const char *scene_path;  /* -s */
    const char *output_dir;  /* -o */
    long width, height;      /* -x -y, 0 = not given */
    long frames;             /* -f, default 1 */
    const char *output_type; /* -t, default "icr" */
    const char *config_path; /* -c, NULL = config.yml when present */
    int verbose, quiet, auto_accept;
    int info, help, version;
    int example;             /* --example: print a scene to start from */
    cr_backend_choice backend;
    long threads;            /* --threads, 0 = from the configuration */
    int trace;               /* --trace i,j given: trace that pixel's path, no image */
    long trace_i, trace_j;   /* its column (from the left) and row (from the top) */
    int resume;              /* --resume: keep the frames an earlier run finished */
} cr_cli;

/* Largest frame accepted, in pixels per side and in total. */
#define CR_MAX_SIDE 65536L
#define CR_MAX_PIXELS (1L << 28)
#define CR_MAX_FRAMES 1000000L

/* Parse argv. prog_cpu_only: the program was started as curray_cpu, which
 * defaults to the CPU backend. Returns 0, or -1 with a message (usage error). */
int cr_cli_parse(int argc, char **argv, int prog_cpu_only, cr_cli *out, cr_err *err);

/* Check the values a render needs (-s -o -x -y present, sizes and frame
 * count sane, output types valid). Returns 0 or -1 with a message. */
int cr_cli_check_render(const cr_cli *c, cr_err *err);

void cr_cli_usage(const char *prog, FILE *out);

/* The answer to "Proceed with rendering? [Y/n]": 1 for yes (an empty or
 * blank line, or one whose first non-blank character is y or Y: " y",
 * "Yes\n"), 0 for anything else. */
int cr_cli_answer_yes(const char *line);

/* Was this process started by an MPI launcher (mpirun, mpiexec, srun with
 * PMI) as one of several? env reads the environment (getenv). Looks at
 * OMPI_COMM_WORLD_SIZE (Open MPI), PMI_SIZE (MPICH, Intel MPI, srun's PMI-2),
 * MV2_COMM_WORLD_SIZE (MVAPICH2), and PMIX_RANK / PMI_RANK above 0 (a
 * launcher that sets only ranks). Returns the number of processes (2 or
 * more; -1 when only a rank above 0 tells) with the variable that says so
 * in why[0..n), or 0 (none, or a size of 1). */
int cr_cli_mpi_launched(const char *(*env)(const char *), char *why, size_t n);

#endif
