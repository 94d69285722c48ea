/* curray core: tracing one ray, and cr_trace_pixel, the ONE implementation
 * both backends run for every pixel.
 *
 * One loop (chapter 6) for both integrators (the frame's integrator behind
 * ray.h): from the observer's state, repeat
 *   the ends (6.8): at the horizon stop -> horizon; at r+ - epsilon bound
 *     for the other exterior (from inside the horizon) -> other side; at
 *     r = 0 (from inside r-, ray.h) -> singularity;
 *     beyond the sky radius
 *     moving outward -> sky (sky.h); step or turn limit -> limit;
 *   one step (cr_ray_advance), with its error monitor;
 *   find the hits inside the step: each object's event (disc.h, sphere.h)
 *     locates its surface on the states inside the step (cr_ray_state_at);
 *   choose the earliest, shade it (its object's colour and frequency ratio)
 *     and end the ray; with no hit, move to the step's end (cr_ray_commit).
 * With ray->path set the loop records the ray's path (path.h).
 */
#ifndef CR_CORE_TRACE_H
#define CR_CORE_TRACE_H

#include "disc.h"
#include "frame.h"
#include "path.h"
#include "sky.h"
#include "sphere.h"

/* Running mean and variance of the error monitor over a ray's steps
 * (Welford); negative or non-finite values (undefined there) are left out. */
typedef struct cr_monitor {
    long n;
    double mean, m2;
} cr_monitor;

CR_HD static inline void cr_monitor_add(cr_monitor *m, double e)
{
    if (e >= 0.0 && cr_isfinite(e)) {
        double d = e - m->mean;
        m->n++;
        m->mean += d / m->n;
        m->m2 += d * (e - m->mean);
    }
}

/* The pixel of a ray not yet ended: no outcome, the error colour, -1 for
 * every value an end sets; x0 the ray's Cartesian position when there are
 * spheres; the path's first point. */
CR_HD static inline void cr_trace_start(const cr_frame *f, cr_ray *ray, cr_pixel *px,
                                        double x0[3])
{
    px->redshift = -1.0;
    px->hit_r = px->hit_phi = -1.0;
    px->bolo = -1.0;
    px->delay = NAN;
    px->object = -1;
    px->order = px->theta_turns = -1;
    px->outcome = CR_OUT_NONE;
    px->color = f->error_color;
    ray->n_cross = ray->n_turn = 0;
    if (f->n_spheres > 0)
        cr_ray_cart(f, ray, cr_ray_y0(ray), x0);
    if (ray->path)
        cr_path_begin(f, ray, ray->path);
}

/* The disc-plane crossing and the polar turning point of the current step,
 * if any, from its start to state y (its end), added to the ray's counts
 * (cr_ray.n_cross, n_turn). */
CR_HD static inline void cr_trace_count(const cr_frame *f, cr_ray *ray, const double *y)
{
    const double *y0 = cr_ray_y0(ray);
    ray->n_cross += cr_ray_sign_change(cr_ray_event_value(f, ray, CR_EV_DISC, y0),
                                       cr_ray_event_value(f, ray, CR_EV_DISC, y));
    ray->n_turn += cr_ray_sign_change(cr_ray_polar_rate(ray, y0), cr_ray_polar_rate(ray, y));
}

/* The ray's counts into its pixel (at its end; a hit's step adds its turning
 * point before the hit state y first, the crossing hit is not counted). */
CR_HD static inline void cr_trace_counts_out(const cr_ray *ray, cr_pixel *px)
{
    px->order = (int16_t)(ray->n_cross < CR_COUNT_MAX ? ray->n_cross : CR_COUNT_MAX);
    px->theta_turns = (int16_t)(ray->n_turn < CR_COUNT_MAX ? ray->n_turn : CR_COUNT_MAX);
}

/* The ray reached the horizon stop: light from the horizon is infinitely
 * redshifted. */
CR_HD static inline void cr_trace_horizon(const cr_frame *f, cr_pixel *px)
{
    px->outcome = CR_OUT_HORIZON;
    px->color = f->horizon_color;
    px->redshift = 0.0;
}

/* The ray left the interior toward the other exterior (ray.h): no source
 * of ours lies there, so no frequency ratio. */
CR_HD static inline void cr_trace_other_side(const cr_frame *f, cr_pixel *px)
{
    px->outcome = CR_OUT_OTHER_SIDE;
    px->color = f->other_side_color;
}

