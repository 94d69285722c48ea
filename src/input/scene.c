/* curray io: scene files (appendix E.4) and their evaluation per frame.
 *
 * Loading walks the libyaml document with the checked getters of yamlutil.h;
 * every error names file:line:col and the key path. The physical checks of
 * ERRATA item 4 depend on the frame (values may be animated), so they are
 * made by cr_scene_frame.
 */
#include "scene.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/trace.h"
#include "../base/png_io.h"
#include "names.h"
#include "sysconfig.h"
#include "yamlutil.h"

/* Largest scene file read (bytes). */
#define SCENE_MAX_BYTES (16L << 20)
/* Largest sky image loaded (pixels). */
#define SKY_MAX_PIXELS (1LL << 28)
/* Relative slack on a^2 + Q^2 <= M^2, so that the extremal case survives
 * rounding (0.6^2 + 0.8^2 is 1.0000000000000002 in doubles). */
#define EXTREMAL_TOL 1e-12
/* Slack (radians) on the observer's theta in [0, pi]. */
#define THETA_TOL 1e-9

#define REQ(k) {k, 1, 0, NULL, NULL, 0}
#define OPT(k) {k, 0, 0, NULL, NULL, 0}
#define MANY(k) {k, 0, 1, NULL, NULL, 0}

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
    enum { R, THETA, PHI, ROLL, PITCH, YAW, HFOV, VFOV, HEXT, VEXT, MOTION, PROJ, RETRO, N };
    cr_yaml_field f[N] = {REQ("r"),       REQ("theta"),   REQ("phi"),        OPT("roll"),
                          OPT("pitch"),   OPT("yaw"),     OPT("hfov"),       OPT("vfov"),
                          OPT("hextent"), OPT("vextent"), OPT("motion"),     OPT("projection"),
                          OPT("retrograde")};
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
    if ((!inf && field_anim(y, &f[R], p, V_NUMBER, 0.0, &s->obs_r, err)) ||
        field_anim(y, &f[THETA], p, V_ANGLE, 0.0, &s->obs_theta, err) ||
        field_anim(y, &f[PHI], p, V_ANGLE, 0.0, &s->obs_phi, err) ||
        field_anim(y, &f[ROLL], p, V_ANGLE, 0.0, &s->roll, err) ||
        field_anim(y, &f[PITCH], p, V_ANGLE, 0.0, &s->pitch, err) ||
        field_anim(y, &f[YAW], p, V_ANGLE, 0.0, &s->yaw, err) ||
        field_anim(y, &f[HFOV], p, V_ANGLE, 0.0, &s->hfov, err) ||
        field_anim(y, &f[VFOV], p, V_ANGLE, 0.0, &s->vfov, err) ||
        field_anim(y, &f[HEXT], p, V_NUMBER, 0.0, &s->hextent, err) ||
        field_anim(y, &f[VEXT], p, V_NUMBER, 0.0, &s->vextent, err))
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
 * finite and > 0, else an error naming the key that says what it is. */
static int positive_number(cr_yaml *y, const cr_yaml_field *f, const char *path,
                           const char *what, const char *unit, double *out, cr_err *err)
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
    return 0;
}

/* accretion: {model: chessboard (default) | keplerian, ...}. The chessboard
 * takes color1, color2, resolution, yaw and radius [inner, outer] (the
 * paper's keys); the Keplerian disc takes radius [inner, outer] or [outer]
 * (or a plain outer radius; the inner radius then defaults to the ISCO),
 * retrograde (default false), inside_isco (nothing, the default, or
 * plunging), and either temperature (the peak temperature in K, default 1e4)
 * or mass_msun and mdot_edd (the hole's mass in solar masses and the
 * accretion rate in Eddington units). Keys of the other model are errors. */
