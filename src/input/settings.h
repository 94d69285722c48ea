/* curray input: the raytracer settings, generated from the table
 * settings.def (one line per setting): the struct cr_trace_settings, its
 * defaults, and the description of every setting (cr_settings) that the
 * configuration parser (sysconfig.c), the frame check (scene evaluation),
 * info.txt and the run hash walk.
 *
 * Units: lengths in units of M (DESIGN "Conventions"); the unit column of
 * settings.def gives each setting's. */
#ifndef CR_INPUT_SETTINGS_H
#define CR_INPUT_SETTINGS_H

#include <limits.h> /* LONG_MAX in settings.def */
#include <math.h>   /* INFINITY in settings.def */
#include <stddef.h>

#include "../core/defs.h" /* cr_integrator, CR_MAX_SAMPLES */
#include "names.h"

/* The C type of each settings.def type. */
#define CR_SETTING_CTYPE_ENUM int
#define CR_SETTING_CTYPE_REAL double
#define CR_SETTING_CTYPE_LONG long
#define CR_SETTING_CTYPE_SIDE int

/* Settings that are not part of the scene but enter every frame (config.yml
 * raytracer section, settings.def): one field per line of the table. Code
 * that fills one by hand should start from cr_trace_defaults(). samples 0
 * means 1 (cr_scene_frame). */
typedef struct cr_trace_settings {
#define CR_SETTING(section, key, type, field, dflt, lo, hi, unit, use, label, info_pos,         \
                   hash_pos, hash_word, doc)                                                    \
    CR_SETTING_CTYPE_##type field;
#include "settings.def"
#undef CR_SETTING
} cr_trace_settings;

/* The built-in defaults (the default column of settings.def). */
static inline cr_trace_settings cr_trace_defaults(void)
{
    cr_trace_settings t;
#define CR_SETTING(section, key, type, field, dflt, lo, hi, unit, use, label, info_pos,         \
                   hash_pos, hash_word, doc)                                                    \
    t.field = dflt;
#include "settings.def"
#undef CR_SETTING
    return t;
}

/* Copy the settings that the frame carries (use FRAME, MINO, RK4) into the
 * frame's fields of the same names. */
#define CR_SETTING_TO_FRAME_FRAME(f, ts, field) (f)->field = (ts)->field;
#define CR_SETTING_TO_FRAME_MINO(f, ts, field) (f)->field = (ts)->field;
#define CR_SETTING_TO_FRAME_RK4(f, ts, field) (f)->field = (ts)->field;
#define CR_SETTING_TO_FRAME_RUN(f, ts, field)
static inline void cr_trace_settings_to_frame(const cr_trace_settings *ts, cr_frame *f)
{
#define CR_SETTING(section, key, type, field, dflt, lo, hi, unit, use, label, info_pos,         \
                   hash_pos, hash_word, doc)                                                    \
    CR_SETTING_TO_FRAME_##use(f, ts, field)
#include "settings.def"
#undef CR_SETTING
}

typedef enum cr_setting_type {
    CR_SETTING_ENUM,
    CR_SETTING_REAL,
    CR_SETTING_LONG,
    CR_SETTING_SIDE
} cr_setting_type;

/* CR_SETTING_ANY: every integrator uses the setting; else the cr_integrator
 * that does. */
#define CR_SETTING_ANY (-1)

/* One line of settings.def. */
typedef struct cr_setting {
    const char *section, *key;
    cr_setting_type type;
    size_t offset;        /* of the field in cr_trace_settings */
    double real_lo, real_hi; /* REAL: lo < v < hi */
    long int_lo, int_hi;     /* LONG, SIDE: lo <= v <= hi; ENUM: int_lo = the cr_names kind */
    const char *unit;
    int in_frame;   /* use is not RUN */
    size_t frame_offset; /* in_frame: of the field of the same name in cr_frame */
    int integrator; /* CR_SETTING_ANY, or the only cr_integrator that uses it */
    const char *label;
    int info_pos, hash_pos;
    const char *hash_word, *doc;
} cr_setting;

/* The table, in settings.def order, and its length. */
extern const cr_setting cr_settings[];
extern const int cr_settings_count;

/* The setting at place pos of info.txt (CR_SETTING_INFO_ORDER) or of the run
 * hash (CR_SETTING_HASH_ORDER), or NULL when pos is outside 0 ..
 * cr_settings_count - 1. */
#define CR_SETTING_INFO_ORDER 0
#define CR_SETTING_HASH_ORDER 1
const cr_setting *cr_setting_in_order(int order, int pos);

/* "section.key" of s into buf. */
void cr_setting_path(const cr_setting *s, char *buf, size_t n);

/* The value of s in ts: a REAL's as a double, the others' (ENUM, LONG, SIDE)
 * as a long; and set it (an int field takes (int)v). */
double cr_setting_real(const cr_setting *s, const cr_trace_settings *ts);
long cr_setting_int(const cr_setting *s, const cr_trace_settings *ts);
void cr_setting_set_real(const cr_setting *s, cr_trace_settings *ts, double v);
void cr_setting_set_int(const cr_setting *s, cr_trace_settings *ts, long v);

/* Check every setting of ts that enters the frame (use not RUN) against
 * its limits, in table order: 0, or -1 with msg set to "section.key =
 * value must ..." for the first one out of them. (A RUN setting is the
 * run's, checked where the configuration is read.) */
int cr_trace_settings_check(const cr_trace_settings *ts, char *msg, size_t n);

/* The value of s in ts as info.txt shows it ("0.005", "mino", "200000",
 * "3 x 3 per pixel", "1e-07 (mino only, unused)"). */
void cr_setting_format(const cr_setting *s, const cr_trace_settings *ts, char *buf, size_t n);

/* The settings that the first hashed runs had (hash_pos below this): always
 * in the run hash text. A setting added later enters it only when it is not
 * at its default, so that a run begun before it existed still resumes. */
#define CR_SETTINGS_HASHED_ALWAYS 7

/* The settings' part of the run hash text: "hash_word value" for each
 * setting in hash_pos order (CR_SETTINGS_HASHED_ALWAYS), separated by single
 * blanks (values with %.17g or %ld, so equal text means equal settings).
 * Returns the length snprintf would write (the text is cut to n - 1). */
int cr_trace_settings_hash_text(const cr_trace_settings *ts, char *buf, size_t n);

#endif
