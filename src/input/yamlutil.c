/* curray io: checked access to libyaml documents (see yamlutil.h). */
#include "yamlutil.h"

#include <errno.h>
#include <limits.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/defs.h"

/* Longest number text converted (digits of a double beyond this are noise). */
#define NUMBER_MAX 128
/* Characters of a scalar shown in messages before it is shortened. */
#define SHOW_MAX 48
/* Deepest nesting of lists and mappings accepted. libyaml's scanner takes
 * time quadratic in the depth of flow collections (it rechecks every open
 * level at each token): a few megabytes of '[' would run for hours. curray's
 * files nest three levels deep. */
#define NEST_MAX 64

/* ---- messages ------------------------------------------------------------ */

static int vfail_at(const cr_yaml *y, yaml_mark_t mark, const char *path, cr_err *err,
                    const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 0)))
#endif
    ;

static int vfail_at(const cr_yaml *y, yaml_mark_t mark, const char *path, cr_err *err,
                    const char *fmt, va_list ap)
{
    char what[CR_ERR_MSG];
    vsnprintf(what, sizeof what, fmt, ap);
    if (path && path[0])
        return cr_err_set(err, "%s:%lu:%lu: %s: %s", y->name, (unsigned long)mark.line + 1,
                          (unsigned long)mark.column + 1, path, what);
    return cr_err_set(err, "%s:%lu:%lu: %s", y->name, (unsigned long)mark.line + 1,
                      (unsigned long)mark.column + 1, what);
}

int cr_yaml_fail_at(const cr_yaml *y, yaml_mark_t mark, const char *path, cr_err *err,
                    const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail_at(y, mark, path, err, fmt, ap);
    va_end(ap);
    return -1;
}

int cr_yaml_fail(const cr_yaml *y, const yaml_node_t *node, const char *path, cr_err *err,
                 const char *fmt, ...)
{
    va_list ap;
    yaml_mark_t mark;
    memset(&mark, 0, sizeof mark);
    if (node)
        mark = node->start_mark;
    va_start(ap, fmt);
    vfail_at(y, mark, path, err, fmt, ap);
    va_end(ap);
    return -1;
}

/* Write text[0..len) between quote characters q into buf (size n >= 1),
 * escaping q, backslash and control bytes, shortened to SHOW_MAX bytes at a
 * UTF-8 character boundary with "..." appended. */
static void quote_text(const char *text, size_t len, char q, char *buf, size_t n)
{
    size_t o = 0, i, shown = len;
    int cut = 0;
    if (n == 0)
        return;
    if (shown > SHOW_MAX) {
        shown = SHOW_MAX;
        while (shown > 0 && ((unsigned char)text[shown] & 0xC0) == 0x80)
            shown--;
        cut = 1;
    }
#define PUT(c)                                                                                 \
    do {                                                                                       \
        if (o + 1 < n)                                                                         \
            buf[o++] = (char)(c);                                                              \
    } while (0)
    PUT(q);
    for (i = 0; i < shown; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c == (unsigned char)q || c == '\\') {
            PUT('\\');
            PUT(c);
        } else if (c == '\n') {
            PUT('\\');
            PUT('n');
        } else if (c == '\t') {
            PUT('\\');
            PUT('t');
        } else if (c < 0x20 || c == 0x7F) {
            static const char hex[] = "0123456789abcdef";
            PUT('\\');
            PUT('x');
            PUT(hex[c >> 4]);
            PUT(hex[c & 15]);
        } else {
            PUT(c);
        }
    }
    if (cut) {
        PUT('.');
        PUT('.');
        PUT('.');
    }
    PUT(q);
#undef PUT
    buf[o] = '\0';
}

static const char *scalar_text(const yaml_node_t *node)
{
    return (const char *)node->data.scalar.value;
}

