/* curray web: the entry point of the WebAssembly build (web.h). */
#include "web.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "../core/trace.h"
#include "../input/names.h"
#include "../input/scene.h"
#include "../output/output.h"

struct cr_web {
    cr_scene scene; /* animation-free: every cr_anim has a == b */
    cr_scene_sphere spheres[CR_WEB_MAX_SPHERES];
    cr_trace_settings ts;
    cr_frame_eval eval; /* the evaluated frame (eval.frame) with its spheres */
    int ready;          /* frame evaluated without error */
    int color2_default; /* accretion.color2 unset: the complement of color1 */
    char name[64];      /* the scene's name in messages (the file it is saved as) */
    cr_err err;
};

/* The scene file's "X deg" (cr_yaml_angle, operation for operation). */
static double deg_to_rad(double v)
{
    return v / 180.0 * CR_PI;
}

/* An integer key: truncated; -1 (which the evaluation refuses with its
 * message, as every count must be positive) for NaN or out of range. */
static int int_of(double v)
{
    return v > -2e9 && v < 2e9 ? (int)v : -1;
}

static void anim_set(cr_anim *a, double v)
{
    a->a = a->b = v;
}

/* A colour 0xRRGGBB; black for anything else (NaN, out of range). */
static cr_rgb rgb_of(double v)
{
    long c = v >= 0.0 && v <= 16777215.0 ? (long)v : 0;
    return cr_rgb_make((int)((c >> 16) & 255), (int)((c >> 8) & 255), (int)(c & 255));
}

/* The parser's defaults for everything a scene file may leave out
 * (scene.c: parse_scene, parse_accretion, parse_observer). */
static void scene_defaults(cr_web *w)
{
    cr_scene *s = &w->scene;
    memset(s, 0, sizeof *s);
    strcpy(w->name, "scene.yml");
    s->path = w->name;
    w->color2_default = 1;
    s->sky_color = cr_rgb_make(0, 0, 0);
    s->horizon_color = cr_rgb_make(255, 0, 0);
    s->error_color = cr_rgb_make(0, 0, 255);
    s->limit_color = cr_rgb_make(255, 255, 0);
    s->other_side_color = cr_rgb_make(96, 0, 128);
    s->singularity_color = cr_rgb_make(255, 255, 255);
    s->disc_order = -1; /* accretion.order unset: every image order */
    s->obs_motion = CR_MOTION_STATIC;
    s->obs_projection = CR_PROJ_RECTILINEAR;
    s->disc_model = CR_DISC_CHESSBOARD;
    s->disc_temperature = 1e4;
    s->disc_has_r_in = 1;
    s->disc_color1 = cr_rgb_make(255, 255, 255);
    s->disc_color2 = cr_rgb_make(0, 0, 0);
    s->disc_n_radial = s->disc_n_sectors = 1;
    s->sky_at_infinity = 1;
    s->spheres = w->spheres;
    s->n_spheres = 0;
    w->ts = cr_trace_defaults();
}

cr_web *cr_web_new(void)
{
    cr_web *w = calloc(1, sizeof *w);
    if (w)
        scene_defaults(w);
    return w;
}

void cr_web_free(cr_web *w)
{
    if (!w)
        return;
    free(w->scene.sky_rgb);
    cr_frame_eval_free(&w->eval);
    free(w);
}

static int fail(cr_web *w, const char *what, const char *key)
{
    w->ready = 0;
    return cr_err_set(&w->err, "%s '%s'", what, key);
}

/* Keys of a sphere (the one added last). */
static int set_sphere(cr_web *w, const char *k, double v)
{
    cr_scene_sphere *sp;
    if (w->scene.n_spheres < 1)
        return -1;
    sp = &w->spheres[w->scene.n_spheres - 1];
    if (!strcmp(k, "color"))
        sp->color = rgb_of(v);
    else if (!strcmp(k, "n_lat"))
        sp->n_lat = int_of(v);
    else if (!strcmp(k, "n_lon"))
        sp->n_lon = int_of(v);
    else if (!strcmp(k, "r"))
        anim_set(&sp->r, v);
    else if (!strcmp(k, "theta"))
        anim_set(&sp->theta, deg_to_rad(v));
    else if (!strcmp(k, "phi"))
        anim_set(&sp->phi, deg_to_rad(v));
    else if (!strcmp(k, "roll"))
        anim_set(&sp->roll, deg_to_rad(v));
    else if (!strcmp(k, "pitch"))
        anim_set(&sp->pitch, deg_to_rad(v));
    else if (!strcmp(k, "yaw"))
        anim_set(&sp->yaw, deg_to_rad(v));
    else if (!strcmp(k, "radius"))
        anim_set(&sp->radius, v);
    else
        return -1;
    return 0;
}

