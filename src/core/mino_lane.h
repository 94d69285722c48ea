/* curray core: the lane-generic part of mino.h, written once over a lane
 * type: the ray's coefficients, W, Th, the right-hand side, the conserved-
 * quantity monitor, the Dormand-Prince 5(4) try, its step-size factor and
 * its accept/reject rule. mino.h includes this body once with the scalar
 * lane (one ray: CR_L = double; what the CPU scalar path, CUDA and wasm
 * compile); lanes.h includes it once more with W rays in a vector (the CPU
 * packet path), so the packet path runs these very formulas. Each lane is
 * one ray: every value below is per ray, with its own step size and its own
 * accept/reject; only the tolerance is the frame's.
 *
 * The includer defines (and undefines afterwards):
 *   CR_L          the lane type: double, or W doubles
 *   CR_LM         the type of a comparison of two CR_L: int, or W masks
 *   CR_LN(x)      the name of x for this lane (x itself for the scalar)
 *   CR_LHD        the functions' qualifiers (CR_HD for the scalar)
 *   CR_LSEL(m, a, b)  lane-wise m ? a : b (both a and b are evaluated)
 *   CR_LANY(m)    whether any lane of mask m is set (the scalar: m itself),
 *                 to skip a branch that no lane takes (values unchanged)
 *   CR_LABS(x), CR_LSQRT(x)  lane-wise fabs and the correctly rounded sqrt
 *   CR_LBC(x)     a double as a CR_L (broadcast)
 * Binary + - * / and comparisons between CR_L, or a CR_L and a double, are
 * lane-wise (GCC and clang vector extensions for the vector lanes), and
 * masks combine with & and |. Every operation is written in the one order
 * both instances evaluate, so a lane computes exactly what the scalar code
 * computes for its ray (no contraction into FMA: the lane code is compiled
 * with -ffp-contract=off). The state layout is mino.h's CR_M_* enum,
 * CR_MN components; loops over the state run to CR_MN.
 *
 * No include guard: included once per lane type. Included with no lane
 * type defined, it stands for mino.h (the scalar instance).
 */
#ifndef CR_L
#include "mino.h"
#else

/* The constants of one ray and the coefficients derived from them
 * (cr_mino_init, mino.h). Every field is a CR_L (lanes.h moves one ray's
 * coefficients into a lane field by field). */
typedef struct CR_LN(cr_mino) {
    CR_L E, L, eta;      /* geodesic.h convention; eta = Carter constant */
    CR_L a;              /* spin */
    CR_L c4, c2, c1, c0; /* W(w) = c4 + c3 w + c2 w^2 + c1 w^3 + c0 w^4 */
    CR_L c3;             /* 0 for light; the r^3 term of R of a massive or
                            charged particle (particle.h) */
    CR_L kap;            /* eta + L^2 */
    CR_L a2E2;           /* a^2 E^2 */
    CR_L p1, p2;         /* dpr/dtau = a w (p1 + p2 w) / D(w) */
    CR_L d1, d2;         /* D(w) = 1 + d1 w + d2 w^2 = Delta / r^2 */
    CR_L d_min;          /* D at the horizon stop: D is clamped to it beyond
                            the stop, where rays end anyway */
    CR_L omega;          /* sqrt(eta + L^2 + a^2 E^2) >= |dn/dtau|, floored */
    /* The chart of pr (cr_mino_rhs): CR_CHART_BL, or CR_CHART_INGOING, where
     * pr is phi~ - atan2(n_y, n_x) with the ingoing Kerr azimuth
     * phi~ = phi + F(r) (metric.h), regular through the future horizon. A
     * CR_L like every field (0 or 1), so that a lane holds it too. */
    CR_L chart;
    CR_L K;  /* eta + (L + a E)^2: R = P^2 - Delta K */
    CR_L pa; /* w^2 P(1/w) = E + pa w^2 */
    /* coordinate time (mino.h): dT/dtau = tc - ta nz^2 - w (tg1 + tg2 w)
     *   + (td1 + td2 w - t3 w^2) / D + the 2M term */
    CR_L m; /* M */
    CR_L tc, ta, tg1, tg2, td1, td2, t3;
} CR_LN(cr_mino);

