/* curray input: evaluating a cr_scene for frame k of n (scene.h): every
 * animated value at that frame, the physical checks of ERRATA item 4 with
 * messages naming the key (and the frame), lengths in units of M, and
 * cr_frame_prepare.
 */
#include "scene.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/disc.h"   /* cr_disc_keplerian_prepare */
#include "../core/frame.h"  /* cr_frame_prepare, units of M */
#include "../core/orbit.h"  /* cr_orbit_*, CR_FLUX_MIN_GAP */
#include "../core/ray.h"    /* cr_ray_starts_at_infinity, cr_ray_crosses_horizons */
#include "../core/sphere.h" /* cr_sphere_prepare */
#include "../core/trace.h"  /* cr_trace_pixel: the preview of automatic exposure */
#include "names.h"

/* Relative slack on a^2 + Q^2 <= M^2, so that the extremal case survives
 * rounding (0.6^2 + 0.8^2 is 1.0000000000000002 in doubles). */
#define EXTREMAL_TOL 1e-12
/* Slack (radians) on the observer's theta in [0, pi]. */
#define THETA_TOL 1e-9

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

/* The largest image plane at infinity, in units of M: a pixel's impact
 * parameter b enters the ray's constants squared (b^2 overflows doubles from
 * 1.3e154 M), so every ray of a wider plane would end in error. At 1e150 M
 * the corner of a square plane still leaves a margin of 10^8 in b^2. */
#define CR_MAX_EXTENT 1e150
/* The farthest observer at a finite r, in units of M: the Mino integrator's
 * right-hand side holds r^4 ((r^2 + a^2)^2), which overflows from 1.3e77 M. */
#define CR_MAX_OBS_R 1e75

static int extent_fail(const cr_scene *s, int k, int n, double m, const cr_observer *o,
                       cr_err *err)
{
    char b[32], vb[32], in_m[96] = "";
    int h = !(o->hextent <= CR_MAX_EXTENT * m);
    double v = h ? o->hextent : o->vextent;
    if (m != 1.0)
        snprintf(in_m, sizeof in_m, " (%s M with metric.m = %g)", num_vs(b, v / m, CR_MAX_EXTENT),
                 m);
    return frame_fail(err, s, k, n,
                      "observer.%s = %s%s%s: the image plane at infinity may be at most %g M "
                      "%s (the squared impact parameter of a wider one overflows, and every "
                      "pixel would be an error ray)%s",
                      h ? "hextent" : "vextent", num_vs(vb, v, CR_MAX_EXTENT * m), !h && !s->has_vextent ? " (hextent x height / width)" : "",
                      in_m, CR_MAX_EXTENT, h ? "wide" : "high",
                      !h && !s->has_vextent ? "; use a smaller hextent or a wider image" : "");
}

/* How close to a horizon (relative to r+) an observer may be: the BL
 * components of its frame grow as 1/Delta, and on the horizon none exists. */
#define HORIZON_GAP_TOL 1e-9

/* An observer inside the outer horizon (observer.h: the free-fall frame;
 * ray.h: the ingoing chart), between the horizons (r- < r < r+) or inside
 * the inner one (0 < r < r-, where the free fall from rest at infinity
 * exists: 2Mr - Q^2 > 0, above its bounce): only infall and a velocity
 * measured by the free-faller. */
