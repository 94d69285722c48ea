/* curray io: per-frame output files and info.txt (output.h). */
#include "output.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fsutil.h"
#include "png_io.h"

#ifndef CURRAY_VERSION
#define CURRAY_VERSION "unknown"
#endif

/* stdio buffer for the large outputs (CSV): 1 MiB keeps write() calls few. */
#define CR_OUT_BUFSIZE (1u << 20)

static const char *const cr_outcome_names[CR_OUT_COUNT_] = {
    "none", "horizon", "disc", "sphere", "sky", "error", "limit",
};

const char *cr_outcome_name(int outcome)
{
    if (outcome < 0 || outcome >= CR_OUT_COUNT_)
        return "unknown";
    return cr_outcome_names[outcome];
}

/* 0..255, rounded to nearest (halves away from zero). */
static uint8_t cr_to_byte(double v)
{
    if (!(v > 0.0))
        return 0;
    if (v >= 255.0)
        return 255;
    return (uint8_t)lround(v);
}

/* (6.9.1) with z = omega_r / omega_s >= 0 (z = +inf allowed: pure blue).
 * The horizon is taken as z = 0 whatever the pixel stores: light from it is
 * infinitely redshifted. A negative ratio (-1: source inside the ergosphere)
 * on a disc or sphere is green; a NaN ratio there is black like every pixel
 * without a source (sky, error, limit, none). */
cr_rgb cr_redshift_color(const cr_pixel *p)
{
    cr_rgb c = {0, 0, 0};
    double z, b;

    switch (p->outcome) {
    case CR_OUT_HORIZON:
        z = 0.0;
        break;
    case CR_OUT_DISC:
    case CR_OUT_SPHERE:
        z = p->redshift;
        if (z != z)
            return c;
        if (z < 0.0) {
            c.g = 255;
            return c;
        }
        break;
    default:
        return c;
    }
    b = 255.0 * atan(z) * (2.0 / CR_PI);
    c.r = cr_to_byte(255.0 - b);
    c.b = cr_to_byte(b);
    return c;
}

static int cr_frame_path(char *out, size_t n, const char *dir, const char *prefix, int k,
                         const char *ext, cr_err *err)
{
    char name[64];
    snprintf(name, sizeof name, "%s_%d.%s", prefix, k, ext);
    if (cr_path_join(out, n, dir, name) != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    return 0;
}

static int cr_check_frame(const cr_pixel *px, int w, int h, cr_err *err)
{
    if (!px || w <= 0 || h <= 0 || (long long)w * h > 0x7fffffffLL / 3)
        return cr_err_set(err, "cannot write a frame of %d x %d pixels", w, h);
    return 0;
}

/* Shared by the c_ and r_ PNGs: colour each pixel, write the file. */
static int cr_output_png(const char *dir, const char *prefix, int k, const cr_pixel *px, int w,
                         int h, int redshift, cr_err *err)
{
    char path[4096];
    size_t n;
    uint8_t *rgb;
    int rc;

    if (cr_check_frame(px, w, h, err) != 0 ||
        cr_frame_path(path, sizeof path, dir, prefix, k, "png", err) != 0)
        return -1;
    n = (size_t)w * (size_t)h;
    rgb = malloc(n * 3);
    if (!rgb)
        return cr_err_set(err, "writing %s: out of memory", path);
    for (size_t i = 0; i < n; i++) {
        cr_rgb c = redshift ? cr_redshift_color(&px[i]) : px[i].color;
        rgb[3 * i] = c.r;
        rgb[3 * i + 1] = c.g;
        rgb[3 * i + 2] = c.b;
    }
    rc = cr_png_write(path, w, h, rgb, err);
    free(rgb);
    return rc;
}

int cr_output_color_png(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err)
{
    return cr_output_png(dir, "c", k, px, w, h, 0, err);
}

int cr_output_redshift_png(const char *dir, int k, const cr_pixel *px, int w, int h,
                           cr_err *err)
{
    return cr_output_png(dir, "r", k, px, w, h, 1, err);
}

/* Decimal digits of v at p; returns the end. */
static char *cr_put_uint(char *p, unsigned long v)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        *p++ = tmp[--n];
    return p;
}

/* "%.17g": enough digits that strtod/sscanf gives back the same double. */
static char *cr_put_double(char *p, double v)
{
    /* fast paths, same text as %.17g: the "undefined" marker and zero */
    if (v == -1.0) {
        memcpy(p, "-1", 2);
        return p + 2;
    }
    if (v == 0.0 && !signbit(v)) {
        *p = '0';
        return p + 1;
    }
    return p + snprintf(p, 32, "%.17g", v);
}

static const char *const cr_csv_header = "x,y,r,g,b,steps,redshift,err_mean,err_std,outcome\n";

