/* curray core: THE integrator interface. One ray under either integrator
 * of the frame (raytracer.integrator), and the only place that asks which:
 *   CR_INTEG_RK4: the paper's BL state (geodesic.h), h by (6.6.1), one RK4
 *     step in the affine parameter, a non-finite result retried smaller,
 *     then an error; continued through the polar axis;
 *   CR_INTEG_MINO: the Mino state (mino.h), one accepted Dormand-Prince 5(4)
 *     step in Mino time, repeated smaller while its error estimate exceeds
 *     the tolerance; the state passes the polar axis smoothly.
 * The trace loop (trace.h) sees only these functions:
 *   start    cr_ray_from_bl, cr_ray_mino_start (the observer at infinity)
 *   step     cr_ray_advance: the current state to the step's end y1
 *   state    cr_ray_state_at: the state at any fraction s of the step
 *            (partial RK4 steps from its start, or the DP5 dense output),
 *            where the objects' events are located (disc.h, sphere.h);
 *            cr_ray_y0, cr_ray_y1, cr_ray_step_length
 *   point    cr_ray_cart, cr_ray_position, cr_ray_momentum, cr_ray_point,
 *            cr_ray_sky_direction of a state
 *   monitor  cr_ray_begin: derivatives at the current state and the error
 *            monitor there: the null error (6.7.1) under RK4, the
 *            first-integral residual of mino.h under Mino
 *   commit   cr_ray_commit: move to the step's end (no hit inside it)
 *   ends     (6.8) cr_ray_at_horizon, cr_ray_escaping, cr_ray_misses_scene,
 *            cr_ray_outside_stop, cr_ray_beyond_stop
 * and the coordinate events of the chart (cr_ray_event_value,
 * cr_ray_event_locate): the disc plane theta = pi/2 and, under Mino, the sky
 * radius, whose crossing cr_ray_commit locates.
 *
 * Charts (Mino only; the rest of the program sees BL positions and
 * momenta). A ray from an observer outside the horizon lives in BL
 * coordinates throughout, as it always did. A ray from an observer between
 * the horizons (f->obs_inside, r- < r < r+) starts in the ingoing Kerr chart
 * (mino.h, CR_CHART_INGOING: pr carries phi~ = phi + F(r), metric.h). There
 * every backward ray moves to larger r (r is a time coordinate inside, and
 * the past lies toward r+), and it leaves the interior one of two ways, fixed
 * by the sign of P(r+) = E (r+^2 + a^2) + a L, the photon's frequency on the
 * horizon:
 *   P(r+) > 0: the light came in through our future horizon. The ray is
 *     followed through r+ in the ingoing chart (regular there) to r+ +
 *     epsilon, where its step is cut (cr_ray_advance); from there on its
 *     events are looked for, and it changes to BL (cr_ray_to_bl: phi =
 *     phi~ - F(r)) beyond 2 (r+ + epsilon) or where it turns inward; it is
 *     then an exterior ray like any other (disc, spheres, sky; back to r+ +
 *     epsilon moving inward: horizon, the past horizon, as for every
 *     exterior ray); one that turns before r+ + epsilon ends as horizon;
 *   P(r+) <= 0: the light came from the other exterior of the eternal hole
 *     (through the other half of the interior's past boundary, where v and
 *     phi~ diverge): the ray ends at r+ - epsilon as CR_OUT_OTHER_SIDE.
 * No event (disc, sphere) is looked for inside r+ + epsilon: nothing curray
 * draws exists there.
 *
 * From an observer inside the inner horizon (f->obs_inner, 0 < r < r-) the
 * ray starts in the same ingoing chart, which also covers the region inside
 * r- that the infall reaches (Delta > 0 again; r is a space coordinate
 * there, so a backward ray may move to smaller r and turn). There the
 * combination (r^2 + a^2) d_t + a d_phi is timelike and future-directed, so
 * every backward ray has P(r) = E (r^2 + a^2) + a L > 0: the one branch of
 * r- in its past is the one from the region between the horizons, which the
 * ingoing chart covers regularly (its rates take the form w^2 K/(Pw - dw)
 * there, as at r+); the other branch of r- lies in its future and is never
 * reached backward. A ray found with P(r-) <= 0 (only by rounding, at the
 * edge of that bound) ends as an error. A ray that leaves r- outward
 * (w < f->w_minus) is then a ray between the horizons like those above
 * (P(r+) decides, as there). A ray that comes closer to r = 0 than
 * CR_R_SING (w >= f->w_sing) ends as CR_OUT_SINGULARITY: the central
 * singularity for a = 0 (only K = 0 rays get there: for Q != 0 every other
 * ray turns, R(0) = -Q^2 K), for a != 0 the ring singularity or the disc
 * r = 0 inside it, through which the ray would go on to r < 0, a region
 * curray does not follow (w = 1/r cannot pass r = 0).
 *
 * The other exterior (only with a sky image for it, skymap.other_side:
 * f->sky.other_width > 0). Between the horizons, (t, phi) -> (-t, -phi) in
 * BL is an isometry that keeps r and the time orientation and swaps the two
 * halves of the interior's past boundary; it maps a ray with constants
 * (E, L, eta) to one with (-E, -L, eta), P -> -P, the state's n_y, dn_y and
 * BL phi negated (pr -> 2 F(r) - pr in the ingoing chart). A ray with
 * P(r+) <= 0 is replaced by its mirror image while it is between the
 * horizons (at its start, or as it leaves r-: cr_ray_mirror), which
 * leaves through our future horizon's mirror, the other exterior's, in the
 * ingoing chart as above; it is then a ray of the other exterior written in
 * its mirror coordinates, where nothing of the scene exists: no events;
 * escaping it shows the other side's sky in its direction there (sky.h),
 * falling back to that exterior's past horizon the horizon colour, both
 * with the outcome CR_OUT_OTHER_SIDE.
 */