static int frame_inside(const cr_scene *s, int k, int n, const cr_metric *mt,
                        const cr_observer *o, cr_err *err)
{
    double rp = cr_metric_r_plus(mt), rm = cr_metric_r_minus(mt);
    if (!(rp - rm > HORIZON_GAP_TOL * rp))
        return frame_fail(err, s, k, n,
                          "observer.r = %g is inside the horizon r+ = %g of an extremal hole "
                          "(r- = r+): there is no region between the horizons, and curray "
                          "does not trace observers inside an extremal hole",
                          o->r, rp);
    if (!(o->r > CR_R_SING_OBS * mt->m))
        return frame_fail(err, s, k, n,
                          "observer.r = %g: inside the event horizon an observer needs "
                          "%g M < r < r+ = %g (r = 0 is the singularity%s, and curray does "
                          "not trace r < 0)",
                          o->r, CR_R_SING_OBS, rp,
                          mt->a != 0.0 ? " or the disc inside the ring" : "");
    if (fabs(o->r - rm) <= HORIZON_GAP_TOL * rp)
        return frame_fail(err, s, k, n,
                          "observer.r = %.10g is on the inner horizon r- = %.10g, where no "
                          "camera frame exists; keep it at least %g r+ away",
                          o->r, rm, HORIZON_GAP_TOL);
    if (o->r < rm && !(2.0 * mt->m * o->r - mt->q * mt->q > 0.0))
        return frame_fail(err, s, k, n,
                          "observer.r = %g is below r = Q^2 / 2M = %g, where the free fall from "
                          "rest at infinity turns back (it bounces there, inside r- = %g); "
                          "curray's frames inside r+ are built on that free fall, so an "
                          "observer inside r- needs r > %g",
                          o->r, mt->q * mt->q / (2.0 * mt->m), rm,
                          mt->q * mt->q / (2.0 * mt->m));
    if (o->motion == CR_MOTION_STATIC)
        return frame_fail(err, s, k, n,
                          o->r < rm
                              ? "observer.r = %g is inside the inner horizon r- = %g: curray "
                                "builds observers inside r+ on the free fall from rest at "
                                "infinity only (a static observer is not supported there); "
                                "use observer.motion: infall, or a velocity [v_r, v_theta, "
                                "v_phi] measured by that free-faller"
                              : "observer.r = %g is inside the event horizon r+ = %g, where no "
                                "observer can stay at rest (r is a time there: everything "
                                "moves to smaller r); use observer.motion: infall (free fall "
                                "from rest at infinity), or a velocity [v_r, v_theta, v_phi] "
                                "measured by that free-faller",
                          o->r, o->r < rm ? rm : rp);
    if (o->motion == CR_MOTION_ZAMO)
        return frame_fail(err, s, k, n,
                          "observer.motion = zamo: no zero angular momentum observer exists "
                          "inside the event horizon (observer.r = %g < r+ = %g, where its lapse "
                          "sqrt(Delta Sigma / A) is imaginary); use infall, or a velocity "
                          "measured by the free-faller",
                          o->r, rp);
    if (o->motion == CR_MOTION_ORBIT)
        return frame_fail(err, s, k, n,
                          "observer.motion = orbit: no circular orbit exists inside the event "
                          "horizon (observer.r = %g < r+ = %g); use infall, or a velocity "
                          "measured by the free-faller",
                          o->r, rp);
    return frame_motion(s, k, n, mt, o, err);
}

/* The observer of a plunge, observer.r = [infall, r_start, r_end]: frame k
 * of n at the fraction k/(n-1) of the proper time from r_start to r_end
 * along the infall worldline (observer.h, cr_infall_worldline) at the
 * frame's theta, r found by bisection on it, and phi = observer.phi at
 * r_start moved as the free-faller's BL phi is (phi~ along the worldline
 * minus F(r) of metric.h; unchanged for a = 0). A frame within 1e-8 r+ of a
 * horizon is moved 2e-8 r+ off it (inside r+, outside r-: the horizons
 * themselves are refused). Returns -1 when 2Mr - Q^2 <= 0 on the way. */
