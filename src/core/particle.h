/* curray core: worldlines of massive, charged test particles in Kerr-Newman.
 *
 * A particle of mass m and charge q (charge-to-mass ratio qm = q/m, 0 for a
 * neutral one) in the hole's field A = -(Q r / Sigma)(dt - a sin^2 dphi),
 * i.e. A_t = -Q r / Sigma, A_phi = Q r a sin^2 / Sigma. Its 4-velocity u^mu
 * (future-directed, u.u = -1, per unit mass) has the conserved constants
 * (Carter 1968; the textbook future-directed convention, unlike geodesic.h's
 * backward rays)
 *   E = -(u_t + qm A_t)    energy at infinity per unit mass,
 *   L = u_phi + qm A_phi   axial angular momentum per unit mass,
 *   K = (Sigma u^theta)^2 + cos^2 (a^2 (1 - E^2) + L^2 / sin^2)   Carter's.
 * In Mino time lambda (d tau = Sigma d lambda, tau the proper time), with
 *   P(r)   = E (r^2 + a^2) - a L - qm Q r,
 *   R(r)   = P^2 - Delta [r^2 + (L - a E)^2 + K]       (dr/dlambda)^2 = R,
 *   Th(u)  = K - (K + L^2 + a^2 (1 - E^2)) u^2 - a^2 (1 - E^2) u^4,
 *            u = cos theta,                            (du/dlambda)^2 = Th,
 *   dphi/dlambda = L / sin^2 - a E + a P / Delta,
 *   dt/dlambda   = (r^2 + a^2) P / Delta - a (a E sin^2 - L),
 * the motion separates exactly as for light, and the Mino state of mino.h
 * (w = 1/r, n, pr and their derivatives) carries it unchanged: W(w) =
 * w^4 R(1/w) gains the term c3 w (R's r^3 term, 2M - 2 E qm Q), a^2 E^2
 * becomes a^2 (E^2 - 1), and dpr/dlambda = a w (p1 + p2 w) / D with
 * p1 = 2 M E - qm Q, p2 = -(E Q^2 + a L). (A photon is the case "1 -> 0",
 * qm = 0, with mino.h's constants (-E, L).) The charge enters R and P only:
 * Th, and so K's form, are those of a neutral particle.
 *
 * The integrator is mino.h's Dormand-Prince 5(4) with its error control
 * (cr_dp5_try, cr_dp5_factor, cr_dp5_dense), the step loop of ray.h. t and
 * tau, which do not enter the right-hand side, are integrated over each
 * accepted step by 8-point Gauss-Legendre quadrature of dt/dlambda and
 * Sigma on the step's dense output, a step being accepted only where that
 * quadrature meets the tolerance too (cr_particle_time_err_). A worldline
 * ends at the horizon stop r = r+ + eps (located on the dense output), or
 * beyond r_max.
 */
#ifndef CR_CORE_PARTICLE_H
#define CR_CORE_PARTICLE_H

#include "mino.h"
#include "observer.h"

/* Why a worldline ended (cr_particle.ended). */
enum {
    CR_PARTICLE_RUNNING = 0,
    CR_PARTICLE_HORIZON = 1, /* reached r+ + eps */
    CR_PARTICLE_ESCAPED = 2, /* beyond r_max */
    CR_PARTICLE_FAILED = 3   /* non-finite state or step size collapsed */
};

/* One particle and the last step of its worldline: the step goes from
 * (y0, t0, tau0, lam0) to (y1, t1, tau1, lam0 + hm). */
typedef struct cr_particle {
    cr_metric mt;
    double E, L, K, qm; /* constants (header comment) */
    double tol;         /* DP5 tolerance */
    double w_stop;      /* 1 / (r+ + eps) */
    double w_min;       /* 1 / r_max */
    cr_mino c;          /* coefficients, mino.h layout */
    cr_dp5 st;          /* stages of the last step; st.k[0] = f(y0) */
    double y0[CR_MN], y1[CR_MN];
    double t0, tau0, lam0, t1, tau1;
    double ph0, ph1; /* continuous (unwrapped) phi at the step's ends */
    double hm;     /* size of the last step (0 before the first) */
    double h_next; /* next trial step */
    long steps;
    int ended;
} cr_particle;