#ifndef CR_CORE_RAY_H
#define CR_CORE_RAY_H

#include "coords.h"
#include "mino.h"

/* Largest state of either integrator. */
#define CR_RAY_NY ((int)CR_MN > (int)CR_NY ? (int)CR_MN : (int)CR_NY)

/* One ray under either integrator: its constants, its state, and the step
 * from that state (to y1 / m1) while events are looked for inside it. */
typedef struct cr_ray {
    int kind; /* cr_integrator */
    /* CR_INTEG_RK4 */
    cr_geo g;
    double y[CR_NY], y1[CR_NY], k1[CR_NY], u[4];
    double h; /* the current step */
    /* CR_INTEG_MINO */
    cr_mino c;
    double m[CR_MN], m1[CR_MN];
    cr_dp5 st;     /* stages; st.k[0] = f(m) */
    double hm;     /* the current step */
    double h_next; /* the next trial step */
    int t_quad;    /* the current step did not resolve T: T inside it by
                      quadrature (cr_mino_t_quad; its end's T too, but for a
                      step that ends beyond every object moving outward) */
    /* Path recorder (cr_path, path.h): NULL except when one ray's path is
     * wanted (--trace, curray.trace); set by the ray's maker to NULL. */
    struct cr_path *path;
    /* Covariant momentum at the observer (cr_ray_momentum of the first
     * state), the observer's side of every frequency ratio (cr_frame_shift);
     * set by cr_ray_mino_start and cr_ray_from_bl. */
    double p_obs[4];
    /* Counts along the ray so far, of either integrator (the trace loop's,
     * trace.h): crossings of the disc plane (cr_ray_event_value CR_EV_DISC
     * changing sign over a step) and polar turning points (sign changes of
     * cr_ray_polar_rate); set to 0 by cr_trace_start. */
    int n_cross, n_turn;
    /* The ingoing chart (header comment; all 0 for an exterior ray): where
     * the ray leaves it (w_exit: f->w_stop going out, f->w_other bound for
     * the other side), whether it goes out (exit_out), whether the current
     * step ends there (exit_step), whether it has left the interior (out:
     * beyond r+ + epsilon, still in the ingoing chart), has changed to BL
     * (crossed) or ended on the other side (other). */
    double w_exit;
    int exit_out, exit_step, out, crossed, other;
    /* From an observer inside r- (header comment; 0 otherwise): inner is 1
     * while the ray is inside r- (w >= f->w_minus), -1 for a ray with
     * P(r-) <= 0 (ends as an error), 0 once it is out; sing: it came within
     * CR_R_SING of r = 0 (ends as CR_OUT_SINGULARITY). */
    int inner, sing;
    /* The ray is the mirror image of one bound for the other exterior
     * (header comment, cr_ray_mirror); 0 otherwise. */
    int mirror;
} cr_ray;

/* The ray is in the ingoing chart (inside r+ + epsilon, from an observer
 * between the horizons). */
CR_HD static inline int cr_ray_ingoing(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && ray->c.chart == CR_CHART_INGOING;
}

/* Whether the objects' events are looked for in the current step: not
 * inside r+ + epsilon (header comment). */
CR_HD static inline int cr_ray_events_on(const cr_ray *ray)
{
    return !ray->mirror && (!cr_ray_ingoing(ray) || ray->out);
}

/* The ray is the mirror image of one bound for the other exterior. */
CR_HD static inline int cr_ray_mirrored(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && ray->mirror;
}

/* BL phi minus the state's atan2(n_y, n_x) + pr: -F(r) in the ingoing
 * chart (phi = phi~ - F(r)), else 0; F(infinity) = 0 (a ray that leaves
 * r+ + epsilon for infinity in one step changes to BL at w = 0). */
CR_HD static inline double cr_ray_phi_shift(const cr_ray *ray, double r)
{
    double F = 0.0;
    if (cr_ray_ingoing(ray) && r < INFINITY)
        cr_metric_ingoing_shift(&ray->g.mt, r, &F, 0);
    return -F;
}

/* The ray's current state (the start of the current step) and the end of
 * the current step (set by cr_ray_advance), in the integrator's layout. */
CR_HD static inline const double *cr_ray_y0(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO ? ray->m : ray->y;
}

CR_HD static inline const double *cr_ray_y1(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO ? ray->m1 : ray->y1;
}

/* Length of the current step in the integrator's parameter: the affine
 * parameter of the backward tangent under RK4, Mino time under Mino. */
CR_HD static inline double cr_ray_step_length(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO ? ray->hm : ray->h;
}

/* Whether the state carries BL time t (RK4 integrates it; Mino does not: it
 * diverges at w = 0). */
