/* curray io: info.txt and frame statistics (info.h). */
#include "info.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../core/orbit.h" /* cr_orbit_eval */
#include "../base/atomic.h"
#include "../base/fsutil.h"

#ifndef CURRAY_VERSION
#define CURRAY_VERSION "unknown"
#endif

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
        if (o == CR_OUT_NONE || o == CR_OUT_OUTSIDE)
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

/* "x M (y)" for a radius x in units of M at the scene's start and end:
 * y = x M in the scene's units. */
static void cr_put_radius_m(FILE *fp, const char *label, const double x[2], const double m[2])
{
    fprintf(fp, "  %-22s %.10g", label, x[0]);
    if (x[1] != x[0])
        fprintf(fp, " -> %.10g", x[1]);
    fprintf(fp, " M (%.10g", x[0] * m[0]);
    if (x[1] * m[1] != x[0] * m[0])
        fprintf(fp, " -> %.10g", x[1] * m[1]);
    fprintf(fp, " in the scene's units)\n");
}

/* The Keplerian disc: model, orbit sense, the ISCO of that sense and the
 * effective inner edge max(inner radius, r_isco), both at the run's first
 * and last frame (ends[0], ends[1]: the frames as traced, units of M, with
 * m[] the scene's M at each), what lies inside the ISCO, and the peak
 * temperature: as given, or as the frames derived it from the mass and
 * accretion rate, with the radiative efficiency 1 - E(r_in). Without frames
 * (ends NULL) the lines derived per frame are left out. */
static void cr_info_keplerian(FILE *fp, const cr_scene *s, const cr_frame *const *ends,
                              const double m[2])
{
    double isco[2], rin[2], tpk[2] = {NAN, NAN}, eta[2] = {NAN, NAN};
    int sense = ends ? ends[1]->disc.sense : 0;
    for (int i = 0; ends && i < 2; i++) {
        const cr_disc *d = &ends[i]->disc;
        cr_orbit o;
        isco[i] = d->r_isco;
        rin[i] = d->r_in;
        if (s->disc_mass_msun > 0.0 && cr_orbit_eval(&ends[i]->metric, d->sense, d->r_in, &o)) {
            tpk[i] = d->t_peak;
            eta[i] = 1.0 - o.E;
        }
    }
    fprintf(fp, "  %-22s keplerian\n", "model");
    if (ends)
        fprintf(fp, "  %-22s %s (%s)\n", "orbit sense",
                s->disc_retrograde ? "retrograde" : "prograde",
                sense > 0 ? "counter-clockwise about +z" : "clockwise about +z");
    else
        fprintf(fp, "  %-22s %s\n", "orbit sense", s->disc_retrograde ? "retrograde" : "prograde");
    if (s->disc_has_r_in)
        cr_put_anim(fp, "inner radius", s->disc_r_in, "");
    else
        fprintf(fp, "  %-22s the ISCO\n", "inner radius");
    cr_put_anim(fp, "outer radius", s->disc_r_out, "");
    if (ends) {
        cr_put_radius_m(fp, "r_isco", isco, m);
        cr_put_radius_m(fp, "effective inner radius", rin, m);
    }
    fprintf(fp, "  %-22s %s\n", "inside the ISCO",
            s->disc_plunge ? "plunging (falling with the ISCO's E and L; dark)" : "nothing");
    if (s->disc_exposure_auto)
        fprintf(fp, "  %-22s auto: %.10g (frame 0 traced %d pixels across: the %gth "
                    "percentile of its lit disc pixels' luminance at %g of white)\n",
                "exposure", s->disc_exposure_found, CR_AUTO_EXPOSURE_WIDTH,
                CR_AUTO_EXPOSURE_PERCENTILE, CR_AUTO_EXPOSURE_LEVEL);
    else
        cr_put_anim(fp, "exposure", s->disc_exposure, "");
    if (!(s->disc_mass_msun > 0.0)) {
        fprintf(fp, "  %-22s %.10g K\n", "peak temperature", s->disc_temperature);
        return;
    }
    fprintf(fp, "  %-22s %.10g solar masses\n", "mass", s->disc_mass_msun);
    fprintf(fp, "  %-22s %.10g Eddington\n", "accretion rate", s->disc_mdot_edd);
    if (!ends)
        return;
    fprintf(fp, "  %-22s %.6g", "efficiency 1 - E(r_in)", eta[0]);
    if (eta[1] != eta[0])
        fprintf(fp, " -> %.6g", eta[1]);
    fprintf(fp, "\n  %-22s %.6g", "peak temperature", tpk[0]);
    if (tpk[1] != tpk[0])
        fprintf(fp, " -> %.6g", tpk[1]);
    fprintf(fp, " K (from the mass and accretion rate)\n");
}