/* A point of a worldline: proper, coordinate and Mino time, BL position
 * (cr_particle_at, cr_particle_current: phi continuous along the worldline,
 * starting in (-pi, pi]), Cartesian position (2.2.8), 4-velocity u^mu. */
typedef struct cr_particle_point {
    double tau, t, lam;
    double r, th, ph;
    double x[3];
    double u[4];
} cr_particle_point;

/* The hole's potential A_t, A_phi at (r, th). */
CR_HD static inline void cr_particle_potential(const cr_metric *mt, double r, double th,
                                               double *At, double *Aph)
{
    double c = cos(th), s = sin(th);
    double sigma = r * r + mt->a * mt->a * c * c;
    *At = -mt->q * r / sigma;
    *Aph = mt->q * r * mt->a * s * s / sigma;
}

/* R(r) and Th(u = cos theta) of constants (E, L, K, qm) (header comment). */
CR_HD static inline double cr_particle_R(const cr_metric *mt, double E, double L, double K,
                                         double qm, double r)
{
    double a = mt->a;
    double P = E * (r * r + a * a) - a * L - qm * mt->q * r;
    double delta = r * r + a * a + mt->q * mt->q - 2.0 * mt->m * r;
    double la = L - a * E;
    return P * P - delta * (r * r + la * la + K);
}

CR_HD static inline double cr_particle_Th(const cr_metric *mt, double E, double L, double K,
                                          double u)
{
    double b = mt->a * mt->a * (1.0 - E * E), u2 = u * u;
    return K - (K + L * L + b) * u2 + b * u2 * u2;
}

/* The constants (E, L, K) of 4-velocity u^mu at (r, th) for charge-to-mass
 * ratio qm. On the axis (sin th = 0) L is 0 and K takes L^2 / sin^2 = 0. */
CR_HD static inline void cr_particle_constants(const cr_metric *mt, double qm, double r,
                                               double th, const double u[4], double *E,
                                               double *L, double *K)
{
    cr_metric_point p;
    double At, Aph, ut, uph, pth, l2;
    cr_metric_eval(mt, r, th, &p);
    cr_particle_potential(mt, r, th, &At, &Aph);
    ut = p.g_tt * u[0] + p.g_tph * u[3];
    uph = p.g_tph * u[0] + p.g_phph * u[3];
    *E = -(ut + qm * At);
    *L = uph + qm * Aph;
    pth = p.sigma * u[2];
    l2 = p.sin2 > 0.0 ? *L * *L / p.sin2 : 0.0;
    *K = pth * pth + p.cos2 * (mt->a * mt->a * (1.0 - *E * *E) + l2);
}

/* Fill the Mino coefficients of constants (E, L, K, qm); w_stop as for
 * cr_mino_init. */
