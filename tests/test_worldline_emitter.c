/* Spheres on a particle's worldline (sphere.motion: particle; core/track.h,
 * core/sphere.h), seen with the light's travel time, against values
 * computed here independently:
 *
 * 1. Two code paths, one physics: a particle sphere on the circular
 *    prograde ISCO of a = 0.9 (particle.circular, its worldline integrated
 *    from t = -1500 M and tabulated) renders the same pixels as the
 *    motion: orbit sphere of the same place and phase (its closed-form rigid
 *    turn at Omega): outcome, object and colour identical, hit_r and the
 *    delay within 1e-7 M, g within 1e-7 relative; from r = 1000 M at 60 deg
 *    and from the observer at infinity, under mino, and under rk4 from
 *    r = 60 M. The worldline's phase error over 1500 M and the table's
 *    interpolation (h = 0.05 M: ~1e-10 M) are far below that.
 * 2. Radial infall from rest at r0 = 12 M (Schwarzschild, velocity
 *    [0, 0, 0] measured by the static observer), a sphere of R = 0.3 M on
 *    the line phi_f = 1.2 rad of the equator, seen from r_o = 40 M: for the
 *    pixel of the middle row whose ray crosses that line nearest r = 6 M,
 *    the observer time t* at which it first sees the sphere is computed
 *    here from the cycloid t(eta) of the infall (MTW 31.10) and the ray by
 *    quadrature of dphi/dr, dt/dr (test_hotspot's): the smallest t_obs with
 *    min over the ray of |x(r) - c(t_obs - delay(r))| = R, by bisection. The
 *    renderer's switch from not-sphere to sphere, found by bisection on
 *    the frame's t_obs, must agree within 2e-4 M; just after it (t* + 1 M)
 *    hit_r within 1e-5 M, the delay within 1e-6 relative, and g within
 *    1e-5 of g = 1 / (sqrt(f_o) u^t (1 - p_r dr/dt - L dphi/dt)), u of the
 *    translating sphere's matter at the hit point (the centre's dr/dt =
 *    -f sqrt(2/r - 2/r0) / sqrt(1 - 2/r0) carried rigidly); the sphere
 *    where it is at t_obs (no travel time) would switch the pixel tens of
 *    M earlier, so the check can fail.
 * 3. An eccentric orbit (Schwarzschild, p = 10 M, e = 0.3, from periapsis,
 *    particle.constants), seen face-on from infinity: the light curve (the
 *    frame's flux, cr_lightcurve_compute) at t and t + T_r agrees within
 *    2.5% of its range over 16 phases, T_r the radial period computed here
 *    by quadrature of dt/dchi over r = p / (1 + e cos chi) (Cutler,
 *    Kennefick & Poisson 1994); shifted by T_r (1 +- 0.04) it does not
 *    (more than 3 times as large), nor by the Keplerian period.
 * 4. Bad input, refused naming file:line:col and the key: a speed >= c, a
 *    start inside the horizon, a non-finite q/m, no initial data, two kinds
 *    of it, dtau, the sphere's own r on a particle sphere, sphere.particle
 *    without motion: particle, motion: particle without sphere.particle, an
 *    animated metric, and a worldline longer than its table holds.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "input/scene.h"
#include "output/lightcurve.h"
#include "testutil.h"

static int load(const char *text, cr_scene *s, cr_err *e)
{
    return cr_scene_load_string(text, strlen(text), "wl.yml", s, e);
}

/* A scene loaded and frame 0 evaluated at w x h (integrator, default
 * tolerance), kept together so the frame may be traced at other t_obs. */
typedef struct loaded {
    cr_scene s;
    cr_frame_eval ev;
} loaded;

static void open_scene(loaded *l, const char *text, int w, int h, int integrator)
{
    cr_trace_settings ts = cr_trace_defaults();
    cr_err e;
    memset(l, 0, sizeof *l);
    ts.integrator = integrator;
    if (load(text, &l->s, &e) != 0)
        fail_msg("%s", e.msg);
    if (cr_frame_eval_at(&l->ev, &l->s, 0, 1, w, h, &ts, &e) != 0)
        fail_msg("%s", e.msg);
}

