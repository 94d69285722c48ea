/* The table of raytracer settings (input/settings.def), line by line.
 *
 * For every setting:
 * - its default lies within its limits, and the whole default set passes
 *   the frame check (cr_trace_settings_check);
 * - a value within its limits other than the default, written in config.yml
 *   as section.key, is read back as given, reaches the frame (use FRAME,
 *   MINO, RK4) and is shown on info.txt's line for it (its label);
 * - values outside its limits (or, for a word, a word of no value) are
 *   refused by the configuration reader with a message naming the key and
 *   its line, and by the frame check with a message naming the key;
 * - info.txt shows every setting, in info_pos order, after "CPU threads";
 * - info_pos and hash_pos each number the lines 0 .. n-1 once, and the run
 *   hash text is the text that older runs hashed (so their --resume still
 *   matches); every setting that differs from the hashed ones changes it,
 *   and one added later (hash_pos >= CR_SETTINGS_HASHED_ALWAYS) leaves it
 *   unchanged at its default.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "base/fsutil.h"
#include "input/settings.h"
#include "input/sysconfig.h"
#include "output/info.h"
#include "testfs.h"

#define assert_contains(hay, needle)                                                            \
    do {                                                                                        \
        if (!strstr((hay), (needle)))                                                           \
            fail_msg("text \"%s\"\n  does not contain \"%s\"", (hay), (needle));                \
    } while (0)

/* A value of s within its limits other than its default, as YAML text and
 * as it is stored. */
static void valid_other(const cr_setting *s, char *yaml, size_t n, double *real, long *integer)
{
    cr_trace_settings d = cr_trace_defaults();
    *real = 0.0;
    *integer = 0;
    switch (s->type) {
    case CR_SETTING_REAL: {
        double v = cr_setting_real(s, &d) * 2.0;
        if (!(v < s->real_hi))
            v = 0.5 * (s->real_lo + cr_setting_real(s, &d));
        *real = v;
        snprintf(yaml, n, "%.17g", v);
        break;
    }
    case CR_SETTING_ENUM: {
        cr_names kind = (cr_names)s->int_lo;
        *integer = (cr_setting_int(s, &d) + 1) % cr_names_count(kind);
        snprintf(yaml, n, "%s", cr_name(kind, (int)*integer));
        break;
    }
    default: /* LONG, SIDE */
        *integer = cr_setting_int(s, &d) == s->int_hi ? s->int_lo : s->int_hi;
        if (s->int_hi == LONG_MAX)
            *integer = cr_setting_int(s, &d) + 7;
        snprintf(yaml, n, "%ld", *integer);
        break;
    }
}

/* Up to 3 values outside the limits of s, as YAML text; returns how many.
 * Integer settings also get a value that is no integer. */
static int invalid_values(const cr_setting *s, char out[][64])
{
    int k = 0;
    switch (s->type) {
    case CR_SETTING_REAL:
        snprintf(out[k++], 64, "%.17g", s->real_lo);
        snprintf(out[k++], 64, "%.17g", s->real_lo - 1.0);
        if (isfinite(s->real_hi))
            snprintf(out[k++], 64, "%.17g", s->real_hi);
        break;
    case CR_SETTING_ENUM:
        snprintf(out[k++], 64, "no_such_%s", s->key);
        snprintf(out[k++], 64, "[%s]", cr_name((cr_names)s->int_lo, 0));
        break;
    default:
        snprintf(out[k++], 64, "%ld", s->int_lo - 1);
        if (s->int_hi < LONG_MAX)
            snprintf(out[k++], 64, "%ld", s->int_hi + 1);
        snprintf(out[k++], 64, "%ld.5", s->int_lo);
        break;
    }
    return k;
}

/* Store the value out[0] of invalid_values for the frame check. */
static void set_invalid(const cr_setting *s, cr_trace_settings *ts)
{
    switch (s->type) {
    case CR_SETTING_REAL:
        cr_setting_set_real(s, ts, s->real_lo);
        break;
    case CR_SETTING_ENUM:
        cr_setting_set_int(s, ts, cr_names_count((cr_names)s->int_lo));
        break;
    default:
        cr_setting_set_int(s, ts, s->int_lo - 1);
        break;
    }
}