CR_HD static inline void cr_particle_coeffs(cr_mino *c, const cr_metric *mt, double E, double L,
                                            double K, double qm, double w_stop)
{
    double a = mt->a, M = mt->m, Q2 = mt->q * mt->q;
    double e = qm * mt->q;
    double B = E * a * a - a * L;
    double la = L - a * E;
    double C = la * la + K;
    double om2;
    c->E = -E; /* mino.h's sign: only |E| is used, as a scale */
    c->L = L;
    c->eta = K;
    c->a = a;
    c->c4 = E * E - 1.0;
    c->c3 = 2.0 * M - 2.0 * E * e;
    c->c2 = e * e + 2.0 * E * B - (a * a + Q2) - C;
    c->c1 = 2.0 * M * C - 2.0 * e * B;
    c->c0 = B * B - (a * a + Q2) * C;
    c->kap = K + L * L;
    c->a2E2 = a * a * (E * E - 1.0);
    c->p1 = 2.0 * M * E - e;
    c->p2 = -(E * Q2 + a * L);
    c->d1 = -2.0 * M;
    c->d2 = a * a + Q2;
    c->d_min = 1.0 + w_stop * (c->d1 + c->d2 * w_stop);
    c->chart = CR_CHART_BL; /* the ingoing chart (mino.h) is for light only */
    c->K = C;
    c->pa = 0.0;
    /* mino.h's coordinate-time component T is light's: particles integrate
     * t and proper time on the dense output instead; its coefficients are
     * zeroed so the unused T rate reads defined values */
    c->m = M;
    c->tc = c->ta = c->tg1 = c->tg2 = c->td1 = c->td2 = c->t3 = 0.0;
    /* the largest |dn/dlambda|^2 = K + L^2 + a^2 (E^2 - 1) u^2 over u */
    om2 = c->kap + (c->a2E2 > 0.0 ? c->a2E2 : 0.0);
    c->omega = sqrt(om2 > 0.0 ? om2 : 0.0);
    if (c->omega < 1e-3 * fabs(E))
        c->omega = 1e-3 * fabs(E);
}

/* dt/dlambda and dtau/dlambda = Sigma at Mino state y. */
CR_HD static inline void cr_particle_rates(const cr_particle *p, const double *y, double *dt,
                                           double *dtau)
{
    double w = y[CR_M_W], r = 1.0 / w, a = p->mt.a;
    double nx = y[CR_M_NX], ny = y[CR_M_NY], nz = y[CR_M_NZ];
    double c2 = nz * nz / (nx * nx + ny * ny + nz * nz), s2 = 1.0 - c2;
    double r2a2 = r * r + a * a;
    double delta = r * r * (1.0 + w * (p->c.d1 + p->c.d2 * w));
    double P = p->E * r2a2 - a * p->L - p->qm * p->mt.q * r;
    *dt = r2a2 * P / delta - a * (a * p->E * s2 - p->L);
    *dtau = r * r + a * a * c2;
}

/* The point of Mino state y with times t, tau, lam. */
CR_HD static inline void cr_particle_point_of(const cr_particle *p, const double *y, double t,
                                              double tau, double lam, cr_particle_point *q)
{
    double dy[CR_MN], cth, sth, dt, sigma, nx = y[CR_M_NX], ny = y[CR_M_NY], nz = y[CR_M_NZ];
    double s2 = nx * nx + ny * ny, s = sqrt(s2), n2 = s2 + nz * nz, dth, dps;
    cr_mino_rhs(&p->c, y, dy);
    cr_mino_position(y, &q->r, &cth, &sth, &q->ph);
    q->th = atan2(sth, cth);
    q->t = t;
    q->tau = tau;
    q->lam = lam;
    cr_bl_to_cart(p->mt.a, q->r, q->th, q->ph, q->x);
    cr_particle_rates(p, y, &dt, &sigma);
    /* theta = atan2(s, nz): dtheta = (nz ds - s dnz) / |n|^2 */
    if (s > 0.0) {
        double ds = (nx * y[CR_M_DNX] + ny * y[CR_M_DNY]) / s;
        dth = (nz * ds - s * y[CR_M_DNZ]) / n2;
        dps = (nx * y[CR_M_DNY] - ny * y[CR_M_DNX]) / s2;
    } else { /* on the axis, moving away from it (L = 0 there) */
        dth = sqrt(y[CR_M_DNX] * y[CR_M_DNX] + y[CR_M_DNY] * y[CR_M_DNY]) / sqrt(n2);
        if (nz < 0.0)
            dth = -dth;
        dps = 0.0;
    }
    q->u[0] = dt / sigma;
    q->u[1] = -y[CR_M_DW] / (y[CR_M_W] * y[CR_M_W] * sigma);
    q->u[2] = dth / sigma;
    q->u[3] = (dps + dy[CR_M_PR]) / sigma;
}

