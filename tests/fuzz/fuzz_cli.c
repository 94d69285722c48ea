/* libFuzzer target: the command line (src/cli/cli.c, appendix E.1).
 *
 * Each input is a command line: its words separated by NUL bytes (a trailing
 * NUL ends the last word; at most FUZZ_CLI_MAX_WORDS words), each copied to
 * a buffer of its exact size so that AddressSanitizer sees a read past a
 * word's end. "curray" is argv[0]. The line is parsed with cr_cli_parse and,
 * when it parses, checked with cr_cli_check_render. Besides crashes,
 * sanitizer reports and hangs (libFuzzer's -timeout), the target aborts when
 * a contract of cli.h is broken: a status other than 0 or -1, a failure
 * without a message, or an accepted line whose values are out of range or
 * point outside its words. tests/fuzz/replay.c runs this same function over
 * files in ordinary builds (the regression test).
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "input/sysconfig.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_CLI_MAX_WORDS 64

#define CHECK(cond)                                                                             \
    do {                                                                                        \
        if (!(cond)) {                                                                          \
            fprintf(stderr, "fuzz_cli: contract broken: %s (line %d)\n", #cond, __LINE__);      \
            abort();                                                                            \
        }                                                                                       \
    } while (0)

/* 1 when s points inside one of the words argv[1..argc). */
static int in_words(const char *s, char **argv, int argc)
{
    int i;
    for (i = 1; i < argc; i++) {
        size_t n = strlen(argv[i]);
        if (s >= argv[i] && s <= argv[i] + n)
            return 1;
    }
    return 0;
}

static void check_failure(int rc, const cr_err *err)
{
    CHECK(rc == -1);
    CHECK(memchr(err->msg, '\0', sizeof err->msg) != NULL);
    CHECK(err->msg[0] != '\0');
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *argv[FUZZ_CLI_MAX_WORDS + 2];
    int argc = 1, rc, i;
    size_t at = 0;
    cr_cli c;
    cr_err err;
    char prog[] = "curray";

    argv[0] = prog;
    while (at < size && argc <= FUZZ_CLI_MAX_WORDS) {
        const uint8_t *end = memchr(data + at, '\0', size - at);
        size_t n = end ? (size_t)(end - (data + at)) : size - at;
        char *w = malloc(n + 1);
        if (!w)
            break;
        memcpy(w, data + at, n);
        w[n] = '\0';
        argv[argc++] = w;
        at += n + 1;
    }
    argv[argc] = NULL;

    memset(&c, 0x5a, sizeof c);
    err.msg[0] = '\0';
    rc = cr_cli_parse(argc, argv, (int)(size & 1), &c, &err);
    if (rc != 0) {
        check_failure(rc, &err);
        goto done;
    }
    /* every string is a word's, or NULL: but the default output types */
    CHECK(in_words(c.output_type, argv, argc) || strcmp(c.output_type, "icr") == 0);
    CHECK(!c.scene_path || in_words(c.scene_path, argv, argc));
    CHECK(!c.output_dir || in_words(c.output_dir, argv, argc));
    CHECK(!c.config_path || in_words(c.config_path, argv, argc));
    CHECK(c.width >= 0 && c.width <= CR_MAX_SIDE);
    CHECK(c.height >= 0 && c.height <= CR_MAX_SIDE);
    CHECK(c.frames >= 1 && c.frames <= CR_MAX_FRAMES);
    CHECK(c.threads >= 0 && c.threads <= CR_SYSCONFIG_MAX_THREADS);
    CHECK(c.verbose >= -1 && c.verbose <= 1);
    CHECK(c.quiet >= -1 && c.quiet <= 1);
    CHECK(c.auto_accept >= -1 && c.auto_accept <= 1);
    CHECK(c.info == 0 || c.info == 1);
    CHECK(c.help == 0 || c.help == 1);
    CHECK(c.version == 0 || c.version == 1);
    CHECK(c.resume == 0 || c.resume == 1);
    CHECK(c.trace == 0 || c.trace == 1);
    CHECK(c.backend == CR_BACKEND_AUTO || c.backend == CR_BACKEND_CPU ||
          c.backend == CR_BACKEND_CUDA);
    if (c.trace)
        CHECK(c.trace_i >= 0 && c.trace_i < CR_MAX_SIDE && c.trace_j >= 0 &&
              c.trace_j < CR_MAX_SIDE);

    err.msg[0] = '\0';
    rc = cr_cli_check_render(&c, &err);
    if (rc != 0) {
        check_failure(rc, &err);
        goto done;
    }
    CHECK(c.scene_path && c.output_dir);
    CHECK(c.width >= 1 && c.height >= 1 && c.width * c.height <= CR_MAX_PIXELS);
    if (c.trace) {
        CHECK(c.trace_i < c.width && c.trace_j < c.height);
    } else {
        const char *p;
        CHECK(c.output_type[0] != '\0');
        for (p = c.output_type; *p; p++)
            CHECK(strchr("icrdbnslfv", *p) != NULL);
    }
done:
    for (i = 1; i < argc; i++)
        free(argv[i]);
    return 0;
}