CR_HD static inline int cr_ray_has_t(const cr_ray *ray)
{
    return ray->kind != CR_INTEG_MINO;
}

/* The coordinate-time delay t_obs - t of state y of the ray's integrator:
 * the time the light at y takes to reach the observer. RK4 integrates t
 * (t = 0 at the observer); Mino carries it regularised (mino.h), and for the
 * observer at infinity gives it renormalised, lim [t_o - t - r_o - 2M
 * ln(r_o/M)] as r_o -> infinity. Meaningless beyond the horizon stop; NaN
 * for a ray from inside the horizon, in the ingoing chart (BL t is not a
 * coordinate there) and after it (the observer's BL t belongs to the
 * interior's own patch, and T is not followed through r+). */
CR_HD static inline double cr_ray_delay(const cr_ray *ray, const double *y)
{
    if (ray->kind != CR_INTEG_MINO)
        return -y[CR_Y_T];
    return ray->c.chart == CR_CHART_BL && !ray->crossed ? cr_mino_delay(&ray->c, y) : NAN;
}

/* The delay at state ys = cr_ray_state_at(ray, s) of the current step of a
 * ray of frame f; under Mino T there by quadrature on the dense output
 * (cr_mino_t_quad) when the step did not resolve it, and always in a
 * science frame (cr_frame.science): the dense output's own T, of 4th order,
 * can be off by more than the step's estimate for its end. */
CR_HD static inline double cr_ray_delay_at(const cr_frame *f, const cr_ray *ray, double s,
                                           const double *ys)
{
    if (ray->kind == CR_INTEG_MINO &&
        (ray->t_quad || (f->science && ray->c.chart == CR_CHART_BL && !ray->crossed))) {
        double y[CR_MN];
        int i;
        for (i = 0; i < CR_MN; i++)
            y[i] = ys[i];
        y[CR_M_T] = cr_mino_t_quad(&ray->c, &ray->st, ray->m, ray->m1, ray->hm, s);
        return cr_ray_delay(ray, y);
    }
    return cr_ray_delay(ray, ys);
}

/* Whether one step may cross much of the scene, its fraction not
 * proportional to the distance along its chord (Mino); RK4 steps are short
 * and nearly straight. */
CR_HD static inline int cr_ray_long_steps(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO;
}

/* Points per step that a path recorder (path.h, cr_path.sub) draws for the
 * integrator of frame f: the step's end plus dense-output points inside it.
 * Mino steps are long (tens per ray), so 8 points a step draw a smooth
 * curve; RK4 steps are short (hundreds to thousands per ray): 1. */
#define CR_RAY_PATH_SUB_MINO 8
#define CR_RAY_PATH_SUB_RK4 1
CR_HD static inline int cr_ray_path_sub(const cr_frame *f)
{
    return f->integrator == CR_INTEG_MINO ? CR_RAY_PATH_SUB_MINO : CR_RAY_PATH_SUB_RK4;
}

/* Whether the integrator (cr_integrator) can start a ray from the observer
 * at infinity: Mino only (cr_ray_mino_start, w = 0); RK4's BL state needs a
 * finite r. */
CR_HD static inline int cr_ray_starts_at_infinity(int integrator)
{
    return integrator == CR_INTEG_MINO;
}

/* Whether the integrator can follow rays through a horizon (from an
 * observer inside r+): Mino only (w = 1/r passes r+ smoothly); RK4's BL
 * state diverges at r+. */
CR_HD static inline int cr_ray_crosses_horizons(int integrator)
{
    return integrator == CR_INTEG_MINO;
}

/* The state at fraction s in [0, 1] of the current step. */
CR_HD static inline void cr_ray_state_at(const cr_ray *ray, double s, double *ys)
{
    if (ray->kind == CR_INTEG_MINO)
        cr_dp5_dense(&ray->st, ray->m, ray->m1, ray->hm, s, ys);
    else
        cr_geo_rk4(&ray->g, ray->y, ray->k1, s * ray->h, ys);
}

/* Cartesian position (2.2.8) of a state of the ray's integrator. */
CR_HD static inline void cr_ray_cart(const cr_frame *f, const cr_ray *ray, const double *y,
                                     double x[3])
{
    if (cr_ray_ingoing(ray)) {
        double yb[CR_MN];
        int i;
        for (i = 0; i < CR_MN; i++)
            yb[i] = y[i];
        yb[CR_M_PR] += cr_ray_phi_shift(ray, 1.0 / y[CR_M_W]);
        cr_mino_cart(f->metric.a, yb, x);
    } else if (ray->kind == CR_INTEG_MINO)
        cr_mino_cart(f->metric.a, y, x);
    else
        cr_bl_to_cart(f->metric.a, y[CR_Y_R], y[CR_Y_TH], y[CR_Y_PH], x);
}

/* BL r, theta, phi of a state of the ray's integrator. */
CR_HD static inline void cr_ray_position(const cr_ray *ray, const double *y, double *r,
                                         double *th, double *ph)
{
    if (ray->kind == CR_INTEG_MINO) {
        double c, s;
        cr_mino_position(y, r, &c, &s, ph);
        *th = atan2(s, c);
        *ph += cr_ray_phi_shift(ray, *r);
    } else {
        *r = y[CR_Y_R];
        *th = y[CR_Y_TH];
        *ph = y[CR_Y_PH];
    }
}