/* W(w) = w^4 R(1/w). */
CR_LHD static inline CR_L CR_LN(cr_mino_W)(const CR_LN(cr_mino) *c, CR_L w)
{
    CR_L w2 = w * w;
    return c->c4 + w * c->c3 + w2 * (c->c2 + w * (c->c1 + w * c->c0));
}

/* Th(u) = (du/dtau)^2 on the ray. */
CR_LHD static inline CR_L CR_LN(cr_mino_Th)(const CR_LN(cr_mino) *c, CR_L u)
{
    CR_L u2 = u * u;
    return c->eta - u2 * (c->kap - c->a2E2 + c->a2E2 * u2);
}

/* Ingoing chart: the rest of d phi~/dtau, and d v/dtau, of the backward ray
 * at state y. With dphi~ = dphi + (a/Delta) dr and dv = dt + ((r^2 + a^2)/Delta) dr,
 * dr/dtau = -(dw/dtau)/w^2, Delta = D/w^2 and Pw = w^2 P = E + pa w^2:
 *   d phi~/dtau - L/sin^2 part = a E - a (Pw + dw)/D,
 *   d v/dtau = -(1 + a^2 w^2) (Pw + dw)/(w^2 D) + a (L + a E sin^2 theta),
 * and on the ray Pw^2 - dw^2 = w^2 D K (from W = Pw^2 - w^2 D K), so
 *   (Pw + dw)/D = w^2 K/(Pw - dw),
 * the form used where |Pw - dw| >= |Pw + dw|: regular at D = 0 for light
 * that crossed the future horizon inward (backward: outward with dw < 0,
 * P > 0). Elsewhere (rays bound for the past boundary, dw -> Pw at D = 0,
 * which ray.h ends before D = 0) the direct form (Pw + dw)/(w^2 D). */
CR_LHD static inline CR_L CR_LN(cr_mino_ingoing_q)(const CR_LN(cr_mino) *c, const CR_L *y)
{
    CR_L w = y[CR_M_W], pw = c->E + c->pa * w * w, dw = y[CR_M_DW];
    CR_L sum = pw + dw, dif = pw - dw;
    /* (Pw + dw) / (w^2 D), in whichever form is better conditioned (equal on
     * the ray): the regular one except where Pw - dw is the smaller (rays
     * bound for the other side, which end before D = 0; K = 0 radial rays,
     * where it is 0/0) */
    return CR_LSEL(CR_LABS(dif) >= CR_LABS(sum), c->K / dif,
                   sum / (w * w * (1.0 + w * (c->d1 + c->d2 * w))));
}

/* dT/dtau at state y (mino.h's coordinate time). The 2M term: inward
 * (dw/dtau >= E/2) 2M w (c2 + c1 w + c0 w^2) / (E + dw/dtau), outward
 * (<= -E/2) 2M (dw/dtau - E) / w, between them the first plus (1/2 -
 * (dw/dtau)/E) times the difference, so it is continuous off the first
 * integral; one division over the selected numerator and denominator. */
CR_LHD static inline CR_L CR_LN(cr_mino_dT)(const CR_LN(cr_mino) *c, const CR_L *y)
{
    CR_L w = y[CR_M_W], nz = y[CR_M_NZ], dw = y[CR_M_DW];
    CR_L D = 1.0 + w * (c->d1 + c->d2 * w);
    CR_L m2 = 2.0 * c->m, poly = w * (c->c2 + w * (c->c1 + w * c->c0));
    CR_LM in = dw >= 0.5 * c->E, mid = dw > -0.5 * c->E;
    CR_L out = m2 * (dw - c->E);
    /* the blend only where a lane lies between the inward and outward forms */
    CR_L num = CR_LSEL(in, m2 * poly,
                       !CR_LANY(mid & (in == 0))
                           ? out
                           : CR_LSEL(mid,
                                     m2 * (w * poly + (0.5 - dw / c->E) *
                                                          (dw * dw - CR_LN(cr_mino_W)(c, w))),
                                     out));
    CR_L den = CR_LSEL(in, c->E + dw, CR_LSEL(mid, w * (c->E + dw), w));
    D = CR_LSEL(D < c->d_min, c->d_min, D);
    return c->tc - c->ta * nz * nz - w * (c->tg1 + c->tg2 * w) +
           ((c->td1 + w * (c->td2 - c->t3 * w)) * den + num * D) / (D * den);
}

