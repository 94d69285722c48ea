/* curray io: the system configuration (appendix E.2), read with the checked
 * getters of yamlutil.h. */
#include "sysconfig.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "yamlutil.h"

/* Largest configuration file read (bytes). */
#define SYSCONFIG_MAX_BYTES (1L << 20)

#define OPT(k) {k, 0, 0, NULL, NULL, 0}
#define REQ(k) {k, 1, 0, NULL, NULL, 0}

void cr_sysconfig_defaults(cr_sysconfig *c)
{
    memset(c, 0, sizeof *c);
    c->gpu_enabled[0] = 1;
    c->cpu_threads = 0;
    c->raytracer = cr_trace_defaults();
    c->video_fps = CR_VIDEO_DEFAULT_FPS;
    c->video_keep_frames = 1;
}

/* "a" or "an" before word. */
static const char *article(const char *word)
{
    return word[0] && strchr("aeiou", word[0]) ? "an" : "a";
}

/* An ENUM setting: a word of its names kind, in any letter case. */
static int get_word(cr_yaml *y, const cr_yaml_field *f, const cr_setting *s, const char *path,
                    cr_trace_settings *ts, cr_err *err)
{
    cr_names kind = (cr_names)s->int_lo;
    char got[96];
    int v = -1;
    if (f->value->type == YAML_SCALAR_NODE && !cr_yaml_is_null(f->value))
        v = cr_name_parse_folded(kind, (const char *)f->value->data.scalar.value,
                                 f->value->data.scalar.length);
    if (v < 0) {
        cr_yaml_describe(f->value, got, sizeof got);
        if (f->value->type != YAML_SCALAR_NODE || cr_yaml_is_null(f->value))
            return cr_yaml_fail(y, f->value, path, err, "expected %s %s name (one of: %s), got %s",
                                article(s->key), s->key, cr_names_list(kind), got);
        return cr_yaml_fail(y, f->value, path, err, "unknown %s %s (expected one of: %s)", s->key,
                            got, cr_names_list(kind));
    }
    cr_setting_set_int(s, ts, v);
    return 0;
}

/* A REAL setting: a finite number within its limits. */
static int get_real(cr_yaml *y, const cr_yaml_field *f, const cr_setting *s, const char *path,
                    cr_trace_settings *ts, cr_err *err)
{
    char got[96];
    double v;
    if (cr_yaml_number(y, f->value, path, &v, err))
        return -1;
    if (!(v > s->real_lo && v < s->real_hi)) {
        cr_yaml_describe(f->value, got, sizeof got);
        if (s->real_lo == 0.0 && s->real_hi == INFINITY)
            return cr_yaml_fail(y, f->value, path, err, "expected a positive number, got %s",
                                got);
        return cr_yaml_fail(y, f->value, path, err,
                            "expected a number above %g and below %g, got %s", s->real_lo,
                            s->real_hi, got);
    }
    cr_setting_set_real(s, ts, v);
    return 0;
}

/* A LONG or SIDE setting: an integer within its limits. */
static int get_integer(cr_yaml *y, const cr_yaml_field *f, const cr_setting *s,
                       const char *path, cr_trace_settings *ts, cr_err *err)
{
    char what[96];
    long v;
    if (s->int_lo == 1 && s->int_hi == LONG_MAX)
        snprintf(what, sizeof what, "a positive integer");
    else
        snprintf(what, sizeof what, "an integer from %ld to %ld", s->int_lo, s->int_hi);
    if (cr_yaml_int(y, f->value, path, s->int_lo, s->int_hi, what, &v, err))
        return -1;
    cr_setting_set_int(s, ts, v);
    return 0;
}

/* Setting s from field f when present. */
static int get_setting(cr_yaml *y, const cr_yaml_field *f, const cr_setting *s,
                       cr_trace_settings *ts, cr_err *err)
{
    char path[CR_YAML_PATH];
    if (!f->value)
        return 0;
    cr_setting_path(s, path, sizeof path);
    switch (s->type) {
    case CR_SETTING_ENUM:
        return get_word(y, f, s, path, ts, err);
    case CR_SETTING_REAL:
        return get_real(y, f, s, path, ts, err);
    default: /* LONG, SIDE */
        return get_integer(y, f, s, path, ts, err);
    }
}

