/* The exact Schwarzschild orbit of a light ray from an observer on the
 * polar axis, for the tests (test_order, test_spectrum): the angle phi swept
 * from the axis, d phi / du = 1 / sqrt(1/b^2 - u^2 + 2 M u^3), u = 1/r,
 * M = 1, by Gauss-Legendre quadrature (over u = u_t (1 - t^2) when the ray
 * turns at u_t, which removes the square-root singularity there), and the
 * radius where phi reaches a given angle. Nothing of curray's is used.
 * Call gl_init() once first. */
#ifndef CR_TESTS_EXACT_ORBIT_H
#define CR_TESTS_EXACT_ORBIT_H

#include <math.h>
#include <string.h>

#ifndef CR_PI
#define CR_PI 3.14159265358979323846
#endif

#define B_CRIT 5.196152422706632 /* 3 sqrt(3) */

/* ---- the exact orbit ------------------------------------------------------ */

/* Gauss-Legendre nodes and weights on [-1, 1], computed once. */
#define GL_N 24
static double gl_x[GL_N], gl_w[GL_N];

static void gl_init(void)
{
    for (int i = 0; i < GL_N; i++) {
        double x = cos(CR_PI * (i + 0.75) / (GL_N + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= GL_N; k++) {
                double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = GL_N * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        gl_x[i] = x;
        gl_w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
}

/* One ray: its impact parameter, the roots of P when it turns. */
typedef struct orbit {
    double b, u0; /* u0 = 1 / r of the observer (0 at infinity) */
    int turns;    /* b > b_c */
    double ut, u1, u3; /* roots u1 < 0 < ut < u3 of P (turns only) */
    double phi_t;      /* angle swept from u0 to the turning point */
} orbit;

static double P(const orbit *o, double u)
{
    return 1.0 / (o->b * o->b) - u * u + 2.0 * u * u * u;
}

/* Root of P in [lo, hi] where P changes sign (bisection). */
static double p_root(const orbit *o, double lo, double hi)
{
    double plo = P(o, lo);
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi), pm = P(o, mid);
        if ((pm < 0.0) == (plo < 0.0)) {
            lo = mid;
            plo = pm;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

/* Turning case: u = ut (1 - t^2); d phi = 2 sqrt(ut) dt / sqrt(2 (u - u1) (u3 - u)). */
static double g_turn(const orbit *o, double t)
{
    double u = o->ut * (1.0 - t * t);
    return 2.0 * sqrt(o->ut) / sqrt(2.0 * (u - o->u1) * (o->u3 - u));
}

static double t_of_u(const orbit *o, double u)
{
    double s = 1.0 - u / o->ut;
    return s > 0.0 ? sqrt(s) : 0.0;
}

/* Integral of fn over [a, b] by composite Gauss-Legendre, n panels. */
static double quad(const orbit *o, double (*fn)(const orbit *, double), double a, double b, int n)
{
    double s = 0.0, h = (b - a) / n;
    for (int p = 0; p < n; p++) {
        double c = a + (p + 0.5) * h;
        for (int i = 0; i < GL_N; i++)
            s += gl_w[i] * fn(o, c + 0.5 * h * gl_x[i]);
    }
    return 0.5 * h * s;
}

static double g_plunge(const orbit *o, double u)
{
    return 1.0 / sqrt(P(o, u));
}

/* Angle swept on the way in from u0 to u (u <= ut when the ray turns). */
static double phi_in(const orbit *o, double u)
{
    if (o->turns)
        return quad(o, g_turn, t_of_u(o, u), t_of_u(o, o->u0), 8);
    return quad(o, g_plunge, o->u0, u, 32);
}

static void orbit_make(orbit *o, double b, double u0)
{
    memset(o, 0, sizeof *o);
    o->b = b;
    o->u0 = u0;
    o->turns = b > B_CRIT;
    if (o->turns) {
        o->ut = p_root(o, 0.0, 1.0 / 3.0);
        o->u3 = p_root(o, 1.0 / 3.0, 0.5);
        o->u1 = 0.5 - o->ut - o->u3; /* the roots of 2u^3 - u^2 + 1/b^2 sum to 1/2 */
        o->phi_t = phi_in(o, o->ut);
    }
}

/* The u in [lo, hi] (on the way in: up to the turning point) where the
 * angle swept from u0 is phi: bisection on phi_in, which increases with u. */
static double u_at(const orbit *o, double phi, double lo, double hi)
{
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (phi_in(o, mid) < phi)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* The radius of the ray's crossing of swept angle phi, or 0 when it never
 * sweeps that far: it leaves first (turning at ut, it has swept
 * 2 phi_t - phi_in(u) at u on the way out, 2 phi_t - phi_in(0) at
 * infinity) or reaches the horizon stop r_stop. */
static double crossing_r(const orbit *o, double phi, double r_stop)
{
    if (o->turns) {
        double back = 2.0 * o->phi_t - phi; /* phi_in at the outbound crossing */
        if (phi <= o->phi_t)
            return 1.0 / u_at(o, phi, o->u0, o->ut);
        if (back <= phi_in(o, 0.0))
            return 0.0;
        return 1.0 / u_at(o, back, 0.0, o->ut);
    }
    if (phi >= phi_in(o, 1.0 / r_stop))
        return 0.0;
    return 1.0 / u_at(o, phi, o->u0, 1.0 / r_stop);
}

#endif