static int plunge_position(const cr_scene *s, int k, int n, const cr_metric *mt,
                           cr_observer *o)
{
    double r0 = s->obs_r.a, r1 = s->obs_r.b, total, d, lo = r1, hi = r0, want, F0, F1, dph;
    double rp = cr_metric_r_plus(mt), rm = cr_metric_r_minus(mt);
    int it;
    if (!(2.0 * mt->m * r1 - mt->q * mt->q > 0.0))
        return -1;
    cr_infall_worldline(mt, o->theta, r0, r1, &total, &d);
    want = n > 1 ? total * (double)k / (double)(n - 1) : 0.0;
    for (it = 0; it < 100 && k > 0; it++) {
        double mid = 0.5 * (lo + hi), t;
        cr_infall_worldline(mt, o->theta, r0, mid, &t, &d);
        if (t > want)
            lo = mid;
        else
            hi = mid;
    }
    o->r = k == 0 ? r0 : (k == n - 1 ? r1 : 0.5 * (lo + hi));
    if (fabs(o->r - rp) < 1e-8 * rp)
        o->r = rp * (1.0 - 2e-8);
    else if (rm > 0.0 && fabs(o->r - rm) < 1e-8 * rp)
        o->r = rm + 2e-8 * rp;
    if (mt->a != 0.0 && rp > rm) {
        cr_infall_worldline(mt, o->theta, r0, o->r, &d, &dph);
        cr_metric_ingoing_shift(mt, r0, &F0, NULL);
        cr_metric_ingoing_shift(mt, o->r, &F1, NULL);
        o->phi += -dph - (F1 - F0);
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
    if (s->obs_r_infall && plunge_position(s, k, n, mt, o))
        return frame_fail(err, s, k, n,
                          "observer.r = [infall, %g, %g]: the free fall from r = %g to %g "
                          "needs 2 M r - Q^2 > 0 all the way (it bounces at r = Q^2 / 2M = %g)",
                          s->obs_r.a, s->obs_r.b, s->obs_r.a, s->obs_r.b,
                          mt->q * mt->q / (2.0 * mt->m));
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
        if (!(o->hextent <= CR_MAX_EXTENT * mt->m) || !(o->vextent <= CR_MAX_EXTENT * mt->m))
            return extent_fail(s, k, n, mt->m, o, err);
        return 0;
    }
    rp = cr_metric_r_plus(mt);
    if (fabs(o->r - rp) <= HORIZON_GAP_TOL * rp)
        return frame_fail(err, s, k, n,
                          "observer.r = %.10g is on the event horizon r+ = %.10g, where no "
                          "camera frame exists; keep it at least %g r+ away (outside, or "
                          "inside with motion infall)",
                          o->r, rp, HORIZON_GAP_TOL);
    if (o->r < rp) {
        if (frame_inside(s, k, n, mt, o, err))
            return -1;
        goto projection;
    }
    re = cr_metric_r_ergo(mt, o->theta);
    mgtt = cr_metric_minus_gtt(mt, o->r, o->theta);
    if (o->r > re && !isfinite(mgtt)) /* r^2 overflows or underflows */
        return frame_fail(err, s, k, n,
                          "observer.r = %g with metric.m = %g is out of the range curray can "
                          "compute with (lengths are in units of M: keep r/M and M sensible)",
                          o->r, mt->m);
    if (o->r > CR_MAX_OBS_R * mt->m) {
        char b[32], rb[32], in_m[96] = "";
        if (mt->m != 1.0)
            snprintf(in_m, sizeof in_m, " (%s M with metric.m = %g)",
                     num_vs(b, o->r / mt->m, CR_MAX_OBS_R), mt->m);
        return frame_fail(err, s, k, n,
                          "observer.r = %s%s: an observer at a finite r may be at most %g M "
                          "from the hole (the integration's powers of r overflow beyond about "
                          "1e77 M, and every pixel would be an error ray); for a distant "
                          "observer use r: inf with hextent",
                          num_vs(rb, o->r, CR_MAX_OBS_R * mt->m), in_m, CR_MAX_OBS_R);
    }
    if (o->motion == CR_MOTION_STATIC && (o->r <= re || !(mgtt > 0.0)))
        return frame_fail(err, s, k, n,
                          "observer.r = %g at theta = %g deg is inside the ergosphere "
                          "(r_E+ = %g): no static observer exists there (observer.motion: "
                          "zamo, orbit, infall or a velocity can be there)",
                          o->r, DEG(o->theta), re);
    if (o->motion != CR_MOTION_STATIC && frame_motion(s, k, n, mt, o, err))
        return -1;
projection:
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
    d->order_sel = s->disc_order >= 0 ? s->disc_order + 1 : 0;
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

/* The Keplerian disc's largest outer radius, in units of M. The flux table
 * (cr_flux_table_fill) spans [r_in, r_out] with 128 nodes and finds the
 * flux peak by 100 golden-section steps over the whole span: up to 1e15 M
 * its peak is exact to 1e-15 and F to 1e-4 of the peak (a = 0.9; 1e-6 at
 * 1e5 M), from about 1e20 M the search misses the peak (the temperature
 * scale is wrong), and from about 4e68 M the integral overflows. */
#define CR_KEPLER_MAX_R_OUT 1e15

/* Message "what" into why[0..n), for cr_scene_keplerian. */
static int keplerian_fail(char *why, size_t n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static int keplerian_fail(char *why, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, n, fmt, ap);
    va_end(ap);
    return -1;
}

int cr_scene_keplerian(const cr_scene *s, const cr_metric *mt, double m, cr_disc *d, char *why,
                       size_t n)
{
    const char *sense = s->disc_retrograde ? "retrograde" : "prograde";
    double rp = cr_metric_r_plus(mt), risco;
    d->sense = cr_orbit_sense(mt, !s->disc_retrograde);
    d->t_peak = s->disc_temperature;
    d->mass_msun = s->disc_mass_msun;
    d->mdot_edd = s->disc_mdot_edd;
    d->plunge = s->disc_plunge;
    risco = cr_orbit_r_isco(mt, d->sense);
    d->r_isco = risco;
    if (!s->disc_has_r_in)
        d->r_in = risco;
    if (s->disc_has_r_in && !(d->r_in > rp))
        return keplerian_fail(why, n,
                              "accretion.radius: the inner radius %g is at or inside the event "
                              "horizon r+ = %g",
                              d->r_in * m, rp * m);
    if (!(risco < d->r_out))
        return keplerian_fail(why, n,
                              "accretion.radius: the %s ISCO r_isco = %g lies at or beyond the "
                              "outer radius %g: no stable orbit is left on the disc",
                              sense, risco * m, d->r_out * m);
    if (d->plunge && d->r_in > risco)
        return keplerian_fail(why, n,
                              "accretion.inside_isco = plunging: the matter falls from the %s "
                              "ISCO r_isco = %g, but the inner radius %g lies outside it; leave "
                              "the inner radius out (radius: [outer]) or put it at or inside "
                              "the ISCO",
                              sense, risco * m, d->r_in * m);
    if (!(d->r_out <= CR_KEPLER_MAX_R_OUT))
        return keplerian_fail(why, n,
                              "accretion.radius: the outer radius %g%s of the keplerian disc "
                              "may be at most %g M (the disc's flux table cannot resolve the "
                              "flux peak over a longer span; a real disc's light comes from "
                              "within a few hundred M)",
                              d->r_out * m, m == 1.0 ? "" : " (in units of metric.m)",
                              CR_KEPLER_MAX_R_OUT);
    if (!(fmax(d->r_in, risco) - cr_orbit_r_photon(mt, d->sense) >= CR_FLUX_MIN_GAP))
        return keplerian_fail(why, n,
                              "accretion: metric.a = %g, metric.q = %g are too close to an "
                              "extremal hole for the keplerian disc: its %s ISCO (%g) lies "
                              "within %g M of the photon orbit and the flux table cannot "
                              "resolve the flux peak there; use a spin up to about 0.9999 M "
                              "(Thorne's limit is 0.998 M)",
                              mt->a * m, mt->q * m, sense, risco * m, (double)CR_FLUX_MIN_GAP);
    if (cr_disc_keplerian_prepare(d, mt) != 0) { /* none of the above: no known cause */
        char lum[96];
        if (d->mass_msun > 0.0)
            snprintf(lum, sizeof lum, "mass_msun = %g, mdot_edd = %g", d->mass_msun, d->mdot_edd);
        else
            snprintf(lum, sizeof lum, "temperature = %g", d->t_peak);
        return keplerian_fail(why, n,
                              "accretion: the keplerian disc cannot be computed for radius "
                              "[%g, %g] around metric.a = %g, metric.q = %g with %s (a value "
                              "is not a finite number); bring these values closer to those of "
                              "the shipped keplerian scenes",
                              d->r_in * m, d->r_out * m, mt->a * m, mt->q * m, lum);
    }
    return 0;
}

/* The Keplerian disc's per-frame data, for a frame already in units of M;
 * m is the scene's M, to give radii in the scene's units in messages. */
static int frame_keplerian(const cr_scene *s, int k, int n, double m, cr_frame *f, cr_err *err)
{
    char why[CR_ERR_MSG];
    if (!f->disc.enabled || f->disc.model != CR_DISC_KEPLERIAN)
        return 0;
    double e;
    if (cr_scene_keplerian(s, &f->metric, m, &f->disc, why, sizeof why))
        return frame_fail(err, s, k, n, "%s", why);
    /* accretion.exposure: a factor on the disc's light (auto: the one
     * cr_scene_auto_exposure found, 1 until it has) */
    if (s->disc_exposure_auto)
        e = s->disc_exposure_found > 0.0 ? s->disc_exposure_found : 1.0;
    else if (s->disc_exposure.a == 0.0 && s->disc_exposure.b == 0.0)
        e = 1.0; /* a scene made without the parser (zeroed): the default */
    else if (eval(s->disc_exposure, k, n, &e))
        return frame_fail(err, s, k, n, "accretion.exposure: not a finite number");
    f->disc.exposure *= e;
    if (!(isfinite(f->disc.exposure) && f->disc.exposure > 0.0))
        return frame_fail(err, s, k, n,
                          "accretion.exposure = %g: the disc's light at that exposure is out of "
                          "the range of doubles (with the peak temperature %g K); use an "
                          "exposure nearer 1",
                          e, f->disc.t_peak);
    return 0;
}

/* The input of the tone curve (cr_tonemap_reinhard, white point w) whose
 * output is c in (0, 1): the positive root of v^2 / w^2 + (1 - c) v - c = 0. */
static double tonemap_inverse(double c, double w)
{
    double a = 1.0 / (w * w), b = 1.0 - c;
    return (-b + sqrt(b * b + 4.0 * a * c)) / (2.0 * a);
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return a < b ? -1 : (a > b);
}

int cr_scene_auto_exposure(cr_scene *s, int n, int width, int height,
                           const cr_trace_settings *ts, long *lit, cr_err *err)
{
    cr_trace_settings t = ts ? *ts : cr_trace_defaults();
    cr_frame_eval e = {0};
    const cr_disc *d;
    double *lum;
    long m = 0, i, np;
    int pw = CR_AUTO_EXPOSURE_WIDTH, ph;
    if (lit)
        *lit = 0;
    if (!s->has_disc || s->disc_model != CR_DISC_KEPLERIAN || !s->disc_exposure_auto)
        return 0;
    ph = width > 0 && height > 0 ? (int)lround((double)pw * height / width) : pw;
    ph = ph < 1 ? 1 : (ph > 8 * pw ? 8 * pw : ph);
    t.samples = 1;
    s->disc_exposure_found = 1.0; /* the preview at exposure 1 */
    if (cr_frame_eval_at(&e, s, 0, n, pw, ph, &t, err))
        return -1;
    np = (long)pw * ph;
    lum = malloc(sizeof *lum * (size_t)np);
    if (!lum) {
        cr_frame_eval_free(&e);
        return frame_fail(err, s, 0, 1, "accretion.exposure: auto: out of memory");
    }
    d = &e.frame.disc;
    for (i = 0; i < np; i++) {
        cr_pixel px = cr_trace_pixel(&e.frame, (int)(i % pw), (int)(i / pw));
        double F, xyz[3], rgb[3], L;
        if (px.outcome != CR_OUT_DISC || !(px.redshift > 0.0))
            continue;
        F = cr_flux_table_F(&d->flux, px.hit_r);
        if (!(F > 0.0))
            continue; /* plunging matter, the zero-torque edge: dark */
        cr_bb_xyz(d->t_scale * sqrt(sqrt(F)), px.redshift, xyz);
        cr_xyz_to_linear_srgb(xyz, rgb);
        L = cr_srgb_luminance(rgb) * d->exposure;
        if (L > 0.0 && isfinite(L))
            lum[m++] = L;
    }
    if (m > 0) {
        /* nearest rank: the smallest value with at least p % of them at or below it */
        long r = (long)ceil(CR_AUTO_EXPOSURE_PERCENTILE / 100.0 * (double)m);
        double f;
        qsort(lum, (size_t)m, sizeof *lum, cmp_double);
        r = r < 1 ? 1 : (r > m ? m : r);
        f = tonemap_inverse(CR_AUTO_EXPOSURE_LEVEL, d->white) / lum[r - 1];
        s->disc_exposure_found = isfinite(f) && f > 0.0 ? f : 1.0;
    }
    if (lit)
        *lit = m;
    free(lum);
    cr_frame_eval_free(&e);
    return 0;
}

/* A moving sphere's motion on metric mt (the scene's units), its r set
 * first for r: isco: omega (the circular orbit's for motion: orbit) into
 * sp; -1 with a message when the orbit does not exist there. */
static int frame_sphere_motion(const cr_scene *s, int k, int n, int i, const cr_metric *mt,
                               cr_sphere *sp, cr_err *err)
{
    const cr_scene_sphere *ss = &s->spheres[i];
    sp->moving = ss->motion != CR_SPHERE_MOTION_STATIC;
    sp->particle = ss->motion == CR_SPHERE_MOTION_PARTICLE;
    sp->omega = ss->motion == CR_SPHERE_MOTION_ROTATING ? ss->omega : 0.0;
    if (ss->motion == CR_SPHERE_MOTION_ORBIT) {
        int sense = cr_orbit_sense(mt, !ss->retrograde);
        cr_orbit o;
        if (ss->r_isco)
            sp->r = cr_orbit_r_isco(mt, sense);
        if (!cr_orbit_eval(mt, sense, sp->r, &o))
            return frame_fail(err, s, k, n,
                              "sphere %d (line %d): motion: orbit at r = %g: no circular orbit "
                              "there (%s orbits exist outside the photon orbit r = %g)",
                              i, ss->line, sp->r, ss->retrograde ? "retrograde" : "prograde",
                              cr_orbit_r_photon(mt, sense));
        sp->omega = o.omega;
    }
    return 0;
}

static int frame_sphere(const cr_scene *s, int k, int n, int i, const cr_metric *mt,
                        cr_sphere *sp, cr_err *err)
{
    const cr_scene_sphere *ss = &s->spheres[i];
    double a = mt->a;
    memset(sp, 0, sizeof *sp);
    sp->color = ss->color;
    sp->n_lat = ss->n_lat;
    sp->n_lon = ss->n_lon;
    if ((!ss->r_isco && eval(ss->r, k, n, &sp->r)) || eval(ss->theta, k, n, &sp->theta) ||
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
    if (frame_sphere_motion(s, k, n, i, mt, sp, err))
        return -1;
    cr_sphere_prepare(sp, a);
    if (sp->moving && !sp->particle) { /* a particle sphere's matter: sphere.h */
        double rb, thb;
        if (cr_sphere_too_fast(mt, sp, &rb, &thb))
            return frame_fail(err, s, k, n,
                              "sphere %d (line %d): motion: %s with omega = %g: its matter at r = "
                              "%g, theta = %g deg would move at or beyond the speed of light "
                              "(%s)",
                              i, ss->line, ss->motion == CR_SPHERE_MOTION_ORBIT ? "orbit" : "rotating",
                              sp->omega, rb, thb * 180.0 / CR_PI,
                              sp->omega == 0.0 ? "no matter is at rest inside the ergosphere"
                                               : "make the sphere smaller or omega lower");
    }
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
    if (s->obs_at_infinity && !cr_ray_starts_at_infinity(t.integrator))
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
    if (!s->obs_at_infinity && f->observer.r < cr_metric_r_plus(&f->metric) &&
        !cr_ray_crosses_horizons(f->integrator))
        return frame_fail(err, s, k, n,
                          "raytracer.integrator = rk4 cannot follow rays through a horizon "
                          "(observer.r = %g is inside r+ = %g); use mino (the default)",
                          f->observer.r, cr_metric_r_plus(&f->metric));
    for (i = 0; i < s->n_spheres; i++)
        if (frame_sphere(s, k, n, i, &f->metric, &sphere_buf[i], err))
            return -1;
    /* a moving sphere is met at t = t_obs - delay, and the delay of a ray
       from inside r+ is not defined (ray.h, cr_ray_delay: BL t is no
       coordinate there and not followed through r+) */
    if (!s->obs_at_infinity && f->observer.r < cr_metric_r_plus(&f->metric))
        for (i = 0; i < s->n_spheres; i++)
            if (sphere_buf[i].moving)
                return frame_fail(err, s, k, n,
                                  "sphere %d (line %d): a moving sphere is seen with the "
                                  "light's travel time from the observer's BL time, which "
                                  "does not exist inside the event horizon (observer.r = %g < "
                                  "r+ = %g): it would never be seen; put the observer outside "
                                  "r+, or the sphere at rest (no motion)",
                                  i, s->spheres[i].line, f->observer.r,
                                  cr_metric_r_plus(&f->metric));
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
        f->sky.other_width = s->sky_other_width;
        f->sky.other_height = s->sky_other_height;
        f->sky.width = s->sky_width;
        f->sky.height = s->sky_height;
    }
    f->sky_color = s->sky_color;
    f->horizon_color = s->horizon_color;
    f->error_color = s->error_color;
    f->limit_color = s->limit_color;
    f->other_side_color = s->other_side_color;
    f->singularity_color = s->singularity_color;
    f->width = width;
    f->height = height;
    if (eval(s->obs_t, k, n, &f->t_obs) || !isfinite(f->t_obs + k * s->obs_dt))
        return frame_fail(err, s, k, n, "observer.t: the time of this frame is not finite");
    f->t_obs += k * s->obs_dt;
    /* inside the core every length is in units of M (messages above use the
     * scene's own units) */
    for (i = 0; i < s->n_spheres; i++) {
        const cr_scene_sphere *ss = &s->spheres[i];
        cr_sphere *sp = &sphere_buf[i];
        cr_sphere_to_units_of_m(sp, f->metric.m);
        if (sp->particle) { /* its table is in units of M already */
            sp->wl = ss->wl;
        }
    }
    f->track = s->track;
    f->n_track = s->n_track;
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
        double gap = fabs(f->observer.r - cr_metric_r_plus(&f->metric));
        if (gap < 2.0 * f->horizon_epsilon)
            f->horizon_epsilon = 0.5 * gap;
    }
    cr_frame_prepare(f);
    /* the boundary of an observer at infinity is at infinity too */
    if (!(isfinite(f->r_max) || (s->obs_at_infinity && f->r_max == INFINITY)) ||
        !isfinite(f->r_stop) ||
        !(f->obs_inside && !f->obs_inner ? f->obs_sqrt_mgtt < 0.0 : f->obs_sqrt_mgtt > 0.0) ||
        !isfinite(f->obs_sqrt_mgtt) || !isfinite(f->tan_half_h) || !isfinite(f->tan_half_v))
        return frame_fail(err, s, k, n,
                          "the scene's numbers are too large to trace (r_max = %g)", f->r_max);
    return 0;
}