static int set_observer(cr_scene *s, const char *k, double v)
{
    if (!strcmp(k, "r")) {
        s->obs_at_infinity = isinf(v) && v > 0.0;
        anim_set(&s->obs_r, v);
    } else if (!strcmp(k, "theta"))
        anim_set(&s->obs_theta, deg_to_rad(v));
    else if (!strcmp(k, "phi"))
        anim_set(&s->obs_phi, deg_to_rad(v));
    else if (!strcmp(k, "roll"))
        anim_set(&s->roll, deg_to_rad(v));
    else if (!strcmp(k, "pitch"))
        anim_set(&s->pitch, deg_to_rad(v));
    else if (!strcmp(k, "yaw"))
        anim_set(&s->yaw, deg_to_rad(v));
    else if (!strcmp(k, "hfov"))
        anim_set(&s->hfov, deg_to_rad(v));
    else if (!strcmp(k, "vfov")) {
        s->has_vfov = !isnan(v);
        anim_set(&s->vfov, s->has_vfov ? deg_to_rad(v) : 0.0);
    } else if (!strcmp(k, "hextent"))
        anim_set(&s->hextent, v);
    else if (!strcmp(k, "vextent")) {
        s->has_vextent = !isnan(v);
        anim_set(&s->vextent, s->has_vextent ? v : 0.0);
    } else if (!strcmp(k, "v_r"))
        anim_set(&s->obs_v[0], v);
    else if (!strcmp(k, "v_theta"))
        anim_set(&s->obs_v[1], v);
    else if (!strcmp(k, "v_phi"))
        anim_set(&s->obs_v[2], v);
    else if (!strcmp(k, "retrograde"))
        s->obs_retrograde = v != 0.0;
    else
        return -1;
    return 0;
}

static int set_accretion(cr_web *w, const char *k, double v)
{
    cr_scene *s = &w->scene;
    if (!strcmp(k, "enabled"))
        s->has_disc = v != 0.0;
    else if (!strcmp(k, "color1"))
        s->disc_color1 = rgb_of(v);
    else if (!strcmp(k, "color2")) {
        w->color2_default = isnan(v);
        s->disc_color2 = rgb_of(isnan(v) ? 0.0 : v);
    }
    else if (!strcmp(k, "n_radial"))
        s->disc_n_radial = int_of(v);
    else if (!strcmp(k, "n_sectors"))
        s->disc_n_sectors = int_of(v);
    else if (!strcmp(k, "yaw"))
        anim_set(&s->disc_yaw, deg_to_rad(v));
    else if (!strcmp(k, "r_in")) {
        s->disc_has_r_in = !isnan(v);
        anim_set(&s->disc_r_in, s->disc_has_r_in ? v : 0.0);
    } else if (!strcmp(k, "r_out"))
        anim_set(&s->disc_r_out, v);
    else if (!strcmp(k, "retrograde"))
        s->disc_retrograde = v != 0.0;
    else if (!strcmp(k, "temperature"))
        s->disc_temperature = v;
    else if (!strcmp(k, "mass_msun"))
        s->disc_mass_msun = isnan(v) ? 0.0 : v;
    else if (!strcmp(k, "mdot_edd"))
        s->disc_mdot_edd = isnan(v) ? 0.0 : v;
    else
        return -1;
    return 0;
}