/* The hit that ends the ray inside the current step: the objects' events
 * (each fills its own hit) and the earliest of them, the disc on a tie.
 * Returns CR_OUT_DISC, CR_OUT_SPHERE or CR_OUT_NONE. x0: as for
 * cr_sphere_event. */
CR_HD static inline int cr_trace_find_hit(const cr_frame *f, const cr_ray *ray, double x0[3],
                                          cr_hit *disc, cr_hit *sphere)
{
    int on_disc, on_sphere;
    if (!cr_ray_events_on(ray)) {
        if (f->n_spheres > 0) /* x0 follows the step, as cr_sphere_event does */
            cr_ray_cart(f, ray, cr_ray_y1(ray), x0);
        return CR_OUT_NONE;
    }
    on_disc = cr_disc_event(f, ray, disc);
    on_sphere = cr_sphere_event(f, ray, x0, sphere);
    if (on_sphere && (!on_disc || sphere->s < disc->s))
        return CR_OUT_SPHERE;
    return on_disc ? CR_OUT_DISC : CR_OUT_NONE;
}

/* Shade the chosen hit (what: CR_OUT_DISC or CR_OUT_SPHERE), the path's last
 * point at it, and the polar turning point of the step before it. */
CR_HD static inline void cr_trace_shade_hit(const cr_frame *f, cr_ray *ray, int what,
                                            const cr_hit *disc, const cr_hit *sphere,
                                            cr_pixel *px)
{
    const cr_hit *h = what == CR_OUT_SPHERE ? sphere : disc;
    ray->n_turn += cr_ray_sign_change(cr_ray_polar_rate(ray, cr_ray_y0(ray)),
                                      cr_ray_polar_rate(ray, h->y));
    if (ray->path)
        cr_path_step(f, ray, ray->path, h->s);
    if (what == CR_OUT_SPHERE)
        cr_sphere_shade(f, ray, h, px);
    else
        cr_disc_shade(f, ray, h, px);
}

/* The ray's cost and error monitor into its pixel. */
CR_HD static inline void cr_trace_finish(cr_pixel *px, long steps, const cr_monitor *m)
{
    px->steps = (uint32_t)steps;
    px->err_mean = m->n > 0 ? m->mean : 0.0;
    px->err_std = m->n > 0 ? sqrt(m->m2 / m->n) : 0.0;
}

/* The ray ran into the step or turn limit. */
CR_HD static inline void cr_trace_limit(const cr_frame *f, cr_pixel *px)
{
    px->outcome = CR_OUT_LIMIT;
    px->color = f->limit_color;
}

/* The ends (6.8) at the ray's current state, before its next step, and its
 * error monitor there: returns 1 when the ray ends here (horizon, sky,
 * limit; px set), else 0. steps, turns: the ray's counts so far. */
CR_HD static inline int cr_trace_ends(const cr_frame *f, cr_ray *ray, cr_pixel *px,
                                      cr_monitor *mon, long steps, double turns)
{
    if (cr_ray_at_horizon(f, ray)) {
        cr_trace_horizon(f, px);
        if (cr_ray_mirrored(ray)) /* the other exterior's past horizon */
            px->outcome = CR_OUT_OTHER_SIDE;
        return 1;
    }
    if (cr_ray_other_side(ray)) {
        cr_trace_other_side(f, px);
        return 1;
    }
    if (cr_ray_singular(ray)) {
        px->outcome = CR_OUT_SINGULARITY;
        px->color = f->singularity_color;
        return 1;
    }
    cr_monitor_add(mon, cr_ray_begin(ray));
    if (cr_ray_escaping(f, ray) || (steps == 0 && cr_ray_misses_scene(f, ray))) {
        cr_sky_shade(f, ray, px);
        return 1;
    }
    if (steps >= f->max_steps || turns >= f->max_turns) {
        cr_trace_limit(f, px);
        return 1;
    }
    return 0;
}

/* Move the ray to the end of a step without a hit: the path's point there,
 * the step's crossing and turning point counted, the commit (cr_ray_commit;
 * turns as there). */
CR_HD static inline void cr_trace_move(const cr_frame *f, cr_ray *ray, double *turns)
{
    if (ray->path)
        cr_path_step(f, ray, ray->path, 1.0);
    cr_trace_count(f, ray, cr_ray_y1(ray));
    cr_ray_commit(f, ray, turns);
}