/* Covariant momentum p_mu of the ray (its backward tangent -k, geodesic.h
 * convention: p_t = E, p_phi = L) at a state y of the ray's integrator. RK4:
 * p_r = g_rr u^r, p_theta = g_thth u^theta. Mino: dr/dtau = Sigma dr/dlambda
 * gives p_r = (dr/dtau) / Delta = -(dw/dtau) / D(w) (D = Delta / r^2), and
 * p_theta = dtheta/dtau = -(dn_z/dtau) / sin(theta) (0 on the axis). */
CR_HD static inline void cr_ray_momentum(const cr_ray *ray, const double *y, double p[4])
{
    if (ray->kind == CR_INTEG_MINO) {
        double w = y[CR_M_W], st = sqrt(y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY]);
        p[0] = ray->c.E;
        p[1] = -y[CR_M_DW] / (1.0 + w * (ray->c.d1 + w * ray->c.d2));
        p[2] = st > 0.0 ? -y[CR_M_DNZ] / st : 0.0;
        p[3] = ray->c.L;
    } else {
        cr_metric_point q;
        cr_metric_eval(&ray->g.mt, y[CR_Y_R], y[CR_Y_TH], &q);
        p[0] = ray->g.E;
        p[1] = q.g_rr * y[CR_Y_UR];
        p[2] = q.g_thth * y[CR_Y_UTH];
        p[3] = ray->g.L;
    }
}

/* Sky direction (6.10.3)/(6.10.4) of state y (the current state, after
 * cr_ray_begin): polar angle and azimuth in [0, 2pi) of the ray's Cartesian
 * direction of motion, the direction of the source on the sky. */
CR_HD static inline void cr_ray_sky_direction(const cr_frame *f, const cr_ray *ray,
                                              const double *y, double *sky_th, double *sky_ph)
{
    if (ray->kind == CR_INTEG_MINO)
        cr_mino_sky_direction(&ray->c, y, sky_th, sky_ph);
    else
        cr_sky_direction(f->metric.a, y, ray->u[3], sky_th, sky_ph);
}

/* Layout of a point of the ray (cr_ray_point; the path recorder's columns
 * after its parameter, path.h): BL time, BL position, Cartesian position
 * (2.2.8), u^mu = dx^mu/dlambda of the backward tangent (affine lambda). */
enum {
    CR_RP_T = 0,
    CR_RP_R,
    CR_RP_TH,
    CR_RP_PH,
    CR_RP_X,
    CR_RP_Y,
    CR_RP_Z,
    CR_RP_UT,
    CR_RP_UR,
    CR_RP_UTH,
    CR_RP_UPH,
    CR_RPN
};

/* The point of state y of the ray's integrator (the CR_RP_* layout above)
 * into p: t under rk4 only (cr_ray_has_t), position, u^mu; returns
 * dt/dparameter there (u^t under rk4, Sigma u^t under mino; for a ray from
 * inside the horizon dv/dtau of the ingoing time instead, regular through
 * r+: cr_ray_t_shift), or NaN at w = 0 (mino at infinity: no finite point). */
CR_HD static inline double cr_ray_point(const cr_frame *f, const cr_ray *ray, const double *y,
                                        double *p)
{
    cr_metric_point q;
    double u[4], a = f->metric.a;
    if (ray->kind == CR_INTEG_MINO) {
        double r, c, s, ph, w = y[CR_M_W], psi, dth, sig;
        cr_geo g;
        if (!(w > 0.0))
            return NAN;
        cr_mino_position(y, &r, &c, &s, &ph);
        ph += cr_ray_phi_shift(ray, r);
        psi = atan2(y[CR_M_NY], y[CR_M_NX]);
        /* dtheta/dtau = dn/dtau . e_theta for the unit vector n */
        dth = (y[CR_M_DNX] * c * cos(psi) + y[CR_M_DNY] * c * sin(psi) - y[CR_M_DNZ] * s) /
              sqrt(y[CR_M_NX] * y[CR_M_NX] + y[CR_M_NY] * y[CR_M_NY] + y[CR_M_NZ] * y[CR_M_NZ]);
        sig = r * r + a * a * c * c;
        p[CR_RP_R] = r;
        p[CR_RP_TH] = atan2(s, c);
        p[CR_RP_PH] = ph;
        cr_ray_cart(f, ray, y, p + CR_RP_X);
        g.mt = f->metric;
        g.E = ray->c.E;
        g.L = ray->c.L;
        g.th_floor = 0.0;
        {
            double yb[CR_NY];
            yb[CR_Y_UR] = -y[CR_M_DW] / (w * w * sig);
            yb[CR_Y_UTH] = dth / sig;
            cr_metric_eval(&f->metric, r, p[CR_RP_TH], &q);
            cr_geo_velocity(&g, yb, &q, u);
        }
        p[CR_RP_UT] = u[0];
        p[CR_RP_UR] = u[1];
        p[CR_RP_UTH] = u[2];
        p[CR_RP_UPH] = u[3];
        return cr_ray_ingoing(ray) || ray->crossed ? cr_mino_ingoing_dv(&ray->c, y)
                                                   : sig * u[0];
    } else {
        double yb[CR_NY], dy[CR_NY];
        int i;
        for (i = 0; i < CR_NY; i++)
            yb[i] = y[i];
        cr_geo_through_axis(yb);
        cr_geo_rhs_full(&ray->g, yb, dy, u, &q);
        p[CR_RP_T] = yb[CR_Y_T];
        p[CR_RP_R] = yb[CR_Y_R];
        p[CR_RP_TH] = yb[CR_Y_TH];
        p[CR_RP_PH] = yb[CR_Y_PH];
        cr_bl_to_cart(a, yb[CR_Y_R], yb[CR_Y_TH], yb[CR_Y_PH], p + CR_RP_X);
        for (i = 0; i < 4; i++)
            p[CR_RP_UT + i] = u[i];
        return u[0];
    }
}