/* Right-hand side dy/dtau. */
CR_LHD static inline void CR_LN(cr_mino_rhs)(const CR_LN(cr_mino) *c, const CR_L *y, CR_L *dy)
{
    CR_L w = y[CR_M_W], nz = y[CR_M_NZ];
    CR_L k = c->kap + 2.0 * c->a2E2 * nz * nz;
    CR_L D = 1.0 + w * (c->d1 + c->d2 * w);
    D = CR_LSEL((D < c->d_min) & (c->chart == CR_CHART_BL), c->d_min, D);
    CR_L bl = c->a * w * (c->p1 + c->p2 * w) / D;
    dy[CR_M_W] = y[CR_M_DW];
    dy[CR_M_DW] = 0.5 * c->c3 + w * (c->c2 + w * (1.5 * c->c1 + 2.0 * c->c0 * w));
    dy[CR_M_NX] = y[CR_M_DNX];
    dy[CR_M_NY] = y[CR_M_DNY];
    dy[CR_M_NZ] = y[CR_M_DNZ];
    dy[CR_M_DNX] = -k * y[CR_M_NX];
    dy[CR_M_DNY] = -k * y[CR_M_NY];
    dy[CR_M_DNZ] = (c->a2E2 - k) * nz;
    /* the ingoing chart's rate only where a lane is in that chart */
    dy[CR_M_PR] = !CR_LANY(c->chart == CR_CHART_INGOING)
                      ? bl
                      : CR_LSEL(c->chart == CR_CHART_INGOING,
                          c->a * (c->E - w * w * CR_LN(cr_mino_ingoing_q)(c, y)), bl);
    dy[CR_M_T] = CR_LN(cr_mino_dT)(c, y);
}

/* The conserved-quantity monitor described at the top of mino.h. */
CR_LHD static inline CR_L CR_LN(cr_mino_monitor)(const CR_LN(cr_mino) *c, const CR_L *y)
{
    CR_L w = y[CR_M_W], w2 = w * w, dw = y[CR_M_DW];
    CR_L u = y[CR_M_NZ], u2 = u * u, du = y[CR_M_DNZ];
    CR_L sr = dw * dw + CR_LABS(c->c4) + CR_LABS(w * c->c3) +
              w2 * (CR_LABS(c->c2) + CR_LABS(w) * (CR_LABS(c->c1) + CR_LABS(w * c->c0)));
    CR_L st = du * du + c->omega * c->omega + CR_LABS(c->eta) +
              u2 * (CR_LABS(c->kap - c->a2E2) + c->a2E2 * u2);
    CR_L er = CR_LSEL(sr > 0.0, CR_LABS(dw * dw - CR_LN(cr_mino_W)(c, w)) / sr, CR_LBC(0.0));
    CR_L et = CR_LSEL(st > 0.0, CR_LABS(du * du - CR_LN(cr_mino_Th)(c, u)) / st, CR_LBC(0.0));
    return CR_LSEL(er > et, er, et);
}

/* ---- Dormand-Prince 5(4) ------------------------------------------------ */

/* Stages of one step: k[0] = f(y0) (first same as last), k[6] = f(y1). */
typedef struct CR_LN(cr_dp5) {
    CR_L k[7][CR_MN];
} CR_LN(cr_dp5);

/* Error estimate of component i in the step of size h with stages st (the
 * difference of the 5th- and 4th-order solutions). */
CR_LHD static inline CR_L CR_LN(cr_dp5_err_of)(const CR_LN(cr_dp5) *st, CR_L h, int i)
{
    const double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                 e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
    const CR_L(*k)[CR_MN] = st->k;
    return h * (e1 * k[0][i] + e3 * k[2][i] + e4 * k[3][i] + e5 * k[4][i] + e6 * k[5][i] +
                e7 * k[6][i]);
}