int cr_output_csv_stream(FILE *fp, const char *name, const cr_pixel *px, int w, int h,
                         cr_err *err)
{
    char line[256];

    if (cr_check_frame(px, w, h, err) != 0)
        return -1;
    fputs(cr_csv_header, fp);
    for (int y = 0; y < h && !ferror(fp); y++) {
        for (int x = 0; x < w; x++) {
            const cr_pixel *q = &px[(size_t)y * w + x];
            /* The ratio is meaningless where no source was reached. */
            int undefined = q->outcome == CR_OUT_NONE || q->outcome == CR_OUT_ERROR ||
                            q->outcome == CR_OUT_LIMIT || q->redshift != q->redshift;
            char *p = line;
            p = cr_put_uint(p, (unsigned long)x);
            *p++ = ',';
            p = cr_put_uint(p, (unsigned long)y);
            *p++ = ',';
            p = cr_put_uint(p, q->color.r);
            *p++ = ',';
            p = cr_put_uint(p, q->color.g);
            *p++ = ',';
            p = cr_put_uint(p, q->color.b);
            *p++ = ',';
            p = cr_put_uint(p, q->steps);
            *p++ = ',';
            p = cr_put_double(p, undefined ? -1.0 : q->redshift);
            *p++ = ',';
            p = cr_put_double(p, q->err_mean);
            *p++ = ',';
            p = cr_put_double(p, q->err_std);
            *p++ = ',';
            const char *o = cr_outcome_name(q->outcome);
            size_t ol = strlen(o);
            memcpy(p, o, ol);
            p += ol;
            *p++ = '\n';
            fwrite(line, 1, (size_t)(p - line), fp);
        }
    }
    return cr_stream_check(fp, name, err);
}

int cr_output_csv(const char *dir, int k, const cr_pixel *px, int w, int h, cr_err *err)
{
    char path[4096];
    cr_atomic a;
    char *buf;
    int rc;

    if (cr_check_frame(px, w, h, err) != 0 ||
        cr_frame_path(path, sizeof path, dir, "d", k, "csv", err) != 0)
        return -1;
    if (cr_atomic_open(&a, path, err) != 0)
        return -1;
    buf = malloc(CR_OUT_BUFSIZE); /* without it stdio's default buffer still works */
    if (buf)
        setvbuf(a.fp, buf, _IOFBF, CR_OUT_BUFSIZE);
    rc = cr_output_csv_stream(a.fp, path, px, w, h, err);
    if (rc == 0)
        rc = cr_atomic_commit(&a, err); /* closes the stream, also on failure */
    else
        cr_atomic_abort(&a);
    free(buf);
    return rc;
}

void cr_frame_stats_compute(const cr_pixel *px, long long n, double seconds,
                            cr_frame_stats *st)
{
    double err_sum = 0.0;
    long long err_n = 0;

    memset(st, 0, sizeof *st);
    st->seconds = seconds;
    for (long long i = 0; i < n; i++) {
        const cr_pixel *p = &px[i];
        int o = p->outcome < CR_OUT_COUNT_ ? p->outcome : CR_OUT_ERROR;
        st->counts[o]++;
        if (o == CR_OUT_NONE)
            continue; /* not traced */
        st->rays++;
        st->steps += p->steps;
        if (p->steps > st->max_steps_ray)
            st->max_steps_ray = p->steps;
        if (cr_isfinite(p->err_mean)) { /* a failed ray may carry NaN */
            double e = fabs(p->err_mean);
            err_sum += e;
            err_n++;
            if (e > st->err_max)
                st->err_max = e;
        }
    }
    st->err_mean = err_n ? err_sum / (double)err_n : 0.0;
}

/* --- info.txt ----------------------------------------------------------- */

#define CR_DEG (180.0 / CR_PI)

/* A length or plain number, "a" or "a -> b" when animated. */
static void cr_put_anim(FILE *fp, const char *label, cr_anim v, const char *unit)
{
    fprintf(fp, "  %-22s %.10g", label, v.a);
    if (v.b != v.a)
        fprintf(fp, " -> %.10g", v.b);
    fprintf(fp, "%s%s\n", unit[0] ? " " : "", unit);
}

/* An angle stored in radians, shown in degrees. */
static void cr_put_angle(FILE *fp, const char *label, cr_anim v)
{
    cr_anim d = {v.a * CR_DEG, v.b * CR_DEG};
    cr_put_anim(fp, label, d, "deg");
}

static void cr_put_rgb(FILE *fp, const char *label, cr_rgb c)
{
    fprintf(fp, "  %-22s [%u, %u, %u]\n", label, c.r, c.g, c.b);
}