/* A number-valued raytracer setting by key (settings.def). */
static int set_raytracer(cr_trace_settings *ts, const char *k, double v)
{
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *s = &cr_settings[i];
        if (strcmp(s->section, "raytracer") != 0 || strcmp(s->key, k) != 0 ||
            s->type == CR_SETTING_ENUM)
            continue;
        if (s->type == CR_SETTING_REAL)
            cr_setting_set_real(s, ts, v);
        else if (s->type == CR_SETTING_LONG) /* -1 (refused) for NaN or out of range */
            cr_setting_set_int(s, ts, v > -9e18 && v < 9e18 ? (long)v : -1);
        else
            cr_setting_set_int(s, ts, int_of(v));
        return 0;
    }
    return -1;
}

/* key = "section.name": the part after the dot when section matches. */
static const char *in_section(const char *key, const char *section)
{
    size_t n = strlen(section);
    return strncmp(key, section, n) == 0 && key[n] == '.' ? key + n + 1 : NULL;
}

int cr_web_set(cr_web *w, const char *key, double v)
{
    cr_scene *s = &w->scene;
    const char *k;
    int rc = -1;
    w->ready = 0;
    if ((k = in_section(key, "metric"))) {
        rc = 0;
        if (!strcmp(k, "m"))
            anim_set(&s->m, v);
        else if (!strcmp(k, "a"))
            anim_set(&s->a, v);
        else if (!strcmp(k, "q"))
            anim_set(&s->q, v);
        else
            rc = -1;
    } else if ((k = in_section(key, "observer")))
        rc = set_observer(s, k, v);
    else if ((k = in_section(key, "accretion")))
        rc = set_accretion(w, k, v);
    else if ((k = in_section(key, "sphere")))
        rc = set_sphere(w, k, v);
    else if ((k = in_section(key, "raytracer")))
        rc = set_raytracer(&w->ts, k, v);
    else if (!strcmp(key, "skymap.boundary")) {
        s->sky_at_infinity = isinf(v) && v > 0.0;
        anim_set(&s->sky_boundary, s->sky_at_infinity ? 0.0 : v);
        rc = 0;
    } else if (!strcmp(key, "sky_color") || !strcmp(key, "horizon_color") ||
               !strcmp(key, "error_color") || !strcmp(key, "limit_color")) {
        cr_rgb c = rgb_of(v);
        rc = 0;
        if (key[0] == 's')
            s->sky_color = c;
        else if (key[0] == 'h')
            s->horizon_color = c;
        else if (key[0] == 'e')
            s->error_color = c;
        else
            s->limit_color = c;
    } else if (!strcmp(key, "redshift_sky")) {
        s->redshift_sky = v != 0.0;
        rc = 0;
    }
    return rc ? fail(w, "unknown scene key", key) : 0;
}

int cr_web_set_word(cr_web *w, const char *key, const char *word)
{
    cr_scene *s = &w->scene;
    int i;
    w->ready = 0;
    if (!strcmp(key, "observer.motion")) {
        /* the words of the scene file (input/names.h); a velocity is a list there */
        if (!strcmp(word, "velocity"))
            i = CR_MOTION_VELOCITY;
        else if ((i = cr_name_parse(CR_NAMES_MOTION, word, strlen(word))) < 0)
            return fail(w, "unknown motion", word);
        s->obs_motion = i;
    } else if (!strcmp(key, "observer.projection")) {
        if ((i = cr_name_parse(CR_NAMES_PROJECTION, word, strlen(word))) < 0)
            return fail(w, "unknown projection", word);
        s->obs_projection = i;
    } else if (!strcmp(key, "accretion.model")) {
        if ((i = cr_name_parse(CR_NAMES_DISC_MODEL, word, strlen(word))) < 0)
            return fail(w, "unknown disc model", word);
        s->disc_model = i;
    } else if (!strcmp(key, "accretion.inside_isco")) {
        if ((i = cr_name_parse(CR_NAMES_INSIDE_ISCO, word, strlen(word))) < 0)
            return fail(w, "unknown value of accretion.inside_isco", word);
        s->disc_plunge = i;
    } else if (!strcmp(key, "name")) {
        size_t n = strlen(word);
        if (n + 1 > sizeof w->name)
            return fail(w, "name too long", word);
        memcpy(w->name, word, n + 1);
    } else if (!strcmp(key, "raytracer.integrator")) {
        if ((i = cr_integrator_parse(word, strlen(word))) < 0)
            return fail(w, "unknown integrator", word);
        w->ts.integrator = i;
    } else
        return fail(w, "unknown scene key", key);
    return 0;
}

