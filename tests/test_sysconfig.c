/* The system configuration (appendix E.2).
 *
 * - built-in defaults (cr_trace_defaults of settings.def), for no file content at all;
 * - raytracer.integrator by name (cr_integrator_name / cr_integrator_parse
 *   agree) and raytracer.tolerance;
 * - listing E.1 as a file; every key; the gpus rule (no section: device 0;
 *   a section: only the listed enabled devices); booleans in every spelling;
 * - every error path names the file, line:col and key, and leaves the
 *   configuration unchanged.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "core/trace.h"
#include "input/sysconfig.h"

#define DATA CR_SOURCE_DIR "/tests/data/"
#define NAME "config.yml"

#define assert_contains(hay, needle)                                                            \
    do {                                                                                        \
        if (!strstr((hay), (needle)))                                                           \
            fail_msg("message \"%s\"\n  does not contain \"%s\"", (hay), (needle));             \
    } while (0)

static int load(const char *text, cr_sysconfig *c, cr_err *e)
{
    e->msg[0] = '\0';
    return cr_sysconfig_load_string(text, strlen(text), NAME, c, e);
}

static void load_ok(const char *text, cr_sysconfig *c)
{
    cr_err e;
    if (load(text, c, &e) != 0)
        fail_msg("load failed: %s\n--- text:\n%s", e.msg, text);
}

static void assert_defaults(const cr_sysconfig *c)
{
    int i;
    assert_int_equal(c->gpu_enabled[0], 1);
    for (i = 1; i < CR_MAX_GPUS; i++)
        assert_int_equal(c->gpu_enabled[i], 0);
    assert_int_equal(c->cpu_threads, 0);
    assert_int_equal(c->raytracer.integrator, cr_trace_defaults().integrator);
    assert_true(c->raytracer.tolerance == cr_trace_defaults().tolerance);
    assert_true(c->raytracer.horizon_epsilon == cr_trace_defaults().horizon_epsilon);
    assert_true(c->raytracer.step_multiplier == cr_trace_defaults().step_multiplier);
    assert_true(c->raytracer.max_steps == cr_trace_defaults().max_steps);
    assert_true(c->raytracer.max_turns == cr_trace_defaults().max_turns);
    assert_int_equal(c->verbose, 0);
    assert_int_equal(c->quiet, 0);
    assert_int_equal(c->keep_log, 0);
    assert_int_equal(c->auto_accept, 0);
    assert_int_equal(c->video_fps, 30);
    assert_int_equal(c->video_keep_frames, 1);
}

static void test_defaults(void **state)
{
    static const char *empties[] = {"", "# nothing here\n", "---\n", "---\n...\n", "~\n",
                                    "{}\n"};
    cr_sysconfig c;
    size_t i;
    (void)state;
    cr_sysconfig_defaults(&c);
    assert_defaults(&c);
    assert_true(c.raytracer.horizon_epsilon == 0.5e-2);
    assert_true(c.raytracer.step_multiplier == 1.0 / 32.0);
    assert_int_equal(c.raytracer.integrator, CR_INTEG_MINO);
    assert_true(c.raytracer.tolerance == 1e-7);
    for (i = 0; i < sizeof empties / sizeof empties[0]; i++) {
        memset(&c, 0x5a, sizeof c);
        load_ok(empties[i], &c);
        assert_defaults(&c);
    }
}

static void test_listing_e1(void **state)
{
    cr_sysconfig c;
    cr_err e;
    (void)state;
    memset(&c, 0x5a, sizeof c);
    if (cr_sysconfig_load(DATA "config_e1.yml", &c, &e))
        fail_msg("%s", e.msg);
    assert_int_equal(c.gpu_enabled[0], 1);
    assert_int_equal(c.gpu_enabled[1], 0);
    assert_int_equal(c.gpu_enabled[2], 0);
    assert_int_equal(c.cpu_threads, 4);
    assert_true(c.raytracer.horizon_epsilon == 0.5e-2);
    assert_true(c.raytracer.step_multiplier == 0.03125);
    assert_true(c.raytracer.max_steps == cr_trace_defaults().max_steps);
    assert_true(c.raytracer.max_turns == cr_trace_defaults().max_turns);
    assert_int_equal(c.verbose, 0);
    assert_int_equal(c.quiet, 0);
    assert_int_equal(c.keep_log, 0);
    assert_int_equal(c.auto_accept, 0);
}

static void test_every_key(void **state)
{
    cr_sysconfig c;
    int i;
    (void)state;
    load_ok("gpus:\n"
            "  1:\n"
            "    enabled: true\n"
            "  3: {enabled: yes}\n"
            "  0: {enabled: false}\n"
            "  63:\n"
            "    enabled: on\n"
            "  5: {enabled: off}\n"
            "cpu:\n"
            "  threads: 12\n"
            "raytracer:\n"
            "  horizon_epsilon: 1e-3\n"
            "  step_multiplier: 0.0625\n"
            "  max_steps: 5000\n"
            "  max_turns: 2.5\n"
            "  integrator: rk4\n"
            "  tolerance: 1e-6\n"
            "log:\n"
            "  verbose: True\n"
            "  quiet: NO\n"
            "  keep_log: On\n"
            "auto_accept: YES\n"
            "video: {fps: 24, keep_frames: false}\n",
            &c);
    for (i = 0; i < CR_MAX_GPUS; i++)
        assert_int_equal(c.gpu_enabled[i], i == 1 || i == 3 || i == 63);
    assert_int_equal(c.cpu_threads, 12);
    assert_true(c.raytracer.horizon_epsilon == 1e-3);
    assert_true(c.raytracer.step_multiplier == 0.0625);
    assert_true(c.raytracer.max_steps == 5000);
    assert_true(c.raytracer.max_turns == 2.5);
    assert_int_equal(c.raytracer.integrator, CR_INTEG_RK4);
    assert_true(c.raytracer.tolerance == 1e-6);
    assert_int_equal(c.verbose, 1);
    assert_int_equal(c.quiet, 0);
    assert_int_equal(c.keep_log, 1);
    assert_int_equal(c.auto_accept, 1);
    assert_int_equal(c.video_fps, 24);
    assert_int_equal(c.video_keep_frames, 0);
}

static void test_gpus_rule(void **state)
{
    cr_sysconfig c;
    int i;
    (void)state;
    /* no gpus section: device 0 */
    load_ok("cpu: {threads: 2}\n", &c);
    assert_int_equal(c.raytracer.simd, CR_SIMD_AUTO);
    assert_int_equal(c.gpu_enabled[0], 1);
    load_ok("cpu: {threads: 2, simd: off}\n", &c);
    assert_int_equal(c.raytracer.simd, CR_SIMD_OFF);
    load_ok("cpu: {simd: auto}\n", &c);
    assert_int_equal(c.raytracer.simd, CR_SIMD_AUTO);
    load_ok("cpu: {threads: 2}\n", &c);
    assert_int_equal(c.gpu_enabled[1], 0);
    /* a section: only the listed enabled ones */
    load_ok("gpus: {1: {enabled: true}}\n", &c);
    assert_int_equal(c.gpu_enabled[0], 0);
    assert_int_equal(c.gpu_enabled[1], 1);
    /* an empty section: none */
    load_ok("gpus: {}\n", &c);
    for (i = 0; i < CR_MAX_GPUS; i++)
        assert_int_equal(c.gpu_enabled[i], 0);
    load_ok("gpus:\n", &c);
    for (i = 0; i < CR_MAX_GPUS; i++)
        assert_int_equal(c.gpu_enabled[i], 0);
}

