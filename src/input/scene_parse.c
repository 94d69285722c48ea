/* curray input: reading scene files (appendix E.4) into a cr_scene.
 *
 * Loading walks the libyaml document with the checked getters of yamlutil.h;
 * every error names file:line:col and the key path. The physical checks of
 * ERRATA item 4 depend on the frame (values may be animated), so they are
 * made by the evaluation, cr_scene_frame (scene_eval.c).
 */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/png_io.h"
#include "../core/defs.h"
#include "../core/track.h"
#include "names.h"
#include "particle_spec.h"
#include "yamlutil.h"

/* Largest scene file read (bytes). */
#define SCENE_MAX_BYTES (16L << 20)
/* Largest sky image loaded (pixels). */
#define SKY_MAX_PIXELS (1LL << 28)

#define REQ(k) {k, 1, 0, NULL, NULL, 0}
#define OPT(k) {k, 0, 0, NULL, NULL, 0}
#define MANY(k) {k, 0, 1, NULL, NULL, 0}

/* A colour with components 0..255. */
#define RGB(r_, g_, b_) ((cr_rgb){.r = (r_), .g = (g_), .b = (b_)})

/* What a scalar value is: a plain number or an angle (stored in radians). */
typedef enum { V_NUMBER, V_ANGLE } value_kind;

static int get_value(cr_yaml *y, yaml_node_t *node, const char *path, value_kind kind,
                     double *out, cr_err *err)
{
    return kind == V_ANGLE ? cr_yaml_angle(y, node, path, out, err)
                           : cr_yaml_number(y, node, path, out, err);
}

/* A value that may be animated: a scalar, or [linear, start, end] whose start
 * and end follow the same unit rules. */
static int get_anim(cr_yaml *y, yaml_node_t *node, const char *path, value_kind kind,
                    cr_anim *out, cr_err *err)
{
    char sub[CR_YAML_PATH], got[96];
    const char *what = kind == V_ANGLE ? "an angle" : "a number";
    double v;

    if (node && node->type == YAML_SEQUENCE_NODE) {
        yaml_node_t *it[3], *first = NULL;
        if (node->data.sequence.items.top > node->data.sequence.items.start)
            first = cr_yaml_node(y, node->data.sequence.items.start[0]);
        if (first && first->type == YAML_SCALAR_NODE && first->data.scalar.length > 0) {
            char c = (char)first->data.scalar.value[0];
            if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) {
                if (!cr_yaml_scalar_is(first, "linear")) {
                    cr_yaml_describe(first, got, sizeof got);
                    cr_yaml_path_index(sub, sizeof sub, path, 0);
                    return cr_yaml_fail(y, first, sub, err,
                                        "unknown animation %s (expected [linear, start, end])",
                                        got);
                }
                if (cr_yaml_list(y, node, path, 3, "an animation [linear, start, end]", it, NULL,
                                 err))
                    return -1;
                cr_yaml_path_index(sub, sizeof sub, path, 1);
                if (get_value(y, it[1], sub, kind, &out->a, err))
                    return -1;
                cr_yaml_path_index(sub, sizeof sub, path, 2);
                return get_value(y, it[2], sub, kind, &out->b, err);
            }
        }
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err,
                            "expected %s or an animation [linear, start, end], got %s", what, got);
    }
    if (get_value(y, node, path, kind, &v, err))
        return -1;
    out->a = out->b = v;
    return 0;
}

/* An optional or required animated field of section path: sets the default
 * dflt when it is absent. */
/* Refuse the keys f[first] .. f[last] (in that order, either direction)
 * that are present, naming the first one found: they do not apply here, and
 * why says so. Returns -1 with err set, or 0 when none is present. */
static int refuse_keys(cr_yaml *y, const cr_yaml_field *f, int first, int last, const char *path,
                       const char *why, cr_err *err)
{
    int step = first <= last ? 1 : -1, i;
    for (i = first;; i += step) {
        if (f[i].value) {
            char sub[CR_YAML_PATH];
            cr_yaml_path_key(sub, sizeof sub, path, f[i].key);
            return cr_yaml_fail(y, f[i].key_node, sub, err, "%s", why);
        }
        if (i == last)
            return 0;
    }
}

static int field_anim(cr_yaml *y, const cr_yaml_field *f, const char *path, value_kind kind,
                      double dflt, cr_anim *out, cr_err *err)
{
    char sub[CR_YAML_PATH];
    if (!f->value) {
        out->a = out->b = dflt;
        return 0;
    }
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    return get_anim(y, f->value, sub, kind, out, err);
}

static int get_rgb(cr_yaml *y, yaml_node_t *node, const char *path, cr_rgb *out, cr_err *err)
{
    yaml_node_t *it[3];
    char sub[CR_YAML_PATH];
    long v[3];
    int i;
    if (cr_yaml_list(y, node, path, 3, "a colour [R, G, B]", it, NULL, err))
        return -1;
    for (i = 0; i < 3; i++) {
        cr_yaml_path_index(sub, sizeof sub, path, i);
        if (cr_yaml_int(y, it[i], sub, 0, 255, "a colour component, an integer from 0 to 255",
                        &v[i], err))
            return -1;
    }
    out->r = (uint8_t)v[0];
    out->g = (uint8_t)v[1];
    out->b = (uint8_t)v[2];
    return 0;
}

static int field_rgb(cr_yaml *y, const cr_yaml_field *f, const char *path, cr_rgb dflt,
                     cr_rgb *out, cr_err *err)
{
    char sub[CR_YAML_PATH];
    if (!f->value) {
        *out = dflt;
        return 0;
    }
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    return get_rgb(y, f->value, sub, out, err);
}

/* resolution: [n1, n2], both positive integers. what names the pair. */
static int field_resolution(cr_yaml *y, const cr_yaml_field *f, const char *path,
                            const char *what, int *n1, int *n2, cr_err *err)
{
    yaml_node_t *it[2];
    char sub[CR_YAML_PATH], sub2[CR_YAML_PATH];
    long v[2];
    int i;
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    if (cr_yaml_list(y, f->value, sub, 2, what, it, NULL, err))
        return -1;
    for (i = 0; i < 2; i++) {
        cr_yaml_path_index(sub2, sizeof sub2, sub, i);
        if (cr_yaml_int(y, it[i], sub2, 1, 2147483647L, "a positive integer", &v[i], err))
            return -1;
    }
    *n1 = (int)v[0];
    *n2 = (int)v[1];
    return 0;
}

/* ---- sections ------------------------------------------------------------- */

static int parse_metric(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_scene *s,
                        cr_err *err)
{
    cr_yaml_field f[] = {REQ("m"), REQ("a"), REQ("q")};
    if (cr_yaml_fields(y, map, "metric", key, f, 3, err))
        return -1;
    if (field_anim(y, &f[0], "metric", V_NUMBER, 0.0, &s->m, err) ||
        field_anim(y, &f[1], "metric", V_NUMBER, 0.0, &s->a, err) ||
        field_anim(y, &f[2], "metric", V_NUMBER, 0.0, &s->q, err))
        return -1;
    return 0;
}

/* A key that takes inf as a plain value (observer.r, skymap.boundary):
 * -1 with a message for -inf and for inf inside an animation, else 0 with
 * *is_inf set when the value is inf. what says what inf means there. */
static int get_inf(cr_yaml *y, yaml_node_t *node, const char *path, const char *what,
                   int *is_inf, cr_err *err)
{
    char sub[CR_YAML_PATH], got[96];
    int sign = cr_yaml_infinity_sign(node);
    *is_inf = 0;
    if (sign < 0) {
        cr_yaml_describe(node, got, sizeof got);
        return cr_yaml_fail(y, node, path, err,
                            "expected a positive number or inf (%s), got %s", what, got);
    }
    if (sign > 0) {
        *is_inf = 1;
        return 0;
    }
    if (node && node->type == YAML_SEQUENCE_NODE) {
        int i, m = (int)(node->data.sequence.items.top - node->data.sequence.items.start);
        for (i = 1; i < m && i < 3; i++) {
            yaml_node_t *it = cr_yaml_node(y, node->data.sequence.items.start[i]);
            if (it && cr_yaml_infinity_sign(it) != 0) {
                cr_yaml_path_index(sub, sizeof sub, path, i);
                return cr_yaml_fail(y, it, sub, err,
                                    "inf (%s) cannot be animated: write it as a plain value, "
                                    "or animate between finite numbers",
                                    what);
            }
        }
    }
    return 0;
}