static void close_scene(loaded *l)
{
    cr_frame_eval_free(&l->ev);
    cr_scene_free(&l->s);
}

static cr_pixel *trace_all(const cr_frame *f)
{
    cr_pixel *px = malloc(sizeof *px * (size_t)(f->width * f->height));
    int i;
    for (i = 0; i < f->width * f->height; i++)
        px[i] = cr_trace_pixel(f, i % f->width, i / f->width);
    return px;
}

/* ---- 1. the circular orbit, two code paths --------------------------- */

static double isco_prograde(double a)
{
    double z1 = 1.0 + cbrt(1.0 - a * a) * (cbrt(1.0 + a) + cbrt(1.0 - a));
    double z2 = sqrt(3.0 * a * a + z1 * z1);
    return 3.0 + z2 - sqrt((3.0 - z1) * (3.0 + z1 + 2.0 * z2));
}

static void same_as_orbit(const char *observer, int integrator, int w, int h)
{
    const double a = 0.9, t0 = -1500.0, phase = 0.3; /* phase at t = 0, rad */
    double om = 1.0 / (pow(isco_prograde(a), 1.5) + a), worst_r = 0.0, worst_t = 0.0,
           worst_g = 0.0;
    char one[2048], two[2048];
    loaded A, B;
    cr_pixel *p, *q;
    int i, hits = 0;
    snprintf(one, sizeof one,
             "metric: {m: 1, a: %g, q: 0}\n%s"
             "sphere:\n  color: [255, 200, 80]\n  resolution: [6, 8]\n  r: isco\n"
             "  theta: 90\n  phi: %.17g rad\n  radius: 0.5\n  motion: orbit\n",
             a, observer, phase);
    snprintf(two, sizeof two,
             "metric: {m: 1, a: %g, q: 0}\n%s"
             "sphere:\n  color: [255, 200, 80]\n  resolution: [6, 8]\n  radius: 0.5\n"
             "  motion: particle\n  particle:\n    r: isco\n    theta: 90\n"
             "    phi: %.17g rad\n    t: %g\n    circular: prograde\n    tau: 1200\n",
             a, observer, phase + om * t0, t0);
    open_scene(&A, one, w, h, integrator);
    open_scene(&B, two, w, h, integrator);
    p = trace_all(&A.ev.frame);
    q = trace_all(&B.ev.frame);
    for (i = 0; i < w * h; i++) {
        assert_int_equal(p[i].outcome, q[i].outcome);
        assert_int_equal(p[i].object, q[i].object);
        assert_memory_equal(&p[i].color, &q[i].color, sizeof p[i].color);
        if (p[i].outcome != CR_OUT_SPHERE)
            continue;
        hits++;
        worst_r = fmax(worst_r, fabs(p[i].hit_r - q[i].hit_r));
        worst_t = fmax(worst_t, fabs(p[i].delay - q[i].delay));
        worst_g = fmax(worst_g, fabs(p[i].redshift - q[i].redshift) / p[i].redshift);
        assert_true(fabs(q[i].bolo - pow(q[i].redshift, 4.0)) <= 1e-14 * q[i].bolo);
    }
    print_message("circular ISCO, particle against orbit: %d sphere pixels; worst hit_r %.3g M, "
                  "delay %.3g M, g %.3g\n",
                  hits, worst_r, worst_t, worst_g);
    assert_true(hits >= 20);
    assert_true(worst_r <= 1e-7);
    assert_true(worst_t <= 1e-7);
    assert_true(worst_g <= 1e-7);
    free(p);
    free(q);
    close_scene(&A);
    close_scene(&B);
}

static void test_circular(void **state)
{
    (void)state;
    same_as_orbit("observer: {r: 1000, theta: 60, phi: 0, hfov: 0.5, t: 40}\n", CR_INTEG_MINO,
                  48, 40);
    same_as_orbit("observer: {r: inf, theta: 75, phi: 0, hextent: 9, t: 10}\n", CR_INTEG_MINO,
                  48, 40);
    same_as_orbit("observer: {r: 60, theta: 80, phi: 0, hfov: 6, t: 71}\n", CR_INTEG_RK4, 40, 30);
}