static void test_booleans(void **state)
{
    static const struct {
        const char *text;
        int value;
    } cases[] = {{"true", 1}, {"True", 1}, {"TRUE", 1}, {"yes", 1},     {"Yes", 1},
                 {"on", 1},   {"ON", 1},   {"false", 0}, {"False", 0}, {"no", 0},
                 {"NO", 0},   {"off", 0},  {"Off", 0},   {"\"true\"", 1}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[128];
        cr_sysconfig c;
        snprintf(text, sizeof text, "auto_accept: %s\nlog: {quiet: %s}\n", cases[i].text,
                 cases[i].text);
        load_ok(text, &c);
        assert_int_equal(c.auto_accept, cases[i].value);
        assert_int_equal(c.quiet, cases[i].value);
    }
}

static void test_integrator(void **state)
{
    static const struct {
        const char *text;
        int value;
    } cases[] = {{"mino", CR_INTEG_MINO}, {"rk4", CR_INTEG_RK4},   {"RK4", CR_INTEG_RK4},
                 {"Mino", CR_INTEG_MINO}, {"\"rk4\"", CR_INTEG_RK4}, {"'mino'", CR_INTEG_MINO}};
    size_t i;
    int k;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[128];
        cr_sysconfig c;
        snprintf(text, sizeof text, "raytracer: {integrator: %s}\n", cases[i].text);
        load_ok(text, &c);
        assert_int_equal(c.raytracer.integrator, cases[i].value);
        assert_true(c.raytracer.tolerance == cr_trace_defaults().tolerance);
    }
    /* the names info.txt shows are the names the file takes */
    for (k = 0; k < CR_INTEG_COUNT_; k++) {
        const char *name = cr_integrator_name(k);
        assert_int_equal(cr_integrator_parse(name, strlen(name)), k);
        assert_non_null(strstr(cr_integrator_names(), name));
    }
    assert_string_equal(cr_integrator_name(CR_INTEG_MINO), "mino");
    assert_string_equal(cr_integrator_name(CR_INTEG_RK4), "rk4");
    assert_string_equal(cr_integrator_name(-1), "unknown");
    assert_string_equal(cr_integrator_name(CR_INTEG_COUNT_), "unknown");
    assert_int_equal(cr_integrator_parse(" rk4\t", 5), CR_INTEG_RK4);
    assert_int_equal(cr_integrator_parse("rk4x", 3), CR_INTEG_RK4);
    assert_int_equal(cr_integrator_parse("rk", 2), -1);
    assert_int_equal(cr_integrator_parse("rk4\0", 4), -1);
    assert_int_equal(cr_integrator_parse("", 0), -1);
    /* tolerance */
    {
        cr_sysconfig c;
        load_ok("raytracer:\n  tolerance: 1e-10\n", &c);
        assert_true(c.raytracer.tolerance == 1e-10);
        assert_int_equal(c.raytracer.integrator, cr_trace_defaults().integrator);
        load_ok("raytracer: {tolerance: 0.5}\n", &c);
        assert_true(c.raytracer.tolerance == 0.5);
    }
}