void cr_yaml_describe(const yaml_node_t *node, char *buf, size_t n)
{
    int count;
    if (n == 0)
        return;
    if (!node) {
        snprintf(buf, n, "nothing");
        return;
    }
    switch (node->type) {
    case YAML_SCALAR_NODE:
        if (node->data.scalar.length == 0 && node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE)
            snprintf(buf, n, "nothing (an empty value)");
        else
            quote_text(scalar_text(node), node->data.scalar.length, '"', buf, n);
        return;
    case YAML_SEQUENCE_NODE:
        count = (int)(node->data.sequence.items.top - node->data.sequence.items.start);
        if (count == 0)
            snprintf(buf, n, "an empty list");
        else
            snprintf(buf, n, "a list of %d item%s", count, count == 1 ? "" : "s");
        return;
    case YAML_MAPPING_NODE:
        snprintf(buf, n, "a mapping");
        return;
    default:
        snprintf(buf, n, "nothing");
        return;
    }
}

void cr_yaml_path_key(char *out, size_t n, const char *parent, const char *key)
{
    if (parent && parent[0])
        snprintf(out, n, "%s.%s", parent, key);
    else
        snprintf(out, n, "%s", key);
}

void cr_yaml_path_index(char *out, size_t n, const char *parent, int i)
{
    snprintf(out, n, "%s[%d]", parent ? parent : "", i);
}

/* ---- loading -------------------------------------------------------------- */

/* Report a libyaml parser failure. text is the input (for the line of a
 * reader error, which libyaml gives as a byte offset only). */
static int parser_error(const cr_yaml *y, const yaml_parser_t *p, const char *text, size_t len,
                        cr_err *err)
{
    const char *problem = p->problem ? p->problem : "unknown error";
    switch (p->error) {
    case YAML_MEMORY_ERROR:
        return cr_err_set(err, "%s: out of memory while reading YAML", y->name);
    case YAML_READER_ERROR: {
        unsigned long line = 1, col = 1;
        size_t i, end = p->problem_offset < len ? p->problem_offset : len;
        for (i = 0; i < end; i++) {
            if (text[i] == '\n') {
                line++;
                col = 1;
            } else {
                col++;
            }
        }
        if (p->problem_value != -1)
            return cr_err_set(err, "%s:%lu:%lu: YAML syntax error: %s (byte 0x%02X)", y->name,
                              line, col, problem, (unsigned)p->problem_value & 0xFFu);
        return cr_err_set(err, "%s:%lu:%lu: YAML syntax error: %s", y->name, line, col,
                          problem);
    }
    default:
        if (p->context)
            return cr_err_set(err, "%s:%lu:%lu: YAML syntax error: %s (%s at line %lu, column %lu)",
                              y->name, (unsigned long)p->problem_mark.line + 1,
                              (unsigned long)p->problem_mark.column + 1, problem, p->context,
                              (unsigned long)p->context_mark.line + 1,
                              (unsigned long)p->context_mark.column + 1);
        return cr_err_set(err, "%s:%lu:%lu: YAML syntax error: %s", y->name,
                          (unsigned long)p->problem_mark.line + 1,
                          (unsigned long)p->problem_mark.column + 1, problem);
    }
}

/* Walk the events of text while the nesting stays within NEST_MAX levels:
 * -1 with a message at the first deeper collection, else 0 (syntax errors
 * are left to yaml_parser_load, which reports them the same way). */
static int check_nesting(const cr_yaml *y, const char *text, size_t len, cr_err *err)
{
    yaml_parser_t p;
    yaml_event_t ev;
    int depth = 0, rc = 0, done = 0;
    if (!yaml_parser_initialize(&p))
        return cr_err_set(err, "%s: out of memory while reading YAML", y->name);
    yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
    while (!done && yaml_parser_parse(&p, &ev)) {
        if (ev.type == YAML_SEQUENCE_START_EVENT || ev.type == YAML_MAPPING_START_EVENT) {
            if (++depth > NEST_MAX) {
                rc = cr_yaml_fail_at(y, ev.start_mark, NULL, err,
                                     "lists and mappings nested more than %d levels deep",
                                     NEST_MAX);
                done = 1;
            }
        } else if (ev.type == YAML_SEQUENCE_END_EVENT || ev.type == YAML_MAPPING_END_EVENT) {
            depth--;
        } else if (ev.type == YAML_STREAM_END_EVENT) {
            done = 1;
        }
        yaml_event_delete(&ev);
    }
    yaml_parser_delete(&p);
    return rc;
}