static void test_defaults_in_limits(void **state)
{
    cr_trace_settings d = cr_trace_defaults();
    char msg[256] = "";
    (void)state;
    assert_true(cr_settings_count >= 7);
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        if (s->type == CR_SETTING_REAL) {
            double v = cr_setting_real(s, &d);
            assert_true(v > s->real_lo && v < s->real_hi && isfinite(v));
        } else if (s->type == CR_SETTING_ENUM) {
            long v = cr_setting_int(s, &d);
            assert_true(v >= 0 && v < cr_names_count((cr_names)s->int_lo));
        } else {
            long v = cr_setting_int(s, &d);
            assert_true(v >= s->int_lo && v <= s->int_hi);
        }
    }
    assert_int_equal(cr_trace_settings_check(&d, msg, sizeof msg), 0);
}

static void test_table_orders(void **state)
{
    (void)state;
    for (int pos = 0; pos < cr_settings_count; pos++) {
        int n_info = 0, n_hash = 0;
        for (int i = 0; i < cr_settings_count; i++) {
            n_info += cr_settings[i].info_pos == pos;
            n_hash += cr_settings[i].hash_pos == pos;
        }
        assert_int_equal(n_info, 1);
        assert_int_equal(n_hash, 1);
        assert_non_null(cr_setting_in_order(CR_SETTING_INFO_ORDER, pos));
        assert_non_null(cr_setting_in_order(CR_SETTING_HASH_ORDER, pos));
    }
    assert_null(cr_setting_in_order(CR_SETTING_INFO_ORDER, cr_settings_count));
    assert_null(cr_setting_in_order(CR_SETTING_HASH_ORDER, -1));
    for (int i = 0; i < cr_settings_count; i++) {
        assert_true(cr_settings[i].doc[0] && cr_settings[i].label[0] &&
                    cr_settings[i].hash_word[0]);
        for (int j = 0; j < i; j++)
            assert_false(!strcmp(cr_settings[i].section, cr_settings[j].section) &&
                         !strcmp(cr_settings[i].key, cr_settings[j].key));
    }
}

/* The text older runs hashed for these settings (resume.c before the table). */
static void test_hash_text(void **state)
{
    cr_trace_settings t = cr_trace_defaults();
    char got[512], want[512];
    (void)state;
    t.integrator = CR_INTEG_RK4;
    t.tolerance = 3e-9;
    t.step_multiplier = 0.1;
    t.horizon_epsilon = 0.02;
    t.max_steps = 12345;
    t.max_turns = 7.5;
    t.samples = 3;
    snprintf(want, sizeof want,
             "integrator %d tolerance %.17g step %.17g eps %.17g max_steps %ld max_turns %.17g "
             "samples %d",
             t.integrator, t.tolerance, t.step_multiplier, t.horizon_epsilon, t.max_steps,
             t.max_turns, t.samples);
    assert_int_equal(cr_trace_settings_hash_text(&t, got, sizeof got), (int)strlen(want));
    assert_string_equal(got, want);
    /* a short buffer: cut, terminated, the full length returned */
    assert_int_equal(cr_trace_settings_hash_text(&t, got, 10), (int)strlen(want));
    assert_int_equal(strlen(got), 9);
    /* settings added after the first hashed runs: absent at their defaults */
    {
        cr_trace_settings d = cr_trace_defaults();
        char def_text[512];
        int n_always = 0;
        cr_trace_settings_hash_text(&d, def_text, sizeof def_text);
        for (int i = 0; i < cr_settings_count; i++)
            n_always += cr_settings[i].hash_pos < CR_SETTINGS_HASHED_ALWAYS;
        assert_int_equal(n_always, CR_SETTINGS_HASHED_ALWAYS);
        for (int pos = 0; pos < CR_SETTINGS_HASHED_ALWAYS; pos++)
            assert_non_null(strstr(def_text, cr_setting_in_order(CR_SETTING_HASH_ORDER,
                                                                 pos)->hash_word));
        for (int pos = CR_SETTINGS_HASHED_ALWAYS; pos < cr_settings_count; pos++) {
            char w[80];
            snprintf(w, sizeof w, " %s ",
                     cr_setting_in_order(CR_SETTING_HASH_ORDER, pos)->hash_word);
            assert_null(strstr(def_text, w));
        }
    }
    /* every setting changes the text */
    for (int i = 0; i < cr_settings_count; i++) {
        cr_trace_settings u = t;
        char other[512];
        const cr_setting *s = &cr_settings[i];
        if (s->type == CR_SETTING_REAL)
            cr_setting_set_real(s, &u, cr_setting_real(s, &u) * (1.0 + 1e-15));
        else
            cr_setting_set_int(s, &u, cr_setting_int(s, &u) + 1);
        cr_trace_settings_hash_text(&u, other, sizeof other);
        assert_string_not_equal(other, want);
    }
}