static void cr_info_scene(FILE *fp, const cr_scene *s, const cr_run_info *run)
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
    if (s->obs_motion == CR_MOTION_VELOCITY) {
        cr_put_anim(fp, "velocity v_r (ZAMO)", s->obs_v[0], "c");
        cr_put_anim(fp, "velocity v_theta", s->obs_v[1], "c");
        cr_put_anim(fp, "velocity v_phi", s->obs_v[2], "c");
    } else if (s->obs_motion != CR_MOTION_STATIC) {
        fprintf(fp, "  %-22s %s%s\n", "motion", cr_name(CR_NAMES_MOTION, s->obs_motion),
                s->obs_motion == CR_MOTION_ORBIT
                    ? (s->obs_retrograde ? " (retrograde)" : " (prograde)")
                    : "");
    }
    if (s->obs_at_infinity) {
        cr_put_anim(fp, "image plane width", s->hextent, "M");
        if (s->has_vextent)
            cr_put_anim(fp, "image plane height", s->vextent, "M");
        else
            fprintf(fp, "  %-22s from the width and the aspect ratio\n", "image plane height");
    } else if (s->obs_projection == CR_PROJ_EQUIRECT) {
        fprintf(fp, "  %-22s equirectangular, 360 x 180 deg\n", "projection");
    } else {
        if (s->obs_projection == CR_PROJ_FISHEYE)
            fprintf(fp, "  %-22s fisheye (equidistant)\n", "projection");
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
    } else if (s->disc_model == CR_DISC_KEPLERIAN) {
        const cr_frame *ends[2] = {run ? run->first : NULL, run ? run->last : NULL};
        int n = run && run->frames > 0 ? run->frames : 1;
        double m[2] = {cr_anim_at(s->m, 0, n), cr_anim_at(s->m, n - 1, n)};
        cr_info_keplerian(fp, s, ends[0] && ends[1] ? ends : NULL, m);
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
    if (s->redshift_sky)
        fprintf(fp, "  %-22s %s\n", "sky in redshift image", "coloured by its shift");
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
    for (int i = 0; i < cr_settings_count; i++) {
        const cr_setting *st = cr_setting_in_order(CR_SETTING_INFO_ORDER, i);
        char v[128];
        if (!st)
            continue;
        cr_setting_format(st, &c->raytracer, v, sizeof v);
        fprintf(fp, "  %-22s %s\n", st->label, v);
    }
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
    fprintf(fp, "  %-22s %llu\n", "integrator steps", st->steps);
    fprintf(fp, "  %-22s %.1f (max %u)\n", "steps per ray", per_ray, st->max_steps_ray);
    if (st->seconds > 0.0)
        fprintf(fp, "  %-22s %.0f\n", "rays per second", (double)st->rays / st->seconds);
    else
        fprintf(fp, "  %-22s n/a\n", "rays per second");
    fprintf(fp, "  %-22s mean %.3e, max %.3e\n", "error monitor", st->err_mean, st->err_max);
    fprintf(fp, "  %-22s", "pixels");
    for (int o = CR_OUT_HORIZON; o <= CR_OUT_LIMIT; o++)
        fprintf(fp, " %s %lld%s", cr_outcome_name(o), st->counts[o], o < CR_OUT_LIMIT ? "," : "");
    if (st->counts[CR_OUT_OTHER_SIDE]) /* only from inside the horizon */
        fprintf(fp, ", other side %lld", st->counts[CR_OUT_OTHER_SIDE]);
    if (st->counts[CR_OUT_SINGULARITY]) /* only from inside r- */
        fprintf(fp, ", singularity %lld", st->counts[CR_OUT_SINGULARITY]);
    if (st->counts[CR_OUT_OUTSIDE]) /* only fisheye images have such pixels */
        fprintf(fp, ", outside the image %lld", st->counts[CR_OUT_OUTSIDE]);
    if (st->counts[CR_OUT_NONE])
        fprintf(fp, ", not traced %lld", st->counts[CR_OUT_NONE]);
    fprintf(fp, "\n");
    if (st->counts[CR_OUT_ERROR] > 0)
        fprintf(fp, "  %-22s %lld of %lld rays %s\n", "warning", st->counts[CR_OUT_ERROR],
                st->rays, CR_INFO_ERROR_ADVICE);
    if (st->counts[CR_OUT_LIMIT] > 0)
        fprintf(fp, "  %-22s %lld rays: %s\n", "warning", st->counts[CR_OUT_LIMIT],
                CR_INFO_LIMIT_ADVICE);
    if (st->files)
        fputs(st->files, fp);
}