int cr_yaml_load(cr_yaml *y, const char *text, size_t len, const char *name, cr_err *err)
{
    yaml_parser_t parser;
    yaml_document_t extra;
    yaml_node_t *second;
    int parser_ok = 0;

    memset(y, 0, sizeof *y);
    y->name = name ? name : "(input)";
    if (!text) {
        text = "";
        len = 0;
    }
    if (check_nesting(y, text, len, err))
        return -1;
    if (!yaml_parser_initialize(&parser))
        return cr_err_set(err, "%s: out of memory while reading YAML", y->name);
    parser_ok = 1;
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, len);
    if (!yaml_parser_load(&parser, &y->doc)) {
        parser_error(y, &parser, text, len, err);
        goto fail;
    }
    y->loaded = 1;
    if (yaml_document_get_root_node(&y->doc)) {
        if (!yaml_parser_load(&parser, &extra)) {
            parser_error(y, &parser, text, len, err);
            goto fail;
        }
        second = yaml_document_get_root_node(&extra);
        if (second) {
            cr_yaml_fail(y, second, NULL, err,
                         "a second YAML document starts here; the file must hold one");
            yaml_document_delete(&extra);
            goto fail;
        }
        yaml_document_delete(&extra);
    }
    yaml_parser_delete(&parser);
    return 0;
fail:
    if (parser_ok)
        yaml_parser_delete(&parser);
    cr_yaml_free(y);
    return -1;
}

void cr_yaml_free(cr_yaml *y)
{
    if (!y)
        return;
    if (y->loaded)
        yaml_document_delete(&y->doc);
    y->loaded = 0;
}

yaml_node_t *cr_yaml_root(cr_yaml *y)
{
    return y->loaded ? yaml_document_get_root_node(&y->doc) : NULL;
}

yaml_node_t *cr_yaml_node(cr_yaml *y, int idx)
{
    return y->loaded ? yaml_document_get_node(&y->doc, idx) : NULL;
}

int cr_yaml_read_file(const char *path, size_t max_bytes, char **text, size_t *len,
                      cr_err *err)
{
    FILE *fp = NULL;
    char *buf = NULL, *grown;
    size_t n = 0, cap = 0, got;

    *text = NULL;
    *len = 0;
    fp = fopen(path, "rb");
    if (!fp) {
        cr_err_set(err, "%s: cannot open: %s", path, strerror(errno));
        goto fail;
    }
    for (;;) {
        if (cap - n < 4096 + 1) {
            size_t ncap = cap ? 2 * cap : 8192;
            if (ncap > max_bytes + 4096 + 1)
                ncap = max_bytes + 4096 + 1;
            if (ncap <= cap) {
                cr_err_set(err, "%s: file too large (more than %lu bytes)", path,
                           (unsigned long)max_bytes);
                goto fail;
            }
            grown = realloc(buf, ncap);
            if (!grown) {
                cr_err_set(err, "%s: out of memory", path);
                goto fail;
            }
            buf = grown;
            cap = ncap;
        }
        got = fread(buf + n, 1, cap - n - 1, fp);
        n += got;
        if (n > max_bytes) {
            cr_err_set(err, "%s: file too large (more than %lu bytes)", path,
                       (unsigned long)max_bytes);
            goto fail;
        }
        if (got == 0) {
            if (ferror(fp)) {
                cr_err_set(err, "%s: read error: %s", path, strerror(errno));
                goto fail;
            }
            break;
        }
    }
    if (!buf) {
        buf = malloc(1);
        if (!buf) {
            cr_err_set(err, "%s: out of memory", path);
            goto fail;
        }
    }
    buf[n] = '\0';
    fclose(fp);
    *text = buf;
    *len = n;
    return 0;
fail:
    if (fp)
        fclose(fp);
    free(buf);
    return -1;
}