/* A word of kind (a string at path) into *out; what names the kind, and
 * expected, a printf format taking the list of words, says what is
 * expected. */
static int get_choice(cr_yaml *y, yaml_node_t *node, const char *path, const char *what,
                      cr_names kind, const char *expected, int *out, cr_err *err)
{
    const char *v;
    char got[96], want[256];
    int i;
    if (cr_yaml_string(y, node, path, &v, err))
        return -1;
    i = cr_name_parse(kind, v, strlen(v));
    if (i >= 0) {
        *out = i;
        return 0;
    }
    cr_yaml_describe(node, got, sizeof got);
    snprintf(want, sizeof want, expected, cr_names_list(kind));
    return cr_yaml_fail(y, node, path, err, "unknown %s %s (expected %s)", what, got, want);
}

/* observer.motion: static | zamo | orbit | infall, or [v_r, v_theta, v_phi]
 * (each a number or an animation [linear, start, end]). */
static int parse_motion(cr_yaml *y, yaml_node_t *node, cr_scene *s, cr_err *err)
{
    const char *path = "observer.motion";
    char what[256];
    if (node->type == YAML_SEQUENCE_NODE) {
        yaml_node_t *it[3];
        char sub[CR_YAML_PATH];
        int i;
        snprintf(what, sizeof what,
                 "a motion (%s) or a 3-velocity [v_r, v_theta, v_phi] measured by the ZAMO",
                 cr_names_list(CR_NAMES_MOTION));
        if (cr_yaml_list(y, node, path, 3, what, it, NULL, err))
            return -1;
        for (i = 0; i < 3; i++) {
            cr_yaml_path_index(sub, sizeof sub, path, i);
            if (get_anim(y, it[i], sub, V_NUMBER, &s->obs_v[i], err))
                return -1;
        }
        s->obs_motion = CR_MOTION_VELOCITY;
        return 0;
    }
    return get_choice(y, node, path, "motion", CR_NAMES_MOTION,
                      "one of: %s, or a 3-velocity [v_r, v_theta, v_phi] measured by the ZAMO",
                      &s->obs_motion, err);
}

static int parse_observer(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_scene *s,
                          cr_err *err)
{
    enum { R, THETA, PHI, ROLL, PITCH, YAW, HFOV, VFOV, HEXT, VEXT, MOTION, PROJ, RETRO, TIME,
           DTIME, N };
    cr_yaml_field f[N] = {REQ("r"),       REQ("theta"),   REQ("phi"),        OPT("roll"),
                          OPT("pitch"),   OPT("yaw"),     OPT("hfov"),       OPT("vfov"),
                          OPT("hextent"), OPT("vextent"), OPT("motion"),     OPT("projection"),
                          OPT("retrograde"), OPT("t"),    OPT("dt")};
    const char *p = "observer";
    yaml_mark_t where;
    int inf, i;

    if (cr_yaml_fields(y, map, p, key, f, N, err) ||
        get_inf(y, f[R].value, "observer.r", "the observer at infinity", &inf, err))
        return -1;
    where = key ? key->start_mark : map->start_mark;
    if ((f[MOTION].value && parse_motion(y, f[MOTION].value, s, err)) ||
        (f[PROJ].value &&
         get_choice(y, f[PROJ].value, "observer.projection", "projection", CR_NAMES_PROJECTION,
                    "one of: %s", &s->obs_projection, err)) ||
        (f[RETRO].value && cr_yaml_bool(y, f[RETRO].value, "observer.retrograde",
                                        &s->obs_retrograde, err)))
        return -1;
    if (f[RETRO].value && s->obs_motion != CR_MOTION_ORBIT)
        return cr_yaml_fail(y, f[RETRO].key_node, "observer.retrograde", err,
                            "applies only to motion: orbit (the sense of the circular orbit)");
    if (inf && s->obs_motion != CR_MOTION_STATIC)
        return cr_yaml_fail(y, f[MOTION].value, "observer.motion", err,
                            "the observer at infinity (r: inf) is static; give observer.r a "
                            "finite value to move");
    if (inf && s->obs_projection != CR_PROJ_RECTILINEAR)
        return cr_yaml_fail(y, f[PROJ].value, "observer.projection", err,
                            "the observer at infinity (r: inf) sees a flat image plane "
                            "(rectilinear); give observer.r a finite value for a %s view",
                            cr_name(CR_NAMES_PROJECTION, s->obs_projection));
    /* which keys apply depends on r: inf (hextent, vextent) or finite (hfov, vfov) */
    if (inf) {
        for (i = HFOV; i <= VFOV; i++)
            if (f[i].value) {
                char sub[CR_YAML_PATH];
                cr_yaml_path_key(sub, sizeof sub, p, f[i].key);
                return cr_yaml_fail(y, f[i].key_node, sub, err,
                                    "an observer at infinity (r: inf) has no field of view; "
                                    "give the width of its image plane with hextent (a "
                                    "length, like r), and optionally its height with vextent");
            }
        if (!f[HEXT].value)
            return cr_yaml_fail_at(y, where, p, err,
                                   "missing required key 'hextent' (the observer at infinity, "
                                   "r: inf, needs the full width of its image plane, a length "
                                   "like r)");
    } else {
        if (refuse_keys(y, f, HEXT, VEXT, p,
                        "applies only to the observer at infinity (r: inf); an observer at a "
                        "finite r takes hfov (and vfov)",
                        err))
            return -1;
        if (s->obs_projection == CR_PROJ_EQUIRECT &&
            refuse_keys(y, f, HFOV, VFOV, p,
                        "an equirectangular view always shows the full sphere (360 x 180 "
                        "deg); leave out hfov and vfov (an image twice as wide as high has "
                        "square pixels)",
                        err))
            return -1;
        if (!f[HFOV].value && s->obs_projection != CR_PROJ_EQUIRECT)
            return cr_yaml_fail_at(y, where, p, err, "missing required key 'hfov'");
    }
    if (!inf && f[R].value && f[R].value->type == YAML_SEQUENCE_NODE &&
        f[R].value->data.sequence.items.top > f[R].value->data.sequence.items.start &&
        cr_yaml_scalar_is(cr_yaml_node(y, f[R].value->data.sequence.items.start[0]), "infall")) {
        /* the plunge: [infall, r_start, r_end] in proper time */
        yaml_node_t *it[3];
        if (cr_yaml_list(y, f[R].value, "observer.r", 3,
                         "a plunge [infall, r_start, r_end]", it, NULL, err) ||
            get_value(y, it[1], "observer.r[1]", V_NUMBER, &s->obs_r.a, err) ||
            get_value(y, it[2], "observer.r[2]", V_NUMBER, &s->obs_r.b, err))
            return -1;
        if (s->obs_motion != CR_MOTION_INFALL)
            return cr_yaml_fail(y, f[R].value, "observer.r", err,
                                "[infall, r_start, r_end] follows the free fall of motion: "
                                "infall; set observer.motion: infall");
        if (!(s->obs_r.a > s->obs_r.b && s->obs_r.b > 0.0 && isfinite(s->obs_r.a)))
            return cr_yaml_fail(y, f[R].value, "observer.r", err,
                                "[infall, %g, %g]: a plunge falls inward, from a finite r_start "
                                "down to r_end, with r_start > r_end > 0",
                                s->obs_r.a, s->obs_r.b);
        s->obs_r_infall = 1;
    } else if (!inf && field_anim(y, &f[R], p, V_NUMBER, 0.0, &s->obs_r, err)) {
        return -1;
    }
    if (
        field_anim(y, &f[THETA], p, V_ANGLE, 0.0, &s->obs_theta, err) ||
        field_anim(y, &f[PHI], p, V_ANGLE, 0.0, &s->obs_phi, err) ||
        field_anim(y, &f[ROLL], p, V_ANGLE, 0.0, &s->roll, err) ||
        field_anim(y, &f[PITCH], p, V_ANGLE, 0.0, &s->pitch, err) ||
        field_anim(y, &f[YAW], p, V_ANGLE, 0.0, &s->yaw, err) ||
        field_anim(y, &f[HFOV], p, V_ANGLE, 0.0, &s->hfov, err) ||
        field_anim(y, &f[VFOV], p, V_ANGLE, 0.0, &s->vfov, err) ||
        field_anim(y, &f[HEXT], p, V_NUMBER, 0.0, &s->hextent, err) ||
        field_anim(y, &f[VEXT], p, V_NUMBER, 0.0, &s->vextent, err) ||
        field_anim(y, &f[TIME], p, V_NUMBER, 0.0, &s->obs_t, err) ||
        (f[DTIME].value && cr_yaml_number(y, f[DTIME].value, "observer.dt", &s->obs_dt, err)))
        return -1;
    if (inf) {
        s->obs_at_infinity = 1;
        s->obs_r.a = s->obs_r.b = INFINITY;
        for (i = PITCH; i <= YAW; i++) {
            const cr_anim *v = i == PITCH ? &s->pitch : &s->yaw;
            if (v->a != 0.0 || v->b != 0.0) {
                char sub[CR_YAML_PATH];
                cr_yaml_path_key(sub, sizeof sub, p, f[i].key);
                return cr_yaml_fail(y, f[i].value, sub, err,
                                    "must be 0: an observer at infinity (r: inf) always looks "
                                    "at the hole and can only roll");
            }
        }
    }
    s->has_vfov = f[VFOV].value != NULL;
    s->has_vextent = f[VEXT].value != NULL;
    return 0;
}

