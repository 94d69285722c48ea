/* curray core: the thin accretion disc in the plane theta = pi/2 (cr_disc,
 * defs.h): the paper's chessboard, the Keplerian disc's per-frame data,
 * matter velocity, frequency ratio and blackbody colour, the disc's event
 * inside a step and the shading of a hit.
 */
#ifndef CR_CORE_DISC_H
#define CR_CORE_DISC_H

#include "colour.h"
#include "orbit.h"
#include "pattern.h"
#include "ray.h"
#include "shift.h"

/* Colour of the disc at BL radius r, azimuth ph, on the top (side 0) or
 * bottom (side 1) face. */
CR_HD static inline cr_rgb cr_disc_color(const cr_disc *d, double r, double ph, int side)
{
    double u = fmod(ph - d->yaw, CR_TWO_PI);
    if (u < 0.0)
        u += CR_TWO_PI;
    return cr_chess(cr_bin((r - d->r_in) / (d->r_out - d->r_in), d->n_radial),
                    cr_bin(u / CR_TWO_PI, d->n_sectors), side ? d->color2 : d->color1);
}

/* Tone-curve white point of the Keplerian disc's colour (linear units of
 * the exposure below): the peak temperature seen at g = 1 maps to linear
 * luminance 1, which the extended Reinhard curve with white point 4 shows at
 * 0.625 of full scale, so blueshifted (g > 1, brighter) parts have headroom
 * up to luminance 4 before they saturate. */
#define CR_KEPLER_WHITE 4.0

/* Derive the Keplerian disc's per-frame data (cr_disc "keplerian" fields)
 * for a frame in units of M (M = 1) whose disc has model, sense (the orbit
 * sense s of orbit.h), plunge, r_in (the requested inner radius), r_out and
 * either t_peak or the physical inputs mass_msun, mdot_edd (both > 0) set.
 * Sets r_isco and the ISCO orbit's E_isco, L_isco, the effective inner edge
 * r_in = max(r_in, r_isco), the flux table with zero torque there, t_scale
 * and t_peak (T(r_peak) = t_peak), exposure (linear sRGB luminance of a
 * t_peak blackbody at g = 1 is 1) and white.
 * Temperature scale: given t_peak, t_scale = t_peak / F_max^(1/4); given the
 * physical inputs, sigma T^4 = (F / Mdot) Mdot c^6 / (G M)^2 with
 * M = mass_msun M_sun and Mdot = mdot_edd Mdot_Edd, Mdot_Edd = L_Edd /
 * (eta c^2), L_Edd = 4 pi G M m_p c / sigma_T and the radiative efficiency
 * eta = 1 - E(r_in) of the zero-torque edge (1 - E_isco for a disc down to
 * the ISCO), and then t_peak = t_scale F_max^(1/4) (orbit.h).
 * Returns 0, or -1 when there is no table (r_isco not finite, r_isco >= r_out,
 * or the ISCO within CR_FLUX_MIN_GAP of the photon orbit: |a| above about
 * 0.99999 M). Host code (thousands of metric evaluations). */
CR_HD static inline int cr_disc_keplerian_prepare(cr_disc *d, const cr_metric *mt)
{
    double xyz[3], rgb[3], lum, r0;
    cr_orbit o;
    d->r_isco = cr_orbit_r_isco(mt, d->sense);
    if (!cr_isfinite(d->r_isco) || !(d->r_isco < d->r_out) ||
        !cr_orbit_eval(mt, d->sense, d->r_isco, &o))
        return -1;
    d->E_isco = o.E;
    d->L_isco = o.L;
    r0 = d->r_in > d->r_isco ? d->r_in : d->r_isco;
    if (!cr_flux_table_fill(&d->flux, mt, d->sense, r0, d->r_out) ||
        !cr_orbit_eval(mt, d->sense, r0, &o))
        return -1;
    d->r_in = r0;
    if (d->mass_msun > 0.0 && d->mdot_edd > 0.0) {
        double m_kg = d->mass_msun * CR_SI_M_SUN;
        double mdot = d->mdot_edd * cr_flux_mdot_edd_si(m_kg, 1.0 - o.E);
        d->t_scale = cr_flux_tscale_si(m_kg, mdot);
        d->t_peak = d->t_scale * sqrt(sqrt(d->flux.F_max));
    } else {
        d->t_scale = cr_flux_tscale_peak(&d->flux, d->t_peak);
    }
    cr_bb_xyz(d->t_peak, 1.0, xyz);
    cr_xyz_to_linear_srgb(xyz, rgb);
    lum = cr_srgb_luminance(rgb);
    d->exposure = lum > 0.0 ? 1.0 / lum : 1.0;
    d->white = CR_KEPLER_WHITE;
    return cr_isfinite(d->t_scale) && cr_isfinite(d->t_peak) && cr_isfinite(d->exposure) ? 0
                                                                                        : -1;
}