/* After a step (cr_ray_advance): the hit that ends the ray inside it, shaded
 * (returns 1), or the move to the step's end (cr_trace_move; returns 0).
 * x0: as for cr_trace_find_hit. */
CR_HD static inline int cr_trace_after_step(const cr_frame *f, cr_ray *ray, cr_pixel *px,
                                            double x0[3], double *turns)
{
    cr_hit disc, sphere;
    int what = cr_trace_find_hit(f, ray, x0, &disc, &sphere);
    if (what != CR_OUT_NONE) {
        cr_trace_shade_hit(f, ray, what, &disc, &sphere, px);
        return 1;
    }
    cr_trace_move(f, ray, turns);
    return 0;
}

/* The ended ray's counts (but for an error), cost and error monitor into
 * its pixel. */
CR_HD static inline void cr_trace_done(const cr_ray *ray, cr_pixel *px, long steps,
                                       const cr_monitor *mon)
{
    if (px->outcome != CR_OUT_ERROR)
        cr_trace_counts_out(ray, px);
    cr_trace_finish(px, steps, mon);
}

/* Trace a ray through the frame's scene (with ray->path set, recording its
 * path, path.h). */
CR_HD static inline cr_pixel cr_trace_loop(const cr_frame *f, cr_ray *ray)
{
    cr_pixel px;
    cr_monitor mon;
    double x0[3] = {0.0, 0.0, 0.0}, turns = 0.0;
    long steps = 0;
    mon.n = 0;
    mon.mean = mon.m2 = 0.0;
    cr_trace_start(f, ray, &px, x0);
    for (;;) {
        if (cr_trace_ends(f, ray, &px, &mon, steps, turns))
            break;
        if (cr_ray_advance(f, ray) != 0) {
            px.outcome = CR_OUT_ERROR;
            break;
        }
        steps++;
        if (cr_trace_after_step(f, ray, &px, x0, &turns))
            break;
    }
    cr_trace_done(ray, &px, steps, &mon);
    return px;
}

/* Trace the backward ray with BL state y and constants g (as made by
 * cr_camera_ray) through the frame's scene, with the frame's integrator. */
CR_HD static inline cr_pixel cr_trace_ray(const cr_frame *f, const cr_geo *g, const double *y)
{
    cr_ray ray;
    cr_ray_from_bl(f, g, y, &ray);
    return cr_trace_loop(f, &ray);
}

/* The ray through image point (x, y) of frame f into ray (path NULL):
 * returns 1, or 0 for a point outside the picture, with *px its pixel as
 * cr_trace_point_path below describes. */
CR_HD static inline int cr_trace_point_ray(const cr_frame *f, double x, double y, cr_ray *ray,
                                           cr_pixel *px)
{
    double n[3], yb[CR_NY];
    cr_geo g;
    if (!cr_camera_in_image(f, x, y)) {
        px->redshift = px->hit_r = px->hit_phi = px->bolo = -1.0;
        px->delay = NAN;
        px->err_mean = px->err_std = 0.0;
        px->steps = 0;
        px->object = -1;
        px->order = px->theta_turns = -1;
        px->outcome = CR_OUT_OUTSIDE;
        px->color = cr_rgb_make(0, 0, 0);
        return 0;
    }
    if (f->obs_at_inf) {
        double alpha, beta;
        cr_camera_screen(f, x, y, &alpha, &beta);
        cr_camera_ray_at_infinity(f, alpha, beta, &ray->c, ray->m);
        cr_ray_mino_start(f, ray);
    } else {
        cr_camera_pixel_dir(f, x, y, n);
        cr_camera_ray(f, n, &g, yb);
        cr_ray_from_bl(f, &g, yb, ray);
    }
    return 1;
}

/* Trace the one ray through image point (x, y) of frame f, in pixel units of
 * cr_camera_screen / cr_camera_pixel_dir: (i, j) is the centre of pixel
 * (i, j) (those functions add 0.5). A point outside the picture
 * (cr_camera_in_image: beyond a fisheye's image circle) is not traced: its
 * pixel has outcome CR_OUT_OUTSIDE, colour black, steps 0, redshift, hit_r,
 * hit_phi and bolo -1, object, order and theta_turns -1, err_mean = err_std
 * = 0, and an empty path. */
