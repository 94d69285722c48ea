/* curray io: a small checked layer over libyaml's document API, shared by the
 * scene (E.4) and system configuration (E.2) loaders.
 *
 * A file is loaded whole into a yaml_document_t (cr_yaml_load); the loaders
 * then walk its nodes with the getters below. Every getter checks the node's
 * type and content and, on failure, returns -1 with a message of the form
 *
 *   NAME:LINE:COL: KEY.PATH: expected WHAT, got "TEXT"
 *
 * where LINE and COL are 1-based positions from libyaml's marks and
 * KEY.PATH is the dotted key path of the offending value ("observer.theta",
 * "sky_color[1]", "gpus.0.enabled"). Nothing is printed.
 *
 * Scalars are read as plain text whatever their quoting or tag: "90" and 90
 * are the same number. A node may come through an alias (libyaml resolves
 * aliases to the same node), so nothing here recurses on unknown shapes.
 */
#ifndef CR_IO_YAMLUTIL_H
#define CR_IO_YAMLUTIL_H

#include <stddef.h>
#include <yaml.h>

#include "../base/error.h"

/* Size of a key path buffer; longer paths are truncated in messages only. */
#define CR_YAML_PATH 160

/* A loaded document and the name used in its messages. */
typedef struct cr_yaml {
    yaml_document_t doc;
    int loaded;       /* doc holds a document to delete */
    const char *name; /* borrowed; the file name for messages */
} cr_yaml;

/* Parse exactly one YAML document from text[0..len) (no NUL needed). A text
 * with no document at all (empty, only comments) loads fine with no root
 * node. More than one document is an error. On failure returns -1 with
 * "NAME:LINE:COL: YAML syntax error: ..." and leaves nothing to free. */
int cr_yaml_load(cr_yaml *y, const char *text, size_t len, const char *name, cr_err *err);

/* Release the document (safe on a zeroed or freed cr_yaml). */
void cr_yaml_free(cr_yaml *y);

/* The document's root node, NULL when it has none. */
yaml_node_t *cr_yaml_root(cr_yaml *y);

/* Read a whole file into a malloc'ed, NUL-terminated buffer. Refuses files
 * larger than max_bytes. Errors name the file and the cause (strerror). */
int cr_yaml_read_file(const char *path, size_t max_bytes, char **text, size_t *len,
                      cr_err *err);

/* Set err to "NAME:LINE:COL: PATH: <fmt...>" at the node's start (PATH and
 * its colon are left out when path is NULL or empty). Returns -1. */
int cr_yaml_fail(const cr_yaml *y, const yaml_node_t *node, const char *path, cr_err *err,
                 const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Same at an explicit libyaml mark (0-based in the mark, printed 1-based). */
int cr_yaml_fail_at(const cr_yaml *y, yaml_mark_t mark, const char *path, cr_err *err,
                    const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Describe a node for the "got ..." part of a message: a scalar as its text
 * in double quotes (escaped, shortened), an empty plain scalar as "nothing",
 * "a mapping", "a list of N items". Always NUL-terminates buf (n >= 1). */
void cr_yaml_describe(const yaml_node_t *node, char *buf, size_t n);

/* Key paths: out = "parent.key" (or "key" at the top), "parent[i]". */
void cr_yaml_path_key(char *out, size_t n, const char *parent, const char *key);
void cr_yaml_path_index(char *out, size_t n, const char *parent, int i);

/* 1 for a scalar that means "no value": empty plain, ~, null, Null, NULL. */
int cr_yaml_is_null(const yaml_node_t *node);

/* 1 when node is a scalar whose text is exactly s (no NUL bytes inside). */
int cr_yaml_scalar_is(const yaml_node_t *node, const char *s);

/* One allowed key of a mapping, for cr_yaml_fields. */
typedef struct cr_yaml_field {
    const char *key; /* in: the key */
    int required;    /* in: report "missing required key" when absent */
    int repeatable;  /* in: may appear more than once (else a duplicate is an error) */
    yaml_node_t *key_node; /* out: key node of the first occurrence, or NULL */
    yaml_node_t *value;    /* out: its value node, or NULL when absent */
    int count;             /* out: occurrences */
} cr_yaml_field;

/* Check that map is a mapping (a null value counts as an empty one) whose
 * keys are all scalars among fields[0..n-1]: unknown keys ("unknown key
 * 'colour' in accretion (expected one of: ...)"), non-scalar keys, duplicates
 * of non-repeatable keys and missing required keys are errors. path names the
 * mapping ("" or NULL for the top level); where, if not NULL, is the node
 * that introduced it (its key), used to place "missing required key". */
int cr_yaml_fields(cr_yaml *y, yaml_node_t *map, const char *path, const yaml_node_t *where,
                   cr_yaml_field *fields, int n, cr_err *err);

/* Require node to be a mapping (or null: *n_pairs = 0); gives its pairs. */
int cr_yaml_mapping(cr_yaml *y, yaml_node_t *node, const char *path, yaml_node_pair_t **pairs,
                    int *n_pairs, cr_err *err);

/* Require node to be a list of exactly n items (n >= 0), or of any length
 * with n < 0 (then *count is set; a null value is an empty list). items, if
 * not NULL, receives the n item nodes. what describes the expected list in
 * messages ("a colour [R, G, B]"); NULL gives "a list of N items". */
int cr_yaml_list(cr_yaml *y, yaml_node_t *node, const char *path, int n, const char *what,
                 yaml_node_t **items, int *count, cr_err *err);

/* The node at index idx of the document (from a pair or item), or NULL. */
yaml_node_t *cr_yaml_node(cr_yaml *y, int idx);

/* A finite plain number such as 30, -1.5, 0.5E-2 (no unit: "30 deg" is an
 * error here). nan, inf, .inf and overflowing values (1e999) are errors. */
int cr_yaml_number(cr_yaml *y, yaml_node_t *node, const char *path, double *out, cr_err *err);

/* An angle "90", "90 deg", "1.570796 rad" or "0.5 pi" (a bare number is in
 * degrees), returned in radians; finite. */
int cr_yaml_angle(cr_yaml *y, yaml_node_t *node, const char *path, double *out_rad,
                  cr_err *err);

/* Whether a scalar spells infinity: +1 for inf, infinity or .inf (any
 * letter case, optionally with '+'), -1 for the same with '-', 0 for anything
 * else (numbers, nan, other words, non-scalars). For the few keys that take
 * inf as a value (observer.r, skymap.boundary); cr_yaml_number still rejects
 * it everywhere. */
int cr_yaml_infinity_sign(const yaml_node_t *node);

/* A decimal integer in [lo, hi]; "2.0" and "1e3" are not integers. what
 * describes it in messages ("a positive integer"); NULL gives "an integer
 * from LO to HI". */
int cr_yaml_int(cr_yaml *y, yaml_node_t *node, const char *path, long lo, long hi,
                const char *what, long *out, cr_err *err);

/* A boolean: true/false, yes/no, on/off in any letter case. */
int cr_yaml_bool(cr_yaml *y, yaml_node_t *node, const char *path, int *out, cr_err *err);

/* A non-empty scalar string without NUL bytes; *out points into the
 * document (valid until cr_yaml_free). */
int cr_yaml_string(cr_yaml *y, yaml_node_t *node, const char *path, const char **out,
                   cr_err *err);

#endif