/* ---- structure ------------------------------------------------------------ */

int cr_yaml_is_null(const yaml_node_t *node)
{
    const char *s;
    size_t n;
    if (!node || node->type != YAML_SCALAR_NODE ||
        node->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return 0;
    s = scalar_text(node);
    n = node->data.scalar.length;
    return n == 0 || (n == 1 && s[0] == '~') ||
           (n == 4 && (!memcmp(s, "null", 4) || !memcmp(s, "Null", 4) || !memcmp(s, "NULL", 4)));
}

int cr_yaml_scalar_is(const yaml_node_t *node, const char *s)
{
    size_t n = strlen(s);
    return node && node->type == YAML_SCALAR_NODE && node->data.scalar.length == n &&
           memcmp(node->data.scalar.value, s, n) == 0;
}

int cr_yaml_mapping(cr_yaml *y, yaml_node_t *node, const char *path, yaml_node_pair_t **pairs,
                    int *n_pairs, cr_err *err)
{
    char got[SHOW_MAX + 32];
    *pairs = NULL;
    *n_pairs = 0;
    if (cr_yaml_is_null(node))
        return 0;
    if (!node || node->type != YAML_MAPPING_NODE) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err, "expected a mapping of keys, got %s", got);
    }
    *pairs = node->data.mapping.pairs.start;
    *n_pairs = (int)(node->data.mapping.pairs.top - node->data.mapping.pairs.start);
    return 0;
}

/* "key1, key2, ..." of the allowed keys into buf. */
static void list_keys(const cr_yaml_field *f, int n, char *buf, size_t size)
{
    size_t o = 0;
    int j;
    buf[0] = '\0';
    for (j = 0; j < n && o < size; j++) {
        int w = snprintf(buf + o, size - o, "%s%s", j ? ", " : "", f[j].key);
        if (w < 0)
            break;
        o += (size_t)w;
    }
}

int cr_yaml_fields(cr_yaml *y, yaml_node_t *map, const char *path, const yaml_node_t *where,
                   cr_yaml_field *f, int n, cr_err *err)
{
    yaml_node_pair_t *pairs;
    int np, i, j;
    char got[SHOW_MAX + 32], keys[512], sub[CR_YAML_PATH];

    for (j = 0; j < n; j++) {
        f[j].key_node = NULL;
        f[j].value = NULL;
        f[j].count = 0;
    }
    if (cr_yaml_mapping(y, map, path, &pairs, &np, err))
        return -1;
    for (i = 0; i < np; i++) {
        yaml_node_t *k = cr_yaml_node(y, pairs[i].key);
        yaml_node_t *v = cr_yaml_node(y, pairs[i].value);
        if (!k || !v)
            return cr_yaml_fail(y, map, path, err, "damaged YAML document");
        if (k->type != YAML_SCALAR_NODE) {
            cr_yaml_describe(k, got, sizeof got);
            return cr_yaml_fail(y, k, path, err, "expected a key name, got %s", got);
        }
        for (j = 0; j < n; j++)
            if (cr_yaml_scalar_is(k, f[j].key))
                break;
        if (j == n) {
            quote_text(scalar_text(k), k->data.scalar.length, '\'', got, sizeof got);
            list_keys(f, n, keys, sizeof keys);
            if (path && path[0])
                return cr_yaml_fail(y, k, NULL, err, "unknown key %s in %s (expected one of: %s)",
                                    got, path, keys);
            return cr_yaml_fail(y, k, NULL, err,
                                "unknown key %s at the top level (expected one of: %s)", got, keys);
        }
        if (f[j].count > 0 && !f[j].repeatable) {
            cr_yaml_path_key(sub, sizeof sub, path, f[j].key);
            return cr_yaml_fail(y, k, sub, err,
                                "duplicate key '%s' (first given at line %lu, column %lu)",
                                f[j].key, (unsigned long)f[j].key_node->start_mark.line + 1,
                                (unsigned long)f[j].key_node->start_mark.column + 1);
        }
        if (f[j].count == 0) {
            f[j].key_node = k;
            f[j].value = v;
        }
        f[j].count++;
    }
    for (j = 0; j < n; j++) {
        if (f[j].required && f[j].count == 0) {
            yaml_mark_t mark = where ? where->start_mark : map->start_mark;
            return cr_yaml_fail_at(y, mark, path, err, "missing required key '%s'", f[j].key);
        }
    }
    return 0;
}

