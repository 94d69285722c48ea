/* curray output: the table of output types (types.h). */
#include "types.h"

#include <stdio.h>
#include <string.h>

#include "fits.h"
#include "lightcurve.h"
#include "output.h"
#include "spectrum.h"

/* Table order is the order the per-frame files of a frame are written and
 * the order the letters are listed in messages. */
static const cr_output_type cr_output_types[] = {
    /* letter, scope, file, per-frame writer, implies, available, unavailable */
    {'i', CR_OUTPUT_PER_RUN, "info.txt", NULL, 0, NULL, NULL},                /* info.h */
    {'c', CR_OUTPUT_PER_FRAME, "png", cr_output_write_color, 0, NULL, NULL},
    {'r', CR_OUTPUT_PER_FRAME, "png", cr_output_write_redshift, 0, NULL, NULL},
    {'d', CR_OUTPUT_PER_FRAME, "csv", cr_output_write_csv, 0, NULL, NULL},
    {'b', CR_OUTPUT_PER_FRAME, "png", cr_output_write_bolometric, 0, NULL, NULL},
    {'n', CR_OUTPUT_PER_FRAME, "png", cr_output_write_order, 0, NULL, NULL},
    {'s', CR_OUTPUT_PER_FRAME, "csv", cr_output_write_spectrum, 0, NULL, NULL},
    {'l', CR_OUTPUT_PER_FRAME, "csv", cr_output_write_lightcurve, 0, NULL, NULL},
    {'f', CR_OUTPUT_PER_FRAME, "fits", cr_output_write_fits, 0, cr_fits_available,
     CR_FITS_MISSING},
    {'v', CR_OUTPUT_PER_RUN, "c.mp4", NULL, 'c', NULL, NULL},                 /* video.h */
};

#define CR_N_OUTPUT_TYPES ((int)(sizeof cr_output_types / sizeof cr_output_types[0]))

const cr_output_type *cr_output_type_find(char t)
{
    for (int i = 0; i < CR_N_OUTPUT_TYPES; i++)
        if (cr_output_types[i].letter == t)
            return &cr_output_types[i];
    return NULL;
}

const cr_output_type *cr_output_type_at(int i)
{
    return i >= 0 && i < CR_N_OUTPUT_TYPES ? &cr_output_types[i] : NULL;
}

int cr_output_type_count(void)
{
    return CR_N_OUTPUT_TYPES;
}

/* "i, c, r, d, b, n, s, l, f, v" into out[n]. */
static void cr_output_letters_list(char *out, size_t n)
{
    size_t len = 0;
    out[0] = '\0';
    for (int i = 0; i < CR_N_OUTPUT_TYPES && len < n; i++) {
        int w = snprintf(out + len, n - len, "%s%c", i ? ", " : "", cr_output_types[i].letter);
        if (w < 0)
            break;
        len += (size_t)w;
    }
}

int cr_output_types_check(const char *types, cr_err *err)
{
    char list[128];
    const char *p;
    cr_output_letters_list(list, sizeof list);
    if (!types[0])
        return cr_err_set(err, "-t: empty output type; use any of %s", list);
    for (p = types; *p; p++)
        if (!cr_output_type_find(*p))
            return cr_err_set(err, "-t: unknown output type '%c' in '%s'; use any of %s", *p,
                              types, list);
    for (int i = 0; i < CR_N_OUTPUT_TYPES; i++) {
        const cr_output_type *t = &cr_output_types[i];
        cr_err why = {""};
        if (t->available && strchr(types, t->letter) && !t->available(&why))
            return cr_err_set(err, "%s", why.msg[0] ? why.msg : t->unavailable);
    }
    return 0;
}

int cr_output_types_has(const char *types, char t)
{
    if (t == '\0')
        return 0;
    for (const char *p = types; *p; p++) {
        const cr_output_type *row = cr_output_type_find(*p);
        if (*p == t || (row && row->implies == t))
            return 1;
    }
    return 0;
}

void cr_output_frame_letters(const char *types, char *out, size_t n)
{
    size_t len = 0;
    for (int i = 0; i < CR_N_OUTPUT_TYPES && len + 1 < n; i++)
        if (cr_output_types[i].scope == CR_OUTPUT_PER_FRAME &&
            cr_output_types_has(types, cr_output_types[i].letter))
            out[len++] = cr_output_types[i].letter;
    if (n)
        out[len] = '\0';
}

int cr_output_file_name(char t, int k, char *out, size_t n)
{
    const cr_output_type *row = cr_output_type_find(t);
    int len;
    if (!row || row->scope != CR_OUTPUT_PER_FRAME)
        return -1;
    len = snprintf(out, n, "%c_%d.%s", t, k, row->file);
    return len < 0 || (size_t)len >= n ? -1 : 0;
}