/* Most keys of one section: the caller's own and the table's. */
#define SECTION_MAX_KEYS 64

/* Section sec (present) named name: its keys are the caller's own[0..n_own-1],
 * which the caller reads from own afterwards, and the settings.def lines of
 * that section, read into c->raytracer here (in table order). Unknown keys
 * are refused with the list of both, own keys first. */
static int parse_section(cr_yaml *y, const cr_yaml_field *sec, const char *name,
                         cr_yaml_field *own, int n_own, cr_sysconfig *c, cr_err *err)
{
    cr_yaml_field f[SECTION_MAX_KEYS];
    const cr_setting *set[SECTION_MAX_KEYS];
    int n = 0, i;
    for (i = 0; i < n_own && n < SECTION_MAX_KEYS; i++) {
        f[n] = own[i];
        set[n++] = NULL;
    }
    for (i = 0; i < cr_settings_count && n < SECTION_MAX_KEYS; i++) {
        if (strcmp(cr_settings[i].section, name) != 0)
            continue;
        f[n] = (cr_yaml_field)OPT(cr_settings[i].key);
        set[n++] = &cr_settings[i];
    }
    if (cr_yaml_fields(y, sec->value, name, sec->key_node, f, n, err))
        return -1;
    for (i = 0; i < n; i++)
        if (set[i] && get_setting(y, &f[i], set[i], &c->raytracer, err))
            return -1;
    for (i = 0; i < n_own; i++)
        own[i] = f[i];
    return 0;
}

static int get_flag(cr_yaml *y, const cr_yaml_field *f, const char *section, int *out,
                    cr_err *err)
{
    char path[CR_YAML_PATH];
    if (!f->value)
        return 0;
    cr_yaml_path_key(path, sizeof path, section, f->key);
    return cr_yaml_bool(y, f->value, path, out, err);
}

/* gpus: {<n>: {enabled: bool}, ...}; only the listed devices marked enabled
 * are used. */
static int parse_gpus(cr_yaml *y, yaml_node_t *map, cr_sysconfig *c, cr_err *err)
{
    yaml_node_pair_t *pairs;
    yaml_node_t *seen[CR_MAX_GPUS];
    int np, i;
    char path[CR_YAML_PATH], what[64];

    memset(seen, 0, sizeof seen);
    memset(c->gpu_enabled, 0, sizeof c->gpu_enabled);
    if (cr_yaml_mapping(y, map, "gpus", &pairs, &np, err))
        return -1;
    snprintf(what, sizeof what, "a GPU number from 0 to %d", CR_MAX_GPUS - 1);
    for (i = 0; i < np; i++) {
        yaml_node_t *k = cr_yaml_node(y, pairs[i].key), *v = cr_yaml_node(y, pairs[i].value);
        cr_yaml_field f[1] = {REQ("enabled")};
        long dev;
        if (!k || !v)
            return cr_yaml_fail(y, map, "gpus", err, "damaged YAML document");
        if (cr_yaml_int(y, k, "gpus", 0, CR_MAX_GPUS - 1, what, &dev, err))
            return -1;
        snprintf(path, sizeof path, "gpus.%ld", dev);
        if (seen[dev])
            return cr_yaml_fail(y, k, path, err,
                                "duplicate GPU %ld (first given at line %lu, column %lu)", dev,
                                (unsigned long)seen[dev]->start_mark.line + 1,
                                (unsigned long)seen[dev]->start_mark.column + 1);
        seen[dev] = k;
        if (cr_yaml_fields(y, v, path, k, f, 1, err) ||
            get_flag(y, &f[0], path, &c->gpu_enabled[dev], err))
            return -1;
    }
    return 0;
}

static int parse_cpu(cr_yaml *y, const cr_yaml_field *sec, cr_sysconfig *c, cr_err *err)
{
    cr_yaml_field f[1] = {OPT("threads")};
    char what[64];
    long v;
    if (parse_section(y, sec, "cpu", f, 1, c, err))
        return -1;
    if (!f[0].value)
        return 0;
    snprintf(what, sizeof what, "a number of threads from 1 to %d", CR_SYSCONFIG_MAX_THREADS);
    if (cr_yaml_int(y, f[0].value, "cpu.threads", 1, CR_SYSCONFIG_MAX_THREADS, what, &v, err))
        return -1;
    c->cpu_threads = (int)v;
    return 0;
}