int cr_yaml_list(cr_yaml *y, yaml_node_t *node, const char *path, int n, const char *what,
                 yaml_node_t **items, int *count, cr_err *err)
{
    char got[SHOW_MAX + 32], deflt[48];
    int m, i;

    if (!what) {
        if (n >= 0)
            snprintf(deflt, sizeof deflt, "a list of %d items", n);
        else
            snprintf(deflt, sizeof deflt, "a list");
        what = deflt;
    }
    if (count)
        *count = 0;
    if (n < 0 && cr_yaml_is_null(node))
        return 0;
    if (!node || node->type != YAML_SEQUENCE_NODE) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
    }
    m = (int)(node->data.sequence.items.top - node->data.sequence.items.start);
    if (n >= 0 && m != n) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
    }
    if (count)
        *count = m;
    if (items && n > 0) {
        for (i = 0; i < n; i++) {
            items[i] = cr_yaml_node(y, node->data.sequence.items.start[i]);
            if (!items[i])
                return cr_yaml_fail(y, node, path, err, "damaged YAML document");
        }
    }
    return 0;
}

/* ---- scalars -------------------------------------------------------------- */

static int is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

static int is_alpha(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

static char lower(char c)
{
    return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c;
}

/* Case-insensitive: s[0..n) equals the lower-case word w. */
static int word_is(const char *s, size_t n, const char *w)
{
    size_t i;
    if (strlen(w) != n)
        return 0;
    for (i = 0; i < n; i++)
        if (lower(s[i]) != w[i])
            return 0;
    return 1;
}

/* The text of a scalar node with surrounding blanks removed. Returns -1 for
 * a node that is not a scalar or holds a NUL byte. */
static int scalar_trimmed(const yaml_node_t *node, const char **s, size_t *n)
{
    const char *t;
    size_t len;
    if (!node || node->type != YAML_SCALAR_NODE)
        return -1;
    t = scalar_text(node);
    len = node->data.scalar.length;
    if (memchr(t, '\0', len))
        return -1;
    while (len > 0 && is_blank(t[0])) {
        t++;
        len--;
    }
    while (len > 0 && is_blank(t[len - 1]))
        len--;
    *s = t;
    *n = len;
    return 0;
}

/* Length of the decimal number at the start of s[0..n):
 * [+-] digits [. digits] [(e|E) [+-] digits], at least one mantissa digit;
 * 0 when there is none. */
static size_t scan_decimal(const char *s, size_t n)
{
    size_t i = 0, digits = 0, save;
    if (i < n && (s[i] == '+' || s[i] == '-'))
        i++;
    while (i < n && is_digit(s[i])) {
        i++;
        digits++;
    }
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && is_digit(s[i])) {
            i++;
            digits++;
        }
    }
    if (digits == 0)
        return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        save = i++;
        if (i < n && (s[i] == '+' || s[i] == '-'))
            i++;
        if (i < n && is_digit(s[i])) {
            while (i < n && is_digit(s[i]))
                i++;
        } else {
            i = save;
        }
    }
    return i;
}

/* 1 when the first blank-separated word of s[0..n) spells a non-finite
 * value: [+-] nan, inf, infinity, .nan, .inf in any case. */