typedef struct err_case {
    const char *text;
    const char *start;
    const char *part;
} err_case;

static void test_errors(void **state)
{
    static const err_case cases[] = {
        {"cpu:\n  threads: 0\n", "config.yml:2:12: cpu.threads: ",
         "expected a number of threads from 1 to 4096, got \"0\""},
        {"cpu:\n  threads: -2\n", "config.yml:2:12: cpu.threads: ", "got \"-2\""},
        {"cpu:\n  threads: 2.5\n", "config.yml:2:12: cpu.threads: ", "got \"2.5\""},
        {"cpu:\n  threads: 100000\n", "config.yml:2:12: cpu.threads: ", "from 1 to 4096"},
        {"cpu:\n  threads: [1]\n", "config.yml:2:12: cpu.threads: ", "got a list of 1 item"},
        {"cpu:\n  simd: on\n", "config.yml:2:9: cpu.simd: ", "(expected one of: auto, off)"},
        {"cpu:\n  simd: 1\n", "config.yml:2:9: cpu.simd: ", "unknown simd"},
        {"cpu:\n  cores: 4\n", "config.yml:2:3: unknown key 'cores' in cpu",
         "(expected one of: threads, simd)"},
        {"cpu: 4\n", "config.yml:1:6: cpu: ", "expected a mapping of keys, got \"4\""},
        {"raytracer:\n  horizon_epsilon: 0\n", "config.yml:2:20: raytracer.horizon_epsilon: ",
         "expected a positive number, got \"0\""},
        {"raytracer:\n  horizon_epsilon: -1e-3\n", "config.yml:2:20: raytracer.horizon_epsilon: ",
         "positive"},
        {"raytracer:\n  horizon_epsilon: .inf\n", "config.yml:2:20: raytracer.horizon_epsilon: ",
         "expected a finite number, got \".inf\""},
        {"raytracer:\n  step_multiplier: nan\n", "config.yml:2:20: raytracer.step_multiplier: ",
         "expected a finite number"},
        {"raytracer:\n  step_multiplier: 1e999\n", "config.yml:2:20: raytracer.step_multiplier: ",
         "expected a finite number"},
        {"raytracer:\n  step_multiplier: small\n",
         "config.yml:2:20: raytracer.step_multiplier: ", "expected a number, got \"small\""},
        {"raytracer:\n  step_multiplier: 1 deg\n",
         "config.yml:2:20: raytracer.step_multiplier: ", "without a unit"},
        {"raytracer:\n  max_steps: 0\n", "config.yml:2:14: raytracer.max_steps: ",
         "expected a positive integer, got \"0\""},
        {"raytracer:\n  max_steps: 1.5e5\n", "config.yml:2:14: raytracer.max_steps: ",
         "expected a positive integer"},
        {"raytracer:\n  max_steps: 99999999999999999999999\n",
         "config.yml:2:14: raytracer.max_steps: ", "expected a positive integer"},
        {"raytracer:\n  max_turns: 0\n", "config.yml:2:14: raytracer.max_turns: ",
         "expected a positive number"},
        {"raytracer:\n  max_turn: 5\n", "config.yml:2:3: unknown key 'max_turn' in raytracer",
         "(expected one of: horizon_epsilon, step_multiplier, max_steps, max_turns, integrator, "
         "tolerance, samples)"},
        {"raytracer:\n  integrator: euler\n", "config.yml:2:15: raytracer.integrator: ",
         "unknown integrator \"euler\" (expected one of: mino, rk4)"},
        {"raytracer:\n  integrator: rk45\n", "config.yml:2:15: raytracer.integrator: ",
         "unknown integrator \"rk45\" (expected one of: mino, rk4)"},
        {"raytracer:\n  integrator: 4\n", "config.yml:2:15: raytracer.integrator: ",
         "unknown integrator \"4\""},
        {"raytracer:\n  integrator: [rk4]\n", "config.yml:2:15: raytracer.integrator: ",
         "expected an integrator name (one of: mino, rk4), got a list of 1 item"},
        {"raytracer:\n  integrator:\n", "config.yml:2:",
         "raytracer.integrator: expected an integrator name (one of: mino, rk4), got nothing"},
        {"raytracer:\n  tolerance: 0\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a positive number, got \"0\""},
        {"raytracer:\n  tolerance: -1e-8\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a positive number, got \"-1e-8\""},
        {"raytracer:\n  tolerance: .inf\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a finite number, got \".inf\""},
        {"raytracer:\n  tolerance: nan\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a finite number, got \"nan\""},
        {"raytracer:\n  tolerance: 1e999\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a finite number"},
        {"raytracer:\n  tolerance: tight\n", "config.yml:2:14: raytracer.tolerance: ",
         "expected a number, got \"tight\""},
        {"raytracer:\n  tolerance: 1e-8 M\n", "config.yml:2:14: raytracer.tolerance: ",
         "without a unit"},
        {"raytracer:\n  tolerance: [1e-8]\n", "config.yml:2:14: raytracer.tolerance: ",
         "got a list of 1 item"},
        {"log:\n  verbose: maybe\n", "config.yml:2:12: log.verbose: ",
         "expected true or false (or yes/no, on/off), got \"maybe\""},
        {"log:\n  verbose: 1\n", "config.yml:2:12: log.verbose: ", "expected true or false"},
        {"log:\n  verbose:\n", "config.yml:2:", "log.verbose: expected true or false (or yes/no, on/off), got nothing"},
        {"log:\n  loud: true\n", "config.yml:2:3: unknown key 'loud' in log",
         "(expected one of: verbose, quiet, keep_log)"},
        {"auto_accept: sure\n", "config.yml:1:14: auto_accept: ", "got \"sure\""},
        {"auto_accept: true\nauto_accept: false\n", "config.yml:2:1: auto_accept: ",
         "duplicate key 'auto_accept' (first given at line 1, column 1)"},
        {"raytrace:\n  max_steps: 5\n", "config.yml:1:1: unknown key 'raytrace' at the top level",
         "(expected one of: gpus, cpu, raytracer, log, auto_accept, video)"},
        {"video:\n  fps: 0\n", "config.yml:2:8: video.fps: ",
         "expected a whole number of frames per second from 1 to 1000, got \"0\""},
        {"video:\n  fps: 29.97\n", "config.yml:2:8: video.fps: ", "got \"29.97\""},
        {"video:\n  keep_frames: maybe\n", "config.yml:2:16: video.keep_frames: ",
         "expected true or false"},
        {"video:\n  speed: 2\n", "config.yml:2:3: unknown key 'speed' in video",
         "(expected one of: fps, keep_frames)"},
        {"gpus:\n  64:\n    enabled: true\n", "config.yml:2:3: gpus: ",
         "expected a GPU number from 0 to 63, got \"64\""},
        {"gpus:\n  first:\n    enabled: true\n", "config.yml:2:3: gpus: ",
         "expected a GPU number from 0 to 63, got \"first\""},
        {"gpus:\n  -1: {enabled: true}\n", "config.yml:2:3: gpus: ", "got \"-1\""},
        {"gpus:\n  0: {enabled: true}\n  00: {enabled: false}\n", "config.yml:3:3: gpus.0: ",
         "duplicate GPU 0 (first given at line 2, column 3)"},
        {"gpus:\n  0:\n    enable: true\n", "config.yml:3:5: unknown key 'enable' in gpus.0",
         "(expected one of: enabled)"},
        {"gpus:\n  0: {}\n", "config.yml:2:3: gpus.0: missing required key 'enabled'", ""},
        {"gpus:\n  0:\n", "config.yml:2:3: gpus.0: missing required key 'enabled'", ""},
        {"gpus:\n  0: {enabled: 2}\n", "config.yml:2:16: gpus.0.enabled: ",
         "expected true or false"},
        {"gpus: [0, 1]\n", "config.yml:1:7: gpus: ", "expected a mapping of keys"},
        {"- gpus\n", "config.yml:1:1: a configuration must be a mapping of keys",
         "got a list of 1 item"},
        {"cpu:\n  threads: 4\n threads: 5\n", "config.yml:3:", "YAML syntax error"},
        {"cpu: {threads: 4\n", "config.yml:", "YAML syntax error"},
        {"cpu:\n\tthreads: 4\n", "config.yml:2:1: YAML syntax error: ", ""},
        {"log: {}\n---\nlog: {}\n", "config.yml:3:1: a second YAML document", ""},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        cr_sysconfig c, before;
        cr_err e;
        memset(&c, 0x5a, sizeof c);
        before = c;
        if (load(cases[i].text, &c, &e) == 0)
            fail_msg("case %zu accepted, expected \"%s%s\"\n--- text:\n%s", i, cases[i].start,
                     cases[i].part, cases[i].text);
        if (strncmp(e.msg, cases[i].start, strlen(cases[i].start)) != 0 ||
            !strstr(e.msg, cases[i].part))
            fail_msg("case %zu: message\n  \"%s\"\nexpected to start with \"%s\" and contain "
                     "\"%s\"\n--- text:\n%s",
                     i, e.msg, cases[i].start, cases[i].part, cases[i].text);
        /* unchanged on failure */
        assert_memory_equal(&c, &before, sizeof c);
    }
}

static void test_errors_files(void **state)
{
    cr_sysconfig c;
    cr_err e;
    (void)state;
    cr_sysconfig_defaults(&c);
    assert_int_equal(cr_sysconfig_load(DATA "no_such_config.yml", &c, &e), -1);
    assert_string_equal(e.msg, DATA "no_such_config.yml: cannot open: No such file or directory");
    assert_int_equal(cr_sysconfig_load(DATA "config_bad.yml", &c, &e), -1);
    assert_string_equal(e.msg, DATA "config_bad.yml:2:12: cpu.threads: expected a number of "
                                    "threads from 1 to 4096, got \"many\"");
    assert_defaults(&c);
    assert_int_equal(cr_sysconfig_load(DATA, &c, &e), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),    cmocka_unit_test(test_listing_e1),
        cmocka_unit_test(test_every_key),   cmocka_unit_test(test_gpus_rule),
        cmocka_unit_test(test_booleans),    cmocka_unit_test(test_integrator),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_errors_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