/* One trial step of size h from y0 with st->k[0] = f(y0): fills the other
 * stages and y1, and returns the error estimate scaled by the tolerance
 * (accept when <= 1; NaN or INFINITY when the step failed). Error scales per
 * component: w relative (floor 1e-3), dw/dtau to E, n absolute, dn/dtau to
 * omega, pr absolute; the largest ratio counts. T (coordinate time) is
 * stepped but not estimated (CR_M_NERR). */
CR_LHD static inline CR_L CR_LN(cr_dp5_try)(const CR_LN(cr_mino) *c, double tol, CR_L h,
                                            const CR_L *y0, CR_LN(cr_dp5) *st, CR_L *y1)
{
    const double a21 = 1.0 / 5.0;
    const double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
    const double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
    const double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                 a54 = -212.0 / 729.0;
    const double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                 a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
    const double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0,
                 b5 = -2187.0 / 6784.0, b6 = 11.0 / 84.0;
    CR_L (*k)[CR_MN] = st->k;
    CR_L t[CR_MN];
    CR_L err = CR_LBC(0.0), sc[CR_MN]; /* 1 / (tol * scale) */
    int i;
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * a21 * k[0][i];
    CR_LN(cr_mino_rhs)(c, t, k[1]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a31 * k[0][i] + a32 * k[1][i]);
    CR_LN(cr_mino_rhs)(c, t, k[2]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a41 * k[0][i] + a42 * k[1][i] + a43 * k[2][i]);
    CR_LN(cr_mino_rhs)(c, t, k[3]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a51 * k[0][i] + a52 * k[1][i] + a53 * k[2][i] + a54 * k[3][i]);
    CR_LN(cr_mino_rhs)(c, t, k[4]);
    for (i = 0; i < CR_MN; i++)
        t[i] = y0[i] + h * (a61 * k[0][i] + a62 * k[1][i] + a63 * k[2][i] + a64 * k[3][i] +
                            a65 * k[4][i]);
    CR_LN(cr_mino_rhs)(c, t, k[5]);
    for (i = 0; i < CR_MN; i++)
        y1[i] = y0[i] + h * (b1 * k[0][i] + b3 * k[2][i] + b4 * k[3][i] + b5 * k[4][i] +
                             b6 * k[5][i]);
    CR_LN(cr_mino_rhs)(c, y1, k[6]);

    {
        /* inverse scales: one division for w, one for dw/dtau */
        CR_L w0 = CR_LABS(y0[CR_M_W]), w1 = CR_LABS(y1[CR_M_W]);
        CR_L d0 = CR_LABS(y0[CR_M_DW]), d1 = CR_LABS(y1[CR_M_DW]);
        double itol = 1.0 / tol;
        CR_L wm = CR_LSEL(w0 > w1, w0, w1);
        wm = CR_LSEL(wm > 1e-3, wm, CR_LBC(1e-3));
        for (i = 0; i < CR_MN; i++)
            sc[i] = CR_LBC(itol); /* n, pr absolute */
        sc[CR_M_W] = itol / wm;
        sc[CR_M_DW] = itol / (CR_LABS(c->E) + CR_LSEL(d0 > d1, d0, d1));
        sc[CR_M_DNX] = sc[CR_M_DNY] = sc[CR_M_DNZ] = itol / c->omega;
    }
    for (i = 0; i < CR_M_NERR; i++) {
        CR_L r = CR_LABS(CR_LN(cr_dp5_err_of)(st, h, i)) * sc[i];
        err = CR_LSEL(r <= err, err, r); /* also propagates NaN */
    }
    return err;
}

/* Factor for the next step size after a step with scaled error err:
 * 0.9 err^(-1/4) within [0.2, 5] (the exponent 1/4 rather than 1/5 avoids a
 * pow() per step and errs on the small side); 0.2 for a NaN error. */
