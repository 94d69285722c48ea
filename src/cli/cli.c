#include "cli.h"

#include <ctype.h>
#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../output/types.h"
#include "../input/sysconfig.h"

enum { OPT_VERSION = 1000, OPT_BACKEND, OPT_THREADS, OPT_RESUME, OPT_TRACE, OPT_EXAMPLE };

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

void cr_cli_usage(const char *prog, FILE *out)
{
    fprintf(out,
            "Usage: %s -s <scene file> -o <output directory> -x <width> -y <height>\n"
            "          [-f <frames>] [-t <output types>] [-c <system configuration>]\n"
            "          [-v <true/false>] [-q <true/false>] [-a <true/false>]\n"
            "          [--backend auto|cpu|cuda] [--threads N] [--resume] [--trace I,J]\n"
            "          [-i] [-h] [--version] [--example] [--]\n"
            "\n"
            "  -s, --scene_file FILE   scene to render (YAML, see README)\n"
            "  -o, --output_dir DIR    where outputs go (created if missing)\n"
            "  -x, --x_res N           frame width in pixels\n"
            "  -y, --y_res N           frame height in pixels\n"
            "  -f, --frames N          number of frames; animated values run from their\n"
            "                          start (frame 0) to their end (frame N-1); default 1\n"
            "  -t, --output_type SET   any of i (info.txt), c (c_<k>.png colour),\n"
            "                          r (r_<k>.png redshift), d (d_<k>.csv pixel data),\n"
            "                          f (f_<k>.fits: redshift, hit, outcome, steps, error),\n"
            "                          b (b_<k>.png bolometric g^4 F, Keplerian disc);\n"
            "                          v (c.mp4, plus r.mp4 with r: MP4 videos);\n"
            "                          default icr\n"
            "  -c, --config FILE       system configuration (default: config.yml if present)\n"
            "  -v, --verbose BOOL      more detail on the console and in the log\n"
            "  -q, --quiet BOOL        no console output (the log still gets it)\n"
            "  -a, --auto_accept BOOL  do not ask before rendering\n"
            "      --backend B         auto (CUDA when a usable GPU exists), cpu or cuda\n"
            "      --threads N         CPU threads, 1 to %d (overrides cpu.threads)\n"
            "      --resume            finish an interrupted run in the same output folder:\n"
            "                          render only the frames whose files are missing\n"
            "      --trace I,J         write the path of pixel (I, J)'s ray (column I from\n"
            "                          the left, row J from the top, from 0) to\n"
            "                          trace_<I>_<J>_<k>.csv per frame; no image, -t ignored\n"
            "  -i, --info              list CUDA devices\n"
            "  -h, --help              this help\n"
            "      --version           print the version\n"
            "      --example           print a complete, commented scene to start from\n"
            "                          (curray --example > my.yml)\n"
            "  --                      ignore the rest of the command line\n",
            prog, CR_SYSCONFIG_MAX_THREADS);
}