static void test_parse_each(void **state)
{
    (void)state;
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        cr_trace_settings d = cr_trace_defaults();
        cr_sysconfig c;
        cr_frame f;
        cr_err err;
        char text[256], v[64];
        double real;
        long integer;
        valid_other(s, v, sizeof v, &real, &integer);
        snprintf(text, sizeof text, "%s:\n  %s: %s\n", s->section, s->key, v);
        err.msg[0] = '\0';
        if (cr_sysconfig_load_string(text, strlen(text), "config.yml", &c, &err) != 0)
            fail_msg("%s: %s", text, err.msg);
        if (s->type == CR_SETTING_REAL) {
            assert_true(cr_setting_real(s, &c.raytracer) == real);
            assert_true(cr_setting_real(s, &d) != real);
        } else {
            assert_int_equal(cr_setting_int(s, &c.raytracer), integer);
            assert_int_not_equal(cr_setting_int(s, &d), integer);
        }
        /* every other setting keeps its default */
        for (int j = 0; j < cr_settings_count; j++)
            if (j != i)
                assert_true(cr_setting_real(&cr_settings[j], &c.raytracer) ==
                            cr_setting_real(&cr_settings[j], &d));
        memset(&f, 0, sizeof f);
        cr_trace_settings_to_frame(&c.raytracer, &f);
        if (s->in_frame) {
            /* the frame's field of the same name holds the value */
            const char *p = (const char *)&f + s->frame_offset;
            if (s->type == CR_SETTING_REAL)
                assert_true(*(const double *)(const void *)p == real);
            else if (s->type == CR_SETTING_LONG)
                assert_true(*(const long *)(const void *)p == integer);
            else
                assert_int_equal(*(const int *)(const void *)p, integer);
        }
    }
}

static void test_refuse_each(void **state)
{
    (void)state;
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        char bad[3][64], text[256], path[96], at[128], msg[256];
        int n = invalid_values(s, bad);
        cr_trace_settings t = cr_trace_defaults();
        cr_setting_path(s, path, sizeof path);
        for (int k = 0; k < n; k++) {
            cr_sysconfig c, before;
            cr_err err;
            cr_sysconfig_defaults(&before);
            c = before;
            snprintf(text, sizeof text, "%s:\n  %s: %s\n", s->section, s->key, bad[k]);
            err.msg[0] = '\0';
            if (cr_sysconfig_load_string(text, strlen(text), "config.yml", &c, &err) == 0)
                fail_msg("accepted %s = %s", path, bad[k]);
            snprintf(at, sizeof at, "config.yml:2:%d: %s: ", (int)strlen(s->key) + 5, path);
            assert_contains(err.msg, at);
            assert_memory_equal(&c, &before, sizeof c);
        }
        if (!s->in_frame)
            continue; /* a RUN setting is checked where it is read, not by the frame */
        set_invalid(s, &t);
        assert_int_equal(cr_trace_settings_check(&t, msg, sizeof msg), -1);
        snprintf(at, sizeof at, "%s = ", path);
        assert_true(strncmp(msg, at, strlen(at)) == 0);
    }
}