/* The optional number of field f of section path into *out when present:
 * finite and > 0, within [lo, hi], else an error naming the key that says
 * what it is and why. */
static int positive_number(cr_yaml *y, const cr_yaml_field *f, const char *path,
                           const char *what, const char *unit, double lo, double hi,
                           const char *why, double *out, cr_err *err)
{
    char sub[CR_YAML_PATH];
    if (!f->value)
        return 0;
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    if (cr_yaml_number(y, f->value, sub, out, err))
        return -1;
    if (!(*out > 0.0) || !isfinite(*out))
        return cr_yaml_fail(y, f->value, sub, err, "%s must be positive (%s), got %g", what,
                            unit, *out);
    if (!(*out >= lo && *out <= hi))
        return cr_yaml_fail(y, f->value, sub, err, "%s must lie between %g and %g %s (%s), got %g",
                            what, lo, hi, unit, why, *out);
    return 0;
}

/* Ranges of the Keplerian disc's brightness keys: the temperature scale
 * T_peak / F_max^(1/4) overflows above about 1e307 K, and the SI
 * computation from the mass and rate ((G M)^2, c^6 Mdot) leaves the range of
 * doubles outside about 1e-150 .. 1e150 of either. */
#define CR_KEPLER_MAX_TEMPERATURE 1e300
#define CR_KEPLER_SI_MIN 1e-100
#define CR_KEPLER_SI_MAX 1e100

/* The keys of accretion, indexed by accretion_key. The chessboard's come
 * first (COLOR1 .. YAW), the Keplerian disc's last (RETRO .. MDOT), so that
 * refuse_keys names the other model's keys by range. */
enum accretion_key {
    ACC_COLOR1, ACC_COLOR2, ACC_RESOLUTION, ACC_YAW, ACC_RADIUS, ACC_MODEL, ACC_ORDER,
    ACC_RETRO, ACC_TEMP, ACC_INSIDE, ACC_MASS, ACC_MDOT, ACC_EXPOSURE, ACC_N
};

/* radius: [inner, outer] from the two items it[] of the list at path sub. */
static int parse_radii(cr_yaml *y, yaml_node_t *const it[2], const char *sub, cr_scene *s,
                       cr_err *err)
{
    char sub2[CR_YAML_PATH];
    cr_yaml_path_index(sub2, sizeof sub2, sub, 0);
    if (get_anim(y, it[0], sub2, V_NUMBER, &s->disc_r_in, err))
        return -1;
    cr_yaml_path_index(sub2, sizeof sub2, sub, 1);
    if (get_anim(y, it[1], sub2, V_NUMBER, &s->disc_r_out, err))
        return -1;
    s->has_disc = 1;
    return 0;
}

/* The Keplerian disc's radius: a plain outer radius, [outer], an animated
 * outer radius [linear, start, end] (the inner radius then defaults to the
 * ISCO), or [inner, outer]. */
static int parse_keplerian_radius(cr_yaml *y, yaml_node_t *node, const char *p, cr_scene *s,
                                  cr_err *err)
{
    char sub[CR_YAML_PATH], sub2[CR_YAML_PATH];
    yaml_node_t *it[2], *first = NULL;
    int count = 0;
    cr_yaml_path_key(sub, sizeof sub, p, "radius");
    if (node->type != YAML_SEQUENCE_NODE) {
        s->disc_has_r_in = 0;
        s->disc_r_in.a = s->disc_r_in.b = 0.0;
        if (get_anim(y, node, sub, V_NUMBER, &s->disc_r_out, err))
            return -1;
        s->has_disc = 1;
        return 0;
    }
    if (cr_yaml_list(y, node, sub, -1, NULL, NULL, &count, err))
        return -1;
    if (count > 0)
        first = cr_yaml_node(y, node->data.sequence.items.start[0]);
    if (count == 1 || (count == 3 && cr_yaml_scalar_is(first, "linear"))) {
        s->disc_has_r_in = 0;
        s->disc_r_in.a = s->disc_r_in.b = 0.0;
        if (count == 1) {
            cr_yaml_path_index(sub2, sizeof sub2, sub, 0);
            if (get_anim(y, first, sub2, V_NUMBER, &s->disc_r_out, err))
                return -1;
        } else if (get_anim(y, node, sub, V_NUMBER, &s->disc_r_out, err))
            return -1;
        s->has_disc = 1;
        return 0;
    }
    if (cr_yaml_list(y, node, sub, 2,
                     "radii [inner, outer] or [outer] (each a number or [linear, start, "
                     "end]; the inner radius defaults to the ISCO)",
                     it, NULL, err))
        return -1;
    return parse_radii(y, it, sub, s, err);
}

/* The peak temperature, or the hole's mass with the accretion rate (the
 * two go together, and not with the temperature). */
static int parse_keplerian_luminosity(cr_yaml *y, const cr_yaml_field *f, const char *p,
                                      cr_scene *s, cr_err *err)
{
    char sub[CR_YAML_PATH];
    if (!f[ACC_MASS].value != !f[ACC_MDOT].value || (f[ACC_TEMP].value && f[ACC_MASS].value)) {
        int i = f[ACC_MASS].value ? ACC_MASS : ACC_MDOT;
        cr_yaml_path_key(sub, sizeof sub, p, f[i].key);
        return cr_yaml_fail(y, f[i].key_node, sub, err, "%s",
                            f[ACC_TEMP].value
                                ? "give either accretion.temperature (the peak temperature) "
                                  "or accretion.mass_msun with accretion.mdot_edd (the "
                                  "physical inputs), not both"
                                : "accretion.mass_msun and accretion.mdot_edd go together "
                                  "(the hole's mass in solar masses and the accretion rate "
                                  "in Eddington units); give both");
    }
    return positive_number(y, &f[ACC_TEMP], p, "the peak temperature", "kelvin", 0.0,
                           CR_KEPLER_MAX_TEMPERATURE, "the disc's temperature scale overflows "
                           "above that", &s->disc_temperature, err) ||
                   positive_number(y, &f[ACC_MASS], p, "the hole's mass", "solar masses",
                                   CR_KEPLER_SI_MIN, CR_KEPLER_SI_MAX, "the temperature is "
                                   "computed from it in SI units, in doubles",
                                   &s->disc_mass_msun, err) ||
                   positive_number(y, &f[ACC_MDOT], p, "the accretion rate", "Eddington units",
                                   CR_KEPLER_SI_MIN, CR_KEPLER_SI_MAX, "the temperature is "
                                   "computed from it in SI units, in doubles",
                                   &s->disc_mdot_edd, err)
               ? -1
               : 0;
}