/* The angle ph + 2 pi k nearest to ref. */
CR_HD static inline double cr_particle_near_(double ph, double ref)
{
    return ph + CR_TWO_PI * floor((ref - ph) / CR_TWO_PI + 0.5);
}

/* phi of Mino state y (in (-pi, pi] + pr). */
CR_HD static inline double cr_particle_phi_(const double *y)
{
    return atan2(y[CR_M_NY], y[CR_M_NX]) + y[CR_M_PR];
}

/* The continuous phi at the end of the last step, followed from its start
 * through 8 points of the dense output (phi changes by far less than pi
 * between them away from the axis; through the axis phi jumps by pi). */
CR_HD static inline void cr_particle_unwrap_end_(cr_particle *p)
{
    double ys[CR_MN], ph = p->ph0;
    int i;
    for (i = 1; i <= 8; i++) {
        if (i < 8)
            cr_dp5_dense(&p->st, p->y0, p->y1, p->hm, i / 8.0, ys);
        ph = cr_particle_near_(cr_particle_phi_(i < 8 ? ys : p->y1), ph);
    }
    p->ph1 = ph;
}

/* Common start: coefficients, stages, first trial step. */
CR_HD static inline void cr_particle_begin_(cr_particle *p, double t0)
{
    cr_particle_coeffs(&p->c, &p->mt, p->E, p->L, p->K, p->qm, p->w_stop);
    if (fabs(p->y0[CR_M_NZ]) < 1e-15) /* cos(pi/2) rounded: in the equator */
        p->y0[CR_M_NZ] = 0.0;
    cr_mino_rhs(&p->c, p->y0, p->st.k[0]);
    p->t0 = p->t1 = t0;
    p->tau0 = p->tau1 = 0.0;
    p->lam0 = 0.0;
    p->ph0 = p->ph1 = cr_particle_phi_(p->y0);
    p->hm = 0.0;
    p->h_next = cr_mino_first_step(&p->c, p->tol);
    p->steps = 0;
    p->ended = CR_PARTICLE_RUNNING;
    {
        int i;
        for (i = 0; i < CR_MN; i++)
            p->y1[i] = p->y0[i];
    }
}

/* The settings every start takes: metric, charge-to-mass ratio, tolerance,
 * horizon stop eps (r+ + eps) and escape radius r_max. Returns 0 (nothing
 * else set) where the hole has no horizon or r is not outside r+ + eps. */
CR_HD static inline int cr_particle_setup_(cr_particle *p, const cr_metric *mt, double qm,
                                           double tol, double eps, double r_max, double r)
{
    double rp = cr_metric_r_plus(mt);
    if (!cr_isfinite(rp) || !(r > rp + eps) || !(r < r_max) || !cr_isfinite(qm) ||
        !(tol > 0.0))
        return 0;
    p->mt = *mt;
    p->qm = qm;
    p->tol = tol;
    p->w_stop = 1.0 / (rp + eps);
    p->w_min = 1.0 / r_max;
    return 1;
}

/* Mino state at (r, th, ph) with Sigma u^r = vr, Sigma u^theta = vth and
 * the particle's L. */
CR_HD static inline void cr_particle_state_(cr_particle *p, double r, double th, double ph,
                                            double vr, double vth)
{
    double st = sin(th), ct = cos(th), sp = sin(ph), cp = cos(ph);
    double vph = p->L == 0.0 ? 0.0 : p->L / st;
    double *y = p->y0;
    y[CR_M_W] = 1.0 / r;
    y[CR_M_DW] = -vr / (r * r);
    y[CR_M_NX] = st * cp;
    y[CR_M_NY] = st * sp;
    y[CR_M_NZ] = ct;
    y[CR_M_DNX] = vth * ct * cp - vph * sp;
    y[CR_M_DNY] = vth * ct * sp + vph * cp;
    y[CR_M_DNZ] = -vth * st;
    y[CR_M_PR] = 0.0;
    y[CR_M_T] = 0.0; /* light's time (mino.h), stepped but unused here */
}

