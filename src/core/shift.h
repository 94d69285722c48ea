/* curray core: the frequency ratio between two observers of one photon.
 *
 * DESIGN "One frequency ratio": for a photon with (covariant) momentum p_mu
 * and any two 4-velocities u_obs^mu, u_em^mu (future-directed, g(u,u) = -1),
 *
 *     g = nu_obs / nu_em = (p . u_obs) / (p . u_em),
 *
 * each dot product evaluated with p_mu at the event where that observer meets
 * the photon. The ratio is invariant under p -> lambda p, so it can be fed the
 * future-directed photon momentum k_mu or curray's backward ray tangent
 * -k_mu alike (geodesic.h). Since p_t and p_phi are conserved in Kerr-Newman,
 * only they are needed for observers with u^r = u^theta = 0 (static
 * observers, circular orbits): p . u = p_t u^t + p_phi u^phi.
 *
 * The paper's static redshift (6.9, cr_redshift_static below) is the
 * special case u_obs = cr_shift_static_velocity at the camera and
 * u_em = cr_shift_static_velocity at the source: then g =
 * sqrt(-g_tt)|source / sqrt(-g_tt)|camera for any photon (tests/test_orbit.c).
 */
#ifndef CR_CORE_SHIFT_H
#define CR_CORE_SHIFT_H

#include "metric.h"

/* g = (p . u_obs) / (p . u_em) with p_obs, p_em the photon's covariant
 * components (any common scale and sign) at the two events and u_obs, u_em
 * contravariant 4-velocities. Returns -1 where p . u_em = 0 or either
 * product is not finite (no such photon/observer pair). */
CR_HD static inline double cr_shift_ratio(const double p_obs[4], const double u_obs[4],
                                          const double p_em[4], const double u_em[4])
{
    double no = p_obs[0] * u_obs[0] + p_obs[1] * u_obs[1] + p_obs[2] * u_obs[2] +
                p_obs[3] * u_obs[3];
    double ne = p_em[0] * u_em[0] + p_em[1] * u_em[1] + p_em[2] * u_em[2] +
                p_em[3] * u_em[3];
    double g;
    if (ne == 0.0)
        return -1.0;
    g = no / ne;
    return cr_isfinite(g) ? g : -1.0;
}

/* The static observer's 4-velocity u^mu = (1/sqrt(-g_tt), 0, 0, 0) at BL
 * (r, th). Returns 0 (u untouched) inside or on the ergosurface, where no
 * static observer exists, 1 otherwise. */
CR_HD static inline int cr_shift_static_velocity(const cr_metric *mt, double r, double th,
                                                 double u[4])
{
    double m = cr_metric_minus_gtt(mt, r, th);
    if (!(m > 0.0) || !cr_isfinite(m))
        return 0;
    u[0] = 1.0 / sqrt(m);
    u[1] = u[2] = u[3] = 0.0;
    return 1;
}

/* The frame's observer's 4-velocity u^mu (BL components): e_t of its tetrad
 * (camera.h), (1, 0, 0, 0) for the observer at infinity. */
CR_HD static inline void cr_frame_observer_velocity(const cr_frame *f, double u[4])
{
    int k;
    for (k = 0; k < 4; k++)
        u[k] = f->obs_at_inf ? (k == 0 ? 1.0 : 0.0) : f->tetrad[0][k];
}

/* g = nu_obs / nu_em (shift.h, the one frequency ratio) of a photon with
 * covariant momentum p at the emitter and p_obs at the observer (any common
 * scale and sign: the ray's backward tangent -k serves; cr_ray keeps its
 * p_obs) emitted by matter of 4-velocity u_em and received by the frame's
 * observer. A moving observer (observer.h) may have u^r, u^theta != 0, so
 * p_obs must be the ray's own momentum there; for an observer with
 * u^r = u^theta = 0 (static, ZAMO, orbit, at infinity) only the conserved
 * p_t, p_phi of p_obs enter, and p itself serves. For an observer between
 * the horizons (f->obs_inside) the observer's side is its exact value 1.
 * -1 where the ratio is undefined (cr_shift_ratio). */
CR_HD static inline double cr_frame_shift(const cr_frame *f, const double p_obs[4],
                                          const double p[4], const double u_em[4])
{
    double u_obs[4];
    if (f->obs_inside) {
        /* p . u_obs = 1 exactly: the camera's backward tangent is -e_0 + n^i e_i
         * (camera.h); the BL product would cancel terms of order 1/Delta */
        double one[4] = {1.0, 0.0, 0.0, 0.0}, u1[4] = {1.0, 0.0, 0.0, 0.0};
        return cr_shift_ratio(one, u1, p, u_em);
    }
    cr_frame_observer_velocity(f, u_obs);
    return cr_shift_ratio(p_obs, u_obs, p, u_em);
}

/* Redshift omega_r/omega_s (3.5.1, 6.9) of light with covariant momentum p
 * (p_obs at the observer, as for cr_frame_shift) from a static source at (r, th) seen by the frame's observer: the one
 * frequency ratio with the static emitter's 4-velocity. For the static
 * observer it equals sqrt(-g_tt)|source / sqrt(-g_tt)|observer (ERRATA) to
 * rounding, whatever p (tests/test_patterns.c). Returns -1 for a source
 * inside the ergosurface, where no static source exists. */
CR_HD static inline double cr_redshift_static(const cr_frame *f, const double p_obs[4],
                                              const double p[4], double r, double th)
{
    double u_em[4];
    if (!cr_shift_static_velocity(&f->metric, r, th, u_em))
        return -1.0;
    return cr_frame_shift(f, p_obs, p, u_em);
}

#endif