static char *read_all(const char *path)
{
    FILE *fp = fopen(path, "rb");
    char *buf;
    long n;
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    buf = malloc((size_t)n + 1);
    assert_int_equal(fread(buf, 1, (size_t)n, fp), (size_t)n);
    buf[n] = '\0';
    fclose(fp);
    return buf;
}

/* info.txt of configuration c into a fresh folder; the text (to free). */
static char *info_of(const cr_sysconfig *c)
{
    char dir[] = "/tmp/cr_test_settings.XXXXXX", path[4096];
    cr_err err;
    char *t;
    assert_non_null(mkdtemp(dir));
    assert_int_equal(cr_info_write(dir, NULL, NULL, c, NULL, 0, &err), 0);
    assert_int_equal(cr_path_join(path, sizeof path, dir, "info.txt"), 0);
    t = read_all(path);
    cr_test_rm_rf(dir);
    return t;
}

static void test_info_each(void **state)
{
    cr_sysconfig c;
    char *t, line[256], v[128];
    const char *at;
    (void)state;
    cr_sysconfig_defaults(&c);
    t = info_of(&c);
    at = strstr(t, "  CPU threads ");
    assert_non_null(at);
    for (int pos = 0; pos < cr_settings_count; pos++) {
        const cr_setting *s = cr_setting_in_order(CR_SETTING_INFO_ORDER, pos);
        const char *next;
        cr_setting_format(s, &c.raytracer, v, sizeof v);
        snprintf(line, sizeof line, "\n  %-22s %s\n", s->label, v);
        next = strstr(at, line);
        if (!next)
            fail_msg("info.txt lacks (or misorders) \"%s\"", line + 1);
        at = next + 1;
    }
    free(t);
    /* the defaults as info.txt has always shown them */
    t = info_of(&c);
    assert_contains(t, "  horizon epsilon        0.005\n  integrator             mino\n"
                       "  tolerance              1e-07\n"
                       "  step multiplier        0.03125 (rk4 only, unused)\n"
                       "  max steps per ray      200000\n  max turns per ray      50\n"
                       "  samples                1 x 1 per pixel\n");
    free(t);
    /* a changed value of each shows on its line */
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        char yaml[64];
        double real;
        long integer;
        cr_sysconfig_defaults(&c);
        valid_other(s, yaml, sizeof yaml, &real, &integer);
        if (s->type == CR_SETTING_REAL)
            cr_setting_set_real(s, &c.raytracer, real);
        else
            cr_setting_set_int(s, &c.raytracer, integer);
        cr_setting_format(s, &c.raytracer, v, sizeof v);
        if (s->type == CR_SETTING_ENUM)
            assert_non_null(strstr(v, yaml));
        else if (s->type == CR_SETTING_LONG || s->type == CR_SETTING_SIDE)
            assert_true(strncmp(v, yaml, strlen(yaml)) == 0);
        else
            assert_true(fabs(strtod(v, NULL) - real) <= 1e-9 * fabs(real));
        snprintf(line, sizeof line, "\n  %-22s %s\n", s->label, v);
        t = info_of(&c);
        assert_contains(t, line);
        free(t);
    }
}

/* A setting that only one integrator uses is marked unused under the other. */
static void test_info_unused(void **state)
{
    cr_trace_settings t = cr_trace_defaults();
    char v[128];
    (void)state;
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        if (s->integrator == CR_SETTING_ANY)
            continue;
        t.integrator = s->integrator;
        cr_setting_format(s, &t, v, sizeof v);
        assert_null(strstr(v, "unused"));
        t.integrator = s->integrator == CR_INTEG_MINO ? CR_INTEG_RK4 : CR_INTEG_MINO;
        cr_setting_format(s, &t, v, sizeof v);
        assert_contains(v, " only, unused)");
        assert_contains(v, cr_integrator_name(s->integrator));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_in_limits), cmocka_unit_test(test_table_orders),
        cmocka_unit_test(test_hash_text),          cmocka_unit_test(test_parse_each),
        cmocka_unit_test(test_refuse_each),        cmocka_unit_test(test_info_each),
        cmocka_unit_test(test_info_unused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