CR_LHD static inline CR_L CR_LN(cr_dp5_factor)(CR_L err)
{
    CR_L fac = 0.9 / CR_LSQRT(CR_LSQRT(err));
    fac = CR_LSEL(fac < 0.2, CR_LBC(0.2), CR_LSEL(fac > 5.0, CR_LBC(5.0), fac));
    fac = CR_LSEL(err <= 1.6e-4, CR_LBC(5.0), fac); /* 0.9 err^(-1/4) >= 5 */
    return CR_LSEL(err == err, fac, CR_LBC(0.2));
}

/* The controller after a try of size *h with scaled error err (retried:
 * an earlier try of this step was rejected). Returns the acceptance (err <=
 * 1): then *h stays the step taken and *h_next becomes the next step's first
 * try, *h times the factor, not grown after a rejection; else *h becomes the
 * smaller retry and *h_next is left. */
CR_LHD static inline CR_LM CR_LN(cr_dp5_control)(CR_L err, CR_LM retried, CR_L *h,
                                                 CR_L *h_next)
{
    CR_L fac = CR_LN(cr_dp5_factor)(err);
    CR_LM ok = err <= 1.0;
    CR_L grow = CR_LSEL(retried & (fac > 1.0), CR_LBC(1.0), fac);
    *h_next = CR_LSEL(ok, *h * grow, *h_next);
    *h = CR_LSEL(ok, *h, *h * fac);
    return ok;
}

/* Whether the last step y0 -> y1 of size h (stages st) left T unresolved:
 * its error estimate above tol (1 + (|T(y0)| + |T(y1)|)/2), the tolerance
 * relative to the scale of the time (T ~ -r_o from a static observer at
 * r_o); a NaN estimate counts as unresolved. */
CR_LHD static inline CR_LM CR_LN(cr_mino_t_unresolved)(const CR_LN(cr_dp5) *st, const CR_L *y0,
                                                       const CR_L *y1, CR_L h, double tol)
{
    CR_L e = CR_LN(cr_dp5_err_of)(st, h, CR_M_T);
    return (CR_LABS(e) <= tol * (1.0 + 0.5 * (CR_LABS(y0[CR_M_T]) + CR_LABS(y1[CR_M_T])))) == 0;
}

/* After an accepted step to y1 (lanes where ok is set) with its stages st:
 * dw/dtau put back on its first integral, sign(dw/dtau) sqrt(W(w)) with W
 * from the ray's constants, in the BL chart where the root is well
 * conditioned: |dw/dtau| >= |E|/10, or |dw/dtau| >= |E|/100 where also
 * |W'(w)| w <= 4 |E| |dw/dtau| (a relative error in w moves the root by at
 * most about twice as much, relative to E, as it is; W'/2 is k[6]'s dw/dtau
 * rate): near a simple radial turning point the state is left as it is, in
 * the slow passage by the photon sphere (W nearly a double root there) it
 * is projected down to |E|/100. And the rates of the last stage that
 * depend on dw/dtau are made those of the new state: k[6] is dw/dtau in its
 * w component and dT/dtau in its T component (nothing else of f(y1)
 * depends on it in this chart), so that the dense output and the next step
 * (first same as last) continue from it.
 * Why: far out W ~ E^2 and the Carter constant of the integrated state is
 * ((dw/dtau)^2 - E^2) / w^2 + ..., so an error tol E in dw/dtau becomes one
 * of about 2 tol / w^2 in it, which the orbit's instability at the photon
 * sphere then amplifies (a relative error e in the constant moves a ray
 * that winds there by about e / (b - b_c) in angle). On the first integral
 * the ray keeps its constants (BENCHMARKS.md: the hit radius of rays near
 * the critical impact parameter from 1e-2 to 2e-7 relative at the default
 * tolerance, the same steps).
 * The ingoing chart (observers inside the horizon) is left as it is: its
 * azimuth's rate depends on dw/dtau too; its rays change to BL beyond
 * 2 (r+ + epsilon), and from there on the projection applies. */
