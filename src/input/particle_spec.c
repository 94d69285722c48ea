/* curray io: the orbit file of `curray orbit` (particle_spec.h). */
#include "particle_spec.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "yamlutil.h"

/* Largest orbit file read (bytes). */
#define PSPEC_MAX_BYTES (1 << 20)

#define FREQ(k) {k, 1, 0, NULL, NULL, 0}
#define FOPT(k) {k, 0, 0, NULL, NULL, 0}

/* A number field f (present) into *out. */
static int num(cr_yaml *y, const cr_yaml_field *f, const char *parent, double *out, cr_err *err)
{
    char p[CR_YAML_PATH];
    cr_yaml_path_key(p, sizeof p, parent, f->key);
    return cr_yaml_number(y, f->value, p, out, err);
}

/* The path pre.key (pre: the particle section's, "particle" in an orbit
 * file, "sphere[0].particle" in a scene). */
static const char *sub(char *buf, size_t n, const char *pre, const char *key)
{
    cr_yaml_path_key(buf, n, pre, key);
    return buf;
}

/* Fail at field f of the particle section pre with a message. */
static int fail_at(cr_yaml *y, const char *pre, const cr_yaml_field *f, cr_err *err,
                   const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
static int fail_at(cr_yaml *y, const char *pre, const cr_yaml_field *f, cr_err *err,
                   const char *fmt, ...)
{
    char p[CR_YAML_PATH], msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    cr_yaml_path_key(p, sizeof p, pre, f->key);
    return cr_yaml_fail(y, f->key_node, p, err, "%s", msg);
}

static int parse_metric(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, cr_particle_spec *s,
                        cr_err *err)
{
    cr_yaml_field f[3] = {FREQ("m"), FREQ("a"), FREQ("q")};
    if (cr_yaml_fields(y, map, "metric", key, f, 3, err) ||
        num(y, &f[0], "metric", &s->mt.m, err) || num(y, &f[1], "metric", &s->mt.a, err) ||
        num(y, &f[2], "metric", &s->mt.q, err))
        return -1;
    if (!(s->mt.m > 0.0))
        return cr_yaml_fail(y, f[0].key_node, "metric.m", err, "the mass must be > 0, got %g",
                            s->mt.m);
    if (s->mt.a * s->mt.a + s->mt.q * s->mt.q > s->mt.m * s->mt.m)
        return cr_yaml_fail(y, key, "metric", err,
                            "a^2 + q^2 = %g exceeds m^2 = %g: no horizon (a naked "
                            "singularity is not supported)",
                            s->mt.a * s->mt.a + s->mt.q * s->mt.q, s->mt.m * s->mt.m);
    return 0;
}

/* One word of a list of choices; returns its index or -1 with a message. */
static int choice(cr_yaml *y, yaml_node_t *node, const char *path, const char *const *words,
                  int n, const char *want, int *out, cr_err *err)
{
    char got[96];
    int i;
    for (i = 0; i < n; i++)
        if (cr_yaml_scalar_is(node, words[i])) {
            *out = i;
            return 0;
        }
    cr_yaml_describe(node, got, sizeof got);
    return cr_yaml_fail(y, node, path, err, "expected %s, got %s", want, got);
}

static int parse_constants(cr_yaml *y, const char *pre, const cr_yaml_field *fc,
                           cr_particle_spec *s, cr_err *err)
{
    static const char *const radial[2] = {"outward", "inward"};
    static const char *const polar[2] = {"south", "north"};
    char P[CR_YAML_PATH], b[CR_YAML_PATH];
    cr_yaml_field f[5] = {FREQ("E"), FREQ("L"), FREQ("K"), FOPT("radial"), FOPT("polar")};
    int rs = 0, ps = 0;
    sub(P, sizeof P, pre, "constants");
    if (cr_yaml_fields(y, fc->value, P, fc->key_node, f, 5, err) || num(y, &f[0], P, &s->E, err) ||
        num(y, &f[1], P, &s->L, err) || num(y, &f[2], P, &s->K, err))
        return -1;
    if (f[3].value && choice(y, f[3].value, sub(b, sizeof b, P, "radial"), radial, 2,
                             "outward or inward", &rs, err))
        return -1;
    if (f[4].value && choice(y, f[4].value, sub(b, sizeof b, P, "polar"), polar, 2,
                             "south (theta growing) or north", &ps, err))
        return -1;
    if (!(s->E > 0.0))
        return cr_yaml_fail(y, f[0].key_node, sub(b, sizeof b, P, "E"), err,
                            "the energy must be > 0 (a future-directed worldline), got %g",
                            s->E);
    s->sr = rs ? -1 : 1;
    s->sth = ps ? -1 : 1;
    return 0;
}

enum {
    P_QM, P_R, P_TH, P_PH, P_T, P_VEL, P_MEAS, P_CONST, P_CIRC, P_TAU, P_DTAU, P_TOL, P_RMAX,
    P_EPS, P_N
};

/* The scalar fields of particle with their defaults, and r: isco. */
static int parse_scalars(cr_yaml *y, const char *P, cr_yaml_field *f, cr_particle_spec *s,
                         int *r_isco, cr_err *err)
{
    char b[CR_YAML_PATH];
    s->qm = 0.0;
    s->phi = 0.0;
    s->t0 = 0.0;
    s->tolerance = 1e-10;
    s->r_max = 1e4;
    s->horizon_epsilon = 1e-6;
    *r_isco = cr_yaml_scalar_is(f[P_R].value, "isco");
    if ((f[P_QM].value && num(y, &f[P_QM], P, &s->qm, err)) ||
        (!*r_isco && num(y, &f[P_R], P, &s->r, err)) ||
        cr_yaml_angle(y, f[P_TH].value, sub(b, sizeof b, P, "theta"), &s->theta, err) ||
        (f[P_PH].value && cr_yaml_angle(y, f[P_PH].value, sub(b, sizeof b, P, "phi"), &s->phi, err)) ||
        (f[P_T].value && num(y, &f[P_T], P, &s->t0, err)) || num(y, &f[P_TAU], P, &s->tau, err) ||
        (f[P_TOL].value && num(y, &f[P_TOL], P, &s->tolerance, err)) ||
        (f[P_RMAX].value && num(y, &f[P_RMAX], P, &s->r_max, err)) ||
        (f[P_EPS].value && num(y, &f[P_EPS], P, &s->horizon_epsilon, err)))
        return -1;
    if (!(s->tau > 0.0))
        return fail_at(y, P, &f[P_TAU], err, "the proper time to follow must be > 0, got %g", s->tau);
    s->dtau = s->tau / 1000.0;
    if (f[P_DTAU].value && num(y, &f[P_DTAU], P, &s->dtau, err))
        return -1;
    if (!(s->dtau > 0.0))
        return fail_at(y, P, &f[P_DTAU], err, "the output spacing must be > 0, got %g", s->dtau);
    if (s->tau / s->dtau > CR_PSPEC_MAX_ROWS)
        return fail_at(y, P, &f[P_DTAU], err, "tau / dtau = %g rows exceeds the limit %g",
                       s->tau / s->dtau, CR_PSPEC_MAX_ROWS);
    if (!(s->tolerance > 0.0 && s->tolerance <= 1e-3))
        return fail_at(y, P, &f[P_TOL], err, "expected a tolerance in (0, 1e-3], got %g", s->tolerance);
    if (!(s->horizon_epsilon > 0.0 && s->horizon_epsilon < 1.0))
        return fail_at(y, P, &f[P_EPS], err, "expected a value in (0, 1), got %g", s->horizon_epsilon);
    return 0;
}

/* The initial data: exactly one of velocity, constants, circular. */
static int parse_initial(cr_yaml *y, const char *pre, yaml_node_t *key, cr_yaml_field *f,
                         cr_particle_spec *s, int r_isco, cr_err *err)
{
    char b[CR_YAML_PATH];
    static const char *const frames[2] = {"static", "zamo"};
    static const char *const senses[2] = {"prograde", "retrograde"};
    const int kinds[3] = {P_VEL, P_CONST, P_CIRC};
    int i, first = -1;
    for (i = 0; i < 3; i++) {
        const cr_yaml_field *k = &f[kinds[i]];
        if (!k->value)
            continue;
        if (first >= 0) {
            char p[CR_YAML_PATH];
            cr_yaml_path_key(p, sizeof p, pre, k->key);
            return cr_yaml_fail(y, k->key_node, p, err,
                                "contradicts %s: give one kind of initial data "
                                "(velocity, constants or circular)",
                                sub(b, sizeof b, pre, f[kinds[first]].key));
        }
        first = i;
    }
    if (first < 0)
        return cr_yaml_fail(y, key, pre, err,
                            "no initial data: give one of velocity (with measured_by), "
                            "constants or circular");
    s->kind = first;
    if (f[P_MEAS].value && s->kind != CR_PSPEC_VELOCITY)
        return fail_at(y, pre, &f[P_MEAS], err, "goes with %s only",
                       sub(b, sizeof b, pre, "velocity"));
    if (r_isco && s->kind != CR_PSPEC_CIRCULAR)
        return fail_at(y, pre, &f[P_R], err, "r: isco goes with %s only",
                       sub(b, sizeof b, pre, "circular"));
    if (s->kind == CR_PSPEC_VELOCITY) {
        yaml_node_t *it[3];
        s->measured_by = CR_PARTICLE_OBS_STATIC;
        if (f[P_MEAS].value && choice(y, f[P_MEAS].value, sub(b, sizeof b, pre, "measured_by"),
                                      frames, 2, "static or zamo", &s->measured_by, err))
            return -1;
        if (cr_yaml_list(y, f[P_VEL].value, sub(b, sizeof b, pre, "velocity"), 3,
                         "a velocity [v_r, v_theta, v_phi]", it, NULL, err))
            return -1;
        for (i = 0; i < 3; i++) {
            char p[CR_YAML_PATH];
            cr_yaml_path_index(p, sizeof p, b, i);
            if (cr_yaml_number(y, it[i], p, &s->v[i], err))
                return -1;
        }
        {
            double v2 = s->v[0] * s->v[0] + s->v[1] * s->v[1] + s->v[2] * s->v[2];
            if (!(v2 < 1.0))
                return fail_at(y, pre, &f[P_VEL], err,
                               "speed %.17g is not below the speed of light (1)", sqrt(v2));
        }
    } else if (s->kind == CR_PSPEC_CONSTANTS) {
        if (parse_constants(y, pre, &f[P_CONST], s, err))
            return -1;
    } else {
        if (choice(y, f[P_CIRC].value, sub(b, sizeof b, pre, "circular"), senses, 2,
                   "prograde or retrograde", &s->retrograde, err))
            return -1;
        if (fabs(s->theta - 0.5 * CR_PI) > 1e-12)
            return fail_at(y, pre, &f[P_TH], err,
                           "a circular orbit lies in the equator: theta must be 90 deg, got "
                           "%g deg",
                           s->theta * 180.0 / CR_PI);
        s->theta = 0.5 * CR_PI;
        if (s->qm != 0.0)
            return fail_at(y, pre, &f[P_CIRC], err,
                           "the circular orbit of orbit.h is a neutral particle's: it "
                           "contradicts charge_to_mass = %g (give velocity or constants)",
                           s->qm);
        if (r_isco)
            s->r = cr_orbit_r_isco(&s->mt, cr_orbit_sense(&s->mt, !s->retrograde));
    }
    return 0;
}

/* The start: outside the horizon, below r_max, and the initial data
 * possible there. */
static int check_start(cr_yaml *y, const char *pre, cr_yaml_field *f, cr_particle_spec *s,
                       cr_err *err)
{
    double rp = cr_metric_r_plus(&s->mt);
    cr_particle p;
    if (!(s->r > rp + s->horizon_epsilon))
        return fail_at(y, pre, &f[P_R], err,
                       "the start r = %g is not outside the horizon r+ = %.17g (the worldline "
                       "ends at r+ + horizon_epsilon)",
                       s->r, rp);
    if (!(s->r < s->r_max))
        return fail_at(y, pre, &f[P_RMAX], err,
                       "r_max = %g must exceed the start r = %g", s->r_max, s->r);
    if (s->kind == CR_PSPEC_VELOCITY && s->measured_by == CR_PARTICLE_OBS_STATIC) {
        double u[4];
        if (!cr_particle_observer_u(&s->mt, s->measured_by, s->r, s->theta, s->v, u))
            return fail_at(y, pre, f[P_MEAS].value ? &f[P_MEAS] : &f[P_VEL], err,
                           "no static observer at r = %g, theta = %g rad (inside the "
                           "ergosurface): measure the velocity with measured_by: zamo",
                           s->r, s->theta);
    }
    if (s->kind == CR_PSPEC_CIRCULAR) {
        cr_orbit o;
        if (!cr_orbit_eval(&s->mt, cr_orbit_sense(&s->mt, !s->retrograde), s->r, &o))
            return fail_at(y, pre, &f[P_R], err,
                           "no circular orbit at r = %g (inside the photon orbit r = %.6g)",
                           s->r,
                           cr_orbit_r_photon(&s->mt, cr_orbit_sense(&s->mt, !s->retrograde)));
    }
    if (!cr_particle_spec_start(s, &p)) {
        if (s->kind == CR_PSPEC_CONSTANTS)
            return fail_at(y, pre, &f[P_CONST], err,
                           "these E, L, K do not allow the start (R(r) = %g, the polar "
                           "potential %g: one is negative)",
                           cr_particle_R(&s->mt, s->E, s->L, s->K, s->qm, s->r),
                           s->K - cos(s->theta) * cos(s->theta) *
                                      (s->mt.a * s->mt.a * (1.0 - s->E * s->E) +
                                       s->L * s->L / fmax(sin(s->theta) * sin(s->theta), 1e-300)));
        return fail_at(y, pre, &f[P_VEL], err,
                       "this velocity cannot start at r = %g, theta = %g rad (on the axis "
                       "only v_r and v_theta)",
                       s->r, s->theta);
    }
    return 0;
}

int cr_particle_spec_parse(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *pre,
                           int for_sphere, cr_particle_spec *s, cr_err *err)
{
    cr_yaml_field f[P_N] = {FOPT("charge_to_mass"), FREQ("r"),        FREQ("theta"),
                            FOPT("phi"),            FOPT("t"),        FOPT("velocity"),
                            FOPT("measured_by"),    FOPT("constants"), FOPT("circular"),
                            FREQ("tau"),            FOPT("dtau"),     FOPT("tolerance"),
                            FOPT("r_max"),          FOPT("horizon_epsilon")};
    int r_isco;
    if (cr_yaml_fields(y, map, pre, key, f, P_N, err))
        return -1;
    if (for_sphere && f[P_DTAU].value)
        return fail_at(y, pre, &f[P_DTAU], err,
                       "is the output spacing of an orbit file: a sphere's worldline is "
                       "tabulated at the renderer's own spacing (leave dtau out)");
    if (parse_scalars(y, pre, f, s, &r_isco, err) ||
        parse_initial(y, pre, key, f, s, r_isco, err))
        return -1;
    if (!f[P_RMAX].key_node)
        f[P_RMAX].key_node = key;
    return check_start(y, pre, f, s, err);
}

/* The view section: the picture of -t c. base: the orbit file's folder
 * ("" or ending in '/'), against which a relative view.scene resolves. */
static int parse_view(cr_yaml *y, yaml_node_t *key, yaml_node_t *map, const char *base,
                      cr_particle_spec *s, cr_err *err)
{
    cr_orbit_view *v = &s->view;
    cr_yaml_field f[4] = {FREQ("scene"), FOPT("color"), FOPT("line_width"), FOPT("orders")};
    const char *scene;
    cr_err at;
    long orders = 2;
    v->given = 1;
    v->by_tau = 1;
    v->line_width = 1.5;
    if (cr_yaml_fields(y, map, "view", key, f, 4, err) ||
        cr_yaml_string(y, f[0].value, "view.scene", &scene, err))
        return -1;
    if (snprintf(v->scene, sizeof v->scene, "%s%s", scene[0] == '/' ? "" : base, scene) >=
        (int)sizeof v->scene)
        return cr_yaml_fail(y, f[0].value, "view.scene", err, "the path is too long");
    cr_yaml_fail(y, f[0].value, "view.scene", &at, "%s", "");
    snprintf(v->where, sizeof v->where, "%s", at.msg);
    if (f[1].value && !cr_yaml_scalar_is(f[1].value, "proper_time")) {
        yaml_node_t *it[3];
        long c[3];
        int i;
        if (f[1].value->type != YAML_SEQUENCE_NODE) {
            char got[96];
            cr_yaml_describe(f[1].value, got, sizeof got);
            return cr_yaml_fail(y, f[1].value, "view.color", err,
                                "expected proper_time or a colour [R, G, B], got %s", got);
        }
        if (cr_yaml_list(y, f[1].value, "view.color", 3, "a colour [R, G, B]", it, NULL, err))
            return -1;
        for (i = 0; i < 3; i++) {
            char p[CR_YAML_PATH];
            cr_yaml_path_index(p, sizeof p, "view.color", i);
            if (cr_yaml_int(y, it[i], p, 0, 255, "a colour component, an integer from 0 to 255",
                            &c[i], err))
                return -1;
        }
        v->by_tau = 0;
        v->color.r = (uint8_t)c[0];
        v->color.g = (uint8_t)c[1];
        v->color.b = (uint8_t)c[2];
    }
    if (f[2].value) {
        if (cr_yaml_number(y, f[2].value, "view.line_width", &v->line_width, err))
            return -1;
        if (!(v->line_width > 0.0 && v->line_width <= 16.0))
            return cr_yaml_fail(y, f[2].value, "view.line_width", err,
                                "expected a width in pixels in (0, 16], got %g", v->line_width);
    }
    if (f[3].value &&
        cr_yaml_int(y, f[3].value, "view.orders", 1, 4,
                    "the number of image orders drawn, 1 (the direct image) to 4", &orders, err))
        return -1;
    v->orders = (int)orders;
    return 0;
}

/* The common part of both loaders; base as for parse_view. */
static int load_text(const char *text, size_t len, const char *name, const char *base,
                     cr_particle_spec *s, cr_err *err)
{
    cr_yaml_field f[3] = {FREQ("metric"), FREQ("particle"), FOPT("view")};
    cr_yaml y;
    yaml_node_t *root;
    int rc = -1;
    memset(s, 0, sizeof *s);
    if (cr_yaml_load(&y, text, len, name ? name : "(orbit)", err))
        return -1;
    root = cr_yaml_root(&y);
    if (!root || root->type != YAML_MAPPING_NODE) {
        cr_err_set(err, "%s: an orbit file is a mapping with metric and particle", y.name);
        goto done;
    }
    if (cr_yaml_fields(&y, root, NULL, NULL, f, 3, err) ||
        parse_metric(&y, f[0].key_node, f[0].value, s, err) ||
        cr_particle_spec_parse(&y, f[1].key_node, f[1].value, "particle", 0, s, err) ||
        (f[2].key_node && parse_view(&y, f[2].key_node, f[2].value, base, s, err)))
        goto done;
    rc = 0;
done:
    cr_yaml_free(&y);
    return rc;
}

int cr_particle_spec_load_string(const char *text, size_t len, const char *name,
                                 cr_particle_spec *s, cr_err *err)
{
    return load_text(text, len, name, "", s, err);
}

int cr_particle_spec_load(const char *path, cr_particle_spec *s, cr_err *err)
{
    char *text = NULL;
    size_t len;
    int rc;
    memset(s, 0, sizeof *s);
    if (!path || !path[0])
        return cr_err_set(err, "no orbit file given");
    if (cr_yaml_read_file(path, (size_t)PSPEC_MAX_BYTES, &text, &len, err)) {
        cr_err inner = *err;
        return cr_err_set(err, "orbit file %s", inner.msg);
    }
    {
        /* the folder of the file, for a relative view.scene */
        const char *slash = strrchr(path, '/');
        char base[4096];
        size_t n = slash ? (size_t)(slash - path) + 1 : 0;
        if (n >= sizeof base) {
            free(text);
            return cr_err_set(err, "orbit file %s: the path is too long", path);
        }
        memcpy(base, path, n);
        base[n] = '\0';
        rc = load_text(text, len, path, base, s, err);
    }
    free(text);
    return rc;
}

int cr_particle_spec_start(const cr_particle_spec *s, cr_particle *p)
{
    double u[4];
    if (s->kind == CR_PSPEC_CONSTANTS)
        return cr_particle_start_constants(p, &s->mt, s->qm, s->tolerance, s->horizon_epsilon,
                                           s->r_max, s->t0, s->r, s->theta, s->phi, s->E, s->L,
                                           s->K, s->sr, s->sth);
    if (s->kind == CR_PSPEC_CIRCULAR) {
        cr_orbit o;
        if (!cr_orbit_eval(&s->mt, cr_orbit_sense(&s->mt, !s->retrograde), s->r, &o))
            return 0;
        cr_orbit_velocity(&o, u);
    } else if (!cr_particle_observer_u(&s->mt, s->measured_by, s->r, s->theta, s->v, u)) {
        return 0;
    }
    return cr_particle_start_u(p, &s->mt, s->qm, s->tolerance, s->horizon_epsilon, s->r_max,
                               s->t0, s->r, s->theta, s->phi, u);
}