/* The header: everything before the first frame record. */
static void cr_info_header(FILE *fp, const cr_run_info *run, const cr_scene *scene,
                           const cr_sysconfig *cfg)
{
    char when[64];
    time_t now = time(NULL);
    struct tm tm;

    if (localtime_r(&now, &tm) == NULL ||
        strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %z", &tm) == 0)
        snprintf(when, sizeof when, "unknown");
    fprintf(fp, "curray %s - relativistic raytracer, run summary\n",
            run && run->version ? run->version : CURRAY_VERSION);
    if (run && run->started) {
        fprintf(fp, "Started                  %s\n", run->started);
        fprintf(fp, "Resumed                  %s\n\n", when);
    } else {
        fprintf(fp, "Started                  %s\n\n", when);
    }
    if (run) {
        fprintf(fp, "Run\n");
        fprintf(fp, "  %-22s %s\n", "scene file", run->scene_path ? run->scene_path : "(none)");
        fprintf(fp, "  %-22s %s\n", "configuration file",
                run->config_path ? run->config_path : "(built-in defaults)");
        fprintf(fp, "  %-22s %s\n", "backend", run->backend ? run->backend : "(unknown)");
        fprintf(fp, "  %-22s %d x %d pixels\n", "frame size", run->width, run->height);
        fprintf(fp, "  %-22s %d\n", "frames", run->frames);
        if (run->frames == 1 && scene && cr_scene_animated(scene))
            fprintf(fp, "  %-22s %s\n", "animation", CR_INFO_ONE_FRAME_OF_ANIMATION);
        fprintf(fp, "  %-22s %s\n", "output types", run->output_types ? run->output_types : "");
        if (run->hash)
            fprintf(fp, "  %-22s %s\n", "run hash", run->hash);
        if (run->stale)
            fprintf(fp, "  %-22s %s (from an earlier run; not overwritten, not deleted)\n",
                    "stale files", run->stale);
        fprintf(fp, "\n");
    }
    if (scene) {
        cr_info_scene(fp, scene, run);
        fprintf(fp, "\n");
    }
    if (cfg) {
        cr_info_config(fp, cfg);
        fprintf(fp, "\n");
    }
}

/* One frame's record: its statistics, then how far the run got once it
 * finished (n_done frames of frames; frames 0: not known), then a blank
 * line. */
static void cr_info_finished(FILE *fp, int n_done, int frames)
{
    if (frames > 0)
        fprintf(fp, "Finished %d of %d frames%s\n", n_done, frames,
                n_done < frames ? " (run incomplete)" : "");
    else
        fprintf(fp, "Finished %d frames\n", n_done);
    fprintf(fp, "\n");
}

static void cr_info_record(FILE *fp, const cr_frame_stats *st, int n_done, int frames)
{
    cr_info_frame(fp, st->frame, st);
    cr_info_finished(fp, n_done, frames);
}

/* Finish a text made with open_memstream: 0, or -1 (the text freed and NULL)
 * when the stream failed, which only lack of memory makes it do. */
static int cr_text_close(FILE *fp, char **text, cr_err *err)
{
    int bad = ferror(fp);
    if (fclose(fp) != 0 || bad) {
        free(*text);
        *text = NULL;
        return cr_err_set(err, "info.txt: out of memory");
    }
    return 0;
}

int cr_info_begin(cr_info *info, const char *dir, const cr_run_info *run,
                  const cr_scene *scene, const cr_sysconfig *cfg, cr_err *err)
{
    FILE *fp;

    memset(info, 0, sizeof *info);
    cr_appender_init(&info->file);
    info->frames = run ? run->frames : 0;
    if (cr_path_join(info->path, sizeof info->path, dir, "info.txt") != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    fp = open_memstream(&info->header, &info->header_len);
    if (!fp)
        return cr_err_set(err, "info.txt: out of memory");
    cr_info_header(fp, run, scene, cfg);
    return cr_text_close(fp, &info->header, err);
}

int cr_info_add_frame(cr_info *info, const cr_frame_stats *st, cr_err *err)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp;
    int rc;

    if (!info->header)
        return cr_err_set(err, "writing %s: info.txt was not begun", info->path);
    fp = open_memstream(&text, &len);
    if (!fp)
        return cr_err_set(err, "info.txt: out of memory");
    if (info->file.fd < 0) /* the first record: header and record appear together */
        fwrite(info->header, 1, info->header_len, fp);
    cr_info_record(fp, st, info->n_done + 1, info->frames);
    if (cr_text_close(fp, &text, err) != 0)
        return -1;
    if (info->file.fd >= 0)
        rc = cr_appender_add(&info->file, text, len, err);
    else
        rc = cr_appender_create(&info->file, info->path, text, len, err);
    free(text);
    if (rc == 0)
        info->n_done++;
    return rc;
}

int cr_info_resume(cr_info *info, char *const *bodies, const int *order, int n, cr_err *err)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp;
    int rc;

    if (n <= 0)
        return 0;
    if (!info->header)
        return cr_err_set(err, "writing %s: info.txt was not begun", info->path);
    if (info->file.fd >= 0)
        return 0;
    fp = open_memstream(&text, &len);
    if (!fp)
        return cr_err_set(err, "info.txt: out of memory");
    fwrite(info->header, 1, info->header_len, fp);
    for (int i = 0; i < n; i++) {
        fputs(bodies[order[i]], fp);
        cr_info_finished(fp, i + 1, info->frames);
    }
    if (cr_text_close(fp, &text, err) != 0)
        return -1;
    rc = cr_appender_create(&info->file, info->path, text, len, err);
    free(text);
    if (rc == 0)
        info->n_done = n;
    return rc;
}