static int parse_accretion(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_scene *s,
                           cr_err *err)
{
    enum { COLOR1, COLOR2, RESOLUTION, YAW, RADIUS, MODEL, RETRO, TEMP, INSIDE, MASS, MDOT, N };
    cr_yaml_field f[N] = {OPT("color1"),      OPT("color2"),    OPT("resolution"),
                          OPT("yaw"),         OPT("radius"),    OPT("model"),
                          OPT("retrograde"),  OPT("temperature"), OPT("inside_isco"),
                          OPT("mass_msun"),   OPT("mdot_edd")};
    const char *p = "accretion";
    yaml_node_t *it[2];
    char sub[CR_YAML_PATH], sub2[CR_YAML_PATH];
    yaml_mark_t where;
    cr_rgb c2;
    int count = 0, kep = 0;

    if (cr_yaml_fields(y, map, p, key, f, N, err))
        return -1;
    where = key ? key->start_mark : map->start_mark;
    s->disc_model = CR_DISC_CHESSBOARD;
    if (f[MODEL].value) {
        cr_yaml_path_key(sub, sizeof sub, p, "model");
        if (get_choice(y, f[MODEL].value, sub, "disc model", CR_NAMES_DISC_MODEL, "one of: %s",
                       &s->disc_model, err))
            return -1;
    }
    kep = s->disc_model == CR_DISC_KEPLERIAN;
    s->disc_retrograde = 0;
    s->disc_temperature = 1e4;
    s->disc_has_r_in = 1;
    s->disc_plunge = 0;
    s->disc_mass_msun = s->disc_mdot_edd = 0.0;
    if (kep) {
        if (refuse_keys(y, f, COLOR1, YAW, p,
                        "applies only to model: chessboard (a keplerian disc is coloured by its "
                        "temperature)",
                        err))
            return -1;
        if (!f[RADIUS].value)
            return cr_yaml_fail_at(y, where, p, err, "missing required key 'radius'");
        if (f[RETRO].value) {
            cr_yaml_path_key(sub, sizeof sub, p, "retrograde");
            if (cr_yaml_bool(y, f[RETRO].value, sub, &s->disc_retrograde, err))
                return -1;
        }
        /* temperature or the physical inputs; mass_msun and mdot_edd together */
        if (!f[MASS].value != !f[MDOT].value || (f[TEMP].value && f[MASS].value)) {
            int i = f[MASS].value ? MASS : MDOT;
            cr_yaml_path_key(sub, sizeof sub, p, f[i].key);
            return cr_yaml_fail(y, f[i].key_node, sub, err, "%s",
                                f[TEMP].value
                                    ? "give either accretion.temperature (the peak temperature) "
                                      "or accretion.mass_msun with accretion.mdot_edd (the "
                                      "physical inputs), not both"
                                    : "accretion.mass_msun and accretion.mdot_edd go together "
                                      "(the hole's mass in solar masses and the accretion rate "
                                      "in Eddington units); give both");
        }
        if (positive_number(y, &f[TEMP], p, "the peak temperature", "kelvin",
                            &s->disc_temperature, err) ||
            positive_number(y, &f[MASS], p, "the hole's mass", "solar masses",
                            &s->disc_mass_msun, err) ||
            positive_number(y, &f[MDOT], p, "the accretion rate", "Eddington units",
                            &s->disc_mdot_edd, err))
            return -1;
        if (f[INSIDE].value) {
            cr_yaml_path_key(sub, sizeof sub, p, "inside_isco");
            if (get_choice(y, f[INSIDE].value, sub, "value", CR_NAMES_INSIDE_ISCO, "one of: %s",
                           &s->disc_plunge, err))
                return -1;
        }
        cr_yaml_path_key(sub, sizeof sub, p, "radius");
        if (f[RADIUS].value->type != YAML_SEQUENCE_NODE) {
            s->disc_has_r_in = 0;
            s->disc_r_in.a = s->disc_r_in.b = 0.0;
            if (get_anim(y, f[RADIUS].value, sub, V_NUMBER, &s->disc_r_out, err))
                return -1;
            s->has_disc = 1;
            return 0;
        }
        if (cr_yaml_list(y, f[RADIUS].value, sub, -1, NULL, NULL, &count, err))
            return -1;
        if (count == 1 || (count == 3 && cr_yaml_scalar_is(cr_yaml_node(y, f[RADIUS].value->data.sequence.items.start[0]), "linear"))) {
            s->disc_has_r_in = 0;
            s->disc_r_in.a = s->disc_r_in.b = 0.0;
            if (count == 1) {
                cr_yaml_path_index(sub2, sizeof sub2, sub, 0);
                if (get_anim(y, cr_yaml_node(y, f[RADIUS].value->data.sequence.items.start[0]),
                             sub2, V_NUMBER, &s->disc_r_out, err))
                    return -1;
            } else if (get_anim(y, f[RADIUS].value, sub, V_NUMBER, &s->disc_r_out, err))
                return -1;
            s->has_disc = 1;
            return 0;
        }
        if (cr_yaml_list(y, f[RADIUS].value, sub, 2,
                         "radii [inner, outer] or [outer] (each a number or [linear, start, "
                         "end]; the inner radius defaults to the ISCO)",
                         it, NULL, err))
            return -1;
        goto radii;
    }
    if (refuse_keys(y, f, MDOT, RETRO, p, "applies only to model: keplerian", err))
        return -1;
    if (!f[COLOR1].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'color1'");
    if (!f[RESOLUTION].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'resolution'");
    if (!f[RADIUS].value)
        return cr_yaml_fail_at(y, where, p, err, "missing required key 'radius'");
    if (field_rgb(y, &f[COLOR1], p, s->disc_color1, &s->disc_color1, err))
        return -1;
    /* (E.4.2) with ERRATA item 3: the complement of color1 */
    c2.r = (uint8_t)(255 - s->disc_color1.r);
    c2.g = (uint8_t)(255 - s->disc_color1.g);
    c2.b = (uint8_t)(255 - s->disc_color1.b);
    if (field_rgb(y, &f[COLOR2], p, c2, &s->disc_color2, err) ||
        field_resolution(y, &f[RESOLUTION], p, "a resolution [radial divisions, sectors]",
                         &s->disc_n_radial, &s->disc_n_sectors, err) ||
        field_anim(y, &f[YAW], p, V_ANGLE, 0.0, &s->disc_yaw, err))
        return -1;
    cr_yaml_path_key(sub, sizeof sub, p, "radius");
    if (cr_yaml_list(y, f[RADIUS].value, sub, 2,
                     "radii [inner, outer] (each a number or [linear, start, end])", it, NULL,
                     err))
        return -1;
radii:
    cr_yaml_path_index(sub2, sizeof sub2, sub, 0);
    if (get_anim(y, it[0], sub2, V_NUMBER, &s->disc_r_in, err))
        return -1;
    cr_yaml_path_index(sub2, sizeof sub2, sub, 1);
    if (get_anim(y, it[1], sub2, V_NUMBER, &s->disc_r_out, err))
        return -1;
    s->has_disc = 1;
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
    enum { IMAGE, BOUNDARY, N };
    cr_yaml_field f[N] = {REQ("image"), OPT("boundary")};
    const char *p = "skymap", *image;
    cr_err perr;
    int inf;

    if (cr_yaml_fields(y, map, p, key, f, N, err) ||
        cr_yaml_string(y, f[IMAGE].value, "skymap.image", &image, err) ||
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
    return 0;
}

static int parse_sphere(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *p,
                        cr_scene_sphere *sp, cr_err *err)
{
    enum { COLOR, RESOLUTION, R, THETA, PHI, ROLL, PITCH, YAW, RADIUS, N };
    cr_yaml_field f[N] = {REQ("color"), REQ("resolution"), REQ("r"),     REQ("theta"),
                          REQ("phi"),   OPT("roll"),       OPT("pitch"), OPT("yaw"),
                          REQ("radius")};
    memset(sp, 0, sizeof *sp);
    sp->line = (int)(key ? key->start_mark.line : map->start_mark.line) + 1;
    if (cr_yaml_fields(y, map, p, key, f, N, err))
        return -1;
    if (field_rgb(y, &f[COLOR], p, sp->color, &sp->color, err) ||
        field_resolution(y, &f[RESOLUTION], p, "a resolution [latitude lines, longitude lines]",
                         &sp->n_lat, &sp->n_lon, err) ||
        field_anim(y, &f[R], p, V_NUMBER, 0.0, &sp->r, err) ||
        field_anim(y, &f[THETA], p, V_ANGLE, 0.0, &sp->theta, err) ||
        field_anim(y, &f[PHI], p, V_ANGLE, 0.0, &sp->phi, err) ||
        field_anim(y, &f[ROLL], p, V_ANGLE, 0.0, &sp->roll, err) ||
        field_anim(y, &f[PITCH], p, V_ANGLE, 0.0, &sp->pitch, err) ||
        field_anim(y, &f[YAW], p, V_ANGLE, 0.0, &sp->yaw, err) ||
        field_anim(y, &f[RADIUS], p, V_NUMBER, 0.0, &sp->radius, err))
        return -1;
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
            if (parse_sphere(y, k, v, p, &s->spheres[s->n_spheres], err))
                return -1;
            s->n_spheres++;
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
                if (parse_sphere(y, NULL, item, p, &s->spheres[s->n_spheres], err))
                    return -1;
                s->n_spheres++;
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
        METRIC, OBSERVER, ACCRETION, SKYMAP, SPHERE, SPHERES, SKY, HORIZON, ERRC, LIMITC, REDSKY, N
    };
    cr_yaml_field f[N] = {REQ("metric"),    REQ("observer"),      OPT("accretion"),
                          OPT("skymap"),    MANY("sphere"),       OPT("spheres"),
                          OPT("sky_color"), OPT("horizon_color"), OPT("error_color"),
                          OPT("limit_color"), OPT("redshift_sky")};
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
    if (parse_spheres(&y, root, s, err))
        goto fail;
    if (field_rgb(&y, &f[SKY], NULL, cr_rgb_make(0, 0, 0), &s->sky_color, err) ||
        field_rgb(&y, &f[HORIZON], NULL, cr_rgb_make(255, 0, 0), &s->horizon_color, err) ||
        field_rgb(&y, &f[ERRC], NULL, cr_rgb_make(0, 0, 255), &s->error_color, err) ||
        field_rgb(&y, &f[LIMITC], NULL, cr_rgb_make(255, 255, 0), &s->limit_color, err) ||
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
    free(s->sky_rgb);
    free(s->spheres);
    memset(s, 0, sizeof *s);
}

/* ---- one frame ------------------------------------------------------------ */

/* Message "SCENE: frame K of N: ..." (the frame part only when n > 1). */
static int frame_fail(cr_err *err, const cr_scene *s, int k, int n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

static int frame_fail(cr_err *err, const cr_scene *s, int k, int n, const char *fmt, ...)
{
    char what[CR_ERR_MSG];
    const char *name = s->path ? s->path : "scene";
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    if (n > 1)
        return cr_err_set(err, "%s: frame %d of %d: %s", name, k, n, what);
    return cr_err_set(err, "%s: %s", name, what);
}

#define DEG(x) ((x) * 180.0 / CR_PI)

/* Evaluate v at frame k of n into *out; -1 when that is not finite (start
 * and end too far apart for doubles). */
static int eval(cr_anim v, int k, int n, double *out)
{
    *out = cr_anim_at(v, k, n);
    return isfinite(*out) ? 0 : -1;
}

/* v in buf with the fewest significant digits, 6 (as %g) to 17, that put
 * the printed number on the same side of limit as v, so that a message
 * comparing the two never reads "hfov = 360 deg ... at most 360". */
static const char *num_vs(char buf[32], double v, double limit)
{
    int p;
    for (p = 6; p <= 17; p++) {
        double back;
        snprintf(buf, 32, "%.*g", p, v);
        back = strtod(buf, NULL);
        if ((back > limit) == (v > limit) && (back < limit) == (v < limit))
            break;
    }
    return buf;
}

/* The largest field of view of the flat (rectilinear) screen: at 170 deg the
 * centre tenth of the image already spans only +-30 deg, and towards 180 deg
 * the whole picture collapses into the centre pixel (hfov: 179 looks empty). */
#define CR_MAX_FOV_DEG 170.0

static int check_fov(const char *key, double v, const cr_scene *s, int k, int n, cr_err *err)
{
    char b[32];
    if (!(v > 0.0 && v < CR_PI))
        return frame_fail(err, s, k, n,
                          "observer.%s = %s deg: a field of view must lie between 0 and 180 deg "
                          "(both excluded)",
                          key, num_vs(b, DEG(v), v > 0.0 ? 180.0 : 0.0));
    if (DEG(v) > CR_MAX_FOV_DEG)
        return frame_fail(err, s, k, n,
                          "observer.%s = %s deg: the flat screen cannot show more than %g deg "
                          "(the picture collapses into its centre); use a smaller field of view "
                          "(30 to 90 deg shows the hole and its surroundings)",
                          key, num_vs(b, DEG(v), CR_MAX_FOV_DEG), CR_MAX_FOV_DEG);
    return 0;
}

/* The metric of frame k, checked for a horizon. */
static int frame_metric(const cr_scene *s, int k, int n, cr_metric *mt, cr_err *err)
{
    double ra, rq;
    int i;
    if (eval(s->m, k, n, &mt->m) || eval(s->a, k, n, &mt->a) || eval(s->q, k, n, &mt->q))
        return frame_fail(err, s, k, n, "metric: m, a or q is not a finite number");
    if (!(mt->m > 0.0))
        return frame_fail(err, s, k, n, "metric.m = %g: the mass M must be positive", mt->m);
    ra = mt->a / mt->m;
    rq = mt->q / mt->m;
    if (!(ra * ra + rq * rq <= 1.0 + EXTREMAL_TOL))
        return frame_fail(err, s, k, n,
                          "metric.a = %g, metric.q = %g: a^2 + q^2 = %g exceeds m^2 = %g, so "
                          "there is no event horizon (a naked singularity); need "
                          "a^2 + q^2 <= m^2",
                          mt->a, mt->q, mt->a * mt->a + mt->q * mt->q, mt->m * mt->m);
    /* within the slack of the extremal case: round M up to it */
    if (mt->m * mt->m - mt->a * mt->a - mt->q * mt->q < 0.0)
        mt->m = sqrt(mt->a * mt->a + mt->q * mt->q);
    for (i = 0; i < 8 && mt->m * mt->m - mt->a * mt->a - mt->q * mt->q < 0.0; i++)
        mt->m = nextafter(mt->m, INFINITY);
    if (!isfinite(cr_metric_r_plus(mt)))
        return frame_fail(err, s, k, n, "metric: m = %g, a = %g, q = %g are out of range",
                          mt->m, mt->a, mt->q);
    return 0;
}

/* The fisheye's field of view: (0, 360] deg. */
static int check_fisheye_fov(const char *key, double v, const cr_scene *s, int k, int n,
                             cr_err *err)
{
    char b[32];
    if (!(v > 0.0 && v <= CR_TWO_PI * (1.0 + 1e-12)))
        return frame_fail(err, s, k, n,
                          "observer.%s = %s deg: a fisheye's field of view must lie above 0 and "
                          "at most 360 deg (360 shows every direction; for a full panorama "
                          "use projection: equirectangular)",
                          key, num_vs(b, DEG(v), v > 0.0 ? 360.0 : 0.0));
    return 0;
}

/* A moving observer (motion other than static) at a finite r outside the
 * horizon: does its motion exist there, with |v| < 1? */
static int frame_motion(const cr_scene *s, int k, int n, const cr_metric *mt,
                        const cr_observer *o, cr_err *err)
{
    double v[3], speed;
    int on_axis = fabs(sin(o->theta)) < 1e-10;
    if (o->motion == CR_MOTION_ORBIT) {
        int sense = cr_orbit_sense(mt, !o->retrograde);
        const char *name = o->retrograde ? "retrograde" : "prograde";
        if (fabs(o->theta - 0.5 * CR_PI) > THETA_TOL)
            return frame_fail(err, s, k, n,
                              "observer.motion = orbit: circular orbits lie in the equatorial "
                              "plane, but observer.theta = %g deg (need 90 deg)",
                              DEG(o->theta));
        if (!cr_observer_zamo_velocity(mt, o, on_axis, v))
            return frame_fail(err, s, k, n,
                              "observer.motion = orbit: no timelike circular orbit exists at "
                              "observer.r = %g; %s circular orbits need r above the %s "
                              "photon orbit r = %g",
                              o->r, name, name, cr_orbit_r_photon(mt, sense));
        return 0;
    }
    if (o->motion == CR_MOTION_VELOCITY) {
        speed = sqrt(o->v[0] * o->v[0] + o->v[1] * o->v[1] + o->v[2] * o->v[2]);
        if (!(speed < 1.0)) {
            char b[32];
            return frame_fail(err, s, k, n,
                              "observer.motion = [%g, %g, %g]: the speed |v| = %s must be "
                              "below 1 (the speed of light)",
                              o->v[0], o->v[1], o->v[2], num_vs(b, speed, 1.0));
        }
        if (on_axis && (o->v[1] != 0.0 || o->v[2] != 0.0))
            return frame_fail(err, s, k, n,
                              "observer.motion = [%g, %g, %g]: on the polar axis (theta = %g "
                              "deg) e_theta and e_phi are not defined; an observer there may "
                              "move only along r (v_theta = v_phi = 0)",
                              o->v[0], o->v[1], o->v[2], DEG(o->theta));
    }
    return 0;
}

static int frame_observer(const cr_scene *s, int k, int n, const cr_metric *mt, int width,
                          int height, cr_observer *o, cr_err *err)
{
    double rp, re, mgtt;
    const int inf = s->obs_at_infinity;
    if ((!inf && eval(s->obs_r, k, n, &o->r)) || eval(s->obs_theta, k, n, &o->theta) ||
        eval(s->obs_phi, k, n, &o->phi) || eval(s->roll, k, n, &o->roll) ||
        eval(s->pitch, k, n, &o->pitch) || eval(s->yaw, k, n, &o->yaw) ||
        (!inf && eval(s->hfov, k, n, &o->hfov)) ||
        (!inf && s->has_vfov && eval(s->vfov, k, n, &o->vfov)) ||
        (inf && eval(s->hextent, k, n, &o->hextent)) ||
        (inf && s->has_vextent && eval(s->vextent, k, n, &o->vextent)) ||
        eval(s->obs_v[0], k, n, &o->v[0]) || eval(s->obs_v[1], k, n, &o->v[1]) ||
        eval(s->obs_v[2], k, n, &o->v[2]))
        return frame_fail(err, s, k, n, "observer: a value is not a finite number");
    o->motion = s->obs_motion;
    o->projection = s->obs_projection;
    o->retrograde = s->obs_retrograde;
    if (o->theta < -THETA_TOL || o->theta > CR_PI + THETA_TOL)
        return frame_fail(err, s, k, n, "observer.theta = %g deg lies outside 0 to 180 deg",
                          DEG(o->theta));
    o->theta = fmin(fmax(o->theta, 0.0), CR_PI);
    if (inf) {
        /* Bardeen's image plane: no horizon, ergosphere or range check applies */
        o->r = INFINITY;
        o->hfov = o->vfov = 0.0;
        if (!(o->hextent > 0.0))
            return frame_fail(err, s, k, n,
                              "observer.hextent = %g: the width of the image plane must be "
                              "positive",
                              o->hextent);
        if (!s->has_vextent) /* square pixels, as (E.4.1) */
            o->vextent = o->hextent * (double)height / (double)width;
        if (!(o->vextent > 0.0 && isfinite(o->vextent)))
            return frame_fail(err, s, k, n,
                              "observer.vextent = %g%s: the height of the image plane must be "
                              "positive and finite",
                              o->vextent, s->has_vextent ? "" : " (hextent x height / width)");
        return 0;
    }
    rp = cr_metric_r_plus(mt);
    if (o->r <= rp)
        return frame_fail(err, s, k, n,
                          "observer.r = %g is at or inside the event horizon r+ = %g", o->r, rp);
    re = cr_metric_r_ergo(mt, o->theta);
    mgtt = cr_metric_minus_gtt(mt, o->r, o->theta);
    if (o->r > re && !isfinite(mgtt)) /* r^2 overflows or underflows */
        return frame_fail(err, s, k, n,
                          "observer.r = %g with metric.m = %g is out of the range curray can "
                          "compute with (lengths are in units of M: keep r/M and M sensible)",
                          o->r, mt->m);
    if (o->motion == CR_MOTION_STATIC && (o->r <= re || !(mgtt > 0.0)))
        return frame_fail(err, s, k, n,
                          "observer.r = %g at theta = %g deg is inside the ergosphere "
                          "(r_E+ = %g): no static observer exists there (observer.motion: "
                          "zamo, orbit, infall or a velocity can be there)",
                          o->r, DEG(o->theta), re);
    if (o->motion != CR_MOTION_STATIC && frame_motion(s, k, n, mt, o, err))
        return -1;
    if (o->projection == CR_PROJ_EQUIRECT) {
        o->hfov = CR_TWO_PI;
        o->vfov = CR_PI;
        return 0;
    }
    if (o->projection == CR_PROJ_FISHEYE) {
        if (!s->has_vfov) /* square pixels: the angle is linear in the pixel */
            o->vfov = o->hfov * (double)height / (double)width;
        return check_fisheye_fov("hfov", o->hfov, s, k, n, err) ||
               check_fisheye_fov("vfov", o->vfov, s, k, n, err);
    }
    if (check_fov("hfov", o->hfov, s, k, n, err))
        return -1;
    if (!s->has_vfov) /* (E.4.1): square pixels */
        o->vfov = 2.0 * atan(tan(0.5 * o->hfov) * (double)height / (double)width);
    return check_fov("vfov", o->vfov, s, k, n, err);
}

static int frame_disc(const cr_scene *s, int k, int n, cr_disc *d, cr_err *err)
{
    memset(d, 0, sizeof *d);
    if (!s->has_disc)
        return 0;
    d->enabled = 1;
    d->color1 = s->disc_color1;
    d->color2 = s->disc_color2;
    d->n_radial = s->disc_n_radial;
    d->n_sectors = s->disc_n_sectors;
    d->model = s->disc_model;
    if (eval(s->disc_yaw, k, n, &d->yaw) || eval(s->disc_r_in, k, n, &d->r_in) ||
        eval(s->disc_r_out, k, n, &d->r_out))
        return frame_fail(err, s, k, n, "accretion: a value is not a finite number");
    if (d->model == CR_DISC_KEPLERIAN) {
        if (!(d->r_out > 0.0))
            return frame_fail(err, s, k, n,
                              "accretion.radius: the outer radius %g must be positive",
                              d->r_out);
        if (s->disc_has_r_in && !(d->r_in < d->r_out))
            return frame_fail(err, s, k, n,
                              "accretion.radius: the inner radius %g must be below the outer "
                              "radius %g",
                              d->r_in, d->r_out);
        return 0; /* the rest needs the metric: frame_keplerian */
    }
    if (d->n_radial < 1 || d->n_sectors < 1)
        return frame_fail(err, s, k, n,
                          "accretion.resolution = [%d, %d]: both must be at least 1",
                          d->n_radial, d->n_sectors);
    if (d->r_in < 0.0)
        return frame_fail(err, s, k, n, "accretion.radius: the inner radius %g is negative",
                          d->r_in);
    if (!(d->r_in < d->r_out))
        return frame_fail(err, s, k, n,
                          "accretion.radius: the inner radius %g must be below the outer "
                          "radius %g",
                          d->r_in, d->r_out);
    return 0;
}

/* The Keplerian disc's per-frame data, for a frame already in units of M;
 * m is the scene's M, to give radii in the scene's units in messages. */
static int frame_keplerian(const cr_scene *s, int k, int n, double m, cr_frame *f, cr_err *err)
{
    cr_disc *d = &f->disc;
    const char *sense = s->disc_retrograde ? "retrograde" : "prograde";
    double rp = cr_metric_r_plus(&f->metric), risco;
    if (!d->enabled || d->model != CR_DISC_KEPLERIAN)
        return 0;
    d->sense = cr_orbit_sense(&f->metric, !s->disc_retrograde);
    d->t_peak = s->disc_temperature;
    d->mass_msun = s->disc_mass_msun;
    d->mdot_edd = s->disc_mdot_edd;
    d->plunge = s->disc_plunge;
    if (s->disc_has_r_in && !(d->r_in > rp))
        return frame_fail(err, s, k, n,
                          "accretion.radius: the inner radius %g is at or inside the event "
                          "horizon r+ = %g",
                          d->r_in * m, rp * m);
    risco = cr_orbit_r_isco(&f->metric, d->sense);
    if (!(risco < d->r_out))
        return frame_fail(err, s, k, n,
                          "accretion.radius: the %s ISCO r_isco = %g lies at or beyond the outer "
                          "radius %g: no stable orbit is left on the disc",
                          sense, risco * m, d->r_out * m);
    if (!s->disc_has_r_in)
        d->r_in = risco;
    if (d->plunge && d->r_in > risco)
        return frame_fail(err, s, k, n,
                          "accretion.inside_isco = plunging: the matter falls from the %s ISCO "
                          "r_isco = %g, but the inner radius %g lies outside it; leave the inner "
                          "radius out (radius: [outer]) or put it at or inside the ISCO",
                          sense, risco * m, d->r_in * m);
    if (cr_disc_keplerian_prepare(d, &f->metric) != 0)
        return frame_fail(err, s, k, n,
                          "accretion: metric.a = %g, metric.q = %g are too close to an extremal "
                          "hole for the keplerian disc: its %s ISCO (%g) lies within %g M of the "
                          "photon orbit and the flux table cannot resolve the flux peak there; "
                          "use a spin up to about 0.9999 M (Thorne's limit is 0.998 M)",
                          f->metric.a * m, f->metric.q * m, sense, risco * m,
                          (double)CR_FLUX_MIN_GAP);
    return 0;
}

static int frame_sphere(const cr_scene *s, int k, int n, int i, double a, cr_sphere *sp,
                        cr_err *err)
{
    const cr_scene_sphere *ss = &s->spheres[i];
    memset(sp, 0, sizeof *sp);
    sp->color = ss->color;
    sp->n_lat = ss->n_lat;
    sp->n_lon = ss->n_lon;
    if (eval(ss->r, k, n, &sp->r) || eval(ss->theta, k, n, &sp->theta) ||
        eval(ss->phi, k, n, &sp->phi) || eval(ss->roll, k, n, &sp->roll) ||
        eval(ss->pitch, k, n, &sp->pitch) || eval(ss->yaw, k, n, &sp->yaw) ||
        eval(ss->radius, k, n, &sp->radius))
        return frame_fail(err, s, k, n, "sphere %d (line %d): a value is not a finite number", i,
                          ss->line);
    if (sp->n_lat < 1 || sp->n_lon < 1)
        return frame_fail(err, s, k, n,
                          "sphere %d (line %d): resolution [%d, %d]: both must be at least 1", i,
                          ss->line, sp->n_lat, sp->n_lon);
    if (sp->r < 0.0)
        return frame_fail(err, s, k, n, "sphere %d (line %d): r = %g must not be negative", i,
                          ss->line, sp->r);
    if (!(sp->radius > 0.0))
        return frame_fail(err, s, k, n, "sphere %d (line %d): radius = %g must be positive", i,
                          ss->line, sp->radius);
    cr_sphere_prepare(sp, a);
    return 0;
}

static int frame_settings(const cr_scene *s, int k, int n, const cr_trace_settings *ts,
                          cr_frame *f, cr_err *err)
{
    cr_trace_settings t = ts ? *ts : cr_trace_defaults();
    char msg[CR_ERR_MSG];
    if (t.samples == 0) /* 0 means 1 */
        t.samples = 1;
    if (cr_trace_settings_check(&t, msg, sizeof msg))
        return frame_fail(err, s, k, n, "%s", msg);
    if (s->obs_at_infinity && t.integrator == CR_INTEG_RK4)
        return frame_fail(err, s, k, n,
                          "raytracer.integrator = %s: the rk4 integrator cannot start at "
                          "infinity (observer.r: inf); use mino, or give observer.r a finite "
                          "value",
                          cr_integrator_name(t.integrator));
    cr_trace_settings_to_frame(&t, f);
    return 0;
}

int cr_scene_frame(const cr_scene *s, int k, int n, int width, int height,
                   const cr_trace_settings *ts, cr_frame *f, cr_sphere *sphere_buf, cr_err *err)
{
    int i;

    memset(f, 0, sizeof *f);
    if (n < 1 || k < 0 || k >= n)
        return frame_fail(err, s, 0, 1, "frame %d of %d does not exist (frames are 0 to n-1)",
                          k, n);
    if (width < 1 || height < 1)
        return frame_fail(err, s, k, n, "the image size %d x %d must be positive", width,
                          height);
    if (s->n_spheres > 0 && !sphere_buf)
        return frame_fail(err, s, k, n, "no room given for the spheres");
    if (frame_settings(s, k, n, ts, f, err) || frame_metric(s, k, n, &f->metric, err) ||
        frame_observer(s, k, n, &f->metric, width, height, &f->observer, err) ||
        frame_disc(s, k, n, &f->disc, err))
        return -1;
    for (i = 0; i < s->n_spheres; i++)
        if (frame_sphere(s, k, n, i, f->metric.a, &sphere_buf[i], err))
            return -1;
    f->spheres = s->n_spheres > 0 ? sphere_buf : NULL;
    f->n_spheres = s->n_spheres;
    if (s->has_sky) {
        if (!s->sky_rgb || s->sky_width < 1 || s->sky_height < 1)
            return frame_fail(err, s, k, n, "skymap: no sky image is loaded");
        if (s->sky_at_infinity)
            f->sky_boundary = 0.0;
        else if (eval(s->sky_boundary, k, n, &f->sky_boundary) || !(f->sky_boundary > 0.0))
            return frame_fail(err, s, k, n, "skymap.boundary = %g must be positive",
                              f->sky_boundary);
        f->sky.rgb = s->sky_rgb;
        f->sky.width = s->sky_width;
        f->sky.height = s->sky_height;
    }
    f->sky_color = s->sky_color;
    f->horizon_color = s->horizon_color;
    f->error_color = s->error_color;
    f->limit_color = s->limit_color;
    f->width = width;
    f->height = height;
    /* inside the core every length is in units of M (messages above use the
     * scene's own units) */
    for (i = 0; i < s->n_spheres; i++)
        cr_sphere_to_units_of_m(&sphere_buf[i], f->metric.m);
    {
        double m_scene = f->metric.m;
        cr_frame_to_units_of_m(f);
        if (frame_keplerian(s, k, n, m_scene, f, err))
            return -1;
    }
    if (!s->obs_at_infinity) {
        /* an observer closer to the horizon than 2 epsilon (8.1: observers
         * just outside the horizon work): stop rays halfway between the
         * observer and r+ instead; the caller sees the smaller
         * horizon_epsilon in the frame and says so */
        double gap = f->observer.r - cr_metric_r_plus(&f->metric);
        if (gap < 2.0 * f->horizon_epsilon)
            f->horizon_epsilon = 0.5 * gap;
    }
    cr_frame_prepare(f);
    /* the boundary of an observer at infinity is at infinity too */
    if (!(isfinite(f->r_max) || (s->obs_at_infinity && f->r_max == INFINITY)) ||
        !isfinite(f->r_stop) || !(f->obs_sqrt_mgtt > 0.0) ||
        !isfinite(f->obs_sqrt_mgtt) || !isfinite(f->tan_half_h) || !isfinite(f->tan_half_v))
        return frame_fail(err, s, k, n,
                          "the scene's numbers are too large to trace (r_max = %g)", f->r_max);
    return 0;
}

/* Is any number of the scene animated ([linear, a, b] with a != b)? Every
 * cr_anim of cr_scene is listed here; a new animatable key belongs here too. */
static int scene_animated(const cr_scene *s)
{
    const cr_anim *v[] = {&s->m,         &s->a,        &s->q,          &s->obs_r,
                          &s->obs_theta, &s->obs_phi,  &s->roll,       &s->pitch,
                          &s->yaw,       &s->hfov,     &s->vfov,       &s->hextent,
                          &s->vextent,   &s->obs_v[0], &s->obs_v[1],   &s->obs_v[2],
                          &s->disc_yaw,  &s->disc_r_in, &s->disc_r_out, &s->sky_boundary};
    size_t i;
    int j;
    for (i = 0; i < sizeof v / sizeof v[0]; i++)
        if (v[i]->a != v[i]->b)
            return 1;
    for (j = 0; j < s->n_spheres; j++) {
        const cr_scene_sphere *p = &s->spheres[j];
        const cr_anim *w[] = {&p->r, &p->theta, &p->phi, &p->roll, &p->pitch, &p->yaw,
                              &p->radius};
        for (i = 0; i < sizeof w / sizeof w[0]; i++)
            if (w[i]->a != w[i]->b)
                return 1;
    }
    return 0;
}

int cr_scene_hints(const cr_scene *s, int n, cr_err *hints, int max_hints)
{
    int count = 0, j, k;
    if (s->has_sky && s->sky_rgb && s->sky_width != 2 * s->sky_height && count < max_hints)
        cr_err_set(&hints[count++],
                   "skymap.image %s is %dx%d pixels, %.3g times as wide as high: the sky map "
                   "covers 360 x 180 deg, so it is stretched %s (an equirectangular image is "
                   "twice as wide as high)",
                   s->sky_image, s->sky_width, s->sky_height,
                   (double)s->sky_width / (double)s->sky_height,
                   s->sky_width > 2 * s->sky_height ? "vertically" : "horizontally");
    /* A sphere is tested in the Cartesian coordinates (2.2.8), where its
     * centre lies sqrt(r^2 + a^2 sin^2 theta) from the origin; the region
     * r <= r+ contains the ball of radius r+ there, so a sphere with
     * |centre| + radius <= r+ lies wholly inside the horizon: no ray reaches
     * it (they stop at r+ + horizon_epsilon). */
    for (j = 0; j < s->n_spheres && count < max_hints; j++) {
        const cr_scene_sphere *p = &s->spheres[j];
        int first = -1, inside = 0;
        for (k = 0; k < n; k++) {
            double m = cr_anim_at(s->m, k, n), a = cr_anim_at(s->a, k, n);
            double q = cr_anim_at(s->q, k, n), r = cr_anim_at(p->r, k, n);
            double st = sin(cr_anim_at(p->theta, k, n));
            double disc = m * m - a * a - q * q;
            double rp = m + sqrt(disc > 0.0 ? disc : 0.0);
            if (sqrt(r * r + a * a * st * st) + cr_anim_at(p->radius, k, n) <= rp) {
                inside++;
                if (first < 0)
                    first = k;
            }
        }
        if (inside == n)
            cr_err_set(&hints[count++],
                       "sphere %d (line %d) lies wholly inside the event horizon%s: no ray "
                       "reaches it, so it cannot be seen",
                       j, p->line, n > 1 ? " in every frame" : "");
        else if (inside > 0)
            cr_err_set(&hints[count++],
                       "sphere %d (line %d) lies wholly inside the event horizon in %d of %d "
                       "frames (first in frame %d): it cannot be seen there",
                       j, p->line, inside, n, first);
    }
    if (n > 1 && !scene_animated(s) && count < max_hints)
        cr_err_set(&hints[count++],
                   "-f %d: nothing in the scene is animated (no [linear, start, end] value), so "
                   "all %d frames are the same image",
                   n, n);
    return count;
}
