/* curray input: enumeration words (names.h). */
#include "names.h"

#include <string.h>

#include "../core/defs.h"

/* X(value, word) for every word of a kind, in value order. */
#define MOTION_WORDS(X)                                                                        \
    X(CR_MOTION_STATIC, "static")                                                              \
    X(CR_MOTION_ZAMO, "zamo")                                                                  \
    X(CR_MOTION_ORBIT, "orbit")                                                                \
    X(CR_MOTION_INFALL, "infall")
#define PROJECTION_WORDS(X)                                                                    \
    X(CR_PROJ_RECTILINEAR, "rectilinear")                                                      \
    X(CR_PROJ_FISHEYE, "fisheye")                                                              \
    X(CR_PROJ_EQUIRECT, "equirectangular")
#define INTEGRATOR_WORDS(X)                                                                    \
    X(CR_INTEG_MINO, "mino")                                                                   \
    X(CR_INTEG_RK4, "rk4")
#define DISC_MODEL_WORDS(X)                                                                    \
    X(CR_DISC_CHESSBOARD, "chessboard")                                                        \
    X(CR_DISC_KEPLERIAN, "keplerian")
#define INSIDE_ISCO_WORDS(X)                                                                   \
    X(0, "nothing")                                                                            \
    X(1, "plunging")
#define OUTCOME_WORDS(X)                                                                       \
    X(CR_OUT_NONE, "none")                                                                     \
    X(CR_OUT_HORIZON, "horizon")                                                               \
    X(CR_OUT_DISC, "disc")                                                                     \
    X(CR_OUT_SPHERE, "sphere")                                                                 \
    X(CR_OUT_SKY, "sky")                                                                       \
    X(CR_OUT_ERROR, "error")                                                                   \
    X(CR_OUT_LIMIT, "limit")                                                                   \
    X(CR_OUT_OUTSIDE, "outside")                                                               \
    X(CR_OUT_OTHER_SIDE, "other side")                                                         \
    X(CR_OUT_SINGULARITY, "singularity")

#define SIMD_WORDS(X)                                                                          \
    X(CR_SIMD_AUTO, "auto")                                                                    \
    X(CR_SIMD_OFF, "off")

#define WORD_AT(v, w) [v] = w,
#define LIST_ITEM(v, w) ", " w
#define ONE(v, w) +1

typedef struct kind_words {
    const char *const *words; /* words[v] for v in 0 .. n-1 */
    int n;
    const char *list; /* the words joined by ", " */
} kind_words;

static const char *const motion_words[] = {MOTION_WORDS(WORD_AT)};
static const char *const projection_words[] = {PROJECTION_WORDS(WORD_AT)};
static const char *const integrator_words[] = {INTEGRATOR_WORDS(WORD_AT)};
static const char *const disc_model_words[] = {DISC_MODEL_WORDS(WORD_AT)};
static const char *const inside_isco_words[] = {INSIDE_ISCO_WORDS(WORD_AT)};
static const char *const outcome_words[] = {OUTCOME_WORDS(WORD_AT)};
static const char *const simd_words[] = {SIMD_WORDS(WORD_AT)};

/* the lists skip the leading ", " of their first item */
static const kind_words kinds[CR_NAMES_COUNT_] = {
    [CR_NAMES_MOTION] = {motion_words, 0 MOTION_WORDS(ONE), &(MOTION_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_PROJECTION] = {projection_words, 0 PROJECTION_WORDS(ONE),
                             &(PROJECTION_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_INTEGRATOR] = {integrator_words, 0 INTEGRATOR_WORDS(ONE),
                             &(INTEGRATOR_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_DISC_MODEL] = {disc_model_words, 0 DISC_MODEL_WORDS(ONE),
                             &(DISC_MODEL_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_INSIDE_ISCO] = {inside_isco_words, 0 INSIDE_ISCO_WORDS(ONE),
                              &(INSIDE_ISCO_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_OUTCOME] = {outcome_words, 0 OUTCOME_WORDS(ONE), &(OUTCOME_WORDS(LIST_ITEM))[2]},
    [CR_NAMES_SIMD] = {simd_words, 0 SIMD_WORDS(ONE), &(SIMD_WORDS(LIST_ITEM))[2]},
};

/* every value of the enumerations that have a word for each has one */
_Static_assert(sizeof projection_words / sizeof *projection_words == CR_PROJ_COUNT_,
               "a projection without a word");
_Static_assert(sizeof integrator_words / sizeof *integrator_words == CR_INTEG_COUNT_,
               "an integrator without a word");
_Static_assert(sizeof outcome_words / sizeof *outcome_words == CR_OUT_COUNT_,
               "an outcome without a word");
_Static_assert(sizeof simd_words / sizeof *simd_words == CR_SIMD_COUNT_,
               "a cpu.simd mode without a word");
_Static_assert(sizeof motion_words / sizeof *motion_words == CR_MOTION_VELOCITY,
               "a motion without a word (only CR_MOTION_VELOCITY, the last, has none)");

static const kind_words *kind_of(cr_names kind)
{
    return (int)kind >= 0 && kind < CR_NAMES_COUNT_ ? &kinds[kind] : NULL;
}

const char *cr_name(cr_names kind, int v)
{
    const kind_words *k = kind_of(kind);
    if (!k || v < 0 || v >= k->n || !k->words[v])
        return "unknown";
    return k->words[v];
}

int cr_name_parse(cr_names kind, const char *text, size_t len)
{
    const kind_words *k = kind_of(kind);
    int i;
    if (!k || !text)
        return -1;
    for (i = 0; i < k->n; i++)
        if (k->words[i] && strlen(k->words[i]) == len && memcmp(k->words[i], text, len) == 0)
            return i;
    return -1;
}

int cr_names_count(cr_names kind)
{
    const kind_words *k = kind_of(kind);
    return k ? k->n : 0;
}

const char *cr_names_list(cr_names kind)
{
    const kind_words *k = kind_of(kind);
    return k ? k->list : "";
}

const char *cr_integrator_name(int integrator)
{
    return cr_name(CR_NAMES_INTEGRATOR, integrator);
}

const char *cr_integrator_names(void)
{
    return cr_names_list(CR_NAMES_INTEGRATOR);
}

static char ascii_lower(char c)
{
    return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c;
}

int cr_name_parse_folded(cr_names kind, const char *text, size_t len)
{
    char low[32];
    size_t i;
    if (!text)
        return -1;
    while (len > 0 && (text[0] == ' ' || text[0] == '\t')) {
        text++;
        len--;
    }
    while (len > 0 && (text[len - 1] == ' ' || text[len - 1] == '\t'))
        len--;
    if (len >= sizeof low)
        return -1;
    for (i = 0; i < len; i++)
        low[i] = ascii_lower(text[i]);
    return cr_name_parse(kind, low, len);
}

int cr_integrator_parse(const char *text, size_t len)
{
    return cr_name_parse_folded(CR_NAMES_INTEGRATOR, text, len);
}

const char *cr_outcome_name(int outcome)
{
    return cr_name(CR_NAMES_OUTCOME, outcome);
}