int cr_frame_eval_at(cr_frame_eval *e, const cr_scene *s, int k, int n, int width, int height,
                     const cr_trace_settings *ts, cr_err *err)
{
    if (s->n_spheres > e->n_room) {
        cr_sphere *p = realloc(e->spheres, sizeof *p * (size_t)s->n_spheres);
        if (!p) {
            memset(&e->frame, 0, sizeof e->frame);
            return frame_fail(err, s, k, n, "out of memory for %d spheres", s->n_spheres);
        }
        e->spheres = p;
        e->n_room = s->n_spheres;
    }
    if (cr_scene_frame(s, k, n, width, height, ts, &e->frame, e->spheres, err)) {
        memset(&e->frame, 0, sizeof e->frame);
        return -1;
    }
    return 0;
}

void cr_frame_eval_free(cr_frame_eval *e)
{
    free(e->spheres);
    memset(e, 0, sizeof *e);
}

/* (scene.h) Every cr_anim of cr_scene is listed here; a new animatable key
 * belongs here too. */
int cr_scene_animated(const cr_scene *s)
{
    const cr_anim *v[] = {&s->m,         &s->a,        &s->q,          &s->obs_r,
                          &s->obs_theta, &s->obs_phi,  &s->roll,       &s->pitch,
                          &s->yaw,       &s->hfov,     &s->vfov,       &s->hextent,
                          &s->vextent,   &s->obs_v[0], &s->obs_v[1],   &s->obs_v[2],
                          &s->disc_yaw,  &s->disc_r_in, &s->disc_r_out, &s->sky_boundary,
                          &s->disc_exposure, &s->obs_t};
    size_t i;
    int j;
    for (i = 0; i < sizeof v / sizeof v[0]; i++)
        if (v[i]->a != v[i]->b)
            return 1;
    if (s->obs_dt != 0.0) /* the observer's time runs on: moving spheres move */
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
            if (p->r_isco) { /* r: isco, as frame_sphere_motion sets it */
                cr_metric mt = {m, a, q};
                r = cr_orbit_r_isco(&mt, cr_orbit_sense(&mt, !p->retrograde));
            }
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
    if (n > 1 && !cr_scene_animated(s) && count < max_hints)
        cr_err_set(&hints[count++],
                   "-f %d: nothing in the scene is animated (no [linear, start, end] value), so "
                   "all %d frames are the same image",
                   n, n);
    return count;
}