/* exposure: auto, or a factor on the disc's light, > 0 (may be animated). */
static int parse_exposure(cr_yaml *y, const cr_yaml_field *f, const char *p, cr_scene *s,
                          cr_err *err)
{
    char sub[CR_YAML_PATH], got[96];
    if (!f->value)
        return 0;
    cr_yaml_path_key(sub, sizeof sub, p, f->key);
    if (cr_yaml_scalar_is(f->value, "auto")) {
        s->disc_exposure_auto = 1;
        return 0;
    }
    if (f->value->type == YAML_SCALAR_NODE && f->value->data.scalar.length > 0) {
        char c = (char)f->value->data.scalar.value[0];
        if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) {
            cr_yaml_describe(f->value, got, sizeof got);
            return cr_yaml_fail(y, f->value, sub, err,
                                "expected auto or a positive number (the factor on the disc's "
                                "light), got %s",
                                got);
        }
    }
    if (get_anim(y, f->value, sub, V_NUMBER, &s->disc_exposure, err))
        return -1;
    if (!(s->disc_exposure.a > 0.0 && s->disc_exposure.b > 0.0) ||
        !(s->disc_exposure.a <= 1e100 && s->disc_exposure.b <= 1e100))
        return cr_yaml_fail(y, f->value, sub, err,
                            "the exposure must lie above 0 and at most 1e+100 (a factor on the "
                            "disc's light; 1 is the default, 2 twice as bright), got %g",
                            s->disc_exposure.a > 0.0 && s->disc_exposure.a <= 1e100
                                ? s->disc_exposure.b
                                : s->disc_exposure.a);
    return 0;
}

/* model: keplerian: radius (required), retrograde, the temperature or the
 * physical inputs, inside_isco; the chessboard's keys are refused. */