static void cr_info_scene(FILE *fp, const cr_scene *s)
{
    fprintf(fp, "Scene\n");
    fprintf(fp, "  %-22s %s\n", "file", s->path ? s->path : "(from memory)");
    fprintf(fp, "Metric (geometrized units)\n");
    cr_put_anim(fp, "mass M", s->m, "");
    cr_put_anim(fp, "spin a = J/M", s->a, "");
    cr_put_anim(fp, "charge Q", s->q, "");
    fprintf(fp, "Observer (Boyer-Lindquist)\n");
    if (s->obs_at_infinity)
        fprintf(fp, "  %-22s inf (the observer at infinity)\n", "r");
    else
        cr_put_anim(fp, "r", s->obs_r, "");
    cr_put_angle(fp, "theta", s->obs_theta);
    cr_put_angle(fp, "phi", s->obs_phi);
    cr_put_angle(fp, "roll", s->roll);
    cr_put_angle(fp, "pitch", s->pitch);
    cr_put_angle(fp, "yaw", s->yaw);
    if (s->obs_at_infinity) {
        cr_put_anim(fp, "image plane width", s->hextent, "M");
        if (s->has_vextent)
            cr_put_anim(fp, "image plane height", s->vextent, "M");
        else
            fprintf(fp, "  %-22s from the width and the aspect ratio\n", "image plane height");
    } else {
        cr_put_angle(fp, "horizontal fov", s->hfov);
        if (s->has_vfov)
            cr_put_angle(fp, "vertical fov", s->vfov);
        else
            fprintf(fp, "  %-22s from the horizontal fov and the aspect ratio (E.4.1)\n",
                    "vertical fov");
    }

    fprintf(fp, "Accretion disc\n");
    if (!s->has_disc) {
        fprintf(fp, "  none\n");
    } else {
        cr_put_rgb(fp, "colour 1 (top)", s->disc_color1);
        cr_put_rgb(fp, "colour 2 (bottom)", s->disc_color2);
        fprintf(fp, "  %-22s %d\n", "radial rings", s->disc_n_radial);
        fprintf(fp, "  %-22s %d\n", "sectors", s->disc_n_sectors);
        cr_put_angle(fp, "yaw", s->disc_yaw);
        cr_put_anim(fp, "inner radius", s->disc_r_in, "");
        cr_put_anim(fp, "outer radius", s->disc_r_out, "");
    }

    fprintf(fp, "Sky\n");
    if (!s->has_sky) {
        fprintf(fp, "  no sky image\n");
    } else {
        fprintf(fp, "  %-22s %s\n", "image", s->sky_image ? s->sky_image : "(none)");
        fprintf(fp, "  %-22s %d x %d pixels\n", "image size", s->sky_width, s->sky_height);
        if (s->sky_at_infinity)
            fprintf(fp, "  %-22s inf (the sky at infinity)\n", "boundary R");
        else
            cr_put_anim(fp, "boundary R", s->sky_boundary, "");
    }

    fprintf(fp, "Spheres: %d\n", s->n_spheres);
    for (int i = 0; i < s->n_spheres; i++) {
        const cr_scene_sphere *sp = &s->spheres[i];
        fprintf(fp, "Sphere %d (line %d)\n", i, sp->line);
        cr_put_rgb(fp, "colour", sp->color);
        fprintf(fp, "  %-22s %d\n", "latitude bands", sp->n_lat);
        fprintf(fp, "  %-22s %d\n", "longitude sectors", sp->n_lon);
        cr_put_anim(fp, "r", sp->r, "");
        cr_put_angle(fp, "theta", sp->theta);
        cr_put_angle(fp, "phi", sp->phi);
        cr_put_angle(fp, "roll", sp->roll);
        cr_put_angle(fp, "pitch", sp->pitch);
        cr_put_angle(fp, "yaw", sp->yaw);
        cr_put_anim(fp, "radius", sp->radius, "");
    }

    fprintf(fp, "Colours\n");
    cr_put_rgb(fp, "sky", s->sky_color);
    cr_put_rgb(fp, "horizon", s->horizon_color);
    cr_put_rgb(fp, "error", s->error_color);
}

static const char *cr_yes_no(int v)
{
    return v ? "yes" : "no";
}