static int nonfinite_word(const char *s, size_t n)
{
    size_t w = 0;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) {
        s++;
        n--;
    }
    while (w < n && !is_blank(s[w]))
        w++;
    return word_is(s, w, "nan") || word_is(s, w, "inf") || word_is(s, w, "infinity") ||
           word_is(s, w, ".nan") || word_is(s, w, ".inf");
}

/* Convert the decimal number s[0..n) found by scan_decimal. Returns 0, or 1
 * when it is not finite as a double (1e999), or 2 when it is too long. */
static int to_double(const char *s, size_t n, double *out)
{
    char buf[NUMBER_MAX + 1], *end;
    const struct lconv *lc;
    double v;
    size_t i;
    if (n > NUMBER_MAX)
        return 2;
    memcpy(buf, s, n);
    buf[n] = '\0';
    /* strtod follows LC_NUMERIC; YAML always uses '.' */
    lc = localeconv();
    if (lc && lc->decimal_point && lc->decimal_point[0] && !lc->decimal_point[1] &&
        lc->decimal_point[0] != '.')
        for (i = 0; i < n; i++)
            if (buf[i] == '.')
                buf[i] = lc->decimal_point[0];
    errno = 0;
    v = strtod(buf, &end);
    if (end != buf + n)
        return 2;
    if (!isfinite(v))
        return 1;
    *out = v;
    return 0;
}

/* Split a scalar into a number and the word after it (the unit, possibly
 * empty). Returns 0, or -1 with a message built from expect (the "expected
 * ..." phrase) and finite_what ("number", "angle"). */
static int number_and_unit(cr_yaml *y, yaml_node_t *node, const char *path, const char *expect,
                           const char *finite_what, double *v, const char **unit,
                           size_t *unit_len, cr_err *err)
{
    char got[SHOW_MAX + 32];
    const char *s;
    size_t n, k;
    int rc;

    cr_yaml_describe(node, got, sizeof got);
    if (!node || node->type != YAML_SCALAR_NODE || cr_yaml_is_null(node))
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", expect, got);
    if (scalar_trimmed(node, &s, &n))
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", expect, got);
    k = scan_decimal(s, n);
    if (k == 0) {
        if (nonfinite_word(s, n))
            return cr_yaml_fail(y, node, path, err, "expected a finite %s, got %s", finite_what,
                                got);
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", expect, got);
    }
    rc = to_double(s, k, v);
    if (rc == 1)
        return cr_yaml_fail(y, node, path, err, "expected a finite %s, got %s", finite_what, got);
    if (rc == 2)
        return cr_yaml_fail(y, node, path, err, "expected %s of at most %d characters, got %s",
                            expect, NUMBER_MAX, got);
    s += k;
    n -= k;
    while (n > 0 && is_blank(s[0])) {
        s++;
        n--;
    }
    for (k = 0; k < n; k++)
        if (!is_alpha(s[k]))
            return cr_yaml_fail(y, node, path, err, "expected %s, got %s", expect, got);
    *unit = s;
    *unit_len = n;
    return 0;
}

int cr_yaml_number(cr_yaml *y, yaml_node_t *node, const char *path, double *out, cr_err *err)
{
    char got[SHOW_MAX + 32];
    const char *unit;
    size_t unit_len;
    double v;
    if (number_and_unit(y, node, path, "a number", "number", &v, &unit, &unit_len, err))
        return -1;
    if (unit_len > 0) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err,
                            "expected a plain number without a unit, got %s", got);
    }
    *out = v;
    return 0;
}

int cr_yaml_infinity_sign(const yaml_node_t *node)
{
    const char *s;
    size_t n;
    int sign = 1;
    if (cr_yaml_is_null(node) || scalar_trimmed(node, &s, &n))
        return 0;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) {
        sign = s[0] == '-' ? -1 : 1;
        s++;
        n--;
    }
    if (word_is(s, n, "inf") || word_is(s, n, "infinity") || word_is(s, n, ".inf"))
        return sign;
    return 0;
}