/* t = v - cr_ray_t_shift(ray, r) for a ray from inside the horizon once it
 * has left the ingoing chart (G(r) of metric.h); 0 otherwise (inside, the
 * time of its points is v itself; exterior rays have BL t). */
CR_HD static inline double cr_ray_t_shift(const cr_ray *ray, double r)
{
    double G = 0.0;
    if (ray->kind == CR_INTEG_MINO && ray->crossed)
        cr_metric_ingoing_shift(&ray->g.mt, r, 0, &G);
    return G;
}

/* Coordinate events located inside a step: the disc plane (for disc.h),
 * the sky radius (Mino only, for cr_ray_commit). */
enum { CR_EV_DISC = -1, CR_EV_SKY = -2 };

/* Value of coordinate event ev at state y of the ray's integrator. The disc
 * plane's is theta - pi/2 under RK4 and -cos(theta) (same sign) under Mino;
 * the sky radius's (Mino only) w - w_sky. */
CR_HD static inline double cr_ray_event_value(const cr_frame *f, const cr_ray *ray, int ev,
                                              const double *y)
{
    if (ev == CR_EV_DISC)
        return ray->kind == CR_INTEG_MINO ? cr_mino_disc_value(y) : y[CR_Y_TH] - 0.5 * CR_PI;
    return y[CR_M_W] - f->w_sky;
}

/* Whether a value that is v0 at a step's start and v1 at its end changes
 * sign over the step (an event crossed; a start exactly on it is not). */
CR_HD static inline int cr_ray_sign_change(double v0, double v1)
{
    return cr_sign_change(v0, v1);
}

/* A multiple of d cos(theta) / dparameter at state y of the ray's
 * integrator, with its sign (zero at a polar turning point): under Mino
 * dn_z/dtau, under RK4 -sin(theta) u^theta, which keeps its sign through the
 * polar axis fold (theta -> -theta, u^theta -> -u^theta). */
CR_HD static inline double cr_ray_polar_rate(const cr_ray *ray, const double *y)
{
    return ray->kind == CR_INTEG_MINO ? cr_mino_polar_rate(y) : -sin(y[CR_Y_TH]) * y[CR_Y_UTH];
}

/* Locate the root of coordinate event ev inside the current step, where the
 * value is v0 at its start and v1 of opposite sign at fraction s_hi,
 * 0 < s_hi <= 1, by regula falsi (cr_falsi) on cr_ray_state_at. Returns the
 * fraction s and the state there in ys. */
CR_HD static inline double cr_ray_event_locate(const cr_frame *f, const cr_ray *ray, int ev,
                                               double v0, double s_hi, double v1, double *ys)
{
    cr_falsi z;
    cr_falsi_start(&z, v0, s_hi, v1);
    while (cr_falsi_next(&z)) {
        cr_ray_state_at(ray, z.s, ys);
        if (!cr_falsi_update(&z, cr_ray_event_value(f, ray, ev, ys)))
            break;
    }
    return z.s;
}

/* The science tolerance: a frame whose pixels are read for their values
 * (cr_frame.science) steps at this fraction of raytracer.tolerance. The
 * error of a value is a sum over the ray's steps (the phases of its radial
 * and angular motion), so it shrinks with the steps' tolerance: at 1/2 of
 * the default 1e-7 the hit radius of rays near the photon sphere is within
 * 7e-8 relative of the exact orbit's, for about 14 % more steps
 * (test_accuracy, BENCHMARKS.md). */
#define CR_SCIENCE_TOL 0.5

/* The local error tolerance of frame f's Mino steps: raytracer.tolerance,
 * times CR_SCIENCE_TOL for a science frame. */
CR_HD static inline double cr_ray_tolerance(const cr_frame *f)
{
    return f->science ? CR_SCIENCE_TOL * f->tolerance : f->tolerance;
}

/* Start a Mino ray from a BL state (RK4 layout) and constants. */
CR_HD static inline void cr_ray_mino_start(const cr_frame *f, cr_ray *ray)
{
    ray->kind = CR_INTEG_MINO;
    ray->path = 0;
    ray->w_exit = 0.0;
    ray->exit_out = ray->exit_step = ray->out = ray->crossed = ray->other = 0;
    ray->inner = ray->sing = ray->mirror = 0;
    if (fabs(ray->m[CR_M_NZ]) < 1e-15) /* cos(pi/2) rounded: on the disc plane */
        ray->m[CR_M_NZ] = 0.0;
    cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
    ray->h_next = cr_mino_first_step(&ray->c, cr_ray_tolerance(f));
    ray->t_quad = 0;
    cr_ray_momentum(ray, ray->m, ray->p_obs);
}