uint8_t *cr_web_sky(cr_web *w, int width, int height)
{
    cr_scene *s = &w->scene;
    w->ready = 0;
    free(s->sky_rgb);
    s->sky_rgb = NULL;
    s->has_sky = 0;
    s->sky_width = s->sky_height = 0;
    if (width < 1 || height < 1 || (long)width * height > CR_WEB_MAX_SKY_PIXELS)
        return NULL;
    s->sky_rgb = malloc((size_t)width * (size_t)height * 3);
    if (!s->sky_rgb)
        return NULL;
    s->has_sky = 1;
    s->sky_width = width;
    s->sky_height = height;
    return s->sky_rgb;
}

void cr_web_clear_spheres(cr_web *w)
{
    w->ready = 0;
    w->scene.n_spheres = 0;
}

int cr_web_add_sphere(cr_web *w)
{
    cr_scene_sphere *sp;
    w->ready = 0;
    if (w->scene.n_spheres >= CR_WEB_MAX_SPHERES)
        return cr_err_set(&w->err, "at most %d spheres", CR_WEB_MAX_SPHERES);
    sp = &w->spheres[w->scene.n_spheres++];
    memset(sp, 0, sizeof *sp);
    sp->line = w->scene.n_spheres;
    return 0;
}

int cr_web_frame(cr_web *w, int width, int height)
{
    cr_scene *s = &w->scene;
    w->err.msg[0] = '\0';
    if (w->color2_default) /* (E.4.2) with ERRATA item 3, as the parser does */
        s->disc_color2 = cr_rgb_make(255 - s->disc_color1.r, 255 - s->disc_color1.g,
                                     255 - s->disc_color1.b);
    w->ready = cr_frame_eval_at(&w->eval, &w->scene, 0, 1, width, height, &w->ts, &w->err) == 0;
    return w->ready ? 0 : -1;
}

const char *cr_web_message(const cr_web *w)
{
    return w->err.msg;
}

int cr_web_width(const cr_web *w)
{
    return w->ready ? w->eval.frame.width : 0;
}

int cr_web_height(const cr_web *w)
{
    return w->ready ? w->eval.frame.height : 0;
}

int cr_web_trace(const cr_web *w, const int32_t *pix, int n, uint8_t *rgb, uint8_t *outcome,
                 double *val)
{
    const cr_frame *f = &w->eval.frame;
    int k;
    if (!w->ready)
        return 0;
    for (k = 0; k < n; k++) {
        int32_t p = pix[k];
        cr_pixel px;
        cr_pixel_values v;
        cr_rgb c[3];
        int m;
        if (p < 0 || p / f->width >= f->height)
            return 0;
        px = cr_trace_pixel(f, p % f->width, p / f->width);
        v = cr_pixel_csv_values(&px);
        c[0] = px.color;
        c[1] = w->scene.redshift_sky ? cr_redshift_sky_color(&px) : cr_redshift_color(&px);
        c[2] = cr_bolometric_color(&px);
        for (m = 0; m < 3; m++) {
            rgb[9 * k + 3 * m] = c[m].r;
            rgb[9 * k + 3 * m + 1] = c[m].g;
            rgb[9 * k + 3 * m + 2] = c[m].b;
        }
        outcome[k] = px.outcome;
        val[4 * k] = v.redshift;
        val[4 * k + 1] = v.hit_r;
        val[4 * k + 2] = v.hit_phi;
        val[4 * k + 3] = v.bolometric;
    }
    return n;
}