/* The 4-velocity of the Keplerian disc's matter at BL radius r (theta =
 * pi/2): the circular orbit of the disc's sense at r >= r_isco, the matter
 * plunging from the ISCO (cr_orbit_plunge_velocity) inside it. Returns 0
 * where neither exists (no circular orbit; at or inside the horizon). */
CR_HD static inline int cr_disc_keplerian_velocity(const cr_disc *d, const cr_metric *mt,
                                                   double r, double u[4])
{
    cr_orbit o;
    if (r < d->r_isco)
        return cr_orbit_plunge_velocity(mt, d->E_isco, d->L_isco, r, u);
    if (!cr_orbit_eval(mt, d->sense, r, &o))
        return 0;
    cr_orbit_velocity(&o, u);
    return 1;
}

/* The frequency ratio g = nu_obs / nu_em (cr_frame_shift) of a photon with
 * covariant momentum p (cr_ray_momentum) emitted by the Keplerian disc's
 * matter (cr_disc_keplerian_velocity) at BL radius r and received by the
 * frame's observer. -1 where that matter does not exist. */
CR_HD static inline double cr_disc_keplerian_g(const cr_frame *f, const double p_obs[4],
                                               const double p[4], double r)
{
    double u_em[4];
    if (!cr_disc_keplerian_velocity(&f->disc, &f->metric, r, u_em))
        return -1.0;
    return cr_frame_shift(f, p_obs, p, u_em);
}

/* Colour of the Keplerian disc at radius r seen with ratio g: the blackbody
 * of T(r) = t_scale F(r)^(1/4) through cr_bb_rgb8 (black where F = 0: the
 * zero-torque edge, and plunging matter inside it). *bolo receives the
 * bolometric brightness g^4 F(r) / F_max (cr_bolometric; 0 where g < 0). */
CR_HD static inline cr_rgb cr_disc_keplerian_color(const cr_disc *d, double r, double g,
                                                   double *bolo)
{
    double F = cr_flux_table_F(&d->flux, r);
    double T = F > 0.0 ? d->t_scale * sqrt(sqrt(F)) : 0.0;
    g = g > 0.0 ? g : 0.0;
    *bolo = cr_bolometric(g, F / d->flux.F_max);
    return cr_bb_rgb8(T, g, d->exposure, d->white);
}

/* The disc's event of the current step: where the step crosses the plane
 * theta = pi/2 (cr_ray_event_locate), counted when the crossing lies between
 * r_hit_in and r_out at a radius the ray reaches (cr_ray_outside_stop) and,
 * with disc.order_sel = N + 1, is the ray's crossing of order N (N
 * crossings before it, ray->n_cross).
 * Returns 1 with h set on a hit (index: the face the ray comes from, 0 top,
 * 1 bottom), else 0. */
CR_HD static inline int cr_disc_event(const cr_frame *f, const cr_ray *ray, cr_hit *h)
{
    double v0, v1, s, rr, th, ph;
    if (!f->disc.enabled || (f->disc.order_sel > 0 && ray->n_cross != f->disc.order_sel - 1))
        return 0;
    v0 = cr_ray_event_value(f, ray, CR_EV_DISC, cr_ray_y0(ray));
    v1 = cr_ray_event_value(f, ray, CR_EV_DISC, cr_ray_y1(ray));
    if (!cr_ray_sign_change(v0, v1))
        return 0;
    s = cr_ray_event_locate(f, ray, CR_EV_DISC, v0, 1.0, v1, h->y);
    cr_ray_position(ray, h->y, &rr, &th, &ph);
    if (rr >= f->disc.r_hit_in && rr <= f->disc.r_out && cr_ray_outside_stop(f, ray, rr)) {
        h->s = s;
        h->index = v0 < 0.0 ? 0 : 1;
        return 1;
    }
    return 0;
}

/* Shade a disc hit h: outcome, face, hit radius and azimuth, delay, and the colour
 * and frequency ratio of the disc's model there: the Keplerian disc's
 * matter (and its bolometric brightness), or the chessboard seen as a
 * static source (6.9). */
CR_HD static inline void cr_disc_shade(const cr_frame *f, const cr_ray *ray, const cr_hit *h,
                                       cr_pixel *px)
{
    double rr, th, ph, p[4];
    int side = h->index;
    cr_ray_position(ray, h->y, &rr, &th, &ph);
    px->outcome = CR_OUT_DISC;
    px->object = (int16_t)side;
    px->hit_r = rr;
    px->hit_phi = cr_wrap_2pi(ph);
    px->delay = cr_ray_delay_at(f, ray, h->s, h->y);
    cr_ray_momentum(ray, h->y, p);
    if (f->disc.model == CR_DISC_KEPLERIAN) {
        px->redshift = cr_disc_keplerian_g(f, ray->p_obs, p, rr);
        px->color = cr_disc_keplerian_color(&f->disc, rr, px->redshift, &px->bolo);
    } else {
        px->color = cr_disc_color(&f->disc, rr, ph, side);
        px->redshift = cr_redshift_static(f, ray->p_obs, p, rr, 0.5 * CR_PI);
    }
}

#endif