/* Replace a ray between the horizons (in the ingoing chart, r- < r < r+)
 * that is bound for the other side by its mirror image (header comment),
 * bound for the mirror of our future horizon: constants (-E, -L, eta), n_y,
 * dn_y negated, pr = 2 F(r) - pr. */
CR_HD static inline void cr_ray_mirror(const cr_frame *f, cr_ray *ray)
{
    double F;
    cr_metric_ingoing_shift(&f->metric, 1.0 / ray->m[CR_M_W], &F, 0);
    cr_mino_init(&ray->c, &f->metric, -ray->c.E, -ray->c.L, ray->c.eta, f->w_stop);
    ray->c.chart = CR_CHART_INGOING;
    ray->m[CR_M_NY] = -ray->m[CR_M_NY];
    ray->m[CR_M_DNY] = -ray->m[CR_M_DNY];
    ray->m[CR_M_PR] = 2.0 * F - ray->m[CR_M_PR];
    cr_mino_t_start(&ray->c, ray->m);
    cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
    ray->mirror = 1;
    ray->exit_out = 1;
    ray->w_exit = f->w_stop;
}

/* The ray of the frame's integrator from the BL state y and constants g made
 * by cr_camera_ray. */
CR_HD static inline void cr_ray_from_bl(const cr_frame *f, const cr_geo *g, const double *y,
                                        cr_ray *ray)
{
    int i;
    ray->path = 0;
    ray->g = *g;
    ray->w_exit = 0.0;
    ray->exit_out = ray->exit_step = ray->out = ray->crossed = ray->other = 0;
    ray->inner = ray->sing = ray->mirror = 0;
    for (i = 0; i < CR_NY; i++)
        ray->y[i] = y[i];
    if (f->integrator == CR_INTEG_MINO) {
        cr_mino_from_bl(g, y, f->w_stop, &ray->c, ray->m);
        if (f->obs_inside) {
            /* the ingoing chart (header comment) */
            double rp = cr_metric_r_plus(&f->metric), F;
            double P = g->E * (rp * rp + g->mt.a * g->mt.a) + g->mt.a * g->L;
            cr_metric_ingoing_shift(&f->metric, y[CR_Y_R], &F, 0);
            ray->c.chart = CR_CHART_INGOING;
            ray->m[CR_M_PR] += F;
            cr_ray_mino_start(f, ray);
            ray->exit_out = P > 0.0;
            ray->w_exit = ray->exit_out ? f->w_stop : f->w_other;
            if (f->obs_inner) {
                double rm = cr_metric_r_minus(&f->metric);
                ray->inner = g->E * (rm * rm + g->mt.a * g->mt.a) + g->mt.a * g->L > 0.0 ? 1 : -1;
            } else if (!ray->exit_out && f->sky.other_width > 0)
                cr_ray_mirror(f, ray);
            return;
        }
        cr_ray_mino_start(f, ray);
    } else {
        ray->kind = CR_INTEG_RK4;
        cr_ray_momentum(ray, ray->y, ray->p_obs);
    }
}

/* Derivatives at the current state, and the error monitor there (negative
 * where it is undefined). */
CR_HD static inline double cr_ray_begin(cr_ray *ray)
{
    cr_metric_point p;
    if (ray->kind == CR_INTEG_MINO)
        return cr_mino_monitor(&ray->c, ray->m);
    cr_geo_rhs_full(&ray->g, ray->y, ray->k1, ray->u, &p);
    return cr_geo_null_error(&p, ray->u);
}

/* The ray reached the horizon stop r+ + epsilon from outside: in BL, and
 * moving inward if it came out of the interior (it starts there at the
 * stop). In the ingoing chart, outside r-: it moves inward (dw/dtau >= 0),
 * which a ray between the horizons never does (R > 0 there): it came out through r+,
 * turned between r+ and r+ + epsilon and falls back toward the past horizon,
 * the end of every exterior ray that reaches the stop. */
CR_HD static inline int cr_ray_at_horizon(const cr_frame *f, const cr_ray *ray)
{
    if (cr_ray_ingoing(ray))
        return !ray->out && !ray->inner && ray->m[CR_M_DW] >= 0.0;
    return ray->kind == CR_INTEG_MINO
               ? cr_mino_at_horizon(ray->m, f->w_stop) && (!ray->crossed || ray->m[CR_M_DW] > 0.0)
               : ray->y[CR_Y_R] <= f->r_stop;
}

/* The ray ended at r+ - epsilon bound for the other side (header comment). */
CR_HD static inline int cr_ray_other_side(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && ray->other;
}

/* The ray came within CR_R_SING of r = 0 from inside r- (header comment). */
CR_HD static inline int cr_ray_singular(const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && ray->sing;
}

/* After a move of a ray from inside r- (cr_ray_commit): whether it is still
 * inside r-, and whether it came within CR_R_SING of r = 0; one that has
 * left r- bound for the other side is mirrored where the frame has a sky for
 * it (cr_ray_mirror). */