/* Start a worldline at coordinate time t0, BL (r, th, ph), with 4-velocity
 * u^mu (future-directed, normalised; cr_particle_observer_u makes one from
 * an observer's measurement). Returns 1, or 0 when the start is refused:
 * no horizon, r not outside r+ + eps or not below r_max, qm not finite,
 * u^t <= 0, a value not finite, or |u.u + 1| > 1e-9 (not a unit timelike
 * vector), or sin th = 0 with L != 0. */
CR_HD static inline int cr_particle_start_u(cr_particle *p, const cr_metric *mt, double qm,
                                            double tol, double eps, double r_max, double t0,
                                            double r, double th, double ph, const double u[4])
{
    cr_metric_point m;
    double uu;
    int i;
    if (!cr_particle_setup_(p, mt, qm, tol, eps, r_max, r) || !(u[0] > 0.0) ||
        !cr_isfinite(t0) || !cr_isfinite(th) || !cr_isfinite(ph))
        return 0;
    for (i = 0; i < 4; i++)
        if (!cr_isfinite(u[i]))
            return 0;
    cr_metric_eval(mt, r, th, &m);
    uu = m.g_tt * u[0] * u[0] + 2.0 * m.g_tph * u[0] * u[3] + m.g_phph * u[3] * u[3] +
         m.g_rr * u[1] * u[1] + m.g_thth * u[2] * u[2];
    if (!(fabs(uu + 1.0) <= 1e-9))
        return 0;
    cr_particle_constants(mt, qm, r, th, u, &p->E, &p->L, &p->K);
    if (m.sin2 == 0.0 && p->L != 0.0)
        return 0;
    cr_particle_state_(p, r, th, ph, m.sigma * u[1], m.sigma * u[2]);
    cr_particle_begin_(p, t0);
    return 1;
}

/* Start a worldline from constants (E, L, K) at (r, th, ph): dr/dlambda =
 * sr sqrt(R), dtheta/dlambda = sth sqrt(Th_theta) (sr, sth = +1 or -1).
 * Returns 1, or 0 when refused: as cr_particle_start_u, or R(r) or the polar
 * potential at th negative (the constants do not allow that position; within
 * 1e-12 of the scale of their terms they count as 0), or E not positive. */
CR_HD static inline int cr_particle_start_constants(cr_particle *p, const cr_metric *mt,
                                                    double qm, double tol, double eps,
                                                    double r_max, double t0, double r,
                                                    double th, double ph, double E, double L,
                                                    double K, int sr, int sth)
{
    double R, Tt, st = sin(th), ct = cos(th), scale;
    if (!cr_particle_setup_(p, mt, qm, tol, eps, r_max, r) || !cr_isfinite(E) ||
        !cr_isfinite(L) || !cr_isfinite(K) || !(E > 0.0) || !cr_isfinite(t0) ||
        !cr_isfinite(th) || !cr_isfinite(ph))
        return 0;
    if (st == 0.0 && L != 0.0)
        return 0;
    R = cr_particle_R(mt, E, L, K, qm, r);
    Tt = K - ct * ct * (mt->a * mt->a * (1.0 - E * E) + (L == 0.0 ? 0.0 : L * L / (st * st)));
    scale = (E * E + 1.0) * (r * r + mt->a * mt->a) * (r * r + mt->a * mt->a) +
            (L * L + fabs(K)) * (r * r + 1.0);
    if (R < -1e-12 * scale || Tt < -1e-12 * (fabs(K) + L * L + mt->a * mt->a + 1.0))
        return 0;
    p->E = E;
    p->L = L;
    p->K = K;
    cr_particle_state_(p, r, th, ph, (sr < 0 ? -1.0 : 1.0) * sqrt(R > 0.0 ? R : 0.0),
                       (sth < 0 ? -1.0 : 1.0) * sqrt(Tt > 0.0 ? Tt : 0.0));
    cr_particle_begin_(p, t0);
    return 1;
}

