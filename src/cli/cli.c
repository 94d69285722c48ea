#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <getopt.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../output/types.h"
#include "../input/sysconfig.h"

static int cr_parse_bool(const char *s, int *out)
{
    static const char *yes[] = {"true", "yes", "on", "1"}, *no[] = {"false", "no", "off", "0"};
    size_t i;
    for (i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        if (strcasecmp(s, yes[i]) == 0) {
            *out = 1;
            return 0;
        }
        if (strcasecmp(s, no[i]) == 0) {
            *out = 0;
            return 0;
        }
    }
    return -1;
}

static int cr_parse_long(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno || end == s || *end != '\0' || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* How an option's value is read (cr_cli_option.kind). */
typedef enum cr_opt_kind {
    CR_OPT_TEXT,    /* a string, kept as given */
    CR_OPT_NUMBER,  /* a whole number from 1 to max, else `bad` with max and the value */
    CR_OPT_BOOL,    /* true/false (cr_parse_bool); bare or before another option: true */
    CR_OPT_FLAG,    /* no value: sets 1 */
    CR_OPT_BACKEND, /* auto, cpu or cuda */
    CR_OPT_PIXEL    /* I,J: the column and row of --trace */
} cr_opt_kind;

/* The command line: one row per option, in the order of the help. It
 * drives getopt_long (the short-option string and the long options), the
 * help text and the checks of each value. */
typedef struct cr_cli_option {
    int key;           /* the short option's letter, or a value >= 1000 for a long one only */
    const char *name;  /* the long option, without "--" */
    cr_opt_kind kind;
    size_t field;      /* offsetof the cr_cli field it sets */
    const char *arg;   /* the value's name in the help, or NULL */
    const char *help;  /* the help, lines after the first indented; may hold one %d: the
                          thread limit */
    long max;          /* CR_OPT_NUMBER: the largest value */
    const char *bad;   /* CR_OPT_NUMBER: the message for a bad value (max, value) */
} cr_cli_option;

enum { OPT_VERSION = 1000, OPT_BACKEND, OPT_THREADS, OPT_RESUME, OPT_TRACE, OPT_EXAMPLE };

#define CR_F(field) offsetof(cr_cli, field)
static const cr_cli_option cr_cli_options[] = {
    {'s', "scene_file", CR_OPT_TEXT, CR_F(scene_path), "FILE", "scene to render (YAML, see README)",
     0, NULL},
    {'o', "output_dir", CR_OPT_TEXT, CR_F(output_dir), "DIR",
     "where outputs go (created if missing)", 0, NULL},
    {'x', "x_res", CR_OPT_NUMBER, CR_F(width), "N", "frame width in pixels", CR_MAX_SIDE,
     "-x: expected a width from 1 to %ld pixels, got '%s'"},
    {'y', "y_res", CR_OPT_NUMBER, CR_F(height), "N", "frame height in pixels", CR_MAX_SIDE,
     "-y: expected a height from 1 to %ld pixels, got '%s'"},
    {'f', "frames", CR_OPT_NUMBER, CR_F(frames), "N",
     "number of frames; animated values run from their\n"
     "start (frame 0) to their end (frame N-1); default 1",
     CR_MAX_FRAMES, "-f: expected a frame count from 1 to %ld, got '%s'"},
    {'t', "output_type", CR_OPT_TEXT, CR_F(output_type), "SET",
     "any of i (info.txt), c (c_<k>.png colour),\n"
     "r (r_<k>.png redshift), d (d_<k>.csv pixel data),\n"
     "f (f_<k>.fits: redshift, hit, outcome, steps, error),\n"
     "b (b_<k>.png bolometric g^4 F, Keplerian disc),\n"
     "n (n_<k>.png image order: direct image, rings),\n"
     "s (s_<k>.csv line profile and continuum, Keplerian disc),\n"
     "l (l_<k>.csv light curve: flux and centroid of the\n"
     "frame's emitting pixels, moving spheres and Keplerian disc);\n"
     "v (c.mp4, plus r.mp4 with r: MP4 videos);\n"
     "default icr",
     0, NULL},
    {'c', "config", CR_OPT_TEXT, CR_F(config_path), "FILE",
     "system configuration (default: config.yml if present)", 0, NULL},
    {'v', "verbose", CR_OPT_BOOL, CR_F(verbose), "BOOL",
     "more detail on the console and in the log", 0, NULL},
    {'q', "quiet", CR_OPT_BOOL, CR_F(quiet), "BOOL", "no console output (the log still gets it)",
     0, NULL},
    {'a', "auto_accept", CR_OPT_BOOL, CR_F(auto_accept), "BOOL", "do not ask before rendering", 0,
     NULL},
    {OPT_BACKEND, "backend", CR_OPT_BACKEND, CR_F(backend), "B",
     "auto (CUDA when a usable GPU exists), cpu or cuda", 0, NULL},
    {OPT_THREADS, "threads", CR_OPT_NUMBER, CR_F(threads), "N",
     "CPU threads, 1 to %d (overrides cpu.threads)", CR_SYSCONFIG_MAX_THREADS,
     "--threads: expected a number of threads from 1 to %ld, got '%s'"},
    {OPT_RESUME, "resume", CR_OPT_FLAG, CR_F(resume), NULL,
     "finish an interrupted run in the same output folder:\n"
     "render only the frames whose files are missing",
     0, NULL},
    {OPT_TRACE, "trace", CR_OPT_PIXEL, CR_F(trace), "I,J",
     "write the path of pixel (I, J)'s ray (column I from\n"
     "the left, row J from the top, from 0) to\n"
     "trace_<I>_<J>_<k>.csv per frame; no image, -t ignored",
     0, NULL},
    {'i', "info", CR_OPT_FLAG, CR_F(info), NULL, "list CUDA devices", 0, NULL},
    {'h', "help", CR_OPT_FLAG, CR_F(help), NULL, "this help", 0, NULL},
    {OPT_VERSION, "version", CR_OPT_FLAG, CR_F(version), NULL, "print the version", 0, NULL},
    {OPT_EXAMPLE, "example", CR_OPT_FLAG, CR_F(example), NULL,
     "print a complete, commented scene to start from\n"
     "(curray --example > my.yml)",
     0, NULL},
};
#undef CR_F
#define CR_CLI_N_OPTIONS (sizeof cr_cli_options / sizeof cr_cli_options[0])
#define CR_HELP_COLUMN 26 /* where the help of every option starts */

/* One option's lines of the help: "  -s, --scene_file FILE   scene ...". */
static void cr_cli_usage_option(const cr_cli_option *o, FILE *out)
{
    char head[64];
    const char *line = o->help, *end;
    int n = snprintf(head, sizeof head, "  %s%c%s--%s%s%s", o->key < 256 ? "-" : " ",
                     o->key < 256 ? o->key : ' ', o->key < 256 ? ", " : "  ", o->name,
                     o->arg ? " " : "", o->arg ? o->arg : "");
    fprintf(out, "%s%*s", head, n < CR_HELP_COLUMN ? CR_HELP_COLUMN - n : 1, "");
    for (;;) {
        end = strchr(line, '\n');
        if (strstr(line, "%d") && (!end || strstr(line, "%d") < end)) {
            char fmt[128];
            snprintf(fmt, sizeof fmt, "%.*s\n", end ? (int)(end - line) : (int)strlen(line),
                     line);
            fprintf(out, fmt, CR_SYSCONFIG_MAX_THREADS);
        } else {
            fprintf(out, "%.*s\n", end ? (int)(end - line) : (int)strlen(line), line);
        }
        if (!end)
            break;
        line = end + 1;
        fprintf(out, "%*s", CR_HELP_COLUMN, "");
    }
}

void cr_cli_usage(const char *prog, FILE *out)
{
    size_t k;
    fprintf(out,
            "Usage: %s -s <scene file> -o <output directory> -x <width> -y <height>\n"
            "          [-f <frames>] [-t <output types>] [-c <system configuration>]\n"
            "          [-v <true/false>] [-q <true/false>] [-a <true/false>]\n"
            "          [--backend auto|cpu|cuda] [--threads N] [--resume] [--trace I,J]\n"
            "          [-i] [-h] [--version] [--example] [--]\n"
            "\n",
            prog);
    for (k = 0; k < CR_CLI_N_OPTIONS; k++)
        cr_cli_usage_option(&cr_cli_options[k], out);
    fprintf(out, "  --%*s%s\n", CR_HELP_COLUMN - 4, "", "ignore the rest of the command line");
}

/* getopt_long's short options ("+:" first: stop at the first non-option,
 * report a missing value as ':') and long options, from the table. */
static void cr_cli_getopt_tables(char *shorts, struct option *longs)
{
    size_t k;
    char *p = shorts;
    *p++ = '+';
    *p++ = ':';
    for (k = 0; k < CR_CLI_N_OPTIONS; k++) {
        const cr_cli_option *o = &cr_cli_options[k];
        int arg = o->kind != CR_OPT_FLAG;
        if (o->key < 256) {
            *p++ = (char)o->key;
            if (arg)
                *p++ = ':';
        }
        longs[k].name = o->name;
        longs[k].has_arg = arg ? required_argument : no_argument;
        longs[k].flag = NULL;
        longs[k].val = o->key;
    }
    *p = '\0';
    memset(&longs[CR_CLI_N_OPTIONS], 0, sizeof longs[0]);
}

static const cr_cli_option *cr_cli_find(int key)
{
    size_t k;
    for (k = 0; k < CR_CLI_N_OPTIONS; k++)
        if (cr_cli_options[k].key == key)
            return &cr_cli_options[k];
    return NULL;
}

/* --trace I,J into c. 0, or -1. */
static int cr_parse_pixel(const char *s, cr_cli *c)
{
    char *end;
    errno = 0;
    c->trace_i = strtol(s, &end, 10);
    if (!errno && end != s && *end == ',' && end[1] != '\0') {
        const char *js = end + 1;
        c->trace_j = strtol(js, &end, 10);
        if (!errno && end != js && *end == '\0' && c->trace_i >= 0 && c->trace_j >= 0 &&
            c->trace_i < CR_MAX_SIDE && c->trace_j < CR_MAX_SIDE)
            return 0;
    }
    return -1;
}

/* The value of option o (optarg) into c. Returns 0, 1 when the value was
 * not this option's (a bare boolean before another option: the word is read
 * again), or -1 with err set. */
static int cr_cli_take(const cr_cli_option *o, char **argv, cr_cli *c, cr_err *err)
{
    void *field = (char *)c + o->field;
    switch (o->kind) {
    case CR_OPT_TEXT:
        *(const char **)field = optarg;
        return 0;
    case CR_OPT_NUMBER:
        if (cr_parse_long(optarg, 1, o->max, field))
            return cr_err_set(err, o->bad, o->max, optarg);
        return 0;
    case CR_OPT_FLAG:
        *(int *)field = 1;
        return 0;
    case CR_OPT_BACKEND:
        if (strcmp(optarg, "auto") == 0)
            c->backend = CR_BACKEND_AUTO;
        else if (strcmp(optarg, "cpu") == 0)
            c->backend = CR_BACKEND_CPU;
        else if (strcmp(optarg, "cuda") == 0)
            c->backend = CR_BACKEND_CUDA;
        else
            return cr_err_set(err, "--backend: expected auto, cpu or cuda, got '%s'", optarg);
        return 0;
    case CR_OPT_PIXEL:
        if (cr_parse_pixel(optarg, c))
            return cr_err_set(err, "--trace: expected a pixel I,J (column, row from 0), got '%s'",
                              optarg);
        c->trace = 1;
        return 0;
    case CR_OPT_BOOL:
        if (cr_parse_bool(optarg, field) == 0)
            return 0;
        if (optarg[0] == '-' && optarg == argv[optind - 1]) {
            /* "-v -s x": -v given without a value; the next word is an option,
             * read again. A value glued to its option ("-q-a", "--verbose=-x")
             * is that option's value, never an option of its own: stepping
             * back over it would read the same word forever. */
            *(int *)field = 1;
            optind--;
            return 1;
        }
        return cr_err_set(err, "-%c: expected true or false, got '%s'", o->key, optarg);
    }
    return 0;
}

int cr_cli_parse(int argc, char **argv, int prog_cpu_only, cr_cli *c, cr_err *err)
{
    char shorts[2 + 2 * CR_CLI_N_OPTIONS + 1];
    struct option longopts[CR_CLI_N_OPTIONS + 1];
    int opt;
    cr_cli_getopt_tables(shorts, longopts);
    memset(c, 0, sizeof *c);
    c->frames = 1;
    c->output_type = "icr";
    c->verbose = c->quiet = c->auto_accept = -1;
    c->backend = prog_cpu_only ? CR_BACKEND_CPU : CR_BACKEND_AUTO;
    /* getopt keeps its place inside a word between calls; glibc starts afresh
     * only at optind = 0 (else a parse that stopped inside "-Zi" would go on
     * in the old words), elsewhere optind = 1 is the reset */
#ifdef __GLIBC__
    optind = 0;
#else
    optind = 1;
#endif
    opterr = 0;
    while ((opt = getopt_long(argc, argv, shorts, longopts, NULL)) != -1) {
        const cr_cli_option *o = opt == ':' || opt == '?' ? NULL : cr_cli_find(opt);
        if (o) {
            if (cr_cli_take(o, argv, c, err) < 0)
                return -1;
            continue;
        }
        if (opt == ':') {
            o = cr_cli_find(optopt);
            if (o && o->kind == CR_OPT_BOOL) {
                /* a trailing -v/-q/-a without its value means true */
                *(int *)((char *)c + o->field) = 1;
                continue;
            }
            if (optopt)
                return cr_err_set(err, "option -%c needs a value (see -h)", optopt);
            return cr_err_set(err, "option %s needs a value (see -h)", argv[optind - 1]);
        }
        if (optopt)
            return cr_err_set(err, "unknown option -%c (see -h)", optopt);
        return cr_err_set(err, "unknown option %s (see -h)", argv[optind - 1]);
    }
    if (optind < argc && strcmp(argv[optind - 1], "--") != 0)
        return cr_err_set(err, "unexpected argument '%s' (see -h)", argv[optind]);
    return 0;
}

int cr_cli_check_render(const cr_cli *c, cr_err *err)
{
    if (!c->scene_path)
        return cr_err_set(err, "no scene file given (-s); see -h");
    if (!c->output_dir)
        return cr_err_set(err, "no output directory given (-o); see -h");
    if (!c->width || !c->height)
        return cr_err_set(err, "the frame size is required: -x <width> -y <height>");
    if (c->width * c->height > CR_MAX_PIXELS)
        return cr_err_set(err,
                          "a %ldx%ld frame has %ld pixels, more than the %ld this version renders "
                          "(it would need about %.1f GiB of memory)",
                          c->width, c->height, c->width * c->height, CR_MAX_PIXELS,
                          (double)c->width * c->height * 48.0 / (1 << 30));
    if (c->trace) {
        if (c->trace_i >= c->width || c->trace_j >= c->height)
            return cr_err_set(err, "--trace: pixel %ld,%ld is outside the %ldx%ld frame "
                                   "(0 <= I < %ld, 0 <= J < %ld)",
                              c->trace_i, c->trace_j, c->width, c->height, c->width, c->height);
        return 0; /* -t is not used */
    }
    return cr_output_types_check(c->output_type, err);
}

int cr_cli_answer_yes(const char *line)
{
    while (isspace((unsigned char)*line))
        line++;
    return *line == '\0' || *line == 'y' || *line == 'Y';
}

/* A variable's value as a whole decimal number >= 0, else -1. */
static long cr_env_count(const char *v)
{
    char *end;
    long n;
    if (!v || !*v)
        return -1;
    errno = 0;
    n = strtol(v, &end, 10);
    return (errno || *end || n < 0) ? -1 : n;
}

int cr_cli_mpi_launched(const char *(*env)(const char *), char *why, size_t n)
{
    static const char *const sizes[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE",
                                        "MV2_COMM_WORLD_SIZE"};
    static const char *const ranks[] = {"PMIX_RANK", "PMI_RANK"};
    size_t i;
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        long k = cr_env_count(env(sizes[i]));
        if (k > 1) {
            snprintf(why, n, "%s=%s", sizes[i], env(sizes[i]));
            return k > 1000000000L ? 1000000000 : (int)k;
        }
    }
    for (i = 0; i < sizeof ranks / sizeof ranks[0]; i++) {
        long k = cr_env_count(env(ranks[i]));
        if (k > 0) {
            snprintf(why, n, "%s=%s", ranks[i], env(ranks[i]));
            return -1;
        }
    }
    return 0;
}