static void cr_info_config(FILE *fp, const cr_sysconfig *c)
{
    int any = 0;
    fprintf(fp, "System configuration\n");
    fprintf(fp, "  %-22s", "GPUs enabled");
    for (int i = 0; i < CR_MAX_GPUS; i++) {
        if (c->gpu_enabled[i]) {
            fprintf(fp, "%s%d", any ? ", " : " ", i);
            any = 1;
        }
    }
    fprintf(fp, "%s\n", any ? "" : " none");
    if (c->cpu_threads > 0)
        fprintf(fp, "  %-22s %d\n", "CPU threads", c->cpu_threads);
    else
        fprintf(fp, "  %-22s all online cores\n", "CPU threads");
    fprintf(fp, "  %-22s %.10g\n", "horizon epsilon", c->horizon_epsilon);
    fprintf(fp, "  %-22s %s\n", "integrator", cr_integrator_name(c->integrator));
    fprintf(fp, "  %-22s %.10g%s\n", "tolerance", c->tolerance,
            c->integrator == CR_INTEG_MINO ? "" : " (mino only, unused)");
    fprintf(fp, "  %-22s %.10g%s\n", "step multiplier", c->step_multiplier,
            c->integrator == CR_INTEG_RK4 ? "" : " (rk4 only, unused)");
    fprintf(fp, "  %-22s %ld\n", "max steps per ray", c->max_steps);
    fprintf(fp, "  %-22s %.10g\n", "max turns per ray", c->max_turns);
    fprintf(fp, "  %-22s %s\n", "verbose", cr_yes_no(c->verbose));
    fprintf(fp, "  %-22s %s\n", "quiet", cr_yes_no(c->quiet));
    fprintf(fp, "  %-22s %s\n", "keep log", cr_yes_no(c->keep_log));
    fprintf(fp, "  %-22s %s\n", "auto accept", cr_yes_no(c->auto_accept));
}

static void cr_info_frame(FILE *fp, int k, const cr_frame_stats *st)
{
    double per_ray = st->rays ? (double)st->steps / (double)st->rays : 0.0;
    fprintf(fp, "Frame %d\n", k);
    fprintf(fp, "  %-22s %.3f s\n", "wall time", st->seconds);
    fprintf(fp, "  %-22s %lld\n", "rays", st->rays);
    fprintf(fp, "  %-22s %llu\n", "RK4 steps", st->steps);
    fprintf(fp, "  %-22s %.1f (max %u)\n", "steps per ray", per_ray, st->max_steps_ray);
    if (st->seconds > 0.0)
        fprintf(fp, "  %-22s %.0f\n", "rays per second", (double)st->rays / st->seconds);
    else
        fprintf(fp, "  %-22s n/a\n", "rays per second");
    fprintf(fp, "  %-22s mean %.3e, max %.3e\n", "null error", st->err_mean, st->err_max);
    fprintf(fp, "  %-22s", "pixels");
    for (int o = CR_OUT_HORIZON; o < CR_OUT_COUNT_; o++)
        fprintf(fp, " %s %lld%s", cr_outcome_name(o), st->counts[o],
                o + 1 < CR_OUT_COUNT_ ? "," : "");
    if (st->counts[CR_OUT_NONE])
        fprintf(fp, ", not traced %lld", st->counts[CR_OUT_NONE]);
    fprintf(fp, "\n");
}

int cr_info_write(const char *dir, const cr_run_info *run, const cr_scene *scene,
                  const cr_sysconfig *cfg, const cr_frame_stats *stats, int n_done,
                  cr_err *err)
{
    char path[4096], when[64];
    cr_atomic a;
    time_t now = time(NULL);
    struct tm tm;
    FILE *fp;

    if (cr_path_join(path, sizeof path, dir, "info.txt") != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    if (localtime_r(&now, &tm) == NULL || strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %z", &tm) == 0)
        snprintf(when, sizeof when, "unknown");
    if (cr_atomic_open(&a, path, err) != 0)
        return -1;
    fp = a.fp;

    fprintf(fp, "curray %s - relativistic raytracer, run summary\n",
            run && run->version ? run->version : CURRAY_VERSION);
    fprintf(fp, "Written                  %s\n\n", when);
    if (run) {
        fprintf(fp, "Run\n");
        fprintf(fp, "  %-22s %s\n", "scene file", run->scene_path ? run->scene_path : "(none)");
        fprintf(fp, "  %-22s %s\n", "configuration file",
                run->config_path ? run->config_path : "(built-in defaults)");
        fprintf(fp, "  %-22s %s\n", "backend", run->backend ? run->backend : "(unknown)");
        fprintf(fp, "  %-22s %d x %d pixels\n", "frame size", run->width, run->height);
        fprintf(fp, "  %-22s %d\n", "frames", run->frames);
        fprintf(fp, "  %-22s %s\n", "output types", run->output_types ? run->output_types : "");
        fprintf(fp, "\n");
    }
    if (scene) {
        cr_info_scene(fp, scene);
        fprintf(fp, "\n");
    }
    if (cfg) {
        cr_info_config(fp, cfg);
        fprintf(fp, "\n");
    }
    for (int k = 0; stats && k < n_done; k++) {
        cr_info_frame(fp, stats[k].frame, &stats[k]);
        fprintf(fp, "\n");
    }
    if (run)
        fprintf(fp, "Finished %d of %d frames%s\n", n_done, run->frames,
                n_done < run->frames ? " (run incomplete)" : "");
    else
        fprintf(fp, "Finished %d frames\n", n_done);
    return cr_atomic_commit(&a, err);
}