CR_HD static inline void cr_ray_inner_update(const cr_frame *f, cr_ray *ray)
{
    if (ray->inner > 0) {
        ray->sing = ray->m[CR_M_W] >= f->w_sing;
        ray->inner = ray->m[CR_M_W] >= f->w_minus;
        if (!ray->inner && !ray->exit_out && f->sky.other_width > 0)
            cr_ray_mirror(f, ray); /* now between the horizons */
    }
}

/* How far state y of the ray's integrator lies beyond the horizon stop
 * r+ + epsilon (> 0 beyond it). */
CR_HD static inline double cr_ray_beyond_stop(const cr_frame *f, const cr_ray *ray,
                                              const double *y)
{
    if (cr_ray_ingoing(ray))
        return -1.0; /* its steps end where it leaves the chart */
    return ray->kind == CR_INTEG_MINO ? y[CR_M_W] - f->w_stop : f->r_stop - y[CR_Y_R];
}

/* Whether a hit located at BL radius r counts. A Mino step can carry the
 * ray past the horizon stop r+ + epsilon, where the ray ends (6.8), so an
 * event located beyond it is not seen; RK4 keeps the paper's rule (the stop
 * is checked at step starts only), so its images stay as they were. */
CR_HD static inline int cr_ray_outside_stop(const cr_frame *f, const cr_ray *ray, double r)
{
    return ray->kind != CR_INTEG_MINO || r >= f->r_stop;
}

CR_HD static inline int cr_ray_escaping(const cr_frame *f, const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO ? cr_mino_escaping(ray->m, f->w_sky)
                                      : ray->y[CR_Y_R] >= f->r_max && ray->u[1] > 0.0;
}

/* Whether a Mino ray that comes in from beyond the sky radius never gets
 * inside it: then R(r) < 0 at r = 1/w_sky, so it turns at a larger radius
 * and leaves again, and ends as sky by the rule above without meeting
 * anything. Only taken when the sky is a plain colour (no direction is
 * needed); the image of an observer at infinity is mostly such rays. */
CR_HD static inline int cr_ray_misses_scene(const cr_frame *f, const cr_ray *ray)
{
    return ray->kind == CR_INTEG_MINO && !f->sky.rgb && f->w_sky > 0.0 &&
           ray->m[CR_M_W] < f->w_sky && ray->m[CR_M_DW] > 0.0 &&
           cr_mino_W(&ray->c, f->w_sky) < 0.0;
}

/* Rejected DP5 tries of one step before the ray ends as an error. */
#define CR_DP5_MAX_RETRIES 60

/* Whether the step's end y1 lies beyond every object (cr_frame.w_obj)
 * moving outward, where the ray meets nothing more and its time is no
 * longer needed. */
CR_HD static inline int cr_ray_time_done(const cr_frame *f, const double *y1)
{
    return y1[CR_M_DW] < 0.0 && y1[CR_M_W] < f->w_obj;
}

/* After an accepted Mino step: where its own estimate says the step did not
 * resolve T (never for a ray from inside the horizon, whose delay is NaN),
 * t_quad is set, so that a hit inside the step takes its T by quadrature on
 * the dense output (cr_ray_delay_at, mino.h), and the end's T is replaced
 * by the quadrature's wherever the time can still be needed
 * (!cr_ray_time_done). A step that leaves every object outward may still
 * meet one before its end: its hit's time is the quadrature's too. The
 * scalar and the packet path (render/cpu_packet.c) both call it. */
CR_HD static inline void cr_ray_time_step(const cr_frame *f, cr_ray *ray)
{
    ray->t_quad = !cr_ray_ingoing(ray) && !ray->crossed && /* no delay there */
                  cr_mino_t_unresolved(&ray->st, ray->m, ray->m1, ray->hm, cr_ray_tolerance(f));
    if (ray->t_quad && !cr_ray_time_done(f, ray->m1))
        ray->m1[CR_M_T] = cr_mino_t_quad(&ray->c, &ray->st, ray->m, ray->m1, ray->hm, 1.0);
}

/* One step from the current state to y1 / m1. Returns 0, or -1 when the
 * integration failed (non-finite state, step size collapsed). In the
 * ingoing chart a step that passes w_exit is taken again, shortened to end
 * there (located on its dense output; exit_step set); a state there outside
 * r- with dw/dtau not negative (NaN: moving inward ends the ray before,
 * cr_ray_at_horizon) fails, and so does a ray with P(r-) <= 0 (inner < 0). */