static int parse_raytracer(cr_yaml *y, const cr_yaml_field *sec, cr_sysconfig *c, cr_err *err)
{
    return parse_section(y, sec, "raytracer", NULL, 0, c, err);
}

static int parse_video(cr_yaml *y, const cr_yaml_field *sec, cr_sysconfig *c, cr_err *err)
{
    enum { FPS, KEEP, N };
    cr_yaml_field f[N] = {OPT("fps"), OPT("keep_frames")};
    char what[64];
    long fps;
    if (cr_yaml_fields(y, sec->value, "video", sec->key_node, f, N, err) ||
        get_flag(y, &f[KEEP], "video", &c->video_keep_frames, err))
        return -1;
    snprintf(what, sizeof what, "a whole number of frames per second from 1 to %d",
             CR_VIDEO_MAX_FPS);
    if (f[FPS].value) {
        if (cr_yaml_int(y, f[FPS].value, "video.fps", 1, CR_VIDEO_MAX_FPS, what, &fps, err))
            return -1;
        c->video_fps = (int)fps;
    }
    return 0;
}

static int parse_log(cr_yaml *y, const cr_yaml_field *sec, cr_sysconfig *c, cr_err *err)
{
    enum { VERBOSE, QUIET, KEEP, N };
    cr_yaml_field f[N] = {OPT("verbose"), OPT("quiet"), OPT("keep_log")};
    const char *p = "log";
    if (cr_yaml_fields(y, sec->value, p, sec->key_node, f, N, err) ||
        get_flag(y, &f[VERBOSE], p, &c->verbose, err) ||
        get_flag(y, &f[QUIET], p, &c->quiet, err) || get_flag(y, &f[KEEP], p, &c->keep_log, err))
        return -1;
    return 0;
}

int cr_sysconfig_load_string(const char *text, size_t len, const char *name, cr_sysconfig *c,
                             cr_err *err)
{
    enum { GPUS, CPU, RAYTRACER, LOG, AUTO, VIDEO, N };
    cr_yaml_field f[N] = {OPT("gpus"), OPT("cpu"),         OPT("raytracer"),
                          OPT("log"),  OPT("auto_accept"), OPT("video")};
    cr_sysconfig tmp;
    cr_yaml y;
    yaml_node_t *root;
    char got[96];

    cr_sysconfig_defaults(&tmp);
    if (cr_yaml_load(&y, text, len, name ? name : "(config)", err))
        return -1;
    root = cr_yaml_root(&y);
    if (root && !cr_yaml_is_null(root)) {
        if (root->type != YAML_MAPPING_NODE) {
            cr_yaml_describe(root, got, sizeof got);
            cr_yaml_fail(&y, root, NULL, err,
                         "a configuration must be a mapping of keys (gpus, cpu, raytracer, "
                         "log, auto_accept, video), got %s",
                         got);
            goto fail;
        }
        if (cr_yaml_fields(&y, root, NULL, NULL, f, N, err))
            goto fail;
        if (f[GPUS].value && parse_gpus(&y, f[GPUS].value, &tmp, err))
            goto fail;
        if ((f[CPU].value && parse_cpu(&y, &f[CPU], &tmp, err)) ||
            (f[RAYTRACER].value && parse_raytracer(&y, &f[RAYTRACER], &tmp, err)) ||
            (f[LOG].value && parse_log(&y, &f[LOG], &tmp, err)) ||
            (f[VIDEO].value && parse_video(&y, &f[VIDEO], &tmp, err)) ||
            get_flag(&y, &f[AUTO], NULL, &tmp.auto_accept, err))
            goto fail;
    }
    cr_yaml_free(&y);
    *c = tmp;
    return 0;
fail:
    cr_yaml_free(&y);
    return -1;
}

int cr_sysconfig_load(const char *path, cr_sysconfig *c, cr_err *err)
{
    char *text;
    size_t len;
    int rc;
    if (!path || !path[0])
        return cr_err_set(err, "no configuration file given");
    if (cr_yaml_read_file(path, (size_t)SYSCONFIG_MAX_BYTES, &text, &len, err))
        return -1;
    rc = cr_sysconfig_load_string(text, len, path, c, err);
    free(text);
    return rc;
}