int cr_info_end(cr_info *info, cr_err *err)
{
    int rc;

    if (!info->header) /* not begun (or zeroed): nothing is open */
        return 0;
    rc = cr_appender_close(&info->file, err);
    free(info->header);
    info->header = NULL;
    info->header_len = 0;
    return rc;
}

int cr_info_write(const char *dir, const cr_run_info *run, const cr_scene *scene,
                  const cr_sysconfig *cfg, const cr_frame_stats *stats, int n_done,
                  cr_err *err)
{
    char path[4096];
    cr_atomic a;
    FILE *fp;
    int frames = run ? run->frames : 0;

    if (cr_path_join(path, sizeof path, dir, "info.txt") != 0)
        return cr_err_set(err, "output folder name too long: '%s'", dir);
    if (cr_atomic_open(&a, path, err) != 0)
        return -1;
    fp = a.fp;
    cr_info_header(fp, run, scene, cfg);
    for (int k = 0; stats && k < n_done; k++)
        cr_info_record(fp, &stats[k], k + 1, frames);
    if (n_done == 0) {
        if (frames > 0)
            fprintf(fp, "Finished 0 of %d frames (run incomplete)\n", frames);
        else
            fprintf(fp, "Finished 0 frames\n");
    }
    return cr_atomic_commit(&a, err);
}