/* Kinds of observer that measure a starting velocity. */
enum { CR_PARTICLE_OBS_STATIC = 0, CR_PARTICLE_OBS_ZAMO = 1 };

/* The 4-velocity u^mu of a particle moving with 3-velocity v = (v_r, v_th,
 * v_ph) (orthonormal components, |v| < 1) measured by the static observer
 * or the ZAMO at (r, th) (observer.h's tetrads; the static one is the ZAMO's
 * boosted as observer.h's static motion). Returns 1, or 0 when |v| >= 1 or
 * not finite, r is not outside the horizon, a static observer does not
 * exist there (inside the ergosurface), or on the axis v_ph != 0. */
CR_HD static inline int cr_particle_observer_u(const cr_metric *mt, int kind, double r,
                                               double th, const double v[3], double u[4])
{
    double e[4][4], e1[4][4], e2[4][4], vs[3], v2, alpha, omega, sp;
    int on_axis = sin(th) == 0.0, mu;
    v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (!(v2 < 1.0) || !(r > cr_metric_r_plus(mt)) || (on_axis && v[2] != 0.0))
        return 0;
    cr_zamo_tetrad(mt, r, th, on_axis, e, &alpha, &omega, &sp);
    if (kind == CR_PARTICLE_OBS_STATIC) {
        /* observer.h's static motion: the boost that cancels the dragging */
        vs[0] = vs[1] = 0.0;
        vs[2] = -omega * sp / alpha;
        if (!(fabs(vs[2]) < 1.0))
            return 0;
        cr_boost_tetrad(e, vs, e1);
    } else {
        int i, j;
        for (i = 0; i < 4; i++)
            for (j = 0; j < 4; j++)
                e1[i][j] = e[i][j];
    }
    cr_boost_tetrad(e1, v, e2);
    for (mu = 0; mu < 4; mu++)
        u[mu] = e2[0][mu];
    return cr_isfinite(u[0]) && u[0] > 0.0;
}

/* The increments of t and tau over fractions [s0, s1] of the last step: 8-point
 * Gauss-Legendre quadrature of dt/dlambda and Sigma on its dense output. */
CR_HD static inline void cr_particle_quad_(const cr_particle *p, double s0, double s1,
                                           double *dt_out, double *dtau_out)
{
    double st = 0.0, sa = 0.0, yq[CR_MN];
    int i;
    for (i = 0; i < 8; i++) {
        double x, wgt, dt, dtau;
        cr_quad_gl8(i, &x, &wgt);
        cr_dp5_dense(&p->st, p->y0, p->y1, p->hm, s0 + 0.5 * (s1 - s0) * (x + 1.0), yq);
        cr_particle_rates(p, yq, &dt, &dtau);
        st += wgt * dt;
        sa += wgt * dtau;
    }
    *dt_out = 0.5 * (s1 - s0) * p->hm * st;
    *dtau_out = 0.5 * (s1 - s0) * p->hm * sa;
}

/* Dense state at fraction s in [0, 1] of the last step, and its t and tau
 * (cr_particle_quad_ on [0, s]). */
CR_HD static inline void cr_particle_dense(const cr_particle *p, double s, double *ys, double *t,
                                           double *tau)
{
    double dt, dtau;
    int i;
    if (p->hm == 0.0 || s <= 0.0) {
        for (i = 0; i < CR_MN; i++)
            ys[i] = p->y0[i];
        *t = p->t0;
        *tau = p->tau0;
        return;
    }
    cr_particle_quad_(p, 0.0, s, &dt, &dtau);
    cr_dp5_dense(&p->st, p->y0, p->y1, p->hm, s, ys);
    *t = p->t0 + dt;
    *tau = p->tau0 + dtau;
}