CR_LHD static inline void CR_LN(cr_mino_project)(const CR_LN(cr_mino) *c, CR_LM ok, CR_L *y1,
                                                 CR_LN(cr_dp5) *st)
{
    CR_L dw = y1[CR_M_DW], W = CR_LN(cr_mino_W)(c, y1[CR_M_W]);
    CR_L root = CR_LSQRT(CR_LSEL(W > 0.0, W, CR_LBC(0.0)));
    CR_L adw = CR_LABS(dw), aE = CR_LABS(c->E);
    CR_L wp = 2.0 * CR_LABS(st->k[6][CR_M_DW] * y1[CR_M_W]); /* |W'(w)| w */
    CR_LM on = ok & (c->chart == CR_CHART_BL) & (W > 0.0) &
               ((adw >= 0.1 * aE) | ((adw >= 0.01 * aE) & (wp <= 4.0 * adw * aE)));
    y1[CR_M_DW] = CR_LSEL(on, CR_LSEL(dw < 0.0, 0.0 - root, root), dw);
    st->k[6][CR_M_W] = y1[CR_M_DW];
    if (CR_LANY(on)) /* vector lanes evaluate both sides of a select */
        st->k[6][CR_M_T] = CR_LSEL(on, CR_LN(cr_mino_dT)(c, y1), st->k[6][CR_M_T]);
}

/* Whether state y is beyond the sky radius w_sky moving outward (the Mino
 * form of cr_ray_escaping). */
CR_LHD static inline CR_LM CR_LN(cr_mino_escaping)(const CR_L *y, double w_sky)
{
    return (y[CR_M_W] <= w_sky) & (y[CR_M_DW] < 0.0);
}

/* Whether state y has reached the horizon stop w_stop (the Mino form of
 * cr_ray_at_horizon). */
CR_LHD static inline CR_LM CR_LN(cr_mino_at_horizon)(const CR_L *y, double w_stop)
{
    return y[CR_M_W] >= w_stop;
}

/* Whether the step y0 -> y1 leaves the sky radius w_sky outward, so that
 * cr_ray_commit cuts it there. */
CR_LHD static inline CR_LM CR_LN(cr_mino_cuts_sky)(const CR_L *y0, const CR_L *y1, double w_sky)
{
    return (y1[CR_M_W] < w_sky) & (y1[CR_M_DW] < 0.0) & (y0[CR_M_W] > w_sky);
}

/* Whether the step y0 -> y1 may cross the equatorial plane (the disc's
 * event, disc.h): n_z changes sign or is 0 at an end (or is not a number).
 * A filter that lets through every step the disc's event can find a
 * crossing in. */
CR_LHD static inline CR_LM CR_LN(cr_mino_may_cross_equator)(const CR_L *y0, const CR_L *y1)
{
    CR_L p = y0[CR_M_NZ] * y1[CR_M_NZ];
    return (p <= 0.0) | (p != p);
}

/* The disc plane's event value of state y, -cos(theta) (ray.h's
 * cr_ray_event_value), and the polar rate dn_z/dtau, whose sign changes are
 * the polar turning points (cr_ray_polar_rate). */
CR_LHD static inline CR_L CR_LN(cr_mino_disc_value)(const CR_L *y)
{
    return -y[CR_M_NZ];
}

CR_LHD static inline CR_L CR_LN(cr_mino_polar_rate)(const CR_L *y)
{
    return y[CR_M_DNZ];
}

/* Whether an event value changes sign from v0 to v1 (a start exactly on
 * the event is not a crossing): cr_ray_sign_change. */
CR_LHD static inline CR_LM CR_LN(cr_sign_change)(CR_L v0, CR_L v1)
{
    return (v0 != 0.0) & ((v0 < 0.0) ^ (v1 < 0.0));
}

/* Turns about the axis made by the step y0 -> y1: the chord of the unit
 * vector n over 2 pi (cr_ray_commit's count toward max_turns). */
CR_LHD static inline CR_L CR_LN(cr_mino_turns)(const CR_L *y0, const CR_L *y1)
{
    CR_L d0 = y1[CR_M_NX] - y0[CR_M_NX], d1 = y1[CR_M_NY] - y0[CR_M_NY],
         d2 = y1[CR_M_NZ] - y0[CR_M_NZ];
    return CR_LSQRT(d0 * d0 + d1 * d1 + d2 * d2) / CR_TWO_PI;
}

#endif /* CR_L */