static int parse_keplerian(cr_yaml *y, const cr_yaml_field *f, yaml_mark_t where, const char *p,
                           cr_scene *s, cr_err *err)
{
    char sub[CR_YAML_PATH];
    if (refuse_keys(y, f, ACC_COLOR1, ACC_YAW, p,
                    "applies only to model: chessboard (a keplerian disc is coloured by its "
                    "temperature)",
                    err))
        return -1;
    if (!f[ACC_RADIUS].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'radius'");
    if (f[ACC_RETRO].value) {
        cr_yaml_path_key(sub, sizeof sub, p, "retrograde");
        if (cr_yaml_bool(y, f[ACC_RETRO].value, sub, &s->disc_retrograde, err))
            return -1;
    }
    if (parse_keplerian_luminosity(y, f, p, s, err))
        return -1;
    if (parse_exposure(y, &f[ACC_EXPOSURE], p, s, err))
        return -1;
    if (f[ACC_INSIDE].value) {
        cr_yaml_path_key(sub, sizeof sub, p, "inside_isco");
        if (get_choice(y, f[ACC_INSIDE].value, sub, "value", CR_NAMES_INSIDE_ISCO, "one of: %s",
                       &s->disc_plunge, err))
            return -1;
    }
    return parse_keplerian_radius(y, f[ACC_RADIUS].value, p, s, err);
}

/* model: chessboard (the paper's): color1, resolution and radius [inner,
 * outer] required, color2 (default: the complement of color1, (E.4.2) with
 * ERRATA item 3) and yaw; the Keplerian disc's keys are refused. */
static int parse_chessboard(cr_yaml *y, const cr_yaml_field *f, yaml_mark_t where,
                            const char *p, cr_scene *s, cr_err *err)
{
    char sub[CR_YAML_PATH];
    yaml_node_t *it[2];
    cr_rgb c2;
    if (refuse_keys(y, f, ACC_EXPOSURE, ACC_RETRO, p, "applies only to model: keplerian", err))
        return -1;
    if (!f[ACC_COLOR1].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'color1'");
    if (!f[ACC_RESOLUTION].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'resolution'");
    if (!f[ACC_RADIUS].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'radius'");
    if (field_rgb(y, &f[ACC_COLOR1], p, s->disc_color1, &s->disc_color1, err))
        return -1;
    c2.r = (uint8_t)(255 - s->disc_color1.r);
    c2.g = (uint8_t)(255 - s->disc_color1.g);
    c2.b = (uint8_t)(255 - s->disc_color1.b);
    if (field_rgb(y, &f[ACC_COLOR2], p, c2, &s->disc_color2, err) ||
        field_resolution(y, &f[ACC_RESOLUTION], p, "a resolution [radial divisions, sectors]",
                         &s->disc_n_radial, &s->disc_n_sectors, err) ||
        field_anim(y, &f[ACC_YAW], p, V_ANGLE, 0.0, &s->disc_yaw, err))
        return -1;
    cr_yaml_path_key(sub, sizeof sub, p, "radius");
    if (cr_yaml_list(y, f[ACC_RADIUS].value, sub, 2,
                     "radii [inner, outer] (each a number or [linear, start, end])", it, NULL,
                     err))
        return -1;
    return parse_radii(y, it, sub, s, err);
}

/* accretion: {model: chessboard (default) | keplerian, ...}. The chessboard
 * takes color1, color2, resolution, yaw and radius [inner, outer] (the
 * paper's keys); the Keplerian disc takes radius [inner, outer] or [outer]
 * (or a plain outer radius; the inner radius then defaults to the ISCO),
 * retrograde (default false), inside_isco (nothing, the default, or
 * plunging), and either temperature (the peak temperature in K, default 1e4)
 * or mass_msun and mdot_edd (the hole's mass in solar masses and the
 * accretion rate in Eddington units). Either model takes order (the one
 * image order in which the disc is seen). Keys of the other model are
 * errors. */
static int parse_accretion(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_scene *s,
                           cr_err *err)
{
    cr_yaml_field f[ACC_N] = {OPT("color1"),     OPT("color2"),      OPT("resolution"),
                              OPT("yaw"),        OPT("radius"),      OPT("model"),
                              OPT("order"),      OPT("retrograde"), OPT("temperature"), OPT("inside_isco"),
                              OPT("mass_msun"),  OPT("mdot_edd"),    OPT("exposure")};
    const char *p = "accretion";
    char sub[CR_YAML_PATH];
    yaml_mark_t where;

    if (cr_yaml_fields(y, map, p, key, f, ACC_N, err))
        return -1;
    where = key ? key->start_mark : map->start_mark;
    s->disc_model = CR_DISC_CHESSBOARD;
    if (f[ACC_MODEL].value) {
        cr_yaml_path_key(sub, sizeof sub, p, "model");
        if (get_choice(y, f[ACC_MODEL].value, sub, "disc model", CR_NAMES_DISC_MODEL,
                       "one of: %s", &s->disc_model, err))
            return -1;
    }
    s->disc_order = -1;
    if (f[ACC_ORDER].value) {
        long v;
        cr_yaml_path_key(sub, sizeof sub, p, "order");
        if (cr_yaml_int(y, f[ACC_ORDER].value, sub, 0, CR_COUNT_MAX - 1,
                        "an image order (0 the direct image, 1 the first ring, ...)", &v, err))
            return -1;
        s->disc_order = (int)v;
    }
    s->disc_retrograde = 0;
    s->disc_temperature = 1e4;
    s->disc_has_r_in = 1;
    s->disc_plunge = 0;
    s->disc_mass_msun = s->disc_mdot_edd = 0.0;
    s->disc_exposure.a = s->disc_exposure.b = 1.0;
    s->disc_exposure_auto = 0;
    s->disc_exposure_found = 0.0;
    if (s->disc_model == CR_DISC_KEPLERIAN)
        return parse_keplerian(y, f, where, p, s, err);
    return parse_chessboard(y, f, where, p, s, err);
}

cr_spectrum_spec cr_spectrum_defaults(void)
{
    cr_spectrum_spec d;
    memset(&d, 0, sizeof d);
    d.line_e0 = 6.4;
    d.line_q = 3.0;
    d.line_bins = 200;
    d.line_lo = 0.1 * d.line_e0;
    d.line_hi = 1.5 * d.line_e0;
    d.f_col = 1.7;
    d.cont_bins = 100;
    return d;
}

/* An energy range [lo, hi] in keV at field f of path: two numbers,
 * 0 < lo < hi. */
static int spectrum_range(cr_yaml *y, const cr_yaml_field *f, const char *path, double *lo,
                          double *hi, cr_err *err)
{
    char sub[CR_YAML_PATH], sub2[CR_YAML_PATH];
    yaml_node_t *it[2];
    double v[2];
    if (!f->value)
        return 0;
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    if (cr_yaml_list(y, f->value, sub, 2, "an energy range [low, high] in keV", it, NULL, err))
        return -1;
    for (int i = 0; i < 2; i++) {
        cr_yaml_path_index(sub2, sizeof sub2, sub, i);
        if (cr_yaml_number(y, it[i], sub2, &v[i], err))
            return -1;
        if (!(v[i] > 0.0) || !isfinite(v[i]))
            return cr_yaml_fail(y, it[i], sub2, err,
                                "a photon energy must be positive (keV), got %g", v[i]);
    }
    if (!(v[0] < v[1]))
        return cr_yaml_fail(y, f->value, sub, err,
                            "the range [%g, %g] keV is empty: the low end must be below the high "
                            "end",
                            v[0], v[1]);
    *lo = v[0];
    *hi = v[1];
    return 0;
}

/* bins of field f of path: a positive integer up to 1e6. */
static int spectrum_bins(cr_yaml *y, const cr_yaml_field *f, const char *path, int *out,
                         cr_err *err)
{
    char sub[CR_YAML_PATH];
    long v;
    if (!f->value)
        return 0;
    cr_yaml_path_key(sub, sizeof sub, path, f->key);
    if (cr_yaml_int(y, f->value, sub, 1, 1000000L, "a number of energy bins from 1 to 1000000",
                    &v, err))
        return -1;
    *out = (int)v;
    return 0;
}

/* spectrum: {line: {energy_kev, emissivity_index, bins, range},
 * continuum: {f_col, bins, range}}, every key optional; only with a
 * Keplerian disc (parsed before). */
static int parse_spectrum(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_scene *s,
                          cr_err *err)
{
    enum { LINE, CONT, N };
    enum { L_E0, L_Q, L_BINS, L_RANGE, L_N };
    enum { C_FCOL, C_BINS, C_RANGE, C_N };
    cr_yaml_field f[N] = {OPT("line"), OPT("continuum")};
    cr_yaml_field lf[L_N] = {OPT("energy_kev"), OPT("emissivity_index"), OPT("bins"),
                             OPT("range")};
    cr_yaml_field cf[C_N] = {OPT("f_col"), OPT("bins"), OPT("range")};
    cr_spectrum_spec *sp = &s->spectrum;
    if (!s->has_disc || s->disc_model != CR_DISC_KEPLERIAN)
        return cr_yaml_fail(y, key, "spectrum", err,
                            "the spectrum is that of a Keplerian disc, and this scene has %s; "
                            "add accretion: {model: keplerian, ...} or remove spectrum",
                            s->has_disc ? "a chessboard disc" : "no disc");
    if (cr_yaml_fields(y, map, "spectrum", key, f, N, err))
        return -1;
    *sp = cr_spectrum_defaults();
    sp->given = 1;
    if (f[LINE].value) {
        const char *p = "spectrum.line";
        int range_given;
        if (cr_yaml_fields(y, f[LINE].value, p, f[LINE].key_node, lf, L_N, err) ||
            positive_number(y, &lf[L_E0], p, "the line's rest energy", "keV", 1e-30, 1e30,
                            "a photon energy", &sp->line_e0, err) ||
            spectrum_bins(y, &lf[L_BINS], p, &sp->line_bins, err))
            return -1;
        if (lf[L_Q].value) {
            char sub[CR_YAML_PATH];
            cr_yaml_path_key(sub, sizeof sub, p, "emissivity_index");
            if (cr_yaml_number(y, lf[L_Q].value, sub, &sp->line_q, err))
                return -1;
            if (!isfinite(sp->line_q) || fabs(sp->line_q) > 100.0)
                return cr_yaml_fail(y, lf[L_Q].value, sub, err,
                                    "the emissivity index q of r^-q must lie between -100 and "
                                    "100, got %g",
                                    sp->line_q);
        }
        range_given = lf[L_RANGE].value != NULL;
        if (spectrum_range(y, &lf[L_RANGE], p, &sp->line_lo, &sp->line_hi, err))
            return -1;
        if (!range_given) {
            sp->line_lo = 0.1 * sp->line_e0;
            sp->line_hi = 1.5 * sp->line_e0;
        }
    }
    if (f[CONT].value) {
        const char *p = "spectrum.continuum";
        if (cr_yaml_fields(y, f[CONT].value, p, f[CONT].key_node, cf, C_N, err) ||
            positive_number(y, &cf[C_FCOL], p, "the colour correction f_col", "T_col / T_eff",
                            1e-3, 1e3, "a colour correction", &sp->f_col, err) ||
            spectrum_bins(y, &cf[C_BINS], p, &sp->cont_bins, err) ||
            spectrum_range(y, &cf[C_RANGE], p, &sp->cont_lo, &sp->cont_hi, err))
            return -1;
    }
    return 0;
}

/* dir + name into a new string (dir may be empty). NULL when out of memory. */
static char *join_path(const char *dir, size_t dir_len, const char *name)
{
    size_t n = strlen(name);
    char *p = malloc(dir_len + n + 1);
    if (!p)
        return NULL;
    memcpy(p, dir, dir_len);
    memcpy(p + dir_len, name, n + 1);
    return p;
}

/* base: the scene file's folder with its trailing '/', "" for the current
 * folder. */
static int parse_skymap(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *base,
                        cr_scene *s, cr_err *err)
{
    enum { IMAGE, BOUNDARY, OTHER, N };
    cr_yaml_field f[N] = {REQ("image"), OPT("boundary"), OPT("other_side")};
    const char *p = "skymap", *image, *other = NULL;
    cr_err perr;
    int inf;

    if (cr_yaml_fields(y, map, p, key, f, N, err) ||
        cr_yaml_string(y, f[IMAGE].value, "skymap.image", &image, err) ||
        (f[OTHER].value &&
         cr_yaml_string(y, f[OTHER].value, "skymap.other_side", &other, err)) ||
        get_inf(y, f[BOUNDARY].value, "skymap.boundary", "the sky at infinity", &inf, err))
        return -1;
    /* omitted or inf: the sky at infinity */
    s->sky_at_infinity = inf || !f[BOUNDARY].value;
    if (!s->sky_at_infinity &&
        field_anim(y, &f[BOUNDARY], p, V_NUMBER, 0.0, &s->sky_boundary, err))
        return -1;
    s->sky_image = join_path(image[0] == '/' ? "" : base, image[0] == '/' ? 0 : strlen(base),
                             image);
    if (!s->sky_image)
        return cr_yaml_fail(y, f[IMAGE].value, "skymap.image", err, "out of memory");
    perr.msg[0] = '\0';
    if (cr_png_read(s->sky_image, SKY_MAX_PIXELS, &s->sky_rgb, &s->sky_width, &s->sky_height,
                    &perr)) {
        s->sky_rgb = NULL;
        return cr_yaml_fail(y, f[IMAGE].value, "skymap.image", err, "%s",
                            perr.msg[0] ? perr.msg : "cannot read the image");
    }
    s->has_sky = 1;
    if (other) {
        /* the other exterior's sky, stored right after ours (cr_sky, defs.h) */
        uint8_t *orgb = NULL, *both;
        size_t ours = (size_t)3 * (size_t)s->sky_width * (size_t)s->sky_height, theirs;
        s->sky_other_image = join_path(other[0] == '/' ? "" : base,
                                       other[0] == '/' ? 0 : strlen(base), other);
        if (!s->sky_other_image)
            return cr_yaml_fail(y, f[OTHER].value, "skymap.other_side", err, "out of memory");
        perr.msg[0] = '\0';
        if (cr_png_read(s->sky_other_image, SKY_MAX_PIXELS, &orgb, &s->sky_other_width,
                        &s->sky_other_height, &perr))
            return cr_yaml_fail(y, f[OTHER].value, "skymap.other_side", err, "%s",
                                perr.msg[0] ? perr.msg : "cannot read the image");
        theirs = (size_t)3 * (size_t)s->sky_other_width * (size_t)s->sky_other_height;
        both = realloc(s->sky_rgb, ours + theirs);
        if (!both) {
            free(orgb);
            s->sky_other_width = s->sky_other_height = 0;
            return cr_yaml_fail(y, f[OTHER].value, "skymap.other_side", err, "out of memory");
        }
        memcpy(both + ours, orgb, theirs);
        free(orgb);
        s->sky_rgb = both;
    }
    return 0;
}

/* sphere.motion and its keys (motion, retrograde, omega; r: isco) of a
 * sphere whose other fields are read: a moving sphere's place follows its
 * motion, so its r, theta and phi are plain values; an orbit lies in the
 * equator. */
static int parse_sphere_motion(cr_yaml *y, const cr_yaml_field *fm, const cr_yaml_field *fr,
                               const cr_yaml_field *fo, const cr_yaml_field *fpos,
                               const char *p, cr_scene_sphere *sp, cr_err *err)
{
    static const char *const words[4] = {"static", "orbit", "rotating", "particle"};
    char sub[CR_YAML_PATH], got[96];
    int i;
    sp->motion = CR_SPHERE_MOTION_STATIC;
    if (fm->value) {
        cr_yaml_path_key(sub, sizeof sub, p, "motion");
        for (i = 0; i < 4 && !cr_yaml_scalar_is(fm->value, words[i]); i++)
            ;
        if (i == 4) {
            cr_yaml_describe(fm->value, got, sizeof got);
            return cr_yaml_fail(y, fm->value, sub, err,
                                "unknown motion %s (expected static, orbit: the circular "
                                "equatorial orbit at its r, rotating: turning about the "
                                "axis at omega, or particle: along the worldline of "
                                "sphere.particle)",
                                got);
        }
        sp->motion = i;
    }
    if (fr->value) {
        cr_yaml_path_key(sub, sizeof sub, p, "retrograde");
        if (sp->motion != CR_SPHERE_MOTION_ORBIT)
            return cr_yaml_fail(y, fr->key_node, sub, err,
                                "applies only to motion: orbit (the sense of the circular orbit)");
        if (cr_yaml_bool(y, fr->value, sub, &sp->retrograde, err))
            return -1;
    }
    if (fo->value) {
        cr_yaml_path_key(sub, sizeof sub, p, "omega");
        if (sp->motion != CR_SPHERE_MOTION_ROTATING)
            return cr_yaml_fail(y, fo->key_node, sub, err,
                                "applies only to motion: rotating (its angular velocity "
                                "dphi/dt)");
        if (cr_yaml_number(y, fo->value, sub, &sp->omega, err)) /* finite */
            return -1;
    }
    if (sp->motion == CR_SPHERE_MOTION_STATIC || sp->motion == CR_SPHERE_MOTION_PARTICLE)
        return 0;
    for (i = 0; i < 3; i++) {
        const cr_anim *v = i == 0 ? &sp->r : (i == 1 ? &sp->theta : &sp->phi);
        if (v->a != v->b) {
            cr_yaml_path_key(sub, sizeof sub, p, fpos[i].key);
            return cr_yaml_fail(y, fpos[i].value, sub, err,
                                "a moving sphere's place follows its motion (phi is its phase "
                                "at t = 0): give a plain value, not an animation");
        }
    }
    if (sp->motion == CR_SPHERE_MOTION_ORBIT && fabs(sp->theta.a - 0.5 * CR_PI) > 1e-12) {
        cr_yaml_path_key(sub, sizeof sub, p, "theta");
        return cr_yaml_fail(y, fpos[1].value, sub, err,
                            "a circular orbit lies in the equator: theta must be 90 deg, got "
                            "%g deg",
                            sp->theta.a * 180.0 / CR_PI);
    }
    if (sp->motion == CR_SPHERE_MOTION_ORBIT)
        sp->theta.a = sp->theta.b = 0.5 * CR_PI;
    return 0;
}

static yaml_node_t *map_key(cr_yaml *y, yaml_node_t *map, const char *key);

/* The worldline table of particle sphere sp (its spec read, on metric mt
 * in the scene's units), appended to s->track in units of M. where: the
 * node for messages (the particle key), p the sphere's path. */
static int sphere_track(cr_yaml *y, yaml_node_t *where, const char *p, const cr_metric *mt,
                        cr_scene *s, cr_scene_sphere *sp, cr_err *err)
{
    const cr_particle_spec *ps = sp->particle;
    double m = mt->m, t_end, h, k = 1.0 / m;
    char sub[CR_YAML_PATH];
    cr_particle pa;
    cr_track_point *tab;
    int ended, n, i, j;
    cr_yaml_path_key(sub, sizeof sub, p, "particle.tau");
    if (!cr_particle_spec_start(ps, &pa) ||
        cr_track_span(&pa, ps->tau, ps->t0 + 0.5 * (CR_TRACK_MAX - 1) * m, &t_end, &ended))
        return cr_yaml_fail(y, where, sub, err,
                            "the worldline's integration failed before its end");
    n = cr_track_count(ps->t0 * k, t_end * k, &h);
    if (h > 0.5)
        return cr_yaml_fail(y, where, sub, err,
                            "the worldline spans more than t = %g M, more than its table "
                            "holds (%d samples at most 0.5 M apart): follow it for less "
                            "proper time",
                            (t_end - ps->t0) * k, CR_TRACK_MAX);
    tab = realloc(s->track, sizeof *tab * (size_t)(s->n_track + n));
    if (!tab)
        return cr_yaml_fail(y, where, sub, err, "out of memory for the worldline's table");
    s->track = tab;
    tab += s->n_track;
    if (!cr_particle_spec_start(ps, &pa) || cr_track_fill(&pa, t_end, n, tab))
        return cr_yaml_fail(y, where, sub, err,
                            "the worldline's integration failed before its end");
    sp->wl.reach_hi = sp->wl.z_hi = -INFINITY;
    sp->wl.reach_lo = sp->wl.z_lo = INFINITY;
    for (i = 0; i < n; i++) { /* into units of M: lengths and times / m, rates * m */
        double c2 = 0.0, rad = sp->radius.a * k, cn;
        for (j = 0; j < 3; j++) {
            tab[i].x[j] *= k;
            c2 += tab[i].x[j] * tab[i].x[j];
        }
        tab[i].w *= m;
        cn = sqrt(c2);
        sp->wl.reach_hi = fmax(sp->wl.reach_hi, cn + rad);
        sp->wl.reach_lo = fmin(sp->wl.reach_lo, cn - rad);
        sp->wl.z_hi = fmax(sp->wl.z_hi, tab[i].x[2] + rad);
        sp->wl.z_lo = fmin(sp->wl.z_lo, tab[i].x[2] - rad);
    }
    /* between samples the Hermite curve may bulge out a little: a margin of
     * the largest step along it */
    {
        double dmax = 0.0;
        for (i = 0; i + 1 < n; i++) {
            double d2 = 0.0;
            for (j = 0; j < 3; j++)
                d2 += (tab[i + 1].x[j] - tab[i].x[j]) * (tab[i + 1].x[j] - tab[i].x[j]);
            dmax = fmax(dmax, sqrt(d2));
        }
        sp->wl.reach_hi += dmax;
        sp->wl.reach_lo -= dmax;
        sp->wl.z_hi += dmax;
        sp->wl.z_lo -= dmax;
    }
    sp->wl.off = s->n_track;
    sp->wl.n = n;
    sp->wl.t0 = ps->t0 * k;
    sp->wl.h = h;
    sp->wl.ph0 = tab[0].ph;
    s->n_track += n;
    return 0;
}

/* sphere.particle of a motion: particle sphere (fpart; fm its motion, fpos
 * its r, theta, phi, which it must not have): the particle section read by
 * particle_spec's parser on the scene's metric (not animated), its start
 * set as the sphere's place, its worldline tabulated. Else particle is
 * refused. */
static int parse_sphere_particle(cr_yaml *y, const cr_yaml_field *fm,
                                 const cr_yaml_field *fpart, const cr_yaml_field *fpos,
                                 const char *p, cr_scene *s, cr_scene_sphere *sp, cr_err *err)
{
    char sub[CR_YAML_PATH];
    cr_particle_spec *ps;
    cr_metric mt;
    int i;
    cr_yaml_path_key(sub, sizeof sub, p, "particle");
    if (sp->motion != CR_SPHERE_MOTION_PARTICLE) {
        if (fpart->value)
            return cr_yaml_fail(y, fpart->key_node, sub, err,
                                "applies only to motion: particle (the initial data of its "
                                "worldline)");
        return 0;
    }
    if (!fpart->value)
        return cr_yaml_fail(y, fm->value, sub, err,
                            "motion: particle needs the particle's initial data: a particle "
                            "section with the keys of an orbit file's");
    for (i = 0; i < 3; i++)
        if (fpos[i].value) {
            char k[CR_YAML_PATH];
            cr_yaml_path_key(k, sizeof k, p, fpos[i].key);
            return cr_yaml_fail(y, fpos[i].key_node, k, err,
                                "a motion: particle sphere starts where its particle does: "
                                "give particle.%s instead",
                                fpos[i].key);
        }
    if (s->m.a != s->m.b || s->a.a != s->a.b || s->q.a != s->q.b)
        return cr_yaml_fail(y, fm->value, sub, err,
                            "motion: particle follows a worldline of one hole: the metric "
                            "must not be animated");
    mt.m = s->m.a;
    mt.a = s->a.a;
    mt.q = s->q.a;
    if (!(mt.m > 0.0) || mt.a * mt.a + mt.q * mt.q > mt.m * mt.m)
        return cr_yaml_fail(y, fm->value, sub, err,
                            "motion: particle needs a hole with a horizon (m > 0, a^2 + q^2 "
                            "<= m^2)");
    ps = calloc(1, sizeof *ps);
    if (!ps)
        return cr_yaml_fail(y, fpart->key_node, sub, err, "out of memory");
    sp->particle = ps;
    ps->mt = mt;
    if (cr_particle_spec_parse(y, fpart->key_node, fpart->value, sub, 1, ps, err))
        return -1;
    sp->r.a = sp->r.b = ps->r;
    sp->theta.a = sp->theta.b = ps->theta;
    sp->phi.a = sp->phi.b = ps->phi;
    if (sp->radius.a != sp->radius.b) {
        char k[CR_YAML_PATH];
        cr_yaml_path_key(k, sizeof k, p, "radius");
        return cr_yaml_fail(y, fpos[3].value, k, err,
                            "a motion: particle sphere keeps its size: give a plain value, "
                            "not an animation");
    }
    {
        yaml_node_t *tk = map_key(y, fpart->value, "tau");
        return sphere_track(y, tk ? tk : fpart->key_node, p, &mt, s, sp, err);
    }
}

static int parse_sphere(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *p,
                        cr_scene *s, cr_scene_sphere *sp, cr_err *err)
{
    enum {
        COLOR, RESOLUTION, R, THETA, PHI, ROLL, PITCH, YAW, RADIUS, MOTION, RETRO, OMEGA, PART, N
    };
    cr_yaml_field f[N] = {REQ("color"),  REQ("resolution"), REQ("r"),     REQ("theta"),
                          REQ("phi"),    OPT("roll"),       OPT("pitch"), OPT("yaw"),
                          REQ("radius"), OPT("motion"),     OPT("retrograde"), OPT("omega"),
                          OPT("particle")};
    cr_yaml_field pos[4];
    yaml_node_t *mk = map_key(y, map, "motion");
    int r_isco, i;
    memset(sp, 0, sizeof *sp);
    sp->line = (int)(key ? key->start_mark.line : map->start_mark.line) + 1;
    /* a particle sphere's place is its particle's start */
    if (mk && mk->type == YAML_SCALAR_NODE) {
        yaml_node_pair_t *pr;
        for (pr = map->data.mapping.pairs.start; pr < map->data.mapping.pairs.top; pr++)
            if (cr_yaml_node(y, pr->key) == mk &&
                cr_yaml_scalar_is(cr_yaml_node(y, pr->value), "particle"))
                f[R].required = f[THETA].required = f[PHI].required = 0;
    }
    if (cr_yaml_fields(y, map, p, key, f, N, err))
        return -1;
    r_isco = cr_yaml_scalar_is(f[R].value, "isco");
    if (r_isco && !(f[MOTION].value && cr_yaml_scalar_is(f[MOTION].value, "orbit"))) {
        char sub[CR_YAML_PATH];
        cr_yaml_path_key(sub, sizeof sub, p, "r");
        return cr_yaml_fail(y, f[R].value, sub, err, "r: isco goes with motion: orbit only");
    }
    sp->r_isco = r_isco;
    if (field_rgb(y, &f[COLOR], p, sp->color, &sp->color, err) ||
        field_resolution(y, &f[RESOLUTION], p, "a resolution [latitude lines, longitude lines]",
                         &sp->n_lat, &sp->n_lon, err) ||
        (!r_isco && field_anim(y, &f[R], p, V_NUMBER, 0.0, &sp->r, err)) ||
        field_anim(y, &f[THETA], p, V_ANGLE, 0.0, &sp->theta, err) ||
        field_anim(y, &f[PHI], p, V_ANGLE, 0.0, &sp->phi, err) ||
        field_anim(y, &f[ROLL], p, V_ANGLE, 0.0, &sp->roll, err) ||
        field_anim(y, &f[PITCH], p, V_ANGLE, 0.0, &sp->pitch, err) ||
        field_anim(y, &f[YAW], p, V_ANGLE, 0.0, &sp->yaw, err) ||
        field_anim(y, &f[RADIUS], p, V_NUMBER, 0.0, &sp->radius, err) ||
        parse_sphere_motion(y, &f[MOTION], &f[RETRO], &f[OMEGA], &f[R], p, sp, err))
        return -1;
    for (i = 0; i < 3; i++)
        pos[i] = f[R + i];
    pos[3] = f[RADIUS];
    return parse_sphere_particle(y, &f[MOTION], &f[PART], pos, p, s, sp, err);
}

/* The key node of key in mapping map, or NULL. */
static yaml_node_t *map_key(cr_yaml *y, yaml_node_t *map, const char *key)
{
    yaml_node_pair_t *pr;
    if (!map || map->type != YAML_MAPPING_NODE)
        return NULL;
    for (pr = map->data.mapping.pairs.start; pr < map->data.mapping.pairs.top; pr++) {
        yaml_node_t *k = cr_yaml_node(y, pr->key);
        if (k && cr_yaml_scalar_is(k, key))
            return k;
    }
    return NULL;
}

/* The checks between a scene's sections for moving spheres: observer.t and
 * observer.dt need one (time enters nothing else), and a moving sphere needs
 * a metric that is not animated (its motion is a worldline of one hole). */
static int check_moving(cr_yaml *y, yaml_node_t *metric, yaml_node_t *observer,
                        const cr_scene *s, cr_err *err)
{
    int i, moving = -1;
    for (i = 0; i < s->n_spheres && moving < 0; i++)
        if (s->spheres[i].motion != CR_SPHERE_MOTION_STATIC)
            moving = i;
    if (moving < 0) {
        const char *keys[2] = {"t", "dt"};
        for (i = 0; i < 2; i++) {
            yaml_node_t *k = map_key(y, observer, keys[i]);
            char sub[CR_YAML_PATH];
            if (!k)
                continue;
            cr_yaml_path_key(sub, sizeof sub, "observer", keys[i]);
            return cr_yaml_fail(y, k, sub, err,
                                "the observer's time needs a moving object: give a sphere a "
                                "motion (sphere.motion: orbit, rotating or particle)");
        }
        return 0;
    }
    if (s->m.a != s->m.b || s->a.a != s->a.b || s->q.a != s->q.b)
        return cr_yaml_fail(y, metric, "metric", err,
                            "sphere %d (line %d) moves: its motion needs one hole, so the "
                            "metric must not be animated",
                            moving, s->spheres[moving].line);
    return 0;
}

/* Room for one more sphere in s->spheres (*cap entries allocated). */
static int grow_spheres(cr_scene *s, int *cap)
{
    cr_scene_sphere *p;
    int ncap;
    if (s->n_spheres < *cap)
        return 0;
    if (*cap > (1 << 24))
        return -1;
    ncap = *cap ? 2 * *cap : 8;
    p = realloc(s->spheres, (size_t)ncap * sizeof *p);
    if (!p)
        return -1;
    s->spheres = p;
    *cap = ncap;
    return 0;
}

/* Every `sphere:` section and every item of a `spheres:` list, in file
 * order. */
static int parse_spheres(cr_yaml *y, yaml_node_t *root, cr_scene *s, cr_err *err)
{
    yaml_node_pair_t *pairs;
    int np, i, j, cap = 0;
    char p[CR_YAML_PATH];

    if (cr_yaml_mapping(y, root, NULL, &pairs, &np, err))
        return -1;
    for (i = 0; i < np; i++) {
        yaml_node_t *k = cr_yaml_node(y, pairs[i].key), *v = cr_yaml_node(y, pairs[i].value);
        if (!k || !v)
            return cr_yaml_fail(y, root, NULL, err, "damaged YAML document");
        if (cr_yaml_scalar_is(k, "sphere")) {
            if (grow_spheres(s, &cap))
                return cr_yaml_fail(y, k, "sphere", err, "out of memory for spheres");
            cr_yaml_path_index(p, sizeof p, "sphere", s->n_spheres);
            s->n_spheres++; /* counted first: cr_scene_free frees what it holds */
            if (parse_sphere(y, k, v, p, s, &s->spheres[s->n_spheres - 1], err))
                return -1;
        } else if (cr_yaml_scalar_is(k, "spheres")) {
            int count;
            if (cr_yaml_list(y, v, "spheres", -1, "a list of spheres", NULL, &count, err))
                return -1;
            for (j = 0; j < count; j++) {
                yaml_node_t *item = cr_yaml_node(y, v->data.sequence.items.start[j]);
                if (!item)
                    return cr_yaml_fail(y, v, "spheres", err, "damaged YAML document");
                if (grow_spheres(s, &cap))
                    return cr_yaml_fail(y, item, "spheres", err, "out of memory for spheres");
                cr_yaml_path_index(p, sizeof p, "spheres", j);
                s->n_spheres++;
                if (parse_sphere(y, NULL, item, p, s, &s->spheres[s->n_spheres - 1], err))
                    return -1;
            }
        }
    }
    return 0;
}

/* Parse text into s (zeroed by the caller); base as for parse_skymap. */
static int parse_scene(const char *text, size_t len, const char *name, const char *base,
                       cr_scene *s, cr_err *err)
{
    enum {
        METRIC, OBSERVER, ACCRETION, SKYMAP, SPHERE, SPHERES, SKY, HORIZON, ERRC, LIMITC, REDSKY,
        OTHERC, SPECTRUM, SINGC, N
    };
    cr_yaml_field f[N] = {REQ("metric"),    REQ("observer"),      OPT("accretion"),
                          OPT("skymap"),    MANY("sphere"),       OPT("spheres"),
                          OPT("sky_color"), OPT("horizon_color"), OPT("error_color"),
                          OPT("limit_color"), OPT("redshift_sky"), OPT("other_side_color"),
                          OPT("spectrum"),    OPT("singularity_color")};
    cr_yaml y;
    yaml_node_t *root;
    char got[96];

    if (cr_yaml_load(&y, text, len, name, err))
        return -1;
    root = cr_yaml_root(&y);
    if (!root || cr_yaml_is_null(root)) {
        cr_err_set(err, "%s: the scene file is empty (it needs at least metric and observer)",
                   y.name);
        goto fail;
    }
    if (root->type != YAML_MAPPING_NODE) {
        cr_yaml_describe(root, got, sizeof got);
        cr_yaml_fail(&y, root, NULL, err,
                     "a scene must be a mapping of keys (metric, observer, ...), got %s", got);
        goto fail;
    }
    if (cr_yaml_fields(&y, root, NULL, NULL, f, N, err))
        goto fail;
    if (parse_metric(&y, f[METRIC].key_node, f[METRIC].value, s, err) ||
        parse_observer(&y, f[OBSERVER].key_node, f[OBSERVER].value, s, err))
        goto fail;
    if (f[ACCRETION].value &&
        parse_accretion(&y, f[ACCRETION].key_node, f[ACCRETION].value, s, err))
        goto fail;
    s->spectrum = cr_spectrum_defaults();
    if (f[SPECTRUM].key_node &&
        parse_spectrum(&y, f[SPECTRUM].key_node, f[SPECTRUM].value, s, err))
        goto fail;
    if (parse_spheres(&y, root, s, err) ||
        check_moving(&y, f[METRIC].key_node, f[OBSERVER].value, s, err))
        goto fail;
    if (field_rgb(&y, &f[SKY], NULL, RGB(0, 0, 0), &s->sky_color, err) ||
        /* the horizon: the paper's red, but black next to a Keplerian disc
         * (a realistic picture; the chessboard keeps the paper's colours) */
        field_rgb(&y, &f[HORIZON], NULL,
                  s->has_disc && s->disc_model == CR_DISC_KEPLERIAN ? RGB(0, 0, 0)
                                                                     : RGB(255, 0, 0),
                  &s->horizon_color, err) ||
        field_rgb(&y, &f[ERRC], NULL, RGB(0, 0, 255), &s->error_color, err) ||
        field_rgb(&y, &f[LIMITC], NULL, RGB(255, 255, 0), &s->limit_color, err) ||
        field_rgb(&y, &f[OTHERC], NULL, RGB(96, 0, 128), &s->other_side_color, err) ||
        field_rgb(&y, &f[SINGC], NULL, RGB(255, 255, 255), &s->singularity_color, err) ||
        (f[REDSKY].value &&
         cr_yaml_bool(&y, f[REDSKY].value, "redshift_sky", &s->redshift_sky, err)))
        goto fail;
    /* last: the image is the slow part */
    if (f[SKYMAP].value &&
        parse_skymap(&y, f[SKYMAP].key_node, f[SKYMAP].value, base, s, err))
        goto fail;
    cr_yaml_free(&y);
    return 0;
fail:
    cr_yaml_free(&y);
    return -1;
}

static char *dup_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *p = malloc(n);
    if (p)
        memcpy(p, s, n);
    return p;
}

/* Common part of both loaders. */
static int scene_load(const char *text, size_t len, const char *name, const char *base,
                      cr_scene *out, cr_err *err)
{
    cr_scene s;
    memset(&s, 0, sizeof s);
    memset(out, 0, sizeof *out);
    s.path = dup_string(name);
    if (!s.path) {
        cr_err_set(err, "%s: out of memory", name);
        goto fail;
    }
    if (parse_scene(text, len, name, base, &s, err))
        goto fail;
    *out = s;
    return 0;
fail:
    cr_scene_free(&s);
    return -1;
}

int cr_scene_load(const char *path, cr_scene *out, cr_err *err)
{
    char *text = NULL, *base = NULL;
    const char *slash;
    size_t len;
    int rc = -1;

    memset(out, 0, sizeof *out);
    if (!path || !path[0])
        return cr_err_set(err, "no scene file given");
    if (cr_yaml_read_file(path, (size_t)SCENE_MAX_BYTES, &text, &len, err))
        return -1;
    slash = strrchr(path, '/');
    base = malloc(slash ? (size_t)(slash - path) + 2 : 1);
    if (!base) {
        cr_err_set(err, "%s: out of memory", path);
        goto done;
    }
    if (slash) {
        memcpy(base, path, (size_t)(slash - path) + 1);
        base[slash - path + 1] = '\0';
    } else {
        base[0] = '\0';
    }
    rc = scene_load(text, len, path, base, out, err);
done:
    free(base);
    free(text);
    return rc;
}

int cr_scene_load_string(const char *text, size_t len, const char *name, cr_scene *out,
                         cr_err *err)
{
    return scene_load(text, len, name ? name : "(scene)", "", out, err);
}

void cr_scene_free(cr_scene *s)
{
    if (!s)
        return;
    free(s->path);
    free(s->sky_image);
    free(s->sky_other_image);
    free(s->sky_rgb);
    for (int i = 0; s->spheres && i < s->n_spheres; i++)
        free(s->spheres[i].particle);
    free(s->spheres);
    free(s->track);
    memset(s, 0, sizeof *s);
}