/* The error of the last step's t and tau (cr_particle_quad_ over the whole
 * step against the sum over its halves) in units of the tolerance: relative
 * to the increments, absolute below 1 M. The state's error control does not
 * see t and tau (they do not enter the right-hand side), and a step that
 * the state allows may be too long for them: radial motion far out, where
 * the rates grow as r^2 across a step from r to several r. */
CR_HD static inline double cr_particle_time_err_(const cr_particle *p)
{
    double t1, a1, ta, aa, tb, ab;
    cr_particle_quad_(p, 0.0, 1.0, &t1, &a1);
    cr_particle_quad_(p, 0.0, 0.5, &ta, &aa);
    cr_particle_quad_(p, 0.5, 1.0, &tb, &ab);
    return fmax(fabs(t1 - ta - tb) / fmax(fabs(t1), 1.0),
                fabs(a1 - aa - ab) / fmax(fabs(a1), 1.0)) /
           p->tol;
}

/* The point at fraction s of the last step (s = 1: its end). */
CR_HD static inline void cr_particle_at(const cr_particle *p, double s, cr_particle_point *q)
{
    double ys[CR_MN], t, tau;
    if (s >= 1.0) {
        cr_particle_point_of(p, p->y1, p->t1, p->tau1, p->lam0 + p->hm, q);
        q->ph = p->ph1;
        return;
    }
    cr_particle_dense(p, s, ys, &t, &tau);
    cr_particle_point_of(p, ys, t, tau, p->lam0 + s * p->hm, q);
    q->ph = cr_particle_near_(q->ph, p->ph0 + s * (p->ph1 - p->ph0));
}

/* The current point (the end of the last step; the start before the first). */
CR_HD static inline void cr_particle_current(const cr_particle *p, cr_particle_point *q)
{
    if (p->hm == 0.0) {
        cr_particle_point_of(p, p->y0, p->t0, p->tau0, p->lam0, q);
        q->ph = p->ph0;
    } else
        cr_particle_at(p, 1.0, q);
}

/* Fraction of the last step where w crosses w_x (w - w_x changes sign over
 * the step), by regula falsi on the dense output. */
CR_HD static inline double cr_particle_cross_(const cr_particle *p, double w_x)
{
    cr_falsi z;
    double ys[CR_MN];
    cr_falsi_start(&z, p->y0[CR_M_W] - w_x, 1.0, p->y1[CR_M_W] - w_x);
    while (cr_falsi_next(&z)) {
        cr_dp5_dense(&p->st, p->y0, p->y1, p->hm, z.s, ys);
        if (!cr_falsi_update(&z, ys[CR_M_W] - w_x))
            break;
    }
    return z.s;
}

/* Cut the last step at fraction s: it then ends there. */
CR_HD static inline void cr_particle_cut_(cr_particle *p, double s)
{
    double ys[CR_MN], t, tau;
    /* the cut step is a step of size s hm from y0: redone, so that the
     * dense output stays that of a DP5 step */
    p->hm *= s;
    cr_dp5_try(&p->c, p->tol, p->hm, p->y0, &p->st, p->y1);
    cr_particle_dense(p, 1.0, ys, &t, &tau);
    p->t1 = t;
    p->tau1 = tau;
    cr_particle_unwrap_end_(p);
}

/* One accepted step of the worldline (the step loop of ray.h's Mino
 * integrator). Returns p->ended: CR_PARTICLE_RUNNING after a step, or why
 * it ended (the last step then ends exactly at the horizon stop or r_max). */
