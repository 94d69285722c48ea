/* libFuzzer target: the system configuration loader (appendix E.2).
 *
 * Each input is a configuration file's text, loaded with
 * cr_sysconfig_load_string over a configuration filled with a marker. Besides
 * crashes and sanitizer reports, the target aborts when a contract of
 * sysconfig.h is broken: a failure without a message or one that changed the
 * configuration, or an accepted configuration with values out of range.
 * tests/fuzz/replay.c runs this same function over files in ordinary builds.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input/sysconfig.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                             \
    do {                                                                                        \
        if (!(cond)) {                                                                          \
            fprintf(stderr, "fuzz_sysconfig: contract broken: %s (line %d)\n", #cond,          \
                    __LINE__);                                                                  \
            abort();                                                                            \
        }                                                                                       \
    } while (0)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cr_sysconfig c, before;
    cr_err err;
    int i;

    memset(&c, 0x5a, sizeof c);
    before = c;
    err.msg[0] = '\0';
    if (cr_sysconfig_load_string((const char *)data, size, "fuzz-config.yml", &c, &err)) {
        CHECK(err.msg[0] != '\0');
        CHECK(memchr(err.msg, '\0', sizeof err.msg) != NULL);
        CHECK(memcmp(&c, &before, sizeof c) == 0);
        return 0;
    }
    for (i = 0; i < CR_MAX_GPUS; i++)
        CHECK(c.gpu_enabled[i] == 0 || c.gpu_enabled[i] == 1);
    CHECK(c.cpu_threads >= 0 && c.cpu_threads <= CR_SYSCONFIG_MAX_THREADS);
    CHECK(c.raytracer.horizon_epsilon > 0.0 && isfinite(c.raytracer.horizon_epsilon));
    CHECK(c.raytracer.step_multiplier > 0.0 && isfinite(c.raytracer.step_multiplier));
    CHECK(c.raytracer.max_steps > 0);
    CHECK(c.raytracer.max_turns > 0.0 && isfinite(c.raytracer.max_turns));
    CHECK(c.verbose == 0 || c.verbose == 1);
    CHECK(c.quiet == 0 || c.quiet == 1);
    CHECK(c.keep_log == 0 || c.keep_log == 1);
    CHECK(c.auto_accept == 0 || c.auto_accept == 1);
    return 0;
}