CR_HD static inline cr_pixel cr_trace_point_path(const cr_frame *f, double x, double y,
                                                cr_path *path)
{
    cr_ray ray;
    cr_pixel px;
    if (!cr_trace_point_ray(f, x, y, &ray, &px)) {
        if (path) {
            path->n = 0;
            path->started = 0;
        }
        return px;
    }
    ray.path = path;
    return cr_trace_loop(f, &ray);
}

CR_HD static inline cr_pixel cr_trace_point(const cr_frame *f, double x, double y)
{
    return cr_trace_point_path(f, x, y, 0);
}

/* Offset from the pixel centre, in pixels, of sub-pixel row or column a of
 * an n x n stratified grid: the sub-pixel centres are at ((a + 0.5) / n) of
 * the pixel, so the offset is (a + 0.5) / n - 0.5; exactly 0 for the middle
 * one of an odd n. */
CR_HD static inline double cr_subpixel_offset(int a, int n)
{
    return (a + 0.5) / n - 0.5;
}

/* The sub-ray whose outcome, redshift, object and error monitor a pixel
 * reports with n x n samples: a = b = n / 2 (integer division), the centre
 * sub-ray for odd n (the very ray of samples = 1), and for even n the one of
 * the four central sub-rays right of and below the centre (offset +0.5 / n
 * in x and in y, image rows counted downward). */
CR_HD static inline int cr_subpixel_centre(int n)
{
    return n / 2;
}

/* Trace pixel (i, j) of frame f (prepared by cr_frame_prepare).
 * With f->samples = n in 2..CR_MAX_SAMPLES (antialiasing) it traces the
 * n x n sub-rays of a stratified regular grid (sub-pixel centres at
 * ((a + 0.5) / n, (b + 0.5) / n) of the pixel, a, b = 0..n-1) through the
 * same camera code. The colour is their mean in linear light (each 8-bit
 * sRGB colour decoded to linear, averaged, encoded back and rounded); steps
 * is the sum of all sub-rays' steps (the pixel's cost); outcome, object,
 * redshift, err_mean and err_std are those of the sub-ray of
 * cr_subpixel_centre. Any other value of samples traces the one ray through
 * the pixel centre, exactly as without antialiasing. */
CR_HD static inline cr_pixel cr_trace_pixel(const cr_frame *f, int i, int j)
{
    int n = f->samples, c, k;
    double sum[3] = {0.0, 0.0, 0.0};
    unsigned long steps = 0;
    cr_pixel px;
    if (n < 2 || n > CR_MAX_SAMPLES)
        n = 1; /* offset 0: the ray through (double)i, (double)j */
    c = cr_subpixel_centre(n);
    px.steps = 0;
    /* one call site for every sub-ray (one inlined trace in the kernel) */
    for (k = 0; k < n * n; k++) {
        int a = k % n, b = k / n;
        cr_pixel s = cr_trace_point(f, i + cr_subpixel_offset(a, n), j + cr_subpixel_offset(b, n));
        if (a == c && b == c)
            px = s;
        if (n > 1) {
            sum[0] += cr_srgb_decode(s.color.r / 255.0);
            sum[1] += cr_srgb_decode(s.color.g / 255.0);
            sum[2] += cr_srgb_decode(s.color.b / 255.0);
            steps += s.steps;
        }
    }
    if (n == 1)
        return px;
    for (k = 0; k < 3; k++)
        sum[k] = cr_srgb_encode(sum[k] / (n * n));
    px.color.r = cr_unit_to_u8(sum[0]);
    px.color.g = cr_unit_to_u8(sum[1]);
    px.color.b = cr_unit_to_u8(sum[2]);
    px.steps = steps > 0xffffffffUL ? 0xffffffffu : (uint32_t)steps;
    return px;
}

/* The path (cr_path) of the ray that pixel (i, j) reports: with antialiasing
 * the sub-ray of cr_subpixel_centre, else the pixel's one ray. Returns that
 * ray's cr_pixel (its outcome, hit point, redshift). */
CR_HD static inline cr_pixel cr_trace_pixel_path(const cr_frame *f, int i, int j, cr_path *path)
{
    int n = f->samples;
    double off;
    if (n < 2 || n > CR_MAX_SAMPLES)
        n = 1;
    off = cr_subpixel_offset(cr_subpixel_centre(n), n);
    return cr_trace_point_path(f, i + off, j + off, path);
}

#endif
