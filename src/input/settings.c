/* curray input: the table of raytracer settings (settings.h). */
#include "settings.h"

#include <stdio.h>
#include <string.h>

#define SETTING_TYPE(type) CR_SETTING_##type
#define SETTING_REAL_LO_REAL(lo) (lo)
#define SETTING_REAL_LO_ENUM(lo) 0.0
#define SETTING_REAL_LO_LONG(lo) 0.0
#define SETTING_REAL_LO_SIDE(lo) 0.0
#define SETTING_INT_LO_REAL(lo) 0L
#define SETTING_INT_LO_ENUM(lo) (long)(lo)
#define SETTING_INT_LO_LONG(lo) (long)(lo)
#define SETTING_INT_LO_SIDE(lo) (long)(lo)
#define SETTING_IN_FRAME_FRAME 1
#define SETTING_IN_FRAME_MINO 1
#define SETTING_IN_FRAME_RK4 1
#define SETTING_IN_FRAME_RUN 0
#define SETTING_FRAME_OFFSET_FRAME(field) offsetof(cr_frame, field)
#define SETTING_FRAME_OFFSET_MINO(field) offsetof(cr_frame, field)
#define SETTING_FRAME_OFFSET_RK4(field) offsetof(cr_frame, field)
#define SETTING_FRAME_OFFSET_RUN(field) 0
#define SETTING_INTEGRATOR_FRAME CR_SETTING_ANY
#define SETTING_INTEGRATOR_MINO CR_INTEG_MINO
#define SETTING_INTEGRATOR_RK4 CR_INTEG_RK4
#define SETTING_INTEGRATOR_RUN CR_SETTING_ANY

const cr_setting cr_settings[] = {
#define CR_SETTING(section, key, type, field, dflt, lo, hi, unit, use, label, info_pos,         \
                   hash_pos, hash_word, doc)                                                    \
    {#section,                                                                                  \
     #key,                                                                                      \
     SETTING_TYPE(type),                                                                        \
     offsetof(cr_trace_settings, field),                                                        \
     SETTING_REAL_LO_##type(lo),                                                                \
     SETTING_REAL_LO_##type(hi),                                                                \
     SETTING_INT_LO_##type(lo),                                                                 \
     SETTING_INT_LO_##type(hi),                                                                 \
     unit,                                                                                      \
     SETTING_IN_FRAME_##use,                                                                    \
     SETTING_FRAME_OFFSET_##use(field),                                                         \
     SETTING_INTEGRATOR_##use,                                                                  \
     label,                                                                                     \
     info_pos,                                                                                  \
     hash_pos,                                                                                  \
     hash_word,                                                                                 \
     doc},
#include "settings.def"
#undef CR_SETTING
};

const int cr_settings_count = (int)(sizeof cr_settings / sizeof cr_settings[0]);

const cr_setting *cr_setting_in_order(int order, int pos)
{
    for (int i = 0; i < cr_settings_count; i++)
        if ((order == CR_SETTING_HASH_ORDER ? cr_settings[i].hash_pos : cr_settings[i].info_pos) ==
            pos)
            return &cr_settings[i];
    return NULL;
}

void cr_setting_path(const cr_setting *s, char *buf, size_t n)
{
    snprintf(buf, n, "%s.%s", s->section, s->key);
}

double cr_setting_real(const cr_setting *s, const cr_trace_settings *ts)
{
    const char *p = (const char *)ts + s->offset;
    return s->type == CR_SETTING_REAL ? *(const double *)(const void *)p
                                      : (double)cr_setting_int(s, ts);
}

long cr_setting_int(const cr_setting *s, const cr_trace_settings *ts)
{
    const char *p = (const char *)ts + s->offset;
    switch (s->type) {
    case CR_SETTING_LONG:
        return *(const long *)(const void *)p;
    case CR_SETTING_REAL:
        return (long)*(const double *)(const void *)p;
    default: /* ENUM, SIDE */
        return (long)*(const int *)(const void *)p;
    }
}

void cr_setting_set_real(const cr_setting *s, cr_trace_settings *ts, double v)
{
    if (s->type == CR_SETTING_REAL)
        *(double *)(void *)((char *)ts + s->offset) = v;
}