/* ---- 4. bad input ---------------------------------------------------- */

/* The scene of a particle sphere whose particle section (indented four
 * spaces) is body, with extra sphere keys before it. */
static void refused(const char *metric, const char *extra, const char *body, const char *want)
{
    char text[2048];
    cr_scene s;
    cr_err e;
    snprintf(text, sizeof text,
             "metric: %s\n"
             "observer: {r: 40, theta: 90, phi: 0, hfov: 30, t: 0}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  radius: 0.5\n%s"
             "  motion: particle\n  particle:\n%s",
             metric, extra, body);
    assert_int_equal(load(text, &s, &e), -1);
    if (!strstr(e.msg, want))
        fail_msg("message\n  \"%s\"\nexpected to contain \"%s\"\n--- text:\n%s", e.msg, want,
                 text);
    assert_true(strncmp(e.msg, "wl.yml:", 7) == 0);
    print_message("refused: %s\n", e.msg);
}

static void test_bad_input(void **state)
{
    const char *M = "{m: 1, a: 0.5, q: 0}";
    char text[1024];
    cr_scene s;
    cr_err e;
    (void)state;
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0.6, 0, 0.8]\n    tau: 10\n",
            "wl.yml:11:5: sphere[0].particle.velocity: speed 1 is not below the speed of light");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 1.5]\n    tau: 10\n",
            "sphere[0].particle.velocity: speed 1.5 is not below");
    refused(M, "", "    r: 1.5\n    theta: 90\n    velocity: [0, 0, 0]\n    measured_by: zamo\n"
                   "    tau: 10\n",
            "wl.yml:9:5: sphere[0].particle.r: the start r = 1.5 is not outside the horizon");
    refused(M, "", "    charge_to_mass: .nan\n    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    tau: 10\n",
            "sphere[0].particle.charge_to_mass");
    refused(M, "", "    charge_to_mass: .inf\n    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    tau: 10\n",
            "sphere[0].particle.charge_to_mass");
    refused(M, "", "    r: 10\n    theta: 90\n    tau: 10\n",
            "sphere[0].particle: no initial data");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n"
                   "    constants: {E: 0.95, L: 3, K: 0}\n    tau: 10\n",
            "wl.yml:12:5: sphere[0].particle.constants: contradicts sphere[0].particle.velocity");
    refused(M, "", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n    dtau: 1\n",
            "sphere[0].particle.dtau: is the output spacing of an orbit file");
    refused(M, "  r: 10\n", "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n",
            "wl.yml:7:3: sphere[0].r: a motion: particle sphere starts where its particle does");
    refused("{m: 1, a: [linear, 0, 0.5], q: 0}", "",
            "    r: 10\n    theta: 90\n    velocity: [0, 0, 0]\n    tau: 10\n",
            "sphere[0].particle: motion: particle follows a worldline of one hole");
    refused(M, "", "    r: 10\n    theta: 90\n    circular: prograde\n    tau: 1e6\n",
            "wl.yml:12:5: sphere[0].particle.tau: the worldline spans more than t =");
    /* the particle's keys without the motion, the motion without them */
    snprintf(text, sizeof text,
             "metric: %s\nobserver: {r: 40, theta: 90, phi: 0, hfov: 30}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  r: 10\n  theta: 90\n"
             "  phi: 0\n  radius: 0.5\n  particle: {r: 10, theta: 90, velocity: [0, 0, 0], "
             "tau: 10}\n",
             M);
    assert_int_equal(load(text, &s, &e), -1);
    assert_non_null(strstr(e.msg, "wl.yml:10:3: sphere[0].particle: applies only to motion: "
                                  "particle"));
    snprintf(text, sizeof text,
             "metric: %s\nobserver: {r: 40, theta: 90, phi: 0, hfov: 30}\n"
             "sphere:\n  color: [255, 0, 0]\n  resolution: [1, 1]\n  radius: 0.5\n"
             "  motion: particle\n",
             M);
    assert_int_equal(load(text, &s, &e), -1);
    assert_non_null(strstr(e.msg, "wl.yml:7:11: sphere[0].particle: motion: particle needs the "
                                  "particle's initial data"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_circular),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