CR_HD static inline int cr_particle_step(cr_particle *p)
{
    double h, ys[CR_MN], t, tau;
    int tries, i;
    if (p->ended)
        return p->ended;
    if (p->hm != 0.0) { /* move to the end of the last step (FSAL) */
        for (i = 0; i < CR_MN; i++) {
            p->y0[i] = p->y1[i];
            p->st.k[0][i] = p->st.k[6][i];
        }
        p->t0 = p->t1;
        p->tau0 = p->tau1;
        p->ph0 = p->ph1;
        p->lam0 += p->hm;
    }
    h = p->h_next;
    for (tries = 0;; tries++) {
        double err = cr_dp5_try(&p->c, p->tol, h, p->y0, &p->st, p->y1), fac;
        if (err <= 1.0) { /* and t, tau over it */
            p->hm = h;
            err = fmax(err, cr_particle_time_err_(p));
        }
        fac = cr_dp5_factor(err);
        if (err <= 1.0) {
            p->hm = h;
            p->h_next = h * (tries > 0 && fac > 1.0 ? 1.0 : fac);
            break;
        }
        h *= fac;
        if (tries == 60 || !(h > 0.0)) {
            p->hm = 0.0;
            p->ended = CR_PARTICLE_FAILED;
            return p->ended;
        }
    }
    p->steps++;
    cr_particle_dense(p, 1.0, ys, &t, &tau);
    p->t1 = t;
    p->tau1 = tau;
    cr_particle_unwrap_end_(p);
    if (!cr_isfinite(t) || !cr_isfinite(tau)) {
        p->ended = CR_PARTICLE_FAILED;
        return p->ended;
    }
    if (p->y1[CR_M_W] >= p->w_stop) {
        cr_particle_cut_(p, cr_particle_cross_(p, p->w_stop));
        p->y1[CR_M_W] = p->w_stop;
        p->ended = CR_PARTICLE_HORIZON;
    } else if (p->y1[CR_M_W] <= p->w_min) {
        cr_particle_cut_(p, cr_particle_cross_(p, p->w_min));
        p->y1[CR_M_W] = p->w_min;
        p->ended = CR_PARTICLE_ESCAPED;
    }
    return p->ended;
}

/* The fraction s of the last step at which the proper time reaches tau_x
 * (tau0 <= tau_x <= tau1), by Newton's method on the quadrature (dtau/ds =
 * hm Sigma > 0), safeguarded by bisection. */
CR_HD static inline double cr_particle_find_tau(const cr_particle *p, double tau_x)
{
    double lo = 0.0, hi = 1.0, s, ys[CR_MN];
    int it;
    if (!(p->tau1 > p->tau0))
        return 1.0;
    s = (tau_x - p->tau0) / (p->tau1 - p->tau0);
    for (it = 0; it < 60; it++) {
        double t, tau, dt, dtau, f, sn;
        cr_particle_dense(p, s, ys, &t, &tau);
        f = tau - tau_x;
        if (f > 0.0)
            hi = s;
        else
            lo = s;
        if (fabs(f) <= 1e-15 * (fabs(tau_x) + 1.0))
            break;
        cr_particle_rates(p, ys, &dt, &dtau);
        sn = s - f / (p->hm * dtau);
        if (!(sn > lo && sn < hi))
            sn = 0.5 * (lo + hi);
        s = sn;
    }
    return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
}

/* The same in coordinate time t (t0 <= t_x <= t1; dt/ds > 0 outside the
 * horizon for a future-directed worldline). */
CR_HD static inline double cr_particle_find_t(const cr_particle *p, double t_x)
{
    double lo = 0.0, hi = 1.0, s, ys[CR_MN];
    int it;
    if (!(p->t1 > p->t0))
        return 1.0;
    s = (t_x - p->t0) / (p->t1 - p->t0);
    for (it = 0; it < 60; it++) {
        double t, tau, dt, dtau, f, sn;
        cr_particle_dense(p, s, ys, &t, &tau);
        f = t - t_x;
        if (f > 0.0)
            hi = s;
        else
            lo = s;
        if (fabs(f) <= 1e-15 * (fabs(t_x) + 1.0))
            break;
        cr_particle_rates(p, ys, &dt, &dtau);
        sn = s - f / (p->hm * dt);
        if (!(sn > lo && sn < hi))
            sn = 0.5 * (lo + hi);
        s = sn;
    }
    return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
}

#endif