int cr_cli_parse(int argc, char **argv, int prog_cpu_only, cr_cli *c, cr_err *err)
{
    static const struct option longopts[] = {
        {"scene_file", required_argument, 0, 's'},
        {"output_dir", required_argument, 0, 'o'},
        {"x_res", required_argument, 0, 'x'},
        {"y_res", required_argument, 0, 'y'},
        {"frames", required_argument, 0, 'f'},
        {"output_type", required_argument, 0, 't'},
        {"config", required_argument, 0, 'c'},
        {"verbose", required_argument, 0, 'v'},
        {"quiet", required_argument, 0, 'q'},
        {"auto_accept", required_argument, 0, 'a'},
        {"info", no_argument, 0, 'i'},
        {"help", no_argument, 0, 'h'},
        {"version", no_argument, 0, OPT_VERSION},
        {"backend", required_argument, 0, OPT_BACKEND},
        {"threads", required_argument, 0, OPT_THREADS},
        {"resume", no_argument, 0, OPT_RESUME},
        {"trace", required_argument, 0, OPT_TRACE},
        {"example", no_argument, 0, OPT_EXAMPLE},
        {0, 0, 0, 0}};
    int opt;
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
    while ((opt = getopt_long(argc, argv, "+:s:o:x:y:f:t:c:v:q:a:ih", longopts, NULL)) != -1) {
        int *flag = NULL;
        switch (opt) {
        case 's': c->scene_path = optarg; break;
        case 'o': c->output_dir = optarg; break;
        case 't': c->output_type = optarg; break;
        case 'c': c->config_path = optarg; break;
        case 'x':
            if (cr_parse_long(optarg, 1, CR_MAX_SIDE, &c->width))
                return cr_err_set(err, "-x: expected a width from 1 to %ld pixels, got '%s'",
                                  CR_MAX_SIDE, optarg);
            break;
        case 'y':
            if (cr_parse_long(optarg, 1, CR_MAX_SIDE, &c->height))
                return cr_err_set(err, "-y: expected a height from 1 to %ld pixels, got '%s'",
                                  CR_MAX_SIDE, optarg);
            break;
        case 'f':
            if (cr_parse_long(optarg, 1, CR_MAX_FRAMES, &c->frames))
                return cr_err_set(err, "-f: expected a frame count from 1 to %ld, got '%s'",
                                  CR_MAX_FRAMES, optarg);
            break;
        case OPT_THREADS:
            if (cr_parse_long(optarg, 1, CR_SYSCONFIG_MAX_THREADS, &c->threads))
                return cr_err_set(err, "--threads: expected a number of threads from 1 to %d, "
                                       "got '%s'",
                                  CR_SYSCONFIG_MAX_THREADS, optarg);
            break;
        case OPT_TRACE: {
            char *end;
            errno = 0;
            c->trace_i = strtol(optarg, &end, 10);
            if (!errno && end != optarg && *end == ',' && end[1] != '\0') {
                const char *js = end + 1;
                c->trace_j = strtol(js, &end, 10);
                if (!errno && end != js && *end == '\0' && c->trace_i >= 0 && c->trace_j >= 0 &&
                    c->trace_i < CR_MAX_SIDE && c->trace_j < CR_MAX_SIDE) {
                    c->trace = 1;
                    break;
                }
            }
            return cr_err_set(err, "--trace: expected a pixel I,J (column, row from 0), got '%s'",
                              optarg);
        }
        case 'v': flag = &c->verbose; break;
        case 'q': flag = &c->quiet; break;
        case 'a': flag = &c->auto_accept; break;
        case 'i': c->info = 1; break;
        case 'h': c->help = 1; break;
        case OPT_VERSION: c->version = 1; break;
        case OPT_EXAMPLE: c->example = 1; break;
        case OPT_RESUME: c->resume = 1; break;
        case OPT_BACKEND:
            if (strcmp(optarg, "auto") == 0)
                c->backend = CR_BACKEND_AUTO;
            else if (strcmp(optarg, "cpu") == 0)
                c->backend = CR_BACKEND_CPU;
            else if (strcmp(optarg, "cuda") == 0)
                c->backend = CR_BACKEND_CUDA;
            else
                return cr_err_set(err, "--backend: expected auto, cpu or cuda, got '%s'", optarg);
            break;
        case ':':
            if (optopt == 'v' || optopt == 'q' || optopt == 'a') {
                /* a trailing -v/-q/-a without its value means true */
                *(optopt == 'v' ? &c->verbose : optopt == 'q' ? &c->quiet : &c->auto_accept) = 1;
                break;
            }
            if (optopt)
                return cr_err_set(err, "option -%c needs a value (see -h)", optopt);
            return cr_err_set(err, "option %s needs a value (see -h)", argv[optind - 1]);
        default:
            if (optopt)
                return cr_err_set(err, "unknown option -%c (see -h)", optopt);
            return cr_err_set(err, "unknown option %s (see -h)", argv[optind - 1]);
        }
        if (flag) {
            if (cr_parse_bool(optarg, flag) == 0)
                continue;
            if (optarg[0] == '-' && optarg == argv[optind - 1]) {
                /* "-v -s x": -v given without a value; the next word is an option,
                 * read again. A value glued to its option ("-q-a", "--verbose=-x")
                 * is that option's value, never an option of its own: stepping
                 * back over it would read the same word forever. */
                *flag = 1;
                optind--;
                continue;
            }
            return cr_err_set(err, "-%c: expected true or false, got '%s'", opt, optarg);
        }
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