int cr_web_probe(const cr_web *w, double x, double y, double *out)
{
    const cr_frame *f = &w->eval.frame;
    cr_pixel px;
    cr_pixel_values v;
    if (!w->ready)
        return -1;
    px = cr_trace_point(f, x, y);
    v = cr_pixel_csv_values(&px);
    out[CR_WEB_PROBE_OUTCOME] = px.outcome;
    out[CR_WEB_PROBE_REDSHIFT] = v.redshift;
    out[CR_WEB_PROBE_HIT_R] = v.hit_r;
    out[CR_WEB_PROBE_HIT_PHI] = v.hit_phi;
    out[CR_WEB_PROBE_BOLO] = v.bolometric;
    out[CR_WEB_PROBE_STEPS] = px.steps;
    out[CR_WEB_PROBE_OBJECT] = px.object;
    out[CR_WEB_PROBE_E] = out[CR_WEB_PROBE_L] = out[CR_WEB_PROBE_CARTER] = NAN;
    if (px.outcome != CR_OUT_OUTSIDE) {
        if (f->obs_at_inf) {
            double alpha, beta, m[CR_MN];
            cr_mino c;
            cr_camera_screen(f, x, y, &alpha, &beta);
            cr_camera_ray_at_infinity(f, alpha, beta, &c, m);
            out[CR_WEB_PROBE_E] = c.E;
            out[CR_WEB_PROBE_L] = c.L;
            out[CR_WEB_PROBE_CARTER] = c.eta;
        } else {
            double n[3], yb[CR_NY];
            cr_geo g;
            cr_camera_pixel_dir(f, x, y, n);
            cr_camera_ray(f, n, &g, yb);
            out[CR_WEB_PROBE_E] = g.E;
            out[CR_WEB_PROBE_L] = g.L;
            out[CR_WEB_PROBE_CARTER] = cr_geo_carter(&g, yb);
        }
    }
    out[CR_WEB_PROBE_R_PLUS] = cr_metric_r_plus(&f->metric);
    return 0;
}

/* Where view pixel (i, j) is seen in the equirectangular sky frame fs, in
 * fractional sky pixels: 1, or 0 where the view shows nothing there. */
static int look_map(const cr_frame *fv, const cr_frame *fs, double i, double j, double *si,
                    double *sj)
{
    double n[3];
    if (!cr_camera_in_image(fv, i, j))
        return 0;
    cr_camera_pixel_dir(fv, i, j, n);
    return cr_camera_dir_pixel(fs, n, si, sj);
}

/* The sky's pixel nearest to (si, sj) (halves rounded up) into o, black
 * where ok is 0: azimuth wraps around (si within one turn of the image;
 * beyond that, column 0), the poles clamp. */
static void look_copy(const cr_frame *fs, const uint8_t *sky_rgba, int ok, double si, double sj,
                      uint8_t *o)
{
    long x, y;
    if (!ok) {
        o[0] = o[1] = o[2] = 0;
        o[3] = 255;
        return;
    }
    /* si > -width, so the truncation of si + 0.5 + width is its floor */
    x = si > -fs->width && si < 2.0 * fs->width ? (long)(si + 0.5 + fs->width) - fs->width : 0;
    x = x < 0 ? x + fs->width : (x >= fs->width ? x - fs->width : x);
    x = x < 0 ? 0 : (x >= fs->width ? fs->width - 1 : x);
    y = sj > 0.0 ? (sj < fs->height ? (long)(sj + 0.5) : fs->height - 1) : 0;
    y = y >= fs->height ? fs->height - 1 : y;
    sky_rgba += 4 * ((size_t)y * fs->width + x);
    o[0] = sky_rgba[0];
    o[1] = sky_rgba[1];
    o[2] = sky_rgba[2];
    o[3] = sky_rgba[3];
}

/* Cells of cell x cell view pixels (web.h): the camera mapping (look_map)
 * is evaluated at their corners and centre, and interpolated bilinearly
 * inside when the interpolated centre lies within CR_WEB_LOOK_TOL sky pixels
 * of the exact one (the mapping is smooth there: everywhere but near a pole
 * and a fisheye's rim); otherwise, or when a corner shows nothing, every
 * pixel of the cell is mapped exactly. cell = 1 maps every pixel exactly. */
#define CR_WEB_LOOK_TOL 0.1