CR_HD static inline int cr_ray_advance(const cr_frame *f, cr_ray *ray)
{
    int tries, i;
    if (ray->kind == CR_INTEG_MINO) {
        double h = ray->h_next;
        int cut = 0;
        ray->exit_step = 0;
        if (cr_ray_ingoing(ray) && (ray->inner < 0 || (!ray->inner && !(ray->m[CR_M_DW] < 0.0))))
            return -1;
        for (tries = 0;; tries++) {
            double err = cr_dp5_try(&ray->c, cr_ray_tolerance(f), h, ray->m, &ray->st, ray->m1);
            double h_next = ray->h_next;
            if (cr_dp5_control(err, tries > 0, &h, &h_next)) {
                double v0, v1;
                cr_mino_project(&ray->c, 1, ray->m1, &ray->st); /* on its first integral */
                v0 = ray->m[CR_M_W] - ray->w_exit;
                v1 = ray->m1[CR_M_W] - ray->w_exit;
                ray->hm = h;
                if (cr_ray_ingoing(ray) && !ray->out && !cut && v1 <= 0.0 && v0 > 0.0) {
                    /* leaves the chart inside this step: end the step there */
                    double ys[CR_RAY_NY];
                    cr_falsi z;
                    cr_falsi_start(&z, v0, 1.0, v1);
                    while (cr_falsi_next(&z)) {
                        cr_ray_state_at(ray, z.s, ys);
                        if (!cr_falsi_update(&z, ys[CR_M_W] - ray->w_exit))
                            break;
                    }
                    h *= z.s;
                    cut = 1;
                    continue;
                }
                ray->exit_step = cut;
                ray->h_next = cut ? ray->h_next : h_next;
                cr_ray_time_step(f, ray);
                return 0;
            }
            cut = 0;
            if (tries == CR_DP5_MAX_RETRIES || !(h > 0.0))
                return -1;
        }
    }
    ray->h = cr_geo_step_size(&ray->g, f->step_multiplier, ray->y[CR_Y_TH], ray->u);
    for (tries = 0;; tries++) {
        int ok = 1;
        cr_geo_rk4(&ray->g, ray->y, ray->k1, ray->h, ray->y1);
        for (i = 0; i < CR_NY; i++)
            ok &= cr_isfinite(ray->y1[i]);
        if (ok && ray->y1[CR_Y_R] > 0.0)
            break;
        if (tries == 4)
            return -1;
        ray->h *= 0.125;
    }
    return cr_isfinite(ray->h) ? 0 : -1;
}

/* A ray out of the interior but still in the ingoing chart changes to BL
 * (phi = phi~ - F(r)) once it is beyond 2 (r+ + epsilon) or moves inward:
 * the ingoing chart is regular for it while it moves out, and BL's 1/Delta in
 * the azimuth's rate just outside r+ would cost steps; moving inward, toward
 * the past horizon, only BL is regular. */
CR_HD static inline void cr_ray_to_bl(const cr_frame *f, cr_ray *ray)
{
    if (!(cr_ray_ingoing(ray) && ray->out &&
          (ray->m[CR_M_W] < 0.5 * f->w_stop || !(ray->m[CR_M_DW] < 0.0))))
        return;
    ray->m[CR_M_PR] += cr_ray_phi_shift(ray, 1.0 / ray->m[CR_M_W]); /* phi~ - F */
    ray->c.chart = CR_CHART_BL;
    ray->crossed = 1;
    cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
}

/* Move the ray to the end of the current step (no hit inside it): under
 * RK4 through the polar axis, under Mino cut at the sky radius when the step
 * crosses it. Adds the turns made around the axis to *turns. */
CR_HD static inline void cr_ray_commit(const cr_frame *f, cr_ray *ray, double *turns)
{
    int i;
    if (ray->kind == CR_INTEG_MINO) {
        *turns += cr_mino_turns(ray->m, ray->m1);
        if (ray->exit_step) {
            /* the step ends where the ray leaves the ingoing chart */
            for (i = 0; i < CR_MN; i++)
                ray->m[i] = ray->m1[i];
            ray->exit_step = 0;
            ray->inner = 0; /* w_exit < w_minus */
            if (!ray->exit_out) {
                /* from inside r- in one step: mirrored here if it can be */
                if (f->sky.other_width > 0)
                    cr_ray_mirror(f, ray);
                else
                    ray->other = 1;
                return;
            }
            ray->out = 1;
            for (i = 0; i < CR_MN; i++)
                ray->st.k[0][i] = ray->st.k[6][i];
            cr_ray_to_bl(f, ray);
            return;
        }
        if (cr_mino_cuts_sky(ray->m, ray->m1, f->w_sky)) {
            double ys[CR_RAY_NY];
            cr_ray_event_locate(f, ray, CR_EV_SKY, ray->m[CR_M_W] - f->w_sky, 1.0,
                                ray->m1[CR_M_W] - f->w_sky, ys);
            for (i = 0; i < CR_MN; i++)
                ray->m[i] = ys[i];
            ray->m[CR_M_W] = f->w_sky;
            if (!(ray->m[CR_M_DW] < 0.0))
                ray->m[CR_M_DW] = -1e-300;
            cr_mino_rhs(&ray->c, ray->m, ray->st.k[0]);
            cr_ray_to_bl(f, ray);
            return;
        }
        for (i = 0; i < CR_MN; i++) {
            ray->m[i] = ray->m1[i];
            ray->st.k[0][i] = ray->st.k[6][i];
        }
        cr_ray_inner_update(f, ray);
        cr_ray_to_bl(f, ray);
        return;
    }
    *turns += fabs(ray->y1[CR_Y_PH] - ray->y[CR_Y_PH]) / CR_TWO_PI;
    cr_geo_through_axis(ray->y1);
    for (i = 0; i < CR_NY; i++)
        ray->y[i] = ray->y1[i];
}

/* A hit located inside the current step by an object's event (disc.h,
 * sphere.h): the step fraction s, the state y there, and index: the sphere,
 * or the disc's face (0 top, 1 bottom). */
typedef struct cr_hit {
    double s;
    double y[CR_RAY_NY];
    int index;
} cr_hit;

#endif