void cr_setting_set_int(const cr_setting *s, cr_trace_settings *ts, long v)
{
    char *p = (char *)ts + s->offset;
    if (s->type == CR_SETTING_LONG)
        *(long *)(void *)p = v;
    else if (s->type != CR_SETTING_REAL)
        *(int *)(void *)p = (int)v;
}

/* "a" or "an" before word. */
static const char *article(const char *word)
{
    return strchr("aeiou", word[0]) && word[0] ? "an" : "a";
}

int cr_trace_settings_check(const cr_trace_settings *ts, char *msg, size_t n)
{
    char path[96];
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        if (!s->in_frame)
            continue;
        cr_setting_path(s, path, sizeof path);
        if (s->type == CR_SETTING_REAL) {
            double v = cr_setting_real(s, ts);
            if (v > s->real_lo && v < s->real_hi && isfinite(v))
                continue;
            if (s->real_lo == 0.0 && s->real_hi == INFINITY)
                snprintf(msg, n, "%s = %g must be positive", path, v);
            else
                snprintf(msg, n, "%s = %g must lie above %g and below %g", path, v, s->real_lo,
                         s->real_hi);
            return -1;
        }
        if (s->type == CR_SETTING_ENUM) {
            long v = cr_setting_int(s, ts);
            cr_names kind = (cr_names)s->int_lo;
            if (v >= 0 && v < cr_names_count(kind))
                continue;
            snprintf(msg, n, "%s = %ld is not %s %s (expected one of: %s)", path, v,
                     article(s->key), s->key, cr_names_list(kind));
            return -1;
        }
        {
            long v = cr_setting_int(s, ts);
            if (v >= s->int_lo && v <= s->int_hi)
                continue;
            if (s->int_lo == 1 && s->int_hi == LONG_MAX)
                snprintf(msg, n, "%s = %ld must be positive", path, v);
            else
                snprintf(msg, n, "%s = %ld must be an integer from %ld to %ld", path, v,
                         s->int_lo, s->int_hi);
            return -1;
        }
    }
    return 0;
}

void cr_setting_format(const cr_setting *s, const cr_trace_settings *ts, char *buf, size_t n)
{
    int k = 0;
    switch (s->type) {
    case CR_SETTING_REAL:
        k = snprintf(buf, n, "%.10g", cr_setting_real(s, ts));
        break;
    case CR_SETTING_LONG:
        k = snprintf(buf, n, "%ld", cr_setting_int(s, ts));
        break;
    case CR_SETTING_ENUM:
        k = snprintf(buf, n, "%s", cr_name((cr_names)s->int_lo, (int)cr_setting_int(s, ts)));
        break;
    case CR_SETTING_SIDE:
        k = snprintf(buf, n, "%ld x %ld per pixel", cr_setting_int(s, ts), cr_setting_int(s, ts));
        break;
    }
    if (s->integrator != CR_SETTING_ANY && ts->integrator != s->integrator && k >= 0 &&
        (size_t)k < n)
        snprintf(buf + k, n - (size_t)k, " (%s only, unused)", cr_integrator_name(s->integrator));
}

/* Does s have its default value in ts? */
static int setting_is_default(const cr_setting *s, const cr_trace_settings *ts)
{
    cr_trace_settings d = cr_trace_defaults();
    if (s->type == CR_SETTING_REAL)
        return cr_setting_real(s, ts) == cr_setting_real(s, &d);
    return cr_setting_int(s, ts) == cr_setting_int(s, &d);
}

int cr_trace_settings_hash_text(const cr_trace_settings *ts, char *buf, size_t n)
{
    size_t len = 0;
    for (int pos = 0; pos < cr_settings_count; pos++) {
        const cr_setting *s = cr_setting_in_order(CR_SETTING_HASH_ORDER, pos);
        char v[64];
        int k;
        if (!s)
            continue;
        if (pos >= CR_SETTINGS_HASHED_ALWAYS && setting_is_default(s, ts))
            continue;
        if (s->type == CR_SETTING_REAL)
            snprintf(v, sizeof v, "%.17g", cr_setting_real(s, ts));
        else
            snprintf(v, sizeof v, "%ld", cr_setting_int(s, ts));
        k = snprintf(len < n ? buf + len : NULL, len < n ? n - len : 0, "%s%s %s",
                     len ? " " : "", s->hash_word, v);
        if (k > 0)
            len += (size_t)k;
    }
    return (int)len;
}