int cr_web_reproject(const cr_web *view, const cr_web *sky, const uint8_t *sky_rgba,
                     uint8_t *out_rgba, int cell)
{
    const cr_frame *fv = &view->eval.frame, *fs = &sky->eval.frame;
    const int W = fv->width, H = fv->height;
    const int C = cell > 1 && W > 1 && H > 1 ? cell : 1;
    int gw, gh, gi, gj, i, j;
    double *node;
    if (!view->ready || !sky->ready || fs->observer.projection != CR_PROJ_EQUIRECT ||
        fv->obs_at_inf)
        return -1;
    if (C == 1) {
        for (j = 0; j < H; j++)
            for (i = 0; i < W; i++) {
                double si, sj;
                int ok = look_map(fv, fs, i, j, &si, &sj);
                look_copy(fs, sky_rgba, ok, si, sj, out_rgba + 4 * ((size_t)j * W + i));
            }
        return 0;
    }
    gw = (W - 1 + C - 1) / C + 1; /* nodes at 0, C, 2C, ..., and W - 1 */
    gh = (H - 1 + C - 1) / C + 1;
    node = malloc(sizeof *node * 3 * (size_t)gw * (size_t)gh);
    if (!node)
        return -1;
    for (gj = 0; gj < gh; gj++)
        for (gi = 0; gi < gw; gi++) {
            double *q = node + 3 * ((size_t)gj * gw + gi);
            int x = gi * C < W ? gi * C : W - 1, y = gj * C < H ? gj * C : H - 1;
            q[2] = look_map(fv, fs, x, y, &q[0], &q[1]);
        }
    for (gj = 0; gj + 1 < gh; gj++)
        for (gi = 0; gi + 1 < gw; gi++) {
            const double *q00 = node + 3 * ((size_t)gj * gw + gi), *q10 = q00 + 3,
                         *q01 = q00 + 3 * (size_t)gw, *q11 = q01 + 3;
            int x0 = gi * C, y0 = gj * C;
            int x1 = x0 + C < W ? x0 + C : W - 1, y1 = y0 + C < H ? y0 + C : H - 1;
            /* the corners' azimuth unwrapped to the first corner's */
            double u[4] = {q00[0], q10[0], q01[0], q11[0]};
            double half = 0.5 * fs->width, ci, cj;
            int k, exact = !(q00[2] && q10[2] && q01[2] && q11[2]);
            for (k = 1; k < 4 && !exact; k++)
                u[k] += u[k] - u[0] > half ? -fs->width : (u[0] - u[k] > half ? fs->width : 0);
            if (!exact) {
                double mi = 0.5 * (x0 + x1), mj = 0.5 * (y0 + y1);
                double bi = 0.25 * (u[0] + u[1] + u[2] + u[3]);
                double bj = 0.25 * (q00[1] + q10[1] + q01[1] + q11[1]);
                exact = !look_map(fv, fs, mi, mj, &ci, &cj);
                if (!exact) {
                    double d = ci - bi;
                    d -= fs->width * floor(d / fs->width + 0.5); /* azimuth difference */
                    exact = !(fabs(d) <= CR_WEB_LOOK_TOL && fabs(cj - bj) <= CR_WEB_LOOK_TOL);
                }
            }
            /* the cell's pixels [x0, x1) x [y0, y1), plus the last column and row */
            for (j = y0; j < (y1 == H - 1 ? H : y1); j++) {
                double fy = y1 > y0 ? (double)(j - y0) / (y1 - y0) : 0.0;
                double li = (1 - fy) * u[0] + fy * u[2], lj = (1 - fy) * q00[1] + fy * q01[1];
                double di = (1 - fy) * u[1] + fy * u[3] - li;
                double dj = (1 - fy) * q10[1] + fy * q11[1] - lj;
                double inv = x1 > x0 ? 1.0 / (x1 - x0) : 0.0;
                for (i = x0; i < (x1 == W - 1 ? W : x1); i++) {
                    uint8_t *o = out_rgba + 4 * ((size_t)j * W + i);
                    double si, sj, fx = (i - x0) * inv;
                    int ok = 1;
                    if (exact) {
                        ok = look_map(fv, fs, i, j, &si, &sj);
                    } else {
                        si = li + fx * di;
                        sj = lj + fx * dj;
                    }
                    look_copy(fs, sky_rgba, ok, si, sj, o);
                }
            }
        }
    free(node);
    return 0;
}