#define ANGLE_EXPECT "an angle like 90, \"90 deg\", \"1.57 rad\" or \"0.5 pi\""

int cr_yaml_angle(cr_yaml *y, yaml_node_t *node, const char *path, double *out_rad,
                  cr_err *err)
{
    char got[SHOW_MAX + 32], u[SHOW_MAX + 8];
    const char *unit;
    size_t unit_len;
    double v, rad;
    if (number_and_unit(y, node, path, ANGLE_EXPECT, "angle", &v, &unit, &unit_len, err))
        return -1;
    if (unit_len == 0 || word_is(unit, unit_len, "deg"))
        rad = v / 180.0 * CR_PI;
    else if (word_is(unit, unit_len, "rad"))
        rad = v;
    else if (word_is(unit, unit_len, "pi"))
        rad = v * CR_PI;
    else {
        cr_yaml_describe(node, got, sizeof got);
        quote_text(unit, unit_len, '\'', u, sizeof u);
        return cr_yaml_fail(y, node, path, err,
                            "unknown angle unit %s (expected deg, rad or pi), got %s", u, got);
    }
    if (!isfinite(rad)) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err, "expected a finite angle, got %s", got);
    }
    *out_rad = rad;
    return 0;
}

int cr_yaml_int(cr_yaml *y, yaml_node_t *node, const char *path, long lo, long hi,
                const char *what, long *out, cr_err *err)
{
    char got[SHOW_MAX + 32], deflt[80];
    const char *s;
    size_t n, i = 0;
    long v = 0;
    int neg = 0;

    if (!what) {
        snprintf(deflt, sizeof deflt, "an integer from %ld to %ld", lo, hi);
        what = deflt;
    }
    cr_yaml_describe(node, got, sizeof got);
    if (cr_yaml_is_null(node) || scalar_trimmed(node, &s, &n))
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
    if (i < n && (s[i] == '+' || s[i] == '-'))
        neg = s[i++] == '-';
    if (i == n)
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
    for (; i < n; i++) {
        int d;
        if (!is_digit(s[i]))
            return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
        d = s[i] - '0';
        /* accumulate negatively: LONG_MIN has no positive counterpart */
        if (v < (LONG_MIN + d) / 10)
            return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
        v = v * 10 - d;
    }
    if (!neg) {
        if (v == LONG_MIN)
            return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
        v = -v;
    }
    if (v < lo || v > hi)
        return cr_yaml_fail(y, node, path, err, "expected %s, got %s", what, got);
    *out = v;
    return 0;
}

int cr_yaml_bool(cr_yaml *y, yaml_node_t *node, const char *path, int *out, cr_err *err)
{
    char got[SHOW_MAX + 32];
    const char *s;
    size_t n;
    if (!cr_yaml_is_null(node) && !scalar_trimmed(node, &s, &n)) {
        if (word_is(s, n, "true") || word_is(s, n, "yes") || word_is(s, n, "on")) {
            *out = 1;
            return 0;
        }
        if (word_is(s, n, "false") || word_is(s, n, "no") || word_is(s, n, "off")) {
            *out = 0;
            return 0;
        }
    }
    cr_yaml_describe(node, got, sizeof got);
    return cr_yaml_fail(y, node, path, err, "expected true or false (or yes/no, on/off), got %s",
                        got);
}

int cr_yaml_string(cr_yaml *y, yaml_node_t *node, const char *path, const char **out,
                   cr_err *err)
{
    char got[SHOW_MAX + 32];
    if (!node || node->type != YAML_SCALAR_NODE || node->data.scalar.length == 0 ||
        cr_yaml_is_null(node) ||
        memchr(node->data.scalar.value, '\0', node->data.scalar.length)) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err, "expected a non-empty text, got %s", got);
    }
    *out = scalar_text(node);
    return 0;
}
